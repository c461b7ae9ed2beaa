/* Private to garments/: cloth-cloth between panels (cloth_cloth.c). */
#ifndef TRYON_GARMENTS_CLOTH_CLOTH_H
#define TRYON_GARMENTS_CLOTH_CLOTH_H

#include "dress_internal.h"

typedef struct gar_cc gar_cc;
/* skip: per vertex, 1 = near a seam, left out (the panels meet there by design). The mesh and
 * skip must outlive the object. */
gar_cc *gar_cc_create(const gar_mesh *m, const uint8_t *skip);
void gar_cc_destroy(gar_cc *cc);
/* Adds to push ([vertex][3]) the moves that take each vertex to thickness from the other
 * panels' triangles it is closer to. */
void gar_cc_repel(gar_cc *cc, const float *x, float thickness, float *push);
/* Edges of one panel through a triangle of another. */
int gar_cc_crossings(gar_cc *cc, const float *x);

#endif
