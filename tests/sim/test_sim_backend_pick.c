/* --backend auto on a GPU races the two backends on the garment (sim_backend_race): the
 * measurement is what picks: the faster median frame wins, and with no OpenCL device the answer
 * is C. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "sim_test_util.h"

static void test_race_picks_the_faster_backend(void **state)
{
    (void)state;
    sim_scene *sc = NULL;
    sim_garment g = {0};
    int nv = 0, nt = 0;
    assert_int_equal(simt_scene_shirt("walk", 4000, 1000, 0.0f, &sc, &g, &nv, &nt), 0);
    const float *xyz, *joints;
    const int32_t *tris;
    sim_scene_eval(sc, 0.0, &xyz, &nv, &tris, &nt, &joints);
    sim_desc d = sim_default_desc();
    sim_backend pick = SIM_BACKEND_OPENCL;
    double ms[2] = {0, 0};
    assert_int_equal(sim_backend_race(&d, &g, xyz, nv, tris, nt, 4, &pick, ms), 0);
    sim_backend have[2];
    int opencl = simt_backends(have) == 2;
    printf("# race: C %.2f ms, OpenCL %.2f ms (%s)\n", ms[0], ms[1],
           opencl ? "a device opened" : "no device");
    assert_true(ms[0] > 0.0);
    if (opencl) /* PoCL here: a CPU device, 4-5x slower than C on the same cores */
        assert_true(ms[1] > 0.0);
    else
        assert_true(ms[1] == -1.0);
    /* the faster one, whichever it is (under the sanitizers the C backend is slowed, PoCL's
       kernels are not) */
    assert_true(pick == (opencl && ms[1] < ms[0] ? SIM_BACKEND_OPENCL : SIM_BACKEND_C));

    /* refused: too few frames, no garment; a garment neither backend takes */
    assert_int_equal(sim_backend_race(&d, &g, xyz, nv, tris, nt, 1, &pick, ms), -SIM_ERR_ARG);
    assert_int_equal(sim_backend_race(&d, NULL, xyz, nv, tris, nt, 4, &pick, ms), -SIM_ERR_ARG);
    g.xyz[0] = NAN;
    assert_int_equal(sim_backend_race(&d, &g, xyz, nv, tris, nt, 4, &pick, ms), -SIM_ERR_BACKEND);
    sim_garment_free(&g);
    sim_scene_destroy(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_race_picks_the_faster_backend),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
