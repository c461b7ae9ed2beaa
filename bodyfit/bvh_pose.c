/* BVH forward kinematics and the rotation helpers the retargeting shares. */
#include "mocap.h"

#include <math.h>
#include <string.h>

#define DEG_TO_RAD 0.017453292519943295

void mocap_mat_mul(const double a[9], const double b[9], double out[9])
{
    double r[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r[i * 3 + j] = a[i * 3] * b[j] + a[i * 3 + 1] * b[3 + j] + a[i * 3 + 2] * b[6 + j];
    memcpy(out, r, sizeof r);
}

void mocap_mat_tmul(const double a[9], const double b[9], double out[9])
{
    double r[9];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            r[i * 3 + j] = a[i] * b[j] + a[3 + i] * b[3 + j] + a[6 + i] * b[6 + j];
    memcpy(out, r, sizeof r);
}

void mocap_mat_apply(const double m[9], const double v[3], double out[3])
{
    double r[3];
    for (int i = 0; i < 3; ++i)
        r[i] = m[i * 3] * v[0] + m[i * 3 + 1] * v[1] + m[i * 3 + 2] * v[2];
    memcpy(out, r, sizeof r);
}

/* Shepperd's method: the largest of w, x, y, z first, so no division by a small number. */
void mocap_mat_to_quat(const double m[9], double q[4])
{
    double tr = m[0] + m[4] + m[8];
    if (tr > m[0] && tr > m[4] && tr > m[8]) {
        double s = 2.0 * sqrt(1.0 + tr);
        q[0] = 0.25 * s;
        q[1] = (m[7] - m[5]) / s;
        q[2] = (m[2] - m[6]) / s;
        q[3] = (m[3] - m[1]) / s;
    } else if (m[0] >= m[4] && m[0] >= m[8]) {
        double s = 2.0 * sqrt(fmax(1e-300, 1.0 + m[0] - m[4] - m[8]));
        q[0] = (m[7] - m[5]) / s;
        q[1] = 0.25 * s;
        q[2] = (m[1] + m[3]) / s;
        q[3] = (m[2] + m[6]) / s;
    } else if (m[4] >= m[8]) {
        double s = 2.0 * sqrt(fmax(1e-300, 1.0 + m[4] - m[0] - m[8]));
        q[0] = (m[2] - m[6]) / s;
        q[1] = (m[1] + m[3]) / s;
        q[2] = 0.25 * s;
        q[3] = (m[5] + m[7]) / s;
    } else {
        double s = 2.0 * sqrt(fmax(1e-300, 1.0 + m[8] - m[0] - m[4]));
        q[0] = (m[3] - m[1]) / s;
        q[1] = (m[2] + m[6]) / s;
        q[2] = (m[5] + m[7]) / s;
        q[3] = 0.25 * s;
    }
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; ++k)
        q[k] /= n;
}

void mocap_quat_to_mat(const double q[4], double m[9])
{
    double w = q[0], x = q[1], y = q[2], z = q[3];
    m[0] = 1 - 2 * (y * y + z * z), m[1] = 2 * (x * y - w * z), m[2] = 2 * (x * z + w * y);
    m[3] = 2 * (x * y + w * z), m[4] = 1 - 2 * (x * x + z * z), m[5] = 2 * (y * z - w * x);
    m[6] = 2 * (x * z - w * y), m[7] = 2 * (y * z + w * x), m[8] = 1 - 2 * (x * x + y * y);
}

void mocap_quat_slerp(const double a[4], const double b[4], double t, double out[4])
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    double sb = d < 0.0 ? -1.0 : 1.0; /* the short way round */
    d = fabs(d);
    double wa = 1.0 - t, wb = t;
    if (d < 0.9995) {
        double th = acos(d), s = sin(th);
        wa = sin((1.0 - t) * th) / s;
        wb = sin(t * th) / s;
    }
    double n = 0.0;
    for (int k = 0; k < 4; ++k) {
        out[k] = wa * a[k] + sb * wb * b[k];
        n += out[k] * out[k];
    }
    n = sqrt(n);
    for (int k = 0; k < 4; ++k)
        out[k] /= n;
}

void mocap_quat_to_axis_angle(const double q[4], float rot[3])
{
    double w = q[0] < 0.0 ? -q[0] : q[0], sg = q[0] < 0.0 ? -1.0 : 1.0;
    double s = sqrt(q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    double th = 2.0 * atan2(s, w);
    double f = s > 1e-12 ? sg * th / s : 2.0 * sg; /* small angles: rot = 2 v */
    for (int k = 0; k < 3; ++k)
        rot[k] = (float)(f * q[1 + k]);
}

void mocap_mat_between(const double from[3], const double to[3], double m[9])
{
    double c = from[0] * to[0] + from[1] * to[1] + from[2] * to[2];
    double v[3] = {from[1] * to[2] - from[2] * to[1], from[2] * to[0] - from[0] * to[2],
                   from[0] * to[1] - from[1] * to[0]};
    double q[4] = {1.0 + c, v[0], v[1], v[2]};
    if (c < -0.999999) { /* opposite: half a turn about any axis normal to from */
        double a[3] = {fabs(from[0]) < 0.9 ? 1.0 : 0.0, fabs(from[0]) < 0.9 ? 0.0 : 1.0, 0.0};
        q[0] = 0.0;
        q[1] = from[1] * a[2] - from[2] * a[1];
        q[2] = from[2] * a[0] - from[0] * a[2];
        q[3] = from[0] * a[1] - from[1] * a[0];
    }
    double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int k = 0; k < 4; ++k)
        q[k] /= n;
    mocap_quat_to_mat(q, m);
}

static void axis_rotation(int axis, double deg, double m[9])
{
    double c = cos(deg * DEG_TO_RAD), s = sin(deg * DEG_TO_RAD);
    int a = (axis + 1) % 3, b = (axis + 2) % 3;
    memset(m, 0, 9 * sizeof(double));
    m[axis * 4] = 1.0;
    m[a * 4] = c, m[b * 4] = c;
    m[a * 3 + b] = -s, m[b * 3 + a] = s;
}

/* BVH convention: the rotation channels compose in the file's order (v_parent = R1 R2 R3 v),
 * translation channels add to the offset. */
static void local_transform(const mocap_joint *j, const float *vals, double rot[9], double t[3])
{
    for (int k = 0; k < 3; ++k)
        t[k] = j->offset[k];
    for (int k = 0; k < 9; ++k)
        rot[k] = (k % 4 == 0) ? 1.0 : 0.0;
    for (int i = 0; i < j->channel_count; ++i) {
        double v = vals[j->channel_first + i];
        int c = j->chan[i];
        if (c <= MOCAP_ZPOS) {
            t[c] += v;
        } else {
            double r[9];
            axis_rotation(c - MOCAP_XROT, v, r);
            mocap_mat_mul(rot, r, rot);
        }
    }
}

int fit_bvh_world(const fit_bvh *b, int frame, float *pos, float *rot)
{
    if (!b || !pos || frame < 0 || frame >= b->frames)
        return -FIT_ERR_ARG;
    double g[FIT_BVH_MAX_JOINTS][9], p[FIT_BVH_MAX_JOINTS][3];
    const float *vals = b->values + (size_t)frame * (size_t)b->channels;
    for (int j = 0; j < b->joint_count; ++j) {
        double r[9], t[3];
        local_transform(&b->joint[j], vals, r, t);
        int pa = b->joint[j].parent; /* parents precede children in the file */
        if (pa < 0) {
            memcpy(g[j], r, sizeof r);
            memcpy(p[j], t, sizeof t);
        } else {
            mocap_mat_mul(g[pa], r, g[j]);
            mocap_mat_apply(g[pa], t, p[j]);
            for (int k = 0; k < 3; ++k)
                p[j][k] += p[pa][k];
        }
        for (int k = 0; k < 3; ++k)
            pos[j * 3 + k] = (float)p[j][k];
        if (rot)
            for (int k = 0; k < 9; ++k)
                rot[j * 9 + k] = (float)g[j][k];
    }
    return 0;
}
