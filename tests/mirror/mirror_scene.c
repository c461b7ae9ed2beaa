/* The known scene for the mirror tests (mirror_scene.h). Camera coordinates: x right, y down,
 * z forward; the camera stands 1 m above the floor looking along world -z. */
#include "mirror_scene.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>

#define FX 525.0f
#define CX 319.5f
#define CY 239.5f
/* torso plane, arm bar in front of it, garment plane between (metres, camera coordinates) */
#define TORSO_Z 2.0f
#define TORSO_X 0.25f
#define TORSO_Y 0.40f
#define ARM_Z   1.6f
#define ARM_X   0.50f
#define ARM_Y0  -0.12f
#define ARM_Y1  -0.02f
#define CLOTH_Z 1.9f
#define CLOTH_X 0.20f
#define CLOTH_Y 0.30f

static int inside(float u, float v, float z, float half_x, float y0, float y1)
{
    float x = (u - CX) * z / FX, y = (v - CY) * z / FX;
    return fabsf(x) <= half_x && y >= y0 && y <= y1;
}

/* Depth (m) of the camera image pixel (u, v); 0 = nothing. */
static float scene_depth(float u, float v)
{
    if (inside(u, v, ARM_Z, ARM_X, ARM_Y0, ARM_Y1))
        return ARM_Z;
    if (inside(u, v, TORSO_Z, TORSO_X, -TORSO_Y, TORSO_Y))
        return TORSO_Z;
    return 0.0f;
}

int ms_expected(int px, int py)
{
    float u = (float)(MS_W - 1 - px), v = (float)py; /* the mirror flips left-right */
    float z = scene_depth(u, v);
    if (z == ARM_Z)
        return MS_PERSON;
    if (inside(u, v, CLOTH_Z, CLOTH_X, -CLOTH_Y, CLOTH_Y))
        return MS_GARMENT;
    return z > 0 ? MS_PERSON : MS_BACKGROUND;
}

int ms_classify(const unsigned char *p)
{
    int r = p[0], g = p[1], b = p[2];
    if (r > 60 && r > g + 40 && r > b + 40)
        return MS_GARMENT;
    if (r < 40 && g < 40 && b < 40)
        return MS_BACKGROUND;
    return MS_PERSON;
}

static void publish(lcm_t *lcm, const char *ch_depth, const char *ch_cloth, uint16_t *pixels,
                    int32_t seq)
{
    int64_t now = bus_now_wall_us();
    tryon_depth_frame_t d = {.utime_capture = now,
                             .seq = seq,
                             .source = "test",
                             .width = MS_W,
                             .height = MS_H,
                             .fx = FX,
                             .fy = FX,
                             .cx = CX,
                             .cy = CY,
                             .metres_per_unit = 0.001f,
                             .camera_to_world = {1, 0, 0, 0, 0, -1, 0, 1, 0, 0, -1, 0, 0, 0, 0, 1},
                             .encoding = TRYON_DEPTH_FRAME_T_ENCODING_U16,
                             .num_bytes = MS_W * MS_H * 2,
                             .data = (uint8_t *)pixels};
    /* the garment quad in world coordinates: (x, 1 - y, -z) */
    float v[12] = {-CLOTH_X, 1 + CLOTH_Y, -CLOTH_Z, CLOTH_X, 1 + CLOTH_Y, -CLOTH_Z,
                   -CLOTH_X, 1 - CLOTH_Y, -CLOTH_Z, CLOTH_X, 1 - CLOTH_Y, -CLOTH_Z};
    int32_t t[6] = {0, 1, 2, 1, 3, 2};
    tryon_cloth_t c = {.utime_capture = now,
                       .seq = seq,
                       .garment_id = "test quad",
                       .topology_id = 1,
                       .num_vertex_coords = 12,
                       .vertices = v,
                       .num_triangle_indices = 6,
                       .triangles = t};
    bus_reject why;
    bus_publish(lcm, ch_depth, BUS_DEPTH_FRAME, &d, &why);
    bus_publish(lcm, ch_cloth, BUS_CLOTH, &c, &why);
}

int ms_serve_until_exit(pid_t pid, int timeout_ms)
{
    char err[256], ch_depth[BUS_CHANNEL_MAX], ch_cloth[BUS_CHANNEL_MAX];
    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    uint16_t *pixels = malloc(MS_W * MS_H * sizeof *pixels);
    if (!lcm || !pixels) {
        free(pixels);
        if (lcm)
            lcm_destroy(lcm);
        kill(pid, SIGKILL);
        waitpid(pid, NULL, 0);
        return -1;
    }
    for (int v = 0; v < MS_H; v++)
        for (int u = 0; u < MS_W; u++) /* little-endian millimetres */
            pixels[v * MS_W + u] = (uint16_t)lrintf(scene_depth((float)u, (float)v) * 1000.0f);
    bus_channel(BUS_CHANNEL_DEPTH, ch_depth, sizeof ch_depth);
    bus_channel(BUS_CHANNEL_CLOTH, ch_cloth, sizeof ch_cloth);
    int status = -1;
    for (int waited = 0, seq = 0; waited < timeout_ms; waited += 100, seq++) {
        publish(lcm, ch_depth, ch_cloth, pixels, seq);
        struct timespec ts = {0, 100 * 1000 * 1000};
        nanosleep(&ts, NULL);
        int st;
        if (waitpid(pid, &st, WNOHANG) == pid) {
            status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
            break;
        }
    }
    if (status < 0) {
        kill(pid, SIGKILL);
        waitpid(pid, NULL, 0);
    }
    free(pixels);
    lcm_destroy(lcm);
    return status;
}
