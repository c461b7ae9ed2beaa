/* OpenCL device choice and the errors around it. Registered twice: as test_cl_device, and as
 * test_cl_nodevice with OCL_ICD_VENDORS pointing nowhere, where no platform exists and the
 * OpenCL backend must refuse cleanly with a message. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "cl_context.h"
#include "sim.h"

static int no_platform_run(void)
{
    const char *v = getenv("OCL_ICD_VENDORS");
    return v && strcmp(v, "/nonexistent") == 0;
}

static void test_cl_device_choice_follows_tryon_cl_device(void **state)
{
    (void)state;
    if (no_platform_run())
        skip();
    sim_cl cl;
    char err[256];
    unsetenv("TRYON_CL_DEVICE");
    if (sim_cl_open(&cl, err, sizeof err) != 0)
        skip(); /* no device on this machine */
    char first[160];
    snprintf(first, sizeof first, "%s", cl.device_name);
    sim_cl_close(&cl);
    /* By index, and by a piece of its name: the same device. */
    setenv("TRYON_CL_DEVICE", "0:0", 1);
    assert_int_equal(sim_cl_open(&cl, err, sizeof err), 0);
    sim_cl_close(&cl);
    char piece[8];
    memcpy(piece, first, sizeof piece - 1); /* device names are longer than 7 characters */
    piece[sizeof piece - 1] = '\0';
    setenv("TRYON_CL_DEVICE", piece, 1);
    assert_int_equal(sim_cl_open(&cl, err, sizeof err), 0);
    assert_string_equal(cl.device_name, first);
    sim_cl_close(&cl);
    /* A device that is not there: a named refusal and a message saying what to look at. */
    setenv("TRYON_CL_DEVICE", "no-such-device-xyz", 1);
    assert_int_equal(sim_cl_open(&cl, err, sizeof err), -SIM_CL_ENAMED);
    assert_non_null(strstr(err, "no-such-device-xyz"));
    setenv("TRYON_CL_DEVICE", "7:9", 1);
    assert_int_equal(sim_cl_open(&cl, err, sizeof err), -SIM_CL_ENAMED);
    unsetenv("TRYON_CL_DEVICE");
    assert_string_not_equal(sim_cl_error_str(-SIM_CL_ENAMED), "unknown OpenCL host error");
}

static void test_cl_without_platform_backend_refuses(void **state)
{
    (void)state;
    if (!no_platform_run())
        skip();
    sim_cl cl;
    char err[256] = "";
    assert_int_equal(sim_cl_open(&cl, err, sizeof err), -SIM_CL_ENODEVICE);
    assert_true(strlen(err) > 0);
    sim_garment g;
    memset(&g, 0, sizeof g);
    assert_int_equal(sim_garment_drape(100, 0.5f, 1.0f, &g), 0);
    sim_desc d = sim_default_desc();
    d.backend = SIM_BACKEND_OPENCL;
    sim_reject why;
    memset(&why, 0, sizeof why);
    assert_null(sim_create(&d, &g, &why));
    assert_int_equal(why.code, SIM_ERR_BACKEND);
    assert_non_null(strstr(why.detail, "OpenCL"));
    sim_garment_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cl_device_choice_follows_tryon_cl_device),
        cmocka_unit_test(test_cl_without_platform_backend_refuses),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
