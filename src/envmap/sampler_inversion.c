/* Inversion (Fishman; pbrt's Distribution2D): a marginal CDF over rows, a conditional CDF
 * per row, each searched for u; the point inside the pixel is what is left of u, so the
 * warp is continuous and keeps the stratification of its input.
 *
 * Cost per sample: two binary searches, ceil(log2 h) + ceil(log2 w) lookups (21 on a
 * 2048 x 1024 map), or with the guide tables ("inversion-guided") two guide lookups and
 * about two CDF lookups per search - the same samples for the same u.
 * Tables: 4 bytes per pixel and per row (integer CDFs; rows without light have none),
 * plus as much again for guides. */
#include "sampler_method.h"

#include "../core/distrib.h"

#include <stdlib.h>

#if defined(__GNUC__) || defined(__clang__)
#define PREFETCH(p) __builtin_prefetch(p)
#else
#define PREFETCH(p) ((void)(p))
#endif

typedef struct inversion {
    lumis__cdf marginal;
    lumis__cdf *rows; /* h conditionals; a row of zero importance has an empty table */
} inversion;

static void inversion_pick(const lumis_sampler *s, double u1, double u2, lumis__pick *p)
{
    const inversion *t = s->data;
    double fy, fx;
    uint32_t j = lumis__cdf_sample(&t->marginal, u2, &fy);
    uint32_t i = lumis__cdf_sample(&t->rows[j], u1, &fx);
    p->x0 = (int)i;
    p->x1 = (int)i + 1;
    p->y0 = (int)j;
    p->y1 = (int)j + 1;
    p->s = fx;
    p->t = fy;
    p->density = lumis__cdf_prob(&t->marginal, j) * lumis__cdf_prob(&t->rows[j], i) /
                 s->env->row_solid_angle[j];
}

/* A batch: the marginal searches (its table is small and stays cached), then the rows'
 * searches one step at a time across the batch, each step prefetching the next lookup of
 * its search, so up to a batch of misses are in flight instead of one. */
static void inversion_pick_n(const lumis_sampler *s, const double *u, int n, lumis__pick *out)
{
    const inversion *t = s->data;
    lumis__cdf_search q[LUMIS__BATCH];
    uint32_t row[LUMIS__BATCH];
    double fy[LUMIS__BATCH];
    uint32_t steps = 0;
    for (int k = 0; k < n; k++) {
        row[k] = lumis__cdf_sample(&t->marginal, u[2 * k + 1], &fy[k]);
        const lumis__cdf *c = &t->rows[row[k]];
        double x = u[2 * k] * LUMIS__ONE32;
        if (c->guide) PREFETCH(c->guide + (uint32_t)(((uint64_t)x * c->n) >> 32));
    }
    for (int k = 0; k < n; k++) {
        const lumis__cdf *c = &t->rows[row[k]];
        q[k] = lumis__cdf_search_start(c, u[2 * k]);
        PREFETCH(lumis__cdf_search_next(c, &q[k]));
        uint32_t len = q[k].len, st = 0;
        while (len > 1) len -= len / 2, st++;
        if (st > steps) steps = st;
    }
    for (uint32_t r = 0; r < steps; r++)
        for (int k = 0; k < n; k++) {
            if (q[k].len <= 1) continue;
            const lumis__cdf *c = &t->rows[row[k]];
            lumis__cdf_search_step(c, &q[k]);
            PREFETCH(lumis__cdf_search_next(c, &q[k]));
        }
    for (int k = 0; k < n; k++) {
        const lumis__cdf *c = &t->rows[row[k]];
        double fx;
        uint32_t i = lumis__cdf_search_end(c, &q[k], &fx);
        uint32_t j = row[k];
        lumis__pick *p = &out[k];
        p->x0 = (int)i;
        p->x1 = (int)i + 1;
        p->y0 = (int)j;
        p->y1 = (int)j + 1;
        p->s = fx;
        p->t = fy[k];
        p->density =
            lumis__cdf_prob(&t->marginal, j) * lumis__cdf_prob(c, i) / s->env->row_solid_angle[j];
    }
}

/* cdf[i] with the implicit cdf[m] = 2^32 (and entries past m, of probability 0, there). */
static uint64_t cdf_at(const lumis__cdf *c, uint32_t i)
{
    return i < c->m ? c->cdf[i] : (uint64_t)1 << 32;
}

/* The u that lumis__cdf_sample maps to entry i at fraction f: the CDF at i plus f of the
 * entry's width.  An entry of probability 0 has width 0: u is where it would start. */
static double cdf_invert(const lumis__cdf *c, uint32_t i, double f)
{
    uint64_t a = cdf_at(c, i), b = cdf_at(c, i + 1);
    double u = ((double)a + f * (double)(b - a)) * (1.0 / LUMIS__ONE32);
    return u < 1.0 ? u : 0x1.fffffffffffffp-1;
}

static void inversion_invert(const lumis_sampler *s, int i, int j, double ps, double pt,
                             double u[2])
{
    const inversion *t = s->data;
    u[1] = cdf_invert(&t->marginal, (uint32_t)j, pt);
    /* A row without light has no conditional table: any u1 lands in another row, and the
     * fraction along the row is as good as any. */
    u[0] = t->rows[j].cdf ? cdf_invert(&t->rows[j], (uint32_t)i, ps) : (i + ps) / s->w;
}

static double inversion_density(const lumis_sampler *s, int i, int j)
{
    const inversion *t = s->data;
    if (!t->rows[j].cdf) return 0.0;
    return lumis__cdf_prob(&t->marginal, (uint32_t)j) * lumis__cdf_prob(&t->rows[j], (uint32_t)i) /
           s->env->row_solid_angle[j];
}

static void inversion_destroy(lumis_sampler *s)
{
    inversion *t = s->data;
    if (!t) return;
    lumis__cdf_free(&t->marginal);
    if (t->rows)
        for (int j = 0; j < s->h; j++) lumis__cdf_free(&t->rows[j]);
    free(t->rows);
    free(t);
}

static const lumis__method inversion_method = {
    inversion_pick, inversion_density, inversion_destroy, 0, inversion_pick_n, inversion_invert};

lumis_status lumis__inversion_init(lumis_sampler *s, const double *imp, int guided)
{
    s->m = &inversion_method;
    inversion *t = calloc(1, sizeof *t);
    s->data = t;
    if (!t) return LUMIS_ERR_OUT_OF_MEMORY;
    t->rows = calloc((size_t)s->h, sizeof *t->rows);
    double *row_sum = malloc((size_t)s->h * sizeof(double));
    lumis_status st = (t->rows && row_sum) ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
    for (int j = 0; j < s->h && st == LUMIS_OK; j++) {
        const double *row = imp + (size_t)j * (size_t)s->w;
        row_sum[j] = 0.0;
        for (int i = 0; i < s->w; i++) row_sum[j] += row[i];
        if (row_sum[j] > 0.0) st = lumis__cdf_build(&t->rows[j], row, (uint32_t)s->w, guided);
    }
    if (st == LUMIS_OK) st = lumis__cdf_build(&t->marginal, row_sum, (uint32_t)s->h, guided);
    free(row_sum);
    if (st != LUMIS_OK) return st;
    /* What was allocated: a CDF (and a guide of n + 1) per row with light, and the
     * marginal. */
    size_t entries = (size_t)s->h + (guided ? (size_t)s->h + 1 : 0);
    for (int j = 0; j < s->h; j++)
        if (t->rows[j].cdf) entries += (size_t)s->w + (guided ? (size_t)s->w + 1 : 0);
    s->table_bytes = 4 * entries;
    s->total_bytes = s->table_bytes + (size_t)s->h * sizeof(lumis__cdf);
    return LUMIS_OK;
}
