/* Private to sim/: the cloth state layout both backends share (STYLE.md 3), the backend table,
 * the driver's state and constants (the passes over it: passes.h, included by their users). Layout
 * rule: fields are only ever added, never renamed.
 */
#ifndef TRYON_SIM_CLOTH_H
#define TRYON_SIM_CLOTH_H

#include <stddef.h>
#include <stdint.h>

#include "budget.h"
#include "collide.h"
#include "sim.h"
#include "spring_kind.h"

/* The cloth, structure of arrays of float. Springs are sorted by graph colour: no two springs
 * of one colour share a vertex, so a colour is processed in parallel without write conflicts
 * (C: OpenMP over a colour; OpenCL: one launch per colour). */
typedef struct sim_cloth {
    int nv, nt, ns;
    float (*x)[4];      /* xyz, w = inverse mass (0 = pinned or attached) */
    float (*x_prev)[4]; /* previous step, same layout; velocity = (x - x_prev) / dt */
    float (*x_rest)[4]; /* the garment as given */
    int32_t (*tris)[4]; /* w unused */
    int32_t (*ends)[2]; /* spring end vertices */
    float *rest;        /* spring rest length, m */
    uint8_t *kind;      /* sim_spring_kind */
    int num_colors;
    int32_t *color_start;      /* colour c holds springs [color_start[c], color_start[c + 1]) */
    int num_stretch_colors;    /* colours [0, this) hold only stretch springs; the rest none */
    float k[SIM_SPRING_KINDS]; /* stiffness per kind, N/m (after any clamp the solver needs) */
    int num_attachments;
    sim_attachment *attachments;
    /* Long-range attachments (tethers, Kim et al. 2012): each free vertex may not be farther
     * from its (geodesically) nearest attached vertex than it was at rest; -1 = no tether. */
    int32_t *tether_anchor;
    float *tether_len;
    /* The strain-limit hierarchy (shock propagation from the attachments outward): the free
     * vertices that attachments reach, by level (the longest chain of parents: stretch
     * neighbours a hop nearer the nearest attached vertex, or as near and above; hierarchy.c);
     * entry e is vertex hier_vertex[e], its stretch springs to its parents are
     * [hier_parent_start[e], hier_parent_start[e + 1]) of hier_parent / hier_rest. */
    int hier_levels;
    int32_t *hier_level_start; /* [hier_levels + 1] entries; level l is entries [start[l], ..) */
    int32_t *hier_vertex;
    int32_t *hier_parent_start;
    int32_t *hier_parent;
    float *hier_rest;
    /* The stretch springs of each vertex (CSR, spring indices in ascending order): vertex v's are
     * adj_spring[adj_start[v] .. adj_start[v + 1]). The support hierarchy walks them. */
    int32_t *adj_start;
    int32_t *adj_spring;
} sim_cloth;

/* The body as the driver keeps it: frame k and k-1. */
typedef struct sim_body {
    int nv, nt;
    int have_prev; /* 0 on the first frame and after a topology change */
    float (*v)[4];
    float (*v_prev)[4];
    int32_t (*tris)[4];
    float (*n)[4];    /* face normals of frame k, of the attachments' triangles only */
    float max_move_m; /* the farthest any vertex moved from k-1 to k */
    long stored;      /* body frames stored: a backend uploads a frame once, whatever the retries */
} sim_body;

struct sim;

/* A backend is a table of functions, like LCM's providers. The driver (sim.c) owns the host
 * state, the host collider (metrics, recovery) and the timing; a backend runs the per-frame
 * work and leaves the result in s->cloth.x / x_prev on the host. */
typedef struct sim_backend_ops {
    const char *name; /* "c", "opencl" */
    /* Allocate the backend's state for s (cloth and body sizes are final). */
    int (*create)(struct sim *s, void **state, char *err, size_t err_size);
    void (*destroy)(void *state);
    /* One body frame: s->body holds frames k and k-1, s->collider has been given frame k. Run
     * feature points, contacts and `iterations` Verlet steps of frame_dt / iterations, filling
     * the ms_* of st it measures and st->feature_points_moved. Returns 0 or -SIM_ERR_x. */
    int (*frame)(void *state, struct sim *s, int iterations, sim_frame_stats *st);
    /* The host state was restored after a divergence: make the device copy match it. */
    int (*upload)(void *state, const struct sim *s);
    const char *(*device_name)(const void *state);
} sim_backend_ops;

extern const sim_backend_ops sim_backend_c;
#ifdef SIM_HAVE_OPENCL
extern const sim_backend_ops sim_backend_opencl;
#endif

struct sim {
    sim_desc desc;
    sim_cloth cloth;
    sim_body body;
    sim_collider *collider;
    const sim_backend_ops *ops;
    void *backend;
    float (*x_good)[4]; /* last published (good) state, restored on divergence */
    float (*x_prev_good)[4];
    float (*x_best)[4]; /* the attempt nearest the strain goals of a frame retried for them */
    float (*x_prev_best)[4];
    float (*x_pinch)[4]; /* of a frame no attempt solved, the least pinched (SIM_PINCH_SPRINGS) */
    float (*x_prev_pinch)[4];
    float *scratch;    /* ns floats: strains for the percentile */
    int32_t *tris3;    /* garment triangles [nt][3] for sim_triangles */
    long frame;        /* body frames stepped */
    int iters_good;    /* the steps of the frame that made the good state (its velocity's step) */
    float strain_good; /* max stretch strain of the last good frame */
    float excess_good; /* its strain over the retry goals (sim.c: strain_excess; > 1: missed) */
    int carried_run;   /* frames carried in a row, up to this one (sim.c: carry_good) */
    /* The moving frame of this body frame (follow.c): x -> m x (3 x 4, row-major) applied to
       the garment before the feature points when follow_on; follow_pq: 2 * (num_attachments +
       SIM_FOLLOW_ANCHORS) points, the anchors (or the attachments) in frames k-1 and k. */
    float follow_m[12];
    int follow_on;
    double (*follow_pq)[3];
    /* The moving frame's anchors: body vertices under the garment's waist band (follow.c),
       chosen on a body frame of follow_anchor_nv vertices. */
    int32_t *follow_anchor;
    int num_follow_anchors, follow_anchor_nv;
    struct sim_carry *carry; /* a frame no attempt solves: the good cloth carried (carry.c) */
    float (*x_first)[4];     /* the garment as made, on the first body frame (body_first) */
    float (*body_first)[4];  /* [max_body_vertices]: that body frame, for re-dressing */
    int first_nv, first_nt;  /* its size; 0 until a body frame was stored */
    /* The frame budget (sim.c, budget.c): the settle tests the next attempt may run
       (sim_solver_params.settle_tests; SIM_SETTLE_ROUNDS / SIM_SETTLE_BATCH without a budget),
       and what the frames so far cost. */
    int settle_tests_max;
    sim_budget budget;
};

/* Solver constants and the reasons for them. */
#define SIM_PEN_TOL_M           0.001f /* ARCHITECTURE.md: penetrating = more than 1 mm inside */
#define SIM_PROVOT_TAU          0.10f  /* Provot 1995: springs corrected past 10 % elongation */
#define SIM_DIVERGE_STRAIN      0.5f   /* 50 % stretch is no fabric: the step blew up */
#define SIM_DIVERGE_SPEED       50.0f  /* m/s; no garment point moves that fast on a person */
#define SIM_DIVERGE_FRAME_SPEED 30.0f  /* m/s over a frame: 3 s of free fall, 6x a fast wrist */
#define SIM_MAX_RETRIES         2      /* each retry doubles the iterations */
#define SIM_CARRY_MAX_STRAIN    0.10f  /* a carried cloth stretched more is dressed again (carry) */
/* Frames carried in a row after which the garment is dressed again as made (sim.c, carry_good):
   the moving frame carries the last good cloth as it is, and a last good cloth the solver cannot
   leave (the T-shirt torn in the arm raise) was carried to the end of the scene, 110 frames. Half
   a second: the boxer's longest carried run (14 frames, the clip whole) ends by itself, and
   dressed again at 5 it went 65 mm inside him (docs/sim-history-6.md, "Contacts searched again
   where a point moved"). */
#define SIM_CARRY_REDRESS_RUN 15
/* A pinch is no tear: at most this many stretch springs past SIM_DIVERGE_STRAIN, none past
   SIM_PINCH_STRAIN. Where a hand presses the hem into the hip the cloth between them has no room:
   on the boxing clip's fitted bodies 1-10 springs of 6 mm went past 50 % (the cloth moved at most
   5 cm, nothing else stretched), the whole frame was failed and the garment carried rigidly,
   20-30 mm inside a body that moved on, and the frames after it, starting there, tore for real
   (80-330 springs; docs/sim-real-motion.md, "Real motion: pinches"). A pinched attempt is retried
   as a torn one is; when no attempt is good, the least pinched is published (sim.c, sim_step). */
#define SIM_PINCH_SPRINGS 16
#define SIM_PINCH_STRAIN  2.0f /* a spring at three times its length has torn, whatever else */
/* A state past SIM_DIVERGE_STRAIN (max_strain, springs_over springs past it) that only pinched. */
static inline int sim_is_pinch(float max_strain, int springs_over)
{
    return max_strain < SIM_PINCH_STRAIN && springs_over <= SIM_PINCH_SPRINGS;
}
/* A strain grown from the last good frame's (good): state_diverged's test. */
static inline float sim_strain_grown(float good)
{
    return 1.05f * good + 0.01f;
}
/* An attempt over this strain has torn: past SIM_DIVERGE_STRAIN and grown, state_diverged fails
   it (sim_solver_params.settle_torn: its settle rounds stop there). */
static inline float sim_torn_strain(float good)
{
    float g = sim_strain_grown(good);
    return g > SIM_DIVERGE_STRAIN ? g : SIM_DIVERGE_STRAIN;
}
/* tryon: the strain goals a frame is retried for (sim_desc.retry_max_strain, retry_p99_strain) */
#define SIM_RETRY_STRAIN   0.03f
#define SIM_RETRY_P99      0.01f
#define SIM_CONTACT_MARGIN 0.03f /* tryon: contacts cached with this reach beyond thickness */
/* tryon: a frame is fast (sim_solver_params.fast) when its fastest cloth point would travel
   farther than this in the frame (the reach: past it a point may meet what the frame's search did
   not see; each such point is searched again as it passes its clearance, sim_collider_research).
   Until 2026-12-08 a fast frame searched every point again every 10 steps instead
   (docs/sim-history-6.md, "Contacts searched again where a point moved"). */
#define SIM_FAST_TRAVEL SIM_CONTACT_MARGIN
/* tryon: a vertex within this of the thickness from its contact triangle rests on the body (the
   response leaves it at the thickness; a millimetre covers the strain passes' moves since) */
#define SIM_REST_TOL_M  0.001f
#define SIM_POST_ROUNDS 4 /* tryon: (strain sweep, tethers, contacts) after the hierarchy */
/* tryon: after those, more rounds, SIM_SETTLE_BATCH at a time and up to SIM_SETTLE_ROUNDS, while
   the largest stretch strain is above SIM_SETTLE_STRAIN: frames where the body moved the cloth
   fast (the walk, the swing) get them, a standing body none (docs/sim.md, "Settle rounds"). */
#define SIM_SETTLE_STRAIN 0.02f
#define SIM_SETTLE_ROUNDS 50 /* 26 until the walk's frames were seen to use them all */
#define SIM_SETTLE_BATCH  2
/* ... and only while each batch takes at least 2 % off that strain: a garment the rounds cannot
   settle (the drape's corners, 9 % falling by 1-2 % a batch) is left to the next frame; frames
   that refresh their contacts search them once more first and do not stop early, nor do frames
   over the strain retry goal (sim_settle_stop: stopped there, the frame is done again) */
#define SIM_SETTLE_PROGRESS 0.98f

/* The moving frame (follow.c). sim_fit_rigid: the rigid motion x -> m x (3 x 4, row-major)
 * that maps the n >= 3 points p onto q best in least squares, or that fraction (0..1) of it (the
 * angle about the same axis, the centroid's way); 0, or -1 when none is defined.
 * sim_follow_motion: s->follow_m and follow_on for this body frame, from the body under the
 * garment's waist band (its anchors; the attachments where it has none).
 * sim_follow: x and x_prev of vertices [begin, end) moved by m (twin: kernels/springs.cl). */
int sim_fit_rigid(const double (*p)[3], const double (*q)[3], int n, double fraction, float m[12]);
void sim_follow_motion(struct sim *s);
void sim_follow(float (*x)[4], float (*x_prev)[4], int begin, int end, const float m[12]);
/* The moving frame's anchors: at most this many body vertices, those nearest the garment's
   vertices whose tether (rest distance to the nearest attachment) is within
   SIM_FOLLOW_BAND_M under SIM_FOLLOW_DEPTH of the longest one: the shirt's waist, half way from
   its chest to its hem. Measured ("Bends: the cause" in docs/sim-history.md): the hem's own band
   holds the thighs, and the marching walk's frame swung with them (47 % strain); at 0.75 and 0.6
   bend_forward had 95.3 % of frames within the goals, at 0.5 99.3 %, at 0.4 80 % (120 frames) */
#define SIM_FOLLOW_ANCHORS 64
#define SIM_FOLLOW_DEPTH   0.5f
#define SIM_FOLLOW_BAND_M  0.01f

/* Fill why (may be NULL) with code and a formatted place; returns -code. */
int sim_reject_set(sim_reject *why, sim_error code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Garment helpers (garment.c): arrays allocated for nv vertices, nt triangles, na attachments;
 * triangles of a tube of cols x rows vertices, row-major, the last column joined to the first. */
int sim_garment_alloc(sim_garment *g, int nv, int nt, int na);
void sim_garment_tube_triangles(int32_t *t, int cols, int rows);

/* Cloth construction (cloth.c). */
int sim_cloth_init(sim_cloth *c, const sim_garment *g, const sim_fabric *f, sim_reject *why);
void sim_cloth_free(sim_cloth *c);
/* The strain-limit hierarchy's arrays from the attachments and the stretch springs by vertex
   (hierarchy.c); 0 or -SIM_ERR_NO_MEMORY (sim_cloth_free frees what was made). */
int sim_cloth_hierarchy(sim_cloth *c);
/* Metrics (metrics.c): stretch strain max and p99; scratch holds ns floats. */
void sim_strain_stats(const sim_cloth *c, float *scratch, float *max_strain, float *p99_strain);
/* How many stretch springs with a free end are strained past limit, and the largest strain of
 * those springs into *free_max (a spring between two glued vertices is as long as the body
 * makes it: no solver can tear it or mend it). */
int sim_strain_count_over(const sim_cloth *c, float limit, float *free_max);

#endif
