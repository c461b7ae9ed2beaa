/* Sewing-pattern garments for the sim (sim/outfit_pattern.c): a pattern dressed by tryon's method
 * (garments/, gar_dress_tryon) on the body model with the body message's shape, then carried to
 * the message's pose, handed to the sim as its garment. A library of its own because garments/
 * itself uses tryon_sim. */
#ifndef TRYON_SIM_OUTFIT_PATTERN_H
#define TRYON_SIM_OUTFIT_PATTERN_H

#include "sim.h"

/* The dressing's figures, for the log and the tests. */
typedef struct sim_pattern_stats {
    float dress_ms;    /* gar_dress_tryon's wall clock on the rest body */
    float seam_gap_mm; /* after dressing */
    int penetrating;   /* after dressing, on the rest body (> 1 mm inside) */
    float total_ms;    /* model, load, mesh, place, dress and carry */
} sim_pattern_stats;

/* o->is_pattern: the pattern o->garment graded to o->size, dressed in o->fabric_name (garments/'s
 * fabric of that name, else cotton) on fit_model made from shape (FIT_SHAPE_PARAMS values,
 * metres), carried from the rest pose to pose (FIT_POSE_PARAMS values). Refuses, why naming
 * the field: a body message without shape or pose (-SIM_ERR_PARAM), a shape out of range
 * (-SIM_ERR_PARAM), a pattern file that cannot be read or meshed (-SIM_ERR_FILE: no body helps).
 * stats may be NULL. */
int sim_outfit_make_pattern(const sim_outfit *o, const float *shape, int num_shape,
                            const float *pose, int num_pose, sim_garment *out,
                            sim_pattern_stats *stats, sim_reject *why);

/* A freshly dressed garment's first frames on its first body, the body held still: the carry to
 * the pose leaves contacts and strain that the first step resolves by moving the cloth, and that
 * motion carried into a frame where the body moves pushed a few vertices through the arm (the
 * T-shirt on the walk's second frame: 2 vertices 4.8 mm inside without these, test_sim_pattern).
 * Steps the sim SIM_PATTERN_SETTLE_FRAMES times on the body, without the frame budget (part of
 * dressing); returns sim_step's result. */
#define SIM_PATTERN_SETTLE_FRAMES 2
int sim_pattern_settle(sim *s, const float *body_xyz, int nv, const int32_t *body_tris, int nt,
                       sim_reject *why);

#endif
