/* Frames no attempt solves are carried by the body (sim/carry.c): nothing stays behind. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "carry.h"
#include "cloth.h"
#include "scene.h"
#include "sim_test_util.h"

/* Deterministic uniform numbers in [-1, 1] (a fixed-seed LCG, so failures reproduce). */
static float rnd(unsigned *s)
{
    *s = *s * 1664525u + 1013904223u;
    return 2.0f * (float)(*s >> 8) / 16777216.0f - 1.0f;
}

/* 30 degrees about the unit axis (1, 2, 2)/3 and a 0.4 m move: q = R p + t. */
static void rigid(const float p[3], float q[3])
{
    double a = 30.0 * 3.141592653589793 / 180.0, c = cos(a), s = sin(a);
    double u[3] = {1.0 / 3, 2.0 / 3, 2.0 / 3}, t[3] = {0.4, -0.1, 0.2};
    double d = u[0] * p[0] + u[1] * p[1] + u[2] * p[2];
    double x[3] = {u[1] * p[2] - u[2] * p[1], u[2] * p[0] - u[0] * p[2], u[0] * p[1] - u[1] * p[0]};
    for (int k = 0; k < 3; k++)
        q[k] = (float)(p[k] * c + x[k] * s + u[k] * d * (1.0 - c) + t[k]);
}

/* A body moved rigidly carries every point near it by the same motion (each triangle's frame
 * turns by the body's rotation, whichever vertex a point is nearest to). */
static void test_carry_follows_a_rigid_body_motion(void **state)
{
    (void)state;
    sim_scene *sc = simt_sphere();
    const float *xyz, *joints;
    const int32_t *tris;
    int nv, nt;
    sim_scene_eval(sc, 0.0, &xyz, &nv, &tris, &nt, &joints);
    sim_body b = {.nv = nv, .nt = nt, .have_prev = 1};
    b.v = calloc((size_t)nv, sizeof *b.v);
    b.v_prev = calloc((size_t)nv, sizeof *b.v_prev);
    b.tris = calloc((size_t)nt, sizeof *b.tris);
    enum { N = 400 };
    float(*x)[4] = calloc(N, sizeof *x), (*want)[4] = calloc(N, sizeof *want);
    assert_true(b.v && b.v_prev && b.tris && x && want);
    for (int i = 0; i < nv; i++) {
        memcpy(b.v_prev[i], xyz + i * 3, 3 * sizeof(float));
        rigid(b.v_prev[i], b.v[i]);
    }
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            b.tris[t][k] = tris[t * 3 + k];
    unsigned seed = 7;
    for (int i = 0; i < N; i++) { /* within 8 cm of the 0.2 m sphere's surface, either side */
        float d[3] = {rnd(&seed), rnd(&seed), rnd(&seed)};
        float n = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + 1e-6f;
        float r = 0.2f + 0.08f * rnd(&seed);
        for (int k = 0; k < 3; k++)
            x[i][k] = d[k] / n * r;
        rigid(x[i], want[i]);
    }
    sim_carry *c = sim_carry_create(nv);
    assert_non_null(c);
    assert_int_equal(sim_carry_points(c, &b, x, N), 0);
    float worst = 0.0f;
    for (int i = 0; i < N; i++)
        for (int k = 0; k < 3; k++)
            worst = fmaxf(worst, fabsf(x[i][k] - want[i][k]));
    printf("# worst carry error %.2e m\n", worst);
    assert_true(worst < 1e-5f);
    /* no earlier body frame: nothing to carry from, the points stay */
    b.have_prev = 0;
    float keep = x[0][0];
    assert_int_equal(sim_carry_points(c, &b, x, N), -1);
    assert_true(x[0][0] == keep);
    sim_carry_destroy(c);
    free(x);
    free(want);
    free(b.v);
    free(b.v_prev);
    free(b.tris);
    sim_scene_destroy(sc);
}

static void centroid(const sim *s, double out[3])
{
    const float *x = sim_positions(s); /* [vertex][4] */
    int n = sim_vertex_count(s);
    out[0] = out[1] = out[2] = 0.0;
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            out[k] += x[i * 4 + k] / n;
}

/* A cloth no attempt can solve (gravity of 1e7 m/s^2) over a body walking 5 cm a frame: from
 * the second frame on every frame is published CARRIED, measured, and the garment moves with
 * the body: after 12 frames it is where the body carried it, not 0.55 m behind. */
static void test_unsolvable_frames_are_carried_with_the_body(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    sim_scene *sc = simt_sphere();
    const float *xyz0, *joints;
    const int32_t *tris;
    int nv, nt;
    sim_scene_eval(sc, 0.0, &xyz0, &nv, &tris, &nt, &joints);
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    assert_non_null(xyz);
    for (int k = 0; k < n; k++) {
        sim_desc d = sim_default_desc();
        d.gravity_m_s2 = 1e7f;
        sim *s = simt_drape(bs[k], SIM_SOLVER_TRYON, 10, &d);
        assert_non_null(s);
        double c0[3], c1[3];
        centroid(s, c0);
        const float step = 0.05f;
        int frames = 12, carried = 0;
        for (int f = 0; f < frames; f++) {
            for (int i = 0; i < nv * 3; i++)
                xyz[i] = xyz0[i] + (i % 3 == 0 ? step * (float)f : 0.0f);
            sim_frame_stats st;
            int r = sim_step(s, xyz, nv, tris, nt, &st, NULL);
            if (f == 0) { /* nothing to carry from yet */
                assert_int_equal(r, -SIM_ERR_DIVERGED);
                continue;
            }
            assert_int_equal(r, 0);
            assert_int_equal(st.state, SIM_STATE_CARRIED);
            assert_true(st.max_strain >= 0.0f && st.penetrating >= 0);
            carried++;
        }
        assert_true(simt_all_finite(s));
        centroid(s, c1);
        printf("# %s: %d frames carried, the garment moved %.4f m (the body %.4f m)\n",
               simt_backend_name(bs[k]), carried, c1[0] - c0[0], step * (frames - 1));
        assert_int_equal(carried, frames - 1);
        assert_true(fabs((c1[0] - c0[0]) - step * (frames - 1)) < 1e-4);
        assert_true(fabs(c1[1] - c0[1]) < 1e-4 && fabs(c1[2] - c0[2]) < 1e-4);
        sim_destroy(s);
    }
    free(xyz);
    sim_scene_destroy(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_carry_follows_a_rigid_body_motion),
        cmocka_unit_test(test_unsolvable_frames_are_carried_with_the_body),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
