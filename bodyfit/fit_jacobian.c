/* Derivatives of linear-blend skinning with respect to the pose, and applying a step.
 *
 * A vertex is v = sum_i w_i (R_i v0 + t_i) over its influences i. Turning joint k and all below
 * it by a small world rotation delta about its centre X_k moves each term by delta x (q_i - X_k)
 * (q_i = R_i v0 + t_i) when joint i is k or below k; so dv/d(delta_k) applied to delta is
 * delta x b_k with b_k = sum_{i below k} w_i (q_i - X_k): the articulated-ICP Jacobian
 * (Pellegrini et al. 2008), exact for the skinning here. */
#include "fit_internal.h"

#include <math.h>
#include <string.h>

void fit_vertex_sparse(const fit_model *m, const float skin[][12], const float *joints, int v,
                       fit_vjac *out)
{
    const float *v0 = m->mesh.v + (size_t)v * 3;
    const uint8_t *wj = m->wjoint + (size_t)v * FIT_MAX_INFLUENCES;
    const float *ww = m->weight + (size_t)v * FIT_MAX_INFLUENCES;
    float acc[FIT_JOINT_COUNT][4]; /* sum w q, sum w */
    out->n = 0;
    out->pos[0] = out->pos[1] = out->pos[2] = 0.0f;
    for (int i = 0; i < FIT_MAX_INFLUENCES; ++i) {
        float w = ww[i];
        if (w == 0.0f)
            continue;
        const float *s = skin[wj[i]];
        float q[3];
        for (int r = 0; r < 3; ++r)
            q[r] = s[r * 4] * v0[0] + s[r * 4 + 1] * v0[1] + s[r * 4 + 2] * v0[2] + s[r * 4 + 3];
        for (int r = 0; r < 3; ++r)
            out->pos[r] += w * q[r];
        for (int k = wj[i]; k >= 0; k = fit_joint_parent((fit_joint)k)) {
            int slot = -1;
            for (int e = 0; e < out->n; ++e)
                if (out->joint[e] == k)
                    slot = e;
            if (slot < 0) {
                slot = out->n++;
                out->joint[slot] = k;
                memset(acc[slot], 0, sizeof acc[slot]);
            }
            for (int r = 0; r < 3; ++r)
                acc[slot][r] += w * q[r];
            acc[slot][3] += w;
        }
    }
    for (int e = 0; e < out->n; ++e) {
        const float *X = joints + out->joint[e] * 3;
        for (int r = 0; r < 3; ++r)
            out->b[e][r] = acc[e][r] - acc[e][3] * X[r];
    }
}

int fit_vertex_jacobian(const fit_model *m, const fit_pose *pose, int vertex, float pos_out[3],
                        double *jac)
{
    if (!m || !pose || !jac || vertex < 0 || vertex >= m->mesh.nv)
        return -FIT_ERR_ARG;
    float skin[FIT_JOINT_COUNT][12], joints[FIT_JOINT_COUNT * 3];
    body_joint_transforms(&m->sk, pose, skin, joints);
    fit_vjac vj;
    fit_vertex_sparse(m, skin, joints, vertex, &vj);
    memset(jac, 0, 3 * FIT_POSE_PARAMS * sizeof *jac);
    for (int r = 0; r < 3; ++r)
        jac[r * FIT_POSE_PARAMS + r] = 1.0;
    /* delta x b = -b x delta: column c of joint k is e_c x b. */
    for (int e = 0; e < vj.n; ++e) {
        const float *b = vj.b[e];
        int c0 = 3 + 3 * vj.joint[e];
        jac[0 * FIT_POSE_PARAMS + c0 + 1] = b[2], jac[0 * FIT_POSE_PARAMS + c0 + 2] = -b[1];
        jac[1 * FIT_POSE_PARAMS + c0 + 0] = -b[2], jac[1 * FIT_POSE_PARAMS + c0 + 2] = b[0];
        jac[2 * FIT_POSE_PARAMS + c0 + 0] = b[1], jac[2 * FIT_POSE_PARAMS + c0 + 1] = -b[0];
    }
    if (pos_out)
        memcpy(pos_out, vj.pos, sizeof vj.pos);
    return 0;
}

void fit_rotation_log(const double m[9], float r[3])
{
    double c = 0.5 * (m[0] + m[4] + m[8] - 1.0);
    c = c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c);
    double th = acos(c);
    double v[3] = {m[7] - m[5], m[2] - m[6], m[3] - m[1]};
    if (th < 1e-6) {
        for (int k = 0; k < 3; ++k)
            r[k] = (float)(0.5 * v[k]);
        return;
    }
    if (th > 3.14159265358979 - 1e-3) {
        /* Near a half turn the skew part vanishes: the axis from the diagonal, sign from v. */
        double a[3];
        for (int k = 0; k < 3; ++k) {
            double d = (m[k * 4] + 1.0) * 0.5;
            a[k] = sqrt(d > 0.0 ? d : 0.0);
        }
        int big = a[0] > a[1] ? (a[0] > a[2] ? 0 : 2) : (a[1] > a[2] ? 1 : 2);
        for (int k = 0; k < 3; ++k)
            if (k != big)
                a[k] = (m[big * 3 + k] + m[k * 3 + big]) / (4.0 * a[big]);
        double sg = (a[0] * v[0] + a[1] * v[1] + a[2] * v[2]) < 0.0 ? -1.0 : 1.0;
        for (int k = 0; k < 3; ++k)
            r[k] = (float)(sg * th * a[k]);
        return;
    }
    double s = th / (2.0 * sin(th));
    for (int k = 0; k < 3; ++k)
        r[k] = (float)(s * v[k]);
}

static void mat_mul3(const double a[9], const double b[9], double o[9])
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            o[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
}

/* To first order a world rotation delta_k of joint k is the local change exp(G_p^T delta_k)
 * L_k, with G_p the parent's world rotation before the step. */
void fit_pose_apply_step(const fit_model *m, fit_pose *pose, const double *step)
{
    float skin[FIT_JOINT_COUNT][12];
    body_joint_transforms(&m->sk, pose, skin, NULL);
    for (int k = 0; k < 3; ++k)
        pose->root[k] += (float)step[k];
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        const double *d = step + 3 + 3 * j;
        int p = fit_joint_parent((fit_joint)j);
        float dl[3];
        for (int r = 0; r < 3; ++r)
            dl[r] = p < 0 ? (float)d[r]
                          : (float)(skin[p][0 * 4 + r] * d[0] + skin[p][1 * 4 + r] * d[1] +
                                    skin[p][2 * 4 + r] * d[2]);
        double e[9], l[9], o[9];
        body_axis_angle_matrix(dl, e);
        body_axis_angle_matrix(pose->rot[j], l);
        mat_mul3(e, l, o);
        fit_rotation_log(o, pose->rot[j]);
    }
}
