/* Radiance RGBE (.hdr, .pic): reader for flat, old-style RLE and new-style RLE scanlines,
 * in any of the row/column orientations with rows first; writer through stb_image_write.
 * Format: Greg Ward, "Real Pixels" (Graphics Gems II) and Radiance's color.c. */
#include "internal.h"

#include "../core/internal.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

typedef struct cursor {
    const unsigned char *p, *end;
} cursor;

/* Reads one header line (without its newline) into buf; 0 at the end of the data. */
static int read_line(cursor *c, char *buf, size_t cap, int *too_long)
{
    if (c->p >= c->end) return 0;
    size_t n = 0;
    *too_long = 0;
    while (c->p < c->end && *c->p != '\n') {
        if (n + 1 < cap)
            buf[n++] = (char)*c->p;
        else
            *too_long = 1;
        c->p++;
    }
    if (c->p >= c->end) return 0; /* no newline: the header never ended */
    c->p++;
    buf[n] = '\0';
    return 1;
}

static void rgbe_to_float(const unsigned char e[4], float scale, float *out)
{
    if (e[3] == 0) {
        out[0] = out[1] = out[2] = 0.0f;
        return;
    }
    /* Radiance's colr_color: the mantissa's centre, (m + 0.5) / 256 * 2^(e - 128). */
    float f = ldexpf(1.0f, (int)e[3] - (128 + 8)) * scale;
    out[0] = ((float)e[0] + 0.5f) * f;
    out[1] = ((float)e[1] + 0.5f) * f;
    out[2] = ((float)e[2] + 0.5f) * f;
}

/* One scanline of w RGBE pixels into line (4 bytes per pixel). */
static lumis_status read_scanline(cursor *c, unsigned char *line, int w, const lumis__read_ctx *ctx,
                                  int row)
{
    const lumis_error_sink *err = ctx->errors;
    size_t avail = (size_t)(c->end - c->p);
    if (w >= 8 && w < 0x8000 && avail >= 4 && c->p[0] == 2 && c->p[1] == 2 && c->p[2] < 128) {
        int encoded_w = (c->p[2] << 8) | c->p[3];
        if (encoded_w != w)
            return lumis__fail(err, LUMIS_ERR_CORRUPT,
                               "%s: scanline %d says it is %d pixels wide, the image is %d",
                               ctx->name, row, encoded_w, w);
        c->p += 4;
        /* New-style RLE: each of the four components run-length coded in turn. */
        for (int comp = 0; comp < 4; comp++) {
            int x = 0;
            while (x < w) {
                if (c->p >= c->end) goto truncated;
                int count = *c->p++;
                if (count > 128) {
                    count -= 128;
                    if (count > w - x)
                        return lumis__fail(err, LUMIS_ERR_CORRUPT, "%s: run overflows scanline %d",
                                           ctx->name, row);
                    if (c->p >= c->end) goto truncated;
                    unsigned char v = *c->p++;
                    for (int k = 0; k < count; k++) line[4 * (x++) + comp] = v;
                } else {
                    if (count == 0 || count > w - x)
                        return lumis__fail(err, LUMIS_ERR_CORRUPT,
                                           "%s: bad literal run in scanline %d", ctx->name, row);
                    if ((size_t)(c->end - c->p) < (size_t)count) goto truncated;
                    for (int k = 0; k < count; k++) line[4 * (x++) + comp] = *c->p++;
                }
            }
        }
        return LUMIS_OK;
    }
    /* Flat pixels, possibly with old-style runs (1,1,1,n) repeating the previous pixel
     * n << shift times, shift growing by 8 for consecutive run markers. */
    int x = 0, shift = 0;
    while (x < w) {
        if ((size_t)(c->end - c->p) < 4) goto truncated;
        const unsigned char *q = c->p;
        c->p += 4;
        if (q[0] == 1 && q[1] == 1 && q[2] == 1) {
            if (x == 0 || shift > 16)
                return lumis__fail(err, LUMIS_ERR_CORRUPT, "%s: bad old-style run in scanline %d",
                                   ctx->name, row);
            size_t count = (size_t)q[3] << shift;
            if (count > (size_t)(w - x))
                return lumis__fail(err, LUMIS_ERR_CORRUPT, "%s: run overflows scanline %d",
                                   ctx->name, row);
            for (size_t k = 0; k < count; k++, x++) memcpy(line + 4 * x, line + 4 * (x - 1), 4);
            shift += 8;
        } else {
            memcpy(line + 4 * x, q, 4);
            x++;
            shift = 0;
        }
    }
    return LUMIS_OK;
truncated:
    return lumis__fail(err, LUMIS_ERR_TRUNCATED, "%s: data ends in scanline %d of the image",
                       ctx->name, row);
}

/* Parses "-Y 512 +X 1024" (or another row-major orientation). */
static lumis_status parse_resolution(const char *s, const lumis__read_ctx *ctx, int64_t *w,
                                     int64_t *h, int *flip_y, int *flip_x)
{
    char sy, ay, sx, ax;
    int used = 0;
    if (sscanf(s, " %c%c %*[0-9-] %c%c %*[0-9-]%n", &sy, &ay, &sx, &ax, &used) != 4 || !used ||
        (sy != '-' && sy != '+') || (sx != '-' && sx != '+'))
        return lumis__fail(ctx->errors, LUMIS_ERR_BAD_HEADER,
                           "%s: malformed resolution line \"%.60s\"", ctx->name, s);
    if (ay != 'Y' || ax != 'X')
        return lumis__fail(ctx->errors, LUMIS_ERR_UNSUPPORTED,
                           "%s: column-major orientation \"%.60s\" is not supported", ctx->name, s);
    /* Parse the numbers ourselves: strtoll reports overflow, sscanf does not. */
    const char *p = s;
    int64_t v[2];
    for (int k = 0; k < 2; k++) {
        while (*p == ' ' || *p == '\t') p++;
        p += 2; /* sign and axis */
        char *endp;
        errno = 0;
        long long n = strtoll(p, &endp, 10);
        if (endp == p)
            return lumis__fail(ctx->errors, LUMIS_ERR_BAD_HEADER,
                               "%s: malformed resolution line \"%.60s\"", ctx->name, s);
        if (errno == ERANGE) n = n < 0 ? INT64_MIN : INT64_MAX;
        v[k] = n;
        p = endp;
    }
    *h = v[0];
    *w = v[1];
    *flip_y = sy == '+'; /* +Y: the first scanline is the bottom row */
    *flip_x = sx == '-';
    return LUMIS_OK;
}

lumis_status lumis__hdr_read(const unsigned char *data, size_t size, const lumis__read_ctx *ctx,
                             lumis_image **out)
{
    const lumis_error_sink *err = ctx->errors;
    cursor c = {data, data + size};
    char line[1024];
    int too_long = 0, xyze = 0, have_format = 0;
    double exposure = 1.0;
    if (size < 2 || data[0] != '#' || data[1] != '?')
        return lumis__fail(err, LUMIS_ERR_BAD_MAGIC,
                           "%s: not a Radiance HDR file (no \"#?\" signature)", ctx->name);
    /* Header: variable lines up to an empty line. */
    for (;;) {
        if (!read_line(&c, line, sizeof line, &too_long))
            return lumis__fail(err, LUMIS_ERR_TRUNCATED, "%s: header never ends", ctx->name);
        if (line[0] == '\0') break;
        if (too_long)
            return lumis__fail(err, LUMIS_ERR_BAD_HEADER, "%s: header line longer than %zu bytes",
                               ctx->name, sizeof line);
        if (strncmp(line, "FORMAT=", 7) == 0) {
            have_format = 1;
            if (strcmp(line + 7, "32-bit_rle_xyze") == 0)
                xyze = 1;
            else if (strcmp(line + 7, "32-bit_rle_rgbe") != 0)
                return lumis__fail(err, LUMIS_ERR_UNSUPPORTED, "%s: unsupported %.60s", ctx->name,
                                   line);
        } else if (strncmp(line, "EXPOSURE=", 9) == 0) {
            /* Stored values are radiance times every EXPOSURE given; undo them. */
            char *endp;
            double e = strtod(line + 9, &endp);
            if (endp == line + 9 || !(e > 0.0) || !isfinite(e))
                return lumis__fail(err, LUMIS_ERR_BAD_HEADER, "%s: bad %.60s", ctx->name, line);
            exposure *= e;
        }
    }
    (void)have_format; /* Radiance assumes RGBE when FORMAT is absent */
    if (!read_line(&c, line, sizeof line, &too_long))
        return lumis__fail(err, LUMIS_ERR_TRUNCATED, "%s: no resolution line", ctx->name);
    int64_t w64 = 0, h64 = 0;
    int flip_y = 0, flip_x = 0;
    lumis_status st = parse_resolution(line, ctx, &w64, &h64, &flip_y, &flip_x);
    if (st != LUMIS_OK) return st;
    st = lumis_image_check_size(w64, h64, ctx->max_pixels);
    if (st != LUMIS_OK)
        return lumis__fail(err, st, "%s: %lld x %lld pixels: %s", ctx->name, (long long)w64,
                           (long long)h64, lumis_status_string(st));
    int w = (int)w64, h = (int)h64;
    /* Every pixel needs at least one byte even when run-length coded (4 per 128-pixel run
     * in the best case): a claimed size far beyond the data is truncated, not allocated. */
    if ((uint64_t)(c.end - c.p) * 32u < (uint64_t)w * (uint64_t)h / 128u)
        return lumis__fail(err, LUMIS_ERR_TRUNCATED,
                           "%s: %d x %d pixels cannot fit in the %zu bytes left", ctx->name, w, h,
                           (size_t)(c.end - c.p));

    unsigned char *scan = malloc((size_t)w * 4);
    st = lumis_image_create(w, h, out);
    if (st != LUMIS_OK || !scan) {
        free(scan);
        lumis_image_destroy(*out);
        *out = NULL;
        return lumis__fail(err, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", ctx->name);
    }
    float scale = (float)(1.0 / exposure);
    for (int r = 0; r < h && st == LUMIS_OK; r++) {
        st = read_scanline(&c, scan, w, ctx, r);
        if (st != LUMIS_OK) break;
        int y = flip_y ? h - 1 - r : r;
        float *dst = (*out)->pixels + (size_t)y * (size_t)w * 3;
        for (int x = 0; x < w; x++) {
            int xx = flip_x ? w - 1 - x : x;
            float *p = dst + 3 * (size_t)xx;
            rgbe_to_float(scan + 4 * (size_t)x, scale, p);
            if (xyze) {
                /* CIE XYZ (Radiance's equal-energy white) to linear Rec. 709 RGB. */
                float X = p[0], Y = p[1], Z = p[2];
                p[0] = 3.2404542f * X - 1.5371385f * Y - 0.4985314f * Z;
                p[1] = -0.9692660f * X + 1.8760108f * Y + 0.0415560f * Z;
                p[2] = 0.0556434f * X - 0.2040259f * Y + 1.0572252f * Z;
            }
        }
    }
    free(scan);
    if (st != LUMIS_OK) {
        lumis_image_destroy(*out);
        *out = NULL;
    }
    return st;
}

static void write_to_file(void *context, void *data, int size)
{
    FILE *f = context;
    if (size > 0) fwrite(data, 1, (size_t)size, f);
}

/* The largest value RGBE holds: mantissa 255/256, exponent 127 (a value of 2^127 or more
 * would need exponent byte 256, which stb wraps to 0: black). */
#define RGBE_MAX 0x1.fep126f

lumis_status lumis__hdr_write(FILE *f, const lumis_image *image)
{
    /* stb clamps nothing and writes new-style RLE for widths 8..32767, flat otherwise: values
     * past RGBE's range are clamped to its largest (as the EXR half writer clamps to 65504),
     * NaN written as 0, in a copy made only when some value needs it. */
    const size_t n = (size_t)image->width * (size_t)image->height * 3;
    const float *px = image->pixels;
    float *copy = NULL;
    for (size_t k = 0; k < n; k++)
        if (!(px[k] <= RGBE_MAX)) {
            copy = malloc(n * sizeof(float));
            if (!copy) return LUMIS_ERR_OUT_OF_MEMORY;
            for (size_t q = 0; q < n; q++)
                copy[q] = px[q] <= RGBE_MAX ? px[q] : (isnan(px[q]) ? 0.0f : RGBE_MAX);
            px = copy;
            break;
        }
    const int ok = stbi_write_hdr_to_func(write_to_file, f, image->width, image->height, 3, px);
    free(copy);
    if (!ok) return LUMIS_ERR_WRITE;
    return ferror(f) ? LUMIS_ERR_WRITE : LUMIS_OK;
}
