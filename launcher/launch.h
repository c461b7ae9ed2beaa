/* launch: the tryon launcher's supervisor. Stages are child processes with their output in a log
 * file each; one that dies is started again, and all are stopped together. */
#ifndef TRYON_LAUNCH_H
#define TRYON_LAUNCH_H

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#define LAUNCH_MAX_ARGS 40

typedef enum launch_role {
    LAUNCH_WORKER, /* any exit is a death: restarted */
    LAUNCH_SOURCE, /* exit 0: the recording has ended, the session ends */
    LAUNCH_VIEW    /* exit 0: the person at the kiosk quit, the session ends */
} launch_role;

typedef struct launch_stage {
    char name[32];                   /* "tryon-sim" */
    char *argv[LAUNCH_MAX_ARGS + 1]; /* argv[0] a path; the strings are the caller's */
    const char *ready;               /* a line the stage prints once it listens; NULL = none */
    launch_role role;
    int nice;       /* added to its niceness (0..19): the cores go to the others first */
    char log[320];  /* its stdout and stderr, appended across restarts */
    pid_t pid;      /* 0 = not running */
    pid_t last_pid; /* the run that ended last */
    int restarts;
    int64_t started_us; /* monotonic */
    long log_offset;    /* where this run's output starts in the log */
    int64_t cpu_us;     /* user + system CPU time of its runs that have ended */
} launch_stage;

/* Starts (or starts again) the stage. Children get SIGTERM if the launcher dies, so none is ever
 * left behind. Returns 0 or -1 (fork failed). */
int launch_start(launch_stage *s);
/* Waits until the stage's log (this run) has its ready line. 0 = ready, -1 = it exited first or
 * timeout_ms passed. */
int launch_wait_ready(launch_stage *s, int timeout_ms);
/* Reaps one exited stage without blocking: its index, and its status in *status (exit code, or
 * 128 + signal); -1 when none exited. The run's CPU time is added to its cpu_us. */
int launch_reap(launch_stage *st, int n, int *status);
/* SIGINT to every running stage, then SIGKILL to those still running after grace_ms; all reaped. */
void launch_stop_all(launch_stage *st, int n, int grace_ms);
/* The last lines of this run's log into out (for messages about a stage that failed). */
void launch_log_tail(const launch_stage *s, char *out, size_t size);
int64_t launch_now_us(void);

/* The path of a sibling executable: $TRYON_BIN_DIR/NAME, the build tree's <folder>/NAME next to
 * the launcher's own folder, the launcher's folder, then $PATH. Returns 0 or -1 (not found). */
int launch_find(const char *name, char *out, size_t size);

#endif
