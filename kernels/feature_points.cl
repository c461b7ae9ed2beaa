/* Seed 000 section 2.1, Eq. 1-2: feature points, twin of sim/feature_points.c (read its header
 * comment for the swept-prism test). One work-item per cloth point. */

int sim_in_swept_prism(__global const float4 *v_prev, __global const float4 *v,
                       __global const int4 *tris, __global const float4 *n_prev,
                       __global const float4 *n_k, int t, float4 p, float h)
{
    int4 f = tris[t];
    float d0 = sim_dot3(sim_sub3(p, v_prev[f.x]), n_prev[t]);
    float d1 = sim_dot3(sim_sub3(p, v[f.x]), n_k[t]);
    if (!(d0 >= -h && d1 < h && d1 < d0))
        return 0;
    float e0 = d0 - h, e1 = d1 - h;
    float ts = e0 > 0.0f ? e0 / (e0 - e1) : 0.0f;
    float4 a, b, cc;
    a.x = v_prev[f.x].x + ts * (v[f.x].x - v_prev[f.x].x);
    a.y = v_prev[f.x].y + ts * (v[f.x].y - v_prev[f.x].y);
    a.z = v_prev[f.x].z + ts * (v[f.x].z - v_prev[f.x].z);
    b.x = v_prev[f.y].x + ts * (v[f.y].x - v_prev[f.y].x);
    b.y = v_prev[f.y].y + ts * (v[f.y].y - v_prev[f.y].y);
    b.z = v_prev[f.y].z + ts * (v[f.y].z - v_prev[f.y].z);
    cc.x = v_prev[f.z].x + ts * (v[f.z].x - v_prev[f.z].x);
    cc.y = v_prev[f.z].y + ts * (v[f.z].y - v_prev[f.z].y);
    cc.z = v_prev[f.z].z + ts * (v[f.z].z - v_prev[f.z].z);
    a.w = b.w = cc.w = 0.0f;
    float4 q, bary;
    sim_closest_on_triangle(p, a, b, cc, &q, &bary);
    float4 nr = sim_cross3(sim_sub3(b, a), sim_sub3(cc, a));
    float nn = sim_dot3(nr, nr);
    if (!(nn > 0.0f))
        return 0;
    float4 r = sim_sub3(p, q);
    float rn = sim_dot3(r, nr);
    float lateral2 = sim_dot3(r, r) - rn * rn / nn;
    return lateral2 <= h * h;
}

__kernel void sim_feature_points(__global float4 *x, __global float4 *x_prev, int begin, int end,
                                 __global const float4 *v_prev, __global const float4 *v,
                                 __global const int4 *tris, __global const float4 *n_prev,
                                 __global const float4 *n_k, int nleaves,
                                 __global const int2 *child, __global const int *order,
                                 __global const float4 *slo, __global const float4 *shi, float h,
                                 float coulomb_mu, __global int *moved)
{
    int i = begin + (int)get_global_id(0);
    if (i >= end)
        return;
    moved[i] = 0;
    float4 p = x[i];
    if (p.w == 0.0f || nleaves < 1)
        return;
    /* D-BVH: every swept box holding p, its prism tested at once (no cap on candidates);
       distance-based selection (seed 000 Figure 2): nearest to p on frame k-1. */
    int best = -1;
    float best_d2 = INFINITY;
    int stack[BVH_STACK], top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int node = stack[--top];
        if (!sim_box_contains(slo[node], shi[node], p))
            continue;
        int leaf = sim_bvh_leaf_of(nleaves, node);
        if (leaf < 0) {
            if (top + 2 <= BVH_STACK) {
                stack[top++] = child[node].y;
                stack[top++] = child[node].x;
            }
            continue;
        }
        int t = order[leaf];
        if (!sim_in_swept_prism(v_prev, v, tris, n_prev, n_k, t, p, h))
            continue;
        int4 f = tris[t];
        float4 q, bary;
        sim_closest_on_triangle(p, v_prev[f.x], v_prev[f.y], v_prev[f.z], &q, &bary);
        float4 r = sim_sub3(p, q);
        float d2 = sim_dot3(r, r);
        if (d2 < best_d2 || (d2 == best_d2 && t < best)) {
            best = t;
            best_d2 = d2;
        }
    }
    if (best < 0)
        return;
    /* Eq. 1: barycentrics of the projection on T^{k-1}, clamped; Eq. 2: carried to T^k. */
    int4 f = tris[best];
    float4 q, th;
    sim_closest_on_triangle(p, v_prev[f.x], v_prev[f.y], v_prev[f.z], &q, &th);
    float dist = sim_dot3(sim_sub3(p, q), n_prev[best]);
    float off = dist > h ? dist : h;
    float4 a = v[f.x], b = v[f.y], c = v[f.z], nk = n_k[best];
    float4 np;
    np.x = th.x * a.x + th.y * b.x + th.z * c.x + off * nk.x;
    np.y = th.x * a.y + th.y * b.y + th.z * c.y + off * nk.y;
    np.z = th.x * a.z + th.y * b.z + th.z * c.z + off * nk.z;
    if (coulomb_mu >= 0.0f) {
        /* twin of coulomb_carry: the push along n^k whole, the slide up to mu times it */
        float4 d = sim_sub3(np, p);
        float dn = sim_dot3(d, nk);
        float4 s;
        s.x = d.x - dn * nk.x;
        s.y = d.y - dn * nk.y;
        s.z = d.z - dn * nk.z;
        s.w = 0.0f;
        float slide = sqrt(sim_dot3(s, s)), most = coulomb_mu * fabs(dn);
        if (slide > most) {
            float keep = most / slide;
            np.x = p.x + dn * nk.x + keep * s.x;
            np.y = p.y + dn * nk.y + keep * s.y;
            np.z = p.z + dn * nk.z + keep * s.z;
        }
    }
    float4 pp = x_prev[i];
    float sx = np.x - p.x, sy = np.y - p.y, sz = np.z - p.z;
    x[i] = (float4)(np.x, np.y, np.z, p.w);
    x_prev[i] = (float4)(pp.x + sx, pp.y + sy, pp.z + sz, pp.w);
    moved[i] = 1;
}
