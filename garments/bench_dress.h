/* tryon-bench-dress's modes besides dressing (bench_modes.c). */
#ifndef TRYON_GARMENTS_BENCH_DRESS_H
#define TRYON_GARMENTS_BENCH_DRESS_H

#include <stdio.h>

#include "garments.h"

/* --drape: the Cusick drape test of one fabric (NULL = every preset) with tryon's dressing at
 * iterations sweeps a step; exit status. */
int bench_drape(const gar_fabric *only, int iterations);

/* --pick-size: the pattern at path in S, M and L on body; exit status. */
struct fit_model;
int bench_pick_size(const char *path, const struct fit_model *body, int shape,
                    const gar_mesh_desc *md, const gar_dress_desc *dd);
/* --stability: the map of seam stiffness x time step for the pattern at path; exit status. */
int bench_stability(const char *path, const struct fit_model *body, int tryon,
                    const gar_mesh_desc *md, const gar_dress_desc *base);

/* --strain-report: the stretch springs of a dressed garment over `over` (strain_report.c):
 * count per panel and the worst with where they lie; 0 or a -GAR_ERR_* code. */
int gar_strain_report(const gar_pattern *p, const gar_mesh *m, const struct fit_model *body,
                      float over, FILE *f);

#endif
