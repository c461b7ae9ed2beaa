/* sim_start: a garment made on a body is published for that body as made, with no step (tryon-sim:
 * a person's first body costs the garment's making, not a frame besides), measured as sim_step
 * measures what it publishes; the frames after it are simulated from there. A garment that takes
 * the body collision state of a sim made on another body topology (tryon-sim's rehearsal on a
 * stand-in body) starts on its own body. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "scene.h"
#include "sim_test_util.h"

#define BODY_VERTS     2000
#define STAND_IN_VERTS 3000 /* the rehearsal's body: another topology, larger */
#define SHIRT_VERTS    1000
#define FRAMES         6

static void body_at(sim_scene *sc, int f, const float **xyz, int *nv, const int32_t **tris, int *nt)
{
    assert_int_equal(sim_scene_eval(sc, f * sim_default_desc().frame_dt_s, xyz, nv, tris, nt, NULL),
                     0);
}

/* frames 1.. after a start: simulated, nothing inside the body, the strain within the goals */
static void step_after_start(sim *s, sim_scene *sc)
{
    for (int f = 1; f < FRAMES; f++) {
        const float *xyz;
        const int32_t *tris;
        int nv, nt;
        sim_frame_stats st;
        body_at(sc, f, &xyz, &nv, &tris, &nt);
        assert_int_equal(sim_step(s, xyz, nv, tris, nt, &st, NULL), 0);
        assert_int_equal(st.penetrating, 0);
        assert_true(st.max_strain <= 0.03f);
        assert_true(st.iterations_used >= sim_default_desc().iterations);
    }
}

static void test_started_garment_is_published_as_made(void **state)
{
    (void)state;
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv, nt;
    assert_int_equal(simt_scene_shirt("walk", BODY_VERTS, SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt), 0);
    sim_desc d = sim_default_desc();
    d.backend = SIM_BACKEND_C;
    sim_reject why = {0};
    sim *s = sim_create(&d, &g, &why);
    assert_non_null(s);
    int n = sim_vertex_count(s);
    size_t bytes = (size_t)n * 4 * sizeof(float);
    float *made = malloc(bytes);
    assert_non_null(made);
    memcpy(made, sim_positions(s), bytes);
    const float *xyz;
    const int32_t *tris;
    body_at(sc, 0, &xyz, &nv, &tris, &nt);
    /* a body the sim refuses changes nothing, and the start can be tried again */
    float *bad = malloc((size_t)nv * 3 * sizeof *bad);
    assert_non_null(bad);
    memcpy(bad, xyz, (size_t)nv * 3 * sizeof *bad);
    bad[7] = NAN;
    sim_frame_stats st;
    assert_int_equal(sim_start(s, bad, nv, tris, nt, &st, &why), -SIM_ERR_NOT_FINITE);
    assert_memory_equal(sim_positions(s), made, bytes);
    assert_int_equal(sim_start(s, xyz, nv, tris, nt, &st, &why), 0);
    /* published as made, measured: the shirt at rest lengths, outside the body it was made on */
    assert_memory_equal(sim_positions(s), made, bytes);
    assert_int_equal(st.state, SIM_STATE_OK);
    assert_true(st.max_strain < 1e-4f && st.p99_strain < 1e-4f);
    assert_int_equal(st.penetrating, 0);
    assert_int_equal(st.iterations_used, 0);
    assert_true(st.ms_total >= st.ms_bvh && st.ms_bvh > 0.0f);
    step_after_start(s, sc);
    /* once stepped, no start */
    assert_int_equal(sim_start(s, xyz, nv, tris, nt, &st, &why), -SIM_ERR_ARG);
    free(bad);
    free(made);
    sim_destroy(s);
    sim_garment_free(&g);
    sim_scene_destroy(sc);
}

static void test_started_on_a_taken_body_state_of_another_topology(void **state)
{
    (void)state;
    sim_scene *stand_in = NULL, *sc = NULL;
    sim_garment g_stand_in = {0}, g = {0};
    int nv, nt;
    assert_int_equal(simt_scene_shirt("walk", STAND_IN_VERTS, SHIRT_VERTS, 0.0f, &stand_in,
                                      &g_stand_in, &nv, &nt),
                     0);
    assert_int_equal(simt_scene_shirt("walk", BODY_VERTS, SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt), 0);
    sim_desc d = sim_default_desc();
    d.backend = SIM_BACKEND_C;
    sim_reject why = {0};
    sim *rehearsal = sim_create(&d, &g_stand_in, &why), *s = sim_create(&d, &g, &why);
    assert_true(rehearsal && s);
    const float *xyz;
    const int32_t *tris;
    body_at(stand_in, 0, &xyz, &nv, &tris, &nt);
    assert_int_equal(sim_start(rehearsal, xyz, nv, tris, nt, NULL, &why), 0);
    assert_int_equal(sim_step(rehearsal, xyz, nv, tris, nt, NULL, &why), 0);
    assert_int_equal(sim_take_body(s, rehearsal), 0);
    sim_destroy(rehearsal);
    body_at(sc, 0, &xyz, &nv, &tris, &nt);
    sim_frame_stats st;
    assert_int_equal(sim_start(s, xyz, nv, tris, nt, &st, &why), 0);
    assert_int_equal(st.penetrating, 0);
    step_after_start(s, sc);
    sim_destroy(s);
    sim_garment_free(&g);
    sim_garment_free(&g_stand_in);
    sim_scene_destroy(sc);
    sim_scene_destroy(stand_in);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_started_garment_is_published_as_made),
        cmocka_unit_test(test_started_on_a_taken_body_state_of_another_topology),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
