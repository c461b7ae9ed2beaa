/* libFuzzer harness: the garment OBJ reader (tryon-sim --garment FILE). */
#include <stdint.h>

#include "fuzz_file.h"
#include "sim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sim_garment g;
    sim_reject why;
    if (sim_garment_load_obj(fuzz_write("garment.obj", data, size), &g, &why) == 0)
        sim_garment_free(&g);
    return 0;
}
