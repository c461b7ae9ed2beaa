/* Where a dressed garment is stretched (tryon-bench-dress --strain-report): the stretch springs
 * over a strain, counted per panel, and the worst of them with where they lie (panel, edges of
 * their ends, joints at their ends, height, distance to the body). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bodyfit.h"
#include "dress_internal.h"

#define GAR_REPORT_WORST 12
/* A vertex this close to the body lies on it (the dressing keeps cloth 3 mm out). */
#define GAR_ON_BODY_M 0.005f

/* per vertex: how many panel edges it lies on (2 = a panel corner), the first of them, and how
 * many joints name it */
static void vertex_roles(const gar_mesh *m, int8_t *edges, int32_t *first, int8_t *joints)
{
    for (int v = 0; v < m->num_vertices; v++)
        edges[v] = 0, first[v] = -1, joints[v] = 0;
    for (int e = 0; e < m->num_edges; e++)
        for (int k = m->edge_offset[e]; k < m->edge_offset[e + 1]; k++) {
            int v = m->edge_vertices[k];
            if (first[v] != e && edges[v] < 9)
                edges[v]++;
            if (first[v] < 0)
                first[v] = e;
        }
    for (int j = 0; j < m->num_joints; j++) {
        const gar_joint *jt = &m->joints[j];
        int32_t vs[3] = {jt->a, jt->b0, jt->b1};
        for (int k = 0; k < 3; k++)
            if (joints[vs[k]] < 99 && (k < 2 || jt->b1 != jt->b0))
                joints[vs[k]]++;
    }
}

static const char *edge_label(const gar_pattern *p, const gar_mesh *m, int e)
{
    if (e < 0)
        return "-";
    for (int pi = 0; pi < p->num_panels && pi < m->num_panels; pi++)
        if (e >= m->panel_first_edge[pi] && e - m->panel_first_edge[pi] < p->panels[pi].num_edges) {
            const char *l = p->panels[pi].edges[e - m->panel_first_edge[pi]].label;
            return l[0] ? l : "edge";
        }
    return "?";
}

/* Per edge label (summed over the panels: a waist edge of four panels is one loop), the cut
 * length and the dressed length: a mean strain over the limit along a whole free edge is the
 * body wider than the pattern there, not the solver. */
static void edge_lengths(const gar_pattern *p, const gar_mesh *m, const gar_body_sdf *sdf, FILE *f)
{
    fprintf(f, "  edge label       cut_mm  dressed_mm  mean_strain  on_body_%%\n");
    for (int e = 0; e < m->num_edges; e++) {
        const char *l = edge_label(p, m, e);
        int seen = 0;
        for (int q = 0; q < e && !seen; q++)
            seen = !strcmp(edge_label(p, m, q), l);
        if (seen)
            continue;
        double cut = 0, dressed = 0;
        int on = 0, all = 0;
        for (int q = e; q < m->num_edges; q++) {
            if (strcmp(edge_label(p, m, q), l))
                continue;
            for (int k = m->edge_offset[q]; k < m->edge_offset[q + 1]; k++, all++)
                on += gar_body_sdf_eval(sdf, m->xyz + 3 * m->edge_vertices[k]) < GAR_ON_BODY_M;
            for (int k = m->edge_offset[q]; k + 1 < m->edge_offset[q + 1]; k++) {
                int a = m->edge_vertices[k], b = m->edge_vertices[k + 1];
                cut += hypotf(m->uv_m[2 * a] - m->uv_m[2 * b],
                              m->uv_m[2 * a + 1] - m->uv_m[2 * b + 1]);
                const float *x = m->xyz + 3 * a, *y = m->xyz + 3 * b;
                dressed += sqrtf((x[0] - y[0]) * (x[0] - y[0]) + (x[1] - y[1]) * (x[1] - y[1]) +
                                 (x[2] - y[2]) * (x[2] - y[2]));
            }
        }
        fprintf(f, "  %-16.16s %7.1f %10.1f %11.4f %10.0f\n", l, 1e3 * cut, 1e3 * dressed,
                cut > 0 ? dressed / cut - 1 : 0, all ? 100.0 * on / all : 0.0);
    }
}

int gar_strain_report(const gar_pattern *p, const gar_mesh *m, const struct fit_model *body,
                      float over, FILE *f)
{
    gar_springs sp;
    int rc = gar_springs_build(m, &sp), nv = m->num_vertices;
    if (rc)
        return rc;
    float *e = malloc((size_t)(sp.n_stretch + 1) * sizeof *e);
    int *worst = calloc(GAR_REPORT_WORST, sizeof *worst),
        *per_panel = calloc((size_t)m->num_panels + 1, sizeof *per_panel);
    int8_t *edges = malloc((size_t)nv + 1), *joints = malloc((size_t)nv + 1);
    int32_t *first = malloc(((size_t)nv + 1) * sizeof *first);
    gar_body_sdf *sdf =
        gar_body_sdf_create(fit_model_rest_vertices(body), fit_model_vertex_count(body),
                            fit_model_triangles(body), fit_model_triangle_count(body));
    if (!e || !worst || !per_panel || !edges || !joints || !first || !sdf)
        rc = -GAR_ERR_NO_MEMORY;
    int count = 0, nw = 0;
    for (int s = 0; s < sp.n_stretch && !rc; s++) {
        const float *a = m->xyz + 3 * sp.ends[2 * s], *b = m->xyz + 3 * sp.ends[2 * s + 1];
        float l = sqrtf((b[0] - a[0]) * (b[0] - a[0]) + (b[1] - a[1]) * (b[1] - a[1]) +
                        (b[2] - a[2]) * (b[2] - a[2]));
        e[s] = (l - sp.rest_m[s]) / sp.rest_m[s];
        if (e[s] <= over)
            continue;
        count++, per_panel[m->panel_of[sp.ends[2 * s]]]++;
        int k = nw < GAR_REPORT_WORST ? nw++ : GAR_REPORT_WORST - 1;
        if (k == GAR_REPORT_WORST - 1 && nw == GAR_REPORT_WORST && e[worst[k]] >= e[s])
            continue;
        for (; k > 0 && e[worst[k - 1]] < e[s]; k--)
            worst[k] = worst[k - 1];
        worst[k] = s;
    }
    if (!rc) {
        vertex_roles(m, edges, first, joints);
        fprintf(f, "%d of %d stretch springs over %.1f %%; per panel:", count, sp.n_stretch,
                100 * over);
        for (int pi = 0; pi < m->num_panels && pi < p->num_panels; pi++)
            if (per_panel[pi])
                fprintf(f, " %s %d", p->panels[pi].name, per_panel[pi]);
        fprintf(f, "\n  strain  rest_mm panel            end: edge(s) joints y_m body_mm\n");
    }
    for (int k = 0; k < nw && !rc; k++) {
        int s = worst[k];
        fprintf(f, "  %6.3f %7.1f %-16.16s", e[s], 1e3f * sp.rest_m[s],
                p->panels[m->panel_of[sp.ends[2 * s]]].name);
        for (int h = 0; h < 2; h++) {
            int v = sp.ends[2 * s + h];
            fprintf(f, " | %s%s %d %.3f %.1f", edge_label(p, m, first[v]), edges[v] > 1 ? "+" : "",
                    joints[v], m->xyz[3 * v + 1], 1e3f * gar_body_sdf_eval(sdf, m->xyz + 3 * v));
        }
        fprintf(f, "\n");
    }
    if (!rc)
        edge_lengths(p, m, sdf, f);
    gar_body_sdf_destroy(sdf);
    free(e), free(worst), free(per_panel), free(edges), free(joints), free(first);
    gar_springs_free(&sp);
    return rc;
}
