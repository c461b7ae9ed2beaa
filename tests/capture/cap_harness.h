/* Test harness for capture: dumps with known content, tryon-capture as a child process, and an
 * LCM listener that keeps every DEPTH and TIMING message it receives. */
#ifndef TRYON_CAP_HARNESS_H
#define TRYON_CAP_HARNESS_H

#include <stdint.h>
#include <sys/types.h>

#include "bus.h"

#define H_MAX_FRAMES 64
#define H_PIXELS     (640 * 480)

typedef struct h_depth {
    int64_t utime_capture, device_timestamp, utime_received;
    int32_t seq, width, height;
    float fx, metres_per_unit;
    char source[16];
    uint16_t *mm; /* H_PIXELS, decoded from little-endian */
} h_depth;

typedef struct harness {
    char dir[256];     /* the dump under test */
    char out_dir[300]; /* --record target */
    char url[128];
    char prefix[64];
    lcm_t *lcm;
    bus_sub *depth_sub, *timing_sub;
    int depth_count, timing_count;
    h_depth depth[H_MAX_FRAMES];
    int32_t timing_seq[H_MAX_FRAMES];
    pid_t child;
    pid_t logger; /* an lcm-logger a test started, killed in h_destroy */
    int err_fd;   /* the child's stderr */
    char err_text[8192];
} harness;

harness *h_create(int port);
void h_destroy(harness *h); /* kills a child still running, removes the dumps */
/* Writes a dump of n frames; frame k at record time 1 + k / fps, timestamp 1000 + 33333 k. */
void h_write_dump(harness *h, int n, double fps);
uint16_t h_raw(int k, int i);
uint32_t h_timestamp(int k);
/* Starts tryon-capture with the given arguments (NULL-terminated). */
void h_start(harness *h, const char *const *args);
/* Handles LCM until the child exits (or timeout_s); returns its exit status, or -1 on timeout. */
int h_wait(harness *h, double timeout_s);
/* Handles LCM until at least n DEPTH messages arrived (or timeout_s). */
int h_wait_frames(harness *h, int n, double timeout_s);

#endif
