#include "fixtures.h"

#include <stdlib.h>
#include <string.h>

static const float identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

void fx_depth_make(fx_depth *f, int w, int h, int seed)
{
    f->pixels = malloc((size_t)w * h * sizeof *f->pixels);
    for (int i = 0; i < w * h; i++)
        f->pixels[i] = (uint16_t)((i * 7 + seed * 131) % 4500);
    f->msg = (tryon_depth_frame_t){
        .utime_capture = 1700000000000000 + seed,
        .device_timestamp = 12345 + seed,
        .seq = seed,
        .source = "fixture",
        .width = w,
        .height = h,
        .fx = 580.0f,
        .fy = 581.0f,
        .cx = w / 2.0f,
        .cy = h / 2.0f,
        .metres_per_unit = 0.001f,
        .encoding = TRYON_DEPTH_FRAME_T_ENCODING_U16,
        .num_bytes = w * h * 2,
        .data = (uint8_t *)f->pixels,
    };
    memcpy(f->msg.camera_to_world, identity, sizeof identity);
    f->msg.camera_to_world[7] = 1.0f; /* camera 1 m above the floor */
}

void fx_depth_free(fx_depth *f)
{
    free(f->pixels);
}

static void mesh_make(int nv, int nt, int seed, float (**v)[3], int32_t (**t)[3])
{
    *v = malloc((size_t)(nv ? nv : 1) * sizeof **v);
    *t = malloc((size_t)(nt ? nt : 1) * sizeof **t);
    for (int i = 0; i < nv; i++)
        for (int k = 0; k < 3; k++)
            (*v)[i][k] = (float)((i * 3 + k + seed) % 97) * 0.01f;
    for (int i = 0; i < nt; i++)
        for (int k = 0; k < 3; k++)
            (*t)[i][k] = (i + k + seed) % nv;
}

void fx_body_make(fx_body *f, int nv, int nt, int seed)
{
    mesh_make(nv, nt, seed, &f->verts, &f->tris);
    for (int i = 0; i < 9; i++)
        f->shape[i] = 0.5f + 0.1f * (float)i;
    for (int i = 0; i < 66; i++)
        f->pose[i] = 0.01f * (float)(i - 33);
    for (int i = 0; i < 21 * 3; i++)
        f->joints[i] = 0.05f * (float)i;
    f->msg = (tryon_body_t){
        .utime_capture = 1700000000000000 + seed,
        .seq = seed,
        .state = TRYON_BODY_T_STATE_TRACKING,
        .fit_residual_mm = 4.5f,
        .num_shape = 9,
        .shape = f->shape,
        .num_pose = 66,
        .pose = f->pose,
        .num_joint_coords = 21 * 3,
        .joints = f->joints,
        .topology_id = 7,
        .num_vertex_coords = 3 * nv,
        .vertices = &f->verts[0][0],
        .num_triangle_indices = 3 * nt,
        .triangles = &f->tris[0][0],
    };
}

void fx_body_free(fx_body *f)
{
    free(f->verts);
    free(f->tris);
}

void fx_cloth_make(fx_cloth *f, int nv, int nt, int seed)
{
    mesh_make(nv, nt, seed, &f->verts, &f->tris);
    f->msg = (tryon_cloth_t){
        .utime_capture = 1700000000000000 + seed,
        .seq = seed,
        .garment_id = "tube-shirt",
        .state = TRYON_CLOTH_T_STATE_OK,
        .max_strain = 0.02f,
        .p99_strain = 0.008f,
        .penetrating = 0,
        .max_pen_mm = 0.0f,
        .topology_id = 3,
        .num_vertex_coords = 3 * nv,
        .vertices = &f->verts[0][0],
        .num_triangle_indices = 3 * nt,
        .triangles = &f->tris[0][0],
    };
}

void fx_cloth_free(fx_cloth *f)
{
    free(f->verts);
    free(f->tris);
}

void fx_timing_make(fx_timing *f, int seed)
{
    static char *names[3] = {"bvh", "feature_points", "iterations"};
    for (int i = 0; i < 3; i++) {
        f->names[i] = names[i];
        f->ms[i] = 0.25f * (float)(i + 1 + seed);
    }
    f->msg = (tryon_timing_t){
        .stage = "sim",
        .seq = seed,
        .utime_capture = 1000 + seed,
        .utime_received = 2000 + seed,
        .utime_started = 2100 + seed,
        .utime_finished = 5000 + seed,
        .num_substages = 3,
        .substage = f->names,
        .substage_ms = f->ms,
    };
}

void fx_control_make(fx_control *f, int seed)
{
    f->msg = (tryon_control_t){
        .utime = 7000 + seed,
        .seq = seed,
        .garment = "shirt",
        .size = TRYON_CONTROL_T_SIZE_M,
        .fabric = "cotton",
    };
}

#define SAME(field) (a->field == b->field)
#define SAME_ARRAY(field, n)                                                                       \
    ((n) == 0 || memcmp(a->field, b->field, (size_t)(n) * sizeof *a->field) == 0)

static int depth_equal(const tryon_depth_frame_t *a, const tryon_depth_frame_t *b)
{
    return SAME(utime_capture) && SAME(device_timestamp) && SAME(seq) &&
           strcmp(a->source, b->source) == 0 && SAME(width) && SAME(height) && SAME(fx) &&
           SAME(fy) && SAME(cx) && SAME(cy) && SAME(metres_per_unit) &&
           memcmp(a->camera_to_world, b->camera_to_world, sizeof a->camera_to_world) == 0 &&
           SAME(encoding) && SAME(num_bytes) && SAME_ARRAY(data, a->num_bytes);
}

static int body_equal(const tryon_body_t *a, const tryon_body_t *b)
{
    return SAME(utime_capture) && SAME(seq) && SAME(state) && SAME(fit_residual_mm) &&
           SAME(num_shape) && SAME_ARRAY(shape, a->num_shape) && SAME(num_pose) &&
           SAME_ARRAY(pose, a->num_pose) && SAME(num_joint_coords) &&
           SAME_ARRAY(joints, a->num_joint_coords) && SAME(topology_id) &&
           SAME(num_vertex_coords) && SAME_ARRAY(vertices, a->num_vertex_coords) &&
           SAME(num_triangle_indices) && SAME_ARRAY(triangles, a->num_triangle_indices);
}

static int cloth_equal(const tryon_cloth_t *a, const tryon_cloth_t *b)
{
    return SAME(utime_capture) && SAME(seq) && strcmp(a->garment_id, b->garment_id) == 0 &&
           SAME(state) && SAME(max_strain) && SAME(p99_strain) && SAME(penetrating) &&
           SAME(max_pen_mm) && SAME(topology_id) && SAME(num_vertex_coords) &&
           SAME_ARRAY(vertices, a->num_vertex_coords) && SAME(num_triangle_indices) &&
           SAME_ARRAY(triangles, a->num_triangle_indices);
}

static int timing_equal(const tryon_timing_t *a, const tryon_timing_t *b)
{
    if (!(strcmp(a->stage, b->stage) == 0 && SAME(seq) && SAME(utime_capture) &&
          SAME(utime_received) && SAME(utime_started) && SAME(utime_finished) &&
          SAME(num_substages) && SAME_ARRAY(substage_ms, a->num_substages)))
        return 0;
    for (int i = 0; i < a->num_substages; i++)
        if (strcmp(a->substage[i], b->substage[i]) != 0)
            return 0;
    return 1;
}

static int control_equal(const tryon_control_t *a, const tryon_control_t *b)
{
    return SAME(utime) && SAME(seq) && strcmp(a->garment, b->garment) == 0 && SAME(size) &&
           strcmp(a->fabric, b->fabric) == 0;
}

int fx_equal(bus_type t, const void *a, const void *b)
{
    switch (t) {
    case BUS_DEPTH_FRAME:
        return depth_equal(a, b);
    case BUS_BODY:
        return body_equal(a, b);
    case BUS_CLOTH:
        return cloth_equal(a, b);
    case BUS_TIMING:
        return timing_equal(a, b);
    case BUS_CONTROL:
        return control_equal(a, b);
    default:
        return 0;
    }
}

int fx_encode(bus_type t, const void *msg, uint8_t **out)
{
    int n = -1;
    switch (t) {
    case BUS_DEPTH_FRAME:
        n = tryon_depth_frame_t_encoded_size(msg);
        break;
    case BUS_BODY:
        n = tryon_body_t_encoded_size(msg);
        break;
    case BUS_CLOTH:
        n = tryon_cloth_t_encoded_size(msg);
        break;
    case BUS_TIMING:
        n = tryon_timing_t_encoded_size(msg);
        break;
    case BUS_CONTROL:
        n = tryon_control_t_encoded_size(msg);
        break;
    default:
        return -1;
    }
    *out = malloc((size_t)n);
    int r = -1;
    switch (t) {
    case BUS_DEPTH_FRAME:
        r = tryon_depth_frame_t_encode(*out, 0, n, msg);
        break;
    case BUS_BODY:
        r = tryon_body_t_encode(*out, 0, n, msg);
        break;
    case BUS_CLOTH:
        r = tryon_cloth_t_encode(*out, 0, n, msg);
        break;
    case BUS_TIMING:
        r = tryon_timing_t_encode(*out, 0, n, msg);
        break;
    case BUS_CONTROL:
        r = tryon_control_t_encode(*out, 0, n, msg);
        break;
    default:
        break;
    }
    return r == n ? n : -1;
}
