/* The check several commands share: the PNG-only options (--exposure, --tonemap) against
 * the output's format.  The options themselves are in each command's table (optparse.h). */
#include "cli.h"

#include <string.h>

int tool_png_only_option(const char *cmd, const char *option, const char *out)
{
    if (!option || !out || lumis_format_from_path(out) == LUMIS_FORMAT_PNG) return EXIT_OK;
    return tool_usage_error(cmd, "%s applies to PNG output only, and %s is not a PNG", option, out);
}
