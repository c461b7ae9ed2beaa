/* The skeleton: joint names and parents, joint limits, and the rest layout from a shape. */
#include "body_internal.h"

#include <math.h>
#include <stdio.h>

#include "tryon_errors.h"

#define FIT_PI 3.14159265358979f
/* Rest A-pose: arms this far from hanging straight down, so they clear the torso. */
#define BODY_ARM_ANGLE (45.0f * FIT_PI / 180.0f)
/* Thigh girth over hip girth: about 0.55 in adults; past 0.62 two thighs no longer fit. */
#define BODY_MAX_THIGH_HIP 0.62f
/* Chest half-width over half the shoulder-joint distance: 0.85..1.0 in adults. */
#define BODY_MAX_CHEST_SHOULDER 1.1f

static const char *const joint_names[] = {
#define X(id, name, parent) name,
    FIT_JOINT_LIST(X)
#undef X
};
static const int joint_parents[] = {
#define X(id, name, parent) parent,
    FIT_JOINT_LIST(X)
#undef X
};

const char *fit_joint_name(fit_joint j)
{
    return (j >= 0 && j < FIT_JOINT_COUNT) ? joint_names[j] : "unknown";
}

int fit_joint_parent(fit_joint j)
{
    return (j >= 0 && j < FIT_JOINT_COUNT) ? joint_parents[j] : -1;
}

TRYON_ERROR_WORDS(FIT_ERROR_LIST, FIT_ERROR_COUNT, fit_error_name, fit_error_string,
                  "FIT_ERR_UNKNOWN")

/* Limits in the anatomical frame, radians, {x lo, y lo, z lo}, {x hi, y hi, z hi}. x is the
 * flexion hinge, y the twist about the bone, z abduction. Left side; the right mirrors y, z. */
static const float limit_lo[FIT_JOINT_COUNT][3] = {
    [FIT_PELVIS] = {-FIT_PI, -FIT_PI, -FIT_PI}, /* the root: free orientation */
    [FIT_SPINE] = {-0.4f, -0.5f, -0.4f},        [FIT_CHEST] = {-0.3f, -0.5f, -0.3f},
    [FIT_NECK] = {-0.6f, -0.9f, -0.5f},         [FIT_HEAD] = {-0.5f, -0.6f, -0.4f},
    [FIT_L_CLAVICLE] = {-0.3f, -0.3f, -0.2f},   [FIT_L_SHOULDER] = {-2.6f, -1.4f, -0.9f},
    [FIT_L_ELBOW] = {-2.6f, -1.4f, -0.1f},      [FIT_L_WRIST] = {-1.2f, -0.3f, -0.5f},
    [FIT_L_HIP] = {-2.0f, -0.7f, -0.4f},        [FIT_L_KNEE] = {-0.05f, -0.3f, -0.05f},
    [FIT_L_ANKLE] = {-0.6f, -0.4f, -0.4f},      [FIT_L_TOE] = {-0.8f, -0.1f, -0.1f},
};
static const float limit_hi[FIT_JOINT_COUNT][3] = {
    [FIT_PELVIS] = {FIT_PI, FIT_PI, FIT_PI}, [FIT_SPINE] = {0.8f, 0.5f, 0.4f},
    [FIT_CHEST] = {0.5f, 0.5f, 0.3f},        [FIT_NECK] = {0.7f, 0.9f, 0.5f},
    [FIT_HEAD] = {0.5f, 0.6f, 0.4f},         [FIT_L_CLAVICLE] = {0.3f, 0.3f, 0.5f},
    [FIT_L_SHOULDER] = {1.0f, 1.4f, 2.2f},   [FIT_L_ELBOW] = {0.05f, 1.4f, 0.1f},
    [FIT_L_WRIST] = {1.2f, 0.3f, 0.5f},      [FIT_L_HIP] = {0.5f, 0.7f, 0.9f},
    [FIT_L_KNEE] = {2.4f, 0.3f, 0.05f},      [FIT_L_ANKLE] = {0.9f, 0.4f, 0.4f},
    [FIT_L_TOE] = {0.4f, 0.1f, 0.1f},
};

/* The right-side joint mirrors the left one (mirror x: y and z rotations change sign). */
static int left_twin(fit_joint j)
{
    switch (j) {
    case FIT_R_CLAVICLE:
        return FIT_L_CLAVICLE;
    case FIT_R_SHOULDER:
        return FIT_L_SHOULDER;
    case FIT_R_ELBOW:
        return FIT_L_ELBOW;
    case FIT_R_WRIST:
        return FIT_L_WRIST;
    case FIT_R_HIP:
        return FIT_L_HIP;
    case FIT_R_KNEE:
        return FIT_L_KNEE;
    case FIT_R_ANKLE:
        return FIT_L_ANKLE;
    case FIT_R_TOE:
        return FIT_L_TOE;
    default:
        return -1;
    }
}

void fit_joint_limits(fit_joint j, float lo[3], float hi[3])
{
    if (j < 0 || j >= FIT_JOINT_COUNT) {
        lo[0] = lo[1] = lo[2] = hi[0] = hi[1] = hi[2] = 0.0f;
        return;
    }
    int l = left_twin(j);
    if (l < 0) {
        for (int k = 0; k < 3; ++k) {
            lo[k] = limit_lo[j][k];
            hi[k] = limit_hi[j][k];
        }
        return;
    }
    lo[0] = limit_lo[l][0];
    hi[0] = limit_hi[l][0];
    for (int k = 1; k < 3; ++k) {
        lo[k] = -limit_hi[l][k];
        hi[k] = -limit_lo[l][k];
    }
}

/* The arm joints' anatomical frame is the world frame turned about z by the A-pose angle. */
static float arm_frame_angle(fit_joint j)
{
    switch (j) {
    case FIT_L_SHOULDER:
    case FIT_L_ELBOW:
    case FIT_L_WRIST:
        return BODY_ARM_ANGLE;
    case FIT_R_SHOULDER:
    case FIT_R_ELBOW:
    case FIT_R_WRIST:
        return -BODY_ARM_ANGLE;
    default:
        return 0.0f;
    }
}

static void rotate_z(float angle, const float in[3], float out[3])
{
    float c = cosf(angle), s = sinf(angle);
    float x = c * in[0] - s * in[1], y = s * in[0] + c * in[1];
    out[0] = x;
    out[1] = y;
    out[2] = in[2];
}

void fit_joint_from_anatomical(fit_joint j, const float anat[3], float rot[3])
{
    rotate_z(arm_frame_angle(j), anat, rot);
}

void fit_joint_to_anatomical(fit_joint j, const float rot[3], float anat[3])
{
    rotate_z(-arm_frame_angle(j), rot, anat);
}

/* The arm frames round-trip through a rotation, which moves a clamped value by ~1e-7 rad: so
 * clamping twice changes nothing, values this close to a limit count as inside. */
#define BODY_LIMIT_SLACK 1e-5f

int fit_pose_clamp(fit_pose *pose)
{
    if (!pose)
        return 0;
    int clamped = 0;
    for (int k = 0; k < 3; ++k) {
        if (!isfinite(pose->root[k])) {
            pose->root[k] = 0.0f;
            ++clamped;
        }
    }
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        float lo[3], hi[3], a[3];
        fit_joint_limits((fit_joint)j, lo, hi);
        fit_joint_to_anatomical((fit_joint)j, pose->rot[j], a);
        int hit = 0;
        for (int k = 0; k < 3; ++k) {
            if (!isfinite(a[k])) {
                a[k] = 0.0f;
                hit = 1;
            } else if (a[k] < lo[k] - BODY_LIMIT_SLACK) {
                a[k] = lo[k];
                hit = 1;
            } else if (a[k] > hi[k] + BODY_LIMIT_SLACK) {
                a[k] = hi[k];
                hit = 1;
            }
        }
        if (hit) {
            fit_joint_from_anatomical((fit_joint)j, a, pose->rot[j]);
            ++clamped;
        }
    }
    return clamped;
}

/* Perimeter of an ellipse with semi-axes a and q*a is pi*a*g(q) (Ramanujan's approximation). */
float body_ellipse_g(float q)
{
    return 3.0f * (1.0f + q) - sqrtf((3.0f + q) * (1.0f + 3.0f * q));
}

static void set3(float *d, float x, float y, float z)
{
    d[0] = x;
    d[1] = y;
    d[2] = z;
}

/* Legs: thighs splay out by an angle chosen so the thighs stay apart where the girth is
 * measured (the slice must be one thigh, and touching thighs would make a handle); shins
 * hang vertically. Hip-joint to ankle-joint distance is exactly leg_length. */
static void build_legs(const fit_shape *s, body_skeleton *sk, float ankle_y, float *hip_y)
{
    float sc = sk->scale, len = s->leg_length;
    float a_hip = s->hip_girth / (FIT_PI * body_ellipse_g(BODY_HIP_Q));
    float hip_x = 0.5f * a_hip;
    float r_t = s->leg_girth / (2.0f * FIT_PI);
    float l1 = 0.5f * len, at = BODY_THIGH_MEASURE_AT * l1;
    float sin_a = (r_t + 0.5f * BODY_THIGH_GAP * sc - hip_x) / at;
    float lo = sinf(3.0f * FIT_PI / 180.0f), hi = sinf(14.0f * FIT_PI / 180.0f);
    sin_a = sin_a < lo ? lo : (sin_a > hi ? hi : sin_a);
    float cos_a = sqrtf(1.0f - sin_a * sin_a);
    float l2 = sqrtf(len * len - l1 * l1 * sin_a * sin_a) - l1 * cos_a;
    *hip_y = ankle_y + l1 * cos_a + l2;
    for (int side = 0; side < 2; ++side) {
        float sx = side == 0 ? 1.0f : -1.0f;
        int hip = side == 0 ? FIT_L_HIP : FIT_R_HIP;
        float kx = hip_x + l1 * sin_a, ky = *hip_y - l1 * cos_a;
        set3(sk->joint[hip], sx * hip_x, *hip_y, 0.0f);
        set3(sk->joint[hip + 1], sx * kx, ky, 0.0f);
        set3(sk->joint[hip + 2], sx * kx, ankle_y, 0.0f);
        set3(sk->joint[hip + 3], sx * kx, 0.03f * sc, 0.12f * sc);
        float d[3] = {sx * sin_a, -cos_a, 0.0f};
        for (int k = 0; k < 3; ++k) {
            sk->leg_dir[side][k] = d[k];
            sk->leg_point[side][k] = sk->joint[hip][k] + at * d[k];
        }
    }
}

static void build_arms(const fit_shape *s, body_skeleton *sk, float shoulder_y)
{
    float sc = sk->scale;
    for (int side = 0; side < 2; ++side) {
        float sx = side == 0 ? 1.0f : -1.0f;
        int cl = side == 0 ? FIT_L_CLAVICLE : FIT_R_CLAVICLE;
        float d[3] = {sx * sinf(BODY_ARM_ANGLE), -cosf(BODY_ARM_ANGLE), 0.0f};
        float sh[3] = {sx * 0.5f * s->shoulder_width, shoulder_y, 0.0f};
        set3(sk->joint[cl], sx * 0.03f * sc, shoulder_y - 0.01f * sc, 0.0f);
        for (int k = 0; k < 3; ++k) {
            sk->joint[cl + 1][k] = sh[k];
            sk->joint[cl + 2][k] = sh[k] + BODY_UPPER_ARM_FRACTION * s->arm_length * d[k];
            sk->joint[cl + 3][k] = sh[k] + s->arm_length * d[k];
            sk->arm_dir[side][k] = d[k];
            sk->arm_point[side][k] =
                sh[k] + BODY_ARM_MEASURE_AT * BODY_UPPER_ARM_FRACTION * s->arm_length * d[k];
        }
    }
}

int body_skeleton_build(const fit_shape *s, body_skeleton *sk, char *err, size_t errlen)
{
    int rc = fit_shape_validate(s, err, errlen);
    if (rc)
        return rc;
    float sc = s->height / 1.75f;
    sk->scale = sc;
    float ankle_y = 0.08f * sc, hip_y;
    build_legs(s, sk, ankle_y, &hip_y);
    /* Shoulder height 0.818 of stature: the usual anthropometric ratio. */
    float shoulder_y = 0.818f * s->height;
    float torso = shoulder_y - hip_y;
    if (torso < 0.3f * sc || torso > 0.7f * sc) {
        if (err)
            snprintf(err, errlen,
                     "fit shape: leg_length %.3f m leaves a torso of %.3f m for height %.3f m "
                     "(needs %.3f..%.3f)",
                     s->leg_length, torso, s->height, 0.3f * sc, 0.7f * sc);
        return -FIT_ERR_RANGE;
    }
    /* Proportions the construction needs: thighs that fit side by side inside the hips, and
     * A-pose arms that clear the chest (else the slices would measure arm and torso as one). */
    if (s->leg_girth > BODY_MAX_THIGH_HIP * s->hip_girth) {
        if (err)
            snprintf(err, errlen,
                     "fit shape: leg_girth %.3f m is more than %.2f of hip_girth %.3f m",
                     s->leg_girth, BODY_MAX_THIGH_HIP, s->hip_girth);
        return -FIT_ERR_RANGE;
    }
    float a_chest = s->chest_girth / (FIT_PI * body_ellipse_g(BODY_CHEST_Q));
    float r_arm = s->arm_girth / (2.0f * FIT_PI);
    float clear = 0.5f * s->shoulder_width + 0.36f * torso - 1.5f * r_arm - a_chest;
    if (clear < 0.03f * sc || a_chest > BODY_MAX_CHEST_SHOULDER * 0.5f * s->shoulder_width) {
        if (err)
            snprintf(err, errlen,
                     "fit shape: chest_girth %.3f m and arm_girth %.3f m are too large for "
                     "shoulder_width %.3f m (the arms would cut into the chest)",
                     s->chest_girth, s->arm_girth, s->shoulder_width);
        return -FIT_ERR_RANGE;
    }
    sk->torso_len = torso;
    sk->hip_y = hip_y;
    sk->waist_y = hip_y + 0.32f * torso;
    sk->chest_y = hip_y + 0.64f * torso;
    set3(sk->joint[FIT_PELVIS], 0.0f, hip_y + 0.05f * sc, 0.0f);
    set3(sk->joint[FIT_SPINE], 0.0f, hip_y + 0.35f * torso, -0.01f * sc);
    set3(sk->joint[FIT_CHEST], 0.0f, hip_y + 0.65f * torso, -0.01f * sc);
    set3(sk->joint[FIT_NECK], 0.0f, shoulder_y + 0.03f * sc, -0.01f * sc);
    set3(sk->joint[FIT_HEAD], 0.0f, s->height - 0.19f * sc, 0.0f);
    build_arms(s, sk, shoulder_y);
    return 0;
}
