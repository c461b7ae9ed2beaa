/* sim: cloth on a moving body. A mass-spring garment is carried by the body (seed 000 feature
 * points) and relaxed by a few Verlet iterations with collision per body frame.
 *
 * Frame: world, metres, y up. Units SI. One sim simulates one garment; the caller owns every
 * array it passes in and may free it as soon as the call returns. */
#ifndef TRYON_SIM_H
#define TRYON_SIM_H

#include <stddef.h>
#include <stdint.h>

/* Why something was refused. One list makes the enum and the words (STYLE.md 11). */
#define SIM_ERROR_LIST(X)                                                                          \
    X(SIM_OK, "ok")                                                                                \
    X(SIM_ERR_ARG, "bad argument")                                                                 \
    X(SIM_ERR_NO_MEMORY, "out of memory")                                                          \
    X(SIM_ERR_EMPTY, "mesh has no vertices or no triangles")                                       \
    X(SIM_ERR_TOO_LARGE, "mesh larger than the configured maximum")                                \
    X(SIM_ERR_NOT_FINITE, "coordinate is NaN or infinite")                                         \
    X(SIM_ERR_INDEX, "triangle index out of range")                                                \
    X(SIM_ERR_DEGENERATE, "degenerate triangle (repeated vertex or zero area)")                    \
    X(SIM_ERR_MASS, "vertex mass not positive and finite")                                         \
    X(SIM_ERR_ATTACHMENT, "attachment refers to a missing vertex or body triangle")                \
    X(SIM_ERR_PARAM, "parameter out of range")                                                     \
    X(SIM_ERR_TOPOLOGY, "body topology differs from the garment's body")                           \
    X(SIM_ERR_BACKEND, "backend unavailable or failed")                                            \
    X(SIM_ERR_DIVERGED, "simulation diverged and could not recover")                               \
    X(SIM_ERR_FILE, "cannot read or parse the garment file")

#define SIM_ERROR_ENUM(id, text) id,
typedef enum sim_error { SIM_ERROR_LIST(SIM_ERROR_ENUM) SIM_ERROR_COUNT } sim_error;
#undef SIM_ERROR_ENUM
/* Errors are returned negated: a function returns 0 or -SIM_ERR_x. */
const char *sim_error_name(int e); /* "SIM_ERR_INDEX"; accepts e or -e */
const char *sim_error_text(int e); /* "triangle index out of range" */

typedef struct sim_reject {
    sim_error code;
    char detail[160]; /* where: "garment triangle 12: index 99 >= 42 vertices" */
} sim_reject;

typedef enum sim_backend { SIM_BACKEND_C = 0, SIM_BACKEND_OPENCL = 1 } sim_backend;

/* seed: seed 000 as published (force springs, Verlet, Provot correction, BVH rebuilt and
 * contacts searched every iteration). tryon: distance constraints projected by colour-batched
 * Gauss-Seidel in small steps, strain limiting, BVH refit, contacts cached per frame. */
typedef enum sim_solver { SIM_SOLVER_TRYON = 0, SIM_SOLVER_SEED = 1 } sim_solver;

/* Fabric. Stiffness is the membrane stiffness in N/m (force per unit width per unit strain);
 * on a square grid a spring of any length carries exactly this constant, so a fabric keeps its
 * behaviour when the mesh is refined. */
typedef struct sim_fabric {
    float density_kg_m2; /* 0 = 0.2 (cotton shirting) */
    float stretch_n_m;   /* 0 = 1000 */
    float shear_n_m;     /* 0 = 100 */
    float bend_n_m;      /* 0 = 2 */
} sim_fabric;

typedef struct sim_desc {
    sim_backend backend;
    sim_solver solver;
    int iterations;     /* Verlet steps per body frame; 0 = 25 */
    float frame_dt_s;   /* 0 = 1/30 */
    sim_fabric fabric;  /* zeros = defaults */
    float damping;      /* fraction of velocity lost per second; 0 = 0.5; < 0 = none */
    float thickness_m;  /* cloth kept this far outside the body; 0 = 0.004 */
    float friction;     /* Coulomb coefficient against the body; 0 = 0.3; < 0 = none */
    float gravity_m_s2; /* downward; 0 = 9.81; < 0 = none */
    float strain_limit; /* tryon solver: stretch springs clamped to rest * (1 + this); 0 = 0.0075 */
    /* tryon solver, garments with 3 or more attachments: the fraction of the rigid motion of
     * the body under the garment's waist band each body frame given to the whole garment before
     * it is simulated (a frame moving with the body, not with the chest when the trunk bends;
     * docs/sim.md, "The moving frame"); 0 = 1; < 0 = none (world frame). The seed solver always
     * simulates in the world frame. */
    float follow;
    /* tryon solver, garments without attachments: the support hierarchy, the strain limit
     * propagated in one pass outward from the vertex the body holds up (docs/sim.md); 0 = on;
     * < 0 = off. Garments with attachments propagate from those, always. */
    int support;
    /* tryon solver: a frame whose stretch strain ends over these goals (max, p99) is done again
     * from its start with twice, then four times the iterations, and the attempt nearest them
     * is published (state recovered), unless the frame before missed them too (docs/sim.md,
     * "Strain retries"); 0 = 0.03, 0.01 (ARCHITECTURE.md's goals after settling); < 0 = not a
     * goal (both: no such retries). */
    float retry_max_strain;
    float retry_p99_strain;
    /* A live mirror's budget for those retries, ms (0 = none, the default): a retry for the
     * strain goals is started only while the frame so far plus twice its last attempt stays
     * within it; otherwise the attempt nearest the goals so far is published, its strain in the
     * stats. A diverged attempt is retried whatever the budget. */
    float retry_budget_ms;
    /* A live stage's deadline for each body frame, ms of wall clock from sim_step's call (0 =
     * none, the default: every settle round and strain retry runs). The settle rounds are cut to
     * what the time left allows (from what the last frames cost: the first frame has no cut),
     * a strain retry is started only as retry_budget_ms says, and a frame cut short is published
     * as it stands, its strain measured, state SIM_STATE_SETTLING. A diverged attempt is retried
     * only while a retry twice as long fits in the time left; past that the frame is carried
     * (the garment as made, carried onto the body: SIM_STATE_CARRIED), or where it cannot be,
     * the last good cloth kept (SIM_STATE_DIVERGED). docs/sim.md, "tryon-sim". */
    float frame_budget_ms;
    int max_body_vertices;  /* 0 = 100000 */
    int max_body_triangles; /* 0 = 200000 */
} sim_desc;

sim_desc sim_default_desc(void); /* every field filled with its default */

typedef enum sim_state {
    SIM_STATE_OK = 0,
    SIM_STATE_RECOVERED = 1,
    SIM_STATE_DIVERGED = 2, /* no attempt solved the frame and nothing carried it: kept */
    /* the frame budget ran out before the settle rounds or a strain retry the frame wanted:
       the cloth as it stood, its strain as measured (cloth_t STATE_SETTLING) */
    SIM_STATE_SETTLING = 3,
    /* no attempt solved the frame: the last good cloth was carried by the body from the last
       body frame to this one (each point with the body's surface nearest it) and the solver
       resettles from there on the next frame (cloth_t STATE_CARRIED) */
    SIM_STATE_CARRIED = 4
} sim_state;
const char *sim_state_name(sim_state s);

/* What one body frame cost and produced. Times in ms of wall clock. */
typedef struct sim_frame_stats {
    float max_strain; /* stretch springs: (|xi - xj| - rest) / rest, max */
    float p99_strain;
    int penetrating;  /* cloth vertices more than 1 mm inside the body */
    float max_pen_mm; /* deepest of them */
    int feature_points_moved;
    sim_state state;
    int retries;         /* recovery attempts this frame */
    int strain_retries;  /* of them, for strain over the retry goals (not divergence) */
    int iterations_used; /* more than asked when recovering */
    int settle_rounds;   /* tryon: strain rounds after the post-stabilisation (0 when settled) */
    float ms_total;
    float ms_bvh;
    float ms_feature_points;
    float ms_contacts;
    float ms_iterations;
    float ms_metrics;
} sim_frame_stats;

/* A cloth vertex glued to a body triangle: x = b0 v0 + b1 v1 + b2 v2 + offset * n. */
typedef struct sim_attachment {
    int32_t vertex;
    int32_t body_triangle;
    float bary[3];
    float offset_m;
} sim_attachment;

/* A garment: a triangle mesh with masses. grid_w * grid_h = num_vertices (row-major) when the
 * mesh is a grid; then shear springs cross each quad and bend springs skip one vertex. Otherwise
 * (grid_w = 0) shear is omitted and bend joins the opposite vertices of adjacent triangles. */
typedef struct sim_garment {
    char id[64];
    int num_vertices;
    float *xyz;     /* [num_vertices][3] */
    float *mass_kg; /* [num_vertices]; NULL = lumped from the fabric density and triangle area */
    int num_triangles;
    int32_t *triangles; /* [num_triangles][3] */
    int grid_w, grid_h;
    int num_attachments;
    sim_attachment *attachments;
} sim_garment;

/* The drape sheet: side_m square, n_vertices (rounded to a square grid), flat at height y_m,
 * centred on x = z = 0. */
int sim_garment_drape(int n_vertices, float side_m, float y_m, sim_garment *out);
/* A shirt around a body mesh: the torso and upper arms offset outward by offset_m (0 = 0.015),
 * resting on the shoulders, resampled to about n_vertices. joints_xyz: FIT_JOINT_COUNT * 3 (the
 * bodyfit joints, used to choose the region); NULL = the region is guessed from the bounding
 * box. hem_m: with joints, the hem's depth below the pelvis joint (0 = 0.12 m: at the hips, above
 * the crotch; 0.25 m reaches over the tops of the thighs, a tunic whose straight hem the thighs
 * stretch when they part in a stride: docs/sim.md, "The hem and the error"). */
int sim_garment_shirt(const float *body_xyz, int nv, const int32_t *body_tris, int nt,
                      const float *joints_xyz, int n_vertices, float offset_m, float hem_m,
                      sim_garment *out, sim_reject *why);
void sim_garment_free(sim_garment *g); /* frees the arrays; the struct itself is the caller's */
/* The garment's attachments moved from one body mesh to another of the same person in the same
 * pose (another resolution of the body model): each glued to the new body's triangle nearest its
 * old foot point, so that it reproduces the vertex exactly as before. Refuses a body or garment
 * that does not validate; changes nothing then. */
int sim_garment_rebind(sim_garment *g, const float *from_xyz, int from_nv, const int32_t *from_tris,
                       int from_nt, const float *to_xyz, int to_nv, const int32_t *to_tris,
                       int to_nt, sim_reject *why);
/* The largest garment any reader or check accepts (vertices; twice as many triangles). */
#define GARMENT_MAX_VERTICES 1000000
/* Checks sizes, finiteness, indices, degenerate triangles, masses and attachments. */
int sim_garment_validate(const sim_garment *g, int body_nt, sim_reject *why);
/* Body check used by sim_step: finite, indices in range, no repeated vertex in a triangle. */
int sim_body_validate(const float *xyz, int nv, const int32_t *tris, int nt, sim_reject *why);
/* Wavefront OBJ ('v', 'f' lines; grid size from a "# grid W H" comment). */
int sim_garment_load_obj(const char *path, sim_garment *out, sim_reject *why);
int sim_garment_save_obj(const sim_garment *g, const char *path);

typedef struct sim sim;
/* Copies the garment. Returns NULL with why filled when it is rejected. */
sim *sim_create(const sim_desc *desc, const sim_garment *garment, sim_reject *why);
void sim_destroy(sim *s);
/* A garment made again on the body another sim (being replaced) has: s takes from's body
 * collision state (the body's tree and adjacency, built once per body topology) instead of
 * building its own on its first frame; from keeps s's empty one. A body of another topology
 * (tryon-sim's rehearsal on a stand-in body) is then built in the arrays taken. Both on the C
 * backend with the same body limits and contact settings, else nothing is taken. 0, or -1
 * (nothing changed). */
int sim_take_body(sim *s, sim *from);

/* The garment as made, for the body it was made on, before any sim_step: the body's collision
 * state is built (a first sim_step's dearest part: its tree and adjacency, 20-30 ms for a
 * 6,000-vertex body) and the cloth is measured as it stands, as sim_step measures what it
 * publishes (stats' strain and penetration; state OK), with no step. The next sim_step sweeps
 * from this body. A live stage publishes a new garment at once this way (tryon-sim): the cloth
 * of its first body costs the making, not a frame besides. 0, or a negative sim_error (a
 * refused body changes nothing; after a step: SIM_ERR_ARG). */
int sim_start(sim *s, const float *body_xyz, int nv, const int32_t *body_tris, int nt,
              sim_frame_stats *stats, sim_reject *why);

/* One body frame (same topology every frame; a change restarts the sweep). Returns 0 or a
 * negative sim_error; the published positions are never NaN: on failure they stay those of the
 * last good frame. */
int sim_step(sim *s, const float *body_xyz, int nv, const int32_t *body_tris, int nt,
             sim_frame_stats *stats, sim_reject *why);

int sim_vertex_count(const sim *s);
int sim_triangle_count(const sim *s);
const float *sim_positions(const sim *s);          /* [vertex][4]: xyz, w = inverse mass */
void sim_copy_positions(const sim *s, float *xyz); /* [vertex][3] */
/* [vertex][3]: m/s, the last step's move of the last frame published over its step */
void sim_copy_velocities(const sim *s, float *vel);
const int32_t *sim_triangles(const sim *s); /* [triangle][3] */
const char *sim_device_name(const sim *s);  /* "C reference (2 threads)", the OpenCL device */
/* The device the OpenCL backend would open (TRYON_CL_DEVICE's, else the first GPU, else the first
   device of any kind), without opening it: 1 a GPU, 0 another kind (PoCL's CPU device), -1 none
   (no platform, a TRYON_CL_DEVICE that names nothing, a build without OpenCL). name: the device's
   name, or why there is none. For choosing a backend: on 2 CPU cores the C backend is 4-5x faster
   than the OpenCL one on PoCL (docs/sim.md). */
int sim_opencl_device(char *name, size_t name_size);
/* Which backend runs this garment faster here, measured (--backend auto on a GPU): `frames`
 * frames (2..1000) of the garment on the still body on each backend, the first not timed (the
 * OpenCL program's build and upload); ms[0] the C backend's median frame, ms[1] OpenCL's (-1: it
 * did not run the garment); *out the faster. Returns 0, or -SIM_ERR_BACKEND when neither ran it. */
int sim_backend_race(const sim_desc *desc, const sim_garment *g, const float *body_xyz, int nv,
                     const int32_t *body_tris, int nt, int frames, sim_backend *out, double ms[2]);
const sim_desc *sim_get_desc(const sim *s);

/* Replace the cloth state (xyz: [vertex][3], at rest: previous = current), e.g. to restart a
 * garment or start from a scrambled state; the rest shape stays the garment's. */
int sim_set_positions(sim *s, const float *xyz, sim_reject *why);
/* The same with velocities (vel: [vertex][3], m/s; NULL = at rest), e.g. another sim's state
 * (sim_copy_positions, sim_copy_velocities) to go on from with other steps. Attached vertices
 * keep their places in both. */
int sim_set_state(sim *s, const float *xyz, const float *vel, sim_reject *why);

/* What a CONTROL request asks the sim to wear (sim/outfit.c, docs/mirror.md): a generated
 * garment by name ("shirt": hem at the hips; "tunic": hem over the thighs) or a garment file
 * (a name ending in ".obj") or a sewing pattern (".json", dressed on the body model); a size S/M/L
 * (the shirt's ease over the body; a file garment scaled around its vertical axis); a fabric preset
 * by name ("" = cotton). */
typedef enum sim_size { SIM_SIZE_S = 0, SIM_SIZE_M = 1, SIM_SIZE_L = 2 } sim_size;
typedef struct sim_outfit {
    char garment[256]; /* as requested */
    int is_file;
    int is_pattern; /* a sewing pattern (".json"): sim_outfit_make_pattern (outfit_pattern.h) */
    sim_size size;
    float offset_m; /* generated garments: ease over the body */
    float hem_m;    /* generated garments: hem below the pelvis joint */
    float scale;    /* file garments: horizontal scale */
    char fabric_name[32];
    sim_fabric fabric;
    char id[96]; /* for CLOTH's garment_id: "shirt M cotton" */
} sim_outfit;
const char *sim_size_name(sim_size s); /* "S", "M", "L" */
/* Resolves a request; refuses (-SIM_ERR_PARAM, why names the field) an unknown garment name,
 * size or fabric. A file is not opened here: sim_outfit_make reads it. */
int sim_outfit_resolve(const char *garment, int size, const char *fabric, sim_outfit *out,
                       sim_reject *why);
/* The outfit's garment made around this body (sim_garment_shirt's arguments). */
int sim_outfit_make(const sim_outfit *o, const float *body_xyz, int nv, const int32_t *body_tris,
                    int nt, const float *joints_xyz, int n_vertices, sim_garment *out,
                    sim_reject *why);
int sim_outfit_same(const sim_outfit *a, const sim_outfit *b); /* 1 = same garment, size, fabric */

/* Test hook: overwrite one vertex (to inject NaN or a far jump). */
void sim_debug_set_vertex(sim *s, int i, float x, float y, float z);

#endif
