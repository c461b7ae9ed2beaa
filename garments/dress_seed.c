/* The seed's dressing (seed 003, Algorithm 1): six parallel loops per step: spring forces;
 * external forces (viscous damping, gravity); joint (seam) forces; velocities with image-space
 * collision; velocity correction of over-elongated springs (Vassilev) and of open joints; new
 * positions (and a floor at y = 0, where the body stands). Loops over springs and joints write
 * their own slots and the per-vertex loops gather them, so no two threads write one vertex. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "tryon_clock.h"
#include "bodyfit.h"
#include "cloth_cloth.h"
#include "dress_internal.h"

#define GAR_GRAVITY_M_S2 9.81f
/* Viscous damping rate (1/s): -c v with c = mass * rate; settles a garment in about 0.5 s. */
#define GAR_DAMPING_PER_S 4.0f
/* Explicit integration is stable for k dt^2 / m below about 4 / (springs per vertex); the
 * stretch stiffness is capped at a tenth of the lightest vertex's limit and the velocity
 * correction (Vassilev) keeps the strain at the fabric's max_strain instead (the seed's way to
 * take steps of a millisecond). */
#define GAR_STABLE_FRACTION 0.3f
/* A joint's force grows with its gap up to this gap, then stays (a seam 30 cm open would
 * otherwise throw its vertices at tens of m/s). */
#define GAR_SEAM_FORCE_REACH_M 0.01f
/* Seams pull their open joints shut over this time constant (s). */
#define GAR_SEAM_TAU_S 0.05f
/* Velocity corrections are capped (m/s) so a badly placed start cannot fling the cloth. */
#define GAR_MAX_CORRECTION_M_S 0.5f
/* Velocity correction rounds per step (the seed: one) and the fastest a joint closes. */
#define GAR_CORRECTION_ROUNDS 6
#define GAR_SEAM_MIN_STEPS    4.0f
/* Seams close no faster than this (m/s), so the panels' interiors, which the velocity
 * correction reaches a ring of springs per round, can follow their edges. */
#define GAR_SEAM_SPEED_M_S 0.5f
/* Cloth thickness for the body (image space) and between panels. */
#define GAR_BODY_MARGIN_M     0.003f
#define GAR_CLOTH_THICKNESS_M 0.003f
/* Cloth-cloth runs every this many steps (the seed runs it less often than the springs). */
#define GAR_CC_EVERY 10

typedef struct dress {
    const gar_mesh *m;
    int n;
    float *x, *v, *mass, *fs, *fj, *dv, *dvj, *push;
    gar_springs sp;
    float k[3], kj, max_strain, friction, dt;
    int32_t *vj_offset, *vj; /* joints per vertex: index * 3 + role (0 = a, 1 = b0, 2 = b1) */
    gar_body_maps maps[3];
    gar_cc *cc;
    uint8_t *skip;
    uint8_t *welded; /* per joint: closed once, sewn from then on */
} dress;

static int joint_csr(dress *d)
{
    const gar_mesh *m = d->m;
    d->vj_offset = calloc((size_t)d->n + 1, sizeof *d->vj_offset);
    d->vj = malloc((size_t)(3 * m->num_joints + 1) * sizeof *d->vj);
    int *fill = malloc((size_t)(d->n + 1) * sizeof *fill);
    if (!d->vj_offset || !d->vj || !fill) {
        free(fill);
        return -GAR_ERR_NO_MEMORY;
    }
    for (int j = 0; j < m->num_joints; j++) {
        d->vj_offset[m->joints[j].a + 1]++;
        d->vj_offset[m->joints[j].b0 + 1]++;
        d->vj_offset[m->joints[j].b1 + 1]++;
    }
    for (int i = 0; i < d->n; i++)
        d->vj_offset[i + 1] += d->vj_offset[i];
    memcpy(fill, d->vj_offset, (size_t)(d->n + 1) * sizeof *fill);
    for (int j = 0; j < m->num_joints; j++) {
        d->vj[fill[m->joints[j].a]++] = 3 * j;
        d->vj[fill[m->joints[j].b0]++] = 3 * j + 1;
        d->vj[fill[m->joints[j].b1]++] = 3 * j + 2;
    }
    free(fill);
    return 0;
}

static void partner(const dress *d, const gar_joint *j, float out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (1 - j->w) * d->x[3 * j->b0 + k] + j->w * d->x[3 * j->b1 + k];
}

/* Gathers a per-joint vector into vertex i: +1 for a, -(1 - w) / -w for the partner's ends. */
static void gather_joints(const dress *d, int i, const float *per_joint, float out[3])
{
    for (int q = d->vj_offset[i]; q < d->vj_offset[i + 1]; q++) {
        int j = d->vj[q] / 3, role = d->vj[q] % 3;
        float w = d->m->joints[j].w, s = role == 0 ? 1 : role == 1 ? -(1 - w) : -w;
        for (int k = 0; k < 3; k++)
            out[k] += s * per_joint[3 * j + k];
    }
}

static void gather_springs(const dress *d, int i, const float *per_spring, float out[3])
{
    for (int q = d->sp.vert_offset[i]; q < d->sp.vert_offset[i + 1]; q++) {
        int s = d->sp.vert_springs[q];
        float sign = d->sp.ends[2 * s] == i ? 1.0f : -1.0f;
        for (int k = 0; k < 3; k++)
            out[k] += sign * per_spring[3 * s + k];
    }
}

/* A joint that has closed to GAR_SEAM_CLOSED_M is sewn: from then on, after each step, its two
 * sides are moved to their common point (in joint order, so the result does not depend on the
 * thread count). */
static void sew(dress *d)
{
    const gar_mesh *m = d->m;
    for (int j = 0; j < m->num_joints; j++) {
        const gar_joint *jt = &m->joints[j];
        float p[3], *a = d->x + 3 * jt->a, g2 = 0;
        partner(d, jt, p);
        for (int k = 0; k < 3; k++)
            g2 += (p[k] - a[k]) * (p[k] - a[k]);
        if (!d->welded[j] && g2 > GAR_SEAM_CLOSED_M * GAR_SEAM_CLOSED_M)
            continue;
        d->welded[j] = 1;
        for (int k = 0; k < 3; k++) {
            float mid = 0.5f * (a[k] + p[k]), shift = mid - p[k];
            a[k] = mid;
            d->x[3 * jt->b0 + k] += shift;
            if (jt->b1 != jt->b0)
                d->x[3 * jt->b1 + k] += shift;
        }
    }
}

/* Loop 5 (seed: Vassilev's velocity modification): an over-elongated stretch spring loses the
 * relative velocity that stretches it and gains one that brings it back to max_strain within
 * the step; an open joint's relative velocity is set to close it. A vertex in several
 * corrections takes their mean (Jacobi). */
static void correct_velocities(dress *d)
{
    const gar_mesh *m = d->m;
    int nj = m->num_joints, n = d->n;
    float dt = d->dt;
#pragma omp parallel for schedule(static)
    for (int s = 0; s < d->sp.n_stretch; s++) {
        int ia = d->sp.ends[2 * s], ib = d->sp.ends[2 * s + 1];
        const float *a = d->x + 3 * ia, *b = d->x + 3 * ib, *va = d->v + 3 * ia,
                    *vb = d->v + 3 * ib;
        float e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float l = sqrtf(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        float lmax = d->sp.rest_m[s] * (1 + d->max_strain), corr = 0;
        if (l > 0) {
            float rel =
                ((vb[0] - va[0]) * e[0] + (vb[1] - va[1]) * e[1] + (vb[2] - va[2]) * e[2]) / l;
            if (l + rel * dt > lmax)
                corr = fmaxf((lmax - l) / dt - rel, -GAR_MAX_CORRECTION_M_S);
        }
        for (int k = 0; k < 3; k++)
            d->dv[3 * s + k] = l > 0 ? 0.5f * corr * e[k] / l : 0;
    }
#pragma omp parallel for schedule(static)
    for (int j = 0; j < nj; j++) {
        float p[3];
        partner(d, &m->joints[j], p);
        const gar_joint *jt = &m->joints[j];
        const float *a = d->x + 3 * jt->a, *va = d->v + 3 * jt->a;
        float g[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        float gl = sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        /* Wide gaps close at GAR_SEAM_SPEED_M_S, narrow ones within a few steps. */
        float tau = fmaxf(GAR_SEAM_MIN_STEPS * dt, fminf(GAR_SEAM_TAU_S, gl / GAR_SEAM_SPEED_M_S));
        for (int k = 0; k < 3; k++) {
            float vp = (1 - jt->w) * d->v[3 * jt->b0 + k] + jt->w * d->v[3 * jt->b1 + k];
            d->dvj[3 * j + k] = 0.5f * (g[k] / tau - (va[k] - vp));
        }
    }
#pragma omp parallel for schedule(static)
    for (int i = 0; i < n; i++) {
        float c[3] = {0, 0, 0}, cj[3] = {0, 0, 0};
        int active = 0;
        for (int q = d->sp.vert_offset[i]; q < d->sp.vert_offset[i + 1]; q++) {
            int sp = d->sp.vert_springs[q];
            if (sp >= d->sp.n_stretch)
                continue;
            float sign = d->sp.ends[2 * sp] == i ? 1.0f : -1.0f; /* a slows, b speeds */
            const float *dv = d->dv + 3 * sp;
            if (dv[0] != 0 || dv[1] != 0 || dv[2] != 0)
                active++;
            for (int k = 0; k < 3; k++)
                c[k] += sign * dv[k];
        }
        int nji = d->vj_offset[i + 1] - d->vj_offset[i];
        if (nji > 0)
            gather_joints(d, i, d->dvj, cj);
        float *v = d->v + 3 * i;
        for (int k = 0; k < 3; k++)
            v[k] += -c[k] / (active > 0 ? active : 1) + (nji > 0 ? cj[k] / nji : 0);
    }
}

static void step(dress *d, int with_cc, float gravity)
{
    const gar_mesh *m = d->m;
    int ns = d->sp.n, nj = m->num_joints, n = d->n;
    float dt = d->dt;
    /* Loop 1: spring forces, f = k (|xj - xi| - rest) along the spring, stored per spring. */
#pragma omp parallel for schedule(static)
    for (int s = 0; s < ns; s++) {
        const float *a = d->x + 3 * d->sp.ends[2 * s], *b = d->x + 3 * d->sp.ends[2 * s + 1];
        float e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float l = sqrtf(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        float f = l > 0 ? d->k[d->sp.kind[s]] * (l - d->sp.rest_m[s]) / l : 0;
        for (int k = 0; k < 3; k++)
            d->fs[3 * s + k] = f * e[k];
    }
    /* Loop 3 (before the gather): joint forces pulling a to its partner. */
#pragma omp parallel for schedule(static)
    for (int j = 0; j < nj; j++) {
        float p[3];
        partner(d, &m->joints[j], p);
        const float *a = d->x + 3 * m->joints[j].a;
        float g[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        float gl = sqrtf(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
        float scale = gl > GAR_SEAM_FORCE_REACH_M ? GAR_SEAM_FORCE_REACH_M / gl : 1.0f;
        for (int k = 0; k < 3; k++)
            d->fj[3 * j + k] = d->kj * scale * g[k];
    }
    /* Loops 2 and 4: external forces, gathered spring and joint forces, velocity, collision. */
#pragma omp parallel for schedule(static)
    for (int i = 0; i < n; i++) {
        float f[3] = {0, -gravity * d->mass[i], 0};
        gather_springs(d, i, d->fs, f);
        gather_joints(d, i, d->fj, f);
        float *v = d->v + 3 * i, *x = d->x + 3 * i;
        for (int k = 0; k < 3; k++)
            v[k] += dt * (f[k] / d->mass[i] - GAR_DAMPING_PER_S * v[k]);
        float p[3] = {x[0] + dt * v[0], x[1] + dt * v[1], x[2] + dt * v[2]}, push[3], nn[3];
        if (gar_body_maps_collide(d->maps, p, GAR_BODY_MARGIN_M, push, nn)) {
            float vn = v[0] * nn[0] + v[1] * nn[1] + v[2] * nn[2];
            for (int k = 0; k < 3; k++) {
                x[k] += push[k];
                if (vn < 0)
                    v[k] -= vn * nn[k];
                v[k] *= 1 - d->friction * 0.1f; /* tangential friction while in contact */
            }
        }
    }
    for (int it = 0; it < GAR_CORRECTION_ROUNDS; it++)
        correct_velocities(d);
    if (with_cc && d->cc) {
        memset(d->push, 0, (size_t)n * 3 * sizeof *d->push);
        gar_cc_repel(d->cc, d->x, GAR_CLOTH_THICKNESS_M, d->push);
    }
    /* Loop 6: new positions; the floor (y = 0) holds what reaches it. */
#pragma omp parallel for schedule(static)
    for (int i = 0; i < n; i++) {
        float *v = d->v + 3 * i, *x = d->x + 3 * i;
        for (int k = 0; k < 3; k++)
            x[k] += dt * v[k] + (with_cc && d->cc ? d->push[3 * i + k] : 0);
        if (x[1] < GAR_BODY_MARGIN_M) {
            x[1] = GAR_BODY_MARGIN_M;
            v[1] = fmaxf(v[1], 0);
            v[0] *= 1 - d->friction, v[2] *= 1 - d->friction;
        }
    }
    sew(d);
}

static float max_gap(const dress *d)
{
    float g = 0;
    for (int j = 0; j < d->m->num_joints; j++) {
        float p[3], s = 0;
        partner(d, &d->m->joints[j], p);
        for (int k = 0; k < 3; k++)
            s +=
                (p[k] - d->x[3 * d->m->joints[j].a + k]) * (p[k] - d->x[3 * d->m->joints[j].a + k]);
        g = fmaxf(g, sqrtf(s));
    }
    return g;
}

static void dress_free(dress *d)
{
    free(d->v), free(d->mass), free(d->fs), free(d->fj), free(d->dv), free(d->dvj), free(d->push);
    free(d->vj_offset), free(d->vj), free(d->skip), free(d->welded);
    gar_springs_free(&d->sp);
    for (int a = 0; a < 3; a++)
        gar_body_maps_free(&d->maps[a]);
    gar_cc_destroy(d->cc);
}

static int dress_init(dress *d, gar_mesh *m, const fit_model *body, const gar_dress_desc *desc)
{
    const gar_fabric *fab = desc && desc->fabric ? desc->fabric : gar_fabric_find("cotton");
    d->m = m, d->n = m->num_vertices, d->x = m->xyz;
    d->dt = desc && desc->dt_s > 0 ? desc->dt_s : 0.001f;
    d->max_strain = fab->max_strain, d->friction = fab->friction;
    float pixel = desc && desc->map_pixel_m > 0 ? desc->map_pixel_m : 0.004f;
    int rc = gar_springs_build(m, &d->sp);
    if (rc)
        return rc;
    size_t n3 = (size_t)d->n * 3, s3 = (size_t)d->sp.n * 3, j3 = (size_t)(m->num_joints + 1) * 3;
    d->v = calloc(n3, sizeof *d->v), d->mass = calloc((size_t)d->n, sizeof *d->mass);
    d->fs = malloc(s3 * sizeof *d->fs), d->dv = malloc(s3 * sizeof *d->dv);
    d->fj = malloc(j3 * sizeof *d->fj), d->dvj = malloc(j3 * sizeof *d->dvj);
    d->push = calloc(n3, sizeof *d->push), d->skip = calloc((size_t)d->n, 1);
    d->welded = calloc((size_t)m->num_joints + 1, 1);
    if (!d->v || !d->mass || !d->fs || !d->dv || !d->fj || !d->dvj || !d->push || !d->skip ||
        !d->welded)
        return -GAR_ERR_NO_MEMORY;
    if ((rc = joint_csr(d)))
        return rc;
    gar_lump_masses(m, fab->density_kg_m2, d->mass);
    float mmin = INFINITY;
    for (int i = 0; i < d->n; i++)
        mmin = fminf(mmin, d->mass[i]);
    float kmax = GAR_STABLE_FRACTION * mmin / (d->dt * d->dt);
    d->k[GAR_STRETCH] = fminf(fab->stretch_n_m, kmax);
    d->k[GAR_SHEAR] = d->k[GAR_STRETCH] * fab->shear_n_m / fab->stretch_n_m;
    d->k[GAR_BEND] = d->k[GAR_STRETCH] * fab->bend_n_m / fab->stretch_n_m;
    d->kj = d->k[GAR_STRETCH] * (desc && desc->seam_gain > 0 ? desc->seam_gain : 1.0f);
    rc = gar_body_maps_render(fit_model_rest_vertices(body), fit_model_vertex_count(body),
                              fit_model_triangles(body), fit_model_triangle_count(body), pixel,
                              d->maps);
    if (rc)
        return rc;
    gar_seam_skip(m, &d->sp, d->skip);
    if (desc && desc->cloth_cloth && !(d->cc = gar_cc_create(m, d->skip)))
        return -GAR_ERR_NO_MEMORY;
    return 0;
}

int gar_dress_seed(const gar_pattern *p, gar_mesh *m, const fit_model *body,
                   const gar_dress_desc *desc, gar_dress_stats *st, gar_reject *why)
{
    if (!p || !m || !body || !st)
        return gar_refuse(why, GAR_ERR_ARG, "dressing needs a pattern, its mesh and a body");
    memset(st, 0, sizeof *st);
    double t0 = tryon_now_ms();
    dress d = {0};
    int rc = dress_init(&d, m, body, desc);
    if (rc) {
        dress_free(&d);
        return gar_refuse(why, -rc, "dressing setup (%d vertices)", m->num_vertices);
    }
    float max_seam = desc && desc->max_seaming_s > 0 ? desc->max_seaming_s : 2.0f;
    int drape = desc && desc->drape_steps > 0 ? desc->drape_steps : 300;
    /* Seaming without gravity (an open panel has nothing to hang from), then draping with it. */
    int seaming_steps = (int)(max_seam / d.dt), s = 0;
    st->seaming_s = -1;
    for (; s < seaming_steps; s++) {
        step(&d, s % GAR_CC_EVERY == 0, 0.0f);
        if (s % 20 == 19 && max_gap(&d) < GAR_SEAM_CLOSED_M) {
            st->seaming_s = (s + 1) * d.dt;
            s++;
            break;
        }
    }
    for (int k = 0; k < drape; k++, s++)
        step(&d, s % GAR_CC_EVERY == 0, GAR_GRAVITY_M_S2);
    st->steps = s;
    dress_free(&d);
    st->ms = (float)(tryon_now_ms() - t0);
    float ms = st->ms, seaming = st->seaming_s;
    int steps = st->steps;
    rc = gar_dress_measure(m, body, st);
    st->ms = ms, st->seaming_s = seaming, st->steps = steps;
    return rc ? gar_refuse(why, -rc, "measuring the dressed garment") : 0;
}
