/* Machinery shared by the light-set methods (not public API).  Formulas: docs/lights.md. */
#ifndef LUMIS_LIGHTS_INTERNAL_H
#define LUMIS_LIGHTS_INTERNAL_H

#include "lumis/lights.h"

#include "../core/internal.h"
#include "../envmap/internal.h"

#include <stddef.h>
#include <stdint.h>

/* Whole-map pixel passes are built several times and lumis__simd_level() picks one
 * (core/internal.h): the rectangle methods' band sums for AVX-512, AVX2 and the baseline
 * (AVX-512 made them ~30 % faster), Wu's passes for AVX2 and the baseline (its AVX-512 build
 * measured slower).  Their sums stay bit-identical: contraction into fused multiply-adds is
 * off (-ffp-contract=off on these files, CMakeLists.txt) and every sum keeps its order;
 * test_lights compares every variant the CPU has, and CI forces each (LUMIS_SIMD). */

/* Exact per-row and per-column factors of the map (map frame, no rotation).  Pixel (i, j)
 * has solid angle omega[j] and first moment (the integral of the direction over it)
 *     m = (a[j] cs[i], b[j], a[j] cc[i]),
 * with a = integral of sin^2 theta d theta over the row, b = dphi times the integral of
 * sin theta cos theta, cs = sin phi_{i+1} - sin phi_i, cc = cos phi_i - cos phi_{i+1}. */
typedef struct lumis__geom {
    int w, h;
    double *omega, *a, *b;   /* h each */
    double *cos_t, *sin_t;   /* h + 1 row edges: cos / sin of theta_j = pi j / h */
    double *cs, *cc;         /* w each */
    double *cos_p, *sin_p;   /* w + 1 column edges: cos / sin of phi_i = 2 pi i / w */
    double scale;            /* the envmap's radiance scale */
    double cos_rot, sin_rot; /* map -> world rotation about +y */
} lumis__geom;

lumis_status lumis__geom_init(lumis__geom *g, const lumis_envmap *env);
void lumis__geom_free(lumis__geom *g);

/* Luminance of pixel p as every method weighs it: Y = scale (0.2126 R + 0.7152 G +
 * 0.0722 B), evaluated in double and rounded to float. */
static inline float lumis__pixel_y(const float *px, double scale)
{
    return (float)(scale *
                   (0.2126 * (double)px[0] + 0.7152 * (double)px[1] + 0.0722 * (double)px[2]));
}

/* Smallest d . p over the patch theta in [theta_r0, theta_r1], phi in [phi_c0, phi_c1]
 * (edge indices into g's tables); d a unit vector in the map frame. */
double lumis__rect_min_dot(const lumis__geom *g, const double d[3], int r0, int r1, int c0, int c1);

/* A pixel rectangle [x0, x1) x [y0, y1). */
typedef struct lumis__rect {
    int x0, y0, x1, y1;
} lumis__rect;

/* Every label of rectangle r set to `label`, by streaming stores where SSE2 has them
 * (their cache lines are not fetched first; Wu's EnvIndirect labels, written last, gain
 * ~1 ms on 2048 x 1024, docs/lights.md). */
void lumis__fill_labels(int32_t *labels, int w, lumis__rect r, int32_t label);

/* Sums over a region while its labels are written. */
typedef struct lumis__acc {
    double rgb[3]; /* sum of L * Omega (unscaled) */
    double m[3];   /* sum of Y m (luminance-weighted first moment) */
    double g[3];   /* sum of m (geometric first moment) */
    double omega;
    int pixels;
} lumis__acc;

/* Adds pixel (i, j) to acc. */
void lumis__acc_pixel(const lumis__geom *g, const lumis_envmap *env, lumis__acc *acc, int i, int j);

/* Adds the geometric moment and solid angle of the whole rectangle r to acc (closed form
 * per row). */
void lumis__acc_rect_geometry(const lumis__geom *g, lumis__rect r, lumis__acc *acc);

/* Labels the pixels of r whose label equals `only` (any pixel if only == INT32_MIN) with
 * `label` and adds them to acc. */
void lumis__acc_rect(const lumis__geom *g, const lumis_envmap *env, int32_t *labels, lumis__rect r,
                     int32_t only, int32_t label, lumis__acc *acc);

/* A set under construction. */
struct lumis_light_set {
    int w, h;
    int sets, count;
    lumis_light *lights; /* sets * count */
    int32_t *labels;     /* w * h */
    double *kmeans_objective;
    lumis_light_set_info info;
};

/* The common descriptor fields, defaults applied and checked. */
typedef struct lumis__common {
    int count, sets;
    double jitter;
    uint64_t seed;
    const lumis_error_sink *errors;
} lumis__common;

lumis_status lumis__common_check(const lumis_envmap *env, const char *what, int count, int sets,
                                 float jitter, uint64_t seed, const lumis_error_sink *errors,
                                 lumis__common *out);

/* Allocates a set of `count` lights per set and a label array (set to -1 if fill). */
lumis_status lumis__set_create(const lumis_envmap *env, const lumis__common *c, int count,
                               lumis_lights_method method, int fill, lumis_light_set **out);

/* Turns light k's sums into the light (direction in world space, power with the scale,
 * solid angle); the extent is set by the caller (lumis__extent_*). */
void lumis__light_from_acc(const lumis__geom *g, const lumis__acc *acc, lumis_light_kind kind,
                           lumis_light *light);

/* Map-frame unit direction of a light (inverse of the rotation applied on output). */
void lumis__light_map_dir(const lumis__geom *g, const lumis_light *light, double d[3]);

/* The lights' total power into info.power; the jittered copies; the build time. */
void lumis__set_finish(lumis_light_set *set, const lumis__geom *g, const lumis_envmap *env,
                       const lumis__common *c, double t0_ms);

double lumis__now_ms(void);

/* Recursive rectangle splitting shared by median cut and variance minimisation: the
 * method's split() cuts r in two (returns 0 if r cannot be split) and priority() orders
 * the regions of the last, partial level. */
typedef struct lumis__splitter {
    int (*split)(void *ctx, lumis__rect r, lumis__rect *a, lumis__rect *b);
    double (*priority)(void *ctx, lumis__rect r);
    void *ctx;
} lumis__splitter;

/* Splits the whole map into exactly k rectangles (k <= pixels); rects holds k entries.
 * Siblings stay adjacent, so for k a power of two, rects 2i and 2i + 1 come from one
 * split. */
lumis_status lumis__split_rects(const lumis__splitter *s, int w, int h, int k, lumis__rect *rects);

/* Finishes a rectangle partition: labels, sums, lights with exact rectangle extents. */
void lumis__lights_from_rects(lumis_light_set *set, const lumis__geom *g, const lumis_envmap *env,
                              const lumis__rect *rects, int k);

/* Inclusive-exclusive summed-area table of a per-pixel quantity: (w + 1) x (h + 1)
 * doubles, sat[(y) (w + 1) + x] = sum over [0, x) x [0, y). */
static inline double lumis__sat_rect(const double *sat, int w, lumis__rect r)
{
    size_t W = (size_t)w + 1;
    return sat[(size_t)r.y1 * W + (size_t)r.x1] - sat[(size_t)r.y0 * W + (size_t)r.x1] -
           sat[(size_t)r.y1 * W + (size_t)r.x0] + sat[(size_t)r.y0 * W + (size_t)r.x0];
}

/* Builds the summed-area tables of Y Omega (e) and of Y m (mx, my, mz; all three or none)
 * in one pass; each (w + 1)(h + 1) doubles. */
lumis_status lumis__sat_build(const lumis__geom *g, const lumis_envmap *env, double *e, double *mx,
                              double *my, double *mz);

/* Band sums of a map (strips.c): for every band of T rows and every column the column's
 * sums over the band, for every row and every band of T columns the row's sums.  Built in
 * one pass over the pixels; then a rectangle's marginals and totals cost
 * O(extent x (bands + 2 T)), each a direct double sum (no differences of running totals). */
typedef struct lumis__strips {
    int w, h, T;
    int nb, nc; /* row bands ceil(h / T), column bands ceil(w / T) */
    const lumis__geom *g;
    const lumis_envmap *env;
    double *ce, *ca, *cb; /* nb x w: sum over the band's rows of Omega_j Y, a_j Y, b_j Y */
    double *crgb;         /* nb x 3w: sum of Omega_j RGB (unscaled) */
    size_t hs;            /* the row sums' band stride: h + 8 */
    double *ry;           /* nc x hs (band-major): sum over the band's columns of Y */
    double *rcs, *rcc;    /* nc x hs: sum of Y cs_i, Y cc_i (only with row_moments) */
    /* A coarse level of STRIPS_GROUP full bands each, so a tall or wide rectangle's
     * marginals add a few coarse bands instead of many fine ones: nB x w for ce, ca, cb
     * and nC x hs for ry, rcs, rcc (nB, nC = full bands / STRIPS_GROUP). */
    int nB, nC;
    double *ce2, *ca2, *cb2, *ry2, *rcs2, *rcc2, *crgb2; /* crgb2: nB x 3w */
    float *y;        /* w x h: every pixel's luminance (lumis__pixel_y) */
    double *scratch; /* 7 max(w, h) doubles, used by lumis__strips_rect and _lights_from_strips */
    size_t scratch_n;
} lumis__strips;

lumis_status lumis__strips_init(lumis__strips *s, const lumis__geom *g, const lumis_envmap *env,
                                int row_moments);
void lumis__strips_free(lumis__strips *s);

/* Column marginals of r: for i in [x0, x1), e[i - x0] = sum over the rows of Omega Y,
 * a[] of a_j Y and b[] of b_j Y (a and b may be NULL). */
void lumis__strips_cols(const lumis__strips *s, lumis__rect r, double *e, double *a, double *b);

/* Row marginals of r: for j in [y0, y1), y[j - y0] = sum over the columns of Y, ycs[] of
 * Y cs_i and ycc[] of Y cc_i (ycs and ycc NULL, or both given with row_moments). */
void lumis__strips_rows(const lumis__strips *s, lumis__rect r, double *y, double *ycs, double *ycc);

/* Totals of r as lumis__acc_rect gives them (without writing labels). */
void lumis__strips_rect(const lumis__strips *s, lumis__rect r, lumis__acc *acc);

/* lumis__lights_from_rects from the strips: labels, sums, lights, extents. */
void lumis__lights_from_strips(lumis_light_set *set, const lumis__strips *s,
                               const lumis__rect *rects, int k);

/* Lights from a complete labelling (set->labels, every pixel in 0 .. count - 1, every label
 * used): one pass of sums, directions at the energy centroids unless dirs (map frame,
 * unit) is given, extents bounding every pixel of each region. */
lumis_status lumis__lights_from_labels(lumis_light_set *set, const lumis__geom *g,
                                       const lumis_envmap *env, const double (*dirs)[3]);

/* Half-angle of a cone from the smallest dot product, rounded up to float. */
float lumis__extent_from_min_dot(double min_dot);

/* Rectangle sides in radians: height pi rows / h, width 2 pi cols / w times sin of the
 * polar angle at the middle of the rectangle. */
void lumis__rect_sides(const lumis__geom *g, lumis__rect r, double *width, double *height);

#endif
