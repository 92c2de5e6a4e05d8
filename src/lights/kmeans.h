/* Wu's EnvDirects' spherical k-means (docs/lights.md, "k-means"), in three files: kmeans.c
 * (the clusters' state and the steps), kmeans_visit.c (an assignment step's re-evaluation
 * of one cluster's members, per SIMD variant) and kmeans_grid.c (the centres in a uniform
 * grid, for radius queries).  What they share: the members' layout, bounds on chords from
 * dot products, the moves. */
#ifndef LUMIS_LIGHTS_KMEANS_H
#define LUMIS_LIGHTS_KMEANS_H

#include "decomp.h"

#include <math.h>
#include <stdint.h>

#if LUMIS__MULTIVERSION /* k-means' AVX-512 visits, when lumis__simd_level() allows them */
#define KM_AVX512 1
#endif

static inline double dist3(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

static inline double sq_dist(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return x * x + y * y + z * z;
}

static inline double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* An upper bound of the chord |x - c| from the computed dot product of unit vectors x and
 * c: |x - c|^2 = |x|^2 + |c|^2 - 2 x.c, the norms within 4e-16 of 1 and the dot product
 * within 4e-16; 4e-15 covers all of it with room to spare. */
static inline double chord_bound(double dot)
{
    double t = 2.0 - 2.0 * dot;
    return sqrt((t > 0.0 ? t : 0.0) + 4e-15);
}

/* Margin of the candidate test: a centre farther than 2 R_a + KM_MARGIN from c_a is
 * farther from every member of a than c_a by at least KM_MARGIN, i.e. its squared chord
 * exceeds c_a's by >= KM_MARGIN^2 = 1e-12, and its dot product falls short of c_a's by
 * >= 5e-13, far beyond rounding: the float comparison could never pick it. */
#define KM_MARGIN 1e-6

/* A lower bound of the chord from the computed dot product (see chord_bound). */
static inline double chord_lower(double dot)
{
    double t = 2.0 - 2.0 * dot - 4e-15;
    return sqrt(t > 0.0 ? t : 0.0);
}

/* A cluster's members, contiguous (structure of arrays), with each member's Hamerly
 * bound kept lazily: slack = (lower bound of the distance to every other centre) - (upper
 * bound of the distance to its own), valid when D[own] + G[own] equalled `now`; since then
 * its own centre moved by at most the growth of D[own] and any other by at most the growth
 * of G[own] (the sum over the steps of the largest drift among the other centres), so
 * slack - (D[own] + G[own] - now) is still a valid slack.  Stored is key = slack + now,
 * and the member cannot change cluster while key - (D[own] + G[own]) exceeds the margin
 * (the rounding of the key, ~1e-16, is far inside the margin). */
typedef struct km_cluster {
    int n, cap;
    int32_t *id;
    double *x, *y, *z, *w, *key;
} km_cluster;

typedef struct km_move {
    int32_t i, to;
    double slack;
} km_move;

/* The centres in a uniform 3D grid over [-1, 1]^3: for unit vectors the chord is the
 * Euclidean distance, so the centres within a radius of a point are found among the cells
 * its box covers, in O(cells + found) instead of O(K).  What the grid returns is a
 * superset, tested with the same sq_dist as a full scan, so every list it yields is the
 * one the scan would (the light sets do not change: docs/lights.md, "k-means"). */
typedef struct km_grid {
    int g;           /* cells per axis */
    double inv_h, h; /* cells per unit; cell size */
    int32_t *start;  /* g^3 + 1 offsets into item */
    int32_t *item;   /* centre indices by cell, ascending within a cell */
    int32_t *cand;   /* a query's result, up to K */
} km_grid;

lumis_status lumis__km_grid_init(km_grid *gr, int k);
void lumis__km_grid_free(km_grid *gr);
/* Counting sort of the centres by cell (stable: ascending indices within a cell). */
void lumis__km_grid_build(km_grid *gr, const double *c, int k);
/* Every centre whose cell meets the box of the ball (p, r) into gr->cand (a superset of the
 * centres within r; a centre left out is farther than r); returns their number, or -1 when
 * the box covers more than a quarter as many cells as there are centres (the caller
 * scans them all then: cheaper). */
int lumis__km_grid_query(km_grid *gr, const double *p, double r, int k);
/* The distance from centre j to its nearest other (INFINITY for K = 1), exactly the
 * minimum a full scan computes. */
double lumis__km_nearest_other(km_grid *gr, const double *c, int k, int j);

/* An assignment step's visit of cluster ca (centre c + 3 ca): its members whose lazy bound
 * fails against `now` (D + G of the cluster) are compared with the near centres nb[0 .. nn)
 * (far: a little under the distance to the nearest centre beyond them); a member that
 * stays gets its new bound, one that moves is appended to moves[nm ..].  fail: room for
 * the cluster's members + 16, zeroed past them.  With avx512 (the CPU has it) eight
 * members at a time, with the same bits.  Returns the new number of moves. */
int lumis__km_visit_cluster(km_cluster *cl, const double *c, int ca, const int32_t *nb, int nn,
                            double far, double now, int avx512, int32_t *fail, km_move *moves,
                            int nm);

/* Spherical k-means of the emissive pixels (dc->em_d, weights em_w) from the k centres c
 * (3 k, updated in place) until no pixel changes cluster (or p->max_iterations): each
 * pixel's cluster into a (m), the iterations and objective history into res. */
lumis_status lumis__kmeans(const lumis__decomp *dc, const lumis__direct_params *p, double *c, int k,
                           int32_t *a, lumis__direct_result *res);

#endif
