/* tryon-bodyfit: DEPTH -> BODY. Fits the body model to every depth frame it gets to (when it
 * falls behind, the newest frame wins and the skipped ones are counted), publishes BODY and a
 * TIMING with the sub-stages segment, fit and skin. A frame it cannot use gets a message on
 * stderr naming the frame and the reason, a BODY in state lost with no vertices, and the
 * process goes on. */
#include "bus.h"
#include "fit_options.h"
#include "fit_track.h"
#include "queue.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* frames between resends of the triangle list: a sim that starts, or starts again, dresses the
   body within a third of a second at 30 fps */
#define FITP_TRIANGLES_EVERY 10
#define FITP_MESSAGES_MAX    20 /* bad-frame messages printed before only counting them */
/* --queue's default: a frame that overruns (a person's first, fitted in 8 turns) makes the next
 * wait rather than be skipped; a longer overrun still skips, so latency stays bounded. */
#define FITP_QUEUE 2

typedef struct fitp {
    lcm_t *lcm;
    char body_channel[BUS_CHANNEL_MAX];
    fit_tracker *tracker;
    /* the frames waiting to be fitted, oldest first (data owned here) */
    tryon_depth_frame_t waiting[BUS_QUEUE_MAX];
    uint8_t *data[BUS_QUEUE_MAX];
    size_t data_cap[BUS_QUEUE_MAX];
    int64_t received_us[BUS_QUEUE_MAX];
    bus_queue queue;
    int triangles_every, max_frames, queue_all;
    long published, skipped, bad, last_triangles_seq, last_topology;
    long doubted, doubt_spells; /* frames published doubtful (fit_result.doubt), and runs of them */
    unsigned last_doubt;
    /* Where the process's CPU goes (every thread, us): starting (building the models), and
     * fitting and publishing; the rest is receiving, checking and copying DEPTH. */
    int64_t cpu_start, cpu_fit;
    long received;
} fitp;

static volatile sig_atomic_t stop;

static void on_signal(int sig)
{
    (void)sig;
    stop = 1;
}

/* Keeps a copy of the frame to wait in the queue; at a full queue it replaces the oldest waiting,
 * counted as skipped. */
static void on_depth(const char *channel, const void *msg, void *user)
{
    (void)channel;
    fitp *p = user;
    const tryon_depth_frame_t *f = msg;
    int supersedes, k = bus_queue_slot(&p->queue, &supersedes);
    if ((size_t)f->num_bytes > p->data_cap[k]) {
        uint8_t *d = realloc(p->data[k], (size_t)f->num_bytes);
        if (!d) {
            fprintf(stderr, "tryon-bodyfit: frame %d: out of memory; skipped\n", f->seq);
            return;
        }
        p->data[k] = d;
        p->data_cap[k] = (size_t)f->num_bytes;
    }
    p->skipped += supersedes;
    p->received++;
    p->waiting[k] = *f;
    memcpy(p->data[k], f->data, (size_t)f->num_bytes);
    p->waiting[k].data = p->data[k];
    p->waiting[k].source = NULL;
    p->received_us[k] = bus_now_wall_us();
    bus_queue_commit(&p->queue);
}

static void fit_frame(fitp *p, int k);

/* --queue all: every frame is fitted as it arrives (tests, offline replays). */
static void on_depth_all(const char *channel, const void *msg, void *user)
{
    on_depth(channel, msg, user);
    int k = bus_queue_take(&((fitp *)user)->queue);
    if (k >= 0)
        fit_frame(user, k);
}

static void publish(fitp *p, const tryon_depth_frame_t *f, const fit_result *r, bus_timing *timing)
{
    float shape[FIT_SHAPE_PARAMS];
    fit_shape_to_array(&r->shape, shape);
    int send_tris =
        r->vertices &&
        (p->last_triangles_seq < 0 || r->topology_id != p->last_topology ||
         f->seq - p->last_triangles_seq >= p->triangles_every || f->seq < p->last_triangles_seq);
    tryon_body_t msg = {
        .utime_capture = f->utime_capture,
        .seq = f->seq,
        .state = (int8_t)r->state,
        .fit_residual_mm = r->residual_mm,
        .num_shape = FIT_SHAPE_PARAMS,
        .shape = shape,
        .num_pose = FIT_POSE_PARAMS,
        .pose = (float *)&r->pose,
        .num_joint_coords = r->vertices ? FIT_JOINT_COUNT * 3 : 0,
        .joints = (float *)r->joints,
        .topology_id = r->topology_id,
        .num_vertex_coords = r->vertices ? 3 * r->vertex_count : 0,
        .vertices = (float *)r->vertices,
        .num_triangle_indices = send_tris ? 3 * r->triangle_count : 0,
        .triangles = (int32_t *)r->triangles,
    };
    bus_reject why;
    if (bus_publish(p->lcm, p->body_channel, BUS_BODY, &msg, &why) != BUS_OK) {
        fprintf(stderr, "tryon-bodyfit: frame %d not published: %s (%s)\n", f->seq,
                bus_error_text(why.code), why.detail);
        return;
    }
    if (send_tris) {
        p->last_triangles_seq = f->seq;
        p->last_topology = r->topology_id;
    }
    p->published++;
    bus_timing_publish(p->lcm, timing);
}

static void fit_frame(fitp *p, int k)
{
    int64_t cpu0 = bus_now_cpu_us();
    tryon_depth_frame_t *f = &p->waiting[k];
    bus_timing timing;
    bus_timing_begin(&timing, "bodyfit", f->seq, f->utime_capture, p->received_us[k]);
    fit_depth_view v = {.width = f->width,
                        .height = f->height,
                        .fx = f->fx,
                        .fy = f->fy,
                        .cx = f->cx,
                        .cy = f->cy,
                        .metres_per_unit = f->metres_per_unit,
                        .depth = (const uint16_t *)f->data};
    memcpy(v.camera_to_world, f->camera_to_world, sizeof v.camera_to_world);
    fit_result r;
    fit_frame_error e = fit_tracker_frame(p->tracker, &v, &r);
    bus_timing_add(&timing, "segment", (float)r.ms_segment);
    bus_timing_add(&timing, "fit", (float)r.ms_fit);
    bus_timing_add(&timing, "skin", (float)r.ms_skin);
    if (e != FIT_FRAME_OK && e != FIT_FRAME_NOBODY && p->bad++ < FITP_MESSAGES_MAX)
        fprintf(stderr, "tryon-bodyfit: frame %d: %s; published as lost, waiting for the next\n",
                f->seq, r.message);
    if (r.doubt) { /* a failure shown, not hidden: one line when a run of doubtful fits starts */
        p->doubted++;
        if (!p->last_doubt && p->doubt_spells++ < FITP_MESSAGES_MAX) {
            char why[96];
            fit_doubt_names(r.doubt, why, sizeof why);
            fprintf(stderr,
                    "tryon-bodyfit: frame %d: fit doubted (%s: %.0f %% of the points explained, "
                    "%.0f %% of the model in free space); published as init until sound again\n",
                    f->seq, why, 100.0f * r.explained, 100.0f * r.free_space);
        }
    }
    p->last_doubt = r.doubt;
    int64_t cpu = bus_now_cpu_us() - cpu0; /* the fit's, every thread (OpenCV's too) */
    bus_timing_add(&timing, "cpu", (float)cpu / 1000.0f);
    publish(p, f, &r, &timing);
    p->cpu_fit += bus_now_cpu_us() - cpu0;
    if (p->max_frames > 0 && p->published >= p->max_frames)
        stop = 1;
}

/* Where the CPU went (docs/bodyfit.md, "CPU a frame in the pipeline"). */
static void print_cpu(const fitp *p)
{
    double rest = (double)(bus_now_cpu_us() - p->cpu_start - p->cpu_fit) / 1000.0;
    fprintf(stderr,
            "tryon-bodyfit: CPU %.0f ms starting (building the models), %.2f ms a body fitted and "
            "published (%ld), %.2f ms a DEPTH received (%ld, with the waiting between them)\n",
            (double)p->cpu_start / 1000.0,
            p->published ? (double)p->cpu_fit / 1000.0 / (double)p->published : 0.0, p->published,
            p->received ? rest / (double)p->received : 0.0, p->received);
}

static void usage(FILE *f)
{
    fprintf(f, "usage: tryon-bodyfit [--frames N] [--triangles-every N] [--queue N|latest|all]\n");
    fit_tracker_options_usage(f, 21);
    fprintf(f, "Fits the body model to every DEPTH frame and publishes BODY (world coordinates,\n"
               "state init/tracking/lost) and TIMING (segment, fit, skin; cpu: the frame's CPU\n"
               "time, every thread). When it falls behind, at most --queue N frames wait (1-4,\n"
               "default 2; latest: 1), oldest first, and one arriving at a full queue replaces\n"
               "the oldest waiting (--queue all: every frame is fitted, in order). --frames:\n"
               "exit after N bodies.\n"
               "--triangles-every: the triangles with every Nth body (10). At the end, where the\n"
               "CPU went: starting, a body fitted and published, a DEPTH received.\n");
    fit_tracker_options_help(f);
    fprintf(f, "LCM: $TRYON_LCM_URL; channels prefixed by $TRYON_CHANNEL_PREFIX.\n");
}

static int parse_args(int argc, char **argv, fitp *p, fit_tracker_desc *d)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int bad = 0;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            exit(0);
        } else if (fit_tracker_option(a, v, d, &bad))
            ;
        else if (strcmp(a, "--frames") && strcmp(a, "--triangles-every") && strcmp(a, "--queue")) {
            fprintf(stderr, "tryon-bodyfit: unknown option %s\n", a);
            usage(stderr);
            return -1;
        } else if (!v)
            bad = 1;
        else if (!strcmp(a, "--frames"))
            bad = fit_parse_int(v, 1, 1000000000, &p->max_frames) != 0;
        else if (!strcmp(a, "--queue")) {
            int n = 1;
            bad = strcmp(v, "all") != 0 && strcmp(v, "latest") != 0 &&
                  fit_parse_int(v, 1, BUS_QUEUE_MAX, &n) != 0;
            p->queue_all = !strcmp(v, "all");
            bus_queue_init(&p->queue, n);
        } else
            bad = fit_parse_int(v, 1, 1000000, &p->triangles_every) != 0;
        if (bad) {
            fprintf(stderr, "tryon-bodyfit: %s needs a value in range, got '%s'\n", a,
                    v ? v : "(nothing)");
            return -1;
        }
        ++i;
    }
    return 0;
}

int main(int argc, char **argv)
{
    fitp p = {.triangles_every = FITP_TRIANGLES_EVERY, .last_triangles_seq = -1};
    bus_queue_init(&p.queue, FITP_QUEUE);
    fit_tracker_desc d = {0};
    if (parse_args(argc, argv, &p, &d))
        return 2;
    int rc = 1;
    char err[512], depth_channel[BUS_CHANNEL_MAX];
    bus_sub *sub = NULL;
    p.tracker = fit_tracker_create(&d, err, sizeof err);
    if (!p.tracker) {
        fprintf(stderr, "tryon-bodyfit: %s\n", err);
        return 1;
    }
    p.lcm = bus_open(NULL, err, sizeof err);
    if (!p.lcm) {
        fprintf(stderr, "tryon-bodyfit: %s\n", err);
        goto done;
    }
    bus_channel(BUS_CHANNEL_DEPTH, depth_channel, sizeof depth_channel);
    bus_channel(BUS_CHANNEL_BODY, p.body_channel, sizeof p.body_channel);
    sub = bus_subscribe(p.lcm, depth_channel, BUS_DEPTH_FRAME,
                        p.queue_all ? on_depth_all : on_depth, &p);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    fprintf(stderr, "tryon-bodyfit: listening on %s -> %s\n", depth_channel, p.body_channel);
    p.cpu_start = bus_now_cpu_us();
    while (!stop) {
        int r = lcm_handle_timeout(p.lcm, p.queue.count ? 0 : 100);
        while (r > 0 && !p.queue_all)
            r = lcm_handle_timeout(p.lcm, 0); /* drain: the newest frames wait */
        int k = bus_queue_take(&p.queue);
        if (k >= 0)
            fit_frame(&p, k);
    }
    fprintf(stderr,
            "tryon-bodyfit: published %ld bodies, %ld frames skipped (newer ones waiting), %ld bad "
            "frames, %ld doubtful fits (runs of them: %ld), %llu DEPTH messages rejected\n",
            p.published, p.skipped, p.bad, p.doubted, p.doubt_spells,
            (unsigned long long)bus_sub_stats(sub)->rejected);
    print_cpu(&p);
    rc = 0;
done:
    bus_unsubscribe(p.lcm, sub);
    if (p.lcm)
        lcm_destroy(p.lcm);
    fit_tracker_destroy(p.tracker);
    for (int k = 0; k < BUS_QUEUE_MAX; k++)
        free(p.data[k]);
    return rc;
}
