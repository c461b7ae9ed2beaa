/* Cloth construction: masses, springs from the triangle mesh, and the graph colouring that lets
 * one colour of springs be projected in parallel. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"
#include "edge_sort.h"
#include "passes.h"

typedef struct spring_list {
    int n, cap;
    int32_t (*ends)[2];
    uint8_t *kind;
} spring_list;

static int spring_push(spring_list *l, int32_t a, int32_t b, uint8_t kind)
{
    if (l->n == l->cap) {
        int cap = l->cap ? l->cap * 2 : 1024;
        int32_t(*e)[2] = realloc(l->ends, (size_t)cap * sizeof *e);
        if (!e)
            return -SIM_ERR_NO_MEMORY;
        l->ends = e;
        uint8_t *k = realloc(l->kind, (size_t)cap);
        if (!k)
            return -SIM_ERR_NO_MEMORY;
        l->kind = k;
        l->cap = cap;
    }
    l->ends[l->n][0] = a < b ? a : b;
    l->ends[l->n][1] = a < b ? b : a;
    l->kind[l->n] = kind;
    l->n++;
    return 0;
}

/* Grid garments: stretch along rows and columns, shear across each quad, bend skipping one
 * vertex (Provot 1995's layout). */
static int springs_grid(spring_list *l, int w, int h)
{
    int r = 0;
    for (int i = 0; i < h && r == 0; i++) {
        for (int j = 0; j < w && r == 0; j++) {
            int v = i * w + j;
            if (j + 1 < w)
                r |= spring_push(l, v, v + 1, SIM_SPRING_STRETCH);
            if (i + 1 < h)
                r |= spring_push(l, v, v + w, SIM_SPRING_STRETCH);
            if (j + 1 < w && i + 1 < h) {
                r |= spring_push(l, v, v + w + 1, SIM_SPRING_SHEAR);
                r |= spring_push(l, v + 1, v + w, SIM_SPRING_SHEAR);
            }
            if (j + 2 < w)
                r |= spring_push(l, v, v + 2, SIM_SPRING_BEND);
            if (i + 2 < h)
                r |= spring_push(l, v, v + 2 * w, SIM_SPRING_BEND);
        }
    }
    return r ? -SIM_ERR_NO_MEMORY : 0;
}

typedef struct half_edge {
    int64_t key; /* min * nv + max */
    int32_t opposite;
} half_edge;

static int half_edge_cmp(const void *a, const void *b)
{
    const half_edge *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return (x->opposite > y->opposite) - (x->opposite < y->opposite);
}

/* The free edges a garment hangs by bound, as a garment's armholes and necklines are (binding
 * tape): a stretch spring across every vertex of a boundary loop that holds an attachment, from
 * one of its boundary neighbours to the other. Such an edge carries the cloth hanging from it as
 * a chain does, and a Gauss-Seidel sweep moves a correction one spring along it: a shirt's
 * armholes crept to the settle threshold every frame (docs/sim-history.md, "The armholes'
 * cost"). A loop without attachments (a hem) hangs free and is left as it is: bound, the shirt's
 * hem took more strain retries. he: the sorted half-edges; attached: nv flags. */
static int springs_binding(spring_list *l, const half_edge *he, int n, int nv,
                           const uint8_t *attached)
{
    int32_t(*nb)[2] = malloc((size_t)nv * sizeof *nb);
    uint8_t *deg = calloc((size_t)nv, 1), *seen = calloc((size_t)nv, 1);
    int r = nb && deg && seen ? 0 : -SIM_ERR_NO_MEMORY;
    for (int i = 0; i < n && r == 0; i++) {
        if ((i > 0 && he[i].key == he[i - 1].key) || (i + 1 < n && he[i + 1].key == he[i].key))
            continue; /* an inner edge */
        int32_t e[2] = {(int32_t)(he[i].key / nv), (int32_t)(he[i].key % nv)};
        for (int k = 0; k < 2; k++) {
            if (deg[e[k]] < 2)
                nb[e[k]][deg[e[k]]] = e[1 - k];
            deg[e[k]] = deg[e[k]] < 3 ? deg[e[k]] + 1 : 3;
        }
    }
    for (int v0 = 0; v0 < nv && r == 0; v0++) {
        if (deg[v0] != 2 || seen[v0])
            continue;
        /* walk the loop (or the chain, up to a non-manifold vertex) once to see if it holds an
           attachment, then once more to bind it */
        for (int pass = 0, bind = 0; pass < 2 && r == 0; pass++) {
            for (int prev = nb[v0][1], v = v0, steps = 0; steps < nv && r == 0; steps++) {
                if (pass == 0) {
                    seen[v] = 1;
                    bind |= attached[v];
                } else if (bind && nb[v][0] != nb[v][1]) {
                    r = spring_push(l, nb[v][0], nb[v][1], SIM_SPRING_STRETCH);
                }
                int next = nb[v][0] == prev ? nb[v][1] : nb[v][0];
                prev = v;
                v = next;
                if (v == v0 || deg[v] != 2)
                    break;
            }
            if (!bind)
                break;
        }
    }
    free(nb);
    free(deg);
    free(seen);
    return r;
}

/* Any triangle mesh: stretch on every edge, bend between the opposite vertices of the two
 * triangles sharing an edge; no shear (the triangulation's diagonals already resist it). */
static int springs_mesh(spring_list *l, const int32_t *tris, int nt, int nv,
                        const uint8_t *attached)
{
    half_edge *he = malloc((size_t)nt * 6 * sizeof *he), *sorted = he + nt * 3;
    int32_t *count = malloc((size_t)(nv + 1) * sizeof *count);
    if (!he || !count) {
        free(he);
        free(count);
        return -SIM_ERR_NO_MEMORY;
    }
    for (int t = 0; t < nt; t++) {
        for (int e = 0; e < 3; e++) {
            int64_t a = tris[t * 3 + e], b = tris[t * 3 + (e + 1) % 3];
            he[t * 3 + e].key = a < b ? a * nv + b : b * nv + a;
            he[t * 3 + e].opposite = tris[t * 3 + (e + 2) % 3];
        }
    }
    sim_edge_sort(he, nt * 3, sizeof *he, nv, half_edge_cmp, sorted, count);
    free(count);
    memcpy(he, sorted, (size_t)nt * 3 * sizeof *he);
    int r = 0;
    for (int i = 0; i < nt * 3 && r == 0; i++) {
        if (i > 0 && he[i].key == he[i - 1].key)
            continue;
        r = spring_push(l, (int32_t)(he[i].key / nv), (int32_t)(he[i].key % nv),
                        SIM_SPRING_STRETCH);
        if (r == 0 && i + 1 < nt * 3 && he[i + 1].key == he[i].key &&
            he[i].opposite != he[i + 1].opposite)
            r = spring_push(l, he[i].opposite, he[i + 1].opposite, SIM_SPRING_BEND);
    }
    if (r == 0)
        r = springs_binding(l, he, nt * 3, nv, attached);
    free(he);
    return r;
}

/* Greedy edge colouring, one group of springs at a time (stretch first, then the rest) so that
 * strain limiting can run over the stretch colours alone. A spring takes the lowest colour
 * neither end uses yet; 64 colours per group cover any vertex degree up to 32. */
static int colour_springs(sim_cloth *c, const spring_list *l, sim_reject *why)
{
    int ns = l->n;
    uint64_t *used = calloc((size_t)c->nv, sizeof *used);
    int16_t *colour = malloc((size_t)ns * sizeof *colour);
    int32_t count[128] = {0};
    if (!used || !colour) {
        free(used);
        free(colour);
        return -SIM_ERR_NO_MEMORY;
    }
    int base = 0, r = 0;
    for (int group = 0; group < 2 && r == 0; group++) {
        memset(used, 0, (size_t)c->nv * sizeof *used);
        int top = 0;
        for (int s = 0; s < ns; s++) {
            if ((l->kind[s] == SIM_SPRING_STRETCH) != (group == 0))
                continue;
            uint64_t both = used[l->ends[s][0]] | used[l->ends[s][1]];
            if (both == ~(uint64_t)0) {
                snprintf(why->detail, sizeof why->detail,
                         "vertex %d has more than 32 springs of one kind", l->ends[s][0]);
                r = -SIM_ERR_PARAM;
                break;
            }
            int k = __builtin_ctzll(~both);
            used[l->ends[s][0]] |= (uint64_t)1 << k;
            used[l->ends[s][1]] |= (uint64_t)1 << k;
            colour[s] = (int16_t)(base + k);
            count[base + k]++;
            if (k + 1 > top)
                top = k + 1;
        }
        if (group == 0)
            c->num_stretch_colors = top;
        base += top;
    }
    c->num_colors = base;
    c->color_start = malloc((size_t)(base + 1) * sizeof *c->color_start);
    c->ends = malloc((size_t)(ns ? ns : 1) * sizeof *c->ends);
    c->kind = malloc((size_t)(ns ? ns : 1));
    c->rest = malloc((size_t)(ns ? ns : 1) * sizeof *c->rest);
    if (r == 0 && (!c->color_start || !c->ends || !c->kind || !c->rest))
        r = -SIM_ERR_NO_MEMORY;
    if (r == 0) {
        c->color_start[0] = 0;
        for (int k = 0; k < base; k++)
            c->color_start[k + 1] = c->color_start[k] + count[k];
        int32_t fill[128];
        memcpy(fill, c->color_start, (size_t)base * sizeof *fill);
        for (int s = 0; s < ns; s++) {
            int d = fill[colour[s]]++;
            c->ends[d][0] = l->ends[s][0];
            c->ends[d][1] = l->ends[s][1];
            c->kind[d] = l->kind[s];
        }
        c->ns = ns;
    }
    free(used);
    free(colour);
    return r;
}

/* Lumped masses: a third of each triangle's area times the density to each of its vertices. */
static void lump_masses(sim_cloth *c, const sim_garment *g, float density)
{
    for (int i = 0; i < c->nv; i++)
        c->x[i][3] = 0.0f;
    for (int t = 0; t < g->num_triangles; t++) {
        const int32_t *v = &g->triangles[t * 3];
        const float *a = &g->xyz[v[0] * 3], *b = &g->xyz[v[1] * 3], *p = &g->xyz[v[2] * 3];
        float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float e2[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
        float cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        float area = 0.5f * sqrtf(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        for (int k = 0; k < 3; k++)
            c->x[v[k]][3] += area * density / 3.0f; /* mass for now, inverted below */
    }
}

/* Binary min-heap of (distance, vertex) for Dijkstra. */
typedef struct heap_item {
    float d;
    int32_t v;
} heap_item;

static void heap_push(heap_item *h, int *n, heap_item it)
{
    int i = (*n)++;
    while (i > 0 && h[(i - 1) / 2].d > it.d) {
        h[i] = h[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h[i] = it;
}

static heap_item heap_pop(heap_item *h, int *n)
{
    heap_item top = h[0], last = h[--(*n)];
    int i = 0;
    for (;;) {
        int k = 2 * i + 1;
        if (k >= *n)
            break;
        if (k + 1 < *n && h[k + 1].d < h[k].d)
            k++;
        if (h[k].d >= last.d)
            break;
        h[i] = h[k];
        i = k;
    }
    h[i] = last;
    return top;
}

/* The stretch springs at each vertex, in spring order: spring[start[v] .. start[v + 1]) (a
 * counting sort of the spring ends). 0, or -SIM_ERR_NO_MEMORY with both NULL. */
static int stretch_springs_by_vertex(const sim_cloth *c, int32_t **start_out, int32_t **spring_out)
{
    int nv = c->nv, ns = c->ns;
    int32_t *start = calloc((size_t)nv + 1, sizeof *start);
    int32_t *spring = malloc((size_t)(2 * ns + 1) * sizeof *spring);
    int32_t *cursor = malloc((size_t)nv * sizeof *cursor + 1);
    *start_out = *spring_out = NULL;
    if (!start || !spring || !cursor) {
        free(start);
        free(spring);
        free(cursor);
        return -SIM_ERR_NO_MEMORY;
    }
    for (int k = 0; k < ns; k++)
        if (c->kind[k] == SIM_SPRING_STRETCH) {
            start[c->ends[k][0] + 1]++;
            start[c->ends[k][1] + 1]++;
        }
    for (int i = 0; i < nv; i++)
        start[i + 1] += start[i];
    memcpy(cursor, start, (size_t)nv * sizeof *cursor);
    for (int k = 0; k < ns; k++)
        if (c->kind[k] == SIM_SPRING_STRETCH) {
            spring[cursor[c->ends[k][0]]++] = k;
            spring[cursor[c->ends[k][1]]++] = k;
        }
    free(cursor);
    *start_out = start;
    *spring_out = spring;
    return 0;
}

static int other_end(const sim_cloth *c, int spring, int v)
{
    return c->ends[spring][0] == v ? c->ends[spring][1] : c->ends[spring][0];
}

/* Tethers: rest geodesic distance (over stretch springs) from every vertex to its nearest
 * attached vertex, multi-source Dijkstra. Vertices no attachment reaches get anchor -1. */
static int build_tethers(sim_cloth *c)
{
    int nv = c->nv, ns = c->ns;
    c->tether_anchor = malloc((size_t)nv * sizeof *c->tether_anchor);
    c->tether_len = malloc((size_t)nv * sizeof *c->tether_len);
    const int32_t *start = c->adj_start, *adj = c->adj_spring;
    heap_item *heap = malloc((size_t)(2 * ns + nv + 1) * sizeof *heap);
    int r = 0;
    if (!c->tether_anchor || !c->tether_len || !heap) {
        r = -SIM_ERR_NO_MEMORY;
        goto done;
    }
    int n = 0;
    for (int i = 0; i < nv; i++) {
        c->tether_anchor[i] = -1;
        c->tether_len[i] = INFINITY;
    }
    for (int a = 0; a < c->num_attachments; a++) {
        int v = c->attachments[a].vertex;
        c->tether_anchor[v] = v;
        c->tether_len[v] = 0.0f;
        heap_push(heap, &n, (heap_item){0.0f, v});
    }
    while (n > 0) {
        heap_item it = heap_pop(heap, &n);
        if (it.d > c->tether_len[it.v])
            continue;
        for (int k = start[it.v]; k < start[it.v + 1]; k++) {
            float d = it.d + c->rest[adj[k]];
            int u = other_end(c, adj[k], it.v);
            if (d < c->tether_len[u]) {
                c->tether_len[u] = d;
                c->tether_anchor[u] = c->tether_anchor[it.v];
                heap_push(heap, &n, (heap_item){d, u});
            }
        }
    }
    /* The anchor is the geodesically nearest attachment; the length the straight rest
     * distance to it, shorter than the geodesic where the garment wraps the body, so a tether
     * holds a garment up even where it lies curved around the chest. */
    for (int i = 0; i < nv; i++) {
        int a = c->tether_anchor[i];
        if (a == i) {
            c->tether_anchor[i] = -1; /* the anchors themselves */
        } else if (a >= 0) {
            float d[3] = {c->x_rest[i][0] - c->x_rest[a][0], c->x_rest[i][1] - c->x_rest[a][1],
                          c->x_rest[i][2] - c->x_rest[a][2]};
            c->tether_len[i] = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
    }
done:
    free(heap);
    return r;
}

int sim_cloth_init(sim_cloth *c, const sim_garment *g, const sim_fabric *f, sim_reject *why)
{
    memset(c, 0, sizeof *c);
    int nv = g->num_vertices, nt = g->num_triangles;
    c->nv = nv;
    c->nt = nt;
    c->x = calloc((size_t)nv, sizeof *c->x);
    c->x_prev = calloc((size_t)nv, sizeof *c->x_prev);
    c->x_rest = calloc((size_t)nv, sizeof *c->x_rest);
    c->tris = calloc((size_t)nt, sizeof *c->tris);
    if (g->num_attachments > 0)
        c->attachments = malloc((size_t)g->num_attachments * sizeof *c->attachments);
    if (!c->x || !c->x_prev || !c->x_rest || !c->tris ||
        (g->num_attachments > 0 && !c->attachments)) {
        sim_cloth_free(c);
        return -SIM_ERR_NO_MEMORY;
    }
    lump_masses(c, g, f->density_kg_m2);
    for (int i = 0; i < nv; i++) {
        float m = g->mass_kg ? g->mass_kg[i] : c->x[i][3];
        for (int d = 0; d < 3; d++)
            c->x[i][d] = g->xyz[i * 3 + d];
        c->x[i][3] = m > 0.0f ? 1.0f / m : 0.0f;
    }
    c->num_attachments = g->num_attachments;
    for (int a = 0; a < g->num_attachments; a++) {
        c->attachments[a] = g->attachments[a];
        c->x[g->attachments[a].vertex][3] = 0.0f; /* driven by the body, not the solver */
    }
    memcpy(c->x_prev, c->x, (size_t)nv * sizeof *c->x);
    memcpy(c->x_rest, c->x, (size_t)nv * sizeof *c->x);
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            c->tris[t][k] = g->triangles[t * 3 + k];
    c->k[SIM_SPRING_STRETCH] = f->stretch_n_m;
    c->k[SIM_SPRING_SHEAR] = f->shear_n_m;
    c->k[SIM_SPRING_BEND] = f->bend_n_m;

    spring_list l = {0};
    uint8_t *attached = calloc((size_t)nv, 1);
    for (int a = 0; attached && a < g->num_attachments; a++)
        attached[g->attachments[a].vertex] = 1;
    int r = !attached       ? -SIM_ERR_NO_MEMORY
            : g->grid_w > 0 ? springs_grid(&l, g->grid_w, g->grid_h)
                            : springs_mesh(&l, g->triangles, nt, nv, attached);
    free(attached);
    if (r == 0)
        r = colour_springs(c, &l, why);
    free(l.ends);
    free(l.kind);
    if (r != 0) {
        sim_cloth_free(c);
        return r;
    }
    for (int s = 0; s < c->ns; s++) {
        const float *a = c->x_rest[c->ends[s][0]], *b = c->x_rest[c->ends[s][1]];
        float d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        c->rest[s] = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    r = stretch_springs_by_vertex(c, &c->adj_start, &c->adj_spring);
    if (r == 0)
        r = build_tethers(c);
    if (r == 0)
        r = sim_cloth_hierarchy(c);
    if (r != 0)
        sim_cloth_free(c);
    return r;
}

void sim_cloth_free(sim_cloth *c)
{
    free(c->x);
    free(c->x_prev);
    free(c->x_rest);
    free(c->tris);
    free(c->ends);
    free(c->rest);
    free(c->kind);
    free(c->color_start);
    free(c->attachments);
    free(c->tether_anchor);
    free(c->tether_len);
    free(c->hier_level_start);
    free(c->hier_vertex);
    free(c->hier_parent_start);
    free(c->hier_parent);
    free(c->hier_rest);
    free(c->adj_start);
    free(c->adj_spring);
    memset(c, 0, sizeof *c);
}
