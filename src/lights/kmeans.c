/* Wu's EnvDirects: spherical k-means on the emissive pixels' energy centroids until no
 * pixel changes cluster.  kmeans.h; docs/lights.md, "k-means". */
#include "kmeans.h"

#include <stdlib.h>
#include <string.h>

/* Work per step is proportional to the pixels of the clusters that can change, not to
 * all emissive pixels: clusters keep member lists, their sums, objective terms and a bound
 * R_a on their members' distance to the centre are recomputed only when they change, and
 * an assignment step looks only at clusters whose centre moved or that a moved centre
 * came near (docs/lights.md, "k-means"). */

/* The clusters' weighted direction sums S = sum w d are kept in fixed point (int64 steps of
 * `unit`): a move subtracts a pixel's w d from one sum and adds it to another exactly, so a
 * centre depends only on its cluster's members, never on the order of the moves, and an
 * update costs O(1) per cluster instead of a pass over its members. */
typedef struct km_state {
    int k;
    km_cluster *cl;
    int32_t *pos; /* m: index of each pixel in its cluster's arrays */
    int64_t *q;   /* 3 m: each pixel's w d in steps of unit */
    int64_t *S;   /* 3 k: the sums of q over each cluster's members */
    double unit;
    double *J;  /* k: sum over the members of w |x - c|^2 / 2 */
    double *R;  /* k: bound of the members' chord distance to the centre */
    double *R0; /* k: R when last computed from the members */
    double *D;  /* k: cumulative drift of each centre */
    double *G;  /* k: cumulative largest drift of the other centres */
} km_state;

static lumis_status km_push(km_state *s, int j, int32_t i, const double v[5])
{
    km_cluster *c = &s->cl[j];
    if (c->n == c->cap) {
        int nc = c->cap ? 2 * c->cap : 16;
        int32_t *id = realloc(c->id, (size_t)nc * sizeof(int32_t));
        if (id) c->id = id;
        double *d = id ? realloc(c->x, 5 * (size_t)nc * sizeof(double)) : NULL;
        if (!d) return LUMIS_ERR_OUT_OF_MEMORY;
        /* one block of five arrays of nc entries: move the old ones to their new places */
        for (size_t f = 4; f >= 1; f--) /* field f: from f cap to f nc, last field first */
            memmove(d + f * (size_t)nc, d + f * (size_t)c->cap, (size_t)c->n * sizeof(double));
        c->x = d;
        c->y = d + nc;
        c->z = d + 2 * (size_t)nc;
        c->w = d + 3 * (size_t)nc;
        c->key = d + 4 * (size_t)nc;
        c->cap = nc;
    }
    int q = c->n++;
    c->id[q] = i;
    c->x[q] = v[0];
    c->y[q] = v[1];
    c->z[q] = v[2];
    c->w[q] = v[3];
    c->key[q] = v[4];
    s->pos[i] = q;
    for (int t = 0; t < 3; t++) s->S[3 * (size_t)j + (size_t)t] += s->q[3 * (size_t)i + (size_t)t];
    return LUMIS_OK;
}

/* Removes member q of cluster j (the last member takes its place). */
static void km_remove(km_state *s, int j, int q)
{
    km_cluster *c = &s->cl[j];
    for (int t = 0; t < 3; t++)
        s->S[3 * (size_t)j + (size_t)t] -= s->q[3 * (size_t)c->id[q] + (size_t)t];
    int last = --c->n;
    if (q == last) return;
    c->id[q] = c->id[last];
    c->x[q] = c->x[last];
    c->y[q] = c->y[last];
    c->z[q] = c->z[last];
    c->w[q] = c->w[last];
    c->key[q] = c->key[last];
    s->pos[c->id[q]] = q;
}

/* The pixels' w d in fixed point: steps of a power of two such that m times the largest
 * weight is below 2^61 steps, so no sum of up to m of them overflows. */
static void km_quantise(km_state *s, const lumis__decomp *dc)
{
    double wmax = 0.0;
    for (int i = 0; i < dc->m; i++) wmax = dc->em_w[i] > wmax ? dc->em_w[i] : wmax;
    int ew, em;
    frexp(wmax, &ew);
    frexp((double)dc->m, &em);
    const int shift = 61 - ew - em; /* w d / unit = w d 2^shift < 2^61 / m */
    s->unit = ldexp(1.0, -shift);
    const double scale = ldexp(1.0, shift); /* exact: a power of two */
    for (int i = 0; i < dc->m; i++)
        for (int t = 0; t < 3; t++)
            s->q[3 * (size_t)i + (size_t)t] =
                (int64_t)llrint(dc->em_w[i] * dc->em_d[3 * (size_t)i + (size_t)t] * scale);
}

/* R_j of cluster j from its members, and with `objective` its term J_j.  Sums run in
 * four interleaved partial sums (fixed order): a single chain of additions is latency
 * bound. */
static void km_cluster_terms(km_state *s, const double *c, int j, int objective)
{
    const km_cluster *cl = &s->cl[j];
    const double c0 = c[3 * j], c1 = c[3 * j + 1], c2 = c[3 * j + 2];
    int q = 0;
    if (objective) {
        double J[4] = {0.0, 0.0, 0.0, 0.0};
        for (; q + 4 <= cl->n; q += 4)
            for (int u = 0; u < 4; u++) {
                double dx = cl->x[q + u] - c0, dy = cl->y[q + u] - c1, dz = cl->z[q + u] - c2;
                J[u] += cl->w[q + u] * 0.5 * (dx * dx + dy * dy + dz * dz);
            }
        for (; q < cl->n; q++) {
            double dx = cl->x[q] - c0, dy = cl->y[q] - c1, dz = cl->z[q] - c2;
            J[0] += cl->w[q] * 0.5 * (dx * dx + dy * dy + dz * dz);
        }
        s->J[j] = (J[0] + J[1]) + (J[2] + J[3]);
    }
    double mn[4] = {2.0, 2.0, 2.0, 2.0};
    for (q = 0; q + 4 <= cl->n; q += 4)
        for (int u = 0; u < 4; u++) {
            double d = cl->x[q + u] * c0 + cl->y[q + u] * c1 + cl->z[q + u] * c2;
            mn[u] = d < mn[u] ? d : mn[u];
        }
    for (; q < cl->n; q++) {
        double d = cl->x[q] * c0 + cl->y[q] * c1 + cl->z[q] * c2;
        mn[0] = d < mn[0] ? d : mn[0];
    }
    const double m01 = mn[0] < mn[1] ? mn[0] : mn[1], m23 = mn[2] < mn[3] ? mn[2] : mn[3];
    const double mind = m01 < m23 ? m01 : m23;
    s->R[j] = s->R0[j] = cl->n > 0 ? chord_bound(mind) : 0.0;
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

/* R_j grows by each drift of the centre (triangle inequality) and is recomputed from the
 * members once it exceeds this factor times its last exact value: a loose R only makes an
 * assignment step look at more neighbouring centres. */
#define KM_R_SLACK 1.5

/* A centre's distance (chord) to another, for the seeds' assignment. */
/* A centre's others, nearest first: the first assignment's candidates on small K, where
 * the K x K lists cost less than grid queries (above K = 256 they cost O(K^2 log K)
 * time and 16 K^2 bytes: the grid then). */
enum { KM_LISTS_MAX_K = 256 };

typedef struct km_near {
    double d;
    int32_t j;
} km_near;

static int cmp_near(const void *pa, const void *pb)
{
    const km_near *a = pa, *b = pb;
    if (a->d != b->d) return a->d < b->d ? -1 : 1;
    return (a->j > b->j) - (a->j < b->j);
}

static int cmp_i32(const void *pa, const void *pb)
{
    const int32_t a = *(const int32_t *)pa, b = *(const int32_t *)pb;
    return (a > b) - (a < b);
}

/* A candidate centre j at dot product dt for the first assignment: the largest dot product
 * wins (the smaller index on ties) into *bd / *best, the second largest into *sec. */
static inline void km_consider(int j, double dt, double *bd, double *sec, int *best)
{
    if (dt > *bd || (dt == *bd && j < *best)) {
        *sec = *bd;
        *bd = dt;
        *best = j;
    } else if (dt > *sec) {
        *sec = dt;
    }
}

/* The state and the scratch of a run. */
typedef struct km_run {
    km_state s;
    double *delta;          /* k: each centre's drift in the last update */
    unsigned char *changed; /* k: clusters whose members changed */
    int32_t *nb;            /* k: a visited cluster's near centres */
    km_move *moves;         /* m */
    int32_t *fail;          /* m + 16 */
    double *nearest;        /* k: each centre's nearest other */
    unsigned char *visit;   /* k */
    km_near *near;          /* k (k - 1), on small K: each centre's others, nearest first */
    km_grid grid;
    int cap; /* of res->objective */
} km_run;

static lumis_status km_run_init(km_run *r, int m, int k)
{
    km_state *s = &r->s;
    memset(r, 0, sizeof *r);
    s->k = k;
    s->cl = calloc((size_t)k, sizeof *s->cl);
    s->pos = malloc((size_t)m * sizeof(int32_t));
    s->q = malloc(3 * (size_t)m * sizeof(int64_t));
    s->S = calloc(3 * (size_t)k, sizeof(int64_t));
    s->J = malloc((size_t)k * sizeof(double));
    s->R = malloc((size_t)k * sizeof(double));
    s->R0 = malloc((size_t)k * sizeof(double));
    s->D = calloc((size_t)k, sizeof(double));
    s->G = calloc((size_t)k, sizeof(double));
    r->delta = malloc((size_t)k * sizeof(double));
    r->changed = malloc((size_t)k);
    r->nb = malloc((size_t)k * sizeof(int32_t));
    r->moves = malloc((size_t)m * sizeof *r->moves);
    r->fail = calloc((size_t)m + 16, sizeof(int32_t));
    r->nearest = malloc((size_t)k * sizeof(double));
    r->visit = malloc((size_t)k);
    r->near = k <= KM_LISTS_MAX_K
                  ? malloc(((size_t)k * (size_t)(k > 1 ? k - 1 : 1)) * sizeof *r->near)
                  : NULL;
    lumis_status st = lumis__km_grid_init(&r->grid, k);
    if (!s->cl || !s->pos || !s->q || !s->S || !s->J || !s->R || !s->R0 || !s->D || !s->G ||
        !r->delta || !r->changed || !r->nb || !r->moves || !r->fail || !r->nearest || !r->visit ||
        (k <= KM_LISTS_MAX_K && !r->near))
        st = LUMIS_ERR_OUT_OF_MEMORY;
    return st;
}

static void km_run_free(km_run *r)
{
    km_state *s = &r->s;
    for (int j = 0; s->cl && j < s->k; j++) {
        free(s->cl[j].id);
        free(s->cl[j].x);
    }
    free(s->cl);
    free(s->pos);
    free(s->q);
    free(s->S);
    free(s->J);
    free(s->R);
    free(s->R0);
    free(s->D);
    free(s->G);
    free(r->delta);
    free(r->changed);
    free(r->nb);
    free(r->moves);
    free(r->fail);
    free(r->nearest);
    free(r->near);
    free(r->visit);
    lumis__km_grid_free(&r->grid);
}

/* Each centre's nearest other: with the lists (small K) their first entry, else from the
 * grid. */
static void km_nearest_others(km_run *r, const double *c, int k)
{
    lumis__km_grid_build(&r->grid, c, k);
    for (int j = 0; j < k; j++) {
        if (!r->near || k == 1) {
            r->nearest[j] = lumis__km_nearest_other(&r->grid, c, k, j);
            continue;
        }
        km_near *L = r->near + (size_t)j * (size_t)(k - 1);
        int t = 0;
        for (int b = 0; b < k; b++)
            if (b != j) L[t++] = (km_near){sqrt(sq_dist(c + 3 * (size_t)j, c + 3 * (size_t)b)), b};
        qsort(L, (size_t)(k - 1), sizeof *L, cmp_near);
        r->nearest[j] = L[0].d; /* the same minimum of the same square roots */
    }
}

/* The seeds' assignment: nearest centre by dot product, the first on ties.  Pixels come in
 * scan order, so the last pixel's centre is usually the answer: it is, with the
 * first-on-ties rule intact, when the pixel lies within half the distance from that centre
 * to every other by more than the margin; the slack is then a valid lower bound.
 * Otherwise only the centres within 2 r + margin of the last one (r the pixel's distance
 * to it) can be nearer, or tie: they are compared, nearest first, and the first one beyond
 * bounds the rest. */
static lumis_status km_first_assignment(km_run *r, const lumis__decomp *dc, const double *c, int k,
                                        int32_t *a)
{
    lumis_status st = LUMIS_OK;
    for (int i = 0, last = 0; st == LUMIS_OK && i < dc->m; i++) {
        const double *x = dc->em_d + 3 * (size_t)i;
        int best = last;
        double slack = INFINITY;
        const double dl = dot3(x, c + 3 * (size_t)last), rl = chord_bound(dl);
        /* half the distance from the last centre to its nearest other */
        const double half = k > 1 ? 0.5 * r->nearest[last] * (1.0 - 1e-15) : INFINITY;
        if (k > 1 && rl + KM_MARGIN < half) {
            slack = 2.0 * (half - rl);
        } else if (k > 1 && r->near) { /* the last one's others, nearest first */
            const km_near *L = r->near + (size_t)last * (size_t)(k - 1);
            const double reach = 2.0 * rl + KM_MARGIN;
            double bd = dl, sec = -INFINITY, rest = INFINITY;
            int t = 0;
            for (; t < k - 1 && L[t].d < reach; t++)
                km_consider(L[t].j, dot3(x, c + 3 * (size_t)L[t].j), &bd, &sec, &best);
            if (t < k - 1) rest = L[t].d * (1.0 - 1e-15) - rl;
            const double lo = chord_lower(sec);
            slack = (lo < rest ? lo : rest) - chord_bound(bd);
        } else if (k > 1) {
            /* the centres within the reach of the last one, and a bound on the others'
             * distance: the nearest found beyond the reach, or the searched radius */
            const double reach = 2.0 * rl + KM_MARGIN, searched = 1.25 * reach;
            const double *cl = c + 3 * (size_t)last;
            int n = lumis__km_grid_query(&r->grid, cl, searched, k);
            const int all = n < 0;
            if (all) n = k;
            /* squared distances: a centre nearer to x than the last one is within 2 rl of
             * it, far inside the reach, so rounding at the reach's edge only adds or drops
             * a candidate that cannot win (it may change sec: the slack stays a bound) */
            const double reach2 = reach * reach;
            double bd = dl, sec = -INFINITY, beyond2 = all ? INFINITY : searched * searched;
            for (int t = 0; t < n; t++) {
                const int j = all ? t : r->grid.cand[t];
                if (j == last) continue;
                const double d2 = sq_dist(cl, c + 3 * (size_t)j);
                if (!(d2 < reach2)) {
                    beyond2 = d2 < beyond2 ? d2 : beyond2;
                    continue;
                }
                km_consider(j, dot3(x, c + 3 * (size_t)j), &bd, &sec, &best);
            }
            const double rest = sqrt(beyond2) * (1.0 - 1e-15) - rl, lo = chord_lower(sec);
            slack = (lo < rest ? lo : rest) - chord_bound(bd);
        }
        a[i] = last = best;
        double v[5] = {x[0], x[1], x[2], dc->em_w[i], slack};
        st = km_push(&r->s, best, i, v);
    }
    return st;
}

/* Update: each changed cluster's centre to its normalised weighted mean direction S / |S|,
 * which minimises the cluster's J = sum w |d - c|^2 / 2 = sum w - c . S over unit c; J falls
 * by exactly (c_new - c_old) . S = |S| |c_new - c_old|^2 / 2.  An unchanged cluster would
 * get the very same centre.  Returns how many centres moved. */
static int km_update(km_run *r, double *c, int k)
{
    km_state *s = &r->s;
    int nmoved = 0;
    double dmax = 0.0, dmax2 = 0.0;
    int jmax = -1;
    for (int j = 0; j < k; j++) {
        r->delta[j] = 0.0;
        if (!r->changed[j]) continue;
        r->changed[j] = 0;
        const int64_t *S = s->S + 3 * (size_t)j;
        const double sx = (double)S[0] * s->unit, sy = (double)S[1] * s->unit,
                     sz = (double)S[2] * s->unit;
        double len = sqrt(sx * sx + sy * sy + sz * sz);
        if (!(len > 0.0)) {                     /* empty cluster: keeps its centre */
            if (s->cl[j].n == 0) s->J[j] = 0.0; /* not a residue of the leavers' terms */
            continue;
        }
        double nc[3] = {sx / len, sy / len, sz / len}, *cj = c + 3 * (size_t)j;
        r->delta[j] = dist3(nc, cj);
        memcpy(cj, nc, sizeof nc);
        if (r->delta[j] > 0.0) {
            const double drop = 0.5 * len * r->delta[j] * r->delta[j];
            s->J[j] = s->J[j] > drop ? s->J[j] - drop : 0.0;
            s->R[j] += r->delta[j];
            if (s->R[j] > KM_R_SLACK * s->R0[j]) km_cluster_terms(s, c, j, 0);
            s->D[j] += r->delta[j];
            if (r->delta[j] > dmax) {
                dmax2 = dmax;
                dmax = r->delta[j];
                jmax = j;
            } else if (r->delta[j] > dmax2) {
                dmax2 = r->delta[j];
            }
            nmoved++;
        }
    }
    /* Hamerly: the other centres approach a member by at most the largest drift among
     * them, which for the farthest-moving centre is the second largest */
    for (int j = 0; j < k; j++) s->G[j] += j == jmax ? dmax2 : dmax;
    return nmoved;
}

/* The clusters an assignment step visits: each moved centre's own, and those it came
 * within their reach of (found around it within the largest reach); when many moved, most
 * clusters are visited anyway: all, without marking. */
static void km_mark_visits(km_run *r, const double *c, int k, int nmoved)
{
    const km_state *s = &r->s;
    if (k <= 0) return; /* (nmoved > 0 means k > 0: for the compiler's object-size check) */
    lumis__km_grid_build(&r->grid, c, k);
    double rmax = 0.0;
    for (int j = 0; j < k; j++) rmax = s->R[j] > rmax ? s->R[j] : rmax;
    memset(r->visit, 4 * nmoved > k, (size_t)k);
    for (int b = 0; b < k && 4 * nmoved <= k; b++) {
        if (!(r->delta[b] > 0.0)) continue;
        r->visit[b] = 1;
        const double *cb = c + 3 * (size_t)b;
        int n = lumis__km_grid_query(&r->grid, cb, 2.0 * rmax + KM_MARGIN, k);
        const int all = n < 0;
        if (all) n = k;
        for (int t = 0; t < n; t++) {
            const int ca = all ? t : r->grid.cand[t];
            const double reach = 2.0 * s->R[ca] + KM_MARGIN;
            if (ca != b && sq_dist(c + 3 * (size_t)ca, cb) < reach * reach) r->visit[ca] = 1;
        }
    }
}

/* Assignment.  The last step left every pixel with its nearest centre; only a centre that
 * moved can change that.  A member x of cluster a has |x - c_a| <= R_a, so a centre b with
 * |c_a - c_b| >= 2 R_a + margin cannot be nearer to it (nor, by the margin, win the float
 * comparison): a cluster is visited only if it moved or a moved centre is near, and then
 * only its members whose lazy Hamerly bound fails are compared with the near centres.
 * Returns the number of moves listed in r->moves. */
static int km_assign(km_run *r, const double *c, int k, int avx512)
{
    km_state *s = &r->s;
    int nm = 0;
    for (int ca = 0; ca < k; ca++) {
        if (!r->visit[ca]) continue; /* neither it nor a centre within its reach moved */
        const double *cc = c + 3 * (size_t)ca;
        const double reach = 2.0 * s->R[ca] + KM_MARGIN, reach2 = reach * reach;
        /* the centres within the reach (ascending, as a full scan lists them) and the
         * nearest beyond it, or the searched radius: a bound on the rest */
        const double searched = 1.25 * reach;
        int n = lumis__km_grid_query(&r->grid, cc, searched, k);
        const int all = n < 0;
        if (all) n = k;
        int nn = 0, need = r->delta[ca] > 0.0;
        double far2 = all ? INFINITY : searched * searched;
        for (int t = 0; t < n; t++) {
            const int b = all ? t : r->grid.cand[t];
            if (b == ca) continue;
            double r2 = sq_dist(cc, c + 3 * (size_t)b);
            if (r2 < reach2) {
                r->nb[nn++] = b;
                need |= r->delta[b] > 0.0;
            } else if (r2 < far2) {
                far2 = r2;
            }
        }
        if (!need) continue;
        if (!all) qsort(r->nb, (size_t)nn, sizeof *r->nb, cmp_i32);
        /* a little under the distance to the nearest centre beyond the reach */
        const double far = sqrt(far2) * (1.0 - 1e-15);
        nm = lumis__km_visit_cluster(&s->cl[ca], c, ca, r->nb, nn, far, s->D[ca] + s->G[ca], avx512,
                                     r->fail, r->moves, nm);
    }
    return nm;
}

/* The moves made: each pixel leaves its cluster for its new one, its objective terms and
 * bounds with it. */
static lumis_status km_apply(km_run *r, const double *c, int32_t *a, int nm)
{
    km_state *s = &r->s;
    lumis_status st = LUMIS_OK;
    for (int t = 0; st == LUMIS_OK && t < nm; t++) {
        const int i = r->moves[t].i, from = a[i], to = r->moves[t].to, q = s->pos[i];
        const km_cluster *cl = &s->cl[from];
        double v[5] = {cl->x[q], cl->y[q], cl->z[q], cl->w[q],
                       r->moves[t].slack + s->D[to] + s->G[to]};
        r->changed[from] = r->changed[to] = 1;
        /* The objective terms follow the pixel. */
        s->J[from] -= v[3] * 0.5 * sq_dist(v, c + 3 * (size_t)from);
        s->J[to] += v[3] * 0.5 * sq_dist(v, c + 3 * (size_t)to);
        km_remove(s, from, q);
        a[i] = to;
        st = km_push(s, to, i, v);
        double rr = chord_bound(v[0] * c[3 * to] + v[1] * c[3 * to + 1] + v[2] * c[3 * to + 2]);
        if (rr > s->R[to]) s->R[to] = rr; /* the leavers' R stays a bound */
    }
    return st;
}

lumis_status lumis__kmeans(const lumis__decomp *dc, const lumis__direct_params *p, double *c, int k,
                           int32_t *a, lumis__direct_result *res)
{
    km_run r;
    lumis_status st = km_run_init(&r, dc->m, k);
    if (st == LUMIS_OK) {
        km_quantise(&r.s, dc);
        km_nearest_others(&r, c, k);
        st = km_first_assignment(&r, dc, c, k, a);
    }
    if (st == LUMIS_OK) {
        for (int j = 0; j < k; j++) {
            km_cluster_terms(&r.s, c, j, 1);
            r.changed[j] = 1;
        }
        st = push_objective(res, &r.cap, km_objective(&r.s));
    }
    res->iterations = 1;
    res->converged = !p->kmeans;
    const int limit = p->max_iterations > 0 ? p->max_iterations : KMEANS_HARD_LIMIT;
#ifdef KM_AVX512
    const int avx512 = lumis__simd_level() >= LUMIS__SIMD_AVX512;
#else
    const int avx512 = 0;
#endif
    for (int updates = 1; st == LUMIS_OK && p->kmeans; updates++) {
        const int nmoved = km_update(&r, c, k);
        st = push_objective(res, &r.cap, km_objective(&r.s));
        if (st != LUMIS_OK || updates >= limit) break;
        int nm = 0;
        if (nmoved > 0) {
            km_mark_visits(&r, c, k, nmoved);
            nm = km_assign(&r, c, k, avx512);
        }
        if ((st = km_apply(&r, c, a, nm)) != LUMIS_OK) break;
        res->iterations++;
        st = push_objective(res, &r.cap, km_objective(&r.s));
        if (nm == 0) {
            res->converged = 1;
            break;
        }
    }
    km_run_free(&r);
    return st;
}
