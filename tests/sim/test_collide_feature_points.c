/* Seed 000 section 2.1, Eq. 1-2, on hand-made cases: a single triangle translated, rotated and
 * scaled past a cloth point; points behind it or out of reach; two triangles claiming a point. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "collide.h"

#define THICK 0.004f
/* Eq. 2 in float on 10 cm triangles: a few ulps of a metre. */
#define POS_TOL_M 2e-6f

/* Triangle in the plane y = 0, normal +y (winding v0, v2, v1 of the x-z layout). */
static const float tri0[9] = {-0.1f, 0.0f, -0.1f, 0.0f, 0.0f, 0.1f, 0.1f, 0.0f, -0.1f};
static const int32_t one_tri[3] = {0, 1, 2};

static sim_collider *make_carry(int coulomb)
{
    char err[128];
    sim_collider *c = sim_collider_create(&(sim_collider_desc){.max_vertices = 16,
                                                               .max_triangles = 8,
                                                               .thickness_m = THICK,
                                                               .friction = 0.3f,
                                                               .max_cloth = 16,
                                                               .carry_coulomb = coulomb},
                                          err, sizeof err);
    assert_non_null(c);
    return c;
}

static sim_collider *make(void)
{
    return make_carry(0);
}

typedef void (*motion)(const float in[3], float out[3]);

static void move_tri(motion m, const float *in, float *out, int nv)
{
    for (int i = 0; i < nv; i++)
        m(in + 3 * i, out + 3 * i);
}

static void up5cm(const float in[3], float out[3])
{
    out[0] = in[0], out[1] = in[1] + 0.05f, out[2] = in[2];
}

/* 30 degrees about the x axis, the +z side rising. */
static void tilt30(const float in[3], float out[3])
{
    float c = cosf(0.5235988f), s = sinf(0.5235988f);
    out[0] = in[0];
    out[1] = c * in[1] + s * in[2];
    out[2] = -s * in[1] + c * in[2];
}

/* Scale 1.5 in the plane and rise 3 cm. */
static void grow_up(const float in[3], float out[3])
{
    out[0] = 1.5f * in[0], out[1] = in[1] + 0.03f, out[2] = 1.5f * in[2];
}

/* Run one point through frames k-1 = tri0 and k = m(tri0); returns how many moved. */
static int sweep(motion m, float p[4], float p_prev[4])
{
    sim_collider *c = make();
    float next[9];
    move_tri(m, tri0, next, 3);
    assert_int_equal(sim_collider_set_body(c, tri0, 3, one_tri, 1), 0);
    assert_int_equal(sim_collider_set_body(c, next, 3, one_tri, 1), 0);
    float x[1][4], xp[1][4];
    memcpy(x[0], p, sizeof x[0]);
    memcpy(xp[0], p_prev, sizeof xp[0]);
    int moved = sim_collider_feature_points(c, x, xp, 0, 1);
    memcpy(p, x[0], sizeof x[0]);
    memcpy(p_prev, xp[0], sizeof xp[0]);
    sim_collider_destroy(c);
    return moved;
}

static void expect_carried(motion m, const float start[3], const float expect[3])
{
    float p[4] = {start[0], start[1], start[2], 1.0f};
    float pp[4] = {start[0] - 0.001f, start[1], start[2] + 0.002f, 1.0f};
    float vel[3] = {p[0] - pp[0], p[1] - pp[1], p[2] - pp[2]};
    assert_int_equal(sweep(m, p, pp), 1);
    for (int k = 0; k < 3; k++) {
        assert_float_equal(p[k], expect[k], POS_TOL_M);
        /* x_prev carried by the same displacement: the velocity is kept. */
        assert_float_equal(p[k] - pp[k], vel[k], POS_TOL_M);
    }
}

static void test_feature_point_follows_moving_triangle(void **state)
{
    (void)state;
    /* Translation: Eq. 2 keeps the barycentrics and the 2 cm gap. */
    float a[3] = {0.01f, 0.02f, -0.02f}, ea[3];
    up5cm(a, ea);
    expect_carried(up5cm, a, ea);
    /* Rotation about an in-plane axis: a rigid motion, so the point moves rigidly too. */
    float b[3] = {0.0f, 0.01f, 0.05f}, eb[3];
    tilt30(b, eb);
    expect_carried(tilt30, b, eb);
    /* Scaling: barycentrics kept on the grown triangle, distance kept along the normal. */
    float c[3] = {0.02f, 0.01f, -0.03f}, ec[3] = {0.03f, 0.04f, -0.045f};
    expect_carried(grow_up, c, ec);
    /* Closer than thickness: lifted to thickness (Eq. 2 with max(dist, thickness)). */
    float d[3] = {0.0f, 0.001f, 0.0f}, ed[3] = {0.0f, 0.05f + THICK, 0.0f};
    expect_carried(up5cm, d, ed);
}

static void test_feature_point_ignores_points_not_swept(void **state)
{
    (void)state;
    /* Behind the triangle at k-1: inside the body, not swept. */
    float p[4] = {0.0f, -0.02f, 0.0f, 1.0f}, pp[4] = {0.0f, -0.02f, 0.0f, 1.0f};
    assert_int_equal(sweep(up5cm, p, pp), 0);
    assert_true(p[1] == -0.02f);
    /* Above where the triangle ends up (plus thickness): not reached. */
    float q[4] = {0.0f, 0.06f, 0.0f, 1.0f}, qp[4] = {0.0f, 0.06f, 0.0f, 1.0f};
    assert_int_equal(sweep(up5cm, q, qp), 0);
    assert_true(q[1] == 0.06f);
    /* Beside the triangle: outside the prism. */
    float r[4] = {0.2f, 0.01f, 0.0f, 1.0f}, rp[4] = {0.2f, 0.01f, 0.0f, 1.0f};
    assert_int_equal(sweep(up5cm, r, rp), 0);
    /* Pinned points (w = 0) are never moved. */
    float s[4] = {0.0f, 0.01f, 0.0f, 0.0f}, sp[4] = {0.0f, 0.01f, 0.0f, 0.0f};
    assert_int_equal(sweep(up5cm, s, sp), 0);
    assert_true(s[1] == 0.01f);
}

/* Two layers under one point: A at y = 0 rises to 5 cm, B at y = -6 mm rises to 6 cm. Both
   sweep the point; A is nearer at k-1, so A carries it (seed 000 Figure 2). */
static void test_feature_point_nearest_of_several_triangles_wins(void **state)
{
    (void)state;
    float v0[18], v1[18];
    memcpy(v0, tri0, sizeof tri0);
    memcpy(v0 + 9, tri0, sizeof tri0);
    for (int i = 0; i < 3; i++)
        v0[9 + 3 * i + 1] = -0.006f;
    memcpy(v1, v0, sizeof v0);
    for (int i = 0; i < 3; i++) {
        v1[3 * i + 1] = 0.05f;
        v1[9 + 3 * i + 1] = 0.06f;
    }
    int32_t t[6] = {0, 1, 2, 3, 4, 5};
    sim_collider *c = make();
    assert_int_equal(sim_collider_set_body(c, v0, 6, t, 2), 0);
    assert_int_equal(sim_collider_set_body(c, v1, 6, t, 2), 0);
    float x[1][4] = {{0.01f, 0.01f, 0.0f, 1.0f}}, xp[1][4] = {{0.01f, 0.01f, 0.0f, 1.0f}};
    assert_int_equal(sim_collider_feature_points(c, x, xp, 0, 1), 1);
    assert_float_equal(x[0][1], 0.05f + 0.01f, POS_TOL_M);
    sim_collider_destroy(c);
}

/* No sweep on the first body or after a topology change. */
static void test_feature_point_needs_two_frames_of_one_topology(void **state)
{
    (void)state;
    sim_collider *c = make();
    float x[1][4] = {{0.0f, 0.01f, 0.0f, 1.0f}}, xp[1][4] = {{0.0f, 0.01f, 0.0f, 1.0f}};
    assert_int_equal(sim_collider_set_body(c, tri0, 3, one_tri, 1), 0);
    assert_int_equal(sim_collider_feature_points(c, x, xp, 0, 1), 0);
    float next[9];
    move_tri(up5cm, tri0, next, 3);
    int32_t flipped[3] = {0, 2, 1};
    assert_int_equal(sim_collider_set_body(c, next, 3, flipped, 1), -SIM_ERR_TOPOLOGY);
    assert_int_equal(sim_collider_feature_points(c, x, xp, 0, 1), 0);
    sim_collider_destroy(c);
}

/* A point above a convex ridge lies outside both faces' own prisms (the offset surface is
   rounded there); the ridge rising through it must still carry it. */
static void test_feature_point_above_convex_ridge_is_carried(void **state)
{
    (void)state;
    float v0[12] = {0, 0, 0.1f, 0, 0, -0.1f, -0.1f, -0.05f, 0, 0.1f, -0.05f, 0};
    float v1[12];
    memcpy(v1, v0, sizeof v0);
    for (int i = 0; i < 4; i++)
        v1[3 * i + 1] += 0.05f;
    int32_t t[6] = {0, 1, 2, 1, 0, 3};
    sim_collider *c = make();
    assert_int_equal(sim_collider_set_body(c, v0, 4, t, 2), 0);
    assert_int_equal(sim_collider_set_body(c, v1, 4, t, 2), 0);
    float x[1][4] = {{0.0f, 0.006f, 0.0f, 1.0f}}, xp[1][4] = {{0.0f, 0.006f, 0.0f, 1.0f}};
    assert_int_equal(sim_collider_feature_points(c, x, xp, 0, 1), 1);
    /* Above the risen ridge (y = 0.05) by at least the thickness. */
    assert_true(x[0][1] >= 0.05f + THICK - POS_TOL_M);
    assert_true(fabsf(x[0][0]) < 0.01f);
    sim_collider_destroy(c);
}

/* Rise 2 cm and slide 5 cm along +x: a body part moving mostly along its own surface. */
static void rise_slide(const float in[3], float out[3])
{
    out[0] = in[0] + 0.05f, out[1] = in[1] + 0.02f, out[2] = in[2];
}

/* The tryon carry: the push along the normal whole, the slide only up to friction (0.3) times
   it; Eq. 2 takes the slide whole. A pure push is the same under both. */
static void test_feature_point_coulomb_carry_bounds_the_slide(void **state)
{
    (void)state;
    for (int coulomb = 0; coulomb < 2; coulomb++) {
        sim_collider *c = make_carry(coulomb);
        float next[9];
        move_tri(rise_slide, tri0, next, 3);
        assert_int_equal(sim_collider_set_body(c, tri0, 3, one_tri, 1), 0);
        assert_int_equal(sim_collider_set_body(c, next, 3, one_tri, 1), 0);
        float x[1][4] = {{0.01f, 0.01f, 0.02f, 1.0f}}, xp[1][4] = {{0.01f, 0.01f, 0.02f, 1.0f}};
        assert_int_equal(sim_collider_feature_points(c, x, xp, 0, 1), 1);
        /* height above the risen plane kept (1 cm); x: 0.01 + 0.05 (Eq. 2) or + 0.3 * 0.02 */
        assert_float_equal(x[0][1], 0.03f, POS_TOL_M);
        assert_float_equal(x[0][0], coulomb ? 0.016f : 0.06f, POS_TOL_M);
        assert_float_equal(x[0][2], 0.02f, POS_TOL_M);
        assert_float_equal(x[0][0] - xp[0][0], 0.0f, POS_TOL_M); /* velocity kept */
        sim_collider_destroy(c);

        c = make_carry(coulomb);
        move_tri(up5cm, tri0, next, 3);
        assert_int_equal(sim_collider_set_body(c, tri0, 3, one_tri, 1), 0);
        assert_int_equal(sim_collider_set_body(c, next, 3, one_tri, 1), 0);
        float y[1][4] = {{0.01f, 0.02f, -0.02f, 1.0f}}, yp[1][4] = {{0.01f, 0.02f, -0.02f, 1.0f}};
        assert_int_equal(sim_collider_feature_points(c, y, yp, 0, 1), 1);
        assert_float_equal(y[0][0], 0.01f, POS_TOL_M);
        assert_float_equal(y[0][1], 0.07f, POS_TOL_M);
        assert_float_equal(y[0][2], -0.02f, POS_TOL_M);
        sim_collider_destroy(c);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_feature_point_follows_moving_triangle),
        cmocka_unit_test(test_feature_point_ignores_points_not_swept),
        cmocka_unit_test(test_feature_point_nearest_of_several_triangles_wins),
        cmocka_unit_test(test_feature_point_above_convex_ridge_is_carried),
        cmocka_unit_test(test_feature_point_needs_two_frames_of_one_topology),
        cmocka_unit_test(test_feature_point_coulomb_carry_bounds_the_slide),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
