/* tryon-bench-mirror: one frame's cost in the mirror's renderer, headless (EGL surfaceless,
 * llvmpipe with LP_NUM_THREADS=1 unless set): a person-sized depth image and a garment of about
 * 7,000 vertices, drawn at a picture size. Three costs, each as tryon-mirror pays it: the frame
 * drawn (the person's image made beforehand, as the depth ring makes it when DEPTH arrives), the
 * read-back a PNG or video frame needs (only those frames pay it), and the person's image on the
 * CPU (once a DEPTH). CPU time is the process's, every thread (the draw's wall time on a busy
 * machine is mostly waiting for a core); page faults are the process's minor faults a frame.
 * A human table, then one line of JSON. */
#include <GLES3/gl3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <time.h>

#include "mirror.h"
#include "tryon_heap.h"
#include "render_private.h"

#define DW 640
#define DH 480
#define F  525.0f

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double cpu_ms(void)
{
    return (double)clock() * 1e3 / CLOCKS_PER_SEC; /* every thread of the process */
}

static long minor_faults(void)
{
    struct rusage u;
    getrusage(RUSAGE_SELF, &u);
    return u.ru_minflt;
}

/* mirror_person_image alone, frames calls into *buf: the median ms of wall time, and the CPU ms
 * a call in t[frames]. -1: out of memory. */
static double person_ms(const mirror_depth *d, int frames, double *t, float **buf, int *cap)
{
    double cpu0 = cpu_ms();
    for (int i = 0; i < frames; i++) {
        double t0 = now_ms();
        if (mirror_person_image(d, buf, cap) < 0)
            return -1.0;
        t[i] = now_ms() - t0;
    }
    t[frames] = (cpu_ms() - cpu0) / frames;
    qsort(t, (size_t)frames, sizeof *t, cmp);
    return t[frames / 2];
}

/* A standing figure 2.2 m away: an elliptic torso column and a wall behind at 3.5 m. */
static void scene(uint16_t *px)
{
    for (int v = 0; v < DH; v++)
        for (int u = 0; u < DW; u++) {
            float x = (u - 319.5f) * 2.2f / F, y = (v - 239.5f) * 2.2f / F;
            float e = (x / 0.2f) * (x / 0.2f);
            float z = e < 1.0f && fabsf(y) < 0.8f ? 2.2f - 0.12f * sqrtf(1.0f - e) : 3.5f;
            px[v * DW + u] = (uint16_t)lrintf(z * 1000.0f);
        }
}

/* A tube of cols x rows vertices around the torso, in world coordinates (camera 1 m up,
 * looking along -z). */
static void garment(float *xyz, int32_t *tris, int cols, int rows)
{
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols; c++) {
            float th = 6.2831853f * (float)c / (float)cols;
            float *p = &xyz[(r * cols + c) * 3];
            p[0] = 0.22f * cosf(th);
            p[1] = 1.3f - 0.6f * (float)r / (float)(rows - 1);
            p[2] = -2.1f - 0.14f * sinf(th);
        }
    int k = 0;
    for (int r = 0; r + 1 < rows; r++)
        for (int c = 0; c < cols; c++) {
            int a = r * cols + c, b = r * cols + (c + 1) % cols;
            int32_t q[6] = {a, a + cols, b, b, a + cols, b + cols};
            memcpy(&tris[k], q, sizeof q);
            k += 6;
        }
}

int main(int argc, char **argv)
{
    int w = 640, h = 480, frames = 100;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--size") && i + 1 < argc && sscanf(argv[i + 1], "%dx%d", &w, &h) == 2)
            i++;
        else if (!strcmp(argv[i], "--frames") && i + 1 < argc && atoi(argv[i + 1]) > 0)
            frames = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: tryon-bench-mirror [--size WxH] [--frames N]\n");
            return !!strcmp(argv[i], "--help") * 2;
        }
    }
    setenv("LP_NUM_THREADS", "1", 0);
    tryon_keep_heap(); /* as tryon-mirror */
    char err[512];
    mirror_gl *gl = mirror_gl_headless(err, sizeof err);
    mirror_renderer *r = gl ? mirror_renderer_create(w, h, err, sizeof err) : NULL;
    enum { COLS = 145, ROWS = 49 }; /* 7,105 vertices, tryon-sim's default shirt */
    uint16_t *px = malloc(DW * DH * sizeof *px);
    float *xyz = malloc(COLS * ROWS * 3 * sizeof *xyz);
    int32_t *tris = malloc(COLS * (ROWS - 1) * 6 * sizeof *tris);
    uint8_t *rgb = malloc((size_t)w * h * 3);
    double *draw = malloc((size_t)frames * sizeof *draw),
           *read = malloc((size_t)frames * sizeof *read),
           *pers = malloc((size_t)(frames + 1) * sizeof *pers);
    int status = 1;
    if (!r || !px || !xyz || !tris || !rgb || !draw || !read || !pers) {
        fprintf(stderr, "tryon-bench-mirror: %s\n", r ? "out of memory" : err);
        goto done;
    }
    scene(px);
    garment(xyz, tris, COLS, ROWS);
    mirror_depth d = {DW,     DH,     F,      F,
                      319.5f, 239.5f, 0.001f, {1, 0, 0, 0, 0, -1, 0, 1, 0, 0, -1, 0, 0, 0, 0, 1},
                      px,     0,      NULL};
    float *image = NULL;
    int image_cap = 0;
    double person = person_ms(&d, frames, pers, &image, &image_cap);
    if (person < 0.0) {
        fprintf(stderr, "tryon-bench-mirror: out of memory for the person's image\n");
        goto done;
    }
    double person_cpu = pers[frames]; /* person_ms leaves its CPU a call there */
    d.person = image;                 /* made on arrival, as the depth ring does */
    mirror_mesh g = {xyz, COLS * ROWS, tris, COLS * (ROWS - 1) * 2, NULL};
    mirror_view v = {.depth = &d, .garment = &g, .overlay_text = "FPS 30.0\nSIM 20.0 MS\nGARMENT"};
    double cpu0 = 0.0;
    long faults0 = 0;
    for (int i = -5; i < frames; i++) { /* five to warm up */
        if (i == 0) {
            cpu0 = cpu_ms();
            faults0 = minor_faults();
        }
        double t0 = now_ms();
        if (mirror_render(r, &v, err, sizeof err) < 0) {
            fprintf(stderr, "tryon-bench-mirror: %s\n", err);
            goto done;
        }
        glFinish();
        if (i >= 0)
            draw[i] = now_ms() - t0;
    }
    double draw_cpu = (cpu_ms() - cpu0) / frames;
    double faults = (double)(minor_faults() - faults0) / frames;
    cpu0 = cpu_ms();
    for (int i = 0; i < frames; i++) {
        double t0 = now_ms();
        mirror_read_rgb(r, rgb);
        read[i] = now_ms() - t0;
    }
    double read_cpu = (cpu_ms() - cpu0) / frames;
    qsort(draw, (size_t)frames, sizeof *draw, cmp);
    qsort(read, (size_t)frames, sizeof *read, cmp);
    int p95 = (int)(0.95 * (frames - 1));
    const char *device = (const char *)glGetString(GL_RENDERER);
    printf("%-10s %10s %10s %10s %10s\n", "picture", "draw p50", "draw p95", "read p50",
           "read p95");
    printf("%4dx%-5d %8.2f ms %7.2f ms %7.2f ms %7.2f ms\n", w, h, draw[frames / 2], draw[p95],
           read[frames / 2], read[p95]);
    printf("CPU (every thread): a frame drawn %.2f ms (%.0f page faults), its read-back %.2f ms, "
           "the person's image %.2f ms a DEPTH (median %.2f ms wall)\n",
           draw_cpu, faults, read_cpu, person_cpu, person);
    printf("{\"width\": %d, \"height\": %d, \"frames\": %d, \"ms_median\": %.3f, \"ms_p95\": %.3f, "
           "\"read_ms_median\": %.3f, \"read_ms_p95\": %.3f, \"verts\": %d, \"device\": \"%s\", "
           "\"lp_num_threads\": \"%s\", \"draw_cpu_ms\": %.3f, \"draw_page_faults\": %.1f, "
           "\"read_cpu_ms\": %.3f, \"person_cpu_ms\": %.3f, \"person_ms_median\": %.3f}\n",
           w, h, frames, draw[frames / 2], draw[p95], read[frames / 2], read[p95], COLS * ROWS,
           device, getenv("LP_NUM_THREADS"), draw_cpu, faults, read_cpu, person_cpu, person);
    status = 0;
done:
    free(px);
    free(xyz);
    free(tris);
    free(rgb);
    free(draw);
    free(read);
    free(pers);
    free(image);
    mirror_renderer_destroy(r);
    mirror_gl_destroy(gl);
    return status;
}
