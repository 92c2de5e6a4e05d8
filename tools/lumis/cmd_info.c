/* lumis info FILE [--json]: statistics of an environment map, or (FILE.ies, FILE.ldt) of a
 * photometric file, with its polar plot (--svg). */
#include "cli.h"

#include <cJSON.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

typedef struct info_cli {
    const char *file, *svg;
    int json;
} info_cli;

static int info_positional(const char *cmd, const char *arg, void *ctx)
{
    info_cli *c = ctx;
    if (c->file)
        return tool_usage_error(cmd, "one map at a time (got '%s' and '%s')", c->file, arg);
    c->file = arg;
    return EXIT_OK;
}

static const tool_opt info_table[] = {
    {.kind = TOOL_OPT_FLAG,
     .name = "--json",
     .help = "print one JSON object; a map's keys: file, format, width, height,\n"
             "min_luminance, avg_luminance, max_luminance, dynamic_range, power,\n"
             "power_rgb, top1_share, top01_share, replaced, replaced_nan, replaced_inf,\n"
             "replaced_negative, sun (null or {dir, radius_deg, sample_radius_deg,\n"
             "share, power_rgb, pixels}); a photometric file's: file, format, standard,\n"
             "manufacturer, luminaire, catalog, lamp, type, symmetry, vertical_angles,\n"
             "horizontal_angles, shape, size_m, flux, lamp_lumens, luminaire_lumens,\n"
             "flux_difference, max_candela, max_at_deg, beam_deg, field_deg,\n"
             "downward_fraction, light_output_ratio, input_watts, efficacy_lm_per_w,\n"
             "nema_type, zonal_lm, cie_flux_code, bug, spacing_criterion,\n"
             "spacing_criterion_not_applicable, tilt_included",
     .at = offsetof(info_cli, json)},
    {.kind = TOOL_OPT_STRING,
     .name = "--svg",
     .metavar = "OUT.svg",
     .help = "a photometric file's polar plot of the two planes (candela; 0 degrees\n"
             "down)",
     .at = offsetof(info_cli, svg),
     .what = "a file"},
    {0},
};

const tool_optspec tool_info_spec = {
    .cmd = "info",
    .usage = "usage: lumis info MAP [--json]\n"
             "       lumis info FILE.ies|FILE.ldt [--json] [--svg OUT.svg]",
    .intro =
        "Prints resolution, min/avg/max luminance, dynamic range, the share of power in the\n"
        "brightest 1 % and 0.1 % of pixels, total power and replaced-value counts.\n"
        "MAP is an .exr, .hdr or .pfm file, or sky[:WxH] / studio[:WxH].\n\n"
        "Definitions (as in the data README): Y = 0.2126 R + 0.7152 G + 0.0722 B; pixel (i, j)\n"
        "of a w x h map subtends Omega_j = (2 pi / w)(cos theta_j - cos theta_j+1), theta_j =\n"
        "pi j / h; power = sum Y Omega; avg = power / 4 pi; top shares rank pixels by Y Omega\n"
        "(the top 1 % is floor(n / 100) pixels, at least one); dynamic range = max Y / smallest\n"
        "positive Y; negative and non-finite channel values are replaced by 0 and counted.  The\n"
        "sun: a compact bright source found by lumis_sun_find (direction, disk radius, share\n"
        "of the power; docs/lights.md, \"The image sun\"), or none.\n\n"
        "A photometric file (IES LM-63 or EULUMDAT, by its extension; docs/photometric.md):\n"
        "the fixture, the table, the luminous shape, the flux integrated from the table and the\n"
        "file's own lumens with their difference, the peak, the beam (50 %) and field (10 %)\n"
        "angles of the two principal planes (C0-C180 and C90-C270) with their NEMA beam types,\n"
        "the downward share (types A and B: front), the light output ratio and the efficacy; for\n"
        "type C the zonal lumens, the CIE flux code, the TM-15-11 BUG rating and the spacing\n"
        "criterion (spacing / mounting height; not applicable to floodlights and uplights).",
    .opts = info_table,
    .positional = info_positional,
};

int cmd_info(int argc, char **argv)
{
    info_cli c = {0};
    const int orc = tool_optparse(&tool_info_spec, argc, argv, &c);
    if (orc >= 0) return orc;
    const char *file = c.file, *svg = c.svg;
    const int json = c.json;
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
