/* tryon-bench-collide: the collision work of one body frame, seed 000 as published against
 * tryon, on the bodyfit body in scripted motion with a shell of cloth points riding on it (no
 * solver: the points are carried by feature points and pushed out by the response, so the
 * penetration figure measures the collision code alone). A human table, then one JSON line.
 *
 *   seed : LBVH rebuilt every frame, feature points, nearest-triangle search in every iteration
 *   tryon: LBVH refit, feature points, one search per frame, surface walks in the iterations */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "tryon_clock.h"
#include "bodyfit.h"
#include "collide.h"
#include "collide_bvh.h"

#define ITERATIONS    25
#define CONTACT_EVERY 10     /* tryon: iterations between contact refreshes (sim/cloth.h) */
#define SHELL_M       0.008f /* cloth points start 8 mm off the skin */
#define TOPOLOGY_RUNS 9      /* builds of a body topology timed (median) */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double percentile(double *v, int n, double p)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    int i = (int)(p * (n - 1) + 0.5);
    return v[i];
}

/* Cloth points: every step-th body vertex, pushed out along its area-weighted normal. */
static int make_shell(const float *xyz, int nv, const int32_t *tris, int nt, int want,
                      float (*x)[4])
{
    float(*vn)[3] = calloc((size_t)nv, sizeof *vn);
    for (int t = 0; t < nt; t++) {
        const float *a = xyz + 3 * tris[3 * t], *b = xyz + 3 * tris[3 * t + 1],
                    *c = xyz + 3 * tris[3 * t + 2];
        float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                vn[tris[3 * t + k]][j] += n[j];
    }
    int step = nv / want > 0 ? nv / want : 1, n = 0;
    for (int i = 0; i < nv && n < want; i += step, n++) {
        float l = sqrtf(vn[i][0] * vn[i][0] + vn[i][1] * vn[i][1] + vn[i][2] * vn[i][2]);
        for (int k = 0; k < 3; k++)
            x[n][k] = xyz[3 * i + k] + SHELL_M * vn[i][k] / (l > 0.0f ? l : 1.0f);
        x[n][3] = 1.0f;
    }
    free(vn);
    return n;
}

typedef struct run {
    double *ms;                                       /* per frame */
    double build, fp, search, track, resolve, metric; /* medians, ms */
    int worst_pen, moved;
    float worst_depth_mm;
} run;

/* One motion, one variant: F frames after the first. */
static int run_variant(int seed, fit_model *m, fit_motion motion, int frames, int npts, run *r)
{
    int nv = fit_model_vertex_count(m), nt = fit_model_triangle_count(m);
    const int32_t *tris = fit_model_triangles(m);
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    float(*x)[4] = malloc((size_t)npts * sizeof *x), (*xp)[4] = malloc((size_t)npts * sizeof *xp);
    double *t[6];
    for (int k = 0; k < 6; k++)
        t[k] = calloc((size_t)frames, sizeof(double));
    char err[160];
    sim_collider *c = sim_collider_create(&(sim_collider_desc){.max_vertices = nv,
                                                               .max_triangles = nt,
                                                               .friction = 0.3f,
                                                               .reach_m = 0.02f,
                                                               .max_cloth = npts},
                                          err, sizeof err);
    if (!c || !xyz || !x || !xp) {
        fprintf(stderr, "bench: %s\n", c ? "out of memory" : err);
        return -1;
    }
    fit_pose pose;
    fit_motion_eval(motion, 0.0, &pose);
    fit_model_pose(m, &pose, xyz, NULL);
    sim_collider_set_body(c, xyz, nv, tris, nt);
    npts = make_shell(xyz, nv, tris, nt, npts, x);
    memcpy(xp, x, (size_t)npts * sizeof *x);
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, npts);
    r->worst_pen = 0, r->worst_depth_mm = 0.0f, r->moved = 0;
    for (int f = 0; f < frames; f++) {
        fit_motion_eval(motion, (f + 1) / 30.0, &pose);
        fit_model_pose(m, &pose, xyz, NULL);
        double t0 = tryon_now_ms();
        sim_collider_set_body(c, xyz, nv, tris, nt);
        if (seed) /* seed 000: both BVHs built from scratch every frame */
            sim_bvh_build_lbvh(&c->bvh, (const float(*)[4])c->v_prev, (const float(*)[4])c->v,
                               (const int32_t(*)[4])c->tris, nt, c->d.thickness_m);
        double t1 = tryon_now_ms();
        r->moved += sim_collider_feature_points(c, x, xp, 0, npts);
        double t2 = tryon_now_ms(), search = 0.0, track = 0.0, resolve = 0.0;
        for (int it = 0; it < ITERATIONS; it++) {
            double a = tryon_now_ms();
            if (seed || it == 0)
                sim_collider_find_contacts(c, (const float(*)[4])x, 0, npts);
            else if (it % CONTACT_EVERY == 0)
                sim_collider_track_contacts(c, (const float(*)[4])x, 0, npts);
            double b = tryon_now_ms();
            sim_collider_resolve(c, x, xp, 0, npts);
            double e = tryon_now_ms();
            if (seed || it == 0)
                search += b - a;
            else
                track += b - a;
            resolve += e - b;
        }
        double t3 = tryon_now_ms();
        int pen;
        float depth;
        sim_collider_penetration(c, (const float(*)[4])x, npts, 0.001f, &pen, &depth);
        double t4 = tryon_now_ms();
        memcpy(xp, x, (size_t)npts * sizeof *x); /* the points are at rest between frames */
        if (pen > r->worst_pen)
            r->worst_pen = pen;
        if (depth * 1000.0f > r->worst_depth_mm)
            r->worst_depth_mm = depth * 1000.0f;
        t[0][f] = t1 - t0, t[1][f] = t2 - t1, t[2][f] = search, t[3][f] = track;
        t[4][f] = resolve, t[5][f] = t4 - t3;
        r->ms[f] = t4 - t0;
        (void)t3;
    }
    r->build = percentile(t[0], frames, 0.5), r->fp = percentile(t[1], frames, 0.5);
    r->search = percentile(t[2], frames, 0.5), r->track = percentile(t[3], frames, 0.5);
    r->resolve = percentile(t[4], frames, 0.5), r->metric = percentile(t[5], frames, 0.5);
    for (int k = 0; k < 6; k++)
        free(t[k]);
    sim_collider_destroy(c);
    free(xyz);
    free(x);
    free(xp);
    return 0;
}

/* A body topology's build (its first frame in the collider: validation, adjacency, the SAH tree;
 * the first frame of tryon-sim's garment, docs/collision.md), median ms of TOPOLOGY_RUNS: each
 * run the body's triangles with their corners turned, a new topology for the collider. */
static double topology_ms(const fit_model *m)
{
    int nv = fit_model_vertex_count(m), nt = fit_model_triangle_count(m);
    const int32_t *tris = fit_model_triangles(m);
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    int32_t *turned = malloc((size_t)nt * 3 * sizeof *turned);
    char err[160];
    sim_collider *c = sim_collider_create(
        &(sim_collider_desc){.max_vertices = nv, .max_triangles = nt}, err, sizeof err);
    double ms[TOPOLOGY_RUNS], median = -1.0;
    if (c && xyz && turned) {
        fit_pose pose;
        fit_motion_eval(FIT_MOTION_STILL, 0.0, &pose);
        fit_model_pose(m, &pose, xyz, NULL);
        for (int t = 0; t < nt; t++)
            for (int k = 0; k < 3; k++)
                turned[3 * t + k] = tris[3 * t + (k + 1) % 3];
        for (int r = 0; r < TOPOLOGY_RUNS; r++) {
            double t0 = tryon_now_ms();
            sim_collider_set_body(c, xyz, nv, r % 2 ? turned : tris, nt);
            ms[r] = tryon_now_ms() - t0;
        }
        median = percentile(ms, TOPOLOGY_RUNS, 0.5);
    }
    sim_collider_destroy(c);
    free(xyz);
    free(turned);
    return median;
}

int main(int argc, char **argv)
{
    int frames = 60, npts = 7000;
    const char *motion_name = "fast_swing";
    static const char usage[] =
        "usage: tryon-bench-collide [--frames F] [--points N] [--motion M]\n";
    for (int i = 1; i < argc; i += 2) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (i + 1 < argc && !strcmp(argv[i], "--frames")) {
            frames = atoi(argv[i + 1]);
        } else if (i + 1 < argc && !strcmp(argv[i], "--points")) {
            npts = atoi(argv[i + 1]);
        } else if (i + 1 < argc && !strcmp(argv[i], "--motion")) {
            motion_name = argv[i + 1];
        } else {
            fprintf(stderr, "tryon-bench-collide: unknown option %s\n%s", argv[i], usage);
            return 2;
        }
    }
    int motion = fit_motion_from_name(motion_name);
    if (frames < 1 || npts < 1 || motion < 0) {
        fprintf(stderr, "tryon-bench-collide: bad --frames, --points or --motion \"%s\"\n",
                motion_name);
        return 2;
    }
    char err[160];
    fit_model *m =
        fit_model_create(&(fit_model_desc){.shape = fit_shape_default()}, err, sizeof err);
    if (!m) {
        fprintf(stderr, "tryon-bench-collide: body model: %s\n", err);
        return 1;
    }
    run r[2];
    const char *names[2] = {"seed", "tryon"};
    printf("body %d vertices %d triangles, %d cloth points, %d iterations, motion %s, %d frames\n",
           fit_model_vertex_count(m), fit_model_triangle_count(m), npts, ITERATIONS, motion_name,
           frames);
    printf("%-6s %8s %8s %8s %8s %8s %8s %8s %8s %6s %7s\n", "", "ms_med", "ms_p95", "bvh", "fp",
           "search", "walk", "resolve", "metric", "pen", "pen_mm");
    for (int v = 0; v < 2; v++) {
        r[v].ms = calloc((size_t)frames, sizeof(double));
        if (run_variant(v == 0, m, (fit_motion)motion, frames, npts, &r[v]) != 0)
            return 1;
        double *ms = r[v].ms;
        double med = percentile(ms, frames, 0.5), p95 = percentile(ms, frames, 0.95);
        printf("%-6s %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %6d %7.2f\n", names[v], med,
               p95, r[v].build, r[v].fp, r[v].search, r[v].track, r[v].resolve, r[v].metric,
               r[v].worst_pen, (double)r[v].worst_depth_mm);
        r[v].ms[0] = med, r[v].ms[1] = p95;
    }
    double topo_ms = topology_ms(m);
    printf("a body topology's build (its first frame): %.2f ms (median of %d)\n", topo_ms,
           TOPOLOGY_RUNS);
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    printf("{\"bench\":\"collide\",\"motion\":\"%s\",\"backend\":\"c\",\"device\":\"C reference "
           "(%d threads)\",\"verts\":%d,\"iterations\":%d,\"frames\":%d,\"ms_median\":%.3f,"
           "\"ms_p95\":%.3f,\"seed_ms_median\":%.3f,\"seed_ms_p95\":%.3f,\"penetrating\":%d,"
           "\"max_pen_mm\":%.2f,\"seed_penetrating\":%d,\"topology_ms\":%.3f}\n",
           motion_name, threads, npts, ITERATIONS, frames, r[1].ms[0], r[1].ms[1], r[0].ms[0],
           r[0].ms[1], r[1].worst_pen, (double)r[1].worst_depth_mm, r[0].worst_pen, topo_ms);
    free(r[0].ms);
    free(r[1].ms);
    fit_model_destroy(m);
    return 0;
}
