/* Kd-tree importance sampling after Ergun, Kurt and Ozturk, "Real-time Kd-tree Based
 * Importance Sampling of Environment Maps" (SCCG 2012), and the exact variant.
 *
 * Build (Algorithms 1-3): start from the whole map as one block; repeatedly split the
 * block of largest SSE (Eq. 1-2) at the position, on either axis, that maximises
 * lSum^2/lSize + rSum^2/rSize (Eq. 3).  Sums come from summed-area tables, so a split
 * costs O(w_b + h_b), and blocks wait in a max-heap keyed by SSE: n blocks cost
 * O(n log n + sum of (w_b + h_b)).  "Size" is solid angle and "Sum" importance (Y Omega),
 * so the SSE measures how far the block's radiance is from constant - the solid-angle-
 * weighted form of the paper's equations, which reduces to them for equal pixels.  (The
 * tables hold absolute prefix sums in double: beside a very bright sun the SSE of a faint
 * block can drown in their rounding, which may change where it is split, never what is
 * sampled: block probabilities are summed pixel by pixel.)
 * Blocks are sorted by probability, descending, and the analytic pdf of Eq. 4,
 *     p(x) = 1 / (log(1 + n/alpha) (alpha + x)),  x in [0, n),
 * is fitted to them by minimising the L1 distance between the blocks' probabilities and
 * the model's, P(i+1) - P(i) with P(x) = log(1 + x/alpha) / log(1 + n/alpha).
 *
 * Sampling (Eq. 8): x = alpha ((1 + n/alpha)^u1 - 1) names block floor(x) in O(1): one
 * lookup of its bounds.  The point inside is uniform in solid angle, placed by what is
 * left of u1 (rescaled to [0, 1) by the model's CDF) and by u2, so the density is exactly
 * (P(i+1) - P(i)) / Omega_block.  The paper's literal variant places it uniformly in
 * azimuth and elevation instead; its density carries the Jacobian 1 / sin(theta).
 * kdtree-exact draws blocks with their true probabilities through an alias table.
 * pdf() finds a direction's block by descending the kd-tree.
 *
 * Tables: 8 bytes per block (16-bit bounds) plus alpha and log(1 + n/alpha) (16 bytes)
 * for sampling; the tree for pdf()
 * adds 8 bytes per node (2n - 1 nodes).  Derivation: docs/samplers.md. */
#include "sampler_method.h"

#include "../core/distrib.h"
#include "../core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_BLOCKS 6144

typedef struct block {
    uint16_t x0, y0, x1, y1; /* pixels [x0, x1) x [y0, y1) */
} block;

typedef struct node {
    uint32_t index; /* leaf: the block's rank; inner: the first of two adjacent children */
    uint16_t pos;   /* inner: split position (pixel column or row) */
    uint8_t axis;   /* 0: split in x, 1: split in y, 2: leaf */
    uint8_t pad;
} node;

typedef struct kdtree {
    block *blocks; /* sorted by probability, descending */
    int n;
    double alpha, log_span; /* log_span = log(1 + n / alpha) */
    node *nodes;
    int node_count;
    lumis__alias exact; /* kdtree-exact only */
} kdtree;

/* ---- the analytic model (Eq. 4, 8) -------------------------------------------------- */

/* P(i+1) - P(i) = log((alpha + i + 1) / (alpha + i)) / log(1 + n / alpha). */
static double model_prob(double alpha, double log_span, int i)
{
    return log1p(1.0 / (alpha + i)) / log_span;
}

/* The L1 objective: sum over blocks of |p_i - (P(i+1) - P(i))|. */
double lumis__kdtree_objective(const double *p, int n, double alpha)
{
    double span = log1p(n / alpha), e = 0.0;
    for (int i = 0; i < n; i++) e += fabs(p[i] - model_prob(alpha, span, i));
    return e;
}

/* Minimises the objective over alpha > 0.  It is one-dimensional and, being an L1 norm,
 * has kinks where Levenberg-Marquardt (the paper's choice, from cminpack) assumes
 * smoothness; a log-spaced scan brackets the best alpha and golden-section search, which
 * needs no derivatives, refines it within the bracket. */
double lumis__kdtree_fit_alpha(const double *p, int n)
{
    if (n <= 1) return 1.0; /* one block: every alpha gives it probability 1 */
    enum { SCAN = 96 };
    const double lo_log = log(1e-6), hi_log = log(1e6 * n);
    double best = 0.0, best_e = INFINITY;
    int best_k = 0;
    for (int k = 0; k < SCAN; k++) {
        double a = exp(lo_log + (hi_log - lo_log) * k / (SCAN - 1));
        double e = lumis__kdtree_objective(p, n, a);
        if (e < best_e) {
            best_e = e;
            best = a;
            best_k = k;
        }
    }
    double step = (hi_log - lo_log) / (SCAN - 1);
    double a = log(best) - step, b = log(best) + step;
    if (best_k == 0) a = log(best);
    if (best_k == SCAN - 1) b = log(best);
    const double g = 0.6180339887498949;
    double c = b - g * (b - a), d = a + g * (b - a);
    double ec = lumis__kdtree_objective(p, n, exp(c)), ed = lumis__kdtree_objective(p, n, exp(d));
    for (int it = 0; it < 60 && b - a > 1e-10; it++) {
        if (ec < ed) {
            b = d;
            d = c;
            ed = ec;
            c = b - g * (b - a);
            ec = lumis__kdtree_objective(p, n, exp(c));
        } else {
            a = c;
            c = d;
            ec = ed;
            d = a + g * (b - a);
            ed = lumis__kdtree_objective(p, n, exp(d));
        }
    }
    double refined = ec < ed ? exp(c) : exp(d);
    return fmin(ec, ed) <= best_e ? refined : best;
}

/* ---- sampling ----------------------------------------------------------------------- */

static double block_omega(const lumis_sampler *s, const block *b)
{
    return lumis__rect_solid_angle(s->env, b->x0, b->y0, b->x1, b->y1);
}

/* The density the sampler reports for block i: per steradian, or per unit of
 * (azimuth, polar angle) in the literal variant. */
static double block_density(const lumis_sampler *s, int i, double prob)
{
    const kdtree *t = s->data;
    const block *b = &t->blocks[i];
    if (s->m->uniform_angles) {
        double dphi = 2.0 * LUMIS_PI * (b->x1 - b->x0) / s->w;
        double dtheta = LUMIS_PI * (b->y1 - b->y0) / s->h;
        return prob / (dphi * dtheta);
    }
    return prob / block_omega(s, b);
}

static void fill_pick(const lumis_sampler *s, int i, double prob, double fs, double ft,
                      lumis__pick *p)
{
    const block *b = &((const kdtree *)s->data)->blocks[i];
    p->x0 = b->x0;
    p->y0 = b->y0;
    p->x1 = b->x1;
    p->y1 = b->y1;
    p->s = fs < 0.0 ? 0.0 : (fs < 1.0 ? fs : 0x1.fffffffffffffp-1);
    p->t = ft;
    p->density = block_density(s, i, prob);
}

/* Cost: O(1): the inverse of the model's CDF, then one lookup of the block's bounds. */
static void kd_pick(const lumis_sampler *s, double u1, double u2, lumis__pick *p)
{
    const kdtree *t = s->data;
    double x = t->alpha * expm1(u1 * t->log_span);
    int i = (int)x;
    if (i >= t->n) i = t->n - 1;
    if (i < 0) i = 0;
    double P0 = log1p(i / t->alpha) / t->log_span;
    double prob = model_prob(t->alpha, t->log_span, i);
    fill_pick(s, i, prob, (u1 - P0) / prob, u2, p);
}

/* The alias bins of kdtree-exact store each block's density (its probability over its
 * solid angle), rounded once to float: what sample() and pdf() both return. */
static float exact_block_density(const void *ctx, uint32_t i, double prob)
{
    return (float)block_density(ctx, (int)i, prob);
}

/* Cost: O(1): one alias bin (density included), then the block's bounds. */
static void kd_exact_pick(const lumis_sampler *s, double u1, double u2, lumis__pick *p)
{
    const kdtree *t = s->data;
    double fs, ft;
    float density;
    uint32_t i = lumis__alias_sample(&t->exact, u1, u2, &fs, &ft, &density);
    const block *b = &t->blocks[i];
    p->x0 = b->x0;
    p->y0 = b->y0;
    p->x1 = b->x1;
    p->y1 = b->y1;
    p->s = fs;
    p->t = ft;
    p->density = density;
}

/* The rank of the block holding pixel (i, j): down the tree, O(depth). */
static int find_block(const kdtree *t, int i, int j)
{
    const node *nd = &t->nodes[0];
    while (nd->axis != 2) {
        int c = nd->axis == 0 ? i : j;
        nd = &t->nodes[nd->index + (c >= nd->pos ? 1u : 0u)];
    }
    return (int)nd->index;
}

static double kd_density(const lumis_sampler *s, int i, int j)
{
    const kdtree *t = s->data;
    int b = find_block(t, i, j);
    return block_density(s, b, model_prob(t->alpha, t->log_span, b));
}

static double kd_exact_density(const lumis_sampler *s, int i, int j)
{
    const kdtree *t = s->data;
    return lumis__alias_value(&t->exact, (uint32_t)find_block(t, i, j));
}

static void kd_destroy(lumis_sampler *s)
{
    kdtree *t = s->data;
    if (!t) return;
    free(t->blocks);
    free(t->nodes);
    lumis__alias_free(&t->exact);
    free(t);
}

static const lumis__method kd_method = {kd_pick, kd_density, kd_destroy, 0, NULL, NULL};
static const lumis__method kd_angles_method = {kd_pick, kd_density, kd_destroy, 1, NULL, NULL};
static const lumis__method kd_exact_method = {kd_exact_pick, kd_exact_density, kd_destroy, 0, NULL,
                                              NULL};

/* ---- building ----------------------------------------------------------------------- */

typedef struct builder {
    int w, h;
    double *sat;  /* (w+1) x (h+1): sums of importance (Y Omega) */
    double *sat2; /* the same of (Y Omega)^2 / Omega = Y^2 Omega */
    double *rows; /* h + 1: prefix sums of the pixel solid angle over rows */
    double eps;   /* SSE below which a block counts as constant */
} builder;

static double rect_sum(const double *sat, int w, int x0, int y0, int x1, int y1)
{
    size_t W = (size_t)w + 1;
    return sat[(size_t)y1 * W + (size_t)x1] - sat[(size_t)y0 * W + (size_t)x1] -
           sat[(size_t)y1 * W + (size_t)x0] + sat[(size_t)y0 * W + (size_t)x0];
}

static double rect_size(const builder *bd, int x0, int y0, int x1, int y1)
{
    return (x1 - x0) * (bd->rows[y1] - bd->rows[y0]);
}

/* Eq. 1-2: SSE = sum Omega (Y - mean)^2 = S2 - S^2 / size. */
static double block_sse(const builder *bd, const block *b)
{
    double s = rect_sum(bd->sat, bd->w, b->x0, b->y0, b->x1, b->y1);
    double s2 = rect_sum(bd->sat2, bd->w, b->x0, b->y0, b->x1, b->y1);
    double e = s2 - s * s / rect_size(bd, b->x0, b->y0, b->x1, b->y1);
    return e > bd->eps * s2 ? e : 0.0;
}

/* Eq. 3: the split maximising lSum^2/lSize + rSum^2/rSize over both axes.  Returns 0 if
 * the block is a single pixel. */
int lumis__kdtree_best_split(const double *sat, const double *rows, int w, int x0, int y0, int x1,
                             int y1, int *axis, int *pos)
{
    double best = -1.0;
    const double total = rect_sum(sat, w, x0, y0, x1, y1);
    const double col_size = rows[y1] - rows[y0]; /* solid angle of one column of the block */
    for (int x = x0 + 1; x < x1; x++) {
        double l = rect_sum(sat, w, x0, y0, x, y1), r = total - l;
        double g = l * l / ((x - x0) * col_size) + r * r / ((x1 - x) * col_size);
        if (g > best) {
            best = g;
            *axis = 0;
            *pos = x;
        }
    }
    for (int y = y0 + 1; y < y1; y++) {
        double l = rect_sum(sat, w, x0, y0, x1, y), r = total - l;
        double ls = (x1 - x0) * (rows[y] - rows[y0]), rs = (x1 - x0) * (rows[y1] - rows[y]);
        double g = l * l / ls + r * r / rs;
        if (g > best) {
            best = g;
            *axis = 1;
            *pos = y;
        }
    }
    return best >= 0.0;
}

typedef struct heap_item {
    double sse;
    int block;
} heap_item;

static void heap_push(heap_item *h, int *n, heap_item it)
{
    int k = (*n)++;
    while (k > 0 && h[(k - 1) / 2].sse < it.sse) {
        h[k] = h[(k - 1) / 2];
        k = (k - 1) / 2;
    }
    h[k] = it;
}

static heap_item heap_pop(heap_item *h, int *n)
{
    heap_item top = h[0], last = h[--*n];
    int k = 0;
    for (;;) {
        int c = 2 * k + 1;
        if (c >= *n) break;
        if (c + 1 < *n && h[c + 1].sse > h[c].sse) c++;
        if (h[c].sse <= last.sse) break;
        h[k] = h[c];
        k = c;
    }
    if (*n > 0) h[k] = last;
    return top;
}

typedef struct ranked {
    double prob;
    int block;
} ranked;

static int by_prob_desc(const void *a, const void *b)
{
    const ranked *x = a, *y = b;
    if (x->prob != y->prob) return x->prob < y->prob ? 1 : -1;
    return (x->block > y->block) - (x->block < y->block); /* deterministic ties */
}

lumis_status lumis__kdtree_init(lumis_sampler *s, const double *imp, const lumis_sampler_desc *desc)
{
    int exact = s->method == LUMIS_METHOD_KDTREE_EXACT;
    s->m =
        exact ? &kd_exact_method : (desc->kdtree_uniform_angles ? &kd_angles_method : &kd_method);
    kdtree *t = calloc(1, sizeof *t);
    s->data = t;
    if (!t) return LUMIS_ERR_OUT_OF_MEMORY;
    const int w = s->w, h = s->h;
    if (w > 65535 || h > 65535) return LUMIS_ERR_TOO_LARGE; /* 16-bit block bounds */
    int want = desc->kdtree_blocks ? desc->kdtree_blocks : DEFAULT_BLOCKS;
    if ((int64_t)want > (int64_t)w * h) want = w * h;

    builder bd = {w, h, NULL, NULL, NULL, 1e-12};
    size_t W = (size_t)w + 1, H = (size_t)h + 1;
    bd.sat = calloc(W * H, sizeof(double));
    bd.sat2 = calloc(W * H, sizeof(double));
    bd.rows = malloc(H * sizeof(double));
    t->blocks = malloc((size_t)want * sizeof(block));
    t->nodes = malloc(((size_t)2 * (size_t)want) * sizeof(node));
    heap_item *heap = malloc((size_t)want * sizeof(heap_item));
    int *leaf_of = malloc((size_t)want * sizeof(int)); /* block -> its leaf node */
    ranked *rank = malloc((size_t)want * sizeof(ranked));
    double *probs = malloc((size_t)want * sizeof(double));
    lumis_status st = LUMIS_OK;
    if (!bd.sat || !bd.sat2 || !bd.rows || !t->blocks || !t->nodes || !heap || !leaf_of || !rank ||
        !probs) {
        st = LUMIS_ERR_OUT_OF_MEMORY;
        goto done;
    }
    bd.rows[0] = 0.0;
    for (int j = 0; j < h; j++) {
        const double omega = s->env->row_solid_angle[j];
        bd.rows[j + 1] = bd.rows[j] + omega;
        double run = 0.0, run2 = 0.0;
        for (int i = 0; i < w; i++) {
            double v = imp[(size_t)j * (size_t)w + (size_t)i];
            run += v;
            run2 += v * v / omega;
            bd.sat[(size_t)(j + 1) * W + (size_t)i + 1] =
                bd.sat[(size_t)j * W + (size_t)i + 1] + run;
            bd.sat2[(size_t)(j + 1) * W + (size_t)i + 1] =
                bd.sat2[(size_t)j * W + (size_t)i + 1] + run2;
        }
    }

    /* Algorithm 1: split the block of largest SSE until there are `want` blocks or every
     * block is constant. */
    int n = 1, nheap = 0;
    t->blocks[0] = (block){0, 0, (uint16_t)w, (uint16_t)h};
    t->nodes[0] = (node){0, 0, 2, 0};
    t->node_count = 1;
    leaf_of[0] = 0;
    double sse0 = block_sse(&bd, &t->blocks[0]);
    if (sse0 > 0.0) heap_push(heap, &nheap, (heap_item){sse0, 0});
    while (n < want && nheap > 0) {
        heap_item top = heap_pop(heap, &nheap);
        block b = t->blocks[top.block];
        int axis = 0, pos = 0;
        if (!lumis__kdtree_best_split(bd.sat, bd.rows, w, b.x0, b.y0, b.x1, b.y1, &axis, &pos))
            continue;
        block l = b, r = b;
        if (axis == 0)
            l.x1 = r.x0 = (uint16_t)pos;
        else
            l.y1 = r.y0 = (uint16_t)pos;
        /* The leaf becomes an inner node with two adjacent children. */
        node *parent = &t->nodes[leaf_of[top.block]];
        uint32_t c = (uint32_t)t->node_count;
        *parent = (node){c, (uint16_t)pos, (uint8_t)axis, 0};
        t->nodes[c] = (node){(uint32_t)top.block, 0, 2, 0};
        t->nodes[c + 1] = (node){(uint32_t)n, 0, 2, 0};
        t->node_count += 2;
        t->blocks[top.block] = l;
        leaf_of[top.block] = (int)c;
        t->blocks[n] = r;
        leaf_of[n] = (int)c + 1;
        double sl = block_sse(&bd, &l), sr = block_sse(&bd, &r);
        if (sl > 0.0) heap_push(heap, &nheap, (heap_item){sl, top.block});
        if (sr > 0.0) heap_push(heap, &nheap, (heap_item){sr, n});
        n++;
    }
    t->n = n;

    /* The blocks' true probabilities, summed pixel by pixel (the blocks partition the
     * map, so this is one pass): differences of summed-area entries can cancel to zero
     * or below for a faint block beside a sun, and kdtree-exact would then never draw
     * light it holds.  Then sort by probability, descending; leaves learn their rank. */
    double total = 0.0;
    for (int k = 0; k < n; k++) {
        const block *b = &t->blocks[k];
        double sum = 0.0;
        for (int y = b->y0; y < b->y1; y++)
            for (int x = b->x0; x < b->x1; x++) sum += imp[(size_t)y * (size_t)w + (size_t)x];
        rank[k] = (ranked){sum, k};
        total += sum;
    }
    for (int k = 0; k < n; k++) rank[k].prob /= total;
    qsort(rank, (size_t)n, sizeof(ranked), by_prob_desc);
    block *sorted = malloc((size_t)n * sizeof(block));
    if (!sorted) {
        st = LUMIS_ERR_OUT_OF_MEMORY;
        goto done;
    }
    for (int k = 0; k < n; k++) {
        sorted[k] = t->blocks[rank[k].block];
        t->nodes[leaf_of[rank[k].block]].index = (uint32_t)k;
        probs[k] = rank[k].prob;
    }
    free(t->blocks);
    t->blocks = sorted;

    t->alpha = lumis__kdtree_fit_alpha(probs, n);
    t->log_span = log1p(n / t->alpha);
    s->kd_alpha = t->alpha;
    s->kd_blocks = n;
    if (exact) st = lumis__alias_build(&t->exact, probs, (uint32_t)n, exact_block_density, s);
    s->table_bytes = (size_t)n * sizeof(block) + 2 * sizeof(double) +
                     (exact ? (size_t)n * sizeof(lumis__alias_bin) : 0);
    s->total_bytes = s->table_bytes + (size_t)t->node_count * sizeof(node);

done:
    free(bd.sat);
    free(bd.sat2);
    free(bd.rows);
    free(heap);
    free(leaf_of);
    free(rank);
    free(probs);
    return st;
}

/* For tests: the blocks (x0, y0, x1, y1, sorted by probability) and their count. */
const uint16_t *lumis__kdtree_blocks(const lumis_sampler *s, int *n)
{
    const kdtree *t = s->data;
    *n = t->n;
    return &t->blocks[0].x0;
}
