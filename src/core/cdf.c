/* 1D inversion sampling over an integer CDF (see distrib.h). */
#include "distrib.h"

#include <math.h>
#include <stdlib.h>

void lumis__quantize(const double *w, size_t n, uint64_t total, uint64_t *units)
{
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) sum += w[i];
    const double scale = (double)total / sum;
    /* Cumulative rounding: entry i gets round(total * prefix_{i+1} / sum) minus what came
     * before, so each entry is within one unit of its share and the sum telescopes to
     * total; an entry of nonzero weight gets at least one unit. */
    double prefix = 0.0;
    uint64_t given = 0;
    size_t largest = 0;
    for (size_t i = 0; i < n; i++) {
        prefix += w[i];
        double target = fmin(prefix * scale, (double)total);
        uint64_t upto = (uint64_t)llround(target);
        uint64_t q = upto > given ? upto - given : 0;
        if (w[i] > 0.0 && q == 0) q = 1;
        if (w[i] <= 0.0) q = 0;
        units[i] = q;
        given += q;
        if (w[i] > w[largest]) largest = i;
    }
    /* What the forced minimum units (or the last rounding) left over or took too much
     * settles on the largest entry: a few units against at least total / n. */
    if (given < total) units[largest] += total - given;
    uint64_t excess = given > total ? given - total : 0;
    while (excess > 0) {
        /* Very many tiny entries in a short table (say 2^28 pixels in one row): take
         * the excess from the entries holding most, never below one unit. */
        size_t big = largest;
        for (size_t i = 0; i < n; i++)
            if (units[i] > units[big]) big = i;
        uint64_t take = units[big] - 1 < excess ? units[big] - 1 : excess;
        if (take == 0) break; /* total < nonzero entries: cannot happen for our tables */
        units[big] -= take;
        excess -= take;
    }
}

lumis_status lumis__cdf_build(lumis__cdf *c, const double *w, uint32_t n, int guided)
{
    c->n = n;
    c->cdf = malloc((size_t)n * sizeof(uint32_t));
    c->guide = guided ? malloc(((size_t)n + 1) * sizeof(uint32_t)) : NULL;
    uint64_t *units = malloc((size_t)n * sizeof(uint64_t));
    if (!c->cdf || !units || (guided && !c->guide)) {
        free(units);
        lumis__cdf_free(c);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    lumis__quantize(w, n, (uint64_t)1 << 32, units);
    uint64_t acc = 0;
    c->m = 0;
    for (uint32_t i = 0; i < n; i++) {
        c->cdf[i] = acc < ((uint64_t)1 << 32) ? (uint32_t)acc : 0xffffffffu; /* unused past m */
        acc += units[i];
        if (units[i]) c->m = i + 1;
    }
    free(units);
    if (guided) {
        /* guide[k]: the entry containing t = k 2^32 / n, so a search for t in
         * [k, k+1) 2^32 / n starts at guide[k] and ends by guide[k + 1]. */
        uint32_t i = 0;
        for (uint32_t k = 0; k <= n; k++) {
            uint64_t t = k == n ? ((uint64_t)1 << 32) - 1 : ((uint64_t)k << 32) / n;
            while (i + 1 < c->m && c->cdf[i + 1] <= t) i++;
            c->guide[k] = i;
        }
    }
    return LUMIS_OK;
}

void lumis__cdf_free(lumis__cdf *c)
{
    free(c->cdf);
    free(c->guide);
    c->cdf = c->guide = NULL;
}

uint32_t lumis__cdf_sample(const lumis__cdf *c, double u, double *frac)
{
    lumis__cdf_search q = lumis__cdf_search_start(c, u);
    while (q.len > 1) {
#if defined(__GNUC__) || defined(__clang__)
        /* Both lookups the next step may make: what a predicted branch used to fetch
         * early, without the misprediction. */
        uint32_t half = q.len / 2, next = (q.len - half) / 2;
        __builtin_prefetch(c->cdf + q.lo + next);
        __builtin_prefetch(c->cdf + q.lo + half + next);
#endif
        lumis__cdf_search_step(c, &q);
    }
    return lumis__cdf_search_end(c, &q, frac);
}
