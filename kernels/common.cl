/* Shared by every program (the host puts this file first). Twins of the C helpers in
 * sim/collide.c: scalar operations in the same order, no contraction into fma, so a kernel and
 * its C twin agree to the last bit except where a library function (acos) differs. */
#pragma OPENCL FP_CONTRACT OFF

#define SIM_REGION_FACE 0
#define SIM_REGION_V0   1
#define SIM_REGION_V1   2
#define SIM_REGION_V2   3
#define SIM_REGION_E01  4
#define SIM_REGION_E12  5
#define SIM_REGION_E20  6

/* Depth bound of the LBVH (sim/bvh.c BVH_STACK). */
#define BVH_STACK 96

float4 sim_sub3(float4 a, float4 b)
{
    return (float4)(a.x - b.x, a.y - b.y, a.z - b.z, 0.0f);
}

float sim_dot3(float4 a, float4 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

float4 sim_cross3(float4 a, float4 b)
{
    return (float4)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x, 0.0f);
}

float4 sim_bary_point(float4 a, float4 b, float4 c, float u, float v, float w)
{
    return (float4)(u * a.x + v * b.x + w * c.x, u * a.y + v * b.y + w * c.y,
                    u * a.z + v * b.z + w * c.z, 0.0f);
}

/* Ericson, Real-Time Collision Detection 5.1.5; twin of sim_closest_on_triangle. */
int sim_closest_on_triangle(float4 p, float4 a, float4 b, float4 c, float4 *q, float4 *bary)
{
    float4 ab = sim_sub3(b, a), ac = sim_sub3(c, a), ap = sim_sub3(p, a);
    float d1 = sim_dot3(ab, ap), d2 = sim_dot3(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) {
        *bary = (float4)(1.0f, 0.0f, 0.0f, 0.0f);
        *q = sim_bary_point(a, b, c, 1.0f, 0.0f, 0.0f);
        return SIM_REGION_V0;
    }
    float4 bp = sim_sub3(p, b);
    float d3 = sim_dot3(ab, bp), d4 = sim_dot3(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) {
        *bary = (float4)(0.0f, 1.0f, 0.0f, 0.0f);
        *q = sim_bary_point(a, b, c, 0.0f, 1.0f, 0.0f);
        return SIM_REGION_V1;
    }
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
        float v = d1 / (d1 - d3);
        *bary = (float4)(1.0f - v, v, 0.0f, 0.0f);
        *q = sim_bary_point(a, b, c, 1.0f - v, v, 0.0f);
        return SIM_REGION_E01;
    }
    float4 cp = sim_sub3(p, c);
    float d5 = sim_dot3(ab, cp), d6 = sim_dot3(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) {
        *bary = (float4)(0.0f, 0.0f, 1.0f, 0.0f);
        *q = sim_bary_point(a, b, c, 0.0f, 0.0f, 1.0f);
        return SIM_REGION_V2;
    }
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
        float w = d2 / (d2 - d6);
        *bary = (float4)(1.0f - w, 0.0f, w, 0.0f);
        *q = sim_bary_point(a, b, c, 1.0f - w, 0.0f, w);
        return SIM_REGION_E20;
    }
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && d4 - d3 >= 0.0f && d5 - d6 >= 0.0f) {
        float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        *bary = (float4)(0.0f, 1.0f - w, w, 0.0f);
        *q = sim_bary_point(a, b, c, 0.0f, 1.0f - w, w);
        return SIM_REGION_E12;
    }
    float denom = 1.0f / (va + vb + vc);
    float v = vb * denom, w = vc * denom;
    *bary = (float4)(1.0f - v - w, v, w, 0.0f);
    *q = sim_bary_point(a, b, c, 1.0f - v - w, v, w);
    return SIM_REGION_FACE;
}

/* The tree of sim/bvh.c: nodes 0..n-2 internal, n-1..2n-2 leaves; one leaf: node 0. */
int sim_bvh_leaf_of(int n, int node)
{
    if (n == 1)
        return 0;
    return node >= n - 1 ? node - (n - 1) : -1;
}

float sim_box_dist2(float4 lo, float4 hi, float4 p)
{
    float ex = p.x < lo.x ? lo.x - p.x : (p.x > hi.x ? p.x - hi.x : 0.0f);
    float ey = p.y < lo.y ? lo.y - p.y : (p.y > hi.y ? p.y - hi.y : 0.0f);
    float ez = p.z < lo.z ? lo.z - p.z : (p.z > hi.z ? p.z - hi.z : 0.0f);
    float d2 = 0.0f;
    d2 += ex * ex;
    d2 += ey * ey;
    d2 += ez * ez;
    return d2;
}

int sim_box_contains(float4 lo, float4 hi, float4 p)
{
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
}

/* Twin of sim_bvh_nearest: the nearest triangle within radius (-1 if none), its closest point
   and barycentrics; the nearer child is visited first, ties keep the lower triangle index. */
int sim_bvh_nearest(int n, __global const int2 *child, __global const int *order,
                    __global const float4 *lo, __global const float4 *hi, __global const float4 *v,
                    __global const int4 *tris, float4 p, float radius, float4 *q, float4 *bary,
                    float *dist)
{
    int best = -1;
    float best_d2 = radius * radius;
    int stack[BVH_STACK], top = 0;
    if (n < 1)
        return -1;
    stack[top++] = 0;
    while (top > 0) {
        int node = stack[--top];
        if (sim_box_dist2(lo[node], hi[node], p) > best_d2)
            continue;
        int leaf = sim_bvh_leaf_of(n, node);
        if (leaf >= 0) {
            int t = order[leaf];
            int4 f = tris[t];
            float4 cq, cb;
            sim_closest_on_triangle(p, v[f.x], v[f.y], v[f.z], &cq, &cb);
            float dx = p.x - cq.x, dy = p.y - cq.y, dz = p.z - cq.z;
            float d2 = dx * dx + dy * dy + dz * dz;
            if (d2 < best_d2 || (d2 == best_d2 && (best < 0 || t < best))) {
                best = t;
                best_d2 = d2;
                *q = cq;
                *bary = cb;
            }
            continue;
        }
        int l = child[node].x, r = child[node].y;
        float dl = sim_box_dist2(lo[l], hi[l], p), dr = sim_box_dist2(lo[r], hi[r], p);
        if (top + 2 > BVH_STACK)
            continue;
        if (dl <= dr) {
            stack[top++] = r;
            stack[top++] = l;
        } else {
            stack[top++] = l;
            stack[top++] = r;
        }
    }
    if (best >= 0)
        *dist = sqrt(best_d2);
    return best;
}

/* Twins of the segment cast in sim/penetration.c: "is p clearly outside the body?" by the parity
   of the crossings of a segment out of the body's box. */
#define SEG_SLACK   1e-5f
#define SEG_BOX_PAD 1e-6f

int sim_segment_hits(float4 o, float4 d, float tmax, float4 a, float4 b, float4 c)
{
    float4 e1 = sim_sub3(b, a), e2 = sim_sub3(c, a);
    float4 pv = sim_cross3(d, e2);
    float det = sim_dot3(e1, pv);
    if (det == 0.0f)
        return 0;
    float inv = 1.0f / det;
    float4 tv = sim_sub3(o, a);
    float u = sim_dot3(tv, pv) * inv;
    if (u < -SEG_SLACK || u > 1.0f + SEG_SLACK)
        return 0;
    float4 qv = sim_cross3(tv, e1);
    float v = sim_dot3(d, qv) * inv;
    if (v < -SEG_SLACK || u + v > 1.0f + SEG_SLACK)
        return 0;
    float t = sim_dot3(e2, qv) * inv;
    if (t < -SEG_SLACK || t > tmax + SEG_SLACK)
        return 0;
    int clear = u > SEG_SLACK && v > SEG_SLACK && u + v < 1.0f - SEG_SLACK && t > SEG_SLACK &&
                t < tmax - SEG_SLACK;
    return clear ? 1 : 2;
}

int sim_segment_box(float4 o4, float4 d4, float tmax, float4 lo4, float4 hi4)
{
    float o[3] = {o4.x, o4.y, o4.z}, d[3] = {d4.x, d4.y, d4.z};
    float lo[3] = {lo4.x, lo4.y, lo4.z}, hi[3] = {hi4.x, hi4.y, hi4.z};
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

/* Crossings of p -> p + tmax d with the body, -1 when one is too near an edge to count. */
int sim_segment_crossings(int n, __global const int2 *child, __global const int *order,
                          __global const float4 *lo, __global const float4 *hi,
                          __global const float4 *v, __global const int4 *tris, float4 p, float4 d,
                          float tmax)
{
    int stack[BVH_STACK], top = 0, count = 0;
    stack[top++] = 0;
    while (top > 0) {
        int node = stack[--top];
        if (!sim_segment_box(p, d, tmax, lo[node], hi[node]))
            continue;
        int leaf = sim_bvh_leaf_of(n, node);
        if (leaf >= 0) {
            int4 f = tris[order[leaf]];
            int h = sim_segment_hits(p, d, tmax, v[f.x], v[f.y], v[f.z]);
            if (h == 2)
                return -1;
            count += h;
            continue;
        }
        if (top + 2 > BVH_STACK)
            return -1;
        stack[top++] = child[node].y;
        stack[top++] = child[node].x;
    }
    return count;
}

/* Twin of sim_collider_clearly_outside: sideways, away from the vertical axis through the centre
   of the body's box, out past its side; within SEG_AXIS_M of the axis, up. */
#define SEG_AXIS_M 0.01f

int sim_clearly_outside(int n, __global const int2 *child, __global const int *order,
                        __global const float4 *lo, __global const float4 *hi,
                        __global const float4 *v, __global const int4 *tris, float4 p)
{
    float4 b0 = lo[0], b1 = hi[0];
    float4 d = (float4)(p.x - 0.5f * (b0.x + b1.x), 0.0f, p.z - 0.5f * (b0.z + b1.z), 0.0f);
    if (d.x * d.x + d.z * d.z > SEG_AXIS_M * SEG_AXIS_M) {
        float tmax = INFINITY;
        if (d.x != 0.0f) {
            float t = ((d.x > 0.0f ? b1.x + 0.01f : b0.x - 0.01f) - p.x) / d.x;
            tmax = t < tmax ? t : tmax;
        }
        if (d.z != 0.0f) {
            float t = ((d.z > 0.0f ? b1.z + 0.01f : b0.z - 0.01f) - p.z) / d.z;
            tmax = t < tmax ? t : tmax;
        }
        if (!(tmax > 0.0f))
            return 1;
        d.x *= tmax;
        d.z *= tmax;
    } else {
        d = (float4)(0.0f, b1.y + 0.01f - p.y, 0.0f, 0.0f);
        if (!(d.y > 0.0f))
            return 1;
    }
    int c = sim_segment_crossings(n, child, order, lo, hi, v, tris, p, d, 1.0f);
    return c >= 0 && c % 2 == 0;
}

/* Twin of the contact search of sim_collider_find_contacts: within radius, or, for a point that
   is not clearly outside (it may be deep inside), at any distance. */
int sim_contact_search(int n, __global const int2 *child, __global const int *order,
                       __global const float4 *lo, __global const float4 *hi,
                       __global const float4 *v, __global const int4 *tris, float4 p, float radius)
{
    float4 q, bary;
    float dist;
    int t = sim_bvh_nearest(n, child, order, lo, hi, v, tris, p, radius, &q, &bary, &dist);
    if (t < 0 && n > 0 && !sim_clearly_outside(n, child, order, lo, hi, v, tris, p))
        t = sim_bvh_nearest(n, child, order, lo, hi, v, tris, p, INFINITY, &q, &bary, &dist);
    return t;
}
