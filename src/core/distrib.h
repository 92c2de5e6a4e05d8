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
#include <string.h>

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

/* The same search in steps, so a batch can interleave many (src/envmap/sampler.c): the
 * answer is the largest i in [lo, lo + len) with cdf[i] <= t.  Each step halves len
 * without a branch on the data (a mispredicted branch would discard the work after it). */
typedef struct lumis__cdf_search {
    double x;         /* u 2^32 */
    uint32_t t;       /* floor(x) */
    uint32_t lo, len; /* the range left */
} lumis__cdf_search;

/* Starts a search (reads the guide entry, if any). */
static inline lumis__cdf_search lumis__cdf_search_start(const lumis__cdf *c, double u)
{
    lumis__cdf_search q;
    q.x = u * LUMIS__ONE32; /* exact: a power-of-two scaling */
    uint64_t t = (uint64_t)q.x;
    q.t = t > 0xffffffffu ? 0xffffffffu : (uint32_t)t;
    if (c->guide) {
        uint32_t k = (uint32_t)(((uint64_t)q.t * c->n) >> 32);
        q.lo = c->guide[k];
        q.len = c->guide[k + 1] - q.lo + 1;
    } else {
        q.lo = 0;
        q.len = c->m;
    }
    return q;
}

/* The next lookup a step will make (to prefetch). */
static inline const uint32_t *lumis__cdf_search_next(const lumis__cdf *c,
                                                     const lumis__cdf_search *q)
{
    return c->cdf + q->lo + q->len / 2;
}

static inline void lumis__cdf_search_step(const lumis__cdf *c, lumis__cdf_search *q)
{
    uint32_t half = q->len / 2;
    q->lo += c->cdf[q->lo + half] <= q->t ? half : 0;
    q->len -= half;
}

/* The entry found (q->len == 1) and where inside it. */
static inline uint32_t lumis__cdf_search_end(const lumis__cdf *c, const lumis__cdf_search *q,
                                             double *frac)
{
    uint32_t lo = q->lo;
    uint64_t next = lo + 1 < c->m ? c->cdf[lo + 1] : (uint64_t)1 << 32;
    *frac = (q->x - (double)c->cdf[lo]) / (double)(next - c->cdf[lo]);
    if (*frac >= 1.0) *frac = 0x1.fffffffffffffp-1;
    return lo;
}

/* ---- Walker / Vose alias table with 32-bit integer thresholds ----------------------- */

/* One column, 16 bytes and 16-byte aligned, so a draw reads one cache line: the accept
 * threshold, the alias, and the values of both outcomes (a copy of the alias's own value,
 * so taking the alias costs no second lookup). */
typedef struct lumis__alias_bin {
    uint32_t thresh;   /* keep this column's entry when 32 random bits r < thresh */
    uint32_t alias;    /* ... else take this one */
    float value;       /* this entry's value (see lumis__alias_build) */
    float alias_value; /* == bin[alias].value */
} lumis__alias_bin;

typedef struct lumis__alias {
    lumis__alias_bin *bin;
    uint32_t n;
} lumis__alias;

/* What an entry's bin stores, from its realised probability (exact, as a double): the
 * owner's density, so that sample and pdf read the same float.  NULL: the probability. */
typedef float (*lumis__alias_value_fn)(const void *ctx, uint32_t entry, double prob);

/* Builds from n weights (sum > 0), n <= 2^31. */
lumis_status lumis__alias_build(lumis__alias *a, const double *w, uint32_t n,
                                lumis__alias_value_fn value, const void *ctx);
void lumis__alias_free(lumis__alias *a);

/* The value stored for entry k (what a draw of k reports). */
static inline float lumis__alias_value(const lumis__alias *a, uint32_t k)
{
    return a->bin[k].value;
}

/* Draws an entry: u1 picks the column (and *frac1 is what is left of it), u2's top 32
 * bits the accept test (*frac2 what is left); *value receives the entry's value.  One
 * lookup (the bin). */
static inline uint32_t lumis__alias_sample(const lumis__alias *a, double u1, double u2,
                                           double *frac1, double *frac2, float *value)
{
    double x = u1 * a->n;
    uint32_t i = (uint32_t)x;
    if (i >= a->n) i = a->n - 1;
    *frac1 = x - i;
    double y = u2 * LUMIS__ONE32;
    uint32_t r = (uint32_t)y;
    *frac2 = y - r;
    const lumis__alias_bin b = a->bin[i];
    /* The accept test is a coin flip: select with masks, not a branch that would be
     * mispredicted half the time (and discard the work of the samples after it). */
    uint32_t keep = 0u - (uint32_t)(r < b.thresh), v, va, vb;
    memcpy(&va, &b.value, sizeof va);
    memcpy(&vb, &b.alias_value, sizeof vb);
    v = (va & keep) | (vb & ~keep);
    memcpy(value, &v, sizeof v);
    return (i & keep) | (b.alias & ~keep);
}

#endif
