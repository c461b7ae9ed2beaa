/* Cloth-cloth between panels (seed 003): per panel a tree whose every node splits its triangles
 * in four (by the quadrants of its panel-space box); two panels' trees are tested box against
 * box, recursing into the four children of each, each recursive call an OpenMP task. Leaves
 * repel vertices from the other panel's triangles, or count edges through them (a crossing). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cloth_cloth.h"

#define LEAF_TRIANGLES 8

typedef struct qnode {
    int first, count; /* into tri */
    int child[4];     /* -1 none */
    float lo[3], hi[3];
} qnode;

struct gar_cc {
    const gar_mesh *m;
    int32_t *tri; /* triangles permuted so each node's are contiguous */
    qnode *node;
    int n_nodes, cap;
    int *root;           /* per panel */
    const uint8_t *skip; /* vertices near a seam: the panels meet there by design */
};

static void tri_uv_centre(const gar_mesh *m, int t, float c[2])
{
    c[0] = c[1] = 0;
    for (int e = 0; e < 3; e++)
        c[0] += m->uv_m[2 * m->triangles[3 * t + e]] / 3,
            c[1] += m->uv_m[2 * m->triangles[3 * t + e] + 1] / 3;
}

static int build(gar_cc *cc, int first, int count)
{
    if (cc->n_nodes == cc->cap)
        return -1;
    int id = cc->n_nodes++;
    qnode *nd = &cc->node[id];
    nd->first = first, nd->count = count;
    for (int k = 0; k < 4; k++)
        nd->child[k] = -1;
    if (count <= LEAF_TRIANGLES)
        return id;
    float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, c[2];
    for (int i = first; i < first + count; i++) {
        tri_uv_centre(cc->m, cc->tri[i], c);
        for (int k = 0; k < 2; k++)
            lo[k] = fminf(lo[k], c[k]), hi[k] = fmaxf(hi[k], c[k]);
    }
    float mid[2] = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2};
    /* Partition into quadrants 0..3 in place (a counting pass per quadrant). */
    int at = first, bounds[5];
    for (int q = 0; q < 4; q++) {
        bounds[q] = at;
        for (int i = at; i < first + count; i++) {
            tri_uv_centre(cc->m, cc->tri[i], c);
            if ((c[0] >= mid[0]) + 2 * (c[1] >= mid[1]) == q) {
                int32_t tmp = cc->tri[i];
                cc->tri[i] = cc->tri[at], cc->tri[at++] = tmp;
            }
        }
    }
    bounds[4] = first + count;
    for (int q = 0; q < 4; q++) {
        int n = bounds[q + 1] - bounds[q];
        if (n == count) /* all centres equal: stop splitting */
            return id;
        if (n > 0) {
            int ch = build(cc, bounds[q], n);
            if (ch < 0)
                return -1;
            cc->node[id].child[q] = ch;
        }
    }
    return id;
}

gar_cc *gar_cc_create(const gar_mesh *m, const uint8_t *skip)
{
    gar_cc *cc = calloc(1, sizeof *cc);
    if (!cc)
        return NULL;
    cc->m = m, cc->skip = skip;
    cc->cap = 2 * m->num_triangles + 4 * m->num_panels + 16;
    cc->tri = malloc((size_t)(m->num_triangles + 1) * sizeof *cc->tri);
    cc->node = malloc((size_t)cc->cap * sizeof *cc->node);
    cc->root = malloc((size_t)m->num_panels * sizeof *cc->root);
    if (!cc->tri || !cc->node || !cc->root) {
        gar_cc_destroy(cc);
        return NULL;
    }
    int at = 0;
    for (int p = 0; p < m->num_panels; p++) {
        int first = at;
        for (int t = 0; t < m->num_triangles; t++)
            if (m->panel_of[m->triangles[3 * t]] == p)
                cc->tri[at++] = t;
        cc->root[p] = at > first ? build(cc, first, at - first) : -1;
        if (at > first && cc->root[p] < 0) {
            gar_cc_destroy(cc);
            return NULL;
        }
    }
    return cc;
}

void gar_cc_destroy(gar_cc *cc)
{
    if (!cc)
        return;
    free(cc->tri), free(cc->node), free(cc->root), free(cc);
}

static void refit(gar_cc *cc, int id, const float *x, float pad)
{
    qnode *nd = &cc->node[id];
    for (int k = 0; k < 3; k++)
        nd->lo[k] = INFINITY, nd->hi[k] = -INFINITY;
    for (int i = nd->first; i < nd->first + nd->count; i++)
        for (int e = 0; e < 3; e++) {
            const float *p = x + 3 * cc->m->triangles[3 * cc->tri[i] + e];
            for (int k = 0; k < 3; k++)
                nd->lo[k] = fminf(nd->lo[k], p[k] - pad), nd->hi[k] = fmaxf(nd->hi[k], p[k] + pad);
        }
}

static int overlap(const qnode *a, const qnode *b)
{
    for (int k = 0; k < 3; k++)
        if (a->lo[k] > b->hi[k] || b->lo[k] > a->hi[k])
            return 0;
    return 1;
}

typedef struct cc_job {
    gar_cc *cc;
    const float *x;
    float thickness;
    float *push; /* [vertex][3] accumulated repulsion, NULL when counting */
    int crossings;
} cc_job;

/* Vertex p against triangle abc: within thickness of its plane over the triangle -> pushed to
 * the side it is on. */
static void repel(cc_job *j, int v, const int32_t *t)
{
    const float *p = j->x + 3 * v, *a = j->x + 3 * t[0], *b = j->x + 3 * t[1], *c = j->x + 3 * t[2];
    float e1[3], e2[3], n[3], d[3];
    for (int k = 0; k < 3; k++)
        e1[k] = b[k] - a[k], e2[k] = c[k] - a[k], d[k] = p[k] - a[k];
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(l > 0))
        return;
    for (int k = 0; k < 3; k++)
        n[k] /= l;
    float h = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    if (fabsf(h) >= j->thickness)
        return;
    /* Inside the triangle (barycentric test in its plane). */
    float d00 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2];
    float d01 = e1[0] * e2[0] + e1[1] * e2[1] + e1[2] * e2[2];
    float d11 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    float d20 = d[0] * e1[0] + d[1] * e1[1] + d[2] * e1[2];
    float d21 = d[0] * e2[0] + d[1] * e2[1] + d[2] * e2[2];
    float den = d00 * d11 - d01 * d01, bv = (d11 * d20 - d01 * d21) / den,
          bw = (d00 * d21 - d01 * d20) / den;
    if (bv < 0 || bw < 0 || bv + bw > 1)
        return;
    float move = (h >= 0 ? 1 : -1) * j->thickness - h;
    for (int k = 0; k < 3; k++) {
#pragma omp atomic
        j->push[3 * v + k] += 0.5f * move * n[k];
    }
}

/* Segment pq through triangle abc (Moller-Trumbore on the segment). */
static int segment_hits(const float *p, const float *q, const float *a, const float *b,
                        const float *c)
{
    float dir[3], e1[3], e2[3], s[3], h[3], qq[3];
    for (int k = 0; k < 3; k++)
        dir[k] = q[k] - p[k], e1[k] = b[k] - a[k], e2[k] = c[k] - a[k], s[k] = p[k] - a[k];
    h[0] = dir[1] * e2[2] - dir[2] * e2[1];
    h[1] = dir[2] * e2[0] - dir[0] * e2[2];
    h[2] = dir[0] * e2[1] - dir[1] * e2[0];
    float det = e1[0] * h[0] + e1[1] * h[1] + e1[2] * h[2];
    if (fabsf(det) < 1e-14f)
        return 0;
    float u = (s[0] * h[0] + s[1] * h[1] + s[2] * h[2]) / det;
    if (u < 0 || u > 1)
        return 0;
    qq[0] = s[1] * e1[2] - s[2] * e1[1];
    qq[1] = s[2] * e1[0] - s[0] * e1[2];
    qq[2] = s[0] * e1[1] - s[1] * e1[0];
    float v = (dir[0] * qq[0] + dir[1] * qq[1] + dir[2] * qq[2]) / det;
    if (v < 0 || u + v > 1)
        return 0;
    float t = (e2[0] * qq[0] + e2[1] * qq[1] + e2[2] * qq[2]) / det;
    return t > 0 && t < 1;
}

static int near_seam(const cc_job *j, const int32_t *t)
{
    return j->cc->skip[t[0]] || j->cc->skip[t[1]] || j->cc->skip[t[2]];
}

static void leaf(cc_job *j, const qnode *a, const qnode *b)
{
    const gar_mesh *m = j->cc->m;
    for (int i = a->first; i < a->first + a->count; i++) {
        const int32_t *ta = m->triangles + 3 * j->cc->tri[i];
        if (near_seam(j, ta))
            continue;
        for (int k = b->first; k < b->first + b->count; k++) {
            const int32_t *tb = m->triangles + 3 * j->cc->tri[k];
            if (near_seam(j, tb))
                continue;
            for (int e = 0; e < 3; e++) {
                if (j->push) {
                    repel(j, ta[e], tb);
                    repel(j, tb[e], ta);
                    continue;
                }
                int hits = segment_hits(j->x + 3 * ta[e], j->x + 3 * ta[(e + 1) % 3],
                                        j->x + 3 * tb[0], j->x + 3 * tb[1], j->x + 3 * tb[2]) +
                           segment_hits(j->x + 3 * tb[e], j->x + 3 * tb[(e + 1) % 3],
                                        j->x + 3 * ta[0], j->x + 3 * ta[1], j->x + 3 * ta[2]);
                if (hits) {
#pragma omp atomic
                    j->crossings += hits;
                }
            }
        }
    }
}

/* The seed's recursion: boxes overlap -> split both in four and test every pair, each call a
 * task. */
static void collide(cc_job *j, int ia, int ib)
{
    const qnode *a = &j->cc->node[ia], *b = &j->cc->node[ib];
    if (!overlap(a, b))
        return;
    int la = a->child[0] < 0 && a->child[1] < 0 && a->child[2] < 0 && a->child[3] < 0;
    int lb = b->child[0] < 0 && b->child[1] < 0 && b->child[2] < 0 && b->child[3] < 0;
    if (la && lb) {
        leaf(j, a, b);
        return;
    }
    for (int p = 0; p < 4; p++)
        for (int q = 0; q < 4; q++) {
            int ca = la ? (p ? -1 : ia) : a->child[p], cb = lb ? (q ? -1 : ib) : b->child[q];
            if (ca < 0 || cb < 0)
                continue;
#pragma omp task firstprivate(ca, cb) if (a->count + b->count > 256)
            collide(j, ca, cb);
        }
#pragma omp taskwait
}

static int run(gar_cc *cc, const float *x, float thickness, float *push)
{
    cc_job j = {cc, x, thickness, push, 0};
    for (int id = cc->n_nodes - 1; id >= 0; id--)
        refit(cc, id, x, thickness);
#pragma omp parallel
#pragma omp single
    for (int a = 0; a < cc->m->num_panels; a++)
        for (int b = a + 1; b < cc->m->num_panels; b++)
            if (cc->root[a] >= 0 && cc->root[b] >= 0)
                collide(&j, cc->root[a], cc->root[b]);
    return j.crossings;
}

void gar_cc_repel(gar_cc *cc, const float *x, float thickness, float *push)
{
    run(cc, x, thickness, push);
}

int gar_cc_crossings(gar_cc *cc, const float *x)
{
    return run(cc, x, 0, NULL);
}
