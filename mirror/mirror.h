/* mirror: the kiosk's picture. The person from the depth frame, the simulated garment over them
 * (hidden where the person is in front), the fitted body if asked, and an overlay; drawn by one
 * OpenGL ES 3 renderer into a framebuffer object that a window shows or a file receives.
 *
 * Coordinates: the depth camera's (x right, y down, z forward, metres); BODY and CLOTH are in
 * world coordinates (y up) and reach the camera through the depth frame's camera_to_world. The
 * picture is the camera's view mirrored left-right, as a mirror shows a person. */
#ifndef TRYON_MIRROR_H
#define TRYON_MIRROR_H

#include <stddef.h>
#include <stdint.h>

/* Why something failed; functions return 0 or -MIRROR_ERR_x (docs/building.md, "Conventions:
 * errors"), with a sentence in err where they take one. One list makes the enum and the words. */
#define MIRROR_ERROR_LIST(X)                                                                       \
    X(MIRROR_OK, "ok")                                                                             \
    X(MIRROR_ERR_NO_MEMORY, "out of memory")                                                       \
    X(MIRROR_ERR_MESH, "triangle index out of range")                                              \
    X(MIRROR_ERR_GL, "OpenGL error")                                                               \
    X(MIRROR_ERR_IO, "file cannot be written")                                                     \
    X(MIRROR_ERR_VIDEO, "the video encoder has gone")

#define MIRROR_ERROR_ENUM(id, text) id,
typedef enum mirror_error { MIRROR_ERROR_LIST(MIRROR_ERROR_ENUM) MIRROR_ERROR_COUNT } mirror_error;
#undef MIRROR_ERROR_ENUM
const char *mirror_error_name(int e); /* "MIRROR_ERR_IO"; accepts e or -e */
const char *mirror_error_text(int e); /* "file cannot be written" */

/* One depth frame as the renderer needs it; data points at w * h little-endian uint16. */
typedef struct mirror_depth {
    int width, height;
    float fx, fy, cx, cy, metres_per_unit;
    float camera_to_world[16]; /* row-major */
    const uint16_t *data;
    int64_t utime_capture;
    /* the person's image made from data (2 floats a pixel: mirror_person_image), or NULL: the
     * renderer makes it. The ring makes it when the frame arrives, while the sim still works on
     * that frame: off the path from CLOTH to screen. */
    const float *person;
} mirror_depth;

/* A triangle mesh in world coordinates. strain: per vertex (NULL = none), for the fit map. */
typedef struct mirror_mesh {
    const float *xyz; /* [nv][3] */
    int nv;
    const int32_t *tris; /* [nt][3] */
    int nt;
    const float *strain; /* [nv] */
} mirror_mesh;

/* What to draw. Zero-initialised fields mean: nothing of that kind. */
typedef struct mirror_view {
    const mirror_depth *depth;  /* the person; required for the garment's camera */
    const mirror_mesh *garment; /* NULL = none yet */
    const mirror_mesh *body;    /* the fitted body, drawn translucent; NULL = not shown */
    float garment_rgb[3];       /* 0..1; all zero = the default red */
    int fit_map;                /* colour the garment by strain instead */
    const char *overlay_text;   /* lines separated by '\n'; NULL = no overlay */
} mirror_view;

/* The renderer needs a current OpenGL ES 3 context (mirror_gl_headless or a window's). */
typedef struct mirror_renderer mirror_renderer;
mirror_renderer *mirror_renderer_create(int width, int height, char *err, size_t err_size);
void mirror_renderer_destroy(mirror_renderer *r);
/* Where mirror_render draws: 0 = the window's back buffer (its size must be the picture's; it
 * saves mirror_present's copy, 6 ms a frame on llvmpipe), anything else = the renderer's own
 * framebuffer object (the default). */
void mirror_renderer_draw_to_window(mirror_renderer *r, int window);
/* Draws into the target above. Returns 0, or -MIRROR_ERR_x with err filled. */
int mirror_render(mirror_renderer *r, const mirror_view *v, char *err, size_t err_size);
/* Draws a scene holding everything a frame may draw (person, arm, fit-map garment, body,
 * overlay) into the target above, so that llvmpipe compiles its shaders before the first real
 * frame (mirror/warmup.c). With a ring, its depth frame also fills every slot of it (the
 * buffers of a camera's frames allocated and touched now), and the ring then forgets it.
 * Returns 0 or -MIRROR_ERR_x with err filled. */
typedef struct mirror_ring mirror_ring;
int mirror_warm_up(mirror_renderer *r, mirror_ring *ring, char *err, size_t err_size);
/* The last picture (from where it was drawn), rows top to bottom, RGB: width * height * 3. */
int mirror_read_rgb(mirror_renderer *r, uint8_t *rgb);
/* Copies the picture to framebuffer 0 (a window's back buffer). */
void mirror_present(mirror_renderer *r, int window_w, int window_h);
unsigned mirror_renderer_fbo(const mirror_renderer *r);

/* The strain colour ramp of the fit map: 0 green, half the limit yellow, the limit and over red.
 * rgb: 3 floats. */
#define MIRROR_FIT_MAP_LIMIT 0.03f /* ARCHITECTURE.md: max stretch strain 3 % */
void mirror_fit_colour(float strain, float *rgb);

/* An OpenGL ES 3 context without any display: EGL's surfaceless Mesa platform. */
typedef struct mirror_gl mirror_gl;
mirror_gl *mirror_gl_headless(char *err, size_t err_size);
void mirror_gl_destroy(mirror_gl *g);

/* The kiosk window (SDL2) with its OpenGL ES 3 context. */
typedef struct mirror_window mirror_window;
typedef enum mirror_key {
    MIRROR_KEY_NONE,
    MIRROR_KEY_NEXT,
    MIRROR_KEY_PREVIOUS,
    MIRROR_KEY_SIZE_UP,
    MIRROR_KEY_SIZE_DOWN,
    MIRROR_KEY_OVERLAY,
    MIRROR_KEY_FIT_MAP,
    MIRROR_KEY_BODY,
    MIRROR_KEY_QUIT
} mirror_key;
mirror_window *mirror_window_create(int width, int height, int kiosk, char *err, size_t err_size);
void mirror_window_destroy(mirror_window *w);
mirror_key mirror_window_poll(mirror_window *w); /* one pending key, or NONE */
void mirror_window_size(mirror_window *w, int *width, int *height);
void mirror_window_swap(mirror_window *w);
/* How the window's pictures reach the display, in words ("through GLX, the picture in memory
 * shared with the X server"); meaningful after the first swap. */
const char *mirror_window_presents(mirror_window *w);

/* Files. */
int mirror_png_write(const char *path, const uint8_t *rgb, int width, int height, char *err,
                     size_t err_size);
/* Reads an 8-bit RGB or RGBA PNG into malloc'd RGB. */
uint8_t *mirror_png_read(const char *path, int *width, int *height);
typedef struct mirror_video mirror_video;
/* ffmpeg reading raw RGB frames on its stdin, writing H.264 into path. */
mirror_video *mirror_video_open(const char *path, int width, int height, int fps, char *err,
                                size_t err_size);
int mirror_video_write(mirror_video *v, const uint8_t *rgb);
int mirror_video_close(mirror_video *v); /* waits for ffmpeg; returns its exit status */

/* Text for the overlay: a built-in 5x7 bitmap font (upper case, digits, punctuation; lower case
 * drawn as upper case). Draws into an RGBA image; returns the width drawn, pixels. */
#define MIRROR_FONT_W 6 /* advance per character, pixels at scale 1 */
#define MIRROR_FONT_H 9 /* line height */
int mirror_text(uint8_t *rgba, int width, int height, int x, int y, int scale, const char *text,
                const uint8_t colour[4]);

/* The depth frames kept so that each CLOTH is drawn with the DEPTH it came from. */
#define MIRROR_RING 8
mirror_ring *mirror_ring_create(void);
void mirror_ring_destroy(mirror_ring *r);
/* Copies the frame in, replacing the oldest. Returns 0 or -MIRROR_ERR_NO_MEMORY. */
int mirror_ring_push(mirror_ring *r, const mirror_depth *d);
/* The frame with this utime_capture; else the newest older one (*exact = 0); NULL if none. */
const mirror_depth *mirror_ring_find(const mirror_ring *r, int64_t utime_capture, int *exact);
const mirror_depth *mirror_ring_newest(const mirror_ring *r);
/* Every frame forgotten; the slots' buffers are kept for the next frames. */
void mirror_ring_forget(mirror_ring *r);

/* Per-vertex strain for the fit map: edge lengths of a garment's first frame are its rest
 * lengths (the sim makes a garment at rest around the body); each vertex gets the largest
 * stretch of its edges. */
typedef struct mirror_strain mirror_strain;
mirror_strain *mirror_strain_create(void);
void mirror_strain_destroy(mirror_strain *s);
void mirror_strain_reset(mirror_strain *s); /* a new garment: the next frame is its rest */
/* Returns the per-vertex strain array (nv), or NULL when out of memory. */
const float *mirror_strain_update(mirror_strain *s, const float *xyz, int nv, const int32_t *tris,
                                  int nt);

#endif
