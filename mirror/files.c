/* Pictures out: PNG through libpng, video through Debian's ffmpeg reading raw frames on a pipe. */
#include <errno.h>
#include <fcntl.h>
#include <png.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "mirror.h"

/* Written fast rather than small: zlib level 1 and no row filters take a 640x480 frame in a few
 * milliseconds, where libpng's defaults take tens, at a kiosk's frame rate. */
int mirror_png_write(const char *path, const uint8_t *rgb, int width, int height, char *err,
                     size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        snprintf(err, n, "%s: %s", path, strerror(errno));
        return -MIRROR_ERR_IO;
    }
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info || setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(f);
        snprintf(err, n, "%s: libpng could not write it", path);
        return -MIRROR_ERR_IO;
    }
    png_init_io(png, f);
    png_set_compression_level(png, 1);
    png_set_filter(png, 0, PNG_FILTER_NONE);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < height; y++)
        png_write_row(png, rgb + (size_t)y * width * 3);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    if (fclose(f) != 0) {
        snprintf(err, n, "%s: %s", path, strerror(errno));
        return -MIRROR_ERR_IO;
    }
    return 0;
}

uint8_t *mirror_png_read(const char *path, int *width, int *height)
{
    png_image img = {.version = PNG_IMAGE_VERSION};
    if (!png_image_begin_read_from_file(&img, path))
        return NULL;
    img.format = PNG_FORMAT_RGB;
    uint8_t *rgb = malloc(PNG_IMAGE_SIZE(img));
    if (!rgb || !png_image_finish_read(&img, NULL, rgb, 0, NULL)) {
        free(rgb);
        png_image_free(&img);
        return NULL;
    }
    *width = (int)img.width;
    *height = (int)img.height;
    return rgb;
}

struct mirror_video {
    pid_t pid;
    int fd;
    size_t frame_bytes;
};

mirror_video *mirror_video_open(const char *path, int width, int height, int fps, char *err,
                                size_t n)
{
    int p[2];
    if (pipe(p) < 0) {
        snprintf(err, n, "pipe: %s", strerror(errno));
        return NULL;
    }
    char size[32], rate[16];
    snprintf(size, sizeof size, "%dx%d", width, height);
    snprintf(rate, sizeof rate, "%d", fps);
    pid_t pid = fork();
    if (pid == 0) {
        dup2(p[0], 0);
        close(p[0]);
        close(p[1]);
        int devnull = open("/dev/null", O_WRONLY);
        if (devnull >= 0)
            dup2(devnull, 1);
        execlp("ffmpeg", "ffmpeg", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt",
               "rgb24", "-s", size, "-r", rate, "-i", "-", "-pix_fmt", "yuv420p", "-vcodec",
               "libx264", "-preset", "veryfast", path, (char *)NULL);
        fprintf(stderr, "tryon-mirror: cannot run ffmpeg: %s\n", strerror(errno));
        _exit(127);
    }
    close(p[0]);
    if (pid < 0) {
        close(p[1]);
        snprintf(err, n, "fork: %s", strerror(errno));
        return NULL;
    }
    mirror_video *v = malloc(sizeof *v);
    if (!v) {
        close(p[1]);
        kill(pid, SIGTERM);
        waitpid(pid, NULL, 0);
        snprintf(err, n, "out of memory");
        return NULL;
    }
    *v = (mirror_video){pid, p[1], (size_t)width * height * 3};
    return v;
}

int mirror_video_write(mirror_video *v, const uint8_t *rgb)
{
    size_t done = 0;
    while (done < v->frame_bytes) {
        ssize_t k = write(v->fd, rgb + done, v->frame_bytes - done);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return -MIRROR_ERR_VIDEO; /* ffmpeg has gone: the caller reports and stops the video */
        done += (size_t)k;
    }
    return 0;
}

int mirror_video_close(mirror_video *v)
{
    if (!v)
        return 0;
    close(v->fd);
    int status = 0;
    while (waitpid(v->pid, &status, 0) < 0 && errno == EINTR)
        ;
    free(v);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}
