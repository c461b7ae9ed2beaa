/* A lost arm turned towards its points (fit_limb.c): the shoulder nearest them; the arm turned
 * at the shoulder so that its shoulder-to-wrist line points at them; the forearm turned, the
 * elbow staying where it was, so that its elbow-to-wrist line does; inside the joint limits. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "bodyfit.h"
#include "fit_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static fit_model *body;

static int setup(void **state)
{
    (void)state;
    fit_model_desc d = {.shape = fit_shape_default(), .target_vertices = 1500};
    body = fit_model_create(&d, NULL, 0);
    return body ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    fit_model_destroy(body);
    return 0;
}

static void joints_of(const fit_pose *p, float j[FIT_JOINT_COUNT * 3])
{
    float skin[FIT_JOINT_COUNT][12];
    body_joint_transforms(&body->sk, p, skin, j);
}

/* Degrees between the line from joint a to joint b and the line from joint a to target. */
static double aim_error_deg(const float *j, int a, int b, const float target[3])
{
    double u[3], v[3], uu = 0, vv = 0, uv = 0;
    for (int k = 0; k < 3; ++k) {
        u[k] = j[b * 3 + k] - j[a * 3 + k];
        v[k] = target[k] - j[a * 3 + k];
        uu += u[k] * u[k], vv += v[k] * v[k], uv += u[k] * v[k];
    }
    return acos(fmin(1.0, uv / sqrt(uu * vv))) * 180.0 / acos(-1.0);
}

/* The guard (forearms up before the chest) and a target where a punch puts the right fist:
 * 25 cm before the elbow, a little up and inwards. */
static void guard(fit_pose *p, float target[3], float j[FIT_JOINT_COUNT * 3])
{
    fit_motion_eval(FIT_MOTION_BOXING_GUARD, 1.5, p);
    joints_of(p, j);
    const float *e = j + FIT_R_ELBOW * 3;
    target[0] = e[0] + 0.06f, target[1] = e[1] + 0.08f, target[2] = e[2] + 0.25f;
}

static void test_forearm_turned_at_the_elbow(void **state)
{
    (void)state;
    fit_pose p;
    float target[3], j0[FIT_JOINT_COUNT * 3], j1[FIT_JOINT_COUNT * 3];
    guard(&p, target, j0);
    assert_int_equal(fit_limb_nearest_shoulder(body, &p, target), FIT_R_SHOULDER);
    double before = aim_error_deg(j0, FIT_R_ELBOW, FIT_R_WRIST, target);
    fit_limb_reaim_forearm(body, &p, FIT_R_SHOULDER, target);
    joints_of(&p, j1);
    double after = aim_error_deg(j1, FIT_R_ELBOW, FIT_R_WRIST, target), moved = 0.0;
    for (int k = 0; k < 3; ++k)
        moved += (j1[FIT_R_ELBOW * 3 + k] - j0[FIT_R_ELBOW * 3 + k]) *
                 (j1[FIT_R_ELBOW * 3 + k] - j0[FIT_R_ELBOW * 3 + k]);
    printf("# forearm: %.1f degrees off the target before, %.1f after; the elbow moved %.1f mm\n",
           before, after, 1000.0 * sqrt(moved));
    assert_true(before > 30.0);
    assert_true(after < 5.0);
    assert_true(sqrt(moved) < 0.002);
    fit_pose q = p;
    assert_int_equal(fit_pose_clamp(&q), 0); /* inside the limits already */
    /* the other arm is left as it was */
    for (int k = 0; k < 3; ++k)
        assert_true(fabsf(j1[FIT_L_WRIST * 3 + k] - j0[FIT_L_WRIST * 3 + k]) < 1e-5f);
}

static void test_arm_turned_at_the_shoulder(void **state)
{
    (void)state;
    fit_pose p;
    float target[3], j0[FIT_JOINT_COUNT * 3], j1[FIT_JOINT_COUNT * 3];
    guard(&p, target, j0);
    double before = aim_error_deg(j0, FIT_R_SHOULDER, FIT_R_WRIST, target);
    fit_limb_reaim(body, &p, FIT_R_SHOULDER, target);
    joints_of(&p, j1);
    double after = aim_error_deg(j1, FIT_R_SHOULDER, FIT_R_WRIST, target);
    printf("# arm: %.1f degrees off the target before, %.1f after\n", before, after);
    assert_true(after < before);
    assert_true(after < 5.0);
    fit_pose q = p;
    assert_int_equal(fit_pose_clamp(&q), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_forearm_turned_at_the_elbow),
        cmocka_unit_test(test_arm_turned_at_the_shoulder),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
