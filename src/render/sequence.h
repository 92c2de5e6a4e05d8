/* The renderer's sample sequences (internal to lumis-render): where every number a camera
 * sample uses comes from.  A camera sample k of pixel (x, y) is a stream of dimensions;
 * each use of numbers takes the next dimension (a pair: one 2D point, or its first
 * coordinate for one number) and asks for point j of the n that camera sample draws in
 * it (n light samples of one vertex, a luminaire's samples ...): index k n + j of the
 * dimension's sequence.  The layout, fixed whatever a sample hits (docs/sampling.md):
 *   dimension 0                 the camera's jitter
 *   then, per vertex of the path, what its light kind takes (light_env.c, light_set.c,
 *   light_luminaire.c), then the BSDF sample that continues the path (integrator.c).
 * PCG32 (the independent reference) ignores dimensions and indices: it hands out its
 * stream's numbers in the order they are asked for, as the renderer always did. */
#ifndef LUMIS_RENDER_SEQUENCE_H
#define LUMIS_RENDER_SEQUENCE_H

#include "lumis/render.h"
#include "lumis/rng.h"

#include <stdint.h>

/* A render's sequence: its kind, seed, the samples per pixel it plans for (stratified and
 * zsobol: 2^log2n), and pmj02's tables. */
typedef struct lumis__seq {
    lumis_sequence kind;
    uint64_t seed, key; /* key: the seed hashed */
    int log2n;
    uint32_t *pmj; /* pmj02: LUMIS__PMJ_PATTERNS tables of LUMIS__PMJ_POINTS (x, y) */
    /* Sobol's dimension 1, bits reversed, a byte of the index at a time: the xor of the
     * reversed columns of the byte's set bits (sobol, zsobol) */
    uint32_t sobol1[4][256];
} lumis__seq;

enum { LUMIS__PMJ_PATTERNS = 32, LUMIS__PMJ_LOG2 = 10, LUMIS__PMJ_POINTS = 1 << LUMIS__PMJ_LOG2 };

/* Makes q for d (its sequence, seed and spp; 0: plan for 2^16 samples).  pmj02 generates
 * its tables here (about 23 ms on one core). */
lumis_status lumis__seq_init(lumis__seq *q, const lumis_render_desc *d, int planned_spp);
void lumis__seq_release(lumis__seq *q);

/* One camera sample's stream. */
typedef struct lumis__stream {
    const lumis__seq *q;
    lumis_pcg32 rng; /* PCG32's numbers; the others' jitter where they need one */
    uint64_t pixel;  /* a hash of the seed and the pixel */
    uint64_t morton; /* zsobol: the pixel's z-order */
    uint32_t k;      /* the camera sample */
    uint32_t dim;    /* the next dimension */
} lumis__stream;

void lumis__stream_start(lumis__stream *s, const lumis__seq *q, int x, int y, int width, int k);

/* Point j of the n the camera sample draws in dimension dim, in [0, 1)^2 (one_d: only u[0]
 * is used, stratified over n strata rather than a grid). */
void lumis__seq_point(lumis__stream *s, uint32_t dim, uint32_t j, uint32_t n, int one_d,
                      double u[2]);

/* The next dimension. */
static inline uint32_t seq_take(lumis__stream *s)
{
    return s->dim++;
}

static inline void seq_2d(lumis__stream *s, uint32_t dim, uint32_t j, uint32_t n, double u[2])
{
    if (s->q->kind == LUMIS_SEQUENCE_PCG) {
        u[0] = lumis_pcg32_double(&s->rng);
        u[1] = lumis_pcg32_double(&s->rng);
    } else {
        lumis__seq_point(s, dim, j, n, 0, u);
    }
}

static inline double seq_1d(lumis__stream *s, uint32_t dim, uint32_t j, uint32_t n)
{
    if (s->q->kind == LUMIS_SEQUENCE_PCG) return lumis_pcg32_double(&s->rng);
    double u[2];
    lumis__seq_point(s, dim, j, n, 1, u);
    return u[0];
}

/* The next n dimensions (the first of them). */
static inline uint32_t seq_take_n(lumis__stream *s, uint32_t n)
{
    const uint32_t d = s->dim;
    s->dim += n;
    return d;
}

/* Point j of n of a BSDF sample's three numbers (lobe choice, then the direction's 2D
 * point), in the two dimensions from dim (seq_take_n(s, 2)). */
static inline void seq_bsdf(lumis__stream *s, uint32_t dim, uint32_t j, uint32_t n, double u[3])
{
    u[0] = seq_1d(s, dim, j, n);
    seq_2d(s, dim + 1, j, n, u + 1);
}

#endif
