#include "lumis/rng.h"

void lumis_pcg32_seed(lumis_pcg32 *rng, uint64_t seed, uint64_t stream)
{
    /* The initialisation of O'Neill's reference pcg32_srandom_r. */
    rng->state = 0u;
    rng->inc = (stream << 1u) | 1u;
    (void)lumis_pcg32_next(rng);
    rng->state += seed;
    (void)lumis_pcg32_next(rng);
}

uint32_t lumis_pcg32_bounded(lumis_pcg32 *rng, uint32_t bound)
{
    /* Lemire's nearly-divisionless method: multiply, reject the biased low slice. */
    uint64_t m = (uint64_t)lumis_pcg32_next(rng) * bound;
    uint32_t low = (uint32_t)m;
    if (low < bound) {
        uint32_t threshold = (uint32_t)(-bound) % bound;
        while (low < threshold) {
            m = (uint64_t)lumis_pcg32_next(rng) * bound;
            low = (uint32_t)m;
        }
    }
    return (uint32_t)(m >> 32);
}

void lumis_pcg32_advance(lumis_pcg32 *rng, int64_t delta)
{
    /* Brown's jump-ahead for LCGs: compose the affine map x -> a x + c with itself. */
    uint64_t cur_mult = 6364136223846793005ULL, cur_plus = rng->inc;
    uint64_t acc_mult = 1u, acc_plus = 0u;
    uint64_t d = (uint64_t)delta; /* two's complement: backwards is a long way forwards */
    while (d > 0) {
        if (d & 1u) {
            acc_mult *= cur_mult;
            acc_plus = acc_plus * cur_mult + cur_plus;
        }
        cur_plus = (cur_mult + 1u) * cur_plus;
        cur_mult *= cur_mult;
        d >>= 1u;
    }
    rng->state = acc_mult * rng->state + acc_plus;
}

static const unsigned primes[LUMIS_HALTON_MAX_DIMENSION] = {
    2,  3,  5,  7,  11, 13, 17, 19, 23, 29,  31,  37,  41,  43,  47,  53,
    59, 61, 67, 71, 73, 79, 83, 89, 97, 101, 103, 107, 109, 113, 127, 131};

double lumis_radical_inverse(unsigned dimension, uint64_t index)
{
    if (dimension >= LUMIS_HALTON_MAX_DIMENSION) return 0.0;
    const uint64_t base = primes[dimension];
    /* Accumulate the reversed digits as an integer, divide once at the end: exact until
     * the integer would overflow, which takes more digits than a double can hold. */
    uint64_t reversed = 0, limit = UINT64_MAX / base - base;
    double inv_base_n = 1.0;
    const double inv_base = 1.0 / (double)base;
    while (index > 0 && reversed < limit) {
        uint64_t next = index / base;
        uint64_t digit = index - next * base;
        reversed = reversed * base + digit;
        inv_base_n *= inv_base;
        index = next;
    }
    double r = (double)reversed * inv_base_n;
    return r < 1.0 ? r : 0x1.fffffffffffffp-1;
}
