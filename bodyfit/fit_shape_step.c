/* The shape's degrees of freedom (fit_shape_q, all but the height's scale) fitted to the
 * points: one Gauss-Newton step a frame on the pose fit's own correspondences, point to the
 * tangent plane of the matched coarse vertex, with the pose held. The derivatives are finite
 * differences of the posed coarse mesh (the shape maps are not linear in every degree, and
 * eight re-posings of the coarse mesh cost about as much as one solver iteration). */
#include "fit_internal.h"

#include <math.h>
#include <string.h>

/* The height's scale is measured, not fitted; the root's translation is fitted with the shape:
 * from the front, a thicker torso is a front surface nearer the camera with the body farther
 * back, and with the pose held the front points would hold the girth where it is. */
#define STEP_SHAPE (FIT_SHAPE_DOF - 1)
#define STEP_DOF   (STEP_SHAPE + 3)
/* Finite-difference steps: 1 % of a ratio, 2 mm of an offset. */
#define STEP_EPS_RATIO  0.01f
#define STEP_EPS_OFFSET 0.002f
/* A weak pull back to the base shape (per unit of ratio squared, per m^2 of offset) against
 * the data term's mean squared residual (about 2e-5 m^2): only what the points do not decide
 * is held by it. */
#define STEP_PRIOR_RATIO  1e-5
#define STEP_PRIOR_OFFSET 1e-3
#define STEP_DAMPING      0.1 /* Levenberg-Marquardt, relative to the diagonal */
/* What a body can be: ratios to the base (leg and arm within about 15 % of the average
 * proportions span the presets), offsets 4 cm of radius (25 cm of girth). */
static const float step_lo[FIT_SHAPE_DOF] = {0.0f, 0.85f, 0.85f,  0.85f, 0.75f,
                                             0.7f, 0.75f, -0.04f, -0.04f};
static const float step_hi[FIT_SHAPE_DOF] = {9.0f,  1.18f, 1.18f, 1.25f, 1.35f,
                                             1.45f, 1.35f, 0.04f, 0.04f};
#define STEP_RATIOS 7 /* a[1..6] are ratios, a[7..8] offsets */

int fit_shape_step(const fit_shape_base *b, fit_model *coarse, const fit_solver *s, fit_pose *pose,
                   const float *points, float gain, float *scratch, fit_shape_q *q)
{
    fit_matches mt = fit_solver_matches(s);
    size_t nv3 = (size_t)b->nv * 3;
    float a[FIT_SHAPE_DOF], eps[FIT_SHAPE_DOF];
    fit_shape_q_to_array(q, a);
    for (int i = 1; i < FIT_SHAPE_DOF; ++i) {
        float ai = a[i];
        eps[i] = i < STEP_RATIOS ? STEP_EPS_RATIO : STEP_EPS_OFFSET;
        a[i] += eps[i];
        fit_shape_q qi = fit_shape_q_from_array(a);
        fit_shape_base_apply(b, coarse, &qi);
        int rc = fit_model_pose_lbs(coarse, pose, scratch + (size_t)(i - 1) * nv3, NULL);
        a[i] = ai;
        if (rc) {
            fit_shape_base_apply(b, coarse, q);
            return rc;
        }
    }
    fit_shape_base_apply(b, coarse, q);
    double A[STEP_DOF * STEP_DOF], g[STEP_DOF];
    memset(A, 0, sizeof A);
    memset(g, 0, sizeof g);
    int n = 0;
    for (int p = 0; p < mt.count; ++p) {
        int v = mt.vertex[p];
        if (v < 0)
            continue;
        const float *x = mt.pos + (size_t)v * 3, *nr = mt.nrm + (size_t)v * 3;
        const float *pt = points + (size_t)p * 3;
        float d[3] = {x[0] - pt[0], x[1] - pt[1], x[2] - pt[2]};
        double r = body_dot(nr, d), J[STEP_DOF], w = mt.weight[p];
        for (int i = 0; i < STEP_SHAPE; ++i) {
            const float *y = scratch + (size_t)i * nv3 + (size_t)v * 3;
            float dy[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
            J[i] = body_dot(nr, dy) / eps[i + 1];
        }
        for (int k = 0; k < 3; ++k)
            J[STEP_SHAPE + k] = nr[k];
        for (int i = 0; i < STEP_DOF; ++i) {
            g[i] -= w * J[i] * r;
            for (int j = 0; j < STEP_DOF; ++j)
                A[i * STEP_DOF + j] += w * J[i] * J[j];
        }
        ++n;
    }
    if (n < STEP_DOF * 4)
        return 0; /* too few points to say anything */
    for (int i = 0; i < STEP_DOF * STEP_DOF; ++i)
        A[i] /= n;
    for (int i = 0; i < STEP_DOF; ++i) {
        if (i >= STEP_SHAPE) {
            A[i * STEP_DOF + i] = A[i * STEP_DOF + i] * (1.0 + STEP_DAMPING) + 1e-9;
            g[i] /= n;
            continue;
        }
        int ratio = i + 1 < STEP_RATIOS;
        double prior = ratio ? STEP_PRIOR_RATIO : STEP_PRIOR_OFFSET;
        double rest = ratio ? 1.0 : 0.0;
        g[i] = g[i] / n - prior * (a[i + 1] - rest);
        A[i * STEP_DOF + i] = A[i * STEP_DOF + i] * (1.0 + STEP_DAMPING) + prior;
    }
    if (fit_cholesky_solve(A, g, STEP_DOF))
        return 0; /* nothing to learn from this frame */
    for (int i = 1; i < FIT_SHAPE_DOF; ++i) {
        float v = a[i] + gain * (float)g[i - 1];
        a[i] = v < step_lo[i] ? step_lo[i] : (v > step_hi[i] ? step_hi[i] : v);
    }
    for (int k = 0; k < 3; ++k)
        pose->root[k] += gain * (float)g[STEP_SHAPE + k];
    *q = fit_shape_q_from_array(a);
    fit_shape_base_apply(b, coarse, q);
    return 0;
}
