/* stb_image's PNG decoder, compiled here (from Debian's libstb-dev header) with every
 * allocation bounded. The shared libstb cannot be told a limit: its zlib inflater doubles
 * its output buffer for as long as the stream asks, so a 300-byte file that declares a
 * 16 x 8 image could make it allocate 2 GB. Here each allocation must stay below a cap
 * derived from the file's size and its declared dimensions, and a larger request fails
 * the decode instead. */
#include "png_decode.h"

#include <stdlib.h>

static _Thread_local size_t alloc_cap;
static _Thread_local int alloc_refused; /* the last decode asked for more than alloc_cap */

static void *bounded_malloc(size_t n)
{
    if (n <= alloc_cap) return malloc(n);
    alloc_refused = 1;
    return NULL;
}

static void *bounded_realloc(void *p, size_t n)
{
    if (n <= alloc_cap) return realloc(p, n);
    alloc_refused = 1;
    return NULL;
}

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_ONLY_PNG
#define STBI_NO_STDIO
#define STBI_NO_LINEAR
#define STBI_NO_HDR
#define STBI_MALLOC(n)     bounded_malloc(n)
#define STBI_REALLOC(p, n) bounded_realloc(p, n)
#define STBI_FREE(p)       free(p)
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wconversion"
#pragma GCC diagnostic ignored "-Wsign-conversion"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wdouble-promotion"
#pragma GCC diagnostic ignored "-Wcast-qual"
#pragma GCC diagnostic ignored "-Wshadow"
#endif
#include <stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
/* Reported at the end of the file: declarations of the loaders left out above. */
#pragma GCC diagnostic ignored "-Wunused-function"
#endif

int lumis__png_decode_info(const unsigned char *data, int size, int *w, int *h)
{
    int comp = 0;
    alloc_cap = (size_t)1 << 20; /* the header reader needs a few bytes only */
    alloc_refused = 0;
    int ok = stbi_info_from_memory(data, size, w, h, &comp);
    alloc_cap = 0;
    return ok;
}

unsigned short *lumis__png_decode_rgb16(const unsigned char *data, int size, int *w, int *h)
{
    int dw = 0, dh = 0;
    if (!lumis__png_decode_info(data, size, &dw, &dh) || dw <= 0 || dh <= 0) return NULL;
    /* The largest buffers a valid file needs: its IDAT data gathered (at most twice the
     * file), the inflated scanlines (8 bytes a pixel plus a filter byte a row at 16-bit
     * RGBA), and the converted output; 16 bytes a pixel covers the last two with room. */
    size_t pixels = (size_t)dw * (size_t)dh;
    alloc_cap = 2 * (size_t)size + 16 * pixels + 16 * (size_t)dh + ((size_t)1 << 16);
    alloc_refused = 0;
    int comp = 0;
    unsigned short *px = stbi_load_16_from_memory(data, size, w, h, &comp, 3);
    alloc_cap = 0;
    if (px && (*w != dw || *h != dh)) {
        free(px);
        return NULL;
    }
    return px;
}

void lumis__png_decode_free(void *pixels)
{
    free(pixels);
}

const char *lumis__png_decode_error(void)
{
    if (alloc_refused)
        return "its compressed data inflates to more than its declared size (corrupt data)";
    const char *why = stbi_failure_reason();
    return why ? why : "unknown";
}
