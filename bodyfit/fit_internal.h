/* Private to the fitter (fit_*.c): the skinning Jacobian in sparse form and the solver. */
#ifndef TRYON_FIT_INTERNAL_H
#define TRYON_FIT_INTERNAL_H

#include "body_internal.h"
#include "fit_track.h"

/* One posed vertex and its derivatives: d(vertex) = t + sum_k delta_k x b[k] for a root move t
 * and small world rotations delta_k about the centres of the joints listed (the joints that
 * move it: its influences and their ancestors). */
typedef struct fit_vjac {
    float pos[3];
    int n;
    int joint[FIT_JOINT_COUNT];
    float b[FIT_JOINT_COUNT][3];
} fit_vjac;

/* skin and joints from body_joint_transforms for the pose. */
void fit_vertex_sparse(const fit_model *m, const float skin[][12], const float *joints, int v,
                       fit_vjac *out);

/* Log map of a rotation matrix (row-major) to an axis-angle vector. */
void fit_rotation_log(const double m[9], float r[3]);

/* What one solve is asked to explain, and how hard. */
typedef struct fit_problem {
    const float *points; /* [count][3] world data points */
    int count;
    const fit_segment *seg; /* silhouette and depth (sampled grid); NULL = no such term */
    const int32_t *nearest; /* seg grid: nearest person pixel (cvs_nearest_set) */
    int roi[4];             /* the box where nearest is known (cvs_nearest_set) */
    const fit_depth_view *view;
    const fit_pose *prev; /* temporal prior's anchor (last frame's pose) */
    int iterations;
    float max_match_m; /* data points farther from the model are outliers */
    float temporal;    /* weight of the temporal prior */
    float explained_m; /* a point this close to the model is explained; 0 = FIT_EXPLAINED_M */
} fit_problem;

typedef struct fit_stats {
    float rms_mm;
    int inliers;
    int explained; /* points within explained_m of the model (the last pass) */
    int iterations;
    int clamped;                     /* pose parameters the last step pushed past a joint limit */
    int sil_checked, sil_violations; /* camera-facing vertices checked against free space, and
                                        those FIT_SIL_OUT_PX or more outside the silhouette
                                        where the camera sees past them (the last pass) */
} fit_stats;
/* A point this close to the model is explained by it, at least: depth noise is 1 cm at 2.5 m. */
#define FIT_EXPLAINED_M 0.04f
/* A model vertex this many grid pixels outside the person, where the camera sees farther, is
 * in free space: a body part where there is none (2 px at stride 2: 3.5 cm at 2.5 m). */
#define FIT_SIL_OUT_PX 2

typedef struct fit_solver fit_solver;
fit_solver *fit_solver_create(const fit_model *coarse);
void fit_solver_destroy(fit_solver *s);
int fit_solve(fit_solver *s, const fit_problem *pb, fit_pose *pose, fit_stats *st);
/* Mean signed point-to-model offset (m, positive = data outside the model) per body part of
 * the last solve: 0 torso, 1 arms, 2 legs; counts in n. */
void fit_solver_part_offsets(const fit_solver *s, double off[3], int n[3]);

/* Topology-keeping shape changes (fit_shape_adapt.c): a copy of a model's rest mesh, normals
 * and joints, re-applied with a uniform scale and per-part girth offsets (m along the normal). */
#define FIT_SHAPE_PARTS 3 /* torso (with head), arms, legs */
typedef struct fit_shape_base {
    float *v, *n;
    int nv;
    float joint[FIT_JOINT_COUNT][3];
    fit_shape shape;
} fit_shape_base;
int fit_shape_base_init(fit_shape_base *b, const fit_model *m);
void fit_shape_base_free(fit_shape_base *b);
int fit_shape_part(int joint);
void fit_shape_base_apply(const fit_shape_base *b, fit_model *m, float scale,
                          const float offset[FIT_SHAPE_PARTS]);
fit_shape fit_shape_adapted(const fit_shape_base *b, float scale,
                            const float offset[FIT_SHAPE_PARTS]);

#endif
