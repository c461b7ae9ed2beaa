/* After wrapping, a vertex the body's surface still reaches (armpits, the crotch: places no
 * surface of revolution fits) is pushed out along the nearest body vertex's normal to the
 * clearance. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bodyfit.h"
#include "pattern_internal.h"
#include "place_internal.h"

int gar_push_out(const struct fit_model *body, const float *body_xyz, float *xyz, int n,
                 float clearance_m)
{
    int nb = fit_model_vertex_count(body);
    float *normals = malloc((size_t)nb * 3 * sizeof *normals);
    gar_grid g = {0};
    int rc = normals ? gar_grid_build(&g, body_xyz, nb, 2 * clearance_m) : -GAR_ERR_NO_MEMORY;
    if (!rc && fit_model_normals(body, body_xyz, normals))
        rc = -GAR_ERR_ARG;
    for (int v = 0; v < n && !rc; v++) {
        float *p = xyz + 3 * v;
        int b = gar_grid_nearest(&g, body_xyz, p);
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
    gar_grid_free(&g);
    return rc;
}
