/* tryon-truth: an oracle in place of tryon-bodyfit. For every DEPTH frame it receives, it
 * publishes on BODY the true body of that frame, rebuilt from the recording's ground truth with
 * the same body model that rendered it. With it the simulation and the pipeline's latency can be
 * measured on recordings with no fitting error in between; tryon-bodyfit replaces it unchanged
 * on the bus. */
#include "bodyfit.h"
#include "bus.h"
#include "recordings.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TRUTH_TRIANGLES_EVERY 30 /* frames between resends of the triangle list (1 s at 30 fps) */

typedef struct truth {
    lcm_t *lcm;
    char body_channel[BUS_CHANNEL_MAX];
    int num_frames;
    rec_gt *gt; /* [num_frames] */
    fit_model *model;
    float *verts; /* [nv][3] */
    float joints[FIT_JOINT_COUNT * 3];
    int triangles_every;
    int published, unknown, max_frames;
    long last_triangles_seq;
} truth;

static volatile sig_atomic_t stop;

static void on_signal(int sig)
{
    (void)sig;
    stop = 1;
}

/* groundtruth.txt: one line per frame, "frame time depth_file gt_file"; '#' comments. */
static int load_truth(truth *t, const char *dir)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/groundtruth.txt", dir);
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "tryon-truth: %s: %s (is this a tryon-synth recording?)\n", path,
                strerror(errno));
        return -1;
    }
    int cap = 0;
    char line[512], depth_file[256], gt_file[256];
    for (int lineno = 1; fgets(line, sizeof line, f); lineno++) {
        int frame;
        double time_s;
        line[strcspn(line, "\r\n")] = '\0';
        if (line[0] == '#' || line[0] == '\0')
            continue;
        if (sscanf(line, "%d %lf %255s %255s", &frame, &time_s, depth_file, gt_file) != 4 ||
            frame != t->num_frames) {
            fprintf(stderr, "tryon-truth: %s line %d: expected frame %d: '%s'\n", path, lineno,
                    t->num_frames, line);
            fclose(f);
            return -1;
        }
        if (t->num_frames == cap) {
            cap = cap ? 2 * cap : 64;
            rec_gt *g = realloc(t->gt, (size_t)cap * sizeof *g);
            if (!g) {
                fclose(f);
                return -1;
            }
            t->gt = g;
        }
        char gt_path[1024];
        snprintf(gt_path, sizeof gt_path, "%s/%s", dir, gt_file);
        rec_report why;
        if (rec_gt_read(gt_path, &t->gt[t->num_frames], &why) != REC_OK) {
            fprintf(stderr, "tryon-truth: %s\n", why.message); /* names the file */
            fclose(f);
            return -1;
        }
        t->num_frames++;
    }
    fclose(f);
    if (t->num_frames == 0) {
        fprintf(stderr, "tryon-truth: %s lists no frame\n", path);
        return -1;
    }
    return 0;
}

static int make_model(truth *t)
{
    const rec_gt *g = &t->gt[0];
    fit_model_desc d = {.shape = fit_shape_from_array(g->shape),
                        .target_vertices = g->target_vertices};
    char err[256];
    t->model = fit_model_create(&d, err, sizeof err);
    if (!t->model) {
        fprintf(stderr, "tryon-truth: body model: %s\n", err);
        return -1;
    }
    t->verts = malloc((size_t)fit_model_vertex_count(t->model) * 3 * sizeof *t->verts);
    return t->verts ? 0 : -1;
}

static void publish_body(truth *t, const tryon_depth_frame_t *f, int64_t received)
{
    bus_timing timing;
    bus_timing_begin(&timing, "bodyfit", f->seq, f->utime_capture, received);
    const rec_gt *g = &t->gt[f->seq];
    fit_pose pose;
    memcpy(pose.root, g->pose, sizeof pose.root);
    memcpy(pose.rot, g->pose + 3, sizeof pose.rot);
    int64_t t0 = bus_now_mono_us();
    fit_model_pose(t->model, &pose, t->verts, t->joints);
    bus_timing_add(&timing, "pose", (float)(bus_now_mono_us() - t0) / 1000.0f);

    int nv = fit_model_vertex_count(t->model), nt = fit_model_triangle_count(t->model);
    int send_tris = t->last_triangles_seq < 0 ||
                    f->seq - t->last_triangles_seq >= t->triangles_every ||
                    f->seq < t->last_triangles_seq;
    tryon_body_t msg = {
        .utime_capture = f->utime_capture,
        .seq = f->seq,
        .state = TRYON_BODY_T_STATE_TRACKING,
        .fit_residual_mm = 0,
        .num_shape = g->num_shape,
        .shape = (float *)g->shape,
        .num_pose = g->num_pose,
        .pose = (float *)g->pose,
        .num_joint_coords = FIT_JOINT_COUNT * 3,
        .joints = t->joints,
        .topology_id = 1,
        .num_vertex_coords = 3 * nv,
        .vertices = t->verts,
        .num_triangle_indices = send_tris ? 3 * nt : 0,
        .triangles = (int32_t *)fit_model_triangles(t->model),
    };
    bus_reject why;
    if (bus_publish(t->lcm, t->body_channel, BUS_BODY, &msg, &why) != BUS_OK) {
        fprintf(stderr, "tryon-truth: frame %d not published: %s (%s)\n", f->seq,
                bus_error_text(why.code), why.detail);
        return;
    }
    if (send_tris)
        t->last_triangles_seq = f->seq;
    t->published++;
    bus_timing_publish(t->lcm, &timing);
}

static void on_depth(const char *channel, const void *msg, void *user)
{
    (void)channel;
    truth *t = user;
    const tryon_depth_frame_t *f = msg;
    int64_t received = bus_now_wall_us();
    if (f->seq < 0 || f->seq >= t->num_frames) {
        if (t->unknown++ < 5)
            fprintf(stderr, "tryon-truth: DEPTH frame %d has no ground truth (0..%d); skipped\n",
                    f->seq, t->num_frames - 1);
        return;
    }
    publish_body(t, f, received);
    if (t->max_frames > 0 && t->published >= t->max_frames)
        stop = 1;
}

/* A positive count, or -1. */
static int parse_count(const char *s)
{
    char *end;
    long v = strtol(s, &end, 10);
    return *s && !*end && v > 0 && v <= 1000000000L ? (int)v : -1;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: tryon-truth --recording DIR [--frames N] [--triangles-every N]\n"
               "Publishes on BODY the true body of every DEPTH frame received (by seq), from\n"
               "the ground truth of a tryon-synth recording: an oracle in place of\n"
               "tryon-bodyfit. --frames: exit after N bodies. LCM: $TRYON_LCM_URL.\n");
}

int main(int argc, char **argv)
{
    truth t = {.triangles_every = TRUTH_TRIANGLES_EVERY, .last_triangles_seq = -1};
    const char *dir = NULL;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--recording") == 0 && i + 1 < argc)
            dir = argv[++i];
        else if (strcmp(argv[i], "--frames") == 0 && i + 1 < argc)
            t.max_frames = parse_count(argv[++i]);
        else if (strcmp(argv[i], "--triangles-every") == 0 && i + 1 < argc)
            t.triangles_every = parse_count(argv[++i]);
        else if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            return 0;
        } else {
            fprintf(stderr, "tryon-truth: unknown option or missing value: %s\n", argv[i]);
            usage(stderr);
            return 2;
        }
    }
    if (!dir || t.triangles_every < 1 || t.max_frames < 0) {
        usage(stderr);
        return 2;
    }
    int rc = 1;
    char err[512], depth_channel[BUS_CHANNEL_MAX];
    bus_sub *sub = NULL;
    if (load_truth(&t, dir) != 0 || make_model(&t) != 0)
        goto done;
    t.lcm = bus_open(NULL, err, sizeof err);
    if (!t.lcm) {
        fprintf(stderr, "tryon-truth: %s\n", err);
        goto done;
    }
    bus_channel(BUS_CHANNEL_DEPTH, depth_channel, sizeof depth_channel);
    bus_channel(BUS_CHANNEL_BODY, t.body_channel, sizeof t.body_channel);
    sub = bus_subscribe(t.lcm, depth_channel, BUS_DEPTH_FRAME, on_depth, &t);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    fprintf(stderr, "tryon-truth: %d frames of ground truth from %s; %s -> %s\n", t.num_frames, dir,
            depth_channel, t.body_channel);
    while (!stop)
        lcm_handle_timeout(t.lcm, 100);
    fprintf(stderr,
            "tryon-truth: published %d bodies, %d frames without ground truth, %llu "
            "DEPTH messages rejected\n",
            t.published, t.unknown, (unsigned long long)bus_sub_stats(sub)->rejected);
    rc = 0;
done:
    bus_unsubscribe(t.lcm, sub);
    if (t.lcm)
        lcm_destroy(t.lcm);
    fit_model_destroy(t.model);
    free(t.verts);
    free(t.gt);
    return rc;
}
