/* tryon-capture as a separate process stops cleanly on SIGINT and SIGTERM: exit 0, nothing
 * more published, fakenect staging removed. Real LCM on loopback. */
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

#define PORT 7683

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

static void stops_cleanly_on(harness *h, int sig)
{
    h_write_dump(h, 20, 30.0);
    const char *args[] = {"--uri", h->dir, "--rate", "5", NULL}; /* 4 s in all */
    h_start(h, args);
    assert_true(h_wait_frames(h, 2, 5.0) >= 2);
    pid_t pid = h->child;
    assert_int_equal(kill(pid, sig), 0);
    int64_t t0 = bus_now_mono_us();
    int rc = h_wait(h, 3.0);
    if (rc != 0)
        fail_msg("exit %d after signal %d: %s", rc, sig, h->err_text);
    assert_true(bus_now_mono_us() - t0 < 1500000); /* not the 3.6 s left to play */
    assert_true(h->depth_count < 20);
    assert_non_null(strstr(h->err_text, "stopped by signal"));
    assert_int_equal(dir_entries(tmpdir), 0);
}

static void test_sigint_stops_cleanly(void **state)
{
    stops_cleanly_on(*state, SIGINT);
}

static void test_sigterm_stops_cleanly(void **state)
{
    stops_cleanly_on(*state, SIGTERM);
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(test_sigint_stops_cleanly),
        T(test_sigterm_stops_cleanly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
