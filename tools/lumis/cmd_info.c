/* lumis info FILE [--json]: statistics of an environment map. */
#include "common.h"

#include <cJSON.h>
#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: lumis info MAP [--json]\n\n"
    "Prints resolution, min/avg/max luminance, dynamic range, the share of power in the\n"
    "brightest 1 % and 0.1 % of pixels, total power and replaced-value counts.\n"
    "MAP is an .exr, .hdr or .pfm file, or sky[:WxH] / studio[:WxH].\n\n"
    "Definitions (as in the data README): Y = 0.2126 R + 0.7152 G + 0.0722 B; pixel (i, j)\n"
    "of a w x h map subtends Omega_j = (2 pi / w)(cos theta_j - cos theta_j+1), theta_j =\n"
    "pi j / h; power = sum Y Omega; avg = power / 4 pi; top shares rank pixels by Y Omega\n"
    "(the top 1 % is floor(n / 100) pixels, at least one); dynamic range = max Y / smallest "
    "positive Y;\n"
    "negative and non-finite channel values are replaced by 0 and counted.\n\n"
    "options:\n"
    "  --json   print one JSON object (keys: file, format, width, height, min_luminance,\n"
    "           avg_luminance, max_luminance, dynamic_range, power, power_rgb, top1_share,\n"
    "           top01_share, replaced, replaced_nan, replaced_inf, replaced_negative)\n";

int cmd_info(int argc, char **argv)
{
    const char *file = NULL;
    int json = 0;
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return tool_usage_error("info", "unknown option '%s'", argv[i]);
        } else if (!file) {
            file = argv[i];
        } else {
            return tool_usage_error("info", "one map at a time (got '%s' and '%s')", file, argv[i]);
        }
    }
    if (!file) return tool_usage_error("info", "no map given");
    lumis_image *image = NULL;
    lumis_read_info info;
    if (tool_load_image(file, &image, &info) != LUMIS_OK) return EXIT_RUNTIME;
    int rc = tool_print_info(stdout, file, image, &info, json);
    lumis_image_destroy(image);
    return rc;
}
