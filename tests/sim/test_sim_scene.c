/* The benchmark's body scene: "all" plays every motion, tells which one plays when, and never
 * jumps between them (a jump would measure the scene's cut, not the cloth). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "scene.h"

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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_all_segments_in_order),
        cmocka_unit_test(test_all_never_jumps),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
