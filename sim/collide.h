/* collide: cloth-body collision for the sim (private to sim/).
 *
 * Seed 000 (Su et al. 2018), per body frame k:
 *   - one LBVH (Karras 2012) over the body triangles, built once per body topology and refitted
 *     every frame; each leaf carries a static box (frame k, inflated by the thickness: the S-BVH)
 *     and a swept box (frames k-1 and k together, inflated: the D-BVH), so both BVHs share one
 * tree;
 *   - feature points (seed 000 section 2.1, Eq. 1-2): cloth points swept by a moving triangle are
 *     carried with it;
 *   - contacts: the nearest triangle within reach of each cloth point, found once per frame (or
 *     every few iterations) and cached; the solver iterations resolve against the cached triangle;
 *   - penetration metric: signed distance with angle-weighted pseudo-normals (Baerentzen & Aanaes
 *     2005).
 *
 * Layout (STYLE.md 3): cloth positions float (*x)[4] with w = inverse mass (0 = pinned, never moved
 * here), body vertices float (*v)[4], triangles int32_t (*tris)[4] (w unused), normals float[4]. */
#ifndef TRYON_SIM_COLLIDE_H
#define TRYON_SIM_COLLIDE_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "collide_bvh.h" /* the collider holds the body's BVH (struct sim_collider, below) */
#include "sim.h"         /* sim_error */

/* Errors: 0 or minus a sim_error (sim.h; docs/building.md, "Conventions: errors"), named by
 * sim_error_name / sim_error_text. */

/* ---- The interface the solver calls ------------------------------------------------------- */

typedef struct sim_collider sim_collider;
typedef struct sim_collider_desc {
    int max_vertices, max_triangles; /* body capacity, allocated at create */
    float thickness_m;               /* cloth kept this far outside the body; 0 = 0.004 */
    float friction;                  /* Coulomb-like coefficient mu, >= 0 */
    float reach_m; /* contact search radius beyond thickness; 0 = 0.03 (covers a frame's motion) */
    int max_cloth; /* cloth points the contact cache holds; 0 = none until sim_collider_reserve */
    /* Feature points: 0 = seed 000's Eq. 2, the point carried with its triangle's whole motion;
       1 = the motion along the triangle's normal whole, along its surface only up to friction
       times that (Coulomb: the tryon solver; sim_collider_feature_points) */
    int carry_coulomb;
    /* Contact response: 0 = the push may become velocity (seed 000; the dressing); 1 = inelastic,
       only the point's own approach may (the tryon solver and its OpenCL twin; resolve.c) */
    int inelastic;
} sim_collider_desc;

/* NULL on failure with the reason in err. */
sim_collider *sim_collider_create(const sim_collider_desc *d, char *err, size_t err_size);
void sim_collider_destroy(sim_collider *c); /* accepts NULL */

/* New body frame: xyz is nv * 3 floats (metres), tris nt * 3 vertex indices. Frame k becomes k-1;
   refit (or build, when the topology is new) the tree over frame k and the swept boxes k-1 -> k.
   Returns 0, or minus a sim_error: a rejected body (NaN, index out of range,
   degenerate, empty, too big) leaves the collider as it was; -SIM_ERR_TOPOLOGY means the body
   was accepted with a new topology (not said for the first body) and this frame has no sweep. */
int sim_collider_set_body(sim_collider *c, const float *xyz, int nv, const int32_t *tris, int nt);

/* Seed 000 section 2.1, Eq. 1-2: carry cloth points swept by the body with their triangle.
   x_prev is moved by the same displacement, so a carried point keeps the velocity it had (the
   carry is a kinematic jump across a frame gap, not a velocity). Returns how many moved. */
int sim_collider_feature_points(sim_collider *c, float (*x)[4], float (*x_prev)[4], int begin,
                                int end);

/* Find the nearest body triangle within thickness + reach for each point in [begin, end) and
   cache it; a point with none there that is not clearly outside (it may be deep inside) gets the
   nearest triangle at any distance, so the response pushes it out; -1: none. Points at or beyond
   the cache size (max_cloth, or sim_collider_reserve) are ignored. */
void sim_collider_find_contacts(sim_collider *c, const float (*x)[4], int begin, int end);

/* The contacts of points [begin, end) at x found by a twin of sim_collider_find_contacts (the
   OpenCL backend's device search against this body frame): cached as if found here, with the
   bounds the penetration metric uses. */
void sim_collider_adopt_contacts(sim_collider *c, const float (*x)[4], const int32_t *contact,
                                 int begin, int end);

/* Cheap refresh between searches: from each cached triangle, walk over the body surface to the
   locally nearest triangle (-1 when it is beyond reach); points without a cached triangle get
   the full search. Exact outside a smooth patch (inside, any face may be a local minimum, which
   still pushes the point out of that face); a different body part coming nearer is only seen by
   sim_collider_find_contacts (or as a feature point), so call that once per frame and this in
   the iterations. */
void sim_collider_track_contacts(sim_collider *c, const float (*x)[4], int begin, int end);

/* Points [begin, end) that have moved farther from where the search saw them than
   sim_research_radius (kernels/contact_rule.h) allows for that search's clearance (their distance
   to the whole body then; thickness + reach for a point that had nothing within reach) are
   searched again: the cached triangle, or none, is only sure to be the one that matters within
   that distance. A point pushed off one wall of a gap narrower than twice the thickness (the
   lowered arm against the chest) goes into the other wall, which the frame's search did not give
   it (docs/garments.md, "The T-shirt with the arms lowered"). */
void sim_collider_research(sim_collider *c, const float (*x)[4], int begin, int end);

/* Push points out to thickness along the contact normal (face normal, or the pseudo-normal at
   edges and vertices of the cached triangle), then friction: cancel the tangential motion
   relative to the body (x - x_prev) up to friction * the normal correction. Never pulls a point
   towards the body. Inelastic (desc.inelastic): x_prev moves with the push beyond the point's own
   approach, so depth the body made is corrected without becoming velocity. */
void sim_collider_resolve(const sim_collider *c, float (*x)[4], float (*x_prev)[4], int begin,
                          int end);

/* How squarely the body holds point i at p up: the upward (+y) component of its cached triangle's
   face normal when p lies within thickness + tol_m of that triangle (closest-point distance), or
   SIM_NOT_RESTING when it has none or lies farther (the support hierarchy's root is the highest
   point with a value above 0: resting on an upward face). */
#define SIM_NOT_RESTING (-2.0f)
float sim_collider_resting(const sim_collider *c, int i, const float p[3], float tol_m);

/* Metric: how many of the n points lie more than tol_m inside the body (signed distance with
   angle-weighted pseudo-normals) and the deepest one (metres, >= 0). Returns 0 or an error. */
int sim_collider_penetration(const sim_collider *c, const float (*x)[4], int n, float tol_m,
                             int *count, float *max_depth_m);

/* The body kept, its cloth forgotten (a garment made again on the same body): every cached
   contact and bound cleared, and the next body frame has no sweep from this one (the new garment
   was made on that frame). */
void sim_collider_restart(sim_collider *c);

/* Grow the contact cache to max_cloth points (not in the frame loop). 0 or an error. */
int sim_collider_reserve(sim_collider *c, int max_cloth);

/* Read-only views for tests and the OpenCL backend. */
typedef struct sim_bvh sim_bvh;
const sim_bvh *sim_collider_bvh(const sim_collider *c);
const int32_t *sim_collider_contacts(const sim_collider *c); /* cached triangle per point */
int sim_collider_body(const sim_collider *c, const float (**v)[4], const float (**v_prev)[4],
                      const int32_t (**tris)[4], const float (**n)[4]); /* returns nt */

/* ---- The collider's state (private to sim/: collide.c, feature_points.c, cl_backend.c) ------ */

struct sim_collider {
    sim_collider_desc d; /* defaults filled in */
    int nv, nt;          /* body now; 0 before the first body */
    int have_prev;       /* frame k-1 has the topology of frame k (a sweep exists) */
    int restarted;       /* sim_collider_restart: the next frame of this topology sweeps nothing */
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
