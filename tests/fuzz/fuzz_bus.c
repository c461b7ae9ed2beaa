/* libFuzzer harness: one LCM message type (FUZZ_BUS_TYPE) through the wire walk, lcm-gen's
 * decoder and validation, as every subscriber receives it (after its tag is checked). A message
 * that passes must validate again. */
#include <stdint.h>
#include <stdlib.h>

#include "bus.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    union {
        tryon_depth_frame_t d;
        tryon_body_t b;
        tryon_cloth_t c;
        tryon_timing_t t;
    } msg;
    bus_reject why;
    if (bus_decode(FUZZ_BUS_TYPE, data, size, &msg, &why) != BUS_OK)
        return 0;
    /* what was accepted is valid: validating it again must agree */
    if (bus_validate(FUZZ_BUS_TYPE, &msg, &why) != BUS_OK)
        abort();
    bus_msg_free(FUZZ_BUS_TYPE, &msg);
    return 0;
}
