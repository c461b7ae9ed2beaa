/* A spin-then-sleep barrier for one OpenMP team (see team_barrier.h for why). Linux: the sleep is
   a futex on the phase word, as libgomp's own barrier does after its spin count. */
#define _DEFAULT_SOURCE /* syscall() for the futex */
#include <limits.h>
#include <linux/futex.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include "team_barrier.h"

/* Spins before sleeping, adapted per thread: doubled (up to SPINS_MAX, some 20-60 us of pause
   instructions, a few spring colours' worth of work) after a wait the spin covered or a short
   sleep, halved (down to SPINS_MIN) after a long sleep. On an idle machine the partner thread
   arrives within microseconds and the spin catches it; when other work holds the cores the
   partner has often lost its own (it is away for a scheduler slice, milliseconds), spinning would
   only delay it, and the budget shrinks to almost passive. A sleep shorter than SLEEP_SHORT_US
   means the partner was running, only later than the spin (uneven work): halving then would
   feed itself (each shorter spin misses more) and left an idle machine sleeping at every
   barrier, 3x slower (measured: 24 ms of iterations a frame instead of 8 on one thread). */
#define SPINS_MAX      1000
#define SPINS_MIN      16
#define SLEEP_SHORT_US 200
static _Thread_local int spin_budget = SPINS_MAX / 2;

static void cpu_relax(void)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
}

void sim_team_barrier_init(sim_team_barrier *b, int threads)
{
    atomic_store(&b->arrived, 0);
    atomic_store(&b->phase, 0);
    atomic_store(&b->sleepers, 0);
    b->threads = threads;
}

void sim_team_barrier_wait(sim_team_barrier *b)
{
    if (b->threads <= 1)
        return;
    /* The phase cannot advance before this thread arrives, so reading it first is safe. */
    int phase = atomic_load(&b->phase);
    if (atomic_fetch_add(&b->arrived, 1) == b->threads - 1) {
        atomic_store(&b->arrived, 0);
        atomic_fetch_add(&b->phase, 1);
        if (atomic_load(&b->sleepers) > 0)
            syscall(SYS_futex, &b->phase, FUTEX_WAKE_PRIVATE, INT_MAX, NULL, NULL, 0);
        return;
    }
    for (int spin = 0; spin < spin_budget; spin++) {
        if (atomic_load(&b->phase) != phase) {
            spin_budget = spin_budget < SPINS_MAX / 2 ? 2 * spin_budget : SPINS_MAX;
            return;
        }
        cpu_relax();
    }
    /* Sleep while the phase is still ours; the waker reads sleepers after advancing the phase
       (both seq_cst), so either it sees this sleeper or this futex call sees the new phase. */
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    atomic_fetch_add(&b->sleepers, 1);
    while (atomic_load(&b->phase) == phase)
        syscall(SYS_futex, &b->phase, FUTEX_WAIT_PRIVATE, phase, NULL, NULL, 0);
    atomic_fetch_sub(&b->sleepers, 1);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    long slept_us = (long)(t1.tv_sec - t0.tv_sec) * 1000000L + (t1.tv_nsec - t0.tv_nsec) / 1000;
    if (slept_us < SLEEP_SHORT_US)
        spin_budget = spin_budget < SPINS_MAX / 2 ? 2 * spin_budget : SPINS_MAX;
    else
        spin_budget = spin_budget > 2 * SPINS_MIN ? spin_budget / 2 : SPINS_MIN;
}
