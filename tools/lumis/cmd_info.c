/* lumis info FILE [--json]: statistics of an environment map, or (FILE.ies, FILE.ldt) of a
 * photometric file, with its polar plot (--svg). */
#include "cli.h"

#include <cJSON.h>
#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: lumis info MAP [--json]\n"
    "       lumis info FILE.ies|FILE.ldt [--json] [--svg OUT.svg]\n\n"
    "Prints resolution, min/avg/max luminance, dynamic range, the share of power in the\n"
    "brightest 1 % and 0.1 % of pixels, total power and replaced-value counts.\n"
    "MAP is an .exr, .hdr or .pfm file, or sky[:WxH] / studio[:WxH].\n\n"
    "Definitions (as in the data README): Y = 0.2126 R + 0.7152 G + 0.0722 B; pixel (i, j)\n"
    "of a w x h map subtends Omega_j = (2 pi / w)(cos theta_j - cos theta_j+1), theta_j =\n"
    "pi j / h; power = sum Y Omega; avg = power / 4 pi; top shares rank pixels by Y Omega\n"
    "(the top 1 % is floor(n / 100) pixels, at least one); dynamic range = max Y / smallest "
    "positive Y;\n"
    "negative and non-finite channel values are replaced by 0 and counted.  The sun: a\n"
    "compact bright source found by lumis_sun_find (direction, disk radius, share of the\n"
    "power; docs/lights.md, \"The image sun\"), or none.\n\n"
    "options:\n"
    "  --json   print one JSON object (keys: file, format, width, height, min_luminance,\n"
    "           avg_luminance, max_luminance, dynamic_range, power, power_rgb, top1_share,\n"
    "           top01_share, replaced, replaced_nan, replaced_inf, replaced_negative, sun:\n"
    "           null or {dir, radius_deg, sample_radius_deg, share, power_rgb, pixels})\n\n"
    "A photometric file (IES LM-63 or EULUMDAT, by its extension; docs/photometric.md):\n"
    "the fixture, the table, the luminous shape, the flux integrated from the table and the\n"
    "file's own lumens with their difference, the peak, the beam (50 %) and field (10 %)\n"
    "angles of the two principal planes (C0-C180 and C90-C270) with their NEMA beam types,\n"
    "the downward share (types A and B: front), the light output ratio and the efficacy; for\n"
    "type C the zonal lumens, the CIE flux code, the TM-15-11 BUG rating and the spacing\n"
    "criterion (spacing / mounting height; not applicable to floodlights and uplights).\n"
    "  --svg OUT.svg   a polar plot of the two planes (candela; 0 degrees down)\n"
    "  --json          one object (keys: file, format, standard, manufacturer, luminaire,\n"
    "                  catalog, lamp, type, symmetry, vertical_angles, horizontal_angles,\n"
    "                  shape, size_m, flux, lamp_lumens, luminaire_lumens, flux_difference,\n"
    "                  max_candela, max_at_deg, beam_deg, field_deg, downward_fraction,\n"
    "                  light_output_ratio, input_watts, efficacy_lm_per_w, nema_type,\n"
    "                  zonal_lm, cie_flux_code, bug, spacing_criterion,\n"
    "                  spacing_criterion_not_applicable, tilt_included)\n";

int cmd_info(int argc, char **argv)
{
    const char *file = NULL, *svg = NULL, *v;
    int json = 0;
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (tool_option(argc, argv, &i, "--svg", &v)) {
            if (!v || !*v) return tool_usage_error("info", "--svg needs a file");
            svg = v;
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return tool_usage_error("info", "unknown option '%s'", argv[i]);
        } else if (!file) {
            file = argv[i];
        } else {
            return tool_usage_error("info", "one map at a time (got '%s' and '%s')", file, argv[i]);
        }
    }
    if (!file) return tool_usage_error("info", "no map given");
    if (tool_is_photometric_path(file)) {
        tool_files files = {0};
        tool_files_input(&files, "file", file);
        if (svg) tool_files_output(&files, "--svg", svg, TOOL_OUT_FILE);
        const int rc = tool_files_check("info", &files);
        return rc != EXIT_OK ? rc : tool_photometric_info(file, json, svg);
    }
    if (svg) return tool_usage_error("info", "--svg: only for a photometric file (.ies, .ldt)");
    lumis_image *image = NULL;
    lumis_read_info info;
    if (tool_load_image(file, &image, &info) != LUMIS_OK) return EXIT_RUNTIME;
    int rc = tool_print_info(stdout, file, image, &info, json);
    lumis_image_destroy(image);
    return rc;
}
