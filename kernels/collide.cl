/* Contacts, response and the penetration metric: twin of sim/collide.c. One work-item per cloth
 * point. Body arrays as the collider holds them: v, tris (int4), face normals nrm, triangle
 * across each edge nbr (int4), vertex -> triangles CSR (vt_start, vt_list). */

/* Cached nearest triangle within radius (thickness + reach), -1 if none. */
__kernel void sim_find_contacts(__global const float4 *x, int begin, int end, int nleaves,
                                __global const int2 *child, __global const int *order,
                                __global const float4 *lo, __global const float4 *hi,
                                __global const float4 *v, __global const int4 *tris, float radius,
                                __global int *contact)
{
    int i = begin + (int)get_global_id(0);
    if (i >= end)
        return;
    contact[i] = sim_contact_search(nleaves, child, order, lo, hi, v, tris, x[i], radius);
}

/* Squared distance from p to triangle t and the region of its closest point. */
float sim_tri_dist2(__global const float4 *v, __global const int4 *tris, int t, float4 p,
                    int *region)
{
    int4 f = tris[t];
    float4 q, bary;
    *region = sim_closest_on_triangle(p, v[f.x], v[f.y], v[f.z], &q, &bary);
    float4 d = sim_sub3(p, q);
    return sim_dot3(d, d);
}

#define WALK_MAX_STEPS 8

/* Twin of walk_nearest (sim/collide.c): greedy descent over the body surface. */
int sim_walk_nearest(__global const float4 *v, __global const int4 *tris,
                     __global const int *vt_start, __global const int *vt_list, float4 p, int t,
                     float *d2_out)
{
    int region;
    float d2 = sim_tri_dist2(v, tris, t, p, &region);
    for (int step = 0; step < WALK_MAX_STEPS && region != SIM_REGION_FACE; step++) {
        int4 f = tris[t];
        int verts[2], nvert = 1;
        if (region <= SIM_REGION_V2) {
            int c = region - SIM_REGION_V0;
            verts[0] = c == 0 ? f.x : (c == 1 ? f.y : f.z);
        } else {
            int e = region - SIM_REGION_E01;
            verts[0] = e == 0 ? f.x : (e == 1 ? f.y : f.z);
            verts[1] = e == 0 ? f.y : (e == 1 ? f.z : f.x);
            nvert = 2;
        }
        int best = t, best_region = region;
        float best_d2 = d2;
        for (int k = 0; k < nvert; k++)
            for (int j = vt_start[verts[k]]; j < vt_start[verts[k] + 1]; j++) {
                int o = vt_list[j], r;
                if (o == best)
                    continue;
                float od2 = sim_tri_dist2(v, tris, o, p, &r);
                if (od2 < best_d2 || (od2 == best_d2 && o < best)) {
                    best = o;
                    best_d2 = od2;
                    best_region = r;
                }
            }
        if (best == t)
            break;
        t = best;
        d2 = best_d2;
        region = best_region;
    }
    *d2_out = d2;
    return t;
}

/* Twin of sim_collider_track_contacts for point i. */
void sim_track_contact_one(__global const float4 *x, int i, int nleaves, __global const int2 *child,
                           __global const int *order, __global const float4 *lo,
                           __global const float4 *hi, __global const float4 *v,
                           __global const int4 *tris, __global const int *vt_start,
                           __global const int *vt_list, float radius, __global int *contact)
{
    int t = contact[i];
    if (t >= 0 && t < nleaves) {
        float d2;
        t = sim_walk_nearest(v, tris, vt_start, vt_list, x[i], t, &d2);
        contact[i] = d2 <= radius * radius ? t : -1;
    } else {
        contact[i] = sim_contact_search(nleaves, child, order, lo, hi, v, tris, x[i], radius);
    }
}

__kernel void sim_track_contacts(__global const float4 *x, int begin, int end, int nleaves,
                                 __global const int2 *child, __global const int *order,
                                 __global const float4 *lo, __global const float4 *hi,
                                 __global const float4 *v, __global const int4 *tris,
                                 __global const int *vt_start, __global const int *vt_list,
                                 float radius, __global int *contact)
{
    int i = begin + (int)get_global_id(0);
    if (i < end)
        sim_track_contact_one(x, i, nleaves, child, order, lo, hi, v, tris, vt_start, vt_list,
                              radius, contact);
}

/* Twin of sim_acos (sim/collide.c): Abramowitz & Stegun 4.4.45 from basic operations. */
float sim_acos(float x)
{
    float a = fabs(x);
    float p = 1.5707288f + a * (-0.2121144f + a * (0.0742610f + a * -0.0187293f));
    float r = sqrt(1.0f - a) * p;
    return x >= 0.0f ? r : 3.14159265f - r;
}

float sim_corner_angle(__global const float4 *v, int4 f, int k)
{
    int ip = k == 0 ? f.x : (k == 1 ? f.y : f.z);
    int ia = k == 0 ? f.y : (k == 1 ? f.z : f.x);
    int ib = k == 0 ? f.z : (k == 1 ? f.x : f.y);
    float4 u = sim_sub3(v[ia], v[ip]), w = sim_sub3(v[ib], v[ip]);
    float cs = sim_dot3(u, w) / sqrt(sim_dot3(u, u) * sim_dot3(w, w));
    cs = cs > 1.0f ? 1.0f : (cs < -1.0f ? -1.0f : cs);
    return sim_acos(cs);
}

/* Baerentzen & Aanaes 2005, twin of sim_collider_pseudo_normal. */
float4 sim_pseudo_normal(__global const float4 *v, __global const int4 *tris,
                         __global const float4 *nrm, __global const int4 *nbr,
                         __global const int *vt_start, __global const int *vt_list, int t,
                         int region)
{
    float4 n = nrm[t];
    if (region == SIM_REGION_FACE)
        return (float4)(n.x, n.y, n.z, 0.0f);
    if (region >= SIM_REGION_E01) {
        int4 nb = nbr[t];
        int e = region - SIM_REGION_E01;
        int o = e == 0 ? nb.x : (e == 1 ? nb.y : nb.z);
        float4 m = o >= 0 ? nrm[o] : n;
        return (float4)(n.x + m.x, n.y + m.y, n.z + m.z, 0.0f);
    }
    int4 f = tris[t];
    int c = region - SIM_REGION_V0;
    int vi = c == 0 ? f.x : (c == 1 ? f.y : f.z);
    float4 out = (float4)(0.0f, 0.0f, 0.0f, 0.0f);
    for (int j = vt_start[vi]; j < vt_start[vi + 1]; j++) {
        int g = vt_list[j];
        int4 fg = tris[g];
        int k = fg.x == vi ? 0 : (fg.y == vi ? 1 : 2);
        float a = sim_corner_angle(v, fg, k);
        float4 ng = nrm[g];
        out.x += a * ng.x;
        out.y += a * ng.y;
        out.z += a * ng.z;
    }
    return out;
}

/* Out to thickness h along the contact normal, inelastic (x_prev moved by the push beyond the
   point's own approach: twin of inelastic_shift in sim/resolve.c), then friction mu bounded by
   the push. */
void sim_resolve_one(__global float4 *x, __global float4 *x_prev, int i,
                     __global const int *contact, __global const float4 *v,
                     __global const int4 *tris, __global const float4 *nrm,
                     __global const int4 *nbr, __global const int *vt_start,
                     __global const int *vt_list, float h, float mu)
{
    int t = contact[i];
    float4 p = x[i];
    if (t < 0 || p.w == 0.0f)
        return;
    int4 f = tris[t];
    float4 q, bary, n;
    int region = sim_closest_on_triangle(p, v[f.x], v[f.y], v[f.z], &q, &bary);
    float4 d = sim_sub3(p, q);
    float dist;
    if (region == SIM_REGION_FACE) {
        n = nrm[t];
        dist = sim_dot3(d, n);
    } else {
        float4 pn = sim_pseudo_normal(v, tris, nrm, nbr, vt_start, vt_list, t, region);
        float len = sqrt(sim_dot3(d, d));
        if (sim_dot3(d, pn) >= 0.0f && len > 1e-9f) {
            n = (float4)(d.x / len, d.y / len, d.z / len, 0.0f);
            dist = len;
        } else {
            float pl = sqrt(sim_dot3(pn, pn));
            n = (float4)(pn.x / pl, pn.y / pl, pn.z / pl, 0.0f);
            dist = -len;
        }
    }
    float push = h - dist;
    if (!(push > 0.0f))
        return;
    float4 prev = x_prev[i];
    float approach = -sim_dot3(sim_sub3(p, prev), n);
    float ghost = push - (approach > 0.0f ? approach : 0.0f);
    ghost = ghost > 0.0f ? ghost : 0.0f;
    p.x += push * n.x;
    p.y += push * n.y;
    p.z += push * n.z;
    prev.x += ghost * n.x;
    prev.y += ghost * n.y;
    prev.z += ghost * n.z;
    x_prev[i] = prev;
    float4 rel = sim_sub3(p, prev);
    float rn = sim_dot3(rel, n);
    float4 tan = (float4)(rel.x - rn * n.x, rel.y - rn * n.y, rel.z - rn * n.z, 0.0f);
    float tl = sqrt(sim_dot3(tan, tan)), limit = mu * push;
    if (tl > 0.0f) {
        float keep = tl <= limit ? 1.0f : limit / tl;
        p.x -= keep * tan.x;
        p.y -= keep * tan.y;
        p.z -= keep * tan.z;
    }
    x[i] = p;
}

/* Twin of sim_collider_research (sim/find_contacts.c): point i searched again when it has moved
   farther from where its contact was searched (seen[i]) than sim_research_radius allows
   (kernels/contact_rule.h) for that search's clearance (the signed distance there to its
   triangle; radius, the search's reach, when it found none). */
void sim_research_one(__global const float4 *x, int i, __global int *contact, __global float4 *seen,
                      __global const float4 *v, __global const int4 *tris,
                      __global const float4 *nrm, __global const int4 *nbr,
                      __global const int *vt_start, __global const int *vt_list, int nleaves,
                      __global const int2 *child, __global const int *order,
                      __global const float4 *lo, __global const float4 *hi, float h, float radius)
{
    int t = contact[i];
    float4 p = x[i], s = seen[i];
    if (p.w == 0.0f)
        return;
    float clear = radius;
    if (t >= 0) {
        int4 f = tris[t];
        float4 q, bary;
        int region = sim_closest_on_triangle(s, v[f.x], v[f.y], v[f.z], &q, &bary);
        float4 d = sim_sub3(s, q);
        if (region == SIM_REGION_FACE) {
            clear = sim_dot3(d, nrm[t]);
        } else {
            float4 pn = sim_pseudo_normal(v, tris, nrm, nbr, vt_start, vt_list, t, region);
            float len = sqrt(sim_dot3(d, d));
            clear = sim_dot3(d, pn) >= 0.0f ? len : -len;
        }
    }
    float r = sim_research_radius(clear, h);
    float4 m = sim_sub3(p, s);
    if (sim_dot3(m, m) > r * r) {
        contact[i] = sim_contact_search(nleaves, child, order, lo, hi, v, tris, p, radius);
        seen[i] = p;
    }
}

__kernel void sim_resolve(__global float4 *x, __global float4 *x_prev, int begin, int end,
                          __global const int *contact, __global const float4 *v,
                          __global const int4 *tris, __global const float4 *nrm,
                          __global const int4 *nbr, __global const int *vt_start,
                          __global const int *vt_list, float h, float mu)
{
    int i = begin + (int)get_global_id(0);
    if (i < end)
        sim_resolve_one(x, x_prev, i, contact, v, tris, nrm, nbr, vt_start, vt_list, h, mu);
}

/* The metric's per-point part: signed distance to the body (unbounded nearest search). */
__kernel void sim_signed_distance(__global const float4 *x, int n, int nleaves,
                                  __global const int2 *child, __global const int *order,
                                  __global const float4 *lo, __global const float4 *hi,
                                  __global const float4 *v, __global const int4 *tris,
                                  __global const float4 *nrm, __global const int4 *nbr,
                                  __global const int *vt_start, __global const int *vt_list,
                                  __global float *sd)
{
    int i = get_global_id(0);
    if (i >= n)
        return;
    float4 p = x[i], q, bary;
    float dist;
    int t = sim_bvh_nearest(nleaves, child, order, lo, hi, v, tris, p, INFINITY, &q, &bary, &dist);
    if (t < 0) {
        sd[i] = INFINITY;
        return;
    }
    int4 f = tris[t];
    int region = sim_closest_on_triangle(p, v[f.x], v[f.y], v[f.z], &q, &bary);
    float4 d = sim_sub3(p, q);
    float len = sqrt(sim_dot3(d, d));
    if (region == SIM_REGION_FACE) {
        sd[i] = sim_dot3(d, nrm[t]);
        return;
    }
    float4 pn = sim_pseudo_normal(v, tris, nrm, nbr, vt_start, vt_list, t, region);
    sd[i] = sim_dot3(d, pn) >= 0.0f ? len : -len;
}

/* Unit face normals of frame k, twin of face_normals in sim/collide.c. */
__kernel void sim_face_normals(__global const float4 *v, __global const int4 *tris, int nt,
                               __global float4 *nrm)
{
    int t = get_global_id(0);
    if (t >= nt)
        return;
    int4 f = tris[t];
    float4 nr = sim_cross3(sim_sub3(v[f.y], v[f.x]), sim_sub3(v[f.z], v[f.x]));
    float len = sqrt(sim_dot3(nr, nr));
    nrm[t] = (float4)(nr.x / len, nr.y / len, nr.z / len, 0.0f);
}
