/* The OpenCL backend (sim_backend_ops): the per-frame work of the tryon solver on an OpenCL
 * device, twin of sim/solver_c.c. Per frame: the new body vertices up, face normals and refit,
 * the moving frame, feature points, attachments, contacts, then ONE kernel running every iteration
 * in one work-group (kernels/springs.cl sim_iterations_tryon), then x and x_prev back to the host.
 * About ten commands a frame however many iterations and colours. The seed solver variant runs on
 * the C backend only. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cl_collide.h"
#include "cloth.h"
#include "frame_settings.h"

/* Work-group size cap of the iterations kernel: every work-item strides over vertices and
   springs; larger groups only add barrier cost on a CPU device. */
#define ITER_GROUP_MAX 1024

/* The pass kernels of a frame run pass by pass (kernels/springs.cl, sim_pass_*). */
typedef enum pass_kind {
    PASS_STEP,
    PASS_SPRINGS,
    PASS_STRAIN,
    PASS_VERTICES,
    PASS_HIERARCHY,
    PASS_SUPPORT,
    PASS_SETTLE_TEST,
    PASS_REOPEN,
    PASS_KINDS
} pass_kind;
static const char *const pass_kernel_names[PASS_KINDS] = {
    "sim_pass_step",      "sim_pass_springs", "sim_pass_strain",      "sim_pass_vertices",
    "sim_pass_hierarchy", "sim_pass_support", "sim_pass_settle_test", "sim_pass_reopen"};

typedef struct cl_state {
    sim_cl cl;
    sim_cl_collide g;
    cl_mem x, x_prev, ends, rest, kind, color_start, anchor, tlen, attach, att_from, att_to;
    cl_mem hier_level_start, hier_vertex, hier_parent_start, hier_parent, hier_rest;
    cl_mem settle; /* the settle rounds the last frame ran (1 int) */
    /* the support hierarchy: stretch springs by vertex (CSR), level per vertex, two lists of nv */
    cl_mem adj_start, adj_spring, level, front;
    cl_mem x_seen; /* where each point's contact was last searched (sim_collider_research) */
    cl_kernel k_iter, k_attach, k_follow;
    /* the frame pass by pass (a GPU): kernels in sim_pass_kind order, the support's group size */
    cl_kernel k_pass[PASS_KINDS];
    int passes;
    size_t support_group;
    size_t group;
    int32_t *moved;       /* host copy of the per-point flags */
    int32_t *contact;     /* host copy of the frame's contacts, for the host metric */
    float (*x_search)[4]; /* the cloth where the contacts were searched */
    long body_stored;     /* the body frame on the device (sim_body.stored); 0: none */
    char name[200];
} cl_state;

static double now_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

static void cl_destroy(void *state)
{
    cl_state *c = state;
    if (!c)
        return;
    if (c->k_iter)
        clReleaseKernel(c->k_iter);
    if (c->k_attach)
        clReleaseKernel(c->k_attach);
    if (c->k_follow)
        clReleaseKernel(c->k_follow);
    for (int i = 0; i < PASS_KINDS; i++)
        if (c->k_pass[i])
            clReleaseKernel(c->k_pass[i]);
    if (c->att_from)
        clReleaseMemObject(c->att_from);
    if (c->att_to)
        clReleaseMemObject(c->att_to);
    if (c->settle)
        clReleaseMemObject(c->settle);
    cl_mem support[] = {c->adj_start, c->adj_spring, c->level, c->front, c->x_seen};
    for (size_t i = 0; i < sizeof support / sizeof support[0]; i++)
        if (support[i])
            clReleaseMemObject(support[i]);
    cl_mem ms[] = {c->x,           c->x_prev,           c->ends,        c->rest,
                   c->kind,        c->color_start,      c->anchor,      c->tlen,
                   c->attach,      c->hier_level_start, c->hier_vertex, c->hier_parent_start,
                   c->hier_parent, c->hier_rest};
    for (size_t i = 0; i < sizeof ms / sizeof ms[0]; i++)
        if (ms[i])
            clReleaseMemObject(ms[i]);
    sim_cl_collide_destroy(&c->g);
    sim_cl_close(&c->cl);
    free(c->moved);
    free(c->contact);
    free(c->x_search);
    free(c);
}

/* A read-only buffer holding a copy of src (at least 16 bytes so empty arrays are valid). */
static cl_mem const_buffer(const sim_cl *cl, size_t bytes, const void *src, cl_int *st)
{
    if (*st != CL_SUCCESS)
        return NULL;
    static const char zero[16];
    /* COPY_HOST_PTR only reads the pointer; the API just is not const-qualified. */
    void *from = (void *)(uintptr_t)(bytes ? src : (const void *)zero);
    return clCreateBuffer(cl->context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                          bytes ? bytes : sizeof zero, from, st);
}

static int cl_upload(void *state, const struct sim *s)
{
    cl_state *c = state;
    size_t bytes = (size_t)s->cloth.nv * 16;
    cl_int st =
        clEnqueueWriteBuffer(c->cl.queue, c->x, CL_FALSE, 0, bytes, s->cloth.x, 0, NULL, NULL);
    if (st == CL_SUCCESS)
        st = clEnqueueWriteBuffer(c->cl.queue, c->x_prev, CL_TRUE, 0, bytes, s->cloth.x_prev, 0,
                                  NULL, NULL);
    return st == CL_SUCCESS ? 0 : -SIM_ERR_BACKEND;
}

/* From this many cloth vertices up a GPU runs the frame pass by pass: on the lent H100 the body
   scene's shirt at 2,079 / 4,180 / 5,124 / 7,105 vertices took 3.2 / 5.0 / 6.1 / 8.1 ms a frame in
   one work-group and 5.6 / 5.6 / 5.9 / 5.5 pass by pass (docs/sim.md, "On a GPU"). */
#define PASSES_MIN_VERTICES 5000

/* Pass by pass on a GPU for a garment of PASSES_MIN_VERTICES or more (TRYON_CL_PASSES=1 or 0
   says otherwise, e.g. to test the passes on PoCL): the pass kernels built and the support's
   group sized. */
static int pass_mode(cl_state *c, int nv, char *err, size_t err_size)
{
    const char *e = getenv("TRYON_CL_PASSES");
    c->passes = e && (!strcmp(e, "0") || !strcmp(e, "1"))
                    ? e[0] == '1'
                    : c->cl.is_gpu && nv >= PASSES_MIN_VERTICES;
    if (!c->passes)
        return 0;
    for (int i = 0; i < PASS_KINDS; i++)
        if (!(c->k_pass[i] = sim_cl_kernel(&c->cl, pass_kernel_names[i], err, err_size)))
            return -1;
    size_t wg = 1;
    cl_int st = clGetKernelWorkGroupInfo(c->k_pass[PASS_SUPPORT], c->cl.device,
                                         CL_KERNEL_WORK_GROUP_SIZE, sizeof wg, &wg, NULL);
    if (st != CL_SUCCESS) {
        snprintf(err, err_size, "OpenCL backend: work-group size: %s", sim_cl_status_name(st));
        return -1;
    }
    c->support_group = wg < ITER_GROUP_MAX ? wg : ITER_GROUP_MAX;
    return 0;
}

static int cl_create(struct sim *s, void **state, char *err, size_t err_size)
{
    const sim_cloth *k = &s->cloth;
    cl_state *c = calloc(1, sizeof *c);
    if (c) {
        c->moved = calloc((size_t)k->nv, sizeof *c->moved);
        c->contact = calloc((size_t)k->nv, sizeof *c->contact);
        c->x_search = calloc((size_t)k->nv, sizeof *c->x_search);
    }
    if (!c || !c->moved || !c->contact || !c->x_search) {
        if (c) {
            free(c->moved);
            free(c->contact);
            free(c->x_search);
        }
        free(c);
        snprintf(err, err_size, "OpenCL backend: out of memory");
        return -SIM_ERR_NO_MEMORY;
    }
    const char *files[] = {SIM_CL_COLLIDE_FILES, "solver_params.h", "springs.cl"};
    if (sim_cl_open(&c->cl, err, err_size) != 0 ||
        sim_cl_build(&c->cl, files, (int)(sizeof files / sizeof files[0]), err, err_size) ||
        sim_cl_collide_create(&c->g, &c->cl, s->desc.max_body_vertices, s->desc.max_body_triangles,
                              k->nv, err, err_size) != 0)
        goto fail;
    cl_int st = CL_SUCCESS;
    size_t nv = (size_t)k->nv, ns = (size_t)k->ns;
    c->x = clCreateBuffer(c->cl.context, CL_MEM_READ_WRITE, nv * 16, NULL, &st);
    if (st == CL_SUCCESS)
        c->x_prev = clCreateBuffer(c->cl.context, CL_MEM_READ_WRITE, nv * 16, NULL, &st);
    c->ends = const_buffer(&c->cl, ns * 8, k->ends, &st);
    c->rest = const_buffer(&c->cl, ns * 4, k->rest, &st);
    c->kind = const_buffer(&c->cl, ns, k->kind, &st);
    c->color_start = const_buffer(&c->cl, (size_t)(k->num_colors + 1) * 4, k->color_start, &st);
    /* No tethers: every anchor -1, so the kernel needs no special case. */
    int32_t *none = k->tether_anchor ? NULL : malloc(nv * 4);
    float *zero = k->tether_len ? NULL : calloc(nv, 4);
    if (!k->tether_anchor && (!none || !zero)) {
        free(none);
        free(zero);
        snprintf(err, err_size, "OpenCL backend: out of memory");
        goto fail;
    }
    for (size_t i = 0; none && i < nv; i++)
        none[i] = -1;
    c->anchor = const_buffer(&c->cl, nv * 4, none ? none : k->tether_anchor, &st);
    c->tlen = const_buffer(&c->cl, nv * 4, zero ? (const void *)zero : k->tether_len, &st);
    free(none);
    free(zero);
    c->attach = const_buffer(&c->cl, (size_t)k->num_attachments * sizeof(sim_attachment),
                             k->attachments, &st);
    /* the strain-limit hierarchy (empty without attachments: 16-byte placeholders) */
    size_t nh = (size_t)k->hier_level_start[k->hier_levels];
    c->hier_level_start =
        const_buffer(&c->cl, (size_t)(k->hier_levels + 1) * 4, k->hier_level_start, &st);
    c->hier_vertex = const_buffer(&c->cl, nh * 4, k->hier_vertex, &st);
    c->hier_parent_start = const_buffer(&c->cl, (nh + 1) * 4, k->hier_parent_start, &st);
    c->hier_parent =
        const_buffer(&c->cl, (size_t)k->hier_parent_start[nh] * 4, k->hier_parent, &st);
    c->hier_rest = const_buffer(&c->cl, (size_t)k->hier_parent_start[nh] * 4, k->hier_rest, &st);
    c->adj_start = const_buffer(&c->cl, (nv + 1) * 4, k->adj_start, &st);
    c->adj_spring = const_buffer(&c->cl, (size_t)k->adj_start[nv] * 4, k->adj_spring, &st);
    if (st == CL_SUCCESS)
        c->level = clCreateBuffer(c->cl.context, CL_MEM_READ_WRITE, nv * 4, NULL, &st);
    if (st == CL_SUCCESS)
        c->front = clCreateBuffer(c->cl.context, CL_MEM_READ_WRITE, 2 * nv * 4, NULL, &st);
    if (st == CL_SUCCESS)
        c->x_seen = clCreateBuffer(c->cl.context, CL_MEM_READ_WRITE, nv * 16, NULL, &st);
    size_t na = k->num_attachments > 0 ? (size_t)k->num_attachments : 1;
    if (st == CL_SUCCESS)
        c->att_from = clCreateBuffer(c->cl.context, CL_MEM_READ_WRITE, na * 16, NULL, &st);
    if (st == CL_SUCCESS)
        c->att_to = clCreateBuffer(c->cl.context, CL_MEM_READ_WRITE, na * 16, NULL, &st);
    if (st == CL_SUCCESS)
        c->settle = clCreateBuffer(c->cl.context, CL_MEM_READ_WRITE, sizeof(cl_int), NULL, &st);
    if (st != CL_SUCCESS) {
        snprintf(err, err_size, "OpenCL backend: cloth buffers: %s", sim_cl_status_name(st));
        goto fail;
    }
    if (!(c->k_iter = sim_cl_kernel(&c->cl, "sim_iterations_tryon", err, err_size)) ||
        !(c->k_attach = sim_cl_kernel(&c->cl, "sim_attachment_targets", err, err_size)) ||
        !(c->k_follow = sim_cl_kernel(&c->cl, "sim_follow", err, err_size)))
        goto fail;
    size_t wg = 1;
    st = clGetKernelWorkGroupInfo(c->k_iter, c->cl.device, CL_KERNEL_WORK_GROUP_SIZE, sizeof wg,
                                  &wg, NULL);
    if (st != CL_SUCCESS) {
        snprintf(err, err_size, "OpenCL backend: work-group size: %s", sim_cl_status_name(st));
        goto fail;
    }
    c->group = wg < ITER_GROUP_MAX ? wg : ITER_GROUP_MAX;
    if (pass_mode(c, k->nv, err, err_size) != 0)
        goto fail;
    snprintf(c->name, sizeof c->name, "OpenCL %s%s", c->cl.device_name,
             c->passes ? ", pass by pass" : "");
    if (cl_upload(c, s) != 0) {
        snprintf(err, err_size, "OpenCL backend: uploading the cloth failed");
        goto fail;
    }
    *state = c;
    return 0;
fail:
    cl_destroy(c);
    return -SIM_ERR_BACKEND;
}

#define ARG(k, i, v) clSetKernelArg((k), (i), sizeof(v), &(v))

/* Where the attached vertices start and end this frame (attachment_targets in solver_c.c). */
static cl_int attachments(cl_state *c, const sim_cloth *k)
{
    if (k->num_attachments == 0)
        return CL_SUCCESS;
    cl_kernel a = c->k_attach;
    cl_int st = ARG(a, 0, c->x);
    st |= ARG(a, 1, c->attach);
    st |= ARG(a, 2, k->num_attachments);
    st |= ARG(a, 3, c->g.v);
    st |= ARG(a, 4, c->g.tris);
    st |= ARG(a, 5, c->att_from);
    st |= ARG(a, 6, c->att_to);
    if (st != CL_SUCCESS)
        return CL_INVALID_KERNEL_ARGS;
    size_t global = (size_t)k->num_attachments;
    return clEnqueueNDRangeKernel(c->cl.queue, a, 1, NULL, &global, NULL, 0, NULL, NULL);
}

/* The moving frame of this body frame (sim/follow.c), on the device and on the host copy (which
   sim_step_travel2 reads): the same bits. */
static cl_int follow(cl_state *c, struct sim *s)
{
    sim_cloth *k = &s->cloth;
    if (!s->follow_on)
        return CL_SUCCESS;
    sim_follow(k->x, k->x_prev, 0, k->nv, s->follow_m);
    const float *m = s->follow_m;
    cl_float4 r[3];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 4; b++)
            r[a].s[b] = m[4 * a + b];
    cl_kernel f = c->k_follow;
    cl_int st = ARG(f, 0, c->x);
    st |= ARG(f, 1, c->x_prev);
    st |= ARG(f, 2, k->nv);
    st |= ARG(f, 3, r[0]);
    st |= ARG(f, 4, r[1]);
    st |= ARG(f, 5, r[2]);
    if (st != CL_SUCCESS)
        return CL_INVALID_KERNEL_ARGS;
    size_t global = (size_t)k->nv;
    return clEnqueueNDRangeKernel(c->cl.queue, f, 1, NULL, &global, NULL, 0, NULL, NULL);
}

/* The frame's settings as both backends read them (sim_solver_params_fill), with whether the
   cloth moves fast and the body's leaves. */
static void frame_params(const cl_state *c, const struct sim *s, int iters, sim_solver_params *p)
{
    const sim_cloth *k = &s->cloth;
    sim_solver_params_fill(s, iters, p);
    /* fast as stage_contacts (solver_c.c) decides it, on the host copy, which matches the device:
       feature points move x and x_prev together, so they do not change the travel */
    p->fast = sim_frame_fast(sim_step_travel2(k, 0, k->nv), iters);
    p->nleaves = c->g.nt;
}

/* The frame's iterations: the settings (sim_solver_params_fill, as the C backend reads them) by
   value, then the buffers in sim_iterations_tryon's order (kernels/springs.cl). */
static cl_int iterations(cl_state *c, const struct sim *s, int iters)
{
    sim_solver_params p;
    frame_params(c, s, iters, &p);
    const cl_mem bufs[] = {c->x,
                           c->x_prev,
                           c->ends,
                           c->rest,
                           c->kind,
                           c->color_start,
                           c->anchor,
                           c->tlen,
                           c->g.child,
                           c->g.order,
                           c->g.lo,
                           c->g.hi,
                           c->g.v,
                           c->g.tris,
                           c->g.n,
                           c->g.nbr,
                           c->g.vt_start,
                           c->g.vt_list,
                           c->g.contact,
                           c->attach,
                           c->att_from,
                           c->att_to,
                           c->hier_level_start,
                           c->hier_vertex,
                           c->hier_parent_start,
                           c->hier_parent,
                           c->hier_rest,
                           c->settle,
                           c->adj_start,
                           c->adj_spring,
                           c->level,
                           c->front,
                           c->x_seen};
    cl_kernel it = c->k_iter;
    cl_int st = clSetKernelArg(it, 0, sizeof p, &p);
    for (cl_uint i = 0; i < sizeof bufs / sizeof bufs[0]; i++)
        st |= clSetKernelArg(it, i + 1, sizeof bufs[i], &bufs[i]);
    if (st != CL_SUCCESS)
        return CL_INVALID_KERNEL_ARGS;
    size_t global = c->group, local = c->group;
    return clEnqueueNDRangeKernel(c->cl.queue, it, 1, NULL, &global, &local, 0, NULL, NULL);
}

/* Sets kernel k's arguments from first on to the n buffers in b. */
static cl_int buffer_args(cl_kernel k, cl_uint first, const cl_mem *b, cl_uint n)
{
    cl_int st = CL_SUCCESS;
    for (cl_uint i = 0; i < n; i++)
        st |= clSetKernelArg(k, first + i, sizeof b[i], &b[i]);
    return st;
}

/* The pass kernels' arguments for this frame: the settings, then the buffers (kernels/springs.cl,
   sim_pass_*); the scalars after the settings are set per launch. */
static cl_int pass_args(cl_state *c, const sim_solver_params *p)
{
    cl_kernel *k = c->k_pass;
    const cl_mem step[] = {c->x, c->x_prev, c->attach, c->att_from, c->att_to, c->x_seen};
    const cl_mem springs[] = {c->x, c->ends, c->rest, c->kind};
    const cl_mem vertices[] = {c->x,         c->x_prev,     c->anchor,    c->tlen,
                               c->g.contact, c->g.v,        c->g.tris,    c->g.n,
                               c->g.nbr,     c->g.vt_start, c->g.vt_list, c->g.child,
                               c->g.order,   c->g.lo,       c->g.hi,      c->x_seen};
    const cl_mem hierarchy[] = {c->x,           c->x_prev,   c->hier_vertex, c->hier_parent_start,
                                c->hier_parent, c->hier_rest};
    const cl_mem support[] = {c->x,         c->x_prev,     c->ends,   c->rest,
                              c->g.contact, c->g.v,        c->g.tris, c->g.n,
                              c->adj_start, c->adj_spring, c->level,  c->front};
    const cl_mem settle[] = {c->x, c->ends, c->rest, c->kind, c->settle};
    const cl_mem reopen[] = {c->x, c->x_prev};
#define N(a) (cl_uint)(sizeof a / sizeof a[0])
    cl_int st = CL_SUCCESS;
    for (int i = 0; i < PASS_KINDS; i++)
        if (i != PASS_SETTLE_TEST)
            st |= clSetKernelArg(k[i], 0, sizeof *p, p);
    st |= buffer_args(k[PASS_STEP], 2, step, N(step));
    st |= buffer_args(k[PASS_SPRINGS], 3, springs, N(springs));
    st |= buffer_args(k[PASS_STRAIN], 3, springs, N(springs));
    st |= buffer_args(k[PASS_VERTICES], 3, vertices, N(vertices));
    st |= buffer_args(k[PASS_HIERARCHY], 3, hierarchy, N(hierarchy));
    st |= buffer_args(k[PASS_SUPPORT], 1, support, N(support));
    st |= buffer_args(k[PASS_SETTLE_TEST], 1, settle, N(settle));
    st |= buffer_args(k[PASS_REOPEN], 1, reopen, N(reopen));
#undef N
    return st;
}

/* Pass kernel kind over n items: groups of PASS_GROUP, the last one partly idle. */
#define PASS_GROUP 128
static cl_int launch(cl_state *c, pass_kind kind, int n)
{
    if (n <= 0)
        return CL_SUCCESS;
    size_t local = PASS_GROUP, global = ((size_t)n + PASS_GROUP - 1) / PASS_GROUP * PASS_GROUP;
    return clEnqueueNDRangeKernel(c->cl.queue, c->k_pass[kind], 1, NULL, &global, &local, 0, NULL,
                                  NULL);
}

/* Pass kernel kind over items [begin, end) (a colour of springs, a level of the hierarchy). */
static cl_int launch_range(cl_state *c, pass_kind kind, int begin, int end)
{
    cl_int st = ARG(c->k_pass[kind], 1, begin);
    st |= ARG(c->k_pass[kind], 2, end);
    return st != CL_SUCCESS ? st : launch(c, kind, end - begin);
}

/* Where a frame walked pass by pass stands. */
typedef struct pass_walk {
    const sim_solver_params *p;
    int nstretch; /* springs [0, nstretch) hold the stretch ones */
    float prev;   /* the settle test before */
    int stop;     /* the settle rounds are over */
    cl_int settled;
} pass_walk;

/* SIM_STAGE_SETTLE_TEST: the largest stretch strain on the device, read back to decide. */
static cl_int pass_settle_test(cl_state *c, pass_walk *w, int rep)
{
    static const cl_int zero = 0;
    cl_int bits = 0;
    cl_int st = clEnqueueWriteBuffer(c->cl.queue, c->settle, CL_FALSE, 0, sizeof zero, &zero, 0,
                                     NULL, NULL);
    st |= ARG(c->k_pass[PASS_SETTLE_TEST], 0, w->nstretch);
    if (st == CL_SUCCESS)
        st = launch(c, PASS_SETTLE_TEST, w->nstretch);
    if (st == CL_SUCCESS)
        st = clEnqueueReadBuffer(c->cl.queue, c->settle, CL_TRUE, 0, sizeof bits, &bits, 0, NULL,
                                 NULL);
    float m;
    memcpy(&m, &bits, sizeof m);
    if (sim_settle_stop(m, w->prev, rep == 0, w->p->fast, w->p))
        w->stop = 1;
    w->prev = m;
    return st;
}

/* One stage of block b's repetition rep, as sim_iterations_tryon runs it in one work-group. */
static cl_int pass_stage(cl_state *c, const sim_cloth *k, pass_walk *w, int stage, int b, int rep)
{
    const sim_solver_params *p = w->p;
    cl_kernel *kp = c->k_pass;
    cl_int st = CL_SUCCESS;
    switch (stage) {
    case SIM_STAGE_STEP:
        st = ARG(kp[PASS_STEP], 1, rep);
        return st != CL_SUCCESS ? st : launch(c, PASS_STEP, p->nv > p->natt ? p->nv : p->natt);
    case SIM_STAGE_SPRINGS:
        for (int col = 0; col < k->num_colors && st == CL_SUCCESS; col++)
            st = launch_range(c, PASS_SPRINGS, k->color_start[col], k->color_start[col + 1]);
        return st;
    case SIM_STAGE_SWEEP:
        for (int col = 0; col < k->num_stretch_colors && st == CL_SUCCESS; col++)
            st = launch_range(c, PASS_STRAIN, k->color_start[col], k->color_start[col + 1]);
        return st;
    case SIM_STAGE_VERTICES: {
        cl_int close = sim_vertices_close(b), open = sim_vertices_open(b, rep, p);
        st = ARG(kp[PASS_VERTICES], 1, close);
        st |= ARG(kp[PASS_VERTICES], 2, open);
        if (b == SIM_BLOCK_SETTLE)
            w->settled = rep + 1;
        return st != CL_SUCCESS ? st : launch(c, PASS_VERTICES, p->nv);
    }
    case SIM_STAGE_HIERARCHY:
        for (int l = 0; l < k->hier_levels && st == CL_SUCCESS; l++)
            st =
                launch_range(c, PASS_HIERARCHY, k->hier_level_start[l], k->hier_level_start[l + 1]);
        return st;
    case SIM_STAGE_SUPPORT:
        return clEnqueueNDRangeKernel(c->cl.queue, kp[PASS_SUPPORT], 1, NULL, &c->support_group,
                                      &c->support_group, 0, NULL, NULL);
    case SIM_STAGE_SETTLE_TEST:
        return pass_settle_test(c, w, rep);
    case SIM_STAGE_REOPEN:
        return launch(c, PASS_REOPEN, p->nv);
    default: /* START and CONTACTS: the commands before (cl_frame) */
        return CL_SUCCESS;
    }
}

/* The frame's iterations pass by pass (a GPU): the host walks the frame's stages
   (kernels/solver_params.h) as sim_iterations_tryon does in one work-group, a launch per pass;
   the settle test is read back to decide. The settle rounds run into *settled. */
static cl_int frame_passes(cl_state *c, const struct sim *s, int iters, cl_int *settled)
{
    sim_solver_params p;
    frame_params(c, s, iters, &p);
    pass_walk w = {.p = &p, .nstretch = s->cloth.color_start[s->cloth.num_stretch_colors]};
    cl_int st = pass_args(c, &p);
    for (int b = 0; b < SIM_BLOCKS && !w.stop && st == CL_SUCCESS; b++)
        for (int rep = 0; rep < sim_block_repeats(b, &p) && !w.stop && st == CL_SUCCESS; rep++)
            for (int i = sim_block_start[b];
                 i < sim_block_start[b + 1] && !w.stop && st == CL_SUCCESS; i++)
                if (sim_stage_runs(sim_frame_stages[i], b, rep, &p))
                    st = pass_stage(c, &s->cloth, &w, sim_frame_stages[i], b, rep);
    *settled = w.settled;
    return st;
}

static int cl_frame(void *state, struct sim *s, int iters, sim_frame_stats *st)
{
    cl_state *c = state;
    sim_cloth *k = &s->cloth;
    const sim_collider *col = s->collider;
    char err[256] = "an OpenCL command failed";
    if (s->desc.solver != SIM_SOLVER_TRYON) {
        fprintf(stderr, "OpenCL backend: the seed solver runs on the C backend only\n");
        return -SIM_ERR_BACKEND;
    }
    double t0 = now_ms();
    /* once per body frame: a retry of the frame (sim.c) finds it there, frame k-1 beside it */
    if (c->body_stored != s->body.stored) {
        if (sim_cl_collide_set_body(&c->g, col, err, sizeof err) != 0)
            goto fail;
        c->body_stored = s->body.stored;
    }
    st->feature_points_moved = 0;
    if (follow(c, s) != CL_SUCCESS)
        goto fail;
    int fp = s->body.have_prev && c->g.have_prev;
    if (fp && sim_cl_collide_feature_points(&c->g, c->x, c->x_prev, 0, k->nv, col->d.thickness_m,
                                            col->d.carry_coulomb ? col->d.friction : -1.0f) != 0)
        goto fail;
    if (fp && clEnqueueReadBuffer(c->cl.queue, c->g.moved, CL_FALSE, 0, (size_t)k->nv * 4, c->moved,
                                  0, NULL, NULL) != CL_SUCCESS)
        goto fail;
    if (attachments(c, k) != CL_SUCCESS)
        goto fail;
    if (clFinish(c->cl.queue) != CL_SUCCESS)
        goto fail;
    double t1 = now_ms();
    for (int i = 0; fp && i < k->nv; i++)
        st->feature_points_moved += c->moved[i];
    st->ms_feature_points = (float)(t1 - t0);
    if (sim_cl_collide_find_contacts(&c->g, c->x, 0, k->nv, col->d.thickness_m + col->d.reach_m))
        goto fail;
    /* the host metric starts from these contacts and their clearance (sim/penetration.c) */
    size_t nbytes = (size_t)k->nv * 16;
    if (clEnqueueReadBuffer(c->cl.queue, c->g.contact, CL_FALSE, 0, (size_t)k->nv * 4, c->contact,
                            0, NULL, NULL) != CL_SUCCESS ||
        clEnqueueReadBuffer(c->cl.queue, c->x, CL_TRUE, 0, nbytes, c->x_search, 0, NULL, NULL) !=
            CL_SUCCESS)
        goto fail;
    sim_collider_adopt_contacts(s->collider, (const float(*)[4])c->x_search, c->contact, 0, k->nv);
    double t2 = now_ms();
    st->ms_contacts = (float)(t2 - t1);
    size_t bytes = (size_t)k->nv * 16;
    cl_int settled = 0;
    if ((c->passes ? frame_passes(c, s, iters, &settled) : iterations(c, s, iters)) != CL_SUCCESS ||
        (!c->passes && clEnqueueReadBuffer(c->cl.queue, c->settle, CL_FALSE, 0, sizeof settled,
                                           &settled, 0, NULL, NULL)) ||
        clEnqueueReadBuffer(c->cl.queue, c->x, CL_FALSE, 0, bytes, k->x, 0, NULL, NULL) ||
        clEnqueueReadBuffer(c->cl.queue, c->x_prev, CL_TRUE, 0, bytes, k->x_prev, 0, NULL, NULL))
        goto fail;
    st->ms_iterations = (float)(now_ms() - t2);
    st->settle_rounds = settled;
    return 0;
fail:
    fprintf(stderr, "OpenCL backend: frame failed on %s: %s\n", c->cl.device_name, err);
    return -SIM_ERR_BACKEND;
}

static const char *cl_device_name(const void *state)
{
    return ((const cl_state *)state)->name;
}

const sim_backend_ops sim_backend_opencl = {
    .name = "opencl",
    .create = cl_create,
    .destroy = cl_destroy,
    .frame = cl_frame,
    .upload = cl_upload,
    .device_name = cl_device_name,
};

int sim_opencl_device(char *name, size_t name_size)
{
    sim_cl cl;
    char err[256] = "";
    int rc = sim_cl_probe(&cl, err, sizeof err);
    if (name && name_size > 0)
        snprintf(name, name_size, "%s", rc == 0 ? cl.device_name : err);
    return rc != 0 ? -1 : cl.is_gpu ? 1 : 0;
}
