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
 *   - laterally, the projection of p onto the plane of the triangle interpolated at the moment t*
 *     its offset surface crossed p (linear in the plane distances) lies within thickness of it
 *     (the offset surface is rounded at convex edges and vertices, as a Minkowski sum is).
 * Several triangles may claim p (seed 000 Figure 2): the one nearest to p at k-1 wins. */
#include <math.h>
#include <string.h>

#include "collide.h"
#include "collide_bvh.h"
#include "collide_geometry.h"

/* Traversal stack: the LBVH depth bound of sim/bvh.c (96), three more a level when 4-wide. */
#define FP_STACK (3 * 96)

/* Is p in the swept prism of triangle t? */
static int in_swept_prism(const sim_collider *c, int t, const float p[3])
{
    const int32_t *f = c->tris[t];
    float h = c->d.thickness_m, r[3];
    sim_v3_sub(p, c->v_prev[f[0]], r);
    float d0 = sim_v3_dot(r, c->n_prev[t]);
    sim_v3_sub(p, c->v[f[0]], r);
    float d1 = sim_v3_dot(r, c->n[t]);
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
    /* Laterally: p's projection onto the plane of T(t*) lies within thickness of the triangle.
       The slack covers the rounded offset surface at convex edges and vertices, where a point
       above a vertex lies outside every face's own prism. */
    float q[3], bary[3], ab[3], ac[3], nr[3];
    sim_closest_on_triangle(p, a, b, cc, q, bary);
    sim_v3_sub(b, a, ab);
    sim_v3_sub(cc, a, ac);
    sim_v3_cross(ab, ac, nr);
    float nn = sim_v3_dot(nr, nr);
    if (!(nn > 0.0f))
        return 0;
    sim_v3_sub(p, q, r);
    float rn = sim_v3_dot(r, nr);
    float lateral2 = sim_v3_dot(r, r) - rn * rn / nn;
    return lateral2 <= h * h;
}

/* Seed 000 Eq. 1-2 for point p and its triangle t: new position in out. */
static void carry(const sim_collider *c, int t, const float p[3], float out[3])
{
    const int32_t *f = c->tris[t];
    float q[3], theta[3], r[3];
    /* Eq. 1: project p onto T^{k-1}; theta its barycentrics, clamped to the triangle (the
       closest point is the normal projection when that falls inside). */
    sim_closest_on_triangle(p, c->v_prev[f[0]], c->v_prev[f[1]], c->v_prev[f[2]], q, theta);
    sim_v3_sub(p, q, r);
    float dist = sim_v3_dot(r, c->n_prev[t]);
    float off = dist > c->d.thickness_m ? dist : c->d.thickness_m;
    /* Eq. 2: the same barycentrics on T^k, at max(dist, thickness) along n^k. */
    for (int k = 0; k < 3; k++)
        out[k] = theta[0] * c->v[f[0]][k] + theta[1] * c->v[f[1]][k] + theta[2] * c->v[f[2]][k] +
                 off * c->n[t][k];
}

/* The tryon solver's carry (carry_coulomb): of the displacement out - p that Eq. 2 gives, the part
   along n^k, the body pushing the point out, is taken whole, the part along the surface only up to
   friction times it, as much as a Coulomb contact passes on. Eq. 2 carries a swept point with
   all of its triangle's motion, as if glued: a torso that turns drags the cloth it touches round
   with it, hoops stretch between the carried points and their neighbours (docs/sim.md, "Strain in
   motion"). The point keeps its height above T^k's plane (the change is along the surface). */
static void coulomb_carry(const sim_collider *c, int t, const float p[3], float out[3])
{
    const float *n = c->n[t];
    float d[3], s[3];
    sim_v3_sub(out, p, d);
    float dn = sim_v3_dot(d, n);
    for (int k = 0; k < 3; k++)
        s[k] = d[k] - dn * n[k];
    float slide = sqrtf(sim_v3_dot(s, s)), most = c->d.friction * fabsf(dn);
    if (!(slide > most))
        return;
    float keep = most / slide;
    for (int k = 0; k < 3; k++)
        out[k] = p[k] + dn * n[k] + keep * s[k];
}

static int in_swept_box(const sim_bvh *b, int node, const float p[3])
{
    const float *lo = b->slo[node], *hi = b->shi[node];
    return p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] && p[2] >= lo[2] &&
           p[2] <= hi[2];
}

/* Triangle t against the best so far: in the swept prism, and nearer to p at k-1 (ties: lower
   index). The best of a set is the same whatever the order its members come in. */
static void take_candidate(const sim_collider *c, int t, const float p[3], int *best,
                           float *best_d2)
{
    if (!in_swept_prism(c, t, p))
        return;
    const int32_t *f = c->tris[t];
    float q[3], bary[3], r[3];
    sim_closest_on_triangle(p, c->v_prev[f[0]], c->v_prev[f[1]], c->v_prev[f[2]], q, bary);
    sim_v3_sub(p, q, r);
    float d2 = sim_v3_dot(r, r);
    if (d2 < *best_d2 || (d2 == *best_d2 && t < *best)) {
        *best = t;
        *best_d2 = d2;
    }
}

/* D-BVH traversal: every triangle whose swept box holds p and whose swept prism holds p is a
   feature pair; the one nearest to p on frame k-1 wins (ties: lower triangle index). No cap on
   the candidates: a fast limb's swept boxes are several triangles wide, so a point sits in dozens
   of them. -1 when none. The descent follows the 4-wide shape of the tree (sim_bvh_node4) over
   the binary nodes' swept boxes: half the pops, and the binary nodes it skips hold their slots'
   boxes, so the leaves reached are the same (those whose own box holds p). */
static int choose_triangle(const sim_collider *c, const float p[3])
{
    const sim_bvh *b = &c->bvh;
    int best = -1;
    float best_d2 = INFINITY;
    if (!in_swept_box(b, 0, p))
        return -1;
    if (b->n == 1) {
        take_candidate(c, b->order[0], p, &best, &best_d2);
        return best;
    }
    int stack[FP_STACK], top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int w = stack[--top];
        const sim_bvh_node4 *q = &b->wide[w];
        for (int k = 0; k < q->count; k++) {
            if (!in_swept_box(b, b->wide_node[w][k], p))
                continue;
            if (q->next[k] < 0)
                take_candidate(c, b->order[-1 - q->next[k]], p, &best, &best_d2);
            else if (top < FP_STACK)
                stack[top++] = q->next[k];
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
        int t = choose_triangle(c, x[i]);
        if (t < 0)
            continue;
        float p[3];
        carry(c, t, x[i], p);
        if (c->d.carry_coulomb)
            coulomb_carry(c, t, x[i], p);
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
