/* Luminaire files, written: the manifest (every number the shortest text that reads back
 * the same) and its images, atomically, beside an images folder the writer owns.  Schema:
 * docs/formats.md, "Luminaire files"; reading: luminaire_file.c. */
#include "lumis/io.h"

#include "internal.h"
#include "luminaire_file.h"

#include "../core/internal.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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
    if (!lumis__lumfile_units_ok(units))
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
    char *dir = lumis__lumfile_dir_of(where);
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
    text = manifest_text(
        &d, units, names,
        lumis__lumfile_pixels_digest(d.pixels, M, (size_t)d.width * (size_t)d.height * 3), &len);
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
