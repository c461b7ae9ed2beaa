/* The shirt on the fitted body against the shirt on the true body (bench_cloth.h). */
#include "bench_cloth.h"

#include "sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

struct bench_cloth {
    sim *on_truth, *on_fit;
    const int32_t *true_tris, *fit_tris;
    int true_nv, true_nt, fit_nv, fit_nt, nv;
    float *a, *b; /* garment positions, [nv][3] */
};

static void reject(char *err, size_t errlen, const char *what, const sim_reject *why)
{
    if (err)
        snprintf(err, errlen, "%s: %s: %s", what, sim_error_name(why->code), why->detail);
}

bench_cloth *bench_cloth_create(int garment_vertices, const float *true_xyz, int true_nv,
                                const int32_t *true_tris, int true_nt, const float *true_joints,
                                const float *fit_xyz, int fit_nv, const int32_t *fit_tris,
                                int fit_nt, char *err, size_t errlen)
{
    bench_cloth *c = calloc(1, sizeof *c);
    sim_garment g = {0};
    sim_reject why = {0};
    sim_desc d = sim_default_desc();
    if (!c)
        goto fail;
    *c = (bench_cloth){.true_tris = true_tris,
                       .fit_tris = fit_tris,
                       .true_nv = true_nv,
                       .true_nt = true_nt,
                       .fit_nv = fit_nv,
                       .fit_nt = fit_nt};
    if (sim_garment_shirt(true_xyz, true_nv, true_tris, true_nt, true_joints, garment_vertices,
                          0.0f, 0.0f, &g, &why) < 0) {
        reject(err, errlen, "shirt on the true body", &why);
        goto fail;
    }
    c->on_truth = sim_create(&d, &g, &why);
    if (!c->on_truth) {
        reject(err, errlen, "sim on the true body", &why);
        goto fail;
    }
    if (sim_garment_rebind(&g, true_xyz, true_nv, true_tris, true_nt, fit_xyz, fit_nv, fit_tris,
                           fit_nt, &why) < 0) {
        reject(err, errlen, "the shirt glued to the fitted body", &why);
        goto fail;
    }
    c->on_fit = sim_create(&d, &g, &why);
    if (!c->on_fit) {
        reject(err, errlen, "sim on the fitted body", &why);
        goto fail;
    }
    c->nv = sim_vertex_count(c->on_truth);
    c->a = malloc((size_t)c->nv * 3 * sizeof(float));
    c->b = malloc((size_t)c->nv * 3 * sizeof(float));
    if (!c->a || !c->b || sim_vertex_count(c->on_fit) != c->nv) {
        if (err)
            snprintf(err, errlen, "out of memory");
        goto fail;
    }
    sim_garment_free(&g);
    return c;
fail:
    sim_garment_free(&g);
    bench_cloth_destroy(c);
    return NULL;
}

double bench_cloth_step(bench_cloth *c, const float *true_xyz, const float *fit_xyz, char *err,
                        size_t errlen)
{
    sim_frame_stats st;
    sim_reject why = {0};
    if (sim_step(c->on_truth, true_xyz, c->true_nv, c->true_tris, c->true_nt, &st, &why) < 0) {
        reject(err, errlen, "the shirt on the true body", &why);
        return -1.0;
    }
    if (sim_step(c->on_fit, fit_xyz, c->fit_nv, c->fit_tris, c->fit_nt, &st, &why) < 0) {
        reject(err, errlen, "the shirt on the fitted body", &why);
        return -1.0;
    }
    sim_copy_positions(c->on_truth, c->a);
    sim_copy_positions(c->on_fit, c->b);
    double sum = 0.0;
    for (int i = 0; i < c->nv * 3; i += 3) {
        double dx = c->a[i] - c->b[i], dy = c->a[i + 1] - c->b[i + 1],
               dz = c->a[i + 2] - c->b[i + 2];
        sum += sqrt(dx * dx + dy * dy + dz * dz);
    }
    return sum / c->nv;
}

void bench_cloth_destroy(bench_cloth *c)
{
    if (!c)
        return;
    sim_destroy(c->on_truth);
    sim_destroy(c->on_fit);
    free(c->a);
    free(c->b);
    free(c);
}
