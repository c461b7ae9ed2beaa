/* The bodies tryon-sim takes in: their triangle lists kept per topology id, so that a stray
 * sender's topology cannot evict the one the garment lives on, with a stated bound on the memory
 * any sender can make the process hold. */
#ifndef TRYON_SIM_BODY_INTAKE_H
#define TRYON_SIM_BODY_INTAKE_H

#include <stdint.h>

#include "sim.h"

/* Triangle lists kept at once. Memory held: at most SIM_TOPOLOGY_SLOTS * max_triangles * 12
 * bytes (4 slots of sim_desc's 200,000 triangles: 9.6 MB), whatever arrives. */
#define SIM_TOPOLOGY_SLOTS 4
/* The live topology (the one the garment was last simulated on) stays pinned this long after
 * the last body that used it arrived or was simulated: while its sender is alive no other list
 * can replace it (2 s: 60 frames, time for a loaded machine to fall behind; a sender whose
 * topology really changed waits that long for a garment of its own). */
#define SIM_TOPOLOGY_LIVE_US 2000000

typedef struct sim_topology {
    int32_t id;
    int nt; /* 0: the slot is free */
    int32_t *tris;
    uint32_t gen;    /* changes whenever the slot takes another list: a garment made on one
                        list knows when the body's list is no longer the same */
    int64_t used_us; /* last time a body used it (least recently used slot is replaced) */
} sim_topology;

typedef struct sim_topologies {
    int max_vertices, max_triangles; /* a body over either is refused */
    sim_topology slot[SIM_TOPOLOGY_SLOTS];
    int has_live;
    int32_t live_id;
    int64_t live_us; /* last time the live topology was simulated */
    int refused;     /* triangle lists refused (too large, or redefining the live one) */
    uint32_t next_gen;
} sim_topologies;

void sim_topologies_init(sim_topologies *t, int max_vertices, int max_triangles);
void sim_topologies_free(sim_topologies *t);

/* A body of nv vertices (0: not known, a lookup) and its topology: nt > 0 triangles to keep (or to
 * check against those kept for id), or nt = 0 for the list kept for id. On success *out is the slot
 * (owned by t, valid until the next intake: keep the id, not the pointer). Refuses, with -SIM_ERR_x
 * and why: a list over max_triangles, an id never given triangles, and, while the live topology is
 * pinned, any other topology and other triangles for the live id (the garment is bound to its
 * body's triangles). */
int sim_topologies_intake(sim_topologies *t, int32_t id, int nv, const int32_t *tris, int nt,
                          int64_t now_us, const sim_topology **out, sim_reject *why);

/* Marks id as the topology the garment was just simulated on (pins it). */
void sim_topologies_mark_live(sim_topologies *t, int32_t id, int64_t now_us);

/* How far a body moved since the one before (same vertices, xyz metres): the median of its
 * vertices' displacements, mm, so that a still body's figure is the fitter's noise however much
 * an arm swings. scratch holds nv floats. */
float sim_body_motion_mm(const float *before, const float *now, int nv, float *scratch);

#endif
