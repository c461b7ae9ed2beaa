/* The contact search of a frame (sim_collider_find_contacts) and the contacts adopted from its
 * OpenCL twin (kernels/collide.cl, sim_find_contacts).
 *
 * The solver calls the search from inside its parallel region, each thread with its own range
 * of cloth points; the points' costs differ (a point with nothing within reach costs less than
 * half of one in contact, and such points gather in parts of the garment), so the halves of a
 * 2-thread team measured 58 % and 42 % of the work. Every point's search is independent of the
 * others' (its own hint, its own cache entry), so a thread that has finished its range takes chunks
 * of the ranges other threads are still working through: the same queries, the same results, done
 * sooner. A thread returns only when every point of its own range is done, by whoever took it. */
#include <math.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdint.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "collide.h"
#include "collide_bvh.h"
#include "contact_rule.h"

/* Points a claim takes: some 25 us of searches, against an atomic operation a claim. */
#define SHARE_CHUNK 32
/* A slot's word: generation (odd while the range is open) in bits 32..63, chunks being done by
   other threads in bits 24..31, the next unclaimed offset into the range in bits 0..23 (ranges
   are at most SIM_SHARE_MAX_POINTS; the offset overshoots by at most a chunk). */
#define GEN_SHIFT   32
#define ACTIVE_ONE  (UINT64_C(1) << 24)
#define ACTIVE_MASK UINT64_C(0xff)
#define NEXT_MASK   UINT64_C(0xffffff)

/* The metric's bound for point i at p, whose contact search against this body frame gave t
   (closest point q, in region): t is the nearest triangle of all (within reach, or at any
   distance), so its pseudo-normal signs the distance exactly; none (-1) means nothing within
   reach and clearly outside. */
static void set_clearance(sim_collider *c, int i, const float p[3], int t, const float q[3],
                          int region)
{
    float clear = c->d.thickness_m + c->d.reach_m;
    if (t >= 0)
        clear = q ? sim_collider_signed_distance_at(c, t, p, q, region)
                  : sim_collider_signed_distance(c, t, p);
    c->clear[i][0] = p[0];
    c->clear[i][1] = p[1];
    c->clear[i][2] = p[2];
    c->clear[i][3] = c->nt > 0 ? clear : 0.0f;
}

/* Points [begin, end): the nearest triangle within reach (the cached one the first bound); none
   there: far outside, or deep inside (then the nearest at any distance). */
static void search_points(sim_collider *c, const float (*x)[4], int begin, int end)
{
    float reach = c->d.thickness_m + c->d.reach_m;
    const float(*v)[4] = (const float(*)[4])c->v;
    const int32_t(*tris)[4] = (const int32_t(*)[4])c->tris;
    for (int i = begin; i < end; i++) {
        float q[3], bary[3], dist;
        int region = SIM_REGION_FACE;
        int t = c->nt > 0 ? sim_bvh_nearest_region(&c->bvh, v, tris, x[i], reach, c->contact[i], q,
                                                   bary, &dist, &region)
                          : -1;
        if (t < 0 && c->nt > 0 && !sim_collider_clearly_outside(c, x[i]))
            t = sim_bvh_nearest_region(&c->bvh, v, tris, x[i], INFINITY, -1, q, bary, &dist,
                                       &region);
        c->contact[i] = t;
        set_clearance(c, i, x[i], t, q, region);
    }
}

#ifdef _OPENMP
/* Chunks of another thread's open range, until none is left. A claim is a compare-and-swap on
   the slot's word that also counts the claimer as active; it fails when the owner has closed or
   reopened the range since its fields were read, so a claim always pairs a chunk with the range
   it belongs to. The owner waits for the active count to drop before it returns. */
static void help_slot(sim_collider *c, sim_contact_slot *s)
{
    for (;;) {
        uint64_t w = atomic_load_explicit(&s->word, memory_order_acquire);
        if (!((w >> GEN_SHIFT) & 1))
            return; /* closed */
        const float(*x)[4] = (const float(*)[4])atomic_load_explicit(&s->x, memory_order_relaxed);
        int begin = atomic_load_explicit(&s->begin, memory_order_relaxed);
        int end = atomic_load_explicit(&s->end, memory_order_relaxed);
        int off = (int)(w & NEXT_MASK);
        if (off >= end - begin)
            return;
        if (!atomic_compare_exchange_weak_explicit(&s->word, &w, w + SHARE_CHUNK + ACTIVE_ONE,
                                                   memory_order_acquire, memory_order_relaxed))
            continue;
        int stop = begin + off + SHARE_CHUNK < end ? begin + off + SHARE_CHUNK : end;
        search_points(c, x, begin + off, stop);
        atomic_fetch_sub_explicit(&s->word, ACTIVE_ONE, memory_order_release);
    }
}

/* This thread's range through its slot, then help the team's other open ranges, then wait until
   the chunks others took of this one are done. */
static void search_shared(sim_collider *c, const float (*x)[4], int begin, int end, int me,
                          int team)
{
    sim_contact_slot *s = &c->share[me];
    uint64_t gen = (atomic_load_explicit(&s->word, memory_order_relaxed) >> GEN_SHIFT) + 1;
    atomic_store_explicit(&s->x, (uintptr_t)x, memory_order_relaxed);
    atomic_store_explicit(&s->begin, begin, memory_order_relaxed);
    atomic_store_explicit(&s->end, end, memory_order_relaxed);
    atomic_store_explicit(&s->word, gen << GEN_SHIFT, memory_order_release); /* open */
    for (;;) {
        uint64_t w = atomic_fetch_add_explicit(&s->word, SHARE_CHUNK, memory_order_acquire);
        int off = (int)(w & NEXT_MASK);
        if (off >= end - begin)
            break;
        search_points(c, x, begin + off,
                      begin + off + SHARE_CHUNK < end ? begin + off + SHARE_CHUNK : end);
    }
    for (int k = 1; k < team; k++)
        help_slot(c, &c->share[(me + k) % team]);
    /* every chunk is claimed; wait for those being done elsewhere (their release makes their
       results visible here), then close (no claim can succeed: nothing is left to claim) */
    for (int spin = 0;
         (atomic_load_explicit(&s->word, memory_order_acquire) >> 24 & ACTIVE_MASK) != 0; spin++)
        if (spin > 64)
            sched_yield(); /* a helper that lost its core */
    atomic_store_explicit(&s->word, (gen + 1) << GEN_SHIFT, memory_order_relaxed);
}
#endif

void sim_collider_find_contacts(sim_collider *c, const float (*x)[4], int begin, int end)
{
    if (!c || !x)
        return;
    end = end < c->max_cloth ? end : c->max_cloth;
    if (end <= begin)
        return;
#ifdef _OPENMP
    int team = omp_get_num_threads(), me = omp_get_thread_num();
    if (omp_get_active_level() == 1 && team > 1 && team <= SIM_SHARE_SLOTS &&
        end - begin <= SIM_SHARE_MAX_POINTS) {
        search_shared(c, x, begin, end, me, team);
        return;
    }
#endif
    /* called by one thread: the points split over a team of its own */
#pragma omp parallel for schedule(dynamic, SHARE_CHUNK)
    for (int i = begin; i < end; i++)
        search_points(c, x, i, i + 1);
}

void sim_collider_research(sim_collider *c, const float (*x)[4], int begin, int end)
{
    if (!c || !x || c->nt == 0)
        return;
    end = end < c->max_cloth ? end : c->max_cloth;
    for (int i = begin; i < end; i++) {
        if (x[i][3] == 0.0f)
            continue;
        const float *b = c->clear[i];
        float d[3] = {x[i][0] - b[0], x[i][1] - b[1], x[i][2] - b[2]};
        float r = sim_research_radius(b[3], c->d.thickness_m);
        if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > r * r)
            search_points(c, x, i, i + 1);
    }
}

void sim_collider_adopt_contacts(sim_collider *c, const float (*x)[4], const int32_t *contact,
                                 int begin, int end)
{
    if (!c || !x || !contact)
        return;
    end = end < c->max_cloth ? end : c->max_cloth;
#pragma omp parallel for schedule(static)
    for (int i = begin; i < end; i++) {
        int t = contact[i] >= 0 && contact[i] < c->nt ? contact[i] : -1;
        c->contact[i] = t;
        set_clearance(c, i, x[i], t, NULL, 0);
    }
}
