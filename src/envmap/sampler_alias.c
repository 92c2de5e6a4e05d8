/* Alias method (Walker 1977, Vose 1991) over all pixels, with integer thresholds so the
 * realised distribution is exactly the stored one at any size (see src/core/alias.c).
 *
 * Cost per sample: O(1), one lookup: a 16-byte bin holds the threshold, the alias and the
 * densities of both outcomes, so neither the pmf nor the row's solid angle is read again.
 * Tables: 16 bytes per pixel; pdf() reads the pixel's own bin. */
#include "sampler_method.h"

#include "../core/distrib.h"

#include <stdlib.h>

typedef struct alias_sampler {
    lumis__alias table;
    double inv_w; /* 1 / width: the row of an entry without an integer division */
} alias_sampler;

/* Bins store the density per steradian, probability / Omega_j, rounded once to float:
 * sample() and pdf() then return that very float. */
static float pixel_density(const void *ctx, uint32_t k, double prob)
{
    const lumis_sampler *s = ctx;
    return (float)(prob / s->env->row_solid_angle[k / (uint32_t)s->w]);
}

static void alias_pick(const lumis_sampler *s, double u1, double u2, lumis__pick *p)
{
    const alias_sampler *a = s->data;
    double fx, fy;
    float density;
    uint32_t k = lumis__alias_sample(&a->table, u1, u2, &fx, &fy, &density);
    /* k / w by a multiplication; the estimate is off by at most one either way. */
    int64_t j = (int64_t)((double)k * a->inv_w), i = (int64_t)k - j * s->w;
    if (i < 0) j--, i += s->w;
    if (i >= s->w) j++, i -= s->w;
    p->x0 = (int)i;
    p->x1 = (int)i + 1;
    p->y0 = (int)j;
    p->y1 = (int)j + 1;
    p->s = fx;
    p->t = fy;
    p->density = density;
}

/* A batch: every bin is requested before the first is read. */
static void alias_pick_n(const lumis_sampler *s, const double *u, int n, lumis__pick *out)
{
#if defined(__GNUC__) || defined(__clang__)
    const alias_sampler *a = s->data;
    for (int k = 0; k < n; k++) {
        uint32_t i = (uint32_t)(u[2 * k] * a->table.n);
        __builtin_prefetch(&a->table.bin[i < a->table.n ? i : a->table.n - 1]);
    }
#endif
    for (int k = 0; k < n; k++) alias_pick(s, u[2 * k], u[2 * k + 1], &out[k]);
}

static double alias_density(const lumis_sampler *s, int i, int j)
{
    const alias_sampler *a = s->data;
    return lumis__alias_value(&a->table, (uint32_t)j * (uint32_t)s->w + (uint32_t)i);
}

static void alias_destroy(lumis_sampler *s)
{
    alias_sampler *a = s->data;
    if (!a) return;
    lumis__alias_free(&a->table);
    free(a);
}

static const lumis__method alias_method = {alias_pick, alias_density, alias_destroy,
                                           0,          alias_pick_n,  NULL};

lumis_status lumis__alias_init(lumis_sampler *s, const double *imp)
{
    s->m = &alias_method;
    alias_sampler *a = calloc(1, sizeof *a);
    s->data = a;
    if (!a) return LUMIS_ERR_OUT_OF_MEMORY;
    uint64_t n = (uint64_t)s->w * (uint64_t)s->h;
    if (n > ((uint64_t)1 << 31)) return LUMIS_ERR_TOO_LARGE;
    a->inv_w = 1.0 / s->w;
    lumis_status st = lumis__alias_build(&a->table, imp, (uint32_t)n, pixel_density, s);
    if (st != LUMIS_OK) return st;
    s->table_bytes = (size_t)n * sizeof(lumis__alias_bin);
    s->total_bytes = s->table_bytes + sizeof *a;
    return LUMIS_OK;
}
