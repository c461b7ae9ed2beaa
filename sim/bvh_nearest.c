/* The nearest-triangle search over the 4-wide copy of the LBVH (sim/bvh.c builds both): the
 * contact search's query (sim_collider_find_contacts) and the metric's exact one. Four slot boxes
 * a node and four leaf triangles at a time in SSE registers (GCC / Clang vector extension), each
 * lane bit for bit the scalar computation, visited in the order of the scalar search so that the
 * answers and their ties are its own. Twin: sim_bvh_nearest of kernels/common.cl (binary tree). */
#include <float.h>
#include <math.h>
#include <stdatomic.h>
#include <string.h>
#if defined(__SSE__)
#include <xmmintrin.h>
#endif

#include "collide.h"
#include "collide_bvh.h"
#include "collide_geometry.h"

/* The LBVH depth bound (sim/bvh.c); the 4-wide search pushes at most three more nodes per level
   than it pops. */
#define WIDE_STACK (3 * 96)
/* The stamp of a 4-wide node being filled (epochs are never negative). */
#define WIDE_BUSY (-2)

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
                         float bary[3], int *region)
{
    int t = b->order[i];
    float cq[3], cb[3];
    int r = sim_closest_on_triangle(p, v[tris[t][0]], v[tris[t][1]], v[tris[t][2]], cq, cb);
    float dx = p[0] - cq[0], dy = p[1] - cq[1], dz = p[2] - cq[2];
    float d2 = dx * dx + dy * dy + dz * dz;
    if (d2 < *best_d2 || (d2 == *best_d2 && (*best < 0 || t < *best))) {
        *best = t;
        *best_d2 = d2;
        *region = r;
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
                            const float p[3], int *best, float *best_d2, float q[3], float bary[3],
                            int *region)
{
    f4 vq[3], vb[3], vd2;
    i4 reg;
    closest4(p, l->v, vq, vb, &vd2, &reg);
    int take = within & mask_bits4(vd2 <= splat4(*best_d2));
    if (!take)
        return;
    float cq[3][4], cb[3][4], cd2[4];
    int32_t creg[4];
    memcpy(cq, vq, sizeof cq);
    memcpy(cb, vb, sizeof cb);
    memcpy(cd2, &vd2, sizeof cd2);
    memcpy(creg, &reg, sizeof creg);
    for (int k = 0; k < 4; k++) {
        if (!(take >> k & 1) || !(box_d2[k] <= *best_d2))
            continue;
        int t = l->tri[k];
        float d2 = cd2[k];
        if (d2 < *best_d2 || (d2 == *best_d2 && (*best < 0 || t < *best))) {
            *best = t;
            *best_d2 = d2;
            *region = creg[k];
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
                         const float p[3], int *best, float *best_d2, float q[3], float bary[3],
                         int *region)
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
                nearest_leaves4(leaf, within & w->leaf_mask, d2, p, best, best_d2, q, bary, region);
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
    return sim_bvh_nearest_region(b, v, tris, p, radius_m, hint, q, bary, dist_m, NULL);
}

int sim_bvh_nearest_region(const sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4],
                           const float p[3], float radius_m, int hint, float q[3], float bary[3],
                           float *dist_m, int *region_out)
{
    int best = -1, region = SIM_REGION_FACE;
    float best_d2 = radius_m * radius_m;
    if (b->n < 1)
        return -1;
    if (hint >= 0 && hint < b->n) {
        /* The hint only shrinks the search ball: a node is pruned when strictly farther than the
           best so far, so ties are still visited and the answer is the hint-free one. */
        float cq[3], cb[3];
        int r = sim_closest_on_triangle(p, v[tris[hint][0]], v[tris[hint][1]], v[tris[hint][2]], cq,
                                        cb);
        float dx = p[0] - cq[0], dy = p[1] - cq[1], dz = p[2] - cq[2];
        float d2 = dx * dx + dy * dy + dz * dz;
        if (d2 <= best_d2) {
            best = hint;
            best_d2 = d2;
            region = r;
            memcpy(q, cq, sizeof cq);
            memcpy(bary, cb, sizeof cb);
        }
    }
    if (b->n == 1)
        nearest_leaf(b, v, tris, p, 0, &best, &best_d2, q, bary, &region);
    else
        nearest_wide(b, v, tris, p, &best, &best_d2, q, bary, &region);
    if (best >= 0 && dist_m)
        *dist_m = sqrtf(best_d2);
    if (best >= 0 && region_out)
        *region_out = region;
    return best;
}
