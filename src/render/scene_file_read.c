/* JSON scene files (cJSON): the schema of lumis/render.h, read into a scene file
 * (scene_file.c keeps what it owns and loads the meshes).  Every failure names the file,
 * the JSON path and what was expected. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "internal.h"

#include "lumis/io.h"

#include <cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct parser {
    const char *file;
    char dir[4096]; /* the scene file's folder, with a trailing slash, or "" */
    const lumis_error_sink *errors;
    lumis_scene_file *f;
    int allow_files; /* 0: mesh files are refused (the fuzzer must not open paths) */
    const lumis_scene_read_options *options; /* NULL: the defaults */
} parser;

static lumis_status bad(const parser *p, const char *path, const char *what)
{
    return lumis__fail(p->errors, LUMIS_ERR_BAD_HEADER, "%s: %s: expected %s", p->file, path, what);
}

/* "a.b" (JSON paths are short; a longer one is cut, which only shortens a message). */
static void join(char *out, size_t cap, const char *a, const char *b)
{
    if (snprintf(out, cap, "%s.%s", a, b) >= (int)cap) out[cap - 1] = '\0';
}

/* Optional number (absent: keeps *out). */
static lumis_status get_number(const parser *p, const cJSON *o, const char *key, const char *path,
                               double lo, double hi, double *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    char at[256];
    join(at, sizeof at, path, key);
    if (!v) return LUMIS_OK;
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)) return bad(p, at, "a number");
    if (v->valuedouble < lo || v->valuedouble > hi) {
        char what[96];
        snprintf(what, sizeof what, "a number in [%g, %g]", lo, hi);
        return bad(p, at, what);
    }
    *out = v->valuedouble;
    return LUMIS_OK;
}

/* The edit distance of two short strings (keys), capped at 9. */
static int key_distance(const char *a, const char *b)
{
    int d[2][33];
    const int la = (int)strlen(a), lb = (int)strlen(b);
    if (la > 32 || lb > 32) return 9;
    for (int j = 0; j <= lb; j++) d[0][j] = j;
    for (int i = 1; i <= la; i++) {
        int *cur = d[i & 1], *prev = d[(i - 1) & 1];
        cur[0] = i;
        for (int j = 1; j <= lb; j++) {
            const int sub = prev[j - 1] + (a[i - 1] != b[j - 1]);
            const int del = prev[j] + 1, ins = cur[j - 1] + 1;
            cur[j] = sub < del ? (sub < ins ? sub : ins) : (del < ins ? del : ins);
        }
    }
    return d[la & 1][lb] < 9 ? d[la & 1][lb] : 9;
}

/* Every key of object o must be one of keys[] (NULL-terminated), and given once: a
 * misspelt key ("lumnaires", "albedo " with a space) would otherwise be ignored without a
 * word, and a duplicate would silently lose to the first.  The message names the JSON
 * path and the nearest known key. */
static lumis_status check_keys(const parser *p, const cJSON *o, const char *path,
                               const char *const *keys)
{
    for (const cJSON *c = o ? o->child : NULL; c; c = c->next) {
        const char *k = c->string ? c->string : "";
        char at[256];
        if (path[0])
            join(at, sizeof at, path, k);
        else
            snprintf(at, sizeof at, "%s", k);
        int known = 0, best = 9;
        const char *near = NULL;
        for (const char *const *q = keys; *q; q++) {
            if (strcmp(*q, k) == 0) known = 1;
            const int dist = key_distance(k, *q);
            if (dist < best) best = dist, near = *q;
        }
        /* a key with blanks around it is a misspelling of the trimmed one */
        if (!known) {
            char list[256] = "";
            for (const char *const *q = keys; *q; q++) {
                strncat(list, *q, sizeof list - strlen(list) - 1);
                if (q[1]) strncat(list, ", ", sizeof list - strlen(list) - 1);
            }
            if (near && best <= 2 + (int)(strlen(k) > 6))
                return lumis__fail(p->errors, LUMIS_ERR_BAD_HEADER,
                                   "%s: \"%s\": unknown key (did you mean \"%s\"? known: %s)",
                                   p->file, at, near, list);
            return lumis__fail(p->errors, LUMIS_ERR_BAD_HEADER,
                               "%s: \"%s\": unknown key (known: %s)", p->file, at, list);
        }
        for (const cJSON *e = o->child; e != c; e = e->next)
            if (e->string && strcmp(e->string, k) == 0)
                return lumis__fail(p->errors, LUMIS_ERR_BAD_HEADER,
                                   "%s: %s: given twice (a JSON object's keys are unique)", p->file,
                                   at);
    }
    return LUMIS_OK;
}

/* An optional whole number (24.5 is not a width). */
static lumis_status get_int(const parser *p, const cJSON *o, const char *key, const char *path,
                            double lo, double hi, double *out)
{
    double v = *out;
    lumis_status st = get_number(p, o, key, path, lo, hi, &v);
    if (st != LUMIS_OK) return st;
    if (v != floor(v)) {
        char at[256], what[96];
        join(at, sizeof at, path, key);
        snprintf(what, sizeof what, "a whole number in [%g, %g]", lo, hi);
        return bad(p, at, what);
    }
    *out = v;
    return LUMIS_OK;
}

static lumis_status get_vec3(const parser *p, const cJSON *o, const char *key, const char *path,
                             int required, float out[3])
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    char at[256];
    join(at, sizeof at, path, key);
    if (!v) return required ? bad(p, at, "an array of 3 numbers (missing)") : LUMIS_OK;
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3) return bad(p, at, "an array of 3 numbers");
    for (int k = 0; k < 3; k++) {
        const cJSON *e = cJSON_GetArrayItem(v, k);
        /* within float's range with room: 1e300 became infinity, and a camera at infinity
         * was then blamed on look_at */
        if (!cJSON_IsNumber(e) || !(fabs(e->valuedouble) <= 1e30))
            return bad(p, at, "an array of 3 numbers within [-1e30, 1e30]");
        out[k] = (float)e->valuedouble;
    }
    return LUMIS_OK;
}

static lumis_status get_rgb(const parser *p, const cJSON *o, const char *key, const char *path,
                            lumis_rgb *out)
{
    float v[3] = {out->r, out->g, out->b};
    lumis_status st = get_vec3(p, o, key, path, 0, v);
    if (st != LUMIS_OK) return st;
    for (int k = 0; k < 3; k++)
        if (v[k] < 0.0f || v[k] > 1.0f) {
            char at[256];
            join(at, sizeof at, path, key);
            return bad(p, at, "reflectances in [0, 1]");
        }
    *out = (lumis_rgb){v[0], v[1], v[2]};
    return LUMIS_OK;
}

static lumis_status parse_material(const parser *p, const cJSON *m, const char *path, lumis_bsdf *b)
{
    if (!cJSON_IsObject(m)) return bad(p, path, "a material object");
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(m, "type");
    char at[256];
    join(at, sizeof at, path, "type");
    if (!cJSON_IsString(t))
        return bad(p, at, "a string: lambert, ward, conductor, plastic or glossy");
    memset(b, 0, sizeof *b);
    double ax = 0.1, ay = -1.0, a = -1.0;
    lumis_status st = LUMIS_OK;
    static const char *const lambert_keys[] = {"type", "albedo", NULL};
    static const char *const ward_keys[] = {"type",    "diffuse", "specular", "alpha",
                                            "alpha_x", "alpha_y", NULL};
    static const char *const ggx_keys[] = {"type", "f0", "alpha", "alpha_x", "alpha_y", NULL};
    /* Cycles' Glossy BSDF (GGX): a colour, no Fresnel, separable masking */
    static const char *const glossy_keys[] = {"type", "color", "alpha", "alpha_x", "alpha_y", NULL};
    /* plastic's coat has F0 = 0.04: no f0 key (it would be read and never used) */
    static const char *const plastic_keys[] = {"type",    "diffuse", "alpha",
                                               "alpha_x", "alpha_y", NULL};
    if (strcmp(t->valuestring, "lambert") == 0) {
        if ((st = check_keys(p, m, path, lambert_keys)) != LUMIS_OK) return st;
        b->type = LUMIS_BSDF_LAMBERT;
        b->diffuse = (lumis_rgb){0.8f, 0.8f, 0.8f};
        st = get_rgb(p, m, "albedo", path, &b->diffuse);
    } else if (strcmp(t->valuestring, "ward") == 0 || strcmp(t->valuestring, "conductor") == 0 ||
               strcmp(t->valuestring, "ggx") == 0 || strcmp(t->valuestring, "plastic") == 0 ||
               strcmp(t->valuestring, "glossy") == 0) {
        int ward = t->valuestring[0] == 'w', plastic = t->valuestring[0] == 'p',
            glossy = strcmp(t->valuestring, "glossy") == 0;
        if ((st = check_keys(p, m, path,
                             ward      ? ward_keys
                             : plastic ? plastic_keys
                             : glossy  ? glossy_keys
                                       : ggx_keys)) != LUMIS_OK)
            return st;
        b->type = ward      ? LUMIS_BSDF_WARD
                  : plastic ? LUMIS_BSDF_GGX_PLASTIC
                  : glossy  ? LUMIS_BSDF_GGX_GLOSSY
                            : LUMIS_BSDF_GGX_CONDUCTOR;
        b->diffuse = (lumis_rgb){ward ? 0.1f : (plastic ? 0.5f : 0.0f),
                                 ward ? 0.1f : (plastic ? 0.5f : 0.0f),
                                 ward ? 0.1f : (plastic ? 0.5f : 0.0f)};
        b->specular = (lumis_rgb){ward ? 0.3f : 0.9f, ward ? 0.3f : 0.9f, ward ? 0.3f : 0.9f};
        if (st == LUMIS_OK) st = get_rgb(p, m, "diffuse", path, &b->diffuse);
        if (st == LUMIS_OK)
            st = get_rgb(p, m, ward ? "specular" : (glossy ? "color" : "f0"), path, &b->specular);
        if (st == LUMIS_OK) st = get_number(p, m, "alpha", path, 1e-3, 1.0, &a);
        if (a > 0.0) ax = a;
        if (st == LUMIS_OK) st = get_number(p, m, "alpha_x", path, 1e-3, 1.0, &ax);
        if (st == LUMIS_OK) st = get_number(p, m, "alpha_y", path, 1e-3, 1.0, &ay);
        b->alpha_x = (float)ax;
        b->alpha_y = (float)(ay > 0.0 ? ay : (a > 0.0 ? a : ax));
    } else {
        return bad(p, at, "lambert, ward, conductor, plastic or glossy");
    }
    return st;
}

/* Loads a mesh file into o, or shares the arrays of the same file loaded before. */
static lumis_status load_mesh(const parser *p, const char *file, const char *path, lumis_object *o)
{
    char full[4096];
    if (file[0] == '/')
        snprintf(full, sizeof full, "%s", file);
    else
        snprintf(full, sizeof full, "%s%s", p->dir, file);
    if (!p->allow_files)
        return lumis__fail(p->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: %s.file: mesh files are not loaded here", p->file, path);
    return lumis__scene_file_load_mesh(p->f, full, p->file, path, p->errors, o);
}

/* {"translate", "rotate_deg", "scale" (a number or 3)} as a row-major 3x4 matrix. */
static lumis_status parse_transform(const parser *p, const cJSON *x, const char *xp, float m[12])
{
    float tr[3] = {0, 0, 0}, rot[3] = {0, 0, 0}, sc[3] = {1, 1, 1};
    lumis_status st;
    if (!cJSON_IsObject(x)) return bad(p, xp, "an object with translate, rotate_deg, scale");
    static const char *const keys[] = {"translate", "rotate_deg", "scale", NULL};
    if ((st = check_keys(p, x, xp, keys)) != LUMIS_OK) return st;
    if ((st = get_vec3(p, x, "translate", xp, 0, tr)) != LUMIS_OK) return st;
    if ((st = get_vec3(p, x, "rotate_deg", xp, 0, rot)) != LUMIS_OK) return st;
    const cJSON *s = cJSON_GetObjectItemCaseSensitive(x, "scale");
    if (cJSON_IsNumber(s))
        sc[0] = sc[1] = sc[2] = (float)s->valuedouble;
    else if ((st = get_vec3(p, x, "scale", xp, 0, sc)) != LUMIS_OK)
        return st;
    if (!(sc[0] != 0.0f && sc[1] != 0.0f && sc[2] != 0.0f && isfinite(sc[0] * sc[1] * sc[2]))) {
        char at[256];
        join(at, sizeof at, xp, "scale");
        return bad(p, at, "a non-zero finite scale");
    }
    lumis__transform_matrix(tr, rot, sc, m);
    return LUMIS_OK;
}

/* Parses objects[k] and appends it to the file: one object, or one per entry of a mesh's
 * "instances". */
static lumis_status parse_object(const parser *p, const cJSON *j, int k)
{
    char path[64];
    snprintf(path, sizeof path, "objects[%d]", k);
    if (!cJSON_IsObject(j)) return bad(p, path, "an object");
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(j, "type");
    char at[256];
    join(at, sizeof at, path, "type");
    if (!cJSON_IsString(t)) return bad(p, at, "a string: sphere, plane or mesh");
    lumis_object o;
    memset(&o, 0, sizeof o);
    float c[3] = {0, 0, 0};
    const cJSON *instances = NULL;
    lumis_status st;
    static const char *const sphere_keys[] = {"type", "center", "radius", "material", NULL};
    static const char *const plane_keys[] = {"type", "point", "normal", "size", "material", NULL};
    static const char *const mesh_keys[] = {"type",      "file",     "transform",
                                            "instances", "material", NULL};
    const int is_sphere = strcmp(t->valuestring, "sphere") == 0,
              is_plane = strcmp(t->valuestring, "plane") == 0,
              is_mesh = strcmp(t->valuestring, "mesh") == 0;
    if ((is_sphere || is_plane || is_mesh) && (st = check_keys(p, j, path,
                                                               is_sphere  ? sphere_keys
                                                               : is_plane ? plane_keys
                                                                          : mesh_keys)) != LUMIS_OK)
        return st;
    if (is_sphere) {
        double r = -1.0;
        o.type = LUMIS_OBJECT_SPHERE;
        if ((st = get_vec3(p, j, "center", path, 1, c)) != LUMIS_OK) return st;
        if ((st = get_number(p, j, "radius", path, 1e-6, 1e9, &r)) != LUMIS_OK) return st;
        if (r < 0.0) {
            join(at, sizeof at, path, "radius");
            return bad(p, at, "a positive number (missing)");
        }
        o.radius = (float)r;
    } else if (strcmp(t->valuestring, "plane") == 0) {
        float n[3] = {0, 1, 0};
        double size = 20.0;
        o.type = LUMIS_OBJECT_PLANE;
        if ((st = get_vec3(p, j, "point", path, 1, c)) != LUMIS_OK) return st;
        if ((st = get_vec3(p, j, "normal", path, 1, n)) != LUMIS_OK) return st;
        if (n[0] == 0.0f && n[1] == 0.0f && n[2] == 0.0f) {
            join(at, sizeof at, path, "normal");
            return bad(p, at, "a non-zero vector");
        }
        if ((st = get_number(p, j, "size", path, 1e-6, 1e9, &size)) != LUMIS_OK) return st;
        o.normal = (lumis_vec3){n[0], n[1], n[2]};
        o.size = (float)size;
    } else if (strcmp(t->valuestring, "mesh") == 0) {
        o.type = LUMIS_OBJECT_MESH;
        const cJSON *f = cJSON_GetObjectItemCaseSensitive(j, "file");
        join(at, sizeof at, path, "file");
        if (!cJSON_IsString(f) || !f->valuestring[0]) return bad(p, at, "a mesh file name");
        const cJSON *x = cJSON_GetObjectItemCaseSensitive(j, "transform");
        instances = cJSON_GetObjectItemCaseSensitive(j, "instances");
        if (x && instances) return bad(p, path, "either \"transform\" or \"instances\", not both");
        char xp[128];
        if (x) {
            join(xp, sizeof xp, path, "transform");
            if ((st = parse_transform(p, x, xp, o.transform)) != LUMIS_OK) return st;
        }
        if (instances) {
            join(xp, sizeof xp, path, "instances");
            if (!cJSON_IsArray(instances) || cJSON_GetArraySize(instances) < 1)
                return bad(p, xp, "a non-empty array of transforms");
        }
        if ((st = load_mesh(p, f->valuestring, path, &o)) != LUMIS_OK) return st;
    } else {
        return bad(p, at, "sphere, plane or mesh");
    }
    o.center = (lumis_vec3){c[0], c[1], c[2]};
    join(at, sizeof at, path, "material");
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(j, "material");
    if (!m) return bad(p, at, "a material object (missing)");
    if ((st = parse_material(p, m, at, &o.material)) != LUMIS_OK) return st;
    if (!instances) return lumis__scene_file_push(p->f, &o);
    for (int q = 0; q < cJSON_GetArraySize(instances); q++) {
        char xp[128];
        snprintf(xp, sizeof xp, "%s.instances[%d]", path, q);
        if ((st = parse_transform(p, cJSON_GetArrayItem(instances, q), xp, o.transform)) !=
            LUMIS_OK)
            return st;
        if ((st = lumis__scene_file_push(p->f, &o)) != LUMIS_OK) return st;
    }
    return LUMIS_OK;
}

/* luminaires[k]: {"file": "lamp.json" | "preset:car", "transform": {"translate",
 * "rotate_deg", "scale" (a number: lengths only)}, "intensity"}. */
static lumis_status parse_luminaire(const parser *p, const cJSON *j, int k)
{
    char path[64], at[256];
    snprintf(path, sizeof path, "luminaires[%d]", k);
    if (!cJSON_IsObject(j)) return bad(p, path, "an object with file, transform, intensity");
    static const char *const keys[] = {"file", "transform", "intensity", NULL};
    lumis_status kst = check_keys(p, j, path, keys);
    if (kst != LUMIS_OK) return kst;
    const cJSON *file = cJSON_GetObjectItemCaseSensitive(j, "file");
    join(at, sizeof at, path, "file");
    if (!cJSON_IsString(file) || !file->valuestring[0])
        return bad(p, at, "a luminaire manifest (.json) or preset:car, preset:bike, preset:small");
    lumis_luminaire_instance in;
    memset(&in, 0, sizeof in);
    float tr[3] = {0, 0, 0}, rot[3] = {0, 0, 0};
    double scale = 1.0, intensity = 1.0;
    lumis_status st;
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(j, "transform");
    if (x) {
        char xp[128];
        join(xp, sizeof xp, path, "transform");
        if (!cJSON_IsObject(x)) return bad(p, xp, "an object with translate, rotate_deg, scale");
        static const char *const xkeys[] = {"translate", "rotate_deg", "scale", NULL};
        if ((st = check_keys(p, x, xp, xkeys)) != LUMIS_OK) return st;
        if ((st = get_vec3(p, x, "translate", xp, 0, tr)) != LUMIS_OK) return st;
        if ((st = get_vec3(p, x, "rotate_deg", xp, 0, rot)) != LUMIS_OK) return st;
        const cJSON *sc = cJSON_GetObjectItemCaseSensitive(x, "scale");
        join(at, sizeof at, xp, "scale");
        if (sc && !cJSON_IsNumber(sc))
            return bad(p, at, "a positive number (a luminaire scales uniformly: lengths only)");
        if ((st = get_number(p, x, "scale", xp, 1e-12, 1e12, &scale)) != LUMIS_OK) return st;
    }
    if ((st = get_number(p, j, "intensity", path, 0.0, 1e30, &intensity)) != LUMIS_OK) return st;
    lumis__rotation_deg(rot, in.placement.r);
    for (int a = 0; a < 3; a++) in.placement.t[a] = tr[a];
    in.scale = scale;
    in.intensity = intensity == 0.0 ? 0.0f : (float)intensity;
    if (intensity == 0.0) { /* 0 means 1 in the descriptor: a black lamp is left out */
        return LUMIS_OK;
    }
    if (!p->allow_files) return LUMIS_OK; /* the fuzzer: nothing is read or acquired */
    char full[4096];
    const char *name = file->valuestring;
    if (strncmp(name, "preset:", 7) == 0 || name[0] == '/')
        snprintf(full, sizeof full, "%s", name);
    else
        snprintf(full, sizeof full, "%s%s", p->dir, name);
    lumis_luminaire *lum = lumis__scene_file_luminaire(p->f, full);
    lumis_luminaire *owned = NULL;
    if (!lum) {
        if (strncmp(name, "preset:", 7) == 0) {
            lumis_luminaire_preset preset;
            if (lumis_luminaire_preset_from_name(name + 7, &preset) != LUMIS_OK)
                return bad(p, at, "preset:car, preset:bike or preset:small");
            st =
                p->options && p->options->load_preset
                    ? p->options->load_preset(p->options->load_preset_user, name, &owned)
                    : lumis_luminaire_preset_create(preset, LUMIS_BASIS_DEFAULT, p->errors, &owned);
        } else {
            lumis_luminaire_read_options ro = {0};
            if (p->errors) ro.errors = *p->errors;
            st = lumis_luminaire_read(full, &ro, &owned);
        }
        if (st != LUMIS_OK)
            return lumis__fail(p->errors, st, "%s: %s.file: cannot load luminaire %s", p->file,
                               path, full);
        lum = owned;
    }
    in.luminaire = lum;
    return lumis__scene_file_add_luminaire(p->f, owned, full, &in);
}

/* photometric[k]: {"file": "fixture.ies" | "fixture.ldt", "position": [x, y, z], "aim":
 * [x, y, z] (a point it aims at; default straight down, -y), "up" or "c0" (a direction
 * for local +x: the fixture's top, C0 for type C; default by the file's type:
 * lumis_photometric_orient), "roll_deg", "multiplier", "area" (true: the file's disk or
 * rectangle opening, else a point)}. */
static lumis_status parse_photometric(const parser *p, const cJSON *j, int k)
{
    char path[64], at[256];
    snprintf(path, sizeof path, "photometric[%d]", k);
    if (!cJSON_IsObject(j))
        return bad(p, path, "an object with file, position, aim, up, roll_deg, multiplier, area");
    static const char *const keys[] = {"file",     "position",   "aim",  "up", "c0",
                                       "roll_deg", "multiplier", "area", NULL};
    lumis_status st = check_keys(p, j, path, keys);
    if (st != LUMIS_OK) return st;
    const cJSON *file = cJSON_GetObjectItemCaseSensitive(j, "file");
    join(at, sizeof at, path, "file");
    if (!cJSON_IsString(file) || !file->valuestring[0])
        return bad(p, at, "a photometric file (IES .ies or EULUMDAT .ldt)");
    float pos[3] = {0, 0, 0}, aim[3];
    double roll = 0.0, mult = 1.0;
    if ((st = get_vec3(p, j, "position", path, 1, pos)) != LUMIS_OK) return st;
    aim[0] = pos[0];
    aim[1] = pos[1] - 1.0f;
    aim[2] = pos[2];
    if ((st = get_vec3(p, j, "aim", path, 0, aim)) != LUMIS_OK) return st;
    /* local +x: "up" (a floodlight's top) and "c0" (a downlight's C0) are one field */
    const char *up_key = cJSON_GetObjectItemCaseSensitive(j, "c0") ? "c0" : "up";
    if (cJSON_GetObjectItemCaseSensitive(j, "c0") && cJSON_GetObjectItemCaseSensitive(j, "up")) {
        join(at, sizeof at, path, "c0");
        return bad(p, at, "up or c0, not both (the same direction: the fixture's local +x)");
    }
    float upv[3];
    int has_up = cJSON_GetObjectItemCaseSensitive(j, up_key) != NULL;
    if ((st = get_vec3(p, j, up_key, path, 0, upv)) != LUMIS_OK) return st;
    if ((st = get_number(p, j, "roll_deg", path, -36000.0, 36000.0, &roll)) != LUMIS_OK) return st;
    if ((st = get_number(p, j, "multiplier", path, 0.0, 1e30, &mult)) != LUMIS_OK) return st;
    if (!(mult > 0)) { /* a dark fixture once left the scene to the default sky */
        join(at, sizeof at, path, "multiplier");
        return bad(p, at, "a number > 0 (to switch a fixture off, leave it out)");
    }
    const cJSON *area = cJSON_GetObjectItemCaseSensitive(j, "area");
    join(at, sizeof at, path, "area");
    if (area && !cJSON_IsBool(area)) return bad(p, at, "true or false");
    lumis_photometric_instance in;
    memset(&in, 0, sizeof in);
    const lumis_vec3 dir = {aim[0] - pos[0], aim[1] - pos[1], aim[2] - pos[2]};
    const lumis_vec3 up = {upv[0], upv[1], upv[2]}, *up_or_null = has_up ? &up : NULL;
    join(at, sizeof at, path, "aim");
    /* checked before the file is read (its type chooses the frame: not read by the
     * fuzzer): what is refused does not depend on the type */
    if (lumis_photometric_orient(LUMIS_PHOTOMETRIC_C, dir, NULL, roll, in.placement.r) != LUMIS_OK)
        return bad(p, at, "a point other than the position");
    join(at, sizeof at, path, up_key);
    if (lumis_photometric_orient(LUMIS_PHOTOMETRIC_C, dir, up_or_null, roll, in.placement.r) !=
        LUMIS_OK)
        return bad(p, at,
                   "a direction not along the aim (the fixture's local +x is made "
                   "perpendicular to the aim)");
    for (int a = 0; a < 3; a++) in.placement.t[a] = pos[a];
    in.multiplier = mult;
    in.area = cJSON_IsTrue(area);
    if (!p->allow_files) return LUMIS_OK; /* the fuzzer reads no file */
    char full[4096];
    const char *name = file->valuestring;
    snprintf(full, sizeof full, "%s%s", name[0] == '/' ? "" : p->dir, name);
    lumis_photometric_file *pf = lumis__scene_file_photometric(p->f, full, p->errors, &st);
    if (!pf)
        return lumis__fail(p->errors, st, "%s: %s.file: cannot read photometric file %s", p->file,
                           path, full);
    in.photometric = pf->model;
    lumis_photometric_info info;
    lumis_photometric_get_info(pf->model, &info);
    if ((st = lumis_photometric_orient(info.type, dir, up_or_null, roll, in.placement.r)) !=
        LUMIS_OK)
        return lumis__fail(p->errors, st, "%s: %s: cannot orient the fixture", p->file, path);
    in.multiplier *= lumis_photometric_tilt_factor(pf, info.type, dir);
    lumis_scene_file *f = p->f;
    lumis_photometric_instance *g =
        realloc(f->photometrics, (size_t)(f->photometric_count + 1) * sizeof *g);
    if (!g) return lumis__fail(p->errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", p->file);
    f->photometrics = g;
    f->photometrics[f->photometric_count++] = in;
    return LUMIS_OK;
}

static lumis_status parse_with(const char *text, size_t n, const char *name, const char *dir,
                               int allow_files, const lumis_error_sink *errors,
                               const lumis_scene_read_options *options, lumis_scene_file **out);

lumis_status lumis_scene_file_read(const char *path, const lumis_scene_read_options *options,
                                   lumis_scene_file **out)
{
    const lumis_error_sink *errors = options ? &options->errors : NULL;
    if (!out || !path) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    char dir[4096] = "";
    const char *slash = strrchr(path, '/');
    if (slash) snprintf(dir, sizeof dir, "%.*s/", (int)(slash - path), path);
    FILE *fp = fopen(path, "rb");
    if (!fp) return lumis__fail(errors, LUMIS_ERR_OPEN, "%s: %s", path, strerror(errno));
    long n = -1;
    if (fseek(fp, 0, SEEK_END) == 0) n = ftell(fp);
    if (n < 0 || n > (1L << 26) || fseek(fp, 0, SEEK_SET) != 0) {
        fclose(fp);
        return lumis__fail(errors, LUMIS_ERR_TOO_LARGE, "%s: not a scene file (size)", path);
    }
    char *text = malloc((size_t)n + 1);
    if (!text) {
        fclose(fp);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    if (fread(text, 1, (size_t)n, fp) != (size_t)n) {
        free(text);
        fclose(fp);
        return lumis__fail(errors, LUMIS_ERR_READ, "%s: read error", path);
    }
    fclose(fp);
    lumis_status st = parse_with(text, (size_t)n, path, dir, 1, errors, options, out);
    free(text);
    if (st != LUMIS_OK || !(*out)->env_map[0] || (options && options->skip_env_map)) return st;
    /* The map, through lumis-io (a file beside the scene, or a procedural spec). */
    lumis_read_options ro = {0};
    if (options) ro = options->map;
    if (errors) ro.errors = *errors;
    st = lumis_map_read((*out)->env_map, &ro, &(*out)->env_image, &(*out)->env_info);
    if (st != LUMIS_OK) {
        lumis_scene_file_destroy(*out);
        *out = NULL;
    }
    return st;
}

lumis_status lumis__scene_file_parse(const char *text, size_t n, const char *name, const char *dir,
                                     int allow_files, const lumis_error_sink *errors,
                                     lumis_scene_file **out)
{
    return parse_with(text, n, name, dir, allow_files, errors, NULL, out);
}

static lumis_status parse_with(const char *text, size_t n, const char *name, const char *dir,
                               int allow_files, const lumis_error_sink *errors,
                               const lumis_scene_read_options *options, lumis_scene_file **out)
{
    if (!out || (!text && n) || !name || !dir) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    parser p = {name, "", errors, NULL, allow_files, options};
    snprintf(p.dir, sizeof p.dir, "%s", dir);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, n, &end, 0);
    if (root && end) { /* only blanks may follow the top-level value */
        for (const char *c = end; c < text + n; c++)
            if (*c != ' ' && *c != '\t' && *c != '\n' && *c != '\r' && *c != '\0') {
                int line = 1;
                for (const char *q = text; q < c; q++) line += *q == '\n';
                cJSON_Delete(root);
                return lumis__fail(errors, LUMIS_ERR_BAD_HEADER,
                                   "%s:%d: text after the scene's closing brace", name, line);
            }
    }
    if (!root) {
        const char *e = cJSON_GetErrorPtr();
        size_t at = e && e >= text && e <= text + n ? (size_t)(e - text) : 0;
        int line = 1;
        for (size_t k = 0; k < at; k++) line += text[k] == '\n';
        return lumis__fail(errors, LUMIS_ERR_BAD_HEADER, "%s:%d: malformed JSON", name, line);
    }
    lumis_scene_file *f = lumis__scene_file_new();
    p.f = f;
    lumis_status st = f ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK && !cJSON_IsObject(root)) st = bad(&p, "(top level)", "an object");
    static const char *const root_keys[] = {"camera",     "environment", "objects",
                                            "luminaires", "photometric", NULL};
    static const char *const camera_keys[] = {"eye",   "look_at", "up", "fov_deg",
                                              "width", "height",  NULL};
    static const char *const env_keys[] = {"map", "rotation_deg", "scale", NULL};
    if (st == LUMIS_OK) st = check_keys(&p, root, "", root_keys);
    if (st == LUMIS_OK && cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(root, "camera")))
        st =
            check_keys(&p, cJSON_GetObjectItemCaseSensitive(root, "camera"), "camera", camera_keys);
    if (st == LUMIS_OK && cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(root, "environment")))
        st = check_keys(&p, cJSON_GetObjectItemCaseSensitive(root, "environment"), "environment",
                        env_keys);
    /* Camera: the renderer's defaults for what is absent. */
    if (st == LUMIS_OK) {
        const cJSON *c = cJSON_GetObjectItemCaseSensitive(root, "camera");
        if (c && !cJSON_IsObject(c))
            st = bad(&p, "camera", "an object");
        else if (c) {
            float v[3];
            double fov = 40, w = 640, h = 480;
            memcpy(v, &f->camera.eye, sizeof v);
            if (st == LUMIS_OK && (st = get_vec3(&p, c, "eye", "camera", 0, v)) == LUMIS_OK)
                f->camera.eye = (lumis_vec3){v[0], v[1], v[2]};
            memcpy(v, &f->camera.look_at, sizeof v);
            if (st == LUMIS_OK && (st = get_vec3(&p, c, "look_at", "camera", 0, v)) == LUMIS_OK)
                f->camera.look_at = (lumis_vec3){v[0], v[1], v[2]};
            memcpy(v, &f->camera.up, sizeof v);
            if (st == LUMIS_OK && (st = get_vec3(&p, c, "up", "camera", 0, v)) == LUMIS_OK)
                f->camera.up = (lumis_vec3){v[0], v[1], v[2]};
            if (st == LUMIS_OK) st = get_number(&p, c, "fov_deg", "camera", 1e-3, 179.0, &fov);
            if (st == LUMIS_OK) st = get_int(&p, c, "width", "camera", 1, 16384, &w);
            if (st == LUMIS_OK) st = get_int(&p, c, "height", "camera", 1, 16384, &h);
            f->camera.fov_deg = (float)fov;
            f->camera.width = (int)w;
            f->camera.height = (int)h;
        }
    }
    if (st == LUMIS_OK) {
        const cJSON *e = cJSON_GetObjectItemCaseSensitive(root, "environment");
        if (e && !cJSON_IsObject(e))
            st = bad(&p, "environment", "an object");
        else if (e) {
            const cJSON *m = cJSON_GetObjectItemCaseSensitive(e, "map");
            double rot = 0, scale = 1;
            if (m && !cJSON_IsString(m))
                st = bad(&p, "environment.map", "a file name or sky/studio spec");
            else if (m) {
                int procedural = strncmp(m->valuestring, "sky", 3) == 0 ||
                                 strncmp(m->valuestring, "studio", 6) == 0;
                if (procedural || m->valuestring[0] == '/')
                    snprintf(f->env_map, sizeof f->env_map, "%s", m->valuestring);
                else
                    snprintf(f->env_map, sizeof f->env_map, "%s%s", p.dir, m->valuestring);
            }
            if (st == LUMIS_OK)
                st = get_number(&p, e, "rotation_deg", "environment", -1e6, 1e6, &rot);
            if (st == LUMIS_OK) st = get_number(&p, e, "scale", "environment", 0, 1e30, &scale);
            f->env_rotation_deg = (float)rot;
            f->env_scale = (float)scale;
        }
    }
    if (st == LUMIS_OK) {
        const cJSON *objs = cJSON_GetObjectItemCaseSensitive(root, "objects");
        if (!cJSON_IsArray(objs))
            st = bad(&p, "objects", "an array of objects");
        else {
            int n_obj = cJSON_GetArraySize(objs);
            for (int k = 0; k < n_obj && st == LUMIS_OK; k++)
                st = parse_object(&p, cJSON_GetArrayItem(objs, k), k);
        }
    }
    if (st == LUMIS_OK) {
        const cJSON *lums = cJSON_GetObjectItemCaseSensitive(root, "luminaires");
        if (lums && !cJSON_IsArray(lums))
            st = bad(&p, "luminaires", "an array of luminaires");
        else if (lums && cJSON_GetArraySize(lums) > 4096)
            st = bad(&p, "luminaires", "at most 4096 luminaires");
        else
            for (int k = 0; lums && k < cJSON_GetArraySize(lums) && st == LUMIS_OK; k++) {
                st = parse_luminaire(&p, cJSON_GetArrayItem(lums, k), k);
                f->luminaires_listed++;
            }
    }
    if (st == LUMIS_OK) {
        const cJSON *fx = cJSON_GetObjectItemCaseSensitive(root, "photometric");
        if (fx && !cJSON_IsArray(fx))
            st = bad(&p, "photometric", "an array of photometric fixtures");
        else if (fx && cJSON_GetArraySize(fx) > 4096)
            st = bad(&p, "photometric", "at most 4096 fixtures");
        else if (fx && cJSON_GetArraySize(fx) == 0) /* else the default sky lights it */
            st = bad(&p, "photometric", "at least one fixture (or no \"photometric\" key)");
        else
            for (int k = 0; fx && k < cJSON_GetArraySize(fx) && st == LUMIS_OK; k++)
                st = parse_photometric(&p, cJSON_GetArrayItem(fx, k), k);
    }
    cJSON_Delete(root);
    if (st != LUMIS_OK) {
        lumis_scene_file_destroy(f);
        return st;
    }
    *out = f;
    return LUMIS_OK;
}
