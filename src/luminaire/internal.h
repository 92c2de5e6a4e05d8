/* Light-field luminaires: the shared model (not public API).  Formulas: docs/luminaire.md. */
#ifndef LUMIS_LUMINAIRE_INTERNAL_H
#define LUMIS_LUMINAIRE_INTERNAL_H

#include "lumis/luminaire.h"

#include "../core/internal.h"

#include <stddef.h>
#include <stdint.h>

#define LUMIS__LUM_MAX_IMAGES 1024
#define LUMIS__LUM_MAX_GRID   256 /* functions along one axis */
#define LUMIS__LUM_MAX_SIDE   16384
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
    float *rgb;              /* M w h 3 */
    uint32_t *sat;           /* M (w + 1)(h + 1), column-major: sat[i (h + 1) + j] */
    double *unit;            /* M: luminance x area (world units) of one quantisation unit
                                of a whole pixel */
    double *power;           /* M: integral of Y_m over S */
    double total_power;
    size_t replaced, bytes;
    lumis_error_sink errors;
    const float **ptrs; /* M pointers into rgb, for lumis_luminaire_get_desc */
};

/* A box on S in pixel coordinates (x in [0, w], y in [0, h]); empty if !(x0 < x1 && y0 <
 * y1). */
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

/* The 1D profile (lumis_luminaire_basis_eval), inline for the hot path. */
static inline double lumis__lum_profile(int bspline, double x)
{
    const double a = x < 0.0 ? -x : x;
    if (bspline) return a <= 0.5 ? 0.75 - a * a : (a < 1.5 ? 0.5 * (1.5 - a) * (1.5 - a) : 0.0);
    return a <= 0.5 ? 1.0 - 2.0 * a * a : (a < 1.0 ? 2.0 * (1.0 - a) * (1.0 - a) : 0.0);
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
    int i0, ilast, j0, j1, jlast;
    double g0, g1, d_i0, d_hi, d_x0, d_x1;
} lumis__prep;

void lumis__lum_prepare(const lumis_luminaire *l, int m, const lumis__box *b, double units,
                        lumis_luminaire_strategy strategy, lumis_luminaire_search search, int depth,
                        lumis__prep *pr);

/* One draw: (x, y) in pixel coordinates, its pixel (i, j) and the density per pixel area
 * of the landed point.  Lookups: the two searches' probes (2 each) and 6. */
void lumis__lum_draw_prepared(const lumis_luminaire *l, const lumis__prep *pr, double u1, double u2,
                              double *x, double *y, int *i, int *j, double *pdf_pixels);

/* count draws from u[2k], u[2k + 1]: the same results as count calls of
 * lumis__lum_draw_prepared, the exact bisections run in lockstep. */
void lumis__lum_draw_batch(const lumis_luminaire *l, const lumis__prep *pr, const double *u,
                           int count, double *x, double *y, int *i, int *j, double *pdf_pixels);

/* One restricted (or uniform) draw of image m inside box b: (x, y) in pixel coordinates
 * and the density per pixel area of the landed point.  units: lumis__lum_box_units(b). */
void lumis__lum_draw(const lumis_luminaire *l, int m, const lumis__box *b, double units,
                     lumis_luminaire_strategy strategy, lumis_luminaire_search search, int depth,
                     double u1, double u2, double *x, double *y, double *pdf_pixels);

/* Fills a sample's geometry and radiance from p and its point (s on S, or u on U for
 * measure AREA_U), with the pdf per unit area given and K_m = count; (i, j) the pixel
 * holding s, or i < 0 to find it. */
void lumis__lum_finish(const lumis_luminaire *l, double px, double py, double pz, int m, double sx,
                       double sy, double ux, double uy, lumis_luminaire_measure measure, double pdf,
                       int count, int i, int j, lumis_luminaire_sample *out);

#endif
