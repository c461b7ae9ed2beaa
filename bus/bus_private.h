/* Private to bus/: one row per message type, so adding a type is one line in each list. */
#ifndef TRYON_BUS_PRIVATE_H
#define TRYON_BUS_PRIVATE_H

#include "bus.h"

#include <stdarg.h>

/* (enum, generated type name) */
#define BUS_TYPE_LIST(X)                                                                           \
    X(BUS_DEPTH_FRAME, tryon_depth_frame_t)                                                        \
    X(BUS_BODY, tryon_body_t)                                                                      \
    X(BUS_CLOTH, tryon_cloth_t)                                                                    \
    X(BUS_TIMING, tryon_timing_t)                                                                  \
    X(BUS_CONTROL, tryon_control_t)

/* Walk the encoded bytes of type t without allocating: every count must be sane and every
 * array must fit in the buffer before lcm's generated decoder (which allocates whatever a count
 * says, then checks) is allowed to see it. */
int bus_wire_check(bus_type t, const uint8_t *buf, size_t len, bus_reject *why);

/* Sets why (may be NULL) and returns -code. */
int bus_reject_set(bus_reject *why, bus_error code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#endif
