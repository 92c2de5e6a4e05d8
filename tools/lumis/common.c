#include "common.h"

#include <cJSON.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

static void print_error(void *user, lumis_status status, const char *message)
{
    (void)user;
    (void)status;
    fprintf(stderr, "lumis: %s\n", message);
}

const lumis_error_sink tool_errors = {print_error, NULL};

int tool_usage_error(const char *cmd, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lumis %s: ", cmd);
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n(see 'lumis %s --help')\n", cmd);
    va_end(ap);
    return EXIT_USAGE;
}

int tool_runtime_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "lumis: ");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, "\n");
    va_end(ap);
    return EXIT_RUNTIME;
}

lumis_status tool_load_image(const char *spec, lumis_image **out, lumis_read_info *info)
{
    lumis_read_info local;
    if (!info) info = &local;
    memset(info, 0, sizeof *info);
    int w = 0, h = 0;
    const char *colon = strchr(spec, ':');
    size_t name_len = colon ? (size_t)(colon - spec) : strlen(spec);
    int is_sky = name_len == 3 && strncmp(spec, "sky", 3) == 0;
    int is_studio = name_len == 6 && strncmp(spec, "studio", 6) == 0;
    if (is_sky || is_studio) {
        if (colon && !tool_parse_size(colon + 1, &w, &h)) {
            fprintf(stderr, "lumis: %s: expected %.*s:WxH, e.g. %.*s:1024x512\n", spec,
                    (int)name_len, spec, (int)name_len, spec);
            return LUMIS_ERR_INVALID_ARGUMENT;
        }
        if (is_sky) {
            lumis_sky_desc d = {0};
            d.width = w;
            d.height = h;
            d.sun_elevation_deg = (float)TOOL_SKY_ELEVATION_DEG;
            d.sun_azimuth_deg = (float)TOOL_SKY_AZIMUTH_DEG;
            d.errors = tool_errors;
            return lumis_sky_create(&d, out);
        }
        lumis_studio_desc d = {0};
        d.width = w;
        d.height = h;
        d.errors = tool_errors;
        return lumis_studio_create(&d, out);
    }
    lumis_read_options opt = {0};
    opt.errors = tool_errors;
    return lumis_image_read(spec, &opt, out, info);
}

lumis_status tool_write_image(const char *path, const lumis_image *image,
                              const lumis_write_options *options)
{
    lumis_write_options opt = {0};
    if (options) opt = *options;
    opt.errors = tool_errors;
    return lumis_image_write(path, image, &opt);
}

int tool_write_json(const char *path, const struct cJSON *json)
{
    char *text = cJSON_Print(json);
    if (!text) return tool_runtime_error("%s: out of memory", path);
    size_t n = strlen(text);
    char *line = malloc(n + 2);
    if (line) {
        memcpy(line, text, n);
        line[n++] = '\n';
        line[n] = '\0';
    }
    cJSON_free(text);
    if (!line) return tool_runtime_error("%s: out of memory", path);
    lumis_status st = lumis_write_text(path, line, n, &tool_errors);
    free(line);
    return st == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
}
