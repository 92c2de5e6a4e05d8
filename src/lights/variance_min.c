/* Variance minimisation (Viriyothai & Debevec 2009, "Variance Minimization Light Probe
 * Sampling"): recursive splits that minimise the summed energy-weighted directional
 * variance of the two halves, one light at the energy centroid of each region.  The
 * variance of a region is sum E |d - mu|^2 = E - |M|^2 / E with E = sum Y Omega and
 * M = sum Y m (the luminance-weighted first moment), so four summed-area tables give it
 * for any rectangle in O(1).  docs/lights.md. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct vm_ctx {
    const lumis__geom *g;
    const double *e, *mx, *my, *mz;
} vm_ctx;

static double variance(const vm_ctx *v, lumis__rect r, double *energy)
{
    int w = v->g->w;
    double e = lumis__sat_rect(v->e, w, r);
    if (energy) *energy = e;
    if (!(e > 0.0)) return 0.0;
    double x = lumis__sat_rect(v->mx, w, r), y = lumis__sat_rect(v->my, w, r),
           z = lumis__sat_rect(v->mz, w, r);
    double var = e - (x * x + y * y + z * z) / e;
    return var > 0.0 ? var : 0.0; /* rounding of nearly one-directional regions */
}

static int vm_split(void *ctx, lumis__rect r, lumis__rect *ra, lumis__rect *rb)
{
    const vm_ctx *v = ctx;
    int nx = r.x1 - r.x0, ny = r.y1 - r.y0;
    if (nx < 2 && ny < 2) return 0;
    double e;
    variance(v, r, &e);
    *ra = *rb = r;
    if (!(e > 0.0)) { /* nothing to weigh: halve the longer side */
        double wd, ht;
        lumis__rect_sides(v->g, r, &wd, &ht);
        if (nx >= 2 && (wd >= ht || ny < 2))
            ra->x1 = rb->x0 = r.x0 + nx / 2;
        else
            ra->y1 = rb->y0 = r.y0 + ny / 2;
        return 1;
    }
    double best = INFINITY;
    int best_axis = -1, best_pos = 0;
    for (int c = r.x0 + 1; c < r.x1; c++) {
        lumis__rect a = r, b = r;
        a.x1 = b.x0 = c;
        double t = variance(v, a, NULL) + variance(v, b, NULL);
        if (t < best) {
            best = t;
            best_axis = 0;
            best_pos = c;
        }
    }
    for (int c = r.y0 + 1; c < r.y1; c++) {
        lumis__rect a = r, b = r;
        a.y1 = b.y0 = c;
        double t = variance(v, a, NULL) + variance(v, b, NULL);
        if (t < best) {
            best = t;
            best_axis = 1;
            best_pos = c;
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
    size_t satn = ((size_t)g.w + 1) * ((size_t)g.h + 1);
    /* Four separate tables rather than one interleaved: each stays below glibc's largest
     * mmap threshold at 2048 x 1024, so repeated builds reuse heap memory. */
    double *sat[4];
    for (int k = 0; k < 4; k++) sat[k] = malloc(satn * sizeof(double));
    lumis__rect *rects = malloc((size_t)c.count * sizeof *rects);
    lumis_light_set *set = NULL;
    st = (sat[0] && sat[1] && sat[2] && sat[3] && rects)
             ? lumis__set_create(env, &c, c.count, LUMIS_LIGHTS_VARIANCE_MIN, 0, &set)
             : LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) {
        lumis__sat_build(&g, env, sat[0], sat[1], sat[2], sat[3]);
        vm_ctx v = {&g, sat[0], sat[1], sat[2], sat[3]};
        lumis__splitter sp = {vm_split, vm_priority, &v};
        st = lumis__split_rects(&sp, g.w, g.h, c.count, rects);
    }
    for (int k = 0; k < 4; k++) free(sat[k]);
    if (st == LUMIS_OK) {
        lumis__lights_from_rects(set, &g, env, rects, c.count);
        lumis__set_finish(set, &g, env, &c, t0);
    }
    free(rects);
    lumis__geom_free(&g);
    if (st != LUMIS_OK) {
        lumis_light_set_destroy(set);
        return lumis__fail(c.errors, st, "variance minimisation: %s", lumis_status_string(st));
    }
    *out = set;
    return LUMIS_OK;
}
