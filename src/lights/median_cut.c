/* Median cut (Debevec 2005, "A Median Cut Algorithm for Light Probe Sampling"): regions of
 * equal energy by recursive splits across the longer side, one light at the energy
 * centroid of each.  Formulas and choices: docs/lights.md. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct mc_ctx {
    const lumis__geom *g;
    const double *sat; /* summed-area table of Y Omega */
} mc_ctx;

/* Energy of r's first (c - x0) columns (axis 0) or first (c - y0) rows (axis 1). */
static double prefix(const mc_ctx *m, lumis__rect r, int axis, int c)
{
    if (axis == 0)
        r.x1 = c;
    else
        r.y1 = c;
    return lumis__sat_rect(m->sat, m->g->w, r);
}

/* The boundary position in (lo, hi) whose two sides' energies are closest: the first
 * position where the prefix reaches half the energy, or the one before it. */
static int equal_energy_cut(const mc_ctx *m, lumis__rect r, int axis, int lo, int hi, double e)
{
    int a = lo + 1, b = hi - 1; /* candidates [a, b] */
    if (!(e > 0.0)) return lo + (hi - lo) / 2;
    while (a < b) { /* smallest c in [a, b] with 2 F(c) >= e, or b */
        int mid = a + (b - a) / 2;
        if (2.0 * prefix(m, r, axis, mid) >= e)
            b = mid;
        else
            a = mid + 1;
    }
    int c = a;
    if (c > lo + 1) {
        double dc = fabs(2.0 * prefix(m, r, axis, c) - e);
        double dp = fabs(2.0 * prefix(m, r, axis, c - 1) - e);
        if (dp <= dc) c = c - 1;
    }
    return c;
}

static int mc_split(void *ctx, lumis__rect r, lumis__rect *ra, lumis__rect *rb)
{
    const mc_ctx *m = ctx;
    int nx = r.x1 - r.x0, ny = r.y1 - r.y0;
    if (nx < 2 && ny < 2) return 0;
    double wd, ht;
    lumis__rect_sides(m->g, r, &wd, &ht);
    int axis = (nx >= 2 && (wd >= ht || ny < 2)) ? 0 : 1;
    double e = lumis__sat_rect(m->sat, m->g->w, r);
    *ra = *rb = r;
    if (axis == 0) {
        int c = equal_energy_cut(m, r, 0, r.x0, r.x1, e);
        ra->x1 = rb->x0 = c;
    } else {
        int c = equal_energy_cut(m, r, 1, r.y0, r.y1, e);
        ra->y1 = rb->y0 = c;
    }
    return 1;
}

static double mc_priority(void *ctx, lumis__rect r)
{
    const mc_ctx *m = ctx;
    return lumis__sat_rect(m->sat, m->g->w, r);
}

lumis_status lumis_lights_median_cut(const lumis_envmap *env, const lumis_median_cut_desc *desc,
                                     lumis_light_set **out)
{
    static const lumis_median_cut_desc zero_desc;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!desc) desc = &zero_desc;
    double t0 = lumis__now_ms();
    lumis__common c;
    lumis_status st = lumis__common_check(env, "median cut", desc->count, desc->sets, desc->jitter,
                                          desc->seed, &desc->errors, &c);
    if (st != LUMIS_OK) return st;
    lumis__geom g;
    if (lumis__geom_init(&g, env) != LUMIS_OK)
        return lumis__fail(c.errors, LUMIS_ERR_OUT_OF_MEMORY, "median cut: out of memory");
    size_t satn = ((size_t)g.w + 1) * ((size_t)g.h + 1);
    double *sat = malloc(satn * sizeof(double));
    lumis__rect *rects = malloc((size_t)c.count * sizeof *rects);
    lumis_light_set *set = NULL;
    st = (sat && rects) ? lumis__set_create(env, &c, c.count, LUMIS_LIGHTS_MEDIAN_CUT, 0, &set)
                        : LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) {
        lumis__sat_build(&g, env, sat, NULL, NULL, NULL);
        mc_ctx m = {&g, sat};
        lumis__splitter sp = {mc_split, mc_priority, &m};
        st = lumis__split_rects(&sp, g.w, g.h, c.count, rects);
    }
    if (st == LUMIS_OK) {
        free(sat);
        sat = NULL;
        lumis__lights_from_rects(set, &g, env, rects, c.count);
        lumis__set_finish(set, &g, env, &c, t0);
    }
    free(sat);
    free(rects);
    lumis__geom_free(&g);
    if (st != LUMIS_OK) {
        lumis_light_set_destroy(set);
        return lumis__fail(c.errors, st, "median cut: %s", lumis_status_string(st));
    }
    *out = set;
    return LUMIS_OK;
}
