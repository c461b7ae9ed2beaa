/* The body LBVH (Karras 2012, "Maximizing parallelism in the construction of BVHs, octrees and
 * k-d trees"): Morton codes of triangle centroids, a radix sort, every internal node found on its
 * own from the longest common prefix of the sorted codes, boxes bottom-up. Built once per body
 * topology; per frame only sim_bvh_refit runs. Twin: kernels/bvh.cl. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "collide.h"

/* Depth bound of an LBVH over 30-bit codes extended by a 32-bit index: each level lengthens the
   common prefix by at least one bit. */
#define BVH_STACK 96
/* The 4-wide search pushes at most three more nodes per level than it pops. */
#define WIDE_STACK (3 * BVH_STACK)
/* The stamp of a 4-wide node being filled (epochs are never negative). */
#define WIDE_BUSY (-2)
/* The refit's subtrees: enough that two or three threads share them evenly (schedule dynamic). */
#define REFIT_TASKS 32

int sim_bvh_init(sim_bvh *b, int max_triangles)
{
    memset(b, 0, sizeof *b);
    if (max_triangles < 1)
        max_triangles = 1;
    size_t n = (size_t)max_triangles, nodes = 2 * n - 1;
    b->cap = max_triangles;
    b->morton = malloc(n * sizeof *b->morton);
    b->order = malloc(n * sizeof *b->order);
    b->child = malloc(n * sizeof *b->child);
    b->parent = malloc(nodes * sizeof *b->parent);
    b->lo = malloc(nodes * sizeof *b->lo);
    b->hi = malloc(nodes * sizeof *b->hi);
    b->slo = malloc(nodes * sizeof *b->slo);
    b->shi = malloc(nodes * sizeof *b->shi);
    b->refit_list = malloc(nodes * sizeof *b->refit_list);
    b->refit_task = malloc((REFIT_TASKS + 2) * sizeof *b->refit_task);
    b->scratch = malloc(4 * n * sizeof *b->scratch);
    /* two cache lines a 4-wide node, aligned so that a node never spans a third */
    b->wide = aligned_alloc(64, n * sizeof *b->wide);
    b->wide_node = malloc(n * sizeof *b->wide_node);
    b->wleaf = aligned_alloc(32, n * sizeof *b->wleaf);
    if (!b->morton || !b->order || !b->child || !b->parent || !b->lo || !b->hi || !b->slo ||
        !b->shi || !b->refit_list || !b->refit_task || !b->scratch || !b->wide || !b->wide_node ||
        !b->wleaf) {
        sim_bvh_free(b);
        return SIM_COLLIDE_ENOMEM;
    }
    return 0;
}

void sim_bvh_free(sim_bvh *b)
{
    if (!b)
        return;
    free(b->morton);
    free(b->order);
    free(b->child);
    free(b->parent);
    free(b->lo);
    free(b->hi);
    free(b->slo);
    free(b->shi);
    free(b->refit_list);
    free(b->refit_task);
    free(b->scratch);
    free(b->wide);
    free(b->wide_node);
    free(b->wleaf);
    memset(b, 0, sizeof *b);
}

/* Spread the low 10 bits of v so two zero bits separate each. */
static uint32_t expand_bits(uint32_t v)
{
    v = (v * 0x00010001u) & 0xFF0000FFu;
    v = (v * 0x00000101u) & 0x0F00F00Fu;
    v = (v * 0x00000011u) & 0xC30C30C3u;
    v = (v * 0x00000005u) & 0x49249249u;
    return v;
}

uint32_t sim_morton3(float x, float y, float z)
{
    float q[3] = {x * 1024.0f, y * 1024.0f, z * 1024.0f};
    uint32_t u[3];
    for (int k = 0; k < 3; k++) {
        /* Written so NaN lands on 0: a float to integer cast of NaN is undefined. */
        float c = q[k] > 0.0f ? (q[k] < 1023.0f ? q[k] : 1023.0f) : 0.0f;
        u[k] = (uint32_t)c;
    }
    return expand_bits(u[0]) * 4 + expand_bits(u[1]) * 2 + expand_bits(u[2]);
}

/* LSD radix sort of (code, triangle) pairs, 8 bits a pass; stable, so equal codes keep triangle
   order and the tree is deterministic. */
static void radix_sort(sim_bvh *b, int n)
{
    uint32_t *k0 = b->morton, *v0 = (uint32_t *)b->order;
    uint32_t *k1 = b->scratch, *v1 = b->scratch + b->cap;
    for (int shift = 0; shift < 32; shift += 8) {
        int count[256] = {0};
        for (int i = 0; i < n; i++)
            count[(k0[i] >> shift) & 255]++;
        int sum = 0;
        for (int d = 0; d < 256; d++) {
            int c = count[d];
            count[d] = sum;
            sum += c;
        }
        for (int i = 0; i < n; i++) {
            int at = count[(k0[i] >> shift) & 255]++;
            k1[at] = k0[i];
            v1[at] = v0[i];
        }
        uint32_t *t = k0;
        k0 = k1;
        k1 = t;
        t = v0;
        v0 = v1;
        v1 = t;
    }
    /* Four passes: the result is back in morton/order. */
}

static int clz32(uint32_t x)
{
    int n = 0;
    if (x == 0)
        return 32;
    while (!(x & 0x80000000u)) {
        x <<= 1;
        n++;
    }
    return n;
}

/* Karras 2012 delta: length of the common prefix of keys i and j, the index breaking ties; -1
   outside the range. */
static int delta(const uint32_t *code, int n, int i, int j)
{
    if (j < 0 || j >= n)
        return -1;
    if (code[i] == code[j])
        return 32 + clz32((uint32_t)i ^ (uint32_t)j);
    return clz32(code[i] ^ code[j]);
}

/* Internal node i of Karras 2012 (Figure 4): its key range and split, children linked. */
static void build_node(sim_bvh *b, int i)
{
    const uint32_t *code = b->morton;
    int n = b->n;
    int d = delta(code, n, i, i + 1) - delta(code, n, i, i - 1) >= 0 ? 1 : -1;
    int dmin = delta(code, n, i, i - d);
    int lmax = 2;
    while (delta(code, n, i, i + lmax * d) > dmin)
        lmax *= 2;
    int l = 0;
    for (int t = lmax / 2; t >= 1; t /= 2)
        if (delta(code, n, i, i + (l + t) * d) > dmin)
            l += t;
    int j = i + l * d;
    int dnode = delta(code, n, i, j);
    int s = 0;
    for (int div = 2;; div *= 2) {
        int t = (l + div - 1) / div;
        if (delta(code, n, i, i + (s + t) * d) > dnode)
            s += t;
        if (t <= 1)
            break;
    }
    int gamma = i + s * d + (d < 0 ? -1 : 0);
    int lo = i < j ? i : j, hi = i < j ? j : i;
    int left = lo == gamma ? n - 1 + gamma : gamma;
    int right = hi == gamma + 1 ? n - 1 + gamma + 1 : gamma + 1;
    b->child[i][0] = left;
    b->child[i][1] = right;
    b->parent[left] = i;
    b->parent[right] = i;
}

static int leaf_of(const sim_bvh *b, int node)
{
    if (b->n == 1)
        return 0;
    return node >= b->n - 1 ? node - (b->n - 1) : -1;
}

/* The 4-wide shape (Wald et al. 2008 collapse): a 4-wide node over binary node i holds i's
   children, each internal one replaced by its own two children. Every binary node is a slot or
   expanded, so every leaf is reached once. Nodes are numbered in creation order; a node's
   children come after it. A node with leaf slots gets a block of their triangles (wleaf). */
static void build_wide(sim_bvh *b)
{
    b->nwide = 0;
    b->nwleaf = 0;
    if (b->n < 2)
        return;
    /* wide_node[w][0] holds the binary node w stands for until its slots are filled */
    b->wide_node[b->nwide++][0] = 0;
    for (int w = 0; w < b->nwide; w++) {
        sim_bvh_node4 *q = &b->wide[w];
        int32_t *slot = b->wide_node[w];
        int bin = slot[0], count = 0;
        for (int j = 0; j < 2; j++) {
            int ch = b->child[bin][j];
            if (leaf_of(b, ch) >= 0) {
                slot[count++] = ch;
            } else {
                slot[count++] = b->child[ch][0];
                slot[count++] = b->child[ch][1];
            }
        }
        memset(q, 0, sizeof *q);
        atomic_init(&q->stamp, -1);
        q->count = count;
        q->leaves = -1;
        for (int k = 0; k < 4; k++) {
            if (k >= count) {
                slot[k] = -1;
                q->next[k] = -1;
                continue;
            }
            int leaf = leaf_of(b, slot[k]);
            if (leaf >= 0) {
                q->next[k] = -1 - leaf;
                q->leaf_mask |= 1 << k;
            } else {
                q->next[k] = b->nwide;
                b->wide_node[b->nwide++][0] = slot[k];
            }
        }
        if (q->leaf_mask) {
            sim_bvh_leaf4 *l = &b->wleaf[b->nwleaf];
            memset(l, 0, sizeof *l);
            for (int k = 0; k < 4; k++)
                l->tri[k] = q->leaf_mask >> k & 1 ? b->order[-1 - q->next[k]] : -1;
            q->leaves = b->nwleaf++;
        }
    }
}

/* Subtree of node r into out, children before their parent (a pre-order reversed); returns the
   count. The stack holds at most one node a level plus one. */
static int subtree_children_first(const sim_bvh *b, int r, int32_t *out)
{
    int stack[BVH_STACK + 2], top = 0, m = 0;
    stack[top++] = r;
    while (top > 0) {
        int node = stack[--top];
        out[m++] = node;
        if (leaf_of(b, node) < 0 && top + 2 <= BVH_STACK + 2) {
            stack[top++] = b->child[node][0];
            stack[top++] = b->child[node][1];
        }
    }
    for (int i = 0, j = m - 1; i < j; i++, j--) {
        int32_t t = out[i];
        out[i] = out[j];
        out[j] = t;
    }
    return m;
}

/* The refit's schedule, per topology: the top of the tree split until REFIT_TASKS subtrees (the
   largest split first), each subtree a task listed children first, then the split nodes, deepest
   first. Every node's box is the min / max of its children's, whatever the order, so the boxes
   are those of the atomic bottom-up pass (Karras 2012 section 4, the kernel's) bit for bit. */
static void build_refit_order(sim_bvh *b)
{
    int32_t *size = (int32_t *)b->scratch; /* leaves under each node; the sort is done with it */
    int32_t *all = b->refit_list;
    int m = subtree_children_first(b, 0, all);
    for (int i = 0; i < m; i++) {
        int node = all[i];
        size[node] = leaf_of(b, node) >= 0 ? 1 : size[b->child[node][0]] + size[b->child[node][1]];
    }
    int front[REFIT_TASKS + 1], nfront = 1, top[REFIT_TASKS], ntop = 0;
    front[0] = 0;
    while (nfront < REFIT_TASKS) {
        int pick = -1;
        for (int i = 0; i < nfront; i++)
            if (leaf_of(b, front[i]) < 0 && (pick < 0 || size[front[i]] > size[front[pick]]))
                pick = i;
        if (pick < 0)
            break;
        int node = front[pick];
        top[ntop++] = node;
        front[pick] = b->child[node][0];
        front[nfront++] = b->child[node][1];
    }
    int at = 0;
    for (int i = 0; i < nfront; i++) {
        b->refit_task[i] = at;
        at += subtree_children_first(b, front[i], b->refit_list + at);
    }
    b->refit_task[nfront] = at;
    for (int i = ntop - 1; i >= 0; i--)
        b->refit_list[at++] = top[i];
    b->nrefit_task = nfront;
}

void sim_bvh_build(sim_bvh *b, const float (*v_prev)[4], const float (*v)[4],
                   const int32_t (*tris)[4], int nt, float pad_m)
{
    b->n = nt;
    float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            float c = (v[tris[t][0]][k] + v[tris[t][1]][k] + v[tris[t][2]][k]) / 3.0f;
            lo[k] = c < lo[k] ? c : lo[k];
            hi[k] = c > hi[k] ? c : hi[k];
        }
    float ext[3];
    for (int k = 0; k < 3; k++)
        ext[k] = hi[k] - lo[k] > 1e-12f ? hi[k] - lo[k] : 1.0f;
    for (int t = 0; t < nt; t++) {
        float q[3];
        for (int k = 0; k < 3; k++) {
            float c = (v[tris[t][0]][k] + v[tris[t][1]][k] + v[tris[t][2]][k]) / 3.0f;
            q[k] = (c - lo[k]) / ext[k];
        }
        b->morton[t] = sim_morton3(q[0], q[1], q[2]);
        b->order[t] = t;
    }
    radix_sort(b, nt);
    b->parent[0] = -1;
    if (nt == 1) {
        b->child[0][0] = b->child[0][1] = 0;
    } else {
#pragma omp parallel for schedule(static)
        for (int i = 0; i < nt - 1; i++)
            build_node(b, i);
    }
    build_wide(b);
    if (nt > 1)
        build_refit_order(b);
    sim_bvh_refit(b, v_prev, v, tris, pad_m);
}

/* fminf / fmaxf without the library call (they are not inlined: their NaN rules differ from
   minss). The body is validated finite, and where fminf would tell -0 from +0 a box distance
   cannot (p - -0 == p - +0), so the refit gives the same answers. */
static float min2(float a, float b)
{
    return a < b ? a : b;
}

static float max2(float a, float b)
{
    return a > b ? a : b;
}

static void leaf_box(sim_bvh *b, int leaf, const float (*v_prev)[4], const float (*v)[4],
                     const int32_t (*tris)[4], float pad_m)
{
    int node = b->n == 1 ? 0 : b->n - 1 + leaf;
    const int32_t *t = tris[b->order[leaf]];
    for (int k = 0; k < 3; k++) {
        float a = v[t[0]][k], c = v[t[1]][k], e = v[t[2]][k];
        float lo = min2(a, min2(c, e)), hi = max2(a, max2(c, e));
        b->lo[node][k] = lo;
        b->hi[node][k] = hi;
        a = v_prev[t[0]][k], c = v_prev[t[1]][k], e = v_prev[t[2]][k];
        b->slo[node][k] = min2(lo, min2(a, min2(c, e))) - pad_m;
        b->shi[node][k] = max2(hi, max2(a, max2(c, e))) + pad_m;
    }
    b->lo[node][3] = b->hi[node][3] = b->slo[node][3] = b->shi[node][3] = 0.0f;
}

static void merge_box(float (*lo)[4], float (*hi)[4], int node, int l, int r)
{
    for (int k = 0; k < 4; k++) {
        lo[node][k] = min2(lo[l][k], lo[r][k]);
        hi[node][k] = max2(hi[l][k], hi[r][k]);
    }
}

static void refit_node(sim_bvh *b, int node, const float (*v_prev)[4], const float (*v)[4],
                       const int32_t (*tris)[4], float pad_m)
{
    if (node >= b->n - 1) {
        leaf_box(b, node - (b->n - 1), v_prev, v, tris, pad_m);
        return;
    }
    merge_box(b->lo, b->hi, node, b->child[node][0], b->child[node][1]);
    merge_box(b->slo, b->shi, node, b->child[node][0], b->child[node][1]);
}

void sim_bvh_refit(sim_bvh *b, const float (*v_prev)[4], const float (*v)[4],
                   const int32_t (*tris)[4], float pad_m)
{
    int n = b->n;
    b->pad = pad_m;
    /* the 4-wide nodes are filled from the new boxes when a search first reaches them */
    b->epoch = (b->epoch + 1) & 0x3fffffff;
    if (n <= 1) {
        if (n == 1)
            leaf_box(b, 0, v_prev, v, tris, pad_m);
        return;
    }
    /* the subtrees in parallel, each children first; then the nodes above them */
#pragma omp parallel for schedule(dynamic, 1)
    for (int task = 0; task < b->nrefit_task; task++)
        for (int i = b->refit_task[task]; i < b->refit_task[task + 1]; i++)
            refit_node(b, b->refit_list[i], v_prev, v, tris, pad_m);
    for (int i = b->refit_task[b->nrefit_task]; i < 2 * n - 1; i++)
        refit_node(b, b->refit_list[i], v_prev, v, tris, pad_m);
}

static float box_dist2(const float lo[4], const float hi[4], const float p[3])
{
    float d2 = 0.0f;
    for (int k = 0; k < 3; k++) {
        float e = p[k] < lo[k] ? lo[k] - p[k] : (p[k] > hi[k] ? p[k] - hi[k] : 0.0f);
        d2 += e * e;
    }
    return d2;
}

/* GCC / Clang vector extension: four floats in one SSE register, lane by lane IEEE arithmetic
   (so each lane is bit for bit what the scalar code computes). */
typedef float f4 __attribute__((vector_size(16)));
typedef int32_t i4 __attribute__((vector_size(16)));

static inline f4 splat4(float x)
{
    return (f4){x, x, x, x};
}

static inline f4 load4(const float *p)
{
    f4 r;
    memcpy(&r, p, sizeof r);
    return r;
}

/* m ? a : b, lane by lane (m all ones or all zeros). */
static inline f4 select4(i4 m, f4 a, f4 b)
{
    return (f4)(((i4)a & m) | ((i4)b & ~m));
}

/* box_dist2 of a 4-wide node's four slots at once, without branches: at most one of below, above
   is positive (lo <= hi), and a mask keeps it (0 otherwise), so each lane is box_dist2's gap. */
static inline f4 wide_box_dist2(const sim_bvh_node4 *w, const float p[3])
{
    f4 d2 = splat4(0.0f), zero = splat4(0.0f);
    for (int a = 0; a < 3; a++) {
        f4 pa = splat4(p[a]);
        f4 below = load4(w->lo[a]) - pa, above = pa - load4(w->hi[a]);
        i4 mb = below > zero, ma = above > zero;
        f4 e = (f4)((i4)below & mb) + (f4)((i4)above & ma);
        d2 += e * e;
    }
    return d2;
}

static inline f4 dot4(const f4 a[3], const f4 b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* sim_closest_on_triangle in four lanes (Ericson 5.1.5): the same dot products, the same tests
   as masks, every region's barycentrics computed and the first region the scalar code would
   return selected (applied last, so it wins). The lanes of an unselected region may divide by
   zero; their values are discarded. */
static inline void closest4(const float p[3], const float tri[3][3][4], f4 q[3], f4 bary[3], f4 *d2,
                            i4 *region)
{
    f4 a[3], b[3], c[3], ab[3], ac[3], ap[3], bp[3], cp[3];
    for (int k = 0; k < 3; k++) {
        f4 pk = splat4(p[k]);
        a[k] = load4(tri[0][k]);
        b[k] = load4(tri[1][k]);
        c[k] = load4(tri[2][k]);
        ab[k] = b[k] - a[k];
        ac[k] = c[k] - a[k];
        ap[k] = pk - a[k];
        bp[k] = pk - b[k];
        cp[k] = pk - c[k];
    }
    f4 zero = splat4(0.0f), one = splat4(1.0f);
    f4 d1 = dot4(ab, ap), d2_ = dot4(ac, ap);
    f4 d3 = dot4(ab, bp), d4 = dot4(ac, bp);
    f4 vc = d1 * d4 - d3 * d2_;
    f4 d5 = dot4(ab, cp), d6 = dot4(ac, cp);
    f4 vb = d5 * d2_ - d1 * d6;
    f4 va = d3 * d6 - d5 * d4;
    f4 e43 = d4 - d3, e56 = d5 - d6;
    /* face */
    f4 denom = one / (va + vb + vc);
    f4 v = vb * denom, w = vc * denom;
    f4 u = one - v - w;
    i4 reg = (i4){SIM_REGION_FACE, SIM_REGION_FACE, SIM_REGION_FACE, SIM_REGION_FACE};
    /* E12 */
    i4 m = (va <= zero) & (e43 >= zero) & (e56 >= zero);
    f4 t = e43 / (e43 + e56);
    u = select4(m, zero, u);
    v = select4(m, one - t, v);
    w = select4(m, t, w);
    reg = (m & SIM_REGION_E12) | (~m & reg);
    /* E20 */
    m = (vb <= zero) & (d2_ >= zero) & (d6 <= zero);
    t = d2_ / (d2_ - d6);
    u = select4(m, one - t, u);
    v = select4(m, zero, v);
    w = select4(m, t, w);
    reg = (m & SIM_REGION_E20) | (~m & reg);
    /* V2 */
    m = (d6 >= zero) & (d5 <= d6);
    u = select4(m, zero, u);
    v = select4(m, zero, v);
    w = select4(m, one, w);
    reg = (m & SIM_REGION_V2) | (~m & reg);
    /* E01 */
    m = (vc <= zero) & (d1 >= zero) & (d3 <= zero);
    t = d1 / (d1 - d3);
    u = select4(m, one - t, u);
    v = select4(m, t, v);
    w = select4(m, zero, w);
    reg = (m & SIM_REGION_E01) | (~m & reg);
    /* V1 */
    m = (d3 >= zero) & (d4 <= d3);
    u = select4(m, zero, u);
    v = select4(m, one, v);
    w = select4(m, zero, w);
    reg = (m & SIM_REGION_V1) | (~m & reg);
    /* V0 */
    m = (d1 <= zero) & (d2_ <= zero);
    u = select4(m, one, u);
    v = select4(m, zero, v);
    w = select4(m, zero, w);
    reg = (m & SIM_REGION_V0) | (~m & reg);
    bary[0] = u;
    bary[1] = v;
    bary[2] = w;
    f4 dist2 = zero;
    for (int k = 0; k < 3; k++) {
        q[k] = u * a[k] + v * b[k] + w * c[k];
        f4 dk = splat4(p[k]) - q[k];
        dist2 = k == 0 ? dk * dk : dist2 + dk * dk;
    }
    *d2 = dist2;
    *region = reg;
}

void sim_closest_on_triangle4(const float p[3], const float tri[3][3][4], float q[3][4],
                              float bary[3][4], float d2[4], int32_t region[4])
{
    f4 vq[3], vb[3], vd2;
    i4 reg;
    closest4(p, tri, vq, vb, &vd2, &reg);
    memcpy(q, vq, sizeof vq);
    memcpy(bary, vb, sizeof vb);
    memcpy(d2, &vd2, sizeof vd2);
    memcpy(region, &reg, sizeof reg);
}

/* Sorted leaf i against the best so far: nearer, or as near with a lower triangle index. */
static void nearest_leaf(const sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4],
                         const float p[3], int i, int *best, float *best_d2, float q[3],
                         float bary[3])
{
    int t = b->order[i];
    float cq[3], cb[3];
    sim_closest_on_triangle(p, v[tris[t][0]], v[tris[t][1]], v[tris[t][2]], cq, cb);
    float dx = p[0] - cq[0], dy = p[1] - cq[1], dz = p[2] - cq[2];
    float d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < *best_d2 || (d2 == *best_d2 && (*best < 0 || t < *best))) {
        *best = t;
        *best_d2 = d2;
        memcpy(q, cq, sizeof cq);
        memcpy(bary, cb, sizeof cb);
    }
}

/* 4-wide node w as this refit has it: the boxes of its slots' binary nodes (empty slots far away:
   never within any radius, and the search also stops at count) and, where it has leaf slots,
   their triangles' vertices (lanes that are not leaves keep the zeros of the build). */
static void fill_wide(const sim_bvh *b, int w, const float (*v)[4], const int32_t (*tris)[4],
                      sim_bvh_node4 *q, sim_bvh_leaf4 *l)
{
    for (int k = 0; k < 4; k++) {
        int bn = b->wide_node[w][k];
        for (int a = 0; a < 3; a++) {
            q->lo[a][k] = bn >= 0 ? b->lo[bn][a] : FLT_MAX;
            q->hi[a][k] = bn >= 0 ? b->hi[bn][a] : FLT_MAX;
        }
        if (l && l->tri[k] >= 0)
            for (int j = 0; j < 3; j++)
                for (int a = 0; a < 3; a++)
                    l->v[j][a][k] = v[tris[l->tri[k]][j]][a];
    }
}

/* 4-wide node w ready for a search of this refit: filled by the first search to reach it (the
   refit itself then writes only the binary boxes, and the nodes no cloth point comes near are
   never copied). The first thread to claim it (stamp set to WIDE_BUSY by compare-and-swap)
   fills it and publishes the epoch; a thread finding it claimed fills its own copy in *mine
   (the same bits). *leaf: its leaf block, or NULL. */
static const sim_bvh_node4 *wide_ready(const sim_bvh *b, int w, const float (*v)[4],
                                       const int32_t (*tris)[4], sim_bvh_node4 *mine,
                                       sim_bvh_leaf4 *mine_leaf, const sim_bvh_leaf4 **leaf)
{
    sim_bvh_node4 *q = &b->wide[w];
    sim_bvh_leaf4 *l = q->leaves >= 0 ? &b->wleaf[q->leaves] : NULL;
    *leaf = l;
    int seen = atomic_load_explicit(&q->stamp, memory_order_acquire);
    if (seen == b->epoch)
        return q;
    if (seen != WIDE_BUSY &&
        atomic_compare_exchange_strong_explicit(&q->stamp, &seen, WIDE_BUSY, memory_order_acquire,
                                                memory_order_relaxed)) {
        fill_wide(b, w, v, tris, q, l);
        atomic_store_explicit(&q->stamp, b->epoch, memory_order_release);
        return q;
    }
    memcpy(mine->next, q->next, sizeof q->next);
    mine->count = q->count;
    mine->leaves = q->leaves;
    mine->leaf_mask = q->leaf_mask;
    if (l) {
        memcpy(mine_leaf->tri, l->tri, sizeof l->tri);
        memset(mine_leaf->v, 0, sizeof mine_leaf->v);
        *leaf = mine_leaf;
    }
    fill_wide(b, w, v, tris, mine, l ? mine_leaf : NULL);
    return mine;
}

/* Bit k set where lane k of m is set (movmskps where SSE is there). */
static inline int mask_bits4(i4 m)
{
#if defined(__SSE__)
    return _mm_movemask_ps((__m128)m);
#else
    return (m[0] & 1) | (m[1] & 2) | (m[2] & 4) | (m[3] & 8);
#endif
}

/* The leaf slots `within` of 4-wide node w (their boxes within the best so far), in slot order,
   each against the best as nearest_leaf does: all four closest points at once, then taken one by
   one, a slot's box tested against the best as the slots before it left it (as a loop of
   nearest_leaf calls would), so the answer and its ties are the scalar search's bit for bit. A
   slot whose triangle is farther than the best on entry changes nothing (the best only shrinks),
   so only the others are taken. */
static void nearest_leaves4(const sim_bvh_leaf4 *l, int within, const float box_d2[4],
                            const float p[3], int *best, float *best_d2, float q[3], float bary[3])
{
    f4 vq[3], vb[3], vd2;
    i4 reg;
    closest4(p, l->v, vq, vb, &vd2, &reg);
    int take = within & mask_bits4(vd2 <= splat4(*best_d2));
    if (!take)
        return;
    float cq[3][4], cb[3][4], cd2[4];
    memcpy(cq, vq, sizeof cq);
    memcpy(cb, vb, sizeof cb);
    memcpy(cd2, &vd2, sizeof cd2);
    for (int k = 0; k < 4; k++) {
        if (!(take >> k & 1) || !(box_d2[k] <= *best_d2))
            continue;
        int t = l->tri[k];
        float d2 = cd2[k];
        if (d2 < *best_d2 || (d2 == *best_d2 && (*best < 0 || t < *best))) {
            *best = t;
            *best_d2 = d2;
            for (int a = 0; a < 3; a++) {
                q[a] = cq[a][k];
                bary[a] = cb[a][k];
            }
        }
    }
}

int sim_bvh_nearest(const sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4],
                    const float p[3], float radius_m, float q[3], float bary[3], float *dist_m)
{
    return sim_bvh_nearest_from(b, v, tris, p, radius_m, -1, q, bary, dist_m);
}

/* The 4-wide descent. Nodes are pushed with their box distance, so a pop compares without
   recomputing, and a child already farther than the best is never pushed. At each node the leaf
   slots first (best_d2 shrinks early), then the internal slots still within the best, farthest
   pushed first (ties: the lower slot first), so the nearest is popped next: it is not pushed but
   taken at once (its pop would find it within the best, which has not changed since). */
static void nearest_wide(const sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4],
                         const float p[3], int *best, float *best_d2, float q[3], float bary[3])
{
    sim_bvh_node4 mine;
    sim_bvh_leaf4 mine_leaf;
    int stack[WIDE_STACK], top = 0;
    float sd[WIDE_STACK];
    int node = 0;
    float node_d2 = box_dist2(b->lo[0], b->hi[0], p);
    for (;;) {
        if (!(node_d2 > *best_d2)) {
            const sim_bvh_leaf4 *leaf;
            const sim_bvh_node4 *w = wide_ready(b, node, v, tris, &mine, &mine_leaf, &leaf);
            f4 vd2 = wide_box_dist2(w, p);
            float d2[4];
            memcpy(d2, &vd2, sizeof d2);
            int slots = (1 << w->count) - 1;
            int within = mask_bits4(vd2 <= splat4(*best_d2)) & slots;
            if (within & w->leaf_mask) {
                nearest_leaves4(leaf, within & w->leaf_mask, d2, p, best, best_d2, q, bary);
                within &= mask_bits4(vd2 <= splat4(*best_d2));
            }
            within &= ~w->leaf_mask;
            if (within && !(within & (within - 1))) { /* one: taken at once */
                int k = __builtin_ctz((unsigned)within);
                node = w->next[k];
                node_d2 = d2[k];
                continue;
            }
            int in[4], nin = 0;
            for (; within; within &= within - 1)
                in[nin++] = __builtin_ctz((unsigned)within);
            if (nin > 0 && top + nin <= WIDE_STACK) { /* always, for trees built here */
                for (int i = 1; i < nin; i++)         /* by distance, descending */
                    for (int j = i; j > 0 && d2[in[j]] > d2[in[j - 1]]; j--) {
                        int t = in[j];
                        in[j] = in[j - 1];
                        in[j - 1] = t;
                    }
                for (int i = 0; i + 1 < nin; i++) {
                    stack[top] = w->next[in[i]];
                    sd[top++] = d2[in[i]];
                }
                node = w->next[in[nin - 1]];
                node_d2 = d2[in[nin - 1]];
                continue;
            }
        }
        if (top == 0)
            break;
        top--;
        node = stack[top];
        node_d2 = sd[top];
    }
}

int sim_bvh_nearest_from(const sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4],
                         const float p[3], float radius_m, int hint, float q[3], float bary[3],
                         float *dist_m)
{
    int best = -1;
    float best_d2 = radius_m * radius_m;
    if (b->n < 1)
        return -1;
    if (hint >= 0 && hint < b->n) {
        /* The hint only shrinks the search ball: a node is pruned when strictly farther than the
           best so far, so ties are still visited and the answer is the hint-free one. */
        float cq[3], cb[3];
        sim_closest_on_triangle(p, v[tris[hint][0]], v[tris[hint][1]], v[tris[hint][2]], cq, cb);
        float dx = p[0] - cq[0], dy = p[1] - cq[1], dz = p[2] - cq[2];
        float d2 = dx * dx + dy * dy + dz * dz;
        if (d2 <= best_d2) {
            best = hint;
            best_d2 = d2;
            memcpy(q, cq, sizeof cq);
            memcpy(bary, cb, sizeof cb);
        }
    }
    if (b->n == 1)
        nearest_leaf(b, v, tris, p, 0, &best, &best_d2, q, bary);
    else
        nearest_wide(b, v, tris, p, &best, &best_d2, q, bary);
    if (best >= 0 && dist_m)
        *dist_m = sqrtf(best_d2);
    return best;
}

/* p inside the box grown by pad (0 for the swept boxes, which are stored padded). */
static int box_contains(const float lo[4], const float hi[4], float pad, const float p[3])
{
    return p[0] >= lo[0] - pad && p[0] <= hi[0] + pad && p[1] >= lo[1] - pad &&
           p[1] <= hi[1] + pad && p[2] >= lo[2] - pad && p[2] <= hi[2] + pad;
}

int sim_bvh_containing(const sim_bvh *b, const float p[3], int swept, int32_t *out, int max_out)
{
    float(*lo)[4] = swept ? b->slo : b->lo;
    float(*hi)[4] = swept ? b->shi : b->hi;
    float pad = swept ? 0.0f : b->pad;
    int found = 0;
    if (b->n < 1)
        return 0;
    int stack[BVH_STACK], top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int node = stack[--top];
        if (!box_contains(lo[node], hi[node], pad, p))
            continue;
        int leaf = leaf_of(b, node);
        if (leaf >= 0) {
            if (found < max_out)
                out[found] = b->order[leaf];
            found++;
            continue;
        }
        if (top + 2 > BVH_STACK)
            continue;
        stack[top++] = b->child[node][1];
        stack[top++] = b->child[node][0];
    }
    return found;
}
