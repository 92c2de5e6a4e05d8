/* A random light-field luminaire for the luminaire tests (tests/stat/test_luminaire.c,
 * tests/stat/test_render_luminaire.c); fixed seeds. */
#ifndef LUMIS_TESTS_LUM_FIXTURE_H
#define LUMIS_TESTS_LUM_FIXTURE_H

#include "../testutil.h"

#include "lumis/luminaire.h"
#include "lumis/rng.h"

#include <stdlib.h>
#include <string.h>

/* ---- a random luminaire ---------------------------------------------------------------- */

typedef struct fixture {
    lumis_luminaire *lum;
    float *pixels;
    const float *ptr[64];
} fixture;

/* 3 x 3 functions on a 0.5 grid centred on the axis, S at delta = 1, images width x height
 * (make_fixture: 16 x 12, square pixels) over [-2, 2] x [-1.5, 1.5]; pixel values random
 * with 30% zeros and some colour. */
static inline fixture make_fixture_sized(lumis_luminaire_basis basis, uint64_t seed, int width,
                                         int height)
{
    fixture f;
    memset(&f, 0, sizeof f);
    lumis_luminaire_desc d = {0};
    d.delta = 1.0;
    d.basis = basis;
    d.grid[0] = d.grid[1] = 3;
    d.grid_origin[0] = d.grid_origin[1] = -0.5;
    d.grid_spacing[0] = d.grid_spacing[1] = 0.5;
    d.width = width;
    d.height = height;
    d.image_origin[0] = -2.0;
    d.image_origin[1] = -1.5;
    d.image_size[0] = 4.0;
    d.image_size[1] = 3.0;
    const size_t n = (size_t)d.width * d.height * 3;
    f.pixels = malloc(9 * n * sizeof(float));
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, seed, 1);
    for (int m = 0; m < 9; m++) {
        for (size_t k = 0; k < n; k += 3) {
            float v = lumis_pcg32_float(&rng) < 0.3f ? 0.0f : 0.1f + 4.0f * lumis_pcg32_float(&rng);
            float tint = lumis_pcg32_float(&rng);
            f.pixels[m * n + k] = v * (0.5f + tint);
            f.pixels[m * n + k + 1] = v;
            f.pixels[m * n + k + 2] = v * (1.5f - tint);
        }
        f.ptr[m] = f.pixels + m * n;
    }
    d.pixels = f.ptr;
    assert_int_equal(lumis_luminaire_create(&d, &f.lum), LUMIS_OK);
    return f;
}

static inline fixture make_fixture(lumis_luminaire_basis basis, uint64_t seed)
{
    return make_fixture_sized(basis, seed, 16, 12);
}

static inline void free_fixture(fixture *f)
{
    lumis_luminaire_destroy(f->lum);
    free(f->pixels);
}

#endif
