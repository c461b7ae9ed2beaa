/* Every message type makes a round trip through LCM (memq://) and arrives equal. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "bus.h"
#include "fixtures.h"

typedef struct catch_state {
    bus_type type;
    const void *sent;
    int got;
    int equal;
} catch_state;

static void on_msg(const char *channel, const void *msg, void *user)
{
    (void)channel;
    catch_state *c = user;
    c->got++;
    c->equal = fx_equal(c->type, c->sent, msg);
}

static void round_trip(bus_type t, const void *msg)
{
    char err[256];
    lcm_t *lcm = bus_open("memq://", err, sizeof err);
    assert_non_null(lcm);
    catch_state c = {.type = t, .sent = msg};
    bus_sub *sub = bus_subscribe(lcm, "ROUND_TRIP", t, on_msg, &c);
    assert_non_null(sub);
    bus_reject why;
    assert_int_equal(bus_publish(lcm, "ROUND_TRIP", t, msg, &why), BUS_OK);
    assert_int_equal(lcm_handle_timeout(lcm, 1000) > 0, 1);
    assert_int_equal(c.got, 1);
    assert_true(c.equal);
    assert_int_equal(bus_sub_stats(sub)->accepted, 1);
    assert_int_equal(bus_sub_stats(sub)->rejected, 0);
    bus_unsubscribe(lcm, sub);
    lcm_destroy(lcm);
}

static void test_depth_frame_round_trip_full_size(void **state)
{
    (void)state;
    fx_depth f;
    fx_depth_make(&f, 640, 480, 3);
    round_trip(BUS_DEPTH_FRAME, &f.msg);
    fx_depth_free(&f);
}

static void test_body_round_trip(void **state)
{
    (void)state;
    fx_body f;
    fx_body_make(&f, 10000, 19996, 5);
    round_trip(BUS_BODY, &f.msg);
    fx_body_free(&f);
}

static void test_body_round_trip_without_triangles(void **state)
{
    (void)state;
    fx_body f;
    fx_body_make(&f, 100, 0, 6); /* same topology as before: triangles omitted */
    round_trip(BUS_BODY, &f.msg);
    fx_body_free(&f);
}

static void test_cloth_round_trip(void **state)
{
    (void)state;
    fx_cloth f;
    fx_cloth_make(&f, 7000, 13800, 2);
    round_trip(BUS_CLOTH, &f.msg);
    fx_cloth_free(&f);
}

static void test_timing_round_trip(void **state)
{
    (void)state;
    fx_timing f;
    fx_timing_make(&f, 4);
    round_trip(BUS_TIMING, &f.msg);
}

typedef struct timing_catch {
    int got;
    tryon_timing_t copy;
    char names[4][32];
    float ms[4];
} timing_catch;

static void on_timing(const char *channel, const void *msg, void *user)
{
    (void)channel;
    const tryon_timing_t *t = msg;
    timing_catch *c = user;
    c->got++;
    c->copy = *t;
    for (int i = 0; i < t->num_substages && i < 4; i++) {
        strncpy(c->names[i], t->substage[i], sizeof c->names[i] - 1);
        c->ms[i] = t->substage_ms[i];
    }
}

static void test_timing_helper_publishes_on_prefixed_channel(void **state)
{
    (void)state;
    setenv("TRYON_CHANNEL_PREFIX", "UNIT_", 1);
    char channel[BUS_CHANNEL_MAX];
    assert_int_equal(bus_channel(BUS_CHANNEL_TIMING, channel, sizeof channel), 0);
    assert_string_equal(channel, "UNIT_TIMING");
    char err[256];
    lcm_t *lcm = bus_open("memq://", err, sizeof err);
    assert_non_null(lcm);
    timing_catch c = {0};
    bus_sub *sub = bus_subscribe(lcm, channel, BUS_TIMING, on_timing, &c);
    bus_timing t;
    int64_t t0 = bus_now_wall_us();
    bus_timing_begin(&t, "sim", 42, t0 - 20000, t0 - 1000);
    bus_timing_add(&t, "bvh", 0.5f);
    bus_timing_add(&t, "iterations", 3.25f);
    assert_int_equal(bus_timing_publish(lcm, &t), BUS_OK);
    lcm_handle_timeout(lcm, 1000);
    assert_int_equal(c.got, 1);
    assert_int_equal(c.copy.seq, 42);
    assert_int_equal(c.copy.num_substages, 2);
    assert_string_equal(c.names[1], "iterations");
    assert_true(c.ms[1] == 3.25f);
    assert_true(c.copy.utime_finished >= c.copy.utime_started);
    assert_true(c.copy.utime_started >= t0);
    bus_unsubscribe(lcm, sub);
    lcm_destroy(lcm);
    unsetenv("TRYON_CHANNEL_PREFIX");
}

static void test_channel_name_too_long_is_refused(void **state)
{
    (void)state;
    char small[4];
    assert_int_equal(bus_channel(BUS_CHANNEL_DEPTH, small, sizeof small), -BUS_ERR_STRING);
}

static void test_bad_url_gives_a_reason(void **state)
{
    (void)state;
    char err[512] = "";
    assert_null(bus_open("nosuchprovider://x", err, sizeof err));
    assert_non_null(strstr(err, "nosuchprovider://x"));
}

static void test_error_names_and_texts(void **state)
{
    (void)state;
    assert_string_equal(bus_error_name(BUS_ERR_INDEX), "BUS_ERR_INDEX");
    assert_string_equal(bus_error_text(BUS_ERR_NOT_FINITE), "number is NaN or infinite");
    assert_string_equal(bus_error_name((bus_error)999), "BUS_ERR_UNKNOWN");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_depth_frame_round_trip_full_size),
        cmocka_unit_test(test_body_round_trip),
        cmocka_unit_test(test_body_round_trip_without_triangles),
        cmocka_unit_test(test_cloth_round_trip),
        cmocka_unit_test(test_timing_round_trip),
        cmocka_unit_test(test_timing_helper_publishes_on_prefixed_channel),
        cmocka_unit_test(test_channel_name_too_long_is_refused),
        cmocka_unit_test(test_bad_url_gives_a_reason),
        cmocka_unit_test(test_error_names_and_texts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
