/* A map's statistics, printed (lumis info, lumis demo). */
#include "cli.h"

#include "lumis/metrics.h"
#include "lumis/render.h"

#include <cJSON.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- map statistics (lumis info, lumis demo) ---------------------------------------- */

/* The map's sun (lumis_sun_find with the defaults), as JSON: null when there is none. */
static cJSON *sun_json(const lumis_sun *sun)
{
    if (!sun->found) return cJSON_CreateNull();
    cJSON *o = cJSON_CreateObject();
    if (!o) return NULL;
    const double d[3] = {sun->dir.x, sun->dir.y, sun->dir.z};
    cJSON_AddItemToObject(o, "dir", cJSON_CreateDoubleArray(d, 3));
    cJSON_AddNumberToObject(o, "radius_deg", sun->radius * (180.0 / 3.14159265358979323846));
    cJSON_AddNumberToObject(o, "sample_radius_deg",
                            sun->sample_radius * (180.0 / 3.14159265358979323846));
    cJSON_AddNumberToObject(o, "share", sun->share);
    cJSON_AddItemToObject(o, "power_rgb", cJSON_CreateDoubleArray(sun->power, 3));
    cJSON_AddNumberToObject(o, "pixels", sun->pixels);
    return o;
}

static int print_json(FILE *f, const char *name, const lumis_envmap_stats *s,
                      const lumis_read_info *info, const lumis_sun *sun)
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
    cJSON_AddItemToObject(o, "sun", sun_json(sun));
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
    lumis_sun sun;
    lumis_envmap *env = NULL;
    if ((st = lumis_envmap_from_image(image, &env)) != LUMIS_OK ||
        (st = lumis_sun_find(env, NULL, &sun, NULL)) != LUMIS_OK) {
        lumis_envmap_destroy(env);
        return tool_runtime_error("%s: %s", name, lumis_status_string(st));
    }
    lumis_envmap_destroy(env);
    if (json) return print_json(f, name, &s, info, &sun);

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
    if (sun.found)
        fprintf(f,
                "sun            dir (%.4f, %.4f, %.4f)  radius %.3f deg  share %.4f  "
                "(%d pixels)\n",
                sun.dir.x, sun.dir.y, sun.dir.z, sun.radius * (180.0 / 3.14159265358979323846),
                sun.share, sun.pixels);
    else
        fprintf(f, "sun            none (docs/lights.md, \"The image sun\")\n");
    fprintf(f, "black pixels   %llu\n", (unsigned long long)s.black_pixels);
    fprintf(f, "replaced       %llu channel values (NaN %llu, Inf %llu, negative %llu)\n",
            (unsigned long long)lumis_replaced_total(info->replaced),
            (unsigned long long)info->replaced.nan, (unsigned long long)info->replaced.inf,
            (unsigned long long)info->replaced.negative);
    if (s.power == 0.0) fprintf(f, "note           the map is black: it emits no light\n");
    return EXIT_OK;
}
