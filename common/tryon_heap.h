/* The process's heap kept between frames (glibc's mallopt). On this project's machines a page the
 * process touches for the first time costs about 11 us (a 2-core VM whose memory is backed
 * lazily: a 16 MB block touched page by page took 44 ms, the second pass 0.1 ms; docs/sim.md,
 * "tryon-sim"), so a stage that frees and allocates again, or meets its first frame with fresh
 * memory, pays for it every time. Every stage calls this once, before its first frame:
 *   - llvmpipe allocates and frees buffers of hundreds of kB every frame (vertices, bins); glibc
 *     handed them back to the kernel (heap trimmed, or mmap'd and unmapped) and the next frame
 *     faulted the same pages in again, zeroed: about 950 page faults a frame drawn with a
 *     7,105-vertex garment (`perf stat -e page-faults`, docs/mirror.md);
 *   - tryon-sim's rehearsal before it listens (sim/rehearse.c) leaves the pages of a garment's
 *     solver and body collision state in the heap for the first real one. */
#ifndef TRYON_HEAP_H
#define TRYON_HEAP_H

#include <malloc.h>

static inline void tryon_keep_heap(void)
{
    /* blocks up to 32 MB (glibc's largest mmap threshold) from the heap, and the heap's top never
     * trimmed below 256 MB: what one frame frees, the next reuses without faulting it in again */
    mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
    mallopt(M_TRIM_THRESHOLD, 256 * 1024 * 1024);
}

#endif
