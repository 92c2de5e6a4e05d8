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
 * Precision: sums are doubles, so a pixel with less than about 2^-53 of its 2 x 2 block's
 * weight may never be drawn, while pdf() reports its share of the map (a bias below
 * 2^-53 of the estimate). */
#include "sampler_method.h"

#include <stdlib.h>

typedef struct level {
    int w, h;
    double *v; /* w * h sums, row-major (double: a float loses faint pixels beside a sun) */
} level;

typedef struct pyramid {
    int count; /* levels[0] is 1 x 1, levels[count - 1] the map */
    level *levels;
    double inv_total; /* 1 / the map's sum (levels[0]) */
} pyramid;

static double at(const level *l, int x, int y)
{
    return (x < l->w && y < l->h) ? l->v[(size_t)y * (size_t)l->w + (size_t)x] : 0.0;
}

/* The four sums of the 2 x 2 block whose top-left child is (x, y) on level l. */
static inline void block(const level *l, int x, int y, double q[4])
{
    q[0] = at(l, x, y);
    q[1] = at(l, x + 1, y);
    q[2] = at(l, x, y + 1);
    q[3] = at(l, x + 1, y + 1);
}

static inline double below_one(double u)
{
    return u < 1.0 ? u : 0x1.fffffffffffffp-1;
}

/* One level down: u1 chooses the column of the block (x, y) lies over, in proportion to
 * its sum, and u2 the pixel within it; each is then rescaled to [0, 1) in its part.  The
 * choices compare u against unnormalised sums (u T < L, not u < L / T): two divisions a
 * level, for the rescaling, instead of five.  A side holding nothing is never chosen,
 * whatever the rounding: for u < 1 and T > 0 the rounded u T is below T (u <= 1 - 2^-53),
 * so with R = 0 (T = L) u T < L, and with L = 0 the right side is taken.  The probability of the
 * pixel reached is its sum over the root's (the ratios of every level telescope), which is what
 * pdf() computes too.  The choices are selects, not branches: in a batch a mispredicted branch
 * would discard the work queued behind it. */
static inline void hier_step(const level *l, int *x, int *y, double *u1, double *u2)
{
    double q[4];
    block(l, 2 * *x, 2 * *y, q);
    const double L = q[0] + q[2], R = q[1] + q[3], m1 = *u1 * (L + R);
    const int right = !(m1 < L);
    const double col = right ? R : L, top = right ? q[1] : q[0], bot = right ? q[3] : q[2];
    *u1 = below_one(right ? (m1 - L) / R : m1 / L);
    const double m2 = *u2 * col;
    const int down = !(m2 < top);
    *u2 = below_one(down ? (m2 - top) / bot : m2 / top);
    *x = 2 * *x + right;
    *y = 2 * *y + down;
}

static void fill(const lumis_sampler *s, int x, int y, double u1, double u2, lumis__pick *p)
{
    const pyramid *py = s->data;
    p->x0 = x;
    p->x1 = x + 1;
    p->y0 = y;
    p->y1 = y + 1;
    p->s = u1;
    p->t = u2;
    p->density = at(&py->levels[py->count - 1], x, y) * py->inv_total / s->env->row_solid_angle[y];
}

/* One sample alone: the same arithmetic as hier_step, with branches, whose prediction starts
 * the next level's reads before the comparison resolves (measured faster here than
 * selects, even prefetched; a batch interleaves instead). */
static void hier_pick(const lumis_sampler *s, double u1, double u2, lumis__pick *p)
{
    const pyramid *py = s->data;
    int x = 0, y = 0;
    for (int k = 1; k < py->count; k++) {
        double q[4];
        block(&py->levels[k], 2 * x, 2 * y, q);
        x *= 2;
        y *= 2;
        const double L = q[0] + q[2], R = q[1] + q[3], m1 = u1 * (L + R);
        double top, bot;
        if (!(m1 < L)) {
            u1 = (m1 - L) / R;
            top = q[1];
            bot = q[3];
            x++;
        } else {
            u1 = m1 / L;
            top = q[0];
            bot = q[2];
        }
        const double m2 = u2 * (top + bot);
        if (!(m2 < top)) {
            u2 = (m2 - top) / bot;
            y++;
        } else {
            u2 = m2 / top;
        }
        u1 = below_one(u1);
        u2 = below_one(u2);
    }
    fill(s, x, y, u1, u2, p);
}

/* A batch descends level by level, all samples at once, each prefetching the block it
 * reads on the next level: a batch of lookups in flight instead of one chain. */
static void hier_pick_n(const lumis_sampler *s, const double *u, int n, lumis__pick *out)
{
    const pyramid *py = s->data;
    int x[LUMIS__BATCH], y[LUMIS__BATCH];
    double u1[LUMIS__BATCH], u2[LUMIS__BATCH];
    for (int k = 0; k < n; k++) {
        x[k] = y[k] = 0;
        u1[k] = u[2 * k];
        u2[k] = u[2 * k + 1];
    }
    for (int lv = 1; lv < py->count; lv++) {
        const level *l = &py->levels[lv], *next = lv + 1 < py->count ? l + 1 : NULL;
        for (int k = 0; k < n; k++) {
            hier_step(l, &x[k], &y[k], &u1[k], &u2[k]);
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
    for (int k = 0; k < n; k++) fill(s, x[k], y[k], u1[k], u2[k], &out[k]);
}

/* Up the pyramid, undoing hier_step level by level: a child chosen from the part
 * [A, A + P) of [0, T) (sums, A what lies before it) maps u' back to (A + u' P) / T.  A
 * pixel holding nothing gets the point where its empty part of [0, 1) sits. */
static void hier_invert(const lumis_sampler *s, int i, int j, double ps, double pt, double u[2])
{
    const pyramid *py = s->data;
    double u1 = ps, u2 = pt;
    for (int k = py->count - 1; k >= 1; k--) {
        int shift = py->count - 1 - k;
        int cx = i >> shift, cy = j >> shift;
        double q[4];
        block(&py->levels[k], cx & ~1, cy & ~1, q);
        const double L = q[0] + q[2], R = q[1] + q[3];
        const double top = (cx & 1) ? q[1] : q[0], bot = (cx & 1) ? q[3] : q[2];
        const double col = top + bot;
        if (col > 0.0) u2 = below_one((cy & 1) ? (top + u2 * bot) / col : u2 * top / col);
        if (L + R > 0.0) u1 = below_one((cx & 1) ? (L + u1 * R) / (L + R) : u1 * L / (L + R));
    }
    u[0] = u1;
    u[1] = u2;
}

static double hier_density(const lumis_sampler *s, int i, int j)
{
    const pyramid *py = s->data;
    return at(&py->levels[py->count - 1], i, j) * py->inv_total / s->env->row_solid_angle[j];
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
    py->inv_total = 1.0 / py->levels[0].v[0];
    s->table_bytes = bytes;
    s->total_bytes = bytes + (size_t)count * sizeof(level);
    return LUMIS_OK;
}
