/* The capture loop: pace, fetch, convert, publish DEPTH and TIMING, optionally record. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bus.h"
#include "capture.h"
#include "recordings.h"

void cap_default_camera_to_world(float m[16])
{
    rec_camera_to_world(m);
}

/* Everything the loop needs, allocated before the first frame. */
typedef struct run_state {
    cap_source *src;
    rec_writer *writer;
    uint8_t *bytes; /* little-endian depth for the message */
    size_t bytes_cap;
    uint16_t *record; /* disparity for --record from millimetre sources */
    float *lag_ms;    /* per frame, for the median and p95 */
    int lag_cap;
    char channel[BUS_CHANNEL_MAX];
    float c2w[16];
    int frames;              /* published so far */
    int64_t t_first, t_last; /* monotonic us: first fetch, last publish */
    int64_t first_utime;     /* wall us of the first frame, for --record times */
} run_state;

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static double percentile(float *v, int n, double p)
{
    if (n <= 0)
        return 0.0;
    qsort(v, (size_t)n, sizeof *v, cmp_float);
    int i = (int)ceil(p * n) - 1;
    return v[i < 0 ? 0 : i >= n ? n - 1 : i];
}

static int run_record(run_state *r, const cap_frame *f, int64_t first_utime, char *err,
                      size_t errlen)
{
    if (f->width != REC_WIDTH || f->height != REC_HEIGHT) {
        snprintf(err, errlen, "--record writes 640x480 fakenect dumps; frame %d is %dx%d", f->seq,
                 f->width, f->height);
        return -CAP_ERR_RECORD;
    }
    const uint16_t *raw = f->raw;
    if (!raw) {
        for (int i = 0; i < REC_WIDTH * REC_HEIGHT; i++)
            r->record[i] = f->depth_mm[i] ? rec_mm_to_raw(f->depth_mm[i] * 0.001) : REC_RAW_NONE;
        raw = r->record;
    }
    double t = f->replay_time_s >= 0.0 ? f->replay_time_s : (f->utime_capture - first_utime) * 1e-6;
    rec_report why;
    /* Times from 1 s, as tryon-synth writes them (fakenect reads a time of 0 as "none"). */
    if (rec_writer_frame(r->writer, raw, 1.0 + t, (uint32_t)f->device_timestamp, &why) != REC_OK) {
        snprintf(err, errlen, "%s", why.message);
        return -CAP_ERR_RECORD;
    }
    return CAP_OK;
}

static int publish(run_state *r, lcm_t *lcm, const cap_frame *f, const char *source, char *err,
                   size_t errlen)
{
    size_t n = (size_t)f->width * (size_t)f->height;
    if (n * 2 > r->bytes_cap) {
        /* Only when the camera's resolution grows, never per frame. */
        free(r->bytes);
        r->bytes = malloc(n * 2);
        r->bytes_cap = r->bytes ? n * 2 : 0;
        if (!r->bytes)
            return -CAP_ERR_NO_MEMORY;
    }
    for (size_t i = 0; i < n; i++) {
        r->bytes[2 * i] = (uint8_t)(f->depth_mm[i] & 0xff);
        r->bytes[2 * i + 1] = (uint8_t)(f->depth_mm[i] >> 8);
    }
    tryon_depth_frame_t msg = {.utime_capture = f->utime_capture,
                               .device_timestamp = f->device_timestamp,
                               .seq = f->seq,
                               .source = (char *)source,
                               .width = f->width,
                               .height = f->height,
                               .fx = f->fx,
                               .fy = f->fy,
                               .cx = f->cx,
                               .cy = f->cy,
                               .metres_per_unit = 0.001f,
                               .encoding = TRYON_DEPTH_FRAME_T_ENCODING_U16,
                               .num_bytes = (int32_t)(n * 2),
                               .data = r->bytes};
    memcpy(msg.camera_to_world, r->c2w, sizeof r->c2w);
    bus_reject why;
    int e = bus_publish(lcm, r->channel, BUS_DEPTH_FRAME, &msg, &why);
    if (e != BUS_OK) {
        snprintf(err, errlen, "frame %d on %s: %s (%s)", f->seq, r->channel, bus_error_text(e),
                 why.detail);
        return -CAP_ERR_BUS;
    }
    return CAP_OK;
}

static void run_free(run_state *r)
{
    cap_source_destroy(r->src);
    rec_writer_destroy(r->writer);
    free(r->bytes);
    free(r->record);
    free(r->lag_ms);
}

static int run_setup(run_state *r, const cap_run_desc *d, char *err, size_t errlen)
{
    int code;
    if (bus_channel(BUS_CHANNEL_DEPTH, r->channel, sizeof r->channel) != 0) {
        snprintf(err, errlen, "channel name too long (TRYON_CHANNEL_PREFIX)");
        return -CAP_ERR_ARG;
    }
    if (d->camera_to_world)
        memcpy(r->c2w, d->camera_to_world, sizeof r->c2w);
    else
        cap_default_camera_to_world(r->c2w);
    r->lag_cap = d->frames > 0 ? d->frames : 1 << 16;
    r->lag_ms = malloc(sizeof(float) * (size_t)r->lag_cap);
    r->bytes_cap = (size_t)REC_WIDTH * REC_HEIGHT * 2;
    r->bytes = malloc(r->bytes_cap);
    r->record = malloc(sizeof(uint16_t) * REC_WIDTH * REC_HEIGHT);
    if (!r->lag_ms || !r->bytes || !r->record)
        return -CAP_ERR_NO_MEMORY;
    if (d->record_dir) {
        rec_report why;
        r->writer = rec_writer_create(d->record_dir, &why);
        if (!r->writer) {
            snprintf(err, errlen, "--record: %s", why.message);
            return -CAP_ERR_RECORD;
        }
    }
    cap_source_desc sd = {.uri = d->uri, .max_speed = d->rate.mode != CAP_RATE_REALTIME};
    r->src = cap_source_create(d->source, &sd, &code, err, errlen);
    return r->src ? CAP_OK : code;
}

static float ms_between(int64_t a_us, int64_t b_us)
{
    return (float)((b_us - a_us) / 1000.0);
}

/* One frame: fetch, wait for its due time, stamp, publish, record. A frame skipped (live camera
 * in FPS mode) or interrupted by a stop while waiting is not counted. */
static int run_frame(run_state *r, const cap_run_desc *d, cap_pacer *pacer,
                     volatile sig_atomic_t *stop, char *err, size_t errlen)
{
    cap_frame f;
    int64_t t_fetch = bus_now_mono_us();
    int e = cap_source_next(r->src, &f, err, errlen);
    if (e != CAP_OK)
        return e;
    int64_t t_fetched = bus_now_mono_us();
    int skip = 0;
    int64_t due = cap_pacer_due(pacer, f.replay_time_s, &skip);
    if (skip)
        return CAP_OK;
    if (r->frames == 0) {
        r->t_first = t_fetch;
        r->first_utime = f.utime_capture;
    }
    cap_sleep_until(due, stop);
    if (*stop)
        return CAP_OK;
    if (f.replay_time_s >= 0.0)
        f.utime_capture = bus_now_wall_us(); /* the replayed camera "delivers" it now */
    int64_t t0 = bus_now_mono_us();
    bus_timing timing;
    bus_timing_begin(&timing, "capture", f.seq, f.utime_capture, f.utime_capture);
    e = publish(r, d->lcm, &f, d->source, err, errlen);
    int64_t t1 = bus_now_mono_us();
    if (e == CAP_OK && r->writer)
        e = run_record(r, &f, r->first_utime, err, errlen);
    if (e != CAP_OK)
        return e;
    bus_timing_add(&timing, "fetch", ms_between(t_fetch, t_fetched));
    bus_timing_add(&timing, "publish", ms_between(t0, t1));
    bus_timing_publish(d->lcm, &timing);
    if (r->frames < r->lag_cap)
        r->lag_ms[r->frames] = ms_between(due, t1);
    r->t_last = bus_now_mono_us();
    r->frames++;
    return CAP_OK;
}

int cap_run(const cap_run_desc *d, volatile sig_atomic_t *stop, cap_run_stats *stats, char *err,
            size_t errlen)
{
    run_state r = {0};
    memset(stats, 0, sizeof *stats);
    int e = run_setup(&r, d, err, errlen);
    cap_pacer pacer;
    cap_pacer_init(&pacer, d->rate);
    /* A recorded frame is fetched (read, converted) first, then waits for its due time, is
     * stamped and published, like a camera that delivers at its frame time. The lag reported is
     * due time to publish done; at --rate max the due time is when the fetch finished. */
    while (e == CAP_OK && !*stop && (d->frames <= 0 || r.frames < d->frames))
        e = run_frame(&r, d, &pacer, stop, err, errlen);
    if (e == CAP_END)
        e = CAP_OK;
    int n = r.frames < r.lag_cap ? r.frames : r.lag_cap;
    stats->frames = r.frames;
    stats->seconds = r.frames ? (r.t_last - r.t_first) * 1e-6 : 0.0;
    stats->lag_p50_ms = percentile(r.lag_ms, n, 0.5);
    stats->lag_p95_ms = percentile(r.lag_ms, n, 0.95);
    stats->lag_max_ms = percentile(r.lag_ms, n, 1.0);
    run_free(&r);
    return e;
}
