/* Posing: per-joint 3x4 matrices from the pose, one tight linear-blend vertex loop, then the
 * contact pass where parts meet (skin_contact.c). */
#include "body_internal.h"

#include <math.h>

/* Rodrigues' formula, in double so chains of joints stay well inside float precision. */
void body_axis_angle_matrix(const float r[3], double m[9])
{
    double x = r[0], y = r[1], z = r[2];
    double th = sqrt(x * x + y * y + z * z);
    if (th < 1e-12) {
        for (int k = 0; k < 9; ++k)
            m[k] = (k % 4 == 0) ? 1.0 : 0.0;
        return;
    }
    x /= th, y /= th, z /= th;
    double c = cos(th), s = sin(th), t = 1.0 - c;
    m[0] = t * x * x + c, m[1] = t * x * y - s * z, m[2] = t * x * z + s * y;
    m[3] = t * x * y + s * z, m[4] = t * y * y + c, m[5] = t * y * z - s * x;
    m[6] = t * x * z - s * y, m[7] = t * y * z + s * x, m[8] = t * z * z + c;
}

static void mat_mul(const double a[9], const double b[9], double out[9])
{
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            out[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
}

static int pose_finite(const fit_pose *p)
{
    const float *f = p->root;
    for (int k = 0; k < 3; ++k)
        if (!isfinite(f[k]))
            return 0;
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        for (int k = 0; k < 3; ++k)
            if (!isfinite(p->rot[j][k]))
                return 0;
    return 1;
}

/* World rotation and position of every joint (the list orders parents before children). */
void body_joint_transforms(const body_skeleton *sk, const fit_pose *pose, float skin[][12],
                           float *joints_out)
{
    double rot[FIT_JOINT_COUNT][9], pos[FIT_JOINT_COUNT][3];
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        double local[9];
        body_axis_angle_matrix(pose->rot[j], local);
        int p = fit_joint_parent((fit_joint)j);
        const float *J = sk->joint[j];
        if (p < 0) {
            for (int k = 0; k < 9; ++k)
                rot[j][k] = local[k];
            for (int k = 0; k < 3; ++k)
                pos[j][k] = (double)J[k] + (double)pose->root[k];
        } else {
            mat_mul(rot[p], local, rot[j]);
            double d[3] = {(double)J[0] - sk->joint[p][0], (double)J[1] - sk->joint[p][1],
                           (double)J[2] - sk->joint[p][2]};
            for (int k = 0; k < 3; ++k)
                pos[j][k] = pos[p][k] + rot[p][k * 3] * d[0] + rot[p][k * 3 + 1] * d[1] +
                            rot[p][k * 3 + 2] * d[2];
        }
        /* v' = R (v - J) + x: rows [R | x - R J]. */
        for (int r = 0; r < 3; ++r) {
            const double *R = rot[j] + r * 3;
            skin[j][r * 4 + 0] = (float)R[0];
            skin[j][r * 4 + 1] = (float)R[1];
            skin[j][r * 4 + 2] = (float)R[2];
            skin[j][r * 4 + 3] = (float)(pos[j][r] - (R[0] * J[0] + R[1] * J[1] + R[2] * J[2]));
        }
        if (joints_out)
            for (int k = 0; k < 3; ++k)
                joints_out[j * 3 + k] = (float)pos[j][k];
    }
}

static void blend_skin(const fit_model *m, const float skin[][12], float *vertices_out)
{
    const float *rest = m->mesh.v, *wt = m->weight;
    const uint8_t *wj = m->wjoint;
    for (int i = 0, n = m->mesh.nv; i < n; ++i) {
        const float *w = wt + (size_t)i * 4;
        const uint8_t *j = wj + (size_t)i * 4;
        const float *m0 = skin[j[0]], *m1 = skin[j[1]], *m2 = skin[j[2]], *m3 = skin[j[3]];
        float b[12];
        for (int k = 0; k < 12; ++k)
            b[k] = w[0] * m0[k] + w[1] * m1[k] + w[2] * m2[k] + w[3] * m3[k];
        const float *v = rest + (size_t)i * 3;
        float *o = vertices_out + (size_t)i * 3;
        o[0] = b[0] * v[0] + b[1] * v[1] + b[2] * v[2] + b[3];
        o[1] = b[4] * v[0] + b[5] * v[1] + b[6] * v[2] + b[7];
        o[2] = b[8] * v[0] + b[9] * v[1] + b[10] * v[2] + b[11];
    }
}

static int pose_mesh(const fit_model *m, const fit_pose *pose, float *vertices_out,
                     float *joints_out, int contact)
{
    if (!m || !pose || !vertices_out)
        return -FIT_ERR_ARG;
    if (!pose_finite(pose))
        return -FIT_ERR_NAN;
    float skin[FIT_JOINT_COUNT][12];
    body_joint_transforms(&m->sk, pose, skin, joints_out);
    blend_skin(m, skin, vertices_out);
    if (contact)
        body_skin_contact(m, skin, vertices_out);
    return 0;
}

int fit_model_pose(const fit_model *m, const fit_pose *pose, float *vertices_out, float *joints_out)
{
    return pose_mesh(m, pose, vertices_out, joints_out, 1);
}

int fit_model_pose_lbs(const fit_model *m, const fit_pose *pose, float *vertices_out,
                       float *joints_out)
{
    return pose_mesh(m, pose, vertices_out, joints_out, 0);
}

int fit_model_normals(const fit_model *m, const float *vertices, float *normals_out)
{
    if (!m || !vertices || !normals_out)
        return -FIT_ERR_ARG;
    int nv = m->mesh.nv;
    for (int i = 0; i < nv * 3; ++i)
        normals_out[i] = 0.0f;
    /* The cross product's length is twice the area: summing it weights faces by area. */
    for (int t = 0; t < m->mesh.nt; ++t) {
        const int32_t *tr = m->mesh.t + (size_t)t * 3;
        const float *a = vertices + (size_t)tr[0] * 3, *b = vertices + (size_t)tr[1] * 3;
        const float *c = vertices + (size_t)tr[2] * 3;
        float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                      u[0] * w[1] - u[1] * w[0]};
        for (int k = 0; k < 3; ++k)
            for (int e = 0; e < 3; ++e)
                normals_out[(size_t)tr[k] * 3 + e] += n[e];
    }
    for (int i = 0; i < nv; ++i) {
        float *n = normals_out + (size_t)i * 3;
        float l = sqrtf(body_dot(n, n));
        if (!(l > 0.0f))
            return -FIT_ERR_MESH; /* a vertex whose faces cancel: the vertices are degenerate */
        n[0] /= l;
        n[1] /= l;
        n[2] /= l;
    }
    return 0;
}
