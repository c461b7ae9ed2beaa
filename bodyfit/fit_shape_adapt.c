/* Shape changes that keep the mesh's topology (so the published mesh keeps its triangles and
 * tryon-sim follows it), in the degrees of freedom of fit_shape_q. Each vertex moves with the
 * map of the joints that skin it, blended by its skinning weights:
 * - every part: scaled vertically about the floor by the height's scale (girths are not: they
 *   come from the offsets; scaling them too measured worse, docs/bodyfit-history.md);
 * - legs: scaled vertically by `leg` about the floor; the rest of the body moves up with the hip
 *   joints and is scaled about them so that the top of the head stays (the height is measured,
 *   the split between legs and trunk is not);
 * - arms: stretched along the rest arm from the shoulder joint by `arm`; arms and clavicles
 *   shifted sideways by the change of half the shoulder width;
 * - then along the rest normal by the part's girth offset. */
#include "fit_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define ADAPT_PI 3.14159265358979

fit_shape_q fit_shape_q_identity(void)
{
    return (fit_shape_q){
        .scale = 1.0f, .leg = 1.0f, .arm = 1.0f, .shoulder = 1.0f, .torso = {1.0f, 1.0f, 1.0f}};
}

void fit_shape_q_to_array(const fit_shape_q *q, float a[FIT_SHAPE_DOF])
{
    a[0] = q->scale, a[1] = q->leg, a[2] = q->arm, a[3] = q->shoulder;
    a[4] = q->torso[0], a[5] = q->torso[1], a[6] = q->torso[2];
    a[7] = q->arm_offset, a[8] = q->leg_offset;
}

fit_shape_q fit_shape_q_from_array(const float a[FIT_SHAPE_DOF])
{
    return (fit_shape_q){.scale = a[0],
                         .leg = a[1],
                         .arm = a[2],
                         .shoulder = a[3],
                         .torso = {a[4], a[5], a[6]},
                         .arm_offset = a[7],
                         .leg_offset = a[8]};
}

int fit_shape_base_init(fit_shape_base *b, const fit_model *m)
{
    int nv = m->mesh.nv;
    memset(b, 0, sizeof *b);
    b->v = malloc((size_t)nv * 3 * sizeof(float));
    b->n = malloc((size_t)nv * 3 * sizeof(float));
    if (!b->v || !b->n) {
        fit_shape_base_free(b);
        return -FIT_ERR_NOMEM;
    }
    memcpy(b->v, m->mesh.v, (size_t)nv * 3 * sizeof(float));
    int rc = fit_model_normals(m, m->mesh.v, b->n);
    if (rc) {
        fit_shape_base_free(b);
        return rc;
    }
    memcpy(b->joint, m->sk.joint, sizeof b->joint);
    b->shape = m->shape;
    b->nv = nv;
    return 0;
}

void fit_shape_base_free(fit_shape_base *b)
{
    free(b->v);
    free(b->n);
    b->v = b->n = NULL;
}

/* The girth offset of a joint's part: arms and legs (the torso's girths are ratios). */
static float offset_of(const fit_shape_q *q, int joint)
{
    if (joint <= FIT_HEAD)
        return 0.0f;
    return joint < FIT_L_HIP ? q->arm_offset : q->leg_offset;
}

enum { MAP_TRUNK, MAP_LEG, MAP_ARM, MAP_CLAVICLE };

static int map_of(int joint)
{
    if (joint >= FIT_L_HIP)
        return MAP_LEG;
    if (joint == FIT_L_CLAVICLE || joint == FIT_R_CLAVICLE)
        return MAP_CLAVICLE;
    return joint > FIT_HEAD ? MAP_ARM : MAP_TRUNK;
}

static int side_of(int joint) /* 0 left, 1 right */
{
    return joint >= FIT_R_CLAVICLE && joint <= FIT_R_WRIST;
}

/* What the maps need, from the base and q. */
typedef struct shape_maps {
    float scale, leg, hip_y, up; /* up: the trunk's vertical scale about the hip joints */
    float shoulder[2][3], dir[2][3], shift[2], arm;
    float torso[3], axis[3][2]; /* pelvis, spine, chest: scale across and its axis (x, z) */
} shape_maps;

static void trunk_map(const shape_maps *s, const float p[3], float out[3])
{
    float y = s->scale * p[1];
    out[0] = p[0];
    out[1] = s->hip_y * s->leg + (y - s->hip_y) * s->up;
    out[2] = p[2];
}

static void joint_map(const shape_maps *s, int joint, const float p[3], float out[3])
{
    int map = map_of(joint), side = side_of(joint);
    if (map == MAP_LEG) {
        out[0] = p[0], out[1] = s->scale * s->leg * p[1], out[2] = p[2];
        return;
    }
    trunk_map(s, p, out);
    if (map == MAP_TRUNK) {
        if (joint <= FIT_CHEST) { /* the hip, waist and chest sections */
            const float *c = s->axis[joint];
            out[0] = c[0] + s->torso[joint] * (out[0] - c[0]);
            out[2] = c[1] + s->torso[joint] * (out[2] - c[1]);
        }
        return;
    }
    if (map == MAP_ARM) {
        float d[3] = {out[0] - s->shoulder[side][0], out[1] - s->shoulder[side][1],
                      out[2] - s->shoulder[side][2]};
        float along = (s->arm - 1.0f) * body_dot(d, s->dir[side]);
        for (int k = 0; k < 3; ++k)
            out[k] += along * s->dir[side][k];
    }
    out[0] += s->shift[side];
}

static void maps_init(const fit_shape_base *b, const fit_shape_q *q, shape_maps *s)
{
    memset(s, 0, sizeof *s);
    s->scale = q->scale, s->leg = q->leg, s->arm = q->arm;
    for (int k = 0; k <= FIT_CHEST; ++k) {
        s->torso[k] = q->torso[k];
        s->axis[k][0] = b->joint[k][0], s->axis[k][1] = b->joint[k][2];
    }
    s->hip_y = 0.5f * q->scale * (b->joint[FIT_L_HIP][1] + b->joint[FIT_R_HIP][1]);
    float top = q->scale * b->shape.height;
    s->up = (top - s->hip_y * q->leg) / (top - s->hip_y);
    const int sh[2] = {FIT_L_SHOULDER, FIT_R_SHOULDER}, wr[2] = {FIT_L_WRIST, FIT_R_WRIST};
    for (int side = 0; side < 2; ++side) {
        float w[3];
        trunk_map(s, b->joint[sh[side]], s->shoulder[side]);
        trunk_map(s, b->joint[wr[side]], w);
        float d[3] = {w[0] - s->shoulder[side][0], w[1] - s->shoulder[side][1],
                      w[2] - s->shoulder[side][2]};
        float l = sqrtf(body_dot(d, d));
        for (int k = 0; k < 3; ++k)
            s->dir[side][k] = l > 0.0f ? d[k] / l : 0.0f;
        s->shift[side] = (q->shoulder - 1.0f) * b->joint[sh[side]][0];
    }
}

/* The inverse of joint_map, which is affine (each step above scales, shears or shifts), as a
 * 3x4 row-major matrix: the map's columns read off at the origin and the unit axes, inverted. */
static void unshape_of(const shape_maps *s, int joint, float out[12])
{
    const float zero[3] = {0.0f, 0.0f, 0.0f};
    float o[3], a[3][3];
    joint_map(s, joint, zero, o);
    for (int k = 0; k < 3; ++k) {
        float e[3] = {0.0f, 0.0f, 0.0f}, x[3];
        e[k] = 1.0f;
        joint_map(s, joint, e, x);
        for (int r = 0; r < 3; ++r)
            a[r][k] = x[r] - o[r];
    }
    double inv[3][3];
    double det = (double)a[0][0] * ((double)a[1][1] * a[2][2] - (double)a[1][2] * a[2][1]) -
                 (double)a[0][1] * ((double)a[1][0] * a[2][2] - (double)a[1][2] * a[2][0]) +
                 (double)a[0][2] * ((double)a[1][0] * a[2][1] - (double)a[1][1] * a[2][0]);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
            inv[r][c] = ((double)a[r1][c1] * a[r2][c2] - (double)a[r1][c2] * a[r2][c1]) / det;
        }
    for (int r = 0; r < 3; ++r) {
        double t = 0.0;
        for (int c = 0; c < 3; ++c) {
            out[r * 4 + c] = (float)inv[r][c];
            t -= inv[r][c] * o[c];
        }
        out[r * 4 + 3] = (float)t;
    }
}

void fit_shape_base_apply(const fit_shape_base *b, fit_model *m, const fit_shape_q *q)
{
    shape_maps s;
    maps_init(b, q, &s);
    for (int i = 0; i < b->nv; ++i) {
        const uint8_t *wj = m->wjoint + (size_t)i * FIT_MAX_INFLUENCES;
        const float *ww = m->weight + (size_t)i * FIT_MAX_INFLUENCES;
        const float *p = b->v + (size_t)i * 3, *n = b->n + (size_t)i * 3;
        float acc[3] = {0.0f, 0.0f, 0.0f}, d = 0.0f, x[3];
        for (int k = 0; k < FIT_MAX_INFLUENCES; ++k) {
            if (ww[k] <= 0.0f)
                continue;
            joint_map(&s, wj[k], p, x);
            for (int c = 0; c < 3; ++c)
                acc[c] += ww[k] * x[c];
            d += ww[k] * offset_of(q, wj[k]);
        }
        for (int c = 0; c < 3; ++c)
            m->mesh.v[(size_t)i * 3 + c] = acc[c] + d * n[c];
    }
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        joint_map(&s, j, b->joint[j], m->sk.joint[j]);
    /* The implicit primitives keep the base shape; the contact pass (skin_contact.c) takes a
       point back to it by each joint's map (measured against the skin itself, the pass was 60
       mm off with the arms down at a 4 % taller, 8 % broader-chested shape). */
    float qa[FIT_SHAPE_DOF], ia[FIT_SHAPE_DOF];
    fit_shape_q identity = fit_shape_q_identity();
    fit_shape_q_to_array(q, qa);
    fit_shape_q_to_array(&identity, ia);
    m->reshaped = memcmp(qa, ia, sizeof qa) != 0;
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        unshape_of(&s, j, m->unshape[j]);
        m->unshape_offset[j] = offset_of(q, j);
    }
}

static float clampf(float v, float lo, float hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

fit_shape fit_shape_adapted(const fit_shape_base *b, const fit_shape_q *q)
{
    shape_maps s;
    maps_init(b, q, &s);
    float a[FIT_SHAPE_PARAMS];
    fit_shape_to_array(&b->shape, a);
    a[0] *= q->scale;          /* height */
    a[7] *= q->scale * q->leg; /* leg length: vertical */
    a[1] *= q->shoulder;       /* shoulder width */
    float v = q->scale * s.up; /* the A-pose arm runs at 45 degrees: half its length */
    a[5] *= q->arm * sqrtf(0.5f * (v * v + 1.0f));                 /* squared is vertical */
    a[4] *= q->torso[0], a[3] *= q->torso[1], a[2] *= q->torso[2]; /* hip, waist, chest */
    a[6] += (float)(2.0 * ADAPT_PI * q->arm_offset);
    a[8] += (float)(2.0 * ADAPT_PI * q->leg_offset);
    for (int i = 0; i < FIT_SHAPE_PARAMS; ++i) {
        float lo, hi;
        fit_shape_param_range(i, &lo, &hi);
        a[i] = clampf(a[i], lo, hi);
    }
    return fit_shape_from_array(a);
}
