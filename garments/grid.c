/* A uniform grid of points (counting sort into cells), for nearest-point queries within one
 * cell's reach: the body's vertices for placement and for the penetration metric. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pattern_internal.h"
#include "place_internal.h"

static int cell_coord(const gar_grid *g, const float *p, int k)
{
    int c = (int)floorf((p[k] - g->lo[k]) / g->cell);
    return c < 0 ? 0 : c >= g->dim[k] ? g->dim[k] - 1 : c;
}

static int cell_index(const gar_grid *g, int x, int y, int z)
{
    return (z * g->dim[1] + y) * g->dim[0] + x;
}

int gar_grid_build(gar_grid *g, const float *xyz, int n, float cell)
{
    memset(g, 0, sizeof *g);
    float hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    g->lo[0] = g->lo[1] = g->lo[2] = INFINITY;
    for (int v = 0; v < n; v++)
        for (int k = 0; k < 3; k++)
            g->lo[k] = fminf(g->lo[k], xyz[3 * v + k]), hi[k] = fmaxf(hi[k], xyz[3 * v + k]);
    g->cell = cell;
    long cells = 1;
    for (int k = 0; k < 3; k++) {
        g->dim[k] = (int)((hi[k] - g->lo[k]) / cell) + 1;
        cells *= g->dim[k];
    }
    if (cells > 50000000L)
        return -GAR_ERR_TOO_LARGE;
    g->start = calloc((size_t)cells + 1, sizeof *g->start);
    g->items = malloc((size_t)n * sizeof *g->items);
    if (!g->start || !g->items)
        return -GAR_ERR_NO_MEMORY;
    for (int v = 0; v < n; v++) {
        const float *p = xyz + 3 * v;
        g->start[cell_index(g, cell_coord(g, p, 0), cell_coord(g, p, 1), cell_coord(g, p, 2)) +
                 1]++;
    }
    for (long c = 0; c < cells; c++)
        g->start[c + 1] += g->start[c];
    int *fill = malloc((size_t)cells * sizeof *fill);
    if (!fill)
        return -GAR_ERR_NO_MEMORY;
    memcpy(fill, g->start, (size_t)cells * sizeof *fill);
    for (int v = 0; v < n; v++) {
        const float *p = xyz + 3 * v;
        g->items[fill[cell_index(g, cell_coord(g, p, 0), cell_coord(g, p, 1),
                                 cell_coord(g, p, 2))]++] = v;
    }
    free(fill);
    return 0;
}

/* Nearest body vertex within one cell's reach, or -1. */
int gar_grid_nearest(const gar_grid *g, const float *xyz, const float *p)
{
    int c[3], best = -1;
    float bd = INFINITY;
    for (int k = 0; k < 3; k++)
        c[k] = cell_coord(g, p, k);
    for (int z = c[2] - 1; z <= c[2] + 1; z++)
        for (int y = c[1] - 1; y <= c[1] + 1; y++)
            for (int x = c[0] - 1; x <= c[0] + 1; x++) {
                if (x < 0 || y < 0 || z < 0 || x >= g->dim[0] || y >= g->dim[1] || z >= g->dim[2])
                    continue;
                int ci = cell_index(g, x, y, z);
                for (int i = g->start[ci]; i < g->start[ci + 1]; i++) {
                    const float *q = xyz + 3 * g->items[i];
                    float dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
                    float d = dx * dx + dy * dy + dz * dz;
                    if (d < bd)
                        bd = d, best = g->items[i];
                }
            }
    return best;
}

void gar_grid_free(gar_grid *g)
{
    free(g->start);
    free(g->items);
    memset(g, 0, sizeof *g);
}
