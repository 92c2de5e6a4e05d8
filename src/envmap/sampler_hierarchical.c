/* Hierarchical sample warping (Clarberg et al. 2005; Falcor's EnvMapSampler) down a
 * pyramid of importance sums built over the map's own pixels: each level halves the
 * width and the height (rounding up), so any size works without resampling the map.
 * At each level u1 chooses the left or right half of a 2 x 2 block and u2 the upper or
 * lower pixel of that column; each is then rescaled to [0, 1) and passed down, so the
 * warp is continuous like inversion.  The probability of a pixel is the product of the
 * ratios chosen on the way, which pdf() recomputes with the same arithmetic.
 *
 * Cost per sample: O(log max(w, h)) levels, four lookups each (one cache line or two).
 * Tables: 8 bytes per pixel and about a third more for the coarser levels.
 * Precision: the ratios are doubles, so a pixel with less than 2^-53 of its 2 x 2 block's
 * weight is drawn with probability 0 - and pdf() reports 0 for it too. */
#include "sampler_method.h"

#include <stdlib.h>

typedef struct level {
    int w, h;
    double *v; /* w * h sums, row-major (double: a float loses faint pixels beside a sun) */
} level;

typedef struct pyramid {
    int count; /* levels[0] is 1 x 1, levels[count - 1] the map */
    level *levels;
} pyramid;

static double at(const level *l, int x, int y)
{
    return (x < l->w && y < l->h) ? l->v[(size_t)y * (size_t)l->w + (size_t)x] : 0.0;
}

/* Probabilities of the left column and, within each column, of the upper pixel of the
 * 2 x 2 block whose top-left child is (x, y) on level l. */
static void split(const level *l, int x, int y, double *p_left, double *p_top_left,
                  double *p_top_right)
{
    double a = at(l, x, y), b = at(l, x + 1, y), c = at(l, x, y + 1), d = at(l, x + 1, y + 1);
    double left = a + c, right = b + d;
    /* An all-zero block is never entered (its parent had probability 0): any split will
     * do, as long as it is not 0/0. */
    *p_left = left + right > 0.0 ? left / (left + right) : 0.5;
    *p_top_left = left > 0.0 ? a / left : 0.0;
    *p_top_right = right > 0.0 ? b / right : 0.0;
}

/* One level down: (x, y) becomes a child of the 2 x 2 block under it.  The choices are
 * coin flips on the data, so they are selects, not branches (a mispredicted branch would
 * discard the work queued behind it); the arithmetic is what pdf() repeats. */
static inline void hier_step(const level *l, int *x, int *y, double *u1, double *u2, double *prob)
{
    double pl, ptl, ptr;
    split(l, 2 * *x, 2 * *y, &pl, &ptl, &ptr);
    int right = !(*u1 < pl);
    double pc = right ? 1.0 - pl : pl;
    *u1 = (right ? *u1 - pl : *u1) / pc;
    double pt = right ? ptr : ptl;
    int down = !(*u2 < pt);
    double pr = down ? 1.0 - pt : pt;
    *u2 = (down ? *u2 - pt : *u2) / pr;
    *prob *= pc;
    *prob *= pr;
    *x = 2 * *x + right;
    *y = 2 * *y + down;
    if (*u1 >= 1.0) *u1 = 0x1.fffffffffffffp-1;
    if (*u2 >= 1.0) *u2 = 0x1.fffffffffffffp-1;
}

static void fill(const lumis_sampler *s, int x, int y, double u1, double u2, double prob,
                 lumis__pick *p)
{
    p->x0 = x;
    p->x1 = x + 1;
    p->y0 = y;
    p->y1 = y + 1;
    p->s = u1;
    p->t = u2;
    p->density = prob / s->env->row_solid_angle[y];
}

/* One sample alone: branches, whose prediction starts the next level's reads before the
 * comparison resolves; measured faster here than selects, even prefetched (for a batch,
 * hier_step interleaves instead).  The same arithmetic as hier_step. */
static void hier_pick(const lumis_sampler *s, double u1, double u2, lumis__pick *p)
{
    const pyramid *py = s->data;
    int x = 0, y = 0;
    double prob = 1.0;
    for (int k = 1; k < py->count; k++) {
        double pl, ptl, ptr;
        split(&py->levels[k], 2 * x, 2 * y, &pl, &ptl, &ptr);
        x *= 2;
        y *= 2;
        double pc, pt, pr;
        if (u1 < pl) {
            pc = pl;
            u1 = u1 / pc;
            pt = ptl;
        } else {
            pc = 1.0 - pl;
            u1 = (u1 - pl) / pc;
            pt = ptr;
            x++;
        }
        if (u2 < pt) {
            pr = pt;
            u2 = u2 / pr;
        } else {
            pr = 1.0 - pt;
            u2 = (u2 - pt) / pr;
            y++;
        }
        prob *= pc;
        prob *= pr;
        if (u1 >= 1.0) u1 = 0x1.fffffffffffffp-1;
        if (u2 >= 1.0) u2 = 0x1.fffffffffffffp-1;
    }
    fill(s, x, y, u1, u2, prob, p);
}

/* A batch descends level by level, all samples at once, each prefetching the block it
 * reads on the next level: a batch of lookups in flight instead of one chain. */
static void hier_pick_n(const lumis_sampler *s, const double *u, int n, lumis__pick *out)
{
    const pyramid *py = s->data;
    int x[LUMIS__BATCH], y[LUMIS__BATCH];
    double u1[LUMIS__BATCH], u2[LUMIS__BATCH], prob[LUMIS__BATCH];
    for (int k = 0; k < n; k++) {
        x[k] = y[k] = 0;
        u1[k] = u[2 * k];
        u2[k] = u[2 * k + 1];
        prob[k] = 1.0;
    }
    for (int lv = 1; lv < py->count; lv++) {
        const level *l = &py->levels[lv], *next = lv + 1 < py->count ? l + 1 : NULL;
        for (int k = 0; k < n; k++) {
            hier_step(l, &x[k], &y[k], &u1[k], &u2[k], &prob[k]);
#if defined(__GNUC__) || defined(__clang__)
            if (next) {
                /* The next block's two rows (at() keeps reads inside the level). */
                int nx = 2 * x[k] < next->w ? 2 * x[k] : next->w - 1;
                int ny = 2 * y[k] < next->h ? 2 * y[k] : next->h - 1;
                const double *r0 = next->v + (size_t)ny * (size_t)next->w + (size_t)nx;
                __builtin_prefetch(r0);
                if (ny + 1 < next->h) __builtin_prefetch(r0 + next->w);
            }
#endif
        }
    }
    for (int k = 0; k < n; k++) fill(s, x[k], y[k], u1[k], u2[k], prob[k], &out[k]);
}

/* Up the pyramid, undoing hier_step level by level: a child chosen with probability p
 * from the part [a, a + p) of [0, 1) maps u' back to a + u' p.  The same split()
 * arithmetic as sampling.  A pixel of probability 0 gets the point where its empty
 * part of [0, 1) sits (u' p = 0 there). */
static void hier_invert(const lumis_sampler *s, int i, int j, double ps, double pt, double u[2])
{
    const pyramid *py = s->data;
    double u1 = ps, u2 = pt;
    for (int k = py->count - 1; k >= 1; k--) {
        int shift = py->count - 1 - k;
        int cx = i >> shift, cy = j >> shift;
        double pl, ptl, ptr;
        split(&py->levels[k], cx & ~1, cy & ~1, &pl, &ptl, &ptr);
        double ptop = (cx & 1) ? ptr : ptl;
        u2 = (cy & 1) ? ptop + u2 * (1.0 - ptop) : u2 * ptop;
        u1 = (cx & 1) ? pl + u1 * (1.0 - pl) : u1 * pl;
        if (u1 >= 1.0) u1 = 0x1.fffffffffffffp-1;
        if (u2 >= 1.0) u2 = 0x1.fffffffffffffp-1;
    }
    u[0] = u1;
    u[1] = u2;
}

static double hier_density(const lumis_sampler *s, int i, int j)
{
    const pyramid *py = s->data;
    double prob = 1.0;
    for (int k = 1; k < py->count; k++) {
        int shift = py->count - 1 - k; /* pixel (i, j) lies under (i >> shift, j >> shift) */
        int cx = i >> shift, cy = j >> shift;
        double pl, ptl, ptr;
        split(&py->levels[k], cx & ~1, cy & ~1, &pl, &ptl, &ptr);
        prob *= (cx & 1) ? 1.0 - pl : pl;
        double pt = (cx & 1) ? ptr : ptl;
        prob *= (cy & 1) ? 1.0 - pt : pt;
    }
    return prob / s->env->row_solid_angle[j];
}

static void hier_destroy(lumis_sampler *s)
{
    pyramid *py = s->data;
    if (!py) return;
    for (int k = 0; k < py->count && py->levels; k++) free(py->levels[k].v);
    free(py->levels);
    free(py);
}

static const lumis__method hier_method = {hier_pick, hier_density, hier_destroy,
                                          0,         hier_pick_n,  hier_invert};

lumis_status lumis__hierarchical_init(lumis_sampler *s, const double *imp)
{
    s->m = &hier_method;
    pyramid *py = calloc(1, sizeof *py);
    s->data = py;
    if (!py) return LUMIS_ERR_OUT_OF_MEMORY;
    /* Levels: the map, then halved (rounding up) until 1 x 1.  Pixel (i, j) of the map
     * lies under (i >> k, j >> k) on the level k steps up, as hier_density assumes. */
    int count = 1;
    for (int w = s->w, h = s->h; w > 1 || h > 1; count++) {
        w = (w + 1) / 2;
        h = (h + 1) / 2;
    }
    py->count = count;
    py->levels = calloc((size_t)count, sizeof(level));
    if (!py->levels) return LUMIS_ERR_OUT_OF_MEMORY;
    size_t bytes = 0;
    for (int k = count - 1, w = s->w, h = s->h; k >= 0; k--) {
        level *l = &py->levels[k];
        l->w = w;
        l->h = h;
        l->v = malloc((size_t)w * (size_t)h * sizeof(double));
        if (!l->v) return LUMIS_ERR_OUT_OF_MEMORY;
        bytes += (size_t)w * (size_t)h * sizeof(double);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                double v;
                if (k == count - 1) {
                    v = imp[(size_t)y * (size_t)w + (size_t)x];
                } else {
                    const level *f = &py->levels[k + 1];
                    v = at(f, 2 * x, 2 * y) + at(f, 2 * x + 1, 2 * y) + at(f, 2 * x, 2 * y + 1) +
                        at(f, 2 * x + 1, 2 * y + 1);
                }
                l->v[(size_t)y * (size_t)w + (size_t)x] = v;
            }
        w = (w + 1) / 2;
        h = (h + 1) / 2;
    }
    s->table_bytes = bytes;
    s->total_bytes = bytes + (size_t)count * sizeof(level);
    return LUMIS_OK;
}
