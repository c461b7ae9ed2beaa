/* The skirt's waistband at the body's waist: placed there on any body shape (heights mapped
 * through the body's hip, waist and chest), it stays there through tryon's dressing (a fastened
 * waistband: its height held), on the three shape presets; the dressed skirt is still closed,
 * outside the body and uncrossed. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bodyfit.h"
#include "dress_internal.h"
#include "garments.h"

/* The waist edge is a circle arc that dips 2.3 cm below its ends at the centre front and lies
 * 0.6-0.7 cm above them between the back's darts: its mean height is a few millimetres under
 * the body's waist slice. */
#define WAIST_TOLERANCE_M 0.03f

/* Mean height of the fastened (waist) vertices; how many there are. */
static float waist_height(const uint8_t *waist, const gar_mesh *m, int *count)
{
    double y = 0;
    *count = 0;
    for (int i = 0; i < m->num_vertices; i++)
        if (waist[i])
            y += m->xyz[3 * i + 1], ++*count;
    return *count ? (float)(y / *count) : NAN;
}

/* The skirt meshed at 3 cm and placed on the body of shape preset PRESET; its fastened (waist)
   vertices. The caller frees all four. */
static uint8_t *placed_skirt(int preset, fit_model **b, gar_pattern *p, gar_mesh *m)
{
    char err[200];
    *b = fit_model_create(
        &(fit_model_desc){.shape = fit_shape_preset(preset), .target_vertices = 6000}, err,
        sizeof err);
    if (!*b)
        fail_msg("body: %s", err);
    gar_reject why = {0};
    if (gar_pattern_load(GAR_PATTERN_DIR "/skirt.json", p, &why))
        fail_msg("%s", why.detail);
    assert_int_equal(gar_mesh_build(p, &(gar_mesh_desc){.spacing_m = 0.03f}, m, &why), 0);
    assert_int_equal(gar_mesh_place(p, m, *b, NULL, NULL, NULL, &why), 0);
    uint8_t *waist = gar_fastened_vertices(p, m);
    assert_non_null(waist);
    return waist;
}

static void skirt_at_waist(int preset)
{
    fit_model *b;
    gar_pattern p;
    gar_mesh m;
    uint8_t *waist = placed_skirt(preset, &b, &p, &m);
    fit_measurements ms;
    assert_int_equal(fit_model_measure(b, &ms), 0);
    gar_reject why = {0};
    int n = 0;
    float placed = waist_height(waist, &m, &n);
    gar_dress_stats st;
    assert_int_equal(gar_dress_tryon(&p, &m, b, &(gar_dress_desc){0}, &st, &why), 0);
    float dressed = waist_height(waist, &m, &n);
    printf("shape %d: body waist %.3f m, waistband placed %.3f m, dressed %.3f m (%d vertices); "
           "seam %.2f mm, %d inside, %d crossings\n",
           preset, ms.waist_y, placed, dressed, n, st.seam_gap_mm, st.penetrating, st.crossings);
    assert_true(n > 10);
    assert_true(fabsf(placed - ms.waist_y) < WAIST_TOLERANCE_M);
    assert_true(fabsf(dressed - ms.waist_y) < WAIST_TOLERANCE_M);
    assert_true(st.seam_gap_mm <= 2.0f && st.penetrating == 0 && st.crossings == 0);
    free(waist);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
    fit_model_destroy(b);
}

static void test_skirt_at_waist_average(void **state)
{
    (void)state;
    skirt_at_waist(0);
}

static void test_skirt_at_waist_slim_tall(void **state)
{
    (void)state;
    skirt_at_waist(1);
}

static void test_skirt_at_waist_broad_short(void **state)
{
    (void)state;
    skirt_at_waist(2);
}

/* On the average body, the reference the files are drawn for, placement keeps the file's heights:
 * place.c's reference landmarks are that body's (fit_model_measure). */
static void test_average_body_keeps_file_heights(void **state)
{
    (void)state;
    fit_model *b;
    gar_pattern p;
    gar_mesh m;
    uint8_t *waist = placed_skirt(0, &b, &p, &m);
    double file = 0;
    int n = 0;
    for (int i = 0; i < m.num_vertices; i++)
        if (waist[i]) {
            float w[3];
            gar_panel_to_world(&p.panels[m.panel_of[i]], m.uv_m + 2 * i, w);
            file += w[1];
        }
    float placed = waist_height(waist, &m, &n);
    printf("average body: waistband %.4f m in the file, %.4f m placed\n", file / n, placed);
    assert_true(fabs(placed - file / n) < 0.003);
    free(waist);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
    fit_model_destroy(b);
}

/* Only a torso panel's waist is fastened: trousers hang from the crotch too. */
static void test_only_skirt_waist_fastened(void **state)
{
    (void)state;
    gar_pattern p;
    gar_reject why = {0};
    if (gar_pattern_load(GAR_PATTERN_DIR "/jeans.json", &p, &why))
        fail_msg("%s", why.detail);
    gar_mesh m;
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.05f}, &m, &why), 0);
    uint8_t *w = gar_fastened_vertices(&p, &m);
    assert_non_null(w);
    for (int i = 0; i < m.num_vertices; i++)
        assert_int_equal(w[i], 0);
    free(w);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_skirt_at_waist_average),
        cmocka_unit_test(test_skirt_at_waist_slim_tall),
        cmocka_unit_test(test_skirt_at_waist_broad_short),
        cmocka_unit_test(test_only_skirt_waist_fastened),
        cmocka_unit_test(test_average_body_keeps_file_heights),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
