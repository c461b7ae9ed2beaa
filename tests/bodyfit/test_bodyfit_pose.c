/* Joint limits, skinning and the scripted motions. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "bodyfit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static fit_model *model;
static float *buf_a, *buf_b;

static int setup(void **state)
{
    (void)state;
    char err[256];
    fit_model_desc d = {.shape = fit_shape_default(), .target_vertices = 6000};
    model = fit_model_create(&d, err, sizeof err);
    if (!model) {
        fprintf(stderr, "create failed: %s\n", err);
        return -1;
    }
    buf_a = malloc((size_t)fit_model_vertex_count(model) * 3 * sizeof(float));
    buf_b = malloc((size_t)fit_model_vertex_count(model) * 3 * sizeof(float));
    return (buf_a && buf_b) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    free(buf_a);
    free(buf_b);
    fit_model_destroy(model);
    return 0;
}

/* Deterministic uniform numbers in [-r, r] (a fixed-seed LCG, so failures reproduce). */
static float rnd(unsigned *s, float r)
{
    *s = *s * 1664525u + 1013904223u;
    return r * (2.0f * (float)(*s >> 8) / 16777216.0f - 1.0f);
}

static void assert_within_limits(const fit_pose *p)
{
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        float lo[3], hi[3], a[3];
        fit_joint_limits((fit_joint)j, lo, hi);
        fit_joint_to_anatomical((fit_joint)j, p->rot[j], a);
        for (int k = 0; k < 3; ++k)
            if (!(a[k] >= lo[k] - 1e-5f && a[k] <= hi[k] + 1e-5f))
                fail_msg("joint %s axis %d = %f outside [%f, %f]", fit_joint_name((fit_joint)j), k,
                         a[k], lo[k], hi[k]);
    }
}

static void test_pose_clamp_enforces_joint_limits(void **state)
{
    (void)state;
    unsigned seed = 12345u;
    for (int n = 0; n < 500; ++n) {
        fit_pose p;
        for (int k = 0; k < 3; ++k)
            p.root[k] = rnd(&seed, 1.0f);
        for (int j = 0; j < FIT_JOINT_COUNT; ++j)
            for (int k = 0; k < 3; ++k)
                p.rot[j][k] = rnd(&seed, 3.0f);
        assert_true(fit_pose_clamp(&p) > 0);
        assert_within_limits(&p);
        assert_int_equal(fit_pose_clamp(&p), 0); /* idempotent */
    }
    fit_pose z;
    memset(&z, 0, sizeof z);
    assert_int_equal(fit_pose_clamp(&z), 0);
    z.rot[FIT_L_KNEE][0] = NAN;
    z.rot[FIT_L_ELBOW][0] = 0.5f; /* the elbow does not hyper-extend this far */
    assert_int_equal(fit_pose_clamp(&z), 2);
    assert_true(z.rot[FIT_L_KNEE][0] == 0.0f);
}

static void test_every_motion_respects_joint_limits(void **state)
{
    (void)state;
    for (int m = 0; m < FIT_MOTION_COUNT; ++m) {
        double d = fit_motion_duration((fit_motion)m);
        for (int i = 0; i <= 400; ++i) {
            fit_pose p;
            fit_motion_eval((fit_motion)m, 2.0 * d * i / 400.0, &p);
            assert_within_limits(&p);
            assert_int_equal(fit_pose_clamp(&p), 0);
        }
    }
}

static void test_zero_pose_reproduces_rest_mesh(void **state)
{
    (void)state;
    fit_pose p;
    memset(&p, 0, sizeof p);
    float joints[FIT_JOINT_COUNT * 3];
    assert_int_equal(fit_model_pose(model, &p, buf_a, joints), 0);
    const float *rest = fit_model_rest_vertices(model), *rj = fit_model_rest_joints(model);
    float worst = 0.0f;
    for (int i = 0; i < fit_model_vertex_count(model) * 3; ++i)
        worst = fmaxf(worst, fabsf(buf_a[i] - rest[i]));
    assert_true(worst < 1e-5f);
    for (int i = 0; i < FIT_JOINT_COUNT * 3; ++i)
        assert_float_equal(joints[i], rj[i], 1e-6f);
}

static void test_weights_sum_to_one_with_few_influences(void **state)
{
    (void)state;
    const float *w = fit_model_weights(model);
    const uint8_t *j = fit_model_weight_joints(model);
    int multi = 0;
    for (int i = 0; i < fit_model_vertex_count(model); ++i) {
        float s = 0.0f;
        int used = 0;
        for (int k = 0; k < FIT_MAX_INFLUENCES; ++k) {
            assert_true(w[i * 4 + k] >= 0.0f);
            assert_true(j[i * 4 + k] < FIT_JOINT_COUNT);
            s += w[i * 4 + k];
            used += w[i * 4 + k] > 0.0f;
        }
        assert_float_equal(s, 1.0f, 1e-5f);
        multi += used > 1;
    }
    /* Smooth across joints: a good share of the vertices blend two or more joints. */
    assert_true(multi > fit_model_vertex_count(model) / 10);
}

static float weight_on(int v, int joint)
{
    const float *w = fit_model_weights(model);
    const uint8_t *j = fit_model_weight_joints(model);
    float s = 0.0f;
    for (int k = 0; k < FIT_MAX_INFLUENCES; ++k)
        if (j[v * 4 + k] == joint)
            s += w[v * 4 + k];
    return s;
}

static void test_rotating_one_joint_moves_only_its_vertices(void **state)
{
    (void)state;
    fit_pose p;
    memset(&p, 0, sizeof p);
    float bend[3] = {-1.2f, 0.0f, 0.0f};
    fit_joint_from_anatomical(FIT_L_ELBOW, bend, p.rot[FIT_L_ELBOW]);
    assert_int_equal(fit_model_pose(model, &p, buf_a, NULL), 0);
    const float *rest = fit_model_rest_vertices(model);
    int moved_owned = 0, owned = 0;
    for (int i = 0; i < fit_model_vertex_count(model); ++i) {
        float d = 0.0f;
        for (int k = 0; k < 3; ++k)
            d = fmaxf(d, fabsf(buf_a[i * 3 + k] - rest[i * 3 + k]));
        float w = weight_on(i, FIT_L_ELBOW) + weight_on(i, FIT_L_WRIST);
        if (w == 0.0f)
            assert_true(d < 1e-5f);
        if (w > 0.5f) {
            ++owned;
            moved_owned += d > 0.01f;
        }
    }
    assert_true(owned > 50);
    assert_true(moved_owned > owned * 9 / 10);
}

/* Bending elbows, shoulders, hips and knees hard: no triangle collapses to nothing or tears
 * into a long sliver (area ratio against the rest mesh stays in a sane band). */
static void test_bending_joints_keeps_triangles_sound(void **state)
{
    (void)state;
    fit_pose p;
    memset(&p, 0, sizeof p);
    const float el[3] = {-1.6f, 0, 0}, sh[3] = {0, 0, 1.2f}, hip[3] = {-1.2f, 0, 0};
    const float kn[3] = {1.6f, 0, 0};
    fit_joint_from_anatomical(FIT_L_ELBOW, el, p.rot[FIT_L_ELBOW]);
    fit_joint_from_anatomical(FIT_L_SHOULDER, sh, p.rot[FIT_L_SHOULDER]);
    fit_joint_from_anatomical(FIT_R_HIP, hip, p.rot[FIT_R_HIP]);
    fit_joint_from_anatomical(FIT_R_KNEE, kn, p.rot[FIT_R_KNEE]);
    assert_int_equal(fit_pose_clamp(&p), 0);
    assert_int_equal(fit_model_pose(model, &p, buf_a, NULL), 0);
    const float *rest = fit_model_rest_vertices(model);
    const int32_t *t = fit_model_triangles(model);
    double lo = 1e9, hi = 0.0;
    for (int i = 0; i < fit_model_triangle_count(model); ++i) {
        double area[2];
        for (int s = 0; s < 2; ++s) {
            const float *v = s ? buf_a : rest;
            const float *a = v + (size_t)t[i * 3] * 3, *b = v + (size_t)t[i * 3 + 1] * 3;
            const float *c = v + (size_t)t[i * 3 + 2] * 3;
            double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2];
            double z = u[0] * w[1] - u[1] * w[0];
            area[s] = sqrt(x * x + y * y + z * z);
        }
        double r = area[1] / area[0];
        lo = fmin(lo, r);
        hi = fmax(hi, r);
    }
    printf("posed / rest triangle area: min %.3f max %.3f\n", lo, hi);
    assert_true(lo > 0.03); /* the groin crease at 70 degrees of hip flexion is the worst */
    assert_true(hi < 8.0);
}

static void test_fast_swing_wrist_reaches_3_m_per_s(void **state)
{
    (void)state;
    const double dt = 1.0 / 240.0;
    double d = fit_motion_duration(FIT_MOTION_FAST_SWING), best = 0.0;
    float prev[FIT_JOINT_COUNT * 3], cur[FIT_JOINT_COUNT * 3];
    fit_pose p;
    for (int i = 0; i * dt <= d; ++i) {
        fit_motion_eval(FIT_MOTION_FAST_SWING, i * dt, &p);
        assert_int_equal(fit_model_pose(model, &p, buf_a, cur), 0);
        if (i > 0) {
            for (int w = 0; w < 2; ++w) {
                int j = w ? FIT_R_WRIST : FIT_L_WRIST;
                double s = 0.0;
                for (int k = 0; k < 3; ++k)
                    s += (cur[j * 3 + k] - prev[j * 3 + k]) * (cur[j * 3 + k] - prev[j * 3 + k]);
                best = fmax(best, sqrt(s) / dt);
            }
        }
        memcpy(prev, cur, sizeof cur);
    }
    printf("fast_swing peak wrist speed %.2f m/s\n", best);
    assert_true(best >= 3.0);
    assert_true(best < 8.0); /* still a human arm */
}

static void test_posing_is_bit_identical_twice(void **state)
{
    (void)state;
    fit_pose p;
    fit_motion_eval(FIT_MOTION_WALK, 0.37, &p);
    float ja[FIT_JOINT_COUNT * 3], jb[FIT_JOINT_COUNT * 3];
    assert_int_equal(fit_model_pose(model, &p, buf_a, ja), 0);
    assert_int_equal(fit_model_pose(model, &p, buf_b, jb), 0);
    assert_memory_equal(buf_a, buf_b, (size_t)fit_model_vertex_count(model) * 3 * sizeof(float));
    assert_memory_equal(ja, jb, sizeof ja);
}

static void test_pose_rejects_nan_and_null(void **state)
{
    (void)state;
    fit_pose p;
    memset(&p, 0, sizeof p);
    p.rot[FIT_HEAD][1] = NAN;
    assert_int_equal(fit_model_pose(model, &p, buf_a, NULL), -FIT_ERR_NAN);
    assert_int_equal(fit_model_pose(model, NULL, buf_a, NULL), -FIT_ERR_ARG);
    assert_int_equal(fit_model_pose(NULL, &p, buf_a, NULL), -FIT_ERR_ARG);
}

static void test_motions_loop_and_have_names(void **state)
{
    (void)state;
    for (int m = 0; m < FIT_MOTION_COUNT; ++m) {
        assert_int_equal(fit_motion_from_name(fit_motion_name((fit_motion)m)), m);
        double d = fit_motion_duration((fit_motion)m);
        fit_pose a, b;
        fit_motion_eval((fit_motion)m, 0.3, &a);
        fit_motion_eval((fit_motion)m, 0.3 + 2.0 * d, &b);
        for (int j = 0; j < FIT_JOINT_COUNT; ++j)
            for (int k = 0; k < 3; ++k)
                assert_float_equal(a.rot[j][k], b.rot[j][k], 1e-5f);
    }
    assert_int_equal(fit_motion_from_name("moonwalk"), -1);
    assert_int_equal(fit_motion_from_name(NULL), -1);
}

/* Direction of the left upper arm, degrees from hanging straight down. */
static double arm_angle(const float *j)
{
    const float *s = j + FIT_L_SHOULDER * 3, *e = j + FIT_L_ELBOW * 3;
    double d[3] = {e[0] - s[0], e[1] - s[1], e[2] - s[2]};
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    return acos(-d[1] / l) * 180.0 / 3.14159265358979;
}

static void test_motions_reach_their_extremes(void **state)
{
    (void)state;
    float j[FIT_JOINT_COUNT * 3];
    fit_pose p;
    fit_motion_eval(FIT_MOTION_ARM_RAISE, 2.0, &p); /* the top of the raise */
    fit_model_pose(model, &p, buf_a, j);
    assert_true(arm_angle(j) > 150.0);
    fit_motion_eval(FIT_MOTION_TURN, 1.5, &p); /* a quarter turn */
    fit_model_pose(model, &p, buf_a, j);
    double dx = j[FIT_L_HIP * 3] - j[FIT_R_HIP * 3],
           dz = j[FIT_L_HIP * 3 + 2] - j[FIT_R_HIP * 3 + 2];
    assert_true(fabs(atan2(dz, dx)) * 180.0 / 3.14159265358979 > 85.0);
    fit_motion_eval(FIT_MOTION_ENTER_LEAVE, 0.0, &p);
    fit_model_pose(model, &p, buf_a, j);
    assert_float_equal(j[FIT_PELVIS * 3], -2.0f, 0.01f);
    fit_motion_eval(FIT_MOTION_ENTER_LEAVE, 4.0, &p); /* standing, facing the camera */
    fit_model_pose(model, &p, buf_a, j);
    assert_float_equal(j[FIT_PELVIS * 3], 0.0f, 0.01f);
    assert_true(j[FIT_L_HIP * 3] > j[FIT_R_HIP * 3]);
    fit_motion_eval(FIT_MOTION_WALK, 0.275, &p); /* left knee up */
    fit_model_pose(model, &p, buf_a, j);
    assert_true(j[FIT_L_ANKLE * 3 + 1] > 0.15f);
}

/* Walking drops the pelvis so the lower foot stays on the floor: no sinking, no floating
 * (the average shape; other shapes are within a couple of centimetres). */
static void test_feet_stay_on_the_floor_while_walking(void **state)
{
    (void)state;
    const fit_motion ms[3] = {FIT_MOTION_WALK, FIT_MOTION_ENTER_LEAVE, FIT_MOTION_STILL};
    for (int m = 0; m < 3; ++m) {
        double d = fit_motion_duration(ms[m]);
        for (int i = 0; i < 120; ++i) {
            fit_pose p;
            fit_motion_eval(ms[m], d * i / 120.0, &p);
            assert_int_equal(fit_model_pose(model, &p, buf_a, NULL), 0);
            float low = buf_a[1];
            for (int k = 1; k < fit_model_vertex_count(model); ++k)
                low = fminf(low, buf_a[k * 3 + 1]);
            if (low < -0.01f || low > 0.02f)
                fail_msg("%s at %.2f s: lowest point %.3f m", fit_motion_name(ms[m]), d * i / 120.0,
                         low);
        }
    }
}

/* Normals are unit length and agree with the faces around them, at rest and posed. */
static void test_normals_are_unit_and_follow_the_faces(void **state)
{
    (void)state;
    float *n = malloc((size_t)fit_model_vertex_count(model) * 3 * sizeof(float));
    assert_non_null(n);
    fit_pose p;
    fit_motion_eval(FIT_MOTION_ARM_RAISE, 1.3, &p);
    assert_int_equal(fit_model_pose(model, &p, buf_a, NULL), 0);
    const float *sets[2] = {fit_model_rest_vertices(model), buf_a};
    for (int s = 0; s < 2; ++s) {
        const float *v = sets[s];
        assert_int_equal(fit_model_normals(model, v, n), 0);
        int nv = fit_model_vertex_count(model), nt = fit_model_triangle_count(model), bad = 0;
        for (int i = 0; i < nv; ++i)
            assert_float_equal(n[i * 3] * n[i * 3] + n[i * 3 + 1] * n[i * 3 + 1] +
                                   n[i * 3 + 2] * n[i * 3 + 2],
                               1.0f, 1e-4f);
        const int32_t *t = fit_model_triangles(model);
        for (int i = 0; i < nt; ++i) {
            const float *a = v + (size_t)t[i * 3] * 3, *b = v + (size_t)t[i * 3 + 1] * 3;
            const float *c = v + (size_t)t[i * 3 + 2] * 3;
            float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            float w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            float f[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                          u[0] * w[1] - u[1] * w[0]};
            for (int k = 0; k < 3; ++k) {
                const float *m = n + (size_t)t[i * 3 + k] * 3;
                bad += f[0] * m[0] + f[1] * m[1] + f[2] * m[2] <= 0.0f;
            }
        }
        assert_true(bad <= nt * 3 / 1000); /* only at the sharpest folds, if anywhere */
    }
    assert_int_equal(fit_model_normals(model, NULL, n), -FIT_ERR_ARG);
    free(n);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pose_clamp_enforces_joint_limits),
        cmocka_unit_test(test_every_motion_respects_joint_limits),
        cmocka_unit_test(test_zero_pose_reproduces_rest_mesh),
        cmocka_unit_test(test_weights_sum_to_one_with_few_influences),
        cmocka_unit_test(test_rotating_one_joint_moves_only_its_vertices),
        cmocka_unit_test(test_bending_joints_keeps_triangles_sound),
        cmocka_unit_test(test_fast_swing_wrist_reaches_3_m_per_s),
        cmocka_unit_test(test_posing_is_bit_identical_twice),
        cmocka_unit_test(test_pose_rejects_nan_and_null),
        cmocka_unit_test(test_motions_loop_and_have_names),
        cmocka_unit_test(test_motions_reach_their_extremes),
        cmocka_unit_test(test_feet_stay_on_the_floor_while_walking),
        cmocka_unit_test(test_normals_are_unit_and_follow_the_faces),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
