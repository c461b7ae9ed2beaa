/* libFuzzer harness: the motion-capture BVH reader (bodyfit/bvh_read.c) and, when a file parses,
 * forward kinematics of its last frame (bodyfit/bvh_pose.c). */
#include <stdint.h>

#include "bodyfit.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fit_bvh *b = NULL;
    char err[256];
    if (fit_bvh_parse((const char *)data, size, "fuzz", &b, err, sizeof err) == 0) {
        static float pos[3 * FIT_BVH_MAX_JOINTS];
        fit_bvh_world(b, fit_bvh_frame_count(b) - 1, pos, NULL);
    }
    fit_bvh_destroy(b);
    return 0;
}
