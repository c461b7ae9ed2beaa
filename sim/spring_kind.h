/* Private to sim/: the kinds of spring, which the cloth's layout (cloth.h) and the passes over it
 * (passes.h) both name. */
#ifndef TRYON_SIM_SPRING_KIND_H
#define TRYON_SIM_SPRING_KIND_H

typedef enum sim_spring_kind {
    SIM_SPRING_STRETCH = 0,
    SIM_SPRING_SHEAR = 1,
    SIM_SPRING_BEND = 2,
    SIM_SPRING_KINDS
} sim_spring_kind;

#endif
