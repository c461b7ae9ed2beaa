/* tryon-bench-bullet: Bullet's soft-body cloth on the drape scene of tryon-bench-sim (1 m x 1 m,
 * N vertices, 200 g/m^2, flat 0.3 m above the top of a fixed 0.25 m sphere at the origin, 3 s at
 * 30 frames/s, K solver iterations per frame), timed and measured the way tryon-bench-sim measures
 * its own solvers, so the two JSON lines compare directly. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tryon_clock.h"
#include "bullet_drape.h"

#define BB_SETTLE_FRAMES 30 /* strain is judged after the first second, as tryon-bench-sim */
#define BB_WARM_FRAMES   5  /* the first frames fault pages in */
#define BB_PEN_TOL_M     0.001f

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The p-quantile of v[0..n) (sorts v). */
static float quantile(float *v, int n, float p)
{
    if (n <= 0)
        return 0.0f;
    qsort(v, (size_t)n, sizeof *v, cmp_float);
    return v[(int)floorf(p * (float)(n - 1) + 0.5f)];
}

static int parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (!*s || *end || v < lo || v > hi)
        return -1;
    *out = (int)v;
    return 0;
}

int main(int argc, char **argv)
{
    int verts = 7056, iterations = 25, frames = 90, substeps = 1, margin_mm = 4;
    for (int i = 1; i < argc; i++) {
        const char *v = i + 1 < argc ? argv[i + 1] : "";
        int bad = 0;
        if (!strcmp(argv[i], "--verts"))
            bad = parse_int(v, 4, 1000000, &verts);
        else if (!strcmp(argv[i], "--iterations"))
            bad = parse_int(v, 1, 10000, &iterations);
        else if (!strcmp(argv[i], "--frames"))
            bad = parse_int(v, 1, 100000, &frames);
        else if (!strcmp(argv[i], "--substeps"))
            bad = parse_int(v, 1, 1000, &substeps);
        else if (!strcmp(argv[i], "--margin-mm"))
            bad = parse_int(v, 1, 1000, &margin_mm);
        else if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            printf("usage: tryon-bench-bullet [--verts N] [--iterations K] [--frames F] "
                   "[--substeps S] [--margin-mm M]\n");
            return 0;
        } else {
            fprintf(stderr, "tryon-bench-bullet: unknown option %s\n", argv[i]);
            bad = -1;
        }
        if (bad) {
            fprintf(stderr, "usage: tryon-bench-bullet [--verts N] [--iterations K] [--frames F] "
                            "[--substeps S] [--margin-mm M]\n");
            return 2;
        }
        i++;
    }
    int side = (int)lroundf(sqrtf((float)verts));
    bullet_drape_desc d = {.side = side,
                           .side_m = 1.0f,
                           .height_m = 0.55f,
                           .sphere_r_m = 0.25f,
                           .mass_kg = 0.2f,
                           .iterations = iterations,
                           .friction = 0.3f,
                           .margin_m = 0.001f * (float)margin_mm};
    char err[160];
    bullet_drape *b = bullet_drape_create(&d, err, sizeof err);
    if (!b) {
        fprintf(stderr, "tryon-bench-bullet: %s\n", err);
        return 1;
    }
    int nv = bullet_drape_node_count(b), ns = bullet_drape_structural_count(b);
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    int32_t *ends = malloc((size_t)ns * 2 * sizeof *ends);
    float *rest = malloc((size_t)ns * sizeof *rest), *strain = malloc((size_t)ns * sizeof *strain);
    float *ms = malloc((size_t)frames * sizeof *ms);
    if (!xyz || !ends || !rest || !strain || !ms) {
        fprintf(stderr, "tryon-bench-bullet: out of memory\n");
        return 1;
    }
    bullet_drape_structural(b, ends, rest);
    float max_strain = 0, p99_strain = 0, max_pen_mm = 0;
    int penetrating = 0, not_finite = 0;
    printf("%-6s %8s %8s %6s %6s\n", "frame", "ms", "strain%", "p99%", "pen");
    for (int f = 0; f < frames; f++) {
        double t0 = tryon_now_ms();
        for (int k = 0; k < substeps; k++)
            bullet_drape_step(b, 1.0f / 30.0f / (float)substeps);
        ms[f] = (float)(tryon_now_ms() - t0);
        bullet_drape_positions(b, xyz);
        int pen = 0;
        for (int i = 0; i < nv; i++) {
            const float *p = xyz + 3 * i;
            float depth = d.sphere_r_m - sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            not_finite += !(isfinite(p[0]) && isfinite(p[1]) && isfinite(p[2]));
            if (depth > BB_PEN_TOL_M) {
                pen++;
                max_pen_mm = fmaxf(max_pen_mm, depth * 1000.0f);
            }
        }
        penetrating = pen > penetrating ? pen : penetrating;
        for (int s = 0; s < ns; s++) {
            const float *p = xyz + 3 * ends[2 * s], *q = xyz + 3 * ends[2 * s + 1];
            float dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
            strain[s] = fmaxf(0.0f, (sqrtf(dx * dx + dy * dy + dz * dz) - rest[s]) / rest[s]);
        }
        float fmax = quantile(strain, ns, 1.0f), fp99 = quantile(strain, ns, 0.99f);
        if (f >= BB_SETTLE_FRAMES || frames <= BB_SETTLE_FRAMES) {
            max_strain = fmaxf(max_strain, fmax);
            p99_strain = fmaxf(p99_strain, fp99);
        }
        if (f % 10 == 9 || f == frames - 1)
            printf("%-6d %8.2f %8.2f %6.2f %6d\n", f, ms[f], 100.0f * fmax, 100.0f * fp99, pen);
    }
    int warm = frames > 2 * BB_WARM_FRAMES ? BB_WARM_FRAMES : 0;
    float ms_p95 = quantile(ms + warm, frames - warm, 0.95f);
    float ms_median = quantile(ms + warm, frames - warm, 0.5f);
    /* cloth_error_mm is null: the converged reference of tryon-bench-sim is a solution of
     * tryon's fabric model, not of Bullet's, and a falling sheet's folds are chaotic */
    printf("{\"scene\":\"drape\",\"solver\":\"bullet\",\"backend\":\"bullet\",\"device\":\"%s "
           "btSoftBody (1 thread)\",\"verts\":%d,\"iterations\":%d,\"frames\":%d,"
           "\"ms_median\":%.3f,\"ms_p95\":%.3f,\"max_strain\":%.5f,\"p99_strain\":%.5f,"
           "\"penetrating\":%d,\"max_pen_mm\":%.2f,\"cloth_error_mm\":null,"
           "\"not_finite\":%d,\"substeps\":%d,\"margin_mm\":%d}\n",
           bullet_drape_version(), nv, iterations, frames, ms_median, ms_p95, max_strain,
           p99_strain, penetrating, max_pen_mm, not_finite, substeps, margin_mm);
    free(xyz);
    free(ends);
    free(rest);
    free(strain);
    free(ms);
    bullet_drape_destroy(b);
    return 0;
}
