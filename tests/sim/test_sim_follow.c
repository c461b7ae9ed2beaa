/* The moving frame (sim/follow.c, sim_desc.follow): the rigid fit by hand (Horn's quaternion
 * method, a fraction of it, what it refuses), and what it is for: a shirt on the body scene's turn
 * keeps its strain at the limit where the world frame lets the tube twist; both backends. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "cloth.h"

#define PI 3.14159265358979323846
#include "sim_test_util.h"

/* Rotation of angle a about the unit axis u (Rodrigues), row-major. */
static void rotation(const double u[3], double a, double r[3][3])
{
    double c = cos(a), s = sin(a), t = 1.0 - c;
    double x = u[0], y = u[1], z = u[2];
    double m[3][3] = {{t * x * x + c, t * x * y - s * z, t * x * z + s * y},
                      {t * x * y + s * z, t * y * y + c, t * y * z - s * x},
                      {t * x * z - s * y, t * y * z + s * x, t * z * z + c}};
    memcpy(r, m, sizeof m);
}

/* A ring of n points round the chest (planar: the case an SVD would need special care for),
   moved by rotation r and translation t. */
static void ring(int n, const double r[3][3], const double t[3], double (*p)[3], double (*q)[3])
{
    for (int i = 0; i < n; i++) {
        double a = 2.0 * PI * i / n;
        p[i][0] = 0.15 * cos(a) + 0.02;
        p[i][1] = 1.35;
        p[i][2] = 0.11 * sin(a) - 0.01;
        for (int k = 0; k < 3; k++)
            q[i][k] = r[k][0] * p[i][0] + r[k][1] * p[i][1] + r[k][2] * p[i][2] + t[k];
    }
}

static void test_fit_recovers_a_rigid_motion(void **state)
{
    (void)state;
    double(*p)[3] = malloc(24 * sizeof *p), (*q)[3] = malloc(24 * sizeof *q);
    const double axis[3] = {0.267261, 0.801784, -0.534522}; /* (1, 3, -2) / |.| */
    const double t[3] = {0.05, -0.02, 0.3};
    double r[3][3], rh[3][3];
    rotation(axis, 0.7, r);
    rotation(axis, 0.35, rh);
    ring(24, r, t, p, q);
    float m[12];
    assert_int_equal(sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, 24, 1.0, m), 0);
    for (int a = 0; a < 3; a++) {
        for (int b = 0; b < 3; b++)
            assert_float_equal(m[4 * a + b], r[a][b], 1e-5);
        assert_float_equal(m[4 * a + 3], t[a], 1e-5);
    }
    /* half of it: half the angle about the same axis, the centroid half its way */
    assert_int_equal(sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, 24, 0.5, m), 0);
    double pc[3] = {0.02, 1.35, -0.01}, qc[3], hc[3];
    for (int a = 0; a < 3; a++) {
        qc[a] = r[a][0] * pc[0] + r[a][1] * pc[1] + r[a][2] * pc[2] + t[a];
        hc[a] = m[4 * a] * pc[0] + m[4 * a + 1] * pc[1] + m[4 * a + 2] * pc[2] + m[4 * a + 3];
        for (int b = 0; b < 3; b++)
            assert_float_equal(m[4 * a + b], rh[a][b], 1e-5);
        assert_float_equal(hc[a], 0.5 * (pc[a] + qc[a]), 1e-5);
    }
    /* none of it: the identity */
    assert_int_equal(sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, 24, 0.0, m), 0);
    for (int k = 0; k < 12; k++) {
        double want = k % 5 == 0 ? 1.0 : 0.0;
        assert_float_equal(m[k], want, 1e-7);
    }
    /* a half turn (the quaternion's sign ambiguity at its largest) */
    double z[3] = {0.0, 1.0, 0.0};
    rotation(z, PI - 1e-3, r);
    ring(24, r, t, p, q);
    assert_int_equal(sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, 24, 1.0, m), 0);
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            assert_float_equal(m[4 * a + b], r[a][b], 1e-5);
    /* refused: fewer than 3 points, a fraction outside 0..1, NaN */
    assert_int_equal(sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, 2, 1.0, m), -1);
    assert_int_equal(sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, 24, 1.5, m), -1);
    assert_int_equal(sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, 24, NAN, m), -1);
    q[3][1] = NAN;
    assert_int_equal(sim_fit_rigid((const double(*)[3])p, (const double(*)[3])q, 24, 1.0, m), -1);
    free(p);
    free(q);
}

static void test_follow_moves_x_and_x_prev(void **state)
{
    (void)state;
    float x[2][4] = {{1, 2, 3, 0.5f}, {0, 0, 0, 0}}, xp[2][4] = {{1, 2, 2.5f, 7}, {1, 0, 0, 0}};
    /* a quarter turn about y, then up 1 */
    const float m[12] = {0, 0, 1, 0, 0, 1, 0, 1, -1, 0, 0, 0};
    sim_follow(x, xp, 0, 2, m);
    const float want_x[2][4] = {{3, 3, -1, 0.5f}, {0, 1, 0, 0}};
    const float want_xp[2][4] = {{2.5f, 3, -1, 7}, {0, 1, -1, 0}};
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 4; k++) {
            assert_float_equal(x[i][k], want_x[i][k], 0.0f);
            assert_float_equal(xp[i][k], want_xp[i][k], 0.0f);
        }
}

/* The turn's first 2 s (its fastest part) with a shirt of 4,000 vertices: in the world frame the
   tube lags and twists (2 % max strain, 2 frames redone), fewer rows propagate the turn too
   quickly to show it */
#define TURN_FRAMES      60
#define TURN_SHIRT_VERTS 4000

/* The shirt on the body scene's turn: worst max and p99 strain after the first 10 frames and
   the worst penetrating count; the last frame's positions in out (nv * 4) when out is given. */
static void run_turn(sim_backend b, float follow, float *max_out, float *p99_out, int *pen_out,
                     int *settle_out, int *retried_out, float *out)
{
    sim_scene *sc = NULL;
    sim_garment g = {0};
    sim_reject why = {0};
    const float *xyz, *joints;
    const int32_t *tris;
    int nv, nt;
    assert_int_equal(simt_scene_shirt("turn", 4000, TURN_SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt), 0);
    assert_true(g.num_attachments >= 3);
    sim_desc d = sim_default_desc();
    d.backend = b;
    d.follow = follow;
    d.max_body_vertices = nv;
    d.max_body_triangles = nt;
    sim *s = sim_create(&d, &g, &why);
    sim_garment_free(&g);
    assert_non_null(s);
    *max_out = *p99_out = 0.0f;
    *pen_out = 0;
    *settle_out = *retried_out = 0;
    for (int f = 0; f < TURN_FRAMES; f++) {
        assert_int_equal(sim_scene_eval(sc, f / 30.0, &xyz, &nv, &tris, &nt, &joints), 0);
        sim_frame_stats st;
        assert_int_equal(sim_step(s, xyz, nv, tris, nt, &st, &why), 0);
        /* the world frame may redo a frame for its strain (the moving frame must not) */
        assert_int_equal(
            st.state == SIM_STATE_OK || (follow < 0.0f && st.state == SIM_STATE_RECOVERED), 1);
        *retried_out += st.state == SIM_STATE_RECOVERED;
        if (f >= 10) {
            *max_out = fmaxf(*max_out, st.max_strain);
            *p99_out = fmaxf(*p99_out, st.p99_strain);
        }
        *pen_out = st.penetrating > *pen_out ? st.penetrating : *pen_out;
        *settle_out += st.settle_rounds;
    }
    assert_true(sim_vertex_count(s) <= 2 * TURN_SHIRT_VERTS); /* out's size */
    if (out)
        memcpy(out, sim_positions(s), (size_t)sim_vertex_count(s) * 4 * sizeof *out);
    sim_destroy(s);
    sim_scene_destroy(sc);
}

static void test_turn_keeps_the_strain_limit(void **state)
{
    (void)state;
    sim_backend bs[2];
    int nb = simt_backends(bs);
    float *first = NULL;
    int nfirst = 0;
    for (int k = 0; k < nb; k++) {
        float max_f, p99_f, max_w, p99_w;
        int pen_f, pen_w, settle_f, settle_w, retried_f, retried_w;
        float *pos = calloc(4 * TURN_SHIRT_VERTS * 2, sizeof *pos);
        run_turn(bs[k], 1.0f, &max_f, &p99_f, &pen_f, &settle_f, &retried_f, pos);
        fprintf(stderr,
                "%s: turn, follow 1: max %.2f %% p99 %.2f %%, %d inside, %d settle rounds, "
                "%d frames retried\n",
                simt_backend_name(bs[k]), 100.0 * max_f, 100.0 * p99_f, pen_f, settle_f, retried_f);
        if (k == 0) {
            run_turn(bs[k], -1.0f, &max_w, &p99_w, &pen_w, &settle_w, &retried_w, NULL);
            fprintf(stderr,
                    "%s: turn, world frame: max %.2f %% p99 %.2f %%, %d inside, %d settle rounds, "
                    "%d frames retried\n",
                    simt_backend_name(bs[k]), 100.0 * max_w, 100.0 * p99_w, pen_w, settle_w,
                    retried_w);
            /* what the frame is for: the world frame needs the settle rounds (or more
               iterations) to hold the twist. Since the shirt's armholes (their free edge hangs at
               about 2 % strain, at the rounds' threshold, in either frame: docs/sim-history.md,
               "Arms down: the cause") the frame's own run takes a few rounds too (20 against 292)
               and both end near 2 % (until then 0 rounds, and the world frame's strain over 1.5x
               the moving frame's) */
            assert_true(settle_w > 0 || retried_w > 0);
            assert_true(10 * settle_f < settle_w);
            assert_int_equal(retried_f, 0);
            assert_true(retried_w > 0);
            assert_int_equal(pen_w, 0);
        }
        assert_true(max_f < 0.02f);
        assert_true(p99_f < 0.0105f);
        assert_int_equal(pen_f, 0);
        /* the backends carry the garment alike (test_cl_backend's tolerance) */
        if (k == 0) {
            first = pos;
            nfirst = 4 * TURN_SHIRT_VERTS * 2;
            continue;
        }
        float worst = 0.0f;
        for (int i = 0; i < nfirst; i++)
            worst = fmaxf(worst, fabsf(pos[i] - first[i]));
        fprintf(stderr, "%s vs %s: max |dx| %.3g m\n", simt_backend_name(bs[0]),
                simt_backend_name(bs[k]), (double)worst);
        assert_true(worst <= 1e-4f);
        free(pos);
    }
    free(first);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fit_recovers_a_rigid_motion),
        cmocka_unit_test(test_follow_moves_x_and_x_prev),
        cmocka_unit_test(test_turn_keeps_the_strain_limit),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
