/* The largest cluster of the points a fit leaves unexplained: a limb the fit has lost (an arm
 * 13 cm from where the model put it) leaves its points together, while depth noise and the
 * ragged silhouette leave theirs scattered over the body. Union-find over the unexplained
 * points, O(n^2) in their number (a few dozen of the ~400). */
#include "fit_internal.h"

#include <math.h>
#include <stdlib.h>

static int uf_root(int *parent, int i)
{
    while (parent[i] != i)
        i = parent[i] = parent[parent[i]];
    return i;
}

int fit_unexplained_cluster(const float *points, const fit_matches *m, float tol, float radius_m,
                            float centroid[3])
{
    size_t cap = (size_t)(m->count > 0 ? m->count : 1);
    int *idx = malloc(cap * 3 * sizeof(int));
    centroid[0] = centroid[1] = centroid[2] = 0.0f;
    if (!idx)
        return -1;
    int *parent = idx + cap, *size = idx + 2 * cap, n = 0, best = 0, best_root = -1;
    for (int i = 0; i < m->count; ++i)
        if (m->vertex[i] < 0 || fabsf(m->resid[i]) > tol)
            idx[n++] = i;
    float r2 = radius_m * radius_m;
    for (int a = 0; a < n; ++a)
        parent[a] = a, size[a] = 0;
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b) {
            const float *p = points + (size_t)idx[a] * 3, *q = points + (size_t)idx[b] * 3;
            float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
            if (body_dot(d, d) <= r2)
                parent[uf_root(parent, a)] = uf_root(parent, b);
        }
    for (int a = 0; a < n; ++a) {
        int r = uf_root(parent, a);
        if (++size[r] > best)
            best = size[r], best_root = r;
    }
    for (int a = 0; a < n && best > 0; ++a)
        if (uf_root(parent, a) == best_root)
            for (int k = 0; k < 3; ++k)
                centroid[k] += points[(size_t)idx[a] * 3 + k] / (float)best;
    free(idx);
    return best;
}
