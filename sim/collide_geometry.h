/* Private to sim/: the geometry the C collider and its OpenCL twins (kernels/common.cl) share,
 * split from collide.h. */
#ifndef TRYON_SIM_COLLIDE_GEOMETRY_H
#define TRYON_SIM_COLLIDE_GEOMETRY_H

#include <stdint.h>

/* ---- Geometry shared by the C reference and its OpenCL twins --------------------------------- */

/* 3-vectors in float[3] (or the xyz of a float[4]), the operations in the kernels' order. */
static inline void sim_v3_sub(const float *a, const float *b, float *o)
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

static inline float sim_v3_dot(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void sim_v3_cross(const float *a, const float *b, float *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* Squared distance from p to the segment a-b (C only: the shirt's arm tubes, the motion probe's
   bones). */
static inline float sim_segment_dist2(const float *p, const float *a, const float *b)
{
    float ab[3], ap[3];
    sim_v3_sub(b, a, ab);
    sim_v3_sub(p, a, ap);
    float l2 = sim_v3_dot(ab, ab);
    float t = l2 > 0.0f ? sim_v3_dot(ap, ab) / l2 : 0.0f;
    t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    float d[3] = {ap[0] - t * ab[0], ap[1] - t * ab[1], ap[2] - t * ab[2]};
    return sim_v3_dot(d, d);
}

/* Where the closest point of a triangle lies: its face, one of its vertices, or one of its edges
   (edge i joins vertex i and vertex (i+1)%3). */
enum {
    SIM_REGION_FACE = 0,
    SIM_REGION_V0,
    SIM_REGION_V1,
    SIM_REGION_V2,
    SIM_REGION_E01,
    SIM_REGION_E12,
    SIM_REGION_E20
};

/* Closest point q on triangle (a, b, c) to p (Ericson, Real-Time Collision Detection 5.1.5), its
   barycentric coordinates and its region. */
int sim_closest_on_triangle(const float p[3], const float a[3], const float b[3], const float c[3],
                            float q[3], float bary[3]);

/* sim_closest_on_triangle for p against four triangles at once, without branches (every region's
   candidate computed, the scalar code's order of tests as masks): tri[vertex][axis][lane]. Each
   lane is bit for bit what the scalar function gives for that triangle: q[axis][lane],
   bary[k][lane], the region, and d2 = |p - q|^2 summed as the nearest search sums it. */
void sim_closest_on_triangle4(const float p[3], const float tri[3][3][4], float q[3][4],
                              float bary[3][4], float d2[4], int32_t region[4]);

#endif
