/* Fakenect staging: validate a dump, then give fakenect an INDEX.txt it can replay without
 * sleeping (see capture.h). */
#define _XOPEN_SOURCE 700 /* realpath */
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "capture.h"
#include "recordings.h"

#ifndef TRYON_FAKENECT_LIBDIR
#define TRYON_FAKENECT_LIBDIR "/usr/lib/x86_64-linux-gnu/fakenect"
#endif

const char *cap_fakenect_libdir(void)
{
    const char *e = getenv(CAP_ENV_LIBDIR);
    return e && *e ? e : TRYON_FAKENECT_LIBDIR;
}

int cap_uri_is_dump(const char *uri)
{
    struct stat st;
    return uri && stat(uri, &st) == 0 && S_ISDIR(st.st_mode);
}

int cap_fakenect_stage(const char *dump_dir, char *staged, size_t staged_size, char *err,
                       size_t errlen)
{
    rec_report why;
    int frames = 0;
    if (rec_validate(dump_dir, &frames, &why) != REC_OK) {
        snprintf(err, errlen, "%s [%s]", why.message, rec_error_name(why.code));
        return -CAP_ERR_RECORDING;
    }
    rec_index idx;
    if (rec_index_read(dump_dir, &idx, &why) != REC_OK) {
        rec_index_free(&idx);
        snprintf(err, errlen, "%s", why.message);
        return -CAP_ERR_RECORDING;
    }
    char abs[PATH_MAX];
    if (!realpath(dump_dir, abs)) {
        rec_index_free(&idx);
        snprintf(err, errlen, "%s: %s", dump_dir, strerror(errno));
        return -CAP_ERR_RECORDING;
    }
    const char *tmp = getenv("TMPDIR");
    snprintf(staged, staged_size, "%s/tryon-fakenect-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(staged)) {
        rec_index_free(&idx);
        snprintf(err, errlen, "cannot make a staging directory %s: %s", staged, strerror(errno));
        return -CAP_ERR_RECORDING;
    }
    int code = CAP_OK;
    char path[PATH_MAX + 128], target[PATH_MAX + 128];
    snprintf(path, sizeof path, "%s/INDEX.txt", staged);
    FILE *fp = fopen(path, "wb");
    for (int i = 0; fp && i < idx.count && code == CAP_OK; i++) {
        /* Record time 0 for every line: fakenect's sleep needs a previous time != 0. */
        char name[96];
        snprintf(name, sizeof name, "d-0.000000-%u-%06d.pgm", idx.frames[i].device_timestamp, i);
        snprintf(path, sizeof path, "%s/%s", staged, name);
        snprintf(target, sizeof target, "%s/%s", abs, idx.frames[i].name);
        if (symlink(target, path) != 0 || fprintf(fp, "%s\n", name) < 0)
            code = -CAP_ERR_RECORDING;
    }
    if (!fp || fclose(fp) != 0)
        code = -CAP_ERR_RECORDING;
    rec_index_free(&idx);
    if (code != CAP_OK) {
        snprintf(err, errlen, "cannot write the staging directory %s: %s", staged, strerror(errno));
        cap_fakenect_unstage(staged);
    }
    return code;
}

void cap_fakenect_unstage(const char *staged)
{
    /* Only what cap_fakenect_stage made: a tryon-fakenect-* directory of links and one index. */
    if (!staged || !strstr(staged, "tryon-fakenect-"))
        return;
    DIR *d = opendir(staged);
    if (!d)
        return;
    struct dirent *e;
    char path[PATH_MAX + 300];
    while ((e = readdir(d))) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        snprintf(path, sizeof path, "%s/%s", staged, e->d_name);
        unlink(path);
    }
    closedir(d);
    rmdir(staged);
}
