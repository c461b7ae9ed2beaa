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
    sp_int contact_every;      /* contacts searched again every this many steps, 0 = never */
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
    float rest_tol;            /* m, SIM_REST_TOL_M */
} sim_solver_params;

#define SIM_SOLVER_PARAMS_FIELDS 27 /* 4-byte fields */

#endif
