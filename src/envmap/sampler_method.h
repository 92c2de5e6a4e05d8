/* The interface between sampler.c and the sampling methods (sampler_*.c), not public API.
 *
 * A method picks a rectangle of pixels [x0, x1) x [y0, y1) (one pixel, a kd-tree block or
 * the whole map) and a point (s, t) in [0,1)^2; sampler.c turns that into a direction
 * uniform in solid angle inside the rectangle (or uniform in angles, for the kd-tree's
 * literal variant), checks that the rounded direction still lies in the rectangle, and
 * looks up its radiance.  pdf() goes the other way: direction -> pixel -> the method's
 * density for that pixel.  Both paths call the same density function with the same
 * arguments, so pdf(sample(u).dir) == sample(u).pdf exactly. */
#ifndef LUMIS_SAMPLER_METHOD_H
#define LUMIS_SAMPLER_METHOD_H

#include "lumis/sampler.h"

#include "internal.h"

typedef struct lumis__pick {
    int x0, y0, x1, y1; /* the rectangle, in pixels */
    double s, t;        /* point inside it, [0,1)^2 (s along u, t along cos theta) */
    double density;     /* the method's density there (see lumis__method.uniform_angles) */
} lumis__pick;

typedef struct lumis__method {
    /* Maps (u1, u2) to a rectangle, a point in it and its density. */
    void (*pick)(const lumis_sampler *s, double u1, double u2, lumis__pick *out);
    /* The density of the region holding pixel (i, j), exactly as pick() reports it. */
    double (*density)(const lumis_sampler *s, int i, int j);
    void (*destroy)(lumis_sampler *s);
    /* 0: density is per steradian (uniform in solid angle inside the rectangle).
     * 1: density is per unit of (phi, theta): the sampler divides by sin(theta). */
    int uniform_angles;
    /* Optional: pick() for n <= LUMIS__BATCH pairs u[0..2n) (already clamped to [0, 1)),
     * with the same results, its lookups interleaved so their cache misses overlap. */
    void (*pick_n)(const lumis_sampler *s, const double *u, int n, lumis__pick *out);
    /* Optional (continuous, one-to-one warps): the u that pick() maps to pixel (i, j) and
     * point (s, t) in it.  NULL: lumis_sampler_invert() reports LUMIS_ERR_UNSUPPORTED. */
    void (*invert)(const lumis_sampler *s, int i, int j, double ps, double pt, double u[2]);
} lumis__method;

enum { LUMIS__BATCH = 32 }; /* samples in flight in sample_n() */

struct lumis_sampler {
    const lumis__method *m;
    const lumis_envmap *env;
    lumis_sampler_method method;
    int w, h;
    int fallback;
    double build_ms;
    size_t table_bytes, total_bytes;
    double kd_alpha;
    int kd_blocks;
    double inv_w; /* 1 / w: a column to an azimuth without a division */
    void *data;   /* the method's own tables */
};

/* Per-pixel importance (w * h doubles, row-major) as the descriptor asks, with MIS
 * compensation applied.  *total receives the sum; 0 means nothing to sample. */
lumis_status lumis__importance(const lumis_envmap *env, const lumis_sampler_desc *desc,
                               double **out, double *total);

/* The methods. */
lumis_status lumis__uniform_init(lumis_sampler *s);
lumis_status lumis__inversion_init(lumis_sampler *s, const double *imp, int guided);
lumis_status lumis__alias_init(lumis_sampler *s, const double *imp);
lumis_status lumis__hierarchical_init(lumis_sampler *s, const double *imp);
lumis_status lumis__kdtree_init(lumis_sampler *s, const double *imp,
                                const lumis_sampler_desc *desc);

/* Internals of the kd-tree exposed for tests (src/envmap/sampler_kdtree.c). */
double lumis__kdtree_objective(const double *p, int n, double alpha);
double lumis__kdtree_fit_alpha(const double *p, int n);
int lumis__kdtree_best_split(const double *sat, const double *rows, int w, int x0, int y0, int x1,
                             int y1, int *axis, int *pos);
const uint16_t *lumis__kdtree_blocks(const lumis_sampler *s, int *n);

#endif
