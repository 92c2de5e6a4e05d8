/* 1D inversion sampling over an integer CDF (see distrib.h). */
#include "distrib.h"

#include <stdlib.h>

void lumis__quantize(const double *w, size_t n, uint64_t total, uint64_t *units)
{
    double sum = 0.0;
    for (size_t i = 0; i < n; i++) sum += w[i];
    const double scale = (double)total / sum;
    uint64_t given = 0;
    size_t largest = 0;
    for (size_t i = 0; i < n; i++) {
        uint64_t q = 0;
        if (w[i] > 0.0) {
            double x = w[i] * scale;
            q = x < 1.0 ? 1 : (x >= (double)total ? total : (uint64_t)x);
        }
        units[i] = q;
        given += q;
        if (w[i] > w[largest]) largest = i;
    }
    /* Rounding down leaves units over (and the minimum of one may take a few): settle the
     * difference on the largest weights, which it changes least in relative terms. */
    while (given != total) {
        if (given < total) {
            units[largest] += total - given;
            given = total;
        } else {
            uint64_t excess = given - total;
            /* Take from the largest entries, never below one unit. */
            size_t big = largest;
            for (size_t i = 0; i < n; i++)
                if (units[i] > units[big]) big = i;
            uint64_t room = units[big] > 1 ? units[big] - 1 : 0;
            uint64_t take = excess < room ? excess : room;
            units[big] -= take;
            given -= take;
            if (take == 0) break; /* cannot happen while total >= nonzero count */
        }
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
    double x = u * LUMIS__ONE32; /* exact: a power-of-two scaling */
    uint64_t t = (uint64_t)x;
    if (t > 0xffffffffu) t = 0xffffffffu;
    /* Largest i < m with cdf[i] <= t, in [lo, hi]. */
    uint32_t lo = 0, hi = c->m - 1;
    if (c->guide) {
        uint32_t k = (uint32_t)((t * c->n) >> 32);
        lo = c->guide[k];
        hi = c->guide[k + 1];
    }
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo + 1) / 2;
        if (c->cdf[mid] <= t)
            lo = mid;
        else
            hi = mid - 1;
    }
    uint64_t next = lo + 1 < c->m ? c->cdf[lo + 1] : (uint64_t)1 << 32;
    *frac = (x - (double)c->cdf[lo]) / (double)(next - c->cdf[lo]);
    if (*frac >= 1.0) *frac = 0x1.fffffffffffffp-1;
    return lo;
}
