/* sim_edge_sort (edge_sort.h). */
#include "edge_sort.h"

#include <stdlib.h>
#include <string.h>

/* A vertex's edges sorted by insertion up to this many, by qsort above. */
#define EDGE_INSERTION_MAX 32

static int64_t key_of(const char *e)
{
    int64_t k;
    memcpy(&k, e, sizeof k);
    return k;
}

void sim_edge_sort(const void *base, int n, size_t size, int nv,
                   int (*cmp)(const void *, const void *), void *out, int32_t *count)
{
    const char *in = base;
    char *o = out, x[64];
    memset(count, 0, (size_t)(nv + 1) * sizeof *count);
    for (int i = 0; i < n; i++)
        count[key_of(in + (size_t)i * size) / nv + 1]++;
    for (int v = 0; v < nv; v++)
        count[v + 1] += count[v];
    for (int i = 0; i < n; i++)
        memcpy(o + (size_t)count[key_of(in + (size_t)i * size) / nv]++ * size,
               in + (size_t)i * size, size);
    /* count[v] is now the end of vertex v's edges, the start of v + 1's */
    for (int v = 0, begin = 0; v < nv; begin = count[v++]) {
        int end = count[v];
        if (end - begin > EDGE_INSERTION_MAX || size > sizeof x) {
            qsort(o + (size_t)begin * size, (size_t)(end - begin), size, cmp);
            continue;
        }
        for (int i = begin + 1; i < end; i++) {
            memcpy(x, o + (size_t)i * size, size);
            int j = i;
            for (; j > begin && cmp(o + (size_t)(j - 1) * size, x) > 0; j--)
                memcpy(o + (size_t)j * size, o + (size_t)(j - 1) * size, size);
            memcpy(o + (size_t)j * size, x, size);
        }
    }
}
