/* What the mirror makes cheaper per frame, checked against the plain version: the person's image
 * (a bordered z plane, branch-free vectorised loops) bit for bit equal to a per-pixel reference
 * with bounds-checked neighbours, on frames with holes, steps, readings out of range and noise;
 * and the garment's triangles marked for upload only when they change. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mirror.h"
#include "render_private.h"

/* person.c's constants: neighbours on one surface within 3 % of the depth, normals from
 * neighbours 3 pixels away, one shade per 2x2 block. */
#define REF_EDGE_JUMP   0.03f
#define REF_NORMAL_STEP 3

static float ref_z(const mirror_depth *d, int u, int v)
{
    if (u < 0 || v < 0 || u >= d->width || v >= d->height)
        return 0.0f;
    float m = (float)d->data[v * d->width + u] * d->metres_per_unit;
    return m >= MIRROR_MIN_DEPTH_M && m <= MIRROR_MAX_DEPTH_M ? m : 0.0f;
}

static void ref_near(const mirror_depth *d, int u, int v, float z, const float *c, float *out)
{
    float zn = ref_z(d, u, v);
    if (zn > 0.0f && fabsf(zn - z) < REF_EDGE_JUMP * z) {
        out[0] = ((float)u - d->cx) / d->fx * zn;
        out[1] = ((float)v - d->cy) / d->fy * zn;
        out[2] = zn;
    } else {
        memcpy(out, c, 3 * sizeof *c);
    }
}

static float ref_shade(const mirror_depth *d, int u, int v, float z)
{
    const int s = REF_NORMAL_STEP;
    float c[3] = {((float)u - d->cx) / d->fx * z, ((float)v - d->cy) / d->fy * z, z};
    float l[3], r[3], t[3], b[3];
    ref_near(d, u - s, v, z, c, l);
    ref_near(d, u + s, v, z, c, r);
    ref_near(d, u, v - s, z, c, t);
    ref_near(d, u, v + s, z, c, b);
    float du[3] = {r[0] - l[0], r[1] - l[1], r[2] - l[2]};
    float dv[3] = {b[0] - t[0], b[1] - t[1], b[2] - t[2]};
    float n[3] = {dv[1] * du[2] - dv[2] * du[1], dv[2] * du[0] - dv[0] * du[2],
                  dv[0] * du[1] - dv[1] * du[0]};
    float len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    return len2 > 0.0f ? fabsf(n[2]) / sqrtf(len2) : 1.0f;
}

/* The definition, pixel by pixel: 2 floats a pixel, test depth and shade. */
static void ref_person(const mirror_depth *d, float *out)
{
    for (int v = 0; v < d->height; v++)
        for (int u = 0; u < d->width; u++) {
            float z = ref_z(d, u, v), *o = &out[(v * d->width + u) * 2];
            o[0] = o[1] = 0.0f;
            if (z == 0.0f)
                continue;
            o[0] = z + mirror_occlusion_margin_m(z);
            int au = u & ~1, av = v & ~1;
            float za = ref_z(d, au, av);
            int anchor = au == u && av == v;
            o[1] = !anchor && za > 0.0f && fabsf(za - z) < REF_EDGE_JUMP * z
                       ? out[(av * d->width + au) * 2 + 1]
                       : ref_shade(d, u, v, z);
        }
}

/* A frame of w x h: a slanted wall, a nearer box (steps), holes, readings too near or too far,
 * and millimetre noise. */
static void scene(uint16_t *px, int w, int h, unsigned seed)
{
    srand(seed);
    for (int v = 0; v < h; v++)
        for (int u = 0; u < w; u++) {
            int mm = 2500 + 3 * u - 2 * v + rand() % 7 - 3;
            if (u > w / 3 && u < w / 2 && v > h / 4)
                mm = 1600 + u + rand() % 5; /* an arm in front: a step of about 0.9 m */
            int r = rand() % 40;
            px[v * w + u] = (uint16_t)(r == 0 ? 0 : r == 1 ? 200 : r == 2 ? 9000 : mm);
        }
}

static void test_person_image_matches_the_per_pixel_reference(void **state)
{
    (void)state;
    const int sizes[][2] = {{37, 29}, {8, 5}, {64, 48}, {640, 480}, {3, 2}};
    for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
        int w = sizes[k][0], h = sizes[k][1];
        uint16_t *px = malloc((size_t)w * h * sizeof *px);
        float *want = malloc((size_t)w * h * 2 * sizeof *want), *got = NULL;
        assert_non_null(px);
        assert_non_null(want);
        scene(px, w, h, (unsigned)k + 1);
        mirror_depth d = {w,
                          h,
                          0.9f * (float)w,
                          0.9f * (float)w,
                          0.5f * (float)w - 0.5f,
                          0.5f * (float)h - 0.5f,
                          0.001f,
                          {0},
                          px,
                          0,
                          NULL};
        int cap = 0;
        ref_person(&d, want);
        assert_int_equal(mirror_person_image(&d, &got, &cap), 0);
        assert_memory_equal(got, want, (size_t)w * h * 2 * sizeof *got);
        int shaded = 0, empty = 0; /* the scene reached both kinds of pixel */
        for (int i = 0; i < w * h; i++) {
            shaded += got[i * 2] > 0.0f && got[i * 2 + 1] > 0.0f && got[i * 2 + 1] < 1.0f;
            empty += got[i * 2] == 0.0f;
        }
        assert_true(w * h < 100 || (shaded > w * h / 2 && empty > 0));
        /* the buffer is reused: a second frame into it, the same answer */
        scene(px, w, h, (unsigned)k + 100);
        ref_person(&d, want);
        assert_int_equal(mirror_person_image(&d, &got, &cap), 0);
        assert_memory_equal(got, want, (size_t)w * h * 2 * sizeof *got);
        free(px);
        free(want);
        free(got);
    }
}

static void test_garment_indices_marked_changed_only_when_they_change(void **state)
{
    (void)state;
    const float xyz[12] = {0, 0, 2, 0.1f, 0, 2, 0, 0.1f, 2, 0.1f, 0.1f, 2};
    int32_t tris[6] = {0, 1, 2, 1, 3, 2};
    mirror_mesh m = {.xyz = xyz, .nv = 4, .tris = tris, .nt = 2};
    const float rgba[4] = {1, 0, 0, 1};
    mirror_cpu_mesh out = {0};
    assert_int_equal(mirror_world_mesh(&m, rgba, 0, &out), 0);
    assert_true(out.idx_changed); /* the first frame: uploaded */
    assert_int_equal(mirror_world_mesh(&m, rgba, 0, &out), 0);
    assert_false(out.idx_changed); /* the same triangles: not again */
    tris[4] = 0;
    assert_int_equal(mirror_world_mesh(&m, rgba, 0, &out), 0);
    assert_true(out.idx_changed); /* one index changed */
    m.nt = 1;
    assert_int_equal(mirror_world_mesh(&m, rgba, 0, &out), 0);
    assert_true(out.idx_changed); /* fewer triangles */
    tris[2] = 9;                  /* out of range: refused, and the next good frame uploads again */
    assert_int_equal(mirror_world_mesh(&m, rgba, 0, &out), -MIRROR_ERR_MESH);
    tris[2] = 2;
    assert_int_equal(mirror_world_mesh(&m, rgba, 0, &out), 0);
    assert_true(out.idx_changed);
    assert_int_equal(out.ni, 3);
    mirror_cpu_mesh_free(&out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_person_image_matches_the_per_pixel_reference),
        cmocka_unit_test(test_garment_indices_marked_changed_only_when_they_change),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
