/* Private to sim/: where a sewn pattern garment is held on the body (sim/pattern_hold.c). */
#ifndef TRYON_SIM_PATTERN_HOLD_H
#define TRYON_SIM_PATTERN_HOLD_H

#include <stdint.h>

#include "sim.h"

/* The garment's highest opening (the boundary component of the highest mean height: a top's
 * neckline, trousers' or a skirt's waistband) attached to the body under it, each of its vertices
 * glued where it is to the body triangle at its nearest body vertex (sim_garment_rebind's glue),
 * as the shirt's top row is: what holds a garment up on a person is the friction of the shoulders
 * or the waist, and the sim's tethers, strain-limit hierarchy and moving frame all hang from
 * attachments (docs/garments.md, "Pattern garments on the moving body"). body_xyz / tris: the body
 * in the pose the garment is in. Returns the number of attachments (> 0) or -SIM_ERR_x. */
int sim_pattern_hold(sim_garment *g, const float *body_xyz, int nv, const int32_t *tris, int nt,
                     sim_reject *why);

#endif
