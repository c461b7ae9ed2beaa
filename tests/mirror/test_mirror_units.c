/* The mirror's pieces without a GPU: the depth ring matches CLOTH to its DEPTH frame, the fit
 * map's strain and colours, the projection that puts world points on the mirrored picture, the
 * occlusion margin, and the bitmap font. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cloth_queue.h"
#include "mirror.h"
#include "render_private.h"

static const float identity_c2w[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

static mirror_depth frame(int64_t utime, uint16_t *px)
{
    mirror_depth d = {64, 48, 50.0f, 50.0f, 31.5f, 23.5f, 0.001f, {0}, px, utime, NULL};
    memcpy(d.camera_to_world, identity_c2w, sizeof identity_c2w);
    return d;
}

static void test_ring_matches_cloth_to_its_depth_frame(void **state)
{
    (void)state;
    mirror_ring *r = mirror_ring_create();
    uint16_t px[64 * 48];
    for (int64_t t = 1; t <= 12; t++) {
        px[0] = (uint16_t)t; /* each frame's first pixel names it */
        mirror_depth d = frame(t * 1000, px);
        assert_int_equal(mirror_ring_push(r, &d), 0);
    }
    int exact;
    const mirror_depth *d = mirror_ring_find(r, 9000, &exact);
    assert_non_null(d);
    assert_true(exact);
    assert_int_equal(d->data[0], 9); /* its own copy, not the caller's buffer */
    d = mirror_ring_find(r, 9500, &exact);
    assert_false(exact);
    assert_int_equal(d->utime_capture, 9000);       /* the newest older one */
    assert_null(mirror_ring_find(r, 2000, &exact)); /* fell out of the ring of 8 */
    assert_int_equal(mirror_ring_newest(r)->utime_capture, 12000);
    mirror_ring_destroy(r);
}

/* The ring makes each frame's person image on arrival (off the path from CLOTH to screen): the
 * very image the renderer would make from that frame, kept per slot. */
static void test_ring_makes_each_frames_person_image(void **state)
{
    (void)state;
    mirror_ring *r = mirror_ring_create();
    assert_non_null(r);
    uint16_t px[2][64 * 48];
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 64 * 48; i++) /* a slope 1.5-2.1 m, the second frame 10 cm farther */
            px[k][i] = (uint16_t)(1500 + 100 * k + (i % 64) * 8 + (i / 64) * 3);
    mirror_depth in[2] = {frame(1000, px[0]), frame(2000, px[1])};
    for (int k = 0; k < 2; k++)
        assert_int_equal(mirror_ring_push(r, &in[k]), 0);
    for (int k = 0; k < 2; k++) {
        int exact;
        const mirror_depth *d = mirror_ring_find(r, in[k].utime_capture, &exact);
        assert_non_null(d);
        assert_non_null(d->person);
        float *want = NULL;
        int cap = 0;
        assert_int_equal(mirror_person_image(&in[k], &want, &cap), 0);
        assert_memory_equal(d->person, want, 64 * 48 * 2 * sizeof(float));
        assert_true(d->person[0] > 1.5f); /* the first pixel's depth, pushed back by the margin */
        free(want);
    }
    mirror_ring_destroy(r);
}

/* The warm-up fills every slot and then forgets the frames: nothing is found afterwards, and the
 * next frames land in the buffers it allocated (a slot's first frame touches fresh pages). */
static void test_ring_forgets_frames_and_keeps_buffers(void **state)
{
    (void)state;
    mirror_ring *r = mirror_ring_create();
    assert_non_null(r);
    uint16_t px[64 * 48] = {0};
    const uint16_t *kept[MIRROR_RING];
    for (int k = 0; k < MIRROR_RING; k++) {
        mirror_depth d = frame(1000 * (k + 1), px);
        assert_int_equal(mirror_ring_push(r, &d), 0);
        kept[k] = mirror_ring_newest(r)->data;
    }
    mirror_ring_forget(r);
    int exact;
    assert_null(mirror_ring_newest(r));
    assert_null(mirror_ring_find(r, 1000 * MIRROR_RING, &exact));
    assert_null(mirror_ring_find(r, INT64_MAX, &exact)); /* not even an older one */
    for (int k = 0; k < MIRROR_RING; k++) {
        px[0] = (uint16_t)(k + 100);
        mirror_depth d = frame(50000 + k, px);
        assert_int_equal(mirror_ring_push(r, &d), 0);
        const mirror_depth *n = mirror_ring_newest(r);
        assert_ptr_equal(n->data, kept[k]);
        assert_int_equal(n->data[0], k + 100);
        assert_non_null(n->person);
    }
    assert_int_equal(mirror_ring_find(r, 50000, &exact)->data[0], 100);
    assert_true(exact);
    mirror_ring_destroy(r);
}

static void test_strain_is_measured_from_the_first_frame(void **state)
{
    (void)state;
    float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    int32_t tri[3] = {0, 1, 2};
    mirror_strain *s = mirror_strain_create();
    const float *e = mirror_strain_update(s, xyz, 3, tri, 1);
    assert_float_equal(e[0], 0.0f, 1e-6f);
    xyz[3] = 1.02f; /* edge 0-1 stretched 2 %, edge 1-2 a little */
    e = mirror_strain_update(s, xyz, 3, tri, 1);
    assert_float_equal(e[0], 0.02f, 1e-5f);
    assert_true(e[1] >= 0.02f - 1e-5f);
    assert_true(e[2] > 0.0f && e[2] < 0.02f);
    mirror_strain_reset(s); /* a new garment: this shape is its rest */
    e = mirror_strain_update(s, xyz, 3, tri, 1);
    assert_float_equal(e[1], 0.0f, 1e-6f);
    mirror_strain_destroy(s);
}

static void test_fit_map_colours(void **state)
{
    (void)state;
    float c[3];
    mirror_fit_colour(0.0f, c);
    assert_true(c[1] > 0.8f && c[0] < 0.01f); /* green */
    mirror_fit_colour(0.5f * MIRROR_FIT_MAP_LIMIT, c);
    assert_true(c[0] > 0.99f && c[1] > 0.8f); /* yellow */
    mirror_fit_colour(2.0f * MIRROR_FIT_MAP_LIMIT, c);
    assert_true(c[0] > 0.99f && c[1] < 0.01f); /* red, and no further */
}

/* Row-major 4x4 times (x, y, z, 1), then the perspective divide and the viewport. */
static void to_pixel(const float m[16], const float p[3], int w, int h, float *px, float *py)
{
    float c[4];
    for (int r = 0; r < 4; r++)
        c[r] = m[r * 4] * p[0] + m[r * 4 + 1] * p[1] + m[r * 4 + 2] * p[2] + m[r * 4 + 3];
    *px = (c[0] / c[3] * 0.5f + 0.5f) * (float)w;
    *py = (0.5f - c[1] / c[3] * 0.5f) * (float)h; /* rows from the top */
}

static void test_world_points_land_on_the_mirrored_pixel(void **state)
{
    (void)state;
    uint16_t px[64 * 48] = {0};
    mirror_depth d = frame(0, px);
    /* camera 1 m up looking along world -z: camera (x, y, z) = world (x, 1 - y, -z) */
    const float c2w[16] = {1, 0, 0, 0, 0, -1, 0, 1, 0, 0, -1, 0, 0, 0, 0, 1};
    memcpy(d.camera_to_world, c2w, sizeof c2w);
    float proj[16], w2c[16], m[16], x, y;
    mirror_projection(&d, 128, 96, proj); /* twice the depth image: scale 2, no margin */
    mirror_world_to_camera(d.camera_to_world, w2c);
    mirror_mat_mul(proj, w2c, m);
    /* camera point (0.4, -0.2, 2): depth pixel u = 50 * 0.2 + 31.5 = 41.5, v = -5 + 23.5 = 18.5;
     * mirrored: picture x = 128 - 2 (u + 0.5) = 44, y = 2 (v + 0.5) = 38 */
    const float world[3] = {0.4f, 1.2f, -2.0f};
    to_pixel(m, world, 128, 96, &x, &y);
    assert_float_equal(x, 44.0f, 1e-3f);
    assert_float_equal(y, 38.0f, 1e-3f);
    float s, offx;
    mirror_picture_fit(&d, 160, 96, &s, &offx); /* wider picture: centred */
    assert_float_equal(s, 2.0f, 1e-6f);
    assert_float_equal(offx, 16.0f, 1e-6f);
}

static void test_occlusion_margin_follows_kinect_noise(void **state)
{
    (void)state;
    /* 17 mm at 1.5 m, 47 mm at 2.5 m (docs/mirror.md), growing with depth */
    assert_float_equal(mirror_occlusion_margin_m(1.5f), 0.0170f, 0.0005f);
    assert_float_equal(mirror_occlusion_margin_m(2.5f), 0.0470f, 0.0005f);
    assert_true(mirror_occlusion_margin_m(4.0f) > mirror_occlusion_margin_m(2.5f));
}

static void test_text_advances_and_clips(void **state)
{
    (void)state;
    uint8_t img[40 * 12 * 4] = {0};
    const uint8_t white[4] = {255, 255, 255, 255};
    assert_int_equal(mirror_text(img, 40, 12, 0, 0, 1, "AB", white), 2 * MIRROR_FONT_W);
    int lit = 0;
    for (int i = 0; i < 40 * 12; i++)
        lit += img[i * 4] == 255;
    assert_true(lit > 10);
    /* far outside the image: nothing written, no crash (ASan watches) */
    assert_int_equal(mirror_text(img, 40, 12, 1000, -50, 3, "xyz~", white), 4 * 3 * MIRROR_FONT_W);
}

/* Failures are named codes from one list (docs/building.md, "Conventions: errors"). */
/* A CLOTH of a quad (topology t, x offset by seq so that each frame's vertices are its own);
 * triangles when with_tris. */
static tryon_cloth_t quad_cloth(int32_t seq, int32_t topology, int with_tris, float *v, int32_t *t)
{
    static const float base[12] = {0, 0, 2, 1, 0, 2, 0, 1, 2, 1, 1, 2};
    static const int32_t tris[6] = {0, 1, 2, 1, 3, 2};
    memcpy(v, base, sizeof base);
    v[0] = (float)seq;
    memcpy(t, tris, sizeof tris);
    return (tryon_cloth_t){.utime_capture = 1000 * seq,
                           .seq = seq,
                           .garment_id = "quad",
                           .topology_id = topology,
                           .num_vertex_coords = 12,
                           .vertices = v,
                           .num_triangle_indices = with_tris ? 6 : 0,
                           .triangles = with_tris ? t : NULL};
}

static void test_cloth_queue_keeps_the_newest_two_in_order(void **state)
{
    (void)state;
    mirror_cloth_queue q;
    mirror_held drawn = {0};
    float v[12];
    int32_t t[6];
    mirror_cloth_queue_init(&q, 2);
    tryon_cloth_t c = quad_cloth(0, 7, 0, v, t);
    assert_int_equal(mirror_cloth_queue_push(&q, &c, 0), -1); /* no triangles for topology 7 */
    assert_int_equal(q.skipped, 1);
    for (int32_t seq = 1; seq <= 3; seq++) { /* a burst: 1 (with triangles), 2, 3 */
        c = quad_cloth(seq, 7, seq == 1, v, t);
        assert_int_equal(mirror_cloth_queue_push(&q, &c, 100 + seq), 0);
    }
    assert_int_equal(mirror_cloth_queue_count(&q), 2);
    assert_int_equal(q.superseded, 1); /* 1 gave way to 3 */
    for (int32_t seq = 2; seq <= 3; seq++) {
        assert_int_equal(mirror_cloth_queue_take(&q, &drawn), 1);
        assert_int_equal(drawn.seq, seq);
        assert_int_equal(drawn.utime_capture, 1000 * seq);
        assert_int_equal(drawn.received_us, 100 + seq);
        assert_true(drawn.xyz[0] == (float)seq && drawn.nv == 4 && drawn.nt == 2);
        assert_int_equal(drawn.tris[5], 2);
    }
    assert_int_equal(mirror_cloth_queue_take(&q, &drawn), 0);
    assert_int_equal(drawn.seq, 3); /* the last drawn stays */
    /* depth 1 (--queue latest): the newest alone */
    mirror_cloth_queue_free(&q);
    mirror_cloth_queue_init(&q, 1);
    for (int32_t seq = 1; seq <= 3; seq++) {
        c = quad_cloth(seq, 7, 1, v, t);
        assert_int_equal(mirror_cloth_queue_push(&q, &c, 0), 0);
    }
    assert_int_equal(q.superseded, 2);
    assert_int_equal(mirror_cloth_queue_take(&q, &drawn), 1);
    assert_int_equal(drawn.seq, 3);
    mirror_cloth_queue_free(&q);
    mirror_held_free(&drawn);
}

static void test_cloth_queue_passes_over_a_replaced_garment(void **state)
{
    (void)state;
    mirror_cloth_queue q;
    mirror_held drawn = {0};
    float v[12];
    int32_t t[6];
    mirror_cloth_queue_init(&q, 2);
    tryon_cloth_t c = quad_cloth(1, 7, 1, v, t);
    assert_int_equal(mirror_cloth_queue_push(&q, &c, 0), 0);
    c = quad_cloth(2, 8, 1, v, t); /* another garment: its own topology and triangles */
    assert_int_equal(mirror_cloth_queue_push(&q, &c, 0), 0);
    assert_int_equal(mirror_cloth_queue_take(&q, &drawn), 1);
    assert_int_equal(drawn.seq, 2); /* 1's triangles are gone: passed over */
    assert_int_equal(drawn.topology, 8);
    assert_int_equal(q.superseded, 1);
    /* triangles that index past a CLOTH's vertices: skipped, nothing waiting replaced */
    c = quad_cloth(3, 8, 0, v, t);
    c.num_vertex_coords = 9;
    assert_int_equal(mirror_cloth_queue_push(&q, &c, 0), -1);
    c = quad_cloth(4, 9, 1, v, t);
    t[0] = 4;
    assert_int_equal(mirror_cloth_queue_push(&q, &c, 0), -1);
    assert_int_equal(q.skipped, 2);
    assert_int_equal(mirror_cloth_queue_count(&q), 0);
    mirror_cloth_queue_free(&q);
    mirror_held_free(&drawn);
}

static void test_failures_are_named(void **state)
{
    (void)state;
    const float xyz[9] = {0, 0, 1, 0.1f, 0, 1, 0, 0.1f, 1};
    const int32_t tris[3] = {0, 1, 3}; /* vertex 3 of 3 */
    const mirror_mesh m = {.xyz = xyz, .nv = 3, .tris = tris, .nt = 1};
    const float rgba[4] = {1, 1, 1, 1};
    mirror_cpu_mesh out = {0};
    assert_int_equal(mirror_world_mesh(&m, rgba, 0, &out), -MIRROR_ERR_MESH);
    mirror_cpu_mesh_free(&out);
    const uint8_t rgb[3] = {0};
    char err[256] = "";
    int rc = mirror_png_write("/nonexistent-dir/x.png", rgb, 1, 1, err, sizeof err);
    assert_int_equal(rc, -MIRROR_ERR_IO);
    assert_string_equal(mirror_error_name(rc), "MIRROR_ERR_IO");
    assert_string_equal(mirror_error_text(MIRROR_ERR_IO), "file cannot be written");
    assert_non_null(strstr(err, "/nonexistent-dir/x.png"));
    assert_string_equal(mirror_error_name(MIRROR_ERROR_COUNT), "MIRROR_ERR_UNKNOWN");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ring_matches_cloth_to_its_depth_frame),
        cmocka_unit_test(test_ring_makes_each_frames_person_image),
        cmocka_unit_test(test_ring_forgets_frames_and_keeps_buffers),
        cmocka_unit_test(test_strain_is_measured_from_the_first_frame),
        cmocka_unit_test(test_fit_map_colours),
        cmocka_unit_test(test_world_points_land_on_the_mirrored_pixel),
        cmocka_unit_test(test_occlusion_margin_follows_kinect_noise),
        cmocka_unit_test(test_text_advances_and_clips),
        cmocka_unit_test(test_failures_are_named),
        cmocka_unit_test(test_cloth_queue_keeps_the_newest_two_in_order),
        cmocka_unit_test(test_cloth_queue_passes_over_a_replaced_garment),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
