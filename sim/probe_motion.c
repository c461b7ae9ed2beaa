/* tryon-probe-motion: what a motion does to the body and to the shirt, frame by frame.
 *
 * The shirt of tryon-bench-sim's body scene on one motion (a scripted one or a BVH clip), and per
 * frame one CSV line: the published statistics, where the stretch springs over the strain goal
 * are on the garment (rows: top, middle, hem; sides: left, back, right, front at rest; with an
 * attached end; the body bone they lie nearest), the worst spring's place and the body's skin
 * stretch under it, what the body does (upper arms and thighs against the trunk, the trunk's
 * bend, the root's speed, the fastest body vertex) and whether its skin passes through itself
 * (probe.h; how many of those vertices lie at the arms and at the thighs). Findings and the
 * columns: docs/sim-real-motion.md, "Real motion: the causes".
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"
#include "collide_geometry.h"
#include "probe.h"
#include "scene.h"

#define PROBE_OVER     0.03f /* the strain goal: springs past it are counted */
#define PROBE_MAX_BONE 7

/* bodyfit's joint order (bodyfit.h FIT_JOINT_LIST), read from the scene's joint array */
enum { J_PELVIS = 0, J_CHEST = 2, J_NECK = 3, J_LSHO = 6, J_LELB = 7, J_LWRI = 8 };
enum { J_RSHO = 10, J_RELB = 11, J_RWRI = 12, J_LHIP = 13, J_LKNEE = 14, J_RHIP = 17 };
enum { J_RKNEE = 18 };
static const int bone_end[PROBE_MAX_BONE][2] = {
    {J_PELVIS, J_NECK}, {J_LSHO, J_LELB},  {J_LELB, J_LWRI}, {J_RSHO, J_RELB},
    {J_RELB, J_RWRI},   {J_LHIP, J_LKNEE}, {J_RHIP, J_RKNEE}};
static const char *bone_name[PROBE_MAX_BONE] = {"trunk",  "l_upper", "l_fore", "r_upper",
                                                "r_fore", "l_thigh", "r_thigh"};

typedef struct probe_opts {
    const char *motion;
    int frames, verts, iterations, body_verts;
    int dump_frame; /* --dump N: that frame as points (probe-body.xyz, probe-cloth.xyz) */
} probe_opts;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: tryon-probe-motion --motion NAME[@SPEED[,AMOUNT]]|FILE.bvh|FILE.lcmlog\n"
            "                          [--frames N] [--verts N] [--iterations K] [--body-verts N]\n"
            "                          [--dump N]\n"
            "(FILE.lcmlog: the bodies a recorded session published, tryon run --record DIR)\n"
            "The shirt of tryon-bench-sim's body scene on a motion (C backend, the clip's whole\n"
            "length unless --frames), one CSV line a frame on stdout: statistics, where the\n"
            "springs over 3 %% strain are, the pose, the skin passing through itself.\n"
            "--dump N writes frame N's body (x y z inside bone) and cloth (x y z strain row "
            "column) as\n"
            "probe-body.xyz and probe-cloth.xyz here. docs/sim-real-motion.md, \"Real motion:\n"
            "the causes\".\n");
}

static int parse(int argc, char **argv, probe_opts *o)
{
    *o = (probe_opts){NULL, 0, 7000, 25, 6000, -1};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            usage(stdout);
            exit(0);
        }
        if (i + 1 >= argc) {
            fprintf(stderr, "tryon-probe-motion: %s needs a value or is unknown\n", a);
            return -1;
        }
        const char *v = argv[++i];
        char *end = NULL;
        long n = strtol(v, &end, 10);
        int num = end && *end == '\0' && end != v;
        if (strcmp(a, "--motion") == 0)
            o->motion = v;
        else if (strcmp(a, "--frames") == 0 && num && n >= 0 && n <= 100000)
            o->frames = (int)n;
        else if (strcmp(a, "--verts") == 0 && num && n >= 200 && n <= 200000)
            o->verts = (int)n;
        else if (strcmp(a, "--iterations") == 0 && num && n >= 1 && n <= 1000)
            o->iterations = (int)n;
        else if (strcmp(a, "--dump") == 0 && num && n >= 0)
            o->dump_frame = (int)n;
        else if (strcmp(a, "--body-verts") == 0 && num && n >= 0 && n <= 100000)
            o->body_verts = (int)n;
        else {
            fprintf(stderr, "tryon-probe-motion: unknown option or bad value: %s %s\n", a, v);
            return -1;
        }
    }
    if (!o->motion) {
        fprintf(stderr, "tryon-probe-motion: --motion is required\n");
        return -1;
    }
    return 0;
}

static float dist2(const float *a, const float *b)
{
    float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

static int nearest_body_vertex(const float *p, const float *xyz, int nv)
{
    int best = 0;
    float bd = INFINITY;
    for (int i = 0; i < nv; i++) {
        float d = dist2(p, &xyz[i * 3]);
        if (d < bd)
            bd = d, best = i;
    }
    return best;
}

/* the largest stretch of the body's skin at vertex v: its triangles' edges against the rest */
static float skin_stretch(int v, const float *xyz, const float *rest, const int32_t *tris, int nt)
{
    float worst = 0.0f;
    for (int t = 0; t < nt; t++) {
        const int32_t *tr = &tris[t * 3];
        if (tr[0] != v && tr[1] != v && tr[2] != v)
            continue;
        for (int e = 0; e < 3; e++) {
            int a = tr[e], b = tr[(e + 1) % 3];
            float l0 = sqrtf(dist2(&rest[a * 3], &rest[b * 3]));
            float l = sqrtf(dist2(&xyz[a * 3], &xyz[b * 3]));
            if (l0 > 0.0f)
                worst = fmaxf(worst, l / l0 - 1.0f);
        }
    }
    return worst;
}

static int nearest_bone(const float *p, const float *j)
{
    int best = 0;
    float bd = INFINITY;
    for (int b = 0; b < PROBE_MAX_BONE; b++) {
        float d = sim_segment_dist2(p, &j[bone_end[b][0] * 3], &j[bone_end[b][1] * 3]);
        if (d < bd)
            bd = d, best = b;
    }
    return best;
}

/* The skin passing through itself (probe.h): how many body vertices, and of those how many lie
 * nearest an arm bone (*arms) and a thigh (*thighs). */
static int skin_inside(const sim *s, const float *xyz, int nv, const int32_t *tris, int nt,
                       float (*pts)[4], uint8_t *inside, const float *joints, int *arms,
                       int *thighs)
{
    int n = sim_probe_skin_inside(s->collider, xyz, nv, tris, nt, pts, inside);
    *arms = *thighs = 0;
    for (int i = 0; n > 0 && i < nv; i++) {
        if (!inside[i])
            continue;
        int b = nearest_bone(&xyz[i * 3], joints);
        *arms += b >= 1 && b <= 4;
        *thighs += b >= 5;
    }
    return n;
}

typedef struct garment_over {
    int n, attached, rows[3], sides[4], bones[PROBE_MAX_BONE], vertical;
    int worst;
    float worst_strain;
} garment_over;

/* the stretch springs past PROBE_OVER: where they are on the shirt's grid (cols x rows, row 0
 * the top, column c at 2 pi c / cols: 0 the model's left, a quarter the back) and on the body */
static void springs_over(const sim_cloth *c, int cols, int rows, const float *joints,
                         garment_over *o)
{
    memset(o, 0, sizeof *o);
    o->worst = -1;
    for (int s = 0; s < c->ns; s++) {
        if (c->kind[s] != SIM_SPRING_STRETCH)
            continue;
        int a = c->ends[s][0], b = c->ends[s][1];
        float strain = sqrtf(dist2(c->x[a], c->x[b])) / c->rest[s] - 1.0f;
        if (strain > o->worst_strain)
            o->worst_strain = strain, o->worst = s;
        if (strain <= PROBE_OVER)
            continue;
        o->n++;
        o->attached += c->x[a][3] == 0.0f || c->x[b][3] == 0.0f;
        int row = a / cols, col = a % cols;
        o->rows[row < rows / 5 ? 0 : (row < 4 * rows / 5 ? 1 : 2)]++;
        o->sides[((col * 8 + cols) / (2 * cols)) % 4]++;
        o->vertical += a / cols != b / cols;
        float mid[3];
        for (int d = 0; d < 3; d++)
            mid[d] = 0.5f * (c->x[a][d] + c->x[b][d]);
        o->bones[nearest_bone(mid, joints)]++;
    }
}

/* one frame as points for a plot: body x y z, inside another part (0/1, skin_inside) and the
 * nearest bone (0 trunk .. 6 r_thigh); cloth x y z strain (its largest stretch spring) */
static void dump(const sim *s, const float *xyz, int nv, int cols, const uint8_t *inside,
                 const float *joints)
{
    FILE *b = fopen("probe-body.xyz", "w"), *c = fopen("probe-cloth.xyz", "w");
    float *worst = calloc((size_t)s->cloth.nv, sizeof *worst);
    for (int i = 0; b && i < nv; i++)
        fprintf(b, "%.4f %.4f %.4f %d %d\n", xyz[i * 3], xyz[i * 3 + 1], xyz[i * 3 + 2], inside[i],
                nearest_bone(&xyz[i * 3], joints));
    for (int k = 0; worst && k < s->cloth.ns; k++) {
        if (s->cloth.kind[k] != SIM_SPRING_STRETCH)
            continue;
        int a = s->cloth.ends[k][0], e = s->cloth.ends[k][1];
        float strain = sqrtf(dist2(s->cloth.x[a], s->cloth.x[e])) / s->cloth.rest[k] - 1.0f;
        worst[a] = fmaxf(worst[a], strain);
        worst[e] = fmaxf(worst[e], strain);
    }
    for (int i = 0; c && worst && i < s->cloth.nv; i++)
        fprintf(c, "%.4f %.4f %.4f %.4f %d %d\n", s->cloth.x[i][0], s->cloth.x[i][1],
                s->cloth.x[i][2], worst[i], i / cols, i % cols);
    free(worst);
    if (b)
        fclose(b);
    if (c)
        fclose(c);
}

static int run(const probe_opts *o)
{
    char err[256] = "";
    sim_scene *sc = sim_scene_body(o->motion, o->body_verts, err, sizeof err);
    if (!sc) {
        fprintf(stderr, "tryon-probe-motion: %s\n", err);
        return 1;
    }
    sim_desc desc = sim_default_desc();
    desc.iterations = o->iterations;
    int frames =
        o->frames > 0 ? o->frames : (int)floor(sim_scene_duration(sc) / desc.frame_dt_s + 0.5);
    const float *xyz, *joints;
    const int32_t *tris;
    int nv, nt;
    sim_scene_eval(sc, 0.0, &xyz, &nv, &tris, &nt, &joints);
    sim_garment g = {0};
    sim_reject why = {0};
    int cols = 0, rows = 0;
    if (sim_garment_shirt(xyz, nv, tris, nt, joints, o->verts, 0.0f, 0.0f, &g, &why) < 0 ||
        sscanf(g.id, "shirt-%dx%d", &cols, &rows) != 2) {
        fprintf(stderr, "tryon-probe-motion: shirt: %s\n", why.detail);
        sim_garment_free(&g);
        sim_scene_destroy(sc);
        return 1;
    }
    sim *s = sim_create(&desc, &g, &why);
    sim_garment_free(&g);
    float *rest = malloc((size_t)nv * 3 * sizeof *rest), pelvis_prev[3];
    float(*pts)[4] = malloc((size_t)nv * sizeof *pts);
    uint8_t *inside = malloc((size_t)nv);
    if (!s || !rest || !pts || !inside) {
        fprintf(stderr, "tryon-probe-motion: %s\n", s ? "no memory" : why.detail);
        sim_destroy(s);
        free(rest);
        free(pts);
        free(inside);
        sim_scene_destroy(sc);
        return 1;
    }
    memcpy(rest, xyz, (size_t)nv * 3 * sizeof *rest);
    memcpy(pelvis_prev, &joints[J_PELVIS * 3], sizeof pelvis_prev);
    printf("frame,state,max_strain_pct,p99_pct,inside,depth_mm,settle,over,over_attached,"
           "over_top,over_mid,over_hem,over_left,over_back,over_right,over_front,over_vertical,"
           "near_trunk,near_l_upper,near_l_fore,near_r_upper,near_r_fore,near_l_thigh,"
           "near_r_thigh,worst_row,worst_col,worst_bone,worst_to_body_mm,worst_skin_pct,"
           "arm_l_deg,arm_r_deg,thigh_l_deg,thigh_r_deg,bend_deg,root_speed,body_fastest,"
           "skin_inside,skin_arms,skin_thighs\n");
    int bad = 0;
    for (int f = 0; f < frames && !bad; f++) {
        sim_scene_eval(sc, (double)f * desc.frame_dt_s, &xyz, &nv, &tris, &nt, &joints);
        sim_frame_stats st;
        int e = sim_step(s, xyz, nv, tris, nt, &st, &why);
        if (e < 0 && e != -SIM_ERR_DIVERGED) {
            fprintf(stderr, "tryon-probe-motion: frame %d: %s\n", f, why.detail);
            bad = 1;
            break;
        }
        garment_over ov;
        springs_over(&s->cloth, cols, rows, joints, &ov);
        const sim_cloth *c = &s->cloth;
        int a = c->ends[ov.worst][0], b = c->ends[ov.worst][1];
        float mid[3];
        for (int d = 0; d < 3; d++)
            mid[d] = 0.5f * (c->x[a][d] + c->x[b][d]);
        int bv = nearest_body_vertex(mid, xyz, nv);
        const float *j = joints;
        float up[3] = {0, 0, 0}, down[3] = {0, -1, 0};
        float arm_l =
            sim_probe_angle_deg(&j[J_NECK * 3], &j[J_PELVIS * 3], &j[J_LSHO * 3], &j[J_LELB * 3]);
        float arm_r =
            sim_probe_angle_deg(&j[J_NECK * 3], &j[J_PELVIS * 3], &j[J_RSHO * 3], &j[J_RELB * 3]);
        float thigh_l =
            sim_probe_angle_deg(&j[J_NECK * 3], &j[J_PELVIS * 3], &j[J_LHIP * 3], &j[J_LKNEE * 3]);
        float thigh_r =
            sim_probe_angle_deg(&j[J_NECK * 3], &j[J_PELVIS * 3], &j[J_RHIP * 3], &j[J_RKNEE * 3]);
        float bend = sim_probe_angle_deg(up, down, &j[J_NECK * 3], &j[J_PELVIS * 3]);
        float speed = sqrtf(dist2(&j[J_PELVIS * 3], pelvis_prev)) / desc.frame_dt_s;
        memcpy(pelvis_prev, &j[J_PELVIS * 3], sizeof pelvis_prev);
        printf("%d,%d,%.2f,%.2f,%d,%.1f,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d,%d", f, (int)st.state,
               100.0f * st.max_strain, 100.0f * st.p99_strain, st.penetrating, st.max_pen_mm,
               st.settle_rounds, ov.n, ov.attached, ov.rows[0], ov.rows[1], ov.rows[2], ov.sides[0],
               ov.sides[1], ov.sides[2], ov.sides[3], ov.vertical);
        for (int k = 0; k < PROBE_MAX_BONE; k++)
            printf(",%d", ov.bones[k]);
        int skin_arms, skin_thighs,
            skin_n = skin_inside(s, xyz, nv, tris, nt, pts, inside, j, &skin_arms, &skin_thighs);
        if (f == o->dump_frame)
            dump(s, xyz, nv, cols, inside, j);
        printf(",%d,%d,%s,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%.2f,%.2f,%d,%d,%d\n", a / cols,
               a % cols, bone_name[nearest_bone(mid, j)], 1000.0f * sqrtf(dist2(mid, &xyz[bv * 3])),
               100.0f * skin_stretch(bv, xyz, rest, tris, nt), arm_l, arm_r, thigh_l, thigh_r, bend,
               speed, s->body.max_move_m / desc.frame_dt_s, skin_n, skin_arms, skin_thighs);
    }
    sim_destroy(s);
    free(rest);
    free(pts);
    free(inside);
    sim_scene_destroy(sc);
    return bad;
}

int main(int argc, char **argv)
{
    probe_opts o;
    if (parse(argc, argv, &o) < 0) {
        usage(stderr);
        return 2;
    }
    return run(&o);
}
