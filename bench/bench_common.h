/* Pieces every benchmark program shares: messages, option parsing, a clock, the machine's
 * CPU model and sorting of timings.  Each program defines bench_name (its name for
 * messages). */
#ifndef LUMIS_BENCH_COMMON_H
#define LUMIS_BENCH_COMMON_H

#include "../tools/args.h"

#include <stddef.h>

extern const char bench_name[];

/* "NAME: message" on stderr; returns 1 (runtime error). */
int bench_fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* "NAME: message" and a pointer to --help on stderr; returns 2 (usage error). */
int bench_usage_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* tool_parse_int and tool_parse_size (tools/args.h, for options) into ints, sizes up to
 * 65536 x 65536. */
int bench_parse_int(const char *s, long lo, long hi, int *out);
int bench_parse_size(const char *s, int *w, int *h);

/* Monotonic seconds. */
double bench_now(void);

/* The "model name" of the first CPU in /proc/cpuinfo, or "unknown". */
void bench_cpu_model(char *out, size_t cap);

/* The map to work on (bench_map.c, which needs lumis-io): the file `map` resized to w x h,
 * or (map NULL) the procedural sky at w x h.  0, or bench_fail's exit code. */
struct lumis_envmap;
int bench_load_map(const char *map, int w, int h, struct lumis_envmap **env);

/* qsort comparator for doubles. */
int bench_cmp_double(const void *a, const void *b);

#endif
