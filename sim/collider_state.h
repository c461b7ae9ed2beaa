/* Private to sim/: the collider's state and the helpers over it (collide.c, find_contacts.c,
 * resolve.c, feature_points.c, penetration.c), split from collide.h. */
#ifndef TRYON_SIM_COLLIDER_STATE_H
#define TRYON_SIM_COLLIDER_STATE_H

#include <stdatomic.h>
#include <stdint.h>

#include "collide.h"
#include "collide_bvh.h"

/* ---- The collider's state (private to sim/: collide.c, feature_points.c, cl_backend.c) ------ */

struct sim_collider {
    sim_collider_desc d; /* defaults filled in */
    int nv, nt;          /* body now; 0 before the first body */
    int have_prev;       /* frame k-1 has the topology of frame k (a sweep exists) */
    float (*v)[4], (*v_prev)[4];
    int32_t (*tris)[4];
    float (*n)[4], (*n_prev)[4]; /* unit face normals, frames k and k-1 */
    float (*n_next)[4];          /* the next frame's, written by its validation */
    int32_t (*nbr)[4];           /* triangle across edge i (i to i+1), -1 on an open edge */
    int32_t *vt_start, *vt_list; /* vertex -> incident triangles (CSR) for pseudo-normals */
    void *edge_scratch;          /* topology build only */
    sim_bvh bvh;
    int32_t *contact; /* cached triangle per cloth point, -1 = none */
    int max_cloth;
    /* Per cloth point, from its last full contact search against this body frame: xyz where the
       point was, w a lower bound of its signed distance to the body there (> 0: outside by at
       least w; <= 0: no bound). The signed distance is 1-Lipschitz, so a point now closer than w
       to that place is still outside: the metric then needs no query of its own. Cleared by
       sim_collider_set_body (a new body frame voids every bound). */
    float (*clear)[4];
    /* Per cloth point, from its last response that moved nothing (sim_collider_resolve): xyz where
       the point was, w a radius within which the response against triangle key[0] of body frame
       key[1] (body_epoch) is sure to move nothing again (w <= 0: none). Written by the resolve of
       that point's owner only; a new body frame voids it through the epoch. */
    float (*quiet)[4];
    int32_t (*quiet_key)[2];
    int32_t body_epoch; /* incremented by every sim_collider_set_body */
    /* Vertex pseudo-normals of this body frame, computed on first use (sim_collider_pseudo_normal):
       vn[i] is valid when vn_stamp[i] == body_epoch. The first thread to claim a vertex (stamp
       set to SIM_VN_BUSY by compare-and-swap) writes it and then publishes the epoch; a thread
       that finds it busy computes its own copy, the same bits. */
    float (*vn)[4];
    atomic_int *vn_stamp;
    /* sim_collider_find_contacts called by a team (sim/find_contacts.c): each thread's range in
       its slot, so that threads done with theirs take chunks of the others'. */
    struct sim_contact_slot *share;
};

/* Threads a team may have for the shared contact search (a bigger team searches unshared). */
#define SIM_SHARE_SLOTS 64
/* Points a range of the shared search may hold (the slot word's offset has 24 bits). */
#define SIM_SHARE_MAX_POINTS (1 << 23)

typedef struct sim_contact_slot {
    _Alignas(64) _Atomic uint64_t word; /* generation | chunks being helped | next offset */
    _Atomic uintptr_t x;                /* the owner's cloth positions */
    atomic_int begin, end;              /* the owner's range */
} sim_contact_slot;

/* Angle-weighted pseudo-normal (Baerentzen & Aanaes 2005) of the feature of triangle t named by a
   SIM_REGION_* (not normalised: only its direction is used). */
void sim_collider_pseudo_normal(const sim_collider *c, int t, int region, float out[3]);

/* Greedy walk over the body surface from triangle t towards p (sim_collider_track_contacts):
   the locally nearest triangle and its squared distance. */
int sim_collider_walk_nearest(const sim_collider *c, const float p[3], int t, float *d2_out);

/* Is p outside the body for sure? Parity of the crossings of a vertical segment from p to above
   the body (0 when a crossing is too near an edge to count: unsure). */
int sim_collider_clearly_outside(const sim_collider *c, const float p[3]);

/* The metric the slow way: one unbounded nearest-triangle search per point (for tests). */
int sim_collider_penetration_exact(const sim_collider *c, const float (*x)[4], int n, float tol_m,
                                   int *count, float *max_depth_m);

/* acos from + - * / and sqrt only (Abramowitz & Stegun 4.4.45, 6.7e-5 rad), bit-equal to its
   OpenCL twin; angle weights of pseudo-normals. */
float sim_acos(float x);

/* Signed distance of p to the body through triangle t (its closest point and pseudo-normal). */
float sim_collider_signed_distance(const sim_collider *c, int t, const float p[3]);
/* The same from t's closest point q to p, in region (sim_closest_on_triangle's, or the nearest
   search's: sim_bvh_nearest_region), without computing them again. */
float sim_collider_signed_distance_at(const sim_collider *c, int t, const float p[3],
                                      const float q[3], int region);

#endif
