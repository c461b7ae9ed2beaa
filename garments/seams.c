/* Seam sampling into the seed's joints: each stitch pairs edge a at arc fraction t with edge b
 * at 1 - t (edges run counter-clockwise on their panels, so the two sides of a seam run in
 * opposite directions). Equal sample counts pair point to point; a gather pairs each vertex of
 * either side with a point on the other side's segment. */
#include <math.h>
#include <stdlib.h>

#include "mesh_internal.h"

/* A partner this close to a vertex (fraction of a segment) is that vertex. */
#define GAR_JOINT_SNAP 1e-4f

/* Adds joints from every vertex of side a to side b; skip_exact leaves out vertices whose
 * partner is exactly a vertex of b (the other direction already paired them). */
static int pair(const int32_t *a, int na, const int32_t *b, int nb, int stitch, int skip_exact,
                gar_joint *out)
{
    int n = 0;
    for (int i = 0; i <= na; i++) {
        float f = (1.0f - (float)i / na) * nb;
        int b0 = (int)floorf(f);
        float w = f - b0;
        if (w > 1 - GAR_JOINT_SNAP)
            b0++, w = 0;
        if (w < GAR_JOINT_SNAP)
            w = 0;
        if (b0 >= nb)
            b0 = nb, w = 0;
        if (skip_exact && w == 0)
            continue;
        out[n++] = (gar_joint){a[i], b[b0], b[w > 0 ? b0 + 1 : b0], w, stitch};
    }
    return n;
}

int gar_seams_build(const gar_pattern *p, gar_mesh *m, gar_reject *why)
{
    int cap = 0;
    for (int s = 0; s < p->num_stitches; s++)
        for (int k = 0; k < 2; k++) {
            int e = m->panel_first_edge[p->stitches[s].panel[k]] + p->stitches[s].edge[k];
            cap += m->edge_offset[e + 1] - m->edge_offset[e];
        }
    m->joints = malloc((size_t)(cap ? cap : 1) * sizeof *m->joints);
    if (!m->joints)
        return gar_refuse(why, GAR_ERR_NO_MEMORY, "%d joints", cap);
    m->num_joints = 0;
    for (int s = 0; s < p->num_stitches; s++) {
        int ea = m->panel_first_edge[p->stitches[s].panel[0]] + p->stitches[s].edge[0];
        int eb = m->panel_first_edge[p->stitches[s].panel[1]] + p->stitches[s].edge[1];
        const int32_t *a = m->edge_vertices + m->edge_offset[ea];
        const int32_t *b = m->edge_vertices + m->edge_offset[eb];
        int na = m->edge_offset[ea + 1] - m->edge_offset[ea] - 1;
        int nb = m->edge_offset[eb + 1] - m->edge_offset[eb] - 1;
        m->num_joints += pair(a, na, b, nb, s, 0, m->joints + m->num_joints);
        if (na != nb)
            m->num_joints += pair(b, nb, a, na, s, 1, m->joints + m->num_joints);
    }
    return 0;
}
