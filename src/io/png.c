/* PNG output: exposure, a tone map, the sRGB transfer curve, 8 bits, via stb_image_write. */
#include "internal.h"

#include "../core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

static const char *const tonemap_names[LUMIS_TONEMAP_COUNT] = {"clamp", "reinhard", "aces"};

const char *lumis_tonemap_name(lumis_tonemap tonemap)
{
    return (unsigned)tonemap < LUMIS_TONEMAP_COUNT ? tonemap_names[tonemap] : "unknown";
}

lumis_status lumis_tonemap_from_name(const char *name, lumis_tonemap *out)
{
    for (int t = 0; name && t < LUMIS_TONEMAP_COUNT; t++)
        if (strcmp(name, tonemap_names[t]) == 0) {
            *out = (lumis_tonemap)t;
            return LUMIS_OK;
        }
    return LUMIS_ERR_INVALID_ARGUMENT;
}

float lumis_tonemap_apply(lumis_tonemap tonemap, float x)
{
    if (!(x > 0.0f)) return 0.0f; /* NaN and negatives are black */
    switch (tonemap) {
    case LUMIS_TONEMAP_REINHARD:
        x = x / (1.0f + x);
        break;
    case LUMIS_TONEMAP_ACES:
        /* Narkowicz 2015, "ACES Filmic Tone Mapping Curve". */
        x = (x * (2.51f * x + 0.03f)) / (x * (2.43f * x + 0.59f) + 0.14f);
        break;
    default:
        break;
    }
    return x < 1.0f ? x : 1.0f;
}

static unsigned char srgb8(float v)
{
    float s = v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
    return (unsigned char)lrintf(s * 255.0f);
}

static void write_to_file(void *context, void *data, int size)
{
    if (size > 0) fwrite(data, 1, (size_t)size, (FILE *)context);
}

lumis_status lumis__png_write(FILE *f, const lumis_image *image, float exposure_ev,
                              lumis_tonemap tonemap)
{
    size_t n = (size_t)image->width * (size_t)image->height * 3;
    if ((size_t)image->width * 3 > (size_t)INT32_MAX) return LUMIS_ERR_TOO_LARGE;
    unsigned char *rgb = malloc(n);
    if (!rgb) return LUMIS_ERR_OUT_OF_MEMORY;
    float k = exp2f(exposure_ev);
    for (size_t i = 0; i < n; i++)
        rgb[i] = srgb8(lumis_tonemap_apply(tonemap, image->pixels[i] * k));
    int ok = stbi_write_png_to_func(write_to_file, f, image->width, image->height, 3, rgb,
                                    image->width * 3);
    free(rgb);
    if (!ok) return LUMIS_ERR_WRITE;
    return ferror(f) ? LUMIS_ERR_WRITE : LUMIS_OK;
}

/* ---- reading ------------------------------------------------------------------------- */

#include "png_decode.h"

#include <pthread.h>

/* The sRGB transfer curve, inverted (IEC 61966-2-1), for every 16-bit code. */
static float srgb_lut[65536];
static pthread_once_t srgb_lut_once = PTHREAD_ONCE_INIT;

static void srgb_lut_init(void)
{
    for (int k = 0; k < 65536; k++) {
        double v = k / 65535.0;
        srgb_lut[k] = (float)(v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4));
    }
}

lumis_status lumis__png_read(const unsigned char *data, size_t size, const lumis__read_ctx *ctx,
                             lumis_image **out)
{
    int w = 0, h = 0;
    if (size < 8 || memcmp(data, "\x89PNG\r\n\x1a\n", 8) != 0)
        return lumis__fail(ctx->errors, LUMIS_ERR_BAD_MAGIC, "%s: not a PNG (no PNG signature)",
                           ctx->name);
    if (size > 0x7fffffff || !lumis__png_decode_info(data, (int)size, &w, &h))
        return lumis__fail(ctx->errors, LUMIS_ERR_CORRUPT, "%s: not a readable PNG: %s", ctx->name,
                           lumis__png_decode_error());
    lumis_status st = lumis_image_check_size(w, h, ctx->max_pixels);
    if (st != LUMIS_OK)
        return lumis__fail(ctx->errors, st, "%s: %d x %d: %s", ctx->name, w, h,
                           lumis_status_string(st));
    unsigned short *px = lumis__png_decode_rgb16(data, (int)size, &w, &h);
    if (!px)
        return lumis__fail(ctx->errors, LUMIS_ERR_CORRUPT, "%s: PNG decoding failed: %s", ctx->name,
                           lumis__png_decode_error());
    st = lumis_image_create(w, h, out);
    if (st == LUMIS_OK) {
        pthread_once(&srgb_lut_once, srgb_lut_init);
        const size_t n = 3 * (size_t)w * (size_t)h;
        for (size_t k = 0; k < n; k++) (*out)->pixels[k] = srgb_lut[px[k]];
    } else {
        lumis__fail(ctx->errors, st, "%s: %s", ctx->name, lumis_status_string(st));
    }
    lumis__png_decode_free(px);
    return st;
}
