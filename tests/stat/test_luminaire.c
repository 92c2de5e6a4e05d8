/* Tests of the light-field luminaire (lumis/luminaire.h), fixed seeds: deterministic.
 *
 * The bases are partitions of unity; the restricted sampler draws exactly its restricted
 * pdf (chi-square per pixel piece), pdf(sample) and invert(sample) agree with the draw,
 * and the secant search lands where bisection does; balancing keeps every image with
 * A_m(p) > 0 and spends the budget; the estimator's mean equals the quadrature irradiance
 * at points near, far, grazing, between the planes, on S and outside every support, for
 * every strategy; the quadrature over S agrees with one over U; a generated luminaire
 * reproduces its emitter's irradiance; malformed descriptors get a clear error. */
/* Oracles:
 * lumis_luminaire_basis_eval — brute force: every basis integrates to 1 and its shifts sum to 1 (1D
 *     and on a grid); zero at its radius (bases_are_partitions_of_unity)
 * lumis_luminaire_basis_radius — hand-worked: the basis is 0 at the radius and positive just inside
 *     (bases_are_partitions_of_unity)
 * lumis_luminaire_basis_name — hand-worked: "quadratic" (bases_are_partitions_of_unity)
 * lumis_luminaire_basis_from_name — hand-worked: "bspline" (bases_are_partitions_of_unity)
 * lumis_luminaire_sample_image — statistical: chi-square per pixel piece against the restricted
 *     pdf; uniform density x box area = 1; the secant search lands where bisection does
 *     (restricted_sampler_draws_its_pdf, uniform_sampler_pdf_and_inverse,
 *     secant_search_matches_binary_search)
 * lumis_luminaire_pdf — consistency: the pdf the draw returned, both strategies
 *     (restricted_sampler_draws_its_pdf, uniform_sampler_pdf_and_inverse)
 * lumis_luminaire_invert — consistency: undoes lumis_luminaire_sample_image, both strategies
 *     (restricted_sampler_draws_its_pdf, uniform_sampler_pdf_and_inverse)
 * lumis_luminaire_balance — hand-worked: masses 1 0 2 3 at budgets ≤ 0 give 1 0 1 1; budgets 1, 16,
 *     17, 64 over 17 lit images spend max(budget, 17); every lit image kept
 *     (balance_floor_below_the_lit_images, balancing_keeps_every_image_and_spends_the_budget)
 * lumis_luminaire_irradiance — brute force: a dense midpoint rule over U of L cos cos / r^2 written
 *     in the test; closed form via the emitter it was acquired from
 *     (quadrature_over_s_matches_quadrature_over_u, generated_luminaire_reproduces_its_emitter)
 * lumis_luminaire_radiance — indirect: the integrand of the test's midpoint rule over U
 *     (quadrature_over_s_matches_quadrature_over_u)
 * lumis_luminaire_estimate — statistical: the mean equals the quadrature irradiance near, far,
 *     grazing, between the planes, on S, outside every support, for every strategy
 *     (estimator_mean_equals_quadrature)
 * lumis_luminaire_sample_point — statistical: mean equals the quadrature, variance measured against
 *     the prediction; consistency: the draws of lumis_luminaire_sample_image, numbers on demand the
 *     same as the array (estimator_mean_equals_quadrature,
 *     sample_point_draws_what_sample_image_draws, numbers_on_demand_match_the_array)
 * lumis_luminaire_capacity — hand-worked: a sample for every image when the budget is smaller
 *     (luminaire_power_and_limits)
 * lumis_luminaire_masses — brute force: the boxes' integrals, exactly 0 where a box misses every
 *     nonzero pixel (sample_point_draws_what_sample_image_draws)
 * lumis_luminaire_global_draw — consistency: drawn once and finished per point, bit for bit
 *     lumis_luminaire_sample_point (global_draws_finish_like_sample_point)
 * lumis_luminaire_global_finish — consistency: bit for bit lumis_luminaire_sample_point; nothing
 *     behind U (global_draws_finish_like_sample_point)
 * lumis_luminaire_predict — statistical: predicted variance against the measured variance of each
 *     strategy; hand-worked: time is the cost model term by term with prime costs; selected probes
 *     unbiased over seeds (prediction_matches_measured_variance, prediction_time_is_the_cost_model,
 *     selected_probes_predict_the_same_means)
 * lumis_luminaire_probes — statistical: log-uniform in distance, half nearer than sqrt(dmin dmax),
 *     a third per decade (probes_are_log_uniform_in_distance)
 * lumis_luminaire_costs_default — none: only used as a base for changed costs
 *     (prediction_arguments_and_bands)
 * lumis_luminaire_create — brute force: total power the sum over images of each pixel's luminance
 *     times its area on S, any grid; 1024 images accepted, 1025 refused
 *     (luminaire_power_and_limits, malformed_descriptors_get_a_clear_error)
 * lumis_luminaire_get_info — brute force: total_power against the sum written in the test
 *     (luminaire_power_and_limits)
 * lumis_luminaire_get_desc — consistency: the geometry and images it was created with
 *     (sample_point_draws_what_sample_image_draws)
 * lumis_luminaire_image — consistency: the pixels it was created with
 *     (sample_point_draws_what_sample_image_draws)
 * lumis_luminaire_destroy — external: leaks seen by ASan and valgrind (luminaire_power_and_limits)
 * lumis_luminaire_acquire — closed form: the generated luminaire reproduces its emitter's
 *     irradiance, itself checked against closed forms (generated_luminaire_reproduces_its_emitter)
 * lumis_luminaire_preset_get — indirect: the presets acquired in
 *     generated_luminaire_reproduces_its_emitter
 * lumis_luminaire_preset_create — error paths only: test_edges refuses bad arguments; the presets'
 *     luminaires only through the CLI
 * lumis_luminaire_preset_name — none: called by no test
 * lumis_luminaire_preset_from_name — none: called by no test (the CLI's --preset names only)
 * lumis_emitter_irradiance — closed form: on-axis disk E = pi L R^2 / (R^2 + D^2) and the cos^n
 *     lobe (emitter_matches_closed_forms)
 * lumis_emitter_radiance — closed form: a striped plate's dark and clear stripes
 *     (emitter_matches_closed_forms)
 * lumis_luminaire_check — hand-worked: both sides of every limit (grid axes, images, sides)
 *     agree with create's verdict (malformed_descriptors_get_a_clear_error)
 * lumis_rigid_identity — hand-worked: passes lumis_rigid_check (rigid_transform_round_trip)
 * lumis_rigid_check — hand-worked: a rotation passes, a scaled axis and a reflection are refused
 *     (rigid_transform_round_trip)
 * lumis_rigid_point_to_world — hand-worked: two points through a rotation about y and a
 *     translation, and the round trip (rigid_transform_round_trip)
 * lumis_rigid_point_to_local — hand-worked: t maps to the origin, t + R z to +z, and the
 *     round trip (rigid_transform_round_trip)
 * lumis_rigid_dir_to_world — hand-worked: x = cos 0.7 x + sin 0.7 z for a rotation about y
 *     (rigid_transform_round_trip)
 * lumis_rigid_dir_to_local — hand-worked: R x is +x locally, t ignored; undoes
 *     lumis_rigid_dir_to_world (rigid_transform_round_trip)
 */
#include "../testutil.h"

#include "luminaire/internal.h"
#include "lum_fixture.h"
#include "stat.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- bases ----------------------------------------------------------------------------- */

static void bases_are_partitions_of_unity(void **state)
{
    (void)state;
    for (int b = LUMIS_BASIS_QUADRATIC; b <= LUMIS_BASIS_BSPLINE; b++) {
        const lumis_luminaire_basis basis = (lumis_luminaire_basis)b;
        double integral = 0.0;
        const int n = 200000;
        for (int k = 0; k < n; k++) {
            double x = -2.0 + 4.0 * (k + 0.5) / n;
            integral += lumis_luminaire_basis_eval(basis, x) * 4.0 / n;
        }
        assert_true(fabs(integral - 1.0) < 1e-6);
        for (int k = 0; k <= 1000; k++) {
            double x = -3.0 + 6.0 * k / 1000.0, sum = 0.0;
            for (int c = -6; c <= 6; c++) sum += lumis_luminaire_basis_eval(basis, x - c);
            assert_true(fabs(sum - 1.0) < 1e-12);
            assert_true(lumis_luminaire_basis_eval(basis, x) >= 0.0);
        }
        const double r = lumis_luminaire_basis_radius(basis);
        assert_true(lumis_luminaire_basis_eval(basis, r) == 0.0);
        assert_true(lumis_luminaire_basis_eval(basis, r - 1e-3) > 0.0);
        /* In 2D on a luminaire's grid: sum of Phi_m(u) == 1 inside the grid's interior. */
        fixture f = make_fixture(basis, 3);
        for (int k = 0; k < 400; k++) {
            double ux = -0.5 + (r - 1.0) * 0.5 + (1.0 - (r - 1.0)) * (k % 20) / 19.0;
            double uy = -0.5 + (r - 1.0) * 0.5 + (1.0 - (r - 1.0)) * (k / 20) / 19.0;
            double s = 0.0;
            for (int m = 0; m < 9; m++) s += lumis__lum_phi(f.lum, m, ux, uy);
            assert_true(fabs(s - 1.0) < 1e-12);
        }
        free_fixture(&f);
    }
    lumis_luminaire_basis out;
    assert_int_equal(lumis_luminaire_basis_from_name("bspline", &out), LUMIS_OK);
    assert_int_equal(out, LUMIS_BASIS_BSPLINE);
    assert_string_equal(lumis_luminaire_basis_name(LUMIS_BASIS_QUADRATIC), "quadratic");
    /* every strategy and search by its documented name, not only the first */
    static const char *const strategies[] = {"default", "restricted", "uniform", "global", "auto"};
    for (int k = 0; k < LUMIS_LUM_STRATEGY_COUNT; k++) {
        lumis_luminaire_strategy st = LUMIS_LUM_STRATEGY_COUNT;
        assert_int_equal(lumis_luminaire_strategy_from_name(strategies[k], &st), LUMIS_OK);
        assert_int_equal(st, k);
        assert_string_equal(lumis_luminaire_strategy_name(st), strategies[k]);
    }
    static const char *const searches[] = {"default", "secant", "binary"};
    for (int k = 0; k < LUMIS_LUM_SEARCH_COUNT; k++) {
        lumis_luminaire_search se = LUMIS_LUM_SEARCH_COUNT;
        assert_int_equal(lumis_luminaire_search_from_name(searches[k], &se), LUMIS_OK);
        assert_int_equal(se, k);
    }
    lumis_luminaire_strategy st = LUMIS_LUM_UNIFORM;
    assert_int_equal(lumis_luminaire_strategy_from_name("restricted ", &st),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(st, LUMIS_LUM_UNIFORM);
}

/* ---- the restricted sampler --------------------------------------------------------------- */

static const lumis_vec3 test_points[] = {
    {0.1f, -0.05f, 1.3f}, /* near S */
    {0.3f, 0.2f, 4.0f},   /* farther */
    {-0.2f, 0.1f, 0.45f}, /* between U and S: the projection flips */
    {1.2f, -0.6f, 1.05f}, /* off to the side, close */
    {0.0f, 0.0f, 12.0f},  /* far: boxes nearly the supports */
};
enum { NPOINTS = sizeof test_points / sizeof test_points[0] };

static void restricted_sampler_draws_its_pdf(void **state)
{
    (void)state;
    const lumis_luminaire_search searches[] = {LUMIS_LUM_SECANT, LUMIS_LUM_BINARY};
    int tests = 0;
    double pmin = 1.0;
    for (int b = LUMIS_BASIS_QUADRATIC; b <= LUMIS_BASIS_BSPLINE; b++) {
        fixture f = make_fixture((lumis_luminaire_basis)b, 11 + b);
        const lumis_luminaire *l = f.lum;
        for (int pi = 0; pi < NPOINTS; pi++)
            for (int m = 0; m < 9; m += 2) {
                lumis_luminaire_query q = {0};
                q.p = test_points[pi];
                q.search = searches[(pi + m) & 1];
                lumis__box bx;
                if (!lumis__lum_box(l, m, q.p.x, q.p.y, q.p.z, &bx)) continue;
                const double units = lumis__lum_box_units(l, m, &bx);
                if (!(units > 0.0)) continue;
                const int w = l->w;
                const int nb = w * l->h;
                double *obs = calloc((size_t)nb, sizeof(double));
                double *expd = calloc((size_t)nb, sizeof(double));
                for (int j = 0; j < l->h; j++)
                    for (int i = 0; i < w; i++) {
                        double ox = fmin(bx.x1, i + 1.0) - fmax(bx.x0, (double)i);
                        double oy = fmin(bx.y1, j + 1.0) - fmax(bx.y0, (double)j);
                        if (ox > 0.0 && oy > 0.0)
                            expd[j * w + i] = (double)lumis__lum_q(l, m, i, j) * ox * oy / units;
                    }
                lumis_pcg32 rng;
                lumis_pcg32_seed(&rng, 99, (uint64_t)(pi * 16 + m));
                const int N = 20000;
                for (int k = 0; k < N; k++) {
                    double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
                    lumis_luminaire_sample s;
                    assert_int_equal(lumis_luminaire_sample_image(l, &q, m, u1, u2, &s), LUMIS_OK);
                    int i, j;
                    assert_true(lumis__lum_pixel(l, s.s[0], s.s[1], &i, &j));
                    obs[j * w + i] += 1.0;
                    /* Every restricted sample conveys energy. */
                    assert_true(s.radiance.g > 0.0f && s.weight > 0.0f);
                    /* pdf() agrees with the draw, and invert() undoes it. */
                    double pdf = lumis_luminaire_pdf(l, &q, m, s.s[0], s.s[1]);
                    assert_true(fabs(pdf - s.pdf) <= 1e-5 * pdf);
                    if (k < 2000) {
                        double v1, v2;
                        assert_int_equal(lumis_luminaire_invert(l, &q, m, s.s[0], s.s[1], &v1, &v2),
                                         LUMIS_OK);
                        assert_true(fabs(v1 - u1) < 1e-9 && fabs(v2 - u2) < 1e-9);
                    }
                }
                for (int k = 0; k < nb; k++) expd[k] *= N;
                int dof;
                double p = stat_chi2_test(obs, expd, (size_t)nb, &dof);
                assert_true(p >= 0.0); /* no sample in a cell of probability 0 */
                if (p < pmin) pmin = p;
                tests++;
                free(obs);
                free(expd);
            }
        free_fixture(&f);
    }
    printf("restricted chi-square: %d tests, smallest p %.4g\n", tests, pmin);
    assert_true(tests >= 30);
    assert_true(pmin > 0.01 / tests); /* Bonferroni */
}

/* The uniform strategy (the restricted box, uniform in area): its density per unit area of
 * S times the box's area is 1, pdf() agrees with the draw, and invert() undoes it (the
 * round trips were tested for the restricted strategy only: a per-pixel density and an
 * inverse with the wrong width passed). */
static void uniform_sampler_pdf_and_inverse(void **state)
{
    (void)state;
    /* pixels twice as wide as high: a box's width and height in pixels differ */
    fixture f = make_fixture_sized(LUMIS_BASIS_QUADRATIC, 5, 16, 24);
    const lumis_luminaire *l = f.lum;
    lumis_luminaire_info in;
    lumis_luminaire_get_info(l, &in);
    int tests = 0;
    for (int pi = 0; pi < NPOINTS; pi++)
        for (int m = 1; m < 9; m += 3) {
            lumis_luminaire_query q = {0};
            q.p = test_points[pi];
            q.strategy = LUMIS_LUM_UNIFORM;
            lumis__box bx;
            if (!lumis__lum_box(l, m, q.p.x, q.p.y, q.p.z, &bx)) continue;
            const double area = (bx.x1 - bx.x0) * (bx.y1 - bx.y0) * in.pixel[0] * in.pixel[1];
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 7, (uint64_t)(pi * 16 + m));
            for (int k = 0; k < 200; k++) {
                const double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
                lumis_luminaire_sample smp;
                if (lumis_luminaire_sample_image(l, &q, m, u1, u2, &smp) != LUMIS_OK) break;
                const double pdf = lumis_luminaire_pdf(l, &q, m, smp.s[0], smp.s[1]);
                if (!(fabs(pdf - smp.pdf) <= 1e-6 * pdf && fabs(pdf * area - 1.0) < 1e-6))
                    fail_msg("point %d, image %d: pdf %g, drawn %g, times the box's area %g", pi, m,
                             pdf, (double)smp.pdf, pdf * area);
                double v1, v2;
                assert_int_equal(lumis_luminaire_invert(l, &q, m, smp.s[0], smp.s[1], &v1, &v2),
                                 LUMIS_OK);
                if (!(fabs(v1 - u1) < 1e-9 && fabs(v2 - u2) < 1e-9))
                    fail_msg("point %d, image %d: (%g, %g) inverts to (%g, %g)", pi, m, u1, u2, v1,
                             v2);
            }
            tests++;
        }
    assert_true(tests >= 8);
    free_fixture(&f);
}

static void secant_search_matches_binary_search(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_BSPLINE, 5);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 5, 5);
    int compared = 0;
    for (int pi = 0; pi < NPOINTS; pi++)
        for (int m = 0; m < 9; m++)
            for (int k = 0; k < 500; k++) {
                double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
                lumis_luminaire_query q = {0};
                q.p = test_points[pi];
                q.search = LUMIS_LUM_SECANT;
                lumis_luminaire_sample a, b;
                if (lumis_luminaire_sample_image(f.lum, &q, m, u1, u2, &a) != LUMIS_OK) break;
                q.search = LUMIS_LUM_BINARY;
                assert_int_equal(lumis_luminaire_sample_image(f.lum, &q, m, u1, u2, &b), LUMIS_OK);
                assert_true(fabs(a.s[0] - b.s[0]) < 1e-12 && fabs(a.s[1] - b.s[1]) < 1e-12);
                assert_true(a.pdf == b.pdf);
                /* A depth limit still lands in the box, with a finite pdf. */
                q.depth = 1;
                assert_int_equal(lumis_luminaire_sample_image(f.lum, &q, m, u1, u2, &b), LUMIS_OK);
                assert_true(isfinite(b.s[0]) && isfinite(b.pdf));
                compared++;
            }
    assert_true(compared > 10000);
    /* The lockstep bisection of the per-point entry gives the very same draws. */
    for (int pi = 0; pi < NPOINTS; pi++)
        for (int m = 0; m < 9; m++) {
            lumis__box bx;
            if (!lumis__lum_box(f.lum, m, test_points[pi].x, test_points[pi].y, test_points[pi].z,
                                &bx))
                continue;
            const double units = lumis__lum_box_units(f.lum, m, &bx);
            if (!(units > 0.0)) continue;
            lumis__prep pr;
            lumis__lum_prepare(f.lum, m, &bx, units, LUMIS_LUM_RESTRICTED, LUMIS_LUM_BINARY, 0,
                               &pr);
            double u[2 * 19], x[19], y[19], pdf[19];
            int is[19], js[19];
            for (int k = 0; k < 2 * 19; k++) u[k] = lumis_pcg32_double(&rng);
            /* Its marginal searched in the table, tabulated, or as it chooses. */
            for (int tab = -1; tab <= 1; tab++) {
                pr.tabulate = tab;
                lumis__lum_draw_batch(f.lum, &pr, u, 19, x, y, is, js, pdf);
                for (int k = 0; k < 19; k++) {
                    double x1, y1, p1;
                    int i1, j1;
                    lumis__lum_draw_prepared(f.lum, &pr, u[2 * k], u[2 * k + 1], &x1, &y1, &i1, &j1,
                                             &p1);
                    assert_true(x[k] == x1 && y[k] == y1 && pdf[k] == p1 && is[k] == i1 &&
                                js[k] == j1);
                }
            }
        }
    free_fixture(&f);
}

/* Draws of many images at once (lumis__lum_draw_group): more lanes and more tabulated
 * marginals than it holds at a time, images it does not tabulate in between; the very same
 * draws as one at a time. */
static void grouped_draws_match_single_draws(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 8);
    enum { NP = 600 };
    lumis__prep *prs = calloc(NP, sizeof *prs);
    int counts[NP], total = 0, np = 0;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 8, 8);
    for (int k = 0; np < NP && k < 100000; k++) {
        const int m = (int)lumis_pcg32_bounded(&rng, 9);
        const double px = 2.0 * lumis_pcg32_double(&rng) - 1.0, py = lumis_pcg32_double(&rng) - 0.5;
        const double pz =
            k % 2 ? 0.15 + 0.6 * lumis_pcg32_double(&rng) : 1.2 + 4.0 * lumis_pcg32_double(&rng);
        lumis__box bx;
        if (!lumis__lum_box(f.lum, m, px, py, pz, &bx)) continue;
        const double units = lumis__lum_box_units(f.lum, m, &bx);
        if (!(units > 0.0)) continue;
        lumis__lum_prepare(f.lum, m, &bx, units, LUMIS_LUM_RESTRICTED, LUMIS_LUM_BINARY, 0,
                           prs + np);
        prs[np].tabulate = np % 7 == 3 ? -1 : 0; /* some searched in the table */
        counts[np] = np % 5 == 0 ? 1 + (int)lumis_pcg32_bounded(&rng, 90) : 1;
        total += counts[np++];
    }
    assert_int_equal(np, NP);
    int entries = 0; /* tabulated marginal entries: more than the group's buffer (2048) */
    for (int p = 0; p < NP; p++) entries += prs[p].ilast + 2 - prs[p].i0;
    assert_true(entries > 2048 && total > 1000);
    double *u = malloc(2 * (size_t)total * sizeof(double));
    double *x = malloc((size_t)total * sizeof(double)), *y = malloc((size_t)total * sizeof(double));
    double *pdf = malloc((size_t)total * sizeof(double));
    int *is = malloc((size_t)total * sizeof(int)), *js = malloc((size_t)total * sizeof(int));
    for (int k = 0; k < 2 * total; k++) u[k] = lumis_pcg32_double(&rng);
    assert_int_equal(lumis__lum_draw_group(f.lum, prs, counts, NP, u, x, y, is, js, pdf), total);
    for (int p = 0, k = 0; p < NP; p++)
        for (int c = 0; c < counts[p]; c++, k++) {
            double x1, y1, p1;
            int i1, j1;
            lumis__lum_draw_prepared(f.lum, prs + p, u[2 * k], u[2 * k + 1], &x1, &y1, &i1, &j1,
                                     &p1);
            assert_true(x[k] == x1 && y[k] == y1 && pdf[k] == p1 && is[k] == i1 && js[k] == j1);
        }
    free(u), free(x), free(y), free(pdf), free(is), free(js), free(prs);
    free_fixture(&f);
}

/* ---- balancing ----------------------------------------------------------------------------- */

/* The header's promise at and below the floor: a budget of 0 or less still gives every lit
 * image one sample (masses 1 0 2 3: counts 1 0 1 1, sum 3), and budgets of 1, 16, 17 and
 * 64 over 17 lit images spend max(budget, 17) (issue 37: the curated list called the
 * mutant that broke this equivalent). */
static void balance_floor_below_the_lit_images(void **state)
{
    (void)state;
    const double mass[4] = {1, 0, 2, 3};
    for (int budget = -5; budget <= 3; budget++) {
        int counts[4] = {9, 9, 9, 9};
        const int sum = lumis_luminaire_balance(mass, 4, budget, 0, counts);
        if (sum != 3 || counts[0] != 1 || counts[1] != 0 || counts[2] != 1 || counts[3] != 1)
            fail_msg("budget %d: sum %d, counts %d %d %d %d", budget, sum, counts[0], counts[1],
                     counts[2], counts[3]);
    }
    double m17[17];
    for (int i = 0; i < 17; i++) m17[i] = 1.0 + i % 5;
    const int budgets[4] = {1, 16, 17, 64};
    for (int b = 0; b < 4; b++) {
        int c[17], total = 0;
        const int sum = lumis_luminaire_balance(m17, 17, budgets[b], 0, c);
        for (int i = 0; i < 17; i++) {
            assert_true(c[i] >= 1);
            total += c[i];
        }
        const int want = budgets[b] > 17 ? budgets[b] : 17;
        if (sum != want || total != want)
            fail_msg("budget %d: sum %d (counts %d), want %d", budgets[b], sum, total, want);
    }
}

static void balancing_keeps_every_image_and_spends_the_budget(void **state)
{
    (void)state;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 17, 3);
    double mass[99];
    int counts[99];
    for (int t = 0; t < 20000; t++) {
        const int n = 1 + (int)lumis_pcg32_bounded(&rng, 99);
        const int budget = 1 + (int)lumis_pcg32_bounded(&rng, 300);
        const int kmax =
            lumis_pcg32_bounded(&rng, 3) == 0 ? 0 : 1 + (int)lumis_pcg32_bounded(&rng, 40);
        int npos = 0;
        double total = 0.0;
        for (int i = 0; i < n; i++) {
            const uint32_t r = lumis_pcg32_bounded(&rng, 4);
            mass[i] = r == 0   ? 0.0
                      : r == 1 ? 1e-9 * lumis_pcg32_double(&rng)
                               : pow(10.0, 4.0 * lumis_pcg32_double(&rng));
            npos += mass[i] > 0.0;
            total += mass[i];
        }
        const int sum = lumis_luminaire_balance(mass, n, budget, kmax, counts);
        long want = budget < npos ? npos : budget;
        if (kmax > 0 && want > (long)kmax * npos) want = (long)kmax * npos;
        if (npos == 0) want = 0;
        assert_int_equal(sum, want);
        int check = 0, capped = 0, raised = 0;
        for (int i = 0; i < n; i++) {
            check += counts[i];
            if (mass[i] > 0.0) {
                assert_true(counts[i] >= 1);
                if (kmax) assert_true(counts[i] <= kmax);
                capped += kmax && counts[i] == kmax;
                raised += counts[i] == 1;
            } else {
                assert_int_equal(counts[i], 0);
            }
        }
        assert_int_equal(check, sum);
        /* Without caps or minimums intervening, each count is within one of its share. */
        if (!capped && !raised && npos)
            for (int i = 0; i < n; i++)
                assert_true(fabs(counts[i] - sum * mass[i] / total) < 1.0 + 1e-9);
    }
}

/* ---- the estimator against quadrature ----------------------------------------------------- */

typedef struct est_case {
    const char *name;
    lumis_vec3 p, n;
} est_case;

static const est_case est_cases[] = {
    {"near", {0.1f, -0.05f, 1.3f}, {0.0f, 0.0f, -1.0f}},
    {"far", {0.3f, 0.2f, 6.0f}, {0.1f, 0.0f, -1.0f}},
    {"grazing", {1.4f, 0.3f, 1.6f}, {-1.0f, 0.0f, -0.08f}},
    {"between U and S", {-0.2f, 0.1f, 0.45f}, {0.0f, 0.0f, -1.0f}},
    {"on S", {0.15f, -0.1f, 1.0f}, {0.0f, 0.2f, -1.0f}},
    {"outside every support", {40.0f, 0.0f, 1.5f}, {0.0f, 0.0f, -1.0f}},
};

static double lum3(lumis_rgb c)
{
    return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

static void estimator_mean_equals_quadrature(void **state)
{
    (void)state;
    const lumis_luminaire_strategy strategies[] = {LUMIS_LUM_RESTRICTED, LUMIS_LUM_UNIFORM,
                                                   LUMIS_LUM_GLOBAL};
    for (int b = LUMIS_BASIS_QUADRATIC; b <= LUMIS_BASIS_BSPLINE; b++) {
        fixture f = make_fixture((lumis_luminaire_basis)b, 21 + b);
        const int cap = lumis_luminaire_capacity(f.lum, 16);
        lumis_luminaire_sample *s = malloc((size_t)cap * sizeof *s);
        double *u = malloc((size_t)cap * 2 * sizeof(double));
        for (size_t c = 0; c < sizeof est_cases / sizeof est_cases[0]; c++) {
            const est_case *ec = &est_cases[c];
            lumis_rgb ref;
            assert_int_equal(lumis_luminaire_irradiance(f.lum, ec->p, ec->n, 6, &ref), LUMIS_OK);
            for (int st = 0; st < 3; st++) {
                /* The global baseline cannot light points on S: a delta in s it never draws. */
                if (strategies[st] == LUMIS_LUM_GLOBAL && !strcmp(ec->name, "on S")) continue;
                lumis_luminaire_query q = {0};
                q.p = ec->p;
                q.budget = 16;
                q.k_max = 6;
                q.strategy = strategies[st];
                q.search = (c & 1) ? LUMIS_LUM_BINARY : LUMIS_LUM_SECANT;
                lumis_pcg32 rng;
                lumis_pcg32_seed(&rng, 1234, (uint64_t)(c * 8 + (size_t)st));
                const int T = strategies[st] == LUMIS_LUM_RESTRICTED ? 3000 : 12000;
                double sum[3] = {0, 0, 0}, sq = 0.0;
                for (int t = 0; t < T; t++) {
                    for (int k = 0; k < 2 * cap; k++) u[k] = lumis_pcg32_double(&rng);
                    int n;
                    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, cap, s, &n),
                                     LUMIS_OK);
                    lumis_rgb e = lumis_luminaire_estimate(s, n, ec->n);
                    sum[0] += e.r, sum[1] += e.g, sum[2] += e.b;
                    sq += lum3(e) * lum3(e);
                }
                lumis_rgb mean = {(float)(sum[0] / T), (float)(sum[1] / T), (float)(sum[2] / T)};
                const double my = lum3(mean), ry = lum3(ref);
                const double se = sqrt(fmax(sq / T - my * my, 0.0) / T);
                printf("%-9s %-22s %-10s ref %.6g  mean %.6g  se %.2g  (%+.2f se)\n",
                       lumis_luminaire_basis_name((lumis_luminaire_basis)b), ec->name,
                       lumis_luminaire_strategy_name(strategies[st]), ry, my, se,
                       se > 0 ? (my - ry) / se : 0.0);
                if (!strcmp(ec->name, "outside every support")) {
                    assert_true(ry == 0.0 && my == 0.0);
                    continue;
                }
                assert_true(ry > 0.0);
                assert_true(fabs(my - ry) < 4.5 * se + 2e-3 * ry);
                /* Colour too (Eq. 14): each channel within its own tolerance. */
                assert_true(fabs(mean.r - ref.r) < 6.0 * se + 5e-3 * ref.r + 0.05 * ry);
            }
        }
        free(s);
        free(u);
        free_fixture(&f);
    }
}

/* lumis_luminaire_predict's variance of each strategy at a probe against the variance of
 * lumis_luminaire_sample_point's estimates measured there: restricted and uniform at the
 * probe's budget, global per sample (the measured variance at K = 480 times K, whose
 * counts are proportional to the images' power within rounding). */
static void prediction_matches_measured_variance(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 77);
    enum { PROBES = 6, T = 3000, KG = 480 };
    lumis_luminaire_probe probes[PROBES];
    assert_int_equal(lumis_luminaire_probes(f.lum, 1.5, 6.0, 5, PROBES, probes), LUMIS_OK);
    const int cap = lumis_luminaire_capacity(f.lum, KG);
    lumis_luminaire_sample *s = malloc((size_t)cap * sizeof *s);
    double *u = malloc((size_t)cap * 2 * sizeof(double));
    int checked = 0;
    for (int k = 0; k < PROBES; k++) {
        lumis_luminaire_predict_desc d = {0};
        d.probes = &probes[k];
        d.probe_count = 1;
        d.budget = 24;
        d.pilot = 1024;
        d.seed = 9;
        lumis_luminaire_prediction p;
        assert_int_equal(lumis_luminaire_predict(f.lum, &d, &p), LUMIS_OK);
        if (!p.probes_lit) continue;
        const lumis_luminaire_strategy_prediction *sp[3] = {&p.restricted, &p.uniform, &p.global};
        for (int st = 0; st < 3; st++) {
            lumis_luminaire_query q = {0};
            q.p = probes[k].p;
            q.budget = st == 2 ? KG : 24;
            q.strategy = st == 0   ? LUMIS_LUM_RESTRICTED
                         : st == 1 ? LUMIS_LUM_UNIFORM
                                   : LUMIS_LUM_GLOBAL;
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 31, (uint64_t)(k * 4 + st));
            double s1 = 0.0, s2 = 0.0, n_sum = 0.0;
            for (int t = 0; t < T; t++) {
                for (int j = 0; j < 2 * cap; j++) u[j] = lumis_pcg32_double(&rng);
                int n;
                assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, cap, s, &n), LUMIS_OK);
                const double e = lum3(lumis_luminaire_estimate(s, n, probes[k].n));
                s1 += e;
                s2 += e * e;
                n_sum += n;
            }
            const double mean = s1 / T, var = fmax(s2 / T - mean * mean, 0.0) * (st == 2 ? KG : 1);
            printf("probe %d %-10s samples %5.1f/%5.1f variance predicted %.4g measured %.4g "
                   "(%.3f)\n",
                   k, lumis_luminaire_strategy_name(q.strategy), sp[st]->samples,
                   st == 2 ? 1.0 : n_sum / T, sp[st]->variance, var, sp[st]->variance / var);
            /* T estimates give the variance to some 5-10 %; the pilot's moments as well */
            assert_true(sp[st]->variance > 0.75 * var && sp[st]->variance < 1.33 * var);
            if (st < 2) assert_true(fabs(sp[st]->samples - n_sum / T) < 1e-9);
        }
        /* Over 4 camera samples of a (0,2) sequence (each sample slot's 4 draws an
         * Owen-scrambled (0,2) net of its own): the mean of 4 estimates against the
         * prediction with strata = 4. */
        d.strata = 4;
        lumis_luminaire_prediction p4;
        assert_int_equal(lumis_luminaire_predict(f.lum, &d, &p4), LUMIS_OK);
        for (int st = 0; st < 2; st++) {
            lumis_luminaire_query q = {0};
            q.p = probes[k].p;
            q.budget = 24;
            q.strategy = st == 0 ? LUMIS_LUM_RESTRICTED : LUMIS_LUM_UNIFORM;
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 37, (uint64_t)(k * 4 + st));
            double s1 = 0.0, s2 = 0.0;
            uint64_t *scr = malloc(sizeof *scr * (size_t)cap);
            for (int t = 0; t < T; t++) {
                double mean4 = 0.0;
                for (int j = 0; j < cap; j++)
                    scr[j] = (uint64_t)lumis_pcg32_next(&rng) << 32 | lumis_pcg32_next(&rng);
                for (int c = 0; c < 4; c++) {
                    for (int j = 0; j < cap; j++) lumis_sobol02((uint32_t)c, scr[j], u + 2 * j);
                    int n;
                    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, cap, s, &n),
                                     LUMIS_OK);
                    mean4 += 0.25 * lum3(lumis_luminaire_estimate(s, n, probes[k].n));
                }
                s1 += mean4;
                s2 += mean4 * mean4;
            }
            free(scr);
            const double mean = s1 / T, var = 4.0 * fmax(s2 / T - mean * mean, 0.0);
            const double pv = st == 0 ? p4.restricted.variance : p4.uniform.variance,
                         iv = st == 0 ? p.restricted.variance : p.uniform.variance;
            printf("probe %d %-10s 4 strata: variance predicted %.4g measured %.4g (%.3f); "
                   "independent %.4g\n",
                   k, lumis_luminaire_strategy_name(q.strategy), pv, var, pv / var, iv);
            assert_true(pv <= iv && pv >= 0.25 * iv);
            assert_true(pv > 0.7 * var && pv < 1.4 * var);
        }
        /* Beyond the pilot's 16-point nets the prediction extrapolates: over 64 camera
         * samples it stays between the independent variance and its 1/64 floor, and within
         * 0.6 to 2.5 of the measured one (it errs on the safe side: 1.3-2.2 here, where the
         * measured variances stand 1.1-3.5x above the floor; issue 37: with only 4 strata
         * tested, the floor turned into a cap under-predicted up to 64x unseen). */
        {
            d.strata = 64;
            lumis_luminaire_prediction p64;
            assert_int_equal(lumis_luminaire_predict(f.lum, &d, &p64), LUMIS_OK);
            lumis_luminaire_query q = {0};
            q.p = probes[k].p;
            q.budget = 24;
            q.strategy = LUMIS_LUM_RESTRICTED;
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 41, (uint64_t)k);
            enum { T64 = 300 };
            double s1 = 0.0, s2 = 0.0;
            uint64_t *scr = malloc(sizeof *scr * (size_t)cap);
            for (int t = 0; t < T64; t++) {
                double m64 = 0.0;
                for (int j = 0; j < cap; j++)
                    scr[j] = (uint64_t)lumis_pcg32_next(&rng) << 32 | lumis_pcg32_next(&rng);
                for (int c = 0; c < 64; c++) {
                    for (int j = 0; j < cap; j++) lumis_sobol02((uint32_t)c, scr[j], u + 2 * j);
                    int n;
                    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, cap, s, &n),
                                     LUMIS_OK);
                    m64 += lum3(lumis_luminaire_estimate(s, n, probes[k].n)) / 64.0;
                }
                s1 += m64;
                s2 += m64 * m64;
            }
            free(scr);
            const double mean = s1 / T64, var = 64.0 * fmax(s2 / T64 - mean * mean, 0.0);
            const double pv = p64.restricted.variance, iv = p.restricted.variance;
            printf("probe %d restricted 64 strata: variance predicted %.4g measured %.4g (%.3f); "
                   "independent %.4g\n",
                   k, pv, var, pv / var, iv);
            assert_true(pv <= iv * (1 + 1e-9) && pv >= iv / 64 * (1 - 1e-9));
            assert_true(pv > 0.6 * var && pv < 2.5 * var);
            d.strata = 0;
        }
        checked++;
    }
    assert_true(checked >= PROBES - 1);
    free(s);
    free(u);
    free_fixture(&f);
}

/* The prediction's time is the cost model applied to its own counts, term by term, at a
 * single probe with costs of distinct primes: camera + image x images + draw x samples +
 * ray x rays (global: per sample + ray x rays), work = variance x ns, the ratios global's
 * work over each (issue 37: a cost identity broken this way kept every choice). */
static void prediction_time_is_the_cost_model(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 80);
    lumis_luminaire_probe probes[4];
    assert_int_equal(lumis_luminaire_probes(f.lum, 1.5, 6.0, 11, 4, probes), LUMIS_OK);
    const lumis_luminaire_costs c = {101, 7, 13, 3, 5, 211, 37};
    int checked = 0;
    for (int k = 0; k < 4; k++) {
        lumis_luminaire_predict_desc d = {0};
        d.probes = &probes[k];
        d.probe_count = 1;
        d.budget = 24;
        d.pilot = 256;
        d.seed = 5;
        d.costs = &c;
        lumis_luminaire_prediction p;
        assert_int_equal(lumis_luminaire_predict(f.lum, &d, &p), LUMIS_OK);
        if (!p.probes_lit) continue;
        const double img = p.images_lit;
        const double want[3] = {c.camera + c.image_restricted * img +
                                    c.restricted * p.restricted.samples + c.ray * p.restricted.rays,
                                c.camera + c.image_uniform * img + c.uniform * p.uniform.samples +
                                    c.ray * p.uniform.rays,
                                c.global + c.ray * p.global.rays};
        const lumis_luminaire_strategy_prediction *sp[3] = {&p.restricted, &p.uniform, &p.global};
        for (int st = 0; st < 3; st++) {
            if (fabs(sp[st]->ns - want[st]) > 1e-9 * want[st])
                fail_msg("probe %d strategy %d: %.12g ns, the cost model %.12g", k, st, sp[st]->ns,
                         want[st]);
            assert_true(fabs(sp[st]->work - sp[st]->variance * sp[st]->ns) <= 1e-9 * sp[st]->work);
            if (sp[st]->work > 0)
                assert_true(fabs(sp[st]->time_ratio - p.global.work / sp[st]->work) <=
                            1e-9 * sp[st]->time_ratio);
        }
        checked++;
    }
    assert_true(checked >= 2);
    free_fixture(&f);
}

/* Probes lie log-uniformly between dmin and dmax from their point of U, along their
 * normal's reverse: the distance r = p.z / -n.z; half of them nearer than sqrt(dmin dmax),
 * each decade a third of them (issue 37: drawn uniformly instead, 91 % beyond 10, unseen). */
static void probes_are_log_uniform_in_distance(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 79);
    enum { N = 3000 };
    lumis_luminaire_probe *pr = malloc(sizeof *pr * N);
    assert_int_equal(lumis_luminaire_probes(f.lum, 0.5, 500.0, 3, N, pr), LUMIS_OK);
    int decade[3] = {0, 0, 0}, near = 0;
    for (int k = 0; k < N; k++) {
        const lumis_vec3 n = pr[k].n;
        assert_true(fabs(n.x * n.x + n.y * n.y + n.z * n.z - 1.0) < 1e-5 && n.z < 0);
        const double r = pr[k].p.z / -n.z;
        assert_true(r >= 0.5 * (1 - 1e-5) && r <= 500.0 * (1 + 1e-5));
        near += r < sqrt(0.5 * 500.0);
        decade[r < 5 ? 0 : r < 50 ? 1 : 2]++;
    }
    if (abs(2 * near - N) > 0.06 * N)
        fail_msg("%d of %d probes nearer than the geometric mean", near, N);
    for (int d = 0; d < 3; d++)
        if (abs(3 * decade[d] - N) > 0.08 * N)
            fail_msg("decade %d holds %d of %d probes", d, decade[d], N);
    free(pr);
    free_fixture(&f);
}

/* Probes selected by their proxies (desc.select) and weighted by the inverse of their
 * chance give the means every probe gives: unbiased over seeds, and one draw of 96 of 480
 * within its noise. */
static void selected_probes_predict_the_same_means(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 78);
    enum { N = 480 };
    lumis_luminaire_probe *probes = malloc(sizeof *probes * N);
    assert_int_equal(lumis_luminaire_probes(f.lum, 1.2, 12.0, 6, N, probes), LUMIS_OK);
    lumis_luminaire_predict_desc d = {0};
    d.probes = probes;
    d.probe_count = N;
    d.budget = 16;
    d.seed = 4;
    lumis_luminaire_prediction all, sel;
    assert_int_equal(lumis_luminaire_predict(f.lum, &d, &all), LUMIS_OK);
    d.select = 96;
    {
        double acc[3] = {0};
        for (int sd = 0; sd < 40; sd++) {
            d.seed = 100 + (uint64_t)sd;
            lumis_luminaire_prediction al;
            d.select = 0;
            assert_int_equal(lumis_luminaire_predict(f.lum, &d, &al), LUMIS_OK);
            d.select = 96;
            assert_int_equal(lumis_luminaire_predict(f.lum, &d, &sel), LUMIS_OK);
            acc[0] += sel.restricted.variance / al.restricted.variance;
            acc[1] += sel.uniform.variance / al.uniform.variance;
            acc[2] += sel.global.variance / al.global.variance;
        }
        /* unbiased: over 40 draws of the selection (and of the pilots, the same for both),
         * the mean ratio is 1 */
        printf("selected over all, mean of 40 seeds: %.3f %.3f %.3f\n", acc[0] / 40, acc[1] / 40,
               acc[2] / 40);
        /* (Horvitz-Thompson: within 0.4 %; dividing by the weights' sum instead is off by
         * 1.4-2.2 % here, and caught) */
        for (int st = 0; st < 3; st++) assert_true(fabs(acc[st] / 40 - 1.0) < 0.012);
        d.seed = 4;
    }
    assert_int_equal(lumis_luminaire_predict(f.lum, &d, &sel), LUMIS_OK);
    assert_true(all.probes_lit > 400 && sel.probes_lit > 80 && sel.probes_lit <= 96);
    const lumis_luminaire_strategy_prediction *a[3] = {&all.restricted, &all.uniform, &all.global},
                                              *b[3] = {&sel.restricted, &sel.uniform, &sel.global};
    for (int st = 0; st < 3; st++) {
        printf("strategy %d: variance %.4g selected %.4g (%.3f), ns %.4g selected %.4g\n", st,
               a[st]->variance, b[st]->variance, b[st]->variance / a[st]->variance, a[st]->ns,
               b[st]->ns);
        assert_true(b[st]->variance > 0.75 * a[st]->variance &&
                    b[st]->variance < 1.33 * a[st]->variance);
        assert_true(fabs(b[st]->ns / a[st]->ns - 1.0) < 0.15);
    }
    free(probes);
    free_fixture(&f);
}

/* The prediction's arguments, bands and edge cases: clear refusals, bands that add up to
 * the whole, nothing lit behind U, costs that change the choice. */
static void prediction_arguments_and_bands(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 79);
    enum { N = 96 };
    lumis_luminaire_probe probes[N];
    assert_int_equal(lumis_luminaire_probes(f.lum, 1.5, 20.0, 8, N, probes), LUMIS_OK);
    lumis_luminaire_probe bad[1];
    assert_int_equal(lumis_luminaire_probes(NULL, 1, 2, 1, 1, bad), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_probes(f.lum, 0, 2, 1, 1, bad), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_probes(f.lum, 3, 2, 1, 1, bad), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_probes(f.lum, 1, 2, 1, 0, bad), LUMIS_ERR_INVALID_ARGUMENT);
    tu_sink sink;
    tu_sink_init(&sink);
    const char *msg = sink.last;
    lumis_luminaire_predict_desc d = {0};
    d.probes = probes;
    d.probe_count = N;
    d.errors = sink.sink;
    lumis_luminaire_prediction p;
    assert_int_equal(lumis_luminaire_predict(f.lum, &d, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_predict(NULL, &d, &p), LUMIS_ERR_INVALID_ARGUMENT);
    const struct {
        int field, value;
    } refusals[] = {{0, 0}, {1, -1}, {2, 5}, {3, -1}, {4, 5000}, {5, -2}};
    for (size_t k = 0; k < sizeof refusals / sizeof refusals[0]; k++) {
        lumis_luminaire_predict_desc e = d;
        int *fields[] = {&e.probe_count, &e.budget, &e.bands, &e.k_max, &e.pilot, &e.select};
        *fields[refusals[k].field] = refusals[k].value;
        sink.last[0] = '\0';
        assert_int_equal(lumis_luminaire_predict(f.lum, &e, &p), LUMIS_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(msg, "luminaire prediction"));
        assert_int_equal(p.best, LUMIS_LUM_RESTRICTED);
    }
    lumis_luminaire_predict_desc e = d;
    e.bands = 3;
    e.band_edges[0] = 5.0;
    e.band_edges[1] = 4.0;
    assert_int_equal(lumis_luminaire_predict(f.lum, &e, &p), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(msg, "band edges must increase"));
    lumis_luminaire_costs costs = lumis_luminaire_costs_default();
    costs.global = 0.0;
    e = d;
    e.costs = &costs;
    assert_int_equal(lumis_luminaire_predict(f.lum, &e, &p), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(msg, "costs"));
    /* bands: their shares add to 1 and their means, weighted, are the whole's */
    lumis_luminaire_prediction whole, banded;
    assert_int_equal(lumis_luminaire_predict(f.lum, &d, &whole), LUMIS_OK);
    e = d;
    e.bands = 3;
    e.band_edges[0] = 3.0;
    e.band_edges[1] = 8.0;
    assert_int_equal(lumis_luminaire_predict(f.lum, &e, &banded), LUMIS_OK);
    assert_int_equal(banded.bands, 3);
    double share = 0.0, var[3] = {0}, ns[3] = {0};
    int lit = 0;
    for (int b = 0; b < 3; b++) {
        assert_true(banded.band[b].probes_lit > 0);
        lit += banded.band[b].probes_lit;
        share += banded.band[b].share;
        for (int st = 0; st < 3; st++) {
            var[st] += banded.band[b].share * banded.band[b].variance[st];
            ns[st] += banded.band[b].share * banded.band[b].ns[st];
        }
    }
    assert_int_equal(lit, whole.probes_lit);
    assert_true(fabs(share - 1.0) < 1e-12);
    assert_true(fabs(var[0] / whole.restricted.variance - 1.0) < 1e-9);
    assert_true(fabs(var[2] / whole.global.variance - 1.0) < 1e-9);
    assert_true(fabs(ns[1] / whole.uniform.ns - 1.0) < 1e-9);
    assert_true(whole.distance[0] <= whole.distance[1] && whole.distance[1] <= whole.distance[2]);
    /* from the origin; a probe is 1.5 to 20 from its point of U, within 1.1 of the origin */
    assert_true(whole.distance[0] > 0.4 && whole.distance[2] < 21.1);
    /* global's own ratio is 1; restricted and uniform made dearer by more than global's
     * variance exceeds theirs (~10^7 on these noise images) lose */
    assert_true(fabs(whole.global.time_ratio - 1.0) < 1e-12);
    assert_int_equal(whole.best, LUMIS_LUM_RESTRICTED);
    costs = lumis_luminaire_costs_default();
    costs.camera *= 1e9;
    costs.uniform *= 1e9;
    costs.restricted *= 1e9;
    e = d;
    e.costs = &costs;
    assert_int_equal(lumis_luminaire_predict(f.lum, &e, &p), LUMIS_OK);
    assert_int_equal(p.best, LUMIS_LUM_GLOBAL);
    /* Beyond the pilot's 16-point nets, more strata never predict a larger variance: with
     * the same pilot, 4096 strata against 256, probe by probe.  Two nets a probe (pilot 32)
     * make the nets' variance noisy, at times above the independent one: that is where an
     * extrapolation that let it exceed 1 would grow with the strata. */
    for (int k = 0; k < 16; k++) {
        lumis_luminaire_predict_desc q = d;
        q.probes = &probes[k];
        q.probe_count = 1;
        q.pilot = 32;
        q.seed = (uint64_t)k;
        lumis_luminaire_prediction p256, p4096;
        q.strata = 256;
        assert_int_equal(lumis_luminaire_predict(f.lum, &q, &p256), LUMIS_OK);
        q.strata = 4096;
        assert_int_equal(lumis_luminaire_predict(f.lum, &q, &p4096), LUMIS_OK);
        if (!(p4096.restricted.variance <= p256.restricted.variance) ||
            !(p4096.uniform.variance <= p256.uniform.variance))
            fail_msg("probe %d: 4096 strata predict %g / %g, 256 strata %g / %g", k,
                     p4096.restricted.variance, p4096.uniform.variance, p256.restricted.variance,
                     p256.uniform.variance);
    }
    /* behind U: nothing lit, every number 0 */
    for (int k = 0; k < N; k++) probes[k].p.z = -probes[k].p.z;
    assert_int_equal(lumis_luminaire_predict(f.lum, &d, &p), LUMIS_OK);
    assert_int_equal(p.probes_lit, 0);
    assert_true(p.restricted.variance == 0.0 && p.global.ns == 0.0);
    assert_int_equal(p.best, LUMIS_LUM_RESTRICTED);
    d.select = 10;
    assert_int_equal(lumis_luminaire_predict(f.lum, &d, &p), LUMIS_OK);
    assert_int_equal(p.probes_lit, 0);
    free_fixture(&f);
}

/* Quadrature over S (the library's) against a dense midpoint rule over U of
 * L(u -> p) cos_u cos_p / r^2 with L from lumis_luminaire_radiance. */
static void quadrature_over_s_matches_quadrature_over_u(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 8);
    const lumis_vec3 ps[] = {{0.1f, -0.05f, 1.3f}, {0.3f, 0.2f, 3.0f}, {-0.2f, 0.1f, 0.6f}};
    for (int c = 0; c < 3; c++) {
        const lumis_vec3 p = ps[c], n = {0.0f, 0.0f, -1.0f};
        lumis_rgb ref;
        assert_int_equal(lumis_luminaire_irradiance(f.lum, p, n, 6, &ref), LUMIS_OK);
        const int N = 1500;
        const double lo = -1.0, hi = 1.0, du = (hi - lo) / N; /* the supports: [-1, 1]^2 */
        double acc = 0.0;
        for (int a = 0; a < N; a++)
            for (int b = 0; b < N; b++) {
                const double ux = lo + (a + 0.5) * du, uy = lo + (b + 0.5) * du;
                const double t = 1.0 / p.z; /* s = u + (p - u) delta / z */
                const double sx = ux + (p.x - ux) * t, sy = uy + (p.y - uy) * t;
                lumis_rgb L = lumis_luminaire_radiance(f.lum, ux, uy, sx, sy);
                const double vx = p.x - ux, vy = p.y - uy, vz = p.z;
                const double r2 = vx * vx + vy * vy + vz * vz;
                const double cosu = vz / sqrt(r2), cosp = vz / sqrt(r2);
                acc += lum3(L) * cosu * cosp / r2 * du * du;
            }
        printf("over S %.6g  over U %.6g\n", lum3(ref), acc);
        assert_true(fabs(acc - lum3(ref)) < 3e-3 * lum3(ref));
    }
    free_fixture(&f);
}

/* ---- the per-point entry ---------------------------------------------------------------- */

static void sample_point_edge_cases(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 4);
    lumis_luminaire_sample s[64];
    double u[128];
    for (int k = 0; k < 128; k++) u[k] = (k * 0.618033988749895) - floor(k * 0.618033988749895);
    lumis_luminaire_query q = {0};
    int n = -1;
    q.p.z = -1.0f; /* behind U */
    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, 64, s, &n), LUMIS_OK);
    assert_int_equal(n, 0);
    q.p.z = 0.0f; /* on U */
    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, 64, s, &n), LUMIS_OK);
    assert_int_equal(n, 0);
    q.p.x = 0.1f;
    q.p.z = 2.0f;
    q.budget = 40;
    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, 8, s, &n),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, 64, s, &n), LUMIS_OK);
    assert_int_equal(n, 40);
    /* Samples come grouped by image, K_m each, matching the balance of A_m(p). */
    double mass[9];
    int counts[9];
    lumis_luminaire_masses(f.lum, q.p, mass);
    assert_int_equal(lumis_luminaire_balance(mass, 9, 40, 0, counts), 40);
    for (int k = 0; k < n; k++) {
        assert_int_equal(s[k].count, counts[s[k].image]);
        assert_true(k == 0 || s[k].image >= s[k - 1].image);
        assert_true(s[k].measure == LUMIS_LUM_AREA_S);
    }
    /* Budget smaller than the images with mass: each still gets one. */
    q.budget = 1;
    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, 64, s, &n), LUMIS_OK);
    int npos = 0;
    for (int m = 0; m < 9; m++) npos += mass[m] > 0.0;
    assert_int_equal(n, npos);
    /* On S: samples on U. */
    q.p.z = 1.0f;
    q.budget = 10;
    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, 64, s, &n), LUMIS_OK);
    assert_true(n >= 1);
    for (int k = 0; k < n; k++) assert_true(s[k].measure == LUMIS_LUM_AREA_U);
    free_fixture(&f);
}

/* Random numbers on demand (query.fill): the very samples the array gives, the numbers
 * asked for in order, at most 128 and an even count at a time, 2 per sample in all; for
 * every strategy, in front of S, between U and S, on S, and for images with more samples
 * than one batch holds. */
typedef struct fill_source {
    const double *u;
    int used, calls, bad;
} fill_source;

static void fill_from(void *state, double *buf, int n)
{
    fill_source *f = state;
    if (n <= 0 || n > 128 || n % 2) f->bad++;
    for (int k = 0; k < n; k++) buf[k] = f->u[f->used + k];
    f->used += n;
    f->calls++;
}

static void numbers_on_demand_match_the_array(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 6);
    enum { CAP = 400 };
    double *u = malloc(2 * CAP * sizeof *u);
    lumis_luminaire_sample *a = malloc(CAP * sizeof *a), *b = malloc(CAP * sizeof *b);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 6, 6);
    for (int k = 0; k < 2 * CAP; k++) u[k] = lumis_pcg32_double(&rng);
    const float zs[3] = {2.5f, 0.6f, 1.0f}; /* in front of S, between U and S, on S */
    const int budgets[3] = {1, 40, 390};
    int checked = 0, big = 0; /* samples of images with more than a batch */
    for (int st = 0; st < 3; st++)
        for (int z = 0; z < 3; z++)
            for (int bi = 0; bi < 3; bi++) {
                lumis_luminaire_query q = {0};
                q.strategy = (lumis_luminaire_strategy)st;
                q.p = (lumis_vec3){0.2f, -0.1f, zs[z]};
                q.budget = budgets[bi];
                int na = -1, nb = -1;
                assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, CAP, a, &na), LUMIS_OK);
                fill_source src = {u, 0, 0, 0};
                q.fill = fill_from;
                q.fill_ctx = &src;
                assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, NULL, CAP, b, &nb),
                                 LUMIS_OK);
                assert_int_equal(na, nb);
                assert_true(na > 0);
                assert_memory_equal(a, b, (size_t)na * sizeof a[0]);
                assert_int_equal(src.used, 2 * na);
                assert_int_equal(src.bad, 0);
                if (budgets[bi] == 390) assert_true(src.calls > 390 / 64);
                for (int k = 0; k < na; k++) big += a[k].count > 64;
                checked++;
            }
    assert_int_equal(checked, 27);
    assert_true(big > 0);
    /* Without u and without fill there is nothing to draw from. */
    lumis_luminaire_query q = {0};
    q.p = (lumis_vec3){0.2f, -0.1f, 2.5f};
    int n = -1;
    assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, NULL, CAP, a, &n),
                     LUMIS_ERR_INVALID_ARGUMENT);
    free(u), free(a), free(b);
    free_fixture(&f);
}

/* The global strategy drawn once and finished per point gives what the per-point entry
 * gives, bit for bit, in front of S, between U and S, and nothing behind U. */
static void global_draws_finish_like_sample_point(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 5);
    enum { K = 40 };
    const int cap = lumis_luminaire_capacity(f.lum, K);
    double u[2 * 64];
    lumis_luminaire_sample drawn[64], a[64], b[64];
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 8, 2);
    for (int r = 0; r < 2 * cap; r++) u[r] = lumis_pcg32_double(&rng);
    lumis_luminaire_query q = {0};
    q.budget = K;
    q.strategy = LUMIS_LUM_GLOBAL;
    int nd = 0;
    assert_int_equal(lumis_luminaire_global_draw(f.lum, &q, u, cap, drawn, &nd), LUMIS_OK);
    assert_int_equal(nd, K);
    const float zs[4] = {3.0f, 1.7f, 0.4f, -0.5f};
    for (int z = 0; z < 4; z++) {
        q.p = (lumis_vec3){0.3f, -0.2f, zs[z]};
        int na = 0, nb = 0;
        assert_int_equal(lumis_luminaire_sample_point(f.lum, &q, u, cap, a, &na), LUMIS_OK);
        assert_int_equal(lumis_luminaire_global_finish(f.lum, q.p, drawn, nd, b, &nb), LUMIS_OK);
        assert_int_equal(na, nb);
        assert_int_equal(na, zs[z] < 0.0f ? 0 : K);
        if (na) assert_memory_equal(a, b, (size_t)na * sizeof a[0]);
    }
    q.strategy = LUMIS_LUM_RESTRICTED; /* only the global strategy can be drawn once */
    assert_int_equal(lumis_luminaire_global_draw(f.lum, &q, u, cap, drawn, &nd),
                     LUMIS_ERR_INVALID_ARGUMENT);
    free_fixture(&f);
}

/* The per-point entry draws what the per-image one does: the same (u1, u2) give image m
 * the same point, pdf, direction and radiance, the weight divided by K_m; its masses are
 * the boxes' integrals, exactly 0 where the box misses every nonzero pixel (images that are
 * zero outside a rectangle, one all zero, so that the entry's shortcut is exercised). */
static void sample_point_draws_what_sample_image_draws(void **state)
{
    (void)state;
    for (int b = LUMIS_BASIS_QUADRATIC; b <= LUMIS_BASIS_BSPLINE; b++) {
        fixture f = make_fixture((lumis_luminaire_basis)b, 21 + b);
        lumis_luminaire_desc d;
        lumis_luminaire_get_desc(f.lum, &d);
        const int w = d.width, h = d.height;
        for (int m = 0; m < 9; m++) {
            float *px = f.pixels + (size_t)m * w * h * 3;
            /* Nonzero only in [2m/3, 2m/3 + 7] x [m/2, m/2 + 5]; image 4 all zero. */
            const int i0 = 2 * m / 3 - 1, j0 = m / 2 - 1;
            for (int j = 0; j < h; j++)
                for (int i = 0; i < w; i++)
                    if (m == 4 || i < i0 || i > i0 + 7 || j < j0 || j > j0 + 5)
                        px[3 * (j * w + i)] = px[3 * (j * w + i) + 1] = px[3 * (j * w + i) + 2] =
                            0.0f;
        }
        /* The sparse luminaire is built from the zeroed pixels (get_desc's pointers are
         * f.lum's own copies, which must stay as they were). */
        d.pixels = f.ptr;
        lumis_luminaire *sparse = NULL;
        assert_int_equal(lumis_luminaire_create(&d, &sparse), LUMIS_OK);
        const float *img4 = lumis_luminaire_image(sparse, 4);
        for (int k = 0; k < 3 * w * h; k++) assert_true(img4[k] == 0.0f);
        const lumis_luminaire *ls[2] = {f.lum, sparse};
        lumis_pcg32 rng;
        lumis_pcg32_seed(&rng, 31, (uint64_t)b);
        int compared = 0, pruned = 0;
        for (int li = 0; li < 2; li++)
            for (int k = 0; k < 400; k++) {
                const lumis_luminaire *l = ls[li];
                lumis_luminaire_query q = {0};
                q.p.x = (float)(3.0 * lumis_pcg32_double(&rng) - 1.5);
                q.p.y = (float)(2.0 * lumis_pcg32_double(&rng) - 1.0);
                q.p.z = (float)(k % 7 == 0 ? 0.3 + 0.6 * lumis_pcg32_double(&rng)
                                           : 1.1 + 6.0 * lumis_pcg32_double(&rng));
                q.budget = k % 13 == 0 ? 300 : 1 + (int)lumis_pcg32_bounded(&rng, 60);
                q.k_max = k % 3 == 0 ? 5 : 0;
                q.search = k % 2 ? LUMIS_LUM_BINARY : LUMIS_LUM_SECANT;
                q.strategy = k % 5 == 0    ? LUMIS_LUM_UNIFORM
                             : k % 11 == 0 ? LUMIS_LUM_GLOBAL
                                           : LUMIS_LUM_RESTRICTED;
                double mass[9];
                lumis_luminaire_masses(l, q.p, mass);
                for (int m = 0; m < 9; m++) {
                    lumis__box bx;
                    double units = 0.0;
                    if (lumis__lum_box(l, m, q.p.x, q.p.y, q.p.z, &bx))
                        units = lumis__lum_box_units(l, m, &bx);
                    assert_true(mass[m] == units * l->unit[m]);
                    pruned += li == 1 && units == 0.0 && l->unit[m] > 0.0;
                }
                double u[2 * 320];
                for (int c = 0; c < 2 * 320; c++) u[c] = lumis_pcg32_double(&rng);
                lumis_luminaire_sample s[320];
                int n = 0;
                assert_int_equal(lumis_luminaire_sample_point(l, &q, u, 320, s, &n), LUMIS_OK);
                for (int c = 0; c < n; c++) {
                    lumis_luminaire_sample a;
                    assert_int_equal(
                        lumis_luminaire_sample_image(l, &q, s[c].image, u[2 * c], u[2 * c + 1], &a),
                        LUMIS_OK);
                    assert_true(a.s[0] == s[c].s[0] && a.s[1] == s[c].s[1]);
                    assert_true(a.u[0] == s[c].u[0] && a.u[1] == s[c].u[1]);
                    assert_true(a.pdf == s[c].pdf && a.distance == s[c].distance);
                    assert_true(a.dir.x == s[c].dir.x && a.dir.y == s[c].dir.y &&
                                a.dir.z == s[c].dir.z);
                    assert_true(a.radiance.r == s[c].radiance.r &&
                                a.radiance.g == s[c].radiance.g && a.radiance.b == s[c].radiance.b);
                    assert_true(fabs(a.weight - s[c].weight * s[c].count) <= 1e-6 * a.weight);
                    compared++;
                }
            }
        printf("sample_point == sample_image: %d samples, %d boxes pruned\n", compared, pruned);
        assert_true(compared > 10000 && pruned > 50);
        lumis_luminaire_destroy(sparse);
        free_fixture(&f);
    }
}

static void rigid_transform_round_trip(void **state)
{
    (void)state;
    lumis_rigid x = lumis_rigid_identity();
    assert_int_equal(lumis_rigid_check(&x), LUMIS_OK);
    const double c = cos(0.7), s = sin(0.7);
    const lumis_rigid r = {{c, 0, s, 0, 1, 0, -s, 0, c}, {1.0, -2.0, 3.0}};
    assert_int_equal(lumis_rigid_check(&r), LUMIS_OK);
    lumis_vec3 p = {0.3f, -1.2f, 2.5f};
    lumis_vec3 q = lumis_rigid_point_to_local(&r, lumis_rigid_point_to_world(&r, p));
    assert_true(fabsf(q.x - p.x) < 1e-5f && fabsf(q.y - p.y) < 1e-5f && fabsf(q.z - p.z) < 1e-5f);
    lumis_vec3 d = lumis_rigid_dir_to_world(&r, p);
    assert_true(fabsf(d.x - (float)(c * 0.3 + s * 2.5)) < 1e-5f);
    q = lumis_rigid_dir_to_local(&r, d);
    assert_true(fabsf(q.z - p.z) < 1e-5f);
    /* by hand: world = R local + t; R turns +x to (c, 0, -s) and +z to (s, 0, c) */
    lumis_vec3 w = lumis_rigid_point_to_world(&r, (lumis_vec3){1, 0, 0});
    assert_true(fabsf(w.x - (float)(c + 1.0)) < 1e-6f && fabsf(w.y + 2.0f) < 1e-6f &&
                fabsf(w.z - (float)(3.0 - s)) < 1e-6f);
    w = lumis_rigid_point_to_world(&r, (lumis_vec3){0, 5, 1});
    assert_true(fabsf(w.x - (float)(s + 1.0)) < 1e-6f && fabsf(w.y - 3.0f) < 1e-6f &&
                fabsf(w.z - (float)(c + 3.0)) < 1e-6f);
    /* local = R^T (world - t): the translation's own point is the origin, t + (s, 0, c) is +z */
    lumis_vec3 l = lumis_rigid_point_to_local(&r, (lumis_vec3){1, -2, 3});
    assert_true(fabsf(l.x) < 1e-6f && fabsf(l.y) < 1e-6f && fabsf(l.z) < 1e-6f);
    l = lumis_rigid_point_to_local(&r, (lumis_vec3){(float)(1 + s), -2, (float)(3 + c)});
    assert_true(fabsf(l.x) < 1e-6f && fabsf(l.y) < 1e-6f && fabsf(l.z - 1.0f) < 1e-6f);
    /* directions ignore t: (c, 0, -s) in the world is +x locally */
    l = lumis_rigid_dir_to_local(&r, (lumis_vec3){(float)c, 0, (float)-s});
    assert_true(fabsf(l.x - 1.0f) < 1e-6f && fabsf(l.y) < 1e-6f && fabsf(l.z) < 1e-6f);
    lumis_rigid bad = r;
    bad.r[0] = 2.0;
    assert_int_equal(lumis_rigid_check(&bad), LUMIS_ERR_INVALID_ARGUMENT);
    bad = r;
    bad.r[4] = -1.0; /* a reflection */
    assert_int_equal(lumis_rigid_check(&bad), LUMIS_ERR_INVALID_ARGUMENT);
}

/* ---- synthetic acquisition --------------------------------------------------------------- */

static void generated_luminaire_reproduces_its_emitter(void **state)
{
    (void)state;
    lumis_luminaire_desc layout;
    lumis_emitter_desc em;
    lumis_emitter_disk disks[4];
    assert_int_equal(lumis_luminaire_preset_get(LUMIS_PRESET_SMALL, &layout, &em, disks), LUMIS_OK);
    const lumis_vec3 n = {0.0f, 0.0f, -1.0f};
    const lumis_vec3 ps[] = {{0.0f, 0.0f, 400.0f},
                             {20.0f, -10.0f, 300.0f},
                             {5.0f, 5.0f, 150.0f},
                             {-30.0f, 10.0f, 600.0f}};
    /* The error is the basis' (filters of h / delta radians against lobes of cos^40..80)
     * and the pixels' (boxes a few pixels wide): both shrink together, the coarse grid with
     * coarse images, the fine grid with images fine enough for its smaller boxes. */
    const int grids[][4] = {{5, 4, 48, 40}, {17, 13, 160, 128}};
    double worst[2] = {0.0, 0.0};
    for (int g = 0; g < 2; g++) {
        lumis_luminaire_desc d = layout;
        d.grid[0] = grids[g][0];
        d.grid[1] = grids[g][1];
        d.grid_spacing[0] = d.grid_spacing[1] = 40.0 / (d.grid[0] - 1);
        d.grid_origin[0] = -0.5 * (d.grid[0] - 1) * d.grid_spacing[0];
        d.grid_origin[1] = -0.5 * (d.grid[1] - 1) * d.grid_spacing[1];
        d.width = grids[g][2];
        d.height = grids[g][3];
        lumis_luminaire *lum = NULL;
        lumis_acquire_desc acq = {0};
        acq.samples_s = 1;
        assert_int_equal(lumis_luminaire_acquire(&d, &em, &acq, &lum), LUMIS_OK);
        for (size_t k = 0; k < sizeof ps / sizeof ps[0]; k++) {
            lumis_rgb a, b;
            assert_int_equal(lumis_luminaire_irradiance(lum, ps[k], n, 4, &a), LUMIS_OK);
            assert_int_equal(lumis_emitter_irradiance(&em, ps[k], n, 0, 0, &b), LUMIS_OK);
            const double rel = fabs(lum3(a) - lum3(b)) / lum3(b);
            printf("grid %2dx%-2d images %3dx%-3d  p (%g, %g, %g): luminaire %.6g  emitter %.6g  "
                   "rel %.3g\n",
                   d.grid[0], d.grid[1], d.width, d.height, ps[k].x, ps[k].y, ps[k].z, lum3(a),
                   lum3(b), rel);
            if (rel > worst[g]) worst[g] = rel;
        }
        lumis_luminaire_destroy(lum);
    }
    assert_true(worst[0] < 0.10);
    assert_true(worst[1] < 0.03);
    assert_true(worst[1] < worst[0]);
}

/* The luminaire's power is the sum over images of the luminance integral of C_m over S
 * (each pixel's luminance times its area on S), whatever the grid; the capacity holds a
 * sample for every image when the budget is smaller; and a grid of exactly the maximum
 * of 1024 images is accepted, one more refused.  Nothing read total_power before: an image
 * power summed per pixel, or only the last image's, passed. */
static void luminaire_power_and_limits(void **state)
{
    (void)state;
    enum { GW = 3, GH = 2, W = 5, H = 4 };
    static float img[GW * GH][W * H * 3];
    const float *ptrs[GW * GH];
    double want = 0.0;
    const double dx = 0.7 / W, dy = 0.45 / H;
    for (int m = 0; m < GW * GH; m++) {
        for (int p = 0; p < W * H; p++)
            for (int c = 0; c < 3; c++) {
                const float v = m == 2 ? 0.0f : (float)(0.1 + 0.05 * ((p * 7 + m * 3 + c) % 11));
                img[m][3 * p + c] = v;
            }
        for (int p = 0; p < W * H; p++)
            want +=
                (0.2126 * img[m][3 * p] + 0.7152 * img[m][3 * p + 1] + 0.0722 * img[m][3 * p + 2]) *
                dx * dy;
        ptrs[m] = img[m];
    }
    lumis_luminaire_desc d = {0};
    d.delta = 1.5;
    d.grid[0] = GW;
    d.grid[1] = GH;
    d.grid_spacing[0] = 0.3;
    d.grid_spacing[1] = 0.2;
    d.width = W;
    d.height = H;
    d.image_origin[0] = -0.35;
    d.image_origin[1] = -0.2;
    d.image_size[0] = 0.7;
    d.image_size[1] = 0.45;
    d.pixels = ptrs;
    lumis_luminaire *l = NULL;
    assert_int_equal(lumis_luminaire_create(&d, &l), LUMIS_OK);
    lumis_luminaire_info in;
    lumis_luminaire_get_info(l, &in);
    if (!(fabs(in.total_power - want) <= 1e-12 * want))
        fail_msg("total power %.12g, sum of the images' luminance integrals %.12g", in.total_power,
                 want);
    /* Every sample's radiance and weight from their definitions, with delta != 1 and
     * h_x != h_y (the fixtures have delta = 1 and a square grid): Psi_m(u -> s) =
     * Phi_m(u) (|s - u|^2 + delta^2)^2 / (delta^2 h_x h_y) C_m(s), and the weight
     * 1 / (K_m pdf_omega) = |delta - p_z| / (K_m pdf |s - p|^3). */
    const lumis_vec3 pts[2] = {{0.05f, -0.02f, 4.0f}, {-0.1f, 0.05f, 0.6f}};
    for (int k = 0; k < 2; k++) {
        lumis_luminaire_query q = {0};
        q.p = pts[k];
        q.budget = 24;
        lumis_luminaire_sample smp[64];
        double u[128];
        for (int t = 0; t < 128; t++) u[t] = fmod(0.5 + t * 0.6180339887498949, 1.0);
        int n = 0;
        assert_int_equal(lumis_luminaire_sample_point(l, &q, u, 64, smp, &n), LUMIS_OK);
        assert_true(n >= 6);
        for (int t = 0; t < n; t++) {
            const lumis_luminaire_sample *o = &smp[t];
            const int m = o->image, i = (int)((o->s[0] + 0.35) / dx),
                      j = (int)((o->s[1] + 0.2) / dy);
            assert_true(i >= 0 && i < W && j >= 0 && j < H);
            const double ex = o->s[0] - o->u[0], ey = o->s[1] - o->u[1];
            const double e2 = ex * ex + ey * ey + 1.5 * 1.5;
            const double psi = lumis__lum_phi(l, m, o->u[0], o->u[1]) * e2 * e2 /
                               (1.5 * 1.5 * 0.3 * 0.2) * img[m][3 * (j * W + i) + 1];
            const double wx = o->s[0] - pts[k].x, wy = o->s[1] - pts[k].y, wz = 1.5 - pts[k].z;
            const double r = sqrt(wx * wx + wy * wy + wz * wz);
            const double wt = fabs(wz) / (o->count * (double)o->pdf * r * r * r);
            if (!(fabs(o->radiance.g - psi) <= 1e-5 * psi + 1e-30 &&
                  fabs(o->weight - wt) <= 1e-5 * wt))
                fail_msg("p %d, sample %d: radiance %g (want %g), weight %g (want %g)", k, t,
                         o->radiance.g, psi, o->weight, wt);
        }
    }
    assert_true(lumis_luminaire_capacity(l, 2) >= GW * GH);
    assert_true(lumis_luminaire_capacity(l, 40) >= 40);
    lumis_luminaire_destroy(l);
    /* 1024 images of one pixel: the limit, accepted; 1025 refused. */
    static float one[3] = {1.0f, 1.0f, 1.0f};
    static const float *many[1025];
    for (int m = 0; m < 1025; m++) many[m] = one;
    d.grid[0] = 32;
    d.grid[1] = 32;
    d.width = d.height = 1;
    d.pixels = many;
    assert_int_equal(lumis_luminaire_create(&d, &l), LUMIS_OK);
    lumis_luminaire_get_info(l, &in);
    assert_int_equal(in.images, 1024);
    lumis_luminaire_destroy(l);
    d.grid[0] = 41;
    d.grid[1] = 25;
    l = (lumis_luminaire *)&l;
    assert_int_equal(lumis_luminaire_create(&d, &l), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(l);
}

/* The synthetic emitter against closed forms.  A disk of constant radiance L and radius R
 * seen on its axis from distance D, facing it: E = pi L R^2 / (R^2 + D^2); with a lobe
 * cos^n about the axis, E = 2 pi L (1 - cos^(n+2) theta_m) / (n + 2), cos theta_m =
 * D / sqrt(D^2 + R^2).  Through a striped plate, a ray crossing a dark stripe carries
 * L (1 - contrast) tint, one crossing a clear stripe L.  (The emitter's irradiance was
 * only compared with a luminaire acquired from the same emitter, so a wrong footprint or
 * plate changed both sides alike.) */
static void emitter_matches_closed_forms(void **state)
{
    (void)state;
    const double L = 3.0, R = 2.0, cz = -4.0;
    for (int lobe = 0; lobe < 2; lobe++) {
        const double n = lobe ? 6.0 : 0.0;
        const lumis_emitter_disk disk = {{0.0, 0.0, cz}, R, {(float)L, (float)L, (float)L}, n};
        lumis_emitter_desc e = {0};
        e.disks = &disk;
        e.disk_count = 1;
        const float pzs[2] = {1.0f, 6.0f};
        for (int k = 0; k < 2; k++) {
            const double D = pzs[k] - cz, cm = D / sqrt(D * D + R * R);
            const double want =
                lobe ? 2 * 3.14159265358979323846 * L * (1 - pow(cm, n + 2)) / (n + 2)
                     : 3.14159265358979323846 * L * R * R / (R * R + D * D);
            lumis_rgb E;
            const lumis_vec3 p = {0.0f, 0.0f, pzs[k]}, nrm = {0.0f, 0.0f, -1.0f};
            assert_int_equal(lumis_emitter_irradiance(&e, p, nrm, 0, 0, &E), LUMIS_OK);
            if (!(fabs(E.g - want) <= 1e-4 * want))
                fail_msg("lobe cos^%g at z = %g: irradiance %.8g, closed form %.8g", n, pzs[k], E.g,
                         want);
        }
    }
    const lumis_emitter_disk big = {{0.0, 0.0, -2.0}, 10.0, {2.0f, 4.0f, 6.0f}, 0.0};
    lumis_emitter_desc e = {0};
    e.disks = &big;
    e.disk_count = 1;
    e.pattern = LUMIS_PATTERN_STRIPES;
    e.plate_z = -1.0;
    e.period[0] = e.period[1] = 1.0;
    e.contrast = 0.75;
    e.tint = (lumis_rgb){0.5f, 1.0f, 0.25f};
    /* from u = (0, 0) towards s = (sx, 0) on S at delta = 1: the plate at x = -sx */
    const lumis_rgb dark = lumis_emitter_radiance(&e, 1.0, 0.0, 0.0, -1.5, 0.0),
                    clear = lumis_emitter_radiance(&e, 1.0, 0.0, 0.0, -0.5, 0.0);
    assert_float_equal(dark.r, 2.0f * 0.25f * 0.5f, 1e-6);
    assert_float_equal(dark.g, 4.0f * 0.25f * 1.0f, 1e-6);
    assert_float_equal(dark.b, 6.0f * 0.25f * 0.25f, 1e-6);
    assert_float_equal(clear.r, 2.0f, 1e-6);
    assert_float_equal(clear.b, 6.0f, 1e-6);
}

/* ---- descriptors -------------------------------------------------------------------------- */

static void malformed_descriptors_get_a_clear_error(void **state)
{
    (void)state;
    float px[4 * 3 * 3] = {0};
    px[4] = 1.0f;
    const float *ptr[4] = {px, px, px, px};
    lumis_luminaire_desc good = {0};
    good.delta = 1.0;
    good.grid[0] = good.grid[1] = 2;
    good.grid_spacing[0] = good.grid_spacing[1] = 1.0;
    good.width = 4;
    good.height = 3;
    good.image_size[0] = good.image_size[1] = 2.0;
    good.pixels = ptr;
    lumis_luminaire *l = NULL;
    assert_int_equal(lumis_luminaire_create(&good, &l), LUMIS_OK);
    lumis_luminaire_destroy(l);
    struct bad {
        const char *needle;
        lumis_status status;
    };
    const struct bad expect[] = {
        {"delta", LUMIS_ERR_INVALID_ARGUMENT},          {"grid", LUMIS_ERR_INVALID_ARGUMENT},
        {"grid", LUMIS_ERR_INVALID_ARGUMENT},           {"spacing", LUMIS_ERR_INVALID_ARGUMENT},
        {"pixels", LUMIS_ERR_BAD_DIMENSIONS},           {"image size", LUMIS_ERR_INVALID_ARGUMENT},
        {"pixels is NULL", LUMIS_ERR_INVALID_ARGUMENT}, {"pixels[2]", LUMIS_ERR_INVALID_ARGUMENT},
        {"basis", LUMIS_ERR_INVALID_ARGUMENT},
    };
    const float *holes[4] = {px, px, NULL, px};
    for (int c = 0; c < 9; c++) {
        lumis_luminaire_desc d = good;
        tu_sink sink;
        tu_sink_init(&sink);
        d.errors = sink.sink;
        switch (c) {
        case 0:
            d.delta = 0.0;
            break;
        case 1:
            d.grid[0] = 0;
            break;
        case 2:
            d.grid[0] = 40, d.grid[1] = 40;
            break;
        case 3:
            d.grid_spacing[1] = -1.0;
            break;
        case 4:
            d.width = 0;
            break;
        case 5:
            d.image_size[0] = NAN;
            break;
        case 6:
            d.pixels = NULL;
            break;
        case 7:
            d.pixels = holes;
            break;
        case 8:
            d.basis = (lumis_luminaire_basis)7;
            break;
        }
        l = (lumis_luminaire *)&d; /* must be reset to NULL */
        assert_int_equal(lumis_luminaire_create(&d, &l), expect[c].status);
        assert_null(l);
        assert_int_equal(sink.count, 1);
        assert_non_null(strstr(sink.last, expect[c].needle));
    }
    /* lumis_luminaire_check says what create says of everything but the pixels, with the
     * same message; the published limits are where it draws the line. */
    assert_int_equal(lumis_luminaire_check(NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_check(&good), LUMIS_OK);
    for (int c = 0; c < 10; c++) {
        lumis_luminaire_desc d = good;
        tu_sink sink;
        tu_sink_init(&sink);
        d.errors = sink.sink;
        d.pixels = NULL; /* not looked at */
        lumis_status want = LUMIS_ERR_INVALID_ARGUMENT;
        const char *needle = "grid";
        switch (c) {
        case 0:
            d.delta = 0.0, needle = "delta";
            break;
        case 1:
            d.grid[0] = 0;
            break;
        case 2:
            d.grid[0] = 40, d.grid[1] = 40;
            break;
        case 3:
            d.width = 0, want = LUMIS_ERR_BAD_DIMENSIONS, needle = "pixels";
            break;
        case 4:
            d.basis = (lumis_luminaire_basis)7, needle = "basis";
            break;
        /* one axis past LUMIS_LUMINAIRE_MAX_GRID, the images within MAX_IMAGES: the
         * per-point tables hold MAX_GRID columns (a 1000 x 1 grid overran them) */
        case 5:
            d.grid[0] = LUMIS_LUMINAIRE_MAX_GRID + 1, d.grid[1] = 1;
            break;
        case 6:
            d.grid[0] = 1, d.grid[1] = 4 * LUMIS_LUMINAIRE_MAX_GRID - 24;
            break;
        case 7:
            d.height = LUMIS_LUMINAIRE_MAX_SIDE + 1, want = LUMIS_ERR_BAD_DIMENSIONS;
            needle = "16384";
            break;
        /* at the limits: accepted */
        case 8:
            d.grid[0] = LUMIS_LUMINAIRE_MAX_GRID, d.grid[1] = 4, want = LUMIS_OK;
            break;
        case 9:
            d.width = d.height = LUMIS_LUMINAIRE_MAX_SIDE, want = LUMIS_OK;
            break;
        }
        assert_int_equal(lumis_luminaire_check(&d), want);
        assert_int_equal(sink.count, want == LUMIS_OK ? 0 : 1);
        if (want != LUMIS_OK) assert_non_null(strstr(sink.last, needle));
    }
    /* Bad pixels are replaced, counted and reported once as a warning. */
    float bad[4 * 3 * 3] = {0};
    bad[0] = NAN, bad[1] = -1.0f, bad[5] = INFINITY, bad[7] = 2.0f;
    const float *bp[4] = {bad, px, px, px};
    lumis_luminaire_desc d = good;
    tu_sink sink;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    d.pixels = bp;
    assert_int_equal(lumis_luminaire_create(&d, &l), LUMIS_OK);
    lumis_luminaire_info info;
    lumis_luminaire_get_info(l, &info);
    assert_int_equal(info.replaced, 3);
    assert_int_equal(sink.count, 1);
    assert_int_equal(sink.status, LUMIS_OK);
    lumis_luminaire_destroy(l);
    /* A reader that replaced values before (lumis_luminaire_read) has them counted too,
     * without a second warning. */
    d.replaced_before = 1440;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    assert_int_equal(lumis_luminaire_create(&d, &l), LUMIS_OK);
    lumis_luminaire_get_info(l, &info);
    assert_int_equal(info.replaced, 1443);
    assert_int_equal(sink.count, 1);
    lumis_luminaire_destroy(l);
    const float *clean[4] = {px, px, px, px};
    d.pixels = clean;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    assert_int_equal(lumis_luminaire_create(&d, &l), LUMIS_OK);
    lumis_luminaire_get_info(l, &info);
    assert_int_equal(info.replaced, 1440);
    assert_int_equal(sink.count, 0);
    lumis_luminaire_destroy(l);
    d.replaced_before = 0;
    /* Emitters too. */
    lumis_luminaire_desc layout;
    lumis_emitter_desc em;
    lumis_emitter_disk disks[4];
    assert_int_equal(lumis_luminaire_preset_get(LUMIS_PRESET_SMALL, &layout, &em, disks), LUMIS_OK);
    disks[1].center[2] = 1.0;
    tu_sink_init(&sink);
    lumis_acquire_desc acq = {0};
    acq.errors = sink.sink;
    assert_int_equal(lumis_luminaire_acquire(&layout, &em, &acq, &l), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "disk 1"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bases_are_partitions_of_unity),
        cmocka_unit_test(restricted_sampler_draws_its_pdf),
        cmocka_unit_test(uniform_sampler_pdf_and_inverse),
        cmocka_unit_test(secant_search_matches_binary_search),
        cmocka_unit_test(grouped_draws_match_single_draws),
        cmocka_unit_test(balancing_keeps_every_image_and_spends_the_budget),
        cmocka_unit_test(balance_floor_below_the_lit_images),
        cmocka_unit_test(estimator_mean_equals_quadrature),
        cmocka_unit_test(quadrature_over_s_matches_quadrature_over_u),
        cmocka_unit_test(prediction_matches_measured_variance),
        cmocka_unit_test(probes_are_log_uniform_in_distance),
        cmocka_unit_test(prediction_time_is_the_cost_model),
        cmocka_unit_test(selected_probes_predict_the_same_means),
        cmocka_unit_test(prediction_arguments_and_bands),
        cmocka_unit_test(sample_point_edge_cases),
        cmocka_unit_test(sample_point_draws_what_sample_image_draws),
        cmocka_unit_test(numbers_on_demand_match_the_array),
        cmocka_unit_test(global_draws_finish_like_sample_point),
        cmocka_unit_test(rigid_transform_round_trip),
        cmocka_unit_test(generated_luminaire_reproduces_its_emitter),
        cmocka_unit_test(luminaire_power_and_limits),
        cmocka_unit_test(emitter_matches_closed_forms),
        cmocka_unit_test(malformed_descriptors_get_a_clear_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
