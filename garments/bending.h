/* Private to garments/: bending that the solver honours (docs/garments.md, "Bending").
 *
 * The isometric bending model of Bergou, Wardetzky, Harmon, Zorin and Grinspun ("A quadratic
 * bending model for inextensible surfaces", SGP 2006): per interior edge of a panel, its two
 * triangles' four vertices and weights K from the flat panel's cotangents, so that
 * C = sum_i K_i x_i (a vector, m) is 0 for any flat or rigidly moved panel and grows with the
 * fold across the edge. The energy B / 2 * s * |C|^2 (B the fabric's bending rigidity, N m;
 * s per stencil, 1 / m^2) is calibrated so that a panel rolled into a cylinder of radius R stores
 * B / 2 / R^2 per unit area, the plate energy. C is linear in the positions, so its XPBD step
 * (Macklin, Mueller and Chentanez, "XPBD", MIG 2016) is exact per stencil: the solver honours
 * the rigidity whatever the sweeps. */
#ifndef TRYON_GARMENTS_BENDING_H
#define TRYON_GARMENTS_BENDING_H

#include <stdint.h>

#include "garments.h"

typedef struct gar_bending {
    int n;              /* stencils (interior edges) */
    int32_t (*v)[4];    /* edge ends 0, 1; the two opposite vertices 2, 3 */
    float (*k)[4];      /* cotangent weights, sum 0 */
    float *s;           /* per stencil, 1 / m^2 */
    float (*lambda)[3]; /* XPBD multipliers of the current step */
    float *alpha, *inv; /* from gar_bending_prepare: alpha~, 1 / (alpha~ + sum w K^2) */
} gar_bending;

/* Stencils over every edge two triangles of one panel share, from the flat panels (uv_m).
 * Returns 0 or -GAR_ERR_NO_MEMORY. Empty (n = 0) when the mesh has no interior edge. */
int gar_bending_build(const gar_mesh *m, gar_bending *b);
void gar_bending_free(gar_bending *b);

/* Bending energy (J) of positions x ([vertex][4], xyz used) with rigidity B (N m), and its
 * gradient (J/m, [vertex][3], added to grad). */
double gar_bending_energy(const gar_bending *b, const float (*x)[4], float rigidity_n_m);
void gar_bending_gradient(const gar_bending *b, const float (*x)[4], float rigidity_n_m,
                          double *grad);

/* The multipliers to 0 (at the start of each step). */
void gar_bending_begin_step(gar_bending *b);
/* The step's constants for rigidity B (N m), step h (s) and the inverse masses in x[v][3]
 * (call again when any of them changes). B <= 0: no bending. */
void gar_bending_prepare(gar_bending *b, const float (*x)[4], float rigidity_n_m, float h);
/* One Gauss-Seidel sweep of the XPBD bending constraints over x ([vertex][4], w = inverse mass,
 * as prepared). */
void gar_bending_project(gar_bending *b, float (*x)[4]);

#endif
