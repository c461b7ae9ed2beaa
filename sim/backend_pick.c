/* --backend auto where the OpenCL device is a GPU: which backend is faster is measured, not
 * assumed. On the lent H100 the OpenCL backend ran the body scene's shirt at 10.8 ms a frame and
 * the C backend at 5.0 ms on the machine's 16 cores (docs/sim.md, "On a GPU"): the solver's
 * iterations run in one work-group, one of the GPU's 132 multiprocessors. */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tryon_clock.h"
#include "sim.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median wall time of frames 1..frames-1 of the garment on the still body on backend b (frame
 * 0 builds the OpenCL program and uploads the cloth), or -1 when the backend does not run it. */
static double time_backend(const sim_desc *desc, sim_backend b, const sim_garment *g,
                           const float *body_xyz, int nv, const int32_t *body_tris, int nt,
                           int frames)
{
    sim_desc d = *desc;
    d.backend = b;
    sim_reject why = {0};
    sim *s = sim_create(&d, g, &why);
    double *ms = malloc((size_t)frames * sizeof *ms);
    int n = 0;
    for (int f = 0; s && ms && f < frames; f++) {
        sim_frame_stats st;
        double t0 = tryon_now_ms();
        if (sim_step(s, body_xyz, nv, body_tris, nt, &st, &why) != 0)
            break;
        if (f > 0)
            ms[n++] = tryon_now_ms() - t0;
    }
    double med = -1.0;
    if (n > 0 && n == frames - 1) {
        qsort(ms, (size_t)n, sizeof *ms, cmp_double);
        med = ms[n / 2];
    }
    free(ms);
    sim_destroy(s);
    return med;
}

int sim_backend_race(const sim_desc *desc, const sim_garment *g, const float *body_xyz, int nv,
                     const int32_t *body_tris, int nt, int frames, sim_backend *out, double ms[2])
{
    if (!desc || !g || !body_xyz || !body_tris || !out || !ms || frames < 2 || frames > 1000)
        return -SIM_ERR_ARG;
    ms[0] = time_backend(desc, SIM_BACKEND_C, g, body_xyz, nv, body_tris, nt, frames);
    ms[1] = time_backend(desc, SIM_BACKEND_OPENCL, g, body_xyz, nv, body_tris, nt, frames);
    if (ms[0] < 0.0 && ms[1] < 0.0)
        return -SIM_ERR_BACKEND;
    *out = ms[1] >= 0.0 && (ms[0] < 0.0 || ms[1] < ms[0]) ? SIM_BACKEND_OPENCL : SIM_BACKEND_C;
    return 0;
}
