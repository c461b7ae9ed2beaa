/* tryon-mirror's state: messages in, frames out. Each CLOTH is drawn over the DEPTH frame it
 * derives from (same utime_capture, from the ring); the frame's cost is reported on TIMING as
 * stage "mirror", so tryon-profile measures capture -> garment on screen. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <GLES3/gl3.h>

#include "mirror_app.h"

/* Depth frames alone are drawn (in a window) when no garment has come for this long: the person
 * is shown before the sim's first cloth, or after it stops. */
#define MIRROR_CLOTH_STALE_US 500000

static void on_depth(const char *ch, const void *m, void *user)
{
    (void)ch;
    mirror_app *a = user;
    const tryon_depth_frame_t *f = m;
    mirror_depth d = {.width = f->width,
                      .height = f->height,
                      .fx = f->fx,
                      .fy = f->fy,
                      .cx = f->cx,
                      .cy = f->cy,
                      .metres_per_unit = f->metres_per_unit,
                      .data = (const uint16_t *)f->data,
                      .utime_capture = f->utime_capture};
    memcpy(d.camera_to_world, f->camera_to_world, sizeof d.camera_to_world);
    if (mirror_ring_push(a->ring, &d) == 0)
        a->depth_new = 1;
}

/* A CLOTH waits to be drawn (mirror/cloth_queue.c: the oldest superseded at a full queue; one
 * that cannot be drawn skipped; both counted). */
static void on_cloth(const char *ch, const void *m, void *user)
{
    (void)ch;
    mirror_app *a = user;
    const tryon_cloth_t *c = m;
    if (mirror_cloth_queue_push(&a->queue, c, bus_now_wall_us()) < 0)
        return;
    if (strcmp(c->garment_id, a->garment_id) != 0) { /* a new garment: its own rest lengths */
        snprintf(a->garment_id, sizeof a->garment_id, "%s", c->garment_id);
        mirror_strain_reset(a->strain);
    }
    a->last_cloth_us = bus_now_mono_us();
    a->have_cloth = 1;
}

static void on_body(const char *ch, const void *m, void *user)
{
    (void)ch;
    mirror_app *a = user;
    const tryon_body_t *b = m;
    mirror_hold(&a->body, b->vertices, b->num_vertex_coords, b->triangles, b->num_triangle_indices,
                b->topology_id);
}

static void on_timing(const char *ch, const void *m, void *user)
{
    (void)ch;
    mirror_app *a = user;
    const tryon_timing_t *t = m;
    stage_latency *s = NULL;
    for (int i = 0; i < a->num_stages && !s; i++)
        if (!strcmp(a->stages[i].stage, t->stage))
            s = &a->stages[i];
    if (!s && a->num_stages < MIRROR_APP_STAGES) {
        s = &a->stages[a->num_stages++];
        snprintf(s->stage, sizeof s->stage, "%s", t->stage);
        s->latency_ms = (double)(t->utime_finished - t->utime_capture) / 1000.0;
        s->work_ms = (double)(t->utime_finished - t->utime_started) / 1000.0;
    }
    if (!s)
        return;
    /* smoothed over about ten frames: readable, and still follows a change within a second */
    s->latency_ms +=
        0.1 * ((double)(t->utime_finished - t->utime_capture) / 1000.0 - s->latency_ms);
    s->work_ms += 0.1 * ((double)(t->utime_finished - t->utime_started) / 1000.0 - s->work_ms);
}

/* Where the next frame is drawn; w, h: the window's size (the picture's headless). */
static int choose_target(mirror_app *a, int *w, int *h)
{
    int direct = 0;
    *w = a->width;
    *h = a->height;
    if (a->window) { /* the picture's size: drawn straight into the back buffer, no copy */
        mirror_window_size(a->window, w, h);
        direct = *w == a->width && *h == a->height;
    }
    mirror_renderer_draw_to_window(a->renderer, direct);
    if (a->window && a->window_path != 1 + direct) { /* said once, and on each change */
        a->window_path = 1 + direct;
        if (direct)
            fprintf(stderr, "tryon-mirror: drawing straight into the window's back buffer\n");
        else
            fprintf(stderr, "tryon-mirror: the window is %dx%d: the picture is scaled into it\n",
                    *w, *h);
    }
    return direct;
}

/* Before the bus is listened to: the first real frame then costs what every frame costs. A
 * failure costs only that: said, and the mirror goes on. */
static void warm_up(mirror_app *a)
{
    char err[512];
    int w, h, direct = choose_target(a, &w, &h);
    int64_t t0 = bus_now_mono_us();
    if (mirror_warm_up(a->renderer, a->ring, err, sizeof err) < 0) {
        fprintf(stderr, "tryon-mirror: warm-up draw: %s; the first frame compiles instead\n", err);
        return;
    }
    if (a->window && !direct) { /* the scaled copy's shader too; not shown (no swap) */
        mirror_present(a->renderer, w, h);
        glFinish();
    }
    /* headless, the first frame also writes the session's first PNG: its read-back and zlib's
       buffers too (kept in the heap, tryon_heap.h), written where nothing keeps it */
    if (a->out_dir && a->rgb) {
        mirror_read_rgb(a->renderer, a->rgb);
        if (mirror_png_write("/dev/null", a->rgb, a->width, a->height, err, sizeof err) < 0)
            fprintf(stderr, "tryon-mirror: warm-up PNG: %s\n", err);
    }
    fprintf(stderr, "tryon-mirror: warmed up: a first draw of %.1f ms (shaders compiled)\n",
            (double)(bus_now_mono_us() - t0) / 1000.0);
}

static int open_output(mirror_app *a)
{
    char err[512];
    if (a->headless) {
        a->gl = mirror_gl_headless(err, sizeof err);
    } else {
        a->window = mirror_window_create(a->width, a->height, a->kiosk, err, sizeof err);
    }
    if (!a->gl && !a->window) {
        fprintf(stderr, "tryon-mirror: %s\n", err);
        return -1;
    }
    a->renderer = mirror_renderer_create(a->width, a->height, err, sizeof err);
    if (!a->renderer) {
        fprintf(stderr, "tryon-mirror: renderer: %s\n", err);
        return -1;
    }
    a->rgb = malloc((size_t)a->width * a->height * 3);
    if (!a->rgb)
        return -1;
    if (a->video_path) {
        a->video = mirror_video_open(a->video_path, a->width, a->height, MIRROR_VIDEO_FPS, err,
                                     sizeof err);
        if (!a->video) {
            fprintf(stderr, "tryon-mirror: --video %s: %s\n", a->video_path, err);
            return -1;
        }
    }
    fprintf(stderr, "tryon-mirror: %dx%d %s on %s\n", a->width, a->height,
            a->headless ? "headless"
            : a->kiosk  ? "kiosk"
                        : "window",
            (const char *)glGetString(GL_RENDERER));
    return 0;
}

int mirror_app_open(mirror_app *a)
{
    char err[512], ch[4][BUS_CHANNEL_MAX];
    a->ring = mirror_ring_create();
    a->strain = mirror_strain_create();
    if (!a->ring || !a->strain)
        return -1;
    a->lcm = bus_open(NULL, err, sizeof err);
    if (!a->lcm) {
        fprintf(stderr, "tryon-mirror: %s\n", err);
        return -1;
    }
    const char *base[4] = {BUS_CHANNEL_DEPTH, BUS_CHANNEL_CLOTH, BUS_CHANNEL_BODY,
                           BUS_CHANNEL_TIMING};
    const bus_type type[4] = {BUS_DEPTH_FRAME, BUS_CLOTH, BUS_BODY, BUS_TIMING};
    bus_handler fn[4] = {on_depth, on_cloth, on_body, on_timing};
    for (int i = 0; i < 4; i++) {
        bus_channel(base[i], ch[i], sizeof ch[i]);
        a->subs[i] = bus_subscribe(a->lcm, ch[i], type[i], fn[i], a);
        if (!a->subs[i]) {
            fprintf(stderr, "tryon-mirror: cannot subscribe to %s\n", ch[i]);
            return -1;
        }
    }
    bus_channel(BUS_CHANNEL_CONTROL, a->ch_control, sizeof a->ch_control);
    if (open_output(a) < 0)
        return -1;
    warm_up(a);
    fprintf(stderr, "tryon-mirror: listening for %s and %s on %s\n", ch[0], ch[1],
            bus_default_url());
    return 0;
}

int mirror_app_due(const mirror_app *a)
{
    if (mirror_cloth_queue_count(&a->queue) > 0)
        return 1;
    /* a window shows the person alone while no garment comes; files get garment frames only */
    return a->window && a->depth_new &&
           (!a->have_cloth || bus_now_mono_us() - a->last_cloth_us > MIRROR_CLOTH_STALE_US);
}

static void overlay_text(const mirror_app *a, char *out, size_t n)
{
    size_t k = (size_t)snprintf(out, n, "FPS %.1f  FRAME %d\n", a->fps, a->frames_drawn);
    for (int i = 0; i < a->num_stages && k < n; i++)
        k += (size_t)snprintf(out + k, n - k, "%-8s %6.1f MS  (WORK %.1f)\n", a->stages[i].stage,
                              a->stages[i].latency_ms, a->stages[i].work_ms);
    if (k < n)
        k += (size_t)snprintf(out + k, n - k, "GARMENT %s\n",
                              a->garment_id[0] ? a->garment_id : "(WAITING)");
    if (a->fit_map && k < n)
        snprintf(out + k, n - k, "FIT MAP: STRAIN 0 - %.0f%%\n", 100.0 * MIRROR_FIT_MAP_LIMIT);
}

static void write_outputs(mirror_app *a)
{
    char err[512], path[600];
    int png = a->out_dir && a->frames_drawn % a->png_every == 0;
    if (!png && !a->video)
        return; /* nothing takes this frame: no read-back (0.5 ms of CPU at 640x480) */
    mirror_read_rgb(a->renderer, a->rgb);
    if (png) {
        snprintf(path, sizeof path, "%s/frame_%05d.png", a->out_dir, a->frames_drawn);
        if (mirror_png_write(path, a->rgb, a->width, a->height, err, sizeof err) < 0)
            fprintf(stderr, "tryon-mirror: frame %d not written: %s\n", a->frames_drawn, err);
        else
            a->pngs_written++;
    }
    if (!a->video)
        return;
    /* The video keeps the camera's time: a frame the mirror had no time to draw is the last one
     * drawn again, so the video plays at the session's pace (at most a second of repeats). */
    int64_t t = a->cloth.utime_capture;
    if (a->video_frames == 0)
        a->video_t0 = t;
    int64_t due = 1 + (t - a->video_t0 + MIRROR_VIDEO_FRAME_US / 2) / MIRROR_VIDEO_FRAME_US;
    int repeat = due - a->video_frames < 1 ? 1 : (int)(due - a->video_frames);
    repeat = repeat > MIRROR_VIDEO_FPS ? MIRROR_VIDEO_FPS : repeat;
    for (int i = 0; i < repeat && a->video; i++, a->video_frames++)
        if (mirror_video_write(a->video, a->rgb) < 0) {
            fprintf(stderr, "tryon-mirror: ffmpeg stopped taking frames; video ends here\n");
            mirror_video_close(a->video);
            a->video = NULL;
        }
}

int mirror_app_frame(mirror_app *a)
{
    int with_cloth = mirror_cloth_queue_take(&a->queue, &a->cloth), exact = 0;
    a->depth_new = 0;
    const mirror_depth *d = with_cloth ? mirror_ring_find(a->ring, a->cloth.utime_capture, &exact)
                                       : mirror_ring_newest(a->ring);
    if (!d)
        return 0; /* no depth frame yet: nothing to draw the garment over */
    a->unmatched += with_cloth && !exact;
    bus_timing t;
    bus_timing_begin(&t, "mirror", with_cloth ? a->cloth.seq : 0, d->utime_capture,
                     with_cloth ? a->cloth.received_us : bus_now_wall_us());
    mirror_mesh garment = {a->cloth.xyz, a->cloth.nv, a->cloth.tris, a->cloth.nt, NULL};
    mirror_mesh body = {a->body.xyz, a->body.nv, a->body.tris, a->body.nt, NULL};
    if (a->fit_map && with_cloth)
        garment.strain =
            mirror_strain_update(a->strain, garment.xyz, garment.nv, garment.tris, garment.nt);
    char text[1024];
    overlay_text(a, text, sizeof text);
    mirror_view v = {.depth = d,
                     .garment = a->have_cloth ? &garment : NULL,
                     .body = a->show_body && a->body.nt > 0 ? &body : NULL,
                     .fit_map = a->fit_map,
                     .overlay_text = a->overlay ? text : NULL};
    char err[512];
    int w, h, direct = choose_target(a, &w, &h);
    int64_t t0 = bus_now_mono_us(), cpu0 = bus_now_cpu_us(); /* llvmpipe's threads too */
    if (mirror_render(a->renderer, &v, err, sizeof err) < 0) {
        fprintf(stderr, "tryon-mirror: frame %d: %s; skipped\n", a->frames_drawn, err);
        return 0;
    }
    glFinish(); /* drawn: what follows is showing or saving it */
    int64_t t1 = bus_now_mono_us();
    if (a->window) {
        if (!direct)
            mirror_present(a->renderer, w, h);
        if (a->out_dir || a->video) /* what the window shows, read back from its own buffer */
            write_outputs(a);
        mirror_window_swap(a->window);
        glFinish(); /* on screen before the frame is called done */
        if (!a->presents_said++)
            fprintf(stderr, "tryon-mirror: the window presents %s\n",
                    mirror_window_presents(a->window));
    } else {
        write_outputs(a);
    }
    int64_t now = bus_now_mono_us();
    bus_timing_add(&t, "render", (float)(t1 - t0) / 1000.0f);
    bus_timing_add(&t, "output", (float)(now - t1) / 1000.0f);
    bus_timing_add(&t, "cpu", (float)(bus_now_cpu_us() - cpu0) / 1000.0f);
    if (a->last_frame_us)
        a->fps += 0.1 * (1e6 / (double)(now - a->last_frame_us) - a->fps);
    a->last_frame_us = now;
    if (with_cloth) {
        a->frames_drawn++;
        bus_timing_publish(a->lcm, &t);
    }
    return 0;
}

void mirror_app_send_control(mirror_app *a)
{
    tryon_control_t c = {.utime = bus_now_wall_us(),
                         .seq = a->control_seq++,
                         .garment = (char *)a->garments[a->garment],
                         .size = (int8_t)a->size,
                         .fabric = (char *)(a->fabric ? a->fabric : "")};
    bus_reject why;
    if (bus_publish(a->lcm, a->ch_control, BUS_CONTROL, &c, &why) != BUS_OK)
        fprintf(stderr, "tryon-mirror: CONTROL not sent: %s (%s)\n", bus_error_text(why.code),
                why.detail);
    else
        fprintf(stderr, "tryon-mirror: asked for %s size %c\n", c.garment, "SML"[a->size]);
}

void mirror_app_close(mirror_app *a)
{
    if (a->video) {
        int st = mirror_video_close(a->video);
        if (st != 0)
            fprintf(stderr, "tryon-mirror: ffmpeg exited with %d; %s may be incomplete\n", st,
                    a->video_path);
        else
            fprintf(stderr, "tryon-mirror: video %s\n", a->video_path);
    }
    fprintf(stderr,
            "tryon-mirror: %d frames drawn (%d PNG), %d CLOTH without its DEPTH frame, %d CLOTH "
            "skipped (triangles not yet received), %d superseded by newer ones waiting\n",
            a->frames_drawn, a->pngs_written, a->unmatched, a->queue.skipped, a->queue.superseded);
    for (int i = 0; i < 4; i++)
        if (a->subs[i]) {
            const bus_stats *s = bus_sub_stats(a->subs[i]);
            if (s->rejected)
                fprintf(stderr, "tryon-mirror: %llu malformed messages dropped (%s)\n",
                        (unsigned long long)s->rejected, bus_error_text(s->last.code));
            bus_unsubscribe(a->lcm, a->subs[i]);
        }
    mirror_renderer_destroy(a->renderer);
    mirror_window_destroy(a->window);
    mirror_gl_destroy(a->gl);
    if (a->lcm)
        lcm_destroy(a->lcm);
    mirror_ring_destroy(a->ring);
    mirror_strain_destroy(a->strain);
    mirror_held_free(&a->cloth);
    mirror_held_free(&a->body);
    mirror_cloth_queue_free(&a->queue);
    free(a->rgb);
}
