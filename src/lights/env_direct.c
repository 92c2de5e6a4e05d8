/* EnvDirects of Wu's decomposition: importance sampling of the emissive pixels through a
 * sum tree (O(log n) per draw and per masked pixel, no CDF rebuilt per draw), masking of
 * a cap about each drawn pixel, spherical k-means on the energy centroids until no pixel
 * changes cluster (a step visits only the clusters a moved centre can reach, and lazy
 * Hamerly bounds skip most of their members), and the return of
 * far pixels to the non-emissive set.  docs/lights.md. */
#include "decomp.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#if LUMIS__MULTIVERSION /* k-means' AVX-512 visits, when lumis__simd_level() allows them */
#include <immintrin.h>
#define KM_AVX512 1
#endif

/* ---- sum tree -------------------------------------------------------------------------- */

typedef struct sum_tree {
    double *t; /* 2 P entries: t[P + i] leaf i, t[k] = t[2k] + t[2k + 1] */
    int P;
} sum_tree;

static lumis_status tree_build(sum_tree *s, const double *w, int n)
{
    int P = 1;
    while (P < n) P *= 2;
    s->P = P;
    s->t = calloc(2 * (size_t)P, sizeof(double));
    if (!s->t) return LUMIS_ERR_OUT_OF_MEMORY;
    for (int i = 0; i < n; i++) s->t[P + i] = w[i];
    for (int k = P - 1; k >= 1; k--) s->t[k] = s->t[2 * k] + s->t[2 * k + 1];
    return LUMIS_OK;
}

/* After leaves ids[0 .. n) (ascending) were set to 0: their ancestors recomputed from their
 * children, level by level, each once (ids is overwritten).  As no sum is carried from
 * before, no rounding drift accumulates however many leaves are zeroed. */
static void tree_update(sum_tree *s, int32_t *ids, int n)
{
    if (s->P == 1) return; /* the one leaf is the root */
    for (int i = 0; i < n; i++) ids[i] = (s->P + ids[i]) / 2;
    while (n > 0) {
        int u = 0;
        for (int i = 0; i < n; i++)
            if (u == 0 || ids[i] != ids[u - 1]) ids[u++] = ids[i];
        for (int i = 0; i < u; i++) s->t[ids[i]] = s->t[2 * ids[i]] + s->t[2 * ids[i] + 1];
        if (ids[0] == 1) break;
        for (int i = 0; i < u; i++) ids[i] /= 2;
        n = u;
    }
}

/* Leaf drawn with probability weight / total from u in [0, 1); the total must be > 0. */
static int tree_sample(const sum_tree *s, double u)
{
    double x = u * s->t[1];
    int k = 1;
    while (k < s->P) {
        double l = s->t[2 * k], r = s->t[2 * k + 1];
        if (l > 0.0 && (x < l || !(r > 0.0))) {
            k = 2 * k;
        } else {
            x -= l;
            k = 2 * k + 1;
        }
    }
    return k - s->P;
}

/* ---- masking ---------------------------------------------------------------------------- */

/* Zeroes the tree leaf of every emissive pixel whose centroid lies within angle alpha of
 * unit direction d (labels map emissive pixels to their indices).  Visits only the pixels
 * of the cap's bounding box in rows and columns, in scan order, so the zeroed leaves come
 * in ascending order for one tree_update (zbuf: room for every emissive pixel). */
static void mask_cap(const lumis__decomp *dc, sum_tree *tree, const double d[3], double alpha,
                     int32_t *zbuf)
{
    const int w = dc->w, h = dc->h;
    const double cos_a = cos(alpha), dth = LUMIS_PI / h, dph = 2.0 * LUMIS_PI / w;
    double th = acos(d[1] < -1.0 ? -1.0 : (d[1] > 1.0 ? 1.0 : d[1]));
    int j0 = (int)floor((th - alpha) / dth) - 1, j1 = (int)ceil((th + alpha) / dth) + 1;
    j0 = j0 < 0 ? 0 : j0;
    j1 = j1 > h ? h : j1;
    int all = th - alpha <= 0.0 || th + alpha >= LUMIS_PI, i0 = 0, span = w;
    if (!all) {
        double s = sin(alpha) / sin(th);
        double half = s >= 1.0 ? LUMIS_PI : asin(s);
        double ph = atan2(d[2], d[0]);
        if (ph < 0.0) ph += 2.0 * LUMIS_PI;
        i0 = (int)floor((ph - half) / dph) - 1;
        int i1 = (int)ceil((ph + half) / dph) + 1;
        span = i1 - i0;
        if (span >= w) {
            span = w;
            i0 = 0;
        }
    }
    i0 = ((i0 % w) + w) % w;
    /* the columns: [i0, i0 + span) modulo w, as at most two ascending ranges */
    const int wrap = i0 + span > w ? i0 + span - w : 0;
    const int ra[2][2] = {{0, wrap}, {i0, wrap ? w : i0 + span}};
    int nz = 0;
    for (int j = j0; j < j1; j++) {
        const size_t o = (size_t)j * (size_t)w;
        for (int r = 0; r < 2; r++)
            for (int i = ra[r][0]; i < ra[r][1]; i++) {
                if (!lumis__emissive(dc, o + (size_t)i)) continue;
                int32_t e = dc->labels[o + (size_t)i];
                double *leaf = &tree->t[tree->P + e];
                if (!(*leaf > 0.0)) continue;
                const double *q = dc->em_d + 3 * (size_t)e;
                if (q[0] * d[0] + q[1] * d[1] + q[2] * d[2] >= cos_a) {
                    *leaf = 0.0;
                    zbuf[nz++] = e;
                }
            }
    }
    tree_update(tree, zbuf, nz);
}

/* ---- spherical k-means ------------------------------------------------------------------
 *
 * Work per step is proportional to the pixels of the clusters that can change, not to
 * all emissive pixels: clusters keep member lists, their sums, objective terms and a bound
 * R_a on their members' distance to the centre are recomputed only when they change, and
 * an assignment step looks only at clusters whose centre moved or that a moved centre
 * came near (docs/lights.md, "k-means"). */

static double dist3(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

static double sq_dist(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return x * x + y * y + z * z;
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* An upper bound of the chord |x - c| from the computed dot product of unit vectors x and
 * c: |x - c|^2 = |x|^2 + |c|^2 - 2 x.c, the norms within 4e-16 of 1 and the dot product
 * within 4e-16; 4e-15 covers all of it with room to spare. */
static double chord_bound(double dot)
{
    double t = 2.0 - 2.0 * dot;
    return sqrt((t > 0.0 ? t : 0.0) + 4e-15);
}

/* Margin of the candidate test: a centre farther than 2 R_a + KM_MARGIN from c_a is
 * farther from every member of a than c_a by at least KM_MARGIN, i.e. its squared chord
 * exceeds c_a's by >= KM_MARGIN^2 = 1e-12, and its dot product falls short of c_a's by
 * >= 5e-13, far beyond rounding: the float comparison could never pick it. */
#define KM_MARGIN 1e-6

/* The positions q0 <= q < n whose bound fails, !(key[q] - now > KM_MARGIN), in ascending
 * order into out; returns their number.  Scalar: branchless, one member at a time. */
static int km_failing(const double *key, int q0, int n, double now, int32_t *out)
{
    int nf = 0;
    for (int q = q0; q < n; q++) {
        out[nf] = q;
        nf += !(key[q] - now > KM_MARGIN);
    }
    return nf;
}

#ifdef KM_AVX512
/* The same with AVX-512: sixteen keys per step, the failing positions compressed in a
 * register and stored whole (a compressing store to memory is microcoded and measured
 * slower than the scalar loop), so out needs room for n + 16.  The same subtraction and
 * comparison: the same positions in the same order. */
__attribute__((target("avx512f"))) static int km_failing_avx512(const double *key, int n,
                                                                double now, int32_t *out)
{
    const __m512d vnow = _mm512_set1_pd(now), vm = _mm512_set1_pd(KM_MARGIN);
    __m512i idx = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i step = _mm512_set1_epi32(16);
    int nf = 0, q = 0;
    for (; q + 16 <= n; q += 16) {
        const __mmask8 p0 =
            _mm512_cmp_pd_mask(_mm512_sub_pd(_mm512_loadu_pd(key + q), vnow), vm, _CMP_GT_OQ);
        const __mmask8 p1 =
            _mm512_cmp_pd_mask(_mm512_sub_pd(_mm512_loadu_pd(key + q + 8), vnow), vm, _CMP_GT_OQ);
        const __mmask16 f = (__mmask16) ~((unsigned)p0 | ((unsigned)p1 << 8));
        _mm512_storeu_si512((void *)(out + nf), _mm512_maskz_compress_epi32(f, idx));
        nf += __builtin_popcount((unsigned)f);
        idx = _mm512_add_epi32(idx, step);
    }
    return nf + km_failing(key, q, n, now, out + nf);
}
#endif

/* A lower bound of the chord from the computed dot product (see chord_bound). */
static double chord_lower(double dot)
{
    double t = 2.0 - 2.0 * dot - 4e-15;
    return sqrt(t > 0.0 ? t : 0.0);
}

/* A cluster's members, contiguous (structure of arrays), with each member's Hamerly
 * bound kept lazily: slack = (lower bound of the distance to every other centre) - (upper
 * bound of the distance to its own), valid when D[own] + G[own] equalled `now`; since then
 * its own centre moved by at most the growth of D[own] and any other by at most the growth
 * of G[own] (the sum over the steps of the largest drift among the other centres), so
 * slack - (D[own] + G[own] - now) is still a valid slack.  Stored is key = slack + now,
 * and the member cannot change cluster while key - (D[own] + G[own]) exceeds the margin
 * (the rounding of the key, ~1e-16, is far inside the margin). */
typedef struct km_cluster {
    int n, cap;
    int32_t *id;
    double *x, *y, *z, *w, *key;
} km_cluster;

/* The clusters' weighted direction sums S = sum w d are kept in fixed point (int64 steps of
 * `unit`): a move subtracts a pixel's w d from one sum and adds it to another exactly, so a
 * centre depends only on its cluster's members, never on the order of the moves, and an
 * update costs O(1) per cluster instead of a pass over its members. */
typedef struct km_state {
    int k;
    km_cluster *cl;
    int32_t *pos; /* m: index of each pixel in its cluster's arrays */
    int64_t *q;   /* 3 m: each pixel's w d in steps of unit */
    int64_t *S;   /* 3 k: the sums of q over each cluster's members */
    double unit;
    double *J;  /* k: sum over the members of w |x - c|^2 / 2 */
    double *R;  /* k: bound of the members' chord distance to the centre */
    double *R0; /* k: R when last computed from the members */
    double *D;  /* k: cumulative drift of each centre */
    double *G;  /* k: cumulative largest drift of the other centres */
} km_state;

static lumis_status km_push(km_state *s, int j, int32_t i, const double v[5])
{
    km_cluster *c = &s->cl[j];
    if (c->n == c->cap) {
        int nc = c->cap ? 2 * c->cap : 16;
        int32_t *id = realloc(c->id, (size_t)nc * sizeof(int32_t));
        if (id) c->id = id;
        double *d = id ? realloc(c->x, 5 * (size_t)nc * sizeof(double)) : NULL;
        if (!d) return LUMIS_ERR_OUT_OF_MEMORY;
        /* one block of five arrays of nc entries: move the old ones to their new places */
        for (size_t f = 4; f >= 1; f--) /* field f: from f cap to f nc, last field first */
            memmove(d + f * (size_t)nc, d + f * (size_t)c->cap, (size_t)c->n * sizeof(double));
        c->x = d;
        c->y = d + nc;
        c->z = d + 2 * (size_t)nc;
        c->w = d + 3 * (size_t)nc;
        c->key = d + 4 * (size_t)nc;
        c->cap = nc;
    }
    int q = c->n++;
    c->id[q] = i;
    c->x[q] = v[0];
    c->y[q] = v[1];
    c->z[q] = v[2];
    c->w[q] = v[3];
    c->key[q] = v[4];
    s->pos[i] = q;
    for (int t = 0; t < 3; t++) s->S[3 * (size_t)j + (size_t)t] += s->q[3 * (size_t)i + (size_t)t];
    return LUMIS_OK;
}

/* Removes member q of cluster j (the last member takes its place). */
static void km_remove(km_state *s, int j, int q)
{
    km_cluster *c = &s->cl[j];
    for (int t = 0; t < 3; t++)
        s->S[3 * (size_t)j + (size_t)t] -= s->q[3 * (size_t)c->id[q] + (size_t)t];
    int last = --c->n;
    if (q == last) return;
    c->id[q] = c->id[last];
    c->x[q] = c->x[last];
    c->y[q] = c->y[last];
    c->z[q] = c->z[last];
    c->w[q] = c->w[last];
    c->key[q] = c->key[last];
    s->pos[c->id[q]] = q;
}

/* The pixels' w d in fixed point: steps of a power of two such that m times the largest
 * weight is below 2^61 steps, so no sum of up to m of them overflows. */
static void km_quantise(km_state *s, const lumis__decomp *dc)
{
    double wmax = 0.0;
    for (int i = 0; i < dc->m; i++) wmax = dc->em_w[i] > wmax ? dc->em_w[i] : wmax;
    int ew, em;
    frexp(wmax, &ew);
    frexp((double)dc->m, &em);
    const int shift = 61 - ew - em; /* w d / unit = w d 2^shift < 2^61 / m */
    s->unit = ldexp(1.0, -shift);
    const double scale = ldexp(1.0, shift); /* exact: a power of two */
    for (int i = 0; i < dc->m; i++)
        for (int t = 0; t < 3; t++)
            s->q[3 * (size_t)i + (size_t)t] =
                (int64_t)llrint(dc->em_w[i] * dc->em_d[3 * (size_t)i + (size_t)t] * scale);
}

/* R_j of cluster j from its members, and with `objective` its term J_j.  Sums run in
 * four interleaved partial sums (fixed order): a single chain of additions is latency
 * bound. */
static void km_cluster_terms(km_state *s, const double *c, int j, int objective)
{
    const km_cluster *cl = &s->cl[j];
    const double c0 = c[3 * j], c1 = c[3 * j + 1], c2 = c[3 * j + 2];
    int q = 0;
    if (objective) {
        double J[4] = {0.0, 0.0, 0.0, 0.0};
        for (; q + 4 <= cl->n; q += 4)
            for (int u = 0; u < 4; u++) {
                double dx = cl->x[q + u] - c0, dy = cl->y[q + u] - c1, dz = cl->z[q + u] - c2;
                J[u] += cl->w[q + u] * 0.5 * (dx * dx + dy * dy + dz * dz);
            }
        for (; q < cl->n; q++) {
            double dx = cl->x[q] - c0, dy = cl->y[q] - c1, dz = cl->z[q] - c2;
            J[0] += cl->w[q] * 0.5 * (dx * dx + dy * dy + dz * dz);
        }
        s->J[j] = (J[0] + J[1]) + (J[2] + J[3]);
    }
    double mn[4] = {2.0, 2.0, 2.0, 2.0};
    for (q = 0; q + 4 <= cl->n; q += 4)
        for (int u = 0; u < 4; u++) {
            double d = cl->x[q + u] * c0 + cl->y[q + u] * c1 + cl->z[q + u] * c2;
            mn[u] = d < mn[u] ? d : mn[u];
        }
    for (; q < cl->n; q++) {
        double d = cl->x[q] * c0 + cl->y[q] * c1 + cl->z[q] * c2;
        mn[0] = d < mn[0] ? d : mn[0];
    }
    const double m01 = mn[0] < mn[1] ? mn[0] : mn[1], m23 = mn[2] < mn[3] ? mn[2] : mn[3];
    const double mind = m01 < m23 ? m01 : m23;
    s->R[j] = s->R0[j] = cl->n > 0 ? chord_bound(mind) : 0.0;
}

static double km_objective(const km_state *s)
{
    double J = 0.0;
    for (int j = 0; j < s->k; j++) J += s->J[j];
    return J;
}

static lumis_status push_objective(lumis__direct_result *r, int *cap, double J)
{
    if (r->objective_count == *cap) {
        int nc = *cap ? 2 * *cap : 16;
        double *p = realloc(r->objective, (size_t)nc * sizeof(double));
        if (!p) return LUMIS_ERR_OUT_OF_MEMORY;
        r->objective = p;
        *cap = nc;
    }
    r->objective[r->objective_count++] = J;
    return LUMIS_OK;
}

/* Safety net for floating-point cycling; the exact algorithm cannot cycle (docs). */
#define KMEANS_HARD_LIMIT 100000

/* R_j grows by each drift of the centre (triangle inequality) and is recomputed from the
 * members once it exceeds this factor times its last exact value: a loose R only makes an
 * assignment step look at more neighbouring centres. */
#define KM_R_SLACK 1.5

typedef struct km_move {
    int32_t i, to;
    double slack;
} km_move;

/* A centre's distance (chord) to another, for the seeds' assignment. */
/* A centre's others, nearest first: the first assignment's candidates on small K, where
 * the K x K lists cost less than grid queries (above K = 256 they cost O(K^2 log K)
 * time and 16 K^2 bytes: the grid then). */
enum { KM_LISTS_MAX_K = 256 };

typedef struct km_near {
    double d;
    int32_t j;
} km_near;

static int cmp_near(const void *pa, const void *pb)
{
    const km_near *a = pa, *b = pb;
    if (a->d != b->d) return a->d < b->d ? -1 : 1;
    return (a->j > b->j) - (a->j < b->j);
}

/* The centres in a uniform 3D grid over [-1, 1]^3: for unit vectors the chord is the
 * Euclidean distance, so the centres within a radius of a point are found among the cells
 * its box covers, in O(cells + found) instead of O(K).  What the grid returns is a
 * superset, tested with the same sq_dist as a full scan, so every list it yields is the
 * one the scan would (the light sets do not change: docs/lights.md, "k-means"). */
typedef struct km_grid {
    int g;           /* cells per axis */
    double inv_h, h; /* cells per unit; cell size */
    int32_t *start;  /* g^3 + 1 offsets into item */
    int32_t *item;   /* centre indices by cell, ascending within a cell */
    int32_t *cand;   /* a query's result, up to K */
} km_grid;

static lumis_status km_grid_init(km_grid *gr, int k)
{
    /* about one centre per cell of the sphere's surface: spacing sqrt(4 pi / K) */
    int g = (int)(2.0 / sqrt(4.0 * LUMIS_PI / (k > 0 ? k : 1)) + 0.5);
    gr->g = g < 1 ? 1 : (g > 48 ? 48 : g);
    gr->h = 2.0 / gr->g;
    gr->inv_h = gr->g / 2.0;
    const size_t cells = (size_t)gr->g * (size_t)gr->g * (size_t)gr->g;
    gr->start = malloc((cells + 1) * sizeof(int32_t));
    gr->item = malloc((size_t)(k > 0 ? k : 1) * sizeof(int32_t));
    gr->cand = malloc((size_t)(k > 0 ? k : 1) * sizeof(int32_t));
    return gr->start && gr->item && gr->cand ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
}

static void km_grid_free(km_grid *gr)
{
    free(gr->start);
    free(gr->item);
    free(gr->cand);
}

static int km_grid_axis(const km_grid *gr, double x)
{
    const double f = (x + 1.0) * gr->inv_h;
    return f < 0.0 ? 0 : (f >= gr->g ? gr->g - 1 : (int)f);
}

static int km_grid_cell(const km_grid *gr, const double *p)
{
    return (km_grid_axis(gr, p[2]) * gr->g + km_grid_axis(gr, p[1])) * gr->g +
           km_grid_axis(gr, p[0]);
}

/* Counting sort of the centres by cell (stable: ascending indices within a cell). */
static void km_grid_build(km_grid *gr, const double *c, int k)
{
    const int cells = gr->g * gr->g * gr->g;
    memset(gr->start, 0, ((size_t)cells + 1) * sizeof(int32_t));
    for (int j = 0; j < k; j++) gr->start[km_grid_cell(gr, c + 3 * (size_t)j) + 1]++;
    for (int q = 0; q < cells; q++) gr->start[q + 1] += gr->start[q];
    for (int j = 0; j < k; j++) gr->item[gr->start[km_grid_cell(gr, c + 3 * (size_t)j)]++] = j;
    for (int q = cells; q > 0; q--) gr->start[q] = gr->start[q - 1];
    gr->start[0] = 0;
}

/* Every centre whose cell meets the box of the ball (p, r) into gr->cand (a superset of the
 * centres within r; a centre left out is farther than r); returns their number, or -1 when
 * the box covers more than a quarter as many cells as there are centres (the caller
 * scans them all then: cheaper). */
static int km_grid_query(km_grid *gr, const double *p, double r, int k)
{
    r = r * (1.0 + 1e-12) + 1e-12; /* the box's rounding never drops a centre */
    int lo[3], hi[3];
    double cells = 1.0;
    for (int a = 0; a < 3; a++) {
        lo[a] = km_grid_axis(gr, p[a] - r);
        hi[a] = km_grid_axis(gr, p[a] + r);
        cells *= hi[a] - lo[a] + 1;
    }
    if (4.0 * cells > k) return -1; /* a plain scan costs less */
    int n = 0;
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++) {
            const int row = (z * gr->g + y) * gr->g;
            const int32_t b = gr->start[row + lo[0]], e = gr->start[row + hi[0] + 1];
            for (int32_t t = b; t < e; t++) gr->cand[n++] = gr->item[t];
        }
    return n;
}

static int cmp_i32(const void *pa, const void *pb)
{
    const int32_t a = *(const int32_t *)pa, b = *(const int32_t *)pb;
    return (a > b) - (a < b);
}

/* The distance from centre j to its nearest other (INFINITY for K = 1), exactly the
 * minimum a full scan computes: balls of doubling radius until one holds a centre within
 * its radius. */
static double km_nearest_other(km_grid *gr, const double *c, int k, int j)
{
    const double *cj = c + 3 * (size_t)j;
    for (double r = gr->h;; r *= 2.0) {
        const int n = km_grid_query(gr, cj, r, k);
        double m2 = INFINITY;
        if (n < 0) {
            for (int b = 0; b < k; b++)
                if (b != j) {
                    const double d2 = sq_dist(cj, c + 3 * (size_t)b);
                    if (d2 < m2) m2 = d2;
                }
            return sqrt(m2);
        }
        for (int t = 0; t < n; t++) {
            const int b = gr->cand[t];
            if (b == j) continue;
            const double d2 = sq_dist(cj, c + 3 * (size_t)b);
            if (d2 < m2) m2 = d2;
        }
        if (m2 <= r * r) return sqrt(m2);
    }
}

/* Failing member q of cluster ca compared with the near centres nb[0 .. nn): the nearest
 * (the current centre, then the first in nb's order, wins ties) into *bd's centre, the
 * second-largest dot product into *sec. */
static inline LUMIS__ALWAYS_INLINE int km_nearest(const double *c, int ca, const int32_t *nb,
                                                  int nn, double x0, double x1, double x2,
                                                  double da, double *bd_out, double *sec_out)
{
    int best = ca;
    double bd = da, sec = -INFINITY;
    for (int t = 0; t < nn; t++) {
        const double *cb = c + 3 * (size_t)nb[t];
        double dt = x0 * cb[0] + x1 * cb[1] + x2 * cb[2];
        if (dt > bd) { /* the current centre wins ties */
            sec = bd;
            bd = dt;
            best = nb[t];
        } else if (dt > sec) {
            sec = dt;
        }
    }
    *bd_out = bd;
    *sec_out = sec;
    return best;
}

/* The member's new bound, or its move: centres beyond the reach are at least far - |x - c_a|
 * away.  Returns the number of moves. */
static inline LUMIS__ALWAYS_INLINE int km_settle(km_cluster *cl, int q, int ca, int best, double da,
                                                 double bd, double sec, double far, double now,
                                                 km_move *moves, int nm)
{
    const double ua = chord_bound(da), lo = chord_lower(sec), lf = far - ua;
    const double lb = lo < lf ? lo : lf; /* no NaN here: no libm fmin */
    const double slack = lb - (best == ca ? ua : chord_bound(bd));
    if (best == ca) {
        cl->key[q] = slack + now;
    } else {
        moves[nm++] = (km_move){cl->id[q], best, slack};
    }
    return nm;
}

/* The failing members fail[0 .. nf) of cluster ca (centre c + 3 ca) re-evaluated against
 * the near centres nb[0 .. nn); returns the new number of moves. */
static int km_visit(km_cluster *cl, const int32_t *fail, int nf, const double *c, int ca,
                    const int32_t *nb, int nn, double far, double now, km_move *moves, int nm)
{
    const double *cc = c + 3 * (size_t)ca;
    for (int f = 0; f < nf; f++) {
        const int q = fail[f];
        const double x0 = cl->x[q], x1 = cl->y[q], x2 = cl->z[q];
        const double da = x0 * cc[0] + x1 * cc[1] + x2 * cc[2];
        double bd, sec;
        const int best = km_nearest(c, ca, nb, nn, x0, x1, x2, da, &bd, &sec);
        nm = km_settle(cl, q, ca, best, da, bd, sec, far, now, moves, nm);
    }
    return nm;
}

#ifdef KM_AVX512
/* km_visit for eight failing members at a time with AVX-512, lane by lane the scalar
 * arithmetic: the dot products with their centre and with each near centre (the largest
 * kept per lane), and for a member that stays, which is most of them (no near centre's dot
 * product exceeds its own centre's), the new bound: its nearest is its centre and its
 * second-largest dot product the near centres' largest.  A member that may move goes
 * through the scalar km_nearest (first wins ties) and km_settle, in member order, so the
 * moves are listed as km_visit lists them.  Same operations in the same order, no
 * contraction (-ffp-contract=off on this file), and IEEE square roots: the same bits. */
/* GCC's gather and scatter macros (unoptimised builds) convert their mask with a sign
 * change that -Wconversion reports; the masks here are plain 8-bit lane masks. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-conversion"
__attribute__((target("avx512f"))) static int km_visit_avx512(km_cluster *cl, const int32_t *fail,
                                                              int nf, const double *c, int ca,
                                                              const int32_t *nb, int nn, double far,
                                                              double now, km_move *moves, int nm)
{
    if (nn == 0) return km_visit(cl, fail, nf, c, ca, nb, nn, far, now, moves, nm);
    const double *cc = c + 3 * (size_t)ca;
    const __m512d c0 = _mm512_set1_pd(cc[0]), c1 = _mm512_set1_pd(cc[1]),
                  c2 = _mm512_set1_pd(cc[2]), two = _mm512_set1_pd(2.0), zero = _mm512_setzero_pd(),
                  eps = _mm512_set1_pd(4e-15), vfar = _mm512_set1_pd(far),
                  vnow = _mm512_set1_pd(now);
    for (int f = 0; f < nf; f += 8) {
        const __mmask8 live = (__mmask8)(nf - f >= 8 ? 0xff : (1u << (nf - f)) - 1u);
        /* fail has room (zeroed) for 16 past its members: inactive lanes are never used */
        const __m256i qi = _mm256_loadu_si256((const __m256i *)(const void *)(fail + f));
        const __m512d x0 = _mm512_mask_i32gather_pd(zero, live, qi, cl->x, 8),
                      x1 = _mm512_mask_i32gather_pd(zero, live, qi, cl->y, 8),
                      x2 = _mm512_mask_i32gather_pd(zero, live, qi, cl->z, 8);
        const __m512d da = _mm512_add_pd(
            _mm512_add_pd(_mm512_mul_pd(x0, c0), _mm512_mul_pd(x1, c1)), _mm512_mul_pd(x2, c2));
        __m512d m1 = _mm512_set1_pd(-INFINITY);
        for (int t = 0; t < nn; t++) {
            const double *cb = c + 3 * (size_t)nb[t];
            const __m512d dt =
                _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(x0, _mm512_set1_pd(cb[0])),
                                            _mm512_mul_pd(x1, _mm512_set1_pd(cb[1]))),
                              _mm512_mul_pd(x2, _mm512_set1_pd(cb[2])));
            m1 = _mm512_max_pd(m1, dt);
        }
        /* the members that stay: chord_bound(da), chord_lower(m1), the slack, the key */
        const __mmask8 moving = _mm512_mask_cmp_pd_mask(live, m1, da, _CMP_GT_OQ);
        const __mmask8 stay = (__mmask8)(live & ~moving);
        const __m512d ua = _mm512_sqrt_pd(
            _mm512_add_pd(_mm512_max_pd(_mm512_sub_pd(two, _mm512_mul_pd(two, da)), zero), eps));
        const __m512d lo = _mm512_sqrt_pd(
            _mm512_max_pd(_mm512_sub_pd(_mm512_sub_pd(two, _mm512_mul_pd(two, m1)), eps), zero));
        const __m512d lb = _mm512_min_pd(lo, _mm512_sub_pd(vfar, ua));
        const __m512d key = _mm512_add_pd(_mm512_sub_pd(lb, ua), vnow);
        _mm512_mask_i32scatter_pd(cl->key, stay, qi, key, 8);
        for (unsigned mv = moving; mv; mv &= mv - 1) {
            const int q = fail[f + __builtin_ctz(mv)];
            const double y0 = cl->x[q], y1 = cl->y[q], y2 = cl->z[q];
            const double d = y0 * cc[0] + y1 * cc[1] + y2 * cc[2];
            double bd, sec;
            const int best = km_nearest(c, ca, nb, nn, y0, y1, y2, d, &bd, &sec);
            nm = km_settle(cl, q, ca, best, d, bd, sec, far, now, moves, nm);
        }
    }
    return nm;
}
#pragma GCC diagnostic pop
#endif

/* A candidate centre j at dot product dt for the first assignment: the largest dot product
 * wins (the smaller index on ties) into *bd / *best, the second largest into *sec. */
static inline void km_consider(int j, double dt, double *bd, double *sec, int *best)
{
    if (dt > *bd || (dt == *bd && j < *best)) {
        *sec = *bd;
        *bd = dt;
        *best = j;
    } else if (dt > *sec) {
        *sec = dt;
    }
}

static lumis_status kmeans(const lumis__decomp *dc, const lumis__direct_params *p, double *c, int k,
                           int32_t *a, lumis__direct_result *res)
{
    const int m = dc->m;
    km_state s;
    memset(&s, 0, sizeof s);
    s.k = k;
    s.cl = calloc((size_t)k, sizeof *s.cl);
    s.pos = malloc((size_t)m * sizeof(int32_t));
    s.q = malloc(3 * (size_t)m * sizeof(int64_t));
    s.S = calloc(3 * (size_t)k, sizeof(int64_t));
    s.J = malloc((size_t)k * sizeof(double));
    s.R = malloc((size_t)k * sizeof(double));
    s.R0 = malloc((size_t)k * sizeof(double));
    s.D = calloc((size_t)k, sizeof(double));
    s.G = calloc((size_t)k, sizeof(double));
    double *delta = malloc((size_t)k * sizeof(double));
    unsigned char *changed = malloc((size_t)k);
    int32_t *nb = malloc((size_t)k * sizeof(int32_t));
    km_move *moves = malloc((size_t)m * sizeof *moves);
    int32_t *fail = calloc((size_t)m + 16, sizeof(int32_t));
    double *nearest = malloc((size_t)k * sizeof(double)); /* each centre's nearest other */
    unsigned char *visit = malloc((size_t)k);
    km_near *near = k <= KM_LISTS_MAX_K
                        ? malloc(((size_t)k * (size_t)(k > 1 ? k - 1 : 1)) * sizeof *near)
                        : NULL;
    km_grid grid;
    int cap = 0;
    lumis_status st = km_grid_init(&grid, k);
    if (!s.cl || !s.pos || !s.q || !s.S || !s.J || !s.R || !s.R0 || !s.D || !s.G || !delta ||
        !changed || !nb || !moves || !fail || !nearest || !visit || (k <= KM_LISTS_MAX_K && !near))
        st = LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) {
        km_quantise(&s, dc);
        km_grid_build(&grid, c, k);
        for (int j = 0; j < k; j++) {
            if (!near || k == 1) { /* from the grid; with the lists, their first entry */
                nearest[j] = km_nearest_other(&grid, c, k, j);
                continue;
            }
            km_near *L = near + (size_t)j * (size_t)(k - 1);
            int t = 0;
            for (int b = 0; b < k; b++)
                if (b != j)
                    L[t++] = (km_near){sqrt(sq_dist(c + 3 * (size_t)j, c + 3 * (size_t)b)), b};
            qsort(L, (size_t)(k - 1), sizeof *L, cmp_near);
            nearest[j] = L[0].d; /* the same minimum of the same square roots */
        }
    }
    /* The seeds' assignment: nearest centre by dot product, the first on ties.  Pixels come
     * in scan order, so the last pixel's centre is usually the answer: it is, with the
     * first-on-ties rule intact, when the pixel lies within half the distance from that
     * centre to every other by more than the margin; the slack is then a valid lower bound.
     * Otherwise only the centres within 2 r + margin of the last one (r the pixel's
     * distance to it) can be nearer, or tie: they are compared, nearest first, and the
     * first one beyond bounds the rest. */
    for (int i = 0, last = 0; st == LUMIS_OK && i < m; i++) {
        const double *x = dc->em_d + 3 * (size_t)i;
        int best = last;
        double slack = INFINITY;
        const double dl = dot3(x, c + 3 * (size_t)last), rl = chord_bound(dl);
        /* half the distance from the last centre to its nearest other */
        const double half = k > 1 ? 0.5 * nearest[last] * (1.0 - 1e-15) : INFINITY;
        if (k > 1 && rl + KM_MARGIN < half) {
            slack = 2.0 * (half - rl);
        } else if (k > 1 && near) { /* the last one's others, nearest first */
            const km_near *L = near + (size_t)last * (size_t)(k - 1);
            const double reach = 2.0 * rl + KM_MARGIN;
            double bd = dl, sec = -INFINITY, rest = INFINITY;
            int t = 0;
            for (; t < k - 1 && L[t].d < reach; t++)
                km_consider(L[t].j, dot3(x, c + 3 * (size_t)L[t].j), &bd, &sec, &best);
            if (t < k - 1) rest = L[t].d * (1.0 - 1e-15) - rl;
            const double lo = chord_lower(sec);
            slack = (lo < rest ? lo : rest) - chord_bound(bd);
        } else if (k > 1) {
            /* the centres within the reach of the last one, and a bound on the others'
             * distance: the nearest found beyond the reach, or the searched radius */
            const double reach = 2.0 * rl + KM_MARGIN, searched = 1.25 * reach;
            const double *cl = c + 3 * (size_t)last;
            int n = km_grid_query(&grid, cl, searched, k);
            const int all = n < 0;
            if (all) n = k;
            /* squared distances: a centre nearer to x than the last one is within 2 rl of
             * it, far inside the reach, so rounding at the reach's edge only adds or drops
             * a candidate that cannot win (it may change sec: the slack stays a bound) */
            const double reach2 = reach * reach;
            double bd = dl, sec = -INFINITY, beyond2 = all ? INFINITY : searched * searched;
            for (int t = 0; t < n; t++) {
                const int j = all ? t : grid.cand[t];
                if (j == last) continue;
                const double d2 = sq_dist(cl, c + 3 * (size_t)j);
                if (!(d2 < reach2)) {
                    beyond2 = d2 < beyond2 ? d2 : beyond2;
                    continue;
                }
                km_consider(j, dot3(x, c + 3 * (size_t)j), &bd, &sec, &best);
            }
            const double rest = sqrt(beyond2) * (1.0 - 1e-15) - rl, lo = chord_lower(sec);
            slack = (lo < rest ? lo : rest) - chord_bound(bd);
        }
        a[i] = last = best;
        double v[5] = {x[0], x[1], x[2], dc->em_w[i], slack};
        st = km_push(&s, best, i, v);
    }
    if (st == LUMIS_OK) {
        for (int j = 0; j < k; j++) {
            km_cluster_terms(&s, c, j, 1);
            changed[j] = 1;
        }
        st = push_objective(res, &cap, km_objective(&s));
    }
    res->iterations = 1;
    res->converged = !p->kmeans;
    const int limit = p->max_iterations > 0 ? p->max_iterations : KMEANS_HARD_LIMIT;
#ifdef KM_AVX512
    const int avx512 = lumis__simd_level() >= LUMIS__SIMD_AVX512;
#endif
    int updates = 0;
    while (st == LUMIS_OK && p->kmeans) {
        /* Update: each changed cluster's centre to its normalised weighted mean direction
         * S / |S|, which minimises the cluster's J = sum w |d - c|^2 / 2 = sum w - c . S
         * over unit c; J falls by exactly (c_new - c_old) . S = |S| |c_new - c_old|^2 / 2.
         * An unchanged cluster would get the very same centre. */
        int nmoved = 0;
        double dmax = 0.0, dmax2 = 0.0;
        int jmax = -1;
        for (int j = 0; j < k; j++) {
            delta[j] = 0.0;
            if (!changed[j]) continue;
            changed[j] = 0;
            const int64_t *S = s.S + 3 * (size_t)j;
            const double sx = (double)S[0] * s.unit, sy = (double)S[1] * s.unit,
                         sz = (double)S[2] * s.unit;
            double len = sqrt(sx * sx + sy * sy + sz * sz);
            if (!(len > 0.0)) {                   /* empty cluster: keeps its centre */
                if (s.cl[j].n == 0) s.J[j] = 0.0; /* not a residue of the leavers' terms */
                continue;
            }
            double nc[3] = {sx / len, sy / len, sz / len}, *cj = c + 3 * (size_t)j;
            delta[j] = dist3(nc, cj);
            memcpy(cj, nc, sizeof nc);
            if (delta[j] > 0.0) {
                const double drop = 0.5 * len * delta[j] * delta[j];
                s.J[j] = s.J[j] > drop ? s.J[j] - drop : 0.0;
                s.R[j] += delta[j];
                if (s.R[j] > KM_R_SLACK * s.R0[j]) km_cluster_terms(&s, c, j, 0);
                s.D[j] += delta[j];
                if (delta[j] > dmax) {
                    dmax2 = dmax;
                    dmax = delta[j];
                    jmax = j;
                } else if (delta[j] > dmax2) {
                    dmax2 = delta[j];
                }
                nmoved++;
            }
        }
        /* Hamerly: the other centres approach a member by at most the largest drift
         * among them, which for the farthest-moving centre is the second largest */
        for (int j = 0; j < k; j++) s.G[j] += j == jmax ? dmax2 : dmax;
        updates++;
        st = push_objective(res, &cap, km_objective(&s));
        if (st != LUMIS_OK || updates >= limit) break;
        /* Assignment.  The last step left every pixel with its nearest centre; only a
         * centre that moved can change that.  A member x of cluster a has |x - c_a| <= R_a,
         * so a centre b with |c_a - c_b| >= 2 R_a + margin cannot be nearer to it (nor,
         * by the margin, win the float comparison): a cluster is visited only if it moved
         * or a moved centre is near, and then only its members whose lazy Hamerly bound
         * fails are compared with the near centres. */
        int nm = 0;
        if (nmoved > 0) {
            /* the clusters to visit: each moved centre's own, and those it came within
             * their reach of (found around it within the largest reach) */
            km_grid_build(&grid, c, k);
            double rmax = 0.0;
            for (int j = 0; j < k; j++) rmax = s.R[j] > rmax ? s.R[j] : rmax;
            /* when many moved, most clusters are visited anyway: no marking */
            memset(visit, 4 * nmoved > k, (size_t)k);
            for (int b = 0; b < k && 4 * nmoved <= k; b++) {
                if (!(delta[b] > 0.0)) continue;
                visit[b] = 1;
                const double *cb = c + 3 * (size_t)b;
                int n = km_grid_query(&grid, cb, 2.0 * rmax + KM_MARGIN, k);
                const int all = n < 0;
                if (all) n = k;
                for (int t = 0; t < n; t++) {
                    const int ca = all ? t : grid.cand[t];
                    const double reach = 2.0 * s.R[ca] + KM_MARGIN;
                    if (ca != b && sq_dist(c + 3 * (size_t)ca, cb) < reach * reach) visit[ca] = 1;
                }
            }
        }
        for (int ca = 0; nmoved > 0 && ca < k; ca++) {
            if (!visit[ca]) continue; /* neither it nor a centre within its reach moved */
            const double *cc = c + 3 * (size_t)ca;
            const double reach = 2.0 * s.R[ca] + KM_MARGIN, reach2 = reach * reach;
            /* the centres within the reach (ascending, as a full scan lists them) and the
             * nearest beyond it, or the searched radius: a bound on the rest */
            const double searched = 1.25 * reach;
            int n = km_grid_query(&grid, cc, searched, k);
            const int all = n < 0;
            if (all) n = k;
            int nn = 0, need = delta[ca] > 0.0;
            double far2 = all ? INFINITY : searched * searched;
            for (int t = 0; t < n; t++) {
                const int b = all ? t : grid.cand[t];
                if (b == ca) continue;
                double r2 = sq_dist(cc, c + 3 * (size_t)b);
                if (r2 < reach2) {
                    nb[nn++] = b;
                    need |= delta[b] > 0.0;
                } else if (r2 < far2) {
                    far2 = r2;
                }
            }
            if (!need) continue;
            if (!all) qsort(nb, (size_t)nn, sizeof *nb, cmp_i32);
            /* a little under the distance to the nearest centre beyond the reach */
            const double far = sqrt(far2) * (1.0 - 1e-15);
            km_cluster *cl = &s.cl[ca];
            const double now = s.D[ca] + s.G[ca];
            /* the members whose bound fails */
#ifdef KM_AVX512
            const int nf = avx512 ? km_failing_avx512(cl->key, cl->n, now, fail)
                                  : km_failing(cl->key, 0, cl->n, now, fail);
#else
            const int nf = km_failing(cl->key, 0, cl->n, now, fail);
#endif
#ifdef KM_AVX512
            nm = avx512 ? km_visit_avx512(cl, fail, nf, c, ca, nb, nn, far, now, moves, nm)
                        : km_visit(cl, fail, nf, c, ca, nb, nn, far, now, moves, nm);
#else
            nm = km_visit(cl, fail, nf, c, ca, nb, nn, far, now, moves, nm);
#endif
        }
        for (int t = 0; st == LUMIS_OK && t < nm; t++) {
            const int i = moves[t].i, from = a[i], to = moves[t].to, q = s.pos[i];
            const km_cluster *cl = &s.cl[from];
            double v[5] = {cl->x[q], cl->y[q], cl->z[q], cl->w[q],
                           moves[t].slack + s.D[to] + s.G[to]};
            changed[from] = changed[to] = 1;
            /* The objective terms follow the pixel. */
            s.J[from] -= v[3] * 0.5 * sq_dist(v, c + 3 * (size_t)from);
            s.J[to] += v[3] * 0.5 * sq_dist(v, c + 3 * (size_t)to);
            km_remove(&s, from, q);
            a[i] = to;
            st = km_push(&s, to, i, v);
            double r = chord_bound(v[0] * c[3 * to] + v[1] * c[3 * to + 1] + v[2] * c[3 * to + 2]);
            if (r > s.R[to]) s.R[to] = r; /* the leavers' R stays a bound */
        }
        if (st != LUMIS_OK) break;
        res->iterations++;
        st = push_objective(res, &cap, km_objective(&s));
        if (nm == 0) {
            res->converged = 1;
            break;
        }
    }
    for (int j = 0; s.cl && j < k; j++) {
        free(s.cl[j].id);
        free(s.cl[j].x);
    }
    free(s.cl);
    free(s.pos);
    free(s.q);
    free(s.S);
    free(s.J);
    free(s.R);
    free(s.R0);
    free(s.D);
    free(s.G);
    free(delta);
    free(changed);
    free(nb);
    free(moves);
    free(fail);
    free(nearest);
    free(near);
    free(visit);
    km_grid_free(&grid);
    return st;
}

/* ---- the step --------------------------------------------------------------------------- */

lumis_status lumis__env_direct(lumis__decomp *dc, const lumis__direct_params *p,
                               lumis__direct_result *out)
{
    memset(out, 0, sizeof *out);
    const int m = dc->m;
    if (m == 0 || p->budget <= 0) {
        for (int e = 0; e < m; e++) {
            dc->em_cluster[e] = -1;
            dc->labels[dc->em_pix[e]] = -1;
        }
        out->returned = m;
        out->converged = 1;
        return LUMIS_OK;
    }
    sum_tree tree;
    if (tree_build(&tree, dc->em_e, m) != LUMIS_OK) return LUMIS_ERR_OUT_OF_MEMORY;
    int32_t *seeds = malloc((size_t)p->budget * sizeof(int32_t));
    double *c = malloc(3 * (size_t)p->budget * sizeof(double));
    int32_t *a = malloc((size_t)m * sizeof(int32_t));
    int32_t *remap = malloc((size_t)p->budget * sizeof(int32_t));
    lumis_status st = (seeds && c && a && remap) ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
    int k = 0;
    if (st == LUMIS_OK) {
        lumis_pcg32 rng;
        lumis_pcg32_seed(&rng, p->seed, 0x656e76646972ULL); /* "envdir" */
        while (k < p->budget && tree.t[1] > 0.0) {
            int e = tree_sample(&tree, lumis_pcg32_double(&rng));
            seeds[k++] = e;
            if (p->mask) /* a, not yet in use, holds the zeroed leaves */
                mask_cap(dc, &tree, dc->em_d + 3 * (size_t)e, p->mask_radius, a);
        }
        out->seeds = k;
        for (int j = 0; j < k; j++)
            memcpy(c + 3 * j, dc->em_d + 3 * (size_t)seeds[j], 3 * sizeof(double));
        st = kmeans(dc, p, c, k, a, out);
    }
    if (st == LUMIS_OK) {
        /* Pixels farther than the return radius from their centre leave the cluster; the
         * clusters left empty disappear and the others are numbered in order. */
        double cos_r = p->return_radius >= LUMIS_PI ? -2.0 : cos(p->return_radius);
        int *size = calloc((size_t)k, sizeof(int));
        if (!size) st = LUMIS_ERR_OUT_OF_MEMORY;
        for (int e = 0; st == LUMIS_OK && e < m; e++) {
            const double *x = dc->em_d + 3 * (size_t)e, *q = c + 3 * (size_t)a[e];
            if (x[0] * q[0] + x[1] * q[1] + x[2] * q[2] < cos_r) {
                a[e] = -1;
                out->returned++;
            } else {
                size[a[e]]++;
            }
        }
        int n = 0;
        for (int j = 0; st == LUMIS_OK && j < k; j++) remap[j] = size[j] ? n++ : -1;
        for (int e = 0; st == LUMIS_OK && e < m; e++) {
            dc->em_cluster[e] = a[e] >= 0 ? remap[a[e]] : -1;
            dc->labels[dc->em_pix[e]] = dc->em_cluster[e];
        }
        out->clusters = n;
        free(size);
    }
    free(tree.t);
    free(seeds);
    free(c);
    free(a);
    free(remap);
    return st;
}
