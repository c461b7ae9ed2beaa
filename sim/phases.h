/* Private to sim/: the passes of the tryon iterations shared out among the threads of one OpenMP
 * team in chunks, in place of a barrier between passes.
 *
 * A frame is a sequence of phases (a spring colour, a per-vertex pass); a phase may start only when
 * every item of the one before is done. Each thread owns an equal part of every phase, cut into a
 * few chunks, and takes the chunks of its part first, then any another thread has not yet taken.
 * A phase ends for a thread when all its items are done, whoever did them. So a thread that has
 * lost its core (other work on a shared machine) is not waited for unless it holds a chunk: the
 * other runs on through the phases alone, and the late one, when it runs again, finds them done
 * and joins where the work is. With a barrier every phase waited for every thread; two threads
 * sharing one core then took 3x one thread's time (docs/sim.md, "Speed work 3").
 *
 * The items of a phase are independent (springs of one colour share no vertex; per-vertex passes),
 * so which thread does a chunk changes no result. */
#ifndef TRYON_SIM_PHASES_H
#define TRYON_SIM_PHASES_H

#include <stdatomic.h>

typedef struct sim_phases {
    int threads, cap;       /* counters for cap phases of this many threads */
    int stride;             /* ints between two threads' claim counters (other cache lines) */
    atomic_int *claimed;    /* [threads][stride]: chunks taken of part t of phase p */
    atomic_int *done;       /* [cap]: items done of phase p */
    atomic_int wake;        /* futex word: bumped to wake the sleepers */
    atomic_int need_wake;   /* a thread went to sleep since the last wake */
    atomic_int sleeper_cpu; /* the CPU the last thread to sleep slept on */
    void *mem;
} sim_phases;

/* One thread's place in the sequence. */
typedef struct sim_phase_cursor {
    int phase;  /* index in the frame */
    int thread; /* this thread, of threads */
    int threads;
    int n;     /* items of the current phase */
    int scan;  /* parts looked at so far: own first, then the others in turn */
    int items; /* items this thread did in the current phase */
} sim_phase_cursor;

void sim_phases_init(sim_phases *ph);
void sim_phases_free(sim_phases *ph);
/* Before a frame, outside the team: counters for `phases` phases of `threads` threads, all zero.
 * Grows the storage when needed (the first frame, a retry with more iterations). 0 or -1. */
int sim_phases_reset(sim_phases *ph, int threads, int phases);
/* In the team, once per thread. */
void sim_phase_cursor_init(sim_phase_cursor *c, int thread, int threads);
/* The next chunk [*b, *e) of the current phase's n items for this thread (the same n from every
 * thread), 0 when none is left. grain: the fewest items worth a chunk of their own. */
int sim_phase_claim(sim_phases *ph, sim_phase_cursor *c, int n, int grain, int *b, int *e);
/* After the last claim: returns when every item of the phase is done (all writes visible), and
 * moves on to the next phase. wake: wake sleeping threads if this ends the phase (a sleeping
 * thread is otherwise woken only when one on another CPU ends a phase). */
void sim_phase_end(sim_phases *ph, sim_phase_cursor *c, int wake);

#endif
