/* The body LBVH (Karras 2012), twin of sim/bvh.c. The sort of the Morton codes runs on the host
 * (once per body topology, sim/bvh.c radix_sort); per frame only sim_bvh_refit runs. */

uint sim_expand_bits(uint v)
{
    v = (v * 0x00010001u) & 0xFF0000FFu;
    v = (v * 0x00000101u) & 0x0F00F00Fu;
    v = (v * 0x00000011u) & 0xC30C30C3u;
    v = (v * 0x00000005u) & 0x49249249u;
    return v;
}

uint sim_morton3(float x, float y, float z)
{
    float qx = x * 1024.0f, qy = y * 1024.0f, qz = z * 1024.0f;
    qx = qx > 0.0f ? (qx < 1023.0f ? qx : 1023.0f) : 0.0f;
    qy = qy > 0.0f ? (qy < 1023.0f ? qy : 1023.0f) : 0.0f;
    qz = qz > 0.0f ? (qz < 1023.0f ? qz : 1023.0f) : 0.0f;
    return sim_expand_bits((uint)qx) * 4 + sim_expand_bits((uint)qy) * 2 +
           sim_expand_bits((uint)qz);
}

/* One code per triangle: its centroid inside the box (lo, lo + ext). */
__kernel void sim_bvh_morton(__global const float4 *v, __global const int4 *tris, int nt, float4 lo,
                             float4 ext, __global uint *morton, __global int *order)
{
    int t = get_global_id(0);
    if (t >= nt)
        return;
    int4 f = tris[t];
    float cx = (v[f.x].x + v[f.y].x + v[f.z].x) / 3.0f;
    float cy = (v[f.x].y + v[f.y].y + v[f.z].y) / 3.0f;
    float cz = (v[f.x].z + v[f.y].z + v[f.z].z) / 3.0f;
    morton[t] = sim_morton3((cx - lo.x) / ext.x, (cy - lo.y) / ext.y, (cz - lo.z) / ext.z);
    order[t] = t;
}

int sim_delta(__global const uint *code, int n, int i, int j)
{
    if (j < 0 || j >= n)
        return -1;
    if (code[i] == code[j])
        return 32 + (int)clz((uint)i ^ (uint)j);
    return (int)clz(code[i] ^ code[j]);
}

/* Karras 2012 Figure 4: internal node i finds its range and split from the sorted codes. */
__kernel void sim_bvh_build_nodes(__global const uint *code, int n, __global int2 *child,
                                  __global int *parent)
{
    int i = get_global_id(0);
    if (i >= n - 1)
        return;
    if (i == 0)
        parent[0] = -1;
    int d = sim_delta(code, n, i, i + 1) - sim_delta(code, n, i, i - 1) >= 0 ? 1 : -1;
    int dmin = sim_delta(code, n, i, i - d);
    int lmax = 2;
    while (sim_delta(code, n, i, i + lmax * d) > dmin)
        lmax *= 2;
    int l = 0;
    for (int t = lmax / 2; t >= 1; t /= 2)
        if (sim_delta(code, n, i, i + (l + t) * d) > dmin)
            l += t;
    int j = i + l * d;
    int dnode = sim_delta(code, n, i, j);
    int s = 0;
    for (int div = 2;; div *= 2) {
        int t = (l + div - 1) / div;
        if (sim_delta(code, n, i, i + (s + t) * d) > dnode)
            s += t;
        if (t <= 1)
            break;
    }
    int gamma = i + s * d + (d < 0 ? -1 : 0);
    int lo = min(i, j), hi = max(i, j);
    int left = lo == gamma ? n - 1 + gamma : gamma;
    int right = hi == gamma + 1 ? n - 1 + gamma + 1 : gamma + 1;
    child[i] = (int2)(left, right);
    parent[left] = i;
    parent[right] = i;
}

void sim_merge_box(volatile __global float4 *lo, volatile __global float4 *hi, int node, int l,
                   int r)
{
    float4 a = lo[l], b = lo[r], c = hi[l], d = hi[r];
    lo[node] = fmin(a, b);
    hi[node] = fmax(c, d);
}

/* Leaf boxes (static: frame k, tight; swept: k-1 with k, padded), then bottom-up: the second
   child to arrive at a node builds its box. Counters are never reset: every refit adds exactly
   two to each, so an odd old value means "second". Boxes are read through volatile pointers and
   written before a fence so the sibling's box is seen complete. */
__kernel void sim_bvh_refit(__global const float4 *v_prev, __global const float4 *v,
                            __global const int4 *tris, __global const int *order,
                            __global const int2 *child, __global const int *parent, int n,
                            float pad, volatile __global float4 *lo, volatile __global float4 *hi,
                            volatile __global float4 *slo, volatile __global float4 *shi,
                            volatile __global uint *counter)
{
    int leaf = get_global_id(0);
    if (leaf >= n)
        return;
    int node = n == 1 ? 0 : n - 1 + leaf;
    int4 f = tris[order[leaf]];
    float4 a = v[f.x], b = v[f.y], c = v[f.z];
    float4 l = fmin(a, fmin(b, c)), h = fmax(a, fmax(b, c));
    float4 pa = v_prev[f.x], pb = v_prev[f.y], pc = v_prev[f.z];
    float4 sl = fmin(l, fmin(pa, fmin(pb, pc))), sh = fmax(h, fmax(pa, fmax(pb, pc)));
    float4 pad4 = (float4)(pad, pad, pad, 0.0f);
    lo[node] = (float4)(l.xyz, 0.0f);
    hi[node] = (float4)(h.xyz, 0.0f);
    slo[node] = (float4)(sl.xyz - pad4.xyz, 0.0f);
    shi[node] = (float4)(sh.xyz + pad4.xyz, 0.0f);
    if (n == 1)
        return;
    for (node = parent[node]; node >= 0; node = parent[node]) {
        mem_fence(CLK_GLOBAL_MEM_FENCE);
        uint seen = atomic_inc(&counter[node]);
        if ((seen & 1u) == 0u)
            return;
        int2 ch = child[node];
        sim_merge_box(lo, hi, node, ch.x, ch.y);
        sim_merge_box(slo, shi, node, ch.x, ch.y);
    }
}
