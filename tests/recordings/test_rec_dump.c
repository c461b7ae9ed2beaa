/* Dumps: written frames read back exactly; every kind of damage is named with file and frame. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "recordings.h"

#define FRAMES 4

typedef struct fixture {
    char dir[256];
    uint16_t raw[REC_WIDTH * REC_HEIGHT];
    uint16_t back[REC_WIDTH * REC_HEIGHT];
} fixture;

static void pattern(uint16_t *raw, int k)
{
    for (int i = 0; i < REC_WIDTH * REC_HEIGHT; i++)
        raw[i] = (uint16_t)((i * 7 + k * 131) % REC_RAW_LEVELS);
}

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    snprintf(f->dir, sizeof f->dir, "/tmp/tryon-test-rec-dump-%d", (int)getpid());
    rec_report why;
    rec_writer *w = rec_writer_create(f->dir, &why);
    assert_non_null(w);
    for (int k = 0; k < FRAMES; k++) {
        pattern(f->raw, k);
        assert_int_equal(rec_writer_frame(w, f->raw, 1.0 + k / 30.0, 1000u * k + 5, &why), REC_OK);
    }
    rec_writer_destroy(w);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", f->dir);
    assert_int_equal(system(cmd), 0);
    free(f);
    return 0;
}

static void frame_path(const fixture *f, int k, char *out, size_t n)
{
    rec_index idx;
    rec_report why;
    assert_int_equal(rec_index_read(f->dir, &idx, &why), REC_OK);
    snprintf(out, n, "%s/%s", f->dir, idx.frames[k].name);
    rec_index_free(&idx);
}

static void test_written_dump_reads_back_exactly(void **state)
{
    fixture *f = *state;
    rec_index idx;
    rec_report why;
    int frames = 0;
    assert_int_equal(rec_validate(f->dir, &frames, &why), REC_OK);
    assert_int_equal(frames, FRAMES);
    assert_int_equal(rec_index_read(f->dir, &idx, &why), REC_OK);
    for (int k = 0; k < FRAMES; k++) {
        assert_int_equal(idx.frames[k].device_timestamp, 1000u * k + 5);
        assert_true(idx.frames[k].record_time_s == strtod(idx.frames[k].name + 2, NULL));
        assert_int_equal(rec_frame_read(f->dir, &idx.frames[k], k, f->back, &why), REC_OK);
        pattern(f->raw, k);
        assert_memory_equal(f->raw, f->back, sizeof f->raw);
    }
    rec_index_free(&idx);
}

static void test_file_is_little_endian_with_fakenect_header(void **state)
{
    fixture *f = *state;
    char path[512];
    frame_path(f, 1, path, sizeof path);
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    char head[18] = {0};
    assert_int_equal(fread(head, 1, 17, fp), 17);
    assert_string_equal(head, "P5 640 480 65535\n");
    unsigned char b[4];
    assert_int_equal(fread(b, 1, 4, fp), 4);
    pattern(f->raw, 1);
    assert_int_equal(b[0] | (b[1] << 8), f->raw[0]);
    assert_int_equal(b[2] | (b[3] << 8), f->raw[1]);
    fseek(fp, 0, SEEK_END);
    assert_int_equal(ftell(fp), 17 + 640 * 480 * 2);
    fclose(fp);
}

static void expect(const fixture *f, rec_error code, int frame, const char *file_part)
{
    rec_report why;
    assert_int_equal(rec_validate(f->dir, NULL, &why), -(int)code);
    assert_int_equal(why.code, code);
    assert_int_equal(why.frame, frame);
    assert_non_null(strstr(why.file, file_part));
    assert_non_null(strstr(why.message, file_part));
    if (frame >= 0) {
        char s[32];
        snprintf(s, sizeof s, "frame %d", frame);
        assert_non_null(strstr(why.message, s));
    }
}

static void test_missing_index_is_named(void **state)
{
    fixture *f = *state;
    char p[300];
    snprintf(p, sizeof p, "%s/INDEX.txt", f->dir);
    assert_int_equal(unlink(p), 0);
    expect(f, REC_ERR_NO_INDEX, -1, "INDEX.txt");
}

static void test_missing_directory_is_named(void **state)
{
    (void)state;
    rec_report why;
    assert_int_equal(rec_validate("/nonexistent/tryon-dump", NULL, &why), -REC_ERR_NO_DIR);
    assert_non_null(strstr(why.message, "/nonexistent/tryon-dump"));
}

static void test_missing_frame_is_named(void **state)
{
    fixture *f = *state;
    char p[512];
    frame_path(f, 2, p, sizeof p);
    assert_int_equal(unlink(p), 0);
    expect(f, REC_ERR_NO_FRAME, 2, strrchr(p, '/') + 1);
}

static void test_truncated_frame_is_named(void **state)
{
    fixture *f = *state;
    char p[512];
    frame_path(f, 3, p, sizeof p);
    assert_int_equal(truncate(p, 17 + 1000), 0);
    expect(f, REC_ERR_TRUNCATED, 3, strrchr(p, '/') + 1);
}

static void test_long_frame_is_named(void **state)
{
    fixture *f = *state;
    char p[512];
    frame_path(f, 0, p, sizeof p);
    FILE *fp = fopen(p, "ab");
    fputc(0, fp);
    fclose(fp);
    expect(f, REC_ERR_TOO_LONG, 0, strrchr(p, '/') + 1);
}

static void test_wrong_header_is_named(void **state)
{
    fixture *f = *state;
    char p[512];
    frame_path(f, 1, p, sizeof p);
    FILE *fp = fopen(p, "r+b");
    fwrite("P5 320 240 65535\n", 1, 17, fp);
    fclose(fp);
    expect(f, REC_ERR_HEADER, 1, strrchr(p, '/') + 1);
}

static void test_value_above_2047_is_named(void **state)
{
    fixture *f = *state;
    char p[512];
    frame_path(f, 2, p, sizeof p);
    FILE *fp = fopen(p, "r+b");
    fseek(fp, 17 + 2 * 641, SEEK_SET);
    fputc(0xff, fp);
    fputc(0x7f, fp);
    fclose(fp);
    expect(f, REC_ERR_VALUE, 2, strrchr(p, '/') + 1);
}

static void rewrite_index(const fixture *f, const char *text)
{
    char p[300];
    snprintf(p, sizeof p, "%s/INDEX.txt", f->dir);
    FILE *fp = fopen(p, "wb");
    fputs(text, fp);
    fclose(fp);
}

static void test_time_going_backwards_is_named(void **state)
{
    fixture *f = *state;
    rec_index idx;
    rec_report why;
    assert_int_equal(rec_index_read(f->dir, &idx, &why), REC_OK);
    char text[1024];
    snprintf(text, sizeof text, "%s\n%s\n%s\n", idx.frames[0].name, idx.frames[2].name,
             idx.frames[1].name);
    rec_index_free(&idx);
    rewrite_index(f, text);
    expect(f, REC_ERR_TIME_ORDER, 2, "INDEX.txt");
}

static void test_timestamp_going_backwards_is_named(void **state)
{
    fixture *f = *state;
    rec_index idx;
    rec_report why;
    assert_int_equal(rec_index_read(f->dir, &idx, &why), REC_OK);
    /* Same frame files, but a later record time that claims an older device timestamp. */
    char a[512], b[512];
    snprintf(a, sizeof a, "%s/%s", f->dir, idx.frames[1].name);
    snprintf(b, sizeof b, "%s/d-9.000000-3.pgm", f->dir);
    assert_int_equal(link(a, b), 0);
    char text[1024];
    snprintf(text, sizeof text, "%s\n%s\nd-9.000000-3.pgm\n", idx.frames[0].name,
             idx.frames[1].name);
    rec_index_free(&idx);
    rewrite_index(f, text);
    expect(f, REC_ERR_TIMESTAMP_ORDER, 2, "INDEX.txt");
}

static void test_garbage_line_and_empty_index_are_named(void **state)
{
    fixture *f = *state;
    rec_report why;
    rewrite_index(f, "hello world\n");
    assert_int_equal(rec_validate(f->dir, NULL, &why), -REC_ERR_BAD_LINE);
    assert_int_equal(why.line, 1);
    assert_non_null(strstr(why.message, "line 1"));
    rewrite_index(f, "");
    assert_int_equal(rec_validate(f->dir, NULL, &why), -REC_ERR_EMPTY);
    rewrite_index(f, "a-1.0-5-x.dat\n");
    assert_int_equal(rec_validate(f->dir, NULL, &why), -REC_ERR_EMPTY);
    /* fakenect keeps a CR as part of the file name, so a CRLF index cannot replay. */
    rewrite_index(f, "d-1.000000-5.pgm\r\n");
    assert_int_equal(rec_validate(f->dir, NULL, &why), -REC_ERR_BAD_LINE);
    assert_non_null(strstr(why.message, "carriage return"));
}

static void test_random_index_damage_never_crashes(void **state)
{
    fixture *f = *state;
    char p[300], text[2048];
    snprintf(p, sizeof p, "%s/INDEX.txt", f->dir);
    FILE *fp = fopen(p, "rb");
    size_t n = fread(text, 1, sizeof text - 1, fp);
    fclose(fp);
    rec_rng rng;
    rec_rng_seed(&rng, 42, 0);
    /* Flip, delete or insert bytes of INDEX.txt; the validator must answer, not crash. */
    for (int round = 0; round < 200; round++) {
        char bad[2100];
        memcpy(bad, text, n);
        size_t len = n;
        int edits = 1 + (int)(rec_rng_u64(&rng) % 4);
        for (int e = 0; e < edits && len > 0; e++) {
            size_t at = (size_t)(rec_rng_u64(&rng) % len);
            int kind = (int)(rec_rng_u64(&rng) % 3);
            if (kind == 0)
                bad[at] = (char)(rec_rng_u64(&rng) & 0xff);
            else if (kind == 1)
                memmove(bad + at, bad + at + 1, --len - at);
            else if (len < sizeof bad - 1) {
                memmove(bad + at + 1, bad + at, len++ - at);
                bad[at] = "-.\n0d/"[rec_rng_u64(&rng) % 6];
            }
        }
        fp = fopen(p, "wb");
        fwrite(bad, 1, len, fp);
        fclose(fp);
        rec_report why;
        int frames = -1;
        int err = rec_validate(f->dir, &frames, &why);
        assert_true(err <= 0 && -err < REC_ERROR_COUNT);
        if (err == REC_OK)
            assert_true(frames >= 1 && frames <= FRAMES);
        else
            assert_true(why.message[0] != 0);
    }
}

static void test_error_names_come_from_one_list(void **state)
{
    (void)state;
    assert_string_equal(rec_error_name(REC_ERR_TRUNCATED), "REC_ERR_TRUNCATED");
    assert_string_equal(rec_error_name(REC_ERROR_COUNT), "REC_ERR_UNKNOWN");
    assert_non_null(strstr(rec_error_text(REC_ERR_HEADER), "P5 640 480"));
}

int main(void)
{
#define T(fn) cmocka_unit_test_setup_teardown(fn, setup, teardown)
    const struct CMUnitTest tests[] = {
        T(test_written_dump_reads_back_exactly),
        T(test_file_is_little_endian_with_fakenect_header),
        T(test_missing_index_is_named),
        cmocka_unit_test(test_missing_directory_is_named),
        T(test_missing_frame_is_named),
        T(test_truncated_frame_is_named),
        T(test_long_frame_is_named),
        T(test_wrong_header_is_named),
        T(test_value_above_2047_is_named),
        T(test_time_going_backwards_is_named),
        T(test_timestamp_going_backwards_is_named),
        T(test_garbage_line_and_empty_index_are_named),
        T(test_random_index_damage_never_crashes),
        cmocka_unit_test(test_error_names_come_from_one_list),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
