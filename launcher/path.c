/* tryon path LOG: where a frame's time goes, stage by stage, from a session recorded with
 * `tryon run --record DIR`. Each frame's TIMING from capture, bodyfit, sim and mirror are joined
 * by their capture time; between two stages is the wait (the next stage still busy, or waiting
 * for a core) and the bus. Printed for every frame, and for the slowest twentieth (what the p95
 * is made of). With --each, also one line a frame in capture order, a stage that did not see
 * the frame shown as "-": where the first frames' time goes, and which stage dropped which. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "session.h"

enum { PATH_CAPTURE, PATH_BODY, PATH_SIM, PATH_MIRROR, PATH_STAGES };
static const char *const stage_names[PATH_STAGES] = {"capture", "bodyfit", "sim", "mirror"};
#define PATH_MAX_RECORDS 400000

typedef struct path_rec {
    int64_t capture, started, finished;
    int stage;
} path_rec;

typedef struct path_log {
    path_rec *rec;
    int n, cap;
} path_log;

static void keep(const char *ch, const uint8_t *d, uint32_t n, void *user)
{
    path_log *p = user;
    size_t k = strlen(ch), t = strlen(BUS_CHANNEL_TIMING);
    if (k < t || strcmp(ch + k - t, BUS_CHANNEL_TIMING) != 0 || p->n >= PATH_MAX_RECORDS)
        return;
    tryon_timing_t m;
    bus_reject why;
    if (bus_decode_sealed(BUS_TIMING, ch, d, n, &m, &why) != BUS_OK)
        return;
    int stage = -1;
    for (int s = 0; s < PATH_STAGES; s++)
        if (!strcmp(m.stage, stage_names[s]))
            stage = s;
    if (stage >= 0 && p->n == p->cap) {
        int cap = p->cap ? 2 * p->cap : 1024;
        path_rec *r = realloc(p->rec, (size_t)cap * sizeof *r);
        if (r) {
            p->rec = r;
            p->cap = cap;
        }
    }
    if (stage >= 0 && p->n < p->cap)
        p->rec[p->n++] = (path_rec){m.utime_capture, m.utime_started, m.utime_finished, stage};
    bus_msg_free(BUS_TIMING, &m);
}

static int by_capture(const void *a, const void *b)
{
    const path_rec *x = a, *y = b;
    return x->capture != y->capture ? (x->capture > y->capture) - (x->capture < y->capture)
                                    : x->stage - y->stage;
}

static int by_ms(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* A frame's path through the stages up to last: 2 * last + 2 segments, ms: the capture's own
 * time, then for each stage after it the wait before it and its work; total last. */
enum { PATH_SEGMENTS = 2 * PATH_STAGES };

static void segments(const path_rec *st[PATH_STAGES], int last, double *seg)
{
    seg[0] = (double)(st[PATH_CAPTURE]->finished - st[PATH_CAPTURE]->capture) / 1e3;
    for (int s = 1; s <= last; s++) {
        seg[2 * s - 1] = (double)(st[s]->started - st[s - 1]->finished) / 1e3;
        seg[2 * s] = (double)(st[s]->finished - st[s]->started) / 1e3;
    }
    seg[2 * last + 1] = (double)(st[last]->finished - st[PATH_CAPTURE]->capture) / 1e3;
}

static void segment_name(int k, int last, char *out, size_t n)
{
    if (k == 0)
        snprintf(out, n, "capture (fetch, publish)");
    else if (k == 2 * last + 1)
        snprintf(out, n, "capture -> %s finished", stage_names[last]);
    else if (k % 2)
        snprintf(out, n, "  wait + bus before %s", stage_names[(k + 1) / 2]);
    else
        snprintf(out, n, "  %s work", stage_names[k / 2]);
}

/* Prints the path up to last over the frames that reached it: p50, p95 and mean of each
 * segment, and its mean over the slowest twentieth of frames by total. */
static void print_path(double (*seg)[PATH_SEGMENTS], int n, int last)
{
    int ns = 2 * last + 2;
    printf("== capture -> %s, %d frames, ms: p50 p95 mean | mean in the slowest 5 %%\n",
           stage_names[last], n);
    if (n == 0)
        return;
    double *v = malloc((size_t)n * sizeof *v), *total = malloc((size_t)n * sizeof *total);
    if (!v || !total) {
        free(v);
        free(total);
        return;
    }
    for (int f = 0; f < n; f++)
        total[f] = seg[f][ns - 1];
    qsort(total, (size_t)n, sizeof *total, by_ms);
    double slow = total[(int)(n * 0.95)];
    for (int k = 0; k < ns; k++) {
        double sum = 0.0, sum_slow = 0.0;
        int n_slow = 0;
        for (int f = 0; f < n; f++) {
            v[f] = seg[f][k];
            sum += v[f];
            if (seg[f][ns - 1] >= slow) {
                sum_slow += v[f];
                n_slow++;
            }
        }
        qsort(v, (size_t)n, sizeof *v, by_ms);
        char name[64];
        segment_name(k, last, name, sizeof name);
        printf("  %-32s %7.1f %7.1f %7.1f | %7.1f\n", name, v[n / 2], v[(int)(n * 0.95)], sum / n,
               n_slow ? sum_slow / n_slow : 0.0);
    }
    free(v);
    free(total);
}

/* One line for the frame whose stages' reports are st (a missing one NULL): the capture's own
 * ms, then per stage the wait before it and its work, and the latency to the last stage seen. */
static void print_frame(int k, const path_rec *st[PATH_STAGES])
{
    printf("%5d %7.1f", k, (double)(st[PATH_CAPTURE]->finished - st[PATH_CAPTURE]->capture) / 1e3);
    int last = PATH_CAPTURE;
    for (int s = 1; s < PATH_STAGES; s++) {
        if (!st[s] || !st[last]) {
            printf(" %7s %7s", "-", "-");
            continue;
        }
        printf(" %7.1f %7.1f", (double)(st[s]->started - st[last]->finished) / 1e3,
               (double)(st[s]->finished - st[s]->started) / 1e3);
        last = s;
    }
    printf(" %7.1f %s\n", (double)(st[last]->finished - st[PATH_CAPTURE]->capture) / 1e3,
           stage_names[last]);
}

int tryon_path(int argc, char **argv)
{
    int each = argc == 4 && !strcmp(argv[3], "--each");
    if ((argc != 3 && !each) || argv[2][0] == '-') {
        int help = argc == 3 && (!strcmp(argv[2], "--help") || !strcmp(argv[2], "-h"));
        fprintf(help ? stdout : stderr,
                "usage: tryon path LOG [--each]\n"
                "  where each frame's time goes, stage by stage (TIMING of a session recorded\n"
                "  with tryon run --record DIR: DIR/session.lcmlog); --each: also one line a\n"
                "  frame, \"-\" where a stage did not see it\n");
        return help ? 0 : 2;
    }
    path_log p = {0};
    if (session_log_each(argv[2], keep, &p) < 0 || p.n == 0) {
        fprintf(stderr, "tryon path: %s: not an LCM log with TIMING messages\n", argv[2]);
        free(p.rec);
        return 2;
    }
    qsort(p.rec, (size_t)p.n, sizeof *p.rec, by_capture);
    double(*to_sim)[PATH_SEGMENTS] = calloc((size_t)p.n, sizeof *to_sim);
    double(*to_mirror)[PATH_SEGMENTS] = calloc((size_t)p.n, sizeof *to_mirror);
    int n_sim = 0, n_mirror = 0, frame = 0;
    if (each)
        printf("== each frame, ms: frame, capture, then wait and work before and in bodyfit, sim, "
               "mirror; latency to the last stage\n");
    for (int i = 0; to_sim && to_mirror && i < p.n;) {
        const path_rec *st[PATH_STAGES] = {0};
        int j = i;
        for (; j < p.n && p.rec[j].capture == p.rec[i].capture; j++)
            st[p.rec[j].stage] = &p.rec[j]; /* a stage restarted mid-frame: its last report */
        i = j;
        if (each && st[PATH_CAPTURE])
            print_frame(frame++, st);
        if (!st[PATH_CAPTURE] || !st[PATH_BODY] || !st[PATH_SIM])
            continue;
        segments(st, PATH_SIM, to_sim[n_sim++]);
        if (st[PATH_MIRROR])
            segments(st, PATH_MIRROR, to_mirror[n_mirror++]);
    }
    print_path(to_sim, n_sim, PATH_SIM);
    print_path(to_mirror, n_mirror, PATH_MIRROR);
    free(to_sim);
    free(to_mirror);
    free(p.rec);
    return 0;
}
