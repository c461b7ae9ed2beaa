/* The person as the renderer takes it: per depth pixel, the depth to test the garment against
 * (pushed back by the camera's uncertainty) and a Lambert shade from the surface's normal. One
 * pass on the CPU, so that the picture's fragments only look the pixel up. */
#include <math.h>
#include <stdlib.h>

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

/* The depth image with what the per-pixel work needs, computed once: a division per neighbour
 * per pixel cost more than everything else together. */
typedef struct depth_view {
    const mirror_depth *d;
    float inv_fx, inv_fy;
} depth_view;

static float depth_at(const depth_view *w, int u, int v)
{
    const mirror_depth *d = w->d;
    if (u < 0 || v < 0 || u >= d->width || v >= d->height)
        return 0.0f;
    float z = (float)d->data[(size_t)v * d->width + u] * d->metres_per_unit;
    return z >= MIRROR_MIN_DEPTH_M && z <= MIRROR_MAX_DEPTH_M ? z : 0.0f;
}

/* The camera-space point at (u, v) if it lies on the same surface as depth z, else c. */
static void near(const depth_view *w, int u, int v, float z, const float *c, float *out)
{
    float zn = depth_at(w, u, v);
    if (zn > 0.0f && fabsf(zn - z) < MIRROR_EDGE_JUMP * z) {
        out[0] = ((float)u - w->d->cx) * zn * w->inv_fx;
        out[1] = ((float)v - w->d->cy) * zn * w->inv_fy;
        out[2] = zn;
    } else {
        out[0] = c[0];
        out[1] = c[1];
        out[2] = c[2];
    }
}

static float shade(const depth_view *w, int u, int v, float z)
{
    const int s = MIRROR_NORMAL_STEP;
    float c[3] = {((float)u - w->d->cx) * z * w->inv_fx, ((float)v - w->d->cy) * z * w->inv_fy, z};
    float l[3], r[3], t[3], b[3];
    near(w, u - s, v, z, c, l);
    near(w, u + s, v, z, c, r);
    near(w, u, v - s, z, c, t);
    near(w, u, v + s, z, c, b);
    float du[3] = {r[0] - l[0], r[1] - l[1], r[2] - l[2]};
    float dv[3] = {b[0] - t[0], b[1] - t[1], b[2] - t[2]};
    float n[3] = {dv[1] * du[2] - dv[2] * du[1], dv[2] * du[0] - dv[0] * du[2],
                  dv[0] * du[1] - dv[1] * du[0]};
    float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    return len2 > 0.0f ? fabsf(n[2]) / sqrtf(len2) : 1.0f;
}

int mirror_person_image(const mirror_depth *d, float **buf, int *cap)
{
    int n = d->width * d->height;
    if (n > *cap) {
        float *p = realloc(*buf, (size_t)n * 2 * sizeof *p);
        if (!p)
            return -1;
        *buf = p;
        *cap = n;
    }
    float *out = *buf;
    depth_view w = {d, 1.0f / d->fx, 1.0f / d->fy};
    for (int v = 0; v < d->height; v++)
        for (int u = 0; u < d->width; u++) {
            float z = depth_at(&w, u, v), *o = &out[((size_t)v * d->width + u) * 2];
            o[0] = z > 0.0f ? z + mirror_occlusion_margin_m(z) : 0.0f;
            if (z == 0.0f) {
                o[1] = 0.0f;
                continue;
            }
            /* shading is smooth at the normals' 3-pixel scale: one shade per 2x2 block, taken
             * from the block's first pixel where it lies on the same surface (4x less work) */
            int au = u & ~1, av = v & ~1;
            float za = depth_at(&w, au, av);
            o[1] = (au != u || av != v) && za > 0.0f && fabsf(za - z) < MIRROR_EDGE_JUMP * z
                       ? out[((size_t)av * d->width + au) * 2 + 1]
                       : shade(&w, u, v, z);
        }
    return 0;
}
