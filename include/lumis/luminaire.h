/* lumis/luminaire.h - light-field luminaires and their position-dependent importance
 * sampling (Lu, Pacanowski and Granier, "Position-Dependent Importance Sampling of Light
 * Field Luminaires", IEEE TVCG 21(2), 2015).
 *
 * The model (Goesele et al. 2003): two parallel planes in the luminaire's frame, U at z = 0
 * and S at z = delta; light travels from U towards +z.  M = W x H basis functions Phi_m
 * on U, each with an axis-aligned compact support on a regular grid, and one RGB image
 * C_m per basis function on a rectangle of S: the irradiance a sensor at s recorded while
 * only the part of U weighted by Phi_m let light through.  The radiance of the ray from u
 * through s is
 *     L(u -> s) = sum_m C_m(s) Psi_m(u -> s),   Psi_m(u -> s) = Phi_m(u) delta^2 /
 *                                                               (h_x h_y cos^4 theta),
 * theta the ray's angle to +z and h_x h_y the area of a grid cell (the integral of Phi_m).
 *
 * Sampling, for a shading point p: the support of Phi_m, projected from p onto S, is a
 * box; image m is sampled proportionally to its luminance restricted to that box (exactly:
 * a summed-area table per image gives the restricted marginal and conditional CDFs), and
 * a budget of K samples is shared among images in proportion to their restricted
 * luminance A_m(p), at most K_max each, never dropping an image with A_m(p) > 0.  Every
 * formula, measure and Jacobian, and every choice the paper leaves open: docs/luminaire.md.
 *
 * Random numbers are explicit (two uniform doubles in [0, 1) per sample); results depend
 * only on them.  A built luminaire is immutable: any number of threads may sample it.
 * Per-point calls allocate nothing and take no locks. */
#ifndef LUMIS_LUMINAIRE_H
#define LUMIS_LUMINAIRE_H

#include "lumis/export.h"
#include "lumis/status.h"
#include "lumis/types.h"

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---- bases ------------------------------------------------------------------------- */

typedef enum lumis_luminaire_basis {
    LUMIS_BASIS_DEFAULT = 0, /* == LUMIS_BASIS_QUADRATIC */
    LUMIS_BASIS_QUADRATIC,   /* Goesele et al.'s piecewise quadratic: support 2 x 2 cells */
    LUMIS_BASIS_BSPLINE,     /* uniform quadratic B-spline: support 3 x 3 cells */
    LUMIS_BASIS_COUNT
} lumis_luminaire_basis;

/* "quadratic", "bspline" ("default" for LUMIS_BASIS_DEFAULT). */
LUMIS_API const char *lumis_luminaire_basis_name(lumis_luminaire_basis basis);
LUMIS_API lumis_status lumis_luminaire_basis_from_name(const char *name,
                                                       lumis_luminaire_basis *out);

/* The 1D profile phi(x), x in grid cells from the function's centre; Phi_m(u) =
 * phi((u_x - c_x) / h_x) phi((u_y - c_y) / h_y).  Both profiles are partitions of unity
 * on the integer grid and integrate to 1. */
LUMIS_API double lumis_luminaire_basis_eval(lumis_luminaire_basis basis, double x);

/* Half-width of the profile's support in cells: 1 (quadratic) or 1.5 (B-spline). */
LUMIS_API double lumis_luminaire_basis_radius(lumis_luminaire_basis basis);

/* ---- the luminaire ----------------------------------------------------------------- */

/* The largest luminaire lumis_luminaire_check accepts: basis functions along x or along y
 * (W, H), images in all (M = W H), and pixels along either side of an image.  A file
 * reader (lumis_luminaire_read) refuses beyond them before it reads a pixel. */
#define LUMIS_LUMINAIRE_MAX_GRID   256
#define LUMIS_LUMINAIRE_MAX_IMAGES 1024
#define LUMIS_LUMINAIRE_MAX_SIDE   16384

typedef struct lumis_luminaire_desc {
    double delta;                /* distance from U (z = 0) to S (z = delta), > 0; required */
    lumis_luminaire_basis basis; /* 0 == Goesele's piecewise quadratic */
    int grid[2];                 /* W, H <= 256: functions along x and y (M = W H <= 1024) */
    double grid_origin[2];       /* centre of basis function (0, 0) on U */
    double grid_spacing[2];      /* h_x, h_y > 0: distance between neighbouring centres */
    int width, height;           /* pixels of every image (each <= 16384); required */
    double image_origin[2];      /* (x, y) on S of the corner of pixel (0, 0) */
    double image_size[2];        /* extent of the images on S along x and y, > 0 */
    /* M pointers, function m = a + W b at grid position (a, b); each to width * height RGB
     * float triples, row-major, pixel (i, j) covering x in origin + [i, i + 1) size / width,
     * y likewise (row 0 at the smallest y).  Copied; needed by lumis_luminaire_create,
     * ignored by lumis_luminaire_acquire. */
    const float *const *pixels;
    lumis_error_sink errors; /* errors, and warnings (reported with status LUMIS_OK) */
    /* Values the caller already replaced by 0 in pixels (an image reader's count): added
     * to the luminaire's own count (lumis_luminaire_info.replaced).  0 == none; 0 from
     * lumis_luminaire_get_desc. */
    size_t replaced_before;
} lumis_luminaire_desc;

typedef struct lumis_luminaire lumis_luminaire;

/* Copies the images and builds one summed-area table of quantised luminance per image.
 * Negative or non-finite values are replaced by 0, counted (lumis_luminaire_info) and
 * reported once as a warning.  Cost: O(M pixels) time; memory 12 bytes per pixel (RGB)
 * plus 4 per entry of the (width + 1) x (height + 1) table, per image. */
LUMIS_API lumis_status lumis_luminaire_create(const lumis_luminaire_desc *desc,
                                              lumis_luminaire **out);

/* Checks a description as lumis_luminaire_create does, all but its pixels: delta, basis,
 * grid and image sizes within the limits above, finite origins and extents.  The reason
 * goes to desc->errors.  LUMIS_ERR_INVALID_ARGUMENT (NULL, or a bad field) or
 * LUMIS_ERR_BAD_DIMENSIONS (image sides).  Cost: O(1). */
LUMIS_API lumis_status lumis_luminaire_check(const lumis_luminaire_desc *desc);

LUMIS_API void lumis_luminaire_destroy(lumis_luminaire *lum);

typedef struct lumis_luminaire_info {
    int images;         /* M */
    int grid[2];        /* W, H */
    int width, height;  /* pixels per image */
    double delta;       /* distance from U to S */
    double pixel[2];    /* size of a pixel on S */
    size_t replaced;    /* negative or non-finite pixel values set to 0 */
    size_t bytes;       /* memory owned */
    double total_power; /* sum over images of the luminance integral of C_m over S */
} lumis_luminaire_info;

LUMIS_API void lumis_luminaire_get_info(const lumis_luminaire *lum, lumis_luminaire_info *out);

/* The descriptor the luminaire was built from, pixels pointing at its own copies (valid
 * while it lives): what a writer of luminaire files needs. */
LUMIS_API void lumis_luminaire_get_desc(const lumis_luminaire *lum, lumis_luminaire_desc *out);

/* Image m's RGB pixels (width * height triples, as in the descriptor), or NULL. */
LUMIS_API const float *lumis_luminaire_image(const lumis_luminaire *lum, int m);

/* Radiance L(u -> s) of the ray from (ux, uy, 0) through (sx, sy, delta): the sum over the
 * at most 4 (quadratic) or 9 (B-spline) functions whose support contains u.  Zero outside
 * the images.  Cost: one pixel lookup per such function. */
LUMIS_API lumis_rgb lumis_luminaire_radiance(const lumis_luminaire *lum, double ux, double uy,
                                             double sx, double sy);

/* ---- rigid placement in a scene ------------------------------------------------------ */

/* world = R local + t, R a rotation (row-major). */
typedef struct lumis_rigid {
    double r[9];
    double t[3];
} lumis_rigid;

LUMIS_API lumis_rigid lumis_rigid_identity(void);
/* LUMIS_ERR_INVALID_ARGUMENT unless R is orthonormal with determinant +1 (to 1e-6). */
LUMIS_API lumis_status lumis_rigid_check(const lumis_rigid *x);
LUMIS_API lumis_vec3 lumis_rigid_point_to_local(const lumis_rigid *x, lumis_vec3 world);
LUMIS_API lumis_vec3 lumis_rigid_point_to_world(const lumis_rigid *x, lumis_vec3 local);
LUMIS_API lumis_vec3 lumis_rigid_dir_to_local(const lumis_rigid *x, lumis_vec3 world);
LUMIS_API lumis_vec3 lumis_rigid_dir_to_world(const lumis_rigid *x, lumis_vec3 local);

/* ---- sampling ---------------------------------------------------------------------- */

typedef enum lumis_luminaire_strategy {
    LUMIS_LUM_STRATEGY_DEFAULT = 0, /* == LUMIS_LUM_RESTRICTED */
    LUMIS_LUM_RESTRICTED,           /* Lu et al.: luminance restricted to the projected box */
    LUMIS_LUM_UNIFORM,              /* baseline: uniform over the projected box */
    LUMIS_LUM_GLOBAL,               /* baseline: global CDFs, no restriction, the same
                                       samples for every point */
    LUMIS_LUM_AUTO,                 /* renders only: per placed luminaire, the strategy
                                       lumis_luminaire_predict expects fastest at equal
                                       error (the samplers refuse it) */
    LUMIS_LUM_STRATEGY_COUNT
} lumis_luminaire_strategy;

typedef enum lumis_luminaire_search {
    LUMIS_LUM_SEARCH_DEFAULT = 0, /* == LUMIS_LUM_BINARY: the same samples, faster
                                     (docs/luminaire.md, "Searches") */
    LUMIS_LUM_SECANT,             /* the paper's modified secant search */
    LUMIS_LUM_BINARY,             /* bisection */
    LUMIS_LUM_SEARCH_COUNT
} lumis_luminaire_search;

/* "restricted", "uniform", "global", "auto"; "secant", "binary". */
LUMIS_API const char *lumis_luminaire_strategy_name(lumis_luminaire_strategy strategy);
LUMIS_API lumis_status lumis_luminaire_strategy_from_name(const char *name,
                                                          lumis_luminaire_strategy *out);
LUMIS_API const char *lumis_luminaire_search_name(lumis_luminaire_search search);
LUMIS_API lumis_status lumis_luminaire_search_from_name(const char *name,
                                                        lumis_luminaire_search *out);

typedef struct lumis_luminaire_query {
    lumis_vec3 p;                      /* shading point, luminaire frame */
    int budget;                        /* K, samples to share among images; 0 == 32 */
    int k_max;                         /* K_max, most samples for one image; 0 == no cap */
    lumis_luminaire_strategy strategy; /* 0 == restricted */
    lumis_luminaire_search search;     /* 0 == binary */
    int depth;                         /* probes per 1D inversion; 0 == unlimited (exact).
                                          A limited search interpolates inside the bracket
                                          it reached: approximate, biased (Fig. 5). */
    /* Optional source of the random numbers: NULL, the caller's array u holds capacity
     * pairs; else the samplers call fill(fill_ctx, buf, n) for the next n numbers (n even,
     * at most 128, in the order u would hold them) as they need them and ignore u, so a
     * caller pays for only the numbers the point uses (often far fewer than capacity). */
    void (*fill)(void *fill_ctx, double *buf, int n);
    void *fill_ctx;
} lumis_luminaire_query;

/* Which plane a sample's pdf is per unit area of. */
typedef enum lumis_luminaire_measure {
    LUMIS_LUM_AREA_S = 0, /* per unit area on S: the general case */
    LUMIS_LUM_AREA_U = 1, /* per unit area on U: p on S (Eq. 9), where s = p */
} lumis_luminaire_measure;

typedef struct lumis_luminaire_sample {
    double s[2];        /* point on S (z = delta), luminaire frame */
    double u[2];        /* point on U (z = 0) on the line through p and s */
    lumis_vec3 dir;     /* unit direction from p towards u: where the light comes from */
    float distance;     /* |u - p| */
    lumis_rgb radiance; /* image m's share of L(u -> s): C_m(s) Psi_m(u -> s) */
    float pdf;          /* density of the sampled point per unit area (see measure) */
    float weight;       /* 1 / (K_m pdf_omega), pdf_omega the density per steradian at p:
                           the sample adds radiance * cos(n, dir) * weight to I(p) */
    int image;          /* m */
    int count;          /* K_m, samples image m received at p */
    lumis_luminaire_measure measure;
} lumis_luminaire_sample;

/* Samples capacity lumis_luminaire_sample needs for a budget K: max(K, M). */
LUMIS_API int lumis_luminaire_capacity(const lumis_luminaire *lum, int budget);

/* All samples for point q->p: balances the budget over images (lumis_luminaire_balance on
 * A_m(p), or on each image's total luminance for the global strategy), then draws K_m
 * samples from each image m in increasing m, sample k from u[2k], u[2k + 1] (or from the
 * numbers q->fill hands out, in the same order; u may then be NULL).  The total is
 * min(K, K_max n) but at least n, n the images with A_m(p) > 0; a point with z <= 0 (behind
 * U) or outside every projected support gets none (*count = 0, LUMIS_OK).  Fails with
 * LUMIS_ERR_INVALID_ARGUMENT if capacity is too small (lumis_luminaire_capacity suffices).
 * Cost: per point, W + H box ranges, 16 table lookups per image whose box meets the image's
 * nonzero pixels, the balancing; per image that gets samples, its restricted marginal over
 * the box's columns (4 lookups per column) unless the box is wide and drawn rarely; per
 * sample, the marginal bisection in that table (log2 of the box's width probes, in L1), the
 * conditional (6 lookups, then log2 of the box's height probes of 2 lookups), one RGB
 * pixel.  Binary search: every draw of the point in lockstep across images, so their loads
 * overlap.  Secant: per draw, data-dependent probes of 4 and 2 lookups.  Measured times
 * per sample: docs/benchmarks.md.  Stack: about 100 KB.  No allocation. */
LUMIS_API lumis_status lumis_luminaire_sample_point(const lumis_luminaire *lum,
                                                    const lumis_luminaire_query *q, const double *u,
                                                    int capacity, lumis_luminaire_sample *out,
                                                    int *count);

/* The global strategy's points on S do not depend on the shading point: a renderer draws
 * them once per set of random numbers and finishes them for every point.
 * lumis_luminaire_global_draw (q->strategy must be LUMIS_LUM_GLOBAL; q->p is ignored) fills
 * each sample's s, image, count and, parked in u[0], its density per pixel area; nothing
 * that needs p.  lumis_luminaire_global_finish completes them for p (out may be drawn):
 * draw then finish gives what lumis_luminaire_sample_point gives for p with the same u, bit
 * for bit (none for p behind U).  Cost of a finish: per sample one RGB pixel and a few
 * dozen flops; no table lookup. */
LUMIS_API lumis_status lumis_luminaire_global_draw(const lumis_luminaire *lum,
                                                   const lumis_luminaire_query *q, const double *u,
                                                   int capacity, lumis_luminaire_sample *out,
                                                   int *count);
LUMIS_API lumis_status lumis_luminaire_global_finish(const lumis_luminaire *lum, lumis_vec3 p,
                                                     const lumis_luminaire_sample *drawn, int count,
                                                     lumis_luminaire_sample *out, int *out_count);

/* The estimator (Eq. 13/14) from the samples of one point: sum of radiance *
 * max(0, n . dir) * weight, n normalised here.  Unbiased for I(p) with an unlimited search (no
 * visibility: multiply each term by it to light a scene). */
LUMIS_API lumis_rgb lumis_luminaire_estimate(const lumis_luminaire_sample *samples, int count,
                                             lumis_vec3 n);

/* A_m(p) for every image (out: M doubles): the luminance integral of C_m over the box its
 * support projects to from p (or, for p on S, Y_m(p) times the support's area on U).
 * Cost: 16 lookups per image whose box meets its image. */
LUMIS_API void lumis_luminaire_masses(const lumis_luminaire *lum, lumis_vec3 p, double *out);

/* Shares budget samples among n images in proportion to mass (>= 0): counts[i] = 0 when
 * mass[i] == 0, else 1 <= counts[i] <= k_max (k_max 0: no cap), summing to
 * min(budget, k_max n+) but at least n+ (n+ the nonzero masses); each count within one of
 * its proportional share where no cap or minimum intervenes.  Returns the sum.  O(n) when
 * nothing is capped. */
LUMIS_API int lumis_luminaire_balance(const double *mass, int n, int budget, int k_max,
                                      int *counts);

/* One sample of image m alone at point p, strategy restricted, uniform or global (the
 * global strategy ignores p for s): fills everything but count (1) and the weight's K_m
 * (taken as 1).  LUMIS_ERR_INVALID_ARGUMENT if image m has nothing to sample at p
 * (A_m(p) == 0).  Cost: as one sample of lumis_luminaire_sample_point plus 16 lookups. */
LUMIS_API lumis_status lumis_luminaire_sample_image(const lumis_luminaire *lum,
                                                    const lumis_luminaire_query *q, int m,
                                                    double u1, double u2,
                                                    lumis_luminaire_sample *out);

/* Density per unit area on S with which image m's sampler at p (strategy q->strategy)
 * draws (sx, sy); 0 outside its box.  For p on S, per unit area on U at (sx, sy) read as
 * a point of U.  Cost: 16 lookups + 4. */
LUMIS_API double lumis_luminaire_pdf(const lumis_luminaire *lum, const lumis_luminaire_query *q,
                                     int m, double sx, double sy);

/* The (u1, u2) that lumis_luminaire_sample_image maps to (sx, sy) (restricted or uniform
 * strategy, exact search): the inverse warp.  LUMIS_ERR_INVALID_ARGUMENT outside the box. */
LUMIS_API lumis_status lumis_luminaire_invert(const lumis_luminaire *lum,
                                              const lumis_luminaire_query *q, int m, double sx,
                                              double sy, double *u1, double *u2);

/* ---- which strategy pays: a prediction ------------------------------------------------
 *
 * For a set of probe points (where a scene's surfaces will be shaded), the variance of each
 * strategy's estimate of I(p) and its cost, hence the time each needs for an equal mean
 * squared error, from the luminaire's tables alone (no scene, no render): docs/luminaire.md,
 * "Which strategy pays".  Per probe and per image m whose box holds energy, a few pilot
 * samples of the restricted and uniform samplers give the first and second moments of the
 * one-sample estimate; the global strategy's moments follow exactly from the restricted
 * ones (its pdf is the restricted one times units(box) / units(image)); the balance gives
 * each strategy's K_m.  The costs are a linear model in nanoseconds (shading points,
 * images with energy, draws, shadow rays) whose defaults were measured on the machine
 * this was written on (lumis_luminaire_costs_default). */

#define LUMIS_LUM_MAX_BANDS 4

/* A point where the scene is shaded: luminaire frame, n its surface normal (need not be
 * unit; light from behind it is not counted). */
typedef struct lumis_luminaire_probe {
    lumis_vec3 p, n;
} lumis_luminaire_probe;

/* The cost model, nanoseconds.  A point sampled with the restricted or uniform strategy
 * costs camera + image_* x (images with energy in their box) + draw x samples + ray x
 * (samples with energy); a global sample costs global + ray x (its chance of energy); the
 * global draws and the camera ray are shared by many samples (its best budget is large). */
typedef struct lumis_luminaire_costs {
    double camera;           /* per shading point: its camera ray, hit and frame */
    double image_restricted; /* per image with energy in its box: A_m(p), the balance,
                                the box's preparation (its marginal's ends) */
    double image_uniform;    /* the same for the uniform strategy */
    double restricted;       /* per restricted draw: the 2D inversion, direction, radiance */
    double uniform;          /* per uniform draw */
    double global;           /* per global sample finished at a point */
    double ray;              /* per shadow ray, with the BSDF's evaluation */
} lumis_luminaire_costs;

/* The defaults (docs/luminaire.md, "Which strategy pays", how they were measured). */
LUMIS_API lumis_luminaire_costs lumis_luminaire_costs_default(void);

typedef struct lumis_luminaire_predict_desc {
    const lumis_luminaire_probe *probes; /* required */
    int probe_count;                     /* 1 to 1 << 20 */
    int budget;                          /* K of the restricted and uniform strategies; 0 == 32 */
    int k_max;                           /* their cap; 0 == none */
    int pilot;                           /* pilot samples per image per probe (<= 4096):
                                            a jittered grid of the largest square <= it, or
                                            with strata, max(2, pilot / n') nets; 0 == 16 */
    uint64_t seed;                       /* of the pilot samples */
    /* 0 or 1: a point's samples are independent (PCG32).  n > 1: sample j of a point is
     * one of a (0,2) sequence's points over n camera samples (sobol, zsobol, pmj02,
     * stratified): the restricted and uniform variances are then those of the mean of
     * Owen-scrambled (0,2) nets of n' points (n' the largest power of two <= min(n, 16)),
     * measured by pilot nets, times n'; beyond 16 extrapolated as a power law in the
     * points, at least 1 / n.  The global strategy's shared draws stay independent. */
    int strata;
    const lumis_luminaire_costs *costs; /* NULL == lumis_luminaire_costs_default() */
    /* 0: every probe counts once.  n > 0 (fewer than the probes): n of the lit ones are
     * drawn in proportion to q = (a / sum a + g / sum g + 1 / lit) / 3, a and g one-point
     * proxies of I(p)^2 and of the global variance, each weighted 1 / (n q), the sums
     * divided by the lit count: the means stay unbiased, and the few points that dominate
     * them are not missed (a small lit object decided a scene: docs/results/lu-strategy). */
    int select;
    /* Optional bands of distance from the luminaire's origin: band b holds the probes with
     * band_edges[b - 1] <= |p| < band_edges[b] (edges increasing); 0 or 1 == one band. */
    int bands;
    double band_edges[LUMIS_LUM_MAX_BANDS - 1];
    lumis_error_sink errors;
} lumis_luminaire_predict_desc;

/* One strategy's prediction, means over the lit probes. */
typedef struct lumis_luminaire_strategy_prediction {
    double samples;      /* samples a point evaluates (global: 1, a sample) */
    double rays;         /* of them with energy: shadow rays */
    double variance;     /* of that point's estimate of I(p) (luminance, the tables' units);
                            a mean of variances, as a mean squared error weighs pixels (a
                            relative one would let a beam's dimmest edge decide) */
    double ns;           /* predicted nanoseconds per point (global: per sample) */
    double work;         /* variance x ns: proportional to the time for a given MSE */
    double time_ratio;   /* global's work / this work: how many times less time than
                            global this strategy needs for an equal error */
    double sample_ratio; /* the same for samples */
} lumis_luminaire_strategy_prediction;

/* One band's means over its lit probes, per strategy (restricted, uniform, global; the
 * global's per sample), as in lumis_luminaire_strategy_prediction. */
typedef struct lumis_luminaire_band {
    int probes_lit;
    double share; /* of the lit probes' weight */
    double variance[3], ns[3];
} lumis_luminaire_band;

typedef struct lumis_luminaire_prediction {
    lumis_luminaire_strategy_prediction restricted, uniform, global;
    lumis_luminaire_strategy best; /* restricted, uniform or global: the least work */
    double energy_share;           /* mean share of global samples with energy at a probe */
    double distance[3];            /* of the lit probes from the luminaire's origin: min,
                                      median, max */
    int probes_lit;                /* probes evaluated with energy in some box (the
                                      others are ignored); the means are over the lit
                                      probes (estimated from those drawn, with select) */
    int images_lit;                /* mean images with energy in their box at a lit probe */
    int bands;                     /* the descriptor's (at least 1) */
    lumis_luminaire_band band[LUMIS_LUM_MAX_BANDS];
} lumis_luminaire_prediction;

/* Fills *out, or fails with LUMIS_ERR_INVALID_ARGUMENT.  With no lit probe, every number
 * is 0 and best is LUMIS_LUM_RESTRICTED (the paper's).
 * Cost: O(probes x images with energy) pilot draws (2 each; measured times:
 * docs/benchmarks.md); deterministic for a seed; allocates a double per probe. */
LUMIS_API lumis_status lumis_luminaire_predict(const lumis_luminaire *lum,
                                               const lumis_luminaire_predict_desc *desc,
                                               lumis_luminaire_prediction *out);

/* n probes lit by the luminaire at distances in [dmin, dmax] (luminaire units, from a point
 * of U, log-uniform), facing it: along rays from U through S drawn in proportion to the
 * light's power, as a scene's surfaces in the beam would be.  dmin > 0, dmax >= dmin.
 * Deterministic for a seed. */
LUMIS_API lumis_status lumis_luminaire_probes(const lumis_luminaire *lum, double dmin, double dmax,
                                              uint64_t seed, int n, lumis_luminaire_probe *out);

/* Irradiance I(p) on a surface of normal n (need not be unit) by deterministic quadrature:
 * over S, per image, on pieces cut at pixel edges and at the basis' knots (Gauss-Legendre
 * with `order` points per axis per piece, 0 == 4), or over U for p on S.  For tests and
 * references: O(pixels in the boxes) time, no allocation. */
LUMIS_API lumis_status lumis_luminaire_irradiance(const lumis_luminaire *lum, lumis_vec3 p,
                                                  lumis_vec3 n, int order, lumis_rgb *out);

/* ---- synthetic acquisition ----------------------------------------------------------- */

/* A flat emissive disk parallel to U, behind it (center z < 0), radiance
 * radiance * cos^exponent(theta) towards +z (theta the angle to +z). */
typedef struct lumis_emitter_disk {
    double center[3];
    double radius;
    lumis_rgb radiance;
    double exponent; /* >= 0; 0 == Lambertian (constant radiance) */
} lumis_emitter_disk;

typedef enum lumis_emitter_pattern {
    LUMIS_PATTERN_NONE = 0, /* clear */
    LUMIS_PATTERN_STRIPES,  /* stripes across x of the given period */
    LUMIS_PATTERN_CHECKER,  /* a checkerboard of the given period */
    LUMIS_PATTERN_COUNT
} lumis_emitter_pattern;

/* Disks behind a patterned plate (a reflector's facets or a lens) at z = plate_z, between
 * the disks and U; rays crossing a dark part keep 1 - contrast of their radiance. */
typedef struct lumis_emitter_desc {
    const lumis_emitter_disk *disks;
    int disk_count;
    lumis_emitter_pattern pattern;
    double plate_z;   /* < 0 and > every disk's z (unless pattern NONE) */
    double period[2]; /* > 0 for a pattern */
    double contrast;  /* in [0, 1] */
    lumis_rgb tint;   /* colour of the dark parts' transmission; 0 == (1, 1, 1) */
} lumis_emitter_desc;

typedef struct lumis_acquire_desc {
    int samples_s;           /* sensor samples per pixel per axis; 0 == 2 */
    int samples_radial;      /* quadrature nodes across each disk's footprint on U; 0 == 6 */
    int samples_angular;     /* ... around it; 0 == 16 */
    lumis_error_sink errors; /* errors */
} lumis_acquire_desc;

/* "Photographs" the emitter through each basis function: C_m(pixel) = the mean over the
 * pixel of E_m(s) = integral over U of L_e(u -> s) Phi_m(u) cos^4 theta / delta^2 du (the
 * irradiance of a sensor at s behind filter Phi_m), by quadrature over each disk's
 * footprint on U.  layout gives the geometry (its pixels are ignored).  Then builds the
 * luminaire as lumis_luminaire_create.  Cost: O(M pixels samples_s^2 disks nodes / M')
 * where M' ~ the number of supports a footprint meets (measured: docs/benchmarks.md). */
LUMIS_API lumis_status lumis_luminaire_acquire(const lumis_luminaire_desc *layout,
                                               const lumis_emitter_desc *emitter,
                                               const lumis_acquire_desc *acquire,
                                               lumis_luminaire **out);

/* The emitter's true radiance along the ray from (ux, uy, 0) towards (sx, sy, delta). */
LUMIS_API lumis_rgb lumis_emitter_radiance(const lumis_emitter_desc *emitter, double delta,
                                           double ux, double uy, double sx, double sy);

/* The emitter's true irradiance at p (z > 0) on a surface of normal n, by quadrature over
 * each disk's footprint on U (nodes: radial x angular per disk; 0 == 48 x 96). */
LUMIS_API lumis_status lumis_emitter_irradiance(const lumis_emitter_desc *emitter, lumis_vec3 p,
                                                lumis_vec3 n, int radial, int angular,
                                                lumis_rgb *out);

/* Layouts of the paper's Table 1 (geometry only; pixels NULL): an emitter of that size. */
typedef enum lumis_luminaire_preset {
    LUMIS_PRESET_BIKE = 0, /* 9 x 7 images of 300 x 300 */
    LUMIS_PRESET_CAR = 1,  /* 11 x 9 images of 256 x 256 */
    LUMIS_PRESET_SMALL = 2 /* 4 x 3 images of 24 x 20: tests */
} lumis_luminaire_preset;

/* Fills a layout, and an emitter (disks: storage for at least 4) that fits it: a few small
 * bright disks behind a striped plate, like a headlight. */
LUMIS_API lumis_status lumis_luminaire_preset_get(lumis_luminaire_preset preset,
                                                  lumis_luminaire_desc *layout,
                                                  lumis_emitter_desc *emitter,
                                                  lumis_emitter_disk *disks);

/* "car", "bike", "small". */
LUMIS_API const char *lumis_luminaire_preset_name(lumis_luminaire_preset preset);
LUMIS_API lumis_status lumis_luminaire_preset_from_name(const char *name,
                                                        lumis_luminaire_preset *out);

/* A preset's luminaire, acquired from its emitter with the default acquisition settings
 * and the given basis (0 == the preset's): lumis_luminaire_preset_get then
 * lumis_luminaire_acquire.  About 2 s for the car preset. */
LUMIS_API lumis_status lumis_luminaire_preset_create(lumis_luminaire_preset preset,
                                                     lumis_luminaire_basis basis,
                                                     const lumis_error_sink *errors,
                                                     lumis_luminaire **out);

#ifdef __cplusplus
}
#endif
#endif
