/* lumis/rng.h - random and quasi-random numbers with explicit state.
 *
 * PCG32 (O'Neill 2014, the XSH-RR output on a 64-bit LCG) and the radical inverse
 * behind Halton sequences.  No hidden global state: results depend only on the seeds
 * the caller passes, whatever the thread count. */
#ifndef LUMIS_RNG_H
#define LUMIS_RNG_H

#include "lumis/export.h"
#include "lumis/status.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lumis_pcg32 {
    uint64_t state;
    uint64_t inc; /* always odd */
} lumis_pcg32;

/* Seeds a generator; different streams give independent sequences for the same seed. */
LUMIS_API void lumis_pcg32_seed(lumis_pcg32 *rng, uint64_t seed, uint64_t stream);

/* The 32 output bits of an LCG state (XSH-RR). */
static inline uint32_t lumis_pcg32_output(uint64_t state)
{
    uint32_t xorshifted = (uint32_t)(((state >> 18u) ^ state) >> 27u);
    uint32_t rot = (uint32_t)(state >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

/* Next 32 uniformly distributed bits. */
static inline uint32_t lumis_pcg32_next(lumis_pcg32 *rng)
{
    uint64_t old = rng->state;
    rng->state = old * 6364136223846793005ULL + rng->inc;
    return lumis_pcg32_output(old);
}

/* Uniform float in [0, 1) with 24 random bits (never returns 1). */
static inline float lumis_pcg32_float(lumis_pcg32 *rng)
{
    return (float)(lumis_pcg32_next(rng) >> 8) * 0x1p-24f;
}

/* Uniform double in [0, 1) with 53 random bits (two draws). */
static inline double lumis_pcg32_double(lumis_pcg32 *rng)
{
    uint64_t hi = lumis_pcg32_next(rng), lo = lumis_pcg32_next(rng);
    return (double)(((hi << 32) | lo) >> 11) * 0x1p-53;
}

/* out[0..n) = n successive lumis_pcg32_double(rng), the very same numbers, several times
 * faster for long runs: the LCG is stepped in interleaved chains (leapfrogging), so the
 * multiplications do not wait on one another. */
LUMIS_API void lumis_pcg32_fill_doubles(lumis_pcg32 *rng, double *out, size_t n);

/* Uniform integer in [0, bound) without modulo bias (Lemire 2019); bound > 0. */
LUMIS_API uint32_t lumis_pcg32_bounded(lumis_pcg32 *rng, uint32_t bound);

/* Moves the generator delta steps forwards (or backwards when negative) in O(log delta). */
LUMIS_API void lumis_pcg32_advance(lumis_pcg32 *rng, int64_t delta);

/* Number of prime bases available to lumis_radical_inverse / lumis_halton. */
#define LUMIS_HALTON_MAX_DIMENSION 32

/* Radical inverse of index in the prime base of the given dimension (0 -> base 2,
 * 1 -> base 3, ...), in [0, 1).  Returns 0 for dimension >= LUMIS_HALTON_MAX_DIMENSION. */
LUMIS_API double lumis_radical_inverse(unsigned dimension, uint64_t index);

/* Component `dimension` of the index-th point of the Halton sequence (same as above). */
static inline double lumis_halton(unsigned dimension, uint64_t index)
{
    return lumis_radical_inverse(dimension, index);
}

/* ---- the renderer's sample sequences (lumis-render; docs/sampling.md) ----------------------
 * Where a render's numbers come from: every number a camera sample uses (the camera's
 * jitter, light and BSDF samples, luminaire and light-set draws) is a coordinate of one of
 * these, in a fixed layout of dimensions.  All are unbiased, and give the same image
 * whatever the threads, tiles and passes. */
typedef enum lumis_sequence {
    LUMIS_SEQUENCE_DEFAULT = 0, /* the library's choice: sobol (docs/sampling.md says why) */
    LUMIS_SEQUENCE_PCG,         /* independent numbers: PCG32, a stream per pixel and camera
                                   sample (error falls as 1 / samples; the renderer's only
                                   numbers before sequences) */
    LUMIS_SEQUENCE_HALTON,      /* Halton, two prime bases per dimension, rotated per pixel
                                   and dimension (Cranley-Patterson) */
    LUMIS_SEQUENCE_STRATIFIED,  /* jittered strata of the planned sample count, in an order
                                   drawn per pixel and dimension (not progressive: more
                                   samples than planned start a new set) */
    LUMIS_SEQUENCE_SOBOL,       /* Owen-scrambled (0,2) Sobol' points, scrambled per pixel
                                   and dimension (Burley 2020): progressive */
    LUMIS_SEQUENCE_ZSOBOL,      /* the same, with pixels in z-order along one sequence per
                                   dimension (pbrt-v4's ZSobol): blue-noise error across the
                                   screen at the planned count */
    LUMIS_SEQUENCE_PMJ02,       /* progressive multi-jittered (0,2) tables (Christensen et
                                   al. 2018), xor-scrambled per pixel and dimension */
    LUMIS_SEQUENCE_COUNT
} lumis_sequence;

/* "default", "pcg", "halton", "stratified", "sobol", "zsobol", "pmj02". */
LUMIS_API const char *lumis_sequence_name(lumis_sequence sequence);
LUMIS_API lumis_status lumis_sequence_from_name(const char *name, lumis_sequence *out);
/* The sequence a render uses for q: q itself, or for LUMIS_SEQUENCE_DEFAULT the library's
 * choice (LUMIS_SEQUENCE_SOBOL). */
LUMIS_API lumis_sequence lumis_sequence_resolve(lumis_sequence q);

/* ---- (0,2) sequences: Sobol' and progressive multi-jittered points -------------------------
 * Both give, at every prefix of 2^m points, a (0,m,2)-net: each of the m + 1 grids of 2^m
 * equal rectangles (2^a x 2^(m-a) cells) holds exactly one point (docs/sampling.md). */

/* Reverses the 32 bits of v (bit 0 becomes bit 31). */
static inline uint32_t lumis_reverse_bits32(uint32_t v)
{
#if defined(__clang__)
    return __builtin_bitreverse32(v);
#else
#if defined(__GNUC__)
    v = __builtin_bswap32(v);
#else
    v = ((v >> 8) & 0x00ff00ffu) | ((v & 0x00ff00ffu) << 8);
    v = (v >> 16) | (v << 16);
#endif
    v = ((v >> 4) & 0x0f0f0f0fu) | ((v & 0x0f0f0f0fu) << 4);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    return ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
#endif
}

/* Component dimension (0 or 1) of point index of Sobol's sequence, as 32 fractional
 * bits: dimension 0 is van der Corput's (the index's bits reversed), dimension 1 the
 * generator of the polynomial x + 1 (Pascal's matrix mod 2).  Together: a (0,2)-sequence.
 * Any other dimension returns 0. */
static inline uint32_t lumis_sobol02_bits(uint32_t index, unsigned dimension)
{
    if (dimension == 0) return lumis_reverse_bits32(index);
    if (dimension != 1) return 0u;
    /* column b of Pascal's matrix: v_{b+1} = v_b ^ (v_b >> 1), v_0 = 1/2 */
    uint32_t y = 0u;
    for (uint32_t v = 1u << 31; index; index >>= 1, v ^= v >> 1)
        if (index & 1u) y ^= v;
    return y;
}

/* The permutation behind Owen scrambling, on reversed bits (Laine and Karras 2011, with
 * Burley's 2020 constants): bit i of the result is bit i of x flipped by a pseudo-random
 * function of the seed and bits 0 .. i - 1.  (Adding the seed and x ^= x * (even constant)
 * each change bit i as a function of bits 0 .. i only.) */
static inline uint32_t lumis_owen_permute_reversed(uint32_t x, uint32_t seed)
{
    x += seed;
    x ^= x * 0x6c50b47cu;
    x ^= x * 0xb82f1e52u;
    x ^= x * 0xc7afe638u;
    x ^= x * 0x8d22f6e6u;
    return x;
}

/* Owen's nested uniform scrambling of the 32-bit fraction v in base 2 (Burley 2020, the
 * hash-based form): bit i (from the top) is flipped by a pseudo-random function of the
 * seed and the bits above it.  A permutation of [0, 2^32) that maps every aligned block of
 * 2^k values onto another one (so nets stay nets), and makes each point uniform. */
static inline uint32_t lumis_owen_scramble(uint32_t v, uint32_t seed)
{
    return lumis_reverse_bits32(lumis_owen_permute_reversed(lumis_reverse_bits32(v), seed));
}

/* Point index of the Owen-scrambled (0,2) Sobol' sequence, in [0, 1)^2: dimension d
 * scrambled with its own seed drawn from seed.  Any prefix of 2^m points of one seed is a
 * (0,m,2)-net; over seeds each point is uniform (the estimate is unbiased). */
LUMIS_API void lumis_sobol02(uint32_t index, uint64_t seed, double u[2]);

/* Morton (z-order) code of (x, y): their bits interleaved, x's in the even places. */
static inline uint64_t lumis_morton2(uint32_t x, uint32_t y)
{
    uint64_t v[2] = {x, y};
    for (int k = 0; k < 2; k++) {
        uint64_t a = v[k];
        a = (a | (a << 16)) & 0x0000ffff0000ffffull;
        a = (a | (a << 8)) & 0x00ff00ff00ff00ffull;
        a = (a | (a << 4)) & 0x0f0f0f0f0f0f0f0full;
        a = (a | (a << 2)) & 0x3333333333333333ull;
        a = (a | (a << 1)) & 0x5555555555555555ull;
        v[k] = a;
    }
    return v[0] | (v[1] << 1);
}

/* A progressive multi-jittered (0,2) sequence (Christensen, Kensler and Kilpatrick 2018):
 * n points (n a power of two, 1 to 2^20) written to xy as 32-bit fractions (x, y pairs),
 * each prefix of 2^m points a (0,m,2)-net that is also jittered in the 2^m strata of each
 * axis.  Built by doubling: each new point goes to the sub-quadrant of its cell the rule
 * of the paper leaves free, at a position drawn uniformly among those that keep every
 * elementary interval filled once.  Deterministic in seed; O(n^1.5) time, O(n log n)
 * scratch.  Returns LUMIS_ERR_INVALID_ARGUMENT for a bad n or a NULL xy, and
 * LUMIS_ERR_OUT_OF_MEMORY. */
LUMIS_API lumis_status lumis_pmj02_generate(uint32_t n, uint64_t seed, uint32_t *xy);

#ifdef __cplusplus
}
#endif
#endif
