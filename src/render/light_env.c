/* The environment map as a light: light, BSDF or multiple importance sampling of the map
 * through its sampler (Veach's balance or power heuristic). */
#include "lumis/render.h"

#include "../core/internal.h"
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The light samples and BSDF samples per vertex, and whether the sampler draws from the
 * map lit with (its radiance and pdf then come from one lookup). */
typedef struct env_state {
    int nl, nb;
    int fused;
} env_state;

/* The map's radiance along the unoccluded BSDF sample bs (world direction wi) of a vertex,
 * and in *k2 its weight against the light samples by the estimator over the number of
 * BSDF samples: bs.weight Le k2 is the sample's share of the direct light. */
static lumis_rgb bsdf_sample_light(const ctx *c, const lumis_bsdf_sample *bs, v3 wi, double *k2)
{
    const lumis_render_desc *d = c->d;
    const env_state *st = c->state;
    const lumis_sampler *smp = d->lighting.sampler;
    const int mis = estimator_use_of(d).mis;
    lumis_rgb Le;
    double w = 1.0;
    if (mis && st->fused) { /* one pixel lookup for the radiance and the light pdf */
        float pl = lumis_sampler_pdf_radiance(smp, tof(wi), &Le);
        w = mis_weight(st->nb, bs->pdf, st->nl, pl, d->power_heuristic);
    } else {
        Le = lumis_envmap_eval(lumis__light_map(d), tof(wi));
        if (mis)
            w = mis_weight(st->nb, bs->pdf, st->nl, lumis_sampler_pdf(smp, tof(wi)),
                           d->power_heuristic);
    }
    *k2 = w / st->nb;
    return Le;
}

/* Direct light from the environment reflected at h towards -dir.  With next, the first
 * BSDF sample is not traced here but handed to the integrator as the path's continuation
 * (shade_next), whatever the estimator: its numbers are drawn either way. */
static v3 shade_at(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v, lumis__next *next)
{
    const lumis_render_desc *d = c->d;
    const env_state *st = c->state;
    lumis__stream *seq = v->seq;
    /* two dimensions: the light samples' points, the BSDF samples' (a lobe and a point) */
    const uint32_t dl = seq_take(seq), db = seq_take_n(seq, 2);
    double *shadow_rays = v->shadow_rays;
    const shading_frame fr = shading_frame_at(h, dir);
    const v3 t = fr.t, b = fr.b, n = fr.n, org = fr.org;
    const lumis_vec3 wo = fr.wo;
    v3 L = mk(0, 0, 0);
    const lumis_bsdf *m = &h->prim->material;
    const lumis_sampler *smp = d->lighting.sampler;
    const estimator_use use = estimator_use_of(d);
    for (int k = 0; use.light && k < st->nl; k++) {
        double u[2];
        seq_2d(seq, dl, (uint32_t)k, (uint32_t)st->nl, u);
        lumis_env_sample e = lumis_sampler_sample(smp, u[0], u[1]);
        v3 wi = fromf(e.dir);
        double cosn = dot(wi, n);
        if (!(cosn > 0.0) || !(e.pdf > 0.0f)) continue;
        lumis_vec3 wil = tof(mk(dot(wi, t), dot(wi, b), cosn));
        lumis_rgb f = lumis_bsdf_eval(m, wo, wil);
        if (f.r == 0.0f && f.g == 0.0f && f.b == 0.0f) continue;
        *shadow_rays += 1.0;
        if (occluded(c->scene, d, org, wi)) continue;
        double w = use.mis ? mis_weight(st->nl, e.pdf, st->nb, lumis_bsdf_pdf(m, wo, wil),
                                        d->power_heuristic)
                           : 1.0;
        double k2 = w * cosn / ((double)e.pdf * st->nl);
        L = add(L, mk(f.r * e.radiance.r * k2, f.g * e.radiance.g * k2, f.b * e.radiance.b * k2));
    }
    if (next) {
        next->org = org;
        next->bs.pdf = 0.0f;
    }
    const int nb = use.bsdf ? st->nb : next ? 1 : 0;
    for (int k = 0; k < nb; k++) {
        double u[3];
        seq_bsdf(seq, m, db, (uint32_t)k, (uint32_t)st->nb, u);
        lumis_bsdf_sample bs = lumis_bsdf_sample_wi(m, wo, u[0], u[1], u[2]);
        if (!(bs.pdf > 0.0f)) continue;
        v3 wi = norm(add(add(mul(t, bs.wi.x), mul(b, bs.wi.y)), mul(n, bs.wi.z)));
        if (next && k == 0) { /* the continuation: its light is escape()'s */
            next->bs = bs;
            next->wi = wi;
            continue;
        }
        *shadow_rays += 1.0;
        if (occluded(c->scene, d, org, wi)) continue;
        double k2;
        const lumis_rgb Le = bsdf_sample_light(c, &bs, wi, &k2);
        L = add(L, mk(bs.weight.r * Le.r * k2, bs.weight.g * Le.g * k2, bs.weight.b * Le.b * k2));
    }
    return L;
}

static v3 shade(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    return shade_at(c, h, dir, v, NULL);
}

static v3 shade_next(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v, lumis__next *next)
{
    return shade_at(c, h, dir, v, next);
}

/* The continuation left the scene along next->wi: the map it sees is the first BSDF
 * sample's share of the direct light (none with the light estimator). */
static v3 escape(const ctx *c, const lumis__next *next)
{
    if (!estimator_use_of(c->d).bsdf) return mk(0, 0, 0);
    double k2;
    const lumis_rgb Le = bsdf_sample_light(c, &next->bs, next->wi, &k2);
    return mk(Le.r * k2, Le.g * k2, Le.b * k2);
}

/* The map and, for light or MIS sampling, its sampler; direct light by any estimator, and
 * paths. */
static void inputs(const lumis_lighting *l, unsigned *needs, unsigned *takes)
{
    *needs = LUMIS__IN_ENV | (l->estimator != LUMIS_ESTIMATOR_BSDF ? LUMIS__IN_SAMPLER : 0u);
    *takes = LUMIS__IN_SAMPLER | LUMIS__IN_EST_LIGHT | LUMIS__IN_EST_BSDF | LUMIS__IN_HIDE |
             LUMIS__IN_POWER | LUMIS__IN_LIGHT_SAMPLES | LUMIS__IN_BSDF_SAMPLES |
             LUMIS__IN_BOUNCES | LUMIS__IN_SUN;
}

static lumis_status prepare(const lumis_scene *scene, const lumis_render_desc *d, void **state)
{
    (void)scene;
    env_state *st = malloc(sizeof *st);
    if (!st) return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "render: out of memory");
    st->nl = d->light_samples ? d->light_samples : 1;
    st->nb = d->bsdf_samples ? d->bsdf_samples : 1;
    st->fused =
        d->lighting.sampler && lumis_sampler_envmap(d->lighting.sampler) == lumis__light_map(d);
    *state = st;
    return LUMIS_OK;
}

const lumis__light_kind lumis__light_env = {
    "the environment map",
    inputs,
    prepare,
    free,
    NULL,
    NULL,
    NULL,
    NULL,
    NULL,
    shade,
    shade_next,
    escape,
};
