/* The renderer's sample sequences (internal to lumis-render): where every number a camera
 * sample uses comes from.  A camera sample k of pixel (x, y) is a stream of dimensions;
 * each use of numbers takes the next dimension (a pair: one 2D point, or its first
 * coordinate for one number) and asks for point j of the n that camera sample draws in
 * it (n light samples of one vertex, a luminaire's samples ...): index k n + j of the
 * dimension's sequence.  The layout, fixed whatever a sample hits (docs/sampling.md):
 *   dimension 0                 the camera's jitter
 *   then, per vertex of the path, what its light kind takes (light_env.c, light_set.c,
 *   light_luminaire.c), then the BSDF sample that continues the path (integrator.c).
 * PCG32 (the independent reference) ignores dimensions and indices: it hands out its
 * stream's numbers in the order they are asked for, as the renderer always did. */
#ifndef LUMIS_RENDER_SEQUENCE_H
#define LUMIS_RENDER_SEQUENCE_H

#include "lumis/bsdf.h"
#include "lumis/rng.h"
#include "lumis/status.h"

#include "../core/internal.h"

#include <stdint.h>

/* A render's sequence: its kind, seed, the samples per pixel it plans for (stratified and
 * zsobol: 2^log2n), and pmj02's tables. */
typedef struct lumis__seq {
    lumis_sequence kind;
    uint64_t seed, key; /* key: the seed hashed */
    int log2n;
    uint32_t *pmj; /* pmj02: LUMIS__PMJ_PATTERNS tables of LUMIS__PMJ_POINTS (x, y) */
    /* Sobol's dimension 1, bits reversed, a byte of the index at a time: the xor of the
     * reversed columns of the byte's set bits (sobol, zsobol) */
    uint32_t sobol1[4][256];
} lumis__seq;

enum { LUMIS__PMJ_PATTERNS = 32, LUMIS__PMJ_LOG2 = 10, LUMIS__PMJ_POINTS = 1 << LUMIS__PMJ_LOG2 };

/* Makes q for a render's sequence (LUMIS_SEQUENCE_DEFAULT: the library's choice) and seed,
 * planned for planned_spp samples per pixel (0: 2^16).  pmj02 generates its tables here
 * (about 23 ms on one core).  errors: an optional sink. */
lumis_status lumis__seq_init(lumis__seq *q, lumis_sequence kind, uint64_t seed, int planned_spp,
                             const lumis_error_sink *errors);
void lumis__seq_release(lumis__seq *q);

/* One camera sample's stream. */
typedef struct lumis__stream {
    const lumis__seq *q;
    lumis_pcg32 rng; /* PCG32's numbers; the others' jitter where they need one */
    uint64_t pixel;  /* a hash of the seed and the pixel */
    uint64_t morton; /* zsobol: the pixel's z-order */
    uint32_t k;      /* the camera sample */
    uint32_t dim;    /* the next dimension */
} lumis__stream;

void lumis__stream_start(lumis__stream *s, const lumis__seq *q, int x, int y, int width, int k);

/* Point j of the n the camera sample draws in dimension dim, in [0, 1)^2 (one_d: only u[0]
 * is used, stratified over n strata rather than a grid). */
void lumis__seq_point(lumis__stream *s, uint32_t dim, uint32_t j, uint32_t n, int one_d,
                      double u[2]);

/* A 32-bit fraction as a double with 21 random bits below it (jitter inside the finest
 * cell: nets stay nets).  The samplers read more than 32 bits of a number: the alias
 * tables take the column and a 32-bit coin from one number and place the direction with
 * what is left, which must still be uniform. */
static inline double lumis__seq_frac53(uint32_t v, uint64_t random)
{
    return (double)(((uint64_t)v << 21) | (random >> 43)) * 0x1p-53;
}

/* Point i of the (0,2) Sobol' sequence, each coordinate Owen-scrambled with its seed, with
 * random bits below: owen(sobol0(i)) = reverse(permute(i)) (dimension 0 is i reversed), and
 * dimension 1 reversed is read from q's byte tables. */
static inline void lumis__sobol_point(const lumis__seq *q, uint32_t i, uint32_t s0, uint32_t s1,
                                      uint64_t low, int one_d, double u[2])
{
    u[0] = lumis__seq_frac53(lumis_reverse_bits32(lumis_owen_permute_reversed(i, s0)), low);
    if (one_d) return;
    const uint32_t r = q->sobol1[0][i & 255u] ^ q->sobol1[1][(i >> 8) & 255u] ^
                       q->sobol1[2][(i >> 16) & 255u] ^ q->sobol1[3][i >> 24];
    u[1] = lumis__seq_frac53(lumis_reverse_bits32(lumis_owen_permute_reversed(r, s1)), low << 21);
}

/* sobol (the default), inline: per pixel and dimension the index shuffled by Owen
 * scrambling (an aligned block stays one, so prefixes stay nets), then each coordinate
 * Owen-scrambled (Burley 2020); one hash gives the three seeds, a multiplication the bits
 * below. */
static inline void lumis__seq_sobol(const lumis__stream *s, uint32_t dim, uint64_t idx, int one_d,
                                    double u[2])
{
    const uint64_t h = lumis__mix64(s->pixel ^ ((uint64_t)dim * 0x9e3779b97f4a7c15ull + 0x50b0));
    /* dimension 0 keeps its order: two dimensions are decorrelated when either is
     * shuffled */
    const uint32_t i = dim == 0 ? (uint32_t)idx
                                : lumis_reverse_bits32(lumis_owen_permute_reversed(
                                      lumis_reverse_bits32((uint32_t)idx), (uint32_t)h));
    lumis__sobol_point(s->q, i, (uint32_t)(h >> 32), (uint32_t)((h * 0xd6e8feb86659fd93ull) >> 32),
                       (h + idx) * 0x9e3779b97f4a7c15ull, one_d, u);
}

/* The next dimension. */
static inline uint32_t seq_take(lumis__stream *s)
{
    return s->dim++;
}

static inline void seq_2d(lumis__stream *s, uint32_t dim, uint32_t j, uint32_t n, double u[2])
{
    if (s->q->kind == LUMIS_SEQUENCE_PCG) {
        u[0] = lumis_pcg32_double(&s->rng);
        u[1] = lumis_pcg32_double(&s->rng);
    } else if (s->q->kind == LUMIS_SEQUENCE_SOBOL) {
        lumis__seq_sobol(s, dim, (uint64_t)s->k * n + j, 0, u);
    } else {
        lumis__seq_point(s, dim, j, n, 0, u);
    }
}

/* lumis_reverse_bits32 in shifts and masks only, so that a loop of them vectorises on
 * every x86-64: the nibbles of each half are reversed in one step, not as a byte swap and
 * a nibble swap, which GCC turns into a bswap instruction (SSE2 has no vector form). */
static inline uint32_t seq_reverse32(uint32_t v)
{
    v = (v >> 16) | (v << 16);
    v = ((v >> 12) & 0x000f000fu) | ((v >> 4) & 0x00f000f0u) | ((v << 4) & 0x0f000f00u) |
        ((v << 12) & 0xf000f000u);
    v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
    return ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
}

/* Point 0 of 1 in each of m dimensions dims[0 .. m) of the camera sample, into u[2 q] and
 * u[2 q + 1]: what seq_2d(s, dims[q], 0, 1, u + 2 q) gives, called in order (PCG32 takes
 * its numbers in that order).  For sobol the points are the same bit for bit, computed in
 * loops over the dimensions instead of one call each (a stratified vertex asks for one
 * point in each of K dimensions): the index's reversal is the same for every dimension
 * and is done once, and the loops carry no dependence from one dimension to the next. */
static inline void seq_2d_dims(lumis__stream *s, const uint32_t *dims, int m, double *u)
{
    if (s->q->kind != LUMIS_SEQUENCE_SOBOL) {
        for (int q = 0; q < m; q++) seq_2d(s, dims[q], 0, 1, u + 2 * q);
        return;
    }
    enum { B = 64 };
    uint32_t a[B], r[B], s0[B], s1[B], z[B];
    uint64_t low[B];
    const lumis__seq *sq = s->q;
    const uint32_t idx = s->k, ridx = lumis_reverse_bits32(idx);
    for (int q0 = 0; q0 < m; q0 += B) {
        const int n = m - q0 < B ? m - q0 : B;
        /* the dimension's hash, and from it the three seeds and the bits below */
        for (int q = 0; q < n; q++) {
            const uint32_t dim = dims[q0 + q];
            const uint64_t h =
                lumis__mix64(s->pixel ^ ((uint64_t)dim * 0x9e3779b97f4a7c15ull + 0x50b0));
            z[q] = (uint32_t)h;
            s0[q] = (uint32_t)(h >> 32);
            s1[q] = (uint32_t)((h * 0xd6e8feb86659fd93ull) >> 32);
            low[q] = (h + idx) * 0x9e3779b97f4a7c15ull;
        }
        /* the shuffled index (dimension 0 keeps its order, as in lumis__seq_sobol) and
         * the first coordinate's scrambled bits: 32-bit lanes the compiler can vectorise */
        for (int q = 0; q < n; q++) {
            const uint32_t sh = seq_reverse32(lumis_owen_permute_reversed(ridx, z[q]));
            const uint32_t i = dims[q0 + q] == 0 ? idx : sh;
            a[q] = seq_reverse32(lumis_owen_permute_reversed(i, s0[q]));
            r[q] = i;
        }
        /* Sobol's dimension 1 of the shuffled index, reversed (the byte tables) */
        for (int q = 0; q < n; q++) {
            const uint32_t i = r[q];
            r[q] = sq->sobol1[0][i & 255u] ^ sq->sobol1[1][(i >> 8) & 255u] ^
                   sq->sobol1[2][(i >> 16) & 255u] ^ sq->sobol1[3][i >> 24];
        }
        for (int q = 0; q < n; q++) r[q] = seq_reverse32(lumis_owen_permute_reversed(r[q], s1[q]));
        for (int q = 0; q < n; q++) {
            double *o = u + 2 * (q0 + q);
            o[0] = lumis__seq_frac53(a[q], low[q]);
            o[1] = lumis__seq_frac53(r[q], low[q] << 21);
        }
    }
}

static inline double seq_1d(lumis__stream *s, uint32_t dim, uint32_t j, uint32_t n)
{
    if (s->q->kind == LUMIS_SEQUENCE_PCG) return lumis_pcg32_double(&s->rng);
    double u[2];
    if (s->q->kind == LUMIS_SEQUENCE_SOBOL)
        lumis__seq_sobol(s, dim, (uint64_t)s->k * n + j, 1, u);
    else
        lumis__seq_point(s, dim, j, n, 1, u);
    return u[0];
}

/* The next n dimensions (the first of them). */
static inline uint32_t seq_take_n(lumis__stream *s, uint32_t n)
{
    const uint32_t d = s->dim;
    s->dim += n;
    return d;
}

/* Point j of n of a BSDF sample's three numbers (lobe choice, then the direction's 2D
 * point), in the two dimensions from dim (seq_take_n(s, 2)).  A BSDF of one lobe
 * (Lambert's, a conductor's, glossy's) reads no lobe number: unless the numbers come in order
 * (PCG32), none is made (0.5). */
static inline void seq_bsdf(lumis__stream *s, const lumis_bsdf *b, uint32_t dim, uint32_t j,
                            uint32_t n, double u[3])
{
    const int one_lobe = b->type == LUMIS_BSDF_LAMBERT || b->type == LUMIS_BSDF_GGX_CONDUCTOR ||
                         b->type == LUMIS_BSDF_GGX_GLOSSY;
    u[0] = one_lobe && s->q->kind != LUMIS_SEQUENCE_PCG ? 0.5 : seq_1d(s, dim, j, n);
    seq_2d(s, dim + 1, j, n, u + 1);
}

#endif
