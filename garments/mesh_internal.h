/* Private to garments/: the mesher's pieces. */
#ifndef TRYON_GARMENTS_MESH_INTERNAL_H
#define TRYON_GARMENTS_MESH_INTERNAL_H

#include "pattern_internal.h"

/* pts: 2 (n + 3) doubles, the last 3 points scratch. Triangles ccw, allocated for the caller. */
int gar_delaunay(double *pts, int n, int32_t **tris_out, int *nt_out);

/* Stitched edges whose lengths differ by at most this fraction get equal sample counts, so
 * their joints pair point to point (1 %: below what a sewer eases in). */
#define GAR_SEAM_EQUAL_FRACTION 0.01f
/* Grid points closer to the outline than this fraction of the spacing are dropped, so each
 * outline segment (at most one spacing long) has an empty diametral circle and comes out of
 * the Delaunay triangulation as an edge. */
#define GAR_GRID_CLEARANCE 0.6

/* Joints for every stitch, from the mesh's edge vertex lists (seams.c). */
int gar_seams_build(const gar_pattern *p, gar_mesh *m, gar_reject *why);

#endif
