/* Metrics that are not collision: stretch strain, max and 99th percentile. */
#include <math.h>

#include "cloth.h"

/* Hoare's selection: the k-th smallest of a[0..n), reordering a. O(n) expected, no allocation. */
static float select_kth(float *a, int n, int k)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        float pivot = a[(lo + hi) / 2];
        int i = lo, j = hi;
        while (i <= j) {
            while (a[i] < pivot)
                i++;
            while (a[j] > pivot)
                j--;
            if (i <= j) {
                float t = a[i];
                a[i] = a[j];
                a[j] = t;
                i++;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
    return a[k];
}

/* Strain (|xi - xj| - rest) / rest of spring s; a NaN counts as the worst strain, so divergence
   is never hidden. */
static float spring_strain(const float (*x)[4], const int32_t (*ends)[2], const float *rest, int s)
{
    const float *a = x[ends[s][0]], *b = x[ends[s][1]];
    float d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    float e = (sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) - rest[s]) / rest[s];
    return e == e ? e : INFINITY;
}

float sim_stretch_max(const float (*x)[4], const int32_t (*ends)[2], const float *rest,
                      const uint8_t *kind, int begin, int end)
{
    float mx = 0.0f;
    for (int s = begin; s < end; s++) {
        if (kind[s] != SIM_SPRING_STRETCH || !(rest[s] > 0.0f))
            continue;
        float e = spring_strain(x, ends, rest, s);
        if (e > mx)
            mx = e;
    }
    return mx;
}

void sim_strain_stats(const sim_cloth *c, float *scratch, float *max_strain, float *p99_strain)
{
    int n = 0;
    float mx = 0.0f;
    for (int s = 0; s < c->ns; s++) {
        if (c->kind[s] != SIM_SPRING_STRETCH || c->rest[s] <= 0.0f)
            continue;
        float e = spring_strain((const float(*)[4])c->x, c->ends, c->rest, s);
        scratch[n++] = e;
        if (e > mx)
            mx = e;
    }
    *max_strain = mx;
    *p99_strain = n ? select_kth(scratch, n, (int)floorf(0.99f * (float)(n - 1))) : 0.0f;
    if (*p99_strain < 0.0f)
        *p99_strain = 0.0f;
}
