/* Light-set methods and parameters as options name them (tools/app/light_options.c). */
#ifndef LUMIS_APP_LIGHTS_H
#define LUMIS_APP_LIGHTS_H

#include "lumis/lights.h"

/* Light-set methods by name (lumis_lights_method_from_name): known, and the names joined
 * for a message. */
int tool_lights_method_known(const char *name);
const char *tool_lights_method_names(void);

/* lumis_light_params_parse of option `opt`'s value `text` (lumis lights --param, lumis render
 * --lights-param): a usage error of command `cmd` (EXIT_USAGE) with the library's message,
 * else EXIT_OK. */
int tool_light_params_parse(lumis_light_params *p, const char *cmd, const char *opt,
                            const char *text);
/* lumis_light_params_check against `method`, as a usage error (EXIT_USAGE) or EXIT_OK. */
int tool_light_params_check(const lumis_light_params *p, const char *cmd, const char *opt,
                            const char *method);

#endif
