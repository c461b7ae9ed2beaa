/* Opening LCM, channel names and clocks. */
#include "bus.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tryon_errors.h"

int bus_channel(const char *base, char *out, size_t out_size)
{
    const char *prefix = getenv("TRYON_CHANNEL_PREFIX");
    int n = snprintf(out, out_size, "%s%s", prefix ? prefix : "", base);
    return (n < 0 || (size_t)n >= out_size) ? -BUS_ERR_STRING : 0;
}

const char *bus_default_url(void)
{
    const char *url = getenv("TRYON_LCM_URL");
    return (url && url[0]) ? url : BUS_DEFAULT_URL;
}

lcm_t *bus_open(const char *url, char *err, size_t err_size)
{
    if (!url)
        url = bus_default_url();
    if (bus_key_load(err, err_size) != 0)
        return NULL;
    lcm_t *lcm = lcm_create(url);
    if (lcm)
        return lcm;
    if (strncmp(url, "udpm://", 7) == 0) {
        /* lcm_create fails for udpm when the kernel has no route for the multicast group. */
        snprintf(err, err_size,
                 "cannot open LCM at %s: multicast is not routable on this machine. Fix: "
                 "'sudo ip route add 224.0.0.0/4 dev lo' (loopback only; see docs/bus.md), "
                 "or set TRYON_LCM_URL to another provider",
                 url);
    } else {
        snprintf(err, err_size, "cannot open LCM at %s: lcm_create failed (bad URL?)", url);
    }
    return NULL;
}

static int64_t clock_us(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

int64_t bus_now_mono_us(void)
{
    return clock_us(CLOCK_MONOTONIC);
}

int64_t bus_now_wall_us(void)
{
    return clock_us(CLOCK_REALTIME);
}

int64_t bus_now_cpu_us(void)
{
    return clock_us(CLOCK_PROCESS_CPUTIME_ID);
}

TRYON_ERROR_WORDS(BUS_ERROR_LIST, BUS_ERROR_COUNT, bus_error_name, bus_error_text,
                  "BUS_ERR_UNKNOWN")

/* Here beside the names, not in wire.c: wire.c calls validate.c, which reports through this. */
TRYON_REJECT_SETTER(bus_reject_set, bus_reject, bus_error)
