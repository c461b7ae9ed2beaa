/* Scoring a fitted body against the true one (tryon-bench-fit). */
#ifndef TRYON_BENCH_FIT_METRICS_H
#define TRYON_BENCH_FIT_METRICS_H

#include "bodyfit.h"

/* Mean distance (m) from each vertex of a to the surface of b, approximated by the distance to
 * the tangent plane of b's nearest vertex (exact on flat parts; the nearest vertex alone would
 * add about half the vertex spacing). b_normals: unit normals of b. */
double fitm_mean_to_surface(const float *a, int na, const float *b, const float *b_normals, int nb);

#endif
