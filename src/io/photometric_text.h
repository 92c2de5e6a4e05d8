/* What the photometric file readers share (photometric_file.c: the text, numbers, fields,
 * IES LM-63 and the entry points; photometric_ldt.c: EULUMDAT).  Private to src/io. */
#ifndef LUMIS_IO_PHOTOMETRIC_TEXT_H
#define LUMIS_IO_PHOTOMETRIC_TEXT_H

#include "lumis/io.h"
#include "lumis/photometry.h"

#include <stddef.h>

typedef struct text {
    const char *name;
    const lumis_error_sink *errors;
    char *buf;   /* a copy, NUL-terminated, lines split in place */
    char **line; /* the start of each line */
    int nlines;
} text;

/* A cursor over the numbers of lines from a given one on (IES: after TILT=; separators:
 * blanks and commas). */
typedef struct cursor {
    text *t;
    int line; /* 0-based */
    char *p;
} cursor;

/* Whether anything but an end mark follows the table: some writers end their files with
 * a line "END" and DOS's end-of-file byte (^Z), which are not values. */
int lumis__pf_trailing_value(cursor *c);
/* Reads one number for `field`; its line in *at (1-based).  Errors: the end of the file,
 * or a token that is not a number. */
lumis_status lumis__pf_read_number(cursor *c, const char *field, double *v, int *at);
/* n angles, increasing; errors name the line of the culprit. */
lumis_status lumis__pf_read_angles(cursor *c, const char *field, int n, double *a);
/* Copies a text field, trimmed, as UTF-8: a field that is not valid UTF-8 is read as
 * Latin-1 (the single bytes of older files' degree signs and non-breaking spaces), C1
 * bytes become U+FFFD, and control characters blanks, so that JSON and XML written from
 * it are always valid.  Never cuts a character in two. */
void lumis__pf_copy_field(char *dst, size_t cap, const char *src);
/* lumis_photometric_create with the model's messages prefixed "file:line: ". */
lumis_status lumis__pf_create_model(const text *t, int line, const lumis_photometric_desc *d,
                                    lumis_photometric **out);
/* A table of zeros lights nothing: refused, not rendered black. */
lumis_status lumis__pf_check_light(const text *t, const double *cd, size_t n);
/* Reads t, an EULUMDAT file, into f (photometric_ldt.c). */
lumis_status lumis__pf_read_ldt(text *t, lumis_photometric_file *f);

#endif
