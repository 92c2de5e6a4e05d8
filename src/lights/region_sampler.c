/* Region samplers: each region of a light set's partition as a stratum of the map, sampled
 * in proportion to luminance times solid angle inside it (docs/lights.md, "Stratified
 * mode").
 *
 * Layout: the pixels of nonzero luminance, grouped by region (scan order inside a region),
 * with one alias table per region over them, all in one array of 16-byte bins; and per
 * pixel of the map its region and its density in that region's sampler, so pdf() and the
 * lookup of a BSDF-sampled direction read 8 bytes.  Every region's probabilities are
 * quantised exactly as the alias sampler's (src/core/alias.c), and sample() and pdf() read
 * the same stored float. */
#include "lumis/lights.h"

#include "../core/distrib.h"
#include "internal.h"

#include <stdlib.h>
#include <string.h>

/* A pixel of the map: its region (-1: none) and its density per steradian in it. */
typedef struct region_px {
    int32_t region;
    float density;
} region_px;

struct lumis_region_sampler {
    const lumis_envmap *env; /* retained */
    int w, h, count;
    double inv_w;
    region_px *px;          /* w * h */
    uint32_t *start;        /* count + 1: region k's entries are [start[k], start[k + 1]) */
    uint32_t *member;       /* the pixel of each entry */
    lumis__alias_bin *bin;  /* one alias table per region, entries local to it */
    double (*power)[3];     /* count: sum over the region of L Omega (scale applied) */
    lumis_light_kind *kind; /* count: what the region's light stands for */
    double build_ms;
    size_t bytes;
};

/* The alias build's density callback: probability over the entry's pixel solid angle. */
typedef struct density_ctx {
    const lumis_region_sampler *rs;
    uint32_t first; /* the region's first entry */
} density_ctx;

static float entry_density(const void *ctx, uint32_t e, double prob)
{
    const density_ctx *c = ctx;
    const uint32_t pixel = c->rs->member[c->first + e];
    return (float)(prob / c->rs->env->row_solid_angle[pixel / (uint32_t)c->rs->w]);
}

void lumis_region_sampler_destroy(lumis_region_sampler *rs)
{
    if (!rs) return;
    free(rs->px);
    free(rs->start);
    free(rs->member);
    free(rs->bin);
    free(rs->power);
    free(rs->kind);
    lumis_envmap_destroy((lumis_envmap *)rs->env);
    free(rs);
}

lumis_status lumis_region_sampler_create(const lumis_envmap *env, const lumis_light_set *set,
                                         const lumis_error_sink *errors, lumis_region_sampler **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!env || !set || set->w != env->width || set->h != env->height)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "region sampler: needs a map and a light set made from a map of its "
                           "size");
    const double t0 = lumis__now_ms();
    const int w = set->w, h = set->h, K = set->count;
    const size_t n = (size_t)w * (size_t)h;
    lumis_region_sampler *rs = calloc(1, sizeof *rs);
    if (!rs) return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "region sampler: out of memory");
    rs->env = lumis__envmap_retain(env);
    rs->w = w;
    rs->h = h;
    rs->count = K;
    rs->inv_w = 1.0 / w;
    rs->px = malloc(n * sizeof *rs->px);
    rs->start = calloc((size_t)K + 1, sizeof *rs->start);
    rs->power = calloc((size_t)K, sizeof *rs->power);
    rs->kind = malloc((size_t)K * sizeof *rs->kind);
    double *weight = NULL;
    uint64_t *units = NULL;
    uint32_t *work = NULL, *cursor = NULL;
    lumis_status st = LUMIS_ERR_OUT_OF_MEMORY;
    if (!rs->px || !rs->start || !rs->power || !rs->kind) goto fail;
    /* a region's power is its light's (the set's sum of L Omega over the region) */
    for (int k = 0; k < K; k++) {
        rs->kind[k] = set->lights[k].kind;
        for (int c = 0; c < 3; c++) rs->power[k][c] = set->lights[k].power[c];
    }

    /* Pass 1: each pixel's region, and the regions' sizes (pixels that shine). */
    const float *pix = env->pixels;
    const double scale = env->scale;
    size_t members = 0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const size_t p = (size_t)j * (size_t)w + (size_t)i;
            const int32_t r = set->labels[p];
            const int shines = lumis__pixel_y(pix + 3 * p, scale) > 0.0f;
            rs->px[p].region = r;
            rs->px[p].density = 0.0f;
            if (r >= 0 && r < K) {
                rs->start[r + 1] += (uint32_t)shines;
                continue;
            }
            if (shines) {
                st = lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                                 "region sampler: pixel (%d, %d) shines but belongs to no region",
                                 i, j);
                goto fail;
            }
            rs->px[p].region = -1;
        }
    for (int k = 0; k < K; k++) members += rs->start[k + 1];
    uint32_t largest = 0;
    for (int k = 0; k < K; k++) {
        const uint32_t size = rs->start[k + 1];
        if (size > largest) largest = size;
        rs->start[k + 1] = rs->start[k] + size;
    }

    /* Pass 2: the entries, region by region (scan order inside one). */
    const size_t m1 = members > 0 ? members : 1, l1 = largest > 0 ? largest : 1u;
    rs->member = malloc(m1 * sizeof *rs->member);
    rs->bin = aligned_alloc(16, m1 * sizeof *rs->bin);
    cursor = malloc(((size_t)K + 1) * sizeof *cursor);
    /* scratch for one region at a time: the weights, the alias build's units and work */
    weight = malloc(l1 * sizeof *weight);
    units = malloc(l1 * sizeof *units);
    work = malloc(l1 * sizeof *work);
    if (!rs->member || !rs->bin || !weight || !cursor || !units || !work) goto fail;
    memcpy(cursor, rs->start, ((size_t)K + 1) * sizeof *cursor);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const size_t p = (size_t)j * (size_t)w + (size_t)i;
            const int32_t r = rs->px[p].region;
            if (r < 0 || !(lumis__pixel_y(pix + 3 * p, scale) > 0.0f)) continue;
            rs->member[cursor[r]++] = (uint32_t)p;
        }

    /* One alias table per region over the weights Y Omega of its entries; each pixel keeps
     * the density its entry stores. */
    for (int k = 0; k < K; k++) {
        const uint32_t first = rs->start[k], size = rs->start[k + 1] - first;
        if (size == 0) continue;
        for (uint32_t e = 0; e < size; e++) {
            const uint32_t p = rs->member[first + e];
            weight[e] = (double)lumis__pixel_y(pix + 3 * (size_t)p, scale) *
                        env->row_solid_angle[p / (uint32_t)w];
        }
        const density_ctx ctx = {rs, first};
        lumis__alias_build_in(rs->bin + first, units, work, weight, size, entry_density, &ctx);
        for (uint32_t e = 0; e < size; e++)
            rs->px[rs->member[first + e]].density = rs->bin[first + e].value;
    }
    free(weight);
    free(cursor);
    free(units);
    free(work);
    rs->bytes = sizeof *rs + n * sizeof *rs->px + ((size_t)K + 1) * sizeof *rs->start +
                m1 * (sizeof *rs->member + sizeof *rs->bin) +
                (size_t)K * (sizeof *rs->power + sizeof *rs->kind);
    rs->build_ms = lumis__now_ms() - t0;
    *out = rs;
    return LUMIS_OK;

fail:
    free(weight);
    free(cursor);
    free(units);
    free(work);
    lumis_region_sampler_destroy(rs);
    return st == LUMIS_ERR_OUT_OF_MEMORY
               ? lumis__fail(errors, st, "region sampler: %d x %d: out of memory", w, h)
               : st;
}

int lumis_region_sampler_count(const lumis_region_sampler *rs)
{
    return rs ? rs->count : 0;
}

lumis_light_kind lumis_region_sampler_kind(const lumis_region_sampler *rs, int region)
{
    return rs && region >= 0 && region < rs->count ? rs->kind[region] : LUMIS_LIGHT_REGION;
}

void lumis_region_sampler_power(const lumis_region_sampler *rs, int region, double power[3])
{
    for (int c = 0; c < 3; c++)
        power[c] = rs && region >= 0 && region < rs->count ? rs->power[region][c] : 0.0;
}

int lumis_region_sampler_empty(const lumis_region_sampler *rs, int region)
{
    return !rs || region < 0 || region >= rs->count || rs->start[region] == rs->start[region + 1];
}

/* A batch, in stages so that the cache misses of a batch overlap instead of following one
 * another: every bin is requested, then every draw reads its bin and requests its entry,
 * then every direction is placed (its pixel's radiance requested), then the radiance is
 * read.  Each result is what a draw alone gives. */
void lumis_region_sampler_sample_n(const lumis_region_sampler *rs, const int *regions,
                                   const double *u, size_t n, lumis_env_sample *out)
{
    enum { BATCH = 32 };
    uint32_t entry[BATCH];
    size_t pixel[BATCH];
    double st[BATCH][2];
    float density[BATCH];
    for (size_t k0 = 0; k0 < n; k0 += BATCH) {
        const size_t m = n - k0 < BATCH ? n - k0 : BATCH;
        for (size_t k = 0; k < m; k++) {
            const int r = regions[k0 + k];
            if (lumis_region_sampler_empty(rs, r)) continue;
            const uint32_t first = rs->start[r], cnt = rs->start[r + 1] - first;
            uint32_t i = (uint32_t)(lumis__clamp_u(u[2 * (k0 + k)]) * cnt);
            if (i >= cnt) i = cnt - 1;
#if defined(__GNUC__) || defined(__clang__)
            __builtin_prefetch(rs->bin + first + i);
#endif
        }
        for (size_t k = 0; k < m; k++) {
            const int r = regions[k0 + k];
            entry[k] = UINT32_MAX;
            if (lumis_region_sampler_empty(rs, r)) continue;
            const uint32_t first = rs->start[r];
            const lumis__alias table = {rs->bin + first, rs->start[r + 1] - first};
            entry[k] = first + lumis__alias_sample(&table, lumis__clamp_u(u[2 * (k0 + k)]),
                                                   lumis__clamp_u(u[2 * (k0 + k) + 1]), &st[k][0],
                                                   &st[k][1], &density[k]);
#if defined(__GNUC__) || defined(__clang__)
            __builtin_prefetch(rs->member + entry[k]);
#endif
        }
        for (size_t k = 0; k < m; k++) {
            lumis_env_sample *o = &out[k0 + k];
            if (entry[k] == UINT32_MAX) {
                memset(o, 0, sizeof *o);
                continue;
            }
            const uint32_t p = rs->member[entry[k]];
            /* p / w by a multiplication; the estimate is off by at most one either way */
            int64_t j = (int64_t)((double)p * rs->inv_w), i = (int64_t)p - j * rs->w;
            if (i < 0) j--, i += rs->w;
            if (i >= rs->w) j++, i -= rs->w;
            pixel[k] = lumis__envmap_place(rs->env, (int)i, (int)j, st[k][0], st[k][1], &o->dir);
            o->pdf = density[k];
        }
        for (size_t k = 0; k < m; k++)
            if (entry[k] != UINT32_MAX)
                out[k0 + k].radiance = lumis__envmap_radiance(rs->env, pixel[k]);
    }
}

lumis_env_sample lumis_region_sampler_sample(const lumis_region_sampler *rs, int region, double u1,
                                             double u2)
{
    const double u[2] = {u1, u2};
    lumis_env_sample r;
    lumis_region_sampler_sample_n(rs, &region, u, 1, &r);
    return r;
}

float lumis_region_sampler_lookup(const lumis_region_sampler *rs, lumis_vec3 dir, int *region,
                                  lumis_rgb *radiance_out)
{
    int i = 0, j = 0;
    if (!rs || (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f)) {
        if (region) *region = -1;
        if (radiance_out) radiance_out->r = radiance_out->g = radiance_out->b = 0.0f;
        return 0.0f;
    }
    lumis_envmap_dir_to_pixel(rs->env, dir, &i, &j);
    const size_t p = (size_t)j * (size_t)rs->w + (size_t)i;
    if (region) *region = rs->px[p].region;
    if (radiance_out) *radiance_out = lumis__envmap_radiance(rs->env, p);
    return rs->px[p].density;
}

float lumis_region_sampler_pdf(const lumis_region_sampler *rs, int region, lumis_vec3 dir)
{
    int r = -1;
    const float d = lumis_region_sampler_lookup(rs, dir, &r, NULL);
    return r == region ? d : 0.0f;
}

size_t lumis_region_sampler_bytes(const lumis_region_sampler *rs)
{
    return rs ? rs->bytes : 0;
}

double lumis_region_sampler_build_ms(const lumis_region_sampler *rs)
{
    return rs ? rs->build_ms : 0.0;
}
