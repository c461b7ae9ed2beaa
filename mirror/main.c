/* tryon-mirror: DEPTH, BODY, CLOTH and TIMING in; the person wearing the garment out, in a
 * window (SDL2, --kiosk full screen) or as PNG frames and a video (--headless). Keys (window):
 * right/left next and previous garment, up/down size, o overlay, f fit map, b fitted body, q quit;
 * a garment or size change goes to tryon-sim over CONTROL. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bus.h"
#include "mirror.h"
#include "tryon_heap.h"
#include "mirror_app.h"

static volatile sig_atomic_t stop_requested;

static void on_signal(int sig)
{
    (void)sig;
    stop_requested = 1;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: tryon-mirror [--headless --out DIR] [--video FILE.mp4] [--kiosk]\n"
               "                    [--size WxH] [--frames N] [--png-every N] [--garment FILE]...\n"
               "                    [--fabric NAME] [--fit-map] [--body] [--no-overlay]\n"
               "                    [--queue N|latest]\n"
               "  --headless: no window; EGL's surfaceless Mesa platform (no display needed)\n"
               "  --out DIR: a PNG per rendered frame (frame_00000.png, ...), every --png-every N\n"
               "  --video FILE.mp4: the frames through ffmpeg (H.264, 30 fps)\n"
               "  --size WxH: the picture, default 640x480 (the window may be resized)\n"
               "  --frames N: exit after N frames drawn with a garment (0: run until stopped)\n"
               "  --queue N|latest: at most N CLOTH wait to be drawn, oldest first (1-4, default\n"
               "          3); one arriving at a full queue supersedes the oldest. latest: 1\n"
               "  --garment FILE: a garment file offered besides shirt and tunic (repeatable)\n"
               "  --fabric NAME: the fabric asked for over CONTROL (cotton, denim, jersey, silk)\n"
               "  keys: right/left garment, up/down size, o overlay, f fit map, b body, q quit\n"
               "  environment: TRYON_LCM_URL, TRYON_CHANNEL_PREFIX, LP_NUM_THREADS (default 1)\n");
}

static int parse_size(const char *v, int *w, int *h)
{
    char x;
    return sscanf(v, "%d%c%d", w, &x, h) == 3 && (x == 'x' || x == 'X') && *w >= 16 && *h >= 16 &&
                   *w <= 8192 && *h <= 8192
               ? 0
               : -1;
}

static int parse(mirror_app *a, int argc, char **argv)
{
    a->width = 640;
    a->height = 480;
    a->png_every = 1;
    a->overlay = 1;
    mirror_cloth_queue_init(&a->queue, MIRROR_APP_QUEUE);
    for (int i = 1; i < argc; i++) {
        const char *o = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(o, "--help") || !strcmp(o, "-h")) {
            usage(stdout);
            exit(0);
        } else if (!strcmp(o, "--headless"))
            a->headless = 1;
        else if (!strcmp(o, "--kiosk"))
            a->kiosk = 1;
        else if (!strcmp(o, "--fit-map"))
            a->fit_map = 1;
        else if (!strcmp(o, "--body"))
            a->show_body = 1;
        else if (!strcmp(o, "--no-overlay"))
            a->overlay = 0;
        else if (!v) {
            fprintf(stderr, "tryon-mirror: %s: unknown option or missing value\n", o);
            return -1;
        } else {
            i++;
            if (!strcmp(o, "--out"))
                a->out_dir = v;
            else if (!strcmp(o, "--video"))
                a->video_path = v;
            else if (!strcmp(o, "--fabric"))
                a->fabric = v;
            else if (!strcmp(o, "--garment") && a->num_garments < MIRROR_APP_MAX_GARMENTS - 2)
                a->garments[a->num_garments++] = v;
            else if (!strcmp(o, "--frames") && atoi(v) >= 0)
                a->frames_wanted = atoi(v);
            else if (!strcmp(o, "--png-every") && atoi(v) >= 1)
                a->png_every = atoi(v);
            else if (!strcmp(o, "--queue") && !strcmp(v, "latest"))
                mirror_cloth_queue_init(&a->queue, 1);
            else if (!strcmp(o, "--queue") && atoi(v) >= 1 && atoi(v) <= BUS_QUEUE_MAX)
                mirror_cloth_queue_init(&a->queue, atoi(v));
            else if (!strcmp(o, "--size") && parse_size(v, &a->width, &a->height) == 0)
                ;
            else {
                fprintf(stderr, "tryon-mirror: %s %s: unknown option or bad value\n", o, v);
                return -1;
            }
        }
    }
    a->garments[a->num_garments++] = "shirt";
    a->garments[a->num_garments++] = "tunic";
    a->size = 1; /* M */
    if (a->out_dir && mkdir(a->out_dir, 0777) < 0 && access(a->out_dir, W_OK) < 0) {
        fprintf(stderr, "tryon-mirror: --out %s: cannot make or write that folder\n", a->out_dir);
        return -1;
    }
    return 0;
}

/* The window's keys: garment and size go to tryon-sim over CONTROL; the rest are the view's. */
static void on_key(mirror_app *a, mirror_key k)
{
    switch (k) {
    case MIRROR_KEY_NEXT:
    case MIRROR_KEY_PREVIOUS:
        a->garment =
            (a->garment + (k == MIRROR_KEY_NEXT ? 1 : a->num_garments - 1)) % a->num_garments;
        mirror_app_send_control(a);
        break;
    case MIRROR_KEY_SIZE_UP:
    case MIRROR_KEY_SIZE_DOWN:
        a->size += k == MIRROR_KEY_SIZE_UP ? (a->size < 2) : -(a->size > 0);
        mirror_app_send_control(a);
        break;
    case MIRROR_KEY_OVERLAY:
        a->overlay = !a->overlay;
        break;
    case MIRROR_KEY_FIT_MAP:
        a->fit_map = !a->fit_map;
        break;
    case MIRROR_KEY_BODY:
        a->show_body = !a->show_body;
        break;
    case MIRROR_KEY_QUIT:
        stop_requested = 1;
        break;
    default:
        break;
    }
}

static int run(mirror_app *a)
{
    while (!stop_requested) {
        /* what has arrived, then one frame: the oldest CLOTH waiting (at most --queue of them) */
        int r = lcm_handle_timeout(a->lcm, mirror_cloth_queue_count(&a->queue) ? 0 : 10);
        while (r > 0 && !stop_requested)
            r = lcm_handle_timeout(a->lcm, 0);
        if (r < 0 && !stop_requested && errno != EINTR) {
            fprintf(stderr, "tryon-mirror: LCM stopped receiving\n");
            return 1;
        }
        if (a->window) {
            mirror_key k;
            while ((k = mirror_window_poll(a->window)) != MIRROR_KEY_NONE)
                on_key(a, k);
        }
        if (mirror_app_due(a) && mirror_app_frame(a) < 0)
            return 1;
        if (a->frames_wanted > 0 && a->frames_drawn >= a->frames_wanted)
            break;
    }
    return 0;
}

int main(int argc, char **argv)
{
    static mirror_app a;
    if (parse(&a, argc, argv) < 0) {
        usage(stderr);
        return 2;
    }
    setenv("LP_NUM_THREADS", "1", 0); /* llvmpipe: one thread; fitting and cloth need the cores */
    tryon_keep_heap();
    struct sigaction sa = {.sa_handler = on_signal};
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    signal(SIGPIPE, SIG_IGN); /* ffmpeg gone: a failed write, reported */
    int status = mirror_app_open(&a) < 0 ? 1 : run(&a);
    mirror_app_close(&a);
    return status;
}
