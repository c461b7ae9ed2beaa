/* Child processes for the launcher: started with their output in a log, watched, restarted,
 * stopped. */
#define _GNU_SOURCE /* prctl's PR_SET_PDEATHSIG */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "launch.h"

int64_t launch_now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

static long file_size(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 ? (long)sb.st_size : 0;
}

int launch_start(launch_stage *s)
{
    s->log_offset = file_size(s->log);
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        /* the launcher's death (even SIGKILL) takes its stages with it */
        prctl(PR_SET_PDEATHSIG, SIGTERM);
        if (getppid() != parent)
            _exit(1);
        if (s->nice > 0 && setpriority(PRIO_PROCESS, 0, s->nice) < 0)
            fprintf(stderr, "tryon: %s: nice %d: %s\n", s->name, s->nice, strerror(errno));
        int fd = open(s->log, O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
            close(fd);
        }
        execv(s->argv[0], s->argv);
        fprintf(stderr, "tryon: cannot run %s: %s\n", s->argv[0], strerror(errno));
        _exit(127);
    }
    s->pid = pid;
    s->started_us = launch_now_us();
    return 0;
}

static int log_has(const launch_stage *s, const char *text)
{
    FILE *f = fopen(s->log, "r");
    if (!f)
        return 0;
    fseek(f, s->log_offset, SEEK_SET);
    char line[1024];
    int found = 0;
    while (!found && fgets(line, sizeof line, f))
        found = strstr(line, text) != NULL;
    fclose(f);
    return found;
}

int launch_wait_ready(launch_stage *s, int timeout_ms)
{
    for (int waited = 0; waited <= timeout_ms; waited += 20) {
        if (!s->ready || log_has(s, s->ready))
            return 0;
        int status;
        if (waitpid(s->pid, &status, WNOHANG) == s->pid) {
            s->pid = 0;
            return -1;
        }
        struct timespec ts = {0, 20 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    return -1;
}

static int64_t cpu_us(const struct rusage *ru)
{
    return (int64_t)(ru->ru_utime.tv_sec + ru->ru_stime.tv_sec) * 1000000 + ru->ru_utime.tv_usec +
           ru->ru_stime.tv_usec;
}

int launch_reap(launch_stage *st, int n, int *status)
{
    for (int i = 0; i < n; i++) {
        int w;
        struct rusage ru;
        if (st[i].pid > 0 && wait4(st[i].pid, &w, WNOHANG, &ru) == st[i].pid) {
            st[i].cpu_us += cpu_us(&ru);
            st[i].last_pid = st[i].pid;
            st[i].pid = 0;
            *status = WIFEXITED(w) ? WEXITSTATUS(w) : 128 + WTERMSIG(w);
            return i;
        }
    }
    return -1;
}

void launch_stop_all(launch_stage *st, int n, int grace_ms)
{
    for (int i = 0; i < n; i++)
        if (st[i].pid > 0)
            kill(st[i].pid, SIGINT);
    int64_t end = launch_now_us() + (int64_t)grace_ms * 1000;
    int running = 1;
    while (running && launch_now_us() < end) {
        int status;
        while (launch_reap(st, n, &status) >= 0)
            ;
        running = 0;
        for (int i = 0; i < n; i++)
            running |= st[i].pid > 0;
        struct timespec ts = {0, 20 * 1000 * 1000};
        if (running)
            nanosleep(&ts, NULL);
    }
    for (int i = 0; i < n; i++)
        if (st[i].pid > 0) {
            fprintf(stderr, "tryon: %s (pid %d) did not stop within %d ms: killed\n", st[i].name,
                    (int)st[i].pid, grace_ms);
            kill(st[i].pid, SIGKILL);
            struct rusage ru;
            if (wait4(st[i].pid, NULL, 0, &ru) == st[i].pid)
                st[i].cpu_us += cpu_us(&ru);
            st[i].pid = 0;
        }
}

void launch_log_tail(const launch_stage *s, char *out, size_t size)
{
    out[0] = 0;
    FILE *f = fopen(s->log, "r");
    if (!f)
        return;
    long end = file_size(s->log), from = end - (long)size + 1;
    from = from < s->log_offset ? s->log_offset : from;
    fseek(f, from, SEEK_SET);
    size_t k = fread(out, 1, size - 1, f);
    out[k] = 0;
    fclose(f);
}

static int executable(const char *path)
{
    return access(path, X_OK) == 0;
}

int launch_find(const char *name, char *out, size_t size)
{
    static const char *folders[] = {"capture", "bodyfit", "sim", "mirror", "recordings", "bus"};
    const char *env = getenv("TRYON_BIN_DIR");
    if (env && *env) {
        snprintf(out, size, "%s/%s", env, name);
        if (executable(out))
            return 0;
    }
    char self[512];
    ssize_t k = readlink("/proc/self/exe", self, sizeof self - 1);
    if (k > 0) {
        self[k] = 0;
        char *slash = strrchr(self, '/');
        if (slash) {
            *slash = 0;
            for (size_t i = 0; i < sizeof folders / sizeof folders[0]; i++) {
                snprintf(out, size, "%s/../%s/%s", self, folders[i], name);
                if (executable(out))
                    return 0;
            }
            snprintf(out, size, "%s/%s", self, name);
            if (executable(out))
                return 0;
        }
    }
    const char *path = getenv("PATH");
    while (path && *path) {
        size_t n = strcspn(path, ":");
        snprintf(out, size, "%.*s/%s", (int)n, path, name);
        if (n && executable(out))
            return 0;
        path += n + (path[n] == ':');
    }
    return -1;
}
