/* The figures of a dressed garment (ARCHITECTURE.md "Metrics"): seam gap, penetration, strain
 * of the stretch springs, crossings between panels. Independent of the dressing method: the
 * body is the mesh itself, not the depth maps. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bodyfit.h"
#include "cloth_cloth.h"
#include "dress_internal.h"

/* A vertex deeper than this counts as penetrating (the metric's 1 mm). */
#define GAR_PEN_TOL_M 0.001f

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static void seam_gap(const gar_mesh *m, gar_dress_stats *st)
{
    float g = 0;
    for (int j = 0; j < m->num_joints; j++) {
        const gar_joint *jt = &m->joints[j];
        float s = 0;
        for (int k = 0; k < 3; k++) {
            float p = (1 - jt->w) * m->xyz[3 * jt->b0 + k] + jt->w * m->xyz[3 * jt->b1 + k];
            s += (p - m->xyz[3 * jt->a + k]) * (p - m->xyz[3 * jt->a + k]);
        }
        g = fmaxf(g, sqrtf(s));
    }
    st->seam_gap_mm = g * 1e3f;
}

static int strain(const gar_mesh *m, const gar_springs *sp, gar_dress_stats *st)
{
    float *e = malloc((size_t)(sp->n_stretch + 1) * sizeof *e);
    if (!e)
        return -GAR_ERR_NO_MEMORY;
    for (int s = 0; s < sp->n_stretch; s++) {
        const float *a = m->xyz + 3 * sp->ends[2 * s], *b = m->xyz + 3 * sp->ends[2 * s + 1];
        float l = sqrtf((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                        (b[2] - a[2]) * (b[2] - a[2]));
        e[s] = (l - sp->rest_m[s]) / sp->rest_m[s];
    }
    qsort(e, (size_t)sp->n_stretch, sizeof *e, cmp_float);
    st->max_strain = sp->n_stretch ? e[sp->n_stretch - 1] : 0;
    st->p99_strain = sp->n_stretch ? e[(int)(0.99 * (sp->n_stretch - 1))] : 0;
    free(e);
    return 0;
}

static int penetration(const gar_mesh *m, const fit_model *body, gar_dress_stats *st)
{
    gar_body_sdf *sdf =
        gar_body_sdf_create(fit_model_rest_vertices(body), fit_model_vertex_count(body),
                            fit_model_triangles(body), fit_model_triangle_count(body));
    if (!sdf)
        return -GAR_ERR_NO_MEMORY;
    st->penetrating = 0;
    st->max_pen_mm = 0;
    for (int v = 0; v < m->num_vertices; v++) {
        float d = gar_body_sdf_eval(sdf, m->xyz + 3 * v);
        if (d < -GAR_PEN_TOL_M) {
            st->penetrating++;
            st->max_pen_mm = fmaxf(st->max_pen_mm, -d * 1e3f);
        }
    }
    gar_body_sdf_destroy(sdf);
    return 0;
}

int gar_dress_measure(const gar_mesh *m, const fit_model *body, gar_dress_stats *st)
{
    if (!m || !body || !st)
        return -GAR_ERR_ARG;
    gar_springs sp;
    int rc = gar_springs_build(m, &sp);
    if (rc)
        return rc;
    seam_gap(m, st);
    rc = strain(m, &sp, st);
    if (!rc)
        rc = penetration(m, body, st);
    uint8_t *skip = calloc((size_t)m->num_vertices + 1, 1);
    if (!rc && !skip)
        rc = -GAR_ERR_NO_MEMORY;
    if (!rc) { /* seam vertices and their stretch neighbours meet the other panel by design */
        gar_seam_skip(m, &sp, skip);
        gar_cc *cc = gar_cc_create(m, skip);
        if (!cc)
            rc = -GAR_ERR_NO_MEMORY;
        else
            st->crossings = gar_cc_crossings(cc, m->xyz);
        gar_cc_destroy(cc);
    }
    free(skip);
    gar_springs_free(&sp);
#ifdef _OPENMP
    st->threads = omp_get_max_threads();
#else
    st->threads = 1;
#endif
    return rc;
}
