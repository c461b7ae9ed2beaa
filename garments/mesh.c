/* Panel meshing: outline samples, the seed's rectangular grid clipped inside, Delaunay; then
 * the panels assembled into one mesh with their edge vertex lists and seam joints. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

#define GAR_DEFAULT_SPACING_M 0.02f
/* Spacing limits: below 2 mm a panel has millions of points, above 0.5 m it is no cloth. */
#define GAR_MIN_SPACING_M     0.002f
#define GAR_MAX_SPACING_M     0.5f
#define GAR_MAX_MESH_VERTICES 200000
/* Points a panel may have: the Delaunay step is O(n^2) (about a second at this many), and a
 * pattern is untrusted: a 100 m panel must be refused, not meshed for hours. 20,000 points is
 * a 6 m^2 panel at 2 cm. */
#define GAR_MAX_PANEL_POINTS 20000

/* Samples per edge: about one per spacing; stitched edges of equal length share a count. */
static int *edge_counts(const gar_pattern *p, const int *first, int ne, float h)
{
    int *n = malloc((size_t)ne * sizeof *n);
    float *len = malloc((size_t)ne * sizeof *len);
    if (!n || !len) {
        free(n), free(len);
        return NULL;
    }
    for (int pi = 0; pi < p->num_panels; pi++)
        for (int e = 0; e < p->panels[pi].num_edges; e++) {
            float l = gar_edge_length(&p->panels[pi], &p->panels[pi].edges[e]);
            len[first[pi] + e] = l;
            n[first[pi] + e] = l / h > 1 ? (int)ceilf(l / h) : 1;
        }
    for (int s = 0; s < p->num_stitches; s++) {
        int a = first[p->stitches[s].panel[0]] + p->stitches[s].edge[0];
        int b = first[p->stitches[s].panel[1]] + p->stitches[s].edge[1];
        if (fabsf(len[a] - len[b]) <= GAR_SEAM_EQUAL_FRACTION * fmaxf(len[a], len[b]))
            n[a] = n[b] = n[a] > n[b] ? n[a] : n[b];
    }
    free(len);
    return n;
}

typedef struct panel_mesh {
    int nb, ni;  /* boundary and interior points */
    double *pts; /* 2 (nb + ni + 3) */
    int32_t *tris;
    int nt;
} panel_mesh;

/* Interior lattice points: inside the outline, clear of it by GAR_GRID_CLEARANCE spacings. */
static int grid_points(const float *poly, int nb, float h, double **pts, int *ni)
{
    float lo[2] = {poly[0], poly[1]}, hi[2] = {poly[0], poly[1]};
    for (int i = 1; i < nb; i++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fminf(lo[k], poly[2 * i + k]);
            hi[k] = fmaxf(hi[k], poly[2 * i + k]);
        }
    /* Rows of the lattice are offset by half a spacing (a triangular lattice): no four of its
     * points are cocircular, which keeps the Delaunay step away from its degenerate case. */
    double dy = h * 0.8660254037844386;
    int cols = (int)((hi[0] - lo[0]) / h) + 2, rows = (int)((hi[1] - lo[1]) / dy) + 1;
    if ((double)cols * rows > GAR_MAX_PANEL_POINTS)
        return -GAR_ERR_TOO_LARGE;
    double *p = malloc(((size_t)nb + (size_t)cols * rows + 3) * 2 * sizeof *p);
    if (!p)
        return -GAR_ERR_NO_MEMORY;
    for (int i = 0; i < nb; i++)
        p[2 * i] = poly[2 * i], p[2 * i + 1] = poly[2 * i + 1];
    int n = nb;
    /* The grid is centred on the bounding box so a symmetric panel meshes symmetrically. */
    double x0 = (lo[0] + hi[0]) / 2 - (cols - 1) * h / 2.0;
    double y0 = (lo[1] + hi[1]) / 2 - (rows - 1) * dy / 2.0;
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols; c++) {
            double x = x0 + (c - 0.5 * (r & 1)) * h, y = y0 + r * dy;
            if (gar_point_in_polygon(poly, nb, x, y) &&
                gar_point_polygon_distance(poly, nb, x, y) >= GAR_GRID_CLEARANCE * h)
                p[2 * n] = x, p[2 * n + 1] = y, n++;
        }
    *pts = p;
    *ni = n - nb;
    return 0;
}

/* Keeps triangles whose centroid is inside the outline; then every outline segment must be a
 * triangle edge, or the outline was not kept. */
static int clip_and_check(const gar_panel *pn, const float *poly, panel_mesh *pm, const int *ecount,
                          gar_reject *why)
{
    int m = 0;
    for (int k = 0; k < pm->nt; k++) {
        const int32_t *t = pm->tris + 3 * k;
        double cx = 0, cy = 0;
        for (int e = 0; e < 3; e++)
            cx += pm->pts[2 * t[e]] / 3, cy += pm->pts[2 * t[e] + 1] / 3;
        if (gar_point_in_polygon(poly, pm->nb, cx, cy))
            memmove(pm->tris + 3 * m++, t, 3 * sizeof *t);
    }
    pm->nt = m;
    for (int i = 0, edge = 0, left = ecount[0]; i < pm->nb; i++, left--) {
        while (left <= 0)
            left = ecount[++edge];
        int a = i, b = (i + 1) % pm->nb, found = 0;
        for (int k = 0; k < pm->nt && !found; k++)
            for (int e = 0; e < 3; e++)
                if (pm->tris[3 * k + e] == a && pm->tris[3 * k + (e + 1) % 3] == b)
                    found = 1;
        if (!found)
            return gar_refuse(why, GAR_ERR_MESH,
                              "panel '%s': edge %d: outline segment %d lost in triangulation "
                              "(a corner sharper than the spacing allows; try a finer spacing)",
                              pn->name, edge, i);
    }
    return 0;
}

static int mesh_panel(const gar_panel *pn, const int *ecount, float h, panel_mesh *pm,
                      gar_reject *why)
{
    int nb = 0;
    for (int e = 0; e < pn->num_edges; e++)
        nb += ecount[e];
    if (nb > GAR_MAX_PANEL_POINTS)
        return gar_refuse(why, GAR_ERR_TOO_LARGE, "panel '%s': %d outline samples (at most %d)",
                          pn->name, nb, GAR_MAX_PANEL_POINTS);
    float *poly = malloc(((size_t)nb + 1) * 2 * sizeof *poly);
    if (!poly)
        return gar_refuse(why, GAR_ERR_NO_MEMORY, "panel '%s'", pn->name);
    for (int e = 0, at = 0; e < pn->num_edges; at += ecount[e], e++)
        gar_edge_sample(pn, &pn->edges[e], ecount[e], poly + 2 * at); /* end = next start */
    pm->nb = nb;
    int rc = grid_points(poly, nb, h, &pm->pts, &pm->ni);
    if (rc)
        rc = gar_refuse(why, -rc, "panel '%s': more than %d points at %.4g m spacing", pn->name,
                        GAR_MAX_PANEL_POINTS, h);
    if (!rc && gar_delaunay(pm->pts, nb + pm->ni, &pm->tris, &pm->nt))
        rc = gar_refuse(why, GAR_ERR_NO_MEMORY, "panel '%s': triangulation", pn->name);
    if (!rc)
        rc = clip_and_check(pn, poly, pm, ecount, why);
    free(poly);
    return rc;
}

static int alloc_mesh(gar_mesh *m, int nv, int nt, int np, int ne, int nev)
{
    m->num_vertices = nv;
    m->num_triangles = nt;
    m->num_panels = np;
    m->num_edges = ne;
    m->uv_m = malloc((size_t)nv * 2 * sizeof *m->uv_m);
    m->xyz = malloc((size_t)nv * 3 * sizeof *m->xyz);
    m->panel_of = malloc((size_t)nv * sizeof *m->panel_of);
    m->triangles = malloc((size_t)nt * 3 * sizeof *m->triangles);
    m->panel_first_edge = malloc((size_t)np * sizeof *m->panel_first_edge);
    m->edge_offset = malloc(((size_t)ne + 1) * sizeof *m->edge_offset);
    m->edge_vertices = malloc((size_t)nev * sizeof *m->edge_vertices);
    return m->uv_m && m->xyz && m->panel_of && m->triangles && m->panel_first_edge &&
                   m->edge_offset && m->edge_vertices
               ? 0
               : -GAR_ERR_NO_MEMORY;
}

/* Copies each panel's points, triangles and edge vertex lists into the one mesh. */
static void assemble(const gar_pattern *p, const panel_mesh *pm, const int *ecount, gar_mesh *m)
{
    int v0 = 0, t0 = 0, ev = 0, fe = 0;
    for (int pi = 0; pi < p->num_panels; pi++) {
        const gar_panel *pn = &p->panels[pi];
        int n = pm[pi].nb + pm[pi].ni;
        for (int i = 0; i < n; i++) {
            float uv[2] = {(float)pm[pi].pts[2 * i], (float)pm[pi].pts[2 * i + 1]};
            memcpy(m->uv_m + 2 * (v0 + i), uv, sizeof uv);
            gar_panel_to_world(pn, uv, m->xyz + 3 * (v0 + i));
            m->panel_of[v0 + i] = pi;
        }
        for (int k = 0; k < 3 * pm[pi].nt; k++)
            m->triangles[3 * t0 + k] = v0 + pm[pi].tris[k];
        m->panel_first_edge[pi] = fe;
        for (int e = 0, at = 0; e < pn->num_edges; at += ecount[fe + e], e++) {
            m->edge_offset[fe + e] = ev;
            for (int j = 0; j <= ecount[fe + e]; j++)
                m->edge_vertices[ev++] = v0 + (at + j) % pm[pi].nb;
        }
        fe += pn->num_edges;
        v0 += n;
        t0 += pm[pi].nt;
    }
    m->edge_offset[fe] = ev;
}

int gar_mesh_build(const gar_pattern *p, const gar_mesh_desc *desc, gar_mesh *m, gar_reject *why)
{
    if (!m)
        return gar_refuse(why, GAR_ERR_ARG, "no output mesh");
    memset(m, 0, sizeof *m);
    if (!p || p->num_panels < 1)
        return gar_refuse(why, GAR_ERR_ARG, "no pattern");
    float h = desc && desc->spacing_m != 0 ? desc->spacing_m : GAR_DEFAULT_SPACING_M;
    if (!(h >= GAR_MIN_SPACING_M && h <= GAR_MAX_SPACING_M))
        return gar_refuse(why, GAR_ERR_RANGE, "spacing %g m outside [%g, %g]", h, GAR_MIN_SPACING_M,
                          GAR_MAX_SPACING_M);
    int first[GAR_MAX_PANELS], ne = 0;
    for (int pi = 0; pi < p->num_panels; pi++)
        first[pi] = ne, ne += p->panels[pi].num_edges;
    int *ecount = edge_counts(p, first, ne, h);
    panel_mesh *pm = calloc((size_t)p->num_panels, sizeof *pm);
    int rc = ecount && pm ? 0 : gar_refuse(why, GAR_ERR_NO_MEMORY, "mesh");
    int nv = 0, nt = 0, nev = 0;
    for (int pi = 0; pi < p->num_panels && !rc; pi++) {
        rc = mesh_panel(&p->panels[pi], ecount + first[pi], h, &pm[pi], why);
        nv += pm[pi].nb + pm[pi].ni;
        nt += pm[pi].nt;
        if (!rc && nv > GAR_MAX_MESH_VERTICES)
            rc = gar_refuse(why, GAR_ERR_TOO_LARGE, "%d vertices at %.4g m spacing", nv, h);
    }
    for (int e = 0; e < ne && !rc; e++)
        nev += ecount[e] + 1;
    if (!rc && alloc_mesh(m, nv, nt, p->num_panels, ne, nev))
        rc = gar_refuse(why, GAR_ERR_NO_MEMORY, "mesh of %d vertices", nv);
    if (!rc) {
        assemble(p, pm, ecount, m);
        rc = gar_seams_build(p, m, why);
    }
    for (int pi = 0; pm && pi < p->num_panels; pi++)
        free(pm[pi].pts), free(pm[pi].tris);
    free(pm);
    free(ecount);
    if (rc)
        gar_mesh_free(m);
    return rc;
}

void gar_mesh_free(gar_mesh *m)
{
    if (!m)
        return;
    free(m->uv_m), free(m->xyz), free(m->panel_of), free(m->triangles);
    free(m->panel_first_edge), free(m->edge_offset), free(m->edge_vertices), free(m->joints);
    memset(m, 0, sizeof *m);
}
