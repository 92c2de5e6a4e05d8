/* The evaluation renderer: an Embree scene (meshes used more than once are instanced), a
 * pinhole camera, and direct illumination from the environment map with light, BSDF or
 * multiple importance sampling; optionally path tracing on top of it.
 * Determinism: sample k of pixel p draws from PCG32 stream p started at a hash of (seed, k),
 * so the image depends on the seed and the sample count, never on how tiles are spread
 * over threads or samples over passes. */
#include "lumis/render.h"
#include "lumis/rng.h"

#include "../core/internal.h"
#include "internal.h"
#include "camera.h"
#include "packet.h"
#include "scene.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- shading ------------------------------------------------------------------------- */

static double mis_weight(double nf, double pf, double ng, double pg, int power)
{
    double a = nf * pf, b = ng * pg;
    if (power) {
        a *= a;
        b *= b;
    }
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

typedef struct ctx {
    const lumis_scene *scene;
    const lumis_render_desc *d;
    int nl, nb;
    int fused; /* the sampler draws from d->env: radiance and pdf from one lookup */
    int sets;  /* light sets interleaved (light_set only) */
    const struct light_soa *soa; /* their lights, as the shading loop reads them */
    const struct lum_inst *lum;  /* the placed luminaires (luminaires only) */
    /* The global strategy's draws for camera samples global_k0 ...: camera sample k,
     * instance i at slot (k - global_k0) * instances + i, global_stride samples a slot. */
    const lumis_luminaire_sample *global;
    const int *global_n;
    int global_k0, global_stride;
} ctx;

/* The lights of one set that light_kinds selects, in float arrays: the shading loop reads
 * six floats a light and nothing else. */
typedef struct light_soa {
    int count;
    float *x, *y, *z, *r, *g, *b;
} light_soa;

/* ---- the light interface: a light set ---------------------------------------------------- */

enum { PACKET = LUMIS__PACKET };

/* Shadow rays of one shading point, traced PACKET at a time (packet.h); a lane's
 * contribution is added when its ray is unoccluded. */
typedef struct packet {
    lumis__packet rays;
    v3 contrib[PACKET];
    int flushed; /* lanes traced in earlier packets */
} packet;

static void packet_trace(const lumis_scene *s, const lumis_render_desc *d, packet *p)
{
    lumis__packet_trace(s->rtc, d->shadow_ray, d->shadow_ray_user, &p->rays);
}

static void packet_flush(const lumis_scene *s, const lumis_render_desc *d, packet *p, v3 *L)
{
    if (p->rays.n == 0) return;
    packet_trace(s, d, p);
    for (int k = 0; k < p->rays.n; k++)
        if (p->rays.r.tfar[k] >= 0.0f) *L = add(*L, p->contrib[k]);
    p->flushed += p->rays.n;
    p->rays.n = 0;
}

static void packet_push(packet *p, v3 o, v3 d, float tfar, v3 contrib)
{
    const float of[3] = {(float)o.x, (float)o.y, (float)o.z},
                df[3] = {(float)d.x, (float)d.y, (float)d.z};
    p->contrib[p->rays.n] = contrib;
    lumis__packet_push(&p->rays, of, df, tfar);
}

/* Every light of the pixel's set: f cos V power, one shadow ray each.  A Lambertian surface
 * needs no BSDF evaluation per light (f = albedo / pi). */
static v3 shade_light_set(const ctx *c, const hit *h, v3 dir, int px, int py, double *shadow_rays)
{
    const lumis_render_desc *d = c->d;
    const light_soa *ls = &c->soa[lumis_light_set_interleave_index(c->sets, px, py)];
    v3 t, b, n = h->n;
    basis(n, &t, &b);
    v3 wow = mul(dir, -1.0);
    lumis_vec3 wo = tof(mk(dot(wow, t), dot(wow, b), dot(wow, n)));
    const lumis_bsdf *m = &h->prim->material;
    const int lambert = m->type == LUMIS_BSDF_LAMBERT;
    const float kr = m->diffuse.r * (float)(1.0 / LUMIS_PI),
                kg = m->diffuse.g * (float)(1.0 / LUMIS_PI),
                kb = m->diffuse.b * (float)(1.0 / LUMIS_PI);
    const v3 o = add(h->p, mul(n, 1e-4 * fmax(1.0, sqrt(dot(h->p, h->p)))));
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

/* splitmix64's finaliser: decorrelates (seed, sample) pairs into PCG start states. */
static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static const char *const visibility_names[] = {"exact", "approx", "none", "shadowmap"};
static const char *const sequence_names[] = {"pcg", "halton"};

const char *lumis_visibility_name(lumis_visibility v)
{
    return (unsigned)v < LUMIS_VISIBILITY_COUNT ? visibility_names[v] : "unknown";
}

lumis_status lumis_visibility_from_name(const char *name, lumis_visibility *out)
{
    for (int k = 0; name && out && k < LUMIS_VISIBILITY_COUNT; k++)
        if (strcmp(name, visibility_names[k]) == 0) {
            *out = (lumis_visibility)k;
            return LUMIS_OK;
        }
    return LUMIS_ERR_INVALID_ARGUMENT;
}

const char *lumis_sequence_name(lumis_sequence q)
{
    return (unsigned)q < LUMIS_SEQUENCE_COUNT ? sequence_names[q] : "unknown";
}

lumis_status lumis_sequence_from_name(const char *name, lumis_sequence *out)
{
    for (int k = 0; name && out && k < LUMIS_SEQUENCE_COUNT; k++)
        if (strcmp(name, sequence_names[k]) == 0) {
            *out = (lumis_sequence)k;
            return LUMIS_OK;
        }
    return LUMIS_ERR_INVALID_ARGUMENT;
}

/* ---- the light interface: light-field luminaires ------------------------------------------ */

/* One placed luminaire as the shading loop reads it. */
typedef struct lum_inst {
    const lumis_luminaire *lum;
    double r[9], t[3], scale, inv_scale, intensity;
    lumis_luminaire_query query;
    int capacity;     /* samples lumis_luminaire_sample_point may return */
    int grid[2];      /* W, H */
    int span;         /* cells of the visibility grid a basis function covers per axis */
    int cells[2];     /* cells of the visibility grid per axis: W + span - 1, ... */
    double cell0[2];  /* centre of cell (0, 0) on U, luminaire frame */
    double cell_h[2]; /* cell size */
    double weight[3]; /* the share of Phi's integral over each covered cell, per axis */
    v3 *cell_world;   /* the cells' centres in the world (approximate visibility) */
    float *smap;      /* shadow maps: per cell n x n distances to the nearest hit, over
                         directions (x / z, y / z) in [-tmax, tmax]^2 of the local frame */
    int smap_n;
    double smap_t;
} lum_inst;

/* Per-thread buffers of the luminaire kind (no allocation per shading point). */
typedef struct lum_scratch {
    lumis_luminaire_sample *s; /* capacity samples */
    float *vis;                /* visibility per cell (approximate visibility) */
    unsigned *stamp;           /* the point a cell's visibility belongs to */
    unsigned point;
    size_t cells;   /* entries of vis and stamp */
    double samples; /* luminaire samples evaluated by this thread */
} lum_scratch;

static v3 rot_apply(const double r[9], v3 a)
{
    return mk(r[0] * a.x + r[1] * a.y + r[2] * a.z, r[3] * a.x + r[4] * a.y + r[5] * a.z,
              r[6] * a.x + r[7] * a.y + r[8] * a.z);
}

static v3 rot_apply_t(const double r[9], v3 a)
{
    return mk(r[0] * a.x + r[3] * a.y + r[6] * a.z, r[1] * a.x + r[4] * a.y + r[7] * a.z,
              r[2] * a.x + r[5] * a.y + r[8] * a.z);
}

/* Mean visibility v_m(p) of image m = (a, b) (Lu et al. 6.2): rays from o to the centres of
 * the cells Phi_m covers, each weighted by its share of Phi_m's integral; a cell already
 * traced for this point is not traced again. */
static double lum_visibility(const ctx *c, const lum_inst *li, lum_scratch *sc, int m, v3 o,
                             double *shadow_rays)
{
    const int a = m % li->grid[0], b = m / li->grid[0];
    packet p;
    p.rays.n = p.flushed = 0;
    int cell[9];
    for (int j = 0; j < li->span; j++)
        for (int i = 0; i < li->span; i++) {
            const int id = (b + j) * li->cells[0] + (a + i);
            if (sc->stamp[id] == sc->point) continue;
            sc->stamp[id] = sc->point;
            const v3 d = sub(li->cell_world[id], o);
            const double len = sqrt(dot(d, d));
            if (!(len > 0.0)) {
                sc->vis[id] = 1.0f;
                continue;
            }
            cell[p.rays.n] = id;
            packet_push(&p, o, mul(d, 1.0 / len), (float)(len * (1.0 - 1e-4)), mk(0, 0, 0));
        }
    if (p.rays.n > 0) {
        packet_trace(c->scene, c->d, &p);
        for (int k = 0; k < p.rays.n; k++)
            sc->vis[cell[k]] = p.rays.r.tfar[k] >= 0.0f ? 1.0f : 0.0f;
        *shadow_rays += p.rays.n;
    }
    double v = 0.0;
    for (int j = 0; j < li->span; j++)
        for (int i = 0; i < li->span; i++)
            v += li->weight[i] * li->weight[j] * sc->vis[(b + j) * li->cells[0] + (a + i)];
    return v;
}

/* Visibility of x from the centre of cell (ci, cj), read from its shadow map: 2 x 2
 * percentage-closer filtering, a depth bias of 1 % plus four texels' slope. */
static double smap_visibility(const lum_inst *li, int ci, int cj, v3 x)
{
    const v3 d = sub(x, li->cell_world[(size_t)cj * (size_t)li->cells[0] + (size_t)ci]);
    const v3 dl = rot_apply_t(li->r, d);
    if (!(dl.z > 0.0)) return 1.0; /* behind U: no light reaches it anyway */
    const int n = li->smap_n;
    const double t = li->smap_t, fx = (dl.x / dl.z + t) / (2.0 * t) * n - 0.5,
                 fy = (dl.y / dl.z + t) / (2.0 * t) * n - 0.5;
    if (!(fx > -0.5 && fx < n - 0.5 && fy > -0.5 && fy < n - 0.5)) return 1.0;
    const double dist = sqrt(dot(d, d)), bias = dist * (0.01 + 4.0 * t / n);
    const int x0 = (int)floor(fx), y0 = (int)floor(fy);
    const double ax = fx - x0, ay = fy - y0;
    const float *map =
        li->smap + ((size_t)cj * (size_t)li->cells[0] + (size_t)ci) * (size_t)n * (size_t)n;
    double v = 0.0;
    for (int q = 0; q < 4; q++) {
        const int i = x0 + (q & 1), j = y0 + (q >> 1);
        const int ic = i < 0 ? 0 : i >= n ? n - 1 : i, jc = j < 0 ? 0 : j >= n ? n - 1 : j;
        const double w = ((q & 1) ? ax : 1.0 - ax) * ((q >> 1) ? ay : 1.0 - ay);
        if (dist <= (double)map[(size_t)jc * (size_t)n + (size_t)ic] + bias) v += w;
    }
    return v;
}

/* Renders every cell's shadow map: n x n rays from its centre over the directions that
 * reach the images (the largest |s - u| / delta over the images and the cells). */
static lumis_status lum_shadow_maps(const lumis_scene *scene, lum_inst *li, int n, int threads)
{
    lumis_luminaire_desc ld;
    lumis_luminaire_get_desc(li->lum, &ld);
    double t = 0.0;
    for (int a = 0; a < 2; a++) {
        const double u0 = li->cell0[a] - 0.5 * li->cell_h[a],
                     u1 = li->cell0[a] + (li->cells[a] - 0.5) * li->cell_h[a];
        const double s0 = ld.image_origin[a], s1 = ld.image_origin[a] + ld.image_size[a];
        t = fmax(t, fmax(fabs(s1 - u0), fabs(s0 - u1)) / ld.delta);
    }
    const size_t cells = (size_t)li->cells[0] * (size_t)li->cells[1];
    li->smap_n = n;
    li->smap_t = t;
    if (!(li->smap = malloc(cells * (size_t)n * (size_t)n * sizeof *li->smap)))
        return LUMIS_ERR_OUT_OF_MEMORY;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (int c = 0; c < (int)cells; c++) {
        const v3 o = li->cell_world[c];
        float *map = li->smap + (size_t)c * (size_t)n * (size_t)n;
        for (int j = 0; j < n; j++)
            for (int i = 0; i < n; i++) {
                const v3 dl = mk(-t + (i + 0.5) * 2.0 * t / n, -t + (j + 0.5) * 2.0 * t / n, 1.0);
                const v3 dir = norm(rot_apply(li->r, dl));
                hit h;
                map[(size_t)j * (size_t)n + (size_t)i] =
                    intersect(scene, o, dir, &h) ? (float)sqrt(dot(sub(h.p, o), sub(h.p, o)))
                                                 : INFINITY;
            }
    }
    return LUMIS_OK;
}

/* The luminaire samplers' random numbers (lumis_luminaire_query.fill).  PCG32: the pixel's
 * generator.  Halton: sample j of camera sample k at index k capacity + 1 + j of
 * dimensions 0 and 1, rotated per pixel (Cranley-Patterson). */
static void fill_pcg(void *rng, double *u, int n)
{
    lumis_pcg32_fill_doubles(rng, u, (size_t)n);
}

typedef struct halton_pairs {
    uint64_t next; /* index of the next pair */
    double r0, r1; /* the pixel's rotation */
} halton_pairs;

static void fill_halton(void *state, double *u, int n)
{
    halton_pairs *h = state;
    for (int j = 0; j < n; j += 2, h->next++) {
        const double u0 = lumis_halton(0, h->next) + h->r0, u1 = lumis_halton(1, h->next) + h->r1;
        u[j] = u0 >= 1.0 ? u0 - 1.0 : u0;
        u[j + 1] = u1 >= 1.0 ? u1 - 1.0 : u1;
    }
}

/* Every placed luminaire at h: its samples (lumis_luminaire_sample_point) times the BSDF and
 * the cosine, each weighted as the sample says (1 / (K_m pdf_omega)), times its visibility. */
static v3 shade_luminaires(const ctx *c, const hit *h, v3 dir, int px, int py, int k,
                           lumis_pcg32 *rng, lum_scratch *sc, double *shadow_rays)
{
    const lumis_render_desc *d = c->d;
    const lumis_luminaire_lighting *ll = d->luminaires;
    v3 t, b, n = h->n;
    basis(n, &t, &b);
    v3 wow = mul(dir, -1.0);
    lumis_vec3 wo = tof(mk(dot(wow, t), dot(wow, b), dot(wow, n)));
    const lumis_bsdf *mat = &h->prim->material;
    const v3 o = add(h->p, mul(n, 1e-4 * fmax(1.0, sqrt(dot(h->p, h->p)))));
    v3 L = mk(0, 0, 0);
    for (int i = 0; i < ll->count; i++) {
        const lum_inst *li = &c->lum[i];
        lumis_luminaire_query q = li->query;
        const v3 pl =
            mul(rot_apply_t(li->r, sub(h->p, mk(li->t[0], li->t[1], li->t[2]))), li->inv_scale);
        q.p = tof(pl);
        if (!(q.p.z > 0.0f)) continue; /* behind U: no light */
        int count = 0;
        halton_pairs hp;
        if (q.strategy == LUMIS_LUM_GLOBAL) {
            /* The same points on S for every shading point: drawn once per camera sample
             * (global_draws), finished here. */
            const size_t slot = (size_t)(k - c->global_k0) * (size_t)ll->count + (size_t)i;
            if (lumis_luminaire_global_finish(li->lum, q.p,
                                              c->global + slot * (size_t)c->global_stride,
                                              c->global_n[slot], sc->s, &count) != LUMIS_OK)
                continue;
        } else if (ll->sequence == LUMIS_SEQUENCE_HALTON) {
            lumis_pcg32 g; /* a rotation per pixel and instance, the same for every k */
            lumis_pcg32_seed(&g, mix64(d->seed ^ 0x51ed27u ^ ((uint64_t)i << 40)),
                             (uint64_t)py * 0x10000u + (uint64_t)px);
            hp.r0 = lumis_pcg32_double(&g);
            hp.r1 = lumis_pcg32_double(&g);
            hp.next = (uint64_t)k * (uint64_t)li->capacity + 1;
            q.fill = fill_halton;
            q.fill_ctx = &hp;
        } else {
            /* Only the numbers the point's samples use (there are often far fewer samples
             * than the capacity reserved for the worst point). */
            q.fill = fill_pcg;
            q.fill_ctx = rng;
        }
        if (q.strategy != LUMIS_LUM_GLOBAL &&
            lumis_luminaire_sample_point(li->lum, &q, NULL, li->capacity, sc->s, &count) !=
                LUMIS_OK)
            continue;
        sc->samples += count;
        sc->point++;
        if (sc->point == 0) { /* the stamps wrapped: forget them all */
            memset(sc->stamp, 0, sizeof *sc->stamp * sc->cells);
            sc->point = 1;
        }
        packet p;
        p.rays.n = p.flushed = 0;
        int vis_image = -1;
        double vis = 1.0;
        for (int j = 0; j < count; j++) {
            const lumis_luminaire_sample *s = &sc->s[j];
            const v3 wi = rot_apply(li->r, mk(s->dir.x, s->dir.y, s->dir.z));
            const double cosn = dot(wi, n);
            /* No light (a sample where Phi_m(u) = 0, or behind the surface): no shadow ray. */
            if (!(cosn > 0.0) || !(s->weight > 0.0f)) continue;
            if (s->radiance.r == 0.0f && s->radiance.g == 0.0f && s->radiance.b == 0.0f) continue;
            lumis_rgb f = lumis_bsdf_eval(mat, wo, tof(mk(dot(wi, t), dot(wi, b), cosn)));
            if (f.r == 0.0f && f.g == 0.0f && f.b == 0.0f) continue;
            const double kk = cosn * s->weight * li->intensity;
            v3 contrib =
                mk(f.r * s->radiance.r * kk, f.g * s->radiance.g * kk, f.b * s->radiance.b * kk);
            if (ll->visibility == LUMIS_VISIBILITY_NONE) {
                L = add(L, contrib);
            } else if (ll->visibility == LUMIS_VISIBILITY_APPROX) {
                if (s->image != vis_image) {
                    vis_image = s->image;
                    vis = lum_visibility(c, li, sc, s->image, o, shadow_rays);
                }
                L = add(L, mul(contrib, vis));
            } else if (ll->visibility == LUMIS_VISIBILITY_SHADOW_MAP) {
                if (s->image != vis_image) {
                    vis_image = s->image;
                    const int ga = s->image % li->grid[0], gb = s->image / li->grid[0];
                    vis = 0.0;
                    for (int jj = 0; jj < li->span; jj++)
                        for (int ii = 0; ii < li->span; ii++)
                            vis += li->weight[ii] * li->weight[jj] *
                                   smap_visibility(li, ga + ii, gb + jj, o);
                }
                L = add(L, mul(contrib, vis));
            } else {
                const float tfar = (float)((double)s->distance * li->scale * (1.0 - 1e-4));
                packet_push(&p, o, wi, tfar, contrib);
                if (p.rays.n == PACKET) packet_flush(c->scene, d, &p, &L);
            }
        }
        *shadow_rays += (double)(p.rays.n + p.flushed);
        packet_flush(c->scene, d, &p, &L);
    }
    return L;
}

/* Direct light from the environment reflected at h towards -dir. */
static v3 shade(const ctx *c, const hit *h, v3 dir, lumis_pcg32 *rng, double *shadow_rays)
{
    const lumis_render_desc *d = c->d;
    v3 t, b, n = h->n, L = mk(0, 0, 0);
    basis(n, &t, &b);
    v3 wow = mul(dir, -1.0);
    lumis_vec3 wo = tof(mk(dot(wow, t), dot(wow, b), dot(wow, n)));
    const lumis_bsdf *m = &h->prim->material;
    double scale = 1e-4 * fmax(1.0, sqrt(dot(h->p, h->p)));
    v3 org = add(h->p, mul(n, scale));
    int use_light = d->estimator != LUMIS_ESTIMATOR_BSDF,
        use_bsdf = d->estimator != LUMIS_ESTIMATOR_LIGHT;
    int mis = d->estimator == LUMIS_ESTIMATOR_MIS;
    for (int k = 0; use_light && k < c->nl; k++) {
        double u1 = lumis_pcg32_double(rng), u2 = lumis_pcg32_double(rng);
        lumis_env_sample e = lumis_sampler_sample(d->sampler, u1, u2);
        v3 wi = fromf(e.dir);
        double cosn = dot(wi, n);
        if (!(cosn > 0.0) || !(e.pdf > 0.0f)) continue;
        lumis_vec3 wil = tof(mk(dot(wi, t), dot(wi, b), cosn));
        lumis_rgb f = lumis_bsdf_eval(m, wo, wil);
        if (f.r == 0.0f && f.g == 0.0f && f.b == 0.0f) continue;
        *shadow_rays += 1.0;
        if (occluded(c->scene, d, org, wi)) continue;
        double w =
            mis ? mis_weight(c->nl, e.pdf, c->nb, lumis_bsdf_pdf(m, wo, wil), d->power_heuristic)
                : 1.0;
        double k2 = w * cosn / ((double)e.pdf * c->nl);
        L = add(L, mk(f.r * e.radiance.r * k2, f.g * e.radiance.g * k2, f.b * e.radiance.b * k2));
    }
    for (int k = 0; use_bsdf && k < c->nb; k++) {
        double u0 = lumis_pcg32_double(rng), u1 = lumis_pcg32_double(rng),
               u2 = lumis_pcg32_double(rng);
        lumis_bsdf_sample bs = lumis_bsdf_sample_wi(m, wo, u0, u1, u2);
        if (!(bs.pdf > 0.0f)) continue;
        v3 wi = norm(add(add(mul(t, bs.wi.x), mul(b, bs.wi.y)), mul(n, bs.wi.z)));
        *shadow_rays += 1.0;
        if (occluded(c->scene, d, org, wi)) continue;
        lumis_rgb Le;
        double w = 1.0;
        if (mis && c->fused) { /* one pixel lookup for the radiance and the light pdf */
            float pl = lumis_sampler_pdf_radiance(d->sampler, tof(wi), &Le);
            w = mis_weight(c->nb, bs.pdf, c->nl, pl, d->power_heuristic);
        } else {
            Le = lumis_envmap_eval(d->env, tof(wi));
            if (mis)
                w = mis_weight(c->nb, bs.pdf, c->nl, lumis_sampler_pdf(d->sampler, tof(wi)),
                               d->power_heuristic);
        }
        double k2 = w / c->nb;
        L = add(L, mk(bs.weight.r * Le.r * k2, bs.weight.g * Le.g * k2, bs.weight.b * Le.b * k2));
    }
    return L;
}

/* ---- jobs: progressive accumulation ------------------------------------------------- */

enum { TILE = 16 };

struct lumis_render_job {
    const lumis_scene *scene;
    lumis_render_desc d;
    lumis_camera cam;
    cam_frame cf;
    double *sum;    /* 3 per pixel: the sum of every sample so far, in sample order */
    light_soa *soa; /* one per light set (light_set only) */
    int sets;
    lum_inst *lum;                     /* one per placed luminaire (luminaires only) */
    int lum_capacity;                  /* the most samples one instance returns */
    size_t lum_cells;                  /* the most visibility cells one instance has */
    lumis_luminaire_lighting lighting; /* a copy; d.luminaires points here */
    lumis_render_stats stats;
};

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

void lumis_render_job_destroy(lumis_render_job *job)
{
    if (!job) return;
    free(job->sum);
    soa_free(job->soa, job->sets);
    for (int i = 0; job->lum && i < job->lighting.count; i++) {
        free(job->lum[i].smap);
        free(job->lum[i].cell_world);
    }
    free(job->lum);
    free(job);
}

/* Checks the luminaire lighting and lays out one lum_inst per placed luminaire. */
static lumis_status lum_prepare(const lumis_render_desc *d, lumis_render_job *job)
{
    const lumis_luminaire_lighting *ll = d->luminaires;
    const lumis_error_sink *errors = &d->errors;
    if (ll->count < 0 || ll->count > 4096 || !ll->instances || ll->budget < 0 ||
        ll->budget > 65536 || ll->k_max < 0 || ll->depth < 0 ||
        (unsigned)ll->strategy >= LUMIS_LUM_STRATEGY_COUNT ||
        (unsigned)ll->search >= LUMIS_LUM_SEARCH_COUNT ||
        (unsigned)ll->visibility >= LUMIS_VISIBILITY_COUNT ||
        (unsigned)ll->sequence >= LUMIS_SEQUENCE_COUNT)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: luminaires: 1 to 4096 instances, budget 0 to 65536, "
                           "k_max and depth >= 0, and known strategy, search, visibility and "
                           "sequence");
    if (!(job->lum = calloc((size_t)ll->count, sizeof *job->lum)))
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "render: luminaires: out of memory");
    for (int i = 0; i < ll->count; i++) {
        const lumis_luminaire_instance *in = &ll->instances[i];
        lum_inst *li = &job->lum[i];
        lumis_rigid x = in->placement;
        int zero = 1;
        for (int k = 0; k < 9; k++) zero &= x.r[k] == 0.0;
        if (zero) memcpy(x.r, lumis_rigid_identity().r, sizeof x.r);
        const double scale = in->scale == 0.0 ? 1.0 : in->scale;
        const double intensity = in->intensity == 0.0f ? 1.0 : in->intensity;
        if (!in->luminaire || lumis_rigid_check(&x) != LUMIS_OK || !(scale > 0.0) ||
            !isfinite(scale) || !(intensity >= 0.0) || !isfinite(intensity) ||
            !isfinite(x.t[0] + x.t[1] + x.t[2]))
            return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "render: luminaire %d: needs a luminaire, a proper rotation, a "
                               "finite translation, scale > 0 and intensity >= 0",
                               i);
        li->lum = in->luminaire;
        memcpy(li->r, x.r, sizeof li->r);
        memcpy(li->t, x.t, sizeof li->t);
        li->scale = scale;
        li->inv_scale = 1.0 / scale;
        li->intensity = intensity;
        li->query.budget = ll->budget ? ll->budget : 32;
        li->query.k_max = ll->k_max;
        li->query.strategy = ll->strategy;
        li->query.search = ll->search;
        li->query.depth = ll->depth;
        li->capacity = lumis_luminaire_capacity(in->luminaire, li->query.budget);
        lumis_luminaire_desc ld;
        lumis_luminaire_get_desc(in->luminaire, &ld);
        /* The visibility grid: cells of the basis grid's size, so that Phi_m covers span x
         * span of them (2 x 2 quadratic, 3 x 3 B-spline); cell centres are the reference
         * light positions. */
        const double radius = lumis_luminaire_basis_radius(ld.basis);
        li->span = (int)(2.0 * radius + 0.5);
        for (int a = 0; a < 2; a++) {
            li->grid[a] = ld.grid[a];
            li->cells[a] = ld.grid[a] + li->span - 1;
            li->cell_h[a] = ld.grid_spacing[a];
            li->cell0[a] = ld.grid_origin[a] + (0.5 - radius) * ld.grid_spacing[a];
        }
        for (int c = 0; c < li->span; c++) { /* the integral of phi over cell c, midpoint rule */
            const int steps = 4096;
            double sum = 0.0;
            for (int q = 0; q < steps; q++)
                sum += lumis_luminaire_basis_eval(ld.basis, c - radius + (q + 0.5) / steps);
            li->weight[c] = sum / steps;
        }
        if (li->capacity > job->lum_capacity) job->lum_capacity = li->capacity;
        const size_t cells = (size_t)li->cells[0] * (size_t)li->cells[1];
        if (cells > job->lum_cells) job->lum_cells = cells;
        if (ll->visibility == LUMIS_VISIBILITY_APPROX ||
            ll->visibility == LUMIS_VISIBILITY_SHADOW_MAP) {
            if (!(li->cell_world = malloc(cells * sizeof *li->cell_world)))
                return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY,
                                   "render: luminaires: out of memory");
            for (int cj = 0; cj < li->cells[1]; cj++)
                for (int ci = 0; ci < li->cells[0]; ci++) {
                    const v3 local = mk(li->cell0[0] + ci * li->cell_h[0],
                                        li->cell0[1] + cj * li->cell_h[1], 0.0);
                    li->cell_world[(size_t)cj * (size_t)li->cells[0] + (size_t)ci] = add(
                        rot_apply(li->r, mul(local, li->scale)), mk(li->t[0], li->t[1], li->t[2]));
                }
        }
    }
    return LUMIS_OK;
}

lumis_status lumis_render_job_create(const lumis_scene *scene, const lumis_render_desc *d,
                                     lumis_render_job **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    const int lum_kind = d && d->luminaires && d->luminaires->count > 0;
    if (lum_kind && (d->light_set || d->max_bounces > 0))
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: luminaires light direct illumination alone (no light set, "
                           "max_bounces 0)");
    if (d && d->light_set && d->max_bounces > 0)
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: a light set lights direct illumination only (max_bounces "
                           "must be 0)");
    if (!scene || !d || (!d->env && !lum_kind) ||
        (!lum_kind && !d->light_set && d->estimator != LUMIS_ESTIMATOR_BSDF && !d->sampler) ||
        (unsigned)d->estimator > LUMIS_ESTIMATOR_BSDF || d->spp < 0 || d->light_samples < 0 ||
        d->bsdf_samples < 0 || d->max_bounces < 0 || d->max_bounces > 1024)
        return lumis__fail(d ? &d->errors : NULL, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: needs a scene, an envmap, a sampler (unless BSDF-only), "
                           "non-negative sample counts and 0 to 1024 bounces");
    cam_frame cf;
    lumis_status cst = lumis__camera_frame(d->camera, &d->errors, &cf);
    if (cst != LUMIS_OK) return cst;
    const lumis_camera cam = cf.cam;
    lumis_render_job *job = calloc(1, sizeof *job);
    if (job) job->sum = calloc(3 * (size_t)cam.width * (size_t)cam.height, sizeof(double));
    if (!job || !job->sum) {
        lumis_render_job_destroy(job);
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "render: %d x %d: out of memory",
                           cam.width, cam.height);
    }
    if (d->light_set &&
        !(job->soa = soa_make(d->light_set, d->light_kinds ? d->light_kinds : ~0u, &job->sets))) {
        lumis_render_job_destroy(job);
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "render: light set: out of memory");
    }
    if (lum_kind) {
        job->lighting = *d->luminaires; /* what destroy reads to free the shadow maps */
        lumis_status lst = lum_prepare(d, job);
        for (int i = 0;
             lst == LUMIS_OK && d->luminaires->visibility == LUMIS_VISIBILITY_SHADOW_MAP &&
             i < d->luminaires->count;
             i++)
            if ((lst = lum_shadow_maps(scene, &job->lum[i], 256,
                                       d->threads > 0 ? d->threads : omp_get_max_threads())) !=
                LUMIS_OK)
                lumis__fail(&d->errors, lst, "render: luminaire %d: shadow maps: out of memory", i);
        if (lst != LUMIS_OK) {
            lumis_render_job_destroy(job);
            return lst;
        }
    }
    job->scene = scene;
    job->d = *d;
    job->d.camera = NULL;                                 /* job->cam is the camera */
    job->d.luminaires = lum_kind ? &job->lighting : NULL; /* copied before lum_prepare */
    job->cam = cam;
    job->cf = cf;
    *out = job;
    return LUMIS_OK;
}

/* One camera sample: direct illumination at the first hit, and with max_bounces > 0 the
 * direct illumination at every further vertex of a BSDF-sampled path.  The environment
 * seen by a continuation ray is not added: the direct estimator at the vertex it left
 * already accounts for it, so each light path is counted once. */
static v3 trace_sample(const ctx *c, const lumis_render_job *job, v3 dir, int px, int py, int k,
                       lumis_pcg32 *rng, lum_scratch *sc, double *shadow, double *bounce)
{
    hit hh;
    if (!intersect(c->scene, job->cf.eye, dir, &hh)) {
        if (job->d.hide_environment || !job->d.env) return mk(0, 0, 0);
        lumis_rgb e = lumis_envmap_eval(job->d.env, tof(dir));
        return mk(e.r, e.g, e.b);
    }
    v3 L = mk(0, 0, 0), beta = mk(1, 1, 1);
    for (int depth = 0;; depth++) {
        /* The light interface: the kind of lights decides how the point is lit. */
        v3 Ld = c->lum             ? shade_luminaires(c, &hh, dir, px, py, k, rng, sc, shadow)
                : job->d.light_set ? shade_light_set(c, &hh, dir, px, py, shadow)
                                   : shade(c, &hh, dir, rng, shadow);
        L = add(L, mk(beta.x * Ld.x, beta.y * Ld.y, beta.z * Ld.z));
        if (depth >= job->d.max_bounces) break;
        v3 t, b, n = hh.n;
        basis(n, &t, &b);
        v3 wow = mul(dir, -1.0);
        lumis_vec3 wo = tof(mk(dot(wow, t), dot(wow, b), dot(wow, n)));
        double u0 = lumis_pcg32_double(rng), u1 = lumis_pcg32_double(rng),
               u2 = lumis_pcg32_double(rng);
        lumis_bsdf_sample bs = lumis_bsdf_sample_wi(&hh.prim->material, wo, u0, u1, u2);
        if (!(bs.pdf > 0.0f)) break;
        beta = mk(beta.x * bs.weight.r, beta.y * bs.weight.g, beta.z * bs.weight.b);
        if (beta.x == 0.0 && beta.y == 0.0 && beta.z == 0.0) break;
        dir = norm(add(add(mul(t, bs.wi.x), mul(b, bs.wi.y)), mul(n, bs.wi.z)));
        v3 org = add(hh.p, mul(n, 1e-4 * fmax(1.0, sqrt(dot(hh.p, hh.p)))));
        *bounce += 1.0;
        if (!intersect(c->scene, org, dir, &hh)) break;
    }
    return L;
}

/* The global strategy's draws of camera samples k0 .. k1 - 1, every instance: a stream per
 * camera sample and instance, the same for every pixel. */
static lumis_status global_draws(const lumis_render_job *job, int k0, int k1,
                                 lumis_luminaire_sample *out, int *n, double *u)
{
    const lumis_luminaire_lighting *ll = &job->lighting;
    for (int k = k0; k < k1; k++)
        for (int i = 0; i < ll->count; i++) {
            const lum_inst *li = &job->lum[i];
            const size_t slot = (size_t)(k - k0) * (size_t)ll->count + (size_t)i;
            lumis_pcg32 g;
            lumis_pcg32_seed(&g, mix64(job->d.seed ^ mix64((uint64_t)k + 1)),
                             0x9e3779b9u + (uint64_t)i);
            for (int j = 0; j < 2 * li->capacity; j++) u[j] = lumis_pcg32_double(&g);
            lumis_status st =
                lumis_luminaire_global_draw(li->lum, &li->query, u, li->capacity,
                                            out + slot * (size_t)job->lum_capacity, &n[slot]);
            if (st != LUMIS_OK) return st;
        }
    return LUMIS_OK;
}

lumis_status lumis_render_job_run(lumis_render_job *job, int samples)
{
    if (!job) return LUMIS_ERR_INVALID_ARGUMENT;
    if (samples < 1 || samples > (1 << 30) - job->stats.spp)
        return lumis__fail(&job->d.errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: %d more samples per pixel is out of range", samples);
    const lumis_render_desc *d = &job->d;
    ctx c = {job->scene,
             d,
             d->light_samples ? d->light_samples : 1,
             d->bsdf_samples ? d->bsdf_samples : 1,
             d->sampler && lumis_sampler_envmap(d->sampler) == d->env,
             job->sets,
             job->soa,
             job->lum,
             NULL,
             NULL,
             0,
             job->lum_capacity};
    const int threads = d->threads > 0 ? d->threads : omp_get_max_threads();
    const int w = job->cam.width, h = job->cam.height, first = job->stats.spp;
    const int tx = (w + TILE - 1) / TILE, ty = (h + TILE - 1) / TILE, tiles = tx * ty;
    double shadow = 0.0, bounce = 0.0, lum_samples = 0.0, t0 = omp_get_wtime();
    int done = 0, failed = 0;
    /* The global strategy draws once per camera sample for every pixel: the camera samples
     * are rendered in chunks whose draws take at most 64 MB. */
    int chunk = samples;
    lumis_luminaire_sample *gbuf = NULL;
    int *gn = NULL;
    double *gu = NULL;
    if (job->lum && job->lighting.strategy == LUMIS_LUM_GLOBAL) {
        const size_t per_k = (size_t)job->lighting.count * (size_t)job->lum_capacity * sizeof *gbuf;
        chunk = (int)((size_t)(64 << 20) / per_k);
        chunk = chunk < 1 ? 1 : chunk > samples ? samples : chunk;
        gbuf = malloc(per_k * (size_t)chunk);
        gn = malloc(sizeof *gn * (size_t)chunk * (size_t)job->lighting.count);
        gu = malloc(2 * sizeof *gu * (size_t)job->lum_capacity);
        if (!gbuf || !gn || !gu) {
            free(gbuf);
            free(gn);
            free(gu);
            return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY,
                               "render: global luminaire draws: out of memory");
        }
        c.global = gbuf;
        c.global_n = gn;
    }
    const int chunks = (samples + chunk - 1) / chunk;
    lumis_status gst = LUMIS_OK;

#pragma omp parallel num_threads(threads) reduction(+ : shadow, bounce, lum_samples)
    {
        lum_scratch sc;
        memset(&sc, 0, sizeof sc);
        if (job->lum) { /* the luminaire kind's buffers, one set per thread */
            sc.cells = job->lum_cells;
            sc.s = malloc(sizeof *sc.s * (size_t)job->lum_capacity);
            sc.vis = malloc(sizeof *sc.vis * sc.cells);
            sc.stamp = calloc(sc.cells, sizeof *sc.stamp);
            if (!sc.s || !sc.vis || !sc.stamp) {
#pragma omp atomic write
                failed = 1;
            }
        }
        for (int ci = 0; ci < chunks; ci++) {
            const int k0 = first + ci * chunk,
                      k1 = k0 + chunk < first + samples ? k0 + chunk : first + samples;
#pragma omp barrier
#pragma omp single
            if (gbuf) {
                c.global_k0 = k0;
                gst = global_draws(job, k0, k1, gbuf, gn, gu);
                if (gst != LUMIS_OK) failed = 1;
            }
            int stop;
#pragma omp atomic read
            stop = failed;
#pragma omp for schedule(dynamic, 1)
            for (int tile = 0; tile < tiles; tile++) {
                if (stop) continue;
                const int x0 = tile % tx * TILE, y0 = tile / tx * TILE;
                const int x1 = x0 + TILE < w ? x0 + TILE : w, y1 = y0 + TILE < h ? y0 + TILE : h;
                for (int y = y0; y < y1; y++)
                    for (int x = x0; x < x1; x++) {
                        const uint64_t pixel = (uint64_t)y * (uint64_t)w + (uint64_t)x;
                        double *acc = job->sum + 3 * pixel;
                        v3 a = mk(acc[0], acc[1], acc[2]);
                        for (int k = k0; k < k1; k++) {
                            /* Sample k of this pixel has its own stream: passes cannot change it.
                             */
                            lumis_pcg32 rng;
                            lumis_pcg32_seed(&rng, mix64(d->seed ^ mix64((uint64_t)k + 1)), pixel);
                            double jx = lumis_pcg32_double(&rng), jy = lumis_pcg32_double(&rng);
                            if (d->pixel_centers) jx = jy = 0.5;
                            double sx = (x + jx) / w * 2.0 - 1.0;
                            double sy = 1.0 - (y + jy) / h * 2.0; /* row 0 on top */
                            v3 dir = camera_dir(&job->cf, sx, sy);
                            a = add(a, trace_sample(&c, job, dir, x, y, k, &rng, &sc, &shadow,
                                                    &bounce));
                        }
                        acc[0] = a.x;
                        acc[1] = a.y;
                        acc[2] = a.z;
                    }
                int now;
#pragma omp atomic capture
                now = ++done;
                if (d->progress && omp_get_thread_num() == 0)
                    d->progress(d->progress_user, now, tiles * chunks);
            }
        }
        lum_samples += sc.samples;
        free(sc.s);
        free(sc.vis);
        free(sc.stamp);
    }
    free(gbuf);
    free(gn);
    free(gu);
    if (gst != LUMIS_OK)
        return lumis__fail(&d->errors, gst, "render: global luminaire draws: %s",
                           lumis_status_string(gst));
    if (failed)
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY,
                           "render: luminaire buffers: out of memory");
    if (d->progress) d->progress(d->progress_user, tiles * chunks, tiles * chunks);
    job->stats.spp += samples;
    job->stats.passes++;
    job->stats.threads = threads;
    job->stats.seconds += omp_get_wtime() - t0;
    job->stats.camera_rays += (double)w * h * samples;
    job->stats.shadow_rays += shadow;
    job->stats.light_samples += lum_samples;
    job->stats.bounce_rays += bounce;
    return LUMIS_OK;
}

lumis_status lumis_render_job_image(const lumis_render_job *job, lumis_image **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!job) return LUMIS_ERR_INVALID_ARGUMENT;
    lumis_status st = lumis_image_create(job->cam.width, job->cam.height, out);
    if (st != LUMIS_OK)
        return lumis__fail(&job->d.errors, st, "render: %d x %d: %s", job->cam.width,
                           job->cam.height, lumis_status_string(st));
    const size_t n = 3 * (size_t)job->cam.width * (size_t)job->cam.height;
    const double inv = job->stats.spp > 0 ? 1.0 / job->stats.spp : 0.0;
    for (size_t k = 0; k < n; k++) (*out)->pixels[k] = (float)(job->sum[k] * inv);
    return LUMIS_OK;
}

void lumis_render_job_stats(const lumis_render_job *job, lumis_render_stats *stats)
{
    if (job && stats) *stats = job->stats;
}

lumis_status lumis_render(const lumis_scene *scene, const lumis_render_desc *d, lumis_image **out,
                          lumis_render_stats *stats)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    lumis_render_job *job = NULL;
    lumis_status st = lumis_render_job_create(scene, d, &job);
    if (st == LUMIS_OK) st = lumis_render_job_run(job, d->spp ? d->spp : 16);
    if (st == LUMIS_OK) st = lumis_render_job_image(job, out);
    if (st == LUMIS_OK && stats) lumis_render_job_stats(job, stats);
    lumis_render_job_destroy(job);
    return st;
}
