/* Alias method (Walker 1977, Vose 1991) over all pixels, with integer thresholds so the
 * realised distribution is exactly the stored one at any size (see src/core/alias.c).
 *
 * Cost per sample: O(1), one lookup (a column: threshold and alias side by side) and the
 * pmf of the result.  Tables: 12 bytes per pixel (threshold, alias, pmf for pdf()). */
#include "sampler_internal.h"

#include "../core/distrib.h"

#include <stdlib.h>

static void alias_pick(const lumis_sampler *s, double u1, double u2, lumis__pick *p)
{
    const lumis__alias *a = s->data;
    double fx, fy;
    uint32_t k = lumis__alias_sample(a, u1, u2, &fx, &fy);
    int j = (int)(k / (uint32_t)s->w), i = (int)(k % (uint32_t)s->w);
    p->x0 = i;
    p->x1 = i + 1;
    p->y0 = j;
    p->y1 = j + 1;
    p->s = fx;
    p->t = fy;
    p->density = a->pmf[k] / s->env->row_solid_angle[j];
}

static double alias_density(const lumis_sampler *s, int i, int j)
{
    const lumis__alias *a = s->data;
    return a->pmf[(size_t)j * (size_t)s->w + (size_t)i] / s->env->row_solid_angle[j];
}

static void alias_destroy(lumis_sampler *s)
{
    if (!s->data) return;
    lumis__alias_free(s->data);
    free(s->data);
}

static const lumis__method alias_method = {alias_pick, alias_density, alias_destroy, 0};

lumis_status lumis__alias_init(lumis_sampler *s, const double *imp)
{
    s->m = &alias_method;
    lumis__alias *a = calloc(1, sizeof *a);
    s->data = a;
    if (!a) return LUMIS_ERR_OUT_OF_MEMORY;
    uint64_t n = (uint64_t)s->w * (uint64_t)s->h;
    if (n > ((uint64_t)1 << 31)) return LUMIS_ERR_TOO_LARGE;
    lumis_status st = lumis__alias_build(a, imp, (uint32_t)n);
    if (st != LUMIS_OK) return st;
    s->table_bytes = (size_t)n * 12;
    s->total_bytes = s->table_bytes;
    return LUMIS_OK;
}
