/* The shirt on the forward trunk bends (docs/sim-real-motion.md, "Real motion"; bend_side, which
 * nearly met the goals before, is left to docs/figures/motion_figures.sh for the sanitizer build's
 * time): from rest, every frame solved, nothing inside, never over 10 % strain, and after the first
 * second within 3 % max / 1 % p99, on both backends. In the moving frame of the attachments (the
 * chest) bend_fast failed (below): docs/sim-history.md, "Bends: the cause". */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "motion_run.h"

/* The trunk bent 30 degrees forward and back in 0.7 s: in the moving frame of the chest (the
   attachments) the hem swung into the hips and off them, at this size 90 points 34 mm inside on
   frame 2, 11.2 % max strain on frame 3, 8.0 % on frame 32; in the waist's frame the hips hold
   it (2.99 % max, 1.99 / 0.93 % after the first second). */
static void test_bend_fast_within_goals(void **state)
{
    (void)state;
    run_motion("bend_fast", 36);
}

/* 30 degrees forward and back at 1 Hz (31 % max strain at 7,000 vertices in the chest's frame). */
static void test_bend_forward_within_goals(void **state)
{
    (void)state;
    run_motion("bend_forward", 36);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bend_fast_within_goals),
        cmocka_unit_test(test_bend_forward_within_goals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
