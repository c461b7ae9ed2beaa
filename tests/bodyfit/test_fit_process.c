/* tryon-bodyfit as its own process, fed DEPTH over udpm on loopback (a private port and channel
 * prefix): a BODY and a TIMING (segment, fit, skin, and the frame's CPU time) per frame; a frame it
 * cannot use (absurd intrinsics, no reading at all) comes back as a lost BODY with no vertices, the
 * log names why, and the next good frame is fitted again; a burst is collapsed to the newest frame;
 * SIGTERM ends it cleanly. */
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
#include "fit_scene.h"
#include "support.h"

#define FP_MAX_SEQ 256

typedef struct seen {
    int bodies, timings, timing_substages_ok, timing_cpu_ok;
    int state[FP_MAX_SEQ], nv[FP_MAX_SEQ], got[FP_MAX_SEQ];
    int last_seq;
} seen;

static void on_body(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_body_t *b = m;
    seen *s = user;
    s->bodies++;
    s->last_seq = b->seq;
    if (b->seq >= 0 && b->seq < FP_MAX_SEQ) {
        s->got[b->seq] = 1;
        s->state[b->seq] = b->state;
        s->nv[b->seq] = b->num_vertex_coords / 3;
    }
}

static void on_timing(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_timing_t *t = m;
    seen *s = user;
    if (strcmp(t->stage, "bodyfit") != 0)
        return;
    s->timings++;
    int found = 0, cpu = 0;
    for (int i = 0; i < t->num_substages; i++) {
        found += !strcmp(t->substage[i], "segment") || !strcmp(t->substage[i], "fit") ||
                 !strcmp(t->substage[i], "skin");
        cpu += !strcmp(t->substage[i], "cpu") && t->substage_ms[i] > 0.0f;
    }
    s->timing_substages_ok += found == 3;
    s->timing_cpu_ok += cpu == 1;
}

static fit_scene_frame *frame;

static void send_depth(lcm_t *lcm, const char *ch, int seq, const fit_depth_view *v)
{
    tryon_depth_frame_t f = {.utime_capture = bus_now_wall_us(),
                             .seq = seq,
                             .source = "test",
                             .width = v->width,
                             .height = v->height,
                             .fx = v->fx,
                             .fy = v->fy,
                             .cx = v->cx,
                             .cy = v->cy,
                             .metres_per_unit = v->metres_per_unit,
                             .encoding = TRYON_DEPTH_FRAME_T_ENCODING_U16,
                             .num_bytes = v->width * v->height * 2,
                             .data = (uint8_t *)v->depth};
    memcpy(f.camera_to_world, v->camera_to_world, sizeof f.camera_to_world);
    bus_reject why;
    assert_int_equal(bus_publish(lcm, ch, BUS_DEPTH_FRAME, &f, &why), BUS_OK);
}

static void pump(lcm_t *lcm, int ms)
{
    for (int k = 0; k < ms / 20; k++)
        lcm_handle_timeout(lcm, 20);
}

static void test_fit_process_bodies_bad_frames_and_burst(void **state)
{
    (void)state;
    char url[128], prefix[32], err[512], ch_depth[BUS_CHANNEL_MAX], ch[BUS_CHANNEL_MAX], out[256];
    ts_private_bus(url, sizeof url, prefix, sizeof prefix);
    snprintf(out, sizeof out, "test_fit_process_%s.log", prefix);
    char *argv[] = {
        getenv("TRYON_BODYFIT_EXE"), "--vertices", "3000", "--fit-vertices", "1000", NULL};
    assert_non_null(argv[0]);
    pid_t pid = ts_spawn_out(argv, NULL, out);
    assert_true(pid > 0);
    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    if (!lcm)
        fail_msg("%s", err);
    seen s = {.last_seq = -1};
    bus_channel(BUS_CHANNEL_DEPTH, ch_depth, sizeof ch_depth);
    bus_channel(BUS_CHANNEL_BODY, ch, sizeof ch);
    bus_sub *sb = bus_subscribe(lcm, ch, BUS_BODY, on_body, &s);
    bus_channel(BUS_CHANNEL_TIMING, ch, sizeof ch);
    bus_sub *st = bus_subscribe(lcm, ch, BUS_TIMING, on_timing, &s);

    char e2[256];
    fit_model_desc md = {.shape = fit_shape_default(), .target_vertices = 3000};
    fit_model *body = fit_model_create(&md, e2, sizeof e2);
    assert_non_null(body);
    float *v = malloc((size_t)fit_model_vertex_count(body) * 3 * sizeof(float));
    frame = malloc(sizeof *frame);
    fit_pose pose;
    fit_motion_eval(FIT_MOTION_STILL, 0.0, &pose);
    fit_scene_pose(body, &pose, v);
    const float *list[1] = {v};
    fit_scene_render(frame, 0, body, list, 1);

    int seq = 0;
    for (int tries = 0; s.bodies == 0 && tries < 100; tries++) {
        send_depth(lcm, ch_depth, seq++, &frame->view); /* until the process listens */
        pump(lcm, 100);
    }
    assert_true(s.bodies > 0);
    pump(lcm, 500);
    /* Absurd intrinsics (valid on the wire), then a frame with no reading at all. */
    fit_depth_view bad = frame->view;
    bad.fx = 1e6f;
    int bad1 = seq++, bad2 = seq++;
    send_depth(lcm, ch_depth, bad1, &bad);
    pump(lcm, 300);
    uint16_t *zero = calloc((size_t)bad.width * bad.height, sizeof *zero);
    bad = frame->view;
    bad.depth = zero;
    send_depth(lcm, ch_depth, bad2, &bad);
    pump(lcm, 300);
    int good = seq++;
    send_depth(lcm, ch_depth, good, &frame->view);
    pump(lcm, 1000);
    /* A burst faster than fitting: the newest two wait, the others are skipped. */
    for (int k = 0; k < 30; k++)
        send_depth(lcm, ch_depth, seq++, &frame->view);
    /* udpm may drop the tail of a burst of 600 KiB frames in the socket buffer: wait until
     * bodies stop coming. */
    for (int k = 0, before = -1; k < 60 && s.bodies != before; k++) {
        before = s.bodies;
        pump(lcm, 500);
    }

    /* Stepped half out of the image: published, but as init, the doubt named in the log. */
    pose.root[0] = 1.3f;
    fit_scene_pose(body, &pose, v);
    fit_scene_render(frame, 0, body, list, 1);
    int out_first = seq, out_last = seq + 2;
    for (int k = 0; k < 3; k++) {
        send_depth(lcm, ch_depth, seq++, &frame->view);
        pump(lcm, 400);
    }
    pump(lcm, 600);

    int status = ts_stop(pid, SIGTERM, 10000);
    char *log = ts_read_file(out);
    remove(out);
    printf("# bodies %d, timings %d (%d with segment/fit/skin); log:\n%s", s.bodies, s.timings,
           s.timing_substages_ok, log ? log : "(none)");
    assert_int_equal(status, 0);
    assert_true(s.got[bad1] && s.state[bad1] == 2 && s.nv[bad1] == 0);
    assert_true(s.got[bad2] && s.state[bad2] == 2 && s.nv[bad2] == 0);
    assert_true(s.got[good] && s.state[good] != 2 && s.nv[good] > 1000);
    assert_true(s.last_seq > good); /* the burst was served */
    assert_true(s.bodies < seq);    /* some of the burst was skipped */
    assert_true(s.timing_substages_ok >= s.bodies - 1);
    assert_true(s.timing_cpu_ok >= s.bodies - 1);
    assert_non_null(log);
    assert_non_null(strstr(log, "FIT_FRAME_INTRINSICS"));
    assert_non_null(strstr(log, "FIT_FRAME_EMPTY"));
    assert_non_null(strstr(log, "skipped (newer ones waiting)"));
    assert_true(s.got[out_last] && s.state[out_last] == 0 && s.nv[out_last] > 1000);
    for (int k = out_first; k <= out_last; k++)
        assert_true(!s.got[k] || s.state[k] != 1); /* never tracking while half out of view */
    assert_non_null(strstr(log, "fit doubted ("));
    assert_non_null(strstr(log, "OUT_OF_VIEW"));
    /* The last line: where the CPU went. Every body it published was fitted, every frame sent
     * that reached it was counted, and building the models cost something. */
    double start_ms = 0.0, body_ms = 0.0, depth_ms = 0.0;
    long published = 0, received = 0;
    const char *cpu_line = strstr(log, "tryon-bodyfit: CPU ");
    assert_non_null(cpu_line);
    assert_int_equal(sscanf(cpu_line,
                            "tryon-bodyfit: CPU %lf ms starting (building the models), %lf ms a "
                            "body fitted and published (%ld), %lf ms a DEPTH received (%ld",
                            &start_ms, &body_ms, &published, &depth_ms, &received),
                     5);
    assert_true(start_ms > 0.0 && body_ms > 0.0 && depth_ms >= 0.0);
    assert_true(published >= s.bodies && received >= published && received <= seq);
    free(log);
    free(zero);
    free(v);
    free(frame);
    fit_model_destroy(body);
    bus_unsubscribe(lcm, sb);
    bus_unsubscribe(lcm, st);
    lcm_destroy(lcm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fit_process_bodies_bad_frames_and_burst),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
