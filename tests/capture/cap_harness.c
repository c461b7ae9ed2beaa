#include "cap_harness.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "recordings.h"

uint16_t h_raw(int k, int i)
{
    /* Every disparity value appears, including 2047 (no reading), shifted per frame. */
    return (uint16_t)((i * 7 + k * 131) % REC_RAW_LEVELS);
}

uint32_t h_timestamp(int k)
{
    return 1000u + 33333u * (uint32_t)k;
}

static void on_depth(const char *channel, const void *msg, void *user)
{
    (void)channel;
    harness *h = user;
    const tryon_depth_frame_t *m = msg;
    if (h->depth_count >= H_MAX_FRAMES)
        return;
    h_depth *d = &h->depth[h->depth_count++];
    d->utime_capture = m->utime_capture;
    d->utime_received = bus_now_wall_us();
    d->device_timestamp = m->device_timestamp;
    d->seq = m->seq;
    d->width = m->width;
    d->height = m->height;
    d->fx = m->fx;
    d->metres_per_unit = m->metres_per_unit;
    snprintf(d->source, sizeof d->source, "%s", m->source);
    if (m->num_bytes == H_PIXELS * 2)
        for (int i = 0; i < H_PIXELS; i++)
            d->mm[i] = (uint16_t)(m->data[2 * i] | (m->data[2 * i + 1] << 8));
}

static void on_timing(const char *channel, const void *msg, void *user)
{
    (void)channel;
    harness *h = user;
    const tryon_timing_t *m = msg;
    if (h->timing_count < H_MAX_FRAMES && !strcmp(m->stage, "capture"))
        h->timing_seq[h->timing_count++] = m->seq;
}

harness *h_create(int port)
{
    harness *h = calloc(1, sizeof *h);
    snprintf(h->dir, sizeof h->dir, "/tmp/tryon-test-cap-%d-%d", port, (int)getpid());
    snprintf(h->out_dir, sizeof h->out_dir, "%s-record", h->dir);
    snprintf(h->url, sizeof h->url, "udpm://239.255.76.67:%d?ttl=0&recv_buf_size=8388608", port);
    snprintf(h->prefix, sizeof h->prefix, "test_cap_%d_", (int)getpid());
    setenv("TRYON_LCM_URL", h->url, 1);
    setenv("TRYON_CHANNEL_PREFIX", h->prefix, 1);
    for (int i = 0; i < H_MAX_FRAMES; i++)
        h->depth[i].mm = calloc(H_PIXELS, sizeof(uint16_t));
    char err[256];
    h->lcm = bus_open(h->url, err, sizeof err);
    if (!h->lcm) {
        fprintf(stderr, "harness: %s\n", err);
        abort();
    }
    char ch[BUS_CHANNEL_MAX];
    bus_channel(BUS_CHANNEL_DEPTH, ch, sizeof ch);
    h->depth_sub = bus_subscribe(h->lcm, ch, BUS_DEPTH_FRAME, on_depth, h);
    bus_channel(BUS_CHANNEL_TIMING, ch, sizeof ch);
    h->timing_sub = bus_subscribe(h->lcm, ch, BUS_TIMING, on_timing, h);
    h->child = -1;
    h->logger = -1;
    h->err_fd = -1;
    return h;
}

static void rm_rf(const char *dir)
{
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "harness: could not remove %s\n", dir);
}

void h_destroy(harness *h)
{
    pid_t kids[2] = {h->child, h->logger};
    for (int i = 0; i < 2; i++)
        if (kids[i] > 0) {
            kill(kids[i], SIGKILL);
            waitpid(kids[i], NULL, 0);
        }
    if (h->err_fd >= 0)
        close(h->err_fd);
    bus_unsubscribe(h->lcm, h->depth_sub);
    bus_unsubscribe(h->lcm, h->timing_sub);
    lcm_destroy(h->lcm);
    rm_rf(h->dir);
    rm_rf(h->out_dir);
    for (int i = 0; i < H_MAX_FRAMES; i++)
        free(h->depth[i].mm);
    free(h);
}

void h_write_dump(harness *h, int n, double fps)
{
    rec_report why;
    rec_writer *w = rec_writer_create(h->dir, &why);
    uint16_t *raw = malloc(sizeof(uint16_t) * H_PIXELS);
    for (int k = 0; k < n; k++) {
        for (int i = 0; i < H_PIXELS; i++)
            raw[i] = h_raw(k, i);
        if (rec_writer_frame(w, raw, 1.0 + k / fps, h_timestamp(k), &why) != REC_OK) {
            fprintf(stderr, "harness: %s\n", why.message);
            abort();
        }
    }
    free(raw);
    rec_writer_destroy(w);
}

void h_start(harness *h, const char *const *args)
{
    int fds[2];
    if (pipe(fds) != 0)
        abort();
    const char *argv[32] = {TRYON_CAPTURE_EXE};
    int n = 1;
    for (; args[n - 1] && n < 31; n++)
        argv[n] = args[n - 1];
    argv[n] = NULL;
    h->child = fork();
    if (h->child == 0) {
        dup2(fds[1], 2);
        close(fds[0]);
        close(fds[1]);
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    close(fds[1]);
    h->err_fd = fds[0];
    fcntl(h->err_fd, F_SETFL, O_NONBLOCK);
    h->err_text[0] = 0;
}

static void drain_stderr(harness *h)
{
    size_t len = strlen(h->err_text);
    while (h->err_fd >= 0 && len + 1 < sizeof h->err_text) {
        ssize_t r = read(h->err_fd, h->err_text + len, sizeof h->err_text - 1 - len);
        if (r <= 0)
            break;
        len += (size_t)r;
        h->err_text[len] = 0;
    }
}

int h_wait(harness *h, double timeout_s)
{
    int64_t end = bus_now_mono_us() + (int64_t)(timeout_s * 1e6);
    int status = 0;
    while (bus_now_mono_us() < end) {
        lcm_handle_timeout(h->lcm, 20);
        drain_stderr(h);
        pid_t r = waitpid(h->child, &status, WNOHANG);
        if (r == h->child) {
            h->child = -1;
            /* Messages sent just before the exit may still be queued. */
            while (lcm_handle_timeout(h->lcm, 100) > 0)
                ;
            drain_stderr(h);
            return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        }
    }
    return -1;
}

int h_wait_frames(harness *h, int n, double timeout_s)
{
    int64_t end = bus_now_mono_us() + (int64_t)(timeout_s * 1e6);
    while (h->depth_count < n && bus_now_mono_us() < end) {
        lcm_handle_timeout(h->lcm, 20);
        drain_stderr(h);
    }
    return h->depth_count;
}
