/* The garment and the body as the renderer draws them: world-space triangles with area-weighted
 * vertex normals; the projection that puts them over the depth camera's picture. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_private.h"

int mirror_cpu_mesh_reserve(mirror_cpu_mesh *m, int nv, int ni)
{
    if (nv > m->v_cap) {
        mirror_vertex *v = realloc(m->v, (size_t)nv * sizeof *v);
        if (!v)
            return -MIRROR_ERR_NO_MEMORY;
        m->v = v;
        m->v_cap = nv;
    }
    if (ni > m->i_cap) {
        uint32_t *i = realloc(m->idx, (size_t)ni * sizeof *i);
        if (!i)
            return -MIRROR_ERR_NO_MEMORY;
        m->idx = i;
        m->i_cap = ni;
    }
    m->nv = m->ni = 0;
    return 0;
}

void mirror_cpu_mesh_free(mirror_cpu_mesh *m)
{
    free(m->v);
    free(m->idx);
    memset(m, 0, sizeof *m);
}

static void normalize3(float *n)
{
    float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (l > 1e-12f) {
        n[0] /= l;
        n[1] /= l;
        n[2] /= l;
    } else {
        n[0] = n[1] = 0.0f;
        n[2] = -1.0f; /* facing the camera */
    }
}

static void cross3(const float *a, const float *b, float *out)
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

int mirror_world_mesh(const mirror_mesh *m, const float rgba[4], int fit_map, mirror_cpu_mesh *out)
{
    /* realloc keeps the frame before's indices: compared as they are written */
    int changed = out->ni != m->nt * 3;
    if (mirror_cpu_mesh_reserve(out, m->nv, m->nt * 3) < 0)
        return -MIRROR_ERR_NO_MEMORY;
    for (int i = 0; i < m->nv; i++) {
        mirror_vertex *p = &out->v[i];
        memcpy(p->pos, &m->xyz[i * 3], 3 * sizeof(float));
        memset(p->normal, 0, sizeof p->normal);
        if (fit_map && m->strain) {
            mirror_fit_colour(m->strain[i], p->rgba);
            p->rgba[3] = rgba[3];
        } else {
            memcpy(p->rgba, rgba, 4 * sizeof(float));
        }
    }
    for (int t = 0; t < m->nt; t++) {
        const int32_t *f = &m->tris[t * 3];
        if (f[0] < 0 || f[1] < 0 || f[2] < 0 || f[0] >= m->nv || f[1] >= m->nv || f[2] >= m->nv)
            return -MIRROR_ERR_MESH;
        const float *a = out->v[f[0]].pos, *b = out->v[f[1]].pos, *c = out->v[f[2]].pos;
        float ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, n[3];
        cross3(ab, ac, n); /* length = twice the area: area-weighted */
        for (int k = 0; k < 3; k++)
            for (int q = 0; q < 3; q++)
                out->v[f[k]].normal[q] += n[q];
        uint32_t *o = &out->idx[t * 3];
        changed |= o[0] != (uint32_t)f[0] || o[1] != (uint32_t)f[1] || o[2] != (uint32_t)f[2];
        o[0] = (uint32_t)f[0];
        o[1] = (uint32_t)f[1];
        o[2] = (uint32_t)f[2];
    }
    for (int i = 0; i < m->nv; i++)
        normalize3(out->v[i].normal);
    out->nv = m->nv;
    out->ni = m->nt * 3;
    out->idx_changed = changed;
    return 0;
}

void mirror_fit_colour(float strain, float *rgb)
{
    float t = strain / MIRROR_FIT_MAP_LIMIT;
    t = t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
    /* green (0) -> yellow (0.5) -> red (1) */
    rgb[0] = t < 0.5f ? 2.0f * t : 1.0f;
    rgb[1] = t < 0.5f ? 0.85f : 0.85f * (2.0f - 2.0f * t);
    rgb[2] = 0.1f;
}

void mirror_picture_fit(const mirror_depth *d, int out_w, int out_h, float *scale, float *offx)
{
    *scale = (float)out_h / (float)d->height;
    *offx = 0.5f * ((float)out_w - *scale * (float)d->width);
}

void mirror_projection(const mirror_depth *d, int out_w, int out_h, float p[16])
{
    const float n = 0.1f, f = 20.0f; /* metres: nearer than any reading, farther than any */
    float s, offx;
    mirror_picture_fit(d, out_w, out_h, &s, &offx);
    memset(p, 0, 16 * sizeof *p);
    /* pixel (u + 0.5) * s + offx of a W-wide picture, then mirrored left-right: x -> -x */
    p[0] = -2.0f * s * d->fx / (float)out_w;
    p[2] = -(2.0f * (s * (d->cx + 0.5f) + offx) / (float)out_w - 1.0f);
    p[5] = -2.0f * s * d->fy / (float)out_h;
    p[6] = 1.0f - 2.0f * s * (d->cy + 0.5f) / (float)out_h;
    p[10] = (f + n) / (f - n);
    p[11] = -2.0f * f * n / (f - n);
    p[14] = 1.0f;
}

void mirror_world_to_camera(const float c[16], float w[16])
{
    memset(w, 0, 16 * sizeof *w);
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++)
            w[r * 4 + k] = c[k * 4 + r]; /* R^T */
        w[r * 4 + 3] = -(c[0 * 4 + r] * c[3] + c[1 * 4 + r] * c[7] + c[2 * 4 + r] * c[11]);
    }
    w[15] = 1.0f;
}

void mirror_mat_mul(const float a[16], const float b[16], float out[16])
{
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            float s = 0.0f;
            for (int k = 0; k < 4; k++)
                s += a[r * 4 + k] * b[k * 4 + c];
            out[r * 4 + c] = s;
        }
}
