/* Light-set methods and their NAME=VALUE parameters as options: the library's
 * (lumis/lights.h), with the CLI's usage errors. */
#include "errors.h"
#include "lights.h"
#include "pipeline.h"

#include <stdio.h>

#include "lumis/metrics.h"
#include "lumis/render.h"

#include <cJSON.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- light-set methods and parameters: the library's (lumis/lights.h), with the CLI's
 * messages --------------------------------------------------------------------------- */

int tool_lights_method_known(const char *name)
{
    lumis_lights_method method;
    return lumis_lights_method_from_name(name, &method) == LUMIS_OK;
}

const char *tool_lights_method_names(void)
{
    static char list[512];
    if (!list[0])
        for (const char *const *n = lumis_lights_method_names(); *n; n++) {
            if (list[0]) strcat(list, ", ");
            strcat(list, *n);
        }
    return list;
}

/* The library's message, kept for a usage error. */
static void keep_message(void *user, lumis_status status, const char *message)
{
    (void)status;
    snprintf((char *)user, 600, "%s", message);
}

int tool_light_params_parse(lumis_light_params *p, const char *cmd, const char *opt,
                            const char *text)
{
    char msg[600] = "";
    const lumis_error_sink sink = {keep_message, msg};
    if (lumis_light_params_parse(p, text, &sink) != LUMIS_OK)
        return tool_usage_error(cmd, "%s: %s", opt, msg);
    return EXIT_OK;
}

int tool_light_params_check(const lumis_light_params *p, const char *cmd, const char *opt,
                            const char *method)
{
    char msg[600] = "";
    const lumis_error_sink sink = {keep_message, msg};
    if (lumis_light_params_check(p, method, &sink) != LUMIS_OK)
        return tool_usage_error(cmd, "%s: %s", opt, msg);
    return EXIT_OK;
}
