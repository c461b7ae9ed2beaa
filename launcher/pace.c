/* tryon pace LOG: the BODY stream of a session recorded with `tryon run --record DIR` played to
 * a tryon-sim at the camera's pace, each body stamped as if captured now. The same fitted bodies
 * whatever the machine's load (record them at a low rate with tryon-bodyfit --queue all), at
 * the pipeline's own pace and with its body stage's latency, so that the sim's deadline
 * (--frame-budget auto) meets them as it meets them live. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "session.h"

#define PACE_MAX_BODIES 100000
#define PACE_MAX_SEQ    (1 << 20) /* a body stage's latency is kept per seq below this */

typedef struct pace_body {
    char channel[128];
    uint8_t *data;
    uint32_t n;
} pace_body;

typedef struct pace_log {
    pace_body *body;
    int n, cap, refused;
    int64_t *latency_us; /* [PACE_MAX_SEQ]: capture -> BODY as recorded (its TIMING); -1 unknown */
} pace_log;

static int ends_with(const char *s, const char *tail)
{
    size_t k = strlen(s), t = strlen(tail);
    return k >= t && strcmp(s + k - t, tail) == 0;
}

static void keep_body(pace_log *p, const char *ch, const uint8_t *d, uint32_t n)
{
    if (strlen(ch) >= sizeof p->body[0].channel || p->n >= PACE_MAX_BODIES) {
        p->refused++;
        return;
    }
    if (p->n == p->cap) {
        int cap = p->cap ? 2 * p->cap : 256;
        pace_body *b = realloc(p->body, (size_t)cap * sizeof *b);
        if (!b) {
            p->refused++;
            return;
        }
        p->body = b;
        p->cap = cap;
    }
    uint8_t *copy = malloc(n);
    if (!copy) {
        p->refused++;
        return;
    }
    memcpy(copy, d, n);
    pace_body *b = &p->body[p->n++];
    snprintf(b->channel, sizeof b->channel, "%s", ch);
    b->data = copy;
    b->n = n;
}

static void keep_latency(pace_log *p, const char *ch, const uint8_t *d, uint32_t n)
{
    tryon_timing_t t;
    bus_reject why;
    if (bus_decode_sealed(BUS_TIMING, ch, d, n, &t, &why) != BUS_OK)
        return;
    if (!strcmp(t.stage, "bodyfit") && t.seq >= 0 && t.seq < PACE_MAX_SEQ)
        p->latency_us[t.seq] = t.utime_finished - t.utime_capture;
    bus_msg_free(BUS_TIMING, &t);
}

static void scan(const char *ch, const uint8_t *d, uint32_t n, void *user)
{
    if (ends_with(ch, BUS_CHANNEL_BODY))
        keep_body(user, ch, d, n);
    else if (ends_with(ch, BUS_CHANNEL_TIMING))
        keep_latency(user, ch, d, n);
}

static void sleep_until_wall(int64_t t_us)
{
    int64_t left = t_us - bus_now_wall_us();
    if (left <= 0)
        return;
    struct timespec ts = {(time_t)(left / 1000000), (long)(left % 1000000) * 1000};
    nanosleep(&ts, NULL);
}

static int parse_double(const char *v, double lo, double hi, double *out)
{
    char *end;
    double x = strtod(v, &end);
    if (end == v || *end || !(x >= lo && x <= hi))
        return -1;
    *out = x;
    return 0;
}

/* Plays the bodies: body k captured at t0 + k / fps, sent when its latency has passed. Returns
 * the bodies sent. */
static int play(lcm_t *lcm, const pace_log *p, double fps, double latency_ms)
{
    char channel[BUS_CHANNEL_MAX];
    bus_channel(BUS_CHANNEL_BODY, channel, sizeof channel);
    int64_t t0 = bus_now_wall_us() + 200000, period_us = (int64_t)(1e6 / fps);
    int sent = 0;
    for (int k = 0; k < p->n; k++) {
        tryon_body_t m;
        bus_reject why;
        const pace_body *b = &p->body[k];
        if (bus_decode_sealed(BUS_BODY, b->channel, b->data, b->n, &m, &why) != BUS_OK) {
            fprintf(stderr, "tryon pace: body %d of the log: %s (%s); skipped\n", k,
                    bus_error_text(why.code), why.detail);
            continue;
        }
        int64_t capture = t0 + k * period_us;
        int64_t lat = latency_ms >= 0.0 ? (int64_t)(latency_ms * 1000.0)
                      : m.seq >= 0 && m.seq < PACE_MAX_SEQ && p->latency_us[m.seq] >= 0
                          ? p->latency_us[m.seq]
                          : 0;
        sleep_until_wall(capture + lat);
        m.utime_capture = capture;
        if (bus_publish(lcm, channel, BUS_BODY, &m, &why) == BUS_OK)
            sent++;
        else
            fprintf(stderr, "tryon pace: body %d not sent: %s (%s)\n", m.seq,
                    bus_error_text(why.code), why.detail);
        bus_msg_free(BUS_BODY, &m);
    }
    return sent;
}

static void pace_usage(FILE *f)
{
    fprintf(f,
            "usage: tryon pace LOG [--fps F] [--latency MS]\n"
            "  LOG's BODY messages (tryon run --record DIR: DIR/session.lcmlog) sent in order on\n"
            "  $TRYON_CHANNEL_PREFIX's BODY, body k captured at k / F s (default 30) and sent\n"
            "  when its body stage's recorded latency (its TIMING) has passed, or --latency MS\n");
}

int tryon_pace(int argc, char **argv)
{
    const char *log = NULL;
    double fps = 30.0, latency_ms = -1.0;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            pace_usage(stdout);
            return 0;
        } else if (a[0] != '-' && !log)
            log = a;
        else if (v && !strcmp(a, "--fps") && parse_double(v, 1.0, 1000.0, &fps) == 0)
            i++;
        else if (v && !strcmp(a, "--latency") && parse_double(v, 0.0, 10000.0, &latency_ms) == 0)
            i++;
        else {
            fprintf(stderr, "tryon pace: %s: unknown option, bad or missing value\n", a);
            pace_usage(stderr);
            return 2;
        }
    }
    pace_log p = {.latency_us = malloc(PACE_MAX_SEQ * sizeof(int64_t))};
    if (!p.latency_us)
        return 1;
    memset(p.latency_us, 0xff, PACE_MAX_SEQ * sizeof(int64_t)); /* -1: unknown */
    int status = 2;
    char err[512];
    lcm_t *lcm = NULL;
    if (!log || session_log_each(log, scan, &p) < 0 || p.n == 0)
        fprintf(stderr, "tryon pace: %s: not an LCM log with BODY messages\n",
                log ? log : "(no LOG given)");
    else if (!(lcm = bus_open(NULL, err, sizeof err)))
        fprintf(stderr, "tryon pace: %s\n", err);
    else {
        int sent = play(lcm, &p, fps, latency_ms);
        printf("tryon pace: %d of %d bodies sent at %.1f fps (%d not kept from the log)\n", sent,
               p.n, fps, p.refused);
        status = sent == p.n ? 0 : 1;
    }
    if (lcm)
        lcm_destroy(lcm);
    for (int k = 0; k < p.n; k++)
        free(p.body[k].data);
    free(p.body);
    free(p.latency_us);
    return status;
}
