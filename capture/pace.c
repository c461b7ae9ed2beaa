/* Pacing: when each frame is due. Recordings replay at their recorded times (realtime), at a
 * fixed rate, or as fast as possible; live cameras pace themselves. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bus.h"
#include "capture.h"

int cap_rate_parse(const char *s, cap_rate *out)
{
    if (!s)
        return -CAP_ERR_ARG;
    if (!strcmp(s, "realtime")) {
        *out = (cap_rate){CAP_RATE_REALTIME, 0.0};
        return 0;
    }
    if (!strcmp(s, "max")) {
        *out = (cap_rate){CAP_RATE_MAX, 0.0};
        return 0;
    }
    char *end;
    double fps = strtod(s, &end);
    if (end == s || *end || !(fps > 0.0) || fps > 10000.0)
        return -CAP_ERR_ARG;
    *out = (cap_rate){CAP_RATE_FPS, fps};
    return 0;
}

void cap_pacer_init(cap_pacer *p, cap_rate rate)
{
    memset(p, 0, sizeof *p);
    p->rate = rate;
}

int64_t cap_pacer_due(cap_pacer *p, double replay_time_s, int *skip)
{
    int64_t now = bus_now_mono_us();
    *skip = 0;
    if (!p->started) {
        p->started = 1;
        p->t0_mono_us = now;
        p->first_replay_s = replay_time_s;
        p->next_fps_us = now;
    }
    int live = replay_time_s < 0.0;
    switch (p->rate.mode) {
    case CAP_RATE_MAX:
        return now;
    case CAP_RATE_REALTIME:
        if (live)
            return now;
        return p->t0_mono_us + (int64_t)((replay_time_s - p->first_replay_s) * 1e6 + 0.5);
    case CAP_RATE_FPS: {
        int64_t due = p->next_fps_us;
        if (live && now + 1000 < due) {
            *skip = 1; /* a live camera cannot be slowed down: drop what comes too early */
            return now;
        }
        /* From the due time, not from now, so that the average rate is exact. */
        p->next_fps_us = due + (int64_t)(1e6 / p->rate.fps + 0.5);
        return live ? now : due;
    }
    }
    return now;
}

void cap_sleep_until(int64_t due_us, volatile sig_atomic_t *stop)
{
    /* Short naps so that SIGINT/SIGTERM end the wait promptly. */
    for (;;) {
        if (stop && *stop)
            return;
        int64_t left = due_us - bus_now_mono_us();
        if (left <= 0)
            return;
        if (left > 50000)
            left = 50000;
        struct timespec ts = {.tv_sec = 0, .tv_nsec = (long)left * 1000};
        while (nanosleep(&ts, &ts) != 0 && errno == EINTR && !(stop && *stop))
            ;
    }
}
