/* Capture pieces without a process: the source registry, rate parsing, the pacer, the
 * disparity table the freenect source uses, fakenect staging. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bus.h"
#include "capture.h"
#include "recordings.h"

static void test_sources_are_found_by_name(void **state)
{
    (void)state;
    assert_non_null(cap_source_find("freenect"));
    assert_non_null(cap_source_find("openni2"));
    assert_null(cap_source_find("kinect2"));
    assert_string_equal(cap_source_name(0), "freenect");
    assert_null(cap_source_name(2));
    int code;
    char err[256];
    assert_null(cap_source_create("nope", &(cap_source_desc){0}, &code, err, sizeof err));
    assert_int_equal(code, -CAP_ERR_SOURCE);
    assert_string_equal(cap_error_name(CAP_ERR_RECORDING), "CAP_ERR_RECORDING");
}

static void test_a_dump_without_fakenect_is_refused(void **state)
{
    (void)state;
    /* This test process links the real libfreenect: opening a dump must say so, not crash. */
    int code;
    char err[512];
    cap_source_desc d = {.uri = "/tmp"};
    assert_null(cap_source_create("freenect", &d, &code, err, sizeof err));
    assert_int_equal(code, -CAP_ERR_NOT_FAKENECT);
    assert_non_null(strstr(err, "/tmp"));
}

static void test_rate_parsing(void **state)
{
    (void)state;
    cap_rate r;
    assert_int_equal(cap_rate_parse("realtime", &r), 0);
    assert_int_equal(r.mode, CAP_RATE_REALTIME);
    assert_int_equal(cap_rate_parse("max", &r), 0);
    assert_int_equal(r.mode, CAP_RATE_MAX);
    assert_int_equal(cap_rate_parse("12.5", &r), 0);
    assert_int_equal(r.mode, CAP_RATE_FPS);
    assert_true(r.fps == 12.5);
    assert_int_equal(cap_rate_parse("0", &r), -CAP_ERR_ARG);
    assert_int_not_equal(cap_rate_parse("-3", &r), 0);
    assert_int_not_equal(cap_rate_parse("30fps", &r), 0);
    assert_int_not_equal(cap_rate_parse(NULL, &r), 0);
}

static void test_pacer_schedules_by_replay_time_and_fps(void **state)
{
    (void)state;
    cap_pacer p;
    int skip;
    cap_pacer_init(&p, (cap_rate){CAP_RATE_REALTIME, 0});
    int64_t d0 = cap_pacer_due(&p, 5.0, &skip);
    int64_t d1 = cap_pacer_due(&p, 5.5, &skip);
    assert_int_equal(d1 - d0, 500000);
    cap_pacer_init(&p, (cap_rate){CAP_RATE_FPS, 20.0});
    d0 = cap_pacer_due(&p, 0.0, &skip);
    d1 = cap_pacer_due(&p, 0.001, &skip);
    int64_t d2 = cap_pacer_due(&p, 0.002, &skip);
    assert_int_equal(d1 - d0, 50000);
    assert_int_equal(d2 - d0, 100000);
    /* Live in FPS mode: an early frame is skipped, not delayed. */
    cap_pacer_init(&p, (cap_rate){CAP_RATE_FPS, 1.0});
    cap_pacer_due(&p, -1.0, &skip);
    assert_int_equal(skip, 0);
    cap_pacer_due(&p, -1.0, &skip);
    assert_int_equal(skip, 1);
    /* Sleeping ends at the due time, or at once when stopped. */
    volatile sig_atomic_t stop = 0;
    int64_t t = bus_now_mono_us();
    cap_sleep_until(t + 30000, &stop);
    assert_true(bus_now_mono_us() - t >= 30000);
    stop = 1;
    t = bus_now_mono_us();
    cap_sleep_until(t + 5000000, &stop);
    assert_true(bus_now_mono_us() - t < 100000);
}

static void test_staging_links_frames_with_zero_times(void **state)
{
    (void)state;
    char dir[128];
    snprintf(dir, sizeof dir, "/tmp/tryon-test-cap-stage-%d", (int)getpid());
    rec_report why;
    rec_writer *w = rec_writer_create(dir, &why);
    uint16_t *raw = calloc(640 * 480, sizeof *raw);
    for (int k = 0; k < 3; k++)
        assert_int_equal(rec_writer_frame(w, raw, 2.0 + k, 10u * k + 1, &why), REC_OK);
    rec_writer_destroy(w);
    char staged[256], err[512];
    assert_int_equal(cap_fakenect_stage(dir, staged, sizeof staged, err, sizeof err), CAP_OK);
    rec_index idx;
    assert_int_equal(rec_index_read(staged, &idx, &why), REC_OK);
    assert_int_equal(idx.count, 3);
    for (int k = 0; k < 3; k++) {
        assert_true(idx.frames[k].record_time_s == 0.0);
        assert_int_equal(idx.frames[k].device_timestamp, 10u * k + 1);
        assert_int_equal(rec_frame_read(staged, &idx.frames[k], k, raw, &why), REC_OK);
    }
    rec_index_free(&idx);
    cap_fakenect_unstage(staged);
    assert_int_not_equal(access(staged, F_OK), 0);
    /* A damaged dump is refused before anything is staged. */
    char p[300];
    snprintf(p, sizeof p, "%s/INDEX.txt", dir);
    unlink(p);
    assert_int_equal(cap_fakenect_stage(dir, staged, sizeof staged, err, sizeof err),
                     -CAP_ERR_RECORDING);
    assert_non_null(strstr(err, "INDEX.txt"));
    snprintf(p, sizeof p, "rm -rf '%s'", dir);
    assert_int_equal(system(p), 0);
    free(raw);
}

typedef struct got {
    int depth, timing;
    float c2w[16];
    int32_t width, seq_last;
    char substages[64];
} got;

static void on_depth(const char *ch, const void *msg, void *user)
{
    (void)ch;
    got *g = user;
    const tryon_depth_frame_t *m = msg;
    memcpy(g->c2w, m->camera_to_world, sizeof g->c2w);
    g->width = m->width;
    g->seq_last = m->seq;
    g->depth++;
}

static void on_timing(const char *ch, const void *msg, void *user)
{
    (void)ch;
    got *g = user;
    const tryon_timing_t *t = msg;
    snprintf(g->substages, sizeof g->substages, "%s:%s,%s", t->stage,
             t->num_substages > 0 ? t->substage[0] : "",
             t->num_substages > 1 ? t->substage[1] : "");
    g->timing++;
}

/* The loop in-process over memq, with OpenNI2's Dummy device as the camera. */
static void test_run_publishes_depth_and_timing_in_process(void **state)
{
    (void)state;
    char err[512];
    lcm_t *lcm = bus_open("memq://", err, sizeof err);
    assert_non_null(lcm);
    got g = {0};
    char ch[BUS_CHANNEL_MAX];
    bus_channel(BUS_CHANNEL_DEPTH, ch, sizeof ch);
    bus_sub *sd = bus_subscribe(lcm, ch, BUS_DEPTH_FRAME, on_depth, &g);
    bus_channel(BUS_CHANNEL_TIMING, ch, sizeof ch);
    bus_sub *st = bus_subscribe(lcm, ch, BUS_TIMING, on_timing, &g);
    float c2w[16] = {1, 0, 0, 0.5f, 0, -1, 0, 1.2f, 0, 0, -1, 3.0f, 0, 0, 0, 1};
    cap_run_desc d = {.source = "openni2",
                      .uri = "Dummy",
                      .rate = {CAP_RATE_MAX, 0},
                      .frames = 3,
                      .camera_to_world = c2w,
                      .lcm = lcm};
    volatile sig_atomic_t stop = 0;
    cap_run_stats stats;
    int e = cap_run(&d, &stop, &stats, err, sizeof err);
    if (e != CAP_OK)
        fail_msg("cap_run: %s", err);
    assert_int_equal(stats.frames, 3);
    while (lcm_handle_timeout(lcm, 0) > 0)
        ;
    assert_int_equal(g.depth, 3);
    assert_int_equal(g.timing, 3);
    assert_int_equal(g.seq_last, 2);
    assert_int_equal(g.width, 320);
    assert_memory_equal(g.c2w, c2w, sizeof c2w);
    assert_string_equal(g.substages, "capture:fetch,publish");
    /* --record writes 640x480 dumps only: the Dummy's 320x240 is refused by name. */
    d.record_dir = "/tmp/tryon-test-cap-units-record";
    e = cap_run(&d, &stop, &stats, err, sizeof err);
    assert_int_equal(e, -CAP_ERR_RECORD);
    assert_non_null(strstr(err, "320x240"));
    assert_int_equal(system("rm -rf /tmp/tryon-test-cap-units-record"), 0);
    bus_unsubscribe(lcm, sd);
    bus_unsubscribe(lcm, st);
    lcm_destroy(lcm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sources_are_found_by_name),
        cmocka_unit_test(test_a_dump_without_fakenect_is_refused),
        cmocka_unit_test(test_rate_parsing),
        cmocka_unit_test(test_pacer_schedules_by_replay_time_and_fps),
        cmocka_unit_test(test_staging_links_frames_with_zero_times),
        cmocka_unit_test(test_run_publishes_depth_and_timing_in_process),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
