/* The isometric bending constraint (garments/bending.c): zero on a flat or rigidly moved panel,
 * the plate's energy on a rolled one, its gradient against finite differences of its energy,
 * and an XPBD step that honours the rigidity (exact on one stencil). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bending.h"
#include "garments.h"

#define SIDE_CM   20.0
#define SPACING_M 0.02f
#define RIGIDITY  1e-5f /* N m: a shirting cotton */

typedef struct panel {
    gar_pattern p;
    gar_mesh m;
    gar_bending b;
    float (*x)[4];
} panel;

/* A 20 cm square panel meshed by the project's mesher (irregular triangles near the outline). */
static void panel_make(panel *pn)
{
    char json[512];
    snprintf(json, sizeof json,
             "{\"pattern\": {\"panels\": {\"sq\": {\"vertices\": [[0, 0], [%g, 0], [%g, %g], "
             "[0, %g]], \"edges\": [{\"endpoints\": [0, 1]}, {\"endpoints\": [1, 2]}, "
             "{\"endpoints\": [2, 3]}, {\"endpoints\": [3, 0]}], \"translation\": [0, 0, 0], "
             "\"rotation\": [0, 0, 0]}}, \"stitches\": []}}",
             SIDE_CM, SIDE_CM, SIDE_CM, SIDE_CM);
    gar_reject why = {0};
    if (gar_pattern_parse(json, strlen(json), &pn->p, &why))
        fail_msg("pattern: %s", why.detail);
    memset(&pn->m, 0, sizeof pn->m);
    if (gar_mesh_build(&pn->p, &(gar_mesh_desc){.spacing_m = SPACING_M}, &pn->m, &why))
        fail_msg("mesh: %s", why.detail);
    assert_int_equal(gar_bending_build(&pn->m, &pn->b), 0);
    assert_true(pn->b.n > pn->m.num_vertices); /* about 3 edges a vertex, most interior */
    pn->x = calloc((size_t)pn->m.num_vertices, sizeof *pn->x);
    assert_non_null(pn->x);
}

static void panel_free(panel *pn)
{
    free(pn->x);
    gar_bending_free(&pn->b);
    gar_mesh_free(&pn->m);
    gar_pattern_free(&pn->p);
}

/* Flat, rotated and moved: no bending energy. */
static void test_flat_and_rigid_store_nothing(void **state)
{
    (void)state;
    panel pn;
    panel_make(&pn);
    float c = cosf(0.7f), s = sinf(0.7f);
    for (int i = 0; i < pn.m.num_vertices; i++) {
        float u = pn.m.uv_m[2 * i], v = pn.m.uv_m[2 * i + 1];
        pn.x[i][0] = c * u + 0.3f, pn.x[i][1] = s * u + 1.0f, pn.x[i][2] = v - 0.2f;
    }
    double e = gar_bending_energy(&pn.b, (const float(*)[4])pn.x, RIGIDITY);
    /* against a 1 cm radius roll of the same panel: B / 2 / R^2 * area = 2e-3 J */
    assert_true(e < 1e-8);
    panel_free(&pn);
}

/* Rolled onto a cylinder of radius R: B / 2 / R^2 per unit area, within the boundary's share
 * (the outline's edges have no stencil: their triangles count half). */
static void test_cylinder_stores_plate_energy(void **state)
{
    (void)state;
    panel pn;
    panel_make(&pn);
    const float radii[] = {0.05f, 0.1f, 0.3f};
    for (int r = 0; r < 3; r++) {
        float R = radii[r];
        for (int i = 0; i < pn.m.num_vertices; i++) {
            float u = pn.m.uv_m[2 * i], v = pn.m.uv_m[2 * i + 1];
            pn.x[i][0] = R * sinf(u / R), pn.x[i][1] = v, pn.x[i][2] = R * (1 - cosf(u / R));
        }
        double e = gar_bending_energy(&pn.b, (const float(*)[4])pn.x, RIGIDITY);
        for (int i = 0; i < pn.m.num_vertices; i++) { /* the other way: along the rows */
            float u = pn.m.uv_m[2 * i], v = pn.m.uv_m[2 * i + 1];
            pn.x[i][0] = u, pn.x[i][1] = R * (1 - cosf(v / R)), pn.x[i][2] = R * sinf(v / R);
        }
        double e2 = gar_bending_energy(&pn.b, (const float(*)[4])pn.x, RIGIDITY);
        double side = SIDE_CM / 100, plate = RIGIDITY / 2.0 / R / R * side * side;
        printf("R %.2f m: %.3g and %.3g J, plate %.3g J\n", R, e, e2, plate);
        assert_true(e > 0.85 * plate && e < 1.15 * plate);
        assert_true(e2 > 0.85 * plate && e2 < 1.15 * plate);
    }
    panel_free(&pn);
}

/* The analytic gradient against central differences of the energy at a crumpled state. */
static void test_gradient_matches_finite_differences(void **state)
{
    (void)state;
    panel pn;
    panel_make(&pn);
    srand(3);
    for (int i = 0; i < pn.m.num_vertices; i++) {
        float u = pn.m.uv_m[2 * i], v = pn.m.uv_m[2 * i + 1];
        pn.x[i][0] = u, pn.x[i][1] = 0.05f * sinf(20 * u) * cosf(13 * v), pn.x[i][2] = v;
        for (int d = 0; d < 3; d++)
            pn.x[i][d] += 0.002f * ((float)rand() / RAND_MAX - 0.5f);
    }
    int n = pn.m.num_vertices;
    double *g = calloc((size_t)n * 3, sizeof *g);
    assert_non_null(g);
    gar_bending_gradient(&pn.b, (const float(*)[4])pn.x, RIGIDITY, g);
    double gmax = 0, errmax = 0;
    for (int i = 0; i < n; i += 7)
        for (int d = 0; d < 3; d++) {
            const float step = 1e-3f;
            float keep = pn.x[i][d];
            pn.x[i][d] = keep + step;
            double ep = gar_bending_energy(&pn.b, (const float(*)[4])pn.x, RIGIDITY);
            pn.x[i][d] = keep - step;
            double em = gar_bending_energy(&pn.b, (const float(*)[4])pn.x, RIGIDITY);
            pn.x[i][d] = keep;
            /* the step as float actually applied on each side */
            double h = ((double)(keep + step) - (double)(keep - step));
            double fd = (ep - em) / h;
            gmax = fmax(gmax, fabs(g[3 * i + d]));
            errmax = fmax(errmax, fabs(fd - g[3 * i + d]));
        }
    printf("gradient: max %.3g J/m, max error against differences %.3g J/m\n", gmax, errmax);
    assert_true(gmax > 0);
    assert_true(errmax < 1e-3 * gmax);
    free(g);
    panel_free(&pn);
}

/* One XPBD step on one stencil is exact (C is linear): it leaves C times
 * alpha~ / (alpha~ + sum w K^2), alpha~ = 1 / (B s h^2), so a stiffer cloth keeps less of its
 * fold, and a rigid one none. */
static float kept(panel *pn, float rigidity, float h)
{
    int n = pn->m.num_vertices, e = pn->b.n / 2;
    for (int i = 0; i < n; i++) {
        float u = pn->m.uv_m[2 * i], v = pn->m.uv_m[2 * i + 1];
        pn->x[i][0] = u, pn->x[i][1] = 0, pn->x[i][2] = v, pn->x[i][3] = 1e4f; /* 0.1 g */
    }
    pn->x[pn->b.v[e][2]][1] = 0.004f; /* one triangle of the edge folded up */
    double c0[3] = {0}, c1[3] = {0};
    for (int i = 0; i < 4; i++)
        c0[1] += pn->b.k[e][i] * pn->x[pn->b.v[e][i]][1];
    gar_bending one = {
        1, pn->b.v + e, pn->b.k + e, pn->b.s + e, pn->b.lambda + e, pn->b.alpha + e, pn->b.inv + e};
    gar_bending_prepare(&one, (const float(*)[4])pn->x, rigidity, h);
    gar_bending_begin_step(&one);
    gar_bending_project(&one, pn->x);
    for (int i = 0; i < 4; i++)
        c1[1] += pn->b.k[e][i] * pn->x[pn->b.v[e][i]][1];
    double alpha = 1.0 / (rigidity * pn->b.s[e] * h * h), wk = 0;
    for (int i = 0; i < 4; i++)
        wk += 1e4 * pn->b.k[e][i] * pn->b.k[e][i];
    double want = alpha / (alpha + wk);
    printf("B %.0e N m: fold kept %.4f, XPBD %.4f\n", rigidity, c1[1] / c0[1], want);
    assert_true(fabs(c1[1] / c0[1] - want) < 1e-3);
    return (float)(c1[1] / c0[1]);
}

static void test_xpbd_step_honours_rigidity(void **state)
{
    (void)state;
    panel pn;
    panel_make(&pn);
    float soft = kept(&pn, 1e-6f, 0.002f), stiff = kept(&pn, 1e-4f, 0.002f);
    float rigid = kept(&pn, 1e3f, 0.002f);
    assert_true(stiff < soft && soft < 1.0f && rigid < 1e-3f);
    panel_free(&pn);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_flat_and_rigid_store_nothing),
        cmocka_unit_test(test_cylinder_stores_plate_energy),
        cmocka_unit_test(test_gradient_matches_finite_differences),
        cmocka_unit_test(test_xpbd_step_honours_rigidity),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
