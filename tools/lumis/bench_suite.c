/* lumis bench: reading a suite file (docs/bench.md has the format) into a checked suite:
 * maps (files, folders, procedural specs), scenes, methods, budgets, the reference and the
 * report's settings.  Every error names the file and the key. */
#include "bench.h"

#include <cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

void bench_suite_free(suite *s)
{
    for (int m = 0; m < s->nmaps; m++) free(s->maps[m].bytes);
    for (int k = 0; k < s->nscenes; k++) free(s->scenes[k].bytes);
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

/* A map entry: a file, a folder (every .exr/.hdr/.pfm in it, sorted), a procedural spec,
 * or {"map": ..., "rotation_deg": ..., "scale": ..., "label": ...}. */
static int parse_map(suite *s, const cJSON *e, const char *file)
{
    const char *spec = NULL, *label = NULL;
    float rot = 0.0f, scale = 1.0f;
    if (cJSON_IsString(e)) {
        spec = e->valuestring;
    } else if (cJSON_IsObject(e)) {
        const cJSON *m = cJSON_GetObjectItemCaseSensitive(e, "map"),
                    *r = cJSON_GetObjectItemCaseSensitive(e, "rotation_deg"),
                    *k = cJSON_GetObjectItemCaseSensitive(e, "scale"),
                    *l = cJSON_GetObjectItemCaseSensitive(e, "label");
        if (!cJSON_IsString(m))
            return tool_runtime_error("%s: maps: an object needs \"map\": a file or spec", file);
        spec = m->valuestring;
        if (cJSON_IsNumber(r)) rot = (float)r->valuedouble;
        if (cJSON_IsNumber(k)) scale = (float)k->valuedouble;
        if (cJSON_IsString(l)) label = l->valuestring;
    } else {
        return tool_runtime_error("%s: maps: expected file names, folders or specs", file);
    }
    if (!*spec) return tool_runtime_error("%s: maps: an empty name", file);
    if (is_procedural(spec))
        return add_map(s, spec, label ? label : spec, label != NULL, rot, scale);
    char path[4096];
    resolve(s, spec, path, sizeof path);
    struct stat sb;
    if (stat(path, &sb) != 0)
        return tool_runtime_error("%s: maps: %s: %s", file, path, strerror(errno));
    if (!S_ISDIR(sb.st_mode))
        return add_map(s, path, label ? label : path, label != NULL, rot, scale);
    DIR *d = opendir(path);
    if (!d) return tool_runtime_error("%s: maps: %s: %s", file, path, strerror(errno));
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
        rc = tool_runtime_error("%s: maps: %s holds no .exr, .hdr or .pfm file", file, path);
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

static int parse_method(const cJSON *e, suite_method *m, const char *file, const char *where)
{
    memset(m, 0, sizeof *m);
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(e, "method"),
                *label = cJSON_GetObjectItemCaseSensitive(e, "label"),
                *mis = cJSON_GetObjectItemCaseSensitive(e, "mis"),
                *blocks = cJSON_GetObjectItemCaseSensitive(e, "blocks"),
                *nl = cJSON_GetObjectItemCaseSensitive(e, "light_samples"),
                *nb = cJSON_GetObjectItemCaseSensitive(e, "bsdf_samples");
    if (!cJSON_IsString(name))
        return tool_runtime_error("%s: %s: needs \"method\": a sampler name or \"bsdf\"", file,
                                  where);
    if (strcmp(name->valuestring, "bsdf") == 0) {
        m->bsdf_only = 1;
        m->estimator = LUMIS_ESTIMATOR_BSDF;
    } else if (lumis_sampler_method_from_name(name->valuestring, &m->sampler.method) != LUMIS_OK) {
        return tool_runtime_error("%s: %s: unknown method '%s'", file, where, name->valuestring);
    }
    if (cJSON_IsString(mis)) {
        if (strcmp(mis->valuestring, "power") == 0)
            m->power = 1;
        else if (strcmp(mis->valuestring, "none") == 0)
            m->estimator = m->bsdf_only ? LUMIS_ESTIMATOR_BSDF : LUMIS_ESTIMATOR_LIGHT;
        else if (strcmp(mis->valuestring, "balance") != 0)
            return tool_runtime_error("%s: %s.mis: expected balance, power or none", file, where);
    }
    if (cJSON_IsNumber(blocks)) m->sampler.kdtree_blocks = blocks->valueint;
    if (cJSON_IsNumber(nl)) m->light_samples = nl->valueint;
    if (cJSON_IsNumber(nb)) m->bsdf_samples = nb->valueint;
    if (m->sampler.kdtree_blocks < 0 || m->light_samples < 0 || m->bsdf_samples < 0 ||
        m->light_samples > 4096 || m->bsdf_samples > 4096)
        return tool_runtime_error("%s: %s: counts must be small non-negative integers", file,
                                  where);
    char tmp[128];
    bench_copy_cut(tmp, sizeof tmp, cJSON_IsString(label) ? label->valuestring : name->valuestring);
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

int bench_parse_suite(const char *path, suite *s)
{
    memset(s, 0, sizeof *s);
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
    cJSON *root = cJSON_ParseWithLength(text, n);
    free(text);
    if (!cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return tool_runtime_error("%s: not a JSON object (malformed JSON?)", path);
    }
    const char *slash = strrchr(path, '/');
    if (slash) snprintf(s->dir, sizeof s->dir, "%.*s", (int)(slash - path), path);
    int rc = EXIT_OK;
    const cJSON *v;
    char base[128];
    bench_copy_cut(base, sizeof base, slash ? slash + 1 : path);
    char *dot = strrchr(base, '.');
    if (dot) *dot = '\0';
    v = cJSON_GetObjectItemCaseSensitive(root, "name");
    make_label(s->name, sizeof s->name, cJSON_IsString(v) ? v->valuestring : base);
    v = cJSON_GetObjectItemCaseSensitive(root, "description");
    if (cJSON_IsString(v)) snprintf(s->description, sizeof s->description, "%s", v->valuestring);

    const cJSON *maps = cJSON_GetObjectItemCaseSensitive(root, "maps");
    if (!cJSON_IsArray(maps) || cJSON_GetArraySize(maps) == 0)
        rc = tool_runtime_error("%s: maps: expected a non-empty array", path);
    for (const cJSON *e = maps ? maps->child : NULL; e && rc == EXIT_OK; e = e->next)
        rc = parse_map(s, e, path);

    const cJSON *scenes = NULL;
    s->scenes = suite_array(root, "scenes", path, sizeof *s->scenes, &scenes, &s->nscenes, &rc);
    for (int k = 0; rc == EXIT_OK && k < s->nscenes; k++) {
        const cJSON *e = cJSON_GetArrayItem(scenes, k);
        suite_scene *sc = &s->scenes[k];
        if (!cJSON_IsString(e) || !*e->valuestring) {
            rc = tool_runtime_error("%s: scenes[%d]: expected a built-in name or a file", path, k);
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

    const cJSON *budgets = NULL;
    s->budgets =
        suite_array(root, "budgets", path, sizeof *s->budgets, &budgets, &s->nbudgets, &rc);
    for (int k = 0; rc == EXIT_OK && k < s->nbudgets; k++) {
        const cJSON *e = cJSON_GetArrayItem(budgets, k);
        const cJSON *spp = cJSON_GetObjectItemCaseSensitive(e, "spp"),
                    *t = cJSON_GetObjectItemCaseSensitive(e, "time");
        suite_budget *b = &s->budgets[k];
        if (cJSON_IsNumber(spp) && !t && spp->valuedouble >= 1 && spp->valuedouble <= 1 << 20) {
            b->spp = spp->valueint;
            snprintf(b->label, sizeof b->label, "spp%d", b->spp);
        } else if (cJSON_IsNumber(t) && !spp && t->valuedouble > 0 && t->valuedouble <= 86400) {
            b->seconds = t->valuedouble;
            snprintf(b->label, sizeof b->label, "t%gs", b->seconds);
        } else {
            rc = tool_runtime_error("%s: budgets[%d]: expected {\"spp\": N} or {\"time\": "
                                    "SECONDS}",
                                    path, k);
        }
    }

    /* The reference: one method at many samples (default inversion, MIS balance). */
    const cJSON *ref = cJSON_GetObjectItemCaseSensitive(root, "reference");
    s->ref_spp = 1024;
    memset(&s->reference, 0, sizeof s->reference);
    s->reference.sampler.method = LUMIS_METHOD_INVERSION;
    snprintf(s->reference.label, sizeof s->reference.label, "reference");
    if (rc == EXIT_OK && ref) {
        const cJSON *spp = cJSON_GetObjectItemCaseSensitive(ref, "spp");
        if (cJSON_IsNumber(spp)) s->ref_spp = spp->valueint;
        if (cJSON_GetObjectItemCaseSensitive(ref, "method"))
            rc = parse_method(ref, &s->reference, path, "reference");
        if (s->ref_spp < 1 || s->ref_spp > 1 << 20)
            rc = tool_runtime_error("%s: reference.spp: expected 1 to 2^20", path);
    }
    v = cJSON_GetObjectItemCaseSensitive(root, "size");
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
    v = cJSON_GetObjectItemCaseSensitive(root, "seed");
    s->seed = cJSON_IsNumber(v) && v->valuedouble >= 0 ? (unsigned long long)v->valuedouble : 1;
    v = cJSON_GetObjectItemCaseSensitive(root, "bounces");
    s->bounces = cJSON_IsNumber(v) ? v->valueint : 0;
    if (rc == EXIT_OK && (s->bounces < 0 || s->bounces > 64))
        rc = tool_runtime_error("%s: bounces: expected 0 to 64", path);
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
    const cJSON *cmp = cJSON_GetObjectItemCaseSensitive(root, "compare");
    for (const cJSON *e = cmp ? cmp->child : NULL; e && rc == EXIT_OK; e = e->next) {
        if (s->ncompare == 8 || !cJSON_IsArray(e) || cJSON_GetArraySize(e) != 2 ||
            !cJSON_IsString(cJSON_GetArrayItem(e, 0)) ||
            !cJSON_IsString(cJSON_GetArrayItem(e, 1))) {
            rc = tool_runtime_error("%s: compare: expected up to 8 pairs [\"A\", \"B\"] of method "
                                    "labels",
                                    path);
            break;
        }
        for (int j = 0; j < 2; j++) {
            const char *lab = cJSON_GetArrayItem(e, j)->valuestring;
            int found = 0;
            for (int k = 0; k < s->nmethods; k++) found |= strcmp(s->methods[k].label, lab) == 0;
            if (!found) rc = tool_runtime_error("%s: compare: no method labelled '%s'", path, lab);
            snprintf(s->compare[s->ncompare][j], sizeof s->compare[0][0], "%s", lab);
        }
        s->ncompare++;
    }
    /* Labels name files: two items must never share one. */
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
    cJSON_Delete(root);
    if (rc != EXIT_OK) bench_suite_free(s);
    return rc;
}
