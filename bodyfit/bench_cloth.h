/* tryon-bench-fit's cloth_vs_truth_mm: the same shirt simulated on the fitted body and on the
 * true body, frame after frame, and the mean distance between their corresponding vertices
 * (what a person in front of the mirror sees of the fit's error; docs/bodyfit.md). */
#ifndef TRYON_BENCH_CLOTH_H
#define TRYON_BENCH_CLOTH_H

#include <stddef.h>
#include <stdint.h>

typedef struct bench_cloth bench_cloth;

/* A shirt of about garment_vertices made around the true body (truth: its joints; the bodyfit
 * joints), then the same garment glued to the fitted body (sim_garment_rebind): vertex i of one
 * is vertex i of the other. Both simulated with the sim library's defaults (25 iterations a
 * body frame, the C backend). NULL with err filled when either is refused. */
bench_cloth *bench_cloth_create(int garment_vertices, const float *true_xyz, int true_nv,
                                const int32_t *true_tris, int true_nt, const float *true_joints,
                                const float *fit_xyz, int fit_nv, const int32_t *fit_tris,
                                int fit_nt, char *err, size_t errlen);
/* One body frame on each (the same topologies as at creation): the mean distance (m) between
 * corresponding garment vertices after it, or -1 when a step failed (err filled). */
double bench_cloth_step(bench_cloth *c, const float *true_xyz, const float *fit_xyz, char *err,
                        size_t errlen);
void bench_cloth_destroy(bench_cloth *c);

#endif
