/* Hostile messages found by review and fuzzing: each case failed before its fix. A DEPTH with an
 * empty byte array (undefined behaviour in lcm-gen's decoder), TIMING reports whose long stage
 * names or unbounded stamps and sequence numbers broke tryon-profile's statistics. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bus.h"
#include "fixtures.h"
#include "profile.h"

static void test_depth_with_no_bytes_is_refused_on_the_wire(void **state)
{
    (void)state;
    fx_depth d;
    fx_depth_make(&d, 8, 6, 1);
    d.msg.num_bytes = 0; /* the encoder writes the count and no data */
    uint8_t *buf;
    int n = fx_encode(BUS_DEPTH_FRAME, &d.msg, &buf);
    assert_true(n > 0);
    tryon_depth_frame_t out;
    bus_reject why;
    /* Refused by the wire walk, before lcm-gen's memcpy(NULL, ..., 0) can run. */
    assert_int_equal(bus_decode(BUS_DEPTH_FRAME, buf, (size_t)n, &out, &why), -BUS_ERR_COUNT);
    assert_non_null(strstr(why.detail, "data"));
    free(buf);
    fx_depth_free(&d);
}

static void test_long_stage_name_keeps_one_slot(void **state)
{
    (void)state;
    bus_profile *p = bus_profile_create();
    assert_non_null(p);
    fx_timing t;
    char longname[] = "a-stage-name-much-longer-than-thirty-one-characters";
    for (int i = 0; i < 40; i++) {
        fx_timing_make(&t, i);
        t.msg.stage = longname;
        assert_int_equal(bus_profile_add(p, &t.msg), 0);
    }
    fx_timing_make(&t, 1);
    assert_int_equal(bus_profile_add(p, &t.msg), 0); /* "sim" still finds a slot */
    bus_stage_stats st[BUS_PROFILE_MAX_STAGES];
    int n = bus_profile_stats(p, st, BUS_PROFILE_MAX_STAGES);
    assert_int_equal(n, 2);
    assert_string_equal(st[0].stage, "sim");
    assert_int_equal(st[1].frames, 40);
    bus_profile_destroy(p);
}

static void test_unbounded_stamps_are_refused(void **state)
{
    (void)state;
    fx_timing t;
    bus_reject why;
    fx_timing_make(&t, 1);
    assert_int_equal(bus_validate(BUS_TIMING, &t.msg, &why), BUS_OK);
    t.msg.utime_capture = INT64_MIN + 5; /* finished - capture would overflow int64 */
    assert_int_equal(bus_validate(BUS_TIMING, &t.msg, &why), -BUS_ERR_RANGE);
    fx_timing_make(&t, 1);
    t.msg.utime_started = INT64_MIN;
    t.msg.utime_capture = 0;
    assert_int_equal(bus_validate(BUS_TIMING, &t.msg, &why), -BUS_ERR_RANGE);
    fx_timing_make(&t, 1);
    t.msg.utime_started = 4000;
    t.msg.utime_finished = INT64_MAX;
    assert_int_equal(bus_validate(BUS_TIMING, &t.msg, &why), -BUS_ERR_RANGE);
}

static void test_one_wild_sequence_number_is_not_billions_of_drops(void **state)
{
    (void)state;
    bus_profile *p = bus_profile_create();
    assert_non_null(p);
    fx_timing t;
    for (int i = 0; i < 200; i++) {
        if (i == 50)
            continue; /* one real drop */
        fx_timing_make(&t, i);
        assert_int_equal(bus_profile_add(p, &t.msg), 0);
    }
    fx_timing_make(&t, 7);
    t.msg.seq = INT32_MAX;
    assert_int_equal(bus_profile_add(p, &t.msg), 0);
    bus_stage_stats st[1];
    assert_int_equal(bus_profile_stats(p, st, 1), 1);
    assert_int_equal(st[0].frames, 200);
    assert_int_equal(st[0].dropped, 1);
    bus_profile_destroy(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_depth_with_no_bytes_is_refused_on_the_wire),
        cmocka_unit_test(test_long_stage_name_keeps_one_slot),
        cmocka_unit_test(test_unbounded_stamps_are_refused),
        cmocka_unit_test(test_one_wild_sequence_number_is_not_billions_of_drops),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
