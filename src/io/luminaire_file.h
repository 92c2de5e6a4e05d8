/* What the luminaire file's reader (luminaire_file.c) and writer (luminaire_file_write.c)
 * share: the format's constants and three helpers.  Private to src/io. */
#ifndef LUMIS_IO_LUMINAIRE_FILE_H
#define LUMIS_IO_LUMINAIRE_FILE_H

#include <stddef.h>
#include <stdint.h>

#define FORMAT_NAME      "lumis-luminaire"
#define MAX_MANIFEST     ((long)1 << 24) /* bytes: 1024 names of 1024 bytes fit many times */
#define MAX_NAME         1024            /* bytes of one image name */
#define MAX_GRID_STR     "1..256"
#define MAX_SIDE_STR     "1..16384"
#define DEFAULT_UNITS    "mm"
#define UNITS_CAP        32
#define IMAGES_SUFFIX    ".images"
#define JSON_NUMBER_SIZE 40

/* 1 if s is 1..UNITS_CAP-1 printable bytes (the manifest's units). */
int lumis__lumfile_units_ok(const char *s);
/* The folder part of path with its trailing slash ("" if none), malloc'ed; NULL: no
 * memory. */
char *lumis__lumfile_dir_of(const char *path);
/* FNV-1a over 32-bit words: the images' float bits, image by image in the luminaire's row
 * order (row 0 the smallest y).  Word-wise, so 99 images of 256 x 256 cost ~20 ms. */
uint64_t lumis__lumfile_pixels_digest(const float *const *images, int count, size_t floats);

#endif
