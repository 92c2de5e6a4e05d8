/* Pieces every benchmark program shares: messages, option parsing, a clock, the machine's
 * CPU model and sorting of timings.  Each program defines bench_name (its name for
 * messages). */
#ifndef LUMIS_BENCH_COMMON_H
#define LUMIS_BENCH_COMMON_H

#include <stddef.h>

extern const char bench_name[];

/* "NAME: message" on stderr; returns 1 (runtime error). */
int bench_fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* "NAME: message" and a pointer to --help on stderr; returns 2 (usage error). */
int bench_usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Parsers returning 0 on malformed or out-of-range input. */
int bench_parse_int(const char *s, long lo, long hi, int *out);
int bench_parse_size(const char *s, int *w, int *h); /* "WxH", each 1..65536 */

/* True if argv[*i] is option `name`, as "--name VALUE" or "--name=VALUE"; *value is then
 * its value (NULL if missing) and *i the last argv element used. */
int bench_option(int argc, char **argv, int *i, const char *name, const char **value);

/* Monotonic seconds. */
double bench_now(void);

/* The "model name" of the first CPU in /proc/cpuinfo, or "unknown". */
void bench_cpu_model(char *out, size_t cap);

/* qsort comparator for doubles. */
int bench_cmp_double(const void *a, const void *b);

#endif
