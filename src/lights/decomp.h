/* Wu's decomposition: state shared by its three files (not public API).
 *   decomposition.c      Eq. 1 threshold, Eq. 2 budget, assembling the set
 *   env_direct.c         EnvDirects: sum-tree sampling, masking, k-means, return
 *   illumination_cut.c   EnvIndirects: implicit light tree and its cut (Eq. 3) */
#ifndef LUMIS_LIGHTS_DECOMP_H
#define LUMIS_LIGHTS_DECOMP_H

#include "internal.h"

#include "lumis/rng.h"

typedef struct lumis__decomp {
    const lumis_envmap *env;
    const lumis__geom *g;
    const lumis_decomp_desc *desc;
    int w, h;
    const float *y;  /* per-pixel luminance (lumis__pixel_y) */
    int32_t *labels; /* the set's labels, used as scratch (see each step) */

    /* Emissive pixels. */
    int m;
    int32_t *em_pix;     /* pixel index */
    double *em_d;        /* 3 m: unit direction of the pixel's centroid (map frame) */
    double *em_w;        /* k-means weight Y |m_p| */
    double *em_e;        /* sampling weight Y Omega */
    int32_t *em_cluster; /* cluster, or -1 when returned to the non-emissive set */
} lumis__decomp;

/* Parameters of the EnvDirect step, defaults applied. */
typedef struct lumis__direct_params {
    int budget;           /* N */
    int mask;             /* mask a cap after each draw */
    int kmeans;           /* refine with k-means */
    double mask_radius;   /* radians */
    double return_radius; /* radians; >= pi returns nothing */
    int max_iterations;   /* assignment steps after the first; 0 == unlimited */
    uint64_t seed;
} lumis__direct_params;

/* Output of the EnvDirect step. */
typedef struct lumis__direct_result {
    int clusters; /* nonempty clusters, ids 0 .. clusters-1 in em_cluster */
    int seeds;
    int iterations;
    int converged;
    int returned;
    double *objective; /* malloc'ed history */
    int objective_count;
} lumis__direct_result;

/* On entry labels[p] is the emissive index of pixel p or -1.  On return em_cluster is set,
 * labels[p] is the cluster of each clustered emissive pixel and -1 for every other. */
lumis_status lumis__env_direct(lumis__decomp *dc, const lumis__direct_params *p,
                               lumis__direct_result *out);

/* Per-tile sums of the non-emissive pixels (E = sum Y Omega, M = sum Y m, N = pixels),
 * stored at [(ty + 1)(tw + 1) + tx + 1] and turned into summed-area tables by
 * lumis__tiles_prefix.  T = 4 on maps of 2^16 pixels or more, else 1. */
enum { LUMIS__Q_E, LUMIS__Q_MX, LUMIS__Q_MY, LUMIS__Q_MZ, LUMIS__Q_N, LUMIS__Q_COUNT };
typedef struct lumis__tiles {
    int T, tw, th;
    double *q[LUMIS__Q_COUNT];
} lumis__tiles;

lumis_status lumis__tiles_init(lumis__tiles *t, int w, int h);
void lumis__tiles_free(lumis__tiles *t);
/* Adds one pixel of luminance y (before the prefix sums). */
void lumis__tiles_add(lumis__tiles *t, const lumis__geom *g, int i, int j, double y);
void lumis__tiles_prefix(lumis__tiles *t);

/* The cut: up to `budget` rectangles covering every pixel labelled -1 (the non-emissive
 * set), each holding at least one of them.  *count receives how many (fewer than budget
 * only if there are fewer such pixels).  rects holds budget entries. */
lumis_status lumis__illumination_cut(const lumis__decomp *dc, const lumis__tiles *tiles, int budget,
                                     lumis_cut_objective obj, double w_v, double w_d, double w_e,
                                     lumis__rect *rects, int *count);

#endif
