/* lumis convert IN OUT [--exposure EV] [--tonemap T] [--resize WxH] [--half] [--big-endian] */
#include "cli.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* What lumis convert reads from its arguments. */
typedef struct convert_cli {
    const char *in, *out;
    const char *png_only, *exr_only, *pfm_only; /* given, for OUT's format */
    int auto_ev;
    lumis_write_options wo;
    int rw, rh;
} convert_cli;

static int parse_compression(const char *v, void *field)
{
    return lumis_exr_compression_from_name(v, field) == LUMIS_OK;
}

#define AT(f) offsetof(convert_cli, f)
static const tool_opt convert_opts[] = {
    {.kind = TOOL_OPT_EXPOSURE,
     .name = "--exposure",
     .metavar = "EV",
     .help = "PNG: multiply radiance by 2^EV before tone mapping; 'auto' (default)\n"
             "brings the mean luminance to 0.18",
     .at = AT(wo.exposure_ev),
     .at2 = AT(auto_ev),
     .note = TOOL_NOTE(convert_cli, png_only)},
    {.kind = TOOL_OPT_PARSE,
     .name = "--tonemap",
     .metavar = "T",
     .help = "PNG: clamp (default), reinhard or aces",
     .at = AT(wo.tonemap),
     .parse = tool_opt_tonemap,
     .what = TOOL_TONEMAP_WHAT,
     .note = TOOL_NOTE(convert_cli, png_only)},
    {.kind = TOOL_OPT_SIZE,
     .name = "--resize",
     .metavar = "WxH",
     .help = "resample as an equirectangular map, preserving total power\n"
             "(every output pixel is the solid-angle mean of what it covers)",
     .at = AT(rw),
     .at2 = AT(rh),
     .what = "512x256"},
    {.kind = TOOL_OPT_FLAG,
     .name = "--half",
     .help = "EXR: write half floats (values above 65504 are clamped)\n"
             "(Radiance HDR holds values below 2^127: larger ones are clamped to\n"
             "its largest, 1.69e38)",
     .at = AT(wo.exr_half),
     .note = TOOL_NOTE(convert_cli, exr_only)},
    {.kind = TOOL_OPT_PARSE,
     .name = "--compression",
     .metavar = "C",
     .help = "EXR: zip (default), none, rle, zips, piz, pxr24, b44, b44a, dwaa, dwab",
     .at = AT(wo.exr_compression),
     .parse = parse_compression,
     .what = "must be one of zip, none, rle, zips, piz, pxr24, b44, b44a, dwaa, dwab",
     .note = TOOL_NOTE(convert_cli, exr_only)},
    {.kind = TOOL_OPT_INT,
     .name = "--tile",
     .metavar = "N",
     .help = "EXR: write a tiled file with N x N tiles",
     .at = AT(wo.exr_tile_size),
     .lo = 1,
     .hi = 65536,
     .what = "a tile size",
     .note = TOOL_NOTE(convert_cli, exr_only)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--big-endian",
     .help = "PFM: write big-endian floats (default little-endian)",
     .at = AT(wo.pfm_big_endian),
     .note = TOOL_NOTE(convert_cli, pfm_only)},
    {0},
};

static int convert_positional(const char *cmd, const char *arg, void *ctx)
{
    convert_cli *c = ctx;
    if (!c->in)
        c->in = arg;
    else if (!c->out)
        c->out = arg;
    else
        return tool_usage_error(cmd, "too many arguments ('%s')", arg);
    return EXIT_OK;
}

const tool_optspec tool_convert_spec = {
    .cmd = "convert",
    .usage = "usage: lumis convert IN OUT [options]",
    .intro =
        "Converts an image.  IN is read by its content (.exr .hdr .pfm, and .png decoded from\n"
        "sRGB to linear) and may also be sky[:WxH] or studio[:WxH]; OUT's format comes from its\n"
        "extension (.exr .hdr .pfm .png).",
    .opts = convert_opts,
    .positional = convert_positional,
};

int cmd_convert(int argc, char **argv)
{
    convert_cli c = {0};
    c.auto_ev = 1;
    int prc = tool_optparse(&tool_convert_spec, argc, argv, &c);
    if (prc >= 0) return prc;
    const char *in = c.in, *out = c.out, *png_only = c.png_only, *exr_only = c.exr_only,
               *pfm_only = c.pfm_only;
    lumis_write_options wo = c.wo;
    const int auto_ev = c.auto_ev, rw = c.rw, rh = c.rh;
    if (!in || !out) return tool_usage_error("convert", "needs IN and OUT");
    tool_files files = {0};
    tool_files_input(&files, "input", in);
    tool_files_output(&files, "output", out, TOOL_OUT_IMAGE);
    int rc = tool_files_check("convert", &files);
    if (rc == EXIT_OK) rc = tool_png_only_option("convert", png_only, out);
    if (rc != EXIT_OK) return rc;
    const lumis_file_format fmt = lumis_format_from_path(out);
    if (exr_only && fmt != LUMIS_FORMAT_EXR)
        return tool_usage_error("convert", "%s applies to EXR output only, and %s is not an EXR",
                                exr_only, out);
    if (pfm_only && fmt != LUMIS_FORMAT_PFM)
        return tool_usage_error("convert", "%s applies to PFM output only, and %s is not a PFM",
                                pfm_only, out);

    lumis_image *image = NULL;
    lumis_read_info info;
    if (tool_load_image(in, &image, &info) != LUMIS_OK) return EXIT_RUNTIME; /* warns */
    if (rw && (rw != image->width || rh != image->height)) {
        lumis_image *resized = NULL;
        lumis_status st = lumis_image_create(rw, rh, &resized);
        if (st == LUMIS_OK)
            st = lumis_equirect_resize(image->pixels, image->width, image->height, resized->pixels,
                                       rw, rh);
        lumis_image_destroy(image);
        image = resized;
        if (st != LUMIS_OK) {
            lumis_image_destroy(image);
            return tool_runtime_error("resize to %dx%d: %s", rw, rh, lumis_status_string(st));
        }
    }
    if (auto_ev) wo.exposure_ev = tool_auto_exposure(image);
    lumis_status st = tool_write_image(out, image, &wo);
    lumis_image_destroy(image);
    return st == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
}
