/* libFuzzer harness: tryon-profile's TIMING consumer. The input is a series of TIMING messages,
 * each preceded by its length (2 bytes, big-endian); every one that decodes is added to one
 * profile, whose statistics are then computed and printed. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "profile.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    bus_profile *p = bus_profile_create();
    if (!p)
        return 0;
    while (size >= 2) {
        size_t n = (size_t)data[0] << 8 | data[1];
        data += 2;
        size -= 2;
        if (n > size)
            n = size;
        tryon_timing_t t;
        bus_reject why;
        if (bus_decode(BUS_TIMING, data, n, &t, &why) == BUS_OK) {
            bus_profile_add(p, &t);
            bus_msg_free(BUS_TIMING, &t);
        }
        data += n;
        size -= n;
    }
    FILE *devnull = fopen("/dev/null", "w");
    if (devnull) {
        bus_profile_print(p, devnull);
        fclose(devnull);
    }
    bus_profile_destroy(p);
    return 0;
}
