/* tryon-capture as a separate process: stopping on a signal, refusing damaged recordings by
 * name, the OpenNI2 source (Dummy device, missing .oni), usage errors. Real LCM on loopback. */
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
#include <unistd.h>

#include "cap_harness.h"
#include "recordings.h"

#define PORT 7682

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

static void expect_rejected(harness *h, const char *needle1, const char *needle2)
{
    const char *args[] = {"--uri", h->dir, "--rate", "max", NULL};
    h_start(h, args);
    int rc = h_wait(h, 8.0);
    if (rc != 3 || !strstr(h->err_text, needle1) || (needle2 && !strstr(h->err_text, needle2)))
        fail_msg("exit %d, stderr: %s (wanted '%s' and '%s')", rc, h->err_text, needle1,
                 needle2 ? needle2 : "");
    assert_int_equal(h->depth_count, 0);
}

static void test_damaged_recordings_are_rejected_by_name(void **state)
{
    harness *h = *state;
    h_write_dump(h, 4, 30.0);
    rec_index idx;
    rec_report why;
    assert_int_equal(rec_index_read(h->dir, &idx, &why), REC_OK);
    char path[512];
    /* Truncated frame 1. */
    snprintf(path, sizeof path, "%s/%s", h->dir, idx.frames[1].name);
    assert_int_equal(truncate(path, 1000), 0);
    expect_rejected(h, idx.frames[1].name, "frame 1");
    assert_non_null(strstr(h->err_text, "REC_ERR_TRUNCATED"));
    /* Missing frame 1. */
    assert_int_equal(unlink(path), 0);
    expect_rejected(h, idx.frames[1].name, "frame 1");
    assert_non_null(strstr(h->err_text, "REC_ERR_NO_FRAME"));
    /* No INDEX.txt. */
    snprintf(path, sizeof path, "%s/INDEX.txt", h->dir);
    assert_int_equal(unlink(path), 0);
    expect_rejected(h, "INDEX.txt", "REC_ERR_NO_INDEX");
    /* No directory at all. */
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", h->dir);
    assert_int_equal(system(cmd), 0);
    expect_rejected(h, h->dir, "REC_ERR_NO_DIR");
    rec_index_free(&idx);
    assert_int_equal(dir_entries(tmpdir), 0);
}

static void test_openni2_dummy_device_publishes_frames(void **state)
{
    harness *h = *state;
    /* OpenNI2's Dummy driver: a live device path (oniDeviceOpen, stream, oniWaitForAnyStream)
     * without hardware, 320x240 millimetre frames at 30 fps. */
    setenv("LSAN_OPTIONS", "suppressions=" TRYON_OPENNI2_LSAN_SUPP, 1);
    const char *args[] = {"--source", "openni2", "--uri", "Dummy", "--frames", "4", NULL};
    h_start(h, args);
    int rc = h_wait(h, 8.0);
    unsetenv("LSAN_OPTIONS");
    if (rc != 0)
        fail_msg("tryon-capture exit %d: %s", rc, h->err_text);
    assert_int_equal(h->depth_count, 4);
    for (int k = 0; k < 4; k++) {
        assert_int_equal(h->depth[k].seq, k);
        assert_string_equal(h->depth[k].source, "openni2");
        assert_int_equal(h->depth[k].width, 320);
        assert_int_equal(h->depth[k].height, 240);
        assert_true(h->depth[k].fx > 100.0f && h->depth[k].fx < 1000.0f);
        if (k > 0)
            assert_true(h->depth[k].device_timestamp > h->depth[k - 1].device_timestamp);
    }
    assert_int_equal(h->timing_count, 4);
}

static void test_missing_oni_file_is_named(void **state)
{
    harness *h = *state;
    const char *args[] = {"--source", "openni2", "--uri", "/nonexistent/tryon.oni", NULL};
    h_start(h, args);
    int rc = h_wait(h, 8.0);
    if (rc != 3 || !strstr(h->err_text, "/nonexistent/tryon.oni"))
        fail_msg("exit %d, stderr: %s", rc, h->err_text);
}

static void test_unknown_source_and_bad_rate_are_usage_errors(void **state)
{
    harness *h = *state;
    const char *a1[] = {"--source", "kinect9", NULL};
    h_start(h, a1);
    assert_int_equal(h_wait(h, 5.0), 2);
    assert_non_null(strstr(h->err_text, "kinect9"));
    const char *a2[] = {"--rate", "fast", NULL};
    h_start(h, a2);
    assert_int_equal(h_wait(h, 5.0), 2);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(test_damaged_recordings_are_rejected_by_name),
        T(test_openni2_dummy_device_publishes_frames),
        T(test_missing_oni_file_is_named),
        T(test_unknown_source_and_bad_rate_are_usage_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
