/* FHIS-style lights (after Ostromoukhov, Donohue & Jodoin 2004, "Fast Hierarchical
 * Importance Sampling with Blue Noise Properties"), a simplified variant: the paper
 * subdivides a Penrose tiling and thresholds its Fibonacci-numbered points against the
 * importance, then moves them by tabulated relaxation vectors.  Here the hierarchy is a
 * Hilbert curve over the map instead: K points by systematic sampling of the energy
 * (Y Omega) along the curve, which is stratified at every level of the curve's quadtree;
 * no relaxation table.  Each light sits at its point (a pixel centre) and owns the pixels
 * nearer to it than to any other point, a Voronoi cell on the sphere, so the set
 * conserves power.  docs/lights.md. */
#include "internal.h"

#include "lumis/rng.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Hilbert index d in [0, n^2) -> cell (x, y) of an n x n grid (n a power of two). */
static void hilbert_d2xy(uint32_t n, uint64_t d, uint32_t *x, uint32_t *y)
{
    uint32_t rx, ry, s, tx = 0, ty = 0;
    uint64_t t = d;
    for (s = 1; s < n; s *= 2) {
        rx = (uint32_t)(1 & (t / 2));
        ry = (uint32_t)(1 & (t ^ rx));
        if (ry == 0) {
            if (rx == 1) {
                tx = s - 1 - tx;
                ty = s - 1 - ty;
            }
            uint32_t tmp = tx;
            tx = ty;
            ty = tmp;
        }
        tx += s * rx;
        ty += s * ry;
        t /= 4;
    }
    *x = tx;
    *y = ty;
}

/* Pixel centre direction (map frame). */
static void centre_dir(int w, int h, int i, int j, double d[3])
{
    double th = LUMIS_PI * (j + 0.5) / h, ph = 2.0 * LUMIS_PI * (i + 0.5) / w;
    d[0] = sin(th) * cos(ph);
    d[1] = cos(th);
    d[2] = sin(th) * sin(ph);
}

/* Weight of pixel p along the curve: its energy, or its solid angle on a black map. */
static double weight(const lumis__geom *g, const lumis_envmap *env, int use_omega, int i, int j)
{
    if (use_omega) return g->omega[j];
    const float *px = env->pixels + ((size_t)j * (size_t)g->w + (size_t)i) * 3;
    return (double)lumis__pixel_y(px, g->scale) * g->omega[j];
}

/* The K points: pixel indices, distinct.  `mark` (w h bytes, zeroed) flags chosen pixels. */
static void choose_points(const lumis__geom *g, const lumis_envmap *env, int K, double u0,
                          int32_t *pts, unsigned char *mark)
{
    const int w = g->w, h = g->h;
    double total = 0.0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) total += weight(g, env, 0, i, j);
    const int use_omega = !(total > 0.0);
    if (use_omega) {
        total = 0.0;
        for (int j = 0; j < h; j++) total += g->omega[j] * w;
    }
    /* The map (i, j) is the cell (x = j, y = i) of an n x n grid, n >= max(2h, w): the
     * curve's first half covers x < n / 2, all of the map when w <= n and h <= n / 2. */
    uint32_t n = 1;
    while (n < (uint32_t)w || n < 2u * (uint32_t)h) n *= 2;
    const uint64_t cells = (uint64_t)n * n;
    int k = 0, pending = 0;
    double run = 0.0, step = total / K, next = u0 * step;
    for (uint64_t d = 0; d < cells && k < K; d++) {
        uint32_t x, y;
        hilbert_d2xy(n, d, &x, &y);
        if (x >= (uint32_t)h || y >= (uint32_t)w) continue;
        int i = (int)y, j = (int)x;
        size_t p = (size_t)j * (size_t)w + (size_t)i;
        run += weight(g, env, use_omega, i, j);
        while (k + pending < K && run > next) { /* thresholds this pixel crosses */
            pending++;
            next = (k + pending + u0) * step;
        }
        if (pending > 0 && !mark[p]) { /* one point per pixel; the rest move on */
            mark[p] = 1;
            pts[k++] = (int32_t)p;
            pending--;
        }
    }
    /* Points still owed (rounding at the end, or a last pixel holding several): the
     * unchosen pixels nearest the end of the map's rows. */
    for (long long p = (long long)w * h - 1; k < K && p >= 0; p--)
        if (!mark[p]) {
            mark[p] = 1;
            pts[k++] = (int32_t)p;
        }
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
    st = (pts && dirs && mark && cand) ? lumis__set_create(env, &c, K, LUMIS_LIGHTS_FHIS, 0, &set)
                                       : LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) {
        lumis_pcg32 rng;
        lumis_pcg32_seed(&rng, c.seed, 0x66686973ULL); /* "fhis" */
        choose_points(&g, env, K, lumis_pcg32_double(&rng), pts, mark);
        for (int q = 0; q < K; q++) centre_dir(w, h, pts[q] % w, pts[q] / w, dirs[q]);
        /* Voronoi cells by tiles: a tile's candidates are the points within the nearest
         * point's angle plus the tile's diameter of its centre. */
        const int T = 16;
        const double dth = LUMIS_PI / h, dph = 2.0 * LUMIS_PI / w;
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
                double amin = INFINITY;
                for (int q = 0; q < K; q++) {
                    double dt = tc[0] * dirs[q][0] + tc[1] * dirs[q][1] + tc[2] * dirs[q][2];
                    double a = acos(dt > 1.0 ? 1.0 : (dt < -1.0 ? -1.0 : dt));
                    if (a < amin) amin = a;
                }
                int nc = 0;
                double lim = amin + 2.0 * rad + 1e-9;
                for (int q = 0; q < K; q++) {
                    double dt = tc[0] * dirs[q][0] + tc[1] * dirs[q][1] + tc[2] * dirs[q][2];
                    if (acos(dt > 1.0 ? 1.0 : (dt < -1.0 ? -1.0 : dt)) <= lim) cand[nc++] = q;
                }
                for (int j = ty; j < y1; j++)
                    for (int i = tx; i < x1; i++) {
                        double p[3];
                        centre_dir(w, h, i, j, p);
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
    lumis__geom_free(&g);
    if (st != LUMIS_OK) {
        lumis_light_set_destroy(set);
        return lumis__fail(c.errors, st, "fhis: %s", lumis_status_string(st));
    }
    *out = set;
    return LUMIS_OK;
}
