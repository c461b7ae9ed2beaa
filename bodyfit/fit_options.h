/* The tracker's command-line options, one parser and one text for tryon-bodyfit and
 * tryon-bench-fit (docs/bodyfit.md, "Using it"). */
#ifndef TRYON_FIT_OPTIONS_H
#define TRYON_FIT_OPTIONS_H

#include "fit_track.h"

#include <stdio.h>

/* A whole decimal integer in lo..hi into *out: 0, or -1 (out unchanged). */
int fit_parse_int(const char *s, int lo, int hi, int *out);
/* A whole number in lo..hi into *out: 0, or -1 (out unchanged). */
int fit_parse_float(const char *s, float lo, float hi, float *out);

/* 1 when a names a tracker option (--points, --iterations, --fit-vertices, --out-vertices or
 * --vertices, --temporal, --predict, --smooth, --smooth-beta-root, --smooth-beta-rot,
 * --smooth-speed-hz, --init-iterations, --start-turns): its value
 * v parsed into d, *bad set when v is missing or out of range. 0 when a is none of them. */
int fit_tracker_option(const char *a, const char *v, fit_tracker_desc *d, int *bad);

/* The options' synopsis (each line indented by indent spaces), for a usage text. */
void fit_tracker_options_usage(FILE *f, int indent);
/* What each option does, with its default. */
void fit_tracker_options_help(FILE *f);

#endif
