/* Private to garments/: refusals and planar polygon helpers shared by the reader and the mesher. */
#ifndef TRYON_GARMENTS_INTERNAL_H
#define TRYON_GARMENTS_INTERNAL_H

#include "garments.h"

#define GAR_PI 3.14159265358979323846

/* Fills why (may be NULL) and returns -code. */
int gar_refuse(gar_reject *why, gar_error code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* The outline is a closed loop (edge k ends where edge k + 1 starts), runs counter-clockwise
 * and does not cross itself (checked on GAR_OUTLINE_CHECK_SAMPLES points per edge). */
#define GAR_OUTLINE_CHECK_SAMPLES 8
int gar_check_outline(const gar_panel *pn, gar_reject *why);

/* Polygon of n points (x, y interleaved). */
double gar_polygon_area(const float *xy, int n); /* signed, > 0 counter-clockwise */
int gar_point_in_polygon(const float *xy, int n, double px, double py);
double gar_point_polygon_distance(const float *xy, int n, double px, double py);
/* Segments ab and cd cross or touch (callers pass segments that share no endpoint). */
int gar_segments_cross(const float *a, const float *b, const float *c, const float *d);

#endif
