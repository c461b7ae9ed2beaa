/* Private to sim/: the solver passes over the cloth (springs.c), the C twins of the kernels in
 * kernels/springs.cl; split from cloth.h. */
#ifndef TRYON_SIM_PASSES_H
#define TRYON_SIM_PASSES_H

#include <stdint.h>

#include "spring_kind.h"

typedef struct sim_cloth sim_cloth; /* cloth.h */

/* C twins of the kernels (kernels/springs.cl): same names, same order of operations. Ranges
 * [begin, end) are vertices or springs; callers split them over threads. */
/* Verlet: x' = x + (x - x_prev) * keep + a dt^2; pinned points (w = 0) stay. */
void sim_verlet(float (*x)[4], float (*x_prev)[4], int begin, int end, float keep,
                const float accel_dt2[3]);
/* seed: f = k dl along the spring plus relative-velocity damping, accumulated into acc dt^2. */
void sim_spring_forces(const float (*x)[4], const float (*x_prev)[4], const int32_t (*ends)[2],
                       const float *rest, const uint8_t *kind, const float k[SIM_SPRING_KINDS],
                       int begin, int end, float dt, float damp_ratio, float (*acc_dt2)[4]);
void sim_verlet_forces(float (*x)[4], float (*x_prev)[4], const float (*acc_dt2)[4], int begin,
                       int end, float keep, const float g_dt2[3]);
/* The clamp: springs of the kinds in `kinds` (bit 1 << kind) longer than rest * (1 + ratio)
 * shortened back to it, each end moved in proportion to its inverse mass (a pinned end stays).
 * seed: Provot's correction (stretch and shear, ratio tau); tryon: the strain limit (below). */
#define SIM_KINDS_STRETCH (1u << SIM_SPRING_STRETCH)
#define SIM_KINDS_PROVOT  (1u << SIM_SPRING_STRETCH | 1u << SIM_SPRING_SHEAR)
void sim_clamp_springs(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                       const uint8_t *kind, int begin, int end, unsigned kinds, float ratio);
/* tryon: XPBD distance constraint, one Gauss-Seidel pass over springs of one colour. alpha =
 * compliance / dt^2 per kind. */
void sim_project_springs(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                         const uint8_t *kind, const float alpha[SIM_SPRING_KINDS], int begin,
                         int end);
/* tryon: tethers, each vertex pulled back within len * (1 + limit) of its anchor. */
void sim_tethers(float (*x)[4], const int32_t *anchor, const float *len, int begin, int end,
                 float limit);
/* tryon: the strain-limit hierarchy over entries [begin, end) in level order: each vertex is
 * moved (alone: its parents count as infinitely heavy) to within rest * (1 + limit) of each of
 * its parents in turn, and its velocity away from a parent it was pulled to is removed (called in
 * the post-stabilisation's bracket: x_prev holds -(x - x_prev)). Vertices of one level are
 * independent. */
void sim_strain_hierarchy(float (*x)[4], float (*x_prev)[4], const int32_t *vertex,
                          const int32_t *parent_start, const int32_t *parent, const float *rest,
                          int begin, int end, float limit);
/* tryon: the support hierarchy, for garments without attachments (docs/sim.md): the strain-limit
 * hierarchy rooted, each frame, at the highest vertex the body holds up (the root: of the vertices
 * resting on an upward face, sim_collider_resting > 0, the highest, the lowest index among equals).
 * sim_support_levels: level[v] = hops over stretch springs from the root, -1 where it does not
 * reach (or no root, root < 0); queue receives the vertices reached but the root in breadth-first
 * order; returns how many. sim_support_pull: vertex v (not pinned) moved alone to within
 * rest (1 + limit) of each stretch neighbour one level nearer the root, in adjacency order, its
 * velocity away from such a neighbour removed where it was past the limit (springs.c says why).
 * Twins: the support block of sim_iterations_tryon (kernels/springs.cl). */
int sim_support_levels(const sim_cloth *c, int root, int32_t *level, int32_t *queue);
void sim_support_pull(float (*x)[4], float (*x_prev)[4], const sim_cloth *c, const int32_t *level,
                      int v, float limit);
/* tryon, post-stabilisation: x_prev -= x before position-only corrections, x_prev += x after,
 * so the velocity x - x_prev survives them; pinned points (w = 0) untouched. */
void sim_post_begin(float (*x)[4], float (*x_prev)[4], int begin, int end);
void sim_post_end(float (*x)[4], float (*x_prev)[4], int begin, int end);
/* tryon: the largest strain (|xi - xj| - rest) / rest of the stretch springs in [begin, end), 0
 * when none is stretched, infinity for a NaN (the settle rounds' test, metrics.c; twin in
 * springs.cl). */
float sim_stretch_max(const float (*x)[4], const int32_t (*ends)[2], const float *rest,
                      const uint8_t *kind, int begin, int end);
/* tryon: the strain limit, the clamp of stretch springs to rest * (1 + limit). */
static inline void sim_strain_limit(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                                    const uint8_t *kind, int begin, int end, float limit)
{
    sim_clamp_springs(x, ends, rest, kind, begin, end, SIM_KINDS_STRETCH, limit);
}

#endif
