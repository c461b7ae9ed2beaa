/* Private to sim/: carrying cloth points with the body from frame k-1 to frame k (carry.c). */
#ifndef TRYON_SIM_CARRY_H
#define TRYON_SIM_CARRY_H

#include "cloth.h"

typedef struct sim_carry sim_carry;
/* The grid and per-vertex tables for bodies of up to max_body_vertices (made once). */
sim_carry *sim_carry_create(int max_body_vertices);
void sim_carry_destroy(sim_carry *c); /* accepts NULL */
/* Moves the n points x from where the body was (from) to where it is (to): nv vertices, the
 * same nt triangles. Returns 0, or -1 when the body is empty or too large (x unchanged). */
int sim_carry_between(sim_carry *c, const float (*from)[4], const float (*to)[4],
                      const int32_t (*tris)[4], int nv, int nt, float (*x)[4], int n);
/* The same from body frame k-1 to k; -1 when the body has no previous frame. */
int sim_carry_points(sim_carry *c, const sim_body *b, float (*x)[4], int n);

/* A frame no attempt solves: the last good cloth moved rigidly with the garment's moving frame
 * (follow.c; recover.c). 0, or -1 (cloth unchanged) for a garment without a moving frame. */
int sim_recover_rigid(struct sim *s);

#endif
