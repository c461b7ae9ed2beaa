/* A live stage's queue of waiting frames; see queue.h. */
#include "queue.h"

void bus_queue_init(bus_queue *q, int depth)
{
    q->depth = depth < 1 ? 1 : depth > BUS_QUEUE_MAX ? BUS_QUEUE_MAX : depth;
    q->head = 0;
    q->count = 0;
}

int bus_queue_slot(const bus_queue *q, int *supersedes)
{
    *supersedes = q->count == q->depth;
    return *supersedes ? q->head : (q->head + q->count) % q->depth;
}

void bus_queue_commit(bus_queue *q)
{
    if (q->count == q->depth)
        q->head = (q->head + 1) % q->depth; /* the oldest was written over */
    else
        q->count++;
}

int bus_queue_take(bus_queue *q)
{
    if (q->count == 0)
        return -1;
    int slot = q->head;
    q->head = (q->head + 1) % q->depth;
    q->count--;
    return slot;
}
