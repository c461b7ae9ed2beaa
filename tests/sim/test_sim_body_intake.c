/* tryon-sim's body intake: triangle lists kept per topology id, the live one pinned against
 * strays, a bounded number of lists, and bodies over the sim's limits refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdlib.h>
#include <string.h>

#include "body_intake.h"

static const int32_t live_tris[] = {0, 1, 2, 1, 3, 2};
static const int32_t other_tris[] = {0, 2, 1};

static void test_lists_are_kept_and_found_by_id(void **state)
{
    (void)state;
    sim_topologies t;
    sim_topologies_init(&t, 100, 10);
    const sim_topology *s;
    sim_reject why = {0};
    assert_int_equal(sim_topologies_intake(&t, 1, 4, NULL, 0, 0, &s, &why), -SIM_ERR_TOPOLOGY);
    assert_int_equal(sim_topologies_intake(&t, 1, 4, live_tris, 2, 0, &s, &why), 0);
    assert_int_equal(s->nt, 2);
    uint32_t gen = s->gen;
    assert_int_equal(sim_topologies_intake(&t, 1, 4, NULL, 0, 10, &s, &why), 0);
    assert_memory_equal(s->tris, live_tris, sizeof live_tris);
    assert_int_equal(sim_topologies_intake(&t, 1, 4, live_tris, 2, 20, &s, &why), 0);
    assert_int_equal(s->gen, gen); /* the same list again is no new list */
    sim_topologies_free(&t);
}

static void test_strays_cannot_evict_the_live_list(void **state)
{
    (void)state;
    sim_topologies t;
    sim_topologies_init(&t, 100, 10);
    const sim_topology *s;
    sim_reject why = {0};
    assert_int_equal(sim_topologies_intake(&t, 1, 4, live_tris, 2, 0, &s, &why), 0);
    uint32_t gen = s->gen;
    sim_topologies_mark_live(&t, 1, 0);
    int64_t now = 1000;
    for (int32_t id = 2; id < 200; id++, now += 1000) { /* a new topology every millisecond */
        assert_int_equal(sim_topologies_intake(&t, id, 3, other_tris, 1, now, &s, &why),
                         -SIM_ERR_TOPOLOGY);
        assert_int_equal(sim_topologies_intake(&t, 1, 3, other_tris, 1, now, &s, &why),
                         -SIM_ERR_TOPOLOGY); /* the live id with other triangles */
        assert_int_equal(sim_topologies_intake(&t, 1, 4, NULL, 0, now, &s, &why), 0);
        assert_int_equal(s->gen, gen);
        sim_topologies_mark_live(&t, 1, now);
    }
    assert_int_equal(t.refused, 2 * 198);
    sim_topologies_free(&t);
}

static void test_a_stale_live_list_gives_way_within_the_bound(void **state)
{
    (void)state;
    sim_topologies t;
    sim_topologies_init(&t, 100, 10);
    const sim_topology *s;
    sim_reject why = {0};
    assert_int_equal(sim_topologies_intake(&t, 1, 4, live_tris, 2, 0, &s, &why), 0);
    sim_topologies_mark_live(&t, 1, 0);
    int64_t later = SIM_TOPOLOGY_LIVE_US; /* its sender stopped: another body may take over */
    for (int32_t id = 2; id < 50; id++) {
        assert_int_equal(sim_topologies_intake(&t, id, 3, other_tris, 1, later + id, &s, &why), 0);
        assert_int_equal(s->id, id);
    }
    int kept = 0;
    for (int i = 0; i < SIM_TOPOLOGY_SLOTS; i++)
        kept += t.slot[i].nt > 0;
    assert_int_equal(kept, SIM_TOPOLOGY_SLOTS); /* never more lists than slots */
    assert_int_equal(sim_topologies_intake(&t, 1, 3, other_tris, 1, later + 99, &s, &why), 0);
    sim_topologies_free(&t);
}

static void test_bodies_over_the_limits_are_refused(void **state)
{
    (void)state;
    sim_topologies t;
    sim_topologies_init(&t, 100, 1);
    const sim_topology *s;
    sim_reject why = {0};
    assert_int_equal(sim_topologies_intake(&t, 1, 4, live_tris, 2, 0, &s, &why),
                     -SIM_ERR_TOO_LARGE);
    assert_int_equal(sim_topologies_intake(&t, 1, 101, other_tris, 1, 0, &s, &why),
                     -SIM_ERR_TOO_LARGE);
    assert_non_null(strstr(why.detail, "101 vertices"));
    assert_int_equal(sim_topologies_intake(&t, 1, 3, other_tris, 1, 0, &s, &why), 0);
    sim_topologies_free(&t);
}

/* A body's motion is its median vertex's: 5 of 9 vertices moved 1 mm and 4 moved 100 mm (an arm
 * swinging) read 1 mm; a still body reads 0. */
static void test_body_motion_is_the_median_vertex(void **state)
{
    (void)state;
    enum { NV = 9 };
    float before[NV * 3] = {0}, now[NV * 3] = {0}, scratch[NV];
    assert_true(sim_body_motion_mm(before, now, NV, scratch) == 0.0f);
    for (int i = 0; i < NV; i++)
        now[3 * i + (i % 3)] = i < 5 ? 0.001f : -0.1f;
    float mm = sim_body_motion_mm(before, now, NV, scratch);
    assert_true(mm > 0.999f && mm < 1.001f);
    assert_true(sim_body_motion_mm(before, now, 0, scratch) == 0.0f);
}

static int by_value(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* The same as a sort's middle element on 1,001 vertices moved along x by scattered amounts, with
 * repeats (every value twice or more). */
static void test_body_motion_matches_a_sort(void **state)
{
    (void)state;
    enum { NV = 1001 };
    static float before[NV * 3], now[NV * 3], scratch[NV], sorted[NV];
    for (int i = 0; i < NV; i++) {
        now[3 * i] = 0.001f * (float)((i * 7919) % 400); /* 0..399 mm */
        sorted[i] = 1000.0f * now[3 * i];
    }
    qsort(sorted, NV, sizeof *sorted, by_value);
    float mm = sim_body_motion_mm(before, now, NV, scratch);
    assert_true(mm == sorted[NV / 2]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lists_are_kept_and_found_by_id),
        cmocka_unit_test(test_body_motion_is_the_median_vertex),
        cmocka_unit_test(test_body_motion_matches_a_sort),
        cmocka_unit_test(test_strays_cannot_evict_the_live_list),
        cmocka_unit_test(test_a_stale_live_list_gives_way_within_the_bound),
        cmocka_unit_test(test_bodies_over_the_limits_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
