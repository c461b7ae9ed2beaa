/* The collider's triangle adjacency (the triangle across each edge) against a brute-force pairing:
 * a closed sphere whose poles are fans (each pole's edges sorted as one large bucket), and a
 * non-manifold "book" whose pages share one edge (paired two by two in triangle order, the last
 * of an odd number open). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#include <cmocka.h>

#include "collide.h"
#include "test_collide_util.h"

static sim_collider *collider_on(const float *xyz, int nv, const int32_t *tris, int nt)
{
    char err[128];
    sim_collider *c = sim_collider_create(
        &(sim_collider_desc){.max_vertices = nv, .max_triangles = nt}, err, sizeof err);
    assert_non_null(c);
    assert_int_equal(sim_collider_set_body(c, xyz, nv, tris, nt), 0);
    return c;
}

static int has_edge(const int32_t *t, int32_t a, int32_t b)
{
    for (int k = 0; k < 3; k++)
        if ((t[k] == a && t[(k + 1) % 3] == b) || (t[k] == b && t[(k + 1) % 3] == a))
            return 1;
    return 0;
}

/* Edge k of triangle t: the triangles holding that edge, in index order, paired two by two. */
static int32_t brute_neighbour(const int32_t *tris, int nt, int t, int k)
{
    int32_t a = tris[3 * t + k], b = tris[3 * t + (k + 1) % 3];
    int rank = -1, count = 0, partner = -1;
    for (int u = 0; u < nt; u++) {
        if (!has_edge(tris + 3 * u, a, b))
            continue;
        if (u == t)
            rank = count;
        count++;
    }
    int want = rank ^ 1, seen = 0;
    for (int u = 0; u < nt && want < count; u++)
        if (has_edge(tris + 3 * u, a, b) && seen++ == want)
            partner = u;
    return partner;
}

static void expect_brute(const float *xyz, int nv, const int32_t *tris, int nt)
{
    sim_collider *c = collider_on(xyz, nv, tris, nt);
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            if (c->nbr[t][k] != brute_neighbour(tris, nt, t, k))
                fail_msg("triangle %d edge %d: neighbour %d, brute force %d", t, k, c->nbr[t][k],
                         brute_neighbour(tris, nt, t, k));
    sim_collider_destroy(c);
}

static void test_sphere_with_fans(void **state)
{
    (void)state;
    float *xyz;
    int32_t *tris;
    int nv, nt;
    tc_sphere(0.2f, 64, 12, &xyz, &nv, &tris, &nt); /* each pole in 64 triangles */
    expect_brute(xyz, nv, tris, nt);
    sim_collider *c = collider_on(xyz, nv, tris, nt);
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            assert_true(c->nbr[t][k] >= 0); /* closed */
    sim_collider_destroy(c);
    free(xyz);
    free(tris);
}

/* pages triangles (0, 1, 2 + p) around the edge 0-1, fanned about it. */
static void book(int pages)
{
    int nv = 2 + pages;
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    int32_t *tris = malloc((size_t)pages * 3 * sizeof *tris);
    xyz[0] = xyz[1] = xyz[2] = 0.0f;
    xyz[3] = 0.0f, xyz[4] = 1.0f, xyz[5] = 0.0f;
    for (int p = 0; p < pages; p++) {
        float a = 6.2831853f * (float)p / (float)pages;
        xyz[3 * (2 + p)] = cosf(a), xyz[3 * (2 + p) + 1] = 0.5f, xyz[3 * (2 + p) + 2] = sinf(a);
        tris[3 * p] = 0, tris[3 * p + 1] = 1, tris[3 * p + 2] = 2 + p;
    }
    expect_brute(xyz, nv, tris, pages);
    sim_collider *c = collider_on(xyz, nv, tris, pages);
    for (int p = 0; p < pages; p++)
        assert_int_equal(c->nbr[p][0], (p ^ 1) < pages ? p ^ 1 : -1);
    sim_collider_destroy(c);
    free(xyz);
    free(tris);
}

static void test_non_manifold_books(void **state)
{
    (void)state;
    book(4);  /* a small bucket */
    book(5);  /* an odd page left open */
    book(41); /* vertex 0's 82 edges: the large-bucket sort */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_with_fans),
        cmocka_unit_test(test_non_manifold_books),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
