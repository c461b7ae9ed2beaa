/* The shirt on a real-motion scene from rest (docs/sim-real-motion.md, "Real motion"), shared by
 * test_sim_motion and test_sim_bend. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <cmocka.h>

#include "cloth.h"
#include "motion_run.h"
#include "sim_test_util.h"

/* frames of motion from rest on each backend: every frame solved (not carried), nothing over
   1 mm inside, max strain never over 10 %, and after the first second within 3 % max, 1 % p99 */
void run_motion(const char *motion, int frames)
{
    sim_backend bs[2];
    int n = simt_backends(bs);
    for (int k = 0; k < n; k++) {
        sim_scene *sc = NULL;
        sim_garment g = {0};
        int nv, nt;
        assert_int_equal(simt_scene_shirt(motion, BODY_VERTS, SHIRT_VERTS, 0.0f, &sc, &g, &nv, &nt),
                         0);
        sim_desc d = sim_default_desc();
        d.backend = bs[k];
        sim_reject why = {0};
        sim *s = sim_create(&d, &g, &why);
        sim_garment_free(&g);
        assert_non_null(s);
        float worst = 0.0f, worst_late = 0.0f, p99_late = 0.0f;
        int solved = 0, inside = 0;
        for (int f = 0; f < frames; f++) {
            const float *xyz, *joints;
            const int32_t *tris;
            assert_int_equal(sim_scene_eval(sc, (double)f / FPS, &xyz, &nv, &tris, &nt, &joints),
                             0);
            sim_frame_stats st;
            assert_int_equal(sim_step(s, xyz, nv, tris, nt, &st, &why), 0);
            solved += st.state == SIM_STATE_OK || st.state == SIM_STATE_RECOVERED;
            inside = st.penetrating > inside ? st.penetrating : inside;
            worst = fmaxf(worst, st.max_strain);
            if (f >= (int)FPS) {
                worst_late = fmaxf(worst_late, st.max_strain);
                p99_late = fmaxf(p99_late, st.p99_strain);
            }
        }
        printf("# %s %s, %d frames: %d solved, worst %d inside, max strain %.2f %% (after 1 s "
               "%.2f %%, p99 %.2f %%)\n",
               motion, simt_backend_name(bs[k]), frames, solved, inside, 100.0 * worst,
               100.0 * worst_late, 100.0 * p99_late);
        assert_true(simt_all_finite(s));
        assert_int_equal(solved, frames);
        assert_int_equal(inside, 0);
        assert_true(worst <= 0.10f);
        assert_true(worst_late <= SIM_RETRY_STRAIN && p99_late <= SIM_RETRY_P99);
        sim_destroy(s);
        sim_scene_destroy(sc);
    }
}
