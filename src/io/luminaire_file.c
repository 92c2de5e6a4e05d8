/* Luminaire files, read: a JSON manifest (cJSON) naming M EXR or PFM images.  Schema:
 * docs/formats.md, "Luminaire files".  Every failure names the manifest, the JSON field
 * and what was expected; the images are read by lumis_image_read and checked against the
 * manifest's size.  Writing: luminaire_file_write.c. */
#include "lumis/io.h"

#include "internal.h"
#include "luminaire_file.h"

#include "../core/internal.h"

#include <cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- the manifest -------------------------------------------------------------------- */

/* The public struct first, then the storage it points into. */
typedef struct manifest_private {
    lumis_luminaire_manifest pub;
    char **names;
    char **paths;
} manifest_private;

void lumis_luminaire_manifest_destroy(lumis_luminaire_manifest *manifest)
{
    if (!manifest) return;
    manifest_private *mp = (manifest_private *)manifest;
    for (int m = 0; m < manifest->image_count; m++) {
        if (mp->names) free(mp->names[m]);
        if (mp->paths) free(mp->paths[m]);
    }
    free(mp->names);
    free(mp->paths);
    free(mp);
}

typedef struct parser {
    const char *file;
    const lumis_error_sink *errors;
} parser;

/* What a JSON value is, for "got ..." (a string is quoted and cut at 40 bytes). */
static const char *describe(const cJSON *v, char *buf, size_t cap)
{
    if (cJSON_IsNumber(v)) {
        snprintf(buf, cap, "%.10g", v->valuedouble);
        return buf;
    }
    if (cJSON_IsString(v)) {
        snprintf(buf, cap, "\"%.40s%s\"", v->valuestring, strlen(v->valuestring) > 40 ? "..." : "");
        return buf;
    }
    if (cJSON_IsBool(v)) return cJSON_IsTrue(v) ? "true" : "false";
    if (cJSON_IsNull(v)) return "null";
    if (cJSON_IsArray(v)) {
        snprintf(buf, cap, "an array of %d", cJSON_GetArraySize(v));
        return buf;
    }
    if (cJSON_IsObject(v)) return "an object";
    return "something else";
}

/* "FILE: FIELD: expected WHAT, got VALUE" (or "missing" for an absent field). */
static lumis_status expected(const parser *p, lumis_status status, const char *field,
                             const char *what, const cJSON *got)
{
    if (!got)
        return lumis__fail(p->errors, status, "%s: %s: missing; expected %s", p->file, field, what);
    char buf[96];
    return lumis__fail(p->errors, status, "%s: %s: expected %s, got %s", p->file, field, what,
                       describe(got, buf, sizeof buf));
}

static int is_integer_in(const cJSON *v, double lo, double hi)
{
    return cJSON_IsNumber(v) && isfinite(v->valuedouble) &&
           v->valuedouble == floor(v->valuedouble) && v->valuedouble >= lo && v->valuedouble <= hi;
}

/* A number: finite, and > 0 when positive is set. */
static int is_number_ok(const cJSON *v, int positive)
{
    return cJSON_IsNumber(v) && isfinite(v->valuedouble) && (!positive || v->valuedouble > 0.0);
}

static lumis_status get_int(const parser *p, const cJSON *obj, const char *key, const char *field,
                            int lo, int hi, const char *range, int *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!is_integer_in(v, lo, hi)) {
        char what[64];
        snprintf(what, sizeof what, "an integer in %s", range);
        return expected(p, LUMIS_ERR_BAD_HEADER, field, what, v);
    }
    *out = (int)v->valuedouble;
    return LUMIS_OK;
}

static lumis_status get_number(const parser *p, const cJSON *obj, const char *key,
                               const char *field, double *out)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    if (!is_number_ok(v, 1)) return expected(p, LUMIS_ERR_BAD_HEADER, field, "a number > 0", v);
    *out = v->valuedouble;
    return LUMIS_OK;
}

/* [a, b]: finite numbers (positive: > 0), or integers in lo..hi when range is given. */
static lumis_status get_pair(const parser *p, const cJSON *obj, const char *key, const char *field,
                             int positive, const char *range, int lo, int hi, double out[2])
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, key);
    char what[96], one[64];
    if (range) {
        snprintf(what, sizeof what, "an array of 2 integers in %s", range);
        snprintf(one, sizeof one, "an integer in %s", range);
    } else {
        snprintf(what, sizeof what, "an array of 2 %s",
                 positive ? "numbers > 0" : "finite numbers");
        snprintf(one, sizeof one, "%s", positive ? "a number > 0" : "a finite number");
    }
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 2)
        return expected(p, LUMIS_ERR_BAD_HEADER, field, what, v);
    for (int k = 0; k < 2; k++) {
        const cJSON *e = cJSON_GetArrayItem(v, k);
        int ok = range ? is_integer_in(e, lo, hi) : is_number_ok(e, positive);
        if (!ok) {
            char at[96];
            snprintf(at, sizeof at, "%s[%d]", field, k);
            return expected(p, LUMIS_ERR_BAD_HEADER, at, one, e);
        }
        out[k] = e->valuedouble;
    }
    return LUMIS_OK;
}

/* A relative path of at most MAX_NAME bytes, '/' separators, no ".." component, no
 * backslash or control character: a manifest opens only files in or below its folder. */
static int name_ok(const char *s)
{
    size_t n = strlen(s);
    if (n == 0 || n > MAX_NAME || s[0] == '/') return 0;
    for (size_t k = 0; k < n; k++)
        if ((unsigned char)s[k] < 0x20 || s[k] == '\\' || s[k] == 0x7f) return 0;
    for (const char *c = s; *c;) {
        const char *end = strchr(c, '/');
        size_t len = end ? (size_t)(end - c) : strlen(c);
        if (len == 2 && c[0] == '.' && c[1] == '.') return 0;
        if (!end) break;
        c = end + 1;
    }
    return s[n - 1] != '/';
}

int lumis__lumfile_units_ok(const char *s)
{
    size_t n = strlen(s);
    if (n == 0 || n >= UNITS_CAP) return 0;
    for (size_t k = 0; k < n; k++)
        if ((unsigned char)s[k] < 0x20 || s[k] == 0x7f) return 0;
    return 1;
}

/* base_dir joined with name ("" or NULL: name alone). */
static char *join_path(const char *base_dir, const char *name)
{
    size_t b = base_dir ? strlen(base_dir) : 0, n = strlen(name);
    int slash = b > 0 && base_dir[b - 1] != '/';
    char *out = malloc(b + (size_t)slash + n + 1);
    if (!out) return NULL;
    if (b) memcpy(out, base_dir, b);
    if (slash) out[b] = '/';
    memcpy(out + b + (size_t)slash, name, n + 1);
    return out;
}

static lumis_status parse_root(const parser *p, const cJSON *root, const char *base_dir,
                               uint64_t max_pixels, manifest_private *mp)
{
    lumis_luminaire_manifest *m = &mp->pub;
    lumis_luminaire_desc *d = &m->desc;
    if (!cJSON_IsObject(root))
        return expected(p, LUMIS_ERR_BAD_MAGIC, "(top level)", "a JSON object", root);
    /* What the file is and which version, before anything that depends on them. */
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, "format");
    if (!cJSON_IsString(v) || strcmp(v->valuestring, FORMAT_NAME) != 0)
        return expected(p, LUMIS_ERR_BAD_MAGIC, "format", "\"" FORMAT_NAME "\"", v);
    v = cJSON_GetObjectItemCaseSensitive(root, "version");
    if (!is_integer_in(v, LUMIS_LUMINAIRE_FORMAT_VERSION, LUMIS_LUMINAIRE_FORMAT_VERSION)) {
        /* A later version is a file this reader is too old for, not a malformed one. */
        lumis_status st = is_integer_in(v, LUMIS_LUMINAIRE_FORMAT_VERSION + 1, 1e9)
                              ? LUMIS_ERR_UNSUPPORTED
                              : LUMIS_ERR_BAD_HEADER;
        return expected(p, st, "version", "1 (the version this lumis reads)", v);
    }
    m->version = LUMIS_LUMINAIRE_FORMAT_VERSION;
    v = cJSON_GetObjectItemCaseSensitive(root, "units");
    if (!cJSON_IsString(v) || !lumis__lumfile_units_ok(v->valuestring))
        return expected(p, LUMIS_ERR_BAD_HEADER, "units",
                        "a unit name of 1..31 printable bytes, e.g. \"mm\"", v);
    snprintf(m->units, sizeof m->units, "%s", v->valuestring);

    lumis_status st = get_number(p, root, "delta", "delta", &d->delta);
    if (st != LUMIS_OK) return st;
    v = cJSON_GetObjectItemCaseSensitive(root, "basis");
    if (!cJSON_IsString(v) ||
        (strcmp(v->valuestring, "quadratic") != 0 && strcmp(v->valuestring, "bspline") != 0))
        return expected(p, LUMIS_ERR_BAD_HEADER, "basis", "\"quadratic\" or \"bspline\"", v);
    d->basis = v->valuestring[0] == 'q' ? LUMIS_BASIS_QUADRATIC : LUMIS_BASIS_BSPLINE;

    double g[2];
    if ((st = get_pair(p, root, "grid", "grid", 1, MAX_GRID_STR, 1, LUMIS_LUMINAIRE_MAX_GRID, g)) !=
        LUMIS_OK)
        return st;
    d->grid[0] = (int)g[0];
    d->grid[1] = (int)g[1];
    if (d->grid[0] * d->grid[1] > LUMIS_LUMINAIRE_MAX_IMAGES)
        return lumis__fail(p->errors, LUMIS_ERR_BAD_HEADER,
                           "%s: grid: expected at most %d images (W H), got %d x %d", p->file,
                           LUMIS_LUMINAIRE_MAX_IMAGES, d->grid[0], d->grid[1]);
    if ((st = get_pair(p, root, "grid_origin", "grid_origin", 0, NULL, 0, 0, d->grid_origin)) !=
        LUMIS_OK)
        return st;
    if ((st = get_pair(p, root, "grid_spacing", "grid_spacing", 1, NULL, 0, 0, d->grid_spacing)) !=
        LUMIS_OK)
        return st;

    const cJSON *img = cJSON_GetObjectItemCaseSensitive(root, "image");
    if (!cJSON_IsObject(img))
        return expected(p, LUMIS_ERR_BAD_HEADER, "image",
                        "an object {\"width\", \"height\", \"origin\", \"size\"}", img);
    if ((st = get_int(p, img, "width", "image.width", 1, LUMIS_LUMINAIRE_MAX_SIDE, MAX_SIDE_STR,
                      &d->width)) != LUMIS_OK ||
        (st = get_int(p, img, "height", "image.height", 1, LUMIS_LUMINAIRE_MAX_SIDE, MAX_SIDE_STR,
                      &d->height)) != LUMIS_OK ||
        (st = get_pair(p, img, "origin", "image.origin", 0, NULL, 0, 0, d->image_origin)) !=
            LUMIS_OK ||
        (st = get_pair(p, img, "size", "image.size", 1, NULL, 0, 0, d->image_size)) != LUMIS_OK)
        return st;

    /* At most 1024 x 16384^2 = 2^38: no overflow in 64 bits. */
    const int M = d->grid[0] * d->grid[1];
    const uint64_t total = (uint64_t)M * (uint64_t)d->width * (uint64_t)d->height;
    if (total > max_pixels)
        return lumis__fail(p->errors, LUMIS_ERR_TOO_LARGE,
                           "%s: image: %d images (grid %d x %d) of %d x %d pixels are %llu pixels, "
                           "over the limit of %llu",
                           p->file, M, d->grid[0], d->grid[1], d->width, d->height,
                           (unsigned long long)total, (unsigned long long)max_pixels);

    const cJSON *list = cJSON_GetObjectItemCaseSensitive(root, "images");
    if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) != M) {
        char what[96];
        snprintf(what, sizeof what, "an array of %d file names (grid %d x %d)", M, d->grid[0],
                 d->grid[1]);
        return expected(p, LUMIS_ERR_BAD_HEADER, "images", what, list);
    }
    mp->names = calloc((size_t)M, sizeof *mp->names);
    mp->paths = calloc((size_t)M, sizeof *mp->paths);
    if (!mp->names || !mp->paths) return LUMIS_ERR_OUT_OF_MEMORY;
    m->image_count = M;
    m->images = (const char *const *)mp->names;
    m->paths = (const char *const *)mp->paths;
    int k = 0;
    for (const cJSON *e = list->child; e && k < M; e = e->next, k++) {
        if (!cJSON_IsString(e) || !name_ok(e->valuestring)) {
            char at[32];
            snprintf(at, sizeof at, "images[%d]", k);
            return expected(p, LUMIS_ERR_BAD_HEADER, at,
                            "a relative path (no leading '/', no '..' component, no '\\')", e);
        }
        mp->names[k] = malloc(strlen(e->valuestring) + 1);
        mp->paths[k] = join_path(base_dir, e->valuestring);
        if (!mp->names[k] || !mp->paths[k]) return LUMIS_ERR_OUT_OF_MEMORY;
        strcpy(mp->names[k], e->valuestring);
    }
    const cJSON *dg = cJSON_GetObjectItemCaseSensitive(root, "pixels_digest");
    if (dg) {
        unsigned long long dv = 0;
        char *end = NULL;
        if (cJSON_IsString(dg) && strlen(dg->valuestring) == 16)
            dv = strtoull(dg->valuestring, &end, 16);
        if (!end || *end)
            return expected(p, LUMIS_ERR_BAD_HEADER, "pixels_digest", "16 hexadecimal digits", dg);
        m->has_pixels_digest = 1;
        m->pixels_digest = (uint64_t)dv;
    }
    /* The core's own checks, as a net under ours (they cannot disagree). */
    return lumis_luminaire_check(d) == LUMIS_OK
               ? LUMIS_OK
               : lumis__fail(p->errors, LUMIS_ERR_BAD_HEADER, "%s: inconsistent geometry", p->file);
}

static uint64_t pixel_limit(const lumis_luminaire_read_options *options)
{
    return options && options->max_pixels ? (uint64_t)options->max_pixels
                                          : LUMIS_DEFAULT_MAX_PIXELS;
}

lumis_status lumis_luminaire_manifest_parse(const char *text, size_t size, const char *name,
                                            const char *base_dir,
                                            const lumis_luminaire_read_options *options,
                                            lumis_luminaire_manifest **out)
{
    const lumis_error_sink *errors = options ? &options->errors : NULL;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    parser p = {name ? name : "<memory>", errors};
    if (!text && size)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "%s: no data given", p.file);
    if (size == 0) return lumis__fail(errors, LUMIS_ERR_EMPTY_FILE, "%s: file is empty", p.file);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, size, &end, 0);
    /* Only white space may follow the value (cJSON stops after it). */
    while (root && end && end < text + size &&
           (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r'))
        end++;
    if (root && end && end < text + size) {
        cJSON_Delete(root);
        root = NULL;
    } else if (!root)
        end = cJSON_GetErrorPtr();
    if (!root) {
        const char *e = end;
        size_t at = e && e >= text && e <= text + size ? (size_t)(e - text) : 0;
        int line = 1;
        for (size_t k = 0; k < at; k++) line += text[k] == '\n';
        return lumis__fail(errors, LUMIS_ERR_BAD_HEADER, "%s:%d: malformed JSON", p.file, line);
    }
    manifest_private *mp = calloc(1, sizeof *mp);
    lumis_status st =
        mp ? parse_root(&p, root, base_dir, pixel_limit(options), mp) : LUMIS_ERR_OUT_OF_MEMORY;
    cJSON_Delete(root);
    if (st == LUMIS_ERR_OUT_OF_MEMORY)
        lumis__fail(errors, st, "%s: out of memory reading the manifest", p.file);
    if (st != LUMIS_OK) {
        lumis_luminaire_manifest_destroy(mp ? &mp->pub : NULL);
        return st;
    }
    *out = &mp->pub;
    return LUMIS_OK;
}

char *lumis__lumfile_dir_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    size_t n = slash ? (size_t)(slash - path) + 1 : 0;
    char *d = malloc(n + 1);
    if (!d) return NULL;
    memcpy(d, path, n);
    d[n] = '\0';
    return d;
}

lumis_status lumis_luminaire_manifest_read(const char *manifest_path,
                                           const lumis_luminaire_read_options *options,
                                           lumis_luminaire_manifest **out)
{
    const lumis_error_sink *errors = options ? &options->errors : NULL;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    char *text = NULL;
    size_t n = 0;
    const lumis_status rst =
        lumis__read_whole(manifest_path, MAX_MANIFEST, "luminaire manifest", errors, &text, &n);
    if (rst != LUMIS_OK) return rst;
    char *dir = lumis__lumfile_dir_of(manifest_path);
    lumis_status st =
        dir ? lumis_luminaire_manifest_parse(text, n, manifest_path, dir, options, out)
            : LUMIS_ERR_OUT_OF_MEMORY;
    free(dir);
    free(text);
    return st;
}

/* ---- reading -------------------------------------------------------------------------- */

uint64_t lumis__lumfile_pixels_digest(const float *const *images, int count, size_t floats)
{
    uint64_t h = 0xcbf29ce484222325ull;
    for (int m = 0; m < count; m++) {
        const float *p = images[m];
        for (size_t k = 0; k < floats; k++) {
            uint32_t w;
            memcpy(&w, p + k, sizeof w);
            h ^= w;
            h *= 0x100000001b3ull;
        }
    }
    return h;
}

/* Image m of the manifest into dst (width * height RGB, row 0 at the smallest y).  The
 * image reader reports its own failures (naming the image file); this adds one message
 * naming the manifest and the field. */
static lumis_status read_image(const char *manifest_path, const lumis_luminaire_manifest *man,
                               int m, const lumis_error_sink *errors, float *dst,
                               uint64_t *replaced)
{
    const lumis_luminaire_desc *d = &man->desc;
    lumis_read_options ro = {0};
    /* The manifest's size as the limit: a larger file is refused before it is decoded. */
    ro.max_pixels = (uint64_t)d->width * (uint64_t)d->height;
    ro.errors = *errors;
    lumis_image *img = NULL;
    lumis_read_info info;
    lumis_status st = lumis_image_read(man->paths[m], &ro, &img, &info);
    if (st == LUMIS_ERR_TOO_LARGE)
        return lumis__fail(errors, LUMIS_ERR_BAD_DIMENSIONS,
                           "%s: images[%d]: \"%s\" has more pixels than image.width x "
                           "image.height = %d x %d",
                           manifest_path, m, man->images[m], d->width, d->height);
    if (st != LUMIS_OK)
        return lumis__fail(errors, st, "%s: images[%d]: cannot read \"%s\" (%s): %s", manifest_path,
                           m, man->images[m], man->paths[m], lumis_status_string(st));
    if (img->width != d->width || img->height != d->height) {
        st = lumis__fail(errors, LUMIS_ERR_BAD_DIMENSIONS,
                         "%s: images[%d]: \"%s\" is %d x %d pixels, expected image.width x "
                         "image.height = %d x %d",
                         manifest_path, m, man->images[m], img->width, img->height, d->width,
                         d->height);
        lumis_image_destroy(img);
        return st;
    }
    /* A file's top row is the largest y (docs/formats.md). */
    const size_t row = (size_t)d->width * 3;
    for (int j = 0; j < d->height; j++)
        memcpy(dst + (size_t)j * row, img->pixels + (size_t)(d->height - 1 - j) * row,
               row * sizeof(float));
    *replaced += lumis_replaced_total(info.replaced);
    lumis_image_destroy(img);
    return LUMIS_OK;
}

lumis_status lumis_luminaire_read(const char *manifest_path,
                                  const lumis_luminaire_read_options *options,
                                  struct lumis_luminaire **out)
{
    static const lumis_luminaire_read_options zero_options;
    if (!options) options = &zero_options;
    const lumis_error_sink *errors = &options->errors;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    lumis_luminaire_manifest *man = NULL;
    lumis_status st = lumis_luminaire_manifest_read(manifest_path, options, &man);
    if (st != LUMIS_OK) return st;
    lumis_luminaire_desc d = man->desc;
    const int M = man->image_count;
    const size_t n = (size_t)d.width * (size_t)d.height * 3;
    float *rgb = malloc((size_t)M * n * sizeof(float));
    const float **ptrs = malloc((size_t)M * sizeof *ptrs);
    if (!rgb || !ptrs) {
        st = lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory for %d images",
                         manifest_path, M);
        goto done;
    }
    uint64_t replaced = 0;
    for (int m = 0; m < M && st == LUMIS_OK; m++) {
        ptrs[m] = rgb + (size_t)m * n;
        st = read_image(manifest_path, man, m, errors, rgb + (size_t)m * n, &replaced);
    }
    if (st != LUMIS_OK) goto done;
    if (man->has_pixels_digest && !replaced &&
        lumis__lumfile_pixels_digest(ptrs, M, n) != man->pixels_digest) {
        st = lumis__fail(errors, LUMIS_ERR_CORRUPT,
                         "%s: pixels_digest: the images are not the ones this manifest was "
                         "written with (changed, or a write of another luminaire over it "
                         "failed half-way): write the luminaire again",
                         manifest_path);
        goto done;
    }
    if (replaced)
        lumis__fail(errors, LUMIS_OK,
                    "%s: %llu negative or non-finite pixel values in the images replaced by 0",
                    manifest_path, (unsigned long long)replaced);
    d.pixels = ptrs;
    d.errors = *errors;
    /* The images' reader already replaced their bad values: the luminaire copies the
     * sanitised images and adds the reader's count to its own (its info said 0 after 1440
     * replacements). */
    d.replaced_before = (size_t)replaced;
    st = lumis_luminaire_create(&d, out);
done:
    free(ptrs);
    free(rgb);
    lumis_luminaire_manifest_destroy(man);
    return st;
}
