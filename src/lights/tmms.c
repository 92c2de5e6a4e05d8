/* TMMS-style strata (after Feng, Yang, Wan & Yu 2016, "Tone-Mapped Mean-Shift Based
 * Environment Map Sampling"), a simplified variant: the paper runs adaptive mean-shift
 * image segmentation on the tone-mapped map; here the map is cut into cells of s x s
 * pixels, the cells' mean luminances are tone mapped by Reinhard's global operator,
 * mean shift on the distribution of those values finds its modes (the levels), connected
 * cells of one level form the strata (so strata follow the shapes of light regions), and
 * an adaptive split-and-merge on energy (Y Omega) then yields exactly K strata: merge the
 * weakest stratum into its weakest neighbour while there are too many, split the
 * strongest at its energy median while there are too few, and trade a split of the
 * strongest for a merge of the weakest adjacent pair while that halves an imbalance.  One
 * light at the energy centroid of each stratum.  docs/lights.md. */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { BINS = 256 };

typedef struct tm_state {
    int cw, ch, ncell, S;
    int32_t *lab; /* stratum of every cell */
    double *ce;   /* energy of every cell */
    double *se;   /* energy of every stratum */
    int32_t *cnt; /* cells of every stratum */
    int32_t *idx; /* scratch: cell indices */
    double dth, dph;
    int s;
} tm_state;

/* The weakest neighbour stratum of stratum a (4-neighbour cells, wrapping in azimuth), or
 * -1. */
static int weakest_neighbour(const tm_state *t, int a)
{
    int best = -1;
    for (int c = 0; c < t->ncell; c++) {
        if (t->lab[c] != a) continue;
        int x = c % t->cw, y = c / t->cw;
        int nb[4] = {y * t->cw + (x + 1) % t->cw, y * t->cw + (x + t->cw - 1) % t->cw,
                     y > 0 ? c - t->cw : -1, y + 1 < t->ch ? c + t->cw : -1};
        for (int k = 0; k < 4; k++) {
            if (nb[k] < 0) continue;
            int b = t->lab[nb[k]];
            if (b == a) continue;
            if (best < 0 || t->se[b] < t->se[best] || (t->se[b] == t->se[best] && b < best))
                best = b;
        }
    }
    return best;
}

/* Merges stratum a into b, then gives the last stratum a's number. */
static void merge(tm_state *t, int a, int b)
{
    const int last = t->S - 1;
    for (int c = 0; c < t->ncell; c++)
        if (t->lab[c] == a) t->lab[c] = b;
    t->se[b] += t->se[a];
    t->cnt[b] += t->cnt[a];
    if (a != last) {
        for (int c = 0; c < t->ncell; c++)
            if (t->lab[c] == last) t->lab[c] = a;
        t->se[a] = t->se[last];
        t->cnt[a] = t->cnt[last];
    }
    t->S--;
}

/* Splits stratum a (>= 2 cells) at the energy median along its longer side. */
static void split(tm_state *t, int a)
{
    int n = 0, x0 = t->cw, x1 = -1, y0 = t->ch, y1 = -1;
    for (int c = 0; c < t->ncell; c++)
        if (t->lab[c] == a) {
            t->idx[n++] = c;
            int x = c % t->cw, y = c / t->cw;
            if (x < x0) x0 = x;
            if (x > x1) x1 = x;
            if (y < y0) y0 = y;
            if (y > y1) y1 = y;
        }
    double mid = 0.5 * (y0 + y1 + 1) * t->s * t->dth;
    double wd = (x1 - x0 + 1) * t->s * t->dph * sin(mid), ht = (y1 - y0 + 1) * t->s * t->dth;
    int by_x = wd >= ht ? 1 : 0;
    if (x1 == x0) by_x = 0;
    if (y1 == y0) by_x = 1;
    /* the cells in order of the cut axis (then the other), from the bounding box */
    n = 0;
    if (by_x) {
        for (int x = x0; x <= x1; x++)
            for (int y = y0; y <= y1; y++)
                if (t->lab[y * t->cw + x] == a) t->idx[n++] = y * t->cw + x;
    } else {
        for (int y = y0; y <= y1; y++)
            for (int x = x0; x <= x1; x++)
                if (t->lab[y * t->cw + x] == a) t->idx[n++] = y * t->cw + x;
    }
    double e = t->se[a], run = 0.0;
    int cut = n / 2;
    if (e > 0.0) {
        cut = 1;
        for (int k = 0; k < n - 1; k++) {
            run += t->ce[t->idx[k]];
            cut = k + 1;
            if (2.0 * run >= e) break;
        }
    }
    int b = t->S++;
    t->se[b] = 0.0;
    t->cnt[b] = 0;
    double ea = 0.0;
    for (int k = 0; k < n; k++) {
        int c = t->idx[k];
        if (k < cut) {
            ea += t->ce[c];
        } else {
            t->lab[c] = b;
            t->se[b] += t->ce[c];
            t->cnt[b]++;
        }
    }
    t->se[a] = ea;
    t->cnt[a] = cut;
}

/* The strongest stratum with at least two cells, or -1. */
static int strongest(const tm_state *t)
{
    int best = -1;
    for (int q = 0; q < t->S; q++)
        if (t->cnt[q] >= 2 && (best < 0 || t->se[q] > t->se[best])) best = q;
    return best;
}

static int weakest(const tm_state *t)
{
    int best = 0;
    for (int q = 1; q < t->S; q++)
        if (t->se[q] < t->se[best]) best = q;
    return best;
}

lumis_status lumis_lights_tmms(const lumis_envmap *env, const lumis_tmms_desc *desc,
                               lumis_light_set **out)
{
    static const lumis_tmms_desc zero_desc;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!desc) desc = &zero_desc;
    double t0 = lumis__now_ms();
    lumis__common c;
    lumis_status st = lumis__common_check(env, "tmms", desc->count, desc->sets, desc->jitter,
                                          desc->seed, &desc->errors, &c);
    if (st != LUMIS_OK) return st;
    if (!(desc->key >= 0.0f) || !isfinite(desc->key))
        return lumis__fail(c.errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "tmms: key must be finite and >= 0 (0 == 0.18)");
    if (!(desc->range_bandwidth >= 0.0f && desc->range_bandwidth <= 1.0f))
        return lumis__fail(c.errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "tmms: range_bandwidth must be in (0, 1] (0 == 0.1)");
    const double key = desc->key > 0.0f ? desc->key : 0.18;
    const double hr = desc->range_bandwidth > 0.0f ? desc->range_bandwidth : 0.1;
    lumis__geom g;
    if (lumis__geom_init(&g, env) != LUMIS_OK)
        return lumis__fail(c.errors, LUMIS_ERR_OUT_OF_MEMORY, "tmms: out of memory");
    const int K = c.count, w = g.w, h = g.h;
    tm_state t;
    memset(&t, 0, sizeof t);
    t.s = 16;
    while (t.s > 1 && (long long)((w + t.s - 1) / t.s) * ((h + t.s - 1) / t.s) < 4LL * K) t.s /= 2;
    t.cw = (w + t.s - 1) / t.s;
    t.ch = (h + t.s - 1) / t.s;
    t.ncell = t.cw * t.ch;
    t.dth = LUMIS_PI / h;
    t.dph = 2.0 * LUMIS_PI / w;
    const size_t nc = (size_t)t.ncell;
    t.lab = malloc(nc * sizeof(int32_t));
    t.ce = calloc(nc, sizeof(double));
    t.se = malloc(nc * sizeof(double));
    t.cnt = malloc(nc * sizeof(int32_t));
    t.idx = malloc(nc * sizeof(int32_t));
    double *com = calloc(nc, sizeof(double)); /* solid angle of every cell */
    int32_t *level = malloc(nc * sizeof(int32_t)), *queue = malloc(nc * sizeof(int32_t));
    lumis_light_set *set = NULL;
    st = (t.lab && t.ce && t.se && t.cnt && t.idx && com && level && queue)
             ? lumis__set_create(env, &c, K, LUMIS_LIGHTS_TMMS, 0, &set)
             : LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) {
        /* Cell energies and solid angles. */
        for (int j = 0; j < h; j++) {
            const float *px = env->pixels + (size_t)j * (size_t)w * 3;
            double *ce = t.ce + (size_t)(j / t.s) * (size_t)t.cw;
            double *co = com + (size_t)(j / t.s) * (size_t)t.cw;
            for (int i = 0; i < w; i++, px += 3) {
                ce[i / t.s] += (double)lumis__pixel_y(px, g.scale) * g.omega[j];
                co[i / t.s] += g.omega[j];
            }
        }
        /* Reinhard's global operator on the cells' mean luminance: Ys = key Y / Y_logavg,
         * t = Ys / (1 + Ys), Y_logavg the solid-angle-weighted log average. */
        double etot = 0.0;
        for (size_t q = 0; q < nc; q++) etot += t.ce[q];
        double delta = 1e-6 * etot / (4.0 * LUMIS_PI) + 1e-300, la = 0.0;
        for (size_t q = 0; q < nc; q++) la += com[q] * log(delta + t.ce[q] / com[q]);
        double ylog = exp(la / (4.0 * LUMIS_PI));
        double hist[BINS];
        memset(hist, 0, sizeof hist);
        for (size_t q = 0; q < nc; q++) {
            double ys = etot > 0.0 ? key * (t.ce[q] / com[q]) / ylog : 0.0;
            double tv = ys / (1.0 + ys);
            int b = (int)(tv * BINS);
            level[q] = b < 0 ? 0 : (b >= BINS ? BINS - 1 : b);
            hist[level[q]] += com[q];
        }
        /* Mean shift (flat kernel of radius hr) from every occupied bin to its mode;
         * modes closer than hr / 2 are one level. */
        int lev_of_bin[BINS], nlev = 0;
        double lev_mode[BINS];
        for (int b = 0; b < BINS; b++) {
            lev_of_bin[b] = -1;
            if (!(hist[b] > 0.0)) continue;
            double m = (b + 0.5) / BINS;
            for (int it = 0; it < 200; it++) {
                double sw = 0.0, sx = 0.0;
                for (int q = 0; q < BINS; q++) {
                    double x = (q + 0.5) / BINS;
                    if (fabs(x - m) <= hr) {
                        sw += hist[q];
                        sx += hist[q] * x;
                    }
                }
                double nm = sx / sw;
                if (fabs(nm - m) < 1e-9) break;
                m = nm;
            }
            int l = -1;
            for (int q = 0; q < nlev; q++)
                if (fabs(lev_mode[q] - m) < 0.5 * hr) l = q;
            if (l < 0) {
                l = nlev;
                lev_mode[nlev++] = m;
            }
            lev_of_bin[b] = l;
        }
        for (size_t q = 0; q < nc; q++) level[q] = lev_of_bin[level[q]];
        /* Strata: connected cells of one level (4-neighbours, wrapping in azimuth). */
        for (size_t q = 0; q < nc; q++) t.lab[q] = -1;
        t.S = 0;
        for (int q0 = 0; q0 < t.ncell; q0++) {
            if (t.lab[q0] >= 0) continue;
            int s = t.S++, head = 0, tail = 0;
            t.se[s] = 0.0;
            t.cnt[s] = 0;
            t.lab[q0] = s;
            queue[tail++] = q0;
            while (head < tail) {
                int q = queue[head++], x = q % t.cw, y = q / t.cw;
                t.se[s] += t.ce[q];
                t.cnt[s]++;
                int nb[4] = {y * t.cw + (x + 1) % t.cw, y * t.cw + (x + t.cw - 1) % t.cw,
                             y > 0 ? q - t.cw : -1, y + 1 < t.ch ? q + t.cw : -1};
                for (int k = 0; k < 4; k++)
                    if (nb[k] >= 0 && t.lab[nb[k]] < 0 && level[nb[k]] == level[q]) {
                        t.lab[nb[k]] = s;
                        queue[tail++] = nb[k];
                    }
            }
        }
        /* Adaptive split and merge to exactly K strata. */
        while (t.S > K) {
            int a = weakest(&t), b = weakest_neighbour(&t, a);
            if (b < 0) break; /* cannot happen: the cell grid is connected */
            merge(&t, a, b);
        }
        while (t.S < K) {
            int a = strongest(&t);
            if (a < 0) break; /* cannot happen: cells >= K */
            split(&t, a);
        }
        for (int round = 0; round < K && t.S >= 3; round++) {
            int big = strongest(&t), a = weakest(&t), b = weakest_neighbour(&t, a);
            if (big < 0 || b < 0 || big == a || big == b) break;
            if (!(t.se[big] > 2.0 * (t.se[a] + t.se[b]))) break;
            int last = t.S - 1;
            merge(&t, a, b);
            if (big == last && a != last) big = a; /* merge renumbered the last stratum */
            split(&t, big);
        }
        if (t.S != K) st = LUMIS_ERR_INVALID_ARGUMENT; /* unreachable for K <= pixels */
    }
    if (st == LUMIS_OK) {
        for (int j = 0; j < h; j++) {
            int32_t *lab = set->labels + (size_t)j * (size_t)w;
            const int32_t *cl = t.lab + (size_t)(j / t.s) * (size_t)t.cw;
            for (int i = 0; i < w; i++) lab[i] = cl[i / t.s];
        }
        st = lumis__lights_from_labels(set, &g, env, NULL);
    }
    if (st == LUMIS_OK) lumis__set_finish(set, &g, env, &c, t0);
    free(t.lab);
    free(t.ce);
    free(t.se);
    free(t.cnt);
    free(t.idx);
    free(com);
    free(level);
    free(queue);
    lumis__geom_free(&g);
    if (st != LUMIS_OK) {
        lumis_light_set_destroy(set);
        return lumis__fail(c.errors, st, "tmms: %s", lumis_status_string(st));
    }
    *out = set;
    return LUMIS_OK;
}
