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

static double luma(const float *p)
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

int lumis_image_spikes(const lumis_image *img, lumis_spike *out, int max)
{
    if (!img || !img->pixels || img->width < 3 || img->height < 3) return 0; /* no 8 others */
    const int w = img->width, h = img->height;
    int found = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const float *p = img->pixels + 3 * ((size_t)y * (size_t)w + (size_t)x);
            const float hi = fmaxf(p[0], fmaxf(p[1], p[2])), lo = fminf(p[0], fminf(p[1], p[2]));
            if (!(hi > 0.0f) || !(lo < 0.02f * hi)) continue; /* not saturated: no spike */
            const double L = luma(p);
            /* the median of the 8 below L / 100 <=> at most 3 of them reach it */
            double n8[8];
            int reach = 0, k = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    if (!dx && !dy) continue;
                    const int yy = y + dy < 0 ? 0 : y + dy >= h ? h - 1 : y + dy;
                    const int xx = (x + dx + w) % w;
                    n8[k] = luma(img->pixels + 3 * ((size_t)yy * (size_t)w + (size_t)xx));
                    reach += n8[k++] * 100.0 >= L;
                }
            if (reach > 3 || !(L > 0.0)) continue;
            if (found < max && out) {
                for (int a = 1; a < 8; a++) /* insertion sort of eight */
                    for (int c = a; c > 0 && n8[c] < n8[c - 1]; c--) {
                        const double t = n8[c];
                        n8[c] = n8[c - 1];
                        n8[c - 1] = t;
                    }
                const double med = 0.5 * (n8[3] + n8[4]);
                out[found].x = x;
                out[found].y = y;
                out[found].ratio = (float)(med > L * 1e-9 ? L / med : 1e9);
            }
            found++;
        }
    return found;
}

uint64_t lumis_sanitize_floats(float *values, size_t count, lumis_replaced *replaced)
{
    lumis_replaced r = {0};
    for (size_t k = 0; k < count; k++) {
        float x = values[k];
        /* One compare catches the common case: finite and non-negative. */
        if (x >= 0.0f && x <= 3.402823466e38f) continue;
        if (isnan(x)) {
            r.nan++;
        } else if (isinf(x)) {
            r.inf++;
        } else {
            r.negative++;
            r.negative_sum += x;
            if (x < r.negative_min) r.negative_min = x, r.negative_min_at = (uint64_t)k;
        }
        values[k] = 0.0f;
    }
    if (replaced) {
        replaced->nan += r.nan;
        replaced->inf += r.inf;
        replaced->negative += r.negative;
        replaced->negative_sum += r.negative_sum;
        if (r.negative_min < replaced->negative_min) {
            replaced->negative_min = r.negative_min;
            replaced->negative_min_at = r.negative_min_at;
        }
    }
    return r.nan + r.inf + r.negative;
}
