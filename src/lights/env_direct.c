/* EnvDirects of Wu's decomposition: importance sampling of the emissive pixels through a
 * sum tree (O(log n) per draw and per masked pixel, no CDF rebuilt per draw), masking of
 * a cap about each drawn pixel, spherical k-means on the energy centroids until no pixel
 * changes cluster (Hamerly's bounds skip most distance evaluations), and the return of
 * far pixels to the non-emissive set.  docs/lights.md. */
#include "decomp.h"

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

/* Sets leaf i to 0; ancestors are recomputed from their children, so no rounding drift
 * accumulates however many leaves are zeroed. */
static void tree_zero(sum_tree *s, int i)
{
    int k = s->P + i;
    s->t[k] = 0.0;
    for (k /= 2; k >= 1; k /= 2) s->t[k] = s->t[2 * k] + s->t[2 * k + 1];
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
 * unit direction d (labels map pixels to emissive indices).  Visits only the pixels of the
 * cap's bounding box in rows and columns. */
static void mask_cap(const lumis__decomp *dc, sum_tree *tree, const double d[3], double alpha)
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
    for (int j = j0; j < j1; j++) {
        const int32_t *lab = dc->labels + (size_t)j * (size_t)w;
        for (int k = 0; k < span; k++) {
            int i = ((i0 + k) % w + w) % w;
            int32_t e = lab[i];
            if (e < 0 || !(tree->t[tree->P + e] > 0.0)) continue;
            const double *q = dc->em_d + 3 * (size_t)e;
            if (q[0] * d[0] + q[1] * d[1] + q[2] * d[2] >= cos_a) tree_zero(tree, e);
        }
    }
}

/* ---- spherical k-means ------------------------------------------------------------------ */

static double dist3(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

/* sum w |d - c_a|^2 / 2 = sum w (1 - d . c_a) for unit vectors, without cancellation. */
static double objective(const lumis__decomp *dc, const int32_t *a, const double *c)
{
    double J = 0.0;
    for (int i = 0; i < dc->m; i++) {
        double r = dist3(dc->em_d + 3 * (size_t)i, c + 3 * (size_t)a[i]);
        J += dc->em_w[i] * 0.5 * r * r;
    }
    return J;
}

/* Nearest centre by dot product; `keep` (or -1) wins ties and anything not strictly
 * better.  Returns the best and its runner-up's distances. */
static int nearest(const double *x, const double *c, int k, int keep, double *d1, double *d2)
{
    int best = keep;
    double bd = keep >= 0 ? x[0] * c[3 * keep] + x[1] * c[3 * keep + 1] + x[2] * c[3 * keep + 2]
                          : -INFINITY;
    for (int j = 0; j < k; j++) {
        if (j == keep) continue;
        const double *q = c + 3 * (size_t)j;
        double dt = x[0] * q[0] + x[1] * q[1] + x[2] * q[2];
        if (dt > bd) {
            bd = dt;
            best = j;
        }
    }
    double second = INFINITY;
    for (int j = 0; j < k; j++)
        if (j != best) {
            double r = dist3(x, c + 3 * (size_t)j);
            if (r < second) second = r;
        }
    *d1 = dist3(x, c + 3 * (size_t)best);
    *d2 = second;
    return best;
}

static lumis_status push_objective(lumis__direct_result *r, int *cap, double J)
{
    if (r->objective_count == *cap) {
        int nc = *cap ? 2 * *cap : 16;
        double *p = realloc(r->objective, (size_t)nc * sizeof(double));
        if (!p) return LUMIS_ERR_OUT_OF_MEMORY;
        r->objective = p;
        *cap = nc;
    }
    r->objective[r->objective_count++] = J;
    return LUMIS_OK;
}

/* Safety net for floating-point cycling; the exact algorithm cannot cycle (docs). */
#define KMEANS_HARD_LIMIT 100000

static lumis_status kmeans(const lumis__decomp *dc, const lumis__direct_params *p, double *c, int k,
                           int32_t *a, lumis__direct_result *res)
{
    const int m = dc->m;
    const double slack = 1e-12; /* bounds stay bounds despite rounding */
    double *u = malloc((size_t)m * sizeof(double)), *l = malloc((size_t)m * sizeof(double));
    double *sum = malloc(3 * (size_t)k * sizeof(double)),
           *delta = malloc((size_t)k * sizeof(double));
    double *half = malloc((size_t)k * sizeof(double));
    int cap = 0;
    lumis_status st = LUMIS_OK;
    if (!u || !l || !sum || !delta || !half) st = LUMIS_ERR_OUT_OF_MEMORY;
    for (int i = 0; st == LUMIS_OK && i < m; i++)
        a[i] = nearest(dc->em_d + 3 * (size_t)i, c, k, -1, &u[i], &l[i]);
    if (st == LUMIS_OK) st = push_objective(res, &cap, objective(dc, a, c));
    res->iterations = 1;
    res->converged = !p->kmeans;
    const int limit = p->max_iterations > 0 ? p->max_iterations : KMEANS_HARD_LIMIT;
    int updates = 0;
    while (st == LUMIS_OK && p->kmeans) {
        /* Update: each centre to its cluster's normalised weighted mean direction, which
         * minimises the cluster's sum w |d - c|^2 over unit c. */
        memset(sum, 0, 3 * (size_t)k * sizeof(double));
        for (int i = 0; i < m; i++)
            for (int q = 0; q < 3; q++)
                sum[3 * a[i] + q] += dc->em_w[i] * dc->em_d[3 * (size_t)i + (size_t)q];
        double dmax = 0.0, dmax2 = 0.0;
        int imax = -1;
        for (int j = 0; j < k; j++) {
            double *s = sum + 3 * (size_t)j, len = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
            delta[j] = 0.0;
            if (!(len > 0.0)) continue; /* empty cluster: keeps its centre */
            double nc[3] = {s[0] / len, s[1] / len, s[2] / len};
            delta[j] = dist3(nc, c + 3 * (size_t)j);
            memcpy(c + 3 * (size_t)j, nc, sizeof nc);
            if (delta[j] > dmax) {
                dmax2 = dmax;
                dmax = delta[j];
                imax = j;
            } else if (delta[j] > dmax2) {
                dmax2 = delta[j];
            }
        }
        updates++;
        st = push_objective(res, &cap, objective(dc, a, c));
        if (st != LUMIS_OK || updates >= limit) break;
        /* Assignment with Hamerly's bounds: u >= |x - c_a|, l <= distance to any other. */
        for (int j = 0; j < k; j++) {
            double best = INFINITY;
            for (int q = 0; q < k; q++)
                if (q != j) {
                    double r = dist3(c + 3 * (size_t)j, c + 3 * (size_t)q);
                    if (r < best) best = r;
                }
            half[j] = 0.5 * best;
        }
        int changes = 0;
        for (int i = 0; i < m; i++) {
            u[i] += delta[a[i]] + slack;
            l[i] -= (a[i] == imax ? dmax2 : dmax) + slack;
            double bound = half[a[i]] > l[i] ? half[a[i]] : l[i];
            if (u[i] <= bound) continue;
            const double *x = dc->em_d + 3 * (size_t)i;
            u[i] = dist3(x, c + 3 * (size_t)a[i]);
            if (u[i] <= bound) continue;
            int b = nearest(x, c, k, a[i], &u[i], &l[i]);
            if (b != a[i]) {
                changes++;
                a[i] = b;
            }
        }
        res->iterations++;
        st = push_objective(res, &cap, objective(dc, a, c));
        if (changes == 0) {
            res->converged = 1;
            break;
        }
    }
    free(u);
    free(l);
    free(sum);
    free(delta);
    free(half);
    return st;
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
            if (p->mask) mask_cap(dc, &tree, dc->em_d + 3 * (size_t)e, p->mask_radius);
        }
        out->seeds = k;
        for (int j = 0; j < k; j++)
            memcpy(c + 3 * j, dc->em_d + 3 * (size_t)seeds[j], 3 * sizeof(double));
        st = kmeans(dc, p, c, k, a, out);
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
