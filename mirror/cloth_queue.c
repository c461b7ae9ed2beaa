/* tryon-mirror's meshes between messages and its queue of CLOTH to draw (cloth_queue.h). */
#include "cloth_queue.h"

#include <stdlib.h>
#include <string.h>

static int keep_vertices(mirror_held *h, const float *xyz, int ncoords)
{
    int nv = ncoords / 3;
    if (nv > h->v_cap) {
        float *p = realloc(h->xyz, (size_t)ncoords * sizeof *p);
        if (!p)
            return -1;
        h->xyz = p;
        h->v_cap = nv;
    }
    memcpy(h->xyz, xyz, (size_t)ncoords * sizeof *xyz);
    h->nv = nv;
    return 0;
}

int mirror_hold(mirror_held *h, const float *xyz, int ncoords, const int32_t *tris, int nidx,
                int32_t topology)
{
    if (nidx == 0 && !tris) /* the vertices alone (a CLOTH waiting: its triangles kept apart) */
        return keep_vertices(h, xyz, ncoords);
    if (nidx == 0 && (topology != h->topology || !h->tris))
        return -1; /* triangles not seen yet for this topology */
    if (keep_vertices(h, xyz, ncoords) < 0)
        return -1;
    if (nidx > 0) {
        if (nidx / 3 > h->t_cap) {
            int32_t *t = realloc(h->tris, (size_t)nidx * sizeof *t);
            if (!t)
                return -1;
            h->tris = t;
            h->t_cap = nidx / 3;
        }
        memcpy(h->tris, tris, (size_t)nidx * sizeof *tris);
        h->nt = nidx / 3;
        h->topology = topology;
    }
    for (int i = 0; i < h->nt * 3; i++) /* old triangles, new vertex count: not drawable */
        if (h->tris[i] >= h->nv)
            return -1;
    return 0;
}

void mirror_held_free(mirror_held *h)
{
    free(h->xyz);
    free(h->tris);
    memset(h, 0, sizeof *h);
}

void mirror_cloth_queue_init(mirror_cloth_queue *q, int depth)
{
    memset(q, 0, sizeof *q);
    bus_queue_init(&q->queue, depth);
}

void mirror_cloth_queue_free(mirror_cloth_queue *q)
{
    mirror_held_free(&q->tris);
    for (int k = 0; k < BUS_QUEUE_MAX; k++)
        mirror_held_free(&q->waiting[k]);
}

int mirror_cloth_queue_push(mirror_cloth_queue *q, const tryon_cloth_t *c, int64_t received_us)
{
    int nv = c->num_vertex_coords / 3;
    /* its triangles, when it carries them, become the garment's: checked against its vertices */
    if (c->num_triangle_indices > 0 &&
        mirror_hold(&q->tris, c->vertices, c->num_vertex_coords, c->triangles,
                    c->num_triangle_indices, c->topology_id) < 0) {
        q->skipped++;
        return -1;
    }
    int drawable = q->tris.tris && q->tris.topology == c->topology_id;
    for (int i = 0; drawable && i < q->tris.nt * 3; i++)
        drawable = q->tris.tris[i] < nv;
    int supersedes, k = bus_queue_slot(&q->queue, &supersedes);
    mirror_held *w = &q->waiting[k];
    if (!drawable || keep_vertices(w, c->vertices, c->num_vertex_coords) < 0) {
        q->skipped++; /* nothing waiting is replaced */
        return -1;
    }
    w->topology = c->topology_id;
    w->utime_capture = c->utime_capture;
    w->seq = c->seq;
    w->received_us = received_us;
    bus_queue_commit(&q->queue);
    q->superseded += supersedes;
    return 0;
}

int mirror_cloth_queue_take(mirror_cloth_queue *q, mirror_held *drawn)
{
    for (int k; (k = bus_queue_take(&q->queue)) >= 0;) {
        const mirror_held *w = &q->waiting[k];
        if (w->topology != q->tris.topology) { /* another garment since */
            q->superseded++;
            continue;
        }
        int new_tris = drawn->topology != w->topology || !drawn->tris;
        if (mirror_hold(drawn, w->xyz, w->nv * 3, q->tris.tris, new_tris ? q->tris.nt * 3 : 0,
                        w->topology) < 0) {
            q->skipped++;
            continue;
        }
        drawn->utime_capture = w->utime_capture;
        drawn->seq = w->seq;
        drawn->received_us = w->received_us;
        return 1;
    }
    return 0;
}

int mirror_cloth_queue_count(const mirror_cloth_queue *q)
{
    return q->queue.count;
}
