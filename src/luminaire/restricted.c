/* The restricted sampler (Lu et al., Eq. 6-10): one image's luminance restricted to the box
 * its basis function's support projects to from the shading point, inverted exactly from
 * the image's summed-area table by the modified secant search or by bisection.  Density per
 * unit area on S.  Derivation: docs/luminaire.md, "Restricted CDFs". */
#include "internal.h"

#include <math.h>

/* x in [0, n] as a cell and a fraction: i in [0, n - 1], f in [0, 1] (x == n -> n - 1, 1). */
static inline void split(double x, int n, int *i, double *f)
{
    int k = x > 0.0 ? (int)x : 0; /* x <= n: truncation is floor, without a libm call */
    if (k > n - 1) k = n - 1;
    if (k < 0) k = 0;
    *i = k;
    *f = x - k;
}

/* ceil(x) - 1 for x in (0, n]: the last cell a range ending at x covers. */
static inline int last_cell(double x)
{
    const int k = (int)x;
    return (double)k == x ? k - 1 : k;
}

static inline const uint32_t *table(const lumis_luminaire *l, int m)
{
    return l->sat + (size_t)m * ((size_t)l->w + 1) * ((size_t)l->h + 1);
}

double lumis__lum_box_units(const lumis_luminaire *l, int m, const lumis__box *b)
{
    lumis__span x, y;
    lumis__lum_span(b->x0, b->x1, l->w, &x);
    lumis__lum_span(b->y0, b->y1, l->h, &y);
    return lumis__lum_span_units(l, m, &x, &y);
}

/* Inline so that lumis__lum_span_units_d shares its 16 loads. */
static inline double span_units(const lumis_luminaire *l, int m, const lumis__span *x,
                                const lumis__span *y)
{
    const uint32_t *t = table(l, m);
    const size_t st = (size_t)l->h + 1;
    const int i0 = x->i0, i1 = x->i1, j0 = y->i0, j1 = y->i1;
    const double f0 = x->f0, f1 = x->f1, g0 = y->f0, g1 = y->f1;
#define S(i, j) ((int64_t)t[(size_t)(i)*st + (size_t)(j)])
    /* F(i + f, j + g) = S + f R + g Q + f g C (exact for piecewise-constant pixels); the
     * integer differences are grouped first, so a box over zero pixels gives exactly 0. */
    const int64_t whole = S(i1, j1) - S(i0, j1) - S(i1, j0) + S(i0, j0);
    const int64_t r11 = S(i1 + 1, j1) - S(i1, j1), r10 = S(i1 + 1, j0) - S(i1, j0);
    const int64_t r01 = S(i0 + 1, j1) - S(i0, j1), r00 = S(i0 + 1, j0) - S(i0, j0);
    const int64_t q11 = S(i1, j1 + 1) - S(i1, j1), q01 = S(i0, j1 + 1) - S(i0, j1);
    const int64_t q10 = S(i1, j0 + 1) - S(i1, j0), q00 = S(i0, j0 + 1) - S(i0, j0);
    const int64_t c11 = S(i1 + 1, j1 + 1) - S(i1 + 1, j1) - q11;
    const int64_t c01 = S(i0 + 1, j1 + 1) - S(i0 + 1, j1) - q01;
    const int64_t c10 = S(i1 + 1, j0 + 1) - S(i1 + 1, j0) - q10;
    const int64_t c00 = S(i0 + 1, j0 + 1) - S(i0 + 1, j0) - q00;
#undef S
    double a = (double)whole + f1 * (double)(r11 - r10) - f0 * (double)(r01 - r00) +
               g1 * (double)(q11 - q01) - g0 * (double)(q10 - q00) + f1 * g1 * (double)c11 -
               f0 * g1 * (double)c01 - f1 * g0 * (double)c10 + f0 * g0 * (double)c00;
    return a > 0.0 ? a : 0.0;
}

double lumis__lum_span_units(const lumis_luminaire *l, int m, const lumis__span *x,
                             const lumis__span *y)
{
    return span_units(l, m, x, y);
}

/* D at column c (a pointer to the table's column): the units of the columns before it
 * between rows j0 + g0 and j1 + g1.  The one formula of the marginal, wherever read. */
static inline double marginal_at(const uint32_t *c, int j0, int j1, double g0, double g1)
{
    const double a = (double)c[j1] - (double)c[j0];
    return a + g1 * (double)(c[j1 + 1] - c[j1]) - g0 * (double)(c[j0 + 1] - c[j0]);
}

double lumis__lum_span_units_d(const lumis_luminaire *l, int m, const lumis__span *x,
                               const lumis__span *y, double d[4])
{
    const uint32_t *t = table(l, m);
    const size_t st = (size_t)l->h + 1;
    const int j0 = y->i0, j1 = y->i1;
    const double g0 = y->f0, g1 = y->f1;
    d[0] = marginal_at(t + (size_t)x->i0 * st, j0, j1, g0, g1);
    d[1] = marginal_at(t + (size_t)(x->i0 + 1) * st, j0, j1, g0, g1);
    d[2] = marginal_at(t + (size_t)x->i1 * st, j0, j1, g0, g1);
    d[3] = marginal_at(t + (size_t)(x->i1 + 1) * st, j0, j1, g0, g1);
    return span_units(l, m, x, y);
}

/* ---- 1D inversion ------------------------------------------------------------------ */

/* The two monotone functions searched: the restricted marginal over columns, D(i) = the
 * units in columns < i between rows y0 and y1 (2 x 2 lookups, adjacent pairs), and a
 * column's prefix P(j) = the units of column i in rows < j (2 lookups). */
typedef struct line {
    const uint32_t *t;
    size_t st;
    int kind; /* 0: D over columns, 1: P over rows of column col */
    int j0, j1;
    double g0, g1;
    const uint32_t *c0, *c1; /* column col and col + 1 of the table */
} line;

static inline double probe(const line *L, int k)
{
    if (L->kind == 0) return marginal_at(L->t + (size_t)k * L->st, L->j0, L->j1, L->g0, L->g1);
    return (double)(L->c1[k] - L->c0[k]);
}

/* The continuous position x in [lo, hi + 1) where the piecewise-linear interpolant of
 * f (f(lo) = flo <= g < f(hi + 1) = fhi) reaches g.
 *
 * Secant (Lu et al.'s modified secant search, Fig. 5): the next probe is the cell where the
 * chord between the bracket's ends crosses g; a step that fails to halve the bracket is
 * followed by a bisection step, so the worst case stays within twice bisection's probes.
 * Binary: bisection.  depth > 0 limits the probes; the result is then the chord's
 * crossing within the bracket reached (approximate). */
/* Where the chord from (lo, flo) to (hi + 1, fhi) reaches g. */
static inline double chord(int lo, int hi, double flo, double fhi, double g)
{
    double t = fhi > flo ? (g - flo) / (fhi - flo) : 0.5;
    if (!(t >= 0.0)) t = 0.0;
    if (t > 0x1.fffffffffffffp-1) t = 0x1.fffffffffffffp-1;
    return lo + t * (hi + 1 - lo);
}

static inline double search(const line *L, int lo, int hi, double flo, double fhi, double g,
                            int secant, int depth)
{
    if (!secant) {
        /* Bisection without branches on the data (the comparisons become conditional
         * moves): the bracket [lo, lo + n) halves each probe, and its ends are read once at
         * the end. */
        int n = hi + 1 - lo, probes = 0;
        while (n > 1 && (depth <= 0 || probes < depth)) {
            const int half = n / 2;
            lo = probe(L, lo + half) <= g ? lo + half : lo;
            n -= half;
            probes++;
        }
        return chord(lo, lo + n - 1, probe(L, lo), probe(L, lo + n), g);
    }
    int probes = 0, bisect = 0;
    while (lo < hi && (depth <= 0 || probes < depth)) {
        const int n = hi + 1 - lo;
        int mid;
        if (!bisect && fhi > flo) {
            mid = lo + (int)((g - flo) / (fhi - flo) * n);
            if (mid <= lo) mid = lo + 1;
            if (mid > hi) mid = hi;
        } else {
            mid = lo + n / 2;
        }
        const double fm = probe(L, mid);
        probes++;
        if (fm <= g) {
            lo = mid;
            flo = fm;
        } else {
            hi = mid - 1;
            fhi = fm;
        }
        bisect = !bisect && 2 * (hi + 1 - lo) > n;
    }
    return chord(lo, hi, flo, fhi, g);
}

/* What every draw of image m in box b shares, from the marginal's values d = D(i0),
 * D(i0 + 1), D(ia), D(ia + 1) at the columns of the box's ends x0 in [i0, i0 + 1) and x1 in
 * [ia, ia + 1] (ia = w - 1 for x1 = w). */
static void prepare_from(const lumis_luminaire *l, int m, const lumis__box *b, double units,
                         const double d[4], lumis_luminaire_search search_kind, int depth,
                         lumis__prep *pr)
{
    pr->m = m;
    pr->b = *b;
    pr->units = units;
    pr->uniform = 0;
    pr->tabulate = 0;
    pr->secant = search_kind == LUMIS_LUM_SECANT;
    pr->depth = depth;
    split(b->y0, l->h, &pr->j0, &pr->g0);
    split(b->y1, l->h, &pr->j1, &pr->g1);
    int i0, ia;
    double f0, fa;
    split(b->x0, l->w, &i0, &f0);
    split(b->x1, l->w, &ia, &fa);
    int ilast = last_cell(b->x1); /* last column the box covers */
    if (ilast < i0) ilast = i0;
    if (ilast > l->w - 1) ilast = l->w - 1;
    int jlast = last_cell(b->y1);
    if (jlast < pr->j0) jlast = pr->j0;
    if (jlast > l->h - 1) jlast = l->h - 1;
    pr->i0 = i0;
    pr->ilast = ilast;
    pr->jlast = jlast;
    pr->d_i0 = d[0];
    /* The bracket's top, D(ilast + 1): ilast is ia, or ia - 1 when x1 is a whole column. */
    pr->d_hi =
        ilast == ia
            ? d[3]
            : (ilast + 1 == ia ? d[2]
                               : marginal_at(table(l, m) + (size_t)(ilast + 1) * ((size_t)l->h + 1),
                                             pr->j0, pr->j1, pr->g0, pr->g1));
    /* Marginal: g between D(x0) and D(x1), D linear inside a column. */
    pr->d_x0 = d[0] + f0 * (d[1] - d[0]);
    pr->d_x1 = d[2] + fa * (d[3] - d[2]);
}

void lumis__lum_prepare_d(const lumis_luminaire *l, int m, const lumis__box *b, double units,
                          const double d[4], lumis_luminaire_search search_kind, int depth,
                          lumis__prep *pr)
{
    prepare_from(l, m, b, units, d, search_kind, depth, pr);
}

void lumis__lum_prepare(const lumis_luminaire *l, int m, const lumis__box *b, double units,
                        lumis_luminaire_strategy strategy, lumis_luminaire_search search_kind,
                        int depth, lumis__prep *pr)
{
    if (strategy == LUMIS_LUM_UNIFORM) {
        pr->m = m;
        pr->b = *b;
        pr->units = units;
        pr->uniform = 1;
        pr->tabulate = 0;
        pr->secant = search_kind == LUMIS_LUM_SECANT;
        pr->depth = depth;
        return;
    }
    int j0, j1, i0, ia;
    double g0, g1, f;
    split(b->y0, l->h, &j0, &g0);
    split(b->y1, l->h, &j1, &g1);
    split(b->x0, l->w, &i0, &f);
    split(b->x1, l->w, &ia, &f);
    const uint32_t *t = table(l, m);
    const size_t st = (size_t)l->h + 1;
    const double d[4] = {marginal_at(t + (size_t)i0 * st, j0, j1, g0, g1),
                         marginal_at(t + (size_t)(i0 + 1) * st, j0, j1, g0, g1),
                         marginal_at(t + (size_t)ia * st, j0, j1, g0, g1),
                         marginal_at(t + (size_t)(ia + 1) * st, j0, j1, g0, g1)};
    prepare_from(l, m, b, units, d, search_kind, depth, pr);
}

void lumis__lum_draw_prepared(const lumis_luminaire *l, const lumis__prep *pr, double u1, double u2,
                              double *x, double *y, int *pi, int *pj, double *pdf_pixels)
{
    const lumis__box *b = &pr->b;
    if (pr->uniform) {
        *x = b->x0 + u1 * (b->x1 - b->x0);
        *y = b->y0 + u2 * (b->y1 - b->y0);
        *pi = lumis__clampi((int)*x, 0, l->w - 1);
        *pj = lumis__clampi((int)*y, 0, l->h - 1);
        *pdf_pixels = 1.0 / ((b->x1 - b->x0) * (b->y1 - b->y0));
        return;
    }
    line L;
    L.t = table(l, pr->m);
    L.st = (size_t)l->h + 1;
    L.kind = 0;
    L.j0 = pr->j0, L.g0 = pr->g0, L.j1 = pr->j1, L.g1 = pr->g1;
    double g = pr->d_x0 + u1 * (pr->d_x1 - pr->d_x0);
    double xs = search(&L, pr->i0, pr->ilast, pr->d_i0, pr->d_hi, g, pr->secant, pr->depth);
    if (xs < b->x0) xs = b->x0;
    if (!(xs < b->x1)) xs = nextafter(b->x1, b->x0);
    const int col = lumis__clampi((int)xs, 0, l->w - 1);

    /* Conditional in column col, restricted to [y0, y1] by the affine map of its CDF. */
    L.kind = 1;
    L.c0 = L.t + (size_t)col * L.st;
    L.c1 = L.c0 + L.st;
    const double p_j0 = probe(&L, L.j0), p_j0n = probe(&L, L.j0 + 1);
    const double p_y0 = p_j0 + L.g0 * (p_j0n - p_j0);
    const double p_j1 = probe(&L, L.j1), p_j1n = probe(&L, L.j1 + 1);
    const double p_y1 = p_j1 + L.g1 * (p_j1n - p_j1);
    const double phi = pr->jlast == L.j1 ? p_j1n : probe(&L, pr->jlast + 1);
    g = p_y0 + u2 * (p_y1 - p_y0);
    double ys = search(&L, L.j0, pr->jlast, p_j0, phi, g, pr->secant, pr->depth);
    if (ys < b->y0) ys = b->y0;
    if (!(ys < b->y1)) ys = nextafter(b->y1, b->y0);
    const int row = lumis__clampi((int)ys, 0, l->h - 1);
    *x = xs;
    *y = ys;
    *pi = col;
    *pj = row;
    /* The pixel's units: column col's prefix at row + 1 less at row (2 more lookups in the
     * lines the search just read). */
    const double q = (double)(L.c1[row + 1] - L.c0[row + 1]) - (double)(L.c1[row] - L.c0[row]);
    *pdf_pixels = pr->units > 0.0 ? q / pr->units : 0.0;
}

/* Whether the draws tabulate the marginal over the box's columns (4 lookups per column)
 * rather than probe the table (4 lookups per probe): when the count's searches would make
 * half as many probes as the box has columns.  Not when they merely make fewer: probing
 * lanes run in lockstep across images too, so their loads overlap as a tabulation's do,
 * and a tabulated lane's probes are cheaper only once the table is paid for.  Measured on
 * the car preset (factor 4, 2, 1, 0 against 2): docs/luminaire.md, "Benchmark". */
static int tabulate_marginal(const lumis__prep *pr, int count)
{
    const int n = pr->ilast + 1 - pr->i0;
    if (pr->tabulate) return pr->tabulate > 0 && n <= LUMIS__LUM_MAX_GRID_TAB;
    if (n > LUMIS__LUM_MAX_GRID_TAB || n < 2) return 0;
    int probes = 0;
    while ((1 << probes) < n) probes++;
    return count * probes * 2 >= n - 1;
}

enum { LANES = 64 }; /* draws in lockstep at most */

/* Up to LANES exact bisection draws waiting to run in lockstep.  Lane k draws image pr[k]
 * from u[2 at[k]], u[2 at[k] + 1] into entry at[k] of the outputs; its marginal is read
 * from tab[k] (D(i0 + c) for c in [0, ncol], tabulated) or, tab[k] NULL, probed in the
 * summed-area table. */
typedef struct lanes {
    const lumis__prep *pr[LANES];
    const double *tab[LANES];
    int at[LANES];
    int n;
} lanes;

/* Runs the lanes of ls (all tabulated, or all probing the table: direct) and empties it.
 * Lanes of different images (brackets of different sizes) step together: a lane whose
 * bracket is down to one column probes its own lower end, which is <= g, and stays.  The
 * same probes and comparisons as lumis__lum_draw_prepared, so the same draws; what lockstep
 * buys is that the lanes' loads are independent, so they overlap instead of each search
 * waiting on its own chain of dependent loads (most images of a point get one or two
 * draws, so the overlap must come from across images). */
static inline void run_lanes(const lumis_luminaire *l, lanes *ls, int direct, const double *u,
                             double *x, double *y, int *pi, int *pj, double *pdf_pixels)
{
    const int nl = ls->n;
    const size_t st = (size_t)l->h + 1;
    double g[LANES], g2[LANES], g0[LANES], g1[LANES];
    int lo[LANES], n[LANES], col[LANES], jl[LANES], j0[LANES], j1[LANES];
    uint32_t gi[LANES];
    const uint32_t *c0s[LANES], *base[LANES];
    ls->n = 0;
    /* Marginal: lo[k] the column offset from i0.  The comparisons become conditional moves
     * (keeping D's value at lo too would be a branch on random data). */
    int most = 1;
    for (int k = 0; k < nl; k++) {
        const lumis__prep *p = ls->pr[k];
        g[k] = p->d_x0 + u[2 * ls->at[k]] * (p->d_x1 - p->d_x0);
        lo[k] = 0;
        n[k] = p->ilast + 1 - p->i0;
        most = n[k] > most ? n[k] : most;
        j0[k] = p->j0, j1[k] = p->j1, g0[k] = p->g0, g1[k] = p->g1;
        base[k] = table(l, p->m) + (size_t)p->i0 * st;
    }
#define D(k, c)                                                                                    \
    (direct ? marginal_at(base[k] + (size_t)(c)*st, j0[k], j1[k], g0[k], g1[k]) : ls->tab[k][c])
    while (most > 1) {
        for (int k = 0; k < nl; k++) {
            const int half = n[k] / 2;
            lo[k] = D(k, lo[k] + half) <= g[k] ? lo[k] + half : lo[k];
            n[k] -= half;
        }
        most -= most / 2;
    }
    for (int k = 0; k < nl; k++) {
        const lumis__box *b = &ls->pr[k]->b;
        const int c = ls->pr[k]->i0 + lo[k];
        double xs = chord(c, c, D(k, lo[k]), D(k, lo[k] + 1), g[k]);
        if (xs < b->x0) xs = b->x0;
        if (!(xs < b->x1)) xs = nextafter(b->x1, b->x0);
        x[ls->at[k]] = xs;
        col[k] = lumis__clampi((int)xs, 0, l->w - 1);
    }
#undef D
    /* Conditionals in the drawn columns.  A column's prefix is an integer, so P(j) <= g2 is
     * P(j) <= floor(g2): the search compares integers. */
    most = 1;
    for (int k = 0; k < nl; k++) {
        const lumis__prep *p = ls->pr[k];
        const int a = j0[k], z = j1[k];
        const uint32_t *c0 = table(l, p->m) + (size_t)col[k] * st, *c1 = c0 + st;
        const double p_j0 = (double)(c1[a] - c0[a]);
        const double p_y0 = p_j0 + g0[k] * ((double)(c1[a + 1] - c0[a + 1]) - p_j0);
        const double p_j1 = (double)(c1[z] - c0[z]);
        const double p_y1 = p_j1 + g1[k] * ((double)(c1[z + 1] - c0[z + 1]) - p_j1);
        g2[k] = p_y0 + u[2 * ls->at[k] + 1] * (p_y1 - p_y0);
        gi[k] = g2[k] >= LUMIS__LUM_UNITS ? UINT32_MAX : g2[k] > 0.0 ? (uint32_t)g2[k] : 0u;
        c0s[k] = c0;
        jl[k] = a;
        n[k] = p->jlast + 1 - a;
        most = n[k] > most ? n[k] : most;
    }
    while (most > 1) {
        for (int k = 0; k < nl; k++) {
            const uint32_t *c0 = c0s[k], *c1 = c0 + st;
            const int half = n[k] / 2, mid = jl[k] + half;
            jl[k] = c1[mid] - c0[mid] <= gi[k] ? mid : jl[k];
            n[k] -= half;
        }
        most -= most / 2;
    }
    for (int k = 0; k < nl; k++) {
        const lumis__prep *p = ls->pr[k];
        const lumis__box *b = &p->b;
        const uint32_t *c0 = c0s[k], *c1 = c0 + st;
        const int j = jl[k], at = ls->at[k];
        const double flo = (double)(c1[j] - c0[j]), fhi = (double)(c1[j + 1] - c0[j + 1]);
        double ys = chord(j, j, flo, fhi, g2[k]);
        if (ys < b->y0) ys = b->y0;
        if (!(ys < b->y1)) ys = nextafter(b->y1, b->y0);
        const int row = lumis__clampi((int)ys, 0, l->h - 1);
        /* The pixel's units: the search's last bracket unless ys was moved off it. */
        const double q = row == j
                             ? fhi - flo
                             : (double)(c1[row + 1] - c0[row + 1]) - (double)(c1[row] - c0[row]);
        y[at] = ys;
        pi[at] = col[k];
        pj[at] = row;
        pdf_pixels[at] = p->units > 0.0 ? q / p->units : 0.0;
    }
}

static void run_tabulated(const lumis_luminaire *l, lanes *ls, const double *u, double *x,
                          double *y, int *pi, int *pj, double *pdf_pixels)
{
    run_lanes(l, ls, 0, u, x, y, pi, pj, pdf_pixels);
}

static void run_direct(const lumis_luminaire *l, lanes *ls, const double *u, double *x, double *y,
                       int *pi, int *pj, double *pdf_pixels)
{
    run_lanes(l, ls, 1, u, x, y, pi, pj, pdf_pixels);
}

/* D(i0 + c) for c in [0, ncol] into d. */
static void tabulate(const lumis_luminaire *l, const lumis__prep *pr, double *d)
{
    const uint32_t *t = table(l, pr->m);
    const size_t st = (size_t)l->h + 1;
    const int ncol = pr->ilast + 1 - pr->i0;
    d[0] = pr->d_i0;
    for (int c = 1; c < ncol; c++)
        d[c] = marginal_at(t + (size_t)(pr->i0 + c) * st, pr->j0, pr->j1, pr->g0, pr->g1);
    d[ncol] = pr->d_hi;
}

static int exact_bisection(const lumis__prep *pr)
{
    return !pr->uniform && !pr->secant && pr->depth <= 0;
}

void lumis__lum_draw_batch(const lumis_luminaire *l, const lumis__prep *pr, const double *u,
                           int count, double *x, double *y, int *pi, int *pj, double *pdf_pixels)
{
    if (!exact_bisection(pr)) {
        for (int k = 0; k < count; k++)
            lumis__lum_draw_prepared(l, pr, u[2 * k], u[2 * k + 1], x + k, y + k, pi + k, pj + k,
                                     pdf_pixels + k);
        return;
    }
    double d[LUMIS__LUM_MAX_GRID_TAB + 1];
    const int tab = tabulate_marginal(pr, count);
    if (tab) tabulate(l, pr, d);
    lanes ls;
    ls.n = 0;
    for (int k = 0; k < count; k++) {
        ls.pr[ls.n] = pr;
        ls.tab[ls.n] = tab ? d : NULL;
        ls.at[ls.n++] = k;
        if (ls.n == LANES || k == count - 1)
            (tab ? run_tabulated : run_direct)(l, &ls, u, x, y, pi, pj, pdf_pixels);
    }
}

int lumis__lum_draw_group(const lumis_luminaire *l, const lumis__prep *pr, const int *counts,
                          int nimg, const double *u, double *x, double *y, int *pi, int *pj,
                          double *pdf_pixels)
{
    enum { TAB = 2048 };
    double buf[TAB];
    lanes tl, dl; /* tabulated lanes, direct lanes */
    tl.n = dl.n = 0;
    int done = 0, used = 0;
    for (int im = 0; im < nimg; im++) {
        const lumis__prep *p = pr + im;
        if (!exact_bisection(p)) {
            lumis__lum_draw_batch(l, p, u + 2 * done, counts[im], x + done, y + done, pi + done,
                                  pj + done, pdf_pixels + done);
            done += counts[im];
            continue;
        }
        const double *tab = NULL;
        if (tabulate_marginal(p, counts[im])) {
            const int ncol = p->ilast + 1 - p->i0;
            if (used + ncol + 1 > TAB) { /* the buffer is full: its lanes go first */
                if (tl.n) run_tabulated(l, &tl, u, x, y, pi, pj, pdf_pixels);
                used = 0;
            }
            tabulate(l, p, buf + used);
            tab = buf + used;
            used += ncol + 1;
        }
        lanes *ls = tab ? &tl : &dl;
        for (int k = 0; k < counts[im]; k++, done++) {
            ls->pr[ls->n] = p;
            ls->tab[ls->n] = tab;
            ls->at[ls->n++] = done;
            if (ls->n == LANES)
                (tab ? run_tabulated : run_direct)(l, ls, u, x, y, pi, pj, pdf_pixels);
        }
    }
    if (tl.n) run_tabulated(l, &tl, u, x, y, pi, pj, pdf_pixels);
    if (dl.n) run_direct(l, &dl, u, x, y, pi, pj, pdf_pixels);
    return done;
}

void lumis__lum_draw(const lumis_luminaire *l, int m, const lumis__box *b, double units,
                     lumis_luminaire_strategy strategy, lumis_luminaire_search search_kind,
                     int depth, double u1, double u2, double *x, double *y, double *pdf_pixels)
{
    lumis__prep pr;
    int i, j;
    lumis__lum_prepare(l, m, b, units, strategy, search_kind, depth, &pr);
    lumis__lum_draw_prepared(l, &pr, u1, u2, x, y, &i, &j, pdf_pixels);
}

/* ---- the per-image triplet --------------------------------------------------------- */

/* Image m's box and units at p under a strategy; 0 if nothing to sample. */
static int image_box(const lumis_luminaire *l, const lumis_luminaire_query *q, int m, lumis__box *b,
                     double *units)
{
    if (l->unit[m] <= 0.0) return 0;
    if (q->strategy == LUMIS_LUM_GLOBAL) {
        b->x0 = 0.0;
        b->x1 = l->w;
        b->y0 = 0.0;
        b->y1 = l->h;
    } else if (!lumis__lum_box(l, m, q->p.x, q->p.y, q->p.z, b)) {
        return 0;
    }
    *units = lumis__lum_box_units(l, m, b);
    return *units > 0.0;
}

/* p on S (Eq. 9): s = p; u uniform over the support of Phi_m (density 1 / its area). */
static int on_s_support(const lumis_luminaire *l, const lumis_luminaire_query *q, int m, double *ua,
                        double *ub, double *area, const float **px)
{
    int i, j;
    if (!lumis__lum_pixel(l, q->p.x, q->p.y, &i, &j)) return 0;
    const float *c =
        l->rgb +
        ((size_t)m * (size_t)l->w * (size_t)l->h + (size_t)j * (size_t)l->w + (size_t)i) * 3;
    if (!(lumis__lum_y(c) > 0.0)) return 0;
    double cx, cy;
    lumis__lum_center(l, m, &cx, &cy);
    ua[0] = cx - l->radius * l->hx;
    ua[1] = cx + l->radius * l->hx;
    ub[0] = cy - l->radius * l->hy;
    ub[1] = cy + l->radius * l->hy;
    *area = (ua[1] - ua[0]) * (ub[1] - ub[0]);
    *px = c;
    return 1;
}

lumis_status lumis_luminaire_sample_image(const lumis_luminaire *l, const lumis_luminaire_query *q,
                                          int m, double u1, double u2, lumis_luminaire_sample *out)
{
    if (!l || !q || !out || m < 0 || m >= l->m || (unsigned)q->strategy >= LUMIS_LUM_AUTO)
        return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis__where where = lumis__lum_where(l, q->p.z);
    if (where == LUMIS__BEHIND) return LUMIS_ERR_INVALID_ARGUMENT;
    if (where == LUMIS__ON_S && q->strategy != LUMIS_LUM_GLOBAL) {
        double ua[2], ub[2], area;
        const float *px;
        if (!on_s_support(l, q, m, ua, ub, &area, &px)) return LUMIS_ERR_INVALID_ARGUMENT;
        lumis__lum_finish_u(l, q->p.x, q->p.y, q->p.z, m, ua[0] + u1 * (ua[1] - ua[0]),
                            ub[0] + u2 * (ub[1] - ub[0]), 1.0 / area, 1, out);
        return LUMIS_OK;
    }
    lumis__box b;
    double units;
    if (!image_box(l, q, m, &b, &units)) return LUMIS_ERR_INVALID_ARGUMENT;
    double x, y, pdf;
    int i, j;
    lumis__prep pr;
    lumis__lum_prepare(l, m, &b, units, q->strategy, q->search, q->depth, &pr);
    lumis__lum_draw_prepared(l, &pr, u1, u2, &x, &y, &i, &j, &pdf);
    lumis__lum_finish_s(l, q->p.x, q->p.y, q->p.z, q->p.z / (q->p.z - l->delta), m, m % l->gw,
                        m / l->gw, l->rgb + (size_t)m * (size_t)l->w * (size_t)l->h * 3, x, y, i, j,
                        pdf, 1, out);
    return LUMIS_OK;
}

double lumis_luminaire_pdf(const lumis_luminaire *l, const lumis_luminaire_query *q, int m,
                           double sx, double sy)
{
    if (!l || !q || m < 0 || m >= l->m || (unsigned)q->strategy >= LUMIS_LUM_AUTO) return 0.0;
    const lumis__where where = lumis__lum_where(l, q->p.z);
    if (where == LUMIS__BEHIND) return 0.0;
    if (where == LUMIS__ON_S && q->strategy != LUMIS_LUM_GLOBAL) {
        double ua[2], ub[2], area;
        const float *px;
        if (!on_s_support(l, q, m, ua, ub, &area, &px)) return 0.0;
        return sx > ua[0] && sx < ua[1] && sy > ub[0] && sy < ub[1] ? 1.0 / area : 0.0;
    }
    lumis__box b;
    double units;
    if (!image_box(l, q, m, &b, &units)) return 0.0;
    const double x = (sx - l->sx0) / l->dx, y = (sy - l->sy0) / l->dy;
    if (!(x >= b.x0 && x < b.x1 && y >= b.y0 && y < b.y1)) return 0.0;
    if (q->strategy == LUMIS_LUM_UNIFORM)
        return 1.0 / ((b.x1 - b.x0) * (b.y1 - b.y0) * l->dx * l->dy);
    const int i = lumis__clampi((int)x, 0, l->w - 1), j = lumis__clampi((int)y, 0, l->h - 1);
    return (double)lumis__lum_q(l, m, i, j) / (units * l->dx * l->dy);
}

lumis_status lumis_luminaire_invert(const lumis_luminaire *l, const lumis_luminaire_query *q, int m,
                                    double sx, double sy, double *u1, double *u2)
{
    if (!l || !q || !u1 || !u2 || m < 0 || m >= l->m || (unsigned)q->strategy >= LUMIS_LUM_AUTO)
        return LUMIS_ERR_INVALID_ARGUMENT;
    if (lumis__lum_where(l, q->p.z) != LUMIS__FRONT && q->strategy != LUMIS_LUM_GLOBAL)
        return LUMIS_ERR_INVALID_ARGUMENT;
    lumis__box b;
    double units;
    if (!image_box(l, q, m, &b, &units)) return LUMIS_ERR_INVALID_ARGUMENT;
    const double x = (sx - l->sx0) / l->dx, y = (sy - l->sy0) / l->dy;
    if (!(x >= b.x0 && x < b.x1 && y >= b.y0 && y < b.y1)) return LUMIS_ERR_INVALID_ARGUMENT;
    if (q->strategy == LUMIS_LUM_UNIFORM) {
        *u1 = (x - b.x0) / (b.x1 - b.x0);
        *u2 = (y - b.y0) / (b.y1 - b.y0);
        return LUMIS_OK;
    }
    /* u1: the units of the box left of x; u2: those of the column below y, each over its
     * restricted total (the same functions the sampler inverts). */
    lumis__box left = b;
    left.x1 = x;
    *u1 = x > b.x0 ? lumis__lum_box_units(l, m, &left) / units : 0.0;
    const int col = lumis__clampi((int)x, 0, l->w - 1);
    lumis__box colb = {col, col + 1.0, b.y0, b.y1}, below = {col, col + 1.0, b.y0, y};
    const double cu = lumis__lum_box_units(l, m, &colb);
    *u2 = cu > 0.0 && y > b.y0 ? lumis__lum_box_units(l, m, &below) / cu : 0.0;
    return LUMIS_OK;
}
