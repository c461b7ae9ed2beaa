/* tryon-profile's statistics: percentiles, drops, fps and pipeline order on known samples, and
 * the executable reading a real LCM log that also holds a corrupt event. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <lcm/eventlog.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bus.h"
#include "fixtures.h"
#include "profile.h"
#include "support.h"

#define FRAME_US 33333

/* Stage `stage` reports frame seq with work w_ms, finishing lat_ms after capture. */
static tryon_timing_t report(const char *stage, int seq, double w_ms, double lat_ms)
{
    int64_t cap = 1000000 + (int64_t)seq * FRAME_US;
    int64_t fin = cap + (int64_t)(lat_ms * 1000);
    return (tryon_timing_t){.stage = (char *)stage,
                            .seq = seq,
                            .utime_capture = cap,
                            .utime_received = cap,
                            .utime_started = fin - (int64_t)(w_ms * 1000),
                            .utime_finished = fin};
}

static void test_profile_percentiles_drops_and_order(void **state)
{
    (void)state;
    bus_profile *p = bus_profile_create();
    char *names[1] = {"iterations"};
    for (int seq = 0; seq < 100; seq++) {
        if (seq == 10 || seq == 20)
            continue; /* two frames dropped by the sim */
        float ms = (float)seq / 10.0f;
        tryon_timing_t sim = report("sim", seq, 1.0 + seq / 100.0, seq + 1.0);
        sim.num_substages = 1;
        sim.substage = names;
        sim.substage_ms = &ms;
        assert_int_equal(bus_profile_add(p, &sim), 0);
    }
    for (int seq = 0; seq < 100; seq++) {
        tryon_timing_t cap = report("capture", seq, 0.5, 0.5);
        assert_int_equal(bus_profile_add(p, &cap), 0);
    }
    bus_stage_stats st[4];
    assert_int_equal(bus_profile_stats(p, st, 4), 2);
    assert_string_equal(st[0].stage, "capture");
    assert_string_equal(st[1].stage, "sim");
    assert_int_equal(st[0].frames, 100);
    assert_int_equal(st[0].dropped, 0);
    assert_int_equal(st[1].frames, 98);
    assert_int_equal(st[1].dropped, 2);
    assert_true(st[0].fps > 29.9 && st[0].fps < 30.1);
    /* sim latencies are seq + 1 ms over seq 0..99 without 10 and 20: nearest-rank p50 is the
     * 49th of 98 values, i.e. seq 50, so 51 ms; p99 is the 98th, 100 ms. */
    assert_true(st[1].lat_p50_ms > 50.99 && st[1].lat_p50_ms < 51.01);
    assert_true(st[1].lat_p99_ms > 99.99 && st[1].lat_p99_ms < 100.01);
    assert_true(st[1].lat_max_ms > 99.99);
    assert_int_equal(st[1].num_substages, 1);
    assert_true(st[1].substage_p50_ms[0] > 4.99 && st[1].substage_p50_ms[0] < 5.01);
    bus_profile_destroy(p);
}

/* The mirror's first CLOTH drawn late: the sim's frames before it never reached the screen and
 * count as the mirror's drops; the sim's own first frames (bodies of nobody are not dressed) and
 * its drops do not. */
static void test_profile_counts_frames_missed_before_the_first(void **state)
{
    (void)state;
    bus_profile *p = bus_profile_create();
    for (int seq = 0; seq < 60; seq++) {
        tryon_timing_t cap = report("capture", seq, 0.5, 0.5);
        assert_int_equal(bus_profile_add(p, &cap), 0);
        if (seq >= 10 && seq != 12) { /* the person from frame 10; body 12 superseded */
            tryon_timing_t sim = report("sim", seq, 10.0, 20.0);
            assert_int_equal(bus_profile_add(p, &sim), 0);
        }
        if (seq >= 14) { /* the sim's 10, 11 and 13 never drawn */
            tryon_timing_t mirror = report("mirror", seq, 5.0, 30.0);
            assert_int_equal(bus_profile_add(p, &mirror), 0);
        }
    }
    bus_stage_stats st[3];
    assert_int_equal(bus_profile_stats(p, st, 3), 3);
    assert_string_equal(st[1].stage, "sim");
    assert_int_equal(st[1].dropped, 1);
    assert_string_equal(st[2].stage, "mirror");
    assert_int_equal(st[2].frames, 46);
    assert_int_equal(st[2].dropped, 3);
    assert_int_equal(st[2].steady_dropped, 3); /* no warm-up: the whole session's */
    bus_profile_destroy(p);
}

/* A warm-up: the first frames by seq are left out of the steady_ figures only; a drop right
 * after the warm-up counts, one inside it does not. */
static void test_profile_warmup(void **state)
{
    (void)state;
    bus_profile *p = bus_profile_create();
    bus_profile_set_warmup(p, 10);
    for (int seq = 5; seq < 105; seq++) { /* the stage's first frame is seq 5 */
        if (seq == 7 || seq == 15 || seq == 50)
            continue; /* 7 inside the warm-up (5..14), 15 its first frame after, 50 later */
        double lat = seq < 15 ? 200.0 : 10.0 + (seq % 10);
        tryon_timing_t sim = report("sim", seq, 1.0, lat);
        assert_int_equal(bus_profile_add(p, &sim), 0);
    }
    bus_stage_stats st[1];
    assert_int_equal(bus_profile_stats(p, st, 1), 1);
    assert_int_equal(st[0].frames, 97);
    assert_int_equal(st[0].dropped, 3);
    assert_true(st[0].lat_p95_ms > 199.0); /* the whole session keeps the warm-up's frames */
    assert_int_equal(st[0].steady_frames, 88);
    assert_int_equal(st[0].steady_dropped, 2);
    assert_true(st[0].steady_lat_p95_ms >= 18.0 && st[0].steady_lat_p95_ms <= 19.0);
    assert_true(st[0].steady_lat_p50_ms >= 14.0 && st[0].steady_lat_p50_ms <= 15.0);
    char *buf = NULL;
    size_t len = 0;
    FILE *out = open_memstream(&buf, &len);
    bus_profile_print(p, out);
    fclose(out);
    assert_non_null(strstr(buf, "after the first 10 frames (warm-up)"));
    assert_non_null(strstr(buf, "\"warmup_frames\": 10, \"steady_dropped\": 2"));
    free(buf);
    bus_profile_set_warmup(p, 0); /* none: the steady figures are the whole session's */
    assert_int_equal(bus_profile_stats(p, st, 1), 1);
    assert_int_equal(st[0].steady_frames, st[0].frames);
    assert_int_equal(st[0].steady_dropped, st[0].dropped);
    bus_profile_destroy(p);
}

/* One event as lcm-logger writes it: the payload and its tag. */
static void write_event(lcm_eventlog_t *log, int64_t n, const char *channel, void *data, int len)
{
    uint8_t *sealed = malloc((size_t)len + BUS_TAG_BYTES);
    assert_non_null(sealed);
    memcpy(sealed, data, (size_t)len);
    bus_reject why;
    assert_int_equal(bus_seal(channel, sealed, (size_t)len, &why), BUS_OK);
    lcm_eventlog_event_t ev = {.eventnum = n,
                               .timestamp = 1000 + n,
                               .channellen = (int32_t)strlen(channel),
                               .datalen = len + BUS_TAG_BYTES,
                               .channel = (char *)channel,
                               .data = sealed};
    assert_int_equal(lcm_eventlog_write_event(log, &ev), 0);
    free(sealed);
}

static void test_profile_reads_an_lcm_log_and_skips_corrupt_events(void **state)
{
    (void)state;
    char dir[256], log_path[300], out_path[300];
    assert_int_equal(ts_temp_dir(dir, sizeof dir, "profile"), 0);
    snprintf(log_path, sizeof log_path, "%s/run.lcmlog", dir);
    snprintf(out_path, sizeof out_path, "%s/out.txt", dir);
    lcm_eventlog_t *log = lcm_eventlog_create(log_path, "w");
    assert_non_null(log);
    int64_t n = 0;
    for (int seq = 0; seq < 30; seq++) {
        tryon_timing_t t = report("sim", seq, 2.0, 40.0);
        uint8_t *buf;
        int len = fx_encode(BUS_TIMING, &t, &buf);
        write_event(log, n++, "TIMING", buf, len);
        if (seq == 5)
            write_event(log, n++, "TIMING", buf, len / 2); /* corrupt: cut in half */
        free(buf);
    }
    uint8_t junk[3] = {9, 9, 9};
    write_event(log, n++, "DEPTH", junk, 3); /* other channels are ignored */
    lcm_eventlog_destroy(log);

    char *argv[] = {TRYON_PROFILE, "--log", log_path, NULL};
    assert_int_equal(ts_wait(ts_spawn_out(argv, NULL, out_path), 20000), 0);
    char *out = ts_read_file(out_path);
    assert_non_null(out);
    assert_non_null(strstr(out, "30 timing reports"));
    assert_non_null(strstr(out, "1 rejected"));
    assert_non_null(strstr(out, "\"last_stage\": \"sim\", \"frames\": 30, \"dropped\": 0"));
    assert_non_null(strstr(out, "\"latency_p50_ms\": 40.000"));
    free(out);
    ts_remove_dir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_profile_percentiles_drops_and_order),
        cmocka_unit_test(test_profile_counts_frames_missed_before_the_first),
        cmocka_unit_test(test_profile_warmup),
        cmocka_unit_test(test_profile_reads_an_lcm_log_and_skips_corrupt_events),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
