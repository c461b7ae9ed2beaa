/* The seed's image-space body (seed 003, after Vassilev et al.): two orthographic cameras at
 * the front and the back of the body's bounding box render depth and normal maps, here
 * rasterised on the CPU. A cloth point whose pixel the body covers and whose z lies between
 * the back and the front depth is inside the body's slab. Front and back alone cannot see the
 * body's sides and tops (a shoulder's normal is nearly perpendicular to z, so a depth along z
 * says little about the depth along the normal), so tryon renders the same pair along x and y
 * too: a point is inside when it is inside all three slabs (a three-view visual hull), and it
 * is pushed out along the normal of the view that finds it shallowest. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "dress_internal.h"

/* A map larger than this is a wrong pixel size, not a body (2 m at 1 mm: 4 M pixels). */
#define GAR_MAP_MAX_PIXELS (8 * 1024 * 1024)

static void rasterise(gar_body_maps *bm, const float *a, const float *b, const float *c,
                      const float n[3])
{
    float lo[2], hi[2];
    for (int k = 0; k < 2; k++) {
        lo[k] = fminf(a[k], fminf(b[k], c[k]));
        hi[k] = fmaxf(a[k], fmaxf(b[k], c[k]));
    }
    int x0 = (int)ceilf((lo[0] - bm->x0) / bm->pixel_m - 0.5f);
    int x1 = (int)floorf((hi[0] - bm->x0) / bm->pixel_m - 0.5f);
    int y0 = (int)ceilf((lo[1] - bm->y0) / bm->pixel_m - 0.5f);
    int y1 = (int)floorf((hi[1] - bm->y0) / bm->pixel_m - 0.5f);
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= bm->w ? bm->w - 1 : x1, y1 = y1 >= bm->h ? bm->h - 1 : y1;
    double det = ((double)b[0] - a[0]) * ((double)c[1] - a[1]) -
                 ((double)c[0] - a[0]) * ((double)b[1] - a[1]);
    if (fabs(det) < 1e-14)
        return; /* seen edge-on: the neighbours cover its pixels */
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            double px = bm->x0 + (x + 0.5) * bm->pixel_m, py = bm->y0 + (y + 0.5) * bm->pixel_m;
            double l1 =
                ((px - a[0]) * ((double)c[1] - a[1]) - ((double)c[0] - a[0]) * (py - a[1])) / det;
            double l2 =
                (((double)b[0] - a[0]) * (py - a[1]) - (px - a[0]) * ((double)b[1] - a[1])) / det;
            double l0 = 1 - l1 - l2;
            /* A hair of slack so shared edges leave no crack between triangles. */
            if (l0 < -1e-6 || l1 < -1e-6 || l2 < -1e-6)
                continue;
            float z = (float)(l0 * a[2] + l1 * b[2] + l2 * c[2]);
            int i = y * bm->w + x;
            if (z > bm->front_z[i]) {
                bm->front_z[i] = z;
                memcpy(bm->front_n + 3 * i, n, 3 * sizeof *n);
            }
            if (z < bm->back_z[i]) {
                bm->back_z[i] = z;
                memcpy(bm->back_n + 3 * i, n, 3 * sizeof *n);
            }
        }
}

/* Coordinates of p seen along axis: (across, up, depth). */
static void view(int axis, const float *p, float out[3])
{
    static const int order[3][3] = {{2, 1, 0}, {0, 2, 1}, {0, 1, 2}};
    for (int k = 0; k < 3; k++)
        out[k] = p[order[axis][k]];
}

static int render_axis(const float *xyz, int nv, const int32_t *tris, int nt, float pixel_m,
                       int axis, gar_body_maps *bm)
{
    memset(bm, 0, sizeof *bm);
    bm->axis = axis;
    float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY}, q[3];
    for (int v = 0; v < nv; v++) {
        view(axis, xyz + 3 * v, q);
        for (int k = 0; k < 2; k++)
            lo[k] = fminf(lo[k], q[k]), hi[k] = fmaxf(hi[k], q[k]);
    }
    bm->pixel_m = pixel_m;
    bm->x0 = lo[0] - 2 * pixel_m;
    bm->y0 = lo[1] - 2 * pixel_m;
    bm->w = (int)((hi[0] - lo[0]) / pixel_m) + 4;
    bm->h = (int)((hi[1] - lo[1]) / pixel_m) + 4;
    if (!(pixel_m > 0) || (double)bm->w * bm->h > GAR_MAP_MAX_PIXELS)
        return -GAR_ERR_RANGE;
    size_t n = (size_t)bm->w * bm->h;
    bm->front_z = malloc(n * sizeof *bm->front_z);
    bm->back_z = malloc(n * sizeof *bm->back_z);
    bm->front_n = calloc(n * 3, sizeof *bm->front_n);
    bm->back_n = calloc(n * 3, sizeof *bm->back_n);
    if (!bm->front_z || !bm->back_z || !bm->front_n || !bm->back_n) {
        gar_body_maps_free(bm);
        return -GAR_ERR_NO_MEMORY;
    }
    for (size_t i = 0; i < n; i++)
        bm->front_z[i] = -INFINITY, bm->back_z[i] = INFINITY;
    for (int t = 0; t < nt; t++) {
        const float *a = xyz + 3 * tris[3 * t], *b = xyz + 3 * tris[3 * t + 1],
                    *c = xyz + 3 * tris[3 * t + 2];
        float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float nn[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        float l = sqrtf(nn[0] * nn[0] + nn[1] * nn[1] + nn[2] * nn[2]);
        if (!(l > 0))
            continue;
        nn[0] /= l, nn[1] /= l, nn[2] /= l;
        float va[3], vb[3], vc[3];
        view(axis, a, va), view(axis, b, vb), view(axis, c, vc);
        rasterise(bm, va, vb, vc, nn);
    }
    return 0;
}

int gar_body_maps_render(const float *xyz, int nv, const int32_t *tris, int nt, float pixel_m,
                         gar_body_maps bm[3])
{
    for (int axis = 0; axis < 3; axis++) {
        int rc = render_axis(xyz, nv, tris, nt, pixel_m, axis, &bm[axis]);
        if (rc) {
            for (int k = 0; k <= axis; k++)
                gar_body_maps_free(&bm[k]);
            return rc;
        }
    }
    return 0;
}

void gar_body_maps_free(gar_body_maps *bm)
{
    free(bm->front_z), free(bm->back_z), free(bm->front_n), free(bm->back_n);
    memset(bm, 0, sizeof *bm);
}

/* One view: 0 outside its slab, else 1 with the depth along the normal and the normal. */
static int collide_axis(const gar_body_maps *bm, const float pw[3], float margin_m, float *depth,
                        const float **normal)
{
    float p[3];
    view(bm->axis, pw, p);
    int x = (int)floorf((p[0] - bm->x0) / bm->pixel_m),
        y = (int)floorf((p[1] - bm->y0) / bm->pixel_m);
    if (x < 0 || y < 0 || x >= bm->w || y >= bm->h)
        return 0;
    int i = y * bm->w + x;
    float f = bm->front_z[i], b = bm->back_z[i];
    if (!(f >= b) || p[2] >= f + margin_m || p[2] <= b - margin_m)
        return 0;
    /* The nearer side in z; the depth along z becomes a depth along the map's normal. */
    int front = p[2] - (f + b) / 2 >= 0;
    const float *n = front ? bm->front_n + 3 * i : bm->back_n + 3 * i;
    float dz = front ? f + margin_m - p[2] : p[2] - (b - margin_m);
    *depth = dz * fabsf(n[bm->axis]);
    *normal = n;
    return 1;
}

int gar_body_maps_collide(const gar_body_maps bm[3], const float p[3], float margin_m,
                          float push[3], float n_out[3])
{
    float best = INFINITY;
    const float *bn = NULL;
    for (int axis = 0; axis < 3; axis++) {
        float depth;
        const float *n;
        if (!collide_axis(&bm[axis], p, margin_m, &depth, &n))
            return 0; /* outside one slab: outside the hull */
        if (depth < best)
            best = depth, bn = n;
    }
    for (int k = 0; k < 3; k++)
        push[k] = best * bn[k], n_out[k] = bn[k];
    return 1;
}
