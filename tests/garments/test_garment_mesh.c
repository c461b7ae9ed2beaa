/* Panel meshing keeps the outline; seam sampling pairs every vertex of every stitched edge. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "garments.h"

#define PI 3.14159265358979323846

static double tri_area(const float *uv, const int32_t *t)
{
    const float *a = uv + 2 * t[0], *b = uv + 2 * t[1], *c = uv + 2 * t[2];
    return 0.5 * (((double)b[0] - a[0]) * ((double)c[1] - a[1]) -
                  ((double)b[1] - a[1]) * ((double)c[0] - a[0]));
}

static void load(const char *json, gar_pattern *p)
{
    gar_reject why = {0};
    if (gar_pattern_parse(json, strlen(json), p, &why))
        fail_msg("%s", why.detail);
}

/* Smallest triangle a mesh at spacing h may hold: a tenth of the grid's half-square. */
static void check_triangles(const gar_mesh *m, float h)
{
    for (int t = 0; t < m->num_triangles; t++)
        if (!(tri_area(m->uv_m, m->triangles + 3 * t) > 0.1 * 0.5 * h * h * 0.1))
            fail_msg("triangle %d: area %g m^2 at spacing %g", t,
                     tri_area(m->uv_m, m->triangles + 3 * t), h);
}

/* A 1 m square at 0.1 m: its area exactly, its 40 outline vertices on the outline. */
static void test_square_mesh_keeps_outline(void **state)
{
    (void)state;
    gar_pattern p;
    load("{\"pattern\": {\"panels\": {\"a\": {\"vertices\": [[0,0],[100,0],[100,100],[0,100]],"
         "\"edges\": [{\"endpoints\": [0,1]}, {\"endpoints\": [1,2]}, {\"endpoints\": [2,3]},"
         "{\"endpoints\": [3,0]}]}}}}",
         &p);
    gar_mesh m;
    gar_reject why = {0};
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.1f}, &m, &why), 0);
    double area = 0;
    for (int t = 0; t < m.num_triangles; t++)
        area += tri_area(m.uv_m, m.triangles + 3 * t);
    assert_float_equal(area, 1.0, 1e-5);
    check_triangles(&m, 0.1f);
    assert_int_equal(m.num_edges, 4);
    assert_int_equal(m.edge_offset[4], 4 * 11);
    for (int e = 0; e < 4; e++)
        for (int k = m.edge_offset[e]; k < m.edge_offset[e + 1]; k++) {
            const float *q = m.uv_m + 2 * m.edge_vertices[k];
            float d = fminf(fminf(q[0], 1 - q[0]), fminf(q[1], 1 - q[1]));
            assert_float_equal(d, 0.0f, 1e-6f);
        }
    /* Interior: one lattice point per 0.866 h^2 of the square left clear of the outline by
     * 0.6 h (0.88 m a side), within 15 %. */
    double want = 0.88 * 0.88 / (0.866 * 0.01);
    if (fabs(m.num_vertices - 40 - want) > 0.15 * want)
        fail_msg("%d interior points, want about %.0f", m.num_vertices - 40, want);
    gar_mesh_free(&m);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
}

/* A disc of two semicircles, r = 0.5 m, at 2 cm: the outline vertices on the circle within
 * 1e-5 m, the mesh area that of the inscribed polygon, within 0.2 % of pi r^2 (a chord of
 * length h loses h^3 / (12 r) each: 157 chords of 2 cm lose 0.04 %). */
static void test_disc_mesh_outline_within_tolerance(void **state)
{
    (void)state;
    gar_pattern p;
    load("{\"pattern\": {\"panels\": {\"d\": {\"vertices\": [[0,0],[100,0]],"
         "\"edges\": [{\"endpoints\": [0,1], \"curvature\": {\"type\": \"circle\", \"params\": "
         "[50, 0, 1]}}, {\"endpoints\": [1,0], \"curvature\": {\"type\": \"circle\", \"params\": "
         "[50, 0, 1]}}]}}}}",
         &p);
    gar_mesh m;
    gar_reject why = {0};
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.02f}, &m, &why), 0);
    for (int k = 0; k < m.edge_offset[m.num_edges]; k++) {
        const float *q = m.uv_m + 2 * m.edge_vertices[k];
        assert_float_equal(hypotf(q[0] - 0.5f, q[1]), 0.5f, 1e-5f);
    }
    double area = 0;
    for (int t = 0; t < m.num_triangles; t++)
        area += tri_area(m.uv_m, m.triangles + 3 * t);
    assert_float_equal(area, PI * 0.25, 0.002 * PI * 0.25);
    check_triangles(&m, 0.02f);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
}

/* Arc-length fraction of each vertex along an edge's vertex list. */
static void edge_fractions(const gar_mesh *m, int e, double *f)
{
    const int32_t *v = m->edge_vertices + m->edge_offset[e];
    int n = m->edge_offset[e + 1] - m->edge_offset[e];
    f[0] = 0;
    for (int i = 1; i < n; i++) {
        const float *a = m->uv_m + 2 * v[i - 1], *b = m->uv_m + 2 * v[i];
        f[i] = f[i - 1] + hypot(b[0] - a[0], b[1] - a[1]);
    }
    for (int i = 1; i < n; i++)
        f[i] /= f[n - 1];
}

static int index_on_edge(const gar_mesh *m, int e, int32_t v)
{
    for (int k = m->edge_offset[e]; k < m->edge_offset[e + 1]; k++)
        if (m->edge_vertices[k] == v)
            return k - m->edge_offset[e];
    return -1;
}

/* Every vertex of both sides of every stitch is in a joint, and each joint's partner sits at
 * the mirrored arc fraction (1 - t) within one sample (2 cm on these patterns). Returns the
 * point-edge joints (a gather's). */
static int check_joints(const gar_pattern *p, const gar_mesh *m, const char *name)
{
    int gathers = 0;
    for (int s = 0; s < p->num_stitches; s++) {
        int e[2];
        for (int k = 0; k < 2; k++)
            e[k] = m->panel_first_edge[p->stitches[s].panel[k]] + p->stitches[s].edge[k];
        double fa[4096], fb[4096];
        int n[2] = {m->edge_offset[e[0] + 1] - m->edge_offset[e[0]],
                    m->edge_offset[e[1] + 1] - m->edge_offset[e[1]]};
        assert_true(n[0] <= 4096 && n[1] <= 4096);
        edge_fractions(m, e[0], fa);
        edge_fractions(m, e[1], fb);
        for (int k = 0; k < 2; k++)
            for (int i = 0; i < n[k]; i++) {
                int32_t v = m->edge_vertices[m->edge_offset[e[k]] + i], paired = 0;
                for (int j = 0; j < m->num_joints && !paired; j++) {
                    const gar_joint *jt = &m->joints[j];
                    paired = jt->stitch == s && (jt->a == v || (jt->w == 0 && jt->b0 == v));
                }
                if (!paired)
                    fail_msg("%s stitch %d side %d: vertex %d unpaired", name, s, k, i);
            }
        for (int j = 0; j < m->num_joints; j++) {
            const gar_joint *jt = &m->joints[j];
            if (jt->stitch != s)
                continue;
            int ka = index_on_edge(m, e[0], jt->a) >= 0 && index_on_edge(m, e[1], jt->b0) >= 0;
            int ea = ka ? e[0] : e[1], eb = ka ? e[1] : e[0];
            const double *ff = ka ? fa : fb, *fo = ka ? fb : fa;
            int ia = index_on_edge(m, ea, jt->a), i0 = index_on_edge(m, eb, jt->b0);
            int i1 = index_on_edge(m, eb, jt->b1);
            assert_true(ia >= 0 && i0 >= 0 && i1 >= 0);
            double partner = (1 - jt->w) * fo[i0] + jt->w * fo[i1];
            int nb = (ka ? n[1] : n[0]) - 1;
            if (fabs(partner - (1 - ff[ia])) > 1.0 / nb)
                fail_msg("%s stitch %d: joint at %.3f meets %.3f", name, s, ff[ia], partner);
            gathers += jt->w > 0;
        }
    }
    return gathers;
}

/* A gather: a 40 cm edge sewn to a 30 cm one (a ruffle, or a sleeve cap eased by more than a
 * sample) pairs every vertex of both sides, partly point to edge. */
static void test_gathered_seam_pairs_point_to_edge(void **state)
{
    (void)state;
    gar_pattern p;
    load(
        "{\"pattern\": {\"panels\": {"
        "\"a\": {\"vertices\": [[0,0],[40,0],[40,20],[0,20]], \"edges\": [{\"endpoints\": [0,1]},"
        "{\"endpoints\": [1,2]}, {\"endpoints\": [2,3]}, {\"endpoints\": [3,0]}]},"
        "\"b\": {\"vertices\": [[5,20],[35,20],[35,40],[5,40]], \"edges\": [{\"endpoints\": [0,1]},"
        "{\"endpoints\": [1,2]}, {\"endpoints\": [2,3]}, {\"endpoints\": [3,0]}]}},"
        "\"stitches\": [[{\"panel\": \"a\", \"edge\": 2}, {\"panel\": \"b\", \"edge\": 0}]]}}",
        &p);
    gar_mesh m;
    gar_reject why = {0};
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.02f}, &m, &why), 0);
    assert_true(check_joints(&p, &m, "gather") > 0);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
}

static void test_shipped_patterns_mesh_and_pair(void **state)
{
    (void)state;
    const char *names[] = {"tshirt", "jeans", "skirt", "dress"};
    for (int g = 0; g < 4; g++)
        for (int s = GAR_SIZE_S; s <= GAR_SIZE_L; s += 2) {
            char path[512];
            snprintf(path, sizeof path, "%s/%s.json", GAR_PATTERN_DIR, names[g]);
            gar_pattern p;
            gar_reject why = {0};
            assert_int_equal(gar_pattern_load(path, &p, &why), 0);
            gar_pattern_grade(&p, (gar_size)s);
            gar_mesh m;
            if (gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.02f}, &m, &why))
                fail_msg("%s: %s", names[g], why.detail);
            assert_true(m.num_vertices > 500 && m.num_joints > 0);
            check_triangles(&m, 0.02f);
            check_joints(&p, &m, names[g]);
            gar_mesh_free(&m);
            gar_pattern_free(&p);
        }
}

static void test_mesh_refuses_bad_spacing(void **state)
{
    (void)state;
    gar_pattern p;
    load("{\"pattern\": {\"panels\": {\"a\": {\"vertices\": [[0,0],[10,0],[0,10]],"
         "\"edges\": [{\"endpoints\": [0,1]}, {\"endpoints\": [1,2]}, {\"endpoints\": [2,0]}]}}}}",
         &p);
    gar_mesh m;
    gar_reject why = {0};
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = -1}, &m, &why),
                     -GAR_ERR_RANGE);
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = NAN}, &m, &why),
                     -GAR_ERR_RANGE);
    assert_null(m.triangles);
    gar_pattern_free(&p);
    /* A 40 m square at 2 cm would be 4 million points: refused, naming the panel. */
    load("{\"pattern\": {\"panels\": {\"big\": {\"vertices\": [[0,0],[4000,0],[4000,4000],"
         "[0,4000]], \"edges\": [{\"endpoints\": [0,1]}, {\"endpoints\": [1,2]},"
         "{\"endpoints\": [2,3]}, {\"endpoints\": [3,0]}]}}}}",
         &p);
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.02f}, &m, &why),
                     -GAR_ERR_TOO_LARGE);
    assert_non_null(strstr(why.detail, "panel 'big'"));
    gar_pattern_free(&p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_square_mesh_keeps_outline),
        cmocka_unit_test(test_disc_mesh_outline_within_tolerance),
        cmocka_unit_test(test_shipped_patterns_mesh_and_pair),
        cmocka_unit_test(test_gathered_seam_pairs_point_to_edge),
        cmocka_unit_test(test_mesh_refuses_bad_spacing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
