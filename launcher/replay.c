/* tryon replay LOG: a session recorded with `tryon run --record DIR` shown again. lcm-logplayer
 * plays its DEPTH, BODY and CLOTH to a new tryon-mirror; the summary is the recorded session's
 * own TIMING, read from the log. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "session.h"

/* LCM log events: sync word, event number, timestamp, channel length, data length, channel,
 * data (big-endian; lcm/eventlog.c). */
#define LOG_SYNC 0xEDA1DA01u

static uint32_t be32(const uint8_t *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

int session_log_each(const char *path,
                     void (*fn)(const char *ch, const uint8_t *d, uint32_t n, void *user),
                     void *user)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return -1;
    uint8_t hdr[28];
    int events = 0;
    char ch[256];
    uint8_t *data = NULL;
    size_t cap = 0;
    while (fread(hdr, 1, sizeof hdr, f) == sizeof hdr) {
        uint32_t chlen = be32(hdr + 20), len = be32(hdr + 24);
        if (be32(hdr) != LOG_SYNC || chlen >= sizeof ch || len > 64u << 20)
            break; /* not an event: the rest is not trusted */
        if (len > cap) {
            uint8_t *d = realloc(data, len);
            if (!d)
                break;
            data = d;
            cap = len;
        }
        if (fread(ch, 1, chlen, f) != chlen || fread(data, 1, len, f) != len)
            break;
        ch[chlen] = 0;
        fn(ch, data, len, user);
        events++;
    }
    free(data);
    fclose(f);
    return events ? events : -1;
}

typedef struct replay_scan {
    char prefix[64];
    int found;
    bus_profile *profile;
} replay_scan;

static void scan(const char *ch, const uint8_t *d, uint32_t n, void *user)
{
    replay_scan *r = user;
    size_t k = strlen(ch), t = strlen(BUS_CHANNEL_TIMING);
    if (k < t || strcmp(ch + k - t, BUS_CHANNEL_TIMING) != 0)
        return;
    if (!r->found && k - t < sizeof r->prefix) {
        snprintf(r->prefix, sizeof r->prefix, "%.*s", (int)(k - t), ch);
        r->found = 1;
    }
    if (strncmp(ch, r->prefix, strlen(r->prefix)) != 0)
        return;
    tryon_timing_t m;
    bus_reject why;
    if (bus_decode_sealed(BUS_TIMING, ch, d, n, &m, &why) == BUS_OK) {
        bus_profile_add(r->profile, &m);
        bus_msg_free(BUS_TIMING, &m);
    }
}

int tryon_replay(int argc, char **argv)
{
    static session s;
    const char *log = NULL, *speed = "1";
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--headless"))
            s.o.headless = 1;
        else if (a[0] != '-' && !log)
            log = a;
        else if (v && !strcmp(a, "--out"))
            s.o.out_dir = argv[++i];
        else if (v && !strcmp(a, "--video"))
            s.o.video = argv[++i];
        else if (v && !strcmp(a, "--speed"))
            speed = argv[++i];
        else {
            fprintf(stderr, "tryon replay: %s: unknown option or missing value\n", a);
            return 2;
        }
    }
    replay_scan r = {.profile = bus_profile_create()};
    if (!log || !r.profile || session_log_each(log, scan, &r) < 0 || !r.found) {
        fprintf(stderr, "tryon replay: %s: not an LCM log of a tryon session (no TIMING)\n",
                log ? log : "(no LOG given)");
        bus_profile_destroy(r.profile);
        return 2;
    }
    if (!s.o.headless && !getenv("DISPLAY") && !getenv("WAYLAND_DISPLAY")) {
        fprintf(stderr, "tryon: no display (DISPLAY is not set): add --headless --out DIR\n");
        bus_profile_destroy(r.profile);
        return 2;
    }
    setenv("TRYON_CHANNEL_PREFIX", r.prefix, 1);
    int status = 1;
    if (session_open(&s) == 0 && session_add_view(&s) == 0) {
        launch_stage *p = session_stage(&s, "lcm-logplayer", LAUNCH_SOURCE, NULL);
        if (p) {
            session_arg(&s, p, "--speed=%s", speed);
            session_arg(&s, p, "--lcm-url=%s", bus_default_url());
            session_arg(&s, p, "--regexp=%s(DEPTH|BODY|CLOTH)", r.prefix);
            session_arg(&s, p, "%s", log);
            if (session_start(&s, 0) == 0)
                status = session_supervise(&s);
        }
    }
    session_close(&s);
    bus_profile_destroy(s.profile);
    printf("== the recorded session's latency per stage (%s):\n", log);
    bus_profile_print(r.profile, stdout);
    bus_profile_destroy(r.profile);
    return status;
}
