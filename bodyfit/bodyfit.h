/* bodyfit: the parametric human body, its scripted motions, and (later) fitting it to depth.
 *
 * Frame: world, metres, y up, floor at y = 0; in the rest pose the body stands at x = z = 0
 * facing +z (towards the camera), arms slightly lowered (A-pose). */
#ifndef TRYON_BODYFIT_H
#define TRYON_BODYFIT_H

#include <stddef.h>
#include <stdint.h>

/* The skeleton. Each joint rotates about its own centre, relative to its parent. */
#define FIT_JOINT_LIST(X)                                                                          \
    X(FIT_PELVIS, "pelvis", -1)                                                                    \
    X(FIT_SPINE, "spine", FIT_PELVIS)                                                              \
    X(FIT_CHEST, "chest", FIT_SPINE)                                                               \
    X(FIT_NECK, "neck", FIT_CHEST)                                                                 \
    X(FIT_HEAD, "head", FIT_NECK)                                                                  \
    X(FIT_L_CLAVICLE, "l_clavicle", FIT_CHEST)                                                     \
    X(FIT_L_SHOULDER, "l_shoulder", FIT_L_CLAVICLE)                                                \
    X(FIT_L_ELBOW, "l_elbow", FIT_L_SHOULDER)                                                      \
    X(FIT_L_WRIST, "l_wrist", FIT_L_ELBOW)                                                         \
    X(FIT_R_CLAVICLE, "r_clavicle", FIT_CHEST)                                                     \
    X(FIT_R_SHOULDER, "r_shoulder", FIT_R_CLAVICLE)                                                \
    X(FIT_R_ELBOW, "r_elbow", FIT_R_SHOULDER)                                                      \
    X(FIT_R_WRIST, "r_wrist", FIT_R_ELBOW)                                                         \
    X(FIT_L_HIP, "l_hip", FIT_PELVIS)                                                              \
    X(FIT_L_KNEE, "l_knee", FIT_L_HIP)                                                             \
    X(FIT_L_ANKLE, "l_ankle", FIT_L_KNEE)                                                          \
    X(FIT_L_TOE, "l_toe", FIT_L_ANKLE)                                                             \
    X(FIT_R_HIP, "r_hip", FIT_PELVIS)                                                              \
    X(FIT_R_KNEE, "r_knee", FIT_R_HIP)                                                             \
    X(FIT_R_ANKLE, "r_ankle", FIT_R_KNEE)                                                          \
    X(FIT_R_TOE, "r_toe", FIT_R_ANKLE)

#define FIT_JOINT_ENUM(id, name, parent) id,
typedef enum fit_joint { FIT_JOINT_LIST(FIT_JOINT_ENUM) FIT_JOINT_COUNT } fit_joint;
#undef FIT_JOINT_ENUM

const char *fit_joint_name(fit_joint j);
int fit_joint_parent(fit_joint j); /* -1 for the root */

/* Shape: what a depth camera can constrain. Metres. */
typedef struct fit_shape {
    float height;         /* floor to top of head */
    float shoulder_width; /* between the shoulder joint centres */
    float chest_girth;
    float waist_girth;
    float hip_girth;
    float arm_length; /* shoulder joint to wrist joint */
    float arm_girth;  /* upper arm, largest */
    float leg_length; /* hip joint to ankle joint */
    float leg_girth;  /* thigh, largest */
} fit_shape;
#define FIT_SHAPE_PARAMS 9

fit_shape fit_shape_default(void); /* an average adult */
#define FIT_SHAPE_PRESETS 3
fit_shape fit_shape_preset(int i); /* 0 = average, 1 = slim tall, 2 = broad short */
const char *fit_shape_preset_name(int i);
void fit_shape_to_array(const fit_shape *s, float out[FIT_SHAPE_PARAMS]);
fit_shape fit_shape_from_array(const float in[FIT_SHAPE_PARAMS]);

/* Pose: root translation plus one axis-angle rotation (radians) per joint, local to its parent.
 * Zero rotations = the rest pose. */
typedef struct fit_pose {
    float root[3];
    float rot[FIT_JOINT_COUNT][3];
} fit_pose;
#define FIT_POSE_PARAMS (3 + 3 * FIT_JOINT_COUNT)

/* Clamp every joint rotation into its limits. Returns how many joints were clamped. */
int fit_pose_clamp(fit_pose *pose);

/* The model: a closed manifold triangle mesh generated from a shape, with skinning weights. */
typedef struct fit_model fit_model;
typedef struct fit_model_desc {
    fit_shape shape;
    int target_vertices; /* 0 = 10000; the mesh has about this many vertices (6K..15K sensible) */
} fit_model_desc;

fit_model *fit_model_create(const fit_model_desc *desc, char *err, size_t errlen);
void fit_model_destroy(fit_model *m);

int fit_model_vertex_count(const fit_model *m);
int fit_model_triangle_count(const fit_model *m);
const int32_t *fit_model_triangles(const fit_model *m);   /* [triangle][3], counter-clockwise seen
                                                            from outside */
const float *fit_model_rest_vertices(const fit_model *m); /* [vertex][3] */
const fit_shape *fit_model_shape(const fit_model *m);

/* The posed body: linear-blend skinning, then where two parts (trunk, arms, legs) pass through
 * each other each part's skin stops at their contact surface (docs/body-model.md). vertices_out:
 * vertex_count * 3 floats; joints_out (may be NULL): FIT_JOINT_COUNT * 3 floats, world joint
 * centres. Deterministic; no allocation. */
int fit_model_pose(const fit_model *m, const fit_pose *pose, float *vertices_out,
                   float *joints_out);
/* Linear-blend skinning alone (what the fitter's derivatives describe); same arguments. */
int fit_model_pose_lbs(const fit_model *m, const fit_pose *pose, float *vertices_out,
                       float *joints_out);

int fit_model_write_obj(const fit_model *m, const float *vertices, const char *path);

/* Scripted motions, for recordings and the simulation benchmarks. */
#define FIT_MOTION_LIST(X)                                                                         \
    X(FIT_MOTION_STILL, "still")                                                                   \
    X(FIT_MOTION_ARM_RAISE, "arm_raise")                                                           \
    X(FIT_MOTION_TURN, "turn")                                                                     \
    X(FIT_MOTION_WALK, "walk")                                                                     \
    X(FIT_MOTION_FAST_SWING, "fast_swing") /* wrist speed >= 3 m/s */                              \
    X(FIT_MOTION_ENTER_LEAVE, "enter_leave")                                                       \
    X(FIT_MOTION_ARMS_DOWN, "arms_down")       /* A-pose to 6 deg from vertical, held, back */     \
    X(FIT_MOTION_BOXING_GUARD, "boxing_guard") /* forearms up against the chest, held, back */     \
    X(FIT_MOTION_BEND_FORWARD, "bend_forward") /* trunk 30 deg forward and back at 1 Hz */         \
    X(FIT_MOTION_BEND_SIDE, "bend_side")       /* trunk 20 deg to either side at 0.5 Hz */         \
    X(FIT_MOTION_TWIST, "twist")               /* trunk 45 deg about the spine, at 0.5 Hz */       \
    X(FIT_MOTION_BEND_FAST, "bend_fast")       /* trunk 30 deg forward and back in 0.7 s */        \
    X(FIT_MOTION_ARMS_CROSS, "arms_cross")     /* forearms crossed before the chest, held, back */ \
    X(FIT_MOTION_DISTANCE, "distance")         /* walks from 1.5 to 3.5 m off the camera, back */  \
    X(FIT_MOTION_PART_OUT, "part_out")         /* steps 1.3 m aside, half out of view, back */

#define FIT_MOTION_ENUM(id, name) id,
typedef enum fit_motion { FIT_MOTION_LIST(FIT_MOTION_ENUM) FIT_MOTION_COUNT } fit_motion;
#undef FIT_MOTION_ENUM

const char *fit_motion_name(fit_motion m);
int fit_motion_from_name(const char *name); /* -1 if unknown */
double fit_motion_duration(fit_motion m);   /* seconds; motions loop after this */
void fit_motion_eval(fit_motion m, double t_s, fit_pose *out);

/* ---- Errors, validation, measurement, skin weights. ---- */

/* Errors as values; one list makes the enum and the messages so a test can name the rejection.
 * Functions return 0 or -FIT_ERR_x (docs/building.md, "Conventions: errors"). */
#define FIT_ERROR_LIST(X)                                                                          \
    X(FIT_OK, "ok")                                                                                \
    X(FIT_ERR_ARG, "missing or invalid argument")                                                  \
    X(FIT_ERR_NAN, "value is not finite")                                                          \
    X(FIT_ERR_RANGE, "value out of range")                                                         \
    X(FIT_ERR_NOMEM, "out of memory")                                                              \
    X(FIT_ERR_IO, "file could not be written")                                                     \
    X(FIT_ERR_MESH, "mesh generation failed")                                                      \
    X(FIT_ERR_MEASURE, "measurement failed")                                                       \
    X(FIT_ERR_PARSE, "malformed file")

#define FIT_ERROR_ENUM(id, msg) id,
typedef enum fit_error { FIT_ERROR_LIST(FIT_ERROR_ENUM) FIT_ERROR_COUNT } fit_error;
#undef FIT_ERROR_ENUM
const char *fit_error_name(int code);   /* "FIT_ERR_PARSE"; accepts code or -code */
const char *fit_error_string(int code); /* "malformed file"; accepts code or -code */

/* Checks every shape parameter against its range (see docs/body-model.md). Returns 0 or a
 * negative fit_error; err (may be NULL) names the parameter and the range. */
int fit_shape_validate(const fit_shape *s, char *err, size_t errlen);
/* Inclusive range of shape parameter i (fit_shape_to_array order), metres. */
void fit_shape_param_range(int i, float *lo, float *hi);
const char *fit_shape_param_name(int i);

/* Pose conventions: root is added to the pelvis joint's rest position (zero = standing at the
 * origin); rot[FIT_PELVIS] turns the whole body about the pelvis joint. About +x, a bone that
 * points up tilts forward for positive angles, one that points down swings backward (so hip and
 * shoulder flexion are negative, knee flexion positive); about +z the left limbs rise sideways.
 *
 * Joint limits: each rotation vector is expressed in the joint's anatomical frame (identity
 * except the arms, whose frame follows the A-pose arm: local -y along the arm, local x the
 * flexion hinge), then clamped per component. */
void fit_joint_limits(fit_joint j, float lo[3], float hi[3]);
/* World (rest parent) rotation vector from an anatomical one and back. */
void fit_joint_from_anatomical(fit_joint j, const float anat[3], float rot[3]);
void fit_joint_to_anatomical(fit_joint j, const float rot[3], float anat[3]);

/* Measured on the rest mesh: girths are perimeters of the slice loop around the torso (chest,
 * waist, hip: horizontal planes) or the limb (arm, thigh: planes perpendicular to the bone). */
typedef struct fit_measurements {
    fit_shape shape;
    float chest_y, waist_y, hip_y; /* heights of the torso slices, metres */
} fit_measurements;
int fit_model_measure(const fit_model *m, fit_measurements *out);

/* Area-weighted unit vertex normals of a posed (or rest) vertex array: vertex_count * 3 floats
 * in, the same out. No allocation. Returns 0 or a negative fit_error. */
int fit_model_normals(const fit_model *m, const float *vertices, float *normals_out);

/* Skinning data: FIT_MAX_INFLUENCES joints and weights per vertex (unused slots weight 0). */
#define FIT_MAX_INFLUENCES 4
const uint8_t *fit_model_weight_joints(const fit_model *m); /* [vertex][4] */
const float *fit_model_weights(const fit_model *m);         /* [vertex][4], sum 1 */
const float *fit_model_rest_joints(const fit_model *m);     /* [joint][3] */

/* ---- Motion capture: BVH files (bodyfit/bvh_read.c) and their retargeting (retarget.c). ---- */

/* A BVH file (Biovision hierarchy: a joint tree, then one line of channel values a frame).
 * Units are the file's own; the frame is y up, the character facing +z with its left at +x, as
 * the CMU conversions and most BVH files are. */
#define FIT_BVH_MAX_JOINTS 256
typedef struct fit_bvh fit_bvh;
/* Parses text (len bytes, need not be NUL-terminated); name labels errors. Returns 0 or a
 * negative fit_error (-FIT_ERR_PARSE: err says "NAME:LINE: what was wrong"). */
int fit_bvh_parse(const char *text, size_t len, const char *name, fit_bvh **out, char *err,
                  size_t errlen);
int fit_bvh_load(const char *path, fit_bvh **out, char *err, size_t errlen);
void fit_bvh_destroy(fit_bvh *b);
int fit_bvh_joint_count(const fit_bvh *b);
int fit_bvh_frame_count(const fit_bvh *b);
double fit_bvh_frame_time(const fit_bvh *b); /* seconds */
const char *fit_bvh_joint_name(const fit_bvh *b, int j);
int fit_bvh_joint_parent(const fit_bvh *b, int j);          /* -1 for the root */
int fit_bvh_find_joint(const fit_bvh *b, const char *name); /* -1 if absent */
/* Forward kinematics of one frame: world joint positions (joint_count * 3, file units) and
 * world rotations (joint_count * 9, row-major; may be NULL). Returns 0 or a negative fit_error. */
int fit_bvh_world(const fit_bvh *b, int frame, float *pos, float *rot);

/* A clip: a BVH file retargeted onto a body shape, resampled to FIT_CLIP_FPS. Each model bone
 * turns as the clip's matching bone does, from the difference of the two rest poses (the clip's
 * T-pose against the model's A-pose); elbows and knees keep only the turn about their hinge;
 * the root moves as the clip's hips, scaled by the ratio of leg lengths; joints are clamped to
 * their limits. Horizontally the clip starts at x = z = 0. */
#define FIT_CLIP_FPS 30
typedef struct fit_clip fit_clip;
int fit_clip_from_bvh(const fit_bvh *b, const fit_model *m, fit_clip **out, char *err,
                      size_t errlen);
void fit_clip_destroy(fit_clip *c);
int fit_clip_frame_count(const fit_clip *c);
double fit_clip_duration(const fit_clip *c); /* seconds; fit_clip_eval loops after this */
/* The pose at time t_s (the nearest frame, looping). */
void fit_clip_eval(const fit_clip *c, double t_s, fit_pose *out);
/* Turns the whole clip about the vertical axis so that its first frame faces the camera (+z):
 * a person steps in front of a mirror facing it, whichever way the capture studio's subject
 * faced; their turns after that are the clip's. Returns the heading taken off (radians, the
 * pelvis's forward direction from +z towards +x; 0 when it has none). */
double fit_clip_face_camera(fit_clip *c);
/* The file's time (seconds) of clip frame 0: 0, or one frame time where the file opens on a
 * reference pose that the motion then leaves in a jump (CMU's clips), which is dropped. */
double fit_clip_start(const fit_clip *c);
/* The clip's BVH joint whose world rotation drives model joint j (-1: none). */
int fit_clip_source_joint(const fit_clip *c, fit_joint j);

#endif
