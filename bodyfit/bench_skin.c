/* tryon-bench-skin: posing time (linear-blend skinning and the contact pass) at 6K / 10K / 15K
 * vertices on one core. Prints a table, then one JSON line. Usage: tryon-bench-skin [RUNS
 * [MOTION]] */
#include "bodyfit.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tryon_clock.h"
#define BENCH_WARMUP 50

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

typedef struct result {
    int target, verts;
    double median, p95;
} result;

/* Poses a motion (walk by default), a new pose each run, and times fit_model_pose alone. */
static int run_scene(int target, int runs, fit_motion motion, result *r)
{
    char err[256];
    fit_model_desc desc = {.shape = fit_shape_default(), .target_vertices = target};
    fit_model *m = fit_model_create(&desc, err, sizeof err);
    if (!m) {
        fprintf(stderr, "tryon-bench-skin: %s\n", err);
        return 1;
    }
    int nv = fit_model_vertex_count(m);
    float *v = malloc((size_t)nv * 3 * sizeof(float));
    double *ms = malloc((size_t)runs * sizeof(double));
    if (!v || !ms) {
        fprintf(stderr, "tryon-bench-skin: out of memory\n");
        free(v);
        free(ms);
        fit_model_destroy(m);
        return 1;
    }
    fit_pose pose;
    for (int i = 0; i < BENCH_WARMUP + runs; ++i) {
        fit_motion_eval(motion, 0.033 * i, &pose);
        double t0 = tryon_now_ms();
        fit_model_pose(m, &pose, v, NULL);
        double t1 = tryon_now_ms();
        if (i >= BENCH_WARMUP)
            ms[i - BENCH_WARMUP] = t1 - t0;
    }
    qsort(ms, (size_t)runs, sizeof(double), cmp_double);
    r->target = target;
    r->verts = nv;
    r->median = ms[runs / 2];
    r->p95 = ms[(int)(0.95 * (runs - 1))];
    free(v);
    free(ms);
    fit_model_destroy(m);
    return 0;
}

#define USAGE                                                                                      \
    "usage: tryon-bench-skin [RUNS [MOTION]]\n  RUNS    posing runs per body size (default "       \
    "2000, at least 10)\n  MOTION  the poses, a bodyfit motion (default walk)\n"

int main(int argc, char **argv)
{
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        fputs(USAGE, stdout);
        return 0;
    }
    if (argc > 3 || (argc > 1 && argv[1][0] == '-')) {
        fprintf(stderr, "tryon-bench-skin: unknown option %s\n" USAGE, argv[argc > 3 ? 3 : 1]);
        return 2;
    }
    int motion = argc > 2 ? fit_motion_from_name(argv[2]) : FIT_MOTION_WALK;
    if (motion < 0) {
        fprintf(stderr, "tryon-bench-skin: unknown motion %s\n" USAGE, argv[2]);
        return 2;
    }
    int runs = argc > 1 ? atoi(argv[1]) : 2000;
    if (runs < 10) {
        fprintf(stderr, "tryon-bench-skin: RUNS must be at least 10\n");
        return 2;
    }
    const int targets[3] = {6000, 10000, 15000};
    result r[3];
    for (int i = 0; i < 3; ++i)
        if (run_scene(targets[i], runs, (fit_motion)motion, &r[i]))
            return 1;
    printf("posing (linear blend, 4 influences, contact pass; 1 core), %s, %d runs after %d "
           "warm-up\n",
           fit_motion_name((fit_motion)motion), runs, BENCH_WARMUP);
    printf("%8s %8s %10s %10s\n", "target", "verts", "ms_median", "ms_p95");
    for (int i = 0; i < 3; ++i)
        printf("%8d %8d %10.4f %10.4f\n", r[i].target, r[i].verts, r[i].median, r[i].p95);
    printf("{\"bench\":\"skin\",\"ms_median\":%.4f,\"ms_p95\":%.4f,\"verts\":%d,"
           "\"iterations\":%d,\"motion\":\"%s\",\"backend\":\"c\",\"device\":\"cpu-1-core\",\"by_"
           "verts\":["
           "{\"verts\":%d,\"ms_median\":%.4f,\"ms_p95\":%.4f},"
           "{\"verts\":%d,\"ms_median\":%.4f,\"ms_p95\":%.4f},"
           "{\"verts\":%d,\"ms_median\":%.4f,\"ms_p95\":%.4f}]}\n",
           r[1].median, r[1].p95, r[1].verts, runs, fit_motion_name((fit_motion)motion), r[0].verts,
           r[0].median, r[0].p95, r[1].verts, r[1].median, r[1].p95, r[2].verts, r[2].median,
           r[2].p95);
    return 0;
}
