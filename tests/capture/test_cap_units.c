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
    cap_error code;
    char err[256];
    assert_null(cap_source_create("nope", &(cap_source_desc){0}, &code, err, sizeof err));
    assert_int_equal(code, CAP_ERR_SOURCE);
    assert_string_equal(cap_error_name(CAP_ERR_RECORDING), "CAP_ERR_RECORDING");
}

static void test_a_dump_without_fakenect_is_refused(void **state)
{
    (void)state;
    /* This test process links the real libfreenect: opening a dump must say so, not crash. */
    cap_error code;
    char err[512];
    cap_source_desc d = {.uri = "/tmp"};
    assert_null(cap_source_create("freenect", &d, &code, err, sizeof err));
    assert_int_equal(code, CAP_ERR_NOT_FAKENECT);
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
    assert_int_not_equal(cap_rate_parse("0", &r), 0);
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
                     CAP_ERR_RECORDING);
    assert_non_null(strstr(err, "INDEX.txt"));
    snprintf(p, sizeof p, "rm -rf '%s'", dir);
    assert_int_equal(system(p), 0);
    free(raw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sources_are_found_by_name),
        cmocka_unit_test(test_a_dump_without_fakenect_is_refused),
        cmocka_unit_test(test_rate_parsing),
        cmocka_unit_test(test_pacer_schedules_by_replay_time_and_fps),
        cmocka_unit_test(test_staging_links_frames_with_zero_times),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
