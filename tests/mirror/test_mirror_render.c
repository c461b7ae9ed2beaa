/* tryon-mirror draws what the geometry says: the garment where it is, hidden by the arm in front
 * of it, the person around it, nothing elsewhere; headless (EGL surfaceless) and in a window
 * under Xvfb give the same picture. The reference comes from the scene's geometry
 * (mirror_scene.c), not from a saved output. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bus.h"
#include "mirror.h"
#include "mirror_scene.h"
#include "support.h"

/* Edges are where pixel rounding (the depth image is sampled at the nearest pixel, the garment's
 * edges rasterised) and the person's normals may differ from the exact geometry: pixels within
 * this many of a change in the expected picture are not judged. */
#define EDGE_BAND_PX 2
/* Of the judged pixels, at least this fraction must show the expected class. */
#define MIN_AGREEMENT 0.995

static int near_edge(int px, int py)
{
    int e = ms_expected(px, py);
    for (int dy = -EDGE_BAND_PX; dy <= EDGE_BAND_PX; dy++)
        for (int dx = -EDGE_BAND_PX; dx <= EDGE_BAND_PX; dx++) {
            int x = px + dx, y = py + dy;
            if (x >= 0 && y >= 0 && x < MS_W && y < MS_H && ms_expected(x, y) != e)
                return 1;
        }
    return 0;
}

static uint8_t *render(const char *dir, int windowed)
{
    char out[300], png[320];
    snprintf(out, sizeof out, "%s/run.txt", dir);
    char *headless[] = {TRYON_MIRROR_EXE, "--headless", "--out",        (char *)dir,
                        "--frames",       "1",          "--no-overlay", NULL};
    char *window[] = {"/usr/bin/xvfb-run",
                      "-a",
                      "-s",
                      "-screen 0 800x600x24",
                      TRYON_MIRROR_EXE,
                      "--out",
                      (char *)dir,
                      "--frames",
                      "1",
                      "--no-overlay",
                      NULL};
    /* The window's teardown (SDL2 over D-Bus, Mesa's EGL unloading its driver) leaves memory
     * LeakSanitizer cannot even name: leaks are checked on the headless run, which runs the same
     * code of ours, and not on the windowed one. */
    char *window_env[] = {"LSAN_OPTIONS=detect_leaks=0", NULL};
    pid_t pid = ts_spawn_out(windowed ? window : headless, windowed ? window_env : NULL, out);
    assert_true(pid > 0);
    int st = ms_serve_until_exit(pid, 30000);
    if (st != 0) {
        char *log = ts_read_file(out);
        fail_msg("tryon-mirror exited with %d:\n%s", st, log ? log : "");
    }
    char *log = ts_read_file(out);
    assert_non_null(log);
    /* llvmpipe's shaders compiled by a warm-up draw before the bus is listened to, not by the
     * first frame a person waits for (mirror.md, "The window under Xvfb") */
    const char *warm = strstr(log, "warmed up: a first draw"),
               *listening = strstr(log, "listening");
    assert_non_null(warm);
    assert_non_null(listening);
    assert_true(warm < listening);
    if (windowed) { /* the window is the picture's size: drawn into it, not copied (mirror.md) */
        assert_non_null(strstr(log, "drawing straight into the window's back buffer"));
        /* and shown through shared memory, not sent over the X socket a frame at a time */
        assert_non_null(strstr(log, "the picture in memory shared with the X server"));
    }
    free(log);
    snprintf(png, sizeof png, "%s/frame_00000.png", dir);
    int w = 0, h = 0;
    uint8_t *rgb = mirror_png_read(png, &w, &h);
    assert_non_null(rgb);
    assert_int_equal(w, MS_W);
    assert_int_equal(h, MS_H);
    return rgb;
}

static void test_headless_frame_matches_the_geometry(void **state)
{
    (void)state;
    char dir[256];
    assert_int_equal(ts_temp_dir(dir, sizeof dir, "mirror"), 0);
    uint8_t *rgb = render(dir, 0);
    long judged = 0, agree = 0, garment = 0, occluded = 0, occluded_person = 0;
    for (int y = 0; y < MS_H; y++)
        for (int x = 0; x < MS_W; x++) {
            if (near_edge(x, y))
                continue;
            int want = ms_expected(x, y), got = ms_classify(&rgb[(y * MS_W + x) * 3]);
            judged++;
            agree += want == got;
            garment += want == MS_GARMENT && got == MS_GARMENT;
            /* the arm's band across the garment: the garment is behind it */
            int under_arm = want == MS_PERSON && y > 200 && y < 236 && x > 270 && x < 370;
            occluded += under_arm;
            occluded_person += under_arm && got == MS_PERSON;
        }
    double fraction = (double)agree / (double)judged;
    print_message("judged %ld pixels, %.4f agree; %ld garment; %ld/%ld arm pixels show the arm\n",
                  judged, fraction, garment, occluded_person, occluded);
    assert_true(fraction >= MIN_AGREEMENT);
    assert_true(garment > 10000); /* 110 x 166 pixels, less the arm and the edge bands */
    assert_true(occluded > 1000);
    assert_true(occluded_person >= occluded * 99 / 100);
    free(rgb);
    ts_remove_dir(dir);
}

/* Pixels whose channels differ by more than this count as different; at most MAX_DIFFERENT of
 * them: the same renderer on the same Mesa, so only a driver's rounding may differ. */
#define CHANNEL_TOLERANCE 8
#define MAX_DIFFERENT     0.001

static void test_window_under_xvfb_matches_headless(void **state)
{
    (void)state;
    if (access("/usr/bin/xvfb-run", X_OK) != 0)
        skip();
    char d1[256], d2[256];
    assert_int_equal(ts_temp_dir(d1, sizeof d1, "mirror-headless"), 0);
    assert_int_equal(ts_temp_dir(d2, sizeof d2, "mirror-window"), 0);
    uint8_t *a = render(d1, 0), *b = render(d2, 1);
    long different = 0;
    for (long i = 0; i < (long)MS_W * MS_H; i++)
        for (int k = 0; k < 3; k++)
            if (abs(a[i * 3 + k] - b[i * 3 + k]) > CHANNEL_TOLERANCE) {
                different++;
                break;
            }
    print_message("%ld of %d pixels differ\n", different, MS_W * MS_H);
    assert_true((double)different <= MAX_DIFFERENT * MS_W * MS_H);
    free(a);
    free(b);
    ts_remove_dir(d1);
    ts_remove_dir(d2);
}

static int setup(void **state)
{
    (void)state;
    char url[128], prefix[32];
    ts_private_bus(url, sizeof url, prefix, sizeof prefix);
    return 0;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_headless_frame_matches_the_geometry),
        cmocka_unit_test(test_window_under_xvfb_matches_headless),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
