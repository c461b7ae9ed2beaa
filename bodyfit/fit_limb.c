/* A lost arm found again: an arm that moved farther between two frames than the fit's gate
 * (13 cm in the fast swing) leaves its points unexplained and together; the arm is turned at
 * the shoulder so that it points at them, or its forearm at the elbow, and the fit run again
 * from there (tracker.c keeps whichever explains more). */
#include "fit_internal.h"

#include <math.h>
#include <string.h>

static float dist2(const float *a, const float *b)
{
    float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return body_dot(d, d);
}

static void cross(const float a[3], const float b[3], float out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* Turns joint j, and everything below it, by angle about the world axis (unit). */
static void limb_turn(const fit_model *m, fit_pose *pose, int j, const float axis[3], float angle)
{
    double step[FIT_POSE_PARAMS];
    memset(step, 0, sizeof step);
    for (int k = 0; k < 3; ++k)
        step[3 + 3 * j + k] = angle * axis[k];
    fit_pose_apply_step(m, pose, step);
}

/* Turns joint j so that the line from joint j to joint tip points at target (the shortest
 * turn). */
static void limb_aim(const fit_model *m, fit_pose *pose, int j, int tip, const float target[3])
{
    float skin[FIT_JOINT_COUNT][12], jt[FIT_JOINT_COUNT * 3];
    body_joint_transforms(&m->sk, pose, skin, jt);
    const float *s = jt + j * 3, *w = jt + tip * 3;
    float u[3] = {w[0] - s[0], w[1] - s[1], w[2] - s[2]};
    float v[3] = {target[0] - s[0], target[1] - s[1], target[2] - s[2]}, axis[3];
    float lu = sqrtf(body_dot(u, u)), lv = sqrtf(body_dot(v, v));
    if (!(lu > 1e-4f) || !(lv > 1e-4f))
        return;
    cross(u, v, axis);
    float la = sqrtf(body_dot(axis, axis));
    if (!(la > 1e-9f))
        return;
    for (int k = 0; k < 3; ++k)
        axis[k] /= la;
    limb_turn(m, pose, j, axis, atan2f(la / (lu * lv), body_dot(u, v) / (lu * lv)));
}

int fit_limb_nearest_shoulder(const fit_model *m, const fit_pose *pose, const float target[3])
{
    float skin[FIT_JOINT_COUNT][12], j[FIT_JOINT_COUNT * 3];
    body_joint_transforms(&m->sk, pose, skin, j);
    return dist2(j + FIT_L_SHOULDER * 3, target) < dist2(j + FIT_R_SHOULDER * 3, target)
               ? FIT_L_SHOULDER
               : FIT_R_SHOULDER;
}

void fit_limb_reaim(const fit_model *m, fit_pose *pose, int sh, const float target[3])
{
    limb_aim(m, pose, sh, sh + 2, target); /* shoulder, elbow, wrist follow each other */
    fit_pose_clamp(pose);
}

void fit_limb_reaim_forearm(const fit_model *m, fit_pose *pose, int sh, const float target[3])
{
    float skin[FIT_JOINT_COUNT][12], j[FIT_JOINT_COUNT * 3];
    int el = sh + 1, wr = sh + 2;
    body_joint_transforms(&m->sk, pose, skin, j);
    const float *s = j + sh * 3, *e = j + el * 3, *w = j + wr * 3;
    float u[3] = {e[0] - s[0], e[1] - s[1], e[2] - s[2]};
    float f[3] = {w[0] - e[0], w[1] - e[1], w[2] - e[2]};
    float v[3] = {target[0] - e[0], target[1] - e[1], target[2] - e[2]};
    float lu = sqrtf(body_dot(u, u));
    if (lu > 1e-4f) {
        /* the upper arm twisted about itself brings the elbow's bend into the target's plane:
         * the angle from f to v, both taken normal to the upper arm */
        for (int k = 0; k < 3; ++k)
            u[k] /= lu;
        float fu = body_dot(f, u), vu = body_dot(v, u), pf[3], pv[3], c[3];
        for (int k = 0; k < 3; ++k)
            pf[k] = f[k] - fu * u[k], pv[k] = v[k] - vu * u[k];
        cross(pf, pv, c);
        limb_turn(m, pose, sh, u, atan2f(body_dot(c, u), body_dot(pf, pv)));
    }
    limb_aim(m, pose, el, wr, target); /* then the elbow bent, in that plane */
    fit_pose_clamp(pose);
}
