/* The Cusick drape test (docs/garments.md, "Drape test"): a disc of fabric laid centred on a
 * smaller support disc and clamped there, as the drapemeter does (BS 5058: a 30 cm specimen on
 * an 18 cm disc), left to hang under its own weight with tryon's dressing (dress_tryon.c), then
 * the area of its shadow seen from above. Drape coefficient = (shadow - support disc) /
 * (specimen - support disc): 1 = stays flat, 0 = hangs straight down. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dress_internal.h"

/* The support's top, high enough that nothing reaches the floor (the hanging ring is at most
 * (specimen - support) / 2 long). */
#define GAR_DRAPE_TOP_M 0.25f
/* The cloth is laid this far above the support (tryon's contact thickness). */
#define GAR_DRAPE_LIFT_M 0.003f
/* Sides of the support cylinder's polygon. */
#define GAR_DRAPE_SIDES 64
/* Shadow raster pixel (m): 1 mm, under 0.3 % of the annulus' area along its outline. */
#define GAR_DRAPE_PIXEL_M 0.001f

/* The specimen as a pattern file: one panel, four circle arcs (exercises the reader). */
static int disc_pattern(float radius_m, gar_pattern *p, gar_reject *why)
{
    float r = radius_m * 100; /* the file is in centimetres */
    char json[1024];
    snprintf(
        json, sizeof json,
        "{\"pattern\": {\"panels\": {\"specimen\": {\"vertices\": [[%g, 0], [0, %g], [%g, 0], "
        "[0, %g]], \"edges\": ["
        "{\"endpoints\": [0, 1], \"curvature\": {\"type\": \"circle\", \"params\": [%g, 0, 1]}},"
        "{\"endpoints\": [1, 2], \"curvature\": {\"type\": \"circle\", \"params\": [%g, 0, 1]}},"
        "{\"endpoints\": [2, 3], \"curvature\": {\"type\": \"circle\", \"params\": [%g, 0, 1]}},"
        "{\"endpoints\": [3, 0], \"curvature\": {\"type\": \"circle\", \"params\": [%g, 0, 1]}}"
        "], \"translation\": [0, 0, 0], \"rotation\": [0, 0, 0]}}, \"stitches\": []},"
        "\"properties\": {\"units_in_meter\": 100}}",
        r, r, -r, -r, r, r, r, r);
    return gar_pattern_parse(json, strlen(json), p, why);
}

/* The support: a closed cylinder of radius r from the floor to its top at h, outward facing. */
static int support_mesh(float r, float h, float **xyz, int32_t **tris, int *nv, int *nt)
{
    int n = GAR_DRAPE_SIDES;
    *nv = 2 * n + 1, *nt = 3 * n;
    *xyz = malloc((size_t)*nv * 3 * sizeof **xyz);
    *tris = malloc((size_t)*nt * 3 * sizeof **tris);
    if (!*xyz || !*tris)
        return -GAR_ERR_NO_MEMORY;
    for (int i = 0; i < n; i++) {
        float a = 2 * GAR_PI * (float)i / (float)n;
        float *top = *xyz + 3 * i, *bot = *xyz + 3 * (n + i);
        top[0] = bot[0] = r * cosf(a), top[2] = bot[2] = -r * sinf(a);
        top[1] = h, bot[1] = 0;
    }
    float *c = *xyz + 3 * 2 * n;
    c[0] = c[2] = 0, c[1] = h;
    for (int i = 0; i < n; i++) {
        int j = (i + 1) % n;
        int32_t *t = *tris + 9 * i;
        /* top cap (normal +y), then the side's two triangles (normal outward) */
        t[0] = 2 * n, t[1] = i, t[2] = j;
        t[3] = i, t[4] = n + i, t[5] = n + j;
        t[6] = i, t[7] = n + j, t[8] = j;
    }
    return 0;
}

/* Area (m^2) of the union of the triangles seen from above (x, z), on a square raster. */
static float shadow_area(const gar_mesh *m, float half_m)
{
    int w = (int)ceilf(2 * half_m / GAR_DRAPE_PIXEL_M);
    uint8_t *cov = calloc((size_t)w * (size_t)w, 1);
    if (!cov)
        return -1;
    for (int t = 0; t < m->num_triangles; t++) {
        float px[3], pz[3];
        for (int k = 0; k < 3; k++) {
            const float *v = m->xyz + 3 * m->triangles[3 * t + k];
            px[k] = (v[0] + half_m) / GAR_DRAPE_PIXEL_M,
            pz[k] = (v[2] + half_m) / GAR_DRAPE_PIXEL_M;
        }
        float area = (px[1] - px[0]) * (pz[2] - pz[0]) - (px[2] - px[0]) * (pz[1] - pz[0]);
        if (fabsf(area) < 1e-12f)
            continue;
        int x0 = (int)fmaxf(0, floorf(fminf(px[0], fminf(px[1], px[2]))));
        int x1 = (int)fminf(w - 1, ceilf(fmaxf(px[0], fmaxf(px[1], px[2]))));
        int z0 = (int)fmaxf(0, floorf(fminf(pz[0], fminf(pz[1], pz[2]))));
        int z1 = (int)fminf(w - 1, ceilf(fmaxf(pz[0], fmaxf(pz[1], pz[2]))));
        for (int z = z0; z <= z1; z++)
            for (int x = x0; x <= x1; x++) {
                float cx = x + 0.5f, cz = z + 0.5f, in = 1;
                for (int k = 0; k < 3 && in; k++) { /* same side of every edge as the area */
                    int j = (k + 1) % 3;
                    float e = (px[j] - px[k]) * (cz - pz[k]) - (cx - px[k]) * (pz[j] - pz[k]);
                    in = e * area >= 0;
                }
                if (in)
                    cov[(size_t)z * (size_t)w + (size_t)x] = 1;
            }
    }
    size_t count = 0;
    for (size_t i = 0; i < (size_t)w * (size_t)w; i++)
        count += cov[i];
    free(cov);
    return (float)count * GAR_DRAPE_PIXEL_M * GAR_DRAPE_PIXEL_M;
}

static int drape_run(const gar_drape_desc *desc, gar_mesh *m, gar_drape_result *out,
                     gar_reject *why)
{
    float rf = 0.5f * desc->specimen_d_m, rs = 0.5f * desc->support_d_m;
    float *sxyz = NULL;
    int32_t *stri = NULL;
    int nv = 0, nt = 0;
    uint8_t *pinned = calloc((size_t)m->num_vertices + 1, 1);
    int rc =
        pinned ? support_mesh(rs, GAR_DRAPE_TOP_M, &sxyz, &stri, &nv, &nt) : -GAR_ERR_NO_MEMORY;
    if (rc) {
        free(pinned), free(sxyz), free(stri);
        return gar_refuse(why, -rc, "drape test setup");
    }
    /* laid flat (panel u -> x, v -> -z, its front up), clamped over the support disc */
    for (int i = 0; i < m->num_vertices; i++) {
        float u = m->uv_m[2 * i], v = m->uv_m[2 * i + 1];
        m->xyz[3 * i] = u, m->xyz[3 * i + 1] = GAR_DRAPE_TOP_M + GAR_DRAPE_LIFT_M;
        m->xyz[3 * i + 2] = -v;
        pinned[i] = hypotf(u, v) <= rs;
    }
    gar_body_mesh body = {sxyz, nv, stri, nt, pinned, NULL};
    gar_dress_desc dd = {
        .fabric = desc->fabric, .drape_steps = desc->steps, .iterations = desc->iterations};
    gar_dress_stats st;
    rc = gar_dress_tryon_on(m, &body, &dd, &st, why);
    if (!rc) {
        float shadow = shadow_area(m, rf + 0.01f);
        float a_s = GAR_PI * rs * rs, a_f = GAR_PI * rf * rf;
        out->shadow_m2 = shadow;
        out->coefficient = (shadow - a_s) / (a_f - a_s);
        out->ms = st.ms;
        out->vertices = m->num_vertices;
        out->drop_m = 0;
        for (int i = 0; i < m->num_vertices; i++)
            out->drop_m = fmaxf(out->drop_m, GAR_DRAPE_TOP_M - m->xyz[3 * i + 1]);
        if (shadow < 0)
            rc = gar_refuse(why, GAR_ERR_NO_MEMORY, "shadow raster");
    }
    free(pinned), free(sxyz), free(stri);
    return rc;
}

int gar_drape_test(const gar_drape_desc *in, gar_drape_result *out, gar_reject *why)
{
    gar_drape_desc d = in ? *in : (gar_drape_desc){0};
    if (!out)
        return gar_refuse(why, GAR_ERR_ARG, "drape test: no result");
    memset(out, 0, sizeof *out);
    d.fabric = d.fabric ? d.fabric : gar_fabric_find("cotton");
    d.specimen_d_m = d.specimen_d_m > 0 ? d.specimen_d_m : 0.30f;
    d.support_d_m = d.support_d_m > 0 ? d.support_d_m : 0.18f;
    d.spacing_m = d.spacing_m > 0 ? d.spacing_m : 0.01f;
    d.steps = d.steps > 0 ? d.steps : 1000;
    if (!(d.support_d_m < d.specimen_d_m) || d.specimen_d_m > 2 * GAR_DRAPE_TOP_M ||
        d.spacing_m > 0.25f * d.support_d_m)
        return gar_refuse(why, GAR_ERR_RANGE,
                          "drape test: support %.3f m must be under the specimen %.3f m (at most "
                          "%.2f m), spacing %.3f m at most a quarter of the support",
                          d.support_d_m, d.specimen_d_m, 2 * GAR_DRAPE_TOP_M, d.spacing_m);
    gar_pattern p;
    gar_mesh m = {0};
    int rc = disc_pattern(0.5f * d.specimen_d_m, &p, why);
    if (rc)
        return rc;
    rc = gar_mesh_build(&p, &(gar_mesh_desc){.spacing_m = d.spacing_m}, &m, why);
    if (!rc)
        rc = drape_run(&d, &m, out, why);
    gar_mesh_free(&m);
    gar_pattern_free(&p);
    return rc;
}
