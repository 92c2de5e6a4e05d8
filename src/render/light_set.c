/* A light set as the renderer's light.  Point mode: every light of the pixel's interleaved
 * set, one shadow ray each, traced 16 at a time.  Stratified mode: the set's regions as
 * strata of the map, one direction drawn in each, combined with a BSDF sample by MIS per
 * region (docs/lights.md, "Stratified mode"), or n_r >= 1 in region r fixed before the
 * render (light_set.region_draws, allocate_draws; "Allocated draws"); or, with
 * light_set.draws = N, N draws over regions chosen per shading point (shade_selected;
 * "Selected draws"). */
#include "lumis/render.h"

#include "../core/internal.h"
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The lights of one set that light_set.kinds selects, in float arrays: the shading loop reads
 * six floats a light and nothing else. */
typedef struct light_soa {
    int count;
    float *x, *y, *z, *r, *g, *b;
} light_soa;

/* The set's lights as the shading loop reads them: one light_soa per interleaved set; in
 * stratified mode the region samplers and the regions lit (those of the kinds asked for
 * that hold light). */
typedef struct set_state {
    light_soa *soa;
    int sets;
    const lumis_region_sampler *rs;
    lumis_region_sampler *owned; /* made here when the render desc gave none */
    int *strata, nstrata;
    float *cone; /* per stratum: its light's direction and -sin(extent) (-2: never below) */
    /* selected draws: per stratum cos and sin of its light's extent and the luminance of its
     * power (the terms of its bound B_r), and per light its stratum (-1: none) */
    float *bound;
    int *stratum_of;
    int *nd; /* allocated draws: per stratum its draw count n_q >= 1; NULL: one each */
    unsigned kinds;
} set_state;

static void soa_free(light_soa *soa, int sets)
{
    for (int k = 0; soa && k < sets; k++) free(soa[k].x);
    free(soa);
}

/* The lights of every set that `kinds` selects, as float arrays (one allocation a set). */
static light_soa *soa_make(const lumis_light_set *set, unsigned kinds, int *sets_out)
{
    const int sets = lumis_light_set_sets(set);
    light_soa *soa = calloc((size_t)sets, sizeof *soa);
    if (!soa) return NULL;
    for (int s = 0; s < sets; s++) {
        const lumis_light *l = NULL;
        int count = 0;
        float *mem = NULL;
        if (lumis_light_set_get(set, s, &l, &count) != LUMIS_OK ||
            !(mem = malloc(6 * sizeof(float) * (size_t)(count > 0 ? count : 1)))) {
            soa_free(soa, sets);
            return NULL;
        }
        light_soa *a = &soa[s];
        a->x = mem;
        a->y = mem + count;
        a->z = mem + 2 * count;
        a->r = mem + 3 * count;
        a->g = mem + 4 * count;
        a->b = mem + 5 * count;
        for (int k = 0; k < count; k++) {
            if (!(kinds & (1u << l[k].kind))) continue;
            const int q = a->count++;
            a->x[q] = l[k].dir.x;
            a->y[q] = l[k].dir.y;
            a->z[q] = l[k].dir.z;
            a->r[q] = (float)l[k].power[0];
            a->g[q] = (float)l[k].power[1];
            a->b[q] = (float)l[k].power[2];
        }
    }
    *sets_out = sets;
    return soa;
}

/* Every light of the pixel's set: f cos V power, one shadow ray each.  A Lambertian surface
 * needs no BSDF evaluation per light (f = albedo / pi). */
static v3 shade(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    const lumis_render_desc *d = c->d;
    const set_state *st = c->state;
    const light_soa *ls = &st->soa[lumis_light_set_interleave_index(st->sets, v->px, v->py)];
    double *shadow_rays = v->shadow_rays;
    const shading_frame sf = shading_frame_at(h, dir);
    const v3 t = sf.t, b = sf.b, n = sf.n, o = sf.org;
    const lumis_vec3 wo = sf.wo;
    const lumis_bsdf *m = &h->prim->material;
    const int lambert = m->type == LUMIS_BSDF_LAMBERT;
    const float kr = m->diffuse.r * (float)(1.0 / LUMIS_PI),
                kg = m->diffuse.g * (float)(1.0 / LUMIS_PI),
                kb = m->diffuse.b * (float)(1.0 / LUMIS_PI);
    const float nx = (float)n.x, ny = (float)n.y, nz = (float)n.z;
    v3 L = mk(0, 0, 0);
    packet p;
    p.rays.n = p.flushed = 0;
    for (int k = 0; k < ls->count; k++) {
        const float wx = ls->x[k], wy = ls->y[k], wz = ls->z[k];
        const float cosn = wx * nx + wy * ny + wz * nz;
        if (!(cosn > 0.0f)) continue;
        float fr = kr, fg = kg, fb = kb;
        if (!lambert) {
            const v3 wi = mk(wx, wy, wz);
            lumis_rgb f = lumis_bsdf_eval(m, wo, tof(mk(dot(wi, t), dot(wi, b), cosn)));
            if (f.r == 0.0f && f.g == 0.0f && f.b == 0.0f) continue;
            fr = f.r;
            fg = f.g;
            fb = f.b;
        }
        packet_push(&p, o, mk(wx, wy, wz), INFINITY,
                    mk(fr * ls->r[k] * cosn, fg * ls->g[k] * cosn, fb * ls->b[k] * cosn));
        if (p.rays.n == PACKET) packet_flush(c->scene, d, &p, &L);
    }
    *shadow_rays += (double)(p.rays.n + p.flushed);
    packet_flush(c->scene, d, &p, &L);
    return L;
}

static const char *const mode_names[] = {"point", "stratified"};

LUMIS__ENUM_NAMES(lumis_lights_mode, LUMIS_LIGHTS_MODE_COUNT, mode_names, lumis_lights_mode_name,
                  lumis_lights_mode_from_name);

/* The BSDF sample of a vertex lit by drawing in the regions, after the light draws: their
 * last shadow rays are traced into *L first.  The sample (dimensions db) is lit by the region
 * it lands in when that region is drawn from, weighed by MIS against n_light light draws of
 * density q_R p_R: q_R from the strata's running sums cdf over total (selected draws), or
 * 1 (cdf NULL: draws in every region of the kinds, n_light = that region's n_q).  Its light is
 * weight Le w; lit 0 when it adds none (light sampling only, no sample, a region of another layer,
 * not drawn from or dark there, occluded). */
typedef struct bsdf_light {
    int lit;
    lumis_rgb weight, Le; /* the sample's f cos / pdf, and the radiance it meets */
    double w;             /* its MIS weight */
} bsdf_light;

static bsdf_light bsdf_sample_regions(const ctx *c, const lumis__vertex *v, const shading_frame *fr,
                                      const lumis_bsdf *m, uint32_t db, int n_light,
                                      const double *cdf, double total, packet *p, v3 *L)
{
    const lumis_render_desc *d = c->d;
    const set_state *st = c->state;
    bsdf_light out = {0};
    *v->shadow_rays += (double)(p->rays.n + p->flushed);
    packet_flush(c->scene, d, p, L);
    const estimator_use use = estimator_use_of(d);
    if (!use.bsdf) return out;
    double ub[3];
    seq_bsdf(v->seq, m, db, 0, 1, ub);
    const lumis_bsdf_sample bs = lumis_bsdf_sample_wi(m, fr->wo, ub[0], ub[1], ub[2]);
    if (!(bs.pdf > 0.0f)) return out;
    const v3 wi = norm(add(add(mul(fr->t, bs.wi.x), mul(fr->b, bs.wi.y)), mul(fr->n, bs.wi.z)));
    int region = -1;
    lumis_rgb Le;
    const float dens = lumis_region_sampler_lookup(st->rs, tof(wi), &region, &Le);
    /* a region of another layer (Wu's split), or one the draws leave out, adds nothing here */
    const int s = region >= 0 ? st->stratum_of[region] : -1;
    const int drawn =
        cdf ? s >= 0
            : region >= 0 && (st->kinds & (1u << lumis_region_sampler_kind(st->rs, region)));
    if (!drawn || (Le.r == 0.0f && Le.g == 0.0f && Le.b == 0.0f)) return out;
    *v->shadow_rays += 1.0;
    if (occluded(c->scene, d, fr->org, wi)) return out;
    /* q of the region it lands in: 0 below the horizon (no draw could land there) */
    const double q = !cdf ? 1.0 : total > 0.0 ? (cdf[s] - (s > 0 ? cdf[s - 1] : 0.0)) / total : 0.0;
    const double pl = q * (double)dens;
    if (!cdf && st->nd && s >= 0) n_light = st->nd[s];
    out.lit = 1;
    out.weight = bs.weight;
    out.Le = Le;
    out.w = use.mis ? mis_weight(1, bs.pdf, n_light, pl, d->power_heuristic) : 1.0;
    return out;
}

/* Stratified mode: n_q directions in every region q lit (n_q = 1, or allocated draws: the
 * counts of allocate_draws), each weighted by radiance over n_q times the region's pdf, and
 * one BSDF sample; with MIS each region is its own multi-sample estimator (n_q draws of its
 * pdf against one of the BSDF's, balance or power heuristic), so the sum over regions is the
 * direct light, unbiased.  Region q's draws are points 0 .. n_q - 1 of its dimension (two
 * numbers each, above the horizon), then three numbers for the BSDF. */
static v3 shade_stratified(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    const lumis_render_desc *d = c->d;
    const set_state *st = c->state;
    lumis__stream *seq = v->seq;
    /* a dimension per stratum (taken whether or not it is drawn, so the layout does not
     * depend on the normal), then the BSDF sample's two */
    const uint32_t d0 = seq_take_n(seq, (uint32_t)st->nstrata), db = seq_take_n(seq, 2);
    const shading_frame fr = shading_frame_at(h, dir);
    const v3 t = fr.t, b = fr.b, n = fr.n, o = fr.org;
    const lumis_vec3 wo = fr.wo;
    v3 L = mk(0, 0, 0);
    const lumis_bsdf *m = &h->prim->material;
    const estimator_use use = estimator_use_of(d);
    /* Seen from below its surface a BSDF reflects nothing, and its sampling draws nothing. */
    if (!(wo.z > 0.0f)) return L;
    /* A Lambertian surface: f and the BSDF's pdf without a call per draw (the values
     * lumis_bsdf_eval and lumis_bsdf_pdf give: albedo / pi, cos / pi). */
    const int lambert = m->type == LUMIS_BSDF_LAMBERT;
    const lumis_rgb kd = {(float)(m->diffuse.r * (1.0 / LUMIS_PI)),
                          (float)(m->diffuse.g * (1.0 / LUMIS_PI)),
                          (float)(m->diffuse.b * (1.0 / LUMIS_PI))};
    packet p;
    p.rays.n = p.flushed = 0;
    enum { CHUNK = 64 };
    int regions[CHUNK], nds[CHUNK];
    uint32_t dims[CHUNK];
    double u[2 * CHUNK];
    lumis_env_sample e[CHUNK];
    const float nx = (float)n.x, ny = (float)n.y, nz = (float)n.z;
    int q = 0, j = 0; /* the next draw: point j of stratum q's n_q */
    while (use.light && q < st->nstrata) {
        int cnt = 0;
        for (; q < st->nstrata && cnt < CHUNK; q++, j = 0) {
            /* A region whose cone lies wholly below the horizon adds exactly nothing (no
             * BSDF here transmits): no draw. */
            const float *cone = st->cone + 4 * q;
            if (cone[0] * nx + cone[1] * ny + cone[2] * nz <= cone[3]) continue;
            if (!st->nd) { /* one draw a region: the vertex's points in one batch */
                regions[cnt] = st->strata[q];
                nds[cnt] = 1;
                dims[cnt++] = d0 + (uint32_t)q;
                continue;
            }
            const int nq = st->nd[q];
            for (; j < nq && cnt < CHUNK; j++, cnt++) {
                regions[cnt] = st->strata[q];
                nds[cnt] = nq;
                seq_2d(seq, d0 + (uint32_t)q, (uint32_t)j, (uint32_t)nq, u + 2 * cnt);
            }
            if (j < nq) break; /* the chunk is full: the stratum's next draws in the next */
        }
        if (!st->nd) seq_2d_dims(seq, dims, cnt, u);
        lumis_region_sampler_sample_n(st->rs, regions, u, (size_t)cnt, e);
        for (int k = 0; k < cnt; k++) {
            const v3 wi = fromf(e[k].dir);
            const double cosn = dot(wi, n);
            if (!(cosn > 0.0)) continue;
            const lumis_vec3 wil = tof(mk(dot(wi, t), dot(wi, b), cosn));
            if (lambert && !(wil.z > 0.0f)) continue;
            const lumis_rgb f = lambert ? kd : lumis_bsdf_eval(m, wo, wil);
            if (f.r == 0.0f && f.g == 0.0f && f.b == 0.0f) continue;
            const float pb = !use.mis  ? 0.0f
                             : lambert ? (float)(wil.z / LUMIS_PI)
                                       : lumis_bsdf_pdf(m, wo, wil);
            const double w =
                use.mis ? mis_weight(nds[k], e[k].pdf, 1, pb, d->power_heuristic) : 1.0;
            const double k2 = w * cosn / ((double)nds[k] * e[k].pdf);
            packet_push(&p, o, wi, INFINITY,
                        mk(f.r * e[k].radiance.r * k2, f.g * e[k].radiance.g * k2,
                           f.b * e[k].radiance.b * k2));
            if (p.rays.n == PACKET) packet_flush(c->scene, d, &p, &L);
        }
    }
    const bsdf_light bl = bsdf_sample_regions(c, v, &fr, m, db, 1, NULL, 0.0, &p, &L);
    if (!bl.lit) return L;
    return add(L, mk(bl.weight.r * bl.Le.r * bl.w, bl.weight.g * bl.Le.g * bl.w,
                     bl.weight.b * bl.Le.b * bl.w));
}

/* cos(theta - e) for cos theta = c, e the half-angle of a cone (cos e, sin e): the largest
 * cosine between a direction at angle theta from the cone's axis and one inside the cone
 * (1 when the direction is inside). */
static inline float cone_cos_bound(float c, float ce, float se)
{
    if (c >= ce) return 1.0f;
    const float s = sqrtf(fmaxf(0.0f, 1.0f - c * c));
    return c * ce + s * se;
}

/* B_r of every stratum for a shading point of normal n, mirror direction r (world) and
 * material m, as a running sum into cdf (cdf[q] = B_0 + ... + B_q); *last gets the last
 * stratum of positive B.  Selected draws pick stratum q with probability B_q / cdf[last].
 *   B_q = Y(P_q) (max(0, n . d_q) + 0.2 cosmax_q) fmax_q,
 * 0 for a region whose cone lies wholly below the horizon (the test of shade_stratified's
 * draws: it adds exactly nothing), where d_q is the region's light (its centroid), cosmax_q
 * bounds n . w over the region's cone (floored at 1e-4: a region that straddles the
 * horizon keeps q > 0) and fmax_q approximates the BSDF's largest value there: albedo / pi
 * for Lambert (a constant: left out), and for the glossy BSDFs the diffuse part plus a GGX
 * lobe of the BSDF's roughness evaluated at the half-vector angle nearest the mirror
 * direction (half the angle between r and the cone).  The cosine at the centroid tracks
 * the region's mean cosine better than the bound alone (measured: docs/lights.md); the
 * bound's share keeps every region that can contribute above 0, so the choice of B moves
 * only the variance, never the mean (docs/lights.md, "Selected draws"). */
static int stratum_bounds(const set_state *st, const lumis_bsdf *m, v3 n, v3 r, float cos_o,
                          double *cdf)
{
    const float nx = (float)n.x, ny = (float)n.y, nz = (float)n.z;
    const float rx = (float)r.x, ry = (float)r.y, rz = (float)r.z;
    float fd = 0.0f, fs = 0.0f, a2 = 0.01f;
    if (m->type != LUMIS_BSDF_LAMBERT) {
        const float ax = m->alpha_x > 0.0f ? m->alpha_x : 0.1f,
                    ay = m->alpha_y > 0.0f ? m->alpha_y : 0.1f;
        a2 = ax * ay;
        const lumis_rgb kd = m->diffuse, ks = m->specular;
        fd = m->type == LUMIS_BSDF_GGX_CONDUCTOR || m->type == LUMIS_BSDF_GGX_GLOSSY
                 ? 0.0f /* one specular lobe, no diffuse part */
                 : (0.2126f * kd.r + 0.7152f * kd.g + 0.0722f * kd.b) * (float)(1.0 / LUMIS_PI);
        float f0 = 0.2126f * ks.r + 0.7152f * ks.g + 0.0722f * ks.b;
        if (m->type == LUMIS_BSDF_GGX_PLASTIC) f0 = 0.04f;
        /* the lobe's f = F D G / (4 cos_o cos_i) at its peak, G and cos_i left to the cosine
         * bound; cos_o floored so that grazing views stay finite */
        fs = fmaxf(f0, 0.01f) / (4.0f * fmaxf(cos_o, 0.05f) * (float)LUMIS_PI);
    }
    double acc = 0.0;
    int last = -1;
    for (int q = 0; q < st->nstrata; q++) {
        const float *cone = st->cone + 4 * q, *bd = st->bound + 3 * q;
        const float c = cone[0] * nx + cone[1] * ny + cone[2] * nz;
        if (c > cone[3]) {
            const float cb = fmaxf(c, 0.0f) + 0.2f * fmaxf(cone_cos_bound(c, bd[0], bd[1]), 1e-4f);
            float f = 1.0f;
            if (fd > 0.0f || fs > 0.0f) {
                /* the cone's nearest direction to r, and the half-vector angle to it */
                const float cr = fminf(
                    cone_cos_bound(cone[0] * rx + cone[1] * ry + cone[2] * rz, bd[0], bd[1]), 1.0f);
                const float c2 = 0.5f * (1.0f + cr), s2 = 0.5f * (1.0f - cr), den = a2 * c2 + s2;
                /* GGX's D = a2 / (pi (a2 cos^2 + sin^2)^2), the pi in fs */
                f = fd + fs * a2 / fmaxf(den * den, 1e-12f);
            }
            acc += (double)(bd[2] * cb * fmaxf(f, 1e-6f));
            last = q;
        }
        cdf[q] = acc;
    }
    return last;
}

/* Selected draws (light_set.draws = N > 0): N directions per vertex instead of one in every
 * region.  Draw i picks stratum q by inverting the cdf of B (stratum_bounds) at (i + u) / N,
 * one u for the vertex (systematic sampling: region r gets floor(N q_r) or ceil(N q_r)
 * draws, in the order of the regions, which the partitions keep spatially coherent), and
 * draws a direction in it; the N draws together have the density
 *     N p_l(w),   p_l(w) = q_R(w) p_R(w)(w),   q_r = B_r / sum B
 * (each draw is uniform over its N-th of the cdf, so their mixture is q), and the light
 * estimate is (1/N) sum_i f L cos / p_l(w_i).  MIS with the one BSDF sample, the balance
 * heuristic for N + 1 samples (Veach's multi-sample form): a light draw weighs
 * N p_l / (N p_l + p_b) and the BSDF sample p_b / (N p_l + p_b) (squares with --mis power),
 * which sum to 1 at every direction, so the sum is unbiased.  The BSDF sample's p_l needs
 * q of the region it lands in: the B of every stratum is kept until then.  Numbers: one
 * dimension for u, one for the N directions (point i of N), two for the BSDF: the layout
 * depends on N only. */
static v3 shade_selected(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    const lumis_render_desc *d = c->d;
    const set_state *st = c->state;
    lumis__stream *seq = v->seq;
    const int N = d->lighting.light_set.draws;
    const uint32_t d0 = seq_take_n(seq, 2), db = seq_take_n(seq, 2);
    const shading_frame fr = shading_frame_at(h, dir);
    const v3 t = fr.t, b = fr.b, n = fr.n, o = fr.org;
    const lumis_vec3 wo = fr.wo;
    v3 L = mk(0, 0, 0);
    const lumis_bsdf *m = &h->prim->material;
    const estimator_use use = estimator_use_of(d);
    if (!(wo.z > 0.0f)) return L;
    const int lambert = m->type == LUMIS_BSDF_LAMBERT;
    const lumis_rgb kd = {(float)(m->diffuse.r * (1.0 / LUMIS_PI)),
                          (float)(m->diffuse.g * (1.0 / LUMIS_PI)),
                          (float)(m->diffuse.b * (1.0 / LUMIS_PI))};
    /* the mirror direction of -dir about n */
    const v3 r = add(dir, mul(n, -2.0 * dot(dir, n)));
    double *cdf = v->scratch;
    const int last = stratum_bounds(st, m, n, r, wo.z, cdf);
    const double total = last >= 0 ? cdf[last] : 0.0;
    packet p;
    p.rays.n = p.flushed = 0;
    enum { CHUNK = 64 };
    int regions[CHUNK], strat[CHUNK];
    double u[2 * CHUNK];
    lumis_env_sample e[CHUNK];
    int q = 0; /* the cdf is walked once: the N points (i + u) / N increase */
    const double u0 = use.light && total > 0.0 ? seq_1d(seq, d0, 0, 1) : 0.0;
    for (int i0 = 0; use.light && total > 0.0 && i0 < N; i0 += CHUNK) {
        const int i1 = i0 + CHUNK < N ? i0 + CHUNK : N;
        for (int i = i0; i < i1; i++) {
            const double x = ((double)i + u0) / N * total;
            while (q < last && cdf[q] <= x) q++;
            strat[i - i0] = q;
            regions[i - i0] = st->strata[q];
            seq_2d(seq, d0 + 1, (uint32_t)i, (uint32_t)N, u + 2 * (i - i0));
        }
        lumis_region_sampler_sample_n(st->rs, regions, u, (size_t)(i1 - i0), e);
        for (int k = 0; k < i1 - i0; k++) {
            const v3 wi = fromf(e[k].dir);
            const double cosn = dot(wi, n);
            if (!(cosn > 0.0) || !(e[k].pdf > 0.0f)) continue;
            const lumis_vec3 wil = tof(mk(dot(wi, t), dot(wi, b), cosn));
            if (lambert && !(wil.z > 0.0f)) continue;
            const lumis_rgb f = lambert ? kd : lumis_bsdf_eval(m, wo, wil);
            if (f.r == 0.0f && f.g == 0.0f && f.b == 0.0f) continue;
            const int s = strat[k];
            const double pl = (cdf[s] - (s > 0 ? cdf[s - 1] : 0.0)) / total * e[k].pdf;
            float pb = 0.0f; /* the BSDF's pdf there (Lambert's: cos / pi) */
            if (use.mis) pb = lambert ? (float)(wil.z / LUMIS_PI) : lumis_bsdf_pdf(m, wo, wil);
            const double w = use.mis ? mis_weight(N, pl, 1, pb, d->power_heuristic) : 1.0;
            const double k2 = w * cosn / (N * pl);
            packet_push(&p, o, wi, INFINITY,
                        mk(f.r * e[k].radiance.r * k2, f.g * e[k].radiance.g * k2,
                           f.b * e[k].radiance.b * k2));
            if (p.rays.n == PACKET) packet_flush(c->scene, d, &p, &L);
        }
    }
    const bsdf_light bl = bsdf_sample_regions(c, v, &fr, m, db, N, cdf, total, &p, &L);
    if (!bl.lit) return L;
    return add(L, mk(bl.w * bl.weight.r * bl.Le.r, bl.w * bl.weight.g * bl.Le.g,
                     bl.w * bl.weight.b * bl.Le.b));
}

static v3 shade_any(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    const set_state *st = c->state;
    if (!st->rs) return shade(c, h, dir, v);
    return c->d->lighting.light_set.draws > 0 ? shade_selected(c, h, dir, v)
                                              : shade_stratified(c, h, dir, v);
}

/* Per thread: the running sums of the strata's bounds (selected draws). */
static void *thread_begin(const void *state)
{
    const set_state *st = state;
    return malloc((size_t)(st->nstrata > 0 ? st->nstrata : 1) * sizeof(double));
}

static void thread_end(void *scratch, double *light_samples)
{
    (void)light_samples;
    free(scratch);
}

/* The set and the map it was made from.  Point lights: every light summed, direct
 * illumination only.  Strata: a direction in every region by light or MIS sampling, paths. */
static void inputs(const lumis_lighting *l, unsigned *needs, unsigned *takes)
{
    *needs = LUMIS__IN_ENV | LUMIS__IN_SET;
    *takes = LUMIS__IN_SET_KINDS | LUMIS__IN_SET_MODE | LUMIS__IN_HIDE | LUMIS__IN_SUN;
    if (l->light_set.mode == LUMIS_LIGHTS_STRATIFIED)
        *takes |= LUMIS__IN_REGIONS | LUMIS__IN_EST_LIGHT | LUMIS__IN_POWER | LUMIS__IN_BOUNCES |
                  LUMIS__IN_SET_DRAWS | LUMIS__IN_SET_ALLOC;
}

static void release(void *state)
{
    set_state *st = state;
    if (st) {
        soa_free(st->soa, st->sets);
        lumis_region_sampler_destroy(st->owned);
        free(st->strata);
        free(st->cone);
        free(st->bound);
        free(st->stratum_of);
        free(st->nd);
    }
    free(st);
}

/* Allocated draws: the n draws of a vertex split over the strata before the render, n_q >= 1,
 * by Neyman allocation (the variance sum_q s_q^2 / n_q least for the total n) against a bound
 * of each region's standard deviation known from the set alone,
 *     s_q = Y(P_q) Omega_q^(1/4),
 * luminous power times the square root of the region's angular size: a region's noise is its
 * visibility's (the chance that a shadow edge crosses a region grows with its size; a sun's
 * one-pixel regions barely vary), measured per region on blender-sunrise
 * (docs/results/sun/README.md, "Where the strata's error comes from").  The draws beyond one
 * a stratum go one at a time to the stratum whose term s_q^2 / n_q falls most (greedy:
 * exact for this convex sum).  The counts change the variance only: each region's draws
 * average to its own estimate whatever n_q is. */
/* (With st->nstrata > 0: prepare asks only then.) */
static int allocate_draws(set_state *st, const lumis_light *l, int n)
{
    double *s2 = malloc((size_t)st->nstrata * sizeof *s2);
    if (!s2) return 0;
    for (int q = 0; q < st->nstrata; q++) {
        st->nd[q] = 1;
        const double s = (double)st->bound[3 * q + 2] * pow(l[st->strata[q]].solid_angle, 0.25);
        s2[q] = s * s;
    }
    for (int left = n - st->nstrata; left > 0; left--) {
        int best = 0;
        double gain = -1.0;
        for (int q = 0; q < st->nstrata; q++) {
            const double g = s2[q] / ((double)st->nd[q] * (st->nd[q] + 1));
            if (g > gain) {
                gain = g;
                best = q;
            }
        }
        st->nd[best]++;
    }
    free(s2);
    return 1;
}

static lumis_status prepare(const lumis_scene *scene, const lumis_render_desc *d, void **state)
{
    (void)scene;
    const int stratified = d->lighting.light_set.mode == LUMIS_LIGHTS_STRATIFIED;
    set_state *st = calloc(1, sizeof *st);
    *state = st;
    if (st && stratified) {
        const lumis_status rst =
            d->lighting.light_set.regions
                ? LUMIS_OK
                : lumis_region_sampler_create(lumis__light_map(d), d->lighting.light_set.set,
                                              &d->errors, &st->owned);
        if (rst != LUMIS_OK) return rst;
        st->rs = d->lighting.light_set.regions ? d->lighting.light_set.regions : st->owned;
        const lumis_light *l = NULL;
        int count = 0;
        lumis_light_set_get(d->lighting.light_set.set, 0, &l, &count);
        if (lumis_region_sampler_count(st->rs) != count)
            return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "render: the region samplers (%d regions) are not the light "
                               "set's (%d lights)",
                               lumis_region_sampler_count(st->rs), count);
        st->kinds = d->lighting.light_set.kinds ? d->lighting.light_set.kinds : ~0u;
        st->strata = malloc((size_t)(count > 0 ? count : 1) * sizeof *st->strata);
        st->cone = malloc((size_t)(count > 0 ? count : 1) * 4 * sizeof *st->cone);
        st->bound = malloc((size_t)(count > 0 ? count : 1) * 3 * sizeof *st->bound);
        st->stratum_of = malloc((size_t)(count > 0 ? count : 1) * sizeof *st->stratum_of);
        if (!st->strata || !st->cone || !st->bound || !st->stratum_of)
            return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY,
                               "render: light set: out of memory");
        for (int k = 0; k < count; k++) {
            st->stratum_of[k] = -1;
            if (!lumis__region_lit(st->rs, k, st->kinds)) continue;
            float *bd = st->bound + 3 * st->nstrata;
            bd[0] = l[k].extent < (float)LUMIS_PI ? cosf(l[k].extent) : -1.0f;
            bd[1] = l[k].extent < (float)LUMIS_PI ? sinf(l[k].extent) : 0.0f;
            double pw[3];
            lumis_region_sampler_power(st->rs, k, pw);
            /* floored: an empty region is left out, so the power of one kept is positive
             * but may round below a float's range */
            bd[2] = fmaxf((float)(0.2126 * pw[0] + 0.7152 * pw[1] + 0.0722 * pw[2]), 1e-30f);
            st->stratum_of[k] = st->nstrata;
            float *cone = st->cone + 4 * st->nstrata;
            cone[0] = l[k].dir.x;
            cone[1] = l[k].dir.y;
            cone[2] = l[k].dir.z;
            /* below the horizon when the angle to the normal is at least 90 degrees + the
             * extent: n . dir <= -sin(extent), with a margin for the float rounding */
            cone[3] = l[k].extent < 1.5f ? -sinf(l[k].extent) - 1e-4f : -2.0f;
            st->strata[st->nstrata++] = k;
        }
        /* Allocated draws: at least one in every region lit.  With no region lit (kinds
         * that select none, or only empty regions) there is nothing to draw and nothing to
         * allocate: the render goes as with region_draws 0, which draws nothing either
         * (the set adds no light; the BSDF's samples find no region drawn from). */
        const int nd = d->lighting.light_set.region_draws;
        if (nd > 0 && st->nstrata > 0) {
            if (nd < st->nstrata)
                return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                                   "render: lighting.light_set.region_draws %d: under the %d "
                                   "regions lit (each draws at least once)",
                                   nd, st->nstrata);
            st->nd = malloc((size_t)st->nstrata * sizeof *st->nd);
            if (!st->nd || !allocate_draws(st, l, nd))
                return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY,
                                   "render: light set: out of memory");
        }
    }
    /* the point lights' arrays: point mode only */
    if (!st || (!stratified &&
                !(st->soa = soa_make(
                      d->lighting.light_set.set,
                      d->lighting.light_set.kinds ? d->lighting.light_set.kinds : ~0u, &st->sets))))
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "render: light set: out of memory");
    return LUMIS_OK;
}

lumis_status lumis__light_set_selection(const lumis_render_desc *d, lumis_vec3 normal,
                                        lumis_vec3 view, const lumis_bsdf *m, double *q)
{
    if (!d || !m || !q || d->lighting.light_set.mode != LUMIS_LIGHTS_STRATIFIED)
        return LUMIS_ERR_INVALID_ARGUMENT;
    void *state = NULL;
    lumis_status st = prepare(NULL, d, &state);
    set_state *ss = state;
    double *cdf = st == LUMIS_OK ? thread_begin(ss) : NULL;
    if (st == LUMIS_OK && !cdf) st = LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) {
        const v3 n = norm(fromf(normal)), dir = norm(fromf(view));
        const v3 r = add(dir, mul(n, -2.0 * dot(dir, n)));
        const int last = stratum_bounds(ss, m, n, r, (float)-dot(dir, n), cdf);
        const double total = last >= 0 ? cdf[last] : 0.0;
        for (int k = 0; k < lumis_region_sampler_count(ss->rs); k++) {
            const int s = ss->stratum_of[k];
            q[k] = s < 0 || total <= 0.0 ? 0.0 : (cdf[s] - (s > 0 ? cdf[s - 1] : 0.0)) / total;
        }
    }
    free(cdf);
    release(state);
    return st;
}

lumis_status lumis__light_set_allocation(const lumis_render_desc *d, int *n)
{
    if (!d || !n || d->lighting.light_set.mode != LUMIS_LIGHTS_STRATIFIED)
        return LUMIS_ERR_INVALID_ARGUMENT;
    void *state = NULL;
    const lumis_status st = prepare(NULL, d, &state);
    const set_state *ss = state;
    for (int k = 0; st == LUMIS_OK && k < lumis_region_sampler_count(ss->rs); k++) {
        const int s = ss->stratum_of[k];
        n[k] = s < 0 ? 0 : ss->nd ? ss->nd[s] : 1;
    }
    release(state);
    return st;
}

const lumis__light_kind lumis__light_set_kind = {
    "a light set", inputs,       prepare,    release,   NULL, NULL,
    NULL,          thread_begin, thread_end, shade_any, NULL, NULL,
};
