/* Helpers shared by the test programs (cmocka). */
#ifndef LUMIS_TESTUTIL_H
#define LUMIS_TESTUTIL_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "lumis/io.h"
#include "lumis/lumis.h"

/* A fresh temporary folder for this test program (removed at exit). */
const char *tu_tmpdir(void);

/* tu_tmpdir()/name, in a static rotating buffer. */
const char *tu_path(const char *name);

/* Writes bytes to a file; asserts on failure. */
void tu_write_file(const char *path, const void *data, size_t size);

/* Reads a whole file (malloc'ed, caller frees); NULL if it cannot. */
unsigned char *tu_read_file(const char *path, size_t *size);

/* An error sink that keeps the last message and status. */
typedef struct tu_sink {
    lumis_error_sink sink;
    char last[512];
    lumis_status status;
    int count;
} tu_sink;
void tu_sink_init(tu_sink *s);

/* A w x h image whose pixels are f(i, j, c). */
lumis_image *tu_image(int w, int h, float (*f)(int i, int j, int c));
/* An envmap of w x h pixels f(i, j, c) (NULL: a sky with a sun 30 degrees up at azimuth
 * 100), rotated and scaled (0: 1). */
lumis_envmap *tu_envmap(int w, int h, float (*f)(int i, int j, int c), float rotation_deg,
                        float scale);
/* An envmap of img's pixels (copied), rotated and scaled (0: 1). */
lumis_envmap *tu_envmap_of(const lumis_image *img, float rotation_deg, float scale);

/* Runs a shell command, capturing stdout and stderr into malloc'ed strings (may be NULL
 * pointers to skip); returns the exit status, or -1 if it could not run. */
int tu_run(const char *cmd, char **out, char **err);

/* Number of entries in a folder whose name starts with prefix. */
int tu_count_entries(const char *dir, const char *prefix);

/* A 2 x 2 luminaire of 2 x 2 grey images (radiance 1) on S = [-1, 1]^2 at delta 1. */
lumis_status tu_tiny_luminaire(lumis_luminaire **out);

#endif
