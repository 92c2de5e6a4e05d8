/* lumis convert IN OUT [--exposure EV] [--tonemap T] [--resize WxH] [--half] [--big-endian] */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: lumis convert IN OUT [options]\n\n"
    "Converts an image.  IN is read by its content (.exr .hdr .pfm, and .png decoded from\n"
    "sRGB to linear) and may also be sky[:WxH] or studio[:WxH]; OUT's format comes from its\n"
    "extension (.exr .hdr .pfm .png).\n\n"
    "options:\n"
    "  --exposure EV   PNG: multiply radiance by 2^EV before tone mapping; 'auto' (default)\n"
    "                  brings the mean luminance to 0.18\n"
    "  --tonemap T     PNG: clamp (default), reinhard or aces\n"
    "  --resize WxH    resample as an equirectangular map, preserving total power\n"
    "                  (every output pixel is the solid-angle mean of what it covers)\n"
    "  --half          EXR: write half floats (values above 65504 are clamped)\n"
    "                  (Radiance HDR holds values below 2^127: larger ones are clamped to\n"
    "                  its largest, 1.69e38)\n"
    "  --compression C EXR: zip (default), none, rle, zips, piz, pxr24, b44, b44a, dwaa, dwab\n"
    "  --tile N        EXR: write a tiled file with N x N tiles\n"
    "  --big-endian    PFM: write big-endian floats (default little-endian)\n";

int cmd_convert(int argc, char **argv)
{
    const char *in = NULL, *out = NULL, *v;
    const char *png_only = NULL, *exr_only = NULL, *pfm_only = NULL; /* given, for OUT's format */
    int auto_ev = 1;
    lumis_write_options wo = {0};
    int rw = 0, rh = 0;
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--exposure", &v)) {
            png_only = "--exposure";
            int rc = tool_exposure_option("convert", v, &wo.exposure_ev, &auto_ev);
            if (rc != EXIT_OK) return rc;
        } else if (tool_option(argc, argv, &i, "--tonemap", &v)) {
            png_only = "--tonemap";
            if (!v || lumis_tonemap_from_name(v, &wo.tonemap) != LUMIS_OK)
                return tool_bad_value("convert", "--tonemap", v, "must be clamp, reinhard or aces");
        } else if (tool_option(argc, argv, &i, "--resize", &v)) {
            if (!tool_parse_size(v, &rw, &rh))
                return tool_bad_value("convert", "--resize", v, "needs WxH, e.g. 512x256");
        } else if (tool_option(argc, argv, &i, "--compression", &v)) {
            exr_only = "--compression";
            if (!v || lumis_exr_compression_from_name(v, &wo.exr_compression) != LUMIS_OK)
                return tool_usage_error("convert", "--compression must be one of zip, none, rle, "
                                                   "zips, piz, pxr24, b44, b44a, dwaa, dwab");
        } else if (tool_option(argc, argv, &i, "--tile", &v)) {
            long t;
            if (!tool_parse_int(v, 1, 65536, &t))
                return tool_bad_value("convert", "--tile", v, "needs a tile size in [1, 65536]");
            wo.exr_tile_size = (int)t;
            exr_only = "--tile";
        } else if (strcmp(argv[i], "--half") == 0) {
            wo.exr_half = 1;
            exr_only = "--half";
        } else if (strcmp(argv[i], "--big-endian") == 0) {
            wo.pfm_big_endian = 1;
            pfm_only = "--big-endian";
        } else if (argv[i][0] == '-' && argv[i][1] != '\0') {
            return tool_usage_error("convert", "unknown option '%s'", argv[i]);
        } else if (!in) {
            in = argv[i];
        } else if (!out) {
            out = argv[i];
        } else {
            return tool_usage_error("convert", "too many arguments ('%s')", argv[i]);
        }
    }
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
