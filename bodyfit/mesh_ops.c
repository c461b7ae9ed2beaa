/* Mesh clean-up after marching tetrahedra: topology check, edge-collapse decimation down to the
 * wanted vertex count, and tangential smoothing projected back onto the implicit surface. */
#include "body_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A collapse may turn no neighbouring triangle's normal by more than about 75 degrees. */
#define BODY_COLLAPSE_MIN_COS 0.25f
/* Fraction of the way a smoothing pass moves a vertex toward its neighbours' centroid. */
#define BODY_SMOOTH_STEP 0.6f

static int uf_find(int *p, int x)
{
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

int body_mesh_topology(const body_mesh *m, int *euler, int *components)
{
    int *p = malloc((size_t)m->nv * sizeof(int));
    if (!p)
        return -FIT_ERR_NOMEM;
    for (int i = 0; i < m->nv; ++i)
        p[i] = i;
    long edges2 = 0;
    for (int t = 0; t < m->nt; ++t) {
        const int32_t *v = m->t + (size_t)t * 3;
        for (int e = 0; e < 3; ++e) {
            int a = uf_find(p, v[e]), b = uf_find(p, v[(e + 1) % 3]);
            if (a != b)
                p[a] = b;
        }
        edges2 += 3;
    }
    int comps = 0;
    for (int i = 0; i < m->nv; ++i)
        comps += uf_find(p, i) == i;
    free(p);
    *components = comps;
    *euler = m->nv - (int)(edges2 / 2) + m->nt;
    return 0;
}

/* Vertex -> incident triangles, compressed rows. */
typedef struct adjacency {
    int *start, *tri;
} adjacency;

static int adjacency_build(const body_mesh *m, adjacency *a)
{
    a->start = calloc((size_t)m->nv + 1, sizeof(int));
    a->tri = malloc((size_t)m->nt * 3 * sizeof(int));
    if (!a->start || !a->tri)
        return -FIT_ERR_NOMEM;
    for (int i = 0; i < m->nt * 3; ++i)
        a->start[m->t[i] + 1]++;
    for (int i = 0; i < m->nv; ++i)
        a->start[i + 1] += a->start[i];
    int *fill = malloc((size_t)m->nv * sizeof(int));
    if (!fill)
        return -FIT_ERR_NOMEM;
    memcpy(fill, a->start, (size_t)m->nv * sizeof(int));
    for (int i = 0; i < m->nt * 3; ++i)
        a->tri[fill[m->t[i]]++] = i / 3;
    free(fill);
    return 0;
}

static void adjacency_free(adjacency *a)
{
    free(a->start);
    free(a->tri);
}

/* Neighbours of v (unique) into out; returns the count (at most cap). */
static int neighbours(const body_mesh *m, const adjacency *a, int v, int *out, int cap)
{
    int n = 0;
    for (int i = a->start[v]; i < a->start[v + 1]; ++i) {
        const int32_t *t = m->t + (size_t)a->tri[i] * 3;
        for (int e = 0; e < 3; ++e) {
            int w = t[e], seen = (w == v);
            for (int k = 0; k < n && !seen; ++k)
                seen = out[k] == w;
            if (!seen && n < cap)
                out[n++] = w;
        }
    }
    return n;
}

static void tri_normal(const float *a, const float *b, const float *c, float n[3])
{
    float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    float v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
}

/* Would moving a and b to pos flip or crush a triangle around them? */
static int collapse_folds(const body_mesh *m, const adjacency *adj, int a, int b, const float *pos)
{
    int ends[2] = {a, b};
    for (int s = 0; s < 2; ++s) {
        int v = ends[s];
        for (int i = adj->start[v]; i < adj->start[v + 1]; ++i) {
            const int32_t *t = m->t + (size_t)adj->tri[i] * 3;
            int has_a = t[0] == a || t[1] == a || t[2] == a;
            int has_b = t[0] == b || t[1] == b || t[2] == b;
            if (has_a && has_b)
                continue;
            const float *p[3], *q[3];
            for (int e = 0; e < 3; ++e) {
                p[e] = m->v + (size_t)t[e] * 3;
                q[e] = (t[e] == v) ? pos : p[e];
            }
            float n0[3], n1[3];
            tri_normal(p[0], p[1], p[2], n0);
            tri_normal(q[0], q[1], q[2], n1);
            float d = body_dot(n0, n1);
            if (d <= BODY_COLLAPSE_MIN_COS * sqrtf(body_dot(n0, n0) * body_dot(n1, n1)))
                return 1;
        }
    }
    return 0;
}

/* Link condition: a and b share exactly the two vertices opposite their edge. */
static int link_ok(const body_mesh *m, const adjacency *adj, int a, int b)
{
    int na[64], nb[64];
    int ca = neighbours(m, adj, a, na, 64), cb = neighbours(m, adj, b, nb, 64);
    int common = 0;
    for (int i = 0; i < ca; ++i)
        for (int k = 0; k < cb; ++k)
            common += na[i] == nb[k];
    return common == 2 && ca < 64 && cb < 64;
}

static void lock_ring(const body_mesh *m, const adjacency *adj, int v, unsigned char *locked)
{
    for (int i = adj->start[v]; i < adj->start[v + 1]; ++i) {
        const int32_t *t = m->t + (size_t)adj->tri[i] * 3;
        locked[t[0]] = locked[t[1]] = locked[t[2]] = 1;
    }
}

typedef struct edge_len {
    float len2;
    int a, b;
} edge_len;

static int edge_cmp(const void *x, const void *y)
{
    const edge_len *p = x, *q = y;
    if (p->len2 != q->len2)
        return p->len2 < q->len2 ? -1 : 1;
    if (p->a != q->a)
        return p->a < q->a ? -1 : 1;
    return (p->b > q->b) - (p->b < q->b);
}

/* Drops dead triangles (first index -1) and vertices no triangle uses. */
static int compact(body_mesh *m)
{
    int *map = malloc((size_t)m->nv * sizeof(int));
    if (!map)
        return -FIT_ERR_NOMEM;
    for (int i = 0; i < m->nv; ++i)
        map[i] = -1;
    int nt = 0;
    for (int t = 0; t < m->nt; ++t) {
        if (m->t[(size_t)t * 3] < 0)
            continue;
        for (int e = 0; e < 3; ++e)
            m->t[(size_t)nt * 3 + e] = m->t[(size_t)t * 3 + e];
        ++nt;
    }
    m->nt = nt;
    int nv = 0;
    for (int i = 0; i < nt * 3; ++i)
        if (map[m->t[i]] < 0)
            map[m->t[i]] = 0;
    for (int i = 0; i < m->nv; ++i) {
        if (map[i] < 0)
            continue;
        map[i] = nv;
        memmove(m->v + (size_t)nv * 3, m->v + (size_t)i * 3, 3 * sizeof(float));
        ++nv;
    }
    for (int i = 0; i < nt * 3; ++i)
        m->t[i] = map[m->t[i]];
    m->nv = nv;
    free(map);
    return 0;
}

static void do_collapse(body_mesh *m, const adjacency *adj, int a, int b, const float *pos)
{
    for (int k = 0; k < 3; ++k)
        m->v[(size_t)b * 3 + k] = pos[k];
    for (int i = adj->start[a]; i < adj->start[a + 1]; ++i) {
        int32_t *t = m->t + (size_t)adj->tri[i] * 3;
        if (t[0] < 0)
            continue;
        if (t[0] == b || t[1] == b || t[2] == b) {
            t[0] = t[1] = t[2] = -1;
            continue;
        }
        for (int e = 0; e < 3; ++e)
            if (t[e] == a)
                t[e] = b;
    }
}

/* One pass: collapse the shortest edges below max_len2, each vertex at most once. */
static int collapse_pass(const body_field *f, body_mesh *m, int target, float max_len2,
                         int *collapsed)
{
    adjacency adj = {0};
    edge_len *edges = malloc((size_t)m->nt * 3 * sizeof(edge_len));
    unsigned char *locked = calloc((size_t)m->nv, 1);
    int rc = (edges && locked) ? adjacency_build(m, &adj) : -FIT_ERR_NOMEM;
    int ne = 0, done = 0;
    for (int t = 0; !rc && t < m->nt; ++t) {
        const int32_t *v = m->t + (size_t)t * 3;
        for (int e = 0; e < 3; ++e) {
            int a = v[e], b = v[(e + 1) % 3];
            if (a > b)
                continue;
            const float *p = m->v + (size_t)a * 3, *q = m->v + (size_t)b * 3;
            float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
            edges[ne++] = (edge_len){body_dot(d, d), a, b};
        }
    }
    if (!rc)
        qsort(edges, (size_t)ne, sizeof(edge_len), edge_cmp);
    for (int i = 0; !rc && i < ne && m->nv - done > target; ++i) {
        int a = edges[i].a, b = edges[i].b;
        if (edges[i].len2 > max_len2)
            break;
        if (locked[a] || locked[b] || !link_ok(m, &adj, a, b))
            continue;
        const float *p = m->v + (size_t)a * 3, *q = m->v + (size_t)b * 3;
        float mid[3] = {0.5f * (p[0] + q[0]), 0.5f * (p[1] + q[1]), 0.5f * (p[2] + q[2])};
        body_field_project(f, mid);
        if (collapse_folds(m, &adj, a, b, mid))
            continue;
        lock_ring(m, &adj, a, locked);
        lock_ring(m, &adj, b, locked);
        do_collapse(m, &adj, a, b, mid);
        ++done;
    }
    adjacency_free(&adj);
    free(edges);
    free(locked);
    *collapsed = done;
    return rc ? rc : compact(m);
}

static float mesh_area(const body_mesh *m)
{
    double a = 0.0;
    for (int t = 0; t < m->nt; ++t) {
        const int32_t *v = m->t + (size_t)t * 3;
        float n[3];
        tri_normal(m->v + (size_t)v[0] * 3, m->v + (size_t)v[1] * 3, m->v + (size_t)v[2] * 3, n);
        a += 0.5 * sqrt((double)body_dot(n, n));
    }
    return (float)a;
}

int body_mesh_decimate(const body_field *f, body_mesh *m, int target)
{
    /* Edge length of an equilateral mesh with target vertices (2 triangles per vertex). */
    float len2 = 2.0f * mesh_area(m) / (sqrtf(3.0f) * (float)target);
    float factor = 1.0f;
    for (int pass = 0; pass < 60 && m->nv > target; ++pass) {
        int done = 0;
        int rc = collapse_pass(f, m, target, factor * len2, &done);
        if (rc)
            return rc;
        if (done < m->nv / 100)
            factor *= 1.3f;
        if (pass % 4 == 3)
            body_mesh_smooth(f, m, 1);
    }
    return 0;
}

/* Tangential umbrella smoothing: each vertex moves toward its neighbours' centroid within its
 * tangent plane, then back onto the surface. Jacobi order, so the result is order-free. */
void body_mesh_smooth(const body_field *f, body_mesh *m, int passes)
{
    float *acc = malloc((size_t)m->nv * 4 * sizeof(float));
    if (!acc)
        return;
    for (int pass = 0; pass < passes; ++pass) {
        memset(acc, 0, (size_t)m->nv * 4 * sizeof(float));
        for (int t = 0; t < m->nt; ++t) {
            const int32_t *v = m->t + (size_t)t * 3;
            for (int e = 0; e < 3; ++e) {
                float *a = acc + (size_t)v[e] * 4;
                const float *p = m->v + (size_t)v[(e + 1) % 3] * 3;
                a[0] += p[0];
                a[1] += p[1];
                a[2] += p[2];
                a[3] += 1.0f;
            }
        }
        for (int i = 0; i < m->nv; ++i) {
            float *p = m->v + (size_t)i * 3, *a = acc + (size_t)i * 4, g[3];
            if (a[3] <= 0.0f)
                continue;
            float d[3] = {a[0] / a[3] - p[0], a[1] / a[3] - p[1], a[2] / a[3] - p[2]};
            body_field_grad(f, p, g);
            float g2 = body_dot(g, g), dn = body_dot(d, g);
            for (int k = 0; k < 3; ++k)
                a[k] = p[k] + BODY_SMOOTH_STEP * (d[k] - (g2 > 0.0f ? dn * g[k] / g2 : 0.0f));
        }
        for (int i = 0; i < m->nv; ++i) {
            float *p = m->v + (size_t)i * 3;
            const float *a = acc + (size_t)i * 4;
            if (a[3] <= 0.0f)
                continue;
            p[0] = a[0];
            p[1] = a[1];
            p[2] = a[2];
            body_field_project(f, p);
        }
    }
    free(acc);
}
