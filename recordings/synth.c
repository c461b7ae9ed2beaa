/* tryon-synth's engine: the bodyfit model in a scripted motion, filmed by the simulated Kinect,
 * written as a fakenect dump with ground truth beside every frame. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bodyfit.h"
#include "rec_private.h"

/* synth names beyond bodyfit's own motions: the occlusion case reuses arm_raise behind a box. */
#define EXTRA_OCCLUSION "occlusion"

const char *rec_synth_motion_name(int i)
{
    if (i >= 0 && i < FIT_MOTION_COUNT)
        return fit_motion_name((fit_motion)i);
    if (i == FIT_MOTION_COUNT)
        return EXTRA_OCCLUSION;
    return NULL;
}

/* Everything a recording needs per frame, allocated once before the frame loop. */
typedef struct synth_state {
    fit_model *model;
    float *vertices;
    float *background;
    float *depth;
    float *scratch;
    uint16_t *raw;
    rec_writer *writer;
    fit_clip *clip; /* --motion FILE.bvh: the clip on this model, else NULL */
} synth_state;

static void synth_free(synth_state *s)
{
    fit_model_destroy(s->model);
    free(s->vertices);
    free(s->background);
    free(s->depth);
    free(s->scratch);
    free(s->raw);
    rec_writer_destroy(s->writer);
    fit_clip_destroy(s->clip);
}

static void fill_gt(rec_gt *g, const rec_synth_desc *d, const char *motion, const fit_model *m,
                    const fit_pose *pose, const float *joints, const rec_scene *scene)
{
    memset(g, 0, sizeof *g);
    snprintf(g->motion, sizeof g->motion, "%s", motion);
    g->shape_preset = d->shape;
    g->target_vertices = d->target_vertices;
    g->num_shape = FIT_SHAPE_PARAMS;
    fit_shape_to_array(fit_model_shape(m), g->shape);
    g->num_pose = FIT_POSE_PARAMS;
    for (int k = 0; k < 3; k++)
        g->pose[k] = pose->root[k];
    for (int j = 0; j < FIT_JOINT_COUNT; j++)
        for (int k = 0; k < 3; k++)
            g->pose[3 + 3 * j + k] = pose->rot[j][k];
    g->num_joints = FIT_JOINT_COUNT;
    for (int j = 0; j < FIT_JOINT_COUNT; j++) {
        snprintf(g->joint_name[j], sizeof g->joint_name[j], "%s", fit_joint_name((fit_joint)j));
        for (int k = 0; k < 3; k++)
            g->joints[j][k] = joints[3 * j + k];
    }
    g->width = REC_WIDTH;
    g->height = REC_HEIGHT;
    g->fx = (float)REC_FX;
    g->fy = (float)REC_FY;
    g->cx = (float)REC_CX;
    g->cy = (float)REC_CY;
    rec_camera_to_world(g->camera_to_world);
    g->noise = d->noise;
    g->seed = d->seed;
    g->scene = *scene;
}

static int synth_setup(synth_state *s, const rec_synth_desc *d, rec_report *why)
{
    char err[256] = "";
    fit_model_desc md = {.shape = fit_shape_preset(d->shape),
                         .target_vertices = d->target_vertices};
    s->model = fit_model_create(&md, err, sizeof err);
    if (!s->model)
        return rec_fail(why, REC_ERR_ARG, "bodyfit", -1, 0, "body model: %s", err);
    size_t n = (size_t)REC_WIDTH * REC_HEIGHT;
    s->vertices = malloc(sizeof(float) * 3 * (size_t)fit_model_vertex_count(s->model));
    s->background = malloc(sizeof(float) * n);
    s->depth = malloc(sizeof(float) * n);
    s->scratch = malloc(sizeof(float) * n);
    s->raw = malloc(sizeof(uint16_t) * n);
    if (!s->vertices || !s->background || !s->depth || !s->scratch || !s->raw)
        return rec_fail(why, REC_ERR_NO_MEMORY, d->out_dir, -1, 0, NULL);
    s->writer = rec_writer_create(d->out_dir, why);
    return s->writer ? REC_OK : -(int)why->code;
}

static int synth_frame(synth_state *s, const rec_synth_desc *d, int motion, const char *name,
                       const rec_scene *scene, int k, rec_report *why)
{
    float c2w[16], joints[3 * FIT_JOINT_COUNT];
    rec_camera_to_world(c2w);
    double t = k / REC_FPS;
    fit_pose pose;
    if (s->clip)
        fit_clip_eval(s->clip, t, &pose);
    else
        fit_motion_eval((fit_motion)motion, t, &pose);
    if (fit_model_pose(s->model, &pose, s->vertices, joints) != 0)
        return rec_fail(why, REC_ERR_ARG, "bodyfit", k, 0, "posing the model failed");
    memcpy(s->depth, s->background, sizeof(float) * REC_WIDTH * REC_HEIGHT);
    rec_render_triangles(c2w, s->vertices, fit_model_triangles(s->model),
                         fit_model_triangle_count(s->model), s->depth);
    rec_noise_desc nd = rec_noise_default(d->noise, d->seed);
    rec_noise_apply(&nd, k, s->depth, s->scratch, s->raw);
    /* Record times start at 1 s: fakenect treats a previous time of exactly 0 as "none". Device
     * timestamps count microseconds, like OpenNI's; a Kinect's own counter differs. */
    int e = rec_writer_frame(s->writer, s->raw, 1.0 + t, (uint32_t)llround(t * 1e6), why);
    if (e != REC_OK)
        return e;
    rec_gt g;
    fill_gt(&g, d, name, s->model, &pose, joints, scene);
    g.frame = k;
    g.time_s = t;
    char path[512];
    if (rec_writer_gt_path(s->writer, path, sizeof path, NULL, 0) != REC_OK)
        return rec_fail(why, REC_ERR_IO, d->out_dir, k, 0, "groundtruth.txt");
    snprintf(g.depth_file, sizeof g.depth_file, "d-%f-%u.pgm", 1.0 + t, (uint32_t)llround(t * 1e6));
    return rec_gt_write(path, &g, why);
}

static int is_bvh(const char *motion)
{
    size_t n = strlen(motion);
    return n > 4 && strcmp(motion + n - 4, ".bvh") == 0;
}

/* A motion-capture file retargeted onto the recording's body (bodyfit.h, fit_clip). */
static int synth_clip(synth_state *s, const char *path, int keep_heading, rec_report *why)
{
    char err[256] = "";
    fit_bvh *b = NULL;
    int rc = fit_bvh_load(path, &b, err, sizeof err);
    if (!rc)
        rc = fit_clip_from_bvh(b, s->model, &s->clip, err, sizeof err);
    if (!rc && !keep_heading) /* the person enters facing the mirror */
        fit_clip_face_camera(s->clip);
    fit_bvh_destroy(b);
    return rc ? rec_fail(why, REC_ERR_ARG, path, -1, 0, "%s", err) : REC_OK;
}

/* The recording's motion name in its ground truth: a clip's file name without its folder. */
static const char *gt_name(const char *motion)
{
    const char *slash = strrchr(motion, '/');
    return slash ? slash + 1 : motion;
}

int rec_synth(const rec_synth_desc *d, rec_report *why)
{
    if (why)
        memset(why, 0, sizeof *why);
    if (!d || !d->out_dir || !d->motion)
        return rec_fail(why, REC_ERR_ARG, NULL, -1, 0, "output directory and motion needed");
    int motion = fit_motion_from_name(d->motion);
    int box = d->occluder;
    if (motion < 0 && !strcmp(d->motion, EXTRA_OCCLUSION)) {
        motion = FIT_MOTION_ARM_RAISE;
        box = 1;
    }
    if (motion < 0 && !is_bvh(d->motion))
        return rec_fail(why, REC_ERR_ARG, d->motion, -1, 0, "unknown motion");
    if (d->shape < 0 || d->shape >= FIT_SHAPE_PRESETS)
        return rec_fail(why, REC_ERR_ARG, "shape", -1, 0, "preset %d is not 0..%d", d->shape,
                        FIT_SHAPE_PRESETS - 1);
    synth_state s = {0};
    int e = synth_setup(&s, d, why);
    if (e == REC_OK && motion < 0)
        e = synth_clip(&s, d->motion, d->keep_heading, why);
    double seconds = s.clip ? fit_clip_duration(s.clip) : fit_motion_duration((fit_motion)motion);
    int frames = d->frames > 0 ? d->frames : (int)ceil(seconds * REC_FPS - 1e-9);
    rec_scene scene = rec_scene_default(box);
    if (e == REC_OK) {
        float c2w[16];
        rec_camera_to_world(c2w);
        rec_render_background(&scene, c2w, s.background);
    }
    for (int k = 0; k < frames && e == REC_OK; k++)
        e = synth_frame(&s, d, motion, gt_name(d->motion), &scene, k, why);
    synth_free(&s);
    return e;
}
