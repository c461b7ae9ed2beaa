/* Device choice, program build and error words for the OpenCL host (Khronos OpenCL-SDK style:
 * every status checked, cleanup through labels in reverse order). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cl_context.h"
#include "kernels.h"

#define MAX_PLATFORMS 8
#define MAX_DEVICES   16

#define SIM_CL_ERROR_TEXT(name, value, text)                                                       \
    case name:                                                                                     \
        return text;
const char *sim_cl_error_str(int code)
{
    code = code < 0 ? -code : code;
    switch (code) {
        SIM_CL_ERROR_LIST(SIM_CL_ERROR_TEXT)
    }
    return "unknown OpenCL host error";
}
#undef SIM_CL_ERROR_TEXT

const char *sim_cl_status_name(cl_int s)
{
    switch (s) {
#define S(x)                                                                                       \
    case x:                                                                                        \
        return #x;
        S(CL_SUCCESS)
        S(CL_DEVICE_NOT_FOUND)
        S(CL_DEVICE_NOT_AVAILABLE)
        S(CL_COMPILER_NOT_AVAILABLE)
        S(CL_MEM_OBJECT_ALLOCATION_FAILURE)
        S(CL_OUT_OF_RESOURCES)
        S(CL_OUT_OF_HOST_MEMORY)
        S(CL_BUILD_PROGRAM_FAILURE)
        S(CL_INVALID_VALUE)
        S(CL_INVALID_PLATFORM)
        S(CL_INVALID_DEVICE)
        S(CL_INVALID_CONTEXT)
        S(CL_INVALID_COMMAND_QUEUE)
        S(CL_INVALID_MEM_OBJECT)
        S(CL_INVALID_BUILD_OPTIONS)
        S(CL_INVALID_PROGRAM)
        S(CL_INVALID_PROGRAM_EXECUTABLE)
        S(CL_INVALID_KERNEL_NAME)
        S(CL_INVALID_KERNEL)
        S(CL_INVALID_ARG_INDEX)
        S(CL_INVALID_ARG_VALUE)
        S(CL_INVALID_ARG_SIZE)
        S(CL_INVALID_KERNEL_ARGS)
        S(CL_INVALID_WORK_DIMENSION)
        S(CL_INVALID_WORK_GROUP_SIZE)
        S(CL_INVALID_GLOBAL_WORK_SIZE)
        S(CL_INVALID_BUFFER_SIZE)
        S(CL_INVALID_OPERATION)
#undef S
    }
    return "unknown OpenCL status";
}

static void describe(sim_cl *cl)
{
    char dev[96] = "?", plat[56] = "?";
    clGetDeviceInfo(cl->device, CL_DEVICE_NAME, sizeof dev, dev, NULL);
    clGetPlatformInfo(cl->platform, CL_PLATFORM_NAME, sizeof plat, plat, NULL);
    dev[sizeof dev - 1] = plat[sizeof plat - 1] = '\0';
    snprintf(cl->device_name, sizeof cl->device_name, "%s (%s)", dev, plat);
    cl_device_type type = 0;
    clGetDeviceInfo(cl->device, CL_DEVICE_TYPE, sizeof type, &type, NULL);
    cl->is_gpu = (type & CL_DEVICE_TYPE_GPU) != 0;
}

/* Pick the device per TRYON_CL_DEVICE, else the first GPU, else the first device. */
static int choose_device(sim_cl *cl, char *err, size_t err_size)
{
    cl_platform_id plats[MAX_PLATFORMS];
    cl_uint np = 0;
    if (clGetPlatformIDs(MAX_PLATFORMS, plats, &np) != CL_SUCCESS || np == 0) {
        snprintf(err, err_size, "OpenCL: no platform found (is an ICD such as pocl installed?)");
        return -SIM_CL_ENODEVICE;
    }
    np = np > MAX_PLATFORMS ? MAX_PLATFORMS : np;
    const char *want = getenv("TRYON_CL_DEVICE");
    int wp = -1, wd = -1;
    if (want && *want && sscanf(want, "%d:%d", &wp, &wd) != 2)
        wp = wd = -1;
    int found_gpu = 0, found_any = 0;
    for (cl_uint p = 0; p < np; p++) {
        cl_device_id devs[MAX_DEVICES];
        cl_uint nd = 0;
        if (clGetDeviceIDs(plats[p], CL_DEVICE_TYPE_ALL, MAX_DEVICES, devs, &nd) != CL_SUCCESS)
            continue;
        nd = nd > MAX_DEVICES ? MAX_DEVICES : nd;
        for (cl_uint d = 0; d < nd; d++) {
            char name[128] = "";
            cl_device_type type = 0;
            clGetDeviceInfo(devs[d], CL_DEVICE_NAME, sizeof name, name, NULL);
            clGetDeviceInfo(devs[d], CL_DEVICE_TYPE, sizeof type, &type, NULL);
            name[sizeof name - 1] = '\0';
            int match = want && *want &&
                        ((wp >= 0 && (cl_uint)wp == p && (cl_uint)wd == d) ||
                         (wp < 0 && strstr(name, want) != NULL));
            if (want && *want) {
                if (match) {
                    cl->platform = plats[p], cl->device = devs[d];
                    return 0;
                }
                continue;
            }
            if ((type & CL_DEVICE_TYPE_GPU) && !found_gpu) {
                cl->platform = plats[p], cl->device = devs[d];
                found_gpu = found_any = 1;
            } else if (!found_any) {
                cl->platform = plats[p], cl->device = devs[d];
                found_any = 1;
            }
        }
    }
    if (want && *want) {
        snprintf(err, err_size, "OpenCL: TRYON_CL_DEVICE=\"%s\" matches no device (see clinfo -l)",
                 want);
        return -SIM_CL_ENAMED;
    }
    if (!found_any) {
        snprintf(err, err_size, "OpenCL: platforms found but no device");
        return -SIM_CL_ENODEVICE;
    }
    return 0;
}

int sim_cl_probe(sim_cl *cl, char *err, size_t err_size)
{
    if (!cl)
        return -SIM_CL_EARG;
    memset(cl, 0, sizeof *cl);
    int rc = choose_device(cl, err, err_size);
    if (rc == 0)
        describe(cl);
    return rc;
}

int sim_cl_open(sim_cl *cl, char *err, size_t err_size)
{
    if (!cl)
        return -SIM_CL_EARG;
    memset(cl, 0, sizeof *cl);
    int rc = choose_device(cl, err, err_size);
    if (rc != 0)
        return rc;
    describe(cl);
    cl_int st;
    cl_context_properties props[] = {CL_CONTEXT_PLATFORM, (cl_context_properties)cl->platform, 0};
    cl->context = clCreateContext(props, 1, &cl->device, NULL, NULL, &st);
    if (st != CL_SUCCESS) {
        snprintf(err, err_size, "OpenCL: clCreateContext on %s: %s", cl->device_name,
                 sim_cl_status_name(st));
        goto fail;
    }
    cl->queue = clCreateCommandQueue(cl->context, cl->device, 0, &st);
    if (st != CL_SUCCESS) {
        snprintf(err, err_size, "OpenCL: clCreateCommandQueue on %s: %s", cl->device_name,
                 sim_cl_status_name(st));
        goto fail;
    }
    return 0;
fail:
    sim_cl_close(cl);
    return -SIM_CL_ECALL;
}

int sim_cl_build(sim_cl *cl, const char *const *files, int nfiles, char *err, size_t err_size)
{
    const char *text[17];
    if (!cl || !cl->context || nfiles < 0 || nfiles > 16)
        return -SIM_CL_EARG;
    text[0] = kernels_source("common.cl");
    for (int i = 0; i < nfiles; i++)
        text[i + 1] = kernels_source(files[i]);
    for (int i = 0; i <= nfiles; i++)
        if (!text[i]) {
            snprintf(err, err_size, "OpenCL: kernel file %s is not embedded",
                     i == 0 ? "common.cl" : files[i - 1]);
            return -SIM_CL_ESOURCE;
        }
    cl_int st;
    cl->program = clCreateProgramWithSource(cl->context, (cl_uint)nfiles + 1, text, NULL, &st);
    if (st != CL_SUCCESS) {
        snprintf(err, err_size, "OpenCL: clCreateProgramWithSource: %s", sim_cl_status_name(st));
        return -SIM_CL_ECALL;
    }
    /* Correctly rounded / and sqrt where offered, so kernels match the C twins. */
    cl_device_fp_config fp = 0;
    clGetDeviceInfo(cl->device, CL_DEVICE_SINGLE_FP_CONFIG, sizeof fp, &fp, NULL);
    const char *opts = (fp & CL_FP_CORRECTLY_ROUNDED_DIVIDE_SQRT)
                           ? "-cl-std=CL1.2 -cl-fp32-correctly-rounded-divide-sqrt"
                           : "-cl-std=CL1.2";
    st = clBuildProgram(cl->program, 1, &cl->device, opts, NULL, NULL);
    if (st != CL_SUCCESS) {
        size_t len = 0;
        clGetProgramBuildInfo(cl->program, cl->device, CL_PROGRAM_BUILD_LOG, 0, NULL, &len);
        char *log = malloc(len + 1);
        if (log) {
            clGetProgramBuildInfo(cl->program, cl->device, CL_PROGRAM_BUILD_LOG, len, log, NULL);
            log[len] = '\0';
            fprintf(stderr, "OpenCL build log (%s):\n%s\n", cl->device_name, log);
            free(log);
        }
        snprintf(err, err_size, "OpenCL: program build failed on %s: %s (log above)",
                 cl->device_name, sim_cl_status_name(st));
        clReleaseProgram(cl->program);
        cl->program = NULL;
        return -SIM_CL_EBUILD;
    }
    return 0;
}

void sim_cl_close(sim_cl *cl)
{
    if (!cl)
        return;
    if (cl->program)
        clReleaseProgram(cl->program);
    if (cl->queue)
        clReleaseCommandQueue(cl->queue);
    if (cl->context)
        clReleaseContext(cl->context);
    memset(cl, 0, sizeof *cl);
}

cl_kernel sim_cl_kernel(const sim_cl *cl, const char *name, char *err, size_t err_size)
{
    cl_int st;
    cl_kernel k = clCreateKernel(cl->program, name, &st);
    if (st != CL_SUCCESS) {
        snprintf(err, err_size, "OpenCL: kernel %s: %s", name, sim_cl_status_name(st));
        return NULL;
    }
    return k;
}
