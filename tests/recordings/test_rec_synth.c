/* tryon-synth's engine: valid dumps, ground truth that rebuilds the frame exactly, seeded noise,
 * the motions' required properties. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bodyfit.h"
#include "recordings.h"

#define N          (REC_WIDTH * REC_HEIGHT)
#define SMALL_MESH 2000 /* fewer vertices keep the sanitizer build fast */

static char dir_a[128], dir_b[128];

static int setup(void **state)
{
    (void)state;
    snprintf(dir_a, sizeof dir_a, "/tmp/tryon-test-synth-a-%d", (int)getpid());
    snprintf(dir_b, sizeof dir_b, "/tmp/tryon-test-synth-b-%d", (int)getpid());
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' '%s'", dir_a, dir_b);
    return system(cmd);
}

static void synth(const char *dir, const char *motion, int frames, int noise, uint64_t seed)
{
    rec_synth_desc d = {.out_dir = dir,
                        .motion = motion,
                        .shape = 1,
                        .frames = frames,
                        .noise = noise,
                        .seed = seed,
                        .target_vertices = SMALL_MESH};
    rec_report why;
    int e = rec_synth(&d, &why);
    if (e != REC_OK)
        fail_msg("rec_synth: %s", why.message);
}

static void read_frame(const char *dir, int k, uint16_t *raw)
{
    rec_index idx;
    rec_report why;
    assert_int_equal(rec_index_read(dir, &idx, &why), REC_OK);
    assert_true(k < idx.count);
    assert_int_equal(rec_frame_read(dir, &idx.frames[k], k, raw, &why), REC_OK);
    rec_index_free(&idx);
}

static void read_gt(const char *dir, int k, rec_gt *g)
{
    char path[256];
    snprintf(path, sizeof path, "%s/gt-%06d.txt", dir, k);
    rec_report why;
    if (rec_gt_read(path, g, &why) != REC_OK)
        fail_msg("%s", why.message);
}

/* The ground truth alone (shape, pose, camera, scene, seed) rebuilds a noisy frame byte for byte:
 * the mesh is recoverable and the noise is seeded. */
static void test_ground_truth_rebuilds_the_frame_exactly(void **state)
{
    (void)state;
    synth(dir_a, "occlusion", 2, 1, 5);
    int frames = 0;
    rec_report why;
    assert_int_equal(rec_validate(dir_a, &frames, &why), REC_OK);
    assert_int_equal(frames, 2);
    rec_gt g;
    read_gt(dir_a, 1, &g);
    assert_int_equal(g.frame, 1);
    assert_string_equal(g.motion, "occlusion");
    assert_int_equal(g.scene.has_box, 1);
    assert_int_equal(g.noise, 1);
    assert_true(g.seed == 5);
    assert_int_equal(g.num_shape, FIT_SHAPE_PARAMS);
    assert_int_equal(g.num_pose, FIT_POSE_PARAMS);
    assert_int_equal(g.num_joints, FIT_JOINT_COUNT);
    assert_true(fabs(g.time_s - 1 / 30.0) < 1e-9);
    assert_true(fabsf(g.fx - (float)REC_FX) < 1e-3f);
    /* Rebuild the true mesh from the ground truth alone and render it again. */
    fit_model_desc md = {.shape = fit_shape_from_array(g.shape),
                         .target_vertices = g.target_vertices};
    char err[256];
    fit_model *m = fit_model_create(&md, err, sizeof err);
    assert_non_null(m);
    fit_pose pose;
    memcpy(pose.root, g.pose, sizeof pose.root);
    for (int j = 0; j < FIT_JOINT_COUNT; j++)
        memcpy(pose.rot[j], &g.pose[3 + 3 * j], sizeof pose.rot[j]);
    float *v = malloc(sizeof(float) * 3 * (size_t)fit_model_vertex_count(m));
    float joints[3 * FIT_JOINT_COUNT];
    assert_int_equal(fit_model_pose(m, &pose, v, joints), 0);
    for (int j = 0; j < FIT_JOINT_COUNT; j++)
        for (int c = 0; c < 3; c++)
            assert_true(fabsf(joints[3 * j + c] - g.joints[j][c]) < 1e-5f);
    float *depth = malloc(sizeof(float) * N), *scratch = malloc(sizeof(float) * N);
    uint16_t *raw = malloc(sizeof(uint16_t) * N), *file = malloc(sizeof(uint16_t) * N);
    rec_render_background(&g.scene, g.camera_to_world, depth);
    rec_render_triangles(g.camera_to_world, v, fit_model_triangles(m), fit_model_triangle_count(m),
                         depth);
    rec_noise_desc nd = rec_noise_default(g.noise, g.seed);
    rec_noise_apply(&nd, 1, depth, scratch, raw);
    read_frame(dir_a, 1, file);
    assert_memory_equal(raw, file, sizeof(uint16_t) * N);
    /* The box is in front: straight at its front face (z = 0.85 m, 1.65 m from the camera) at
     * knee height; noise there is about 5 mm axial plus 8 mm quantisation steps. */
    int bu = (int)lround(REC_CX + REC_FX * 0.3 / 1.65),
        bv = (int)lround(REC_CY + REC_FY * 0.6 / 1.65);
    assert_in_range(rec_raw_to_mm(file[bv * REC_WIDTH + bu]), 1600, 1700);
    /* And the person is in the picture: many pixels nearer than the wall. */
    int body = 0;
    for (int i = 0; i < N; i++)
        body += file[i] != REC_RAW_NONE && rec_raw_to_mm(file[i]) < 3000;
    assert_true(body > 5000);
    free(v);
    free(depth);
    free(scratch);
    free(raw);
    free(file);
    fit_model_destroy(m);
}

static void test_motion_names_and_bad_arguments(void **state)
{
    (void)state;
    int n = 0;
    while (rec_synth_motion_name(n))
        n++;
    assert_int_equal(n, FIT_MOTION_COUNT + 1);
    rec_report why;
    rec_synth_desc d = {.out_dir = dir_a, .motion = "moonwalk", .frames = 1};
    assert_int_equal(rec_synth(&d, &why), -REC_ERR_ARG);
    assert_non_null(strstr(why.message, "moonwalk"));
    d.motion = "still";
    d.shape = 7;
    assert_int_equal(rec_synth(&d, &why), -REC_ERR_ARG);
}

/* A motion-capture clip: recorded as its retargeted poses, named by its file; a file that is no
 * BVH is refused with its name. */
static void test_motion_capture_clip_is_recorded(void **state)
{
    (void)state;
    const char *bvh = "/usr/share/assimp/models/BVH/Boxing_Toes.bvh";
    synth(dir_b, bvh, 3, 0, 1);
    int frames = 0;
    rec_report why;
    assert_int_equal(rec_validate(dir_b, &frames, &why), REC_OK);
    assert_int_equal(frames, 3);
    rec_gt g;
    read_gt(dir_b, 2, &g);
    assert_string_equal(g.motion, "Boxing_Toes.bvh");
    fit_model_desc md = {.shape = fit_shape_preset(1), .target_vertices = SMALL_MESH};
    char err[256];
    fit_model *m = fit_model_create(&md, err, sizeof err);
    fit_bvh *b = NULL;
    fit_clip *c = NULL;
    assert_non_null(m);
    assert_int_equal(fit_bvh_load(bvh, &b, err, sizeof err), 0);
    assert_int_equal(fit_clip_from_bvh(b, m, &c, err, sizeof err), 0);
    fit_clip_face_camera(c); /* tryon-synth's default: the person enters facing the camera */
    fit_pose p;
    fit_clip_eval(c, 2.0 / 30.0, &p);
    for (int k = 0; k < 3; k++)
        assert_true(fabsf(g.pose[k] - p.root[k]) < 1e-5f);
    for (int j = 0; j < FIT_JOINT_COUNT; j++)
        for (int k = 0; k < 3; k++)
            assert_true(fabsf(g.pose[3 + 3 * j + k] - p.rot[j][k]) < 1e-5f);
    fit_clip_destroy(c);
    fit_bvh_destroy(b);
    fit_model_destroy(m);
    rec_synth_desc d = {.out_dir = dir_b, .motion = "/nonexistent/walk.bvh", .frames = 1};
    assert_int_equal(rec_synth(&d, &why), -REC_ERR_ARG);
    assert_non_null(strstr(why.message, "/nonexistent/walk.bvh"));
}

static void test_fast_swing_wrist_reaches_3_m_per_s_at_30_fps(void **state)
{
    (void)state;
    fit_model_desc md = {.shape = fit_shape_preset(1), .target_vertices = SMALL_MESH};
    char err[256];
    fit_model *m = fit_model_create(&md, err, sizeof err);
    assert_non_null(m);
    float *v = malloc(sizeof(float) * 3 * (size_t)fit_model_vertex_count(m));
    float prev[3 * FIT_JOINT_COUNT], cur[3 * FIT_JOINT_COUNT];
    double best = 0.0, period = fit_motion_duration(FIT_MOTION_FAST_SWING);
    fit_pose pose;
    for (int k = 0; k <= (int)(period * REC_FPS) + 1; k++) {
        fit_motion_eval(FIT_MOTION_FAST_SWING, k / REC_FPS, &pose);
        assert_int_equal(fit_model_pose(m, &pose, v, cur), 0);
        for (int w = 0; k > 0 && w < 2; w++) {
            int j = w ? FIT_R_WRIST : FIT_L_WRIST;
            double dx = cur[3 * j] - prev[3 * j], dy = cur[3 * j + 1] - prev[3 * j + 1],
                   dz = cur[3 * j + 2] - prev[3 * j + 2];
            best = fmax(best, sqrt(dx * dx + dy * dy + dz * dz) * REC_FPS);
        }
        memcpy(prev, cur, sizeof cur);
    }
    if (best < 3.0)
        fail_msg("fastest wrist moves %.2f m/s between frames", best);
    free(v);
    fit_model_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ground_truth_rebuilds_the_frame_exactly),
        cmocka_unit_test(test_motion_names_and_bad_arguments),
        cmocka_unit_test(test_motion_capture_clip_is_recorded),
        cmocka_unit_test(test_fast_swing_wrist_reaches_3_m_per_s_at_30_fps),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
