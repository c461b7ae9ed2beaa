/* Private to sim/: the body's bounding-volume hierarchy (bvh.c, bvh_nearest.c; its device twin
 * kernels/bvh.cl), split from collide.h. */
#ifndef TRYON_SIM_COLLIDE_BVH_H
#define TRYON_SIM_COLLIDE_BVH_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "collide_geometry.h"

typedef struct sim_bvh sim_bvh;

/* ---- The LBVH (Karras 2012) ------------------------------------------------------------------ */

/* Nodes 0..n-2 are internal (0 is the root), n-1..2n-2 the leaves in Morton order; a child index
   names a node. Leaf i of the sorted order holds triangle order[i]. With one triangle the root is
   the leaf (node 0). */
struct sim_bvh {
    int n, cap;                 /* leaves (triangles) now, capacity */
    uint32_t *morton;           /* per sorted leaf (an LBVH's; zeros for the SAH tree) */
    int32_t *order;             /* sorted leaf -> triangle */
    int32_t (*child)[2];        /* per internal node */
    int32_t *parent;            /* per node, -1 at the root */
    float (*lo)[4], (*hi)[4];   /* static boxes (frame k), per node: inflated by pad when
                                   queried, tight for the nearest-triangle search */
    float (*slo)[4], (*shi)[4]; /* swept boxes (k-1 with k, inflated by pad), per node */
    float pad;                  /* the thickness, m */
    /* The refit's schedule (per topology): refit_list holds every node, children before their
       parent, as nrefit_task subtrees (task i: refit_list[refit_task[i] .. refit_task[i + 1]))
       and then the nodes above them. */
    int32_t *refit_list, *refit_task;
    int nrefit_task;
    uint32_t *scratch; /* radix sort ping-pong, 2 * cap keys + 2 * cap values */
    /* The nearest search's 4-wide copy of the tree: each node holds a binary node's children or,
       where those are internal, their children, so a descent pops half as many nodes and tests
       four boxes at once. Shape built with the topology; boxes (from lo/hi) and leaf blocks
       filled by the first search to reach a node after each refit (its stamp says which). */
    struct sim_bvh_node4 *wide;
    int32_t (*wide_node)[4]; /* per 4-wide node: each slot's binary node (-1: empty) */
    /* The triangles of the 4-wide nodes' leaf slots, one block per node that has any, laid out
       for sim_closest_on_triangle4. */
    struct sim_bvh_leaf4 *wleaf;
    int nwide, nwleaf;
    int32_t epoch; /* incremented by every refit */
};

typedef struct sim_bvh_node4 {
    float lo[3][4], hi[3][4]; /* [axis][slot]: static boxes of the slots' binary nodes */
    int32_t next[4];          /* >= 0: the slot's 4-wide node; < 0: sorted leaf -1 - next */
    int32_t count;            /* slots in use, 2..4 */
    int32_t leaves;           /* its block in wleaf, -1 when no slot is a leaf */
    int32_t leaf_mask;        /* bit k: slot k is a leaf */
    atomic_int stamp;         /* the refit (epoch) its boxes and leaf block hold, or WIDE_BUSY */
} sim_bvh_node4;

typedef struct sim_bvh_leaf4 {
    float v[3][3][4]; /* [vertex][axis][slot]; slots that are not leaves hold zeros */
    int32_t tri[4];   /* triangle of each slot, -1 when not a leaf */
} sim_bvh_leaf4;

int sim_bvh_init(sim_bvh *b, int max_triangles); /* 0 or -SIM_ERR_NO_MEMORY */
void sim_bvh_free(sim_bvh *b);
/* Topology by binned SAH over the triangles of frame k (built once per body topology: sim/bvh.c).
   Then a refit. */
void sim_bvh_build(sim_bvh *b, const float (*v_prev)[4], const float (*v)[4],
                   const int32_t (*tris)[4], int nt, float pad_m);
/* Topology by LBVH, the device build's twin: Morton codes of the centroids of frame k inside their
   box, radix sort, hierarchy from the longest common prefix. Then a refit. Quicker to build, slower
   to search (what rebuilds every frame). */
void sim_bvh_build_lbvh(sim_bvh *b, const float (*v_prev)[4], const float (*v)[4],
                        const int32_t (*tris)[4], int nt, float pad_m);
/* Leaf boxes from the triangles, then bottom-up through parent links, the second child to arrive
   at a node (atomic counter) computing its box. */
void sim_bvh_refit(sim_bvh *b, const float (*v_prev)[4], const float (*v)[4],
                   const int32_t (*tris)[4], float pad_m);

/* 30-bit Morton code of a point given in [0,1]^3 (10 bits per axis, clamped). */
uint32_t sim_morton3(float x, float y, float z);

/* Nearest triangle to p within radius_m (closest point distance); -1 when none. q and bary: the
   closest point and its barycentrics. Ties keep the lower triangle index. v and tris: those the
   tree was last built or refitted over. */
int sim_bvh_nearest(const sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4],
                    const float p[3], float radius_m, float q[3], float bary[3], float *dist_m);

/* The same answer, found faster when hint (a triangle index, or -1) is near p: its distance
   starts as the bound (the contact cache from the last search is a good hint). */
int sim_bvh_nearest_from(const sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4],
                         const float p[3], float radius_m, int hint, float q[3], float bary[3],
                         float *dist_m);
/* The same, and the region of the closest point on the triangle found (sim_closest_on_triangle's,
   bit for bit: the sign of a signed distance needs it). region may be NULL. */
int sim_bvh_nearest_region(const sim_bvh *b, const float (*v)[4], const int32_t (*tris)[4],
                           const float p[3], float radius_m, int hint, float q[3], float bary[3],
                           float *dist_m, int *region);

/* Triangles whose leaf box (static, or swept when swept != 0; both inflated by pad) contains p, up
   to max_out of them written to out; returns how many contain p (which may exceed max_out). */
int sim_bvh_containing(const sim_bvh *b, const float p[3], int swept, int32_t *out, int max_out);

#endif
