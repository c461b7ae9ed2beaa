/* A frame no attempt solves, recovered first by the garment's moving frame (sim.c, carry_good).
 *
 * The last good cloth carried point by point with the body (carry.c) follows, for each point,
 * the body triangle at its nearest body vertex. Where two body parts are close and move apart
 * (a hand hanging beside the hip at the hem, on Boxing_Toes.bvh) neighbouring points follow
 * different parts: that carry stretched the shirt to 875 % on the frame that failed, the garment
 * was dressed again as made, 28 mm inside the boxer's trunk, and every frame solved from there
 * failed again, ten in a row (docs/sim-history-5.md, "The clips: the causes"). The moving frame
 * (follow.c) moves the whole cloth rigidly with the body under its waist band: it stretches
 * nothing, and the frames after it start from the last good shape (whole clip: 48 frames carried
 * instead of 79, none deeper than 29 mm instead of 71; also falling back, as before, to the
 * garment dressed again when that shape is past SIM_CARRY_MAX_STRAIN: 50 carried, 58 mm). */
#include <string.h>

#include "carry.h"

int sim_recover_rigid(struct sim *s)
{
    const sim_body *b = &s->body;
    /* the garments that have a moving frame (follow.c): the tryon solver's, held by attachments */
    if (s->desc.solver != SIM_SOLVER_TRYON || !(s->desc.follow > 0.0f) || !b->have_prev ||
        s->cloth.num_attachments < 3 || !s->follow_anchor)
        return -1;
    size_t bytes = (size_t)s->cloth.nv * sizeof *s->cloth.x;
    memcpy(s->cloth.x, s->x_good, bytes);
    memcpy(s->cloth.x_prev, s->x_good, bytes);
    if (s->follow_on) /* off: the body under the waist band did not move */
        sim_follow(s->cloth.x, s->cloth.x_prev, 0, s->cloth.nv, s->follow_m);
    return 0;
}
