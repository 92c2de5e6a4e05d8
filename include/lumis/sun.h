/* lumis/sun.h - the image sun: a compact, very bright source found in an environment map
 * (a sun disk and its aureole, a studio's small lamp), fitted as a cone and split off the
 * map exactly.
 *
 * The sun is a set S of whole pixels: every pixel whose centre lies within `radius` of
 * `dir` (angles between unit vectors in double precision, the pixel centre as
 * lumis_envmap_uv_to_dir gives it).  The sun's radiance in a direction is the map's
 * radiance there when the direction's pixel is in S, else zero (lumis_sun_eval); the
 * residual map is the map with S's pixels set to zero.  So sun + residual == map in every
 * direction, bit for bit, and a render that samples the sun as a cone and the residual by
 * any sampler is unbiased against the unsplit map.  The cone sampled, of half-angle
 * `sample_radius`, holds every point of every pixel of S (its pdf is positive wherever the
 * sun's radiance is).  Derivations and the detection rule: docs/lights.md, "The image sun". */
#ifndef LUMIS_SUN_H
#define LUMIS_SUN_H

#include "lumis/envmap.h"
#include "lumis/export.h"
#include "lumis/status.h"
#include "lumis/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* How the sun is looked for (zero-initialisable). */
typedef struct lumis_sun_desc {
    double max_radius_deg; /* the largest sun disk, degrees, in (0, 20]; 0 == 5 */
    double min_share;      /* the least share of the map's luminance power a sun holds, in
                              (0, 1]; 0 == 0.1 */
    double threshold;      /* the luminance cut relative to the brightest pixel, in (0, 1);
                              0 == automatic: the lowest of 1e-4, 2e-4, 5e-4, 0.001 ... 0.5 whose
                              region stays within max_radius_deg */
    lumis_error_sink errors;
} lumis_sun_desc;

/* A sun found in a map: what lumis_sun_find fits.  All angles in radians. */
typedef struct lumis_sun {
    int found;            /* 1: a sun; 0: none (the fields below are then zero; share, pixels
                             and threshold describe the best candidate, if any) */
    lumis_vec3 dir;       /* unit world direction: luminance-power-weighted mean of the
                             candidate region's pixel centres */
    double radius;        /* the disk: pixels with centres within radius of dir are the sun */
    double sample_radius; /* the cone sampled: holds every point of the sun's pixels */
    lumis_rgb radiance;   /* mean radiance of the sun's pixels: power / solid_angle */
    double power[3];      /* sum of L * Omega over the sun's pixels, per channel, scale applied */
    double solid_angle;   /* steradians of the sun's pixels */
    double share;         /* the sun's share of the map's luminance power, sum(Y * Omega) */
    double threshold;     /* the luminance cut the region was grown with, relative to the peak */
    int pixels;           /* the sun's pixels */
} lumis_sun;

/* Looks for a sun in env.  The region is grown (8-neighbours, across the seam and the
 * poles) from the brightest pixel over the pixels of luminance >= threshold x the
 * brightest; at the automatic threshold the lowest cut whose region keeps every pixel
 * centre within max_radius_deg of the brightest pixel is taken.  Its direction is the
 * luminance-power-weighted mean of its pixel centres, its radius the largest angle from
 * there to one of them; every pixel with its centre inside is the sun's.  No sun
 * (found == 0, LUMIS_OK) when the map is black, no cut keeps the region compact, the disk
 * exceeds max_radius_deg or the sampled cone twice that (a map too coarse for the sun), or
 * the sun holds less than min_share of the power.  residual (may be NULL): with a sun, a
 * new map (same size, rotation and scale) with the sun's pixels zeroed, which the caller
 * destroys; without one, NULL.  O(width x height) time and memory.
 * LUMIS_ERR_INVALID_ARGUMENT: NULL env or out, a field of desc out of range. */
LUMIS_API lumis_status lumis_sun_find(const lumis_envmap *env, const lumis_sun_desc *desc,
                                      lumis_sun *out, lumis_envmap **residual);

/* The sun's radiance towards world direction dir (need not be normalised): env's radiance
 * there if dir's pixel is one of the sun's, else black.  env must be the map the sun was
 * found in (its rotation decides the pixels).  Cost: a dot product, and near the sun one
 * pixel lookup and two angles. */
LUMIS_API lumis_rgb lumis_sun_eval(const lumis_sun *sun, const lumis_envmap *env, lumis_vec3 dir);

/* Nonzero if pixel (i, j) of env is one of the sun's (its centre within radius of dir). */
LUMIS_API int lumis_sun_contains(const lumis_sun *sun, const lumis_envmap *env, int i, int j);

/* A direction uniform in solid angle in the cone of half-angle sample_radius about dir,
 * from two uniform numbers in [0, 1): cos theta = 1 - u1 (1 - cos r), phi = 2 pi u2 about
 * dir.  *pdf (may be NULL) = 1 / (2 pi (1 - cos r)) per steradian.  No sun: dir and pdf 0.
 * Cost: a sqrt, a sin and a cos. */
LUMIS_API lumis_vec3 lumis_sun_sample(const lumis_sun *sun, double u1, double u2, double *pdf);

/* Density per steradian of lumis_sun_sample drawing dir (need not be normalised):
 * 1 / (2 pi (1 - cos r)) inside the cone, 0 outside or without a sun. */
LUMIS_API double lumis_sun_pdf(const lumis_sun *sun, lumis_vec3 dir);

/* The (u1, u2) that lumis_sun_sample maps to dir, in u[0], u[1].  LUMIS_ERR_INVALID_ARGUMENT:
 * NULL arguments, no sun, a zero or non-finite dir, or dir outside the cone. */
LUMIS_API lumis_status lumis_sun_invert(const lumis_sun *sun, lumis_vec3 dir, double u[2]);

/* ---- the sun's pixels by their power ------------------------------------------------------
 *
 * A uniform cone wastes nothing only when the sun is uniform; a real sun's pixels span orders
 * of magnitude (its core, its aureole), and a uniform draw over them is noisy.  The sun
 * sampler draws the sun's pixels in proportion to their luminance power Y Omega, and a
 * direction uniform in solid angle inside the pixel drawn:
 *     p(w) = Y_q / sum over S of Y Omega   per steradian on pixel q of the sun, 0 elsewhere,
 * so the sun's radiance over its pdf varies with its pixels' colour only.  What a renderer
 * lighting with a sun uses (lighting.sun.sampler). */
typedef struct lumis_sun_sampler lumis_sun_sampler;

/* Lists the sun's pixels of env with positive luminance and their cumulative powers.  env is
 * borrowed: it must outlive the sampler.  LUMIS_ERR_INVALID_ARGUMENT: NULL arguments or a sun
 * not found; LUMIS_ERR_OUT_OF_MEMORY.  O(pixels of the rows near the sun). */
LUMIS_API lumis_status lumis_sun_sampler_create(const lumis_envmap *env, const lumis_sun *sun,
                                                const lumis_error_sink *errors,
                                                lumis_sun_sampler **out);

/* NULL is accepted. */
LUMIS_API void lumis_sun_sampler_destroy(lumis_sun_sampler *sampler);

/* A direction from two uniform numbers in [0, 1): u1 chooses the pixel (binary search over
 * the cumulative powers) and, rescaled, the azimuth inside it; u2 the cosine of the polar
 * angle inside it.  *pdf (per steradian) and *radiance (env's radiance there; either may be
 * NULL).  Cost: a binary search over the sun's pixels, an acos, a sin and a cos. */
LUMIS_API lumis_vec3 lumis_sun_sampler_sample(const lumis_sun_sampler *sampler, double u1,
                                              double u2, double *pdf, lumis_rgb *radiance);

/* Density per steradian of drawing dir (need not be normalised), and the sun's radiance there
 * (radiance may be NULL): 0 and black off the sun's pixels.  Cost: a pixel lookup and a
 * binary search. */
LUMIS_API double lumis_sun_sampler_pdf(const lumis_sun_sampler *sampler, lumis_vec3 dir,
                                       lumis_rgb *radiance);

#ifdef __cplusplus
}
#endif
#endif
