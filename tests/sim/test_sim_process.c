/* tryon-sim as its own process, fed BODY over udpm on loopback (a private port and channel
 * prefix): it publishes CLOTH and TIMING per frame, survives a malformed BODY (the bus drops it)
 * and a body the sim rejects (it skips the frame), and exits cleanly on SIGTERM. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bus.h"
#include "scene.h"
#include "support.h"

typedef struct counts {
    int cloth, timing, cloth_with_tris, nv, last_seq;
} counts;

static void on_cloth(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_cloth_t *c = m;
    counts *n = user;
    n->cloth++;
    n->cloth_with_tris += c->num_triangle_indices > 0;
    n->nv = c->num_vertex_coords / 3;
    n->last_seq = c->seq;
}

static void on_timing(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_timing_t *t = m;
    if (strcmp(t->stage, "sim") == 0)
        ((counts *)user)->timing++;
}

static void send_body(lcm_t *lcm, const char *ch, sim_scene *sc, int seq, int degenerate)
{
    const float *xyz, *joints;
    const int32_t *tris;
    int nv, nt;
    sim_scene_eval(sc, seq / 30.0, &xyz, &nv, &tris, &nt, &joints);
    int32_t *t = malloc((size_t)nt * 3 * sizeof *t);
    assert_non_null(t);
    memcpy(t, tris, (size_t)nt * 3 * sizeof *t);
    if (degenerate)
        t[1] = t[0]; /* valid on the wire, refused by the sim */
    tryon_body_t b = {.utime_capture = bus_now_wall_us(),
                      .seq = seq,
                      .state = 1,
                      .topology_id = 1,
                      .num_vertex_coords = nv * 3,
                      .vertices = (float *)xyz,
                      .num_triangle_indices = nt * 3,
                      .triangles = t};
    bus_reject why;
    assert_int_equal(bus_publish(lcm, ch, BUS_BODY, &b, &why), BUS_OK);
    free(t);
}

static void test_sim_process_publishes_cloth_and_survives_bad_bodies(void **state)
{
    (void)state;
    char url[128], prefix[32], err[512], ch_body[BUS_CHANNEL_MAX], ch_cloth[BUS_CHANNEL_MAX];
    char ch_timing[BUS_CHANNEL_MAX], out[256];
    ts_private_bus(url, sizeof url, prefix, sizeof prefix);
    const char *exe = getenv("TRYON_SIM_EXE");
    assert_non_null(exe);
    snprintf(out, sizeof out, "test_sim_process_%s.log", prefix);
    char *argv[] = {(char *)exe, "--backend", "c", "--verts", "400", "--queue", "all", NULL};
    pid_t pid = ts_spawn_out(argv, NULL, out);
    assert_true(pid > 0);

    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    if (!lcm)
        fail_msg("%s", err);
    bus_channel(BUS_CHANNEL_BODY, ch_body, sizeof ch_body);
    bus_channel(BUS_CHANNEL_CLOTH, ch_cloth, sizeof ch_cloth);
    bus_channel(BUS_CHANNEL_TIMING, ch_timing, sizeof ch_timing);
    counts n = {0};
    bus_sub *sc_cloth = bus_subscribe(lcm, ch_cloth, BUS_CLOTH, on_cloth, &n);
    bus_sub *sc_timing = bus_subscribe(lcm, ch_timing, BUS_TIMING, on_timing, &n);
    float c[3] = {0.0f, 1.2f, 0.0f};
    sim_scene *sc = sim_scene_sphere(0.15f, c, 300);

    /* until the process listens, bodies are lost: resend until the first CLOTH */
    int seq = 0;
    for (int tries = 0; n.cloth == 0 && tries < 100; tries++) {
        send_body(lcm, ch_body, sc, seq++, 0);
        lcm_handle_timeout(lcm, 100);
    }
    assert_true(n.cloth > 0);
    for (int k = 0; k < 6; k++) /* let the bodies already queued come back */
        lcm_handle_timeout(lcm, 50);
    int before = n.cloth;
    /* a malformed BODY: garbage bytes on the channel */
    const char junk[] = "this is not a body_t";
    lcm_publish(lcm, ch_body, junk, sizeof junk);
    /* a body the sim refuses: a triangle repeats a vertex */
    send_body(lcm, ch_body, sc, seq++, 1);
    for (int k = 0; k < 20 && n.cloth < before + 3; k++) {
        send_body(lcm, ch_body, sc, seq++, 0);
        lcm_handle_timeout(lcm, 100);
    }
    for (int k = 0; k < 5; k++) /* the last TIMING follows its CLOTH */
        lcm_handle_timeout(lcm, 50);
    int status = ts_stop(pid, SIGTERM, 10000); /* a clean exit on SIGTERM */
    char *log = ts_read_file(out);
    printf("# cloth %d (first %d), with triangles %d, timing %d, %d vertices; log:\n%s", n.cloth,
           before, n.cloth_with_tris, n.timing, n.nv, log ? log : "(none)");
    assert_int_equal(status, 0);
    assert_true(n.cloth >= before + 3); /* still serving after the bad bodies */
    assert_true(n.timing >= before + 3);
    assert_true(n.cloth_with_tris >= 1);
    assert_non_null(log);
    assert_non_null(strstr(log, "SIM_ERR_DEGENERATE"));
    assert_non_null(strstr(log, "1 BODY messages dropped"));
    free(log);
    remove(out);
    sim_scene_destroy(sc);
    bus_unsubscribe(lcm, sc_cloth);
    bus_unsubscribe(lcm, sc_timing);
    lcm_destroy(lcm);
}

/* --queue latest (the default): a burst of bodies faster than the sim is collapsed to the
 * newest, so the cloth published last is the last body's and latency does not pile up. */
static void test_sim_process_latest_body_wins(void **state)
{
    (void)state;
    char url[128], prefix[32], err[512], ch_body[BUS_CHANNEL_MAX], ch_cloth[BUS_CHANNEL_MAX];
    char out[256];
    ts_private_bus(url, sizeof url, prefix, sizeof prefix);
    snprintf(out, sizeof out, "test_sim_process_latest_%s.log", prefix);
    const char *exe = getenv("TRYON_SIM_EXE");
    assert_non_null(exe);
    /* a heavy enough garment that one frame outlasts the burst */
    char *argv[] = {(char *)exe, "--backend", "c", "--verts", "6000", "--iterations", "60", NULL};
    pid_t pid = ts_spawn_out(argv, NULL, out);
    assert_true(pid > 0);
    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    if (!lcm)
        fail_msg("%s", err);
    bus_channel(BUS_CHANNEL_BODY, ch_body, sizeof ch_body);
    bus_channel(BUS_CHANNEL_CLOTH, ch_cloth, sizeof ch_cloth);
    counts n = {.last_seq = -1};
    bus_sub *sc_cloth = bus_subscribe(lcm, ch_cloth, BUS_CLOTH, on_cloth, &n);
    float c[3] = {0.0f, 1.2f, 0.0f};
    sim_scene *sc = sim_scene_sphere(0.15f, c, 300);
    int seq = 0;
    for (int tries = 0; n.cloth == 0 && tries < 100; tries++) {
        send_body(lcm, ch_body, sc, seq++, 0);
        lcm_handle_timeout(lcm, 100);
    }
    assert_true(n.cloth > 0);
    for (int k = 0; k < 20; k++) /* the bodies queued while the garment was made */
        lcm_handle_timeout(lcm, 50);
    int before = n.cloth;
    const int burst = 30;
    for (int k = 0; k < burst; k++)
        send_body(lcm, ch_body, sc, seq++, 0);
    for (int k = 0; k < 300 && n.last_seq != seq - 1; k++)
        lcm_handle_timeout(lcm, 100);
    int status = ts_stop(pid, SIGTERM, 10000);
    char *log = ts_read_file(out);
    printf("# burst of %d bodies: %d cloth, last seq %d of %d; log:\n%s", burst, n.cloth - before,
           n.last_seq, seq - 1, log ? log : "(none)");
    assert_int_equal(status, 0);
    assert_int_equal(n.last_seq, seq - 1); /* the newest body was simulated */
    assert_true(n.cloth - before < burst); /* and not every one before it */
    assert_non_null(log);
    assert_null(strstr(log, " 0 superseded"));
    free(log);
    remove(out);
    sim_scene_destroy(sc);
    bus_unsubscribe(lcm, sc_cloth);
    lcm_destroy(lcm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_process_publishes_cloth_and_survives_bad_bodies),
        cmocka_unit_test(test_sim_process_latest_body_wins),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
