/* BVH reader: the HIERARCHY (a tree of joints with offsets and channels) and the MOTION (one
 * row of channel values per frame). Every file is untrusted: each refusal names the line. */
#include "mocap.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Frames a file may hold: an hour at 120 fps. */
#define BVH_MAX_FRAMES (120 * 3600)
/* Longest token: joint names are short; numbers need 30 characters at most. */
#define BVH_TOKEN_MAX 64

typedef struct lexer {
    const char *p, *end, *name;
    int line;
    char tok[BVH_TOKEN_MAX];
    int tok_line; /* line of the token in tok; at the end, of the last token */
    char *err;
    size_t errlen;
} lexer;

static int fail(lexer *lx, const char *fmt, ...)
{
    if (lx->err && lx->errlen) {
        int n = snprintf(lx->err, lx->errlen, "%s:%d: ", lx->name, lx->tok_line);
        if (n >= 0 && (size_t)n < lx->errlen) {
            va_list ap;
            va_start(ap, fmt);
            vsnprintf(lx->err + n, lx->errlen - (size_t)n, fmt, ap);
            va_end(ap);
        }
    }
    return -FIT_ERR_PARSE;
}

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

/* The next whitespace-separated token into lx->tok; "" at the end of the text. */
static int next(lexer *lx)
{
    while (lx->p < lx->end && is_space(*lx->p)) {
        if (*lx->p == '\n')
            ++lx->line;
        ++lx->p;
    }
    int prev = lx->tok_line;
    lx->tok_line = lx->line;
    size_t n = 0;
    while (lx->p < lx->end && !is_space(*lx->p)) {
        if (*lx->p == '\0')
            return fail(lx, "NUL byte in the text");
        if (n + 1 >= sizeof lx->tok)
            return fail(lx, "token longer than %d characters", BVH_TOKEN_MAX - 1);
        lx->tok[n++] = *lx->p++;
    }
    lx->tok[n] = '\0';
    if (n == 0) /* the end: errors name the last line with text */
        lx->tok_line = prev;
    return 0;
}

static int expect(lexer *lx, const char *word, const char *where)
{
    int rc = next(lx);
    if (rc)
        return rc;
    if (strcmp(lx->tok, word) != 0)
        return fail(lx, "expected '%s' %s, found '%s'", word, where, lx->tok);
    return 0;
}

static int number(lexer *lx, double *out, const char *what)
{
    int rc = next(lx);
    if (rc)
        return rc;
    if (!lx->tok[0])
        return fail(lx, "file ends where %s was expected", what);
    char *e;
    double v = strtod(lx->tok, &e);
    if (e == lx->tok || *e)
        return fail(lx, "%s: '%s' is not a number", what, lx->tok);
    if (!isfinite(v) || fabs(v) > 1e9)
        return fail(lx, "%s: '%s' is not finite or beyond 1e9", what, lx->tok);
    *out = v;
    return 0;
}

static int offset3(lexer *lx, float out[3])
{
    int rc = expect(lx, "OFFSET", "after '{'");
    for (int k = 0; k < 3 && !rc; ++k) {
        double v = 0.0;
        rc = number(lx, &v, "OFFSET value");
        out[k] = (float)v;
    }
    return rc;
}

static int channel_of(const char *s)
{
    static const char *const names[] = {"Xposition", "Yposition", "Zposition",
                                        "Xrotation", "Yrotation", "Zrotation"};
    for (int i = 0; i < 6; ++i)
        if (strcmp(s, names[i]) == 0)
            return i;
    return -1;
}

static int channels(lexer *lx, fit_bvh *b, mocap_joint *j)
{
    double n;
    int rc = expect(lx, "CHANNELS", "after OFFSET");
    if (!rc)
        rc = number(lx, &n, "CHANNELS count");
    if (rc)
        return rc;
    if (n != floor(n) || n < 0 || n > 6)
        return fail(lx, "CHANNELS count %s is not 0..6", lx->tok);
    j->channel_count = (int)n;
    j->channel_first = b->channels;
    unsigned seen = 0;
    for (int i = 0; i < j->channel_count; ++i) {
        if ((rc = next(lx)))
            return rc;
        int c = channel_of(lx->tok);
        if (c < 0)
            return fail(lx, "unknown channel '%s'", lx->tok);
        if (seen & (1u << c))
            return fail(lx, "channel '%s' given twice", lx->tok);
        seen |= 1u << c;
        j->chan[i] = (unsigned char)c;
    }
    b->channels += j->channel_count;
    return 0;
}

static int end_site(lexer *lx, mocap_joint *j)
{
    if (j->has_end)
        return fail(lx, "joint '%s' has two End Sites", j->name);
    int rc = expect(lx, "Site", "after 'End'");
    if (!rc)
        rc = expect(lx, "{", "after 'End Site'");
    if (!rc)
        rc = offset3(lx, j->end_offset);
    if (!rc)
        rc = expect(lx, "}", "after the End Site's OFFSET");
    j->has_end = 1;
    return rc;
}

/* A joint after its keyword: name { OFFSET CHANNELS children }. Depth is bounded by the
 * joint count (each level adds a joint). */
static int joint(lexer *lx, fit_bvh *b, int parent)
{
    int rc = next(lx);
    if (rc)
        return rc;
    if (!lx->tok[0] || strcmp(lx->tok, "{") == 0)
        return fail(lx, "joint without a name");
    if (b->joint_count >= FIT_BVH_MAX_JOINTS)
        return fail(lx, "more than %d joints", FIT_BVH_MAX_JOINTS);
    int id = b->joint_count++;
    mocap_joint *j = &b->joint[id];
    snprintf(j->name, sizeof j->name, "%s", lx->tok);
    j->parent = parent;
    if ((rc = expect(lx, "{", "after the joint name")) || (rc = offset3(lx, j->offset)) ||
        (rc = channels(lx, b, j)))
        return rc;
    for (;;) {
        if ((rc = next(lx)))
            return rc;
        if (strcmp(lx->tok, "}") == 0)
            return 0;
        if (strcmp(lx->tok, "JOINT") == 0)
            rc = joint(lx, b, id);
        else if (strcmp(lx->tok, "End") == 0)
            rc = end_site(lx, &b->joint[id]);
        else if (!lx->tok[0])
            return fail(lx, "file ends inside joint '%s'", b->joint[id].name);
        else
            return fail(lx, "expected JOINT, End Site or '}' in joint '%s', found '%s'",
                        b->joint[id].name, lx->tok);
        if (rc)
            return rc;
    }
}

static int motion(lexer *lx, fit_bvh *b, size_t text_len)
{
    double n, t;
    int rc = expect(lx, "MOTION", "after the hierarchy");
    if (!rc)
        rc = expect(lx, "Frames:", "after MOTION");
    if (!rc)
        rc = number(lx, &n, "frame count");
    if (rc)
        return rc;
    if (n != floor(n) || n < 1 || n > BVH_MAX_FRAMES)
        return fail(lx, "frame count %s is not 1..%d", lx->tok, BVH_MAX_FRAMES);
    b->frames = (int)n;
    size_t count = (size_t)b->frames * (size_t)b->channels;
    /* Each value takes two bytes at least: a file cannot hold more (and no huge allocation
     * follows from a small file that claims many frames). */
    if (count > text_len / 2 + 1)
        return fail(lx, "%d frames of %d values do not fit in a file of %zu bytes", b->frames,
                    b->channels, text_len);
    if ((rc = expect(lx, "Frame", "after the frame count")) ||
        (rc = expect(lx, "Time:", "after 'Frame'")) || (rc = number(lx, &t, "frame time")))
        return rc;
    if (!(t > 1e-4 && t <= 1.0))
        return fail(lx, "frame time %s s is not in (0.0001, 1]", lx->tok);
    b->frame_time_s = t;
    b->values = malloc((count ? count : 1) * sizeof(float));
    if (!b->values)
        return -FIT_ERR_NOMEM;
    for (size_t i = 0; i < count; ++i) {
        double v;
        if ((rc = number(lx, &v, "channel value"))) {
            if (!lx->tok[0])
                return fail(lx, "file ends in frame %zu of %d (value %zu of %d)",
                            i / (size_t)b->channels + 1, b->frames, i % (size_t)b->channels + 1,
                            b->channels);
            return rc;
        }
        b->values[i] = (float)v;
    }
    /* What follows the declared frames is not read: the Frames: line rules, as in other
     * readers (Boxing_Toes.bvh holds one row more than it declares). */
    return 0;
}

int fit_bvh_parse(const char *text, size_t len, const char *name, fit_bvh **out, char *err,
                  size_t errlen)
{
    if (err && errlen)
        err[0] = '\0';
    if (!out || (!text && len))
        return -FIT_ERR_ARG;
    *out = NULL;
    fit_bvh *b = calloc(1, sizeof *b);
    if (!b)
        return -FIT_ERR_NOMEM;
    lexer lx = {.p = text,
                .end = text + len,
                .name = name ? name : "bvh",
                .line = 1,
                .tok_line = 1,
                .err = err,
                .errlen = errlen};
    int rc = expect(&lx, "HIERARCHY", "at the start");
    if (!rc)
        rc = expect(&lx, "ROOT", "after HIERARCHY");
    if (!rc)
        rc = joint(&lx, b, -1);
    if (!rc)
        rc = motion(&lx, b, len);
    if (rc) {
        fit_bvh_destroy(b);
        return rc;
    }
    *out = b;
    return 0;
}

int fit_bvh_load(const char *path, fit_bvh **out, char *err, size_t errlen)
{
    if (!path || !out)
        return -FIT_ERR_ARG;
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f) {
        if (err)
            snprintf(err, errlen, "%s: cannot open", path);
        return -FIT_ERR_IO;
    }
    char *text = NULL;
    long n = -1;
    if (fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) >= 0 && fseek(f, 0, SEEK_SET) == 0)
        text = malloc((size_t)n + 1);
    size_t got = text ? fread(text, 1, (size_t)n, f) : 0;
    fclose(f);
    if (!text || got != (size_t)n) {
        free(text);
        if (err)
            snprintf(err, errlen, "%s: cannot read", path);
        return text ? -FIT_ERR_IO : -FIT_ERR_NOMEM;
    }
    int rc = fit_bvh_parse(text, got, path, out, err, errlen);
    free(text);
    return rc;
}

void fit_bvh_destroy(fit_bvh *b)
{
    if (!b)
        return;
    free(b->values);
    free(b);
}

int fit_bvh_joint_count(const fit_bvh *b)
{
    return b ? b->joint_count : 0;
}

int fit_bvh_frame_count(const fit_bvh *b)
{
    return b ? b->frames : 0;
}

double fit_bvh_frame_time(const fit_bvh *b)
{
    return b ? b->frame_time_s : 0.0;
}

const char *fit_bvh_joint_name(const fit_bvh *b, int j)
{
    return (b && j >= 0 && j < b->joint_count) ? b->joint[j].name : NULL;
}

int fit_bvh_joint_parent(const fit_bvh *b, int j)
{
    return (b && j >= 0 && j < b->joint_count) ? b->joint[j].parent : -1;
}

int fit_bvh_find_joint(const fit_bvh *b, const char *name)
{
    if (!b || !name)
        return -1;
    for (int j = 0; j < b->joint_count; ++j)
        if (strcmp(b->joint[j].name, name) == 0)
            return j;
    return -1;
}
