/* libFuzzer harness: the fakenect dump reader (tryon-capture --source freenect, rec_validate).
 * The input is the dump's INDEX.txt; the directory also holds one valid 640x480 frame written
 * at start-up, so index lines naming it reach the frame checks. An input starting with 'P' is
 * instead the head of that frame file (its header), the rest of the frame kept. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_file.h"
#include "recordings.h"

#define FRAME_NAME "d-1.000000-0.pgm"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static uint8_t *frame; /* the valid frame file's bytes */
static size_t frame_size;
static int frame_changed; /* the file on disk is not the valid frame (rewritten only then) */

static void init(void)
{
    static uint16_t raw[640 * 480];
    rec_report why;
    rec_writer *w = rec_writer_create(fuzz_dir(), &why);
    if (!w || rec_writer_frame(w, raw, 1.0, 0, &why) != REC_OK)
        abort();
    rec_writer_destroy(w);
    size_t len = strlen(fuzz_dir()) + sizeof "/" FRAME_NAME;
    char *path = malloc(len);
    snprintf(path, len, "%s/%s", fuzz_dir(), FRAME_NAME);
    FILE *f = fopen(path, "rb");
    if (!f)
        abort();
    fseek(f, 0, SEEK_END);
    frame_size = (size_t)ftell(f);
    rewind(f);
    frame = malloc(frame_size);
    if (!frame || fread(frame, 1, frame_size, f) != frame_size)
        abort();
    fclose(f);
    free(path);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!frame)
        init();
    if (size > 0 && data[0] == 'P') {
        uint8_t *head = malloc(frame_size > size ? frame_size : size);
        if (!head)
            return 0;
        memcpy(head, frame, frame_size);
        memcpy(head, data, size);
        fuzz_write(FRAME_NAME, head, size > frame_size ? size : frame_size);
        free(head);
        frame_changed = 1;
        fuzz_write("INDEX.txt", (const uint8_t *)FRAME_NAME "\n", sizeof FRAME_NAME);
    } else {
        if (frame_changed)
            fuzz_write(FRAME_NAME, frame, frame_size);
        frame_changed = 0;
        fuzz_write("INDEX.txt", data, size);
    }
    int frames;
    rec_report why;
    rec_validate(fuzz_dir(), &frames, &why);
    return 0;
}
