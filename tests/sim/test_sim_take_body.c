/* sim_take_body: a garment made again on the same body (tryon-sim, when the fitter's shape
 * settles) takes the replaced sim's body collision state instead of building its own, and
 * simulates exactly what a sim that built it would: the same bits, frame after frame. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "scene.h"
#include "sim_test_util.h"

#define BODY_VERTS  2000
#define SHIRT_VERTS 1000
#define FRAMES      5

static void step_frames(sim *s, sim_scene *sc, int first, int n, sim_frame_stats *st)
{
    for (int f = first; f < first + n; f++) {
        const float *xyz;
        const int32_t *tris;
        int nv, nt;
        assert_int_equal(
            sim_scene_eval(sc, f * sim_default_desc().frame_dt_s, &xyz, &nv, &tris, &nt, NULL), 0);
        assert_int_equal(sim_step(s, xyz, nv, tris, nt, &st[f - first], NULL), 0);
    }
}

static void test_taken_body_simulates_the_same(void **state)
{
    (void)state;
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv, nt;
    assert_int_equal(simt_scene_shirt("walk", BODY_VERTS, SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt), 0);
    sim_desc d = sim_default_desc();
    d.backend = SIM_BACKEND_C;
    sim_reject why = {0};
    sim *before = sim_create(&d, &g, &why), *taker = sim_create(&d, &g, &why),
        *fresh = sim_create(&d, &g, &why);
    assert_true(before && taker && fresh);
    sim_frame_stats st[FRAMES], st_fresh[FRAMES];
    assert_int_equal(sim_take_body(taker, before), -1); /* nothing to take yet */
    step_frames(before, sc, 0, FRAMES, st);
    assert_int_equal(sim_take_body(taker, before), 0);
    assert_int_equal(sim_take_body(taker, before), -1); /* before's body is gone */
    sim_destroy(before);                                /* it holds taker's empty collider */
    step_frames(taker, sc, FRAMES, FRAMES, st);
    step_frames(fresh, sc, FRAMES, FRAMES, st_fresh);
    for (int f = 0; f < FRAMES; f++) {
        assert_int_equal(st[f].state, st_fresh[f].state);
        assert_int_equal(st[f].penetrating, st_fresh[f].penetrating);
        assert_true(st[f].max_strain == st_fresh[f].max_strain);
    }
    int n = sim_vertex_count(taker);
    assert_int_equal(n, sim_vertex_count(fresh));
    assert_memory_equal(sim_positions(taker), sim_positions(fresh), (size_t)n * 4 * sizeof(float));
    /* a sim that has stepped, or one with other contact settings, takes nothing */
    sim_desc thick = d;
    thick.thickness_m = 2.0f * sim_default_desc().thickness_m;
    sim *other = sim_create(&thick, &g, &why);
    assert_non_null(other);
    assert_int_equal(sim_take_body(other, taker), -1);
    assert_int_equal(sim_take_body(fresh, taker), -1);
    sim_destroy(other);
    sim_destroy(taker);
    sim_destroy(fresh);
    sim_garment_free(&g);
    sim_scene_destroy(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_taken_body_simulates_the_same),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
