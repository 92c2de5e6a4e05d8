/* Statistical tests of every environment-map sampler (fixed seeds: deterministic).
 *
 * For every method and every synthetic map: the pdf integrates to one, pdf(sample) equals
 * the pdf returned while sampling, a chi-square goodness-of-fit test of the samples
 * against the method's own pdf (Bonferroni-corrected p > 0.01), and unbiasedness of the
 * power estimate.  Exact methods also give a constant weight on a grey map and a pdf that
 * lines up with eval() pixel for pixel.  Then: the alias table's exactness at 2048 x 1024,
 * the kd-tree's invariants, the uniform fallback on black maps, and per-pixel chi-square
 * on the real maps in data/ when they are there. */
/* Oracles:
 * lumis_sampler_pdf_n — consistency: equal to lumis_sampler_pdf direction by direction, with and
 *     without radiance (pdf_of_sample_matches)
 * lumis_sampler_invert_n — consistency: equal to lumis_sampler_invert, stops at the first refused
 *     direction and names it (pdf_of_sample_matches)
 * lumis_sampler_create — statistical: every method on 7 synthetic and the real maps (below); error
 *     paths: bad descriptors (chi_square_goodness_of_fit, invalid_descriptors)
 * lumis_sampler_destroy — external: ASan sees the map kept alive and freed with its sampler
 *     (sampler_keeps_its_map_alive)
 * lumis_sampler_sample — statistical: chi-square against the pdf, unbiased power against the true
 *     standard error summed over pixels, per-pixel chi-square on the real maps
 *     (chi_square_goodness_of_fit, power_estimates_are_unbiased, real_maps_per_pixel_chi_square)
 * lumis_sampler_pdf — statistical, hand-worked: integrates to one by exact cell probabilities; pdf
 *     / importance constant per pixel with Rec. 709 Y, mean, max written in the test; MIS
 *     compensation's 10 and 20 ratio (pdf_integrates_to_one, importance_kinds_weight_the_channels,
 *     compensation_subtracts_the_mean_over_the_sphere)
 * lumis_sampler_pdf_radiance — consistency: equals lumis_sampler_pdf and lumis_envmap_eval for
 *     sampled and arbitrary directions (pdf_of_sample_matches)
 * lumis_sampler_sample_n — consistency: the very samples of lumis_sampler_sample
 *     (pdf_of_sample_matches)
 * lumis_sampler_invert — consistency: round trip with lumis_sampler_sample both ways; hand-worked:
 *     a dark pixel inverts to where its share would start (invert_round_trips,
 *     invert_of_a_dark_pixel)
 * lumis_sampler_envmap — hand-worked: the map it was built on (pdf_of_sample_matches)
 * lumis_sampler_get_method — hand-worked: the default is inversion-guided
 *     (sampler_keeps_its_map_alive)
 * lumis_sampler_is_uniform_fallback — hand-worked: a black map falls back, pdf 1 / 4 pi, one
 *     message (black_map_falls_back_to_uniform_and_says_so)
 * lumis_sampler_table_bytes — hand-worked: bytes of each table counted by hand for a 20 x 10 map
 *     (table_bytes_count_every_table)
 * lumis_sampler_total_bytes — hand-worked: table bytes plus the structure
 *     (table_bytes_count_every_table)
 * lumis_sampler_kdtree_blocks — invariance: blocks partition the map, every pixel once; a constant
 *     map needs 1 (kdtree_blocks_partition_the_map)
 * lumis_sampler_kdtree_alpha — none: its fit (internal) is checked against a scan of the objective,
 *     the getter is not (kdtree_alpha_minimises_the_objective)
 * lumis_sampler_build_ms — none: a timing, only printed by the CLI
 * lumis_luminance — indirect: exact samplers' pdf / Y constant with Rec. 709 coefficients written
 *     in the test (importance_kinds_weight_the_channels)
 * lumis_envmap_pixel_solid_angle — indirect: the true standard error and the alias table's pmf
 *     summed with it (alias_is_exact_at_2048x1024)
 * lumis_envmap_width — indirect: every exact cell probability walks the map with it (cell_prob)
 * lumis_envmap_height — indirect: every exact cell probability walks the map with it (cell_prob)
 * lumis_sampler_method_from_name — hand-worked: "kdtree-exact"; "cdf" refused (invalid_descriptors)
 */
#include "../testutil.h"

#include "core/distrib.h"
#include "envmap/sampler_method.h"
#include "stat.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PI 3.14159265358979323846

/* ---- maps ---------------------------------------------------------------------------- */

static float f_const(int i, int j, int c)
{
    (void)i, (void)j, (void)c;
    return 0.7f;
}
static float f_grad(int i, int j, int c)
{
    return 0.1f + 0.05f * (float)i + 0.02f * (float)j * (float)(c + 1);
}
static float f_hot(int i, int j, int c)
{
    (void)c;
    return (i == 7 && j == 5) ? 500.0f : 0.0f;
}
static float f_checker(int i, int j, int c)
{
    (void)c;
    return ((i / 4 + j / 4) & 1) ? 3.0f : 0.05f;
}
static float f_pole(int i, int j, int c)
{
    (void)i, (void)c;
    return j == 0 ? 2.0f : 0.0f;
}
static float f_holes(int i, int j, int c)
{
    /* Rows without light in the middle and dark pixels in lit rows. */
    return (j >= 5 && j <= 7) || i % 5 == 2 ? 0.0f : (float)(1 + (i * 7 + j * 3 + c) % 5);
}
static float f_colour(int i, int j, int c)
{
    return (float)(1 + (i * 3 + j * 5 + c * 7) % 11);
}

typedef struct map_case {
    const char *name;
    int w, h;
    float (*f)(int, int, int);
    float rotation;
    int sky; /* procedural sky with a sun instead of f */
} map_case;

static const map_case maps[] = {
    {"constant", 32, 16, f_const, 0, 0},   {"gradient", 48, 24, f_grad, 0, 0},
    {"hot pixel", 20, 10, f_hot, 0, 0},    {"sun sky", 64, 32, NULL, 0, 1},
    {"checker", 32, 16, f_checker, 0, 0},  {"1x1", 1, 1, f_const, 0, 0},
    {"3x1", 3, 1, f_grad, 0, 0},           {"3x2", 3, 2, f_colour, 0, 0},
    {"pole", 16, 8, f_pole, 0, 0},         {"rotated colour", 24, 12, f_colour, 33.0f, 0},
    {"holes", 20, 16, f_holes, -71.0f, 0},
};
enum { NMAPS = sizeof maps / sizeof maps[0] };

static lumis_envmap *make_map(const map_case *mc)
{
    return tu_envmap(mc->w, mc->h, mc->sky ? NULL : mc->f, mc->rotation, 0.0f);
}

/* ---- configurations ------------------------------------------------------------------ */

typedef struct config {
    const char *name;
    lumis_sampler_method method;
    int uniform_angles, compensate, blocks;
    int exact; /* realises the importance exactly (constant weight on a grey map) */
} config;

static const config configs[] = {
    {"inversion", LUMIS_METHOD_INVERSION, 0, 0, 0, 1},
    {"inversion-guided", LUMIS_METHOD_INVERSION_GUIDED, 0, 0, 0, 1},
    {"alias", LUMIS_METHOD_ALIAS, 0, 0, 0, 1},
    {"kdtree", LUMIS_METHOD_KDTREE, 0, 0, 64, 0},
    {"kdtree-uniform-angles", LUMIS_METHOD_KDTREE, 1, 0, 64, 0},
    {"kdtree-exact", LUMIS_METHOD_KDTREE_EXACT, 0, 0, 64, 0},
    {"hierarchical", LUMIS_METHOD_HIERARCHICAL, 0, 0, 0, 1},
    {"uniform", LUMIS_METHOD_UNIFORM, 0, 0, 0, 0},
    {"alias-compensated", LUMIS_METHOD_ALIAS, 0, 1, 0, 0},
};
enum { NCONFIGS = sizeof configs / sizeof configs[0] };

static lumis_sampler *make_sampler(const lumis_envmap *env, const config *c)
{
    lumis_sampler_desc d = {0};
    d.method = c->method;
    d.kdtree_uniform_angles = c->uniform_angles;
    d.compensate = c->compensate;
    d.kdtree_blocks = c->blocks;
    lumis_sampler *s = NULL;
    assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_OK);
    return s;
}

static double exact_power_y(const lumis_envmap *env)
{
    lumis_envmap_stats st;
    assert_int_equal(lumis_envmap_stats_compute(env, &st), LUMIS_OK);
    return st.power;
}

/* Direction at the centre (in u and cos theta) of sub-cell (a, b) of r x r in pixel (i, j). */
static lumis_vec3 cell_dir(const lumis_envmap *env, int i, int j, int r, int a, int b)
{
    int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    double c0 = cos(PI * j / h), c1 = cos(PI * (j + 1) / h);
    double c = c0 + (b + 0.5) / r * (c1 - c0);
    float v = (float)(acos(c) / PI);
    return lumis_envmap_uv_to_dir(env, (float)((i + (a + 0.5) / r) / w), v);
}

static double sin_theta(lumis_vec3 d)
{
    double xz = sqrt((double)d.x * d.x + (double)d.z * d.z);
    return xz / sqrt(xz * xz + (double)d.y * d.y);
}

/* Probability of sub-cell (a, b) of pixel (i, j) under the sampler's pdf, exactly:
 * the density is constant per pixel in solid angle, or (literal variant) constant per
 * unit of (phi, theta). */
static double cell_prob(const lumis_sampler *s, const lumis_envmap *env, int uniform_angles, int i,
                        int j, int r, int a, int b)
{
    int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    lumis_vec3 d = cell_dir(env, i, j, r, a, b);
    double pdf = lumis_sampler_pdf(s, d);
    double c0 = cos(PI * j / h), c1 = cos(PI * (j + 1) / h);
    double ca = c0 + (double)b / r * (c1 - c0), cb = c0 + (double)(b + 1) / r * (c1 - c0);
    double dphi = 2 * PI / w / r;
    if (uniform_angles) return pdf * sin_theta(d) * dphi * (acos(cb) - acos(ca));
    return pdf * dphi * (ca - cb);
}

static int subdivision(int w, int h)
{
    return w * h >= 512 ? 1 : (int)ceil(sqrt(512.0 / (w * h)));
}

/* ---- the per-method, per-map tests -------------------------------------------------- */

static void pdf_integrates_to_one(void **state)
{
    (void)state;
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        int w = maps[m].w, h = maps[m].h, r = subdivision(w, h);
        for (int c = 0; c < NCONFIGS; c++) {
            lumis_sampler *s = make_sampler(env, &configs[c]);
            double total = 0.0;
            for (int j = 0; j < h; j++)
                for (int i = 0; i < w; i++)
                    for (int b = 0; b < r; b++)
                        for (int a = 0; a < r; a++)
                            total += cell_prob(s, env, configs[c].uniform_angles, i, j, r, a, b);
            if (fabs(total - 1.0) > 1e-4)
                fail_msg("%s on %s: integral %.9f", configs[c].name, maps[m].name, total);
            lumis_sampler_destroy(s);
        }
        lumis_envmap_destroy(env);
    }
}

static void pdf_of_sample_matches(void **state)
{
    (void)state;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 11, 0);
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        for (int c = 0; c < NCONFIGS; c++) {
            lumis_sampler *s = make_sampler(env, &configs[c]);
            for (int k = 0; k < 20000; k++) {
                double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
                if (k == 0) u1 = u2 = 0.0; /* the corners of the unit square */
                if (k == 1) u1 = u2 = 0x1.fffffffffffffp-1;
                if (k == 2) u1 = 1.0, u2 = -0.25; /* outside [0, 1): clamped in */
                if (k == 3) u1 = NAN, u2 = 2.0;
                lumis_env_sample e = lumis_sampler_sample(s, u1, u2);
                float p = lumis_sampler_pdf(s, e.dir);
                double len = sqrt((double)e.dir.x * e.dir.x + (double)e.dir.y * e.dir.y +
                                  (double)e.dir.z * e.dir.z);
                if (!(e.pdf > 0.0f) || p != e.pdf || fabs(len - 1.0) > 1e-6) /* bit for bit */
                    fail_msg("%s on %s, sample %d: pdf %g, pdf(dir) %g, |dir| %g", configs[c].name,
                             maps[m].name, k, e.pdf, p, len);
                lumis_rgb L = lumis_envmap_eval(env, e.dir);
                assert_true(L.r == e.radiance.r && L.g == e.radiance.g && L.b == e.radiance.b);
                /* The fused lookup gives the same density and radiance, also for any
                 * direction (not only sampled ones). */
                lumis_rgb L2;
                assert_true(lumis_sampler_pdf_radiance(s, e.dir, &L2) == p);
                assert_memory_equal(&L2, &L, sizeof L);
                lumis_vec3 any = {(float)(lumis_pcg32_double(&rng) - 0.5),
                                  (float)(lumis_pcg32_double(&rng) - 0.5),
                                  (float)(lumis_pcg32_double(&rng) - 0.5)};
                lumis_rgb L3 = lumis_envmap_eval(env, any), L4;
                assert_true(lumis_sampler_pdf_radiance(s, any, &L4) == lumis_sampler_pdf(s, any));
                assert_memory_equal(&L3, &L4, sizeof L3);
            }
            assert_true(lumis_sampler_envmap(s) == env);
            /* The batch gives the very same samples as the scalar calls. */
            double ub[2 * 100];
            lumis_env_sample batch[100];
            for (int k = 0; k < 200; k++) ub[k] = lumis_pcg32_double(&rng);
            lumis_sampler_sample_n(s, ub, 100, batch);
            for (int k = 0; k < 100; k++) {
                lumis_env_sample e = lumis_sampler_sample(s, ub[2 * k], ub[2 * k + 1]);
                assert_memory_equal(&e, &batch[k], sizeof e);
            }
            /* The batched pdf and invert give the very numbers of the single calls; invert
             * stops at the first direction it refuses and says which. */
            lumis_vec3 bd[101];
            float bp[101], bp2[101];
            lumis_rgb br[101];
            double bu[202];
            for (int k = 0; k < 100; k++) bd[k] = batch[k].dir;
            bd[100] = (lumis_vec3){0.0f, 0.0f, 0.0f};
            lumis_sampler_pdf_n(s, bd, 101, bp, br);
            lumis_sampler_pdf_n(s, bd, 101, bp2, NULL);
            size_t failed = 0;
            lumis_status inv = lumis_sampler_invert_n(s, bd, 101, bu, &failed);
            double v0[2];
            int invertible = lumis_sampler_invert(s, bd[0], v0) != LUMIS_ERR_UNSUPPORTED;
            assert_int_equal(inv, invertible ? LUMIS_ERR_INVALID_ARGUMENT : LUMIS_ERR_UNSUPPORTED);
            assert_int_equal(failed, inv == LUMIS_ERR_UNSUPPORTED ? 0 : 100);
            for (int k = 0; k < 101; k++) {
                lumis_rgb L;
                float p = lumis_sampler_pdf_radiance(s, bd[k], &L);
                assert_true(bp[k] == p && bp2[k] == p);
                assert_memory_equal(&br[k], &L, sizeof L);
                double v[2];
                if (k < (int)failed) {
                    assert_int_equal(lumis_sampler_invert(s, bd[k], v), LUMIS_OK);
                    assert_memory_equal(v, &bu[2 * k], sizeof v);
                }
            }
            assert_int_equal(lumis_sampler_invert_n(s, bd, 100, bu, &failed),
                             inv == LUMIS_ERR_UNSUPPORTED ? LUMIS_ERR_UNSUPPORTED : LUMIS_OK);
            assert_int_equal(failed, inv == LUMIS_ERR_UNSUPPORTED ? 0 : 100);
            /* The poles themselves: finite densities (uniform-in-angles grows as 1/sin). */
            assert_true(isfinite(lumis_sampler_pdf(s, (lumis_vec3){0, 1, 0})));
            assert_true(isfinite(lumis_sampler_pdf(s, (lumis_vec3){0, -1, 0})));
            /* The zero vector is no direction: density 0 and black, from both lookups. */
            lumis_rgb L0 = {-1.0f, -1.0f, -1.0f};
            assert_true(lumis_sampler_pdf(s, (lumis_vec3){0, 0, 0}) == 0.0f);
            assert_true(lumis_sampler_pdf_radiance(s, (lumis_vec3){0, 0, 0}, &L0) == 0.0f);
            assert_true(L0.r == 0.0f && L0.g == 0.0f && L0.b == 0.0f);
            lumis_sampler_destroy(s);
        }
        lumis_envmap_destroy(env);
    }
}

/* Chi-square of n samples against the sampler's own pdf; returns the p-value. */
static double chi2_against_pdf(const lumis_sampler *s, const lumis_envmap *env, int uniform_angles,
                               int r, int n, uint64_t seed)
{
    int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    size_t cells = (size_t)w * h * r * r;
    double *obs = calloc(cells, sizeof(double)), *expct = calloc(cells, sizeof(double));
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, seed, 7);
    for (int k = 0; k < n; k++) {
        double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
        lumis_env_sample e = lumis_sampler_sample(s, u1, u2);
        int i, j;
        lumis_envmap_dir_to_pixel(env, e.dir, &i, &j);
        float u, v;
        lumis_envmap_dir_to_uv(env, e.dir, &u, &v);
        int a = (int)((u * w - i) * r), b;
        double y = e.dir.y / sqrt((double)e.dir.x * e.dir.x + (double)e.dir.y * e.dir.y +
                                  (double)e.dir.z * e.dir.z);
        double c0 = cos(PI * j / h), c1 = cos(PI * (j + 1) / h);
        b = (int)((c0 - y) / (c0 - c1) * r);
        a = a < 0 ? 0 : (a >= r ? r - 1 : a);
        b = b < 0 ? 0 : (b >= r ? r - 1 : b);
        obs[(((size_t)j * w + i) * r + b) * r + a] += 1.0;
    }
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++)
            for (int b = 0; b < r; b++)
                for (int a = 0; a < r; a++)
                    expct[(((size_t)j * w + i) * r + b) * r + a] =
                        n * cell_prob(s, env, uniform_angles, i, j, r, a, b);
    int dof;
    double p = stat_chi2_test(obs, expct, cells, &dof);
    free(obs);
    free(expct);
    return p;
}

static void chi_square_goodness_of_fit(void **state)
{
    (void)state;
    const double alpha = 0.01 / (NMAPS * NCONFIGS); /* Bonferroni */
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        for (int c = 0; c < NCONFIGS; c++) {
            lumis_sampler *s = make_sampler(env, &configs[c]);
            double p = chi2_against_pdf(s, env, configs[c].uniform_angles,
                                        subdivision(maps[m].w, maps[m].h), 200000,
                                        1000u + (uint64_t)(m * NCONFIGS + c));
            if (!(p > alpha))
                fail_msg("%s on %s: chi-square p = %g (< %g)", configs[c].name, maps[m].name, p,
                         alpha);
            lumis_sampler_destroy(s);
        }
        lumis_envmap_destroy(env);
    }
}

static void power_estimates_are_unbiased(void **state)
{
    (void)state;
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        double exact_y = exact_power_y(env);
        lumis_rgb pw = lumis_envmap_power(env);
        for (int c = 0; c < NCONFIGS; c++) {
            if (configs[c].compensate) continue; /* compensation is for MIS: biased alone */
            lumis_sampler *s = make_sampler(env, &configs[c]);
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 99, (uint64_t)c);
            const int n = 50000;
            double sy = 0, syy = 0, sr = 0, srr = 0;
            for (int k = 0; k < n; k++) {
                lumis_env_sample e =
                    lumis_sampler_sample(s, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
                double wy = lumis_luminance(e.radiance) / e.pdf, wr = e.radiance.r / e.pdf;
                sy += wy;
                syy += wy * wy;
                sr += wr;
                srr += wr * wr;
            }
            double my = sy / n, mr = sr / n;
            double sey = sqrt(fmax(syy / n - my * my, 0.0) / n),
                   ser = sqrt(fmax(srr / n - mr * mr, 0.0) / n);
            if (fabs(my - exact_y) > 4 * sey + 1e-5 * exact_y ||
                fabs(mr - pw.r) > 4 * ser + 1e-5 * pw.r)
                fail_msg("%s on %s: Y %.6g +- %.2g vs %.6g; R %.6g +- %.2g vs %.6g",
                         configs[c].name, maps[m].name, my, sey, exact_y, mr, ser, pw.r);
            lumis_sampler_destroy(s);
        }
        lumis_envmap_destroy(env);
    }
}

/* Exact samplers: radiance / pdf is the same for every sample of a grey map, and on any
 * map pdf * power == Y of the pixel eval() returns - no half-texel offset anywhere. */
static void exact_samplers_line_up_with_eval(void **state)
{
    (void)state;
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        double power = exact_power_y(env);
        for (int c = 0; c < NCONFIGS; c++) {
            if (!configs[c].exact) continue;
            lumis_sampler *s = make_sampler(env, &configs[c]);
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 5, 5);
            for (int k = 0; k < 5000; k++) {
                lumis_env_sample e =
                    lumis_sampler_sample(s, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
                double y = lumis_luminance(e.radiance);
                if (fabs(y / e.pdf - power) > 2e-5 * power)
                    fail_msg("%s on %s: Y/pdf = %.9g, power %.9g", configs[c].name, maps[m].name,
                             y / e.pdf, power);
            }
            lumis_sampler_destroy(s);
        }
        lumis_envmap_destroy(env);
    }
}

static void weights_are_bounded(void **state)
{
    (void)state;
    /* One lit pixel and a 3x2 map: every exact sampler's weight equals the power; the
     * others' weights stay finite and positive. */
    const map_case *cases[] = {&maps[2], &maps[7]};
    for (int m = 0; m < 2; m++) {
        lumis_envmap *env = make_map(cases[m]);
        double power = exact_power_y(env);
        for (int c = 0; c < NCONFIGS; c++) {
            lumis_sampler *s = make_sampler(env, &configs[c]);
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 3, 3);
            double wmax = 0.0;
            for (int k = 0; k < 20000; k++) {
                lumis_env_sample e =
                    lumis_sampler_sample(s, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
                double wy = lumis_luminance(e.radiance) / e.pdf;
                assert_true(isfinite(wy) && wy >= 0.0);
                if (wy > wmax) wmax = wy;
            }
            if (configs[c].exact && wmax > power * (1 + 2e-5))
                fail_msg("%s on %s: max weight %g > power %g", configs[c].name, cases[m]->name,
                         wmax, power);
            lumis_sampler_destroy(s);
        }
        lumis_envmap_destroy(env);
    }
}

/* Small pixels: on a rotated 2048 x 1024 sky every sample's direction looks up the pixel
 * it was drawn in (pdf bit for bit, radiance equal), for every method.  The warp computes
 * sin and cos with its own polynomials, so this is where a too-large error would show. */
static void exact_on_small_pixels(void **state)
{
    (void)state;
    lumis_sky_desc sd = {0};
    sd.width = 2048;
    sd.sun_elevation_deg = 35.0f;
    lumis_image *img = NULL;
    assert_int_equal(lumis_sky_create(&sd, &img), LUMIS_OK);
    lumis_envmap_desc ed = {0};
    ed.pixels = img->pixels;
    ed.width = img->width;
    ed.height = img->height;
    ed.rotation_deg = 71.3f;
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_create(&ed, &env), LUMIS_OK);
    lumis_image_destroy(img);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 23, 1);
    for (int c = 0; c < NCONFIGS; c++) {
        config cfg = configs[c];
        cfg.blocks = 0;
        lumis_sampler *s = make_sampler(env, &cfg);
        for (int k = 0; k < 100000; k++) {
            lumis_env_sample e =
                lumis_sampler_sample(s, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
            lumis_rgb L;
            float p = lumis_sampler_pdf_radiance(s, e.dir, &L);
            if (p != e.pdf || memcmp(&L, &e.radiance, sizeof L) != 0)
                fail_msg("%s, sample %d: pdf %.9g, pdf(dir) %.9g", cfg.name, k, e.pdf, p);
        }
        lumis_sampler_destroy(s);
    }
    lumis_envmap_destroy(env);
}

/* ---- inverse warps ------------------------------------------------------------------ */

static double angle_between(lumis_vec3 a, lumis_vec3 b)
{
    double cx = (double)a.y * b.z - (double)a.z * b.y, cy = (double)a.z * b.x - (double)a.x * b.z,
           cz = (double)a.x * b.y - (double)a.y * b.x;
    double d = (double)a.x * b.x + (double)a.y * b.y + (double)a.z * b.z;
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), d);
}

/* invert(sample(u)) == u and sample(invert(dir)) == dir, to the float rounding of the
 * direction, on every map (zero rows and pixels included); directions in pixels of
 * probability 0 invert to a u whose sample is a lit pixel; alias and the kd-tree methods
 * refuse. */
static void invert_round_trips(void **state)
{
    (void)state;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 31, 4);
    for (int m = 0; m < NMAPS; m++) {
        lumis_envmap *env = make_map(&maps[m]);
        for (int c = 0; c < NCONFIGS; c++) {
            lumis_sampler *s = make_sampler(env, &configs[c]);
            lumis_sampler_method method = configs[c].method;
            double v[2];
            lumis_vec3 up = {0.0f, 1.0f, 0.0f};
            if (method == LUMIS_METHOD_ALIAS || method == LUMIS_METHOD_KDTREE ||
                method == LUMIS_METHOD_KDTREE_EXACT) {
                assert_int_equal(lumis_sampler_invert(s, up, v), LUMIS_ERR_UNSUPPORTED);
                lumis_sampler_destroy(s);
                continue;
            }
            assert_int_equal(lumis_sampler_invert(s, (lumis_vec3){0, 0, 0}, v),
                             LUMIS_ERR_INVALID_ARGUMENT);
            assert_int_equal(lumis_sampler_invert(s, up, NULL), LUMIS_ERR_INVALID_ARGUMENT);
            double worst_u = 0.0, worst_dir = 0.0;
            for (int k = 0; k < 5000; k++) {
                double u[2] = {lumis_pcg32_double(&rng), lumis_pcg32_double(&rng)};
                lumis_env_sample e = lumis_sampler_sample(s, u[0], u[1]);
                assert_int_equal(lumis_sampler_invert(s, e.dir, v), LUMIS_OK);
                double du = fmax(fabs(v[0] - u[0]), fabs(v[1] - u[1]));
                if (du > worst_u) worst_u = du;
                /* Any direction: through u and back. */
                lumis_vec3 d = {(float)(lumis_pcg32_double(&rng) - 0.5),
                                (float)(lumis_pcg32_double(&rng) - 0.5),
                                (float)(lumis_pcg32_double(&rng) - 0.5)};
                assert_int_equal(lumis_sampler_invert(s, d, v), LUMIS_OK);
                assert_true(v[0] >= 0.0 && v[0] < 1.0 && v[1] >= 0.0 && v[1] < 1.0);
                lumis_env_sample b = lumis_sampler_sample(s, v[0], v[1]);
                assert_true(b.pdf > 0.0f); /* even from a pixel never drawn */
                if (lumis_sampler_pdf(s, d) > 0.0f) {
                    double a = angle_between(b.dir, d);
                    if (a > worst_dir) worst_dir = a;
                }
            }
            /* Float directions carry about 1e-7 rad; a pixel of these maps is >= 0.1 rad
             * wide in azimuth and the polar rows >= 0.005 in cos theta. */
            if (worst_u > 2e-5 || worst_dir > 2e-6)
                fail_msg("%s on %s: |invert(sample(u)) - u| up to %g, angle(sample(invert(d)), "
                         "d) up to %g rad",
                         configs[c].name, maps[m].name, worst_u, worst_dir);
            lumis_sampler_destroy(s);
        }
        lumis_envmap_destroy(env);
    }
}

/* A pixel of probability 0 inverts to where its share of [0, 1)^2 would start. */
static void invert_of_a_dark_pixel(void **state)
{
    (void)state;
    const map_case holes = {"holes", 20, 16, f_holes, 0.0f, 0};
    lumis_envmap *env = make_map(&holes);
    lumis_sampler_desc d = {0};
    d.method = LUMIS_METHOD_INVERSION;
    lumis_sampler *s = NULL;
    assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_OK);
    /* Pixel (2, 3) is dark in a lit row: u1 lies where pixel 3 of that row begins, u2
     * inside the row. */
    double u[2], left[2];
    lumis_vec3 dark = cell_dir(env, 2, 3, 1, 0, 0), next = cell_dir(env, 3, 3, 4, 0, 0);
    assert_true(lumis_sampler_pdf(s, dark) == 0.0f);
    assert_int_equal(lumis_sampler_invert(s, dark, u), LUMIS_OK);
    assert_int_equal(lumis_sampler_invert(s, next, left), LUMIS_OK);
    assert_true(u[0] <= left[0] && left[0] - u[0] < 0.01);
    int i, j;
    lumis_env_sample e = lumis_sampler_sample(s, u[0], u[1]);
    lumis_envmap_dir_to_pixel(env, e.dir, &i, &j);
    assert_int_equal(j, 3);
    assert_int_equal(i, 3);
    lumis_sampler_destroy(s);
    lumis_envmap_destroy(env);
}

/* ---- specific properties ------------------------------------------------------------- */

static float f_black(int i, int j, int c)
{
    (void)i, (void)j, (void)c;
    return 0.0f;
}

static void black_map_falls_back_to_uniform_and_says_so(void **state)
{
    (void)state;
    lumis_image *img = tu_image(16, 8, f_black);
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    for (int m = 1; m < LUMIS_METHOD_UNIFORM; m++) {
        tu_sink sink;
        tu_sink_init(&sink);
        lumis_sampler_desc d = {0};
        d.method = (lumis_sampler_method)m;
        d.compensate = m == LUMIS_METHOD_ALIAS;
        d.errors = sink.sink;
        lumis_sampler *s = NULL;
        assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_OK);
        assert_true(lumis_sampler_is_uniform_fallback(s));
        assert_int_equal(sink.count, 1);
        assert_int_equal(sink.status, LUMIS_OK);
        assert_non_null(strstr(sink.last, "uniformly"));
        lumis_env_sample e = lumis_sampler_sample(s, 0.3, 0.6);
        assert_true(fabsf(e.pdf - (float)(1 / (4 * PI))) < 1e-7f);
        lumis_sampler_destroy(s);
    }
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

static void sampler_keeps_its_map_alive(void **state)
{
    (void)state;
    lumis_image *img = tu_image(8, 4, f_grad);
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    lumis_image_destroy(img);
    lumis_sampler *s = NULL;
    assert_int_equal(lumis_sampler_create(env, NULL, &s), LUMIS_OK);
    assert_int_equal(lumis_sampler_get_method(s), LUMIS_METHOD_INVERSION_GUIDED);
    lumis_envmap_destroy(env); /* the sampler still holds it (ASan would catch a use) */
    lumis_env_sample e = lumis_sampler_sample(s, 0.5, 0.5);
    assert_true(e.pdf > 0.0f && e.radiance.r > 0.0f);
    lumis_sampler_destroy(s);
}

static void invalid_descriptors(void **state)
{
    (void)state;
    lumis_image *img = tu_image(8, 4, f_grad);
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    lumis_sampler *s = NULL;
    lumis_sampler_desc d = {0};
    d.method = LUMIS_METHOD_COUNT;
    assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_ERR_INVALID_ARGUMENT);
    d.method = LUMIS_METHOD_KDTREE;
    d.kdtree_blocks = -1;
    assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_sampler_create(NULL, NULL, &s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_sampler_create(env, NULL, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_sampler_method m;
    assert_int_equal(lumis_sampler_method_from_name("kdtree-exact", &m), LUMIS_OK);
    assert_int_equal(m, LUMIS_METHOD_KDTREE_EXACT);
    assert_int_equal(lumis_sampler_method_from_name("cdf", &m), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_sampler_destroy(NULL);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

/* The pdf of an exact method is the importance it was asked for over its total, per
 * steradian: pdf(pixel) / value(pixel) is the same for every pixel, with the value the
 * luminance, the channels' mean or their maximum (f_colour has every channel the largest
 * somewhere). */
static void importance_kinds_weight_the_channels(void **state)
{
    (void)state;
    lumis_image *img = tu_image(24, 12, f_colour);
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    static const lumis_importance kinds[] = {LUMIS_IMPORTANCE_LUMINANCE, LUMIS_IMPORTANCE_AVERAGE,
                                             LUMIS_IMPORTANCE_MAX_CHANNEL};
    for (int k = 0; k < 3; k++) {
        lumis_sampler_desc d = {0};
        d.method = LUMIS_METHOD_INVERSION;
        d.importance = kinds[k];
        lumis_sampler *s = NULL;
        assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_OK);
        double ratio0 = 0.0;
        for (int j = 0; j < 12; j++)
            for (int i = 0; i < 24; i++) {
                const float *p = img->pixels + 3 * (j * 24 + i);
                double v = k == 0   ? 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
                           : k == 1 ? (p[0] + p[1] + p[2]) / 3.0
                                    : fmax(fmax(p[0], p[1]), p[2]);
                double ratio = lumis_sampler_pdf(s, cell_dir(env, i, j, 1, 0, 0)) / v;
                if (i == 0 && j == 0) ratio0 = ratio;
                if (!(fabs(ratio / ratio0 - 1.0) < 1e-5))
                    fail_msg("importance %d, pixel (%d, %d): pdf / value %.9g, pixel 0 %.9g", k, i,
                             j, ratio, ratio0);
            }
        lumis_sampler_destroy(s);
    }
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

static int bright_a_i = 3, bright_a_j = 2, bright_b_i = 9, bright_b_j = 5;
static float f_two_bright(int i, int j, int c)
{
    (void)c;
    if (i == bright_a_i && j == bright_a_j) return 10.0f;
    if (i == bright_b_i && j == bright_b_j) return 20.0f;
    return 1.0f;
}

/* MIS compensation (Karlik et al. 2019) subtracts the mean over the sphere,
 * mean = sum(v Omega) / 4 pi: on a grey map of 1 with pixels of 10 and 20 only those two
 * keep importance, in the ratio (10 - mean) / (20 - mean) per steradian. */
static void compensation_subtracts_the_mean_over_the_sphere(void **state)
{
    (void)state;
    lumis_image *img = tu_image(16, 8, f_two_bright);
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    const double oa = lumis_equirect_solid_angle(16, 8, bright_a_j),
                 ob = lumis_equirect_solid_angle(16, 8, bright_b_j);
    const double mean = 1.0 + (9.0 * oa + 19.0 * ob) / (4.0 * PI);
    static const lumis_sampler_method methods[] = {LUMIS_METHOD_ALIAS, LUMIS_METHOD_INVERSION};
    for (int m = 0; m < 2; m++) {
        lumis_sampler_desc d = {0};
        d.method = methods[m];
        d.compensate = 1;
        lumis_sampler *s = NULL;
        assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_OK);
        const double pa = lumis_sampler_pdf(s, cell_dir(env, bright_a_i, bright_a_j, 1, 0, 0));
        const double pb = lumis_sampler_pdf(s, cell_dir(env, bright_b_i, bright_b_j, 1, 0, 0));
        const double want_pa = (10.0 - mean) / ((10.0 - mean) * oa + (20.0 - mean) * ob);
        if (!(fabs(pa / pb - (10.0 - mean) / (20.0 - mean)) < 1e-6 &&
              fabs(pa / want_pa - 1.0) < 1e-6))
            fail_msg("%s: pdfs %.9g and %.9g, want %.9g in the ratio %.9g",
                     lumis_sampler_method_name(methods[m]), pa, pb, want_pa,
                     (10.0 - mean) / (20.0 - mean));
        assert_true(lumis_sampler_pdf(s, cell_dir(env, 0, 0, 1, 0, 0)) == 0.0f);
        lumis_sampler_destroy(s);
    }
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

/* What the tables take, counted by hand for a 20 x 10 map lit everywhere: inversion has
 * a 4-byte CDF entry per pixel and per row, the guided variant a guide of n + 1 entries
 * beside each CDF; alias has a 16-byte bin per pixel. */
static void table_bytes_count_every_table(void **state)
{
    (void)state;
    lumis_image *img = tu_image(20, 10, f_grad);
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    static const struct {
        lumis_sampler_method method;
        size_t bytes;
    } want[] = {{LUMIS_METHOD_INVERSION, 4 * (10 + 10 * 20)},
                {LUMIS_METHOD_INVERSION_GUIDED, 4 * (10 + 11 + 10 * (20 + 21))},
                {LUMIS_METHOD_ALIAS, 16 * 200}};
    for (int k = 0; k < 3; k++) {
        lumis_sampler_desc d = {0};
        d.method = want[k].method;
        lumis_sampler *s = NULL;
        assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_OK);
        if (lumis_sampler_table_bytes(s) != want[k].bytes)
            fail_msg("%s: %zu table bytes, want %zu", lumis_sampler_method_name(want[k].method),
                     lumis_sampler_table_bytes(s), want[k].bytes);
        assert_true(lumis_sampler_total_bytes(s) > lumis_sampler_table_bytes(s));
        lumis_sampler_destroy(s);
    }
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

/* The alias table realises exactly the pmf it stores, at 2^21 entries: every column's
 * threshold and alias are summed back into probabilities. */
static void alias_is_exact_at_2048x1024(void **state)
{
    (void)state;
    lumis_sky_desc sd = {0};
    sd.width = 2048;
    sd.sun_elevation_deg = 20.0f;
    lumis_image *img = NULL;
    assert_int_equal(lumis_sky_create(&sd, &img), LUMIS_OK);
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    lumis_image_destroy(img);
    lumis_sampler_desc d = {0};
    d.method = LUMIS_METHOD_ALIAS;
    lumis_sampler *s = NULL;
    assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_OK);
    /* The sampler's data starts with its alias table (sampler_alias.c). */
    const lumis__alias *a = s->data;
    size_t n = a->n;
    double *real = calloc(n, sizeof(double)), *imp = NULL, total = 0.0;
    for (size_t k = 0; k < n; k++) {
        const lumis__alias_bin *b = &a->bin[k];
        double keep = b->thresh == 0xffffffffu && b->alias == k ? 4294967296.0 : (double)b->thresh;
        real[k] += keep;
        real[b->alias] += 4294967296.0 - keep;
        /* A bin carries its alias's value, so a draw reads one bin. */
        assert_true(b->alias_value == a->bin[b->alias].value);
    }
    assert_int_equal(lumis__importance(env, &d, &imp, &total), LUMIS_OK);
    double tv = 0.0, worst = 0.0;
    for (size_t k = 0; k < n; k++) {
        /* The bins store the density per steradian; times Omega, the probability. */
        double stored = a->bin[k].value * lumis_envmap_pixel_solid_angle(env, (int)(k / 2048));
        double p = real[k] / (4294967296.0 * (double)n);
        double rel = fabs(p - stored) / stored;
        if (rel > worst) worst = rel;
        tv += 0.5 * fabs(p - imp[k] / total);
        assert_true(imp[k] == 0.0 || stored > 0.0); /* nothing that shines is lost */
    }
    /* Realised == stored to float rounding; stored == importance to 2^-32 quantisation. */
    if (worst > 1e-7) fail_msg("realised pmf differs from stored by %g (relative)", worst);
    if (tv > 1e-6) fail_msg("total variation from the importance %g", tv);
    free(real);
    free(imp);
    lumis_sampler_destroy(s);
    lumis_envmap_destroy(env);
}

/* ---- kd-tree invariants ------------------------------------------------------------- */

static void kdtree_blocks_partition_the_map(void **state)
{
    (void)state;
    static const int counts[] = {1, 2, 7, 64, 300};
    lumis_envmap *env = make_map(&maps[3]); /* sun sky, 64 x 32 */
    for (int k = 0; k < 5; k++) {
        lumis_sampler_desc d = {0};
        d.method = LUMIS_METHOD_KDTREE;
        d.kdtree_blocks = counts[k];
        lumis_sampler *s = NULL;
        assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_OK);
        int n;
        const uint16_t *b = lumis__kdtree_blocks(s, &n);
        assert_int_equal(n, counts[k]);
        assert_int_equal(lumis_sampler_kdtree_blocks(s), n);
        int cover[64 * 32] = {0};
        for (int q = 0; q < n; q++)
            for (int y = b[4 * q + 1]; y < b[4 * q + 3]; y++)
                for (int x = b[4 * q]; x < b[4 * q + 2]; x++) cover[y * 64 + x]++;
        for (int p = 0; p < 64 * 32; p++) assert_int_equal(cover[p], 1);
        lumis_sampler_destroy(s);
    }
    lumis_envmap_destroy(env);
    /* A constant map needs one block, whatever was asked. */
    env = make_map(&maps[0]);
    lumis_sampler_desc d = {0};
    d.method = LUMIS_METHOD_KDTREE;
    lumis_sampler *s = NULL;
    assert_int_equal(lumis_sampler_create(env, &d, &s), LUMIS_OK);
    assert_int_equal(lumis_sampler_kdtree_blocks(s), 1);
    lumis_sampler_destroy(s);
    lumis_envmap_destroy(env);
}

static void kdtree_split_is_the_brute_force_optimum(void **state)
{
    (void)state;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 17, 1);
    for (int trial = 0; trial < 50; trial++) {
        int w = 2 + (int)lumis_pcg32_bounded(&rng, 12), h = 2 + (int)lumis_pcg32_bounded(&rng, 9);
        double v[14 * 11], rows[12], om[11];
        double *sat = calloc((size_t)(w + 1) * (h + 1), sizeof(double));
        rows[0] = 0;
        for (int j = 0; j < h; j++) {
            om[j] = lumis_equirect_solid_angle(w, h, j);
            rows[j + 1] = rows[j] + om[j];
        }
        for (int j = 0; j < h; j++)
            for (int i = 0; i < w; i++) {
                double y = lumis_pcg32_double(&rng);
                v[j * w + i] = y * y * y * om[j];
            }
        for (int j = 0; j < h; j++)
            for (int i = 0; i < w; i++)
                sat[(j + 1) * (w + 1) + i + 1] = v[j * w + i] + sat[j * (w + 1) + i + 1] +
                                                 sat[(j + 1) * (w + 1) + i] - sat[j * (w + 1) + i];
        /* Brute force: every split, sums recomputed pixel by pixel. */
        double best = -1;
        int bax = -1, bpos = -1;
        for (int axis = 0; axis < 2; axis++)
            for (int pos = 1; pos < (axis ? h : w); pos++) {
                double ls = 0, rs = 0, lz = 0, rz = 0;
                for (int j = 0; j < h; j++)
                    for (int i = 0; i < w; i++) {
                        int left = axis ? j < pos : i < pos;
                        if (left) {
                            ls += v[j * w + i];
                            lz += om[j];
                        } else {
                            rs += v[j * w + i];
                            rz += om[j];
                        }
                    }
                double g = ls * ls / lz + rs * rs / rz;
                if (g > best * (1 + 1e-12)) {
                    best = g;
                    bax = axis;
                    bpos = pos;
                }
            }
        int axis, pos;
        assert_true(lumis__kdtree_best_split(sat, rows, w, 0, 0, w, h, &axis, &pos));
        if (axis != bax || pos != bpos)
            fail_msg("trial %d (%dx%d): split %d@%d, brute force %d@%d", trial, w, h, axis, pos,
                     bax, bpos);
        free(sat);
    }
}

static void kdtree_alpha_minimises_the_objective(void **state)
{
    (void)state;
    /* Sorted probabilities shaped like a real map's: a few bright blocks, a long tail. */
    enum { N = 500 };
    double p[N], sum = 0;
    for (int i = 0; i < N; i++) sum += p[i] = 1.0 / (3.0 + i) + 1e-4 * exp(-i / 50.0);
    for (int i = 0; i < N; i++) p[i] /= sum;
    double a = lumis__kdtree_fit_alpha(p, N), e = lumis__kdtree_objective(p, N, a);
    for (int k = 0; k <= 4000; k++) {
        double b = exp(log(1e-4) + (log(1e5) - log(1e-4)) * k / 4000.0);
        if (lumis__kdtree_objective(p, N, b) < e * (1 - 1e-9))
            fail_msg("objective(%g) = %.12g < objective(fitted %g) = %.12g", b,
                     lumis__kdtree_objective(p, N, b), a, e);
    }
    /* Data drawn from the model itself: the fit finds its alpha. */
    double q[N], span = log1p(N / 7.5);
    for (int i = 0; i < N; i++) q[i] = log1p(1.0 / (7.5 + i)) / span;
    double fit = lumis__kdtree_fit_alpha(q, N);
    if (fabs(fit - 7.5) > 1e-4 * 7.5) fail_msg("model data alpha 7.5, fitted %g", fit);
}

/* ---- real maps ---------------------------------------------------------------------- */

/* The true standard error of the n-sample power estimate, sqrt((int Y^2/p - P^2) / n), by
 * summing over pixels (centres: exact for densities constant per pixel).  An empirical
 * error from the samples themselves would miss rare bright hits of heavy-tailed
 * estimators (uniform sampling of a sun) and call a correct sampler biased. */
static double true_stderr(const lumis_sampler *s, const lumis_envmap *env, double power, int n)
{
    int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    double m2 = 0.0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double y = lumis_luminance(lumis_envmap_texel(env, i, j));
            if (y == 0.0) continue;
            double pdf = lumis_sampler_pdf(s, cell_dir(env, i, j, 1, 0, 0));
            m2 += y * y * lumis_envmap_pixel_solid_angle(env, j) / pdf;
        }
    return sqrt(fmax(m2 - power * power, 0.0) / n);
}

/* Power estimate from n samples: mean and standard error of Y / pdf. */
static void power_estimate(const lumis_sampler *s, int n, uint64_t seed, double *mean, double *se)
{
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, seed, 3);
    double sum = 0.0, sum2 = 0.0;
    for (int k = 0; k < n; k++) {
        lumis_env_sample e =
            lumis_sampler_sample(s, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
        double w = lumis_luminance(e.radiance) / e.pdf;
        sum += w;
        sum2 += w * w;
    }
    *mean = sum / n;
    *se = sqrt(fmax(sum2 / n - *mean * *mean, 0.0) / n);
}

/* Every real map, every method: per-pixel chi-square (bins pooled where the expected
 * count is below 5), which catches probability moved between pixels, and unbiasedness. */
static void real_maps_per_pixel_chi_square(void **state)
{
    (void)state;
    static const char *const files[] = {
        "blender-city.exr",     "blender-courtyard.exr", "blender-forest.exr",
        "blender-interior.exr", "blender-night.exr",     "blender-studio.exr",
        "blender-sunrise.exr",  "blender-sunset.exr",    "pmndrs-apartment.exr",
        "pmndrs-city.exr",      "pmndrs-dawn.exr",       "pmndrs-forest.exr",
        "pmndrs-lobby.exr",     "pmndrs-night.exr",      "pmndrs-studio.exr",
        "pmndrs-sunrise.exr",   "pmndrs-sunset.exr",     "pmndrs-venice.exr"};
    enum { NFILES = sizeof files / sizeof files[0] };
    char path[1024];
    snprintf(path, sizeof path, "%s/hdri/%s", LUMIS_DATA_DIR, files[0]);
    if (access(path, R_OK) != 0) {
        print_message("data/ not fetched: skipping the real maps\n");
        skip();
    }
    const double alpha = 0.01 / (NFILES * NCONFIGS);
    for (int f = 0; f < NFILES; f++) {
        snprintf(path, sizeof path, "%s/hdri/%s", LUMIS_DATA_DIR, files[f]);
        lumis_image *img = NULL;
        assert_int_equal(lumis_image_read(path, NULL, &img, NULL), LUMIS_OK);
        lumis_envmap *env = NULL;
        assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
        lumis_image_destroy(img);
        double power = exact_power_y(env);
        for (int c = 0; c < NCONFIGS; c++) {
            config cfg = configs[c];
            cfg.blocks = 0; /* the default 6144 blocks */
            lumis_sampler *s = make_sampler(env, &cfg);
            double p = chi2_against_pdf(s, env, cfg.uniform_angles, 1, 250000, 77u + (uint64_t)c);
            if (!(p > alpha))
                fail_msg("%s on %s: per-pixel chi-square p = %g", cfg.name, files[f], p);
            if (!cfg.compensate) {
                double mean, se;
                power_estimate(s, 100000, 5u + (uint64_t)c, &mean, &se);
                if (fabs(mean - power) > 4 * se + 1e-5 * power) /* then judge by the truth */
                    se = fmax(se, true_stderr(s, env, power, 100000));
                if (fabs(mean - power) > 4 * se + 1e-5 * power)
                    fail_msg("%s on %s: power %.6g +- %.2g, exact %.6g", cfg.name, files[f], mean,
                             se, power);
            }
            lumis_sampler_destroy(s);
        }
        lumis_envmap_destroy(env);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pdf_integrates_to_one),
        cmocka_unit_test(pdf_of_sample_matches),
        cmocka_unit_test(chi_square_goodness_of_fit),
        cmocka_unit_test(power_estimates_are_unbiased),
        cmocka_unit_test(exact_samplers_line_up_with_eval),
        cmocka_unit_test(exact_on_small_pixels),
        cmocka_unit_test(invert_round_trips),
        cmocka_unit_test(invert_of_a_dark_pixel),
        cmocka_unit_test(weights_are_bounded),
        cmocka_unit_test(black_map_falls_back_to_uniform_and_says_so),
        cmocka_unit_test(sampler_keeps_its_map_alive),
        cmocka_unit_test(invalid_descriptors),
        cmocka_unit_test(alias_is_exact_at_2048x1024),
        cmocka_unit_test(importance_kinds_weight_the_channels),
        cmocka_unit_test(compensation_subtracts_the_mean_over_the_sphere),
        cmocka_unit_test(table_bytes_count_every_table),
        cmocka_unit_test(kdtree_blocks_partition_the_map),
        cmocka_unit_test(kdtree_split_is_the_brute_force_optimum),
        cmocka_unit_test(kdtree_alpha_minimises_the_objective),
        cmocka_unit_test(real_maps_per_pixel_chi_square),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
