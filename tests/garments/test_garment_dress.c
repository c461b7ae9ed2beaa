/* The seed dressing's parts: the image-space body agrees with the body mesh, the spring
 * families are built, and seaming closes a seam; tryon's dressing meets the seam and
 * penetration targets on a skirt and on jeans. */
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
#include "strain_held.h"

static fit_model *body_create(void)
{
    char err[200];
    fit_model *b = fit_model_create(
        &(fit_model_desc){.shape = fit_shape_default(), .target_vertices = 6000}, err, sizeof err);
    if (!b)
        fail_msg("body: %s", err);
    return b;
}

/* Points around the body, 5 mm or more from its surface: the three-view maps call them inside
 * exactly when the mesh's signed distance does, but for a visual hull's blind spots (concave
 * places no axis sees: the armpit, the crotch), which stay under 3 %. */
static void test_body_maps_agree_with_mesh(void **state)
{
    (void)state;
    fit_model *b = body_create();
    const float *xyz = fit_model_rest_vertices(b);
    int nv = fit_model_vertex_count(b);
    gar_body_maps maps[3];
    assert_int_equal(gar_body_maps_render(xyz, nv, fit_model_triangles(b),
                                          fit_model_triangle_count(b), 0.004f, maps),
                     0);
    gar_body_sdf *sdf =
        gar_body_sdf_create(xyz, nv, fit_model_triangles(b), fit_model_triangle_count(b));
    assert_non_null(sdf);
    srand(7);
    int tested = 0, wrong = 0, inside = 0;
    for (int i = 0; i < 20000; i++) {
        const float *q = xyz + 3 * (rand() % nv);
        float p[3], push[3], n[3];
        for (int k = 0; k < 3; k++)
            p[k] = q[k] + 0.04f * ((float)rand() / RAND_MAX - 0.5f);
        float d = gar_body_sdf_eval(sdf, p);
        if (fabsf(d) < 0.005f)
            continue;
        int hit = gar_body_maps_collide(maps, p, 0, push, n);
        tested++;
        inside += d < 0;
        wrong += hit != (d < 0);
        if (hit) /* the push leaves the point outside, along an outward normal */
            assert_true(push[0] * n[0] + push[1] * n[1] + push[2] * n[2] >= 0);
    }
    assert_true(tested > 5000 && inside > 1000);
    if (wrong > 0.03 * tested)
        fail_msg("%d of %d points classified against the mesh", wrong, tested);
    gar_body_sdf_destroy(sdf);
    for (int a = 0; a < 3; a++)
        gar_body_maps_free(&maps[a]);
    fit_model_destroy(b);
}

static gar_pattern load(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s.json", GAR_PATTERN_DIR, name);
    gar_pattern p;
    gar_reject why = {0};
    if (gar_pattern_load(path, &p, &why))
        fail_msg("%s", why.detail);
    return p;
}

/* Stretch springs are the mesh's edges (V + F - 1 per panel by Euler, each a disc), shear
 * springs its interior edges, bend springs exist; rest lengths are the flat ones. */
static void test_spring_families(void **state)
{
    (void)state;
    gar_pattern p = load("skirt");
    gar_mesh m;
    gar_reject why = {0};
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.03f}, &m, &why), 0);
    gar_springs sp;
    assert_int_equal(gar_springs_build(&m, &sp), 0);
    assert_int_equal(sp.n_stretch, m.num_vertices + m.num_triangles - m.num_panels);
    int boundary = m.edge_offset[m.num_edges] - m.num_edges; /* outline segments */
    int shear = 0, bend = 0;
    for (int s = 0; s < sp.n; s++) {
        shear += sp.kind[s] == GAR_SHEAR;
        bend += sp.kind[s] == GAR_BEND;
        assert_true(sp.rest_m[s] > 0);
    }
    assert_int_equal(shear, sp.n_stretch - boundary);
    assert_true(bend > m.num_vertices / 2);
    gar_springs_free(&sp);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
}

/* The skirt placed on the body and seamed: the seams close to a fraction of the placement's
 * gap, nothing is NaN, nothing ends deep in the body. */
static void test_seaming_closes_skirt(void **state)
{
    (void)state;
    fit_model *b = body_create();
    gar_pattern p = load("skirt");
    gar_mesh m;
    gar_reject why = {0};
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.03f}, &m, &why), 0);
    assert_int_equal(gar_mesh_place(&p, &m, b, NULL, NULL, NULL, &why), 0);
    gar_dress_stats before, after;
    assert_int_equal(gar_dress_measure(&m, b, &before), 0);
    gar_dress_desc d = {.max_seaming_s = 0.6f, .drape_steps = 50};
    assert_int_equal(gar_dress_seed(&p, &m, b, &d, &after, &why), 0);
    for (int i = 0; i < 3 * m.num_vertices; i++)
        assert_true(isfinite(m.xyz[i]));
    if (!(after.seam_gap_mm < 0.25f * before.seam_gap_mm))
        fail_msg("seam gap %.1f mm after, %.1f mm placed", after.seam_gap_mm, before.seam_gap_mm);
    assert_true(after.max_pen_mm < 20);
    assert_true(after.steps == 650 || after.seaming_s > 0);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
    fit_model_destroy(b);
}

/* tryon's dressing (XPBD, seams as constraints, BVH contacts) of a pattern at 3 cm: every seam
 * within the 2 mm target, no vertex more than 1 mm inside the body (the exact metric on the body
 * mesh), no panel through another, no spring stretched past the fabric's max strain (the jeans
 * in denim 5.1 % against denim's 2 % with the narrower crotch and 3 sweeps under gravity), gravity
 * on only after the seams closed. */
static void dress_tryon(const char *name, const char *fabric)
{
    fit_model *b = body_create();
    gar_pattern p = load(name);
    gar_mesh m;
    gar_reject why = {0};
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.03f}, &m, &why), 0);
    assert_int_equal(gar_mesh_place(&p, &m, b, NULL, NULL, NULL, &why), 0);
    gar_dress_stats before, after;
    assert_int_equal(gar_dress_measure(&m, b, &before), 0);
    gar_dress_desc d = {.fabric = gar_fabric_find(fabric), .cloth_cloth = 1};
    assert_int_equal(gar_dress_tryon(&p, &m, b, &d, &after, &why), 0);
    for (int i = 0; i < 3 * m.num_vertices; i++)
        assert_true(isfinite(m.xyz[i]));
    if (!(before.seam_gap_mm > 20 && after.seam_gap_mm <= 2.0f))
        fail_msg("%s: seam gap %.2f mm after, %.1f mm placed", name, after.seam_gap_mm,
                 before.seam_gap_mm);
    if (after.penetrating != 0 || after.crossings != 0)
        fail_msg("%s: %d vertices inside (%.2f mm), %d crossings", name, after.penetrating,
                 after.max_pen_mm, after.crossings);
    if (!(after.max_strain <= d.fabric->max_strain))
        fail_msg("%s in %s: max strain %.4f over %.2f", name, fabric, after.max_strain,
                 d.fabric->max_strain);
    assert_true(after.seaming_s > 0 && after.steps > 0);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
    fit_model_destroy(b);
}

static void test_tryon_dresses_skirt(void **state)
{
    (void)state;
    dress_tryon("skirt", "cotton");
}

static void test_tryon_dresses_jeans_in_denim(void **state)
{
    (void)state;
    dress_tryon("jeans", "denim");
}

/* The last rounds of strain limit, seams and contacts (gar_dress_desc.spread_rounds) spread the
 * stretch left at the corners where a seam ends on a free edge: the jeans' worst spring (at the
 * waist-hip corner on the hip) falls to well under what it is without them, the p99 does not
 * rise, and the seams stay closed with nothing inside the body. */
static void dress_spread(fit_model *b, const gar_pattern *p, int rounds, gar_dress_stats *st)
{
    gar_mesh m;
    gar_reject why = {0};
    assert_int_equal(gar_mesh_build(p, &(gar_mesh_desc){.spacing_m = 0.03f}, &m, &why), 0);
    assert_int_equal(gar_mesh_place(p, &m, b, NULL, NULL, NULL, &why), 0);
    gar_dress_desc d = {.cloth_cloth = 1, .spread_rounds = rounds};
    assert_int_equal(gar_dress_tryon(p, &m, b, &d, st, &why), 0);
    if (st->seam_gap_mm > 2.0f || st->penetrating || st->crossings)
        fail_msg("spread %d: seam gap %.2f mm, %d inside, %d crossings", rounds, st->seam_gap_mm,
                 st->penetrating, st->crossings);
    gar_mesh_free(&m);
}

static void test_tryon_spreads_corner_strain(void **state)
{
    (void)state;
    fit_model *b = body_create();
    gar_pattern p = load("jeans");
    gar_dress_stats none, spread;
    dress_spread(b, &p, -1, &none);
    dress_spread(b, &p, 0, &spread);
    printf("jeans at 3 cm: max strain %.3f -> %.3f, p99 %.4f -> %.4f\n", none.max_strain,
           spread.max_strain, none.p99_strain, spread.p99_strain);
    if (!(spread.max_strain < 0.5f * none.max_strain && spread.p99_strain <= none.p99_strain))
        fail_msg("max strain %.3f -> %.3f, p99 %.4f -> %.4f", none.max_strain, spread.max_strain,
                 none.p99_strain, spread.p99_strain);
    gar_pattern_free(&p);
    fit_model_destroy(b);
}

/* The strain limit with a fastened height held: a spring from a fastened vertex, stretched
 * along a slant, shortens at each pass (a linearised step: the fastened end does not move along
 * the spring) to rest (1 + limit), the fastened vertex's height kept and the free end taking all
 * the vertical correction; a free spring is shortened in one pass, split by inverse mass. */
static void test_strain_limit_holds_fastened_height(void **state)
{
    (void)state;
    float x[4][4] = {{0, 1, 0, 2}, {0.6f, 0.2f, 0, 2}, {0, 0, 0, 1}, {0, 0, 2, 3}};
    const int32_t ends[2][2] = {{0, 1}, {2, 3}};
    const float rest[2] = {0.5f, 1.0f};
    const uint8_t fastened[4] = {1, 0, 0, 0};
    float last = 1.0f; /* the slanted spring's length, 1.0 at the start */
    for (int pass = 0; pass < 30; pass++) {
        gar_strain_limit_held(x, ends, rest, fastened, 0.1f, 0, 2);
        float d[3] = {x[1][0] - x[0][0], x[1][1] - x[0][1], x[1][2] - x[0][2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        assert_true(len <= last + 1e-6f && len >= 0.55f - 1e-5f);
        last = len;
    }
    assert_float_equal(last, 0.55f, 1e-4f);
    assert_float_equal(x[0][1], 1.0f, 0.0f); /* the held height */
    assert_true(x[0][0] > 0.0f && x[1][1] > 0.2f);
    /* the free spring: 2 long, limit 1.1, moved 0.9 in all, 1 : 3 by inverse mass */
    assert_float_equal(x[2][2], 0.225f, 1e-5f);
    assert_float_equal(x[3][2], 2.0f - 0.675f, 1e-5f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_body_maps_agree_with_mesh),
        cmocka_unit_test(test_spring_families),
        cmocka_unit_test(test_seaming_closes_skirt),
        cmocka_unit_test(test_tryon_dresses_skirt),
        cmocka_unit_test(test_tryon_dresses_jeans_in_denim),
        cmocka_unit_test(test_tryon_spreads_corner_strain),
        cmocka_unit_test(test_strain_limit_holds_fastened_height),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
