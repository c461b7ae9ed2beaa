/* Seed 000 section 2.1: feature points. A cloth point that the body swept over between frames
 * k-1 and k is carried with the triangle that swept it, before the static simulation of frame k.
 * Twin: kernels/feature_points.cl.
 *
 * The swept volume of triangle T is the prism between the offset surface of T^{k-1} and that of
 * T^k (offset = thickness). A point p is in it when
 *   - it was outside the body at k-1: d0 = n^{k-1}.(p - v0^{k-1}) >= -thickness,
 *   - it is inside the offset surface at k: d1 = n^k.(p - v0^k) < thickness,
 *   - the triangle came towards it (d1 < d0; a point resting on a body part sliding past is left
 *     to contacts and friction),
 *   - laterally, the projection of p onto the triangle interpolated at the moment t* its offset
 *     surface crossed p (linear in the plane distances) lies inside it.
 * Several triangles may claim p (seed 000 Figure 2): the one nearest to p at k-1 wins. */
#include <math.h>
#include <string.h>

#include "collide.h"

/* Candidates per point from the D-BVH; a point in more swept boxes keeps the first ones (the
   D-BVH leaves of a body frame overlap a point a handful of times at most). */
#define FP_MAX_CANDIDATES 32
/* Barycentric slack on the lateral test so a point on a shared edge is claimed by both sides
   despite rounding; distance-based selection then picks one. */
#define FP_BARY_SLACK 1e-4f

static void sub3(const float *a, const float *b, float *o)
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

static float dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const float *a, const float *b, float *o)
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* Is p in the swept prism of triangle t? */
static int in_swept_prism(const sim_collider *c, int t, const float p[3])
{
    const int32_t *f = c->tris[t];
    float h = c->d.thickness_m, r[3];
    sub3(p, c->v_prev[f[0]], r);
    float d0 = dot3(r, c->n_prev[t]);
    sub3(p, c->v[f[0]], r);
    float d1 = dot3(r, c->n[t]);
    if (!(d0 >= -h && d1 < h && d1 < d0))
        return 0;
    float e0 = d0 - h, e1 = d1 - h;
    float ts = e0 > 0.0f ? e0 / (e0 - e1) : 0.0f;
    float a[3], b[3], cc[3];
    for (int k = 0; k < 3; k++) {
        a[k] = c->v_prev[f[0]][k] + ts * (c->v[f[0]][k] - c->v_prev[f[0]][k]);
        b[k] = c->v_prev[f[1]][k] + ts * (c->v[f[1]][k] - c->v_prev[f[1]][k]);
        cc[k] = c->v_prev[f[2]][k] + ts * (c->v[f[2]][k] - c->v_prev[f[2]][k]);
    }
    /* Barycentrics of p's projection onto the plane of (a, b, cc): signed sub-areas. */
    float ab[3], ac[3], nr[3], pa[3], pb[3], pc[3], w[3];
    sub3(b, a, ab);
    sub3(cc, a, ac);
    cross3(ab, ac, nr);
    float nn = dot3(nr, nr);
    if (!(nn > 0.0f))
        return 0;
    sub3(a, p, pa);
    sub3(b, p, pb);
    sub3(cc, p, pc);
    cross3(pb, pc, w);
    float u = dot3(w, nr) / nn;
    cross3(pc, pa, w);
    float v = dot3(w, nr) / nn;
    return u >= -FP_BARY_SLACK && v >= -FP_BARY_SLACK && 1.0f - u - v >= -FP_BARY_SLACK;
}

/* Seed 000 Eq. 1-2 for point p and its triangle t: new position in out. */
static void carry(const sim_collider *c, int t, const float p[3], float out[3])
{
    const int32_t *f = c->tris[t];
    float q[3], theta[3], r[3];
    /* Eq. 1: project p onto T^{k-1}; theta its barycentrics, clamped to the triangle (the
       closest point is the normal projection when that falls inside). */
    sim_closest_on_triangle(p, c->v_prev[f[0]], c->v_prev[f[1]], c->v_prev[f[2]], q, theta);
    sub3(p, q, r);
    float dist = dot3(r, c->n_prev[t]);
    float off = dist > c->d.thickness_m ? dist : c->d.thickness_m;
    /* Eq. 2: the same barycentrics on T^k, at max(dist, thickness) along n^k. */
    for (int k = 0; k < 3; k++)
        out[k] = theta[0] * c->v[f[0]][k] + theta[1] * c->v[f[1]][k] + theta[2] * c->v[f[2]][k] +
                 off * c->n[t][k];
}

/* The candidate nearest to p on the previous frame (ties: lower triangle index); -1 if none is
   a feature pair. */
static int choose_triangle(const sim_collider *c, const float p[3], const int32_t *cand, int nc)
{
    int best = -1;
    float best_d2 = INFINITY;
    for (int j = 0; j < nc; j++) {
        int t = cand[j];
        if (!in_swept_prism(c, t, p))
            continue;
        const int32_t *f = c->tris[t];
        float q[3], bary[3], r[3];
        sim_closest_on_triangle(p, c->v_prev[f[0]], c->v_prev[f[1]], c->v_prev[f[2]], q, bary);
        sub3(p, q, r);
        float d2 = dot3(r, r);
        if (d2 < best_d2 || (d2 == best_d2 && t < best)) {
            best = t;
            best_d2 = d2;
        }
    }
    return best;
}

int sim_collider_feature_points(sim_collider *c, float (*x)[4], float (*x_prev)[4], int begin,
                                int end)
{
    if (!c || !x || !x_prev || !c->have_prev || c->nt == 0)
        return 0;
    int moved = 0;
#pragma omp parallel for schedule(static) reduction(+ : moved)
    for (int i = begin; i < end; i++) {
        if (x[i][3] == 0.0f)
            continue; /* pinned: moved only by its owner */
        int32_t cand[FP_MAX_CANDIDATES];
        int nc = sim_bvh_containing(&c->bvh, x[i], 1, cand, FP_MAX_CANDIDATES);
        nc = nc < FP_MAX_CANDIDATES ? nc : FP_MAX_CANDIDATES;
        int t = nc > 0 ? choose_triangle(c, x[i], cand, nc) : -1;
        if (t < 0)
            continue;
        float p[3];
        carry(c, t, x[i], p);
        for (int k = 0; k < 3; k++) {
            float step = p[k] - x[i][k];
            x[i][k] = p[k];
            x_prev[i][k] += step; /* same displacement: the point keeps its velocity */
        }
        if (i < c->max_cloth)
            c->contact[i] = t; /* the carrying triangle is the point's contact now */
        moved++;
    }
    return moved;
}
