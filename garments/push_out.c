/* After wrapping, a vertex the body's surface still reaches (armpits, the crotch: places no
 * surface of revolution fits) is pushed out along the nearest body vertex's normal to the
 * clearance. Nearest vertices come from a uniform grid of cells one search radius wide. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bodyfit.h"
#include "pattern_internal.h"
#include "place_internal.h"

typedef struct cell_grid {
    float lo[3], cell;
    int dim[3];
    int *start, *items; /* counting sort: cell c holds items[start[c] .. start[c + 1]) */
} cell_grid;

static int cell_coord(const cell_grid *g, const float *p, int k)
{
    int c = (int)floorf((p[k] - g->lo[k]) / g->cell);
    return c < 0 ? 0 : c >= g->dim[k] ? g->dim[k] - 1 : c;
}

static int cell_index(const cell_grid *g, int x, int y, int z)
{
    return (z * g->dim[1] + y) * g->dim[0] + x;
}

static int grid_build(cell_grid *g, const float *xyz, int n, float cell)
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
static int grid_nearest(const cell_grid *g, const float *xyz, const float *p)
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

int gar_push_out(const struct fit_model *body, const float *body_xyz, float *xyz, int n,
                 float clearance_m)
{
    int nb = fit_model_vertex_count(body);
    float *normals = malloc((size_t)nb * 3 * sizeof *normals);
    cell_grid g = {0};
    int rc = normals ? grid_build(&g, body_xyz, nb, 2 * clearance_m) : -GAR_ERR_NO_MEMORY;
    if (!rc && fit_model_normals(body, body_xyz, normals))
        rc = -GAR_ERR_ARG;
    for (int v = 0; v < n && !rc; v++) {
        float *p = xyz + 3 * v;
        int b = grid_nearest(&g, body_xyz, p);
        if (b < 0)
            continue;
        const float *q = body_xyz + 3 * b, *nn = normals + 3 * b;
        float d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
        float along = d[0] * nn[0] + d[1] * nn[1] + d[2] * nn[2];
        if (along >= clearance_m &&
            d[0] * d[0] + d[1] * d[1] + d[2] * d[2] >= clearance_m * clearance_m)
            continue;
        /* Keep the tangential offset, set the normal one to the clearance. */
        for (int k = 0; k < 3; k++)
            p[k] += (clearance_m - along) * nn[k];
    }
    free(normals);
    free(g.start);
    free(g.items);
    return rc;
}
