/* tryon-capture as a separate process replaying fakenect dumps through Debian's fakenect
 * libfreenect (the live code path), over real LCM on loopback multicast. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <dirent.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <lcm/eventlog.h>

#include "cap_harness.h"
#include "recordings.h"

#define PORT 7681

static char tmpdir[300];

static int setup(void **state)
{
    harness *h = h_create(PORT);
    /* The child's fakenect staging goes here, so the test can see it cleaned up. */
    snprintf(tmpdir, sizeof tmpdir, "%s-tmp", h->dir);
    mkdir(tmpdir, 0755);
    setenv("TMPDIR", tmpdir, 1);
    *state = h;
    return 0;
}

static int teardown(void **state)
{
    h_destroy(*state);
    rmdir(tmpdir);
    return 0;
}

static int dir_entries(const char *dir)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)))
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    if (d)
        closedir(d);
    return n;
}

/* Values, order, count and device timestamps, against the dump. */
static void check_frames_exact(const harness *h, int n)
{
    uint16_t table[REC_RAW_LEVELS];
    rec_raw_to_mm_table(table);
    assert_int_equal(h->depth_count, n);
    for (int k = 0; k < n; k++) {
        const h_depth *d = &h->depth[k];
        assert_int_equal(d->seq, k);
        assert_int_equal(d->device_timestamp, h_timestamp(k));
        assert_int_equal(d->width, 640);
        assert_int_equal(d->height, 480);
        assert_string_equal(d->source, "freenect");
        assert_true(fabsf(d->metres_per_unit - 0.001f) < 1e-9f);
        assert_true(fabsf(d->fx - (float)REC_FX) < 1e-3f);
        for (int i = 0; i < H_PIXELS; i++)
            if (d->mm[i] != table[h_raw(k, i)])
                fail_msg("frame %d pixel %d: %u mm, dump says raw %u = %u mm", k, i, d->mm[i],
                         h_raw(k, i), table[h_raw(k, i)]);
        if (k > 0)
            assert_true(d->utime_capture > h->depth[k - 1].utime_capture);
    }
}

static void test_dump_arrives_frame_exact_at_realtime(void **state)
{
    harness *h = *state;
    const int n = 10;
    h_write_dump(h, n, 30.0);
    const char *args[] = {"--source", "freenect", "--uri", h->dir, NULL};
    h_start(h, args);
    int rc = h_wait(h, 8.0);
    if (rc != 0)
        fail_msg("tryon-capture exit %d: %s", rc, h->err_text);
    check_frames_exact(h, n);
    /* Realtime: never before the recorded time; late only by what a frame costs (generous, for
     * the sanitizer build on a busy 2-core machine). */
    for (int k = 1; k < n; k++) {
        double got = (h->depth[k].utime_capture - h->depth[0].utime_capture) * 1e-6;
        double want = k / 30.0;
        if (got < want - 0.002 || got > want + 0.25)
            fail_msg("frame %d stamped %.4f s after frame 0, recorded %.4f s", k, got, want);
    }
    assert_int_equal(h->timing_count, n);
    for (int k = 0; k < n; k++)
        assert_int_equal(h->timing_seq[k], k);
    assert_int_equal(dir_entries(tmpdir), 0);
}

static void test_rate_max_is_fast_and_record_reproduces_the_dump(void **state)
{
    harness *h = *state;
    const int n = 12;
    h_write_dump(h, n, 2.0); /* 5.5 s in real time */
    const char *args[] = {"--uri", h->dir, "--rate", "max", "--record", h->out_dir, NULL};
    h_start(h, args);
    int rc = h_wait(h, 8.0);
    if (rc != 0)
        fail_msg("tryon-capture exit %d: %s", rc, h->err_text);
    check_frames_exact(h, n);
    double span = (h->depth[n - 1].utime_capture - h->depth[0].utime_capture) * 1e-6;
    assert_true(span < 3.0); /* realtime would take 5.5 s */
    /* The recording holds the same disparities, timestamps and record times. */
    rec_index a, b;
    rec_report why;
    int frames = 0;
    assert_int_equal(rec_validate(h->out_dir, &frames, &why), REC_OK);
    assert_int_equal(frames, n);
    assert_int_equal(rec_index_read(h->dir, &a, &why), REC_OK);
    assert_int_equal(rec_index_read(h->out_dir, &b, &why), REC_OK);
    uint16_t *ra = malloc(H_PIXELS * 2), *rb = malloc(H_PIXELS * 2);
    for (int k = 0; k < n; k++) {
        assert_int_equal(a.frames[k].device_timestamp, b.frames[k].device_timestamp);
        assert_true(fabs(a.frames[k].record_time_s - b.frames[k].record_time_s) < 2e-6);
        assert_int_equal(rec_frame_read(h->dir, &a.frames[k], k, ra, &why), REC_OK);
        assert_int_equal(rec_frame_read(h->out_dir, &b.frames[k], k, rb, &why), REC_OK);
        assert_memory_equal(ra, rb, H_PIXELS * 2);
    }
    free(ra);
    free(rb);
    rec_index_free(&a);
    rec_index_free(&b);
}

static void test_frames_option_stops_early(void **state)
{
    harness *h = *state;
    h_write_dump(h, 8, 30.0);
    const char *args[] = {"--uri", h->dir, "--rate", "max", "--frames", "3", NULL};
    h_start(h, args);
    assert_int_equal(h_wait(h, 8.0), 0);
    check_frames_exact(h, 3);
    assert_int_equal(dir_entries(tmpdir), 0);
}

static void test_committed_sample_replays_frame_exact(void **state)
{
    harness *h = *state;
    const char *dir = TRYON_SAMPLES_DIR "/fast_swing_s1";
    rec_index idx;
    rec_report why;
    assert_int_equal(rec_index_read(dir, &idx, &why), REC_OK);
    const char *args[] = {"--uri", dir, NULL};
    h_start(h, args);
    int rc = h_wait(h, 8.0);
    if (rc != 0)
        fail_msg("tryon-capture exit %d: %s", rc, h->err_text);
    assert_int_equal(h->depth_count, idx.count);
    uint16_t table[REC_RAW_LEVELS], *raw = malloc(H_PIXELS * 2);
    rec_raw_to_mm_table(table);
    for (int k = 0; k < idx.count; k++) {
        assert_int_equal(rec_frame_read(dir, &idx.frames[k], k, raw, &why), REC_OK);
        assert_int_equal(h->depth[k].seq, k);
        assert_int_equal(h->depth[k].device_timestamp, idx.frames[k].device_timestamp);
        for (int i = 0; i < H_PIXELS; i++)
            if (h->depth[k].mm[i] != table[raw[i]])
                fail_msg("frame %d pixel %d differs", k, i);
    }
    free(raw);
    rec_index_free(&idx);
}

static void nap_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static void test_lcm_logger_records_the_depth_channel(void **state)
{
    harness *h = *state;
    const int n = 6;
    h_write_dump(h, n, 30.0);
    char log[400], url_opt[200], chan[BUS_CHANNEL_MAX];
    snprintf(log, sizeof log, "%s/depth.lcmlog", h->out_dir);
    mkdir(h->out_dir, 0755);
    snprintf(url_opt, sizeof url_opt, "--lcm-url=%s", h->url); /* -l is refused by lcm 1.3.1 */
    bus_channel(BUS_CHANNEL_DEPTH, chan, sizeof chan);
    h->logger = fork();
    if (h->logger == 0) {
        execlp("lcm-logger", "lcm-logger", url_opt, "-c", chan, "-f", log, (char *)NULL);
        _exit(127);
    }
    nap_ms(800); /* let the logger subscribe (generous: a busy machine, a sanitizer build) */
    const char *args[] = {"--uri", h->dir, NULL};
    h_start(h, args);
    assert_int_equal(h_wait(h, 8.0), 0);
    assert_int_equal(h->depth_count, n);
    nap_ms(500); /* and write what it received (it flushes every 100 ms) */
    kill(h->logger, SIGINT);
    int status = 0;
    waitpid(h->logger, &status, 0);
    h->logger = -1;
    lcm_eventlog_t *el = lcm_eventlog_create(log, "r");
    assert_non_null(el);
    int events = 0;
    lcm_eventlog_event_t *ev;
    while ((ev = lcm_eventlog_read_next_event(el))) {
        tryon_depth_frame_t m;
        bus_reject why;
        assert_string_equal(ev->channel, chan);
        assert_int_equal(bus_decode_sealed(BUS_DEPTH_FRAME, ev->channel, ev->data,
                                           (size_t)ev->datalen, &m, &why),
                         BUS_OK); /* the log keeps the tag */
        assert_int_equal(m.seq, events);
        assert_int_equal(m.device_timestamp, h_timestamp(events));
        assert_int_equal(m.num_bytes, H_PIXELS * 2);
        for (int i = 0; i < H_PIXELS; i++)
            if ((m.data[2 * i] | (m.data[2 * i + 1] << 8)) != h->depth[events].mm[i])
                fail_msg("logged frame %d pixel %d differs from the one received live", events, i);
        bus_msg_free(BUS_DEPTH_FRAME, &m);
        lcm_eventlog_free_event(ev);
        events++;
    }
    lcm_eventlog_destroy(el);
    assert_int_equal(events, n);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(test_dump_arrives_frame_exact_at_realtime),
        T(test_rate_max_is_fast_and_record_reproduces_the_dump),
        T(test_frames_option_stops_early),
        T(test_committed_sample_replays_frame_exact),
        T(test_lcm_logger_records_the_depth_channel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
