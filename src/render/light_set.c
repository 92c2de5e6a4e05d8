/* A light set as the renderer's light: every light of the pixel's interleaved set, one
 * shadow ray each, traced 16 at a time. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The lights of one set that light_kinds selects, in float arrays: the shading loop reads
 * six floats a light and nothing else. */
typedef struct light_soa {
    int count;
    float *x, *y, *z, *r, *g, *b;
} light_soa;

/* The set's lights as the shading loop reads them: one light_soa per interleaved set. */
typedef struct set_state {
    light_soa *soa;
    int sets;
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

static int lights(const lumis_render_desc *d)
{
    return d->light_set != NULL;
}

static void release(void *state)
{
    set_state *st = state;
    if (st) soa_free(st->soa, st->sets);
    free(st);
}

static lumis_status prepare(const lumis_scene *scene, const lumis_render_desc *d, void **state)
{
    (void)scene;
    if (d->max_bounces > 0)
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: a light set lights direct illumination only (max_bounces "
                           "must be 0)");
    set_state *st = calloc(1, sizeof *st);
    *state = st;
    if (!st ||
        !(st->soa = soa_make(d->light_set, d->light_kinds ? d->light_kinds : ~0u, &st->sets)))
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "render: light set: out of memory");
    return LUMIS_OK;
}

const lumis__light_kind lumis__light_set_kind = {
    "light set", lights, prepare, release, NULL, NULL, NULL, NULL, NULL, shade,
};
