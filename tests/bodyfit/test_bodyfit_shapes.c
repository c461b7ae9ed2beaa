/* Random shapes across the parameter ranges: accepted ones build and measure right. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "bodyfit.h"

#include <math.h>
#include <string.h>

/* Every parameter within 1 cm of what was asked (girths are the 1 cm; the lengths
 * and height are tighter in test_bodyfit_measure). */
#define GIRTH_TOL 0.01f

/* Shapes drawn across the ranges (fixed seed): every one the validator accepts must build a
 * closed body that measures what was asked. */
static void test_random_valid_shapes_build_and_measure(void **state)
{
    (void)state;
    unsigned seed = 2024u;
    int built = 0;
    for (int n = 0; n < 40 && built < 3; ++n) {
        float a[FIT_SHAPE_PARAMS];
        for (int i = 0; i < FIT_SHAPE_PARAMS; ++i) {
            float lo, hi;
            fit_shape_param_range(i, &lo, &hi);
            seed = seed * 1664525u + 1013904223u;
            a[i] = lo + (hi - lo) * (float)(seed >> 8) / 16777216.0f;
        }
        char err[256];
        fit_model_desc d = {.shape = fit_shape_from_array(a), .target_vertices = 6000};
        fit_model *m = fit_model_create(&d, err, sizeof err);
        if (!m) {
            assert_non_null(strstr(err, "fit shape")); /* rejected for its proportions only */
            continue;
        }
        fit_measurements me;
        assert_int_equal(fit_model_measure(m, &me), 0);
        float got[FIT_SHAPE_PARAMS];
        fit_shape_to_array(&me.shape, got);
        for (int i = 0; i < FIT_SHAPE_PARAMS; ++i)
            if (fabsf(got[i] - a[i]) > GIRTH_TOL)
                fail_msg("shape %d: %s measured %.4f, asked %.4f", n, fit_shape_param_name(i),
                         got[i], a[i]);
        fit_model_destroy(m);
        ++built;
    }
    assert_int_equal(built, 3);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_random_valid_shapes_build_and_measure),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
