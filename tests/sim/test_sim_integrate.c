/* The integration and the spring passes against hand computation. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include "cloth.h"
#include "sim_test_util.h"

/* Verlet from rest under gravity: x_n = x_0 - g dt^2 n (n + 1) / 2 (each step adds one more
 * g dt^2 to the displacement). */
static void test_sim_verlet_free_fall_matches_closed_form(void **state)
{
    (void)state;
    float x[1][4] = {{0, 1, 0, 1}}, xp[1][4] = {{0, 1, 0, 1}};
    float dt = 0.01f, a[3] = {0, -9.81f * dt * dt, 0};
    for (int n = 0; n < 10; n++)
        sim_verlet(x, xp, 0, 1, 1.0f, a);
    assert_float_equal(x[0][1], 1.0f - 9.81f * dt * dt * 55.0f, 1e-5f);
    /* a pinned point does not move */
    float y[1][4] = {{0, 1, 0, 0}}, yp[1][4] = {{0, 1, 0, 0}};
    sim_verlet(y, yp, 0, 1, 1.0f, a);
    assert_float_equal(y[0][1], 1.0f, 0.0f);
}

/* XPBD: two unit masses 1.5 m apart on a 1 m spring of compliance alpha move together by
 * C / (w1 + w2 + alpha) each. */
static void test_sim_project_spring_by_hand(void **state)
{
    (void)state;
    float x[2][4] = {{0, 0, 0, 1}, {1.5f, 0, 0, 1}};
    int32_t ends[1][2] = {{0, 1}};
    float rest[1] = {1.0f};
    uint8_t kind[1] = {SIM_SPRING_STRETCH};
    float alpha[SIM_SPRING_KINDS] = {1.0f, 1.0f, 1.0f};
    sim_project_springs(x, ends, rest, kind, alpha, 0, 1);
    float move = 0.5f / 3.0f; /* C = 0.5, w1 + w2 + alpha = 3 */
    assert_float_equal(x[0][0], move, 1e-6f);
    assert_float_equal(x[1][0], 1.5f - move, 1e-6f);
}

/* seed: f = k dl; acc dt^2 = f w dt^2 on each end, opposite signs. */
static void test_sim_spring_force_by_hand(void **state)
{
    (void)state;
    float x[2][4] = {{0, 0, 0, 2}, {0, 1.1f, 0, 0.5f}};
    int32_t ends[1][2] = {{0, 1}};
    float rest[1] = {1.0f}, k[SIM_SPRING_KINDS] = {100.0f, 0, 0};
    uint8_t kind[1] = {SIM_SPRING_STRETCH};
    float acc[2][4] = {{0}};
    float dt = 0.001f;
    sim_spring_forces(x, x, ends, rest, kind, k, 0, 1, dt, 0.0f, acc);
    float f = 100.0f * 0.1f; /* N toward each other */
    assert_float_equal(acc[0][1], f * 2.0f * dt * dt, 1e-9f);
    assert_float_equal(acc[1][1], -f * 0.5f * dt * dt, 1e-9f);
}

/* The whole driver: a small sheet far from the body falls by the closed form in one frame. */
static void test_sim_frame_free_fall(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    float body[3 * 3] = {0, -50, 0, 1, -50, 0, 0, -50, 1};
    int32_t tri[3] = {0, 1, 2};
    for (int k = 0; k < n; k++) {
        sim_desc d = sim_default_desc();
        d.damping = -1.0f;
        d.iterations = 10;
        sim *s = simt_drape(bs[k], SIM_SOLVER_TRYON, 4, &d);
        assert_non_null(s);
        float y0 = sim_positions(s)[1];
        assert_int_equal(sim_step(s, body, 3, tri, 1, NULL, NULL), 0);
        float dt = d.frame_dt_s / 10.0f;
        float expect = y0 - 9.81f * dt * dt * 55.0f;
        for (int i = 0; i < sim_vertex_count(s); i++)
            assert_float_equal(sim_positions(s)[i * 4 + 1], expect, 1e-5f);
        printf("# %s: fell %.6f m, closed form %.6f m\n", simt_backend_name(bs[k]),
               y0 - sim_positions(s)[1], y0 - expect);
        sim_destroy(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_verlet_free_fall_matches_closed_form),
        cmocka_unit_test(test_sim_project_spring_by_hand),
        cmocka_unit_test(test_sim_spring_force_by_hand),
        cmocka_unit_test(test_sim_frame_free_fall),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
