/* The frame budget's cost model (budget.h): an attempt costs its fixed part plus a round's time
 * for each step, the post-stabilisation's rounds and each settle round. */
#include <math.h>

#include "budget.h"
#include "cloth.h"

/* Weight of the newest frame in the smoothed costs: a step of the walk costs twice its
   neighbour on a busy machine, and one frame must not swing the next frame's plan. */
#define SIM_BUDGET_SMOOTH 0.25f

/* The rounds an attempt of iters steps runs before its settle rounds (cloth.h: the hierarchy's
   round and SIM_POST_ROUNDS more). */
static int rounds_before_settle(int iters)
{
    return iters + 1 + SIM_POST_ROUNDS;
}

static float smooth(float old, float now)
{
    if (!(now >= 0.0f) || !isfinite(now))
        return old;
    return old > 0.0f ? old + SIM_BUDGET_SMOOTH * (now - old) : now;
}

int sim_budget_settle_tests(const sim_budget *b, double budget_ms, double spent_ms, int iters,
                            int full)
{
    if (!(budget_ms > 0.0) || !(b->round_ms > 0.0f))
        return full;
    double left = budget_ms - spent_ms - b->fixed_ms - b->tail_ms -
                  (double)b->round_ms * rounds_before_settle(iters);
    double tests = floor(left / ((double)b->round_ms * SIM_SETTLE_BATCH));
    return tests <= 0.0 ? 0 : tests >= full ? full : (int)tests;
}

void sim_budget_learn_attempt(sim_budget *b, const sim_frame_stats *st, int iters)
{
    int rounds = rounds_before_settle(iters) + st->settle_rounds;
    b->fixed_ms = smooth(b->fixed_ms, st->ms_feature_points + st->ms_contacts);
    b->round_ms = smooth(b->round_ms, st->ms_iterations / (float)rounds);
}

void sim_budget_learn_tail(sim_budget *b, const sim_frame_stats *st)
{
    b->tail_ms = smooth(b->tail_ms, st->ms_metrics);
}
