/* tryon-sim's rehearsal (sim/rehearse.c): the first garment made once before the stage listens. */
#ifndef SIM_REHEARSE_H
#define SIM_REHEARSE_H

#include "sim.h"

/* The stand-in body: the body model's average shape at rest, with as many vertices as the
 * fitter's published body or more (bodyfit publishes 6,000; the model's default is 10,000), so
 * that the rehearsal touches at least the memory a real body's collision state needs. */
#define SIM_REHEARSE_BODY_VERTICES 10000

/* Makes the outfit (a generated or OBJ garment; for a sewing pattern, the shirt) on the stand-in
 * body, starts it (sim_start) and steps it once on the C backend, and returns that sim: the first
 * real garment takes its body collision state (sim_take_body: the tree's and adjacency's arrays,
 * sized for the largest body, their pages already the process's) and builds its own body's in
 * them, instead of faulting fresh pages in while a person waits. NULL with err filled when it
 * cannot be made (the stage goes on without it). */
sim *sim_rehearse(const sim_outfit *worn, const sim_desc *desc, int verts, char *err,
                  size_t err_size);

#endif
