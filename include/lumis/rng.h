/* lumis/rng.h - random and quasi-random numbers with explicit state.
 *
 * PCG32 (O'Neill 2014, the XSH-RR output on a 64-bit LCG) and the radical inverse
 * behind Halton sequences.  No hidden global state: results depend only on the seeds
 * the caller passes, whatever the thread count. */
#ifndef LUMIS_RNG_H
#define LUMIS_RNG_H

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
void lumis_pcg32_seed(lumis_pcg32 *rng, uint64_t seed, uint64_t stream);

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
void lumis_pcg32_fill_doubles(lumis_pcg32 *rng, double *out, size_t n);

/* Uniform integer in [0, bound) without modulo bias (Lemire 2019); bound > 0. */
uint32_t lumis_pcg32_bounded(lumis_pcg32 *rng, uint32_t bound);

/* Moves the generator delta steps forwards (or backwards when negative) in O(log delta). */
void lumis_pcg32_advance(lumis_pcg32 *rng, int64_t delta);

/* Number of prime bases available to lumis_radical_inverse / lumis_halton. */
#define LUMIS_HALTON_MAX_DIMENSION 32

/* Radical inverse of index in the prime base of the given dimension (0 -> base 2,
 * 1 -> base 3, ...), in [0, 1).  Returns 0 for dimension >= LUMIS_HALTON_MAX_DIMENSION. */
double lumis_radical_inverse(unsigned dimension, uint64_t index);

/* Component `dimension` of the index-th point of the Halton sequence (same as above). */
static inline double lumis_halton(unsigned dimension, uint64_t index)
{
    return lumis_radical_inverse(dimension, index);
}

#ifdef __cplusplus
}
#endif
#endif
