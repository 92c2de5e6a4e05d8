/* lumis/envmap.h - the equirectangular environment-map model.
 *
 * Coordinates (docs/coordinates.md derives and pins them): right-handed, y up.  A map
 * coordinate (u, v) in [0,1)^2 has azimuth phi = 2 pi u and polar angle theta = pi v from
 * +y, and the direction
 *     d = (sin theta cos phi, cos theta, sin theta sin phi).
 * Pixel (i, j) of a w x h map covers u in [i/w, (i+1)/w), v in [j/h, (j+1)/h); row 0 is
 * the zenith.  It subtends (2 pi / w)(cos theta_j - cos theta_{j+1}) steradians with
 * theta_j = pi j / h.  Radiance is piecewise constant per pixel: eval() returns the value
 * of the pixel the direction falls in, which is exactly the function the samplers are
 * built for.
 *
 * A lumis_envmap owns a sanitized copy of the pixels (NaN, Inf and negative values become
 * 0; the counts are kept), a rotation about +y and a scale applied to every radiance. */
#ifndef LUMIS_ENVMAP_H
#define LUMIS_ENVMAP_H

#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/status.h"
#include "lumis/types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lumis_envmap lumis_envmap;

typedef struct lumis_envmap_desc {
    const float *pixels; /* width * height RGB floats, row 0 = zenith; borrowed for the call */
    int width, height;   /* each >= 1 */
    float rotation_deg;  /* rotation of the map about +y; 0 == none */
    float scale;         /* radiance multiplier; 0 == default 1 */
    uint64_t max_pixels; /* 0 == LUMIS_DEFAULT_MAX_PIXELS */
    lumis_error_sink errors;
} lumis_envmap_desc;

/* Builds an environment map from a pixel buffer (copied). */
LUMIS_API lumis_status lumis_envmap_create(const lumis_envmap_desc *desc, lumis_envmap **out);

/* Convenience: builds from a lumis_image with no rotation and unit scale. */
LUMIS_API lumis_status lumis_envmap_from_image(const lumis_image *image, lumis_envmap **out);

/* Releases the caller's reference; the map is freed when no sampler built from it is
 * alive any more (samplers keep a reference).  NULL is accepted. */
LUMIS_API void lumis_envmap_destroy(lumis_envmap *env);

LUMIS_API int lumis_envmap_width(const lumis_envmap *env);
LUMIS_API int lumis_envmap_height(const lumis_envmap *env);
LUMIS_API float lumis_envmap_scale(const lumis_envmap *env);
LUMIS_API float lumis_envmap_rotation_deg(const lumis_envmap *env);

/* The sanitized pixels, unscaled (width * height * 3 floats, valid while env lives). */
LUMIS_API const float *lumis_envmap_pixels(const lumis_envmap *env);

/* Channel values replaced by 0 when the map was built. */
LUMIS_API lumis_replaced lumis_envmap_replaced(const lumis_envmap *env);

/* Radiance of pixel (i, j), scale applied.  Indices are clamped into the map. */
LUMIS_API lumis_rgb lumis_envmap_texel(const lumis_envmap *env, int i, int j);

/* Radiance arriving from world direction dir (need not be normalized; the zero vector
 * returns black).  Cost: one lookup. */
LUMIS_API lumis_rgb lumis_envmap_eval(const lumis_envmap *env, lumis_vec3 dir);

/* World direction -> continuous map coordinate (u, v) in [0,1)^2, rotation applied. */
LUMIS_API void lumis_envmap_dir_to_uv(const lumis_envmap *env, lumis_vec3 dir, float *u, float *v);

/* Map coordinate (u, v) -> unit world direction, rotation applied. */
LUMIS_API lumis_vec3 lumis_envmap_uv_to_dir(const lumis_envmap *env, float u, float v);

/* Pixel containing world direction dir. */
LUMIS_API void lumis_envmap_dir_to_pixel(const lumis_envmap *env, lumis_vec3 dir, int *i, int *j);

/* Solid angle of any pixel in row j, in steradians. */
LUMIS_API double lumis_envmap_pixel_solid_angle(const lumis_envmap *env, int j);

/* Statistics of a map, with the definitions of ../shared/data/README.md. */
typedef struct lumis_envmap_stats {
    int width, height;
    double min_luminance, max_luminance; /* over pixels */
    double min_positive_luminance;       /* smallest Y > 0; 0 if the map is black */
    double avg_luminance;                /* sum(Y * Omega) / (4 pi) */
    double dynamic_range;                /* max / min_positive; 0 if the map is black */
    double power;                        /* sum(Y * Omega), steradian-weighted luminance */
    double power_rgb[3];                 /* sum(L * Omega) per channel */
    double top1_share;     /* share of power in the floor(n/100) (>= 1) pixels of largest Y*Omega */
    double top01_share;    /* same for floor(n/1000) (>= 1) pixels */
    uint64_t black_pixels; /* pixels with Y == 0 */
} lumis_envmap_stats;

/* Computes the statistics (scale applied) in O(n) time and O(n) temporary memory. */
LUMIS_API lumis_status lumis_envmap_stats_compute(const lumis_envmap *env, lumis_envmap_stats *out);

/* The same statistics straight from an equirectangular pixel buffer (width * height RGB
 * floats, row 0 the zenith) times scale, without building an envmap.  The pixels must
 * already be finite and non-negative (as lumis-io's readers return them). */
LUMIS_API lumis_status lumis_equirect_stats(const float *pixels, int width, int height, float scale,
                                            lumis_envmap_stats *out);

/* Total power per channel, sum(L * Omega) over pixels, scale applied. */
LUMIS_API lumis_rgb lumis_envmap_power(const lumis_envmap *env);

/* ---- Coordinate helpers for a map without rotation ---------------------------------- */

/* (u, v) -> unit direction; see the formula at the top of this header. */
LUMIS_API lumis_vec3 lumis_equirect_to_dir(float u, float v);

/* Direction (need not be normalized, not zero) -> (u, v) in [0,1)^2. */
LUMIS_API void lumis_equirect_from_dir(lumis_vec3 dir, float *u, float *v);

/* Solid angle of a pixel in row j of a w x h equirectangular map. */
LUMIS_API double lumis_equirect_solid_angle(int width, int height, int j);

/* Resamples an equirectangular RGB map to new_w x new_h so that every output pixel holds
 * the solid-angle-weighted mean of the input over its area: total power (sum L * Omega)
 * is preserved exactly, in either direction.  dst holds new_w * new_h * 3 floats. */
LUMIS_API lumis_status lumis_equirect_resize(const float *src, int width, int height, float *dst,
                                             int new_w, int new_h);

#ifdef __cplusplus
}
#endif
#endif
