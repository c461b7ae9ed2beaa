/* Triangle lists per topology id with a pinned live one; see body_intake.h. */
#include "body_intake.h"

#include "cloth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sim_topologies_init(sim_topologies *t, int max_vertices, int max_triangles)
{
    memset(t, 0, sizeof *t);
    t->max_vertices = max_vertices;
    t->max_triangles = max_triangles;
}

void sim_topologies_free(sim_topologies *t)
{
    for (int i = 0; i < SIM_TOPOLOGY_SLOTS; i++)
        free(t->slot[i].tris);
    memset(t->slot, 0, sizeof t->slot);
}

static int pinned(const sim_topologies *t, int32_t id, int64_t now_us)
{
    return t->has_live && t->live_id == id && now_us - t->live_us < SIM_TOPOLOGY_LIVE_US;
}

static sim_topology *find(sim_topologies *t, int32_t id)
{
    for (int i = 0; i < SIM_TOPOLOGY_SLOTS; i++)
        if (t->slot[i].nt > 0 && t->slot[i].id == id)
            return &t->slot[i];
    return NULL;
}

/* A free slot, else the least recently used one that is not pinned (one always exists: only
 * one id is live). */
static sim_topology *victim(sim_topologies *t, int64_t now_us)
{
    sim_topology *v = NULL;
    for (int i = 0; i < SIM_TOPOLOGY_SLOTS; i++) {
        sim_topology *s = &t->slot[i];
        if (s->nt == 0)
            return s;
        if (!pinned(t, s->id, now_us) && (!v || s->used_us < v->used_us))
            v = s;
    }
    return v;
}

static int store(sim_topology *s, int32_t id, const int32_t *tris, int nt, uint32_t *gen,
                 sim_reject *why)
{
    int32_t *copy = realloc(s->tris, (size_t)nt * 3 * sizeof *copy);
    if (!copy)
        return sim_reject_set(why, SIM_ERR_NO_MEMORY, "topology %d: %d triangles", (int)id, nt);
    memcpy(copy, tris, (size_t)nt * 3 * sizeof *copy);
    s->tris = copy;
    s->nt = nt;
    s->id = id;
    s->gen = ++*gen;
    return 0;
}

int sim_topologies_intake(sim_topologies *t, int32_t id, int nv, const int32_t *tris, int nt,
                          int64_t now_us, const sim_topology **out, sim_reject *why)
{
    if (nv < 0 || nv > t->max_vertices || nt < 0 || nt > t->max_triangles || (nt > 0 && !tris)) {
        t->refused++;
        return sim_reject_set(why, SIM_ERR_TOO_LARGE,
                              "body of %d vertices, %d triangles (topology %d; max %d, %d)", nv, nt,
                              (int)id, t->max_vertices, t->max_triangles);
    }
    if (t->has_live && id != t->live_id && pinned(t, t->live_id, now_us)) {
        t->refused++;
        return sim_reject_set(why, SIM_ERR_TOPOLOGY,
                              "topology %d while the garment lives on topology %d", (int)id,
                              (int)t->live_id);
    }
    sim_topology *s = find(t, id);
    if (nt == 0 && !s)
        return sim_reject_set(why, SIM_ERR_TOPOLOGY, "no triangles for topology %d yet", (int)id);
    if (nt > 0) {
        int same = s && s->nt == nt && memcmp(s->tris, tris, (size_t)nt * 3 * sizeof *tris) == 0;
        if (s && !same && pinned(t, id, now_us)) {
            t->refused++;
            return sim_reject_set(why, SIM_ERR_TOPOLOGY,
                                  "topology %d is live with %d triangles: another list of %d "
                                  "refused",
                                  (int)id, s->nt, nt);
        }
        if (!s)
            s = victim(t, now_us);
        if (!same) {
            int r = store(s, id, tris, nt, &t->next_gen, why);
            if (r < 0)
                return r;
        }
    }
    s->used_us = now_us;
    if (t->has_live && id == t->live_id && pinned(t, id, now_us))
        t->live_us = now_us; /* its sender is alive */
    *out = s;
    return 0;
}

void sim_topologies_mark_live(sim_topologies *t, int32_t id, int64_t now_us)
{
    t->has_live = 1;
    t->live_id = id;
    t->live_us = now_us;
}

/* The k-th smallest of v[0..n) (Hoare's selection: linear on average, a frame's body in about a
 * tenth of a sort); v is reordered. */
static float select_kth(float *v, int n, int k)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        float pivot = v[lo + (hi - lo) / 2];
        int i = lo, j = hi;
        while (i <= j) {
            while (v[i] < pivot)
                i++;
            while (v[j] > pivot)
                j--;
            if (i <= j) {
                float t = v[i];
                v[i++] = v[j];
                v[j--] = t;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return v[k];
    }
    return v[k];
}

float sim_body_motion_mm(const float *before, const float *now, int nv, float *scratch)
{
    if (nv <= 0)
        return 0.0f;
    for (int i = 0; i < nv; i++) {
        float dx = now[3 * i] - before[3 * i], dy = now[3 * i + 1] - before[3 * i + 1],
              dz = now[3 * i + 2] - before[3 * i + 2];
        scratch[i] = 1000.0f * sqrtf(dx * dx + dy * dy + dz * dz);
    }
    return select_kth(scratch, nv, nv / 2);
}
