/* A sewn pattern garment held on the body by its highest opening (pattern_hold.h). */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"
#include "pattern_hold.h"

typedef struct edge {
    int32_t a, b; /* a < b */
} edge;

static int edge_cmp(const void *p, const void *q)
{
    const edge *x = p, *y = q;
    return x->a != y->a ? (x->a > y->a) - (x->a < y->a) : (x->b > y->b) - (x->b < y->b);
}

static int32_t root_of(int32_t *parent, int32_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

/* Marks in on_edge the vertices of boundary edges (used by one triangle) and joins each such
 * edge's ends in parent. Returns 0 or -1 (out of memory). */
static int boundary(const sim_garment *g, int32_t *parent, uint8_t *on_edge)
{
    int ne = g->num_triangles * 3;
    edge *e = malloc((size_t)ne * sizeof *e);
    if (!e)
        return -1;
    for (int t = 0; t < g->num_triangles; t++)
        for (int k = 0; k < 3; k++) {
            int32_t a = g->triangles[t * 3 + k], b = g->triangles[t * 3 + (k + 1) % 3];
            e[t * 3 + k] = (edge){a < b ? a : b, a < b ? b : a};
        }
    qsort(e, (size_t)ne, sizeof *e, edge_cmp);
    for (int i = 0; i < g->num_vertices; i++)
        parent[i] = i;
    for (int i = 0; i < ne;) {
        int j = i + 1;
        while (j < ne && e[j].a == e[i].a && e[j].b == e[i].b)
            j++;
        if (j - i == 1) {
            on_edge[e[i].a] = on_edge[e[i].b] = 1;
            int32_t ra = root_of(parent, e[i].a), rb = root_of(parent, e[i].b);
            if (ra != rb)
                parent[ra] = rb;
        }
        i = j;
    }
    free(e);
    return 0;
}

/* The boundary component of the highest mean height: its root, or -1 when there is none. */
static int32_t highest_opening(const sim_garment *g, int32_t *parent, const uint8_t *on_edge)
{
    int nv = g->num_vertices;
    double *sum = calloc((size_t)nv * 2, sizeof *sum);
    int32_t best = -1;
    if (!sum)
        return -1;
    for (int i = 0; i < nv; i++)
        if (on_edge[i]) {
            int32_t r = root_of(parent, i);
            sum[r * 2] += g->xyz[i * 3 + 1];
            sum[r * 2 + 1] += 1.0;
        }
    double top = -DBL_MAX;
    for (int i = 0; i < nv; i++)
        if (sum[i * 2 + 1] > 0.0 && sum[i * 2] / sum[i * 2 + 1] > top) {
            top = sum[i * 2] / sum[i * 2 + 1];
            best = i;
        }
    free(sum);
    return best;
}

/* Body vertex nearest p (brute force: an opening has a few hundred vertices). */
static int nearest_vertex(const float *p, const float *xyz, int nv)
{
    int best = 0;
    float bd = FLT_MAX;
    for (int v = 0; v < nv; v++) {
        float dx = p[0] - xyz[v * 3], dy = p[1] - xyz[v * 3 + 1], dz = p[2] - xyz[v * 3 + 2];
        float d = dx * dx + dy * dy + dz * dz;
        if (d < bd) {
            bd = d;
            best = v;
        }
    }
    return best;
}

int sim_pattern_hold(sim_garment *g, const float *body_xyz, int nv, const int32_t *tris, int nt,
                     sim_reject *why)
{
    int gv = g->num_vertices;
    int32_t *parent = malloc((size_t)gv * sizeof *parent);
    int32_t *tri_of = calloc((size_t)nv, sizeof *tri_of); /* a triangle at each body vertex */
    uint8_t *on_edge = calloc((size_t)gv, 1);
    sim_attachment *at = malloc((size_t)gv * sizeof *at);
    int na = 0, r = 0;
    if (!parent || !tri_of || !on_edge || !at || boundary(g, parent, on_edge) < 0)
        r = sim_reject_set(why, SIM_ERR_NO_MEMORY, "holding a garment of %d vertices", gv);
    int32_t top = r == 0 ? highest_opening(g, parent, on_edge) : -1;
    if (r == 0 && top < 0)
        r = sim_reject_set(why, SIM_ERR_ATTACHMENT, "the garment has no opening to hold it by");
    for (int t = 0; r == 0 && t < nt; t++)
        for (int k = 0; k < 3; k++)
            tri_of[tris[t * 3 + k]] = t;
    for (int i = 0; r == 0 && i < gv; i++) {
        if (!on_edge[i] || root_of(parent, i) != root_of(parent, top))
            continue;
        /* the foot at the body vertex (a corner of tri_of's triangle); the rebind below glues
           the vertex exactly to the triangle nearest that foot */
        int v = nearest_vertex(&g->xyz[i * 3], body_xyz, nv);
        int t = tri_of[v];
        at[na] = (sim_attachment){.vertex = i, .body_triangle = t};
        for (int k = 0; k < 3; k++)
            at[na].bary[k] = tris[t * 3 + k] == v ? 1.0f : 0.0f;
        na++;
    }
    if (r == 0) {
        free(g->attachments);
        g->attachments = at;
        g->num_attachments = na;
        at = NULL;
        r = sim_garment_rebind(g, body_xyz, nv, tris, nt, body_xyz, nv, tris, nt, why);
    }
    free(parent);
    free(tri_of);
    free(on_edge);
    free(at);
    return r < 0 ? r : na;
}
