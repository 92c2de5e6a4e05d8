/* PNG output (exposure, a tone map, the sRGB transfer curve, 8 bits) via stb_image_write;
 * PNG input, decoded from sRGB to linear, via libpng. */
#include "internal.h"

#include "../core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

static const char *const tonemap_names[] = {"clamp", "reinhard", "aces"};

LUMIS__ENUM_NAMES(lumis_tonemap, LUMIS_TONEMAP_COUNT, tonemap_names, lumis_tonemap_name,
                  lumis_tonemap_from_name);

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

/* ---- reading: libpng ---------------------------------------------------------------- */

#include <png.h>
#include <pthread.h>
#include <setjmp.h>

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

typedef struct png_source {
    const unsigned char *data;
    size_t size, pos;
    char error[160]; /* libpng's message when it fails */
} png_source;

static void png_source_read(png_structp png, png_bytep out, size_t n)
{
    png_source *src = (png_source *)png_get_io_ptr(png);
    if (n > src->size - src->pos) png_error(png, "file ends inside a chunk");
    memcpy(out, src->data + src->pos, n);
    src->pos += n;
}

static void png_on_error(png_structp png, png_const_charp message)
{
    png_source *src = (png_source *)png_get_error_ptr(png);
    snprintf(src->error, sizeof src->error, "%s", message);
    png_longjmp(png, 1);
}

static void png_on_warning(png_structp png, png_const_charp message)
{
    (void)png; /* the library never prints; a warning leaves a readable image */
    (void)message;
}

lumis_status lumis__png_read(const unsigned char *data, size_t size, const lumis__read_ctx *ctx,
                             lumis_image **out)
{
    if (size < 8 || png_sig_cmp(data, 0, 8) != 0)
        return lumis__fail(ctx->errors, LUMIS_ERR_BAD_MAGIC, "%s: not a PNG (no PNG signature)",
                           ctx->name);
    png_source src = {data, size, 0, ""};
    png_structp png =
        png_create_read_struct(PNG_LIBPNG_VER_STRING, &src, png_on_error, png_on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!info) {
        png_destroy_read_struct(&png, NULL, NULL);
        return lumis__fail(ctx->errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: %s", ctx->name,
                           lumis_status_string(LUMIS_ERR_OUT_OF_MEMORY));
    }
    /* Changed after setjmp and used after a longjmp: volatile. */
    unsigned short *volatile px = NULL;
    png_bytep *volatile rows = NULL;
    lumis_image *volatile img = NULL;
    volatile lumis_status st = LUMIS_ERR_CORRUPT;
    if (setjmp(png_jmpbuf(png))) goto done;

    png_set_read_fn(png, &src, png_source_read);
    /* Ancillary chunks (text, ICC profiles) are skipped or read; none may claim more than
     * this, whatever the build's default. */
    png_set_chunk_malloc_max(png, 8u << 20);
#ifdef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION
    /* Mutated chunks would almost all stop at their CRC; the fuzzer wants what follows. */
    png_set_crc_action(png, PNG_CRC_QUIET_USE, PNG_CRC_QUIET_USE);
#endif
    png_read_info(png, info);
    const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    st = lumis_image_check_size(w, h, ctx->max_pixels);
    if (st != LUMIS_OK) {
        lumis__fail(ctx->errors, st, "%s: %u x %u: %s", ctx->name, (unsigned)w, (unsigned)h,
                    lumis_status_string(st));
        goto done;
    }
    st = LUMIS_ERR_CORRUPT;
    /* Every file to 16-bit RGB in host order: palettes and low bit depths expanded, grey
     * replicated, alpha dropped (8-bit values are scaled exactly, by 257). */
    png_set_expand(png);
    png_set_expand_16(png);
    png_set_gray_to_rgb(png);
    png_set_strip_alpha(png);
#if !defined(__BYTE_ORDER__) || __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    png_set_swap(png);
#endif
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    if (png_get_channels(png, info) != 3 || png_get_bit_depth(png, info) != 16 ||
        png_get_rowbytes(png, info) != (size_t)w * 6)
        png_error(png, "unexpected pixel layout after conversion");
    px = malloc((size_t)w * (size_t)h * 6);
    rows = malloc((size_t)h * sizeof *rows);
    if (!px || !rows) {
        st = LUMIS_ERR_OUT_OF_MEMORY;
        snprintf(src.error, sizeof src.error, "%s", lumis_status_string(st));
        goto done;
    }
    for (png_uint_32 y = 0; y < h; y++) rows[y] = (png_bytep)(px + (size_t)y * w * 3);
    png_read_image(png, rows);
    png_read_end(png, NULL);

    lumis_image *made = NULL;
    st = lumis_image_create((int)w, (int)h, &made);
    if (st != LUMIS_OK) {
        snprintf(src.error, sizeof src.error, "%s", lumis_status_string(st));
        goto done;
    }
    pthread_once(&srgb_lut_once, srgb_lut_init);
    const size_t n = 3 * (size_t)w * (size_t)h;
    for (size_t k = 0; k < n; k++) made->pixels[k] = srgb_lut[px[k]];
    img = made;

done:
    png_destroy_read_struct(&png, &info, NULL);
    free(rows);
    free(px);
    if (img) {
        *out = img;
        return LUMIS_OK;
    }
    if (src.error[0])
        lumis__fail(ctx->errors, st, "%s: not a readable PNG: %s", ctx->name, src.error);
    return st;
}
