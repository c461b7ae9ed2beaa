/* The contact search called by a team, each thread with its own range (as the solver calls it),
 * where threads done with their range take chunks of the others' (sim/find_contacts.c): the
 * contacts and clearance bounds are bit for bit those of one thread searching all the points,
 * for teams of 2 to 5 threads, uneven ranges, an empty range, and threads that do not call.
 * And the search again of a point that moved past its clearance (sim_collider_research), also one
 * the frame's search found nothing within reach for. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <cmocka.h>

#include "collide.h"
#include "test_collide_util.h"

#define NP 3000

typedef struct fixture {
    sim_collider *c;
    float (*x)[4];
    int32_t contact[NP];
    float clear[NP][4];
    int early; /* a thread found its range unfinished when the search returned */
} fixture;

/* A sphere of 0.2 m and points around it: in contact, far outside, and deep inside. */
static void make(fixture *f)
{
    float *xyz;
    int32_t *tris;
    int nv, nt;
    tc_sphere(0.2f, 32, 24, &xyz, &nv, &tris, &nt);
    char err[128];
    f->c = sim_collider_create(&(sim_collider_desc){.max_vertices = nv,
                                                    .max_triangles = nt,
                                                    .thickness_m = 0.004f,
                                                    .friction = 0.3f,
                                                    .reach_m = 0.03f,
                                                    .max_cloth = NP},
                               err, sizeof err);
    assert_non_null(f->c);
    assert_int_equal(sim_collider_set_body(f->c, xyz, nv, tris, nt), 0);
    free(xyz);
    free(tris);
    f->x = malloc(NP * sizeof *f->x);
    uint32_t s = 4711u;
    for (int i = 0; i < NP; i++) {
        float dir[3];
        tc_direction(&s, dir);
        /* the first third in contact, then far ones, then some inside, so ranges differ in cost */
        float r = i < NP / 3 ? tc_range(&s, 0.2f, 0.23f)
                             : (i % 7 == 0 ? tc_range(&s, 0.0f, 0.15f) : tc_range(&s, 0.3f, 0.6f));
        for (int k = 0; k < 3; k++)
            f->x[i][k] = r * dir[k];
        f->x[i][3] = 1.0f;
    }
}

static void reset(fixture *f)
{
    f->early = 0;
    for (int i = 0; i < NP; i++)
        f->c->contact[i] = -1;
    memset(f->c->clear, 0, NP * sizeof *f->c->clear);
}

static void check_same(const fixture *f)
{
    assert_int_equal(f->early, 0);
    assert_memory_equal(f->c->contact, f->contact, sizeof f->contact);
    assert_memory_equal(f->c->clear, f->clear, sizeof f->clear);
}

/* Thread k of team of t gets a range proportional to (k + 1)^2 (the last one empty when
   empty_last); threads listed in skip do not call. */
static void team_search(fixture *f, int t, int empty_last, int skip)
{
#ifdef _OPENMP
#pragma omp parallel num_threads(t)
    {
        int k = omp_get_thread_num(), n = omp_get_num_threads(), parts = 0, before = 0;
        int m = empty_last ? n - 1 : n;
        for (int j = 0; j < m; j++) {
            parts += (j + 1) * (j + 1);
            before += j < k ? (j + 1) * (j + 1) : 0;
        }
        int vb = k < m ? (int)((long)NP * before / parts) : NP;
        int ve = k < m ? (int)((long)NP * (before + (k + 1) * (k + 1)) / parts) : NP;
        if (k != skip) {
            sim_collider_find_contacts(f->c, (const float(*)[4])f->x, vb, ve);
            /* done when it returns, also the chunks other threads took */
            if (memcmp(f->c->contact + vb, f->contact + vb, (size_t)(ve - vb) * sizeof(int32_t)))
#pragma omp atomic write
                f->early = 1;
        }
#pragma omp barrier
#pragma omp master
        if (skip >= 0 && skip < n) { /* the skipped range, by one thread on its own */
            int pb = 0;
            for (int j = 0; j < skip; j++)
                pb += (j + 1) * (j + 1);
            sim_collider_find_contacts(f->c, (const float(*)[4])f->x, (int)((long)NP * pb / parts),
                                       (int)((long)NP * (pb + (skip + 1) * (skip + 1)) / parts));
        }
    }
#else
    (void)empty_last;
    (void)skip;
    (void)t;
    sim_collider_find_contacts(f->c, (const float(*)[4])f->x, 0, NP);
#endif
}

static void test_collide_find_contacts_by_a_team_equals_one_thread(void **state)
{
    (void)state;
    fixture f;
    make(&f);
    reset(&f);
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    sim_collider_find_contacts(f.c, (const float(*)[4])f.x, 0, NP);
    memcpy(f.contact, f.c->contact, sizeof f.contact);
    memcpy(f.clear, f.c->clear, sizeof f.clear);
    int in = 0, none = 0;
    for (int i = 0; i < NP; i++) {
        in += f.contact[i] >= 0;
        none += f.contact[i] < 0;
    }
    assert_true(in > NP / 4 && none > NP / 4); /* both kinds of points are there */
    for (int t = 2; t <= 5; t++)
        for (int variant = 0; variant < 3; variant++) {
            reset(&f);
            team_search(&f, t, variant == 1, variant == 2 ? 1 : -1);
            check_same(&f);
            /* again with the cache as hints, as from frame to frame */
            team_search(&f, t, variant == 1, variant == 2 ? 1 : -1);
            check_same(&f);
        }
    free(f.x);
    sim_collider_destroy(f.c);
}

/* Points far outside (nothing within reach): one moved a centimetre stays without a contact; one
   moved onto the surface, past its clearance, gets the triangle under it and the response puts
   it out at the thickness. The solver's steps rely on this, not on searching every point again
   (sim/solver_c.c, stage_contacts); without it the second point was left 1 mm from the sphere. */
static void test_collide_research_finds_a_point_that_had_no_contact(void **state)
{
    (void)state;
    fixture f;
    make(&f);
    reset(&f);
    float far[2][4] = {{0.0f, 0.3f, 0.0f, 1.0f}, {0.3f, 0.0f, 0.0f, 1.0f}};
    float prev[2][4];
    memcpy(f.x, far, sizeof far);
    sim_collider_find_contacts(f.c, (const float(*)[4])f.x, 0, 2);
    assert_int_equal(sim_collider_contacts(f.c)[0], -1);
    assert_int_equal(sim_collider_contacts(f.c)[1], -1);
    f.x[0][1] = 0.29f;  /* 1 cm: within the clearance (thickness + reach) */
    f.x[1][0] = 0.201f; /* onto the sphere of 0.2 m, within the thickness */
    memcpy(prev, f.x, sizeof prev);
    sim_collider_research(f.c, (const float(*)[4])f.x, 0, 2);
    assert_int_equal(sim_collider_contacts(f.c)[0], -1);
    assert_true(sim_collider_contacts(f.c)[1] >= 0);
    sim_collider_resolve(f.c, f.x, prev, 0, 2);
    float r = sqrtf(f.x[1][0] * f.x[1][0] + f.x[1][1] * f.x[1][1] + f.x[1][2] * f.x[1][2]);
    /* the sphere's facets lie inside 0.2 m by up to 0.2 (1 - cos(pi / 24)) = 1.7 mm */
    assert_true(r > 0.2f + 0.004f - 0.002f);
    assert_float_equal(f.x[0][1], 0.29f, 0.0f);
    free(f.x);
    sim_collider_destroy(f.c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_collide_find_contacts_by_a_team_equals_one_thread),
        cmocka_unit_test(test_collide_research_finds_a_point_that_had_no_contact),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
