/* Isometric (quadratic) bending as XPBD constraints: see bending.h. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bending.h"

/* s = GAR_BEND_CALIB / (A0 + A1), so that a panel rolled into a cylinder of radius R stores
 * B / 2 / R^2 per unit area (the plate's bending energy at curvature 1 / R). Bergou et al.'s
 * Q = 3 / (A0 + A1) K^T K stored 2.6 to 2.9 times that on the project's meshes (2 cm lattice
 * clipped to a square, rolled across and along its rows, R 5 to 30 cm): 3 / 2.75.
 * test_garment_bend checks the calibrated energy on both rolls. */
#define GAR_BEND_CALIB 1.09f

typedef struct hedge {
    int32_t a, b, opp, panel; /* a < b */
} hedge;

static int hedge_cmp(const void *x, const void *y)
{
    const hedge *p = x, *q = y;
    return p->a != q->a ? (p->a > q->a) - (p->a < q->a) : (p->b > q->b) - (p->b < q->b);
}

/* Cotangent of the angle between 2D vectors p and q. */
static float cot2(const float p[2], const float q[2])
{
    float cr = fabsf(p[0] * q[1] - p[1] * q[0]);
    return (p[0] * q[0] + p[1] * q[1]) / fmaxf(cr, 1e-12f);
}

/* K and s of the stencil (edge x0 x1, opposite x2 and x3) from the flat layout; the angles are
 * the triangles' interior angles at the edge's ends. Returns 0 for a degenerate stencil. */
static int stencil(const gar_mesh *m, const int32_t v[4], float k[4], float *s)
{
    float p[4][2];
    for (int i = 0; i < 4; i++)
        p[i][0] = m->uv_m[2 * v[i]], p[i][1] = m->uv_m[2 * v[i] + 1];
    float e0[2] = {p[1][0] - p[0][0], p[1][1] - p[0][1]}, m0[2] = {-e0[0], -e0[1]};
    float e1[2] = {p[2][0] - p[0][0], p[2][1] - p[0][1]};
    float e2[2] = {p[3][0] - p[0][0], p[3][1] - p[0][1]};
    float e3[2] = {p[2][0] - p[1][0], p[2][1] - p[1][1]};
    float e4[2] = {p[3][0] - p[1][0], p[3][1] - p[1][1]};
    float a0 = 0.5f * fabsf(e0[0] * e1[1] - e0[1] * e1[0]);
    float a1 = 0.5f * fabsf(e0[0] * e2[1] - e0[1] * e2[0]);
    if (!(a0 > 1e-10f && a1 > 1e-10f))
        return 0;
    float c01 = cot2(e0, e1), c02 = cot2(e0, e2), c03 = cot2(m0, e3), c04 = cot2(m0, e4);
    k[0] = c03 + c04, k[1] = c01 + c02, k[2] = -c01 - c03, k[3] = -c02 - c04;
    *s = GAR_BEND_CALIB / (a0 + a1);
    return 1;
}

int gar_bending_build(const gar_mesh *m, gar_bending *b)
{
    memset(b, 0, sizeof *b);
    int nh = 3 * m->num_triangles;
    hedge *h = malloc((size_t)(nh ? nh : 1) * sizeof *h);
    b->v = malloc((size_t)(nh / 2 + 1) * sizeof *b->v);
    b->k = malloc((size_t)(nh / 2 + 1) * sizeof *b->k);
    b->s = malloc((size_t)(nh / 2 + 1) * sizeof *b->s);
    b->lambda = calloc((size_t)(nh / 2 + 1), sizeof *b->lambda);
    b->alpha = calloc((size_t)(nh / 2 + 1), sizeof *b->alpha);
    b->inv = calloc((size_t)(nh / 2 + 1), sizeof *b->inv);
    if (!h || !b->v || !b->k || !b->s || !b->lambda || !b->alpha || !b->inv) {
        free(h);
        gar_bending_free(b);
        return -GAR_ERR_NO_MEMORY;
    }
    for (int t = 0; t < m->num_triangles; t++)
        for (int e = 0; e < 3; e++) {
            int32_t a = m->triangles[3 * t + e], c = m->triangles[3 * t + (e + 1) % 3];
            h[3 * t + e] = (hedge){a < c ? a : c, a < c ? c : a, m->triangles[3 * t + (e + 2) % 3],
                                   m->panel_of[a]};
        }
    qsort(h, (size_t)nh, sizeof *h, hedge_cmp);
    for (int i = 1; i < nh; i++) {
        if (h[i].a != h[i - 1].a || h[i].b != h[i - 1].b || h[i].opp == h[i - 1].opp)
            continue;
        int32_t *v = b->v[b->n];
        v[0] = h[i].a, v[1] = h[i].b, v[2] = h[i - 1].opp, v[3] = h[i].opp;
        b->n += stencil(m, v, b->k[b->n], &b->s[b->n]);
    }
    free(h);
    return 0;
}

void gar_bending_free(gar_bending *b)
{
    free(b->v), free(b->k), free(b->s), free(b->lambda), free(b->alpha), free(b->inv);
    memset(b, 0, sizeof *b);
}

/* C = sum_i K_i x_i of stencil e. */
static void curvature(const gar_bending *b, int e, const float (*x)[4], double c[3])
{
    c[0] = c[1] = c[2] = 0;
    for (int i = 0; i < 4; i++)
        for (int d = 0; d < 3; d++)
            c[d] += (double)b->k[e][i] * x[b->v[e][i]][d];
}

double gar_bending_energy(const gar_bending *b, const float (*x)[4], float rigidity_n_m)
{
    double e = 0;
    for (int s = 0; s < b->n; s++) {
        double c[3];
        curvature(b, s, x, c);
        e += 0.5 * rigidity_n_m * b->s[s] * (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    }
    return e;
}

void gar_bending_gradient(const gar_bending *b, const float (*x)[4], float rigidity_n_m,
                          double *grad)
{
    for (int s = 0; s < b->n; s++) {
        double c[3];
        curvature(b, s, x, c);
        for (int i = 0; i < 4; i++)
            for (int d = 0; d < 3; d++)
                grad[3 * b->v[s][i] + d] += rigidity_n_m * b->s[s] * b->k[s][i] * c[d];
    }
}

void gar_bending_begin_step(gar_bending *b)
{
    memset(b->lambda, 0, (size_t)b->n * sizeof *b->lambda);
}

void gar_bending_prepare(gar_bending *b, const float (*x)[4], float rigidity_n_m, float h)
{
    for (int s = 0; s < b->n; s++) {
        /* E = |C|^2 / (2 alpha), alpha = 1 / (B s); XPBD's alpha~ = alpha / h^2 */
        float alpha = rigidity_n_m > 0 ? 1.0f / (rigidity_n_m * b->s[s] * h * h) : 0.0f;
        float wsum = alpha;
        for (int i = 0; i < 4; i++)
            wsum += x[b->v[s][i]][3] * b->k[s][i] * b->k[s][i];
        b->alpha[s] = alpha;
        b->inv[s] = rigidity_n_m > 0 && wsum > 0 ? 1.0f / wsum : 0.0f; /* 0: left alone */
    }
}

void gar_bending_project(gar_bending *b, float (*x)[4])
{
    for (int s = 0; s < b->n; s++) {
        const int32_t *v = b->v[s];
        const float *k = b->k[s];
        float inv = b->inv[s], alpha = b->alpha[s], *lambda = b->lambda[s];
        float *p[4] = {x[v[0]], x[v[1]], x[v[2]], x[v[3]]};
        for (int d = 0; d < 3; d++) {
            float c = k[0] * p[0][d] + k[1] * p[1][d] + k[2] * p[2][d] + k[3] * p[3][d];
            float dl = -(c + alpha * lambda[d]) * inv;
            lambda[d] += dl;
            for (int i = 0; i < 4; i++)
                p[i][d] += p[i][3] * k[i] * dl;
        }
    }
}
