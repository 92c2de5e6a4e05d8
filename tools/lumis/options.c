/* The options several commands share: a sampler's, --exposure, the PNG-only ones. */
#include "cli.h"

#include <math.h>
#include <string.h>

int tool_sampler_option(const char *cmd, int argc, char **argv, int *i, lumis_sampler_desc *d,
                        float *rotation)
{
    const char *v;
    if (tool_option(argc, argv, i, "--method", &v)) {
        if (!v || lumis_sampler_method_from_name(v, &d->method) != LUMIS_OK)
            return tool_usage_error(cmd, "--method must be one of inversion, inversion-guided, "
                                         "alias, kdtree, kdtree-exact, hierarchical, uniform");
    } else if (tool_option(argc, argv, i, "--blocks", &v)) {
        long k;
        if (!tool_parse_int(v, 1, 1 << 24, &k))
            return tool_bad_value(cmd, "--blocks", v, "needs a count in [1, 16777216]");
        d->kdtree_blocks = (int)k;
    } else if (strcmp(argv[*i], "--kdtree-uniform-angles") == 0) {
        d->kdtree_uniform_angles = 1;
    } else if (strcmp(argv[*i], "--compensate") == 0) {
        d->compensate = 1;
    } else if (tool_option(argc, argv, i, "--importance", &v)) {
        if (v && strcmp(v, "luminance") == 0)
            d->importance = LUMIS_IMPORTANCE_LUMINANCE;
        else if (v && strcmp(v, "average") == 0)
            d->importance = LUMIS_IMPORTANCE_AVERAGE;
        else if (v && strcmp(v, "max-channel") == 0)
            d->importance = LUMIS_IMPORTANCE_MAX_CHANNEL;
        else
            return tool_bad_value(cmd, "--importance", v,
                                  "must be luminance, average or max-channel");
    } else if (tool_option(argc, argv, i, "--rotate", &v)) {
        double deg;
        /* a usage error about --rotate, not the envmap's "rotation finite" */
        if (!tool_parse_double(v, &deg) || !(fabs(deg) <= 1e6))
            return tool_bad_value(cmd, "--rotate", v, "needs degrees in [-1e6, 1e6]");
        *rotation = (float)deg;
    } else {
        return -1;
    }
    return EXIT_OK;
}

int tool_exposure_option(const char *cmd, const char *v, float *ev, int *is_auto)
{
    double x;
    if (v && strcmp(v, "auto") == 0) {
        *is_auto = 1;
        *ev = 0.0f;
        return EXIT_OK;
    }
    if (!tool_parse_double(v, &x) || x < -64 || x > 64)
        return tool_usage_error(cmd, "--exposure needs 'auto' or stops in [-64, 64], not '%s'",
                                v ? v : "");
    *is_auto = 0;
    *ev = (float)x;
    return EXIT_OK;
}

int tool_png_only_option(const char *cmd, const char *option, const char *out)
{
    if (!option || !out || lumis_format_from_path(out) == LUMIS_FORMAT_PNG) return EXIT_OK;
    return tool_usage_error(cmd, "%s applies to PNG output only, and %s is not a PNG", option, out);
}
