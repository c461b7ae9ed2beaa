/* The BVH reader on the shipped CMU and boxing clips and on malformed text. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "bodyfit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BVH_DIR "/usr/share/assimp/models/BVH/"

/* A two-joint file whose answers follow by hand: the root turned 90 degrees about z. */
static const char good[] = "HIERARCHY\n"      /* 1 */
                           "ROOT Hips\n"      /* 2 */
                           "{\n"              /* 3 */
                           "  OFFSET 0 0 0\n" /* 4 */
                           "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation "
                           "Yrotation\n"                                    /* 5 */
                           "  JOINT Arm\n"                                  /* 6 */
                           "  {\n"                                          /* 7 */
                           "    OFFSET 1 0 0\n"                             /* 8 */
                           "    CHANNELS 3 Zrotation Xrotation Yrotation\n" /* 9 */
                           "    End Site\n"                                 /* 10 */
                           "    {\n"                                        /* 11 */
                           "      OFFSET 2 0 0\n"                           /* 12 */
                           "    }\n"                                        /* 13 */
                           "  }\n"                                          /* 14 */
                           "}\n"                                            /* 15 */
                           "MOTION\n"                                       /* 16 */
                           "Frames: 2\n"                                    /* 17 */
                           "Frame Time: 0.5\n"                              /* 18 */
                           "0 1 0 90 0 0 0 0 0\n"                           /* 19 */
                           "0 1 0 0 0 0 0 0 0\n";                           /* 20 */

static void test_bvh_reads_a_hand_checked_file(void **state)
{
    (void)state;
    fit_bvh *b = NULL;
    char err[256];
    assert_int_equal(fit_bvh_parse(good, strlen(good), "t.bvh", &b, err, sizeof err), 0);
    assert_int_equal(fit_bvh_joint_count(b), 2);
    assert_int_equal(fit_bvh_frame_count(b), 2);
    assert_true(fabs(fit_bvh_frame_time(b) - 0.5) < 1e-12);
    assert_int_equal(fit_bvh_find_joint(b, "Arm"), 1);
    assert_int_equal(fit_bvh_joint_parent(b, 1), 0);
    float p[6], r[18];
    assert_int_equal(fit_bvh_world(b, 0, p, r), 0);
    /* Rz(90) takes the arm's offset (1, 0, 0) to (0, 1, 0), above the hips at (0, 1, 0). */
    assert_true(fabsf(p[3]) < 1e-6f && fabsf(p[4] - 2.0f) < 1e-6f && fabsf(p[5]) < 1e-6f);
    assert_int_equal(fit_bvh_world(b, 1, p, NULL), 0);
    assert_true(fabsf(p[3] - 1.0f) < 1e-6f && fabsf(p[4] - 1.0f) < 1e-6f);
    assert_int_equal(fit_bvh_world(b, 2, p, NULL), -FIT_ERR_ARG);
    fit_bvh_destroy(b);
}

/* A malformed variant of good: one substring replaced; the refusal must name line. */
typedef struct bad_case {
    const char *from, *to;
    int line;
} bad_case;

static void test_bvh_refuses_malformed_text_with_its_line(void **state)
{
    (void)state;
    static const bad_case cases[] = {
        {"HIERARCHY", "HIERARCH", 1},
        {"ROOT Hips", "ROOT", 3},
        {"Xposition Y", "Wposition Y", 5},
        {"CHANNELS 3", "CHANNELS 7", 9},
        {"CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 3 Zrotation Xrotation Xrotation", 9},
        {"OFFSET 1 0 0", "OFFSET 1 x 0", 8},
        {"  JOINT Arm\n  {", "  JOINT Arm\n  (", 7},
        {"Frames: 2", "Frames: 0", 17},
        {"Frames: 2", "Frames: 2.5", 17},
        {"Time: 0.5", "Time: 0", 18},
        {"0 1 0 0 0 0 0 0 0\n", "0 1 0 0 0 0 0 0\n", 20},
        {"0 1 0 90 0 0 0 0 0\n", "0 1 0 90 0 0 0 0 x\n", 19},
        {"0 1 0 90", "0 nan 0 90", 19},
        {"0 1 0 90", "0 1e300 0 90", 19},
        {"Frames: 2", "Frames: 400000", 17},
        {"    End Site", "    End Sight", 10},
        {"MOTION", "MOTIONS", 16},
    };
    char text[1024], err[256];
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        const char *at = strstr(good, cases[i].from);
        assert_non_null(at);
        size_t pre = (size_t)(at - good);
        snprintf(text, sizeof text, "%.*s%s%s", (int)pre, good, cases[i].to,
                 at + strlen(cases[i].from));
        fit_bvh *b = (fit_bvh *)1;
        int rc = fit_bvh_parse(text, strlen(text), "t.bvh", &b, err, sizeof err);
        char want[32];
        snprintf(want, sizeof want, "t.bvh:%d: ", cases[i].line);
        if (rc != -FIT_ERR_PARSE || strncmp(err, want, strlen(want)) != 0)
            fail_msg("case %zu (%s -> %s): rc %d, '%s', wanted '%s...'", i, cases[i].from,
                     cases[i].to, rc, err, want);
        assert_null(b);
    }
    /* Truncated anywhere in the hierarchy or the motion: refused, never read past the end. */
    for (size_t n = 0; n + 1 < sizeof good - 1; ++n) {
        fit_bvh *b = NULL;
        int rc = fit_bvh_parse(good, n, "t.bvh", &b, err, sizeof err);
        if (rc == 0) { /* cut inside the last value's digits still parses: a shorter number */
            assert_true(n >= sizeof good - 4);
            fit_bvh_destroy(b);
        } else {
            assert_int_equal(rc, -FIT_ERR_PARSE);
            assert_null(b);
        }
    }
}

static void test_bvh_refuses_too_many_joints(void **state)
{
    (void)state;
    size_t cap = 64 * 1024;
    char *t = malloc(cap), err[256];
    assert_non_null(t);
    size_t n = (size_t)snprintf(t, cap, "HIERARCHY\nROOT r\n{\nOFFSET 0 0 0\nCHANNELS 0\n");
    for (int i = 0; i < FIT_BVH_MAX_JOINTS + 4; ++i)
        n += (size_t)snprintf(t + n, cap - n, "JOINT j%d\n{\nOFFSET 0 1 0\nCHANNELS 0\n", i);
    fit_bvh *b = NULL;
    assert_int_equal(fit_bvh_parse(t, n, "deep.bvh", &b, err, sizeof err), -FIT_ERR_PARSE);
    assert_non_null(strstr(err, "more than 256 joints"));
    assert_null(b);
    free(t);
}

typedef struct clip_case {
    const char *file;
    int joints, frames;
    double frame_time;
} clip_case;

static void test_bvh_reads_the_shipped_clips(void **state)
{
    (void)state;
    static const clip_case cases[] = {
        {BVH_DIR "01_01.bvh", 31, 2752, 0.0083333},
        {BVH_DIR "01_03.bvh", 31, 4511, 0.0083333},
        {BVH_DIR "Boxing_Toes.bvh", 21, 3069, 0.01},
    };
    char err[256];
    for (size_t i = 0; i < 3; ++i) {
        fit_bvh *b = NULL;
        int rc = fit_bvh_load(cases[i].file, &b, err, sizeof err);
        if (rc)
            fail_msg("%s: %s", cases[i].file, err);
        assert_int_equal(fit_bvh_joint_count(b), cases[i].joints);
        assert_int_equal(fit_bvh_frame_count(b), cases[i].frames);
        assert_true(fabs(fit_bvh_frame_time(b) - cases[i].frame_time) < 1e-9);
        fit_bvh_destroy(b);
    }
}

/* 01_01's first frame: hips at (9.3722, 17.8693, -17.3198) unturned, the left thigh turned
 * -17 degrees about z. LeftUpLeg = hips + (1.36306, -1.79463, 0.83929); LeftLeg adds
 * Rz(-17) (2.44811, -6.72613, 0) = (0.37461, -7.14799, 0), worked by hand. Bone lengths stay
 * those of the offsets in every frame. */
static void test_bvh_known_joint_positions(void **state)
{
    (void)state;
    char err[256];
    fit_bvh *b = NULL;
    assert_int_equal(fit_bvh_load(BVH_DIR "01_01.bvh", &b, err, sizeof err), 0);
    int up = fit_bvh_find_joint(b, "LeftUpLeg"), leg = fit_bvh_find_joint(b, "LeftLeg");
    assert_true(up > 0 && leg > up);
    float *p = malloc((size_t)fit_bvh_joint_count(b) * 3 * sizeof(float));
    assert_non_null(p);
    assert_int_equal(fit_bvh_world(b, 0, p, NULL), 0);
    const float want_up[3] = {10.73526f, 16.07467f, -16.48051f};
    const float want_leg[3] = {11.10987f, 8.92668f, -16.48051f};
    for (int k = 0; k < 3; ++k) {
        assert_true(fabsf(p[up * 3 + k] - want_up[k]) < 1e-3f);
        assert_true(fabsf(p[leg * 3 + k] - want_leg[k]) < 1e-3f);
    }
    const double thigh = sqrt(2.44811 * 2.44811 + 6.72613 * 6.72613);
    for (int f = 0; f < fit_bvh_frame_count(b); f += 97) {
        assert_int_equal(fit_bvh_world(b, f, p, NULL), 0);
        double d = 0.0;
        for (int k = 0; k < 3; ++k)
            d += (p[leg * 3 + k] - p[up * 3 + k]) * (p[leg * 3 + k] - p[up * 3 + k]);
        assert_true(fabs(sqrt(d) - thigh) < 1e-3);
    }
    free(p);
    fit_bvh_destroy(b);
    assert_int_equal(fit_bvh_load("/nonexistent/x.bvh", &b, err, sizeof err), -FIT_ERR_IO);
    assert_non_null(strstr(err, "/nonexistent/x.bvh"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bvh_reads_a_hand_checked_file),
        cmocka_unit_test(test_bvh_refuses_malformed_text_with_its_line),
        cmocka_unit_test(test_bvh_refuses_too_many_joints),
        cmocka_unit_test(test_bvh_reads_the_shipped_clips),
        cmocka_unit_test(test_bvh_known_joint_positions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
