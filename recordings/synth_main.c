/* tryon-synth: write a synthetic Kinect v1 recording (fakenect dump) with ground truth. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "recordings.h"

static void usage(FILE *fp)
{
    fprintf(fp,
            "usage: tryon-synth --out DIR [--motion NAME|FILE.bvh] [--shape 0|1|2] [--frames N]\n"
            "                   [--noise on|off] [--seed N] [--vertices N] [--occluder]\n"
            "                   [--heading camera|clip]\n"
            "motions:");
    for (int i = 0; rec_synth_motion_name(i); i++)
        fprintf(fp, " %s", rec_synth_motion_name(i));
    fprintf(fp,
            "\n        FILE.bvh: a motion-capture clip (CMU-style BVH) retargeted onto the body,\n"
            "        turned to face the camera at its start (--heading camera, the default: a\n"
            "        person before a mirror) or as captured (--heading clip)\n"
            "Replay: tryon-capture --source freenect --uri DIR\n");
}

static int parse_int(const char *s, long lo, long hi, long *out)
{
    char *end;
    long v = strtol(s, &end, 10);
    if (end == s || *end || v < lo || v > hi)
        return -1;
    *out = v;
    return 0;
}

int main(int argc, char **argv)
{
    rec_synth_desc d = {.motion = "still", .noise = 1, .seed = 1};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        long n;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(a, "--occluder")) {
            d.occluder = 1;
            continue;
        }
        if (!v) {
            fprintf(stderr, "tryon-synth: %s needs a value\n", a);
            usage(stderr);
            return 2;
        }
        i++;
        if (!strcmp(a, "--out"))
            d.out_dir = v;
        else if (!strcmp(a, "--motion"))
            d.motion = v;
        else if (!strcmp(a, "--heading") && (!strcmp(v, "camera") || !strcmp(v, "clip")))
            d.keep_heading = !strcmp(v, "clip");
        else if (!strcmp(a, "--noise") && (!strcmp(v, "on") || !strcmp(v, "off")))
            d.noise = !strcmp(v, "on");
        else if (!strcmp(a, "--shape") && !parse_int(v, 0, 2, &n))
            d.shape = (int)n;
        else if (!strcmp(a, "--frames") && !parse_int(v, 1, 1000000, &n))
            d.frames = (int)n;
        else if (!strcmp(a, "--seed") && !parse_int(v, 0, 0x7fffffffL, &n))
            d.seed = (uint64_t)n;
        else if (!strcmp(a, "--vertices") && !parse_int(v, 100, 1000000, &n))
            d.target_vertices = (int)n;
        else {
            fprintf(stderr, "tryon-synth: bad option or value: %s %s\n", a, v);
            usage(stderr);
            return 2;
        }
    }
    if (!d.out_dir) {
        fprintf(stderr, "tryon-synth: --out DIR is required\n");
        usage(stderr);
        return 2;
    }
    rec_report why;
    int e = rec_synth(&d, &why);
    if (e != REC_OK) {
        fprintf(stderr, "tryon-synth: %s [%s]\n", why.message, rec_error_name(e));
        return 1;
    }
    int frames = 0;
    e = rec_validate(d.out_dir, &frames, &why);
    if (e != REC_OK) {
        fprintf(stderr, "tryon-synth: wrote an invalid dump: %s\n", why.message);
        return 1;
    }
    printf("tryon-synth: %d frames of '%s' (shape %d, noise %s, seed %" PRIu64 ") in %s\n", frames,
           d.motion, d.shape, d.noise ? "on" : "off", d.seed, d.out_dir);
    return 0;
}
