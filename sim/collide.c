/* The collider: body frames in, contacts cached, points pushed out, penetration measured.
 * Twin: kernels/collide.cl. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collide.h"
#include "collide_bvh.h"
#include "collide_geometry.h"
#include "edge_sort.h"

#define DEFAULT_THICKNESS_M 0.004f /* sim.h default: cloth kept 4 mm off the skin */
#define DEFAULT_REACH_M                                                                            \
    0.03f /* 3 cm: a wrist at 3 m/s moves 10 cm a frame, but the feature                           \
             points carry the swept cloth; contacts only need the rest */
/* Steps of the contact walk: a point moves a few triangles at most between searches. */
#define WALK_MAX_STEPS 8
/* Twice the area (m^2) below which a triangle is degenerate: a 0.1 mm sliver of a 1 mm edge. */
#define DEGENERATE_2AREA_M2 1e-10f
/* vn_stamp of a vertex pseudo-normal being written (body_epoch is never negative). */
#define SIM_VN_BUSY (-2)

typedef struct edge_key {
    int64_t key; /* min vertex * nv + max vertex */
    int32_t tri, edge;
} edge_key;

sim_collider *sim_collider_create(const sim_collider_desc *d, char *err, size_t err_size)
{
    if (!d || d->max_vertices < 3 || d->max_triangles < 1 || !(d->thickness_m >= 0.0f) ||
        !(d->friction >= 0.0f) || !(d->reach_m >= 0.0f) || d->max_cloth < 0) {
        snprintf(err, err_size,
                 "collider: bad description (need max_vertices >= 3, max_triangles >= 1, "
                 "thickness, friction, reach >= 0)");
        return NULL;
    }
    sim_collider *c = calloc(1, sizeof *c);
    if (!c)
        goto nomem;
    c->d = *d;
    if (c->d.thickness_m == 0.0f)
        c->d.thickness_m = DEFAULT_THICKNESS_M;
    if (c->d.reach_m == 0.0f)
        c->d.reach_m = DEFAULT_REACH_M;
    size_t nv = (size_t)d->max_vertices, nt = (size_t)d->max_triangles;
    c->v = malloc(nv * sizeof *c->v);
    c->v_prev = malloc(nv * sizeof *c->v_prev);
    c->tris = malloc(nt * sizeof *c->tris);
    c->n = malloc(nt * sizeof *c->n);
    c->n_prev = malloc(nt * sizeof *c->n_prev);
    c->n_next = malloc(nt * sizeof *c->n_next);
    c->nbr = malloc(nt * sizeof *c->nbr);
    c->vt_start = malloc((nv + 1) * sizeof *c->vt_start);
    c->vt_list = malloc(3 * nt * sizeof *c->vt_list);
    c->edge_scratch = malloc(6 * nt * sizeof(edge_key)); /* the edges, and sorted */
    c->vn = malloc(nv * sizeof *c->vn);
    c->vn_stamp = malloc(nv * sizeof *c->vn_stamp);
    c->share = aligned_alloc(_Alignof(sim_contact_slot), SIM_SHARE_SLOTS * sizeof *c->share);
    if (!c->v || !c->v_prev || !c->tris || !c->n || !c->n_prev || !c->n_next || !c->nbr ||
        !c->vt_start || !c->vt_list || !c->edge_scratch || !c->vn || !c->vn_stamp || !c->share)
        goto nomem;
    for (size_t i = 0; i < nv; i++)
        atomic_init(&c->vn_stamp[i], -1);
    for (int i = 0; i < SIM_SHARE_SLOTS; i++) {
        atomic_init(&c->share[i].word, 0); /* generation 0: closed */
        atomic_init(&c->share[i].x, 0);
        atomic_init(&c->share[i].begin, 0);
        atomic_init(&c->share[i].end, 0);
    }
    if (sim_bvh_init(&c->bvh, d->max_triangles) != 0)
        goto nomem;
    if (d->max_cloth > 0 && sim_collider_reserve(c, d->max_cloth) != 0)
        goto nomem;
    return c;
nomem:
    snprintf(err, err_size, "collider: out of memory for %d vertices, %d triangles",
             d->max_vertices, d->max_triangles);
    sim_collider_destroy(c);
    return NULL;
}

void sim_collider_destroy(sim_collider *c)
{
    if (!c)
        return;
    free(c->v);
    free(c->v_prev);
    free(c->tris);
    free(c->n);
    free(c->n_prev);
    free(c->n_next);
    free(c->nbr);
    free(c->vt_start);
    free(c->vt_list);
    free(c->edge_scratch);
    free(c->vn);
    free(c->vn_stamp);
    free(c->share);
    free(c->contact);
    free(c->clear);
    free(c->quiet);
    free(c->quiet_key);
    sim_bvh_free(&c->bvh);
    free(c);
}

void sim_collider_restart(sim_collider *c)
{
    if (!c)
        return;
    for (int i = 0; i < c->max_cloth; i++) {
        c->contact[i] = -1;
        c->clear[i][3] = 0.0f;
        c->quiet[i][3] = 0.0f;
        c->quiet_key[i][0] = -1;
        c->quiet_key[i][1] = 0;
    }
    c->restarted = 1;
}

int sim_collider_reserve(sim_collider *c, int max_cloth)
{
    if (!c || max_cloth < 0)
        return -SIM_ERR_ARG;
    if (max_cloth <= c->max_cloth)
        return 0;
    int32_t *p = realloc(c->contact, (size_t)max_cloth * sizeof *p);
    if (!p)
        return -SIM_ERR_NO_MEMORY;
    c->contact = p;
    float(*q)[4] = realloc(c->clear, (size_t)max_cloth * sizeof *q);
    if (!q)
        return -SIM_ERR_NO_MEMORY;
    c->clear = q;
    float(*qu)[4] = realloc(c->quiet, (size_t)max_cloth * sizeof *qu);
    if (!qu)
        return -SIM_ERR_NO_MEMORY;
    c->quiet = qu;
    int32_t(*qk)[2] = realloc(c->quiet_key, (size_t)max_cloth * sizeof *qk);
    if (!qk)
        return -SIM_ERR_NO_MEMORY;
    c->quiet_key = qk;
    for (int i = c->max_cloth; i < max_cloth; i++) {
        p[i] = -1;
        q[i][3] = 0.0f;
        qu[i][3] = 0.0f;
        qk[i][0] = -1;
        qk[i][1] = 0;
    }
    c->max_cloth = max_cloth;
    return 0;
}

const sim_bvh *sim_collider_bvh(const sim_collider *c)
{
    return &c->bvh;
}

const int32_t *sim_collider_contacts(const sim_collider *c)
{
    return c->contact;
}

int sim_collider_body(const sim_collider *c, const float (**v)[4], const float (**v_prev)[4],
                      const int32_t (**tris)[4], const float (**n)[4])
{
    *v = (const float(*)[4])c->v;
    *v_prev = (const float(*)[4])c->v_prev;
    *tris = (const int32_t(*)[4])c->tris;
    *n = (const float(*)[4])c->n;
    return c->nt;
}

static void set_bary(float q[3], float bary[3], const float *a, const float *b, const float *c,
                     float u, float v, float w)
{
    bary[0] = u;
    bary[1] = v;
    bary[2] = w;
    for (int k = 0; k < 3; k++)
        q[k] = u * a[k] + v * b[k] + w * c[k];
}

int sim_closest_on_triangle(const float p[3], const float a[3], const float b[3], const float c[3],
                            float q[3], float bary[3])
{
    float ab[3], ac[3], ap[3], bp[3], cp[3];
    sim_v3_sub(b, a, ab);
    sim_v3_sub(c, a, ac);
    sim_v3_sub(p, a, ap);
    float d1 = sim_v3_dot(ab, ap), d2 = sim_v3_dot(ac, ap);
    if (d1 <= 0.0f && d2 <= 0.0f) {
        set_bary(q, bary, a, b, c, 1.0f, 0.0f, 0.0f);
        return SIM_REGION_V0;
    }
    sim_v3_sub(p, b, bp);
    float d3 = sim_v3_dot(ab, bp), d4 = sim_v3_dot(ac, bp);
    if (d3 >= 0.0f && d4 <= d3) {
        set_bary(q, bary, a, b, c, 0.0f, 1.0f, 0.0f);
        return SIM_REGION_V1;
    }
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) {
        float v = d1 / (d1 - d3);
        set_bary(q, bary, a, b, c, 1.0f - v, v, 0.0f);
        return SIM_REGION_E01;
    }
    sim_v3_sub(p, c, cp);
    float d5 = sim_v3_dot(ab, cp), d6 = sim_v3_dot(ac, cp);
    if (d6 >= 0.0f && d5 <= d6) {
        set_bary(q, bary, a, b, c, 0.0f, 0.0f, 1.0f);
        return SIM_REGION_V2;
    }
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) {
        float w = d2 / (d2 - d6);
        set_bary(q, bary, a, b, c, 1.0f - w, 0.0f, w);
        return SIM_REGION_E20;
    }
    float va = d3 * d6 - d5 * d4;
    if (va <= 0.0f && d4 - d3 >= 0.0f && d5 - d6 >= 0.0f) {
        float w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        set_bary(q, bary, a, b, c, 0.0f, 1.0f - w, w);
        return SIM_REGION_E12;
    }
    float denom = 1.0f / (va + vb + vc);
    float v = vb * denom, w = vc * denom;
    set_bary(q, bary, a, b, c, 1.0f - v - w, v, w);
    return SIM_REGION_FACE;
}

/* Reject a body before touching the collider: the caller keeps the last good one. The area test
   has each triangle's cross product: its unit face normal goes to n_next (as the frame's normals,
   once the body is accepted). */
static int validate_body(sim_collider *c, const float *xyz, int nv, const int32_t *tris, int nt)
{
    if (!xyz || !tris || nv < 0 || nt < 0)
        return -SIM_ERR_ARG;
    if (nv == 0 || nt == 0)
        return -SIM_ERR_EMPTY;
    if (nv > c->d.max_vertices || nt > c->d.max_triangles)
        return -SIM_ERR_TOO_LARGE;
    for (int i = 0; i < 3 * nv; i++)
        if (!isfinite(xyz[i]))
            return -SIM_ERR_NOT_FINITE;
    for (int t = 0; t < nt; t++) {
        const int32_t *f = tris + 3 * t;
        for (int k = 0; k < 3; k++)
            if (f[k] < 0 || f[k] >= nv)
                return -SIM_ERR_INDEX;
        if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0])
            return -SIM_ERR_DEGENERATE;
        float e1[3], e2[3], cr[3];
        sim_v3_sub(xyz + 3 * f[1], xyz + 3 * f[0], e1);
        sim_v3_sub(xyz + 3 * f[2], xyz + 3 * f[0], e2);
        sim_v3_cross(e1, e2, cr);
        float len = sqrtf(sim_v3_dot(cr, cr));
        if (!(len > DEGENERATE_2AREA_M2))
            return -SIM_ERR_DEGENERATE;
        for (int k = 0; k < 3; k++)
            c->n_next[t][k] = cr[k] / len;
        c->n_next[t][3] = 0.0f;
    }
    return 0;
}

static int cmp_edge(const void *pa, const void *pb)
{
    const edge_key *a = pa, *b = pb;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return a->tri != b->tri ? (a->tri < b->tri ? -1 : 1) : a->edge - b->edge;
}

/* Per topology: triangles across each edge and the triangles around each vertex. */
static void build_adjacency(sim_collider *c)
{
    int nv = c->nv, nt = c->nt;
    edge_key *e = c->edge_scratch, *sorted = e + 3 * nt;
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int32_t a = c->tris[t][k], b = c->tris[t][(k + 1) % 3];
            int32_t lo = a < b ? a : b, hi = a < b ? b : a;
            e[3 * t + k] = (edge_key){(int64_t)lo * nv + hi, t, k};
            c->nbr[t][k] = -1;
        }
    sim_edge_sort(e, 3 * nt, sizeof *e, nv, cmp_edge, sorted, c->vt_start);
    e = sorted;
    for (int i = 0; i + 1 < 3 * nt; i++)
        if (e[i].key == e[i + 1].key) {
            c->nbr[e[i].tri][e[i].edge] = e[i + 1].tri;
            c->nbr[e[i + 1].tri][e[i + 1].edge] = e[i].tri;
            i++; /* a non-manifold edge pairs its triangles two by two */
        }
    memset(c->vt_start, 0, (size_t)(nv + 1) * sizeof *c->vt_start);
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            c->vt_start[c->tris[t][k] + 1]++;
    for (int i = 0; i < nv; i++)
        c->vt_start[i + 1] += c->vt_start[i];
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            c->vt_list[c->vt_start[c->tris[t][k]]++] = t;
    /* The fill advanced each start to the next vertex's start: shift back by one. */
    for (int i = nv; i > 0; i--)
        c->vt_start[i] = c->vt_start[i - 1];
    c->vt_start[0] = 0;
}

static int same_topology(const sim_collider *c, int nv, const int32_t *tris, int nt)
{
    if (c->nt != nt || c->nv != nv)
        return 0;
    for (int t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++)
            if (c->tris[t][k] != tris[3 * t + k])
                return 0;
    return 1;
}

int sim_collider_set_body(sim_collider *c, const float *xyz, int nv, const int32_t *tris, int nt)
{
    if (!c)
        return -SIM_ERR_ARG;
    int rc = validate_body(c, xyz, nv, tris, nt);
    if (rc != 0)
        return rc;
    int had_body = c->nt > 0;
    int same = same_topology(c, nv, tris, nt);
    c->body_epoch =
        (c->body_epoch + 1) & 0x3fffffff; /* voids every quiet radius (sim_collider_resolve) */
    for (int i = 0; i < c->max_cloth; i++)
        c->clear[i][3] = 0.0f; /* the bounds were for the old body frame */
    /* the validation's normals become frame k's (k's become k-1's on the same topology) */
    float(*tn)[4] = c->n_next;
    if (same) {
        float(*tv)[4] = c->v_prev;
        c->v_prev = c->v;
        c->v = tv;
        c->n_next = c->n_prev;
        c->n_prev = c->n;
    } else {
        c->n_next = c->n;
    }
    c->n = tn;
    for (int i = 0; i < nv; i++) {
        c->v[i][0] = xyz[3 * i];
        c->v[i][1] = xyz[3 * i + 1];
        c->v[i][2] = xyz[3 * i + 2];
        c->v[i][3] = 0.0f;
    }
    if (same) {
        if (c->restarted) { /* no sweep into the frame a new garment was made on */
            memcpy(c->v_prev, c->v, (size_t)nv * sizeof *c->v);
            memcpy(c->n_prev, c->n, (size_t)nt * sizeof *c->n);
        }
        sim_bvh_refit(&c->bvh, (const float(*)[4])c->v_prev, (const float(*)[4])c->v,
                      (const int32_t(*)[4])c->tris, c->d.thickness_m);
        c->have_prev = !c->restarted;
        c->restarted = 0;
        return 0;
    }
    c->restarted = 0;
    c->nv = nv;
    c->nt = nt;
    for (int t = 0; t < nt; t++) {
        c->tris[t][0] = tris[3 * t];
        c->tris[t][1] = tris[3 * t + 1];
        c->tris[t][2] = tris[3 * t + 2];
        c->tris[t][3] = 0;
    }
    memcpy(c->v_prev, c->v, (size_t)nv * sizeof *c->v);
    memcpy(c->n_prev, c->n, (size_t)nt * sizeof *c->n);
    build_adjacency(c);
    sim_bvh_build(&c->bvh, (const float(*)[4])c->v_prev, (const float(*)[4])c->v,
                  (const int32_t(*)[4])c->tris, nt, c->d.thickness_m);
    for (int i = 0; i < c->max_cloth; i++)
        c->contact[i] = -1;
    c->have_prev = 0;
    return had_body ? -SIM_ERR_TOPOLOGY : 0;
}

/* acos by Abramowitz & Stegun 4.4.45 (error <= 6.7e-5 rad): only + - * / and sqrt, all
   correctly rounded, so kernels/collide.cl computes the very same bits where a library acos
   may differ by an ulp (and an ulp in a contact normal grows over the iterations). */
float sim_acos(float x)
{
    float a = fabsf(x);
    float p = 1.5707288f + a * (-0.2121144f + a * (0.0742610f + a * -0.0187293f));
    float r = sqrtf(1.0f - a) * p;
    return x >= 0.0f ? r : 3.14159265f - r;
}

/* Interior angle of triangle t at its corner k. */
static float corner_angle(const sim_collider *c, int t, int k)
{
    const float *p = c->v[c->tris[t][k]], *a = c->v[c->tris[t][(k + 1) % 3]],
                *b = c->v[c->tris[t][(k + 2) % 3]];
    float u[3], w[3];
    sim_v3_sub(a, p, u);
    sim_v3_sub(b, p, w);
    float cs = sim_v3_dot(u, w) / sqrtf(sim_v3_dot(u, u) * sim_v3_dot(w, w));
    cs = cs > 1.0f ? 1.0f : (cs < -1.0f ? -1.0f : cs);
    return sim_acos(cs);
}

/* Bærentzen & Aanæs 2005: the normals of the triangles around vertex vi weighted by their
   angles there, summed in vertex-to-triangle order. */
static void vertex_pseudo_normal(const sim_collider *c, int vi, float out[3])
{
    out[0] = out[1] = out[2] = 0.0f;
    for (int j = c->vt_start[vi]; j < c->vt_start[vi + 1]; j++) {
        int f = c->vt_list[j];
        int k = c->tris[f][0] == vi ? 0 : (c->tris[f][1] == vi ? 1 : 2);
        float a = corner_angle(c, f, k);
        for (int m = 0; m < 3; m++)
            out[m] += a * c->n[f][m];
    }
}

void sim_collider_pseudo_normal(const sim_collider *c, int t, int region, float out[3])
{
    if (region == SIM_REGION_FACE) {
        memcpy(out, c->n[t], 3 * sizeof *out);
        return;
    }
    if (region >= SIM_REGION_E01) {
        /* Edge: both faces weigh pi. */
        int o = c->nbr[t][region - SIM_REGION_E01];
        for (int k = 0; k < 3; k++)
            out[k] = c->n[t][k] + (o >= 0 ? c->n[o][k] : c->n[t][k]);
        return;
    }
    /* A vertex: from the cache when this body frame's is there (the response asks for the same
       few hundred vertices in every iteration; computing all 10,000 per frame would cost more). */
    int vi = c->tris[t][region - SIM_REGION_V0];
    atomic_int *stamp = &c->vn_stamp[vi];
    int seen = atomic_load_explicit(stamp, memory_order_acquire);
    if (seen == c->body_epoch) {
        memcpy(out, c->vn[vi], 3 * sizeof *out);
        return;
    }
    vertex_pseudo_normal(c, vi, out);
    if (seen != SIM_VN_BUSY &&
        atomic_compare_exchange_strong_explicit(stamp, &seen, SIM_VN_BUSY, memory_order_acquire,
                                                memory_order_relaxed)) {
        memcpy(c->vn[vi], out, 3 * sizeof *out);
        c->vn[vi][3] = 0.0f;
        atomic_store_explicit(stamp, c->body_epoch, memory_order_release);
    }
}

float sim_collider_signed_distance_at(const sim_collider *c, int t, const float p[3],
                                      const float q[3], int region)
{
    float d[3], pn[3];
    sim_v3_sub(p, q, d);
    float dist = sqrtf(sim_v3_dot(d, d));
    if (region == SIM_REGION_FACE)
        return sim_v3_dot(d, c->n[t]);
    sim_collider_pseudo_normal(c, t, region, pn);
    return sim_v3_dot(d, pn) >= 0.0f ? dist : -dist;
}

float sim_collider_signed_distance(const sim_collider *c, int t, const float p[3])
{
    float q[3], bary[3];
    const int32_t *f = c->tris[t];
    int region = sim_closest_on_triangle(p, c->v[f[0]], c->v[f[1]], c->v[f[2]], q, bary);
    return sim_collider_signed_distance_at(c, t, p, q, region);
}

/* Squared distance from p to triangle t and the region of its closest point. */
static float tri_dist2(const sim_collider *c, int t, const float p[3], int *region)
{
    float q[3], bary[3], d[3];
    const int32_t *f = c->tris[t];
    *region = sim_closest_on_triangle(p, c->v[f[0]], c->v[f[1]], c->v[f[2]], q, bary);
    sim_v3_sub(p, q, d);
    return sim_v3_dot(d, d);
}

/* Greedy descent over the body surface from triangle t: while the closest point lies on an edge
   or a vertex, try the triangles around that feature's vertices and move to the nearest. Ends at
   a local minimum of the distance (the global one on a smooth patch). */
int sim_collider_walk_nearest(const sim_collider *c, const float p[3], int t, float *d2_out)
{
    int region;
    float d2 = tri_dist2(c, t, p, &region);
    for (int step = 0; step < WALK_MAX_STEPS && region != SIM_REGION_FACE; step++) {
        int verts[2], nvert = 1;
        if (region <= SIM_REGION_V2) {
            verts[0] = c->tris[t][region - SIM_REGION_V0];
        } else {
            int e = region - SIM_REGION_E01;
            verts[0] = c->tris[t][e];
            verts[1] = c->tris[t][(e + 1) % 3];
            nvert = 2;
        }
        int best = t, best_region = region;
        float best_d2 = d2;
        for (int k = 0; k < nvert; k++)
            for (int j = c->vt_start[verts[k]]; j < c->vt_start[verts[k] + 1]; j++) {
                int o = c->vt_list[j], r;
                if (o == best)
                    continue;
                float od2 = tri_dist2(c, o, p, &r);
                if (od2 < best_d2 || (od2 == best_d2 && o < best)) {
                    best = o, best_d2 = od2, best_region = r;
                }
            }
        if (best == t)
            break;
        t = best, d2 = best_d2, region = best_region;
    }
    *d2_out = d2;
    return t;
}

void sim_collider_track_contacts(sim_collider *c, const float (*x)[4], int begin, int end)
{
    if (!c || !x || c->nt == 0)
        return;
    end = end < c->max_cloth ? end : c->max_cloth;
    float reach = c->d.thickness_m + c->d.reach_m;
    const float(*v)[4] = (const float(*)[4])c->v;
    const int32_t(*tris)[4] = (const int32_t(*)[4])c->tris;
#pragma omp parallel for schedule(static)
    for (int i = begin; i < end; i++) {
        int t = c->contact[i];
        if (t >= 0 && t < c->nt) {
            float d2;
            t = sim_collider_walk_nearest(c, x[i], t, &d2);
            c->contact[i] = d2 <= reach * reach ? t : -1;
        } else {
            float q[3], bary[3], dist;
            t = sim_bvh_nearest(&c->bvh, v, tris, x[i], reach, q, bary, &dist);
            if (t < 0 && !sim_collider_clearly_outside(c, x[i]))
                t = sim_bvh_nearest(&c->bvh, v, tris, x[i], INFINITY, q, bary, &dist);
            c->contact[i] = t;
        }
    }
}
