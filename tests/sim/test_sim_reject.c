/* Bad garments and bad bodies are refused with the named error, never crash. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "sim_test_util.h"

static void expect_garment_rejected(sim_garment *g, sim_error code)
{
    sim_reject why = {0};
    sim *s = sim_create(NULL, g, &why);
    printf("# %s: %s\n", sim_error_name(why.code), why.detail);
    assert_null(s);
    assert_int_equal(why.code, code);
    assert_true(strlen(why.detail) > 0);
}

static void test_sim_bad_garments_are_named(void **state)
{
    (void)state;
    sim_garment g = {0};
    expect_garment_rejected(&g, SIM_ERR_EMPTY);
    assert_int_equal(sim_garment_drape(9, 1.0f, 0.0f, &g), 0);

    g.xyz[4] = NAN;
    expect_garment_rejected(&g, SIM_ERR_NOT_FINITE);
    g.xyz[4] = 0.0f;

    int32_t t5 = g.triangles[5];
    g.triangles[5] = 9;
    expect_garment_rejected(&g, SIM_ERR_INDEX);
    g.triangles[5] = -1;
    expect_garment_rejected(&g, SIM_ERR_INDEX);
    g.triangles[5] = t5;

    int32_t keep = g.triangles[1];
    g.triangles[1] = g.triangles[0];
    expect_garment_rejected(&g, SIM_ERR_DEGENERATE);
    g.triangles[1] = keep;

    float mass[9] = {1, 1, 1, 1, 0, 1, 1, 1, 1};
    g.mass_kg = mass;
    expect_garment_rejected(&g, SIM_ERR_MASS);
    g.mass_kg = NULL;

    sim_attachment at = {.vertex = 99, .body_triangle = 0};
    g.attachments = &at;
    g.num_attachments = 1;
    expect_garment_rejected(&g, SIM_ERR_ATTACHMENT);
    g.attachments = NULL;
    g.num_attachments = 0;

    g.grid_w = 4;
    expect_garment_rejected(&g, SIM_ERR_PARAM);
    g.grid_w = 3;

    sim_desc d = sim_default_desc();
    d.fabric.stretch_n_m = NAN;
    sim_reject why = {0};
    assert_null(sim_create(&d, &g, &why));
    assert_int_equal(why.code, SIM_ERR_PARAM);
    sim_garment_free(&g);
}

/* A collapsed triangle (three vertices on one point) is degenerate even with distinct indices. */
static void test_sim_zero_area_garment_is_degenerate(void **state)
{
    (void)state;
    sim_garment g = {0};
    assert_int_equal(sim_garment_drape(9, 1.0f, 0.0f, &g), 0);
    for (int k = 0; k < 3; k++)
        memcpy(&g.xyz[g.triangles[k] * 3], &g.xyz[g.triangles[0] * 3], 3 * sizeof(float));
    expect_garment_rejected(&g, SIM_ERR_DEGENERATE);
    sim_garment_free(&g);
}

static void test_sim_bad_bodies_are_named_and_skipped(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        sim *s = simt_drape(bs[k], SIM_SOLVER_TRYON, 6, NULL);
        assert_non_null(s);
        float body[4 * 3] = {0, -1, 0, 1, -1, 0, 0, -1, 1, 1, -1, 1};
        int32_t tris[2 * 3] = {0, 1, 2, 1, 3, 2};
        sim_reject why = {0};
        assert_int_equal(sim_step(s, body, 4, tris, 2, NULL, &why), 0);
        float y = sim_positions(s)[1];

        body[7] = INFINITY;
        assert_int_equal(sim_step(s, body, 4, tris, 2, NULL, &why), -SIM_ERR_NOT_FINITE);
        printf("# %s\n", why.detail);
        body[7] = -1.0f;
        tris[4] = 4;
        assert_int_equal(sim_step(s, body, 4, tris, 2, NULL, &why), -SIM_ERR_INDEX);
        printf("# %s\n", why.detail);
        tris[4] = 1;
        assert_int_equal(sim_step(s, body, 4, tris, 2, NULL, &why), -SIM_ERR_DEGENERATE);
        tris[4] = 3;
        assert_int_equal(sim_step(s, body, 0, tris, 2, NULL, &why), -SIM_ERR_EMPTY);
        assert_int_equal(sim_step(s, NULL, 4, tris, 2, NULL, &why), -SIM_ERR_EMPTY);
        /* nothing was simulated by the rejected frames; the next good one goes on */
        assert_float_equal(sim_positions(s)[1], y, 0.0f);
        assert_int_equal(sim_step(s, body, 4, tris, 2, NULL, &why), 0);
        assert_true(sim_positions(s)[1] < y);
        sim_destroy(s);
    }
}

static void test_sim_garment_obj_round_trip_and_missing_file(void **state)
{
    (void)state;
    sim_garment g = {0}, h = {0};
    assert_int_equal(sim_garment_drape(16, 0.5f, 1.0f, &g), 0);
    const char *path = "test_sim_reject_garment.obj";
    assert_int_equal(sim_garment_save_obj(&g, path), 0);
    sim_reject why = {0};
    assert_int_equal(sim_garment_load_obj(path, &h, &why), 0);
    assert_int_equal(h.num_vertices, 16);
    assert_int_equal(h.num_triangles, g.num_triangles);
    assert_int_equal(h.grid_w, 4);
    assert_memory_equal(h.triangles, g.triangles, (size_t)g.num_triangles * 3 * sizeof(int32_t));
    for (int i = 0; i < 48; i++)
        assert_float_equal(h.xyz[i], g.xyz[i], 1e-6f);
    remove(path);
    sim_garment_free(&h);
    assert_int_equal(sim_garment_load_obj("/nonexistent/garment.obj", &h, &why), -SIM_ERR_FILE);
    assert_non_null(strstr(why.detail, "/nonexistent/garment.obj"));
    sim_garment_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_bad_garments_are_named),
        cmocka_unit_test(test_sim_zero_area_garment_is_degenerate),
        cmocka_unit_test(test_sim_bad_bodies_are_named_and_skipped),
        cmocka_unit_test(test_sim_garment_obj_round_trip_and_missing_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
