/* Which luminaire strategy pays: each strategy's variance at probe points and its cost,
 * from the luminaire's tables (docs/luminaire.md, "Which strategy pays").
 *
 * At a probe p and for image m whose box B holds energy, X = Y(radiance) max(0, n.dir) /
 * pdf_omega is the one-sample estimate of image m's share I_m of the irradiance.  Pilot
 * draws of the restricted and the uniform samplers give E[X] = I_m and E[X^2] for each.
 * The global sampler draws image m's points by its whole table: its density is the
 * restricted one times units(B) / units(image) inside B and its samples outside B carry
 * nothing, so its second moment is E_r[X^2] units(image) / units(B), exactly, with no
 * pilot of its own (which would mostly miss B).  With K_m samples of image m, a point's
 * estimate has variance sum_m (E[X^2] - I_m^2) / K_m. */
#include "internal.h"

#include "lumis/rng.h"

#include <stdlib.h>
#include <string.h>

lumis_luminaire_costs lumis_luminaire_costs_default(void)
{
    /* Measured on the 2-core AMD EPYC VM this was written on, one thread, from render
     * times of the headlight scene (car preset, 128 x 80, 4 spp) with K = 8 and 128 and
     * visibility exact and none: docs/luminaire.md, "Which strategy pays". */
    lumis_luminaire_costs c = {.camera = 300.0,
                               .image_restricted = 50.0,
                               .image_uniform = 36.0,
                               .restricted = 54.0,
                               .uniform = 35.0,
                               .global = 10.5,
                               .ray = 28.0};
    return c;
}

static double luma(lumis_rgb c)
{
    return 0.2126 * (double)c.r + 0.7152 * (double)c.g + 0.0722 * (double)c.b;
}

/* The one-sample estimate of image m from a prepared draw: Y(radiance) max(0, n.dir) /
 * pdf_omega. */
static double estimate_one(const lumis_luminaire *l, const lumis__prep *pr, lumis_vec3 p,
                           lumis_vec3 n, double u1, double u2)
{
    double x, y, pdf;
    int i, j;
    lumis__lum_draw_prepared(l, pr, u1, u2, &x, &y, &i, &j, &pdf);
    lumis_luminaire_sample s;
    const int m = pr->m;
    lumis__lum_finish_s(l, p.x, p.y, p.z, p.z / (p.z - l->delta), m, m % l->gw, m / l->gw,
                        l->rgb + (size_t)m * (size_t)l->w * (size_t)l->h * 3, x, y, i, j, pdf, 1,
                        &s);
    const double c = (double)n.x * s.dir.x + (double)n.y * s.dir.y + (double)n.z * s.dir.z;
    return c > 0.0 ? luma(s.radiance) * c * (double)s.weight : 0.0;
}

/* Moments of one probe, per strategy: its estimate's variance and samples, with energy. */
typedef struct probe_moments {
    double var[3], samples[3], rays[3]; /* restricted, uniform, global (per sample) */
    double share;                       /* global: chance a sample has energy at p */
    int images;                         /* images with energy in their box */
} probe_moments;

/* Moments at probe k; 0 if p is not lit (I(p) == 0, behind U or on S). */
static int probe_at(const lumis_luminaire *l, const lumis_luminaire_predict_desc *d,
                    const double *image_units, double power, int k, probe_moments *pm)
{
    const lumis_luminaire_probe *pr = &d->probes[k];
    if (lumis__lum_where(l, pr->p.z) != LUMIS__FRONT) return 0;
    const double nl =
        sqrt((double)pr->n.x * pr->n.x + (double)pr->n.y * pr->n.y + (double)pr->n.z * pr->n.z);
    if (!(nl > 0.0) || !isfinite(nl)) return 0;
    const lumis_vec3 n = {(float)(pr->n.x / nl), (float)(pr->n.y / nl), (float)(pr->n.z / nl)};
    double mass[LUMIS__LUM_MAX_IMAGES], mu[LUMIS__LUM_MAX_IMAGES], var[2][LUMIS__LUM_MAX_IMAGES],
        nz[2][LUMIS__LUM_MAX_IMAGES], m2r[LUMIS__LUM_MAX_IMAGES];
    int counts[LUMIS__LUM_MAX_IMAGES];
    lumis_luminaire_masses(l, pr->p, mass);
    /* The pilot.  Independent samples (strata <= 1): a jittered side x side grid, for the
     * moments.  Stratified (strata n > 1): `reps` Owen-scrambled (0,2) nets of n' points,
     * n' the largest power of two <= min(n, 16), the layout a (0,2) sequence gives a sample
     * slot over n' camera samples: the variance of their means is the stratified variance
     * (beyond 16, a power law from 1 to n' points extrapolates it, at least 1 / n). */
    const int want = d->pilot > 0 ? d->pilot : 16;
    int side = (int)sqrt((double)want + 0.5), net = 1;
    side = side < 1 ? 1 : side;
    while (d->strata > 1 && net * 2 <= d->strata && net < 16) net *= 2;
    const int reps = net > 1 ? (want / net < 2 ? 2 : want / net) : 1;
    const int pilot = net > 1 ? reps * net : side * side;
    lumis_pcg32 g;
    lumis_pcg32_seed(&g, d->seed, 2u * (uint64_t)k + 1u);
    memset(pm, 0, sizeof *pm);
    double xs[2][4096];
    for (int m = 0; m < l->m; m++) {
        mu[m] = var[0][m] = var[1][m] = nz[0][m] = nz[1][m] = m2r[m] = 0.0;
        lumis__box b;
        if (!(mass[m] > 0.0) || !lumis__lum_box(l, m, pr->p.x, pr->p.y, pr->p.z, &b)) continue;
        const double units = mass[m] / l->unit[m];
        lumis__prep prep[2];
        lumis__lum_prepare(l, m, &b, units, LUMIS_LUM_RESTRICTED, LUMIS_LUM_BINARY, 0, &prep[0]);
        lumis__lum_prepare(l, m, &b, units, LUMIS_LUM_UNIFORM, LUMIS_LUM_BINARY, 0, &prep[1]);
        pm->images++;
        uint64_t scramble = 0;
        for (int t = 0; t < pilot; t++) {
            double u[2];
            if (net > 1) {
                if (t % net == 0)
                    scramble = (uint64_t)lumis_pcg32_next(&g) << 32 | lumis_pcg32_next(&g);
                lumis_sobol02((uint32_t)(t % net), scramble, u);
            } else {
                u[0] = ((t % side) + lumis_pcg32_double(&g)) / side;
                u[1] = ((t / side) + lumis_pcg32_double(&g)) / side;
            }
            for (int st = 0; st < 2; st++)
                xs[st][t] = estimate_one(l, &prep[st], pr->p, n, u[0], u[1]);
        }
        for (int st = 0; st < 2; st++) {
            double s1 = 0.0, s2 = 0.0, r1 = 0.0, r2 = 0.0;
            for (int t = 0; t < pilot; t++) {
                s1 += xs[st][t];
                s2 += xs[st][t] * xs[st][t];
                nz[st][m] += xs[st][t] > 0.0;
            }
            const double mean = s1 / pilot, v = fmax(s2 / pilot - mean * mean, 0.0);
            var[st][m] = v;
            if (net > 1) { /* the spread of the nets' means: n' times their variance */
                for (int r = 0; r < reps; r++) {
                    double mr = 0.0;
                    for (int i = 0; i < net; i++) mr += xs[st][r * net + i];
                    mr /= net;
                    r1 += mr;
                    r2 += mr * mr;
                }
                const double vn = net * fmax(r2 - r1 * r1 / reps, 0.0) / (reps - 1);
                var[st][m] = vn;
                if (d->strata > net && v > 0.0) {
                    const double ratio = fmin(vn / v, 1.0);
                    const double gx = pow(ratio, log((double)d->strata) / log((double)net));
                    var[st][m] = v * fmax(gx, 1.0 / d->strata);
                }
            }
            nz[st][m] /= pilot;
            if (st == 0) {
                mu[m] = mean;
                m2r[m] = s2 / pilot;
            }
        }
    }
    if (!pm->images) return 0; /* no box with energy: not lit */
    /* restricted and uniform: the same balance over A_m(p) */
    lumis_luminaire_balance(mass, l->m, d->budget > 0 ? d->budget : 32, d->k_max, counts);
    for (int m = 0; m < l->m; m++) {
        if (!counts[m]) continue;
        for (int st = 0; st < 2; st++) {
            pm->var[st] += var[st][m] / counts[m];
            pm->samples[st] += counts[m];
            pm->rays[st] += counts[m] * nz[st][m];
        }
        /* global, per sample: image m drawn with chance power_m / power, its points by
         * the whole image's units; independent draws (shared by every point) */
        const double pi = l->power[m] / power, frac = mass[m] / l->unit[m] / image_units[m];
        if (!(pi > 0.0) || !(frac > 0.0)) continue;
        pm->var[2] += fmax(m2r[m] / frac - mu[m] * mu[m], 0.0) / pi;
        pm->rays[2] += pi * frac * nz[0][m];
        pm->share += pi * frac;
    }
    pm->samples[2] = 1.0;
    return 1;
}

/* Proxies of a probe's variances, for choosing probes.  Per image, a one-point estimate
 * of I_m(p): A_m(p) times the geometry at its box's centre (the support's centre on U,
 * Phi = 1).  Then out[0] = I(p)^2, which the restricted and uniform variances go as, and
 * out[1] = sum_m I_m^2 units(image) / (units(box) pi_m), which the global one goes as
 * (it grows as the box's share of the image falls).  *lit: a box holds energy. */
static void probe_proxy(const lumis_luminaire *l, const lumis_luminaire_probe *pr,
                        const double *image_units, double power, int *lit, double out[2])
{
    const lumis_vec3 p = pr->p;
    *lit = 0;
    out[0] = out[1] = 0.0;
    if (lumis__lum_where(l, p.z) != LUMIS__FRONT) return;
    const double nl =
        sqrt((double)pr->n.x * pr->n.x + (double)pr->n.y * pr->n.y + (double)pr->n.z * pr->n.z);
    if (!(nl > 0.0) || !isfinite(nl)) return;
    double mass[LUMIS__LUM_MAX_IMAGES], sum = 0.0;
    lumis_luminaire_masses(l, p, mass);
    /* between U and S the light comes from the far side of s (t < 0) */
    const double side = p.z > l->delta ? 1.0 : -1.0;
    for (int m = 0; m < l->m; m++) {
        lumis__box b;
        if (!(mass[m] > 0.0) || !lumis__lum_box(l, m, p.x, p.y, p.z, &b)) continue;
        *lit = 1;
        const double sx = l->sx0 + 0.5 * (b.x0 + b.x1) * l->dx,
                     sy = l->sy0 + 0.5 * (b.y0 + b.y1) * l->dy;
        const double wx = sx - p.x, wy = sy - p.y, wz = l->delta - p.z;
        const double r2 = wx * wx + wy * wy + wz * wz, r = sqrt(r2);
        const double cn =
            side * ((double)pr->n.x * wx + (double)pr->n.y * wy + (double)pr->n.z * wz) / (nl * r);
        if (!(cn > 0.0) || !(r > 0.0)) continue;
        double cx, cy;
        lumis__lum_center(l, m, &cx, &cy);
        const double e2 = (sx - cx) * (sx - cx) + (sy - cy) * (sy - cy) + l->delta * l->delta;
        const double im = mass[m] * e2 * e2 * l->psi_scale * cn * fabs(wz) / (r2 * r);
        const double frac = mass[m] / l->unit[m] / image_units[m], pi = l->power[m] / power;
        sum += im;
        if (frac > 0.0 && pi > 0.0) out[1] += im * im / (frac * pi);
    }
    out[0] = sum * sum;
}

static int band_of(const lumis_luminaire_predict_desc *d, int bands, lumis_vec3 p)
{
    const double r = sqrt((double)p.x * p.x + (double)p.y * p.y + (double)p.z * p.z);
    int b = 0;
    while (b + 1 < bands && r >= d->band_edges[b]) b++;
    return b;
}

/* `select` of the n lit probes (a box with energy), drawn systematically in proportion to
 * q_k = (a_k / sum a + g_k / sum g + 1 / n) / 3, a and g the proxies of I(p)^2 and of the
 * global variance (the few bright points, and the few the global strategy hardly reaches,
 * dominate the mean variances; the uniform third keeps every region's chance), each
 * weighted 1 / (select q_k).  Counts the lit probes per band: the denominators of the
 * means (Horvitz-Thompson; dividing by the weights' sum instead biased them by 1-2 %, 5-8 %
 * with an I^2 proxy alone, weights and variances being correlated).  Returns how many were drawn,
 * -1 out of memory. */
static int select_probes(const lumis_luminaire *l, const lumis_luminaire_predict_desc *d,
                         const double *image_units, double power, int bands, int *idx, double *wt,
                         double *lit_band)
{
    const int n = d->probe_count;
    double *q = malloc(sizeof *q * (size_t)n * 2);
    if (!q) return -1;
    double *g2 = q + n, sa = 0.0, sg = 0.0;
    int front = 0;
    for (int k = 0; k < n; k++) {
        int lit;
        double x[2];
        probe_proxy(l, &d->probes[k], image_units, power, &lit, x);
        q[k] = lit ? x[0] : -1.0;
        g2[k] = x[1];
        if (lit) {
            sa += x[0];
            sg += x[1];
            front++;
            lit_band[band_of(d, bands, d->probes[k].p)] += 1.0;
        }
    }
    if (!front) {
        free(q);
        return 0;
    }
    for (int k = 0; k < n; k++)
        q[k] = q[k] < 0.0 ? 0.0
                          : ((sa > 0.0 ? q[k] / sa : 1.0 / front) +
                             (sg > 0.0 ? g2[k] / sg : 1.0 / front) + 1.0 / front) /
                                3.0;
    lumis_pcg32 g;
    lumis_pcg32_seed(&g, d->seed, 0x73656c656374ull);
    const double u0 = lumis_pcg32_double(&g);
    double acc = 0.0;
    int k = 0, got = 0;
    for (int j = 0; j < d->select; j++) {
        const double t = (j + u0) / d->select;
        while (k < n - 1 && (q[k] == 0.0 || acc + q[k] <= t)) acc += q[k++];
        if (q[k] == 0.0) break;
        idx[got] = k;
        wt[got++] = 1.0 / (d->select * q[k]);
    }
    free(q);
    return got;
}

lumis_status lumis_luminaire_predict(const lumis_luminaire *l,
                                     const lumis_luminaire_predict_desc *d,
                                     lumis_luminaire_prediction *out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    out->best = LUMIS_LUM_RESTRICTED;
    if (!l || !d) return LUMIS_ERR_INVALID_ARGUMENT;
    if (!d->probes || d->probe_count < 1 || d->probe_count > (1 << 20) || d->budget < 0 ||
        d->budget > 65536 || d->k_max < 0 || d->pilot < 0 || d->pilot > 4096 || d->strata < 0 ||
        d->select < 0 || d->bands < 0 || d->bands > LUMIS_LUM_MAX_BANDS)
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "luminaire prediction: needs 1 to 2^20 probes, budget 0 to 65536, "
                           "k_max, strata and select >= 0, 0 to 4096 pilot samples and 0 to 4 "
                           "bands");
    const int bands = d->bands > 1 ? d->bands : 1;
    for (int b = 1; b + 1 < bands; b++)
        if (!(d->band_edges[b] > d->band_edges[b - 1]))
            return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "luminaire prediction: band edges must increase");
    const lumis_luminaire_costs c = d->costs ? *d->costs : lumis_luminaire_costs_default();
    if (!(c.camera >= 0.0 && c.image_restricted >= 0.0 && c.image_uniform >= 0.0 &&
          c.restricted > 0.0 && c.uniform > 0.0 && c.global > 0.0 && c.ray >= 0.0) ||
        !isfinite(c.camera + c.image_restricted + c.image_uniform + c.restricted + c.uniform +
                  c.global + c.ray))
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "luminaire prediction: costs must be finite, draws > 0, the rest >= 0");
    double image_units[LUMIS__LUM_MAX_IMAGES], power = 0.0;
    for (int m = 0; m < l->m; m++) {
        const lumis__box whole = {0.0, (double)l->w, 0.0, (double)l->h};
        image_units[m] = l->unit[m] > 0.0 ? lumis__lum_box_units(l, m, &whole) : 0.0;
        if (l->unit[m] > 0.0) power += l->power[m];
    }
    if (!(power > 0.0)) return LUMIS_OK;
    /* which probes, and their weights: every one (1), or `select` of them by a proxy */
    const int sel = d->select > 0 && d->select < d->probe_count;
    int n_eval = d->probe_count;
    int *idx = sel ? malloc(sizeof *idx * (size_t)d->select) : NULL;
    double *wt = sel ? malloc(sizeof *wt * (size_t)d->select) : NULL;
    double *dist = malloc(sizeof *dist * (size_t)d->probe_count);
    double known[LUMIS_LUM_MAX_BANDS] = {0};
    if (sel && idx && wt && dist)
        n_eval = select_probes(l, d, image_units, power, bands, idx, wt, known);
    if (!dist || (sel && (!idx || !wt || n_eval < 0))) {
        free(idx);
        free(wt);
        free(dist);
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY,
                           "luminaire prediction: out of memory");
    }
    /* weighted sums over the lit probes: variance, samples, rays, ns, per strategy */
    double rv[3] = {0}, ns[3] = {0}, smp[3] = {0}, ray[3] = {0}, share = 0.0, images = 0.0;
    double litw = 0.0, bandw[LUMIS_LUM_MAX_BANDS] = {0};
    int lit = 0;
    out->bands = bands;
    for (int e = 0; e < n_eval; e++) {
        const int k = sel ? idx[e] : e;
        const double w = sel ? wt[e] : 1.0;
        probe_moments pm;
        if (!probe_at(l, d, image_units, power, k, &pm)) continue;
        lit++;
        litw += w;
        const int b = band_of(d, bands, d->probes[k].p);
        const double cost[3] = {c.camera + c.image_restricted * pm.images +
                                    c.restricted * pm.samples[0] + c.ray * pm.rays[0],
                                c.camera + c.image_uniform * pm.images + c.uniform * pm.samples[1] +
                                    c.ray * pm.rays[1],
                                c.global + c.ray * pm.rays[2]};
        lumis_luminaire_band *bd = &out->band[b];
        bd->probes_lit++;
        bandw[b] += w;
        for (int st = 0; st < 3; st++) {
            bd->variance[st] += w * pm.var[st];
            bd->ns[st] += w * cost[st];
            rv[st] += w * pm.var[st];
            smp[st] += w * pm.samples[st];
            ray[st] += w * pm.rays[st];
            ns[st] += w * cost[st];
        }
        share += w * pm.share;
        images += w * pm.images;
        const lumis_vec3 p = d->probes[k].p;
        dist[lit - 1] = sqrt((double)p.x * p.x + (double)p.y * p.y + (double)p.z * p.z);
    }
    if (lit) {
        qsort(dist, (size_t)lit, sizeof *dist, lumis__cmp_double);
        out->distance[0] = dist[0];
        out->distance[1] = dist[lit / 2];
        out->distance[2] = dist[lit - 1];
    }
    free(dist);
    free(idx);
    free(wt);
    if (!lit) return LUMIS_OK;
    if (sel) { /* Horvitz-Thompson: the sums over the count they estimate */
        litw = 0.0;
        for (int b = 0; b < bands; b++) litw += bandw[b] = known[b];
        if (!(litw > 0.0)) return LUMIS_OK;
    }
    for (int b = 0; b < bands; b++) {
        out->band[b].share = bandw[b] / litw;
        for (int st = 0; st < 3 && bandw[b] > 0.0; st++) {
            out->band[b].variance[st] /= bandw[b];
            out->band[b].ns[st] /= bandw[b];
        }
    }
    lumis_luminaire_strategy_prediction *sp[3] = {&out->restricted, &out->uniform, &out->global};
    for (int st = 0; st < 3; st++) {
        sp[st]->samples = smp[st] / litw;
        sp[st]->rays = ray[st] / litw;
        sp[st]->variance = rv[st] / litw;
        sp[st]->ns = ns[st] / litw;
        sp[st]->work = sp[st]->variance * sp[st]->ns;
    }
    double best = HUGE_VAL;
    for (int st = 0; st < 3; st++) {
        sp[st]->time_ratio = sp[st]->work > 0.0 ? out->global.work / sp[st]->work : 0.0;
        const double sv = sp[st]->variance * sp[st]->samples;
        sp[st]->sample_ratio = sv > 0.0 ? out->global.variance / sv : 0.0;
        if (sp[st]->work > 0.0 && sp[st]->work < best) {
            best = sp[st]->work;
            out->best = st == 0   ? LUMIS_LUM_RESTRICTED
                        : st == 1 ? LUMIS_LUM_UNIFORM
                                  : LUMIS_LUM_GLOBAL;
        }
    }
    out->energy_share = share / litw;
    out->images_lit = (int)(images / litw + 0.5);
    out->probes_lit = lit;
    return LUMIS_OK;
}

lumis_status lumis_luminaire_probes(const lumis_luminaire *l, double dmin, double dmax,
                                    uint64_t seed, int n, lumis_luminaire_probe *out)
{
    if (!l || !out || n < 1 || !(dmin > 0.0) || !(dmax >= dmin) || !isfinite(dmax))
        return LUMIS_ERR_INVALID_ARGUMENT;
    double power = 0.0;
    for (int m = 0; m < l->m; m++) power += l->unit[m] > 0.0 ? l->power[m] : 0.0;
    if (!(power > 0.0)) return LUMIS_ERR_INVALID_ARGUMENT;
    lumis_pcg32 g;
    lumis_pcg32_seed(&g, seed, 0x70726f6265ull);
    lumis_luminaire_query q;
    memset(&q, 0, sizeof q);
    q.strategy = LUMIS_LUM_GLOBAL;
    q.p.z = (float)(3.0 * l->delta); /* any point in front: the global draw ignores it */
    for (int k = 0; k < n; k++) {
        /* image m in proportion to its power, u uniform on its support, s by its table */
        double t = lumis_pcg32_double(&g) * power;
        int m = 0;
        while (m < l->m - 1 && (l->unit[m] <= 0.0 || t >= l->power[m])) {
            if (l->unit[m] > 0.0) t -= l->power[m];
            m++;
        }
        double cx, cy;
        lumis__lum_center(l, m, &cx, &cy);
        const double ux = cx + (2.0 * lumis_pcg32_double(&g) - 1.0) * l->radius * l->hx,
                     uy = cy + (2.0 * lumis_pcg32_double(&g) - 1.0) * l->radius * l->hy;
        lumis_luminaire_sample s;
        const double u1 = lumis_pcg32_double(&g), u2 = lumis_pcg32_double(&g);
        double dx = 0.0, dy = 0.0;
        if (lumis_luminaire_sample_image(l, &q, m, u1, u2, &s) == LUMIS_OK) {
            dx = s.s[0] - ux;
            dy = s.s[1] - uy;
        }
        const double len = sqrt(dx * dx + dy * dy + l->delta * l->delta);
        const double dir[3] = {dx / len, dy / len, l->delta / len};
        const double r = dmin * pow(dmax / dmin, lumis_pcg32_double(&g));
        out[k].p.x = (float)(ux + r * dir[0]);
        out[k].p.y = (float)(uy + r * dir[1]);
        out[k].p.z = (float)(r * dir[2]);
        out[k].n.x = (float)-dir[0];
        out[k].n.y = (float)-dir[1];
        out[k].n.z = (float)-dir[2];
    }
    return LUMIS_OK;
}
