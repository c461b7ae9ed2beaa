/* libFuzzer harness: a recorded session's bodies as a bench scene (sim/scene_log.c, tryon-bench-sim
 * --motion FILE.lcmlog). The input is a series of events, each a flag byte (bit 0: on CLOTH, not
 * BODY; bit 1: left unsealed), a 2-byte big-endian length and that many payload bytes; they are
 * written as an lcm-logger log, the sealed ones with this host's key so that the reader gets past
 * the tag to the messages, and the log is read. Every eighth input is written as it is instead,
 * for the log format itself. */
#include <lcm/eventlog.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "bus.h"
#include "fuzz_file.h"
#include "scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void write_log(const char *path, const uint8_t *data, size_t size)
{
    lcm_eventlog_t *log = lcm_eventlog_create(path, "w");
    if (!log)
        return;
    uint8_t *buf = malloc(65536 + BUS_TAG_BYTES);
    for (int64_t n = 0; buf && size >= 3; n++) {
        int flags = data[0];
        size_t len = (size_t)data[1] << 8 | data[2];
        data += 3;
        size -= 3;
        len = len > size ? size : len;
        const char *channel = flags & 1 ? "F_CLOTH" : "F_BODY";
        memcpy(buf, data, len);
        bus_reject why;
        if ((flags & 2) || bus_seal(channel, buf, len, &why) != BUS_OK)
            memset(buf + len, 0, BUS_TAG_BYTES);
        lcm_eventlog_event_t ev = {.eventnum = n,
                                   .timestamp = 1000 + n,
                                   .channellen = (int32_t)strlen(channel),
                                   .datalen = (int32_t)(len + BUS_TAG_BYTES),
                                   .channel = (char *)channel,
                                   .data = buf};
        lcm_eventlog_write_event(log, &ev);
        data += len;
        size -= len;
    }
    free(buf);
    lcm_eventlog_destroy(log);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path;
    if (size > 0 && data[0] % 8 == 7) {
        path = fuzz_write("raw.lcmlog", data + 1, size - 1);
    } else {
        path = fuzz_write("session.lcmlog", NULL, 0);
        write_log(path, data, size);
    }
    char err[256];
    sim_scene *sc = sim_scene_log(path, err, sizeof err);
    if (sc) {
        const float *xyz, *joints;
        const int32_t *tris;
        int nv, nt;
        sim_scene_eval(sc, 0.0, &xyz, &nv, &tris, &nt, &joints);
        sim_scene_eval(sc, sim_scene_duration(sc), &xyz, &nv, &tris, &nt, &joints);
        sim_scene_destroy(sc);
    }
    return 0;
}
