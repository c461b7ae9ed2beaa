/* Private to sim/: tryon-bench-sim's sewing-pattern garments (`--scene body --garment
 * PATTERN.json`, sim/bench_pattern.c). The pattern is dressed once by sim/outfit_pattern.c on the
 * scene's own body model at rest and carried to the scene's first frame; every run of the bench
 * (the measured one and the references) gets a copy. Also the check that sleeves follow the arms
 * and trouser legs the legs. */
#ifndef TRYON_SIM_BENCH_PATTERN_H
#define TRYON_SIM_BENCH_PATTERN_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"
#include "sim.h"

/* A limb panel's vertex "follows" its limb when it is within this of the nearest body vertex
 * skinned mostly to that limb (shoulder, elbow, wrist; hip, knee, ankle, toe; the same side):
 * a sleeve or trouser leg is loose by 1 to 3 cm at rest, and the body's vertices are about 2 cm
 * apart at 6,000 vertices, so 5 cm holds a garment that moves with its limb and refuses one left
 * a hand's width behind. */
#define BENCH_LIMB_NEAR_M 0.05f

typedef struct bench_pattern bench_pattern;

typedef struct bench_pattern_desc {
    const char *path;    /* the pattern file */
    sim_size size;       /* graded to */
    const char *fabric;  /* garments/' fabric name; "" = cotton */
    int target_vertices; /* about this many (0: the 2 cm mesh) */
    int body_verts;      /* the scene's body model (sim_scene_body's target_vertices) */
} bench_pattern_desc;

/* The fabric of the request, for the sim's desc; -1 with err filled when the request is refused
 * (an unknown size or fabric, a file not ending in .json). */
int bench_pattern_fabric(const bench_pattern_desc *d, sim_fabric *out, char *err, size_t err_size);

/* Dresses the pattern on the scene's body model (default shape, d->body_verts) at rest. NULL with
 * err filled on any refusal. sc: the scene (its body must be that model). */
bench_pattern *bench_pattern_create(const bench_pattern_desc *d, sim_scene *sc, char *err,
                                    size_t err_size);
void bench_pattern_destroy(bench_pattern *bp);

/* A copy of the dressed garment (the caller frees it with sim_garment_free). 0 or -1. */
int bench_pattern_garment(const bench_pattern *bp, sim_garment *out);

/* The garment brought from the rest pose, where it was dressed, to the scene's first frame xyz0
 * (the same topology) by the sim itself: BENCH_PATTERN_TURN_IN_FRAMES frames of the body blended
 * from rest to xyz0 (a smoothstep), then sim_pattern_settle on xyz0. Carried there in one jump
 * (sim/carry.c, as tryon-sim does), the jeans' inseams went with the wrong leg when the first
 * frame is a stride: 278 vertices up to 80 mm inside the body on the walk's first frame. Returns
 * sim_step's result. */
#define BENCH_PATTERN_TURN_IN_FRAMES 15
int bench_pattern_turn_in(const bench_pattern *bp, sim *s, const float *xyz0, int nv,
                          const int32_t *tris, int nt, sim_reject *why);

/* The dressing's figures, for the log and the JSON line. */
typedef struct bench_pattern_info {
    float dress_ms, total_ms, spacing_m, seam_gap_mm, max_strain, p99_strain;
    int penetrating, vertices, arm_vertices, leg_vertices;
} bench_pattern_info;
void bench_pattern_get_info(const bench_pattern *bp, bench_pattern_info *out);

/* The fractions of the arm panels' and the leg panels' vertices within BENCH_LIMB_NEAR_M of
 * their limb, for the cloth x ([vertex][3], the garment's order) on the body body_xyz of
 * body_nv vertices (the scene's topology). A garment without such panels, or a body of another
 * topology, gets -1. */
void bench_pattern_limbs(const bench_pattern *bp, const float *x, const float *body_xyz,
                         int body_nv, float *arm_frac, float *leg_frac);

#endif
