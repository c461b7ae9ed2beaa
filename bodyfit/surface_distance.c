/* Mesh-to-mesh distance (tryon-bench-fit, tests): a uniform grid over b, nearest vertex search
 * growing ring by ring. */
#include "fit_track.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define FITM_CELL_M 0.03f

double fit_mean_surface_distance(const float *a, int na, const float *b, const float *bn, int nb)
{
    float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
    for (int i = 0; i < nb; ++i)
        for (int k = 0; k < 3; ++k) {
            lo[k] = fminf(lo[k], b[i * 3 + k]);
            hi[k] = fmaxf(hi[k], b[i * 3 + k]);
        }
    int dim[3];
    for (int k = 0; k < 3; ++k)
        dim[k] = (int)((hi[k] - lo[k]) / FITM_CELL_M) + 1;
    size_t cells = (size_t)dim[0] * dim[1] * dim[2];
    int *start = calloc(cells + 1, sizeof(int)), *items = malloc((size_t)nb * sizeof(int));
    int *cellof = malloc((size_t)nb * sizeof(int));
    if (!start || !items || !cellof) {
        free(start), free(items), free(cellof);
        return -1.0;
    }
    for (int i = 0; i < nb; ++i) {
        int c[3];
        for (int k = 0; k < 3; ++k) {
            c[k] = (int)((b[i * 3 + k] - lo[k]) / FITM_CELL_M);
            c[k] = c[k] < 0 ? 0 : (c[k] >= dim[k] ? dim[k] - 1 : c[k]);
        }
        cellof[i] = (c[2] * dim[1] + c[1]) * dim[0] + c[0];
        start[cellof[i] + 1]++;
    }
    for (size_t k = 0; k < cells; ++k)
        start[k + 1] += start[k];
    for (int i = 0; i < nb; ++i)
        items[start[cellof[i]]++] = i;
    for (size_t k = cells; k > 0; --k)
        start[k] = start[k - 1];
    start[0] = 0;
    double sum = 0.0;
    for (int i = 0; i < na; ++i) {
        const float *p = a + (size_t)i * 3;
        int c[3], best = -1;
        float best_d2 = INFINITY;
        for (int k = 0; k < 3; ++k)
            c[k] = (int)floorf((p[k] - lo[k]) / FITM_CELL_M);
        for (int ring = 0; ring < 200; ++ring) {
            for (int z = c[2] - ring; z <= c[2] + ring; ++z)
                for (int y = c[1] - ring; y <= c[1] + ring; ++y)
                    for (int x = c[0] - ring; x <= c[0] + ring; ++x) {
                        if (abs(x - c[0]) != ring && abs(y - c[1]) != ring && abs(z - c[2]) != ring)
                            continue;
                        if (x < 0 || y < 0 || z < 0 || x >= dim[0] || y >= dim[1] || z >= dim[2])
                            continue;
                        int cell = (z * dim[1] + y) * dim[0] + x;
                        for (int e = start[cell]; e < start[cell + 1]; ++e) {
                            const float *q = b + (size_t)items[e] * 3;
                            float d[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
                            float d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                            if (d2 < best_d2)
                                best_d2 = d2, best = items[e];
                        }
                    }
            /* Everything nearer than the ring's inner distance has been seen. */
            if (best >= 0 && sqrtf(best_d2) <= (float)ring * FITM_CELL_M)
                break;
        }
        const float *q = b + (size_t)best * 3, *n = bn + (size_t)best * 3;
        float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        sum += fabs(d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
    }
    free(start), free(items), free(cellof);
    return na ? sum / na : 0.0;
}
