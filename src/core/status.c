#include "lumis/status.h"

#include "internal.h"

#include <stdarg.h>
#include <stdio.h>

static const char *const status_names[] = {
#define LUMIS_X_NAME(code, name, text) name,
    LUMIS_STATUS_TABLE(LUMIS_X_NAME)
#undef LUMIS_X_NAME
};

static const char *const status_texts[] = {
#define LUMIS_X_TEXT(code, name, text) text,
    LUMIS_STATUS_TABLE(LUMIS_X_TEXT)
#undef LUMIS_X_TEXT
};

const char *lumis_status_name(lumis_status status)
{
    if ((unsigned)status >= (unsigned)LUMIS_STATUS_COUNT) return "unknown-status";
    return status_names[status];
}

const char *lumis_status_string(lumis_status status)
{
    if ((unsigned)status >= (unsigned)LUMIS_STATUS_COUNT) return "unknown status";
    return status_texts[status];
}

lumis_status lumis__fail(const lumis_error_sink *sink, lumis_status status, const char *fmt, ...)
{
    if (sink && sink->fn) {
        char message[512];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(message, sizeof message, fmt, ap);
        va_end(ap);
        sink->fn(sink->user, status, message);
    }
    return status;
}
