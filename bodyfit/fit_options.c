/* The tracker's command-line options (fit_options.h): the values' ranges once, for both
 * executables. */
#include "fit_options.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

int fit_parse_int(const char *s, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || !*s || *end || v < lo || v > hi)
        return -1;
    *out = (int)v;
    return 0;
}

int fit_parse_float(const char *s, float lo, float hi, float *out)
{
    char *end;
    float v = strtof(s, &end);
    if (!*s || *end || !(v >= lo && v <= hi))
        return -1;
    *out = v;
    return 0;
}

/* --smooth on|off|HZ: the One Euro filter on (its default cut-off at rest), off, or on with
 * that cut-off (0: off). */
static int parse_smooth(const char *v, float *hz)
{
    if (!strcmp(v, "on") || !strcmp(v, "off")) {
        *hz = !strcmp(v, "off") ? -1.0f : 0.0f;
        return 0;
    }
    float f;
    if (fit_parse_float(v, 0.0f, 100.0f, &f))
        return -1;
    *hz = f == 0.0f ? -1.0f : f; /* 0 Hz: no filter */
    return 0;
}

int fit_tracker_option(const char *a, const char *v, fit_tracker_desc *d, int *bad)
{
    static const char *const names[] = {
        "--points",           "--iterations",        "--fit-vertices",    "--out-vertices",
        "--vertices",         "--temporal",          "--predict",         "--smooth",
        "--smooth-beta-root", "--smooth-beta-rot",   "--smooth-speed-hz", "--init-iterations",
        "--start-turns",      "--smooth-doubt-speed"};
    int known = 0;
    for (size_t k = 0; k < sizeof names / sizeof names[0] && !known; ++k)
        known = !strcmp(a, names[k]);
    if (!known)
        return 0;
    if (!v)
        *bad = 1;
    else if (!strcmp(a, "--points"))
        *bad = fit_parse_int(v, 20, 100000, &d->points) != 0;
    else if (!strcmp(a, "--iterations"))
        *bad = fit_parse_int(v, 1, 200, &d->iterations) != 0;
    else if (!strcmp(a, "--init-iterations"))
        *bad = fit_parse_int(v, 1, 200, &d->init_iterations) != 0;
    else if (!strcmp(a, "--start-turns"))
        *bad = fit_parse_int(v, 1, 8, &d->start_turns) != 0;
    else if (!strcmp(a, "--fit-vertices"))
        *bad = fit_parse_int(v, 1000, 60000, &d->fit_vertices) != 0;
    else if (!strcmp(a, "--out-vertices") || !strcmp(a, "--vertices"))
        *bad = fit_parse_int(v, 1000, 60000, &d->out_vertices) != 0;
    else if (!strcmp(a, "--temporal"))
        *bad = fit_parse_float(v, 1e-30f, 1e3f, &d->temporal) != 0;
    else if (!strcmp(a, "--predict")) {
        float g;
        *bad = fit_parse_float(v, 0.0f, 2.0f, &g) != 0;
        d->predict = *bad ? d->predict : (g == 0.0f ? -1.0f : g); /* 0: none */
    } else if (!strcmp(a, "--smooth"))
        *bad = parse_smooth(v, &d->smooth_hz) != 0;
    else if (!strcmp(a, "--smooth-beta-root"))
        *bad = fit_parse_float(v, 1e-6f, 1e4f, &d->smooth_beta_root) != 0;
    else if (!strcmp(a, "--smooth-beta-rot"))
        *bad = fit_parse_float(v, 1e-6f, 1e4f, &d->smooth_beta_rot) != 0;
    else if (!strcmp(a, "--smooth-doubt-speed")) {
        float c;
        *bad = fit_parse_float(v, 0.0f, 100.0f, &c) != 0;
        d->smooth_doubt_mps = *bad ? d->smooth_doubt_mps : (c == 0.0f ? -1.0f : c); /* 0: none */
    } else
        *bad = fit_parse_float(v, 0.01f, 100.0f, &d->smooth_speed_hz) != 0;
    return 1;
}

void fit_tracker_options_usage(FILE *f, int indent)
{
    fprintf(f,
            "%*s[--points N] [--iterations N] [--fit-vertices N] [--out-vertices N]\n"
            "%*s[--temporal W] [--predict G] [--smooth on|off|HZ] [--smooth-beta-root B]\n"
            "%*s[--smooth-beta-rot B] [--smooth-speed-hz HZ] [--smooth-doubt-speed MPS]\n"
            "%*s[--init-iterations N] [--start-turns N]\n",
            indent, "", indent, "", indent, "", indent, "");
}

void fit_tracker_options_help(FILE *f)
{
    fprintf(f,
            "The fit: --points: data points per frame (%d); --iterations: Gauss-Newton\n"
            "iterations per frame (6); --fit-vertices: the coarse mesh fitted (1500);\n"
            "--out-vertices (or --vertices): the mesh published (6000); --temporal: the\n"
            "temporal prior's weight (2e-4); --predict: the share of the last frame's motion\n"
            "carried on (1; 0: none); --smooth: the published pose's One Euro filter, on, off\n"
            "or its cut-off at rest in Hz (0.5; 0: off); --smooth-beta-root: its rise per m/s\n"
            "of the root, the root's and every joint's (16); --smooth-beta-rot: its rise per\n"
            "m/s of a joint's reach, its rad/s times the distance to the farthest joint below\n"
            "it (3); --smooth-speed-hz: the cut-off of its speed estimate (1.5);\n"
            "--smooth-doubt-speed: while the fit is doubted (published init), the fastest\n"
            "any published joint moves, m/s (%.0f; 0: no bound).\n"
            "A person entering: --init-iterations: Gauss-Newton iterations from the rest pose\n"
            "on their first frame (12; a restart after a lost part takes 40); --start-turns:\n"
            "turns of shape and pose a frame over their first frames (1-8; 8: all on the\n"
            "first frame, the default; fewer: cheaper first frames, more jitter).\n",
            FIT_TRACK_POINTS, (double)FIT_TRACK_DOUBT_MPS);
}
