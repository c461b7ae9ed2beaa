/* Signed distance to the body mesh for the penetration figure: the closest point over the
 * triangles around the nearest body vertex, signed by that triangle's outward normal. Exact
 * where the nearest triangle touches the nearest vertex, which holds on the body's even mesh. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dress_internal.h"
#include "place_internal.h"

/* Points farther than this from every body vertex are outside (grid reach). */
#define GAR_SDF_REACH_M 0.05f

struct gar_body_sdf {
    const float *xyz;
    const int32_t *tris;
    gar_grid grid;
    int32_t *vt_offset, *vt; /* triangles per vertex */
};

gar_body_sdf *gar_body_sdf_create(const float *xyz, int nv, const int32_t *tris, int nt)
{
    gar_body_sdf *b = calloc(1, sizeof *b);
    if (!b)
        return NULL;
    b->xyz = xyz, b->tris = tris;
    b->vt_offset = calloc((size_t)nv + 1, sizeof *b->vt_offset);
    b->vt = malloc((size_t)(3 * nt + 1) * sizeof *b->vt);
    if (!b->vt_offset || !b->vt || gar_grid_build(&b->grid, xyz, nv, GAR_SDF_REACH_M)) {
        gar_body_sdf_destroy(b);
        return NULL;
    }
    for (int i = 0; i < 3 * nt; i++)
        b->vt_offset[tris[i] + 1]++;
    for (int v = 0; v < nv; v++)
        b->vt_offset[v + 1] += b->vt_offset[v];
    int *fill = malloc((size_t)(nv + 1) * sizeof *fill);
    if (!fill) {
        gar_body_sdf_destroy(b);
        return NULL;
    }
    memcpy(fill, b->vt_offset, (size_t)(nv + 1) * sizeof *fill);
    for (int i = 0; i < 3 * nt; i++)
        b->vt[fill[tris[i]]++] = i / 3;
    free(fill);
    return b;
}

/* Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5). */
static void closest_on_triangle(const float *p, const float *a, const float *b, const float *c,
                                float *q)
{
    float ab[3], ac[3], ap[3];
    for (int k = 0; k < 3; k++)
        ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
#define DOT(u, v) ((u)[0] * (v)[0] + (u)[1] * (v)[1] + (u)[2] * (v)[2])
    float d1 = DOT(ab, ap), d2 = DOT(ac, ap);
    if (d1 <= 0 && d2 <= 0) {
        memcpy(q, a, 3 * sizeof *q);
        return;
    }
    float bp[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
    float d3 = DOT(ab, bp), d4 = DOT(ac, bp);
    if (d3 >= 0 && d4 <= d3) {
        memcpy(q, b, 3 * sizeof *q);
        return;
    }
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        float v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++)
            q[k] = a[k] + v * ab[k];
        return;
    }
    float cp[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
    float d5 = DOT(ab, cp), d6 = DOT(ac, cp);
    if (d6 >= 0 && d5 <= d6) {
        memcpy(q, c, 3 * sizeof *q);
        return;
    }
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        float w = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++)
            q[k] = a[k] + w * ac[k];
        return;
    }
    float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++)
            q[k] = b[k] + w * (c[k] - b[k]);
        return;
    }
    float den = 1 / (va + vb + vc), v = vb * den, w = vc * den;
    for (int k = 0; k < 3; k++)
        q[k] = a[k] + ab[k] * v + ac[k] * w;
}

float gar_body_sdf_eval(const gar_body_sdf *b, const float p[3])
{
    int v = gar_grid_nearest(&b->grid, b->xyz, p);
    if (v < 0)
        return 1.0f;
    float best = INFINITY, sign = 1;
    for (int i = b->vt_offset[v]; i < b->vt_offset[v + 1]; i++) {
        const int32_t *t = b->tris + 3 * b->vt[i];
        const float *a = b->xyz + 3 * t[0], *c1 = b->xyz + 3 * t[1], *c2 = b->xyz + 3 * t[2];
        float q[3], d[3], e1[3], e2[3], n[3];
        closest_on_triangle(p, a, c1, c2, q);
        for (int k = 0; k < 3; k++)
            d[k] = p[k] - q[k], e1[k] = c1[k] - a[k], e2[k] = c2[k] - a[k];
        float dist = sqrtf(DOT(d, d));
        if (dist < best) {
            n[0] = e1[1] * e2[2] - e1[2] * e2[1];
            n[1] = e1[2] * e2[0] - e1[0] * e2[2];
            n[2] = e1[0] * e2[1] - e1[1] * e2[0];
            best = dist;
            sign = DOT(d, n) < 0 ? -1.0f : 1.0f;
        }
    }
#undef DOT
    return sign * best;
}

void gar_body_sdf_destroy(gar_body_sdf *b)
{
    if (!b)
        return;
    gar_grid_free(&b->grid);
    free(b->vt_offset), free(b->vt), free(b);
}
