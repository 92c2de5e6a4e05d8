/* The renderer's shading, shared by its light kinds (internal to lumis-render): the context
 * a shading point is lit in, the packets of shadow rays, and each kind's entry points.
 *   environment map  light_env.c        light, BSDF or MIS sampling of the map
 *   light set        light_set.c        every light of the pixel's interleaved set
 *   luminaires       light_luminaire.c  Lu et al.'s strategies, visibility modes, sequences
 * The job (render.c) prepares the kind a render asks for and calls its shade function at
 * every vertex. */
#ifndef LUMIS_RENDER_SHADE_H
#define LUMIS_RENDER_SHADE_H

#include "lumis/render.h"
#include "lumis/rng.h"

#include "packet.h"
#include "scene.h"
#include "vec.h"

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

/* splitmix64's finaliser: decorrelates (seed, sample) pairs into PCG start states. */
static inline uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

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

/* ---- the environment map (light_env.c) ---- */

/* Direct light from the environment reflected at h towards -dir. */
v3 lumis__shade_env(const ctx *c, const hit *h, v3 dir, lumis_pcg32 *rng, double *shadow_rays);

/* ---- a light set (light_set.c) ---- */

/* The lights of every set that `kinds` selects, as float arrays (one allocation a set). */
light_soa *lumis__soa_make(const lumis_light_set *set, unsigned kinds, int *sets_out);
void lumis__soa_free(light_soa *soa, int sets);
/* Every light of the pixel's set: f cos V power, one shadow ray each. */
v3 lumis__shade_light_set(const ctx *c, const hit *h, v3 dir, int px, int py, double *shadow_rays);

/* ---- luminaires (light_luminaire.c) ---- */

/* Checks the luminaire lighting and lays out one lum_inst per placed luminaire in *lum (set
 * before any failure: the caller frees it), with the most samples one instance returns and
 * the most visibility cells one has. */
lumis_status lumis__render_lum_prepare(const lumis_render_desc *d, lum_inst **lum, int *capacity,
                                       size_t *most_cells);
/* Renders every cell's shadow map of an instance (LUMIS_VISIBILITY_SHADOW_MAP). */
lumis_status lumis__lum_shadow_maps(const lumis_scene *scene, lum_inst *li, int n, int threads);
/* The global strategy's draws of camera samples k0 .. k1 - 1, every instance. */
lumis_status lumis__lum_global_draws(const lumis_luminaire_lighting *ll, const lum_inst *lum,
                                     int capacity, uint64_t seed, int k0, int k1,
                                     lumis_luminaire_sample *out, int *n, double *u);
/* Every placed luminaire at h. */
v3 lumis__shade_luminaires(const ctx *c, const hit *h, v3 dir, int px, int py, int k,
                           lumis_pcg32 *rng, lum_scratch *sc, double *shadow_rays);

#endif
