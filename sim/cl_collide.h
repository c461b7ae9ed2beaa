/* The collider on an OpenCL device (private to sim/): buffers mirroring the host
 * collider (sim/collide.h) and the kernels of kernels/bvh.cl, feature_points.cl, collide.cl.
 * The tree's topology comes from the host collider once per body topology (its Morton sort and
 * hierarchy are the C reference; the kernel twins are tested against it); per frame the device
 * takes the new body vertices and refits. */
#ifndef TRYON_SIM_CL_COLLIDE_H
#define TRYON_SIM_CL_COLLIDE_H

#include "cl_context.h"
#include "collide.h"

/* Files the program needs (after kernels/common.cl). */
#define SIM_CL_COLLIDE_FILES "bvh.cl", "feature_points.cl", "contact_rule.h", "collide.cl"

typedef struct sim_cl_collide {
    const sim_cl *cl;
    int max_nv, max_nt, max_cloth;
    int nv, nt, have_prev;
    cl_mem v, v_prev, tris, n, n_prev, nbr, vt_start, vt_list;
    cl_mem morton, order, child, parent, lo, hi, slo, shi, counter;
    cl_mem contact, moved, sd;
    cl_kernel k_morton, k_nodes, k_refit, k_normals, k_fp, k_contacts, k_resolve, k_sd, k_track;
} sim_cl_collide;

/* cl must have a program built with SIM_CL_COLLIDE_FILES. 0 or -SIM_CL_Ex. */
int sim_cl_collide_create(sim_cl_collide *g, const sim_cl *cl, int max_nv, int max_nt,
                          int max_cloth, char *err, size_t err_size);
void sim_cl_collide_destroy(sim_cl_collide *g); /* accepts a zeroed g */

/* Body frame k from the host collider. A new topology uploads triangles, adjacency and the tree
   (no sweep this frame); the same topology uploads the vertices only, then face normals and the
   refit run on the device. Enqueued, not waited for. */
int sim_cl_collide_set_body(sim_cl_collide *g, const sim_collider *c, char *err, size_t err_size);

/* The per-point passes on device buffers of float4 (x, x_prev): enqueued, not waited for. */
/* coulomb_mu >= 0: the tryon carry with that friction (coulomb_carry, sim/feature_points.c);
   < 0: seed 000's Eq. 2 */
int sim_cl_collide_feature_points(sim_cl_collide *g, cl_mem x, cl_mem x_prev, int begin, int end,
                                  float thickness_m, float coulomb_mu);
int sim_cl_collide_find_contacts(sim_cl_collide *g, cl_mem x, int begin, int end, float radius_m);
/* Twin of sim_collider_track_contacts: the surface walk from each cached triangle. */
int sim_cl_collide_track_contacts(sim_cl_collide *g, cl_mem x, int begin, int end, float radius_m);
int sim_cl_collide_resolve(sim_cl_collide *g, cl_mem x, cl_mem x_prev, int begin, int end,
                           float thickness_m, float friction);
/* Signed distance per point into g->sd. */
int sim_cl_collide_signed_distance(sim_cl_collide *g, cl_mem x, int n);

#endif
