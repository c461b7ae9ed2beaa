/* CONTROL's garment requests resolved and made: names, sizes and fabrics map onto the garments
 * the sim can make, a larger size stands farther from the body, a tunic reaches lower than a
 * shirt, a file garment is graded by size, and unknown names are refused with the field named. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "scene.h"
#include "sim.h"

static void test_requests_resolve_to_garments(void **state)
{
    (void)state;
    sim_outfit o;
    sim_reject why;
    assert_int_equal(sim_outfit_resolve("shirt", SIM_SIZE_M, "", &o, &why), 0);
    assert_false(o.is_file);
    assert_string_equal(o.fabric_name, "cotton");
    assert_string_equal(o.id, "shirt M cotton");
    sim_outfit t;
    assert_int_equal(sim_outfit_resolve("tunic", SIM_SIZE_L, "denim", &t, &why), 0);
    assert_true(t.hem_m > o.hem_m);
    assert_true(t.offset_m > o.offset_m);
    assert_true(t.fabric.density_kg_m2 > o.fabric.density_kg_m2);
    assert_false(sim_outfit_same(&o, &t));
    sim_outfit o2;
    assert_int_equal(sim_outfit_resolve("shirt", SIM_SIZE_M, "cotton", &o2, &why), 0);
    assert_true(sim_outfit_same(&o, &o2));
    assert_int_equal(sim_outfit_resolve("/x/y/dress.obj", SIM_SIZE_S, "silk", &o, &why), 0);
    assert_true(o.is_file);
    assert_string_equal(o.id, "dress.obj S silk");
}

static void test_unknown_requests_are_refused(void **state)
{
    (void)state;
    sim_outfit o;
    sim_reject why;
    assert_int_equal(sim_outfit_resolve("cape", SIM_SIZE_M, "", &o, &why), -SIM_ERR_PARAM);
    assert_non_null(strstr(why.detail, "garment 'cape'"));
    assert_int_equal(sim_outfit_resolve("shirt", 3, "", &o, &why), -SIM_ERR_PARAM);
    assert_non_null(strstr(why.detail, "size 3"));
    assert_int_equal(sim_outfit_resolve("shirt", SIM_SIZE_S, "tweed", &o, &why), -SIM_ERR_PARAM);
    assert_non_null(strstr(why.detail, "fabric 'tweed'"));
    assert_int_equal(sim_outfit_resolve("", SIM_SIZE_S, "", &o, &why), -SIM_ERR_PARAM);
    sim_outfit f;
    assert_int_equal(sim_outfit_resolve("/nonexistent/x.obj", SIM_SIZE_M, "", &f, &why), 0);
    sim_garment g;
    assert_int_equal(sim_outfit_make(&f, NULL, 0, NULL, 0, NULL, 0, &g, &why), -SIM_ERR_FILE);
}

/* Mean horizontal distance of the garment's vertices from their centroid's vertical axis, and
 * the lowest vertex. */
static void girth(const sim_garment *g, float *radius, float *lowest)
{
    double cx = 0, cz = 0, r = 0;
    *lowest = INFINITY;
    for (int i = 0; i < g->num_vertices; i++) {
        cx += g->xyz[i * 3];
        cz += g->xyz[i * 3 + 2];
        *lowest = fminf(*lowest, g->xyz[i * 3 + 1]);
    }
    cx /= g->num_vertices;
    cz /= g->num_vertices;
    for (int i = 0; i < g->num_vertices; i++)
        r += hypot(g->xyz[i * 3] - cx, g->xyz[i * 3 + 2] - cz);
    *radius = (float)(r / g->num_vertices);
}

static void make_on_body(const char *garment, int size, sim_garment *g, float *radius,
                         float *lowest)
{
    char err[160] = "";
    sim_scene *sc = sim_scene_body("still", 3000, err, sizeof err);
    assert_non_null(sc);
    const float *xyz, *joints;
    const int32_t *tris;
    int nv, nt;
    assert_int_equal(sim_scene_eval(sc, 0.0, &xyz, &nv, &tris, &nt, &joints), 0);
    sim_outfit o;
    sim_reject why;
    assert_int_equal(sim_outfit_resolve(garment, size, "", &o, &why), 0);
    assert_int_equal(sim_outfit_make(&o, xyz, nv, tris, nt, joints, 2000, g, &why), 0);
    assert_string_equal(g->id, o.id);
    girth(g, radius, lowest);
    sim_scene_destroy(sc);
}

static void test_sizes_and_garments_change_the_shape(void **state)
{
    (void)state;
    sim_garment s, l, t;
    float rs, rl, rt, ls, ll, lt;
    make_on_body("shirt", SIM_SIZE_S, &s, &rs, &ls);
    make_on_body("shirt", SIM_SIZE_L, &l, &rl, &ll);
    make_on_body("tunic", SIM_SIZE_M, &t, &rt, &lt);
    /* L's ease is 12 mm more than S's: the mean radius grows by about that */
    assert_true(rl - rs > 0.008f && rl - rs < 0.016f);
    /* the tunic's hem is 0.13 m below the shirt's (0.25 vs 0.12 m under the pelvis) */
    assert_true(ls - lt > 0.09f);
    sim_garment_free(&s);
    sim_garment_free(&l);
    sim_garment_free(&t);
}

static void test_file_garment_is_graded(void **state)
{
    (void)state;
    char path[64];
    snprintf(path, sizeof path, "/tmp/test_sim_outfit_%d.obj", (int)getpid());
    sim_garment sheet;
    assert_int_equal(sim_garment_drape(64, 0.5f, 1.0f, &sheet), 0);
    assert_int_equal(sim_garment_save_obj(&sheet, path), 0);
    float r[3];
    for (int size = SIM_SIZE_S; size <= SIM_SIZE_L; size++) {
        sim_outfit o;
        sim_reject why;
        sim_garment g;
        float low;
        assert_int_equal(sim_outfit_resolve(path, size, "", &o, &why), 0);
        assert_int_equal(sim_outfit_make(&o, NULL, 0, NULL, 0, NULL, 0, &g, &why), 0);
        assert_int_equal(g.num_vertices, sheet.num_vertices);
        girth(&g, &r[size], &low);
        sim_garment_free(&g);
    }
    assert_true(fabsf(r[SIM_SIZE_S] / r[SIM_SIZE_M] - 0.96f) < 1e-3f);
    assert_true(fabsf(r[SIM_SIZE_L] / r[SIM_SIZE_M] - 1.04f) < 1e-3f);
    sim_garment_free(&sheet);
    unlink(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_requests_resolve_to_garments),
        cmocka_unit_test(test_unknown_requests_are_refused),
        cmocka_unit_test(test_sizes_and_garments_change_the_shape),
        cmocka_unit_test(test_file_garment_is_graded),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
