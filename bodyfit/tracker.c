/* The tracker: per frame, segment, fit the coarse model, skin the published mesh. States: INIT
 * while the shape is being estimated (the first shape_frames frames of a person), TRACKING,
 * LOST (nobody, a bad frame, or a fit that does not explain the points); after LOST the next
 * person is initialised from the rest pose again, with no human in the loop. */
#include "cv_shim.h"
#include "fit_internal.h"
#include "fit_smooth.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tryon_clock.h"

static double track_cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

/* A fit is lost when fewer than this share of the points are explained, or worse than this. */
#define TRACK_MIN_INLIERS 0.6f
#define TRACK_MAX_RMS_MM  30.0f
/* Correspondence gates: wide from the rest pose, tighter once tracking. */
#define TRACK_GATE_INIT_M  0.25f
#define TRACK_GATE_TRACK_M 0.12f
/* The silhouette's distance transform covers the person's box and this many grid pixels around
 * it (20 px at stride 2 is 17 cm at 2.5 m: farther model vertices are pulled from the box edge). */
#define TRACK_SILHOUETTE_MARGIN_PX 20
/* Share of the last frame's motion carried into the next frame's start: the whole of it measured
 * best (fast swing 18.3 -> 9.5 mm, walk 3.4 -> 2.9, still 2.9 -> 3.1; docs/bodyfit.md). */
#define TRACK_PREDICT 1.0f
/* Temporal prior weight (per m^2 or rad^2 against the data term's mean squared residual). */
#define TRACK_TEMPORAL 2e-4f
/* The pelvis joint stands this far behind the visible front surface (half a body depth). */
#define TRACK_BODY_HALF_DEPTH_M 0.10f

/* A person's first frames: the shape and the pose fitted in turns (a shape step at half gain,
 * then a pose iteration), so that the shape moves the published joints over the first frames
 * rather than over the next ones (jitter standing still). */
/* 2: still jitter 2.00 / 2.12 / 2.34 mm; 4: 2.02 / 2.02 / 1.87 (400 points); with 800 points,
 * 4 and half steps after: 1.19 / 1.54 / 1.47; 8 and the running mean after
 * (track_shape_update): 1.15 / 1.27 / 1.10 (the filter's speed at 0.7 Hz for all of these). */
#define TRACK_SHAPE_FIRST_ROUNDS 8
/* A person's first frame cost 88 iterations and 40 ms when each turn had 6 pose iterations and
 * the fit from the rest pose 40: the next frames waited behind it. One iteration a turn, and 12
 * from the rest pose, leave the errors as they were (docs/bodyfit.md, "A person's first
 * frames"); --start-turns spreads the turns over the first frames (cheaper frames, more
 * jitter: the shape then moves the published joints after the first frame). */
#define TRACK_START_TURN_ITERATIONS 1
#define TRACK_INIT_ITERATIONS       12
/* A restart after a part was lost for good (below) starts from a rest pose far from the body's
 * (arms crossed: 12 iterations left the forearms in the chest 12 frames longer,
 * test_fit_doubt); it is rare, and keeps the 40 a person's first frame had. */
#define TRACK_RESTART_ITERATIONS 40

/* Doubting a fit (docs/bodyfit.md, "Failure"): measured causes, each against what a sound fit of
 * the same person shows. A doubtful fit is still published, with state INIT, and the shape does
 * not learn from it; TRACKING comes back after TRACK_SOUND_FRAMES sound frames in a row. */
#define TRACK_DOUBT_EXPLAINED 0.95f /* fewer of the points explained */
#define TRACK_DOUBT_RMS_RATIO 1.25f /* RMS over the person's own RMS when the fit was sound */
/* More of the model's seen vertices in free space: a shape a little off leaves 3-11 % there
 * standing still (slim_tall: 0.10 doubted 8 of its still frames); a lost part 13-17 %. */
#define TRACK_DOUBT_FREE_SPACE 0.15f
#define TRACK_DOUBT_CLAMPED    4 /* more pose parameters held at their joint limits */
#define TRACK_SOUND_FRAMES     3
/* Unexplained points this close to each other are one cluster (the ~800 points lie about
 * 3-3.5 cm apart on a person at 2.5 m). */
#define TRACK_CLUSTER_RADIUS_M 0.06f
/* This many of them together: a limb left behind (headline set, frames published tracking:
 * 9 of the 17 bad ones have 3 or more, 4 of the 507 good ones). */
#define TRACK_DOUBT_CLUSTER 3
/* A fit explaining fewer of the points than this for TRACK_RESTART_FRAMES frames in a row, with
 * the person in view, has lost a part of the body for good (an arm fitted into the chest after
 * stepping half out of view explains 81-84 % of the points; crossed arms 92-99 %): the pose
 * starts again from the rest pose on the next frame, the shape kept. */
#define TRACK_RESTART_EXPLAINED 0.90f
#define TRACK_RESTART_FRAMES    10
/* A limb left behind that the shoulder's turn has not brought back for this many frames in a
 * row restarts the pose too (after crossed arms an arm kept inside the chest left its points
 * unexplained, together, for good; the fast swing's arm comes back within 9). */
#define TRACK_RESTART_LOST_PART_FRAMES 15
/* Turned further than this from the camera, a single depth view sees the shoulders and hips
 * edge-on and one arm not at all (cos 60 degrees: the turn recordings' error rises past it). */
#define TRACK_DOUBT_FACING_COS 0.5f
/* The person's sound RMS is kept per square metre of their distance from the camera: a
 * Kinect's depth noise and its disparity steps both grow with the square of the distance (the
 * fit's RMS over z^2 measured 1.47, 1.39, 1.39 mm/m^2 at 1.5, 2.5, 3.5 m on the `distance`
 * recording). It learns slowly from sound fits only; a point is explained within this many of
 * it (at least FIT_EXPLAINED_M). */
#define TRACK_RMS_BASE_GAIN   0.05f
#define TRACK_EXPLAINED_RMSES 4.0f

struct fit_tracker {
    fit_tracker_desc d;
    fit_model *coarse, *full;
    fit_solver *solver;
    fit_segmenter *seg;
    float *verts, *pts;
    int32_t *nearest;
    int nearest_cap;
    fit_pose pose, prev, last; /* last: the pose fitted the frame before pose */
    fit_shape shape;
    fit_shape_base base_coarse, base_full;
    fit_shape_q q;        /* the shape's degrees of freedom (fit_shape_adapt.c) */
    float *shape_scratch; /* fit_shape_step's posed coarse meshes */
    int have_pose, have_last, person_frames, topology_id;
    int shape_learnt; /* frames the shape has learnt from at the fast gain */
    int start_turns;  /* a person's first turns of shape and pose still to do */
    double height_sum;
    int height_n;
    fit_smoother smooth;  /* the published pose only */
    float rms_base;       /* the fit's RMS while sound, mm per m^2 of distance (0: none yet) */
    int sound_frames;     /* sound fits in a row (TRACK_SOUND_FRAMES for a new person) */
    int failing_frames;   /* fits in a row under TRACK_RESTART_EXPLAINED, the person in view */
    int lost_part_frames; /* fits in a row with a limb left behind, the person in view */
    fit_pose published;
    float published_joints[FIT_JOINT_COUNT * 3]; /* world, of the pose last published */
    int have_published;
    int iterations, shape_steps; /* this frame's work (fit_result) */
    fit_pose start;              /* fit_tracker_start_from's, for the next frame */
    int have_start;
};

/* Builds the coarse and the published model of a shape; keeps the old ones on failure. */
static int track_models(fit_tracker *t, const fit_shape *shape, char *err, size_t errlen)
{
    fit_model_desc dc = {.shape = *shape, .target_vertices = t->d.fit_vertices};
    fit_model_desc df = {.shape = *shape, .target_vertices = t->d.out_vertices};
    fit_model *c = fit_model_create(&dc, err, errlen);
    fit_model *f = c ? fit_model_create(&df, err, errlen) : NULL;
    fit_solver *s = f ? fit_solver_create(c) : NULL;
    float *v = s ? malloc((size_t)fit_model_vertex_count(f) * 3 * sizeof(float)) : NULL;
    if (!v) {
        fit_model_destroy(c);
        fit_model_destroy(f);
        fit_solver_destroy(s);
        return -1;
    }
    fit_model_destroy(t->coarse);
    fit_model_destroy(t->full);
    fit_solver_destroy(t->solver);
    free(t->verts);
    t->coarse = c, t->full = f, t->solver = s, t->verts = v;
    t->shape = *shape;
    t->topology_id++;
    return 0;
}

/* Each joint's reach: the farthest joint below it in the rest pose (a leaf: its bone's length). */
static void track_smooth_levers(fit_tracker *t)
{
    const float *r = fit_model_rest_joints(t->coarse);
    float lever[FIT_JOINT_COUNT] = {0};
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        for (int a = fit_joint_parent((fit_joint)j); a >= 0; a = fit_joint_parent((fit_joint)a)) {
            float d[3] = {r[j * 3] - r[a * 3], r[j * 3 + 1] - r[a * 3 + 1],
                          r[j * 3 + 2] - r[a * 3 + 2]};
            float l = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            lever[a] = l > lever[a] ? l : lever[a];
        }
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        if (lever[j] <= 0.0f) {
            int p = fit_joint_parent((fit_joint)j);
            float d[3] = {r[j * 3] - r[p * 3], r[j * 3 + 1] - r[p * 3 + 1],
                          r[j * 3 + 2] - r[p * 3 + 2]};
            lever[j] = p >= 0 ? sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) : 1.0f;
        }
    fit_smoother_set_levers(&t->smooth, lever);
}

fit_tracker *fit_tracker_create(const fit_tracker_desc *d, char *err, size_t errlen)
{
    fit_tracker *t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    t->d = d ? *d : (fit_tracker_desc){0};
    fit_tracker_desc *x = &t->d;
    x->out_vertices = x->out_vertices ? x->out_vertices : 6000;
    x->fit_vertices = x->fit_vertices ? x->fit_vertices : 1500;
    x->points = x->points > 0 ? x->points : FIT_TRACK_POINTS;
    x->iterations = x->iterations > 0 ? x->iterations : 6;
    x->init_iterations = x->init_iterations > 0 ? x->init_iterations : TRACK_INIT_ITERATIONS;
    x->start_turns = x->start_turns > 0 ? x->start_turns : TRACK_SHAPE_FIRST_ROUNDS;
    x->shape_frames = x->shape_frames > 0 ? x->shape_frames : 10;
    x->temporal = x->temporal > 0.0f ? x->temporal : TRACK_TEMPORAL;
    x->predict = x->predict < 0.0f ? 0.0f : (x->predict > 0.0f ? x->predict : TRACK_PREDICT);
    x->smooth_doubt_mps = x->smooth_doubt_mps != 0.0f ? x->smooth_doubt_mps : FIT_TRACK_DOUBT_MPS;
    fit_smooth_desc sd = {.min_cutoff_hz = x->smooth_hz,
                          .beta_root = x->smooth_beta_root,
                          .beta_rot = x->smooth_beta_rot,
                          .speed_cutoff_hz = x->smooth_speed_hz};
    fit_smoother_init(&t->smooth, &sd);
    fit_shape s0 = x->shape.height > 0.0f ? x->shape : fit_shape_default();
    t->seg = fit_segmenter_create(&x->segment, err, errlen);
    if (!t->seg || track_models(t, &s0, err, errlen)) {
        fit_tracker_destroy(t);
        return NULL;
    }
    t->topology_id = 1;
    t->q = fit_shape_q_identity();
    t->sound_frames = TRACK_SOUND_FRAMES;
    track_smooth_levers(t);
    t->shape_scratch = malloc((size_t)FIT_SHAPE_DOF * (size_t)fit_model_vertex_count(t->coarse) *
                              3 * sizeof(float));
    if (!t->shape_scratch || fit_shape_base_init(&t->base_coarse, t->coarse) ||
        fit_shape_base_init(&t->base_full, t->full)) {
        if (err)
            snprintf(err, errlen, "fit_tracker_create: out of memory");
        fit_tracker_destroy(t);
        return NULL;
    }
    return t;
}

void fit_tracker_destroy(fit_tracker *t)
{
    if (!t)
        return;
    fit_model_destroy(t->coarse);
    fit_model_destroy(t->full);
    fit_solver_destroy(t->solver);
    fit_segmenter_destroy(t->seg);
    fit_shape_base_free(&t->base_coarse);
    fit_shape_base_free(&t->base_full);
    free(t->verts);
    free(t->pts);
    free(t->nearest);
    free(t->shape_scratch);
    free(t);
}

/* Rest pose standing on the floor where the points are, facing the camera. */
static void track_initial_pose(fit_tracker *t, const fit_segment *sg, const fit_depth_view *v)
{
    const float *m = v->camera_to_world, *rest = fit_model_rest_joints(t->coarse);
    memset(&t->pose, 0, sizeof t->pose);
    float to_cam[2] = {m[3] - sg->centroid[0], m[11] - sg->centroid[2]};
    float l = sqrtf(to_cam[0] * to_cam[0] + to_cam[1] * to_cam[1]);
    float c[3] = {sg->centroid[0], 0.0f, sg->centroid[2]};
    if (l > 1e-3f) {
        c[0] -= TRACK_BODY_HALF_DEPTH_M * to_cam[0] / l;
        c[2] -= TRACK_BODY_HALF_DEPTH_M * to_cam[1] / l;
        t->pose.rot[FIT_PELVIS][1] = atan2f(to_cam[0], to_cam[1]); /* body +z to the camera */
    }
    t->pose.root[0] = c[0] - rest[FIT_PELVIS * 3];
    t->pose.root[1] = -sg->floor[3] / sg->floor[1]; /* feet on the floor plane */
    t->pose.root[2] = c[2] - rest[FIT_PELVIS * 3 + 2];
}

/* About `points` of the person's points, the same image cells from frame to frame: a cell is
 * kept when its ordered-dither threshold (a 64 x 64 Bayer matrix tiled over the grid) falls under
 * the wanted share, which spreads the kept cells evenly at any share. Every k-th point instead
 * moves every chosen point to a neighbouring cell whenever the person gains or loses a pixel,
 * and the fit then follows the sampling as well as the body (docs/bodyfit.md, jitter). */
#define TRACK_DITHER_BITS 6
static unsigned track_dither(unsigned x, unsigned y)
{
    unsigned v = 0, a = x ^ y;
    for (int bit = TRACK_DITHER_BITS - 1; bit >= 0; --bit) /* interleave (x^y, y) bit-reversed */
        v |= (((a >> bit) & 1u) << (2 * (TRACK_DITHER_BITS - 1 - bit) + 1)) |
             (((y >> bit) & 1u) << (2 * (TRACK_DITHER_BITS - 1 - bit)));
    return v; /* each of 0 .. 4^bits - 1 once per tile */
}

static int track_subsample(fit_tracker *t, const fit_segment *sg)
{
    if (sg->count <= t->d.points) {
        memcpy(t->pts, sg->points, (size_t)sg->count * 3 * sizeof(float));
        return sg->count;
    }
    const unsigned tile = 1u << TRACK_DITHER_BITS;
    unsigned share = (unsigned)((double)(tile * tile) * t->d.points / sg->count + 0.5);
    int n = 0, src = 0;
    for (int y = 0; y < sg->height; ++y)
        for (int x = 0; x < sg->width; ++x) {
            if (!sg->mask[y * sg->width + x])
                continue;
            if (track_dither((unsigned)x & (tile - 1), (unsigned)y & (tile - 1)) < share)
                memcpy(t->pts + (size_t)n++ * 3, sg->points + (size_t)src * 3, 3 * sizeof(float));
            src++;
        }
    return n;
}

/* Shape: the height from the top of the person over the first shape_frames frames (unless the
 * head reaches the top row; the feet often touch the bottom one); then the rest of the shape's
 * degrees of freedom (leg and arm length, shoulder width, five girths) by a Gauss-Newton step a
 * frame on the pose fit's correspondences, fast over the first frames and slowly after (a
 * person does not change shape between frames). The mesh keeps its topology
 * (fit_shape_adapt.c, fit_shape_step.c). */
#define TRACK_SHAPE_GAIN_INIT  0.5f  /* each of the first frame's turns */
#define TRACK_SHAPE_GAIN_AFTER 0.02f /* per frame, applied every TRACK_SHAPE_EVERY frames */
/* After the first frames the shape is refined every 8th frame only, with 8 frames' gain: the
 * same rate, at an eighth of the cost (the step re-poses the coarse mesh 8 times; +0.6-1.3 ms
 * of CPU a frame when every frame took one). */
#define TRACK_SHAPE_EVERY 8

/* fit_solve, its iterations counted in the frame's work. */
static int track_solve(fit_tracker *t, const fit_problem *pb, fit_pose *pose, fit_stats *st)
{
    int rc = fit_solve(t->solver, pb, pose, st);
    t->iterations += st->iterations;
    return rc;
}

static void track_shape_apply(fit_tracker *t)
{
    fit_shape_base_apply(&t->base_coarse, t->coarse, &t->q);
    fit_shape_base_apply(&t->base_full, t->full, &t->q);
    t->shape = fit_shape_adapted(&t->base_full, &t->q);
}

static void track_shape_reset(fit_tracker *t)
{
    t->q = fit_shape_q_identity();
    t->height_sum = 0.0;
    t->height_n = 0;
    if (!t->d.fixed_shape)
        track_shape_apply(t);
}

/* The square of the person's distance along the optical axis, m^2 (at least 0.25: 0.5 m). */
static float track_distance2(const fit_segment *sg, const fit_depth_view *v)
{
    const float *m = v->camera_to_world;
    float d[3] = {sg->centroid[0] - m[3], sg->centroid[1] - m[7], sg->centroid[2] - m[11]};
    float z = m[2] * d[0] + m[6] * d[1] + m[10] * d[2];
    return z > 0.5f ? z * z : 0.25f;
}

/* Before the fit of a person's first frames: the height from the top of the points, so the
 * frame is fitted with it (after the fit, the model would grow under a placed pose). */
static void track_height_update(fit_tracker *t, const fit_segment *sg, const fit_depth_view *v)
{
    if (t->d.fixed_shape || t->person_frames >= t->d.shape_frames || sg->touches_top)
        return;
    /* The segmentation drops the outermost sample of every silhouette as a possible flying
     * pixel, the crown's too: the head reaches one sample spacing higher than its top point
     * (without the drop the average's height was 4 mm short, with it 18 mm). */
    float spacing = (float)sg->stride * sqrtf(track_distance2(sg, v)) / v->fy;
    t->height_sum += sg->top_y + spacing;
    t->height_n++;
    float h = (float)(t->height_sum / t->height_n), lo, hi;
    fit_shape_param_range(0, &lo, &hi);
    h = h < lo ? lo : (h > hi ? hi : h);
    t->q.scale = h / t->base_full.shape.height;
    track_shape_apply(t);
}

/* One shape step; the coarse model is left with the new shape (fit_shape_step), and with
 * publish the published model and shape too (a turn leaves those to the last turn). */
static void track_shape_update(fit_tracker *t, fit_pose *pose, const float *points, int publish)
{
    int init = t->shape_learnt < t->d.shape_frames;
    if (!init && (t->shape_learnt - t->d.shape_frames) % TRACK_SHAPE_EVERY)
        return;
    /* Over the first frames after the first, a running mean of the frames' own estimates, the
     * first frame (fitted in turns to convergence) counting twice: half of each frame's step
     * passed half of that frame's noise to the joints (the arm length moved 1-1.5 % a frame,
     * 5-8 mm at the wrist, standing still; docs/bodyfit.md, jitter). */
    float gain =
        !init ? TRACK_SHAPE_EVERY * TRACK_SHAPE_GAIN_AFTER
              : (t->shape_learnt ? 1.0f / (float)(t->shape_learnt + 2) : TRACK_SHAPE_GAIN_INIT);
    t->shape_steps++;
    if (fit_shape_step(&t->base_coarse, t->coarse, t->solver, pose, points, gain, t->shape_scratch,
                       &t->q) == 0 &&
        publish)
        track_shape_apply(t);
}

static int track_shape_turns(fit_tracker *t, const fit_problem *pb, fit_pose *pose, fit_stats *st)
{
    fit_problem turn = *pb;
    turn.iterations = TRACK_START_TURN_ITERATIONS;
    turn.max_match_m = TRACK_GATE_TRACK_M;
    int rc = 0;
    for (int k = 0; k < t->d.start_turns && t->start_turns > 0 && !rc; ++k, --t->start_turns) {
        track_shape_update(t, pose, pb->points, 0);
        rc = track_solve(t, &turn, pose, st);
    }
    track_shape_apply(t); /* the 6,000-vertex model once, not once a turn */
    return rc;
}

/* The unexplained points' largest cluster; when it is a limb left behind, the arm nearest it
 * is turned at the shoulder to point at the cluster and the fit run again; unless that found
 * the limb, its forearm is turned to point at it and the fit run again from there, the temporal
 * prior then held to the turned pose (held to the frame's prediction, where the forearm was
 * lost, the fit took it back there). The pose that explains the most points is kept if it
 * explains more than the fit (docs/bodyfit.md, "A lost forearm").
 * *fitted: 0 when the solver's matches are not the kept pose's (a try was made). */
static int track_find_limb(fit_tracker *t, fit_problem *pb, fit_pose *pose, fit_stats *st,
                           int fresh, int *fitted)
{
    float tol = pb->explained_m > 0.0f ? pb->explained_m : FIT_EXPLAINED_M, at[3], at2[3];
    fit_matches mt = fit_solver_matches(t->solver);
    int cluster = fit_unexplained_cluster(pb->points, &mt, tol, TRACK_CLUSTER_RADIUS_M, at);
    if (fresh || cluster < TRACK_DOUBT_CLUSTER)
        return cluster;
    const fit_pose from = *pose;
    int sh = fit_limb_nearest_shoulder(t->coarse, &from, at), kept = -1, last = -1;
    for (int k = 0; k < 2; ++k) {
        if (k == 1 && kept == 0 && cluster < TRACK_DOUBT_CLUSTER)
            break; /* the arm turned at the shoulder explained its points */
        fit_pose alt = from, turned;
        fit_problem retry = *pb;
        if (k == 0) {
            fit_limb_reaim(t->coarse, &alt, sh, at);
        } else {
            fit_limb_reaim_forearm(t->coarse, &alt, sh, at);
            turned = alt;
            retry.prev = &turned;
        }
        fit_stats st2;
        if (track_solve(t, &retry, &alt, &st2))
            break;
        last = k;
        if (st2.explained <= st->explained)
            continue;
        *pose = alt;
        *st = st2;
        kept = k;
        mt = fit_solver_matches(t->solver);
        cluster = fit_unexplained_cluster(pb->points, &mt, tol, TRACK_CLUSTER_RADIUS_M, at2);
    }
    if (kept >= 0 && kept != last) { /* the solver's matches again the kept pose's */
        fit_problem measure = *pb;
        fit_stats st3;
        measure.iterations = 0;
        if (!track_solve(t, &measure, pose, &st3))
            last = kept;
    }
    *fitted = kept >= 0 && kept == last;
    return cluster;
}

static void track_predict(fit_pose *out, const fit_pose *now, const fit_pose *before, float g)
{
    for (int k = 0; k < 3; ++k)
        out->root[k] = now->root[k] + g * (now->root[k] - before->root[k]);
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        for (int k = 0; k < 3; ++k)
            out->rot[j][k] = now->rot[j][k] + g * (now->rot[j][k] - before->rot[j][k]);
    fit_pose_clamp(out);
}

void fit_doubt_names(unsigned doubt, char *buf, size_t len)
{
    static const char *const names[] = {"UNEXPLAINED", "FREE_SPACE", "OUT_OF_VIEW",
                                        "LIMITS",      "SIDE_ON",    "LOST_PART"};
    size_t n = 0;
    if (len)
        buf[0] = '\0';
    for (unsigned k = 0; k < sizeof names / sizeof names[0] && n < len; ++k)
        if (doubt & (1u << k)) {
            int w = snprintf(buf + n, len - n, "%s%s", n ? " " : "", names[k]);
            n += w > 0 ? (size_t)w : 0;
        }
}

/* The causes found in this frame's fit (FIT_DOUBT_* bits); a sound fit updates the person's RMS. */
/* The cosine of the angle between the fitted body's front and the way to the camera, in the
 * floor plane (1: facing it). */
static float track_facing(const fit_pose *p, const fit_segment *sg, const fit_depth_view *v)
{
    double m[9];
    body_axis_angle_matrix(p->rot[FIT_PELVIS], m);
    const float *c = v->camera_to_world;
    float fx = (float)m[2], fz = (float)m[8]; /* body +z is its front */
    float tx = c[3] - sg->centroid[0], tz = c[11] - sg->centroid[2];
    float l = sqrtf((fx * fx + fz * fz) * (tx * tx + tz * tz));
    return l > 1e-6f ? (fx * tx + fz * tz) / l : 1.0f;
}

static unsigned track_doubt(fit_tracker *t, const fit_stats *st, const fit_segment *sg,
                            const fit_result *r, float z2, float facing)
{
    unsigned d = 0;
    if (facing < TRACK_DOUBT_FACING_COS)
        d |= FIT_DOUBT_SIDE_ON;
    float rms = st->rms_mm / z2;
    if (r->explained < TRACK_DOUBT_EXPLAINED ||
        (t->rms_base > 0.0f && rms > TRACK_DOUBT_RMS_RATIO * t->rms_base))
        d |= FIT_DOUBT_UNEXPLAINED;
    if (r->free_space > TRACK_DOUBT_FREE_SPACE)
        d |= FIT_DOUBT_FREE_SPACE;
    if (sg->touches_side)
        d |= FIT_DOUBT_OUT_OF_VIEW;
    if (st->clamped >= TRACK_DOUBT_CLAMPED)
        d |= FIT_DOUBT_LIMITS;
    if (r->unexplained_cluster >= TRACK_DOUBT_CLUSTER)
        d |= FIT_DOUBT_LOST_PART;
    if (!d || t->rms_base <= 0.0f)
        t->rms_base =
            t->rms_base > 0.0f ? t->rms_base + TRACK_RMS_BASE_GAIN * (rms - t->rms_base) : rms;
    t->sound_frames = d ? 0 : t->sound_frames + 1;
    int in_view = !(d & (FIT_DOUBT_OUT_OF_VIEW | FIT_DOUBT_SIDE_ON));
    int failing = r->explained < TRACK_RESTART_EXPLAINED && in_view;
    t->failing_frames = failing ? t->failing_frames + 1 : 0;
    t->lost_part_frames = (d & FIT_DOUBT_LOST_PART) && in_view ? t->lost_part_frames + 1 : 0;
    return d;
}

static fit_frame_error track_lost(fit_tracker *t, fit_result *out, fit_frame_error e,
                                  const char *why)
{
    if (t->have_pose || t->person_frames)
        track_shape_reset(t); /* the next person may be another */
    t->have_pose = 0;
    t->have_last = 0;
    t->have_published = 0;
    fit_smoother_reset(&t->smooth);
    t->person_frames = 0;
    t->shape_learnt = 0;
    t->start_turns = 0;
    t->rms_base = 0.0f;
    t->sound_frames = TRACK_SOUND_FRAMES; /* a new person is trusted until doubted */
    t->failing_frames = 0;
    t->lost_part_frames = 0;
    out->state = FIT_STATE_LOST;
    out->error = e;
    if (why && why != out->message)
        snprintf(out->message, sizeof out->message, "%s", why);
    out->vertices = NULL;
    out->vertex_count = 0;
    return e;
}

/* A doubted fit's published pose p, as far from the pose last published as a joint may move in a
 * frame (smooth_doubt_mps): the step scaled down until no joint moves farther (joint motion is
 * near linear in the scale over a frame's step; three rounds). Returns 1 if p was changed. */
static int track_bound_speed(fit_tracker *t, const fit_pose *was_p, fit_pose *p)
{
    const float step_m = t->d.smooth_doubt_mps * t->smooth.d.frame_s, *was_j = t->published_joints;
    const fit_pose was = *was_p;
    float skin[FIT_JOINT_COUNT][12], j[FIT_JOINT_COUNT * 3];
    int changed = 0;
    for (int round = 0; round < 3; ++round) {
        body_joint_transforms(&t->full->sk, p, skin, j);
        float far2 = 0.0f;
        for (int k = 0; k < FIT_JOINT_COUNT; ++k) {
            float d[3] = {j[k * 3] - was_j[k * 3], j[k * 3 + 1] - was_j[k * 3 + 1],
                          j[k * 3 + 2] - was_j[k * 3 + 2]};
            far2 = fmaxf(far2, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        }
        if (far2 <= step_m * step_m * 1.0001f)
            break;
        float a = step_m / sqrtf(far2);
        for (int k = 0; k < 3; ++k)
            p->root[k] = was.root[k] + a * (p->root[k] - was.root[k]);
        for (int q = 0; q < FIT_JOINT_COUNT; ++q)
            for (int k = 0; k < 3; ++k)
                p->rot[q][k] = was.rot[q][k] + a * (p->rot[q][k] - was.rot[q][k]);
        fit_pose_clamp(p);
        changed = 1;
    }
    return changed;
}

void fit_tracker_start_from(fit_tracker *t, const fit_pose *pose)
{
    t->start = *pose;
    fit_pose_clamp(&t->start);
    t->have_start = 1;
}

fit_frame_error fit_tracker_frame(fit_tracker *t, const fit_depth_view *v, fit_result *out)
{
    memset(out, 0, sizeof *out);
    out->shape = t->shape;
    out->topology_id = t->topology_id;
    t->iterations = t->shape_steps = 0;
    double t0 = tryon_now_ms(), c0 = track_cpu_ms();
    fit_segment sg;
    fit_frame_error e = fit_segmenter_frame(t->seg, v, &sg, out->message, sizeof out->message);
    out->ms_segment = tryon_now_ms() - t0;
    out->cpu_ms_segment = track_cpu_ms() - c0;
    if (e)
        return track_lost(t, out, e, NULL);
    size_t cells = (size_t)sg.width * (size_t)sg.height;
    if ((int)cells > t->nearest_cap) {
        free(t->nearest);
        free(t->pts);
        t->nearest = malloc(cells * sizeof(int32_t));
        t->pts = malloc(cells * 3 * sizeof(float));
        t->nearest_cap = t->nearest && t->pts ? (int)cells : 0;
        if (!t->nearest_cap)
            return track_lost(t, out, FIT_FRAME_INTERNAL, "out of memory");
    }
    char err[256];
    int roi[4];
    if (cvs_nearest_set(sg.mask, sg.width, sg.height, TRACK_SILHOUETTE_MARGIN_PX, t->nearest, roi,
                        err, sizeof err))
        return track_lost(t, out, FIT_FRAME_INTERNAL, err);
    out->ms_segment = tryon_now_ms() - t0;
    double c1 = track_cpu_ms(), t1 = tryon_now_ms();
    out->cpu_ms_segment = c1 - c0;
    int fresh = !t->have_pose;
    track_height_update(t, &sg, v);
    if (fresh)
        track_initial_pose(t, &sg, v);
    float z2 = track_distance2(&sg, v);
    fit_problem pb = {.points = t->pts,
                      .count = track_subsample(t, &sg),
                      .seg = &sg,
                      .nearest = t->nearest,
                      .roi = {roi[0], roi[1], roi[2], roi[3]},
                      .view = v,
                      .prev = fresh ? NULL : &t->pose,
                      .iterations = !fresh             ? t->d.iterations
                                    : t->person_frames ? TRACK_RESTART_ITERATIONS
                                                       : t->d.init_iterations,
                      .max_match_m = fresh ? TRACK_GATE_INIT_M : TRACK_GATE_TRACK_M,
                      .temporal = fresh ? 0.0f : t->d.temporal,
                      .explained_m = TRACK_EXPLAINED_RMSES * 1e-3f * t->rms_base * z2};
    /* Constant velocity: the last frame's motion, scaled by predict, starts the fit and anchors
     * the temporal prior (a swinging arm is then not held back by where it was). */
    t->prev = t->pose;
    if (!fresh && t->have_last && t->d.predict > 0.0f)
        track_predict(&t->prev, &t->pose, &t->last, t->d.predict);
    fit_pose pose = t->prev;
    if (!fresh && t->have_start)
        pose = t->start;
    t->have_start = 0;
    pb.prev = fresh ? NULL : &t->prev;
    fit_stats st;
    int rc = track_solve(t, &pb, &pose, &st);
    int whole = !sg.touches_side && track_facing(&pose, &sg, v) >= TRACK_DOUBT_FACING_COS;
    if (!rc && fresh && !t->person_frames && !t->d.fixed_shape && whole)
        t->start_turns = TRACK_SHAPE_FIRST_ROUNDS;
    if (!rc && t->start_turns > 0 && whole)
        rc = track_shape_turns(t, &pb, &pose, &st);
    int matches_fitted = 1; /* the solver's matches are those of the pose kept */
    out->unexplained_cluster = rc ? 0 : track_find_limb(t, &pb, &pose, &st, fresh, &matches_fitted);
    out->ms_fit = tryon_now_ms() - t1;
    out->cpu_ms_fit = track_cpu_ms() - c1;
    out->iterations = t->iterations;
    out->shape_steps = t->shape_steps;
    out->points_used = pb.count;
    out->residual_mm = st.rms_mm;
    out->explained = pb.count ? (float)st.explained / (float)pb.count : 0.0f;
    out->free_space = st.sil_checked ? (float)st.sil_violations / (float)st.sil_checked : 0.0f;
    if (rc || st.inliers < TRACK_MIN_INLIERS * (float)pb.count || st.rms_mm > TRACK_MAX_RMS_MM) {
        snprintf(out->message, sizeof out->message,
                 "%s: %s (%d of %d points within %.0f mm, RMS %.1f mm)",
                 fit_frame_error_name(FIT_FRAME_FIT), fit_frame_error_text(FIT_FRAME_FIT),
                 st.inliers, pb.count, 1000.0f * pb.max_match_m, st.rms_mm);
        return track_lost(t, out, FIT_FRAME_FIT, NULL);
    }
    out->doubt = track_doubt(t, &st, &sg, out, z2, track_facing(&pose, &sg, v));
    t->last = t->pose;
    t->have_last = !fresh;
    t->pose = pose;
    t->have_pose = 1;
    t->person_frames++;
    /* The first frames estimate the shape whatever the doubt, unless the body is seen side-on or
     * cut by the image's side (walking in: the lengths learnt from a side view left the joints
     * 40-44 mm off once facing the camera); after them a doubtful fit does not teach the shape
     * (crossed arms would fatten the torso: arms_cross s0 joints 52 -> 36 mm). */
    unsigned partial = FIT_DOUBT_SIDE_ON | FIT_DOUBT_OUT_OF_VIEW;
    if (!t->d.fixed_shape && matches_fitted && !(out->doubt & partial) && !t->start_turns &&
        (!out->doubt || t->person_frames <= t->d.shape_frames)) {
        track_shape_update(t, &t->pose, t->pts, 1);
        t->shape_learnt++;
    }
    out->shape_steps = t->shape_steps;
    double t2 = tryon_now_ms(), c2 = track_cpu_ms();
    const fit_pose last_published = t->published;
    t->published = t->pose;
    if (fresh)
        fit_smoother_reset(&t->smooth);
    if (t->d.smooth_hz >= 0.0f)
        fit_smoother_step(&t->smooth, &t->pose, &t->published);
    if (t->have_published && t->sound_frames < TRACK_SOUND_FRAMES && t->d.smooth_doubt_mps > 0.0f &&
        track_bound_speed(t, &last_published, &t->published))
        fit_smoother_hold(&t->smooth, &t->published);
    fit_model_pose(t->full, &t->published, t->verts, out->joints);
    memcpy(t->published_joints, out->joints, sizeof t->published_joints);
    t->have_published = 1;
    out->ms_skin = tryon_now_ms() - t2;
    out->cpu_ms_skin = track_cpu_ms() - c2;
    int settled = t->d.fixed_shape || t->person_frames > t->d.shape_frames;
    out->state =
        settled && t->sound_frames >= TRACK_SOUND_FRAMES ? FIT_STATE_TRACKING : FIT_STATE_INIT;
    out->pose = t->published;
    out->shape = t->shape;
    out->vertices = t->verts;
    out->vertex_count = fit_model_vertex_count(t->full);
    out->triangles = fit_model_triangles(t->full);
    out->triangle_count = fit_model_triangle_count(t->full);
    out->topology_id = t->topology_id;
    if (t->failing_frames >= TRACK_RESTART_FRAMES ||
        t->lost_part_frames >= TRACK_RESTART_LOST_PART_FRAMES) { /* publish this, then restart */
        t->have_pose = t->have_last = 0;
        t->failing_frames = t->lost_part_frames = 0;
    }
    return FIT_FRAME_OK;
}
