/* Garments: the drape sheet, a shirt generated around a body mesh, and their validation. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"

/* A triangle under a square micrometre is no cloth: 1e-12 m^2. */
#define GARMENT_MIN_AREA_M2 1e-12f

void sim_garment_free(sim_garment *g)
{
    if (!g)
        return;
    free(g->xyz);
    free(g->mass_kg);
    free(g->triangles);
    free(g->attachments);
    memset(g, 0, sizeof *g);
}

int sim_garment_alloc(sim_garment *g, int nv, int nt, int na)
{
    memset(g, 0, sizeof *g);
    g->num_vertices = nv;
    g->num_triangles = nt;
    g->num_attachments = na;
    g->xyz = calloc((size_t)nv * 3, sizeof *g->xyz);
    g->triangles = calloc((size_t)nt * 3, sizeof *g->triangles);
    if (na > 0)
        g->attachments = calloc((size_t)na, sizeof *g->attachments);
    if (!g->xyz || !g->triangles || (na > 0 && !g->attachments)) {
        sim_garment_free(g);
        return -SIM_ERR_NO_MEMORY;
    }
    return 0;
}

/* Two triangles per grid quad, counter-clockwise seen from +y for a sheet in the x-z plane with
 * columns along +x and rows along +z. wrap: the last column joins the first (a tube). */
static void grid_triangles(int32_t *t, int w, int h, int wrap)
{
    int cols = wrap ? w : w - 1, n = 0;
    for (int i = 0; i + 1 < h; i++) {
        for (int j = 0; j < cols; j++) {
            int j1 = (j + 1) % w;
            int32_t a = i * w + j, b = i * w + j1, c = (i + 1) * w + j, d = (i + 1) * w + j1;
            t[n++] = a, t[n++] = c, t[n++] = b;
            t[n++] = b, t[n++] = c, t[n++] = d;
        }
    }
}

void sim_garment_tube_triangles(int32_t *t, int cols, int rows)
{
    grid_triangles(t, cols, rows, 1);
}

int sim_garment_drape(int n_vertices, float side_m, float y_m, sim_garment *out)
{
    int n = (int)lroundf(sqrtf((float)(n_vertices > 4 ? n_vertices : 4)));
    if (!out || !(side_m > 0.0f) || !isfinite(y_m) || n * n > GARMENT_MAX_VERTICES)
        return -SIM_ERR_PARAM;
    int r = sim_garment_alloc(out, n * n, 2 * (n - 1) * (n - 1), 0);
    if (r < 0)
        return r;
    snprintf(out->id, sizeof out->id, "drape-%dx%d", n, n);
    float h = side_m / (float)(n - 1);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) {
            float *p = &out->xyz[(i * n + j) * 3];
            p[0] = -0.5f * side_m + h * (float)j;
            p[1] = y_m;
            p[2] = -0.5f * side_m + h * (float)i;
        }
    }
    grid_triangles(out->triangles, n, n, 0);
    out->grid_w = n;
    out->grid_h = n;
    return 0;
}

int sim_garment_validate(const sim_garment *g, int body_nt, sim_reject *why)
{
    if (!g || g->num_vertices <= 0 || g->num_triangles <= 0 || !g->xyz || !g->triangles)
        return sim_reject_set(why, SIM_ERR_EMPTY, "garment: %d vertices, %d triangles",
                              g ? g->num_vertices : 0, g ? g->num_triangles : 0);
    int nv = g->num_vertices, nt = g->num_triangles;
    if (nv > GARMENT_MAX_VERTICES || nt > 2 * GARMENT_MAX_VERTICES)
        return sim_reject_set(why, SIM_ERR_TOO_LARGE, "garment: %d vertices (max %d)", nv,
                              GARMENT_MAX_VERTICES);
    for (int i = 0; i < nv * 3; i++)
        if (!isfinite(g->xyz[i]))
            return sim_reject_set(why, SIM_ERR_NOT_FINITE, "garment vertex %d coordinate %d = %g",
                                  i / 3, i % 3, g->xyz[i]);
    for (int t = 0; t < nt; t++) {
        const int32_t *v = &g->triangles[t * 3];
        for (int k = 0; k < 3; k++)
            if (v[k] < 0 || v[k] >= nv)
                return sim_reject_set(why, SIM_ERR_INDEX,
                                      "garment triangle %d: index %d outside 0..%d", t, v[k],
                                      nv - 1);
        const float *a = &g->xyz[v[0] * 3], *b = &g->xyz[v[1] * 3], *c = &g->xyz[v[2] * 3];
        float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        float cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                       e1[0] * e2[1] - e1[1] * e2[0]};
        float area = 0.5f * sqrtf(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2] || !(area > GARMENT_MIN_AREA_M2))
            return sim_reject_set(why, SIM_ERR_DEGENERATE,
                                  "garment triangle %d (%d %d %d): area %g m^2", t, v[0], v[1],
                                  v[2], area);
    }
    for (int i = 0; g->mass_kg && i < nv; i++)
        if (!(g->mass_kg[i] > 0.0f) || !isfinite(g->mass_kg[i]))
            return sim_reject_set(why, SIM_ERR_MASS, "garment vertex %d mass %g kg", i,
                                  g->mass_kg[i]);
    if (g->grid_w != 0 && (g->grid_w < 2 || g->grid_h < 2 || (int64_t)g->grid_w * g->grid_h != nv))
        return sim_reject_set(why, SIM_ERR_PARAM, "garment grid %d x %d != %d vertices", g->grid_w,
                              g->grid_h, nv);
    if (g->num_attachments < 0 || (g->num_attachments > 0 && !g->attachments))
        return sim_reject_set(why, SIM_ERR_ATTACHMENT, "%d attachments", g->num_attachments);
    for (int a = 0; a < g->num_attachments; a++) {
        const sim_attachment *at = &g->attachments[a];
        int bad_tri = at->body_triangle < 0 || (body_nt > 0 && at->body_triangle >= body_nt);
        if (at->vertex < 0 || at->vertex >= nv || bad_tri || !isfinite(at->bary[0]) ||
            !isfinite(at->bary[1]) || !isfinite(at->bary[2]) || !isfinite(at->offset_m))
            return sim_reject_set(why, SIM_ERR_ATTACHMENT,
                                  "attachment %d: vertex %d, body triangle %d", a, at->vertex,
                                  at->body_triangle);
    }
    return 0;
}
