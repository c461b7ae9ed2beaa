/* The published pose's One Euro filter (bodyfit/fit_smooth.c): a still pose with noise comes
 * out still, a step is followed within a few frames, a reset passes the next pose through. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fit_smooth.h"
#include "fit_track.h"

/* Uniform in -1..1, a fixed stream (the test is deterministic). */
static float noise(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return (float)((*s >> 8) & 0xffff) / 32767.5f - 1.0f;
}

/* Every joint at the middle of its range: noise around it stays inside the limits. */
static void mid_pose(fit_pose *p)
{
    memset(p, 0, sizeof *p);
    p->root[1] = 0.9f;
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        float lo[3], hi[3], a[3];
        fit_joint_limits((fit_joint)j, lo, hi);
        for (int k = 0; k < 3; ++k)
            a[k] = 0.5f * (lo[k] + hi[k]);
        fit_joint_from_anatomical((fit_joint)j, a, p->rot[j]);
    }
}

/* Squared distance between two poses, root in m, rotations in rad, summed. */
static double pose_d2(const fit_pose *a, const fit_pose *b, int root)
{
    double s = 0.0;
    for (int k = 0; k < 3; ++k) {
        if (root) {
            double d = a->root[k] - b->root[k];
            s += d * d;
        } else
            for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
                double d = a->rot[j][k] - b->rot[j][k];
                s += d * d;
            }
    }
    return s;
}

/* 7 mm and 0.02 rad of noise a frame on a body standing still (the 800-point fit's; the
 * 400-point fit had 10 mm and 0.03 rad, where the speed estimate at 1.5 Hz leaves 0.27 of the
 * input's motion): the frame-to-frame motion of what is published is under a quarter of the
 * input's (4.5 -> 1.2 mm of jitter on still_s0). */
static void test_still_noise_is_smoothed(void **state)
{
    (void)state;
    fit_smoother s;
    fit_smoother_init(&s, NULL);
    fit_pose truth, in, out, last_in, last_out;
    mid_pose(&truth);
    unsigned seed = 11;
    double in_root = 0, out_root = 0, in_rot = 0, out_rot = 0;
    for (int f = 0; f < 300; ++f) {
        in = truth;
        for (int k = 0; k < 3; ++k)
            in.root[k] += 0.007f * noise(&seed);
        for (int j = 0; j < FIT_JOINT_COUNT; ++j)
            for (int k = 0; k < 3; ++k)
                in.rot[j][k] += 0.02f * noise(&seed);
        fit_smoother_step(&s, &in, &out);
        if (f >= 30) { /* after the filter has settled */
            in_root += pose_d2(&in, &last_in, 1), out_root += pose_d2(&out, &last_out, 1);
            in_rot += pose_d2(&in, &last_in, 0), out_rot += pose_d2(&out, &last_out, 0);
        }
        last_in = in, last_out = out;
    }
    assert_true(in_root > 0.0 && in_rot > 0.0);
    assert_true(sqrt(out_root / in_root) < 0.25);
    printf("ratios root %.3f rot %.3f\n", sqrt(out_root / in_root), sqrt(out_rot / in_rot));
    assert_true(sqrt(out_rot / in_rot) < 0.25);
    /* and it stays where the body is: no drift */
    assert_true(sqrt(pose_d2(&out, &truth, 1)) < 0.01);
}

/* Frames until every root component is within 5 mm and every rotation within 0.01 rad of a step
 * of root_step_m and 0.4 rad; 100 if never. */
static int frames_to_follow(const fit_smooth_desc *d, float pelvis_lever_m, float root_step_m)
{
    fit_smoother s;
    fit_smoother_init(&s, d);
    float lever[FIT_JOINT_COUNT];
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        lever[j] = 1.0f;
    lever[FIT_PELVIS] = pelvis_lever_m;
    fit_smoother_set_levers(&s, lever);
    fit_pose a, b, out;
    mid_pose(&a);
    b = a;
    b.root[0] += root_step_m;
    b.rot[FIT_PELVIS][1] += 0.4f;
    for (int f = 0; f < 10; ++f)
        fit_smoother_step(&s, &a, &out);
    for (int f = 1; f <= 100; ++f) {
        fit_smoother_step(&s, &b, &out);
        if (fabsf(out.root[0] - b.root[0]) < 0.005f &&
            fabsf(out.rot[FIT_PELVIS][1] - b.rot[FIT_PELVIS][1]) < 0.01f)
            return f;
    }
    return 100;
}

/* The speed raises the cut-off: the defaults follow a step within 10 frames (a third of a
 * second); the same filter held at its resting cut-off (a tiny beta) would not; a joint with a
 * short reach opens it later, unless the whole body moves (the root's speed opens it too). */
static void test_step_is_followed(void **state)
{
    (void)state;
    int adaptive = frames_to_follow(NULL, 1.0f, 0.3f);
    fit_smooth_desc slow = {.beta_root = 1e-6f, .beta_rot = 1e-6f};
    int fixed = frames_to_follow(&slow, 1.0f, 0.3f);
    /* the same turn of a joint that reaches 5 cm (a hand) is smoothed longer */
    int long_lever = frames_to_follow(NULL, 1.0f, 0.0f);
    int short_lever = frames_to_follow(NULL, 0.05f, 0.0f);
    int short_with_body = frames_to_follow(NULL, 0.05f, 0.3f);
    print_message("step followed in %d frames (a fixed %.1f Hz low-pass: %d); a turn alone: %d "
                  "frames, %d with a 5 cm reach, %d when the body moves 0.3 m with it\n",
                  adaptive, (double)FIT_SMOOTH_MIN_CUTOFF_HZ, fixed, long_lever, short_lever,
                  short_with_body);
    assert_true(adaptive <= 10);
    assert_true(fixed > 20);
    assert_true(short_lever > long_lever);
    assert_true(short_with_body < short_lever);
}

static void test_reset_passes_through(void **state)
{
    (void)state;
    fit_smoother s;
    fit_smoother_init(&s, NULL);
    fit_pose a, b, out;
    mid_pose(&a);
    b = a;
    b.root[2] += 1.0f;
    fit_smoother_step(&s, &a, &out);
    fit_smoother_step(&s, &b, &out);
    assert_true(out.root[2] < b.root[2] - 0.01f); /* filtered */
    fit_smoother_reset(&s);
    fit_smoother_step(&s, &b, &out);
    assert_float_equal(out.root[2], b.root[2], 0.0);
    assert_memory_equal(&out, &b, sizeof out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_still_noise_is_smoothed),
        cmocka_unit_test(test_step_is_followed),
        cmocka_unit_test(test_reset_passes_through),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
