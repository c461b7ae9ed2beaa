/* Two separate processes talk over the default transport (udpm, on loopback, ttl=0): a full-size
 * 640x480 depth frame and a 10K-vertex body go out and come back intact. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <signal.h>
#include <string.h>

#include "bus.h"
#include "fixtures.h"
#include "support.h"

typedef struct echo_state {
    int ready;
    int depth_equal, body_equal;
    const void *depth_sent, *body_sent;
} echo_state;

static void on_ready(const char *ch, const void *msg, void *user)
{
    (void)ch;
    (void)msg;
    ((echo_state *)user)->ready = 1;
}

static void on_echo_depth(const char *ch, const void *msg, void *user)
{
    (void)ch;
    echo_state *s = user;
    s->depth_equal = fx_equal(BUS_DEPTH_FRAME, s->depth_sent, msg) ? 1 : -1;
}

static void on_echo_body(const char *ch, const void *msg, void *user)
{
    (void)ch;
    echo_state *s = user;
    s->body_equal = fx_equal(BUS_BODY, s->body_sent, msg) ? 1 : -1;
}

static void test_full_size_frame_crosses_processes_over_udpm(void **state)
{
    (void)state;
    char url[128], prefix[32], err[512];
    ts_private_bus(url, sizeof url, prefix, sizeof prefix);
    assert_non_null(strstr(url, "udpm://"));
    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    if (!lcm)
        fail_msg("%s", err);

    fx_depth d;
    fx_body b;
    fx_depth_make(&d, 640, 480, 11);
    fx_body_make(&b, 10000, 19996, 11);
    echo_state s = {.depth_sent = &d.msg, .body_sent = &b.msg};
    char ch_ready[BUS_CHANNEL_MAX], ch_ed[BUS_CHANNEL_MAX], ch_eb[BUS_CHANNEL_MAX];
    char ch_d[BUS_CHANNEL_MAX], ch_b[BUS_CHANNEL_MAX];
    bus_channel(BUS_CHANNEL_TIMING, ch_ready, sizeof ch_ready);
    bus_channel("ECHO_DEPTH", ch_ed, sizeof ch_ed);
    bus_channel("ECHO_BODY", ch_eb, sizeof ch_eb);
    bus_channel(BUS_CHANNEL_DEPTH, ch_d, sizeof ch_d);
    bus_channel(BUS_CHANNEL_BODY, ch_b, sizeof ch_b);
    bus_sub *s1 = bus_subscribe(lcm, ch_ready, BUS_TIMING, on_ready, &s);
    bus_sub *s2 = bus_subscribe(lcm, ch_ed, BUS_DEPTH_FRAME, on_echo_depth, &s);
    bus_sub *s3 = bus_subscribe(lcm, ch_eb, BUS_BODY, on_echo_body, &s);

    char *argv[] = {BUS_PEER, "2", "15000", NULL};
    pid_t peer = ts_spawn(argv, NULL);
    assert_true(peer > 0);
    int64_t end = bus_now_mono_us() + 10 * 1000 * 1000;
    while (!s.ready && bus_now_mono_us() < end)
        lcm_handle_timeout(lcm, 100);
    assert_true(s.ready);

    bus_reject why;
    assert_int_equal(bus_publish(lcm, ch_d, BUS_DEPTH_FRAME, &d.msg, &why), BUS_OK);
    assert_int_equal(bus_publish(lcm, ch_b, BUS_BODY, &b.msg, &why), BUS_OK);
    while ((!s.depth_equal || !s.body_equal) && bus_now_mono_us() < end)
        lcm_handle_timeout(lcm, 100);
    int status = ts_wait(peer, 5000);

    assert_int_equal(s.depth_equal, 1);
    assert_int_equal(s.body_equal, 1);
    assert_int_equal(status, 0);
    assert_int_equal(bus_sub_stats(s2)->rejected, 0);
    bus_unsubscribe(lcm, s1);
    bus_unsubscribe(lcm, s2);
    bus_unsubscribe(lcm, s3);
    lcm_destroy(lcm);
    fx_depth_free(&d);
    fx_body_free(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_size_frame_crosses_processes_over_udpm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
