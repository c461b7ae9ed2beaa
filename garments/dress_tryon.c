/* tryon's own dressing (docs/garments.md "tryon's dressing"): sim/'s XPBD in small steps
 * (Verlet prediction, one Gauss-Seidel sweep of the distance constraints and of the strain limit
 * per step), the seams as zero-length constraints whose target length shrinks to 0 over the
 * seaming time, exact cloth-body contacts from sim/'s BVH (sim_collider_*), gravity only once
 * every seam is closed, then draping steps and a few position-only rounds (strain limit, seams,
 * contacts) that leave the velocities alone. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "tryon_clock.h"
#include "bodyfit.h"
#include "cloth.h"
#include "passes.h"
#include "cloth_cloth.h"
#include "dress_internal.h"
#include "bending.h"
#include "strain_held.h"

#define GAR_GRAVITY_M_S2 9.81f
/* Seams close no faster than this (m/s): the panels' interiors follow their edges. */
#define GAR_TRYON_SEAM_SPEED_M_S 1.0f
/* Seaming takes at least this long (s) and at most desc->max_seaming_s. */
#define GAR_TRYON_MIN_SEAMING_S 0.05f
/* Velocity damping rates (1/s): strong while seaming (nothing holds the panels), light while
 * draping (the garment must still settle in a few tenths of a second). */
#define GAR_TRYON_SEAM_DAMPING_PER_S  20.0f
#define GAR_TRYON_DRAPE_DAMPING_PER_S 6.0f
/* Contacts searched every this many steps (the reach, 3 cm, covers the motion in between). */
#define GAR_TRYON_CONTACT_EVERY 4
/* Cloth-cloth between panels every this many steps, pushing to this distance. */
#define GAR_TRYON_CC_EVERY     8
#define GAR_TRYON_CC_THICKNESS 0.003f
/* Gravity comes on once every joint is this close (the seam gap target; the contacts, applied
 * after the seams in each step, hold a few joints about a millimetre open where the body lies
 * between them, and the last rounds close them further). */
#define GAR_TRYON_SEAMED_M 0.002f
/* ... or once the widest gap, under this, has stopped closing over this many steps: where the
 * body lies between the two sides of a joint (the dress's shoulder seam at the neck) the contacts
 * hold it a few millimetres open; the last rounds close it (seams after contacts). */
#define GAR_TRYON_STALLED_M   0.01f
#define GAR_TRYON_STALL_STEPS 10
/* sim_collider_resolve bounds the tangential correction by the friction coefficient times the
 * normal correction of the step. A garment held up by its own tension (a waistband on the
 * hips) is pushed out each step only by what gravity moved it in, far less than the normal force
 * its tension exerts, and slid down the hips with the fabric's coefficient (jeans 7 cm in
 * 0.3 s); this gain holds the waist where it was sewn (docs/garments.md). */
#define GAR_TRYON_FRICTION_GAIN 2.5f
/* Rounds of seam passes and contacts at the very end (point-edge joints share vertices:
 * Gauss-Seidel needs several passes). */
#define GAR_TRYON_SEAM_ROUNDS 8
#define GAR_TRYON_SEAM_PASSES 10
/* Position-only rounds after the last step. */
#define GAR_TRYON_SETTLE_ROUNDS 30
/* Rounds of strain limit, seams and contacts at the very end, positions only: the stretch the
 * seams and the contacts left at the corners where a seam ends on a free edge is spread along
 * that edge (Gauss-Seidel moves it a few springs a round; docs/garments.md, "Strain"). */
#define GAR_TRYON_SPREAD_ROUNDS 100
/* ... each of this many passes of strain limit and seams, then the contacts (the contacts cost
 * most: 4 passes a round brought the jeans M's max from 9.0 to 5.3 % for about 15 ms more). */
#define GAR_TRYON_SPREAD_PASSES 4
/* Sweeps of the constraints and the contacts a step: each sweep the strain limit takes back some
 * of the stretch the contacts put in where the body is wider than the pattern; 3 lower the p99
 * strain of 1 by up to 60 % for about a third more time (docs/garments.md, "Strain"). */
#define GAR_TRYON_ITERATIONS 3
/* ... and once gravity is on: a garment hanging from the shoulders or the hips is held at the
 * strain limit wherever the sweeps leave its weight unconverged, and the contacts add their push
 * on top; 8 brought the T-shirt's and the dress's max strain from 3.4-6.5 to 2.4-2.9 % (S/M/L)
 * for 4 to 20 % more time (the jeans M; docs/garments.md, "Strain"). */
#define GAR_TRYON_DRAPE_ITERATIONS 8
/* The strain limit aims a little under the fabric's, so the sweeps' residue stays within it. */
#define GAR_TRYON_LIMIT_MARGIN 0.8f

typedef struct tdress {
    gar_mesh *m;
    int n;
    float (*x)[4], (*xp)[4]; /* w = inverse mass */
    gar_springs sp;
    /* The springs sorted by colour (no two of a colour share a vertex: sim's vector sweeps take
     * eight at a time), stretch colours first. */
    int32_t *ends, *col_start;
    float *rest;
    uint8_t *kind;
    int ncol, nstretch_col;
    float alpha[SIM_SPRING_KINDS], limit, h;
    int iterations;       /* sweeps of constraints and contacts a step */
    int drape_iterations; /* ... once gravity is on */
    int spread_rounds;    /* the last rounds of strain limit, seams and contacts */
    float seam_alpha;     /* the seams' XPBD compliance over h^2 (0 = hard) */
    float *gap0;          /* per joint, the gap at the start */
    sim_collider *col;
    gar_cc *cc;
    uint8_t *skip;
    float *xyz, *push;       /* [vertex][3] scratch for cloth-cloth */
    const uint8_t *pinned;   /* [vertex] 1 = held where it was placed (NULL = none) */
    gar_bending bend;        /* isometric bending (bending.h), the fabric's rigidity */
    int sweep_cols;          /* colours swept by the distance constraints */
    float *pin_xyz;          /* [vertex][3] where */
    const uint8_t *fastened; /* [vertex] 1 = a fastened waistband's (NULL = none) */
    float *fast_y;           /* [vertex] the height it is held at: where it was placed */
    int any_fastened;        /* some vertex is fastened */
} tdress;

static void partner(const tdress *d, const gar_joint *j, float out[3])
{
    for (int k = 0; k < 3; k++)
        out[k] = (1 - j->w) * d->x[j->b0][k] + j->w * d->x[j->b1][k];
}

static float joint_gap(const tdress *d, const gar_joint *j)
{
    float p[3], g[3];
    partner(d, j, p);
    sim_v3_sub(p, d->x[j->a], g);
    return sqrtf(sim_v3_dot(g, g));
}

/* The seams as XPBD distance constraints of target length gap0 * shrink (0 = closed), hard
 * (no compliance): C = |p - x_a| - target, p the partner on the other side's point or segment. */
static void project_seams(tdress *d, float shrink)
{
    const gar_mesh *m = d->m;
    for (int j = 0; j < m->num_joints; j++) {
        const gar_joint *jt = &m->joints[j];
        float p[3], g[3];
        partner(d, jt, p);
        sim_v3_sub(p, d->x[jt->a], g);
        float len = sqrtf(sim_v3_dot(g, g)), target = d->gap0[j] * shrink;
        /* the gradient is n at a, -(1 - w) n at b0 and -w n at b1 (b1 == b0: the point itself) */
        float w = jt->b1 != jt->b0 ? jt->w : 0.0f;
        float wa = d->x[jt->a][3], w0 = (1 - w) * d->x[jt->b0][3], w1 = w * d->x[jt->b1][3];
        float wsum = wa + (1 - w) * w0 + w * w1 + d->seam_alpha;
        if (len <= target || len < 1e-9f || wsum <= 0)
            continue;
        float c = (len - target) / (len * wsum); /* along g, per unit inverse mass */
        for (int k = 0; k < 3; k++) {
            d->x[jt->a][k] += wa * c * g[k];
            d->x[jt->b0][k] -= w0 * c * g[k];
            d->x[jt->b1][k] -= w1 * c * g[k];
        }
    }
}

static float max_gap(const tdress *d)
{
    float g = 0;
    for (int j = 0; j < d->m->num_joints; j++)
        g = fmaxf(g, joint_gap(d, &d->m->joints[j]));
    return g;
}

/* The cloth-body contacts: searched afresh (search) or from the cached triangles, then the
 * response (push out to the thickness, friction); and the floor the body stands on. */
static void contacts(tdress *d, int search)
{
    int n = d->n;
#pragma omp parallel
    {
        int t = 0, nt = 1;
#ifdef _OPENMP
        t = omp_get_thread_num(), nt = omp_get_num_threads();
#endif
        int b = (int)((long)n * t / nt), e = (int)((long)n * (t + 1) / nt);
        if (search)
            sim_collider_find_contacts(d->col, (const float(*)[4])d->x, b, e);
        sim_collider_resolve(d->col, d->x, d->xp, b, e);
        for (int i = b; i < e; i++)
            if (d->x[i][1] < GAR_TRYON_THICKNESS_M)
                d->x[i][1] = GAR_TRYON_THICKNESS_M;
    }
}

/* Panels pushed apart where one comes within the thickness of another (positions only). */
static void cloth_cloth(tdress *d)
{
    if (!d->cc)
        return;
    for (int i = 0; i < d->n; i++)
        memcpy(d->xyz + 3 * i, d->x[i], 3 * sizeof(float));
    memset(d->push, 0, (size_t)d->n * 3 * sizeof *d->push);
    gar_cc_repel(d->cc, d->xyz, GAR_TRYON_CC_THICKNESS, d->push);
    for (int i = 0; i < d->n; i++)
        for (int k = 0; k < 3; k++) {
            d->x[i][k] += d->push[3 * i + k];
            d->xp[i][k] += d->push[3 * i + k];
        }
}

/* The distance constraints, the strain limit, bending (first sweep of a step only: XPBD's
 * multipliers make one sweep honour the rigidity, and the sweeps cost a third more each with it)
 * and the seams. */
static void constraints(tdress *d, float shrink, int bend)
{
    const int32_t(*ends)[2] = (const int32_t(*)[2])d->ends;
    for (int c = 0; c < d->sweep_cols; c++)
        sim_project_springs(d->x, ends, d->rest, d->kind, d->alpha, d->col_start[c],
                            d->col_start[c + 1]);
    for (int c = 0; c < d->nstretch_col; c++)
        sim_strain_limit(d->x, ends, d->rest, d->kind, d->col_start[c], d->col_start[c + 1],
                         d->limit);
    if (bend)
        gar_bending_project(&d->bend, d->x);
    project_seams(d, shrink);
}

/* Pinned vertices back where they were placed, at rest. */
static void hold_pins(tdress *d)
{
    for (int i = 0; d->fast_y && i < d->n; i++)
        if (d->fastened[i]) /* its height only: it is free to settle around the body */
            d->x[i][1] = d->xp[i][1] = d->fast_y[i];
    for (int i = 0; d->pinned && i < d->n; i++)
        if (d->pinned[i]) {
            memcpy(d->x[i], d->pin_xyz + 3 * i, 3 * sizeof(float));
            memcpy(d->xp[i], d->x[i], 3 * sizeof(float));
        }
}

/* One small step: Verlet (damped, gravity when on), the constraints, the contacts. */
static void step(tdress *d, int s, float shrink, float gravity, float damping_per_s)
{
    float g[3] = {0, -gravity * d->h * d->h, 0};
    sim_verlet(d->x, d->xp, 0, d->n, 1.0f - damping_per_s * d->h, g);
    gar_bending_begin_step(&d->bend);
    constraints(d, shrink, 1);
    if (s % GAR_TRYON_CC_EVERY == 0)
        cloth_cloth(d);
    contacts(d, s % GAR_TRYON_CONTACT_EVERY == 0);
    /* further sweeps of constraints and contacts (cached): the stretch that the contacts put
     * back each sweep is what the strain limit removes next (docs/garments.md, "Strain") */
    for (int k = 1; k < d->iterations; k++) {
        constraints(d, shrink, 0);
        contacts(d, 0);
    }
    hold_pins(d);
}

/* The last rounds: passes of the strain limit and the seams (closed: they were), then the
 * contacts (so nothing ends inside the body), positions only. A fastened waist's vertices keep
 * their height in the strain limit (gar_strain_limit_held): the cloth hanging from them is pulled
 * up to them instead of each pass pulling them down half-way and the hold putting them back. Each
 * round's strain limit shortens the corner springs, the seams and contacts put back part of it on
 * their neighbours: the peak spreads along the edge instead of being put back where it was. */
static void spread(tdress *d)
{
    const int32_t(*ends)[2] = (const int32_t(*)[2])d->ends;
    for (int r = 0; r < d->spread_rounds; r++) {
        sim_post_begin(d->x, d->xp, 0, d->n);
        for (int k = 0; k < GAR_TRYON_SPREAD_PASSES; k++) {
            for (int c = 0; c < d->nstretch_col; c++)
                if (d->any_fastened) /* a fastened waist's height held */
                    gar_strain_limit_held(d->x, ends, d->rest, d->fastened, d->limit,
                                          d->col_start[c], d->col_start[c + 1]);
                else
                    sim_strain_limit(d->x, ends, d->rest, d->kind, d->col_start[c],
                                     d->col_start[c + 1], d->limit);
            project_seams(d, 0.0f);
        }
        sim_post_end(d->x, d->xp, 0, d->n);
        contacts(d, r % GAR_TRYON_CONTACT_EVERY == 0);
        hold_pins(d);
    }
}

/* Position-only rounds: the velocities x - x_prev survive (sim's post-stabilisation bracket). */
static void settle(tdress *d)
{
    for (int r = 0; r < GAR_TRYON_SETTLE_ROUNDS; r++) {
        gar_bending_begin_step(&d->bend);
        sim_post_begin(d->x, d->xp, 0, d->n);
        constraints(d, 0.0f, 1);
        sim_post_end(d->x, d->xp, 0, d->n);
        contacts(d, r == 0);
        hold_pins(d);
    }
    /* the seams last, alternating with the contacts, then alone: a joint the contacts held open
     * closes (each side moves by half its gap, a millimetre or two, within the thickness) */
    for (int r = 0; r < GAR_TRYON_SEAM_ROUNDS; r++) {
        sim_post_begin(d->x, d->xp, 0, d->n);
        for (int k = 0; k < GAR_TRYON_SEAM_PASSES; k++)
            project_seams(d, 0.0f);
        sim_post_end(d->x, d->xp, 0, d->n);
        contacts(d, r + 1 == GAR_TRYON_SEAM_ROUNDS);
    }
    hold_pins(d);
    spread(d);
}

/* Greedy edge colouring, stretch springs first then the rest: a spring takes the lowest colour
 * neither end uses yet among its group's 64 (any vertex of a garment mesh has far fewer). */
static int colour_springs(tdress *d)
{
    const gar_springs *sp = &d->sp;
    int ns = sp->n, n = d->n;
    uint64_t *used = calloc((size_t)n + 1, sizeof *used);
    int16_t *colour = malloc(((size_t)ns + 1) * sizeof *colour);
    d->col_start = calloc(2 * 64 + 1, sizeof *d->col_start);
    d->ends = malloc(((size_t)ns + 1) * 2 * sizeof *d->ends);
    d->rest = malloc(((size_t)ns + 1) * sizeof *d->rest);
    d->kind = malloc((size_t)ns + 1);
    int rc = 0, base = 0;
    if (!used || !colour || !d->col_start || !d->ends || !d->rest || !d->kind)
        rc = -GAR_ERR_NO_MEMORY;
    for (int group = 0; group < 2 && !rc; group++) {
        int first = group ? sp->n_stretch : 0, last = group ? ns : sp->n_stretch, top = 0;
        memset(used, 0, (size_t)n * sizeof *used);
        for (int s = first; s < last && !rc; s++) {
            int a = sp->ends[2 * s], b = sp->ends[2 * s + 1];
            uint64_t freec = ~(used[a] | used[b]);
            if (!freec) {
                rc = -GAR_ERR_TOO_LARGE;
                break;
            }
            int k = __builtin_ctzll(freec);
            used[a] |= UINT64_C(1) << k, used[b] |= UINT64_C(1) << k;
            colour[s] = (int16_t)(base + k);
            d->col_start[base + k + 1]++;
            top = k + 1 > top ? k + 1 : top;
        }
        base += top;
        if (!group)
            d->nstretch_col = base;
    }
    if (!rc) {
        d->ncol = base;
        for (int c = 0; c < base; c++)
            d->col_start[c + 1] += d->col_start[c];
        int *fill = (int *)used; /* enough room: n + 1 words of 64 bits >= 2 * 64 ints */
        if ((size_t)(n + 1) * sizeof *used < (size_t)base * sizeof *fill) {
            rc = -GAR_ERR_TOO_LARGE;
        } else {
            memcpy(fill, d->col_start, (size_t)base * sizeof *fill);
            for (int s = 0; s < ns; s++) {
                int q = fill[colour[s]]++;
                d->ends[2 * q] = sp->ends[2 * s], d->ends[2 * q + 1] = sp->ends[2 * s + 1];
                d->rest[q] = sp->rest_m[s], d->kind[q] = sp->kind[s];
            }
        }
    }
    free(used), free(colour);
    return rc;
}

static void tdress_free(tdress *d)
{
    free(d->ends), free(d->col_start), free(d->rest), free(d->kind);
    free(d->x), free(d->xp), free(d->gap0), free(d->skip), free(d->xyz), free(d->push);
    free(d->pin_xyz), free(d->fast_y);
    gar_springs_free(&d->sp);
    gar_bending_free(&d->bend);
    sim_collider_destroy(d->col);
    gar_cc_destroy(d->cc);
}

static int tdress_init(tdress *d, gar_mesh *m, const gar_body_mesh *body,
                       const gar_dress_desc *desc)
{
    const gar_fabric *fab = desc && desc->fabric ? desc->fabric : gar_fabric_find("cotton");
    d->m = m, d->n = m->num_vertices;
    d->h = desc && desc->dt_s > 0 ? desc->dt_s : 0.002f;
    d->iterations = desc && desc->iterations > 0 ? desc->iterations : GAR_TRYON_ITERATIONS;
    d->drape_iterations =
        desc && desc->iterations > 0 ? desc->iterations : GAR_TRYON_DRAPE_ITERATIONS;
    d->spread_rounds = !desc || !desc->spread_rounds ? GAR_TRYON_SPREAD_ROUNDS
                       : desc->spread_rounds > 0     ? desc->spread_rounds
                                                     : 0;
    if (desc && desc->seam_gain > 0)
        d->seam_alpha = 1.0f / (desc->seam_gain * fab->stretch_n_m * d->h * d->h);
    d->limit = fab->max_strain * GAR_TRYON_LIMIT_MARGIN;
    int rc = gar_springs_build(m, &d->sp);
    if (rc)
        return rc;
    size_t n = (size_t)d->n;
    d->x = malloc(n * sizeof *d->x), d->xp = malloc(n * sizeof *d->xp);
    d->gap0 = calloc((size_t)m->num_joints + 1, sizeof *d->gap0);
    d->skip = calloc(n + 1, 1);
    d->xyz = malloc(n * 3 * sizeof *d->xyz), d->push = malloc(n * 3 * sizeof *d->push);
    float *mass = malloc((n + 1) * sizeof *mass);
    if (!d->x || !d->xp || !d->gap0 || !d->skip || !d->xyz || !d->push || !mass) {
        free(mass);
        return -GAR_ERR_NO_MEMORY;
    }
    gar_lump_masses(m, fab->density_kg_m2, mass);
    for (int i = 0; i < d->n; i++) {
        memcpy(d->x[i], m->xyz + 3 * i, 3 * sizeof(float));
        d->x[i][3] = 1.0f / mass[i];
        memcpy(d->xp[i], d->x[i], sizeof d->x[i]);
    }
    free(mass);
    /* XPBD compliance 1 / k per kind, over h^2 (sim_project_springs' alpha) */
    float k[SIM_SPRING_KINDS] = {fab->stretch_n_m, fab->shear_n_m, fab->bend_n_m};
    for (int i = 0; i < SIM_SPRING_KINDS; i++)
        d->alpha[i] = 1.0f / (k[i] * d->h * d->h);
    for (int j = 0; j < m->num_joints; j++)
        d->gap0[j] = joint_gap(d, &m->joints[j]);
    if ((rc = colour_springs(d)) || (rc = gar_bending_build(m, &d->bend)))
        return rc;
    /* Bending is the isometric model's alone: distance constraints across an edge or over two
     * edges, stiff at these masses and steps, locked the folds whatever their stiffness
     * (docs/garments.md, "Bending"); in the plane a triangle mesh of stretch edges is rigid in
     * shear by itself. */
    d->sweep_cols = d->nstretch_col;
    gar_bending_prepare(&d->bend, (const float(*)[4])d->x, fab->bend_rigidity_n_m, d->h);
    gar_seam_skip(m, &d->sp, d->skip);
    if (desc && desc->cloth_cloth && !(d->cc = gar_cc_create(m, d->skip)))
        return -GAR_ERR_NO_MEMORY;
    char err[160];
    sim_collider_desc cd = {.max_vertices = body->num_vertices,
                            .max_triangles = body->num_triangles,
                            .thickness_m = GAR_TRYON_THICKNESS_M,
                            .friction = fab->friction,
                            .max_cloth = d->n,
                            .carry_coulomb = 1};
    if (!(d->col = sim_collider_create(&cd, err, sizeof err)))
        return -GAR_ERR_NO_MEMORY;
    if (sim_collider_set_body(d->col, body->xyz, body->num_vertices, body->triangles,
                              body->num_triangles) < 0)
        return -GAR_ERR_ARG;
    if ((d->fastened = body->fastened)) {
        if (!(d->fast_y = malloc(n * sizeof *d->fast_y)))
            return -GAR_ERR_NO_MEMORY;
        for (size_t i = 0; i < n; i++) {
            d->fast_y[i] = m->xyz[3 * i + 1];
            d->any_fastened |= d->fastened[i];
        }
    }
    if ((d->pinned = body->pinned)) {
        if (!(d->pin_xyz = malloc(n * 3 * sizeof *d->pin_xyz)))
            return -GAR_ERR_NO_MEMORY;
        memcpy(d->pin_xyz, m->xyz, n * 3 * sizeof *d->pin_xyz);
    }
    return 0;
}

uint8_t *gar_fastened_vertices(const gar_pattern *p, const gar_mesh *m)
{
    uint8_t *w = calloc((size_t)m->num_vertices + 1, 1);
    for (int pi = 0; w && pi < p->num_panels && pi < m->num_panels; pi++)
        for (int e = 0; e < p->panels[pi].num_edges && gar_panel_part(p, pi) == GAR_PART_TORSO;
             e++) {
            if (strcmp(p->panels[pi].edges[e].label, GAR_WAIST_LABEL))
                continue;
            int fe = m->panel_first_edge[pi] + e;
            for (int k = m->edge_offset[fe]; k < m->edge_offset[fe + 1]; k++)
                w[m->edge_vertices[k]] = 1;
        }
    return w;
}

int gar_dress_tryon_on(gar_mesh *m, const gar_body_mesh *body, const gar_dress_desc *desc,
                       gar_dress_stats *st, gar_reject *why)
{
    if (!m || !body || !body->xyz || !body->triangles || !st)
        return gar_refuse(why, GAR_ERR_ARG, "dressing needs a mesh and a body");
    memset(st, 0, sizeof *st);
    double t0 = tryon_now_ms();
    tdress d = {0};
    int rc = tdress_init(&d, m, body, desc);
    if (rc) {
        tdress_free(&d);
        return gar_refuse(why, -rc, "dressing setup (%d vertices)", m->num_vertices);
    }
    float max_seam = desc && desc->max_seaming_s > 0 ? desc->max_seaming_s : 1.0f;
    int drape = desc && desc->drape_steps > 0 ? desc->drape_steps : 150;
    /* Seaming: every seam's target shrinks linearly to 0 over the time its widest gap takes at
     * the seam speed; then steps at target 0 until every joint is closed. No gravity. */
    float close_s =
        fminf(max_seam, fmaxf(GAR_TRYON_MIN_SEAMING_S, max_gap(&d) / GAR_TRYON_SEAM_SPEED_M_S));
    int close_steps = (int)ceilf(close_s / d.h), max_steps = (int)(max_seam / d.h), s = 0;
    st->seaming_s = -1;
    float last_gap = INFINITY;
    /* no friction while seaming: the panels slide over the body as the seams pull them */
    float friction = d.col->d.friction;
    d.col->d.friction = 0.0f;
    for (; s < max_steps; s++) {
        float shrink = s < close_steps ? 1.0f - (float)(s + 1) / close_steps : 0.0f;
        step(&d, s, shrink, 0.0f, GAR_TRYON_SEAM_DAMPING_PER_S);
        if (shrink > 0.0f || s % GAR_TRYON_STALL_STEPS)
            continue;
        float gap = max_gap(&d);
        if (gap < GAR_TRYON_SEAMED_M || (gap < GAR_TRYON_STALLED_M && gap > 0.98f * last_gap)) {
            st->seaming_s = (s + 1) * d.h;
            s++;
            break;
        }
        last_gap = gap;
    }
    d.col->d.friction = friction * GAR_TRYON_FRICTION_GAIN;
    d.iterations = d.drape_iterations;
    for (int k = 0; k < drape; k++, s++)
        step(&d, s, 0.0f, GAR_GRAVITY_M_S2, GAR_TRYON_DRAPE_DAMPING_PER_S);
    settle(&d);
    for (int i = 0; i < d.n; i++)
        memcpy(m->xyz + 3 * i, d.x[i], 3 * sizeof(float));
    st->steps = s;
    tdress_free(&d);
    st->ms = (float)(tryon_now_ms() - t0);
    return 0;
}

int gar_dress_tryon(const gar_pattern *p, gar_mesh *m, const fit_model *body,
                    const gar_dress_desc *desc, gar_dress_stats *st, gar_reject *why)
{
    if (!p || !m || !body || !st)
        return gar_refuse(why, GAR_ERR_ARG, "dressing needs a pattern, its mesh and a body");
    uint8_t *waist = gar_fastened_vertices(p, m);
    if (!waist)
        return gar_refuse(why, GAR_ERR_NO_MEMORY, "dressing (%d vertices)", m->num_vertices);
    gar_body_mesh bm = {fit_model_rest_vertices(body),
                        fit_model_vertex_count(body),
                        fit_model_triangles(body),
                        fit_model_triangle_count(body),
                        NULL,
                        waist};
    int rc = gar_dress_tryon_on(m, &bm, desc, st, why);
    free(waist);
    if (rc)
        return rc;
    float ms = st->ms, seaming = st->seaming_s;
    int steps = st->steps;
    rc = gar_dress_measure(m, body, st);
    st->ms = ms, st->seaming_s = seaming, st->steps = steps;
    return rc ? gar_refuse(why, -rc, "measuring the dressed garment") : 0;
}
