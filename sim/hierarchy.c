/* The strain-limit hierarchy's levels and parents (sim_cloth's hier_* arrays; the pass itself is
 * sim_strain_hierarchy in springs.c and its twin in kernels/springs.cl).
 *
 * A vertex's parents are its stretch neighbours one hop nearer the attachments (breadth first
 * over the stretch springs) and, among those as many hops away, the ones above it at rest along
 * a spring that rises more than SIM_HIER_RISE of its length. Levels are the longest chain of
 * parents, so every parent is final before its child is corrected and the vertices of one level
 * stay independent.
 *
 * Why the second kind: with the triangles' diagonals among the stretch springs, breadth-first
 * hops put the two ends of every other vertical spring of a column on the same level wherever
 * the shortest path comes in sideways: the columns under the shirt's armholes, which hang from
 * the armhole's free edge. The pass never touched those springs, so the column hung from one
 * spring in two, and the garment's weight stretched the other (bend_forward without strain
 * retries, 90 frames: of the springs over 3 % after the pass, 10,574 joined two vertices of one
 * level against 328 a vertex and its parent, up to 33 %; "Bends: the hierarchy's levels" in
 * docs/sim-history-5.md). */
#include <stdlib.h>

#include "cloth.h"

/* A same-level neighbour is a parent when the spring to it rises more than this fraction of its
   length (30 degrees): the columns and the diagonals whatever the cells' aspect, never the hoops.
   Measured (bend_forward, 90 frames, no strain retries: frames within 3 % / 1 %, max): 0.5
   46.7 %, 8.9 %; 0.7 43.3 %, 7.5 %; 0.8 40.0 %, 6.7 %; breadth first alone 20.0 %, 8.8 %. */
#define SIM_HIER_RISE 0.5f

typedef struct hier_key {
    int32_t hop; /* hops from the attachments */
    float y;     /* m, height at rest */
    int32_t v;
} hier_key;

/* Nearer the attachments first, then higher, then by index: every parent before its child. */
static int key_cmp(const void *pa, const void *pb)
{
    const hier_key *a = pa, *b = pb;
    if (a->hop != b->hop)
        return a->hop < b->hop ? -1 : 1;
    if (a->y != b->y)
        return a->y > b->y ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

/* hop[v]: stretch-spring hops from the nearest attached vertex (0 for those), -1 where none
   reaches; queue: nv entries of scratch. */
static void hops_from_attachments(const sim_cloth *c, int32_t *hop, int32_t *queue)
{
    int head = 0, tail = 0;
    for (int v = 0; v < c->nv; v++)
        hop[v] = -1;
    for (int a = 0; a < c->num_attachments; a++) {
        int v = c->attachments[a].vertex;
        if (hop[v] < 0) {
            hop[v] = 0;
            queue[tail++] = v;
        }
    }
    while (head < tail) {
        int v = queue[head++];
        for (int k = c->adj_start[v]; k < c->adj_start[v + 1]; k++) {
            const int32_t *e = c->ends[c->adj_spring[k]];
            int u = e[0] == v ? e[1] : e[0];
            if (hop[u] < 0) {
                hop[u] = hop[v] + 1;
                queue[tail++] = u;
            }
        }
    }
}

/* Whether u is a parent of its stretch neighbour v (spring s). */
static int is_parent(const sim_cloth *c, const int32_t *hop, int u, int v, int s)
{
    if (hop[u] < 0 || hop[v] <= 0)
        return 0;
    if (hop[u] == hop[v] - 1)
        return 1;
    return hop[u] == hop[v] && c->x_rest[u][1] - c->x_rest[v][1] > SIM_HIER_RISE * c->rest[s];
}

/* Levels (longest chain of parents, 0 for the attached) in key order; entries grouped by level,
   key order within each; parents listed in adjacency order. */
static void fill_levels(sim_cloth *c, const int32_t *hop, const hier_key *key, int n,
                        int32_t *level)
{
    c->hier_levels = 0;
    for (int v = 0; v < c->nv; v++)
        level[v] = hop[v] == 0 ? 0 : -1;
    for (int e = 0; e < n; e++) {
        int v = key[e].v, l = 1;
        for (int k = c->adj_start[v]; k < c->adj_start[v + 1]; k++) {
            int s = c->adj_spring[k], u = c->ends[s][0] == v ? c->ends[s][1] : c->ends[s][0];
            if (is_parent(c, hop, u, v, s) && level[u] + 1 > l)
                l = level[u] + 1;
        }
        level[v] = l;
        c->hier_levels = l > c->hier_levels ? l : c->hier_levels;
    }
    /* counting sort by level: hier_level_start[l - 1] is where level l starts */
    for (int l = 0; l <= c->hier_levels; l++)
        c->hier_level_start[l] = 0;
    for (int e = 0; e < n; e++)
        c->hier_level_start[level[key[e].v] - 1]++;
    for (int l = 0, sum = 0; l <= c->hier_levels; l++) {
        int count = c->hier_level_start[l];
        c->hier_level_start[l] = sum;
        sum += count;
    }
    int np = 0;
    for (int e = 0; e < n; e++) {
        int v = key[e].v;
        c->hier_vertex[c->hier_level_start[level[v] - 1]++] = v;
    }
    for (int l = c->hier_levels; l > 0; l--) /* back to the starts */
        c->hier_level_start[l] = c->hier_level_start[l - 1];
    c->hier_level_start[0] = 0;
    for (int e = 0; e < n; e++) {
        int v = c->hier_vertex[e];
        c->hier_parent_start[e] = np;
        for (int k = c->adj_start[v]; k < c->adj_start[v + 1]; k++) {
            int s = c->adj_spring[k], u = c->ends[s][0] == v ? c->ends[s][1] : c->ends[s][0];
            if (is_parent(c, hop, u, v, s)) {
                c->hier_parent[np] = u;
                c->hier_rest[np++] = c->rest[s];
            }
        }
    }
    c->hier_parent_start[n] = np;
}

int sim_cloth_hierarchy(sim_cloth *c)
{
    int nv = c->nv, ns = c->ns, r = 0;
    int32_t *hop = malloc((size_t)nv * sizeof *hop);
    int32_t *scratch = malloc((size_t)nv * sizeof *scratch);
    hier_key *key = malloc((size_t)(nv + 1) * sizeof *key);
    c->hier_vertex = malloc((size_t)(nv + 1) * sizeof *c->hier_vertex);
    c->hier_level_start = malloc((size_t)(nv + 2) * sizeof *c->hier_level_start);
    c->hier_parent_start = malloc((size_t)(nv + 1) * sizeof *c->hier_parent_start);
    c->hier_parent = malloc((size_t)(2 * ns + 1) * sizeof *c->hier_parent);
    c->hier_rest = malloc((size_t)(2 * ns + 1) * sizeof *c->hier_rest);
    if (!hop || !scratch || !key || !c->hier_vertex || !c->hier_level_start ||
        !c->hier_parent_start || !c->hier_parent || !c->hier_rest) {
        r = -SIM_ERR_NO_MEMORY;
        goto done;
    }
    hops_from_attachments(c, hop, scratch);
    int n = 0;
    for (int v = 0; v < nv; v++)
        if (hop[v] > 0)
            key[n++] = (hier_key){hop[v], c->x_rest[v][1], v};
    qsort(key, (size_t)n, sizeof *key, key_cmp);
    fill_levels(c, hop, key, n, scratch);
done:
    free(hop);
    free(scratch);
    free(key);
    return r;
}
