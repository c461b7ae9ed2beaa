/* Private to mirror/: tryon-mirror's state between the bus and the renderer. */
#ifndef TRYON_MIRROR_APP_H
#define TRYON_MIRROR_APP_H

#include "bus.h"
#include "mirror.h"
#include "cloth_queue.h"

#define MIRROR_APP_MAX_GARMENTS 16
#define MIRROR_APP_STAGES       8
#define MIRROR_VIDEO_FPS        30 /* the camera's rate */
#define MIRROR_VIDEO_FRAME_US   (1000000 / MIRROR_VIDEO_FPS)
/* --queue's default: CLOTH waiting to be drawn, oldest first (bus/queue.h). With one, the newest
 * only, a person's entry (the sim catching up on a few bodies while the mirror, at niceness 5,
 * waits for a core) left 1-6 frames undrawn in every run; two left one undrawn in 2 of 30 runs
 * (headless, the first frame's PNG took 30 ms while three CLOTH came); three, none in 8, at the
 * same latency (docs/mirror.md, "Figures today"). */
#define MIRROR_APP_QUEUE 3

typedef struct stage_latency {
    char stage[32];
    double latency_ms, work_ms; /* smoothed: finished - capture, finished - started */
} stage_latency;

typedef struct mirror_app {
    /* options */
    int width, height, headless, kiosk, frames_wanted, png_every, overlay, fit_map, show_body;
    const char *out_dir, *video_path, *fabric;
    const char *garments[MIRROR_APP_MAX_GARMENTS];
    int num_garments, garment, size;
    /* bus */
    lcm_t *lcm;
    bus_sub *subs[4];
    char ch_control[BUS_CHANNEL_MAX];
    int32_t control_seq;
    /* what arrived */
    mirror_ring *ring;
    mirror_held cloth, body;  /* the garment drawn last (or now), the body */
    mirror_cloth_queue queue; /* the CLOTH waiting to be drawn (--queue) */
    char garment_id[64];
    int depth_new, have_cloth, unmatched;
    int64_t last_cloth_us, last_frame_us;
    stage_latency stages[MIRROR_APP_STAGES];
    int num_stages;
    double fps;
    /* output */
    mirror_gl *gl;
    mirror_window *window;
    mirror_renderer *renderer;
    mirror_strain *strain;
    mirror_video *video;
    uint8_t *rgb;
    int frames_drawn, pngs_written;
    int window_path;   /* said on stderr: 0 not yet, 1 scaled from the renderer's own, 2 direct */
    int presents_said; /* how the window presents, said after the first swap */
    int64_t video_frames, video_t0; /* frames piped; the first one's utime_capture */
} mirror_app;

int mirror_app_open(mirror_app *a);      /* bus, subscriptions, GL (window or headless), outputs */
void mirror_app_close(mirror_app *a);    /* and a summary on stderr */
int mirror_app_due(const mirror_app *a); /* 1 = something new to draw */
int mirror_app_frame(mirror_app *a);     /* draw, show or write, report TIMING */
void mirror_app_send_control(mirror_app *a);

#endif
