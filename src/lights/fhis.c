/* FHIS (Ostromoukhov, Donohue & Jodoin 2004, "Fast Hierarchical Importance Sampling with
 * Blue Noise Properties"): a Penrose tiling (penrose.c) is subdivided adaptively, down to
 * the level the importance asks for; each sampling tile keeps its point where the
 * importance reaches the value of its Fibonacci-numbered F-code, and the point moves by a
 * tabulated correction vector (fhis_lut.h, from our own Lloyd relaxation: tools/fhis_lut.c)
 * that gives the set its blue-noise spacing.  Importance is the map's energy density
 * (Y Omega per pixel) times a magnitude, found by bisection so that the set has exactly K
 * points in distinct pixels.  Each light sits at its point and owns the pixels nearer to it
 * than to any other point, a Voronoi cell on the sphere, so the set conserves power.
 * docs/lights.md. */
#include "internal.h"
#include "fhis_lut.h"
#include "penrose.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Pixel centre direction (map frame). */
static void centre_dir(int w, int h, int i, int j, double d[3])
{
    double th = LUMIS_PI * (j + 0.5) / h, ph = 2.0 * LUMIS_PI * (i + 0.5) / w;
    d[0] = sin(th) * cos(ph);
    d[1] = cos(th);
    d[2] = sin(th) * sin(ph);
}

/* The prototype's uniform start: every tile down to level 6 before adaptive refinement. */
enum { FH_MIN_LEVEL = 6 };

typedef struct fh_cand {
    double t;    /* the magnitude at which this point is accepted: F-code value / e(p1) */
    double x, y; /* position in pixels, y down from the zenith */
    int32_t pixel;
} fh_cand;

typedef struct fh_ctx {
    int w, h;
    const double *e; /* w h: importance density (energy Y Omega per unit pixel area) */
    double *pyr;     /* max pyramid: level k is ceil(w / 2^k) x ceil(h / 2^k) */
    size_t off[32];
    int pw[32], ph[32], nlev;
    double m; /* magnitude: importance = m e */
    fh_cand *cand;
    size_t n, cap, tiles, budget;
    int over;    /* the tile budget ran out, or memory */
    int nomem;   /* memory ran out (an error, where the budget is not) */
    int correct; /* move points by the correction table */
} fh_ctx;

static double e_at(const fh_ctx *c, const double p[2])
{
    if (!(p[0] >= 0.0 && p[0] < c->w && p[1] >= 0.0 && p[1] < c->h)) return 0.0;
    int i = (int)p[0], j = (int)p[1];
    return c->e[(size_t)j * (size_t)c->w + (size_t)i];
}

/* Largest e over the pixels a triangle's bounding box touches (a bound: never below the
 * importance anywhere in the triangle), 0 when it misses the map. */
static double e_max(const fh_ctx *c, const double p[3][2])
{
    double x0 = fmin(p[0][0], fmin(p[1][0], p[2][0])), x1 = fmax(p[0][0], fmax(p[1][0], p[2][0]));
    double y0 = fmin(p[0][1], fmin(p[1][1], p[2][1])), y1 = fmax(p[0][1], fmax(p[1][1], p[2][1]));
    if (x1 < 0.0 || y1 < 0.0 || x0 >= c->w || y0 >= c->h) return 0.0;
    int i0 = x0 < 0.0 ? 0 : (int)x0, j0 = y0 < 0.0 ? 0 : (int)y0;
    int i1 = x1 >= c->w ? c->w - 1 : (int)x1, j1 = y1 >= c->h ? c->h - 1 : (int)y1;
    int k = 0;
    while (k + 1 < c->nlev && ((i1 >> k) - (i0 >> k) > 1 || (j1 >> k) - (j0 >> k) > 1)) k++;
    double v = 0.0;
    for (int j = j0 >> k; j <= j1 >> k; j++)
        for (int i = i0 >> k; i <= i1 >> k; i++) {
            double q = c->pyr[c->off[k] + (size_t)j * (size_t)c->pw[k] + (size_t)i];
            if (q > v) v = q;
        }
    return v;
}

static void add_cand(fh_ctx *c, double t, const double p[2])
{
    if (c->n == c->cap) {
        size_t cap = c->cap ? 2 * c->cap : 256;
        fh_cand *n = realloc(c->cand, cap * sizeof *n);
        if (!n) {
            c->over = c->nomem = 1;
            return;
        }
        c->cand = n;
        c->cap = cap;
    }
    fh_cand *q = &c->cand[c->n++];
    q->t = t;
    q->x = p[0];
    q->y = p[1];
    q->pixel = (int32_t)((size_t)(int)p[1] * (size_t)c->w + (size_t)(int)p[0]);
}

/* Adaptive subdivision and thresholding, depth first: a tile splits while its level is
 * below the level its importance asks for (at least FH_MIN_LEVEL); a sampling tile that
 * stays keeps its point when the importance reaches its F-code's value. */
static void visit(fh_ctx *c, const lumis__ptile *t)
{
    if (c->over || ++c->tiles > c->budget) {
        c->over = 1;
        return;
    }
    lumis__ptile ch[4];
    if (t->type == LUMIS__PT_A || t->type == LUMIS__PT_B) {
        const double e = e_at(c, t->p1), I = c->m * e;
        if (!(I > 0.0)) return;
        int req = lumis__penrose_level_for(I);
        if (req < FH_MIN_LEVEL) req = FH_MIN_LEVEL;
        if (t->level < req && t->level < LUMIS__PENROSE_MAX_LEVEL) {
            lumis__ptile_split(t, ch);
            visit(c, &ch[0]);
            return;
        }
        const double v = lumis__fcode_value(t->fcode, 2 * t->level);
        if (I < v) return;
        double p[2] = {t->p1[0], t->p1[1]};
        if (c->correct) {
            const float *uw = lumis__fhis_lut[lumis__penrose_importance_index(I)]
                                             [lumis__penrose_structural_index(t->fcode)];
            lumis__ptile_point(t, uw, p);
        }
        if (p[0] >= 0.0 && p[0] < c->w && p[1] >= 0.0 && p[1] < c->h) add_cand(c, v / e, p);
        return;
    }
    double p[3][2];
    lumis__ptile_vertices(t, p);
    const double I = c->m * e_max(c, p);
    if (!(I > 0.0)) return;
    int req = lumis__penrose_level_for(I);
    if (req < FH_MIN_LEVEL) req = FH_MIN_LEVEL;
    if (t->level >= req || t->level >= LUMIS__PENROSE_MAX_LEVEL) return;
    const int n = lumis__ptile_split(t, ch);
    for (int k = 0; k < n; k++) visit(c, &ch[k]);
}

static int cmp_cand(const void *a, const void *b)
{
    const fh_cand *p = a, *q = b;
    if (p->t != q->t) return p->t < q->t ? -1 : 1;
    if (p->y != q->y) return p->y < q->y ? -1 : 1;
    return (p->x > q->x) - (p->x < q->x);
}

/* The point set at magnitude m, sorted by acceptance threshold; returns the number of
 * distinct pixels among its points (`mark`: w h zeroed bytes, zeroed again on return). */
static size_t run(fh_ctx *c, double m, unsigned char *mark)
{
    c->m = m;
    c->n = 0;
    c->tiles = 0;
    c->over = 0;
    lumis__ptile root = lumis__penrose_root(c->w, c->h);
    visit(c, &root);
    if (c->n > 1) qsort(c->cand, c->n, sizeof *c->cand, cmp_cand); /* cand is NULL when empty */
    size_t distinct = 0;
    for (size_t k = 0; k < c->n; k++)
        if (!mark[c->cand[k].pixel]) {
            mark[c->cand[k].pixel] = 1;
            distinct++;
        }
    for (size_t k = 0; k < c->n; k++) mark[c->cand[k].pixel] = 0;
    return distinct;
}

/* The K points (distinct pixels; directions into dirs, pixels into pts): the Penrose
 * point set at the smallest magnitude, found by bisection, that yields K distinct pixels,
 * its K points of lowest threshold.  When no magnitude within the tile budget gets there
 * (K near the pixel count), the remaining points go to the unchosen pixels of highest
 * importance.  `mark`: w h bytes, zeroed. */
static lumis_status choose_points(const lumis__geom *g, const lumis_envmap *env, int K, int correct,
                                  int32_t *pts, double (*dirs)[3], unsigned char *mark)
{
    const int w = g->w, h = g->h;
    const size_t np = (size_t)w * (size_t)h;
    fh_ctx c;
    memset(&c, 0, sizeof c);
    c.w = w;
    c.h = h;
    c.correct = correct;
    c.budget = 16 * np + ((size_t)1 << 22);
    size_t pyr_n = 0;
    for (int k = 0; k < 32; k++) {
        c.pw[k] = (int)(((size_t)w + ((size_t)1 << k) - 1) >> k);
        c.ph[k] = (int)(((size_t)h + ((size_t)1 << k) - 1) >> k);
        c.off[k] = pyr_n;
        pyr_n += (size_t)c.pw[k] * (size_t)c.ph[k];
        c.nlev = k + 1;
        if (c.pw[k] == 1 && c.ph[k] == 1) break;
    }
    double *pyr = malloc(pyr_n * sizeof(double));
    if (!pyr) return LUMIS_ERR_OUT_OF_MEMORY;
    c.pyr = pyr;
    c.e = pyr; /* level 0 */
    double total = 0.0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const float *px = env->pixels + ((size_t)j * (size_t)w + (size_t)i) * 3;
            double e = (double)lumis__pixel_y(px, g->scale) * g->omega[j];
            pyr[(size_t)j * (size_t)w + (size_t)i] = e;
            total += e;
        }
    if (!(total > 0.0)) { /* a black map: sample solid angle */
        total = 0.0;
        for (int j = 0; j < h; j++)
            for (int i = 0; i < w; i++) {
                pyr[(size_t)j * (size_t)w + (size_t)i] = g->omega[j];
                total += g->omega[j];
            }
    }
    for (int k = 1; k < c.nlev; k++)
        for (int j = 0; j < c.ph[k]; j++)
            for (int i = 0; i < c.pw[k]; i++) {
                double v = 0.0;
                for (int dj = 0; dj < 2; dj++)
                    for (int di = 0; di < 2; di++) {
                        int x = 2 * i + di, y = 2 * j + dj;
                        if (x < c.pw[k - 1] && y < c.ph[k - 1]) {
                            double q =
                                pyr[c.off[k - 1] + (size_t)y * (size_t)c.pw[k - 1] + (size_t)x];
                            if (q > v) v = q;
                        }
                    }
                pyr[c.off[k] + (size_t)j * (size_t)c.pw[k] + (size_t)i] = v;
            }
    /* About I / area(root) points per unit area at importance I: a first guess, then
     * doubling and bisection in the magnitude. */
    lumis__ptile root = lumis__penrose_root(w, h);
    double rp[3][2];
    lumis__ptile_vertices(&root, rp);
    const double root_area = 0.5 * fabs((rp[1][0] - rp[0][0]) * (rp[2][1] - rp[0][1]) -
                                        (rp[2][0] - rp[0][0]) * (rp[1][1] - rp[0][1]));
    double lo = 0.0, hi = (double)K * root_area / total;
    size_t got = run(&c, hi, mark);
    for (int it = 0; it < 200 && got < (size_t)K && !c.over; it++) {
        lo = hi;
        hi *= 2.0;
        got = run(&c, hi, mark);
    }
    if (got >= (size_t)K) {
        if (lo == 0.0) { /* the guess was enough: find a magnitude below it that is not */
            lo = hi;
            for (int it = 0; it < 200 && lo > 0.0; it++) {
                lo *= 0.5;
                if (run(&c, lo, mark) < (size_t)K) break;
                hi = lo;
            }
        }
        for (int it = 0; it < 48 && hi - lo > 1e-12 * hi; it++) {
            double mid = 0.5 * (lo + hi);
            if (run(&c, mid, mark) >= (size_t)K)
                hi = mid;
            else
                lo = mid;
        }
        run(&c, hi, mark);
    }
    if (c.nomem) {
        free(c.cand);
        free(pyr);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    int k = 0;
    for (size_t q = 0; q < c.n && k < K; q++) {
        const fh_cand *p = &c.cand[q];
        if (mark[p->pixel]) continue;
        mark[p->pixel] = 1;
        pts[k] = p->pixel;
        double th = LUMIS_PI * p->y / h, ph = 2.0 * LUMIS_PI * p->x / w;
        dirs[k][0] = sin(th) * cos(ph);
        dirs[k][1] = cos(th);
        dirs[k][2] = sin(th) * sin(ph);
        k++;
    }
    /* Points still owed: the unchosen pixels of highest importance, at their centres. */
    while (k < K) {
        size_t best = np;
        for (size_t p = 0; p < np; p++)
            if (!mark[p] && (best == np || c.e[p] > c.e[best])) best = p;
        mark[best] = 1;
        pts[k] = (int32_t)best;
        centre_dir(w, h, (int)(best % (size_t)w), (int)(best / (size_t)w), dirs[k]);
        k++;
    }
    free(c.cand);
    free(pyr);
    return LUMIS_OK;
}

lumis_status lumis_lights_fhis(const lumis_envmap *env, const lumis_fhis_desc *desc,
                               lumis_light_set **out)
{
    static const lumis_fhis_desc zero_desc;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!desc) desc = &zero_desc;
    double t0 = lumis__now_ms();
    lumis__common c;
    lumis_status st = lumis__common_check(env, "fhis", desc->count, desc->sets, desc->jitter,
                                          desc->seed, &desc->errors, &c);
    if (st != LUMIS_OK) return st;
    lumis__geom g;
    if (lumis__geom_init(&g, env) != LUMIS_OK)
        return lumis__fail(c.errors, LUMIS_ERR_OUT_OF_MEMORY, "fhis: out of memory");
    const int K = c.count, w = g.w, h = g.h;
    lumis_light_set *set = NULL;
    int32_t *pts = malloc((size_t)K * sizeof(int32_t));
    double(*dirs)[3] = malloc((size_t)K * sizeof *dirs);
    unsigned char *mark = calloc((size_t)w * (size_t)h, 1);
    int32_t *cand = malloc((size_t)K * sizeof(int32_t));
    double *trig = malloc(2 * ((size_t)w + (size_t)h) * sizeof(double));
    st = (pts && dirs && mark && cand && trig)
             ? lumis__set_create(env, &c, K, LUMIS_LIGHTS_FHIS, 0, &set)
             : LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) {
        st = choose_points(&g, env, K, 1, pts, dirs, mark);
    }
    if (st == LUMIS_OK) {
        /* Voronoi cells by tiles: a tile's candidates are the points within the nearest
         * point's angle plus the tile's diameter of its centre. */
        const int T = 16;
        const double dth = LUMIS_PI / h, dph = 2.0 * LUMIS_PI / w;
        for (int j = 0; j < h; j++) { /* pixel centres: sin, cos of theta and of phi */
            trig[2 * j] = sin(dth * (j + 0.5));
            trig[2 * j + 1] = cos(dth * (j + 0.5));
        }
        for (int i = 0; i < w; i++) {
            trig[2 * (size_t)h + 2 * (size_t)i] = cos(dph * (i + 0.5));
            trig[2 * (size_t)h + 2 * (size_t)i + 1] = sin(dph * (i + 0.5));
        }
        for (int ty = 0; ty < h; ty += T)
            for (int tx = 0; tx < w; tx += T) {
                int y1 = ty + T < h ? ty + T : h, x1 = tx + T < w ? tx + T : w;
                double th0 = dth * ty, th1 = dth * y1;
                double smax = (th0 <= 0.5 * LUMIS_PI && th1 >= 0.5 * LUMIS_PI)
                                  ? 1.0
                                  : fmax(sin(th0), sin(th1));
                double tc[3], rad = 0.5 * (th1 - th0) + 0.5 * dph * (x1 - tx) * smax;
                double thc = 0.5 * (th0 + th1), phc = 0.5 * dph * (tx + x1);
                tc[0] = sin(thc) * cos(phc);
                tc[1] = cos(thc);
                tc[2] = sin(thc) * sin(phc);
                double dmax = -1.0;
                for (int q = 0; q < K; q++) {
                    double dt = tc[0] * dirs[q][0] + tc[1] * dirs[q][1] + tc[2] * dirs[q][2];
                    if (dt > dmax) dmax = dt;
                }
                /* within angle lim of the centre: dot >= cos(lim), loosened by a rounding
                 * margin (an extra candidate never changes a pixel's nearest point) */
                const double lim = acos(dmax > 1.0 ? 1.0 : dmax) + 2.0 * rad + 1e-9;
                const double dlim = lim >= LUMIS_PI ? -2.0 : cos(lim) - 1e-12;
                int nc = 0;
                for (int q = 0; q < K; q++) {
                    double dt = tc[0] * dirs[q][0] + tc[1] * dirs[q][1] + tc[2] * dirs[q][2];
                    if (dt >= dlim) cand[nc++] = q;
                }
                for (int j = ty; j < y1; j++)
                    for (int i = tx; i < x1; i++) {
                        const double sth = trig[2 * j], *cp = trig + 2 * (size_t)h + 2 * (size_t)i;
                        const double p[3] = {sth * cp[0], trig[2 * j + 1], sth * cp[1]};
                        int best = cand[0];
                        double bd = -2.0;
                        for (int t = 0; t < nc; t++) {
                            const double *v = dirs[cand[t]];
                            double dt = p[0] * v[0] + p[1] * v[1] + p[2] * v[2];
                            if (dt > bd) {
                                bd = dt;
                                best = cand[t];
                            }
                        }
                        set->labels[(size_t)j * (size_t)w + (size_t)i] = best;
                    }
            }
        /* A point's own pixel is its own (dot 1); make that exact whatever the rounding. */
        for (int q = 0; q < K; q++) set->labels[pts[q]] = q;
        st = lumis__lights_from_labels(set, &g, env, (const double(*)[3])dirs);
    }
    if (st == LUMIS_OK) lumis__set_finish(set, &g, env, &c, t0);
    free(pts);
    free(dirs);
    free(mark);
    free(cand);
    free(trig);
    lumis__geom_free(&g);
    if (st != LUMIS_OK) {
        lumis_light_set_destroy(set);
        return lumis__fail(c.errors, st, "fhis: %s", lumis_status_string(st));
    }
    *out = set;
    return LUMIS_OK;
}
