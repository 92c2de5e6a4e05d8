/* The luminaire lighting's auto strategy (lumis_render_luminaire_choices): the points the
 * render will shade, found by a coarse grid of camera rays, then per luminaire the strategy
 * (and, with auto_bands, the distance bands) lumis_luminaire_predict finds fastest.  The
 * light kind that uses the choices is light_luminaire.c. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "camera.h"
#include "internal.h"
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define AUTO_COLS   96
#define AUTO_ROWS   60
#define AUTO_SELECT 240

/* The points the render will shade: the first hits of AUTO_COLS x AUTO_ROWS camera rays
 * through pixel centres, world frame (n facing the camera).  Returns how many. */
static int auto_hits(const lumis_scene *scene, const cam_frame *cf, v3 *p, v3 *n)
{
    int k = 0;
    for (int y = 0; y < AUTO_ROWS; y++)
        for (int x = 0; x < AUTO_COLS; x++) {
            hit h;
            const v3 dir = camera_dir(cf, (x + 0.5) / AUTO_COLS * 2.0 - 1.0,
                                      1.0 - (y + 0.5) / AUTO_ROWS * 2.0);
            if (!intersect(scene, cf->eye, dir, &h)) continue;
            p[k] = h.p;
            n[k++] = h.n;
        }
    return k;
}

/* auto's budget for a luminaire it gives the global strategy: the model's global costs no
 * camera ray per sample, so the draws of a camera sample must outweigh its ray some 20
 * times (K a power of two at least the lighting's). */
static int auto_global_budget(int budget, double global_ns, double camera_ns)
{
    int k = budget > 0 ? budget : 32;
    while (k < 65536 && global_ns > 0.0 && k * global_ns < 20.0 * camera_ns) k *= 2;
    return k;
}

/* Bands of equal probe counts (at least 288 probes in front of U each, at most
 * LUMIS_LUM_MAX_BANDS): their edges into pd.  dist: scratch, one per probe. */
static void auto_bands(const lumis_luminaire_probe *pr, int n, double *dist,
                       lumis_luminaire_predict_desc *pd)
{
    int m = 0;
    for (int k = 0; k < n; k++)
        if (pr[k].p.z > 0.0f)
            dist[m++] = sqrt((double)pr[k].p.x * pr[k].p.x + (double)pr[k].p.y * pr[k].p.y +
                             (double)pr[k].p.z * pr[k].p.z);
    qsort(dist, (size_t)m, sizeof *dist, lumis__cmp_double);
    int bands = m / 288 < LUMIS_LUM_MAX_BANDS ? m / 288 : LUMIS_LUM_MAX_BANDS;
    for (; bands > 1; bands--) { /* equal quantiles (a flat scene): fewer bands */
        int ok = 1;
        for (int b = 0; b + 1 < bands; b++) {
            pd->band_edges[b] = dist[(size_t)(b + 1) * (size_t)m / (size_t)bands];
            if (b > 0 && !(pd->band_edges[b] > pd->band_edges[b - 1])) ok = 0;
        }
        if (ok) break;
    }
    pd->bands = bands < 1 ? 1 : bands;
}

/* The choice from a banded prediction: every assignment of strategies to bands, each at
 * its budget per camera sample (global at auto_global_budget, its camera ray charged),
 * scored by (mean variance) x (mean ns) over the lit probes; more than one band only if
 * allowed and that beats the best single strategy by 10 %. */
static void auto_choose(const lumis_luminaire_prediction *p, int budget, const double *edges,
                        int allow_bands, double camera, lumis_luminaire_choice *c)
{
    const int k = budget > 0 ? budget : 32, kg = auto_global_budget(budget, p->global.ns, camera);
    const int nb = p->bands > 1 ? p->bands : 1;
    double v[LUMIS_LUM_MAX_BANDS][3], cost[LUMIS_LUM_MAX_BANDS][3], w[LUMIS_LUM_MAX_BANDS];
    for (int b = 0; b < nb; b++) {
        const lumis_luminaire_band *bd = &p->band[b];
        w[b] = bd->share;
        for (int st = 0; st < 2; st++) v[b][st] = bd->variance[st], cost[b][st] = bd->ns[st];
        v[b][2] = bd->variance[2] / kg;
        cost[b][2] = kg * bd->ns[2] + camera;
    }
    static const lumis_luminaire_strategy names[3] = {LUMIS_LUM_RESTRICTED, LUMIS_LUM_UNIFORM,
                                                      LUMIS_LUM_GLOBAL};
    int policies = 1;
    for (int b = 0; b < nb; b++) policies *= 3;
    double best = HUGE_VAL, single = HUGE_VAL;
    int best_pol = 0, single_pol = 0;
    for (int pol = 0; pol < policies; pol++) {
        double sv = 0.0, sc = 0.0;
        int uniform_pol = 1, x = pol;
        for (int b = 0; b < nb; b++, x /= 3) {
            sv += w[b] * v[b][x % 3];
            sc += w[b] * cost[b][x % 3];
            uniform_pol &= x % 3 == pol % 3;
        }
        const double work = sv * sc;
        if (work < best) best = work, best_pol = pol;
        if (uniform_pol && work < single) single = work, single_pol = pol;
    }
    const int pol = allow_bands && nb > 1 && best < 0.9 * single ? best_pol : single_pol;
    c->band_gain = single / best;
    /* the assignment; a band without lit probes takes its neighbour's strategy, and
     * adjacent bands of one strategy merge */
    int dig[LUMIS_LUM_MAX_BANDS], known = -1;
    for (int b = 0, x = pol; b < nb; b++, x /= 3) dig[b] = x % 3;
    for (int b = 0; b < nb; b++)
        if (w[b] > 0.0) {
            known = dig[b];
            break;
        }
    for (int b = 0; b < nb; b++) dig[b] = w[b] > 0.0 ? (known = dig[b]) : known;
    c->bands = 0;
    for (int b = 0; b < nb; b++) {
        const lumis_luminaire_strategy s = names[dig[b] < 0 ? 0 : dig[b]];
        if (c->bands > 0 && s == c->strategy[c->bands - 1]) continue;
        if (c->bands > 0) c->edge[c->bands - 1] = edges[b - 1];
        c->strategy[c->bands] = s;
        c->budget[c->bands] = s == LUMIS_LUM_GLOBAL ? kg : k;
        c->bands++;
    }
}

lumis_status lumis_render_luminaire_choices(const lumis_scene *scene, const lumis_render_desc *d,
                                            lumis_luminaire_choice *out)
{
    if (!scene || !d || !d->lighting.luminaires || !out || d->lighting.luminaires->count < 0 ||
        (d->lighting.luminaires->count > 0 && !d->lighting.luminaires->instances))
        return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis_luminaire_lighting *ll = d->lighting.luminaires;
    for (int i = 0; i < ll->count; i++) {
        memset(&out[i], 0, sizeof out[i]);
        out[i].bands = 1;
        out[i].strategy[0] =
            ll->strategy == LUMIS_LUM_STRATEGY_DEFAULT ? LUMIS_LUM_RESTRICTED : ll->strategy;
        out[i].budget[0] = ll->budget ? ll->budget : 32;
        out[i].band_gain = 1.0;
    }
    if (ll->strategy != LUMIS_LUM_AUTO || ll->count == 0) return LUMIS_OK;
    const lumis_luminaire_costs costs =
        ll->auto_costs ? *ll->auto_costs : lumis_luminaire_costs_default();
    cam_frame cf;
    lumis_status st = lumis__camera_frame(d->camera, &d->errors, &cf);
    if (st != LUMIS_OK) return st;
    static const int cells = AUTO_COLS * AUTO_ROWS;
    v3 *hp = malloc(sizeof *hp * (size_t)cells * 2);
    double *dist = malloc(sizeof *dist * (size_t)cells);
    lumis_luminaire_probe *pr = malloc(sizeof *pr * (size_t)cells);
    if (!hp || !pr || !dist) {
        free(hp);
        free(pr);
        free(dist);
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY,
                           "render: auto strategy: out of memory");
    }
    v3 *hn = hp + cells;
    const int nh = auto_hits(scene, &cf, hp, hn);
    for (int i = 0; i < ll->count && st == LUMIS_OK; i++) {
        const lumis_luminaire_instance *in = &ll->instances[i];
        double scale;
        const lumis_rigid x = lumis__instance_placement(in, &scale);
        const double inv = 1.0 / scale;
        out[i].strategy[0] = LUMIS_LUM_RESTRICTED; /* nothing in view: the paper's */
        if (!in->luminaire || nh == 0) continue;
        for (int k = 0; k < nh; k++) {
            pr[k].p = tof(mul(rot_apply_t(x.r, sub(hp[k], mk(x.t[0], x.t[1], x.t[2]))), inv));
            pr[k].n = tof(rot_apply_t(x.r, hn[k]));
        }
        lumis_luminaire_predict_desc pd = {0};
        pd.probes = pr;
        pd.probe_count = nh;
        pd.budget = ll->budget;
        pd.k_max = ll->k_max;
        pd.pilot = 16;
        pd.select = AUTO_SELECT;
        pd.costs = &costs;
        /* (0,2) sequences stratify a sample slot over the camera samples */
        const lumis_sequence q = lumis_sequence_resolve(d->sequence);
        pd.strata = q == LUMIS_SEQUENCE_PCG || q == LUMIS_SEQUENCE_HALTON ? 1
                    : d->spp > 0                                          ? d->spp
                                                                          : 16;
        pd.seed = (uint64_t)0x6175746f + (uint64_t)i;
        pd.errors = d->errors;
        auto_bands(pr, nh, dist, &pd);
        lumis_luminaire_prediction *p = &out[i].prediction;
        st = lumis_luminaire_predict(in->luminaire, &pd, p);
        if (st != LUMIS_OK || !p->probes_lit) continue;
        auto_choose(p, ll->budget, pd.band_edges, ll->auto_bands, costs.camera, &out[i]);
    }
    free(hp);
    free(pr);
    free(dist);
    return st;
}
