/* A spin-then-sleep barrier for one OpenMP team (see team_barrier.h for why). Linux: the sleep is
   a futex on the phase word, as libgomp's own barrier does after its spin count. */
#define _DEFAULT_SOURCE /* syscall() for the futex */
#include <limits.h>
#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "team_barrier.h"

/* Spins before sleeping, adapted per thread: doubled (up to SPINS_MAX, some 20-60 us of pause
   instructions, a few spring colours' worth of work) after a wait the spin covered, halved (down
   to SPINS_MIN) after one that had to sleep. On an idle machine the partner thread arrives within
   microseconds and the spin catches it; when other work holds the cores the partner has often
   lost its own, spinning would only delay it, and the budget shrinks to almost passive. */
#define SPINS_MAX 1000
#define SPINS_MIN 16
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
    spin_budget = spin_budget > 2 * SPINS_MIN ? spin_budget / 2 : SPINS_MIN;
    /* Sleep while the phase is still ours; the waker reads sleepers after advancing the phase
       (both seq_cst), so either it sees this sleeper or this futex call sees the new phase. */
    atomic_fetch_add(&b->sleepers, 1);
    while (atomic_load(&b->phase) == phase)
        syscall(SYS_futex, &b->phase, FUTEX_WAIT_PRIVATE, phase, NULL, NULL, 0);
    atomic_fetch_sub(&b->sleepers, 1);
}
