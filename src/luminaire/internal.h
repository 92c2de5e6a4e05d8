/* Light-field luminaires: the shared model (not public API).  Formulas: docs/luminaire.md. */
#ifndef LUMIS_LUMINAIRE_INTERNAL_H
#define LUMIS_LUMINAIRE_INTERNAL_H

#include "lumis/luminaire.h"

#include "../core/internal.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#define LUMIS__LUM_MAX_IMAGES LUMIS_LUMINAIRE_MAX_IMAGES
#define LUMIS__LUM_MAX_GRID   LUMIS_LUMINAIRE_MAX_GRID /* functions along one axis */
#define LUMIS__LUM_MAX_SIDE   LUMIS_LUMINAIRE_MAX_SIDE
/* Widest box (in columns) whose marginal lumis__lum_draw_batch may tabulate on the stack. */
#define LUMIS__LUM_MAX_GRID_TAB 256
/* Quantisation units per image: every summed-area table entry fits in 32 bits. */
#define LUMIS__LUM_UNITS 4294967295.0

struct lumis_luminaire {
    double delta;
    lumis_luminaire_basis basis;
    double radius; /* support half-width in cells */
    int gw, gh, m; /* grid W, H and M = W H */
    double gx0, gy0, hx, hy;
    double inv_hx, inv_hy;
    double psi_scale; /* 1 / (delta^2 h_x h_y) */
    int w, h;
    double sx0, sy0, sw, sh; /* image rectangle on S */
    double dx, dy;           /* pixel size */
    double inv_pixel_area;   /* 1 / (dx dy) */
    float *rgb;              /* M w h 3 */
    uint32_t *sat;           /* M (w + 1)(h + 1), column-major: sat[i (h + 1) + j] */
    double *unit;            /* M: luminance x area (world units) of one quantisation unit
                                of a whole pixel */
    double *power;           /* M: integral of Y_m over S */
    int *nz;                 /* M x 4: pixels [i0, i1] x [j0, j1] hold all of image m's
                                nonzero units (i0 > i1 if none): a box outside has A_m = 0 */
    double total_power;
    size_t replaced, bytes;
    lumis_error_sink errors;
    const float **ptrs; /* M pointers into rgb, for lumis_luminaire_get_desc */
};

/* A box on S in pixel coordinates (x in [0, w], y in [0, h]); empty if !(x0 < x1 && y0 <
 * y1). */
/* Gauss-Legendre nodes x[] on [0, 1] and weights w[] summing to 1, `order` of each (1 to 8;
 * another order gives 4): the quadratures of lumis_luminaire_irradiance and of a
 * photometric opening's near field. */
void lumis__gauss01(int order, double *x, double *w);

typedef struct lumis__box {
    double x0, x1, y0, y1;
} lumis__box;

/* Where the ray geometry of point p stands (docs/luminaire.md, "Projection"). */
typedef enum lumis__where {
    LUMIS__BEHIND = 0, /* z <= 0 (or on U): no light reaches p */
    LUMIS__FRONT = 1,  /* z > 0 and not on S: sample S in projected boxes */
    LUMIS__ON_S = 2,   /* |z - delta| <= 1e-7 delta: sample U (Eq. 9) */
} lumis__where;

/* Checks a descriptor's geometry (everything but the pixels), reporting to d->errors. */
lumis_status lumis__lum_check(const lumis_luminaire_desc *d);

/* Builds from sanitised RGB; takes ownership of rgb (freed on failure). */
lumis_status lumis__lum_build(const lumis_luminaire_desc *d, float *rgb, size_t replaced,
                              lumis_luminaire **out);

lumis__where lumis__lum_where(const lumis_luminaire *l, double pz);

/* Centre of basis function m on U. */
static inline void lumis__lum_center(const lumis_luminaire *l, int m, double *cx, double *cy)
{
    *cx = l->gx0 + (m % l->gw) * l->hx;
    *cy = l->gy0 + (m / l->gw) * l->hy;
}

/* The 1D profile (lumis_luminaire_basis_eval), inline for the hot path and without
 * branches (their outcome is random per sample): each profile is its outer piece less the
 * square that the inner piece differs by, 2 (1 - a)^2 - (1 - 2a)^2 = 1 - 2a^2 and
 * 0.5 (1.5 - a)^2 - 1.5 (0.5 - a)^2 = 0.75 - a^2, with a clamped to the support. */
static inline double lumis__lum_profile(int bspline, double x)
{
    const double a = fabs(x);
    if (bspline) {
        const double o = 1.5 - lumis__minsel(a, 1.5), i = lumis__maxsel(0.5 - a, 0.0);
        return 0.5 * o * o - 1.5 * i * i;
    }
    const double o = 1.0 - lumis__minsel(a, 1.0), i = lumis__maxsel(1.0 - 2.0 * a, 0.0);
    return 2.0 * o * o - i * i;
}

/* Phi_m(u) for the function at grid position (a, b). */
static inline double lumis__lum_phi_ab(const lumis_luminaire *l, int a, int b, double ux, double uy)
{
    const int bs = l->basis == LUMIS_BASIS_BSPLINE;
    return lumis__lum_profile(bs, (ux - l->gx0) * l->inv_hx - a) *
           lumis__lum_profile(bs, (uy - l->gy0) * l->inv_hy - b);
}

/* Phi_m(u). */
static inline double lumis__lum_phi(const lumis_luminaire *l, int m, double ux, double uy)
{
    return lumis__lum_phi_ab(l, m % l->gw, m / l->gw, ux, uy);
}

/* The box on S that the support of Phi_m projects to from p (FRONT), clipped to the
 * images, in pixel coordinates.  Returns nonzero if it is not empty. */
int lumis__lum_box(const lumis_luminaire *l, int m, double px, double py, double pz, lumis__box *b);

/* One axis of that box: for grid column (axis 0) or row (axis 1) `index`, p's coordinate
 * pc on that axis: [lo, hi] in pixels, nonzero if not empty.  Boxes are separable: image
 * (a, b)'s box is column a's x-range times row b's y-range. */
int lumis__lum_box_axis(const lumis_luminaire *l, int axis, int index, double pc, double pz,
                        double *lo, double *hi);

/* A coordinate range [x0, x1] in [0, n] as cells and fractions (x == n -> n - 1, 1). */
typedef struct lumis__span {
    int i0, i1;
    double f0, f1;
} lumis__span;

static inline void lumis__lum_span(double x0, double x1, int n, lumis__span *s)
{
    int k0 = (int)x0, k1 = (int)x1; /* x >= 0: truncation is floor */
    if (k0 > n - 1) k0 = n - 1;
    if (k1 > n - 1) k1 = n - 1;
    s->i0 = k0;
    s->i1 = k1;
    s->f0 = x0 - k0;
    s->f1 = x1 - k1;
}

/* The integral of image m's quantised luminance over the box of spans x and y, in units x
 * pixels: exactly 0 when every pixel the box touches is 0.  16 lookups. */
double lumis__lum_span_units(const lumis_luminaire *l, int m, const lumis__span *x,
                             const lumis__span *y);

/* The same, and the restricted marginal D(k) (the units in columns < k between rows y0 and
 * y1, as lumis__lum_prepare reads it) at k = x.i0, x.i0 + 1, x.i1, x.i1 + 1 from the same
 * 16 lookups. */
double lumis__lum_span_units_d(const lumis_luminaire *l, int m, const lumis__span *x,
                               const lumis__span *y, double d[4]);

/* The same for a box. */
double lumis__lum_box_units(const lumis_luminaire *l, int m, const lumis__box *b);

/* Pixel (i, j) of image m holding S point (sx, sy); 0 if outside the images. */
int lumis__lum_pixel(const lumis_luminaire *l, double sx, double sy, int *i, int *j);

/* Luminance of an RGB pixel as sampling weighs it. */
static inline double lumis__lum_y(const float *px)
{
    return 0.2126 * (double)px[0] + 0.7152 * (double)px[1] + 0.0722 * (double)px[2];
}

/* Quantised luminance of pixel (i, j) of image m (from its table: 4 lookups). */
static inline uint32_t lumis__lum_q(const lumis_luminaire *l, int m, int i, int j)
{
    const size_t stride = (size_t)l->h + 1;
    const uint32_t *t = l->sat + (size_t)m * ((size_t)l->w + 1) * stride;
    return t[(size_t)(i + 1) * stride + (size_t)j + 1] - t[(size_t)(i + 1) * stride + (size_t)j] -
           t[(size_t)i * stride + (size_t)j + 1] + t[(size_t)i * stride + (size_t)j];
}

/* Image m's sampler at one point: what every draw in box b shares (6 lookups). */
typedef struct lumis__prep {
    lumis__box b;
    double units;
    int m, uniform, secant, depth;
    int tabulate; /* lumis__lum_draw_batch's marginal: 0 its choice, 1 tabulated, -1 searched
                     in the table (tests pin both) */
    int i0, ilast, j0, j1, jlast;
    double g0, g1, d_i0, d_hi, d_x0, d_x1;
} lumis__prep;

void lumis__lum_prepare(const lumis_luminaire *l, int m, const lumis__box *b, double units,
                        lumis_luminaire_strategy strategy, lumis_luminaire_search search, int depth,
                        lumis__prep *pr);

/* The same for the restricted strategy with d from lumis__lum_span_units_d (no lookups):
 * the very same prep. */
void lumis__lum_prepare_d(const lumis_luminaire *l, int m, const lumis__box *b, double units,
                          const double d[4], lumis_luminaire_search search, int depth,
                          lumis__prep *pr);

/* One draw: (x, y) in pixel coordinates, its pixel (i, j) and the density per pixel area
 * of the landed point.  Lookups: the two searches' probes (2 each) and 6. */
void lumis__lum_draw_prepared(const lumis_luminaire *l, const lumis__prep *pr, double u1, double u2,
                              double *x, double *y, int *i, int *j, double *pdf_pixels);

/* count draws from u[2k], u[2k + 1]: the same results as count calls of
 * lumis__lum_draw_prepared, the exact bisections run in lockstep. */
void lumis__lum_draw_batch(const lumis_luminaire *l, const lumis__prep *pr, const double *u,
                           int count, double *x, double *y, int *i, int *j, double *pdf_pixels);

/* The draws of nimg images (pr[k] drawn counts[k] times, in order) from u[2n], u[2n + 1]:
 * the same results as lumis__lum_draw_batch on each, every exact bisection in lockstep
 * across images (a lockstep group for images whose marginal is tabulated, one for those
 * probed in the table).  Returns the sum of the counts. */
int lumis__lum_draw_group(const lumis_luminaire *l, const lumis__prep *pr, const int *counts,
                          int nimg, const double *u, double *x, double *y, int *i, int *j,
                          double *pdf_pixels);

/* One restricted (or uniform) draw of image m inside box b: (x, y) in pixel coordinates
 * and the density per pixel area of the landed point.  units: lumis__lum_box_units(b). */
void lumis__lum_draw(const lumis_luminaire *l, int m, const lumis__box *b, double units,
                     lumis_luminaire_strategy strategy, lumis_luminaire_search search, int depth,
                     double u1, double u2, double *x, double *y, double *pdf_pixels);

/* A sample's radiance and weight once its direction is known (u on U, s on S, pixel
 * (i, j) of image m at grid position (a, b), img its RGB pixels): shared by
 * lumis__lum_finish_s and lumis__lum_finish_u.  pdf_omega = pdf r^2 / cos at the sampled
 * plane, written cos = cnum / r: weight = cnum / (K_m pdf r^3), one division. */
static inline void lumis__lum_shade(const lumis_luminaire *l, int a, int b, const float *img,
                                    double sx, double sy, double ux, double uy, int i, int j,
                                    double pdf, int count, double cnum, double r3,
                                    lumis_luminaire_sample *o)
{
    const double phi = lumis__lum_phi_ab(l, a, b, ux, uy);
    /* Psi_m(u -> s) = Phi_m(u) delta^2 / (h_x h_y cos^4 theta), cos theta = delta / |s - u|. */
    const double ex = sx - ux, ey = sy - uy;
    const double e2 = ex * ex + ey * ey + l->delta * l->delta;
    const double psi = phi * e2 * e2 * l->psi_scale;
    const float *c = img + ((size_t)j * (size_t)l->w + (size_t)i) * 3;
    /* phi == 0 (u on the support's edge): no energy, weight 0 as for a miss. */
    const int lit = phi > 0.0;
    o->radiance.r = lit ? (float)(psi * c[0]) : 0.0f;
    o->radiance.g = lit ? (float)(psi * c[1]) : 0.0f;
    o->radiance.b = lit ? (float)(psi * c[2]) : 0.0f;
    o->weight = lit ? (float)(cnum / ((double)count * pdf * r3)) : 0.0f;
}

/* A sample on S (measure AREA_S) from p, its point s in pixel coordinates (x, y) inside
 * pixel (i, j) and its density per pixel area: everything a sample holds, with
 * t = z / (z - delta) (the projection from S to U through p). */
static inline void lumis__lum_finish_s(const lumis_luminaire *l, double px, double py, double pz,
                                       double t, int m, int a, int b, const float *img, double x,
                                       double y, int i, int j, double pdf_pixels, int count,
                                       lumis_luminaire_sample *o)
{
    const double sx = l->sx0 + x * l->dx, sy = l->sy0 + y * l->dy;
    const double pdf = pdf_pixels * l->inv_pixel_area;
    /* The line from p through s meets U at u = p + (s - p) t: p, s and u are on one line,
     * so |u - p| = |t| |s - p| and the direction to u is sign(t) (s - p) / |s - p|. */
    const double wx = sx - px, wy = sy - py, wz = l->delta - pz;
    const double ux = px + wx * t, uy = py + wy * t;
    o->s[0] = sx;
    o->s[1] = sy;
    o->u[0] = ux;
    o->u[1] = uy;
    o->image = m;
    o->count = count;
    o->measure = LUMIS_LUM_AREA_S;
    o->pdf = (float)pdf;
    const double r2 = wx * wx + wy * wy + wz * wz, r = sqrt(r2);
    const double dist = r * fabs(t);
    o->distance = (float)dist;
    if (!(dist > 0.0) || !(pdf > 0.0) || !isfinite(ux) || !isfinite(uy)) {
        o->radiance.r = o->radiance.g = o->radiance.b = 0.0f;
        o->weight = 0.0f;
        o->dir.x = o->dir.y = 0.0f;
        o->dir.z = -1.0f;
        return;
    }
    const double inv = copysign(1.0 / r, t);
    o->dir.x = (float)(wx * inv);
    o->dir.y = (float)(wy * inv);
    o->dir.z = (float)(wz * inv);
    lumis__lum_shade(l, a, b, img, sx, sy, ux, uy, i, j, pdf, count, fabs(wz), r2 * r, o);
}

/* A sample of p on S (measure AREA_U, Eq. 9): s = p, u on U with density pdf per unit
 * area of U, K_m = count. */
void lumis__lum_finish_u(const lumis_luminaire *l, double px, double py, double pz, int m,
                         double ux, double uy, double pdf, int count, lumis_luminaire_sample *out);

#endif
