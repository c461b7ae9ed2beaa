/* The pattern reader against hand-computed outlines, and malformed patterns refused by name. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "garments.h"

#define PI 3.14159265358979323846
/* Reader arithmetic is float: 1e-5 m is far below anything a pattern draws. */
#define TOL_M 1e-5f

static int parse(const char *json, gar_pattern *p, gar_reject *why)
{
    return gar_pattern_parse(json, strlen(json), p, why);
}

/* A 100 x 100 panel (file units) whose bottom edge carries the given curvature JSON. */
static void square_with(const char *curvature, const char *props, char *out, size_t n)
{
    snprintf(out, n,
             "{\"pattern\": {\"panels\": {\"a\": {\"vertices\": [[0,0],[100,0],[100,100],[0,100]],"
             "\"edges\": [{\"endpoints\": [0,1]%s%s}, {\"endpoints\": [1,2]},"
             "{\"endpoints\": [2,3]}, {\"endpoints\": [3,0]}],"
             "\"translation\": [0, 50, 0], \"rotation\": [0, 0, 0]}}},"
             "\"properties\": {%s}}",
             curvature[0] ? ", \"curvature\": " : "", curvature, props);
}

static void test_square_outline_in_metres(void **state)
{
    (void)state;
    char js[1024];
    square_with("", "\"curvature_coords\": \"relative\", \"units_in_meter\": 100", js, sizeof js);
    gar_pattern p;
    gar_reject why = {0};
    assert_int_equal(parse(js, &p, &why), 0);
    assert_int_equal(p.num_panels, 1);
    const gar_panel *a = &p.panels[0];
    assert_string_equal(a->name, "a");
    assert_int_equal(a->num_edges, 4);
    assert_float_equal(a->uv_m[4], 1.0f, TOL_M); /* vertex 2 = (100, 100) cm */
    assert_float_equal(a->uv_m[5], 1.0f, TOL_M);
    assert_float_equal(gar_edge_length(a, &a->edges[1]), 1.0f, TOL_M);
    assert_float_equal(a->translation_m[1], 0.5f, TOL_M);
    gar_pattern_free(&p);
    gar_pattern_free(&p); /* a freed pattern frees again harmlessly */
}

static void test_units_in_meter_300(void **state)
{
    (void)state;
    char js[1024];
    square_with("", "\"units_in_meter\": 300", js, sizeof js);
    gar_pattern p;
    assert_int_equal(parse(js, &p, NULL), 0);
    assert_float_equal(p.panels[0].uv_m[2], 100.0f / 300.0f, TOL_M);
    assert_float_equal(p.units_in_meter, 300.0f, 0);
    gar_pattern_free(&p);
}

/* P = S + cx (E - S) + cy perp(E - S): S = (0,0), E = (1,0) m, (0.5, 0.5) -> control (0.5, 0.5);
 * the quadratic's midpoint is S/4 + C/2 + E/4 = (0.5, 0.25). */
static void test_both_quadratic_encodings_agree(void **state)
{
    (void)state;
    const char *enc[2] = {"[0.5, 0.5]", "{\"type\": \"quadratic\", \"params\": [[0.5, 0.5]]}"};
    for (int k = 0; k < 2; k++) {
        char js[1024];
        square_with(enc[k], "", js, sizeof js);
        gar_pattern p;
        gar_reject why = {0};
        assert_int_equal(parse(js, &p, &why), 0);
        const gar_panel *a = &p.panels[0];
        assert_int_equal(a->edges[0].kind, GAR_QUADRATIC);
        assert_float_equal(a->edges[0].ctrl[0][0], 0.5f, TOL_M);
        assert_float_equal(a->edges[0].ctrl[0][1], 0.5f, TOL_M);
        float mid[2];
        gar_edge_eval(a, &a->edges[0], 0.5f, mid);
        assert_float_equal(mid[0], 0.5f, TOL_M);
        assert_float_equal(mid[1], 0.25f, TOL_M);
        gar_pattern_free(&p);
    }
}

/* Controls (0.25, 0.3) and (0.75, 0.3) m: B(1/2) = (S + 3 C1 + 3 C2 + E) / 8 = (0.5, 0.225). */
static void test_cubic_relative_controls(void **state)
{
    (void)state;
    char js[1024];
    square_with("{\"type\": \"cubic\", \"params\": [[0.25, 0.3], [0.75, 0.3]]}", "", js, sizeof js);
    gar_pattern p;
    assert_int_equal(parse(js, &p, NULL), 0);
    float mid[2];
    gar_edge_eval(&p.panels[0], &p.panels[0].edges[0], 0.5f, mid);
    assert_float_equal(mid[0], 0.5f, TOL_M);
    assert_float_equal(mid[1], 0.225f, TOL_M);
    gar_pattern_free(&p);
}

/* Bottom edge (0,0) -> (1,0) m as a semicircle of radius 0.5 bulging right (down, outside). */
static void test_circle_semicircle_right(void **state)
{
    (void)state;
    char js[1024];
    square_with("{\"type\": \"circle\", \"params\": [50, 0, 1]}", "", js, sizeof js);
    gar_pattern p;
    gar_reject why = {0};
    assert_int_equal(parse(js, &p, &why), 0);
    const gar_panel *a = &p.panels[0];
    float mid[2], q[2];
    gar_edge_eval(a, &a->edges[0], 0.5f, mid);
    assert_float_equal(mid[0], 0.5f, TOL_M);
    assert_float_equal(mid[1], -0.5f, TOL_M);
    gar_edge_eval(a, &a->edges[0], 0.25f, q); /* 45 degrees past the start, centre (0.5, 0) */
    assert_float_equal(hypotf(q[0] - 0.5f, q[1]), 0.5f, TOL_M);
    assert_float_equal(gar_edge_length(a, &a->edges[0]), (float)(PI * 0.5), 1e-4f);
    gar_pattern_free(&p);
}

/* Arcs built directly: chord (0,0)->(0.6,0), radius 0.5; small arc sagitta 0.5 - 0.4 = 0.1,
 * large arc 0.5 + 0.4 = 0.9; right = 1 bulges to -y, right = 0 to +y. */
static void test_circle_flags(void **state)
{
    (void)state;
    float uv[4] = {0, 0, 0.6f, 0};
    gar_panel pn = {.num_vertices = 2, .uv_m = uv};
    const float want[2][2] = {{0.1f, 0.9f}, {0.1f, 0.9f}};
    for (int right = 0; right < 2; right++)
        for (int large = 0; large < 2; large++) {
            gar_edge e = {.v0 = 0,
                          .v1 = 1,
                          .kind = GAR_CIRCLE,
                          .radius_m = 0.5f,
                          .large_arc = large,
                          .right = right};
            float mid[2];
            gar_edge_eval(&pn, &e, 0.5f, mid);
            assert_float_equal(mid[0], 0.3f, TOL_M);
            assert_float_equal(mid[1], (right ? -1 : 1) * want[right][large], TOL_M);
        }
    /* A radius below half the chord is raised to it: a semicircle. */
    gar_edge e = {.v0 = 0, .v1 = 1, .kind = GAR_CIRCLE, .radius_m = 0.1f, .right = 1};
    assert_float_equal(gar_edge_length(&pn, &e), (float)(PI * 0.3), 1e-4f);
}

/* world = Rz Ry Rx [u, v, 0] + t. Rx(90) takes +y to +z, Ry(90) takes +z to +x, Rz(90) takes
 * +y to -x; the two orders differ, so this pins R = Rz Ry Rx. */
static void test_rotation_euler_xyz_degrees(void **state)
{
    (void)state;
    float uv[2] = {0, 1}, out[3];
    gar_panel pn = {.rotation_deg = {90, 90, 0}, .translation_m = {1, 2, 3}};
    gar_panel_to_world(&pn, uv, out);
    assert_float_equal(out[0], 2.0f, TOL_M); /* (1, 0, 0) + t */
    assert_float_equal(out[1], 2.0f, TOL_M);
    assert_float_equal(out[2], 3.0f, TOL_M);
    gar_panel pz = {.rotation_deg = {0, 90, 90}};
    gar_panel_to_world(&pz, uv, out); /* Ry leaves +y, Rz(90) takes it to -x */
    assert_float_equal(out[0], -1.0f, TOL_M);
    assert_float_equal(out[1], 0.0f, TOL_M);
    assert_float_equal(out[2], 0.0f, TOL_M);
}

static void test_panel_order_and_stitches(void **state)
{
    (void)state;
    const char *js =
        "{\"pattern\": {\"panels\": {"
        "\"a\": {\"vertices\": [[0,0],[10,0],[0,10]], \"edges\": [{\"endpoints\": [0,1]},"
        "{\"endpoints\": [1,2]}, {\"endpoints\": [2,0]}]},"
        "\"b\": {\"vertices\": [[0,0],[10,0],[0,10]], \"edges\": [{\"endpoints\": [0,1]},"
        "{\"endpoints\": [1,2]}, {\"endpoints\": [2,0]}]}},"
        "\"stitches\": [[{\"panel\": \"a\", \"edge\": 2}, {\"panel\": \"b\", \"edge\": 0}]],"
        "\"panel_order\": [\"b\", \"a\"]}}";
    gar_pattern p;
    gar_reject why = {0};
    assert_int_equal(parse(js, &p, &why), 0);
    assert_string_equal(p.panels[0].name, "b");
    assert_int_equal(p.num_stitches, 1);
    assert_int_equal(p.stitches[0].panel[0], 1);
    assert_int_equal(p.stitches[0].edge[0], 2);
    assert_int_equal(p.stitches[0].panel[1], 0);
    assert_float_equal(p.units_in_meter, 100.0f, 0); /* the format's default */
    gar_pattern_free(&p);
}

typedef struct bad_case {
    const char *json;
    gar_error code;
    const char *where; /* must appear in the detail */
} bad_case;

#define TRI(EDGE0)                                                                                 \
    "\"a\": {\"vertices\": [[0,0],[10,0],[0,10]], \"edges\": [" EDGE0 ","                          \
    "{\"endpoints\": [1,2]}, {\"endpoints\": [2,0]}]}"
#define PAT(PANELS, REST) "{\"pattern\": {\"panels\": {" PANELS "}" REST "}}"

static const bad_case bad[] = {
    {"{\"pattern\": ", GAR_ERR_JSON, "byte"},
    {"{\"panels\": {}}", GAR_ERR_MISSING, "pattern"},
    {PAT("", ""), GAR_ERR_MISSING, "0 panels"},
    {PAT(TRI("{\"endpoints\": [0,7]}"), ""), GAR_ERR_RANGE, "panel 'a': edge 0"},
    {PAT(TRI("{\"endpoints\": [0]}"), ""), GAR_ERR_TYPE, "panel 'a': edge 0"},
    {PAT(TRI("{}"), ""), GAR_ERR_MISSING, "panel 'a': edge 0"},
    {PAT(TRI("{\"endpoints\": [0,1], \"curvature\": {\"type\": \"circle\", \"params\": [-2,0,1]}}"),
         ""),
     GAR_ERR_CURVE, "panel 'a': edge 0"},
    {PAT(TRI("{\"endpoints\": [0,1], \"curvature\": {\"type\": \"spline\", \"params\": []}}"), ""),
     GAR_ERR_CURVE, "spline"},
    {PAT(TRI("{\"endpoints\": [0,1], \"curvature\": {\"type\": \"quadratic\", \"params\": "
             "[[0.5,0.1],[0.5,0.2]]}}"),
         ""),
     GAR_ERR_CURVE, "panel 'a': edge 0"},
    {PAT(TRI("{\"endpoints\": [0,1], \"curvature\": [0.5]}"), ""), GAR_ERR_CURVE,
     "panel 'a': edge 0"},
    {PAT("\"a\": {\"vertices\": [[0,0],[10,0],[0,10]], \"edges\": [{\"endpoints\": [0,1]},"
         "{\"endpoints\": [2,0]}, {\"endpoints\": [1,2]}]}",
         ""),
     GAR_ERR_OUTLINE, "panel 'a': edge 0 ends"},
    {PAT("\"a\": {\"vertices\": [[0,0],[10,0],[20,0]], \"edges\": [{\"endpoints\": [0,1]},"
         "{\"endpoints\": [1,2]}, {\"endpoints\": [2,0]}]}",
         ""),
     GAR_ERR_OUTLINE, "no area"},
    {PAT("\"a\": {\"vertices\": [[0,0],[10,0],[0,10],[10,10]], \"edges\": [{\"endpoints\": "
         "[0,1]}, {\"endpoints\": [1,2]}, {\"endpoints\": [2,3]}, {\"endpoints\": [3,0]}]}",
         ""),
     GAR_ERR_OUTLINE, "panel 'a'"},
    {PAT("\"a\": {\"vertices\": [[0,0],[10,0],[0,\"x\"]], \"edges\": []}", ""), GAR_ERR_OUTLINE,
     "panel 'a'"},
    {PAT("\"a\": {\"vertices\": [[0,0],[10,0],[0,\"x\"]], \"edges\": [{\"endpoints\": [0,1]},"
         "{\"endpoints\": [1,2]}]}",
         ""),
     GAR_ERR_TYPE, "panel 'a': vertex 2"},
    {PAT(TRI("{\"endpoints\": [0,1]}"),
         ", \"stitches\": [[{\"panel\": \"zz\", \"edge\": 0}, {\"panel\": \"a\", \"edge\": 1}]]"),
     GAR_ERR_STITCH, "no panel 'zz'"},
    {PAT(TRI("{\"endpoints\": [0,1]}"),
         ", \"stitches\": [[{\"panel\": \"a\", \"edge\": 9}, {\"panel\": \"a\", \"edge\": 1}]]"),
     GAR_ERR_STITCH, "stitch 0 side 0: panel 'a' has no edge 9"},
    {PAT(TRI("{\"endpoints\": [0,1]}"), ", \"stitches\": [[{\"panel\": \"a\", \"edge\": 1}]]"),
     GAR_ERR_STITCH, "stitch 0"},
    {PAT(TRI("{\"endpoints\": [0,1]}"), ", \"panel_order\": [\"q\"]"), GAR_ERR_MISSING,
     "no panel 'q'"},
    {"{\"pattern\": {\"panels\": {" TRI("{\"endpoints\": [0,1]}") "}}, \"properties\": "
                                                                  "{\"units_in_meter\": 0}}",
     GAR_ERR_RANGE, "units_in_meter"},
    {PAT(TRI("{\"endpoints\": [0,1]}") ", \"b\": 5", ""), GAR_ERR_TYPE, "panel 'b'"},
    {PAT("\"a\": {\"vertices\": [[0,0],[1e9,0],[0,10]], \"edges\": [{\"endpoints\": [0,1]},"
         "{\"endpoints\": [1,2]}, {\"endpoints\": [2,0]}]}",
         ""),
     GAR_ERR_RANGE, "panel 'a': vertex 1 beyond"},
    {PAT(TRI("{\"endpoints\": [0,1], \"curvature\": [0.5, 1e30]}"), ""), GAR_ERR_CURVE,
     "panel 'a': edge 0"},
};

static void test_malformed_patterns_refused_by_name(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        gar_pattern p;
        gar_reject why = {0};
        int rc = parse(bad[i].json, &p, &why);
        if (rc != -(int)bad[i].code || !strstr(why.detail, bad[i].where))
            fail_msg("case %zu: got %s \"%s\", want %s with \"%s\"", i, gar_error_name(rc),
                     why.detail, gar_error_name(bad[i].code), bad[i].where);
        assert_int_equal(p.num_panels, 0); /* nothing half-built left behind */
        assert_null(p.panels);
    }
    gar_pattern p;
    gar_reject why = {0};
    assert_int_equal(gar_pattern_load("/nonexistent/x.json", &p, &why), -GAR_ERR_IO);
    assert_non_null(strstr(why.detail, "/nonexistent/x.json"));
}

/* Every prefix of a valid file is refused cleanly (no crash, no leak under ASan). */
static void test_truncated_files_refused(void **state)
{
    (void)state;
    char js[1024];
    square_with("{\"type\": \"circle\", \"params\": [50, 0, 1]}", "\"units_in_meter\": 100", js,
                sizeof js);
    size_t n = strlen(js);
    for (size_t k = 0; k + 1 < n; k++) {
        gar_pattern p;
        gar_reject why = {0};
        assert_true(gar_pattern_parse(js, k, &p, &why) < 0);
    }
}

/* R [u, v, 0] + t for Euler XYZ degrees (R = Rz Ry Rx), by hand. */
static void world_of(const double rot_deg[3], const double t[3], double u, double v, double out[3])
{
    double a = rot_deg[0] * PI / 180, b = rot_deg[1] * PI / 180, c = rot_deg[2] * PI / 180;
    double x[3] = {u, v * cos(a), v * sin(a)};                                           /* Rx */
    double y[3] = {cos(b) * x[0] + sin(b) * x[2], x[1], -sin(b) * x[0] + cos(b) * x[2]}; /* Ry */
    double z[3] = {cos(c) * y[0] - sin(c) * y[1], sin(c) * y[0] + cos(c) * y[1], y[2]};  /* Rz */
    for (int k = 0; k < 3; k++)
        out[k] = z[k] + t[k];
}

static void expect_world(const gar_panel *pn, const float uv[2], const double want[3])
{
    float w[3];
    gar_panel_to_world(pn, uv, w);
    for (int k = 0; k < 3; k++)
        assert_float_equal(w[k], (float)want[k], TOL_M);
}

/* A panel drawn clockwise (as the data sets draw their mirrored right and back panels) loads,
 * turned over: every vertex and every curve's midpoint where the file puts it in the world, the
 * edges in the file's order, its front normal on the side the file's winding gives. */
static void test_clockwise_panel_turned_over(void **state)
{
    (void)state;
    const char *js =
        "{\"pattern\": {\"panels\": {\"b\": {\"vertices\": [[0,0],[0,100],[100,100],[100,0]],"
        "\"edges\": [{\"endpoints\": [0,1], \"curvature\": {\"type\": \"cubic\", \"params\": "
        "[[0.3,0.1],[0.7,-0.1]]}}, {\"endpoints\": [1,2], \"curvature\": {\"type\": \"circle\", "
        "\"params\": [80,0,1]}}, {\"endpoints\": [2,3]}, {\"endpoints\": [3,0], \"curvature\": "
        "[0.5,0.2]}], \"translation\": [1,2,3], \"rotation\": [10,20,30]}}}}";
    const double rot[3] = {10, 20, 30}, t[3] = {0.01, 0.02, 0.03};
    const double file_uv[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    gar_pattern p;
    gar_reject why = {0};
    if (parse(js, &p, &why))
        fail_msg("%s", why.detail);
    const gar_panel *b = &p.panels[0];
    for (int i = 0; i < 4; i++) {
        double want[3];
        world_of(rot, t, file_uv[i][0], file_uv[i][1], want);
        expect_world(b, b->uv_m + 2 * i, want);
        assert_int_equal(b->edges[i].v0, i);
        assert_int_equal(b->edges[i].v1, (i + 1) % 4);
    }
    /* edge 0, cubic: S (0,0), E (0,1), controls S + c (E - S) + d perp(E - S), perp = (-y, x) */
    double p1[2] = {-0.1, 0.3}, p2[2] = {0.1, 0.7}, mid[3];
    world_of(rot, t, (3 * p1[0] + 3 * p2[0]) / 8, (1 + 3 * p1[1] + 3 * p2[1]) / 8, mid);
    float uv[2];
    gar_edge_eval(b, &b->edges[0], 0.5f, uv);
    expect_world(b, uv, mid);
    /* edge 1, the small arc of radius 0.8 from (0,1) to (1,1), turning left (right = 1): its
       centre left of the chord, its midpoint 0.8 - sqrt(0.8^2 - 0.5^2) short of it, inside */
    world_of(rot, t, 0.5, 1.0 - (0.8 - sqrt(0.64 - 0.25)), mid);
    gar_edge_eval(b, &b->edges[1], 0.5f, uv);
    expect_world(b, uv, mid);
    /* edge 3, quadratic: S (1,0), E (0,0), control (0.5, -0.2) */
    world_of(rot, t, 0.5, -0.1, mid);
    gar_edge_eval(b, &b->edges[3], 0.5f, uv);
    expect_world(b, uv, mid);
    /* the front normal (the counter-clockwise side, now +w) is the file's -R z */
    float o[3], x[3], y[3];
    gar_panel_to_world(b, (const float[2]){0, 0}, o);
    gar_panel_to_world(b, (const float[2]){1, 0}, x);
    gar_panel_to_world(b, (const float[2]){0, 1}, y);
    double ex[3] = {x[0] - o[0], x[1] - o[1], x[2] - o[2]},
           ey[3] = {y[0] - o[0], y[1] - o[1], y[2] - o[2]};
    double n[3] = {ex[1] * ey[2] - ex[2] * ey[1], ex[2] * ey[0] - ex[0] * ey[2],
                   ex[0] * ey[1] - ex[1] * ey[0]};
    double rz[3] = {cos(30 * PI / 180) * sin(20 * PI / 180) * cos(10 * PI / 180) +
                        sin(30 * PI / 180) * sin(10 * PI / 180),
                    sin(30 * PI / 180) * sin(20 * PI / 180) * cos(10 * PI / 180) -
                        cos(30 * PI / 180) * sin(10 * PI / 180),
                    cos(20 * PI / 180) * cos(10 * PI / 180)}; /* R z */
    for (int k = 0; k < 3; k++)
        assert_float_equal((float)n[k], (float)-rz[k], TOL_M);
    gar_pattern_free(&p);
}

/* Files of a public data set (tests/garments/data/NOTICE), as they are: every panel loads, its
 * right and back panels turned over, every point where the file puts it. */
static void test_data_set_files_load(void **state)
{
    (void)state;
    const struct {
        const char *file;
        int panels, stitches;
    } files[] = {{"garmentcode_shirt_mean.json", 8, 18}, {"garmentcode_dress_pencil.json", 6, 23}};
    for (int f = 0; f < 2; f++) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s", GAR_TEST_DATA_DIR, files[f].file);
        gar_pattern p;
        gar_reject why = {0};
        if (gar_pattern_load(path, &p, &why))
            fail_msg("%s: %s", path, why.detail);
        assert_int_equal(p.num_panels, files[f].panels);
        assert_int_equal(p.num_stitches, files[f].stitches);
        if (f == 0) { /* left_btorso, drawn clockwise: vertex 2 (12.8474, 45.89674...) cm */
            int k = gar_pattern_find_panel(&p, "left_btorso");
            assert_true(k >= 0);
            const double rot[3] = {0, 0, 0}, t[3] = {0, 0.9466024668570651, -0.2};
            double want[3];
            world_of(rot, t, 0.128474, 0.4589674322821761, want);
            expect_world(&p.panels[k], p.panels[k].uv_m + 4, want);
        }
        gar_pattern_free(&p);
    }
}

static const char *const shipped[] = {"tshirt", "jeans", "skirt", "dress"};

static void test_shipped_patterns_load_and_grade(void **state)
{
    (void)state;
    for (int g = 0; g < 4; g++) {
        char path[512];
        snprintf(path, sizeof path, "%s/%s.json", GAR_PATTERN_DIR, shipped[g]);
        float hem[3];
        for (int s = GAR_SIZE_S; s <= GAR_SIZE_L; s++) {
            gar_pattern p;
            gar_reject why = {0};
            if (gar_pattern_load(path, &p, &why))
                fail_msg("%s: %s", path, why.detail);
            assert_true(p.num_panels >= 2 && p.num_stitches >= 2);
            gar_pattern_grade(&p, (gar_size)s);
            hem[s] = gar_edge_length(&p.panels[0], &p.panels[0].edges[0]);
            gar_pattern_free(&p);
        }
        /* One grade step scales girth by 4 %. */
        assert_true(hem[0] < hem[1] && hem[1] < hem[2]);
        assert_float_equal(hem[2] / hem[1], 1.04f, 0.01f);
    }
    assert_int_equal(gar_size_from_name("m"), GAR_SIZE_M);
    assert_int_equal(gar_size_from_name("XL"), -1);
}

static void test_fabric_presets(void **state)
{
    (void)state;
    const char *need[] = {"cotton", "denim", "jersey", "silk"};
    for (int i = 0; i < 4; i++) {
        const gar_fabric *f = gar_fabric_find(need[i]);
        assert_non_null(f);
        assert_true(f->density_kg_m2 > 0 && f->stretch_n_m > f->shear_n_m && f->bend_n_m > 0);
        assert_true(f->friction > 0 && f->friction < 1 && f->max_strain > 0);
    }
    assert_null(gar_fabric_find("tweed"));
    assert_true(gar_fabric_find("denim")->density_kg_m2 > gar_fabric_find("silk")->density_kg_m2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_square_outline_in_metres),
        cmocka_unit_test(test_units_in_meter_300),
        cmocka_unit_test(test_both_quadratic_encodings_agree),
        cmocka_unit_test(test_cubic_relative_controls),
        cmocka_unit_test(test_circle_semicircle_right),
        cmocka_unit_test(test_circle_flags),
        cmocka_unit_test(test_rotation_euler_xyz_degrees),
        cmocka_unit_test(test_panel_order_and_stitches),
        cmocka_unit_test(test_malformed_patterns_refused_by_name),
        cmocka_unit_test(test_truncated_files_refused),
        cmocka_unit_test(test_shipped_patterns_load_and_grade),
        cmocka_unit_test(test_clockwise_panel_turned_over),
        cmocka_unit_test(test_data_set_files_load),
        cmocka_unit_test(test_fabric_presets),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
