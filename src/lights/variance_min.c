/* Variance minimisation (Viriyothai & Debevec 2009, "Variance Minimization Light Probe
 * Sampling"): recursive splits that minimise the summed energy-weighted directional
 * variance of the two halves, one light at the energy centroid of each region.  The
 * variance of a region is sum E |d - mu|^2 = E - |M|^2 / E with E = sum Y Omega and
 * M = sum Y m (the luminance-weighted first moment), so the marginals of E and M along an
 * axis (from the band sums of strips.c) give the variance of both halves at every cut
 * position in one sweep.  docs/lights.md. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct vm_ctx {
    const lumis__strips *s;
    double *q[4];  /* max(w, h) + 1 each: marginals of E, Mx, My, Mz */
    double *sf[4]; /* their suffix sums */
} vm_ctx;

static double var_of(double e, double x, double y, double z)
{
    if (!(e > 0.0)) return 0.0;
    double v = e - (x * x + y * y + z * z) / e;
    return v > 0.0 ? v : 0.0; /* rounding of nearly one-directional regions */
}

/* The marginals of E and M of r along axis 0 (columns) or 1 (rows) into v->q[0..3];
 * returns their length. */
static int marginals(const vm_ctx *v, lumis__rect r, int axis)
{
    const lumis__geom *g = v->s->g;
    double *e = v->q[0], *mx = v->q[1], *my = v->q[2], *mz = v->q[3];
    if (axis == 0) {
        int n = r.x1 - r.x0;
        lumis__strips_cols(v->s, r, e, mx, my); /* mx <- sum a Y, my <- sum b Y */
        for (int k = 0; k < n; k++) {
            double A = mx[k];
            mx[k] = A * g->cs[r.x0 + k];
            mz[k] = A * g->cc[r.x0 + k];
        }
        return n;
    }
    int n = r.y1 - r.y0;
    lumis__strips_rows(v->s, r, e, mx, mz); /* e <- sum Y, mx <- sum Y cs, mz <- sum Y cc */
    for (int k = 0; k < n; k++) {
        int j = r.y0 + k;
        double y = e[k];
        e[k] = y * g->omega[j];
        my[k] = y * g->b[j];
        mx[k] *= g->a[j];
        mz[k] *= g->a[j];
    }
    return n;
}

/* Variance of the whole of r and its energy. */
static double variance(const vm_ctx *v, lumis__rect r, double *energy)
{
    int n = marginals(v, r, 0);
    double t[4] = {0.0, 0.0, 0.0, 0.0};
    for (int q = 0; q < 4; q++)
        for (int k = 0; k < n; k++) t[q] += v->q[q][k];
    if (energy) *energy = t[0];
    return var_of(t[0], t[1], t[2], t[3]);
}

/* The best cut along one axis: position (relative, in [1, n - 1]) and V(a) + V(b). */
static int best_cut(const vm_ctx *v, int n, double *best)
{
    /* prefix and suffix sums, each side of every cut a direct sum (an empty side is
     * exactly 0, never a difference of totals) */
    for (int q = 0; q < 4; q++) {
        double run = 0.0;
        for (int k = n - 1; k >= 0; k--) v->sf[q][k] = run += v->q[q][k];
    }
    double p[4] = {0.0, 0.0, 0.0, 0.0};
    int pos = -1;
    for (int c = 1; c < n; c++) {
        for (int q = 0; q < 4; q++) p[q] += v->q[q][c - 1];
        double t = var_of(p[0], p[1], p[2], p[3]) +
                   var_of(v->sf[0][c], v->sf[1][c], v->sf[2][c], v->sf[3][c]);
        if (t < *best) {
            *best = t;
            pos = c;
        }
    }
    return pos;
}

static int vm_split(void *ctx, lumis__rect r, lumis__rect *ra, lumis__rect *rb)
{
    const vm_ctx *v = ctx;
    int nx = r.x1 - r.x0, ny = r.y1 - r.y0;
    if (nx < 2 && ny < 2) return 0;
    /* the column marginals give the energy and serve the column cuts below */
    const int ncol = marginals(v, r, 0);
    double e = 0.0;
    for (int k = 0; k < ncol; k++) e += v->q[0][k];
    *ra = *rb = r;
    if (!(e > 0.0)) { /* nothing to weigh: halve the longer side */
        double wd, ht;
        lumis__rect_sides(v->s->g, r, &wd, &ht);
        if (nx >= 2 && (wd >= ht || ny < 2))
            ra->x1 = rb->x0 = r.x0 + nx / 2;
        else
            ra->y1 = rb->y0 = r.y0 + ny / 2;
        return 1;
    }
    double best = INFINITY;
    int best_axis = -1, best_pos = 0;
    if (nx >= 2) {
        int c = best_cut(v, ncol, &best);
        if (c > 0) {
            best_axis = 0;
            best_pos = r.x0 + c;
        }
    }
    if (ny >= 2) {
        int c = best_cut(v, marginals(v, r, 1), &best);
        if (c > 0) {
            best_axis = 1;
            best_pos = r.y0 + c;
        }
    }
    if (best_axis < 0) { /* NaN everywhere cannot happen with finite pixels; stay safe */
        best_axis = nx >= 2 ? 0 : 1;
        best_pos = best_axis == 0 ? r.x0 + nx / 2 : r.y0 + ny / 2;
    }
    if (best_axis == 0)
        ra->x1 = rb->x0 = best_pos;
    else
        ra->y1 = rb->y0 = best_pos;
    return 1;
}

static double vm_priority(void *ctx, lumis__rect r)
{
    return variance(ctx, r, NULL);
}

lumis_status lumis_lights_variance_min(const lumis_envmap *env, const lumis_variance_min_desc *desc,
                                       lumis_light_set **out)
{
    static const lumis_variance_min_desc zero_desc;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!desc) desc = &zero_desc;
    double t0 = lumis__now_ms();
    lumis__common c;
    lumis_status st = lumis__common_check(env, "variance minimisation", desc->count, desc->sets,
                                          desc->jitter, desc->seed, &desc->errors, &c);
    if (st != LUMIS_OK) return st;
    lumis__geom g;
    if (lumis__geom_init(&g, env) != LUMIS_OK)
        return lumis__fail(c.errors, LUMIS_ERR_OUT_OF_MEMORY,
                           "variance minimisation: out of memory");
    lumis__strips strips;
    memset(&strips, 0, sizeof strips);
    const size_t len = (size_t)(g.w > g.h ? g.w : g.h) + 1;
    double *qmem = malloc(8 * len * sizeof(double));
    lumis__rect *rects = malloc((size_t)c.count * sizeof *rects);
    lumis_light_set *set = NULL;
    st = (qmem && rects) ? lumis__strips_init(&strips, &g, env, 1) : LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK)
        st = lumis__set_create(env, &c, c.count, LUMIS_LIGHTS_VARIANCE_MIN, 0, &set);
    if (st == LUMIS_OK) {
        vm_ctx v = {&strips,
                    {qmem, qmem + len, qmem + 2 * len, qmem + 3 * len},
                    {qmem + 4 * len, qmem + 5 * len, qmem + 6 * len, qmem + 7 * len}};
        lumis__splitter sp = {vm_split, vm_priority, &v};
        st = lumis__split_rects(&sp, g.w, g.h, c.count, rects);
    }
    if (st == LUMIS_OK) {
        lumis__lights_from_strips(set, &strips, rects, c.count);
        lumis__set_finish(set, &g, env, &c, t0);
    }
    lumis__strips_free(&strips);
    free(qmem);
    free(rects);
    lumis__geom_free(&g);
    if (st != LUMIS_OK) {
        lumis_light_set_destroy(set);
        return lumis__fail(c.errors, st, "variance minimisation: %s", lumis_status_string(st));
    }
    *out = set;
    return LUMIS_OK;
}
