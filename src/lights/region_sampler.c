/* Region samplers: each region of a light set's partition as a stratum of the map, sampled
 * in proportion to luminance times solid angle inside it (docs/lights.md, "Stratified
 * mode").
 *
 * A draw inverts the region's distribution in two dimensions: u1 picks a row of the
 * region by its marginal CDF, u2 a pixel of that row by the row's conditional CDF, and
 * where each fell inside the share it picked places the direction inside the pixel (u1
 * along cos theta, u2 along the azimuth).  The map is monotone in each coordinate, so a
 * stratified (low-discrepancy) set of 2-D points stays stratified over the region and
 * inside its pixels; an alias table (one lookup, no search) scattered it
 * (docs/results/tenth).  Guide tables (the cutpoint method: for each of n equal slices of
 * a CDF of n cells, the cell the slice starts in) make both searches a lookup and about
 * one step on average.
 *
 * Layout: the pixels of nonzero luminance ("entries"), grouped by region and in scan order
 * inside one, so that a region's rows are consecutive runs of entries: 16 bytes each (the
 * region's units before the entry, its column) and a 4-byte guide slot each (the row's
 * slice whose number is the entry's position in the row).  The rows of all regions, 40
 * bytes each with their guide slot (small: a few thousand rows at K = 32).  Per pixel of
 * the map, its region and its density in that region's sampler, so pdf() and the lookup
 * of a BSDF-sampled direction read 8 bytes.  Every region's probabilities are quantised
 * as the alias sampler's (integer units, 2^32 per pixel on average, each pixel that shines
 * at least one, src/core/distrib.h; fewer a pixel in a region of more than 2^21 pixels, so
 * that its cumulative units stay integers a double holds exactly), and a draw computes its density
 * from its entry's units by the very operations that stored the pixel's, so sample() and pdf() give
 * the same float. */
#include "lumis/lights.h"

#include "../core/distrib.h"
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A pixel of the map: its region (-1: none) and its density per steradian in it. */
typedef struct region_px {
    int32_t region;
    float density;
} region_px;

/* A pixel that shines, in its region.  cum: the region's units before it, integers of at
 * most 2^53 (unit_shift), so exact: every entry keeps its units >= 1 and its density > 0. */
typedef struct region_entry {
    double cum;
    uint32_t col;    /* its column (its row is the row's) */
    uint32_t unused; /* (16 bytes: four to a cache line) */
} region_entry;

/* A row of a region: its entries are [first, the next row's first). */
typedef struct region_row {
    double cum;     /* the region's units before the row */
    double inv;     /* 1 / the row's units */
    double scale;   /* an entry's density per unit: density_scale() */
    uint32_t first; /* its first entry */
    uint32_t j;     /* the map's row */
    uint32_t guide; /* for the row at position q of its region: slice q of the region's
                       units starts in the region's row number guide */
    uint32_t unused;
} region_row;

struct lumis_region_sampler {
    const lumis_envmap *env; /* retained */
    int w, h, count;
    double inv_w;           /* 1 / w */
    double (*col)[2];       /* w, or NULL on maps narrower than PLACE_MIN_W: column i's
                               direction (cos, sin of the azimuth of its centre, rotation
                               applied) */
    region_px *px;          /* w * h */
    uint32_t *start;        /* count + 1: region k's entries are [start[k], start[k + 1]) */
    uint32_t *rstart;       /* count + 1: region k's rows are [rstart[k], rstart[k + 1]) */
    region_entry *entry;    /* by region, scan order inside one; and two spare */
    uint32_t *guide;        /* per entry: for the entry at position q of its row, slice q of
                               the row's units starts in the row's entry number guide[] */
    region_row *row;        /* the regions' rows; and two spare (first: the entries' count) */
    double (*power)[3];     /* count: sum over the region of L Omega (scale applied) */
    lumis_light_kind *kind; /* count: what the region's light stands for */
    double build_ms;
    size_t bytes;
};

void lumis_region_sampler_destroy(lumis_region_sampler *rs)
{
    if (!rs) return;
    free(rs->px);
    free(rs->col);
    free(rs->start);
    free(rs->rstart);
    free(rs->entry);
    free(rs->guide);
    free(rs->row);
    free(rs->power);
    free(rs->kind);
    lumis_envmap_destroy((lumis_envmap *)rs->env);
    free(rs);
}

/* The units a pixel of a region of `size` pixels gets on average, 2^shift: 2^32, or fewer
 * where size x 2^32 would pass 2^53 (a region of more than 2^21 pixels), so that the
 * region's cumulative units are integers a double holds exactly.  At 2^32 units the
 * rounding had merged a dim pixel's one unit with its neighbour's: a pixel that shines at
 * density 0, and draws of pdf 0 (test_regions, region_of_more_than_2p21_pixels). */
static inline int unit_shift(uint32_t size)
{
    int s = 32;
    while (s > 0 && ((uint64_t)size << s) > ((uint64_t)1 << 53)) s--;
    return s;
}

/* A region's units as a double: its pixels' count times 2^unit_shift. */
static inline double region_total(const lumis_region_sampler *rs, int k)
{
    const uint32_t size = rs->start[k + 1] - rs->start[k];
    return (double)((uint64_t)size << unit_shift(size));
}

/* An entry's density per unit, in map row j of a region of `total` units: probability
 * over solid angle.  Its density is its units times this, at build and draw alike. */
static inline double density_scale(const lumis_envmap *env, double total, uint32_t j)
{
    return 1.0 / (total * env->row_solid_angle[j]);
}

/* Placing a direction inside its pixel: from the column's direction (rs->col) turned by
 * the small angle d = 2 pi (s - 1/2) / w, |d| <= pi / w, whose sine and cosine take a
 * short series (truncated after d^5 and d^6: errors below d^7 / 7! and d^8 / 8!, 1.7e-11
 * at w = 32, as small as the samplers' warp's 2e-9 needs), instead of the sine and cosine
 * of the whole azimuth and the map's rotation after it.  Narrower maps take the warp. */
#define PLACE_MIN_W 32

/* The guide of n consecutive cells whose lower ends cum(0) < cum(1) < ... lie in [lo, hi):
 * slot q gets the last cell whose lower end is at most the start of slice q,
 * lo + (hi - lo) q / n, less hi 2^-48.  A draw whose u falls in slice q (q = floor(u n))
 * looks for its point lo + u (hi - lo) from there, forward only: computed with at most
 * three roundings of under hi 2^-53 each (u n, u (hi - lo), the sum), the point is never
 * below the slot's start by more than that, and the margin covers it many times, so the
 * slot's cell never lies past the point. */
#define BUILD_GUIDE(n, lo, hi, cum, slot)                                                          \
    do {                                                                                           \
        uint32_t c_ = 0;                                                                           \
        for (uint32_t q_ = 0; q_ < (n); q_++) {                                                    \
            const double x_ = (lo) + ((hi) - (lo)) * ((double)q_ / (double)(n)) - (hi)*0x1p-48;    \
            while (c_ + 1 < (n) && (cum(c_ + 1)) <= x_) c_++;                                      \
            slot(q_) = c_;                                                                         \
        }                                                                                          \
    } while (0)

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
    rs->inv_w = 1.0 / w;
    rs->count = K;
    rs->px = malloc(n * sizeof *rs->px);
    rs->start = calloc((size_t)K + 1, sizeof *rs->start);
    rs->rstart = calloc((size_t)K + 1, sizeof *rs->rstart);
    rs->power = calloc((size_t)K, sizeof *rs->power);
    rs->kind = malloc((size_t)K * sizeof *rs->kind);
    double *weight = NULL;
    uint64_t *units = NULL;
    uint32_t *cursor = NULL;
    /* per region: the last row seen (pass 1), then the next row's slot (pass 2) */
    int64_t *row_at = malloc(((size_t)K + 1) * sizeof *row_at);
    lumis_status st = LUMIS_ERR_OUT_OF_MEMORY;
    if (!rs->px || !rs->start || !rs->rstart || !rs->power || !rs->kind || !row_at) goto fail;
    if (w >= PLACE_MIN_W) {
        rs->col = malloc((size_t)w * sizeof *rs->col);
        if (!rs->col) goto fail;
        for (int i = 0; i < w; i++) {
            const double a = 2.0 * LUMIS_PI * (i + 0.5) / w, ca = cos(a), sa = sin(a);
            rs->col[i][0] = env->cos_rot * ca - env->sin_rot * sa;
            rs->col[i][1] = env->sin_rot * ca + env->cos_rot * sa;
        }
    }
    /* a region's power is its light's (the set's sum of L Omega over the region) */
    for (int k = 0; k < K; k++) {
        rs->kind[k] = set->lights[k].kind;
        for (int c = 0; c < 3; c++) rs->power[k][c] = set->lights[k].power[c];
        row_at[k] = -1;
    }

    /* Pass 1: each pixel's region, and the regions' sizes (pixels that shine) and rows. */
    const float *pix = env->pixels;
    const double scale = env->scale;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const size_t p = (size_t)j * (size_t)w + (size_t)i;
            const int32_t r = set->labels[p];
            const int shines = lumis__pixel_y(pix + 3 * p, scale) > 0.0f;
            rs->px[p].region = r;
            rs->px[p].density = 0.0f;
            if (r >= 0 && r < K) {
                rs->start[r + 1] += (uint32_t)shines;
                if (shines && row_at[r] != j) rs->rstart[r + 1]++, row_at[r] = j;
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
    uint32_t largest = 0;
    for (int k = 0; k < K; k++) {
        const uint32_t size = rs->start[k + 1];
        if (size > largest) largest = size;
        rs->start[k + 1] = rs->start[k] + size;
        rs->rstart[k + 1] += rs->rstart[k];
    }
    const uint32_t members = rs->start[K], rows = rs->rstart[K];

    /* Pass 2: the entries, region by region (scan order inside one), and their rows.  The
     * spares: a search reads up to two cells after a row's last (its tests discard them),
     * and the last row's entries end at the first spare row's first. */
    const size_t l1 = largest > 0 ? largest : 1u;
    rs->entry = malloc(((size_t)members + 2) * sizeof *rs->entry);
    rs->row = malloc(((size_t)rows + 2) * sizeof *rs->row);
    rs->guide = malloc(((size_t)members + 1) * sizeof *rs->guide);
    cursor = malloc(((size_t)K + 1) * sizeof *cursor);
    /* scratch for one region at a time: the weights and their units */
    weight = malloc(l1 * sizeof *weight);
    units = malloc(l1 * sizeof *units);
    if (!rs->entry || !rs->row || !rs->guide || !weight || !cursor || !units) goto fail;
    memset(rs->entry + members, 0, 2 * sizeof *rs->entry);
    memset(rs->guide + members, 0, sizeof *rs->guide);
    memset(rs->row + rows, 0, 2 * sizeof *rs->row);
    rs->row[rows].first = rs->row[rows + 1].first = members;
    memcpy(cursor, rs->start, ((size_t)K + 1) * sizeof *cursor);
    for (int k = 0; k < K; k++) row_at[k] = rs->rstart[k];
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const size_t p = (size_t)j * (size_t)w + (size_t)i;
            const int32_t r = rs->px[p].region;
            if (r < 0 || !(lumis__pixel_y(pix + 3 * p, scale) > 0.0f)) continue;
            const uint32_t e = cursor[r]++;
            /* the region's first entry in row j opens a row */
            if (e == rs->start[r] || rs->row[row_at[r] - 1].j != (uint32_t)j) {
                rs->row[row_at[r]].first = e;
                rs->row[row_at[r]++].j = (uint32_t)j;
            }
            rs->entry[e].col = (uint32_t)i;
        }

    /* Per region: the units of Y Omega (quantised as the alias sampler's), the entries'
     * and rows' cumulative units, the densities, and the guides. */
    for (int k = 0; k < K; k++) {
        const uint32_t first = rs->start[k], size = rs->start[k + 1] - first;
        if (size == 0) continue;
        const uint32_t r0 = rs->rstart[k], nr = rs->rstart[k + 1] - r0;
        for (uint32_t s = r0; s < r0 + nr; s++) {
            const uint32_t j = rs->row[s].j;
            for (uint32_t e = rs->row[s].first; e < rs->row[s + 1].first; e++)
                weight[e - first] =
                    (double)lumis__pixel_y(pix + 3 * ((size_t)j * (size_t)w + rs->entry[e].col),
                                           scale) *
                    env->row_solid_angle[j];
        }
        lumis__quantize(weight, size, (uint64_t)size << unit_shift(size), units);
        uint64_t acc = 0;
        for (uint32_t e = first; e < first + size; e++) {
            rs->entry[e].cum = (double)acc;
            acc += units[e - first];
        }
        const double total = region_total(rs, k);
        for (uint32_t s = r0; s < r0 + nr; s++) {
            const uint32_t j = rs->row[s].j, e0 = rs->row[s].first, ne = rs->row[s + 1].first - e0;
            /* the row's units: from its first entry's to the next row's first entry's */
            const double lo = rs->entry[e0].cum,
                         up = s + 1 < r0 + nr ? rs->entry[e0 + ne].cum : total;
            const double ds = density_scale(env, total, j);
            rs->row[s].cum = lo;
            rs->row[s].inv = 1.0 / (up - lo);
            rs->row[s].scale = ds;
            for (uint32_t e = e0; e < e0 + ne; e++) {
                const double c1 = e + 1 < e0 + ne ? rs->entry[e + 1].cum : up;
                rs->px[(size_t)j * (size_t)w + rs->entry[e].col].density =
                    (float)((c1 - rs->entry[e].cum) * ds);
            }
#define ENTRY_CUM(c)  rs->entry[e0 + (c)].cum
#define ENTRY_SLOT(q) rs->guide[e0 + (q)]
            BUILD_GUIDE(ne, lo, up, ENTRY_CUM, ENTRY_SLOT);
#undef ENTRY_CUM
#undef ENTRY_SLOT
        }
#define ROW_CUM(c)  rs->row[r0 + (c)].cum
#define ROW_SLOT(q) rs->row[r0 + (q)].guide
        BUILD_GUIDE(nr, 0.0, total, ROW_CUM, ROW_SLOT);
#undef ROW_CUM
#undef ROW_SLOT
    }
    free(weight);
    free(cursor);
    free(units);
    free(row_at);
    rs->bytes = sizeof *rs + n * sizeof *rs->px + 2 * ((size_t)K + 1) * sizeof *rs->start +
                ((size_t)members + 2) * sizeof *rs->entry +
                ((size_t)members + 1) * sizeof *rs->guide + ((size_t)rows + 2) * sizeof *rs->row +
                (size_t)K * (sizeof *rs->power + sizeof *rs->kind) +
                (rs->col ? (size_t)w * sizeof *rs->col : 0);
    rs->build_ms = lumis__now_ms() - t0;
    *out = rs;
    return LUMIS_OK;

fail:
    free(weight);
    free(cursor);
    free(units);
    free(row_at);
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

/* f clamped to [0, 1) (rounding may put a point's position in its cell just outside). */
static inline double clamp_fraction(double f)
{
    return f >= 0.0 ? (f < 1.0 ? f : 0x1.fffffffffffffp-1) : 0.0;
}

/* The slice of n equal slices of [0, 1) that u falls in. */
static inline uint32_t slice(double u, uint32_t n)
{
    const uint32_t q = (uint32_t)(u * n);
    return q < n ? q : n - 1;
}

/* The direction of (s, t) in [0, 1)^2 inside pixel (i, j), uniform in solid angle (s
 * along the azimuth, t along cos theta); returns whether the point is clear of the
 * pixel's edges by LUMIS__EDGE_MARGIN, as lumis__envmap_place_clear (which places it on
 * maps narrower than PLACE_MIN_W). */
static inline int place(const lumis_region_sampler *rs, uint32_t i, uint32_t j, double s, double t,
                        lumis_vec3 *dir)
{
    if (!rs->col) return lumis__envmap_place_clear(rs->env, rs->inv_w, (int)i, (int)j, s, t, dir);
    const double c0 = rs->env->cos_row[j], c1 = rs->env->cos_row[j + 1];
    const double c = c0 + t * (c1 - c0), s2 = (1.0 - c) * (1.0 + c);
    const double st = sqrt(s2 > 0.0 ? s2 : 0.0);
    const double d = (s - 0.5) * (2.0 * LUMIS_PI) * rs->inv_w, d2 = d * d;
    const double sd = d + d * d2 * (-1.0 / 6 + d2 * (1.0 / 120));
    const double cd = 1.0 + d2 * (-0.5 + d2 * (1.0 / 24 + d2 * (-1.0 / 720)));
    const double ca = rs->col[i][0], sa = rs->col[i][1];
    dir->x = (float)(st * (ca * cd - sa * sd));
    dir->y = (float)c;
    dir->z = (float)(st * (sa * cd + ca * sd));
    /* distances to the four edges, in radians (azimuth) and in cos theta */
    const double gx = 1.0 - s, ex = s < gx ? s : gx;
    const double dphi = (2.0 * LUMIS_PI) * rs->inv_w * ex;
    const double up = c0 - c, down = c - c1;
    double e = up < down ? up : down;
    e = dphi < e ? dphi : e;
    return e >= LUMIS__EDGE_MARGIN;
}

/* A batch, in stages so that the cache misses of a batch overlap instead of following one
 * another: every draw requests its row slot; reads it and requests the row; finds its row
 * (the slot's, then usually no step or one) and requests its entry slot; reads that and
 * requests the entry; finds its entry and requests its pixel's radiance; places its
 * direction; reads the radiance.  Each result is what a draw alone gives. */
void lumis_region_sampler_sample_n(const lumis_region_sampler *rs, const int *regions,
                                   const double *u, size_t n, lumis_env_sample *out)
{
    enum { BATCH = 32 };
    uint32_t cell[BATCH], first[BATCH], end[BATCH], j[BATCH];
    double x[BATCH], hi[BATCH], t[BATCH], ds[BATCH];
    size_t pixel[BATCH];
    if (!rs) {
        memset(out, 0, n * sizeof *out);
        return;
    }
    for (size_t k0 = 0; k0 < n; k0 += BATCH) {
        const size_t m = n - k0 < BATCH ? n - k0 : BATCH;
        /* the row: the last whose units before it are at most u1 times the region's (the
         * rows are few, so their slots are cached: no stage of their own) */
        for (size_t k = 0; k < m; k++) {
            const int r = regions[k0 + k];
            if (r < 0 || r >= rs->count || rs->start[r] == rs->start[r + 1]) {
                cell[k] = UINT32_MAX;
                continue;
            }
            const uint32_t r0 = rs->rstart[r], r1 = rs->rstart[r + 1];
            const double total = region_total(rs, r), u1 = lumis__clamp_u(u[2 * (k0 + k)]);
            const double v = u1 * total;
            uint32_t s = r0 + rs->row[r0 + slice(u1, r1 - r0)].guide;
            /* two steps without branches (a mispredicted exit costs more), any more by the
             * loop (the slot's row never lies past v: BUILD_GUIDE) */
            s += (uint32_t)((s + 1 < r1) & (rs->row[s + 1].cum <= v)) +
                 (uint32_t)((s + 2 < r1) & (rs->row[s + 2].cum <= v));
            while (s + 1 < r1 && rs->row[s + 1].cum <= v) s++;
            const double lo = rs->row[s].cum, up = s + 1 < r1 ? rs->row[s + 1].cum : total;
            t[k] = clamp_fraction((v - lo) * rs->row[s].inv);
            /* u2 inverts the row's conditional: a point of the row's units [lo, up) */
            const double u2 = lumis__clamp_u(u[2 * (k0 + k) + 1]);
            first[k] = rs->row[s].first;
            end[k] = rs->row[s + 1].first;
            j[k] = rs->row[s].j;
            hi[k] = up;
            ds[k] = rs->row[s].scale;
            x[k] = lo + u2 * (up - lo);
            cell[k] = first[k] + slice(u2, end[k] - first[k]);
#if defined(__GNUC__) || defined(__clang__)
            __builtin_prefetch(rs->guide + cell[k]);
#endif
        }
        for (size_t k = 0; k < m; k++) {
            if (cell[k] == UINT32_MAX) continue;
            cell[k] = first[k] + rs->guide[cell[k]];
#if defined(__GNUC__) || defined(__clang__)
            __builtin_prefetch(rs->entry + cell[k]);
#endif
        }
        /* the entry: the last of the row whose units before it are at most x */
        for (size_t k = 0; k < m; k++) {
            if (cell[k] == UINT32_MAX) continue;
            uint32_t e = cell[k];
            e += (uint32_t)((e + 1 < end[k]) & (rs->entry[e + 1].cum <= x[k])) +
                 (uint32_t)((e + 2 < end[k]) & (rs->entry[e + 2].cum <= x[k]));
            while (e + 1 < end[k] && rs->entry[e + 1].cum <= x[k]) e++;
            const double lo = rs->entry[e].cum, up = e + 1 < end[k] ? rs->entry[e + 1].cum : hi[k];
            x[k] = clamp_fraction((x[k] - lo) / (up - lo)); /* along the azimuth */
            out[k0 + k].pdf = (float)((up - lo) * ds[k]);
            cell[k] = rs->entry[e].col;
            pixel[k] = (size_t)j[k] * (size_t)rs->w + cell[k];
#if defined(__GNUC__) || defined(__clang__)
            __builtin_prefetch(rs->env->pixels + 3 * pixel[k]);
#endif
        }
        for (size_t k = 0; k < m; k++) {
            lumis_env_sample *o = &out[k0 + k];
            if (cell[k] == UINT32_MAX) {
                memset(o, 0, sizeof *o);
                continue;
            }
            /* x and t are in [0, 1) (clamp_fraction); a point near its pixel's edges
             * (about one in 10^3) goes the long way, which keeps it inside */
            if (!place(rs, cell[k], j[k], x[k], t[k], &o->dir))
                lumis__envmap_place(rs->env, (int)cell[k], (int)j[k], x[k], t[k], &o->dir);
        }
        for (size_t k = 0; k < m; k++)
            if (cell[k] != UINT32_MAX)
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
