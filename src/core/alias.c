/* Walker's alias method with Vose's construction, on integers (see distrib.h).
 *
 * Weights become integer units summing to exactly n 2^32; each column holds 2^32 units,
 * split between its own entry (thresh) and one alias.  Integer arithmetic makes the
 * construction exact: the realised probability of entry k is exactly
 * (thresh[k] + sum over columns j aliasing k of (2^32 - thresh[j])) / (n 2^32), which
 * equals its units / (n 2^32).  A float threshold, as in pbrt-v4, leaves about 3 bits for
 * the accept test over 2^21 entries and realises a visibly different distribution. */
#include "distrib.h"

#include <stdlib.h>

/* Values are all set before the first call, so the alias's value can be copied. */
static void set_bin(lumis__alias *a, uint32_t k, uint32_t thresh, uint32_t alias)
{
    a->bin[k].thresh = thresh;
    a->bin[k].alias = alias;
    a->bin[k].alias_value = a->bin[alias].value;
}

/* The build into n bins (16-byte aligned), with scratch for n units and n work entries. */
static void build_in(lumis__alias_bin *bin, uint64_t *units, uint32_t *work, const double *w,
                     uint32_t n, lumis__alias_value_fn value, const void *ctx);

lumis_status lumis__alias_build(lumis__alias *a, const double *w, uint32_t n,
                                lumis__alias_value_fn value, const void *ctx)
{
    a->n = n;
    /* 16-byte bins, 16-byte aligned: no bin straddles two cache lines. */
    a->bin = aligned_alloc(16, (size_t)n * sizeof(lumis__alias_bin));
    uint64_t *units = malloc((size_t)n * sizeof(uint64_t));
    uint32_t *work = malloc((size_t)n * sizeof(uint32_t));
    if (!a->bin || !units || !work) {
        free(units);
        free(work);
        lumis__alias_free(a);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    build_in(a->bin, units, work, w, n, value, ctx);
    free(units);
    free(work);
    return LUMIS_OK;
}

static void build_in(lumis__alias_bin *bin, uint64_t *units, uint32_t *work, const double *w,
                     uint32_t n, lumis__alias_value_fn value, const void *ctx)
{
    const uint64_t one = (uint64_t)1 << 32;
    lumis__alias view = {bin, n}, *a = &view;
    lumis__quantize(w, n, (uint64_t)n << 32, units);
    const double inv_total = 1.0 / ((double)n * LUMIS__ONE32);
    for (uint32_t i = 0; i < n; i++) {
        double prob = (double)units[i] * inv_total;
        a->bin[i].value = value ? value(ctx, i, prob) : (float)prob;
    }

    /* Vose: small entries (under one column) fill up from large ones.  `work` holds the
     * small stack growing up from 0 and the large stack growing down from n. */
    uint32_t ns = 0, nl = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (units[i] < one)
            work[ns++] = i;
        else
            work[n - 1 - nl++] = i;
    }
    while (ns > 0 && nl > 0) {
        uint32_t s = work[--ns];
        uint32_t l = work[n - nl]; /* top of the large stack */
        set_bin(a, s, (uint32_t)units[s], l);
        units[l] -= one - units[s];
        if (units[l] < one) {
            nl--;
            work[ns++] = l;
        }
    }
    /* What remains holds exactly one column each (the arithmetic is exact). */
    while (nl > 0) {
        uint32_t l = work[n - nl--];
        set_bin(a, l, 0xffffffffu, l);
    }
    while (ns > 0) {
        uint32_t s = work[--ns];
        set_bin(a, s, 0xffffffffu, s);
    }
}

void lumis__alias_free(lumis__alias *a)
{
    free(a->bin);
    a->bin = NULL;
}
