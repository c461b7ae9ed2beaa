/* A tryon session: the stages started in order on a private channel prefix, supervised (a stage
 * that dies is started again at once), stopped together, and the latency summary at the end. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "session.h"

static volatile sig_atomic_t stop_requested;

void session_request_stop(void)
{
    stop_requested = 1;
}

static void on_timing(const char *ch, const void *m, void *user)
{
    (void)ch;
    bus_profile_add(((session *)user)->profile, m);
}

/* Two cores for four processes: a thread that spins while it waits for work takes the core
 * another stage needs, and a stage split over threads that then queue for the same two cores
 * gains nothing (docs/pipeline.md, "Threads"). What the environment already says stays. */
static void session_thread_defaults(void)
{
    setenv("OMP_WAIT_POLICY", "passive", 0); /* tryon-sim's OpenMP workers sleep when idle */
    setenv("LP_NUM_THREADS", "1", 0);        /* tryon-mirror's llvmpipe: one thread */
}

int session_open(session *s)
{
    s->opened_us = launch_now_us();
    session_thread_defaults();
    const char *pre = getenv("TRYON_CHANNEL_PREFIX");
    if (pre && *pre)
        snprintf(s->prefix, sizeof s->prefix, "%s", pre);
    else
        snprintf(s->prefix, sizeof s->prefix, "RUN%d_", (int)getpid());
    setenv("TRYON_CHANNEL_PREFIX", s->prefix, 1); /* every stage inherits it */
    if (s->o.record_dir) {
        snprintf(s->dir, sizeof s->dir, "%s", s->o.record_dir);
        if (mkdir(s->dir, 0777) < 0 && errno != EEXIST) {
            fprintf(stderr, "tryon: --record %s: %s\n", s->dir, strerror(errno));
            return -1;
        }
    } else {
        const char *tmp = getenv("TMPDIR");
        snprintf(s->dir, sizeof s->dir, "%s/tryon-run-XXXXXX", tmp && *tmp ? tmp : "/tmp");
        if (!mkdtemp(s->dir)) {
            fprintf(stderr, "tryon: cannot make a folder for the logs: %s\n", strerror(errno));
            return -1;
        }
    }
    char err[512], ch[BUS_CHANNEL_MAX];
    s->lcm = bus_open(NULL, err, sizeof err);
    if (!s->lcm) {
        fprintf(stderr, "tryon: %s\n", err);
        return -1;
    }
    s->profile = bus_profile_create();
    if (s->profile)
        bus_profile_set_warmup(s->profile, SESSION_WARMUP_FRAMES);
    bus_channel(BUS_CHANNEL_TIMING, ch, sizeof ch);
    s->timing_sub = bus_subscribe(s->lcm, ch, BUS_TIMING, on_timing, s);
    if (!s->profile || !s->timing_sub) {
        fprintf(stderr, "tryon: cannot subscribe to %s\n", ch);
        return -1;
    }
    struct sigaction sa = {.sa_handler = (void (*)(int))session_request_stop};
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    return 0;
}

void session_close(session *s)
{
    launch_stop_all(s->st, s->n, 3000);
    if (!s->closed_us)
        s->closed_us = launch_now_us();
    if (s->timing_sub)
        bus_unsubscribe(s->lcm, s->timing_sub);
    s->timing_sub = NULL;
    if (s->lcm)
        lcm_destroy(s->lcm);
    s->lcm = NULL;
}

launch_stage *session_stage(session *s, const char *exe, launch_role role, const char *ready)
{
    if (s->n == SESSION_MAX_STAGES)
        return NULL;
    char *path = s->paths[s->n];
    if (launch_find(exe, path, sizeof s->paths[0]) < 0) {
        fprintf(stderr,
                "tryon: %s not found (looked in $TRYON_BIN_DIR, the build tree beside tryon, "
                "and $PATH)\n",
                exe);
        return NULL;
    }
    launch_stage *st = &s->st[s->n++];
    memset(st, 0, sizeof *st);
    snprintf(st->name, sizeof st->name, "%s", exe);
    snprintf(st->log, sizeof st->log, "%s/%s.log", s->dir, exe);
    st->argv[0] = path;
    st->role = role;
    st->ready = ready;
    return st;
}

void session_arg(session *s, launch_stage *st, const char *fmt, const char *value)
{
    int argc = 0;
    while (st->argv[argc])
        argc++;
    if (argc >= LAUNCH_MAX_ARGS)
        return;
    if (!strchr(fmt, '%')) {
        st->argv[argc] = (char *)fmt;
        return;
    }
    int si = (int)(st - s->st), k = 0;
    while (k < 8 && s->args[si][k][0])
        k++;
    if (k == 8)
        return;
    snprintf(s->args[si][k], sizeof s->args[si][k], fmt, value);
    st->argv[argc] = s->args[si][k];
}

static void say_failed(const launch_stage *st, const char *what)
{
    char tail[1200];
    launch_log_tail(st, tail, sizeof tail);
    fprintf(stderr, "tryon: %s %s; its last words (%s):\n%s\n", st->name, what, st->log, tail);
}

int session_start(session *s, int first)
{
    for (int i = first; i < s->n; i++) {
        launch_stage *st = &s->st[i];
        if (launch_start(st) < 0) {
            fprintf(stderr, "tryon: cannot start %s: %s\n", st->name, strerror(errno));
            return -1;
        }
        fprintf(stderr, "tryon: started %s (pid %d)\n", st->name, (int)st->pid);
        if (launch_wait_ready(st, 15000) < 0) {
            say_failed(st, st->pid ? "did not say it was ready within 15 s" : "exited at start");
            return -1;
        }
    }
    return 0;
}

/* A stage ended by itself. Returns 1 when the session should end (cleanly: *status 0). */
static int on_stage_exit(launch_stage *st, int code, int *status)
{
    if (stop_requested) /* Ctrl-C reached the stages too (one process group): nothing to restart */
        return 1;
    if (st->role == LAUNCH_SOURCE && code == 0) {
        fprintf(stderr, "tryon: %s finished: the recording has ended\n", st->name);
        return 1;
    }
    if (st->role == LAUNCH_VIEW && code == 0) {
        fprintf(stderr, "tryon: %s closed: stopping\n", st->name);
        return 1;
    }
    int64_t now = launch_now_us();
    /* a stage that exits by itself with an error right after it started will do so again */
    if (code > 0 && code < 128 && now - st->started_us < 2000000) {
        say_failed(st, "failed at start");
        *status = 1;
        return 1;
    }
    if (now - st->started_us > SESSION_RESTART_WINDOW_US)
        st->restarts = 0;
    if (++st->restarts > SESSION_MAX_RESTARTS) {
        say_failed(st, "keeps dying; giving up");
        *status = 1;
        return 1;
    }
    if (code >= 128)
        fprintf(stderr, "tryon: %s (pid %d) was killed by signal %d; restarting it\n", st->name,
                (int)st->last_pid, code - 128);
    else
        fprintf(stderr, "tryon: %s (pid %d) exited with %d; restarting it\n", st->name,
                (int)st->last_pid, code);
    if (launch_start(st) < 0) {
        fprintf(stderr, "tryon: cannot restart %s: %s\n", st->name, strerror(errno));
        *status = 1;
        return 1;
    }
    fprintf(stderr, "tryon: %s restarted (pid %d); the others carry on\n", st->name, (int)st->pid);
    return 0;
}

int session_supervise(session *s)
{
    int status = 0, ending = 0;
    int64_t drain_until = 0;
    while (!stop_requested) {
        int r = lcm_handle_timeout(s->lcm, 20);
        if (r < 0 && errno != EINTR && !stop_requested) {
            fprintf(stderr, "tryon: LCM stopped receiving\n");
            status = 1;
            break;
        }
        int code, i;
        while (!ending && (i = launch_reap(s->st, s->n, &code)) >= 0)
            if (on_stage_exit(&s->st[i], code, &status)) {
                ending = 1;
                drain_until = launch_now_us() + (status == 0 ? SESSION_DRAIN_US : 0);
            }
        if (ending && launch_now_us() >= drain_until)
            break;
    }
    if (stop_requested)
        fprintf(stderr, "tryon: stopping (Ctrl-C)\n");
    launch_stop_all(s->st, s->n, 3000);
    return status;
}

void session_summary(session *s)
{
    printf("== latency per stage (TIMING, %s):\n", s->prefix);
    bus_profile_print(s->profile, stdout);
    double wall_s = (double)(s->closed_us - s->opened_us) / 1e6;
    printf("== CPU time per stage (user + system, every run; the session took %.1f s):\n", wall_s);
    for (int i = 0; i < s->n; i++)
        printf("  %-14s %6.2f s  %5.1f %% of one core\n", s->st[i].name,
               (double)s->st[i].cpu_us / 1e6,
               wall_s > 0.0 ? 100.0 * (double)s->st[i].cpu_us / 1e6 / wall_s : 0.0);
    printf("== logs: %s\n", s->dir);
    fflush(stdout);
    bus_profile_destroy(s->profile);
    s->profile = NULL;
}
