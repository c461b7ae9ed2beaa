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
/* Solves A x = b in place for a symmetric positive definite n x n A (row-major, its lower
   triangle read and overwritten by the factor); -1 when A is not positive definite. */
int fit_cholesky_solve(double *A, double *x, int n);

/* Topology-keeping shape changes (fit_shape_adapt.c): a copy of a model's rest mesh, normals
 * and joints, re-applied with the shape's degrees of freedom below. */
/* One degree of freedom per shape parameter (fit_shape order but the torso's three girths as
 * ratios): ratios are 1 and offsets 0 for the base shape. */
typedef struct fit_shape_q {
    float scale;      /* height over the base's: vertical, about the floor */
    float leg;        /* leg length over the height-scaled base's, height kept */
    float arm;        /* arm length over the base's, along the rest arm */
    float shoulder;   /* shoulder width over the base's */
    float torso[3];   /* hip, waist, chest girth over the base's: the pelvis, spine and chest
                         parts scaled across (x and z) about their joint */
    float arm_offset; /* m along the rest normal: the arm's girth grows by 2 pi times it */
    float leg_offset; /* the same for the legs */
} fit_shape_q;
#define FIT_SHAPE_DOF 9 /* fit_shape_q as an array, in that order */
fit_shape_q fit_shape_q_identity(void);
void fit_shape_q_to_array(const fit_shape_q *q, float a[FIT_SHAPE_DOF]);
fit_shape_q fit_shape_q_from_array(const float a[FIT_SHAPE_DOF]);

typedef struct fit_shape_base {
    float *v, *n;
    int nv;
    float joint[FIT_JOINT_COUNT][3];
    fit_shape shape;
} fit_shape_base;
int fit_shape_base_init(fit_shape_base *b, const fit_model *m);
void fit_shape_base_free(fit_shape_base *b);
void fit_shape_base_apply(const fit_shape_base *b, fit_model *m, const fit_shape_q *q);
fit_shape fit_shape_adapted(const fit_shape_base *b, const fit_shape_q *q);

/* The last solve's correspondences (fit_solve.c): point i of the problem matched to coarse
 * vertex vertex[i] (-1: none) with weight weight[i] and signed point-to-plane residual resid[i]
 * (m); the posed coarse vertices and normals at the solved pose. Valid until the next solve. */
typedef struct fit_matches {
    const int32_t *vertex;
    const float *weight, *resid, *pos, *nrm;
    int count;
} fit_matches;
fit_matches fit_solver_matches(const fit_solver *s);

/* One Gauss-Newton step of the shape's degrees of freedom (all but the height's scale, which
 * the top of the person gives) with the root's translation, on the last solve's
 * correspondences, the rest of the pose held; gain scales
 * the step (fit_shape_step.c); points: the solve's data points. scratch: FIT_SHAPE_DOF * the coarse
 * vertex count * 3 floats. The coarse model is left with q applied. Returns 0 or a negative
 * fit_error. */
int fit_shape_step(const fit_shape_base *b, fit_model *coarse, const fit_solver *s, fit_pose *pose,
                   const float *points, float gain, float *scratch, fit_shape_q *q);

/* The most points of one cluster among the points the model leaves unexplained (no match, or
 * farther than tol from it), points within radius_m of each other joined (fit_unexplained.c):
 * a limb the fit has lost leaves its points together, depth noise leaves them scattered.
 * centroid: that cluster's mean point. -1 without memory. */
int fit_unexplained_cluster(const float *points, const fit_matches *m, float tol, float radius_m,
                            float centroid[3]);
/* A lost arm turned towards its points, target (world; fit_limb.c): the shoulder nearest
 * target (FIT_L_SHOULDER or FIT_R_SHOULDER); the arm of shoulder sh turned about the shoulder
 * so that its shoulder-to-wrist line points at target; or its forearm turned, the upper arm
 * twisted about itself and the elbow bent, so that its elbow-to-wrist line does. The pose is
 * kept inside the joint limits. */
int fit_limb_nearest_shoulder(const fit_model *m, const fit_pose *pose, const float target[3]);
void fit_limb_reaim(const fit_model *m, fit_pose *pose, int sh, const float target[3]);
void fit_limb_reaim_forearm(const fit_model *m, fit_pose *pose, int sh, const float target[3]);

#endif
