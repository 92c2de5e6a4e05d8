/* EnvIndirects of Wu's decomposition: a cut through a binary light tree over the
 * non-emissive pixels, refined node by node by the objective of Eq. 3 (the modified
 * illumination cut) or by variance alone (the original cut).
 *
 * The tree is implicit: a node is a pixel rectangle of the map, split across its longer
 * side (in radians) at the middle, and only the nodes the cut reaches are ever built.
 * Node sums come in O(1) from summed-area tables over T x T tiles (T = 4 on large maps,
 * so the tables stay small), splits fall on tile boundaries while a node spans more than
 * one tile, and inside a tile they are summed from the pixels.  Children without a
 * non-emissive pixel are skipped (the other child takes the node's place).
 * docs/lights.md. */
#include "decomp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define Q_E     LUMIS__Q_E
#define Q_MX    LUMIS__Q_MX
#define Q_MY    LUMIS__Q_MY
#define Q_MZ    LUMIS__Q_MZ
#define Q_N     LUMIS__Q_N
#define Q_COUNT LUMIS__Q_COUNT

typedef struct node {
    lumis__rect r;
    double q[Q_COUNT]; /* E = sum Y Omega, M = sum Y m, N = pixels (non-emissive only) */
    double v, d;       /* variance and directional extent */
} node;

typedef struct cut_ctx {
    const lumis__decomp *dc;
    const lumis__geom *g;
    const lumis__tiles *tiles; /* their summed-area tables */
} cut_ctx;

lumis_status lumis__tiles_init(lumis__tiles *t, int w, int h)
{
    memset(t, 0, sizeof *t);
    t->T = (long long)w * h >= 65536 ? 4 : 1;
    t->tw = (w + t->T - 1) / t->T;
    t->th = (h + t->T - 1) / t->T;
    /* Not zeroed (the luminance pass assigns each tile's first row); the summed-area
     * tables' border, row 0 and column 0, is. */
    const size_t W = (size_t)t->tw + 1, n = W * ((size_t)t->th + 1);
    for (int k = 0; k < Q_COUNT + 3; k++) {
        double *a = malloc(n * sizeof(double));
        if (!a) {
            lumis__tiles_free(t);
            return LUMIS_ERR_OUT_OF_MEMORY;
        }
        memset(a, 0, W * sizeof(double));
        for (size_t r = 1; r * W < n; r++) a[r * W] = 0.0;
        if (k < Q_COUNT)
            t->q[k] = a;
        else
            t->rgb[k - Q_COUNT] = a;
    }
    return LUMIS_OK;
}

void lumis__tiles_free(lumis__tiles *t)
{
    for (int k = 0; k < Q_COUNT; k++) {
        free(t->q[k]);
        t->q[k] = NULL;
    }
    for (int k = 0; k < 3; k++) {
        free(t->rgb[k]);
        t->rgb[k] = NULL;
    }
}

int lumis__tiles_aligned(const lumis__tiles *t, int w, int h, lumis__rect r)
{
    const int T = t->T;
    return r.x0 % T == 0 && (r.x1 % T == 0 || r.x1 == w) && r.y0 % T == 0 &&
           (r.y1 % T == 0 || r.y1 == h);
}

lumis__rect lumis__tiles_of(const lumis__tiles *t, lumis__rect r)
{
    lumis__rect q = {r.x0 / t->T, r.y0 / t->T, (r.x1 + t->T - 1) / t->T, (r.y1 + t->T - 1) / t->T};
    return q;
}

void lumis__tiles_prefix(lumis__tiles *t)
{
    /* the five tables in one sweep: five independent chains of additions instead of one */
    const size_t W = (size_t)t->tw + 1;
    for (size_t ty = 1; ty <= (size_t)t->th; ty++) {
        double run[Q_COUNT] = {0.0};
        for (size_t tx = 1; tx <= (size_t)t->tw; tx++)
            for (int k = 0; k < Q_COUNT; k++) {
                double *s = t->q[k];
                run[k] += s[ty * W + tx];
                s[ty * W + tx] = s[(ty - 1) * W + tx] + run[k];
            }
    }
}

static int aligned(const cut_ctx *c, lumis__rect r)
{
    return lumis__tiles_aligned(c->tiles, c->dc->w, c->dc->h, r);
}

static void node_sums(const cut_ctx *c, node *nd)
{
    const lumis__rect r = nd->r;
    if (aligned(c, r)) {
        lumis__rect t = lumis__tiles_of(c->tiles, r);
        for (int k = 0; k < Q_COUNT; k++)
            nd->q[k] = lumis__sat_rect(c->tiles->q[k], c->tiles->tw, t);
        nd->q[Q_N] = round(nd->q[Q_N]); /* integers, exact unless rounding intrudes */
    } else {
        const lumis__decomp *dc = c->dc;
        const lumis__geom *g = c->g;
        memset(nd->q, 0, sizeof nd->q);
        for (int j = r.y0; j < r.y1; j++)
            for (int i = r.x0; i < r.x1; i++) {
                size_t p = (size_t)j * (size_t)dc->w + (size_t)i;
                if (!lumis__non_emissive(dc, p)) continue;
                double v = lumis__pixel_y(dc->env->pixels + 3 * p, g->scale);
                nd->q[Q_E] += v * g->omega[j];
                nd->q[Q_MX] += v * g->a[j] * g->cs[i];
                nd->q[Q_MY] += v * g->b[j];
                nd->q[Q_MZ] += v * g->a[j] * g->cc[i];
                nd->q[Q_N] += 1.0;
            }
    }
    double e = nd->q[Q_E], mx = nd->q[Q_MX], my = nd->q[Q_MY], mz = nd->q[Q_MZ];
    double mm = mx * mx + my * my + mz * mz;
    nd->v = e > 0.0 ? fmax(0.0, e - mm / e) : 0.0;
    double d[3];
    if (mm > 0.0) {
        double l = sqrt(mm);
        d[0] = mx / l;
        d[1] = my / l;
        d[2] = mz / l;
    } else { /* no luminance: the rectangle's middle direction */
        double th = 0.5 * LUMIS_PI * (r.y0 + r.y1) / c->g->h;
        double ph = LUMIS_PI * (r.x0 + r.x1) / c->g->w;
        d[0] = sin(th) * cos(ph);
        d[1] = cos(th);
        d[2] = sin(th) * sin(ph);
    }
    nd->d = acos(lumis__rect_min_dot(c->g, d, r.y0, r.y1, r.x0, r.x1));
}

/* Splits a node with at least two non-emissive pixels into two that each hold some. */
static void node_split(const cut_ctx *c, const node *parent, node *a, node *b)
{
    lumis__rect r = parent->r;
    const int T = c->tiles->T;
    for (;;) {
        int tx0 = r.x0 / T, tx1 = (r.x1 + T - 1) / T, ty0 = r.y0 / T, ty1 = (r.y1 + T - 1) / T;
        int tiles = aligned(c, r) && (tx1 - tx0 > 1 || ty1 - ty0 > 1);
        int nx = tiles ? tx1 - tx0 : r.x1 - r.x0, ny = tiles ? ty1 - ty0 : r.y1 - r.y0;
        double wd, ht;
        lumis__rect_sides(c->g, r, &wd, &ht);
        int axis = (nx >= 2 && (wd >= ht || ny < 2)) ? 0 : 1;
        a->r = b->r = r;
        if (axis == 0) {
            int pos = tiles ? (tx0 + nx / 2) * T : r.x0 + nx / 2;
            a->r.x1 = b->r.x0 = pos;
        } else {
            int pos = tiles ? (ty0 + ny / 2) * T : r.y0 + ny / 2;
            a->r.y1 = b->r.y0 = pos;
        }
        node_sums(c, a);
        node_sums(c, b);
        if (a->q[Q_N] > 0.0 && b->q[Q_N] > 0.0) return;
        r = a->q[Q_N] > 0.0 ? a->r : b->r; /* a child without pixels: descend into the other */
    }
}

/* The cut's nodes under a tournament tree of their maxima (variance, extent, energy; zeros
 * for a node that cannot split), so that the node Eq. 3 picks is found by branch and bound
 * instead of a scan of every node at every split (O(K^2) at K = 4096: 30 ms of Wu's
 * 76 ms on an interior map).  Every term is non-negative, so a subtree's objective bound
 * from its maxima is at least each of its nodes' objective in floating point too, and
 * the search visits subtrees in index order: it returns exactly the node the scan would
 * (the first of the largest). */
typedef struct cut_tree {
    int leaves;  /* a power of two >= the budget */
    double *max; /* 3 per tree node, 1-based heap order: v, d, E */
    int splittable;
} cut_tree;

static void cut_tree_set(cut_tree *t, int k, const node *nd)
{
    const int can = nd->q[Q_N] >= 2.0;
    size_t i = (size_t)t->leaves + (size_t)k;
    double *m = t->max + 3 * i;
    m[0] = can ? nd->v : 0.0;
    m[1] = can ? nd->d : 0.0;
    m[2] = can ? nd->q[Q_E] : 0.0;
    for (i >>= 1; i >= 1; i >>= 1) {
        const double *l = t->max + 6 * i, *r = l + 3;
        double *p = t->max + 3 * i;
        for (int c = 0; c < 3; c++) p[c] = l[c] > r[c] ? l[c] : r[c];
    }
}

typedef struct cut_search {
    const cut_tree *t;
    const node *cut;
    int n, original, best;
    double sv, sd, se, bo;
} cut_search;

static double cut_objective(const cut_search *q, double v, double d, double e)
{
    return q->original ? v : q->sv * v + q->sd * d + q->se * e;
}

static void cut_find(cut_search *q, size_t i, int lo, int width)
{
    if (lo >= q->n) return;
    const double *m = q->t->max + 3 * i;
    /* a subtree whose bound cannot beat the best so far (ties go to the earlier node) */
    if (q->best >= 0 && !(cut_objective(q, m[0], m[1], m[2]) > q->bo)) return;
    if (width == 1) {
        const node *nd = &q->cut[lo];
        if (nd->q[Q_N] < 2.0) return;
        const double o = cut_objective(q, nd->v, nd->d, nd->q[Q_E]);
        if (o > q->bo || q->best < 0) {
            q->bo = o;
            q->best = lo;
        }
        return;
    }
    cut_find(q, 2 * i, lo, width / 2);
    cut_find(q, 2 * i + 1, lo + width / 2, width / 2);
}

lumis_status lumis__illumination_cut(const lumis__decomp *dc, const lumis__tiles *tiles, int budget,
                                     lumis_cut_objective obj, double w_v, double w_d, double w_e,
                                     lumis__rect *rects, int *count)
{
    *count = 0;
    if (budget <= 0) return LUMIS_OK;
    cut_ctx c;
    memset(&c, 0, sizeof c);
    c.dc = dc;
    c.g = dc->g;
    c.tiles = tiles;
    cut_tree t;
    t.leaves = 1;
    while (t.leaves < budget) t.leaves *= 2;
    node *cut = malloc((size_t)budget * sizeof *cut);
    t.max = calloc(6 * (size_t)t.leaves, sizeof(double));
    lumis_status st = cut && t.max ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
    int n = 0;
    if (st == LUMIS_OK) {
        lumis__rect whole = {0, 0, dc->w, dc->h};
        cut[0].r = whole;
        node_sums(&c, &cut[0]);
        if (cut[0].q[Q_N] > 0.0) {
            n = 1;
            cut_tree_set(&t, 0, &cut[0]);
        }
    }
    while (st == LUMIS_OK && n > 0 && n < budget) {
        /* Eq. 3 normalises each term by its maximum over the nodes that can still split
         * (the tree's root; zero when none can) */
        const double mv = t.max[3], md = t.max[4], me = t.max[5];
        cut_search q;
        q.t = &t;
        q.cut = cut;
        q.n = n;
        q.original = obj == LUMIS_CUT_ORIGINAL;
        q.sv = mv > 0.0 ? w_v / mv : 0.0;
        q.sd = md > 0.0 ? w_d / md : 0.0;
        q.se = me > 0.0 ? w_e / me : 0.0;
        q.best = -1;
        q.bo = -INFINITY;
        cut_find(&q, 1, 0, t.leaves);
        if (q.best < 0) break; /* every node is a single pixel */
        node a, b;
        node_split(&c, &cut[q.best], &a, &b);
        cut[q.best] = a;
        cut[n] = b;
        cut_tree_set(&t, q.best, &a);
        cut_tree_set(&t, n, &b);
        n++;
    }
    for (int k = 0; k < n; k++) rects[k] = cut[k].r;
    *count = n;
    free(cut);
    free(t.max);
    return st;
}
