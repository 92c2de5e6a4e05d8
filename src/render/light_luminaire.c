/* Light-field luminaires as the renderer's light (Lu et al.): each placed luminaire's samples
 * at a shading point, with exact visibility (a shadow ray each), the paper's approximate
 * visibility (rays or shadow maps per basis cell) or none; PCG32 or Halton numbers. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "internal.h"
#include "shade.h"

#include <math.h>
#include <stdlib.h>
#include <omp.h>
#include <string.h>

/* One placed luminaire as the shading loop reads it. */
typedef struct lum_inst {
    const lumis_luminaire *lum;
    double r[9], t[3], scale, inv_scale, intensity;
    lumis_luminaire_query query; /* the lighting's search, depth and cap */
    /* The strategy and budget by distance from the luminaire's origin (its units): band b
     * from edge[b - 1] to edge[b]; one band unless auto chose more. */
    int bands;
    double edge[LUMIS_LUM_MAX_BANDS - 1];
    lumis_luminaire_strategy strategy[LUMIS_LUM_MAX_BANDS];
    int budget[LUMIS_LUM_MAX_BANDS];
    int global; /* a band samples globally: gquery's draws, once per camera sample */
    lumis_luminaire_query gquery;
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

/* The kind's state: the placed luminaires, and the global strategy's draws of the chunk of
 * camera samples being rendered (camera sample k, instance i at slot (k - global_k0) *
 * count + i, `capacity` samples a slot). */
typedef struct lum_state {
    lum_inst *lum;
    lumis_luminaire_lighting lighting; /* a copy of the render's */
    int capacity;                      /* the most samples one instance returns */
    uint32_t dims;                     /* the instances' capacities, summed */
    size_t cells;                      /* the most visibility cells one instance has */
    lumis_error_sink errors;
    lumis_luminaire_sample *global;
    int *global_n;
    double *global_u;
    int global_k0;
} lum_state;

static const char *const visibility_names[] = {"exact", "approx", "none", "shadowmap"};

LUMIS__ENUM_NAMES(lumis_visibility, LUMIS_VISIBILITY_COUNT, visibility_names, lumis_visibility_name,
                  lumis_visibility_from_name);

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

/* The luminaire samplers' numbers (lumis_luminaire_query.fill): PCG32, the camera
 * sample's stream in order; Halton, point j of the capacity's worth of one dimension per
 * instance (index k capacity + j, as Lu et al.'s Fig. 8); the (0,2) sequences and strata,
 * a dimension per sample j (the capacity's worth per instance), index k.  A point uses the
 * first m of its capacity, m varying from point to point: the first m of each block of
 * one dimension are no net (Sobol' fell as 1 / spp: relMSE 6.9e-5 to 1.0e-6 from 4 to 256
 * spp on headlight-close, Halton 6.7e-5 to 2.7e-7), while sample j of successive camera
 * samples is one. */
static void fill_pcg(void *rng, double *u, int n)
{
    lumis_pcg32_fill_doubles(rng, u, (size_t)n);
}

typedef struct seq_pairs {
    lumis__stream *seq;
    uint32_t dim, next, n;
    int per_sample; /* a dimension per sample, else n points of one */
} seq_pairs;

static void fill_seq(void *state, double *u, int n)
{
    seq_pairs *p = state;
    for (int j = 0; j < n; j += 2, p->next++)
        if (p->per_sample)
            seq_2d(p->seq, p->dim + p->next, 0, 1, u + j);
        else
            seq_2d(p->seq, p->dim, p->next, p->n, u + j);
}

/* Every placed luminaire at h: its samples (lumis_luminaire_sample_point) times the BSDF and
 * the cosine, each weighted as the sample says (1 / (K_m pdf_omega)), times its visibility. */
static v3 shade(const ctx *c, const hit *h, v3 dir, const lumis__vertex *v)
{
    const lumis_render_desc *d = c->d;
    const lum_state *st = c->state;
    const lumis_luminaire_lighting *ll = &st->lighting;
    const int k = v->k;
    lumis__stream *seq = v->seq;
    const int per_sample = seq->q->kind != LUMIS_SEQUENCE_HALTON;
    /* per instance: its capacity's worth of dimensions (one with Halton) */
    const uint32_t dim0 = seq_take_n(seq, per_sample ? st->dims : (uint32_t)ll->count);
    uint32_t dim = dim0;
    lum_scratch *sc = v->scratch;
    double *shadow_rays = v->shadow_rays;
    const shading_frame fr = shading_frame_at(h, dir);
    const v3 t = fr.t, b = fr.b, n = fr.n, o = fr.org;
    const lumis_vec3 wo = fr.wo;
    const lumis_bsdf *mat = &h->prim->material;
    v3 L = mk(0, 0, 0);
    for (int i = 0; i < ll->count; i++) {
        const lum_inst *li = &st->lum[i];
        /* the instance's dimensions, taken whether it lights h or not */
        const uint32_t idim = dim;
        dim += per_sample ? (uint32_t)li->capacity : 1u;
        lumis_luminaire_query q = li->query;
        const v3 pl =
            mul(rot_apply_t(li->r, sub(h->p, mk(li->t[0], li->t[1], li->t[2]))), li->inv_scale);
        q.p = tof(pl);
        if (!(q.p.z > 0.0f)) continue; /* behind U: no light */
        int band = 0;
        if (li->bands > 1) {
            const double r = sqrt(dot(pl, pl));
            while (band + 1 < li->bands && r >= li->edge[band]) band++;
        }
        q.strategy = li->strategy[band];
        q.budget = li->budget[band];
        int count = 0;
        seq_pairs sp = {seq, idim, 0, (uint32_t)li->capacity, per_sample};
        if (q.strategy == LUMIS_LUM_GLOBAL) {
            /* The same points on S for every shading point: drawn once per camera sample
             * (global_draws), finished here. */
            const size_t slot = (size_t)(k - st->global_k0) * (size_t)ll->count + (size_t)i;
            if (lumis_luminaire_global_finish(li->lum, q.p,
                                              st->global + slot * (size_t)st->capacity,
                                              st->global_n[slot], sc->s, &count) != LUMIS_OK)
                continue;
        } else if (seq->q->kind != LUMIS_SEQUENCE_PCG) {
            q.fill = fill_seq;
            q.fill_ctx = &sp;
        } else {
            /* Only the numbers the point's samples use (there are often far fewer samples
             * than the capacity reserved for the worst point). */
            q.fill = fill_pcg;
            q.fill_ctx = &seq->rng;
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

lumis_rigid lumis__instance_placement(const lumis_luminaire_instance *in, double *scale)
{
    lumis_rigid x = in->placement;
    int zero = 1;
    for (int k = 0; k < 9; k++) zero &= x.r[k] == 0.0;
    if (zero) memcpy(x.r, lumis_rigid_identity().r, sizeof x.r);
    *scale = in->scale == 0.0 ? 1.0 : in->scale;
    return x;
}

/* Checks the luminaire lighting and lays out one lum_inst per placed luminaire. */
static lumis_status lum_prepare_as(const lumis_render_desc *d, const lumis_luminaire_choice *chosen,
                                   lum_inst **lum, int *capacity, uint32_t *dims,
                                   size_t *most_cells)
{
    const lumis_luminaire_lighting *ll = d->lighting.luminaires;
    const lumis_error_sink *errors = &d->errors;
    if (ll->count < 1 || ll->count > 4096 || !ll->instances || ll->budget < 0 ||
        ll->budget > 65536 || ll->k_max < 0 || ll->depth < 0 ||
        (unsigned)ll->strategy >= LUMIS_LUM_STRATEGY_COUNT ||
        (unsigned)ll->search >= LUMIS_LUM_SEARCH_COUNT ||
        (unsigned)ll->visibility >= LUMIS_VISIBILITY_COUNT)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: lighting.luminaires: 1 to 4096 instances, budget 0 to 65536, "
                           "k_max and depth >= 0, and known strategy, search and visibility");
    if (!(*lum = calloc((size_t)ll->count, sizeof **lum)))
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "render: luminaires: out of memory");
    for (int i = 0; i < ll->count; i++) {
        const lumis_luminaire_instance *in = &ll->instances[i];
        lum_inst *li = &(*lum)[i];
        double scale;
        const lumis_rigid x = lumis__instance_placement(in, &scale);
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
        li->bands = 1;
        li->strategy[0] =
            ll->strategy == LUMIS_LUM_STRATEGY_DEFAULT ? LUMIS_LUM_RESTRICTED : ll->strategy;
        li->budget[0] = li->query.budget;
        if (chosen) {
            li->bands = chosen[i].bands;
            memcpy(li->edge, chosen[i].edge, sizeof li->edge);
            memcpy(li->strategy, chosen[i].strategy, sizeof li->strategy);
            memcpy(li->budget, chosen[i].budget, sizeof li->budget);
        }
        li->capacity = 0;
        for (int b = 0; b < li->bands; b++) {
            const int cap = lumis_luminaire_capacity(in->luminaire, li->budget[b]);
            if (cap > li->capacity) li->capacity = cap;
            if (li->strategy[b] == LUMIS_LUM_GLOBAL) {
                li->global = 1;
                li->gquery = li->query;
                li->gquery.strategy = LUMIS_LUM_GLOBAL;
                li->gquery.budget = li->budget[b];
            }
        }
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
        if (li->capacity > *capacity) *capacity = li->capacity;
        *dims += (uint32_t)li->capacity;
        const size_t cells = (size_t)li->cells[0] * (size_t)li->cells[1];
        if (cells > *most_cells) *most_cells = cells;
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

/* Checks the luminaire lighting and lays out one lum_inst per placed luminaire, each with
 * the strategy (and budget) auto chose for it. */
static lumis_status lum_prepare(const lumis_scene *scene, const lumis_render_desc *d,
                                lum_inst **lum, int *capacity, uint32_t *dims, size_t *most_cells)
{
    const lumis_luminaire_lighting *ll = d->lighting.luminaires;
    if (ll->strategy != LUMIS_LUM_AUTO || ll->count <= 0 || ll->count > 4096 || !ll->instances)
        return lum_prepare_as(d, NULL, lum, capacity, dims, most_cells);
    /* into the caller's array when it gave one */
    lumis_luminaire_choice *own = ll->chosen ? NULL : malloc(sizeof *own * (size_t)ll->count);
    lumis_luminaire_choice *chosen = ll->chosen ? ll->chosen : own;
    lumis_status st = chosen ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
    if (st != LUMIS_OK)
        lumis__fail(&d->errors, st, "render: luminaires: out of memory");
    else
        st = lumis_render_luminaire_choices(scene, d, chosen);
    if (st == LUMIS_OK) st = lum_prepare_as(d, chosen, lum, capacity, dims, most_cells);
    free(own);
    return st;
}

/* The global strategy's draws of camera samples k0 .. k1 - 1, every instance: a stream per
 * camera sample and instance, the same for every pixel. */
static lumis_status global_draws(const lumis_luminaire_lighting *ll, const lum_inst *lum,
                                 int capacity, uint64_t seed, int k0, int k1,
                                 lumis_luminaire_sample *out, int *n, double *u)
{
    for (int k = k0; k < k1; k++)
        for (int i = 0; i < ll->count; i++) {
            const lum_inst *li = &lum[i];
            const size_t slot = (size_t)(k - k0) * (size_t)ll->count + (size_t)i;
            n[slot] = 0;
            if (!li->global) continue; /* no band of it samples globally */
            lumis_pcg32 g;
            lumis_pcg32_seed(&g, lumis__mix64(seed ^ lumis__mix64((uint64_t)k + 1)),
                             0x9e3779b9u + (uint64_t)i);
            for (int j = 0; j < 2 * li->capacity; j++) u[j] = lumis_pcg32_double(&g);
            lumis_status st = lumis_luminaire_global_draw(li->lum, &li->gquery, u, li->capacity,
                                                          out + slot * (size_t)capacity, &n[slot]);
            if (st != LUMIS_OK) return st;
        }
    return LUMIS_OK;
}

/* ---- the kind ------------------------------------------------------------------------ */

/* The luminaires alone: their own budget and strategies, direct illumination only. */
static void inputs(const lumis_lighting *l, unsigned *needs, unsigned *takes)
{
    (void)l;
    *needs = LUMIS__IN_LUMINAIRES;
    *takes = 0;
}

static void release(void *state)
{
    lum_state *st = state;
    if (!st) return;
    for (int i = 0; st->lum && i < st->lighting.count; i++) {
        free(st->lum[i].smap);
        free(st->lum[i].cell_world);
    }
    free(st->lum);
    free(st);
}

static lumis_status prepare(const lumis_scene *scene, const lumis_render_desc *d, void **state)
{
    lum_state *st = calloc(1, sizeof *st);
    *state = st;
    if (!st) return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "render: out of memory");
    st->lighting = *d->lighting.luminaires; /* what release reads to free the shadow maps */
    st->errors = d->errors;
    lumis_status lst = lum_prepare(scene, d, &st->lum, &st->capacity, &st->dims, &st->cells);
    for (int i = 0;
         lst == LUMIS_OK && d->lighting.luminaires->visibility == LUMIS_VISIBILITY_SHADOW_MAP &&
         i < d->lighting.luminaires->count;
         i++)
        if ((lst = lum_shadow_maps(scene, &st->lum[i], 256,
                                   d->threads > 0 ? d->threads : omp_get_max_threads())) !=
            LUMIS_OK)
            lumis__fail(&d->errors, lst, "render: luminaire %d: shadow maps: out of memory", i);
    return lst;
}

/* The global strategy draws once per camera sample for every pixel: the camera samples are
 * rendered in chunks whose draws take at most 64 MB. */
static lumis_status run_begin(void *state, int samples, int *chunk)
{
    lum_state *st = state;
    int global = 0;
    for (int i = 0; i < st->lighting.count; i++) global |= st->lum[i].global;
    if (!global) return LUMIS_OK;
    const size_t per_k = (size_t)st->lighting.count * (size_t)st->capacity * sizeof *st->global;
    int n = (int)((size_t)(64 << 20) / per_k);
    n = n < 1 ? 1 : n > samples ? samples : n;
    st->global = malloc(per_k * (size_t)n);
    st->global_n = malloc(sizeof *st->global_n * (size_t)n * (size_t)st->lighting.count);
    st->global_u = malloc(2 * sizeof *st->global_u * (size_t)st->capacity);
    if (!st->global || !st->global_n || !st->global_u)
        return lumis__fail(&st->errors, LUMIS_ERR_OUT_OF_MEMORY,
                           "render: global luminaire draws: out of memory");
    *chunk = n;
    return LUMIS_OK;
}

static lumis_status chunk_begin(void *state, uint64_t seed, int k0, int k1)
{
    lum_state *st = state;
    if (!st->global) return LUMIS_OK;
    st->global_k0 = k0;
    const lumis_status gst = global_draws(&st->lighting, st->lum, st->capacity, seed, k0, k1,
                                          st->global, st->global_n, st->global_u);
    if (gst != LUMIS_OK)
        lumis__fail(&st->errors, gst, "render: global luminaire draws: %s",
                    lumis_status_string(gst));
    return gst;
}

static void run_end(void *state)
{
    lum_state *st = state;
    free(st->global);
    free(st->global_n);
    free(st->global_u);
    st->global = NULL;
    st->global_n = NULL;
    st->global_u = NULL;
}

static void thread_end_(void *scratch, double *light_samples)
{
    lum_scratch *sc = scratch;
    if (!sc) return;
    *light_samples += sc->samples;
    free(sc->s);
    free(sc->vis);
    free(sc->stamp);
    free(sc);
}

/* A thread's buffers: the samples of one instance, and visibility per cell. */
static void *thread_begin(const void *state)
{
    const lum_state *st = state;
    lum_scratch *sc = calloc(1, sizeof *sc);
    if (!sc) return NULL;
    sc->cells = st->cells;
    sc->s = malloc(sizeof *sc->s * (size_t)st->capacity);
    sc->vis = malloc(sizeof *sc->vis * sc->cells);
    sc->stamp = calloc(sc->cells, sizeof *sc->stamp);
    if (!sc->s || !sc->vis || !sc->stamp) {
        double ignored = 0.0;
        thread_end_(sc, &ignored);
        return NULL;
    }
    return sc;
}

const lumis__light_kind lumis__light_luminaires = {
    "luminaires", inputs,       prepare,     release, run_begin, chunk_begin,
    run_end,      thread_begin, thread_end_, shade,   NULL,      NULL,
};
