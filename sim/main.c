/* tryon-sim: BODY in, CLOTH and TIMING out. The garment is loaded (--garment FILE) or generated
 * around the first body received; every body frame is one sim_step. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "body_intake.h"
#include "budget.h"
#include "bodyfit.h"
#include "bus.h"
#include "garments.h"
#include "outfit_pattern.h"
#include "queue.h"
#include "rehearse.h"
#include "sim.h"
#include "tryon_clock.h"
#include "tryon_heap.h"

/* The garment's triangles go with every 10th CLOTH (and a new garment's first): a mirror that
   starts, or starts again, draws it within a third of a second at 30 fps, for 170 kB more a
   tenth of the frames at 7,000 vertices */
#define SIM_MAIN_TRIANGLES_EVERY 10
#define SIM_MAIN_JOINTS          21 /* bodyfit's FIT_JOINT_COUNT */
#define SIM_MAIN_SHAPE           FIT_SHAPE_PARAMS
#define SIM_MAIN_POSE            FIT_POSE_PARAMS
/* Shape parameters (metres) within this of those the garment was made on are the same shape: a
 * third of the shirt's ease (15 mm at size M), for a garment made on a shape still estimated (a
 * person's first frames: the walk's shirt kept from its first body stretched to 6.6 %) */
#define SIM_MAIN_SHAPE_SAME_M 0.005f
/* ... and within this for a garment made on a settled shape: a girth 15 mm larger is 2.4 mm more
 * radius, a sixth of the 15 mm the shirt stands off the skin, a length 15 mm longer moves an
 * armhole or a hem by less. The fitter refines a settled shape by 5-6 mm after a doubt: at 5 mm
 * the garment was made again then, on whatever pose the body had (the fitted 01_01's arms lying
 * in the trunk), and the sim carried 36 of its 149 bodies against 15 (docs/pipeline.md, "Live") */
#define SIM_MAIN_SHAPE_SETTLED_M 0.015f
/* A garment that diverges this many bodies in a row (1 s at 30 fps) is made again on the next
 * body: one made on a body that cannot carry it never recovers. */
#define SIM_MAIN_DIVERGED_REBUILD 30
/* --frame-budget's default, ms (sim_desc.frame_budget_ms): the camera's period is 33 ms, and a
 * body the sim is still busy with when the next arrives makes that one wait (and a third one
 * supersede it); the body stage takes about 25 ms of the 50 ms from capture to cloth at p95
 * (docs/mirror.md, "Figures"): the rest, 25 ms, less the publishing. */
#define SIM_MAIN_FRAME_BUDGET_MS 20.0f
/* --deadline's default, ms from capture (--frame-budget auto): the goal is capture -> cloth
 * <= 50 ms at p95; 5 ms of it are left for a frame whose fixed part (no settle round) overruns
 * and for the wait for a core. */
#define SIM_MAIN_DEADLINE_MS 45.0f
/* --queue's default: one frame may overrun the camera's period by up to a period with no body
 * superseded (bus_queue); a longer overrun still supersedes, so latency stays bounded. */
#define SIM_MAIN_QUEUE 2
/* A body stamped this soon after the last frame was published was queued while the sim worked:
 * its arrival time is not known (sim_pace_body). */
#define SIM_MAIN_QUEUED_US 1000

static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

/* A body received and not simulated yet. */
typedef struct pending_body {
    int32_t seq, topology_id;
    int8_t state; /* BODY's tracking state: the fitter's shape is final once TRACKING */
    int64_t utime_capture, received;
    int nv, cap;
    float *xyz; /* [nv][3] */
    int has_joints;
    float joints[SIM_MAIN_JOINTS * 3];
    int num_shape, num_pose; /* the body model's parameters, for dressing a pattern */
    float shape[SIM_MAIN_SHAPE], pose[SIM_MAIN_POSE];
} pending_body;

typedef struct app {
    lcm_t *lcm;
    sim_desc desc;
    const char *garment_path, *fabric;
    int size; /* --size: S, M, L = 0, 1, 2 */
    int verts, frames_wanted, frames_done, skipped, triangles_every;
    float hem_m;    /* the generated shirt's hem below the pelvis joint (0: sim_garment_shirt's) */
    int every_body; /* --queue all: simulate every body; else the newest `queue.depth` */
    int backend_auto;    /* --backend auto (the default), until decided (auto_backend) */
    int bodies_received; /* simulated, superseded or skipped */
    int superseded;      /* waiting when the queue was full and a newer one came: not simulated */
    int settling;        /* published cut short by the frame budget (SIM_STATE_SETTLING) */
    int inside_frames;   /* published with a vertex > 1 mm inside the body */
    float deepest_mm, worst_strain; /* over every cloth published */
    int strain_frames;              /* published over 3 % max or 1 % p99 strain */
    pending_body waiting[BUS_QUEUE_MAX];
    bus_queue queue; /* which of `waiting` wait, oldest first */
    sim *sim;
    sim *replaced; /* the garment dropped (drop_sim), until the next is made: its body state */
    char garment_id[64];
    sim_topologies topo;  /* body triangle lists per topology id (bounded, live one pinned) */
    uint32_t garment_gen; /* the list (sim_topology.gen) the garment was made on */
    int refused;          /* bodies refused: unknown topology, too large, or no garment on them */
    int diverged_run;     /* bodies in a row on which the garment diverged */
    int made_on_init;     /* the garment was made on, or has since met, an INIT body: a shape
                             still estimated (a person entering, or entering again) */
    int fresh;            /* the garment was made on the body now stepped: sim_start, no step */
    int rehearse;         /* --rehearse on: the first garment made once before listening */
    int made_num_shape;   /* the shape the garment was made on (0: the body carried none) */
    int made_settled;     /* ... on a TRACKING body: a settled shape */
    float made_shape[SIM_MAIN_SHAPE];
    int fatal;  /* an error no body can fix (the garment file): exit 1 */
    float *xyz; /* cloth vertices for the message */
    char channel_cloth[BUS_CHANNEL_MAX];
    sim_outfit outfit, wanted, before; /* worn, asked for over CONTROL (sim/outfit.c), last */
    int want_switch, controls_refused;
    int32_t topology;  /* CLOTH's topology_id: a new one for every garment made */
    int tris_due;      /* the garment is new: its triangles go with the next CLOTH */
    FILE *stats;       /* --stats FILE: a CSV line of sim_frame_stats per simulated body */
    int budget_auto;   /* --frame-budget auto: each body's budget from the pace (budget.c) */
    float deadline_ms; /* --deadline: capture -> cloth, for --frame-budget auto (0: none) */
    sim_pace pace;
    int64_t published_us;  /* wall clock: the last frame's CLOTH and TIMING went out */
    int over_budget;       /* frames whose sim_step took longer than their budget */
    float settle_floor_mm; /* --settle-floor: a body that moved less gets no settle round */
    int settle_skipped;    /* bodies that did */
    float *moved_xyz;      /* --stats, --settle-floor: the last simulated body, for its motion */
    float *moved_scratch;
    int moved_nv;
} app;

/* --backend auto: where the device OpenCL would open is a GPU, the faster backend on the first
   garment, measured (sim_backend_race: 6 frames on the first body, about 0.1 s) and kept for the
   session; where TRYON_CL_DEVICE names a device, OpenCL; otherwise C: on a machine without a GPU
   the OpenCL device is a CPU (PoCL), where the C backend is 4-5x faster on the same cores
   (docs/sim.md, the headline). */
static void auto_backend(app *a, const sim_garment *g, const pending_body *b,
                         const sim_topology *topo)
{
    char name[256];
    int gpu = sim_opencl_device(name, sizeof name);
    const char *want = getenv("TRYON_CL_DEVICE");
    a->desc.backend = SIM_BACKEND_C;
    if (want && *want && gpu >= 0) {
        a->desc.backend = SIM_BACKEND_OPENCL;
        return;
    }
    double ms[2];
    sim_backend pick;
    if (gpu == 1 &&
        sim_backend_race(&a->desc, g, b->xyz, b->nv, topo->tris, topo->nt, 6, &pick, ms) == 0) {
        a->desc.backend = pick;
        a->backend_auto = 0; /* measured once: the session keeps it */
        fprintf(stderr,
                "tryon-sim: --backend auto: %.1f ms a frame on C, %.1f on OpenCL (%s): the %s "
                "backend\n",
                ms[0], ms[1], name, pick == SIM_BACKEND_C ? "C" : "OpenCL");
    } else if (gpu == 0)
        fprintf(stderr,
                "tryon-sim: the OpenCL device, %s, is not a GPU: the C backend, faster there "
                "(--backend opencl to use it anyway)\n",
                name);
    else if (gpu < 0)
        fprintf(stderr, "tryon-sim: no OpenCL device (%s): the C backend\n", name);
}

/* Makes the garment on body b. Returns 0, or -1: the body cannot carry it (refused, the next
 * body is tried) or a->fatal is set (the garment file is bad: no body helps). */
static int make_sim(app *a, const pending_body *b, const sim_topology *topo)
{
    int64_t t0 = bus_now_mono_us();
    sim_garment g = {0};
    sim_reject why = {0};
    sim_pattern_stats ps = {0};
    int r =
        a->outfit.is_pattern
            ? sim_outfit_make_pattern(&a->outfit, b->shape, b->num_shape, b->pose, b->num_pose,
                                      b->xyz, b->nv, topo->tris, topo->nt, a->verts, &g, &ps, &why)
            : sim_outfit_make(&a->outfit, b->xyz, b->nv, topo->tris, topo->nt,
                              b->has_joints ? b->joints : NULL, a->verts, &g, &why);
    a->fatal = r < 0 && a->outfit.is_file && (!a->outfit.is_pattern || r == -SIM_ERR_FILE);
    if (r == 0 && a->outfit.is_pattern)
        fprintf(stderr,
                "tryon-sim: pattern %s dressed on body %d's model in %.0f ms (%.0f ms in all), "
                "seams %.1f mm, %d vertices inside\n",
                a->outfit.id, b->seq, ps.dress_ms, ps.total_ms, ps.seam_gap_mm, ps.penetrating);
    if (r < 0) {
        fprintf(stderr, "tryon-sim: garment %s on body %d: %s: %s%s\n", a->outfit.garment, b->seq,
                sim_error_name(why.code), why.detail,
                a->fatal ? "" : "; body refused, waiting for one that can carry the garment");
        return -1;
    }
    a->desc.fabric = a->outfit.fabric;
    /* a pattern keeps the dressing's contact thickness (outfit_pattern.h) */
    a->desc.thickness_m =
        a->outfit.is_pattern ? sim_pattern_thickness_m() : sim_default_desc().thickness_m;
    if (a->backend_auto)
        auto_backend(a, &g, b, topo);
    a->sim = sim_create(&a->desc, &g, &why);
    if (!a->sim && why.code == SIM_ERR_BACKEND && a->desc.backend == SIM_BACKEND_OPENCL) {
        fprintf(stderr, "tryon-sim: %s; falling back to the C backend\n", why.detail);
        a->desc.backend = SIM_BACKEND_C;
        a->sim = sim_create(&a->desc, &g, &why);
    }
    snprintf(a->garment_id, sizeof a->garment_id, "%s", g.id);
    sim_garment_free(&g);
    if (!a->sim) {
        fprintf(stderr, "tryon-sim: body %d: %s: %s; body refused\n", b->seq,
                sim_error_name(why.code), why.detail);
        return -1;
    }
    if (a->replaced) { /* the body's tree and adjacency, not built again */
        sim_take_body(a->sim, a->replaced);
        sim_destroy(a->replaced);
        a->replaced = NULL;
    }
    if (a->outfit.is_pattern &&
        sim_pattern_settle(a->sim, b->xyz, b->nv, topo->tris, topo->nt, &why) < 0) {
        fprintf(stderr, "tryon-sim: body %d: settling the pattern: %s; body refused\n", b->seq,
                why.detail);
        sim_destroy(a->sim);
        a->sim = NULL;
        return -1;
    }
    free(a->xyz);
    a->xyz = malloc((size_t)sim_vertex_count(a->sim) * 3 * sizeof *a->xyz);
    if (!a->xyz) {
        sim_destroy(a->sim);
        a->sim = NULL;
        return -1;
    }
    a->garment_gen = topo->gen;
    a->fresh = !a->outfit.is_pattern; /* a pattern's settling has stepped it on this body */
    a->diverged_run = 0;
    a->made_on_init = b->state == TRYON_BODY_T_STATE_INIT;
    a->made_num_shape = b->num_shape;
    a->made_settled = b->state == TRYON_BODY_T_STATE_TRACKING;
    memcpy(a->made_shape, b->shape, sizeof a->made_shape);
    a->topology++;
    a->tris_due = 1;
    fprintf(stderr, "tryon-sim: garment %s, %d vertices, %s solver on %s, made in %.0f ms\n",
            a->garment_id, sim_vertex_count(a->sim),
            a->desc.solver == SIM_SOLVER_SEED ? "seed" : "tryon", sim_device_name(a->sim),
            (double)(bus_now_mono_us() - t0) / 1e3);
    return 0;
}

/* The garment is dropped, to be made again on the next body; the sim is kept until then, so that
 * the new one takes its body collision state (sim_take_body) instead of building it again. */
static void drop_sim(app *a)
{
    if (a->sim) {
        sim_destroy(a->replaced);
        a->replaced = a->sim;
    }
    a->sim = NULL;
    a->diverged_run = 0;
}

/* CLOTH's state is the frame's sim_state, value for value (bus/cloth_t.lcm) */
_Static_assert(SIM_STATE_OK == TRYON_CLOTH_T_STATE_OK &&
                   SIM_STATE_RECOVERED == TRYON_CLOTH_T_STATE_RECOVERED &&
                   SIM_STATE_DIVERGED == TRYON_CLOTH_T_STATE_DIVERGED &&
                   SIM_STATE_SETTLING == TRYON_CLOTH_T_STATE_SETTLING &&
                   SIM_STATE_CARRIED == TRYON_CLOTH_T_STATE_CARRIED,
               "sim_state and cloth_t's states differ");

static void publish(app *a, const pending_body *b, const sim_frame_stats *st, bus_timing *t)
{
    sim_copy_positions(a->sim, a->xyz);
    int nv = sim_vertex_count(a->sim), nt = sim_triangle_count(a->sim);
    int with_tris = a->tris_due || a->frames_done % a->triangles_every == 0;
    a->tris_due = 0;
    tryon_cloth_t msg = {
        .utime_capture = b->utime_capture,
        .seq = b->seq,
        .garment_id = a->garment_id,
        .state = (int8_t)st->state,
        .max_strain = st->max_strain,
        .p99_strain = st->p99_strain,
        .penetrating = st->penetrating,
        .max_pen_mm = st->max_pen_mm,
        .topology_id = a->topology,
        .num_vertex_coords = nv * 3,
        .vertices = a->xyz,
        .num_triangle_indices = with_tris ? nt * 3 : 0,
        .triangles = with_tris ? (int32_t *)sim_triangles(a->sim) : NULL,
    };
    bus_reject why;
    if (bus_publish(a->lcm, a->channel_cloth, BUS_CLOTH, &msg, &why) != BUS_OK)
        fprintf(stderr, "tryon-sim: frame %d: CLOTH not sent: %s (%s)\n", b->seq,
                bus_error_text(why.code), why.detail);
    bus_timing_add(t, "bvh", st->ms_bvh);
    bus_timing_add(t, "feature_points", st->ms_feature_points);
    bus_timing_add(t, "contacts", st->ms_contacts);
    bus_timing_add(t, "iterations", st->ms_iterations);
    bus_timing_add(t, "metrics", st->ms_metrics);
    bus_timing_publish(a->lcm, t);
}

/* A body arrives: its triangles are kept at once (a superseded body may carry them), its
 * vertices wait in a.waiting for the main loop, replacing the oldest one waiting when the queue
 * is full. */
static void on_body(const char *channel, const void *m, void *user)
{
    (void)channel;
    app *a = user;
    const tryon_body_t *b = m;
    int64_t received = bus_now_wall_us();
    a->bodies_received++;
    int supersedes;
    pending_body *p = &a->waiting[bus_queue_slot(&a->queue, &supersedes)];
    int nv = b->num_vertex_coords / 3;
    if (nv == 0) { /* no person (bodyfit lost them): the last cloth stands */
        if (a->skipped++ < 5)
            fprintf(stderr, "tryon-sim: body %d has no vertices (state %d); frame skipped\n",
                    b->seq, b->state);
        return;
    }
    /* Checked before anything is kept: a body the sim cannot take never replaces a waiting one
     * nor the triangles the garment lives on. */
    const sim_topology *topo;
    sim_reject why = {0};
    int r = sim_topologies_intake(&a->topo, b->topology_id, nv, b->triangles,
                                  b->num_triangle_indices / 3, bus_now_mono_us(), &topo, &why);
    if (r < 0) {
        if (a->refused++ < 5 || a->refused % 100 == 0)
            fprintf(stderr, "tryon-sim: body %d refused (%d so far): %s: %s\n", b->seq, a->refused,
                    sim_error_name(r), why.detail);
        return;
    }
    if (nv > p->cap) {
        float *x = realloc(p->xyz, (size_t)nv * 3 * sizeof *x);
        if (!x) {
            fprintf(stderr, "tryon-sim: body %d: out of memory for %d vertices; skipped\n", b->seq,
                    nv);
            a->skipped++;
            return;
        }
        p->xyz = x;
        p->cap = nv;
    }
    a->superseded += supersedes;
    memcpy(p->xyz, b->vertices, (size_t)nv * 3 * sizeof *p->xyz);
    p->nv = nv;
    p->seq = b->seq;
    p->topology_id = b->topology_id;
    p->state = b->state;
    p->utime_capture = b->utime_capture;
    p->received = received;
    p->has_joints = b->num_joint_coords == SIM_MAIN_JOINTS * 3;
    if (p->has_joints)
        memcpy(p->joints, b->joints, sizeof p->joints);
    p->num_shape = b->num_shape == SIM_MAIN_SHAPE ? b->num_shape : 0;
    p->num_pose = b->num_pose == SIM_MAIN_POSE ? b->num_pose : 0;
    if (p->num_shape) /* LCM decodes an empty array as NULL */
        memcpy(p->shape, b->shape, sizeof p->shape);
    if (p->num_pose)
        memcpy(p->pose, b->pose, sizeof p->pose);
    bus_queue_commit(&a->queue);
    sim_pace_body(&a->pace, b->seq, b->utime_capture, received,
                  received - a->published_us > SIM_MAIN_QUEUED_US);
}

/* CONTROL: the garment to wear next. It is made on the next body; the pipeline never stops. */
static void on_control(const char *channel, const void *m, void *user)
{
    (void)channel;
    app *a = user;
    const tryon_control_t *c = m;
    sim_outfit o;
    sim_reject why = {0};
    if (sim_outfit_resolve(c->garment, c->size, c->fabric, &o, &why) < 0) {
        a->controls_refused++;
        fprintf(stderr, "tryon-sim: CONTROL %d refused: %s; still wearing %s\n", c->seq, why.detail,
                a->outfit.id);
        return;
    }
    if (a->outfit.hem_m != o.hem_m && !o.is_file && !strcmp(o.garment, a->outfit.garment))
        o.hem_m = a->outfit.hem_m; /* --hem stays with its garment */
    if (sim_outfit_same(&o, &a->outfit))
        return;
    a->wanted = o;
    a->want_switch = 1;
}

/* The requested garment replaces the worn one: made around the next body, as at the start. */
static void switch_garment(app *a)
{
    fprintf(stderr, "tryon-sim: CONTROL: %s replaces %s\n", a->wanted.id, a->outfit.id);
    a->before = a->outfit;
    a->outfit = a->wanted;
    a->want_switch = 0;
    drop_sim(a);
}

/* A requested garment file that cannot be read: the one worn before stays. */
static int fall_back(app *a, const pending_body *b, const sim_topology *topo)
{
    if (!a->fatal || a->frames_done == 0 || sim_outfit_same(&a->outfit, &a->before))
        return -1;
    a->controls_refused++;
    fprintf(stderr, "tryon-sim: %s cannot be made; back to %s\n", a->outfit.id, a->before.id);
    a->outfit = a->before;
    a->fatal = 0;
    return make_sim(a, b, topo);
}

/* Back to TRACKING after INIT bodies: whether the shape moved since the garment was made. The
 * fitter holds the shape while it doubts a fit (published INIT), so a doubt leaves it where it
 * was and the garment goes on; a person entering has their shape estimated over their first
 * frames, and the garment made on the first of them is made again. A body that carries no shape
 * (or did not when the garment was made) says nothing: made again. */
static int shape_moved(const app *a, const pending_body *b)
{
    if (!b->num_shape || b->num_shape != a->made_num_shape)
        return 1;
    float same = a->made_settled ? SIM_MAIN_SHAPE_SETTLED_M : SIM_MAIN_SHAPE_SAME_M;
    for (int k = 0; k < b->num_shape; k++)
        if (!(fabsf(b->shape[k] - a->made_shape[k]) <= same))
            return 1;
    return 0;
}

/* --stats: the median vertex's motion since the last simulated body, mm; -1 for the first body
 * and after the vertex count changed (or without memory). */
static float body_moved(app *a, const pending_body *b)
{
    float mm = -1.0f;
    if (a->moved_xyz && a->moved_nv == b->nv)
        mm = sim_body_motion_mm(a->moved_xyz, b->xyz, b->nv, a->moved_scratch);
    if (a->moved_nv != b->nv) {
        free(a->moved_xyz);
        free(a->moved_scratch);
        a->moved_xyz = malloc((size_t)b->nv * 3 * sizeof *a->moved_xyz);
        a->moved_scratch = malloc((size_t)b->nv * sizeof *a->moved_scratch);
        a->moved_nv = a->moved_xyz && a->moved_scratch ? b->nv : 0;
    }
    if (a->moved_nv)
        memcpy(a->moved_xyz, b->xyz, (size_t)b->nv * 3 * sizeof *a->moved_xyz);
    return mm;
}

static void step_body(app *a, pending_body *b)
{
    bus_timing t; /* work starts now: the garment is made on the first body */
    bus_timing_begin(&t, "sim", b->seq, b->utime_capture, b->received);
    const sim_topology *topo;
    sim_reject why = {0};
    int64_t now = bus_now_mono_us();
    /* Looked up again by id: the list may have been replaced since the body arrived. */
    if (sim_topologies_intake(&a->topo, b->topology_id, 0, NULL, 0, now, &topo, &why) < 0) {
        fprintf(stderr, "tryon-sim: body %d: %s; frame skipped\n", b->seq, why.detail);
        a->skipped++;
        return;
    }
    if (a->sim && topo->gen != a->garment_gen) {
        fprintf(stderr,
                "tryon-sim: body %d: topology %d is not the garment's body; the garment is "
                "made again\n",
                b->seq, b->topology_id);
        drop_sim(a);
    }
    if (b->state == TRYON_BODY_T_STATE_INIT)
        a->made_on_init = 1;
    if (a->sim && a->made_on_init && b->state == TRYON_BODY_T_STATE_TRACKING) {
        a->made_on_init = 0;
        if (shape_moved(a, b)) {
            fprintf(stderr,
                    "tryon-sim: body %d: the fitter's shape is settled (init -> tracking); the "
                    "garment is made again on it\n",
                    b->seq);
            drop_sim(a);
        }
    }
    if (!a->sim && make_sim(a, b, topo) < 0 && fall_back(a, b, topo) < 0) {
        a->refused++;
        if (a->fatal)
            stop_requested = 1;
        return;
    }
    float budget = a->desc.frame_budget_ms;
    if (a->budget_auto)
        budget = sim_pace_budget_ms(&a->pace, b->utime_capture, bus_now_wall_us(), a->deadline_ms,
                                    SIM_MAIN_FRAME_BUDGET_MS);
    float moved = a->stats || a->settle_floor_mm > 0.0f ? body_moved(a, b) : -1.0f;
    int still = moved >= 0.0f && moved < a->settle_floor_mm;
    if (still) { /* the fitter's noise: nothing to settle */
        budget = SIM_PACE_MIN_MS;
        a->settle_skipped++;
    }
    sim_set_frame_budget(a->sim, budget);
    sim_frame_stats st;
    int64_t cpu0 = bus_now_cpu_us(); /* every OpenMP thread's */
    /* a garment made on this very body is published as made: its first frame costs the
       making, not a step besides (sim_start) */
    int r = a->fresh ? sim_start(a->sim, b->xyz, b->nv, topo->tris, topo->nt, &st, &why)
                     : sim_step(a->sim, b->xyz, b->nv, topo->tris, topo->nt, &st, &why);
    a->fresh = 0;
    float cpu_ms = (float)(bus_now_cpu_us() - cpu0) / 1000.0f;
    if (r < 0 && r != -SIM_ERR_DIVERGED) {
        fprintf(stderr, "tryon-sim: body %d rejected: %s: %s; frame skipped\n", b->seq,
                sim_error_name(r), why.detail);
        a->skipped++;
        return;
    }
    a->diverged_run = r == -SIM_ERR_DIVERGED ? a->diverged_run + 1 : 0;
    a->settling += st.state == SIM_STATE_SETTLING;
    a->inside_frames += st.penetrating > 0;
    a->deepest_mm = fmaxf(a->deepest_mm, st.max_pen_mm);
    a->worst_strain = fmaxf(a->worst_strain, st.max_strain);
    a->strain_frames += !(st.max_strain <= a->desc.retry_max_strain) || /* the strain goals */
                        !(st.p99_strain <= a->desc.retry_p99_strain);
    if (r == 0)
        sim_topologies_mark_live(&a->topo, b->topology_id, now);
    if (r == -SIM_ERR_DIVERGED)
        fprintf(stderr, "tryon-sim: body %d: %s; publishing the last good cloth\n", b->seq,
                why.detail);
    a->over_budget += budget > 0.0f && st.ms_total > budget && !still;
    bus_timing_add(&t, "cpu", cpu_ms);
    bus_timing_add(&t, "budget", budget);
    int64_t t_pub = bus_now_mono_us();
    publish(a, b, &st, &t);
    a->published_us = bus_now_wall_us();
    sim_pace_published(&a->pace, (float)(bus_now_mono_us() - t_pub) / 1000.0f);
    if (a->stats)
        fprintf(a->stats, "%d,%d,%d,%d,%d,%d,%d,%.4f,%.2f,%.2f,%.2f,%.2f,%.3f,%.2f\n", b->seq,
                st.state, st.settle_rounds, st.retries, st.strain_retries, st.iterations_used,
                st.feature_points_moved, st.max_strain, st.max_pen_mm, st.ms_iterations,
                st.ms_total, cpu_ms, budget, moved);
    a->frames_done++;
    if (a->diverged_run >= SIM_MAIN_DIVERGED_REBUILD) {
        fprintf(stderr,
                "tryon-sim: the garment diverged on %d bodies in a row; made again on the "
                "next body\n",
                a->diverged_run);
        drop_sim(a);
    }
}

static int usage(FILE *f, int rc)
{
    fprintf(f,
            "usage: tryon-sim [--backend auto|opencl|c] [--solver tryon|seed] [--garment FILE]\n"
            "                 [--size S|M|L]\n"
            "                 [--verts N] [--iterations K] [--frames N] [--queue N|latest|all]\n"
            "                 [--follow F] [--retry-budget MS] [--hem M] [--fabric NAME]\n"
            "                 [--frame-budget auto|MS] [--deadline MS] [--settle-floor MM]\n"
            "                 [--stats FILE] [--rehearse on|off]\n"
            "  --stats FILE: a CSV line per simulated body (body, state, settle rounds, retries,\n"
            "          strain retries, iterations, feature points moved, max strain, max\n"
            "          penetration mm, iterations ms, total ms, CPU ms (all threads), budget ms,\n"
            "          the body's median vertex motion since the last simulated body, mm)\n"
            "  --rehearse on|off: before listening, the garment made, started and stepped once\n"
            "          on a stand-in body, its memory kept for the first person (default on)\n"
            "  --backend auto (default): where the OpenCL device is a GPU, the faster of C and\n"
            "          OpenCL on the first garment, measured; OpenCL where TRYON_CL_DEVICE names\n"
            "          a device; else C. opencl falls back to C when no device opens\n"
            "  --queue N (1-4, default 2): at most N bodies wait while a frame is simulated;\n"
            "          one arriving at a full queue supersedes the oldest waiting (counted), so\n"
            "          latency stays bounded; 2 lets one frame overrun with no body lost.\n"
            "          latest: 1 (only the newest waits); all: every body, in order (replays)\n"
            "  --retry-budget MS: a frame missing the strain goals is done again with more\n"
            "          iterations only while the frame fits in MS (0, default: always)\n"
            "  --frame-budget auto|MS: each body's time (0: none): settle rounds and strain\n"
            "          retries stop when it is spent, the cloth is published as it stands (state\n"
            "          settling, its strain measured). auto (default): until the next body's\n"
            "          arrival (learnt from the bodies' capture times and arrivals) or --deadline\n"
            "          after capture, whichever is first (20 ms until the pace is known, and\n"
            "          for a body captured over 1 s ago: a log played again)\n"
            "  --deadline MS: capture -> cloth published, for --frame-budget auto (default 45;\n"
            "          0: only the next body's arrival)\n"
            "  --settle-floor MM: a body whose median vertex moved less than MM since the last\n"
            "          simulated one gets no settle round nor strain retry (0, default: off)\n"
            "  --frames N: exit after N bodies received (simulated, superseded or skipped)\n"
            "  --hem M: the generated shirt's hem M metres below the pelvis joint (0, default:\n"
            "          0.12, at the hips; 0.25: a tunic over the tops of the thighs)\n"
            "  --garment FILE.json: a sewing pattern (garments/patterns), dressed on the body\n"
            "          model of the first body's shape and pose; needs BODY's shape and pose;\n"
            "          meshed to about --verts vertices\n"
            "  --size S|M|L: the garment's size (default M)\n"
            "  CONTROL messages switch the garment (shirt, tunic, FILE.obj, FILE.json), size and\n"
            "          fabric\n"
            "          on the next body (docs/mirror.md)\n"
            "  --follow F: the fraction (0..1, default 1) of the rigid motion of the body at\n"
            "          the garment's waist given to all of it each frame; < 0: world frame\n");
    return rc;
}

/* A value 0 .. 1000 (a body frame's budget in ms, a motion in mm): 0, or -1 for anything else. */
static int parse_ms(const char *v, float *ms)
{
    char *end;
    double x = strtod(v, &end);
    if (end == v || *end != 0 || !(x >= 0.0 && x <= 1000.0))
        return -1;
    *ms = (float)x;
    return 0;
}

/* --queue N|latest|all */
static int parse_queue(const char *v, app *a)
{
    char *end;
    long n = strtol(v, &end, 10);
    if (!strcmp(v, "latest") || !strcmp(v, "all"))
        n = 1; /* all: one body handled at a time, none ever superseded */
    else if (end == v || *end || n < 1 || n > BUS_QUEUE_MAX)
        return -1;
    a->every_body = !strcmp(v, "all");
    bus_queue_init(&a->queue, (int)n);
    return 0;
}

static int parse(app *a, int argc, char **argv)
{
    a->desc = sim_default_desc();
    a->desc.frame_budget_ms = SIM_MAIN_FRAME_BUDGET_MS; /* live: on time (the bench: no budget) */
    a->budget_auto = 1;
    a->deadline_ms = SIM_MAIN_DEADLINE_MS;
    a->backend_auto = 1; /* the product runs on the GPU where there is one (auto_backend) */
    a->verts = 7000;
    a->rehearse = 1;
    a->size = SIM_SIZE_M;
    a->triangles_every = SIM_MAIN_TRIANGLES_EVERY;
    bus_queue_init(&a->queue, SIM_MAIN_QUEUE);
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(o, "--help") || !strcmp(o, "-h"))
            return 1;
        if (!v) {
            fprintf(stderr, "tryon-sim: %s needs a value\n", o);
            return -1;
        }
        if (!strcmp(o, "--backend") &&
            (!strcmp(v, "c") || !strcmp(v, "opencl") || !strcmp(v, "auto"))) {
            a->backend_auto = !strcmp(v, "auto");
            a->desc.backend = !strcmp(v, "c") ? SIM_BACKEND_C : SIM_BACKEND_OPENCL;
        } else if (!strcmp(o, "--solver") && (!strcmp(v, "seed") || !strcmp(v, "tryon")))
            a->desc.solver = !strcmp(v, "seed") ? SIM_SOLVER_SEED : SIM_SOLVER_TRYON;
        else if (!strcmp(o, "--garment"))
            a->garment_path = v;
        else if (!strcmp(o, "--size") && gar_size_from_name(v) >= 0)
            a->size = gar_size_from_name(v);
        else if (!strcmp(o, "--fabric"))
            a->fabric = v;
        else if (!strcmp(o, "--verts"))
            a->verts = atoi(v);
        else if (!strcmp(o, "--rehearse") && (!strcmp(v, "on") || !strcmp(v, "off")))
            a->rehearse = !strcmp(v, "on");
        else if (!strcmp(o, "--iterations"))
            a->desc.iterations = atoi(v);
        else if (!strcmp(o, "--hem") && atof(v) >= 0.0)
            a->hem_m = (float)atof(v);
        else if (!strcmp(o, "--follow") && atof(v) <= 1.0)
            a->desc.follow = (float)atof(v);
        else if (!strcmp(o, "--retry-budget") && atof(v) >= 0.0)
            a->desc.retry_budget_ms = (float)atof(v);
        else if (!strcmp(o, "--frame-budget") && !strcmp(v, "auto"))
            a->budget_auto = 1;
        else if (!strcmp(o, "--frame-budget") && parse_ms(v, &a->desc.frame_budget_ms) == 0)
            a->budget_auto = 0;
        else if (!strcmp(o, "--deadline") && parse_ms(v, &a->deadline_ms) == 0)
            ;
        else if (!strcmp(o, "--settle-floor") && parse_ms(v, &a->settle_floor_mm) == 0)
            ;
        else if (!strcmp(o, "--frames"))
            a->frames_wanted = atoi(v);
        else if (!strcmp(o, "--queue") && parse_queue(v, a) == 0)
            ;
        else if (!strcmp(o, "--stats") && !a->stats && (a->stats = fopen(v, "w")))
            fprintf(a->stats,
                    "body,state,settle_rounds,retries,strain_retries,iterations,"
                    "feature_points_moved,max_strain,max_pen_mm,ms_iterations,ms_total,cpu_ms,"
                    "budget_ms,body_move_mm\n");
        else {
            fprintf(stderr, "tryon-sim: unknown option or bad value: %s %s\n", o, v);
            return -1;
        }
        i++;
    }
    sim_reject why;
    if (sim_outfit_resolve(a->garment_path ? a->garment_path : "shirt", a->size,
                           a->fabric ? a->fabric : "", &a->outfit, &why) < 0) {
        fprintf(stderr, "tryon-sim: %s\n", why.detail);
        return -1;
    }
    if (a->hem_m > 0.0f)
        a->outfit.hem_m = a->hem_m;
    return 0;
}

int main(int argc, char **argv)
{
    app a = {0};
    int pr = parse(&a, argc, argv);
    if (pr != 0) {
        if (a.stats)
            fclose(a.stats);
        return pr > 0 ? usage(stdout, 0) : usage(stderr, 2);
    }
    char err[512], channel_body[BUS_CHANNEL_MAX];
    sim_topologies_init(&a.topo, a.desc.max_body_vertices, a.desc.max_body_triangles);
    a.lcm = bus_open(NULL, err, sizeof err);
    if (!a.lcm) {
        fprintf(stderr, "tryon-sim: %s\n", err);
        return 1;
    }
    tryon_keep_heap();
    /* before subscribing: bodies sent meanwhile are not kept (a backlog for --queue all) */
    if (a.rehearse) { /* kept as the garment replaced: the first one takes its body state */
        double t0 = tryon_now_ms();
        a.replaced = sim_rehearse(&a.outfit, &a.desc, a.verts, err, sizeof err);
        if (!a.replaced)
            fprintf(stderr, "tryon-sim: no rehearsal (%s); the first garment takes fresh memory\n",
                    err);
        else
            fprintf(stderr, "tryon-sim: rehearsed the garment on a stand-in body in %.0f ms\n",
                    tryon_now_ms() - t0);
    }
    bus_channel(BUS_CHANNEL_BODY, channel_body, sizeof channel_body);
    bus_channel(BUS_CHANNEL_CLOTH, a.channel_cloth, sizeof a.channel_cloth);
    bus_sub *sub = bus_subscribe(a.lcm, channel_body, BUS_BODY, on_body, &a);
    char channel_control[BUS_CHANNEL_MAX];
    bus_channel(BUS_CHANNEL_CONTROL, channel_control, sizeof channel_control);
    bus_sub *control_sub = bus_subscribe(a.lcm, channel_control, BUS_CONTROL, on_control, &a);
    if (!sub || !control_sub) {
        fprintf(stderr, "tryon-sim: cannot subscribe to %s\n", channel_body);
        sim_destroy(a.replaced);
        lcm_destroy(a.lcm);
        return 1;
    }
    struct sigaction sa = {.sa_handler = on_signal};
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    fprintf(stderr, "tryon-sim: waiting for %s on %s\n", channel_body, bus_default_url());
    while (!stop_requested) {
        /* drain what has arrived (latest) or take one body at a time (all) */
        int r = lcm_handle_timeout(a.lcm, a.queue.count ? 0 : 100);
        if (r > 0 && !a.every_body)
            continue;
        if (a.want_switch)
            switch_garment(&a);
        int slot = bus_queue_take(&a.queue);
        if (slot >= 0)
            step_body(&a, &a.waiting[slot]);
        if (a.frames_wanted > 0 && a.bodies_received >= a.frames_wanted && !a.queue.count)
            stop_requested = 1;
    }
    const bus_stats *bs = bus_sub_stats(sub);
    char budget_name[64];
    if (a.budget_auto)
        snprintf(budget_name, sizeof budget_name, "auto, deadline %g ms", (double)a.deadline_ms);
    else
        snprintf(budget_name, sizeof budget_name, "%g ms", (double)a.desc.frame_budget_ms);
    fprintf(stderr,
            "tryon-sim: %d frames simulated, %d superseded by a newer body, %d skipped, %d "
            "refused, %llu BODY messages dropped; %d published settling, %d over their budget "
            "(--frame-budget %s), %d without settle rounds (--settle-floor %g mm)\n",
            a.frames_done, a.superseded, a.skipped, a.refused, (unsigned long long)bs->rejected,
            a.settling, a.over_budget, budget_name, a.settle_skipped, (double)a.settle_floor_mm);
    fprintf(stderr,
            "tryon-sim: cloth as published: %d frames with a vertex more than 1 mm inside the "
            "body (deepest %.1f mm), %d over %g %% max or %g %% p99 strain (worst %.1f %%)\n",
            a.inside_frames, (double)a.deepest_mm, a.strain_frames,
            100.0 * (double)a.desc.retry_max_strain, 100.0 * (double)a.desc.retry_p99_strain,
            100.0 * (double)a.worst_strain);
    int failed = a.fatal || (a.frames_wanted > 0 && a.frames_done < a.frames_wanted && !a.sim);
    fprintf(stderr, "tryon-sim: %llu CONTROL accepted, %llu dropped as malformed, %d refused\n",
            (unsigned long long)bus_sub_stats(control_sub)->accepted,
            (unsigned long long)bus_sub_stats(control_sub)->rejected, a.controls_refused);
    bus_unsubscribe(a.lcm, control_sub);
    bus_unsubscribe(a.lcm, sub);
    lcm_destroy(a.lcm);
    sim_destroy(a.sim);
    sim_destroy(a.replaced);
    sim_topologies_free(&a.topo);
    if (a.stats)
        fclose(a.stats);
    free(a.xyz);
    for (int i = 0; i < BUS_QUEUE_MAX; i++)
        free(a.waiting[i].xyz);
    free(a.moved_xyz);
    free(a.moved_scratch);
    return failed ? 1 : 0;
}
