/* A frame drawn before the first message: llvmpipe compiles each shader for the state it is drawn
 * with at its first draw (about 90 ms on one core), and a kiosk's first real frame should not
 * pay for it while the bodies behind it queue. The scene holds everything a frame may draw: a
 * person with a nearer arm, a garment of a shirt's size coloured by the fit map, the translucent
 * body, the overlay with its ramp. */
#include <GLES3/gl3.h>
#include <stdio.h>
#include <stdlib.h>

#include "mirror.h"

#define WARM_W    640 /* a Kinect's depth image: the textures get their real size now */
#define WARM_H    480
#define WARM_GRID 84 /* 7,056 vertices: the shirt's */

int mirror_warm_up(mirror_renderer *r, mirror_ring *ring, char *err, size_t n)
{
    uint16_t *z = malloc((size_t)WARM_W * WARM_H * sizeof *z);
    if (!z)
        return -MIRROR_ERR_NO_MEMORY;
    for (int y = 0; y < WARM_H; y++) /* a torso at 2 m, an arm at 1.6 m across it, mm */
        for (int x = 0; x < WARM_W; x++)
            z[y * WARM_W + x] = x > 200 && x < 440 ? (y > 220 && y < 260 ? 1600 : 2000) : 0;
    mirror_depth d = {.width = WARM_W,
                      .height = WARM_H,
                      .fx = 525.0f,
                      .fy = 525.0f,
                      .cx = WARM_W / 2.0f,
                      .cy = WARM_H / 2.0f,
                      .metres_per_unit = 0.001f,
                      .camera_to_world = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1},
                      .data = z};
    /* a garment between the torso and the arm, as many vertices as a shirt (its buffers, and
       llvmpipe's bins, get their real size now), and the body just behind it, metres */
    float *xyz = malloc((size_t)WARM_GRID * WARM_GRID * 3 * sizeof *xyz);
    float *strain = malloc((size_t)WARM_GRID * WARM_GRID * sizeof *strain);
    int32_t *grid = malloc((size_t)(WARM_GRID - 1) * (WARM_GRID - 1) * 6 * sizeof *grid);
    if (!xyz || !strain || !grid) {
        free(z);
        free(xyz);
        free(strain);
        free(grid);
        return -MIRROR_ERR_NO_MEMORY;
    }
    int nt = 0;
    for (int j = 0; j < WARM_GRID; j++)
        for (int i = 0; i < WARM_GRID; i++) {
            float *p = xyz + 3 * (j * WARM_GRID + i);
            p[0] = -0.2f + 0.4f * (float)i / (WARM_GRID - 1);
            p[1] = -0.2f + 0.4f * (float)j / (WARM_GRID - 1);
            p[2] = 1.9f;
            strain[j * WARM_GRID + i] = 0.04f * (float)i / (WARM_GRID - 1); /* the whole ramp */
            if (i + 1 < WARM_GRID && j + 1 < WARM_GRID) {
                int32_t a = j * WARM_GRID + i, b = a + 1, c = a + WARM_GRID, e = c + 1;
                int32_t t[6] = {a, b, e, a, e, c};
                for (int k = 0; k < 6; k++)
                    grid[6 * nt / 2 + k] = t[k];
                nt += 2;
            }
        }
    static const float behind[] = {-0.2f, -0.2f, 1.95f, 0.2f,  -0.2f, 1.95f,
                                   0.2f,  0.2f,  1.95f, -0.2f, 0.2f,  1.95f};
    static const int32_t tris[] = {0, 1, 2, 0, 2, 3};
    mirror_mesh garment = {xyz, WARM_GRID * WARM_GRID, grid, nt, strain},
                body = {behind, 4, tris, 2, NULL};
    mirror_view v = {.depth = &d,
                     .garment = &garment,
                     .body = &body,
                     .fit_map = 1,
                     .overlay_text = "WARM-UP 0.0 MS"};
    int rc = mirror_render(r, &v, err, n);
    glFinish(); /* llvmpipe rasterises (and compiles what it still needs) here */
    /* A slot's first frame allocates its pixels and its person's image, about 5 MB of pages
       touched for the first time: 20-38 ms each for the first eight frames, measured at nice 5
       while the fit and the cloth took the cores, so the first CLOTH waited behind them. */
    for (int k = 0; ring && rc == 0 && k < MIRROR_RING; k++)
        if (mirror_ring_push(ring, &d) < 0) {
            snprintf(err, n, "no memory for the depth frames' ring");
            rc = -MIRROR_ERR_NO_MEMORY;
        }
    if (ring)
        mirror_ring_forget(ring);
    free(z);
    free(xyz);
    free(strain);
    free(grid);
    return rc;
}
