/* The libfreenect source: Kinect v1 through libfreenect's callback API (its sync wrapper crashed
 * at shutdown), or a fakenect dump when the process runs with Debian's fakenect library.
 * libfreenect delivers raw 11-bit disparity; this source converts it to millimetres with
 * libfreenect's own formula (recordings.h: rec_raw_to_mm), since fakenect serves only
 * FREENECT_DEPTH_11BIT. */
#define _GNU_SOURCE /* dladdr: tell the fakenect library from the real one */
#include <dlfcn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>

#include <libfreenect.h>

#include "bus.h"
#include "cap_private.h"
#include "recordings.h"

#define PIXELS (REC_WIDTH * REC_HEIGHT)

typedef struct fn_state {
    freenect_context *ctx;
    freenect_device *dev;
    int started;
    int dump;        /* replaying a fakenect dump */
    rec_index index; /* the dump's own INDEX.txt, for the record times */
    int timeout_ms;
    int got; /* set by the callback */
    uint32_t timestamp;
    int64_t utime;
    int32_t seq;
    uint16_t table[REC_RAW_LEVELS];
    uint16_t raw[PIXELS];   /* libfreenect writes here (freenect_set_depth_buffer) */
    uint16_t frame[PIXELS]; /* the raw frame handed out */
    uint16_t mm[PIXELS];
} fn_state;

static void depth_cb(freenect_device *dev, void *depth, uint32_t timestamp)
{
    fn_state *s = freenect_get_user(dev);
    s->utime = bus_now_wall_us();
    memcpy(s->frame, depth, sizeof s->frame);
    s->timestamp = timestamp;
    s->got = 1;
}

static int library_is_fakenect(void)
{
    Dl_info info;
    void *sym = (void *)(uintptr_t)&freenect_process_events;
    return dladdr(sym, &info) && info.dli_fname && strstr(info.dli_fname, "fakenect");
}

static int fn_open(cap_source *src, const cap_source_desc *d, char *err, size_t errlen)
{
    fn_state *s = calloc(1, sizeof *s);
    if (!s)
        return -CAP_ERR_NO_MEMORY;
    src->impl = s;
    s->timeout_ms = d->timeout_ms > 0 ? d->timeout_ms : 2000;
    rec_raw_to_mm_table(s->table);
    int index = 0;
    if (cap_uri_is_dump(d->uri)) {
        s->dump = 1;
        if (!library_is_fakenect() || !getenv("FAKENECT_PATH")) {
            snprintf(err, errlen, "%s is a dump, but this process runs the real libfreenect",
                     d->uri);
            return -CAP_ERR_NOT_FAKENECT;
        }
        rec_report why;
        if (rec_index_read(d->uri, &s->index, &why) != REC_OK) {
            snprintf(err, errlen, "%s", why.message);
            return -CAP_ERR_RECORDING;
        }
    } else if (d->uri && *d->uri) {
        char *end;
        index = (int)strtol(d->uri, &end, 10);
        if (*end || index < 0) {
            snprintf(err, errlen, "'%s' is neither a device index nor a dump directory", d->uri);
            return -CAP_ERR_ARG;
        }
    }
    if (freenect_init(&s->ctx, NULL) < 0) {
        snprintf(err, errlen, "freenect_init failed");
        return -CAP_ERR_DEVICE;
    }
    freenect_set_log_level(s->ctx, FREENECT_LOG_ERROR);
    freenect_select_subdevices(s->ctx, FREENECT_DEVICE_CAMERA);
    int n = freenect_num_devices(s->ctx);
    if (n <= index) {
        snprintf(err, errlen, "Kinect %d requested, %d found (is it plugged in and powered?)",
                 index, n < 0 ? 0 : n);
        return -CAP_ERR_NO_DEVICE;
    }
    if (freenect_open_device(s->ctx, &s->dev, index) < 0) {
        snprintf(err, errlen, "cannot open Kinect %d (permissions? see docs/capture.md)", index);
        s->dev = NULL;
        return -CAP_ERR_DEVICE;
    }
    freenect_set_user(s->dev, s);
    freenect_set_depth_callback(s->dev, depth_cb);
    freenect_frame_mode mode =
        freenect_find_depth_mode(FREENECT_RESOLUTION_MEDIUM, FREENECT_DEPTH_11BIT);
    if (freenect_set_depth_mode(s->dev, mode) < 0 ||
        freenect_set_depth_buffer(s->dev, s->raw) < 0 || freenect_start_depth(s->dev) < 0) {
        snprintf(err, errlen, "cannot start the depth stream (11-bit, 640x480)");
        return -CAP_ERR_DEVICE;
    }
    s->started = 1;
    return CAP_OK;
}

static int fn_wait(fn_state *s, char *err, size_t errlen)
{
    int64_t deadline = bus_now_mono_us() + (int64_t)s->timeout_ms * 1000;
    s->got = 0;
    while (!s->got) {
        int r;
        if (s->dump) {
            /* fakenect: each call replays one INDEX.txt line; -1 after the last one. */
            if (s->seq >= s->index.count)
                return CAP_END;
            r = freenect_process_events(s->ctx);
            if (r < 0)
                return CAP_END;
            continue;
        }
        struct timeval tv = {0, 100000};
        r = freenect_process_events_timeout(s->ctx, &tv);
        if (r < 0) {
            snprintf(err, errlen, "freenect_process_events failed (%d): camera unplugged?", r);
            return -CAP_ERR_DEVICE;
        }
        if (!s->got && bus_now_mono_us() > deadline) {
            snprintf(err, errlen, "no depth frame from the Kinect in %d ms", s->timeout_ms);
            return -CAP_ERR_TIMEOUT;
        }
    }
    return CAP_OK;
}

static int fn_next(cap_source *src, cap_frame *out, char *err, size_t errlen)
{
    fn_state *s = src->impl;
    int e = fn_wait(s, err, errlen);
    if (e != CAP_OK)
        return e;
    for (int i = 0; i < PIXELS; i++) {
        uint16_t r = s->frame[i];
        s->mm[i] = s->table[r < REC_RAW_LEVELS ? r : REC_RAW_NONE];
    }
    *out = (cap_frame){.width = REC_WIDTH,
                       .height = REC_HEIGHT,
                       .depth_mm = s->mm,
                       .raw = s->frame,
                       .fx = (float)REC_FX,
                       .fy = (float)REC_FY,
                       .cx = (float)REC_CX,
                       .cy = (float)REC_CY,
                       .device_timestamp = s->timestamp,
                       .seq = s->seq,
                       .utime_capture = s->utime,
                       .replay_time_s = -1.0};
    if (s->dump)
        out->replay_time_s =
            s->index.frames[s->seq].record_time_s - s->index.frames[0].record_time_s;
    s->seq++;
    return CAP_OK;
}

static void fn_close(cap_source *src)
{
    fn_state *s = src->impl;
    if (!s)
        return;
    if (s->dev) {
        if (s->started)
            freenect_stop_depth(s->dev);
        freenect_close_device(s->dev);
    }
    if (s->ctx)
        freenect_shutdown(s->ctx);
    rec_index_free(&s->index);
    free(s);
    src->impl = NULL;
}

const cap_source_api cap_freenect_api = {"freenect", fn_open, fn_next, fn_close};
