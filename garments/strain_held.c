/* The strain limit with fastened vertices' heights held (docs/garments.md, "Strain"). */
#include <math.h>

#include "strain_held.h"

/* Springs [begin, end) of one colour longer than rest (1 + limit) shortened back to it; a
 * fastened end moves only around the body (x, z), its height being held: the correction is
 * split by each end's inverse mass along the spring as each end can move. */
void gar_strain_limit_held(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                           const uint8_t *fastened, float limit, int begin, int end)
{
    for (int s = begin; s < end; s++) {
        int i = ends[s][0], j = ends[s][1];
        float *a = x[i], *b = x[j];
        float d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), target = rest[s] * (1 + limit);
        if (len <= target)
            continue;
        float n[3] = {d[0] / len, d[1] / len, d[2] / len};
        /* each end's mobility along n: w (1 - n_y^2) for a fastened end, w otherwise */
        float ma[3] = {a[3], fastened[i] ? 0.0f : a[3], a[3]};
        float mb[3] = {b[3], fastened[j] ? 0.0f : b[3], b[3]};
        float wsum = 0;
        for (int k = 0; k < 3; k++)
            wsum += (ma[k] + mb[k]) * n[k] * n[k];
        if (wsum <= 1e-12f)
            continue;
        float lambda = (len - target) / wsum;
        for (int k = 0; k < 3; k++) {
            a[k] += ma[k] * n[k] * lambda;
            b[k] -= mb[k] * n[k] * lambda;
        }
    }
}
