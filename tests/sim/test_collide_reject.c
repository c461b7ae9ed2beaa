/* Bad bodies are refused with a named error and leave the collider as it was. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "collide.h"

static const float good[12] = {0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0};
static const int32_t good_tris[6] = {0, 2, 1, 0, 1, 3};

static sim_collider *make(void)
{
    char err[128];
    sim_collider *c = sim_collider_create(
        &(sim_collider_desc){.max_vertices = 4, .max_triangles = 2, .max_cloth = 4}, err,
        sizeof err);
    assert_non_null(c);
    assert_int_equal(sim_collider_set_body(c, good, 4, good_tris, 2), 0);
    return c;
}

static void expect_rejected(const float *xyz, int nv, const int32_t *tris, int nt, int code)
{
    sim_collider *c = make();
    assert_int_equal(sim_collider_set_body(c, xyz, nv, tris, nt), code);
    assert_string_not_equal(sim_error_text(code), "unknown error");
    /* The last good body is kept: a point 1 cm above triangle 0 still finds it. */
    const float(*v)[4], (*vp)[4], (*n)[4];
    const int32_t(*t)[4];
    assert_int_equal(sim_collider_body(c, &v, &vp, &t, &n), 2);
    float x[1][4] = {{0.2f, -0.01f, 0.2f, 1.0f}};
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, 1);
    assert_int_equal(sim_collider_contacts(c)[0], 0);
    sim_collider_destroy(c);
}

static void test_collide_rejects_bad_bodies_by_name(void **state)
{
    (void)state;
    float bad[12];
    memcpy(bad, good, sizeof bad);
    bad[4] = NAN;
    expect_rejected(bad, 4, good_tris, 2, -SIM_ERR_NOT_FINITE);
    bad[4] = INFINITY;
    expect_rejected(bad, 4, good_tris, 2, -SIM_ERR_NOT_FINITE);
    int32_t out_of_range[6] = {0, 2, 1, 0, 1, 4};
    expect_rejected(good, 4, out_of_range, 2, -SIM_ERR_INDEX);
    int32_t negative[6] = {0, 2, 1, -1, 1, 3};
    expect_rejected(good, 4, negative, 2, -SIM_ERR_INDEX);
    int32_t repeated[6] = {0, 2, 1, 0, 0, 3};
    expect_rejected(good, 4, repeated, 2, -SIM_ERR_DEGENERATE);
    float collinear[12] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0};
    int32_t line[6] = {0, 1, 2, 0, 1, 3};
    expect_rejected(collinear, 4, line, 2, -SIM_ERR_DEGENERATE);
    expect_rejected(good, 0, good_tris, 0, -SIM_ERR_EMPTY);
    expect_rejected(good, 4, good_tris, 0, -SIM_ERR_EMPTY);
    expect_rejected(NULL, 4, good_tris, 2, -SIM_ERR_ARG);
    expect_rejected(good, -1, good_tris, 2, -SIM_ERR_ARG);
    float big[15] = {0};
    int32_t big_tris[9] = {0, 1, 2, 0, 1, 3, 0, 1, 4};
    expect_rejected(big, 5, big_tris, 3, -SIM_ERR_TOO_LARGE);
}

static void test_collide_create_rejects_bad_description(void **state)
{
    (void)state;
    char err[128] = "";
    assert_null(sim_collider_create(NULL, err, sizeof err));
    assert_true(strlen(err) > 0);
    assert_null(sim_collider_create(
        &(sim_collider_desc){.max_vertices = 3, .max_triangles = 1, .thickness_m = NAN}, err,
        sizeof err));
    assert_null(sim_collider_create(
        &(sim_collider_desc){.max_vertices = 3, .max_triangles = 1, .friction = -1.0f}, err,
        sizeof err));
    sim_collider_destroy(NULL);
    assert_string_equal(sim_error_text(12345), "unknown error");
}

/* Empty cloth, NULL arrays, an empty metric: no crash, sane answers. */
static void test_collide_empty_inputs_are_harmless(void **state)
{
    (void)state;
    char err[128];
    sim_collider *c = sim_collider_create(
        &(sim_collider_desc){.max_vertices = 4, .max_triangles = 2}, err, sizeof err);
    assert_non_null(c);
    int count = -1;
    float depth = -1.0f;
    /* No body yet. */
    float x[1][4] = {{0, 0, 0, 1}}, xp[1][4] = {{0, 0, 0, 1}};
    assert_int_equal(sim_collider_penetration(c, (const float(*)[4])x, 1, 0.001f, &count, &depth),
                     0);
    assert_int_equal(count, 0);
    assert_int_equal(sim_collider_feature_points(c, x, xp, 0, 1), 0);
    /* No contact cache reserved: find_contacts and resolve ignore the points. */
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, 1);
    sim_collider_resolve(c, x, xp, 0, 1);
    assert_int_equal(sim_collider_penetration(c, NULL, 1, 0.001f, &count, &depth), -SIM_ERR_ARG);
    assert_int_equal(sim_collider_reserve(c, -1), -SIM_ERR_ARG);
    assert_int_equal(sim_collider_reserve(c, 8), 0);
    sim_collider_destroy(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_collide_rejects_bad_bodies_by_name),
        cmocka_unit_test(test_collide_create_rejects_bad_description),
        cmocka_unit_test(test_collide_empty_inputs_are_harmless),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
