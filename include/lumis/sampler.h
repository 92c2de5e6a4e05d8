/* lumis/sampler.h - importance sampling of an environment map.
 *
 * One interface, several methods.  A lumis_sampler is built from a lumis_envmap and a
 * zero-initialisable descriptor; it draws directions with a density per steradian and
 * evaluates that density for any direction.  Every method is exact for the envmap's
 * piecewise-constant radiance: pdf(sample(u).dir) == sample(u).pdf, the pdf integrates to
 * one over the sphere, and within a pixel (or block) directions are uniform in solid
 * angle.  Derivations of every pdf and Jacobian: docs/samplers.md.
 *
 * Random numbers: sample() takes two uniform doubles in [0, 1) (others are clamped in).
 * Give them full 53-bit precision (lumis_pcg32_double): the alias method spends up to
 * log2(pixels) bits on the index and 32 on its accept test.  Results depend only on these
 * inputs.
 *
 * Threads: a built sampler is immutable; any number of threads may sample from it.
 * The sampler keeps a reference to its envmap (see lumis_envmap_destroy). */
#ifndef LUMIS_SAMPLER_H
#define LUMIS_SAMPLER_H

#include "lumis/envmap.h"
#include "lumis/export.h"
#include "lumis/status.h"
#include "lumis/types.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lumis_sampler_method {
    LUMIS_METHOD_DEFAULT = 0,      /* == LUMIS_METHOD_INVERSION_GUIDED */
    LUMIS_METHOD_INVERSION,        /* marginal + conditional CDFs, binary search */
    LUMIS_METHOD_INVERSION_GUIDED, /* the same CDFs, searches started from a guide table */
    LUMIS_METHOD_ALIAS,            /* Walker/Vose alias table over pixels, O(1) */
    LUMIS_METHOD_KDTREE,           /* Ergun, Kurt and Ozturk: SSE kd-tree, fitted pdf, O(1) */
    LUMIS_METHOD_KDTREE_EXACT,     /* the same blocks, chosen with their true probabilities */
    LUMIS_METHOD_HIERARCHICAL,     /* warping down a mip pyramid, O(log n) */
    LUMIS_METHOD_UNIFORM,          /* uniform over the sphere */
    LUMIS_METHOD_COUNT
} lumis_sampler_method;

/* "inversion", "inversion-guided", "alias", "kdtree", "kdtree-exact", "hierarchical",
 * "uniform" ("default" for LUMIS_METHOD_DEFAULT). */
LUMIS_API const char *lumis_sampler_method_name(lumis_sampler_method method);
LUMIS_API lumis_status lumis_sampler_method_from_name(const char *name, lumis_sampler_method *out);

/* What a pixel's probability is proportional to (before MIS compensation). */
typedef enum lumis_importance {
    LUMIS_IMPORTANCE_DEFAULT = 0, /* == LUMIS_IMPORTANCE_LUMINANCE */
    LUMIS_IMPORTANCE_LUMINANCE,   /* Y times the pixel's solid angle */
    LUMIS_IMPORTANCE_AVERAGE,     /* (R + G + B) / 3 times the solid angle */
    LUMIS_IMPORTANCE_MAX_CHANNEL, /* max(R, G, B) times the solid angle */
    LUMIS_IMPORTANCE_COUNT
} lumis_importance;

typedef struct lumis_sampler_desc {
    lumis_sampler_method method; /* 0 == default (inversion-guided) */
    lumis_importance importance; /* 0 == luminance x solid angle */
    int compensate;              /* nonzero: MIS compensation (Karlik et al. 2019): sample
                                    max(v - mean v, 0); falls back to v where that is 0 */
    int kdtree_blocks;           /* kd-tree leaves; 0 == 6144 (the paper's setting) */
    int kdtree_uniform_angles;   /* nonzero: the paper's literal variant, uniform in
                                    elevation and azimuth inside a block */
    lumis_error_sink errors;     /* errors, and warnings (reported with status LUMIS_OK) */
} lumis_sampler_desc;

typedef struct lumis_sampler lumis_sampler;

/* One drawn direction. */
typedef struct lumis_env_sample {
    lumis_vec3 dir;     /* unit world direction */
    float pdf;          /* density per steradian (> 0) */
    lumis_rgb radiance; /* the envmap's radiance there (eval(dir)) */
} lumis_env_sample;

/* Builds the method's tables.  A map with zero importance everywhere is not an error: the
 * sampler then samples uniformly, warns once through desc->errors and reports it in
 * lumis_sampler_is_uniform_fallback().  Retains env until lumis_sampler_destroy. */
LUMIS_API lumis_status lumis_sampler_create(const lumis_envmap *env, const lumis_sampler_desc *desc,
                                            lumis_sampler **out);

LUMIS_API void lumis_sampler_destroy(lumis_sampler *sampler);

/* Draws a direction from two uniform numbers in [0, 1).  Cost: see each method's file;
 * no allocation, no locks. */
LUMIS_API lumis_env_sample lumis_sampler_sample(const lumis_sampler *sampler, double u1, double u2);

/* Draws n directions from the 2n uniform numbers u[0..2n) (pairs). */
LUMIS_API void lumis_sampler_sample_n(const lumis_sampler *sampler, const double *u, size_t n,
                                      lumis_env_sample *out);

/* Density per steradian of drawing world direction dir (need not be normalized). */
LUMIS_API float lumis_sampler_pdf(const lumis_sampler *sampler, lumis_vec3 dir);

/* The same density and, from the same pixel lookup, the map's radiance in that direction
 * (lumis_envmap_eval): what an MIS weight for a BSDF sample needs, for one direction to
 * pixel conversion instead of two. */
LUMIS_API float lumis_sampler_pdf_radiance(const lumis_sampler *sampler, lumis_vec3 dir,
                                           lumis_rgb *radiance);

/* The inverse of sample(): the (u1, u2) in [0, 1)^2 that sample() maps to world direction
 * dir (need not be normalized), in u[0] and u[1].  Defined for the continuous, one-to-one
 * warps: inversion, inversion-guided, hierarchical and uniform (and the uniform fallback);
 * alias and the kd-tree methods shuffle [0, 1)^2 (a column's two outcomes share it, blocks
 * are reordered), so they have no inverse and return LUMIS_ERR_UNSUPPORTED.  Zero vector,
 * non-finite dir or NULL arguments: LUMIS_ERR_INVALID_ARGUMENT.
 * Round trips: sample(invert(dir)).dir == dir to float rounding, and invert(sample(u).dir)
 * == u to float rounding of the direction, when dir's pixel has probability > 0.  A pixel
 * of probability 0 (pdf(dir) == 0) is never drawn: invert returns the point of [0, 1)^2
 * where its empty share would be (the CDF, or split, at its edge), which sample() maps into
 * a neighbouring pixel that has light; within a row without light u1 is the azimuth in
 * turns.  Cost: one pixel lookup (an atan2) plus, for hierarchical, one split per level.
 * Derivation: docs/samplers.md. */
LUMIS_API lumis_status lumis_sampler_invert(const lumis_sampler *sampler, lumis_vec3 dir,
                                            double u[2]);

/* pdf() of the n directions dirs[0..n) into pdf[0..n) and, when radiance is not NULL, the
 * map's radiance there into radiance[0..n) (lumis_sampler_pdf_radiance): the very numbers
 * of n single calls, for a host that evaluates whole arrays in one call (the Python
 * package). */
LUMIS_API void lumis_sampler_pdf_n(const lumis_sampler *sampler, const lumis_vec3 *dirs, size_t n,
                                   float *pdf, lumis_rgb *radiance);

/* invert() of the n directions dirs[0..n) into u[0..2n) (pairs), as n single calls.  Stops
 * at the first direction invert() refuses and returns its status, with its index in *failed
 * (which may be NULL); LUMIS_OK and *failed == n when every direction went through. */
LUMIS_API lumis_status lumis_sampler_invert_n(const lumis_sampler *sampler, const lumis_vec3 *dirs,
                                              size_t n, double *u, size_t *failed);

/* The envmap the sampler draws from (it holds a reference to it). */
LUMIS_API const lumis_envmap *lumis_sampler_envmap(const lumis_sampler *sampler);

/* Bytes of the sampling tables (what sample() reads), and all bytes the sampler owns
 * (pdf() lookup structures included). */
LUMIS_API size_t lumis_sampler_table_bytes(const lumis_sampler *sampler);
LUMIS_API size_t lumis_sampler_total_bytes(const lumis_sampler *sampler);

/* Wall-clock time the build took, in milliseconds. */
LUMIS_API double lumis_sampler_build_ms(const lumis_sampler *sampler);

LUMIS_API lumis_sampler_method lumis_sampler_get_method(const lumis_sampler *sampler);

/* Nonzero if the map had no importance anywhere and the sampler samples uniformly. */
LUMIS_API int lumis_sampler_is_uniform_fallback(const lumis_sampler *sampler);

/* The kd-tree's fitted alpha (Eq. 4 of Ergun et al.) and its number of blocks; 0 for
 * other methods. */
LUMIS_API double lumis_sampler_kdtree_alpha(const lumis_sampler *sampler);
LUMIS_API int lumis_sampler_kdtree_blocks(const lumis_sampler *sampler);

#ifdef __cplusplus
}
#endif
#endif
