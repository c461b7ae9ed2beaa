/* A frame drawn before the first message: llvmpipe compiles each shader for the state it is drawn
 * with at its first draw (about 90 ms on one core), and a kiosk's first real frame should not
 * pay for it while the bodies behind it queue. The scene holds everything a frame may draw: a
 * person with a nearer arm, a garment coloured by the fit map, the translucent body, the
 * overlay with its ramp. */
#include <GLES3/gl3.h>
#include <stdlib.h>

#include "mirror.h"

#define WARM_W 640 /* a Kinect's depth image: the textures get their real size now */
#define WARM_H 480

int mirror_warm_up(mirror_renderer *r, char *err, size_t n)
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
    /* a quad between the torso and the arm, and the body just behind it, metres */
    static const float quad[] = {-0.2f, -0.2f, 1.9f, 0.2f,  -0.2f, 1.9f,
                                 0.2f,  0.2f,  1.9f, -0.2f, 0.2f,  1.9f};
    static const float behind[] = {-0.2f, -0.2f, 1.95f, 0.2f,  -0.2f, 1.95f,
                                   0.2f,  0.2f,  1.95f, -0.2f, 0.2f,  1.95f};
    static const int32_t tris[] = {0, 1, 2, 0, 2, 3};
    static const float strain[] = {0.0f, 0.01f, 0.02f, 0.04f};
    mirror_mesh garment = {quad, 4, tris, 2, strain}, body = {behind, 4, tris, 2, NULL};
    mirror_view v = {.depth = &d,
                     .garment = &garment,
                     .body = &body,
                     .fit_map = 1,
                     .overlay_text = "WARM-UP 0.0 MS"};
    int rc = mirror_render(r, &v, err, n);
    glFinish(); /* llvmpipe rasterises (and compiles what it still needs) here */
    free(z);
    return rc;
}
