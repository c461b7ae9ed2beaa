/* The library's errors (sim.h SIM_ERROR_LIST): names, texts, and the reject record every
 * fallible function fills. Its own file so that the driver (sim.c) and what it validates
 * (garment.c, cloth.c, ...) both depend on it, not on each other. */
#include <stdarg.h>
#include <stdio.h>

#include "cloth.h"

#define SIM_ERROR_NAME(id, text) #id,
#define SIM_ERROR_TEXT(id, text) text,
static const char *const error_names[] = {SIM_ERROR_LIST(SIM_ERROR_NAME)};
static const char *const error_texts[] = {SIM_ERROR_LIST(SIM_ERROR_TEXT)};

const char *sim_error_name(int e)
{
    e = e < 0 ? -e : e;
    return e < SIM_ERROR_COUNT ? error_names[e] : "SIM_ERR_UNKNOWN";
}

const char *sim_error_text(int e)
{
    e = e < 0 ? -e : e;
    return e < SIM_ERROR_COUNT ? error_texts[e] : "unknown error";
}

int sim_reject_set(sim_reject *why, sim_error code, const char *fmt, ...)
{
    if (why) {
        why->code = code;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(why->detail, sizeof why->detail, fmt, ap);
        va_end(ap);
    }
    return -(int)code;
}
