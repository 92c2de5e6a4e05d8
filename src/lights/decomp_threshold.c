/* Wu's decomposition, its pass over the pixels: the emissive threshold (Eq. 1, an exact
 * percentile: a sample-bracketed selection, or two-level radix selection), the pixels over
 * it, and the tiles' sums the EnvIndirects' cut reads (decomposition.c assembles the set).
 * docs/lights.md. */
#include "decomp.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return (u & 0x80000000u) ? 0u : u; /* luminance is >= 0; -0 counts as 0 */
}

/* The rank-th smallest (1-based) of n non-negative floats: hist (65536 entries, zeroed)
 * gets the histogram of the high 16 bits of their IEEE patterns, which order like the
 * values; a second histogram of the low 16 bits inside the bucket found settles it. */
static float select_rank_radix(const float *y, size_t n, size_t rank, uint32_t *hist)
{
    for (size_t p = 0; p < n; p++) hist[float_bits(y[p]) >> 16]++;
    size_t below = 0;
    uint32_t hi = 0;
    while (below + hist[hi] < rank) below += hist[hi++];
    memset(hist, 0, 65536 * sizeof(uint32_t));
    for (size_t p = 0; p < n; p++) {
        uint32_t b = float_bits(y[p]);
        if ((b >> 16) == hi) hist[b & 0xffffu]++;
    }
    uint32_t lo = 0;
    while (below + hist[lo] < rank) below += hist[lo++];
    uint32_t bits = (hi << 16) | lo;
    float out;
    memcpy(&out, &bits, sizeof out);
    return out;
}

/* The k-th smallest (0-based) of a[0 .. n), reordering a (Hoare's selection, median of
 * three pivots). */
static float kth_smallest(float *a, ptrdiff_t n, ptrdiff_t k)
{
    ptrdiff_t lo = 0, hi = n - 1;
    while (lo < hi) {
        float x = a[lo], y = a[lo + (hi - lo) / 2], z = a[hi];
        float pv = x < y ? (y < z ? y : (x < z ? z : x)) : (x < z ? x : (y < z ? z : y));
        ptrdiff_t i = lo, j = hi;
        while (i <= j) {
            while (a[i] < pv) i++;
            while (a[j] > pv) j--;
            if (i <= j) {
                float t = a[i];
                a[i] = a[j];
                a[j] = t;
                i++;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return a[k]; /* between the two parts: equal to the pivot */
    }
    return a[k];
}

/* Size of the sample that places the bracket; maps of fewer than 4 SELECT_SAMPLE pixels
 * gather every pixel. */
enum { SELECT_SAMPLE = 16384 };

/* The exact rank-th smallest (1-based) luminance, and the pixels that may be emissive,
 * without storing the luminance of every pixel: a strided sample of SELECT_SAMPLE pixels
 * puts a lower bound `lo` 6 binomial standard deviations + 16 ranks under the target rank
 * of the sample; the luminance pass counts, row by row while the row is hot, the pixels
 * under lo and gathers the others (index and luminance), a few per cent of the map.  If
 * fewer than `rank` lie under lo, the answer is a selection among the gathered, and since
 * the threshold L_T is at least that percentile, every emissive pixel is among them too.
 * Should the bound miss (rank pixels or more under it), the gathering overflow (ties), or
 * a threshold given by the caller lie under lo, the luminance of the whole map is computed
 * again and the radix selection runs (full_candidates), so no answer depends on the
 * sample. */
typedef struct bracket {
    float lo;       /* -INFINITY: every pixel is gathered */
    int full;       /* the gathering overflowed */
    size_t below;   /* pixels under lo */
    size_t nc, cap; /* gathered pixels, room */
    int32_t *idx;   /* their pixel indices, ascending */
    float *val;     /* their luminance */
} bracket;

static lumis_status bracket_init(bracket *b, const lumis_envmap *env, double scale, size_t n,
                                 size_t rank, int w)
{
    enum { S = SELECT_SAMPLE };
    memset(b, 0, sizeof *b);
    b->lo = -INFINITY;
    size_t expect = n;
    float *sample = NULL;
    if (n >= 4 * (size_t)S) {
        const double f = (double)rank / (double)n;
        const ptrdiff_t margin = (ptrdiff_t)(6.0 * sqrt(S * f * (1.0 - f))) + 16;
        const ptrdiff_t ilo = (ptrdiff_t)(f * S) - margin;
        if (ilo > 0) {
            sample = malloc(S * sizeof(float));
            if (!sample) return LUMIS_ERR_OUT_OF_MEMORY;
            const size_t stride = n / S;
            for (size_t t = 0; t < S; t++)
                sample[t] = lumis__pixel_y(env->pixels + 3 * (t * stride + stride / 2), scale);
            b->lo = kth_smallest(sample, S, ilo);
            free(sample);
            /* expected above lo: (S - ilo) / S of the map; room for twice that */
            expect = (size_t)((double)n * (double)(S - ilo) / S * 2.0) + 4096;
        }
    }
    b->cap = (expect < n ? expect : n) + (size_t)w; /* + w: a row's gathering overshoots */
    b->idx = malloc(b->cap * sizeof(int32_t));
    b->val = malloc(b->cap * sizeof(float));
    return b->idx && b->val ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
}

/* One row of luminance (row index o of its first pixel) into the count under lo and the
 * gathering.  Groups of 16 are counted by a loop the compiler vectorises; a group with a
 * value at or over lo (a few per cent) is gathered without branches. */
static void bracket_row(bracket *b, const float *restrict yr, int w, size_t o)
{
    enum { G = 16 };
    if (b->full) return;
    if (b->nc + (size_t)w > b->cap) {
        b->full = 1; /* the full pass will run */
        return;
    }
    size_t below = b->below, nc = b->nc;
    const float lo = b->lo;
    int i = 0;
    for (; i + G <= w; i += G) {
        int nlo = 0;
        for (int k = 0; k < G; k++) nlo += yr[i + k] < lo;
        below += (size_t)nlo;
        if (nlo == G) continue;
        for (int k = 0; k < G; k++) {
            const float v = yr[i + k];
            b->idx[nc] = (int32_t)(o + (size_t)(i + k));
            b->val[nc] = v;
            nc += !(v < lo);
        }
    }
    for (; i < w; i++) {
        const float v = yr[i];
        below += v < lo;
        b->idx[nc] = (int32_t)(o + (size_t)i);
        b->val[nc] = v;
        nc += !(v < lo);
    }
    b->below = below;
    b->nc = nc;
}

/* Y of one group of 16 pixels (their RGB in d, as doubles) into yr and v, raising mx. */
static inline LUMIS__ALWAYS_INLINE void group_luminance(const float *restrict p, double sc,
                                                        double d[48], double v[16],
                                                        float *restrict yr, float mx[16])
{
    for (int k = 0; k < 48; k++) d[k] = p[k];
    for (int k = 0; k < 16; k++) {
        float f = (float)(sc * (0.2126 * d[3 * k] + 0.7152 * d[3 * k + 1] + 0.0722 * d[3 * k + 2]));
        yr[k] = f;
        mx[k] = f > mx[k] ? f : mx[k];
        v[k] = f;
    }
}

/* The sum of a group's 16 values of Y, a fixed pairwise tree (v is overwritten). */
static inline LUMIS__ALWAYS_INLINE double group_sum(double v[16])
{
    for (int k = 0; k < 8; k++) v[k] += v[k + 8];
    for (int k = 0; k < 4; k++) v[k] += v[k + 4];
    return (v[0] + v[2]) + (v[1] + v[3]);
}

/* Luminance of one row of w pixels (lumis__pixel_y) into yr; returns the row's sum of Y
 * and raises *ymax.  Groups of 16 have fixed trip counts, so the compiler vectorises them
 * even at -O2 (the double arithmetic of each pixel is unchanged); the sum of a group is a
 * fixed pairwise tree and the groups are added in order. */
static inline LUMIS__ALWAYS_INLINE double
row_luminance_body(const float *restrict px, float *restrict yr, int w, double sc, float *ymax)
{
    enum { G = 16 };
    double row = 0.0;
    float mx[G];
    for (int k = 0; k < G; k++) mx[k] = *ymax;
    int i = 0;
    for (; i + G <= w; i += G, px += 3 * G) {
        double d[3 * G], v[G];
        group_luminance(px, sc, d, v, yr + i, mx);
        row += group_sum(v);
    }
    for (; i < w; i++, px += 3) {
        float f = lumis__pixel_y(px, sc);
        yr[i] = f;
        mx[0] = f > mx[0] ? f : mx[0];
        row += f;
    }
    for (int k = 0; k < G; k++) *ymax = mx[k] > *ymax ? mx[k] : *ymax;
    return row;
}

/* The sums of one tile row's stretch of n pixels, in the order every tile sum uses (pixel
 * by pixel, then weighted by the row's factors): s = (Y, Y cs, Y cc, R, G, B). */
static inline LUMIS__ALWAYS_INLINE void stretch_sums(const float *restrict px,
                                                     const float *restrict yr,
                                                     const double *restrict cs,
                                                     const double *restrict cc, int n, double s[6])
{
    double ys = 0.0, ycs = 0.0, ycc = 0.0, r = 0.0, gr = 0.0, b = 0.0;
    for (int k = 0; k < n; k++) {
        const double v = yr[k];
        ys += v;
        ycs += v * cs[k];
        ycc += v * cc[k];
        r += px[3 * k];
        gr += px[3 * k + 1];
        b += px[3 * k + 2];
    }
    s[0] = ys;
    s[1] = ycs;
    s[2] = ycc;
    s[3] = r;
    s[4] = gr;
    s[5] = b;
}

/* Adds one tile row's stretch sums to tile q, or with `first` (the tile's first row; the
 * tiles are not zeroed) assigns them. */
static inline LUMIS__ALWAYS_INLINE void tile_add(const lumis__tiles *t, size_t q, const double s[6],
                                                 double om, double a, double b, int first)
{
    const double v[7] = {s[0] * om, s[1] * a, s[0] * b, s[2] * a, s[3] * om, s[4] * om, s[5] * om};
    double *const dst[7] = {t->q[LUMIS__Q_E],  t->q[LUMIS__Q_MX], t->q[LUMIS__Q_MY],
                            t->q[LUMIS__Q_MZ], t->rgb[0],         t->rgb[1],
                            t->rgb[2]};
    for (int k = 0; k < 7; k++) dst[k][q] = first ? v[k] : dst[k][q] + v[k];
}

/* Row j (its luminance yr already computed) into the tile sums over all pixels, for any
 * tile size (row_pass does tiles of 4 with the luminance).  Tiles whose pixels are not all
 * non-emissive are summed again later (dirty_tile). */
static void row_tiles(const lumis__tiles *t, const lumis__geom *g, const float *restrict px,
                      const float *restrict yr, int j)
{
    const int T = t->T, w = g->w;
    const size_t q0 = (size_t)(j / T + 1) * ((size_t)t->tw + 1) + 1;
    const double om = g->omega[j], a = g->a[j], b = g->b[j];
    for (int tx = 0; tx < t->tw; tx++) {
        double s[6];
        const int i = tx * T, n = (tx + 1) * T < w ? T : w - i;
        stretch_sums(px + 3 * i, yr + i, g->cs + i, g->cc + i, n, s);
        tile_add(t, q0 + (size_t)tx, s, om, a, b, j % T == 0);
    }
}

/* Four doubles: GCC's vector extensions, so that a group's four tiles' sums stay values
 * (registers) across the tile's rows rather than memory added to at every row. */
typedef double v4d __attribute__((vector_size(32)));

/* row_luminance and row_tiles in one loop, for tiles of 4, over one row of tiles (rows j0 ..
 * j0 + rows - 1, rows <= 4, j0 a multiple of 4): for each group of 16 columns, the four
 * tiles' sums are carried in registers through the rows (lane u the group's u-th tile) and
 * stored once.  Every sum is the one of stretch_sums then tile_add, in the same order (a
 * tile's first row assigns, the others add), and Y is row_luminance's, bit for bit.  yr
 * receives the rows' luminance (row t at yr + t w), rowsum their sums of Y. */
static inline LUMIS__ALWAYS_INLINE void row_pass_body(const lumis__tiles *t, const lumis__geom *g,
                                                      const float *restrict px, float *restrict yr,
                                                      int j0, int rows, float *ymax,
                                                      double *restrict rowsum)
{
    enum { G = 16 };
    const int w = g->w;
    const size_t W = (size_t)w;
    const double sc = g->scale;
    const size_t q0 = (size_t)(j0 / 4 + 1) * ((size_t)t->tw + 1) + 1;
    double *restrict tE = t->q[LUMIS__Q_E] + q0, *restrict tX = t->q[LUMIS__Q_MX] + q0,
                     *restrict tY = t->q[LUMIS__Q_MY] + q0, *restrict tZ = t->q[LUMIS__Q_MZ] + q0,
                     *restrict tR = t->rgb[0] + q0, *restrict tG = t->rgb[1] + q0,
                     *restrict tB = t->rgb[2] + q0;
    float mx[G];
    for (int k = 0; k < G; k++) mx[k] = *ymax;
    for (int r = 0; r < rows; r++) rowsum[r] = 0.0;
    int i = 0;
    for (; i + G <= w; i += G) {
        const double *cs = g->cs + i, *cc = g->cc + i;
        /* CS[k], CC[k]: the k-th column's factor of each of the four tiles */
        v4d CS[4], CC[4];
        for (int k = 0; k < 4; k++) {
            CS[k] = (v4d){cs[k], cs[4 + k], cs[8 + k], cs[12 + k]};
            CC[k] = (v4d){cc[k], cc[4 + k], cc[8 + k], cc[12 + k]};
        }
        v4d E = {0}, X = {0}, Y = {0}, Z = {0}, R = {0}, Gr = {0}, B = {0};
        for (int r = 0; r < rows; r++) {
            const int j = j0 + r;
            const double om = g->omega[j], a = g->a[j], b = g->b[j];
            double d[3 * G], v[G];
            group_luminance(px + (size_t)r * 3 * W + 3 * (size_t)i, sc, d, v,
                            yr + (size_t)r * W + (size_t)i, mx);
            v4d ys = {v[0], v[4], v[8], v[12]}, ycs = ys * CS[0], ycc = ys * CC[0];
            v4d rr = {d[0], d[12], d[24], d[36]}, rg = {d[1], d[13], d[25], d[37]},
                rb = {d[2], d[14], d[26], d[38]};
            for (int k = 1; k < 4; k++) {
                const v4d vk = {v[k], v[4 + k], v[8 + k], v[12 + k]};
                ys += vk;
                ycs += vk * CS[k];
                ycc += vk * CC[k];
                rr += (v4d){d[3 * k], d[3 * k + 12], d[3 * k + 24], d[3 * k + 36]};
                rg += (v4d){d[3 * k + 1], d[3 * k + 13], d[3 * k + 25], d[3 * k + 37]};
                rb += (v4d){d[3 * k + 2], d[3 * k + 14], d[3 * k + 26], d[3 * k + 38]};
            }
            if (r == 0) { /* the tiles are not zeroed: their first row assigns */
                E = ys * om;
                X = ycs * a;
                Y = ys * b;
                Z = ycc * a;
                R = rr * om;
                Gr = rg * om;
                B = rb * om;
            } else {
                E += ys * om;
                X += ycs * a;
                Y += ys * b;
                Z += ycc * a;
                R += rr * om;
                Gr += rg * om;
                B += rb * om;
            }
            rowsum[r] += group_sum(v);
        }
        const int tx = i / 4;
        memcpy(tE + tx, &E, sizeof E);
        memcpy(tX + tx, &X, sizeof X);
        memcpy(tY + tx, &Y, sizeof Y);
        memcpy(tZ + tx, &Z, sizeof Z);
        memcpy(tR + tx, &R, sizeof R);
        memcpy(tG + tx, &Gr, sizeof Gr);
        memcpy(tB + tx, &B, sizeof B);
    }
    const int i0 = i;
    for (int r = 0; r < rows; r++) {
        const int j = j0 + r;
        const float *p = px + (size_t)r * 3 * W;
        float *y = yr + (size_t)r * W;
        for (int c = i0; c < w; c++) {
            float f = lumis__pixel_y(p + 3 * (size_t)c, sc);
            y[c] = f;
            mx[0] = f > mx[0] ? f : mx[0];
            rowsum[r] += f;
        }
        for (int tx = i0 / 4; tx < t->tw; tx++) {
            double s[6];
            const int c0 = tx * 4, n = c0 + 4 < w ? 4 : w - c0;
            stretch_sums(p + 3 * c0, y + c0, g->cs + c0, g->cc + c0, n, s);
            tile_add(t, q0 + (size_t)tx, s, g->omega[j], g->a[j], g->b[j], r == 0);
        }
    }
    for (int k = 0; k < G; k++) *ymax = mx[k] > *ymax ? mx[k] : *ymax;
}

/* The two passes for AVX2 and the baseline (internal.h), picked per call. */
#if LUMIS__MULTIVERSION
static LUMIS__TARGET_AVX2 double row_luminance_avx2(const float *restrict px, float *restrict yr,
                                                    int w, double sc, float *ymax)
{
    return row_luminance_body(px, yr, w, sc, ymax);
}

static LUMIS__TARGET_AVX2 void row_pass_avx2(const lumis__tiles *t, const lumis__geom *g,
                                             const float *restrict px, float *restrict yr, int j0,
                                             int rows, float *ymax, double *restrict rowsum)
{
    row_pass_body(t, g, px, yr, j0, rows, ymax, rowsum);
}
#endif

static double row_luminance(const float *restrict px, float *restrict yr, int w, double sc,
                            float *ymax)
{
#if LUMIS__MULTIVERSION
    if (lumis__simd_level() >= LUMIS__SIMD_AVX2) return row_luminance_avx2(px, yr, w, sc, ymax);
#endif
    return row_luminance_body(px, yr, w, sc, ymax);
}

static void row_pass(const lumis__tiles *t, const lumis__geom *g, const float *restrict px,
                     float *restrict yr, int j0, int rows, float *ymax, double *restrict rowsum)
{
#if LUMIS__MULTIVERSION
    if (lumis__simd_level() >= LUMIS__SIMD_AVX2) {
        row_pass_avx2(t, g, px, yr, j0, rows, ymax, rowsum);
        return;
    }
#endif
    row_pass_body(t, g, px, yr, j0, rows, ymax, rowsum);
}

/* Tile (tx, ty) summed again over its non-emissive pixels only. */
void lumis__decomp_dirty_tile(const lumis__tiles *t, const lumis__decomp *dc, int tx, int ty)
{
    const lumis__geom *g = dc->g;
    const int T = t->T, w = g->w;
    const size_t q = (size_t)(ty + 1) * ((size_t)t->tw + 1) + (size_t)tx + 1;
    for (int k = 0; k < LUMIS__Q_COUNT; k++) t->q[k][q] = 0.0;
    for (int k = 0; k < 3; k++) t->rgb[k][q] = 0.0;
    const int i0 = tx * T, i1 = i0 + T < w ? i0 + T : w;
    const int j1 = (ty + 1) * T < g->h ? (ty + 1) * T : g->h;
    for (int j = ty * T; j < j1; j++) {
        const size_t o = (size_t)j * (size_t)w;
        double s[6] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        int n = 0;
        for (int i = i0; i < i1; i++) {
            if (!lumis__non_emissive(dc, o + (size_t)i)) continue;
            const double v = lumis__pixel_y(dc->env->pixels + (o + (size_t)i) * 3, g->scale);
            const float *px = dc->env->pixels + (o + (size_t)i) * 3;
            s[0] += v;
            s[1] += v * g->cs[i];
            s[2] += v * g->cc[i];
            s[3] += px[0];
            s[4] += px[1];
            s[5] += px[2];
            n++;
        }
        tile_add(t, q, s, g->omega[j], g->a[j], g->b[j], 0);
        t->q[LUMIS__Q_N][q] += n;
    }
}

/* Every tile's pixel count (the non-emissive count of a tile without emissive pixels). */
static void tile_counts(const lumis__tiles *t, int w, int h)
{
    const int T = t->T;
    for (int ty = 0; ty < t->th; ty++) {
        const int ny = (ty + 1) * T < h ? T : h - ty * T;
        double *row = t->q[LUMIS__Q_N] + (size_t)(ty + 1) * ((size_t)t->tw + 1) + 1;
        for (int tx = 0; tx < t->tw; tx++) {
            const int nx = (tx + 1) * T < w ? T : w - tx * T;
            row[tx] = (double)(nx * ny);
        }
    }
}

/* Every pixel's luminance into *out (malloc'ed), when the gathered pixels do not settle
 * Eq. 1: a second pass over the map. */
static lumis_status full_luminance(const lumis_envmap *env, const lumis__geom *g, float **out)
{
    const size_t w = (size_t)g->w;
    float *y = malloc(w * (size_t)g->h * sizeof(float));
    if (!y) return LUMIS_ERR_OUT_OF_MEMORY;
    float ymax = 0.0f;
    for (size_t j = 0; j < (size_t)g->h; j++)
        (void)row_luminance(env->pixels + j * w * 3, y + j * w, g->w, g->scale, &ymax);
    *out = y;
    return LUMIS_OK;
}

/* The gathered pixels replaced by every pixel over lt, from the whole map's luminance. */
static lumis_status full_candidates(bracket *b, const float *y, size_t n, double lt)
{
    size_t c = 0;
    for (size_t p = 0; p < n; p++) c += (double)y[p] > lt;
    if (c > b->cap) {
        int32_t *idx = realloc(b->idx, c * sizeof(int32_t));
        if (idx) b->idx = idx;
        float *val = idx ? realloc(b->val, c * sizeof(float)) : NULL;
        if (!val) return LUMIS_ERR_OUT_OF_MEMORY;
        b->val = val;
        b->cap = c;
    }
    b->nc = 0;
    for (size_t p = 0; p < n; p++)
        if ((double)y[p] > lt) {
            b->idx[b->nc] = (int32_t)p;
            b->val[b->nc++] = y[p];
        }
    return LUMIS_OK;
}

/* The emissive pixels (the gathered over lt, in scan order): em_pix, their labels (their
 * indices), em_bits, and per row (rowsum[h + j], rowsum[2 h + j]) their luminance and
 * count. */
static lumis_status classify(lumis__decomp *dc, const bracket *b, double lt, double *rowsum)
{
    const size_t n = (size_t)dc->w * (size_t)dc->h, h = (size_t)dc->h;
    size_t m = 0;
    for (size_t c = 0; c < b->nc; c++) m += (double)b->val[c] > lt;
    uint64_t *bits = calloc((n + 63) / 64, sizeof(uint64_t));
    dc->em_pix = malloc((m > 0 ? m : 1) * sizeof(int32_t));
    dc->em_bits = bits;
    if (!bits || !dc->em_pix) return LUMIS_ERR_OUT_OF_MEMORY;
    int e = 0;
    for (size_t c = 0; c < b->nc; c++) {
        if (!((double)b->val[c] > lt)) continue;
        const int32_t p = b->idx[c];
        const size_t j = (size_t)p / (size_t)dc->w;
        dc->em_pix[e] = p;
        dc->labels[p] = e++;
        bits[(size_t)p >> 6] |= (uint64_t)1 << ((size_t)p & 63);
        rowsum[h + j] += b->val[c];
        rowsum[2 * h + j] += 1.0;
    }
    dc->m = e;
    return LUMIS_OK;
}

/* Eq. 1 and the classification, in one pass over the pixels (and a second only when the
 * bracket missed): the map's luminance statistics and L_T into info; per row, rowsum[j] its
 * luminance, rowsum[h + j] and rowsum[2 h + j] its emissive pixels' luminance and count;
 * the tiles' sums over all their pixels (the tiles holding emissive pixels are summed again
 * by lumis__decomp_dirty_tile once the returned pixels are known); the emissive pixels into
 * dc (em_pix, em_bits, m, and their labels). */
lumis_status lumis__decomp_threshold(lumis__decomp *dc, lumis__tiles *tiles, double *rowsum,
                                     lumis_light_set_info *info)
{
    const lumis__geom *g = dc->g;
    const lumis_envmap *env = dc->env;
    const lumis_decomp_desc *desc = dc->desc;
    const int w = g->w, h = g->h;
    const size_t n = (size_t)w * (size_t)h;
    float *yrow = malloc(4 * (size_t)w * sizeof(float)), *yall = NULL; /* 4 rows */
    uint32_t *hist = calloc(65536, sizeof(uint32_t));
    bracket br;
    memset(&br, 0, sizeof br);
    lumis_status st = yrow && hist ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
    if (st != LUMIS_OK) goto out;

    /* ---- Eq. 1: L_T = max(L_b, lambda L_avg, gamma L_max) ---- */
    const double pct = desc->percentile > 0.0f ? (double)desc->percentile : 98.0;
    size_t rank = (size_t)ceil(pct / 100.0 * (double)n);
    rank = rank < 1 ? 1 : (rank > n ? n : rank);
    if ((st = bracket_init(&br, env, g->scale, n, rank, w)) != LUMIS_OK) goto out;
    double power_y = 0.0;
    float ymax = 0.0f;
    for (int j0 = 0; j0 < h; j0 += 4) { /* a row of tiles of 4 at a time */
        const int rows = h - j0 < 4 ? h - j0 : 4;
        if (tiles->T == 4) {
            row_pass(tiles, g, env->pixels + (size_t)j0 * (size_t)w * 3, yrow, j0, rows, &ymax,
                     rowsum + j0);
        } else {
            for (int r = 0; r < rows; r++) {
                const size_t o = (size_t)(j0 + r) * (size_t)w;
                rowsum[j0 + r] = row_luminance(env->pixels + o * 3, yrow + (size_t)r * (size_t)w, w,
                                               g->scale, &ymax);
                row_tiles(tiles, g, env->pixels + o * 3, yrow + (size_t)r * (size_t)w, j0 + r);
            }
        }
        for (int r = 0; r < rows; r++) {
            power_y += rowsum[j0 + r] * g->omega[j0 + r];
            bracket_row(&br, yrow + (size_t)r * (size_t)w, w, (size_t)(j0 + r) * (size_t)w);
        }
    }
    tile_counts(tiles, w, h);
    float lb = 0.0f;
    const int gathered = !br.full && br.below < rank;
    if (gathered) { /* the answer is among the gathered: select on a copy */
        float *sel = malloc((br.nc > 0 ? br.nc : 1) * sizeof(float));
        if (!sel) {
            st = LUMIS_ERR_OUT_OF_MEMORY;
            goto out;
        }
        memcpy(sel, br.val, br.nc * sizeof(float));
        lb = kth_smallest(sel, (ptrdiff_t)br.nc, (ptrdiff_t)(rank - br.below - 1));
        free(sel);
    } else {
        if ((st = full_luminance(env, g, &yall)) != LUMIS_OK) goto out;
        lb = select_rank_radix(yall, n, rank, hist);
    }
    info->percentile_luminance = lb;
    info->avg_luminance = power_y / (4.0 * LUMIS_PI);
    info->max_luminance = ymax;
    const double lambda = desc->lambda > 0.0f ? (double)desc->lambda : 3.0,
                 gamma = desc->gamma > 0.0f ? (double)desc->gamma : 0.001;
    double lt = fmax((double)lb, fmax(lambda * info->avg_luminance, gamma * (double)ymax));
    if (desc->threshold > 0.0f) lt = desc->threshold;
    info->threshold = lt;
    if (!gathered || !(lt >= (double)br.lo)) {
        /* the gathered may miss emissive pixels: gather them from the whole map */
        if (!yall && (st = full_luminance(env, g, &yall)) != LUMIS_OK) goto out;
        if ((st = full_candidates(&br, yall, n, lt)) != LUMIS_OK) goto out;
        free(yall);
        yall = NULL;
    }

    /* classification: the gathered over L_T are the emissive pixels */
    st = classify(dc, &br, lt, rowsum);
out:
    free(yrow);
    free(yall);
    free(hist);
    free(br.idx);
    free(br.val);
    return st;
}
