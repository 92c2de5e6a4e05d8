/* lumis/image.h - float RGB image buffers and their validation.
 *
 * A lumis_image is a plain struct: width x height pixels of 3 floats (linear RGB),
 * interleaved, row-major, row 0 at the top.  lumis_image_create allocates it,
 * lumis_image_destroy frees the struct and its pixels. */
#ifndef LUMIS_IMAGE_H
#define LUMIS_IMAGE_H

#include "lumis/export.h"
#include "lumis/status.h"
#include "lumis/types.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Default largest accepted image, in pixels (2^28: 16384 x 16384; 3 GiB as float RGB). */
#define LUMIS_DEFAULT_MAX_PIXELS ((uint64_t)1 << 28)

typedef struct lumis_image {
    int width, height;
    float *pixels; /* width * height * 3 floats, owned by the image */
} lumis_image;

/* Counts of channel values replaced by 0 because they were NaN, infinite or negative, and
 * the most negative of them: compression leaves tiny negatives in most real HDRIs, while a
 * large one marks a broken cluster of pixels (zero-initialise it). */
typedef struct lumis_replaced {
    uint64_t nan, inf, negative;
    float negative_min;       /* the most negative value replaced (0: none) */
    double negative_sum;      /* the sum of the negative values replaced (<= 0) */
    uint64_t negative_min_at; /* its index among the values of the call that met it */
} lumis_replaced;

/* Checks width and height (each >= 1) against max_pixels (0 == LUMIS_DEFAULT_MAX_PIXELS)
 * without overflowing, before anything is allocated.  Returns LUMIS_ERR_BAD_DIMENSIONS for
 * non-positive sizes and LUMIS_ERR_TOO_LARGE beyond the limit. */
LUMIS_API lumis_status lumis_image_check_size(int64_t width, int64_t height, uint64_t max_pixels);

/* Allocates a zero-filled image.  Sizes are checked with the default pixel limit. */
LUMIS_API lumis_status lumis_image_create(int width, int height, lumis_image **out);

/* Copies an image (pixels included). */
LUMIS_API lumis_status lumis_image_clone(const lumis_image *src, lumis_image **out);

/* Frees the image and its pixels; NULL is accepted. */
LUMIS_API void lumis_image_destroy(lumis_image *image);

/* Replaces every NaN, infinite or negative value among count floats by 0 and adds what it
 * replaced to *replaced (which may be NULL), keeping its most negative value and where it
 * was.  Returns the number of values replaced. */
LUMIS_API uint64_t lumis_sanitize_floats(float *values, size_t count, lumis_replaced *replaced);

/* Total of a lumis_replaced. */
static inline uint64_t lumis_replaced_total(lumis_replaced r)
{
    return r.nan + r.inf + r.negative;
}

/* A pixel no camera makes: far brighter than its neighbours and of a saturated colour (a
 * pure-blue "sun"), as a broken compression block leaves; a real sun is near white. */
typedef struct lumis_spike {
    int x, y;    /* the pixel (row 0 at the top) */
    float ratio; /* its luminance over the median of its 8 neighbours' (capped at 1e9) */
} lumis_spike;

/* Finds the spikes of an equirectangular RGB image: pixels whose smallest channel is under
 * 2 % of their largest, and whose luminance is more than 100 times the median of their 8
 * neighbours' (columns wrap, rows clamp).  Writes up to max of them to out (which may be
 * NULL with max 0) in scan order and returns how many there are.  Cost: one pass, the
 * neighbours only of saturated pixels. */
LUMIS_API int lumis_image_spikes(const lumis_image *img, lumis_spike *out, int max);

#ifdef __cplusplus
}
#endif
#endif
