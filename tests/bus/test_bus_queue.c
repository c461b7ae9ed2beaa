/* bus/queue.c: a live stage's waiting frames, oldest first, the oldest superseded at a full queue,
 * nothing changed by a frame that was never committed. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "queue.h"

static void test_queue_keeps_order_and_supersedes_the_oldest(void **state)
{
    (void)state;
    bus_queue q;
    int frame[BUS_QUEUE_MAX], sup, superseded = 0;
    bus_queue_init(&q, 2);
    assert_int_equal(bus_queue_take(&q), -1);
    for (int k = 0; k < 5; k++) { /* frames 0..4 arrive while the stage is busy */
        frame[bus_queue_slot(&q, &sup)] = k;
        superseded += sup;
        bus_queue_commit(&q);
    }
    assert_int_equal(superseded, 3);
    assert_int_equal(q.count, 2);
    assert_int_equal(frame[bus_queue_take(&q)], 3); /* the two newest, oldest first */
    frame[bus_queue_slot(&q, &sup)] = 5;            /* one arrives while 3 is worked on */
    assert_int_equal(sup, 0);
    bus_queue_commit(&q);
    assert_int_equal(frame[bus_queue_take(&q)], 4);
    assert_int_equal(frame[bus_queue_take(&q)], 5);
    assert_int_equal(bus_queue_take(&q), -1);
}

/* A frame found bad while it is written (never committed) replaces nothing: the oldest still
 * waits and is taken first. */
static void test_queue_uncommitted_frame_changes_nothing(void **state)
{
    (void)state;
    bus_queue q;
    int frame[BUS_QUEUE_MAX], sup;
    bus_queue_init(&q, 1);
    frame[bus_queue_slot(&q, &sup)] = 7;
    bus_queue_commit(&q);
    int slot = bus_queue_slot(&q, &sup);
    assert_int_equal(sup, 1); /* full: this one would supersede 7 ... */
    (void)slot;               /* ... but is refused before its commit */
    assert_int_equal(frame[bus_queue_take(&q)], 7);
}

/* A depth out of 1..BUS_QUEUE_MAX is taken as the nearest bound. */
static void test_queue_depth_bounds(void **state)
{
    (void)state;
    bus_queue q;
    bus_queue_init(&q, 0);
    assert_int_equal(q.depth, 1);
    bus_queue_init(&q, 1000);
    assert_int_equal(q.depth, BUS_QUEUE_MAX);
    int sup, n = 0;
    for (int k = 0; k < 3 * BUS_QUEUE_MAX; k++) {
        bus_queue_slot(&q, &sup);
        n += sup;
        bus_queue_commit(&q);
    }
    assert_int_equal(n, 2 * BUS_QUEUE_MAX);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_queue_keeps_order_and_supersedes_the_oldest),
        cmocka_unit_test(test_queue_uncommitted_frame_changes_nothing),
        cmocka_unit_test(test_queue_depth_bounds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
