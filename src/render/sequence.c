/* The renderer's sample sequences (sequence.h): PCG32, Halton, jittered strata,
 * Owen-scrambled Sobol' (per pixel, or in z-order across pixels) and pmj02 tables.
 * Why each randomisation keeps the estimate unbiased and the nets nets: docs/sampling.md. */
#include "sequence.h"

#include "lumis/render_job.h"

#include "../core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int ceil_log2(uint64_t n)
{
    int l = 0;
    while (l < 63 && (1ull << l) < n) l++;
    return l;
}

lumis_status lumis__seq_init(lumis__seq *q, lumis_sequence kind, uint64_t seed, int planned_spp,
                             const lumis_error_sink *errors)
{
    q->kind = kind;
    q->seed = seed;
    q->key = lumis__mix64(seed + 0x5eed);
    q->log2n = ceil_log2(planned_spp > 0 ? (uint64_t)planned_spp : 1u << 16);
    q->pmj = NULL;
    for (int b = 0; b < 4; b++)
        for (uint32_t x = 0; x < 256; x++)
            q->sobol1[b][x] = lumis_reverse_bits32(lumis_sobol02_bits(x << (8 * b), 1));
    if ((unsigned)q->kind >= LUMIS_SEQUENCE_COUNT)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "render: unknown sequence %d",
                           (int)q->kind);
    q->kind = lumis_sequence_resolve(q->kind);
    if (q->kind != LUMIS_SEQUENCE_PMJ02) return LUMIS_OK;
    q->pmj = malloc(sizeof *q->pmj * 2 * LUMIS__PMJ_POINTS * LUMIS__PMJ_PATTERNS);
    if (!q->pmj)
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "render: pmj02 tables: out of memory");
    for (size_t p = 0; p < LUMIS__PMJ_PATTERNS; p++) {
        /* the tables depend on the pattern only, not the seed: the seed scrambles them */
        const lumis_status st = lumis_pmj02_generate(LUMIS__PMJ_POINTS, 0x706d6a30ull + p,
                                                     q->pmj + 2 * (size_t)LUMIS__PMJ_POINTS * p);
        if (st != LUMIS_OK) {
            lumis__seq_release(q);
            return lumis__fail(errors, st, "render: pmj02 tables: %s", lumis_status_string(st));
        }
    }
    return LUMIS_OK;
}

void lumis__seq_release(lumis__seq *q)
{
    free(q->pmj);
    q->pmj = NULL;
}

void lumis__stream_start(lumis__stream *s, const lumis__seq *q, int x, int y, int width, int k)
{
    const uint64_t pixel = (uint64_t)y * (uint64_t)width + (uint64_t)x;
    s->q = q;
    s->k = (uint32_t)k;
    s->dim = 0;
    /* PCG32: sample k of this pixel has its own stream, so passes cannot change it (the
     * renderer's numbers before the sequences, bit for bit) */
    if (q->kind == LUMIS_SEQUENCE_PCG)
        lumis_pcg32_seed(&s->rng, lumis__mix64(q->seed ^ lumis__mix64((uint64_t)k + 1)), pixel);
    s->pixel = lumis__mix64(q->key ^ (pixel * 0x9e3779b97f4a7c15ull));
    s->morton = q->kind == LUMIS_SEQUENCE_ZSOBOL ? lumis_morton2((uint32_t)x, (uint32_t)y) : 0;
}

/* A bijection of [0, 2^bits) keyed by key: odd multiplications, xor-shifts and an addition,
 * each invertible modulo 2^bits. */
static uint32_t permute(uint32_t i, uint32_t bits, uint64_t key)
{
    if (bits == 0) return 0;
    const uint32_t mask = bits >= 32 ? 0xffffffffu : (1u << bits) - 1u;
    const uint32_t sh = bits / 2 + 1;
    uint32_t x = i & mask;
    x = (x + (uint32_t)key) & mask;
    x = (x * (((uint32_t)(key >> 32)) | 1u)) & mask;
    x ^= x >> sh;
    x = (x * 0x2c1b3c6du) & mask;
    x ^= x >> sh;
    x = (x + (uint32_t)(key >> 40)) & mask;
    x = (x * 0x297a2d39u) & mask;
    x ^= x >> sh;
    return x;
}

/* Owen's scrambling of the 64-bit index I in base 2 from the top: bit i flipped by a
 * function of the seed and the bits above it, so the 2^k consecutive indices of an aligned
 * block go to an aligned block, permuted.  (The reversed index hashed as
 * lumis_owen_scramble does, with 64-bit even constants.) */
static inline uint64_t reverse64(uint64_t v)
{
#if defined(__GNUC__) || defined(__clang__)
    v = __builtin_bswap64(v);
#else
    v = ((v >> 8) & 0x00ff00ff00ff00ffull) | ((v & 0x00ff00ff00ff00ffull) << 8);
    v = ((v >> 16) & 0x0000ffff0000ffffull) | ((v & 0x0000ffff0000ffffull) << 16);
    v = (v >> 32) | (v << 32);
#endif
    v = ((v >> 4) & 0x0f0f0f0f0f0f0f0full) | ((v & 0x0f0f0f0f0f0f0f0full) << 4);
    v = ((v >> 2) & 0x3333333333333333ull) | ((v & 0x3333333333333333ull) << 2);
    return ((v >> 1) & 0x5555555555555555ull) | ((v & 0x5555555555555555ull) << 1);
}

static uint64_t index_scramble(uint64_t I, uint64_t seed)
{
    uint64_t x = reverse64(I);
    x += seed;
    x ^= x * 0x9e3779b97f4a7c16ull;
    x ^= x * 0xbf58476d1ce4e5b8ull;
    x ^= x * 0x94d049bb133111eaull;
    x ^= x * 0xd6e8feb86659fd92ull;
    return reverse64(x);
}

/* 53 random bits as a double in [0, 1). */
static inline double unit53(uint64_t random)
{
    return (double)(random >> 11) * 0x1p-53;
}

void lumis__seq_point(lumis__stream *s, uint32_t dim, uint32_t j, uint32_t n, int one_d,
                      double u[2])
{
    const lumis__seq *q = s->q;
    const uint64_t idx = (uint64_t)s->k * n + j;
    switch (q->kind) {
    case LUMIS_SEQUENCE_HALTON: {
        /* dimensions 2 dim and 2 dim + 1 of Halton's sequence (past 32: the first again),
         * rotated per pixel and dimension (Cranley-Patterson) */
        const uint64_t h = lumis__mix64(s->pixel ^ lumis__mix64(dim + 0x4a17));
        const unsigned b = (2u * dim) % LUMIS_HALTON_MAX_DIMENSION;
        const double v0 = lumis_halton(b, idx + 1) + unit53(h),
                     v1 = lumis_halton(b + 1, idx + 1) + unit53(lumis__mix64(h));
        u[0] = v0 >= 1.0 ? v0 - 1.0 : v0;
        u[1] = v1 >= 1.0 ? v1 - 1.0 : v1;
        return;
    }
    case LUMIS_SEQUENCE_STRATIFIED: {
        /* the planned n spp points as 2^L strata (a 2^ceil(L/2) x 2^floor(L/2) grid, or L
         * strata of [0, 1)), visited in an order drawn per pixel and dimension, jittered;
         * each further block of 2^L points is a new such set */
        const uint32_t L = (uint32_t)(q->log2n + ceil_log2(n));
        const uint64_t block = L >= 32 ? 0 : idx >> L;
        const uint64_t key =
            lumis__mix64(s->pixel ^ lumis__mix64(((uint64_t)dim << 24) + block + 0x57a7));
        const uint32_t st = permute((uint32_t)idx, L, key);
        const uint64_t jit = lumis__mix64(key ^ idx);
        if (one_d) {
            u[0] = ((double)st + unit53(jit)) * ldexp(1.0, -(int)L);
            u[1] = 0.0;
            return;
        }
        const uint32_t lx = (L + 1) / 2, ly = L / 2;
        u[0] = ((double)(st & ((1u << lx) - 1u)) + unit53(jit)) * ldexp(1.0, -(int)lx);
        u[1] = ((double)(st >> lx) + unit53(lumis__mix64(jit))) * ldexp(1.0, -(int)ly);
        return;
    }
    case LUMIS_SEQUENCE_SOBOL: /* seq_2d and seq_1d do not come here for it */
        lumis__seq_sobol(s, dim, idx, one_d, u);
        return;
    case LUMIS_SEQUENCE_ZSOBOL: {
        /* pbrt-v4's ZSobol idea: pixel p's planned 2^L points are indices p 2^L .. of one
         * sequence in z-order, so neighbouring pixels share the nets of their union (blue
         * noise across the screen); the index is Owen-scrambled per dimension, the same
         * scramble for all pixels.  Past the plan, each further block of 2^L points is
         * scrambled afresh. */
        const uint32_t L =
            (uint32_t)(q->log2n + ceil_log2(n)) < 30 ? (uint32_t)(q->log2n + ceil_log2(n)) : 30;
        const uint64_t block = idx >> L, within = idx & ((1ull << L) - 1u);
        const uint64_t seed =
            lumis__mix64(q->key ^ ((uint64_t)dim * 0x9e3779b97f4a7c15ull + (block << 40) + 0x250b));
        const uint64_t I = index_scramble((s->morton << L) | within, seed);
        /* the coordinates' scramble too is one per dimension, as pbrt's (the points depend
         * on the index's low 32 bits) */
        const uint64_t g = seed * 0xd6e8feb86659fd93ull;
        lumis__sobol_point(q, (uint32_t)I, (uint32_t)g, (uint32_t)(g >> 32),
                           (g + I) * 0x9e3779b97f4a7c15ull, one_d, u);
        return;
    }
    case LUMIS_SEQUENCE_PMJ02: {
        /* Table dim mod P (then the next ones, one per 2^10 points).  The tables share
         * their construction's rules (point N + i is point i's partner), so index k of two
         * tables is the same point up to the scrambles: the pairs of dimensions would be
         * degenerate in 4D (the error of a product of two dimensions stopped falling at
         * 256 samples).  So the points of each doubling [2^j, 2^(j+1)) come in an order
         * drawn per pixel and dimension (every power-of-two prefix keeps its set: nets stay
         * nets), and each coordinate is Owen-scrambled per pixel and dimension. */
        const uint64_t block = idx >> LUMIS__PMJ_LOG2;
        const uint32_t p = (uint32_t)((dim + 7u * block) % LUMIS__PMJ_PATTERNS);
        const uint64_t h =
            lumis__mix64(s->pixel ^ lumis__mix64(((uint64_t)dim << 24) + block + 0x9302));
        uint32_t i = (uint32_t)(idx & (LUMIS__PMJ_POINTS - 1));
        if (i > 1) {
            uint32_t level = 31;
            while (!(i >> level)) level--;
            i = (1u << level) | permute(i - (1u << level), level, lumis__mix64(h + level));
        }
        const uint32_t *t = q->pmj + 2 * ((size_t)p * LUMIS__PMJ_POINTS + i);
        const uint64_t low = lumis__mix64(h ^ idx);
        u[0] = lumis__seq_frac53(lumis_owen_scramble(t[0], (uint32_t)h), low);
        u[1] = lumis__seq_frac53(lumis_owen_scramble(t[1], (uint32_t)(h >> 32)), low << 21);
        return;
    }
    default: /* PCG32 (seq_2d and seq_1d do not come here for it) */
        u[0] = lumis_pcg32_double(&s->rng);
        u[1] = one_d ? 0.0 : lumis_pcg32_double(&s->rng);
        return;
    }
}

lumis_status lumis_sequence_fill(const lumis_sequence_desc *d, int first_sample, int samples,
                                 double *out)
{
    if (!d) return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis_error_sink *e = &d->errors;
    const int width = d->width ? d->width : 1, n = d->per_sample ? d->per_sample : 1;
    if (d->width < 0 || d->x < 0 || d->x >= width || d->y < 0)
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT,
                           "sequence: pixel (%d, %d) outside an image %d wide", d->x, d->y,
                           d->width);
    if (d->planned_spp < 0)
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT,
                           "sequence: planned_spp %d (expected >= 0)", d->planned_spp);
    if (d->dimension < 0)
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT, "sequence: dimension %d (expected >= 0)",
                           d->dimension);
    if (d->per_sample < 0)
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT, "sequence: per_sample %d (expected >= 0)",
                           d->per_sample);
    if (first_sample < 0 || samples < 0 || (int64_t)first_sample + samples > INT32_MAX)
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT,
                           "sequence: samples %d from %d (expected counts >= 0 within 2^31)",
                           samples, first_sample);
    if (samples && !out) return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT, "sequence: out is NULL");
    lumis__seq q;
    const lumis_status st = lumis__seq_init(&q, d->sequence, d->seed, d->planned_spp, e);
    if (st != LUMIS_OK) return st;
    size_t i = 0;
    for (int k = first_sample; k < first_sample + samples; k++) {
        lumis__stream s;
        lumis__stream_start(&s, &q, d->x, d->y, width, k);
        if (q.kind == LUMIS_SEQUENCE_PCG) /* the pairs before this dimension's */
            for (uint64_t skip = 0; skip < 2 * (uint64_t)d->dimension * (uint64_t)n; skip++)
                (void)lumis_pcg32_double(&s.rng);
        for (int j = 0; j < n; j++, i++)
            seq_2d(&s, (uint32_t)d->dimension, (uint32_t)j, (uint32_t)n, out + 2 * i);
    }
    lumis__seq_release(&q);
    return LUMIS_OK;
}
