/* Placement: every shipped garment, and a data set's shirt, on each of the three body shape
 * presets, lands outside the body with each panel's front facing away from it. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bodyfit.h"
#include "garments.h"

/* Placed vertices sit at least this far out from the body's nearest vertex (the clearance is
 * 2 cm; the body's own triangles are about 2 cm across at 6,000 vertices). */
#define MIN_GAP_M 0.005f

typedef struct body {
    fit_model *m;
    const float *xyz;
    float *normals;
    int nv;
} body;

static int nearest(const body *b, const float *p)
{
    int best = 0;
    float bd = INFINITY;
    for (int v = 0; v < b->nv; v++) {
        float dx = p[0] - b->xyz[3 * v], dy = p[1] - b->xyz[3 * v + 1],
              dz = p[2] - b->xyz[3 * v + 2], d = dx * dx + dy * dy + dz * dz;
        if (d < bd)
            bd = d, best = v;
    }
    return best;
}

static void check_outside(const body *b, const gar_mesh *m, const char *what)
{
    for (int v = 0; v < m->num_vertices; v++) {
        const float *p = m->xyz + 3 * v;
        int n = nearest(b, p);
        float d[3] = {p[0] - b->xyz[3 * n], p[1] - b->xyz[3 * n + 1], p[2] - b->xyz[3 * n + 2]};
        float out =
            d[0] * b->normals[3 * n] + d[1] * b->normals[3 * n + 1] + d[2] * b->normals[3 * n + 2];
        if (!(out > 0) || !(sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) > MIN_GAP_M))
            fail_msg("%s: vertex %d (panel %d) at (%.3f %.3f %.3f) is %.4f m from the body, "
                     "%.4f along its normal",
                     what, v, m->panel_of[v], p[0], p[1], p[2],
                     sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), out);
    }
}

/* The point of a body part's axis nearest p: a vertical line through the pelvis, a leg's
 * hip-ankle segment at p's height, an arm's shoulder-wrist segment. */
static void part_axis_point(gar_part part, const float *joints, const float *p, float *out)
{
    static const int ends[GAR_PART_COUNT][2] = {{FIT_PELVIS, FIT_PELVIS},
                                                {FIT_L_SHOULDER, FIT_L_WRIST},
                                                {FIT_R_SHOULDER, FIT_R_WRIST},
                                                {FIT_L_HIP, FIT_L_ANKLE},
                                                {FIT_R_HIP, FIT_R_ANKLE}};
    const float *a = joints + 3 * ends[part][0], *b = joints + 3 * ends[part][1];
    float t;
    if (part == GAR_PART_TORSO) {
        t = 0;
    } else if (part == GAR_PART_LEG_L || part == GAR_PART_LEG_R) {
        t = (a[1] - p[1]) / (a[1] - b[1]);
    } else {
        float d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        t = ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1] + (p[2] - a[2]) * d[2]) /
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    for (int k = 0; k < 3; k++)
        out[k] = a[k] + t * (b[k] - a[k]);
    if (part != GAR_PART_ARM_L && part != GAR_PART_ARM_R)
        out[1] = p[1]; /* vertical parts: the horizontal direction only */
}

/* Each panel's triangles, front normal (ccw in the panel frame), point away from the axis of
 * the body part the panel belongs to. */
static void check_facing(const gar_pattern *p, const fit_model *body, const gar_mesh *m,
                         const char *what)
{
    const float *joints = fit_model_rest_joints(body);
    for (int pi = 0; pi < m->num_panels; pi++) {
        gar_part part = gar_panel_part(p, pi);
        int away = 0, total = 0;
        for (int t = 0; t < m->num_triangles; t++) {
            const int32_t *tr = m->triangles + 3 * t;
            if (m->panel_of[tr[0]] != pi)
                continue;
            const float *a = m->xyz + 3 * tr[0], *c1 = m->xyz + 3 * tr[1], *c2 = m->xyz + 3 * tr[2];
            float e1[3], e2[3], nrm[3], c[3], ax[3];
            for (int k = 0; k < 3; k++)
                e1[k] = c1[k] - a[k], e2[k] = c2[k] - a[k], c[k] = (a[k] + c1[k] + c2[k]) / 3;
            nrm[0] = e1[1] * e2[2] - e1[2] * e2[1];
            nrm[1] = e1[2] * e2[0] - e1[0] * e2[2];
            nrm[2] = e1[0] * e2[1] - e1[1] * e2[0];
            part_axis_point(part, joints, c, ax);
            float out = 0;
            for (int k = 0; k < 3; k++)
                out += nrm[k] * (c[k] - ax[k]);
            away += out > 0;
            total++;
        }
        /* All but where the push-out step folds a panel round a tight spot (1 %). */
        if (away < 0.99 * total)
            fail_msg("%s: panel %d: %d of %d triangles face the body", what, pi, total - away,
                     total);
    }
}

/* Each sleeve panel placed along its arm: its vertices spread along the shoulder-wrist axis over
 * at least 3/4 of the panel's longer side (the data set's sleeves are 31 cm long and 21 cm wide:
 * placed across the arm they spread over 21). */
static void check_sleeves_along_arms(const gar_pattern *p, const fit_model *body, const gar_mesh *m,
                                     const char *what)
{
    const float *jn = fit_model_rest_joints(body);
    for (int pi = 0; pi < m->num_panels; pi++) {
        gar_part part = gar_panel_part(p, pi);
        if (part != GAR_PART_ARM_L && part != GAR_PART_ARM_R)
            continue;
        const gar_panel *pn = &p->panels[pi];
        float lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int v = 0; v < pn->num_vertices; v++)
            for (int k = 0; k < 2; k++)
                lo[k] = fminf(lo[k], pn->uv_m[2 * v + k]),
                hi[k] = fmaxf(hi[k], pn->uv_m[2 * v + k]);
        float longer = fmaxf(hi[0] - lo[0], hi[1] - lo[1]);
        const float *a = jn + 3 * (part == GAR_PART_ARM_L ? FIT_L_SHOULDER : FIT_R_SHOULDER);
        const float *b = jn + 3 * (part == GAR_PART_ARM_L ? FIT_L_WRIST : FIT_R_WRIST);
        float d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), tlo = INFINITY, thi = -INFINITY;
        for (int v = 0; v < m->num_vertices; v++) {
            if (m->panel_of[v] != pi)
                continue;
            const float *q = m->xyz + 3 * v;
            float t = ((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1] + (q[2] - a[2]) * d[2]) / len;
            tlo = fminf(tlo, t), thi = fmaxf(thi, t);
        }
        if (!(thi - tlo >= 0.75f * longer))
            fail_msg("%s: sleeve panel '%s' spreads %.3f m along its arm, its longer side %.3f m",
                     what, pn->name, thi - tlo, longer);
    }
}

static body body_of_preset(int s)
{
    char err[200];
    body b = {0};
    b.m = fit_model_create(&(fit_model_desc){.shape = fit_shape_preset(s), .target_vertices = 6000},
                           err, sizeof err);
    if (!b.m)
        fail_msg("body: %s", err);
    b.nv = fit_model_vertex_count(b.m);
    b.xyz = fit_model_rest_vertices(b.m);
    b.normals = malloc((size_t)b.nv * 3 * sizeof *b.normals);
    assert_non_null(b.normals);
    assert_int_equal(fit_model_normals(b.m, b.xyz, b.normals), 0);
    return b;
}

/* The pattern at path placed on b (its panel named want_panel classed as want): outside the body,
 * facing away; with sleeves, each sleeve panel along its arm. */
static void place_and_check(const body *b, const char *path, const char *want_panel, gar_part want,
                            int sleeves, const char *what)
{
    gar_pattern p;
    gar_mesh m;
    gar_reject why = {0};
    if (gar_pattern_load(path, &p, &why))
        fail_msg("%s: %s", path, why.detail);
    assert_int_equal(gar_panel_part(&p, gar_pattern_find_panel(&p, want_panel)), want);
    assert_int_equal(gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.03f}, &m, &why), 0);
    if (gar_mesh_place(&p, &m, b->m, NULL, NULL, NULL, &why))
        fail_msg("%s: %s", what, why.detail);
    check_outside(b, &m, what);
    check_facing(&p, b->m, &m, what);
    if (sleeves)
        check_sleeves_along_arms(&p, b->m, &m, what);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
}

static void test_shipped_garments_placed_on_presets(void **state)
{
    (void)state;
    const char *names[] = {"tshirt", "jeans", "skirt", "dress"};
    const gar_part want_part[] = {GAR_PART_ARM_L, GAR_PART_LEG_R, GAR_PART_TORSO, GAR_PART_TORSO};
    const char *want_panel[] = {"sleeve_l", "front_r", "front", "back"};
    for (int s = 0; s < FIT_SHAPE_PRESETS; s++) {
        body b = body_of_preset(s);
        for (int g = 0; g < 4; g++) {
            char path[512], what[64];
            snprintf(path, sizeof path, "%s/%s.json", GAR_PATTERN_DIR, names[g]);
            snprintf(what, sizeof what, "%s on %s", names[g], fit_shape_preset_name(s));
            place_and_check(&b, path, want_panel[g], want_part[g], 0, what);
        }
        free(b.normals);
        fit_model_destroy(b.m);
    }
}

/* A file of a public data set (tests/garments/data/NOTICE), its sleeves in two halves running
 * along u: outside the body, facing away, each half along its arm, on every preset. */
static void test_data_set_shirt_placed_on_presets(void **state)
{
    (void)state;
    for (int s = 0; s < FIT_SHAPE_PRESETS; s++) {
        char path[512], what[64];
        body b = body_of_preset(s);
        snprintf(path, sizeof path, "%s/garmentcode_shirt_mean.json", GAR_TEST_DATA_DIR);
        snprintf(what, sizeof what, "data set shirt on %s", fit_shape_preset_name(s));
        place_and_check(&b, path, "left_sleeve_b", GAR_PART_ARM_L, 1, what);
        free(b.normals);
        fit_model_destroy(b.m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_shipped_garments_placed_on_presets),
        cmocka_unit_test(test_data_set_shirt_placed_on_presets),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
