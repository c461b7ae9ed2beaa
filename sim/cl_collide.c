/* Host side of the device collider: buffers, uploads, kernel launches. Every cl* call checked;
 * creation unwinds through sim_cl_collide_destroy, which releases whatever exists. */
#include <stdio.h>
#include <string.h>

#include "cl_collide.h"

static cl_mem buffer(const sim_cl *cl, size_t bytes, cl_int *st)
{
    if (*st != CL_SUCCESS)
        return NULL;
    return clCreateBuffer(cl->context, CL_MEM_READ_WRITE, bytes ? bytes : 16, NULL, st);
}

int sim_cl_collide_create(sim_cl_collide *g, const sim_cl *cl, int max_nv, int max_nt,
                          int max_cloth, char *err, size_t err_size)
{
    memset(g, 0, sizeof *g);
    if (!cl || !cl->program || max_nv < 3 || max_nt < 1 || max_cloth < 0)
        return -SIM_CL_EARG;
    g->cl = cl;
    g->max_nv = max_nv, g->max_nt = max_nt, g->max_cloth = max_cloth;
    size_t nv = (size_t)max_nv, nt = (size_t)max_nt, nodes = 2 * nt - 1, nc = (size_t)max_cloth;
    cl_int st = CL_SUCCESS;
    g->v = buffer(cl, nv * 16, &st);
    g->v_prev = buffer(cl, nv * 16, &st);
    g->tris = buffer(cl, nt * 16, &st);
    g->n = buffer(cl, nt * 16, &st);
    g->n_prev = buffer(cl, nt * 16, &st);
    g->nbr = buffer(cl, nt * 16, &st);
    g->vt_start = buffer(cl, (nv + 1) * 4, &st);
    g->vt_list = buffer(cl, 3 * nt * 4, &st);
    g->morton = buffer(cl, nt * 4, &st);
    g->order = buffer(cl, nt * 4, &st);
    g->child = buffer(cl, nt * 8, &st);
    g->parent = buffer(cl, nodes * 4, &st);
    g->lo = buffer(cl, nodes * 16, &st);
    g->hi = buffer(cl, nodes * 16, &st);
    g->slo = buffer(cl, nodes * 16, &st);
    g->shi = buffer(cl, nodes * 16, &st);
    g->counter = buffer(cl, nt * 4, &st);
    g->contact = buffer(cl, nc * 4, &st);
    g->moved = buffer(cl, nc * 4, &st);
    g->sd = buffer(cl, nc * 4, &st);
    if (st != CL_SUCCESS) {
        snprintf(err, err_size, "OpenCL: buffers for %d body vertices, %d triangles: %s", max_nv,
                 max_nt, sim_cl_status_name(st));
        sim_cl_collide_destroy(g);
        return -SIM_CL_ECALL;
    }
    struct {
        cl_kernel *k;
        const char *name;
    } ks[] = {{&g->k_morton, "sim_bvh_morton"},   {&g->k_nodes, "sim_bvh_build_nodes"},
              {&g->k_refit, "sim_bvh_refit"},     {&g->k_normals, "sim_face_normals"},
              {&g->k_fp, "sim_feature_points"},   {&g->k_contacts, "sim_find_contacts"},
              {&g->k_resolve, "sim_resolve"},     {&g->k_sd, "sim_signed_distance"},
              {&g->k_track, "sim_track_contacts"}};
    for (size_t i = 0; i < sizeof ks / sizeof ks[0]; i++)
        if (!(*ks[i].k = sim_cl_kernel(cl, ks[i].name, err, err_size))) {
            sim_cl_collide_destroy(g);
            return -SIM_CL_ECALL;
        }
    return 0;
}

void sim_cl_collide_destroy(sim_cl_collide *g)
{
    if (!g)
        return;
    cl_kernel ks[] = {g->k_morton,   g->k_nodes,   g->k_refit, g->k_normals, g->k_fp,
                      g->k_contacts, g->k_resolve, g->k_sd,    g->k_track};
    for (size_t i = 0; i < sizeof ks / sizeof ks[0]; i++)
        if (ks[i])
            clReleaseKernel(ks[i]);
    cl_mem ms[] = {g->v,       g->v_prev, g->tris,    g->n,       g->n_prev, g->nbr, g->vt_start,
                   g->vt_list, g->morton, g->order,   g->child,   g->parent, g->lo,  g->hi,
                   g->slo,     g->shi,    g->counter, g->contact, g->moved,  g->sd};
    for (size_t i = 0; i < sizeof ms / sizeof ms[0]; i++)
        if (ms[i])
            clReleaseMemObject(ms[i]);
    memset(g, 0, sizeof *g);
}

static cl_int write(const sim_cl *cl, cl_mem m, size_t bytes, const void *src)
{
    if (bytes == 0)
        return CL_SUCCESS;
    return clEnqueueWriteBuffer(cl->queue, m, CL_FALSE, 0, bytes, src, 0, NULL, NULL);
}

static cl_int launch(const sim_cl *cl, cl_kernel k, int n)
{
    if (n <= 0)
        return CL_SUCCESS;
    size_t global = (size_t)n;
    return clEnqueueNDRangeKernel(cl->queue, k, 1, NULL, &global, NULL, 0, NULL, NULL);
}

#define ARG(k, i, v) clSetKernelArg((k), (i), sizeof(v), &(v))

static cl_int refit(sim_cl_collide *g, float pad)
{
    cl_kernel k = g->k_refit;
    cl_int st = ARG(k, 0, g->v_prev);
    st |= ARG(k, 1, g->v);
    st |= ARG(k, 2, g->tris);
    st |= ARG(k, 3, g->order);
    st |= ARG(k, 4, g->child);
    st |= ARG(k, 5, g->parent);
    st |= ARG(k, 6, g->nt);
    st |= ARG(k, 7, pad);
    st |= ARG(k, 8, g->lo);
    st |= ARG(k, 9, g->hi);
    st |= ARG(k, 10, g->slo);
    st |= ARG(k, 11, g->shi);
    st |= ARG(k, 12, g->counter);
    if (st != CL_SUCCESS)
        return CL_INVALID_KERNEL_ARGS;
    return launch(g->cl, k, g->nt);
}

static cl_int normals(sim_cl_collide *g)
{
    cl_kernel k = g->k_normals;
    cl_int st = ARG(k, 0, g->v);
    st |= ARG(k, 1, g->tris);
    st |= ARG(k, 2, g->nt);
    st |= ARG(k, 3, g->n);
    if (st != CL_SUCCESS)
        return CL_INVALID_KERNEL_ARGS;
    return launch(g->cl, k, g->nt);
}

static int upload_topology(sim_cl_collide *g, const sim_collider *c, char *err, size_t err_size)
{
    const sim_cl *cl = g->cl;
    size_t nv = (size_t)c->nv, nt = (size_t)c->nt;
    int rc = 0;
    static const cl_uint zero = 0;
    SIM_CL_CHECK(write(cl, g->tris, nt * 16, c->tris), rc, err, err_size, out);
    SIM_CL_CHECK(write(cl, g->nbr, nt * 16, c->nbr), rc, err, err_size, out);
    SIM_CL_CHECK(write(cl, g->vt_start, (nv + 1) * 4, c->vt_start), rc, err, err_size, out);
    SIM_CL_CHECK(write(cl, g->vt_list, 3 * nt * 4, c->vt_list), rc, err, err_size, out);
    SIM_CL_CHECK(write(cl, g->morton, nt * 4, c->bvh.morton), rc, err, err_size, out);
    SIM_CL_CHECK(write(cl, g->order, nt * 4, c->bvh.order), rc, err, err_size, out);
    SIM_CL_CHECK(write(cl, g->child, nt * 8, c->bvh.child), rc, err, err_size, out);
    SIM_CL_CHECK(write(cl, g->parent, (2 * nt - 1) * 4, c->bvh.parent), rc, err, err_size, out);
    SIM_CL_CHECK(
        clEnqueueFillBuffer(cl->queue, g->counter, &zero, sizeof zero, 0, nt * 4, 0, NULL, NULL),
        rc, err, err_size, out);
    SIM_CL_CHECK(write(cl, g->v, nv * 16, c->v), rc, err, err_size, out);
    SIM_CL_CHECK(write(cl, g->v_prev, nv * 16, c->v), rc, err, err_size, out);
out:
    return rc;
}

int sim_cl_collide_set_body(sim_cl_collide *g, const sim_collider *c, char *err, size_t err_size)
{
    int rc = 0;
    if (!g || !c || c->nt < 1 || c->nv > g->max_nv || c->nt > g->max_nt) {
        snprintf(err, err_size, "OpenCL collider: body missing or larger than its buffers");
        return -SIM_CL_EARG;
    }
    int same = c->have_prev && g->nt == c->nt && g->nv == c->nv;
    if (same) {
        cl_mem t = g->v_prev;
        g->v_prev = g->v;
        g->v = t;
        t = g->n_prev;
        g->n_prev = g->n;
        g->n = t;
        SIM_CL_CHECK(write(g->cl, g->v, (size_t)c->nv * 16, c->v), rc, err, err_size, out);
    } else {
        g->nv = c->nv, g->nt = c->nt;
        rc = upload_topology(g, c, err, err_size);
        if (rc != 0)
            return rc;
    }
    SIM_CL_CHECK(normals(g), rc, err, err_size, out);
    if (!same)
        SIM_CL_CHECK(clEnqueueCopyBuffer(g->cl->queue, g->n, g->n_prev, 0, 0, (size_t)c->nt * 16, 0,
                                         NULL, NULL),
                     rc, err, err_size, out);
    SIM_CL_CHECK(refit(g, c->d.thickness_m), rc, err, err_size, out);
    g->have_prev = same;
out:
    return rc;
}

int sim_cl_collide_feature_points(sim_cl_collide *g, cl_mem x, cl_mem x_prev, int begin, int end,
                                  float thickness_m, float coulomb_mu)
{
    if (!g->have_prev || end <= begin)
        return 0;
    cl_kernel k = g->k_fp;
    cl_int st = ARG(k, 0, x);
    st |= ARG(k, 1, x_prev);
    st |= ARG(k, 2, begin);
    st |= ARG(k, 3, end);
    st |= ARG(k, 4, g->v_prev);
    st |= ARG(k, 5, g->v);
    st |= ARG(k, 6, g->tris);
    st |= ARG(k, 7, g->n_prev);
    st |= ARG(k, 8, g->n);
    st |= ARG(k, 9, g->nt);
    st |= ARG(k, 10, g->child);
    st |= ARG(k, 11, g->order);
    st |= ARG(k, 12, g->slo);
    st |= ARG(k, 13, g->shi);
    st |= ARG(k, 14, thickness_m);
    st |= ARG(k, 15, coulomb_mu);
    st |= ARG(k, 16, g->moved);
    if (st != CL_SUCCESS)
        return -SIM_CL_ECALL;
    return launch(g->cl, k, end - begin) == CL_SUCCESS ? 0 : -SIM_CL_ECALL;
}

int sim_cl_collide_find_contacts(sim_cl_collide *g, cl_mem x, int begin, int end, float radius_m)
{
    cl_kernel k = g->k_contacts;
    cl_int st = ARG(k, 0, x);
    st |= ARG(k, 1, begin);
    st |= ARG(k, 2, end);
    st |= ARG(k, 3, g->nt);
    st |= ARG(k, 4, g->child);
    st |= ARG(k, 5, g->order);
    st |= ARG(k, 6, g->lo);
    st |= ARG(k, 7, g->hi);
    st |= ARG(k, 8, g->v);
    st |= ARG(k, 9, g->tris);
    st |= ARG(k, 10, radius_m);
    st |= ARG(k, 11, g->contact);
    if (st != CL_SUCCESS)
        return -SIM_CL_ECALL;
    return launch(g->cl, k, end - begin) == CL_SUCCESS ? 0 : -SIM_CL_ECALL;
}

int sim_cl_collide_track_contacts(sim_cl_collide *g, cl_mem x, int begin, int end, float radius_m)
{
    cl_kernel k = g->k_track;
    cl_int st = ARG(k, 0, x);
    st |= ARG(k, 1, begin);
    st |= ARG(k, 2, end);
    st |= ARG(k, 3, g->nt);
    st |= ARG(k, 4, g->child);
    st |= ARG(k, 5, g->order);
    st |= ARG(k, 6, g->lo);
    st |= ARG(k, 7, g->hi);
    st |= ARG(k, 8, g->v);
    st |= ARG(k, 9, g->tris);
    st |= ARG(k, 10, g->vt_start);
    st |= ARG(k, 11, g->vt_list);
    st |= ARG(k, 12, radius_m);
    st |= ARG(k, 13, g->contact);
    if (st != CL_SUCCESS)
        return -SIM_CL_ECALL;
    return launch(g->cl, k, end - begin) == CL_SUCCESS ? 0 : -SIM_CL_ECALL;
}

int sim_cl_collide_resolve(sim_cl_collide *g, cl_mem x, cl_mem x_prev, int begin, int end,
                           float thickness_m, float friction)
{
    cl_kernel k = g->k_resolve;
    cl_int st = ARG(k, 0, x);
    st |= ARG(k, 1, x_prev);
    st |= ARG(k, 2, begin);
    st |= ARG(k, 3, end);
    st |= ARG(k, 4, g->contact);
    st |= ARG(k, 5, g->v);
    st |= ARG(k, 6, g->tris);
    st |= ARG(k, 7, g->n);
    st |= ARG(k, 8, g->nbr);
    st |= ARG(k, 9, g->vt_start);
    st |= ARG(k, 10, g->vt_list);
    st |= ARG(k, 11, thickness_m);
    st |= ARG(k, 12, friction);
    if (st != CL_SUCCESS)
        return -SIM_CL_ECALL;
    return launch(g->cl, k, end - begin) == CL_SUCCESS ? 0 : -SIM_CL_ECALL;
}

int sim_cl_collide_signed_distance(sim_cl_collide *g, cl_mem x, int n)
{
    cl_kernel k = g->k_sd;
    cl_int st = ARG(k, 0, x);
    st |= ARG(k, 1, n);
    st |= ARG(k, 2, g->nt);
    st |= ARG(k, 3, g->child);
    st |= ARG(k, 4, g->order);
    st |= ARG(k, 5, g->lo);
    st |= ARG(k, 6, g->hi);
    st |= ARG(k, 7, g->v);
    st |= ARG(k, 8, g->tris);
    st |= ARG(k, 9, g->n);
    st |= ARG(k, 10, g->nbr);
    st |= ARG(k, 11, g->vt_start);
    st |= ARG(k, 12, g->vt_list);
    st |= ARG(k, 13, g->sd);
    if (st != CL_SUCCESS)
        return -SIM_CL_ECALL;
    return launch(g->cl, k, n) == CL_SUCCESS ? 0 : -SIM_CL_ECALL;
}
