/* The strain-limit hierarchy's levels (sim/hierarchy.c) on the shirt: the columns under the
 * armholes, which hang from the armhole's free edge, hang from the vertex above them in the
 * hierarchy. With breadth-first levels every other vertical spring of those columns joined two
 * vertices of one level, which the pass never corrects, and the garment's weight stretched them
 * (docs/sim-history-5.md, "Bends: the hierarchy's levels"). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "cloth.h"
#include "sim_test_util.h"

#define BODY_VERTS  3000
#define SHIRT_VERTS 2000
/* hierarchy.c's SIM_HIER_RISE: a spring rising more than this fraction of its length joins a
   parent (above) and its child */
#define RISE 0.5f

/* level[v] from the hierarchy's arrays: 0 attached or unreached, l for entries of level l. */
static void levels_of(const sim_cloth *c, int *level)
{
    for (int v = 0; v < c->nv; v++)
        level[v] = 0;
    for (int l = 0; l < c->hier_levels; l++)
        for (int e = c->hier_level_start[l]; e < c->hier_level_start[l + 1]; e++)
            level[c->hier_vertex[e]] = l + 1;
}

/* Breadth-first hops over the stretch springs from the attached vertices (the levels before). */
static void hops_of(const sim_cloth *c, int *hop, int *queue)
{
    int head = 0, tail = 0;
    for (int v = 0; v < c->nv; v++)
        hop[v] = -1;
    for (int a = 0; a < c->num_attachments; a++)
        if (hop[c->attachments[a].vertex] < 0)
            hop[queue[tail++] = c->attachments[a].vertex] = 0;
    while (head < tail) {
        int v = queue[head++];
        for (int s = 0; s < c->ns; s++) {
            if (c->kind[s] != SIM_SPRING_STRETCH || (c->ends[s][0] != v && c->ends[s][1] != v))
                continue;
            int u = c->ends[s][0] == v ? c->ends[s][1] : c->ends[s][0];
            if (hop[u] < 0)
                hop[queue[tail++] = u] = hop[v] + 1;
        }
    }
}

static int is_parent_entry(const sim_cloth *c, int e, int u)
{
    for (int k = c->hier_parent_start[e]; k < c->hier_parent_start[e + 1]; k++)
        if (c->hier_parent[k] == u)
            return 1;
    return 0;
}

/* Every parent comes a level before its child; every free vertex reached has a parent; every
   stretch spring rising more than RISE of its length between two free vertices is a parent's and
   its child's, the higher end the parent. */
static void test_hierarchy_hangs_every_column(void **state)
{
    (void)state;
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv, nt;
    assert_int_equal(simt_scene_shirt("still", BODY_VERTS, SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt),
                     0);
    sim_desc d = sim_default_desc();
    sim_cloth c;
    assert_int_equal(sim_cloth_init(&c, &g, &d.fabric, NULL), 0);
    int *level = malloc((size_t)c.nv * sizeof *level),
        *entry = malloc((size_t)c.nv * sizeof *entry);
    int *hop = malloc((size_t)c.nv * sizeof *hop), *queue = malloc((size_t)c.nv * sizeof *queue);
    assert_non_null(level && entry && hop && queue);
    levels_of(&c, level);
    hops_of(&c, hop, queue);
    for (int v = 0; v < c.nv; v++)
        entry[v] = -1;
    int n = c.hier_level_start[c.hier_levels];
    for (int e = 0; e < n; e++) {
        int v = c.hier_vertex[e];
        entry[v] = e;
        assert_true(c.hier_parent_start[e + 1] > c.hier_parent_start[e]);
        for (int k = c.hier_parent_start[e]; k < c.hier_parent_start[e + 1]; k++)
            assert_true(level[c.hier_parent[k]] < level[v]);
    }
    int rising = 0, same_hop = 0;
    for (int s = 0; s < c.ns; s++) {
        int i = c.ends[s][0], j = c.ends[s][1];
        if (c.kind[s] != SIM_SPRING_STRETCH || entry[i] < 0 || entry[j] < 0)
            continue;
        int hi = c.x_rest[i][1] > c.x_rest[j][1] ? i : j, lo = hi == i ? j : i;
        if (!(c.x_rest[hi][1] - c.x_rest[lo][1] > RISE * c.rest[s]))
            continue;
        rising++;
        same_hop += hop[i] == hop[j];
        assert_true(is_parent_entry(&c, entry[lo], hi) || is_parent_entry(&c, entry[hi], lo));
        if (hop[i] == hop[j])
            assert_true(is_parent_entry(&c, entry[lo], hi));
    }
    printf("# shirt %s: %d levels, %d rising springs, %d of them within one breadth-first level\n",
           g.id, c.hier_levels, rising, same_hop);
    assert_true(same_hop > 0); /* the case the breadth-first levels left uncorrected is here */
    free(level);
    free(entry);
    free(hop);
    free(queue);
    sim_cloth_free(&c);
    sim_garment_free(&g);
    sim_scene_destroy(sc);
}

/* A garment without attachments has no hierarchy. */
static void test_hierarchy_empty_without_attachments(void **state)
{
    (void)state;
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv, nt;
    assert_int_equal(simt_scene_shirt("still", BODY_VERTS, 400, 0.0f, &sc, &g, &nv, &nt), 0);
    g.num_attachments = 0;
    sim_desc d = sim_default_desc();
    sim_cloth c;
    assert_int_equal(sim_cloth_init(&c, &g, &d.fabric, NULL), 0);
    assert_int_equal(c.hier_levels, 0);
    assert_int_equal(c.hier_level_start[0], 0);
    sim_cloth_free(&c);
    sim_garment_free(&g);
    sim_scene_destroy(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_hierarchy_hangs_every_column),
        cmocka_unit_test(test_hierarchy_empty_without_attachments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
