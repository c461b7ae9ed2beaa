/* Private to sim/: a dressed sewing pattern's panels sewn into one mesh for the sim
 * (sim/pattern_weld.c). */
#ifndef TRYON_SIM_PATTERN_WELD_H
#define TRYON_SIM_PATTERN_WELD_H

#include <stdint.h>

#include "garments.h"
#include "sim.h"

/* Triangles thinner than this after sewing are dropped (sim/garment.c refuses a garment triangle
 * of 1e-12 m^2 or less; a sliver of an eased seam can come near it). */
#define SIM_WELD_MIN_AREA_M2 1e-9f

/* out: m's vertices with every seam joint's two sides made one vertex (a point-edge joint's
 * vertex joins the nearer end of its partner segment), at the mean of the positions it joins;
 * triangles that lose a corner to the sewing or become slivers dropped, and vertices no triangle
 * keeps removed. The sim sees no seams (sim_garment has springs only along triangle edges), so
 * panels left apart fall off the body one by one. part_of (may be NULL): per vertex of m, compacted
 * in place to out's vertices. Returns 0 or -SIM_ERR_NO_MEMORY / -SIM_ERR_EMPTY. */
int sim_pattern_weld(const gar_mesh *m, sim_garment *out, int8_t *part_of, sim_reject *why);

#endif
