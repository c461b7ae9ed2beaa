/* What a motion does to the body (probe.h): the skin's passing through itself, angles. */
#include <math.h>
#include <string.h>

#include "probe.h"

#define PROBE_PI 3.14159265358979f
/* metres: far below the skin offset, far above float rounding in a 2 m scene */
#define PROBE_NUDGES 3
static const float nudge[PROBE_NUDGES][3] = {
    {0, 0, 0}, {3e-5f, 7e-5f, -5e-5f}, {-6e-5f, -4e-5f, 8e-5f}};

int sim_probe_skin_inside(const sim_collider *c, const float *xyz, int nv, const int32_t *tris,
                          int nt, float (*pts)[4], uint8_t *inside)
{
    if (!c || !xyz || !tris || !pts || nv <= 0 || nt <= 0)
        return -SIM_ERR_ARG;
    memset(pts, 0, (size_t)nv * sizeof *pts);
    for (int t = 0; t < nt; t++) {
        const int32_t *f = &tris[t * 3];
        if (f[0] < 0 || f[0] >= nv || f[1] < 0 || f[1] >= nv || f[2] < 0 || f[2] >= nv)
            return -SIM_ERR_ARG;
        const float *a = &xyz[f[0] * 3], *b = &xyz[f[1] * 3], *q = &xyz[f[2] * 3];
        float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float e2[3] = {q[0] - a[0], q[1] - a[1], q[2] - a[2]};
        /* twice the area along the outward normal (counter-clockwise from outside) */
        float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
        for (int k = 0; k < 3; k++)
            for (int d = 0; d < 3; d++)
                pts[f[k]][d] += n[d];
    }
    int count = 0;
#pragma omp parallel for schedule(static) reduction(+ : count)
    for (int i = 0; i < nv; i++) {
        float *p = pts[i];
        float l = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int d = 0; d < 3; d++)
            p[d] = xyz[i * 3 + d] + (l > 0.0f ? SIM_PROBE_SKIN_OFF_M * p[d] / l : 0.0f);
        /* "unsure" (a crossing too near an edge to count) is asked again from points nudged off
           the edge: a regular mesh (a UV sphere) lines its edges up with the ray */
        int in = 1;
        for (int k = 0; k < PROBE_NUDGES && in; k++) {
            float q[3] = {p[0] + nudge[k][0], p[1] + nudge[k][1], p[2] + nudge[k][2]};
            in = !sim_collider_clearly_outside(c, q);
        }
        if (inside)
            inside[i] = (uint8_t)in;
        count += in;
    }
    return count;
}

float sim_probe_angle_deg(const float a[3], const float b[3], const float c[3], const float d[3])
{
    float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    float v[3] = {d[0] - c[0], d[1] - c[1], d[2] - c[2]};
    float nu = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    float nv = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(nu > 0.0f) || !(nv > 0.0f))
        return 0.0f;
    float cs = (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) / (nu * nv);
    cs = cs > 1.0f ? 1.0f : (cs < -1.0f ? -1.0f : cs);
    return acosf(cs) * 180.0f / PROBE_PI;
}
