/* A live stage's queue of waiting frames: which to take next, which a newer one supersedes. */
#ifndef TRYON_BUS_QUEUE_H
#define TRYON_BUS_QUEUE_H

/* The frames waiting for a live stage, oldest first, at most `depth` (1..BUS_QUEUE_MAX) of
 * them: one arriving at a full queue supersedes the oldest waiting. Depth 1 keeps only the newest
 * (a frame that overruns the camera's period by any amount loses one); depth 2 lets one frame
 * overrun by up to a period with every frame still taken, the one that waited then late (and, in
 * tryon-sim, short: its deadline is near; docs/pipeline.md, "Live: the newest body wins"). The
 * queue holds slot numbers; the frames themselves live in the caller's array. */
#define BUS_QUEUE_MAX 4
typedef struct bus_queue {
    int depth, head, count;
} bus_queue;

/* depth out of 1..BUS_QUEUE_MAX is taken as the nearest bound. */
void bus_queue_init(bus_queue *q, int depth);
/* The slot the next frame is written into, and whether that replaces the oldest frame waiting
 * (*supersedes = 1: the queue is full). Nothing changes until bus_queue_commit: a frame found bad
 * while it is written replaces nothing. */
int bus_queue_slot(const bus_queue *q, int *supersedes);
/* The frame written into bus_queue_slot's slot now waits behind the others. */
void bus_queue_commit(bus_queue *q);
/* The oldest frame waiting, taken out of the queue (its slot stays as it is until a later commit
 * writes it), or -1 when none waits. */
int bus_queue_take(bus_queue *q);

#endif
