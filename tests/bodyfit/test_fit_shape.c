/* The shape estimated from a person's first frames, and a limb lost by a fast motion found
 * again. Scenes rendered with tryon-synth's camera (exact depth), the shape not given to the
 * tracker: it starts from the average body every time. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fit_scene.h"

#define FPS 30.0
/* Standing still, the estimated body's surface within this of the true one (mean symmetric
 * distance, m): 6.8 and 6.9 mm measured on these scenes; 9.2 mm on slim_tall with the height
 * and three girth offsets alone estimated (the estimator before, docs/bodyfit-history.md). */
#define STILL_SURFACE_M 0.008
/* The fast swing's arm, once lost, is found again within this many frames (it was lost for
 * the rest of the swing before a lost limb was looked for). */
#define LOST_RUN_FRAMES 8
#define LOST_JOINTS_M   0.060

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

/* Area-weighted vertex normals of a mesh given by its triangles (the tracker's published mesh
 * has another topology than the true body's). */
static void mesh_normals(const float *v, int nv, const int32_t *t, int nt, float *n)
{
    memset(n, 0, (size_t)nv * 3 * sizeof(float));
    for (int i = 0; i < nt; ++i) {
        const float *a = v + t[i * 3] * 3, *b = v + t[i * 3 + 1] * 3, *c = v + t[i * 3 + 2] * 3;
        float e[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float f[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float x[3] = {e[1] * f[2] - e[2] * f[1], e[2] * f[0] - e[0] * f[2],
                      e[0] * f[1] - e[1] * f[0]};
        for (int k = 0; k < 3; ++k)
            for (int j = 0; j < 3; ++j)
                n[t[i * 3 + k] * 3 + j] += x[j];
    }
    for (int i = 0; i < nv; ++i) {
        float *p = n + i * 3, l = sqrtf(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int j = 0; j < 3 && l > 0.0f; ++j)
            p[j] /= l;
    }
}

/* Symmetric mean surface distance of the published mesh to the true one, m. */
static double surface_error(const fit_result *r, const fit_model *truth, const float *tv)
{
    int nv = fit_model_vertex_count(truth);
    float *tn = malloc((size_t)nv * 3 * sizeof(float));
    float *fn = malloc((size_t)r->vertex_count * 3 * sizeof(float));
    assert_non_null(tn);
    assert_non_null(fn);
    fit_model_normals(truth, tv, tn);
    mesh_normals(r->vertices, r->vertex_count, r->triangles, r->triangle_count, fn);
    double d = 0.5 * (fit_mean_surface_distance(r->vertices, r->vertex_count, tv, tn, nv) +
                      fit_mean_surface_distance(tv, nv, r->vertices, fn, r->vertex_count));
    free(tn);
    free(fn);
    return d;
}

static double joints_error(const fit_result *r, const float *tj)
{
    double e = 0.0;
    for (int j = 0; j < FIT_JOINT_COUNT * 3; j += 3) {
        float d[3] = {r->joints[j] - tj[j], r->joints[j + 1] - tj[j + 1],
                      r->joints[j + 2] - tj[j + 2]};
        e += sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / FIT_JOINT_COUNT;
    }
    return e;
}

/* Fits frames 0..frames-1 of motion m on a body of shape preset; calls back per frame. */
typedef void (*frame_fn)(int k, const fit_result *r, const fit_model *truth, const float *tv,
                         const float *tj, void *ctx);
static void run(int preset, fit_motion m, int frames, frame_fn fn, void *ctx)
{
    char err[256];
    fit_model_desc d = {.shape = fit_shape_preset(preset), .target_vertices = 6000};
    fit_model *truth = fit_model_create(&d, err, sizeof err);
    assert_non_null(truth);
    float *tv = malloc((size_t)fit_model_vertex_count(truth) * 3 * sizeof(float));
    assert_non_null(tv);
    fit_tracker *tr = fit_tracker_create(NULL, err, sizeof err);
    assert_non_null(tr);
    for (int k = 0; k < frames; ++k) {
        fit_pose p;
        float tj[FIT_JOINT_COUNT * 3];
        fit_motion_eval(m, k / FPS, &p);
        fit_model_pose(truth, &p, tv, tj);
        const float *list[1] = {tv};
        fit_scene_render(frame, 0, truth, list, 1);
        fit_result r;
        fit_tracker_frame(tr, &frame->view, &r);
        assert_int_not_equal(r.state, FIT_STATE_LOST);
        fn(k, &r, truth, tv, tj, ctx);
    }
    fit_tracker_destroy(tr);
    free(tv);
    fit_model_destroy(truth);
}

typedef struct still_ctx {
    int frames;
    double surface;
    fit_shape shape;
} still_ctx;

static void still_frame(int k, const fit_result *r, const fit_model *truth, const float *tv,
                        const float *tj, void *ctx)
{
    (void)tj;
    still_ctx *c = ctx;
    if (k == c->frames - 1) {
        c->surface = surface_error(r, truth, tv);
        c->shape = r->shape;
    }
}

/* Standing still, slim_tall and broad_short: the surface within STILL_SURFACE_M after 20
 * frames, and the leg length, arm length and shoulder width each nearer the truth than the
 * average body the tracker starts from. */
static void test_shape_estimated_standing_still(void **state)
{
    (void)state;
    for (int preset = 1; preset <= 2; ++preset) {
        still_ctx c = {.frames = 20};
        run(preset, FIT_MOTION_STILL, c.frames, still_frame, &c);
        float est[FIT_SHAPE_PARAMS], want[FIT_SHAPE_PARAMS], avg[FIT_SHAPE_PARAMS];
        fit_shape w = fit_shape_preset(preset), a = fit_shape_default();
        fit_shape_to_array(&c.shape, est);
        fit_shape_to_array(&w, want);
        fit_shape_to_array(&a, avg);
        printf("# %s still: surface %.1f mm; height %+.0f, leg %+.0f, arm %+.0f, shoulder %+.0f,"
               " chest %+.0f, waist %+.0f, hip %+.0f mm off\n",
               fit_shape_preset_name(preset), 1000.0 * c.surface, 1000.0 * (est[0] - want[0]),
               1000.0 * (est[7] - want[7]), 1000.0 * (est[5] - want[5]),
               1000.0 * (est[1] - want[1]), 1000.0 * (est[2] - want[2]),
               1000.0 * (est[3] - want[3]), 1000.0 * (est[4] - want[4]));
        assert_true(c.surface <= STILL_SURFACE_M);
        static const int lengths[] = {7, 5, 1}; /* leg length, arm length, shoulder width */
        for (int i = 0; i < 3; ++i) {
            int p = lengths[i];
            if (fabsf(avg[p] - want[p]) > 0.01f)
                assert_true(fabsf(est[p] - want[p]) < fabsf(avg[p] - want[p]));
        }
    }
}

typedef struct swing_ctx {
    int run, longest, lost_frames, lost_tracking;
    unsigned causes;
} swing_ctx;

static void swing_frame(int k, const fit_result *r, const fit_model *truth, const float *tv,
                        const float *tj, void *ctx)
{
    (void)truth, (void)tv;
    swing_ctx *c = ctx;
    if (k < 10)
        return; /* the shape's first frames */
    int lost = joints_error(r, tj) > LOST_JOINTS_M;
    c->run = lost ? c->run + 1 : 0;
    c->lost_frames += lost;
    c->lost_tracking += lost && r->state == FIT_STATE_TRACKING;
    c->causes |= r->doubt;
    c->longest = c->run > c->longest ? c->run : c->longest;
}

/* The fast swing on slim_tall (wrist at 3.9 m/s, the arm 13 cm apart between frames): the arm
 * may be lost, but for no more than LOST_RUN_FRAMES frames in a row. */
static void test_swing_arm_found_again(void **state)
{
    (void)state;
    swing_ctx c = {0};
    run(1, FIT_MOTION_FAST_SWING, 48, swing_frame, &c);
    printf("# fast swing, slim_tall: %d frames over %.0f mm of joint error (%d published "
           "TRACKING), the longest run %d, causes %#x\n",
           c.lost_frames, 1000.0 * LOST_JOINTS_M, c.lost_tracking, c.longest, c.causes);
    assert_true(c.longest <= LOST_RUN_FRAMES);
    assert_int_equal(c.lost_tracking, 0);
    assert_true(c.causes & FIT_DOUBT_LOST_PART);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shape_estimated_standing_still),
        cmocka_unit_test(test_swing_arm_found_again),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
