/* A dressed pattern's panels sewn into one mesh (pattern_weld.h): the sim's springs follow the
 * triangles' edges, so a seam exists for it only where the two panels share vertices. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cloth.h"
#include "pattern_weld.h"

static int32_t root_of(int32_t *parent, int32_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

/* Union-find over the joints; the lower index is the root, so roots come in vertex order. */
static void join_seams(const gar_mesh *m, int32_t *parent)
{
    for (int i = 0; i < m->num_vertices; i++)
        parent[i] = i;
    for (int j = 0; j < m->num_joints; j++) {
        const gar_joint *jt = &m->joints[j];
        int32_t b = jt->w < 0.5f ? jt->b0 : jt->b1;
        if (jt->a < 0 || jt->a >= m->num_vertices || b < 0 || b >= m->num_vertices)
            continue;
        int32_t ra = root_of(parent, jt->a), rb = root_of(parent, b);
        if (ra != rb)
            parent[ra > rb ? ra : rb] = ra < rb ? ra : rb;
    }
}

static float twice_area(const float *a, const float *b, const float *c)
{
    float e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    float e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    float cr[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    return sqrtf(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
}

/* The sewn triangles into tris (each vertex its root's mean position in xyz); returns their
 * count. */
static int sewn_triangles(const gar_mesh *m, int32_t *parent, const float *xyz, int32_t *tris)
{
    int nt = 0;
    for (int t = 0; t < m->num_triangles; t++) {
        int32_t v[3];
        for (int k = 0; k < 3; k++)
            v[k] = root_of(parent, m->triangles[t * 3 + k]);
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2] ||
            !(twice_area(&xyz[v[0] * 3], &xyz[v[1] * 3], &xyz[v[2] * 3]) >
              2.0f * SIM_WELD_MIN_AREA_M2))
            continue;
        memcpy(&tris[nt * 3], v, sizeof v);
        nt++;
    }
    return nt;
}

int sim_pattern_weld(const gar_mesh *m, sim_garment *out, int8_t *part_of, sim_reject *why)
{
    int nv = m->num_vertices;
    int32_t *parent = malloc((size_t)nv * sizeof *parent);
    int32_t *index = malloc((size_t)nv * sizeof *index);
    int32_t *tris = malloc((size_t)m->num_triangles * 3 * sizeof *tris);
    float *sum = calloc((size_t)nv * 4, sizeof *sum); /* x, y, z, count per root */
    float *xyz = malloc((size_t)nv * 3 * sizeof *xyz);
    int r = parent && index && tris && sum && xyz ? 0 : -SIM_ERR_NO_MEMORY;
    if (r == 0) {
        join_seams(m, parent);
        for (int i = 0; i < nv; i++) {
            int32_t p = root_of(parent, i);
            for (int k = 0; k < 3; k++)
                sum[p * 4 + k] += m->xyz[i * 3 + k];
            sum[p * 4 + 3] += 1.0f;
        }
        for (int i = 0; i < nv; i++)
            for (int k = 0; k < 3; k++)
                xyz[i * 3 + k] = sum[i * 4 + 3] > 0.0f ? sum[i * 4 + k] / sum[i * 4 + 3] : 0.0f;
        int nt = sewn_triangles(m, parent, xyz, tris);
        /* the vertices the kept triangles use, in order (a root precedes what joined it) */
        for (int i = 0; i < nv; i++)
            index[i] = -1;
        for (int i = 0; i < nt * 3; i++)
            index[tris[i]] = 0;
        int n = 0;
        for (int i = 0; i < nv; i++)
            if (index[i] == 0) {
                index[i] = n;
                memmove(&xyz[n * 3], &xyz[i * 3], 3 * sizeof *xyz);
                if (part_of)
                    part_of[n] = part_of[i];
                n++;
            }
        for (int i = 0; i < nt * 3; i++)
            tris[i] = index[tris[i]];
        memset(out, 0, sizeof *out);
        if (nt == 0)
            r = sim_reject_set(why, SIM_ERR_EMPTY, "no triangle left after sewing the panels");
        else if (sim_garment_alloc(out, n, nt, 0) < 0)
            r = sim_reject_set(why, SIM_ERR_NO_MEMORY, "garment of %d vertices", n);
        else {
            memcpy(out->xyz, xyz, (size_t)n * 3 * sizeof *xyz);
            memcpy(out->triangles, tris, (size_t)nt * 3 * sizeof *tris);
        }
    } else
        sim_reject_set(why, SIM_ERR_NO_MEMORY, "sewing a garment of %d vertices", nv);
    free(parent);
    free(index);
    free(tris);
    free(sum);
    free(xyz);
    return r;
}
