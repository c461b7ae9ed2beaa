/* The pipeline end to end, every stage its own process on a private udpm port and channel
 * prefix: tryon-capture replays a recording through libfreenect's fakenect (the live code path),
 * tryon-bodyfit fits the body to every DEPTH frame, tryon-sim dresses the fitted body (no
 * garment vertex more than 1 mm inside it: the sim's penetration count is against the body it
 * was given). The test listens as tryon-mirror and tryon-profile
 * would: one CLOTH per depth frame, in order, carrying its frame's capture time, finite, on the
 * body and never inside it, and a TIMING from every stage for every frame. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cmocka.h>

#include "bus.h"
#include "support.h"

#define E2E_FRAMES     8      /* the fast_swing_s1 sample: wrist at 3.9 m/s */
#define E2E_MAX_FRAMES 64     /* what the listener keeps per stream */
#define E2E_TIMEOUT_MS 120000 /* sanitizer builds simulate a frame in about a second */

enum { STAGE_CAPTURE, STAGE_BODYFIT, STAGE_SIM, STAGE_COUNT };
static const char *const stage_names[STAGE_COUNT] = {"capture", "bodyfit", "sim"};

typedef struct listener {
    int depth, body, cloth;
    int64_t depth_utime[E2E_MAX_FRAMES];
    int cloth_seq[E2E_MAX_FRAMES];
    int64_t cloth_utime[E2E_MAX_FRAMES];
    int timing[STAGE_COUNT][E2E_MAX_FRAMES];
    float body_lo[3], body_hi[3]; /* bounding box of the last body */
    int cloth_nv, cloth_not_finite, cloth_off_body, cloth_penetrating, cloth_diverged;
    float worst_strain;
} listener;

static void on_depth(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_depth_frame_t *f = m;
    listener *l = user;
    if (f->seq >= 0 && f->seq < E2E_MAX_FRAMES)
        l->depth_utime[f->seq] = f->utime_capture;
    l->depth++;
}

static void on_body(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_body_t *b = m;
    listener *l = user;
    for (int d = 0; d < 3; d++) {
        l->body_lo[d] = INFINITY;
        l->body_hi[d] = -INFINITY;
    }
    for (int i = 0; i < b->num_vertex_coords; i++) {
        l->body_lo[i % 3] = fminf(l->body_lo[i % 3], b->vertices[i]);
        l->body_hi[i % 3] = fmaxf(l->body_hi[i % 3], b->vertices[i]);
    }
    l->body++;
}

static void on_cloth(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_cloth_t *c = m;
    listener *l = user;
    if (l->cloth < E2E_MAX_FRAMES) {
        l->cloth_seq[l->cloth] = c->seq;
        l->cloth_utime[l->cloth] = c->utime_capture;
    }
    l->cloth++;
    l->cloth_nv = c->num_vertex_coords / 3;
    /* the garment hangs on the body: no vertex more than 10 cm outside the body's box (the
     * body of the same seq arrived before this cloth: the sim needs it to make the cloth) */
    for (int i = 0; i < c->num_vertex_coords; i++) {
        float x = c->vertices[i];
        if (!isfinite(x))
            l->cloth_not_finite++;
        else if (x < l->body_lo[i % 3] - 0.1f || x > l->body_hi[i % 3] + 0.1f)
            l->cloth_off_body++;
    }
    l->cloth_penetrating += c->penetrating;
    l->cloth_diverged += c->state == TRYON_CLOTH_T_STATE_DIVERGED;
    l->worst_strain = fmaxf(l->worst_strain, c->max_strain);
}

static void on_timing(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_timing_t *t = m;
    listener *l = user;
    for (int s = 0; s < STAGE_COUNT; s++)
        if (strcmp(t->stage, stage_names[s]) == 0 && t->seq >= 0 && t->seq < E2E_MAX_FRAMES)
            l->timing[s][t->seq]++;
}

/* Waits until a child's log says it listens (its subscription is made before it says so). */
static int wait_for_line(const char *log_path, const char *text, int timeout_ms)
{
    for (int waited = 0; waited < timeout_ms; waited += 50) {
        char *log = ts_read_file(log_path);
        int found = log && strstr(log, text);
        free(log);
        if (found)
            return 1;
        nanosleep(&(struct timespec){.tv_nsec = 50 * 1000 * 1000}, NULL);
    }
    return 0;
}

static void print_log(const char *name, const char *path)
{
    char *log = ts_read_file(path);
    printf("# %s log:\n%s", name, log ? log : "(none)\n");
    free(log);
}

static void test_e2e_capture_bodyfit_sim(void **state)
{
    (void)state;
    char url[128], prefix[32], err[512], dir[256], logs[3][300], frames[16];
    ts_private_bus(url, sizeof url, prefix, sizeof prefix);
    assert_int_equal(ts_temp_dir(dir, sizeof dir, "e2e"), 0);
    for (int s = 0; s < STAGE_COUNT; s++)
        snprintf(logs[s], sizeof logs[s], "%s/%s.log", dir, stage_names[s]);
    snprintf(frames, sizeof frames, "%d", E2E_FRAMES);
    const char *recording = TRYON_SAMPLES_DIR "/fast_swing_s1";

    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    if (!lcm)
        fail_msg("%s", err);
    listener l = {0};
    const struct {
        const char *base;
        bus_type type;
        bus_handler fn;
    } subs[] = {{BUS_CHANNEL_DEPTH, BUS_DEPTH_FRAME, on_depth},
                {BUS_CHANNEL_BODY, BUS_BODY, on_body},
                {BUS_CHANNEL_CLOTH, BUS_CLOTH, on_cloth},
                {BUS_CHANNEL_TIMING, BUS_TIMING, on_timing}};
    bus_sub *sub[4];
    for (int i = 0; i < 4; i++) {
        char ch[BUS_CHANNEL_MAX];
        bus_channel(subs[i].base, ch, sizeof ch);
        sub[i] = bus_subscribe(lcm, ch, subs[i].type, subs[i].fn, &l);
        assert_non_null(sub[i]);
    }

    /* downstream first: each says when it listens, then the camera starts */
    char *sim_argv[] = {TRYON_SIM_EXE, "--backend", "c",       "--verts", "2000",
                        "--frames",    frames,      "--queue", "all",     NULL};
    /* --queue all: every frame fitted even where a sanitizer build fits slower than 30 fps */
    char *fit_argv[] = {TRYON_BODYFIT_EXE, "--frames", frames, "--queue", "all", NULL};
    char *capture_argv[] = {TRYON_CAPTURE_EXE, "--source", "freenect", "--uri", (char *)recording,
                            "--rate",          "realtime", "--frames", frames,  NULL};
    pid_t sim = ts_spawn_out(sim_argv, NULL, logs[STAGE_SIM]);
    pid_t fit = ts_spawn_out(fit_argv, NULL, logs[STAGE_BODYFIT]);
    assert_true(sim > 0 && fit > 0);
    int ready = wait_for_line(logs[STAGE_SIM], "waiting for", 10000) &&
                wait_for_line(logs[STAGE_BODYFIT], "listening on", 10000);
    pid_t capture = ready ? ts_spawn_out(capture_argv, NULL, logs[STAGE_CAPTURE]) : -1;

    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (int waited = 0; capture > 0 && l.cloth < E2E_FRAMES && waited < E2E_TIMEOUT_MS;) {
        lcm_handle_timeout(lcm, 100);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        waited = (int)((t1.tv_sec - t0.tv_sec) * 1000 + (t1.tv_nsec - t0.tv_nsec) / 1000000);
    }
    for (int k = 0; k < 10; k++) /* the last TIMING follows its CLOTH */
        lcm_handle_timeout(lcm, 50);
    /* each stage exits 0 by itself after its frames */
    int rc_capture = capture > 0 ? ts_wait(capture, 20000) : -2;
    int rc_fit = ts_wait(fit, 20000);
    int rc_sim = ts_wait(sim, 20000);
    for (int s = 0; s < STAGE_COUNT; s++)
        print_log(stage_names[s], logs[s]);
    printf("# depth %d, body %d, cloth %d (%d vertices), worst max strain %.1f %%\n", l.depth,
           l.body, l.cloth, l.cloth_nv, 100.0f * l.worst_strain);

    assert_true(ready);
    assert_int_equal(rc_capture, 0);
    assert_int_equal(rc_fit, 0);
    assert_int_equal(rc_sim, 0);
    assert_int_equal(l.depth, E2E_FRAMES);
    assert_int_equal(l.body, E2E_FRAMES);
    assert_int_equal(l.cloth, E2E_FRAMES);
    for (int k = 0; k < E2E_FRAMES; k++) {
        assert_int_equal(l.cloth_seq[k], k); /* every frame, in order */
        assert_true(l.cloth_utime[k] == l.depth_utime[k] && l.depth_utime[k] > 0);
        for (int s = 0; s < STAGE_COUNT; s++)
            assert_int_equal(l.timing[s][k], 1);
    }
    assert_true(l.cloth_nv > 1000);
    assert_int_equal(l.cloth_not_finite, 0);
    assert_int_equal(l.cloth_off_body, 0);
    assert_int_equal(l.cloth_penetrating, 0); /* fast swing included */
    assert_int_equal(l.cloth_diverged, 0);

    for (int i = 0; i < 4; i++)
        bus_unsubscribe(lcm, sub[i]);
    lcm_destroy(lcm);
    ts_remove_dir(dir);
}

/* tryon-truth on a directory that is not a recording, or whose ground-truth list is damaged:
 * a clear error naming the file and line, exit 1, nothing published. */
static void test_e2e_truth_rejects_bad_recordings(void **state)
{
    (void)state;
    char url[128], prefix[32], dir[256], path[400], log_path[400];
    ts_private_bus(url, sizeof url, prefix, sizeof prefix);
    assert_int_equal(ts_temp_dir(dir, sizeof dir, "e2e_truth"), 0);
    snprintf(log_path, sizeof log_path, "%s/truth.log", dir);
    const struct {
        const char *groundtruth; /* NULL: no file */
        const char *expect;
    } cases[] = {
        {NULL, "groundtruth.txt"},
        {"# frame record_time_s depth_file ground_truth_file\n", "lists no frame"},
        {"# comment\n1 1.0 d-1.pgm gt-000001.txt\n", "line 2: expected frame 0"},
        {"0 1.0 d-0.pgm gt-000000.txt\n", "gt-000000.txt"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        snprintf(path, sizeof path, "%s/groundtruth.txt", dir);
        remove(path);
        if (cases[c].groundtruth) {
            FILE *f = fopen(path, "w");
            assert_non_null(f);
            fputs(cases[c].groundtruth, f);
            fclose(f);
        }
        char *argv[] = {TRYON_TRUTH_EXE, "--recording", dir, NULL};
        pid_t pid = ts_spawn_out(argv, NULL, log_path);
        assert_true(pid > 0);
        int rc = ts_wait(pid, 20000);
        char *log = ts_read_file(log_path);
        printf("# case %zu: exit %d: %s", c, rc, log ? log : "(no output)\n");
        assert_int_equal(rc, 1);
        assert_non_null(log);
        assert_non_null(strstr(log, cases[c].expect));
        free(log);
    }
    ts_remove_dir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_e2e_capture_bodyfit_sim),
        cmocka_unit_test(test_e2e_truth_rejects_bad_recordings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
