/* Bowyer-Watson Delaunay triangulation of a panel's points (boundary samples and the clipped
 * grid). O(n^2), which is milliseconds at the few thousand points of a panel; no library in
 * Debian offers a C constrained triangulation under a free licence (Shewchuk's Triangle is
 * non-free), and on these inputs the outline's segments come out Delaunay (mesh.c checks). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

typedef struct dtri {
    int v[3];
    double cx, cy, r2;
} dtri;

static void circumcircle(const double *p, dtri *t)
{
    const double *a = p + 2 * t->v[0], *b = p + 2 * t->v[1], *c = p + 2 * t->v[2];
    double bx = b[0] - a[0], by = b[1] - a[1], cx = c[0] - a[0], cy = c[1] - a[1];
    double d = 2 * (bx * cy - by * cx);
    double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
    double ux = (cy * b2 - by * c2) / d, uy = (bx * c2 - cx * b2) / d;
    t->cx = a[0] + ux;
    t->cy = a[1] + uy;
    t->r2 = ux * ux + uy * uy;
}

/* p strictly inside the circumcircle of ccw triangle v (the classic in-circle determinant). */
static int in_circle(const double *pts, const int v[3], int p)
{
    const double *a = pts + 2 * v[0], *b = pts + 2 * v[1], *c = pts + 2 * v[2], *d = pts + 2 * p;
    double ax = a[0] - d[0], ay = a[1] - d[1], bx = b[0] - d[0], by = b[1] - d[1];
    double cx = c[0] - d[0], cy = c[1] - d[1];
    double det = (ax * ax + ay * ay) * (bx * cy - cx * by) -
                 (bx * bx + by * by) * (ax * cy - cx * ay) +
                 (cx * cx + cy * cy) * (ax * by - bx * ay);
    return det > 0;
}

typedef struct dedge {
    int a, b;
} dedge;

/* Points are x, y interleaved; three more slots after the n points hold the super triangle. */
int gar_delaunay(double *pts, int n, int32_t **tris_out, int *nt_out)
{
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) {
            lo[k] = fmin(lo[k], pts[2 * i + k]);
            hi[k] = fmax(hi[k], pts[2 * i + k]);
        }
    double mx = (lo[0] + hi[0]) / 2, my = (lo[1] + hi[1]) / 2;
    double size = 20 * fmax(fmax(hi[0] - lo[0], hi[1] - lo[1]), 1e-3);
    double super[6] = {mx - size, my - size, mx + size, my - size, mx, my + size};
    memcpy(pts + 2 * n, super, sizeof super);
    int cap = 2 * n + 16, nt = 1;
    dtri *t = malloc((size_t)cap * sizeof *t);
    int *bad = malloc((size_t)cap * sizeof *bad);
    dedge *poly = malloc((size_t)cap * 3 * sizeof *poly);
    if (!t || !bad || !poly) {
        free(t), free(bad), free(poly);
        return -GAR_ERR_NO_MEMORY;
    }
    t[0] = (dtri){{n, n + 1, n + 2}, 0, 0, 0};
    circumcircle(pts, &t[0]);
    for (int i = 0; i < n; i++) {
        double px = pts[2 * i], py = pts[2 * i + 1];
        int nbad = 0, npoly = 0;
        for (int k = 0; k < nt; k++) {
            double dx = px - t[k].cx, dy = py - t[k].cy;
            /* The cached circle culls; the determinant, exact for near-cocircular points to
             * double rounding, decides. */
            if (dx * dx + dy * dy < t[k].r2 * (1 + 1e-9) + 1e-30 && in_circle(pts, t[k].v, i))
                bad[nbad++] = k;
        }
        /* The cavity's boundary: edges of bad triangles that no other bad triangle shares. */
        for (int k = 0; k < nbad; k++)
            for (int e = 0; e < 3; e++) {
                int a = t[bad[k]].v[e], b = t[bad[k]].v[(e + 1) % 3], shared = 0;
                for (int m = 0; m < nbad && !shared; m++)
                    for (int f = 0; f < 3 && m != k; f++)
                        if (t[bad[m]].v[f] == b && t[bad[m]].v[(f + 1) % 3] == a)
                            shared = 1;
                if (!shared)
                    poly[npoly++] = (dedge){a, b};
            }
        if (nt - nbad + npoly > cap) {
            cap = 2 * cap + npoly;
            dtri *nt2 = realloc(t, (size_t)cap * sizeof *t);
            int *nb2 = nt2 ? realloc(bad, (size_t)cap * sizeof *bad) : NULL;
            dedge *np2 = nb2 ? realloc(poly, (size_t)cap * 3 * sizeof *poly) : NULL;
            t = nt2 ? nt2 : t;
            bad = nb2 ? nb2 : bad;
            poly = np2 ? np2 : poly;
            if (!np2) {
                free(t), free(bad), free(poly);
                return -GAR_ERR_NO_MEMORY;
            }
        }
        /* New triangles fill the bad slots first, then the end of the array. */
        for (int k = 0; k < npoly; k++) {
            int slot = k < nbad ? bad[k] : nt++;
            t[slot] = (dtri){{poly[k].a, poly[k].b, i}, 0, 0, 0};
            circumcircle(pts, &t[slot]);
        }
    }
    int32_t *out = malloc((size_t)(nt ? nt : 1) * 3 * sizeof *out);
    int m = 0;
    for (int k = 0; out && k < nt; k++) {
        if (t[k].v[0] >= n || t[k].v[1] >= n || t[k].v[2] >= n)
            continue;
        for (int e = 0; e < 3; e++)
            out[3 * m + e] = t[k].v[e];
        m++;
    }
    free(t), free(bad), free(poly);
    if (!out)
        return -GAR_ERR_NO_MEMORY;
    *tris_out = out;
    *nt_out = m;
    return 0;
}
