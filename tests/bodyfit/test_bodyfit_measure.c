/* Shapes and measurements: the generated mesh measures what the shape asked for. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "bodyfit.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The tolerances: girths within 1 cm; height within 1 cm (the top vertex sits a
 * fraction of a millimetre under the true crown); lengths come from joint centres, exact. */
#define GIRTH_TOL  0.01f
#define HEIGHT_TOL 0.01f
#define LENGTH_TOL 0.001f

static void check_preset(int i)
{
    char err[256];
    fit_model_desc d = {.shape = fit_shape_preset(i)};
    fit_model *m = fit_model_create(&d, err, sizeof err);
    if (!m)
        fail_msg("%s: %s", fit_shape_preset_name(i), err);
    fit_measurements me;
    assert_int_equal(fit_model_measure(m, &me), 0);
    const fit_shape *w = &d.shape, *g = &me.shape;
    printf("%-12s height %.4f/%.4f chest %.4f/%.4f waist %.4f/%.4f hip %.4f/%.4f arm %.4f/%.4f "
           "thigh %.4f/%.4f\n",
           fit_shape_preset_name(i), g->height, w->height, g->chest_girth, w->chest_girth,
           g->waist_girth, w->waist_girth, g->hip_girth, w->hip_girth, g->arm_girth, w->arm_girth,
           g->leg_girth, w->leg_girth);
    assert_true(fabsf(g->chest_girth - w->chest_girth) < GIRTH_TOL);
    assert_true(fabsf(g->waist_girth - w->waist_girth) < GIRTH_TOL);
    assert_true(fabsf(g->hip_girth - w->hip_girth) < GIRTH_TOL);
    assert_true(fabsf(g->arm_girth - w->arm_girth) < GIRTH_TOL);
    assert_true(fabsf(g->leg_girth - w->leg_girth) < GIRTH_TOL);
    assert_true(fabsf(g->height - w->height) < HEIGHT_TOL);
    assert_true(fabsf(g->shoulder_width - w->shoulder_width) < LENGTH_TOL);
    assert_true(fabsf(g->arm_length - w->arm_length) < LENGTH_TOL);
    assert_true(fabsf(g->leg_length - w->leg_length) < LENGTH_TOL);
    /* Torso slices in the expected order, and the feet on the floor. */
    assert_true(me.hip_y < me.waist_y && me.waist_y < me.chest_y);
    const float *v = fit_model_rest_vertices(m);
    float low = v[1];
    for (int k = 1; k < fit_model_vertex_count(m); ++k)
        low = fminf(low, v[k * 3 + 1]);
    assert_true(low > -0.01f && low < 0.02f);
    fit_model_destroy(m);
}

static void test_average_preset_measures_its_shape(void **state)
{
    (void)state;
    check_preset(0);
}

static void test_slim_tall_preset_measures_its_shape(void **state)
{
    (void)state;
    check_preset(1);
}

static void test_broad_short_preset_measures_its_shape(void **state)
{
    (void)state;
    check_preset(2);
}

static void test_shape_array_round_trips(void **state)
{
    (void)state;
    float a[FIT_SHAPE_PARAMS];
    fit_shape s = fit_shape_preset(2);
    fit_shape_to_array(&s, a);
    fit_shape r = fit_shape_from_array(a);
    assert_memory_equal(&s, &r, sizeof s);
    assert_float_equal(a[0], s.height, 0.0f);
    assert_float_equal(a[8], s.leg_girth, 0.0f);
    assert_string_equal(fit_shape_preset_name(1), "slim_tall");
}

static void test_shape_validation_names_the_parameter(void **state)
{
    (void)state;
    char err[256];
    for (int i = 0; i < FIT_SHAPE_PRESETS; ++i) {
        fit_shape s = fit_shape_preset(i);
        assert_int_equal(fit_shape_validate(&s, err, sizeof err), 0);
    }
    for (int i = 0; i < FIT_SHAPE_PARAMS; ++i) {
        float a[FIT_SHAPE_PARAMS], lo, hi;
        fit_shape s = fit_shape_default();
        fit_shape_to_array(&s, a);
        fit_shape_param_range(i, &lo, &hi);
        a[i] = hi + 0.1f;
        s = fit_shape_from_array(a);
        assert_int_equal(fit_shape_validate(&s, err, sizeof err), -FIT_ERR_RANGE);
        assert_non_null(strstr(err, fit_shape_param_name(i)));
        a[i] = NAN;
        s = fit_shape_from_array(a);
        assert_int_equal(fit_shape_validate(&s, err, sizeof err), -FIT_ERR_NAN);
    }
    assert_int_equal(fit_shape_validate(NULL, err, sizeof err), -FIT_ERR_ARG);
    assert_string_equal(fit_error_string(-FIT_ERR_IO), "file could not be written");
    assert_string_equal(fit_error_string(FIT_ERR_IO), "file could not be written");
    assert_string_equal(fit_error_name(-FIT_ERR_PARSE), "FIT_ERR_PARSE");
    assert_string_equal(fit_error_name(FIT_ERROR_COUNT), "FIT_ERR_UNKNOWN");
}

static void test_validation_rejects_inconsistent_proportions(void **state)
{
    (void)state;
    char err[256];
    fit_shape s = fit_shape_default();
    s.leg_girth = 0.75f; /* two such thighs do not fit in 1 m of hips */
    assert_int_equal(fit_shape_validate(&s, err, sizeof err), 0);
    fit_model_desc d = {.shape = s};
    assert_null(fit_model_create(&d, err, sizeof err));
    assert_non_null(strstr(err, "leg_girth"));
    d.shape = fit_shape_default();
    d.shape.chest_girth = 1.35f; /* wider than the shoulders: the arms would cut in */
    assert_null(fit_model_create(&d, err, sizeof err));
    assert_non_null(strstr(err, "shoulder_width"));
    d.shape = fit_shape_default();
    d.shape.height = 1.40f; /* legs of 0.86 m leave too little torso */
    assert_null(fit_model_create(&d, err, sizeof err));
    assert_non_null(strstr(err, "leg_length"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_average_preset_measures_its_shape),
        cmocka_unit_test(test_slim_tall_preset_measures_its_shape),
        cmocka_unit_test(test_broad_short_preset_measures_its_shape),
        cmocka_unit_test(test_shape_array_round_trips),
        cmocka_unit_test(test_shape_validation_names_the_parameter),
        cmocka_unit_test(test_validation_rejects_inconsistent_proportions),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
