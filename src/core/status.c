#include "lumis/status.h"

#include "internal.h"

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
