/* The tryon solver's settings for a frame, one formula each, for the C and OpenCL backends. */
#include <math.h>
#include <string.h>

#include "cloth.h"
#include "passes.h"
#include "frame_settings.h"

_Static_assert(sizeof(sim_solver_params) == SIM_SOLVER_PARAMS_FIELDS * 4,
               "sim_solver_params: 4-byte fields only, no padding (kernels/solver_params.h)");
_Static_assert(SIM_SPRING_KINDS == 3, "sim_solver_params.alpha: one per spring kind");

void sim_solver_params_fill(const struct sim *s, int iters, sim_solver_params *p)
{
    const sim_cloth *c = &s->cloth;
    const sim_collider *col = s->collider;
    memset(p, 0, sizeof *p);
    float dt = s->desc.frame_dt_s / (float)iters;
    p->nv = c->nv;
    p->num_colors = c->num_colors;
    p->num_stretch_colors = c->num_stretch_colors;
    p->iters = iters;
    p->dt = dt;
    for (int k = 0; k < SIM_SPRING_KINDS; k++)
        p->alpha[k] = c->k[k] > 0.0f ? 1.0f / (c->k[k] * dt * dt) : 1e30f;
    p->limit = s->desc.strain_limit;
    /* damping: the fraction of velocity lost per second, spread over the substeps */
    p->keep = s->desc.damping > 0.0f ? powf(1.0f - s->desc.damping, dt) : 1.0f;
    p->g[1] = -s->desc.gravity_m_s2 * dt * dt;
    p->radius = col->d.thickness_m + col->d.reach_m;
    p->h = col->d.thickness_m;
    p->mu = col->d.friction;
    p->natt = c->num_attachments;
    p->hier_levels = c->hier_levels;
    p->post_rounds = SIM_POST_ROUNDS;
    p->settle_tests =
        s->settle_tests_max; /* SIM_SETTLE_ROUNDS / SIM_SETTLE_BATCH, or the budget's */
    p->settle_batch = SIM_SETTLE_BATCH;
    p->settle_progress = SIM_SETTLE_PROGRESS;
    p->settle_strain = SIM_SETTLE_STRAIN;
    p->support = s->desc.support && c->num_attachments == 0;
    p->settle_hold = s->desc.solver == SIM_SOLVER_TRYON && s->desc.retry_max_strain > 0.0f
                         ? s->desc.retry_max_strain
                         : 0.0f;
    p->settle_torn = s->desc.solver == SIM_SOLVER_TRYON ? sim_torn_strain(s->strain_good) : 0.0f;
    p->rest_tol = SIM_REST_TOL_M;
}

float sim_step_travel2(const sim_cloth *c, int b, int e)
{
    float m2 = 0.0f;
    for (int i = b; i < e; i++) {
        float d[3] = {c->x[i][0] - c->x_prev[i][0], c->x[i][1] - c->x_prev[i][1],
                      c->x[i][2] - c->x_prev[i][2]};
        m2 = fmaxf(m2, d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    }
    return m2;
}

int sim_frame_fast(float travel2, int iters)
{
    return sqrtf(travel2) * (float)iters > SIM_FAST_TRAVEL;
}
