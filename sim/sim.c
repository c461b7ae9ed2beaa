/* The per-frame driver: validation, the body frames, the backend, divergence detection and
 * recovery, and the published metrics. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "carry.h"
#include "cloth.h"
#include "passes.h"

const char *sim_state_name(sim_state s)
{
    switch (s) {
    case SIM_STATE_OK:
        return "ok";
    case SIM_STATE_RECOVERED:
        return "recovered";
    case SIM_STATE_DIVERGED:
        return "diverged";
    case SIM_STATE_SETTLING:
        return "settling";
    case SIM_STATE_CARRIED:
        return "carried";
    }
    return "unknown";
}

static void save_good(sim *s);
static void keep_good(sim *s, float max_strain);

sim_desc sim_default_desc(void)
{
    return (sim_desc){
        .backend = SIM_BACKEND_C,
        .solver = SIM_SOLVER_TRYON,
        .iterations = 25,
        .frame_dt_s = 1.0f / 30.0f,
        .fabric = {.density_kg_m2 = 0.2f,
                   .stretch_n_m = 1000.0f,
                   .shear_n_m = 100.0f,
                   .bend_n_m = 2.0f},
        .damping = 0.5f,
        .thickness_m = 0.004f,
        .friction = 0.3f,
        .gravity_m_s2 = 9.81f,
        /* the clamp, under the 1 % of quasi-inextensible cloth (ARCHITECTURE.md's p99 goal): the
           contacts and attachments placed after it move points too, and with the clamp at 1 %
           the fast swing published p99 1.11 %; at 0.75 % 0.93 % (docs/sim.md, "The strain
           limit's headroom"). Cotton under its own weight strains about 0.1 %. */
        .strain_limit = 0.0075f,
        .follow = 1.0f,
        .support = 1,
        .retry_max_strain = SIM_RETRY_STRAIN,
        .retry_p99_strain = SIM_RETRY_P99,
        .max_body_vertices = 100000,
        .max_body_triangles = 200000,
    };
}

/* Zero means default; negative means none where the header says so. */
static sim_desc fill_defaults(const sim_desc *in)
{
    sim_desc d = in ? *in : sim_default_desc();
    sim_desc z = sim_default_desc();
#define DEFAULT(f)                                                                                 \
    if (d.f == 0)                                                                                  \
    d.f = z.f
    DEFAULT(iterations);
    DEFAULT(frame_dt_s);
    DEFAULT(fabric.density_kg_m2);
    DEFAULT(fabric.stretch_n_m);
    DEFAULT(fabric.shear_n_m);
    DEFAULT(fabric.bend_n_m);
    DEFAULT(damping);
    DEFAULT(thickness_m);
    DEFAULT(friction);
    DEFAULT(gravity_m_s2);
    DEFAULT(strain_limit);
    DEFAULT(follow);
    DEFAULT(support);
    DEFAULT(retry_max_strain);
    DEFAULT(retry_p99_strain);
    DEFAULT(max_body_vertices);
    DEFAULT(max_body_triangles);
#undef DEFAULT
    if (d.damping < 0.0f)
        d.damping = 0.0f;
    if (d.friction < 0.0f)
        d.friction = 0.0f;
    if (d.gravity_m_s2 < 0.0f)
        d.gravity_m_s2 = 0.0f;
    if (d.follow < 0.0f)
        d.follow = 0.0f;
    if (d.support < 0)
        d.support = 0;
    return d;
}

static int check_desc(const sim_desc *d, sim_reject *why)
{
    const sim_fabric *f = &d->fabric;
    if (d->iterations < 1 || d->iterations > 10000)
        return sim_reject_set(why, SIM_ERR_PARAM, "iterations = %d (1..10000)", d->iterations);
    if (!(d->frame_dt_s > 0.0f && d->frame_dt_s < 1.0f))
        return sim_reject_set(why, SIM_ERR_PARAM, "frame_dt_s = %g (0..1 s)", d->frame_dt_s);
    if (!(f->density_kg_m2 > 0.0f && f->stretch_n_m > 0.0f && f->shear_n_m > 0.0f &&
          f->bend_n_m > 0.0f && isfinite(f->stretch_n_m) && isfinite(f->shear_n_m) &&
          isfinite(f->bend_n_m) && isfinite(f->density_kg_m2)))
        return sim_reject_set(why, SIM_ERR_PARAM,
                              "fabric density and stiffnesses must be "
                              "positive and finite");
    if (!(d->damping < 1.0f) || !isfinite(d->friction) || !isfinite(d->gravity_m_s2) ||
        !(d->thickness_m > 0.0f && d->thickness_m < 0.1f) || !(d->strain_limit > 0.0f) ||
        !(d->follow <= 1.0f) || isnan(d->retry_max_strain) || isnan(d->retry_p99_strain) ||
        isnan(d->retry_budget_ms) || isnan(d->frame_budget_ms))
        return sim_reject_set(why, SIM_ERR_PARAM,
                              "damping < 1, 0 < thickness < 0.1 m, strain_limit > 0, "
                              "follow <= 1, retry strains and budgets not NaN needed");
    if (d->backend != SIM_BACKEND_C && d->backend != SIM_BACKEND_OPENCL)
        return sim_reject_set(why, SIM_ERR_PARAM, "backend %d unknown", (int)d->backend);
    if (d->solver != SIM_SOLVER_TRYON && d->solver != SIM_SOLVER_SEED)
        return sim_reject_set(why, SIM_ERR_PARAM, "solver %d unknown", (int)d->solver);
    return 0;
}

int sim_body_validate(const float *xyz, int nv, const int32_t *tris, int nt, sim_reject *why)
{
    if (nv <= 0 || nt <= 0 || !xyz || !tris)
        return sim_reject_set(why, SIM_ERR_EMPTY, "body: %d vertices, %d triangles", nv, nt);
    for (int i = 0; i < nv * 3; i++)
        if (!isfinite(xyz[i]))
            return sim_reject_set(why, SIM_ERR_NOT_FINITE, "body vertex %d coordinate %d = %g",
                                  i / 3, i % 3, xyz[i]);
    for (int t = 0; t < nt; t++) {
        const int32_t *v = &tris[t * 3];
        for (int k = 0; k < 3; k++)
            if (v[k] < 0 || v[k] >= nv)
                return sim_reject_set(why, SIM_ERR_INDEX,
                                      "body triangle %d: index %d outside 0..%d", t, v[k], nv - 1);
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2])
            return sim_reject_set(why, SIM_ERR_DEGENERATE,
                                  "body triangle %d repeats a vertex (%d %d %d)", t, v[0], v[1],
                                  v[2]);
    }
    return 0;
}

static void body_free(sim_body *b)
{
    free(b->v);
    free(b->v_prev);
    free(b->tris);
    free(b->n);
    memset(b, 0, sizeof *b);
}

/* Sized for the largest body, written for each body's nv and nt (body_store) and read no
 * further: not cleared. Clearing touched every page (8 MB) of memory recycled from the garment
 * replaced: 22-24 ms of the 37-46 ms that making the garment again took in the pipeline when the
 * fitter's shape settled (15 ms now). */
static int body_alloc(sim_body *b, int max_v, int max_t)
{
    b->v = malloc((size_t)max_v * sizeof *b->v);
    b->v_prev = malloc((size_t)max_v * sizeof *b->v_prev);
    b->tris = malloc((size_t)max_t * sizeof *b->tris);
    b->n = malloc((size_t)max_t * sizeof *b->n);
    return (b->v && b->v_prev && b->tris && b->n) ? 0 : -SIM_ERR_NO_MEMORY;
}

/* Frame k becomes k-1; the new frame, its triangles and face normals are stored. */
static void body_store(sim_body *b, const float *xyz, int nv, const int32_t *tris, int nt)
{
    int same = b->nv == nv && b->nt == nt;
    for (int t = 0; same && t < nt; t++)
        same = b->tris[t][0] == tris[t * 3] && b->tris[t][1] == tris[t * 3 + 1] &&
               b->tris[t][2] == tris[t * 3 + 2];
    float(*tmp)[4] = b->v_prev;
    b->v_prev = b->v;
    b->v = tmp;
    for (int i = 0; i < nv; i++) {
        for (int d = 0; d < 3; d++)
            b->v[i][d] = xyz[i * 3 + d];
        b->v[i][3] = 0.0f;
    }
    b->have_prev = same;
    float m2 = 0.0f; /* the largest squared move (the body is finite: no NaN to order) */
    for (int i = 0; same && i < nv; i++) {
        float dx = b->v[i][0] - b->v_prev[i][0], dy = b->v[i][1] - b->v_prev[i][1],
              dz = b->v[i][2] - b->v_prev[i][2];
        float d2 = dx * dx + dy * dy + dz * dz;
        m2 = d2 > m2 ? d2 : m2;
    }
    b->max_move_m = sqrtf(m2);
    if (same)
        return; /* the same triangles */
    b->nv = nv;
    b->nt = nt;
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            b->tris[t][k] = tris[t * 3 + k];
}

/* Face normals of the triangles the attachments hang from (nothing else reads b->n; the collider
   keeps its own normals of every triangle). */
static void body_attachment_normals(sim_body *b, const sim_attachment *at, int na)
{
    for (int a = 0; a < na; a++) {
        int t = at[a].body_triangle;
        const float *p0 = b->v[b->tris[t][0]], *p1 = b->v[b->tris[t][1]], *p2 = b->v[b->tris[t][2]];
        float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
        float e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
        float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        float inv = len > 0.0f ? 1.0f / len : 0.0f;
        for (int d = 0; d < 3; d++)
            b->n[t][d] = n[d] * inv;
    }
}

/* seed: explicit springs are stable only for dt < 2 sqrt(m / k_sum), k_sum the stiffness on a
 * vertex. The seed must run with springs soft enough for its step, and relies on Provot's
 * correction for the rest; we clamp the same way (half the limit, for margin) and say so. */
static void clamp_seed_stiffness(sim_cloth *c, float dt)
{
    float m_min = INFINITY;
    for (int i = 0; i < c->nv; i++)
        if (c->x[i][3] > 0.0f && 1.0f / c->x[i][3] < m_min)
            m_min = 1.0f / c->x[i][3];
    if (!isfinite(m_min))
        return;
    /* a grid vertex carries 4 springs of each kind; 12 in all */
    float k_max = 0.5f * 4.0f * m_min / (dt * dt) / 12.0f;
    for (int k = 0; k < SIM_SPRING_KINDS; k++)
        if (c->k[k] > k_max)
            c->k[k] = k_max;
}

#ifndef SIM_HAVE_OPENCL
int sim_opencl_device(char *name, size_t name_size)
{
    if (name && name_size > 0)
        snprintf(name, name_size, "built without OpenCL");
    return -1;
}
#endif

static const sim_backend_ops *backend_ops(sim_backend b)
{
#ifdef SIM_HAVE_OPENCL
    if (b == SIM_BACKEND_OPENCL)
        return &sim_backend_opencl;
#endif
    return b == SIM_BACKEND_C ? &sim_backend_c : NULL;
}

sim *sim_create(const sim_desc *desc, const sim_garment *g, sim_reject *why)
{
    sim_reject local;
    if (!why)
        why = &local;
    memset(why, 0, sizeof *why);
    sim_desc d = fill_defaults(desc);
    if (check_desc(&d, why) < 0)
        return NULL;
    if (!g) {
        sim_reject_set(why, SIM_ERR_ARG, "no garment");
        return NULL;
    }
    if (sim_garment_validate(g, d.max_body_triangles, why) < 0)
        return NULL;
    const sim_backend_ops *ops = backend_ops(d.backend);
    if (!ops) {
        sim_reject_set(why, SIM_ERR_BACKEND, "backend %s not built into this binary",
                       d.backend == SIM_BACKEND_OPENCL ? "opencl" : "?");
        return NULL;
    }
    sim *s = calloc(1, sizeof *s);
    if (!s) {
        sim_reject_set(why, SIM_ERR_NO_MEMORY, "sim");
        return NULL;
    }
    s->desc = d;
    s->ops = ops;
    int r = sim_cloth_init(&s->cloth, g, &d.fabric, why);
    if (r < 0) {
        if (why->detail[0] == 0)
            sim_reject_set(why, (sim_error)-r, "building the cloth of %d vertices",
                           g->num_vertices);
        why->code = (sim_error)-r;
        free(s);
        return NULL;
    }
    if (d.solver == SIM_SOLVER_SEED)
        clamp_seed_stiffness(&s->cloth, d.frame_dt_s / (float)d.iterations);
    int nv = s->cloth.nv;
    s->x_good = malloc((size_t)nv * sizeof *s->x_good);
    s->x_prev_good = malloc((size_t)nv * sizeof *s->x_prev_good);
    s->x_best = malloc((size_t)nv * sizeof *s->x_best);
    s->x_prev_best = malloc((size_t)nv * sizeof *s->x_prev_best);
    s->x_pinch = malloc((size_t)nv * sizeof *s->x_pinch);
    s->x_prev_pinch = malloc((size_t)nv * sizeof *s->x_prev_pinch);
    s->scratch = malloc((size_t)(s->cloth.ns + 1) * sizeof *s->scratch);
    s->tris3 = malloc((size_t)s->cloth.nt * 3 * sizeof *s->tris3);
    s->follow_pq = malloc((size_t)(2 * (s->cloth.num_attachments + SIM_FOLLOW_ANCHORS) + 1) *
                          sizeof *s->follow_pq);
    s->follow_anchor = malloc(SIM_FOLLOW_ANCHORS * sizeof *s->follow_anchor);
    s->carry = sim_carry_create(d.max_body_vertices);
    s->x_first = malloc((size_t)nv * sizeof *s->x_first);
    s->body_first = malloc((size_t)d.max_body_vertices * sizeof *s->body_first);
    if (!s->x_good || !s->x_prev_good || !s->x_best || !s->x_prev_best || !s->x_pinch ||
        !s->x_prev_pinch || !s->scratch || !s->tris3 || !s->follow_pq || !s->follow_anchor ||
        !s->carry || !s->x_first || !s->body_first ||
        body_alloc(&s->body, d.max_body_vertices, d.max_body_triangles) < 0) {
        sim_reject_set(why, SIM_ERR_NO_MEMORY, "sim state for %d vertices", nv);
        sim_destroy(s);
        return NULL;
    }
    save_good(s);
    memcpy(s->x_first, s->cloth.x, (size_t)nv * sizeof *s->x_first);
    s->iters_good = d.iterations;
    s->settle_tests_max = SIM_SETTLE_ROUNDS / SIM_SETTLE_BATCH;
    memcpy(s->tris3, g->triangles, (size_t)s->cloth.nt * 3 * sizeof *s->tris3);

    char err[160] = "";
    sim_collider_desc cd = {
        .max_vertices = d.max_body_vertices,
        .max_triangles = d.max_body_triangles,
        .thickness_m = d.thickness_m,
        .friction = d.friction,
        .reach_m = SIM_CONTACT_MARGIN,
        .max_cloth = nv,
        .carry_coulomb = d.solver == SIM_SOLVER_TRYON, /* the seed keeps its Eq. 2 */
        .inelastic = d.solver == SIM_SOLVER_TRYON,
    };
    s->collider = sim_collider_create(&cd, err, sizeof err);
    if (!s->collider) {
        sim_reject_set(why, SIM_ERR_BACKEND, "collider: %s", err);
        sim_destroy(s);
        return NULL;
    }
    if (ops->create(s, &s->backend, err, sizeof err) < 0) {
        sim_reject_set(why, SIM_ERR_BACKEND, "%s backend: %s", ops->name, err);
        sim_destroy(s);
        return NULL;
    }
    return s;
}

void sim_destroy(sim *s)
{
    if (!s)
        return;
    if (s->ops && s->backend)
        s->ops->destroy(s->backend);
    sim_collider_destroy(s->collider);
    sim_cloth_free(&s->cloth);
    body_free(&s->body);
    free(s->x_good);
    free(s->x_prev_good);
    free(s->x_best);
    free(s->x_prev_best);
    free(s->x_pinch);
    free(s->x_prev_pinch);
    free(s->scratch);
    free(s->tris3);
    free(s->follow_pq);
    free(s->follow_anchor);
    sim_carry_destroy(s->carry);
    free(s->x_first);
    free(s->body_first);
    free(s);
}

int sim_take_body(sim *s, sim *from)
{
    if (!s || !from || s->desc.backend != SIM_BACKEND_C || from->desc.backend != SIM_BACKEND_C ||
        s->body.stored || from->collider->nt == 0)
        return -1;
    const sim_collider_desc *a = &s->collider->d, *b = &from->collider->d;
    if (a->max_vertices != b->max_vertices || a->max_triangles != b->max_triangles ||
        a->thickness_m != b->thickness_m || a->friction != b->friction ||
        a->reach_m != b->reach_m || a->carry_coulomb != b->carry_coulomb ||
        a->inelastic != b->inelastic ||
        sim_collider_reserve(from->collider, s->collider->max_cloth) != 0)
        return -1;
    sim_collider *c = s->collider;
    s->collider = from->collider;
    from->collider = c;
    sim_collider_restart(s->collider);
    return 0;
}

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

/* Divergence: a coordinate that is not finite; a stretch no fabric survives, and growing; or a
 * point faster than any garment moves on a person, unless the strain is relaxing (a scrambled
 * start snapping back to its rest shape moves fast and is no divergence). 0: none; 2: a pinch
 * (cloth.h: the stretch alone, on a few springs), which a retry may solve and which is
 * published if none does; 1: any other. */
static int state_diverged(sim *s, int iters, float *max_strain, float *p99_strain)
{
    const sim_cloth *c = &s->cloth;
    float dt = s->desc.frame_dt_s / (float)iters;
    float max_step2 = SIM_DIVERGE_SPEED * dt * SIM_DIVERGE_SPEED * dt;
    /* cloth dragged by the body may move as fast as the body does, and then some */
    float max_frame = SIM_DIVERGE_FRAME_SPEED * s->desc.frame_dt_s + 2.0f * s->body.max_move_m;
    float max_frame2 = max_frame * max_frame;
    int too_fast = 0;
    for (int i = 0; i < c->nv; i++) {
        float v2 = 0.0f, f2 = 0.0f;
        for (int d = 0; d < 3; d++) {
            if (!isfinite(c->x[i][d]) || !isfinite(c->x_prev[i][d]))
                return 1;
            float dv = c->x[i][d] - c->x_prev[i][d];
            float df = c->x[i][d] - s->x_good[i][d];
            v2 += dv * dv;
            f2 += df * df;
        }
        too_fast |= v2 > max_step2 || f2 > max_frame2;
    }
    sim_strain_stats(c, s->scratch, max_strain, p99_strain);
    int growing = *max_strain > sim_strain_grown(s->strain_good);
    /* relaxing from a real stretch (a percent at least): at rest, strains of 1e-7 are rounding,
       and a cloth in free fall "relaxed" from 9e-7 to 2e-7 while falling 5 km in a frame */
    int relaxing = s->strain_good > 0.01f && *max_strain < 0.9f * s->strain_good;
    /* a stretch no fabric survives is a failure unless it is relaxing: growing or standing (a
       state stuck at 30x its rest length passed while it merely stayed there, docs/sim.md,
       "Real motion") */
    if (too_fast && !relaxing)
        return 1;
    if (*max_strain < SIM_DIVERGE_STRAIN || (!growing && relaxing))
        return 0;
    float free_max;
    int over = sim_strain_count_over(c, SIM_DIVERGE_STRAIN, &free_max);
    if (free_max < SIM_DIVERGE_STRAIN)
        return 0; /* only springs between glued vertices: the body's own stretch under them */
    return sim_is_pinch(free_max, over) ? 2 : 1;
}

/* How far a frame's strain is over the retry goals: > 1 misses one of them; 0 without goals
   (and for the seed solver, which is measured as published). */
static float strain_excess(const sim *s, float max_strain, float p99)
{
    const sim_desc *d = &s->desc;
    if (d->solver != SIM_SOLVER_TRYON)
        return 0.0f;
    float e = 0.0f;
    if (d->retry_max_strain > 0.0f)
        e = fmaxf(e, max_strain / d->retry_max_strain);
    if (d->retry_p99_strain > 0.0f)
        e = fmaxf(e, p99 / d->retry_p99_strain);
    return e;
}

/* The state becomes the last good one; max_strain is its max stretch strain. */
static void keep_good(sim *s, float max_strain)
{
    s->strain_good = max_strain;
    size_t bytes = (size_t)s->cloth.nv * sizeof *s->x_good;
    memcpy(s->x_good, s->cloth.x, bytes);
    memcpy(s->x_prev_good, s->cloth.x_prev, bytes);
}

static void save_good(sim *s)
{
    float max_strain, p99;
    sim_strain_stats(&s->cloth, s->scratch, &max_strain, &p99);
    keep_good(s, max_strain);
    s->excess_good = strain_excess(s, max_strain, p99);
}

static void restore_good(sim *s)
{
    size_t bytes = (size_t)s->cloth.nv * sizeof *s->x_good;
    memcpy(s->cloth.x, s->x_good, bytes);
    memcpy(s->cloth.x_prev, s->x_prev_good, bytes);
    s->ops->upload(s->backend, s);
}

/* x_prev, which holds the velocity as the last step's move, made the move of a step of another
   length (a frame of `from` steps to one of `to`): the same velocity. Attached vertices too (the
   driver places them; their x_prev is only read as their previous place). */
static void restep_velocity(sim *s, int from, int to)
{
    float r = (float)from / (float)to;
    for (int i = 0; i < s->cloth.nv; i++)
        for (int d = 0; d < 3; d++)
            s->cloth.x_prev[i][d] =
                s->cloth.x[i][d] - (s->cloth.x[i][d] - s->cloth.x_prev[i][d]) * r;
    s->ops->upload(s->backend, s);
}

/* The time a strain retry must fit in: the smaller of the two budgets (0: none). */
static double retry_budget(const sim_desc *d)
{
    double r = d->retry_budget_ms > 0.0f ? d->retry_budget_ms : 0.0;
    double f = d->frame_budget_ms > 0.0f ? d->frame_budget_ms : 0.0;
    return r > 0.0 && (f <= 0.0 || r < f) ? r : f;
}

/* The frame budget cut an attempt's settle rounds: it ran every round it was allowed, fewer than
   the solver's, and ended over the strain the rounds settle to (cloth.h). */
static int settle_cut(const sim_frame_stats *st, int allowed, float max_strain)
{
    return allowed < SIM_SETTLE_ROUNDS / SIM_SETTLE_BATCH &&
           st->settle_rounds >= allowed * SIM_SETTLE_BATCH && max_strain > SIM_SETTLE_STRAIN;
}

/* The stage times of every attempt of a frame add up. */
static void add_stage_times(sim_frame_stats *sum, const sim_frame_stats *st)
{
    sum->ms_feature_points += st->ms_feature_points;
    sum->ms_contacts += st->ms_contacts;
    sum->ms_iterations += st->ms_iterations;
}

static void set_stage_times(sim_frame_stats *st, const sim_frame_stats *sum)
{
    st->ms_feature_points = sum->ms_feature_points;
    st->ms_contacts = sum->ms_contacts;
    st->ms_iterations = sum->ms_iterations;
}

static int set_body(sim *s, const float *xyz, int nv, const int32_t *tris, int nt, sim_reject *why)
{
    int r = sim_body_validate(xyz, nv, tris, nt, why);
    if (r < 0)
        return r;
    if (nv > s->desc.max_body_vertices || nt > s->desc.max_body_triangles)
        return sim_reject_set(why, SIM_ERR_TOO_LARGE, "body of %d vertices, %d triangles > %d, %d",
                              nv, nt, s->desc.max_body_vertices, s->desc.max_body_triangles);
    for (int a = 0; a < s->cloth.num_attachments; a++)
        if (s->cloth.attachments[a].body_triangle >= nt)
            return sim_reject_set(why, SIM_ERR_TOPOLOGY,
                                  "attachment %d needs body triangle %d; body has %d", a,
                                  s->cloth.attachments[a].body_triangle, nt);
    r = sim_collider_set_body(s->collider, xyz, nv, tris, nt);
    if (r < 0 && r != -SIM_ERR_TOPOLOGY)
        return sim_reject_set(why, r == -SIM_ERR_DEGENERATE ? SIM_ERR_DEGENERATE : SIM_ERR_BACKEND,
                              "body rejected by the collider: %s", sim_error_text(r));
    body_store(&s->body, xyz, nv, tris, nt);
    s->body.stored++;
    if (s->body.stored == 1) { /* the body the garment was made on: for re-dressing (carry) */
        memcpy(s->body_first, s->body.v, (size_t)nv * sizeof *s->body_first);
        s->first_nv = nv;
        s->first_nt = nt;
    }
    body_attachment_normals(&s->body, s->cloth.attachments, s->cloth.num_attachments);
    if (r == -SIM_ERR_TOPOLOGY)
        s->body.have_prev = 0;
    sim_follow_motion(s);
    return 0;
}

/* The garment as made, moved rigidly as its attachments moved since the body it was made on
   (Horn's fit, follow.c): no spring is stretched, whatever the pose. 0, or -1 without three
   attachments or with another body topology. */
static int redress_rigid(sim *s)
{
    int na = s->cloth.num_attachments;
    if (na < 3 || s->first_nv != s->body.nv || s->first_nt != s->body.nt)
        return -1;
    double(*p)[3] = s->follow_pq, (*q)[3] = s->follow_pq + na;
    for (int a = 0; a < na; a++) {
        const sim_attachment *at = &s->cloth.attachments[a];
        const int32_t *t = s->body.tris[at->body_triangle];
        for (int d = 0; d < 3; d++) {
            p[a][d] = q[a][d] = 0.0;
            for (int k = 0; k < 3; k++) {
                p[a][d] += (double)at->bary[k] * s->body_first[t[k]][d];
                q[a][d] += (double)at->bary[k] * s->body.v[t[k]][d];
            }
        }
    }
    float m[12];
    if (sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, na, 1.0, m) != 0)
        return -1;
    for (int i = 0; i < s->cloth.nv; i++) {
        const float *x = s->x_first[i];
        for (int r = 0; r < 3; r++)
            s->cloth.x[i][r] =
                m[r * 4] * x[0] + m[r * 4 + 1] * x[1] + m[r * 4 + 2] * x[2] + m[r * 4 + 3];
        s->cloth.x[i][3] = x[3];
    }
    return 0;
}

/* No attempt solved the frame: the last good cloth (restored) carried by the body from its last
   frame to this one, at rest in it (a velocity that diverged is not kept). When that cloth is
   itself stretched past SIM_CARRY_MAX_STRAIN (a bad state the solver cannot leave), the garment
   is dressed again: the garment as made, moved rigidly with its attachments (a garment without
   them: carried point by point from the body it was made on). 0, or -1 when there is no last
   body frame to carry from (the cloth stays as it was). */
static int carry_or_redress(sim *s)
{
    if (sim_carry_points(s->carry, &s->body, s->cloth.x, s->cloth.nv) < 0)
        return -1;
    float max_strain, p99;
    sim_strain_stats(&s->cloth, s->scratch, &max_strain, &p99);
    if (!(max_strain <= SIM_CARRY_MAX_STRAIN) && redress_rigid(s) != 0 &&
        s->first_nv == s->body.nv && s->first_nt == s->body.nt) {
        memcpy(s->cloth.x, s->x_first, (size_t)s->cloth.nv * sizeof *s->cloth.x);
        sim_carry_between(s->carry, (const float(*)[4])s->body_first, (const float(*)[4])s->body.v,
                          (const int32_t(*)[4])s->body.tris, s->body.nv, s->body.nt, s->cloth.x,
                          s->cloth.nv);
    }
    return 0;
}

/* First the garment's moving frame, which stretches nothing (recover.c), then the carry point by
   point (a garment without a moving frame). After SIM_CARRY_REDRESS_RUN frames carried in a row
   the last good cloth is one the solver cannot leave: the garment is dressed again as made. */
static int carry_good(sim *s)
{
    if (s->carried_run >= SIM_CARRY_REDRESS_RUN && redress_rigid(s) == 0) {
        s->carried_run = 0;
    } else if (sim_recover_rigid(s) != 0 && carry_or_redress(s) != 0) {
        return -1;
    }
    memcpy(s->cloth.x_prev, s->cloth.x, (size_t)s->cloth.nv * sizeof *s->cloth.x_prev);
    s->ops->upload(s->backend, s);
    return 0;
}

/* What is published is measured: its strain (given) and how much of it is inside the body. */
static void measure_published(sim *s, float max_strain, float p99, sim_frame_stats *st)
{
    st->max_strain = max_strain;
    st->p99_strain = p99;
    float depth = 0.0f;
    sim_collider_penetration(s->collider, (const float(*)[4])s->cloth.x, s->cloth.nv, SIM_PEN_TOL_M,
                             &st->penetrating, &depth);
    st->max_pen_mm = depth * 1000.0f;
}

/* sim_start's and sim_step's first part: the stats cleared, the body frame taken in (validated,
   stored, the collider on it). 0, or a refusal that changed nothing. */
static int frame_begin(sim *s, const float *body_xyz, int nv, const int32_t *body_tris, int nt,
                       sim_frame_stats *st, sim_reject *why)
{
    memset(st, 0, sizeof *st);
    if (!s)
        return sim_reject_set(why, SIM_ERR_ARG, "sim is NULL");
    return set_body(s, body_xyz, nv, body_tris, nt, why);
}

int sim_start(sim *s, const float *body_xyz, int nv, const int32_t *body_tris, int nt,
              sim_frame_stats *st, sim_reject *why)
{
    sim_frame_stats local;
    if (!st)
        st = &local;
    if (s && s->frame > 0) {
        memset(st, 0, sizeof *st);
        return sim_reject_set(why, SIM_ERR_ARG, "sim_start after %ld frames stepped", s->frame);
    }
    double t0 = now_ms();
    int r = frame_begin(s, body_xyz, nv, body_tris, nt, st, why);
    if (r < 0)
        return r;
    double t1 = now_ms();
    float max_strain, p99;
    sim_strain_stats(&s->cloth, s->scratch, &max_strain, &p99);
    measure_published(s, max_strain, p99, st);
    st->state = SIM_STATE_OK;
    st->ms_bvh = (float)(t1 - t0);
    st->ms_metrics = (float)(now_ms() - t1);
    st->ms_total = (float)(now_ms() - t0);
    return 0;
}

/* An attempt set aside during a frame's retries (sim_step): the good one nearest the strain
   goals, or the least pinched. iters 0: none yet. */
typedef struct kept_attempt {
    float (*x)[4], (*x_prev)[4];
    float strain, p99;
    int iters;
} kept_attempt;

static void keep_attempt(const sim *s, kept_attempt *k, float strain, float p99, int iters)
{
    size_t bytes = (size_t)s->cloth.nv * sizeof *k->x;
    memcpy(k->x, s->cloth.x, bytes);
    memcpy(k->x_prev, s->cloth.x_prev, bytes);
    k->strain = strain;
    k->p99 = p99;
    k->iters = iters;
}

static void take_attempt(sim *s, const kept_attempt *k, float *strain, float *p99, int *iters)
{
    size_t bytes = (size_t)s->cloth.nv * sizeof *k->x;
    memcpy(s->cloth.x, k->x, bytes);
    memcpy(s->cloth.x_prev, k->x_prev, bytes);
    s->ops->upload(s->backend, s);
    *strain = k->strain;
    *p99 = k->p99;
    *iters = k->iters;
}

/* A budget (ms, 0: none) leaves no time for another attempt twice as long as the last (started
   at ta; t0: the frame's start; now: that attempt's end). */
static int no_time_for_retry(double budget, double t0, double ta, double now)
{
    return budget > 0.0 && (now - t0) + 2.0 * (now - ta) > budget;
}

/* A live frame's deadline (sim_desc.frame_budget_ms) is spent for a retry; a garment's first
   step has no deadline. */
static int frame_spent(const sim *s, double t0, double ta, double now)
{
    return s->frame > 0 && no_time_for_retry(s->desc.frame_budget_ms, t0, ta, now);
}

int sim_step(sim *s, const float *body_xyz, int nv, const int32_t *body_tris, int nt,
             sim_frame_stats *st, sim_reject *why)
{
    sim_frame_stats local;
    if (!st)
        st = &local;
    double t0 = now_ms();
    int r = frame_begin(s, body_xyz, nv, body_tris, nt, st, why);
    if (r < 0) {
        st->state = SIM_STATE_OK; /* nothing simulated; the last good cloth stands */
        return r;
    }
    double t1 = now_ms();
    st->ms_bvh = (float)(t1 - t0);

    /* a diverged attempt is retried from the last good state with twice the iterations; so is
       one whose strain misses the goals, and the good attempt nearest them is published */
    int iters = s->desc.iterations, ok = 0;
    int strain_retry = !(s->excess_good > 1.0f);
    float max_strain = 0.0f, p99 = 0.0f;
    float excess = 0.0f, best_excess = INFINITY;
    kept_attempt best = {s->x_best, s->x_prev_best, 0.0f, 0.0f, 0};
    kept_attempt pinch = {s->x_pinch, s->x_prev_pinch, INFINITY, 0.0f, 0};
    sim_frame_stats sum = {0};
    double budget = retry_budget(&s->desc);
    int late = 0; /* the frame budget cut settle rounds or a strain retry */
    for (int attempt = 0; attempt <= SIM_MAX_RETRIES; attempt++) {
        /* the good state's velocity is its last step's move: for another step, that step's */
        if (iters != s->iters_good)
            restep_velocity(s, s->iters_good, iters);
        double ta = now_ms();
        int allowed = sim_budget_settle_tests(&s->budget, s->desc.frame_budget_ms, ta - t0, iters,
                                              SIM_SETTLE_ROUNDS / SIM_SETTLE_BATCH);
        s->settle_tests_max = allowed;
        r = s->ops->frame(s->backend, s, iters, st);
        sim_budget_learn_attempt(&s->budget, st, iters);
        add_stage_times(&sum, st);
        int diverged = r == 0 ? state_diverged(s, iters, &max_strain, &p99) : 1;
        int good = !diverged;
        if (diverged == 2 && max_strain < pinch.strain) /* published if no attempt is good */
            keep_attempt(s, &pinch, max_strain, p99, iters);
        excess = strain_excess(s, max_strain, p99);
        late |= good && settle_cut(st, allowed, max_strain);
        /* no time left for a retry twice as long as this attempt: publish the nearest so far */
        double spent = now_ms();
        int no_time = no_time_for_retry(budget, t0, ta, spent);
        late |= good && no_time && excess > 1.0f && strain_retry && attempt < SIM_MAX_RETRIES &&
                s->desc.frame_budget_ms > 0.0f;
        if (good && (!(excess > 1.0f) || !strain_retry || attempt == SIM_MAX_RETRIES || no_time) &&
            !(best_excess < excess)) {
            ok = 1;
            break;
        }
        if (good && excess < best_excess) {
            keep_attempt(s, &best, max_strain, p99, iters);
            best_excess = excess;
        }
        if (good && no_time)
            break; /* an earlier attempt was nearer the goals: it is published below */
        /* restore the last good state and retry with smaller steps */
        restore_good(s);
        if (!good && frame_spent(s, t0, ta, spent))
            break; /* no time for a retry twice as long: the frame is carried (below) */
        if (attempt < SIM_MAX_RETRIES) {
            st->retries++;
            st->strain_retries += good;
            iters *= 2;
        }
    }
    /* an earlier attempt was good and nearer the goals than the last (or the last diverged); or
       none was good and one only pinched (cloth.h, SIM_PINCH_SPRINGS): published as it is, its
       strain said, rather than the last good cloth carried (docs/sim.md, "Stability") */
    const kept_attempt *kept = ok ? NULL : best.iters > 0 ? &best : pinch.iters > 0 ? &pinch : NULL;
    if (kept) {
        take_attempt(s, kept, &max_strain, &p99, &iters);
        excess = kept == &best ? best_excess : strain_excess(s, max_strain, p99);
        ok = 1;
    }
    set_stage_times(st, &sum);
    st->iterations_used = iters;
    s->frame++;
    double t2 = now_ms();
    int carried = !ok && carry_good(s) == 0;
    s->carried_run = carried ? s->carried_run + 1 : 0;
    /* What is published is measured, whatever made it: solved, carried or kept. */
    if (!ok)
        sim_strain_stats(&s->cloth, s->scratch, &max_strain, &p99);
    measure_published(s, max_strain, p99, st);
    if (!ok && !carried) {
        st->state = SIM_STATE_DIVERGED;
        st->ms_total = (float)(now_ms() - t0);
        return sim_reject_set(why, SIM_ERR_DIVERGED,
                              "frame %ld: diverged with %d, and up to %d iterations; the last "
                              "good cloth is kept",
                              s->frame, s->desc.iterations, iters);
    }
    st->state = carried       ? SIM_STATE_CARRIED
                : late        ? SIM_STATE_SETTLING
                : st->retries ? SIM_STATE_RECOVERED
                              : SIM_STATE_OK;
    if (carried) {
        excess = strain_excess(s, max_strain, p99);
        iters = s->desc.iterations;
    }
    keep_good(s, max_strain); /* the strain of this very state, measured by state_diverged */
    s->excess_good = excess;
    s->iters_good = iters;
    double t3 = now_ms();
    st->ms_metrics = (float)(t3 - t2);
    st->ms_total = (float)(t3 - t0);
    sim_budget_learn_tail(&s->budget, st);
    return 0;
}

int sim_vertex_count(const sim *s)
{
    return s->cloth.nv;
}

int sim_triangle_count(const sim *s)
{
    return s->cloth.nt;
}

const float *sim_positions(const sim *s)
{
    return &s->cloth.x[0][0];
}

void sim_copy_positions(const sim *s, float *xyz)
{
    for (int i = 0; i < s->cloth.nv; i++)
        for (int d = 0; d < 3; d++)
            xyz[i * 3 + d] = s->cloth.x[i][d];
}

void sim_copy_velocities(const sim *s, float *vel)
{
    float inv_dt = (float)s->iters_good / s->desc.frame_dt_s;
    for (int i = 0; i < s->cloth.nv; i++)
        for (int d = 0; d < 3; d++)
            vel[i * 3 + d] = (s->cloth.x[i][d] - s->cloth.x_prev[i][d]) * inv_dt;
}

const int32_t *sim_triangles(const sim *s)
{
    return s->tris3;
}

const char *sim_device_name(const sim *s)
{
    return s->ops->device_name(s->backend);
}

const sim_desc *sim_get_desc(const sim *s)
{
    return &s->desc;
}

void sim_debug_set_vertex(sim *s, int i, float x, float y, float z)
{
    if (i < 0 || i >= s->cloth.nv)
        return;
    s->cloth.x[i][0] = x;
    s->cloth.x[i][1] = y;
    s->cloth.x[i][2] = z;
    s->ops->upload(s->backend, s);
}

int sim_set_positions(sim *s, const float *xyz, sim_reject *why)
{
    return sim_set_state(s, xyz, NULL, why);
}

int sim_set_state(sim *s, const float *xyz, const float *vel, sim_reject *why)
{
    if (!s || !xyz)
        return sim_reject_set(why, SIM_ERR_ARG, "sim_set_state: NULL");
    for (int i = 0; i < s->cloth.nv * 3; i++)
        if (!isfinite(xyz[i]) || (vel && !isfinite(vel[i])))
            return sim_reject_set(why, SIM_ERR_NOT_FINITE, "%s %d coordinate %d = %g",
                                  isfinite(xyz[i]) ? "velocity" : "position", i / 3, i % 3,
                                  isfinite(xyz[i]) ? vel[i] : xyz[i]);
    /* Verlet's velocity is the last step's move: this sim's step */
    float dt = s->desc.frame_dt_s / (float)s->desc.iterations;
    for (int i = 0; i < s->cloth.nv; i++) {
        if (s->cloth.x[i][3] == 0.0f)
            continue; /* attached vertices stay where the body puts them */
        for (int d = 0; d < 3; d++) {
            s->cloth.x[i][d] = xyz[i * 3 + d];
            s->cloth.x_prev[i][d] = xyz[i * 3 + d] - (vel ? vel[i * 3 + d] * dt : 0.0f);
        }
    }
    save_good(s);
    s->iters_good = s->desc.iterations;
    return s->ops->upload(s->backend, s);
}
