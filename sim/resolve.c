/* The contact response (sim_collider_resolve): each cloth point against its cached triangle,
 * pushed out to the thickness with Coulomb-like friction, and the quiet radius that lets a point
 * the response left alone be skipped while it stays within it. Twin: kernels/collide.cl. */
#include <math.h>
#include <string.h>

#include "collide.h"
#include "collide_geometry.h"

/* The quiet radius (sim_collider_resolve): margins of QUIET_EPS_M = 50 um against rounding (the
   values below carry errors of some 1e-6 m for body coordinates of a few metres), and only on
   triangles whose heights are at least QUIET_MIN_HEIGHT_M, where the region tests of
   sim_closest_on_triangle are that accurate too. */
#define QUIET_EPS_M        5e-5f
#define QUIET_MIN_HEIGHT_M 1e-3f

/* Point p (face region of triangle t, signed distance dist >= thickness, closest point with
   barycentrics bary) moved nothing. Within what radius of p does that hold for sure? While p stays
   nearer than its margin to each edge line of t and its plane distance above thickness, the
   closest point stays in the face region and the response moves nothing. 0: no radius. */
static float quiet_radius(const sim_collider *c, int t, float dist, const float bary[3])
{
    const int32_t *f = c->tris[t];
    const float *a = c->v[f[0]], *b = c->v[f[1]], *p = c->v[f[2]];
    float ab[3], ac[3], bc[3], cr[3];
    sim_v3_sub(b, a, ab);
    sim_v3_sub(p, a, ac);
    sim_v3_sub(p, b, bc);
    sim_v3_cross(ab, ac, cr);
    float area2 = sqrtf(sim_v3_dot(cr, cr));
    /* heights onto the edges opposite a, b, c; the distance of the closest point to each edge is
       its barycentric times that height */
    float h[3] = {area2 / sqrtf(sim_v3_dot(bc, bc)), area2 / sqrtf(sim_v3_dot(ac, ac)),
                  area2 / sqrtf(sim_v3_dot(ab, ab))};
    float r = dist - c->d.thickness_m;
    for (int k = 0; k < 3; k++) {
        if (!(h[k] >= QUIET_MIN_HEIGHT_M))
            return 0.0f;
        float m = bary[k] * h[k];
        r = m < r ? m : r;
    }
    r -= QUIET_EPS_M;
    return r > 0.0f ? r : 0.0f;
}

/* The same for a point whose closest point q lies on an edge or a vertex of t (d = p - q, len =
   |d| >= thickness, signed positive by the feature's pseudo-normal). As p moves by r, d moves by
   at most 2 r (the closest point on a triangle is 1-Lipschitz in p), so d stays on the positive
   side of every pseudo-normal of t (face, edges, vertices) with more margin than 2 r, whichever
   feature q then lies on, and len stays above thickness while r < len - thickness. */
static float quiet_radius_feature(const sim_collider *c, int t, const float d[3], float len)
{
    const int32_t *f = c->tris[t];
    const float *a = c->v[f[0]], *b = c->v[f[1]], *p = c->v[f[2]];
    float ab[3], ac[3], bc[3];
    sim_v3_sub(b, a, ab);
    sim_v3_sub(p, a, ac);
    sim_v3_sub(p, b, bc);
    float r = len - c->d.thickness_m;
    if (!(r > QUIET_EPS_M))
        return 0.0f;
    /* the region tests need the same accuracy as for the face */
    float cr[3];
    sim_v3_cross(ab, ac, cr);
    float area2 = sqrtf(sim_v3_dot(cr, cr));
    if (!(area2 / sqrtf(sim_v3_dot(bc, bc)) >= QUIET_MIN_HEIGHT_M &&
          area2 / sqrtf(sim_v3_dot(ac, ac)) >= QUIET_MIN_HEIGHT_M &&
          area2 / sqrtf(sim_v3_dot(ab, ab)) >= QUIET_MIN_HEIGHT_M))
        return 0.0f;
    for (int region = SIM_REGION_FACE; region <= SIM_REGION_E20; region++) {
        float pn[3];
        sim_collider_pseudo_normal(c, t, region, pn);
        float pl = sqrtf(sim_v3_dot(pn, pn));
        if (!(pl > 0.0f))
            return 0.0f;
        float m = 0.5f * sim_v3_dot(d, pn) / pl;
        r = m < r ? m : r;
    }
    r -= QUIET_EPS_M;
    return r > 0.0f ? r : 0.0f;
}

/* Inelastic contact: of the push, only what undoes the point's own approach this step (its move
   into the surface since x_prev) may become velocity; the rest, depth the body made by moving over
   the point (a lowered arm closing the armpit over the cloth) or depth it was found at, moves
   x_prev too. Otherwise a 20-40 mm push in a 1.3 ms step leaves the point flying out at 15-30
   m/s, into the body part on the other side (docs/garments-history.md, "The T-shirt with the arms
   lowered"). The shift of x_prev along the normal, >= 0. */
static float inelastic_shift(const float *x, const float *x_prev, const float nrm[3], float push)
{
    float mv[3];
    sim_v3_sub(x, x_prev, mv);
    float approach = -sim_v3_dot(mv, nrm);
    float ghost = push - (approach > 0.0f ? approach : 0.0f);
    return ghost > 0.0f ? ghost : 0.0f;
}

/* One point against its cached triangle: out to thickness along the contact normal (inelastic
   when the desc says so), then Coulomb-like friction on the motion since x_prev, bounded by
   friction * the push. Returns the quiet radius when it moved nothing (0 when it did, or none is
   known). */
static float resolve_point(const sim_collider *c, int t, float *x, float *x_prev)
{
    float q[3], bary[3], d[3], nrm[3];
    const int32_t *f = c->tris[t];
    int region = sim_closest_on_triangle(x, c->v[f[0]], c->v[f[1]], c->v[f[2]], q, bary);
    sim_v3_sub(x, q, d);
    float dist;
    if (region == SIM_REGION_FACE) {
        memcpy(nrm, c->n[t], sizeof nrm);
        dist = sim_v3_dot(d, nrm);
    } else {
        float pn[3];
        sim_collider_pseudo_normal(c, t, region, pn);
        float len = sqrtf(sim_v3_dot(d, d));
        if (sim_v3_dot(d, pn) >= 0.0f && len > 1e-9f) {
            for (int k = 0; k < 3; k++)
                nrm[k] = d[k] / len;
            dist = len;
        } else {
            float pl = sqrtf(sim_v3_dot(pn, pn));
            for (int k = 0; k < 3; k++)
                nrm[k] = pn[k] / pl;
            dist = -len;
        }
    }
    float push = c->d.thickness_m - dist;
    if (!(push > 0.0f))
        return region == SIM_REGION_FACE ? quiet_radius(c, t, dist, bary)
                                         : quiet_radius_feature(c, t, d, dist);
    float ghost = c->d.inelastic ? inelastic_shift(x, x_prev, nrm, push) : 0.0f;
    for (int k = 0; k < 3; k++) {
        x[k] += push * nrm[k];
        x_prev[k] += ghost * nrm[k];
    }
    float rel[3], tan[3];
    sim_v3_sub(x, x_prev, rel);
    float rn = sim_v3_dot(rel, nrm);
    for (int k = 0; k < 3; k++)
        tan[k] = rel[k] - rn * nrm[k];
    float tl = sqrtf(sim_v3_dot(tan, tan)), limit = c->d.friction * push;
    if (!(tl > 0.0f))
        return 0.0f;
    float keep = tl <= limit ? 1.0f : limit / tl;
    for (int k = 0; k < 3; k++)
        x[k] -= keep * tan[k];
    return 0.0f;
}

void sim_collider_resolve(const sim_collider *c, float (*x)[4], float (*x_prev)[4], int begin,
                          int end)
{
    if (!c || !x || !x_prev || c->nt == 0)
        return;
    end = end < c->max_cloth ? end : c->max_cloth;
    /* A point the response left alone, still within its quiet radius of where it was then
       (same triangle, same body frame), would be left alone again: skipped, the result is the
       same (quiet_radius). Of some 5,000 points in contact per step, a few dozen are pushed. */
#pragma omp parallel for schedule(static)
    for (int i = begin; i < end; i++) {
        int t = c->contact[i];
        if (t < 0 || x[i][3] == 0.0f)
            continue;
        float *qu = c->quiet[i];
        if (c->quiet_key[i][0] == t && c->quiet_key[i][1] == c->body_epoch && qu[3] > 0.0f) {
            float d[3];
            sim_v3_sub(x[i], qu, d);
            if (sim_v3_dot(d, d) < qu[3] * qu[3])
                continue;
        }
        float r = resolve_point(c, t, x[i], x_prev[i]);
        qu[0] = x[i][0];
        qu[1] = x[i][1];
        qu[2] = x[i][2];
        qu[3] = r;
        c->quiet_key[i][0] = t;
        c->quiet_key[i][1] = c->body_epoch;
    }
}

float sim_collider_resting(const sim_collider *c, int i, const float p[3], float tol_m)
{
    int t = i < c->max_cloth ? c->contact[i] : -1;
    if (t < 0)
        return SIM_NOT_RESTING;
    const int32_t *f = c->tris[t];
    float q[3], bary[3], d[3], r = c->d.thickness_m + tol_m;
    sim_closest_on_triangle(p, c->v[f[0]], c->v[f[1]], c->v[f[2]], q, bary);
    sim_v3_sub(p, q, d);
    return sim_v3_dot(d, d) <= r * r ? c->n[t][1] : SIM_NOT_RESTING;
}
