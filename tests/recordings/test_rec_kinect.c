/* The Kinect v1 model: libfreenect's disparity formula, its inverse, the noise statistics, the
 * scene renderer. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "recordings.h"

#define N (REC_WIDTH * REC_HEIGHT)

static void test_raw_to_mm_matches_libfreenect_formula_samples(void **state)
{
    (void)state;
    /* Hand evaluation of registration.c's formula with the default zero-plane info:
     * mm = 9000 / (7.5 - ((raw - 800) / 4 - 0.375) * 0.1042), truncated. */
    static const int raws[] = {500, 600, 700, 800, 900, 1000};
    for (size_t i = 0; i < sizeof raws / sizeof raws[0]; i++) {
        double metric = ((raws[i] - 800) / 4.0 - 0.375) * 0.1042;
        uint16_t want = (uint16_t)(10.0 * (metric * 120.0 / (7.5 - metric) + 120.0));
        assert_int_equal(rec_raw_to_mm((uint16_t)raws[i]), want);
    }
    assert_int_equal(rec_raw_to_mm(REC_RAW_NONE), 0);
    assert_int_equal(rec_raw_to_mm(1500), 0); /* past the formula's pole */
}

static void test_mm_to_raw_inverts_and_quantises(void **state)
{
    (void)state;
    for (double z = 0.5; z <= 4.5; z += 0.01) {
        uint16_t r = rec_mm_to_raw(z);
        assert_true(r < REC_RAW_NONE);
        double back = rec_raw_to_mm(r) / 1000.0;
        /* Quantisation step about z^2 / (8 f b) ... use a generous bound of the local step. */
        double step = (rec_raw_to_mm(r + 1) - rec_raw_to_mm(r)) / 1000.0;
        assert_true(fabs(back - z) <= step * 0.5 + 0.001);
    }
    assert_int_equal(rec_mm_to_raw(0.3), REC_RAW_NONE);
    assert_int_equal(rec_mm_to_raw(5.0), REC_RAW_NONE);
    assert_int_equal(rec_mm_to_raw(NAN), REC_RAW_NONE);
    /* Step sizes quoted in docs: about 3 mm at 1 m, 12 mm at 2 m, 46 mm at 4 m. */
    uint16_t r1 = rec_mm_to_raw(1.0), r4 = rec_mm_to_raw(4.0);
    int s1 = rec_raw_to_mm(r1 + 1) - rec_raw_to_mm(r1);
    int s4 = rec_raw_to_mm(r4 + 1) - rec_raw_to_mm(r4);
    assert_in_range(s1, 2, 4);
    assert_in_range(s4, 38, 56);
}

static void test_sigma_z_follows_nguyen(void **state)
{
    (void)state;
    assert_true(fabs(rec_sigma_z(0.4) - 0.0012) < 1e-12);
    assert_true(fabs(rec_sigma_z(2.4) - (0.0012 + 0.0019 * 4.0)) < 1e-12);
}

static void test_grazing_angle_terms_follow_nguyen(void **state)
{
    (void)state;
    assert_true(fabs(rec_sigma_z_angle(2.0, 0.0) - rec_sigma_z(2.0)) < 1e-15);
    double th = 60.0 / 90.0 * 1.5707963267948966; /* theta / (pi/2 - theta) = 2 */
    assert_true(fabs(rec_sigma_z_angle(2.0, th) - (rec_sigma_z(2.0) + 0.0001 / sqrt(2.0) * 4.0)) <
                1e-12);
    assert_true(fabs(rec_sigma_lateral_px(0.0) - 0.8) < 1e-15);
    assert_true(fabs(rec_sigma_lateral_px(th) - (0.8 + 0.035 * 2.0)) < 1e-12);
}

/* A wall at 2 m whose depth grows by step_m per column: seen at atan(step fx / z) to the ray. */
static int dropped_on_slant(float step_m)
{
    float *d = malloc(sizeof(float) * N), *s = malloc(sizeof(float) * N);
    uint16_t *raw = malloc(sizeof(uint16_t) * N);
    for (int v = 0; v < REC_HEIGHT; v++)
        for (int u = 0; u < REC_WIDTH; u++)
            d[v * REC_WIDTH + u] = 2.0f + step_m * (float)(u - 320);
    rec_noise_desc nd = rec_noise_default(1, 3);
    nd.shadows = 0;
    nd.edge_jump_m = 0.2f; /* the steep slant is one surface, not an edge */
    rec_noise_apply(&nd, 0, d, s, raw);
    int lost = 0;
    for (int v = 200; v < 280; v++)
        for (int u = 310; u < 330; u++)
            lost += raw[v * REC_WIDTH + u] == REC_RAW_NONE;
    free(d);
    free(s);
    free(raw);
    return lost;
}

static void test_surfaces_past_85_degrees_read_nothing(void **state)
{
    (void)state;
    assert_int_equal(dropped_on_slant(0.09f), 80 * 20);  /* about 88 degrees */
    assert_true(dropped_on_slant(0.02f) < 80 * 20 / 10); /* about 80 degrees: kept */
}

/* A flat wall 2 m away filling the image. */
static void flat(float *d, float z)
{
    for (int i = 0; i < N; i++)
        d[i] = z;
}

static void test_noise_off_is_exact_quantisation(void **state)
{
    (void)state;
    float *d = malloc(sizeof(float) * N), *s = malloc(sizeof(float) * N);
    uint16_t *raw = malloc(sizeof(uint16_t) * N);
    flat(d, 2.0f);
    d[0] = 0.0f;
    d[1] = 6.0f;
    rec_noise_desc nd = rec_noise_default(0, 1);
    rec_noise_apply(&nd, 0, d, s, raw);
    assert_int_equal(raw[0], REC_RAW_NONE);
    assert_int_equal(raw[1], REC_RAW_NONE);
    for (int i = 2; i < N; i++)
        assert_int_equal(raw[i], rec_mm_to_raw(2.0));
    free(d);
    free(s);
    free(raw);
}

static void test_noise_on_has_the_model_sigma_and_is_seeded(void **state)
{
    (void)state;
    float *d = malloc(sizeof(float) * N), *s = malloc(sizeof(float) * N);
    uint16_t *a = malloc(sizeof(uint16_t) * N), *b = malloc(sizeof(uint16_t) * N);
    const double z = 2.0;
    flat(d, (float)z);
    rec_noise_desc nd = rec_noise_default(1, 7);
    rec_noise_apply(&nd, 3, d, s, a);
    rec_noise_apply(&nd, 3, d, s, b);
    assert_memory_equal(a, b, sizeof(uint16_t) * N);
    double sum = 0, sum2 = 0;
    int n = 0;
    for (int i = 0; i < N; i++) {
        if (a[i] == REC_RAW_NONE)
            continue;
        double m = rec_raw_to_mm(a[i]) / 1000.0 - z;
        sum += m;
        sum2 += m * m;
        n++;
    }
    assert_true(n > N * 0.99); /* a flat wall has no edges and no shadows */
    double mean = sum / n, sd = sqrt(sum2 / n - mean * mean);
    /* Expected: axial sigma plus the uniform quantisation error, step^2 / 12. */
    uint16_t r = rec_mm_to_raw(z);
    double step = (rec_raw_to_mm(r + 1) - rec_raw_to_mm(r)) / 1000.0;
    double want = sqrt(rec_sigma_z(z) * rec_sigma_z(z) + step * step / 12.0);
    assert_true(fabs(sd - want) < 0.15 * want);
    assert_true(fabs(mean) < 0.003);
    nd.seed = 8;
    rec_noise_apply(&nd, 3, d, s, b);
    assert_true(memcmp(a, b, sizeof(uint16_t) * N) != 0);
    free(d);
    free(s);
    free(a);
    free(b);
}

static void test_projector_casts_a_shadow_beside_a_near_object(void **state)
{
    (void)state;
    float *d = malloc(sizeof(float) * N), *s = malloc(sizeof(float) * N);
    uint16_t *raw = malloc(sizeof(uint16_t) * N);
    flat(d, 3.0f);
    for (int v = 200; v < 280; v++)
        for (int u = 300; u < 340; u++)
            d[v * REC_WIDTH + u] = 1.5f;
    rec_noise_desc nd = rec_noise_default(1, 1);
    nd.edge_drop = 1e-9f;
    nd.lateral_px = 1e-6f;
    rec_noise_apply(&nd, 0, d, s, raw);
    /* Shadow width on the wall: f b (1/z_near - 1/z_far) = 575.8*0.075*(1/1.5-1/3) = 14.4 px,
     * on the -u side of the object (the projector at camera +x throws it to the left). */
    int row = 240 * REC_WIDTH, shadow = 0;
    for (int u = 260; u < 300; u++)
        shadow += raw[row + u] == REC_RAW_NONE;
    assert_in_range(shadow, 12, 17);
    for (int u = 340; u < 400; u++)
        assert_int_not_equal(raw[row + u], REC_RAW_NONE);
    free(d);
    free(s);
    free(raw);
}

static void test_background_floor_and_wall_depths(void **state)
{
    (void)state;
    float *d = malloc(sizeof(float) * N), m[16];
    rec_camera_to_world(m);
    rec_scene sc = rec_scene_default(0);
    rec_render_background(&sc, m, d);
    /* The centre ray goes straight to the wall at z = -1.5: 4.0 m. */
    assert_true(fabsf(d[240 * REC_WIDTH + 320] - 4.0f) < 1e-4f);
    /* Bottom row: the floor, 1 m below the lens: depth = 1 * fy / (v - cy). */
    float want = (float)(REC_FY / (479 - REC_CY));
    assert_true(fabsf(d[479 * REC_WIDTH + 320] - want) < 1e-3f);
    rec_scene box = rec_scene_default(1);
    rec_render_background(&box, m, d);
    /* A ray through the box's front face: front at z = 0.85, 1.65 m from the camera. */
    int u = (int)lround(REC_CX + REC_FX * 0.25 / 1.65),
        v = (int)lround(REC_CY + REC_FY * 0.5 / 1.65);
    assert_true(fabsf(d[v * REC_WIDTH + u] - 1.65f) < 1e-3f);
    free(d);
}

static void test_triangle_depth_is_exact_and_nearest_wins(void **state)
{
    (void)state;
    float *d = calloc(N, sizeof(float)), m[16];
    rec_camera_to_world(m);
    /* A big world-space square facing the camera at z = 0 (2.5 m away), and a smaller one at
     * z = 0.5 in front of it. */
    float v[] = {-1,    0,    0,    1,    0,    0,    1,    2,    0,    -1,    2,    0,
                 -0.2f, 0.8f, 0.5f, 0.2f, 0.8f, 0.5f, 0.2f, 1.2f, 0.5f, -0.2f, 1.2f, 0.5f};
    int32_t t[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    rec_render_triangles(m, v, t, 4, d);
    assert_true(fabsf(d[240 * REC_WIDTH + 320] - 2.0f) < 1e-5f);
    assert_true(fabsf(d[240 * REC_WIDTH + 500] - 2.5f) < 1e-5f);
    assert_true(d[5 * REC_WIDTH + 5] == 0.0f || fabsf(d[5 * REC_WIDTH + 5] - 2.5f) < 1e-5f);
    free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_raw_to_mm_matches_libfreenect_formula_samples),
        cmocka_unit_test(test_mm_to_raw_inverts_and_quantises),
        cmocka_unit_test(test_sigma_z_follows_nguyen),
        cmocka_unit_test(test_grazing_angle_terms_follow_nguyen),
        cmocka_unit_test(test_surfaces_past_85_degrees_read_nothing),
        cmocka_unit_test(test_noise_off_is_exact_quantisation),
        cmocka_unit_test(test_noise_on_has_the_model_sigma_and_is_seeded),
        cmocka_unit_test(test_projector_casts_a_shadow_beside_a_near_object),
        cmocka_unit_test(test_background_floor_and_wall_depths),
        cmocka_unit_test(test_triangle_depth_is_exact_and_nearest_wins),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
