/* Metrics that are not collision: stretch strain, max and 99th percentile. */
#include <math.h>

#include "cloth.h"
#include "passes.h"

/* Restore the min-heap order of h[0..m) below position i. */
static void sift_down(float *h, int m, int i)
{
    for (;;) {
        int l = 2 * i + 1, r = l + 1, s = i;
        if (l < m && h[l] < h[s])
            s = l;
        if (r < m && h[r] < h[s])
            s = r;
        if (s == i)
            return;
        float t = h[i];
        h[i] = h[s];
        h[s] = t;
        i = s;
    }
}

/* The k-th smallest (from 0) of a[0..n), reordering a: the smallest of the n - k largest, kept in
   a min-heap in a[0..n-k) while the rest is scanned. For the 99th percentile the heap is a
   hundredth of the values and most of the others cost one comparison. (Hoare's selection before
   it made several passes of swaps: sim_strain_stats' share of the body scene 1.09 -> 0.63 %,
   perf record, on the one thread that checks each attempt.) No NaN: spring_strain never gives
   one. */
static float select_kth(float *a, int n, int k)
{
    int m = n - k;
    for (int i = m / 2 - 1; i >= 0; i--)
        sift_down(a, m, i);
    for (int i = m; i < n; i++)
        if (a[i] > a[0]) {
            a[0] = a[i];
            sift_down(a, m, 0);
        }
    return a[0];
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

int sim_strain_count_over(const sim_cloth *c, float limit, float *free_max)
{
    int n = 0;
    float mx = 0.0f;
    for (int s = 0; s < c->ns; s++) {
        if (c->kind[s] != SIM_SPRING_STRETCH || c->rest[s] <= 0.0f ||
            (c->x[c->ends[s][0]][3] == 0.0f && c->x[c->ends[s][1]][3] == 0.0f))
            continue;
        float e = spring_strain((const float(*)[4])c->x, c->ends, c->rest, s);
        n += e > limit;
        mx = e > mx ? e : mx;
    }
    *free_max = mx;
    return n;
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
