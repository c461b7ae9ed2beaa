/* The pose fit: Gauss-Newton (Levenberg-Marquardt damped) on the coarse model, with analytic
 * derivatives through the skinning (fit_jacobian.c). Terms, each normalised by its count:
 * - data to model: every data point to the plane of its nearest camera-facing model vertex,
 *   robust (Huber) and gated;
 * - model to data, free space (Ganapathi et al. 2012): a camera-facing model vertex that projects
 *   where the camera sees no person is pulled to the ray of the nearest person pixel; one that
 *   lies in front of the seen surface is pushed back to it;
 * - temporal prior: each parameter's change from the last frame;
 * - rest prior: small pull of every joint toward its rest angle (twists a depth camera cannot
 *   see stay put);
 * - joint limits: every step is projected into fit_joint_limits (fit_pose_clamp). */
#include "fit_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NP FIT_POSE_PARAMS
/* Nearest-vertex grid cell, m: a data point more than a cell away from every vertex is an
 * outlier in any case (the gate is at most 2 cells). */
#define SOLVE_CELL_M        0.08f
#define SOLVE_HUBER_M       0.02f /* residuals past 2 cm weigh less: depth noise is ~1-2 cm */
#define SOLVE_SIL_WEIGHT    0.5   /* free-space term against the data term */
#define SOLVE_SIL_EVERY     4     /* every 4th camera-facing coarse vertex checks free space */
#define SOLVE_FRONT_SLACK_M 0.03f
/* in front of the seen surface by more than this: violation */
#define SOLVE_REST_PRIOR 2e-5 /* per radian squared, against a data term of ~1e-4 m^2 */
/* Levenberg-Marquardt damping, relative to the diagonal. Depth barely sees some combinations of
 * joints (a clavicle against its shoulder, the head against the neck, a wrist's twist): at 1e-3
 * one step from the true pose on a noise-free frame of the boxer's guard turned the head 0.3 rad
 * and moved the shoulders 20-40 mm, and 6 iterations from the truth ended 16.9 mm off the true
 * joints; at 0.1, 9.2 mm (docs/bodyfit.md, "The solver's damping"). */
#define SOLVE_LM_DAMPING 0.1

struct fit_solver {
    const fit_model *m;
    float *pos, *nrm;
    uint8_t *front;
    int32_t *cell_start, *cell_items, *match;
    float *cell_pos; /* the position of cell_items[e] at cell_pos + 3 e: read in order */
    float *match_w, *match_r;
    int ncells_cap, match_cap, match_n;
};

fit_solver *fit_solver_create(const fit_model *coarse)
{
    fit_solver *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    int nv = fit_model_vertex_count(coarse);
    s->m = coarse;
    s->pos = malloc((size_t)nv * 3 * sizeof(float));
    s->nrm = malloc((size_t)nv * 3 * sizeof(float));
    s->front = malloc((size_t)nv);
    s->cell_items = malloc((size_t)nv * sizeof(int32_t));
    s->cell_pos = malloc((size_t)nv * 3 * sizeof(float));
    s->ncells_cap = 64 * 64 * 64;
    s->cell_start = malloc(((size_t)s->ncells_cap + 1) * sizeof(int32_t));
    if (!s->pos || !s->nrm || !s->front || !s->cell_items || !s->cell_pos || !s->cell_start) {
        fit_solver_destroy(s);
        return NULL;
    }
    return s;
}

void fit_solver_destroy(fit_solver *s)
{
    if (!s)
        return;
    free(s->pos);
    free(s->nrm);
    free(s->front);
    free(s->cell_items);
    free(s->cell_pos);
    free(s->cell_start);
    free(s->match);
    free(s->match_w);
    free(s->match_r);
    free(s);
}

typedef struct grid {
    float lo[3];
    int dim[3];
} grid;

static int cell_of(const grid *g, const float *p, int c[3])
{
    for (int k = 0; k < 3; ++k) {
        c[k] = (int)floorf((p[k] - g->lo[k]) / SOLVE_CELL_M);
        if (c[k] < 0 || c[k] >= g->dim[k])
            return -1;
    }
    return (c[2] * g->dim[1] + c[1]) * g->dim[0] + c[0];
}

/* Counting sort of the camera-facing vertices into cells. */
static int grid_build(fit_solver *s, grid *g, const float cam[3])
{
    int nv = s->m->mesh.nv, nf = 0;
    float hi[3] = {-1e9f, -1e9f, -1e9f};
    g->lo[0] = g->lo[1] = g->lo[2] = 1e9f;
    for (int i = 0; i < nv; ++i) {
        const float *p = s->pos + (size_t)i * 3, *n = s->nrm + (size_t)i * 3;
        float d[3] = {p[0] - cam[0], p[1] - cam[1], p[2] - cam[2]};
        s->front[i] = body_dot(n, d) < 0.0f;
        if (!s->front[i])
            continue;
        ++nf;
        for (int k = 0; k < 3; ++k) {
            g->lo[k] = body_minf(g->lo[k], p[k]);
            hi[k] = body_maxf(hi[k], p[k]);
        }
    }
    if (!nf)
        return -1;
    long cells = 1;
    for (int k = 0; k < 3; ++k) {
        g->lo[k] -= SOLVE_CELL_M;
        g->dim[k] = (int)((hi[k] - g->lo[k]) / SOLVE_CELL_M) + 2;
        cells *= g->dim[k];
    }
    if (cells > s->ncells_cap)
        return -1; /* a body 5 m across: nothing to fit */
    memset(s->cell_start, 0, ((size_t)cells + 1) * sizeof(int32_t));
    int c[3];
    for (int i = 0; i < nv; ++i)
        if (s->front[i])
            s->cell_start[cell_of(g, s->pos + (size_t)i * 3, c) + 1]++;
    for (long k = 0; k < cells; ++k)
        s->cell_start[k + 1] += s->cell_start[k];
    for (int i = 0; i < nv; ++i)
        if (s->front[i]) {
            int cell = cell_of(g, s->pos + (size_t)i * 3, c), e = s->cell_start[cell]++;
            s->cell_items[e] = i;
            memcpy(s->cell_pos + (size_t)e * 3, s->pos + (size_t)i * 3, 3 * sizeof(float));
        }
    for (long k = cells; k > 0; --k)
        s->cell_start[k] = s->cell_start[k - 1];
    s->cell_start[0] = 0;
    return 0;
}

/* The nearest camera-facing vertex within a cell of p (d2_out: its squared distance), or -1.
 * The 3 x 3 x 3 cells around p's, clipped to the grid: a row of 3 cells is consecutive, and so
 * are their vertices (cell_items, cell_pos), so each row is one run; the vertices are seen in
 * the same order as cell by cell (a tie keeps the first). */
static int grid_nearest(const fit_solver *s, const grid *g, const float *p, float *d2_out)
{
    int c[3], lo[3], hi[3], best = -1;
    float best_d2 = SOLVE_CELL_M * SOLVE_CELL_M;
    for (int k = 0; k < 3; ++k) {
        c[k] = (int)floorf((p[k] - g->lo[k]) / SOLVE_CELL_M);
        lo[k] = c[k] > 0 ? c[k] - 1 : 0;
        hi[k] = c[k] < g->dim[k] - 1 ? c[k] + 1 : g->dim[k] - 1;
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1] && lo[0] <= hi[0]; ++y) {
            int row = (z * g->dim[1] + y) * g->dim[0];
            int e1 = s->cell_start[row + hi[0] + 1];
            for (int e = s->cell_start[row + lo[0]]; e < e1; ++e) {
                const float *q = s->cell_pos + (size_t)e * 3;
                float d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
                float d2 = body_dot(d, d);
                if (d2 < best_d2) {
                    best_d2 = d2;
                    best = s->cell_items[e];
                }
            }
        }
    *d2_out = best_d2;
    return best;
}

/* Adds w (g . dv - r)^2 for a residual r with gradient g on the vertex to the normal equations
 * (JtJ upper triangle, Jtr). The row's entries come in blocks of 3 consecutive parameters (the
 * root's translation, then each joint's rotation, joints ascending): the upper triangle is the
 * rest of a block and every later block, 3 at a time without an index per entry. */
static void add_row(const fit_vjac *vj, const float g[3], float r, double w, double *A, double *b)
{
    int base[1 + FIT_JOINT_COUNT], order[FIT_JOINT_COUNT];
    double val[3 + 3 * FIT_JOINT_COUNT];
    /* The joints in ascending order (insertion sort of a handful), so that the upper triangle
     * is the pairs i <= j: no test per pair (half the cost of the fit's points). */
    for (int e = 0; e < vj->n; ++e) {
        int k = e;
        for (; k > 0 && vj->joint[order[k - 1]] > vj->joint[e]; --k)
            order[k] = order[k - 1];
        order[k] = e;
    }
    int nb = 1 + vj->n;
    base[0] = 0;
    for (int k = 0; k < 3; ++k)
        val[k] = g[k];
    for (int o = 0; o < vj->n; ++o) {
        int e = order[o];
        const float *bb = vj->b[e];
        /* g . (delta x b) = delta . (b x g) */
        base[o + 1] = 3 + 3 * vj->joint[e];
        val[3 * o + 3] = bb[1] * g[2] - bb[2] * g[1];
        val[3 * o + 4] = bb[2] * g[0] - bb[0] * g[2];
        val[3 * o + 5] = bb[0] * g[1] - bb[1] * g[0];
    }
    for (int bi = 0; bi < nb; ++bi)
        for (int k = 0; k < 3; ++k) {
            int i = base[bi] + k;
            double wv = w * val[3 * bi + k], *row = A + i * NP;
            b[i] += wv * r;
            for (int j = k; j < 3; ++j)
                row[base[bi] + j] += wv * val[3 * bi + j];
            for (int bj = bi + 1; bj < nb; ++bj) {
                double *dst = row + base[bj];
                const double *src = val + 3 * bj;
                dst[0] += wv * src[0];
                dst[1] += wv * src[1];
                dst[2] += wv * src[2];
            }
        }
}

typedef struct frame_ctx {
    float skin[FIT_JOINT_COUNT][12], joints[FIT_JOINT_COUNT * 3];
    grid g;
    float cam[3];
} frame_ctx;

/* Data to model: point-to-plane, Huber weights, gated at max_match_m. Returns the inliers. */
static int data_term(fit_solver *s, const fit_problem *pb, frame_ctx *f, double *A, double *b,
                     double *sq, int *explained)
{
    int in = 0;
    *explained = 0;
    double w0 = 1.0 / (pb->count > 0 ? pb->count : 1);
    float gate2 = pb->max_match_m * pb->max_match_m;
    float tol = pb->explained_m > 0.0f ? pb->explained_m : FIT_EXPLAINED_M;
    s->match_n = pb->count;
    for (int i = 0; i < pb->count; ++i) {
        const float *p = pb->points + (size_t)i * 3;
        float d2;
        int v = grid_nearest(s, &f->g, p, &d2);
        s->match[i] = -1;
        if (v < 0 || d2 > gate2)
            continue;
        fit_vjac vj;
        fit_vertex_sparse(s->m, f->skin, f->joints, v, &vj);
        const float *n = s->nrm + (size_t)v * 3;
        float d[3] = {vj.pos[0] - p[0], vj.pos[1] - p[1], vj.pos[2] - p[2]};
        float r = body_dot(n, d);
        float a = fabsf(r);
        double w = a > SOLVE_HUBER_M ? w0 * SOLVE_HUBER_M / a : w0;
        add_row(&vj, n, -r, w, A, b);
        *sq += (double)r * r;
        *explained += a <= tol;
        s->match[i] = v;
        s->match_w[i] = (float)(w / w0);
        s->match_r[i] = r;
        ++in;
    }
    return in;
}

/* Camera coordinates of a world point (camera_to_world is [R | t]: c = R^T (p - t)). */
static void to_cam(const float m[16], const float *p, float c[3])
{
    float d[3] = {p[0] - m[3], p[1] - m[7], p[2] - m[11]};
    for (int k = 0; k < 3; ++k)
        c[k] = m[0 * 4 + k] * d[0] + m[1 * 4 + k] * d[1] + m[2 * 4 + k] * d[2];
}

/* A camera-space gradient a as a world-space one: R a. */
static void to_world_dir(const float m[16], const float a[3], float g[3])
{
    for (int k = 0; k < 3; ++k)
        g[k] = m[k * 4] * a[0] + m[k * 4 + 1] * a[1] + m[k * 4 + 2] * a[2];
}

/* With A NULL, only counts the vertices in free space (st: sil_checked, sil_violations). */
static void free_space_term(fit_solver *s, const fit_problem *pb, frame_ctx *f, double *A,
                            double *b, fit_stats *st)
{
    const fit_segment *sg = pb->seg;
    const fit_depth_view *vw = pb->view;
    const float *m = vw->camera_to_world;
    int nv = s->m->mesh.nv, seen = 0;
    for (int v = 0; v < nv; v += SOLVE_SIL_EVERY)
        seen += s->front[v];
    double w0 = SOLVE_SIL_WEIGHT / (seen > 0 ? seen : 1);
    for (int v = 0; v < nv; v += SOLVE_SIL_EVERY) {
        if (!s->front[v])
            continue;
        float c[3];
        to_cam(m, s->pos + (size_t)v * 3, c);
        if (!(c[2] > 0.1f))
            continue;
        float u = (vw->fx * c[0] / c[2] + vw->cx) / (float)sg->stride;
        float r = (vw->fy * c[1] / c[2] + vw->cy) / (float)sg->stride;
        int gx = (int)lrintf(u), gy = (int)lrintf(r);
        if (gx < 0 || gy < 0 || gx >= sg->width || gy >= sg->height)
            continue; /* outside the image: nothing is known there */
        int i = gy * sg->width + gx;
        fit_vjac vj;
        st->sil_checked += A == NULL;
        if (sg->mask[i] && !A)
            continue;
        if (sg->mask[i]) {
            float z = sg->depth_m[i];
            if (!(z > 0.0f) || c[2] > z - SOLVE_FRONT_SLACK_M)
                continue;
            float g[3], a[3] = {0.0f, 0.0f, 1.0f};
            to_world_dir(m, a, g);
            fit_vertex_sparse(s->m, f->skin, f->joints, v, &vj);
            add_row(&vj, g, -(c[2] - (z - SOLVE_FRONT_SLACK_M)), w0, A, b);
            continue;
        }
        /* Free space is violated only where the camera sees past the vertex: a nearer reading
         * there (an occluder) or none at all says nothing about it (Ganapathi et al. 2012). */
        float zo = sg->depth_m[i];
        if (!(zo > c[2] + SOLVE_FRONT_SLACK_M))
            continue;
        /* Outside the transformed box the nearest person pixel is the box edge's. */
        int cx = gx < pb->roi[0] ? pb->roi[0] : (gx > pb->roi[2] ? pb->roi[2] : gx);
        int cy = gy < pb->roi[1] ? pb->roi[1] : (gy > pb->roi[3] ? pb->roi[3] : gy);
        int q = pb->roi[2] >= 0 ? pb->nearest[cy * sg->width + cx] : -1;
        if (q < 0)
            continue;
        if (!A) {
            int dx = q % sg->width - gx, dy = q / sg->width - gy;
            st->sil_violations += dx * dx + dy * dy >= FIT_SIL_OUT_PX * FIT_SIL_OUT_PX;
            continue;
        }

        float ru = ((float)((q % sg->width) * sg->stride) - vw->cx) / vw->fx;
        float rv = ((float)((q / sg->width) * sg->stride) - vw->cy) / vw->fy;
        fit_vertex_sparse(s->m, f->skin, f->joints, v, &vj);
        float ax[3] = {1.0f, 0.0f, -ru}, ay[3] = {0.0f, 1.0f, -rv}, g[3];
        to_world_dir(m, ax, g);
        add_row(&vj, g, -(c[0] - c[2] * ru), w0, A, b);
        to_world_dir(m, ay, g);
        add_row(&vj, g, -(c[1] - c[2] * rv), w0, A, b);
    }
}

/* Temporal prior toward prev (root and local angles, to first order) and the rest prior. */
static void prior_terms(const fit_problem *pb, const fit_pose *pose, const frame_ctx *f, double *A,
                        double *b)
{
    double wt = pb->temporal > 1e-7f ? pb->temporal : 1e-7; /* keeps A positive definite */
    for (int k = 0; k < 3; ++k) {
        A[k * NP + k] += wt;
        b[k] -= wt * (pose->root[k] - (pb->prev ? pb->prev->root[k] : pose->root[k]));
    }
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        int p = fit_joint_parent((fit_joint)j);
        float dt[3], dr[3];
        for (int k = 0; k < 3; ++k) {
            dt[k] = pb->prev ? pose->rot[j][k] - pb->prev->rot[j][k] : 0.0f;
            dr[k] = p < 0 ? 0.0f : pose->rot[j][k];
        }
        double wr = p < 0 ? 0.0 : SOLVE_REST_PRIOR;
        /* The world step d maps to the local change G_p^T d: the residual in world axes is
         * G_p times the local one. */
        for (int r = 0; r < 3; ++r) {
            double lt = 0.0, lr = 0.0;
            for (int k = 0; k < 3; ++k) {
                double g = p < 0 ? (r == k) : f->skin[p][r * 4 + k];
                lt += g * dt[k];
                lr += g * dr[k];
            }
            int i = 3 + 3 * j + r;
            A[i * NP + i] += wt + wr;
            b[i] -= wt * lt + wr * lr;
        }
    }
}

/* Cholesky of the symmetric n x n A (its lower triangle read; the upper left as it was),
   solving A x = b in place; -1 when A is not positive definite. */
int fit_cholesky_solve(double *A, double *x, int n)
{
    for (int j = 0; j < n; ++j) {
        double d = A[j * n + j];
        for (int k = 0; k < j; ++k)
            d -= A[j * n + k] * A[j * n + k];
        if (!(d > 0.0))
            return -1;
        d = sqrt(d);
        A[j * n + j] = d;
        for (int i = j + 1; i < n; ++i) {
            double v = A[i * n + j];
            for (int k = 0; k < j; ++k)
                v -= A[i * n + k] * A[j * n + k];
            A[i * n + j] = v / d;
        }
    }
    for (int i = 0; i < n; ++i) {
        double v = x[i];
        for (int k = 0; k < i; ++k)
            v -= A[i * n + k] * x[k];
        x[i] = v / A[i * n + i];
    }
    for (int i = n - 1; i >= 0; --i) {
        double v = x[i];
        for (int k = i + 1; k < n; ++k)
            v -= A[k * n + i] * x[k];
        x[i] = v / A[i * n + i];
    }
    return 0;
}

/* The symmetric A (upper triangle filled) mirrored, then solved (fit_cholesky_solve). */
static int solve_spd(double *A, double *x)
{
    for (int i = 0; i < NP; ++i)
        for (int j = 0; j < i; ++j)
            A[i * NP + j] = A[j * NP + i];
    return fit_cholesky_solve(A, x, NP);
}

int fit_solve(fit_solver *s, const fit_problem *pb, fit_pose *pose, fit_stats *st)
{
    frame_ctx f;
    const float *m = pb->view ? pb->view->camera_to_world : NULL;
    f.cam[0] = m ? m[3] : 0.0f, f.cam[1] = m ? m[7] : 1.0f, f.cam[2] = m ? m[11] : 2.5f;
    memset(st, 0, sizeof *st);
    if (pb->count > s->match_cap) {
        free(s->match);
        free(s->match_w);
        free(s->match_r);
        s->match = malloc((size_t)pb->count * sizeof(int32_t));
        s->match_w = malloc((size_t)pb->count * sizeof(float));
        s->match_r = malloc((size_t)pb->count * sizeof(float));
        s->match_cap = s->match && s->match_w && s->match_r ? pb->count : 0;
        if (!s->match_cap)
            return -FIT_ERR_NOMEM;
    }
    s->match_n = 0;
    for (int it = 0; it <= pb->iterations; ++it) {
        body_joint_transforms(&s->m->sk, pose, f.skin, f.joints);
        fit_model_pose_lbs(s->m, pose, s->pos, NULL);
        if (fit_model_normals(s->m, s->pos, s->nrm) || grid_build(s, &f.g, f.cam))
            return -FIT_ERR_MESH;
        double A[NP * NP], b[NP], sq = 0.0;
        memset(A, 0, sizeof A);
        memset(b, 0, sizeof b);
        st->inliers = data_term(s, pb, &f, A, b, &sq, &st->explained);
        st->rms_mm = st->inliers ? (float)(1000.0 * sqrt(sq / st->inliers)) : 0.0f;
        if (it == pb->iterations) { /* the last pass only measures */
            if (pb->seg && pb->nearest)
                free_space_term(s, pb, &f, NULL, NULL, st);
            break;
        }
        if (pb->seg && pb->nearest)
            free_space_term(s, pb, &f, A, b, st);
        prior_terms(pb, pose, &f, A, b);
        for (int i = 0; i < NP; ++i)
            A[i * NP + i] *= 1.0 + SOLVE_LM_DAMPING;
        if (solve_spd(A, b))
            return -FIT_ERR_NAN;
        fit_pose_apply_step(s->m, pose, b);
        st->clamped = fit_pose_clamp(pose);
        st->iterations = it + 1;
    }
    return 0;
}

fit_matches fit_solver_matches(const fit_solver *s)
{
    return (fit_matches){.vertex = s->match,
                         .weight = s->match_w,
                         .resid = s->match_r,
                         .pos = s->pos,
                         .nrm = s->nrm,
                         .count = s->match_n};
}
