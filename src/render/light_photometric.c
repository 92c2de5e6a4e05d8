/* Photometric fixtures as lights (lumis_photometric_lighting): a far-field table placed as a
 * point, or as its flat luminous opening (a disk or a rectangle facing the aim) whose every
 * point emits the table's distribution.  A point is sampled by its one direction (a delta:
 * no BSDF sample can find it); an opening by points on it, uniform by area, combined with
 * BSDF samples that hit it by MIS.  Derivations: docs/photometric.md. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct fixture {
    const lumis_photometric *p;
    double r[9], t[3]; /* local to world: world = r local + t (row-major) */
    double mult;
    int area;              /* 0: a point; 1: a disk; 2: a rectangle */
    double hx, hy, radius; /* the rectangle's half length (x) and width (y); the disk's radius */
    double A;              /* the opening's area */
} fixture;

typedef struct photometric_state {
    fixture *f;
    int count, nl, nb, any_area;
} photometric_state;

static v3 to_world(const fixture *f, double x, double y, double z)
{
    const double *r = f->r;
    return mk(r[0] * x + r[1] * y + r[2] * z, r[3] * x + r[4] * y + r[5] * z,
              r[6] * x + r[7] * y + r[8] * z);
}

static v3 to_local(const fixture *f, v3 w)
{
    const double *r = f->r;
    return mk(r[0] * w.x + r[3] * w.y + r[6] * w.z, r[1] * w.x + r[4] * w.y + r[7] * w.z,
              r[2] * w.x + r[5] * w.y + r[8] * w.z);
}

/* The table's intensity towards l (from the fixture, in its frame), multiplier applied. */
static double intensity(const fixture *f, v3 l)
{
    const lumis_vec3 d = {(float)l.x, (float)l.y, (float)l.z};
    return f->mult * lumis_photometric_intensity(f->p, d);
}

/* A point of the opening from two numbers, uniform by area (local z = 0). */
static void opening_point(const fixture *f, const double u[2], double *x, double *y)
{
    if (f->area == 1) { /* the disk: r = R sqrt(u0), phi = 2 pi u1 */
        const double rr = f->radius * sqrt(u[0]), phi = 2.0 * LUMIS_PI * u[1];
        *x = rr * cos(phi);
        *y = rr * sin(phi);
    } else {
        *x = (2.0 * u[0] - 1.0) * f->hx;
        *y = (2.0 * u[1] - 1.0) * f->hy;
    }
}

/* Where the ray org + s wi meets the opening, if it does from its front (s > 0): *s, and
 * wi in the fixture's frame (its z: the cosine at the opening, between -wi and the aim). */
static int hit_opening(const fixture *f, v3 org, v3 wi, double *s, v3 *wl)
{
    const v3 o = to_local(f, sub(org, mk(f->t[0], f->t[1], f->t[2]))), w = to_local(f, wi);
    /* the front: the side the aim (-z) points to, so the ray travels towards +z */
    if (!(w.z > 0.0) || !(o.z < 0.0)) return 0;
    const double t = -o.z / w.z, x = o.x + t * w.x, y = o.y + t * w.y;
    const int inside = f->area == 1 ? x * x + y * y <= f->radius * f->radius
                                    : fabs(x) <= f->hx && fabs(y) <= f->hy;
    if (!inside) return 0;
    *s = t;
    *wl = w;
    return 1;
}

static v3 shade(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    const lumis_render_desc *d = c->d;
    const photometric_state *st = c->state;
    lumis__stream *seq = v->seq;
    /* the light samples' points (one dimension for every fixture), the BSDF samples' */
    const uint32_t dl = seq_take(seq), db = seq_take_n(seq, 2);
    const shading_frame fr = shading_frame_at(h, dir);
    const v3 t = fr.t, b = fr.b, n = fr.n, org = fr.org;
    const lumis_vec3 wo = fr.wo;
    const lumis_bsdf *m = &h->prim->material;
    const int use_light = d->estimator != LUMIS_ESTIMATOR_BSDF,
              use_bsdf = d->estimator != LUMIS_ESTIMATOR_LIGHT,
              mis = d->estimator == LUMIS_ESTIMATOR_MIS;
    v3 L = mk(0, 0, 0);
    packet p;
    p.rays.n = p.flushed = 0;
    const uint32_t total = (uint32_t)(st->count * st->nl);
    for (int q = 0; q < st->count; q++) {
        const fixture *f = &st->f[q];
        /* a point is found by its light sample alone, whatever the estimator */
        const int nl = f->area ? (use_light ? st->nl : 0) : st->nl;
        for (int k = 0; k < nl; k++) {
            double u[2] = {0.5, 0.5}, x = 0, y = 0;
            seq_2d(seq, dl, (uint32_t)(q * st->nl + k), total, u);
            if (f->area) opening_point(f, u, &x, &y);
            const v3 pl = add(to_world(f, x, y, 0.0), mk(f->t[0], f->t[1], f->t[2]));
            /* the geometry from the surface point itself; the shadow ray from the lifted
             * origin (its lift would otherwise bias d^2 by about lift / d) */
            const v3 w = sub(pl, h->p), ws = sub(pl, org);
            const double d2 = dot(w, w), dist = sqrt(d2), dist_s = sqrt(dot(ws, ws));
            if (!(dist > 0.0) || !(dist_s > 0.0)) continue;
            const v3 wi = mul(w, 1.0 / dist);
            const double cos_s = dot(wi, n);
            if (!(cos_s > 0.0)) continue;
            const v3 el = to_local(f, mul(wi, -1.0)); /* from the fixture to the point */
            double weight = 1.0;
            const lumis_vec3 wil = tof(mk(dot(wi, t), dot(wi, b), cos_s));
            if (f->area) { /* the opening's front only; MIS with the BSDF's density */
                const double cos_l = -el.z;
                if (!(cos_l > 0.0)) continue;
                if (mis && st->nb > 0) {
                    const double pl_sa = d2 / (f->A * cos_l);
                    weight = mis_weight(st->nl, pl_sa, st->nb, lumis_bsdf_pdf(m, wo, wil),
                                        d->power_heuristic);
                }
            }
            const double I = intensity(f, el);
            if (!(I > 0.0)) continue;
            const lumis_rgb fb = lumis_bsdf_eval(m, wo, wil);
            if (fb.r == 0.0f && fb.g == 0.0f && fb.b == 0.0f) continue;
            /* E = I cos_s / d^2 for a point; for an opening the area pdf 1/A cancels the
             * radiance's 1/A and cos_l: the same expression at the sampled point */
            const double k2 = weight * I * cos_s / (d2 * st->nl);
            packet_push(&p, org, mul(ws, 1.0 / dist_s), (float)(dist_s * (1.0 - 1e-4)),
                        mk(fb.r * k2, fb.g * k2, fb.b * k2));
            if (p.rays.n == PACKET) packet_flush(c->scene, d, &p, &L);
        }
        if (!f->area || !use_bsdf) continue;
        for (int k = 0; k < st->nb; k++) { /* BSDF samples that find the opening */
            double u[3];
            seq_bsdf(seq, m, db, (uint32_t)(q * st->nb + k), (uint32_t)(st->count * st->nb), u);
            const lumis_bsdf_sample bs = lumis_bsdf_sample_wi(m, wo, u[0], u[1], u[2]);
            if (!(bs.pdf > 0.0f)) continue;
            const v3 wi = norm(add(add(mul(t, bs.wi.x), mul(b, bs.wi.y)), mul(n, bs.wi.z)));
            double s;
            v3 wl;
            if (!hit_opening(f, org, wi, &s, &wl)) continue;
            const double cos_l = wl.z, I = intensity(f, mul(wl, -1.0));
            if (!(I > 0.0)) continue;
            const double Le = I / (f->A * cos_l);
            double weight = 1.0;
            if (mis && st->nl > 0)
                weight =
                    mis_weight(st->nb, bs.pdf, st->nl, s * s / (f->A * cos_l), d->power_heuristic);
            const double k2 = weight * Le / st->nb;
            packet_push(&p, org, wi, (float)(s * (1.0 - 1e-4)),
                        mk(bs.weight.r * k2, bs.weight.g * k2, bs.weight.b * k2));
            if (p.rays.n == PACKET) packet_flush(c->scene, d, &p, &L);
        }
    }
    *v->shadow_rays += (double)(p.rays.n + p.flushed);
    packet_flush(c->scene, d, &p, &L);
    return L;
}

static int lights(const lumis_render_desc *d)
{
    return d->photometric && d->photometric->count > 0;
}

static void release(void *state)
{
    photometric_state *st = state;
    if (st) free(st->f);
    free(st);
}

static lumis_status prepare(const lumis_scene *scene, const lumis_render_desc *d, void **state)
{
    (void)scene;
    const lumis_photometric_lighting *pl = d->photometric;
    if (!pl->instances || pl->count < 0 || pl->count > 100000)
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: photometric lighting needs 1 to 100000 instances");
    photometric_state *st = calloc(1, sizeof *st);
    if (st) st->f = calloc((size_t)pl->count, sizeof *st->f);
    if (!st || !st->f) {
        release(st);
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "render: out of memory");
    }
    *state = st;
    st->count = pl->count;
    st->nl = d->light_samples ? d->light_samples : 1;
    st->nb = d->bsdf_samples ? d->bsdf_samples : 1;
    for (int q = 0; q < pl->count; q++) {
        const lumis_photometric_instance *in = &pl->instances[q];
        fixture *f = &st->f[q];
        lumis_rigid x = in->placement;
        int zero = 1;
        for (int k = 0; k < 9; k++) zero &= x.r[k] == 0.0;
        if (zero) x.r[0] = x.r[4] = x.r[8] = 1.0;
        if (!in->photometric || lumis_rigid_check(&x) != LUMIS_OK || !(in->multiplier >= 0.0) ||
            !isfinite(in->multiplier) || !isfinite(x.t[0]) || !isfinite(x.t[1]) ||
            !isfinite(x.t[2]))
            return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "render: photometric fixture %d: needs a table, a proper rotation, "
                               "a finite position and a multiplier >= 0",
                               q);
        memcpy(f->r, x.r, sizeof f->r);
        memcpy(f->t, x.t, sizeof f->t);
        f->p = in->photometric;
        f->mult = in->multiplier == 0.0 ? 1.0 : in->multiplier;
        lumis_photometric_info info;
        lumis_photometric_get_info(f->p, &info);
        if (in->area && info.shape == LUMIS_SHAPE_DISK && info.width > 0) {
            f->area = 1;
            f->radius = 0.5 * info.width;
            f->A = LUMIS_PI * f->radius * f->radius;
        } else if (in->area && info.shape == LUMIS_SHAPE_RECTANGLE && info.width > 0 &&
                   info.length > 0) {
            f->area = 2;
            f->hx = 0.5 * info.length;
            f->hy = 0.5 * info.width;
            f->A = info.length * info.width;
        } else if (in->area) { /* not quietly a point */
            return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "render: photometric fixture %d: its file's luminous shape is "
                               "\"%s\": the opening (area) model takes a disk or a rectangle of "
                               "non-zero size; render it as a point (no area)",
                               q, lumis_photometric_shape_name(info.shape));
        }
        st->any_area |= f->area != 0;
    }
    return LUMIS_OK;
}

const lumis__light_kind lumis__light_photometric = {
    "photometric fixtures", lights, prepare, release, NULL, NULL, NULL, NULL, NULL, shade,
};

/* The frame docs/photometric.md ("Aiming a fixture") states: local -z along the aim; local
 * +x from `up` when given (projected perpendicular to the aim), else by the type: type C
 * the hanging pose (aim -y, C0 +x) turned by the smallest rotation taking -y to the aim;
 * types A and B a yoke (up: world +y made perpendicular to the aim, the lateral axis
 * horizontal); then rolled about the aim. */
lumis_status lumis_photometric_orient(lumis_photometric_type type, lumis_vec3 aim,
                                      const lumis_vec3 *up, double roll_deg, double R[9])
{
    if (type != LUMIS_PHOTOMETRIC_A && type != LUMIS_PHOTOMETRIC_B && type != LUMIS_PHOTOMETRIC_C)
        return LUMIS_ERR_INVALID_ARGUMENT;
    v3 a = fromf(aim);
    const double len = sqrt(dot(a, a));
    if (!(len > 0.0) || !isfinite(len) || !isfinite(roll_deg)) return LUMIS_ERR_INVALID_ARGUMENT;
    a = mul(a, 1.0 / len);
    const v3 z = mul(a, -1.0); /* local +z */
    /* the aim's horizontal length: below 1e-9 (5.7e-8 degrees) it is vertical */
    const double h2 = a.x * a.x + a.z * a.z, h = sqrt(h2);
    v3 x;
    if (up) { /* as close to `up` as the aim allows */
        const v3 u = fromf(*up);
        const double ul = sqrt(dot(u, u));
        if (!(ul > 0.0) || !isfinite(ul)) return LUMIS_ERR_INVALID_ARGUMENT;
        x = sub(u, mul(a, dot(u, a)));
        if (!(sqrt(dot(x, x)) > 1e-6 * ul)) return LUMIS_ERR_INVALID_ARGUMENT;
    } else if (type == LUMIS_PHOTOMETRIC_C) {
        /* +x under the rotation about (-a.z, 0, a.x) by acos(-a.y): 1 - a.y written as
         * h^2 / (1 + a.y) above the horizon, where the difference would cancel */
        const double d = a.y <= 0.0 ? 1.0 - a.y : h2 / (1.0 + a.y);
        x = a.y > 0.0 && h <= 1e-9 ? mk(1, 0, 0) /* straight up: the half turn about x */
                                   : mk(1.0 - a.x * a.x / d, a.x, -a.x * a.z / d);
    } else if (h > 1e-9) { /* a yoke: the lateral axis horizontal, up towards +y */
        const v3 lateral = mk(a.z / h, 0.0, -a.x / h);
        x = cross(lateral, z);
    } else {
        x = mk(1, 0, 0); /* straight up or down: the top towards +x */
    }
    x = norm(sub(x, mul(z, dot(x, z))));
    const v3 y = cross(z, x);
    const double rr = roll_deg * LUMIS_PI / 180.0, cr = cos(rr), sr = sin(rr);
    const v3 xr = norm(add(mul(x, cr), mul(y, sr))), yr = cross(z, xr);
    /* columns x, y, z: world = R local */
    R[0] = xr.x, R[1] = yr.x, R[2] = z.x;
    R[3] = xr.y, R[4] = yr.y, R[5] = z.y;
    R[6] = xr.z, R[7] = yr.z, R[8] = z.z;
    return LUMIS_OK;
}
