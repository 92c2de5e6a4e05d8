/* Median cut (Debevec 2005, "A Median Cut Algorithm for Light Probe Sampling"): regions of
 * equal energy by recursive splits across the longer side, one light at the energy
 * centroid of each.  Formulas and choices: docs/lights.md. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct mc_ctx {
    const lumis__strips *s;
    double *marg; /* max(w, h) doubles: the marginal being cut */
} mc_ctx;

/* Energy marginal of r along axis 0 (per column) or 1 (per row) into m->marg; returns
 * the number of entries. */
static int marginal(const mc_ctx *m, lumis__rect r, int axis)
{
    if (axis == 0) {
        lumis__strips_cols(m->s, r, m->marg, NULL, NULL);
        return r.x1 - r.x0;
    }
    lumis__strips_rows(m->s, r, m->marg, NULL, NULL);
    for (int j = r.y0; j < r.y1; j++) m->marg[j - r.y0] *= m->s->g->omega[j];
    return r.y1 - r.y0;
}

/* The boundary position in (0, n) whose two sides' energies are closest: the first
 * position where the prefix reaches half the energy, or the one before it. */
static int equal_energy_cut(const double *marg, int n)
{
    double e = 0.0;
    for (int k = 0; k < n; k++) e += marg[k];
    if (!(e > 0.0)) return n / 2;
    /* the smallest c in [1, n - 1] with 2 F(c) >= e (F(c) the energy of the first c
     * entries), or n - 1; then c - 1 if that is at least as close */
    double prev = 0.0, f = 0.0;
    int c = 0;
    while (c < n - 1) {
        prev = f;
        f += marg[c++];
        if (2.0 * f >= e) break;
    }
    if (c > 1 && fabs(2.0 * prev - e) <= fabs(2.0 * f - e)) c--;
    return c;
}

static int mc_split(void *ctx, lumis__rect r, lumis__rect *ra, lumis__rect *rb)
{
    const mc_ctx *m = ctx;
    int nx = r.x1 - r.x0, ny = r.y1 - r.y0;
    if (nx < 2 && ny < 2) return 0;
    double wd, ht;
    lumis__rect_sides(m->s->g, r, &wd, &ht);
    int axis = (nx >= 2 && (wd >= ht || ny < 2)) ? 0 : 1;
    int n = marginal(m, r, axis), c = equal_energy_cut(m->marg, n);
    *ra = *rb = r;
    if (axis == 0)
        ra->x1 = rb->x0 = r.x0 + c;
    else
        ra->y1 = rb->y0 = r.y0 + c;
    return 1;
}

static double mc_priority(void *ctx, lumis__rect r)
{
    const mc_ctx *m = ctx;
    int n = marginal(m, r, 0);
    double e = 0.0;
    for (int k = 0; k < n; k++) e += m->marg[k];
    return e;
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
    lumis__strips strips;
    memset(&strips, 0, sizeof strips);
    const size_t len = (size_t)(g.w > g.h ? g.w : g.h);
    double *marg = malloc(len * sizeof(double));
    lumis__rect *rects = malloc((size_t)c.count * sizeof *rects);
    lumis_light_set *set = NULL;
    st = (marg && rects) ? lumis__strips_init(&strips, &g, env, 0) : LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) st = lumis__set_create(env, &c, c.count, LUMIS_LIGHTS_MEDIAN_CUT, 0, &set);
    if (st == LUMIS_OK) {
        mc_ctx m = {&strips, marg};
        lumis__splitter sp = {mc_split, mc_priority, &m};
        st = lumis__split_rects(&sp, g.w, g.h, c.count, rects);
    }
    if (st == LUMIS_OK) {
        lumis__lights_from_strips(set, &strips, rects, c.count);
        lumis__set_finish(set, &g, env, &c, t0);
    }
    lumis__strips_free(&strips);
    free(marg);
    free(rects);
    lumis__geom_free(&g);
    if (st != LUMIS_OK) {
        lumis_light_set_destroy(set);
        return lumis__fail(c.errors, st, "median cut: %s", lumis_status_string(st));
    }
    *out = set;
    return LUMIS_OK;
}
