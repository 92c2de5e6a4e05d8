/* Luminaire files: a JSON manifest (cJSON) naming M EXR or PFM images.  Schema:
 * docs/formats.md, "Luminaire files".  Every failure names the manifest, the JSON field
 * and what was expected; the images are read by lumis_image_read and checked against the
 * manifest's size. */
#include "lumis/io.h"

#include "internal.h"

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

#define FORMAT_NAME      "lumis-luminaire"
#define MAX_MANIFEST     ((long)1 << 24) /* bytes: 1024 names of 1024 bytes fit many times */
#define MAX_NAME         1024            /* bytes of one image name */
#define MAX_GRID_STR     "1..256"
#define MAX_SIDE_STR     "1..16384"
#define DEFAULT_UNITS    "mm"
#define UNITS_CAP        32
#define IMAGES_SUFFIX    ".images"
#define JSON_NUMBER_SIZE 40

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

static int units_ok(const char *s)
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
    if (!cJSON_IsString(v) || !units_ok(v->valuestring))
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

/* The folder part of path with its trailing slash ("" if none), malloc'ed. */
static char *dir_of(const char *path)
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
    char *dir = dir_of(manifest_path);
    lumis_status st =
        dir ? lumis_luminaire_manifest_parse(text, n, manifest_path, dir, options, out)
            : LUMIS_ERR_OUT_OF_MEMORY;
    free(dir);
    free(text);
    return st;
}

/* ---- reading -------------------------------------------------------------------------- */

/* Image m of the manifest into dst (width * height RGB, row 0 at the smallest y).  The
 * image reader reports its own failures (naming the image file); this adds one message
 * naming the manifest and the field. */
/* FNV-1a over 32-bit words: the images' float bits, image by image in the luminaire's row
 * order (row 0 the smallest y).  Word-wise, so 99 images of 256 x 256 cost ~20 ms. */
static uint64_t pixels_digest(const float *const *images, int count, size_t floats)
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
    if (man->has_pixels_digest && !replaced && pixels_digest(ptrs, M, n) != man->pixels_digest) {
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

/* ---- writing -------------------------------------------------------------------------- */

/* A growing text buffer; a failed allocation sticks (ok == 0) and is checked once. */
typedef struct text_buf {
    char *s;
    size_t len, cap;
    int ok;
} text_buf;

static void put(text_buf *b, const char *s, size_t n)
{
    if (!b->ok) return;
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 1024;
        while (cap < b->len + n + 1) cap *= 2;
        char *grown = realloc(b->s, cap);
        if (!grown) {
            b->ok = 0;
            return;
        }
        b->s = grown;
        b->cap = cap;
    }
    memcpy(b->s + b->len, s, n);
    b->len += n;
    b->s[b->len] = '\0';
}

static void puts_(text_buf *b, const char *s)
{
    put(b, s, strlen(s));
}

/* A JSON string: quotes, backslashes and control characters escaped. */
static void put_string(text_buf *b, const char *s)
{
    put(b, "\"", 1);
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\') {
            char e[2] = {'\\', (char)c};
            put(b, e, 2);
        } else if (c < 0x20) {
            char e[8];
            snprintf(e, sizeof e, "\\u%04x", c);
            puts_(b, e);
        } else
            put(b, (const char *)&c, 1);
    }
    put(b, "\"", 1);
}

/* The shortest %g that reads back as x exactly (a '.' whatever the locale). */
static void put_number(text_buf *b, double x)
{
    char s[JSON_NUMBER_SIZE];
    for (int prec = 1; prec <= 17; prec++) {
        snprintf(s, sizeof s, "%.*g", prec, x);
        if (strtod(s, NULL) == x) break;
    }
    for (char *c = s; *c; c++)
        if (*c == ',') *c = '.';
    puts_(b, s);
}

static void put_pair(text_buf *b, const double v[2])
{
    puts_(b, "[");
    put_number(b, v[0]);
    puts_(b, ", ");
    put_number(b, v[1]);
    puts_(b, "]");
}

static char *manifest_text(const lumis_luminaire_desc *d, const char *units, char *const *names,
                           uint64_t digest, size_t *len)
{
    text_buf b = {NULL, 0, 0, 1};
    puts_(&b, "{\n  \"format\": \"" FORMAT_NAME "\",\n  \"version\": 1,\n  \"units\": ");
    put_string(&b, units);
    puts_(&b, ",\n  \"delta\": ");
    put_number(&b, d->delta);
    puts_(&b, ",\n  \"basis\": ");
    put_string(&b, d->basis == LUMIS_BASIS_BSPLINE ? "bspline" : "quadratic");
    char s[64];
    snprintf(s, sizeof s, ",\n  \"grid\": [%d, %d],\n  \"grid_origin\": ", d->grid[0], d->grid[1]);
    puts_(&b, s);
    put_pair(&b, d->grid_origin);
    puts_(&b, ",\n  \"grid_spacing\": ");
    put_pair(&b, d->grid_spacing);
    snprintf(s, sizeof s, ",\n  \"image\": {\"width\": %d, \"height\": %d, \"origin\": ", d->width,
             d->height);
    puts_(&b, s);
    put_pair(&b, d->image_origin);
    puts_(&b, ", \"size\": ");
    put_pair(&b, d->image_size);
    puts_(&b, "},\n  \"images\": [");
    const int M = d->grid[0] * d->grid[1];
    for (int m = 0; m < M; m++) {
        puts_(&b, m ? ",\n    " : "\n    ");
        put_string(&b, names[m]);
    }
    snprintf(s, sizeof s, "\n  ],\n  \"pixels_digest\": \"%016llx\"\n}\n",
             (unsigned long long)digest);
    puts_(&b, s);
    if (!b.ok) {
        free(b.s);
        return NULL;
    }
    *len = b.len;
    return b.s;
}

/* Removes a luminaire image folder this module made: its images (aNNN_bNNN.exr or .pfm),
 * then moves anything else it holds into keep (when given, and where keep has no entry of
 * that name: a user's notes beside the images stay beside them), and removes the folder if
 * it is then empty. */
static void remove_images(const char *folder, const char *keep)
{
    DIR *dp = opendir(folder);
    if (!dp) return;
    const size_t n = strlen(folder);
    char path[4096];
    struct dirent *e;
    while ((e = readdir(dp)) != NULL) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
        if (n + strlen(e->d_name) + 2 > sizeof path) continue;
        snprintf(path, sizeof path, "%s/%s", folder, e->d_name);
        unsigned a, b;
        char ext[8], tail;
        if (sscanf(e->d_name, "a%3u_b%3u.%7s%c", &a, &b, ext, &tail) == 3 &&
            (strcmp(ext, "exr") == 0 || strcmp(ext, "pfm") == 0)) {
            unlink(path);
            continue;
        }
        const size_t kl = keep ? strlen(keep) : 0, el = strlen(e->d_name);
        char *there = keep ? malloc(kl + el + 2) : NULL;
        struct stat sb;
        if (there) {
            memcpy(there, keep, kl);
            there[kl] = '/';
            memcpy(there + kl + 1, e->d_name, el + 1);
            if (lstat(there, &sb) != 0) (void)rename(path, there);
            free(there);
        }
    }
    closedir(dp);
    rmdir(folder);
}

/* lumis_luminaire_write at `where` (manifest_path with its links followed), messages naming
 * manifest_path. */
static lumis_status write_luminaire(const char *manifest_path, const char *where,
                                    const struct lumis_luminaire *lum,
                                    const lumis_luminaire_write_options *options)
{
    static const lumis_luminaire_write_options zero_options;
    if (!options) options = &zero_options;
    const lumis_error_sink *errors = &options->errors;
    if (!manifest_path || !*manifest_path || !lum)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "luminaire write: no manifest path or luminaire given");
    lumis_file_format format =
        options->image_format == LUMIS_FORMAT_AUTO ? LUMIS_FORMAT_EXR : options->image_format;
    if (format != LUMIS_FORMAT_EXR && format != LUMIS_FORMAT_PFM)
        return lumis__fail(
            errors, LUMIS_ERR_INVALID_ARGUMENT,
            "%s: luminaire images are written as EXR or PFM (lossless float), not %s",
            manifest_path, lumis_format_name(format));
    const char *units = options->units ? options->units : DEFAULT_UNITS;
    if (!units_ok(units))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: units: expected 1..31 printable bytes", manifest_path);
    const char *base = strrchr(where, '/');
    base = base ? base + 1 : where;
    if (!*base || strcmp(base, ".") == 0 || strcmp(base, "..") == 0)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: the manifest path names a folder, not a file", manifest_path);
    /* <stem>.images beside the manifest; a name without a stem (".json") keeps it whole. */
    const char *dot = strrchr(base, '.');
    size_t stem = dot && dot > base ? (size_t)(dot - base) : strlen(base);
    /* The image names must be names a reader accepts (no '\\' or control character). */
    for (size_t k = 0; k < stem; k++)
        if ((unsigned char)base[k] < 0x20 || base[k] == '\\' || base[k] == 0x7f)
            return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "%s: a manifest name with '\\' or a control character would give "
                               "image names the format does not allow",
                               manifest_path);
    if (stem + sizeof IMAGES_SUFFIX + 32 > MAX_NAME)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: the manifest's name is too long for its image names",
                           manifest_path);

    lumis_luminaire_desc d;
    lumis_luminaire_get_desc(lum, &d);
    const int M = d.grid[0] * d.grid[1];
    const char *ext = format == LUMIS_FORMAT_EXR ? "exr" : "pfm";
    /* Nothing of an existing luminaire is touched until the new one is complete: the images
     * go to a fresh staging folder beside it; then the old folder steps aside, the staging
     * folder takes its name, and the manifest is replaced (atomically).  A failure at any
     * step puts the old folder back, so the old manifest and images stay a pair.  (A crash
     * between the swap and the manifest leaves the old manifest with the new images, which
     * the manifest's pixel digest refuses on load, and a staging or old folder beside.) */
    char *dir = dir_of(where);
    const size_t dlen = dir ? strlen(dir) : 0;
    const size_t flen = dlen + stem + sizeof IMAGES_SUFFIX; /* with its NUL */
    char *folder = malloc(flen), *stage = malloc(flen + 16), *old = malloc(flen + 16);
    char *path = malloc(flen + 48); /* an image's path in either folder */
    char *text = NULL;
    float *flipped = malloc((size_t)d.width * (size_t)d.height * 3 * sizeof(float));
    char **names = calloc((size_t)M, sizeof *names);
    lumis_status st = LUMIS_OK;
    int staged = 0, moved_old = 0, swapped = 0, blocked = 0;
    sigset_t was;
    if (!dir || !folder || !stage || !old || !path || !flipped || !names) {
        st = lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", manifest_path);
        goto done;
    }
    snprintf(folder, flen, "%s%.*s" IMAGES_SUFFIX, dir, (int)stem, base);
    struct stat sb;
    const int exists = lstat(folder, &sb) == 0;
    if (exists && !S_ISDIR(sb.st_mode)) {
        st = lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot create the image folder %s: %s",
                         manifest_path, folder, strerror(ENOTDIR));
        goto done;
    }
    snprintf(stage, flen + 16, "%s.new-XXXXXX", folder);
    lumis__signals_block(&was); /* made and registered for removal on an interrupt, at once */
    const int made = mkdtemp(stage) != NULL;
    const int made_errno = errno;
    if (made) lumis__atomic_track_stage(stage, d.grid[0], d.grid[1], ext);
    lumis__signals_restore(&was);
    if (!made) {
        st = lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot create the image folder %s: %s",
                         manifest_path, stage, strerror(made_errno));
        goto done;
    }
    staged = 1;
    lumis_write_options wo = {0};
    wo.format = format;
    wo.errors = *errors;
    const size_t cap = stem + sizeof IMAGES_SUFFIX + 32;
    for (int m = 0; m < M && st == LUMIS_OK; m++) {
        /* The name relative to the manifest: "<stem>.images/a003_b001.exr". */
        names[m] = malloc(cap);
        if (!names[m]) {
            st = lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", manifest_path);
            break;
        }
        snprintf(names[m], cap, "%.*s" IMAGES_SUFFIX "/a%03d_b%03d.%s", (int)stem, base,
                 m % d.grid[0], m / d.grid[0], ext);
        snprintf(path, flen + 48, "%s/a%03d_b%03d.%s", stage, m % d.grid[0], m / d.grid[0], ext);
        /* Rows reversed: a file's top row is the largest y. */
        const size_t row = (size_t)d.width * 3;
        for (int j = 0; j < d.height; j++)
            memcpy(flipped + (size_t)j * row, d.pixels[m] + (size_t)(d.height - 1 - j) * row,
                   row * sizeof(float));
        lumis_image img = {d.width, d.height, flipped};
        st = lumis_image_write(path, &img, &wo);
    }
    if (st != LUMIS_OK) goto done;
    size_t len = 0;
    text = manifest_text(&d, units, names,
                         pixels_digest(d.pixels, M, (size_t)d.width * (size_t)d.height * 3), &len);
    if (!text) {
        st = lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", manifest_path);
        goto done;
    }
    /* From here to the end all or nothing: an interrupt waits until the manifest and its
     * folder are a pair again (the new one, or the old one put back). */
    lumis__signals_block(&was);
    blocked = 1;
    if (exists) { /* the old folder steps aside (rename onto an empty folder of our own) */
        snprintf(old, flen + 16, "%s.old-XXXXXX", folder);
        const int aside = mkdtemp(old) != NULL;
        if (!aside || rename(folder, old) != 0) {
            const int e = errno;
            if (aside) rmdir(old);
            st = lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot move the old images aside: %s",
                             manifest_path, strerror(e));
            goto done;
        }
        moved_old = 1;
    }
    if (rename(stage, folder) != 0) {
        st = lumis__fail(errors, LUMIS_ERR_WRITE, "%s: cannot rename %s to %s: %s", manifest_path,
                         stage, folder, strerror(errno));
        goto done;
    }
    swapped = 1;
    st = lumis_write_text(where, text, len, errors);
done:
    if (st != LUMIS_OK) {
        /* Take back what this call made; the old luminaire goes back where it was. */
        if (swapped && rename(folder, stage) != 0) staged = 0; /* cannot: leave it */
        if (moved_old && rename(old, folder) == 0) moved_old = 0;
        if (staged) remove_images(stage, NULL);
    }
    if (st == LUMIS_OK && moved_old) remove_images(old, folder); /* other files move along */
    if (staged) lumis__atomic_untrack_stage(stage);
    if (blocked) lumis__signals_restore(&was);
    if (names)
        for (int m = 0; m < M; m++) free(names[m]);
    free(names);
    free(flipped);
    free(path);
    free(old);
    free(stage);
    free(folder);
    free(dir);
    free(text);
    return st;
}

lumis_status lumis_luminaire_write(const char *manifest_path, const struct lumis_luminaire *lum,
                                   const lumis_luminaire_write_options *options)
{
    const lumis_error_sink *errors = options ? &options->errors : NULL;
    if (!manifest_path || !*manifest_path)
        return write_luminaire(manifest_path, manifest_path, lum, options);
    /* Through a link, the images go beside the manifest the link names (beside the link,
     * that manifest would name images that are not there). */
    int fd = -1;
    char *where = lumis__follow_links(manifest_path, &fd);
    if (!where)
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", manifest_path);
    lumis_status st =
        fd >= 0 ? lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                              "%s: a luminaire manifest is a file beside its images, not a stream",
                              manifest_path)
                : write_luminaire(manifest_path, where, lum, options);
    free(where);
    return st;
}
