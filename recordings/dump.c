/* Fakenect dumps: INDEX.txt plus one PGM-like file per depth frame, parsed the way Debian's
 * fakenect 0.5.3 parses them (fakenect.c: sscanf "%c-%lf-%u-%*s" on each INDEX.txt line, the
 * file is the line itself inside FAKENECT_PATH, one header line, then raw little-endian data). */
#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "recordings.h"
#include "rec_private.h"
#include "tryon_errors.h"

TRYON_ERROR_WORDS(REC_ERROR_LIST, REC_ERROR_COUNT, rec_error_name, rec_error_text,
                  "REC_ERR_UNKNOWN")

int rec_fail(rec_report *why, rec_error code, const char *file, int frame, int line,
             const char *fmt, ...)
{
    if (!why)
        return -(int)code;
    why->code = code;
    why->frame = frame;
    why->line = line;
    snprintf(why->file, sizeof why->file, "%s", file ? file : "");
    char detail[320] = "";
    if (fmt) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(detail, sizeof detail, fmt, ap);
        va_end(ap);
    }
    char where[64] = "";
    if (frame >= 0 && line > 0)
        snprintf(where, sizeof where, " (frame %d, INDEX.txt line %d)", frame, line);
    else if (frame >= 0)
        snprintf(where, sizeof where, " (frame %d)", frame);
    else if (line > 0)
        snprintf(where, sizeof where, " (INDEX.txt line %d)", line);
    snprintf(why->message, sizeof why->message, "%s%s: %s%s%s", why->file, where, error_texts[code],
             detail[0] ? ": " : "", detail);
    return -(int)code;
}

static void report_ok(rec_report *why)
{
    if (why)
        memset(why, 0, sizeof *why);
}

void rec_index_free(rec_index *idx)
{
    if (!idx)
        return;
    free(idx->frames);
    idx->frames = NULL;
    idx->count = 0;
}

/* One INDEX.txt line: type, record time, device timestamp, as fakenect's sscanf reads them. */
static int parse_line(const char *line, char *type, double *t, unsigned *ts)
{
    char c = 0;
    double time = 0.0;
    unsigned stamp = 0;
    int n = 0;
    if (sscanf(line, "%c-%lf-%u%n", &c, &time, &stamp, &n) != 3)
        return -1;
    if (line[n] != '-' && line[n] != '.')
        return -1;
    *type = c;
    *t = time;
    *ts = stamp;
    return 0;
}

static int index_add(rec_index *out, int *cap, double t, unsigned ts, const char *name)
{
    if (out->count == *cap) {
        int ncap = *cap ? *cap * 2 : 64;
        rec_entry *f = realloc(out->frames, (size_t)ncap * sizeof *f);
        if (!f)
            return -REC_ERR_NO_MEMORY;
        out->frames = f;
        *cap = ncap;
    }
    rec_entry *e = &out->frames[out->count++];
    e->record_time_s = t;
    e->device_timestamp = ts;
    snprintf(e->name, sizeof e->name, "%s", name);
    return REC_OK;
}

/* One INDEX.txt line (newline removed). ended_at: the first empty line seen, 0 = none. */
static int index_line(rec_index *out, int *cap, char *line, int lineno, int *ended_at,
                      const char *path, rec_report *why)
{
    if (line[0] == 0) {
        /* fakenect stops at the first empty line (a line of spaces is a file name to it):
         * anything after it would never play. */
        if (!*ended_at)
            *ended_at = lineno;
        return REC_OK;
    }
    if (*ended_at)
        return rec_fail(why, REC_ERR_BAD_LINE, path, -1, lineno,
                        "frames after the empty line %d would never replay", *ended_at);
    if (strchr(line, '\r'))
        return rec_fail(why, REC_ERR_BAD_LINE, path, -1, lineno,
                        "carriage return: fakenect would open a file name ending in it");
    char type;
    double t;
    unsigned ts;
    if (parse_line(line, &type, &t, &ts) != 0)
        return rec_fail(why, REC_ERR_BAD_LINE, path, -1, lineno, "'%.80s'", line);
    if (type != 'd')
        return REC_OK; /* rgb ('r') and accelerometer ('a') lines: tryon uses depth only */
    if (strlen(line) >= sizeof out->frames[0].name || strchr(line, '/'))
        return rec_fail(why, REC_ERR_BAD_LINE, path, out->count, lineno,
                        "file name too long or outside the directory: '%.80s'", line);
    if (index_add(out, cap, t, ts, line) != REC_OK)
        return rec_fail(why, REC_ERR_NO_MEMORY, path, out->count, lineno, NULL);
    return REC_OK;
}

int rec_index_read(const char *dir, rec_index *out, rec_report *why)
{
    memset(out, 0, sizeof *out);
    report_ok(why);
    char path[512];
    snprintf(path, sizeof path, "%s/INDEX.txt", dir);
    struct stat st;
    if (stat(dir, &st) != 0)
        return rec_fail(why, REC_ERR_NO_DIR, dir, -1, 0, "%s", strerror(errno));
    if (!S_ISDIR(st.st_mode))
        return rec_fail(why, REC_ERR_NO_DIR, dir, -1, 0, "not a directory");
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return rec_fail(why, REC_ERR_NO_INDEX, path, -1, 0, "%s", strerror(errno));
    char line[1024];
    int cap = 0, lineno = 0, ended_at = 0;
    int err = REC_OK;
    while (err == REC_OK && fgets(line, sizeof line, fp)) {
        lineno++;
        size_t len = strlen(line);
        if (len == sizeof line - 1 && line[len - 1] != '\n') {
            err = rec_fail(why, REC_ERR_BAD_LINE, path, -1, lineno, "line too long");
            break;
        }
        if (len && line[len - 1] == '\n')
            line[--len] = 0;
        err = index_line(out, &cap, line, lineno, &ended_at, path, why);
    }
    fclose(fp);
    if (err == REC_OK && out->count == 0)
        err = rec_fail(why, REC_ERR_EMPTY, path, -1, 0, NULL);
    return err;
}

int rec_frame_read(const char *dir, const rec_entry *e, int frame, uint16_t *raw, rec_report *why)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", dir, e->name);
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return rec_fail(why, REC_ERR_NO_FRAME, path, frame, 0, "%s", strerror(errno));
    int err = REC_OK;
    char header[sizeof REC_PGM_HEADER];
    size_t hl = strlen(REC_PGM_HEADER);
    size_t got = fread(header, 1, hl, fp);
    if (got != hl || memcmp(header, REC_PGM_HEADER, hl) != 0) {
        header[got < hl ? got : hl] = 0;
        for (size_t i = 0; header[i]; i++)
            if (header[i] == '\n')
                header[i] = ' ';
        err = rec_fail(why, got < hl ? REC_ERR_TRUNCATED : REC_ERR_HEADER, path, frame, 0,
                       "starts with '%.17s'", header);
        goto done;
    }
    static const size_t n = (size_t)REC_WIDTH * REC_HEIGHT;
    uint8_t buf[4096];
    size_t pix = 0;
    while (pix < n) {
        size_t want = (n - pix) * 2 < sizeof buf ? (n - pix) * 2 : sizeof buf;
        size_t r = fread(buf, 1, want, fp);
        for (size_t i = 0; i + 1 < r; i += 2, pix++) {
            uint16_t v = (uint16_t)(buf[i] | (buf[i + 1] << 8));
            if (v > REC_RAW_NONE) {
                err = rec_fail(why, REC_ERR_VALUE, path, frame, 0, "pixel (%zu, %zu) = %u",
                               pix % REC_WIDTH, pix / REC_WIDTH, v);
                goto done;
            }
            if (raw)
                raw[pix] = v;
        }
        if (r < want) {
            err = rec_fail(why, REC_ERR_TRUNCATED, path, frame, 0, "%zu of %zu data bytes present",
                           pix * 2 + (r & 1), n * 2);
            goto done;
        }
    }
    if (fgetc(fp) != EOF)
        err = rec_fail(why, REC_ERR_TOO_LONG, path, frame, 0, NULL);
done:
    fclose(fp);
    return err;
}

int rec_validate(const char *dir, int *frames_out, rec_report *why)
{
    rec_index idx;
    if (frames_out)
        *frames_out = 0;
    int err = rec_index_read(dir, &idx, why);
    if (err != REC_OK) {
        rec_index_free(&idx);
        return err;
    }
    char path[512];
    snprintf(path, sizeof path, "%s/INDEX.txt", dir);
    for (int i = 1; i < idx.count && err == REC_OK; i++) {
        const rec_entry *a = &idx.frames[i - 1], *b = &idx.frames[i];
        uint32_t step = b->device_timestamp - a->device_timestamp;
        if (!(b->record_time_s > a->record_time_s))
            err = rec_fail(why, REC_ERR_TIME_ORDER, path, i, 0, "%s at %.6f s after %s at %.6f s",
                           b->name, b->record_time_s, a->name, a->record_time_s);
        else if (step == 0 || step >= 0x80000000u)
            err = rec_fail(why, REC_ERR_TIMESTAMP_ORDER, path, i, 0, "%s: %u after %u", b->name,
                           b->device_timestamp, a->device_timestamp);
    }
    for (int i = 0; i < idx.count && err == REC_OK; i++)
        err = rec_frame_read(dir, &idx.frames[i], i, NULL, why);
    if (err == REC_OK && frames_out)
        *frames_out = idx.count;
    rec_index_free(&idx);
    return err;
}
