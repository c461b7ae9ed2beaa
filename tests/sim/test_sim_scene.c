/* The benchmark's body scene: "all" plays every motion, tells which one plays when, and never
 * jumps between them (a jump would measure the scene's cut, not the cloth); a garment made on one
 * body detail moves to another (the bench's --ref-body-verts); the shirt's hem sits at the hips
 * unless asked lower. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bodyfit.h"
#include "scene.h"
#include "sim.h"
#include "sim_test_util.h"

/* Largest distance any body vertex moves between frames f - 1 and f, metres. */
static float frame_jump(sim_scene *sc, float *prev, int f)
{
    const float *xyz, *joints;
    const int32_t *tris;
    int nv, nt;
    assert_int_equal(sim_scene_eval(sc, f / 30.0, &xyz, &nv, &tris, &nt, &joints), 0);
    float jump = 0.0f;
    for (int i = 0; f > 0 && i < nv; i++) {
        float d2 = 0.0f;
        for (int k = 0; k < 3; k++)
            d2 += (xyz[i * 3 + k] - prev[i * 3 + k]) * (xyz[i * 3 + k] - prev[i * 3 + k]);
        jump = fmaxf(jump, sqrtf(d2));
    }
    memcpy(prev, xyz, (size_t)nv * 3 * sizeof *prev);
    return jump;
}

static void test_all_segments_in_order(void **state)
{
    (void)state;
    char err[160] = "";
    sim_scene *sc = sim_scene_body("all", 4000, err, sizeof err);
    assert_non_null(sc);
    assert_int_equal(sim_scene_segment_count(), 5);
    const char *want[] = {"still", "arm_raise", "turn", "walk", "fast_swing"};
    int last = -1, seen = 0;
    double total = sim_scene_duration(sc), local;
    for (double t = 0.0; t < total; t += 0.05) {
        int k = sim_scene_segment(sc, t, &local);
        assert_true(k >= 0 && k < 5);
        assert_true(local >= 0.0 && local < 4.0 + 1e-9);
        assert_int_equal(k, sim_scene_all_segment(t, NULL));
        if (k != last) {
            assert_int_equal(k, last + 1); /* each motion once, in order */
            assert_string_equal(sim_scene_segment_name(k), want[k]);
            seen++;
            last = k;
        }
    }
    assert_int_equal(seen, 5);
    assert_int_equal(sim_scene_segment(sc, total + 0.01, NULL), 0); /* it loops */
    assert_string_equal(sim_scene_segment_name(5), "none");
    sim_scene_destroy(sc);

    sim_scene *walk = sim_scene_body("walk", 4000, err, sizeof err);
    assert_non_null(walk);
    assert_int_equal(sim_scene_segment(walk, 1.0, &local), -1);
    sim_scene_destroy(walk);
}

/* Between any two frames no body vertex moves more than a fast swing's hand does (the wrist at
 * 3.9 m/s is 13 cm a frame, the fingertips more), and at the seam between two motions no more
 * than in the frames on either side of it: the motions crossfade, the body never jumps (before,
 * the arm went from 100 degrees raised to the A-pose in one frame: 0.5 m). */
static void test_all_never_jumps(void **state)
{
    (void)state;
    char err[160] = "";
    sim_scene *sc = sim_scene_body("all", 4000, err, sizeof err);
    assert_non_null(sc);
    int frames = (int)(sim_scene_duration(sc) * 30.0) + 30; /* and on into the loop */
    float *prev = malloc(60000 * 3 * sizeof *prev), *jump = calloc((size_t)frames, sizeof *jump);
    assert_true(prev && jump);
    float worst = 0.0f;
    for (int f = 0; f < frames; f++)
        worst = fmaxf(worst, jump[f] = frame_jump(sc, prev, f));
    print_message("# largest move between frames: %.1f mm\n", worst * 1000.0f);
    assert_true(worst < 0.2f);
    int seams = 0;
    for (int f = 2; f + 1 < frames; f++) {
        if (sim_scene_segment(sc, f / 30.0, NULL) == sim_scene_segment(sc, (f - 1) / 30.0, NULL))
            continue;
        float around = fmaxf(jump[f - 1], jump[f + 1]);
        print_message("# seam at frame %d: %.1f mm (%.1f mm around it)\n", f, jump[f] * 1000.0f,
                      around * 1000.0f);
        assert_true(jump[f] <= 1.1f * around + 0.002f);
        seams++;
    }
    assert_int_equal(seams, 5);
    free(prev);
    free(jump);
    sim_scene_destroy(sc);
}

/* Where attachment a puts its vertex on body (xyz, tris): sum of bary * corners + offset * unit
 * normal, as the solver places it. */
static void attached_at(const sim_attachment *a, const float *xyz, const int32_t *tris,
                        float out[3])
{
    const int32_t *v = &tris[a->body_triangle * 3];
    const float *p0 = &xyz[v[0] * 3], *p1 = &xyz[v[1] * 3], *p2 = &xyz[v[2] * 3];
    float e1[3], e2[3], n[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = p1[k] - p0[k];
        e2[k] = p2[k] - p0[k];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++)
        out[k] =
            a->bary[0] * p0[k] + a->bary[1] * p1[k] + a->bary[2] * p2[k] + a->offset_m * n[k] / len;
}

/* A shirt made on the 4,000-vertex body, rebound to the 6,000-vertex one in the same pose: every
 * attachment still puts its vertex where it is (to 0.05 mm), on a triangle whose foot is within
 * 5 mm of the old one (the two bodies' surfaces are that close: 3.1 mm here) and as far below the
 * vertex as before (to 3 mm); a body with a NaN is refused and changes nothing. */
static void test_rebind_to_other_detail(void **state)
{
    (void)state;
    char err[160] = "";
    sim_scene *a = sim_scene_body("still", 4000, err, sizeof err);
    sim_scene *b = sim_scene_body("still", 6000, err, sizeof err);
    assert_true(a && b);
    const float *xa, *xb, *ja;
    const int32_t *ta, *tb;
    int nva, nta, nvb, ntb;
    assert_int_equal(sim_scene_eval(a, 0.0, &xa, &nva, &ta, &nta, &ja), 0);
    assert_int_equal(sim_scene_eval(b, 0.0, &xb, &nvb, &tb, &ntb, NULL), 0);
    assert_true(nvb > nva);
    sim_garment g = {0};
    sim_reject why = {0};
    assert_int_equal(sim_garment_shirt(xa, nva, ta, nta, ja, 2000, 0.0f, 0.0f, &g, &why), 0);
    assert_true(g.num_attachments >= 3);
    size_t bytes = (size_t)g.num_attachments * sizeof *g.attachments;
    sim_attachment *old = malloc(bytes);
    assert_non_null(old);
    memcpy(old, g.attachments, bytes);

    /* refused: a NaN in the new body; nothing changed */
    float *bad = malloc((size_t)nvb * 3 * sizeof *bad);
    assert_non_null(bad);
    memcpy(bad, xb, (size_t)nvb * 3 * sizeof *bad);
    bad[7] = NAN;
    assert_int_equal(sim_garment_rebind(&g, xa, nva, ta, nta, bad, nvb, tb, ntb, &why),
                     -SIM_ERR_NOT_FINITE);
    assert_memory_equal(g.attachments, old, bytes);

    assert_int_equal(sim_garment_rebind(&g, xa, nva, ta, nta, xb, nvb, tb, ntb, &why), 0);
    assert_int_equal(sim_garment_validate(&g, ntb, &why), 0);
    float worst_place = 0.0f, worst_foot = 0.0f;
    for (int i = 0; i < g.num_attachments; i++) {
        const sim_attachment *n = &g.attachments[i];
        assert_int_equal(n->vertex, old[i].vertex);
        float p[3], fa[3], fb[3];
        attached_at(n, xb, tb, p);
        sim_attachment foot_a = old[i], foot_b = *n;
        foot_a.offset_m = foot_b.offset_m = 0.0f;
        attached_at(&foot_a, xa, ta, fa);
        attached_at(&foot_b, xb, tb, fb);
        float dp = 0.0f, df = 0.0f;
        for (int k = 0; k < 3; k++) {
            dp += (p[k] - g.xyz[n->vertex * 3 + k]) * (p[k] - g.xyz[n->vertex * 3 + k]);
            df += (fa[k] - fb[k]) * (fa[k] - fb[k]);
        }
        worst_place = fmaxf(worst_place, sqrtf(dp));
        worst_foot = fmaxf(worst_foot, sqrtf(df));
        assert_true(fabsf(n->offset_m - old[i].offset_m) < 0.003f);
    }
    print_message("# rebound %d attachments: placed within %.3f mm, feet moved up to %.2f mm\n",
                  g.num_attachments, worst_place * 1000.0f, worst_foot * 1000.0f);
    assert_true(worst_place < 5e-5f);
    assert_true(worst_foot < 0.006f); /* the bodies differ by some mm where the top row sits */
    free(bad);
    free(old);
    sim_garment_free(&g);
    sim_scene_destroy(a);
    sim_scene_destroy(b);
}

/* The shirt's lowest row, metres (y), made with hem_m on the body "still" at frame 0. */
static float shirt_hem_y(float hem_m, int *code)
{
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv, nt;
    *code = -simt_scene_shirt("still", 6000, 2000, hem_m, &sc, &g, &nv, &nt);
    assert_non_null(sc);
    float lo = INFINITY;
    for (int i = 0; *code == 0 && i < g.num_vertices; i++)
        lo = fminf(lo, g.xyz[i * 3 + 1]);
    sim_garment_free(&g);
    sim_scene_destroy(sc);
    return lo;
}

/* The default hem is above the crotch (the lowest body point near the midline), where nothing
   of the legs is inside it: a straight tube around both thighs has no solution in a stride
   (docs/sim.md, "The hem and the error"); 0.25 m asks for that tunic. A bad hem is refused. */
static void test_shirt_hem_at_the_hips(void **state)
{
    (void)state;
    char err[160] = "";
    sim_scene *sc = sim_scene_body("still", 6000, err, sizeof err);
    assert_non_null(sc);
    const float *xyz;
    const int32_t *tris;
    int nv, nt;
    assert_int_equal(sim_scene_eval(sc, 0.0, &xyz, &nv, &tris, &nt, NULL), 0);
    float cx = 0.0f, crotch = INFINITY;
    for (int i = 0; i < nv; i++)
        cx += xyz[i * 3] / (float)nv;
    for (int i = 0; i < nv; i++)
        if (fabsf(xyz[i * 3] - cx) < 0.015f && xyz[i * 3 + 1] > 0.5f)
            crotch = fminf(crotch, xyz[i * 3 + 1]);
    sim_scene_destroy(sc);
    int code;
    float hem = shirt_hem_y(0.0f, &code);
    assert_int_equal(code, 0);
    float tunic = shirt_hem_y(0.25f, &code);
    assert_int_equal(code, 0);
    print_message("# crotch %.3f m, hem %.3f m (default), %.3f m (0.25)\n", crotch, hem, tunic);
    assert_true(hem > crotch + 0.03f);
    assert_true(tunic < crotch);
    assert_true(fabsf(shirt_hem_y(0.12f, &code) - hem) < 1e-6f);
    const float bad[] = {-0.1f, 0.5f, NAN, INFINITY};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        shirt_hem_y(bad[k], &code);
        assert_int_equal(code, SIM_ERR_PARAM);
    }
}

/* The stability map's axes: "NAME@SPEED,AMOUNT" plays a scripted motion SPEED times as fast with
 * its rotations times AMOUNT: at time t it is the motion at SPEED t; AMOUNT 0 is the rest pose;
 * bad specifications are refused by name. */
static void test_scaled_motion(void **state)
{
    (void)state;
    char err[256];
    sim_scene *plain = sim_scene_body("bend_forward", 2000, err, sizeof err);
    sim_scene *fast = sim_scene_body("bend_forward@2", 2000, err, sizeof err);
    sim_scene *none = sim_scene_body("arms_down@1,0", 2000, err, sizeof err);
    sim_scene *down = sim_scene_body("arms_down@1,1.15", 2000, err, sizeof err);
    sim_scene *deflt = sim_scene_body("arms_down", 2000, err, sizeof err);
    assert_true(plain && fast && none && down && deflt);
    assert_float_equal(sim_scene_duration(fast), 0.5 * sim_scene_duration(plain), 1e-9);
    const float *a, *b, *ja, *jb;
    const int32_t *tris;
    int nv, nt;
    /* bend_forward@2 at 0.1 s is bend_forward at 0.2 s (the sine's peak is at 0.25 s) */
    assert_int_equal(sim_scene_eval(plain, 0.2, &a, &nv, &tris, &nt, &ja), 0);
    float want[32 * 3];
    memcpy(want, ja, sizeof want);
    assert_int_equal(sim_scene_eval(fast, 0.1, &b, &nv, &tris, &nt, &jb), 0);
    for (int k = 0; k < 3 * 21; k++)
        assert_float_equal(jb[k], want[k], 1e-6);
    /* amount 0: the rest pose, whenever; arms_down at 3 s with amount 1.15: the wrists lower
       than with the default amount (6 degrees from vertical) */
    assert_int_equal(sim_scene_eval(none, 3.0, &a, &nv, &tris, &nt, &ja), 0);
    memcpy(want, ja, sizeof want);
    assert_int_equal(sim_scene_eval(deflt, 0.0, &b, &nv, &tris, &nt, &jb), 0);
    for (int k = 0; k < 3 * 21; k++)
        assert_float_equal(jb[k], want[k], 1e-6);
    assert_int_equal(sim_scene_eval(deflt, 3.0, &a, &nv, &tris, &nt, &ja), 0);
    float w_default[3], s_default[3];
    memcpy(w_default, ja + 3 * FIT_L_WRIST, sizeof w_default);
    memcpy(s_default, ja + 3 * FIT_L_SHOULDER, sizeof s_default);
    assert_int_equal(sim_scene_eval(down, 3.0, &b, &nv, &tris, &nt, &jb), 0);
    /* the arm nearer vertical: the wrist nearer straight below the shoulder */
    float off_default = fabsf(w_default[0] - s_default[0]);
    float off_down = fabsf(jb[3 * FIT_L_WRIST] - jb[3 * FIT_L_SHOULDER]);
    printf("# arms_down at 3 s: wrist %.3f m beside the shoulder, %.3f with amount 1.15\n",
           (double)off_default, (double)off_down);
    assert_true(off_down < 0.5f * off_default);
    sim_scene_destroy(plain);
    sim_scene_destroy(fast);
    sim_scene_destroy(none);
    sim_scene_destroy(down);
    sim_scene_destroy(deflt);
    const char *bad[] = {"bend@2",   "arms_down@0", "arms_down@-1", "arms_down@11", "arms_down@1,4",
                         "walk@1,x", "walk@",       "all@2",        "arms_down@nan"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        err[0] = '\0';
        assert_null(sim_scene_body(bad[i], 2000, err, sizeof err));
        assert_non_null(strstr(err, bad[i]));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_segments_in_order),  cmocka_unit_test(test_all_never_jumps),
        cmocka_unit_test(test_rebind_to_other_detail), cmocka_unit_test(test_shirt_hem_at_the_hips),
        cmocka_unit_test(test_scaled_motion),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
