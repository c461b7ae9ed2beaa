/* fit_model: builds the calibrated rest mesh and its skinning weights from a shape. */
#include "body_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Girths are corrected until every one is this close to the asked value (the contract is 1 cm;
 * the slack covers the chord error of a differently sized mesh). */
#define BODY_GIRTH_TOLERANCE  0.004f
#define BODY_CALIB_ITERATIONS 5
/* Calibration iterates on a mesh this coarse (girths barely depend on resolution), then the
 * wanted mesh is built once and corrected again only if it still misses. */
#define BODY_CALIB_VERTICES 3000
/* Vertices per square metre of surface per 1/h^2 for the Kuhn marching tetrahedra lattice:
 * the mean over orientations of sum_d |n . d| over its 7 edge directions. */
#define BODY_MT_DENSITY 4.49f
/* Marching tetrahedra produce this many times the wanted vertices; collapses bring it down. */
#define BODY_OVERSAMPLE 2.2f

/* Marching tetrahedra at a spacing giving about 2x the target, retried on a shifted grid if a
 * thin gap sampled badly (the body must be one sphere-like surface), then decimated and
 * smoothed when finish is set (calibration measures the raw, projected mesh). */
static int build_mesh(const body_field *f, float scale, int target, int finish, body_mesh *m)
{
    float area = 1.9f * scale * scale;
    float h = sqrtf(BODY_MT_DENSITY * area / (BODY_OVERSAMPLE * (float)target));
    /* A cylinder of radius r always holds grid points when r exceeds ~0.87 h; and the thighs'
     * 4.4 cm gap (skeleton.c) stays open when no grid edge (up to sqrt(3) h) spans it. */
    h = fminf(h, fminf(1.1f * f->min_radius, BODY_THIGH_GAP * scale * 0.577f));
    int rc = -FIT_ERR_MESH;
    for (int attempt = 0; attempt < 8; ++attempt) {
        if (attempt >= 2)
            h *= 0.9f; /* shifting alone did not help: sample finer */
        float off[3] = {fmodf(0.37f * (float)attempt, 1.0f) * h,
                        fmodf(0.23f * (float)attempt, 1.0f) * h,
                        fmodf(0.31f * (float)attempt, 1.0f) * h};
        rc = body_polygonise(f, h, off, m);
        if (rc)
            return rc;
        int euler = 0, comps = 0;
        rc = body_mesh_topology(m, &euler, &comps);
        if (!rc && euler == 2 && comps == 1 && m->nv >= target)
            break;
        if (!rc && m->nv < target)
            h *= 0.85f;
        body_mesh_free(m);
        rc = -FIT_ERR_MESH;
    }
    if (rc || !finish)
        return rc;
    rc = body_mesh_decimate(f, m, target);
    if (!rc)
        body_mesh_smooth(f, m, 2);
    return rc;
}

static float girth_error(const fit_shape *want, const fit_shape *got)
{
    float e = fabsf(want->chest_girth - got->chest_girth);
    e = fmaxf(e, fabsf(want->waist_girth - got->waist_girth));
    e = fmaxf(e, fabsf(want->hip_girth - got->hip_girth));
    e = fmaxf(e, fabsf(want->arm_girth - got->arm_girth));
    return fmaxf(e, fabsf(want->leg_girth - got->leg_girth));
}

/* One girth's fixed-point step: a secant step once two measurements exist (the hip also grows
 * with the thighs, so its slope is well under proportional), else a proportional one. */
static float calib_step(float c, float want, float got, float *prev_c, float *prev_got)
{
    float next = c * want / got;
    if (*prev_c > 0.0f && fabsf(c - *prev_c) > 1e-4f) {
        float slope = (got - *prev_got) / (c - *prev_c);
        float lo = 0.2f * got / c; /* at least a fifth of proportional */
        if (slope > lo)
            next = c + (want - got) / slope;
    }
    *prev_c = c;
    *prev_got = got;
    return next;
}

typedef struct calib_state {
    body_calib c, prev_c, prev_got;
} calib_state;

static void calib_update(calib_state *s, const fit_shape *want, const fit_shape *got)
{
    s->c.chest = calib_step(s->c.chest, want->chest_girth, got->chest_girth, &s->prev_c.chest,
                            &s->prev_got.chest);
    s->c.waist = calib_step(s->c.waist, want->waist_girth, got->waist_girth, &s->prev_c.waist,
                            &s->prev_got.waist);
    s->c.hip =
        calib_step(s->c.hip, want->hip_girth, got->hip_girth, &s->prev_c.hip, &s->prev_got.hip);
    s->c.arm =
        calib_step(s->c.arm, want->arm_girth, got->arm_girth, &s->prev_c.arm, &s->prev_got.arm);
    s->c.leg =
        calib_step(s->c.leg, want->leg_girth, got->leg_girth, &s->prev_c.leg, &s->prev_got.leg);
}

static int build_and_measure(fit_model *m, const body_calib *c, int target, int finish)
{
    body_mesh_free(&m->mesh);
    body_field_build(&m->sk, &m->shape, c, &m->field);
    int rc = build_mesh(&m->field, m->sk.scale, target, finish, &m->mesh);
    if (!rc)
        rc = body_measure(m->mesh.v, m->mesh.nv, m->mesh.t, m->mesh.nt, &m->sk, &m->meas);
    return rc;
}

static int calibrate(fit_model *m, int target)
{
    /* Start from the corrections the presets converge to (the smooth union and the tapers
     * move every girth the same way), so one coarse round usually suffices. */
    calib_state st = {{1.0f, 1.0f, 0.985f, 1.055f, 1.068f}, {0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}};
    int coarse = target < BODY_CALIB_VERTICES ? target : BODY_CALIB_VERTICES;
    for (int it = 0; it < BODY_CALIB_ITERATIONS; ++it) {
        int rc = build_and_measure(m, &st.c, coarse, 0);
        if (rc)
            return rc;
        if (girth_error(&m->shape, &m->meas.shape) < 0.5f * BODY_GIRTH_TOLERANCE)
            break;
        calib_update(&st, &m->shape, &m->meas.shape);
    }
    for (int it = 0; it < 2; ++it) {
        int rc = build_and_measure(m, &st.c, target, 1);
        if (rc || girth_error(&m->shape, &m->meas.shape) < BODY_GIRTH_TOLERANCE)
            return rc;
        calib_update(&st, &m->shape, &m->meas.shape);
    }
    return 0;
}

/* Keeps the FIT_MAX_INFLUENCES largest joint weights of each vertex, renormalised. */
static int build_weights(fit_model *m)
{
    int nv = m->mesh.nv;
    m->wjoint = malloc((size_t)nv * FIT_MAX_INFLUENCES);
    m->weight = malloc((size_t)nv * FIT_MAX_INFLUENCES * sizeof(float));
    if (!m->wjoint || !m->weight)
        return -FIT_ERR_NOMEM;
    for (int i = 0; i < nv; ++i) {
        float w[FIT_JOINT_COUNT], sum = 0.0f;
        body_field_joint_weights(&m->field, m->mesh.v + (size_t)i * 3, w);
        uint8_t *jj = m->wjoint + (size_t)i * FIT_MAX_INFLUENCES;
        float *ww = m->weight + (size_t)i * FIT_MAX_INFLUENCES;
        for (int k = 0; k < FIT_MAX_INFLUENCES; ++k) {
            int best = 0;
            for (int j = 1; j < FIT_JOINT_COUNT; ++j)
                if (w[j] > w[best])
                    best = j;
            /* Influences under 1 % are dropped: they only cost time. */
            jj[k] = (uint8_t)best;
            ww[k] = (k == 0 || w[best] >= 0.01f) ? w[best] : 0.0f;
            if (ww[k] == 0.0f)
                jj[k] = jj[0];
            w[best] = -1.0f;
            sum += ww[k];
        }
        for (int k = 0; k < FIT_MAX_INFLUENCES; ++k)
            ww[k] /= sum;
    }
    return 0;
}

fit_model *fit_model_create(const fit_model_desc *desc, char *err, size_t errlen)
{
    if (err && errlen)
        err[0] = '\0';
    if (!desc) {
        if (err)
            snprintf(err, errlen, "fit_model_create: no description given");
        return NULL;
    }
    int target = desc->target_vertices ? desc->target_vertices : 10000;
    if (target < 1000 || target > 60000) {
        if (err)
            snprintf(err, errlen,
                     "fit_model_create: target_vertices %d is outside 1000..60000 (0 = 10000)",
                     desc->target_vertices);
        return NULL;
    }
    fit_model *m = calloc(1, sizeof(*m));
    if (!m) {
        if (err)
            snprintf(err, errlen, "fit_model_create: out of memory");
        return NULL;
    }
    m->shape = desc->shape;
    int rc = body_skeleton_build(&m->shape, &m->sk, err, errlen);
    if (!rc)
        rc = calibrate(m, target);
    if (!rc)
        rc = build_weights(m);
    if (rc) {
        if (err && !err[0])
            snprintf(err, errlen, "fit_model_create: %s (target %d vertices)", fit_error_string(rc),
                     target);
        fit_model_destroy(m);
        return NULL;
    }
    return m;
}

void fit_model_destroy(fit_model *m)
{
    if (!m)
        return;
    body_mesh_free(&m->mesh);
    free(m->wjoint);
    free(m->weight);
    free(m);
}

int fit_model_vertex_count(const fit_model *m)
{
    return m ? m->mesh.nv : 0;
}

int fit_model_triangle_count(const fit_model *m)
{
    return m ? m->mesh.nt : 0;
}

const int32_t *fit_model_triangles(const fit_model *m)
{
    return m ? m->mesh.t : NULL;
}

const float *fit_model_rest_vertices(const fit_model *m)
{
    return m ? m->mesh.v : NULL;
}

const fit_shape *fit_model_shape(const fit_model *m)
{
    return m ? &m->shape : NULL;
}

const uint8_t *fit_model_weight_joints(const fit_model *m)
{
    return m ? m->wjoint : NULL;
}

const float *fit_model_weights(const fit_model *m)
{
    return m ? m->weight : NULL;
}

const float *fit_model_rest_joints(const fit_model *m)
{
    return m ? &m->sk.joint[0][0] : NULL;
}

int fit_model_measure(const fit_model *m, fit_measurements *out)
{
    if (!m || !out)
        return -FIT_ERR_ARG;
    *out = m->meas;
    return 0;
}

int fit_model_write_obj(const fit_model *m, const float *vertices, const char *path)
{
    if (!m || !path)
        return -FIT_ERR_ARG;
    const float *v = vertices ? vertices : m->mesh.v;
    FILE *fp = fopen(path, "w");
    if (!fp)
        return -FIT_ERR_IO;
    fprintf(fp, "# tryon body model: %d vertices, %d triangles\n", m->mesh.nv, m->mesh.nt);
    for (int i = 0; i < m->mesh.nv; ++i)
        fprintf(fp, "v %.6f %.6f %.6f\n", v[i * 3], v[i * 3 + 1], v[i * 3 + 2]);
    for (int i = 0; i < m->mesh.nt; ++i)
        fprintf(fp, "f %d %d %d\n", m->mesh.t[i * 3] + 1, m->mesh.t[i * 3 + 1] + 1,
                m->mesh.t[i * 3 + 2] + 1);
    int bad = ferror(fp);
    if (fclose(fp) != 0 || bad)
        return -FIT_ERR_IO;
    return 0;
}
