/* Small meshes and random numbers shared by the collision tests. */
#ifndef TRYON_TEST_COLLIDE_UTIL_H
#define TRYON_TEST_COLLIDE_UTIL_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

/* xorshift32: fixed seeds, the same numbers on every machine (STYLE.md 13). */
static inline float tc_rand(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return (float)(*s >> 8) / 16777216.0f;
}

static inline float tc_range(uint32_t *s, float lo, float hi)
{
    return lo + (hi - lo) * tc_rand(s);
}

/* A random unit direction (rejection from the cube, so uniform on the sphere). */
static inline void tc_direction(uint32_t *s, float dir[3])
{
    float len;
    do {
        for (int k = 0; k < 3; k++)
            dir[k] = tc_range(s, -1.0f, 1.0f);
        len = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    } while (len < 0.1f || len > 1.0f);
    for (int k = 0; k < 3; k++)
        dir[k] /= len;
}

/* A closed UV sphere of radius r at the origin: slices x stacks, outward winding.
   Vertices: 2 + slices * (stacks - 1); triangles: 2 * slices * (stacks - 1). Caller frees. */
static inline void tc_sphere(float r, int slices, int stacks, float **xyz, int *nv, int32_t **tris,
                             int *nt)
{
    const float pi = 3.14159265358979f;
    int rings = stacks - 1;
    *nv = 2 + slices * rings;
    *nt = 2 * slices * rings;
    float *v = malloc((size_t)*nv * 3 * sizeof *v);
    int32_t *t = malloc((size_t)*nt * 3 * sizeof *t);
    v[0] = 0.0f, v[1] = r, v[2] = 0.0f;
    v[3] = 0.0f, v[4] = -r, v[5] = 0.0f;
    for (int i = 0; i < rings; i++) {
        float th = pi * (float)(i + 1) / (float)stacks;
        for (int j = 0; j < slices; j++) {
            float ph = 2.0f * pi * (float)j / (float)slices;
            float *p = v + 3 * (2 + i * slices + j);
            p[0] = r * sinf(th) * cosf(ph);
            p[1] = r * cosf(th);
            p[2] = r * sinf(th) * sinf(ph);
        }
    }
    int k = 0;
#define RV(i, j) (2 + (i)*slices + ((j) % slices))
    for (int j = 0; j < slices; j++) {
        t[k++] = 0, t[k++] = RV(0, j + 1), t[k++] = RV(0, j);
        t[k++] = 1, t[k++] = RV(rings - 1, j), t[k++] = RV(rings - 1, j + 1);
    }
    for (int i = 0; i + 1 < rings; i++)
        for (int j = 0; j < slices; j++) {
            t[k++] = RV(i, j), t[k++] = RV(i, j + 1), t[k++] = RV(i + 1, j);
            t[k++] = RV(i + 1, j), t[k++] = RV(i, j + 1), t[k++] = RV(i + 1, j + 1);
        }
#undef RV
    /* Make every face point away from the centre, whatever the loops above chose. */
    for (int f = 0; f < *nt; f++) {
        float *a = v + 3 * t[3 * f], *b = v + 3 * t[3 * f + 1], *c = v + 3 * t[3 * f + 2];
        float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                      e1[0] * e2[1] - e1[1] * e2[0]};
        float m[3] = {a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
        if (n[0] * m[0] + n[1] * m[1] + n[2] * m[2] < 0.0f) {
            int32_t s = t[3 * f + 1];
            t[3 * f + 1] = t[3 * f + 2];
            t[3 * f + 2] = s;
        }
    }
    *xyz = v;
    *tris = t;
}

/* A soup of nt random triangles (edges 1-10 cm) in the box [-0.5, 0.5]^3; 3 vertices each. */
static inline void tc_soup(uint32_t *seed, int nt, float **xyz, int32_t **tris)
{
    float *v = malloc((size_t)nt * 9 * sizeof *v);
    int32_t *t = malloc((size_t)nt * 3 * sizeof *t);
    for (int f = 0; f < nt; f++) {
        float c[3] = {tc_range(seed, -0.5f, 0.5f), tc_range(seed, -0.5f, 0.5f),
                      tc_range(seed, -0.5f, 0.5f)};
        for (int k = 0; k < 3; k++) {
            for (int a = 0; a < 3; a++)
                v[9 * f + 3 * k + a] = c[a] + tc_range(seed, -0.05f, 0.05f);
            t[3 * f + k] = 3 * f + k;
        }
    }
    *xyz = v;
    *tris = t;
}

#endif
