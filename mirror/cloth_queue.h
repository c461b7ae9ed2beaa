/* Private to mirror/: the meshes tryon-mirror keeps between messages, and the CLOTH waiting to be
 * drawn (mirror/cloth_queue.c). */
#ifndef TRYON_MIRROR_CLOTH_QUEUE_H
#define TRYON_MIRROR_CLOTH_QUEUE_H

#include "bus.h"
#include "queue.h"

/* A mesh message kept between frames: triangles arrive only now and then (topology_id). */
typedef struct mirror_held {
    float *xyz;
    int nv, v_cap;
    int32_t *tris;
    int nt, t_cap;
    int32_t topology;
    int64_t utime_capture, received_us;
    int32_t seq;
} mirror_held;

/* Keeps a mesh: its vertices, and its triangles when nidx > 0 (else the ones kept for this
 * topology; tris NULL with nidx 0: the vertices alone). -1, the mesh not drawable: no triangles
 * yet for this topology, a triangle past the vertices, out of memory. */
int mirror_hold(mirror_held *h, const float *xyz, int ncoords, const int32_t *tris, int nidx,
                int32_t topology);
void mirror_held_free(mirror_held *h);

/* The CLOTH waiting to be drawn, oldest first, at most `depth` (bus/queue.h): with 1 only the
 * newest is drawn; with 2 (tryon-mirror's default) a person's entry, when the sim publishes a
 * few catching up while the mirror waits for a core, loses fewer frames (docs/mirror.md). The
 * garment's triangles are kept once, as last sent; a CLOTH waiting with a topology replaced
 * since (another garment) is passed over. */
typedef struct mirror_cloth_queue {
    mirror_held tris;                   /* the garment's triangles, by topology */
    mirror_held waiting[BUS_QUEUE_MAX]; /* vertices, capture time, seq, arrival */
    bus_queue queue;
    int skipped;    /* refused: no triangles for the topology, one past the vertices, memory */
    int superseded; /* replaced by newer ones at a full queue, or of a replaced topology */
} mirror_cloth_queue;

void mirror_cloth_queue_init(mirror_cloth_queue *q, int depth);
void mirror_cloth_queue_free(mirror_cloth_queue *q);
/* A CLOTH arrives (received_us: its arrival, wall clock): 0 waiting, -1 skipped (counted). */
int mirror_cloth_queue_push(mirror_cloth_queue *q, const tryon_cloth_t *c, int64_t received_us);
/* The oldest waiting becomes `drawn` (vertices, triangles, capture time, seq, arrival): 1, or 0
 * when none waits. */
int mirror_cloth_queue_take(mirror_cloth_queue *q, mirror_held *drawn);
int mirror_cloth_queue_count(const mirror_cloth_queue *q);

#endif
