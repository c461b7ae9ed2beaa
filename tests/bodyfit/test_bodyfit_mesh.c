/* The generated body mesh: closed, manifold, outward, not self-intersecting, sized as asked. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include "bodyfit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Smallest triangle area and angle we accept: slivers break normals and collision downstream
 * (the builder's decimation and smoothing give at least about 6 degrees in practice). */
#define MIN_TRIANGLE_AREA      1e-8
#define MIN_TRIANGLE_ANGLE_DEG 3.0

static fit_model *model;

static int setup(void **state)
{
    (void)state;
    char err[256];
    fit_model_desc d = {.shape = fit_shape_default(), .target_vertices = 10000};
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

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

static int find_root(int *p, int x)
{
    while (p[x] != x)
        x = p[x] = p[p[x]];
    return x;
}

/* No sliver: area and every angle above the minimum. */
static void check_triangle_shape(const float *v, const int32_t *tr, int i)
{
    const float *p0 = v + (size_t)tr[0] * 3, *p1 = v + (size_t)tr[1] * 3;
    const float *p2 = v + (size_t)tr[2] * 3;
    double u[3], w[3], c[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = p1[k] - p0[k];
        w[k] = p2[k] - p0[k];
    }
    c[0] = u[1] * w[2] - u[2] * w[1];
    c[1] = u[2] * w[0] - u[0] * w[2];
    c[2] = u[0] * w[1] - u[1] * w[0];
    double area = 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
    if (area < MIN_TRIANGLE_AREA)
        fail_msg("triangle %d has area %g m^2", i, area);
    const float *p[3] = {p0, p1, p2};
    for (int k = 0; k < 3; ++k) {
        double a[3], b[3];
        for (int c2 = 0; c2 < 3; ++c2) {
            a[c2] = (double)p[(k + 1) % 3][c2] - p[k][c2];
            b[c2] = (double)p[(k + 2) % 3][c2] - p[k][c2];
        }
        double cosang = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) /
                        sqrt((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) *
                             (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]));
        if (acos(fmin(1.0, fmax(-1.0, cosang))) * 180.0 / 3.14159265358979 < MIN_TRIANGLE_ANGLE_DEG)
            fail_msg("triangle %d has an angle under %.0f degrees", i, MIN_TRIANGLE_ANGLE_DEG);
    }
}

/* Every directed edge once and its reverse once (manifold and consistently oriented), one
 * component, Euler characteristic 2, every vertex used, no sliver. */
static void check_closed_manifold(const fit_model *m)
{
    int nv = fit_model_vertex_count(m), nt = fit_model_triangle_count(m);
    const int32_t *t = fit_model_triangles(m);
    const float *v = fit_model_rest_vertices(m);
    uint64_t *e = malloc((size_t)nt * 3 * sizeof(uint64_t));
    int *parent = malloc((size_t)nv * sizeof(int));
    char *used = calloc((size_t)nv, 1);
    assert_non_null(e);
    assert_non_null(parent);
    assert_non_null(used);
    for (int i = 0; i < nv; ++i)
        parent[i] = i;
    for (int i = 0; i < nt; ++i) {
        const int32_t *tr = t + (size_t)i * 3;
        assert_true(tr[0] != tr[1] && tr[1] != tr[2] && tr[0] != tr[2]);
        for (int k = 0; k < 3; ++k) {
            int a = tr[k], b = tr[(k + 1) % 3];
            assert_true(a >= 0 && a < nv);
            used[a] = 1;
            e[i * 3 + k] = ((uint64_t)(uint32_t)a << 32) | (uint32_t)b;
            int ra = find_root(parent, a), rb = find_root(parent, b);
            if (ra != rb)
                parent[ra] = rb;
        }
        check_triangle_shape(v, tr, i);
    }
    qsort(e, (size_t)nt * 3, sizeof(uint64_t), cmp_u64);
    for (int i = 0; i < nt * 3; ++i) {
        if (i > 0)
            assert_true(e[i] != e[i - 1]); /* a directed edge twice: inconsistent or non-manifold */
        uint64_t rev = (e[i] << 32) | (e[i] >> 32);
        assert_non_null(bsearch(&rev, e, (size_t)nt * 3, sizeof(uint64_t), cmp_u64));
    }
    int comps = 0;
    for (int i = 0; i < nv; ++i) {
        assert_true(used[i]);
        comps += find_root(parent, i) == i;
    }
    assert_int_equal(comps, 1);
    int edges = nt * 3 / 2;
    assert_int_equal(nv - edges + nt, 2);
    free(e);
    free(parent);
    free(used);
}

static void test_mesh_is_closed_manifold_with_euler_characteristic_2(void **state)
{
    (void)state;
    check_closed_manifold(model);
}

/* Counter-clockwise seen from outside makes the divergence-theorem volume positive; an adult
 * body is 0.05..0.12 m^3. */
static void test_triangles_face_outward(void **state)
{
    (void)state;
    const int32_t *t = fit_model_triangles(model);
    const float *v = fit_model_rest_vertices(model);
    double vol = 0.0;
    for (int i = 0; i < fit_model_triangle_count(model); ++i) {
        const float *a = v + (size_t)t[i * 3] * 3, *b = v + (size_t)t[i * 3 + 1] * 3;
        const float *c = v + (size_t)t[i * 3 + 2] * 3;
        vol += (a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
                a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
                a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0])) /
               6.0;
    }
    assert_true(vol > 0.05 && vol < 0.12);
}

static double orient(const float *a, const float *b, const float *c, const float *d)
{
    double u[3], w[3], x[3];
    for (int k = 0; k < 3; ++k) {
        u[k] = (double)b[k] - a[k];
        w[k] = (double)c[k] - a[k];
        x[k] = (double)d[k] - a[k];
    }
    return x[0] * (u[1] * w[2] - u[2] * w[1]) + x[1] * (u[2] * w[0] - u[0] * w[2]) +
           x[2] * (u[0] * w[1] - u[1] * w[0]);
}

/* Does segment pq cross triangle abc (strictly)? */
static int segment_hits(const float *p, const float *q, const float *a, const float *b,
                        const float *c)
{
    double d1 = orient(a, b, c, p), d2 = orient(a, b, c, q);
    if ((d1 > 0) == (d2 > 0) || d1 == 0 || d2 == 0)
        return 0;
    double s1 = orient(p, q, a, b), s2 = orient(p, q, b, c), s3 = orient(p, q, c, a);
    return (s1 > 0 && s2 > 0 && s3 > 0) || (s1 < 0 && s2 < 0 && s3 < 0);
}

static int triangles_intersect(const float *v, const int32_t *t1, const int32_t *t2)
{
    for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k)
            if (t1[i] == t2[k])
                return 0; /* neighbours meet at a shared vertex by construction */
    const float *a[3], *b[3];
    for (int i = 0; i < 3; ++i) {
        a[i] = v + (size_t)t1[i] * 3;
        b[i] = v + (size_t)t2[i] * 3;
    }
    for (int i = 0; i < 3; ++i) {
        if (segment_hits(a[i], a[(i + 1) % 3], b[0], b[1], b[2]) ||
            segment_hits(b[i], b[(i + 1) % 3], a[0], a[1], a[2]))
            return 1;
    }
    return 0;
}

/* Cell range a triangle's bounding box covers. */
static void triangle_cells(const float *v, const int32_t *tr, const float *lo, float cell,
                           int c0[3], int c1[3])
{
    for (int k = 0; k < 3; ++k) {
        float mn = 1e9f, mx = -1e9f;
        for (int e = 0; e < 3; ++e) {
            mn = fminf(mn, v[(size_t)tr[e] * 3 + k]);
            mx = fmaxf(mx, v[(size_t)tr[e] * 3 + k]);
        }
        c0[k] = (int)((mn - lo[k]) / cell);
        c1[k] = (int)((mx - lo[k]) / cell);
    }
}

typedef struct tri_grid {
    int dim[3], ncell;
    int *end; /* end[c]: one past cell c's last entry in lst; cell c starts at end[c - 1] */
    int *lst;
} tri_grid;

/* Uniform grid of triangle bounding boxes, two passes: count, then fill. */
static void tri_grid_build(const float *v, int nv, const int32_t *t, int nt, float cell,
                           tri_grid *g)
{
    float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
    for (int i = 0; i < nv * 3; ++i) {
        lo[i % 3] = fminf(lo[i % 3], v[i]);
        hi[i % 3] = fmaxf(hi[i % 3], v[i]);
    }
    for (int k = 0; k < 3; ++k)
        g->dim[k] = (int)((hi[k] - lo[k]) / cell) + 1;
    g->ncell = g->dim[0] * g->dim[1] * g->dim[2];
    g->end = calloc((size_t)g->ncell + 1, sizeof(int));
    g->lst = NULL;
    assert_non_null(g->end);
    for (int pass = 0; pass < 2; ++pass) {
        for (int i = 0; i < nt; ++i) {
            int c0[3], c1[3];
            triangle_cells(v, t + (size_t)i * 3, lo, cell, c0, c1);
            for (int z = c0[2]; z <= c1[2]; ++z)
                for (int y = c0[1]; y <= c1[1]; ++y)
                    for (int x = c0[0]; x <= c1[0]; ++x) {
                        int c = (z * g->dim[1] + y) * g->dim[0] + x;
                        if (pass == 0)
                            g->end[c + 1]++;
                        else
                            g->lst[g->end[c]++] = i;
                    }
        }
        if (pass == 0) {
            for (int c = 0; c < g->ncell; ++c)
                g->end[c + 1] += g->end[c];
            g->lst = malloc((size_t)g->end[g->ncell] * sizeof(int) + 1);
            assert_non_null(g->lst);
        }
    }
}

/* Intersecting triangle pairs; pairs are tested only within shared cells of the grid. */
static int count_self_intersections(const float *v)
{
    int nt = fit_model_triangle_count(model), nv = fit_model_vertex_count(model);
    const int32_t *t = fit_model_triangles(model);
    tri_grid g;
    tri_grid_build(v, nv, t, nt, 0.04f, &g);
    int hits = 0, begin = 0;
    for (int c = 0; c < g.ncell; ++c) {
        int end = g.end[c];
        for (int i = begin; i < end; ++i)
            for (int k = i + 1; k < end; ++k)
                hits += triangles_intersect(v, t + (size_t)g.lst[i] * 3, t + (size_t)g.lst[k] * 3);
        begin = end;
    }
    free(g.lst);
    free(g.end);
    return hits;
}

static void test_rest_mesh_has_no_self_intersection(void **state)
{
    (void)state;
    assert_int_equal(count_self_intersections(fit_model_rest_vertices(model)), 0);
}

/* The checker itself: an arm swung into the side of the body must be caught. */
static void test_self_intersection_check_catches_arm_in_body(void **state)
{
    (void)state;
    fit_pose p;
    memset(&p, 0, sizeof p);
    const float into[3] = {0.0f, 0.0f, -0.9f};
    fit_joint_from_anatomical(FIT_L_SHOULDER, into, p.rot[FIT_L_SHOULDER]);
    float *v = malloc((size_t)fit_model_vertex_count(model) * 3 * sizeof(float));
    assert_non_null(v);
    assert_int_equal(fit_model_pose(model, &p, v, NULL), 0);
    assert_true(count_self_intersections(v) > 0);
    free(v);
}

static void test_target_vertices_within_15_percent(void **state)
{
    (void)state;
    const int targets[3] = {6000, 10000, 15000};
    assert_true(abs(fit_model_vertex_count(model) - 10000) <= 1500); /* built by setup */
    for (int i = 0; i < 3; i += 2) {
        char err[256];
        fit_model_desc d = {.shape = fit_shape_preset(i), .target_vertices = targets[i]};
        fit_model *m = fit_model_create(&d, err, sizeof err);
        if (!m)
            fail_msg("%s", err);
        int nv = fit_model_vertex_count(m);
        assert_true(abs(nv - targets[i]) <= targets[i] * 15 / 100);
        check_closed_manifold(m);
        fit_model_destroy(m);
    }
}

static void test_create_rejects_bad_input_with_a_reason(void **state)
{
    (void)state;
    char err[256];
    fit_model_desc d = {.shape = fit_shape_default()};
    d.shape.height = NAN;
    assert_null(fit_model_create(&d, err, sizeof err));
    assert_non_null(strstr(err, "height"));
    d.shape = fit_shape_default();
    d.shape.chest_girth = 3.0f;
    assert_null(fit_model_create(&d, err, sizeof err));
    assert_non_null(strstr(err, "chest_girth"));
    d.shape = fit_shape_default();
    d.target_vertices = 10;
    assert_null(fit_model_create(&d, err, sizeof err));
    assert_non_null(strstr(err, "target_vertices"));
    assert_null(fit_model_create(NULL, err, sizeof err));
    fit_model_destroy(NULL);
}

static void test_write_obj_round_trips_counts(void **state)
{
    (void)state;
    char path[] = "/tmp/tryon_body_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    assert_int_equal(fit_model_write_obj(model, NULL, path), 0);
    FILE *fp = fopen(path, "r");
    assert_non_null(fp);
    char line[128];
    int nv = 0, nf = 0;
    while (fgets(line, sizeof line, fp)) {
        nv += line[0] == 'v';
        nf += line[0] == 'f';
    }
    fclose(fp);
    unlink(path);
    assert_int_equal(nv, fit_model_vertex_count(model));
    assert_int_equal(nf, fit_model_triangle_count(model));
    assert_int_equal(fit_model_write_obj(model, NULL, "/nonexistent-dir/x.obj"), -FIT_ERR_IO);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mesh_is_closed_manifold_with_euler_characteristic_2),
        cmocka_unit_test(test_triangles_face_outward),
        cmocka_unit_test(test_rest_mesh_has_no_self_intersection),
        cmocka_unit_test(test_self_intersection_check_catches_arm_in_body),
        cmocka_unit_test(test_target_vertices_within_15_percent),
        cmocka_unit_test(test_create_rejects_bad_input_with_a_reason),
        cmocka_unit_test(test_write_obj_round_trips_counts),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
