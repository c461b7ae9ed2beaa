/* The person as the renderer takes it: per depth pixel, the depth to test the garment against
 * (pushed back by the camera's uncertainty) and a Lambert shade from the surface's normal. One
 * pass on the CPU, so that the picture's fragments only look the pixel up. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_private.h"

/* Neighbours on one surface differ by less than this fraction of the depth: an arm 0.1 m in
 * front of a torso at 2 m is 5 %; a Kinect v1 disparity step at 4 m is 1.2 % (ARCHITECTURE.md). */
#define MIRROR_EDGE_JUMP 0.03f
/* Normals from neighbours this many pixels away: the sensor's noise averaged over a few pixels. */
#define MIRROR_NORMAL_STEP 3

float mirror_occlusion_margin_m(float z)
{
    /* Three axial sigmas of Kinect v1 noise, 3 (0.0012 + 0.0019 (z - 0.4)^2) m, plus one
     * disparity step, z^2 / (8 f b) = 0.0029 z^2 m (ARCHITECTURE.md, Nguyen et al. 2012): 17 mm
     * at 1.5 m, 47 mm at 2.5 m. Without it the cloth, 15 mm over the skin, flickers behind the
     * noise. */
    return 3.0f * (0.0012f + 0.0019f * (z - 0.4f) * (z - 0.4f)) + 0.0029f * z * z;
}

/* The depth image as the per-pixel work reads it, made once per frame: z in metres (0: no
 * reading) per pixel in a plane with a border of MIRROR_NORMAL_STEP zeros all round, and the
 * back-projection factors per column and per row (over the border too). Converting and
 * range-checking each neighbour of each pixel again, and dividing by fx, cost more than the
 * shading itself (6.4 -> 2.1 ms for a 640x480 frame); the border takes the bounds test out of
 * every neighbour's read (docs/mirror.md). */
#define BORDER MIRROR_NORMAL_STEP
typedef struct depth_view {
    int stride;           /* floats a row of z, the border included */
    const float *z;       /* pixel (0, 0); (u, v) at z[v * stride + u], u and v from -BORDER */
    const float *xs, *ys; /* (u - cx) / fx, (v - cy) / fy; index from -BORDER */
} depth_view;

/* The floats make_view needs besides the image. */
static size_t view_floats(int w, int h)
{
    return (size_t)(w + 2 * BORDER) * (h + 2 * BORDER) + (w + 2 * BORDER) + (h + 2 * BORDER);
}

/* The camera-space point at pixel offset k from (u, v) if it lies on the same surface as depth
 * z, else c. */
static inline void near(const depth_view *w, const float *zp, int k, int u, int v, float z,
                        const float *c, float *out)
{
    /* every term computed, then chosen: no branch, so that the callers' loops are vectorised */
    float zn = zp[k], x = w->xs[u] * zn, y = w->ys[v] * zn;
    int same = (zn > 0.0f) & (fabsf(zn - z) < MIRROR_EDGE_JUMP * z);
    out[0] = same ? x : c[0];
    out[1] = same ? y : c[1];
    out[2] = same ? zn : c[2];
}

/* zp points at (u, v)'s z. */
static inline float shade(const depth_view *w, const float *zp, int u, int v, float z)
{
    const int s = MIRROR_NORMAL_STEP, row = s * w->stride;
    float c[3] = {w->xs[u] * z, w->ys[v] * z, z};
    float l[3], r[3], t[3], b[3];
    near(w, zp, -s, u - s, v, z, c, l);
    near(w, zp, s, u + s, v, z, c, r);
    near(w, zp, -row, u, v - s, z, c, t);
    near(w, zp, row, u, v + s, z, c, b);
    float du[3] = {r[0] - l[0], r[1] - l[1], r[2] - l[2]};
    float dv[3] = {b[0] - t[0], b[1] - t[1], b[2] - t[2]};
    float n[3] = {dv[1] * du[2] - dv[2] * du[1], dv[2] * du[0] - dv[0] * du[2],
                  dv[0] * du[1] - dv[1] * du[0]};
    float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    float q = fabsf(n[2]) / sqrtf(len2 > 0.0f ? len2 : 1.0f);
    return len2 > 0.0f ? q : 1.0f;
}

/* The z plane and the factors, in the caller's buffer. */
static void make_view(const mirror_depth *d, float *buf, depth_view *w)
{
    int stride = d->width + 2 * BORDER, rows = d->height + 2 * BORDER;
    float *z0 = buf, *xs = buf + (size_t)stride * rows, *ys = xs + stride;
    memset(z0, 0, (size_t)stride * BORDER * sizeof *z0); /* the border's top rows */
    memset(z0 + (size_t)stride * (BORDER + d->height), 0, (size_t)stride * BORDER * sizeof *z0);
    for (int v = 0; v < d->height; v++) {
        float *z = z0 + (size_t)(v + BORDER) * stride;
        const uint16_t *px = d->data + (size_t)v * d->width;
        for (int k = 0; k < BORDER; k++)
            z[k] = z[BORDER + d->width + k] = 0.0f;
        for (int u = 0; u < d->width; u++) {
            float m = (float)px[u] * d->metres_per_unit;
            z[BORDER + u] = m >= MIRROR_MIN_DEPTH_M && m <= MIRROR_MAX_DEPTH_M ? m : 0.0f;
        }
    }
    for (int u = -BORDER; u < d->width + BORDER; u++)
        xs[u + BORDER] = ((float)u - d->cx) / d->fx;
    for (int v = -BORDER; v < d->height + BORDER; v++)
        ys[v + BORDER] = ((float)v - d->cy) / d->fy;
    *w = (depth_view){stride, z0 + (size_t)BORDER * stride + BORDER, xs + BORDER, ys + BORDER};
}

/* One row's test depths, shades 0 (no reading) for now: both lanes written, so that the loop is
 * vectorised. */
static void test_depths(const float *restrict z, int n, float *restrict out)
{
    for (int u = 0; u < n; u++) {
        float t = z[u] + mirror_occlusion_margin_m(z[u]);
        out[u * 2] = z[u] > 0.0f ? t : 0.0f;
        out[u * 2 + 1] = 0.0f;
    }
}

/* The shades of row v's block anchors (its even pixels; v even), 0 where there is no reading:
 * every anchor shaded, without a branch, so that the loop is vectorised. */
static void anchor_shades(const depth_view *w, int v, int width, float *restrict orow)
{
    const float *zrow = w->z + (size_t)v * w->stride;
    for (int u = 0; u < width; u += 2) {
        float z = zrow[u], s = shade(w, &zrow[u], u, v, z);
        orow[u * 2 + 1] = z > 0.0f ? s : 0.0f;
    }
}

int mirror_person_image(const mirror_depth *d, float **buf, int *cap)
{
    int n = d->width * d->height;
    /* the image (2 floats a pixel), then the view's z plane and factors */
    size_t need = (size_t)n * 2 + view_floats(d->width, d->height);
    if (need > (size_t)INT_MAX)
        return -MIRROR_ERR_NO_MEMORY;
    if (need > (size_t)*cap) {
        float *p = realloc(*buf, need * sizeof *p);
        if (!p)
            return -MIRROR_ERR_NO_MEMORY;
        *buf = p;
        *cap = (int)need;
    }
    float *out = *buf;
    depth_view w;
    make_view(d, out + (size_t)n * 2, &w);
    for (int v = 0; v < d->height; v++) {
        const float *zrow = w.z + (size_t)v * w.stride;
        const float *arow = w.z + (size_t)(v & ~1) * w.stride; /* the 2x2 block's first row */
        float *orow = out + (size_t)v * d->width * 2;
        const float *srow = out + (size_t)(v & ~1) * d->width * 2;
        test_depths(zrow, d->width, orow);
        if (!(v & 1))
            anchor_shades(&w, v, d->width, orow);
        /* shading is smooth at the normals' 3-pixel scale: one shade per 2x2 block, taken from
         * the block's first pixel where it lies on the same surface (4x less work) */
        for (int u = (v & 1) ? 0 : 1; u < d->width; u += (v & 1) ? 1 : 2) {
            float z = zrow[u], za = arow[u & ~1];
            if (z == 0.0f)
                continue;
            orow[u * 2 + 1] = za > 0.0f && fabsf(za - z) < MIRROR_EDGE_JUMP * z
                                  ? srow[(u & ~1) * 2 + 1]
                                  : shade(&w, &zrow[u], u, v, z);
        }
    }
    return 0;
}
