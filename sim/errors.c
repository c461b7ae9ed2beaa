/* The library's errors (sim.h SIM_ERROR_LIST): names, texts, and the reject record every
 * fallible function fills. Its own file so that the driver (sim.c) and what it validates
 * (garment.c, cloth.c, ...) both depend on it, not on each other. */
#include "cloth.h"
#include "tryon_errors.h"

TRYON_ERROR_WORDS(SIM_ERROR_LIST, SIM_ERROR_COUNT, sim_error_name, sim_error_text,
                  "SIM_ERR_UNKNOWN")
TRYON_REJECT_SETTER(sim_reject_set, sim_reject, sim_error)
