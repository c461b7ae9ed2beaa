/* Private to sim/: what a motion does to the body, measured for tryon-probe-motion
 * (probe_motion.c) and its test (docs/sim-real-motion.md, "Real motion: the causes"). */
#ifndef TRYON_SIM_PROBE_H
#define TRYON_SIM_PROBE_H

#include <stdint.h>

#include "collide.h"

/* The skin moved this far out along each body vertex's normal: a vertex whose skin merely
   touches another part (an arm resting on the trunk) stays outside it. */
#define SIM_PROBE_SKIN_OFF_M 0.002f

/* The body's skin passing through itself (an arm pressed into the trunk, a thigh into the
 * belly): how many of the nv body vertices, moved SIM_PROBE_SKIN_OFF_M out along their normal,
 * lie inside the body by the parity of a ray's crossings (a closed skin passing through itself
 * holds them inside the other part; the signed distance cannot tell, its nearest surface being
 * the vertex's own). c holds this body frame (sim_collider_set_body); pts is nv * 4 floats of
 * scratch; inside (may be NULL) gets 1 for each such vertex. Returns the count, or -SIM_ERR_ARG. */
int sim_probe_skin_inside(const sim_collider *c, const float *xyz, int nv, const int32_t *tris,
                          int nt, float (*pts)[4], uint8_t *inside);

/* The angle in degrees between the directions a -> b and c -> d (0 for a zero direction). */
float sim_probe_angle_deg(const float a[3], const float b[3], const float c[3], const float d[3]);

#endif
