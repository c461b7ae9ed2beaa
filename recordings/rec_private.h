/* Private to recordings/: shared between its files, not part of the public API. */
#ifndef TRYON_REC_PRIVATE_H
#define TRYON_REC_PRIVATE_H

#include "recordings.h"

/* The header fakenect's record tool writes before 640x480 16-bit depth. */
#define REC_PGM_HEADER "P5 640 480 65535\n"

/* Fills why (when not NULL) and returns -code. file: the file at fault; frame: -1 = none;
 * line: INDEX.txt line, 0 = none. */
int rec_fail(rec_report *why, rec_error code, const char *file, int frame, int line,
             const char *fmt, ...) __attribute__((format(printf, 6, 7)));

#endif
