/* Stability scenes from the cloth literature (Baraff & Witkin 1998; Bridson et al. 2002; Provot
 * 1995): each must stay finite and bounded in every frame. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "sim_test_util.h"

#define STAB_N 8 /* 8 x 8 sheet of 0.5 m */

/* A sheet whose top row hangs from a bar: the bar's two triangles, moved and turned by the
 * caller each frame. */
typedef struct bar {
    float v[4 * 3];
    int32_t tris[2 * 3];
} bar;

static void bar_place(bar *b, float cx, float cy, float cz, float angle)
{
    /* a 1.2 m bar along x, 2 cm tall, turned about the vertical axis through its centre */
    float c = cosf(angle), s = sinf(angle);
    const float xs[4] = {-0.6f, 0.6f, 0.6f, -0.6f}, ys[4] = {0.0f, 0.0f, 0.02f, 0.02f};
    for (int i = 0; i < 4; i++) {
        b->v[i * 3] = cx + xs[i] * c;
        b->v[i * 3 + 1] = cy + ys[i];
        b->v[i * 3 + 2] = cz - xs[i] * s;
    }
    const int32_t t[6] = {0, 1, 2, 0, 2, 3};
    for (int i = 0; i < 6; i++)
        b->tris[i] = t[i];
}

static sim *hanging_sheet(sim_backend backend, sim_solver solver)
{
    sim_garment g = {0};
    assert_int_equal(sim_garment_drape(STAB_N * STAB_N, 0.5f, 0.0f, &g), 0);
    for (int i = 0; i < g.num_vertices; i++) {
        float z = g.xyz[i * 3 + 2];
        g.xyz[i * 3 + 1] = 0.75f - z; /* row 0 at y = 1, hanging down */
        g.xyz[i * 3 + 2] = 0.01f;
    }
    sim_attachment at[STAB_N];
    for (int c = 0; c < STAB_N; c++) {
        float u = (g.xyz[c * 3] + 0.6f) / 1.2f;
        at[c] = (sim_attachment){
            .vertex = c, .body_triangle = 0, .bary = {1.0f - u, u, 0.0f}, .offset_m = 0.01f};
    }
    g.attachments = at;
    g.num_attachments = STAB_N;
    sim_desc d = sim_default_desc();
    d.backend = backend;
    d.solver = solver;
    sim *s = sim_create(&d, &g, NULL);
    g.attachments = NULL;
    g.num_attachments = 0;
    sim_garment_free(&g);
    return s;
}

/* Finite, within 3 m of the origin, strain under the divergence bound. */
static void assert_bounded(const sim *s, const sim_frame_stats *st)
{
    assert_true(simt_all_finite(s));
    const float *x = sim_positions(s);
    for (int i = 0; i < sim_vertex_count(s); i++)
        assert_true(fabsf(x[i * 4]) < 3.0f && fabsf(x[i * 4 + 1]) < 3.0f &&
                    fabsf(x[i * 4 + 2]) < 3.0f);
    assert_true(st->state != SIM_STATE_DIVERGED);
}

static int solver_count(sim_backend b)
{
    return b == SIM_BACKEND_C ? 2 : 1; /* the seed variant is a C reference only */
}

/* Bridson et al. 2002 start a sheet from random positions: it must untangle into a sheet. */
static void test_sim_random_start_recovers(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        for (int solver = 0; solver < solver_count(bs[k]); solver++) {
            sim_garment g = {0};
            assert_int_equal(sim_garment_drape(STAB_N * STAB_N, 0.5f, 1.0f, &g), 0);
            srand(7);
            /* the rest shape is taken from the garment, so scramble after creation */
            sim_desc d = sim_default_desc();
            d.backend = bs[k];
            d.solver = (sim_solver)solver;
            sim *s = sim_create(&d, &g, NULL);
            assert_non_null(s);
            float *xyz = malloc((size_t)g.num_vertices * 3 * sizeof *xyz);
            assert_non_null(xyz);
            for (int i = 0; i < g.num_vertices * 3; i++)
                xyz[i] = 0.3f * ((float)rand() / (float)RAND_MAX - 0.5f) + (i % 3 == 1);
            assert_int_equal(sim_set_positions(s, xyz, NULL), 0);
            free(xyz);
            float mx0, p990;
            {
                float far0[9] = {0, -5, 0, 1, -5, 0, 0, -5, 1};
                int32_t tri0[3] = {0, 1, 2};
                sim_frame_stats st0 = {0};
                sim_step(s, far0, 3, tri0, 1, &st0, NULL);
                mx0 = st0.max_strain;
                p990 = st0.p99_strain;
            }
            float far[9] = {0, -5, 0, 1, -5, 0, 0, -5, 1};
            int32_t tri[3] = {0, 1, 2};
            sim_frame_stats st = {0};
            int bad = 0;
            for (int f = 0; f < 40; f++) {
                int r = sim_step(s, far, 3, tri, 1, &st, NULL);
                bad += r < 0;
                assert_true(simt_all_finite(s));
            }
            printf("# %s/%d random start: strain %.3f p99 %.3f after 1 frame, %.3f %.3f after "
                   "40 frames, %d bad frames\n",
                   simt_backend_name(bs[k]), solver, mx0, p990, st.max_strain, st.p99_strain, bad);
            /* untangled: springs back near rest (the seed is held by Provot's 10 % correction
             * alone) */
            assert_true(st.p99_strain < (solver == SIM_SOLVER_SEED ? 0.15f : 0.05f));
            if (solver == SIM_SOLVER_TRYON)
                assert_int_equal(bad, 0);

            sim_destroy(s);
            sim_garment_free(&g);
        }
    }
}

/* Pulled: the bar jerks the hanging sheet sideways at 0.5 to 8 m/s for a quarter second. */
static void test_sim_pulled_sheet_stays_bounded(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    const float speeds[] = {0.5f, 8.0f};
    for (int k = 0; k < n; k++) {
        for (int solver = 0; solver < solver_count(bs[k]); solver++) {
            for (int v = 0; v < 2; v++) {
                sim *s = hanging_sheet(bs[k], (sim_solver)solver);
                assert_non_null(s);
                bar b;
                sim_frame_stats st = {0};
                float x = 0.0f, worst = 0.0f;
                for (int f = 0; f < 18; f++) {
                    if (f >= 4 && f < 12)
                        x += speeds[v] / 30.0f;
                    bar_place(&b, x, 1.0f, 0.0f, 0.0f);
                    sim_step(s, b.v, 4, b.tris, 2, &st, NULL);
                    assert_bounded(s, &st);
                    worst = fmaxf(worst, st.max_strain);
                }
                printf("# %s/%d pulled at %.1f m/s: worst strain %.3f\n", simt_backend_name(bs[k]),
                       solver, speeds[v], worst);
                sim_destroy(s);
            }
        }
    }
}

/* Twist: the bar turns half a turn in two thirds of a second; the sheet winds up without blowing
 * up. */
static void test_sim_half_turn_twist_stays_bounded(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        for (int solver = 0; solver < solver_count(bs[k]); solver++) {
            sim *s = hanging_sheet(bs[k], (sim_solver)solver);
            assert_non_null(s);
            bar b;
            sim_frame_stats st = {0};
            for (int f = 0; f < 30; f++) {
                float a = 3.14159265f * fminf((float)f / 20.0f, 1.0f);
                bar_place(&b, 0.0f, 1.0f, 0.0f, a);
                sim_step(s, b.v, 4, b.tris, 2, &st, NULL);
                assert_bounded(s, &st);
            }
            printf("# %s/%d twist: strain %.3f\n", simt_backend_name(bs[k]), solver, st.max_strain);
            sim_destroy(s);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_random_start_recovers),
        cmocka_unit_test(test_sim_pulled_sheet_stays_bounded),
        cmocka_unit_test(test_sim_half_turn_twist_stays_bounded),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
