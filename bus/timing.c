/* Filling and publishing timing_t, one per stage per frame. */
#include "bus.h"

#include <stdio.h>
#include <string.h>

void bus_timing_begin(bus_timing *t, const char *stage, int32_t seq, int64_t utime_capture,
                      int64_t utime_received)
{
    memset(t, 0, sizeof *t);
    snprintf(t->stage, sizeof t->stage, "%s", stage);
    t->seq = seq;
    t->utime_capture = utime_capture;
    t->utime_received = utime_received;
    t->utime_started = bus_now_wall_us();
}

void bus_timing_add(bus_timing *t, const char *substage, float ms)
{
    if (t->num_substages >= BUS_MAX_SUBSTAGES)
        return;
    snprintf(t->substage[t->num_substages], sizeof t->substage[0], "%s", substage);
    t->substage_ms[t->num_substages] = ms;
    t->num_substages++;
}

int bus_timing_publish(lcm_t *lcm, const bus_timing *t)
{
    char channel[BUS_CHANNEL_MAX];
    char *names[BUS_MAX_SUBSTAGES];
    float ms[BUS_MAX_SUBSTAGES];
    for (int i = 0; i < t->num_substages; i++) {
        names[i] = (char *)t->substage[i];
        ms[i] = t->substage_ms[i];
    }
    tryon_timing_t msg = {
        .stage = (char *)t->stage,
        .seq = t->seq,
        .utime_capture = t->utime_capture,
        .utime_received = t->utime_received,
        .utime_started = t->utime_started,
        .utime_finished = bus_now_wall_us(),
        .num_substages = t->num_substages,
        .substage = names,
        .substage_ms = ms,
    };
    if (bus_channel(BUS_CHANNEL_TIMING, channel, sizeof channel) != 0)
        return -BUS_ERR_STRING;
    bus_reject why;
    return bus_publish(lcm, channel, BUS_TIMING, &msg, &why);
}
