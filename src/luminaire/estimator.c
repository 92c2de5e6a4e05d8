/* Balancing the sample budget over images (Lu et al., Eq. 10-13), the per-point sampling
 * entry, the estimator (Eq. 13/14) and the reference irradiance by quadrature (Eq. 2-4).
 * Measures and Jacobians: docs/luminaire.md. */
#include "internal.h"

#include <limits.h>
#include <math.h>
#include <string.h>

static const char *const strategy_names[] = {"default", "restricted", "uniform", "global", "auto"};
static const char *const search_names[] = {"default", "secant", "binary"};

LUMIS__ENUM_NAMES(lumis_luminaire_strategy, LUMIS_LUM_STRATEGY_COUNT, strategy_names,
                  lumis_luminaire_strategy_name, lumis_luminaire_strategy_from_name);

LUMIS__ENUM_NAMES(lumis_luminaire_search, LUMIS_LUM_SEARCH_COUNT, search_names,
                  lumis_luminaire_search_name, lumis_luminaire_search_from_name);

/* ---- balancing --------------------------------------------------------------------- */

int lumis_luminaire_balance(const double *mass, int n, int budget, int k_max, int *counts)
{
    if (n <= 0 || n > LUMIS__LUM_MAX_IMAGES || !mass || !counts) return 0;
    /* The nonzero masses, packed: every pass below visits only them, in increasing i. */
    int pos[LUMIS__LUM_MAX_IMAGES], npos = 0;
    double pm[LUMIS__LUM_MAX_IMAGES];
    double mmin = INFINITY, msum = 0.0;
    for (int i = 0; i < n; i++) {
        counts[i] = 0;
        if (mass[i] > 0.0) {
            pos[npos] = i;
            pm[npos++] = mass[i];
            msum += mass[i];
            if (mass[i] < mmin) mmin = mass[i];
        }
    }
    if (npos == 0) return 0;
    const double cap = k_max > 0 ? (double)k_max : INFINITY;
    long long total = budget > 0 ? budget : 0;
    if (total < npos) total = npos;
    if (k_max > 0 && total > (long long)k_max * npos) total = (long long)k_max * npos;
    if (total == npos || (k_max > 0 && total == (long long)k_max * npos)) {
        const int k = (int)(total / npos);
        for (int p = 0; p < npos; p++) counts[pos[p]] = k;
        return (int)total;
    }
    const double N = (double)total;
    /* Continuous shares x_i = clamp(lambda m_i, 1, K_max) with sum N: f(lambda) = sum x_i - N
     * is increasing and piecewise linear, so Newton's step (exact on the right piece) with
     * a bisection safeguard ends in a few passes; without clamping in one.  The passes are
     * written without branches on the data (which piece a share is on is unpredictable). */
    double lo = 0.0, hi = N / mmin, lambda = N / msum;
    for (int it = 0; it < 200; it++) {
        double fixed = 0.0, slope = 0.0;
        for (int p = 0; p < npos; p++) {
            const double x = lambda * pm[p];
            const int low = x <= 1.0, high = !low && x >= cap;
            fixed += low ? 1.0 : (high ? cap : 0.0);
            slope += low || high ? 0.0 : pm[p];
        }
        const double f = fixed + lambda * slope - N;
        if (fabs(f) <= 1e-9 * N) break;
        if (f < 0.0)
            lo = lambda;
        else
            hi = lambda;
        double next = slope > 0.0 ? (N - fixed) / slope : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (next == lambda) break;
        lambda = next;
    }
    /* Integers by cumulative rounding of the shares: each within one of its share (so in
     * [1, K_max]), the sum exactly N. */
    double prefix = 0.0;
    long long given = 0;
    for (int p = 0; p < npos; p++) {
        double x = lambda * pm[p];
        x = x < 1.0 ? 1.0 : (x > cap ? cap : x);
        prefix += x;
        long long upto = (long long)(prefix + 0.5); /* prefix >= 0: round half up */
        if (upto > total) upto = total;
        long long k = upto - given;
        if (k < 1) k = 1;
        if (k > total) k = total;
        counts[pos[p]] = (int)k;
        given += k;
    }
    /* Rounding drift (a unit at most, in practice): settle it on entries that can take it,
     * from the last. */
    for (int p = npos - 1; given != total && p >= 0; p--) {
        int *c = counts + pos[p];
        while (given < total && *c < cap) (*c)++, given++;
        while (given > total && *c > 1) (*c)--, given--;
    }
    return (int)given;
}

/* ---- masses and the per-point entry ------------------------------------------------- */

/* What the per-point entry learns about p while computing the masses: every grid column's
 * and row's box range (boxes are separable) and, per image with A_m(p) > 0, the marginal
 * at the box's end columns (lumis__lum_span_units_d), so preparing an image's draws reads
 * no table again. */
typedef struct point_boxes {
    double xlo[LUMIS__LUM_MAX_GRID], xhi[LUMIS__LUM_MAX_GRID];
    double ylo[LUMIS__LUM_MAX_GRID], yhi[LUMIS__LUM_MAX_GRID];
    double d[LUMIS__LUM_MAX_IMAGES][4];
} point_boxes;

/* A_m(p) for every image, and the units of its box (0 for p on S).  The spans are computed
 * once per grid column and row, and images whose box misses the images, or misses every
 * pixel of the image that is not 0, cost no lookup. */
static void masses(const lumis_luminaire *l, lumis__where where, double px, double py, double pz,
                   lumis_luminaire_strategy strategy, double *mass, double *units, point_boxes *pb)
{
    for (int m = 0; m < l->m; m++) mass[m] = units[m] = 0.0;
    if (strategy == LUMIS_LUM_GLOBAL) {
        for (int m = 0; m < l->m; m++)
            if (l->unit[m] > 0.0) {
                mass[m] = l->power[m];
                units[m] = LUMIS__LUM_UNITS;
            }
        return;
    }
    if (where == LUMIS__FRONT) {
        lumis__span xs[LUMIS__LUM_MAX_GRID], ys[LUMIS__LUM_MAX_GRID];
        unsigned char xok[LUMIS__LUM_MAX_GRID], yok[LUMIS__LUM_MAX_GRID];
        for (int a = 0; a < l->gw; a++) {
            xok[a] = (unsigned char)lumis__lum_box_axis(l, 0, a, px, pz, &pb->xlo[a], &pb->xhi[a]);
            if (xok[a]) lumis__lum_span(pb->xlo[a], pb->xhi[a], l->w, &xs[a]);
        }
        for (int b = 0; b < l->gh; b++) {
            yok[b] = (unsigned char)lumis__lum_box_axis(l, 1, b, py, pz, &pb->ylo[b], &pb->yhi[b]);
            if (yok[b]) lumis__lum_span(pb->ylo[b], pb->yhi[b], l->h, &ys[b]);
        }
        for (int b = 0; b < l->gh; b++) {
            if (!yok[b]) continue;
            for (int a = 0; a < l->gw; a++) {
                const int m = a + l->gw * b;
                const int *nz = l->nz + 4 * m;
                /* Outside the nonzero pixels (or all zero: nz[0] > nz[1]) the box holds
                 * exactly 0 units. */
                if (!xok[a] || xs[a].i1 < nz[0] || xs[a].i0 > nz[1] || ys[b].i1 < nz[2] ||
                    ys[b].i0 > nz[3])
                    continue;
                units[m] = lumis__lum_span_units_d(l, m, &xs[a], &ys[b], pb->d[m]);
                mass[m] = units[m] * l->unit[m];
            }
        }
    } else if (where == LUMIS__ON_S) {
        int i, j;
        if (!lumis__lum_pixel(l, px, py, &i, &j)) return;
        for (int m = 0; m < l->m; m++) {
            const double y = lumis__lum_y(l->rgb + ((size_t)m * (size_t)l->w * (size_t)l->h +
                                                    (size_t)j * (size_t)l->w + (size_t)i) *
                                                       3);
            mass[m] = y * (2.0 * l->radius * l->hx) * (2.0 * l->radius * l->hy);
        }
    }
}

void lumis_luminaire_masses(const lumis_luminaire *l, lumis_vec3 p, double *out)
{
    double units[LUMIS__LUM_MAX_IMAGES];
    point_boxes pb;
    masses(l, lumis__lum_where(l, p.z), p.x, p.y, p.z, LUMIS_LUM_RESTRICTED, out, units, &pb);
}

int lumis_luminaire_capacity(const lumis_luminaire *l, int budget)
{
    if (budget <= 0) budget = 32;
    return budget > l->m ? budget : l->m;
}

/* The second pass of the per-point entry: every parked draw's geometry and radiance at p. */
static void finish_draws(const lumis_luminaire *l, double px, double py, double pz,
                         lumis_luminaire_sample *out, int n)
{
    const size_t npx = (size_t)l->w * (size_t)l->h;
    const double t = pz / (pz - l->delta);
    for (int k = 0; k < n;) {
        const int m = out[k].image, a = m % l->gw, b = m / l->gw, km = out[k].count;
        const float *img = l->rgb + (size_t)m * npx * 3;
        for (const int end = k + km; k < end; k++) {
            const double x = out[k].s[0], y = out[k].s[1];
            /* The pixel the draw landed in, as lumis__lum_draw_prepared finds it. */
            const int i = lumis__clampi((int)x, 0, l->w - 1),
                      j = lumis__clampi((int)y, 0, l->h - 1);
            lumis__lum_finish_s(l, px, py, pz, t, m, a, b, img, x, y, i, j, out[k].u[0], km,
                                out + k);
        }
    }
}

enum { GS = 64 }; /* samples drawn at once */

/* The random numbers of samples [n, n + c), c <= GS: read from u, or handed out by q->fill
 * into buf (2 GS doubles). */
static const double *numbers(const lumis_luminaire_query *q, const double *u, int n, int c,
                             double *buf)
{
    if (!q->fill) return u + 2 * (size_t)n;
    q->fill(q->fill_ctx, buf, 2 * c);
    return buf;
}

static lumis_status sample_point(const lumis_luminaire *l, const lumis_luminaire_query *q,
                                 const double *u, int capacity, lumis_luminaire_sample *out,
                                 int *count, int draw_only)
{
    if (!count) return LUMIS_ERR_INVALID_ARGUMENT;
    *count = 0;
    if (!l || !q || (capacity > 0 && ((!u && !q->fill) || !out)) ||
        (unsigned)q->strategy >= (unsigned)LUMIS_LUM_AUTO ||
        (unsigned)q->search >= (unsigned)LUMIS_LUM_SEARCH_COUNT)
        return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis__where where = lumis__lum_where(l, q->p.z);
    if (where == LUMIS__BEHIND) return LUMIS_OK;
    const lumis_luminaire_strategy strategy =
        q->strategy == LUMIS_LUM_STRATEGY_DEFAULT ? LUMIS_LUM_RESTRICTED : q->strategy;
    const double px = q->p.x, py = q->p.y, pz = q->p.z;
    double mass[LUMIS__LUM_MAX_IMAGES], units[LUMIS__LUM_MAX_IMAGES];
    int counts[LUMIS__LUM_MAX_IMAGES];
    point_boxes pb;
    masses(l, where, px, py, pz, strategy, mass, units, &pb);
    const int total =
        lumis_luminaire_balance(mass, l->m, q->budget > 0 ? q->budget : 32, q->k_max, counts);
    if (total > capacity) return LUMIS_ERR_INVALID_ARGUMENT;
    const size_t npx = (size_t)l->w * (size_t)l->h;
    double ubuf[2 * GS];
    int n = 0;
    if (where == LUMIS__ON_S && strategy != LUMIS_LUM_GLOBAL) {
        for (int m = 0; m < l->m; m++) {
            /* Eq. 9: s = p; u uniform over the support of Phi_m. */
            double cx, cy;
            lumis__lum_center(l, m, &cx, &cy);
            const double rx = l->radius * l->hx, ry = l->radius * l->hy;
            const double pdf = 1.0 / (4.0 * rx * ry);
            for (int done = 0; done < counts[m];) {
                const int c = counts[m] - done < GS ? counts[m] - done : GS;
                const double *v = numbers(q, u, n, c, ubuf);
                for (int k = 0; k < c; k++, n++)
                    lumis__lum_finish_u(l, px, py, pz, m, cx - rx + 2.0 * rx * v[2 * k],
                                        cy - ry + 2.0 * ry * v[2 * k + 1], pdf, counts[m], out + n);
                done += c;
            }
        }
        *count = n;
        return LUMIS_OK;
    }
    /* Two passes: every draw first, each asking for its RGB pixel as soon as it is known,
     * then every sample's geometry and radiance, by which time the pixels have arrived.  The
     * first pass parks a draw in its sample: s = its pixel coordinates, u[0] = its density
     * per pixel area.  Draws are made for groups of images at once (lumis__lum_draw_group:
     * most images get one or two samples, whose searches alone would wait on their loads one
     * after another). */
    enum { GI = 32 };
    lumis__prep prs[GI];
    int gcount[GI], gm[GI], gi = 0, gs = 0;
    double xs[GS], ys[GS], pdf[GS];
    int is[GS], js[GS];
    for (int m = 0; m <= l->m; m++) {
        if (m < l->m && !counts[m]) continue;
        if (gi && (m == l->m || gi == GI || gs + counts[m] > GS)) {
            lumis__lum_draw_group(l, prs, gcount, gi, numbers(q, u, n, gs, ubuf), xs, ys, is, js,
                                  pdf);
            for (int g = 0, k = 0; g < gi; g++) {
                const float *img = l->rgb + (size_t)gm[g] * npx * 3;
                for (int c = 0; c < gcount[g]; c++, k++, n++) {
#if defined(__GNUC__) || defined(__clang__)
                    __builtin_prefetch(img + ((size_t)js[k] * (size_t)l->w + (size_t)is[k]) * 3);
#endif
                    out[n].s[0] = xs[k];
                    out[n].s[1] = ys[k];
                    out[n].u[0] = pdf[k];
                    out[n].image = gm[g];
                    out[n].count = gcount[g];
                }
            }
            gi = gs = 0;
        }
        if (m == l->m) break;
        lumis__box b;
        lumis__prep *pr = prs + gi;
        if (strategy == LUMIS_LUM_GLOBAL) {
            b.x0 = b.y0 = 0.0;
            b.x1 = l->w;
            b.y1 = l->h;
        } else {
            b.x0 = pb.xlo[m % l->gw], b.x1 = pb.xhi[m % l->gw];
            b.y0 = pb.ylo[m / l->gw], b.y1 = pb.yhi[m / l->gw];
        }
        if (strategy == LUMIS_LUM_RESTRICTED)
            lumis__lum_prepare_d(l, m, &b, units[m], pb.d[m], q->search, q->depth, pr);
        else
            lumis__lum_prepare(l, m, &b, units[m], strategy, q->search, q->depth, pr);
        if (counts[m] <= GS) { /* joins the group */
            gcount[gi] = counts[m];
            gm[gi] = m;
            gi++;
            gs += counts[m];
            continue;
        }
        const float *img = l->rgb + (size_t)m * npx * 3;
        for (int done = 0; done < counts[m];) {
            const int c = counts[m] - done < GS ? counts[m] - done : GS;
            lumis__lum_draw_batch(l, pr, numbers(q, u, n, c, ubuf), c, xs, ys, is, js, pdf);
            for (int k = 0; k < c; k++, n++) {
#if defined(__GNUC__) || defined(__clang__)
                __builtin_prefetch(img + ((size_t)js[k] * (size_t)l->w + (size_t)is[k]) * 3);
#endif
                out[n].s[0] = xs[k];
                out[n].s[1] = ys[k];
                out[n].u[0] = pdf[k];
                out[n].image = m;
                out[n].count = counts[m];
            }
            done += c;
        }
    }
    if (draw_only) { /* the global strategy's draws, finished per point later */
        *count = n;
        return LUMIS_OK;
    }
    finish_draws(l, px, py, pz, out, n);
    *count = n;
    return LUMIS_OK;
}

lumis_status lumis_luminaire_sample_point(const lumis_luminaire *l, const lumis_luminaire_query *q,
                                          const double *u, int capacity,
                                          lumis_luminaire_sample *out, int *count)
{
    return sample_point(l, q, u, capacity, out, count, 0);
}

lumis_status lumis_luminaire_global_draw(const lumis_luminaire *l, const lumis_luminaire_query *q,
                                         const double *u, int capacity, lumis_luminaire_sample *out,
                                         int *count)
{
    if (!l || !q || q->strategy != LUMIS_LUM_GLOBAL) {
        if (count) *count = 0;
        return LUMIS_ERR_INVALID_ARGUMENT;
    }
    lumis_luminaire_query g = *q;
    g.p.x = g.p.y = 0.0f;
    g.p.z = (float)(3.0 * l->delta); /* any point in front of S: the draws ignore it */
    return sample_point(l, &g, u, capacity, out, count, 1);
}

lumis_status lumis_luminaire_global_finish(const lumis_luminaire *l, lumis_vec3 p,
                                           const lumis_luminaire_sample *drawn, int count,
                                           lumis_luminaire_sample *out, int *out_count)
{
    if (!out_count) return LUMIS_ERR_INVALID_ARGUMENT;
    *out_count = 0;
    if (!l || count < 0 || (count > 0 && (!drawn || !out))) return LUMIS_ERR_INVALID_ARGUMENT;
    if (lumis__lum_where(l, p.z) == LUMIS__BEHIND) return LUMIS_OK;
    if (out != drawn) memcpy(out, drawn, (size_t)count * sizeof *out);
    finish_draws(l, p.x, p.y, p.z, out, count);
    *out_count = count;
    return LUMIS_OK;
}

lumis_rgb lumis_luminaire_estimate(const lumis_luminaire_sample *s, int count, lumis_vec3 n)
{
    double acc[3] = {0.0, 0.0, 0.0};
    const double nl = sqrt((double)n.x * n.x + (double)n.y * n.y + (double)n.z * n.z);
    if (nl > 0.0) n.x = (float)(n.x / nl), n.y = (float)(n.y / nl), n.z = (float)(n.z / nl);
    for (int k = 0; k < count; k++) {
        const double c =
            (double)n.x * s[k].dir.x + (double)n.y * s[k].dir.y + (double)n.z * s[k].dir.z;
        if (!(c > 0.0)) continue;
        const double w = c * (double)s[k].weight;
        acc[0] += w * s[k].radiance.r;
        acc[1] += w * s[k].radiance.g;
        acc[2] += w * s[k].radiance.b;
    }
    lumis_rgb r = {(float)acc[0], (float)acc[1], (float)acc[2]};
    return r;
}

/* ---- reference irradiance by quadrature -------------------------------------------- */

/* Gauss-Legendre nodes and weights on [0, 1], orders 1..8. */
void lumis__gauss01(int order, double *x, double *w)
{
    static const double n2[] = {0.5773502691896257}, w2[] = {1.0};
    static const double n3[] = {0.0, 0.7745966692414834},
                        w3[] = {0.8888888888888888, 0.5555555555555556};
    static const double n4[] = {0.3399810435848563, 0.8611363115940526},
                        w4[] = {0.6521451548625461, 0.3478548451374538};
    static const double n5[] = {0.0, 0.5384693101056831, 0.9061798459386640},
                        w5[] = {0.5688888888888889, 0.4786286704993665, 0.2369268850561891};
    static const double n6[] = {0.2386191860831969, 0.6612093864662645, 0.9324695142031521},
                        w6[] = {0.4679139345726910, 0.3607615730481386, 0.1713244923791704};
    static const double n7[] = {0.0, 0.4058451513773972, 0.7415311855993945, 0.9491079123427585},
                        w7[] = {0.4179591836734694, 0.3818300505051189, 0.2797053914892766,
                                0.1294849661688697};
    static const double n8[] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                0.9602898564975363},
                        w8[] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                0.1012285362903763};
    const double *nn = n4, *ww = w4;
    switch (order) {
    case 1:
        x[0] = 0.5, w[0] = 1.0;
        return;
    case 2:
        nn = n2, ww = w2;
        break;
    case 3:
        nn = n3, ww = w3;
        break;
    case 5:
        nn = n5, ww = w5;
        break;
    case 6:
        nn = n6, ww = w6;
        break;
    case 7:
        nn = n7, ww = w7;
        break;
    case 8:
        nn = n8, ww = w8;
        break;
    default:
        break;
    }
    int k = 0;
    const int half = (order + 1) / 2;
    for (int a = 0; a < half; a++) {
        const int zero = (order & 1) && a == 0;
        x[k] = 0.5 - 0.5 * nn[a], w[k] = 0.5 * ww[a], k++;
        if (!zero) x[k] = 0.5 + 0.5 * nn[a], w[k] = 0.5 * ww[a], k++;
    }
}

/* The next breakpoint after v, at most hi: a pixel edge (integer) or a knot (sorted). */
static double next_break(double v, double hi, const double *knots, int nk)
{
    double n = floor(v) + 1.0;
    for (int k = 0; k < nk; k++)
        if (knots[k] > v && knots[k] < n) n = knots[k];
    return n < hi ? n : hi;
}

lumis_status lumis_luminaire_irradiance(const lumis_luminaire *l, lumis_vec3 p, lumis_vec3 nrm,
                                        int order, lumis_rgb *out)
{
    if (!l || !out) return LUMIS_ERR_INVALID_ARGUMENT;
    out->r = out->g = out->b = 0.0f;
    if (order <= 0) order = 4;
    if (order > 8) order = 8;
    double gx[8], gw[8];
    lumis__gauss01(order, gx, gw);
    const double px = p.x, py = p.y, pz = p.z, d = l->delta;
    const double nl = sqrt((double)nrm.x * nrm.x + (double)nrm.y * nrm.y + (double)nrm.z * nrm.z);
    if (!(nl > 0.0)) return LUMIS_ERR_INVALID_ARGUMENT;
    const double nx = nrm.x / nl, ny = nrm.y / nl, nz = nrm.z / nl;
    const lumis__where where = lumis__lum_where(l, pz);
    if (where == LUMIS__BEHIND) return LUMIS_OK;
    double acc[3] = {0.0, 0.0, 0.0};
    /* Knots of the profile, in cells from the centre. */
    const double kq[] = {-1.0, -0.5, 0.5, 1.0}, kb[] = {-1.5, -0.5, 0.5, 1.5};
    const double *knots = l->basis == LUMIS_BASIS_BSPLINE ? kb : kq;
    const size_t npx = (size_t)l->w * (size_t)l->h;
    for (int m = 0; m < l->m; m++) {
        if (l->unit[m] <= 0.0) continue;
        double cx, cy;
        lumis__lum_center(l, m, &cx, &cy);
        if (where == LUMIS__ON_S) {
            /* Eq. 9: s = p; integrate over U, piece by piece between knots. */
            int i, j;
            if (!lumis__lum_pixel(l, px, py, &i, &j)) return LUMIS_OK;
            const float *c = l->rgb + ((size_t)m * npx + (size_t)j * (size_t)l->w + (size_t)i) * 3;
            for (int ax = 0; ax < 3; ax++)
                for (int ay = 0; ay < 3; ay++) {
                    const double x0 = cx + knots[ax] * l->hx, x1 = cx + knots[ax + 1] * l->hx;
                    const double y0 = cy + knots[ay] * l->hy, y1 = cy + knots[ay + 1] * l->hy;
                    for (int a = 0; a < order; a++)
                        for (int b = 0; b < order; b++) {
                            const double ux = x0 + gx[a] * (x1 - x0), uy = y0 + gx[b] * (y1 - y0);
                            const double vx = ux - px, vy = uy - py;
                            const double r2 = vx * vx + vy * vy + pz * pz, r = sqrt(r2);
                            const double cp = (nx * vx + ny * vy - nz * pz) / r;
                            if (!(cp > 0.0)) continue;
                            const double phi = lumis__lum_phi(l, m, ux, uy);
                            const double e2 = vx * vx + vy * vy + d * d;
                            const double psi = phi * e2 * e2 / (d * d * l->hx * l->hy);
                            const double g = (pz / r) * cp / r2;
                            const double wgt = gw[a] * gw[b] * (x1 - x0) * (y1 - y0) * psi * g;
                            for (int k = 0; k < 3; k++) acc[k] += wgt * c[k];
                        }
                }
            continue;
        }
        lumis__box bx;
        if (!lumis__lum_box(l, m, px, py, pz, &bx)) continue;
        if (!(lumis__lum_box_units(l, m, &bx) > 0.0)) continue;
        /* Knots projected onto S, in pixel coordinates, sorted (the map is monotone). */
        const double kk = (pz - d) / pz, cc = d / pz;
        double kxs[4], kys[4];
        for (int a = 0; a < 4; a++) {
            const int src = kk < 0.0 ? 3 - a : a;
            kxs[a] = (kk * (cx + knots[src] * l->hx) + cc * px - l->sx0) / l->dx;
            kys[a] = (kk * (cy + knots[src] * l->hy) + cc * py - l->sy0) / l->dy;
        }
        for (double x0 = bx.x0, x1 = x0; x0 < bx.x1; x0 = x1) {
            x1 = next_break(x0, bx.x1, kxs, 4);
            for (double y0 = bx.y0, y1 = y0; y0 < bx.y1; y0 = y1) {
                y1 = next_break(y0, bx.y1, kys, 4);
                const int i = lumis__clampi((int)floor(0.5 * (x0 + x1)), 0, l->w - 1);
                const int j = lumis__clampi((int)floor(0.5 * (y0 + y1)), 0, l->h - 1);
                const float *c =
                    l->rgb + ((size_t)m * npx + (size_t)j * (size_t)l->w + (size_t)i) * 3;
                if (c[0] == 0.0f && c[1] == 0.0f && c[2] == 0.0f) continue;
                double part = 0.0;
                for (int a = 0; a < order; a++)
                    for (int b = 0; b < order; b++) {
                        const double sx = l->sx0 + (x0 + gx[a] * (x1 - x0)) * l->dx;
                        const double sy = l->sy0 + (y0 + gx[b] * (y1 - y0)) * l->dy;
                        const double t = pz / (pz - d);
                        const double ux = px + (sx - px) * t, uy = py + (sy - py) * t;
                        const double phi = lumis__lum_phi(l, m, ux, uy);
                        if (!(phi > 0.0)) continue;
                        /* Light arrives at p from u: cos at p uses the direction to u. */
                        const double vx = ux - px, vy = uy - py, vz = -pz;
                        const double cp =
                            (nx * vx + ny * vy + nz * vz) / sqrt(vx * vx + vy * vy + vz * vz);
                        if (!(cp > 0.0)) continue;
                        const double wx = sx - px, wy = sy - py, wz = d - pz;
                        const double r2 = wx * wx + wy * wy + wz * wz;
                        const double g = fabs(wz) / sqrt(r2) * cp / r2;
                        const double ex = sx - ux, ey = sy - uy;
                        const double e2 = ex * ex + ey * ey + d * d;
                        const double psi = phi * e2 * e2 / (d * d * l->hx * l->hy);
                        part += gw[a] * gw[b] * psi * g;
                    }
                part *= (x1 - x0) * (y1 - y0) * l->dx * l->dy;
                for (int k = 0; k < 3; k++) acc[k] += part * c[k];
            }
        }
    }
    out->r = (float)acc[0];
    out->g = (float)acc[1];
    out->b = (float)acc[2];
    return LUMIS_OK;
}
