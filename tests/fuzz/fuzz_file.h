/* Harnesses of file readers: the input written to a file of the process's own. */
#ifndef TRYON_FUZZ_FILE_H
#define TRYON_FUZZ_FILE_H

#include <stddef.h>
#include <stdint.h>

/* A directory made once per process (removed at exit); returns its path. */
const char *fuzz_dir(void);
/* Writes data to fuzz_dir()/name and returns the full path (static storage). */
const char *fuzz_write(const char *name, const uint8_t *data, size_t size);

#endif
