/* The settle rounds' stop (kernels/solver_params.h, sim_settle_stop): they stop for slow progress
 * only within the strain retry goal. The bends' frames take 1.5-3 % off the strain a batch, at
 * the progress bound, so they stopped at 4-9 % and were done again; with the plain contact push,
 * the velocity it left made those frames fast (sim_frame_fast), which kept the rounds going
 * (docs/sim-real-motion.md, "Real motion: the bends' settle rounds"). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "cloth.h"
#include "frame_settings.h"
#include "sim_test_util.h"

#define BODY_VERTS  6000
#define SHIRT_VERTS 2000
#define ITERS       8 /* steps a frame: a third of the default, so that frames end over the goal */
#define FRAMES      20

static sim_solver_params settings(float hold)
{
    sim_solver_params p = {0};
    p.settle_progress = SIM_SETTLE_PROGRESS;
    p.settle_strain = SIM_SETTLE_STRAIN;
    p.settle_hold = hold;
    return p;
}

/* m after a batch that took 1 % off prev: over the goal the rounds go on, within it they stop;
   without a goal (no retries) they stop; within the settle goal or with progress as before. */
static void test_settle_stop_holds_over_the_retry_goal(void **state)
{
    (void)state;
    sim_solver_params held = settings(SIM_RETRY_STRAIN), free = settings(0.0f);
    float slow = 0.99f;
    assert_int_equal(sim_settle_stop(0.05f, 0.05f / slow, 0, 0, &held), 0);
    assert_int_equal(sim_settle_stop(0.05f, 0.05f / slow, 0, 0, &free), 1);
    assert_int_equal(sim_settle_stop(0.025f, 0.025f / slow, 0, 0, &held), 1);
    assert_int_equal(sim_settle_stop(0.025f, 0.025f / 0.9f, 0, 0, &held), 0);
    assert_int_equal(sim_settle_stop(0.019f, 0.05f, 0, 0, &held), 1);
    assert_int_equal(sim_settle_stop(0.05f, 0.05f / slow, 1, 0, &free), 0);
    assert_int_equal(sim_settle_stop(0.05f, 0.05f / slow, 0, 1, &free), 0);
}

/* A torn attempt (over settle_torn) stops its rounds at once, held or first test alike; under
   that bound the rules above decide; the settings' bound is the divergence test's, past
   SIM_DIVERGE_STRAIN and grown from the last good frame's strain. */
static void test_settle_stops_when_torn(void **state)
{
    (void)state;
    sim_solver_params held = settings(SIM_RETRY_STRAIN);
    held.settle_torn = sim_torn_strain(0.1f);
    assert_true(held.settle_torn == SIM_DIVERGE_STRAIN);
    assert_int_equal(sim_settle_stop(0.8f, 0.9f, 1, 1, &held), 1);
    assert_int_equal(sim_settle_stop(0.8f, 0.9f, 0, 0, &held), 1);
    assert_int_equal(sim_settle_stop(0.45f, 0.9f, 0, 0, &held), 0);
    held.settle_torn = 0.0f; /* never: the seed solver */
    assert_int_equal(sim_settle_stop(0.8f, 0.9f, 1, 1, &held), 0);
    assert_true(sim_torn_strain(0.6f) > 0.6f * 1.05f);
}

/* The frame's settings carry the desc's retry goal, none when retries are off. */
static void test_settings_take_the_retry_goal(void **state)
{
    (void)state;
    sim_desc d = sim_default_desc();
    sim *s = simt_drape(SIM_BACKEND_C, SIM_SOLVER_TRYON, 8, &d);
    assert_non_null(s);
    sim_solver_params p;
    sim_solver_params_fill(s, 25, &p);
    assert_true(p.settle_hold == SIM_RETRY_STRAIN);
    assert_true(p.settle_torn == sim_torn_strain(0.0f));
    sim_destroy(s);
    d.retry_max_strain = d.retry_p99_strain = -1.0f;
    s = simt_drape(SIM_BACKEND_C, SIM_SOLVER_TRYON, 8, &d);
    assert_non_null(s);
    sim_solver_params_fill(s, 25, &p);
    assert_true(p.settle_hold == 0.0f);
    sim_destroy(s);
}

/* The shirt (test size) on the trunk bent forward, with few steps a frame so that frames end over
   the goal: with retries, every frame published over it ran every settle round of its attempts;
   without retries, some stopped early (the scene tests the rule). On each backend. */
static void run_bend(sim_backend b, int retries, int *early, int *over)
{
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv, nt;
    assert_int_equal(
        simt_scene_shirt("bend_forward", BODY_VERTS, SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt), 0);
    sim_desc d = sim_default_desc();
    d.backend = b;
    d.iterations = ITERS;
    if (!retries)
        d.retry_max_strain = d.retry_p99_strain = -1.0f;
    sim_reject why = {0};
    sim *s = sim_create(&d, &g, &why);
    sim_garment_free(&g);
    assert_non_null(s);
    *early = *over = 0;
    for (int f = 0; f < FRAMES; f++) {
        const float *xyz, *joints;
        const int32_t *tris;
        assert_int_equal(sim_scene_eval(sc, f / 30.0, &xyz, &nv, &tris, &nt, &joints), 0);
        sim_frame_stats st;
        assert_int_equal(sim_step(s, xyz, nv, tris, nt, &st, &why), 0);
        if (st.max_strain > SIM_RETRY_STRAIN) {
            (*over)++;
            *early += st.settle_rounds < SIM_SETTLE_ROUNDS;
        }
    }
    printf("# bend %s, retries %s: %d frames over the goal, %d stopped early\n",
           simt_backend_name(b), retries ? "on" : "off", *over, *early);
    sim_destroy(s);
    sim_scene_destroy(sc);
}

static void test_frames_over_the_goal_run_every_round(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        int early, over;
        run_bend(bs[k], 0, &early, &over);
        assert_true(over > 0 && early > 0); /* the scene tests the rule */
        run_bend(bs[k], 1, &early, &over);
        assert_int_equal(early, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_settle_stop_holds_over_the_retry_goal),
        cmocka_unit_test(test_settle_stops_when_torn),
        cmocka_unit_test(test_settings_take_the_retry_goal),
        cmocka_unit_test(test_frames_over_the_goal_run_every_round),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
