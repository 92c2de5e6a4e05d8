/* How a program of tools/ reports: exit codes, the error sink, usage and runtime errors
 * (tools/app/common.c). */
#ifndef LUMIS_APP_ERRORS_H
#define LUMIS_APP_ERRORS_H

#include "lumis/status.h"

/* Exit codes of every subcommand. */
enum { EXIT_OK = 0, EXIT_RUNTIME = 1, EXIT_USAGE = 2 };

/* Error sink that prints "lumis: message" on stderr. */
extern const lumis_error_sink tool_errors;

/* Prints "lumis CMD: message" on stderr; returns EXIT_USAGE. */
int tool_usage_error(const char *cmd, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* A bad option value: "lumis CMD: OPTION EXPECTED, not 'VALUE'" (or "(no value given)"
 * when value is NULL); returns EXIT_USAGE. */
int tool_bad_value(const char *cmd, const char *option, const char *value, const char *expected);

/* Prints "lumis: message" on stderr; returns EXIT_RUNTIME. */
int tool_runtime_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#endif
