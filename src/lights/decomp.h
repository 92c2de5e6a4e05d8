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
    const uint64_t *em_bits; /* bit p: pixel p is emissive (its luminance is over L_T) */
    int32_t *labels;         /* the set's labels, used as scratch: until the end only an
                              * emissive pixel's label is written (its index, then its
                              * cluster or -1) */

    /* Emissive pixels. */
    int m;
    int32_t *em_pix;     /* pixel index */
    double *em_d;        /* 3 m: unit direction of the pixel's centroid (map frame) */
    double *em_w;        /* k-means weight Y |m_p| */
    double *em_e;        /* sampling weight Y Omega */
    int32_t *em_cluster; /* cluster, or -1 when returned to the non-emissive set */
} lumis__decomp;

/* Whether pixel p is emissive (over the threshold). */
static inline int lumis__emissive(const lumis__decomp *dc, size_t p)
{
    return (int)((dc->em_bits[p >> 6] >> (p & 63)) & 1u);
}

/* Whether pixel p belongs to the non-emissive set: under the threshold (such a pixel's
 * label is not written before the end), or emissive and returned (label -1). */
static inline int lumis__non_emissive(const lumis__decomp *dc, size_t p)
{
    return !lumis__emissive(dc, p) || dc->labels[p] == -1;
}

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

/* On entry labels[p] is the emissive index of each emissive pixel p.  On return em_cluster
 * is set, and labels[p] is the cluster of each clustered emissive pixel, -1 of each
 * returned one. */
lumis_status lumis__env_direct(lumis__decomp *dc, const lumis__direct_params *p,
                               lumis__direct_result *out);

/* Per-tile sums of the non-emissive pixels (E = sum Y Omega, M = sum Y m, N = pixels),
 * stored at [(ty + 1)(tw + 1) + tx + 1] and turned into summed-area tables by
 * lumis__tiles_prefix; rgb (sum L Omega, same layout) stays per tile.  T = 4 on maps of
 * 2^16 pixels or more, else 1. */
enum { LUMIS__Q_E, LUMIS__Q_MX, LUMIS__Q_MY, LUMIS__Q_MZ, LUMIS__Q_N, LUMIS__Q_COUNT };
typedef struct lumis__tiles {
    int T, tw, th;
    double *q[LUMIS__Q_COUNT];
    double *rgb[3];
} lumis__tiles;

lumis_status lumis__tiles_init(lumis__tiles *t, int w, int h);
void lumis__tiles_free(lumis__tiles *t);
void lumis__tiles_prefix(lumis__tiles *t);
/* Whether r's edges lie on tile edges (or the map's), so its sums come from the tiles. */
int lumis__tiles_aligned(const lumis__tiles *t, int w, int h, lumis__rect r);
/* r's tile range (r aligned). */
lumis__rect lumis__tiles_of(const lumis__tiles *t, lumis__rect r);

/* Eq. 1 and the classification (decomp_threshold.c): the map's luminance statistics and L_T
 * into info; rowsum (3 h doubles, zeroed) per row: its luminance, its emissive pixels'
 * luminance, their count; the tiles' sums over every pixel; the emissive pixels into dc
 * (em_pix, em_bits, m, their labels).  dc's env, g, desc, w, h and labels are set. */
lumis_status lumis__decomp_threshold(lumis__decomp *dc, lumis__tiles *tiles, double *rowsum,
                                     lumis_light_set_info *info);
/* Tile (tx, ty) summed again over its non-emissive pixels only. */
void lumis__decomp_dirty_tile(const lumis__tiles *t, const lumis__decomp *dc, int tx, int ty);

/* The cut: up to `budget` rectangles covering every pixel labelled -1 (the non-emissive
 * set), each holding at least one of them.  *count receives how many (fewer than budget
 * only if there are fewer such pixels).  rects holds budget entries. */
lumis_status lumis__illumination_cut(const lumis__decomp *dc, const lumis__tiles *tiles, int budget,
                                     lumis_cut_objective obj, double w_v, double w_d, double w_e,
                                     lumis__rect *rects, int *count);

#endif
