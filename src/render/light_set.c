/* A light set as the renderer's light.  Point mode: every light of the pixel's interleaved
 * set, one shadow ray each, traced 16 at a time.  Stratified mode: the set's regions as
 * strata of the map, one direction drawn in each, combined with a BSDF sample by MIS per
 * region (docs/lights.md, "Stratified mode"). */
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

/* Stratified mode: one direction in every region lit, weighted by radiance over the
 * region's pdf, and one BSDF sample; with MIS each region is its own two-technique
 * estimator (its pdf against the BSDF's), so the sum over regions is the direct light,
 * unbiased.  Two numbers are drawn for each region above the horizon, three for the
 * BSDF. */
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
    const int use_light = d->lighting.estimator != LUMIS_ESTIMATOR_BSDF,
              use_bsdf = d->lighting.estimator != LUMIS_ESTIMATOR_LIGHT,
              mis = d->lighting.estimator == LUMIS_ESTIMATOR_MIS;
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
    int regions[CHUNK];
    double u[2 * CHUNK];
    lumis_env_sample e[CHUNK];
    const float nx = (float)n.x, ny = (float)n.y, nz = (float)n.z;
    for (int q0 = 0; use_light && q0 < st->nstrata; q0 += CHUNK) {
        const int q1 = q0 + CHUNK < st->nstrata ? q0 + CHUNK : st->nstrata;
        int cnt = 0;
        for (int q = q0; q < q1; q++) {
            /* A region whose cone lies wholly below the horizon adds exactly nothing (no
             * BSDF here transmits): no draw. */
            const float *cone = st->cone + 4 * q;
            if (cone[0] * nx + cone[1] * ny + cone[2] * nz <= cone[3]) continue;
            regions[cnt] = st->strata[q];
            seq_2d(seq, d0 + (uint32_t)q, 0, 1, u + 2 * cnt);
            cnt++;
        }
        lumis_region_sampler_sample_n(st->rs, regions, u, (size_t)cnt, e);
        for (int q = 0; q < cnt; q++) {
            const v3 wi = fromf(e[q].dir);
            const double cosn = dot(wi, n);
            if (!(cosn > 0.0)) continue;
            const lumis_vec3 wil = tof(mk(dot(wi, t), dot(wi, b), cosn));
            if (lambert && !(wil.z > 0.0f)) continue;
            const lumis_rgb f = lambert ? kd : lumis_bsdf_eval(m, wo, wil);
            if (f.r == 0.0f && f.g == 0.0f && f.b == 0.0f) continue;
            const float pb = !mis      ? 0.0f
                             : lambert ? (float)(wil.z / LUMIS_PI)
                                       : lumis_bsdf_pdf(m, wo, wil);
            const double w = mis ? mis_weight(1, e[q].pdf, 1, pb, d->power_heuristic) : 1.0;
            const double k2 = w * cosn / e[q].pdf;
            packet_push(&p, o, wi, INFINITY,
                        mk(f.r * e[q].radiance.r * k2, f.g * e[q].radiance.g * k2,
                           f.b * e[q].radiance.b * k2));
            if (p.rays.n == PACKET) packet_flush(c->scene, d, &p, &L);
        }
    }
    *v->shadow_rays += (double)(p.rays.n + p.flushed);
    packet_flush(c->scene, d, &p, &L);
    if (!use_bsdf) return L;
    double ub[3];
    seq_bsdf(seq, m, db, 0, 1, ub);
    const lumis_bsdf_sample bs = lumis_bsdf_sample_wi(m, wo, ub[0], ub[1], ub[2]);
    if (!(bs.pdf > 0.0f)) return L;
    const v3 wi = norm(add(add(mul(t, bs.wi.x), mul(b, bs.wi.y)), mul(n, bs.wi.z)));
    int region = -1;
    lumis_rgb Le;
    const float pl = lumis_region_sampler_lookup(st->rs, tof(wi), &region, &Le);
    /* a region of another layer (Wu's split) or one without light adds nothing here */
    if (region < 0 || !(st->kinds & (1u << lumis_region_sampler_kind(st->rs, region))) ||
        (Le.r == 0.0f && Le.g == 0.0f && Le.b == 0.0f))
        return L;
    *v->shadow_rays += 1.0;
    if (occluded(c->scene, d, o, wi)) return L;
    const double w = mis ? mis_weight(1, bs.pdf, 1, pl, d->power_heuristic) : 1.0;
    return add(L, mk(bs.weight.r * Le.r * w, bs.weight.g * Le.g * w, bs.weight.b * Le.b * w));
}

static v3 shade_any(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    const set_state *st = c->state;
    return st->rs ? shade_stratified(c, h, dir, v) : shade(c, h, dir, v);
}

/* The set and the map it was made from.  Point lights: every light summed, direct
 * illumination only.  Strata: a direction in every region by light or MIS sampling, paths. */
static void inputs(const lumis_lighting *l, unsigned *needs, unsigned *takes)
{
    *needs = LUMIS__IN_ENV | LUMIS__IN_SET;
    *takes = LUMIS__IN_SET_KINDS | LUMIS__IN_SET_MODE | LUMIS__IN_HIDE | LUMIS__IN_SUN;
    if (l->light_set.mode == LUMIS_LIGHTS_STRATIFIED)
        *takes |= LUMIS__IN_REGIONS | LUMIS__IN_EST_LIGHT | LUMIS__IN_POWER | LUMIS__IN_BOUNCES;
}

static void release(void *state)
{
    set_state *st = state;
    if (st) {
        soa_free(st->soa, st->sets);
        lumis_region_sampler_destroy(st->owned);
        free(st->strata);
        free(st->cone);
    }
    free(st);
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
        if (!st->strata || !st->cone)
            return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY,
                               "render: light set: out of memory");
        for (int k = 0; k < count; k++) {
            if (!(st->kinds & (1u << lumis_region_sampler_kind(st->rs, k))) ||
                lumis_region_sampler_empty(st->rs, k))
                continue;
            float *cone = st->cone + 4 * st->nstrata;
            cone[0] = l[k].dir.x;
            cone[1] = l[k].dir.y;
            cone[2] = l[k].dir.z;
            /* below the horizon when the angle to the normal is at least 90 degrees + the
             * extent: n . dir <= -sin(extent), with a margin for the float rounding */
            cone[3] = l[k].extent < 1.5f ? -sinf(l[k].extent) - 1e-4f : -2.0f;
            st->strata[st->nstrata++] = k;
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

const lumis__light_kind lumis__light_set_kind = {
    "a light set", inputs, prepare, release, NULL, NULL, NULL, NULL, NULL, shade_any,
};
