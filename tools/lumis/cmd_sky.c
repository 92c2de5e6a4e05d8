/* lumis sky ... -o OUT and lumis studio ... -o OUT: procedural maps written to a file. */
#include "cli.h"

#include <string.h>

static const char sky_usage[] =
    "usage: lumis sky [options] -o OUT\n\n"
    "Writes a clear sky after Preetham, Shirley and Smits (1999): Perez sky luminance and\n"
    "chromaticity, a sun disk (0.53 degrees) attenuated by Rayleigh and aerosol extinction,\n"
    "and a Lambertian ground lit by both.  Units: kcd/m^2 (the sun holds most of the power).\n\n"
    "options:\n"
    "  --sun-elevation DEG  sun above the horizon, 0..90 (default 35)\n"
    "  --sun-azimuth DEG    0 = +x, 90 = +z, i.e. increasing u (default 60)\n"
    "  --turbidity T        haze, 1.7..10 (default 2.5, a clear day)\n"
    "  --ground-albedo A    0..1 (default 0.1)\n"
    "  --no-sun             the sky without the sun disk\n"
    "  --size WxH           resolution (default 1024x512)\n"
    "  --exposure EV|auto, --tonemap T   for PNG output (as in lumis convert; default auto)\n"
    "  -o, --output OUT     output file (.exr .hdr .pfm .png)\n";

static const char studio_usage[] =
    "usage: lumis studio [options] -o OUT\n\n"
    "Writes a studio map: a dark surround with key, fill, rim and overhead soft boxes,\n"
    "anti-aliased exactly, so its power is the same at any resolution.\n\n"
    "options:\n"
    "  --intensity K        multiplier of the soft boxes (default 1)\n"
    "  --size WxH           resolution (default 1024x512)\n"
    "  --exposure EV|auto, --tonemap T   for PNG output (as in lumis convert; default auto)\n"
    "  -o, --output OUT     output file (.exr .hdr .pfm .png)\n";

/* Options both commands share; returns -1 if argv[*i] is not one of them. */
static int common_option(const char *cmd, int argc, char **argv, int *i, int *w, int *h,
                         const char **out, lumis_write_options *wo, int *auto_ev,
                         const char **png_only)
{
    const char *v;
    if (tool_option(argc, argv, i, "--size", &v)) {
        if (!tool_parse_size(v, w, h))
            return tool_bad_value(cmd, "--size", v, "needs WxH, e.g. 1024x512");
    } else if (tool_option(argc, argv, i, "--output", &v) || tool_option(argc, argv, i, "-o", &v)) {
        if (!v) return tool_usage_error(cmd, "-o needs a file name");
        *out = v;
    } else if (tool_option(argc, argv, i, "--exposure", &v)) {
        *png_only = "--exposure";
        return tool_exposure_option(cmd, v, &wo->exposure_ev, auto_ev);
    } else if (tool_option(argc, argv, i, "--tonemap", &v)) {
        *png_only = "--tonemap";
        if (!v || lumis_tonemap_from_name(v, &wo->tonemap) != LUMIS_OK)
            return tool_bad_value(cmd, "--tonemap", v, "must be clamp, reinhard or aces");
    } else {
        return -1;
    }
    return EXIT_OK;
}

/* Checked before the map is made. */
static int check_output(const char *cmd, const char *out, const char *png_only)
{
    if (!out) return tool_usage_error(cmd, "no output file (-o OUT)");
    int rc = tool_png_only_option(cmd, png_only, out);
    if (rc != EXIT_OK) return rc;
    tool_files files = {0};
    tool_files_output(&files, "output", out, TOOL_OUT_IMAGE);
    return tool_files_check(cmd, &files);
}

static int finish(lumis_status st, lumis_image *image, const char *out, lumis_write_options wo,
                  int auto_ev)
{
    if (st != LUMIS_OK) return EXIT_RUNTIME; /* the library's sink has printed why */
    if (auto_ev) wo.exposure_ev = tool_auto_exposure(image);
    st = tool_write_image(out, image, &wo);
    lumis_image_destroy(image);
    return st == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
}

int cmd_sky(int argc, char **argv)
{
    lumis_sky_desc d = {0};
    d.sun_elevation_deg = (float)TOOL_SKY_ELEVATION_DEG;
    d.sun_azimuth_deg = (float)TOOL_SKY_AZIMUTH_DEG;
    d.errors = tool_errors;
    lumis_write_options wo = {0};
    int auto_ev = 1;
    const char *out = NULL, *v, *png_only = NULL;
    for (int i = 1; i < argc; i++) {
        double x;
        int rc = common_option("sky", argc, argv, &i, &d.width, &d.height, &out, &wo, &auto_ev,
                               &png_only);
        if (rc > 0) return rc;
        if (rc == 0) continue;
        if (tool_is_help(argv[i])) {
            fputs(sky_usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--sun-elevation", &v)) {
            if (!tool_parse_double(v, &x) || x < 0 || x > 90)
                return tool_bad_value("sky", "--sun-elevation", v, "needs degrees in [0, 90]");
            d.sun_elevation_deg = (float)x;
            d.sun_at_horizon = x == 0.0; /* 0 in the descriptor means the default */
        } else if (tool_option(argc, argv, &i, "--sun-azimuth", &v)) {
            if (!tool_parse_double(v, &x))
                return tool_bad_value("sky", "--sun-azimuth", v, "needs degrees");
            d.sun_azimuth_deg = (float)x;
        } else if (tool_option(argc, argv, &i, "--turbidity", &v)) {
            if (!tool_parse_double(v, &x) || x < 1.7 || x > 10)
                return tool_bad_value("sky", "--turbidity", v, "needs a value in [1.7, 10]");
            d.turbidity = (float)x;
        } else if (tool_option(argc, argv, &i, "--ground-albedo", &v)) {
            if (!tool_parse_double(v, &x) || x < 0 || x > 1)
                return tool_bad_value("sky", "--ground-albedo", v, "needs a value in [0, 1]");
            d.ground_albedo = x == 0.0 ? -1.0f : (float)x; /* 0 in the descriptor means default */
        } else if (strcmp(argv[i], "--no-sun") == 0) {
            d.no_sun = 1;
        } else {
            return tool_usage_error("sky", "unknown argument '%s'", argv[i]);
        }
    }
    int rc = check_output("sky", out, png_only);
    if (rc != EXIT_OK) return rc;
    lumis_image *image = NULL;
    lumis_status st = lumis_sky_create(&d, &image);
    return finish(st, image, out, wo, auto_ev);
}

int cmd_studio(int argc, char **argv)
{
    lumis_studio_desc d = {0};
    d.errors = tool_errors;
    lumis_write_options wo = {0};
    int auto_ev = 1;
    const char *out = NULL, *v, *png_only = NULL;
    for (int i = 1; i < argc; i++) {
        double x;
        int rc = common_option("studio", argc, argv, &i, &d.width, &d.height, &out, &wo, &auto_ev,
                               &png_only);
        if (rc > 0) return rc;
        if (rc == 0) continue;
        if (tool_is_help(argv[i])) {
            fputs(studio_usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--intensity", &v)) {
            if (!tool_parse_double(v, &x) || !(x > 0) || !(x <= 1e30))
                return tool_bad_value("studio", "--intensity", v, "needs a number in (0, 1e30]");
            d.intensity = (float)x;
        } else {
            return tool_usage_error("studio", "unknown argument '%s'", argv[i]);
        }
    }
    int rc = check_output("studio", out, png_only);
    if (rc != EXIT_OK) return rc;
    lumis_image *image = NULL;
    lumis_status st = lumis_studio_create(&d, &image);
    return finish(st, image, out, wo, auto_ev);
}
