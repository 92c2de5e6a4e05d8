/* lumis/status.h - status codes, their names, and the optional error sink.
 *
 * Every public function that can fail returns a lumis_status.  The codes, their
 * names and their default texts come from one X-macro table so they can never
 * drift apart.  Messages with context (file, reason) go to an error sink the
 * caller may provide; the library itself never prints and never exits. */
#ifndef LUMIS_STATUS_H
#define LUMIS_STATUS_H

#include "lumis/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* X(code, name, default text) */
#define LUMIS_STATUS_TABLE(X)                                                                      \
    X(LUMIS_OK, "ok", "success")                                                                   \
    X(LUMIS_ERR_INVALID_ARGUMENT, "invalid-argument", "invalid argument")                          \
    X(LUMIS_ERR_OUT_OF_MEMORY, "out-of-memory", "out of memory")                                   \
    X(LUMIS_ERR_OPEN, "open", "cannot open file")                                                  \
    X(LUMIS_ERR_READ, "read", "read error")                                                        \
    X(LUMIS_ERR_WRITE, "write", "cannot write output")                                             \
    X(LUMIS_ERR_EMPTY_FILE, "empty-file", "file is empty")                                         \
    X(LUMIS_ERR_UNKNOWN_FORMAT, "unknown-format", "unknown file format")                           \
    X(LUMIS_ERR_BAD_MAGIC, "bad-magic", "file content does not match its format")                  \
    X(LUMIS_ERR_BAD_HEADER, "bad-header", "malformed header")                                      \
    X(LUMIS_ERR_BAD_DIMENSIONS, "bad-dimensions", "zero, negative or malformed dimensions")        \
    X(LUMIS_ERR_TOO_LARGE, "too-large", "dimensions exceed the pixel limit")                       \
    X(LUMIS_ERR_TRUNCATED, "truncated", "data ends before the image does")                         \
    X(LUMIS_ERR_CORRUPT, "corrupt", "corrupt image data")                                          \
    X(LUMIS_ERR_UNSUPPORTED, "unsupported", "unsupported feature of the format")                   \
    X(LUMIS_ERR_MISSING_CHANNELS, "missing-channels", "image has no RGB or Y channels")

typedef enum lumis_status {
#define LUMIS_X_ENUM(code, name, text) code,
    LUMIS_STATUS_TABLE(LUMIS_X_ENUM)
#undef LUMIS_X_ENUM
        LUMIS_STATUS_COUNT
} lumis_status;

/* Short stable name of a status, e.g. "truncated"; "unknown-status" if out of range. */
LUMIS_API const char *lumis_status_name(lumis_status status);

/* Human-readable default text of a status, e.g. "data ends before the image does". */
LUMIS_API const char *lumis_status_string(lumis_status status);

/* Receives one message per failure, with context (file name, reason).  The message is
 * valid only during the call. */
typedef void (*lumis_error_fn)(void *user, lumis_status status, const char *message);

/* Optional error sink; a zeroed sink discards messages. */
typedef struct lumis_error_sink {
    lumis_error_fn fn; /* NULL == discard */
    void *user;        /* passed back to fn */
} lumis_error_sink;

#ifdef __cplusplus
}
#endif
#endif
