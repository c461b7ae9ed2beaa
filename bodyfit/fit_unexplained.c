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

int fit_unexplained_cluster(const float *points, const fit_matches *m, float tol, float radius_m)
{
    int n = 0, best = 0;
    int *idx = malloc((size_t)(m->count > 0 ? m->count : 1) * 2 * sizeof(int));
    if (!idx)
        return -1;
    int *parent = idx + (m->count > 0 ? m->count : 1);
    for (int i = 0; i < m->count; ++i)
        if (m->vertex[i] < 0 || fabsf(m->resid[i]) > tol)
            idx[n++] = i;
    float r2 = radius_m * radius_m;
    for (int a = 0; a < n; ++a)
        parent[a] = a;
    for (int a = 0; a < n; ++a)
        for (int b = a + 1; b < n; ++b) {
            const float *p = points + (size_t)idx[a] * 3, *q = points + (size_t)idx[b] * 3;
            float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
            if (body_dot(d, d) <= r2)
                parent[uf_root(parent, a)] = uf_root(parent, b);
        }
    /* Sizes counted in place of the indices, which are no longer needed. */
    for (int a = 0; a < n; ++a)
        idx[a] = 0;
    for (int a = 0; a < n; ++a) {
        int r = uf_root(parent, a);
        best = ++idx[r] > best ? idx[r] : best;
    }
    free(idx);
    return best;
}
