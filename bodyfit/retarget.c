/* Retargeting a BVH clip onto the body model: each model bone turns in the world as the clip's
 * matching bone does, measured from the two rest poses, then joint by joint down the tree the
 * local rotation is kept to the hinge (elbows, knees) and to the joint limits. */
#include "mocap.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct fit_clip {
    int frames;
    double start_s; /* the file's time of clip frame 0 */
    fit_pose *pose; /* [frames] */
    int src[FIT_JOINT_COUNT];
};

/* Where the clip's rest skeleton and the model's differ, per model joint. */
typedef struct retarget_map {
    int src[FIT_JOINT_COUNT];       /* the BVH joint whose world rotation drives the model joint */
    double fix[FIT_JOINT_COUNT][9]; /* C: model rest bone direction onto the clip's (W = G C) */
    double hinge[FIT_JOINT_COUNT][3]; /* unit hinge axis (elbows, knees), else zero */
    double flex[FIT_JOINT_COUNT];     /* sign of flexion about the hinge: +1 knees, -1 elbows */
    double dir[FIT_JOINT_COUNT][3];   /* the model's rest bone direction out of each joint */
    double rest[FIT_JOINT_COUNT][3];  /* the model's rest joint centres, m */
    int toe[2];
    double scale;      /* model metres per file unit: ratio of the leg lengths */
    double leg_file;   /* the clip's leg length, file units */
    int first;         /* the file's first frame of motion (1: frame 0 is a reference pose) */
    double hips0[3];   /* the clip's first hips position, file units */
    double floor_y;    /* lowest toe of the clip, file units */
    double pelvis_toe; /* model pelvis joint above its toe joints at rest, m */
} retarget_map;

static int find_any(const fit_bvh *b, const char *const *names)
{
    for (; *names; ++names) {
        int j = fit_bvh_find_joint(b, *names);
        if (j >= 0)
            return j;
    }
    return -1;
}

static int first_child(const fit_bvh *b, int j)
{
    for (int c = j + 1; c < b->joint_count; ++c)
        if (b->joint[c].parent == j)
            return c;
    return -1;
}

/* The clip's joints by structure from the hand, the foot and the head up, so both the CMU
 * naming (LeftShoulder = clavicle) and the usual one (LeftCollar, LeftShoulder) map. */
static int map_joints(const fit_bvh *b, int src[FIT_JOINT_COUNT], char *err, size_t errlen)
{
    static const char *const hand[2][4] = {{"LeftHand", "LeftWrist", "LHand", NULL},
                                           {"RightHand", "RightWrist", "RHand", NULL}};
    static const char *const foot[2][4] = {{"LeftFoot", "LeftAnkle", "LFoot", NULL},
                                           {"RightFoot", "RightAnkle", "RFoot", NULL}};
    static const char *const head[] = {"Head", "head", NULL};
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        src[j] = -1;
    src[FIT_PELVIS] = 0;
    src[FIT_HEAD] = find_any(b, head);
    src[FIT_NECK] = fit_bvh_joint_parent(b, src[FIT_HEAD]);
    for (int side = 0; side < 2; ++side) {
        int w = side ? FIT_R_WRIST : FIT_L_WRIST, a = side ? FIT_R_ANKLE : FIT_L_ANKLE;
        src[w] = find_any(b, hand[side]);
        for (int k = 1; k <= 3; ++k) /* elbow, shoulder, clavicle */
            src[w - k] = fit_bvh_joint_parent(b, src[w - k + 1]);
        src[a] = find_any(b, foot[side]);
        src[a - 1] = fit_bvh_joint_parent(b, src[a]);
        src[a - 2] = fit_bvh_joint_parent(b, src[a - 1]);
        src[a + 1] = first_child(b, src[a]);
        if (src[a + 1] < 0) /* no toe joint: the foot's own turn, towards its End Site */
            src[a + 1] = src[a];
    }
    src[FIT_CHEST] = fit_bvh_joint_parent(b, src[FIT_L_CLAVICLE]);
    src[FIT_SPINE] = fit_bvh_joint_parent(b, src[FIT_CHEST]);
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        if (src[j] < 0 || (j != FIT_PELVIS && src[j] == 0)) {
            if (err)
                snprintf(err, errlen, "bvh: no joint of the clip matches the model's '%s'",
                         fit_joint_name((fit_joint)j));
            return -FIT_ERR_ARG;
        }
    }
    return 0;
}

static double normalise(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0.0)
        for (int k = 0; k < 3; ++k)
            v[k] /= n;
    return n;
}

/* The clip's rest-pose direction out of joint j: towards the joint driving the model child,
 * else the first child chain with a length, else the End Site. Rest rotations are identity,
 * so offsets add up. */
static double clip_rest_dir(const fit_bvh *b, int j, int to, double d[3])
{
    if (to > j) {
        double s[3] = {0, 0, 0};
        for (int c = to; c != j && c >= 0; c = b->joint[c].parent)
            for (int k = 0; k < 3; ++k)
                s[k] += b->joint[c].offset[k];
        memcpy(d, s, sizeof s);
        if (normalise(d) > 0.0)
            return 1.0;
    }
    for (int c = first_child(b, j); c >= 0; c = first_child(b, c)) {
        for (int k = 0; k < 3; ++k)
            d[k] = b->joint[c].offset[k];
        if (normalise(d) > 0.0)
            return 1.0;
    }
    for (int k = 0; k < 3; ++k)
        d[k] = b->joint[j].has_end ? b->joint[j].end_offset[k] : 0.0;
    return normalise(d);
}

static int model_child(fit_joint j)
{
    for (int c = 0; c < FIT_JOINT_COUNT; ++c)
        if (fit_joint_parent((fit_joint)c) == (int)j)
            return (j == FIT_CHEST) ? FIT_NECK : c; /* the chest's bone is the neck's */
    return -1;
}

static void model_rest_dir(const float *rest, fit_joint j, double d[3])
{
    int c = model_child(j);
    if (c >= 0) {
        for (int k = 0; k < 3; ++k)
            d[k] = rest[c * 3 + k] - rest[j * 3 + k];
    } else if (j == FIT_HEAD) {
        d[0] = 0, d[1] = 1, d[2] = 0;
    } else if (j == FIT_L_TOE || j == FIT_R_TOE) {
        d[0] = 0, d[1] = 0, d[2] = 1;
    } else { /* wrists: on along the forearm */
        int p = fit_joint_parent(j);
        for (int k = 0; k < 3; ++k)
            d[k] = rest[j * 3 + k] - rest[p * 3 + k];
    }
    normalise(d);
}

static double leg_length(const fit_bvh *b, int hip, int ankle)
{
    double s[3] = {0, 0, 0};
    for (int c = ankle; c != hip && c >= 0; c = b->joint[c].parent)
        for (int k = 0; k < 3; ++k)
            s[k] += b->joint[c].offset[k];
    return normalise(s);
}

static int build_map(const fit_bvh *b, const fit_model *m, retarget_map *map, char *err,
                     size_t errlen)
{
    int rc = map_joints(b, map->src, err, errlen);
    if (rc)
        return rc;
    const float *rest = fit_model_rest_joints(m);
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        double dm[3], db[3];
        int c = model_child((fit_joint)j);
        model_rest_dir(rest, (fit_joint)j, dm);
        memcpy(map->dir[j], dm, sizeof dm);
        for (int k = 0; k < 3; ++k)
            map->rest[j][k] = rest[j * 3 + k];
        memset(map->hinge[j], 0, sizeof map->hinge[j]);
        map->flex[j] = (j == FIT_L_KNEE || j == FIT_R_KNEE) ? 1.0 : -1.0;
        if (j == FIT_PELVIS || clip_rest_dir(b, map->src[j], c >= 0 ? map->src[c] : -1, db) == 0) {
            for (int k = 0; k < 9; ++k)
                map->fix[j][k] = (k % 4 == 0) ? 1.0 : 0.0;
        } else {
            mocap_mat_between(dm, db, map->fix[j]);
        }
        if (j == FIT_L_ELBOW || j == FIT_R_ELBOW || j == FIT_L_KNEE || j == FIT_R_KNEE) {
            float ax[3] = {1.0f, 0.0f, 0.0f}, w[3];
            fit_joint_from_anatomical((fit_joint)j, ax, w);
            for (int k = 0; k < 3; ++k)
                map->hinge[j][k] = w[k];
        }
    }
    double lb = 0.5 * (leg_length(b, map->src[FIT_L_HIP], map->src[FIT_L_ANKLE]) +
                       leg_length(b, map->src[FIT_R_HIP], map->src[FIT_R_ANKLE]));
    if (!(lb > 0.0)) {
        if (err)
            snprintf(err, errlen, "bvh: the clip's legs have no length");
        return -FIT_ERR_ARG;
    }
    map->scale = fit_model_shape(m)->leg_length / lb;
    map->leg_file = lb;
    map->toe[0] = map->src[FIT_L_TOE];
    map->toe[1] = map->src[FIT_R_TOE];
    map->pelvis_toe =
        rest[FIT_PELVIS * 3 + 1] - 0.5 * (rest[FIT_L_TOE * 3 + 1] + rest[FIT_R_TOE * 3 + 1]);
    return 0;
}

/* The swing-twist split: the part of q that turns about unit axis h. */
static void twist_about(const double q[4], const double h[3], double out[4])
{
    double d = q[1] * h[0] + q[2] * h[1] + q[3] * h[2];
    double t[4] = {q[0], d * h[0], d * h[1], d * h[2]};
    double n = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2] + t[3] * t[3]);
    if (n < 1e-9) {
        out[0] = 1.0, out[1] = out[2] = out[3] = 0.0;
        return;
    }
    for (int k = 0; k < 4; ++k)
        out[k] = t[k] / n;
}

static int is_hinge(const retarget_map *map, int j)
{
    return j >= 0 &&
           (map->hinge[j][0] != 0.0 || map->hinge[j][1] != 0.0 || map->hinge[j][2] != 0.0);
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* A bent elbow or knee can only bend about its hinge: twist the upper arm (thigh) target about
 * its own bone so the hinge lies normal to the plane the clip's limb bends in. Nearly straight
 * limbs define no plane: the twist fades out between 5 and 20 degrees of bend. */
static void align_hinge(const retarget_map *map, double g[][9], int j, int child, double w[9])
{
    double u[3], f[3], h[3], want[3], t[9];
    mocap_mat_apply(w, map->dir[j], u);
    mocap_mat_mul(g[map->src[child]], map->fix[child], t);
    mocap_mat_apply(t, map->dir[child], f);
    mocap_mat_apply(w, map->hinge[child], h);
    cross(u, f, want);
    double s = normalise(want), lo = sin(5.0 * 0.017453292519943295),
           hi = sin(20.0 * 0.017453292519943295);
    if (s < lo)
        return;
    for (int k = 0; k < 3; ++k)
        want[k] *= map->flex[child];
    double e = s > hi ? 1.0 : (s - lo) / (hi - lo);
    e = e * e * (3.0 - 2.0 * e);
    double c[3];
    cross(h, want, c);
    double phi = e * atan2(dot(c, u), dot(h, want));
    double q[4] = {cos(0.5 * phi), sin(0.5 * phi) * u[0], sin(0.5 * phi) * u[1],
                   sin(0.5 * phi) * u[2]};
    mocap_quat_to_mat(q, t);
    mocap_mat_mul(t, w, w);
}

static int hinge_child(const retarget_map *map, int j)
{
    for (int c = j + 1; c < FIT_JOINT_COUNT; ++c)
        if (fit_joint_parent((fit_joint)c) == j && is_hinge(map, c))
            return c;
    return -1;
}

/* One clip frame from the clip's world rotations g and hips position. Returns the lowest toe
 * joint's height as posed. */
static double frame_pose(const retarget_map *map, double g[][9], const double hips[3],
                         fit_pose *out)
{
    double w[FIT_JOINT_COUNT][9]; /* the model's world rotations as posed */
    double x[FIT_JOINT_COUNT][3]; /* and its joint centres */
    memset(out, 0, sizeof *out);
    out->root[0] = (float)(map->scale * (hips[0] - map->hips0[0]));
    out->root[1] = (float)(map->scale * (hips[1] - map->floor_y) - map->pelvis_toe);
    out->root[2] = (float)(map->scale * (hips[2] - map->hips0[2]));
    for (int j = 0; j < FIT_JOINT_COUNT; ++j) {
        double target[9], local[9], q[4];
        mocap_mat_mul(g[map->src[j]], map->fix[j], target);
        int c = hinge_child(map, j);
        if (c >= 0)
            align_hinge(map, g, j, c, target);
        int p = fit_joint_parent((fit_joint)j);
        if (p >= 0)
            mocap_mat_tmul(w[p], target, local);
        else
            memcpy(local, target, sizeof local);
        mocap_mat_to_quat(local, q);
        if (is_hinge(map, j))
            twist_about(q, map->hinge[j], q);
        fit_pose one;
        memset(&one, 0, sizeof one);
        mocap_quat_to_axis_angle(q, one.rot[j]);
        fit_pose_clamp(&one);
        memcpy(out->rot[j], one.rot[j], sizeof one.rot[j]);
        /* the rotation as clamped, so the children make up for what the limits took */
        double a[3] = {one.rot[j][0], one.rot[j][1], one.rot[j][2]};
        double th = normalise(a);
        double qc[4] = {cos(0.5 * th), sin(0.5 * th) * a[0], sin(0.5 * th) * a[1],
                        sin(0.5 * th) * a[2]};
        mocap_quat_to_mat(qc, local);
        if (p >= 0) {
            double d[3] = {map->rest[j][0] - map->rest[p][0], map->rest[j][1] - map->rest[p][1],
                           map->rest[j][2] - map->rest[p][2]};
            mocap_mat_mul(w[p], local, w[j]);
            mocap_mat_apply(w[p], d, x[j]);
            for (int k = 0; k < 3; ++k)
                x[j][k] += x[p][k];
        } else {
            memcpy(w[j], local, sizeof local);
            for (int k = 0; k < 3; ++k)
                x[j][k] = map->rest[j][k] + out->root[k];
        }
    }
    return fmin(x[FIT_L_TOE][1], x[FIT_R_TOE][1]);
}

/* The clip's world rotations and hips at time t: the two nearest frames, slerped. */
static int sample(const fit_bvh *b, double t, float *pa, float *ra, float *pb, float *rb,
                  double g[][9], double hips[3])
{
    double fi = t / b->frame_time_s;
    int f0 = (int)floor(fi);
    f0 = f0 < 0 ? 0 : (f0 >= b->frames ? b->frames - 1 : f0);
    int f1 = f0 + 1 < b->frames ? f0 + 1 : f0;
    double a = fi - f0;
    a = a < 0.0 ? 0.0 : (a > 1.0 ? 1.0 : a);
    int rc = fit_bvh_world(b, f0, pa, ra);
    if (!rc)
        rc = fit_bvh_world(b, f1, pb, rb);
    if (rc)
        return rc;
    for (int j = 0; j < b->joint_count; ++j) {
        double ma[9], mb[9], qa[4], qb[4], q[4];
        for (int k = 0; k < 9; ++k) {
            ma[k] = ra[j * 9 + k];
            mb[k] = rb[j * 9 + k];
        }
        mocap_mat_to_quat(ma, qa);
        mocap_mat_to_quat(mb, qb);
        mocap_quat_slerp(qa, qb, a, q);
        mocap_quat_to_mat(q, g[j]);
    }
    for (int k = 0; k < 3; ++k)
        hips[k] = (1.0 - a) * pa[k] + a * pb[k];
    return 0;
}

/* The lowest the clip's toe joints ever go: the floor the model's toes stand on. */
static int clip_floor(const fit_bvh *b, retarget_map *map, float *pos)
{
    map->floor_y = INFINITY;
    for (int f = map->first; f < b->frames; ++f) {
        int rc = fit_bvh_world(b, f, pos, NULL);
        if (rc)
            return rc;
        if (f == map->first)
            for (int k = 0; k < 3; ++k)
                map->hips0[k] = pos[k];
        for (int s = 0; s < 2; ++s)
            map->floor_y = fmin(map->floor_y, pos[map->toe[s] * 3 + 1]);
    }
    return 0;
}

/* CMU's clips open on a reference T-pose, then jump to the motion: frame 0 is dropped when some
 * joint moves from it to frame 1 by more than a tenth of a leg (10 m/s at 120 fps: no person
 * moves so in a frame). */
static int reference_frame(const fit_bvh *b, const retarget_map *map, float *pa, float *pb)
{
    if (b->frames < 3 || fit_bvh_world(b, 0, pa, NULL) || fit_bvh_world(b, 1, pb, NULL))
        return 0;
    double worst = 0.0;
    for (int j = 0; j < b->joint_count; ++j) {
        double d2 = 0.0;
        for (int k = 0; k < 3; ++k)
            d2 += (pa[j * 3 + k] - pb[j * 3 + k]) * (pa[j * 3 + k] - pb[j * 3 + k]);
        worst = fmax(worst, d2);
    }
    return sqrt(worst) > 0.1 * map->leg_file;
}

int fit_clip_from_bvh(const fit_bvh *b, const fit_model *m, fit_clip **out, char *err,
                      size_t errlen)
{
    if (!b || !m || !out)
        return -FIT_ERR_ARG;
    *out = NULL;
    retarget_map map;
    int rc = build_map(b, m, &map, err, errlen);
    if (rc)
        return rc;
    size_t nj = (size_t)b->joint_count;
    float *buf = malloc(nj * 24 * sizeof(float));
    map.first = buf ? reference_frame(b, &map, buf, buf + nj * 3) : 0;
    double start = map.first * b->frame_time_s, span = (b->frames - 1) * b->frame_time_s - start;
    int n = (int)floor(span * FIT_CLIP_FPS + 1e-6) + 1;
    fit_clip *c = calloc(1, sizeof *c);
    double(*g)[9] = malloc(nj * sizeof *g);
    if (c)
        c->pose = malloc((size_t)n * sizeof *c->pose);
    rc = (c && c->pose && buf && g) ? 0 : -FIT_ERR_NOMEM;
    if (!rc)
        rc = clip_floor(b, &map, buf);
    double toe_lo = INFINITY;
    for (int f = 0; f < n && !rc; ++f) {
        double hips[3];
        rc = sample(b, start + (double)f / FIT_CLIP_FPS, buf, buf + nj * 3, buf + nj * 12,
                    buf + nj * 15, g, hips);
        if (!rc)
            toe_lo = fmin(toe_lo, frame_pose(&map, g, hips, &c->pose[f]));
    }
    /* The model's proportions are not the clip's: the lowest its toes go is their rest height
     * (the floor), so the feet neither float nor sink. */
    double lift = 0.5 * (map.rest[FIT_L_TOE][1] + map.rest[FIT_R_TOE][1]) - toe_lo;
    for (int f = 0; f < n && !rc; ++f)
        c->pose[f].root[1] += (float)lift;
    free(buf);
    free(g);
    if (rc) {
        fit_clip_destroy(c);
        return rc;
    }
    c->frames = n;
    c->start_s = start;
    memcpy(c->src, map.src, sizeof c->src);
    *out = c;
    return 0;
}

/* A rotation as a matrix, from the pose's axis-angle vector. */
static void axis_angle_mat(const float r[3], double m[9])
{
    double a[3] = {r[0], r[1], r[2]};
    double th = normalise(a);
    double q[4] = {cos(0.5 * th), sin(0.5 * th) * a[0], sin(0.5 * th) * a[1], sin(0.5 * th) * a[2]};
    mocap_quat_to_mat(q, m);
}

double fit_clip_face_camera(fit_clip *c)
{
    if (!c || c->frames < 1)
        return 0.0;
    /* the heading of frame 0: where the pelvis's forward (+z at rest: the camera) points, seen
       from above */
    double r0[9], f[3], fz[3] = {0.0, 0.0, 1.0};
    axis_angle_mat(c->pose[0].rot[FIT_PELVIS], r0);
    mocap_mat_apply(r0, fz, f);
    if (!(f[0] * f[0] + f[2] * f[2] > 1e-12))
        return 0.0; /* lying face up or down: no heading to take */
    double h = atan2(f[0], f[2]);
    double qy[4] = {cos(-0.5 * h), 0.0, sin(-0.5 * h), 0.0}, turn[9];
    mocap_quat_to_mat(qy, turn);
    for (int k = 0; k < c->frames; ++k) {
        fit_pose *p = &c->pose[k];
        double r[9], t[9], q[4];
        axis_angle_mat(p->rot[FIT_PELVIS], r);
        mocap_mat_mul(turn, r, t);
        mocap_mat_to_quat(t, q);
        mocap_quat_to_axis_angle(q, p->rot[FIT_PELVIS]);
        /* the path turns with the person, about where it starts (x = z = 0) */
        double at[3] = {p->root[0], 0.0, p->root[2]}, to[3];
        mocap_mat_apply(turn, at, to);
        p->root[0] = (float)to[0];
        p->root[2] = (float)to[2];
    }
    return h;
}

void fit_clip_destroy(fit_clip *c)
{
    if (!c)
        return;
    free(c->pose);
    free(c);
}

int fit_clip_frame_count(const fit_clip *c)
{
    return c ? c->frames : 0;
}

double fit_clip_duration(const fit_clip *c)
{
    return c ? (double)c->frames / FIT_CLIP_FPS : 0.0;
}

void fit_clip_eval(const fit_clip *c, double t_s, fit_pose *out)
{
    if (!out)
        return;
    if (!c || c->frames < 1 || !isfinite(t_s)) {
        memset(out, 0, sizeof *out);
        return;
    }
    double d = (double)c->frames / FIT_CLIP_FPS, t = fmod(t_s, d);
    long k = (long)floor((t < 0.0 ? t + d : t) * FIT_CLIP_FPS + 0.5) % c->frames;
    *out = c->pose[k];
}

double fit_clip_start(const fit_clip *c)
{
    return c ? c->start_s : 0.0;
}

int fit_clip_source_joint(const fit_clip *c, fit_joint j)
{
    return (c && j >= 0 && j < FIT_JOINT_COUNT) ? c->src[j] : -1;
}
