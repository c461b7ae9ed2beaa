/* Sample messages for the bus tests, and deep equality. */
#ifndef TRYON_TEST_BUS_FIXTURES_H
#define TRYON_TEST_BUS_FIXTURES_H

#include "bus.h"

/* Each fills a message whose arrays point into storage owned by the fixture struct. */
typedef struct fx_depth {
    tryon_depth_frame_t msg;
    uint16_t *pixels;
} fx_depth;
void fx_depth_make(fx_depth *f, int w, int h, int seed);
void fx_depth_free(fx_depth *f);

typedef struct fx_body {
    tryon_body_t msg;
    float shape[9], pose[66], joints[21 * 3];
    float (*verts)[3];
    int32_t (*tris)[3];
} fx_body;
void fx_body_make(fx_body *f, int nv, int nt, int seed);
void fx_body_free(fx_body *f);

typedef struct fx_cloth {
    tryon_cloth_t msg;
    float (*verts)[3];
    int32_t (*tris)[3];
} fx_cloth;
void fx_cloth_make(fx_cloth *f, int nv, int nt, int seed);
void fx_cloth_free(fx_cloth *f);

typedef struct fx_timing {
    tryon_timing_t msg;
    char *names[3];
    float ms[3];
} fx_timing;
void fx_timing_make(fx_timing *f, int seed);

typedef struct fx_control {
    tryon_control_t msg;
} fx_control;
void fx_control_make(fx_control *f, int seed); /* garment "shirt", size M, fabric "cotton" */

/* 1 if the two decoded messages of type t are equal field by field. */
int fx_equal(bus_type t, const void *a, const void *b);

/* Encodes msg of type t into a malloc'd buffer; returns its length (or -1). */
int fx_encode(bus_type t, const void *msg, uint8_t **out);

#endif
