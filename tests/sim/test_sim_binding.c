/* Bound edges (sim/cloth.c, springs_binding): a mesh garment's boundary loops that hold an
 * attachment get a stretch spring across every vertex, so that the shirt's free armhole edge,
 * hanging between the glued chest and back, settles in the frame's iterations instead of creeping
 * to the settle threshold every frame (docs/sim-history.md, "The armholes' cost" and "Bound
 * armholes"). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "cloth.h"
#include "sim_test_util.h"

#define BODY_VERTS  6000
#define SHIRT_VERTS 2000
#define BENCH_VERTS 7000 /* the bench's shirt: its 145-column armholes crept, 77 did not */
#define FPS         30.0
/* Frames after the first second that ran settle rounds, out of 30 of "still" with the bench's
   7,000-vertex shirt: 0 bound (max strain 1.63 %), 30 (every frame, 2.00 %) with the armholes'
   edge unbound. */
#define STILL_FRAMES      60
#define MAX_SETTLE_FRAMES 3

/* Stretch springs joining two vertices of grid row `row` (cols columns) `gap` columns apart. */
static int row_springs(const sim_cloth *c, int cols, int row, int gap)
{
    int n = 0;
    for (int s = 0; s < c->ns; s++) {
        int a = c->ends[s][0], b = c->ends[s][1];
        if (c->kind[s] != SIM_SPRING_STRETCH || a / cols != row || b / cols != row)
            continue;
        int d = abs(a % cols - b % cols);
        n += d == gap || d == cols - gap;
    }
    return n;
}

/* The shirt's top loop (glued outside the armholes) is bound, one spring across each of its
   vertices; its hem (no attachment) is not. */
static void test_binding_crosses_the_attached_loop_only(void **state)
{
    (void)state;
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv, nt, cols, rows;
    assert_int_equal(simt_scene_shirt("still", BODY_VERTS, SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt),
                     0);
    assert_int_equal(sscanf(g.id, "shirt-%dx%d", &cols, &rows), 2);
    assert_true(g.num_attachments > 0 && g.num_attachments < cols);
    sim_desc d = sim_default_desc();
    sim_cloth c;
    assert_int_equal(sim_cloth_init(&c, &g, &d.fabric, NULL), 0);
    int top = row_springs(&c, cols, 0, 2), hem = row_springs(&c, cols, rows - 1, 2);
    printf("# shirt %dx%d: %d binding springs on the top loop, %d on the hem\n", cols, rows, top,
           hem);
    assert_int_equal(top, cols);
    assert_int_equal(hem, 0);
    assert_int_equal(row_springs(&c, cols, 0, 1), cols); /* the edge itself, once */
    sim_cloth_free(&c);
    sim_garment_free(&g);
    sim_scene_destroy(sc);
}

/* The body standing still: after the first second the shirt settles within the frame's
   iterations; with the armholes' edge unbound it needed settle rounds on every frame. */
static void test_bound_armholes_settle(void **state)
{
    (void)state;
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv, nt;
    assert_int_equal(simt_scene_shirt("still", BODY_VERTS, BENCH_VERTS, 0.0f, &sc, &g, &nv, &nt),
                     0);
    sim_desc d = sim_default_desc();
    sim_reject why = {0};
    sim *s = sim_create(&d, &g, &why);
    sim_garment_free(&g);
    assert_non_null(s);
    int settle = 0;
    float worst = 0.0f;
    for (int f = 0; f < STILL_FRAMES; f++) {
        const float *xyz, *joints;
        const int32_t *tris;
        assert_int_equal(sim_scene_eval(sc, (double)f / FPS, &xyz, &nv, &tris, &nt, &joints), 0);
        sim_frame_stats st;
        assert_int_equal(sim_step(s, xyz, nv, tris, nt, &st, &why), 0);
        if (f >= (int)FPS) {
            settle += st.settle_rounds > 0;
            worst = fmaxf(worst, st.max_strain);
        }
    }
    printf("# still, %d frames after the first second: %d with settle rounds, max strain %.2f %%\n",
           STILL_FRAMES - (int)FPS, settle, 100.0 * worst);
    assert_true(simt_all_finite(s));
    assert_true(settle <= MAX_SETTLE_FRAMES);
    assert_true(worst <= SIM_RETRY_STRAIN);
    sim_destroy(s);
    sim_scene_destroy(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_binding_crosses_the_attached_loop_only),
        cmocka_unit_test(test_bound_armholes_settle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
