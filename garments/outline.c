/* Panel outlines: loop, orientation and self-crossing checks; planar polygon helpers. */
#include <math.h>
#include <stdlib.h>

#include "pattern_internal.h"

double gar_polygon_area(const float *xy, int n)
{
    double a = 0;
    for (int i = 0; i < n; i++) {
        const float *p = xy + 2 * i, *q = xy + 2 * ((i + 1) % n);
        a += (double)p[0] * q[1] - (double)q[0] * p[1];
    }
    return a / 2;
}

int gar_point_in_polygon(const float *xy, int n, double px, double py)
{
    int in = 0;
    for (int i = 0, j = n - 1; i < n; j = i++) {
        double xi = xy[2 * i], yi = xy[2 * i + 1], xj = xy[2 * j], yj = xy[2 * j + 1];
        if ((yi > py) != (yj > py) && px < (xj - xi) * (py - yi) / (yj - yi) + xi)
            in = !in;
    }
    return in;
}

static double point_segment_distance(const float *a, const float *b, double px, double py)
{
    double dx = b[0] - a[0], dy = b[1] - a[1], l2 = dx * dx + dy * dy;
    double t = l2 > 0 ? ((px - a[0]) * dx + (py - a[1]) * dy) / l2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return hypot(a[0] + t * dx - px, a[1] + t * dy - py);
}

double gar_point_polygon_distance(const float *xy, int n, double px, double py)
{
    double best = INFINITY;
    for (int i = 0; i < n; i++) {
        double d = point_segment_distance(xy + 2 * i, xy + 2 * ((i + 1) % n), px, py);
        best = d < best ? d : best;
    }
    return best;
}

static double orient(const float *a, const float *b, const float *c)
{
    return ((double)b[0] - a[0]) * ((double)c[1] - a[1]) -
           ((double)b[1] - a[1]) * ((double)c[0] - a[0]);
}

/* p on segment ab, given that the three are collinear. */
static int within(const float *a, const float *b, const float *p)
{
    return fmin(a[0], b[0]) <= p[0] && p[0] <= fmax(a[0], b[0]) && fmin(a[1], b[1]) <= p[1] &&
           p[1] <= fmax(a[1], b[1]);
}

int gar_segments_cross(const float *a, const float *b, const float *c, const float *d)
{
    double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
        return 1;
    /* Touching: one segment's end lies on the other. */
    return (o1 == 0 && within(a, b, c)) || (o2 == 0 && within(a, b, d)) ||
           (o3 == 0 && within(c, d, a)) || (o4 == 0 && within(c, d, b));
}

/* The outline's signed area (m^2, > 0 counter-clockwise), on GAR_OUTLINE_CHECK_SAMPLES points an
 * edge; NAN without memory. */
static double outline_area(const gar_panel *pn)
{
    int ne = pn->num_edges, k = GAR_OUTLINE_CHECK_SAMPLES;
    float *xy = malloc((size_t)(ne * k + 1) * 2 * sizeof *xy);
    if (!xy)
        return NAN;
    for (int i = 0; i < ne; i++)
        gar_edge_sample(pn, &pn->edges[i], k, xy + 2 * i * k); /* last overwritten by next */
    double area = gar_polygon_area(xy, ne * k);
    free(xy);
    return area;
}

int gar_panel_make_ccw(gar_panel *pn, gar_reject *why)
{
    double area = outline_area(pn);
    if (isnan(area))
        return gar_refuse(why, GAR_ERR_NO_MEMORY, "panel '%s' outline", pn->name);
    if (!(area < 0))
        return 0;
    for (int i = 0; i < pn->num_vertices; i++)
        pn->uv_m[2 * i] = -pn->uv_m[2 * i];
    for (int e = 0; e < pn->num_edges; e++) {
        gar_edge *ed = &pn->edges[e];
        ed->ctrl[0][0] = -ed->ctrl[0][0];
        ed->ctrl[1][0] = -ed->ctrl[1][0];
        ed->right = !ed->right; /* a mirrored arc turns the other way */
    }
    /* R Ry(180) = Rz(c) Ry(b) Rx(a) Ry(180) = Rz(c) Ry(b + 180) Rx(-a) */
    pn->rotation_deg[0] = -pn->rotation_deg[0];
    pn->rotation_deg[1] = pn->rotation_deg[1] + 180.0f;
    return 1;
}

int gar_check_loop(const gar_panel *pn, gar_reject *why)
{
    int ne = pn->num_edges;
    for (int i = 0; i < ne; i++)
        if (pn->edges[i].v1 != pn->edges[(i + 1) % ne].v0)
            return gar_refuse(why, GAR_ERR_OUTLINE,
                              "panel '%s': edge %d ends at vertex %d but edge %d starts at vertex "
                              "%d (edges must form one loop)",
                              pn->name, i, pn->edges[i].v1, (i + 1) % ne,
                              pn->edges[(i + 1) % ne].v0);
    return 0;
}

int gar_check_outline(const gar_panel *pn, gar_reject *why)
{
    int ne = pn->num_edges, k = GAR_OUTLINE_CHECK_SAMPLES;
    int loop = gar_check_loop(pn, why);
    if (loop)
        return loop;
    int n = ne * k;
    float *xy = malloc((size_t)(n + 1) * 2 * sizeof *xy);
    if (!xy)
        return gar_refuse(why, GAR_ERR_NO_MEMORY, "panel '%s' outline", pn->name);
    for (int i = 0; i < ne; i++)
        gar_edge_sample(pn, &pn->edges[i], k, xy + 2 * i * k); /* last overwritten by next */
    int rc = 0;
    double area = gar_polygon_area(xy, n);
    if (!(area > 0))
        rc = gar_refuse(why, GAR_ERR_OUTLINE, "panel '%s': outline encloses no area (%.3g m^2)",
                        pn->name, area);
    for (int i = 0; i < n && !rc; i++)
        for (int j = i + 2; j < n && !rc; j++) {
            if (i == 0 && j == n - 1)
                continue; /* neighbours through the closing point */
            if (gar_segments_cross(xy + 2 * i, xy + 2 * (i + 1), xy + 2 * j,
                                   xy + 2 * ((j + 1) % n)))
                rc = gar_refuse(why, GAR_ERR_OUTLINE,
                                "panel '%s': edge %d crosses or touches edge %d", pn->name, i / k,
                                j / k);
        }
    free(xy);
    return rc;
}
