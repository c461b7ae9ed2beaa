/* libFuzzer harness: the ground-truth reader of recordings (gt-NNNNNN.txt, tryon-truth). */
#include <stdint.h>

#include "fuzz_file.h"
#include "recordings.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    rec_gt g;
    rec_report why;
    rec_gt_read(fuzz_write("gt-000000.txt", data, size), &g, &why);
    return 0;
}
