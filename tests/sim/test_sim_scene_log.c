/* A recorded session's bodies as the bench's scene (scene.h, sim_scene_log; tryon-bench-sim
 * --motion FILE.lcmlog): the bodies a pipeline published, in order from the first one tracked,
 * their triangles from the message that carried them, another sender's and unsealed events left
 * out; a log with nothing to run on, or one that starts after its sender did, refused by name. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <lcm/eventlog.h>

#include "bus.h"
#include "fixtures.h"
#include "scene.h"
#include "support.h"

#define NV     6
#define NT     8
#define JOINTS (21 * 3)

/* an octahedron of radius 0.2 m around (dx, 1, 0) */
static const float octa[NV][3] = {{0.2f, 1, 0}, {-0.2f, 1, 0}, {0, 1.2f, 0},
                                  {0, 0.8f, 0}, {0, 1, 0.2f},  {0, 1, -0.2f}};
static const int32_t octa_tris[NT][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                         {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};

typedef struct log_writer {
    lcm_eventlog_t *log;
    int64_t n;
} log_writer;

/* One event as lcm-logger writes it; sealed = 0 leaves the bus's tag off (another machine's). */
static void put(log_writer *w, const char *channel, const uint8_t *data, int len, int sealed)
{
    uint8_t *buf = malloc((size_t)len + BUS_TAG_BYTES);
    assert_non_null(buf);
    memcpy(buf, data, (size_t)len);
    bus_reject why;
    if (sealed)
        assert_int_equal(bus_seal(channel, buf, (size_t)len, &why), BUS_OK);
    else
        memset(buf + len, 0xA5, BUS_TAG_BYTES);
    lcm_eventlog_event_t ev = {.eventnum = w->n,
                               .timestamp = 1000 + 33333 * w->n,
                               .channellen = (int32_t)strlen(channel),
                               .datalen = len + BUS_TAG_BYTES,
                               .channel = (char *)channel,
                               .data = buf};
    w->n++;
    assert_int_equal(lcm_eventlog_write_event(w->log, &ev), 0);
    free(buf);
}

/* A body at x offset dx: state, topology, triangles sent or not (0 = the kept list). */
static void put_body(log_writer *w, const char *channel, int seq, int8_t state, int32_t topology,
                     int with_tris, float dx, int sealed)
{
    float v[NV][3], joints[JOINTS];
    for (int i = 0; i < NV; i++)
        for (int d = 0; d < 3; d++)
            v[i][d] = octa[i][d] + (d == 0 ? dx : 0.0f);
    for (int j = 0; j < JOINTS; j++)
        joints[j] = (float)j * 0.01f + (j % 3 == 0 ? dx : 0.0f);
    int lost = state == TRYON_BODY_T_STATE_LOST;
    tryon_body_t b = {.utime_capture = 1000000 + 33333 * (int64_t)seq,
                      .seq = seq,
                      .state = state,
                      .num_joint_coords = lost ? 0 : JOINTS,
                      .joints = joints,
                      .topology_id = topology,
                      .num_vertex_coords = lost ? 0 : NV * 3,
                      .vertices = &v[0][0],
                      .num_triangle_indices = lost || !with_tris ? 0 : NT * 3,
                      .triangles = (int32_t *)&octa_tris[0][0]};
    uint8_t *buf = NULL;
    int len = fx_encode(BUS_BODY, &b, &buf);
    assert_true(len > 0);
    put(w, channel, buf, len, sealed);
    free(buf);
}

static char dir[256];

static void log_path(char *out, size_t size, const char *name)
{
    snprintf(out, size, "%s/%s.lcmlog", dir, name);
}

static int setup(void **state)
{
    (void)state;
    return ts_temp_dir(dir, sizeof dir, "scene_log") == 0 ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    ts_remove_dir(dir);
    return 0;
}

static void test_log_scene_plays_the_tracked_bodies_in_order(void **state)
{
    (void)state;
    char path[320];
    log_path(path, sizeof path, "session");
    log_writer w = {.log = lcm_eventlog_create(path, "w")};
    assert_non_null(w.log);
    put_body(&w, "P_BODY", 0, TRYON_BODY_T_STATE_INIT, 1, 1, -1.0f, 1);    /* before tracking */
    put_body(&w, "P_BODY", 1, TRYON_BODY_T_STATE_TRACKING, 1, 0, 0.0f, 1); /* frame 0 */
    put_body(&w, "P_BODY", 2, TRYON_BODY_T_STATE_LOST, 1, 0, 0.0f, 1);     /* skipped */
    put_body(&w, "P_BODY", 3, TRYON_BODY_T_STATE_TRACKING, 1, 0, 0.5f, 0); /* unsealed */
    uint8_t junk[40] = {1, 2, 3};
    put(&w, "P_BODY", junk, sizeof junk, 1);                                /* not a body */
    put_body(&w, "P_CLOTH", 4, TRYON_BODY_T_STATE_TRACKING, 1, 1, 0.7f, 1); /* not BODY */
    put_body(&w, "P_BODY", 5, TRYON_BODY_T_STATE_TRACKING, 9, 1, 0.9f, 1);  /* another mesh */
    put_body(&w, "P_BODY", 6, TRYON_BODY_T_STATE_INIT, 1, 0, 0.1f, 1);      /* frame 1 */
    put_body(&w, "P_BODY", 7, TRYON_BODY_T_STATE_TRACKING, 1, 1, 0.2f, 1);  /* frame 2 */
    lcm_eventlog_destroy(w.log);

    char err[256] = "";
    sim_scene *sc = sim_scene_body(path, 2000, err, sizeof err);
    assert_non_null(sc);
    assert_true(fabs(sim_scene_duration(sc) - 3.0 / 30.0) < 1e-9);
    const float want_dx[] = {0.0f, 0.1f, 0.2f, 0.2f};
    const double at_s[] = {0.0, 1.0 / 30.0, 2.0 / 30.0, 5.0};
    for (int k = 0; k < 4; k++) {
        const float *xyz, *joints;
        const int32_t *tris;
        int nv, nt;
        assert_int_equal(sim_scene_eval(sc, at_s[k], &xyz, &nv, &tris, &nt, &joints), 0);
        assert_int_equal(nv, NV);
        assert_int_equal(nt, NT);
        assert_memory_equal(tris, octa_tris, sizeof octa_tris);
        assert_non_null(joints);
        for (int i = 0; i < NV; i++)
            assert_float_equal(xyz[i * 3], octa[i][0] + want_dx[k], 1e-6f);
        assert_float_equal(joints[3], 0.03f + want_dx[k], 1e-6f);
    }
    sim_scene_destroy(sc);
}

static void test_log_scene_refuses_what_it_cannot_run(void **state)
{
    (void)state;
    char path[320], err[256] = "";
    /* no such file */
    log_path(path, sizeof path, "absent");
    assert_null(sim_scene_body(path, 2000, err, sizeof err));
    assert_non_null(strstr(err, path));
    assert_non_null(strstr(err, "cannot open"));

    /* nobody tracked: every body before the shape settled, or lost */
    log_path(path, sizeof path, "untracked");
    log_writer w = {.log = lcm_eventlog_create(path, "w")};
    assert_non_null(w.log);
    put_body(&w, "BODY", 0, TRYON_BODY_T_STATE_INIT, 1, 1, 0.0f, 1);
    put_body(&w, "BODY", 1, TRYON_BODY_T_STATE_LOST, 1, 0, 0.0f, 1);
    put_body(&w, "BODY", 2, TRYON_BODY_T_STATE_TRACKING, 1, 1, 0.0f, 0); /* unsealed */
    lcm_eventlog_destroy(w.log);
    assert_null(sim_scene_body(path, 2000, err, sizeof err));
    assert_non_null(strstr(err, "no body tracked"));
    assert_non_null(strstr(err, "1 refused"));

    /* the log starts after the sender sent its triangles */
    log_path(path, sizeof path, "late");
    w = (log_writer){.log = lcm_eventlog_create(path, "w")};
    assert_non_null(w.log);
    put_body(&w, "BODY", 0, TRYON_BODY_T_STATE_TRACKING, 3, 0, 0.0f, 1);
    lcm_eventlog_destroy(w.log);
    assert_null(sim_scene_body(path, 2000, err, sizeof err));
    assert_non_null(strstr(err, "without its triangles"));

    /* a file that is no log at all */
    log_path(path, sizeof path, "text");
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs("this is not an LCM log\n", f);
    fclose(f);
    assert_null(sim_scene_body(path, 2000, err, sizeof err));
    assert_non_null(strstr(err, path));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_log_scene_plays_the_tracked_bodies_in_order),
        cmocka_unit_test(test_log_scene_refuses_what_it_cannot_run),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
