/* Edge geometry: lines, quadratic and cubic Beziers, SVG-style circle arcs; arc-length sampling. */
#include <math.h>

#include "pattern_internal.h"

/* Arc length by a fine polyline: 256 chords keep a quarter circle within 1e-5 of its length. */
#define CURVE_TABLE_STEPS 256

static void lerp2(const float a[2], const float b[2], float t, float out[2])
{
    out[0] = a[0] + (b[0] - a[0]) * t;
    out[1] = a[1] + (b[1] - a[1]) * t;
}

/* The arc's centre and start/sweep angles (radians). The radius is raised to half the chord
 * when smaller, as SVG does. A positive sweep runs counter-clockwise (GarmentCode right = 1). */
static void arc_frame(const float s[2], const float e[2], const gar_edge *ed, double c[2],
                      double *r, double *a0, double *sweep)
{
    double dx = e[0] - s[0], dy = e[1] - s[1], d = sqrt(dx * dx + dy * dy);
    double rr = ed->radius_m > d / 2 ? ed->radius_m : d / 2;
    double h = sqrt(fmax(rr * rr - d * d / 4, 0.0));
    double nx = d > 0 ? -dy / d : 0, ny = d > 0 ? dx / d : 0; /* unit left normal */
    /* Counter-clockwise travel keeps the centre on the left of the chord for the small arc and
     * on its right for the large one; clockwise travel mirrors that. */
    int ccw = ed->right != 0;
    double side = (ccw == !ed->large_arc) ? 1.0 : -1.0;
    c[0] = (s[0] + e[0]) / 2 + side * h * nx;
    c[1] = (s[1] + e[1]) / 2 + side * h * ny;
    *r = rr;
    *a0 = atan2(s[1] - c[1], s[0] - c[0]);
    double a1 = atan2(e[1] - c[1], e[0] - c[0]), da = a1 - *a0;
    if (ccw)
        while (da <= 0)
            da += 2 * GAR_PI;
    else
        while (da >= 0)
            da -= 2 * GAR_PI;
    *sweep = da;
}

void gar_edge_eval(const gar_panel *panel, const gar_edge *ed, float t, float out[2])
{
    const float *s = panel->uv_m + 2 * ed->v0, *e = panel->uv_m + 2 * ed->v1;
    float u = 1 - t;
    switch (ed->kind) {
    case GAR_QUADRATIC:
        for (int k = 0; k < 2; k++)
            out[k] = u * u * s[k] + 2 * u * t * ed->ctrl[0][k] + t * t * e[k];
        return;
    case GAR_CUBIC:
        for (int k = 0; k < 2; k++)
            out[k] = u * u * u * s[k] + 3 * u * u * t * ed->ctrl[0][k] +
                     3 * u * t * t * ed->ctrl[1][k] + t * t * t * e[k];
        return;
    case GAR_CIRCLE: {
        double c[2], r, a0, sweep;
        arc_frame(s, e, ed, c, &r, &a0, &sweep);
        if (t <= 0 || t >= 1) { /* the endpoints exactly, so outlines close */
            out[0] = t <= 0 ? s[0] : e[0];
            out[1] = t <= 0 ? s[1] : e[1];
            return;
        }
        double a = a0 + sweep * t;
        out[0] = (float)(c[0] + r * cos(a));
        out[1] = (float)(c[1] + r * sin(a));
        return;
    }
    case GAR_LINE:
    default:
        lerp2(s, e, t, out);
        return;
    }
}

/* Cumulative chord lengths at CURVE_TABLE_STEPS + 1 parameters. */
static void length_table(const gar_panel *panel, const gar_edge *e, double *cum)
{
    float prev[2], p[2];
    gar_edge_eval(panel, e, 0, prev);
    cum[0] = 0;
    for (int i = 1; i <= CURVE_TABLE_STEPS; i++) {
        gar_edge_eval(panel, e, (float)i / CURVE_TABLE_STEPS, p);
        cum[i] = cum[i - 1] + hypot(p[0] - prev[0], p[1] - prev[1]);
        prev[0] = p[0], prev[1] = p[1];
    }
}

float gar_edge_length(const gar_panel *panel, const gar_edge *e)
{
    if (e->kind == GAR_LINE) {
        const float *s = panel->uv_m + 2 * e->v0, *q = panel->uv_m + 2 * e->v1;
        return hypotf(q[0] - s[0], q[1] - s[1]);
    }
    double cum[CURVE_TABLE_STEPS + 1];
    length_table(panel, e, cum);
    return (float)cum[CURVE_TABLE_STEPS];
}

int gar_edge_sample(const gar_panel *panel, const gar_edge *e, int n, float *out)
{
    if (!panel || !e || !out || n < 1)
        return -GAR_ERR_ARG;
    double cum[CURVE_TABLE_STEPS + 1];
    length_table(panel, e, cum);
    double total = cum[CURVE_TABLE_STEPS];
    int j = 0;
    for (int i = 0; i <= n; i++) {
        float t;
        if (i == 0 || i == n || total <= 0) {
            t = i == n ? 1.0f : (float)i / n;
        } else {
            double target = total * i / n;
            while (j < CURVE_TABLE_STEPS - 1 && cum[j + 1] < target)
                j++;
            double seg = cum[j + 1] - cum[j], f = seg > 0 ? (target - cum[j]) / seg : 0;
            t = (float)((j + f) / CURVE_TABLE_STEPS);
        }
        gar_edge_eval(panel, e, t, out + 2 * i);
    }
    return 0;
}

void gar_panel_to_world(const gar_panel *panel, const float uv[2], float out[3])
{
    const double deg = GAR_PI / 180.0;
    double cx = cos(panel->rotation_deg[0] * deg), sx = sin(panel->rotation_deg[0] * deg);
    double cy = cos(panel->rotation_deg[1] * deg), sy = sin(panel->rotation_deg[1] * deg);
    double cz = cos(panel->rotation_deg[2] * deg), sz = sin(panel->rotation_deg[2] * deg);
    double p[3] = {uv[0], uv[1], 0};
    /* R = Rz Ry Rx: x first, then y, then z. */
    double q1[3] = {p[0], cx * p[1] - sx * p[2], sx * p[1] + cx * p[2]};
    double q2[3] = {cy * q1[0] + sy * q1[2], q1[1], -sy * q1[0] + cy * q1[2]};
    double q3[3] = {cz * q2[0] - sz * q2[1], sz * q2[0] + cz * q2[1], q2[2]};
    for (int k = 0; k < 3; k++)
        out[k] = (float)(q3[k] + panel->translation_m[k]);
}
