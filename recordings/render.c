/* The simulated camera and scene: a pinhole depth camera (Kinect v1 intrinsics, recordings.h),
 * a floor, a back wall, an optional box, and a z-buffer rasteriser for the body's triangles. */
#include <math.h>

#include "recordings.h"

void rec_camera_to_world(float m[16])
{
    /* Camera x = world +x, camera y (down) = world -y, optical axis = world -z. */
    static const float c2w[16] = {
        1, 0, 0, 0, 0, -1, 0, REC_CAMERA_HEIGHT_M, 0, 0, -1, REC_CAMERA_DISTANCE_M, 0, 0, 0, 1};
    for (int i = 0; i < 16; i++)
        m[i] = c2w[i];
}

rec_scene rec_scene_default(int with_box)
{
    /* The box stands on the floor half a metre in front of the person, covering the legs and
     * one side of the hips: the "partial occlusion" case. */
    return (rec_scene){.wall_z = -1.5f,
                       .has_box = with_box,
                       .box_min = {-0.05f, 0.0f, 0.55f},
                       .box_max = {0.55f, 0.85f, 0.85f}};
}

static void to_camera(const float m[16], const float *p, double out[3])
{
    double d[3] = {p[0] - m[3], p[1] - m[7], p[2] - m[11]};
    for (int k = 0; k < 3; k++)
        out[k] = m[0 * 4 + k] * d[0] + m[1 * 4 + k] * d[1] + m[2 * 4 + k] * d[2];
}

/* Ray-box slab test; returns the entry parameter or INFINITY. */
static double hit_box(const rec_scene *s, const double o[3], const double d[3])
{
    double t0 = 0.0, t1 = INFINITY;
    for (int k = 0; k < 3; k++) {
        if (fabs(d[k]) < 1e-12) {
            if (o[k] < s->box_min[k] || o[k] > s->box_max[k])
                return INFINITY;
            continue;
        }
        double a = (s->box_min[k] - o[k]) / d[k], b = (s->box_max[k] - o[k]) / d[k];
        if (a > b) {
            double t = a;
            a = b;
            b = t;
        }
        t0 = fmax(t0, a);
        t1 = fmin(t1, b);
        if (t0 > t1)
            return INFINITY;
    }
    return t0 > 0.0 ? t0 : INFINITY;
}

void rec_render_background(const rec_scene *s, const float m[16], float *depth_m)
{
    double o[3] = {m[3], m[7], m[11]};
    for (int v = 0; v < REC_HEIGHT; v++)
        for (int u = 0; u < REC_WIDTH; u++) {
            /* Ray with unit optical-axis component, so its parameter is the depth. */
            double dc[3] = {(u - REC_CX) / REC_FX, (v - REC_CY) / REC_FY, 1.0};
            double d[3];
            for (int k = 0; k < 3; k++)
                d[k] = m[k * 4 + 0] * dc[0] + m[k * 4 + 1] * dc[1] + m[k * 4 + 2] * dc[2];
            double best = INFINITY;
            if (d[1] < 0.0)
                best = fmin(best, -o[1] / d[1]);
            if ((s->wall_z - o[2]) / d[2] > 0.0)
                best = fmin(best, (s->wall_z - o[2]) / d[2]);
            if (s->has_box)
                best = fmin(best, hit_box(s, o, d));
            depth_m[v * REC_WIDTH + u] = isfinite(best) ? (float)best : 0.0f;
        }
}

#define NEAR_M 0.1

static void raster_triangle(const double p[3][3], float *depth_m)
{
    double x[3], y[3], iz[3];
    for (int k = 0; k < 3; k++) {
        if (p[k][2] < NEAR_M)
            return; /* nothing tryon films comes this close; no clipping needed */
        iz[k] = 1.0 / p[k][2];
        x[k] = REC_FX * p[k][0] * iz[k] + REC_CX;
        y[k] = REC_FY * p[k][1] * iz[k] + REC_CY;
    }
    double area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0]);
    if (fabs(area) < 1e-12)
        return;
    int u0 = (int)ceil(fmin(x[0], fmin(x[1], x[2]))), u1 = (int)floor(fmax(x[0], fmax(x[1], x[2])));
    int v0 = (int)ceil(fmin(y[0], fmin(y[1], y[2]))), v1 = (int)floor(fmax(y[0], fmax(y[1], y[2])));
    u0 = u0 < 0 ? 0 : u0;
    v0 = v0 < 0 ? 0 : v0;
    u1 = u1 >= REC_WIDTH ? REC_WIDTH - 1 : u1;
    v1 = v1 >= REC_HEIGHT ? REC_HEIGHT - 1 : v1;
    for (int v = v0; v <= v1; v++)
        for (int u = u0; u <= u1; u++) {
            /* Pixel centres sit on integer coordinates, as in freenect_camera_to_world. */
            double w0 = ((x[1] - u) * (y[2] - v) - (x[2] - u) * (y[1] - v)) / area;
            double w1 = ((x[2] - u) * (y[0] - v) - (x[0] - u) * (y[2] - v)) / area;
            double w2 = 1.0 - w0 - w1;
            if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0)
                continue;
            /* 1/z is affine in the image for a planar triangle: interpolate it, not z. */
            float z = (float)(1.0 / (w0 * iz[0] + w1 * iz[1] + w2 * iz[2]));
            float *dst = &depth_m[v * REC_WIDTH + u];
            if (!(*dst > 0.0f) || z < *dst)
                *dst = z;
        }
}

void rec_render_triangles(const float m[16], const float *vertices, const int32_t *triangles,
                          int triangle_count, float *depth_m)
{
    for (int t = 0; t < triangle_count; t++) {
        double p[3][3];
        for (int k = 0; k < 3; k++)
            to_camera(m, &vertices[3 * triangles[3 * t + k]], p[k]);
        raster_triangle(p, depth_m);
    }
}
