/* Malformed input is rejected with a named reason, counted, and never reaches a handler; the
 * subscriber keeps serving the good messages around it. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bus.h"
#include "fixtures.h"

#define BODY_NV 40
#define BODY_NT 30

/* Byte offset of num_vertex_coords in an encoded fx_body (see bus/body_t.lcm field order). */
static size_t body_num_vertices_offset(const tryon_body_t *m)
{
    return 8 + 8 + 4 + 1 + 4 + 4 + 4 * (size_t)m->num_shape + 4 + 4 * (size_t)m->num_pose + 4 +
           4 * (size_t)m->num_joint_coords + 4;
}

static void put_i32(uint8_t *p, int32_t v)
{
    uint32_t u = (uint32_t)v;
    p[0] = (uint8_t)(u >> 24);
    p[1] = (uint8_t)(u >> 16);
    p[2] = (uint8_t)(u >> 8);
    p[3] = (uint8_t)u;
}

static int decode_body(const uint8_t *buf, size_t len, bus_reject *why)
{
    tryon_body_t out;
    int e = bus_decode(BUS_BODY, buf, len, &out, why);
    if (e == BUS_OK)
        bus_msg_free(BUS_BODY, &out);
    return e;
}

static void test_valid_messages_of_every_type_decode(void **state)
{
    (void)state;
    fx_depth d;
    fx_body b;
    fx_cloth c;
    fx_timing t;
    fx_control k;
    fx_depth_make(&d, 64, 48, 1);
    fx_body_make(&b, BODY_NV, BODY_NT, 1);
    fx_cloth_make(&c, 20, 10, 1);
    fx_timing_make(&t, 1);
    fx_control_make(&k, 1);
    const void *msgs[BUS_TYPE_COUNT] = {&d.msg, &b.msg, &c.msg, &t.msg, &k.msg};
    for (int ty = 0; ty < BUS_TYPE_COUNT; ty++) {
        uint8_t *buf;
        int n = fx_encode((bus_type)ty, msgs[ty], &buf);
        assert_true(n > 0);
        union {
            tryon_depth_frame_t d;
            tryon_body_t b;
            tryon_cloth_t c;
            tryon_timing_t t;
            tryon_control_t k;
        } out;
        bus_reject why;
        assert_int_equal(bus_decode((bus_type)ty, buf, (size_t)n, &out, &why), BUS_OK);
        assert_true(fx_equal((bus_type)ty, msgs[ty], &out));
        bus_msg_free((bus_type)ty, &out);
        free(buf);
    }
    fx_depth_free(&d);
    fx_body_free(&b);
    fx_cloth_free(&c);
}

static void test_every_truncation_is_rejected(void **state)
{
    (void)state;
    fx_timing t;
    fx_timing_make(&t, 2);
    fx_body b;
    fx_body_make(&b, BODY_NV, BODY_NT, 2);
    const void *msgs[2] = {&b.msg, &t.msg};
    const bus_type types[2] = {BUS_BODY, BUS_TIMING};
    for (int k = 0; k < 2; k++) {
        uint8_t *buf;
        int n = fx_encode(types[k], msgs[k], &buf);
        for (int len = 0; len < n; len++) {
            /* A copy of exactly len bytes, so ASan sees any read past the end. */
            uint8_t *cut = malloc((size_t)(len ? len : 1));
            memcpy(cut, buf, (size_t)len);
            bus_reject why;
            union {
                tryon_body_t b;
                tryon_timing_t t;
            } out;
            assert_int_equal(bus_decode(types[k], cut, (size_t)len, &out, &why),
                             -BUS_ERR_TRUNCATED);
            free(cut);
        }
        free(buf);
    }
    fx_body_free(&b);
}

static void test_absurd_counts_are_rejected_before_allocation(void **state)
{
    (void)state;
    fx_body b;
    fx_body_make(&b, BODY_NV, BODY_NT, 3);
    uint8_t *buf;
    int n = fx_encode(BUS_BODY, &b.msg, &buf);
    size_t at = body_num_vertices_offset(&b.msg);
    bus_reject why;

    put_i32(buf + at, -3);
    assert_int_equal(decode_body(buf, (size_t)n, &why), -BUS_ERR_COUNT);
    assert_non_null(strstr(why.detail, "num_vertex_coords"));

    put_i32(buf + at, INT32_MAX); /* 24 GiB if lcm's decoder were trusted with it */
    assert_int_equal(decode_body(buf, (size_t)n, &why), -BUS_ERR_COUNT);

    put_i32(buf + at, 3 * BUS_MAX_VERTICES); /* sane count, but the bytes are not there */
    assert_int_equal(decode_body(buf, (size_t)n, &why), -BUS_ERR_TRUNCATED);

    b.msg.num_vertex_coords = 3 * BODY_NV - 1; /* not whole vertices */
    assert_int_equal(bus_validate(BUS_BODY, &b.msg, &why), -BUS_ERR_COUNT);
    b.msg.num_vertex_coords = 3 * BODY_NV;

    put_i32(buf + at, 3 * BODY_NV);
    assert_int_equal(decode_body(buf, (size_t)n, &why), BUS_OK);
    free(buf);
    fx_body_free(&b);
}

static void test_nan_coordinate_is_rejected_with_its_place(void **state)
{
    (void)state;
    fx_body b;
    fx_body_make(&b, BODY_NV, BODY_NT, 4);
    b.verts[5][1] = NAN;
    uint8_t *buf;
    int n = fx_encode(BUS_BODY, &b.msg, &buf);
    bus_reject why;
    assert_int_equal(decode_body(buf, (size_t)n, &why), -BUS_ERR_NOT_FINITE);
    assert_non_null(strstr(why.detail, "vertices[5][1]"));
    free(buf);
    b.verts[5][1] = INFINITY;
    assert_int_equal(bus_validate(BUS_BODY, &b.msg, &why), -BUS_ERR_NOT_FINITE);
    b.verts[5][1] = 5000.0f; /* 5 km: finite but absurd */
    assert_int_equal(bus_validate(BUS_BODY, &b.msg, &why), -BUS_ERR_RANGE);
    fx_body_free(&b);
}

static void test_out_of_range_triangle_index_is_rejected(void **state)
{
    (void)state;
    fx_cloth c;
    fx_cloth_make(&c, 20, 10, 5);
    bus_reject why;
    c.tris[3][2] = 20;
    assert_int_equal(bus_validate(BUS_CLOTH, &c.msg, &why), -BUS_ERR_INDEX);
    assert_non_null(strstr(why.detail, "triangles[3][2] = 20"));
    c.tris[3][2] = -1;
    assert_int_equal(bus_validate(BUS_CLOTH, &c.msg, &why), -BUS_ERR_INDEX);
    c.tris[3][2] = 19;
    assert_int_equal(bus_validate(BUS_CLOTH, &c.msg, &why), BUS_OK);
    fx_cloth_free(&c);
}

/* Every state cloth_t names is sent and taken (a carried frame once went unsent: the sim's
 * CARRIED was out of the checked range); one past them is refused. */
static void test_every_cloth_state_is_accepted(void **state)
{
    (void)state;
    fx_cloth c;
    fx_cloth_make(&c, 20, 10, 6);
    bus_reject why;
    const int8_t states[] = {TRYON_CLOTH_T_STATE_OK, TRYON_CLOTH_T_STATE_RECOVERED,
                             TRYON_CLOTH_T_STATE_DIVERGED, TRYON_CLOTH_T_STATE_SETTLING,
                             TRYON_CLOTH_T_STATE_CARRIED};
    for (size_t i = 0; i < sizeof states; i++) {
        c.msg.state = states[i];
        assert_int_equal(bus_validate(BUS_CLOTH, &c.msg, &why), BUS_OK);
    }
    c.msg.state = TRYON_CLOTH_T_STATE_CARRIED + 1;
    assert_int_equal(bus_validate(BUS_CLOTH, &c.msg, &why), -BUS_ERR_RANGE);
    assert_non_null(strstr(why.detail, "state 5"));
    c.msg.state = -1;
    assert_int_equal(bus_validate(BUS_CLOTH, &c.msg, &why), -BUS_ERR_RANGE);
    fx_cloth_free(&c);
}

static void test_wrong_type_and_trailing_bytes_are_rejected(void **state)
{
    (void)state;
    fx_cloth c;
    fx_cloth_make(&c, 20, 10, 6);
    uint8_t *buf;
    int n = fx_encode(BUS_CLOTH, &c.msg, &buf);
    bus_reject why;
    assert_int_equal(decode_body(buf, (size_t)n, &why), -BUS_ERR_FINGERPRINT);
    uint8_t *longer = calloc((size_t)n + 3, 1);
    memcpy(longer, buf, (size_t)n);
    tryon_cloth_t out;
    assert_int_equal(bus_decode(BUS_CLOTH, longer, (size_t)n + 3, &out, &why), -BUS_ERR_TRAILING);
    free(longer);
    free(buf);
    fx_cloth_free(&c);
}

static void test_depth_frame_checks(void **state)
{
    (void)state;
    fx_depth d;
    fx_depth_make(&d, 64, 48, 7);
    bus_reject why;
    d.msg.width = 0;
    assert_int_equal(bus_validate(BUS_DEPTH_FRAME, &d.msg, &why), -BUS_ERR_DIMENSIONS);
    d.msg.width = 64;
    d.msg.num_bytes -= 2;
    assert_int_equal(bus_validate(BUS_DEPTH_FRAME, &d.msg, &why), -BUS_ERR_DATA_SIZE);
    d.msg.num_bytes += 2;
    d.msg.encoding = 9;
    assert_int_equal(bus_validate(BUS_DEPTH_FRAME, &d.msg, &why), -BUS_ERR_ENCODING);
    d.msg.encoding = TRYON_DEPTH_FRAME_T_ENCODING_U16;
    d.msg.fx = -1;
    assert_int_equal(bus_validate(BUS_DEPTH_FRAME, &d.msg, &why), -BUS_ERR_RANGE);
    d.msg.fx = NAN;
    assert_int_equal(bus_validate(BUS_DEPTH_FRAME, &d.msg, &why), -BUS_ERR_NOT_FINITE);
    d.msg.fx = 580;
    assert_int_equal(bus_validate(BUS_DEPTH_FRAME, &d.msg, &why), BUS_OK);
    fx_depth_free(&d);
}

static void test_timing_checks(void **state)
{
    (void)state;
    fx_timing t;
    fx_timing_make(&t, 8);
    bus_reject why;
    t.msg.utime_finished = t.msg.utime_started - 1;
    assert_int_equal(bus_validate(BUS_TIMING, &t.msg, &why), -BUS_ERR_RANGE);
    t.msg.utime_finished = t.msg.utime_started;
    t.ms[1] = NAN;
    assert_int_equal(bus_validate(BUS_TIMING, &t.msg, &why), -BUS_ERR_NOT_FINITE);
    t.ms[1] = 1;
    t.msg.stage = "";
    assert_int_equal(bus_validate(BUS_TIMING, &t.msg, &why), -BUS_ERR_STRING);
}

static void count_good(const char *channel, const void *msg, void *user)
{
    (void)channel;
    const tryon_body_t *b = msg;
    int *seen = user;
    /* A handler only ever sees validated bodies. */
    for (int i = 0; i < b->num_vertex_coords; i++)
        assert_true(isfinite(b->vertices[i]));
    (*seen)++;
}

static void test_subscriber_counts_rejections_and_keeps_serving(void **state)
{
    (void)state;
    char err[256];
    lcm_t *lcm = bus_open("memq://", err, sizeof err);
    int seen = 0;
    bus_sub *sub = bus_subscribe(lcm, "B", BUS_BODY, count_good, &seen);
    bus_sub_quiet(sub, 1);

    fx_body good, nan_body, bad_index;
    fx_body_make(&good, BODY_NV, BODY_NT, 9);
    fx_body_make(&nan_body, BODY_NV, BODY_NT, 9);
    fx_body_make(&bad_index, BODY_NV, BODY_NT, 9);
    nan_body.verts[0][0] = NAN;
    bad_index.tris[0][0] = BODY_NV + 5;
    uint8_t *g, *nb, *bi;
    int gn = fx_encode(BUS_BODY, &good.msg, &g);
    int nbn = fx_encode(BUS_BODY, &nan_body.msg, &nb);
    int bin = fx_encode(BUS_BODY, &bad_index.msg, &bi);
    uint8_t junk[5] = {1, 2, 3, 4, 5};

    /* Signed with this host's key, so that the decoder's checks are what is tested. */
    bus_reject sent;
    bus_publish_raw(lcm, "B", junk, sizeof junk, &sent); /* truncated */
    bus_publish_raw(lcm, "B", g, (size_t)gn, &sent);
    bus_publish_raw(lcm, "B", nb, (size_t)nbn, &sent);
    bus_publish_raw(lcm, "B", bi, (size_t)bin, &sent);
    bus_publish_raw(lcm, "B", g, (size_t)gn - 1, &sent); /* truncated by one byte */
    bus_publish_raw(lcm, "B", g, (size_t)gn, &sent);
    for (int i = 0; i < 6; i++)
        lcm_handle_timeout(lcm, 500);

    const bus_stats *st = bus_sub_stats(sub);
    assert_int_equal(seen, 2);
    assert_int_equal(st->accepted, 2);
    assert_int_equal(st->rejected, 4);
    assert_int_equal(st->rejected_by[BUS_ERR_TRUNCATED], 2);
    assert_int_equal(st->rejected_by[BUS_ERR_NOT_FINITE], 1);
    assert_int_equal(st->rejected_by[BUS_ERR_INDEX], 1);
    assert_int_equal(st->last.code, BUS_ERR_TRUNCATED);

    /* Publishing refuses what a subscriber would reject: nothing is sent. */
    bus_reject why;
    assert_int_equal(bus_publish(lcm, "B", BUS_BODY, &nan_body.msg, &why), -BUS_ERR_NOT_FINITE);
    assert_int_equal(lcm_handle_timeout(lcm, 100), 0);
    assert_int_equal(st->rejected + st->accepted, 6);

    free(g);
    free(nb);
    free(bi);
    fx_body_free(&good);
    fx_body_free(&nan_body);
    fx_body_free(&bad_index);
    bus_unsubscribe(lcm, sub);
    lcm_destroy(lcm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_valid_messages_of_every_type_decode),
        cmocka_unit_test(test_every_truncation_is_rejected),
        cmocka_unit_test(test_absurd_counts_are_rejected_before_allocation),
        cmocka_unit_test(test_nan_coordinate_is_rejected_with_its_place),
        cmocka_unit_test(test_out_of_range_triangle_index_is_rejected),
        cmocka_unit_test(test_wrong_type_and_trailing_bytes_are_rejected),
        cmocka_unit_test(test_depth_frame_checks),
        cmocka_unit_test(test_timing_checks),
        cmocka_unit_test(test_every_cloth_state_is_accepted),
        cmocka_unit_test(test_subscriber_counts_rejections_and_keeps_serving),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
