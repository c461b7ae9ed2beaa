/* Private to launcher/: one `tryon run` or `tryon replay` session. */
#ifndef TRYON_LAUNCH_SESSION_H
#define TRYON_LAUNCH_SESSION_H

#include "bus.h"
#include "launch.h"
#include "profile.h"

#define SESSION_MAX_STAGES 8
/* A stage that dies this many times within SESSION_RESTART_WINDOW_US is given up on. */
#define SESSION_MAX_RESTARTS      5
#define SESSION_RESTART_WINDOW_US 30000000
/* After the recording ends, frames still in the pipeline get this long to arrive. */
#define SESSION_DRAIN_US 1500000
/* The summary also gives the figures without each stage's first frames: a person entering, the
 * fitter's shape estimated over 10 frames, the garment made on the first body and again on the
 * first tracking one, and settled (docs/pipeline.md, "The latency summary"). */
#define SESSION_WARMUP_FRAMES 15
/* tryon-mirror's niceness by default: on two cores the four stages want 45-50 ms of CPU a 33 ms
 * frame; a picture drawn a little later costs the screen's latency less than a body fitted or a
 * cloth simulated later, which delays both the cloth and every picture after (docs/pipeline.md,
 * "Threads"). */
#define LAUNCH_MIRROR_NICE 5

typedef struct session_opts {
    const char *recording; /* NULL with live */
    int live, headless, kiosk;
    const char *out_dir, *video, *garment, *fabric, *record_dir, *body, *backend, *rate;
    const char *log; /* replay */
    const char *speed, *png_every;
    int mirror_nice; /* tryon-mirror's niceness (--mirror-nice) */
} session_opts;

typedef struct session {
    session_opts o;
    char dir[256]; /* logs (and the recording with --record) */
    char prefix[64];
    lcm_t *lcm;
    bus_sub *timing_sub;
    bus_profile *profile;
    launch_stage st[SESSION_MAX_STAGES];
    int n;
    char paths[SESSION_MAX_STAGES][512];
    char args[SESSION_MAX_STAGES][8][512]; /* formatted arguments the argv point at */
    int64_t opened_us, closed_us;          /* monotonic: the session's wall time */
} session;

/* Opens the bus (TIMING for the summary) and the log folder, and sets the stages' thread
 * defaults (session_thread_defaults). Returns 0 or -1, said. */
int session_open(session *s);
void session_close(session *s);
/* Adds a stage running exe (found with launch_find) and returns it; NULL, said, if not found. */
launch_stage *session_stage(session *s, const char *exe, launch_role role, const char *ready);
/* Appends one argument (copied when fmt has a %) to the stage's argv. */
void session_arg(session *s, launch_stage *st, const char *fmt, const char *value);
/* Starts the stages from index first on, each once the one before says it is ready. */
int session_start(session *s, int first);
/* tryon-mirror with the session's view options. */
int session_add_view(session *s);
int tryon_replay(int argc, char **argv);
/* Calls fn for every event of an LCM log (replay.c); returns the number read, -1 if the file
 * does not open or is not an LCM log. */
int session_log_each(const char *path,
                     void (*fn)(const char *ch, const uint8_t *d, uint32_t n, void *user),
                     void *user);
/* tryon pace LOG: a recorded session's bodies played at the camera's pace (pace.c). */
int tryon_pace(int argc, char **argv);
/* tryon path LOG: where each frame's time went, stage by stage (path.c). */
int tryon_path(int argc, char **argv);
/* Supervises until the source ends, the view quits, Ctrl-C, or a stage fails for good; then
 * stops every stage. Returns the launcher's exit status. */
int session_supervise(session *s);
void session_summary(session *s); /* after session_close; frees the profile */
void session_request_stop(void);  /* async-signal-safe */

#endif
