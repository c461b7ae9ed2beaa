/* The integration and the spring passes against hand computation. */
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
#include "passes.h"
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
/* xorshift32 (fixed seed) in [lo, hi). */
static float wide_rand(uint32_t *r, float lo, float hi)
{
    *r ^= *r << 13;
    *r ^= *r >> 17;
    *r ^= *r << 5;
    return lo + (hi - lo) * (float)(*r >> 8) / 16777216.0f;
}

/* The spring passes run 4 or 8 springs (vertices) at a time where the CPU allows: one call over a
 * colour must equal, bit for bit, the same springs one call each (the scalar loop). A colour of 203
 * springs on 512 vertices (a random matching: no shared vertex), some ends pinned (w = 0), some
 * springs of zero length, most stretched past the limit, all kinds. Verlet (two vertices at a
 * time) likewise, x_prev included, an odd count so the tail runs scalar. */
static void test_sim_spring_passes_wide_equal_scalar(void **state)
{
    (void)state;
    enum { NV = 512, NS = 203 };
    static float x0[NV][4], xw[NV][4], xs[NV][4], p0[NV][4], pw[NV][4], ps[NV][4];
    static int32_t ends[NS][2], perm[NV], anchor[NV];
    static float rest[NS], tlen[NV];
    static uint8_t kind[NS];
    uint32_t r = 99u;
    for (int i = 0; i < NV; i++) {
        for (int k = 0; k < 3; k++)
            x0[i][k] = wide_rand(&r, -1.0f, 1.0f);
        x0[i][3] = wide_rand(&r, 0.0f, 1.0f) < 0.1f ? 0.0f : wide_rand(&r, 10.0f, 100.0f);
        perm[i] = i;
        for (int k = 0; k < 4; k++)
            p0[i][k] = x0[i][k] + (k < 3 ? wide_rand(&r, -0.01f, 0.01f) : 0.0f);
    }
    for (int i = NV - 1; i > 0; i--) {
        int j = (int)wide_rand(&r, 0.0f, (float)(i + 1)) % (i + 1), t = perm[i];
        perm[i] = perm[j], perm[j] = t;
    }
    for (int s = 0; s < NS; s++) {
        ends[s][0] = perm[2 * s];
        ends[s][1] = perm[2 * s + 1];
        if (s % 17 == 5) /* zero length */
            for (int k = 0; k < 3; k++)
                x0[ends[s][1]][k] = x0[ends[s][0]][k];
        float d[3] = {x0[ends[s][1]][0] - x0[ends[s][0]][0], x0[ends[s][1]][1] - x0[ends[s][0]][1],
                      x0[ends[s][1]][2] - x0[ends[s][0]][2]};
        rest[s] = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) * wide_rand(&r, 0.8f, 1.05f);
        kind[s] = (uint8_t)(s % 7 == 3   ? SIM_SPRING_BEND
                            : s % 7 == 1 ? SIM_SPRING_SHEAR
                                         : SIM_SPRING_STRETCH);
    }
    for (int i = 0; i < NV; i++) {
        anchor[i] = i % 5 == 0 ? -1 : perm[(i * 7) % NV];
        tlen[i] = wide_rand(&r, 0.5f, 2.0f);
    }
    const float alpha[SIM_SPRING_KINDS] = {1e-3f, 2e-3f, 5e-2f};
    const float g[3] = {0.0f, -1e-4f, 0.0f};
    for (int pass = 0; pass < 5; pass++) {
        memcpy(xw, x0, sizeof x0);
        memcpy(xs, x0, sizeof x0);
        memcpy(pw, p0, sizeof p0);
        memcpy(ps, p0, sizeof p0);
        if (pass == 0) {
            sim_project_springs(xw, (const int32_t(*)[2])ends, rest, kind, alpha, 0, NS);
            for (int s = 0; s < NS; s++)
                sim_project_springs(xs, (const int32_t(*)[2])ends, rest, kind, alpha, s, s + 1);
        } else if (pass == 1) {
            sim_strain_limit(xw, (const int32_t(*)[2])ends, rest, kind, 0, NS, 0.01f);
            for (int s = 0; s < NS; s++)
                sim_strain_limit(xs, (const int32_t(*)[2])ends, rest, kind, s, s + 1, 0.01f);
        } else if (pass == 4) {
            /* the clamp on stretch and shear (the seed's Provot correction) */
            sim_clamp_springs(xw, (const int32_t(*)[2])ends, rest, kind, 0, NS, SIM_KINDS_PROVOT,
                              0.02f);
            for (int s = 0; s < NS; s++)
                sim_clamp_springs(xs, (const int32_t(*)[2])ends, rest, kind, s, s + 1,
                                  SIM_KINDS_PROVOT, 0.02f);
        } else if (pass == 3) {
            sim_verlet(xw, pw, 0, NV - 1, 0.999f, g);
            for (int i = 0; i < NV - 1; i++)
                sim_verlet(xs, ps, i, i + 1, 0.999f, g);
            assert_memory_equal(pw, ps, sizeof pw);
        } else {
            /* tethers move free vertices towards anchors that do not move: anchors pinned */
            for (int i = 0; i < NV; i++)
                if (anchor[i] >= 0)
                    xw[anchor[i]][3] = xs[anchor[i]][3] = 0.0f;
            sim_tethers(xw, anchor, tlen, 0, NV, 0.01f);
            for (int i = 0; i < NV; i++)
                sim_tethers(xs, anchor, tlen, i, i + 1, 0.01f);
        }
        assert_memory_equal(xw, xs, sizeof xw);
        assert_memory_not_equal(xw, x0, sizeof xw); /* something moved */
    }
}

/* The one clamp: which kinds it takes, and to what length. Three springs along x, each stretched
   to 1.5 rest (ends of equal weight), one of each kind. */
static void test_sim_clamp_kinds_by_hand(void **state)
{
    (void)state;
    int32_t ends[3][2] = {{0, 1}, {2, 3}, {4, 5}};
    float rest[3] = {1.0f, 1.0f, 1.0f};
    uint8_t kind[3] = {SIM_SPRING_STRETCH, SIM_SPRING_SHEAR, SIM_SPRING_BEND};
    for (int provot = 0; provot < 2; provot++) {
        float x[6][4];
        for (int i = 0; i < 6; i++) {
            x[i][0] = i % 2 ? 1.5f : 0.0f;
            x[i][1] = (float)(i / 2);
            x[i][2] = 0.0f;
            x[i][3] = 1.0f;
        }
        if (provot)
            sim_clamp_springs(x, (const int32_t(*)[2])ends, rest, kind, 0, 3, SIM_KINDS_PROVOT,
                              0.1f);
        else
            sim_strain_limit(x, (const int32_t(*)[2])ends, rest, kind, 0, 3, 0.1f);
        /* stretch: always to 1.1 rest, each end moved half way; shear: only by Provot's; bend:
           never */
        assert_float_equal(x[1][0] - x[0][0], 1.1f, 1e-6f);
        assert_float_equal(x[0][0], 0.2f, 1e-6f);
        assert_float_equal(x[3][0] - x[2][0], provot ? 1.1f : 1.5f, 1e-6f);
        assert_float_equal(x[5][0] - x[4][0], 1.5f, 1e-6f);
    }
}

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

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* sim_strain_stats against a sort: 2,000 stretch springs of random lengths (a tenth of them
   repeating one length: ties), 500 shear springs stretched far more that must not count. */
static void test_sim_strain_stats_match_sort(void **state)
{
    (void)state;
    enum { NS = 2000, NO = 500 };
    sim_cloth c;
    memset(&c, 0, sizeof c);
    c.ns = NS + NO;
    c.nv = 2 * c.ns;
    c.x = calloc((size_t)c.nv, sizeof *c.x);
    c.ends = calloc((size_t)c.ns, sizeof *c.ends);
    c.rest = calloc((size_t)c.ns, sizeof *c.rest);
    c.kind = calloc((size_t)c.ns, 1);
    float *scratch = calloc((size_t)c.ns, sizeof *scratch), *expect = calloc(NS, sizeof *expect);
    uint32_t seed = 99u;
    for (int s = 0; s < c.ns; s++) {
        seed = seed * 1664525u + 1013904223u;
        float len = s % 10 == 3 ? 1.02f : 0.95f + 0.1f * (float)(seed >> 8) / 16777216.0f;
        c.kind[s] = s < NS ? SIM_SPRING_STRETCH : SIM_SPRING_SHEAR;
        if (s >= NS)
            len = 2.0f;
        c.ends[s][0] = 2 * s;
        c.ends[s][1] = 2 * s + 1;
        c.x[2 * s + 1][0] = len;
        c.rest[s] = 1.0f;
    }
    for (int s = 0; s < NS; s++)
        expect[s] = (sqrtf(c.x[2 * s + 1][0] * c.x[2 * s + 1][0]) - 1.0f) / 1.0f;
    qsort(expect, NS, sizeof *expect, cmp_float);
    float mx = -1.0f, p99 = -1.0f;
    sim_strain_stats(&c, scratch, &mx, &p99);
    assert_true(mx == expect[NS - 1]);
    assert_true(p99 == expect[(int)floorf(0.99f * (float)(NS - 1))]);
    free(c.x);
    free(c.ends);
    free(c.rest);
    free(c.kind);
    free(scratch);
    free(expect);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_verlet_free_fall_matches_closed_form),
        cmocka_unit_test(test_sim_strain_stats_match_sort),
        cmocka_unit_test(test_sim_project_spring_by_hand),
        cmocka_unit_test(test_sim_spring_passes_wide_equal_scalar),
        cmocka_unit_test(test_sim_clamp_kinds_by_hand),
        cmocka_unit_test(test_sim_spring_force_by_hand),
        cmocka_unit_test(test_sim_frame_free_fall),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
