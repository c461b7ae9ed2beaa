/* tryon-sim --garment tshirt.json as its own process on a private loopback bus: a body without the
 * model's shape and pose is refused with the reason logged (and no CLOTH), the T-shirt is dressed
 * on the first body that has them (the body model walking), and every body after it (--queue all)
 * gets its CLOTH, the garment's vertices finite. */
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "bodyfit.h"
#include "bus.h"
#include "support.h"

#define BODIES 6

typedef struct counts {
    int cloth, finite, nv;
} counts;

static void on_cloth(const char *ch, const void *m, void *user)
{
    (void)ch;
    const tryon_cloth_t *c = m;
    counts *n = user;
    int ok = c->num_vertex_coords > 0;
    for (int i = 0; i < c->num_vertex_coords; i++)
        ok = ok && isfinite(c->vertices[i]);
    n->cloth++;
    n->finite += ok;
    n->nv = c->num_vertex_coords / 3;
}

/* The model walking at frame seq; with_model = 0 leaves out its shape and pose. */
static void send_body(lcm_t *lcm, const char *ch, const fit_model *m, float *xyz, int seq,
                      int with_model)
{
    fit_pose pose;
    float joints[FIT_JOINT_COUNT * 3], shape[FIT_SHAPE_PARAMS], pose_a[FIT_POSE_PARAMS];
    fit_motion_eval(FIT_MOTION_WALK, seq / 30.0, &pose);
    assert_int_equal(fit_model_pose(m, &pose, xyz, joints), 0);
    fit_shape_to_array(fit_model_shape(m), shape);
    memcpy(pose_a, pose.root, sizeof pose.root);
    memcpy(pose_a + 3, pose.rot, sizeof pose.rot);
    tryon_body_t b = {.utime_capture = bus_now_wall_us(),
                      .seq = seq,
                      .state = 1,
                      .num_shape = with_model ? FIT_SHAPE_PARAMS : 0,
                      .shape = shape,
                      .num_pose = with_model ? FIT_POSE_PARAMS : 0,
                      .pose = pose_a,
                      .num_joint_coords = FIT_JOINT_COUNT * 3,
                      .joints = joints,
                      .topology_id = 1,
                      .num_vertex_coords = fit_model_vertex_count(m) * 3,
                      .vertices = xyz,
                      .num_triangle_indices = fit_model_triangle_count(m) * 3,
                      .triangles = (int32_t *)fit_model_triangles(m)};
    bus_reject why;
    assert_int_equal(bus_publish(lcm, ch, BUS_BODY, &b, &why), BUS_OK);
}

static void test_tshirt_process(void **state)
{
    (void)state;
    char url[128], prefix[32], err[512], ch_body[BUS_CHANNEL_MAX], ch[BUS_CHANNEL_MAX], out[256];
    ts_private_bus(url, sizeof url, prefix, sizeof prefix);
    snprintf(out, sizeof out, "test_sim_pattern_process_%s.log", prefix);
    /* --verts: the pattern meshed to about 1,000 vertices (7,000 by default), so that the
       sanitizer build dresses it in seconds */
    char *argv[] = {
        getenv("TRYON_SIM_EXE"),        "--backend", "c", "--queue", "all",  "--garment",
        GAR_PATTERN_DIR "/tshirt.json", "--size",    "L", "--verts", "1000", NULL};
    assert_non_null(argv[0]);
    fit_model *m =
        fit_model_create(&(fit_model_desc){.shape = fit_shape_default()}, err, sizeof err);
    assert_non_null(m);
    float *xyz = malloc((size_t)fit_model_vertex_count(m) * 3 * sizeof *xyz);
    assert_non_null(xyz);
    pid_t pid = ts_spawn_out(argv, NULL, out);
    assert_true(pid > 0);
    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    if (!lcm)
        fail_msg("%s", err);
    bus_channel(BUS_CHANNEL_BODY, ch_body, sizeof ch_body);
    bus_channel(BUS_CHANNEL_CLOTH, ch, sizeof ch);
    counts n = {0};
    bus_sub *sub = bus_subscribe(lcm, ch, BUS_CLOTH, on_cloth, &n);
    /* Until the process listens bodies are lost: bodies without the model's parameters until
     * the log says one was refused (no garment can be made on them: no CLOTH), then bodies with
     * them until the first CLOTH. */
    int seq = 0, refused = 0;
    for (int tries = 0; !refused && tries < 100; tries++) {
        send_body(lcm, ch_body, m, xyz, seq++, 0);
        lcm_handle_timeout(lcm, 100);
        char *log = ts_read_file(out);
        refused = log && strstr(log, "needed to dress a pattern");
        free(log);
    }
    assert_true(refused);
    assert_int_equal(n.cloth, 0);
    for (int tries = 0; n.cloth == 0 && tries < 60; tries++) {
        send_body(lcm, ch_body, m, xyz, seq++, 1);
        /* the dressing takes 0.3-0.7 s in a Release build, seconds under the sanitizers */
        for (int k = 0; k < 10 && n.cloth == 0; k++)
            lcm_handle_timeout(lcm, 100);
    }
    if (n.cloth == 0) {
        ts_stop(pid, SIGTERM, 10000);
        char *log = ts_read_file(out);
        fail_msg("no CLOTH; log:\n%s", log ? log : "(none)");
    }
    for (int k = 0; k < 20; k++) /* those queued while the garment was made */
        lcm_handle_timeout(lcm, 50);
    int before = n.cloth;
    for (int k = 0; k < BODIES; k++)
        send_body(lcm, ch_body, m, xyz, seq++, 1);
    for (int k = 0; k < 200 && n.cloth < before + BODIES; k++)
        lcm_handle_timeout(lcm, 50);
    int status = ts_stop(pid, SIGTERM, 10000);
    char *log = ts_read_file(out);
    remove(out);
    printf("# cloth %d (%d before), finite %d, %d vertices; log:\n%s", n.cloth, before, n.finite,
           n.nv, log ? log : "(none)");
    assert_int_equal(status, 0);
    assert_int_equal(n.cloth, before + BODIES); /* a CLOTH per body */
    assert_int_equal(n.finite, n.cloth);
    assert_true(n.nv > 100);
    assert_non_null(log);
    assert_non_null(strstr(log, "pattern tshirt.json L cotton dressed"));
    free(log);
    bus_unsubscribe(lcm, sub);
    lcm_destroy(lcm);
    free(xyz);
    fit_model_destroy(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_tshirt_process)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}
