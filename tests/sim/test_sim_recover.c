/* Divergence is detected, recovered from where possible, reported, and never published. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include "sim_test_util.h"

static void step_sphere(sim *s, sim_scene *sc, int frames, sim_frame_stats *st, int *ret)
{
    for (int f = 0; f < frames; f++) {
        const float *xyz, *joints;
        const int32_t *tris;
        int nv, nt;
        sim_scene_eval(sc, f / 30.0, &xyz, &nv, &tris, &nt, &joints);
        *ret = sim_step(s, xyz, nv, tris, nt, st, NULL);
    }
}

static void test_sim_injected_nan_is_recovered(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    sim_scene *sc = simt_sphere();
    for (int k = 0; k < n; k++) {
        sim *s = simt_drape(bs[k], SIM_SOLVER_TRYON, 12, NULL);
        assert_non_null(s);
        sim_frame_stats st;
        int r;
        step_sphere(s, sc, 5, &st, &r);
        assert_int_equal(st.state, SIM_STATE_OK);
        sim_debug_set_vertex(s, 30, NAN, 0.0f, 0.0f);
        step_sphere(s, sc, 1, &st, &r);
        printf("# %s: after NaN: state %s, retries %d\n", simt_backend_name(bs[k]),
               sim_state_name(st.state), st.retries);
        assert_int_equal(r, 0);
        assert_int_equal(st.state, SIM_STATE_RECOVERED);
        assert_true(st.retries >= 1);
        assert_true(simt_all_finite(s));
        /* a far jump (3.6 m in one frame, 110 m/s) is divergence too */
        sim_debug_set_vertex(s, 40, 0.0f, 4.0f, 0.0f);
        step_sphere(s, sc, 1, &st, &r);
        assert_int_equal(r, 0);
        assert_int_equal(st.state, SIM_STATE_RECOVERED);
        for (int i = 0; i < sim_vertex_count(s); i++)
            assert_true(fabsf(sim_positions(s)[i * 4 + 1]) < 1.0f);
        step_sphere(s, sc, 1, &st, &r);
        assert_int_equal(st.state, SIM_STATE_OK);
        sim_destroy(s);
    }
    sim_scene_destroy(sc);
}

/* Gravity of 1e7 m/s^2 blows up at any step size: the frame is reported DIVERGED, the error
 * named, and the cloth published stays the last good one. */
static void test_sim_unrecoverable_is_reported_not_published(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    sim_scene *sc = simt_sphere();
    for (int k = 0; k < n; k++) {
        sim_desc d = sim_default_desc();
        d.gravity_m_s2 = 1e7f;
        sim *s = simt_drape(bs[k], SIM_SOLVER_TRYON, 8, &d);
        assert_non_null(s);
        float before = sim_positions(s)[1];
        sim_frame_stats st;
        int r;
        step_sphere(s, sc, 2, &st, &r);
        assert_int_equal(r, -SIM_ERR_DIVERGED);
        assert_int_equal(st.state, SIM_STATE_DIVERGED);
        assert_true(simt_all_finite(s));
        assert_float_equal(sim_positions(s)[1], before, 0.0f);
        sim_destroy(s);
    }
    sim_scene_destroy(sc);
}

/* Absurd stiffness: the tryon solver's projection is unconditionally stable; the seed clamps
 * its springs to its step. Both stay finite and bounded. */
static void test_sim_absurd_stiffness_stays_finite(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    sim_scene *sc = simt_sphere();
    for (int k = 0; k < n; k++) {
        for (int solver = 0; solver < (bs[k] == SIM_BACKEND_C ? 2 : 1); solver++) {
            sim_desc d = sim_default_desc();
            d.fabric.stretch_n_m = 1e9f;
            d.fabric.bend_n_m = 1e9f;
            sim *s = simt_drape(bs[k], (sim_solver)solver, 10, &d);
            assert_non_null(s);
            sim_frame_stats st;
            int r;
            step_sphere(s, sc, 10, &st, &r);
            printf("# %s/%d: state %s strain %.4f\n", simt_backend_name(bs[k]), solver,
                   sim_state_name(st.state), st.max_strain);
            assert_true(simt_all_finite(s));
            assert_true(st.max_strain < 0.5f);
            sim_destroy(s);
        }
    }
    sim_scene_destroy(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_injected_nan_is_recovered),
        cmocka_unit_test(test_sim_unrecoverable_is_reported_not_published),
        cmocka_unit_test(test_sim_absurd_stiffness_stays_finite),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
