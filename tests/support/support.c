#include "support.h"

#include <errno.h>
#include <signal.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

extern char **environ;

#define TS_MAX_ENV 512

pid_t ts_spawn(char *const argv[], char *const env_add[])
{
    char *env[TS_MAX_ENV];
    int n = 0;
    for (int i = 0; env_add && env_add[i] && n < TS_MAX_ENV - 1; i++)
        env[n++] = env_add[i];
    for (char **e = environ; *e && n < TS_MAX_ENV - 1; e++) {
        /* Entries in env_add override the inherited ones of the same name. */
        const char *eq = strchr(*e, '=');
        size_t len = eq ? (size_t)(eq - *e) + 1 : strlen(*e);
        int overridden = 0;
        for (int i = 0; env_add && env_add[i]; i++)
            overridden |= strncmp(env_add[i], *e, len) == 0;
        if (!overridden)
            env[n++] = *e;
    }
    env[n] = NULL;
    pid_t pid;
    if (posix_spawn(&pid, argv[0], NULL, NULL, argv, env) != 0)
        return -1;
    return pid;
}

int ts_wait(pid_t pid, int timeout_ms)
{
    struct timespec step = {0, 5 * 1000 * 1000};
    for (int waited = 0;; waited += 5) {
        int status;
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid)
            return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        if (r < 0 && errno != EINTR)
            return -1;
        if (waited >= timeout_ms) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            return -1;
        }
        nanosleep(&step, NULL);
    }
}

int ts_stop(pid_t pid, int sig, int timeout_ms)
{
    kill(pid, sig);
    return ts_wait(pid, timeout_ms);
}

void ts_private_bus(char *url, size_t url_size, char *prefix, size_t prefix_size)
{
    int id = (int)getpid();
    /* 7700..8699: away from LCM's default 7667 so a running pipeline is never disturbed. */
    snprintf(url, url_size, "udpm://239.255.76.67:%d?ttl=0&recv_buf_size=8388608",
             7700 + id % 1000);
    snprintf(prefix, prefix_size, "T%d_", id);
    setenv("TRYON_LCM_URL", url, 1);
    setenv("TRYON_CHANNEL_PREFIX", prefix, 1);
}

int ts_temp_dir(char *out, size_t size, const char *tag)
{
    const char *tmp = getenv("TMPDIR");
    snprintf(out, size, "%s/tryon-%s-XXXXXX", tmp && tmp[0] ? tmp : "/tmp", tag);
    return mkdtemp(out) ? 0 : -1;
}

void ts_remove_dir(const char *dir)
{
    char *argv[] = {"/bin/rm", "-rf", (char *)dir, NULL};
    ts_wait(ts_spawn(argv, NULL), 10000);
}
