/* Command-line parsing shared by the lumis tool and the benchmark programs. */
#ifndef LUMIS_TOOLS_ARGS_H
#define LUMIS_TOOLS_ARGS_H

/* True if argv[*i] is the option `name` ("--name VALUE" or "--name=VALUE"); then *value is
 * its value and *i points at the last argv element used.  A missing value sets *value to
 * NULL (the caller reports it). */
int tool_option(int argc, char **argv, int *i, const char *name, const char **value);

/* Parsers returning 0 on malformed or out-of-range input. */
int tool_parse_double(const char *s, double *out);
int tool_parse_int(const char *s, long lo, long hi, long *out);
/* "A,B,...": 1 to max finite numbers, no empty part; returns how many (0: malformed). */
int tool_parse_doubles(const char *s, double *out, int max);
/* An unsigned 64-bit integer in `base` (0: 0x.. and 0.. prefixes too); no sign, no blanks,
 * nothing after it, not out of range. */
int tool_parse_u64(const char *s, int base, unsigned long long *out);
/* n, or this machine's processor count when n is more (with a note on stderr). */
int tool_cap_threads(const char *cmd, int n);
int tool_parse_size(const char *s, int *w, int *h); /* "WxH", each 1..INT_MAX */

/* True for --help / -h. */
int tool_is_help(const char *arg);

#endif
