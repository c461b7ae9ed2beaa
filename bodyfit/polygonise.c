/* Marching tetrahedra over a regular grid, each cube split into the six Kuhn tetrahedra that
 * share its main diagonal. The split is the same in every cube, so neighbouring tetrahedra
 * share faces and the surface is closed and manifold; one vertex per crossed grid edge. */
#include "body_internal.h"

#include <math.h>
#include <stdlib.h>

/* Grid values closer to zero than this fraction of h are pushed outside, so no surface vertex
 * lands on a grid point (which would make zero-area triangles). */
#define BODY_SNAP 0.02f

typedef struct grid {
    int nx, ny, nz;
    float h, o[3];
    float *val;
    int32_t *edge_vid; /* [point][7] vertex on the edge from the point along direction d */
    body_mesh *out;
    int cap_v, cap_t;
    const body_field *f;
} grid;

static size_t gidx(const grid *g, int i, int j, int k)
{
    return ((size_t)k * (size_t)g->ny + (size_t)j) * (size_t)g->nx + (size_t)i;
}

static int grow(body_mesh *m, int *cap_v, int *cap_t)
{
    if (m->nv + 4 > *cap_v) {
        int c = *cap_v * 2 + 1024;
        float *v = realloc(m->v, (size_t)c * 3 * sizeof(float));
        if (!v)
            return -FIT_ERR_NOMEM;
        m->v = v;
        *cap_v = c;
    }
    if (m->nt + 4 > *cap_t) {
        int c = *cap_t * 2 + 2048;
        int32_t *t = realloc(m->t, (size_t)c * 3 * sizeof(int32_t));
        if (!t)
            return -FIT_ERR_NOMEM;
        m->t = t;
        *cap_t = c;
    }
    return 0;
}

static void point_pos(const grid *g, const int c[3], float p[3])
{
    for (int k = 0; k < 3; ++k)
        p[k] = g->o[k] + g->h * (float)c[k];
}

/* Vertex on the edge between grid points c0 and c1 (c1 - c0 a 0/1 vector, not zero). */
static int32_t edge_vertex(grid *g, const int c0[3], const int c1[3])
{
    int d = (c1[0] - c0[0]) + 2 * (c1[1] - c0[1]) + 4 * (c1[2] - c0[2]);
    const int *lo = c0, *hi = c1;
    if (d < 0) {
        lo = c1;
        hi = c0;
        d = -d;
    }
    size_t slot = gidx(g, lo[0], lo[1], lo[2]) * 7 + (size_t)(d - 1);
    if (g->edge_vid[slot] >= 0)
        return g->edge_vid[slot];
    float f0 = g->val[gidx(g, lo[0], lo[1], lo[2])], f1 = g->val[gidx(g, hi[0], hi[1], hi[2])];
    float p0[3], p1[3], t = f0 / (f0 - f1);
    point_pos(g, lo, p0);
    point_pos(g, hi, p1);
    body_mesh *m = g->out;
    float *p = m->v + (size_t)m->nv * 3;
    for (int k = 0; k < 3; ++k)
        p[k] = p0[k] + t * (p1[k] - p0[k]);
    g->edge_vid[slot] = m->nv;
    return m->nv++;
}

static void emit(grid *g, int32_t a, int32_t b, int32_t c)
{
    int32_t *t = g->out->t + (size_t)g->out->nt * 3;
    t[0] = a;
    t[1] = b;
    t[2] = c;
    g->out->nt++;
}

/* Emits the polygon (3 or 4 vertices, in cyclic order) facing from inside to outside. */
static void emit_polygon(grid *g, const int32_t *q, int n, const float out_dir[3])
{
    const float *v = g->out->v;
    float nrm[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) { /* Newell's normal: robust for thin polygons */
        const float *a = v + (size_t)q[i] * 3, *b = v + (size_t)q[(i + 1) % n] * 3;
        nrm[0] += (a[1] - b[1]) * (a[2] + b[2]);
        nrm[1] += (a[2] - b[2]) * (a[0] + b[0]);
        nrm[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    int flip = body_dot(nrm, out_dir) < 0.0f;
    int32_t r[4];
    for (int i = 0; i < n; ++i)
        r[i] = flip ? q[n - 1 - i] : q[i];
    if (n == 3) {
        emit(g, r[0], r[1], r[2]);
        return;
    }
    /* Split the quad along its shorter diagonal. */
    const float *p0 = v + (size_t)r[0] * 3, *p1 = v + (size_t)r[1] * 3;
    const float *p2 = v + (size_t)r[2] * 3, *p3 = v + (size_t)r[3] * 3;
    float d02 = 0, d13 = 0;
    for (int k = 0; k < 3; ++k) {
        d02 += (p0[k] - p2[k]) * (p0[k] - p2[k]);
        d13 += (p1[k] - p3[k]) * (p1[k] - p3[k]);
    }
    if (d02 <= d13) {
        emit(g, r[0], r[1], r[2]);
        emit(g, r[0], r[2], r[3]);
    } else {
        emit(g, r[0], r[1], r[3]);
        emit(g, r[1], r[2], r[3]);
    }
}

static void do_tet(grid *g, const int c[4][3])
{
    int in[4], out[4], ni = 0, no = 0;
    for (int i = 0; i < 4; ++i) {
        if (g->val[gidx(g, c[i][0], c[i][1], c[i][2])] < 0.0f)
            in[ni++] = i;
        else
            out[no++] = i;
    }
    if (ni == 0 || no == 0)
        return;
    float dir[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < no; ++i)
            dir[k] += (float)c[out[i]][k] / (float)no;
        for (int i = 0; i < ni; ++i)
            dir[k] -= (float)c[in[i]][k] / (float)ni;
    }
    int32_t q[4];
    if (ni == 1 || no == 1) {
        int lone = ni == 1 ? in[0] : out[0];
        const int *rest = ni == 1 ? out : in;
        for (int i = 0; i < 3; ++i)
            q[i] = edge_vertex(g, c[lone], c[rest[i]]);
        emit_polygon(g, q, 3, dir);
        return;
    }
    q[0] = edge_vertex(g, c[in[0]], c[out[0]]);
    q[1] = edge_vertex(g, c[in[0]], c[out[1]]);
    q[2] = edge_vertex(g, c[in[1]], c[out[1]]);
    q[3] = edge_vertex(g, c[in[1]], c[out[0]]);
    emit_polygon(g, q, 4, dir);
}

static const int kuhn_perm[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                    {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};

static int do_cube(grid *g, int i, int j, int k)
{
    int any_in = 0, any_out = 0;
    for (int n = 0; n < 8; ++n) {
        float v = g->val[gidx(g, i + (n & 1), j + ((n >> 1) & 1), k + ((n >> 2) & 1))];
        any_in |= v < 0.0f;
        any_out |= v >= 0.0f;
    }
    if (!any_in || !any_out)
        return 0;
    for (int t = 0; t < 6; ++t) {
        int rc = grow(g->out, &g->cap_v, &g->cap_t);
        if (rc)
            return rc;
        int c[4][3];
        int cur[3] = {i, j, k};
        for (int s = 0; s < 4; ++s) {
            if (s > 0)
                cur[kuhn_perm[t][s - 1]] += 1;
            c[s][0] = cur[0];
            c[s][1] = cur[1];
            c[s][2] = cur[2];
        }
        do_tet(g, c);
    }
    return 0;
}

static void fill_values(grid *g)
{
    float snap = BODY_SNAP * g->h;
    for (int k = 0; k < g->nz; ++k)
        for (int j = 0; j < g->ny; ++j)
            for (int i = 0; i < g->nx; ++i) {
                int c[3] = {i, j, k};
                float p[3];
                point_pos(g, c, p);
                float v = body_field_eval(g->f, p);
                if (fabsf(v) < snap)
                    v = snap;
                g->val[gidx(g, i, j, k)] = v;
            }
}

int body_polygonise(const body_field *f, float h, const float offset[3], body_mesh *out)
{
    grid g = {0};
    g.f = f;
    g.h = h;
    g.out = out;
    out->v = NULL;
    out->t = NULL;
    out->nv = out->nt = 0;
    for (int k = 0; k < 3; ++k)
        g.o[k] = f->lo[k] - h + offset[k];
    g.nx = (int)((f->hi[0] - g.o[0]) / h) + 3;
    g.ny = (int)((f->hi[1] - g.o[1]) / h) + 3;
    g.nz = (int)((f->hi[2] - g.o[2]) / h) + 3;
    size_t np = (size_t)g.nx * (size_t)g.ny * (size_t)g.nz;
    g.val = malloc(np * sizeof(float));
    g.edge_vid = malloc(np * 7 * sizeof(int32_t));
    int rc = (g.val && g.edge_vid) ? 0 : -FIT_ERR_NOMEM;
    if (!rc) {
        for (size_t i = 0; i < np * 7; ++i)
            g.edge_vid[i] = -1;
        fill_values(&g);
        for (int k = 0; k + 1 < g.nz && !rc; ++k)
            for (int j = 0; j + 1 < g.ny && !rc; ++j)
                for (int i = 0; i + 1 < g.nx && !rc; ++i)
                    rc = do_cube(&g, i, j, k);
    }
    free(g.val);
    free(g.edge_vid);
    if (!rc && out->nt == 0)
        rc = -FIT_ERR_MESH;
    if (rc) {
        body_mesh_free(out);
        return rc;
    }
    for (int i = 0; i < out->nv; ++i)
        body_field_project(f, out->v + (size_t)i * 3);
    return 0;
}

void body_mesh_free(body_mesh *m)
{
    if (!m)
        return;
    free(m->v);
    free(m->t);
    m->v = NULL;
    m->t = NULL;
    m->nv = m->nt = 0;
}
