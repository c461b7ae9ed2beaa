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

#endif
