/* Private to sim/: the tryon solver's settings for a frame (kernels/solver_params.h), filled once
 * for both backends. */
#ifndef TRYON_SIM_FRAME_SETTINGS_H
#define TRYON_SIM_FRAME_SETTINGS_H

#include "solver_params.h"

struct sim;

/* Every field from s for a frame of iters steps; contact_every (decided per frame from the
   cloth's speed) and nleaves (the device's body) are left 0 for the backend to set. */
void sim_solver_params_fill(const struct sim *s, int iters, sim_solver_params *p);

/* The largest squared distance a cloth point of [b, e) moves in a step at its current velocity. */
float sim_step_travel2(const struct sim_cloth *c, int b, int e);
/* contact_every for a frame whose fastest point moves sqrt(travel2) a step: contacts are cached
   for the frame; when the cloth itself moves fast (a falling sheet, a hem kicked by a thigh:
   farther than the reach in the frame) they are refreshed every SIM_CONTACT_EVERY steps, else 0 */
int sim_contact_every(float travel2, int iters);

#endif
