/* The body's tree. Its topology is built once per body topology (the body mesh keeps its triangles
 * from frame to frame) and only refitted per frame, so the build is chosen for the tree's quality
 * rather than its own speed: a binned SAH (surface area heuristic) build, top down, on the
 * topology's first frame. The Karras LBVH (Karras 2012, "Maximizing parallelism in the construction
 * of BVHs, octrees and k-d trees": Morton codes of triangle centroids, a radix sort, every internal
 * node found on its own from the longest common prefix of the sorted codes) is kept for what
 * rebuilds every frame (the seed's method, tryon-bench-collide) and as the twin of the device's
 * build kernels (kernels/bvh.cl). Refit: boxes bottom-up, the twin of the device's. Both builds
 * give the same shape of tree (internal nodes 0..n-2 from the root, leaf i of the triangles in
 * `order` is node n-1+i), so the refit, the 4-wide copy and every query serve either; their
 * answers do not depend on the tree. docs/collision.md, "One tree, two box sets". */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collide.h"
#include "collide_bvh.h"

/* Depth bound of either tree. An LBVH over 30-bit codes extended by a 32-bit index: each level
   lengthens the common prefix by at least one bit. The SAH build: SAH splits down to SAH_DEPTH,
   then halves, so at most SAH_DEPTH + 31 levels. */
#define BVH_STACK 96
/* The SAH build: candidate planes a node and axis, the depth after which it halves, and the
   size of node it halves (binning a node costs its 48 bins whatever its size, and below a few
   triangles the SAH and the median split give trees that answer queries alike; the nodes of two
   to four triangles are most of the tree's nodes and were most of its build). */
#define SAH_BINS  16
#define SAH_DEPTH 48
#define SAH_MIN   4
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
        return -SIM_ERR_NO_MEMORY;
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

/* Half the surface area of binary node i's static box (the build's frame). */
static float box_area(const sim_bvh *b, int i)
{
    float e[3];
    for (int k = 0; k < 3; k++)
        e[k] = b->hi[i][k] - b->lo[i][k];
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
}

/* The 4-wide shape (Wald et al. 2008 collapse): a 4-wide node over binary node i starts with
   i's two children and opens the internal slot of the largest box (the one a query is likeliest
   to enter; in the build's frame) into its two children, in place, until it has four slots or
   none is internal. The tree is uneven (a leaf beside a subtree of hundreds), so opening
   by area rather than level by level keeps nodes full and the descent short. Every binary node
   is a slot or opened, so every leaf is reached once. Nodes are numbered in creation order; a
   node's children come after it. A node with leaf slots gets a block of their triangles (wleaf).
   The boxes must be those of the topology's frame (after the build's first refit). */
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
        int bin = slot[0], count = 2;
        slot[0] = b->child[bin][0];
        slot[1] = b->child[bin][1];
        while (count < 4) {
            int pick = -1;
            for (int k = 0; k < count; k++)
                if (leaf_of(b, slot[k]) < 0 &&
                    (pick < 0 || box_area(b, slot[k]) > box_area(b, slot[pick])))
                    pick = k;
            if (pick < 0)
                break;
            int ch = slot[pick];
            for (int k = count; k > pick + 1; k--)
                slot[k] = slot[k - 1];
            slot[pick] = b->child[ch][0];
            slot[pick + 1] = b->child[ch][1];
            count++;
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

/* Topology by LBVH (the kernels' twin): Morton codes of the centroids in their box, radix sort,
   every internal node from the longest common prefix. */
static void topology_lbvh(sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4], int nt)
{
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
#pragma omp parallel for schedule(static)
    for (int i = 0; i < nt - 1; i++)
        build_node(b, i);
}

/* The SAH build's node: triangles order[begin, end) under internal node `node`. */
typedef struct sah_task {
    int begin, end, node, depth;
} sah_task;

static float half_area(const float lo[3], const float hi[3])
{
    float e0 = hi[0] - lo[0], e1 = hi[1] - lo[1], e2 = hi[2] - lo[2];
    return e0 * e1 + e1 * e2 + e2 * e0;
}

/* The bin of centroid coordinate c in [lo, lo + ext). */
static int sah_bin(float c, float lo, float ext)
{
    int q = (int)((c - lo) / ext * (float)SAH_BINS);
    return q < 0 ? 0 : (q >= SAH_BINS ? SAH_BINS - 1 : q);
}

/* The cheapest plane between two bins along each axis k with ext[k] > 0: the expected cost of a
   query reaching the node, area(left) * triangles(left) + area(right) * triangles(right). One
   pass over the node's triangles bins all three axes. q[k]: the last bin of the left side (its
   cost in cost[k]), or -1 when every centroid falls in one bin or ext[k] is 0. tlo, thi, cen: per
   triangle. */
static void sah_planes(const sim_bvh *b, const sah_task *t, const float cmin[3], const float ext[3],
                       const float (*tlo)[4], const float (*thi)[4], const float (*cen)[4],
                       int q[3], float cost[3])
{
    int cnt[3][SAH_BINS] = {{0}}, right_cnt[SAH_BINS];
    float blo[3][SAH_BINS][3], bhi[3][SAH_BINS][3], right_area[SAH_BINS];
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < SAH_BINS; j++)
            for (int a = 0; a < 3; a++)
                blo[k][j][a] = FLT_MAX, bhi[k][j][a] = -FLT_MAX;
    float e[3];
    for (int k = 0; k < 3; k++)
        e[k] = ext[k] > 0.0f ? ext[k] : 1.0f; /* an axis of no extent: binned, never split */
    for (int i = t->begin; i < t->end; i++) {
        int tri = b->order[i];
        for (int k = 0; k < 3; k++) {
            int j = sah_bin(cen[tri][k], cmin[k], e[k]);
            cnt[k][j]++;
            for (int a = 0; a < 3; a++) {
                blo[k][j][a] = min2(blo[k][j][a], tlo[tri][a]);
                bhi[k][j][a] = max2(bhi[k][j][a], thi[tri][a]);
            }
        }
    }
    for (int k = 0; k < 3; k++) {
        q[k] = -1;
        if (!(ext[k] > 0.0f))
            continue;
        float lo[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, hi[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
        for (int j = SAH_BINS - 1, n = 0; j > 0; j--) {
            n += cnt[k][j];
            for (int a = 0; a < 3; a++)
                lo[a] = min2(lo[a], blo[k][j][a]), hi[a] = max2(hi[a], bhi[k][j][a]);
            right_cnt[j] = n;
            right_area[j] = n > 0 ? half_area(lo, hi) : 0.0f;
        }
        for (int a = 0; a < 3; a++)
            lo[a] = FLT_MAX, hi[a] = -FLT_MAX;
        for (int j = 0, n = 0; j < SAH_BINS - 1; j++) {
            n += cnt[k][j];
            for (int a = 0; a < 3; a++)
                lo[a] = min2(lo[a], blo[k][j][a]), hi[a] = max2(hi[a], bhi[k][j][a]);
            if (n == 0 || right_cnt[j + 1] == 0)
                continue;
            float c = half_area(lo, hi) * (float)n + right_area[j + 1] * (float)right_cnt[j + 1];
            if (q[k] < 0 || c < cost[k]) {
                q[k] = j;
                cost[k] = c;
            }
        }
    }
}

/* order[begin, end) rearranged so that the k-th smallest centroid along axis a is at k, those
   before it no larger and those after no smaller (Hoare's selection). */
static void select_kth(int32_t *order, int begin, int end, int k, const float (*cen)[4], int a)
{
    while (end - begin > 1) {
        float pivot = cen[order[begin + (end - begin) / 2]][a];
        int i = begin, j = end - 1;
        while (i <= j) {
            while (cen[order[i]][a] < pivot)
                i++;
            while (cen[order[j]][a] > pivot)
                j--;
            if (i <= j) {
                int32_t x = order[i];
                order[i++] = order[j];
                order[j--] = x;
            }
        }
        if (k <= j)
            end = j + 1;
        else if (k >= i)
            begin = i;
        else
            return;
    }
}

/* Topology by binned SAH, depth first from the root: each node split at the cheapest plane of
   any axis (sah_planes), or halved at the median centroid of its longest axis when no plane
   separates its centroids, it is SAH_DEPTH deep or holds SAH_MIN triangles or fewer. A side of one
   triangle is a leaf. The triangles' boxes and centroids are kept, by triangle, in the leaf entries
   of lo, hi and slo, which the refit then overwrites. Depth first, the stack holds at most one node
   a level. */
static void topology_sah(sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4], int nt)
{
    float(*tlo)[4] = b->lo + (nt - 1), (*thi)[4] = b->hi + (nt - 1), (*cen)[4] = b->slo + (nt - 1);
    for (int t = 0; t < nt; t++) {
        b->order[t] = t;
        b->morton[t] = 0; /* an LBVH's codes; none here */
        for (int k = 0; k < 3; k++) {
            float a = v[tris[t][0]][k], c = v[tris[t][1]][k], e = v[tris[t][2]][k];
            cen[t][k] = (a + c + e) / 3.0f;
            tlo[t][k] = min2(a, min2(c, e));
            thi[t][k] = max2(a, max2(c, e));
        }
    }
    sah_task stack[BVH_STACK + 2];
    int top = 0, next = 1;
    stack[top++] = (sah_task){0, nt, 0, 0};
    while (top > 0) {
        sah_task t = stack[--top];
        float cmin[3] = {FLT_MAX, FLT_MAX, FLT_MAX}, cmax[3] = {-FLT_MAX, -FLT_MAX, -FLT_MAX};
        for (int i = t.begin; i < t.end; i++)
            for (int k = 0; k < 3; k++) {
                cmin[k] = min2(cmin[k], cen[b->order[i]][k]);
                cmax[k] = max2(cmax[k], cen[b->order[i]][k]);
            }
        int axis = -1, bin = -1, wide = 0, q[3] = {-1, -1, -1};
        float best = 0.0f, ext[3], cost[3];
        for (int k = 0; k < 3; k++) {
            ext[k] = cmax[k] - cmin[k];
            if (ext[k] > ext[wide])
                wide = k;
        }
        if (t.depth < SAH_DEPTH && t.end - t.begin > SAH_MIN)
            sah_planes(b, &t, cmin, ext, (const float(*)[4])tlo, (const float(*)[4])thi,
                       (const float(*)[4])cen, q, cost);
        for (int k = 0; k < 3; k++)
            if (q[k] >= 0 && (axis < 0 || cost[k] < best))
                axis = k, bin = q[k], best = cost[k];
        int mid = t.begin + (t.end - t.begin) / 2;
        if (axis >= 0) {
            float lo = cmin[axis], ext = cmax[axis] - cmin[axis];
            int i = t.begin, j = t.end - 1;
            while (i <= j) {
                if (sah_bin(cen[b->order[i]][axis], lo, ext) <= bin) {
                    i++;
                } else {
                    int32_t x = b->order[i];
                    b->order[i] = b->order[j];
                    b->order[j--] = x;
                }
            }
            mid = i; /* both sides hold a triangle: the plane had some on each */
        } else {
            select_kth(b->order, t.begin, t.end, mid, (const float(*)[4])cen, wide);
        }
        int begin[2] = {t.begin, mid}, end[2] = {mid, t.end};
        for (int s = 0; s < 2; s++) {
            int child = end[s] - begin[s] == 1 ? nt - 1 + begin[s] : next++;
            if (end[s] - begin[s] > 1)
                stack[top++] = (sah_task){begin[s], end[s], child, t.depth + 1};
            b->child[t.node][s] = child;
            b->parent[child] = t.node;
        }
    }
}

static void build(sim_bvh *b, const float (*v_prev)[4], const float (*v)[4],
                  const int32_t (*tris)[4], int nt, float pad_m, int sah)
{
    b->n = nt;
    b->parent[0] = -1;
    if (nt == 1) {
        b->order[0] = 0;
        b->morton[0] = 0;
        b->child[0][0] = b->child[0][1] = 0;
    } else if (nt > 1 && sah) {
        topology_sah(b, v, tris, nt);
    } else {
        topology_lbvh(b, v, tris, nt);
    }
    if (nt > 1)
        build_refit_order(b);
    sim_bvh_refit(b, v_prev, v, tris, pad_m);
    build_wide(b); /* by the boxes of this frame */
}

void sim_bvh_build(sim_bvh *b, const float (*v_prev)[4], const float (*v)[4],
                   const int32_t (*tris)[4], int nt, float pad_m)
{
    build(b, v_prev, v, tris, nt, pad_m, 1);
}

void sim_bvh_build_lbvh(sim_bvh *b, const float (*v_prev)[4], const float (*v)[4],
                        const int32_t (*tris)[4], int nt, float pad_m)
{
    build(b, v_prev, v, tris, nt, pad_m, 0);
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
