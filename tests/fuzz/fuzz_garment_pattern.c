/* libFuzzer harness: the sewing pattern reader (garments/pattern_json.c) and, when a pattern
 * parses, its meshing at a coarse spacing (outline checks, sampling, Delaunay, seams). */
#include <stdint.h>

#include "garments.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    gar_pattern p;
    gar_reject why;
    if (gar_pattern_parse((const char *)data, size, &p, &why) == 0) {
        gar_mesh m;
        /* 10 cm keeps each input fast; the point limits bound the worst case anyway. */
        if (gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = 0.1f}, &m, &why) == 0)
            gar_mesh_free(&m);
        gar_pattern_free(&p);
    }
    return 0;
}
