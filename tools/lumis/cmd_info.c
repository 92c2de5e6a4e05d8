/* lumis info FILE [--json]: statistics of an environment map. */
#include "common.h"

#include <cJSON.h>
#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: lumis info MAP [--json]\n\n"
    "Prints resolution, min/avg/max luminance, dynamic range, the share of power in the\n"
    "brightest 1 %% and 0.1 %% of pixels, total power and replaced-value counts.\n"
    "MAP is an .exr, .hdr or .pfm file, or sky[:WxH] / studio[:WxH].\n\n"
    "Definitions (as in the data README): Y = 0.2126 R + 0.7152 G + 0.0722 B; pixel (i, j)\n"
    "of a w x h map subtends Omega_j = (2 pi / w)(cos theta_j - cos theta_j+1), theta_j =\n"
    "pi j / h; power = sum Y Omega; avg = power / 4 pi; top shares rank pixels by Y Omega\n"
    "(the top 1 %% is floor(n / 100) pixels, at least one); dynamic range = max Y / smallest "
    "positive Y;\n"
    "negative and non-finite channel values are replaced by 0 and counted.\n\n"
    "options:\n"
    "  --json   print one JSON object (keys: file, format, width, height, min_luminance,\n"
    "           avg_luminance, max_luminance, dynamic_range, power, power_rgb, top1_share,\n"
    "           top01_share, replaced, replaced_nan, replaced_inf, replaced_negative)\n";

static int print_json(FILE *f, const char *name, const lumis_envmap_stats *s,
                      const lumis_read_info *info)
{
    cJSON *o = cJSON_CreateObject();
    if (!o) return EXIT_RUNTIME;
    cJSON_AddStringToObject(o, "file", name);
    cJSON_AddStringToObject(o, "format",
                            info->format ? lumis_format_name(info->format) : "procedural");
    cJSON_AddNumberToObject(o, "width", s->width);
    cJSON_AddNumberToObject(o, "height", s->height);
    cJSON_AddNumberToObject(o, "min_luminance", s->min_luminance);
    cJSON_AddNumberToObject(o, "avg_luminance", s->avg_luminance);
    cJSON_AddNumberToObject(o, "max_luminance", s->max_luminance);
    cJSON_AddNumberToObject(o, "dynamic_range", s->dynamic_range);
    cJSON_AddNumberToObject(o, "power", s->power);
    cJSON *rgb = cJSON_CreateDoubleArray(s->power_rgb, 3);
    cJSON_AddItemToObject(o, "power_rgb", rgb);
    cJSON_AddNumberToObject(o, "top1_share", s->top1_share);
    cJSON_AddNumberToObject(o, "top01_share", s->top01_share);
    cJSON_AddNumberToObject(o, "replaced", (double)lumis_replaced_total(info->replaced));
    cJSON_AddNumberToObject(o, "replaced_nan", (double)info->replaced.nan);
    cJSON_AddNumberToObject(o, "replaced_inf", (double)info->replaced.inf);
    cJSON_AddNumberToObject(o, "replaced_negative", (double)info->replaced.negative);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    if (!text) return EXIT_RUNTIME;
    fprintf(f, "%s\n", text);
    cJSON_free(text);
    return EXIT_OK;
}

int tool_print_info(FILE *f, const char *name, const lumis_image *image,
                    const lumis_read_info *info, int json)
{
    lumis_envmap_stats s;
    lumis_status st = lumis_equirect_stats(image->pixels, image->width, image->height, 1.0f, &s);
    if (st != LUMIS_OK) return tool_runtime_error("%s: %s", name, lumis_status_string(st));
    if (json) return print_json(f, name, &s, info);

    fprintf(f, "file           %s (%s)\n", name,
            info->format ? lumis_format_name(info->format) : "procedural");
    fprintf(f, "resolution     %d x %d\n", s.width, s.height);
    fprintf(f, "luminance      min %.6g  avg %.6g  max %.6g\n", s.min_luminance, s.avg_luminance,
            s.max_luminance);
    if (s.dynamic_range > 0.0)
        fprintf(f, "dynamic range  %.4g : 1 (max / smallest positive)\n", s.dynamic_range);
    else
        fprintf(f, "dynamic range  - (the map is black)\n");
    fprintf(f, "power (Y)      %.6g  (sum Y Omega)\n", s.power);
    fprintf(f, "power (RGB)    %.6g %.6g %.6g\n", s.power_rgb[0], s.power_rgb[1], s.power_rgb[2]);
    fprintf(f, "top 1%% share   %.4f\n", s.top1_share);
    fprintf(f, "top 0.1%% share %.4f\n", s.top01_share);
    fprintf(f, "black pixels   %llu\n", (unsigned long long)s.black_pixels);
    fprintf(f, "replaced       %llu channel values (NaN %llu, Inf %llu, negative %llu)\n",
            (unsigned long long)lumis_replaced_total(info->replaced),
            (unsigned long long)info->replaced.nan, (unsigned long long)info->replaced.inf,
            (unsigned long long)info->replaced.negative);
    if (s.power == 0.0) fprintf(f, "note           the map is black: it emits no light\n");
    return EXIT_OK;
}

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
