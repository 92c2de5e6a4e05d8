/* Wu's decomposition ("Efficient Environment Map Rendering based on Decomposition", Wu
 * 2024), assembled stage by stage: the emissive threshold and pixels (Eq. 1,
 * decomp_threshold.c), the light budget (Eq. 2), the EnvDirects (env_direct.c), and the
 * EnvIndirects (illumination_cut.c), into one set.  docs/lights.md. */
#include "decomp.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* One pixel of indirect_rect: its terms (zeros unless it is non-emissive) into s. */
static inline void pixel_terms(const lumis__decomp *dc, const float *row, size_t o, int i,
                               int32_t label, double s[8], int *n)
{
    const lumis__geom *g = dc->g;
    const int in = lumis__non_emissive(dc, o + (size_t)i);
    const double mk = in, v = (double)lumis__pixel_y(row + (size_t)i * 3, g->scale) * mk;
    const float *px = row + (size_t)i * 3;
    s[0] += (double)px[0] * mk;
    s[1] += (double)px[1] * mk;
    s[2] += (double)px[2] * mk;
    s[3] += v;
    s[4] += v * g->cs[i];
    s[5] += v * g->cc[i];
    s[6] += g->cs[i] * mk;
    s[7] += g->cc[i] * mk;
    if (in) dc->labels[o + (size_t)i] = label;
    *n += in;
}

/* An aligned EnvIndirect's sums from the tiles: power and moments of its non-emissive
 * pixels; the geometric moment and solid angle of the whole rectangle, from which the
 * clustered emissive pixels inside are subtracted afterwards. */
static void tiles_rect_acc(const lumis__tiles *t, const lumis__geom *g, lumis__rect r,
                           lumis__acc *acc)
{
    memset(acc, 0, sizeof *acc);
    const lumis__rect tr = lumis__tiles_of(t, r);
    const size_t W = (size_t)t->tw + 1;
    for (int ty = tr.y0; ty < tr.y1; ty++) {
        const size_t o = (size_t)(ty + 1) * W + 1;
        const double *cr = t->rgb[0] + o, *cg = t->rgb[1] + o, *cb = t->rgb[2] + o;
        double s0 = 0.0, s1 = 0.0, s2 = 0.0; /* three independent chains */
        for (int tx = tr.x0; tx < tr.x1; tx++) {
            s0 += cr[tx];
            s1 += cg[tx];
            s2 += cb[tx];
        }
        acc->rgb[0] += s0;
        acc->rgb[1] += s1;
        acc->rgb[2] += s2;
    }
    acc->m[0] = lumis__sat_rect(t->q[LUMIS__Q_MX], t->tw, tr);
    acc->m[1] = lumis__sat_rect(t->q[LUMIS__Q_MY], t->tw, tr);
    acc->m[2] = lumis__sat_rect(t->q[LUMIS__Q_MZ], t->tw, tr);
    acc->pixels = (int)llround(lumis__sat_rect(t->q[LUMIS__Q_N], t->tw, tr));
    lumis__acc_rect_geometry(g, r, acc);
}

/* lumis__acc_rect for an EnvIndirect that is not aligned to the tiles: labels the
 * non-emissive pixels of r and adds them to acc, reading each pixel's luminance from y
 * instead of recomputing it.  Another pixel is added as zeros (multiplied by a 0/1 mask,
 * exact for finite values); two interleaved accumulators per sum halve the add-latency
 * chains. */
static void indirect_rect(const lumis__decomp *dc, lumis__rect r, int32_t label, lumis__acc *acc)
{
    const lumis__geom *g = dc->g;
    const int w = g->w;
    for (int j = r.y0; j < r.y1; j++) {
        const size_t o = (size_t)j * (size_t)w;
        const float *row = dc->env->pixels + o * 3;
        double s0[8] = {0, 0, 0, 0, 0, 0, 0, 0}, s1[8] = {0, 0, 0, 0, 0, 0, 0, 0};
        int n = 0, i = r.x0;
        for (; i + 1 < r.x1; i += 2) {
            pixel_terms(dc, row, o, i, label, s0, &n);
            pixel_terms(dc, row, o, i + 1, label, s1, &n);
        }
        if (i < r.x1) pixel_terms(dc, row, o, i, label, s0, &n);
        double t[8];
        for (int k = 0; k < 8; k++) t[k] = s0[k] + s1[k];
        const double om = g->omega[j];
        acc->rgb[0] += t[0] * om;
        acc->rgb[1] += t[1] * om;
        acc->rgb[2] += t[2] * om;
        acc->m[0] += g->a[j] * t[4];
        acc->m[1] += g->b[j] * t[3];
        acc->m[2] += g->a[j] * t[5];
        acc->g[0] += g->a[j] * t[6];
        acc->g[1] += g->b[j] * n;
        acc->g[2] += g->a[j] * t[7];
        acc->omega += om * n;
        acc->pixels += n;
    }
}

/* The smallest d . p over the patches of each cluster's pixels (mind[k] starts at 1), the
 * exact patch minimum (lumis__rect_min_dot, two atan2) evaluated only where it can be the
 * smallest: a patch lies within rho of its centre c, so its minimum is at least
 * cos(angle(d, c) + rho) and at most d . c; a pixel whose lower bound exceeds its
 * cluster's least d . c cannot hold the minimum.  The result is that of evaluating every
 * pixel. */
static void direct_extents(const lumis__decomp *dc, int nd, double (*dirs)[3], double *mind)
{
    const lumis__geom *g = dc->g;
    const int w = dc->w, h = dc->h;
    const double dth = LUMIS_PI / h, dph = 2.0 * LUMIS_PI / w;
    const double kt = 0.5 / cos(0.5 * dth), kp = 0.5 / cos(0.5 * dph);
    double *ub = malloc((size_t)(nd > 0 ? nd : 1) * sizeof(double));
    if (!ub) { /* no room for the bounds: every pixel exactly */
        for (int e = 0; e < dc->m; e++) {
            const int cl = dc->em_cluster[e];
            if (cl < 0) continue;
            const int j = (int)(dc->em_pix[e] / w), i = (int)(dc->em_pix[e] % w);
            mind[cl] = fmin(mind[cl], lumis__rect_min_dot(g, dirs[cl], j, j + 1, i, i + 1));
        }
        return;
    }
    for (int k = 0; k < nd; k++) ub[k] = 1.0;
    int row = -1;
    double cr = 1.0, sr = 0.0;
    for (int pass = 0; pass < 2; pass++)
        for (int e = 0; e < dc->m; e++) {
            const int cl = dc->em_cluster[e];
            if (cl < 0) continue;
            const int j = (int)(dc->em_pix[e] / w), i = (int)(dc->em_pix[e] % w);
            /* the patch centre, by the half-angle formulas from the edges */
            const double ct = (g->cos_t[j] + g->cos_t[j + 1]) * kt,
                         st = (g->sin_t[j] + g->sin_t[j + 1]) * kt;
            const double cp = (g->cos_p[i] + g->cos_p[i + 1]) * kp,
                         sp = (g->sin_p[i] + g->sin_p[i + 1]) * kp;
            const double *d = dirs[cl];
            const double dc_ = d[0] * st * cp + d[1] * ct + d[2] * st * sp;
            if (pass == 0) {
                ub[cl] = dc_ < ub[cl] ? dc_ : ub[cl];
                continue;
            }
            /* rho: half the row's height plus half its widest width, a path along a
             * meridian and a parallel no shorter than the way to any point of the patch */
            if (j != row) { /* pixels come in scan order: once per row */
                const double rho =
                    (0.5 * dth + 0.5 * dph * fmax(g->sin_t[j], g->sin_t[j + 1])) * (1.0 + 1e-9);
                row = j;
                cr = cos(rho);
                sr = sin(rho);
            }
            const double lb = dc_ < -cr ? -1.0 : dc_ * cr - sqrt(fmax(0.0, 1.0 - dc_ * dc_)) * sr;
            if (lb - 1e-9 > ub[cl]) continue;
            mind[cl] = fmin(mind[cl], lumis__rect_min_dot(g, d, j, j + 1, i, i + 1));
        }
    free(ub);
}

static lumis_status check_desc(const lumis_decomp_desc *d, const lumis_error_sink *err)
{
    const char *bad = NULL;
    if ((unsigned)d->variant >= LUMIS_DECOMP_VARIANT_COUNT)
        bad = "variant is unknown";
    else if ((unsigned)d->cut >= LUMIS_CUT_COUNT)
        bad = "cut objective is unknown";
    else if ((unsigned)d->mask_radius >= LUMIS_MASK_COUNT)
        bad = "mask radius reading is unknown";
    else if (!(d->percentile >= 0.0f && d->percentile <= 100.0f))
        bad = "percentile must be in (0, 100] (0 == 98)";
    else if (!(d->lambda >= 0.0f) || !isfinite(d->lambda))
        bad = "lambda must be finite and >= 0";
    else if (!(d->gamma >= 0.0f) || !isfinite(d->gamma))
        bad = "gamma must be finite and >= 0";
    else if (!(d->threshold >= 0.0f) || !isfinite(d->threshold))
        bad = "threshold must be finite and >= 0 (0 == Eq. 1)";
    else if (!(d->budget_a >= 0.0f) || !isfinite(d->budget_a) || !(d->budget_b >= 0.0f) ||
             !isfinite(d->budget_b))
        bad = "budget exponents a and b must be finite and >= 0 (0 == 1 and 1/4)";
    else if (!(d->min_share >= 0.0f && d->min_share <= 1.0f))
        bad = "min_share must be in [0, 1] (0 == Eq. 2 alone)";
    else if (!(d->mask_scale >= 0.0f) || !isfinite(d->mask_scale))
        bad = "mask scale s must be finite and >= 0 (0 == 0.15)";
    else if (!(d->return_factor >= 0.0f) || !isfinite(d->return_factor))
        bad = "return factor must be finite and >= 0 (0 == 2)";
    else if (d->kmeans_max_iterations < 0)
        bad = "kmeans_max_iterations must be >= 0";
    else if (!(d->w_v >= 0.0f && d->w_d >= 0.0f && d->w_e >= 0.0f) || !isfinite(d->w_v) ||
             !isfinite(d->w_d) || !isfinite(d->w_e))
        bad = "cut weights must be finite and >= 0 (0 == 1, 5, 1)";
    if (bad) return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT, "decomposition: %s", bad);
    return LUMIS_OK;
}

static double def(float v, double d)
{
    return v > 0.0f ? (double)v : d;
}

/* ---- Eq. 2: N = K G_em / (G_em + G_nem), G = L^a dw^b, L the mean luminance ---- */
static int eq2_budget(const lumis__decomp *dc, const double *rowsum, int K,
                      lumis_light_set_info *info)
{
    const lumis__geom *g = dc->g;
    const lumis_decomp_desc *desc = dc->desc;
    const int w = dc->w, h = dc->h, m = dc->m;
    double e_em = 0.0, o_em = 0.0, e_ne = 0.0, o_ne = 0.0;
    for (int j = 0; j < h; j++) {
        const double rem = rowsum[h + j], cem = rowsum[2 * h + j];
        e_em += rem * g->omega[j];
        o_em += cem * g->omega[j];
        e_ne += (cem < w ? fmax(0.0, rowsum[j] - rem) : 0.0) * g->omega[j];
        o_ne += (w - cem) * g->omega[j];
    }
    const long long n_ne = (long long)w * h - m;
    const double ea = def(desc->budget_a, 1.0), eb = def(desc->budget_b, 0.25);
    double g_em = o_em > 0.0 ? pow(e_em / o_em, ea) * pow(o_em, eb) : 0.0;
    double g_ne = o_ne > 0.0 ? pow(e_ne / o_ne, ea) * pow(o_ne, eb) : 0.0;
    info->gamma_em = g_em;
    info->gamma_nem = g_ne;
    long long N = g_em + g_ne > 0.0 ? llround(K * g_em / (g_em + g_ne)) : 0;
    if (desc->min_share > 0.0f && e_em + e_ne > 0.0) {
        /* each class at least min_share of its power's share of the lights */
        const double p_em = e_em / (e_em + e_ne), q = desc->min_share;
        const long long lo = (long long)ceil(q * K * p_em - 1e-9),
                        hi = K - (long long)ceil(q * K * (1.0 - p_em) - 1e-9);
        if (N < lo) N = lo;
        if (N > hi) N = hi;
    }
    if (m > 0 && N < 1) N = 1;            /* emissive pixels get at least one EnvDirect */
    if (n_ne > 0 && N > K - 1) N = K - 1; /* ... and the rest at least one EnvIndirect */
    if (n_ne == 0) N = K;
    if (N > m) N = m;
    info->budget = (int)N;
    return (int)N;
}

/* The emissive pixels' directions and weights (em_d, em_w, em_e) for the EnvDirect step. */
static lumis_status direct_inputs(lumis__decomp *dc)
{
    const lumis__geom *g = dc->g;
    const int m = dc->m, w = dc->w;
    dc->em_d = malloc(3 * (size_t)(m > 0 ? m : 1) * sizeof(double));
    dc->em_w = malloc((size_t)(m > 0 ? m : 1) * sizeof(double));
    dc->em_e = malloc((size_t)(m > 0 ? m : 1) * sizeof(double));
    dc->em_cluster = malloc((size_t)(m > 0 ? m : 1) * sizeof(int32_t));
    if (!dc->em_d || !dc->em_w || !dc->em_e || !dc->em_cluster) return LUMIS_ERR_OUT_OF_MEMORY;
    for (int e = 0; e < m; e++) {
        int j = (int)(dc->em_pix[e] / w), i = (int)(dc->em_pix[e] % w);
        double mx = g->a[j] * g->cs[i], my = g->b[j], mz = g->a[j] * g->cc[i];
        double len = sqrt(mx * mx + my * my + mz * mz);
        dc->em_d[3 * e] = mx / len;
        dc->em_d[3 * e + 1] = my / len;
        dc->em_d[3 * e + 2] = mz / len;
        const double ye = lumis__pixel_y(dc->env->pixels + 3 * (size_t)dc->em_pix[e], g->scale);
        dc->em_w[e] = ye * len;
        dc->em_e[e] = ye * g->omega[j];
    }
    return LUMIS_OK;
}

/* The EnvDirect step's parameters: the variant's steps, the mask's radius (the cap of
 * solid angle s 4 pi / K, or s 4 pi / K radians) and the return radius. */
static lumis__direct_params direct_params(const lumis_decomp_desc *desc, int K, int N)
{
    lumis_decomp_variant var = desc->variant ? desc->variant : LUMIS_DECOMP_FULL;
    lumis__direct_params dp;
    memset(&dp, 0, sizeof dp);
    dp.budget = N;
    dp.mask = var == LUMIS_DECOMP_IS_MASK || var == LUMIS_DECOMP_FULL;
    dp.kmeans = var == LUMIS_DECOMP_IS_KMEANS || var == LUMIS_DECOMP_FULL;
    const double s = def(desc->mask_scale, 0.15);
    if (desc->mask_radius == LUMIS_MASK_RADIANS) {
        dp.mask_radius = s * 4.0 * LUMIS_PI / K;
    } else { /* the cap of solid angle s 4 pi / K: 2 pi (1 - cos r) = s 4 pi / K */
        double q = s / K;
        dp.mask_radius = q >= 1.0 ? LUMIS_PI : 2.0 * asin(sqrt(q));
    }
    dp.return_radius = def(desc->return_factor, 2.0) * dp.mask_radius;
    dp.max_iterations = desc->kmeans_max_iterations;
    dp.seed = desc->seed;
    return dp;
}

/* The clusters' sums into acc; when the EnvDirects took the whole budget and pixels came
 * back to the non-emissive set (which then needs a light), the weakest cluster is given
 * back too.  Returns the clusters kept. */
static int direct_sums(lumis__decomp *dc, int nd, int K, long long ne_final, int *returned,
                       lumis__acc *acc)
{
    const lumis__geom *g = dc->g;
    const int m = dc->m, w = dc->w;
    for (int e = 0; e < m; e++) {
        int cl = dc->em_cluster[e];
        if (cl >= 0)
            lumis__acc_pixel(g, dc->env, &acc[cl], (int)(dc->em_pix[e] % w),
                             (int)(dc->em_pix[e] / w));
    }
    if (!(ne_final > 0 && nd >= K)) return nd;
    /* Give the weakest cluster back to the non-emissive set. */
    int weakest = 0;
    for (int k = 1; k < nd; k++)
        if (acc[k].rgb[0] + acc[k].rgb[1] + acc[k].rgb[2] <
            acc[weakest].rgb[0] + acc[weakest].rgb[1] + acc[weakest].rgb[2])
            weakest = k;
    for (int e = 0; e < m; e++) {
        int cl = dc->em_cluster[e];
        if (cl == weakest) {
            dc->em_cluster[e] = -1;
            dc->labels[dc->em_pix[e]] = -1;
            ++*returned;
        } else if (cl > weakest) {
            dc->em_cluster[e] = cl - 1;
            dc->labels[dc->em_pix[e]] = cl - 1;
        }
    }
    memmove(&acc[weakest], &acc[weakest + 1], (size_t)(nd - weakest - 1) * sizeof *acc);
    return nd - 1;
}

/* The tiles holding emissive pixels, summed again over their non-emissive pixels now that
 * the returned ones are known (the others hold only non-emissive pixels); then their
 * summed-area tables.  tile_of: scratch of (tw + 1)(th + 1) zeros. */
static void retile(lumis__tiles *tiles, const lumis__decomp *dc, int32_t *tile_of)
{
    const size_t TW = (size_t)tiles->tw + 1;
    for (int e = 0; e < dc->m; e++) {
        const int i = (int)(dc->em_pix[e] % dc->w), j = (int)(dc->em_pix[e] / dc->w);
        const int tx = i / tiles->T, ty = j / tiles->T;
        int32_t *f = &tile_of[(size_t)(ty + 1) * TW + (size_t)tx + 1];
        if (*f) continue;
        *f = 1;
        lumis__decomp_dirty_tile(tiles, dc, tx, ty);
    }
    lumis__tiles_prefix(tiles);
}

/* The EnvDirects' lights (nd of them, from acc) with their extents. */
static lumis_status direct_lights(const lumis__decomp *dc, int nd, const lumis__acc *acc,
                                  lumis_light *lights)
{
    for (int k = 0; k < nd; k++)
        lumis__light_from_acc(dc->g, &acc[k], LUMIS_LIGHT_ENV_DIRECT, &lights[k]);
    double *mind = malloc((size_t)(nd > 0 ? nd : 1) * sizeof(double)), (*dirs)[3] = NULL;
    dirs = malloc((size_t)(nd > 0 ? nd : 1) * sizeof *dirs);
    if (!mind || !dirs) {
        free(mind);
        free(dirs);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    for (int k = 0; k < nd; k++) {
        mind[k] = 1.0;
        lumis__light_map_dir(dc->g, &lights[k], dirs[k]);
    }
    direct_extents(dc, nd, dirs, mind);
    for (int k = 0; k < nd; k++) lights[k].extent = lumis__extent_from_min_dot(mind[k]);
    free(mind);
    free(dirs);
    return LUMIS_OK;
}

/* The EnvIndirects' lights (ni rectangles, labels nd + k) into lights[nd ..]: an aligned
 * rectangle's sums come from the tiles (tile_of[t] = its index + 1 for its tiles), with its
 * clustered emissive pixels' geometry taken out; any other is summed from its pixels.
 * tile_of: scratch of (tw + 1)(th + 1). */
static void indirect_lights(lumis__decomp *dc, const lumis__tiles *tiles, int nd, int ni,
                            const lumis__rect *rects, int32_t *tile_of, lumis__acc *ia,
                            lumis_light *lights)
{
    const lumis__geom *g = dc->g;
    const int w = dc->w, h = dc->h;
    const size_t TW = (size_t)tiles->tw + 1;
    memset(tile_of, 0, TW * ((size_t)tiles->th + 1) * sizeof(int32_t));
    for (int k = 0; k < ni; k++) {
        if (!lumis__tiles_aligned(tiles, w, h, rects[k])) {
            memset(&ia[k], 0, sizeof ia[k]);
            indirect_rect(dc, rects[k], nd + k, &ia[k]);
            continue;
        }
        tiles_rect_acc(tiles, g, rects[k], &ia[k]);
        lumis__fill_labels(dc->labels, w, rects[k], nd + k);
        const lumis__rect tr = lumis__tiles_of(tiles, rects[k]);
        for (int ty = tr.y0; ty < tr.y1; ty++)
            for (int tx = tr.x0; tx < tr.x1; tx++)
                tile_of[(size_t)(ty + 1) * TW + (size_t)tx + 1] = k + 1;
    }
    for (int e = 0; e < dc->m; e++) {
        if (dc->em_cluster[e] < 0) continue;
        const int i = (int)(dc->em_pix[e] % w), j = (int)(dc->em_pix[e] / w);
        const int32_t k = tile_of[(size_t)(j / tiles->T + 1) * TW + (size_t)(i / tiles->T) + 1] - 1;
        if (k < 0) continue;
        dc->labels[dc->em_pix[e]] = dc->em_cluster[e];
        const double mx = g->a[j] * g->cs[i], mz = g->a[j] * g->cc[i];
        ia[k].g[0] -= mx;
        ia[k].g[1] -= g->b[j];
        ia[k].g[2] -= mz;
        ia[k].omega -= g->omega[j];
    }
    for (int k = 0; k < ni; k++) {
        lumis_light *l = &lights[nd + k];
        lumis__light_from_acc(g, &ia[k], LUMIS_LIGHT_ENV_INDIRECT, l);
        double d[3];
        lumis__light_map_dir(g, l, d);
        l->extent = lumis__extent_from_min_dot(
            lumis__rect_min_dot(g, d, rects[k].y0, rects[k].y1, rects[k].x0, rects[k].x1));
    }
}

lumis_status lumis_lights_decompose(const lumis_envmap *env, const lumis_decomp_desc *desc,
                                    lumis_light_set **out)
{
    static const lumis_decomp_desc zero_desc;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!desc) desc = &zero_desc;
    const double t0 = lumis__now_ms();
    lumis__common c;
    lumis_status st = lumis__common_check(env, "decomposition", desc->count, desc->sets,
                                          desc->jitter, desc->seed, &desc->errors, &c);
    if (st != LUMIS_OK) return st;
    if ((st = check_desc(desc, c.errors)) != LUMIS_OK) return st;
    const lumis_error_sink *err = c.errors;
    lumis__geom g;
    if (lumis__geom_init(&g, env) != LUMIS_OK)
        return lumis__fail(err, LUMIS_ERR_OUT_OF_MEMORY, "decomposition: out of memory");
    const int K = c.count, w = g.w, h = g.h;
    lumis_light_set *set = NULL;
    double *rowsum = calloc(3 * (size_t)h, sizeof(double)); /* per row: Y, emissive Y, count */
    lumis__rect *rects = malloc((size_t)K * sizeof *rects);
    lumis__acc *acc = calloc((size_t)K, sizeof *acc);
    lumis__decomp dc;
    memset(&dc, 0, sizeof dc);
    lumis__direct_result dr;
    memset(&dr, 0, sizeof dr);
    lumis__tiles tiles;
    memset(&tiles, 0, sizeof tiles);
    int32_t *tile_of = NULL;
    st = (rowsum && rects && acc)
             ? lumis__set_create(env, &c, K, LUMIS_LIGHTS_DECOMPOSITION, 0, &set)
             : LUMIS_ERR_OUT_OF_MEMORY;
    if (st == LUMIS_OK) st = lumis__tiles_init(&tiles, w, h);
    if (st == LUMIS_OK) {
        tile_of = calloc(((size_t)tiles.tw + 1) * ((size_t)tiles.th + 1), sizeof(int32_t));
        if (!tile_of) st = LUMIS_ERR_OUT_OF_MEMORY;
    }
    if (st != LUMIS_OK) goto done;
    lumis_light_set_info *info = &set->info;
    dc.env = env;
    dc.g = &g;
    dc.desc = desc;
    dc.w = w;
    dc.h = h;
    dc.labels = set->labels;

    /* Eq. 1: the threshold and the emissive pixels; Eq. 2: the EnvDirects' share of K */
    if ((st = lumis__decomp_threshold(&dc, &tiles, rowsum, info)) != LUMIS_OK) goto done;
    info->emissive_pixels = dc.m;
    const int N = eq2_budget(&dc, rowsum, K, info);

    /* EnvDirects: importance-sampled seeds, masks, k-means, returns */
    if ((st = direct_inputs(&dc)) != LUMIS_OK) goto done;
    const lumis__direct_params dp = direct_params(desc, K, N);
    info->mask_radius = dp.mask_radius;
    if ((st = lumis__env_direct(&dc, &dp, &dr)) != LUMIS_OK) goto done;
    info->seeds = dr.seeds;
    info->kmeans_iterations = dr.iterations;
    info->kmeans_converged = dr.converged;
    set->kmeans_objective = dr.objective;
    dr.objective = NULL;
    info->kmeans_objective = set->kmeans_objective;
    info->kmeans_objective_count = dr.objective_count;
    const long long ne_final = (long long)w * h - dc.m + dr.returned;
    const int nd = direct_sums(&dc, dr.clusters, K, ne_final, &dr.returned, acc);
    info->returned_pixels = dr.returned;

    /* EnvIndirects: the illumination cut over the non-emissive pixels' tiles */
    retile(&tiles, &dc, tile_of);
    int ni = 0;
    lumis_cut_objective cut = desc->cut ? desc->cut : LUMIS_CUT_MODIFIED;
    st = lumis__illumination_cut(&dc, &tiles, K - nd, cut, def(desc->w_v, 1.0), def(desc->w_d, 5.0),
                                 def(desc->w_e, 1.0), rects, &ni);
    if (st != LUMIS_OK) goto done;

    /* the lights */
    if ((st = direct_lights(&dc, nd, acc, set->lights)) != LUMIS_OK) goto done;
    indirect_lights(&dc, &tiles, nd, ni, rects, tile_of, acc + nd /* nd + ni <= K */, set->lights);
    set->count = nd + ni;
    info->direct = nd;
    info->indirect = ni;
    if (set->count < K)
        lumis__fail(err, LUMIS_OK,
                    "decomposition: %d lights instead of %d: the masked emissive pixels gave %d "
                    "clusters and the %lld non-emissive pixels cannot hold more",
                    set->count, K, nd, ne_final);
    lumis__set_finish(set, &g, env, &c, t0);

done:
    free(tile_of);
    lumis__tiles_free(&tiles);
    free(rowsum);
    free((void *)dc.em_bits);
    free(rects);
    free(acc);
    free(dc.em_pix);
    free(dc.em_d);
    free(dc.em_w);
    free(dc.em_e);
    free(dc.em_cluster);
    free(dr.objective);
    lumis__geom_free(&g);
    if (st != LUMIS_OK) {
        lumis_light_set_destroy(set);
        return lumis__fail(err, st, "decomposition: %s", lumis_status_string(st));
    }
    *out = set;
    return LUMIS_OK;
}
