/* The garment OBJ reader against hostile files: sizes and indices that overflow int are refused
 * with the file and line named, never wrapped into values that pass validation. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sim.h"

/* A unit square as two triangles, plus the extra lines given. */
static int load_text(const char *extra, sim_garment *g, sim_reject *why)
{
    char path[] = "/tmp/tryon_garment_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    fprintf(f, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n%s", extra);
    fclose(f);
    int r = sim_garment_load_obj(path, g, why);
    unlink(path);
    return r;
}

static void test_square_loads(void **state)
{
    (void)state;
    sim_garment g;
    sim_reject why = {0};
    assert_int_equal(load_text("# grid 2 2\nf 1 2 3\nf 2 4/4 3//3\n", &g, &why), 0);
    assert_int_equal(g.num_vertices, 4);
    assert_int_equal(g.num_triangles, 2);
    assert_int_equal(g.grid_w * g.grid_h, 4);
    sim_garment_free(&g);
}

static void test_grid_product_overflowing_int_is_refused(void **state)
{
    (void)state;
    sim_garment g;
    sim_reject why = {0};
    /* 4 x 1073741825 wraps to 4 in 32-bit int arithmetic. */
    assert_true(load_text("# grid 4 1073741825\nf 1 2 3\nf 2 4 3\n", &g, &why) < 0);
    assert_non_null(strstr(why.detail, ":5: grid"));
    /* The same garment built in memory: validation computes the product without wrapping. */
    sim_garment m;
    assert_int_equal(load_text("f 1 2 3\nf 2 4 3\n", &m, &why), 0);
    m.grid_w = 4;
    m.grid_h = 1073741825;
    assert_int_equal(sim_garment_validate(&m, 0, &why), -SIM_ERR_PARAM);
    sim_garment_free(&m);
}

static void test_face_index_overflowing_int_is_refused(void **state)
{
    (void)state;
    sim_garment g;
    sim_reject why = {0};
    /* 4294967298 - 1 wraps to the valid index 1 when cut to int. */
    assert_true(load_text("f 1 2 3\nf 2 4 4294967298\n", &g, &why) < 0);
    assert_non_null(strstr(why.detail, ":6: face"));
    assert_true(load_text("f 1 2 -1\n", &g, &why) < 0);
    assert_true(load_text("f 1 2\n", &g, &why) < 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_square_loads),
        cmocka_unit_test(test_grid_product_overflowing_int_is_refused),
        cmocka_unit_test(test_face_index_overflowing_int_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
