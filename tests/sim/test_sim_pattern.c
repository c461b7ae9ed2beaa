/* A sewing pattern worn by the sim (sim/outfit_pattern.c): the shipped T-shirt dressed on the body
 * model of the body's shape, carried to the first frame of the model's walk, then simulated on a
 * second of the walk (the skirt standing): sewn into one piece (its openings counted), held by its
 * highest opening, finite, no vertex more than 1 mm inside the body, never carried, not falling
 * off the body (the panels were once handed to the sim unsewn and fell off one by one), and the
 * T-shirt's published strain within the figures' bounds. Bodies without the model's parameters
 * and unreadable patterns are refused with the field named. */
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
#include "cloth.h"
#include "outfit_pattern.h"
#include "pattern_weld.h"
#include "sim.h"

#define FRAMES 8
/* The T-shirt's longer take: half a second of the walk (docs/garments.md, "Pattern garments on
 * the moving body"), its strain judged after STRAIN_FROM frames; a coarse garment on a coarse
 * body, so that the sanitizer build runs it in seconds (a frame there costs 50 to 100 times a
 * release build's). */
#define TSHIRT_FRAMES 15
#define STRAIN_FROM   5
#define GARMENT_VERTS 1200
#define BODY_VERTS    2000
/* The garment's lowest point may not sink more than this over the take: a garment sliding off
 * the body (or its panels falling apart) drops tens of centimetres in a second. */
#define MAX_SINK_M 0.03f

/* The mesh's openings: components of its boundary edges (edges of one triangle). */
static int openings(const sim_garment *g)
{
    int nv = g->num_vertices, n = 0;
    int *parent = malloc((size_t)nv * sizeof *parent);
    unsigned char *on = calloc((size_t)nv, 1);
    assert_non_null(parent);
    assert_non_null(on);
    for (int i = 0; i < nv; i++)
        parent[i] = i;
    /* each undirected edge's triangles counted over the sorted edge list (a shell sort) */
    int ne = g->num_triangles * 3;
    long long *key = malloc((size_t)ne * sizeof *key);
    assert_non_null(key);
    for (int t = 0; t < g->num_triangles; t++)
        for (int k = 0; k < 3; k++) {
            long long a = g->triangles[t * 3 + k], b = g->triangles[t * 3 + (k + 1) % 3];
            key[t * 3 + k] = a < b ? a * nv + b : b * nv + a;
        }
    for (int gap = ne / 2; gap > 0; gap /= 2)
        for (int i = gap; i < ne; i++)
            for (int j = i; j >= gap && key[j - gap] > key[j]; j -= gap) {
                long long t = key[j];
                key[j] = key[j - gap];
                key[j - gap] = t;
            }
    for (int i = 0; i < ne;) {
        int j = i + 1;
        while (j < ne && key[j] == key[i])
            j++;
        if (j - i == 1) {
            int a = (int)(key[i] / nv), b = (int)(key[i] % nv);
            on[a] = on[b] = 1;
            while (parent[a] != a)
                a = parent[a];
            while (parent[b] != b)
                b = parent[b];
            parent[a] = b;
        }
        i = j;
    }
    for (int i = 0; i < nv; i++)
        n += on[i] && parent[i] == i;
    free(key);
    free(parent);
    free(on);
    return n;
}

static float lowest_y(const float *x, int n)
{
    float y = INFINITY;
    for (int i = 0; i < n; i++)
        y = fminf(y, x[i * 3 + 1]);
    return y;
}

static void pose_array(const fit_pose *p, float out[FIT_POSE_PARAMS])
{
    memcpy(out, p->root, sizeof p->root);
    memcpy(out + 3, p->rot, sizeof p->rot);
}

/* The pattern at path, size, worn on motion's first frames frames; it has holes openings; with
 * strain set its published strain after the first STRAIN_FROM frames stays within 3 % max and 1 %
 * p99. */
static void wear_on(fit_motion motion, const char *path, sim_size size, const char *id, int frames,
                    int holes, int strain)
{
    fit_shape shape = fit_shape_default();
    char err[200];
    fit_model *body = fit_model_create(
        &(fit_model_desc){.shape = shape, .target_vertices = BODY_VERTS}, err, sizeof err);
    assert_non_null(body);
    int nv = fit_model_vertex_count(body), nt = fit_model_triangle_count(body);
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    float joints[FIT_JOINT_COUNT * 3], shape_a[FIT_SHAPE_PARAMS], pose_a[FIT_POSE_PARAMS];
    assert_non_null(xyz);
    fit_shape_to_array(&shape, shape_a);
    fit_pose pose;
    fit_motion_eval(motion, 0.0, &pose);
    pose_array(&pose, pose_a);

    sim_outfit o;
    sim_reject why = {0};
    assert_int_equal(sim_outfit_resolve(path, size, "", &o, &why), 0);
    assert_true(o.is_pattern);
    assert_string_equal(o.id, id);
    sim_garment g = {0};
    sim_pattern_stats ps;
    assert_int_equal(fit_model_pose(body, &pose, xyz, joints), 0);
    int r = sim_outfit_make_pattern(&o, shape_a, FIT_SHAPE_PARAMS, pose_a, FIT_POSE_PARAMS, xyz, nv,
                                    fit_model_triangles(body), nt, GARMENT_VERTS, &g, &ps, &why);
    if (r != 0)
        fail_msg("%s: %s", sim_error_name(why.code), why.detail);
    assert_true(g.num_vertices > 100 && g.num_triangles > 100);
    assert_int_equal(openings(&g), holes);
    /* held by its highest opening: every attached vertex above the garment's mean height */
    assert_true(g.num_attachments >= 3);
    float mean_y = 0.0f, top_y = INFINITY;
    for (int i = 0; i < g.num_vertices; i++)
        mean_y += g.xyz[i * 3 + 1] / (float)g.num_vertices;
    for (int a = 0; a < g.num_attachments; a++)
        top_y = fminf(top_y, g.xyz[g.attachments[a].vertex * 3 + 1]);
    assert_true(top_y > mean_y);
    print_message("%s dressed in %.0f ms (%.0f ms in all), seams %.1f mm, %d inside\n", id,
                  ps.dress_ms, ps.total_ms, ps.seam_gap_mm, ps.penetrating);

    sim_desc d = sim_default_desc();
    d.backend = SIM_BACKEND_C;
    d.fabric = o.fabric;
    sim *s = sim_create(&d, &g, &why);
    if (!s)
        fail_msg("sim_create: %s", why.detail);
    fit_motion_eval(motion, 0.0, &pose);
    assert_int_equal(fit_model_pose(body, &pose, xyz, joints), 0);
    assert_int_equal(sim_pattern_settle(s, xyz, nv, fit_model_triangles(body), nt, &why), 0);
    float *c = malloc((size_t)g.num_vertices * 3 * sizeof *c);
    assert_non_null(c);
    sim_copy_positions(s, c);
    float start_low = lowest_y(c, g.num_vertices), worst_max = 0.0f, worst_p99 = 0.0f;
    for (int k = 0; k < frames; k++) {
        fit_motion_eval(motion, k / 30.0, &pose);
        assert_int_equal(fit_model_pose(body, &pose, xyz, joints), 0);
        sim_frame_stats st;
        r = sim_step(s, xyz, nv, fit_model_triangles(body), nt, &st, &why);
        if (r != 0)
            fail_msg("frame %d: %s", k, why.detail);
        print_message("frame %d: %s, %.1f ms, %d inside (max %.2f mm), max strain %.3f\n", k,
                      sim_state_name(st.state), st.ms_total, st.penetrating, st.max_pen_mm,
                      st.max_strain);
        assert_int_equal(st.penetrating, 0);
        assert_true(st.state != SIM_STATE_DIVERGED && st.state != SIM_STATE_CARRIED);
        if (k >= STRAIN_FROM) {
            worst_max = fmaxf(worst_max, st.max_strain);
            worst_p99 = fmaxf(worst_p99, st.p99_strain);
        }
    }
    sim_copy_positions(s, c);
    for (int i = 0; i < g.num_vertices * 3; i++)
        assert_true(isfinite(c[i]));
    print_message("%s: %d vertices, %d attached, lowest point %.1f mm lower after %d frames, "
                  "worst max / p99 strain %.2f / %.2f %%\n",
                  id, g.num_vertices, g.num_attachments,
                  (start_low - lowest_y(c, g.num_vertices)) * 1e3f, frames, worst_max * 100.0f,
                  worst_p99 * 100.0f);
    assert_true(start_low - lowest_y(c, g.num_vertices) < MAX_SINK_M);
    if (strain) {
        assert_true(worst_max <= 0.03f);
        assert_true(worst_p99 <= 0.01f);
    }
    free(c);
    sim_destroy(s);
    sim_garment_free(&g);
    free(xyz);
    fit_model_destroy(body);
}

static void test_tshirt_walks(void **state)
{
    (void)state;
    wear_on(FIT_MOTION_WALK, GAR_PATTERN_DIR "/tshirt.json", SIM_SIZE_M, "tshirt.json M cotton",
            TSHIRT_FRAMES, 4, 1);
}

/* The moving frame (sim/follow.c) of the pattern at path on the walk's second frame: its anchors
 * (0: it follows its attachments) and how far it turns the garment, degrees. Dressed on the walk's
 * first pose and settled there, as wear_on does. */
static void follow_on_walk(const char *path, int *anchors, float *turn_deg)
{
    char err[200];
    fit_shape shape = fit_shape_default();
    fit_model *body = fit_model_create(
        &(fit_model_desc){.shape = shape, .target_vertices = BODY_VERTS}, err, sizeof err);
    assert_non_null(body);
    int nv = fit_model_vertex_count(body), nt = fit_model_triangle_count(body);
    const int32_t *tris = fit_model_triangles(body);
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    float joints[FIT_JOINT_COUNT * 3], shape_a[FIT_SHAPE_PARAMS], pose_a[FIT_POSE_PARAMS];
    assert_non_null(xyz);
    fit_shape_to_array(&shape, shape_a);
    fit_pose pose;
    fit_motion_eval(FIT_MOTION_WALK, 0.0, &pose);
    pose_array(&pose, pose_a);
    assert_int_equal(fit_model_pose(body, &pose, xyz, joints), 0);
    sim_outfit o;
    sim_reject why = {0};
    sim_garment g = {0};
    assert_int_equal(sim_outfit_resolve(path, SIM_SIZE_M, "", &o, &why), 0);
    assert_int_equal(sim_outfit_make_pattern(&o, shape_a, FIT_SHAPE_PARAMS, pose_a, FIT_POSE_PARAMS,
                                             xyz, nv, tris, nt, GARMENT_VERTS, &g, NULL, &why),
                     0);
    sim_desc d = sim_default_desc();
    d.backend = SIM_BACKEND_C;
    d.fabric = o.fabric;
    sim *s = sim_create(&d, &g, &why);
    assert_non_null(s);
    assert_int_equal(sim_pattern_settle(s, xyz, nv, tris, nt, &why), 0);
    fit_motion_eval(FIT_MOTION_WALK, 1.0 / 30.0, &pose);
    assert_int_equal(fit_model_pose(body, &pose, xyz, joints), 0);
    sim_step(s, xyz, nv, tris, nt, NULL, &why); /* the frame's outcome is not the question */
    const float *m = s->follow_m;
    *anchors = s->num_follow_anchors;
    *turn_deg = acosf(fminf(1.0f, (m[0] + m[5] + m[10] - 1.0f) / 2.0f)) * 57.29578f;
    print_message(
        "%s: moving frame on %d anchors, turned %.2f degrees on the walk's second frame\n", path,
        *anchors, *turn_deg);
    sim_destroy(s);
    sim_garment_free(&g);
    free(xyz);
    fit_model_destroy(body);
}

/* Trousers follow their waist band, not their thighs. Half way down the jeans' longest tether
 * (where a shirt's waist is) are the thighs, which swing opposite ways in a stride: fitted to
 * them, the moving frame turned the jeans 7.8 degrees on the walk's first frame, the frame
 * diverged and the jeans were dressed again in the rest pose, their legs inside the striding ones
 * (docs/garments.md, "The jeans on the walk"). The T-shirt keeps its waist. */
static void test_trousers_follow_the_waist(void **state)
{
    (void)state;
    int anchors;
    float turn;
    follow_on_walk(GAR_PATTERN_DIR "/jeans.json", &anchors, &turn);
    assert_int_equal(anchors, 0);
    assert_true(turn < 2.0f);
    follow_on_walk(GAR_PATTERN_DIR "/tshirt.json", &anchors, &turn);
    assert_true(anchors >= 3);
}

static void test_skirt_stands(void **state)
{
    (void)state;
    /* standing: on the walk the skirt L does not hold yet (its waistband is dressed onto the
       thighs), nor the jeans at this coarse mesh (docs/garments.md, "The jeans on the walk") */
    wear_on(FIT_MOTION_STILL, GAR_PATTERN_DIR "/skirt.json", SIM_SIZE_L, "skirt.json L cotton",
            FRAMES, 2, 0);
}

/* Two unit squares of two triangles each, side by side with a 1 mm gap (x = 1 and x = 1.001),
 * sewn along that edge: two point-point joints. Then the right square's edge eased onto the left
 * one's: its middle vertex joined by a point-edge joint to the nearer end. */
static void test_weld_sews_seams(void **state)
{
    (void)state;
    float xyz[] = {0,      0, 0, 1, 0, 0, 1, 1, 0, 0,      1, 0,
                   1.001f, 0, 0, 2, 0, 0, 2, 1, 0, 1.001f, 1, 0};
    int32_t tris[] = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
    gar_joint joints[] = {{.a = 4, .b0 = 1, .b1 = 1}, {.a = 7, .b0 = 2, .b1 = 2}};
    int8_t part[8] = {0, 0, 0, 0, 1, 1, 1, 1};
    gar_mesh m = {.num_vertices = 8,
                  .xyz = xyz,
                  .num_triangles = 4,
                  .triangles = tris,
                  .num_joints = 2,
                  .joints = joints};
    sim_garment g = {0};
    sim_reject why = {0};
    assert_int_equal(sim_pattern_weld(&m, &g, part, &why), 0);
    assert_int_equal(g.num_vertices, 6); /* 4 and 7 joined 1 and 2 */
    assert_int_equal(g.num_triangles, 4);
    assert_float_equal(g.xyz[1 * 3], 1.0005f, 1e-6f); /* the mean of the two sides */
    for (int i = 0; i < g.num_triangles * 3; i++)
        assert_true(g.triangles[i] >= 0 && g.triangles[i] < 6);
    assert_int_equal(part[4], 1); /* vertex 5 (the right square's) is now vertex 4 */
    assert_int_equal(openings(&g), 1);
    sim_garment_free(&g);

    /* a point-edge joint: vertex 8 in the middle of the right square's left edge goes to the
       nearer end (w 0.4: b0) of the left square's edge; the triangles that lose a corner drop */
    float xyz2[] = {0, 0, 0, 1, 0, 0, 1, 1,      0, 0, 1,      0,    1.001f, 0,
                    0, 2, 0, 0, 2, 1, 0, 1.001f, 1, 0, 1.001f, 0.4f, 0};
    int32_t tris2[] = {0, 1, 2, 0, 2, 3, 4, 5, 8, 8, 5, 6, 8, 6, 7};
    gar_joint joints2[] = {{.a = 4, .b0 = 1, .b1 = 1},
                           {.a = 7, .b0 = 2, .b1 = 2},
                           {.a = 8, .b0 = 1, .b1 = 2, .w = 0.4f}};
    m = (gar_mesh){.num_vertices = 9,
                   .xyz = xyz2,
                   .num_triangles = 5,
                   .triangles = tris2,
                   .num_joints = 3,
                   .joints = joints2};
    assert_int_equal(sim_pattern_weld(&m, &g, NULL, &why), 0);
    assert_int_equal(g.num_vertices, 6);
    assert_int_equal(g.num_triangles, 4); /* (4 5 8) lost a corner: 4 and 8 are both 1 now */
    sim_garment_free(&g);

    /* every triangle sewn shut: refused by name */
    gar_joint all[] = {{.a = 1, .b0 = 0, .b1 = 0}, {.a = 2, .b0 = 0, .b1 = 0}};
    m = (gar_mesh){.num_vertices = 4,
                   .xyz = xyz,
                   .num_triangles = 2,
                   .triangles = tris,
                   .num_joints = 2,
                   .joints = all};
    assert_int_equal(sim_pattern_weld(&m, &g, NULL, &why), -SIM_ERR_EMPTY);
    assert_non_null(strstr(why.detail, "sewing"));
    assert_null(g.xyz);
}

static void test_refusals(void **state)
{
    (void)state;
    sim_outfit o;
    sim_reject why = {0};
    sim_garment g = {0};
    float shape_a[FIT_SHAPE_PARAMS], pose_a[FIT_POSE_PARAMS] = {0};
    fit_shape shape = fit_shape_default();
    fit_shape_to_array(&shape, shape_a);
    assert_int_equal(sim_outfit_resolve(GAR_PATTERN_DIR "/skirt.json", SIM_SIZE_S, "", &o, &why),
                     0);
    /* a body message without the model's parameters */
    assert_int_equal(sim_outfit_make_pattern(&o, NULL, 0, pose_a, FIT_POSE_PARAMS, NULL, 0, NULL, 0,
                                             0, &g, NULL, &why),
                     -SIM_ERR_PARAM);
    assert_non_null(strstr(why.detail, "shape"));
    /* a shape out of the model's range */
    float bad[FIT_SHAPE_PARAMS];
    memcpy(bad, shape_a, sizeof bad);
    bad[0] = 50.0f;
    assert_int_equal(sim_outfit_make_pattern(&o, bad, FIT_SHAPE_PARAMS, pose_a, FIT_POSE_PARAMS,
                                             NULL, 0, NULL, 0, 0, &g, NULL, &why),
                     -SIM_ERR_PARAM);
    /* a pattern that cannot be read: no body helps */
    assert_int_equal(sim_outfit_resolve("/nonexistent/none.json", SIM_SIZE_M, "", &o, &why), 0);
    assert_int_equal(sim_outfit_make_pattern(&o, shape_a, FIT_SHAPE_PARAMS, pose_a, FIT_POSE_PARAMS,
                                             NULL, 0, NULL, 0, 0, &g, NULL, &why),
                     -SIM_ERR_FILE);
    assert_non_null(strstr(why.detail, "none.json"));
    assert_null(g.xyz);
    /* the generic maker refuses a pattern instead of reading it as something else */
    assert_true(sim_outfit_make(&o, NULL, 0, NULL, 0, NULL, 0, &g, &why) < 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_weld_sews_seams), cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_tshirt_walks),    cmocka_unit_test(test_trousers_follow_the_waist),
        cmocka_unit_test(test_skirt_stands),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
