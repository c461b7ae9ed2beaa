/* capture: depth camera sources behind one interface (like LCM's providers: a table of function
 * pointers picked by name), pacing, and the loop that publishes DEPTH and TIMING.
 *
 * Sources: "freenect" (libfreenect's callback API; a Kinect v1, or a fakenect dump replayed by
 * Debian's fakenect library) and "openni2" (OpenNI2's C API; a live device or an .oni file). */
#ifndef TRYON_CAPTURE_H
#define TRYON_CAPTURE_H

#include <signal.h>
#include <stddef.h>
#include <stdint.h>

#include <lcm/lcm.h>

#define CAP_ERROR_LIST(X)                                                                          \
    X(CAP_OK, "ok")                                                                                \
    X(CAP_END, "end of the recording")                                                             \
    X(CAP_ERR_ARG, "invalid argument")                                                             \
    X(CAP_ERR_SOURCE, "unknown source name")                                                       \
    X(CAP_ERR_RECORDING, "recording is missing or damaged")                                        \
    X(CAP_ERR_NOT_FAKENECT, "a dump needs the fakenect libfreenect (run via tryon-capture)")       \
    X(CAP_ERR_NO_DEVICE, "no camera found")                                                        \
    X(CAP_ERR_DEVICE, "camera library call failed")                                                \
    X(CAP_ERR_TIMEOUT, "no frame before the timeout")                                              \
    X(CAP_ERR_BUS, "publishing failed")                                                            \
    X(CAP_ERR_RECORD, "writing --record failed")                                                   \
    X(CAP_ERR_NO_MEMORY, "out of memory")

#define CAP_ERROR_ENUM(id, text) id,
typedef enum cap_error { CAP_ERROR_LIST(CAP_ERROR_ENUM) CAP_ERROR_COUNT } cap_error;
#undef CAP_ERROR_ENUM
/* Functions return 0 (CAP_OK), CAP_END (a result, not an error) or -CAP_ERR_x
 * (docs/building.md, "Conventions: errors"). */
const char *cap_error_name(int e); /* accepts e or -e */
const char *cap_error_text(int e);

/* One depth frame as a source delivers it. Pointers stay valid until the next call. */
typedef struct cap_frame {
    int width, height;
    const uint16_t *depth_mm; /* width * height, 0 = no reading */
    const uint16_t *raw;      /* Kinect 11-bit disparity when the source has it, else NULL */
    float fx, fy, cx, cy;
    int64_t device_timestamp; /* the camera's counter: freenect ticks, OpenNI microseconds */
    int32_t seq;              /* from 0 */
    int64_t utime_capture;    /* wall clock us when the frame reached us */
    double replay_time_s;     /* recordings: time since the first frame; live: negative */
} cap_frame;

typedef struct cap_source cap_source;
typedef struct cap_source_desc {
    const char *uri; /* freenect: device index ("0") or dump directory; openni2: URI or .oni */
    int timeout_ms;  /* a live camera silent this long is an error; 0 = 2000 */
    int max_speed;   /* recordings: deliver as fast as possible (pacing is done by cap_pacer) */
} cap_source_desc;

/* The provider table every source fills (STYLE.md: LCM's lcm_provider_t). */
typedef struct cap_source_api {
    const char *name;
    int (*open)(cap_source *s, const cap_source_desc *d, char *err, size_t errlen);
    /* CAP_OK with a frame, CAP_END at the end of a recording, or -CAP_ERR_x. */
    int (*next)(cap_source *s, cap_frame *out, char *err, size_t errlen);
    void (*close)(cap_source *s);
} cap_source_api;

struct cap_source {
    const cap_source_api *api;
    void *impl;
};

const cap_source_api *cap_source_find(const char *name); /* NULL if unknown */
const char *cap_source_name(int i);                      /* NULL past the end */
cap_source *cap_source_create(const char *name, const cap_source_desc *d, int *code, char *err,
                              size_t errlen);
int cap_source_next(cap_source *s, cap_frame *out, char *err, size_t errlen);
void cap_source_destroy(cap_source *s);

/* Fakenect staging. Debian's fakenect sleeps between frames by their record times and exits the
 * process on a missing file, so tryon-capture validates the dump first and hands fakenect a
 * private INDEX.txt (in a fresh temporary directory, linking to the original frames) whose record
 * times are all zero: fakenect then never sleeps and cap_pacer paces by the original times. */
#define CAP_ENV_STAGED "TRYON_FAKENECT_STAGED" /* set in the re-executed capture process */
#define CAP_ENV_LIBDIR "TRYON_FAKENECT_LIBDIR" /* overrides the fakenect library directory */
int cap_fakenect_stage(const char *dump_dir, char *staged, size_t staged_size, char *err,
                       size_t errlen);
void cap_fakenect_unstage(const char *staged);
const char *cap_fakenect_libdir(void);
int cap_uri_is_dump(const char *uri); /* a directory holding INDEX.txt or meant to */

/* Pacing. */
typedef enum cap_rate_mode { CAP_RATE_REALTIME, CAP_RATE_MAX, CAP_RATE_FPS } cap_rate_mode;
typedef struct cap_rate {
    cap_rate_mode mode;
    double fps;
} cap_rate;
int cap_rate_parse(const char *s, cap_rate *out); /* "realtime", "max" or fps; 0 or -CAP_ERR_ARG */

typedef struct cap_pacer {
    cap_rate rate;
    int started;
    int64_t t0_mono_us;
    double first_replay_s;
    int64_t next_fps_us;
} cap_pacer;
void cap_pacer_init(cap_pacer *p, cap_rate rate);
/* When frame k (replay time in seconds; negative for live) is due, in monotonic us. For live
 * sources in FPS mode a frame that is early is skipped: *skip = 1. */
int64_t cap_pacer_due(cap_pacer *p, double replay_time_s, int *skip);
/* Sleeps until the monotonic time due_us, waking early when *stop becomes non-zero. */
void cap_sleep_until(int64_t due_us, volatile sig_atomic_t *stop);

/* The capture loop (tryon-capture without the option parsing). */
typedef struct cap_run_desc {
    const char *source; /* "freenect" or "openni2" */
    const char *uri;
    cap_rate rate;
    int frames;                   /* 0 = until the end or a signal */
    const char *record_dir;       /* NULL = do not record */
    const float *camera_to_world; /* 16 floats, NULL = the default (docs/capture.md) */
    lcm_t *lcm;
    int quiet;
} cap_run_desc;
typedef struct cap_run_stats {
    int frames;
    double seconds;    /* first frame fetched to last published */
    double lag_p50_ms; /* scheduled replay time to publish (recordings) */
    double lag_p95_ms;
    double lag_max_ms;
} cap_run_stats;
int cap_run(const cap_run_desc *d, volatile sig_atomic_t *stop, cap_run_stats *stats, char *err,
            size_t errlen);

/* The default camera pose: a Kinect 1.0 m above the floor, 2.5 m in front of the person, level,
 * looking along world -z (the same as tryon-synth's). */
void cap_default_camera_to_world(float m[16]);

#endif
