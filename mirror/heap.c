/* The process's heap kept between frames. llvmpipe allocates and frees buffers of hundreds of kB
 * every frame (vertices, bins); glibc handed them back to the kernel (heap trimmed, or mmap'd and
 * unmapped) and the next frame faulted the same pages in again, zeroed: about 950 page faults a
 * frame drawn with a 7,105-vertex garment (`perf stat -e page-faults`, docs/mirror.md). */
#include <malloc.h>

#include "mirror.h"

void mirror_keep_heap(void)
{
    /* blocks up to 32 MB (glibc's largest mmap threshold) from the heap, and the heap's top never
     * trimmed below 256 MB: a frame's buffers are reused by the next frame, not faulted in again */
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, 256 * 1024 * 1024);
}
