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

/* Seq steps over which two capture times still give the camera's period: a body stage that
   drops frames skips seqs, one restarted begins again at 0. */
#define SIM_PACE_MAX_SEQ_STEP 30
/* Periods and arrivals past this are no pace (a paused recording, a clock step). */
#define SIM_PACE_MAX_MS 1000.0f

void sim_pace_body(sim_pace *p, int32_t seq, int64_t capture_us, int64_t received_us, int exact)
{
    int32_t steps = seq - p->last_seq;
    if (p->last_capture_us > 0 && steps > 0 && steps <= SIM_PACE_MAX_SEQ_STEP) {
        float ms = (float)(capture_us - p->last_capture_us) / 1000.0f / (float)steps;
        if (ms > 0.0f && ms <= SIM_PACE_MAX_MS)
            p->period_ms = smooth(p->period_ms, ms);
    }
    float arrive = (float)(received_us - capture_us) / 1000.0f;
    if (exact && arrive <= SIM_PACE_MAX_MS)
        p->arrive_ms = smooth(p->arrive_ms, arrive);
    p->last_seq = seq;
    p->last_capture_us = capture_us;
}

void sim_pace_published(sim_pace *p, float ms)
{
    p->publish_ms = smooth(p->publish_ms, ms);
}

float sim_pace_budget_ms(const sim_pace *p, int64_t capture_us, int64_t now_us, float deadline_ms,
                         float fallback_ms)
{
    double age_ms = (double)(now_us - capture_us) / 1000.0;
    if (!(p->period_ms > 0.0f) || !(age_ms <= SIM_PACE_MAX_MS))
        return fallback_ms; /* no pace yet, or a stamp from another time (a log played again) */
    double due_ms = (double)p->period_ms + (double)p->arrive_ms; /* the next body, from capture */
    if (deadline_ms > 0.0f && deadline_ms < due_ms)
        due_ms = deadline_ms;
    double left = due_ms - age_ms - (double)p->publish_ms;
    return left > SIM_PACE_MIN_MS ? (float)left : SIM_PACE_MIN_MS;
}

void sim_set_frame_budget(sim *s, float ms)
{
    if (s && ms >= 0.0f)
        s->desc.frame_budget_ms = ms;
}
