/* Ground-truth files: plain "key values..." lines, one fact per line, so a person can read them
 * and any language can parse them. */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rec_private.h"

static void put_floats(FILE *fp, const char *key, const float *v, int n)
{
    fprintf(fp, "%s", key);
    for (int i = 0; i < n; i++)
        fprintf(fp, " %.9g", v[i]);
    fprintf(fp, "\n");
}

int rec_gt_write(const char *path, const rec_gt *g, rec_report *why)
{
    FILE *fp = fopen(path, "wb");
    if (!fp)
        return rec_fail(why, REC_ERR_IO, path, g->frame, 0, "%s", strerror(errno));
    fprintf(fp, "# tryon-synth ground truth; docs/recordings.md describes every line\n");
    fprintf(fp, "frame %d\n", g->frame);
    fprintf(fp, "time_s %.9f\n", g->time_s);
    fprintf(fp, "depth_file %s\n", g->depth_file);
    fprintf(fp, "motion %s\n", g->motion);
    fprintf(fp, "shape_preset %d\n", g->shape_preset);
    fprintf(fp, "target_vertices %d\n", g->target_vertices);
    fprintf(fp, "num_shape %d\n", g->num_shape);
    put_floats(fp, "shape", g->shape, g->num_shape);
    fprintf(fp, "num_pose %d\n", g->num_pose);
    put_floats(fp, "pose", g->pose, g->num_pose);
    fprintf(fp, "num_joints %d\n", g->num_joints);
    for (int j = 0; j < g->num_joints; j++)
        fprintf(fp, "joint %s %.9g %.9g %.9g\n", g->joint_name[j], g->joints[j][0], g->joints[j][1],
                g->joints[j][2]);
    fprintf(fp, "image %d %d\n", g->width, g->height);
    fprintf(fp, "intrinsics %.9g %.9g %.9g %.9g\n", g->fx, g->fy, g->cx, g->cy);
    put_floats(fp, "camera_to_world", g->camera_to_world, 16);
    fprintf(fp, "noise %d\n", g->noise);
    fprintf(fp, "seed %" PRIu64 "\n", g->seed);
    fprintf(fp, "wall_z %.9g\n", g->scene.wall_z);
    fprintf(fp, "box %d %.9g %.9g %.9g %.9g %.9g %.9g\n", g->scene.has_box, g->scene.box_min[0],
            g->scene.box_min[1], g->scene.box_min[2], g->scene.box_max[0], g->scene.box_max[1],
            g->scene.box_max[2]);
    if (fclose(fp) != 0)
        return rec_fail(why, REC_ERR_IO, path, g->frame, 0, "%s", strerror(errno));
    return REC_OK;
}

static int get_floats(const char *s, float *v, int n, int max)
{
    if (n < 0 || n > max)
        return -1;
    for (int i = 0; i < n; i++) {
        char *end;
        v[i] = strtof(s, &end);
        if (end == s)
            return -1;
        s = end;
    }
    return 0;
}

static int get_int(const char *s, int *v, int lo, int hi)
{
    return sscanf(s, "%d", v) == 1 && *v >= lo && *v <= hi ? 0 : -1;
}

/* One "key values" line; joints counts the joint lines seen so far. */
static int gt_line(rec_gt *g, const char *key, const char *rest, int *joints)
{
    if (!strcmp(key, "frame"))
        return get_int(rest, &g->frame, 0, 1 << 30);
    if (!strcmp(key, "time_s"))
        return sscanf(rest, "%lf", &g->time_s) == 1 ? 0 : -1;
    if (!strcmp(key, "depth_file"))
        return sscanf(rest, "%95s", g->depth_file) == 1 ? 0 : -1;
    if (!strcmp(key, "motion"))
        return sscanf(rest, "%31s", g->motion) == 1 ? 0 : -1;
    if (!strcmp(key, "shape_preset"))
        return get_int(rest, &g->shape_preset, 0, 64);
    if (!strcmp(key, "target_vertices"))
        return get_int(rest, &g->target_vertices, 0, 1 << 24);
    if (!strcmp(key, "num_shape"))
        return get_int(rest, &g->num_shape, 0, REC_GT_MAX_SHAPE);
    if (!strcmp(key, "shape"))
        return get_floats(rest, g->shape, g->num_shape, REC_GT_MAX_SHAPE);
    if (!strcmp(key, "num_pose"))
        return get_int(rest, &g->num_pose, 0, REC_GT_MAX_POSE);
    if (!strcmp(key, "pose"))
        return get_floats(rest, g->pose, g->num_pose, REC_GT_MAX_POSE);
    if (!strcmp(key, "num_joints"))
        return get_int(rest, &g->num_joints, 0, REC_GT_MAX_JOINTS);
    if (!strcmp(key, "joint")) {
        if (*joints >= g->num_joints)
            return -1;
        int j = (*joints)++;
        return sscanf(rest, "%23s %f %f %f", g->joint_name[j], &g->joints[j][0], &g->joints[j][1],
                      &g->joints[j][2]) == 4
                   ? 0
                   : -1;
    }
    if (!strcmp(key, "image"))
        return sscanf(rest, "%d %d", &g->width, &g->height) == 2 ? 0 : -1;
    if (!strcmp(key, "intrinsics"))
        return sscanf(rest, "%f %f %f %f", &g->fx, &g->fy, &g->cx, &g->cy) == 4 ? 0 : -1;
    if (!strcmp(key, "camera_to_world"))
        return get_floats(rest, g->camera_to_world, 16, 16);
    if (!strcmp(key, "noise"))
        return get_int(rest, &g->noise, 0, 1);
    if (!strcmp(key, "seed"))
        return sscanf(rest, "%" SCNu64, &g->seed) == 1 ? 0 : -1;
    if (!strcmp(key, "wall_z"))
        return sscanf(rest, "%f", &g->scene.wall_z) == 1 ? 0 : -1;
    if (!strcmp(key, "box"))
        return sscanf(rest, "%d %f %f %f %f %f %f", &g->scene.has_box, &g->scene.box_min[0],
                      &g->scene.box_min[1], &g->scene.box_min[2], &g->scene.box_max[0],
                      &g->scene.box_max[1], &g->scene.box_max[2]) == 7
                   ? 0
                   : -1;
    return 0; /* unknown keys are left for newer readers */
}

int rec_gt_read(const char *path, rec_gt *g, rec_report *why)
{
    memset(g, 0, sizeof *g);
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return rec_fail(why, REC_ERR_NO_FRAME, path, -1, 0, "%s", strerror(errno));
    char line[4096];
    int lineno = 0, joints = 0;
    int err = REC_OK;
    while (fgets(line, sizeof line, fp)) {
        lineno++;
        if (line[0] == '#' || line[0] == '\n')
            continue;
        char key[32];
        int n = 0;
        if (sscanf(line, "%31s%n", key, &n) != 1 || gt_line(g, key, line + n, &joints) != 0) {
            err = rec_fail(why, REC_ERR_BAD_LINE, path, g->frame, 0, "line %d: '%.60s'", lineno,
                           line);
            break;
        }
    }
    fclose(fp);
    if (err == REC_OK && joints != g->num_joints)
        err = rec_fail(why, REC_ERR_BAD_LINE, path, g->frame, 0, "%d joint lines, expected %d",
                       joints, g->num_joints);
    return err;
}
