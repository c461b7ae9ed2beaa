/* Sorting a mesh's edges, each keyed lo * nv + hi by its two vertices (lo < hi < nv): the
 * collider's adjacency and the cloth's springs, once per topology. */
#ifndef TRYON_SIM_EDGE_SORT_H
#define TRYON_SIM_EDGE_SORT_H

#include <stddef.h>
#include <stdint.h>

/* n elements of size bytes at base, each starting with its int64_t key, sorted by cmp (which
 * orders by key first) into out (n elements, distinct from base). A counting sort by the lower
 * vertex, then each vertex's few edges by insertion (stable); a vertex with many edges (a fan:
 * a hostile mesh's one vertex in every triangle) by qsort, so that no mesh makes it quadratic.
 * Linear in the edges, where one qsort of them all was a third of a body topology's build.
 * count: nv + 1 ints of scratch. */
void sim_edge_sort(const void *base, int n, size_t size, int nv,
                   int (*cmp)(const void *, const void *), void *out, int32_t *count);

#endif
