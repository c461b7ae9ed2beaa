/* Private to sim/: a barrier for the threads of one OpenMP team that spins a little before it
 * yields. The tryon iterations pass about 20 barriers per step (one per spring colour), 500 a
 * frame, each after a few microseconds of work per thread. With OMP_WAIT_POLICY=passive (which
 * the sim asks for on a shared machine) an OpenMP barrier puts the early thread to sleep on a
 * futex and the wake-up costs more than the work; fully active waiting wastes a core whenever the
 * partner thread has lost its own. A short bounded spin covers the usual case (the partner
 * arrives within microseconds), then the thread sleeps as a passive one does. */
#ifndef TRYON_SIM_TEAM_BARRIER_H
#define TRYON_SIM_TEAM_BARRIER_H

#include <stdatomic.h>

typedef struct sim_team_barrier {
    atomic_int arrived;  /* threads at the barrier in this phase */
    atomic_int phase;    /* incremented by the last thread to arrive: everyone may go */
    atomic_int sleepers; /* threads asleep (futex) on phase */
    int threads;
} sim_team_barrier;

/* Before the team uses it, by one thread (then an OpenMP barrier). */
void sim_team_barrier_init(sim_team_barrier *b, int threads);
/* Every thread of the team; returns when all have arrived. Everything a thread wrote before is
   visible to every thread after (seq_cst read-modify-write, release / acquire on the phase). */
void sim_team_barrier_wait(sim_team_barrier *b);

#endif
