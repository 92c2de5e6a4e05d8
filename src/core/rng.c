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

void lumis_pcg32_fill_doubles(lumis_pcg32 *rng, double *out, size_t n)
{
    enum { W = 8 }; /* states per chain step: W / 2 doubles */
    const uint64_t a = 6364136223846793005ULL;
    size_t k = 0;
    if (n >= W / 2) {
        /* W steps as one affine map x -> aw x + cw; chain i holds states i, i + W, ... */
        uint64_t aw = 1u, cw = 0u, s[W];
        for (int i = 0; i < W; i++) {
            aw *= a;
            cw = cw * a + rng->inc;
        }
        s[0] = rng->state;
        for (int i = 1; i < W; i++) s[i] = s[i - 1] * a + rng->inc;
        for (; k + W / 2 <= n; k += W / 2) {
            uint32_t o[W];
            for (int i = 0; i < W; i++) {
                o[i] = lumis_pcg32_output(s[i]);
                s[i] = s[i] * aw + cw;
            }
            for (int j = 0; j < W / 2; j++)
                out[k + (size_t)j] =
                    (double)((((uint64_t)o[2 * j] << 32) | o[2 * j + 1]) >> 11) * 0x1p-53;
        }
        rng->state = s[0]; /* the first state not yet used */
    }
    for (; k < n; k++) out[k] = lumis_pcg32_double(rng);
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
