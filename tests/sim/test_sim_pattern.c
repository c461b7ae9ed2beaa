/* A sewing pattern worn by the sim (sim/outfit_pattern.c): the shipped T-shirt dressed on the body
 * model of the body's shape, carried to the first frame of the model's walk, then simulated on the
 * walk's next frames: finite, no vertex more than 1 mm inside the body. Bodies without the model's
 * parameters and unreadable patterns are refused with the field named. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bodyfit.h"
#include "outfit_pattern.h"
#include "sim.h"

#define FRAMES 8

static void pose_array(const fit_pose *p, float out[FIT_POSE_PARAMS])
{
    memcpy(out, p->root, sizeof p->root);
    memcpy(out + 3, p->rot, sizeof p->rot);
}

/* The pattern at path, size, worn on the walk's first FRAMES frames. */
static void wear_on_walk(const char *path, sim_size size, const char *id)
{
    fit_shape shape = fit_shape_default();
    char err[200];
    fit_model *body = fit_model_create(&(fit_model_desc){.shape = shape}, err, sizeof err);
    assert_non_null(body);
    int nv = fit_model_vertex_count(body), nt = fit_model_triangle_count(body);
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    float joints[FIT_JOINT_COUNT * 3], shape_a[FIT_SHAPE_PARAMS], pose_a[FIT_POSE_PARAMS];
    assert_non_null(xyz);
    fit_shape_to_array(&shape, shape_a);
    fit_pose pose;
    fit_motion_eval(FIT_MOTION_WALK, 0.0, &pose);
    pose_array(&pose, pose_a);

    sim_outfit o;
    sim_reject why = {0};
    assert_int_equal(sim_outfit_resolve(path, size, "", &o, &why), 0);
    assert_true(o.is_pattern);
    assert_string_equal(o.id, id);
    sim_garment g = {0};
    sim_pattern_stats ps;
    int r = sim_outfit_make_pattern(&o, shape_a, FIT_SHAPE_PARAMS, pose_a, FIT_POSE_PARAMS, &g, &ps,
                                    &why);
    if (r != 0)
        fail_msg("%s: %s", sim_error_name(why.code), why.detail);
    assert_true(g.num_vertices > 100 && g.num_triangles > 100);
    print_message("%s dressed in %.0f ms (%.0f ms in all), seams %.1f mm, %d inside\n", id,
                  ps.dress_ms, ps.total_ms, ps.seam_gap_mm, ps.penetrating);

    sim_desc d = sim_default_desc();
    d.backend = SIM_BACKEND_C;
    d.fabric = o.fabric;
    sim *s = sim_create(&d, &g, &why);
    if (!s)
        fail_msg("sim_create: %s", why.detail);
    fit_motion_eval(FIT_MOTION_WALK, 0.0, &pose);
    assert_int_equal(fit_model_pose(body, &pose, xyz, joints), 0);
    assert_int_equal(sim_pattern_settle(s, xyz, nv, fit_model_triangles(body), nt, &why), 0);
    for (int k = 0; k < FRAMES; k++) {
        fit_motion_eval(FIT_MOTION_WALK, k / 30.0, &pose);
        assert_int_equal(fit_model_pose(body, &pose, xyz, joints), 0);
        sim_frame_stats st;
        r = sim_step(s, xyz, nv, fit_model_triangles(body), nt, &st, &why);
        if (r != 0)
            fail_msg("frame %d: %s", k, why.detail);
        print_message("frame %d: %s, %.1f ms, %d inside (max %.2f mm), max strain %.3f\n", k,
                      sim_state_name(st.state), st.ms_total, st.penetrating, st.max_pen_mm,
                      st.max_strain);
        assert_int_equal(st.penetrating, 0);
        assert_true(st.state != SIM_STATE_DIVERGED);
    }
    float *c = malloc((size_t)g.num_vertices * 3 * sizeof *c);
    assert_non_null(c);
    sim_copy_positions(s, c);
    for (int i = 0; i < g.num_vertices * 3; i++)
        assert_true(isfinite(c[i]));
    free(c);
    sim_destroy(s);
    sim_garment_free(&g);
    free(xyz);
    fit_model_destroy(body);
}

static void test_tshirt_walks(void **state)
{
    (void)state;
    wear_on_walk(GAR_PATTERN_DIR "/tshirt.json", SIM_SIZE_M, "tshirt.json M cotton");
}

static void test_skirt_walks(void **state)
{
    (void)state;
    wear_on_walk(GAR_PATTERN_DIR "/skirt.json", SIM_SIZE_L, "skirt.json L cotton");
}

static void test_refusals(void **state)
{
    (void)state;
    sim_outfit o;
    sim_reject why = {0};
    sim_garment g = {0};
    float shape_a[FIT_SHAPE_PARAMS], pose_a[FIT_POSE_PARAMS] = {0};
    fit_shape shape = fit_shape_default();
    fit_shape_to_array(&shape, shape_a);
    assert_int_equal(sim_outfit_resolve(GAR_PATTERN_DIR "/skirt.json", SIM_SIZE_S, "", &o, &why),
                     0);
    /* a body message without the model's parameters */
    assert_int_equal(sim_outfit_make_pattern(&o, NULL, 0, pose_a, FIT_POSE_PARAMS, &g, NULL, &why),
                     -SIM_ERR_PARAM);
    assert_non_null(strstr(why.detail, "shape"));
    /* a shape out of the model's range */
    float bad[FIT_SHAPE_PARAMS];
    memcpy(bad, shape_a, sizeof bad);
    bad[0] = 50.0f;
    assert_int_equal(
        sim_outfit_make_pattern(&o, bad, FIT_SHAPE_PARAMS, pose_a, FIT_POSE_PARAMS, &g, NULL, &why),
        -SIM_ERR_PARAM);
    /* a pattern that cannot be read: no body helps */
    assert_int_equal(sim_outfit_resolve("/nonexistent/none.json", SIM_SIZE_M, "", &o, &why), 0);
    assert_int_equal(sim_outfit_make_pattern(&o, shape_a, FIT_SHAPE_PARAMS, pose_a, FIT_POSE_PARAMS,
                                             &g, NULL, &why),
                     -SIM_ERR_FILE);
    assert_non_null(strstr(why.detail, "none.json"));
    assert_null(g.xyz);
    /* the generic maker refuses a pattern instead of reading it as something else */
    assert_true(sim_outfit_make(&o, NULL, 0, NULL, 0, NULL, 0, &g, &why) < 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_tshirt_walks),
        cmocka_unit_test(test_skirt_walks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
