/* The integrator: one camera sample's path.  Direct illumination at the first hit through
 * the light kind (shade.h), and with max_bounces > 0 the same at every further vertex of a
 * BSDF-sampled path. */
#include "lumis/render.h"

#include "shade.h"

#include <math.h>

/* One camera sample: direct illumination at the first hit, and with max_bounces > 0 the
 * direct illumination at every further vertex of a BSDF-sampled path.  The environment
 * seen by a continuation ray is only added as the share of the direct estimator at the
 * vertex it left: when the kind hands its BSDF sample over as the continuation
 * (shade_next), the map that ray sees on escaping is that sample's MIS-weighted share
 * (escape); a continuation drawn here is not a direct sample and adds nothing.  So each
 * light path is counted once.  The last vertex traces its BSDF sample as a shadow ray
 * (shade): an occlusion test is cheaper than a hit. */
v3 lumis__trace_sample(const ctx *c, const lumis__light_kind *kind, v3 eye, v3 dir,
                       const lumis__vertex *v, double *bounce)
{
    const lumis_render_desc *d = c->d;
    hit hh;
    if (!intersect(c->scene, eye, dir, &hh)) {
        if (d->lighting.hide_environment || !d->lighting.env) return mk(0, 0, 0);
        lumis_rgb e = lumis_envmap_eval(d->lighting.env, tof(dir));
        return mk(e.r, e.g, e.b);
    }
    v3 L = mk(0, 0, 0), beta = mk(1, 1, 1);
    for (int depth = 0;; depth++) {
        const int last = depth >= d->max_bounces, handed = !last && kind->shade_next;
        /* The light interface: the kind of lights decides how the point is lit. */
        lumis__next nx;
        v3 Ld = handed ? kind->shade_next(c, &hh, dir, v, &nx) : kind->shade(c, &hh, dir, v);
        if (d->lighting.sun.sun) Ld = add(Ld, lumis__sun_shade(c, &hh, dir, v));
        L = add(L, mk(beta.x * Ld.x, beta.y * Ld.y, beta.z * Ld.z));
        if (last) break;
        if (!handed) {
            const shading_frame fr = shading_frame_at(&hh, dir);
            double u[3];
            seq_bsdf(v->seq, &hh.prim->material, seq_take_n(v->seq, 2), 0, 1, u);
            nx.bs = lumis_bsdf_sample_wi(&hh.prim->material, fr.wo, u[0], u[1], u[2]);
            nx.wi =
                norm(add(add(mul(fr.t, nx.bs.wi.x), mul(fr.b, nx.bs.wi.y)), mul(fr.n, nx.bs.wi.z)));
            nx.org = fr.org;
        }
        if (!(nx.bs.pdf > 0.0f)) break;
        beta = mk(beta.x * nx.bs.weight.r, beta.y * nx.bs.weight.g, beta.z * nx.bs.weight.b);
        if (beta.x == 0.0 && beta.y == 0.0 && beta.z == 0.0) break;
        dir = nx.wi;
        *bounce += 1.0;
        if (!intersect(c->scene, nx.org, dir, &hh)) {
            if (handed) {
                const v3 Le = kind->escape(c, &nx);
                L = add(L, mk(beta.x * Le.x, beta.y * Le.y, beta.z * Le.z));
            }
            break;
        }
    }
    return L;
}
