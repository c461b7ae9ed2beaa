/* Each collision kernel against its C twin on random input (STYLE.md 8): a sphere body moved and
 * deformed between two frames, cloth points scattered around it. Skipped when no OpenCL device
 * exists. Tolerances: the tree is integer work and min/max (exact); positions go through the same
 * float operations in the same order with fma contraction off and correctly rounded / and sqrt,
 * so they agree to 1e-6 m (a few ulps at 1 m) - acos in vertex pseudo-normals may differ by ulps.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "cl_collide.h"
#include "test_collide_util.h"

#define NP      3000
#define POS_TOL 1e-6f

typedef struct fixture {
    sim_cl cl;
    sim_cl_collide g;
    sim_collider *c;
    float *xyz0, *xyz1;
    int32_t *tris;
    int nv, nt;
    cl_mem x, x_prev;
    float (*hx)[4], (*hxp)[4];
} fixture;

static int setup(void **state)
{
    static fixture f;
    memset(&f, 0, sizeof f);
    char err[512];
    int rc = sim_cl_open(&f.cl, err, sizeof err);
    if (rc != 0) {
        fprintf(stderr, "no OpenCL device, skipping: %s\n", err);
        *state = NULL;
        return 0;
    }
    const char *files[] = {SIM_CL_COLLIDE_FILES};
    if (sim_cl_build(&f.cl, files, (int)(sizeof files / sizeof files[0]), err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    tc_sphere(0.2f, 40, 20, &f.xyz0, &f.nv, &f.tris, &f.nt);
    f.xyz1 = malloc((size_t)f.nv * 3 * sizeof *f.xyz1);
    uint32_t s = 2024u;
    for (int i = 0; i < f.nv; i++) {
        /* Frame k: 3 cm up and 2 cm along x, scaled by 1.05, every vertex jittered by 5 mm. */
        f.xyz1[3 * i] = 1.05f * f.xyz0[3 * i] + 0.02f + tc_range(&s, -0.005f, 0.005f);
        f.xyz1[3 * i + 1] = 1.05f * f.xyz0[3 * i + 1] + 0.03f + tc_range(&s, -0.005f, 0.005f);
        f.xyz1[3 * i + 2] = 1.05f * f.xyz0[3 * i + 2] + tc_range(&s, -0.005f, 0.005f);
    }
    f.c = sim_collider_create(&(sim_collider_desc){.max_vertices = f.nv,
                                                   .max_triangles = f.nt,
                                                   .thickness_m = 0.004f,
                                                   .friction = 0.4f,
                                                   .max_cloth = NP},
                              err, sizeof err);
    if (!f.c || sim_cl_collide_create(&f.g, &f.cl, f.nv, f.nt, NP, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return -1;
    }
    f.hx = malloc(NP * sizeof *f.hx);
    f.hxp = malloc(NP * sizeof *f.hxp);
    for (int i = 0; i < NP; i++) {
        float d[3], len;
        do {
            for (int k = 0; k < 3; k++)
                d[k] = tc_range(&s, -1.0f, 1.0f);
            len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        } while (len < 0.1f || len > 1.0f);
        /* every tenth point deep inside, beyond reach of the surface */
        float r = i % 10 == 5 ? tc_range(&s, 0.03f, 0.15f) : tc_range(&s, 0.195f, 0.26f);
        for (int k = 0; k < 3; k++)
            f.hx[i][k] = d[k] / len * r;
        f.hx[i][3] = i % 50 == 0 ? 0.0f : 1.0f;
        for (int k = 0; k < 3; k++)
            f.hxp[i][k] = f.hx[i][k] + tc_range(&s, -0.002f, 0.002f);
        f.hxp[i][3] = f.hx[i][3];
    }
    cl_int st;
    f.x = clCreateBuffer(f.cl.context, CL_MEM_READ_WRITE, NP * 16, NULL, &st);
    f.x_prev = clCreateBuffer(f.cl.context, CL_MEM_READ_WRITE, NP * 16, NULL, &st);
    /* Two frames on both sides. */
    if (sim_collider_set_body(f.c, f.xyz0, f.nv, f.tris, f.nt) != 0 ||
        sim_cl_collide_set_body(&f.g, f.c, err, sizeof err) != 0 ||
        sim_collider_set_body(f.c, f.xyz1, f.nv, f.tris, f.nt) != 0 ||
        sim_cl_collide_set_body(&f.g, f.c, err, sizeof err) != 0) {
        fprintf(stderr, "set_body: %s\n", err);
        return -1;
    }
    *state = &f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    if (!f)
        return 0;
    if (f->x)
        clReleaseMemObject(f->x);
    if (f->x_prev)
        clReleaseMemObject(f->x_prev);
    sim_cl_collide_destroy(&f->g);
    sim_cl_close(&f->cl);
    sim_collider_destroy(f->c);
    free(f->xyz0);
    free(f->xyz1);
    free(f->tris);
    free(f->hx);
    free(f->hxp);
    return 0;
}

static void read(fixture *f, cl_mem m, size_t bytes, void *dst)
{
    assert_int_equal(clEnqueueReadBuffer(f->cl.queue, m, CL_TRUE, 0, bytes, dst, 0, NULL, NULL),
                     CL_SUCCESS);
}

static void put(fixture *f, cl_mem m, size_t bytes, const void *src)
{
    assert_int_equal(clEnqueueWriteBuffer(f->cl.queue, m, CL_TRUE, 0, bytes, src, 0, NULL, NULL),
                     CL_SUCCESS);
}

static void test_cl_bvh_refit_matches_c(void **state)
{
    fixture *f = *state;
    if (!f)
        skip();
    int nodes = 2 * f->nt - 1;
    float(*b)[4] = malloc((size_t)nodes * sizeof *b);
    float(*boxes[4])[4] = {f->c->bvh.lo, f->c->bvh.hi, f->c->bvh.slo, f->c->bvh.shi};
    cl_mem dev[4] = {f->g.lo, f->g.hi, f->g.slo, f->g.shi};
    for (int j = 0; j < 4; j++) {
        read(f, dev[j], (size_t)nodes * 16, b);
        for (int i = 0; i < nodes; i++)
            for (int k = 0; k < 3; k++)
                assert_true(b[i][k] == boxes[j][i][k]);
    }
    float(*n)[4] = malloc((size_t)f->nt * sizeof *n);
    read(f, f->g.n, (size_t)f->nt * 16, n);
    for (int t = 0; t < f->nt; t++)
        for (int k = 0; k < 3; k++)
            assert_float_equal(n[t][k], f->c->n[t][k], 1e-7f);
    free(n);
    free(b);
}

static void test_cl_bvh_morton_and_hierarchy_match_c(void **state)
{
    fixture *f = *state;
    if (!f)
        skip();
    int nt = f->nt;
    /* Codes of frame k in a box chosen here; the C twin is sim_morton3 on the same numbers. */
    cl_float4 lo = {{-0.3f, -0.3f, -0.3f, 0.0f}}, ext = {{0.6f, 0.7f, 0.6f, 1.0f}};
    cl_kernel k = f->g.k_morton;
    assert_int_equal(clSetKernelArg(k, 0, sizeof(cl_mem), &f->g.v), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 1, sizeof(cl_mem), &f->g.tris), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 2, sizeof(int), &nt), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 3, sizeof lo, &lo), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 4, sizeof ext, &ext), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 5, sizeof(cl_mem), &f->g.morton), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 6, sizeof(cl_mem), &f->g.order), CL_SUCCESS);
    size_t global = (size_t)nt;
    assert_int_equal(clEnqueueNDRangeKernel(f->cl.queue, k, 1, NULL, &global, NULL, 0, NULL, NULL),
                     CL_SUCCESS);
    uint32_t *codes = malloc((size_t)nt * sizeof *codes);
    read(f, f->g.morton, (size_t)nt * 4, codes);
    const float(*v)[4] = (const float(*)[4])f->c->v;
    for (int t = 0; t < nt; t++) {
        const int32_t *tr = f->c->tris[t];
        float q[3];
        for (int a = 0; a < 3; a++)
            q[a] = ((v[tr[0]][a] + v[tr[1]][a] + v[tr[2]][a]) / 3.0f - lo.s[a]) / ext.s[a];
        assert_int_equal(codes[t], sim_morton3(q[0], q[1], q[2]));
    }
    /* Hierarchy from the sorted codes of the C LBVH over the same frame: the same tree, node for
       node. (The collider's own tree is the SAH one, sim/bvh.c; the device refits that.) */
    sim_bvh lbvh;
    assert_int_equal(sim_bvh_init(&lbvh, nt), 0);
    sim_bvh_build_lbvh(&lbvh, (const float(*)[4])f->c->v, v, (const int32_t(*)[4])f->c->tris, nt,
                       0.0f);
    put(f, f->g.morton, (size_t)nt * 4, lbvh.morton);
    cl_int st;
    cl_mem child = clCreateBuffer(f->cl.context, CL_MEM_READ_WRITE, (size_t)nt * 8, NULL, &st);
    cl_mem parent =
        clCreateBuffer(f->cl.context, CL_MEM_READ_WRITE, (size_t)(2 * nt - 1) * 4, NULL, &st);
    k = f->g.k_nodes;
    assert_int_equal(clSetKernelArg(k, 0, sizeof(cl_mem), &f->g.morton), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 1, sizeof(int), &nt), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 2, sizeof(cl_mem), &child), CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 3, sizeof(cl_mem), &parent), CL_SUCCESS);
    global = (size_t)(nt - 1);
    assert_int_equal(clEnqueueNDRangeKernel(f->cl.queue, k, 1, NULL, &global, NULL, 0, NULL, NULL),
                     CL_SUCCESS);
    int32_t(*ch)[2] = malloc((size_t)nt * sizeof *ch);
    int32_t *par = malloc((size_t)(2 * nt - 1) * sizeof *par);
    read(f, child, (size_t)(nt - 1) * 8, ch);
    read(f, parent, (size_t)(2 * nt - 1) * 4, par);
    for (int i = 0; i < nt - 1; i++) {
        assert_int_equal(ch[i][0], lbvh.child[i][0]);
        assert_int_equal(ch[i][1], lbvh.child[i][1]);
    }
    for (int i = 0; i < 2 * nt - 1; i++)
        assert_int_equal(par[i], lbvh.parent[i]);
    sim_bvh_free(&lbvh);
    /* The device collider's sorted order is used by the other tests: put it back. */
    put(f, f->g.order, (size_t)nt * 4, f->c->bvh.order);
    clReleaseMemObject(child);
    clReleaseMemObject(parent);
    free(ch);
    free(par);
    free(codes);
}

static void compare_points(float (*a)[4], float (*b)[4], int n)
{
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 4; k++)
            assert_float_equal(a[i][k], b[i][k], POS_TOL);
}

static void feature_points_match_c(fixture *f, int coulomb)
{
    f->c->d.carry_coulomb = coulomb;
    float(*x)[4] = malloc(NP * sizeof *x), (*xp)[4] = malloc(NP * sizeof *xp);
    float(*dx)[4] = malloc(NP * sizeof *dx), (*dxp)[4] = malloc(NP * sizeof *dxp);
    memcpy(x, f->hx, NP * sizeof *x);
    memcpy(xp, f->hxp, NP * sizeof *xp);
    put(f, f->x, NP * 16, x);
    put(f, f->x_prev, NP * 16, xp);
    int moved = sim_collider_feature_points(f->c, x, xp, 0, NP);
    assert_true(moved > 100); /* the case is not vacuous */
    assert_int_equal(sim_cl_collide_feature_points(&f->g, f->x, f->x_prev, 0, NP, 0.004f,
                                                   coulomb ? f->c->d.friction : -1.0f),
                     0);
    read(f, f->x, NP * 16, dx);
    read(f, f->x_prev, NP * 16, dxp);
    int32_t *flags = malloc(NP * sizeof *flags);
    read(f, f->g.moved, NP * 4, flags);
    int dmoved = 0;
    for (int i = 0; i < NP; i++)
        dmoved += flags[i];
    assert_int_equal(dmoved, moved);
    compare_points(x, dx, NP);
    compare_points(xp, dxp, NP);
    free(flags);
    free(x);
    free(xp);
    free(dx);
    free(dxp);
    f->c->d.carry_coulomb = 0;
}

/* Both carries: seed 000's Eq. 2 and the tryon solver's Coulomb-bounded one. */
static void test_cl_feature_points_match_c(void **state)
{
    fixture *f = *state;
    if (!f)
        skip();
    feature_points_match_c(f, 0);
    feature_points_match_c(f, 1);
}

static void test_cl_contacts_resolve_and_distance_match_c(void **state)
{
    fixture *f = *state;
    if (!f)
        skip();
    float(*x)[4] = malloc(NP * sizeof *x), (*xp)[4] = malloc(NP * sizeof *xp);
    float(*dx)[4] = malloc(NP * sizeof *dx);
    memcpy(x, f->hx, NP * sizeof *x);
    memcpy(xp, f->hxp, NP * sizeof *xp);
    put(f, f->x, NP * 16, x);
    put(f, f->x_prev, NP * 16, xp);
    sim_collider_find_contacts(f->c, (const float(*)[4])x, 0, NP);
    assert_int_equal(sim_cl_collide_find_contacts(&f->g, f->x, 0, NP, 0.004f + 0.03f), 0);
    int32_t *dc = malloc(NP * sizeof *dc);
    read(f, f->g.contact, NP * 4, dc);
    int found = 0;
    for (int i = 0; i < NP; i++) {
        assert_int_equal(dc[i], f->c->contact[i]);
        found += dc[i] >= 0;
    }
    assert_true(found > NP / 2);
    sim_collider_resolve(f->c, x, xp, 0, NP);
    assert_int_equal(sim_cl_collide_resolve(&f->g, f->x, f->x_prev, 0, NP, 0.004f, 0.4f), 0);
    read(f, f->x, NP * 16, dx);
    compare_points(x, dx, NP);
    /* The surface walk from the cached triangles, after every point moved up to 8 mm. */
    uint32_t s = 77u;
    for (int i = 0; i < NP; i++)
        for (int k = 0; k < 3; k++)
            x[i][k] += tc_range(&s, -0.008f, 0.008f);
    put(f, f->x, NP * 16, x);
    sim_collider_track_contacts(f->c, (const float(*)[4])x, 0, NP);
    assert_int_equal(sim_cl_collide_track_contacts(&f->g, f->x, 0, NP, 0.004f + 0.03f), 0);
    read(f, f->g.contact, NP * 4, dc);
    for (int i = 0; i < NP; i++)
        assert_int_equal(dc[i], f->c->contact[i]);
    /* Signed distance of the original points. */
    put(f, f->x, NP * 16, f->hx);
    assert_int_equal(sim_cl_collide_signed_distance(&f->g, f->x, NP), 0);
    float *sd = malloc(NP * sizeof *sd);
    read(f, f->g.sd, NP * 4, sd);
    const float(*v)[4], (*vp)[4], (*n)[4];
    const int32_t(*t)[4];
    sim_collider_body(f->c, &v, &vp, &t, &n);
    for (int i = 0; i < NP; i++) {
        float q[3], bary[3], d;
        int tri = sim_bvh_nearest(&f->c->bvh, v, t, f->hx[i], INFINITY, q, bary, &d);
        assert_true(tri >= 0);
        assert_float_equal(sd[i], sim_collider_signed_distance(f->c, tri, f->hx[i]), POS_TOL);
    }
    free(sd);
    free(dc);
    free(x);
    free(xp);
    free(dx);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cl_bvh_refit_matches_c),
        cmocka_unit_test(test_cl_bvh_morton_and_hierarchy_match_c),
        cmocka_unit_test(test_cl_feature_points_match_c),
        cmocka_unit_test(test_cl_contacts_resolve_and_distance_match_c),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
