/* Retargeting: the model's limbs point where the clip's bones point, at 30 frames a second,
 * inside the joint limits, the feet on the floor. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "bodyfit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BVH_DIR "/usr/share/assimp/models/BVH/"

static fit_model *model;

static int setup(void **state)
{
    (void)state;
    char err[256];
    fit_model_desc d = {.shape = fit_shape_default(), .target_vertices = 6000};
    model = fit_model_create(&d, err, sizeof err);
    if (!model)
        fprintf(stderr, "create failed: %s\n", err);
    return model ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    fit_model_destroy(model);
    return 0;
}

static double angle_deg(const float *a0, const float *a1, const float *b0, const float *b1)
{
    double u[3], v[3], nu = 0, nv = 0, d = 0;
    for (int k = 0; k < 3; ++k) {
        u[k] = a1[k] - a0[k];
        v[k] = b1[k] - b0[k];
        nu += u[k] * u[k];
        nv += v[k] * v[k];
        d += u[k] * v[k];
    }
    double c = d / sqrt(nu * nv);
    return acos(c > 1 ? 1 : (c < -1 ? -1 : c)) * 57.29577951308232;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Bones compared: the model's joint pair and the clip's (the joints driving them). */
static const fit_joint bones[][2] = {
    {FIT_L_SHOULDER, FIT_L_ELBOW}, {FIT_L_ELBOW, FIT_L_WRIST}, {FIT_R_SHOULDER, FIT_R_ELBOW},
    {FIT_R_ELBOW, FIT_R_WRIST},    {FIT_L_HIP, FIT_L_KNEE},    {FIT_L_KNEE, FIT_L_ANKLE},
    {FIT_R_HIP, FIT_R_KNEE},       {FIT_R_KNEE, FIT_R_ANKLE},  {FIT_SPINE, FIT_NECK},
};
#define BONES (sizeof bones / sizeof bones[0])

typedef struct clip_case {
    const char *file;
    int frames;                 /* at 30 fps */
    int start_frames;           /* the file's frames dropped at the start (a reference pose) */
    double median_deg, p95_deg; /* bound on the bone direction error */
} clip_case;

static void check_clip(const clip_case *cc)
{
    char err[256];
    fit_bvh *b = NULL;
    fit_clip *c = NULL;
    assert_int_equal(fit_bvh_load(cc->file, &b, err, sizeof err), 0);
    int rc = fit_clip_from_bvh(b, model, &c, err, sizeof err);
    if (rc)
        fail_msg("%s: %s", cc->file, err);
    assert_int_equal(fit_clip_frame_count(c), cc->frames);
    assert_true(fabs(fit_clip_start(c) - cc->start_frames * fit_bvh_frame_time(b)) < 1e-9);
    int n = fit_clip_frame_count(c), nj = fit_bvh_joint_count(b);
    float *v = malloc((size_t)fit_model_vertex_count(model) * 3 * sizeof(float));
    float *bp = malloc((size_t)nj * 3 * sizeof(float));
    double *err_deg = malloc((size_t)n * BONES * sizeof(double));
    assert_true(v && bp && err_deg);
    float joints[FIT_JOINT_COUNT * 3];
    int m = 0;
    double toe_lo = 1e9;
    for (int f = 0; f < n; ++f) {
        fit_pose p, q;
        fit_clip_eval(c, (double)f / FIT_CLIP_FPS, &p);
        q = p;
        assert_int_equal(fit_pose_clamp(&q), 0); /* inside the limits already */
        assert_int_equal(fit_model_pose(model, &p, v, joints), 0);
        /* the clip's own frame at the same time (the nearest one) */
        int bf = (int)floor((fit_clip_start(c) + (double)f / FIT_CLIP_FPS) / fit_bvh_frame_time(b) +
                            0.5);
        assert_int_equal(fit_bvh_world(b, bf < fit_bvh_frame_count(b) ? bf : bf - 1, bp, NULL), 0);
        for (size_t i = 0; i < BONES; ++i) {
            int s0 = fit_clip_source_joint(c, bones[i][0]),
                s1 = fit_clip_source_joint(c, bones[i][1]);
            err_deg[m++] = angle_deg(joints + bones[i][0] * 3, joints + bones[i][1] * 3,
                                     bp + s0 * 3, bp + s1 * 3);
        }
        toe_lo = fmin(toe_lo, fmin(joints[FIT_L_TOE * 3 + 1], joints[FIT_R_TOE * 3 + 1]));
    }
    if (getenv("RETARGET_DEBUG")) {
        for (size_t i = 0; i < BONES; ++i) {
            double mx = 0, sum = 0;
            for (int k = (int)i; k < m; k += (int)BONES) {
                mx = fmax(mx, err_deg[k]);
                sum += err_deg[k];
            }
            printf("bone %s-%s mean %.1f max %.1f\n", fit_joint_name(bones[i][0]),
                   fit_joint_name(bones[i][1]), sum / n, mx);
        }
    }
    qsort(err_deg, (size_t)m, sizeof *err_deg, cmp_double);
    double med = err_deg[m / 2], p95 = err_deg[(int)(0.95 * m)];
    printf("%s: %d frames, bone direction error median %.2f deg, p95 %.2f, max %.2f; lowest toe "
           "%.3f m\n",
           cc->file, n, med, p95, err_deg[m - 1], toe_lo);
    assert_true(med < cc->median_deg);
    assert_true(p95 < cc->p95_deg);
    /* the lowest the toes go is the model's toe height at rest: on the floor */
    const float *rest = fit_model_rest_joints(model);
    assert_true(fabs(toe_lo - rest[FIT_L_TOE * 3 + 1]) < 0.002);
    free(v);
    free(bp);
    free(err_deg);
    fit_clip_destroy(c);
    fit_bvh_destroy(b);
}

static void test_retargeted_limbs_point_like_the_clip_01_01(void **state)
{
    (void)state;
    clip_case cc = {BVH_DIR "01_01.bvh", 688, 1, 5.0, 12.0};
    check_clip(&cc);
}

static void test_retargeted_limbs_point_like_the_clip_boxing(void **state)
{
    (void)state;
    clip_case cc = {BVH_DIR "Boxing_Toes.bvh", 921, 0, 5.0, 12.0};
    check_clip(&cc);
}

static void test_retargeted_limbs_point_like_the_clip_01_03(void **state)
{
    (void)state;
    clip_case cc = {BVH_DIR "01_03.bvh", 1128, 1, 5.0, 12.0};
    check_clip(&cc);
}

/* Turned to face the camera: Boxing_Toes's subject starts with their back to it; after
 * fit_clip_face_camera the first frame's pelvis faces +z, and every frame's body is the clip's
 * turned rigidly about the vertical through x = z = 0 by the heading taken off. */
static void test_clip_turned_to_face_the_camera(void **state)
{
    (void)state;
    char err[256];
    fit_bvh *b = NULL;
    fit_clip *c = NULL, *turned = NULL;
    assert_int_equal(fit_bvh_load(BVH_DIR "Boxing_Toes.bvh", &b, err, sizeof err), 0);
    assert_int_equal(fit_clip_from_bvh(b, model, &c, err, sizeof err), 0);
    assert_int_equal(fit_clip_from_bvh(b, model, &turned, err, sizeof err), 0);
    double h = fit_clip_face_camera(turned);
    assert_true(fabs(h) > 2.5);                             /* about half a turn */
    assert_true(fabs(fit_clip_face_camera(turned)) < 1e-4); /* facing it already */
    int nv = fit_model_vertex_count(model);
    float *v = malloc((size_t)nv * 3 * sizeof *v), ja[FIT_JOINT_COUNT * 3], jb[FIT_JOINT_COUNT * 3];
    assert_non_null(v);
    double ch = cos(h), sh = sin(h);
    static const int frames[] = {0, 100, 500, 900};
    for (size_t f = 0; f < sizeof frames / sizeof frames[0]; ++f) {
        fit_pose pa, pb;
        fit_clip_eval(c, frames[f] / (double)FIT_CLIP_FPS, &pa);
        fit_clip_eval(turned, frames[f] / (double)FIT_CLIP_FPS, &pb);
        assert_int_equal(fit_model_pose(model, &pa, v, ja), 0);
        assert_int_equal(fit_model_pose(model, &pb, v, jb), 0);
        for (int j = 0; j < FIT_JOINT_COUNT; ++j) { /* R_y(-h) applied to the clip's joint */
            double x = ja[3 * j], z = ja[3 * j + 2];
            assert_true(fabs(jb[3 * j] - (x * ch - z * sh)) < 2e-4);
            assert_true(fabs(jb[3 * j + 1] - ja[3 * j + 1]) < 2e-4);
            assert_true(fabs(jb[3 * j + 2] - (x * sh + z * ch)) < 2e-4);
        }
        if (f == 0) { /* the hips' line across the camera's view: the person faces it */
            double dx = jb[3 * FIT_L_HIP] - jb[3 * FIT_R_HIP];
            double dz = jb[3 * FIT_L_HIP + 2] - jb[3 * FIT_R_HIP + 2];
            assert_true(fabs(dz) < 0.2 * fabs(dx));
        }
    }
    free(v);
    fit_clip_destroy(turned);
    fit_clip_destroy(c);
    fit_bvh_destroy(b);
}

/* A skeleton without arms or legs cannot drive the model: refused, naming the joint. */
static void test_retarget_refuses_a_skeleton_without_limbs(void **state)
{
    (void)state;
    static const char text[] = "HIERARCHY\nROOT Hips\n{\nOFFSET 0 0 0\nCHANNELS 3 Xposition "
                               "Yposition Zposition\nJOINT Head\n{\nOFFSET 0 1 0\nCHANNELS 0\n"
                               "End Site\n{\nOFFSET 0 1 0\n}\n}\n}\nMOTION\nFrames: 1\n"
                               "Frame Time: 0.1\n0 0 0\n";
    char err[256];
    fit_bvh *b = NULL;
    fit_clip *c = (fit_clip *)1;
    assert_int_equal(fit_bvh_parse(text, sizeof text - 1, "head.bvh", &b, err, sizeof err), 0);
    assert_int_equal(fit_clip_from_bvh(b, model, &c, err, sizeof err), -FIT_ERR_ARG);
    assert_null(c);
    assert_non_null(strstr(err, "no joint of the clip matches the model's"));
    fit_bvh_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_retargeted_limbs_point_like_the_clip_01_01),
        cmocka_unit_test(test_retargeted_limbs_point_like_the_clip_boxing),
        cmocka_unit_test(test_retargeted_limbs_point_like_the_clip_01_03),
        cmocka_unit_test(test_clip_turned_to_face_the_camera),
        cmocka_unit_test(test_retarget_refuses_a_skeleton_without_limbs),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
