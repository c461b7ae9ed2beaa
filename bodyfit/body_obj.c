/* tryon-body-obj: writes the body model as a Wavefront .obj, posed by a motion at a time.
 * Usage: tryon-body-obj OUT.obj [PRESET 0..2] [MOTION] [TIME_S] [TARGET_VERTICES] */
#include "bodyfit.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    static const char usage[] =
        "usage: tryon-body-obj OUT.obj [PRESET 0..2] [MOTION] [TIME_S] [TARGET_VERTICES]\n";
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        fputs(usage, stdout);
        return 0;
    }
    for (int i = 1; i < argc; i++)
        if (argv[i][0] == '-' && i != 4) { /* TIME_S may be negative; nothing else may */
            fprintf(stderr, "tryon-body-obj: unknown option %s\n%s", argv[i], usage);
            return 2;
        }
    if (argc < 2 || argc > 6) {
        fputs(usage, stderr);
        return 2;
    }
    int preset = argc > 2 ? atoi(argv[2]) : 0;
    int motion = argc > 3 ? fit_motion_from_name(argv[3]) : FIT_MOTION_STILL;
    double t = argc > 4 ? atof(argv[4]) : 0.0;
    fit_model_desc desc = {.shape = fit_shape_preset(preset),
                           .target_vertices = argc > 5 ? atoi(argv[5]) : 0};
    if (motion < 0) {
        fprintf(stderr, "tryon-body-obj: unknown motion '%s'\n", argv[3]);
        return 2;
    }
    char err[256];
    double t0 = now_s();
    fit_model *m = fit_model_create(&desc, err, sizeof err);
    if (!m) {
        fprintf(stderr, "tryon-body-obj: %s\n", err);
        return 1;
    }
    double t1 = now_s();
    fit_measurements me;
    fit_model_measure(m, &me);
    const fit_shape *s = &me.shape;
    printf("%s: %d vertices, %d triangles, created in %.3f s\n", fit_shape_preset_name(preset),
           fit_model_vertex_count(m), fit_model_triangle_count(m), t1 - t0);
    printf("height %.4f shoulder %.4f chest %.4f waist %.4f hip %.4f arm %.4f/%.4f leg "
           "%.4f/%.4f\n",
           s->height, s->shoulder_width, s->chest_girth, s->waist_girth, s->hip_girth,
           s->arm_length, s->arm_girth, s->leg_length, s->leg_girth);
    float *v = malloc((size_t)fit_model_vertex_count(m) * 3 * sizeof(float));
    fit_pose pose;
    fit_motion_eval((fit_motion)motion, t, &pose);
    int rc = v ? fit_model_pose(m, &pose, v, NULL) : -FIT_ERR_NOMEM;
    if (!rc)
        rc = fit_model_write_obj(m, v, argv[1]);
    if (rc)
        fprintf(stderr, "tryon-body-obj: %s: %s\n", argv[1], fit_error_string(rc));
    free(v);
    fit_model_destroy(m);
    return rc ? 1 : 0;
}
