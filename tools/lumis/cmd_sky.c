/* lumis sky ... -o OUT and lumis studio ... -o OUT: procedural maps written to a file. */
#include "cli.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

/* What lumis sky and lumis studio read from their options. */
typedef struct map_cli {
    lumis_sky_desc sky;
    lumis_studio_desc studio;
    float albedo; /* --ground-albedo, or -1 */
    lumis_write_options wo;
    int auto_ev;
    const char *out, *png_only;
} map_cli;

#define AT(f) offsetof(map_cli, f)
/* The options both commands take; sky's width and height are studio's too (copied). */
#define MAP_OPTIONS                                                                                \
    {.kind = TOOL_OPT_SIZE,                                                                        \
     .name = "--size",                                                                             \
     .metavar = "WxH",                                                                             \
     .help = "resolution (default 1024x512)",                                                      \
     .at = AT(sky.width),                                                                          \
     .at2 = AT(sky.height)},                                                                       \
        {.kind = TOOL_OPT_EXPOSURE,                                                                \
         .name = "--exposure",                                                                     \
         .metavar = "EV|auto",                                                                     \
         .help = "for PNG output: stops (as in lumis convert; default auto)",                      \
         .at = AT(wo.exposure_ev),                                                                 \
         .at2 = AT(auto_ev),                                                                       \
         .note = TOOL_NOTE(map_cli, png_only)},                                                    \
        {.kind = TOOL_OPT_PARSE,                                                                   \
         .name = "--tonemap",                                                                      \
         .metavar = "T",                                                                           \
         .help = "for PNG output: clamp (default), reinhard or aces",                              \
         .at = AT(wo.tonemap),                                                                     \
         .parse = tool_opt_tonemap,                                                                \
         .what = TOOL_TONEMAP_WHAT,                                                                \
         .note = TOOL_NOTE(map_cli, png_only)},                                                    \
    {                                                                                              \
        .kind = TOOL_OPT_STRING, .name = "--output", .alias = "-o", .metavar = "OUT",              \
        .help = "output file (.exr .hdr .pfm .png)", .at = AT(out), .what = "a file name"          \
    }

static const tool_opt sky_opts[] = {
    {.kind = TOOL_OPT_FLOAT,
     .name = "--sun-elevation",
     .metavar = "DEG",
     .help = "sun above the horizon, 0..90 (default 35)",
     .at = AT(sky.sun_elevation_deg),
     .lo = 0,
     .hi = 90,
     .what = "degrees"},
    {.kind = TOOL_OPT_FLOAT,
     .name = "--sun-azimuth",
     .metavar = "DEG",
     .help = "0 = +x, 90 = +z, i.e. increasing u (default 60)",
     .at = AT(sky.sun_azimuth_deg),
     .lo = -HUGE_VAL,
     .hi = HUGE_VAL,
     .what = "degrees"},
    {.kind = TOOL_OPT_FLOAT,
     .name = "--turbidity",
     .metavar = "T",
     .help = "haze, 1.7..10 (default 2.5, a clear day)",
     .at = AT(sky.turbidity),
     .lo = 1.7,
     .hi = 10,
     .what = "a value"},
    {.kind = TOOL_OPT_FLOAT,
     .name = "--ground-albedo",
     .metavar = "A",
     .help = "0..1 (default 0.1)",
     .at = AT(albedo),
     .lo = 0,
     .hi = 1,
     .what = "a value"},
    {.kind = TOOL_OPT_FLAG,
     .name = "--no-sun",
     .help = "the sky without the sun disk",
     .at = AT(sky.no_sun)},
    MAP_OPTIONS,
    {0},
};

const tool_optspec tool_sky_spec = {
    .cmd = "sky",
    .usage = "usage: lumis sky [options] -o OUT",
    .intro =
        "Writes a clear sky after Preetham, Shirley and Smits (1999): Perez sky luminance and\n"
        "chromaticity, a sun disk (0.53 degrees) attenuated by Rayleigh and aerosol extinction,\n"
        "and a Lambertian ground lit by both.  Units: kcd/m^2 (the sun holds most of the power).",
    .opts = sky_opts,
};

static const tool_opt studio_opts[] = {
    {.kind = TOOL_OPT_FLOAT,
     .name = "--intensity",
     .metavar = "K",
     .help = "multiplier of the soft boxes (default 1)",
     .at = AT(studio.intensity),
     .lo = 0,
     .open_lo = 1,
     .hi = 1e30},
    MAP_OPTIONS,
    {0},
};

const tool_optspec tool_studio_spec = {
    .cmd = "studio",
    .usage = "usage: lumis studio [options] -o OUT",
    .intro = "Writes a studio map: a dark surround with key, fill, rim and overhead soft boxes,\n"
             "anti-aliased exactly, so its power is the same at any resolution.",
    .opts = studio_opts,
};

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

/* The options into c (sky.width and height are studio's too).  -1 to go on, else an exit
 * code. */
static int read_options(const tool_optspec *spec, int argc, char **argv, map_cli *c)
{
    c->wo = (lumis_write_options){0};
    c->auto_ev = 1;
    c->albedo = -1.0f;
    int rc = tool_optparse(spec, argc, argv, c);
    if (rc >= 0) return rc;
    rc = check_output(spec->cmd, c->out, c->png_only);
    return rc == EXIT_OK ? -1 : rc;
}

int cmd_sky(int argc, char **argv)
{
    map_cli c = {0};
    c.sky.sun_elevation_deg = (float)TOOL_SKY_ELEVATION_DEG;
    c.sky.sun_azimuth_deg = (float)TOOL_SKY_AZIMUTH_DEG;
    c.sky.errors = tool_errors;
    const int rc = read_options(&tool_sky_spec, argc, argv, &c);
    if (rc >= 0) return rc;
    c.sky.sun_at_horizon = c.sky.sun_elevation_deg == 0.0f; /* 0 in the descriptor: default */
    if (c.albedo >= 0.0f)
        c.sky.ground_albedo = c.albedo == 0.0f ? -1.0f : c.albedo; /* 0: default */
    lumis_image *image = NULL;
    lumis_status st = lumis_sky_create(&c.sky, &image);
    return finish(st, image, c.out, c.wo, c.auto_ev);
}

int cmd_studio(int argc, char **argv)
{
    map_cli c = {0};
    c.studio.errors = tool_errors;
    const int rc = read_options(&tool_studio_spec, argc, argv, &c);
    if (rc >= 0) return rc;
    c.studio.width = c.sky.width;
    c.studio.height = c.sky.height;
    lumis_image *image = NULL;
    lumis_status st = lumis_studio_create(&c.studio, &image);
    return finish(st, image, c.out, c.wo, c.auto_ev);
}
