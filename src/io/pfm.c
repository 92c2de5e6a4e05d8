/* Portable Float Map (.pfm): "PF" (RGB) or "Pf" (grey), width, height, a scale whose sign
 * gives the byte order (negative: little-endian), then raw 32-bit floats, bottom row
 * first.  The scale's magnitude is not applied, as in most readers. */
#include "internal.h"

#include "../core/internal.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int is_space(unsigned char ch)
{
    return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r' || ch == '\v' || ch == '\f';
}

/* Next whitespace-delimited token of the header, copied into buf. */
static int next_token(const unsigned char **p, const unsigned char *end, char *buf, size_t cap)
{
    while (*p < end && is_space(**p)) (*p)++;
    size_t n = 0;
    while (*p < end && !is_space(**p)) {
        if (n + 1 >= cap) return 0;
        buf[n++] = (char)*(*p)++;
    }
    buf[n] = '\0';
    return n > 0 && *p < end; /* a token must be followed by whitespace */
}

static lumis_status parse_dim(const char *tok, const lumis__read_ctx *ctx, const char *what,
                              int64_t *out)
{
    *out = 0; /* written on every path: callers read it only on success, but say so */
    char *endp;
    errno = 0;
    long long v = strtoll(tok, &endp, 10);
    if (*endp != '\0' || endp == tok)
        return lumis__fail(ctx->errors, LUMIS_ERR_BAD_HEADER, "%s: %s \"%s\" is not an integer",
                           ctx->name, what, tok);
    if (errno == ERANGE) v = v < 0 ? INT64_MIN : INT64_MAX;
    *out = v;
    return LUMIS_OK;
}

static float load_float(const unsigned char *b, int big_endian)
{
    uint32_t u =
        big_endian
            ? ((uint32_t)b[0] << 24 | (uint32_t)b[1] << 16 | (uint32_t)b[2] << 8 | (uint32_t)b[3])
            : ((uint32_t)b[3] << 24 | (uint32_t)b[2] << 16 | (uint32_t)b[1] << 8 | (uint32_t)b[0]);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

lumis_status lumis__pfm_read(const unsigned char *data, size_t size, const lumis__read_ctx *ctx,
                             lumis_image **out)
{
    const lumis_error_sink *err = ctx->errors;
    if (size < 2 || data[0] != 'P' || (data[1] != 'F' && data[1] != 'f'))
        return lumis__fail(err, LUMIS_ERR_BAD_MAGIC, "%s: not a PFM file (no \"PF\"/\"Pf\")",
                           ctx->name);
    int channels = data[1] == 'F' ? 3 : 1;
    const unsigned char *p = data + 2, *end = data + size;
    if (p >= end || !is_space(*p))
        return lumis__fail(err, LUMIS_ERR_BAD_MAGIC, "%s: not a PFM file", ctx->name);
    char tw[32], th[32], ts[64];
    if (!next_token(&p, end, tw, sizeof tw) || !next_token(&p, end, th, sizeof th) ||
        !next_token(&p, end, ts, sizeof ts))
        return lumis__fail(err, p >= end ? LUMIS_ERR_TRUNCATED : LUMIS_ERR_BAD_HEADER, "%s: %s",
                           ctx->name, p >= end ? "header ends early" : "header field too long");
    int64_t w64, h64;
    lumis_status st = parse_dim(tw, ctx, "width", &w64);
    if (st == LUMIS_OK) st = parse_dim(th, ctx, "height", &h64);
    if (st != LUMIS_OK) return st;
    char *endp;
    double scale = strtod(ts, &endp);
    if (*endp != '\0' || scale == 0.0 || !isfinite(scale))
        return lumis__fail(err, LUMIS_ERR_BAD_HEADER, "%s: scale \"%s\" must be a non-zero number",
                           ctx->name, ts);
    p++; /* exactly one whitespace character separates the header from the data */

    st = lumis_image_check_size(w64, h64, ctx->max_pixels);
    if (st != LUMIS_OK)
        return lumis__fail(err, st, "%s: %lld x %lld pixels: %s", ctx->name, (long long)w64,
                           (long long)h64, lumis_status_string(st));
    size_t w = (size_t)w64, h = (size_t)h64;
    size_t need = w * h * (size_t)channels * 4; /* cannot overflow after the size check */
    size_t have = (size_t)(end - p);
    if (have < need)
        return lumis__fail(err, LUMIS_ERR_TRUNCATED,
                           "%s: %zu x %zu pixels need %zu bytes of data, the file has %zu",
                           ctx->name, w, h, need, have);
    st = lumis_image_create((int)w, (int)h, out);
    if (st != LUMIS_OK) return lumis__fail(err, st, "%s: %s", ctx->name, lumis_status_string(st));
    int big = scale > 0.0;
    for (size_t r = 0; r < h; r++) {
        const unsigned char *src = p + r * w * (size_t)channels * 4;
        float *dst = (*out)->pixels + (h - 1 - r) * w * 3; /* bottom row first */
        for (size_t x = 0; x < w; x++) {
            if (channels == 3) {
                for (int c = 0; c < 3; c++)
                    dst[3 * x + (size_t)c] = load_float(src + 12 * x + 4 * (size_t)c, big);
            } else {
                float v = load_float(src + 4 * x, big);
                dst[3 * x] = dst[3 * x + 1] = dst[3 * x + 2] = v;
            }
        }
    }
    ctx->info->grey = channels == 1;
    if (have > need) /* a file padded, or a header that says fewer rows than it holds */
        lumis__fail(err, LUMIS_OK, "%s: %zu bytes after the %zu x %zu pixels ignored", ctx->name,
                    have - need, w, h);
    return LUMIS_OK;
}

lumis_status lumis__pfm_write(FILE *f, const lumis_image *image, int big_endian)
{
    size_t w = (size_t)image->width, h = (size_t)image->height;
    fprintf(f, "PF\n%zu %zu\n%s\n", w, h, big_endian ? "1.0" : "-1.0");
    unsigned char *row = malloc(w * 12);
    if (!row) return LUMIS_ERR_OUT_OF_MEMORY;
    for (size_t r = 0; r < h; r++) {
        const float *src = image->pixels + (h - 1 - r) * w * 3;
        for (size_t k = 0; k < w * 3; k++) {
            uint32_t u;
            memcpy(&u, &src[k], sizeof u);
            unsigned char *b = row + 4 * k;
            for (int i = 0; i < 4; i++) {
                int s = big_endian ? 24 - 8 * i : 8 * i;
                b[i] = (unsigned char)(u >> s);
            }
        }
        if (fwrite(row, 1, w * 12, f) != w * 12) break;
    }
    free(row);
    return ferror(f) ? LUMIS_ERR_WRITE : LUMIS_OK;
}
