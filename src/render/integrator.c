/* The integrator: one camera sample's path.  Direct illumination at the first hit through
 * the light kind (shade.h), and with max_bounces > 0 the same at every further vertex of a
 * BSDF-sampled path. */
#include "lumis/render.h"

#include "shade.h"

#include <math.h>

/* One camera sample: direct illumination at the first hit, and with max_bounces > 0 the
 * direct illumination at every further vertex of a BSDF-sampled path.  The environment
 * seen by a continuation ray is not added: the direct estimator at the vertex it left
 * already accounts for it, so each light path is counted once. */
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
        /* The light interface: the kind of lights decides how the point is lit. */
        v3 Ld = kind->shade(c, &hh, dir, v);
        if (d->lighting.sun.sun) Ld = add(Ld, lumis__sun_shade(c, &hh, dir, v));
        L = add(L, mk(beta.x * Ld.x, beta.y * Ld.y, beta.z * Ld.z));
        if (depth >= d->max_bounces) break;
        const shading_frame fr = shading_frame_at(&hh, dir);
        const v3 t = fr.t, b = fr.b, n = fr.n;
        const lumis_vec3 wo = fr.wo;
        double u[3];
        seq_bsdf(v->seq, &hh.prim->material, seq_take_n(v->seq, 2), 0, 1, u);
        lumis_bsdf_sample bs = lumis_bsdf_sample_wi(&hh.prim->material, wo, u[0], u[1], u[2]);
        if (!(bs.pdf > 0.0f)) break;
        beta = mk(beta.x * bs.weight.r, beta.y * bs.weight.g, beta.z * bs.weight.b);
        if (beta.x == 0.0 && beta.y == 0.0 && beta.z == 0.0) break;
        dir = norm(add(add(mul(t, bs.wi.x), mul(b, bs.wi.y)), mul(n, bs.wi.z)));
        *bounce += 1.0;
        if (!intersect(c->scene, fr.org, dir, &hh)) break;
    }
    return L;
}
