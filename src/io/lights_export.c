/* Light sets as files: a JSON description, and glTF 2.0 with KHR_lights_punctual directional
 * lights, which three.js, Babylon.js, Blender and game engines load.  Units: docs/lights.md
 * ("Export"). */
#include "internal.h"

#include "../core/internal.h"
#include "lumis/io.h"
#include "lumis/lights.h"
#include "lumis/version.h"

#include <cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *kind_name(lumis_light_kind k)
{
    return k == LUMIS_LIGHT_ENV_DIRECT     ? "env_direct"
           : k == LUMIS_LIGHT_ENV_INDIRECT ? "env_indirect"
                                           : "region";
}

/* colour * intensity == power per channel, colour's largest channel 1 (black: 0, 0). */
static void colour_intensity(const lumis_light *l, double c[3], double *intensity)
{
    double m = fmax(l->power[0], fmax(l->power[1], l->power[2]));
    *intensity = m > 0.0 ? m : 0.0;
    for (int k = 0; k < 3; k++) c[k] = m > 0.0 ? l->power[k] / m : 0.0;
}

/* The unit quaternion (x, y, z, w) turning -Z, a glTF light's direction of travel, into
 * -dir (the light shines from dir): the shortest arc from -Z to -dir. */
void lumis__light_quaternion(lumis_vec3 dir, double q[4])
{
    double n = sqrt((double)dir.x * dir.x + (double)dir.y * dir.y + (double)dir.z * dir.z);
    double tx = -dir.x / n, ty = -dir.y / n, tz = -dir.z / n; /* travel */
    /* a = (0, 0, -1); q = (a x t, 1 + a . t), normalized. */
    double cx = ty, cy = -tx, cz = 0.0, w = 1.0 - tz;
    double len = sqrt(cx * cx + cy * cy + cz * cz + w * w);
    if (len < 1e-12) { /* t == +Z: half a turn about Y */
        q[0] = 0.0;
        q[1] = 1.0;
        q[2] = 0.0;
        q[3] = 0.0;
        return;
    }
    q[0] = cx / len;
    q[1] = cy / len;
    q[2] = cz / len;
    q[3] = w / len;
}

static lumis_status write_json(const char *path, cJSON *root, const lumis_error_sink *errors)
{
    char *text = root ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text) return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    size_t n = strlen(text);
    char *line = malloc(n + 2);
    if (!line) {
        cJSON_free(text);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    memcpy(line, text, n);
    line[n++] = '\n';
    line[n] = '\0';
    cJSON_free(text);
    lumis_status st = lumis_write_text(path, line, n, errors);
    free(line);
    return st;
}

/* What both writers start from: the options' sink and the chosen set's lights. */
typedef struct export_args {
    const lumis_error_sink *errors;
    int index, count;
    const lumis_light *lights;
} export_args;

static lumis_status begin(const char *path, const lumis_light_set *set,
                          const lumis_light_export_options *options, export_args *a)
{
    a->errors = options ? &options->errors : NULL;
    a->index = options ? options->set_index : 0;
    a->lights = NULL;
    a->count = 0;
    if (!path || !set)
        return lumis__fail(a->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "light export: needs a path and a set");
    if (lumis_light_set_get(set, a->index, &a->lights, &a->count) != LUMIS_OK)
        return lumis__fail(a->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: the set has no light set %d (it holds %d)", path, a->index,
                           lumis_light_set_sets(set));
    return LUMIS_OK;
}

lumis_status lumis_light_set_write_json(const char *path, const lumis_light_set *set,
                                        const lumis_light_export_options *options)
{
    export_args a;
    lumis_status st = begin(path, set, options, &a);
    if (st != LUMIS_OK) return st;
    const lumis_error_sink *errors = a.errors;
    const lumis_light *l = a.lights;
    const int count = a.count, index = a.index;
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "generator", "lumis " LUMIS_VERSION_STRING);
    cJSON_AddStringToObject(root, "coordinates",
                            "right-handed, y up; dir points from the scene towards the light");
    cJSON_AddStringToObject(root, "units",
                            "power: sum over the region of radiance x solid angle (the map's "
                            "radiance units x sr); colour x intensity == power");
    if (options && options->source) cJSON_AddStringToObject(root, "source", options->source);
    if (options && options->method) cJSON_AddStringToObject(root, "method", options->method);
    if (options && options->parameters && *options->parameters)
        cJSON_AddStringToObject(root, "parameters", options->parameters);
    cJSON_AddNumberToObject(root, "set", index);
    cJSON_AddNumberToObject(root, "sets", lumis_light_set_sets(set));
    int w = 0, h = 0;
    const int32_t *labels = lumis_light_set_labels(set, &w, &h);
    cJSON_AddNumberToObject(root, "map_width", w);
    cJSON_AddNumberToObject(root, "map_height", h);
    cJSON *arr = cJSON_AddArrayToObject(root, "lights");
    for (int k = 0; k < count && arr; k++) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddItemToArray(arr, o);
        const double d[3] = {l[k].dir.x, l[k].dir.y, l[k].dir.z};
        double c[3], intensity;
        colour_intensity(&l[k], c, &intensity);
        cJSON_AddItemToObject(o, "dir", cJSON_CreateDoubleArray(d, 3));
        cJSON_AddItemToObject(o, "power", cJSON_CreateDoubleArray(l[k].power, 3));
        cJSON_AddItemToObject(o, "color", cJSON_CreateDoubleArray(c, 3));
        cJSON_AddNumberToObject(o, "intensity", intensity);
        cJSON_AddNumberToObject(o, "solid_angle", l[k].solid_angle);
        cJSON_AddNumberToObject(o, "extent_rad", l[k].extent);
        cJSON_AddNumberToObject(o, "pixels", l[k].pixels);
        cJSON_AddStringToObject(o, "kind", kind_name(l[k].kind));
        if (options && options->masks && labels) {
            /* The region as runs [row, first column, length] of its pixels. */
            cJSON *runs = cJSON_AddArrayToObject(o, "region_runs");
            for (int j = 0; j < h && runs; j++)
                for (int i = 0; i < w;) {
                    if (labels[(size_t)j * (size_t)w + (size_t)i] != k) {
                        i++;
                        continue;
                    }
                    int i0 = i;
                    while (i < w && labels[(size_t)j * (size_t)w + (size_t)i] == k) i++;
                    const int run[3] = {j, i0, i - i0};
                    cJSON_AddItemToArray(runs, cJSON_CreateIntArray(run, 3));
                }
        }
    }
    return write_json(path, root, errors);
}

lumis_status lumis_light_set_write_gltf(const char *path, const lumis_light_set *set,
                                        const lumis_light_export_options *options)
{
    export_args a;
    lumis_status st = begin(path, set, options, &a);
    if (st != LUMIS_OK) return st;
    const lumis_error_sink *errors = a.errors;
    const lumis_light *l = a.lights;
    const int count = a.count;
    cJSON *root = cJSON_CreateObject();
    cJSON *asset = cJSON_AddObjectToObject(root, "asset");
    cJSON_AddStringToObject(asset, "version", "2.0");
    cJSON_AddStringToObject(asset, "generator", "lumis " LUMIS_VERSION_STRING);
    cJSON *used = cJSON_AddArrayToObject(root, "extensionsUsed");
    cJSON_AddItemToArray(used, cJSON_CreateString("KHR_lights_punctual"));
    cJSON *ext = cJSON_AddObjectToObject(root, "extensions");
    cJSON *khr = cJSON_AddObjectToObject(ext, "KHR_lights_punctual");
    cJSON *lights = cJSON_AddArrayToObject(khr, "lights");
    cJSON_AddNumberToObject(root, "scene", 0);
    cJSON *scenes = cJSON_AddArrayToObject(root, "scenes");
    cJSON *scene = cJSON_CreateObject();
    cJSON_AddItemToArray(scenes, scene);
    cJSON_AddStringToObject(scene, "name", options && options->method ? options->method : "lights");
    if (options && options->parameters && *options->parameters)
        cJSON_AddStringToObject(cJSON_AddObjectToObject(scene, "extras"), "parameters",
                                options->parameters);
    cJSON *scene_nodes = cJSON_AddArrayToObject(scene, "nodes");
    cJSON *nodes = cJSON_AddArrayToObject(root, "nodes");
    for (int k = 0; k < count; k++) {
        char name[64];
        snprintf(name, sizeof name, "%s %d", kind_name(l[k].kind), k);
        double c[3], intensity, q[4];
        colour_intensity(&l[k], c, &intensity);
        cJSON *li = cJSON_CreateObject();
        cJSON_AddItemToArray(lights, li);
        cJSON_AddStringToObject(li, "name", name);
        cJSON_AddStringToObject(li, "type", "directional");
        cJSON_AddItemToObject(li, "color", cJSON_CreateDoubleArray(c, 3));
        cJSON_AddNumberToObject(li, "intensity", intensity);
        lumis__light_quaternion(l[k].dir, q);
        cJSON *node = cJSON_CreateObject();
        cJSON_AddItemToArray(nodes, node);
        cJSON_AddStringToObject(node, "name", name);
        cJSON_AddItemToObject(node, "rotation", cJSON_CreateDoubleArray(q, 4));
        cJSON *ne = cJSON_AddObjectToObject(node, "extensions");
        cJSON *nk = cJSON_AddObjectToObject(ne, "KHR_lights_punctual");
        cJSON_AddNumberToObject(nk, "light", k);
        cJSON_AddItemToArray(scene_nodes, cJSON_CreateNumber(k));
    }
    return write_json(path, root, errors);
}
