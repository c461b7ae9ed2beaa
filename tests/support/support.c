#include "support.h"

#include <errno.h>
#include <fcntl.h>
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

static pid_t spawn_with(char *const argv[], char *const env_add[], const char *out_path);

pid_t ts_spawn(char *const argv[], char *const env_add[])
{
    return spawn_with(argv, env_add, NULL);
}

pid_t ts_spawn_out(char *const argv[], char *const env_add[], const char *out_path)
{
    return spawn_with(argv, env_add, out_path);
}

char *ts_read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)(n > 0 ? n : 0) + 1);
    size_t got = s ? fread(s, 1, (size_t)(n > 0 ? n : 0), f) : 0;
    if (s)
        s[got] = 0;
    fclose(f);
    return s;
}

static pid_t spawn_with(char *const argv[], char *const env_add[], const char *out_path)
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
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    if (out_path) {
        posix_spawn_file_actions_addopen(&fa, 1, out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        posix_spawn_file_actions_adddup2(&fa, 1, 2);
    }
    pid_t pid;
    int rc = posix_spawn(&pid, argv[0], &fa, NULL, argv, env);
    posix_spawn_file_actions_destroy(&fa);
    return rc == 0 ? pid : -1;
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
