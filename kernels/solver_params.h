/* The tryon solver's settings for one frame, declared once for the host and the OpenCL kernels:
 * sim/solver_params.c fills it for both backends (the C solver reads it, sim/cl_backend.c passes
 * it by value to sim_iterations_tryon in kernels/springs.cl, which the host builds with this file
 * before it). Only 4-byte int and float fields, no vectors: no padding, the same layout in C and
 * OpenCL C. The host asserts the size; the kernel sim_solver_params_layout reports its own size
 * and the last field's offset, which test_cl_backend compares with the host's. */
#ifndef TRYON_SOLVER_PARAMS_H
#define TRYON_SOLVER_PARAMS_H

#ifdef __OPENCL_VERSION__
typedef int sp_int;
#else
#include <stdint.h>
typedef int32_t sp_int;
#endif

typedef struct sim_solver_params {
    sp_int nv;                 /* cloth vertices */
    sp_int num_colors;         /* spring colours, the stretch ones first */
    sp_int num_stretch_colors; /* colours of stretch springs (the strain limit's sweep) */
    sp_int iters;              /* steps in the frame */
    float dt;                  /* s, one step */
    float alpha[3];            /* XPBD compliance / dt^2 per spring kind, 1/(k dt^2) */
    float limit;               /* the strain limit, a fraction of rest */
    float keep;                /* velocity kept per step (damping) */
    float g[3];                /* gravity times dt^2, m */
    sp_int fast;               /* the cloth travels past the contacts' reach in the frame (0/1) */
    sp_int nleaves;            /* body triangles (the BVH's leaves) */
    float radius;              /* m, the contact search's reach: thickness + reach */
    float h;                   /* m, the cloth's thickness */
    float mu;                  /* friction */
    sp_int natt;               /* attachments */
    sp_int hier_levels;        /* levels of the strain-limit hierarchy */
    sp_int post_rounds;        /* SIM_POST_ROUNDS */
    sp_int settle_tests;       /* SIM_SETTLE_ROUNDS / SIM_SETTLE_BATCH */
    sp_int settle_batch;       /* SIM_SETTLE_BATCH */
    float settle_progress;     /* SIM_SETTLE_PROGRESS */
    float settle_strain;       /* SIM_SETTLE_STRAIN */
    sp_int support;            /* the support hierarchy on (a garment without attachments) */
    float settle_hold; /* above this strain the settle rounds do not stop for slow progress: the
                          frame's retry goal (sim_desc.retry_max_strain; 0: no retries) */
    float settle_torn; /* over this strain the settle rounds stop: the attempt is torn, the
                          driver's divergence test fails it whatever settling does (cloth.h
                          sim_torn_strain; 0: never) */
    float rest_tol;    /* m, SIM_REST_TOL_M (the last field: sim_solver_params_layout) */
} sim_solver_params;

#define SIM_SOLVER_PARAMS_FIELDS 29 /* 4-byte fields */

#endif

/* ---- The tryon frame: one list of stages both backends walk ----------------------------------
 * sim/solver_c.c iterations_tryon and kernels/springs.cl sim_iterations_tryon both run a frame as
 * sim_frame_blocks below: each block a run of stages of sim_frame_stages, repeated
 * sim_block_repeats times, a stage skipped where sim_stage_runs says so. A backend only says how
 * it runs each stage (threads and phases on the host, one work-group on a device). */
typedef enum sim_stage {
    SIM_STAGE_START,       /* per vertex: the moving frame, feature points, attachment targets */
    SIM_STAGE_CONTACTS,    /* the contact search */
    SIM_STAGE_STEP,        /* per vertex: Verlet, the attachments placed */
    SIM_STAGE_SPRINGS,     /* XPBD, colour by colour */
    SIM_STAGE_SWEEP,       /* the strain limit, one Gauss-Seidel sweep over the stretch colours */
    SIM_STAGE_VERTICES,    /* per vertex: tethers, the post-stabilisation's bracket closed (post
                              rounds: x_prev += x), the contact searched again for a point that
                              moved past its clearance, the contact response, the bracket opened
                              for the next post round (x_prev -= x) */
    SIM_STAGE_HIERARCHY,   /* the strain-limit hierarchy, level by level */
    SIM_STAGE_SUPPORT,     /* the support hierarchy (support set: no attachments) */
    SIM_STAGE_SETTLE_TEST, /* the largest stretch strain: the settle rounds go on or stop */
    SIM_STAGE_REOPEN,      /* per vertex: the bracket opened for a settle round */
    SIM_STAGES
} sim_stage;

typedef enum sim_block {
    SIM_BLOCK_OPEN,   /* once: START, CONTACTS */
    SIM_BLOCK_STEPS,  /* iters steps: STEP, SPRINGS, SWEEP, VERTICES */
    SIM_BLOCK_POST,   /* 1 + post_rounds rounds: HIERARCHY and SUPPORT in the first, SWEEP,
                         VERTICES */
    SIM_BLOCK_SETTLE, /* up to settle_tests * settle_batch rounds: SETTLE_TEST before each batch,
                         REOPEN, SWEEP, VERTICES */
    SIM_BLOCKS
} sim_block;

#ifdef __OPENCL_VERSION__
#define SIM_FRAME_TABLE __constant
#else
#define SIM_FRAME_TABLE static const
#endif

SIM_FRAME_TABLE int sim_frame_stages[] = {
    SIM_STAGE_START,       SIM_STAGE_CONTACTS,                                       /* OPEN */
    SIM_STAGE_STEP,        SIM_STAGE_SPRINGS,  SIM_STAGE_SWEEP, SIM_STAGE_VERTICES,  /* STEPS */
    SIM_STAGE_HIERARCHY,   SIM_STAGE_SUPPORT,  SIM_STAGE_SWEEP, SIM_STAGE_VERTICES,  /* POST */
    SIM_STAGE_SETTLE_TEST, SIM_STAGE_REOPEN,   SIM_STAGE_SWEEP, SIM_STAGE_VERTICES}; /* SETTLE */
/* block b's stages: sim_frame_stages[sim_block_start[b] .. sim_block_start[b + 1]) */
SIM_FRAME_TABLE int sim_block_start[SIM_BLOCKS + 1] = {0, 2, 6, 10, 14};

/* How many times block b runs in a frame (the settle block at most: SETTLE_TEST may end it). */
static inline int sim_block_repeats(int b, const sim_solver_params *p)
{
    return b == SIM_BLOCK_STEPS    ? p->iters
           : b == SIM_BLOCK_POST   ? 1 + p->post_rounds
           : b == SIM_BLOCK_SETTLE ? p->settle_tests * p->settle_batch
                                   : 1;
}

/* Whether stage st of block b runs in repetition rep. */
static inline int sim_stage_runs(int st, int b, int rep, const sim_solver_params *p)
{
    if (st == SIM_STAGE_HIERARCHY)
        return rep == 0;
    if (st == SIM_STAGE_SUPPORT)
        return rep == 0 && p->support;
    if (st == SIM_STAGE_SETTLE_TEST)
        return rep % p->settle_batch == 0;
    (void)b;
    return 1;
}

/* SIM_STAGE_VERTICES: whether it closes the post-stabilisation's bracket before the contact
   response (every post and settle round) and opens it after (the last step, every post round but
   the last: the next round's corrections are positions only). */
static inline int sim_vertices_close(int b)
{
    return b == SIM_BLOCK_POST || b == SIM_BLOCK_SETTLE;
}

static inline int sim_vertices_open(int b, int rep, const sim_solver_params *p)
{
    return b == SIM_BLOCK_STEPS ? rep == p->iters - 1 : b == SIM_BLOCK_POST && rep < p->post_rounds;
}

/* SIM_STAGE_SETTLE_TEST's decision, 1 to stop the settle rounds: the largest stretch strain m is
   within the settle goal; or, in a frame whose cloth is not fast (p->fast), the last batch did
   not take enough off it (prev: the test before; first: this is the frame's first test) while m
   is within the retry goal. Above that goal a frame stopped early is done again with twice the
   steps: the bends' frames take 1.5-3 % off a batch, at the progress bound, and reach the goal
   in the rounds left (docs/sim.md, "Real motion: the bends' settle rounds"). Or m is over
   settle_torn: the attempt has torn, the driver fails it whatever the rounds do, and they would
   only spend the frame's time. */
static inline int sim_settle_stop(float m, float prev, int first, int fast,
                                  const sim_solver_params *p)
{
    int hold = p->settle_hold > 0.0f && m > p->settle_hold;
    return !(m > p->settle_strain) || (p->settle_torn > 0.0f && m > p->settle_torn) ||
           (!fast && !first && !hold && !(m < p->settle_progress * prev));
}
