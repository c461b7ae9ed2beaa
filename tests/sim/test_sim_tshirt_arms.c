/* The T-shirt (set-in sleeves) with the arms lowered to the sides (docs/garments.md, "The T-shirt
 * with the arms lowered"): dressed on the body model in the A-pose, then the arms brought down to
 * 6 degrees from vertical. The lowering arm closes the armpit over the cloth, 15-40 mm in a frame;
 * the contact response pushed those points out as velocity, they flew into the body part on the
 * other side, and frames diverged and were carried (22 of 40 here before the response was made
 * inelastic). Now no frame is carried and no published vertex is deeper than issue 19's 5 mm;
 * the strain is only bounded well below divergence (issue 19's 10 % is not met: the body's own
 * skin folds through itself at the armpit, docs/garments-history.md). A coarse garment on a
 * coarse body, so that the sanitizer build runs it in seconds. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bodyfit.h"
#include "outfit_pattern.h"
#include "sim.h"

#define GARMENT_VERTS 1200
#define BODY_VERTS    2000
/* arms_down lowers the arms 39 degrees from the A-pose's 45 over 1.5 s; AMOUNT of that, SPEED
   times as fast, held for the rest of the take */
#define AMOUNT 1.0
#define SPEED  2.0
#define FRAMES 40
/* issue 19's depth bound for every frame ("never deeper than 5 mm"); the strain only bounded
   short of SIM_DIVERGE_STRAIN (50 %): issue 19's 10 % is not met here. The worst spring joins the
   chest to upper-arm skin buried 28 mm inside the chest, and what it reaches swings with the
   garment's starting state: 18-49 % over dressings and resolutions, 29 % with sim's dressing
   today (docs/garments-history.md, "test_sim_tshirt_arms after the merges") */
#define MAX_DEPTH_MM 5.0f
#define MAX_STRAIN   0.35f

static void pose_at(double t_s, fit_pose *pose)
{
    fit_motion_eval(FIT_MOTION_ARMS_DOWN, t_s * SPEED, pose);
    for (int j = 0; j < FIT_JOINT_COUNT; j++) /* rotation vectors: the angle scaled */
        for (int k = 0; k < 3; k++)
            pose->rot[j][k] = (float)(AMOUNT * pose->rot[j][k]);
}

static void test_tshirt_arms_lowered(void **state)
{
    (void)state;
    fit_shape shape = fit_shape_default();
    char err[200];
    fit_model *body = fit_model_create(
        &(fit_model_desc){.shape = shape, .target_vertices = BODY_VERTS}, err, sizeof err);
    assert_non_null(body);
    int nv = fit_model_vertex_count(body), nt = fit_model_triangle_count(body);
    const int32_t *tris = fit_model_triangles(body);
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    float shape_a[FIT_SHAPE_PARAMS], pose_a[FIT_POSE_PARAMS];
    assert_non_null(xyz);
    fit_shape_to_array(&shape, shape_a);
    fit_pose pose;
    pose_at(0.0, &pose);
    memcpy(pose_a, pose.root, sizeof pose.root);
    memcpy(pose_a + 3, pose.rot, sizeof pose.rot);
    assert_int_equal(fit_model_pose(body, &pose, xyz, NULL), 0);

    sim_outfit o;
    sim_reject why = {0};
    sim_garment g = {0};
    assert_int_equal(sim_outfit_resolve(GAR_PATTERN_DIR "/tshirt.json", SIM_SIZE_M, "", &o, &why),
                     0);
    if (sim_outfit_make_pattern(&o, shape_a, FIT_SHAPE_PARAMS, pose_a, FIT_POSE_PARAMS, xyz, nv,
                                tris, nt, GARMENT_VERTS, &g, NULL, &why) != 0)
        fail_msg("%s: %s", sim_error_name(why.code), why.detail);
    sim_desc d = sim_default_desc();
    d.backend = SIM_BACKEND_C;
    d.fabric = o.fabric;
    d.thickness_m = sim_pattern_thickness_m();
    sim *s = sim_create(&d, &g, &why);
    if (!s)
        fail_msg("sim_create: %s", why.detail);
    assert_int_equal(sim_pattern_settle(s, xyz, nv, tris, nt, &why), 0);

    int carried = 0;
    float deepest = 0.0f, worst_strain = 0.0f;
    for (int k = 1; k <= FRAMES; k++) {
        pose_at(k / 30.0, &pose);
        assert_int_equal(fit_model_pose(body, &pose, xyz, NULL), 0);
        sim_frame_stats st;
        if (sim_step(s, xyz, nv, tris, nt, &st, &why) != 0)
            fail_msg("frame %d: %s", k, why.detail);
        print_message("frame %d: %s, %d inside (max %.2f mm), max strain %.3f p99 %.4f\n", k,
                      sim_state_name(st.state), st.penetrating, st.max_pen_mm, st.max_strain,
                      st.p99_strain);
        carried += st.state == SIM_STATE_CARRIED || st.state == SIM_STATE_DIVERGED;
        deepest = fmaxf(deepest, st.max_pen_mm);
        worst_strain = fmaxf(worst_strain, st.max_strain);
    }
    print_message("T-shirt, %d vertices, arms lowered %.1f degrees: %d frames carried, deepest "
                  "%.2f mm, worst max strain %.2f %%\n",
                  g.num_vertices, 39.0 * AMOUNT, carried, deepest, worst_strain * 100.0f);
    assert_int_equal(carried, 0);
    assert_true(deepest <= MAX_DEPTH_MM);
    assert_true(worst_strain <= MAX_STRAIN);
    sim_destroy(s);
    sim_garment_free(&g);
    free(xyz);
    fit_model_destroy(body);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tshirt_arms_lowered),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
