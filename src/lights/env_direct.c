/* EnvDirects of Wu's decomposition: importance sampling of the emissive pixels through a
 * sum tree (O(log n) per draw and per masked pixel, no CDF rebuilt per draw), masking of
 * a cap about each drawn pixel, spherical k-means (kmeans.c) on the energy centroids until no pixel
 * changes cluster (a step visits only the clusters a moved centre can reach, and lazy
 * Hamerly bounds skip most of their members), and the return of
 * far pixels to the non-emissive set.  docs/lights.md. */
#include "kmeans.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- sum tree -------------------------------------------------------------------------- */

typedef struct sum_tree {
    double *t; /* 2 P entries: t[P + i] leaf i, t[k] = t[2k] + t[2k + 1] */
    int P;
} sum_tree;

static lumis_status tree_build(sum_tree *s, const double *w, int n)
{
    int P = 1;
    while (P < n) P *= 2;
    s->P = P;
    s->t = calloc(2 * (size_t)P, sizeof(double));
    if (!s->t) return LUMIS_ERR_OUT_OF_MEMORY;
    for (int i = 0; i < n; i++) s->t[P + i] = w[i];
    for (int k = P - 1; k >= 1; k--) s->t[k] = s->t[2 * k] + s->t[2 * k + 1];
    return LUMIS_OK;
}

/* After leaves ids[0 .. n) (ascending) were set to 0: their ancestors recomputed from their
 * children, level by level, each once (ids is overwritten).  As no sum is carried from
 * before, no rounding drift accumulates however many leaves are zeroed. */
static void tree_update(sum_tree *s, int32_t *ids, int n)
{
    if (s->P == 1) return; /* the one leaf is the root */
    for (int i = 0; i < n; i++) ids[i] = (s->P + ids[i]) / 2;
    while (n > 0) {
        int u = 0;
        for (int i = 0; i < n; i++)
            if (u == 0 || ids[i] != ids[u - 1]) ids[u++] = ids[i];
        for (int i = 0; i < u; i++) s->t[ids[i]] = s->t[2 * ids[i]] + s->t[2 * ids[i] + 1];
        if (ids[0] == 1) break;
        for (int i = 0; i < u; i++) ids[i] /= 2;
        n = u;
    }
}

/* Leaf drawn with probability weight / total from u in [0, 1); the total must be > 0. */
static int tree_sample(const sum_tree *s, double u)
{
    double x = u * s->t[1];
    int k = 1;
    while (k < s->P) {
        double l = s->t[2 * k], r = s->t[2 * k + 1];
        if (l > 0.0 && (x < l || !(r > 0.0))) {
            k = 2 * k;
        } else {
            x -= l;
            k = 2 * k + 1;
        }
    }
    return k - s->P;
}

/* ---- masking ---------------------------------------------------------------------------- */

/* Zeroes the tree leaf of every emissive pixel whose centroid lies within angle alpha of
 * unit direction d (labels map emissive pixels to their indices).  Visits only the pixels
 * of the cap's bounding box in rows and columns, in scan order, so the zeroed leaves come
 * in ascending order for one tree_update (zbuf: room for every emissive pixel). */
static void mask_cap(const lumis__decomp *dc, sum_tree *tree, const double d[3], double alpha,
                     int32_t *zbuf)
{
    const int w = dc->w, h = dc->h;
    const double cos_a = cos(alpha), dth = LUMIS_PI / h, dph = 2.0 * LUMIS_PI / w;
    double th = acos(d[1] < -1.0 ? -1.0 : (d[1] > 1.0 ? 1.0 : d[1]));
    int j0 = (int)floor((th - alpha) / dth) - 1, j1 = (int)ceil((th + alpha) / dth) + 1;
    j0 = j0 < 0 ? 0 : j0;
    j1 = j1 > h ? h : j1;
    int all = th - alpha <= 0.0 || th + alpha >= LUMIS_PI, i0 = 0, span = w;
    if (!all) {
        double s = sin(alpha) / sin(th);
        double half = s >= 1.0 ? LUMIS_PI : asin(s);
        double ph = atan2(d[2], d[0]);
        if (ph < 0.0) ph += 2.0 * LUMIS_PI;
        i0 = (int)floor((ph - half) / dph) - 1;
        int i1 = (int)ceil((ph + half) / dph) + 1;
        span = i1 - i0;
        if (span >= w) {
            span = w;
            i0 = 0;
        }
    }
    i0 = ((i0 % w) + w) % w;
    /* the columns: [i0, i0 + span) modulo w, as at most two ascending ranges */
    const int wrap = i0 + span > w ? i0 + span - w : 0;
    const int ra[2][2] = {{0, wrap}, {i0, wrap ? w : i0 + span}};
    int nz = 0;
    for (int j = j0; j < j1; j++) {
        const size_t o = (size_t)j * (size_t)w;
        for (int r = 0; r < 2; r++)
            for (int i = ra[r][0]; i < ra[r][1]; i++) {
                if (!lumis__emissive(dc, o + (size_t)i)) continue;
                int32_t e = dc->labels[o + (size_t)i];
                double *leaf = &tree->t[tree->P + e];
                if (!(*leaf > 0.0)) continue;
                const double *q = dc->em_d + 3 * (size_t)e;
                if (q[0] * d[0] + q[1] * d[1] + q[2] * d[2] >= cos_a) {
                    *leaf = 0.0;
                    zbuf[nz++] = e;
                }
            }
    }
    tree_update(tree, zbuf, nz);
}

/* ---- the step --------------------------------------------------------------------------- */

lumis_status lumis__env_direct(lumis__decomp *dc, const lumis__direct_params *p,
                               lumis__direct_result *out)
{
    memset(out, 0, sizeof *out);
    const int m = dc->m;
    if (m == 0 || p->budget <= 0) {
        for (int e = 0; e < m; e++) {
            dc->em_cluster[e] = -1;
            dc->labels[dc->em_pix[e]] = -1;
        }
        out->returned = m;
        out->converged = 1;
        return LUMIS_OK;
    }
    sum_tree tree;
    if (tree_build(&tree, dc->em_e, m) != LUMIS_OK) return LUMIS_ERR_OUT_OF_MEMORY;
    int32_t *seeds = malloc((size_t)p->budget * sizeof(int32_t));
    double *c = malloc(3 * (size_t)p->budget * sizeof(double));
    int32_t *a = malloc((size_t)m * sizeof(int32_t));
    int32_t *remap = malloc((size_t)p->budget * sizeof(int32_t));
    lumis_status st = (seeds && c && a && remap) ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
    int k = 0;
    if (st == LUMIS_OK) {
        lumis_pcg32 rng;
        lumis_pcg32_seed(&rng, p->seed, 0x656e76646972ULL); /* "envdir" */
        while (k < p->budget && tree.t[1] > 0.0) {
            int e = tree_sample(&tree, lumis_pcg32_double(&rng));
            seeds[k++] = e;
            if (p->mask) /* a, not yet in use, holds the zeroed leaves */
                mask_cap(dc, &tree, dc->em_d + 3 * (size_t)e, p->mask_radius, a);
        }
        out->seeds = k;
        for (int j = 0; j < k; j++)
            memcpy(c + 3 * j, dc->em_d + 3 * (size_t)seeds[j], 3 * sizeof(double));
        st = lumis__kmeans(dc, p, c, k, a, out);
    }
    if (st == LUMIS_OK) {
        /* Pixels farther than the return radius from their centre leave the cluster; the
         * clusters left empty disappear and the others are numbered in order. */
        double cos_r = p->return_radius >= LUMIS_PI ? -2.0 : cos(p->return_radius);
        int *size = calloc((size_t)k, sizeof(int));
        if (!size) st = LUMIS_ERR_OUT_OF_MEMORY;
        for (int e = 0; st == LUMIS_OK && e < m; e++) {
            const double *x = dc->em_d + 3 * (size_t)e, *q = c + 3 * (size_t)a[e];
            if (x[0] * q[0] + x[1] * q[1] + x[2] * q[2] < cos_r) {
                a[e] = -1;
                out->returned++;
            } else {
                size[a[e]]++;
            }
        }
        int n = 0;
        for (int j = 0; st == LUMIS_OK && j < k; j++) remap[j] = size[j] ? n++ : -1;
        for (int e = 0; st == LUMIS_OK && e < m; e++) {
            dc->em_cluster[e] = a[e] >= 0 ? remap[a[e]] : -1;
            dc->labels[dc->em_pix[e]] = dc->em_cluster[e];
        }
        out->clusters = n;
        free(size);
    }
    free(tree.t);
    free(seeds);
    free(c);
    free(a);
    free(remap);
    return st;
}
