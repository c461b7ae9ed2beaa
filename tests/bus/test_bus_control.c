/* CONTROL, the garment requests: a good one round-trips, every malformed one is refused with its
 * reason, counted by the subscriber, and never reaches the handler. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "bus.h"
#include "fixtures.h"

static int decode_control(const uint8_t *buf, size_t len, bus_reject *why)
{
    tryon_control_t out;
    int e = bus_decode(BUS_CONTROL, buf, len, &out, why);
    if (e == BUS_OK)
        bus_msg_free(BUS_CONTROL, &out);
    return e;
}

static void test_control_round_trips(void **state)
{
    (void)state;
    fx_control k;
    fx_control_make(&k, 4);
    k.msg.garment = "/tmp/garments/dress.obj";
    k.msg.size = TRYON_CONTROL_T_SIZE_L;
    k.msg.fabric = "";
    uint8_t *buf;
    int n = fx_encode(BUS_CONTROL, &k.msg, &buf);
    assert_true(n > 0);
    tryon_control_t out;
    bus_reject why;
    assert_int_equal(bus_decode(BUS_CONTROL, buf, (size_t)n, &out, &why), BUS_OK);
    assert_true(fx_equal(BUS_CONTROL, &k.msg, &out));
    bus_msg_free(BUS_CONTROL, &out);
    free(buf);
}

static void test_control_every_truncation_is_refused(void **state)
{
    (void)state;
    fx_control k;
    fx_control_make(&k, 5);
    uint8_t *buf;
    int n = fx_encode(BUS_CONTROL, &k.msg, &buf);
    for (int len = 0; len < n; len++) {
        uint8_t *cut = malloc((size_t)(len ? len : 1)); /* exactly len bytes, for ASan */
        memcpy(cut, buf, (size_t)len);
        bus_reject why;
        assert_int_equal(decode_control(cut, (size_t)len, &why), -BUS_ERR_TRUNCATED);
        free(cut);
    }
    free(buf);
}

static void test_control_contents_are_checked(void **state)
{
    (void)state;
    fx_control k;
    bus_reject why;
    fx_control_make(&k, 6);
    k.msg.size = 3;
    assert_int_equal(bus_validate(BUS_CONTROL, &k.msg, &why), -BUS_ERR_RANGE);
    assert_non_null(strstr(why.detail, "size 3"));
    k.msg.size = -1;
    assert_int_equal(bus_validate(BUS_CONTROL, &k.msg, &why), -BUS_ERR_RANGE);
    fx_control_make(&k, 6);
    k.msg.garment = "";
    assert_int_equal(bus_validate(BUS_CONTROL, &k.msg, &why), -BUS_ERR_STRING);
    assert_non_null(strstr(why.detail, "garment"));
    k.msg.garment = NULL;
    assert_int_equal(bus_validate(BUS_CONTROL, &k.msg, &why), -BUS_ERR_STRING);
    fx_control_make(&k, 6);
    k.msg.fabric = NULL;
    assert_int_equal(bus_validate(BUS_CONTROL, &k.msg, &why), -BUS_ERR_STRING);
    assert_non_null(strstr(why.detail, "fabric"));
    fx_control_make(&k, 6);
    k.msg.seq = -2;
    assert_int_equal(bus_validate(BUS_CONTROL, &k.msg, &why), -BUS_ERR_RANGE);
    char longname[BUS_MAX_STRING + 10];
    memset(longname, 'a', sizeof longname - 1);
    longname[sizeof longname - 1] = 0;
    fx_control_make(&k, 6);
    k.msg.garment = longname;
    assert_int_equal(bus_validate(BUS_CONTROL, &k.msg, &why), -BUS_ERR_STRING);
}

/* Byte offset of the garment string's length: fingerprint, utime, seq. */
#define GARMENT_LEN_AT (8 + 8 + 4)

static void put_i32(uint8_t *p, int32_t v)
{
    uint32_t u = (uint32_t)v;
    p[0] = (uint8_t)(u >> 24);
    p[1] = (uint8_t)(u >> 16);
    p[2] = (uint8_t)(u >> 8);
    p[3] = (uint8_t)u;
}

static void count_good(const char *ch, const void *msg, void *user)
{
    (void)ch;
    const tryon_control_t *m = msg;
    assert_string_equal(m->garment, "shirt");
    (*(int *)user)++;
}

static void test_subscriber_refuses_and_counts_bad_control(void **state)
{
    (void)state;
    char err[256];
    lcm_t *lcm = bus_open("memq://", err, sizeof err);
    assert_non_null(lcm);
    int seen = 0;
    bus_sub *sub = bus_subscribe(lcm, "C", BUS_CONTROL, count_good, &seen);
    bus_sub_quiet(sub, 1);

    fx_control good;
    fx_control_make(&good, 7);
    uint8_t *g, *bad_size, *no_nul, *huge_len;
    int gn = fx_encode(BUS_CONTROL, &good.msg, &g);
    fx_encode(BUS_CONTROL, &good.msg, &bad_size);
    fx_encode(BUS_CONTROL, &good.msg, &no_nul);
    fx_encode(BUS_CONTROL, &good.msg, &huge_len);
    /* size is the byte after the garment string ("shirt" + NUL, 6 bytes) */
    bad_size[GARMENT_LEN_AT + 4 + 6] = 9;
    no_nul[GARMENT_LEN_AT + 4 + 5] = 'x';
    put_i32(huge_len + GARMENT_LEN_AT, INT32_MAX);

    bus_reject sent; /* sealed (bus.h) so that only the payload is wrong */
    bus_publish_raw(lcm, "C", g, (size_t)gn, &sent);
    bus_publish_raw(lcm, "C", bad_size, (size_t)gn, &sent);
    bus_publish_raw(lcm, "C", no_nul, (size_t)gn, &sent);
    bus_publish_raw(lcm, "C", huge_len, (size_t)gn, &sent);
    bus_publish_raw(lcm, "C", g, (size_t)gn - 1, &sent); /* truncated by one byte */
    bus_publish_raw(lcm, "C", g, (size_t)gn, &sent);
    for (int i = 0; i < 6; i++)
        lcm_handle_timeout(lcm, 500);

    const bus_stats *st = bus_sub_stats(sub);
    assert_int_equal(seen, 2);
    assert_int_equal(st->accepted, 2);
    assert_int_equal(st->rejected, 4);
    assert_int_equal(st->rejected_by[BUS_ERR_RANGE], 1);
    assert_int_equal(st->rejected_by[BUS_ERR_STRING], 2);
    assert_int_equal(st->rejected_by[BUS_ERR_TRUNCATED], 1);

    bus_reject why;
    good.msg.size = 7; /* publishing refuses what a subscriber would */
    assert_int_equal(bus_publish(lcm, "C", BUS_CONTROL, &good.msg, &why), -BUS_ERR_RANGE);
    assert_int_equal(lcm_handle_timeout(lcm, 100), 0);

    free(g);
    free(bad_size);
    free(no_nul);
    free(huge_len);
    bus_unsubscribe(lcm, sub);
    lcm_destroy(lcm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_control_round_trips),
        cmocka_unit_test(test_control_every_truncation_is_refused),
        cmocka_unit_test(test_control_contents_are_checked),
        cmocka_unit_test(test_subscriber_refuses_and_counts_bad_control),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
