/* Measuring the rest mesh the way a tape would: slice with a plane, keep the loop around the
 * torso or limb (the one enclosing a reference point), take its perimeter. */
#include "body_internal.h"

#include <math.h>
#include <stdlib.h>

typedef struct slice_key {
    uint64_t edge;
    int seg;
} slice_key;

typedef struct slice_seg {
    float p[2][2]; /* endpoints in plane coordinates */
    float len;
} slice_seg;

static int key_cmp(const void *x, const void *y)
{
    const slice_key *a = x, *b = y;
    if (a->edge != b->edge)
        return a->edge < b->edge ? -1 : 1;
    return (a->seg > b->seg) - (a->seg < b->seg);
}

static int uf_find(int *p, int x)
{
    while (p[x] != x) {
        p[x] = p[p[x]];
        x = p[x];
    }
    return x;
}

static void plane_basis(const float n[3], float u[3], float w[3])
{
    float a[3] = {1, 0, 0};
    if (fabsf(n[0]) > 0.8f)
        a[0] = 0, a[1] = 1;
    float d = body_dot(a, n);
    for (int k = 0; k < 3; ++k)
        u[k] = a[k] - d * n[k];
    float l = sqrtf(body_dot(u, u));
    for (int k = 0; k < 3; ++k)
        u[k] /= l;
    w[0] = n[1] * u[2] - n[2] * u[1];
    w[1] = n[2] * u[0] - n[0] * u[2];
    w[2] = n[0] * u[1] - n[1] * u[0];
}

/* Cuts triangle t by the plane; fills the segment and its two edge keys. */
static int cut_triangle(const float *v, const int32_t *t, const float *pt, const float *n,
                        const float *u, const float *w, slice_seg *seg, uint64_t keys[2])
{
    float s[3];
    for (int e = 0; e < 3; ++e) {
        const float *p = v + (size_t)t[e] * 3;
        float d[3] = {p[0] - pt[0], p[1] - pt[1], p[2] - pt[2]};
        s[e] = body_dot(d, n);
    }
    int k = 0;
    for (int e = 0; e < 3 && k < 2; ++e) {
        int a = t[e], b = t[(e + 1) % 3];
        float sa = s[e], sb = s[(e + 1) % 3];
        if ((sa < 0.0f) == (sb < 0.0f))
            continue;
        const float *pa = v + (size_t)a * 3, *pb = v + (size_t)b * 3;
        float r = sa / (sa - sb), q[3];
        for (int c = 0; c < 3; ++c)
            q[c] = pa[c] + r * (pb[c] - pa[c]) - pt[c];
        seg->p[k][0] = body_dot(q, u);
        seg->p[k][1] = body_dot(q, w);
        uint32_t lo = (uint32_t)(a < b ? a : b), hi = (uint32_t)(a < b ? b : a);
        keys[k++] = ((uint64_t)lo << 32) | hi;
    }
    if (k != 2)
        return 0;
    float dx = seg->p[1][0] - seg->p[0][0], dy = seg->p[1][1] - seg->p[0][1];
    seg->len = sqrtf(dx * dx + dy * dy);
    return 1;
}

/* Does the ray from the origin along +u cross the segment? */
static int ray_crosses(const slice_seg *s)
{
    float y0 = s->p[0][1], y1 = s->p[1][1];
    if ((y0 > 0.0f) == (y1 > 0.0f))
        return 0;
    float x = s->p[0][0] + (s->p[1][0] - s->p[0][0]) * (0.0f - y0) / (y1 - y0);
    return x > 0.0f;
}

float body_slice_girth(const float *v, const int32_t *t, int nt, const float point[3],
                       const float normal[3])
{
    float n[3] = {normal[0], normal[1], normal[2]}, u[3], w[3];
    float ln = sqrtf(body_dot(n, n));
    if (!(ln > 0.0f))
        return -1.0f;
    for (int k = 0; k < 3; ++k)
        n[k] /= ln;
    plane_basis(n, u, w);
    slice_seg *seg = malloc((size_t)nt * sizeof(slice_seg));
    slice_key *key = malloc((size_t)nt * 2 * sizeof(slice_key));
    int *parent = malloc((size_t)nt * sizeof(int));
    double *per = calloc((size_t)nt, sizeof(double));
    int *cross = calloc((size_t)nt, sizeof(int));
    float best = -1.0f;
    if (!seg || !key || !parent || !per || !cross)
        goto done;
    int ns = 0;
    for (int i = 0; i < nt; ++i) {
        uint64_t k2[2];
        if (!cut_triangle(v, t + (size_t)i * 3, point, n, u, w, &seg[ns], k2))
            continue;
        key[2 * ns] = (slice_key){k2[0], ns};
        key[2 * ns + 1] = (slice_key){k2[1], ns};
        parent[ns] = ns;
        ++ns;
    }
    qsort(key, (size_t)ns * 2, sizeof(slice_key), key_cmp);
    for (int i = 1; i < ns * 2; ++i) {
        if (key[i].edge != key[i - 1].edge)
            continue;
        int a = uf_find(parent, key[i].seg), b = uf_find(parent, key[i - 1].seg);
        if (a != b)
            parent[a] = b;
    }
    for (int i = 0; i < ns; ++i) {
        int r = uf_find(parent, i);
        per[r] += seg[i].len;
        cross[r] += ray_crosses(&seg[i]);
    }
    /* The innermost loop around the point: odd crossings, smallest perimeter. */
    for (int i = 0; i < ns; ++i)
        if (parent[i] == i && (cross[i] & 1) && (best < 0.0f || per[i] < best))
            best = (float)per[i];
done:
    free(seg);
    free(key);
    free(parent);
    free(per);
    free(cross);
    return best;
}

static float dist3(const float *a, const float *b)
{
    float d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return sqrtf(body_dot(d, d));
}

int body_measure(const float *v, int nv, const int32_t *t, int nt, const body_skeleton *sk,
                 fit_measurements *out)
{
    if (!v || !t || nv <= 0 || nt <= 0 || !out)
        return -FIT_ERR_ARG;
    fit_shape *s = &out->shape;
    float top = v[1];
    for (int i = 1; i < nv; ++i)
        top = fmaxf(top, v[(size_t)i * 3 + 1]);
    s->height = top;
    s->shoulder_width = dist3(sk->joint[FIT_L_SHOULDER], sk->joint[FIT_R_SHOULDER]);
    s->arm_length = dist3(sk->joint[FIT_L_SHOULDER], sk->joint[FIT_L_WRIST]);
    s->leg_length = dist3(sk->joint[FIT_L_HIP], sk->joint[FIT_L_ANKLE]);
    const float up[3] = {0, 1, 0};
    float pc[3] = {0, sk->chest_y, 0}, pw[3] = {0, sk->waist_y, 0}, ph[3] = {0, sk->hip_y, 0};
    out->chest_y = sk->chest_y;
    out->waist_y = sk->waist_y;
    out->hip_y = sk->hip_y;
    s->chest_girth = body_slice_girth(v, t, nt, pc, up);
    s->waist_girth = body_slice_girth(v, t, nt, pw, up);
    s->hip_girth = body_slice_girth(v, t, nt, ph, up);
    float al = body_slice_girth(v, t, nt, sk->arm_point[0], sk->arm_dir[0]);
    float ar = body_slice_girth(v, t, nt, sk->arm_point[1], sk->arm_dir[1]);
    float ll = body_slice_girth(v, t, nt, sk->leg_point[0], sk->leg_dir[0]);
    float lr = body_slice_girth(v, t, nt, sk->leg_point[1], sk->leg_dir[1]);
    s->arm_girth = 0.5f * (al + ar);
    s->leg_girth = 0.5f * (ll + lr);
    if (s->chest_girth < 0 || s->waist_girth < 0 || s->hip_girth < 0 || al < 0 || ar < 0 ||
        ll < 0 || lr < 0)
        return -FIT_ERR_MEASURE;
    return 0;
}
