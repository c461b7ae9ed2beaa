/* Latency statistics from timing_t reports. */
#include "profile.h"

#include <stdlib.h>
#include <string.h>

typedef struct stage_samples {
    char name[32];
    int n, cap;
    double *work_ms, *lat_ms;
    int32_t *seq;
    int64_t first_finish, last_finish;
    int num_sub;
    char sub[BUS_MAX_SUBSTAGES][32];
    int sub_n[BUS_MAX_SUBSTAGES], sub_cap[BUS_MAX_SUBSTAGES];
    double *sub_ms[BUS_MAX_SUBSTAGES];
} stage_samples;

struct bus_profile {
    int num_stages;
    int warmup;
    stage_samples stages[BUS_PROFILE_MAX_STAGES];
};

/* Where a stage sits in the pipeline; unknown stages sort after, by name. */
static int stage_rank(const char *name)
{
    static const char *const order[] = {"capture", "bodyfit", "sim", "mirror"};
    for (int i = 0; i < 4; i++)
        if (strcmp(name, order[i]) == 0)
            return i;
    return 4;
}

bus_profile *bus_profile_create(void)
{
    return calloc(1, sizeof(bus_profile));
}

void bus_profile_destroy(bus_profile *p)
{
    if (!p)
        return;
    for (int i = 0; i < p->num_stages; i++) {
        stage_samples *s = &p->stages[i];
        free(s->work_ms);
        free(s->lat_ms);
        free(s->seq);
        for (int k = 0; k < s->num_sub; k++)
            free(s->sub_ms[k]);
    }
    free(p);
}

static int grow(void **ptr, int *cap, int need, size_t elem)
{
    if (need <= *cap)
        return 0;
    int c = *cap ? *cap * 2 : 256;
    void *q = realloc(*ptr, (size_t)c * elem);
    if (!q)
        return -1;
    *ptr = q;
    *cap = c;
    return 0;
}

/* Room for one more sample in each of the three per-frame arrays. */
static int reserve_samples(stage_samples *s)
{
    if (s->n < s->cap)
        return 0;
    int cap = s->cap ? s->cap * 2 : 256;
    double *w = realloc(s->work_ms, (size_t)cap * sizeof *w);
    if (w)
        s->work_ms = w;
    double *l = realloc(s->lat_ms, (size_t)cap * sizeof *l);
    if (l)
        s->lat_ms = l;
    int32_t *q = realloc(s->seq, (size_t)cap * sizeof *q);
    if (q)
        s->seq = q;
    if (!w || !l || !q)
        return -1;
    s->cap = cap;
    return 0;
}

/* Names are stored cut to 31 characters, so they are compared cut the same way: a long name
 * finds its own slot again instead of taking a new one on every report. */
#define NAME_KEY 32

static stage_samples *find_stage(bus_profile *p, const char *name)
{
    char key[NAME_KEY];
    snprintf(key, sizeof key, "%s", name);
    for (int i = 0; i < p->num_stages; i++)
        if (strcmp(p->stages[i].name, key) == 0)
            return &p->stages[i];
    if (p->num_stages == BUS_PROFILE_MAX_STAGES)
        return NULL;
    stage_samples *s = &p->stages[p->num_stages++];
    snprintf(s->name, sizeof s->name, "%s", key);
    return s;
}

static int add_substage(stage_samples *s, const char *name, double ms)
{
    char key[NAME_KEY];
    snprintf(key, sizeof key, "%s", name);
    int k = 0;
    while (k < s->num_sub && strcmp(s->sub[k], key) != 0)
        k++;
    if (k == s->num_sub) {
        if (k == BUS_MAX_SUBSTAGES)
            return 0;
        snprintf(s->sub[k], sizeof s->sub[k], "%s", key);
        s->num_sub++;
    }
    if (grow((void **)&s->sub_ms[k], &s->sub_cap[k], s->sub_n[k] + 1, sizeof(double)) != 0)
        return -1;
    s->sub_ms[k][s->sub_n[k]++] = ms;
    return 0;
}

int bus_profile_add(bus_profile *p, const tryon_timing_t *t)
{
    stage_samples *s = find_stage(p, t->stage);
    if (!s || reserve_samples(s) != 0)
        return -BUS_ERR_NO_MEMORY;
    s->work_ms[s->n] = (double)(t->utime_finished - t->utime_started) / 1000.0;
    s->lat_ms[s->n] = (double)(t->utime_finished - t->utime_capture) / 1000.0;
    s->seq[s->n] = t->seq;
    if (s->n == 0 || t->utime_finished < s->first_finish)
        s->first_finish = t->utime_finished;
    if (s->n == 0 || t->utime_finished > s->last_finish)
        s->last_finish = t->utime_finished;
    s->n++;
    for (int i = 0; i < t->num_substages; i++)
        if (add_substage(s, t->substage[i], t->substage_ms[i]) != 0)
            return -BUS_ERR_NO_MEMORY;
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int cmp_i32(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

/* Nearest-rank percentile of a sorted array. */
static double percentile(const double *sorted, int n, double q)
{
    if (n == 0)
        return 0;
    int k = (int)(q / 100.0 * n + 0.999999) - 1;
    return sorted[k < 0 ? 0 : (k >= n ? n - 1 : k)];
}

static void sorted_percentiles(const double *v, int n, double *p50, double *p95, double *p99,
                               double *max)
{
    double *c = malloc((size_t)(n ? n : 1) * sizeof *c);
    if (!c) {
        *p50 = *p95 = *p99 = *max = 0;
        return;
    }
    memcpy(c, v, (size_t)n * sizeof *c);
    qsort(c, (size_t)n, sizeof *c, cmp_double);
    *p50 = percentile(c, n, 50);
    *p95 = percentile(c, n, 95);
    *p99 = percentile(c, n, 99);
    *max = n ? c[n - 1] : 0;
    free(c);
}

static int count_dropped(const int32_t *seq, int n)
{
    int32_t *c = malloc((size_t)(n ? n : 1) * sizeof *c);
    if (!c || n == 0) {
        free(c);
        return 0;
    }
    memcpy(c, seq, (size_t)n * sizeof *c);
    qsort(c, (size_t)n, sizeof *c, cmp_i32);
    /* Only gaps up to BUS_PROFILE_MAX_GAP count as drops: a larger jump is a stage that
     * restarted its numbering (or one stray report), and one report must not claim billions of
     * lost frames. */
    int64_t dropped = 0;
    for (int i = 1; i < n; i++) {
        int64_t gap = (int64_t)c[i] - c[i - 1] - 1;
        if (gap > 0 && gap <= BUS_PROFILE_MAX_GAP)
            dropped += gap;
    }
    free(c);
    return dropped > INT32_MAX ? INT32_MAX : (int)dropped;
}

static int32_t first_seq(const stage_samples *s)
{
    int32_t first = s->n ? s->seq[0] : 0;
    for (int i = 1; i < s->n; i++)
        first = s->seq[i] < first ? s->seq[i] : first;
    return first;
}

/* The latencies of the frames after the first `warmup` by seq, and the frames missing among
 * them (from the warm-up's end on). */
static void steady_stats(const stage_samples *s, int warmup, bus_stage_stats *o)
{
    int32_t first = first_seq(s);
    double *lat = malloc((size_t)(s->n + 1) * sizeof *lat);
    int32_t *seq = malloc((size_t)(s->n + 1) * sizeof *seq);
    if (!lat || !seq) { /* out of memory: no steady figures rather than wrong ones */
        free(lat);
        free(seq);
        return;
    }
    int n = 0;
    for (int i = 0; i < s->n; i++)
        if ((int64_t)s->seq[i] - first >= warmup) {
            lat[n] = s->lat_ms[i];
            seq[n++] = s->seq[i];
        }
    o->steady_frames = n;
    double max;
    sorted_percentiles(lat, n, &o->steady_lat_p50_ms, &o->steady_lat_p95_ms, &o->steady_lat_p99_ms,
                       &max);
    if (n && warmup > 0) /* the warm-up's last frame as a fence: a gap right after counts */
        seq[n++] = (int32_t)((int64_t)first + warmup - 1);
    o->steady_dropped = count_dropped(seq, n);
    free(lat);
    free(seq);
}

/* The stage that hands this one every frame it makes, or NULL: capture's every DEPTH goes to the
 * fitter, the sim's every CLOTH to the mirror; the fitter's BODY of nobody is not dressed, so
 * the sim's first frame is the person's. */
static const stage_samples *feeder(const bus_profile *p, const char *name)
{
    const char *from = !strcmp(name, "bodyfit") ? "capture" : !strcmp(name, "mirror") ? "sim" : 0;
    for (int i = 0; from && i < p->num_stages; i++)
        if (!strcmp(p->stages[i].name, from) && p->stages[i].n > 0)
            return &p->stages[i];
    return NULL;
}

/* Frames its feeder made before this stage's first one: never reached it (a mirror that drew
 * its first CLOTH late superseded those before it), counted as dropped as gaps are. */
static int dropped_before(const stage_samples *s, const stage_samples *from)
{
    if (!from || s->n == 0)
        return 0;
    int32_t first = first_seq(s);
    int64_t lead = (int64_t)first - first_seq(from);
    int missing = 0;
    for (int i = 0; lead > 0 && lead <= BUS_PROFILE_MAX_GAP && i < from->n; i++)
        missing += from->seq[i] < first;
    return missing;
}

static void stage_stats(const stage_samples *s, const stage_samples *from, int warmup,
                        bus_stage_stats *o)
{
    memset(o, 0, sizeof *o);
    snprintf(o->stage, sizeof o->stage, "%s", s->name);
    o->frames = s->n;
    o->dropped = count_dropped(s->seq, s->n) + dropped_before(s, from);
    double span_s = (double)(s->last_finish - s->first_finish) / 1e6;
    o->fps = (s->n > 1 && span_s > 0) ? (s->n - 1) / span_s : 0;
    sorted_percentiles(s->work_ms, s->n, &o->work_p50_ms, &o->work_p95_ms, &o->work_p99_ms,
                       &o->work_max_ms);
    sorted_percentiles(s->lat_ms, s->n, &o->lat_p50_ms, &o->lat_p95_ms, &o->lat_p99_ms,
                       &o->lat_max_ms);
    steady_stats(s, warmup, o);
    if (warmup == 0)
        o->steady_dropped = o->dropped;
    o->num_substages = s->num_sub;
    for (int k = 0; k < s->num_sub; k++) {
        double p95, p99, max;
        snprintf(o->substage[k], sizeof o->substage[k], "%s", s->sub[k]);
        sorted_percentiles(s->sub_ms[k], s->sub_n[k], &o->substage_p50_ms[k], &p95, &p99, &max);
    }
}

static int cmp_stats(const void *a, const void *b)
{
    const bus_stage_stats *x = a, *y = b;
    int rx = stage_rank(x->stage), ry = stage_rank(y->stage);
    return rx != ry ? rx - ry : strcmp(x->stage, y->stage);
}

void bus_profile_set_warmup(bus_profile *p, int frames)
{
    p->warmup = frames > 0 ? frames : 0;
}

int bus_profile_stats(const bus_profile *p, bus_stage_stats *out, int max)
{
    int n = p->num_stages < max ? p->num_stages : max;
    for (int i = 0; i < n; i++)
        stage_stats(&p->stages[i], feeder(p, p->stages[i].name), p->warmup, &out[i]);
    qsort(out, (size_t)n, sizeof *out, cmp_stats);
    return n;
}

void bus_profile_print(const bus_profile *p, FILE *out)
{
    bus_stage_stats st[BUS_PROFILE_MAX_STAGES];
    int n = bus_profile_stats(p, st, BUS_PROFILE_MAX_STAGES);
    fprintf(out, "%-10s %7s %7s %7s %9s %9s %9s %11s %11s %11s\n", "stage", "frames", "dropped",
            "fps", "work p50", "work p95", "work p99", "latency p50", "latency p95", "latency p99");
    for (int i = 0; i < n; i++)
        fprintf(out, "%-10s %7d %7d %7.1f %9.2f %9.2f %9.2f %11.2f %11.2f %11.2f\n", st[i].stage,
                st[i].frames, st[i].dropped, st[i].fps, st[i].work_p50_ms, st[i].work_p95_ms,
                st[i].work_p99_ms, st[i].lat_p50_ms, st[i].lat_p95_ms, st[i].lat_p99_ms);
    if (p->warmup > 0) {
        fprintf(out, "after the first %d frames (warm-up):\n", p->warmup);
        fprintf(out, "%-10s %7s %7s %11s %11s %11s\n", "stage", "frames", "dropped", "latency p50",
                "latency p95", "latency p99");
        for (int i = 0; i < n; i++)
            fprintf(out, "%-10s %7d %7d %11.2f %11.2f %11.2f\n", st[i].stage, st[i].steady_frames,
                    st[i].steady_dropped, st[i].steady_lat_p50_ms, st[i].steady_lat_p95_ms,
                    st[i].steady_lat_p99_ms);
    }
    for (int i = 0; i < n; i++)
        for (int k = 0; k < st[i].num_substages; k++)
            fprintf(out, "  %s/%s p50 %.3f ms\n", st[i].stage, st[i].substage[k],
                    st[i].substage_p50_ms[k]);
    /* End to end: capture to the last stage's output. */
    const bus_stage_stats *last = n ? &st[n - 1] : NULL;
    fprintf(out,
            "{\"stages\": %d, \"last_stage\": \"%s\", \"frames\": %d, \"dropped\": %d, "
            "\"fps\": %.2f, \"latency_p50_ms\": %.3f, \"latency_p95_ms\": %.3f, "
            "\"latency_p99_ms\": %.3f, \"ms_median\": %.3f, \"ms_p95\": %.3f, "
            "\"warmup_frames\": %d, \"steady_dropped\": %d, \"steady_latency_p95_ms\": %.3f}\n",
            n, last ? last->stage : "", last ? last->frames : 0, last ? last->dropped : 0,
            last ? last->fps : 0, last ? last->lat_p50_ms : 0, last ? last->lat_p95_ms : 0,
            last ? last->lat_p99_ms : 0, last ? last->work_p50_ms : 0, last ? last->work_p95_ms : 0,
            p->warmup, last ? last->steady_dropped : 0, last ? last->steady_lat_p95_ms : 0);
}
