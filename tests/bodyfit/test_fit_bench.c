/* tryon-bench-fit as a user runs it: on the noise-free arm_raise sample it scores the fit (every
 * error field present and small), writes fit_%05d.obj and joints.jsonl in camera coordinates,
 * fits from the true pose with --true-start, gives -1 error fields for a dump without ground
 * truth, and refuses unknown options. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "support.h"

static double json_field(const char *text, const char *key)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\":", key);
    const char *p = strstr(text, pat);
    assert_non_null(p);
    return strtod(p + strlen(pat), NULL);
}

/* Runs tryon-bench-fit with argv, its output into log; it must exit 0 and end in a JSON line,
   whose start goes to *json. Returns the output (the caller frees it). */
static char *run_bench(char **argv, const char *log, const char **json)
{
    pid_t pid = ts_spawn_out(argv, NULL, log);
    assert_true(pid > 0);
    int rc = ts_wait(pid, 100000);
    char *text = ts_read_file(log);
    printf("%s", text ? text : "(no output)\n");
    assert_int_equal(rc, 0);
    assert_non_null(text);
    *json = strrchr(text, '{');
    assert_non_null(*json);
    return text;
}

/* run_bench in a temporary folder of its own, removed after: the JSON line's fields keys[0..n). */
static void bench_fields(const char *tag, char **argv, const char *const *keys, double *values,
                         int n)
{
    char dir[256], log[400];
    const char *json;
    assert_int_equal(ts_temp_dir(dir, sizeof dir, tag), 0);
    snprintf(log, sizeof log, "%s/log.txt", dir);
    char *text = run_bench(argv, log, &json);
    for (int k = 0; k < n; ++k)
        values[k] = json_field(json, keys[k]);
    free(text);
    ts_remove_dir(dir);
}

static void test_fit_bench_scores_and_writes(void **state)
{
    (void)state;
    char dir[256], out[400], log[400], path[500];
    assert_int_equal(ts_temp_dir(dir, sizeof dir, "fitbench"), 0);
    snprintf(out, sizeof out, "%s/out", dir);
    snprintf(log, sizeof log, "%s/log.txt", dir);
    char scores[500];
    snprintf(scores, sizeof scores, "%s/scores.txt", dir);
    char *argv[] = {TRYON_BENCH_FIT_EXE,
                    "--out",
                    out,
                    "--scores",
                    scores,
                    TRYON_SAMPLES_DIR "/arm_raise_s0_exact",
                    NULL};
    const char *json;
    char *text = run_bench(argv, log, &json);
    assert_true(json_field(json, "surface_mm") > 0.0 && json_field(json, "surface_mm") < 10.0);
    assert_true(json_field(json, "joints_mm") > 0.0 && json_field(json, "joints_mm") < 30.0);
    assert_true(json_field(json, "ms_median") > 0.0);
    /* CPU a frame: every thread's at least this thread's, which is at least its sub-stages' */
    double cpu = json_field(json, "cpu_ms_median"), all = json_field(json, "process_cpu_ms_median");
    double seg = json_field(json, "segment_cpu_ms_median"),
           fit = json_field(json, "fit_cpu_ms_median");
    assert_true(cpu > 0.0 && all >= cpu - 0.01);
    assert_true(seg > 0.0 && fit > 0.0 && json_field(json, "skin_cpu_ms_median") > 0.0);
    assert_true(json_field(json, "process_cpu_ms_p95") >= all);
    assert_true(json_field(json, "tracked_fraction") == 1.0);
    assert_true(json_field(json, "frames") == 4.0);
    assert_true(json_field(json, "cloth_vs_truth_mm") == -1.0); /* not asked for */
    /* the person in view in every frame: the errors over those are the errors over all */
    assert_true(json_field(json, "in_view_frames") == 4.0);
    assert_true(fabs(json_field(json, "surface_mm_in_view") - json_field(json, "surface_mm")) <
                0.011);
    assert_true(fabs(json_field(json, "joints_mm_in_view") - json_field(json, "joints_mm")) <
                0.011);
    free(text);
    /* --scores: a line per frame, its errors those of the JSON line's range */
    text = ts_read_file(scores);
    assert_non_null(text);
    int lines = 0;
    for (const char *l = text; l && *l; l = strchr(l, '\n') ? strchr(l, '\n') + 1 : NULL) {
        int frame, st;
        unsigned doubt;
        double surf, joints;
        assert_int_equal(
            sscanf(l, "arm_raise_s0_exact %d %d %u %lf %lf", &frame, &st, &doubt, &surf, &joints),
            5);
        assert_int_equal(frame, lines);
        assert_true(surf > 0.0 && surf < 10.0 && joints > 0.0 && joints < 30.0);
        lines++;
    }
    assert_int_equal(lines, 4);
    free(text);
    struct stat st;
    for (int k = 0; k < 4; ++k) {
        snprintf(path, sizeof path, "%s/fit_%05d.obj", out, k);
        assert_int_equal(stat(path, &st), 0);
        assert_true(st.st_size > 100000);
    }
    snprintf(path, sizeof path, "%s/joints.jsonl", out);
    text = ts_read_file(path);
    assert_non_null(text);
    assert_non_null(strstr(text, "{\"frame\": 3"));
    /* The pelvis in camera coordinates: about 2.5 m along the axis (tryon-synth's camera). */
    const char *pel = strstr(text, "\"pelvis\": [");
    assert_non_null(pel);
    double x, y, z;
    assert_int_equal(sscanf(pel + strlen("\"pelvis\": ["), "%lf, %lf, %lf", &x, &y, &z), 3);
    assert_true(z > 2.3 && z < 2.7 && x > -0.2 && x < 0.2);
    free(text);
    ts_remove_dir(dir);
}

/* The shirt on the fitted and on the true body: the same garment, close on a noise-free fit. */
static void test_fit_bench_cloth_vs_truth(void **state)
{
    (void)state;
    char *argv[] = {TRYON_BENCH_FIT_EXE, "--cloth-vertices", "300",
                    TRYON_SAMPLES_DIR "/arm_raise_s0_exact", NULL};
    static const char *const keys[] = {"cloth_vs_truth_mm", "cloth_vertices"};
    double v[2];
    bench_fields("fitbench3", argv, keys, v, 2);
    assert_true(v[0] > 0.0 && v[0] < 20.0);
    assert_true(v[1] == 300.0);
}

/* --true-start (with --true-shape): every frame fitted from its true pose, so the error left is
 * the fit's terms' own: under the tracked fit's (4.1 mm on this sample). */
static void test_fit_bench_from_the_true_pose(void **state)
{
    (void)state;
    char *argv[] = {TRYON_BENCH_FIT_EXE, "--true-shape", "--true-start",
                    TRYON_SAMPLES_DIR "/arm_raise_s0_exact", NULL};
    static const char *const keys[] = {"joints_mm"};
    double j;
    bench_fields("fitbench4", argv, keys, &j, 1);
    assert_true(j > 0.0 && j < 3.5);
}

static void test_fit_bench_without_truth_and_bad_options(void **state)
{
    (void)state;
    char dir[256], rec[300], log[400], cmd[1200];
    assert_int_equal(ts_temp_dir(dir, sizeof dir, "fitbench2"), 0);
    snprintf(rec, sizeof rec, "%s/rec", dir);
    snprintf(log, sizeof log, "%s/log.txt", dir);
    /* A copy of the sample without its ground truth: any fakenect dump. */
    snprintf(cmd, sizeof cmd, "cp -r '%s/still_s0' '%s' && rm -f '%s'/gt-* '%s/groundtruth.txt'",
             TRYON_SAMPLES_DIR, rec, rec, rec);
    assert_int_equal(system(cmd), 0);
    char *argv[] = {TRYON_BENCH_FIT_EXE, rec, NULL};
    const char *json;
    char *text = run_bench(argv, log, &json);
    assert_true(json_field(json, "surface_mm") == -1.0);
    assert_true(json_field(json, "joints_mm") == -1.0);
    assert_true(json_field(json, "ms_median") > 0.0);
    free(text);
    char *bad[] = {TRYON_BENCH_FIT_EXE, "--no-such-option", rec, NULL};
    pid_t pid = ts_spawn_out(bad, NULL, log);
    assert_int_equal(ts_wait(pid, 10000), 2);
    text = ts_read_file(log);
    assert_non_null(strstr(text, "unknown option --no-such-option"));
    free(text);
    ts_remove_dir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fit_bench_scores_and_writes),
        cmocka_unit_test(test_fit_bench_cloth_vs_truth),
        cmocka_unit_test(test_fit_bench_from_the_true_pose),
        cmocka_unit_test(test_fit_bench_without_truth_and_bad_options),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
