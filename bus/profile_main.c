/* tryon-profile: per-stage and end-to-end latency of a running pipeline (live, from TIMING) or
 * of a recorded session (an LCM log written by lcm-logger). */
#include "profile.h"

#include <lcm/eventlog.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static volatile sig_atomic_t stop;

static void on_signal(int sig)
{
    (void)sig;
    stop = 1;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: tryon-profile --live SECONDS | --log FILE.lcmlog [--warmup N]\n"
               "  --live S   listen to TIMING for S seconds (or until Ctrl-C)\n"
               "  --log F    read every TIMING message of an lcm-logger log\n"
               "  --warmup N also the figures without each stage's first N frames (default 0)\n"
               "Prints a table per stage (frames, drops, fps, work and latency p50/p95/p99),\n"
               "then one JSON line with the end-to-end figures.\n");
}

static void on_timing(const char *channel, const void *msg, void *user)
{
    (void)channel;
    if (bus_profile_add(user, msg) != 0)
        fprintf(stderr, "tryon-profile: too many stages or out of memory; report dropped\n");
}

static int ends_with(const char *s, const char *tail)
{
    size_t n = strlen(s), m = strlen(tail);
    return n >= m && strcmp(s + n - m, tail) == 0;
}

static int from_log(bus_profile *p, const char *path)
{
    lcm_eventlog_t *log = lcm_eventlog_create(path, "r");
    if (!log) {
        fprintf(stderr, "tryon-profile: cannot open LCM log %s\n", path);
        return 1;
    }
    long used = 0, rejected = 0;
    lcm_eventlog_event_t *ev;
    while ((ev = lcm_eventlog_read_next_event(log)) != NULL) {
        if (ends_with(ev->channel, BUS_CHANNEL_TIMING)) {
            tryon_timing_t t;
            bus_reject why;
            if (bus_decode_sealed(BUS_TIMING, ev->channel, ev->data, (size_t)ev->datalen, &t,
                                  &why) == BUS_OK) {
                used += bus_profile_add(p, &t) == 0;
                bus_msg_free(BUS_TIMING, &t);
            } else if (rejected++ < 5) {
                fprintf(stderr, "tryon-profile: %s event %lld on %s rejected: %s (%s)\n", path,
                        (long long)ev->eventnum, ev->channel, bus_error_text(why.code), why.detail);
            }
        }
        lcm_eventlog_free_event(ev);
    }
    lcm_eventlog_destroy(log);
    fprintf(stderr, "tryon-profile: %ld timing reports from %s, %ld rejected\n", used, path,
            rejected);
    return 0;
}

static int live(bus_profile *p, double seconds)
{
    char err[512], channel[BUS_CHANNEL_MAX];
    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    if (!lcm) {
        fprintf(stderr, "tryon-profile: %s\n", err);
        return 1;
    }
    bus_channel(BUS_CHANNEL_TIMING, channel, sizeof channel);
    bus_sub *sub = bus_subscribe(lcm, channel, BUS_TIMING, on_timing, p);
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    int64_t end = bus_now_mono_us() + (int64_t)(seconds * 1e6);
    while (!stop && bus_now_mono_us() < end)
        lcm_handle_timeout(lcm, 100);
    const bus_stats *st = bus_sub_stats(sub);
    fprintf(stderr, "tryon-profile: %llu timing reports on %s, %llu rejected\n",
            (unsigned long long)st->accepted, channel, (unsigned long long)st->rejected);
    bus_unsubscribe(lcm, sub);
    lcm_destroy(lcm);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc > 1 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        usage(stdout);
        return 0;
    }
    long warmup = 0;
    if (argc == 5 && strcmp(argv[3], "--warmup") == 0) {
        char *end;
        warmup = strtol(argv[4], &end, 10);
        if (end == argv[4] || *end || warmup < 0 || warmup > 100000) {
            fprintf(stderr, "tryon-profile: --warmup needs a number of frames, got '%s'\n",
                    argv[4]);
            return 2;
        }
        argc = 3;
    }
    if (argc != 3 || (strcmp(argv[1], "--live") != 0 && strcmp(argv[1], "--log") != 0)) {
        if (argc > 1 && strcmp(argv[1], "--live") != 0 && strcmp(argv[1], "--log") != 0)
            fprintf(stderr, "tryon-profile: unknown option %s\n", argv[1]);
        else if (argc > 3)
            fprintf(stderr, "tryon-profile: unexpected argument %s\n", argv[3]);
        usage(stderr);
        return 2;
    }
    bus_profile *p = bus_profile_create();
    if (!p)
        return 1;
    bus_profile_set_warmup(p, (int)warmup);
    int rc;
    if (strcmp(argv[1], "--log") == 0) {
        rc = from_log(p, argv[2]);
    } else {
        double s = atof(argv[2]);
        if (!(s > 0)) {
            fprintf(stderr, "tryon-profile: --live needs a positive number of seconds\n");
            bus_profile_destroy(p);
            return 2;
        }
        rc = live(p, s);
    }
    if (rc == 0)
        bus_profile_print(p, stdout);
    bus_profile_destroy(p);
    return rc;
}
