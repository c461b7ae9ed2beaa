/* Latency profile from timing_t messages: per stage and end to end. Public as part of the bus
 * library (tryon-profile and tests use it). */
#ifndef TRYON_BUS_PROFILE_H
#define TRYON_BUS_PROFILE_H

#include <stdio.h>

#include "bus.h"

#define BUS_PROFILE_MAX_STAGES 16
/* Sequence gaps larger than this (frames) are a restart, not drops (30 s at 30 fps). */
#define BUS_PROFILE_MAX_GAP 900

typedef struct bus_stage_stats {
    char stage[32];
    int frames;
    /* sequence numbers missing in gaps of at most BUS_PROFILE_MAX_GAP, and for the fitter and
       the mirror the frames capture or the sim made before their first */
    int dropped;
    double fps; /* frames per second of wall clock between the first and last finish */
    double work_p50_ms, work_p95_ms, work_p99_ms, work_max_ms; /* finished - started */
    double lat_p50_ms, lat_p95_ms, lat_p99_ms, lat_max_ms;     /* finished - utime_capture */
    /* after the warm-up (bus_profile_set_warmup): frames with seq from the stage's first seq +
       warmup on; equal to the above when there is none */
    int steady_frames, steady_dropped;
    double steady_lat_p50_ms, steady_lat_p95_ms, steady_lat_p99_ms;
    int num_substages;
    char substage[BUS_MAX_SUBSTAGES][32];
    double substage_p50_ms[BUS_MAX_SUBSTAGES];
} bus_stage_stats;

typedef struct bus_profile bus_profile;
bus_profile *bus_profile_create(void);
void bus_profile_destroy(bus_profile *p);
/* Adds one report. Returns 0, or -BUS_ERR_NO_MEMORY when out of memory or the stage table is
 * full. */
int bus_profile_add(bus_profile *p, const tryon_timing_t *t);
/* The first `frames` frames of each stage by sequence number (a person entering: the fitter's
 * shape estimated, the garment made and made again) are left out of the steady_ figures, as the
 * architecture's timings are taken after warm-up; the whole-session figures keep them. 0: none. */
void bus_profile_set_warmup(bus_profile *p, int frames);
/* Fills out[] (at most max) in pipeline order: capture, bodyfit, sim, mirror, then others by
 * name. Returns the number of stages. */
int bus_profile_stats(const bus_profile *p, bus_stage_stats *out, int max);
/* A human table, then one JSON line naming the end-to-end figures (the last stage's latency);
 * with a warm-up, a second table of the frames after it, and the JSON line's steady_ fields. */
void bus_profile_print(const bus_profile *p, FILE *out);

#endif
