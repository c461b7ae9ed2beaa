/* OpenCL host plumbing for the sim (private to sim/): device choice, the program
 * built from the embedded the .cl files of kernels/, kernels by name. Every cl* call is checked.
 *
 * Device choice: TRYON_CL_DEVICE = "P:D" (platform and device index, as `clinfo -l` lists them)
 * or a substring of the device name ("pthread", "H100"); otherwise the first GPU of any
 * platform, otherwise the first device of any kind (PoCL's CPU device "pthread-..."). */
#ifndef TRYON_SIM_CL_CONTEXT_H
#define TRYON_SIM_CL_CONTEXT_H

#ifndef CL_TARGET_OPENCL_VERSION
#define CL_TARGET_OPENCL_VERSION 120
#endif
#include <CL/cl.h>
#include <stddef.h>

#define SIM_CL_ERROR_LIST(X)                                                                       \
    X(SIM_CL_OK, 0, "ok")                                                                          \
    X(SIM_CL_ENODEVICE, 101, "no OpenCL platform or device found")                                 \
    X(SIM_CL_ENAMED, 102, "TRYON_CL_DEVICE names no device")                                       \
    X(SIM_CL_ECALL, 103, "an OpenCL call failed")                                                  \
    X(SIM_CL_EBUILD, 104, "the OpenCL program did not build (log on stderr)")                      \
    X(SIM_CL_ESOURCE, 105, "a kernel source file is not embedded")                                 \
    X(SIM_CL_EARG, 106, "invalid argument")

#define SIM_CL_ERROR_ENUM(name, value, text) name = value,
typedef enum sim_cl_error { SIM_CL_ERROR_LIST(SIM_CL_ERROR_ENUM) } sim_cl_error;
#undef SIM_CL_ERROR_ENUM

/* Functions return 0 or -SIM_CL_Ex (docs/building.md, "Conventions: errors"): 101 and up, so
 * never mistaken for a sim_error; the backend reports any of them as -SIM_ERR_BACKEND. */
const char *sim_cl_error_str(int code);        /* accepts code or -code */
const char *sim_cl_status_name(cl_int status); /* "CL_OUT_OF_RESOURCES" */

typedef struct sim_cl {
    cl_platform_id platform;
    cl_device_id device;
    cl_context context;
    cl_command_queue queue;
    cl_program program;
    char device_name[160]; /* "pthread-skylake-avx512 (Portable Computing Language)" */
    int is_gpu;
} sim_cl;

/* Choose the device as sim_cl_open would, and only describe it (device_name, is_gpu): no context
   is made, nothing needs closing. */
int sim_cl_probe(sim_cl *cl, char *err, size_t err_size);
/* Choose the device and make its context and in-order queue. On failure cl is left closed. */
int sim_cl_open(sim_cl *cl, char *err, size_t err_size);
/* Build one program from kernels/common.cl followed by the named embedded files, with options
   that keep kernels equal to their C twins (correctly rounded divide and sqrt where the device
   offers it; never -cl-fast-relaxed-math). The build log goes to stderr on failure. */
int sim_cl_build(sim_cl *cl, const char *const *files, int nfiles, char *err, size_t err_size);
void sim_cl_close(sim_cl *cl); /* accepts a zeroed or half-open cl */

/* A kernel of the built program, NULL with err filled when absent. */
cl_kernel sim_cl_kernel(const sim_cl *cl, const char *name, char *err, size_t err_size);

/* Checked call: on failure, say which call, where, and the status, then jump to label. */
#define SIM_CL_CHECK(call, rc, err, err_size, label)                                               \
    do {                                                                                           \
        cl_int st_ = (call);                                                                       \
        if (st_ != CL_SUCCESS) {                                                                   \
            snprintf((err), (err_size), "%s:%d: %s failed: %s", __FILE__, __LINE__, #call,         \
                     sim_cl_status_name(st_));                                                     \
            (rc) = -SIM_CL_ECALL;                                                                  \
            goto label;                                                                            \
        }                                                                                          \
    } while (0)

#endif
