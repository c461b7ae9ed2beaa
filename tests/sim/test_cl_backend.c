/* The OpenCL backend agrees with the C reference: the same drape sheet falling on a sphere that
 * rises through it (feature points, contacts, friction, springs, strain limiting, one vertex
 * attached to the sphere), run with both backends from sim_create. Skipped when no OpenCL device
 * exists.
 *
 * Tolerance: both run the same float operations in the same order (fma contraction off,
 * correctly rounded divide and sqrt, acos from basic operations), and on PoCL they agree bit for
 * bit. A GPU's compiler may still order a reduction or a library call differently, and contacts
 * turn an ulp into a different branch; 0.1 mm is 1/40 of the cloth thickness: far below anything
 * visible, far above rounding. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "cl_collide.h"
#include "cl_context.h"
#include "solver_params.h"
#include "sim.h"
#include "test_collide_util.h"

#define FRAMES    8
#define AGREE_TOL 1e-4f

static int have_device(void)
{
    sim_cl cl;
    char err[256];
    if (sim_cl_open(&cl, err, sizeof err) != 0) {
        fprintf(stderr, "skipping: %s\n", err);
        return 0;
    }
    sim_cl_close(&cl);
    return 1;
}

static sim *make(sim_backend b, const sim_garment *g)
{
    sim_desc d = sim_default_desc();
    d.backend = b;
    d.max_body_vertices = 4000;
    d.max_body_triangles = 8000;
    sim_reject why;
    memset(&why, 0, sizeof why);
    sim *s = sim_create(&d, g, &why);
    if (!s)
        fprintf(stderr, "sim_create(%s): %s\n", b == SIM_BACKEND_C ? "c" : "opencl", why.detail);
    assert_non_null(s);
    return s;
}

static void test_cl_backend_agrees_with_c(void **state)
{
    (void)state;
    if (!have_device())
        skip();
    sim_garment g;
    memset(&g, 0, sizeof g);
    assert_int_equal(sim_garment_drape(400, 0.8f, 0.25f, &g), 0);
    float *xyz, *moved;
    int32_t *tris;
    int nv, nt;
    tc_sphere(0.2f, 32, 16, &xyz, &nv, &tris, &nt);
    moved = malloc((size_t)nv * 3 * sizeof *moved);
    /* One vertex near the sheet's centre glued 4 cm above the sphere's cap: the attachment
       path (targets, placement spread over the steps) runs on both backends. */
    sim_attachment glue = {
        .vertex = 210, .body_triangle = 0, .bary = {0.34f, 0.33f, 0.33f}, .offset_m = 0.04f};
    g.num_attachments = 1;
    g.attachments = &glue;
    sim *sc = make(SIM_BACKEND_C, &g), *so = make(SIM_BACKEND_OPENCL, &g);
    float worst = 0.0f;
    int fp_c = 0, fp_o = 0;
    for (int f = 0; f < FRAMES; f++) {
        /* The sphere rises 1.5 cm a frame: it sweeps the sheet (feature points). */
        for (int i = 0; i < nv; i++) {
            moved[3 * i] = xyz[3 * i];
            moved[3 * i + 1] = xyz[3 * i + 1] + 0.015f * (float)f;
            moved[3 * i + 2] = xyz[3 * i + 2];
        }
        sim_frame_stats a, b;
        sim_reject why;
        int rc = sim_step(sc, moved, nv, tris, nt, &a, &why);
        if (rc != 0)
            fprintf(stderr, "frame %d: %s\n", f, why.detail);
        assert_int_equal(rc, 0);
        assert_int_equal(sim_step(so, moved, nv, tris, nt, &b, &why), 0);
        fp_c += a.feature_points_moved;
        fp_o += b.feature_points_moved;
        /* the metric runs on the host for both, from each backend's own contacts */
        assert_int_equal(a.penetrating, b.penetrating);
        assert_float_equal(a.max_pen_mm, b.max_pen_mm, 1e-3f);
        assert_float_equal(a.max_strain, b.max_strain, 1e-4f);
        const float *pc = sim_positions(sc), *po = sim_positions(so);
        for (int i = 0; i < 4 * sim_vertex_count(sc); i++)
            worst = fmaxf(worst, fabsf(pc[i] - po[i]));
    }
    fprintf(stderr, "%s vs %s: max |dx| %.3g m over %d frames; feature points %d / %d\n",
            sim_device_name(sc), sim_device_name(so), (double)worst, FRAMES, fp_c, fp_o);
    assert_true(fp_c > 0);
    assert_true(worst <= AGREE_TOL);
    /* TRYON_CL_PASSES=1 (test_cl_backend_passes): the frame ran pass by pass, as on a GPU */
    const char *passes = getenv("TRYON_CL_PASSES");
    if (passes && !strcmp(passes, "1"))
        assert_non_null(strstr(sim_device_name(so), "pass by pass"));
    sim_destroy(sc);
    sim_destroy(so);
    g.num_attachments = 0;
    g.attachments = NULL; /* the test's own array, not the garment's */
    sim_garment_free(&g);
    free(xyz);
    free(moved);
    free(tris);
}

/* sim_solver_params as the device compiles it: the host's size and last field's offset. */
static void test_cl_solver_params_layout(void **state)
{
    (void)state;
    if (!have_device())
        skip();
    sim_cl cl;
    char err[256] = "";
    const char *files[] = {SIM_CL_COLLIDE_FILES, "solver_params.h", "springs.cl"};
    assert_int_equal(sim_cl_open(&cl, err, sizeof err), 0);
    assert_int_equal(
        sim_cl_build(&cl, files, (int)(sizeof files / sizeof files[0]), err, sizeof err), 0);
    cl_kernel k = sim_cl_kernel(&cl, "sim_solver_params_layout", err, sizeof err);
    assert_non_null(k);
    cl_int st;
    cl_mem out = clCreateBuffer(cl.context, CL_MEM_WRITE_ONLY, 2 * sizeof(cl_int), NULL, &st);
    assert_int_equal(st, CL_SUCCESS);
    assert_int_equal(clSetKernelArg(k, 0, sizeof out, &out), CL_SUCCESS);
    size_t one = 1;
    assert_int_equal(clEnqueueNDRangeKernel(cl.queue, k, 1, NULL, &one, NULL, 0, NULL, NULL),
                     CL_SUCCESS);
    cl_int got[2] = {-1, -1};
    assert_int_equal(clEnqueueReadBuffer(cl.queue, out, CL_TRUE, 0, sizeof got, got, 0, NULL, NULL),
                     CL_SUCCESS);
    printf("# device: sim_solver_params %d bytes, rest_tol at %d\n", got[0], got[1]);
    assert_int_equal(got[0], (int)sizeof(sim_solver_params));
    assert_int_equal(got[1], (int)offsetof(sim_solver_params, rest_tol));
    clReleaseMemObject(out);
    clReleaseKernel(k);
    sim_cl_close(&cl);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cl_backend_agrees_with_c),
        cmocka_unit_test(test_cl_solver_params_layout),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
