/* bus_peer: a second process for the bus tests. It echoes every DEPTH and BODY message it
 * receives (decoded, validated, re-encoded) to ECHO_DEPTH / ECHO_BODY, announces itself with a
 * timing message on READY until the first message arrives, and exits after N echoes or a
 * deadline. Channels take the TRYON_CHANNEL_PREFIX like every tryon process. */
#include "bus.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct peer {
    lcm_t *lcm;
    int echoed;
    char echo_depth[BUS_CHANNEL_MAX];
    char echo_body[BUS_CHANNEL_MAX];
} peer;

static void on_depth(const char *channel, const void *msg, void *user)
{
    (void)channel;
    peer *p = user;
    bus_reject why;
    if (bus_publish(p->lcm, p->echo_depth, BUS_DEPTH_FRAME, msg, &why) == BUS_OK)
        p->echoed++;
}

static void on_body(const char *channel, const void *msg, void *user)
{
    (void)channel;
    peer *p = user;
    bus_reject why;
    if (bus_publish(p->lcm, p->echo_body, BUS_BODY, msg, &why) == BUS_OK)
        p->echoed++;
}

int main(int argc, char **argv)
{
    static const char usage[] = "usage: bus_peer [ECHOES (1)] [DEADLINE_MS (10000)]\n";
    if (argc > 1 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        fputs(usage, stdout);
        return 0;
    }
    for (int i = 1; i < argc; i++)
        if (argv[i][0] == '-' || i > 2) {
            fprintf(stderr, "bus_peer: unknown option %s\n%s", argv[i], usage);
            return 2;
        }
    int want = argc > 1 ? atoi(argv[1]) : 1;
    int deadline_ms = argc > 2 ? atoi(argv[2]) : 10000;
    char err[512];
    peer p = {0};
    p.lcm = bus_open(NULL, err, sizeof err);
    if (!p.lcm) {
        fprintf(stderr, "bus_peer: %s\n", err);
        return 2;
    }
    char depth[BUS_CHANNEL_MAX], body[BUS_CHANNEL_MAX];
    bus_channel(BUS_CHANNEL_DEPTH, depth, sizeof depth);
    bus_channel(BUS_CHANNEL_BODY, body, sizeof body);
    bus_channel("ECHO_DEPTH", p.echo_depth, sizeof p.echo_depth);
    bus_channel("ECHO_BODY", p.echo_body, sizeof p.echo_body);
    bus_sub *sd = bus_subscribe(p.lcm, depth, BUS_DEPTH_FRAME, on_depth, &p);
    bus_sub *sb = bus_subscribe(p.lcm, body, BUS_BODY, on_body, &p);
    int64_t end = bus_now_mono_us() + (int64_t)deadline_ms * 1000;
    while (p.echoed < want && bus_now_mono_us() < end) {
        if (p.echoed == 0) {
            bus_timing t;
            bus_timing_begin(&t, "peer-ready", 0, 0, 0);
            bus_timing_publish(p.lcm, &t);
        }
        lcm_handle_timeout(p.lcm, 50);
    }
    bus_unsubscribe(p.lcm, sd);
    bus_unsubscribe(p.lcm, sb);
    lcm_destroy(p.lcm);
    return p.echoed >= want ? 0 : 1;
}
