/* The C reference backend: the per-frame work of both solver variants on the host, one OpenMP
 * team per frame, one worksharing loop per spring colour. */
#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cloth.h"
#include "passes.h"
#include "frame_settings.h"
#include "phases.h"

typedef struct c_state {
    float (*acc)[4];      /* seed: spring forces times dt^2 / m, per vertex */
    float (*att_from)[4]; /* attached vertices at the start and end of the frame */
    float (*att_to)[4];
    int32_t *att_order; /* attachments by vertex (place_attachments) */
    sim_phases phases;  /* the tryon iterations' passes (phases.h) */
    /* per settle test of a frame: the largest stretch strain, as float bits (non-negative
       floats order as their bits), maxed over the threads */
    _Atomic uint32_t settle[SIM_SETTLE_ROUNDS / SIM_SETTLE_BATCH];
    int settle_rounds; /* run in the last frame */
    /* the frame's start in the team (stage_start): feature points moved, and the fastest cloth
       point's squared travel in a step as float bits (non-negative floats order as their bits) */
    atomic_int fp_moved;
    _Atomic uint32_t travel2;
    /* the support hierarchy (cloth.h), per vertex: its contact face's up when it rests on the
       body, its level, and the vertices in breadth-first order */
    float *rest_up;
    int32_t *level;
    int32_t *queue;
    char name[64];
} c_state;

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static void c_destroy(void *state)
{
    c_state *c = state;
    if (!c)
        return;
    free(c->acc);
    free(c->att_from);
    free(c->att_to);
    free(c->att_order);
    free(c->rest_up);
    free(c->level);
    free(c->queue);
    sim_phases_free(&c->phases);
    free(c);
}

static int c_create(struct sim *s, void **state, char *err, size_t err_size)
{
    c_state *c = calloc(1, sizeof *c);
    int na = s->cloth.num_attachments + 1;
    if (c) {
        c->acc = calloc((size_t)s->cloth.nv, sizeof *c->acc);
        c->att_from = calloc((size_t)na, sizeof *c->att_from);
        c->att_to = calloc((size_t)na, sizeof *c->att_to);
        c->att_order = calloc((size_t)na, sizeof *c->att_order);
        c->rest_up = calloc((size_t)s->cloth.nv + 1, sizeof *c->rest_up);
        c->level = calloc((size_t)s->cloth.nv + 1, sizeof *c->level);
        c->queue = calloc((size_t)s->cloth.nv + 1, sizeof *c->queue);
        sim_phases_init(&c->phases);
    }
    if (!c || !c->acc || !c->att_from || !c->att_to || !c->att_order || !c->rest_up || !c->level ||
        !c->queue) {
        snprintf(err, err_size, "C backend: out of memory for %d vertices", s->cloth.nv);
        c_destroy(c);
        return -SIM_ERR_NO_MEMORY;
    }
    /* the attachments by vertex (a stable insertion sort: a garment has a row or two of them), so
     * that each chunk of vertices places its own */
    const sim_attachment *att = s->cloth.attachments;
    for (int a = 0; a < s->cloth.num_attachments; a++) {
        int k = a;
        for (; k > 0 && att[c->att_order[k - 1]].vertex > att[a].vertex; k--)
            c->att_order[k] = c->att_order[k - 1];
        c->att_order[k] = a;
    }
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    snprintf(c->name, sizeof c->name, "C reference (%d threads)", threads);
    *state = c;
    return 0;
}

/* This thread's share [b, e) of n items. */
static void thread_range(int n, int *b, int *e)
{
    int t = 0, nt = 1;
#ifdef _OPENMP
    t = omp_get_thread_num();
    nt = omp_get_num_threads();
#endif
    *b = (int)((long)n * t / nt);
    *e = (int)((long)n * (t + 1) / nt);
}

/* The first of the attachments (att_order: by vertex) on a vertex >= vb. */
static int first_attachment(const struct sim *s, const c_state *cs, int vb)
{
    const sim_attachment *att = s->cloth.attachments;
    int lo = 0, hi = s->cloth.num_attachments;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (att[cs->att_order[mid]].vertex < vb)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Attached vertices follow their body triangle: x = sum b_k v_k + offset n, from where they
 * were to where frame k puts them, spread over the steps of the frame as the body moved. Those
 * on vertices [vb, ve). */
static void attachment_targets(struct sim *s, c_state *cs, int vb, int ve)
{
    const sim_body *b = &s->body;
    for (int k = first_attachment(s, cs, vb);
         k < s->cloth.num_attachments && s->cloth.attachments[cs->att_order[k]].vertex < ve; k++) {
        int a = cs->att_order[k];
        const sim_attachment *at = &s->cloth.attachments[a];
        const int32_t *t = b->tris[at->body_triangle];
        for (int d = 0; d < 3; d++) {
            cs->att_from[a][d] = s->cloth.x[at->vertex][d];
            cs->att_to[a][d] = at->bary[0] * b->v[t[0]][d] + at->bary[1] * b->v[t[1]][d] +
                               at->bary[2] * b->v[t[2]][d] +
                               at->offset_m * b->n[at->body_triangle][d];
        }
    }
}

/* The attachments on vertices [vb, ve) to step it of iters (att_order: by vertex). */
static void place_attachments(struct sim *s, const c_state *cs, int it, int iters, int vb, int ve)
{
    const sim_attachment *att = s->cloth.attachments;
    float u = (float)(it + 1) / (float)iters;
    for (int k = first_attachment(s, cs, vb);
         k < s->cloth.num_attachments && att[cs->att_order[k]].vertex < ve; k++) {
        int a = cs->att_order[k], v = att[a].vertex;
        for (int d = 0; d < 3; d++) {
            s->cloth.x_prev[v][d] = s->cloth.x[v][d];
            s->cloth.x[v][d] = cs->att_from[a][d] + u * (cs->att_to[a][d] - cs->att_from[a][d]);
        }
    }
}

/* m into the float bits at *max when larger (non-negative floats order as their bits). */
static void atomic_max_bits(_Atomic uint32_t *max, float m)
{
    uint32_t bits, seen = atomic_load(max);
    memcpy(&bits, &m, sizeof bits);
    while (bits > seen && !atomic_compare_exchange_weak(max, &seen, bits))
        ;
}

static float bits_float(_Atomic uint32_t *bits)
{
    uint32_t b = atomic_load(bits);
    float f;
    memcpy(&f, &b, sizeof f);
    return f;
}

/* Chunk sizes worth a claim of their own (sim_phase_claim): a few microseconds of work. */
#define GRAIN_SPRINGS  256
#define GRAIN_VERTICES 512

/* The phases of a frame (sim_phases_reset's count): each stage of the frame's list
   (kernels/solver_params.h) that runs, its phases (one per pass, a spring pass one per colour). */
static int stage_phases(int st, const sim_solver_params *p)
{
    return st == SIM_STAGE_SPRINGS   ? p->num_colors
           : st == SIM_STAGE_SWEEP   ? p->num_stretch_colors
           : st == SIM_STAGE_SUPPORT ? 2
                                     : 1;
}

static int tryon_phases(const sim_solver_params *p)
{
    int n = 0;
    for (int b = 0; b < SIM_BLOCKS; b++)
        for (int rep = 0; rep < sim_block_repeats(b, p); rep++)
            for (int k = sim_block_start[b]; k < sim_block_start[b + 1]; k++)
                if (sim_stage_runs(sim_frame_stages[k], b, rep, p))
                    n += stage_phases(sim_frame_stages[k], p);
    return n;
}

/* One phase: springs [first, last) of one colour, XPBD (alpha) or the strain limit (!alpha). */
static void springs_phase(sim_phases *ph, sim_phase_cursor *cur, sim_cloth *c, int first, int last,
                          const float *alpha, float limit)
{
    int b, e;
    while (sim_phase_claim(ph, cur, last - first, GRAIN_SPRINGS, &b, &e)) {
        if (alpha)
            sim_project_springs(c->x, c->ends, c->rest, c->kind, alpha, first + b, first + e);
        else
            sim_strain_limit(c->x, c->ends, c->rest, c->kind, first + b, first + e, limit);
    }
    sim_phase_end(ph, cur, 0);
}

/* One Gauss-Seidel sweep of the strain limit over the stretch colours. */
static void strain_limit_sweep(sim_phases *ph, sim_phase_cursor *cur, sim_cloth *c, float limit)
{
    for (int col = 0; col < c->num_stretch_colors; col++)
        springs_phase(ph, cur, c, c->color_start[col], c->color_start[col + 1], NULL, limit);
}

/* Per vertex: the tethers (anchors are attached and do not move), the contacts, then for what
 * follows: the post-stabilisation's bracket (end: this round's, begin: the next round's). */
static void vertex_phase(struct sim *s, sim_phases *ph, sim_phase_cursor *cur, float limit,
                         int post_end, int post_begin, int wake)
{
    sim_cloth *c = &s->cloth;
    int b, e;
    while (sim_phase_claim(ph, cur, c->nv, GRAIN_VERTICES, &b, &e)) {
        sim_tethers(c->x, c->tether_anchor, c->tether_len, b, e, limit);
        if (post_end)
            sim_post_end(c->x, c->x_prev, b, e);
        sim_collider_research(s->collider, (const float(*)[4])c->x, b, e);
        sim_collider_resolve(s->collider, c->x, c->x_prev, b, e);
        if (post_begin)
            sim_post_begin(c->x, c->x_prev, b, e);
    }
    sim_phase_end(ph, cur, wake);
}

/* The support hierarchy (cloth.h), for a garment without attachments: which vertices rest on an
 * upward face (all threads), then one thread picks the highest as the root, walks the levels from
 * it and pulls each vertex to within the limit of its parents, level by level (inside the
 * post-stabilisation's bracket). */
static void support_hierarchy(struct sim *s, c_state *cs, sim_phases *ph, sim_phase_cursor *cur,
                              float limit)
{
    sim_cloth *c = &s->cloth;
    int b, e;
    while (sim_phase_claim(ph, cur, c->nv, GRAIN_VERTICES, &b, &e))
        for (int i = b; i < e; i++)
            cs->rest_up[i] = sim_collider_resting(s->collider, i, c->x[i], SIM_REST_TOL_M);
    sim_phase_end(ph, cur, 0);
    while (sim_phase_claim(ph, cur, 1, 1, &b, &e)) {
        int root = -1;
        for (int i = 0; i < c->nv; i++)
            if (cs->rest_up[i] > 0.0f && (root < 0 || c->x[i][1] > c->x[root][1]))
                root = i;
        int n = sim_support_levels(c, root, cs->level, cs->queue);
        for (int q = 0; q < n; q++)
            sim_support_pull(c->x, c->x_prev, c, cs->level, cs->queue[q], limit);
    }
    sim_phase_end(ph, cur, 0);
}

/* What the stages of one thread share: the frame's place and its decisions (the same in every
   thread: each reads them after the phase that makes them). */
typedef struct frame_walk {
    const sim_solver_params *p;
    sim_phases *ph;
    sim_phase_cursor cur;
    int fast;      /* the cloth travels past the contacts' reach in the frame (sim_frame_fast) */
    float prev;    /* the last settle test's largest strain */
    double t_fp;   /* thread 0: when the start ended, */
    double t_cont; /* and the contact search */
} frame_walk;

/* SIM_STAGE_START, per vertex chunk: the moving frame, the feature points (each vertex's own
 * sweep), the targets of the attachments on those vertices (from where the moving frame put them),
 * and the fastest point's travel. */
static void stage_start(struct sim *s, c_state *cs, frame_walk *w)
{
    sim_cloth *c = &s->cloth;
    int b, e;
    while (sim_phase_claim(w->ph, &w->cur, c->nv, GRAIN_VERTICES, &b, &e)) {
        if (s->follow_on)
            sim_follow(c->x, c->x_prev, b, e, s->follow_m);
        if (s->body.have_prev)
            atomic_fetch_add(&cs->fp_moved,
                             sim_collider_feature_points(s->collider, c->x, c->x_prev, b, e));
        attachment_targets(s, cs, b, e);
        atomic_max_bits(&cs->travel2, sim_step_travel2(c, b, e));
    }
    sim_phase_end(w->ph, &w->cur, 1);
    if (w->cur.thread == 0)
        w->t_fp = now_ms();
}

/* SIM_STAGE_CONTACTS: each thread's part whole (the search shares out its own,
 * sim/find_contacts.c). Contacts are cached for the frame, the body still through its steps (its
 * own motion is carried by the feature points and the moving frame); a point that moves past its
 * clearance (the distance within which the search saw nothing nearer, sim_collider_research) is
 * searched again before its contact response, whether the search found it a triangle or nothing
 * within reach. Whether the cloth moves fast (farther than the reach in the frame: a falling
 * sheet, a hem kicked by a thigh) is decided here for the settle test. */
static void stage_contacts(struct sim *s, c_state *cs, frame_walk *w)
{
    sim_cloth *c = &s->cloth;
    int b, e;
    while (sim_phase_claim(w->ph, &w->cur, c->nv, c->nv, &b, &e))
        sim_collider_find_contacts(s->collider, (const float(*)[4])c->x, b, e);
    sim_phase_end(w->ph, &w->cur, 1);
    if (w->cur.thread == 0)
        w->t_cont = now_ms();
    w->fast = sim_frame_fast(bits_float(&cs->travel2), w->p->iters);
}

/* SIM_STAGE_STEP it, per vertex: Verlet, the attachments placed (the previous phase's tethers
 * were the last to read them). */
static void stage_step(struct sim *s, c_state *cs, frame_walk *w, int it)
{
    sim_cloth *c = &s->cloth;
    int b, e;
    while (sim_phase_claim(w->ph, &w->cur, c->nv, GRAIN_VERTICES, &b, &e)) {
        sim_verlet(c->x, c->x_prev, b, e, w->p->keep, w->p->g);
        place_attachments(s, cs, it, w->p->iters, b, e);
    }
    sim_phase_end(w->ph, &w->cur, 1);
}

/* SIM_STAGE_SETTLE_TEST before settle round rep (cloth.h): the largest stretch strain measured
 * by all; the rounds go on while it is above SIM_SETTLE_STRAIN and the last batch took enough off
 * it. Every thread reads the same maximum after the phase, so all take the same branch. Returns
 * 1 to stop. */
static int stage_settle_test(struct sim *s, c_state *cs, frame_walk *w, int rep)
{
    sim_cloth *c = &s->cloth;
    int nstretch = c->color_start[c->num_stretch_colors], b, e, k = rep / w->p->settle_batch;
    while (sim_phase_claim(w->ph, &w->cur, nstretch, GRAIN_SPRINGS, &b, &e))
        atomic_max_bits(&cs->settle[k],
                        sim_stretch_max((const float(*)[4])c->x, c->ends, c->rest, c->kind, b, e));
    sim_phase_end(w->ph, &w->cur, 1);
    float m = bits_float(&cs->settle[k]);
    if (sim_settle_stop(m, w->prev, k == 0, w->fast, w->p))
        return 1;
    w->prev = m;
    return 0;
}

/* SIM_STAGE_REOPEN before a settle round: the bracket opened (a point the rounds move far, a
 * sheet landing on a sphere, is searched again in the round's contact response). */
static void stage_reopen(struct sim *s, frame_walk *w)
{
    sim_cloth *c = &s->cloth;
    int b, e;
    while (sim_phase_claim(w->ph, &w->cur, c->nv, GRAIN_VERTICES, &b, &e))
        sim_post_begin(c->x, c->x_prev, b, e);
    sim_phase_end(w->ph, &w->cur, 0);
}

/* Stage st of block b, repetition rep. Returns 1 when the frame ends here (a settle test). */
static int run_stage(struct sim *s, c_state *cs, frame_walk *w, int st, int b, int rep)
{
    sim_cloth *c = &s->cloth;
    const sim_solver_params *p = w->p;
    int reps = sim_block_repeats(b, p);
    switch (st) {
    case SIM_STAGE_START:
        stage_start(s, cs, w);
        break;
    case SIM_STAGE_CONTACTS:
        stage_contacts(s, cs, w);
        break;
    case SIM_STAGE_STEP:
        stage_step(s, cs, w, rep);
        break;
    case SIM_STAGE_SPRINGS:
        for (int col = 0; col < c->num_colors; col++)
            springs_phase(w->ph, &w->cur, c, c->color_start[col], c->color_start[col + 1], p->alpha,
                          p->limit);
        break;
    case SIM_STAGE_SWEEP:
        strain_limit_sweep(w->ph, &w->cur, c, p->limit);
        break;
    case SIM_STAGE_VERTICES: {
        /* sleepers woken at the end of the post rounds and of each settle batch */
        int wake = (b == SIM_BLOCK_POST && rep + 1 == reps) ||
                   (b == SIM_BLOCK_SETTLE && (rep + 1) % p->settle_batch == 0);
        vertex_phase(s, w->ph, &w->cur, p->limit, sim_vertices_close(b),
                     sim_vertices_open(b, rep, p), wake);
        if (b == SIM_BLOCK_SETTLE && w->cur.thread == 0)
            cs->settle_rounds = rep + 1;
        break;
    }
    case SIM_STAGE_HIERARCHY: {
        int e0, e1;
        while (sim_phase_claim(w->ph, &w->cur, 1, 1, &e0, &e1))
            sim_strain_hierarchy(c->x, c->x_prev, c->hier_vertex, c->hier_parent_start,
                                 c->hier_parent, c->hier_rest, 0,
                                 c->hier_level_start[c->hier_levels], p->limit);
        sim_phase_end(w->ph, &w->cur, 0);
        break;
    }
    case SIM_STAGE_SUPPORT:
        support_hierarchy(s, cs, w->ph, &w->cur, p->limit);
        break;
    case SIM_STAGE_SETTLE_TEST:
        return stage_settle_test(s, cs, w, rep);
    case SIM_STAGE_REOPEN:
        stage_reopen(s, w);
        break;
    default:
        break;
    }
    return 0;
}

/* The tryon solver's frame: the stages of kernels/solver_params.h in order, each shared out in
 * phases among one OpenMP team (one team a frame: each team a thread joins after sleeping costs
 * it a wake-up, 30-60 us with OMP_WAIT_POLICY=passive); the stages' ms into st.
 *
 * Post-stabilisation of the strain limit (docs/sim.md): one Gauss-Seidel sweep per step moves a
 * correction about one spring, so a long region stretched a little stays stretched. The
 * hierarchy from the attachments outward removes it in one pass, a sweep settles the springs
 * within a level, the tethers hold; positions only, the velocities x - x_prev are kept (x_prev
 * moves with x), then the contacts as in every step. Then SIM_POST_ROUNDS more rounds of sweep,
 * tethers and contacts: the last contact push undoes strain where the body moved into the cloth
 * in the last step (about the relative speed times the step: 20 % at 25 steps in the walk,
 * docs/sim.md). Then the settle rounds. */
static void iterations_tryon(struct sim *s, c_state *cs, const sim_solver_params *p,
                             sim_frame_stats *st)
{
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    /* one phase per pass, shared out in chunks (phases.h); out of memory: one thread */
    if (sim_phases_reset(&cs->phases, threads, tryon_phases(p)) < 0)
        threads = 1, sim_phases_reset(&cs->phases, 1, 0);
    sim_phases *ph = &cs->phases;
    for (int k = 0; k < SIM_SETTLE_ROUNDS / SIM_SETTLE_BATCH; k++)
        atomic_store(&cs->settle[k], 0u);
    cs->settle_rounds = 0;
    atomic_store(&cs->fp_moved, 0);
    atomic_store(&cs->travel2, 0u);
    double t0 = now_ms(), t_fp = t0, t_cont = t0;
#pragma omp parallel num_threads(threads)
    {
        int t = 0, nt = 1;
#ifdef _OPENMP
        t = omp_get_thread_num();
        nt = omp_get_num_threads();
#endif
        frame_walk w = {.p = p, .ph = ph, .t_fp = t0, .t_cont = t0};
        sim_phase_cursor_init(&w.cur, t, nt < ph->threads ? nt : ph->threads);
        int stop = 0;
        for (int b = 0; b < SIM_BLOCKS && !stop; b++)
            for (int rep = 0; rep < sim_block_repeats(b, p) && !stop; rep++)
                for (int k = sim_block_start[b]; k < sim_block_start[b + 1] && !stop; k++)
                    if (sim_stage_runs(sim_frame_stages[k], b, rep, p))
                        stop = run_stage(s, cs, &w, sim_frame_stages[k], b, rep);
        if (t == 0)
            t_fp = w.t_fp, t_cont = w.t_cont;
    }
    double t1 = now_ms();
    st->feature_points_moved = atomic_load(&cs->fp_moved);
    st->ms_feature_points = (float)(t_fp - t0);
    st->ms_contacts = (float)(t_cont - t_fp);
    st->ms_iterations = (float)(t1 - t_cont);
    st->settle_rounds = cs->settle_rounds;
}

static void iterations_seed(struct sim *s, c_state *cs, int iters, float dt, float keep,
                            const float g[3], float *ms_contacts)
{
    sim_cloth *c = &s->cloth;
    float(*acc)[4] = cs->acc;
    double t_contacts = 0.0;
#pragma omp parallel
    {
        int vb, ve;
        thread_range(c->nv, &vb, &ve);
        for (int it = 0; it < iters; it++) {
            memset(acc + vb, 0, (size_t)(ve - vb) * sizeof *acc);
#pragma omp barrier
            for (int col = 0; col < c->num_colors; col++) {
#pragma omp for schedule(static)
                for (int s0 = c->color_start[col]; s0 < c->color_start[col + 1]; s0 += 64) {
                    int s1 = s0 + 64 < c->color_start[col + 1] ? s0 + 64 : c->color_start[col + 1];
                    sim_spring_forces((const float(*)[4])c->x, (const float(*)[4])c->x_prev,
                                      (const int32_t(*)[2])c->ends, c->rest, c->kind, c->k, s0, s1,
                                      dt, 0.02f, acc);
                }
            }
            sim_verlet_forces(c->x, c->x_prev, (const float(*)[4])acc, vb, ve, keep, g);
#pragma omp single
            place_attachments(s, cs, it, iters, 0, c->nv);
            for (int col = 0; col < c->num_colors; col++) {
#pragma omp for schedule(static)
                for (int s0 = c->color_start[col]; s0 < c->color_start[col + 1]; s0 += 64) {
                    int s1 = s0 + 64 < c->color_start[col + 1] ? s0 + 64 : c->color_start[col + 1];
                    sim_clamp_springs(c->x, c->ends, c->rest, c->kind, s0, s1, SIM_KINDS_PROVOT,
                                      SIM_PROVOT_TAU);
                }
            }
            /* seed 000: the S-BVH is searched in every iteration */
            double t0 = now_ms();
            sim_collider_find_contacts(s->collider, (const float(*)[4])c->x, vb, ve);
#pragma omp barrier
#pragma omp master
            t_contacts += now_ms() - t0;
            sim_collider_resolve(s->collider, c->x, c->x_prev, vb, ve);
#pragma omp barrier
        }
    }
    *ms_contacts = (float)t_contacts;
}

static int c_frame(void *state, struct sim *s, int iters, sim_frame_stats *st)
{
    c_state *cs = state;
    sim_cloth *c = &s->cloth;
    sim_solver_params p;
    sim_solver_params_fill(s, iters, &p);
    if (s->desc.solver == SIM_SOLVER_TRYON) {
        iterations_tryon(s, cs, &p, st);
        return 0;
    }
    double t0 = now_ms();
    st->feature_points_moved = 0;
    if (s->follow_on)
        sim_follow(c->x, c->x_prev, 0, c->nv, s->follow_m);
    if (s->body.have_prev)
        st->feature_points_moved =
            sim_collider_feature_points(s->collider, c->x, c->x_prev, 0, c->nv);
    attachment_targets(s, cs, 0, c->nv);
    double t1 = now_ms();
    st->ms_feature_points = (float)(t1 - t0);
    float ms_contacts = 0.0f;
    iterations_seed(s, cs, iters, p.dt, p.keep, p.g, &ms_contacts);
    st->ms_contacts = ms_contacts;
    st->ms_iterations = (float)(now_ms() - t1) - ms_contacts;
    return 0;
}

static int c_upload(void *state, const struct sim *s)
{
    (void)state;
    (void)s;
    return 0; /* the host copy is the state */
}

static const char *c_device_name(const void *state)
{
    return ((const c_state *)state)->name;
}

const sim_backend_ops sim_backend_c = {
    .name = "c",
    .create = c_create,
    .destroy = c_destroy,
    .frame = c_frame,
    .upload = c_upload,
    .device_name = c_device_name,
};
