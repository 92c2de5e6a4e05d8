/* lumis lights MAP --method M [-k K] ...: an environment map as K directional lights (median
 * cut, variance minimisation, Wu's decomposition), exported for renderers and game engines
 * (JSON, glTF 2.0 KHR_lights_punctual) and drawn on the map (PNG). */
#include "common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: lumis lights MAP --method M [-k K] [--sets N] [--rotate DEG]\n"
    "                    [--json OUT.json [--masks]] [--gltf OUT.gltf] [--png OUT.png]\n\n"
    "Turns an environment map into K directional lights whose powers add up to the map's\n"
    "(each light: sum over its region of radiance x solid angle, at the region's energy\n"
    "centroid), prints them, and writes them for other tools.  docs/lights.md has every\n"
    "method and unit.\n\n"
    "options:\n"
    "  --method M      median-cut, variance-min, fhis, tmms (simplified; docs/lights.md),\n"
    "                  wu (Wu's decomposition: EnvDirects on the emissive pixels,\n"
    "                  EnvIndirects for the rest), wu-is, wu-is-mask,\n"
    "                  wu-is-kmeans, wu-original-cut (required)\n"
    "  -k K            number of lights (default 64)\n"
    "  --sets N        interleaved sets to build (default 8; files hold the original)\n"
    "  --rotate DEG    rotate the map about +y first\n"
    "  --json OUT      directions, power, colour and intensity, solid angle, extent, kind\n"
    "  --masks         with --json: each light's region as pixel runs [row, column, length]\n"
    "  --gltf OUT      glTF 2.0 with one KHR_lights_punctual directional light per light\n"
    "                  (three.js, Babylon.js, Blender, game engines); intensity in lux for a\n"
    "                  map in cd/m^2\n"
    "  --png OUT       the map (auto exposure) with the regions' borders in cyan, the\n"
    "                  EnvDirects' (emissive) pixels in orange and every light marked (red:\n"
    "                  EnvDirect, green: EnvIndirect, white: a median-cut or variance-min\n"
    "                  region)\n";

static void put(lumis_image *img, int x, int y, const float c[3])
{
    if (x < 0 || y < 0 || x >= img->width || y >= img->height) return;
    float *p = img->pixels + 3 * ((size_t)y * (size_t)img->width + (size_t)x);
    p[0] = c[0];
    p[1] = c[1];
    p[2] = c[2];
}

/* The picture of Wu's Fig. 4-5: the map, region borders, EnvDirect pixels tinted, lights
 * marked.  Colours are set relative to the exposure so they show after tone mapping. */
static int write_picture(const char *path, const lumis_envmap *env, const lumis_light_set *set)
{
    const int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    lumis_image *img = NULL;
    if (lumis_image_create(w, h, &img) != LUMIS_OK)
        return tool_runtime_error("%s: out of memory", path);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            lumis_rgb c = lumis_envmap_texel(env, i, j);
            float *p = img->pixels + 3 * ((size_t)j * (size_t)w + (size_t)i);
            p[0] = c.r;
            p[1] = c.g;
            p[2] = c.b;
        }
    lumis_write_options wo = {0};
    wo.exposure_ev = tool_auto_exposure(img);
    wo.tonemap = LUMIS_TONEMAP_ACES;
    const float white = 2.0f * exp2f(-wo.exposure_ev);
    int lw = 0, lh = 0;
    const int32_t *labels = lumis_light_set_labels(set, &lw, &lh);
    const lumis_light *l = NULL;
    int count = 0;
    lumis_light_set_get(set, 0, &l, &count);
    if (labels && lw == w && lh == h) {
        /* Blends with the pixel clamped to display white, so they show on a bright sky. */
        const float orange[3] = {0.6f * white, 0.12f * white, 0.0f},
                    cyan[3] = {0.0f, 0.35f * white, 0.6f * white};
        for (int j = 0; j < h; j++)
            for (int i = 0; i < w; i++) {
                const int32_t a = labels[(size_t)j * (size_t)w + (size_t)i];
                float *p = img->pixels + 3 * ((size_t)j * (size_t)w + (size_t)i);
                const int right = labels[(size_t)j * (size_t)w + (size_t)((i + 1) % w)];
                const int below = j + 1 < h ? labels[(size_t)(j + 1) * (size_t)w + (size_t)i] : a;
                const float *tint = a != right || a != below ? cyan
                                    : a >= 0 && a < count && l[a].kind == LUMIS_LIGHT_ENV_DIRECT
                                        ? orange
                                        : NULL;
                if (tint)
                    for (int c = 0; c < 3; c++) p[c] = 0.15f * fminf(p[c], 0.5f * white) + tint[c];
            }
    }
    const int arm = w >= 512 ? w / 256 : 2;
    for (int k = 0; k < count; k++) {
        int i = 0, j = 0;
        lumis_envmap_dir_to_pixel(env, l[k].dir, &i, &j);
        const float red[3] = {white, 0, 0}, green[3] = {0, white, 0},
                    grey[3] = {white, white, white};
        const float *c = l[k].kind == LUMIS_LIGHT_ENV_DIRECT     ? red
                         : l[k].kind == LUMIS_LIGHT_ENV_INDIRECT ? green
                                                                 : grey;
        for (int d = -arm; d <= arm; d++)
            for (int t = -1; t <= 1; t++) {
                put(img, (i + d + w) % w, j + t * (arm > 2), c);
                put(img, (i + t * (arm > 2) + w) % w, j + d, c);
            }
    }
    lumis_status st = tool_write_image(path, img, &wo);
    lumis_image_destroy(img);
    return st == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
}

int cmd_lights(int argc, char **argv)
{
    const char *map = NULL, *method = NULL, *json = NULL, *gltf = NULL, *png = NULL, *v;
    int k = 0, sets = 0, masks = 0;
    double rotation = 0.0;
    for (int i = 1; i < argc; i++) {
        long x;
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--method", &v)) {
            if (!v || !tool_lights_method_known(v)) {
                char want[256];
                snprintf(want, sizeof want, "must be one of %s", tool_lights_method_names());
                return tool_bad_value("lights", "--method", v, want);
            }
            method = v;
        } else if (tool_option(argc, argv, &i, "-k", &v)) {
            if (!tool_parse_int(v, 1, 1 << 20, &x))
                return tool_bad_value("lights", "-k", v, "needs a count in [1, 2^20]");
            k = (int)x;
        } else if (tool_option(argc, argv, &i, "--sets", &v)) {
            if (!tool_parse_int(v, 1, 64, &x))
                return tool_bad_value("lights", "--sets", v, "needs a count in [1, 64]");
            sets = (int)x;
        } else if (tool_option(argc, argv, &i, "--rotate", &v)) {
            if (!tool_parse_double(v, &rotation) || !isfinite(rotation))
                return tool_bad_value("lights", "--rotate", v, "needs degrees");
        } else if (tool_option(argc, argv, &i, "--json", &v)) {
            json = v;
        } else if (tool_option(argc, argv, &i, "--gltf", &v)) {
            gltf = v;
        } else if (tool_option(argc, argv, &i, "--png", &v)) {
            png = v;
        } else if (strcmp(argv[i], "--masks") == 0) {
            masks = 1;
        } else if (argv[i][0] != '-' && !map) {
            map = argv[i];
        } else {
            return tool_usage_error("lights", "unknown argument '%s'", argv[i]);
        }
    }
    if (!map) return tool_usage_error("lights", "no map given");
    if (!method) return tool_usage_error("lights", "--method M is required");
    if (masks && !json) return tool_usage_error("lights", "--masks goes with --json OUT");
    tool_files files = {0};
    tool_files_input(&files, "map", map);
    tool_files_output(&files, "--json", json, TOOL_OUT_FILE);
    tool_files_output(&files, "--gltf", gltf, TOOL_OUT_FILE);
    tool_files_output(&files, "--png", png, TOOL_OUT_PNG);
    int rc = tool_files_check("lights", &files);
    if (rc != EXIT_OK) return rc;

    lumis_envmap *env = NULL;
    lumis_light_set *set = NULL;
    if (tool_make_envmap(map, NULL, (float)rotation, 1.0f, &env) != LUMIS_OK) return EXIT_RUNTIME;
    rc = EXIT_RUNTIME;
    if (tool_make_light_set(env, method, k, sets, &set) != LUMIS_OK) goto done;
    const lumis_light_set_info *info = lumis_light_set_get_info(set);
    const lumis_light *l = NULL;
    int count = 0;
    lumis_light_set_get(set, 0, &l, &count);
    double total[3] = {0, 0, 0};
    for (int q = 0; q < count; q++)
        for (int c = 0; c < 3; c++) total[c] += l[q].power[c];
    printf("%s: %d lights by %s (%d EnvDirects, %d EnvIndirects), %d sets, built in %.2f ms\n", map,
           count, method, info->direct, info->indirect, lumis_light_set_sets(set), info->build_ms);
    printf("total power (RGB) %.6g %.6g %.6g\n", total[0], total[1], total[2]);
    printf("%5s %-13s %9s %9s %9s %12s %12s %12s %10s %9s\n", "light", "kind", "x", "y", "z",
           "power r", "power g", "power b", "sr", "extent");
    for (int q = 0; q < count; q++)
        printf("%5d %-13s %9.5f %9.5f %9.5f %12.6g %12.6g %12.6g %10.4g %9.4f\n", q,
               l[q].kind == LUMIS_LIGHT_ENV_DIRECT     ? "env-direct"
               : l[q].kind == LUMIS_LIGHT_ENV_INDIRECT ? "env-indirect"
                                                       : "region",
               l[q].dir.x, l[q].dir.y, l[q].dir.z, l[q].power[0], l[q].power[1], l[q].power[2],
               l[q].solid_angle, l[q].extent);
    lumis_light_export_options eo = {0};
    eo.masks = masks;
    eo.source = map;
    eo.method = method;
    eo.errors = tool_errors;
    if ((json && lumis_light_set_write_json(json, set, &eo) != LUMIS_OK) ||
        (gltf && lumis_light_set_write_gltf(gltf, set, &eo) != LUMIS_OK) ||
        (png && write_picture(png, env, set) != EXIT_OK))
        goto done;
    rc = fflush(stdout) == 0 ? EXIT_OK : tool_runtime_error("write error on stdout");
done:
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
    return rc;
}
