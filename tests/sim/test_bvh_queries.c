/* Both trees (the SAH build the collider uses, the LBVH the device kernels twin) against brute
 * force on random triangle soups: nearest triangle, box containment, refit after motion equal to
 * a fresh build, and the trees' shape. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "collide.h"
#include "collide_bvh.h"
#include "collide_geometry.h"
#include "test_collide_util.h"

#define NT      600
#define QUERIES 400
/* Nearest distances agree to float rounding of a 1 m scene. */
#define DIST_TOL_M 1e-6f

typedef struct mesh {
    int nv, nt;
    float (*v)[4], (*v_prev)[4];
    int32_t (*tris)[4];
} mesh;

static mesh make_mesh(uint32_t seed)
{
    mesh m;
    float *xyz;
    int32_t *t3;
    tc_soup(&seed, NT, &xyz, &t3);
    m.nt = NT;
    m.nv = 3 * NT;
    m.v = malloc((size_t)m.nv * sizeof *m.v);
    m.v_prev = malloc((size_t)m.nv * sizeof *m.v_prev);
    m.tris = malloc((size_t)m.nt * sizeof *m.tris);
    for (int i = 0; i < m.nv; i++) {
        for (int k = 0; k < 3; k++)
            m.v[i][k] = xyz[3 * i + k];
        m.v[i][3] = 0.0f;
    }
    memcpy(m.v_prev, m.v, (size_t)m.nv * sizeof *m.v);
    for (int f = 0; f < m.nt; f++) {
        for (int k = 0; k < 3; k++)
            m.tris[f][k] = t3[3 * f + k];
        m.tris[f][3] = 0;
    }
    free(xyz);
    free(t3);
    return m;
}

static void free_mesh(mesh *m)
{
    free(m->v);
    free(m->v_prev);
    free(m->tris);
}

static float brute_nearest(const mesh *m, const float p[3], int *tri)
{
    float best = INFINITY;
    *tri = -1;
    for (int f = 0; f < m->nt; f++) {
        float q[3], b[3];
        sim_closest_on_triangle(p, m->v[m->tris[f][0]], m->v[m->tris[f][1]], m->v[m->tris[f][2]], q,
                                b);
        float d = sqrtf((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                        (p[2] - q[2]) * (p[2] - q[2]));
        if (d < best) {
            best = d;
            *tri = f;
        }
    }
    return best;
}

static int in_box(const mesh *m, int f, const float p[3], float pad, int swept)
{
    for (int k = 0; k < 3; k++) {
        float lo = INFINITY, hi = -INFINITY;
        for (int j = 0; j < 3; j++) {
            float a = m->v[m->tris[f][j]][k];
            lo = fminf(lo, a), hi = fmaxf(hi, a);
            if (swept) {
                a = m->v_prev[m->tris[f][j]][k];
                lo = fminf(lo, a), hi = fmaxf(hi, a);
            }
        }
        if (p[k] < lo - pad || p[k] > hi + pad)
            return 0;
    }
    return 1;
}

static void check_queries(const sim_bvh *b, const mesh *m, uint32_t seed, float pad)
{
    int32_t out[NT];
    for (int qi = 0; qi < QUERIES; qi++) {
        float p[3] = {tc_range(&seed, -0.6f, 0.6f), tc_range(&seed, -0.6f, 0.6f),
                      tc_range(&seed, -0.6f, 0.6f)};
        int bt;
        float bd = brute_nearest(m, p, &bt);
        float q[3], bary[3], d = -1.0f;
        int t = sim_bvh_nearest(b, (const float(*)[4])m->v, (const int32_t(*)[4])m->tris, p,
                                INFINITY, q, bary, &d);
        assert_int_not_equal(t, -1);
        assert_float_equal(d, bd, DIST_TOL_M);
        /* Within a radius below the nearest distance, nothing is found. */
        if (bd > 2e-3f)
            assert_int_equal(sim_bvh_nearest(b, (const float(*)[4])m->v,
                                             (const int32_t(*)[4])m->tris, p, bd - 1e-3f, q, bary,
                                             &d),
                             -1);
        for (int swept = 0; swept < 2; swept++) {
            int n = sim_bvh_containing(b, p, swept, out, NT);
            int expect = 0;
            for (int f = 0; f < m->nt; f++)
                if (in_box(m, f, p, pad, swept)) {
                    expect++;
                    int seen = 0;
                    for (int j = 0; j < n; j++)
                        seen |= out[j] == f;
                    assert_true(seen);
                }
            assert_int_equal(n, expect);
        }
    }
}

static void test_bvh_nearest_and_containment_match_brute_force(void **state)
{
    (void)state;
    mesh m = make_mesh(12345u);
    sim_bvh b;
    assert_int_equal(sim_bvh_init(&b, NT), 0);
    sim_bvh_build(&b, (const float(*)[4])m.v_prev, (const float(*)[4])m.v,
                  (const int32_t(*)[4])m.tris, m.nt, 0.01f);
    check_queries(&b, &m, 777u, 0.01f);
    sim_bvh_build_lbvh(&b, (const float(*)[4])m.v_prev, (const float(*)[4])m.v,
                       (const int32_t(*)[4])m.tris, m.nt, 0.01f);
    check_queries(&b, &m, 777u, 0.01f);
    sim_bvh_free(&b);
    free_mesh(&m);
}

static void test_bvh_refit_equals_rebuild(void **state)
{
    (void)state;
    mesh m = make_mesh(999u);
    sim_bvh refit, fresh;
    assert_int_equal(sim_bvh_init(&refit, NT), 0);
    assert_int_equal(sim_bvh_init(&fresh, NT), 0);
    sim_bvh_build(&refit, (const float(*)[4])m.v_prev, (const float(*)[4])m.v,
                  (const int32_t(*)[4])m.tris, m.nt, 0.004f);
    /* Move every vertex up to 5 cm: the topology stays, the boxes follow. */
    uint32_t s = 4242u;
    memcpy(m.v_prev, m.v, (size_t)m.nv * sizeof *m.v);
    for (int i = 0; i < m.nv; i++)
        for (int k = 0; k < 3; k++)
            m.v[i][k] += tc_range(&s, -0.05f, 0.05f);
    sim_bvh_refit(&refit, (const float(*)[4])m.v_prev, (const float(*)[4])m.v,
                  (const int32_t(*)[4])m.tris, 0.004f);
    sim_bvh_build(&fresh, (const float(*)[4])m.v_prev, (const float(*)[4])m.v,
                  (const int32_t(*)[4])m.tris, m.nt, 0.004f);
    check_queries(&refit, &m, 31u, 0.004f);
    check_queries(&fresh, &m, 31u, 0.004f);
    /* The root boxes agree exactly: both are unions of the same leaf boxes. */
    for (int k = 0; k < 3; k++) {
        assert_true(refit.lo[0][k] == fresh.lo[0][k] && refit.hi[0][k] == fresh.hi[0][k]);
        assert_true(refit.slo[0][k] == fresh.slo[0][k] && refit.shi[0][k] == fresh.shi[0][k]);
    }
    sim_bvh_free(&refit);
    sim_bvh_free(&fresh);
    free_mesh(&m);
}

/* Every node but the root has one parent, every leaf is reached once; returns the depth (levels
   of internal nodes on the longest path) and the tree's SAH cost: the half areas of the internal
   nodes' boxes, each times the triangles under it. */
static int check_tree(const sim_bvh *b, int nt, double *sah)
{
    int *hits = calloc((size_t)(2 * nt - 1), sizeof *hits);
    int *depth = calloc((size_t)(2 * nt - 1), sizeof *depth);
    int *under = calloc((size_t)(2 * nt - 1), sizeof *under);
    int deepest = 0;
    for (int i = 0; i < nt - 1; i++)
        for (int c = 0; c < 2; c++) {
            int ch = b->child[i][c];
            assert_true(ch > 0 && ch < 2 * nt - 1);
            assert_int_equal(b->parent[ch], i);
            hits[ch]++;
        }
    assert_int_equal(hits[0], 0);
    for (int i = 1; i < 2 * nt - 1; i++)
        assert_int_equal(hits[i], 1);
    int *seen = calloc((size_t)nt, sizeof *seen);
    for (int i = 0; i < nt; i++)
        seen[b->order[i]]++;
    for (int i = 0; i < nt; i++)
        assert_int_equal(seen[i], 1);
    /* depth and triangle counts through the parent links (a node's parent is internal) */
    *sah = 0.0;
    for (int leaf = nt - 1; leaf < 2 * nt - 1; leaf++) {
        int d = 0;
        for (int node = b->parent[leaf]; node >= 0; node = b->parent[node]) {
            under[node]++;
            d++;
            assert_true(d <= 2 * nt);
        }
        deepest = d > deepest ? d : deepest;
    }
    for (int i = 0; i < nt - 1; i++) {
        double e[3];
        for (int k = 0; k < 3; k++)
            e[k] = (double)b->hi[i][k] - (double)b->lo[i][k];
        *sah += (e[0] * e[1] + e[1] * e[2] + e[2] * e[0]) * under[i];
    }
    free(hits);
    free(depth);
    free(under);
    free(seen);
    return deepest;
}

/* The LBVH's codes are sorted; the SAH tree is no deeper than the searches' stacks (96) and
   cheaper by its own measure than the LBVH over the same soup (what it is built for). */
static void test_bvh_trees_are_binary_trees(void **state)
{
    (void)state;
    mesh m = make_mesh(5u);
    /* a tall soup, as a standing body is: the Morton codes split each axis of the box as often
       as the others, so the LBVH's nodes come out as tall as the soup (measured: the SAH tree's
       cost is 0.88 of the LBVH's here) */
    for (int i = 0; i < m.nv; i++)
        m.v[i][1] *= 5.0f;
    memcpy(m.v_prev, m.v, (size_t)m.nv * sizeof *m.v);
    sim_bvh b;
    double sah_lbvh, sah_sah;
    assert_int_equal(sim_bvh_init(&b, NT), 0);
    sim_bvh_build_lbvh(&b, (const float(*)[4])m.v_prev, (const float(*)[4])m.v,
                       (const int32_t(*)[4])m.tris, m.nt, 0.0f);
    for (int i = 1; i < m.nt; i++)
        assert_true(b.morton[i - 1] <= b.morton[i]);
    check_tree(&b, m.nt, &sah_lbvh);
    sim_bvh_build(&b, (const float(*)[4])m.v_prev, (const float(*)[4])m.v,
                  (const int32_t(*)[4])m.tris, m.nt, 0.0f);
    int depth = check_tree(&b, m.nt, &sah_sah);
    assert_true(depth <= 96);
    assert_true(sah_sah < 0.9 * sah_lbvh);
    sim_bvh_free(&b);
    free_mesh(&m);
}

/* Triangles all with one centroid (no plane separates them): the SAH build halves them, and the
   nearest is still the lowest index among the equally near. */
static void test_bvh_sah_coincident_triangles(void **state)
{
    (void)state;
    mesh m = make_mesh(7u);
    for (int f = 0; f < m.nt; f++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                m.v[m.tris[f][j]][k] = m.v[m.tris[0][j]][k];
    memcpy(m.v_prev, m.v, (size_t)m.nv * sizeof *m.v);
    sim_bvh b;
    double sah;
    assert_int_equal(sim_bvh_init(&b, NT), 0);
    sim_bvh_build(&b, (const float(*)[4])m.v_prev, (const float(*)[4])m.v,
                  (const int32_t(*)[4])m.tris, m.nt, 0.0f);
    int depth = check_tree(&b, m.nt, &sah);
    assert_true(depth <= 11); /* halved: ceil(log2(600)) = 10 levels, and the root */
    float p[3] = {1.0f, 1.0f, 1.0f}, q[3], bary[3], d;
    assert_int_equal(sim_bvh_nearest(&b, (const float(*)[4])m.v, (const int32_t(*)[4])m.tris, p,
                                     10.0f, q, bary, &d),
                     0);
    sim_bvh_free(&b);
    free_mesh(&m);
}

/* The smallest trees (2, 3 and 5 triangles), both builds: valid, and the queries' answers. */
static void test_bvh_small_trees(void **state)
{
    (void)state;
    const int sizes[3] = {2, 3, 5};
    for (int k = 0; k < 3; k++)
        for (int sah = 0; sah < 2; sah++) {
            mesh m = make_mesh(100u + (uint32_t)k);
            m.nt = sizes[k];
            sim_bvh b;
            double cost;
            assert_int_equal(sim_bvh_init(&b, m.nt), 0);
            (sah ? sim_bvh_build : sim_bvh_build_lbvh)(&b, (const float(*)[4])m.v_prev,
                                                       (const float(*)[4])m.v,
                                                       (const int32_t(*)[4])m.tris, m.nt, 0.0f);
            assert_true(check_tree(&b, m.nt, &cost) <= m.nt - 1);
            check_queries(&b, &m, 55u, 0.0f);
            sim_bvh_free(&b);
            free_mesh(&m);
        }
}

static void test_bvh_morton_interleaves_axes(void **state)
{
    (void)state;
    assert_int_equal(sim_morton3(0.0f, 0.0f, 0.0f), 0u);
    assert_int_equal(sim_morton3(0.0f, 0.0f, 1.0f / 1024.0f), 1u);
    assert_int_equal(sim_morton3(0.0f, 1.0f / 1024.0f, 0.0f), 2u);
    assert_int_equal(sim_morton3(1.0f / 1024.0f, 0.0f, 0.0f), 4u);
    assert_int_equal(sim_morton3(1.0f, 1.0f, 1.0f), 0x3FFFFFFFu);
    assert_int_equal(sim_morton3(-5.0f, 2.0f, NAN), sim_morton3(0.0f, 1.0f, 0.0f));
}

/* One triangle: the root is the leaf. */
static void test_bvh_single_triangle(void **state)
{
    (void)state;
    float v[3][4] = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}};
    int32_t t[1][4] = {{0, 1, 2, 0}};
    sim_bvh b;
    assert_int_equal(sim_bvh_init(&b, 1), 0);
    sim_bvh_build(&b, (const float(*)[4])v, (const float(*)[4])v, (const int32_t(*)[4])t, 1, 0.0f);
    float p[3] = {0.25f, 0.25f, 0.5f}, q[3], bary[3], d;
    assert_int_equal(
        sim_bvh_nearest(&b, (const float(*)[4])v, (const int32_t(*)[4])t, p, 1.0f, q, bary, &d), 0);
    assert_float_equal(d, 0.5f, 1e-6f);
    int32_t out[2];
    float in[3] = {0.2f, 0.2f, 0.0f};
    assert_int_equal(sim_bvh_containing(&b, in, 0, out, 2), 1);
    assert_int_equal(sim_bvh_containing(&b, p, 0, out, 2), 0);
    sim_bvh_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bvh_nearest_and_containment_match_brute_force),
        cmocka_unit_test(test_bvh_refit_equals_rebuild),
        cmocka_unit_test(test_bvh_trees_are_binary_trees),
        cmocka_unit_test(test_bvh_sah_coincident_triangles),
        cmocka_unit_test(test_bvh_small_trees),
        cmocka_unit_test(test_bvh_morton_interleaves_axes),
        cmocka_unit_test(test_bvh_single_triangle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
