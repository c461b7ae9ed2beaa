/* The depth-image work bodyfit hands to OpenCV (core, imgproc), behind C functions: the only
 * C++ in bodyfit/ is cv_shim.cpp. Images are row-major, width x height, caller-owned. Every
 * function returns 0, or -1 when OpenCV threw (the message goes to err). */
#ifndef TRYON_CV_SHIM_H
#define TRYON_CV_SHIM_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Flying pixels: out[i] = 1 where the largest minus the smallest valid depth (m) in the 3x3
 * neighbourhood of a valid pixel exceeds jump_m (depth 0 = no reading, left out). */
int cvs_depth_edges(const float *depth_m, int width, int height, float jump_m, uint8_t *out,
                    char *err, size_t errlen);

/* 8-connected components of mask (non-zero = set). labels[i]: 0 = background, 1..count.
 * Per component (index label - 1, at most max_comps): pixel count and bounding box. */
typedef struct cvs_component {
    int area;
    int x0, y0, x1, y1; /* inclusive */
} cvs_component;
int cvs_components(const uint8_t *mask, int width, int height, int32_t *labels,
                   cvs_component *comps, int max_comps, int *count, char *err, size_t errlen);

/* out = mask dilated by a (2 radius + 1) square (non-zero = set; out 0 or 1). */
int cvs_dilate(const uint8_t *mask, int width, int height, int radius, uint8_t *out, char *err,
               size_t errlen);

/* Inside roi (x0, y0, x1, y1 inclusive: the set pixels' bounding box grown by margin, clipped
 * to the image), the index (y * width + x) of the nearest set pixel of mask (L2 distance
 * transform with pixel labels); -1 elsewhere and everywhere when the mask is empty (roi then
 * 0 0 -1 -1). Only the box is transformed: the far background needs no answer. */
int cvs_nearest_set(const uint8_t *mask, int width, int height, int margin, int32_t *nearest,
                    int roi[4], char *err, size_t errlen);

#ifdef __cplusplus
}
#endif
#endif
