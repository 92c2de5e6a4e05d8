/* Band sums of a map: what the rectangle methods (median cut, variance minimisation) read
 * instead of the pixels.  One pass over the pixels accumulates, for every band of T rows
 * and every column, the column's sums over the band (Omega Y, a Y, b Y and Omega RGB), and
 * for every row and every band of T columns the row's sums (Y, Y cs, Y cc).  Any
 * rectangle's column or row marginals then cost O(extent x (bands + 2 T)) and its totals
 * the same, every sum a direct double sum of pixel values (no differences of running
 * totals, so a region's power is exact to its own rounding).  The accumulations are
 * element-wise along rows, so the compiler may vectorise them without reassociating a
 * sum.  docs/lights.md. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

/* The pixel pass is built for AVX-512 and AVX2 too (lumis__strips_init, internal.h): it is
 * compute-bound, not memory-bound (docs/lights.md, performance). */

enum { STRIP_T = 16, STRIP_CHUNK = 256 }; /* STRIP_CHUNK: a multiple of STRIP_T */
enum { STRIPS_GROUP = 8 };                /* fine bands per coarse band */

/* One row's stretch of n < 16 pixels (the map's last, partial column band): luminance
 * (lumis__pixel_y) into yr, the band's column sums, and the sum of Y over the stretch into
 * *ry.  Whole bands go through strip_band. */
static inline LUMIS__ALWAYS_INLINE void strip_group(const float *restrict px, float *restrict yr,
                                                    int n, double sc, double om, double aj,
                                                    double bj, double *restrict ce,
                                                    double *restrict ca, double *restrict cb,
                                                    double *restrict cr, double *restrict ry)
{
    double sy = 0.0;
    for (int k = 0; k < n; k++) {
        float f = lumis__pixel_y(px + 3 * k, sc);
        double v = f;
        yr[k] = f;
        ce[k] += om * v;
        ca[k] += aj * v;
        cb[k] += bj * v;
        for (int c = 0; c < 3; c++) cr[3 * k + c] += om * (double)px[3 * k + c];
        sy += v;
    }
    *ry = sy;
}

/* Eight doubles, eight floats: GCC's vector extensions, so that the column sums below are
 * values (registers), not arrays the compiler keeps on the stack; the AVX-512 build makes
 * each one register, the others two or four. */
typedef double v8d __attribute__((vector_size(64)));
typedef float v8f __attribute__((vector_size(32)));

/* (macros: a function returning or taking a vector would change the ABI per build) */
#define LOAD8(v, p)                                                                                \
    do {                                                                                           \
        v8f f_;                                                                                    \
        memcpy(&f_, (p), sizeof f_);                                                               \
        (v) = __builtin_convertvector(f_, v8d);                                                    \
    } while (0)
#define STORE8(p, v) memcpy((p), &(v), sizeof(v8d))

/* A whole column band of 16 columns over the rows [0, rows) of a row band: strip_group's
 * n == 16 case row after row, with the band's 96 column sums held as values across the
 * rows instead of added to memory at every row, and stored once.  The same additions in
 * the same order (each column's sum starts at 0 and adds its rows in order), so the same
 * bits.  px, yr: the band's first row; W: the map's width; om, aj, bj: the factors from
 * the band's first row; ry: the rows' stretch sums, one per row. */
static inline LUMIS__ALWAYS_INLINE void
strip_band(const float *restrict px, float *restrict yr, size_t W, int rows, double sc,
           const double *restrict om, const double *restrict aj, const double *restrict bj,
           double *restrict ce, double *restrict ca, double *restrict cb, double *restrict cr,
           double *restrict ry)
{
    const v8d z = {0};
    v8d r0 = z, r1 = z, r2 = z, r3 = z, r4 = z, r5 = z, e0 = z, e1 = z, a0 = z, a1 = z, b0 = z,
        b1 = z;
    for (int t = 0; t < rows; t++) {
        const float *p = px + (size_t)t * 3 * W;
        const double o = om[t], ja = aj[t], jb = bj[t];
        double d[3 * STRIP_T], y[STRIP_T];
        v8d d0, d1, d2, d3, d4, d5;
        LOAD8(d0, p);
        LOAD8(d1, p + 8);
        LOAD8(d2, p + 16);
        LOAD8(d3, p + 24);
        LOAD8(d4, p + 32);
        LOAD8(d5, p + 40);
        r0 += o * d0;
        r1 += o * d1;
        r2 += o * d2;
        r3 += o * d3;
        r4 += o * d4;
        r5 += o * d5;
        STORE8(d, d0);
        STORE8(d + 8, d1);
        STORE8(d + 16, d2);
        STORE8(d + 24, d3);
        STORE8(d + 32, d4);
        STORE8(d + 40, d5);
        for (int k = 0; k < STRIP_T; k++) {
            float f =
                (float)(sc * (0.2126 * d[3 * k] + 0.7152 * d[3 * k + 1] + 0.0722 * d[3 * k + 2]));
            yr[(size_t)t * W + (size_t)k] = f;
            y[k] = f;
        }
        v8d y0, y1;
        memcpy(&y0, y, sizeof y0);
        memcpy(&y1, y + 8, sizeof y1);
        e0 += o * y0;
        e1 += o * y1;
        a0 += ja * y0;
        a1 += ja * y1;
        b0 += jb * y0;
        b1 += jb * y1;
        for (int k = 0; k < 8; k++) y[k] += y[k + 8];
        for (int k = 0; k < 4; k++) y[k] += y[k + 4];
        ry[t] = (y[0] + y[2]) + (y[1] + y[3]);
    }
    STORE8(ce, e0);
    STORE8(ce + 8, e1);
    STORE8(ca, a0);
    STORE8(ca + 8, a1);
    STORE8(cb, b0);
    STORE8(cb + 8, b1);
    STORE8(cr, r0);
    STORE8(cr + 8, r1);
    STORE8(cr + 16, r2);
    STORE8(cr + 24, r3);
    STORE8(cr + 32, r4);
    STORE8(cr + 40, r5);
}

/* Sums of Y cs and Y cc over a stretch of n <= 16 pixels of a row (variance minimisation's
 * row moments), a pairwise tree when n == 16. */
static inline LUMIS__ALWAYS_INLINE void strip_moments(const float *restrict yr,
                                                      const double *restrict cs,
                                                      const double *restrict cc, int n,
                                                      double *restrict rcs, double *restrict rcc)
{
    if (n == STRIP_T) {
        double xs[STRIP_T], xc[STRIP_T];
        for (int k = 0; k < STRIP_T; k++) {
            xs[k] = (double)yr[k] * cs[k];
            xc[k] = (double)yr[k] * cc[k];
        }
        for (int k = 0; k < 8; k++) {
            xs[k] += xs[k + 8];
            xc[k] += xc[k + 8];
        }
        for (int k = 0; k < 4; k++) {
            xs[k] += xs[k + 4];
            xc[k] += xc[k + 4];
        }
        *rcs = (xs[0] + xs[2]) + (xs[1] + xs[3]);
        *rcc = (xc[0] + xc[2]) + (xc[1] + xc[3]);
        return;
    }
    double a = 0.0, c = 0.0;
    for (int k = 0; k < n; k++) {
        a += (double)yr[k] * cs[k];
        c += (double)yr[k] * cc[k];
    }
    *rcs = a;
    *rcc = c;
}

/* Coarse column sums: c = f for the group's first band, c += f for the others. */
static inline LUMIS__ALWAYS_INLINE void coarse_add(double *restrict c, const double *restrict f,
                                                   size_t n, int first)
{
    if (first)
        memcpy(c, f, n * sizeof *c);
    else
        for (size_t i = 0; i < n; i++) c[i] += f[i];
}

/* Coarse row sum of row j over group C of column bands (band-major, stride h), in order. */
static inline LUMIS__ALWAYS_INLINE void coarse_row(const double *fine, double *coarse, size_t h,
                                                   int C, int j)
{
    const double *f = fine + (size_t)C * STRIPS_GROUP * h + (size_t)j;
    double t = f[0];
    for (int k = 1; k < STRIPS_GROUP; k++) t += f[(size_t)k * h];
    coarse[(size_t)C * h + (size_t)j] = t;
}

/* out[i] += the sum over bands [b0, b1) of band[b][off + i] for i < n, coarse bands where
 * a whole group lies inside (stride: a band's length). */
static void add_bands(const double *fine, const double *coarse, size_t stride, int b0, int b1,
                      size_t off, int n, double *restrict out)
{
    const int B0 = (b0 + STRIPS_GROUP - 1) / STRIPS_GROUP, B1 = b1 / STRIPS_GROUP;
    const int f1 = B0 < B1 ? B0 * STRIPS_GROUP : b1;
    for (int b = b0; b < f1; b++) {
        const double *f = fine + (size_t)b * stride + off;
        for (int i = 0; i < n; i++) out[i] += f[i];
    }
    if (B0 >= B1) return;
    for (int B = B0; B < B1; B++) {
        const double *c = coarse + (size_t)B * stride + off;
        for (int i = 0; i < n; i++) out[i] += c[i];
    }
    for (int b = B1 * STRIPS_GROUP; b < b1; b++) {
        const double *f = fine + (size_t)b * stride + off;
        for (int i = 0; i < n; i++) out[i] += f[i];
    }
}

static inline LUMIS__ALWAYS_INLINE lumis_status strips_init(lumis__strips *s, const lumis__geom *g,
                                                            const lumis_envmap *env,
                                                            int row_moments)
{
    memset(s, 0, sizeof *s);
    const int w = g->w, h = g->h, T = STRIP_T;
    s->w = w;
    s->h = h;
    s->T = T;
    s->nb = (h + T - 1) / T;
    s->nc = (w + T - 1) / T;
    s->g = g;
    s->env = env;
    /* row sums band-major with a stride of h plus one cache line: with a stride of a power of
     * two, a row's bands would all fall in one cache set */
    s->hs = (size_t)h + 8;
    const size_t HS = s->hs;
    const size_t W = (size_t)w, nb = (size_t)s->nb, rows = HS * (size_t)s->nc;
    s->nB = h / T / STRIPS_GROUP;
    s->nC = w / T / STRIPS_GROUP;
    const size_t coarse = 6 * (size_t)s->nB * W + 3 * (size_t)s->nC * HS;
    size_t total =
        6 * nb * W + (row_moments ? 3 : 1) * rows + 7 * (W > (size_t)h ? W : (size_t)h) + coarse;
    double *mem = malloc(total * sizeof(double));
    float *yf = malloc((size_t)w * (size_t)h * sizeof(float));
    if (!mem || !yf) {
        free(mem);
        free(yf);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    s->y = yf;
    s->ce = mem;
    s->ca = s->ce + nb * W;
    s->cb = s->ca + nb * W;
    s->crgb = s->cb + nb * W;
    s->ry = s->crgb + 3 * nb * W;
    s->rcs = row_moments ? s->ry + rows : NULL;
    s->rcc = row_moments ? s->rcs + rows : NULL;
    s->scratch = (row_moments ? s->rcc : s->ry) + rows;
    s->scratch_n = 7 * (W > (size_t)h ? W : (size_t)h);
    s->ce2 = s->scratch + s->scratch_n;
    s->ca2 = s->ce2 + (size_t)s->nB * W;
    s->cb2 = s->ca2 + (size_t)s->nB * W;
    s->ry2 = s->cb2 + (size_t)s->nB * W;
    s->rcs2 = s->ry2 + (size_t)s->nC * HS;
    s->rcc2 = s->rcs2 + (size_t)s->nC * HS;
    s->crgb2 = s->rcc2 + (size_t)s->nC * HS;

    for (int b = 0; b < s->nb; b++) {
        const int j0 = b * T, j1 = j0 + T < h ? j0 + T : h;
        /* Column chunks whose band sums stay in L1 across the band's rows (zeroed there, not
         * in a pass of their own); a chunk holds whole groups of column bands. */
        for (int x0 = 0; x0 < w; x0 += STRIP_CHUNK) {
            const int x1 = x0 + STRIP_CHUNK < w ? x0 + STRIP_CHUNK : w;
            const size_t o = (size_t)b * W + (size_t)x0, nx = (size_t)(x1 - x0);
            /* row sums are stored band-major, [c][j]: see lumis__strips_rows */
            for (int i = x0, c = 0; i < x1; i += T, c++) {
                const size_t q = (size_t)(i - x0), p0 = (size_t)j0 * W + (size_t)x0 + q;
                const size_t rq = (size_t)(x0 / T + c) * HS + (size_t)j0;
                if (x1 - i >= T) { /* a whole column band: its sums in registers */
                    strip_band(env->pixels + p0 * 3, yf + p0, W, j1 - j0, g->scale, g->omega + j0,
                               g->a + j0, g->b + j0, s->ce + o + q, s->ca + o + q, s->cb + o + q,
                               s->crgb + (o + q) * 3, &s->ry[rq]);
                    continue;
                }
                const int n = x1 - i;
                memset(s->ce + o + q, 0, (size_t)n * sizeof(double));
                memset(s->ca + o + q, 0, (size_t)n * sizeof(double));
                memset(s->cb + o + q, 0, (size_t)n * sizeof(double));
                memset(s->crgb + 3 * (o + q), 0, 3 * (size_t)n * sizeof(double));
                for (int j = j0; j < j1; j++) {
                    const size_t p = p0 + (size_t)(j - j0) * W;
                    strip_group(env->pixels + p * 3, yf + p, n, g->scale, g->omega[j], g->a[j],
                                g->b[j], s->ce + o + q, s->ca + o + q, s->cb + o + q,
                                s->crgb + (o + q) * 3, &s->ry[rq + (size_t)(j - j0)]);
                }
            }
            /* the coarse row sums of the chunk's whole groups */
            for (int j = j0; j < j1; j++)
                for (int C = x0 / T / STRIPS_GROUP; C < s->nC && C * STRIPS_GROUP * T < x1; C++)
                    coarse_row(s->ry, s->ry2, HS, C, j);
            if (row_moments)
                for (int j = j0; j < j1; j++) {
                    const size_t p = (size_t)j * W + (size_t)x0;
                    const size_t rb = (size_t)(x0 / T) * HS + (size_t)j;
                    for (int i = x0, c = 0; i < x1; i += T, c++) {
                        const size_t rq = rb + (size_t)c * HS;
                        const int n = x1 - i < T ? x1 - i : T;
                        strip_moments(yf + p + (size_t)(i - x0), g->cs + i, g->cc + i, n,
                                      &s->rcs[rq], &s->rcc[rq]);
                    }
                    for (int C = x0 / T / STRIPS_GROUP; C < s->nC && C * STRIPS_GROUP * T < x1;
                         C++) {
                        coarse_row(s->rcs, s->rcs2, HS, C, j);
                        coarse_row(s->rcc, s->rcc2, HS, C, j);
                    }
                }
            /* the band's coarse column sums, added in band order */
            if (b < s->nB * STRIPS_GROUP) {
                const size_t co = (size_t)(b / STRIPS_GROUP) * W + (size_t)x0;
                const int first = b % STRIPS_GROUP == 0;
                coarse_add(s->ce2 + co, s->ce + o, nx, first);
                coarse_add(s->ca2 + co, s->ca + o, nx, first);
                coarse_add(s->cb2 + co, s->cb + o, nx, first);
                coarse_add(s->crgb2 + 3 * co, s->crgb + 3 * o, 3 * nx, first);
            }
        }
    }
    return LUMIS_OK;
}

#if LUMIS__MULTIVERSION
static LUMIS__TARGET_AVX512 lumis_status strips_init_avx512(lumis__strips *s, const lumis__geom *g,
                                                            const lumis_envmap *env,
                                                            int row_moments)
{
    return strips_init(s, g, env, row_moments);
}

static LUMIS__TARGET_AVX2 lumis_status strips_init_avx2(lumis__strips *s, const lumis__geom *g,
                                                        const lumis_envmap *env, int row_moments)
{
    return strips_init(s, g, env, row_moments);
}
#endif

lumis_status lumis__strips_init(lumis__strips *s, const lumis__geom *g, const lumis_envmap *env,
                                int row_moments)
{
#if LUMIS__MULTIVERSION
    switch (lumis__simd_level()) {
    case LUMIS__SIMD_AVX512:
        return strips_init_avx512(s, g, env, row_moments);
    case LUMIS__SIMD_AVX2:
        return strips_init_avx2(s, g, env, row_moments);
    default:
        break;
    }
#endif
    return strips_init(s, g, env, row_moments);
}

void lumis__strips_free(lumis__strips *s)
{
    free(s->ce);
    free(s->y);
    s->ce = NULL;
    s->y = NULL;
}

/* Adds rows [j0, j1) of columns [x0, x1) to the per-column sums, from the pixels. */
static void direct_rows(const lumis__strips *s, int j0, int j1, int x0, int x1, double *e,
                        double *a, double *b, double *rgb)
{
    const lumis__geom *g = s->g;
    for (int j = j0; j < j1; j++) {
        const size_t o = (size_t)j * (size_t)s->w + (size_t)x0;
        const float *yr = s->y + o;
        const double om = g->omega[j], aj = g->a[j], bj = g->b[j];
        const int n = x1 - x0;
        if (rgb) {
            const float *px = s->env->pixels + o * 3;
            double r = 0.0, gg = 0.0, bl = 0.0;
            for (int i = 0; i < n; i++, px += 3) {
                r += (double)px[0];
                gg += (double)px[1];
                bl += (double)px[2];
            }
            rgb[0] += om * r;
            rgb[1] += om * gg;
            rgb[2] += om * bl;
            continue;
        }
        for (int i = 0; i < n; i++) e[i] += om * (double)yr[i];
        if (a)
            for (int i = 0; i < n; i++) a[i] += aj * (double)yr[i];
        if (b)
            for (int i = 0; i < n; i++) b[i] += bj * (double)yr[i];
    }
}

void lumis__strips_cols(const lumis__strips *s, lumis__rect r, double *e, double *a, double *b)
{
    const int n = r.x1 - r.x0, T = s->T;
    const size_t W = (size_t)s->w;
    for (int i = 0; i < n; i++) {
        e[i] = 0.0;
        if (a) a[i] = 0.0;
        if (b) b[i] = 0.0;
    }
    int b0 = (r.y0 + T - 1) / T, b1 = r.y1 / T;
    if (b0 >= b1) {
        direct_rows(s, r.y0, r.y1, r.x0, r.x1, e, a, b, NULL);
        return;
    }
    add_bands(s->ce, s->ce2, W, b0, b1, (size_t)r.x0, n, e);
    if (a) add_bands(s->ca, s->ca2, W, b0, b1, (size_t)r.x0, n, a);
    if (b) add_bands(s->cb, s->cb2, W, b0, b1, (size_t)r.x0, n, b);
    direct_rows(s, r.y0, b0 * T, r.x0, r.x1, e, a, b, NULL);
    direct_rows(s, b1 * T, r.y1, r.x0, r.x1, e, a, b, NULL);
}

/* The row sums are stored band-major (ry[c h + j] for column band c and row j), so the
 * bands add into all rows of a rectangle elementwise (vectorised, no chain of additions
 * per row); each row's sum still takes its bands in order, then its direct stretches. */
void lumis__strips_rows(const lumis__strips *s, lumis__rect r, double *y, double *ycs, double *ycc)
{
    const int T = s->T, n = r.y1 - r.y0;
    const size_t H = s->hs;
    const lumis__geom *g = s->g;
    const int c0 = (r.x0 + T - 1) / T, c1 = r.x1 / T;
    int d0 = r.x1, d1 = r.x1; /* the direct stretches: [x0, d0) and [d1, x1) */
    for (int k = 0; k < n; k++) {
        y[k] = 0.0;
        if (ycs) ycs[k] = ycc[k] = 0.0;
    }
    if (c0 < c1) {
        add_bands(s->ry, s->ry2, H, c0, c1, (size_t)r.y0, n, y);
        if (ycs) {
            add_bands(s->rcs, s->rcs2, H, c0, c1, (size_t)r.y0, n, ycs);
            add_bands(s->rcc, s->rcc2, H, c0, c1, (size_t)r.y0, n, ycc);
        }
        d0 = c0 * T;
        d1 = c1 * T;
    }
    for (int k = 0; k < n; k++) {
        const float *row = s->y + (size_t)(r.y0 + k) * (size_t)s->w;
        double sy = y[k], sx = ycs ? ycs[k] : 0.0, sz = ycs ? ycc[k] : 0.0;
        for (int pass = 0; pass < 2; pass++) {
            int i0 = pass ? d1 : r.x0, i1 = pass ? r.x1 : d0;
            for (int i = i0; i < i1; i++) {
                double v = row[i];
                sy += v;
                if (ycs) {
                    sx += v * g->cs[i];
                    sz += v * g->cc[i];
                }
            }
        }
        y[k] = sy;
        if (ycs) {
            ycs[k] = sx;
            ycc[k] = sz;
        }
    }
}

void lumis__strips_rect(const lumis__strips *s, lumis__rect r, lumis__acc *acc)
{
    const lumis__geom *g = s->g;
    const int n = r.x1 - r.x0, T = s->T;
    const size_t W = (size_t)s->w;
    double *e = s->scratch, *a = e + W, *b = a + W;
    lumis__strips_cols(s, r, e, a, b);
    memset(acc, 0, sizeof *acc);
    double mx = 0.0, my = 0.0, mz = 0.0;
    for (int i = 0; i < n; i++) {
        mx += a[i] * g->cs[r.x0 + i];
        my += b[i];
        mz += a[i] * g->cc[r.x0 + i];
    }
    acc->m[0] = mx;
    acc->m[1] = my;
    acc->m[2] = mz;
    double rgb[3] = {0.0, 0.0, 0.0};
    int b0 = (r.y0 + T - 1) / T, b1 = r.y1 / T;
    if (b0 >= b1) {
        direct_rows(s, r.y0, r.y1, r.x0, r.x1, NULL, NULL, NULL, rgb);
    } else {
        /* each column's RGB over the bands (elementwise, so vectorised), then the columns */
        double *cr = b + W;
        for (int i = 0; i < 3 * n; i++) cr[i] = 0.0;
        add_bands(s->crgb, s->crgb2, 3 * W, b0, b1, 3 * (size_t)r.x0, 3 * n, cr);
        for (int i = 0; i < n; i++) {
            rgb[0] += cr[3 * i];
            rgb[1] += cr[3 * i + 1];
            rgb[2] += cr[3 * i + 2];
        }
        direct_rows(s, r.y0, b0 * T, r.x0, r.x1, NULL, NULL, NULL, rgb);
        direct_rows(s, b1 * T, r.y1, r.x0, r.x1, NULL, NULL, NULL, rgb);
    }
    for (int c = 0; c < 3; c++) acc->rgb[c] = rgb[c];
    lumis__acc_rect_geometry(g, r, acc);
    acc->pixels = n * (r.y1 - r.y0);
}

void lumis__lights_from_strips(lumis_light_set *set, const lumis__strips *s,
                               const lumis__rect *rects, int k)
{
    const lumis__geom *g = s->g;
    /* a row of label q, past lumis__strips_rect's part of the scratch */
    int32_t *fill = (int32_t *)(void *)(s->scratch + 6 * (size_t)(s->w > s->h ? s->w : s->h));
    for (int q = 0; q < k; q++) {
        const lumis__rect r = rects[q];
        const size_t n = (size_t)(r.x1 - r.x0);
        for (size_t i = 0; i < n; i++) fill[i] = q;
        for (int j = r.y0; j < r.y1; j++)
            memcpy(set->labels + (size_t)j * (size_t)s->w + (size_t)r.x0, fill, n * sizeof *fill);
        lumis__acc acc;
        lumis__strips_rect(s, r, &acc);
        lumis_light *l = &set->lights[q];
        lumis__light_from_acc(g, &acc, LUMIS_LIGHT_REGION, l);
        double d[3];
        lumis__light_map_dir(g, l, d);
        l->extent = lumis__extent_from_min_dot(lumis__rect_min_dot(g, d, r.y0, r.y1, r.x0, r.x1));
    }
}
