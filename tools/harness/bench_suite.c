/* lumis bench: reading a suite file (docs/bench.md has the format) into a checked suite:
 * maps (files, folders, procedural specs), scenes, methods, budgets, the reference and the
 * report's settings.  Every error names the file and the key. */
#include "harness.h"

#include <cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

void bench_suite_free(suite *s)
{
    for (int m = 0; m < s->nmaps; m++) free(s->maps[m].bytes);
    for (int k = 0; k < s->nscenes; k++) {
        free(s->scenes[k].bytes);
        free(s->scenes[k].maps);
    }
    free(s->maps);
    free(s->scenes);
    free(s->methods);
    free(s->budgets);
}

/* Copies at most cap - 1 bytes (a cut label is still a label). */
void bench_copy_cut(char *out, size_t cap, const char *in)
{
    size_t n = strlen(in);
    if (n >= cap) n = cap - 1;
    memcpy(out, in, n);
    out[n] = '\0';
}

/* Labels become file names: [A-Za-z0-9._-], the rest '-'. */
static void make_label(char *out, size_t cap, const char *in)
{
    size_t k = 0;
    for (; in[k] && k + 1 < cap; k++) {
        char c = in[k];
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 c == '.' || c == '_' || c == '-';
        out[k] = ok ? c : '-';
    }
    out[k] = '\0';
}

static int is_map_file(const char *name)
{
    const char *dot = strrchr(name, '.');
    return dot && (strcasecmp(dot, ".exr") == 0 || strcasecmp(dot, ".hdr") == 0 ||
                   strcasecmp(dot, ".pfm") == 0);
}

/* "sky", "studio", optionally followed by ":WxH" (as tool_load_image reads them); a file
 * named sky_garage.hdr is a file. */
static int is_procedural(const char *spec)
{
    size_t n = strcspn(spec, ":");
    return (n == 3 && strncmp(spec, "sky", 3) == 0) || (n == 6 && strncmp(spec, "studio", 6) == 0);
}

/* A suite's relative paths resolve against its folder (a path too long is cut, and then
 * fails to open with its name in the message). */
static void resolve(const suite *s, const char *name, char *out, size_t cap)
{
    if (name[0] == '/' || !s->dir[0]) {
        bench_copy_cut(out, cap, name);
        return;
    }
    bench_copy_cut(out, cap, s->dir);
    size_t n = strlen(out);
    if (n + 1 < cap) out[n++] = '/';
    bench_copy_cut(out + n, cap - n, name);
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static int add_map(suite *s, const char *spec, const char *label, int user_label, float rot,
                   float scale)
{
    suite_map *grown = realloc(s->maps, (size_t)(s->nmaps + 1) * sizeof *grown);
    if (!grown) return tool_runtime_error("bench: out of memory");
    s->maps = grown;
    suite_map *m = &grown[s->nmaps++];
    memset(m, 0, sizeof *m);
    snprintf(m->spec, sizeof m->spec, "%s", spec);
    m->is_file = !is_procedural(spec);
    const char *base = strrchr(label, '/');
    base = base ? base + 1 : label;
    char tmp[128];
    bench_copy_cut(tmp, sizeof tmp, base);
    char *dot = m->is_file && !user_label ? strrchr(tmp, '.') : NULL;
    if (dot) *dot = '\0';
    make_label(m->label, sizeof m->label, user_label ? label : tmp);
    m->rotation_deg = rot;
    m->scale = scale;
    return EXIT_OK;
}

/* Every key of obj is one of keys (NULL-terminated): a misspelt or misplaced key would
 * otherwise be ignored, and the suite would measure something else than it says. */
static int check_keys(const cJSON *obj, const char *const *keys, const char *file,
                      const char *where)
{
    for (const cJSON *c = obj->child; c; c = c->next) {
        int known = 0;
        for (const char *const *k = keys; *k && !known; k++) known = strcmp(*k, c->string) == 0;
        if (known) continue;
        char list[512] = "";
        for (const char *const *k = keys; *k; k++) {
            size_t len = strlen(list);
            snprintf(list + len, sizeof list - len, "%s%s", len ? ", " : "", *k);
        }
        return tool_runtime_error("%s: %s%s%s: unknown key (expected %s)", file, where,
                                  *where ? "." : "", c->string, list);
    }
    return EXIT_OK;
}

/* obj[key] as a number into *out, which stays as it is when the key is absent; another
 * type is an error that names where.key. */
static int opt_number(const cJSON *obj, const char *key, const char *file, const char *where,
                      double *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!v) return EXIT_OK;
    if (!cJSON_IsNumber(v))
        return tool_runtime_error("%s: %s%s%s: expected a number", file, where, *where ? "." : "",
                                  key);
    *out = v->valuedouble;
    return EXIT_OK;
}

/* The same for a string (*out: NULL when absent). */
static int opt_string(const cJSON *obj, const char *key, const char *file, const char *where,
                      const char **out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    *out = NULL;
    if (!v) return EXIT_OK;
    if (!cJSON_IsString(v))
        return tool_runtime_error("%s: %s%s%s: expected a string", file, where, *where ? "." : "",
                                  key);
    *out = v->valuestring;
    return EXIT_OK;
}

/* A map entry: a file, a folder (every .exr/.hdr/.pfm in it, sorted), a procedural spec,
 * or {"map": ..., "rotation_deg": ..., "scale": ..., "label": ...}. */
static int parse_map(suite *s, const cJSON *e, const char *file, const char *where)
{
    static const char *const keys[] = {"map", "rotation_deg", "scale", "label", NULL};
    const char *spec = NULL, *label = NULL;
    float rot = 0.0f, scale = 1.0f;
    if (cJSON_IsString(e)) {
        spec = e->valuestring;
    } else if (cJSON_IsObject(e)) {
        double r = 0.0, k = 1.0;
        int rc = check_keys(e, keys, file, where);
        if (rc == EXIT_OK) rc = opt_string(e, "map", file, where, &spec);
        if (rc == EXIT_OK) rc = opt_number(e, "rotation_deg", file, where, &r);
        if (rc == EXIT_OK) rc = opt_number(e, "scale", file, where, &k);
        if (rc == EXIT_OK) rc = opt_string(e, "label", file, where, &label);
        if (rc != EXIT_OK) return rc;
        if (!spec)
            return tool_runtime_error("%s: %s: an object needs \"map\": a file or spec", file,
                                      where);
        rot = (float)r;
        scale = (float)k;
    } else {
        return tool_runtime_error("%s: %s: expected a file name, folder or spec", file, where);
    }
    if (!*spec) return tool_runtime_error("%s: %s: an empty name", file, where);
    if (is_procedural(spec))
        return add_map(s, spec, label ? label : spec, label != NULL, rot, scale);
    char path[4096];
    resolve(s, spec, path, sizeof path);
    struct stat sb;
    if (stat(path, &sb) != 0)
        return tool_runtime_error("%s: %s: %s: %s", file, where, path, strerror(errno));
    if (!S_ISDIR(sb.st_mode))
        return add_map(s, path, label ? label : path, label != NULL, rot, scale);
    DIR *d = opendir(path);
    if (!d) return tool_runtime_error("%s: %s: %s: %s", file, where, path, strerror(errno));
    char **names = NULL;
    int n = 0, rc = EXIT_OK;
    for (struct dirent *de; (de = readdir(d));) {
        if (de->d_name[0] == '.' || !is_map_file(de->d_name)) continue;
        char **grown = realloc(names, (size_t)(n + 1) * sizeof *grown);
        if (!grown || !(grown[n] = strdup(de->d_name))) {
            names = grown ? grown : names;
            rc = tool_runtime_error("bench: out of memory");
            break;
        }
        names = grown;
        n++;
    }
    closedir(d);
    if (rc == EXIT_OK && n == 0)
        rc = tool_runtime_error("%s: %s: %s holds no .exr, .hdr or .pfm file", file, where, path);
    if (n) qsort(names, (size_t)n, sizeof *names, cmp_str);
    for (int k = 0; k < n; k++) {
        char full[4096 + 256];
        snprintf(full, sizeof full, "%s/%s", path, names[k]);
        if (rc == EXIT_OK) rc = add_map(s, full, names[k], 0, rot, scale);
        free(names[k]);
    }
    free(names);
    return rc;
}

/* obj[key], when present, as an integer in [lo, hi] into *out (where names obj). */
static int opt_count(const cJSON *obj, const char *key, const char *file, const char *where,
                     double lo, double hi, int *out)
{
    double v = *out;
    int rc = opt_number(obj, key, file, where, &v);
    if (rc != EXIT_OK) return rc;
    if (!cJSON_GetObjectItemCaseSensitive(obj, key)) return EXIT_OK; /* absent: the default */
    if (v < lo || v > hi || v != floor(v))
        return tool_runtime_error("%s: %s%s%s: expected an integer from %.0f to %.0f", file, where,
                                  *where ? "." : "", key, lo, hi);
    *out = (int)v;
    return EXIT_OK;
}

static const char *const method_keys[] =
    {"method",     "label",        "mis",    "blocks", "light_samples", "bsdf_samples", "k",
     "interleave", "upsample",     "params", "mode",   "sequence",      "sun",          "draws",
     "auto",       "region_draws", NULL},
                         *reference_keys[] = {"method",        "label",        "mis",      "blocks",
                                              "light_samples", "bsdf_samples", "spp",      "k",
                                              "params",        "mode",         "sequence", "sun",
                                              "draws",         "region_draws", NULL};

/* The library's refusal, kept to be said with the suite file and key. */
static void keep_refusal(void *user, lumis_status status, const char *message)
{
    (void)status;
    snprintf((char *)user, 512, "%s", message);
}

/* The render fields lumis_session_check names, and the suite keys that set them. */
static const struct {
    const char *field, *key;
} field_keys[] = {
    {"lighting.sampler", "blocks"},
    {"lighting.estimator", "mis"},
    {"power_heuristic", "mis"},
    {"light_samples", "light_samples"},
    {"bsdf_samples", "bsdf_samples"},
    {"upsample", "upsample"},
    {"lighting.light_set.mode", "mode"},
    {"lights_k", "k"},
    {"interleave", "interleave"},
    {"lights_params", "params"},
    {"lighting.light_set.draws", "draws"},
    {"lighting.light_set.region_draws", "region_draws"},
};

/* A light-set method's keys as the library sees them: the session it would run, with a
 * stand-in map and camera (lumis_session_check reads only whether they are given) and,
 * with "blocks", a stand-in sampler.  The library says which choices a light set takes
 * (in which mode); its refusal is printed with the suite file and key.  Exit code. */
static int check_light_set(const suite_method *m, int blocks, const char *file, const char *where)
{
    lumis_image *img = NULL;
    lumis_envmap *env = NULL;
    lumis_sampler *smp = NULL;
    lumis_status st = lumis_image_create(8, 4, &img);
    if (st == LUMIS_OK) {
        for (size_t k = 0; k < 3 * 8 * 4; k++) img->pixels[k] = 1.0f;
        st = lumis_envmap_from_image(img, &env);
    }
    if (st == LUMIS_OK && blocks) st = lumis_sampler_create(env, &m->sampler, &smp);
    int rc = EXIT_OK;
    if (st != LUMIS_OK) {
        rc = tool_runtime_error("%s: %s: checking the light set: %s", file, where,
                                lumis_status_string(st));
    } else {
        const lumis_camera cam = {0};
        char refusal[512] = "";
        lumis_session_desc d = {0};
        d.render.camera = &cam;
        d.render.errors = (lumis_error_sink){keep_refusal, refusal};
        d.render.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
        d.render.lighting.env = env;
        d.render.lighting.sampler = smp;
        d.render.lighting.estimator = m->estimator;
        d.render.lighting.light_set.mode = m->lights_mode;
        d.render.lighting.light_set.draws = m->lights_draws;
        d.render.lighting.light_set.region_draws = m->lights_region_draws;
        d.render.power_heuristic = m->power;
        d.render.light_samples = m->light_samples;
        d.render.bsdf_samples = m->bsdf_samples;
        d.lights = m->lights;
        d.lights_k = m->lights_k;
        d.interleave = m->interleave;
        d.upsample = m->upsample;
        d.lights_params = m->lights_params.given ? &m->lights_params : NULL;
        if (lumis_session_check(&d) != LUMIS_OK) {
            const char *key = NULL;
            for (size_t k = 0; !key && k < sizeof field_keys / sizeof *field_keys; k++)
                if (strstr(refusal, field_keys[k].field)) key = field_keys[k].key;
            rc = key ? tool_runtime_error("%s: %s.%s: %s", file, where, key, refusal)
                     : tool_runtime_error("%s: %s: %s", file, where, refusal);
        }
    }
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
    return rc;
}

/* A method's "auto": true, the session chooses the estimator by its prediction from the scene
 * (LUMIS_AUTO_PREDICT, lumis render's default); "pilots", by pilot renders
 * (LUMIS_AUTO_PILOTS); absent or false, 0.  Exit code. */
static int parse_auto(const cJSON *e, const char *file, const char *where, int *mode)
{
    const cJSON *aut = cJSON_GetObjectItemCaseSensitive(e, "auto");
    const int pilots = cJSON_IsString(aut) && strcmp(aut->valuestring, "pilots") == 0;
    if (aut && !cJSON_IsBool(aut) && !pilots)
        return tool_runtime_error("%s: %s.auto: expected true, false or \"pilots\"", file, where);
    *mode = pilots ? LUMIS_AUTO_PILOTS : cJSON_IsTrue(aut) ? LUMIS_AUTO_PREDICT : 0;
    return EXIT_OK;
}

/* A method (where: "methods[K]" or "reference", whose "spp" is read by the caller). */
static int parse_method(const cJSON *e, suite_method *m, const char *file, const char *where)
{
    memset(m, 0, sizeof *m);
    if (!cJSON_IsObject(e)) return tool_runtime_error("%s: %s: expected an object", file, where);
    const char *name = NULL, *label = NULL, *mis = NULL;
    int rc =
        check_keys(e, strcmp(where, "reference") == 0 ? reference_keys : method_keys, file, where);
    if (rc == EXIT_OK) rc = opt_string(e, "method", file, where, &name);
    if (rc == EXIT_OK) rc = opt_string(e, "label", file, where, &label);
    if (rc == EXIT_OK) rc = opt_string(e, "mis", file, where, &mis);
    const char *seq = NULL;
    if (rc == EXIT_OK) rc = opt_string(e, "sequence", file, where, &seq);
    if (rc != EXIT_OK) return rc;
    if (seq && lumis_sequence_from_name(seq, &m->sequence) != LUMIS_OK)
        return tool_runtime_error("%s: %s.sequence: expected sobol, zsobol, pmj02, halton, "
                                  "stratified, pcg or default",
                                  file, where);
    /* "method", with "auto", is the sampler of its MIS candidate (default inversion) */
    if (parse_auto(e, file, where, &m->auto_estimator) != EXIT_OK) return EXIT_RUNTIME;
    if (m->auto_estimator && !name) name = "inversion";
    if (!name)
        return tool_runtime_error("%s: %s: needs \"method\": a sampler name or \"bsdf\"", file,
                                  where);
    if (m->auto_estimator && (strcmp(name, "bsdf") == 0 || tool_lights_method_known(name)))
        return tool_runtime_error("%s: %s.auto: the session chooses between the map with MIS "
                                  "and its median-cut strata: \"method\" may only name the "
                                  "MIS candidate's sampler, not '%s'",
                                  file, where, name);
    if (strcmp(name, "bsdf") == 0) {
        m->bsdf_only = 1;
        m->estimator = LUMIS_ESTIMATOR_BSDF;
    } else if (tool_lights_method_known(name)) {
        /* A light set (median-cut, variance-min, wu...): every light, one shadow ray each,
         * or its regions as strata ("mode": "stratified"). */
        bench_copy_cut(m->lights, sizeof m->lights, name);
        const char *mode = NULL;
        rc = opt_string(e, "mode", file, where, &mode);
        if (rc != EXIT_OK) return rc;
        if (mode && lumis_lights_mode_from_name(mode, &m->lights_mode) != LUMIS_OK)
            return tool_runtime_error("%s: %s.mode: expected point or stratified", file, where);
        /* a reference must converge to the image: point lights do not */
        if (strcmp(where, "reference") == 0 && m->lights_mode != LUMIS_LIGHTS_STRATIFIED)
            return tool_runtime_error("%s: reference: a light set is a reference only in "
                                      "\"mode\": \"stratified\" (point lights are biased)",
                                      file);
        rc = opt_count(e, "k", file, where, 1, 1 << 20, &m->lights_k);
        if (rc == EXIT_OK)
            rc = opt_count(e, "draws", file, where, 1, LUMIS_LIGHT_SET_MAX_DRAWS, &m->lights_draws);
        if (rc == EXIT_OK)
            rc = opt_count(e, "region_draws", file, where, 1, LUMIS_LIGHT_SET_MAX_DRAWS,
                           &m->lights_region_draws);
        if (rc == EXIT_OK && m->lights_draws && m->lights_mode != LUMIS_LIGHTS_STRATIFIED)
            return tool_runtime_error("%s: %s.draws: chooses regions as strata: needs \"mode\": "
                                      "\"stratified\"",
                                      file, where);
        if (rc == EXIT_OK) rc = opt_count(e, "interleave", file, where, 1, 64, &m->interleave);
        if (rc == EXIT_OK) rc = opt_count(e, "upsample", file, where, 1, 16, &m->upsample);
        const char *params = NULL;
        if (rc == EXIT_OK) rc = opt_string(e, "params", file, where, &params);
        if (rc != EXIT_OK) return rc;
        if (params) {
            char opt[256];
            snprintf(opt, sizeof opt, "%s: %s.params", file, where);
            if (tool_light_params_parse(&m->lights_params, "bench", opt, params) != EXIT_OK ||
                tool_light_params_check(&m->lights_params, "bench", opt, name) != EXIT_OK)
                return EXIT_RUNTIME;
        }
        /* which of the other keys a light set takes is the library's to say (check_light_set,
         * once they are read) */
    } else if (lumis_sampler_method_from_name(name, &m->sampler.method) != LUMIS_OK) {
        return tool_runtime_error("%s: %s.method: unknown method '%s' (a sampler, bsdf, or a "
                                  "light set: %s)",
                                  file, where, name, tool_lights_method_names());
    }
    if (!m->lights[0] && (cJSON_GetObjectItemCaseSensitive(e, "k") ||
                          cJSON_GetObjectItemCaseSensitive(e, "interleave") ||
                          cJSON_GetObjectItemCaseSensitive(e, "upsample") ||
                          cJSON_GetObjectItemCaseSensitive(e, "params") ||
                          cJSON_GetObjectItemCaseSensitive(e, "mode") ||
                          cJSON_GetObjectItemCaseSensitive(e, "draws") ||
                          cJSON_GetObjectItemCaseSensitive(e, "region_draws")))
        return tool_runtime_error("%s: %s: k, interleave, upsample, params, draws, region_draws "
                                  "and mode belong to light sets",
                                  file, where);
    if (mis) {
        if (strcmp(mis, "power") == 0)
            m->power = 1;
        else if (strcmp(mis, "none") == 0)
            m->estimator = m->bsdf_only ? LUMIS_ESTIMATOR_BSDF : LUMIS_ESTIMATOR_LIGHT;
        else if (strcmp(mis, "balance") != 0)
            return tool_runtime_error("%s: %s.mis: expected balance, power or none", file, where);
    }
    rc = opt_count(e, "blocks", file, where, 0, 1 << 30, &m->sampler.kdtree_blocks);
    if (rc == EXIT_OK) rc = opt_count(e, "light_samples", file, where, 0, 4096, &m->light_samples);
    if (rc == EXIT_OK) rc = opt_count(e, "bsdf_samples", file, where, 0, 4096, &m->bsdf_samples);
    if (rc == EXIT_OK && m->lights[0])
        rc = check_light_set(m, cJSON_GetObjectItemCaseSensitive(e, "blocks") != NULL, file, where);
    if (rc != EXIT_OK) return rc;
    const cJSON *sun = cJSON_GetObjectItemCaseSensitive(e, "sun");
    if (sun && !cJSON_IsBool(sun))
        return tool_runtime_error("%s: %s.sun: expected true or false", file, where);
    m->sun = cJSON_IsTrue(sun);
    if (m->auto_estimator && (m->sun || m->estimator != LUMIS_ESTIMATOR_MIS))
        return tool_runtime_error("%s: %s.auto: chooses the estimator itself: not with %s", file,
                                  where, m->sun ? "\"sun\"" : "\"mis\": \"none\"");
    if (m->sun && m->bsdf_only)
        return tool_runtime_error("%s: %s.sun: the image sun is sampled as a light: not with "
                                  "\"method\": \"bsdf\"",
                                  file, where);
    char tmp[128];
    bench_copy_cut(tmp, sizeof tmp, label ? label : m->auto_estimator ? "auto" : name);
    make_label(m->label, sizeof m->label, tmp);
    return EXIT_OK;
}

/* The non-empty array root[key] and zeroed storage for its *count elements; NULL, with
 * *rc set, if it is missing or empty or memory is short (nothing happens if *rc is set). */
static void *suite_array(const cJSON *root, const char *key, const char *path, size_t elem,
                         const cJSON **array, int *count, int *rc)
{
    if (*rc != EXIT_OK) return NULL;
    *array = cJSON_GetObjectItemCaseSensitive(root, key);
    if (!cJSON_IsArray(*array) || cJSON_GetArraySize(*array) == 0) {
        *rc = tool_runtime_error("%s: %s: expected a non-empty array", path, key);
        return NULL;
    }
    *count = cJSON_GetArraySize(*array);
    void *p = calloc((size_t)*count, elem);
    if (!p) *rc = tool_runtime_error("bench: out of memory");
    return p;
}

/* The suite file's JSON object (*out, the caller deletes it); an error names the line and
 * column where it is malformed. */
static int suite_read(const char *path, cJSON **out)
{
    size_t n = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return tool_runtime_error("%s: %s", path, strerror(errno));
    char *text = NULL;
    if (fseek(f, 0, SEEK_END) == 0) {
        long len = ftell(f);
        if (len >= 0 && len < (1L << 24) && fseek(f, 0, SEEK_SET) == 0) {
            text = malloc((size_t)len + 1);
            if (text) n = fread(text, 1, (size_t)len, f);
        }
    }
    fclose(f);
    if (!text) return tool_runtime_error("%s: cannot read it", path);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, n, &end, 0);
    if (!root) { /* cJSON points at where it gave up: name its line and column */
        size_t at = end && end >= text && end <= text + n ? (size_t)(end - text) : 0;
        int line = 1, col = 1;
        for (size_t k = 0; k < at; k++) {
            col = text[k] == '\n' ? 1 : col + 1;
            line += text[k] == '\n';
        }
        int near = 0;
        while (at + (size_t)near < n && near < 24 && text[at + near] != '\n' &&
               text[at + near] != '\r')
            near++;
        int rc = tool_runtime_error("%s:%d:%d: malformed JSON%s%.*s%s", path, line, col,
                                    near ? " near '" : " (it ends too soon)", near, text + at,
                                    near ? "'" : "");
        free(text);
        return rc;
    }
    free(text);
    if (!cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return tool_runtime_error("%s: expected a JSON object {...} at the top", path);
    }
    *out = root;
    return EXIT_OK;
}

/* The suite's folder (relative paths are from it), its top-level keys, name and
 * description. */
static int parse_suite_names(const cJSON *root, const char *path, suite *s)
{
    const char *slash = strrchr(path, '/');
    if (slash) snprintf(s->dir, sizeof s->dir, "%.*s", (int)(slash - path), path);
    static const char *const keys[] = {
        "name",        "description",         "maps",     "scenes",  "methods",
        "budgets",     "reference",           "size",     "seed",    "bounces",
        "exposure_ev", "preview_exposure_ev", "flip_hdr", "compare", NULL};
    int rc = check_keys(root, keys, path, "");
    char base[128];
    bench_copy_cut(base, sizeof base, slash ? slash + 1 : path);
    char *dot = strrchr(base, '.');
    if (dot) *dot = '\0';
    const char *name = NULL, *description = NULL;
    if (rc == EXIT_OK) rc = opt_string(root, "name", path, "", &name);
    if (rc == EXIT_OK) rc = opt_string(root, "description", path, "", &description);
    make_label(s->name, sizeof s->name, name ? name : base);
    if (description) snprintf(s->description, sizeof s->description, "%s", description);
    return rc;
}

/* maps: a non-empty array. */
static int parse_maps(const cJSON *root, const char *path, suite *s, int rc)
{
    const cJSON *maps = cJSON_GetObjectItemCaseSensitive(root, "maps");
    if (rc == EXIT_OK && (!cJSON_IsArray(maps) || cJSON_GetArraySize(maps) == 0))
        rc = tool_runtime_error("%s: maps: expected a non-empty array", path);
    int mk = 0;
    for (const cJSON *e = maps ? maps->child : NULL; e && rc == EXIT_OK; e = e->next, mk++) {
        char where[32];
        snprintf(where, sizeof where, "maps[%d]", mk);
        rc = parse_map(s, e, path, where);
    }
    return rc;
}

/* {"scene": NAME, "maps": [LABEL...]}: the scene with those maps alone (sc->maps); the
 * scene's name in *e. */
static int parse_scene_maps(const cJSON **e, const char *path, suite *s, int k, suite_scene *sc)
{
    static const char *const keys[] = {"scene", "maps", NULL};
    char where[32];
    snprintf(where, sizeof where, "scenes[%d]", k);
    int rc = check_keys(*e, keys, path, where);
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(*e, "scene"),
                *maps = cJSON_GetObjectItemCaseSensitive(*e, "maps");
    if (rc == EXIT_OK && (!cJSON_IsArray(maps) || cJSON_GetArraySize(maps) == 0))
        rc = tool_runtime_error("%s: scenes[%d].maps: expected a non-empty array of map labels",
                                path, k);
    if (rc == EXIT_OK && !(sc->maps = calloc((size_t)s->nmaps, 1)))
        rc = tool_runtime_error("bench: out of memory");
    int j = 0;
    for (const cJSON *m = maps ? maps->child : NULL; m && rc == EXIT_OK; m = m->next, j++) {
        int found = -1;
        for (int i = 0; i < s->nmaps && cJSON_IsString(m); i++)
            if (strcmp(s->maps[i].label, m->valuestring) == 0) found = i;
        if (found < 0)
            rc = tool_runtime_error("%s: scenes[%d].maps[%d]: expected the label of one of the "
                                    "suite's maps%s%s%s",
                                    path, k, j, cJSON_IsString(m) ? " (none is labelled '" : "",
                                    cJSON_IsString(m) ? m->valuestring : "",
                                    cJSON_IsString(m) ? "')" : "");
        else
            sc->maps[found] = 1;
    }
    *e = name;
    return rc;
}

/* scenes: built-in names or files, labelled by their names; or {"scene": ..., "maps": [...]},
 * a scene with some of the maps only. */
static int parse_scenes(const cJSON *root, const char *path, suite *s, int rc)
{
    const cJSON *scenes = NULL;
    s->scenes = suite_array(root, "scenes", path, sizeof *s->scenes, &scenes, &s->nscenes, &rc);
    for (int k = 0; rc == EXIT_OK && k < s->nscenes; k++) {
        const cJSON *e = cJSON_GetArrayItem(scenes, k);
        suite_scene *sc = &s->scenes[k];
        if (cJSON_IsObject(e)) rc = parse_scene_maps(&e, path, s, k, sc);
        if (rc != EXIT_OK) break;
        if (!cJSON_IsString(e) || !*e->valuestring) {
            rc = tool_runtime_error("%s: scenes[%d]: expected a built-in name or a file, or "
                                    "{\"scene\": ..., \"maps\": [...]}",
                                    path, k);
            break;
        }
        int builtin = 0;
        for (const char *const *b = lumis_scene_builtin_names(); *b; b++)
            builtin |= strcmp(*b, e->valuestring) == 0;
        sc->is_file = !builtin;
        if (builtin)
            snprintf(sc->spec, sizeof sc->spec, "%s", e->valuestring);
        else
            resolve(s, e->valuestring, sc->spec, sizeof sc->spec);
        const char *b = strrchr(e->valuestring, '/');
        char tmp[128];
        bench_copy_cut(tmp, sizeof tmp, b ? b + 1 : e->valuestring);
        char *d2 = builtin ? NULL : strrchr(tmp, '.');
        if (d2) *d2 = '\0';
        make_label(sc->label, sizeof sc->label, tmp);
    }
    return rc;
}

/* methods: each labelled once. */
static int parse_methods(const cJSON *root, const char *path, suite *s, int rc)
{
    const cJSON *methods = NULL;
    s->methods =
        suite_array(root, "methods", path, sizeof *s->methods, &methods, &s->nmethods, &rc);
    for (int k = 0; rc == EXIT_OK && k < s->nmethods; k++) {
        char where[32];
        snprintf(where, sizeof where, "methods[%d]", k);
        rc = parse_method(cJSON_GetArrayItem(methods, k), &s->methods[k], path, where);
        for (int j = 0; rc == EXIT_OK && j < k; j++)
            if (strcmp(s->methods[j].label, s->methods[k].label) == 0)
                rc = tool_runtime_error("%s: methods[%d]: label '%s' is used twice (give "
                                        "\"label\")",
                                        path, k, s->methods[k].label);
    }
    return rc;
}

/* budgets: {"spp": N} or {"time": SECONDS} each. */
static int parse_budgets(const cJSON *root, const char *path, suite *s, int rc)
{
    const cJSON *budgets = NULL;
    s->budgets =
        suite_array(root, "budgets", path, sizeof *s->budgets, &budgets, &s->nbudgets, &rc);
    for (int k = 0; rc == EXIT_OK && k < s->nbudgets; k++) {
        static const char *const budget_keys[] = {"spp", "time", NULL};
        const cJSON *e = cJSON_GetArrayItem(budgets, k);
        char where[32];
        snprintf(where, sizeof where, "budgets[%d]", k);
        suite_budget *b = &s->budgets[k];
        const int has_spp = cJSON_HasObjectItem(e, "spp"), has_t = cJSON_HasObjectItem(e, "time");
        if (!cJSON_IsObject(e) || has_spp == has_t) {
            rc = tool_runtime_error("%s: %s: expected {\"spp\": N} or {\"time\": SECONDS}", path,
                                    where);
            break;
        }
        rc = check_keys(e, budget_keys, path, where);
        if (rc == EXIT_OK && has_spp) {
            rc = opt_count(e, "spp", path, where, 1, 1 << 20, &b->spp);
            snprintf(b->label, sizeof b->label, "spp%d", b->spp);
        } else if (rc == EXIT_OK) {
            rc = opt_number(e, "time", path, where, &b->seconds);
            if (rc == EXIT_OK && !(b->seconds > 0 && b->seconds <= 86400))
                rc = tool_runtime_error("%s: %s.time: expected seconds, over 0 and at most 86400",
                                        path, where);
            snprintf(b->label, sizeof b->label, "t%gs", b->seconds);
        }
    }
    return rc;
}

/* reference: its method and samples, or the default. */
static int parse_reference(const cJSON *root, const char *path, suite *s, int rc)
{
    /* The reference: one method at many samples (default inversion, MIS balance). */
    const cJSON *ref = cJSON_GetObjectItemCaseSensitive(root, "reference");
    s->ref_spp = 1024;
    memset(&s->reference, 0, sizeof s->reference);
    s->reference.sampler.method = LUMIS_METHOD_INVERSION;
    snprintf(s->reference.label, sizeof s->reference.label, "reference");
    if (rc == EXIT_OK && ref) {
        if (!cJSON_IsObject(ref))
            rc = tool_runtime_error("%s: reference: expected {\"spp\": N, \"method\": ...}", path);
        if (rc == EXIT_OK) rc = opt_count(ref, "spp", path, "reference", 1, 1 << 20, &s->ref_spp);
        if (rc == EXIT_OK)
            rc = cJSON_HasObjectItem(ref, "method")
                     ? parse_method(ref, &s->reference, path, "reference")
                     : check_keys(ref, reference_keys, path, "reference");
    }
    return rc;
}

/* How every item renders: size, seed, bounces, exposures, flip_hdr. */
static int parse_render_settings(const cJSON *root, const char *path, suite *s, int rc)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "size");
    if (rc == EXIT_OK && v) {
        if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2 ||
            !cJSON_IsNumber(cJSON_GetArrayItem(v, 0)) || !cJSON_IsNumber(cJSON_GetArrayItem(v, 1)))
            rc = tool_runtime_error("%s: size: expected [width, height]", path);
        else {
            s->width = cJSON_GetArrayItem(v, 0)->valueint;
            s->height = cJSON_GetArrayItem(v, 1)->valueint;
            if (s->width < 1 || s->height < 1 || s->width > 16384 || s->height > 16384)
                rc = tool_runtime_error("%s: size: 1 to 16384 pixels each way", path);
        }
    }
    double seed = 1;
    if (rc == EXIT_OK) rc = opt_number(root, "seed", path, "", &seed);
    if (rc == EXIT_OK && !(seed >= 0 && seed <= 9007199254740992.0 && seed == floor(seed)))
        rc = tool_runtime_error("%s: seed: expected an integer from 0 to 2^53", path);
    s->seed = rc == EXIT_OK ? (unsigned long long)seed : 1;
    if (rc == EXIT_OK) rc = opt_count(root, "bounces", path, "", 0, 64, &s->bounces);
    v = cJSON_GetObjectItemCaseSensitive(root, "exposure_ev");
    s->exposure_ev = cJSON_IsNumber(v) ? (float)v->valuedouble : 0.0f;
    s->exposure_auto = cJSON_IsString(v) && strcmp(v->valuestring, "auto") == 0;
    if (rc == EXIT_OK && v && !cJSON_IsNumber(v) && !s->exposure_auto)
        rc = tool_runtime_error("%s: exposure_ev: expected stops or \"auto\"", path);
    v = cJSON_GetObjectItemCaseSensitive(root, "preview_exposure_ev");
    s->preview_ev = cJSON_IsNumber(v) ? (float)v->valuedouble : s->exposure_ev;
    s->preview_auto =
        v ? cJSON_IsString(v) && strcmp(v->valuestring, "auto") == 0 : s->exposure_auto;
    if (rc == EXIT_OK && v && !cJSON_IsNumber(v) && !s->preview_auto)
        rc = tool_runtime_error("%s: preview_exposure_ev: expected stops or \"auto\"", path);
    v = cJSON_GetObjectItemCaseSensitive(root, "flip_hdr");
    s->flip_hdr = v ? cJSON_IsTrue(v) : 1;
    if (rc == EXIT_OK && v && !cJSON_IsBool(v))
        rc = tool_runtime_error("%s: flip_hdr: expected true or false", path);
    return rc;
}

/* compare: pairs of method labels. */
static int parse_compare(const cJSON *root, const char *path, suite *s, int rc)
{
    const cJSON *cmp = cJSON_GetObjectItemCaseSensitive(root, "compare");
    if (rc == EXIT_OK && cmp && !cJSON_IsArray(cmp))
        rc = tool_runtime_error("%s: compare: expected an array of pairs [\"A\", \"B\"]", path);
    for (const cJSON *e = cmp ? cmp->child : NULL; e && rc == EXIT_OK; e = e->next) {
        if (s->ncompare == 8 || !cJSON_IsArray(e) || cJSON_GetArraySize(e) != 2 ||
            !cJSON_IsString(cJSON_GetArrayItem(e, 0)) ||
            !cJSON_IsString(cJSON_GetArrayItem(e, 1))) {
            rc = tool_runtime_error("%s: compare[%d]: expected up to 8 pairs [\"A\", \"B\"] of "
                                    "method labels",
                                    path, s->ncompare);
            break;
        }
        for (int j = 0; j < 2; j++) {
            const char *lab = cJSON_GetArrayItem(e, j)->valuestring;
            int found = 0;
            for (int k = 0; k < s->nmethods; k++) found |= strcmp(s->methods[k].label, lab) == 0;
            if (!found && rc == EXIT_OK)
                rc = tool_runtime_error("%s: compare[%d][%d]: no method labelled '%s'", path,
                                        s->ncompare, j, lab);
            snprintf(s->compare[s->ncompare][j], sizeof s->compare[0][0], "%s", lab);
        }
        s->ncompare++;
    }
    return rc;
}

/* Labels name files: two items must never share one. */
static int check_labels(const char *path, const suite *s, int rc)
{
    for (int a = 0; rc == EXIT_OK && a < s->nmaps; a++)
        for (int b = 0; rc == EXIT_OK && b < a; b++)
            if (strcmp(s->maps[a].label, s->maps[b].label) == 0)
                rc = tool_runtime_error("%s: maps: two maps are labelled '%s' (%s and %s): list "
                                        "each once, or give {\"map\": ..., \"label\": ...}",
                                        path, s->maps[a].label, s->maps[b].spec, s->maps[a].spec);
    for (int a = 0; rc == EXIT_OK && a < s->nscenes; a++)
        for (int b = 0; rc == EXIT_OK && b < a; b++)
            if (strcmp(s->scenes[a].label, s->scenes[b].label) == 0)
                rc = tool_runtime_error("%s: scenes[%d]: another scene is also labelled '%s'", path,
                                        a, s->scenes[a].label);
    for (int a = 0; rc == EXIT_OK && a < s->nbudgets; a++)
        for (int b = 0; rc == EXIT_OK && b < a; b++)
            if (strcmp(s->budgets[a].label, s->budgets[b].label) == 0)
                rc = tool_runtime_error("%s: budgets[%d]: the same budget as budgets[%d]", path, a,
                                        b);
    return rc;
}

int bench_parse_suite(const char *path, suite *s)
{
    memset(s, 0, sizeof *s);
    cJSON *root = NULL;
    int rc = suite_read(path, &root);
    if (rc != EXIT_OK) return rc;
    rc = parse_suite_names(root, path, s);
    rc = parse_maps(root, path, s, rc);
    rc = parse_scenes(root, path, s, rc);
    rc = parse_methods(root, path, s, rc);
    rc = parse_budgets(root, path, s, rc);
    rc = parse_reference(root, path, s, rc);
    rc = parse_render_settings(root, path, s, rc);
    rc = parse_compare(root, path, s, rc);
    rc = check_labels(path, s, rc);
    cJSON_Delete(root);
    if (rc != EXIT_OK) bench_suite_free(s);
    return rc;
}
