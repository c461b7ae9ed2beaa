/* tryon-bench-sim's sewing-pattern garments (bench_pattern.h): dressed once by the sim's own
 * pattern dressing (sim/outfit_pattern.c) on the scene's body model, copied into every run, and
 * the check that the limb panels stay on their limbs. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_pattern.h"
#include "bodyfit.h"
#include "cloth.h"
#include "garments.h"
#include "outfit_pattern.h"

/* The limbs, as the garment's parts name them (gar_part) and as the body's skinning does. */
enum { LIMB_ARM_L, LIMB_ARM_R, LIMB_LEG_L, LIMB_LEG_R, LIMB_COUNT };

struct bench_pattern {
    sim_garment garment;
    int8_t *limb_of_vertex; /* garment vertex -> limb, -1 torso */
    int8_t *limb_of_body;   /* body vertex -> limb, -1 elsewhere */
    int body_nv;
    float *rest_xyz;                 /* the body model at rest, where the garment is dressed */
    int32_t *limb_verts[LIMB_COUNT]; /* each limb's body vertices */
    int limb_nv[LIMB_COUNT];
    bench_pattern_info info;
};

static int limb_of_part(int part)
{
    switch (part) {
    case GAR_PART_ARM_L:
        return LIMB_ARM_L;
    case GAR_PART_ARM_R:
        return LIMB_ARM_R;
    case GAR_PART_LEG_L:
        return LIMB_LEG_L;
    case GAR_PART_LEG_R:
        return LIMB_LEG_R;
    default:
        return -1;
    }
}

static int limb_of_joint(int j)
{
    if (j >= FIT_L_SHOULDER && j <= FIT_L_WRIST)
        return LIMB_ARM_L;
    if (j >= FIT_R_SHOULDER && j <= FIT_R_WRIST)
        return LIMB_ARM_R;
    if (j >= FIT_L_HIP && j <= FIT_L_TOE)
        return LIMB_LEG_L;
    if (j >= FIT_R_HIP && j <= FIT_R_TOE)
        return LIMB_LEG_R;
    return -1;
}

/* Each body vertex's limb: that of its strongest skinning joint. */
static int8_t *body_limbs(const fit_model *m)
{
    int nv = fit_model_vertex_count(m);
    const uint8_t *wj = fit_model_weight_joints(m);
    const float *w = fit_model_weights(m);
    int8_t *limb = malloc((size_t)nv);
    for (int v = 0; limb && v < nv; v++) {
        int best = 0;
        for (int k = 1; k < FIT_MAX_INFLUENCES; k++)
            if (w[v * FIT_MAX_INFLUENCES + k] > w[v * FIT_MAX_INFLUENCES + best])
                best = k;
        limb[v] = (int8_t)limb_of_joint(wj[v * FIT_MAX_INFLUENCES + best]);
    }
    return limb;
}

/* Each limb's body vertices listed (the limb check scans only its own limb's). 0 or -1. */
static int index_limbs(bench_pattern *bp)
{
    for (int l = 0; l < LIMB_COUNT; l++) {
        bp->limb_verts[l] = malloc((size_t)bp->body_nv * sizeof *bp->limb_verts[l]);
        if (!bp->limb_verts[l])
            return -1;
        for (int v = 0; v < bp->body_nv; v++)
            if (bp->limb_of_body[v] == l)
                bp->limb_verts[l][bp->limb_nv[l]++] = v;
    }
    return 0;
}

int bench_pattern_fabric(const bench_pattern_desc *d, sim_fabric *out, char *err, size_t err_size)
{
    sim_outfit o;
    sim_reject why = {0};
    int r = sim_outfit_resolve(d->path, (int)d->size, d->fabric ? d->fabric : "", &o, &why);
    if (r < 0 || !o.is_pattern) {
        snprintf(err, err_size, "--garment %s: %s", d->path,
                 r < 0 ? why.detail : "not a sewing pattern (.json)");
        return -1;
    }
    *out = o.fabric;
    return 0;
}

bench_pattern *bench_pattern_create(const bench_pattern_desc *d, sim_scene *sc, char *err,
                                    size_t err_size)
{
    sim_outfit o;
    sim_reject why = {0};
    if (sim_outfit_resolve(d->path, (int)d->size, d->fabric ? d->fabric : "", &o, &why) < 0) {
        snprintf(err, err_size, "--garment %s: %s", d->path, why.detail);
        return NULL;
    }
    const float *xyz;
    const int32_t *tris;
    int nv, nt;
    fit_model *m = fit_model_create(
        &(fit_model_desc){.shape = fit_shape_default(), .target_vertices = d->body_verts}, err,
        err_size);
    bench_pattern *bp = calloc(1, sizeof *bp);
    if (!m || !bp || sim_scene_eval(sc, 0.0, &xyz, &nv, &tris, &nt, NULL) < 0 ||
        nv != fit_model_vertex_count(m)) {
        if (m && bp)
            snprintf(err, err_size, "the scene's body is not the body model of %d vertices",
                     d->body_verts);
        fit_model_destroy(m);
        free(bp);
        return NULL;
    }
    sim_pattern_stats ps = {0};
    int8_t *part = NULL;
    bp->rest_xyz = malloc((size_t)nv * 3 * sizeof *bp->rest_xyz);
    int r = bp->rest_xyz ? 0 : sim_reject_set(&why, SIM_ERR_NO_MEMORY, "body of %d vertices", nv);
    if (r == 0) {
        memcpy(bp->rest_xyz, fit_model_rest_vertices(m), (size_t)nv * 3 * sizeof *bp->rest_xyz);
        r = sim_pattern_dress_on(&o, m, bp->rest_xyz, d->target_vertices, &bp->garment, &part, &ps,
                                 &why);
    }
    bp->body_nv = nv;
    bp->limb_of_body = r == 0 ? body_limbs(m) : NULL;
    bp->limb_of_vertex = part;
    fit_model_destroy(m);
    if (r < 0 || !bp->limb_of_body) {
        snprintf(err, err_size, "%s: %s", sim_error_name(why.code), why.detail);
        bench_pattern_destroy(bp);
        return NULL;
    }
    if (index_limbs(bp) < 0) {
        snprintf(err, err_size, "out of memory");
        bench_pattern_destroy(bp);
        return NULL;
    }
    bench_pattern_info *in = &bp->info;
    *in = (bench_pattern_info){.dress_ms = ps.dress_ms,
                               .total_ms = ps.total_ms,
                               .spacing_m = ps.spacing_m,
                               .seam_gap_mm = ps.seam_gap_mm,
                               .max_strain = ps.max_strain,
                               .p99_strain = ps.p99_strain,
                               .penetrating = ps.penetrating,
                               .vertices = bp->garment.num_vertices};
    for (int i = 0; i < bp->garment.num_vertices; i++) {
        part[i] = (int8_t)limb_of_part(part[i]);
        in->arm_vertices += part[i] == LIMB_ARM_L || part[i] == LIMB_ARM_R;
        in->leg_vertices += part[i] == LIMB_LEG_L || part[i] == LIMB_LEG_R;
    }
    return bp;
}

void bench_pattern_destroy(bench_pattern *bp)
{
    if (!bp)
        return;
    sim_garment_free(&bp->garment);
    free(bp->limb_of_vertex);
    free(bp->limb_of_body);
    free(bp->rest_xyz);
    for (int l = 0; l < LIMB_COUNT; l++)
        free(bp->limb_verts[l]);
    free(bp);
}

int bench_pattern_garment(const bench_pattern *bp, sim_garment *out)
{
    const sim_garment *g = &bp->garment;
    *out = *g;
    out->xyz = malloc((size_t)g->num_vertices * 3 * sizeof *out->xyz);
    out->triangles = malloc((size_t)g->num_triangles * 3 * sizeof *out->triangles);
    out->attachments = malloc((size_t)(g->num_attachments + 1) * sizeof *out->attachments);
    out->mass_kg = NULL; /* lumped from the fabric, as the original */
    if (!out->xyz || !out->triangles || !out->attachments) {
        sim_garment_free(out);
        return -1;
    }
    memcpy(out->xyz, g->xyz, (size_t)g->num_vertices * 3 * sizeof *out->xyz);
    memcpy(out->triangles, g->triangles, (size_t)g->num_triangles * 3 * sizeof *out->triangles);
    memcpy(out->attachments, g->attachments, (size_t)g->num_attachments * sizeof *g->attachments);
    return 0;
}

void bench_pattern_get_info(const bench_pattern *bp, bench_pattern_info *out)
{
    *out = bp->info;
}

/* Whether cloth point p is within BENCH_LIMB_NEAR_M of a body vertex of limb. */
static int near_limb(const bench_pattern *bp, const float *p, const float *body_xyz, int limb)
{
    const float r2 = BENCH_LIMB_NEAR_M * BENCH_LIMB_NEAR_M;
    for (int k = 0; k < bp->limb_nv[limb]; k++) {
        int v = bp->limb_verts[limb][k];
        float dx = p[0] - body_xyz[v * 3], dy = p[1] - body_xyz[v * 3 + 1],
              dz = p[2] - body_xyz[v * 3 + 2];
        if (dx * dx + dy * dy + dz * dz <= r2)
            return 1;
    }
    return 0;
}

void bench_pattern_limbs(const bench_pattern *bp, const float *x, const float *body_xyz,
                         int body_nv, float *arm_frac, float *leg_frac)
{
    int near[2] = {0, 0}, total[2] = {0, 0};
    int n = body_nv == bp->body_nv ? bp->garment.num_vertices : 0;
#pragma omp parallel for schedule(static) reduction(+ : near[:2], total[:2])
    for (int i = 0; i < n; i++) {
        int limb = bp->limb_of_vertex[i];
        if (limb < 0)
            continue;
        int kind = limb >= LIMB_LEG_L; /* 0 arms, 1 legs */
        total[kind]++;
        near[kind] += near_limb(bp, x + (size_t)i * 3, body_xyz, limb);
    }
    *arm_frac = total[0] ? (float)near[0] / (float)total[0] : -1.0f;
    *leg_frac = total[1] ? (float)near[1] / (float)total[1] : -1.0f;
}

int bench_pattern_turn_in(const bench_pattern *bp, sim *s, const float *xyz0, int nv,
                          const int32_t *tris, int nt, sim_reject *why)
{
    if (nv != bp->body_nv)
        return sim_reject_set(why, SIM_ERR_PARAM, "turn-in: a body of %d vertices, not %d", nv,
                              bp->body_nv);
    float *b = malloc((size_t)nv * 3 * sizeof *b);
    if (!b)
        return sim_reject_set(why, SIM_ERR_NO_MEMORY, "turn-in: body of %d vertices", nv);
    int r = 0;
    for (int k = 1; k <= BENCH_PATTERN_TURN_IN_FRAMES && r == 0; k++) {
        float u = (float)k / BENCH_PATTERN_TURN_IN_FRAMES, w = u * u * (3.0f - 2.0f * u);
        for (int i = 0; i < nv * 3; i++)
            b[i] = (1.0f - w) * bp->rest_xyz[i] + w * xyz0[i];
        sim_frame_stats st;
        r = sim_step(s, b, nv, tris, nt, &st, why);
    }
    free(b);
    return r < 0 ? r : sim_pattern_settle(s, xyz0, nv, tris, nt, why);
}
