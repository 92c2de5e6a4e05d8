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

/* ---- spherical k-means ------------------------------------------------------------------
 *
 * Work per step is proportional to the pixels of the clusters that can change, not to
 * all emissive pixels: clusters keep member lists, their sums, objective terms and a bound
 * R_a on their members' distance to the centre are recomputed only when they change, and
 * an assignment step looks only at clusters whose centre moved or that a moved centre
 * came near (docs/lights.md, "k-means"). */

static double dist3(const double *a, const double *b)
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* An upper bound of the chord |x - c| from the computed dot product of unit vectors x and
 * c: |x - c|^2 = |x|^2 + |c|^2 - 2 x.c, the norms within 4e-16 of 1 and the dot product
 * within 4e-16; 4e-15 covers all of it with room to spare. */
static double chord_bound(double dot)
{
    return sqrt(fmax(0.0, 2.0 - 2.0 * dot) + 4e-15);
}

/* Margin of the candidate test: a centre farther than 2 R_a + KM_MARGIN from c_a is
 * farther from every member of a than c_a by at least KM_MARGIN, i.e. its squared chord
 * exceeds c_a's by >= KM_MARGIN^2 = 1e-12, and its dot product falls short of c_a's by
 * >= 5e-13, far beyond rounding: the float comparison could never pick it. */
#define KM_MARGIN 1e-6

typedef struct km_state {
    int m, k;
    const double *x, *w; /* unit directions (3 m) and weights (m) */
    double *c;           /* 3 k centres */
    int32_t *a;          /* m: cluster of each pixel */
    int32_t *head;       /* k: first member, -1 if none */
    int32_t *next, *prev;
    double *J; /* k: sum over the members of w |x - c|^2 / 2 */
    double *R; /* k: bound of the members' chord distance to the centre */
} km_state;

static void km_link(km_state *s, int i, int b)
{
    s->a[i] = b;
    s->prev[i] = -1;
    s->next[i] = s->head[b];
    if (s->head[b] >= 0) s->prev[s->head[b]] = i;
    s->head[b] = i;
}

static void km_unlink(km_state *s, int i)
{
    int b = s->a[i];
    if (s->prev[i] >= 0)
        s->next[s->prev[i]] = s->next[i];
    else
        s->head[b] = s->next[i];
    if (s->next[i] >= 0) s->prev[s->next[i]] = s->prev[i];
}

/* Objective term of cluster j; with `bound`, also R_j from its members. */
static void km_cluster_terms(km_state *s, int j, int bound)
{
    const double *cj = s->c + 3 * (size_t)j;
    double J = 0.0, mind = 2.0;
    for (int i = s->head[j]; i >= 0; i = s->next[i]) {
        const double *x = s->x + 3 * (size_t)i;
        double dx = x[0] - cj[0], dy = x[1] - cj[1], dz = x[2] - cj[2];
        J += s->w[i] * 0.5 * (dx * dx + dy * dy + dz * dz);
        if (bound) {
            double d = dot3(x, cj);
            if (d < mind) mind = d;
        }
    }
    s->J[j] = J;
    if (bound) s->R[j] = s->head[j] >= 0 ? chord_bound(mind) : 0.0;
}

static double km_objective(const km_state *s)
{
    double J = 0.0;
    for (int j = 0; j < s->k; j++) J += s->J[j];
    return J;
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
    km_state s = {m, k, dc->em_d, dc->em_w, c, a, NULL, NULL, NULL, NULL, NULL};
    s.head = malloc((size_t)k * sizeof(int32_t));
    s.next = malloc((size_t)m * sizeof(int32_t));
    s.prev = malloc((size_t)m * sizeof(int32_t));
    s.J = malloc((size_t)k * sizeof(double));
    s.R = malloc((size_t)k * sizeof(double));
    double *delta = malloc((size_t)k * sizeof(double));
    unsigned char *changed = malloc((size_t)k);
    int32_t *cand = malloc((size_t)k * sizeof(int32_t));
    int32_t *moves = malloc(2 * (size_t)m * sizeof(int32_t));
    int cap = 0;
    lumis_status st = LUMIS_OK;
    if (!s.head || !s.next || !s.prev || !s.J || !s.R || !delta || !changed || !cand || !moves)
        st = LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) {
        /* The seeds' assignment: nearest centre by dot product, the first on ties. */
        for (int j = 0; j < k; j++) s.head[j] = -1;
        for (int i = m - 1; i >= 0; i--) { /* linked in index order */
            const double *x = s.x + 3 * (size_t)i;
            int best = -1;
            double bd = -INFINITY;
            for (int j = 0; j < k; j++) {
                double dt = dot3(x, c + 3 * (size_t)j);
                if (dt > bd) {
                    bd = dt;
                    best = j;
                }
            }
            km_link(&s, i, best);
        }
        for (int j = 0; j < k; j++) {
            km_cluster_terms(&s, j, 1);
            changed[j] = 1;
        }
        st = push_objective(res, &cap, km_objective(&s));
    }
    res->iterations = 1;
    res->converged = !p->kmeans;
    const int limit = p->max_iterations > 0 ? p->max_iterations : KMEANS_HARD_LIMIT;
    int updates = 0;
    while (st == LUMIS_OK && p->kmeans) {
        /* Update: each changed cluster's centre to its normalised weighted mean direction,
         * which minimises the cluster's sum w |d - c|^2 over unit c.  An unchanged
         * cluster would get the very same centre. */
        int nmoved = 0;
        for (int j = 0; j < k; j++) {
            delta[j] = 0.0;
            if (!changed[j]) continue;
            changed[j] = 0;
            double sx = 0.0, sy = 0.0, sz = 0.0;
            for (int i = s.head[j]; i >= 0; i = s.next[i]) {
                const double *x = s.x + 3 * (size_t)i, wi = s.w[i];
                sx += wi * x[0];
                sy += wi * x[1];
                sz += wi * x[2];
            }
            double len = sqrt(sx * sx + sy * sy + sz * sz);
            if (!(len > 0.0)) continue; /* empty cluster: keeps its centre */
            double nc[3] = {sx / len, sy / len, sz / len}, *cj = c + 3 * (size_t)j;
            delta[j] = dist3(nc, cj);
            memcpy(cj, nc, sizeof nc);
            if (delta[j] > 0.0) {
                km_cluster_terms(&s, j, 1);
                nmoved++;
            }
        }
        updates++;
        st = push_objective(res, &cap, km_objective(&s));
        if (st != LUMIS_OK || updates >= limit) break;
        /* Assignment.  The last step left every pixel with its nearest centre; only a
         * centre that moved can change that.  A member x of cluster a has |x - c_a| <= R_a,
         * so a centre b with |c_a - c_b| >= 2 R_a + margin cannot be nearer to it: a
         * cluster is visited only if it moved (then every near centre is a candidate) or a
         * moved centre is near (then only the moved ones are, since the others kept their
         * order with c_a for every member). */
        int nm = 0;
        for (int ca = 0; nmoved > 0 && ca < k; ca++) {
            const double *cc = c + 3 * (size_t)ca;
            const int self = delta[ca] > 0.0;
            int nc = 0;
            for (int b = 0; b < k; b++)
                if (b != ca && (self || delta[b] > 0.0) &&
                    dist3(cc, c + 3 * (size_t)b) < 2.0 * s.R[ca] + KM_MARGIN)
                    cand[nc++] = b;
            if (nc == 0) continue;
            for (int i = s.head[ca]; i >= 0; i = s.next[i]) {
                const double *x = s.x + 3 * (size_t)i;
                int best = ca;
                double bd = dot3(x, cc);
                for (int q = 0; q < nc; q++) {
                    double dt = dot3(x, c + 3 * (size_t)cand[q]);
                    if (dt > bd) { /* the current centre wins ties */
                        bd = dt;
                        best = cand[q];
                    }
                }
                if (best != ca) {
                    moves[2 * nm] = i;
                    moves[2 * nm + 1] = best;
                    nm++;
                }
            }
        }
        for (int q = 0; q < nm; q++) {
            int i = moves[2 * q], b = moves[2 * q + 1];
            changed[a[i]] = changed[b] = 1;
            km_unlink(&s, i);
            km_link(&s, i, b);
            double r = chord_bound(dot3(s.x + 3 * (size_t)i, c + 3 * (size_t)b));
            if (r > s.R[b]) s.R[b] = r; /* the leavers' R stays a bound */
        }
        for (int j = 0; j < k; j++)
            if (changed[j]) km_cluster_terms(&s, j, 0);
        res->iterations++;
        st = push_objective(res, &cap, km_objective(&s));
        if (nm == 0) {
            res->converged = 1;
            break;
        }
    }
    free(s.head);
    free(s.next);
    free(s.prev);
    free(s.J);
    free(s.R);
    free(delta);
    free(changed);
    free(cand);
    free(moves);
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
