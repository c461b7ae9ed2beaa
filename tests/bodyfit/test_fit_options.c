/* The tracker's options shared by tryon-bodyfit and tryon-bench-fit (fit_options.h): each
 * parsed into the tracker's description with its range, --smooth's on/off/Hz, --vertices as
 * --out-vertices, a missing or out-of-range value refused, another option left to the caller. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "fit_options.h"

static void test_options_parsed(void **state)
{
    (void)state;
    fit_tracker_desc d = {0};
    int bad = 0;
    assert_int_equal(fit_tracker_option("--points", "640", &d, &bad), 1);
    assert_int_equal(bad, 0);
    assert_int_equal(d.points, 640);
    assert_int_equal(fit_tracker_option("--iterations", "9", &d, &bad), 1);
    assert_int_equal(d.iterations, 9);
    assert_int_equal(fit_tracker_option("--vertices", "3000", &d, &bad), 1);
    assert_int_equal(d.out_vertices, 3000);
    assert_int_equal(fit_tracker_option("--out-vertices", "4000", &d, &bad), 1);
    assert_int_equal(d.out_vertices, 4000);
    assert_int_equal(fit_tracker_option("--fit-vertices", "2000", &d, &bad), 1);
    assert_int_equal(d.fit_vertices, 2000);
    assert_int_equal(fit_tracker_option("--temporal", "0.01", &d, &bad), 1);
    assert_float_equal(d.temporal, 0.01f, 1e-9f);
    assert_int_equal(fit_tracker_option("--predict", "0", &d, &bad), 1);
    assert_true(d.predict < 0.0f); /* 0: none, which the tracker reads as negative */
    assert_int_equal(fit_tracker_option("--smooth-beta-rot", "6", &d, &bad), 1);
    assert_float_equal(d.smooth_beta_rot, 6.0f, 0.0f);
    assert_int_equal(fit_tracker_option("--smooth-beta-root", "24", &d, &bad), 1);
    assert_float_equal(d.smooth_beta_root, 24.0f, 0.0f);
    assert_int_equal(fit_tracker_option("--smooth-speed-hz", "0.7", &d, &bad), 1);
    assert_float_equal(d.smooth_speed_hz, 0.7f, 0.0f);
    assert_int_equal(fit_tracker_option("--init-iterations", "20", &d, &bad), 1);
    assert_int_equal(d.init_iterations, 20);
    assert_int_equal(fit_tracker_option("--start-turns", "2", &d, &bad), 1);
    assert_int_equal(d.start_turns, 2);
    assert_int_equal(fit_tracker_option("--smooth-doubt-speed", "3.5", &d, &bad), 1);
    assert_float_equal(d.smooth_doubt_mps, 3.5f, 0.0f);
    assert_int_equal(fit_tracker_option("--smooth-doubt-speed", "0", &d, &bad), 1);
    assert_true(d.smooth_doubt_mps < 0.0f); /* 0: no bound, which the tracker reads as negative */
    assert_int_equal(bad, 0);
    assert_int_equal(fit_tracker_option("--smooth-doubt-speed", "-2", &d, &bad), 1);
    assert_int_equal(bad, 1);
}

static void test_smooth_values(void **state)
{
    (void)state;
    fit_tracker_desc d = {0};
    int bad = 0;
    fit_tracker_option("--smooth", "off", &d, &bad);
    assert_true(d.smooth_hz < 0.0f);
    fit_tracker_option("--smooth", "on", &d, &bad);
    assert_float_equal(d.smooth_hz, 0.0f, 0.0f); /* the default cut-off */
    fit_tracker_option("--smooth", "1.5", &d, &bad);
    assert_float_equal(d.smooth_hz, 1.5f, 0.0f);
    fit_tracker_option("--smooth", "0", &d, &bad);
    assert_true(d.smooth_hz < 0.0f);
    assert_int_equal(bad, 0);
    assert_int_equal(fit_tracker_option("--smooth", "maybe", &d, &bad), 1);
    assert_int_equal(bad, 1);
}

static void test_bad_values_and_other_options(void **state)
{
    (void)state;
    fit_tracker_desc d = {0};
    const char *bad_pairs[][2] = {{"--points", "10"},
                                  {"--points", "8x"},
                                  {"--points", ""},
                                  {"--iterations", "0"},
                                  {"--vertices", "999"},
                                  {"--fit-vertices", "70000"},
                                  {"--temporal", "0"},
                                  {"--predict", "3"},
                                  {"--smooth", "-1"},
                                  {"--smooth-beta-rot", "0"},
                                  {"--smooth-beta-root", "nan"},
                                  {"--smooth-speed-hz", "0"},
                                  {"--init-iterations", "0"},
                                  {"--start-turns", "9"},
                                  {"--start-turns", "0"}};
    for (size_t k = 0; k < sizeof bad_pairs / sizeof bad_pairs[0]; ++k) {
        int bad = 0;
        assert_int_equal(fit_tracker_option(bad_pairs[k][0], bad_pairs[k][1], &d, &bad), 1);
        assert_int_equal(bad, 1);
    }
    assert_int_equal(d.points, 0); /* a refused value leaves the field as it was */
    int bad = 0;
    assert_int_equal(fit_tracker_option("--points", NULL, &d, &bad), 1);
    assert_int_equal(bad, 1);
    bad = 0;
    assert_int_equal(fit_tracker_option("--frames", "3", &d, &bad), 0);
    assert_int_equal(fit_tracker_option("--point", "3", &d, &bad), 0);
    assert_int_equal(bad, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_options_parsed),
        cmocka_unit_test(test_smooth_values),
        cmocka_unit_test(test_bad_values_and_other_options),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
