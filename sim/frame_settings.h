/* Private to sim/: the tryon solver's settings for a frame (kernels/solver_params.h), filled once
 * for both backends. */
#ifndef TRYON_SIM_FRAME_SETTINGS_H
#define TRYON_SIM_FRAME_SETTINGS_H

#include "solver_params.h"

struct sim;

/* Every field from s for a frame of iters steps; fast (decided per frame from the cloth's speed)
   and nleaves (the device's body) are left 0 for the backend to set. */
void sim_solver_params_fill(const struct sim *s, int iters, sim_solver_params *p);

/* The largest squared distance a cloth point of [b, e) moves in a step at its current velocity. */
float sim_step_travel2(const struct sim_cloth *c, int b, int e);
/* fast for a frame whose fastest point moves sqrt(travel2) a step: 1 when the cloth itself
   moves farther than the reach in the frame (a falling sheet, a hem kicked by a thigh), else 0.
   Such a frame's settle rounds do not stop for slow progress (sim_settle_stop). */
int sim_frame_fast(float travel2, int iters);

#endif
