/* Private to sim/: a live stage's deadline for a body frame (sim_desc.frame_budget_ms). The
 * driver (sim.c) asks before each attempt how many settle tests fit in the time left, from what
 * the last frames cost; the solvers stop their settle rounds there (sim_solver_params
 * .settle_tests), so both backends keep the deadline without reading a clock mid-frame. */
#ifndef TRYON_SIM_BUDGET_H
#define TRYON_SIM_BUDGET_H

#include "sim.h"

/* What the frames so far cost, smoothed; zeros until a frame was measured. */
typedef struct sim_budget {
    float fixed_ms; /* an attempt's feature points and contact search */
    float round_ms; /* one solver round: a step, a post round or a settle round alike (a settle
                       round does less than a step, so the estimate is on the safe side) */
    float tail_ms;  /* after the attempts: the published metrics */
} sim_budget;

/* The settle tests an attempt of iters steps may run when spent_ms of a frame of budget_ms are
   gone: 0..full; full without a budget (budget_ms <= 0) or before anything was measured. */
int sim_budget_settle_tests(const sim_budget *b, double budget_ms, double spent_ms, int iters,
                            int full);

/* An attempt of iters steps measured (its stage times and settle rounds in st). */
void sim_budget_learn_attempt(sim_budget *b, const sim_frame_stats *st, int iters);
/* The frame's tail measured (st->ms_metrics). */
void sim_budget_learn_tail(sim_budget *b, const sim_frame_stats *st);

/* The bodies' pace, for a deadline per body (tryon-sim --frame-budget auto): a frame that ends
 * before the next body arrives leaves no body waiting, and none superseded. Learnt from the
 * bodies themselves; zeros until measured. Times: wall clock, as BODY's utime_capture. */
typedef struct sim_pace {
    int32_t last_seq;
    int64_t last_capture_us; /* 0: no body yet */
    float period_ms;         /* between two camera frames (capture times over seq steps) */
    float arrive_ms;  /* capture -> body at tryon-sim, from bodies that found it waiting (a body
                         queued while it worked is stamped late, and not learnt) */
    float publish_ms; /* after sim_step: CLOTH and TIMING out */
} sim_pace;

/* A body arrived: seq and capture time; received_us is exact when the sim was waiting for it. */
void sim_pace_body(sim_pace *p, int32_t seq, int64_t capture_us, int64_t received_us, int exact);
/* The publishing after a frame took ms. */
void sim_pace_published(sim_pace *p, float ms);
/* The frame budget (ms from now_us, sim_desc.frame_budget_ms) of the body captured at
 * capture_us: its frame ends, publishing included, by the earlier of the next body's arrival
 * (capture + period + arrive) and capture + deadline_ms (0: no such deadline). fallback_ms until
 * the pace is known, and for a body captured more than a second ago (a recorded log played
 * again: its stamps say nothing of now); at least SIM_PACE_MIN_MS when the deadline has passed
 * (0 would be no budget to sim_step: no settle round runs, the frame is as short as it can be). */
float sim_pace_budget_ms(const sim_pace *p, int64_t capture_us, int64_t now_us, float deadline_ms,
                         float fallback_ms);
#define SIM_PACE_MIN_MS 0.001f

/* Sets a live sim's frame budget for its next sim_step (sim_desc.frame_budget_ms; a NaN or
 * negative one is ignored). */
void sim_set_frame_budget(sim *s, float ms);

#endif
