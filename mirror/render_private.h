/* Private to mirror/: the pieces of one frame the renderer builds on the CPU. */
#ifndef TRYON_MIRROR_RENDER_PRIVATE_H
#define TRYON_MIRROR_RENDER_PRIVATE_H

#include "mirror.h"

/* One vertex as the shader takes it: camera- or world-space position, normal, colour. */
typedef struct mirror_vertex {
    float pos[3], normal[3], rgba[4];
} mirror_vertex;

/* A growing CPU-side mesh, reused frame after frame (no allocation once warm). */
typedef struct mirror_cpu_mesh {
    mirror_vertex *v;
    uint32_t *idx;
    int nv, ni, v_cap, i_cap;
    int idx_changed; /* idx differs from the frame before's (mirror_world_mesh) */
} mirror_cpu_mesh;
int mirror_cpu_mesh_reserve(mirror_cpu_mesh *m, int nv, int ni);
void mirror_cpu_mesh_free(mirror_cpu_mesh *m);

/* The person is drawn per picture pixel from the depth image (render.c, person_fs). */
#define MIRROR_MIN_DEPTH_M 0.3f /* Kinect v1 sees nothing nearer (ARCHITECTURE.md: 0.5-4.5 m) */
#define MIRROR_MAX_DEPTH_M 8.0f
/* How far the person must be in front of the garment to hide it at depth z, metres. */
float mirror_occlusion_margin_m(float z);
/* Per depth pixel, two floats: the depth the garment is tested against (0 = no reading) and the
 * shade (0..1). *buf grows as needed (*cap floats: it also holds the work's scratch). */
int mirror_person_image(const mirror_depth *d, float **buf, int *cap);
/* A world-space mesh with area-weighted vertex normals, one colour or the fit map. */
int mirror_world_mesh(const mirror_mesh *m, const float rgba[4], int fit_map, mirror_cpu_mesh *out);

/* Row-major 4x4 matrices. proj: camera space to clip space for an out_w x out_h picture of the
 * depth camera's view, fitted to the picture's height, mirrored left-right. */
void mirror_projection(const mirror_depth *d, int out_w, int out_h, float proj[16]);
/* How the picture samples the depth image: scale (picture pixels per depth pixel) and the
 * picture's left margin, pixels. */
void mirror_picture_fit(const mirror_depth *d, int out_w, int out_h, float *scale, float *offx);
void mirror_world_to_camera(const float c2w[16], float w2c[16]);
void mirror_mat_mul(const float a[16], const float b[16], float out[16]);

#endif
