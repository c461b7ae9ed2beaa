/* The GarmentCode / Korosteleva JSON reader (ARCHITECTURE.md "Garment patterns"), on cJSON. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "garments.h"
#include "pattern_internal.h"
#include "tryon_errors.h"

/* A pattern file larger than this is not a sewing pattern (the data sets' are under 100 KB). */
#define GAR_MAX_FILE_BYTES (16 * 1024 * 1024)
/* Relative control coordinates beyond this are no garment curve (the data sets' stay within
 * about 1). */
#define GAR_MAX_RELATIVE 100.0

TRYON_ERROR_WORDS(GAR_ERROR_LIST, GAR_ERROR_COUNT, gar_error_name, gar_error_text,
                  "GAR_ERR_UNKNOWN")
TRYON_REJECT_SETTER(gar_refuse, gar_reject, gar_error)

static int read_number(const cJSON *j, double *out)
{
    if (!cJSON_IsNumber(j))
        return -GAR_ERR_TYPE;
    if (!isfinite(j->valuedouble))
        return -GAR_ERR_RANGE;
    *out = j->valuedouble;
    return 0;
}

/* A [x, y] or [x, y, z] array of finite numbers. */
static int read_vec(const cJSON *j, int n, double *out)
{
    if (!cJSON_IsArray(j) || cJSON_GetArraySize(j) != n)
        return -GAR_ERR_TYPE;
    for (int k = 0; k < n; k++) {
        int rc = read_number(cJSON_GetArrayItem(j, k), &out[k]);
        if (rc)
            return rc;
    }
    return 0;
}

/* Relative control point: P = S + cx (E - S) + cy perp(E - S), perp(x, y) = (-y, x). */
static void rel_to_abs(const float s[2], const float e[2], const double c[2], float out[2])
{
    /* Callers check |c| <= GAR_MAX_RELATIVE first, so the point stays finite. */
    double dx = e[0] - s[0], dy = e[1] - s[1];
    out[0] = (float)(s[0] + c[0] * dx - c[1] * dy);
    out[1] = (float)(s[1] + c[0] * dy + c[1] * dx);
}

static int read_curvature(const cJSON *cv, gar_panel *pn, gar_edge *ed, int ei, double scale,
                          gar_reject *why)
{
    const float *s = pn->uv_m + 2 * ed->v0, *e = pn->uv_m + 2 * ed->v1;
    double c[2];
    if (cJSON_IsArray(cv)) { /* the older encoding: one quadratic control point */
        if (read_vec(cv, 2, c) || fabs(c[0]) > GAR_MAX_RELATIVE || fabs(c[1]) > GAR_MAX_RELATIVE)
            return gar_refuse(why, GAR_ERR_CURVE,
                              "panel '%s': edge %d: curvature must be [cx, cy] within %g", pn->name,
                              ei, GAR_MAX_RELATIVE);
        ed->kind = GAR_QUADRATIC;
        rel_to_abs(s, e, c, ed->ctrl[0]);
        return 0;
    }
    if (!cJSON_IsObject(cv))
        return gar_refuse(why, GAR_ERR_CURVE,
                          "panel '%s': edge %d: curvature is neither [cx, cy] nor an object",
                          pn->name, ei);
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(cv, "type");
    const cJSON *params = cJSON_GetObjectItemCaseSensitive(cv, "params");
    if (!cJSON_IsString(type) || !cJSON_IsArray(params))
        return gar_refuse(why, GAR_ERR_CURVE,
                          "panel '%s': edge %d: curvature needs a string \"type\" and an array "
                          "\"params\"",
                          pn->name, ei);
    const char *t = type->valuestring;
    if (!strcmp(t, "quadratic") || !strcmp(t, "cubic")) {
        int n = t[0] == 'q' ? 1 : 2;
        if (cJSON_GetArraySize(params) != n)
            return gar_refuse(why, GAR_ERR_CURVE,
                              "panel '%s': edge %d: %s curvature needs %d control point(s), has %d",
                              pn->name, ei, t, n, cJSON_GetArraySize(params));
        for (int k = 0; k < n; k++) {
            if (read_vec(cJSON_GetArrayItem(params, k), 2, c) || fabs(c[0]) > GAR_MAX_RELATIVE ||
                fabs(c[1]) > GAR_MAX_RELATIVE)
                return gar_refuse(
                    why, GAR_ERR_CURVE,
                    "panel '%s': edge %d: control point %d must be [cx, cy] within %g", pn->name,
                    ei, k, GAR_MAX_RELATIVE);
            rel_to_abs(s, e, c, ed->ctrl[k]);
        }
        ed->kind = n == 1 ? GAR_QUADRATIC : GAR_CUBIC;
        return 0;
    }
    if (!strcmp(t, "circle")) {
        double r, large, right;
        if (cJSON_GetArraySize(params) != 3 || read_number(cJSON_GetArrayItem(params, 0), &r) ||
            read_number(cJSON_GetArrayItem(params, 1), &large) ||
            read_number(cJSON_GetArrayItem(params, 2), &right))
            return gar_refuse(why, GAR_ERR_CURVE,
                              "panel '%s': edge %d: circle params must be [radius, large_arc, "
                              "right] numbers",
                              pn->name, ei);
        if (!(r > 0) || !(r / scale <= GAR_MAX_COORD_M) || (large != 0 && large != 1) ||
            (right != 0 && right != 1))
            return gar_refuse(
                why, GAR_ERR_CURVE,
                "panel '%s': edge %d: circle radius %g must be in (0, %g m] and flags "
                "%g, %g 0 or 1",
                pn->name, ei, r, GAR_MAX_COORD_M, large, right);
        ed->kind = GAR_CIRCLE;
        ed->radius_m = (float)(r / scale);
        ed->large_arc = (int)large;
        ed->right = (int)right;
        return 0;
    }
    return gar_refuse(why, GAR_ERR_CURVE, "panel '%s': edge %d: unknown curvature type \"%.40s\"",
                      pn->name, ei, t);
}

static int read_edge(const cJSON *je, gar_panel *pn, int ei, double scale, gar_reject *why)
{
    gar_edge *ed = &pn->edges[ei];
    if (!cJSON_IsObject(je))
        return gar_refuse(why, GAR_ERR_TYPE, "panel '%s': edge %d is not an object", pn->name, ei);
    const cJSON *ep = cJSON_GetObjectItemCaseSensitive(je, "endpoints");
    double v[2];
    if (!ep)
        return gar_refuse(why, GAR_ERR_MISSING, "panel '%s': edge %d has no \"endpoints\"",
                          pn->name, ei);
    if (read_vec(ep, 2, v) || v[0] != floor(v[0]) || v[1] != floor(v[1]))
        return gar_refuse(why, GAR_ERR_TYPE, "panel '%s': edge %d: endpoints must be two integers",
                          pn->name, ei);
    if (v[0] < 0 || v[1] < 0 || v[0] >= pn->num_vertices || v[1] >= pn->num_vertices ||
        v[0] == v[1])
        return gar_refuse(why, GAR_ERR_RANGE,
                          "panel '%s': edge %d: endpoints [%g, %g] not two distinct vertices of %d",
                          pn->name, ei, v[0], v[1], pn->num_vertices);
    ed->v0 = (int)v[0];
    ed->v1 = (int)v[1];
    ed->kind = GAR_LINE;
    const cJSON *label = cJSON_GetObjectItemCaseSensitive(je, "label");
    if (cJSON_IsString(label))
        snprintf(ed->label, sizeof ed->label, "%s", label->valuestring);
    const cJSON *cv = cJSON_GetObjectItemCaseSensitive(je, "curvature");
    if (cv && !cJSON_IsNull(cv))
        return read_curvature(cv, pn, ed, ei, scale, why);
    return 0;
}

static int read_panel(const cJSON *jp, gar_panel *pn, double scale, gar_reject *why)
{
    snprintf(pn->name, sizeof pn->name, "%s", jp->string ? jp->string : "");
    if (!cJSON_IsObject(jp))
        return gar_refuse(why, GAR_ERR_TYPE, "panel '%s' is not an object", pn->name);
    const cJSON *verts = cJSON_GetObjectItemCaseSensitive(jp, "vertices");
    const cJSON *edges = cJSON_GetObjectItemCaseSensitive(jp, "edges");
    if (!cJSON_IsArray(verts) || !cJSON_IsArray(edges))
        return gar_refuse(why, verts && edges ? GAR_ERR_TYPE : GAR_ERR_MISSING,
                          "panel '%s': needs arrays \"vertices\" and \"edges\"", pn->name);
    int nv = cJSON_GetArraySize(verts), ne = cJSON_GetArraySize(edges);
    if (nv < 2 || ne < 2 || nv > GAR_MAX_PANEL_VERTICES || ne > GAR_MAX_PANEL_VERTICES)
        return gar_refuse(why,
                          nv > GAR_MAX_PANEL_VERTICES || ne > GAR_MAX_PANEL_VERTICES
                              ? GAR_ERR_TOO_LARGE
                              : GAR_ERR_OUTLINE,
                          "panel '%s': %d vertices and %d edges (2..%d and 2..%d allowed)",
                          pn->name, nv, ne, GAR_MAX_PANEL_VERTICES, GAR_MAX_PANEL_VERTICES);
    pn->uv_m = calloc((size_t)nv * 2, sizeof *pn->uv_m);
    pn->edges = calloc((size_t)ne, sizeof *pn->edges);
    if (!pn->uv_m || !pn->edges)
        return gar_refuse(why, GAR_ERR_NO_MEMORY, "panel '%s'", pn->name);
    pn->num_vertices = nv;
    pn->num_edges = ne;
    for (int i = 0; i < nv; i++) {
        double p[2];
        if (read_vec(cJSON_GetArrayItem(verts, i), 2, p))
            return gar_refuse(why, GAR_ERR_TYPE, "panel '%s': vertex %d must be [x, y] finite",
                              pn->name, i);
        if (!(fabs(p[0] / scale) <= GAR_MAX_COORD_M && fabs(p[1] / scale) <= GAR_MAX_COORD_M))
            return gar_refuse(why, GAR_ERR_RANGE, "panel '%s': vertex %d beyond %g m", pn->name, i,
                              GAR_MAX_COORD_M);
        pn->uv_m[2 * i] = (float)(p[0] / scale);
        pn->uv_m[2 * i + 1] = (float)(p[1] / scale);
    }
    for (int i = 0; i < ne; i++) {
        int rc = read_edge(cJSON_GetArrayItem(edges, i), pn, i, scale, why);
        if (rc)
            return rc;
    }
    double t[3] = {0, 0, 0}, r[3] = {0, 0, 0};
    const cJSON *jt = cJSON_GetObjectItemCaseSensitive(jp, "translation");
    const cJSON *jr = cJSON_GetObjectItemCaseSensitive(jp, "rotation");
    if ((jt && read_vec(jt, 3, t)) || (jr && read_vec(jr, 3, r)))
        return gar_refuse(why, GAR_ERR_TYPE,
                          "panel '%s': translation and rotation must be 3 finite numbers",
                          pn->name);
    for (int k = 0; k < 3; k++)
        if (!(fabs(t[k] / scale) <= GAR_MAX_COORD_M && fabs(r[k]) <= 1e4))
            return gar_refuse(why, GAR_ERR_RANGE,
                              "panel '%s': translation beyond %g m or rotation beyond 1e4 degrees",
                              pn->name, GAR_MAX_COORD_M);
    for (int k = 0; k < 3; k++) {
        pn->translation_m[k] = (float)(t[k] / scale);
        pn->rotation_deg[k] = (float)r[k];
    }
    int rc = gar_check_loop(pn, why);
    if (rc == 0)
        rc = gar_panel_make_ccw(pn, why);
    return rc < 0 ? rc : gar_check_outline(pn, why);
}

static int read_stitch(const cJSON *js, int si, gar_pattern *p, gar_reject *why)
{
    if (!cJSON_IsArray(js) || cJSON_GetArraySize(js) != 2)
        return gar_refuse(why, GAR_ERR_STITCH, "stitch %d: must be an array of two sides", si);
    gar_stitch *st = &p->stitches[si];
    for (int k = 0; k < 2; k++) {
        const cJSON *side = cJSON_GetArrayItem(js, k);
        const cJSON *pn = cJSON_GetObjectItemCaseSensitive(side, "panel");
        const cJSON *ed = cJSON_GetObjectItemCaseSensitive(side, "edge");
        double e;
        if (!cJSON_IsString(pn) || read_number(ed, &e) || e != floor(e))
            return gar_refuse(why, GAR_ERR_STITCH,
                              "stitch %d side %d: needs a string \"panel\" and an integer \"edge\"",
                              si, k);
        int pi = gar_pattern_find_panel(p, pn->valuestring);
        if (pi < 0)
            return gar_refuse(why, GAR_ERR_STITCH, "stitch %d side %d: no panel '%.60s'", si, k,
                              pn->valuestring);
        if (e < 0 || e >= p->panels[pi].num_edges)
            return gar_refuse(why, GAR_ERR_STITCH,
                              "stitch %d side %d: panel '%s' has no edge %g (it has %d)", si, k,
                              p->panels[pi].name, e, p->panels[pi].num_edges);
        st->panel[k] = pi;
        st->edge[k] = (int)e;
    }
    if (st->panel[0] == st->panel[1] && st->edge[0] == st->edge[1])
        return gar_refuse(why, GAR_ERR_STITCH, "stitch %d: panel '%s' edge %d stitched to itself",
                          si, p->panels[st->panel[0]].name, st->edge[0]);
    return 0;
}

/* Panels in panel_order when given (every name once, every panel named), else file order. */
static int panel_sources(const cJSON *panels, const cJSON *order, const cJSON **out, int n,
                         gar_reject *why)
{
    if (!order || cJSON_IsNull(order)) {
        int i = 0;
        for (const cJSON *c = panels->child; c; c = c->next)
            out[i++] = c;
        return 0;
    }
    if (!cJSON_IsArray(order) || cJSON_GetArraySize(order) != n)
        return gar_refuse(why, GAR_ERR_TYPE, "panel_order: must list each of the %d panels once",
                          n);
    for (int i = 0; i < n; i++) {
        const cJSON *nm = cJSON_GetArrayItem(order, i);
        if (!cJSON_IsString(nm))
            return gar_refuse(why, GAR_ERR_TYPE, "panel_order[%d]: not a string", i);
        out[i] = cJSON_GetObjectItemCaseSensitive(panels, nm->valuestring);
        if (!out[i])
            return gar_refuse(why, GAR_ERR_MISSING, "panel_order[%d]: no panel '%.60s'", i,
                              nm->valuestring);
        for (int j = 0; j < i; j++)
            if (out[j] == out[i])
                return gar_refuse(why, GAR_ERR_RANGE, "panel_order[%d]: '%.60s' listed twice", i,
                                  nm->valuestring);
    }
    return 0;
}

static double read_units(const cJSON *root, gar_reject *why, int *rc)
{
    const cJSON *props = cJSON_GetObjectItemCaseSensitive(root, "properties");
    const cJSON *units = cJSON_GetObjectItemCaseSensitive(props, "units_in_meter");
    const cJSON *coords = cJSON_GetObjectItemCaseSensitive(props, "curvature_coords");
    double u = 100; /* the format's default: centimetres */
    *rc = 0;
    if (units && (read_number(units, &u) || !(u >= 1e-3 && u <= 1e6)))
        *rc = gar_refuse(why, GAR_ERR_RANGE, "properties.units_in_meter must be in [0.001, 1e6]");
    else if (coords && (!cJSON_IsString(coords) || strcmp(coords->valuestring, "relative")))
        *rc = gar_refuse(why, GAR_ERR_CURVE,
                         "properties.curvature_coords: only \"relative\" is supported");
    return u;
}

static int read_pattern(const cJSON *root, gar_pattern *p, gar_reject *why)
{
    const cJSON *pat = cJSON_GetObjectItemCaseSensitive(root, "pattern");
    const cJSON *panels = cJSON_GetObjectItemCaseSensitive(pat, "panels");
    if (!cJSON_IsObject(root) || !cJSON_IsObject(pat) || !cJSON_IsObject(panels))
        return gar_refuse(why, GAR_ERR_MISSING, "no object \"pattern\" with an object \"panels\"");
    int rc;
    double scale = read_units(root, why, &rc);
    if (rc)
        return rc;
    p->units_in_meter = (float)scale;
    int n = cJSON_GetArraySize(panels);
    if (n < 1 || n > GAR_MAX_PANELS)
        return gar_refuse(why, n ? GAR_ERR_TOO_LARGE : GAR_ERR_MISSING,
                          "pattern has %d panels (1..%d allowed)", n, GAR_MAX_PANELS);
    const cJSON *src[GAR_MAX_PANELS];
    rc = panel_sources(panels, cJSON_GetObjectItemCaseSensitive(pat, "panel_order"), src, n, why);
    if (rc)
        return rc;
    p->panels = calloc((size_t)n, sizeof *p->panels);
    if (!p->panels)
        return gar_refuse(why, GAR_ERR_NO_MEMORY, "panels");
    p->num_panels = n;
    for (int i = 0; i < n; i++)
        if ((rc = read_panel(src[i], &p->panels[i], scale, why)))
            return rc;
    const cJSON *st = cJSON_GetObjectItemCaseSensitive(pat, "stitches");
    if (!st || cJSON_IsNull(st))
        return 0;
    int ns = cJSON_GetArraySize(st);
    if (!cJSON_IsArray(st) || ns > GAR_MAX_STITCHES)
        return gar_refuse(why, cJSON_IsArray(st) ? GAR_ERR_TOO_LARGE : GAR_ERR_TYPE,
                          "stitches: must be an array of at most %d", GAR_MAX_STITCHES);
    p->stitches = calloc((size_t)(ns ? ns : 1), sizeof *p->stitches);
    if (!p->stitches)
        return gar_refuse(why, GAR_ERR_NO_MEMORY, "stitches");
    p->num_stitches = ns;
    for (int i = 0; i < ns; i++)
        if ((rc = read_stitch(cJSON_GetArrayItem(st, i), i, p, why)))
            return rc;
    return 0;
}

int gar_pattern_parse(const char *json, size_t len, gar_pattern *out, gar_reject *why)
{
    if (!out)
        return gar_refuse(why, GAR_ERR_ARG, "no output pattern");
    memset(out, 0, sizeof *out);
    if (!json || len > GAR_MAX_FILE_BYTES)
        return gar_refuse(why, json ? GAR_ERR_TOO_LARGE : GAR_ERR_ARG, "%zu bytes of JSON", len);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(json, len, &end, 0);
    if (!root)
        return gar_refuse(why, GAR_ERR_JSON, "JSON syntax error at byte %td",
                          end ? end - json : (ptrdiff_t)0);
    int rc = read_pattern(root, out, why);
    cJSON_Delete(root);
    if (rc)
        gar_pattern_free(out);
    return rc;
}

int gar_pattern_load(const char *path, gar_pattern *out, gar_reject *why)
{
    if (out)
        memset(out, 0, sizeof *out);
    if (!path || !out)
        return gar_refuse(why, GAR_ERR_ARG, "no path or output");
    FILE *f = fopen(path, "rb");
    if (!f)
        return gar_refuse(why, GAR_ERR_IO, "%.150s: cannot open", path);
    char *buf = malloc(GAR_MAX_FILE_BYTES + 1);
    size_t n = buf ? fread(buf, 1, GAR_MAX_FILE_BYTES + 1, f) : 0;
    int err = ferror(f);
    fclose(f);
    int rc;
    if (!buf)
        rc = gar_refuse(why, GAR_ERR_NO_MEMORY, "%.150s", path);
    else if (err)
        rc = gar_refuse(why, GAR_ERR_IO, "%.150s: read error", path);
    else if (n > GAR_MAX_FILE_BYTES)
        rc = gar_refuse(why, GAR_ERR_TOO_LARGE, "%.150s: larger than %d bytes", path,
                        GAR_MAX_FILE_BYTES);
    else if ((rc = gar_pattern_parse(buf, n, out, why)) && why) {
        char inner[sizeof why->detail];
        memcpy(inner, why->detail, sizeof inner);
        snprintf(why->detail, sizeof why->detail, "%.60s: %.130s", path, inner);
    }
    free(buf);
    return rc;
}

void gar_pattern_free(gar_pattern *p)
{
    if (!p)
        return;
    for (int i = 0; i < p->num_panels && p->panels; i++) {
        free(p->panels[i].uv_m);
        free(p->panels[i].edges);
    }
    free(p->panels);
    free(p->stitches);
    memset(p, 0, sizeof *p);
}

int gar_pattern_find_panel(const gar_pattern *p, const char *name)
{
    for (int i = 0; p && name && i < p->num_panels; i++)
        if (!strcmp(p->panels[i].name, name))
            return i;
    return -1;
}
