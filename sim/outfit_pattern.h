/* Sewing-pattern garments for the sim (sim/outfit_pattern.c): a pattern dressed by tryon's method
 * (garments/, gar_dress_tryon) on the body model with the body message's shape, then carried to
 * the message's pose, handed to the sim as its garment. A library of its own because garments/
 * itself uses tryon_sim. */
#ifndef TRYON_SIM_OUTFIT_PATTERN_H
#define TRYON_SIM_OUTFIT_PATTERN_H

#include <stdint.h>

#include "sim.h"

/* The dressing's figures, for the log and the tests. */
typedef struct sim_pattern_stats {
    float dress_ms;               /* gar_dress_tryon's wall clock on the rest body */
    float seam_gap_mm;            /* after dressing */
    int penetrating;              /* after dressing, on the rest body (> 1 mm inside) */
    float total_ms;               /* model, load, mesh, place, dress and carry */
    float spacing_m;              /* the mesh's */
    float max_strain, p99_strain; /* after dressing, on the rest body (stretch springs) */
} sim_pattern_stats;

/* gar_mesh_build's default: 2 cm, about 2,500 vertices for the shipped T-shirt and jeans. */
#define SIM_PATTERN_DEFAULT_SPACING_M 0.02f

/* o->is_pattern: the pattern o->garment graded to o->size, dressed in o->fabric_name (garments/'s
 * fabric of that name, else cotton) on fit_model made from shape (FIT_SHAPE_PARAMS values,
 * metres), carried from the rest pose to pose (FIT_POSE_PARAMS values), its panels sewn into one
 * mesh (sim/pattern_weld.h) and its highest opening attached to the body (sim/pattern_hold.h).
 * body_xyz, nv, body_tris, nt: the body message's mesh of that shape and pose, which the
 * attachments are moved to (NULL: they stay on the model's own mesh, 10,000 vertices);
 * target_vertices: the garment meshed to about that many vertices (0: at 2 cm). Refuses,
 * why naming the field: a body message without shape or pose (-SIM_ERR_PARAM), a shape out of
 * range (-SIM_ERR_PARAM), a pattern file that cannot be read or meshed (-SIM_ERR_FILE: no body
 * helps). stats may be NULL. */
int sim_outfit_make_pattern(const sim_outfit *o, const float *shape, int num_shape,
                            const float *pose, int num_pose, const float *body_xyz, int nv,
                            const int32_t *body_tris, int nt, int target_vertices, sim_garment *out,
                            sim_pattern_stats *stats, sim_reject *why);

/* The same on a body model given, carried from its rest pose to posed_xyz (its vertices in the
 * pose where the sim starts), meshed at the spacing that gives about target_vertices (0: 2 cm;
 * the count reached is out->num_vertices). part_of (may be NULL): a new array, per garment
 * vertex, of the gar_part (garments.h) of its panel: torso, an arm or a leg; the caller frees
 * it. Refuses as sim_outfit_make_pattern. */
struct fit_model;
int sim_pattern_dress_on(const sim_outfit *o, const struct fit_model *body, const float *posed_xyz,
                         int target_vertices, sim_garment *out, int8_t **part_of,
                         sim_pattern_stats *stats, sim_reject *why);

/* A freshly dressed garment's first frames on its first body, the body held still: the carry to
 * the pose leaves contacts and strain that the first step resolves by moving the cloth, and that
 * motion carried into a frame where the body moves pushed a few vertices through the arm (the
 * T-shirt on the walk's second frame: 2 vertices 4.8 mm inside without these, test_sim_pattern).
 * Steps the sim SIM_PATTERN_SETTLE_FRAMES times on the body, without the frame budget (part of
 * dressing); returns sim_step's result. */
#define SIM_PATTERN_SETTLE_FRAMES 2

/* The contact thickness (sim_desc.thickness_m) a sim wearing a dressed pattern needs: the
 * dressing's, so that the contacts hold the cloth where the dressing left it (garments.h). */
float sim_pattern_thickness_m(void);
int sim_pattern_settle(sim *s, const float *body_xyz, int nv, const int32_t *body_tris, int nt,
                       sim_reject *why);

#endif
