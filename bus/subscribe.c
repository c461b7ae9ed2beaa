/* Subscriptions that decode and validate before a handler sees a message. */
#include "bus_private.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Rejections are printed for the first few, then every hundredth, so a flood of bad messages
 * cannot drown the log; the counters always tell the whole story. */
#define BUS_REPORT_FIRST 5
#define BUS_REPORT_EVERY 100

struct bus_sub {
    lcm_subscription_t *lcm_sub;
    bus_type type;
    bus_handler fn;
    void *user;
    int quiet;
    bus_stats stats;
};

/* Room for any decoded message type. */
typedef union bus_any_msg {
    tryon_depth_frame_t depth;
    tryon_body_t body;
    tryon_cloth_t cloth;
    tryon_timing_t timing;
} bus_any_msg;

static void on_raw(const lcm_recv_buf_t *rbuf, const char *channel, void *user)
{
    bus_sub *s = user;
    bus_any_msg msg;
    bus_reject why = {0};
    int e = bus_decode_sealed(s->type, channel, rbuf->data, rbuf->data_size, &msg, &why);
    if (e != BUS_OK) {
        s->stats.rejected++;
        s->stats.rejected_by[-e]++;
        s->stats.last = why;
        uint64_t n = s->stats.rejected;
        if (!s->quiet && (n <= BUS_REPORT_FIRST || n % BUS_REPORT_EVERY == 0))
            fprintf(stderr,
                    "bus: rejected a %u-byte %s on %s: %s (%s); dropped, %llu rejected so far\n",
                    (unsigned)rbuf->data_size, bus_type_name(s->type), channel, bus_error_text(e),
                    why.detail, (unsigned long long)n);
        return;
    }
    s->stats.accepted++;
    s->fn(channel, &msg, s->user);
    bus_msg_free(s->type, &msg);
}

bus_sub *bus_subscribe(lcm_t *lcm, const char *channel, bus_type t, bus_handler fn, void *user)
{
    if (!lcm || !channel || !fn || t < 0 || t >= BUS_TYPE_COUNT)
        return NULL;
    bus_sub *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    *s = (bus_sub){.type = t, .fn = fn, .user = user};
    s->lcm_sub = lcm_subscribe(lcm, channel, on_raw, s);
    if (!s->lcm_sub) {
        free(s);
        return NULL;
    }
    return s;
}

const bus_stats *bus_sub_stats(const bus_sub *s)
{
    return &s->stats;
}

void bus_sub_quiet(bus_sub *s, int quiet)
{
    s->quiet = quiet;
}

void bus_unsubscribe(lcm_t *lcm, bus_sub *s)
{
    if (!s)
        return;
    if (lcm)
        lcm_unsubscribe(lcm, s->lcm_sub);
    free(s);
}
