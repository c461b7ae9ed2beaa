/* Private to garments/: the strain limit of tryon's dressing with fastened heights held. */
#ifndef TRYON_GARMENTS_STRAIN_HELD_H
#define TRYON_GARMENTS_STRAIN_HELD_H

#include <stdint.h>

/* The stretch springs [begin, end) of one colour (no two share a vertex; x[v][3] the inverse
 * mass) longer than rest (1 + limit) shortened back to it; a vertex with fastened[v] set keeps
 * its height. */
void gar_strain_limit_held(float (*x)[4], const int32_t (*ends)[2], const float *rest,
                           const uint8_t *fastened, float limit, int begin, int end);

#endif
