/* lumis lights MAP --method M [-k K] ...: an environment map as K directional lights (median
 * cut, variance minimisation, Wu's decomposition), exported for renderers and game engines
 * (JSON, glTF 2.0 KHR_lights_punctual as .gltf or .glb, in the frame they show the map in)
 * and drawn on the map (PNG). */
#include "cli.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

static void put(lumis_image *img, int x, int y, const float c[3])
{
    if (x < 0 || y < 0 || x >= img->width || y >= img->height) return;
    float *p = img->pixels + 3 * ((size_t)y * (size_t)img->width + (size_t)x);
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
}

/* What a map pixel shows under the tint: nothing, an emissive pixel of an EnvDirect (Eq. 1's
 * Y > L_T, kept by k-means), or an emissive pixel given back to the EnvIndirects. */
enum { PIC_PLAIN = 0, PIC_RETURNED = 1, PIC_DIRECT = 2 };

static int pixel_class(const lumis_envmap *env, const int32_t *labels, const lumis_light *l,
                       int count, double threshold, int i, int j)
{
    const int32_t a = labels[(size_t)j * (size_t)lumis_envmap_width(env) + (size_t)i];
    if (a < 0 || a >= count) return PIC_PLAIN;
    if (l[a].kind == LUMIS_LIGHT_ENV_DIRECT) return PIC_DIRECT;
    if (l[a].kind != LUMIS_LIGHT_ENV_INDIRECT) return PIC_PLAIN;
    /* Y as the decomposition weighs it (lumis__pixel_y on the scaled texel) */
    const lumis_rgb c = lumis_envmap_texel(env, i, j);
    const float y = (float)(0.2126 * (double)c.r + 0.7152 * (double)c.g + 0.0722 * (double)c.b);
    return (double)y > threshold ? PIC_RETURNED : PIC_PLAIN;
}

/* The picture of Wu's Fig. 4-5, `pw` pixels wide (the map's aspect): the map (box-filtered
 * when smaller, nearest when larger), region borders, emissive pixels tinted, lights marked.
 * A picture pixel takes the strongest class of the map pixels it covers, so that a sun of a
 * few pixels stays visible when the picture is smaller than the map; borders and markers are
 * drawn at the picture's resolution and stay one line wide.  Colours are set relative to the
 * exposure so they show after tone mapping. */
static int write_picture(const char *path, const lumis_envmap *env, const lumis_light_set *set,
                         int pw)
{
    const int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    if (pw <= 0) pw = w;
    int ph = (int)lround((double)pw * h / w);
    if (ph < 1) ph = 1;
    lumis_image *img = NULL;
    unsigned char *cls = malloc((size_t)pw * (size_t)ph);
    int32_t *lab = malloc((size_t)pw * (size_t)ph * sizeof *lab);
    if (!cls || !lab || lumis_image_create(pw, ph, &img) != LUMIS_OK) {
        free(cls);
        free(lab);
        return tool_runtime_error("%s: out of memory", path);
    }
    int lw = 0, lh = 0;
    const int32_t *labels = lumis_light_set_labels(set, &lw, &lh);
    if (!labels || lw != w || lh != h) labels = NULL;
    const lumis_light *l = NULL;
    int count = 0;
    lumis_light_set_get(set, 0, &l, &count);
    const lumis_light_set_info *info = lumis_light_set_get_info(set);
    const double threshold = info->method == LUMIS_LIGHTS_DECOMPOSITION && info->threshold > 0
                                 ? info->threshold
                                 : INFINITY;
    for (int y = 0; y < ph; y++) {
        /* the map pixels [i0, i1) x [j0, j1) under picture pixel (x, y); at least one */
        const int j0 = (int)((long long)y * h / ph), j1e = (int)((long long)(y + 1) * h / ph);
        const int j1 = j1e > j0 ? j1e : j0 + 1;
        for (int x = 0; x < pw; x++) {
            const int i0 = (int)((long long)x * w / pw), i1e = (int)((long long)(x + 1) * w / pw);
            const int i1 = i1e > i0 ? i1e : i0 + 1;
            double s[3] = {0, 0, 0};
            int c = PIC_PLAIN;
            for (int j = j0; j < j1; j++)
                for (int i = i0; i < i1; i++) {
                    const lumis_rgb t = lumis_envmap_texel(env, i, j);
                    s[0] += t.r;
                    s[1] += t.g;
                    s[2] += t.b;
                    if (labels && c < PIC_DIRECT) {
                        const int k = pixel_class(env, labels, l, count, threshold, i, j);
                        c = k > c ? k : c;
                    }
                }
            const double n = (double)(j1 - j0) * (double)(i1 - i0);
            float *p = img->pixels + 3 * ((size_t)y * (size_t)pw + (size_t)x);
            for (int q = 0; q < 3; q++) p[q] = (float)(s[q] / n);
            const size_t o = (size_t)y * (size_t)pw + (size_t)x;
            cls[o] = (unsigned char)c;
            /* the region at the picture pixel's centre */
            const int ci = (int)(((long long)2 * x + 1) * w / (2 * (long long)pw)),
                      cj = (int)(((long long)2 * y + 1) * h / (2 * (long long)ph));
            lab[o] = labels ? labels[(size_t)cj * (size_t)w + (size_t)ci] : -1;
        }
    }
    lumis_write_options wo = {0};
    wo.exposure_ev = tool_auto_exposure(img);
    wo.tonemap = LUMIS_TONEMAP_ACES;
    const float white = 2.0f * exp2f(-wo.exposure_ev);
    if (labels) {
        /* Region borders replace the pixel; the tints keep a trace of it, clamped to display
         * white so that they show on a bright sky. */
        const float orange[3] = {0.5f * white, 0.08f * white, 0.0f},
                    magenta[3] = {0.5f * white, 0.0f, 0.5f * white},
                    cyan[3] = {0.0f, 0.5f * white, 0.9f * white};
        for (int y = 0; y < ph; y++)
            for (int x = 0; x < pw; x++) {
                const size_t o = (size_t)y * (size_t)pw + (size_t)x;
                const int32_t a = lab[o];
                const int32_t right = lab[(size_t)y * (size_t)pw + (size_t)((x + 1) % pw)];
                const int32_t below = y + 1 < ph ? lab[o + (size_t)pw] : a;
                float *p = img->pixels + 3 * o;
                const float *tint = cls[o] == PIC_DIRECT     ? orange
                                    : cls[o] == PIC_RETURNED ? magenta
                                                             : NULL;
                if (a != right || a != below)
                    for (int c = 0; c < 3; c++) p[c] = cyan[c];
                else if (tint)
                    for (int c = 0; c < 3; c++) p[c] = 0.05f * fminf(p[c], 0.5f * white) + tint[c];
            }
    }
    /* Crosses 3 pixels thick from 256 pixels wide, their arms a 256th of the width (>= 3),
     * outlined in black (all outlines first, so that no outline cuts a neighbour's cross). */
    const int arm = pw / 256 > 3 ? pw / 256 : 3, thick = pw >= 256;
    for (int pass = 0; pass < 2; pass++)
        for (int k = 0; k < count; k++) {
            int i = 0, j = 0;
            lumis_envmap_dir_to_pixel(env, l[k].dir, &i, &j);
            const int x = (int)(((long long)2 * i + 1) * pw / (2 * (long long)w)),
                      y = (int)(((long long)2 * j + 1) * ph / (2 * (long long)h));
            const float red[3] = {white, 0, 0}, green[3] = {0, white, 0},
                        grey[3] = {white, white, white}, black[3] = {0, 0, 0};
            const float *c = pass == 0                               ? black
                             : l[k].kind == LUMIS_LIGHT_ENV_DIRECT   ? red
                             : l[k].kind == LUMIS_LIGHT_ENV_INDIRECT ? green
                                                                     : grey;
            const int e = pass == 0, t1 = thick + e;
            for (int d = -arm - e; d <= arm + e; d++)
                for (int t = -t1; t <= t1; t++) {
                    put(img, (x + d + pw) % pw, y + t, c);
                    put(img, (x + t + pw) % pw, y + d, c);
                }
        }
    lumis_status st = tool_write_image(path, img, &wo);
    lumis_image_destroy(img);
    free(cls);
    free(lab);
    return st == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
}

/* The lights' diffuse irradiance against the map's, by the surface normal's elevation: the
 * mean over 8 azimuths of each, and the worst relative error among them. */
static int print_irradiance(const lumis_envmap *env, const lumis_light_set *set)
{
    const double pi = 3.14159265358979323846;
    printf("irradiance (luminance) of a diffuse surface facing elevation e, mean over 8 "
           "azimuths:\n%9s %12s %12s %9s %9s\n",
           "elevation", "map", "lights", "error", "worst");
    double worst_all = 0.0;
    for (int e = -90; e <= 90; e += 15) {
        double ms = 0.0, ls = 0.0, worst = 0.0;
        const int az = e == -90 || e == 90 ? 1 : 8; /* the poles face one way */
        for (int a = 0; a < az; a++) {
            const double el = e * pi / 180.0, phi = 2.0 * pi * a / az;
            const lumis_vec3 n = {(float)(cos(el) * cos(phi)), (float)sin(el),
                                  (float)(cos(el) * sin(phi))};
            double se = 0.0, me = 0.0;
            if (lumis_light_set_irradiance(env, set, n, &se, &me) != LUMIS_OK)
                return tool_runtime_error("lights: --irradiance: out of memory");
            ms += me / az;
            ls += se / az;
            const double err = me > 0.0 ? fabs(se / me - 1.0) : 0.0;
            if (err > worst) worst = err;
        }
        if (worst > worst_all) worst_all = worst;
        printf("%9d %12.6g %12.6g %+8.2f%% %8.2f%%\n", e, ms, ls,
               ms > 0.0 ? 100.0 * (ls / ms - 1.0) : 0.0, 100.0 * worst);
    }
    /* the upper hemisphere's share of the power: the lights above the horizon, and the map's
     * rows above it */
    double p_set = 0.0, p_all = 0.0;
    const lumis_light *l = NULL;
    int count = 0;
    lumis_light_set_get(set, 0, &l, &count);
    for (int q = 0; q < count; q++) {
        const double y = 0.2126 * l[q].power[0] + 0.7152 * l[q].power[1] + 0.0722 * l[q].power[2];
        p_all += y;
        if (l[q].dir.y > 0.0f) p_set += y;
    }
    const int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    double m_up = 0.0, m_all = 0.0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const lumis_rgb c = lumis_envmap_texel(env, i, j);
            const double y = lumis_luminance(c) * lumis_envmap_pixel_solid_angle(env, j);
            m_all += y;
            if (2 * j < h) m_up += y; /* rows above the horizon (row h/2 starts below) */
        }
    printf("worst error %.2f%%; upper hemisphere's share of the power: lights %.1f%%, map "
           "%.1f%%\n",
           100.0 * worst_all, p_all > 0.0 ? 100.0 * p_set / p_all : 0.0,
           m_all > 0.0 ? 100.0 * m_up / m_all : 0.0);
    return EXIT_OK;
}

/* The set as lumis lights prints it: counts, parameters (given), timings, the fold (NULL:
 * none), total power and a table of the lights; exported: directions go to files too. */
static void print_set(const char *map, const char *method, const lumis_light_set *set,
                      const char *given, double read_ms, double setup_ms,
                      const lumis_light_fold *fold, int exported, lumis_export_frame frame)
{
    const lumis_light_set_info *info = lumis_light_set_get_info(set);
    const lumis_light *l = NULL;
    int count = 0;
    lumis_light_set_get(set, 0, &l, &count);
    double total[3] = {0, 0, 0};
    for (int q = 0; q < count; q++)
        for (int c = 0; c < 3; c++) total[c] += l[q].power[c];
    char split[96] = ""; /* Wu's kinds; the other methods make regions only */
    if (info->method == LUMIS_LIGHTS_DECOMPOSITION)
        snprintf(split, sizeof split, " (%d EnvDirects, %d EnvIndirects)", info->direct,
                 info->indirect);
    printf("%s: %d lights by %s%s, %d sets, built in %.2f ms\n", map, count, method, split,
           lumis_light_set_sets(set), info->build_ms);
    if (*given) printf("parameters %s\n", given);
    printf("map read in %.2f ms, set up in %.2f ms\n", read_ms, setup_ms);
    if (fold)
        printf("above ground: %d light%s below the horizon folded into the nearest above, "
               "%.2f %% of the power (RGB %.6g %.6g %.6g)\n",
               fold->folded, fold->folded == 1 ? "" : "s", 100.0 * fold->share, fold->power[0],
               fold->power[1], fold->power[2]);
    if (info->method == LUMIS_LIGHTS_DECOMPOSITION)
        printf("emissive pixels %d (Y > L_T = %.6g), %d given back to the EnvIndirects\n",
               info->emissive_pixels, info->threshold, info->returned_pixels);
    printf("total power (RGB) %.6g %.6g %.6g\n", total[0], total[1], total[2]);
    if (exported)
        printf("directions below in lumis's frame (u = 0 along +x); the files' in the %s frame%s\n",
               lumis_export_frame_name(frame),
               frame == LUMIS_EXPORT_FRAME_ENGINE
                   ? " (-x, y, -z: where three.js and Blender show them)"
                   : "");
    printf("%5s %-13s %9s %9s %9s %12s %12s %12s %10s %9s\n", "light", "kind", "x", "y", "z",
           "power r", "power g", "power b", "sr", "extent");
    for (int q = 0; q < count; q++)
        printf("%5d %-13s %9.5f %9.5f %9.5f %12.6g %12.6g %12.6g %10.4g %9.4f\n", q,
               l[q].kind == LUMIS_LIGHT_ENV_DIRECT     ? "env-direct"
               : l[q].kind == LUMIS_LIGHT_ENV_INDIRECT ? "env-indirect"
                                                       : "region",
               l[q].dir.x, l[q].dir.y, l[q].dir.z, l[q].power[0], l[q].power[1], l[q].power[2],
               l[q].solid_angle, l[q].extent);
}

/* --json, --gltf (with the parameters and the fold recorded) and --png.  Exit code. */
static int export_set(const lumis_envmap *env, const lumis_light_set *set, const char *map,
                      const char *method, const char *given, int above_ground, int masks,
                      lumis_export_frame frame, const char *json, const char *gltf, const char *png,
                      int png_width, const lumis_sun *sun)
{
    lumis_light_export_options eo = {0};
    eo.sun = sun && sun->found ? sun : NULL;
    eo.masks = masks;
    eo.source = map;
    eo.method = method;
    char recorded[1100]; /* the parameters and the fold, in the files */
    snprintf(recorded, sizeof recorded, "%s%s%s", given, *given && above_ground ? "," : "",
             above_ground ? "above-ground" : "");
    eo.parameters = recorded;
    eo.errors = tool_errors;
    eo.frame = frame;
    if ((json && lumis_light_set_write_json(json, set, &eo) != LUMIS_OK) ||
        (gltf && lumis_light_set_write_gltf(gltf, set, &eo) != LUMIS_OK) ||
        (png && write_picture(png, env, set, png_width) != EXIT_OK))
        return EXIT_RUNTIME;
    return EXIT_OK;
}

/* --sun: the map's sun (lumis_sun_find) and the map without it, printed.  Exit code. */
static int split_sun(const lumis_envmap *env, lumis_sun *sun, lumis_envmap **residual)
{
    lumis_sun_desc sd = {0};
    sd.errors = tool_errors;
    if (lumis_sun_find(env, &sd, sun, residual) != LUMIS_OK) return EXIT_RUNTIME;
    if (sun->found)
        printf("sun: dir (%.5f, %.5f, %.5f) in lumis's frame, radius %.4f deg (cone %.4f "
               "deg), power %.6g %.6g %.6g, share %.4f, %d pixels; the lights below are the "
               "rest of the map's\n",
               sun->dir.x, sun->dir.y, sun->dir.z, sun->radius * (180.0 / 3.14159265358979),
               sun->sample_radius * (180.0 / 3.14159265358979), sun->power[0], sun->power[1],
               sun->power[2], sun->share, sun->pixels);
    else
        printf("sun: none found (docs/lights.md, \"The image sun\"): the lights are the whole "
               "map's\n");
    return EXIT_OK;
}

/* What lumis lights reads from its arguments. */
typedef struct lights_cli {
    const char *map, *method, *json, *gltf, *png, *frame_given;
    int k, sets, masks, png_width, irradiance, above_ground, sun;
    lumis_light_params params;
    lumis_export_frame frame;
    double rotation;
} lights_cli;

static int method_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    if (!v || !tool_lights_method_known(v)) {
        char want[256];
        snprintf(want, sizeof want, "must be one of %s", tool_lights_method_names());
        return tool_bad_value(cmd, opt->name, v, want);
    }
    ((lights_cli *)ctx)->method = v;
    return EXIT_OK;
}

static int param_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    return tool_light_params_parse(&((lights_cli *)ctx)->params, cmd, opt->name, v);
}

static int parse_frame(const char *v, void *field)
{
    return lumis_export_frame_from_name(v, field) == LUMIS_OK;
}

static int lights_positional(const char *cmd, const char *arg, void *ctx)
{
    lights_cli *c = ctx;
    if (c->map) return tool_usage_error(cmd, "unknown argument '%s'", arg);
    c->map = arg;
    return EXIT_OK;
}

#define AT(f) offsetof(lights_cli, f)
static const tool_opt lights_opts[] = {
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--method",
     .metavar = "M",
     .help = "median-cut (the default: the lowest error of the light sets in the\n"
             "project's equal-time renders), variance-min, fhis, tmms (a variant;\n"
             "docs/lights.md), wu (Wu's decomposition: EnvDirects on the emissive\n"
             "pixels, EnvIndirects for the rest), wu-is, wu-is-mask,\n"
             "wu-is-kmeans, wu-original-cut",
     .handle = method_option},
    {.kind = TOOL_OPT_INT,
     .name = "-k",
     .metavar = "K",
     .help = "number of lights (default 64)",
     .at = AT(k),
     .lo = 1,
     .hi = 1 << 20},
    {.kind = TOOL_OPT_INT,
     .name = "--sets",
     .metavar = "N",
     .help = "interleaved sets to build (default 8; files hold the original)",
     .at = AT(sets),
     .lo = 1,
     .hi = 64},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--param",
     .metavar = "P",
     .help = "the method's parameters, NAME=VALUE[,NAME=VALUE...] (repeatable):\n"
             "every method: jitter (0.1), seed (0); Wu: percentile (98),\n"
             "lambda (3), gamma (0.001), threshold (L_T instead of Eq. 1), a (1),\n"
             "b (0.25), s (0.15), mask (cap|radians), return (2),\n"
             "kmeans-iterations (until no pixel moves), wv (1), wd (5), we (1),\n"
             "min-share (each class's least share of the lights; docs/lights.md);\n"
             "tmms: key (0.18), bandwidth (0.1).  docs/lights.md says what each is",
     .handle = param_option},
    {.kind = TOOL_OPT_DOUBLE,
     .name = "--rotate",
     .metavar = "DEG",
     .help = "rotate the map about +y first",
     .at = AT(rotation),
     .lo = -1e6,
     .hi = 1e6,
     .what = "degrees"},
    {.kind = TOOL_OPT_FLAG,
     .name = "--above-ground",
     .help = "keep only lights above the horizon (a scene with a ground plane,\n"
             "y = 0): each light below it is folded into the nearest light above,\n"
             "which takes its power (the total is kept; the folded share is\n"
             "printed)",
     .at = AT(above_ground)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--sun",
     .help = "split the map's sun off first (lumis_sun_find: a compact bright\n"
             "source): the lights are the rest of the map's, and the files hold\n"
             "the sun first, a directional light with its angular radius\n"
             "(docs/lights-export.md)",
     .at = AT(sun)},
    {.kind = TOOL_OPT_STRING,
     .name = "--json",
     .metavar = "OUT",
     .help = "directions, power, colour and intensity, solid angle, extent, kind",
     .at = AT(json),
     .what = "a file"},
    {.kind = TOOL_OPT_FLAG,
     .name = "--masks",
     .help = "with --json: each light's region as pixel runs [row, column, length]",
     .at = AT(masks)},
    {.kind = TOOL_OPT_STRING,
     .name = "--gltf",
     .metavar = "OUT",
     .help = "glTF 2.0 with one KHR_lights_punctual directional light per light\n"
             "(three.js, Babylon.js, Blender, game engines); intensity in lux for a\n"
             "map in cd/m^2.  OUT.gltf is text, OUT.glb a binary container",
     .at = AT(gltf),
     .what = "a file"},
    {.kind = TOOL_OPT_PARSE,
     .name = "--frame",
     .metavar = "F",
     .help = "the files' directions: engine (default; each light comes from where\n"
             "three.js, glTF viewers and Blender show its source on the same map,\n"
             "whose centre u = 1/2 they put along +x) or lumis (lumis's own frame,\n"
             "u = 0 along +x).  Recorded in the files; docs/lights-export.md",
     .at = AT(frame),
     .parse = parse_frame,
     .what = "must be engine or lumis",
     .note = TOOL_NOTE(lights_cli, frame_given)},
    {.kind = TOOL_OPT_STRING,
     .name = "--png",
     .metavar = "OUT",
     .help = "the map (auto exposure) with the regions' borders in cyan, the\n"
             "EnvDirects' (emissive) pixels in orange, emissive pixels given back\n"
             "to the EnvIndirects in magenta, and every light marked (red:\n"
             "EnvDirect, green: EnvIndirect, white: a region of the other methods)",
     .at = AT(png),
     .what = "a file"},
    {.kind = TOOL_OPT_INT,
     .name = "--png-width",
     .metavar = "W",
     .help = "the picture's width in pixels, height to the map's aspect (default:\n"
             "the map's); borders and markers are drawn at this size",
     .at = AT(png_width),
     .lo = 16,
     .hi = 16384,
     .what = "pixels"},
    {.kind = TOOL_OPT_FLAG,
     .name = "--irradiance",
     .help = "the diffuse irradiance the lights give a surface facing each\n"
             "elevation (-90 to 90 degrees, 8 azimuths each) against the map's,\n"
             "and the upper hemisphere's share of the power",
     .at = AT(irradiance)},
    {0},
};

const tool_optspec tool_lights_spec = {
    .cmd = "lights",
    .usage = "usage: lumis lights MAP [--method M] [-k K] [--sets N] [--param NAME=VALUE,...]\n"
             "                    [--rotate DEG] [--above-ground] [--sun]\n"
             "                    [--json OUT.json [--masks]] [--gltf OUT.gltf|OUT.glb]\n"
             "                    [--frame engine|lumis]\n"
             "                    [--png OUT.png [--png-width W]] [--irradiance]",
    .intro = "Turns an environment map into K directional lights whose powers add up to the map's\n"
             "(each light: sum over its region of radiance x solid angle, at the region's energy\n"
             "centroid), prints them, and writes them for other tools.  docs/lights.md has every\n"
             "method and unit; which method for which goal: docs/lights.md, \"Which method\".",
    .opts = lights_opts,
    .positional = lights_positional,
};

int cmd_lights(int argc, char **argv)
{
    lights_cli c = {0};
    c.frame = LUMIS_EXPORT_FRAME_ENGINE;
    const int orc = tool_optparse(&tool_lights_spec, argc, argv, &c);
    if (orc >= 0) return orc;
    const char *map = c.map, *method = c.method, *json = c.json, *gltf = c.gltf, *png = c.png;
    const int k = c.k, sets = c.sets, masks = c.masks, png_width = c.png_width,
              irradiance = c.irradiance, above_ground = c.above_ground;
    const int frame_given = c.frame_given != NULL;
    lumis_light_params params = c.params;
    const lumis_export_frame frame = c.frame;
    const double rotation = c.rotation;
    if (!map) return tool_usage_error("lights", "no map given");
    if (!method) method = "median-cut";
    const int prc = tool_light_params_check(&params, "lights", "--param", method);
    if (prc != EXIT_OK) return prc;
    if (masks && !json) return tool_usage_error("lights", "--masks goes with --json OUT");
    if (frame_given && !json && !gltf)
        return tool_usage_error("lights", "--frame goes with --json OUT or --gltf OUT");
    if (png_width && !png) return tool_usage_error("lights", "--png-width goes with --png OUT");
    tool_files files = {0};
    tool_files_input(&files, "map", map);
    tool_files_output(&files, "--json", json, TOOL_OUT_FILE);
    tool_files_output(&files, "--gltf", gltf, TOOL_OUT_GLTF);
    tool_files_output(&files, "--png", png, TOOL_OUT_PNG);
    int rc = tool_files_check("lights", &files);
    if (rc != EXIT_OK) return rc;

    lumis_envmap *env = NULL;
    lumis_light_set *set = NULL;
    /* timed apart: the file's decoding (OpenEXR's, zlib's) and lumis's own set-up */
    lumis_image *img = NULL;
    lumis_read_info rinfo;
    const double t_read = tool_now_seconds();
    if (tool_load_image(map, &img, &rinfo) != LUMIS_OK) return EXIT_RUNTIME;
    const double t_setup = tool_now_seconds();
    const lumis_status est = tool_make_envmap(map, img, (float)rotation, 1.0f, &env, NULL);
    const double t_done = tool_now_seconds();
    lumis_image_destroy(img);
    if (est != LUMIS_OK) return EXIT_RUNTIME;
    rc = EXIT_RUNTIME;
    lumis_sun sun = {0};
    lumis_envmap *residual = NULL;
    if (c.sun && split_sun(env, &sun, &residual) != EXIT_OK) goto done;
    if (lumis_lights_by_name(residual ? residual : env, method, k, sets, &params, &tool_errors,
                             &set) != LUMIS_OK)
        goto done;
    lumis_light_fold fold = {0};
    if (above_ground) {
        const lumis_vec3 up = {0.0f, 1.0f, 0.0f};
        if (lumis_light_set_fold_below(set, up, &tool_errors, &fold) != LUMIS_OK) goto done;
    }
    char given[1024];
    lumis_light_params_format(&params, given, sizeof given);
    print_set(map, method, set, given, 1e3 * (t_setup - t_read), 1e3 * (t_done - t_setup),
              above_ground ? &fold : NULL, json || gltf, frame);
    if (irradiance && print_irradiance(residual ? residual : env, set) != EXIT_OK) goto done;
    if (export_set(residual ? residual : env, set, map, method, given, above_ground, masks, frame,
                   json, gltf, png, png_width, &sun) != EXIT_OK)
        goto done;
    rc = fflush(stdout) == 0 ? EXIT_OK : tool_runtime_error("write error on stdout");
done:
    lumis_envmap_destroy(residual);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
    return rc;
}
