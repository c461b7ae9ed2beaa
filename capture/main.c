/* tryon-capture: publish depth frames from a camera or a recording on the DEPTH channel. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bus.h"
#include "capture.h"

static volatile sig_atomic_t stop_flag = 0;

static void on_signal(int sig)
{
    (void)sig;
    stop_flag = 1;
}

static void usage(FILE *fp)
{
    fprintf(fp,
            "usage: tryon-capture [--source freenect|openni2] [--uri DEVICE|DUMP_DIR|FILE.oni]\n"
            "                     [--rate realtime|max|FPS] [--frames N] [--record DIR]\n"
            "                     [--camera-height M] [--camera-distance M] [--stats]\n"
            "A fakenect dump is replayed through Debian's fakenect libfreenect: tryon-capture\n"
            "validates it and restarts itself with that library (%s).\n",
            cap_fakenect_libdir());
}

typedef struct options {
    cap_run_desc run;
    float c2w[16];
    int stats;
} options;

static int parse(int argc, char **argv, options *o)
{
    o->run.source = "freenect";
    o->run.rate = (cap_rate){CAP_RATE_REALTIME, 0.0};
    cap_default_camera_to_world(o->c2w);
    o->run.camera_to_world = o->c2w;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        char *end = NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            exit(0);
        } else if (!strcmp(a, "--stats")) {
            o->stats = 1;
            continue;
        } else if (!strcmp(a, "--quiet")) {
            o->run.quiet = 1;
            continue;
        }
        if (!v) {
            fprintf(stderr, "tryon-capture: %s needs a value\n", a);
            return -1;
        }
        i++;
        if (!strcmp(a, "--source"))
            o->run.source = v;
        else if (!strcmp(a, "--uri"))
            o->run.uri = v;
        else if (!strcmp(a, "--record"))
            o->run.record_dir = v;
        else if (!strcmp(a, "--rate")) {
            if (cap_rate_parse(v, &o->run.rate) != 0) {
                fprintf(stderr, "tryon-capture: --rate %s: want realtime, max or a frame rate\n",
                        v);
                return -1;
            }
        } else if (!strcmp(a, "--frames")) {
            long n = strtol(v, &end, 10);
            if (*end || n < 0 || n > 100000000) {
                fprintf(stderr, "tryon-capture: --frames %s: want a count >= 0\n", v);
                return -1;
            }
            o->run.frames = (int)n;
        } else if (!strcmp(a, "--camera-height") || !strcmp(a, "--camera-distance")) {
            float m = strtof(v, &end);
            if (*end || !(m > -100.0f && m < 100.0f)) {
                fprintf(stderr, "tryon-capture: %s %s: want metres\n", a, v);
                return -1;
            }
            o->c2w[!strcmp(a, "--camera-height") ? 7 : 11] = m;
        } else {
            fprintf(stderr, "tryon-capture: unknown option %s\n", a);
            return -1;
        }
    }
    if (o->run.record_dir && o->run.uri && !strcmp(o->run.record_dir, o->run.uri)) {
        fprintf(stderr, "tryon-capture: --record %s would overwrite the recording it replays\n",
                o->run.record_dir);
        return -1;
    }
    if (!cap_source_find(o->run.source)) {
        fprintf(stderr, "tryon-capture: unknown source '%s' (freenect or openni2)\n",
                o->run.source);
        return -1;
    }
    return 0;
}

/* A dump replays through fakenect's libfreenect, which must be the one this process loaded:
 * validate, stage, and restart with LD_LIBRARY_PATH and FAKENECT_PATH set. Returns only on
 * failure: 3 for a damaged recording, as cap_run's CAP_ERR_RECORDING. */
static int reexec_with_fakenect(char **argv, const char *dump)
{
    char staged[512], err[768];
    if (cap_fakenect_stage(dump, staged, sizeof staged, err, sizeof err) != CAP_OK) {
        fprintf(stderr, "tryon-capture: rejected recording: %s\n", err);
        return 3;
    }
    const char *old = getenv("LD_LIBRARY_PATH");
    char path[2048];
    snprintf(path, sizeof path, "%s%s%s", cap_fakenect_libdir(), old && *old ? ":" : "",
             old ? old : "");
    setenv("LD_LIBRARY_PATH", path, 1);
    setenv("FAKENECT_PATH", staged, 1);
    setenv("FAKENECT_LOOP", "0", 1); /* newer fakenect loops by default; 0.5.3 never does */
    setenv(CAP_ENV_STAGED, staged, 1);
    execv("/proc/self/exe", argv);
    perror("tryon-capture: re-exec with fakenect");
    cap_fakenect_unstage(staged);
    return 1;
}

/* freenect URIs are device indices; anything else names a dump (which may be missing). */
static int uri_names_dump(const char *uri)
{
    if (!uri || !*uri)
        return 0;
    for (const char *c = uri; *c; c++)
        if (*c < '0' || *c > '9')
            return 1;
    return cap_uri_is_dump(uri);
}

int main(int argc, char **argv)
{
    options o = {0};
    if (parse(argc, argv, &o) != 0) {
        usage(stderr);
        return 2;
    }
    const char *staged = getenv(CAP_ENV_STAGED);
    if (!strcmp(o.run.source, "freenect") && uri_names_dump(o.run.uri) && !staged)
        return reexec_with_fakenect(argv, o.run.uri);
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    char err[1024] = "";
    lcm_t *lcm = bus_open(NULL, err, sizeof err);
    if (!lcm) {
        fprintf(stderr, "tryon-capture: %s\n", err);
        cap_fakenect_unstage(staged);
        return 1;
    }
    o.run.lcm = lcm;
    cap_run_stats st;
    int e = cap_run(&o.run, &stop_flag, &st, err, sizeof err);
    lcm_destroy(lcm);
    cap_fakenect_unstage(staged);
    double fps = st.seconds > 0.0 ? (st.frames - 1) / st.seconds : 0.0;
    if (!o.run.quiet && (e == CAP_OK || st.frames > 0))
        fprintf(stderr,
                "tryon-capture: %d frames in %.3f s (%.1f frames/s), due-to-published lag "
                "p50 %.3f ms p95 %.3f ms max %.3f ms%s\n",
                st.frames, st.seconds, fps, st.lag_p50_ms, st.lag_p95_ms, st.lag_max_ms,
                stop_flag ? " (stopped by signal)" : "");
    if (o.stats)
        printf("{\"frames\":%d,\"seconds\":%.6f,\"fps\":%.2f,\"lag_p50_ms\":%.4f,"
               "\"lag_p95_ms\":%.4f,\"lag_max_ms\":%.4f}\n",
               st.frames, st.seconds, fps, st.lag_p50_ms, st.lag_p95_ms, st.lag_max_ms);
    if (e != CAP_OK) {
        fprintf(stderr, "tryon-capture: %s: %s [%s]\n", cap_error_text(e), err, cap_error_name(e));
        return e == -CAP_ERR_RECORDING ? 3 : 1;
    }
    return 0;
}
