/* tryon-sim as its own process, fed BODY over udpm on loopback (a private port and channel
 * prefix): it publishes CLOTH and TIMING per frame, survives a malformed BODY (the bus drops it)
 * and a body the sim rejects (it skips the frame), collapses a burst to the newest body, makes a
 * garment made on an INIT body again once the body is TRACKING, and exits cleanly on SIGTERM. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bodyfit.h"
#include "bus.h"
#include "scene.h"
#include "sim.h"
#include "support.h"

typedef struct counts {
    int cloth, timing, cloth_with_tris, nv, last_seq, before_last_seq;
    int topology, garments; /* the last CLOTH's topology_id, and how many ids were seen */
    int inside;             /* CLOTH with a vertex > 1 mm inside the body */
} counts;

static void on_cloth(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_cloth_t *c = m;
    counts *n = user;
    n->cloth++;
    n->inside += c->penetrating > 0;
    n->cloth_with_tris += c->num_triangle_indices > 0;
    n->nv = c->num_vertex_coords / 3;
    n->before_last_seq = n->last_seq;
    n->last_seq = c->seq;
    n->garments += c->topology_id != n->topology;
    n->topology = c->topology_id;
}

static void on_timing(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_timing_t *t = m;
    if (strcmp(t->stage, "sim") == 0)
        ((counts *)user)->timing++;
}

static int8_t body_state = TRYON_BODY_T_STATE_TRACKING; /* the state of the bodies sent */
static float body_shape[FIT_SHAPE_PARAMS];              /* their shape, when body_has_shape */
static int body_has_shape;

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
                      .state = body_state,
                      .num_shape = body_has_shape ? FIT_SHAPE_PARAMS : 0,
                      .shape = body_has_shape ? body_shape : NULL,
                      .topology_id = 1,
                      .num_vertex_coords = nv * 3,
                      .vertices = (float *)xyz,
                      .num_triangle_indices = nt * 3,
                      .triangles = t};
    bus_reject why;
    assert_int_equal(bus_publish(lcm, ch, BUS_BODY, &b, &why), BUS_OK);
    free(t);
}

/* One tryon-sim process on a private bus, and the test's end of that bus. */
typedef struct session {
    pid_t pid;
    char out[256];
    lcm_t *lcm;
    char ch_body[BUS_CHANNEL_MAX];
    bus_sub *subs[2];
    sim_scene *sc;
    counts n;
    int seq; /* next body's */
} session;

/* Starts tryon-sim with the options given (NULL-ended), then sends bodies until the first CLOTH
 * comes back (until the process listens, bodies are lost) and lets those queued come back. */
static void session_start(session *s, const char *tag, char *const options[])
{
    char url[128], prefix[32], err[512], ch[BUS_CHANNEL_MAX];
    memset(s, 0, sizeof *s);
    s->n.last_seq = -1;
    ts_private_bus(url, sizeof url, prefix, sizeof prefix);
    snprintf(s->out, sizeof s->out, "test_sim_process_%s_%s.log", tag, prefix);
    char *argv[16] = {getenv("TRYON_SIM_EXE")};
    assert_non_null(argv[0]);
    for (int i = 0; options[i] && i < 14; i++)
        argv[i + 1] = options[i];
    s->pid = ts_spawn_out(argv, NULL, s->out);
    assert_true(s->pid > 0);
    s->lcm = bus_open(NULL, err, sizeof err);
    if (!s->lcm)
        fail_msg("%s", err);
    bus_channel(BUS_CHANNEL_BODY, s->ch_body, sizeof s->ch_body);
    bus_channel(BUS_CHANNEL_CLOTH, ch, sizeof ch);
    s->subs[0] = bus_subscribe(s->lcm, ch, BUS_CLOTH, on_cloth, &s->n);
    bus_channel(BUS_CHANNEL_TIMING, ch, sizeof ch);
    s->subs[1] = bus_subscribe(s->lcm, ch, BUS_TIMING, on_timing, &s->n);
    float c[3] = {0.0f, 1.2f, 0.0f};
    s->sc = sim_scene_sphere(0.15f, c, 300);
    for (int tries = 0; s->n.cloth == 0 && tries < 100; tries++) {
        send_body(s->lcm, s->ch_body, s->sc, s->seq++, 0);
        lcm_handle_timeout(s->lcm, 100);
    }
    assert_true(s->n.cloth > 0);
    for (int k = 0; k < 20; k++) /* the bodies queued while the garment was made */
        lcm_handle_timeout(s->lcm, 50);
}

/* SIGTERM (a clean exit is asserted by the caller); returns the status and the process's log. */
static int session_stop(session *s, char **log)
{
    for (int k = 0; k < 5; k++) /* the last TIMING follows its CLOTH */
        lcm_handle_timeout(s->lcm, 50);
    int status = ts_stop(s->pid, SIGTERM, 10000);
    *log = ts_read_file(s->out);
    remove(s->out);
    sim_scene_destroy(s->sc);
    for (int i = 0; i < 2; i++)
        bus_unsubscribe(s->lcm, s->subs[i]);
    lcm_destroy(s->lcm);
    return status;
}

/* --queue all: every body is simulated, a malformed one (dropped by the bus), one the sim refuses
 * and an empty one (both skipped) are reported, and the process serves on. */
static void test_sim_process_publishes_cloth_and_survives_bad_bodies(void **state)
{
    (void)state;
    session s;
    session_start(&s, "bad",
                  (char *[]){"--backend", "c", "--verts", "400", "--queue", "all", NULL});
    int before = s.n.cloth;
    /* a malformed BODY: garbage bytes on the channel */
    const char junk[] = "this is not a body_t";
    lcm_publish(s.lcm, s.ch_body, junk, sizeof junk);
    /* a body the sim refuses: a triangle repeats a vertex */
    send_body(s.lcm, s.ch_body, s.sc, s.seq++, 1);
    /* no person: a valid body with no vertices (bodyfit's LOST state) */
    tryon_body_t empty = {.utime_capture = bus_now_wall_us(), .seq = s.seq++, .topology_id = 1};
    bus_reject why;
    assert_int_equal(bus_publish(s.lcm, s.ch_body, BUS_BODY, &empty, &why), BUS_OK);
    for (int k = 0; k < 20 && s.n.cloth < before + 3; k++) {
        send_body(s.lcm, s.ch_body, s.sc, s.seq++, 0);
        lcm_handle_timeout(s.lcm, 100);
    }
    char *log;
    int status = session_stop(&s, &log);
    printf("# cloth %d (first %d), with triangles %d, timing %d, %d vertices; log:\n%s", s.n.cloth,
           before, s.n.cloth_with_tris, s.n.timing, s.n.nv, log ? log : "(none)");
    assert_int_equal(status, 0);
    assert_true(s.n.cloth >= before + 3); /* still serving after the bad bodies */
    assert_true(s.n.timing >= before + 3);
    assert_true(s.n.cloth_with_tris >= 1);
    assert_non_null(log);
    /* its triangles differ from the live topology's: refused at intake (the list kept), or, if
     * the sim stood idle past the pin, no garment can be made on it */
    assert_true(strstr(log, "SIM_ERR_TOPOLOGY: topology 1 is live") ||
                strstr(log, "SIM_ERR_DEGENERATE"));
    assert_non_null(strstr(log, "has no vertices"));
    assert_non_null(strstr(log, "1 BODY messages dropped"));
    /* before it listened, the garment was made once on a stand-in body (--rehearse on) */
    const char *rehearsed = strstr(log, "rehearsed the garment on a stand-in body");
    assert_true(rehearsed && rehearsed < strstr(log, "waiting for"));
    /* the summary of the cloth published: as many frames inside as the CLOTH messages said (at
       least as many where a CLOTH went out after the test stopped listening) */
    const char *sum = strstr(log, "cloth as published: "), *sim = strstr(log, "frames simulated");
    int inside = -1, simulated = -1;
    assert_true(sum && sscanf(sum, "cloth as published: %d frames", &inside) == 1);
    while (sim && sim > log && sim[-1] == ' ')
        sim--;
    while (sim && sim > log && sim[-1] >= '0' && sim[-1] <= '9')
        sim--;
    assert_true(sim && sscanf(sim, "%d frames simulated", &simulated) == 1);
    if (simulated == s.n.cloth)
        assert_int_equal(inside, s.n.inside);
    else
        assert_true(inside >= s.n.inside && inside <= s.n.inside + simulated - s.n.cloth);
    free(log);
}

/* --backend auto (the default): the OpenCL backend on a GPU (or the device TRYON_CL_DEVICE names),
 * the C backend where the OpenCL device is a CPU (PoCL) or there is none, and the log says which
 * and why. */
static void test_sim_process_auto_backend(void **state)
{
    (void)state;
    char name[256];
    int gpu = sim_opencl_device(name, sizeof name);
    const char *want = getenv("TRYON_CL_DEVICE");
    int opencl = gpu == 1 || (want && *want && gpu >= 0);
    session s;
    session_start(&s, "auto", (char *[]){"--verts", "400", "--queue", "all", NULL});
    char *log;
    int status = session_stop(&s, &log);
    printf("# OpenCL device: %s (%d); log:\n%s", name, gpu, log ? log : "(none)");
    assert_int_equal(status, 0);
    assert_non_null(log);
    if (opencl) {
        assert_non_null(strstr(log, "tryon solver on"));
        assert_null(strstr(log, "C reference"));
    } else {
        assert_non_null(strstr(log, "tryon solver on C reference"));
        assert_non_null(strstr(log, gpu == 0 ? "is not a GPU" : "no OpenCL device"));
        assert_non_null(strstr(log, name));
    }
    free(log);
}

/* A burst of bodies faster than the sim is collapsed to the newest `depth` (--queue latest: 1;
 * the default: 2), simulated in order, so the cloth published last is the last body's and
 * latency does not pile up. */
static void burst_keeps_the_newest(int depth)
{
    session s;
    /* a heavy enough garment that one frame outlasts the burst */
    session_start(
        &s, "latest",
        depth == 1 ? (char *[]){"--backend", "c", "--verts", "6000", "--iterations", "60",
                                "--queue", "latest", NULL}
                   : (char *[]){"--backend", "c", "--verts", "6000", "--iterations", "60", NULL});
    int before = s.n.cloth;
    const int burst = 30;
    for (int k = 0; k < burst; k++)
        send_body(s.lcm, s.ch_body, s.sc, s.seq++, 0);
    for (int k = 0; k < 300 && s.n.last_seq != s.seq - 1; k++)
        lcm_handle_timeout(s.lcm, 100);
    char *log;
    int status = session_stop(&s, &log);
    printf("# burst of %d bodies: %d cloth, last seq %d of %d; log:\n%s", burst, s.n.cloth - before,
           s.n.last_seq, s.seq - 1, log ? log : "(none)");
    assert_int_equal(status, 0);
    assert_int_equal(s.n.last_seq, s.seq - 1); /* the newest body was simulated */
    assert_true(s.n.cloth - before < burst);   /* and not every one before it */
    if (depth == 2)                            /* the one before it waited, and went first */
        assert_int_equal(s.n.before_last_seq, s.seq - 2);
    else
        assert_true(s.n.before_last_seq < s.seq - 2);
    assert_non_null(log);
    assert_null(strstr(log, " 0 superseded"));
    free(log);
}

static void test_sim_process_latest_body_wins(void **state)
{
    (void)state;
    burst_keeps_the_newest(1);
    burst_keeps_the_newest(2);
}

/* --stats FILE: a header, then one CSV line of 14 fields per simulated body (as many as CLOTH
 * messages came back), iterations, milliseconds and CPU time positive, the budget (the default,
 * --frame-budget auto) positive, the body's motion -1 for the first body; with --settle-floor
 * 1000 mm every body after the first is counted as still (no settle round). */
static void test_sim_process_stats_file(void **state)
{
    (void)state;
    session s;
    const char *path = "test_sim_process_stats.csv"; /* in the test's build folder */
    session_start(&s, "stats",
                  (char *[]){"--backend", "c", "--verts", "400", "--queue", "all", "--stats",
                             (char *)path, "--settle-floor", "1000", "--rehearse", "off", NULL});
    for (int k = 0; k < 5; k++) {
        send_body(s.lcm, s.ch_body, s.sc, s.seq++, 0);
        lcm_handle_timeout(s.lcm, 100);
    }
    for (int k = 0; k < 50 && s.n.last_seq != s.seq - 1; k++)
        lcm_handle_timeout(s.lcm, 100);
    char *log;
    int status = session_stop(&s, &log);
    char *csv = ts_read_file(path);
    remove(path);
    printf("# %d cloth; stats:\n%s", s.n.cloth, csv ? csv : "(none)");
    assert_int_equal(status, 0);
    assert_non_null(csv);
    assert_true(strncmp(csv, "body,state,settle_rounds,", 25) == 0);
    int rows = 0;
    for (char *line = strchr(csv, '\n'); line && line[1]; line = strchr(line + 1, '\n')) {
        int body, st, settle, retries, strain_retries, iters, fp;
        float strain, pen, ms_it, ms, cpu, budget, moved;
        assert_int_equal(sscanf(line + 1, "%d,%d,%d,%d,%d,%d,%d,%f,%f,%f,%f,%f,%f,%f", &body, &st,
                                &settle, &retries, &strain_retries, &iters, &fp, &strain, &pen,
                                &ms_it, &ms, &cpu, &budget, &moved),
                         14);
        /* the first body's garment is published as made (sim_start): no iteration */
        assert_true((rows == 0 ? iters == 0 && settle == 0 : iters > 0) && ms > 0.0f &&
                    settle >= 0 && fp >= 0);
        assert_true(cpu > 0.0f && budget > 0.0f);
        assert_true(rows == 0 ? moved == -1.0f : moved >= 0.0f); /* the first has none before */
        rows++;
    }
    assert_int_equal(rows, s.n.cloth);
    free(csv);
    const char *said = strstr(log, " without settle rounds");
    int still = -1;
    if (said) {
        while (said > log && said[-1] >= '0' && said[-1] <= '9')
            said--;
        still = atoi(said);
    }
    assert_null(strstr(log, "rehearsed")); /* --rehearse off */
    free(log);
    assert_int_equal(still, rows - 1);
}

/* bodyfit publishes INIT while it estimates the shape: the garment made on such a body is made
 * again, once, on the first TRACKING body (a new topology id), not on later bodies, and once
 * more when INIT bodies come again (someone entering) and then TRACKING. */
static void test_sim_process_redress_when_tracking(void **state)
{
    (void)state;
    session s;
    body_state = TRYON_BODY_T_STATE_INIT;
    session_start(&s, "redress",
                  (char *[]){"--backend", "c", "--verts", "400", "--queue", "all", NULL});
    int init_garments = s.n.garments;
    /* INIT x3; TRACKING x4; someone enters again: INIT x2, TRACKING x2. Each phase's cloth is
     * awaited before its garments are counted. */
    static const int8_t I = TRYON_BODY_T_STATE_INIT, T = TRYON_BODY_T_STATE_TRACKING;
    static const int8_t phases[3][4] = {{I, I, I, -1}, {T, T, T, T}, {I, I, T, T}};
    int garments[3];
    for (int p = 0; p < 3; p++) {
        for (int k = 0; k < 4 && phases[p][k] >= 0; k++) {
            body_state = phases[p][k];
            send_body(s.lcm, s.ch_body, s.sc, s.seq++, 0);
            lcm_handle_timeout(s.lcm, 50);
        }
        for (int k = 0; k < 100 && s.n.last_seq != s.seq - 1; k++)
            lcm_handle_timeout(s.lcm, 100);
        garments[p] = s.n.garments;
    }
    body_state = TRYON_BODY_T_STATE_TRACKING;
    char *log;
    int status = session_stop(&s, &log);
    printf("# garments: %d after the first cloth, then %d (INIT), %d (TRACKING), %d (INIT, "
           "TRACKING); log:\n%s",
           init_garments, garments[0], garments[1], garments[2], log ? log : "(none)");
    const char *said = log ? strstr(log, "init -> tracking") : NULL;
    const char *said2 = said ? strstr(said + 1, "init -> tracking") : NULL;
    int said_thrice = said2 && strstr(said2 + 1, "init -> tracking");
    free(log);
    assert_int_equal(status, 0);
    assert_int_equal(s.n.last_seq, s.seq - 1);
    assert_int_equal(init_garments, 1);
    assert_int_equal(garments[0], 1); /* INIT bodies are dressed, not dressed again */
    assert_int_equal(garments[1], 2); /* once, not on every TRACKING body */
    assert_int_equal(garments[2], 3);
    assert_non_null(said2);
    assert_false(said_thrice);
}

/* Bodies with a shape: INIT then TRACKING remakes the garment only where the shape moved since
 * it was made. A doubt (bodyfit publishes INIT and holds the shape) keeps the garment; the shape
 * settling after someone enters, or someone else entering, makes it again. */
static void test_sim_process_doubt_keeps_garment(void **state)
{
    (void)state;
    session s;
    body_has_shape = 1;
    body_state = TRYON_BODY_T_STATE_INIT;
    for (int j = 0; j < FIT_SHAPE_PARAMS; j++) /* the first body (the garment's): entering */
        body_shape[j] = 0.31f;
    session_start(&s, "doubt",
                  (char *[]){"--backend", "c", "--verts", "400", "--queue", "all", NULL});
    static const int8_t I = TRYON_BODY_T_STATE_INIT, T = TRYON_BODY_T_STATE_TRACKING;
    /* entering (shape 0.31 m while estimated, 0.32 once settled: 10 mm, over the 5 mm a garment
     * made on a shape still estimated keeps); a doubt with the shape held; someone else (0.36); a
     * doubt whose shape moves by 10 mm, less than the 15 mm a garment on a settled shape keeps */
    static const int8_t phases[4][4] = {{I, I, T, T}, {I, I, T, T}, {I, I, T, T}, {I, T, T, -1}};
    static const float first[4] = {0.31f, 0.32f, 0.36f, 0.37f},
                       settled[4] = {0.32f, 0.32f, 0.36f, 0.37f};
    int garments[4];
    for (int p = 0; p < 4; p++) {
        for (int k = 0; k < 4 && phases[p][k] >= 0; k++) {
            body_state = phases[p][k];
            for (int j = 0; j < FIT_SHAPE_PARAMS; j++)
                body_shape[j] = body_state == I ? first[p] : settled[p];
            send_body(s.lcm, s.ch_body, s.sc, s.seq++, 0);
            lcm_handle_timeout(s.lcm, 50);
        }
        for (int k = 0; k < 100 && s.n.last_seq != s.seq - 1; k++)
            lcm_handle_timeout(s.lcm, 100);
        garments[p] = s.n.garments;
    }
    body_has_shape = 0;
    body_state = TRYON_BODY_T_STATE_TRACKING;
    char *log;
    int status = session_stop(&s, &log);
    printf("# garments after each phase: %d %d %d %d; log:\n%s", garments[0], garments[1],
           garments[2], garments[3], log ? log : "(none)");
    free(log);
    assert_int_equal(status, 0);
    assert_int_equal(s.n.last_seq, s.seq - 1);
    assert_int_equal(garments[0], 2); /* made on entering, again once the shape settled */
    assert_int_equal(garments[1], 2); /* a doubt: the same shape, the same garment */
    assert_int_equal(garments[2], 3); /* someone else */
    assert_int_equal(garments[3], 3); /* 2 mm is the same shape */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_process_publishes_cloth_and_survives_bad_bodies),
        cmocka_unit_test(test_sim_process_latest_body_wins),
        cmocka_unit_test(test_sim_process_auto_backend),
        cmocka_unit_test(test_sim_process_stats_file),
        cmocka_unit_test(test_sim_process_redress_when_tracking),
        cmocka_unit_test(test_sim_process_doubt_keeps_garment),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
