/* tryon: the whole pipeline in one command. `tryon run` starts capture, the body stage, the sim
 * and the mirror as separate processes on a private channel prefix, restarts a stage that dies,
 * stops them all on Ctrl-C or when the recording ends, and prints the latency summary;
 * `tryon replay LOG` shows a recorded session again; `tryon pace LOG` plays its bodies to a
 * tryon-sim at the camera's pace (pace.c); `tryon path LOG` says where its frames' time went
 * (path.c). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "session.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: tryon run [RECORDING | --live] [--headless --out DIR] [--video FILE.mp4]\n"
               "                 [--garment FILE] [--fabric NAME] [--record DIR]\n"
               "                 [--body bodyfit|truth] [--backend auto|c|opencl] [--rate R]\n"
               "                 [--png-every N] [--kiosk] [--mirror-nice N]\n"
               "       tryon replay LOG [--headless --out DIR] [--video FILE.mp4] [--speed S]\n"
               "       tryon pace LOG [--fps F] [--latency MS]\n"
               "       tryon path LOG\n"
               "  RECORDING: a fakenect dump (INDEX.txt) or an .oni file; --live: a camera\n"
               "             (libfreenect, then OpenNI2)\n"
               "  --body: the body stage, tryon-bodyfit (default) or tryon-truth (the recording's\n"
               "          true body; recordings made by tryon-synth only)\n"
               "  --record DIR: the session's LCM log (DIR/session.lcmlog, for tryon replay), the\n"
               "          depth frames (DIR/depth) and the stages' logs\n"
               "  --rate R: the recording's pace (realtime, max or frames per second)\n"
               "  --mirror-nice N: tryon-mirror's niceness, 0-19 (default 5): where the cores are\n"
               "          short, the next body's fit and cloth go before the last one's picture\n"
               "  Ctrl-C stops everything; a stage that dies is restarted within a second.\n");
}

/* 0..19: a stage may only be made nicer (no privilege needed) */
static int parse_nice(const char *v, int *out)
{
    char *end;
    long n = strtol(v, &end, 10);
    if (end == v || *end || n < 0 || n > 19)
        return -1;
    *out = (int)n;
    return 0;
}

static int parse_run(session_opts *o, int argc, char **argv)
{
    o->body = "bodyfit";
    o->backend = "auto";
    o->rate = "realtime";
    o->mirror_nice = LAUNCH_MIRROR_NICE;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--live"))
            o->live = 1;
        else if (!strcmp(a, "--headless"))
            o->headless = 1;
        else if (!strcmp(a, "--kiosk"))
            o->kiosk = 1;
        else if (a[0] != '-' && !o->recording)
            o->recording = a;
        else if (!strcmp(a, "--mirror-nice")) {
            if (!v || parse_nice(v, &o->mirror_nice) < 0) {
                fprintf(stderr, "tryon: --mirror-nice %s: give a niceness from 0 to 19\n",
                        v ? v : "(missing)");
                return -1;
            }
            i++;
        } else if (!v || a[0] != '-') {
            fprintf(stderr, "tryon: %s: unknown option or missing value\n", a);
            return -1;
        } else {
            const char **slot = !strcmp(a, "--out")         ? &o->out_dir
                                : !strcmp(a, "--video")     ? &o->video
                                : !strcmp(a, "--garment")   ? &o->garment
                                : !strcmp(a, "--fabric")    ? &o->fabric
                                : !strcmp(a, "--record")    ? &o->record_dir
                                : !strcmp(a, "--body")      ? &o->body
                                : !strcmp(a, "--backend")   ? &o->backend
                                : !strcmp(a, "--rate")      ? &o->rate
                                : !strcmp(a, "--png-every") ? &o->png_every
                                                            : NULL;
            if (!slot) {
                fprintf(stderr, "tryon: %s: unknown option\n", a);
                return -1;
            }
            *slot = v;
            i++;
        }
    }
    if (!o->live == !o->recording) {
        fprintf(stderr, "tryon run: give a RECORDING or --live (one of them)\n");
        return -1;
    }
    if (strcmp(o->body, "bodyfit") && strcmp(o->body, "truth")) {
        fprintf(stderr, "tryon run: --body %s: bodyfit or truth\n", o->body);
        return -1;
    }
    if (o->live && !strcmp(o->body, "truth")) {
        fprintf(stderr,
                "tryon run: --body truth needs a recording with ground truth, not --live\n");
        return -1;
    }
    return 0;
}

/* Checks made before anything starts, each naming the fix. */
static int preflight(const session_opts *o)
{
    struct stat sb;
    if (o->recording && stat(o->recording, &sb) != 0) {
        fprintf(stderr, "tryon: recording %s: %s\n", o->recording, strerror(errno));
        return -1;
    }
    if (!o->headless && !getenv("DISPLAY") && !getenv("WAYLAND_DISPLAY")) {
        fprintf(stderr, "tryon: no display (neither DISPLAY nor WAYLAND_DISPLAY is set): add "
                        "--headless --out DIR (PNG frames) or --video FILE.mp4\n");
        return -1;
    }
    return 0;
}

static int add_capture(session *s, const char *source)
{
    launch_stage *c = session_stage(s, "tryon-capture", LAUNCH_SOURCE, NULL);
    if (!c)
        return -1;
    session_arg(s, c, "--source", NULL);
    session_arg(s, c, "%s", source);
    if (s->o.recording) {
        session_arg(s, c, "--uri", NULL);
        session_arg(s, c, "%s", s->o.recording);
    }
    session_arg(s, c, "--rate", NULL);
    session_arg(s, c, "%s", s->o.rate);
    session_arg(s, c, "--quiet", NULL);
    if (s->o.record_dir) {
        session_arg(s, c, "--record", NULL);
        session_arg(s, c, "%s/depth", s->o.record_dir);
    }
    return 0;
}

int session_add_view(session *s)
{
    launch_stage *m = session_stage(s, "tryon-mirror", LAUNCH_VIEW, "listening for");
    if (!m)
        return -1;
    m->nice = s->o.mirror_nice;
    if (s->o.headless)
        session_arg(s, m, "--headless", NULL);
    if (s->o.kiosk && !s->o.headless)
        session_arg(s, m, "--kiosk", NULL);
    const char *out = s->o.out_dir;
    if (s->o.headless && !out && !s->o.video) /* headless needs somewhere to put the frames */
        out = "";
    if (out) {
        session_arg(s, m, "--out", NULL);
        session_arg(s, m, "%s", *out ? out : s->dir);
    }
    if (out && s->o.png_every) {
        session_arg(s, m, "--png-every", NULL);
        session_arg(s, m, "%s", s->o.png_every);
    }
    if (s->o.video) {
        session_arg(s, m, "--video", NULL);
        session_arg(s, m, "%s", s->o.video);
    }
    if (s->o.garment) {
        session_arg(s, m, "--garment", NULL);
        session_arg(s, m, "%s", s->o.garment);
    }
    if (s->o.fabric) {
        session_arg(s, m, "--fabric", NULL);
        session_arg(s, m, "%s", s->o.fabric);
    }
    return 0;
}

static int add_stages(session *s)
{
    launch_stage *sim = session_stage(s, "tryon-sim", LAUNCH_WORKER, "waiting for");
    if (!sim)
        return -1;
    session_arg(s, sim, "--backend", NULL);
    session_arg(s, sim, "%s", s->o.backend);
    if (s->o.garment) {
        session_arg(s, sim, "--garment", NULL);
        session_arg(s, sim, "%s", s->o.garment);
    }
    if (s->o.fabric) {
        session_arg(s, sim, "--fabric", NULL);
        session_arg(s, sim, "%s", s->o.fabric);
    }
    int truth = !strcmp(s->o.body, "truth");
    launch_stage *body = session_stage(s, truth ? "tryon-truth" : "tryon-bodyfit", LAUNCH_WORKER,
                                       truth ? "frames of ground truth" : "listening on");
    if (!body) {
        if (!truth)
            fprintf(stderr, "tryon: on a recording from tryon-synth, --body truth runs without "
                            "the fitter\n");
        return -1;
    }
    if (truth) {
        session_arg(s, body, "--recording", NULL);
        session_arg(s, body, "%s", s->o.recording);
    }
    if (session_add_view(s) < 0)
        return -1;
    if (s->o.record_dir) {
        launch_stage *lg = session_stage(s, "lcm-logger", LAUNCH_WORKER, NULL);
        if (!lg)
            return -1;
        session_arg(s, lg, "--quiet", NULL);
        session_arg(s, lg, "-f", NULL);
        session_arg(s, lg, "--channel=%s.*", s->prefix);
        session_arg(s, lg, "--lcm-url=%s", bus_default_url());
        session_arg(s, lg, "%s/session.lcmlog", s->o.record_dir);
    }
    return 0;
}

/* --live: libfreenect first, then OpenNI2; a source that fails at once is said and the next is
 * tried. */
static int start_live(session *s)
{
    static const char *sources[] = {"freenect", "openni2"};
    char said[2][400];
    for (int k = 0; k < 2; k++) {
        if (add_capture(s, sources[k]) < 0)
            return -1;
        launch_stage *c = &s->st[s->n - 1];
        launch_start(c);
        fprintf(stderr, "tryon: started %s --source %s (pid %d)\n", c->name, sources[k],
                (int)c->pid);
        if (launch_wait_ready(c, 0) == 0) /* no ready line: give it 3 s to fail */
            for (int i = 0; i < 150 && c->pid; i++) {
                int code;
                launch_reap(c, 1, &code);
                nanosleep(&(struct timespec){0, 20 * 1000 * 1000}, NULL);
            }
        if (c->pid)
            return 0;
        launch_log_tail(c, said[k], sizeof said[k]);
        s->n--;
    }
    fprintf(stderr,
            "tryon: no camera: tried libfreenect (%s) and OpenNI2 (%s); plug one in, or "
            "run a recording: tryon run RECORDING\n",
            strtok(said[0], "\n"), strtok(said[1], "\n"));
    return -1;
}

static int run(int argc, char **argv)
{
    static session s;
    if (parse_run(&s.o, argc, argv) < 0 || preflight(&s.o) < 0)
        return 2;
    int status = 1, ran = 0;
    if (session_open(&s) == 0 && add_stages(&s) == 0 && session_start(&s, 0) == 0) {
        if (s.o.live ? start_live(&s) == 0
                     : add_capture(&s, "freenect") == 0 && session_start(&s, s.n - 1) == 0) {
            status = session_supervise(&s);
            ran = 1;
        }
    }
    session_close(&s);
    if (!ran) { /* said above, with the stage's own words */
        bus_profile_destroy(s.profile);
        return status;
    }
    session_summary(&s); /* every stage has stopped: every TIMING is in */
    const char *out = s.o.out_dir ? s.o.out_dir : s.o.headless && !s.o.video ? s.dir : NULL;
    if (out)
        printf("== frames: %s/frame_*.png\n", out);
    if (s.o.video)
        printf("== video: %s\n", s.o.video);
    return status;
}

int main(int argc, char **argv)
{
    if (argc >= 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        usage(stdout);
        return 0;
    }
    if (argc >= 2 && !strcmp(argv[1], "run"))
        return run(argc, argv);
    if (argc >= 2 && !strcmp(argv[1], "replay"))
        return tryon_replay(argc, argv);
    if (argc >= 2 && !strcmp(argv[1], "pace"))
        return tryon_pace(argc, argv);
    if (argc >= 2 && !strcmp(argv[1], "path"))
        return tryon_path(argc, argv);
    usage(stderr);
    return 2;
}
