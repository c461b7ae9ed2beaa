/* Fit of a dressed garment per body region (docs/garments.md, "Which size fits"): each garment
 * vertex belongs to the region of the body under it (the strongest skinning joint of the
 * nearest body vertex); per region the strain of the stretch springs starting there, the share
 * of vertices touching the body and the median distance to it. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bodyfit.h"
#include "dress_internal.h"
#include "place_internal.h"

/* A garment vertex this close to the body's surface touches it (the dressing keeps cloth 3 mm
 * out; 2 mm more for the draped state's noise). */
#define GAR_FIT_CONTACT_M 0.005f
/* Body vertices are looked up within this reach; a garment vertex farther from the body (a
 * skirt's hem) belongs to no region. */
#define GAR_FIT_REACH_M 0.10f

#define GAR_REGION_NAME(id, name) name,
static const char *const region_names[] = {GAR_REGION_LIST(GAR_REGION_NAME)};
#undef GAR_REGION_NAME

const char *gar_region_name(gar_region r)
{
    return r >= 0 && r < GAR_REGION_COUNT ? region_names[r] : "?";
}

static gar_region region_of_joint(int j)
{
    switch (j) {
    case FIT_NECK:
    case FIT_HEAD:
    case FIT_L_CLAVICLE:
    case FIT_R_CLAVICLE:
        return GAR_REGION_SHOULDERS;
    case FIT_CHEST:
        return GAR_REGION_CHEST;
    case FIT_SPINE:
        return GAR_REGION_WAIST;
    case FIT_PELVIS:
        return GAR_REGION_HIPS;
    case FIT_L_HIP:
    case FIT_R_HIP:
        return GAR_REGION_THIGHS;
    case FIT_L_KNEE:
    case FIT_R_KNEE:
    case FIT_L_ANKLE:
    case FIT_R_ANKLE:
    case FIT_L_TOE:
    case FIT_R_TOE:
        return GAR_REGION_LOWER_LEGS;
    default:
        return GAR_REGION_ARMS;
    }
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The region of every garment vertex (-1: none within reach) and its distance to the body. */
static int classify(const gar_mesh *m, const fit_model *body, int8_t *region, float *dist)
{
    const float *bx = fit_model_rest_vertices(body);
    int nv = fit_model_vertex_count(body);
    const uint8_t *wj = fit_model_weight_joints(body);
    const float *ww = fit_model_weights(body);
    gar_grid g;
    gar_body_sdf *sdf =
        gar_body_sdf_create(bx, nv, fit_model_triangles(body), fit_model_triangle_count(body));
    if (!sdf || gar_grid_build(&g, bx, nv, GAR_FIT_REACH_M)) {
        gar_body_sdf_destroy(sdf);
        return -GAR_ERR_NO_MEMORY;
    }
    for (int v = 0; v < m->num_vertices; v++) {
        const float *p = m->xyz + 3 * v;
        int b = gar_grid_nearest(&g, bx, p);
        region[v] = -1;
        dist[v] = GAR_FIT_REACH_M;
        if (b < 0)
            continue;
        int best = 0;
        for (int k = 1; k < FIT_MAX_INFLUENCES; k++)
            if (ww[FIT_MAX_INFLUENCES * b + k] > ww[FIT_MAX_INFLUENCES * b + best])
                best = k;
        region[v] = (int8_t)region_of_joint(wj[FIT_MAX_INFLUENCES * b + best]);
        float d = gar_body_sdf_eval(sdf, p);
        if (d >= 1.0f) /* beyond the signed distance's reach: the nearest vertex's distance */
            d = sqrtf((p[0] - bx[3 * b]) * (p[0] - bx[3 * b]) +
                      (p[1] - bx[3 * b + 1]) * (p[1] - bx[3 * b + 1]) +
                      (p[2] - bx[3 * b + 2]) * (p[2] - bx[3 * b + 2]));
        dist[v] = d;
    }
    gar_grid_free(&g);
    gar_body_sdf_destroy(sdf);
    return 0;
}

/* One region's figures from the per-vertex and per-spring values that fall in it. */
static void summarise(gar_fit_region *r, float *strain, int ns, float *dist, int nd, int touching)
{
    r->vertices = nd;
    if (ns) {
        qsort(strain, (size_t)ns, sizeof *strain, cmp_float);
        r->max_strain = strain[ns - 1];
        r->p95_strain = strain[(int)(0.95 * (ns - 1))];
    }
    if (nd) {
        qsort(dist, (size_t)nd, sizeof *dist, cmp_float);
        r->gap_mm = dist[nd / 2] * 1e3f;
        r->contact = (float)touching / (float)nd;
    }
}

int gar_fit_measure(const gar_mesh *m, const fit_model *body, gar_fit *out)
{
    if (!m || !body || !out)
        return -GAR_ERR_ARG;
    memset(out, 0, sizeof *out);
    gar_springs sp;
    int rc = gar_springs_build(m, &sp), n = m->num_vertices;
    if (rc)
        return rc;
    int8_t *region = malloc((size_t)n + 1);
    float *dist = malloc(((size_t)n + 1) * sizeof *dist);
    float *vals = malloc(((size_t)n + (size_t)sp.n_stretch + 1) * sizeof *vals);
    rc = region && dist && vals ? classify(m, body, region, dist) : -GAR_ERR_NO_MEMORY;
    for (int r = 0; r < GAR_REGION_COUNT && !rc; r++) {
        int ns = 0, nd = 0, touching = 0;
        for (int s = 0; s < sp.n_stretch; s++) {
            int a = sp.ends[2 * s], b = sp.ends[2 * s + 1];
            if (region[a] != r)
                continue;
            float l = 0;
            for (int k = 0; k < 3; k++)
                l += (m->xyz[3 * a + k] - m->xyz[3 * b + k]) *
                     (m->xyz[3 * a + k] - m->xyz[3 * b + k]);
            vals[ns++] = sqrtf(l) / sp.rest_m[s] - 1;
        }
        float *d = vals + ns;
        for (int v = 0; v < n; v++)
            if (region[v] == r) {
                d[nd++] = dist[v];
                touching += dist[v] < GAR_FIT_CONTACT_M;
            }
        summarise(&out->region[r], vals, ns, d, nd, touching);
    }
    free(region), free(dist), free(vals);
    gar_springs_free(&sp);
    return rc;
}
