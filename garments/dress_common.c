/* Pieces both dressing methods and the measure share: lumped masses and the seam neighbourhood
 * that cloth-cloth leaves out. */
#include <math.h>
#include <string.h>

#include "dress_internal.h"

void gar_lump_masses(const gar_mesh *m, float density_kg_m2, float *mass)
{
    double total = 0;
    memset(mass, 0, (size_t)m->num_vertices * sizeof *mass);
    for (int t = 0; t < m->num_triangles; t++) {
        const int32_t *tr = m->triangles + 3 * t;
        const float *a = m->uv_m + 2 * tr[0], *b = m->uv_m + 2 * tr[1], *c = m->uv_m + 2 * tr[2];
        float area = 0.5f * fabsf((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
        for (int e = 0; e < 3; e++)
            mass[tr[e]] += density_kg_m2 * area / 3;
        total += density_kg_m2 * area;
    }
    float floor_kg = m->num_vertices ? 0.5f * (float)(total / m->num_vertices) : 0;
    for (int i = 0; i < m->num_vertices; i++)
        mass[i] = fmaxf(mass[i], floor_kg);
}

void gar_seam_skip(const gar_mesh *m, const gar_springs *sp, uint8_t *skip)
{
    for (int j = 0; j < m->num_joints; j++)
        skip[m->joints[j].a] = skip[m->joints[j].b0] = skip[m->joints[j].b1] = 1;
    for (int s = 0; s < sp->n_stretch; s++) {
        int a = sp->ends[2 * s], b = sp->ends[2 * s + 1];
        if ((skip[a] & 1) || (skip[b] & 1))
            skip[a] |= 2, skip[b] |= 2;
    }
}
