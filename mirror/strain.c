/* Per-vertex strain for the fit map. CLOTH carries the garment's worst strain, not each
 * spring's; the mirror takes the edge lengths of a garment's first frame as its rest lengths
 * (tryon-sim makes each garment at rest around the body it is first given) and measures every
 * later frame against them. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mirror.h"

struct mirror_strain {
    int nv, ne, have_rest;
    int32_t *edges; /* [ne][2], each triangle's three edges */
    float *rest;    /* [ne] metres */
    float *vertex;  /* [nv] */
    int e_cap, v_cap;
};

mirror_strain *mirror_strain_create(void)
{
    return calloc(1, sizeof(mirror_strain));
}

void mirror_strain_destroy(mirror_strain *s)
{
    if (!s)
        return;
    free(s->edges);
    free(s->rest);
    free(s->vertex);
    free(s);
}

void mirror_strain_reset(mirror_strain *s)
{
    s->have_rest = 0;
}

static float edge_len(const float *xyz, const int32_t *e)
{
    const float *a = &xyz[e[0] * 3], *b = &xyz[e[1] * 3];
    float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
}

static int grow(mirror_strain *s, int nv, int ne)
{
    if (ne > s->e_cap) {
        int32_t *e = realloc(s->edges, (size_t)ne * 2 * sizeof *e);
        float *r = e ? realloc(s->rest, (size_t)ne * sizeof *r) : NULL;
        if (e)
            s->edges = e;
        if (!r)
            return -MIRROR_ERR_NO_MEMORY;
        s->rest = r;
        s->e_cap = ne;
    }
    if (nv > s->v_cap) {
        float *v = realloc(s->vertex, (size_t)nv * sizeof *v);
        if (!v)
            return -MIRROR_ERR_NO_MEMORY;
        s->vertex = v;
        s->v_cap = nv;
    }
    return 0;
}

const float *mirror_strain_update(mirror_strain *s, const float *xyz, int nv, const int32_t *tris,
                                  int nt)
{
    if (!s->have_rest || s->nv != nv || s->ne != nt * 3) {
        if (grow(s, nv, nt * 3) < 0)
            return NULL;
        for (int t = 0; t < nt; t++)
            for (int k = 0; k < 3; k++) {
                s->edges[(t * 3 + k) * 2 + 0] = tris[t * 3 + k];
                s->edges[(t * 3 + k) * 2 + 1] = tris[t * 3 + (k + 1) % 3];
            }
        s->nv = nv;
        s->ne = nt * 3;
        for (int e = 0; e < s->ne; e++)
            s->rest[e] = edge_len(xyz, &s->edges[e * 2]);
        s->have_rest = 1;
    }
    memset(s->vertex, 0, (size_t)nv * sizeof *s->vertex);
    for (int e = 0; e < s->ne; e++) {
        if (s->rest[e] <= 1e-6f)
            continue;
        float strain = (edge_len(xyz, &s->edges[e * 2]) - s->rest[e]) / s->rest[e];
        for (int k = 0; k < 2; k++) {
            float *v = &s->vertex[s->edges[e * 2 + k]];
            *v = strain > *v ? strain : *v;
        }
    }
    return s->vertex;
}
