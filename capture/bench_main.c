/* tryon-bench-capture: listens on DEPTH and TIMING while tryon-capture runs, and reports what
 * arrived: frames, drops (gaps in seq), receive rate, and capture-to-receive latency. Prints a
 * human table, then one JSON line.
 *   tryon-bench-capture --frames N [--timeout S] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bus.h"

#define MAX_FRAMES 100000

typedef struct bench {
    int frames, timings, gaps;
    int32_t last_seq;
    int64_t first_us, last_us;
    float *latency_ms;
} bench;

static void on_depth(const char *channel, const void *msg, void *user)
{
    (void)channel;
    bench *b = user;
    const tryon_depth_frame_t *m = msg;
    int64_t now = bus_now_wall_us();
    if (b->frames > 0 && m->seq != b->last_seq + 1)
        b->gaps += m->seq > b->last_seq ? m->seq - b->last_seq - 1 : 1;
    if (b->frames == 0)
        b->first_us = now;
    b->last_us = now;
    b->last_seq = m->seq;
    if (b->frames < MAX_FRAMES)
        b->latency_ms[b->frames] = (float)((now - m->utime_capture) / 1000.0);
    b->frames++;
}

static void on_timing(const char *channel, const void *msg, void *user)
{
    (void)channel;
    const tryon_timing_t *t = msg;
    if (!strcmp(t->stage, "capture"))
        ((bench *)user)->timings++;
}

static int cmp(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static double pct(const float *v, int n, double p)
{
    int i = (int)ceil(p * n) - 1;
    return n ? v[i < 0 ? 0 : i] : 0.0;
}

int main(int argc, char **argv)
{
    int want = 0;
    double timeout_s = 60.0;
    static const char usage[] = "usage: tryon-bench-capture --frames N [--timeout S]\n";
    for (int i = 1; i < argc; i += 2) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (i + 1 < argc && !strcmp(argv[i], "--frames")) {
            want = atoi(argv[i + 1]);
        } else if (i + 1 < argc && !strcmp(argv[i], "--timeout")) {
            timeout_s = atof(argv[i + 1]);
        } else {
            fprintf(stderr, "tryon-bench-capture: unknown option %s\n%s", argv[i], usage);
            return 2;
        }
    }
    if (want <= 0 || want > MAX_FRAMES || !(timeout_s > 0.0)) {
        fputs(usage, stderr);
        return 2;
    }
    char err[512], ch[BUS_CHANNEL_MAX];
    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    if (!lcm) {
        fprintf(stderr, "tryon-bench-capture: %s\n", err);
        return 1;
    }
    bench b = {.latency_ms = malloc(sizeof(float) * MAX_FRAMES)};
    bus_channel(BUS_CHANNEL_DEPTH, ch, sizeof ch);
    bus_sub *sd = bus_subscribe(lcm, ch, BUS_DEPTH_FRAME, on_depth, &b);
    bus_channel(BUS_CHANNEL_TIMING, ch, sizeof ch);
    bus_sub *st = bus_subscribe(lcm, ch, BUS_TIMING, on_timing, &b);
    int64_t end = bus_now_mono_us() + (int64_t)(timeout_s * 1e6);
    while (b.frames < want && bus_now_mono_us() < end)
        lcm_handle_timeout(lcm, 100);
    /* The TIMING of the last frame follows its DEPTH. */
    while (b.timings < b.frames && lcm_handle_timeout(lcm, 200) > 0)
        ;
    int n = b.frames < MAX_FRAMES ? b.frames : MAX_FRAMES;
    qsort(b.latency_ms, (size_t)n, sizeof(float), cmp);
    double secs = (b.last_us - b.first_us) * 1e-6;
    double fps = secs > 0.0 ? (b.frames - 1) / secs : 0.0;
    printf("%-28s %10s\n", "DEPTH frames received", "");
    printf("%-28s %10d\n", "frames", b.frames);
    printf("%-28s %10d\n", "missing (of --frames)", want - b.frames);
    printf("%-28s %10d\n", "frames skipped in seq", b.gaps);
    printf("%-28s %10d\n", "TIMING (capture) messages", b.timings);
    printf("%-28s %10.1f\n", "receive rate (frames/s)", fps);
    printf("%-28s %10.3f\n", "capture->receive p50 (ms)", pct(b.latency_ms, n, 0.5));
    printf("%-28s %10.3f\n", "capture->receive p95 (ms)", pct(b.latency_ms, n, 0.95));
    printf("{\"frames\":%d,\"missing\":%d,\"seq_gaps\":%d,\"timings\":%d,\"fps\":%.2f,"
           "\"ms_median\":%.4f,\"ms_p95\":%.4f}\n",
           b.frames, want - b.frames, b.gaps, b.timings, fps, pct(b.latency_ms, n, 0.5),
           pct(b.latency_ms, n, 0.95));
    bus_unsubscribe(lcm, sd);
    bus_unsubscribe(lcm, st);
    lcm_destroy(lcm);
    free(b.latency_ms);
    return b.frames == want ? 0 : 1;
}
