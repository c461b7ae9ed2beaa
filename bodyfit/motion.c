/* Scripted motions: closed-form, deterministic poses that stay inside the joint limits.
 * Angles are set in each joint's anatomical frame (x flexion, y twist, z abduction). */
#include "bodyfit.h"

#include <math.h>
#include <string.h>

#define TWO_PI 6.283185307179586

static const char *const motion_names[] = {
#define X(id, name) name,
    FIT_MOTION_LIST(X)
#undef X
};

/* Seconds per loop. Walk: two strides of 1.1 s; fast swing: two swings of 0.8 s. */
static const double motion_durations[] = {4.0, 4.0, 6.0, 2.2, 1.6, 8.0, 6.0, 6.0,
                                          2.0, 4.0, 4.0, 1.4, 6.0, 8.0, 6.0};

const char *fit_motion_name(fit_motion m)
{
    return (m >= 0 && m < FIT_MOTION_COUNT) ? motion_names[m] : "unknown";
}

int fit_motion_from_name(const char *name)
{
    if (!name)
        return -1;
    for (int i = 0; i < FIT_MOTION_COUNT; ++i)
        if (strcmp(name, motion_names[i]) == 0)
            return i;
    return -1;
}

double fit_motion_duration(fit_motion m)
{
    return (m >= 0 && m < FIT_MOTION_COUNT) ? motion_durations[m] : 1.0;
}

static void set_anat(fit_pose *p, fit_joint j, double x, double y, double z)
{
    float a[3] = {(float)x, (float)y, (float)z};
    fit_joint_from_anatomical(j, a, p->rot[j]);
}

static double pos(double x)
{
    return x > 0.0 ? x : 0.0;
}

static void still(double t, fit_pose *p)
{
    double b = sin(TWO_PI * t / 4.0); /* breathing, 15 breaths a minute */
    set_anat(p, FIT_SPINE, 0.02 * b, 0.0, 0.0);
    set_anat(p, FIT_CHEST, 0.015 * b, 0.0, 0.0);
    p->root[0] = (float)(0.004 * sin(TWO_PI * t / 8.0));
}

static void arm_raise(double t, fit_pose *p)
{
    /* Abduction from the 45 degree A-pose up to 160 degrees and back. */
    double a = (160.0 - 45.0) * 3.141592653589793 / 180.0 * 0.5 * (1.0 - cos(TWO_PI * t / 4.0));
    set_anat(p, FIT_L_SHOULDER, 0.0, 0.0, a);
    set_anat(p, FIT_R_SHOULDER, 0.0, 0.0, -a);
    set_anat(p, FIT_L_CLAVICLE, 0.0, 0.0, 0.1 * a);
    set_anat(p, FIT_R_CLAVICLE, 0.0, 0.0, -0.1 * a);
}

static void turn(double t, fit_pose *p)
{
    set_anat(p, FIT_PELVIS, 0.0, 1.5707963 * sin(TWO_PI * t / 6.0), 0.0);
    set_anat(p, FIT_L_ELBOW, -0.2, 0.0, 0.0);
    set_anat(p, FIT_R_ELBOW, -0.2, 0.0, 0.0);
}

/* Legs and arms of a gait cycle at phase ph, scaled by amplitude env (0 = standing). Returns
 * how far the pelvis must drop so the lower foot stays on the floor. */
static double gait(double ph, double env, double hip_amp, fit_pose *p)
{
    /* Thigh and shin of an average adult, m (motions do not know the shape). */
    const double thigh = 0.43, shin = 0.43;
    double reach = 0.0;
    for (int side = 0; side < 2; ++side) {
        double s = side == 0 ? sin(ph) : -sin(ph), c = side == 0 ? cos(ph) : -cos(ph);
        fit_joint hip = side == 0 ? FIT_L_HIP : FIT_R_HIP;
        fit_joint sh = side == 0 ? FIT_L_SHOULDER : FIT_R_SHOULDER;
        /* Negative hip x swings the leg forward; the knee bends while it swings through (c > 0);
         * the ankle keeps the sole level (the angles of a planar chain add up). */
        double h = -hip_amp * env * s, k = 0.6 * env * pos(c) * pos(c);
        set_anat(p, hip, h, 0.0, 0.0);
        set_anat(p, (fit_joint)(hip + 1), k, 0.0, 0.0);
        set_anat(p, (fit_joint)(hip + 2), fmax(-0.58, -(h + k)), 0.0, 0.0);
        set_anat(p, sh, 0.35 * env * s, 0.0, 0.0); /* arms swing against the legs */
        set_anat(p, (fit_joint)(sh + 1), -0.3 * env, 0.0, 0.0);
        reach = fmax(reach, thigh * cos(h) + shin * cos(h + k));
    }
    return thigh + shin - reach;
}

static void walk(double t, fit_pose *p)
{
    /* In place: march, thigh up and shin back, so the feet leave the floor. */
    double ph = TWO_PI * t / 1.1;
    for (int side = 0; side < 2; ++side) {
        double lift = pos(side == 0 ? sin(ph) : -sin(ph));
        fit_joint hip = side == 0 ? FIT_L_HIP : FIT_R_HIP;
        fit_joint sh = side == 0 ? FIT_L_SHOULDER : FIT_R_SHOULDER;
        set_anat(p, hip, -0.6 * lift, 0.0, 0.0);
        set_anat(p, (fit_joint)(hip + 1), 1.1 * lift, 0.0, 0.0);
        set_anat(p, (fit_joint)(hip + 2), -0.5 * lift, 0.0, 0.0); /* sole level */
        set_anat(p, sh, 0.35 * (side == 0 ? sin(ph) : -sin(ph)), 0.0, 0.0);
        set_anat(p, (fit_joint)(sh + 1), -0.4, 0.0, 0.0);
    }
}

static void fast_swing(double t, fit_pose *p)
{
    /* 1.25 Hz, +-1 rad about the shoulder: peak 7.9 rad/s, over 3 m/s at the wrist. */
    double s = sin(TWO_PI * t / 0.8);
    set_anat(p, FIT_L_SHOULDER, -0.5 + 1.0 * s, 0.0, 0.0);
    set_anat(p, FIT_R_SHOULDER, -0.5 - 1.0 * s, 0.0, 0.0);
    set_anat(p, FIT_L_ELBOW, -0.4 - 0.2 * s, 0.0, 0.0);
    set_anat(p, FIT_R_ELBOW, -0.4 + 0.2 * s, 0.0, 0.0);
}

/* Walks in from x = -2 m (facing +x), turns to the camera, stands, turns and walks out to
 * x = +2 m. Phases: 0-2.5 walk in, 2.5-3 turn, 3-5 stand, 5-5.5 turn, 5.5-8 walk out. */
static void enter_leave(double t, fit_pose *p)
{
    const double half_pi = 1.5707963267948966;
    double x = 0.0, yaw = 0.0, env = 0.0, ph = 0.0;
    if (t < 2.5) {
        double u = t / 2.5;
        x = -2.0 + 2.0 * u * u * (3.0 - 2.0 * u);
        yaw = half_pi;
        env = sin(3.141592653589793 * u);
        ph = TWO_PI * t / 1.0;
    } else if (t < 3.0) {
        yaw = half_pi * (1.0 - (t - 2.5) / 0.5);
    } else if (t < 5.0) {
        yaw = 0.0;
    } else if (t < 5.5) {
        yaw = half_pi * (t - 5.0) / 0.5;
    } else {
        double u = (t - 5.5) / 2.5;
        x = 2.0 * u * u * (3.0 - 2.0 * u);
        yaw = half_pi;
        env = sin(3.141592653589793 * u);
        ph = TWO_PI * (t - 5.5) / 1.0;
    }
    p->root[0] = (float)x;
    set_anat(p, FIT_PELVIS, 0.0, yaw, 0.0);
    p->root[1] = (float)-gait(ph, env, 0.4, p);
}

#define DEG 0.017453292519943295

/* 0 -> 1 over 1.5 s, held until 4.5 s, back to 0 by 6 s (smoothstep ramps). */
static double hold(double t)
{
    double u = t < 1.5 ? t / 1.5 : (t < 4.5 ? 1.0 : (6.0 - t) / 1.5);
    u = u < 0.0 ? 0.0 : u;
    return u * u * (3.0 - 2.0 * u);
}

static void arms_down(double t, fit_pose *p)
{
    /* The A-pose arm is 45 deg from vertical: 39 deg of adduction leaves 6 deg. */
    double a = -39.0 * DEG * hold(t);
    set_anat(p, FIT_L_SHOULDER, 0.0, 0.0, a);
    set_anat(p, FIT_R_SHOULDER, 0.0, 0.0, -a);
}

static void boxing_guard(double t, fit_pose *p)
{
    /* Upper arms forward, in and turned inwards, elbows bent 130 deg: elbows before the ribs,
     * fists 8 cm apart before the chin, the forearms close over the chest (default shape: the
     * wrist joints 4 cm in front of the chest's surface). */
    double u = hold(t);
    for (int side = 0; side < 2; ++side) {
        double sg = side == 0 ? 1.0 : -1.0;
        fit_joint sh = side == 0 ? FIT_L_SHOULDER : FIT_R_SHOULDER;
        set_anat(p, sh, -0.9 * u, sg * -0.5 * u, sg * -0.6 * u);
        set_anat(p, (fit_joint)(sh + 1), -2.3 * u, 0.0, 0.0);
    }
}

/* The trunk turned by total angle a (radians) about anatomical axis k, shared by the spine
 * (55 %) and the chest (45 %) as a real back bends over its length. */
static void trunk(fit_pose *p, int k, double a)
{
    double s[3] = {0, 0, 0}, c[3] = {0, 0, 0};
    s[k] = 0.55 * a;
    c[k] = 0.45 * a;
    set_anat(p, FIT_SPINE, s[0], s[1], s[2]);
    set_anat(p, FIT_CHEST, c[0], c[1], c[2]);
}

static void arms_cross(double t, fit_pose *p)
{
    /* Upper arms forward, in and turned inwards, elbows bent: each forearm lies across the
     * chest toward the other side (default shape: the wrists 11 and 8 cm past the midline), the
     * left one straighter, lower and in front, so that they cross 8 cm apart (measured from the
     * posed joints) instead of passing through each other. */
    double u = hold(t);
    set_anat(p, FIT_L_SHOULDER, -1.0 * u, -1.0 * u, -0.5 * u);
    set_anat(p, FIT_R_SHOULDER, -1.0 * u, 1.0 * u, 0.5 * u);
    set_anat(p, FIT_L_ELBOW, -1.3 * u, 0.0, 0.0);
    set_anat(p, FIT_R_ELBOW, -1.9 * u, 0.0, 0.0);
}

/* Facing the camera (2.5 m away at the root's origin), walks back from 1.5 m to 3.5 m over 4 s
 * and forward again: root z from +1 to -1 m (the wall stands at -1.5). */
static void distance(double t, fit_pose *p)
{
    double u = t < 4.0 ? t / 4.0 : (8.0 - t) / 4.0;
    p->root[2] = (float)(1.0 - 2.0 * u * u * (3.0 - 2.0 * u));
    double env = sin(3.141592653589793 * (t < 4.0 ? t / 4.0 : (t - 4.0) / 4.0));
    p->root[1] = (float)-gait(TWO_PI * t / 1.0, env, 0.3, p);
}

/* Steps 1.3 m to the right (image right: the camera looks along -z), where the image ends 1.39 m
 * from the axis at 2.5 m, so the far half of the body is out of view, stays, steps back. */
static void part_out(double t, fit_pose *p)
{
    p->root[0] = (float)(1.3 * hold(t));
}

void fit_motion_eval(fit_motion m, double t_s, fit_pose *out)
{
    if (!out)
        return;
    memset(out, 0, sizeof(*out));
    if (m < 0 || m >= FIT_MOTION_COUNT)
        return;
    double d = motion_durations[m];
    double t = isfinite(t_s) ? fmod(t_s, d) : 0.0;
    if (t < 0.0)
        t += d;
    switch (m) {
    case FIT_MOTION_STILL:
        still(t, out);
        break;
    case FIT_MOTION_ARM_RAISE:
        arm_raise(t, out);
        break;
    case FIT_MOTION_TURN:
        turn(t, out);
        break;
    case FIT_MOTION_WALK:
        walk(t, out);
        break;
    case FIT_MOTION_FAST_SWING:
        fast_swing(t, out);
        break;
    case FIT_MOTION_ENTER_LEAVE:
        enter_leave(t, out);
        break;
    case FIT_MOTION_ARMS_DOWN:
        arms_down(t, out);
        break;
    case FIT_MOTION_BOXING_GUARD:
        boxing_guard(t, out);
        break;
    case FIT_MOTION_BEND_FORWARD:
        trunk(out, 0, 30.0 * DEG * sin(TWO_PI * t));
        break;
    case FIT_MOTION_BEND_SIDE:
        trunk(out, 2, 20.0 * DEG * sin(TWO_PI * t / 2.0));
        break;
    case FIT_MOTION_TWIST:
        trunk(out, 1, 45.0 * DEG * sin(TWO_PI * t / 2.0));
        break;
    case FIT_MOTION_BEND_FAST:
        trunk(out, 0, 30.0 * DEG * sin(TWO_PI * t / 0.7));
        break;
    case FIT_MOTION_ARMS_CROSS:
        arms_cross(t, out);
        break;
    case FIT_MOTION_DISTANCE:
        distance(t, out);
        break;
    case FIT_MOTION_PART_OUT:
        part_out(t, out);
        break;
    default:
        break;
    }
}
