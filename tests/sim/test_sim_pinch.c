/* A pinch is no tear (cloth.h, SIM_PINCH_SPRINGS): a frame whose every attempt leaves a few
 * springs past SIM_DIVERGE_STRAIN, and nothing else torn, is published as solved with that
 * strain said, instead of the last good cloth carried; springs between two glued vertices,
 * as long as the body makes them, are no tear at any length. The pinch is made by the shirt's
 * glued top row: one body triangle under it moved sideways by two springs' length, so its glued
 * vertex goes with it and the springs to its neighbours stretch past SIM_DIVERGE_STRAIN whatever
 * the solver does. (A cloth torn for real is carried: test_sim_carry.) */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "cloth.h"
#include "sim_test_util.h"

#define BODY_VERTS  2000
#define SHIRT_VERTS 1500

/* The shirt standing still for a few frames, then one frame with the body triangles of the
 * first attachment's vertex moved sideways by `springs` times the top row's spring length: that
 * frame's statistics into *st, the distance of the first attachment's vertex from its moved
 * triangle's attachment point into *off_m (0: it went with the body), its springs past
 * SIM_DIVERGE_STRAIN into *over. */
static void pinch_frame(sim_backend b, float springs, sim_frame_stats *st, float *off_m, int *over)
{
    sim_scene *sc;
    sim_garment g;
    int nv, nt;
    assert_int_equal(simt_scene_shirt("still", BODY_VERTS, SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt),
                     0);
    assert_true(g.num_attachments > 8);
    const float *xyz0;
    const int32_t *tris;
    sim_scene_eval(sc, 0.0, &xyz0, &nv, &tris, &nt, NULL);
    float *body = malloc((size_t)nv * 3 * sizeof *body);
    uint8_t *moved = calloc((size_t)nv, 1);
    assert_true(body && moved);
    memcpy(body, xyz0, (size_t)nv * 3 * sizeof *body);
    const float *p = g.xyz;
    float spring_m = sqrtf((p[3] - p[0]) * (p[3] - p[0]) + (p[4] - p[1]) * (p[4] - p[1]) +
                           (p[5] - p[2]) * (p[5] - p[2]));
    sim_desc d = sim_default_desc();
    d.backend = b;
    sim_reject why = {0};
    sim *s = sim_create(&d, &g, &why);
    assert_non_null(s);
    for (int f = 0; f < 4; f++)
        assert_int_equal(sim_step(s, body, nv, tris, nt, st, &why), 0);
    int v0 = g.attachments[0].vertex, glued = 0; /* a vertex may hang from several triangles */
    for (int k = 0; k < g.num_attachments; k++) {
        const int32_t *t = &tris[g.attachments[k].body_triangle * 3];
        int first = g.attachments[k].vertex == v0;
        glued += first;
        if (first)
            for (int c = 0; c < 3; c++)
                moved[t[c]] = 1;
    }
    assert_true(glued >= 1);
    for (int i = 0; i < nv; i++)
        body[i * 3] += moved[i] ? springs * spring_m : 0.0f;
    assert_int_equal(sim_step(s, body, nv, tris, nt, st, &why), 0);
    float free_max;
    *over = sim_strain_count_over(&s->cloth, SIM_DIVERGE_STRAIN, &free_max);
    *off_m = simt_attachment_off_m(s, &g.attachments[0], body, tris);
    sim_destroy(s);
    sim_garment_free(&g);
    sim_scene_destroy(sc);
    free(body);
    free(moved);
}

/* The bounds: a few springs under SIM_PINCH_STRAIN pinch; more, or one past it, tear. */
static void test_pinch_bounds(void **state)
{
    (void)state;
    assert_true(sim_is_pinch(0.9f, 1));
    assert_true(sim_is_pinch(SIM_PINCH_STRAIN * 0.99f, SIM_PINCH_SPRINGS));
    assert_false(sim_is_pinch(0.9f, SIM_PINCH_SPRINGS + 1));
    assert_false(sim_is_pinch(SIM_PINCH_STRAIN, 1));
}

static void test_a_pinch_is_published(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        sim_frame_stats st;
        float off;
        int over;
        pinch_frame(bs[k], 2.0f, &st, &off, &over);
        printf("# %s, one glued vertex moved: state %d, max strain %.2f, %d springs past 50 %%, "
               "%.1f mm from its triangle\n",
               simt_backend_name(bs[k]), (int)st.state, st.max_strain, over, 1000.0f * off);
        assert_true(st.state != SIM_STATE_CARRIED && st.state != SIM_STATE_DIVERGED);
        assert_true(over > 0 && over <= SIM_PINCH_SPRINGS);
        assert_true(st.max_strain > SIM_DIVERGE_STRAIN && st.max_strain < SIM_PINCH_STRAIN);
        assert_true(off < 0.002f);                  /* the glued vertex went with its triangle */
        pinch_frame(bs[k], 6.0f, &st, &off, &over); /* past SIM_PINCH_STRAIN */
        printf("# %s, one glued vertex moved 6 springs: state %d, max strain %.2f, %d free "
               "springs past 50 %%, %.1f mm from its triangle\n",
               simt_backend_name(bs[k]), (int)st.state, st.max_strain, over, 1000.0f * off);
        /* only the springs between glued vertices stay past SIM_PINCH_STRAIN: the body's own
           stretch, which no attempt can mend, is no tear either */
        assert_true(st.state != SIM_STATE_CARRIED && st.state != SIM_STATE_DIVERGED);
        assert_true(st.max_strain > SIM_PINCH_STRAIN);
        assert_true(over <= SIM_PINCH_SPRINGS);
        assert_true(off < 0.002f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pinch_bounds),
        cmocka_unit_test(test_a_pinch_is_published),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
