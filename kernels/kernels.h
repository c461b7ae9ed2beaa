/* kernels: the OpenCL C sources of the .cl files of kernels/, embedded at build time
 * (kernels/embed.cmake). Each .cl file starts from kernels/common.cl, which the host puts first in
 * every program. */
#ifndef TRYON_KERNELS_H
#define TRYON_KERNELS_H

typedef struct kernels_file {
    const char *name; /* "bvh.cl" */
    const char *text; /* the file, NUL-terminated */
} kernels_file;

extern const kernels_file kernels_files[]; /* ends with {0, 0} */
extern const int kernels_file_count;

/* The text of one embedded file, or NULL when there is none of that name. */
const char *kernels_source(const char *name);

#endif
