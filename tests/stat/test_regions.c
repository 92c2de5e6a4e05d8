/* Statistical tests of the region samplers (lumis_region_sampler: a light set's regions as
 * strata), fixed seeds.  For every light-set method (median cut, variance minimisation,
 * FHIS, TMMS, Wu with its EnvDirects and EnvIndirects, Wu with emissive pixels handed back,
 * and Wu's masked-sampling ablations) on synthetic maps and a sky with a sun:
 *   - each region's pdf integrates to one over the region (and is 0 outside it),
 *   - pdf(sample()) equals the pdf returned while sampling, bit for bit, the sample lies in
 *     its region and carries the map's radiance there,
 *   - a chi-square test of each region's samples against its own pdf,
 *   - the stratified estimate sum_k L(w_k) / p_k(w_k) of the map's power is unbiased (within
 *     4 standard errors of the exact pixel sum), and the regions' powers add up to it,
 *   - a draw is monotone in each of u1 and u2 (2-D inversion: what keeps a stratified set of
 *     points stratified). */
/* Oracles:
 * lumis_region_sampler_create — statistical: region samplers of every light-set method (below);
 *     error paths: no map, no set, another map's set (region_sampler_refuses_mismatches)
 * lumis_region_sampler_destroy — external: leaks seen by ASan and valgrind
 *     (region_pdf_integrates_to_one)
 * lumis_region_sampler_pdf — brute force: each region's pdf integrates to one over sub-cells of its
 *     pixels, 0 outside; density x region power = Y (region_pdf_integrates_to_one)
 * lumis_region_sampler_sample — statistical: chi-square per region against its pdf; the stratified
 *     power estimate within 4 sigma of lumis_envmap_power; draws land in their own pixel at widths
 *     49, 97, 98, 196, 255; property: monotone in u1 (rows, then cos theta) and in u2 (pixels of
 *     the row, then azimuth), as an inversion is; a region of 2^22 pixels: every draw's pdf > 0
 *     and pdf(dir) (region_chi_square, stratified_power_is_unbiased,
 *     samples_land_in_their_pixel_at_awkward_widths, region_draws_are_monotone_in_u,
 *     region_of_more_than_2p21_pixels)
 * lumis_region_sampler_sample_n — consistency: the very samples of lumis_region_sampler_sample
 *     (region_pdf_of_sample_matches)
 * lumis_region_sampler_power — brute force: the regions' powers add to the map's exact pixel sum
 *     (stratified_power_is_unbiased, region_pdf_integrates_to_one)
 * lumis_region_sampler_lookup — consistency: the density lumis_region_sampler_pdf gives for the
 *     region it names (region_pdf_integrates_to_one)
 * lumis_region_sampler_count — consistency: the light set's light count
 *     (region_pdf_integrates_to_one)
 * lumis_region_sampler_kind — consistency: the light's kind; Wu's spots give both kinds
 *     (region_pdf_integrates_to_one, wu_cases_cover_both_kinds_and_returns)
 * lumis_region_sampler_empty — consistency: a region whose pdf integrates to 0
 *     (region_pdf_integrates_to_one)
 * lumis_region_sampler_bytes — none: only > 0 (wu_cases_cover_both_kinds_and_returns)
 * lumis_region_sampler_build_ms — none: a timing, only >= 0 (wu_cases_cover_both_kinds_and_returns)
 */
#include "../testutil.h"

#include "lumis/lights.h"
#include "stat.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static float f_grad(int i, int j, int c)
{
    return 0.1f + 0.05f * (float)i + 0.02f * (float)j * (float)(c + 1);
}
static float f_checker(int i, int j, int c)
{
    (void)c;
    return ((i / 4 + j / 4) & 1) ? 3.0f : 0.05f;
}
static float f_holes(int i, int j, int c)
{
    return (j >= 5 && j <= 7) || i % 5 == 2 ? 0.0f : (float)(1 + (i * 7 + j * 3 + c) % 5);
}
/* A few very bright pixels in a dim surround: Wu's emissive pixels, some far apart (so
 * they are handed back with a small return factor). */
static float f_spots(int i, int j, int c)
{
    if ((i == 5 && j == 3) || (i == 6 && j == 3) || (i == 30 && j == 10) || (i == 17 && j == 14))
        return 400.0f + 50.0f * (float)c;
    return 0.2f + 0.01f * (float)((i * 5 + j * 3 + c) % 7);
}

typedef struct map_case {
    const char *name;
    int w, h;
    float (*f)(int, int, int);
    float rotation, scale;
    int sky;
} map_case;

static const map_case maps[] = {
    {"gradient", 48, 24, f_grad, 0, 0, 0},
    {"checker", 32, 16, f_checker, 0, 0, 0},
    {"holes", 20, 16, f_holes, -71.0f, 0, 0},
    {"spots", 40, 20, f_spots, 25.0f, 0.5f, 0}, /* rotated and scaled */
    {"sun sky", 64, 32, NULL, 0, 0, 1},
};
enum { NMAPS = sizeof maps / sizeof maps[0] };

typedef struct method_case {
    const char *method, *params;
    int k;
} method_case;

static const method_case methods[] = {
    {"median-cut", NULL, 8},
    {"median-cut", NULL, 1},
    {"variance-min", NULL, 6},
    {"fhis", NULL, 8},
    {"tmms", NULL, 8},
    {"wu", NULL, 8},
    {"wu", "return=0.1", 8}, /* emissive pixels handed back to the EnvIndirects */
    {"wu-is", NULL, 8},      /* seeds drawn with replacement, no masking, no k-means */
    {"wu-is-mask", NULL, 8}, /* masked pixels, no k-means */
    {"wu-original-cut", NULL, 5},
};
enum { NMETHODS = sizeof methods / sizeof methods[0] };

static lumis_envmap *make_map(const map_case *mc)
{
    return tu_envmap(mc->w, mc->h, mc->sky ? NULL : mc->f, mc->rotation, mc->scale);
}

static lumis_light_set *make_set(const lumis_envmap *env, const method_case *mc)
{
    lumis_light_params p;
    memset(&p, 0, sizeof p);
    if (mc->params) assert_int_equal(lumis_light_params_parse(&p, mc->params, NULL), LUMIS_OK);
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(env, mc->method, mc->k, 1, &p, NULL, &set), LUMIS_OK);
    return set;
}

static lumis_region_sampler *make_regions(const lumis_envmap *env, const lumis_light_set *set)
{
    lumis_region_sampler *rs = NULL;
    assert_int_equal(lumis_region_sampler_create(env, set, NULL, &rs), LUMIS_OK);
    return rs;
}

/* Each region's pdf on an r x r grid of sub-cells per pixel (u and cos theta): the
 * density is constant inside a pixel, so a cell's probability is pdf x its solid angle. */
enum { SUB = 2 };

static lumis_vec3 cell_dir(const lumis_envmap *env, int i, int j, int a, int b)
{
    int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    double c0 = cos(PI * j / h), c1 = cos(PI * (j + 1) / h);
    double c = c0 + (b + 0.5) / SUB * (c1 - c0);
    return lumis_envmap_uv_to_dir(env, (float)((i + (a + 0.5) / SUB) / w), (float)(acos(c) / PI));
}

static double cell_omega(const lumis_envmap *env, int j)
{
    return lumis_envmap_pixel_solid_angle(env, j) / (SUB * SUB);
}

/* The cell of direction d: (pixel, a, b) flattened. */
static size_t cell_of(const lumis_envmap *env, lumis_vec3 d)
{
    int w = lumis_envmap_width(env), h = lumis_envmap_height(env), i, j;
    lumis_envmap_dir_to_pixel(env, d, &i, &j);
    float u, v;
    lumis_envmap_dir_to_uv(env, d, &u, &v);
    int a = (int)((u * w - i) * SUB);
    double y = d.y / sqrt((double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z);
    double c0 = cos(PI * j / h), c1 = cos(PI * (j + 1) / h);
    int b = (int)((c0 - y) / (c0 - c1) * SUB);
    a = a < 0 ? 0 : (a >= SUB ? SUB - 1 : a);
    b = b < 0 ? 0 : (b >= SUB ? SUB - 1 : b);
    return (((size_t)j * w + i) * SUB + b) * SUB + a;
}

static void region_pdf_integrates_to_one(void **state)
{
    (void)state;
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        const int w = maps[m].w, h = maps[m].h;
        for (int c = 0; c < NMETHODS; c++) {
            lumis_light_set *set = make_set(env, &methods[c]);
            lumis_region_sampler *rs = make_regions(env, set);
            const int K = lumis_region_sampler_count(rs);
            int lc = 0;
            const lumis_light *lights = NULL;
            assert_int_equal(lumis_light_set_get(set, 0, &lights, &lc), LUMIS_OK);
            assert_int_equal(K, lc);
            for (int k = 0; k < K; k++) {
                double total = 0.0, outside = 0.0, pw[3];
                /* inside a region the density is Y / (sum of Y Omega over the region) */
                lumis_region_sampler_power(rs, k, pw);
                const double py = 0.2126 * pw[0] + 0.7152 * pw[1] + 0.0722 * pw[2];
                for (int j = 0; j < h; j++)
                    for (int i = 0; i < w; i++)
                        for (int b = 0; b < SUB; b++)
                            for (int a = 0; a < SUB; a++) {
                                lumis_vec3 d = cell_dir(env, i, j, a, b);
                                int r = -2;
                                float dens = lumis_region_sampler_lookup(rs, d, &r, NULL);
                                double p = lumis_region_sampler_pdf(rs, k, d) * cell_omega(env, j);
                                total += p;
                                if (r != k) outside += p;
                                if (r != k) continue;
                                assert_true(dens == lumis_region_sampler_pdf(rs, k, d));
                                const double y = lumis_luminance(lumis_envmap_eval(env, d));
                                if (fabs(dens * py - y) > 1e-5 * y + 1e-30)
                                    fail_msg("%s on %s, region %d: density %g x power %g != Y %g",
                                             methods[c].method, maps[m].name, k, dens, py, y);
                            }
                const int empty = lumis_region_sampler_empty(rs, k);
                if (outside != 0.0 || (!empty && fabs(total - 1.0) > 1e-4) ||
                    (empty && total != 0.0))
                    fail_msg("%s on %s, region %d of %d: integral %.9f (outside %g, empty %d)",
                             methods[c].method, maps[m].name, k, K, total, outside, empty);
                assert_int_equal(lumis_region_sampler_kind(rs, k), lights[k].kind);
            }
            lumis_region_sampler_destroy(rs);
            lumis_light_set_destroy(set);
        }
        lumis_envmap_destroy(env);
    }
}

static void region_pdf_of_sample_matches(void **state)
{
    (void)state;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 23, 0);
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        for (int c = 0; c < NMETHODS; c++) {
            lumis_light_set *set = make_set(env, &methods[c]);
            lumis_region_sampler *rs = make_regions(env, set);
            for (int k = 0; k < lumis_region_sampler_count(rs); k++) {
                if (lumis_region_sampler_empty(rs, k)) {
                    assert_true(lumis_region_sampler_sample(rs, k, 0.5, 0.5).pdf == 0.0f);
                    continue;
                }
                for (int n = 0; n < 2000; n++) {
                    double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
                    if (n == 0) u1 = u2 = 0.0;
                    if (n == 1) u1 = u2 = 0x1.fffffffffffffp-1;
                    if (n == 2) u1 = NAN, u2 = 2.0; /* clamped in */
                    lumis_env_sample e = lumis_region_sampler_sample(rs, k, u1, u2);
                    int r = -2;
                    lumis_rgb L;
                    float p = lumis_region_sampler_lookup(rs, e.dir, &r, &L);
                    lumis_rgb Le = lumis_envmap_eval(env, e.dir);
                    if (!(e.pdf > 0.0f) || p != e.pdf || r != k ||
                        lumis_region_sampler_pdf(rs, k, e.dir) != e.pdf ||
                        memcmp(&L, &e.radiance, sizeof L) != 0 ||
                        memcmp(&Le, &e.radiance, sizeof L) != 0)
                        fail_msg("%s on %s, region %d, sample %d: pdf %g, pdf(dir) %g, region %d",
                                 methods[c].method, maps[m].name, k, n, e.pdf, p, r);
                }
            }
            /* A batch over every region (and past them) in a shuffled order, longer than
             * one batch: the draws alone, bit for bit. */
            {
                enum { NB = 77 };
                int reg[NB];
                double ub[2 * NB];
                lumis_env_sample batch[NB];
                const int K = lumis_region_sampler_count(rs);
                for (int q = 0; q < NB; q++) {
                    reg[q] = (int)(lumis_pcg32_next(&rng) % (uint32_t)(K + 2)) - 1;
                    ub[2 * q] = lumis_pcg32_double(&rng);
                    ub[2 * q + 1] = lumis_pcg32_double(&rng);
                }
                lumis_region_sampler_sample_n(rs, reg, ub, NB, batch);
                for (int q = 0; q < NB; q++) {
                    lumis_env_sample one =
                        lumis_region_sampler_sample(rs, reg[q], ub[2 * q], ub[2 * q + 1]);
                    assert_memory_equal(&one, &batch[q], sizeof one);
                }
            }
            /* Out of range and the zero vector: nothing. */
            assert_true(lumis_region_sampler_sample(rs, -1, 0.5, 0.5).pdf == 0.0f);
            assert_true(
                lumis_region_sampler_sample(rs, lumis_region_sampler_count(rs), 0.5, 0.5).pdf ==
                0.0f);
            int r = 0;
            assert_true(lumis_region_sampler_lookup(rs, (lumis_vec3){0, 0, 0}, &r, NULL) == 0.0f);
            assert_int_equal(r, -1);
            lumis_region_sampler_destroy(rs);
            lumis_light_set_destroy(set);
        }
        lumis_envmap_destroy(env);
    }
}

static void region_chi_square(void **state)
{
    (void)state;
    /* Bonferroni over every (map, method, region) tested */
    const double alpha = 0.01 / (NMAPS * NMETHODS * 8);
    const int n = 20000;
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        const int w = maps[m].w, h = maps[m].h;
        const size_t cells = (size_t)w * h * SUB * SUB;
        double *obs = malloc(cells * sizeof *obs), *expct = malloc(cells * sizeof *expct);
        for (int c = 0; c < NMETHODS; c++) {
            lumis_light_set *set = make_set(env, &methods[c]);
            lumis_region_sampler *rs = make_regions(env, set);
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 4000u + (uint64_t)(m * NMETHODS + c), 3);
            for (int k = 0; k < lumis_region_sampler_count(rs); k++) {
                if (lumis_region_sampler_empty(rs, k)) continue;
                memset(obs, 0, cells * sizeof *obs);
                for (int s = 0; s < n; s++) {
                    lumis_env_sample e = lumis_region_sampler_sample(
                        rs, k, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
                    obs[cell_of(env, e.dir)] += 1.0;
                }
                for (int j = 0; j < h; j++)
                    for (int i = 0; i < w; i++)
                        for (int b = 0; b < SUB; b++)
                            for (int a = 0; a < SUB; a++)
                                expct[(((size_t)j * w + i) * SUB + b) * SUB + a] =
                                    n * lumis_region_sampler_pdf(rs, k, cell_dir(env, i, j, a, b)) *
                                    cell_omega(env, j);
                int dof;
                double p = stat_chi2_test(obs, expct, cells, &dof);
                if (!(p > alpha))
                    fail_msg("%s on %s, region %d: chi-square p = %g (< %g), dof %d",
                             methods[c].method, maps[m].name, k, p, alpha, dof);
            }
            lumis_region_sampler_destroy(rs);
            lumis_light_set_destroy(set);
        }
        free(obs);
        free(expct);
        lumis_envmap_destroy(env);
    }
}

/* One draw in every region, each weighted by L / p_k: the stratified estimate of the map's
 * power sum(L Omega).  Its mean over n draws must match the exact sum. */
static void stratified_power_is_unbiased(void **state)
{
    (void)state;
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        const lumis_rgb exact = lumis_envmap_power(env);
        for (int c = 0; c < NMETHODS; c++) {
            lumis_light_set *set = make_set(env, &methods[c]);
            lumis_region_sampler *rs = make_regions(env, set);
            const int K = lumis_region_sampler_count(rs);
            double sum_regions[3] = {0, 0, 0};
            for (int k = 0; k < K; k++) {
                double pw[3];
                lumis_region_sampler_power(rs, k, pw);
                for (int ch = 0; ch < 3; ch++) sum_regions[ch] += pw[ch];
            }
            const double ex[3] = {exact.r, exact.g, exact.b};
            for (int ch = 0; ch < 3; ch++)
                if (fabs(sum_regions[ch] - ex[ch]) > 1e-5 * ex[ch])
                    fail_msg("%s on %s: the regions' power %g, the map's %g (channel %d)",
                             methods[c].method, maps[m].name, sum_regions[ch], ex[ch], ch);
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 77, (uint64_t)(m * NMETHODS + c));
            const int n = 4000;
            double s[3] = {0, 0, 0}, ss[3] = {0, 0, 0};
            for (int it = 0; it < n; it++) {
                double est[3] = {0, 0, 0};
                for (int k = 0; k < K; k++) {
                    lumis_env_sample e = lumis_region_sampler_sample(
                        rs, k, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
                    if (!(e.pdf > 0.0f)) continue;
                    est[0] += e.radiance.r / e.pdf;
                    est[1] += e.radiance.g / e.pdf;
                    est[2] += e.radiance.b / e.pdf;
                }
                for (int ch = 0; ch < 3; ch++) {
                    s[ch] += est[ch];
                    ss[ch] += est[ch] * est[ch];
                }
            }
            for (int ch = 0; ch < 3; ch++) {
                const double mean = s[ch] / n, se = sqrt(fmax(ss[ch] / n - mean * mean, 0.0) / n);
                if (fabs(mean - ex[ch]) > 4 * se + 1e-5 * ex[ch])
                    fail_msg("%s on %s: channel %d: %.7g +- %.2g vs %.7g", methods[c].method,
                             maps[m].name, ch, mean, se, ex[ch]);
            }
            lumis_region_sampler_destroy(rs);
            lumis_light_set_destroy(set);
        }
        lumis_envmap_destroy(env);
    }
}

/* Wu's cases above hold what they are meant to: EnvDirects and EnvIndirects both, and
 * (with return=0.1) emissive pixels handed back. */
static void wu_cases_cover_both_kinds_and_returns(void **state)
{
    (void)state;
    lumis_envmap *env = make_map(&maps[3]); /* spots */
    lumis_light_set *set = make_set(env, &methods[6]);
    const lumis_light_set_info *info = lumis_light_set_get_info(set);
    assert_true(info->direct > 0 && info->indirect > 0);
    assert_true(info->returned_pixels > 0);
    lumis_region_sampler *rs = make_regions(env, set);
    int kinds = 0;
    for (int k = 0; k < lumis_region_sampler_count(rs); k++)
        kinds |= 1 << lumis_region_sampler_kind(rs, k);
    assert_int_equal(kinds, (1 << LUMIS_LIGHT_ENV_DIRECT) | (1 << LUMIS_LIGHT_ENV_INDIRECT));
    assert_true(lumis_region_sampler_bytes(rs) > 0);
    assert_true(lumis_region_sampler_build_ms(rs) >= 0.0);
    lumis_region_sampler_destroy(rs);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* Refusals: no map, no set, a set of another map's size. */
static float f_unique(int i, int j, int c)
{
    return 1.0f + 0.37f * (float)i + 0.011f * (float)j * (float)(c + 1) + 0.0003f * (float)(i * j);
}

/* Every bin of a one-region sampler, at widths where p / w by a multiplication with 1 / w
 * rounds below a row's start (49, 98, 196; 97, 255 and a power of two beside them), lands
 * in its own pixel: each pixel's density differs from its neighbours', so pdf(dir) equals
 * the sample's pdf only there (issue 37: the correction removed misplaced ~1.4 % of draws by
 * one row on these widths, unseen at the 20-64 pixel widths of the tests above). */
static void samples_land_in_their_pixel_at_awkward_widths(void **state)
{
    (void)state;
    static const int widths[] = {49, 98, 196, 97, 255, 256};
    for (size_t q = 0; q < sizeof widths / sizeof widths[0]; q++) {
        const int w = widths[q], h = w / 2;
        lumis_envmap *env = tu_envmap(w, h, f_unique, 0, 0);
        const method_case mc = {"median-cut", NULL, 1};
        lumis_light_set *set = make_set(env, &mc);
        lumis_region_sampler *rs = make_regions(env, set);
        const int n = w * h;
        int bad = 0;
        for (int b = 0; b < n; b++)
            for (int side = 0; side < 2; side++) {
                const double u1 = (b + 0.5) / n, u2 = side ? 0.9 : 0.1;
                const lumis_env_sample e = lumis_region_sampler_sample(rs, 0, u1, u2);
                if (!(e.pdf > 0) || lumis_region_sampler_pdf(rs, 0, e.dir) != e.pdf) bad++;
            }
        if (bad)
            fail_msg("width %d: %d of %d draws outside the pixel their pdf is of", w, bad, 2 * n);
        lumis_region_sampler_destroy(rs);
        lumis_light_set_destroy(set);
        lumis_envmap_destroy(env);
    }
}

/* A region's draw inverts its distribution (rows by u1, then the row's pixels by u2, the
 * rest of each inside the pixel), so it is monotone in each coordinate: sweeping u1 at a
 * fixed u2, the rows never go up the map and cos theta never rises (inside a row, along
 * cos theta), and the row's pixel and azimuth stay put; sweeping u2 at a fixed u1, the row
 * and cos theta stay put and the pixels go left to right, the azimuth inside one rising.
 * This is what keeps a stratified (Sobol') set of points stratified over the region and
 * inside its pixels; an alias table, which scatters the points over the region with the
 * same distribution (every test above passes with it), fails it. */
static void region_draws_are_monotone_in_u(void **state)
{
    (void)state;
    enum { N = 193 };
    static const double fixed[] = {0.0, 0.137, 0.5, 0.861, 0x1.fffffffffffffp-1};
    /* float directions: cos theta to 2e-4, the azimuth to 2e-3 pixels (a direction that
     * rounding would put across its pixel's edge is pulled inside, and near a pole the
     * azimuth is coarse); a pixel's height in cos theta is 0.06 or more here */
    const double tol = 2e-4, tol_az = 2e-3;
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        const int w = maps[m].w;
        for (int c = 0; c < NMETHODS; c++) {
            lumis_light_set *set = make_set(env, &methods[c]);
            lumis_region_sampler *rs = make_regions(env, set);
            for (int k = 0; k < lumis_region_sampler_count(rs); k++) {
                if (lumis_region_sampler_empty(rs, k)) continue;
                for (size_t f = 0; f < sizeof fixed / sizeof fixed[0]; f++)
                    for (int axis = 0; axis < 2; axis++) {
                        int pi = -1, pj = -1;
                        double py = 0.0, paz = 0.0;
                        for (int q = 0; q < N; q++) {
                            const double sweep = (q + 0.5) / N;
                            const double u1 = axis ? fixed[f] : sweep, u2 = axis ? sweep : fixed[f];
                            const lumis_env_sample e = lumis_region_sampler_sample(rs, k, u1, u2);
                            int i, j;
                            float uu, vv;
                            lumis_envmap_dir_to_pixel(env, e.dir, &i, &j);
                            lumis_envmap_dir_to_uv(env, e.dir, &uu, &vv);
                            const double y = e.dir.y;
                            /* the azimuth inside the pixel, in pixels (rotation-proof) */
                            double az = (double)uu * w - i;
                            if (az > w / 2.0) az -= w;
                            if (az < -w / 2.0) az += w;
                            int bad = 0;
                            if (q > 0 && !axis) /* u1 sweeps: rows down, cos theta down */
                                bad = j < pj || y > py + tol ||
                                      (j == pj && (i != pi || fabs(az - paz) > tol_az));
                            if (q > 0 && axis) /* u2 sweeps: the row and cos theta stay */
                                bad = j != pj || fabs(y - py) > tol || i < pi ||
                                      (i == pi && az < paz - tol_az);
                            if (bad)
                                fail_msg("%s on %s, region %d, u%d sweeps (u%d = %g), step %d: "
                                         "pixel (%d, %d) after (%d, %d), cos theta %.7f after "
                                         "%.7f, azimuth %.6f after %.6f",
                                         methods[c].method, maps[m].name, k, axis ? 2 : 1,
                                         axis ? 1 : 2, fixed[f], q, i, j, pi, pj, y, py, az, paz);
                            pi = i, pj = j, py = y, paz = az;
                        }
                    }
            }
            lumis_region_sampler_destroy(rs);
            lumis_light_set_destroy(set);
        }
        lumis_envmap_destroy(env);
    }
}

/* One region of more than 2^21 shining pixels, whose units (2^32 a pixel on average)
 * would pass 2^53, where a double no longer holds every integer: a 4096 x 1024 map, all of
 * it one region (median cut, K = 1), bright but for dim pixels of one unit each (the least
 * the quantisation gives what shines) spread over the map and at the end of every row
 * (where a draw of u2 -> 1 ends).  Every pixel that shines keeps a density > 0 (nothing
 * that shines is drawn with probability 0: src/core/distrib.h), the densities integrate to
 * one, and draws over the whole region (u1 on a fine grid, u2 random, 0 and the largest
 * double below 1) all have pdf > 0, equal to pdf(dir), in the region, with the map's
 * radiance.  With 2^32 units a pixel whatever the region's size, 10659 of its pixels had
 * density 0 and 36114 of the 393216 draws pdf 0 (u2 -> 1 at a row whose last pixel's
 * units had rounded away): a render dividing by it. */
static float f_big(int i, int j, int c)
{
    (void)c;
    return i == 4095 || (i * 7 + j * 13) % 101 == 0 ? 1e-30f : 1.0f + 0.25f * (float)(j & 3);
}

static void region_of_more_than_2p21_pixels(void **state)
{
    (void)state;
    enum { W = 4096, H = 1024 };
    lumis_envmap *env = tu_envmap(W, H, f_big, 0, 0);
    const method_case mc = {"median-cut", NULL, 1};
    lumis_light_set *set = make_set(env, &mc);
    lumis_region_sampler *rs = make_regions(env, set);
    assert_int_equal(lumis_region_sampler_count(rs), 1);
    double total = 0.0;
    long zero = 0;
    for (int j = 0; j < H; j++) {
        const double om = lumis_envmap_pixel_solid_angle(env, j);
        for (int i = 0; i < W; i++) {
            const lumis_vec3 d =
                lumis_envmap_uv_to_dir(env, (float)((i + 0.5) / W), (float)((j + 0.5) / H));
            int r = -2;
            const float dens = lumis_region_sampler_lookup(rs, d, &r, NULL);
            assert_int_equal(r, 0);
            if (!(dens > 0.0f)) zero++;
            total += dens * om;
        }
    }
    if (zero || fabs(total - 1.0) > 1e-4)
        fail_msg("%ld of %d shining pixels of density 0; integral %.9f", zero, W * H, total);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 41, 0);
    enum { NB = 1 << 17 };
    long bad = 0;
    double u[2 * 64];
    int reg[64] = {0};
    lumis_env_sample e[64];
    for (int b0 = 0; b0 < NB; b0 += 64)
        for (int side = 0; side < 3; side++) {
            for (int b = 0; b < 64; b++) {
                u[2 * b] = (b0 + b + 0.5) / NB;
                u[2 * b + 1] = side == 0   ? lumis_pcg32_double(&rng)
                               : side == 1 ? 0.0
                                           : 0x1.fffffffffffffp-1;
            }
            lumis_region_sampler_sample_n(rs, reg, u, 64, e);
            for (int b = 0; b < 64; b++) {
                int r = -2;
                lumis_rgb L;
                const float p = lumis_region_sampler_lookup(rs, e[b].dir, &r, &L);
                if (!(e[b].pdf > 0.0f) || p != e[b].pdf || r != 0 ||
                    memcmp(&L, &e[b].radiance, sizeof L) != 0) {
                    if (bad++ < 5)
                        print_message("u (%.17g, %.17g): pdf %g, pdf(dir) %g, region %d\n",
                                      u[2 * b], u[2 * b + 1], e[b].pdf, p, r);
                }
            }
        }
    if (bad) fail_msg("%ld of %d draws with pdf 0 or not pdf(dir)", bad, 3 * NB);
    lumis_region_sampler_destroy(rs);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

static void region_sampler_refuses_mismatches(void **state)
{
    (void)state;
    lumis_envmap *a = make_map(&maps[0]), *b = make_map(&maps[1]);
    lumis_light_set *set = make_set(a, &methods[0]);
    lumis_region_sampler *rs = (lumis_region_sampler *)1;
    assert_int_equal(lumis_region_sampler_create(b, set, NULL, &rs), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(rs);
    assert_int_equal(lumis_region_sampler_create(NULL, set, NULL, &rs), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_region_sampler_create(a, NULL, NULL, &rs), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_region_sampler_create(a, set, NULL, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_region_sampler_count(NULL), 0);
    assert_true(lumis_region_sampler_empty(NULL, 0));
    lumis_region_sampler_destroy(NULL);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(a);
    lumis_envmap_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(region_pdf_integrates_to_one),
        cmocka_unit_test(region_pdf_of_sample_matches),
        cmocka_unit_test(region_chi_square),
        cmocka_unit_test(stratified_power_is_unbiased),
        cmocka_unit_test(wu_cases_cover_both_kinds_and_returns),
        cmocka_unit_test(region_sampler_refuses_mismatches),
        cmocka_unit_test(samples_land_in_their_pixel_at_awkward_widths),
        cmocka_unit_test(region_draws_are_monotone_in_u),
        cmocka_unit_test(region_of_more_than_2p21_pixels),
    };
    /* LUMIS_TEST_FILTER=region_of* runs the tests of that name alone */
    if (getenv("LUMIS_TEST_FILTER")) cmocka_set_test_filter(getenv("LUMIS_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
