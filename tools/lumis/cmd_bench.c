/* lumis bench SUITE.json: renders every (map, scene, method, budget) of a suite, compares
 * each image with a cached high-spp reference, and writes results.csv, results.json, a
 * Markdown summary with mean errors and average rankings, convergence plots (SVG) and an
 * HTML page.  Work is resumable (an item is done when its result file exists), splits
 * into shards across machines, and runs in parallel processes with --jobs. */
#include "common.h"

#include <cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const char usage[] =
    "usage: lumis bench SUITE.json [--out DIR] [--jobs N] [--shard I/N] [--merge DIR...]\n"
    "                  [--report-only] [--threads N]\n\n"
    "Runs a benchmark suite (docs/bench.md has the format): for every map, scene, method\n"
    "and budget it renders an image, compares it with a reference of the same map and\n"
    "scene (rendered once at high spp and cached under DIR/refs by a hash of everything\n"
    "that makes it), and computes RMSE, relative MSE, PSNR, CIELAB Delta E, LDR-FLIP and\n"
    "HDR-FLIP.  Then it writes DIR/results.csv, results.json, results.md (means, average\n"
    "rankings, pairwise comparisons), convergence-*.svg and index.html.\n\n"
    "options:\n"
    "  --out DIR        output folder (default: bench-out/SUITE_NAME)\n"
    "  --jobs N         N render processes at once, each with cores/N threads (default 1;\n"
    "                   equal-time budgets are fairest with 1)\n"
    "  --shard I/N      only items I, I+N, I+2N, ... (0 <= I < N), for job arrays; writes no\n"
    "                   report: join the shards' folders with --merge\n"
    "  --merge DIR...   copy the results of other runs' folders into DIR, then report\n"
    "  --report-only    render nothing: report on the results DIR has\n"
    "  --threads N      render threads (default: all cores, divided by --jobs)\n\n"
    "An interrupted run resumes where it stopped: finished items are kept.\n";

/* ---- the suite ------------------------------------------------------------------------- */

typedef struct suite_map {
    char label[128], spec[4096];
    float rotation_deg, scale;
    int is_file;
} suite_map;

typedef struct suite_scene {
    char label[128], spec[4096]; /* a built-in name or a resolved file path */
    int is_file;
} suite_scene;

typedef struct suite_method {
    char label[128];
    lumis_sampler_desc sampler;
    int bsdf_only;
    lumis_estimator estimator;
    int power, light_samples, bsdf_samples;
} suite_method;

typedef struct suite_budget {
    char label[64];
    int spp;
    double seconds;
} suite_budget;

typedef struct suite {
    char name[128], description[1024], dir[4096];
    suite_map *maps;
    suite_scene *scenes;
    suite_method *methods, reference;
    suite_budget *budgets;
    int nmaps, nscenes, nmethods, nbudgets;
    int ref_spp, width, height, bounces, flip_hdr;
    unsigned long long seed;
    float exposure_ev, preview_ev;
    int exposure_auto, preview_auto; /* "auto": per reference, its mean luminance to 0.18 */
    char compare[8][2][128];         /* pairs of method labels to compare in the report */
    int ncompare;
} suite;

static void suite_free(suite *s)
{
    free(s->maps);
    free(s->scenes);
    free(s->methods);
    free(s->budgets);
}

/* Copies at most cap - 1 bytes (a cut label is still a label). */
static void copy_cut(char *out, size_t cap, const char *in)
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
        copy_cut(out, cap, name);
        return;
    }
    copy_cut(out, cap, s->dir);
    size_t n = strlen(out);
    if (n + 1 < cap) out[n++] = '/';
    copy_cut(out + n, cap - n, name);
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
    copy_cut(tmp, sizeof tmp, base);
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
    copy_cut(tmp, sizeof tmp, cJSON_IsString(label) ? label->valuestring : name->valuestring);
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

static int parse_suite(const char *path, suite *s)
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
    copy_cut(base, sizeof base, slash ? slash + 1 : path);
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
        copy_cut(tmp, sizeof tmp, b ? b + 1 : e->valuestring);
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
    if (rc != EXIT_OK) suite_free(s);
    return rc;
}

/* ---- items and hashes -------------------------------------------------------------------- */

typedef struct item {
    int map, scene, method, budget;
    char id[600];
} item;

static int nitems(const suite *s)
{
    return s->nmaps * s->nscenes * s->nmethods * s->nbudgets;
}

static item item_at(const suite *s, int index)
{
    item it;
    it.budget = index % s->nbudgets;
    index /= s->nbudgets;
    it.method = index % s->nmethods;
    index /= s->nmethods;
    it.scene = index % s->nscenes;
    it.map = index / s->nscenes;
    snprintf(it.id, sizeof it.id, "%s__%s__%s__%s", s->maps[it.map].label,
             s->scenes[it.scene].label, s->methods[it.method].label, s->budgets[it.budget].label);
    return it;
}

static uint64_t fnv(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t k = 0; k < n; k++) h = (h ^ p[k]) * 0x100000001b3ull;
    return h;
}

static uint64_t fnv_str(uint64_t h, const char *s)
{
    return fnv(h, s, strlen(s) + 1);
}

/* A file's bytes into the hash (a missing file hashes its name, and fails later). */
static uint64_t fnv_file(uint64_t h, const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return fnv_str(h, path);
    unsigned char buf[65536];
    for (size_t n; (n = fread(buf, 1, sizeof buf, f)) > 0;) h = fnv(h, buf, n);
    fclose(f);
    return h;
}

/* Everything that makes a reference image: the map's content, its rotation and scale,
 * the scene (a file's content; a built-in's name and lumis' version), the size, the
 * reference's method, samples, bounces and seed. */
static void reference_key(const suite *s, int m, int sc, char *out, size_t cap)
{
    uint64_t h = 0xcbf29ce484222325ull;
    h = fnv_str(h, "lumis-reference-v1");
    h = fnv_str(h, LUMIS_VERSION_STRING);
    const suite_map *map = &s->maps[m];
    h = map->is_file ? fnv_file(h, map->spec) : fnv_str(h, map->spec);
    char buf[512];
    snprintf(buf, sizeof buf, "%.9g %.9g %d %d %d %d %d %d %d %d %d %d %llu", map->rotation_deg,
             map->scale, s->width, s->height, s->ref_spp, (int)s->reference.sampler.method,
             s->reference.sampler.kdtree_blocks, s->reference.bsdf_only,
             (int)s->reference.estimator * 2 + s->reference.power, s->reference.light_samples,
             s->reference.bsdf_samples, s->bounces, s->seed);
    h = fnv_str(h, buf);
    const suite_scene *scene = &s->scenes[sc];
    h = scene->is_file ? fnv_file(h, scene->spec) : fnv_str(h, scene->spec);
    snprintf(out, cap, "%016llx", (unsigned long long)h);
}

/* Everything an item's result depends on besides its reference: the method, the budget,
 * the seed, the metrics' settings.  Stored in the result; a result whose key differs
 * (the suite changed under the same labels) is stale and redone. */
static void item_key(const suite *s, const item *it, char *out, size_t cap)
{
    char ref[32], buf[1024];
    reference_key(s, it->map, it->scene, ref, sizeof ref);
    const suite_method *m = &s->methods[it->method];
    const suite_budget *b = &s->budgets[it->budget];
    snprintf(buf, sizeof buf,
             "lumis-item-v1 %s %s %d %d %d %d %d %d %d %d %.9g %llu %d %d %d %.9g %d %d %.9g",
             LUMIS_VERSION_STRING, ref, (int)m->sampler.method, m->sampler.kdtree_blocks,
             m->sampler.compensate, m->bsdf_only, (int)m->estimator, m->power, m->light_samples,
             m->bsdf_samples, b->seconds, s->seed, b->spp, s->width, s->height, s->exposure_ev,
             s->exposure_auto, s->flip_hdr, s->preview_ev);
    uint64_t h = fnv_str(0xcbf29ce484222325ull, buf);
    snprintf(out, cap, "%016llx", (unsigned long long)h);
}

/* The item's result file, parsed, if it exists and belongs to the suite as it is now. */
static cJSON *load_item(const suite *s, const char *out, const item *it)
{
    char path[8800];
    snprintf(path, sizeof path, "%s/results/%s.json", out, it->id);
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char buf[16384];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    cJSON *j = cJSON_ParseWithLength(buf, n);
    char key[32];
    item_key(s, it, key, sizeof key);
    const cJSON *k = cJSON_GetObjectItemCaseSensitive(j, "item_key");
    if (!cJSON_IsString(k) || strcmp(k->valuestring, key) != 0) {
        cJSON_Delete(j);
        return NULL;
    }
    return j;
}

static int item_done(const suite *s, const char *out, const item *it)
{
    cJSON *j = load_item(s, out, it);
    cJSON_Delete(j);
    return j != NULL;
}

/* Shards split the (map, scene) pairs when there are enough of them, so that each
 * reference is rendered by one shard only; otherwise the items. */
static int in_shard(const suite *s, int k, long shard_i, long shard_n)
{
    const int pairs = s->nmaps * s->nscenes;
    if (pairs >= shard_n) return (k / (s->nmethods * s->nbudgets)) % shard_n == shard_i;
    return k % shard_n == shard_i;
}

/* ---- running ------------------------------------------------------------------------------- */

typedef struct run_ctx {
    const suite *s;
    const char *out;
    int threads;
    int argc;
    char **argv;
} run_ctx;

static int file_exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

/* mkdir -p */
static int make_dir(const char *path)
{
    char buf[8800];
    copy_cut(buf, sizeof buf, path);
    for (char *p = buf + 1; *p; p++)
        if (*p == '/') {
            *p = '\0';
            if (mkdir(buf, 0755) != 0 && errno != EEXIST)
                return tool_runtime_error("%s: cannot create folder: %s", buf, strerror(errno));
            *p = '/';
        }
    if (mkdir(buf, 0755) == 0 || errno == EEXIST) return EXIT_OK;
    return tool_runtime_error("%s: cannot create folder: %s", path, strerror(errno));
}

static void fill_render_opts(const run_ctx *c, const item *it, const suite_method *m,
                             tool_render_opts *o)
{
    const suite *s = c->s;
    memset(o, 0, sizeof *o);
    const suite_scene *sc = &s->scenes[it->scene];
    if (sc->is_file)
        o->scene_path = sc->spec;
    else
        o->scene_name = sc->spec;
    o->envspec = s->maps[it->map].spec;
    o->rotation_deg = s->maps[it->map].rotation_deg;
    o->scale = s->maps[it->map].scale;
    o->sampler = m->sampler;
    o->bsdf_only = m->bsdf_only;
    o->rd.estimator = m->estimator;
    o->rd.power_heuristic = m->power;
    o->rd.light_samples = m->light_samples;
    o->rd.bsdf_samples = m->bsdf_samples;
    o->rd.seed = s->seed;
    o->rd.threads = c->threads;
    o->rd.max_bounces = s->bounces;
    o->width = s->width;
    o->height = s->height;
    o->quiet = 1;
    o->argc = c->argc;
    o->argv = c->argv;
    o->png_options.exposure_ev = s->preview_ev;
    o->png_options.tonemap = LUMIS_TONEMAP_ACES;
}

static int ensure_reference(const run_ctx *c, int m, int sc, char *exr, size_t cap)
{
    const suite *s = c->s;
    char key[32], png[8800];
    reference_key(s, m, sc, key, sizeof key);
    snprintf(exr, cap, "%s/refs/%s.exr", c->out, key);
    snprintf(png, sizeof png, "%s/refs/%s.png", c->out, key);
    if (file_exists(exr)) { /* cached; its preview follows the suite's current settings */
        lumis_image *img = NULL;
        if (tool_load_image(exr, &img, NULL) != LUMIS_OK) return EXIT_RUNTIME;
        lumis_write_options wo = {0};
        wo.tonemap = LUMIS_TONEMAP_ACES;
        wo.exposure_ev = s->preview_auto ? tool_auto_exposure(img) : s->preview_ev;
        int rc = tool_write_image(png, img, &wo) == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
        lumis_image_destroy(img);
        return rc;
    }
    item it = {m, sc, 0, 0, ""};
    tool_render_opts o;
    fill_render_opts(c, &it, &s->reference, &o);
    o.rd.spp = s->ref_spp;
    o.rd.seed = s->seed + 0x5eedull; /* independent of every test image */
    o.out = exr;
    o.png = png;
    fprintf(stderr, "lumis bench: reference %s / %s: %d spp ...\n", s->maps[m].label,
            s->scenes[sc].label, s->ref_spp);
    if (s->preview_auto) o.png = NULL; /* written below, once the exposure is known */
    tool_render_result r;
    int rc = tool_render(&o, &r);
    if (rc == EXIT_OK && s->preview_auto) {
        lumis_write_options wo = o.png_options;
        wo.exposure_ev = tool_auto_exposure(r.image);
        if (tool_write_image(png, r.image, &wo) != LUMIS_OK) rc = EXIT_RUNTIME;
    }
    lumis_image_destroy(r.image);
    return rc;
}

static int run_item(const run_ctx *c, const item *it, int index, int total)
{
    const suite *s = c->s;
    char result[8800], exr[8800], png[8800], flip_png[8800], ref_exr[8800];
    snprintf(result, sizeof result, "%s/results/%s.json", c->out, it->id);
    if (item_done(s, c->out, it)) return EXIT_OK; /* resumed: done before */
    char key[32];
    reference_key(s, it->map, it->scene, key, sizeof key);
    snprintf(ref_exr, sizeof ref_exr, "%s/refs/%s.exr", c->out, key);
    snprintf(exr, sizeof exr, "%s/renders/%s.exr", c->out, it->id);
    snprintf(png, sizeof png, "%s/previews/%s.png", c->out, it->id);
    snprintf(flip_png, sizeof flip_png, "%s/previews/%s-flip.png", c->out, it->id);
    const suite_budget *b = &s->budgets[it->budget];
    lumis_image *ref = NULL;
    if (tool_load_image(ref_exr, &ref, NULL) != LUMIS_OK) return EXIT_RUNTIME;
    const float ref_ev = tool_auto_exposure(ref), ev = s->exposure_auto ? ref_ev : s->exposure_ev;
    tool_render_opts o;
    fill_render_opts(c, it, &s->methods[it->method], &o);
    o.rd.spp = b->spp;
    o.time_budget = b->seconds;
    o.out = exr;
    o.png = png;
    if (s->preview_auto) o.png_options.exposure_ev = ref_ev;
    tool_render_result r;
    if (tool_render(&o, &r) != EXIT_OK) {
        lumis_image_destroy(ref);
        return EXIT_RUNTIME;
    }
    int rc = EXIT_RUNTIME;
    float *map = malloc(sizeof(float) * (size_t)r.image->width * (size_t)r.image->height);
    tool_metrics m;
    if (map && tool_compare_images(ref, r.image, ev, 0.0, s->flip_hdr, &m, map) == EXIT_OK &&
        tool_write_flip_map(flip_png, map, r.image->width, r.image->height) == EXIT_OK) {
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "id", it->id);
        cJSON_AddStringToObject(j, "suite", s->name);
        cJSON_AddStringToObject(j, "map", s->maps[it->map].label);
        cJSON_AddStringToObject(j, "scene", s->scenes[it->scene].label);
        cJSON_AddStringToObject(j, "method", s->methods[it->method].label);
        cJSON_AddStringToObject(j, "budget", b->label);
        cJSON_AddStringToObject(j, "reference", key);
        char ikey[32];
        item_key(s, it, ikey, sizeof ikey);
        cJSON_AddStringToObject(j, "item_key", ikey);
        cJSON_AddNumberToObject(j, "spp", r.stats.spp);
        cJSON_AddNumberToObject(j, "render_seconds", r.stats.seconds);
        /* BSDF sampling builds no light sampler worth counting (the CLI makes one anyway). */
        const int bsdf = s->methods[it->method].bsdf_only;
        cJSON_AddNumberToObject(j, "sampler_build_ms", bsdf ? 0.0 : r.sampler_build_ms);
        cJSON_AddNumberToObject(j, "sampler_table_bytes",
                                bsdf ? 0.0 : (double)r.sampler_table_bytes);
        cJSON_AddNumberToObject(j, "shadow_rays", r.stats.shadow_rays);
        cJSON_AddNumberToObject(j, "threads", r.stats.threads);
        tool_metrics_json(&m, j);
        rc = tool_write_json(result, j); /* last: its existence marks the item done */
        cJSON_Delete(j);
        fprintf(stderr, "[%d/%d] %s: %d spp in %.2f s, relmse %.4g, flip_ldr %.4f\n", index + 1,
                total, it->id, r.stats.spp, r.stats.seconds, m.err.relmse, m.flip_ldr);
    }
    free(map);
    lumis_image_destroy(ref);
    lumis_image_destroy(r.image);
    return rc;
}

/* ---- the report --------------------------------------------------------------------------------
 */

enum { M_RMSE, M_RELMSE, M_PSNR, M_LAB, M_FLIP_LDR, M_FLIP_HDR, NMETRICS };
static const char *const metric_key[NMETRICS] = {"rmse",        "relmse",   "psnr",
                                                 "lab_delta_e", "flip_ldr", "flip_hdr"};
static const char *const metric_title[NMETRICS] = {"RMSE",   "relMSE",   "PSNR dB",
                                                   "Lab ΔE", "FLIP-LDR", "FLIP-HDR"};

typedef struct result {
    int present;
    double v[NMETRICS];
    double seconds, build_ms, table_bytes;
    int spp;
} result;

static double jnum(const cJSON *o, const char *k)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, k);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static int load_results(const suite *s, const char *out, result *res)
{
    int found = 0;
    for (int k = 0; k < nitems(s); k++) {
        item it = item_at(s, k);
        res[k].present = 0;
        cJSON *j = load_item(s, out, &it); /* stale results (other settings) are left out */
        if (!j) continue;
        for (int m = 0; m < NMETRICS; m++) res[k].v[m] = jnum(j, metric_key[m]);
        if (isnan(res[k].v[M_PSNR]) && res[k].v[M_RMSE] == 0.0) res[k].v[M_PSNR] = INFINITY;
        res[k].seconds = jnum(j, "render_seconds");
        res[k].build_ms = jnum(j, "sampler_build_ms");
        res[k].table_bytes = jnum(j, "sampler_table_bytes");
        res[k].spp = (int)jnum(j, "spp");
        res[k].present = 1;
        found++;
        cJSON_Delete(j);
    }
    return found;
}

static int idx(const suite *s, int m, int sc, int me, int b)
{
    return ((m * s->nscenes + sc) * s->nmethods + me) * s->nbudgets + b;
}

/* Ranks of the methods in one (map, scene, budget) group, 1 = best, ties share the mean
 * rank; NaN where a result is missing. */
static void rank_group(const suite *s, const result *res, int m, int sc, int b, int metric,
                       double *ranks)
{
    int higher_better = metric == M_PSNR;
    for (int a = 0; a < s->nmethods; a++) {
        const result *ra = &res[idx(s, m, sc, a, b)];
        if (!ra->present || isnan(ra->v[metric])) {
            ranks[a] = NAN;
            continue;
        }
        double better = 0, ties = 0;
        for (int o = 0; o < s->nmethods; o++) {
            const result *ro = &res[idx(s, m, sc, o, b)];
            if (o == a || !ro->present || isnan(ro->v[metric])) continue;
            double x = ra->v[metric], y = ro->v[metric];
            if (higher_better ? y > x : y < x)
                better++;
            else if (y == x)
                ties++;
        }
        ranks[a] = 1.0 + better + 0.5 * ties;
    }
}

typedef struct summary {
    double mean[NMETRICS], rank[NMETRICS], seconds, spp, build_ms, table_bytes;
    int n;
} summary;

static void summarize(const suite *s, const result *res, int b, summary *out)
{
    for (int me = 0; me < s->nmethods; me++) memset(&out[me], 0, sizeof out[me]);
    double *ranks = calloc((size_t)s->nmethods, sizeof *ranks);
    int *rank_n = calloc((size_t)s->nmethods * NMETRICS, sizeof *rank_n);
    if (!ranks || !rank_n) {
        free(ranks);
        free(rank_n);
        return;
    }
    for (int m = 0; m < s->nmaps; m++)
        for (int sc = 0; sc < s->nscenes; sc++) {
            for (int metric = 0; metric < NMETRICS; metric++) {
                rank_group(s, res, m, sc, b, metric, ranks);
                for (int me = 0; me < s->nmethods; me++)
                    if (!isnan(ranks[me])) {
                        out[me].rank[metric] += ranks[me];
                        rank_n[me * NMETRICS + metric]++;
                    }
            }
            for (int me = 0; me < s->nmethods; me++) {
                const result *r = &res[idx(s, m, sc, me, b)];
                if (!r->present) continue;
                for (int metric = 0; metric < NMETRICS; metric++)
                    out[me].mean[metric] += r->v[metric];
                out[me].seconds += r->seconds;
                out[me].spp += r->spp;
                out[me].build_ms += r->build_ms;
                out[me].table_bytes += r->table_bytes;
                out[me].n++;
            }
        }
    for (int me = 0; me < s->nmethods; me++) {
        summary *u = &out[me];
        if (u->n) {
            for (int metric = 0; metric < NMETRICS; metric++) u->mean[metric] /= u->n;
            u->seconds /= u->n;
            u->spp /= u->n;
            u->build_ms /= u->n;
            u->table_bytes /= u->n;
        }
        for (int metric = 0; metric < NMETRICS; metric++) {
            int n = rank_n[me * NMETRICS + metric];
            u->rank[metric] = n ? u->rank[metric] / n : NAN;
        }
    }
    free(ranks);
    free(rank_n);
}

static int method_index(const suite *s, const char *label)
{
    for (int k = 0; k < s->nmethods; k++)
        if (strcmp(s->methods[k].label, label) == 0) return k;
    return -1;
}

static void machine_facts(char *out, size_t cap)
{
    char model[256] = "unknown CPU";
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, "model name", 10) == 0) {
            const char *colon = strchr(line, ':');
            if (colon) snprintf(model, sizeof model, "%s", colon + 2);
            model[strcspn(model, "\n")] = '\0';
            break;
        }
    if (f) fclose(f);
    snprintf(out, cap, "%s, %ld cores", model, sysconf(_SC_NPROCESSORS_ONLN));
}

/* Pairwise verdicts: for each budget, in how many (map, scene) pairs A beats B on relMSE
 * and FLIP, the geometric mean of the relMSE ratio, and the pairs where A loses. */
static void write_comparisons(FILE *md, const suite *s, const result *res)
{
    for (int c = 0; c < s->ncompare; c++) {
        int a = method_index(s, s->compare[c][0]), bm = method_index(s, s->compare[c][1]);
        if (a < 0 || bm < 0) continue;
        fprintf(md, "\n## %s against %s\n\n", s->methods[a].label, s->methods[bm].label);
        fprintf(
            md,
            "| budget | pairs | %s better (relMSE) | relMSE ratio %s/%s (geometric mean) "
            "| %s better (FLIP-LDR) | %s loses on (relMSE ratio) |\n|---|---|---|---|---|---|\n",
            s->methods[a].label, s->methods[a].label, s->methods[bm].label, s->methods[a].label,
            s->methods[a].label);
        for (int b = 0; b < s->nbudgets; b++) {
            int pairs = 0, wins = 0, flip_wins = 0, flip_pairs = 0;
            double logsum = 0;
            char losses[4096] = "";
            for (int m = 0; m < s->nmaps; m++)
                for (int sc = 0; sc < s->nscenes; sc++) {
                    const result *ra = &res[idx(s, m, sc, a, b)], *rb = &res[idx(s, m, sc, bm, b)];
                    if (!ra->present || !rb->present) continue;
                    double x = ra->v[M_RELMSE], y = rb->v[M_RELMSE];
                    if (!(x > 0 && y > 0)) continue;
                    pairs++;
                    logsum += log(x / y);
                    if (x < y) {
                        wins++;
                    } else {
                        size_t len = strlen(losses);
                        snprintf(losses + len, sizeof losses - len, "%s%s/%s (%.2f)",
                                 len ? ", " : "", s->maps[m].label, s->scenes[sc].label, x / y);
                    }
                    if (!isnan(ra->v[M_FLIP_LDR]) && !isnan(rb->v[M_FLIP_LDR])) {
                        flip_pairs++;
                        flip_wins += ra->v[M_FLIP_LDR] < rb->v[M_FLIP_LDR];
                    }
                }
            if (!pairs) continue;
            fprintf(md, "| %s | %d | %d of %d | %.3f | %d of %d | %s |\n", s->budgets[b].label,
                    pairs, wins, pairs, exp(logsum / pairs), flip_wins, flip_pairs,
                    losses[0] ? losses : "none");
        }
        fprintf(md, "\nA ratio below 1 means %s has the smaller error.\n", s->methods[a].label);
        /* Memory: the sampling tables, averaged over every item of the two methods. */
        double ta = 0, tb = 0;
        int na = 0, nb = 0;
        for (int k = 0; k < nitems(s); k++) {
            item it = item_at(s, k);
            if (!res[k].present || !(res[k].table_bytes > 0)) continue;
            if (it.method == a) ta += res[k].table_bytes, na++;
            if (it.method == bm) tb += res[k].table_bytes, nb++;
        }
        if (na && nb)
            fprintf(md,
                    "\nSampling tables: %s %.0f bytes, %s %.0f bytes on average: %s's are %.1f "
                    "times %s.\n",
                    s->methods[a].label, ta / na, s->methods[bm].label, tb / nb,
                    s->methods[a].label, ta / na <= tb / nb ? tb / ta * na / nb : ta / tb * nb / na,
                    ta / na <= tb / nb ? "smaller" : "larger");
    }
}

/* Writes a text built in a FILE* (tmpfile) atomically to path. */
static int commit_tmp(FILE *f, const char *path)
{
    long n = ftell(f);
    char *text = n >= 0 ? malloc((size_t)n + 1) : NULL;
    rewind(f);
    int rc = EXIT_RUNTIME;
    if (text && fread(text, 1, (size_t)n, f) == (size_t)n &&
        lumis_write_text(path, text, (size_t)n, &tool_errors) == LUMIS_OK)
        rc = EXIT_OK;
    free(text);
    fclose(f);
    return rc;
}

static const char *const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                      "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

/* relMSE (mean over maps) against render time (mean over maps), log-log, per scene. */
static int write_svg(const char *path, const suite *s, const result *res, int sc)
{
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    double *px = calloc((size_t)s->nmethods * (size_t)s->nbudgets * 2, sizeof *px);
    if (!px) return tool_runtime_error("bench: out of memory");
    for (int me = 0; me < s->nmethods; me++)
        for (int b = 0; b < s->nbudgets; b++) {
            double t = 0, e = 0;
            int n = 0;
            for (int m = 0; m < s->nmaps; m++) {
                const result *r = &res[idx(s, m, sc, me, b)];
                if (!r->present || !(r->v[M_RELMSE] > 0) || !(r->seconds > 0)) continue;
                t += r->seconds;
                e += r->v[M_RELMSE];
                n++;
            }
            double *p = px + 2 * (me * s->nbudgets + b);
            p[0] = n ? log10(t / n) : NAN;
            p[1] = n ? log10(e / n) : NAN;
            if (n) {
                xmin = fmin(xmin, p[0]);
                xmax = fmax(xmax, p[0]);
                ymin = fmin(ymin, p[1]);
                ymax = fmax(ymax, p[1]);
            }
        }
    if (!isfinite(xmin)) { /* nothing to plot: no stale plot either */
        free(px);
        unlink(path);
        return EXIT_OK;
    }
    xmin = floor(xmin - 0.05), xmax = ceil(xmax + 0.05);
    ymin = floor(ymin - 0.05), ymax = ceil(ymax + 0.05);
    const double W = 640, H = 420, L = 70, R = 170, T = 30, B = 50;
    FILE *f = tmpfile();
    if (!f) {
        free(px);
        return tool_runtime_error("%s: cannot write a temporary file", path);
    }
#define X(v) (L + ((v)-xmin) / (xmax - xmin) * (W - L - R))
#define Y(v) (H - B - ((v)-ymin) / (ymax - ymin) * (H - T - B))
    fprintf(f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" "
            "viewBox=\"0 0 %g %g\" font-family=\"sans-serif\" font-size=\"12\">\n"
            "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
            "<text x=\"%g\" y=\"18\" font-size=\"14\">%s: relMSE vs render time (means over "
            "maps)</text>\n",
            W, H, W, H, L, s->scenes[sc].label);
    for (double d = xmin; d <= xmax + 1e-9; d += 1)
        fprintf(f,
                "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>"
                "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">1e%g s</text>\n",
                X(d), T, X(d), H - B, X(d), H - B + 16, d);
    for (double d = ymin; d <= ymax + 1e-9; d += 1)
        fprintf(f,
                "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">1e%g</text>\n",
                L, Y(d), W - R, Y(d), L - 6, Y(d) + 4, d);
    fprintf(f,
            "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">render time (log)</text>\n"
            "<text x=\"16\" y=\"%g\" transform=\"rotate(-90 16 %g)\" "
            "text-anchor=\"middle\">relMSE (log)</text>\n",
            (L + W - R) / 2, H - 12, (T + H - B) / 2, (T + H - B) / 2);
    for (int me = 0; me < s->nmethods; me++) {
        const char *col = palette[me % 8];
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"", col);
        for (int b = 0; b < s->nbudgets; b++) {
            const double *p = px + 2 * (me * s->nbudgets + b);
            if (!isnan(p[0])) fprintf(f, "%.1f,%.1f ", X(p[0]), Y(p[1]));
        }
        fprintf(f, "\"/>\n");
        for (int b = 0; b < s->nbudgets; b++) {
            const double *p = px + 2 * (me * s->nbudgets + b);
            if (!isnan(p[0]))
                fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"%s\"/>\n", X(p[0]),
                        Y(p[1]), col);
        }
        fprintf(f,
                "<rect x=\"%g\" y=\"%d\" width=\"14\" height=\"4\" fill=\"%s\"/>"
                "<text x=\"%g\" y=\"%d\">%s</text>\n",
                W - R + 14, 40 + 18 * me, col, W - R + 34, 45 + 18 * me, s->methods[me].label);
    }
#undef X
#undef Y
    fprintf(f, "</svg>\n");
    free(px);
    return commit_tmp(f, path);
}

static void fmt_metric(char *buf, size_t cap, double v, int metric)
{
    if (isnan(v))
        snprintf(buf, cap, "–");
    else if (isinf(v))
        snprintf(buf, cap, "∞");
    else if (metric == M_PSNR)
        snprintf(buf, cap, "%.2f", v);
    else
        snprintf(buf, cap, "%.4g", v);
}

static void html_escape(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '<')
            fputs("&lt;", f);
        else if (*s == '>')
            fputs("&gt;", f);
        else if (*s == '&')
            fputs("&amp;", f);
        else if (*s == '"')
            fputs("&quot;", f);
        else
            fputc(*s, f);
    }
}

static int write_report(const suite *s, const char *out, int argc, char **argv)
{
    const int n = nitems(s);
    result *res = calloc((size_t)n, sizeof *res);
    summary *sum = calloc((size_t)s->nmethods * (size_t)s->nbudgets, sizeof *sum);
    if (!res || !sum) {
        free(res);
        free(sum);
        return tool_runtime_error("bench: out of memory");
    }
    int found = load_results(s, out, res);
    for (int b = 0; b < s->nbudgets; b++) summarize(s, res, b, sum + b * s->nmethods);
    char machine[400], cmd[4096] = "lumis", date[64], path[8800];
    machine_facts(machine, sizeof machine);
    for (int k = 0; k < argc; k++) {
        size_t len = strlen(cmd);
        snprintf(cmd + len, sizeof cmd - len, " %s", argv[k]);
    }
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", gmtime(&now));
    int rc = EXIT_OK;

    /* results.csv */
    FILE *f = tmpfile();
    if (!f) rc = tool_runtime_error("bench: cannot write a temporary file");
    if (f) {
        fprintf(f, "map,scene,method,budget,spp,render_seconds,sampler_build_ms,"
                   "sampler_table_bytes");
        for (int m = 0; m < NMETRICS; m++) fprintf(f, ",%s", metric_key[m]);
        fprintf(f, "\n");
        for (int k = 0; k < n; k++) {
            if (!res[k].present) continue;
            item it = item_at(s, k);
            fprintf(f, "%s,%s,%s,%s,%d,%.6g,%.6g,%.0f", s->maps[it.map].label,
                    s->scenes[it.scene].label, s->methods[it.method].label,
                    s->budgets[it.budget].label, res[k].spp, res[k].seconds, res[k].build_ms,
                    res[k].table_bytes);
            for (int m = 0; m < NMETRICS; m++) fprintf(f, ",%.9g", res[k].v[m]);
            fprintf(f, "\n");
        }
        snprintf(path, sizeof path, "%s/results.csv", out);
        if (commit_tmp(f, path) != EXIT_OK) rc = EXIT_RUNTIME;
    }

    /* results.json */
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "suite", s->name);
    cJSON_AddStringToObject(j, "description", s->description);
    cJSON_AddStringToObject(j, "command", cmd);
    cJSON_AddStringToObject(j, "lumis_version", LUMIS_VERSION_STRING);
    cJSON_AddStringToObject(j, "machine", machine);
    cJSON_AddStringToObject(j, "date", date);
    cJSON_AddNumberToObject(j, "items", n);
    cJSON_AddNumberToObject(j, "items_done", found);
    if (s->exposure_auto)
        cJSON_AddStringToObject(j, "exposure_ev", "auto");
    else
        cJSON_AddNumberToObject(j, "exposure_ev", s->exposure_ev);
    cJSON_AddNumberToObject(j, "reference_spp", s->ref_spp);
    cJSON *jsum = cJSON_AddArrayToObject(j, "summary");
    for (int b = 0; b < s->nbudgets; b++)
        for (int me = 0; me < s->nmethods; me++) {
            const summary *u = &sum[b * s->nmethods + me];
            cJSON *o = cJSON_CreateObject();
            cJSON_AddStringToObject(o, "budget", s->budgets[b].label);
            cJSON_AddStringToObject(o, "method", s->methods[me].label);
            cJSON_AddNumberToObject(o, "n", u->n);
            cJSON_AddNumberToObject(o, "mean_spp", u->spp);
            cJSON_AddNumberToObject(o, "mean_render_seconds", u->seconds);
            cJSON_AddNumberToObject(o, "mean_sampler_build_ms", u->build_ms);
            cJSON_AddNumberToObject(o, "mean_sampler_table_bytes", u->table_bytes);
            for (int m = 0; m < NMETRICS; m++) {
                char key[64];
                snprintf(key, sizeof key, "mean_%s", metric_key[m]);
                if (isfinite(u->mean[m]))
                    cJSON_AddNumberToObject(o, key, u->mean[m]);
                else
                    cJSON_AddNullToObject(o, key);
                snprintf(key, sizeof key, "rank_%s", metric_key[m]);
                if (isfinite(u->rank[m]))
                    cJSON_AddNumberToObject(o, key, u->rank[m]);
                else
                    cJSON_AddNullToObject(o, key);
            }
            cJSON_AddItemToArray(jsum, o);
        }
    snprintf(path, sizeof path, "%s/results.json", out);
    if (tool_write_json(path, j) != EXIT_OK) rc = EXIT_RUNTIME;
    cJSON_Delete(j);

    /* results.md */
    FILE *md = tmpfile();
    if (!md) rc = tool_runtime_error("bench: cannot write a temporary file");
    if (md) {
        fprintf(md, "# lumis bench: %s\n\n", s->name);
        if (s->description[0]) fprintf(md, "%s\n\n", s->description);
        char expo[128];
        if (s->exposure_auto)
            snprintf(expo, sizeof expo, "2^EV with EV per reference, its mean luminance to 0.18");
        else
            snprintf(expo, sizeof expo, "2^%g", s->exposure_ev);
        fprintf(md,
                "- command: `%s`\n- lumis %s, %s\n- machine: %s\n- %d of %d items (%d maps × %d "
                "scenes × %d methods × %d budgets)%s\n- reference: %d spp, %s; errors against "
                "it, lower is better except PSNR\n- RMSE, relMSE (ε = 0.01), PSNR: linear HDR "
                "values, PSNR peak = the reference's largest value; Lab ΔE (CIE76, D65) and "
                "FLIP-LDR on values × %s, clamped to [0, 1]; FLIP-HDR with the reference's "
                "exposure range and ACES; 67.02 pixels per degree\n",
                cmd, LUMIS_VERSION_STRING, date, machine, found, n, s->nmaps, s->nscenes,
                s->nmethods, s->nbudgets,
                found < n ? " — **incomplete**: run the remaining shards" : "", s->ref_spp,
                s->reference.bsdf_only ? "BSDF sampling"
                                       : lumis_sampler_method_name(s->reference.sampler.method),
                expo);
        for (int b = 0; b < s->nbudgets; b++) {
            const suite_budget *bu = &s->budgets[b];
            if (bu->spp)
                fprintf(md, "\n## Budget: %d samples per pixel\n\n", bu->spp);
            else
                fprintf(md, "\n## Budget: %g s of rendering (equal time)\n\n", bu->seconds);
            fprintf(md,
                    "Means over (map, scene) pairs; rank = average rank per pair (1 = best).\n\n"
                    "| method | n | spp | render s | build ms | table bytes |");
            for (int m = 0; m < NMETRICS; m++) fprintf(md, " %s |", metric_title[m]);
            for (int m = 0; m < NMETRICS; m++)
                if (m != M_RMSE && m != M_PSNR) fprintf(md, " rank %s |", metric_title[m]);
            fprintf(md, "\n|---|---|---|---|---|---|");
            for (int m = 0; m < 2 * NMETRICS - 2; m++) fprintf(md, "---|");
            fprintf(md, "\n");
            for (int me = 0; me < s->nmethods; me++) {
                const summary *u = &sum[b * s->nmethods + me];
                fprintf(md, "| %s | %d | %.1f | %.3f | %.2f | %.0f |", s->methods[me].label, u->n,
                        u->spp, u->seconds, u->build_ms, u->table_bytes);
                char buf[64];
                for (int m = 0; m < NMETRICS; m++) {
                    fmt_metric(buf, sizeof buf, u->n ? u->mean[m] : NAN, m);
                    fprintf(md, " %s |", buf);
                }
                for (int m = 0; m < NMETRICS; m++)
                    if (m != M_RMSE && m != M_PSNR) {
                        if (isnan(u->rank[m]))
                            fprintf(md, " – |");
                        else
                            fprintf(md, " %.2f |", u->rank[m]);
                    }
                fprintf(md, "\n");
            }
        }
        write_comparisons(md, s, res);
        /* Per map, relMSE at the last budget. */
        int lb = s->nbudgets - 1;
        fprintf(md, "\n## relMSE per map and scene (budget %s)\n\n| map | scene |",
                s->budgets[lb].label);
        for (int me = 0; me < s->nmethods; me++) fprintf(md, " %s |", s->methods[me].label);
        fprintf(md, "\n|---|---|");
        for (int me = 0; me < s->nmethods; me++) fprintf(md, "---|");
        fprintf(md, "\n");
        for (int m = 0; m < s->nmaps; m++)
            for (int sc = 0; sc < s->nscenes; sc++) {
                fprintf(md, "| %s | %s |", s->maps[m].label, s->scenes[sc].label);
                for (int me = 0; me < s->nmethods; me++) {
                    const result *r = &res[idx(s, m, sc, me, lb)];
                    char buf[64];
                    fmt_metric(buf, sizeof buf, r->present ? r->v[M_RELMSE] : NAN, M_RELMSE);
                    fprintf(md, " %s |", buf);
                }
                fprintf(md, "\n");
            }
        snprintf(path, sizeof path, "%s/results.md", out);
        if (commit_tmp(md, path) != EXIT_OK) rc = EXIT_RUNTIME;
    }

    /* convergence plots, one per scene */
    for (int sc = 0; sc < s->nscenes; sc++) {
        snprintf(path, sizeof path, "%s/convergence-%s.svg", out, s->scenes[sc].label);
        if (write_svg(path, s, res, sc) != EXIT_OK) rc = EXIT_RUNTIME;
    }

    /* index.html: tables, plots, and the image grid of the last budget */
    FILE *h = tmpfile();
    if (!h) rc = tool_runtime_error("bench: cannot write a temporary file");
    if (h) {
        fprintf(h,
                "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>lumis "
                "bench: ");
        html_escape(h, s->name);
        fprintf(h, "</title>\n<style>body{font-family:sans-serif;margin:24px;max-width:1400px}"
                   "table{border-collapse:collapse;margin:8px 0 20px}td,th{border:1px solid #ccc;"
                   "padding:3px 8px;text-align:right}th{background:#f3f3f3}td:first-child,"
                   "th:first-child{text-align:left}figure{display:inline-block;margin:4px;"
                   "text-align:center;font-size:12px;vertical-align:top}figure img{display:block;"
                   "max-width:260px;image-rendering:pixelated}.grid{margin-bottom:16px}"
                   "</style></head><body>\n<h1>lumis bench: ");
        html_escape(h, s->name);
        fprintf(h, "</h1>\n<p>");
        html_escape(h, s->description);
        fprintf(h, "</p>\n<p>Command: <code>");
        html_escape(h, cmd);
        fprintf(h,
                "</code><br>lumis %s, %s, %s. %d of %d items. Reference: %d spp. Errors "
                "against the reference; lower is better except PSNR. Details: "
                "<a href=\"results.md\">results.md</a>, <a href=\"results.csv\">results.csv</a>, "
                "<a href=\"results.json\">results.json</a>.</p>\n",
                LUMIS_VERSION_STRING, date, machine, found, n, s->ref_spp);
        for (int b = 0; b < s->nbudgets; b++) {
            fprintf(h,
                    "<h2>Budget %s</h2>\n<table><tr><th>method</th><th>n</th><th>spp</th>"
                    "<th>render s</th>",
                    s->budgets[b].label);
            for (int m = 0; m < NMETRICS; m++) fprintf(h, "<th>%s</th>", metric_title[m]);
            fprintf(h, "<th>rank relMSE</th><th>rank FLIP-LDR</th></tr>\n");
            for (int me = 0; me < s->nmethods; me++) {
                const summary *u = &sum[b * s->nmethods + me];
                fprintf(h, "<tr><td>%s</td><td>%d</td><td>%.1f</td><td>%.3f</td>",
                        s->methods[me].label, u->n, u->spp, u->seconds);
                char buf[64];
                for (int m = 0; m < NMETRICS; m++) {
                    fmt_metric(buf, sizeof buf, u->n ? u->mean[m] : NAN, m);
                    fprintf(h, "<td>%s</td>", buf);
                }
                for (int m = M_RELMSE; m <= M_FLIP_LDR; m += M_FLIP_LDR - M_RELMSE) {
                    if (isnan(u->rank[m]))
                        fprintf(h, "<td>–</td>");
                    else
                        fprintf(h, "<td>%.2f</td>", u->rank[m]);
                }
                fprintf(h, "</tr>\n");
            }
            fprintf(h, "</table>\n");
        }
        fprintf(h, "<h2>Convergence</h2>\n");
        for (int sc = 0; sc < s->nscenes; sc++) {
            snprintf(path, sizeof path, "%s/convergence-%s.svg", out, s->scenes[sc].label);
            if (file_exists(path))
                fprintf(h,
                        "<img src=\"convergence-%s.svg\" alt=\"convergence, %s\" "
                        "width=\"640\">\n",
                        s->scenes[sc].label, s->scenes[sc].label);
        }
        int lb = s->nbudgets - 1;
        fprintf(h, "<h2>Images (budget %s): render, then its FLIP error map</h2>\n",
                s->budgets[lb].label);
        for (int m = 0; m < s->nmaps; m++)
            for (int sc = 0; sc < s->nscenes; sc++) {
                char key[32];
                reference_key(s, m, sc, key, sizeof key);
                fprintf(h, "<div class=\"grid\"><h3>%s / %s</h3>\n", s->maps[m].label,
                        s->scenes[sc].label);
                snprintf(path, sizeof path, "%s/refs/%s.png", out, key);
                if (file_exists(path))
                    fprintf(h,
                            "<figure><img src=\"refs/%s.png\" alt=\"reference\" loading=\"lazy\">"
                            "reference</figure>\n",
                            key);
                for (int me = 0; me < s->nmethods; me++) {
                    int k = idx(s, m, sc, me, lb);
                    if (!res[k].present) continue;
                    item it = item_at(s, k);
                    fprintf(h,
                            "<figure><img src=\"previews/%s.png\" alt=\"%s\" loading=\"lazy\">"
                            "<img src=\"previews/%s-flip.png\" alt=\"FLIP %s\" loading=\"lazy\">"
                            "%s: relMSE %.3g, FLIP %.3f</figure>\n",
                            it.id, it.id, it.id, it.id, s->methods[me].label, res[k].v[M_RELMSE],
                            s->flip_hdr ? res[k].v[M_FLIP_HDR] : res[k].v[M_FLIP_LDR]);
                }
                fprintf(h, "</div>\n");
            }
        fprintf(h, "</body></html>\n");
        snprintf(path, sizeof path, "%s/index.html", out);
        if (commit_tmp(h, path) != EXIT_OK) rc = EXIT_RUNTIME;
    }
    if (rc == EXIT_OK)
        fprintf(stderr,
                "lumis bench: %d of %d items; wrote %s/results.{csv,json,md}, "
                "convergence-*.svg and index.html\n",
                found, n, out);
    free(res);
    free(sum);
    return rc;
}

/* Copies every results/ and previews/ file (and refs/ PNGs) of src into dst. */
static int merge_dir(const char *src, const char *dst)
{
    static const char *const subs[] = {"results", "previews", "refs"};
    for (int k = 0; k < 3; k++) {
        char sd[8800], dd[8800];
        snprintf(sd, sizeof sd, "%s/%s", src, subs[k]);
        snprintf(dd, sizeof dd, "%s/%s", dst, subs[k]);
        DIR *d = opendir(sd);
        if (!d) {
            if (k == 0) return tool_runtime_error("--merge %s: no results/ folder there", src);
            continue;
        }
        for (struct dirent *de; (de = readdir(d));) {
            if (de->d_name[0] == '.') continue;
            char a[9600], b[9600];
            snprintf(a, sizeof a, "%s/%s", sd, de->d_name);
            snprintf(b, sizeof b, "%s/%s", dd, de->d_name);
            if (k == 2 && file_exists(b)) continue; /* references are shared by hash */
            FILE *in = fopen(a, "rb");
            if (!in) continue;
            size_t cap = 1 << 20, len = 0;
            char *buf = malloc(cap);
            for (size_t got; buf && (got = fread(buf + len, 1, cap - len, in)) > 0;) {
                len += got;
                if (len == cap) {
                    char *g = realloc(buf, cap *= 2);
                    if (!g) free(buf);
                    buf = g;
                }
            }
            fclose(in);
            lumis_status st =
                buf ? lumis_write_text(b, buf, len, &tool_errors) : LUMIS_ERR_OUT_OF_MEMORY;
            free(buf);
            if (st != LUMIS_OK) {
                closedir(d);
                return EXIT_RUNTIME;
            }
        }
        closedir(d);
    }
    return EXIT_OK;
}

int cmd_bench(int argc, char **argv)
{
    const char *suite_path = NULL, *out = NULL, *v;
    long jobs = 1, threads = 0, shard_i = 0, shard_n = 1;
    int report_only = 0, merging = 0, sharded = 0;
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--out", &v)) {
            if (!v || !*v) return tool_usage_error("bench", "--out needs a folder");
            out = v;
        } else if (tool_option(argc, argv, &i, "--jobs", &v)) {
            if (!tool_parse_int(v, 1, 256, &jobs))
                return tool_usage_error("bench", "--jobs needs a count in [1, 256]");
        } else if (tool_option(argc, argv, &i, "--threads", &v)) {
            if (!tool_parse_int(v, 1, 4096, &threads))
                return tool_usage_error("bench", "--threads needs a count");
        } else if (tool_option(argc, argv, &i, "--shard", &v)) {
            char *slash = v ? strchr(v, '/') : NULL;
            if (!slash) return tool_usage_error("bench", "--shard needs I/N, e.g. 0/4");
            *slash = '\0';
            int ok = tool_parse_int(v, 0, 1 << 20, &shard_i) &&
                     tool_parse_int(slash + 1, 1, 1 << 20, &shard_n) && shard_i < shard_n;
            *slash = '/';
            if (!ok) return tool_usage_error("bench", "--shard needs I/N with 0 <= I < N");
            sharded = 1;
        } else if (strcmp(argv[i], "--merge") == 0) {
            merging = 1;
            struct stat sb;
            if (i + 1 >= argc || stat(argv[i + 1], &sb) != 0 || !S_ISDIR(sb.st_mode))
                return tool_usage_error("bench", "--merge needs folders of earlier runs");
            while (i + 1 < argc && stat(argv[i + 1], &sb) == 0 && S_ISDIR(sb.st_mode)) i++;
        } else if (strcmp(argv[i], "--report-only") == 0) {
            report_only = 1;
        } else if (argv[i][0] != '-' && !suite_path) {
            suite_path = argv[i];
        } else {
            return tool_usage_error("bench", "unknown argument '%s'", argv[i]);
        }
    }
    if (!suite_path) return tool_usage_error("bench", "needs a SUITE.json");
    if (sharded && (merging || report_only))
        return tool_usage_error("bench", "--shard renders; --merge and --report-only report");
    suite s;
    if (parse_suite(suite_path, &s) != EXIT_OK) return EXIT_RUNTIME;
    char outbuf[4096];
    if (!out) {
        snprintf(outbuf, sizeof outbuf, "bench-out/%s", s.name);
        out = outbuf;
    }
    static const char *const subs[] = {"", "/refs", "/renders", "/results", "/previews"};
    for (int k = 0; k < 5; k++) {
        char d[8800];
        snprintf(d, sizeof d, "%s%s", out, subs[k]);
        if (make_dir(d) != EXIT_OK) {
            suite_free(&s);
            return EXIT_RUNTIME;
        }
    }
    int rc = EXIT_OK;
    if (merging)
        for (int i = 1; i < argc && rc == EXIT_OK; i++)
            if (strcmp(argv[i], "--merge") == 0)
                for (int k = i + 1; k < argc && rc == EXIT_OK; k++) {
                    struct stat sb;
                    if (stat(argv[k], &sb) != 0 || !S_ISDIR(sb.st_mode)) break;
                    rc = merge_dir(argv[k], out);
                }
    if (!merging && !report_only && rc == EXIT_OK) {
        long cores = sysconf(_SC_NPROCESSORS_ONLN);
        run_ctx c = {&s, out, (int)(threads ? threads : (cores > jobs ? cores / jobs : 1)), argc,
                     argv};
        const int total = nitems(&s);
        int mine = 0, todo = 0;
        for (int k = 0; k < total; k++)
            if (in_shard(&s, k, shard_i, shard_n)) {
                mine++;
                item it = item_at(&s, k);
                todo += !item_done(&s, out, &it);
            }
        fprintf(stderr, "lumis bench: suite %s, %d items (%d in this shard, %d to render)\n",
                s.name, total, mine, todo);
        /* References first, with every thread, for the pairs this shard needs.  With
         * --jobs the parent forks workers afterwards, so it must never start OpenMP's or
         * Embree's threads itself (they do not survive a fork): references are rendered
         * in a child process then. */
        run_ctx rc_all = c;
        rc_all.threads = (int)threads;
        pid_t refs_pid = jobs > 1 ? (fflush(NULL), fork()) : 0;
        if (refs_pid < 0) rc = tool_runtime_error("bench: fork: %s", strerror(errno));
        if (refs_pid == 0) {
            for (int m = 0; m < s.nmaps && rc == EXIT_OK; m++)
                for (int sc = 0; sc < s.nscenes && rc == EXIT_OK; sc++) {
                    int need = 0;
                    for (int k = 0; k < total && !need; k++) {
                        item it = item_at(&s, k);
                        need = it.map == m && it.scene == sc && in_shard(&s, k, shard_i, shard_n) &&
                               !item_done(&s, out, &it);
                    }
                    char ref[8800];
                    if (need) rc = ensure_reference(&rc_all, m, sc, ref, sizeof ref);
                }
            if (jobs > 1) {
                fflush(NULL);
                _exit(rc);
            }
        } else if (refs_pid > 0) {
            int status = 0;
            if (waitpid(refs_pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
                rc = EXIT_RUNTIME;
        }
        /* Items, in --jobs processes. */
        if (rc == EXIT_OK && jobs <= 1) {
            for (int k = 0; k < total && rc == EXIT_OK; k++)
                if (in_shard(&s, k, shard_i, shard_n)) {
                    item it = item_at(&s, k);
                    rc = run_item(&c, &it, k, total);
                }
        } else if (rc == EXIT_OK) {
            fflush(NULL);
            pid_t *pids = calloc((size_t)jobs, sizeof *pids);
            for (long j = 0; pids && j < jobs; j++) {
                pid_t pid = fork();
                if (pid == 0) {
                    int crc = EXIT_OK;
                    for (int k = 0, mi = 0; k < total && crc == EXIT_OK; k++)
                        if (in_shard(&s, k, shard_i, shard_n) && mi++ % jobs == j) {
                            item it = item_at(&s, k);
                            crc = run_item(&c, &it, k, total);
                        }
                    fflush(NULL);
                    _exit(crc);
                }
                if (pid < 0) rc = tool_runtime_error("bench: fork: %s", strerror(errno));
                pids[j] = pid;
            }
            for (long j = 0; pids && j < jobs; j++) {
                int status = 0;
                if (pids[j] > 0 && (waitpid(pids[j], &status, 0) < 0 || !WIFEXITED(status) ||
                                    WEXITSTATUS(status) != 0))
                    rc = EXIT_RUNTIME;
            }
            if (!pids) rc = tool_runtime_error("bench: out of memory");
            free(pids);
        }
        if (rc != EXIT_OK)
            fprintf(stderr, "lumis bench: stopped; run the same command again to resume\n");
    }
    if (rc == EXIT_OK && !sharded) rc = write_report(&s, out, argc, argv);
    if (rc == EXIT_OK && sharded)
        fprintf(stderr,
                "lumis bench: shard %ld/%ld done; join the shards with: lumis bench %s --out DIR "
                "--merge SHARD_DIR...\n",
                shard_i, shard_n, suite_path);
    suite_free(&s);
    return rc;
}
