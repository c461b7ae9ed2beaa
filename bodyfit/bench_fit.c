/* tryon-bench-fit: replays fakenect dumps through the recordings reader (the file reader and
 * raw-to-millimetre table tryon-capture uses), fits every frame with the tracker tryon-bodyfit
 * runs, and scores it against tryon-synth's ground truth where there is one. A table per
 * recording, then one JSON line (docs/bodyfit.md). */
#include "fit_options.h"
#include "fit_track.h"
#include "recordings.h"
#ifdef BENCH_FIT_CLOTH
#include "bench_cloth.h"
#endif

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

typedef struct bench_opts {
    fit_tracker_desc td;
    const char *out_dir;
    int max_frames, multi;   /* multi: several recordings, each --out in its own folder */
    int cloth_vertices;      /* the shirt of cloth_vs_truth_mm; 0 = none (the default) */
    const char *scores_path; /* --scores FILE */
    int true_shape;          /* --true-shape: the recording's own shape, held (a diagnosis) */
    int true_except;         /* --true-shape-except K: that one parameter the average's; -1 */
    int true_start;          /* --true-start: each frame fitted from its true pose (a diagnosis) */
    FILE *scores;            /* one line per scored frame, or NULL */
    int first;               /* --first N: a line for each of a recording's first N frames */
} bench_opts;

typedef struct totals {
    double *ms, *cpu, *pcpu; /* wall, this thread's CPU, every thread's CPU (ms a frame) */
    int nms, cap, ncpu, cap_cpu, npcpu, cap_pcpu;
    double *sub[3]; /* this thread's CPU ms in segment, fit, skin (fit_result.cpu_ms_*) */
    int nsub[3], cap_sub[3];
    double surface_sum, joints_sum, jitter_sq;
    double view_surface_sum, view_joints_sum; /* over the frames with the person in view */
    int view_scored;
    double *surface;
    int nsurface, cap_surface;
    int scored, jitter_n, in_view, tracked_in_view, recover_max, recover_n;
    int bad, bad_flagged, doubted; /* failure: see score_frame */
    double cloth_sum;
    int cloth_n;
    int iterations_max, shape_steps_max; /* the most work in any one frame (fit_result) */
    double first_ms_max;                 /* the longest of the first --first frames, wall ms */
} totals;

static double clock_ms(clockid_t c)
{
    struct timespec ts;
    clock_gettime(c, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static double now_ms(void)
{
    return clock_ms(CLOCK_MONOTONIC);
}

static int push(double **a, int *n, int *cap, double v)
{
    if (*n == *cap) {
        int c = *cap ? 2 * *cap : 256;
        double *p = realloc(*a, (size_t)c * sizeof *p);
        if (!p)
            return -1;
        *a = p, *cap = c;
    }
    (*a)[(*n)++] = v;
    return 0;
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double quantile(double *v, int n, double q)
{
    if (n <= 0)
        return -1.0;
    qsort(v, (size_t)n, sizeof *v, cmp_d);
    int i = (int)(q * (n - 1) + 0.5);
    return v[i];
}

/* Ground truth per frame (groundtruth.txt lists gt files in frame order), or none. */
static rec_gt *load_gt(const char *dir, int frames)
{
    char path[1100], line[600], depth[256], gtf[256];
    snprintf(path, sizeof path, "%s/groundtruth.txt", dir);
    FILE *f = fopen(path, "r");
    if (!f)
        return NULL;
    rec_gt *gt = calloc((size_t)frames, sizeof *gt);
    int n = 0;
    while (gt && n < frames && fgets(line, sizeof line, f)) {
        int fr;
        double ts;
        if (line[0] == '#' || sscanf(line, "%d %lf %255s %255s", &fr, &ts, depth, gtf) != 4)
            continue;
        char p2[1400];
        snprintf(p2, sizeof p2, "%s/%s", dir, gtf);
        rec_report why;
        if (fr != n || rec_gt_read(p2, &gt[n], &why) != REC_OK) {
            fprintf(stderr, "tryon-bench-fit: %s: ground truth unusable at frame %d; scoring off\n",
                    dir, n);
            free(gt);
            gt = NULL;
            break;
        }
        n++;
    }
    fclose(f);
    if (gt && n < frames) {
        free(gt);
        return NULL;
    }
    return gt;
}

/* Every true joint inside the image and the camera's range. */
static int in_view(const rec_gt *g)
{
    const float *m = g->camera_to_world;
    for (int j = 0; j < g->num_joints; ++j) {
        const float *p = g->joints[j];
        float d[3] = {p[0] - m[3], p[1] - m[7], p[2] - m[11]}, c[3];
        for (int k = 0; k < 3; ++k)
            c[k] = m[0 * 4 + k] * d[0] + m[1 * 4 + k] * d[1] + m[2 * 4 + k] * d[2];
        if (c[2] < REC_RANGE_MIN_M || c[2] > REC_RANGE_MAX_M)
            return 0;
        float u = g->fx * c[0] / c[2] + g->cx, v = g->fy * c[1] / c[2] + g->cy;
        if (u < 0 || v < 0 || u >= (float)g->width || v >= (float)g->height)
            return 0;
    }
    return 1;
}

static void to_camera(const float m[16], const float *p, float c[3])
{
    float d[3] = {p[0] - m[3], p[1] - m[7], p[2] - m[11]};
    for (int k = 0; k < 3; ++k)
        c[k] = m[0 * 4 + k] * d[0] + m[1 * 4 + k] * d[1] + m[2 * 4 + k] * d[2];
}

/* fit_%05d.obj and a joints.jsonl line, in camera coordinates. */
static int write_out(const char *dir, int k, const fit_result *r, const float m[16], FILE *jl)
{
    char path[1100];
    snprintf(path, sizeof path, "%s/fit_%05d.obj", dir, k);
    FILE *f = fopen(path, "w");
    if (!f)
        return -1;
    fprintf(
        f, "# tryon-bench-fit frame %d, depth camera coordinates (x right, y down, z forward, m)\n",
        k);
    for (int i = 0; i < r->vertex_count; ++i) {
        float c[3];
        to_camera(m, r->vertices + (size_t)i * 3, c);
        fprintf(f, "v %.5f %.5f %.5f\n", c[0], c[1], c[2]);
    }
    for (int i = 0; i < r->triangle_count; ++i)
        fprintf(f, "f %d %d %d\n", r->triangles[i * 3] + 1, r->triangles[i * 3 + 1] + 1,
                r->triangles[i * 3 + 2] + 1);
    int bad = fclose(f) != 0;
    fprintf(jl, "{\"frame\": %d, \"state\": %d, \"joints\": {", k, r->state);
    for (int j = 0; j < FIT_JOINT_COUNT && r->vertices; ++j) {
        float c[3];
        to_camera(m, r->joints + j * 3, c);
        fprintf(jl, "%s\"%s\": [%.5f, %.5f, %.5f]", j ? ", " : "", fit_joint_name((fit_joint)j),
                c[0], c[1], c[2]);
    }
    fprintf(jl, "}}\n");
    return bad ? -1 : 0;
}

typedef struct rec_scores {
    double surface, joints, jitter_sq;
    int scored, jitter_n, in_view, tracked, recover;
    int bad, bad_flagged, doubted;
    double cloth_sum;
    int cloth_n;
} rec_scores;

/* A bad fit: past the goals for a whole recording (surface 15 mm, joints 40 mm). A good
 * tracker publishes no bad fit as TRACKING (docs/bodyfit.md, "Failure"). */
#define BENCH_BAD_SURFACE_M 0.015
#define BENCH_BAD_JOINTS_M  0.040

/* A ground truth's pose (recordings.h: root translation, then axis-angle per joint). */
static fit_pose gt_pose(const rec_gt *g)
{
    fit_pose p;
    memcpy(p.root, g->pose, sizeof p.root);
    memcpy(p.rot, g->pose + 3, sizeof p.rot);
    return p;
}

/* Scores one fitted frame against its truth; the frame's surface and joint errors (m) in
 * err_out. */
static void score_frame(const fit_result *r, const rec_gt *g, const rec_gt *gprev,
                        const float *prev_joints, fit_model *truth, float *tv, float *tn, float *fn,
                        rec_scores *s, totals *tot, double err_out[2])
{
    err_out[0] = err_out[1] = -1.0;
    fit_pose pose = gt_pose(g);
    float tj[FIT_JOINT_COUNT * 3];
    fit_model_pose(truth, &pose, tv, tj);
    int ntv = fit_model_vertex_count(truth);
    if (fit_model_normals(truth, tv, tn))
        return;
    /* Normals of the fitted mesh: area-weighted, as fit_model_normals does. */
    memset(fn, 0, (size_t)r->vertex_count * 3 * sizeof(float));
    for (int t = 0; t < r->triangle_count; ++t) {
        const int32_t *tr = r->triangles + (size_t)t * 3;
        const float *a = r->vertices + (size_t)tr[0] * 3, *b = r->vertices + (size_t)tr[1] * 3,
                    *c = r->vertices + (size_t)tr[2] * 3;
        float u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]},
              w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                      u[0] * w[1] - u[1] * w[0]};
        for (int k = 0; k < 3; ++k)
            for (int e = 0; e < 3; ++e)
                fn[(size_t)tr[k] * 3 + e] += n[e];
    }
    for (int i = 0; i < r->vertex_count; ++i) {
        float *n = fn + (size_t)i * 3, l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; ++k)
            n[k] = l > 0.0f ? n[k] / l : 0.0f;
    }
    double d = 0.5 * (fit_mean_surface_distance(r->vertices, r->vertex_count, tv, tn, ntv) +
                      fit_mean_surface_distance(tv, ntv, r->vertices, fn, r->vertex_count));
    double je = 0.0;
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        float e[3] = {r->joints[j * 3] - tj[j * 3], r->joints[j * 3 + 1] - tj[j * 3 + 1],
                      r->joints[j * 3 + 2] - tj[j * 3 + 2]};
        je += sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    }
    je /= FIT_JOINT_COUNT;
    err_out[0] = d, err_out[1] = je;
    s->surface += d, s->joints += je, s->scored++;
    tot->surface_sum += d, tot->joints_sum += je, tot->scored++;
    int bad = d > BENCH_BAD_SURFACE_M || je > BENCH_BAD_JOINTS_M;
    int doubted = r->state != FIT_STATE_TRACKING;
    s->bad += bad, s->bad_flagged += bad && doubted, s->doubted += doubted;
    tot->bad += bad, tot->bad_flagged += bad && doubted, tot->doubted += doubted;
    push(&tot->surface, &tot->nsurface, &tot->cap_surface, d);
    if (gprev && prev_joints) {
        for (int j = 0; j < FIT_JOINT_COUNT; ++j)
            for (int k = 0; k < 3; ++k) {
                double e = (r->joints[j * 3 + k] - prev_joints[j * 3 + k]) -
                           (g->joints[j][k] - gprev->joints[j][k]);
                s->jitter_sq += e * e / FIT_JOINT_COUNT;
                tot->jitter_sq += e * e / FIT_JOINT_COUNT;
            }
        s->jitter_n++, tot->jitter_n++;
    }
}

#ifdef BENCH_FIT_CLOTH
/* The shirt on both bodies this frame (made on the first frame both exist; tv: the true mesh
 * score_frame posed). Off for the recording after an error. */
static void cloth_frame(bench_cloth **c, int *off, const bench_opts *o, const fit_result *r,
                        const rec_gt *g, const fit_model *truth, const float *tv, rec_scores *s,
                        totals *tot)
{
    char err[400];
    if (*off || o->cloth_vertices <= 0)
        return;
    if (!*c) {
        float tj[FIT_JOINT_COUNT * 3];
        for (int j = 0; j < FIT_JOINT_COUNT; ++j)
            memcpy(tj + j * 3, g->joints[j], 3 * sizeof(float));
        *c = bench_cloth_create(o->cloth_vertices, tv, fit_model_vertex_count(truth),
                                fit_model_triangles(truth), fit_model_triangle_count(truth), tj,
                                r->vertices, r->vertex_count, r->triangles, r->triangle_count, err,
                                sizeof err);
    }
    double d = *c ? bench_cloth_step(*c, tv, r->vertices, err, sizeof err) : -1.0;
    if (d < 0.0) {
        fprintf(stderr, "tryon-bench-fit: cloth_vs_truth off for this recording: %s\n", err);
        *off = 1;
        return;
    }
    s->cloth_sum += d, s->cloth_n++;
    tot->cloth_sum += d, tot->cloth_n++;
}
#endif

/* The most work in any one frame; with --first N a line for each of the first N frames, the
 * cost of a person entering (docs/bodyfit.md, "A person's first frames"). */
static void frame_work(const bench_opts *o, totals *tot, const char *name, int k,
                       const fit_result *r, double wall_ms, const double cpu_sub[3],
                       float shape_prev[FIT_SHAPE_PARAMS], int *have_shape)
{
    /* How far the shape moved since the last frame: its largest parameter's change, mm (what
     * a garment made on the first body would miss; docs/bodyfit.md). */
    float shape[FIT_SHAPE_PARAMS], moved = 0.0f;
    fit_shape_to_array(&r->shape, shape);
    for (int i = 0; i < FIT_SHAPE_PARAMS && *have_shape; ++i) {
        float d = fabsf(shape[i] - shape_prev[i]);
        moved = d > moved ? d : moved;
    }
    *have_shape = r->vertices != NULL;
    memcpy(shape_prev, shape, sizeof shape);
    if (r->iterations > tot->iterations_max)
        tot->iterations_max = r->iterations;
    if (r->shape_steps > tot->shape_steps_max)
        tot->shape_steps_max = r->shape_steps;
    if (k >= o->first)
        return;
    if (wall_ms > tot->first_ms_max)
        tot->first_ms_max = wall_ms;
    printf("first %-24s %3d %d %7.2f %7.2f %7.2f %7.2f %4d %2d %6.1f\n", name, k, r->state, wall_ms,
           cpu_sub[0], cpu_sub[1], cpu_sub[2], r->iterations, r->shape_steps, 1000.0f * moved);
}

static int bench_recording(const char *dir, const bench_opts *o, totals *tot)
{
    rec_index idx;
    rec_report why;
    if (rec_index_read(dir, &idx, &why) != REC_OK) {
        fprintf(stderr, "tryon-bench-fit: %s\n", why.message);
        rec_index_free(&idx);
        return -1;
    }
    int frames = o->max_frames > 0 && o->max_frames < idx.count ? o->max_frames : idx.count;
    rec_gt *gt = load_gt(dir, frames);
    fit_tracker_desc td = o->td;
    if (o->true_shape && gt) {
        td.fixed_shape = 1;
        td.shape = fit_shape_from_array(gt[0].shape);
        if (o->true_except >= 0) {
            float a[FIT_SHAPE_PARAMS], avg[FIT_SHAPE_PARAMS];
            fit_shape avg_shape = fit_shape_default();
            fit_shape_to_array(&td.shape, a);
            fit_shape_to_array(&avg_shape, avg);
            a[o->true_except] = avg[o->true_except];
            td.shape = fit_shape_from_array(a);
        }
    }
    char err[512];
    fit_tracker *tr = fit_tracker_create(&td, err, sizeof err);
    fit_model *truth = NULL;
    if (gt) {
        fit_model_desc md = {.shape = fit_shape_from_array(gt[0].shape),
                             .target_vertices = gt[0].target_vertices};
        truth = fit_model_create(&md, err, sizeof err);
    }
    uint16_t *raw = malloc(REC_WIDTH * REC_HEIGHT * sizeof *raw);
    uint16_t *mm = malloc(REC_WIDTH * REC_HEIGHT * sizeof *mm);
    int ntv = truth ? fit_model_vertex_count(truth) : 0;
    float *tv = malloc(((size_t)ntv + 1) * 3 * sizeof(float));
    float *tn = malloc(((size_t)ntv + 1) * 3 * sizeof(float));
    float *fn = malloc((size_t)60000 * 3 * sizeof(float));
    FILE *jl = NULL;
    /* One recording: its frames in DIR; several: each in DIR/<recording name>. */
    char out_dir[1100] = "";
    if (o->out_dir) {
        const char *base = dir + strlen(dir);
        while (base > dir && base[-1] == '/')
            --base;
        const char *nm = base;
        while (nm > dir && nm[-1] != '/')
            --nm;
        mkdir(o->out_dir, 0777);
        if (o->multi)
            snprintf(out_dir, sizeof out_dir, "%s/%.*s", o->out_dir, (int)(base - nm), nm);
        else
            snprintf(out_dir, sizeof out_dir, "%s", o->out_dir);
        mkdir(out_dir, 0777);
        char p[1200];
        snprintf(p, sizeof p, "%s/joints.jsonl", out_dir);
        jl = fopen(p, "w");
    }
    int rc = 0;
    if (!tr || !raw || !mm || !tv || !tn || !fn || (gt && !truth) || (o->out_dir && !jl)) {
        fprintf(stderr, "tryon-bench-fit: %s: cannot start: %s\n", dir,
                !tr || (gt && !truth) ? err : "out of memory or --out not writable");
        rc = -1;
        goto done;
    }
    uint16_t table[REC_RAW_LEVELS];
    rec_raw_to_mm_table(table);
    double *ms = NULL;
    int nms = 0, cap = 0, entered = -1;
    rec_scores s = {0};
    s.recover = -1;
    float prev_joints[FIT_JOINT_COUNT * 3], shape_prev[FIT_SHAPE_PARAMS] = {0};
    int have_prev = 0, have_shape = 0;
    const char *name = strrchr(dir, '/') ? strrchr(dir, '/') + 1 : dir;
#ifdef BENCH_FIT_CLOTH
    bench_cloth *cloth = NULL;
    int cloth_off = 0;
#endif
    for (int k = 0; k < frames; ++k) {
        if (rec_frame_read(dir, &idx.frames[k], k, raw, &why) != REC_OK) {
            fprintf(stderr, "tryon-bench-fit: %s; frame skipped\n", why.message);
            have_prev = 0;
            continue;
        }
        for (int i = 0; i < REC_WIDTH * REC_HEIGHT; ++i)
            mm[i] = table[raw[i] < REC_RAW_LEVELS ? raw[i] : REC_RAW_NONE];
        fit_depth_view v = {.width = REC_WIDTH,
                            .height = REC_HEIGHT,
                            .fx = (float)REC_FX,
                            .fy = (float)REC_FY,
                            .cx = (float)REC_CX,
                            .cy = (float)REC_CY,
                            .metres_per_unit = 0.001f,
                            .depth = mm};
        if (gt)
            memcpy(v.camera_to_world, gt[k].camera_to_world, sizeof v.camera_to_world);
        else
            rec_camera_to_world(v.camera_to_world);
        fit_result r;
        /* Wall time, this thread's CPU time (what a loaded machine does not inflate) and every
         * thread's (OpenCV's workers too: what the process costs the machine). */
        double t0 = now_ms(), c0 = clock_ms(CLOCK_THREAD_CPUTIME_ID);
        double p0 = clock_ms(CLOCK_PROCESS_CPUTIME_ID);
        if (o->true_start && gt) {
            fit_pose start = gt_pose(&gt[k]);
            fit_tracker_start_from(tr, &start);
        }
        fit_tracker_frame(tr, &v, &r);
        double dt = now_ms() - t0;
        push(&tot->cpu, &tot->ncpu, &tot->cap_cpu, clock_ms(CLOCK_THREAD_CPUTIME_ID) - c0);
        push(&tot->pcpu, &tot->npcpu, &tot->cap_pcpu, clock_ms(CLOCK_PROCESS_CPUTIME_ID) - p0);
        const double sub[3] = {r.cpu_ms_segment, r.cpu_ms_fit, r.cpu_ms_skin};
        for (int q = 0; q < 3; ++q)
            push(&tot->sub[q], &tot->nsub[q], &tot->cap_sub[q], sub[q]);
        push(&ms, &nms, &cap, dt);
        push(&tot->ms, &tot->nms, &tot->cap, dt);
        frame_work(o, tot, name, k, &r, dt, sub, shape_prev, &have_shape);
        if (jl && r.vertices && write_out(out_dir, k, &r, v.camera_to_world, jl))
            fprintf(stderr, "tryon-bench-fit: %s: frame %d not written\n", out_dir, k);
        if (jl && !r.vertices)
            fprintf(jl, "{\"frame\": %d, \"state\": %d, \"joints\": {}}\n", k, r.state);
        int view = gt ? in_view(&gt[k]) : 1;
        if (view && entered < 0)
            entered = k;
        if (view) {
            s.in_view++;
            s.tracked += r.state != FIT_STATE_LOST;
        }
        if (entered >= 0 && s.recover < 0 && r.state != FIT_STATE_LOST)
            s.recover = k - entered;
        double err[2] = {-1.0, -1.0};
        if (gt && r.vertices)
            score_frame(&r, &gt[k], have_prev && k > 0 ? &gt[k - 1] : NULL,
                        have_prev ? prev_joints : NULL, truth, tv, tn, fn, &s, tot, err);
        if (view && err[0] >= 0.0) {
            tot->view_surface_sum += err[0], tot->view_joints_sum += err[1];
            tot->view_scored++;
        }
        if (o->scores && gt && r.vertices)
            fprintf(o->scores, "%s %d %d %u %.2f %.2f %.3f %.3f %.2f %d %d\n", name, k, r.state,
                    r.doubt, 1000.0 * err[0], 1000.0 * err[1], r.explained, r.free_space,
                    r.residual_mm, r.unexplained_cluster, view);
#ifdef BENCH_FIT_CLOTH
        if (gt && r.vertices)
            cloth_frame(&cloth, &cloth_off, o, &r, &gt[k], truth, tv, &s, tot);
#endif
        have_prev = r.vertices != NULL;
        if (have_prev)
            memcpy(prev_joints, r.joints, sizeof prev_joints);
    }
    tot->in_view += s.in_view, tot->tracked_in_view += s.tracked;
    if (s.recover >= 0) {
        tot->recover_max = s.recover > tot->recover_max ? s.recover : tot->recover_max;
        tot->recover_n++;
    }
    double med = quantile(ms, nms, 0.5), p95 = quantile(ms, nms, 0.95);
    if (gt)
        printf("%-24s %-11s %-11s %5d %7.2f %7.2f %8.1f %8.1f %8.2f %7.1f %5d %5d %5d %5d %7.1f\n",
               name, gt[0].motion, fit_shape_preset_name(gt[0].shape_preset), frames, med, p95,
               s.scored ? 1000.0 * s.surface / s.scored : -1.0,
               s.scored ? 1000.0 * s.joints / s.scored : -1.0,
               s.jitter_n ? 1000.0 * sqrt(s.jitter_sq / s.jitter_n) : -1.0,
               s.in_view ? 100.0 * s.tracked / s.in_view : -1.0, s.recover, s.doubted, s.bad,
               s.bad - s.bad_flagged, s.cloth_n ? 1000.0 * s.cloth_sum / s.cloth_n : -1.0);
    else
        printf("%-24s %-11s %-11s %5d %7.2f %7.2f %8s %8s %8s %7s %5s %5s %5s %5s %7s\n", name, "-",
               "-", frames, med, p95, "-1", "-1", "-1", "-1", "-1", "-1", "-1", "-1", "-1");
    free(ms);
#ifdef BENCH_FIT_CLOTH
    bench_cloth_destroy(cloth);
#endif
done:
    if (jl)
        fclose(jl);
    free(raw), free(mm), free(tv), free(tn), free(fn), free(gt);
    fit_model_destroy(truth);
    fit_tracker_destroy(tr);
    rec_index_free(&idx);
    return rc;
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: tryon-bench-fit [--out DIR] [--frames N] [--cloth-vertices N] [--scores FILE]\n"
            "                       [--true-shape] [--true-shape-except K] [--true-start]\n"
            "                       [--first N]\n");
    fit_tracker_options_usage(f, 23);
    fprintf(f,
            "                       RECORDING...\n"
            "Fits every frame of each fakenect dump (tryon-synth recordings are scored against\n"
            "their ground truth; others are fitted and timed, their error fields -1). Prints a\n"
            "table per recording, then one JSON line. --out DIR: each frame's mesh as\n"
            "DIR/fit_%%05d.obj and its joints in DIR/joints.jsonl, in depth camera coordinates\n"
            "(x right, y down, z forward, metres); with several recordings, in DIR/NAME/ each.\n"
            "--frames: the first N of each recording (all). --cloth-vertices: the shirt dressed\n"
            "on the fitted and on the true body for cloth_vs_truth_mm, N vertices (0, the\n"
            "default: not dressed, the field -1; the two sims take about 60 ms of CPU a frame\n"
            "with 600). --scores FILE: one line per scored frame, 'recording frame state doubt\n"
            "surface_mm joints_mm explained free_space residual_mm unexplained_cluster\n"
            "in_view' (in_view 1: every true joint inside the image and the camera's range;\n"
            "the JSON line's surface_mm_in_view and joints_mm_in_view are over those frames).\n"
            "--true-shape: fit with the recording's true shape, held (the pose's share of the\n"
            "error, a diagnosis); --true-shape-except K: the same with parameter K (0..8,\n"
            "fit_shape order) the average preset's (what that parameter's error costs).\n"
            "--true-start: each frame's fit starts from its true pose (with --true-shape:\n"
            "what the fit's own terms do to the truth, a diagnosis).\n"
            "--first N: a line for each of a recording's first N frames, 'first recording\n"
            "frame state wall_ms segment_cpu_ms fit_cpu_ms skin_cpu_ms iterations\n"
            "shape_steps shape_moved_mm' (what a person entering costs; the largest shape\n"
            "parameter's change since the last frame; first_ms_max in the JSON line).\n");
    fit_tracker_options_help(f);
}

static int parse_args(int argc, char **argv, bench_opts *o, int *first)
{
    int i = 1;
    for (; i < argc && argv[i][0] == '-'; ++i) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        int bad = 0;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            exit(0);
        } else if (!strcmp(a, "--true-shape")) {
            o->true_shape = 1;
            continue;
        } else if (!strcmp(a, "--true-start")) {
            o->true_start = 1;
            continue;
        } else if (fit_tracker_option(a, v, &o->td, &bad))
            ;
        else if (strcmp(a, "--out") && strcmp(a, "--frames") && strcmp(a, "--cloth-vertices") &&
                 strcmp(a, "--scores") && strcmp(a, "--true-shape-except") &&
                 strcmp(a, "--first")) {
            fprintf(stderr, "tryon-bench-fit: unknown option %s\n", a);
            usage(stderr);
            return -1;
        } else if (!v)
            bad = 1;
        else if (!strcmp(a, "--out"))
            o->out_dir = v;
        else if (!strcmp(a, "--frames"))
            bad = fit_parse_int(v, 1, 1000000, &o->max_frames) != 0;
        else if (!strcmp(a, "--cloth-vertices"))
            bad = fit_parse_int(v, 0, 100000, &o->cloth_vertices) != 0;
        else if (!strcmp(a, "--scores"))
            o->scores_path = v;
        else if (!strcmp(a, "--first"))
            bad = fit_parse_int(v, 0, 1000000, &o->first) != 0;
        else {
            bad = fit_parse_int(v, 0, FIT_SHAPE_PARAMS - 1, &o->true_except) != 0;
            o->true_shape = 1;
        }
        if (bad) {
            fprintf(stderr, "tryon-bench-fit: %s needs a value in range, got '%s'\n", a,
                    v ? v : "(nothing)");
            return -1;
        }
        ++i;
    }
    *first = i;
    if (i >= argc) {
        usage(stderr);
        return -1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    bench_opts o = {.true_except = -1};
    int first;
    if (parse_args(argc, argv, &o, &first))
        return 2;
    if (o.scores_path && !(o.scores = fopen(o.scores_path, "w"))) {
        fprintf(stderr, "tryon-bench-fit: --scores %s: cannot write it\n", o.scores_path);
        return 2;
    }
    printf("%-24s %-11s %-11s %5s %7s %7s %8s %8s %8s %7s %5s %5s %5s %5s %7s\n", "recording",
           "motion", "shape", "frames", "ms_med", "ms_p95", "surf_mm", "joint_mm", "jitter",
           "track%", "recov", "doubt", "bad", "badtr", "cloth");
    totals tot = {0};
    o.multi = argc - first > 1;
    int failed = 0;
    for (int i = first; i < argc; ++i)
        failed += bench_recording(argv[i], &o, &tot) != 0;
    fit_tracker_desc d = o.td;
    int scored = tot.scored > 0;
    printf("{\"bench\":\"fit\",\"ms_median\":%.3f,\"ms_p95\":%.3f,\"cpu_ms_median\":%.3f,"
           "\"cpu_ms_p95\":%.3f,\"process_cpu_ms_median\":%.3f,\"process_cpu_ms_p95\":%.3f,"
           "\"segment_cpu_ms_median\":%.3f,\"fit_cpu_ms_median\":%.3f,"
           "\"skin_cpu_ms_median\":%.3f,\"surface_mm\":%.2f,"
           "\"surface_mm_p95\":%.2f,\"joints_mm\":%.2f,\"jitter_mm\":%.2f,"
           "\"tracked_fraction\":%.4f,\"frames_to_recover\":%d,\"verts\":%d,\"iterations\":%d,"
           "\"points\":%d,\"fit_verts\":%d,\"frames\":%d,\"recordings_failed\":%d,"
           "\"doubted_frames\":%d,\"bad_frames\":%d,\"bad_tracking_frames\":%d,"
           "\"cloth_vs_truth_mm\":%.2f,\"cloth_vertices\":%d,"
           "\"frame_iterations_max\":%d,\"frame_shape_steps_max\":%d,\"first_ms_max\":%.3f,"
           "\"in_view_frames\":%d,\"surface_mm_in_view\":%.2f,\"joints_mm_in_view\":%.2f,"
           "\"backend\":\"c\",\"device\":\"cpu-1-core\"}\n",
           quantile(tot.ms, tot.nms, 0.5), quantile(tot.ms, tot.nms, 0.95),
           quantile(tot.cpu, tot.ncpu, 0.5), quantile(tot.cpu, tot.ncpu, 0.95),
           quantile(tot.pcpu, tot.npcpu, 0.5), quantile(tot.pcpu, tot.npcpu, 0.95),
           quantile(tot.sub[0], tot.nsub[0], 0.5), quantile(tot.sub[1], tot.nsub[1], 0.5),
           quantile(tot.sub[2], tot.nsub[2], 0.5),
           scored ? 1000.0 * tot.surface_sum / tot.scored : -1.0,
           scored ? 1000.0 * quantile(tot.surface, tot.nsurface, 0.95) : -1.0,
           scored ? 1000.0 * tot.joints_sum / tot.scored : -1.0,
           tot.jitter_n ? 1000.0 * sqrt(tot.jitter_sq / tot.jitter_n) : -1.0,
           scored && tot.in_view ? (double)tot.tracked_in_view / tot.in_view : -1.0,
           scored && tot.recover_n ? tot.recover_max : -1, d.out_vertices ? d.out_vertices : 6000,
           d.iterations ? d.iterations : 6, d.points ? d.points : FIT_TRACK_POINTS,
           d.fit_vertices ? d.fit_vertices : 1500, tot.nms, failed, scored ? tot.doubted : -1,
           scored ? tot.bad : -1, scored ? tot.bad - tot.bad_flagged : -1,
           tot.cloth_n ? 1000.0 * tot.cloth_sum / tot.cloth_n : -1.0, o.cloth_vertices,
           tot.iterations_max, tot.shape_steps_max, o.first ? tot.first_ms_max : -1.0,
           scored ? tot.view_scored : -1,
           tot.view_scored ? 1000.0 * tot.view_surface_sum / tot.view_scored : -1.0,
           tot.view_scored ? 1000.0 * tot.view_joints_sum / tot.view_scored : -1.0);
    if (o.scores && fclose(o.scores)) {
        fprintf(stderr, "tryon-bench-fit: --scores %s: write failed\n", o.scores_path);
        failed++;
    }
    free(tot.ms);
    free(tot.cpu);
    free(tot.pcpu);
    for (int q = 0; q < 3; ++q)
        free(tot.sub[q]);
    free(tot.surface);
    return failed ? 1 : 0;
}
