/* Shape changes that keep the mesh's topology: the rest mesh and skeleton scaled vertically
 * about the floor (height, and the lengths with it; ADAPT_ACROSS of it across), then each vertex
 * moved along its rest normal by its part's girth offset (torso, arms, legs; blended by the
 * skinning weights so the parts meet smoothly). A girth grows by 2 pi times the offset. Cheap
 * enough to refine every frame, and the published mesh keeps its triangles, so tryon-sim follows
 * it. */
#include "fit_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define ADAPT_PI 3.14159265358979
/* How much of the height's scale applies across the body: none measured best (slim_tall and
 * broad_short, still and walk: 11.2 mm against 13.6 at half and 16.7 at all; docs/bodyfit.md).
 * Girths then come from the offsets alone. */
#define ADAPT_ACROSS 0.0f

int fit_shape_base_init(fit_shape_base *b, const fit_model *m)
{
    int nv = m->mesh.nv;
    memset(b, 0, sizeof *b);
    b->v = malloc((size_t)nv * 3 * sizeof(float));
    b->n = malloc((size_t)nv * 3 * sizeof(float));
    if (!b->v || !b->n) {
        fit_shape_base_free(b);
        return -FIT_ERR_NOMEM;
    }
    memcpy(b->v, m->mesh.v, (size_t)nv * 3 * sizeof(float));
    int rc = fit_model_normals(m, m->mesh.v, b->n);
    if (rc) {
        fit_shape_base_free(b);
        return rc;
    }
    memcpy(b->joint, m->sk.joint, sizeof b->joint);
    b->shape = m->shape;
    b->nv = nv;
    return 0;
}

void fit_shape_base_free(fit_shape_base *b)
{
    free(b->v);
    free(b->n);
    b->v = b->n = NULL;
}

int fit_shape_part(int joint)
{
    if (joint <= FIT_HEAD)
        return 0;
    return joint < FIT_L_HIP ? 1 : 2;
}

void fit_shape_base_apply(const fit_shape_base *b, fit_model *m, float scale,
                          const float offset[FIT_SHAPE_PARTS])
{
    float h = 1.0f + ADAPT_ACROSS * (scale - 1.0f);
    float sk[3] = {h, scale, h};
    for (int i = 0; i < b->nv; ++i) {
        const uint8_t *wj = m->wjoint + (size_t)i * FIT_MAX_INFLUENCES;
        const float *ww = m->weight + (size_t)i * FIT_MAX_INFLUENCES;
        float d = 0.0f;
        for (int k = 0; k < FIT_MAX_INFLUENCES; ++k)
            d += ww[k] * offset[fit_shape_part(wj[k])];
        for (int k = 0; k < 3; ++k)
            m->mesh.v[(size_t)i * 3 + k] =
                sk[k] * b->v[(size_t)i * 3 + k] + d * b->n[(size_t)i * 3 + k];
    }
    for (int j = 0; j < FIT_JOINT_COUNT; ++j)
        for (int k = 0; k < 3; ++k)
            m->sk.joint[j][k] = sk[k] * b->joint[j][k];
}

fit_shape fit_shape_adapted(const fit_shape_base *b, float scale,
                            const float offset[FIT_SHAPE_PARTS])
{
    float a[FIT_SHAPE_PARAMS];
    fit_shape_to_array(&b->shape, a);
    float across = 1.0f + ADAPT_ACROSS * (scale - 1.0f);
    a[0] *= scale, a[7] *= scale; /* height, leg length: vertical */
    /* The A-pose arm runs at 45 degrees: half its length squared is vertical. */
    a[5] *= sqrtf(0.5f * (scale * scale + across * across));
    a[1] *= across; /* shoulder width */
    for (int i = 2; i < FIT_SHAPE_PARAMS; ++i)
        if (i == 2 || i == 3 || i == 4 || i == 6 || i == 8)
            a[i] *= across;
    float g0 = (float)(2.0 * ADAPT_PI * offset[0]), g1 = (float)(2.0 * ADAPT_PI * offset[1]);
    float g2 = (float)(2.0 * ADAPT_PI * offset[2]);
    a[2] += g0, a[3] += g0, a[4] += g0; /* chest, waist, hip */
    a[6] += g1;                         /* arm */
    a[8] += g2;                         /* leg */
    return fit_shape_from_array(a);
}
