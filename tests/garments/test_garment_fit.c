/* The Cusick drape test (each fabric preset in its band, a stiff fabric drapes less than a soft
 * one, the coefficient is a share of the hanging ring), the fit per body region, size picking (a
 * bigger body never picks a smaller size than a smaller body) and the stability map's two ends. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bodyfit.h"
#include "garments.h"

/* Coarse enough for seconds under the sanitizers. */
#define DRAPE_SPACING_M 0.02f
#define DRAPE_STEPS     500
#define FIT_SPACING_M   0.03f

static float drape(const char *fabric, int iterations)
{
    gar_drape_result r;
    gar_reject why = {0};
    gar_drape_desc d = {.fabric = gar_fabric_find(fabric),
                        .spacing_m = DRAPE_SPACING_M,
                        .steps = DRAPE_STEPS,
                        .iterations = iterations};
    assert_non_null(d.fabric);
    if (gar_drape_test(&d, &r, &why))
        fail_msg("drape %s: %s", fabric, why.detail);
    printf("drape %s (%d sweeps): %.3f, lowest point %.1f mm below, %d vertices\n", fabric,
           iterations, r.coefficient, r.drop_m * 1e3f, r.vertices);
    /* a share of the hanging ring; it hangs (no longer flat) but not below its own width (60 mm,
     * stretched at most the fabric's max_strain, laid 3 mm above the support) */
    assert_true(r.coefficient >= 0.0f && r.coefficient <= 1.0f);
    assert_true(r.drop_m > 0.005f && r.drop_m < 0.060f * (1 + d.fabric->max_strain) + 0.003f);
    return r.coefficient;
}

static void test_stiff_fabric_drapes_less(void **state)
{
    (void)state;
    /* the dressing's own setting (3 sweeps a step) at a coarse mesh: each preset in its
     * published band (docs/garments.md, "Drape test"; tryon-bench-dress --drape) and in order */
    float silk = drape("silk", 0), jersey = drape("jersey", 0);
    float cotton = drape("cotton", 0), denim = drape("denim", 0);
    assert_true(silk >= 0.20f && silk <= 0.45f);
    assert_true(jersey >= 0.25f && jersey <= 0.50f);
    assert_true(cotton >= 0.45f && cotton <= 0.75f);
    assert_true(denim >= 0.70f && denim <= 0.95f);
    assert_true(silk < jersey && jersey < cotton && cotton < denim);
}

static void test_drape_refuses_bad_geometry(void **state)
{
    (void)state;
    gar_drape_result r;
    gar_reject why = {0};
    gar_drape_desc d = {.specimen_d_m = 0.18f, .support_d_m = 0.30f};
    assert_int_equal(gar_drape_test(&d, &r, &why), -GAR_ERR_RANGE);
    assert_non_null(strstr(why.detail, "support"));
}

static fit_model *body(int preset)
{
    char err[200];
    fit_model *b = fit_model_create(
        &(fit_model_desc){.shape = fit_shape_preset(preset), .target_vertices = 6000}, err,
        sizeof err);
    if (!b)
        fail_msg("body: %s", err);
    return b;
}

static void pick(int preset, gar_size_pick *pk)
{
    fit_model *b = body(preset);
    gar_reject why = {0};
    gar_dress_desc dd = {0};
    if (gar_pick_size(GAR_PATTERN_DIR "/skirt.json", b,
                      &(gar_mesh_desc){.spacing_m = FIT_SPACING_M}, &dd, pk, &why))
        fail_msg("pick on shape %d: %s", preset, why.detail);
    printf("shape %d: %s\n", preset, pk->reason);
    for (int s = GAR_SIZE_S; s <= GAR_SIZE_L; s++) {
        assert_true(pk->dressed[s]);
        /* a skirt covers the hips or thighs, nothing of the arms or shoulders */
        const gar_fit *f = &pk->fit[s];
        assert_true(f->region[GAR_REGION_HIPS].vertices + f->region[GAR_REGION_THIGHS].vertices >
                    0);
        assert_int_equal(f->region[GAR_REGION_ARMS].vertices, 0);
        assert_int_equal(f->region[GAR_REGION_SHOULDERS].vertices, 0);
        for (int r = 0; r < GAR_REGION_COUNT; r++) {
            const gar_fit_region *g = &f->region[r];
            assert_true(g->contact >= 0 && g->contact <= 1);
            assert_true(g->p95_strain <= g->max_strain);
        }
    }
    fit_model_destroy(b);
}

static void test_bigger_body_picks_no_smaller_size(void **state)
{
    (void)state;
    gar_size_pick slim, broad;
    pick(1, &slim);  /* slim tall: hips 0.94 m */
    pick(2, &broad); /* broad short: hips 1.10 m */
    assert_true(broad.size >= slim.size);
    /* the pick follows its rule: within the limit, or no size was */
    int any = 0;
    for (int s = GAR_SIZE_S; s <= GAR_SIZE_L; s++)
        any |= broad.tight[s] <= broad.limit;
    if (any)
        assert_true(broad.tight[broad.size] <= broad.limit);
    /* the same skirt is tighter on the broader body, size for size */
    assert_true(broad.tight[GAR_SIZE_M] > slim.tight[GAR_SIZE_M]);
}

/* The stability map's two ends (docs/garments.md, "Stability map"): the seed's explicit springs
 * blow up or leave the seams open with joints 100 times as stiff as its stretch springs; tryon's
 * XPBD seams of that stiffness close at a 4 ms step. */
static int skirt_closes(fit_model *b, int tryon, float gain, float dt_s)
{
    gar_pattern p;
    gar_mesh m = {0};
    gar_reject why = {0};
    gar_dress_stats st;
    assert_int_equal(gar_pattern_load(GAR_PATTERN_DIR "/skirt.json", &p, &why), 0);
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = FIT_SPACING_M}, &m, &why), 0);
    assert_int_equal(gar_mesh_place(&p, &m, b, NULL, NULL, NULL, &why), 0);
    gar_dress_desc d = {.seam_gain = gain, .dt_s = dt_s, .cloth_cloth = 1};
    int rc = tryon ? gar_dress_tryon(&p, &m, b, &d, &st, &why)
                   : gar_dress_seed(&p, &m, b, &d, &st, &why);
    assert_int_equal(rc, 0);
    int finite = 1;
    for (int i = 0; i < 3 * m.num_vertices; i++)
        finite &= isfinite(m.xyz[i]) && fabsf(m.xyz[i]) < 3.0f;
    printf("%s, seams %g x stretch, %.1f ms: seam gap %.1f mm, max strain %.2f, %s\n",
           tryon ? "tryon" : "seed", gain, dt_s * 1e3f, st.seam_gap_mm, st.max_strain,
           finite ? "finite" : "blew up");
    gar_mesh_free(&m);
    gar_pattern_free(&p);
    return finite && st.seam_gap_mm <= 2.0f && st.max_strain < 5.0f && st.penetrating == 0;
}

static void test_stability_ends(void **state)
{
    (void)state;
    fit_model *b = body(0);
    assert_false(skirt_closes(b, 0, 100.0f, 0.001f));
    assert_true(skirt_closes(b, 1, 100.0f, 0.004f));
    fit_model_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stiff_fabric_drapes_less),
        cmocka_unit_test(test_drape_refuses_bad_geometry),
        cmocka_unit_test(test_bigger_body_picks_no_smaller_size),
        cmocka_unit_test(test_stability_ends),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
