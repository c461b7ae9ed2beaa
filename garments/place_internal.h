/* Private to garments/: placement helpers. */
#ifndef TRYON_GARMENTS_PLACE_INTERNAL_H
#define TRYON_GARMENTS_PLACE_INTERNAL_H

struct fit_model;

/* Points in cells of one size; nearest queries look in the 27 cells around a point. */
typedef struct gar_grid {
    float lo[3], cell;
    int dim[3];
    int *start, *items; /* counting sort: cell c holds items[start[c] .. start[c + 1]) */
} gar_grid;
int gar_grid_build(gar_grid *g, const float *xyz, int n, float cell);
/* Nearest point within one cell's reach (else -1). */
int gar_grid_nearest(const gar_grid *g, const float *xyz, const float *p);
void gar_grid_free(gar_grid *g);

/* Moves each of the n points (xyz) the body's surface reaches within clearance_m out along the
 * nearest body vertex's normal to clearance_m. Returns 0 or -GAR_ERR_x. */
int gar_push_out(const struct fit_model *body, const float *body_xyz, float *xyz, int n,
                 float clearance_m);

#endif
