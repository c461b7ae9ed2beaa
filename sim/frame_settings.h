/* Private to sim/: the tryon solver's settings for a frame (kernels/solver_params.h), filled once
 * for both backends. */
#ifndef TRYON_SIM_FRAME_SETTINGS_H
#define TRYON_SIM_FRAME_SETTINGS_H

#include "solver_params.h"

struct sim;

/* Every field from s for a frame of iters steps; contact_every (decided per frame from the
   cloth's speed) and nleaves (the device's body) are left 0 for the backend to set. */
void sim_solver_params_fill(const struct sim *s, int iters, sim_solver_params *p);

#endif
