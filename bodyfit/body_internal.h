/* Private to bodyfit/: the skeleton layout, the implicit body, the mesh builder, measurement. */
#ifndef TRYON_BODY_INTERNAL_H
#define TRYON_BODY_INTERNAL_H

#include "bodyfit.h"

/* Depth / width of the torso's elliptical sections (typical adult ratios). */
#define BODY_CHEST_Q 0.70f
#define BODY_WAIST_Q 0.78f
#define BODY_HIP_Q   0.75f
/* Upper arm share of shoulder-to-wrist length; where along the bones girths are measured. */
#define BODY_UPPER_ARM_FRACTION 0.54f
#define BODY_ARM_MEASURE_AT     0.4f
#define BODY_THIGH_MEASURE_AT   0.3f
/* Clear space between the thighs where their girth is measured, m (times height / 1.75 m). */
#define BODY_THIGH_GAP 0.044f

/* Perimeter of an ellipse with semi-axes a and q*a is pi * a * body_ellipse_g(q). */
float body_ellipse_g(float q);

/* The rest skeleton and the places girths are measured, all derived from a fit_shape. */
typedef struct body_skeleton {
    float joint[FIT_JOINT_COUNT][3];
    float scale;     /* height / 1.75 m: sizes of parts the shape does not name */
    float torso_len; /* shoulder height minus hip-joint height */
    float chest_y, waist_y, hip_y;
    float arm_point[2][3], arm_dir[2][3]; /* upper-arm girth plane, [0] left [1] right */
    float leg_point[2][3], leg_dir[2][3]; /* thigh girth plane */
} body_skeleton;

int body_skeleton_build(const fit_shape *s, body_skeleton *out, char *err, size_t errlen);

/* Multipliers applied to the cross-sections so measured girths match the shape. */
typedef struct body_calib {
    float chest, waist, hip, arm, leg;
} body_calib;

/* A tapered capsule: distance to the segment, minus a radius interpolated along it. */
typedef struct body_cone {
    float a[3], ba[3], inv_l2, ra, rb;
    int joint, joint2;  /* joint2 >= 0: weight shared with joint2 along split_dir */
    float split_dir[3]; /* fraction to joint2 = smoothstep(split_lo, split_hi, p . split_dir) */
    float split_lo, split_hi;
} body_cone;

#define BODY_TORSO_KEYS 5
#define BODY_MAX_CONES  20
#define BODY_MAX_PRIMS  (BODY_MAX_CONES + 2)

typedef struct body_field {
    float key_y[BODY_TORSO_KEYS], key_a[BODY_TORSO_KEYS], key_b[BODY_TORSO_KEYS];
    float key_z[BODY_TORSO_KEYS];
    float torso_lo, torso_hi, torso_round, torso_round_top; /* rim radii, bottom and top */
    float spine_y, chest_y, torso_ramp; /* torso weight split pelvis / spine / chest */
    float head_c[3], head_r[3];
    body_cone cone[BODY_MAX_CONES];
    int cone_count;
    /* The cones again, one array per number (body_field_build fills them): the distance to
     * every cone is then one vectorised loop, the same arithmetic in the same order. */
    struct {
        float ax[BODY_MAX_CONES], ay[BODY_MAX_CONES], az[BODY_MAX_CONES];
        float bx[BODY_MAX_CONES], by[BODY_MAX_CONES], bz[BODY_MAX_CONES];
        float inv_l2[BODY_MAX_CONES], ra[BODY_MAX_CONES], rb[BODY_MAX_CONES];
    } soa;
    float min_radius;   /* thinnest part (hand, wrist), m: the grid must resolve it */
    float blend;        /* exponential smooth-union radius, m */
    float skin_sigma;   /* softness of the skinning partition, m */
    float lo[3], hi[3]; /* bounding box of the surface plus a margin */
} body_field;

void body_field_build(const body_skeleton *sk, const fit_shape *s, const body_calib *c,
                      body_field *out);
/* Signed distance-like value: < 0 inside. */
float body_field_eval(const body_field *f, const float p[3]);
/* Gradient by central differences. */
void body_field_grad(const body_field *f, const float p[3], float g[3]);
/* Distance to one primitive (< 0 inside): 0 the torso, 1 the head, 2 + i cone i. */
float body_field_prim_dist(const body_field *f, int prim, const float p[3]);
/* Moves p onto the zero set by a few Newton steps along the gradient. */
void body_field_project(const body_field *f, float p[3]);
/* Per-joint skinning weights at p (FIT_JOINT_COUNT floats, sum 1). */
void body_field_joint_weights(const body_field *f, const float p[3], float w[FIT_JOINT_COUNT]);

typedef struct body_mesh {
    float *v;   /* [nv][3] */
    int32_t *t; /* [nt][3] */
    int nv, nt;
} body_mesh;

void body_mesh_free(body_mesh *m);
/* Marching tetrahedra (Kuhn split of each grid cube) at spacing h, grid shifted by offset. */
int body_polygonise(const body_field *f, float h, const float offset[3], body_mesh *out);
/* Euler characteristic and connected components of a closed mesh. */
int body_mesh_topology(const body_mesh *m, int *euler, int *components);
/* Edge collapses down to target vertices, with smoothing passes projected to the surface. */
int body_mesh_decimate(const body_field *f, body_mesh *m, int target);
void body_mesh_smooth(const body_field *f, body_mesh *m, int passes);

/* Girths, height and lengths of a rest mesh. */
int body_measure(const float *v, int nv, const int32_t *t, int nt, const body_skeleton *sk,
                 fit_measurements *out);
/* Perimeter of the slice loop of the mesh by the plane (point, normal) that encloses point. */
float body_slice_girth(const float *v, const int32_t *t, int nt, const float point[3],
                       const float normal[3]);

/* The model object (model.c builds it, skin.c poses it). */
struct fit_model {
    fit_shape shape;
    body_skeleton sk;
    body_field field;
    body_mesh mesh;
    uint8_t *wjoint;
    float *weight;
    fit_measurements meas;
    /* The mesh reshaped after the field was built (fit_shape_base_apply, the tracker's learnt
     * shape): per joint, the map from the reshaped rest space back to the field's (3x4
     * row-major, the inverse of the reshaping's affine map for that joint) and the girth offset
     * its part gained (m), through which the contact pass measures the field. 0: not reshaped
     * (the maps are not used). */
    int reshaped;
    float unshape[FIT_JOINT_COUNT][12];
    float unshape_offset[FIT_JOINT_COUNT];
};

/* Rodrigues' formula (skin.c): the rotation matrix (row-major) of an axis-angle vector. */
void body_axis_angle_matrix(const float r[3], double m[9]);
/* Per joint, the skinning matrix [R | x - R J] (3x4 row-major: R the world rotation, x the world
 * centre, J the rest centre) and, if joints_out is set, the world centres (skin.c). */
void body_joint_transforms(const body_skeleton *sk, const fit_pose *pose, float skin[][12],
                           float *joints_out);

/* Where two parts of the posed body (trunk, each arm, each leg; a vertex belongs to the part
 * holding most of its skinning weight) pass through each other, moves each part's vertices to
 * their contact surface (skin_contact.c). skin: body_joint_transforms' matrices. */
void body_skin_contact(const fit_model *m, const float skin[][12], float *vertices);

/* Small vector helpers. */
static inline float body_dot(const float a[3], const float b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
/* fminf and fmaxf for numbers that are never NaN: the libm calls are not inlined without
 * -ffinite-math-only (NaN's rule), and the body's implicit surface takes the minimum of its
 * primitives a million times a model (12 % of building one). The same result otherwise. */
static inline float body_minf(float a, float b)
{
    return b < a ? b : a;
}
static inline float body_maxf(float a, float b)
{
    return b > a ? b : a;
}
static inline float body_smoothstep(float lo, float hi, float x)
{
    float t = (x - lo) / (hi - lo);
    t = t < 0.0f ? 0.0f : (t > 1.0f ? 1.0f : t);
    return t * t * (3.0f - 2.0f * t);
}

#endif
