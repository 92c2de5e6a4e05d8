/* Light sets as files: a JSON description, and glTF 2.0 (text or binary) with
 * KHR_lights_punctual directional lights, which three.js, Babylon.js, Blender and game engines
 * load, in the frame those show the map in.  Units and frames: docs/lights-export.md. */
#include "internal.h"

#include "../core/internal.h"
#include "lumis/io.h"
#include "lumis/lights.h"
#include "lumis/sun.h"
#include "lumis/version.h"

#include <cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *kind_name(lumis_light_kind k)
{
    return k == LUMIS_LIGHT_ENV_DIRECT     ? "env_direct"
           : k == LUMIS_LIGHT_ENV_INDIRECT ? "env_indirect"
                                           : "region";
}

static const char *const frame_names[] = {"engine", "lumis"};

LUMIS__ENUM_NAMES(lumis_export_frame, LUMIS_EXPORT_FRAME_COUNT, frame_names,
                  lumis_export_frame_name, lumis_export_frame_from_name);

/* lumis sees column u along azimuth 2 pi u from +x; three.js (equirectUv: u = atan2(z, x) /
 * 2 pi + 1/2) and Blender through its glTF importer see it along 2 pi u - pi: half a turn
 * about +y, which keeps y and negates x and z (docs/lights-export.md, "Frames"). */
lumis_vec3 lumis_export_frame_dir(lumis_export_frame frame, lumis_vec3 dir)
{
    if (frame == LUMIS_EXPORT_FRAME_ENGINE) {
        dir.x = -dir.x;
        dir.z = -dir.z;
    }
    return dir;
}

/* cJSON's builders return NULL (or false) when an allocation fails and leave the document
 * without that part: each result goes through these, which clear *ok then, so that a
 * document with a hole is never written (out of memory instead). */
static cJSON *need(int *ok, cJSON *x)
{
    if (!x) *ok = 0;
    return x;
}

/* Adds item (NULL: a failed create) to object o under key, or to array o (key NULL);
 * deletes it when it cannot be added. */
static cJSON *add_item(int *ok, cJSON *o, const char *key, cJSON *item)
{
    const int added =
        item && o && (key ? cJSON_AddItemToObject(o, key, item) : cJSON_AddItemToArray(o, item));
    if (!added) {
        cJSON_Delete(item);
        *ok = 0;
        return NULL;
    }
    return item;
}

/* What a file says of its frame: the name, and how a map pixel maps to a direction. */
static void add_frame(int *ok, cJSON *o, lumis_export_frame frame)
{
    need(ok, cJSON_AddStringToObject(o, "frame", lumis_export_frame_name(frame)));
    need(
        ok,
        cJSON_AddStringToObject(
            o, "frame_equirect",
            frame == LUMIS_EXPORT_FRAME_ENGINE
                ? "right-handed, y up; the light of map pixel (u, v) in [0,1)^2 (v = 0 the top "
                  "row) "
                  "comes from (sin t cos p, cos t, sin t sin p), p = 2 pi (u - 1/2), t = pi v: "
                  "u = 1/2 along +x, where three.js (equirectUv) and Blender (its glTF importer) "
                  "show it"
                : "right-handed, y up; the light of map pixel (u, v) in [0,1)^2 (v = 0 the top "
                  "row) "
                  "comes from (sin t cos p, cos t, sin t sin p), p = 2 pi u, t = pi v: u = 0 along "
                  "+x (lumis's own frame; three.js and Blender show u = 1/2 there)"));
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

static void put_u32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v & 0xffu);
    p[1] = (unsigned char)((v >> 8) & 0xffu);
    p[2] = (unsigned char)((v >> 16) & 0xffu);
    p[3] = (unsigned char)(v >> 24);
}

/* Writes the document as text (a final newline added) or, binary, as a glTF container
 * (glTF 2.0, "GLB File Format Specification"): a 12-byte header (magic "glTF", version 2,
 * the total length), then one chunk (its length, type "JSON", the text padded with spaces
 * to a multiple of 4 bytes), little-endian.  There is no BIN chunk: the lights hold no
 * buffer. */
static lumis_status write_json(const char *path, cJSON *root, int ok, int binary,
                               const lumis_error_sink *errors)
{
    char *text = root && ok ? (binary ? cJSON_PrintUnformatted(root) : cJSON_Print(root)) : NULL;
    cJSON_Delete(root);
    if (!text) return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    const size_t n = strlen(text);
    const size_t padded = (n + 3) & ~(size_t)3, head = binary ? 20 : 0;
    if (binary && padded + head > UINT32_MAX) {
        cJSON_free(text);
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: too large for a binary glTF (%zu bytes)", path, n);
    }
    const size_t size = binary ? head + padded : n + 1;
    unsigned char *bytes = malloc(size + 1);
    if (!bytes) {
        cJSON_free(text);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    if (binary) {
        memcpy(bytes, "glTF", 4);
        put_u32(bytes + 4, 2);
        put_u32(bytes + 8, (uint32_t)size);
        put_u32(bytes + 12, (uint32_t)padded);
        memcpy(bytes + 16, "JSON", 4);
        memcpy(bytes + head, text, n);
        memset(bytes + head + n, ' ', padded - n);
    } else {
        memcpy(bytes, text, n);
        bytes[n] = '\n';
    }
    bytes[size] = '\0';
    cJSON_free(text);
    lumis_status st = lumis_write_text(path, (const char *)bytes, size, errors);
    free(bytes);
    return st;
}

/* Case-insensitive: does path end in ext (".glb")? */
static int has_extension(const char *path, const char *ext)
{
    const size_t n = strlen(path), m = strlen(ext);
    if (n <= m || path[n - m - 1] == '/') return 0;
    for (size_t k = 0; k < m; k++) {
        char c = path[n - m + k];
        if (c >= 'A' && c <= 'Z') c = (char)(c - 'A' + 'a');
        if (c != ext[k]) return 0;
    }
    return 1;
}

/* What both writers start from: the options' sink and the chosen set's lights. */
typedef struct export_args {
    const lumis_error_sink *errors;
    int index, count;
    const lumis_light *lights;
    lumis_export_frame frame;
    const lumis_sun *sun;  /* found, or NULL */
    lumis_light sun_light; /* the sun as a directional light (extent: its sampled cone) */
} export_args;

/* The sun as a light: its direction, power, solid angle, the cone that holds its pixels. */
static lumis_light sun_as_light(const lumis_sun *sun)
{
    lumis_light l;
    memset(&l, 0, sizeof l);
    l.dir = sun->dir;
    l.extent = (float)sun->sample_radius;
    for (int c = 0; c < 3; c++) l.power[c] = sun->power[c];
    l.solid_angle = sun->solid_angle;
    l.pixels = sun->pixels;
    return l;
}

static lumis_status begin(const char *path, const lumis_light_set *set,
                          const lumis_light_export_options *options, export_args *a)
{
    a->errors = options ? &options->errors : NULL;
    a->index = options ? options->set_index : 0;
    a->lights = NULL;
    a->count = 0;
    a->frame = options ? options->frame : LUMIS_EXPORT_FRAME_ENGINE;
    a->sun = options ? options->sun : NULL;
    if (a->sun && !a->sun->found)
        return lumis__fail(a->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: sun: no sun (found 0): leave it NULL",
                           path ? path : "light export");
    if (a->sun) a->sun_light = sun_as_light(a->sun);
    if (!path || !set)
        return lumis__fail(a->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "light export: needs a path and a set");
    if ((unsigned)a->frame >= LUMIS_EXPORT_FRAME_COUNT)
        return lumis__fail(a->errors, LUMIS_ERR_INVALID_ARGUMENT, "%s: unknown frame %d", path,
                           (int)a->frame);
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
    int ok = 1;
    cJSON *root = need(&ok, cJSON_CreateObject());
    need(&ok, cJSON_AddStringToObject(root, "generator", "lumis " LUMIS_VERSION_STRING));
    need(&ok, cJSON_AddStringToObject(root, "coordinates",
                                      "right-handed, y up; dir points from the scene towards the "
                                      "light, in the frame below"));
    add_frame(&ok, root, a.frame);
    need(&ok, cJSON_AddStringToObject(root, "units",
                                      "power: sum over the region of radiance x solid angle (the "
                                      "map's radiance units x sr); colour x intensity == power"));
    if (options && options->source)
        need(&ok, cJSON_AddStringToObject(root, "source", options->source));
    if (options && options->method)
        need(&ok, cJSON_AddStringToObject(root, "method", options->method));
    if (options && options->parameters && *options->parameters)
        need(&ok, cJSON_AddStringToObject(root, "parameters", options->parameters));
    need(&ok, cJSON_AddNumberToObject(root, "set", index));
    need(&ok, cJSON_AddNumberToObject(root, "sets", lumis_light_set_sets(set)));
    int w = 0, h = 0;
    const int32_t *labels = lumis_light_set_labels(set, &w, &h);
    need(&ok, cJSON_AddNumberToObject(root, "map_width", w));
    need(&ok, cJSON_AddNumberToObject(root, "map_height", h));
    cJSON *arr = need(&ok, cJSON_AddArrayToObject(root, "lights"));
    if (a.sun) {
        need(&ok, cJSON_AddNumberToObject(root, "sun_index", 0));
        cJSON *o = add_item(&ok, arr, NULL, cJSON_CreateObject());
        const lumis_vec3 f = lumis_export_frame_dir(a.frame, a.sun_light.dir);
        const double d[3] = {f.x, f.y, f.z};
        double c[3], intensity;
        colour_intensity(&a.sun_light, c, &intensity);
        add_item(&ok, o, "dir", cJSON_CreateDoubleArray(d, 3));
        add_item(&ok, o, "power", cJSON_CreateDoubleArray(a.sun_light.power, 3));
        add_item(&ok, o, "color", cJSON_CreateDoubleArray(c, 3));
        need(&ok, cJSON_AddNumberToObject(o, "intensity", intensity));
        need(&ok, cJSON_AddNumberToObject(o, "solid_angle", a.sun_light.solid_angle));
        need(&ok, cJSON_AddNumberToObject(o, "extent_rad", a.sun->sample_radius));
        need(&ok, cJSON_AddNumberToObject(o, "angular_radius_rad", a.sun->radius));
        need(&ok, cJSON_AddNumberToObject(o, "share", a.sun->share));
        need(&ok, cJSON_AddNumberToObject(o, "pixels", a.sun_light.pixels));
        need(&ok, cJSON_AddStringToObject(o, "kind", "sun"));
    }
    for (int k = 0; k < count && ok; k++) {
        cJSON *o = add_item(&ok, arr, NULL, cJSON_CreateObject());
        const lumis_vec3 f = lumis_export_frame_dir(a.frame, l[k].dir);
        const double d[3] = {f.x, f.y, f.z};
        double c[3], intensity;
        colour_intensity(&l[k], c, &intensity);
        add_item(&ok, o, "dir", cJSON_CreateDoubleArray(d, 3));
        add_item(&ok, o, "power", cJSON_CreateDoubleArray(l[k].power, 3));
        add_item(&ok, o, "color", cJSON_CreateDoubleArray(c, 3));
        need(&ok, cJSON_AddNumberToObject(o, "intensity", intensity));
        need(&ok, cJSON_AddNumberToObject(o, "solid_angle", l[k].solid_angle));
        need(&ok, cJSON_AddNumberToObject(o, "extent_rad", l[k].extent));
        need(&ok, cJSON_AddNumberToObject(o, "pixels", l[k].pixels));
        need(&ok, cJSON_AddStringToObject(o, "kind", kind_name(l[k].kind)));
        if (options && options->masks && labels) {
            /* The region as runs [row, first column, length] of its pixels. */
            cJSON *runs = need(&ok, cJSON_AddArrayToObject(o, "region_runs"));
            for (int j = 0; j < h && ok; j++)
                for (int i = 0; i < w;) {
                    if (labels[(size_t)j * (size_t)w + (size_t)i] != k) {
                        i++;
                        continue;
                    }
                    int i0 = i;
                    while (i < w && labels[(size_t)j * (size_t)w + (size_t)i] == k) i++;
                    const int run[3] = {j, i0, i - i0};
                    add_item(&ok, runs, NULL, cJSON_CreateIntArray(run, 3));
                }
        }
    }
    return write_json(path, root, ok, 0, errors);
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
    lumis_gltf_container container = options ? options->container : LUMIS_GLTF_AUTO;
    if (container == LUMIS_GLTF_AUTO)
        container = has_extension(path, ".glb")    ? LUMIS_GLTF_BINARY
                    : has_extension(path, ".gltf") ? LUMIS_GLTF_TEXT
                                                   : LUMIS_GLTF_AUTO;
    if (container != LUMIS_GLTF_TEXT && container != LUMIS_GLTF_BINARY)
        return lumis__fail(errors, LUMIS_ERR_UNKNOWN_FORMAT,
                           "%s: unknown glTF container (name it .gltf for text, .glb for "
                           "binary)",
                           path);
    int ok = 1;
    cJSON *root = need(&ok, cJSON_CreateObject());
    cJSON *asset = need(&ok, cJSON_AddObjectToObject(root, "asset"));
    need(&ok, cJSON_AddStringToObject(asset, "version", "2.0"));
    need(&ok, cJSON_AddStringToObject(asset, "generator", "lumis " LUMIS_VERSION_STRING));
    add_frame(&ok, need(&ok, cJSON_AddObjectToObject(asset, "extras")), a.frame);
    cJSON *used = need(&ok, cJSON_AddArrayToObject(root, "extensionsUsed"));
    add_item(&ok, used, NULL, cJSON_CreateString("KHR_lights_punctual"));
    cJSON *ext = need(&ok, cJSON_AddObjectToObject(root, "extensions"));
    cJSON *khr = need(&ok, cJSON_AddObjectToObject(ext, "KHR_lights_punctual"));
    cJSON *lights = need(&ok, cJSON_AddArrayToObject(khr, "lights"));
    need(&ok, cJSON_AddNumberToObject(root, "scene", 0));
    cJSON *scenes = need(&ok, cJSON_AddArrayToObject(root, "scenes"));
    cJSON *scene = add_item(&ok, scenes, NULL, cJSON_CreateObject());
    need(&ok, cJSON_AddStringToObject(scene, "name",
                                      options && options->method ? options->method : "lights"));
    if (options && options->parameters && *options->parameters)
        need(&ok, cJSON_AddStringToObject(need(&ok, cJSON_AddObjectToObject(scene, "extras")),
                                          "parameters", options->parameters));
    cJSON *scene_nodes = need(&ok, cJSON_AddArrayToObject(scene, "nodes"));
    cJSON *nodes = need(&ok, cJSON_AddArrayToObject(root, "nodes"));
    const int first = a.sun ? -1 : 0;
    for (int k = first; k < count && ok; k++) {
        const lumis_light *lk = k < 0 ? &a.sun_light : &l[k];
        const int at = k - first; /* the light's and its node's index */
        char name[64];
        if (k < 0)
            snprintf(name, sizeof name, "sun");
        else
            snprintf(name, sizeof name, "%s %d", kind_name(l[k].kind), k);
        double c[3], intensity, q[4];
        colour_intensity(lk, c, &intensity);
        cJSON *li = add_item(&ok, lights, NULL, cJSON_CreateObject());
        need(&ok, cJSON_AddStringToObject(li, "name", name));
        need(&ok, cJSON_AddStringToObject(li, "type", "directional"));
        add_item(&ok, li, "color", cJSON_CreateDoubleArray(c, 3));
        need(&ok, cJSON_AddNumberToObject(li, "intensity", intensity));
        lumis__light_quaternion(lumis_export_frame_dir(a.frame, lk->dir), q);
        cJSON *node = add_item(&ok, nodes, NULL, cJSON_CreateObject());
        need(&ok, cJSON_AddStringToObject(node, "name", name));
        add_item(&ok, node, "rotation", cJSON_CreateDoubleArray(q, 4));
        if (k < 0) { /* the sun's size, which KHR_lights_punctual has no field for */
            cJSON *x = need(&ok, cJSON_AddObjectToObject(node, "extras"));
            need(&ok, cJSON_AddNumberToObject(x, "angular_radius_rad", a.sun->radius));
            need(&ok, cJSON_AddNumberToObject(x, "extent_rad", a.sun->sample_radius));
            need(&ok, cJSON_AddNumberToObject(x, "share", a.sun->share));
        }
        cJSON *ne = need(&ok, cJSON_AddObjectToObject(node, "extensions"));
        cJSON *nk = need(&ok, cJSON_AddObjectToObject(ne, "KHR_lights_punctual"));
        need(&ok, cJSON_AddNumberToObject(nk, "light", at));
        add_item(&ok, scene_nodes, NULL, cJSON_CreateNumber(at));
    }
    return write_json(path, root, ok, container == LUMIS_GLTF_BINARY, errors);
}
