/* Scene bodies for tryon-bench-sim and the tests. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"
#ifdef SIM_HAVE_BODYFIT
#include "bodyfit.h"
#endif

#define SCENE_PI      3.14159265358979f
#define SCENE_BLEND_S 0.5 /* "all": each segment crossfades from the last over this long */
/* A clip's scene first turns the body from the model's A-pose into the clip's first pose over
   this long: the shirt is made on the scene's first frame, and made on a clip's (arms at the
   sides) the tube ran through both arms (docs/sim-history.md, "Arms down: the clips") */
#define SCENE_CLIP_IN_S 1.0

struct sim_scene {
    int nv, nt;
    float *rest; /* nv * 3 */
    float *xyz;  /* nv * 3, posed */
    int32_t *tris;
    float joints[32 * 3];
    int has_joints;
    int kind; /* 0 sphere, 1 body model, 2 capsule figure, 3 recorded bodies */
    /* kind 3: frames bodies of nv vertices (frames * nv * 3) and their joints (frames *
       joint_floats), frame k shown from (k - 0.5) to (k + 0.5) * frame_dt_s */
    int frames, joint_floats;
    float *rec_xyz, *rec_joints;
    double frame_dt_s;
    int motion; /* -1 = all, -2 = a motion-capture clip */
    /* a scripted motion's time scale and the scale of its joint rotations ("NAME@SPEED,AMOUNT") */
    double speed, amount;
#ifdef SIM_HAVE_BODYFIT
    fit_model *model;
    fit_clip *clip; /* a motion-capture clip (motion FILE.bvh), else NULL */
#endif
};

static sim_scene *scene_alloc(int nv, int nt)
{
    sim_scene *sc = calloc(1, sizeof *sc);
    if (!sc)
        return NULL;
    sc->nv = nv;
    sc->nt = nt;
    sc->rest = calloc((size_t)nv * 3, sizeof *sc->rest);
    sc->xyz = calloc((size_t)nv * 3, sizeof *sc->xyz);
    sc->tris = calloc((size_t)nt * 3, sizeof *sc->tris);
    if (!sc->rest || !sc->xyz || !sc->tris) {
        sim_scene_destroy(sc);
        return NULL;
    }
    return sc;
}

void sim_scene_destroy(sim_scene *sc)
{
    if (!sc)
        return;
#ifdef SIM_HAVE_BODYFIT
    fit_clip_destroy(sc->clip);
    fit_model_destroy(sc->model);
#endif
    free(sc->rest);
    free(sc->xyz);
    free(sc->tris);
    free(sc->rec_xyz);
    free(sc->rec_joints);
    free(sc);
}

sim_scene *sim_scene_recorded(int nv, const int32_t *tris, int nt, int frames, float *xyz,
                              float *joints, int joint_floats, double frame_dt_s)
{
    if (nv < 3 || nt < 1 || frames < 1 || !xyz || joint_floats < 0 || joint_floats > 32 * 3 ||
        !(frame_dt_s > 0.0))
        return NULL;
    sim_scene *sc = scene_alloc(nv, nt);
    if (!sc)
        return NULL;
    memcpy(sc->tris, tris, (size_t)nt * 3 * sizeof *tris);
    sc->kind = 3;
    sc->frames = frames;
    sc->rec_xyz = xyz;
    sc->rec_joints = joint_floats > 0 ? joints : NULL;
    sc->joint_floats = sc->rec_joints ? joint_floats : 0;
    sc->has_joints = sc->rec_joints != NULL;
    sc->frame_dt_s = frame_dt_s;
    if (!sc->rec_joints)
        free(joints);
    return sc;
}

/* kind 3: the recorded body nearest t_s (the last one past the end). */
static void recorded_eval(sim_scene *sc, double t_s)
{
    double k = isfinite(t_s) ? floor(t_s / sc->frame_dt_s + 0.5) : 0.0;
    int f = k < 0.0 ? 0 : (k >= (double)sc->frames ? sc->frames - 1 : (int)k);
    memcpy(sc->xyz, sc->rec_xyz + (size_t)f * sc->nv * 3, (size_t)sc->nv * 3 * sizeof *sc->xyz);
    if (sc->rec_joints)
        memcpy(sc->joints, sc->rec_joints + (size_t)f * sc->joint_floats,
               (size_t)sc->joint_floats * sizeof *sc->joints);
}

static int is_log(const char *motion)
{
    size_t n = strlen(motion);
    return n > 7 && strcmp(motion + n - 7, ".lcmlog") == 0;
}

#ifndef SIM_HAVE_BUS
sim_scene *sim_scene_log(const char *path, char *err, size_t err_size)
{
    snprintf(err, err_size, "%s: built without the bus (bus/), no LCM log can be read", path);
    return NULL;
}
#endif

/* UV sphere: rings of latitude between two poles. */
static void sphere_mesh(float *xyz, int32_t *tris, int rings, int segs, float r, const float c[3])
{
    int v = 0, t = 0;
    xyz[v++] = c[0], xyz[v++] = c[1] + r, xyz[v++] = c[2];
    for (int i = 1; i < rings; i++) {
        float th = SCENE_PI * (float)i / (float)rings;
        for (int j = 0; j < segs; j++) {
            float ph = 2.0f * SCENE_PI * (float)j / (float)segs;
            xyz[v++] = c[0] + r * sinf(th) * cosf(ph);
            xyz[v++] = c[1] + r * cosf(th);
            xyz[v++] = c[2] - r * sinf(th) * sinf(ph);
        }
    }
    xyz[v++] = c[0], xyz[v++] = c[1] - r, xyz[v++] = c[2];
    int south = 1 + (rings - 1) * segs;
    for (int j = 0; j < segs; j++) {
        int j1 = (j + 1) % segs;
        tris[t++] = 0, tris[t++] = 1 + j, tris[t++] = 1 + j1;
        int a = 1 + (rings - 2) * segs;
        tris[t++] = south, tris[t++] = a + j1, tris[t++] = a + j;
    }
    for (int i = 0; i + 2 < rings; i++) {
        for (int j = 0; j < segs; j++) {
            int j1 = (j + 1) % segs;
            int a = 1 + i * segs + j, b = 1 + i * segs + j1;
            int cc = 1 + (i + 1) * segs + j, d = 1 + (i + 1) * segs + j1;
            tris[t++] = a, tris[t++] = cc, tris[t++] = b;
            tris[t++] = b, tris[t++] = cc, tris[t++] = d;
        }
    }
}

sim_scene *sim_scene_sphere(float radius_m, const float centre[3], int n_triangles)
{
    int rings = (int)sqrtf((float)n_triangles / 4.0f);
    rings = rings < 4 ? 4 : rings;
    int segs = 2 * rings;
    sim_scene *sc = scene_alloc(2 + (rings - 1) * segs, 2 * segs * (rings - 1));
    if (!sc)
        return NULL;
    sphere_mesh(sc->rest, sc->tris, rings, segs, radius_m, centre);
    memcpy(sc->xyz, sc->rest, (size_t)sc->nv * 3 * sizeof *sc->xyz);
    return sc;
}

/* "all": each motion plays a whole number of its cycles or half-cycles, so that it ends in the
 * pose it started from: arm raise up and down (4 s), turn left and back (3 s), three steps of the
 * walk (3.3 s), four swings (3.2 s). */
static const struct {
    const char *name;
    double seconds;
} segments[] = {
    {"still", 3.0}, {"arm_raise", 4.0}, {"turn", 3.0}, {"walk", 3.3}, {"fast_swing", 3.2}};
#define SCENE_MOTIONS ((int)(sizeof segments / sizeof segments[0]))

static double all_duration(void)
{
    double total = 0.0;
    for (int i = 0; i < SCENE_MOTIONS; i++)
        total += segments[i].seconds;
    return total;
}

int sim_scene_segment(const sim_scene *sc, double t_s, double *local_s)
{
    if (sc->kind == 0 || sc->motion != -1) {
        if (local_s)
            *local_s = t_s;
        return -1;
    }
    return sim_scene_all_segment(t_s, local_s);
}

int sim_scene_all_segment(double t_s, double *local_s)
{
    double t = fmod(t_s, all_duration());
    int k = 0;
    while (k + 1 < SCENE_MOTIONS && t >= segments[k].seconds)
        t -= segments[k++].seconds;
    if (local_s)
        *local_s = t;
    return k;
}

int sim_scene_segment_count(void)
{
    return SCENE_MOTIONS;
}

const char *sim_scene_segment_name(int k)
{
    return k >= 0 && k < SCENE_MOTIONS ? segments[k].name : "none";
}

#ifdef SIM_HAVE_BODYFIT
/* The pose of "all" at t_s: the motions one after the other, each crossfading from the one
 * before over its first SCENE_BLEND_S (the previous motion plays on while its weight falls, a
 * smoothstep), so the body never jumps between segments: a person does not go from an arm
 * raised to 100 degrees to the A-pose in one frame, and the jump would measure the scene's cut,
 * not the cloth. The very first segment starts from its own pose. */
static void all_motions_pose(const sim_scene *sc, double t_s, fit_pose *pose)
{
    double t;
    int k = sim_scene_segment(sc, t_s, &t);
    fit_motion_eval((fit_motion)fit_motion_from_name(segments[k].name), t, pose);
    if (t >= SCENE_BLEND_S || (k == 0 && t_s < all_duration()))
        return;
    int prev = (k + SCENE_MOTIONS - 1) % SCENE_MOTIONS;
    fit_pose from;
    fit_motion_eval((fit_motion)fit_motion_from_name(segments[prev].name),
                    segments[prev].seconds + t, &from);
    double u = t / SCENE_BLEND_S, w = u * u * (3.0 - 2.0 * u);
    for (int k3 = 0; k3 < 3; k3++) {
        pose->root[k3] = (float)((1.0 - w) * from.root[k3] + w * pose->root[k3]);
        for (int j = 0; j < FIT_JOINT_COUNT; j++) /* rotation vectors */
            pose->rot[j][k3] = (float)((1.0 - w) * from.rot[j][k3] + w * pose->rot[j][k3]);
    }
}

static int is_bvh(const char *motion)
{
    size_t n = strlen(motion);
    return n > 4 && strcmp(motion + n - 4, ".bvh") == 0;
}

/* motion FILE.bvh: the clip retargeted onto the scene's model. */
static int load_clip(sim_scene *sc, const char *path, char *err, size_t err_size)
{
    fit_bvh *b = NULL;
    int rc = fit_bvh_load(path, &b, err, err_size);
    if (!rc)
        rc = fit_clip_from_bvh(b, sc->model, &sc->clip, err, err_size);
    fit_bvh_destroy(b);
    return rc;
}

/* "NAME@SPEED[,AMOUNT]": a scripted motion played SPEED times as fast, its joint rotations times
   AMOUNT (the stability map's axes: arms_down@1,1.15 holds the arms vertical, bend_forward@2 bends
   at 2 Hz). name gets NAME. Returns 0, or -1 with err filled. */
static int motion_scale(const char *motion, char *name, size_t name_size, double *speed,
                        double *amount, char *err, size_t err_size)
{
    *speed = *amount = 1.0;
    const char *at = strchr(motion, '@');
    size_t n = at ? (size_t)(at - motion) : strlen(motion);
    if (n >= name_size) {
        snprintf(err, err_size, "motion '%.40s...' too long", motion);
        return -1;
    }
    memcpy(name, motion, n);
    name[n] = '\0';
    if (!at)
        return 0;
    char *end;
    *speed = strtod(at + 1, &end);
    if (*end == ',')
        *amount = strtod(end + 1, &end);
    if (*end != '\0' || !(*speed > 0.0 && *speed <= 10.0) || !(*amount >= 0.0 && *amount <= 3.0) ||
        fit_motion_from_name(name) < 0) {
        snprintf(err, err_size,
                 "motion '%s': NAME@SPEED[,AMOUNT] takes a scripted motion, 0 < SPEED <= 10 and "
                 "0 <= AMOUNT <= 3",
                 motion);
        return -1;
    }
    return 0;
}

sim_scene *sim_scene_body(const char *motion, int target_vertices, char *err, size_t err_size)
{
    if (is_log(motion))
        return sim_scene_log(motion, err, err_size);
    int m = is_bvh(motion) ? -2 : -1;
    char name[64];
    double speed = 1.0, amount = 1.0;
    if (!is_bvh(motion) &&
        motion_scale(motion, name, sizeof name, &speed, &amount, err, err_size) != 0)
        return NULL;
    if (strcmp(motion, "all") != 0 && !is_bvh(motion) && (m = fit_motion_from_name(name)) < 0) {
        snprintf(err, err_size, "motion '%s' unknown", motion);
        return NULL;
    }
    fit_model_desc md = {.shape = fit_shape_default(), .target_vertices = target_vertices};
    fit_model *model = fit_model_create(&md, err, err_size);
    if (!model)
        return NULL;
    sim_scene *sc = scene_alloc(fit_model_vertex_count(model), fit_model_triangle_count(model));
    if (!sc) {
        fit_model_destroy(model);
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    sc->model = model;
    sc->kind = 1;
    sc->motion = m;
    sc->speed = speed;
    sc->amount = amount;
    sc->has_joints = 1;
    memcpy(sc->tris, fit_model_triangles(model), (size_t)sc->nt * 3 * sizeof *sc->tris);
    if (is_bvh(motion) && load_clip(sc, motion, err, err_size) != 0) {
        sim_scene_destroy(sc);
        return NULL;
    }
    return sc;
}

/* A clip's pose at t_s: SCENE_CLIP_IN_S from the A-pose (rotations 0) at the clip's first root
 * position into its first pose (a smoothstep), then the clip. */
static void clip_pose(const fit_clip *clip, double t_s, fit_pose *pose)
{
    double t = isfinite(t_s) ? fmod(t_s, SCENE_CLIP_IN_S + fit_clip_duration(clip)) : 0.0;
    t = t < 0.0 ? 0.0 : t;
    if (t >= SCENE_CLIP_IN_S) {
        fit_clip_eval(clip, t - SCENE_CLIP_IN_S, pose);
        return;
    }
    fit_clip_eval(clip, 0.0, pose);
    double u = t / SCENE_CLIP_IN_S, w = u * u * (3.0 - 2.0 * u);
    for (int j = 0; j < FIT_JOINT_COUNT; j++) /* rotation vectors, from 0 */
        for (int k = 0; k < 3; k++)
            pose->rot[j][k] = (float)(w * pose->rot[j][k]);
}

/* A scripted motion at t_s, sped up and its rotations scaled (motion_scale). */
static void scaled_motion_pose(const sim_scene *sc, double t_s, fit_pose *pose)
{
    fit_motion_eval((fit_motion)sc->motion, t_s * sc->speed, pose);
    if (sc->amount != 1.0)
        for (int j = 0; j < FIT_JOINT_COUNT; j++) /* rotation vectors: the angle scaled */
            for (int k = 0; k < 3; k++)
                pose->rot[j][k] = (float)(sc->amount * pose->rot[j][k]);
}

int sim_scene_eval(sim_scene *sc, double t_s, const float **xyz, int *nv, const int32_t **tris,
                   int *nt, const float **joints)
{
    if (sc->kind == 3)
        recorded_eval(sc, t_s);
    if (sc->kind == 1) {
        fit_pose pose;
        if (sc->clip)
            clip_pose(sc->clip, t_s, &pose);
        else if (sc->motion >= 0)
            scaled_motion_pose(sc, t_s, &pose);
        else
            all_motions_pose(sc, t_s, &pose);
        if (fit_model_pose(sc->model, &pose, sc->xyz, sc->joints) < 0)
            return -1;
    }
    *xyz = sc->xyz;
    *nv = sc->nv;
    *tris = sc->tris;
    *nt = sc->nt;
    if (joints)
        *joints = sc->has_joints ? sc->joints : NULL;
    return 0;
}

double sim_scene_duration(const sim_scene *sc)
{
    if (sc->kind == 3)
        return sc->frames * sc->frame_dt_s;
    if (sc->kind != 1)
        return 1e9;
    if (sc->clip)
        return SCENE_CLIP_IN_S + fit_clip_duration(sc->clip);
    if (sc->motion >= 0)
        return fit_motion_duration((fit_motion)sc->motion) / sc->speed;
    return all_duration();
}
#else
/* Without bodyfit: a capsule figure (torso and two arms, as separate closed spheres stretched
 * into ellipsoids) whose arms swing fore and aft, the wrists reaching 3 m/s in fast_swing. */
#define FIG_PARTS 3
static const float fig_centre[FIG_PARTS][3] = {{0, 1.25f, 0}, {-0.24f, 1.2f, 0}, {0.24f, 1.2f, 0}};
static const float fig_radii[FIG_PARTS][3] = {
    {0.16f, 0.32f, 0.11f}, {0.05f, 0.3f, 0.05f}, {0.05f, 0.3f, 0.05f}};
#define FIG_RINGS 16

sim_scene *sim_scene_body(const char *motion, int target_vertices, char *err, size_t err_size)
{
    (void)target_vertices;
    if (is_log(motion))
        return sim_scene_log(motion, err, err_size);
    int m = -1;
    for (int i = 0; i < SCENE_MOTIONS; i++)
        if (strcmp(motion, segments[i].name) == 0)
            m = i;
    if (m < 0 && strcmp(motion, "all") != 0) {
        snprintf(err, err_size, "motion '%s' unknown", motion);
        return NULL;
    }
    int pv = 2 + (FIG_RINGS - 1) * 2 * FIG_RINGS, pt = 2 * 2 * FIG_RINGS * (FIG_RINGS - 1);
    sim_scene *sc = scene_alloc(pv * FIG_PARTS, pt * FIG_PARTS);
    if (!sc) {
        snprintf(err, err_size, "out of memory");
        return NULL;
    }
    for (int p = 0; p < FIG_PARTS; p++) {
        float o[3] = {0, 0, 0};
        sphere_mesh(sc->rest + p * pv * 3, sc->tris + p * pt * 3, FIG_RINGS, 2 * FIG_RINGS, 1.0f,
                    o);
        for (int i = 0; i < pv; i++)
            for (int d = 0; d < 3; d++)
                sc->rest[(p * pv + i) * 3 + d] =
                    sc->rest[(p * pv + i) * 3 + d] * fig_radii[p][d] + fig_centre[p][d];
        for (int i = 0; i < pt * 3; i++)
            sc->tris[p * pt * 3 + i] += p * pv;
    }
    sc->kind = 2;
    sc->motion = m;
    return sc;
}

int sim_scene_eval(sim_scene *sc, double t_s, const float **xyz, int *nv, const int32_t **tris,
                   int *nt, const float **joints)
{
    if (sc->kind == 3)
        recorded_eval(sc, t_s);
    if (sc->kind == 2) {
        /* arms swing about the shoulder (y = 1.5 m); fast_swing: amplitude 0.9 rad at 1.6 Hz
         * gives 0.55 m * 0.9 * 2 pi * 1.6 = 5 m/s peak at the hand */
        int m = sc->motion < 0 ? sim_scene_segment(sc, t_s, NULL) : sc->motion;
        float amp = m == 4 ? 0.9f : (m == 0 ? 0.0f : 0.3f);
        float freq = m == 4 ? 1.6f : 0.5f;
        int pv = sc->nv / FIG_PARTS;
        memcpy(sc->xyz, sc->rest, (size_t)sc->nv * 3 * sizeof *sc->xyz);
        for (int p = 1; p < FIG_PARTS; p++) {
            float a = amp * sinf(2.0f * SCENE_PI * freq * (float)t_s) * (p == 1 ? 1.0f : -1.0f);
            for (int i = p * pv; i < (p + 1) * pv; i++) {
                float y = sc->rest[i * 3 + 1] - 1.5f, z = sc->rest[i * 3 + 2];
                sc->xyz[i * 3 + 1] = 1.5f + y * cosf(a) - z * sinf(a);
                sc->xyz[i * 3 + 2] = y * sinf(a) + z * cosf(a);
            }
        }
    }
    *xyz = sc->xyz;
    *nv = sc->nv;
    *tris = sc->tris;
    *nt = sc->nt;
    if (joints)
        *joints = NULL;
    return 0;
}

double sim_scene_duration(const sim_scene *sc)
{
    if (sc->kind == 3)
        return sc->frames * sc->frame_dt_s;
    return sc->kind == 2 ? (sc->motion < 0 ? all_duration() : 1e9) : 1e9;
}
#endif
