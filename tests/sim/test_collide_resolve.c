/* Contacts and response: points pushed out to thickness and never pulled in, friction bounded by
 * the push, and the penetration metric against analytic spheres. */
#include <math.h>
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

#define THICK 0.004f
#define N     500
/* Float rounding of positions near 1 m. */
#define EPS_M 2e-6f

static sim_collider *make(int nv, int nt, float friction)
{
    char err[128];
    sim_collider *c = sim_collider_create(&(sim_collider_desc){.max_vertices = nv,
                                                               .max_triangles = nt,
                                                               .thickness_m = THICK,
                                                               .friction = friction,
                                                               .max_cloth = N},
                                          err, sizeof err);
    assert_non_null(c);
    return c;
}

/* A 1 m square at y = 0, normal +y. */
static const float square[12] = {-0.5f, 0, -0.5f, 0.5f, 0, -0.5f, 0.5f, 0, 0.5f, -0.5f, 0, 0.5f};
static const int32_t square_tris[6] = {0, 2, 1, 0, 3, 2};

static void test_collide_resolve_pushes_out_and_never_pulls_in(void **state)
{
    (void)state;
    sim_collider *c = make(4, 2, 0.0f);
    assert_int_equal(sim_collider_set_body(c, square, 4, square_tris, 2), 0);
    float x[N][4], xp[N][4], before[N][4];
    uint32_t s = 17u;
    for (int i = 0; i < N; i++) {
        x[i][0] = tc_range(&s, -0.45f, 0.45f);
        x[i][1] = tc_range(&s, -0.003f, 0.02f);
        x[i][2] = tc_range(&s, -0.45f, 0.45f);
        x[i][3] = 1.0f;
        memcpy(xp[i], x[i], sizeof x[i]);
    }
    memcpy(before, x, sizeof x);
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, N);
    sim_collider_resolve(c, x, xp, 0, N);
    int pushed = 0;
    for (int i = 0; i < N; i++) {
        if (before[i][1] < THICK) {
            assert_float_equal(x[i][1], THICK, EPS_M);
            pushed++;
        } else {
            assert_true(x[i][1] == before[i][1]);
        }
        /* Friction 0 and no motion: the point only moves along the normal. */
        assert_true(x[i][0] == before[i][0] && x[i][2] == before[i][2]);
    }
    assert_true(pushed > 50);
    sim_collider_destroy(c);
}

/* The inelastic response (sim_collider_desc.inelastic): over the square, frictionless, a point
 * found 20 mm deep without moving in the step (the body moved over it) goes out to the thickness
 * with no velocity (x_prev moved with it), where the plain push leaves it flying out at 24 mm a
 * step; a point that came 2 mm into the surface in the step stops (the plain push bounces it out
 * at 3 mm a step); one that was already leaving keeps its outward 1 mm a step. */
static void test_collide_inelastic_response_adds_no_velocity(void **state)
{
    (void)state;
    char err[128];
    for (int inelastic = 0; inelastic <= 1; inelastic++) {
        sim_collider *c = sim_collider_create(&(sim_collider_desc){.max_vertices = 4,
                                                                   .max_triangles = 2,
                                                                   .thickness_m = THICK,
                                                                   .max_cloth = N,
                                                                   .inelastic = inelastic},
                                              err, sizeof err);
        assert_non_null(c);
        assert_int_equal(sim_collider_set_body(c, square, 4, square_tris, 2), 0);
        /* deep and still; approaching 2 mm a step from 1 mm deep; leaving 1 mm a step from 2 mm
           deep */
        float x[3][4] = {
            {0.1f, -0.020f, 0.1f, 1.0f}, {0.2f, -0.001f, 0.2f, 1.0f}, {0.3f, -0.002f, 0.3f, 1.0f}};
        float xp[3][4] = {
            {0.1f, -0.020f, 0.1f, 1.0f}, {0.2f, 0.001f, 0.2f, 1.0f}, {0.3f, -0.003f, 0.3f, 1.0f}};
        sim_collider_find_contacts(c, (const float(*)[4])x, 0, 3);
        sim_collider_resolve(c, x, xp, 0, 3);
        for (int i = 0; i < 3; i++)
            assert_float_equal(x[i][1], THICK, EPS_M); /* out to the thickness either way */
        if (!inelastic) {
            assert_float_equal(x[0][1] - xp[0][1], 0.024f, EPS_M);
            assert_float_equal(x[1][1] - xp[1][1], 0.003f, EPS_M);
        } else {
            assert_float_equal(x[0][1] - xp[0][1], 0.0f, EPS_M);
            assert_float_equal(x[1][1] - xp[1][1], 0.0f, EPS_M);
            assert_float_equal(x[2][1] - xp[2][1], 0.001f, EPS_M);
        }
        sim_collider_destroy(c);
    }
}

static void test_collide_friction_bounded_by_push(void **state)
{
    (void)state;
    sim_collider *c = make(4, 2, 0.5f);
    assert_int_equal(sim_collider_set_body(c, square, 4, square_tris, 2), 0);
    /* Point 0: 2 mm under, moving 0.5 mm sideways: push 6 mm, friction limit 3 mm, stopped.
       Point 1: 2 mm under, moving 10 mm sideways: slowed by exactly 3 mm.
       Point 2: above thickness, moving: untouched. */
    float x[3][4] = {{0.0005f, -0.002f, 0, 1}, {0.01f, -0.002f, 0, 1}, {0.01f, 0.01f, 0, 1}};
    float xp[3][4] = {{0, -0.002f, 0, 1}, {0, -0.002f, 0, 1}, {0, 0.01f, 0, 1}};
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, 3);
    sim_collider_resolve(c, x, xp, 0, 3);
    assert_float_equal(x[0][0], 0.0f, EPS_M);
    assert_float_equal(x[0][1], THICK, EPS_M);
    assert_float_equal(x[1][0], 0.01f - 0.5f * 0.006f, EPS_M);
    assert_float_equal(x[1][1], THICK, EPS_M);
    assert_true(x[2][0] == 0.01f && x[2][1] == 0.01f);
    sim_collider_destroy(c);
}

/* The signed distance of the mesh against the analytic sphere. An inscribed UV sphere with 64
   slices and 32 stacks lies inside the true sphere by at most r (1 - cos(pi / 32)) ~ 0.5 %. */
static void test_collide_penetration_matches_analytic_sphere(void **state)
{
    (void)state;
    const float r = 0.2f, sag = r * (1.0f - cosf(3.14159265f / 32.0f)) * 2.0f;
    float *xyz;
    int32_t *tris;
    int nv, nt;
    tc_sphere(r, 64, 32, &xyz, &nv, &tris, &nt);
    sim_collider *c = make(nv, nt, 0.3f);
    assert_int_equal(sim_collider_set_body(c, xyz, nv, tris, nt), 0);
    float x[N][4];
    uint32_t s = 99u;
    int inside = 0;
    float deepest = 0.0f;
    for (int i = 0; i < N; i++) {
        /* Radii away from the surface by more than the tessellation error. */
        float dir[3];
        tc_direction(&s, dir);
        float rad = tc_range(&s, 0.05f, 0.35f);
        if (fabsf(rad - r) < 0.01f)
            rad = r + (rad < r ? -0.01f : 0.01f);
        for (int k = 0; k < 3; k++)
            x[i][k] = dir[k] * rad;
        x[i][3] = 1.0f;
        if (rad < r - 0.001f) {
            inside++;
            deepest = fmaxf(deepest, r - rad);
        }
        /* Per point: the signed distance through the nearest triangle. */
        float q[3], bary[3], d;
        const sim_bvh *b = sim_collider_bvh(c);
        const float(*v)[4], (*vp)[4], (*n)[4];
        const int32_t(*t)[4];
        sim_collider_body(c, &v, &vp, &t, &n);
        int tri = sim_bvh_nearest(b, v, t, x[i], INFINITY, q, bary, &d);
        assert_true(tri >= 0);
        float sd = sim_collider_signed_distance(c, tri, x[i]);
        assert_true(sd >= rad - r - 1e-5f && sd <= rad - r + sag);
    }
    int count;
    float depth;
    assert_int_equal(sim_collider_penetration(c, (const float(*)[4])x, N, 0.001f, &count, &depth),
                     0);
    assert_int_equal(count, inside);
    assert_true(depth <= deepest + 1e-5f && depth >= deepest - sag);
    free(xyz);
    free(tris);
    sim_collider_destroy(c);
}

/* Points just inside a sphere, at faces, edges and vertices alike, come out to thickness. */
static void test_collide_resolve_clears_sphere_shell(void **state)
{
    (void)state;
    float *xyz;
    int32_t *tris;
    int nv, nt;
    tc_sphere(0.15f, 24, 12, &xyz, &nv, &tris, &nt);
    sim_collider *c = make(nv, nt, 0.3f);
    assert_int_equal(sim_collider_set_body(c, xyz, nv, tris, nt), 0);
    float x[N][4], xp[N][4];
    uint32_t s = 5u;
    for (int i = 0; i < N; i++) {
        float dir[3];
        tc_direction(&s, dir);
        float rad = tc_range(&s, 0.13f, 0.16f);
        for (int k = 0; k < 3; k++)
            x[i][k] = dir[k] * rad;
        x[i][3] = 1.0f;
        memcpy(xp[i], x[i], sizeof x[i]);
    }
    /* Iterate like the solver does: contacts once, resolve a few times. */
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, N);
    for (int it = 0; it < 3; it++)
        sim_collider_resolve(c, x, xp, 0, N);
    int count;
    float depth;
    assert_int_equal(sim_collider_penetration(c, (const float(*)[4])x, N, 0.0f, &count, &depth), 0);
    assert_int_equal(count, 0);
    free(xyz);
    free(tris);
    sim_collider_destroy(c);
}

/* The response skips a point still within its quiet radius; that must change nothing. On a bumpy
   sphere (concave and convex edges), points drift in small random steps; one collider keeps its
   quiet radii, the other has them voided before every response (a new body frame, the same body):
   positions and previous positions equal bit for bit after every step. */
static void test_collide_quiet_response_equals_full_response(void **state)
{
    (void)state;
    float *xyz;
    int32_t *tris;
    int nv, nt;
    tc_sphere(0.15f, 32, 16, &xyz, &nv, &tris, &nt);
    uint32_t s = 23u;
    for (int i = 0; i < nv; i++) {
        float f = tc_range(&s, 0.85f, 1.15f);
        for (int k = 0; k < 3; k++)
            xyz[3 * i + k] *= f;
    }
    sim_collider *a = make(nv, nt, 0.3f), *b = make(nv, nt, 0.3f);
    assert_int_equal(sim_collider_set_body(a, xyz, nv, tris, nt), 0);
    assert_int_equal(sim_collider_set_body(b, xyz, nv, tris, nt), 0);
    static float xa[N][4], pa[N][4], xb[N][4], pb[N][4];
    for (int i = 0; i < N; i++) {
        float dir[3];
        tc_direction(&s, dir);
        float rad = tc_range(&s, 0.12f, 0.20f);
        for (int k = 0; k < 3; k++)
            xa[i][k] = dir[k] * rad;
        xa[i][3] = 1.0f;
    }
    memcpy(pa, xa, sizeof xa);
    int quiet = 0;
    for (int step = 0; step < 60; step++) {
        if (step % 20 == 0) { /* a contact search now and then, as the solver does */
            sim_collider_find_contacts(a, (const float(*)[4])xa, 0, N);
            memcpy(xb, xa, sizeof xa);
            memcpy(pb, pa, sizeof pa);
            sim_collider_find_contacts(b, (const float(*)[4])xb, 0, N);
        }
        for (int i = 0; i < N; i++) /* drift inwards, a few tenths of a mm a step */
            for (int k = 0; k < 3; k++) {
                pa[i][k] = xa[i][k];
                xa[i][k] += tc_range(&s, -3e-4f, 3e-4f) - 2e-4f * xa[i][k] / 0.15f;
            }
        memcpy(xb, xa, sizeof xa);
        memcpy(pb, pa, sizeof pa);
        sim_collider_resolve(a, xa, pa, 0, N);
        assert_int_equal(sim_collider_set_body(b, xyz, nv, tris, nt), 0);
        sim_collider_resolve(b, xb, pb, 0, N);
        assert_memory_equal(xa, xb, sizeof xa);
        assert_memory_equal(pa, pb, sizeof pa);
        for (int i = 0; i < N; i++)
            quiet += a->quiet[i][3] > 0.0f;
    }
    assert_true(quiet > N * 60 / 4); /* the skip was taken, often */
    free(xyz);
    free(tris);
    sim_collider_destroy(a);
    sim_collider_destroy(b);
}

/* On a convex body the walk from the cached triangle ends at the searched nearest triangle. */
static void test_collide_track_contacts_matches_search_on_smooth_body(void **state)
{
    (void)state;
    float *xyz;
    int32_t *tris;
    int nv, nt;
    tc_sphere(0.15f, 48, 24, &xyz, &nv, &tris, &nt);
    sim_collider *c = make(nv, nt, 0.3f);
    assert_int_equal(sim_collider_set_body(c, xyz, nv, tris, nt), 0);
    static float x[N][4];
    uint32_t s = 8u;
    for (int i = 0; i < N; i++) {
        float dir[3];
        tc_direction(&s, dir);
        float rad = tc_range(&s, 0.15f, 0.17f);
        for (int k = 0; k < 3; k++)
            x[i][k] = dir[k] * rad;
        x[i][3] = 1.0f;
    }
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, N);
    /* Every point slides up to 1.5 cm (a few triangles) along the surface, staying outside: inside
       a body every face is a local minimum of the distance, and the walk may stop at any. */
    for (int i = 0; i < N; i++) {
        float r0 = sqrtf(x[i][0] * x[i][0] + x[i][1] * x[i][1] + x[i][2] * x[i][2]);
        for (int k = 0; k < 3; k++)
            x[i][k] += tc_range(&s, -0.008f, 0.008f);
        float r1 = sqrtf(x[i][0] * x[i][0] + x[i][1] * x[i][1] + x[i][2] * x[i][2]);
        for (int k = 0; k < 3; k++)
            x[i][k] *= r0 / r1;
    }
    sim_collider_track_contacts(c, (const float(*)[4])x, 0, N);
    int32_t tracked[N];
    memcpy(tracked, sim_collider_contacts(c), sizeof tracked);
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, N);
    const int32_t *searched = sim_collider_contacts(c);
    const float(*v)[4], (*vp)[4], (*n)[4];
    const int32_t(*t)[4];
    sim_collider_body(c, &v, &vp, &t, &n);
    int same = 0;
    for (int i = 0; i < N; i++) {
        assert_int_equal(tracked[i] >= 0, searched[i] >= 0);
        if (searched[i] < 0)
            continue;
        /* Equal distances (a tie between triangles at a shared vertex may pick either). */
        float q[3], b[3], da, db;
        sim_closest_on_triangle(x[i], v[t[tracked[i]][0]], v[t[tracked[i]][1]], v[t[tracked[i]][2]],
                                q, b);
        da = sqrtf((x[i][0] - q[0]) * (x[i][0] - q[0]) + (x[i][1] - q[1]) * (x[i][1] - q[1]) +
                   (x[i][2] - q[2]) * (x[i][2] - q[2]));
        sim_closest_on_triangle(x[i], v[t[searched[i]][0]], v[t[searched[i]][1]],
                                v[t[searched[i]][2]], q, b);
        db = sqrtf((x[i][0] - q[0]) * (x[i][0] - q[0]) + (x[i][1] - q[1]) * (x[i][1] - q[1]) +
                   (x[i][2] - q[2]) * (x[i][2] - q[2]));
        assert_float_equal(da, db, 1e-6f);
        same += tracked[i] == searched[i];
    }
    assert_true(same > N * 9 / 10);
    free(xyz);
    free(tris);
    sim_collider_destroy(c);
}

/* The fast metric (walk + segment cast) answers exactly as the unbounded search, on a body of two
   separate spheres with points inside, outside and between them, hints fresh and stale. */
static void test_collide_penetration_fast_equals_exact(void **state)
{
    (void)state;
    float *a, *b;
    int32_t *ta, *tb;
    int na, nta, nb, ntb;
    tc_sphere(0.2f, 40, 20, &a, &na, &ta, &nta);
    tc_sphere(0.08f, 24, 12, &b, &nb, &tb, &ntb);
    int nv = na + nb, nt = nta + ntb;
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    int32_t *tris = malloc((size_t)nt * 3 * sizeof *tris);
    memcpy(xyz, a, (size_t)na * 3 * sizeof *xyz);
    for (int i = 0; i < nb; i++) {
        xyz[3 * (na + i)] = b[3 * i] + 0.3f;
        xyz[3 * (na + i) + 1] = b[3 * i + 1];
        xyz[3 * (na + i) + 2] = b[3 * i + 2];
    }
    memcpy(tris, ta, (size_t)nta * 3 * sizeof *tris);
    for (int i = 0; i < 3 * ntb; i++)
        tris[3 * nta + i] = tb[i] + na;
    sim_collider *c = make(nv, nt, 0.3f);
    assert_int_equal(sim_collider_set_body(c, xyz, nv, tris, nt), 0);
    static float x[N][4];
    uint32_t s = 123u;
    for (int round = 0; round < 2; round++) {
        for (int i = 0; i < N; i++) {
            if (round == 0) {
                x[i][0] = tc_range(&s, -0.3f, 0.45f);
                x[i][1] = tc_range(&s, -0.25f, 0.25f);
                x[i][2] = tc_range(&s, -0.25f, 0.25f);
                x[i][3] = 1.0f;
            } else {
                for (int k = 0; k < 3; k++) /* stale hints: the points moved after the search */
                    x[i][k] += tc_range(&s, -0.02f, 0.02f);
            }
        }
        if (round == 0)
            sim_collider_find_contacts(c, (const float(*)[4])x, 0, N);
        int cf, ce;
        float df, de;
        assert_int_equal(sim_collider_penetration(c, (const float(*)[4])x, N, 0.001f, &cf, &df), 0);
        assert_int_equal(
            sim_collider_penetration_exact(c, (const float(*)[4])x, N, 0.001f, &ce, &de), 0);
        assert_true(ce > 20);
        assert_int_equal(cf, ce);
        assert_float_equal(df, de, 1e-6f);
    }
    free(a), free(b), free(ta), free(tb), free(xyz), free(tris);
    sim_collider_destroy(c);
}

/* A point deeper inside than thickness + reach still gets a contact (the nearest triangle at any
   distance) and the response brings it out; a point far outside gets none. */
static void test_collide_deep_points_are_pushed_out(void **state)
{
    (void)state;
    float *xyz;
    int32_t *tris;
    int nv, nt;
    tc_sphere(0.2f, 32, 16, &xyz, &nv, &tris, &nt);
    sim_collider *c = make(nv, nt, 0.3f);
    assert_int_equal(sim_collider_set_body(c, xyz, nv, tris, nt), 0);
    float x[4][4] = {{0.05f, 0.02f, 0.01f, 1},
                     {-0.1f, 0.03f, 0.05f, 1},
                     {0.6f, 0.1f, 0.0f, 1},
                     {0.0137f, -0.5f, 0.0713f, 1}};
    float xp[4][4];
    memcpy(xp, x, sizeof x);
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, 4);
    const int32_t *ct = sim_collider_contacts(c);
    assert_true(ct[0] >= 0 && ct[1] >= 0);
    assert_true(ct[2] == -1 && ct[3] == -1);
    sim_collider_resolve(c, x, xp, 0, 4);
    int count;
    float depth;
    assert_int_equal(sim_collider_penetration(c, (const float(*)[4])x, 4, 0.001f, &count, &depth),
                     0);
    assert_int_equal(count, 0);
    free(xyz);
    free(tris);
    sim_collider_destroy(c);
}

/* The metric's shortcut (a point the contact search saw outside by w that has moved less than w is
   still outside) never hides a penetration: points found 5 mm or more outside a sphere are moved
   towards their nearest surface point: staying, to 2 mm outside, to 2 mm inside; each time the
   metric equals the unbounded search and, inside, counts every point. A new body frame voids the
   bounds of the old one. */
static void test_collide_penetration_clearance_never_hides_a_point(void **state)
{
    (void)state;
    float *xyz;
    int32_t *tris;
    int nv, nt;
    const float r = 0.2f;
    tc_sphere(r, 48, 24, &xyz, &nv, &tris, &nt);
    sim_collider *c = make(nv, nt, 0.3f);
    assert_int_equal(sim_collider_set_body(c, xyz, nv, tris, nt), 0);
    static float x0[N][4], x[N][4];
    uint32_t s = 77u;
    for (int i = 0; i < N; i++) {
        float dir[3];
        tc_direction(&s, dir);
        for (int k = 0; k < 3; k++)
            x0[i][k] = dir[k];
    }
    int cf, ce;
    float df, de;
    for (int m = 0; m < 3; m++) {
        for (int i = 0; i < N; i++) {
            for (int k = 0; k < 3; k++)
                x[i][k] = x0[i][k] * (r + 0.005f);
            x[i][3] = 1.0f;
        }
        sim_collider_find_contacts(c, (const float(*)[4])x, 0, N);
        if (m == 2) {
            /* as the OpenCL backend hands over its device search: the same contacts, adopted */
            static int32_t found[N];
            memcpy(found, sim_collider_contacts(c), sizeof found);
            sim_collider_adopt_contacts(c, (const float(*)[4])x, found, 0, N);
        }
        const float(*v)[4], (*vp)[4], (*n)[4];
        const int32_t(*t)[4];
        sim_collider_body(c, &v, &vp, &t, &n);
        const int32_t *ct = sim_collider_contacts(c);
        for (int i = 0; i < N; i++) {
            float q[3], b[3], d[3];
            assert_true(ct[i] >= 0);
            sim_closest_on_triangle(x[i], v[t[ct[i]][0]], v[t[ct[i]][1]], v[t[ct[i]][2]], q, b);
            for (int k = 0; k < 3; k++)
                d[k] = x[i][k] - q[k];
            float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            assert_true(len > 0.0049f);
            float to = m == 0 ? len : (m == 1 ? 0.002f : -0.002f);
            for (int k = 0; k < 3; k++)
                x[i][k] = q[k] + d[k] / len * to;
        }
        assert_int_equal(sim_collider_penetration(c, (const float(*)[4])x, N, 0.001f, &cf, &df), 0);
        assert_int_equal(
            sim_collider_penetration_exact(c, (const float(*)[4])x, N, 0.001f, &ce, &de), 0);
        assert_int_equal(cf, ce);
        assert_float_equal(df, de, 1e-6f);
        assert_int_equal(cf, m == 2 ? N : 0);
        assert_true(m < 2 || df > 0.0019f);
    }
    /* a new body frame: points seen 5 mm outside, then the sphere moves 1 cm along +x, so those
       on its +x side are inside; the bounds of the old frame must not hide them */
    for (int i = 0; i < N; i++)
        for (int k = 0; k < 3; k++)
            x[i][k] = x0[i][k] * (r + 0.005f);
    sim_collider_find_contacts(c, (const float(*)[4])x, 0, N);
    for (int i = 0; i < nv; i++)
        xyz[3 * i] += 0.01f;
    assert_int_equal(sim_collider_set_body(c, xyz, nv, tris, nt), 0);
    assert_int_equal(sim_collider_penetration(c, (const float(*)[4])x, N, 0.001f, &cf, &df), 0);
    assert_int_equal(sim_collider_penetration_exact(c, (const float(*)[4])x, N, 0.001f, &ce, &de),
                     0);
    assert_int_equal(cf, ce);
    assert_float_equal(df, de, 1e-6f);
    assert_true(ce > 0 && ce < N);
    free(xyz);
    free(tris);
    sim_collider_destroy(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_collide_resolve_pushes_out_and_never_pulls_in),
        cmocka_unit_test(test_collide_inelastic_response_adds_no_velocity),
        cmocka_unit_test(test_collide_friction_bounded_by_push),
        cmocka_unit_test(test_collide_penetration_matches_analytic_sphere),
        cmocka_unit_test(test_collide_resolve_clears_sphere_shell),
        cmocka_unit_test(test_collide_quiet_response_equals_full_response),
        cmocka_unit_test(test_collide_track_contacts_matches_search_on_smooth_body),
        cmocka_unit_test(test_collide_penetration_fast_equals_exact),
        cmocka_unit_test(test_collide_deep_points_are_pushed_out),
        cmocka_unit_test(test_collide_penetration_clearance_never_hides_a_point),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
