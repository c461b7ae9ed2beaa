/* Phases shared out in chunks among the threads of one team (see phases.h for why). Linux: a
   thread with nothing to do sleeps on a futex, as the team barrier did. */
#define _GNU_SOURCE /* sched_getcpu(), syscall() for the futex */
#include <limits.h>
#include <linux/futex.h>
#include <sched.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include "phases.h"

/* Chunks per thread's part: enough that a thread finishing early takes over the other's last
   ones (the contact response, the heaviest pass, is uneven over the garment), few enough that the
   claims (one atomic each) stay a small part of a chunk's work. */
#define CHUNKS_MAX 4

/* Spins before sleeping, adapted per thread as the team barrier did: doubled (up to SPINS_MAX,
   some 20-60 us of pause instructions) after a wait the spin covered or a short sleep, halved
   (down to SPINS_MIN) after a long one. A short sleep means the other thread was running, only
   later than the spin; a long one that it had lost its core, where spinning would only take more
   of the core it needs. */
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

void sim_phases_init(sim_phases *ph)
{
    memset(ph, 0, sizeof *ph);
}

void sim_phases_free(sim_phases *ph)
{
    free(ph->mem);
    sim_phases_init(ph);
}

int sim_phases_reset(sim_phases *ph, int threads, int phases)
{
    atomic_store(&ph->wake, 0);
    atomic_store(&ph->need_wake, 0);
    atomic_store(&ph->sleeper_cpu, -1);
    if (threads <= 1) {
        ph->threads = 1; /* one thread takes every phase whole: no counters */
        return 0;
    }
    if (threads > ph->threads || phases > ph->cap) {
        int cap = phases > ph->cap ? phases : ph->cap;
        int stride = (cap + 15) / 16 * 16 + 16; /* parts of different threads on other lines */
        void *mem = aligned_alloc(64, (size_t)(threads + 1) * (size_t)stride * sizeof(atomic_int));
        if (!mem)
            return -1;
        free(ph->mem);
        ph->mem = mem;
        ph->claimed = mem;
        ph->done = ph->claimed + (size_t)threads * (size_t)stride;
        ph->cap = cap;
        ph->stride = stride;
    }
    ph->threads = threads;
    /* atomic_int is a plain int here (lock-free): zero bytes are zero counters */
    for (int t = 0; t < threads; t++)
        memset((void *)(ph->claimed + (size_t)t * (size_t)ph->stride), 0,
               (size_t)phases * sizeof(atomic_int));
    memset((void *)ph->done, 0, (size_t)phases * sizeof(atomic_int));
    return 0;
}

void sim_phase_cursor_init(sim_phase_cursor *c, int thread, int threads)
{
    memset(c, 0, sizeof *c);
    c->thread = thread;
    c->threads = threads;
}

int sim_phase_claim(sim_phases *ph, sim_phase_cursor *c, int n, int grain, int *b, int *e)
{
    c->n = n;
    int nt = c->threads;
    if (nt <= 1) {
        if (c->scan++ > 0 || n <= 0)
            return 0;
        *b = 0;
        *e = n;
        c->items = n;
        return 1;
    }
    for (; c->scan < nt; c->scan++) {
        int part = (c->thread + c->scan) % nt;
        int pb = (int)((long)n * part / nt), pe = (int)((long)n * (part + 1) / nt);
        int k = (pe - pb) / (grain > 0 ? grain : 1);
        k = pe <= pb ? 0 : k < 1 ? 1 : k > CHUNKS_MAX ? CHUNKS_MAX : k;
        atomic_int *taken = &ph->claimed[(size_t)part * (size_t)ph->stride + (size_t)c->phase];
        /* another's part: look before taking, so an idle thread does not pull the line away */
        if (c->scan > 0 && atomic_load_explicit(taken, memory_order_relaxed) >= k)
            continue;
        int j = atomic_fetch_add_explicit(taken, 1, memory_order_relaxed);
        if (j < k) {
            *b = pb + (int)((long)(pe - pb) * j / k);
            *e = pb + (int)((long)(pe - pb) * (j + 1) / k);
            c->items += *e - *b;
            return 1;
        }
    }
    return 0;
}

static long elapsed_us(const struct timespec *t0)
{
    struct timespec t1;
    clock_gettime(CLOCK_MONOTONIC, &t1);
    return (long)(t1.tv_sec - t0->tv_sec) * 1000000L + (t1.tv_nsec - t0->tv_nsec) / 1000;
}

/* One system call per sleep: the first waker after a thread went to sleep clears need_wake. */
static void wake_sleepers(sim_phases *ph)
{
    if (atomic_exchange(&ph->need_wake, 0)) {
        atomic_fetch_add(&ph->wake, 1);
        syscall(SYS_futex, &ph->wake, FUTEX_WAKE_PRIVATE, INT_MAX, NULL, NULL, 0);
    }
}

/* Until phase p's n items are done. The sleeper raises need_wake before its last look at the
   counter, and whoever wakes reads need_wake after adding its items (all seq_cst): either the
   waker sees it, or this look sees the items. A sleeper is woken at the phases marked wake (a
   step's start, the frame's end) and when a thread on another CPU ends a phase: waking one that
   slept on this thread's own CPU would only make the two take turns on it. */
static void wait_done(sim_phases *ph, int p, int n)
{
    atomic_int *done = &ph->done[p];
    for (int spin = 0; spin < spin_budget; spin++) {
        if (atomic_load_explicit(done, memory_order_acquire) >= n) {
            spin_budget = spin_budget < SPINS_MAX / 2 ? 2 * spin_budget : SPINS_MAX;
            return;
        }
        cpu_relax();
    }
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    atomic_store(&ph->sleeper_cpu, sched_getcpu());
    for (;;) {
        atomic_store(&ph->need_wake, 1);
        int gen = atomic_load(&ph->wake);
        if (atomic_load(done) >= n)
            break;
        syscall(SYS_futex, &ph->wake, FUTEX_WAIT_PRIVATE, gen, NULL, NULL, 0);
    }
    if (elapsed_us(&t0) < SLEEP_SHORT_US)
        spin_budget = spin_budget < SPINS_MAX / 2 ? 2 * spin_budget : SPINS_MAX;
    else
        spin_budget = spin_budget > 2 * SPINS_MIN ? spin_budget / 2 : SPINS_MIN;
}

void sim_phase_end(sim_phases *ph, sim_phase_cursor *c, int wake)
{
    int n = c->n, items = c->items;
    if (c->threads > 1) {
        int sum = items > 0 ? atomic_fetch_add(&ph->done[c->phase], items) + items
                            : atomic_load(&ph->done[c->phase]);
        if (sum < n)
            wait_done(ph, c->phase, n);
        if (((items > 0 && sum == n) || wake) && atomic_load(&ph->need_wake) &&
            (wake || atomic_load(&ph->sleeper_cpu) != sched_getcpu()))
            wake_sleepers(ph);
    }
    c->phase++;
    c->n = 0;
    c->scan = 0;
    c->items = 0;
}
