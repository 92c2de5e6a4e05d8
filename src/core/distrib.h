/* Discrete distributions with exact, integer tables (shared building blocks).
 *
 * Both tables quantise probabilities to multiples of 2^-32 (of the whole, or of one
 * alias column), so the distribution a sampler realises is exactly the one its pdf
 * reports, and every entry of nonzero weight keeps at least one unit: nothing that
 * shines is ever given probability 0 (which would bias every estimate).  Derivation:
 * docs/samplers.md. */
#ifndef LUMIS_CORE_DISTRIB_H
#define LUMIS_CORE_DISTRIB_H

#include "lumis/status.h"

#include <stddef.h>
#include <stdint.h>

#define LUMIS__ONE32 4294967296.0 /* 2^32 */

/* Turns n non-negative weights (sum > 0) into integer units summing to exactly `total`,
 * proportional to the weights, each nonzero weight getting at least one unit.
 * Requires total >= number of nonzero weights. */
void lumis__quantize(const double *w, size_t n, uint64_t total, uint64_t *units);

/* ---- 1D inversion with an integer CDF ------------------------------------------------ */

/* cdf[0] = 0 <= cdf[1] <= ... <= cdf[m-1] and an implicit cdf[m] = 2^32, where m - 1 is
 * the last entry of nonzero weight (entries after it have probability 0 and no stored
 * value: 2^32 does not fit in 32 bits).  Entry i < m has probability
 * (cdf[i+1] - cdf[i]) / 2^32. */
typedef struct lumis__cdf {
    uint32_t *cdf;   /* n entries (those from m on unused) */
    uint32_t *guide; /* NULL, or n + 1 entries: guide[k] = entry holding k 2^32 / n */
    uint32_t n, m;
} lumis__cdf;

/* Builds from n weights (sum > 0).  guided: also build the guide table. */
lumis_status lumis__cdf_build(lumis__cdf *c, const double *w, uint32_t n, int guided);
void lumis__cdf_free(lumis__cdf *c);

/* Probability of entry i, exactly. */
static inline double lumis__cdf_prob(const lumis__cdf *c, uint32_t i)
{
    if (i >= c->m) return 0.0;
    uint64_t hi = i + 1 < c->m ? c->cdf[i + 1] : (uint64_t)1 << 32;
    return (double)(hi - c->cdf[i]) * (1.0 / LUMIS__ONE32);
}

/* The entry u in [0,1) falls in, and where inside it (*frac in [0,1), continuous in u).
 * Binary search: ceil(log2 n) lookups, or about two with the guide table. */
uint32_t lumis__cdf_sample(const lumis__cdf *c, double u, double *frac);

/* ---- Walker / Vose alias table with 32-bit integer thresholds ----------------------- */

/* One column: both fields share a cache line, so a draw costs one memory access (plus the
 * pmf of the result). */
typedef struct lumis__alias_column {
    uint32_t thresh; /* keep this column's entry when 32 random bits r < thresh */
    uint32_t alias;  /* ... else take this one */
} lumis__alias_column;

typedef struct lumis__alias {
    lumis__alias_column *col;
    float *pmf; /* the realised probability of each entry, rounded to float */
    uint32_t n;
} lumis__alias;

/* Builds from n weights (sum > 0), n <= 2^31. */
lumis_status lumis__alias_build(lumis__alias *a, const double *w, uint32_t n);
void lumis__alias_free(lumis__alias *a);

/* Draws an entry: u1 picks the column (and *frac1 is what is left of it), u2's top 32
 * bits the accept test (*frac2 what is left).  One lookup (the column). */
static inline uint32_t lumis__alias_sample(const lumis__alias *a, double u1, double u2,
                                           double *frac1, double *frac2)
{
    double x = u1 * a->n;
    uint32_t i = (uint32_t)x;
    if (i >= a->n) i = a->n - 1;
    *frac1 = x - i;
    double y = u2 * LUMIS__ONE32;
    uint32_t r = (uint32_t)y;
    *frac2 = y - r;
    const lumis__alias_column c = a->col[i];
    return r < c.thresh ? i : c.alias;
}

#endif
