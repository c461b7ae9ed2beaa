/* Recovery of a frame the solver cannot solve (sim.c): rather than leave the last good cloth
 * where it was while the body walks away from it (a frozen frame), the last good cloth is
 * carried by the body from frame k-1 to frame k, each point rigidly with the body triangle at
 * its nearest body vertex (the skinning the body itself went through, as seen by its surface),
 * and the solver resettles from there on the next frame. Host-side, for both backends: the
 * backend's copy is uploaded after it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "carry.h"

/* Grid cells: a few body vertices each at the body model's 1 cm spacing. */
#define CARRY_CELL_M  0.05f
#define CARRY_BUCKETS (1 << 15)
/* Points farther than this from every body vertex (cells searched out to it) move with the
 * body's mean motion: a shirt's point is never that far from the body it hangs on. */
#define CARRY_SEARCH_CELLS 8

/* The two body frames a carry goes between. */
typedef struct carry_view {
    const float (*v_prev)[4], (*v)[4];
    const int32_t (*tris)[4];
    int nv, nt;
} carry_view;

struct sim_carry {
    int max_nv;
    int32_t *start; /* [CARRY_BUCKETS + 1] */
    int32_t *order; /* [max_nv] body vertices sorted by bucket */
    int32_t *tri;   /* [max_nv] one triangle at each vertex, -1 for none */
};

sim_carry *sim_carry_create(int max_body_vertices)
{
    sim_carry *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->max_nv = max_body_vertices;
    c->start = malloc((CARRY_BUCKETS + 1) * sizeof *c->start);
    c->order = malloc((size_t)max_body_vertices * sizeof *c->order);
    c->tri = malloc((size_t)max_body_vertices * sizeof *c->tri);
    if (!c->start || !c->order || !c->tri) {
        sim_carry_destroy(c);
        return NULL;
    }
    return c;
}

void sim_carry_destroy(sim_carry *c)
{
    if (!c)
        return;
    free(c->start);
    free(c->order);
    free(c->tri);
    free(c);
}

static int cell_of(float x)
{
    return (int)floorf(x / CARRY_CELL_M);
}

static uint32_t bucket(int i, int j, int k)
{
    uint32_t h = (uint32_t)i * 73856093u ^ (uint32_t)j * 19349663u ^ (uint32_t)k * 83492791u;
    return h & (CARRY_BUCKETS - 1);
}

static void build(sim_carry *c, const carry_view *b)
{
    memset(c->start, 0, (CARRY_BUCKETS + 1) * sizeof *c->start);
    for (int i = 0; i < b->nv; i++) {
        const float *p = b->v_prev[i];
        c->start[bucket(cell_of(p[0]), cell_of(p[1]), cell_of(p[2])) + 1]++;
        c->tri[i] = -1;
    }
    for (int h = 0; h < CARRY_BUCKETS; h++)
        c->start[h + 1] += c->start[h];
    for (int i = 0; i < b->nv; i++) { /* counting sort; start[h] ends as bucket h's end */
        const float *p = b->v_prev[i];
        c->order[c->start[bucket(cell_of(p[0]), cell_of(p[1]), cell_of(p[2]))]++] = i;
    }
    for (int h = CARRY_BUCKETS; h > 0; h--)
        c->start[h] = c->start[h - 1];
    c->start[0] = 0;
    for (int t = 0; t < b->nt; t++)
        for (int k = 0; k < 3; k++)
            c->tri[b->tris[t][k]] = t;
}

/* The body vertex nearest p in frame k-1, -1 when none is within the searched cells. */
static int nearest(const sim_carry *c, const carry_view *b, const float p[3])
{
    int ci = cell_of(p[0]), cj = cell_of(p[1]), ck = cell_of(p[2]), best = -1;
    float best_d2 = INFINITY;
    for (int r = 1; r <= CARRY_SEARCH_CELLS; r *= 2) {
        for (int i = ci - r; i <= ci + r; i++)
            for (int j = cj - r; j <= cj + r; j++)
                for (int k = ck - r; k <= ck + r; k++) {
                    uint32_t h = bucket(i, j, k);
                    for (int32_t s = c->start[h]; s < c->start[h + 1]; s++) {
                        const float *q = b->v_prev[c->order[s]];
                        float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
                        float d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                        if (d2 < best_d2 || (d2 == best_d2 && c->order[s] < best)) {
                            best_d2 = d2;
                            best = c->order[s];
                        }
                    }
                }
        /* every vertex within r cells has been seen: a nearer one would lie inside */
        float reach = (float)r * CARRY_CELL_M;
        if (best >= 0 && best_d2 <= reach * reach)
            return best;
    }
    return best;
}

/* Orthonormal frame of triangle t (rows: edge, in-plane normal to it, face normal); 0 when the
 * triangle is degenerate. */
static int frame_of(const float (*v)[4], const int32_t *tri, float f[3][3])
{
    const float *a = v[tri[0]], *b = v[tri[1]], *c = v[tri[2]];
    float e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    float g[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    float n[3] = {e[1] * g[2] - e[2] * g[1], e[2] * g[0] - e[0] * g[2], e[0] * g[1] - e[1] * g[0]};
    float le = sqrtf(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    float ln = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(le > 1e-9f) || !(ln > 1e-12f))
        return 0;
    for (int k = 0; k < 3; k++) {
        f[0][k] = e[k] / le;
        f[2][k] = n[k] / ln;
    }
    f[1][0] = f[2][1] * f[0][2] - f[2][2] * f[0][1];
    f[1][1] = f[2][2] * f[0][0] - f[2][0] * f[0][2];
    f[1][2] = f[2][0] * f[0][1] - f[2][1] * f[0][0];
    return 1;
}

/* p moves with body vertex i: its offset turned as the triangle at i turned (F_k^T F_k-1). */
static void carry_point(const sim_carry *c, const carry_view *b, int i, float p[3])
{
    float d[3] = {p[0] - b->v_prev[i][0], p[1] - b->v_prev[i][1], p[2] - b->v_prev[i][2]};
    float f0[3][3], f1[3][3];
    int t = c->tri[i];
    if (t >= 0 && frame_of(b->v_prev, b->tris[t], f0) && frame_of(b->v, b->tris[t], f1)) {
        float l[3];
        for (int r = 0; r < 3; r++)
            l[r] = f0[r][0] * d[0] + f0[r][1] * d[1] + f0[r][2] * d[2];
        for (int k = 0; k < 3; k++)
            d[k] = f1[0][k] * l[0] + f1[1][k] * l[1] + f1[2][k] * l[2];
    }
    for (int k = 0; k < 3; k++)
        p[k] = b->v[i][k] + d[k];
}

int sim_carry_between(sim_carry *c, const float (*from)[4], const float (*to)[4],
                      const int32_t (*tris)[4], int nv, int nt, float (*x)[4], int n)
{
    if (!c || nv < 1 || nv > c->max_nv)
        return -1;
    carry_view view = {.v_prev = from, .v = to, .tris = tris, .nv = nv, .nt = nt}, *b = &view;
    build(c, b);
    double mean[3] = {0, 0, 0}; /* the body's mean move, for points far from it */
    for (int i = 0; i < b->nv; i++)
        for (int k = 0; k < 3; k++)
            mean[k] += (double)(b->v[i][k] - b->v_prev[i][k]) / b->nv;
    for (int p = 0; p < n; p++) {
        int i = nearest(c, b, x[p]);
        if (i >= 0) {
            carry_point(c, b, i, x[p]);
        } else {
            for (int k = 0; k < 3; k++)
                x[p][k] += (float)mean[k];
        }
    }
    return 0;
}

int sim_carry_points(sim_carry *c, const sim_body *b, float (*x)[4], int n)
{
    if (!b->have_prev)
        return -1;
    return sim_carry_between(c, (const float(*)[4])b->v_prev, (const float(*)[4])b->v,
                             (const int32_t(*)[4])b->tris, b->nv, b->nt, x, n);
}
