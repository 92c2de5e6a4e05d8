/* The image sun as a light (lighting.sun, lumis/sun.h): at every vertex one direction drawn
 * on the sun's pixels by their power (its sampler) and one BSDF sample, each weighted against the
 * sun's pdf alone by `estimator`, added to what the light kind draws from the residual map.  The
 * sun's radiance is the whole map's on the sun's pixels (lumis_sun_eval) and the residual is zero
 * there, so the two estimates sum to the map's light, unbiased (docs/lights.md, "The image sun").
 */
#include "lumis/render.h"

#include "shade.h"

v3 lumis__sun_shade(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    const lumis_render_desc *d = c->d;
    const lumis_sun_sampler *sun = d->lighting.sun.sampler;
    lumis__stream *seq = v->seq;
    /* the sun's numbers follow the kind's: a point on the sun, a lobe and a point */
    const uint32_t dl = seq_take(seq), db = seq_take_n(seq, 2);
    const shading_frame fr = shading_frame_at(h, dir);
    const v3 t = fr.t, b = fr.b, n = fr.n, org = fr.org;
    const lumis_vec3 wo = fr.wo;
    const lumis_bsdf *m = &h->prim->material;
    const estimator_use use = estimator_use_of(d);
    v3 L = mk(0, 0, 0);
    if (use.light) {
        double u[2], ps = 0.0;
        seq_2d(seq, dl, 0, 1, u);
        lumis_rgb Le;
        const lumis_vec3 s = lumis_sun_sampler_sample(sun, u[0], u[1], &ps, &Le);
        const v3 wi = fromf(s);
        const double cosn = dot(wi, n);
        if (cosn > 0.0 && ps > 0.0 && (Le.r != 0.0f || Le.g != 0.0f || Le.b != 0.0f)) {
            const lumis_vec3 wil = tof(mk(dot(wi, t), dot(wi, b), cosn));
            const lumis_rgb f = lumis_bsdf_eval(m, wo, wil);
            if (f.r != 0.0f || f.g != 0.0f || f.b != 0.0f) {
                *v->shadow_rays += 1.0;
                if (!occluded(c->scene, d, org, wi)) {
                    const double w = use.mis ? mis_weight(1, ps, 1, lumis_bsdf_pdf(m, wo, wil),
                                                          d->power_heuristic)
                                             : 1.0;
                    const double k2 = w * cosn / ps;
                    L = add(L, mk(f.r * Le.r * k2, f.g * Le.g * k2, f.b * Le.b * k2));
                }
            }
        }
    }
    if (!use.bsdf) return L;
    double u[3];
    seq_bsdf(seq, m, db, 0, 1, u);
    const lumis_bsdf_sample bs = lumis_bsdf_sample_wi(m, wo, u[0], u[1], u[2]);
    if (!(bs.pdf > 0.0f)) return L;
    const v3 wi = norm(add(add(mul(t, bs.wi.x), mul(b, bs.wi.y)), mul(n, bs.wi.z)));
    /* only a direction on the sun's pixels is worth a shadow ray (rarely: the sun is small) */
    lumis_rgb Le;
    const double ps = lumis_sun_sampler_pdf(sun, tof(wi), &Le);
    if (Le.r == 0.0f && Le.g == 0.0f && Le.b == 0.0f) return L;
    *v->shadow_rays += 1.0;
    if (occluded(c->scene, d, org, wi)) return L;
    const double w = use.mis ? mis_weight(1, bs.pdf, 1, ps, d->power_heuristic) : 1.0;
    return add(L, mk(bs.weight.r * Le.r * w, bs.weight.g * Le.g * w, bs.weight.b * Le.b * w));
}
