/* The frame budget (sim_desc.frame_budget_ms, tryon-sim --frame-budget): settle rounds cut to
 * the time left and strain retries only when they fit; a frame cut short is published as it
 * stands, its strain measured, state SETTLING. Without a budget, or with one never reached,
 * nothing changes, bit for bit. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "budget.h"
#include "cloth.h"
#include "queue.h"
#include "sim_test_util.h"

enum { FRAMES = 12, FULL = SIM_SETTLE_ROUNDS / SIM_SETTLE_BATCH };

/* The cost model alone: no budget or nothing measured gives every settle test; with costs
 * learnt, the tests that fit in the time left; none when it is spent; a NaN cost is not learnt. */
static void test_budget_settle_tests_fit_the_time_left(void **state)
{
    (void)state;
    sim_budget b = {0};
    assert_int_equal(sim_budget_settle_tests(&b, 20.0, 0.0, 25, FULL), FULL);
    sim_frame_stats st = {.ms_feature_points = 1.0f, .ms_contacts = 2.0f, .settle_rounds = 0};
    int rounds = 25 + 1 + SIM_POST_ROUNDS; /* 0.5 ms each */
    st.ms_iterations = 0.5f * (float)rounds;
    sim_budget_learn_attempt(&b, &st, 25);
    assert_int_equal(sim_budget_settle_tests(&b, 0.0, 0.0, 25, FULL), FULL);
    /* 3 ms fixed + 15 ms of rounds: 2 ms left in 20, two batches of 0.5 ms rounds */
    assert_int_equal(sim_budget_settle_tests(&b, 20.0, 0.0, 25, FULL), 2);
    assert_int_equal(sim_budget_settle_tests(&b, 20.0, 1.0, 25, FULL), 1);
    assert_int_equal(sim_budget_settle_tests(&b, 20.0, 19.0, 25, FULL), 0);
    assert_int_equal(sim_budget_settle_tests(&b, 1e6, 0.0, 25, FULL), FULL);
    /* a retry's attempt of 50 steps has no time left for settle rounds */
    assert_int_equal(sim_budget_settle_tests(&b, 20.0, 0.0, 50, FULL), 0);
    st.ms_iterations = NAN;
    sim_budget_learn_attempt(&b, &st, 25);
    assert_true(b.round_ms == 0.5f);
    /* the tail after the attempts counts too */
    sim_frame_stats tail = {.ms_metrics = 1.0f};
    sim_budget_learn_tail(&b, &tail);
    assert_int_equal(sim_budget_settle_tests(&b, 20.0, 0.0, 25, FULL), 1);
}

/* A shirt of 1,000 vertices on the body scene's walk (a body of 4,000 vertices). */
static sim *walk_shirt(sim_backend b, float frame_budget_ms, sim_scene **sc)
{
    sim_garment g = {0};
    sim_reject why = {0};
    int nv, nt;
    assert_int_equal(simt_scene_shirt("walk", 4000, 1000, 0.0f, sc, &g, &nv, &nt), 0);
    sim_desc d = sim_default_desc();
    d.backend = b;
    d.frame_budget_ms = frame_budget_ms;
    d.max_body_vertices = nv;
    d.max_body_triangles = nt;
    sim *s = sim_create(&d, &g, &why);
    sim_garment_free(&g);
    assert_non_null(s);
    return s;
}

static void step(sim *s, sim_scene *sc, int f, sim_frame_stats *st)
{
    const float *xyz, *joints;
    const int32_t *tris;
    int nv, nt;
    assert_int_equal(sim_scene_eval(sc, f / 30.0, &xyz, &nv, &tris, &nt, &joints), 0);
    assert_int_equal(sim_step(s, xyz, nv, tris, nt, st, NULL), 0);
}

/* A budget too small for any settle round or retry (1 us): from the second frame (the first has
 * no costs measured yet) no settle round and no retry runs; a frame that ends over the strain the
 * rounds settle to is SETTLING, one under it and the retry goals OK; the strain
 * published is the cloth's own; nothing is NaN. The same walk without a budget settles. */
static void test_sim_budget_too_small_publishes_as_it_stands(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        sim_scene *sc, *sc_plain;
        sim *s = walk_shirt(bs[k], 1e-3f, &sc);
        sim *plain = walk_shirt(bs[k], 0.0f, &sc_plain);
        int settling = 0, settled_plain = 0;
        for (int f = 0; f < FRAMES; f++) {
            sim_frame_stats st, ref;
            step(s, sc, f, &st);
            step(plain, sc_plain, f, &ref);
            settled_plain += ref.settle_rounds > 0 || ref.strain_retries > 0;
            assert_true(simt_all_finite(s));
            float max_strain, p99;
            sim_strain_stats(&s->cloth, s->scratch, &max_strain, &p99);
            assert_true(max_strain == st.max_strain && p99 == st.p99_strain);
            if (f == 0)
                continue;
            assert_int_equal(st.settle_rounds, 0);
            assert_int_equal(st.retries, 0);
            /* over the settle rounds' strain: cut; over a retry goal only: cut unless the
               frame before missed them too (no retry then, sim.h) */
            int over = st.max_strain > SIM_RETRY_STRAIN || st.p99_strain > SIM_RETRY_P99;
            if (st.max_strain > SIM_SETTLE_STRAIN)
                assert_int_equal(st.state, SIM_STATE_SETTLING);
            else if (!over)
                assert_int_equal(st.state, SIM_STATE_OK);
            settling += st.state == SIM_STATE_SETTLING;
        }
        printf("# %s: a 1 us budget: %d of %d frames settling; without it %d frames settle or "
               "retry\n",
               simt_backend_name(bs[k]), settling, FRAMES - 1, settled_plain);
        assert_true(settled_plain >= 1);
        assert_true(settling >= 1);
        sim_destroy(s);
        sim_destroy(plain);
        sim_scene_destroy(sc);
        sim_scene_destroy(sc_plain);
    }
}

/* A budget no frame reaches (1,000 s) is no budget: the same cloth and statistics bit for bit,
 * settle rounds and all. A NaN budget is refused. */
/* A diverged frame past its deadline is not retried: it is carried (the garment as made, carried
 * onto the body), finite, and the next frame goes on; with time left, or without a deadline, it
 * is retried and recovered as before. Both backends. */
static void test_sim_budget_spent_carries_a_diverged_frame(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        for (int with_budget = 0; with_budget <= 1; with_budget++) {
            sim_scene *sc;
            sim *s = walk_shirt(bs[k], with_budget ? 1e-3f : 0.0f, &sc);
            sim_frame_stats st;
            for (int f = 0; f < 5; f++)
                step(s, sc, f, &st);
            sim_debug_set_vertex(s, 30, NAN, 0.0f, 0.0f);
            step(s, sc, 5, &st);
            printf("# %s, %s: a NaN: state %s, retries %d\n", simt_backend_name(bs[k]),
                   with_budget ? "a 1 us budget" : "no budget", sim_state_name(st.state),
                   st.retries);
            assert_int_equal(st.state, with_budget ? SIM_STATE_CARRIED : SIM_STATE_RECOVERED);
            assert_true(with_budget ? st.retries == 0 : st.retries >= 1);
            assert_true(simt_all_finite(s));
            step(s, sc, 6, &st);
            assert_true(st.state != SIM_STATE_DIVERGED);
            assert_true(simt_all_finite(s));
            sim_destroy(s);
            sim_scene_destroy(sc);
        }
    }
}

static void test_sim_budget_never_reached_changes_nothing(void **state)
{
    (void)state;
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        sim_scene *sc, *sc_plain;
        sim *s = walk_shirt(bs[k], 1e6f, &sc);
        sim *plain = walk_shirt(bs[k], 0.0f, &sc_plain);
        int rounds = 0;
        for (int f = 0; f < FRAMES; f++) {
            sim_frame_stats st, ref;
            step(s, sc, f, &st);
            step(plain, sc_plain, f, &ref);
            assert_int_equal(st.settle_rounds, ref.settle_rounds);
            assert_int_equal(st.retries, ref.retries);
            assert_int_equal(st.state, ref.state);
            assert_true(st.max_strain == ref.max_strain && st.p99_strain == ref.p99_strain);
            rounds += st.settle_rounds;
        }
        assert_memory_equal(sim_positions(s), sim_positions(plain),
                            (size_t)sim_vertex_count(s) * 4 * sizeof(float));
        printf("# %s: %d settle rounds in %d frames, the same with a budget never reached\n",
               simt_backend_name(bs[k]), rounds, FRAMES);
        sim_destroy(s);
        sim_destroy(plain);
        sim_scene_destroy(sc);
        sim_scene_destroy(sc_plain);
    }
    sim_desc d = sim_default_desc();
    d.frame_budget_ms = NAN;
    sim_garment g = {0};
    sim_reject why = {0};
    assert_int_equal(sim_garment_drape(64, 0.5f, 1.0f, &g), 0);
    assert_null(sim_create(&d, &g, &why));
    assert_int_equal(why.code, SIM_ERR_PARAM);
    sim_garment_free(&g);
}

/* The pace learnt from the bodies: the camera's period from capture times over seq steps (a
 * dropped frame skips a seq), the arrival from bodies that found the sim waiting only; the
 * budget ends the frame, publishing included, by the next body's arrival or the deadline. */
static void test_pace_deadline_from_the_bodies(void **state)
{
    (void)state;
    sim_pace p = {0};
    const int64_t t0 = 1700000000000000;                                /* wall clock, us */
    assert_true(sim_pace_budget_ms(&p, t0, t0, 45.0f, 20.0f) == 20.0f); /* nothing learnt */
    sim_pace_body(&p, 0, t0, t0 + 20000, 1);
    sim_pace_body(&p, 2, t0 + 66000, t0 + 86000, 1);  /* seq 1 dropped: 33 ms a frame */
    sim_pace_body(&p, 3, t0 + 99000, t0 + 189000, 0); /* queued: 90 ms not learnt */
    assert_float_equal(p.period_ms, 33.0f, 1e-3f);
    assert_float_equal(p.arrive_ms, 20.0f, 1e-3f);
    sim_pace_published(&p, 1.0f);
    /* started 20 ms after capture: the deadline (45) is before the next arrival (53) */
    assert_float_equal(sim_pace_budget_ms(&p, t0, t0 + 20000, 45.0f, 20.0f), 24.0f, 1e-3f);
    assert_float_equal(sim_pace_budget_ms(&p, t0, t0 + 20000, 0.0f, 20.0f), 32.0f, 1e-3f);
    assert_float_equal(sim_pace_budget_ms(&p, t0, t0 + 20000, 60.0f, 20.0f), 32.0f, 1e-3f);
    /* started past the deadline: the shortest frame, never 0 (no budget at all to sim_step) */
    assert_true(sim_pace_budget_ms(&p, t0, t0 + 60000, 45.0f, 20.0f) == SIM_PACE_MIN_MS);
    /* a body captured 2 s ago (a log played again): the fallback */
    assert_true(sim_pace_budget_ms(&p, t0, t0 + 2000000, 45.0f, 20.0f) == 20.0f);
    /* a restarted body stage (seq back to 0), a paused recording: no period learnt from them */
    sim_pace_body(&p, 0, t0 + 132000, t0 + 152000, 1);
    sim_pace_body(&p, 1, t0 + 5000000, t0 + 5020000, 1);
    assert_float_equal(p.period_ms, 33.0f, 1e-3f);
    sim_pace_body(&p, 2, t0 + 5033000, t0 + 5033000 - 5000, 1); /* a clock step: not learnt */
    assert_float_equal(p.arrive_ms, 20.0f, 1e-3f);
}

/* A sim stage on a timeline, driven by budget.c: bodies captured at 30 fps arrive after a fitting
 * latency that jitters (10-30 ms); a frame costs FIXED_MS plus ROUND_MS for each round, and wants
 * every settle round it may run (the walk's worst case), and every spike_every-th frame spike_ms
 * more (a frame that lost its core, the walk's steps). As tryon-sim's loop, through its queue
 * (bus_queue, --queue depth): an idle sim takes the body that arrives, a busy one the oldest
 * waiting on finishing; a body arriving at a full queue supersedes the oldest.
 * budget_ms > 0: that budget every frame; 0: the pace's deadline (--frame-budget auto). */
enum { PACE_BODIES = 600, PACE_ITERS = 25 };
#define FIXED_MS   12.0
#define ROUND_MS   0.4
#define TAIL_MS    0.2
#define PUBLISH_MS 0.5
#define PERIOD_MS  (1000.0 / 30.0)

typedef struct pace_run {
    int superseded, simulated, over_deadline, rounds;
    double latency_max_ms, wait_max_ms; /* capture -> published; arrival -> frame started */
    double latency_p95_ms;
} pace_run;

typedef struct pace_setup {
    float budget_ms, deadline_ms;
    int depth, spike_every;
    double spike_ms;
} pace_setup;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double fit_latency_ms(int k)
{
    return 10.0 + (double)((k * 7919) % 21); /* 10..30 ms, every value, no order */
}

static int64_t us(double ms)
{
    return (int64_t)llround(ms * 1000.0);
}

/* One frame of body k started at now: its cost, learnt by the budget as sim.c's driver does. */
static double frame_ms(sim_budget *b, float budget_ms, double spent_ms, int *rounds)
{
    int tests = sim_budget_settle_tests(b, budget_ms, spent_ms, PACE_ITERS, FULL);
    *rounds = tests * SIM_SETTLE_BATCH;
    int all = PACE_ITERS + 1 + SIM_POST_ROUNDS + *rounds;
    sim_frame_stats st = {.ms_feature_points = (float)(FIXED_MS / 2),
                          .ms_contacts = (float)(FIXED_MS / 2),
                          .ms_iterations = (float)(ROUND_MS * all),
                          .settle_rounds = *rounds};
    sim_budget_learn_attempt(b, &st, PACE_ITERS);
    sim_frame_stats tail = {.ms_metrics = (float)TAIL_MS};
    sim_budget_learn_tail(b, &tail);
    return FIXED_MS + ROUND_MS * all + TAIL_MS;
}

static pace_run run_stage(pace_setup ps)
{
    float budget_ms = ps.budget_ms, deadline_ms = ps.deadline_ms;
    sim_budget b = {0};
    sim_pace p = {0};
    pace_run r = {0};
    bus_queue q;
    bus_queue_init(&q, ps.depth);
    int waiting[BUS_QUEUE_MAX];
    static double latency[PACE_BODIES];
    double now = 0.0, published = -1.0;
    int next = 0;
    while (next < PACE_BODIES || q.count) {
        if (!q.count && now < next * PERIOD_MS + fit_latency_ms(next))
            now = next * PERIOD_MS + fit_latency_ms(next); /* idle: woken by the next body */
        while (next < PACE_BODIES && next * PERIOD_MS + fit_latency_ms(next) <= now) {
            int supersedes, slot = bus_queue_slot(&q, &supersedes);
            r.superseded += supersedes;
            waiting[slot] = next;
            bus_queue_commit(&q);
            sim_pace_body(&p, next, us(next * PERIOD_MS), us(now), now - published > 1.0);
            next++;
        }
        int k = waiting[bus_queue_take(&q)];
        if (k > 1 && now - (k * PERIOD_MS + fit_latency_ms(k)) > r.wait_max_ms)
            r.wait_max_ms = now - (k * PERIOD_MS + fit_latency_ms(k));
        double capture = k * PERIOD_MS, start = now;
        float budget = budget_ms > 0.0f
                           ? budget_ms
                           : sim_pace_budget_ms(&p, us(capture), us(now), deadline_ms, 20.0f);
        int rounds;
        now += frame_ms(&b, budget, 0.0, &rounds) + PUBLISH_MS;
        if (ps.spike_every > 0 && k % ps.spike_every == ps.spike_every - 1)
            now += ps.spike_ms;
        latency[r.simulated] = now - capture;
        sim_pace_published(&p, (float)PUBLISH_MS);
        published = now;
        r.simulated++;
        r.rounds += rounds;
        /* a frame with time for its fixed part ends by its deadline */
        double fixed = FIXED_MS + ROUND_MS * (PACE_ITERS + 1 + SIM_POST_ROUNDS) + TAIL_MS;
        if (budget_ms <= 0.0f && k > 1 && start + fixed + PUBLISH_MS <= capture + deadline_ms &&
            now > capture + deadline_ms + 1e-3)
            r.over_deadline++;
        if (now - capture > r.latency_max_ms && k > 1)
            r.latency_max_ms = now - capture;
    }
    qsort(latency, (size_t)r.simulated, sizeof *latency, cmp_double);
    r.latency_p95_ms = latency[(int)(0.95 * r.simulated)];
    return r;
}

/* The stage costs fit the frame interval (a frame without settle rounds: 23.5 ms of 33): with
 * the pace's deadline no body is superseded, each frame with time for its fixed part ends by
 * its deadline, and the frames still get settle rounds. A fixed budget of the frame interval,
 * blind to the publishing and to a late start, falls behind on the same timeline: bodies
 * superseded, and a longer wait and latency. */
static void test_pace_supersedes_no_body_when_costs_fit(void **state)
{
    (void)state;
    pace_run a = run_stage((pace_setup){.deadline_ms = 45.0f, .depth = 1});
    pace_run next = run_stage((pace_setup){.depth = 1});
    pace_run fixed = run_stage((pace_setup){.budget_ms = (float)PERIOD_MS, .depth = 1});
    printf("# %d bodies at 30 fps: --frame-budget auto (deadline 45 ms): %d superseded, settle "
           "rounds %.1f a body, latency max %.1f ms, wait max %.1f ms; the next arrival only: %d, "
           "%.1f, %.1f, %.1f ms; a fixed 33.3 ms: %d superseded, %.1f rounds, %.1f, %.1f ms\n",
           PACE_BODIES, a.superseded, (double)a.rounds / a.simulated, a.latency_max_ms,
           a.wait_max_ms, next.superseded, (double)next.rounds / next.simulated,
           next.latency_max_ms, next.wait_max_ms, fixed.superseded,
           (double)fixed.rounds / fixed.simulated, fixed.latency_max_ms, fixed.wait_max_ms);
    assert_int_equal(a.superseded, 0);
    assert_int_equal(a.simulated, PACE_BODIES);
    assert_int_equal(a.over_deadline, 0);
    assert_true(a.latency_max_ms < fixed.latency_max_ms && a.wait_max_ms < fixed.wait_max_ms);
    assert_true(a.rounds > 0);
    assert_int_equal(next.superseded, 0);
    assert_true(next.rounds > a.rounds); /* later deadline, more rounds */
    assert_true(fixed.superseded > 0);
}

/* A frame in 40 overruns by 30 ms (its fixed part 55 ms against the camera's 33). With only the
 * newest body waiting (--queue latest) the body that arrives during it and the one after meet,
 * and one is superseded; with two allowed to wait (--queue 2, the default) every body is
 * simulated, the one that waited late and without settle rounds: the latency of the frames
 * after the overrun rises (here the p95 by 5 ms), no frame is later than the overrun itself. An
 * overrun of three periods supersedes with either. */
static void test_queue_of_two_absorbs_an_overrun(void **state)
{
    (void)state;
    pace_setup ps = {.deadline_ms = 45.0f, .depth = 1, .spike_every = 40, .spike_ms = 30.0};
    pace_run one = run_stage(ps);
    ps.depth = 2;
    pace_run two = run_stage(ps);
    ps.spike_ms = 90.0; /* an overrun of about three periods: the queue of two supersedes */
    pace_run long_two = run_stage(ps);
    printf("# a frame in 40 30 ms longer: --queue latest %d superseded, latency p95 %.1f max %.1f "
           "ms; --queue 2: %d, %.1f, %.1f ms; 90 ms longer, --queue 2: %d, %.1f, %.1f ms\n",
           one.superseded, one.latency_p95_ms, one.latency_max_ms, two.superseded,
           two.latency_p95_ms, two.latency_max_ms, long_two.superseded, long_two.latency_p95_ms,
           long_two.latency_max_ms);
    assert_true(one.superseded > 0);
    assert_int_equal(two.superseded, 0);
    assert_int_equal(two.simulated, PACE_BODIES);
    assert_true(two.latency_p95_ms <= one.latency_p95_ms + 10.0);
    assert_true(two.latency_max_ms <= one.latency_max_ms + 1e-9);
    assert_true(long_two.superseded > 0);
    assert_true(long_two.superseded + long_two.simulated == PACE_BODIES);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_budget_settle_tests_fit_the_time_left),
        cmocka_unit_test(test_pace_deadline_from_the_bodies),
        cmocka_unit_test(test_pace_supersedes_no_body_when_costs_fit),
        cmocka_unit_test(test_queue_of_two_absorbs_an_overrun),
        cmocka_unit_test(test_sim_budget_too_small_publishes_as_it_stands),
        cmocka_unit_test(test_sim_budget_never_reached_changes_nothing),
        cmocka_unit_test(test_sim_budget_spent_carries_a_diverged_frame),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
