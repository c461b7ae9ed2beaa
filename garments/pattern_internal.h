/* Private to garments/: refusals and planar polygon helpers shared by the reader and the mesher. */
#ifndef TRYON_GARMENTS_INTERNAL_H
#define TRYON_GARMENTS_INTERNAL_H

#include "garments.h"

#define GAR_PI 3.14159265358979323846

/* Fills why (may be NULL) and returns -code. */
int gar_refuse(gar_reject *why, gar_error code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* The outline is a closed loop (edge k ends where edge k + 1 starts), runs counter-clockwise
 * (gar_panel_make_ccw turns a clockwise one over first), encloses an area and does not cross itself
 * (checked on GAR_OUTLINE_CHECK_SAMPLES points per edge). */
#define GAR_OUTLINE_CHECK_SAMPLES 8
int gar_check_outline(const gar_panel *pn, gar_reject *why);
int gar_check_loop(const gar_panel *pn, gar_reject *why); /* the loop alone */
/* A panel whose outline runs clockwise (the data sets' panels mirrored from their other half:
 * GarmentCode's right and back panels) turned over: the same panel described from its other
 * side, u -> -u with the rotation turned half round its v axis, so that every point lands where
 * it did in the world, the edges keep their order, direction and stitches, and the front normal
 * (the counter-clockwise side) still faces where the file's winding made it face. Needs the
 * loop (edge k ends where edge k + 1 starts). 1 turned over, 0 not, or -error. */
int gar_panel_make_ccw(gar_panel *pn, gar_reject *why);

/* Polygon of n points (x, y interleaved). */
double gar_polygon_area(const float *xy, int n); /* signed, > 0 counter-clockwise */
int gar_point_in_polygon(const float *xy, int n, double px, double py);
double gar_point_polygon_distance(const float *xy, int n, double px, double py);
/* Segments ab and cd cross or touch (callers pass segments that share no endpoint). */
int gar_segments_cross(const float *a, const float *b, const float *c, const float *d);

#endif
