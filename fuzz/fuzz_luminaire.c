/* libFuzzer target: the luminaire manifest parser (lumis_luminaire_manifest_parse) on
 * arbitrary bytes.  It opens no file, so this covers the JSON walk, every field check, the
 * pixel limit and the image-name rules.  The contract: a manifest exactly when the status is
 * LUMIS_OK; then its geometry is one lumis_luminaire_create accepts (checked by building it
 * from black images when it is small), M names that are relative without "..", and paths
 * under the base folder; never a crash, a sanitizer report or a leak. */
#include "lumis/io.h"
#include "lumis/luminaire.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#define FUZZ_MAX_PIXELS ((size_t)1 << 22)
#define BUILD_PIXELS    4096 /* total pixels up to which the luminaire is built */

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static float black[BUILD_PIXELS * 3];

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    lumis_luminaire_read_options ro = {0};
    ro.max_pixels = FUZZ_MAX_PIXELS;
    lumis_luminaire_manifest *m = NULL;
    lumis_status st =
        lumis_luminaire_manifest_parse((const char *)data, size, "fuzz.json", "/base", &ro, &m);
    if ((st == LUMIS_OK) != (m != NULL)) __builtin_trap();
    if (!m) return 0;
    const lumis_luminaire_desc *d = &m->desc;
    if (m->version != LUMIS_LUMINAIRE_FORMAT_VERSION || !m->units[0]) __builtin_trap();
    if (d->grid[0] < 1 || d->grid[1] < 1 || m->image_count != d->grid[0] * d->grid[1])
        __builtin_trap();
    if (!(d->delta > 0.0) || !isfinite(d->delta) || d->pixels) __builtin_trap();
    if ((size_t)m->image_count * (size_t)d->width * (size_t)d->height > FUZZ_MAX_PIXELS)
        __builtin_trap();
    for (int k = 0; k < m->image_count; k++) {
        const char *name = m->images[k], *path = m->paths[k];
        if (!name || !path || !name[0] || name[0] == '/' || strncmp(path, "/base/", 6) != 0 ||
            strcmp(path + 6, name) != 0)
            __builtin_trap();
        for (const char *c = name; *c; c++)
            if (c[0] == '.' && c[1] == '.' && (c == name || c[-1] == '/') &&
                (c[2] == '/' || c[2] == '\0'))
                __builtin_trap();
    }
    /* What the parser accepts, the core accepts. */
    if ((size_t)m->image_count * (size_t)d->width * (size_t)d->height <= BUILD_PIXELS) {
        const float *ptrs[1024];
        for (int k = 0; k < m->image_count; k++) ptrs[k] = black;
        lumis_luminaire_desc c = *d;
        c.pixels = ptrs;
        lumis_luminaire *lum = NULL;
        if (lumis_luminaire_create(&c, &lum) != LUMIS_OK) __builtin_trap();
        lumis_luminaire_destroy(lum);
    }
    lumis_luminaire_manifest_destroy(m);
    return 0;
}
