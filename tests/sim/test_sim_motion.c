/* The shirt on the real-motion scenes (docs/sim-real-motion.md, "Real motion"): its armholes leave
 * room for arms lowered to the sides, and short takes of arms_down, boxing_guard and twist keep the
 * published statistics within issue 19's goals on every frame; both backends (the trunk bends:
 * test_sim_bend). */
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
#include "collide.h"
#include "collide_geometry.h"
#include "motion_run.h"
#include "sim_test_util.h"

/* bodyfit's joint indices (FIT_JOINT_LIST) in a body frame's joint array */
#define FIT_PELVIS 0

/* The shirt made on motion's first frame, then the body at t_s: the distance from the shirt's
   points above the pelvis joint (further down the hands hang beside the hips, millimetres from
   the hem, where the cloth is free to move aside) to the body, m; the attached columns and all
   columns into na, cols. */
static float shirt_clearance(const char *motion, double t_s, int *na, int *cols)
{
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv, nt, rows = 0;
    assert_int_equal(simt_scene_shirt(motion, BODY_VERTS, SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt), 0);
    assert_int_equal(sscanf(g.id, "shirt-%dx%d", cols, &rows), 2);
    *na = g.num_attachments;
    const float *xyz, *joints;
    const int32_t *tris;
    assert_int_equal(sim_scene_eval(sc, t_s, &xyz, &nv, &tris, &nt, &joints), 0);
    float above_y = joints[FIT_PELVIS * 3 + 1];
    float nearest = INFINITY;
    for (int i = 0; i < g.num_vertices; i++)
        for (int t = 0; t < nt && g.xyz[i * 3 + 1] > above_y; t++) {
            float q[3], bary[3];
            const float *p = &g.xyz[i * 3];
            sim_closest_on_triangle(p, &xyz[tris[t * 3] * 3], &xyz[tris[t * 3 + 1] * 3],
                                    &xyz[tris[t * 3 + 2] * 3], q, bary);
            float d2 = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                       (p[2] - q[2]) * (p[2] - q[2]);
            nearest = fminf(nearest, d2);
        }
    printf("# %s at %.1f s: above the pelvis joint (%.3f m) the shirt as made is %.1f mm from the "
           "body\n",
           motion, t_s, above_y, 1000.0 * sqrtf(nearest));
    sim_garment_free(&g);
    sim_scene_destroy(sc);
    return sqrtf(nearest);
}

/* The shirt made on the A-pose, then the arms lowered to 6 degrees from vertical (arms_down at
   1.5 s): no shirt point within the cloth's thickness of the body. Before the armholes the tube's
   glued top row lay inside the lowered arms (12 of its points at frame 38; docs/sim-history.md,
   "Arms down: the cause"). */
static void test_armholes_clear_the_lowered_arms(void **state)
{
    (void)state;
    int na, cols;
    float d = shirt_clearance("arms_down", 1.5, &na, &cols);
    /* the armholes' columns hang free: fewer attachments than columns, most of them kept */
    printf("# %d of %d top-row columns attached\n", na, cols);
    assert_true(na < cols && na > cols / 2);
    assert_true(d > sim_default_desc().thickness_m);
}

/* A clip's scene starts in the A-pose and turns into the clip's first pose over its first second
   (sim/scene.c), so the shirt is made on the A-pose: at 1 s (CMU 01_01's first pose, the arms at
   the sides) it is clear of the arms. Made on that pose itself, 175 of the 7,000-vertex shirt's
   points were inside the body on the first frame ("Arms down: the clips"). */
static void test_clip_scene_dresses_on_the_a_pose(void **state)
{
    (void)state;
    const char *clip = "/usr/share/assimp/models/BVH/01_01.bvh";
    FILE *f = fopen(clip, "rb");
    if (!f) {
        printf("# %s missing (assimp-testmodels): skipped\n", clip);
        return;
    }
    fclose(f);
    int na, cols;
    assert_true(shirt_clearance(clip, 1.0, &na, &cols) > sim_default_desc().thickness_m);
}

/* The arms reach 6 degrees from vertical at 1.5 s (frame 45) and stay there: before the
   armholes every frame from 40 was carried, 13 mm inside, 23 % strain at this size. */
static void test_arms_down_within_goals(void **state)
{
    (void)state;
    run_motion("arms_down", 50);
}

/* Forearms against the chest, the upper arms against the ribs. */
static void test_boxing_guard_within_goals(void **state)
{
    (void)state;
    run_motion("boxing_guard", 40);
}

/* The trunk twisted: with the armholes' edge glued on its slope the skinning sheared it apart
   (49 % strain, frames carried), so the edge hangs free. */
static void test_twist_within_goals(void **state)
{
    (void)state;
    run_motion("twist", 40);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_armholes_clear_the_lowered_arms),
        cmocka_unit_test(test_clip_scene_dresses_on_the_a_pose),
        cmocka_unit_test(test_arms_down_within_goals),
        cmocka_unit_test(test_boxing_guard_within_goals),
        cmocka_unit_test(test_twist_within_goals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
