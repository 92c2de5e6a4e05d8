/* The renderer's shading, shared by its light kinds (internal to lumis-render): the context
 * a shading point is lit in, the packets of shadow rays, and each kind's entry points.
 *   environment map  light_env.c        light, BSDF or MIS sampling of the map
 *   light set        light_set.c        every light of the pixel's interleaved set
 *   luminaires       light_luminaire.c  Lu et al.'s strategies, visibility modes, sequences
 *   photometric      light_photometric.c  IES / EULUMDAT fixtures: points, or openings with MIS
 * The job (render.c) prepares the kind a render asks for and calls its shade function at
 * every vertex. */
#ifndef LUMIS_RENDER_SHADE_H
#define LUMIS_RENDER_SHADE_H

#include "lumis/render.h"
#include "lumis/rng.h"

#include "internal.h"
#include "packet.h"
#include "sequence.h"
#include "scene.h"
#include "vec.h"

#include <math.h>
#include <stdint.h>

static inline double mis_weight(double nf, double pf, double ng, double pg, int power)
{
    double a = nf * pf, b = ng * pg;
    if (power) {
        a *= a;
        b *= b;
    }
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

/* The techniques lighting.estimator asks a light kind for: light samples, BSDF samples, and
 * whether the two are weighed by MIS (else each counts in full). */
typedef struct estimator_use {
    int light, bsdf, mis;
} estimator_use;

static inline estimator_use estimator_use_of(const lumis_render_desc *d)
{
    estimator_use e;
    e.light = d->lighting.estimator != LUMIS_ESTIMATOR_BSDF;
    e.bsdf = d->lighting.estimator != LUMIS_ESTIMATOR_LIGHT;
    e.mis = d->lighting.estimator == LUMIS_ESTIMATOR_MIS;
    return e;
}

/* The frame a point is shaded in: its normal n and tangents t, b, the direction towards
 * the eye in that frame (what the BSDFs take), the world direction of the frame's local
 * direction (x, y, z) is x t + y b + z n, and the origin of its shadow and continuation
 * rays, lifted off the surface in proportion to the point's distance from the origin. */
typedef struct shading_frame {
    v3 n, t, b, org;
    lumis_vec3 wo;
} shading_frame;

static inline shading_frame shading_frame_at(const hit *h, v3 dir)
{
    shading_frame f;
    f.n = h->n;
    basis(f.n, &f.t, &f.b);
    const v3 wow = mul(dir, -1.0);
    f.wo = tof(mk(dot(wow, f.t), dot(wow, f.b), dot(wow, f.n)));
    f.org = add(h->p, mul(f.n, 1e-4 * fmax(1.0, sqrt(dot(h->p, h->p)))));
    return f;
}

/* What a shading point is lit in: the scene, the render's settings and the light kind's
 * state (what its prepare() made). */
typedef struct ctx {
    const lumis_scene *scene;
    const lumis_render_desc *d;
    const void *state;
} ctx;

/* One camera sample's vertex as a light kind sees it. */
typedef struct lumis__vertex {
    int px, py, k;       /* the pixel and the camera sample */
    lumis__stream *seq;  /* the sample's numbers (sequence.h) */
    void *scratch;       /* the kind's per-thread buffers (thread_begin), or NULL */
    double *shadow_rays; /* add the shadow rays traced */
} lumis__vertex;

/* A vertex's BSDF sample that continues its path (shade_next): its origin, world direction
 * and the sample (bs.pdf 0: the path ends). */
typedef struct lumis__next {
    v3 org, wi;
    lumis_bsdf_sample bs;
} lumis__next;

/* What a light kind may use of a render description (lighting.c checks them). */
enum {
    LUMIS__IN_SAMPLER = 1u << 0,        /* lighting.sampler */
    LUMIS__IN_EST_LIGHT = 1u << 1,      /* lighting.estimator LIGHT */
    LUMIS__IN_EST_BSDF = 1u << 2,       /* lighting.estimator BSDF */
    LUMIS__IN_SET = 1u << 3,            /* lighting.light_set.set */
    LUMIS__IN_SET_KINDS = 1u << 4,      /* lighting.light_set.kinds */
    LUMIS__IN_SET_MODE = 1u << 5,       /* lighting.light_set.mode stratified */
    LUMIS__IN_REGIONS = 1u << 6,        /* lighting.light_set.regions */
    LUMIS__IN_LUMINAIRES = 1u << 7,     /* lighting.luminaires */
    LUMIS__IN_PHOTOMETRIC = 1u << 8,    /* lighting.photometric */
    LUMIS__IN_ENV = 1u << 9,            /* lighting.env */
    LUMIS__IN_HIDE = 1u << 10,          /* lighting.hide_environment */
    LUMIS__IN_POWER = 1u << 11,         /* power_heuristic */
    LUMIS__IN_LIGHT_SAMPLES = 1u << 12, /* light_samples */
    LUMIS__IN_BSDF_SAMPLES = 1u << 13,  /* bsdf_samples */
    LUMIS__IN_BOUNCES = 1u << 14,       /* max_bounces > 0 */
    LUMIS__IN_SUN = 1u << 15,           /* lighting.sun.sun */
    LUMIS__IN_SET_DRAWS = 1u << 16,     /* lighting.light_set.draws */
    LUMIS__IN_SET_ALLOC = 1u << 17,     /* lighting.light_set.region_draws */
    LUMIS__IN_COUNT = 18
};

/* The renderer's light interface: a kind of light is one file and one entry of render.c's
 * table, indexed by lumis_lighting_kind.  Optional entries are NULL. */
typedef struct lumis__light_kind {
    const char *name; /* what lights the scene, for messages: "luminaires" */
    /* What the kind needs (must be given) and takes (may be given) of LUMIS__IN_* for l
     * (a light set's needs and takes depend on its mode; the map's on the estimator). */
    void (*inputs)(const lumis_lighting *l, unsigned *needs, unsigned *takes);
    /* Makes the kind's state from a checked d (freed by release, also after a failure) */
    lumis_status (*prepare)(const lumis_scene *scene, const lumis_render_desc *d, void **state);
    void (*release)(void *state);
    /* Optional, around a lumis_render_job_run of `samples` camera samples: how many camera
     * samples a chunk may hold (*chunk starts at samples), and the work before each chunk
     * (k0 .. k1 - 1) and after the run. */
    lumis_status (*run_begin)(void *state, int samples, int *chunk);
    lumis_status (*chunk_begin)(void *state, uint64_t seed, int k0, int k1);
    void (*run_end)(void *state);
    /* Optional per-thread buffers (NULL: out of memory) and their release, which adds the
     * light samples the thread evaluated. */
    void *(*thread_begin)(const void *state);
    void (*thread_end)(void *scratch, double *light_samples);
    /* The light reflected at h towards -dir. */
    v3 (*shade)(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v);
    /* Optional, for paths: shade() with its (first) BSDF sample not traced but handed back
     * in *next as the path's continuation (the integrator then draws none of its own), and
     * the light that sample's ray brings when it leaves the scene, per unit of the sample's
     * weight (its share of shade()'s light: the map seen, weighed by MIS).  One ray per
     * vertex fewer than a separate continuation; the same expectation. */
    v3 (*shade_next)(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v, lumis__next *next);
    v3 (*escape)(const ctx *c, const lumis__next *next);
} lumis__light_kind;

extern const lumis__light_kind lumis__light_env;         /* light_env.c */
extern const lumis__light_kind lumis__light_set_kind;    /* light_set.c */
extern const lumis__light_kind lumis__light_luminaires;  /* light_luminaire.c */
extern const lumis__light_kind lumis__light_photometric; /* light_photometric.c */

/* Whether region k of rs is one the stratified mode draws from: of a kind in `kinds` (0:
 * every kind) and holding light.  The lit regions are the strata (light_set.c) and the
 * floor of light_set.region_draws (lighting.c). */
static inline int lumis__region_lit(const lumis_region_sampler *rs, int k, unsigned kinds)
{
    const unsigned mask = kinds ? kinds : ~0u;
    return (mask & (1u << lumis_region_sampler_kind(rs, k))) && !lumis_region_sampler_empty(rs, k);
}

/* The kind of d->lighting (d checked). */
const lumis__light_kind *lumis__light_kind_of(const lumis_render_desc *d);

enum { PACKET = LUMIS__PACKET };

/* Shadow rays of one shading point, traced PACKET at a time (packet.h); a lane's
 * contribution is added when its ray is unoccluded. */
typedef struct packet {
    lumis__packet rays;
    v3 contrib[PACKET];
    int flushed; /* lanes traced in earlier packets */
} packet;

static inline void packet_trace(const lumis_scene *s, const lumis_render_desc *d, packet *p)
{
    lumis__packet_trace(s->rtc, d->shadow_ray, d->shadow_ray_user, &p->rays);
}

static inline void packet_flush(const lumis_scene *s, const lumis_render_desc *d, packet *p, v3 *L)
{
    if (p->rays.n == 0) return;
    packet_trace(s, d, p);
    for (int k = 0; k < p->rays.n; k++)
        if (p->rays.r.tfar[k] >= 0.0f) *L = add(*L, p->contrib[k]);
    p->flushed += p->rays.n;
    p->rays.n = 0;
}

static inline void packet_push(packet *p, v3 o, v3 d, float tfar, v3 contrib)
{
    const float of[3] = {(float)o.x, (float)o.y, (float)o.z},
                df[3] = {(float)d.x, (float)d.y, (float)d.z};
    p->contrib[p->rays.n] = contrib;
    lumis__packet_push(&p->rays, of, df, tfar);
}

/* ---- the image sun (light_sun.c) ---- */

/* The sun's direct light at h towards -dir (a cone sample and a BSDF sample, by
 * d->lighting.estimator), added to what the kind gives. */
v3 lumis__sun_shade(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v);

/* ---- the integrator (integrator.c) ---- */

/* One camera sample from eye along dir: what the kind lights at its first hit, and along a
 * BSDF-sampled path of up to c->d->max_bounces further vertices (bounce rays counted). */
v3 lumis__trace_sample(const ctx *c, const lumis__light_kind *kind, v3 eye, v3 dir,
                       const lumis__vertex *v, double *bounce);

#endif
