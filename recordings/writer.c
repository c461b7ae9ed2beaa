/* Writing fakenect dumps: the same layout fakenect's own record tool produces. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "rec_private.h"

struct rec_writer {
    char dir[400];
    FILE *index;
    FILE *gt_index;
    int frames;
    double last_time;
    char last_name[96];
    uint8_t buf[REC_WIDTH * REC_HEIGHT * 2];
};

static int mkdir_p(const char *dir)
{
    char tmp[400];
    snprintf(tmp, sizeof tmp, "%s", dir);
    for (char *p = tmp + 1; *p; p++) {
        if (*p != '/')
            continue;
        *p = 0;
        if (mkdir(tmp, 0755) != 0 && errno != EEXIST)
            return -1;
        *p = '/';
    }
    if (mkdir(tmp, 0755) != 0 && errno != EEXIST)
        return -1;
    return 0;
}

rec_writer *rec_writer_create(const char *dir, rec_report *why)
{
    if (!dir || strlen(dir) >= 300) {
        rec_fail(why, REC_ERR_ARG, dir, -1, 0, "directory name missing or too long");
        return NULL;
    }
    if (mkdir_p(dir) != 0) {
        rec_fail(why, REC_ERR_IO, dir, -1, 0, "%s", strerror(errno));
        return NULL;
    }
    rec_writer *w = calloc(1, sizeof *w);
    if (!w) {
        rec_fail(why, REC_ERR_NO_MEMORY, dir, -1, 0, NULL);
        return NULL;
    }
    snprintf(w->dir, sizeof w->dir, "%s", dir);
    char path[512];
    snprintf(path, sizeof path, "%s/INDEX.txt", dir);
    w->index = fopen(path, "wb");
    if (!w->index) {
        rec_fail(why, REC_ERR_IO, path, -1, 0, "%s", strerror(errno));
        free(w);
        return NULL;
    }
    return w;
}

int rec_writer_frame(rec_writer *w, const uint16_t *raw, double record_time_s,
                     uint32_t device_timestamp, rec_report *why)
{
    if (!w || !raw)
        return rec_fail(why, REC_ERR_ARG, NULL, -1, 0, "no writer or no frame");
    if (w->frames > 0 && !(record_time_s > w->last_time))
        return rec_fail(why, REC_ERR_TIME_ORDER, w->dir, w->frames, 0, "%.6f after %.6f",
                        record_time_s, w->last_time);
    char name[96], path[512];
    snprintf(name, sizeof name, "d-%f-%u.pgm", record_time_s, device_timestamp);
    snprintf(path, sizeof path, "%s/%s", w->dir, name);
    for (int i = 0; i < REC_WIDTH * REC_HEIGHT; i++) {
        w->buf[2 * i] = (uint8_t)(raw[i] & 0xff);
        w->buf[2 * i + 1] = (uint8_t)(raw[i] >> 8);
    }
    FILE *fp = fopen(path, "wb");
    if (!fp)
        return rec_fail(why, REC_ERR_IO, path, w->frames, 0, "%s", strerror(errno));
    size_t hl = strlen(REC_PGM_HEADER);
    int ok = fwrite(REC_PGM_HEADER, 1, hl, fp) == hl &&
             fwrite(w->buf, 1, sizeof w->buf, fp) == sizeof w->buf;
    ok = (fclose(fp) == 0) && ok;
    if (!ok)
        return rec_fail(why, REC_ERR_IO, path, w->frames, 0, "short write");
    /* The frame file is complete before INDEX.txt names it, so a reader never sees a partial
     * frame listed. */
    if (fprintf(w->index, "%s\n", name) < 0 || fflush(w->index) != 0)
        return rec_fail(why, REC_ERR_IO, w->dir, w->frames, 0, "INDEX.txt: %s", strerror(errno));
    w->last_time = record_time_s;
    snprintf(w->last_name, sizeof w->last_name, "%s", name);
    w->frames++;
    return REC_OK;
}

int rec_writer_gt_path(rec_writer *w, char *path, size_t path_size, char *name, size_t name_size)
{
    if (!w || w->frames == 0)
        return -REC_ERR_ARG;
    if (!w->gt_index) {
        char p[512];
        snprintf(p, sizeof p, "%s/groundtruth.txt", w->dir);
        w->gt_index = fopen(p, "wb");
        if (!w->gt_index)
            return -REC_ERR_IO;
        fprintf(w->gt_index, "# frame record_time_s depth_file ground_truth_file\n");
    }
    int frame = w->frames - 1;
    char gt[32];
    snprintf(gt, sizeof gt, "gt-%06d.txt", frame);
    snprintf(path, path_size, "%s/%s", w->dir, gt);
    if (name)
        snprintf(name, name_size, "%s", gt);
    if (fprintf(w->gt_index, "%d %f %s %s\n", frame, w->last_time, w->last_name, gt) < 0 ||
        fflush(w->gt_index) != 0)
        return -REC_ERR_IO;
    return REC_OK;
}

int rec_writer_frames(const rec_writer *w)
{
    return w ? w->frames : 0;
}

void rec_writer_destroy(rec_writer *w)
{
    if (!w)
        return;
    if (w->index)
        fclose(w->index);
    if (w->gt_index)
        fclose(w->gt_index);
    free(w);
}
