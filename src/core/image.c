#include "lumis/image.h"
#include "lumis/version.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *lumis_version(void)
{
    return LUMIS_VERSION_STRING;
}

lumis_status lumis_image_check_size(int64_t width, int64_t height, uint64_t max_pixels)
{
    if (max_pixels == 0) max_pixels = LUMIS_DEFAULT_MAX_PIXELS;
    if (width <= 0 || height <= 0) return LUMIS_ERR_BAD_DIMENSIONS;
    /* Keep every size an int and every byte count a size_t, whatever the limit says. */
    if (width > INT32_MAX || height > INT32_MAX) return LUMIS_ERR_TOO_LARGE;
    uint64_t w = (uint64_t)width, h = (uint64_t)height;
    if (w > max_pixels / h) return LUMIS_ERR_TOO_LARGE;
    if (w * h > (uint64_t)SIZE_MAX / (3 * sizeof(float))) return LUMIS_ERR_TOO_LARGE;
    return LUMIS_OK;
}

lumis_status lumis_image_create(int width, int height, lumis_image **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    lumis_status st = lumis_image_check_size(width, height, 0);
    if (st != LUMIS_OK) return st;
    lumis_image *img = malloc(sizeof *img);
    if (!img) return LUMIS_ERR_OUT_OF_MEMORY;
    img->width = width;
    img->height = height;
    img->pixels = calloc((size_t)width * (size_t)height * 3, sizeof(float));
    if (!img->pixels) {
        free(img);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    *out = img;
    return LUMIS_OK;
}

lumis_status lumis_image_clone(const lumis_image *src, lumis_image **out)
{
    if (!src || !out) return LUMIS_ERR_INVALID_ARGUMENT;
    lumis_status st = lumis_image_create(src->width, src->height, out);
    if (st != LUMIS_OK) return st;
    memcpy((*out)->pixels, src->pixels,
           (size_t)src->width * (size_t)src->height * 3 * sizeof(float));
    return LUMIS_OK;
}

void lumis_image_destroy(lumis_image *image)
{
    if (!image) return;
    free(image->pixels);
    free(image);
}

uint64_t lumis_sanitize_floats(float *values, size_t count, lumis_replaced *replaced)
{
    lumis_replaced r = {0, 0, 0};
    for (size_t k = 0; k < count; k++) {
        float x = values[k];
        /* One compare catches the common case: finite and non-negative. */
        if (x >= 0.0f && x <= 3.402823466e38f) continue;
        if (isnan(x))
            r.nan++;
        else if (isinf(x))
            r.inf++;
        else
            r.negative++;
        values[k] = 0.0f;
    }
    if (replaced) {
        replaced->nan += r.nan;
        replaced->inf += r.inf;
        replaced->negative += r.negative;
    }
    return r.nan + r.inf + r.negative;
}
