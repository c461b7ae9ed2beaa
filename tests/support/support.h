/* Test support: child processes with a deadline, and an LCM URL and channel prefix of the
 * test's own so that ctest -j never lets two tests hear each other. */
#ifndef TRYON_TEST_SUPPORT_H
#define TRYON_TEST_SUPPORT_H

#include <stddef.h>
#include <sys/types.h>

/* Starts argv[0] (a path) with the current environment plus env_add ("NAME=value", NULL-ended,
 * may be NULL). Returns the pid, or -1. */
pid_t ts_spawn(char *const argv[], char *const env_add[]);
/* Like ts_spawn, with stdout and stderr written to out_path (truncated first). */
pid_t ts_spawn_out(char *const argv[], char *const env_add[], const char *out_path);
/* Reads a whole (small) file into a malloc'd, NUL-terminated string; NULL if unreadable. */
char *ts_read_file(const char *path);
/* Waits up to timeout_ms. Returns the exit status, 128 + signal if it was killed by one, or -1 if
 * the deadline passed (the child is then killed with SIGKILL and reaped). */
int ts_wait(pid_t pid, int timeout_ms);
/* Sends sig, then waits up to timeout_ms as ts_wait does. */
int ts_stop(pid_t pid, int sig, int timeout_ms);

/* A udpm URL on a port derived from this process's pid, with a large receive buffer, and a
 * channel prefix likewise; also exported as TRYON_LCM_URL and TRYON_CHANNEL_PREFIX so child
 * processes inherit them. */
void ts_private_bus(char *url, size_t url_size, char *prefix, size_t prefix_size);

/* Path of a fresh temporary directory (mkdtemp under $TMPDIR or /tmp). */
int ts_temp_dir(char *out, size_t size, const char *tag);
/* rm -r of a directory made by ts_temp_dir. */
void ts_remove_dir(const char *dir);

#endif
