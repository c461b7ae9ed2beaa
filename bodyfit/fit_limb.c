/* A lost arm found again: an arm that moved farther between two frames than the fit's gate
 * (13 cm in the fast swing) leaves its points unexplained and together; the arm is turned at
 * the shoulder so that it points at them, and the fit run again from there (tracker.c keeps
 * whichever explains more). */
#include "fit_internal.h"

#include <math.h>
#include <string.h>

static float dist2(const float *a, const float *b)
{
    float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return body_dot(d, d);
}

int fit_limb_reaim(const fit_model *m, fit_pose *pose, const float target[3])
{
    float skin[FIT_JOINT_COUNT][12], j[FIT_JOINT_COUNT * 3];
    body_joint_transforms(&m->sk, pose, skin, j);
    int sh = dist2(j + FIT_L_SHOULDER * 3, target) < dist2(j + FIT_R_SHOULDER * 3, target)
                 ? FIT_L_SHOULDER
                 : FIT_R_SHOULDER;
    int wr = sh + 2; /* shoulder, elbow, wrist follow each other in FIT_JOINT_LIST */
    const float *s = j + sh * 3, *w = j + wr * 3;
    float u[3] = {w[0] - s[0], w[1] - s[1], w[2] - s[2]};
    float v[3] = {target[0] - s[0], target[1] - s[1], target[2] - s[2]};
    float lu = sqrtf(body_dot(u, u)), lv = sqrtf(body_dot(v, v));
    if (!(lu > 1e-4f) || !(lv > 1e-4f))
        return sh;
    float axis[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2],
                     u[0] * v[1] - u[1] * v[0]};
    float sn = sqrtf(body_dot(axis, axis)) / (lu * lv), cs = body_dot(u, v) / (lu * lv);
    float angle = atan2f(sn, cs), la = sqrtf(body_dot(axis, axis));
    if (!(la > 1e-9f))
        return sh;
    double step[FIT_POSE_PARAMS];
    memset(step, 0, sizeof step);
    for (int k = 0; k < 3; ++k)
        step[3 + 3 * sh + k] = angle * axis[k] / la;
    fit_pose_apply_step(m, pose, step);
    fit_pose_clamp(pose);
    return sh;
}
