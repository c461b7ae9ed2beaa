/* The seed's three spring families on a triangle mesh, with rest lengths from the flat panels. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dress_internal.h"

/* Two neighbours of a vertex nearly opposite (more than 150 degrees apart in the panel) are
 * joined by a bend spring: the triangle-mesh form of the grid's skip-one springs. */
#define GAR_BEND_COS -0.866f

typedef struct half {
    int32_t a, b, opp; /* a < b */
} half;

static int half_cmp(const void *x, const void *y)
{
    const half *p = x, *q = y;
    return p->a != q->a ? (p->a > q->a) - (p->a < q->a) : (p->b > q->b) - (p->b < q->b);
}

static float rest(const gar_mesh *m, int i, int j)
{
    return hypotf(m->uv_m[2 * i] - m->uv_m[2 * j], m->uv_m[2 * i + 1] - m->uv_m[2 * j + 1]);
}

static int add(gar_springs *s, int *cap, const gar_mesh *m, int i, int j, gar_spring_kind k)
{
    if (s->n == *cap) {
        *cap = 2 * *cap + 64;
        int32_t *e = realloc(s->ends, (size_t)*cap * 2 * sizeof *e);
        float *r = e ? realloc(s->rest_m, (size_t)*cap * sizeof *r) : NULL;
        uint8_t *kk = r ? realloc(s->kind, (size_t)*cap) : NULL;
        s->ends = e ? e : s->ends;
        s->rest_m = r ? r : s->rest_m;
        if (!kk)
            return -GAR_ERR_NO_MEMORY;
        s->kind = kk;
    }
    s->ends[2 * s->n] = i, s->ends[2 * s->n + 1] = j;
    s->rest_m[s->n] = rest(m, i, j);
    s->kind[s->n++] = (uint8_t)k;
    return 0;
}

static int build_csr(gar_springs *s, int nv)
{
    s->vert_offset = calloc((size_t)nv + 1, sizeof *s->vert_offset);
    s->vert_springs = malloc((size_t)(2 * s->n + 1) * sizeof *s->vert_springs);
    int *fill = malloc((size_t)(nv + 1) * sizeof *fill);
    if (!s->vert_offset || !s->vert_springs || !fill) {
        free(fill);
        return -GAR_ERR_NO_MEMORY;
    }
    for (int i = 0; i < 2 * s->n; i++)
        s->vert_offset[s->ends[i] + 1]++;
    for (int v = 0; v < nv; v++)
        s->vert_offset[v + 1] += s->vert_offset[v];
    memcpy(fill, s->vert_offset, (size_t)(nv + 1) * sizeof *fill);
    for (int i = 0; i < 2 * s->n; i++)
        s->vert_springs[fill[s->ends[i]]++] = i / 2;
    free(fill);
    return 0;
}

int gar_springs_build(const gar_mesh *m, gar_springs *s)
{
    memset(s, 0, sizeof *s);
    int nh = 3 * m->num_triangles, cap = 0, rc = 0;
    half *h = malloc((size_t)(nh ? nh : 1) * sizeof *h);
    if (!h)
        return -GAR_ERR_NO_MEMORY;
    for (int t = 0; t < m->num_triangles; t++)
        for (int e = 0; e < 3; e++) {
            int32_t a = m->triangles[3 * t + e], b = m->triangles[3 * t + (e + 1) % 3];
            h[3 * t + e] = (half){a < b ? a : b, a < b ? b : a, m->triangles[3 * t + (e + 2) % 3]};
        }
    qsort(h, (size_t)nh, sizeof *h, half_cmp);
    for (int i = 0; i < nh && !rc; i++)
        if (i == 0 || h[i].a != h[i - 1].a || h[i].b != h[i - 1].b)
            rc = add(s, &cap, m, h[i].a, h[i].b, GAR_STRETCH);
    s->n_stretch = s->n;
    for (int i = 1; i < nh && !rc; i++)
        if (h[i].a == h[i - 1].a && h[i].b == h[i - 1].b)
            rc = add(s, &cap, m, h[i].opp, h[i - 1].opp, GAR_SHEAR);
    free(h);
    if (!rc)
        rc = build_csr(s, m->num_vertices);
    /* Bend: over each vertex's stretch neighbours. */
    for (int v = 0; v < m->num_vertices && !rc; v++)
        for (int p = s->vert_offset[v]; p < s->vert_offset[v + 1] && !rc; p++)
            for (int q = p + 1; q < s->vert_offset[v + 1] && !rc; q++) {
                int sp = s->vert_springs[p], sq = s->vert_springs[q];
                if (s->kind[sp] != GAR_STRETCH || s->kind[sq] != GAR_STRETCH)
                    continue;
                int a = s->ends[2 * sp] == v ? s->ends[2 * sp + 1] : s->ends[2 * sp];
                int b = s->ends[2 * sq] == v ? s->ends[2 * sq + 1] : s->ends[2 * sq];
                float ax = m->uv_m[2 * a] - m->uv_m[2 * v],
                      ay = m->uv_m[2 * a + 1] - m->uv_m[2 * v + 1];
                float bx = m->uv_m[2 * b] - m->uv_m[2 * v],
                      by = m->uv_m[2 * b + 1] - m->uv_m[2 * v + 1];
                float c = (ax * bx + ay * by) / (hypotf(ax, ay) * hypotf(bx, by));
                if (c < GAR_BEND_COS)
                    rc = add(s, &cap, m, a, b, GAR_BEND);
            }
    if (!rc) { /* the bend springs join the per-vertex lists */
        free(s->vert_offset), free(s->vert_springs);
        rc = build_csr(s, m->num_vertices);
    }
    if (rc)
        gar_springs_free(s);
    return rc;
}

void gar_springs_free(gar_springs *s)
{
    free(s->ends), free(s->rest_m), free(s->kind), free(s->vert_offset), free(s->vert_springs);
    memset(s, 0, sizeof *s);
}
