/* Photometric fixtures as lights (lumis_photometric_lighting): a far-field table placed as a
 * point, or as its luminous opening: a flat one (a disk or a rectangle facing the aim) or a
 * solid one (a box, a vertical cylinder, a sphere), whose every surface point emits the
 * table's intensity over the area the opening shows that way.  A point is sampled by its
 * one direction (a delta: no BSDF sample can find it); an opening by points on it (a solid's
 * faces in proportion to the area they show the shading point), combined with BSDF samples
 * that hit it by MIS.  Derivations: docs/photometric.md. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The opening's kinds: flat ones facing the aim (emitting nothing behind them), and solid
 * ones (a box, a vertical cylinder, a sphere, centred on the fixture's position) whose every
 * surface point emits L(d) = I(d) / A_proj(d) towards d, A_proj the solid's area seen from
 * d: so the intensity of the whole is I(d) in every direction (docs/photometric.md). */
enum { POINT = 0, DISK, RECT, BOX, CYLINDER, SPHERE };

typedef struct fixture {
    const lumis_photometric *p;
    double r[9], t[3]; /* local to world: world = r local + t (row-major) */
    double mult;
    int area; /* POINT, DISK, ... */
    /* half extents along x (length), y (width) and z (height); the radius (disk, cylinder,
     * sphere) */
    double hx, hy, hz, radius;
    double A; /* the flat opening's area; a solid's surface area */
    /* the near-field fixture: its light field, the residual beyond its cone, its report */
    const lumis_luminaire *lf;
    lumis_photometric *residual;
    const lumis_photometric_light_field_report *rep;
} fixture;

typedef struct photometric_state {
    fixture *f;
    int count, nl, nb, any_area;
    int capacity; /* the most samples a near-field fixture's light field returns (0: none) */
} photometric_state;

enum { NEAR_BUDGET = 32 }; /* light-field samples per vertex of a near-field fixture */

/* A thread's buffer for the light fields' samples, and how many it evaluated. */
typedef struct photometric_scratch {
    lumis_luminaire_sample *s;
    double samples;
} photometric_scratch;

static void fill_pcg(void *rng, double *u, int n)
{
    lumis_pcg32_fill_doubles(rng, u, (size_t)n);
}

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

/* A near-field fixture's point at the field's weight w: w I_residual + (1 - w) I_table; the
 * table alone (the same arithmetic as a plain fixture's) at w = 0. */
static double point_intensity(const fixture *f, v3 l, double w)
{
    if (!(w > 0.0)) return intensity(f, l);
    const lumis_vec3 d = {(float)l.x, (float)l.y, (float)l.z};
    const double res = f->residual ? lumis_photometric_intensity(f->residual, d) : 0.0;
    return f->mult * (w * res + (w < 1.0 ? (1.0 - w) * lumis_photometric_intensity(f->p, d) : 0));
}

/* w times the light field's estimate at h (its samples times the BSDF and the cosine, one
 * shadow ray each): the field's numbers from a PCG32 stream of its own, keyed by the pixel
 * (and the render's seed), the camera sample, the vertex's dimension and the fixture. */
static void near_field_samples(const ctx *c, const fixture *f, double w, const hit *h,
                               const shading_frame *fr, const lumis__stream *seq, uint32_t dim,
                               int index, int capacity, photometric_scratch *sc, packet *p, v3 *L)
{
    const v3 centre = mk(f->t[0], f->t[1], f->t[2]);
    const v3 xl = to_local(f, sub(h->p, centre));
    lumis_luminaire_query q = {0};
    q.p = tof(mk(xl.x, -xl.y, -xl.z)); /* the field's frame: half a turn about x */
    if (!(q.p.z > 0.0f)) return;       /* behind the opening */
    q.budget = NEAR_BUDGET;
    q.strategy = LUMIS_LUM_RESTRICTED;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, lumis__mix64(seq->pixel ^ lumis__mix64(((uint64_t)seq->k << 32) | dim)),
                     (uint64_t)index);
    q.fill = fill_pcg;
    q.fill_ctx = &rng;
    int count = 0;
    if (lumis_luminaire_sample_point(f->lf, &q, NULL, capacity, sc->s, &count) != LUMIS_OK) return;
    sc->samples += count;
    const lumis_bsdf *m = &h->prim->material;
    for (int j = 0; j < count; j++) {
        const lumis_luminaire_sample *s = &sc->s[j];
        if (!(s->weight > 0.0f) ||
            !(s->radiance.g > 0.0f || s->radiance.r > 0.0f || s->radiance.b > 0.0f))
            continue;
        /* the field's frame to the fixture's (half a turn about x), then the world */
        const v3 wi = norm(to_world(f, s->dir.x, -s->dir.y, -s->dir.z));
        const double cosn = dot(wi, fr->n);
        if (!(cosn > 0.0)) continue;
        const lumis_rgb fb =
            lumis_bsdf_eval(m, fr->wo, tof(mk(dot(wi, fr->t), dot(wi, fr->b), cosn)));
        if (fb.r == 0.0f && fb.g == 0.0f && fb.b == 0.0f) continue;
        const double k = w * f->mult * cosn * s->weight;
        packet_push(
            p, fr->org, wi, (float)(s->distance * (1.0 - 1e-4)),
            mk(fb.r * s->radiance.r * k, fb.g * s->radiance.g * k, fb.b * s->radiance.b * k));
        if (p->rays.n == PACKET) packet_flush(c->scene, c->d, p, L);
    }
}

/* The opening's area seen from the unit direction d (its frame): a flat one's from its front
 * only. */
static double projected_area(const fixture *f, v3 d)
{
    switch (f->area) {
    case DISK:
    case RECT:
        return d.z < 0.0 ? -d.z * f->A : 0.0;
    case BOX:
        return 4.0 *
               (f->hy * f->hz * fabs(d.x) + f->hx * f->hz * fabs(d.y) + f->hx * f->hy * fabs(d.z));
    case CYLINDER:
        return LUMIS_PI * f->radius * f->radius * fabs(d.z) +
               4.0 * f->radius * f->hz * sqrt(fmax(0.0, 1.0 - d.z * d.z));
    default: /* SPHERE */
        return LUMIS_PI * f->radius * f->radius;
    }
}

/* The radiance a surface point of normal n sends towards the unit direction d (both in the
 * fixture's frame), multiplier applied; 0 behind the surface. */
static double radiance(const fixture *f, v3 d, v3 n)
{
    if (!(dot(d, n) > 0.0)) return 0.0;
    const double a = projected_area(f, d);
    return a > 0.0 ? intensity(f, d) / a : 0.0;
}

/* The solid's faces as a point of the shading point xl (local) may choose them: each face's
 * weight is its area seen from the centre's direction to xl (0 for faces turned away, which
 * xl cannot see); a curved side's is its projected area.  w[] per face, their sum returned. */
static double face_weights(const fixture *f, v3 xl, double w[6])
{
    const double len = sqrt(dot(xl, xl));
    const v3 c = len > 0.0 ? mul(xl, 1.0 / len) : mk(0, 0, -1);
    double sum = 0.0;
    if (f->area == BOX) {
        const double a[3] = {4.0 * f->hy * f->hz, 4.0 * f->hx * f->hz, 4.0 * f->hx * f->hy};
        const double cc[3] = {c.x, c.y, c.z};
        for (int k = 0; k < 3; k++) {
            w[2 * k] = a[k] * fmax(0.0, cc[k]);      /* the face at +h */
            w[2 * k + 1] = a[k] * fmax(0.0, -cc[k]); /* at -h */
            sum += w[2 * k] + w[2 * k + 1];
        }
    } else { /* CYLINDER: top, bottom, side */
        const double cap = LUMIS_PI * f->radius * f->radius;
        w[0] = cap * fmax(0.0, c.z);
        w[1] = cap * fmax(0.0, -c.z);
        w[2] = 4.0 * f->radius * f->hz * sqrt(fmax(0.0, 1.0 - c.z * c.z));
        sum = w[0] + w[1] + w[2];
    }
    return sum;
}

/* A point of the opening for the shading point xl (local), from two numbers: the point, its
 * outward normal and the density per unit area it was chosen with.  Flat openings and the
 * sphere uniformly by area; a box's or a cylinder's face by face_weights, then uniformly on
 * it.  0 when xl sees none of it. */
static int opening_sample(const fixture *f, v3 xl, const double u_in[2], v3 *y, v3 *n,
                          double *pdf_area)
{
    double u[2] = {u_in[0], u_in[1]};
    if (f->area == DISK || f->area == RECT) {
        if (f->area == DISK) { /* r = R sqrt(u0), phi = 2 pi u1 */
            const double rr = f->radius * sqrt(u[0]), phi = 2.0 * LUMIS_PI * u[1];
            *y = mk(rr * cos(phi), rr * sin(phi), 0.0);
        } else {
            *y = mk((2.0 * u[0] - 1.0) * f->hx, (2.0 * u[1] - 1.0) * f->hy, 0.0);
        }
        *n = mk(0, 0, -1);
        *pdf_area = 1.0 / f->A;
        return 1;
    }
    if (f->area == SPHERE) { /* uniform on the sphere */
        const double z = 1.0 - 2.0 * u[0], rr = sqrt(fmax(0.0, 1.0 - z * z));
        const double phi = 2.0 * LUMIS_PI * u[1];
        *n = mk(rr * cos(phi), rr * sin(phi), z);
        *y = mul(*n, f->radius);
        *pdf_area = 1.0 / f->A;
        return 1;
    }
    double w[6];
    const double sum = face_weights(f, xl, w);
    if (!(sum > 0.0)) return 0;
    const int faces = f->area == BOX ? 6 : 3;
    int last = faces - 1, k = 0;
    while (w[last] == 0.0) last--; /* sum > 0: some face has weight */
    double acc = 0.0, t = u[0] * sum;
    while (k < last && (w[k] == 0.0 || t >= acc + w[k])) acc += w[k++];
    u[0] = fmin(fmax((t - acc) / w[k], 0.0), 0x1.fffffffffffffp-1); /* reused within the face */
    const double a = 2.0 * u[0] - 1.0, b = 2.0 * u[1] - 1.0;
    double face_area;
    if (f->area == BOX) {
        const double sgn = k % 2 ? -1.0 : 1.0;
        if (k / 2 == 0) {
            *y = mk(sgn * f->hx, a * f->hy, b * f->hz);
            *n = mk(sgn, 0, 0);
            face_area = 4.0 * f->hy * f->hz;
        } else if (k / 2 == 1) {
            *y = mk(a * f->hx, sgn * f->hy, b * f->hz);
            *n = mk(0, sgn, 0);
            face_area = 4.0 * f->hx * f->hz;
        } else {
            *y = mk(a * f->hx, b * f->hy, sgn * f->hz);
            *n = mk(0, 0, sgn);
            face_area = 4.0 * f->hx * f->hy;
        }
    } else if (k < 2) { /* a cap: uniform on the disk */
        const double sgn = k ? -1.0 : 1.0, rr = f->radius * sqrt(u[0]), phi = 2.0 * LUMIS_PI * u[1];
        *y = mk(rr * cos(phi), rr * sin(phi), sgn * f->hz);
        *n = mk(0, 0, sgn);
        face_area = LUMIS_PI * f->radius * f->radius;
    } else { /* the side: uniform in angle and height */
        const double phi = 2.0 * LUMIS_PI * u[0];
        *n = mk(cos(phi), sin(phi), 0.0);
        *y = mk(f->radius * n->x, f->radius * n->y, b * f->hz);
        face_area = 4.0 * LUMIS_PI * f->radius * f->hz;
    }
    *pdf_area = w[k] / (sum * face_area);
    return 1;
}

/* The density per unit area opening_sample gives the point of normal n (a face's, for the
 * shading point xl). */
static double opening_pdf_area(const fixture *f, v3 xl, v3 n)
{
    if (f->area != BOX && f->area != CYLINDER) return 1.0 / f->A;
    double w[6];
    const double sum = face_weights(f, xl, w);
    if (!(sum > 0.0)) return 0.0;
    if (f->area == BOX) {
        const int axis = fabs(n.x) > 0.5 ? 0 : fabs(n.y) > 0.5 ? 1 : 2;
        const double nc = axis == 0 ? n.x : axis == 1 ? n.y : n.z;
        const int k = 2 * axis + (nc < 0.0);
        const double face_area = axis == 0   ? 4.0 * f->hy * f->hz
                                 : axis == 1 ? 4.0 * f->hx * f->hz
                                             : 4.0 * f->hx * f->hy;
        return w[k] / (sum * face_area);
    }
    if (fabs(n.z) > 0.5) return w[n.z > 0.0 ? 0 : 1] / (sum * LUMIS_PI * f->radius * f->radius);
    return w[2] / (sum * 4.0 * LUMIS_PI * f->radius * f->hz);
}

/* Where the ray o + s w (local) first enters the opening from outside, from its front: *s
 * and the surface's outward normal there. */
static int opening_hit(const fixture *f, v3 o, v3 w, double *s, v3 *n)
{
    if (f->area == DISK || f->area == RECT) {
        /* the front: the side the aim (-z) points to, so the ray travels towards +z */
        if (!(w.z > 0.0) || !(o.z < 0.0)) return 0;
        const double t = -o.z / w.z, x = o.x + t * w.x, y = o.y + t * w.y;
        const int inside = f->area == DISK ? x * x + y * y <= f->radius * f->radius
                                           : fabs(x) <= f->hx && fabs(y) <= f->hy;
        if (!inside) return 0;
        *s = t;
        *n = mk(0, 0, -1);
        return 1;
    }
    if (f->area == SPHERE) {
        const double b = dot(o, w), c = dot(o, o) - f->radius * f->radius, disc = b * b - c;
        if (!(c > 0.0) || !(disc >= 0.0)) return 0; /* from outside only */
        const double t = -b - sqrt(disc);
        if (!(t > 0.0)) return 0;
        *s = t;
        *n = mul(add(o, mul(w, t)), 1.0 / f->radius);
        return 1;
    }
    if (f->area == BOX) { /* slabs: the entry is the largest near distance */
        const double oo[3] = {o.x, o.y, o.z}, ww[3] = {w.x, w.y, w.z},
                     hh[3] = {f->hx, f->hy, f->hz};
        double tin = -INFINITY, tout = INFINITY;
        int axis = -1;
        for (int k = 0; k < 3; k++) {
            if (ww[k] == 0.0) {
                if (fabs(oo[k]) > hh[k]) return 0;
                continue;
            }
            double t0 = (-hh[k] - oo[k]) / ww[k], t1 = (hh[k] - oo[k]) / ww[k];
            if (t0 > t1) {
                const double tmp = t0;
                t0 = t1;
                t1 = tmp;
            }
            if (t0 > tin) tin = t0, axis = k;
            if (t1 < tout) tout = t1;
        }
        if (axis < 0 || !(tin > 0.0) || !(tin <= tout)) return 0;
        *s = tin;
        const double sgn = ww[axis] > 0.0 ? -1.0 : 1.0;
        *n = mk(axis == 0 ? sgn : 0, axis == 1 ? sgn : 0, axis == 2 ? sgn : 0);
        return 1;
    }
    /* CYLINDER: the side (x^2 + y^2 = r^2, |z| <= hz) or a cap, whichever comes first */
    double best = INFINITY;
    v3 bn = mk(0, 0, 0);
    const double a = w.x * w.x + w.y * w.y, b = o.x * w.x + o.y * w.y,
                 c = o.x * o.x + o.y * o.y - f->radius * f->radius;
    if (a > 0.0 && c > 0.0 && b * b - a * c >= 0.0) {
        const double t = (-b - sqrt(b * b - a * c)) / a, z = o.z + t * w.z;
        if (t > 0.0 && fabs(z) <= f->hz) {
            best = t;
            bn = mk((o.x + t * w.x) / f->radius, (o.y + t * w.y) / f->radius, 0.0);
        }
    }
    for (int cap = 0; cap < 2; cap++) {
        const double zc = cap ? -f->hz : f->hz, sgn = cap ? -1.0 : 1.0;
        if (!(sgn * o.z > f->hz) || !(sgn * w.z < 0.0)) continue; /* outside, heading in */
        const double t = (zc - o.z) / w.z, x = o.x + t * w.x, y = o.y + t * w.y;
        if (t > 0.0 && t < best && x * x + y * y <= f->radius * f->radius) {
            best = t;
            bn = mk(0, 0, sgn);
        }
    }
    if (!isfinite(best)) return 0;
    *s = best;
    *n = bn;
    return 1;
}

static v3 shade(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    const lumis_render_desc *d = c->d;
    const photometric_state *st = c->state;
    lumis__stream *seq = v->seq;
    /* the light samples' points (one dimension for every fixture), the BSDF samples' */
    const uint32_t dl = seq_take(seq), db = seq_take_n(seq, 2);
    /* the near-field fixtures' light fields: a dimension of their own (none without one) */
    const uint32_t dn = st->capacity > 0 ? seq_take(seq) : 0;
    const shading_frame fr = shading_frame_at(h, dir);
    const v3 t = fr.t, b = fr.b, n = fr.n, org = fr.org;
    const lumis_vec3 wo = fr.wo;
    const lumis_bsdf *m = &h->prim->material;
    const estimator_use use = estimator_use_of(d);
    v3 L = mk(0, 0, 0);
    packet p;
    p.rays.n = p.flushed = 0;
    const uint32_t total = (uint32_t)(st->count * st->nl);
    for (int q = 0; q < st->count; q++) {
        const fixture *f = &st->f[q];
        const v3 centre = mk(f->t[0], f->t[1], f->t[2]);
        const v3 xl = to_local(f, sub(h->p, centre)); /* the surface point, fixture's frame */
        /* a near-field fixture: the field's share at this distance, its samples (found by
         * light sampling alone, as a point is) */
        const double wn = f->lf ? lumis_photometric_near_weight(f->rep, sqrt(dot(xl, xl))) : 0.0;
        if (wn > 0.0)
            near_field_samples(c, f, wn, h, &fr, seq, dn, q, st->capacity, v->scratch, &p, &L);
        /* a point is found by its light sample alone, whatever the estimator */
        const int nl = f->area ? (use.light ? st->nl : 0) : st->nl;
        for (int k = 0; k < nl; k++) {
            double u[2] = {0.5, 0.5}, pdf_area = 0.0;
            seq_2d(seq, dl, (uint32_t)(q * st->nl + k), total, u);
            v3 yl = mk(0, 0, 0), nrm = mk(0, 0, -1);
            if (f->area && !opening_sample(f, xl, u, &yl, &nrm, &pdf_area)) continue;
            const v3 pl = add(to_world(f, yl.x, yl.y, yl.z), centre);
            /* the geometry from the surface point itself; the shadow ray from the lifted
             * origin (its lift would otherwise bias d^2 by about lift / d) */
            const v3 w = sub(pl, h->p), ws = sub(pl, org);
            const double d2 = dot(w, w), dist = sqrt(d2), dist_s = sqrt(dot(ws, ws));
            if (!(dist > 0.0) || !(dist_s > 0.0)) continue;
            const v3 wi = mul(w, 1.0 / dist);
            const double cos_s = dot(wi, n);
            if (!(cos_s > 0.0)) continue;
            const v3 el = to_local(f, mul(wi, -1.0)); /* from the fixture to the point */
            double weight = 1.0, I;
            const lumis_vec3 wil = tof(mk(dot(wi, t), dot(wi, b), cos_s));
            if (f->area) { /* L cos_l / pdf_area: a flat opening's I / (A cos_l) x cos_l x A */
                const double cos_l = dot(el, nrm);
                if (!(cos_l > 0.0)) continue;
                I = radiance(f, el, nrm) * cos_l / pdf_area;
                if (use.mis && st->nb > 0)
                    weight = mis_weight(st->nl, pdf_area * d2 / cos_l, st->nb,
                                        lumis_bsdf_pdf(m, wo, wil), d->power_heuristic);
            } else {
                I = point_intensity(f, el, wn);
            }
            if (!(I > 0.0)) continue;
            const lumis_rgb fb = lumis_bsdf_eval(m, wo, wil);
            if (fb.r == 0.0f && fb.g == 0.0f && fb.b == 0.0f) continue;
            /* E = I cos_s / d^2 for a point; for an opening the area pdf cancels the
             * radiance's 1 / A_proj and cos_l: the same expression at the sampled point */
            const double k2 = weight * I * cos_s / (d2 * st->nl);
            packet_push(&p, org, mul(ws, 1.0 / dist_s), (float)(dist_s * (1.0 - 1e-4)),
                        mk(fb.r * k2, fb.g * k2, fb.b * k2));
            if (p.rays.n == PACKET) packet_flush(c->scene, d, &p, &L);
        }
        if (!f->area || !use.bsdf) continue;
        const v3 ol = to_local(f, sub(org, centre));
        for (int k = 0; k < st->nb; k++) { /* BSDF samples that find the opening */
            double u[3];
            seq_bsdf(seq, m, db, (uint32_t)(q * st->nb + k), (uint32_t)(st->count * st->nb), u);
            const lumis_bsdf_sample bs = lumis_bsdf_sample_wi(m, wo, u[0], u[1], u[2]);
            if (!(bs.pdf > 0.0f)) continue;
            const v3 wi = norm(add(add(mul(t, bs.wi.x), mul(b, bs.wi.y)), mul(n, bs.wi.z)));
            double s;
            v3 nrm;
            const v3 wl = to_local(f, wi);
            if (!opening_hit(f, ol, wl, &s, &nrm)) continue;
            const v3 el = mul(wl, -1.0); /* emitted back along the ray */
            const double cos_l = dot(el, nrm), Le = radiance(f, el, nrm);
            if (!(Le > 0.0) || !(cos_l > 0.0)) continue;
            double weight = 1.0;
            if (use.mis && st->nl > 0)
                weight =
                    mis_weight(st->nb, bs.pdf, st->nl, opening_pdf_area(f, xl, nrm) * s * s / cos_l,
                               d->power_heuristic);
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

/* The fixtures alone: points, or openings combined with the BSDF's samples; paths too. */
static void inputs(const lumis_lighting *l, unsigned *needs, unsigned *takes)
{
    (void)l;
    *needs = LUMIS__IN_PHOTOMETRIC;
    *takes = LUMIS__IN_EST_LIGHT | LUMIS__IN_EST_BSDF | LUMIS__IN_POWER | LUMIS__IN_LIGHT_SAMPLES |
             LUMIS__IN_BSDF_SAMPLES | LUMIS__IN_BOUNCES;
}

static void release(void *state)
{
    photometric_state *st = state;
    for (int q = 0; st && st->f && q < st->count; q++) lumis_photometric_destroy(st->f[q].residual);
    if (st) free(st->f);
    free(st);
}

/* A thread's buffer of light-field samples (one sample when no fixture has a field). */
static void *thread_begin(const void *state)
{
    const photometric_state *st = state;
    photometric_scratch *sc = calloc(1, sizeof *sc);
    if (sc && !(sc->s = malloc(sizeof *sc->s * (size_t)(st->capacity > 0 ? st->capacity : 1)))) {
        free(sc);
        sc = NULL;
    }
    return sc;
}

static void thread_end(void *scratch, double *light_samples)
{
    photometric_scratch *sc = scratch;
    if (!sc) return;
    *light_samples += sc->samples;
    free(sc->s);
    free(sc);
}

static lumis_status prepare(const lumis_scene *scene, const lumis_render_desc *d, void **state)
{
    (void)scene;
    const lumis_photometric_lighting *pl = d->lighting.photometric;
    if (!pl->instances || pl->count < 1 || pl->count > 100000)
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.photometric: 1 to 100000 instances");
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
        const double W = info.width, Ln = info.length, Hh = info.height;
        f->radius = 0.5 * W;
        f->hx = 0.5 * Ln;
        f->hy = 0.5 * W;
        f->hz = 0.5 * Hh;
        int ok = 1;
        if (in->area) switch (info.shape) {
            case LUMIS_SHAPE_DISK:
                f->area = DISK;
                f->A = LUMIS_PI * f->radius * f->radius;
                ok = W > 0;
                break;
            case LUMIS_SHAPE_RECTANGLE:
                f->area = RECT;
                f->A = Ln * W;
                ok = W > 0 && Ln > 0;
                break;
            case LUMIS_SHAPE_BOX:
                f->area = BOX;
                f->A = 2.0 * (Ln * W + Ln * Hh + W * Hh);
                ok = W > 0 && Ln > 0 && Hh > 0;
                break;
            case LUMIS_SHAPE_CYLINDER:
                f->area = CYLINDER;
                f->A = 2.0 * LUMIS_PI * f->radius * f->radius + LUMIS_PI * W * Hh;
                ok = W > 0 && Hh > 0;
                break;
            case LUMIS_SHAPE_SPHERE:
                f->area = SPHERE;
                f->A = 4.0 * LUMIS_PI * f->radius * f->radius;
                ok = W > 0;
                break;
            default:
                ok = 0;
            }
        if (!ok || !isfinite(f->A)) /* not quietly a point */
            return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "render: photometric fixture %d: its file's luminous shape is "
                               "\"%s\"%s: the opening (area) model takes a disk, a rectangle, a "
                               "box, a cylinder or a sphere of non-zero size; render it as a "
                               "point (no area)",
                               q, lumis_photometric_shape_name(info.shape),
                               info.shape == LUMIS_SHAPE_POINT || info.shape == LUMIS_SHAPE_OTHER
                                   ? ""
                                   : " with a zero size");
        st->any_area |= f->area != 0;
        if (!in->light_field && !in->light_field_report) continue;
        /* the near-field fixture: its field and report made from this table, a point */
        const lumis_photometric_light_field_report *r = in->light_field_report;
        const char *why =
            !in->light_field || !r ? "needs both a light field and its report"
            : in->area             ? "is a point with a light field near it, not an opening (area)"
            : info.type != LUMIS_PHOTOMETRIC_C
                ? "needs a type C table (its residual beyond the field's cone)"
            : !(fabs(r->flux - info.flux) <= 1e-9 * fabs(info.flux))
                ? "has a report whose flux is not the table's (made from another file?)"
            : !(r->near_until >= 0.0 && r->near_until <= r->far_from && isfinite(r->far_from) &&
                r->ramp_from_deg >= 0.0 && r->ramp_from_deg <= r->max_angle_deg &&
                r->max_angle_deg < 90.0)
                ? "has a report whose near_until, far_from (0 <= near_until <= far_from, "
                  "finite) or cone (0 <= ramp_from_deg <= max_angle_deg < 90) is wrong"
                : NULL;
        if (why)
            return lumis__fail(
                &d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                "render: photometric fixture %d: light_field: the near-field fixture "
                "%s",
                q, why);
        f->lf = in->light_field;
        f->rep = r;
        if (lumis_photometric_beyond(f->p, r->ramp_from_deg, r->max_angle_deg, &d->errors,
                                     &f->residual) != LUMIS_OK)
            return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "render: photometric fixture %d: light_field: no residual table", q);
        const int cap = lumis_luminaire_capacity(f->lf, NEAR_BUDGET);
        if (cap > st->capacity) st->capacity = cap;
    }
    return LUMIS_OK;
}

const lumis__light_kind lumis__light_photometric = {
    "photometric fixtures", inputs,     prepare, release, NULL, NULL, NULL,
    thread_begin,           thread_end, shade,   NULL,    NULL,
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
