/* Private to garments/: placement helpers. */
#ifndef TRYON_GARMENTS_PLACE_INTERNAL_H
#define TRYON_GARMENTS_PLACE_INTERNAL_H

struct fit_model;
/* Moves each of the n points (xyz) the body's surface reaches within clearance_m out along the
 * nearest body vertex's normal to clearance_m. Returns 0 or -GAR_ERR_x. */
int gar_push_out(const struct fit_model *body, const float *body_xyz, float *xyz, int n,
                 float clearance_m);

#endif
