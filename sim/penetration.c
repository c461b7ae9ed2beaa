/* The penetration metric: cloth points more than tol inside the body, by signed distance with
 * angle-weighted pseudo-normals (Baerentzen & Aanaes 2005).
 *
 * Exact, and cheap for the usual point: from the point's cached contact, walk over the surface to
 * the locally nearest point q (sim_collider_walk_nearest). If p lies on the outer side there, p is
 * outside the body unless the segment p -> q crosses the surface: a closed surface separates
 * inside from outside, and just short of q the segment is outside. So only a segment cast through
 * the tree is needed (a thin line touches few boxes); when it hits anything, or p is on the
 * inner side, the unbounded nearest search decides. A point without a contact is far from the
 * surface: the parity of the crossings of a segment out of the body's box (sideways, away from its
 * vertical axis) tells outside (even) from inside; an odd count, or a crossing too near an edge to
 * count, goes to the exact search. Cheaper still, and first: a point the contact search of this
 * body frame saw outside by w, that has moved less than w since, is outside (still_outside).
 * sim_collider_penetration_exact does the unbounded search for every point. */
#include <math.h>

#include "collide.h"
#include "collide_bvh.h"
#include "collide_geometry.h"

/* Hits this close to q (as a fraction of |p - q|) are the surface at q itself. */
#define SEG_END 0.999f
/* Barycentric slack: a segment through a shared edge counts as a hit on both sides. */
#define SEG_SLACK 1e-5f
/* Box slack for the segment's traversal, metres: above float rounding of a 2 m scene. */
#define SEG_BOX_PAD 1e-6f
#define SEG_STACK   (3 * 96) /* the trees' depth bound, three more a level when 4-wide */
/* Within this of the body's vertical axis (metres) the parity segment goes up, not sideways. */
#define SEG_AXIS_M 0.01f
/* Slack on a clearance bound, metres: far above the rounding of a distance in a 2 m scene
   (float ulp there ~2e-7 m), far below the metric's 1 mm tolerance. */
#define CLEAR_SLACK 1e-5f

/* Segment o + t d, t in [0, tmax], against triangle (a, b, c) (Moeller & Trumbore 1997): 0 no hit,
   1 a clear hit, 2 a hit within slack of an edge or end (a vertex or edge crossing may count
   twice or not at all: the caller then asks the exact search). A segment in the triangle's plane
   is no hit: it cannot change sides without crossing a neighbour. */
static int segment_hits(const float o[3], const float d[3], float tmax, const float *a,
                        const float *b, const float *c)
{
    float e1[3], e2[3], pv[3], tv[3], qv[3];
    sim_v3_sub(b, a, e1);
    sim_v3_sub(c, a, e2);
    sim_v3_cross(d, e2, pv);
    float det = sim_v3_dot(e1, pv);
    if (det == 0.0f)
        return 0;
    float inv = 1.0f / det;
    sim_v3_sub(o, a, tv);
    float u = sim_v3_dot(tv, pv) * inv;
    if (u < -SEG_SLACK || u > 1.0f + SEG_SLACK)
        return 0;
    sim_v3_cross(tv, e1, qv);
    float v = sim_v3_dot(d, qv) * inv;
    if (v < -SEG_SLACK || u + v > 1.0f + SEG_SLACK)
        return 0;
    float t = sim_v3_dot(e2, qv) * inv;
    if (t < -SEG_SLACK || t > tmax + SEG_SLACK)
        return 0;
    int clear = u > SEG_SLACK && v > SEG_SLACK && u + v < 1.0f - SEG_SLACK && t > SEG_SLACK &&
                t < tmax - SEG_SLACK;
    return clear ? 1 : 2;
}

static int segment_box(const float o[3], const float d[3], float tmax, const float *lo,
                       const float *hi)
{
    float t0 = 0.0f, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        float l = lo[k] - SEG_BOX_PAD, h = hi[k] + SEG_BOX_PAD;
        if (d[k] == 0.0f) {
            if (o[k] < l || o[k] > h)
                return 0;
            continue;
        }
        float a = (l - o[k]) / d[k], b = (h - o[k]) / d[k];
        if (a > b) {
            float s = a;
            a = b;
            b = s;
        }
        t0 = a > t0 ? a : t0;
        t1 = b < t1 ? b : t1;
        if (t0 > t1)
            return 0;
    }
    return 1;
}

/* Triangle t against the segment: the crossings so far, or -1 once one is unsure. */
static int count_hit(const sim_collider *c, int t, const float p[3], const float d[3], float tmax,
                     int n)
{
    const int32_t *f = c->tris[t];
    int h = segment_hits(p, d, tmax, c->v[f[0]], c->v[f[1]], c->v[f[2]]);
    return h == 2 ? -1 : n + h;
}

/* Crossings of the segment p -> p + tmax d with the body: their number, or -1 when one of them
   is too close to an edge or an end to count reliably. The descent follows the 4-wide shape of
   the tree (sim_bvh_node4) over the binary boxes: a box holds its children's, and the slab test
   is monotone in the box (each bound's rounding is), so the leaves reached are exactly those
   whose own box the segment meets, as in the binary descent, and the count is theirs. */
static int segment_crossings(const sim_collider *c, const float p[3], const float d[3], float tmax)
{
    const sim_bvh *b = &c->bvh;
    if (!segment_box(p, d, tmax, b->lo[0], b->hi[0]))
        return 0;
    if (b->n == 1)
        return count_hit(c, b->order[0], p, d, tmax, 0);
    int stack[SEG_STACK], top = 0, n = 0;
    stack[top++] = 0;
    while (top > 0) {
        int w = stack[--top];
        const sim_bvh_node4 *q = &b->wide[w];
        for (int k = 0; k < q->count; k++) {
            int bn = b->wide_node[w][k];
            if (!segment_box(p, d, tmax, b->lo[bn], b->hi[bn]))
                continue;
            if (q->next[k] < 0) {
                n = count_hit(c, b->order[-1 - q->next[k]], p, d, tmax, n);
                if (n < 0)
                    return -1;
            } else if (top < SEG_STACK) {
                stack[top++] = q->next[k];
            } else {
                return -1; /* cannot happen; "unsure" lets the exact search decide */
            }
        }
    }
    return n;
}

/* The segment runs horizontally away from the vertical axis through the centre of the body's box,
   out past the box's side: for a point beside the body (a hem, a sleeve) the shortest way out,
   through a few boxes, where a segment up to above the body's box runs along the torso and the
   arm (measured: the casts' share of the body scene's time 2.9 -> 1.1 %). A point within
   SEG_AXIS_M of the axis takes the segment up. Any segment out of the box gives the same parity
   for a closed body; the kernel's twin (sim_clearly_outside) casts the same one. */
int sim_collider_clearly_outside(const sim_collider *c, const float p[3])
{
    const float *lo = c->bvh.lo[0], *hi = c->bvh.hi[0];
    float d[3] = {p[0] - 0.5f * (lo[0] + hi[0]), 0.0f, p[2] - 0.5f * (lo[2] + hi[2])};
    if (d[0] * d[0] + d[2] * d[2] > SEG_AXIS_M * SEG_AXIS_M) {
        float tmax = INFINITY;
        for (int k = 0; k < 3; k += 2)
            if (d[k] != 0.0f) {
                float t = ((d[k] > 0.0f ? hi[k] + 0.01f : lo[k] - 0.01f) - p[k]) / d[k];
                tmax = t < tmax ? t : tmax;
            }
        if (!(tmax > 0.0f))
            return 1; /* beside the body's box */
        d[0] *= tmax;
        d[2] *= tmax;
    } else {
        d[0] = d[2] = 0.0f;
        d[1] = hi[1] + 0.01f - p[1];
        if (!(d[1] > 0.0f))
            return 1; /* above the body's box */
    }
    int n = segment_crossings(c, p, d, 1.0f);
    return n >= 0 && n % 2 == 0;
}

/* Signed distance of p through the unbounded nearest search; +inf with no body. */
static float exact_sd(const sim_collider *c, const float p[3], int hint)
{
    float q[3], bary[3], dist;
    int t = sim_bvh_nearest_from(&c->bvh, (const float(*)[4])c->v, (const int32_t(*)[4])c->tris, p,
                                 INFINITY, hint, q, bary, &dist);
    return t < 0 ? INFINITY : sim_collider_signed_distance(c, t, p);
}

/* Signed distance of p when it is inside; some positive number when it is outside. */
static float fast_sd(const sim_collider *c, const float p[3], int hint)
{
    if (hint < 0 || hint >= c->nt) /* no contact: p is far from the surface */
        return sim_collider_clearly_outside(c, p) ? INFINITY : exact_sd(c, p, hint);
    float d2;
    int t = sim_collider_walk_nearest(c, p, hint, &d2);
    float sd = sim_collider_signed_distance(c, t, p);
    if (!(sd > 0.0f))
        return exact_sd(c, p, t);
    float q[3], bary[3], d[3];
    const int32_t *f = c->tris[t];
    sim_closest_on_triangle(p, c->v[f[0]], c->v[f[1]], c->v[f[2]], q, bary);
    sim_v3_sub(q, p, d);
    return segment_crossings(c, p, d, SEG_END) == 0 ? sd : exact_sd(c, p, t);
}

/* Outside for sure: the last contact search saw point i outside by clear[i].w at clear[i].xyz, and
   the body has not moved since (sim_collider_set_body voids the bounds). The signed distance is
   1-Lipschitz, so p is still outside if it has moved less than that. */
static int still_outside(const sim_collider *c, int i, const float p[3])
{
    if (i >= c->max_cloth)
        return 0;
    const float *b = c->clear[i];
    if (!(b[3] > CLEAR_SLACK))
        return 0;
    float d[3];
    sim_v3_sub(p, b, d);
    float m = b[3] - CLEAR_SLACK;
    return sim_v3_dot(d, d) < m * m;
}

static int metric(const sim_collider *c, const float (*x)[4], int n, float tol_m, int exact,
                  int *count, float *max_depth_m)
{
    if (!c || (!x && n > 0) || n < 0 || !count || !max_depth_m)
        return -SIM_ERR_ARG;
    int cnt = 0;
    float deepest = 0.0f;
    if (c->nt > 0) {
#pragma omp parallel for schedule(static) reduction(+ : cnt) reduction(max : deepest)
        for (int i = 0; i < n; i++) {
            if (!exact && still_outside(c, i, x[i]))
                continue;
            int hint = i < c->max_cloth ? c->contact[i] : -1;
            float sd = exact ? exact_sd(c, x[i], hint) : fast_sd(c, x[i], hint);
            if (sd < -tol_m)
                cnt++;
            if (-sd > deepest)
                deepest = -sd;
        }
    }
    *count = cnt;
    *max_depth_m = deepest;
    return 0;
}

int sim_collider_penetration(const sim_collider *c, const float (*x)[4], int n, float tol_m,
                             int *count, float *max_depth_m)
{
    return metric(c, x, n, tol_m, 0, count, max_depth_m);
}

int sim_collider_penetration_exact(const sim_collider *c, const float (*x)[4], int n, float tol_m,
                                   int *count, float *max_depth_m)
{
    return metric(c, x, n, tol_m, 1, count, max_depth_m);
}
