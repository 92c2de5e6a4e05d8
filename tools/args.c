/* Command-line parsing shared by the lumis tool and the benchmark programs (args.h). */
#include "args.h"

#include <errno.h>
#include <stdio.h>
#include <unistd.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int tool_is_help(const char *arg)
{
    return strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0;
}

int tool_option(int argc, char **argv, int *i, const char *name, const char **value)
{
    const char *a = argv[*i];
    size_t n = strlen(name);
    if (strncmp(a, name, n) != 0) return 0;
    if (a[n] == '=') {
        *value = a + n + 1;
        return 1;
    }
    if (a[n] != '\0') return 0;
    /* the next argument is the value, unless it is another option ("--json --masks" took
     * "--masks" as a file name): then no value is given (a usage error) */
    const int next = *i + 1 < argc && !(argv[*i + 1][0] == '-' && argv[*i + 1][1] == '-');
    *value = next ? argv[++*i] : NULL;
    return 1;
}

int tool_parse_double(const char *s, double *out)
{
    if (!s || !*s) return 0;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (*end != '\0' || errno == ERANGE || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

int tool_parse_doubles(const char *s, double *out, int max)
{
    int n = 0;
    for (const char *p = s; p && n < max; n++) {
        char part[64];
        const char *comma = strchr(p, ',');
        const size_t len = comma ? (size_t)(comma - p) : strlen(p);
        if (len == 0 || len >= sizeof part) return 0;
        memcpy(part, p, len);
        part[len] = '\0';
        if (!tool_parse_double(part, &out[n])) return 0;
        p = comma ? comma + 1 : NULL;
        if (!p) return n + 1;
    }
    return 0; /* NULL, or more than max numbers */
}

int tool_parse_int(const char *s, long lo, long hi, long *out)
{
    if (!s || !*s) return 0;
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (*end != '\0' || errno == ERANGE || v < lo || v > hi) return 0;
    *out = v;
    return 1;
}

int tool_cap_threads(const char *cmd, int n)
{
    /* the images never depend on the thread count, so more threads than processors only
     * cost memory and time (--threads 1000 started 1000) */
    const long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    if (cpus > 0 && n > cpus) {
        fprintf(stderr, "lumis %s: --threads %d: capped at %ld, this machine's processors\n", cmd,
                n, cpus);
        return (int)cpus;
    }
    return n;
}

int tool_parse_u64(const char *s, int base, unsigned long long *out)
{
    /* strtoull would take "-5" as 2^64 - 5 and skip leading blanks: a digit must come first */
    if (!s || !(*s >= '0' && *s <= '9')) return 0;
    char *end;
    errno = 0;
    const unsigned long long v = strtoull(s, &end, base);
    if (*end != '\0' || errno == ERANGE) return 0;
    *out = v;
    return 1;
}

int tool_parse_size(const char *s, int *w, int *h)
{
    if (!s) return 0;
    const char *x = strchr(s, 'x');
    if (!x) return 0;
    char buf[32];
    size_t n = (size_t)(x - s);
    if (n == 0 || n >= sizeof buf) return 0;
    memcpy(buf, s, n);
    buf[n] = '\0';
    long lw, lh;
    if (!tool_parse_int(buf, 1, INT_MAX, &lw) || !tool_parse_int(x + 1, 1, INT_MAX, &lh)) return 0;
    *w = (int)lw;
    *h = (int)lh;
    return 1;
}
