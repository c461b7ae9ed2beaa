/* A frame no attempt solves, on a garment with a moving frame: the last good cloth is carried
 * rigidly with the body under its waist band (sim/recover.c), never torn by body parts that move
 * apart, and on with the body; after SIM_CARRY_REDRESS_RUN frames carried in a row the garment
 * is dressed again as made (sim.c, carry_good), so a last good cloth the solver cannot leave is
 * not carried for ever. */
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
#include "scene.h"
#include "sim_test_util.h"

#define BODY_VERTS  2000
#define SHIRT_VERTS 1000
#define FRAMES      45
/* Rigid motion keeps every spring's length to float rounding (measured 0.0000-0.0005 %); the
   carry point by point, each point with the triangle at its nearest body vertex, stretched the
   shirt on the first 1.5 s of arms_down to 8.6 % (C; docs/sim-history-5.md, "The clips: the
   causes") */
#define RIGID_STRAIN 0.001f
/* the attached vertices against their attachments' places on a body that turns rigidly, metres */
#define ATTACH_TOL_M 0.001f

/* The shirt on motion where every attempt fails (gravity 1e7 m/s^2, the strain limit at 100 %).
 * With the contacts searched again after a long move (docs/collision.md, "Response") the body
 * holds such a cloth and the strain limit at its default keeps it under SIM_DIVERGE_STRAIN (24.6 %
 * measured on turn): the loose limit lets it blow up. */
static sim *make_unsolvable(sim_backend b, const char *motion, sim_scene **sc, sim_garment *g,
                            sim_desc *d)
{
    int nv, nt;
    assert_int_equal(simt_scene_shirt(motion, BODY_VERTS, SHIRT_VERTS, 0.0f, sc, g, &nv, &nt), 0);
    *d = sim_default_desc();
    d->backend = b;
    d->gravity_m_s2 = 1e7f;
    d->strain_limit = 1.0f;
    sim_reject why = {0};
    sim *s = sim_create(d, g, &why);
    assert_non_null(s);
    return s;
}

/* Frame 0 has nothing to carry from (DIVERGED), every later frame is CARRIED. Returns the worst
 * published max strain; *attach_m the farthest an attached vertex lies from its attachment's
 * place on the last frame. */
static float run_unsolvable(sim_backend b, const char *motion, float *attach_m)
{
    sim_scene *sc = NULL;
    sim_garment g = {0};
    sim_desc d;
    sim *s = make_unsolvable(b, motion, &sc, &g, &d);
    int nv, nt;
    float worst = 0.0f;
    const float *xyz;
    const int32_t *tris;
    for (int f = 0; f < FRAMES; f++) {
        assert_int_equal(sim_scene_eval(sc, f * d.frame_dt_s, &xyz, &nv, &tris, &nt, NULL), 0);
        sim_frame_stats st;
        int r = sim_step(s, xyz, nv, tris, nt, &st, NULL);
        if (f == 0) {
            assert_int_equal(r, -SIM_ERR_DIVERGED);
            continue;
        }
        assert_int_equal(r, 0);
        assert_int_equal(st.state, SIM_STATE_CARRIED);
        worst = fmaxf(worst, st.max_strain);
    }
    assert_true(simt_all_finite(s));
    *attach_m = 0.0f;
    for (int a = 0; a < g.num_attachments; a++)
        *attach_m = fmaxf(*attach_m, simt_attachment_off_m(s, &g.attachments[a], xyz, tris));
    sim_destroy(s);
    sim_garment_free(&g);
    sim_scene_destroy(sc);
    return worst;
}

static void test_sim_carry_rigid_keeps_the_garment_whole(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        float attach_turn, attach_arms;
        float turn = run_unsolvable(bs[k], "turn", &attach_turn);
        float arms = run_unsolvable(bs[k], "arms_down", &attach_arms);
        printf("# %s: carried frames' worst strain: turn %.4f %%, arms_down %.4f %%; attached "
               "vertices on the turning body within %.2f mm of their places\n",
               simt_backend_name(bs[k]), 100.0 * turn, 100.0 * arms, 1000.0 * attach_turn);
        assert_true(turn <= RIGID_STRAIN);
        assert_true(arms <= RIGID_STRAIN);
        assert_true(attach_turn <= ATTACH_TOL_M);
    }
}

/* Every attempt fails, as above, from a stretched last good cloth (the shirt as made scaled 1.05
   about its centre, set after the first frame; its attached vertices keep their places, so the
   springs by them stretch most: 29 % measured): the carried frames publish it as it is until the
   run reaches SIM_CARRY_REDRESS_RUN, then the garment as made, unstretched. Carried rigidly for
   ever, every frame published the stretched cloth. */
static void test_sim_carry_redresses_after_a_long_run(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        sim_scene *sc = NULL;
        sim_garment g = {0};
        sim_desc d;
        sim *s = make_unsolvable(bs[k], "still", &sc, &g, &d);
        sim_reject why = {0};
        int nv, nt;
        const float *xyz;
        const int32_t *tris;
        float stretched_seen = 0.0f, after = 1.0f;
        int redressed_at = -1;
        for (int f = 0; f < 3 * SIM_CARRY_REDRESS_RUN; f++) {
            assert_int_equal(sim_scene_eval(sc, f * d.frame_dt_s, &xyz, &nv, &tris, &nt, NULL), 0);
            sim_frame_stats st;
            int r = sim_step(s, xyz, nv, tris, nt, &st, NULL);
            if (f == 0) {
                assert_int_equal(r, -SIM_ERR_DIVERGED);
                float c[3] = {0, 0, 0}, *p = malloc((size_t)g.num_vertices * 3 * sizeof *p);
                assert_non_null(p);
                for (int i = 0; i < g.num_vertices; i++)
                    for (int j = 0; j < 3; j++)
                        c[j] += g.xyz[i * 3 + j] / (float)g.num_vertices;
                for (int i = 0; i < g.num_vertices * 3; i++)
                    p[i] = c[i % 3] + 1.05f * (g.xyz[i] - c[i % 3]);
                assert_int_equal(sim_set_positions(s, p, &why), 0);
                free(p);
                continue;
            }
            assert_int_equal(r, 0);
            assert_int_equal(st.state, SIM_STATE_CARRIED);
            if (st.max_strain > 0.04f && redressed_at < 0)
                stretched_seen = fmaxf(stretched_seen, st.max_strain);
            if (st.max_strain <= RIGID_STRAIN && redressed_at < 0)
                redressed_at = f;
            if (redressed_at >= 0)
                after = f == redressed_at ? st.max_strain : fmaxf(after, st.max_strain);
        }
        printf("# %s: the stretched cloth carried at %.2f %%, dressed again at frame %d, then "
               "%.4f %%\n",
               simt_backend_name(bs[k]), 100.0 * stretched_seen, redressed_at, 100.0 * after);
        assert_true(stretched_seen > 0.04f);
        assert_int_equal(redressed_at, SIM_CARRY_REDRESS_RUN + 1);
        assert_true(after <= RIGID_STRAIN);
        sim_destroy(s);
        sim_garment_free(&g);
        sim_scene_destroy(sc);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_carry_rigid_keeps_the_garment_whole),
        cmocka_unit_test(test_sim_carry_redresses_after_a_long_run),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
