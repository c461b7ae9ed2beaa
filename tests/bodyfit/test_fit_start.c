/* A person entering costs the fitter no more than a few ordinary frames: the work of every frame
 * (Gauss-Newton iterations and shape steps, fit_result) is bounded, the first frame included,
 * which fitted shape and pose in 88 iterations before (40 ms: the next frames waited behind it;
 * docs/bodyfit.md, "A person's first frames"). Counted, not timed: the bound holds on a loaded
 * machine and under the sanitizers. Scenes rendered with tryon-synth's camera (exact depth):
 * nobody, then slim_tall walking in the open, the tracker starting from the average body. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>

#include "fit_scene.h"

#define FPS          30.0
#define EMPTY_FRAMES 2  /* nobody in front of the camera first */
#define PERSON       12 /* then this many frames of the person */
/* The most iterations any frame may take: the first frame's 12 from the rest pose and 8 turns
 * of one; a tracked frame takes 6, 18 when a lost limb is looked for (two tries). */
#define START_MAX_ITERATIONS 24
/* The shape's turns on the first frame (8) and the frame's own step after them. */
#define START_MAX_SHAPE_STEPS 9

static fit_scene_frame *frame;

static int setup(void **state)
{
    (void)state;
    frame = malloc(sizeof *frame);
    return frame ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    free(frame);
    return 0;
}

/* The work of each of the person's frames (iterations[k], shape_steps[k]) with the tracker
 * described by d; every frame with the person must be published with a body. */
static void run(const fit_tracker_desc *d, int iterations[PERSON], int shape_steps[PERSON])
{
    char err[256];
    fit_model_desc md = {.shape = fit_shape_preset(1), .target_vertices = 6000};
    fit_model *truth = fit_model_create(&md, err, sizeof err);
    assert_non_null(truth);
    float *tv = malloc((size_t)fit_model_vertex_count(truth) * 3 * sizeof(float));
    assert_non_null(tv);
    fit_tracker *tr = fit_tracker_create(d, err, sizeof err);
    assert_non_null(tr);
    for (int k = 0; k < EMPTY_FRAMES + PERSON; ++k) {
        int p = k - EMPTY_FRAMES;
        fit_pose pose;
        fit_motion_eval(FIT_MOTION_WALK, (p > 0 ? p : 0) / FPS, &pose);
        fit_model_pose(truth, &pose, tv, NULL);
        const float *list[1] = {tv};
        fit_scene_render(frame, 0, truth, list, p >= 0);
        fit_result r;
        fit_tracker_frame(tr, &frame->view, &r);
        if (p < 0) {
            assert_int_equal(r.state, FIT_STATE_LOST);
            assert_int_equal(r.iterations, 0);
            continue;
        }
        assert_int_not_equal(r.state, FIT_STATE_LOST); /* the first frame too: no recovery lag */
        assert_non_null(r.vertices);
        iterations[p] = r.iterations;
        shape_steps[p] = r.shape_steps;
    }
    fit_tracker_destroy(tr);
    free(tv);
    fit_model_destroy(truth);
}

/* The defaults: every turn of shape and pose on the first frame (the still jitter depends on
 * it), and yet no frame over START_MAX_ITERATIONS iterations. */
static void test_first_frame_bounded(void **state)
{
    (void)state;
    int it[PERSON], steps[PERSON];
    run(NULL, it, steps);
    printf("# defaults: the first frame %d iterations, %d shape steps; the second %d, %d\n", it[0],
           steps[0], it[1], steps[1]);
    assert_true(steps[0] >= 8); /* the shape is fitted on the first frame, not after */
    for (int k = 0; k < PERSON; ++k) {
        assert_true(it[k] > 0);
        assert_true(it[k] <= START_MAX_ITERATIONS);
        assert_true(steps[k] <= START_MAX_SHAPE_STEPS);
        if (k > 0)
            assert_true(steps[k] <= 1); /* one step a frame after the first */
    }
}

/* --start-turns 2: the 8 turns spread over the first 4 frames, 2 a frame (and the frame's own
 * step after the last), each of those frames within its 2 turns' iterations of an ordinary
 * one. */
static void test_turns_spread(void **state)
{
    (void)state;
    fit_tracker_desc d = {.start_turns = 2};
    int it[PERSON], steps[PERSON], ordinary = 6, limb = 2 * 6, init = 12;
    run(&d, it, steps);
    printf("# --start-turns 2: iterations %d %d %d %d %d, shape steps %d %d %d %d %d\n", it[0],
           it[1], it[2], it[3], it[4], steps[0], steps[1], steps[2], steps[3], steps[4]);
    assert_true(it[0] <= init + 2);
    for (int k = 0; k < 4; ++k)
        assert_true(steps[k] >= 2 && steps[k] <= 3);
    for (int k = 1; k < PERSON; ++k) {
        assert_true(it[k] <= ordinary + limb + (k < 4 ? 2 : 0));
        if (k >= 4)
            assert_true(steps[k] <= 1);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_first_frame_bounded),
        cmocka_unit_test(test_turns_spread),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
