/* Core building blocks: status table, image buffers, sanitizing, PCG32, Halton. */
/* Oracles:
 * lumis_status_name — hand-worked: "ok", "truncated", unknown codes; names distinct
 *     (status_names_are_unique_and_total)
 * lumis_status_string — hand-worked: non-empty for every code, "unknown status" past the end
 *     (status_names_are_unique_and_total)
 * lumis_image_check_size — hand-worked: limits 0, negative, 16384^2, 64-bit overflow, max_pixels
 *     edge (image_sizes_are_checked_before_allocation)
 * lumis_image_create — hand-worked: zero-filled 3 x 2, bad size refused, NULL out
 *     (image_sizes_are_checked_before_allocation)
 * lumis_image_clone — hand-worked: first and last values copied into a new buffer
 *     (image_sizes_are_checked_before_allocation)
 * lumis_image_destroy — external: leaks seen by ASan (make sanitize) and valgrind
 *     (scripts/memcheck.sh); NULL accepted (image_sizes_are_checked_before_allocation)
 * lumis_sanitize_floats — hand-worked: NaN, ±inf, negatives, -0, FLT_MAX counted and replaced,
 *     counts accumulate (sanitize_counts_each_kind)
 * lumis_replaced_total — hand-worked: 5 of 9 hand-made values (sanitize_counts_each_kind)
 * lumis_image_spikes — hand-worked: a blue spike at the seam found, a sun and a dim-surround pixel
 *     not; 3 x 3 and 3 x 2 maps (spikes_are_saturated_and_isolated)
 * lumis_pcg32_seed — external: the reference pcg32-demo sequence, seed 42 stream 54
 *     (pcg32_matches_the_reference_sequence)
 * lumis_pcg32_next — external: the reference pcg32-demo sequence
 *     (pcg32_matches_the_reference_sequence)
 * lumis_pcg32_output — indirect: inside lumis_pcg32_next, pinned by the reference sequence
 *     (pcg32_matches_the_reference_sequence)
 * lumis_pcg32_advance — brute force: 1000 single steps forward, then back to the seed
 *     (pcg32_advance_jumps_both_ways)
 * lumis_pcg32_fill_doubles — brute force: successive lumis_pcg32_double calls, every length
 *     (pcg32_fill_doubles_matches_successive_draws)
 * lumis_pcg32_float — statistical: in [0, 1), mean 1/2 within 4 sigma
 *     (pcg32_floats_and_bounded_are_uniform)
 * lumis_pcg32_double — statistical: in [0, 1) over 200000 draws
 *     (pcg32_floats_and_bounded_are_uniform)
 * lumis_pcg32_bounded — statistical: chi-square over 7 bins; bound 3 2^30 draws multiples of 3 a
 *     third of the time (pcg32_floats_and_bounded_are_uniform,
 *     pcg32_bounded_rejects_the_biased_slice)
 * lumis_radical_inverse — hand-worked: base-2 and base-3 digits reversed, huge indices in [0, 1)
 *     (radical_inverse_reverses_digits)
 * lumis_halton — hand-worked: 12 in base 5; the first 81 base-3 points fill 81 strata
 *     (radical_inverse_reverses_digits)
 * lumis_simd_variant — hand-worked: the CPU's best level under LUMIS_SIMD=avx512, "baseline" when
 *     forced (simd_variant_follows_the_environment)
 */
#include "testutil.h"

#include "core/distrib.h"
#include "core/internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static void status_names_are_unique_and_total(void **state)
{
    (void)state;
    for (int a = 0; a < LUMIS_STATUS_COUNT; a++) {
        const char *na = lumis_status_name((lumis_status)a);
        assert_true(strlen(na) > 0);
        assert_true(strlen(lumis_status_string((lumis_status)a)) > 0);
        assert_string_not_equal(na, "unknown-status");
        for (int b = a + 1; b < LUMIS_STATUS_COUNT; b++)
            assert_string_not_equal(na, lumis_status_name((lumis_status)b));
    }
    assert_string_equal(lumis_status_name(LUMIS_OK), "ok");
    assert_string_equal(lumis_status_name(LUMIS_ERR_TRUNCATED), "truncated");
    assert_string_equal(lumis_status_name(LUMIS_STATUS_COUNT), "unknown-status");
    assert_string_equal(lumis_status_name((lumis_status)-1), "unknown-status");
    assert_string_equal(lumis_status_string(LUMIS_STATUS_COUNT), "unknown status");
}

static void fail_helper_formats_into_the_sink(void **state)
{
    (void)state;
    tu_sink s;
    tu_sink_init(&s);
    assert_int_equal(lumis__fail(&s.sink, LUMIS_ERR_CORRUPT, "%s: %d", "x.exr", 7),
                     LUMIS_ERR_CORRUPT);
    assert_string_equal(s.last, "x.exr: 7");
    assert_int_equal(s.status, LUMIS_ERR_CORRUPT);
    /* A zeroed sink and a NULL sink discard quietly. */
    lumis_error_sink none = {0};
    assert_int_equal(lumis__fail(&none, LUMIS_ERR_READ, "x"), LUMIS_ERR_READ);
    assert_int_equal(lumis__fail(NULL, LUMIS_ERR_READ, "x"), LUMIS_ERR_READ);
}

static void image_sizes_are_checked_before_allocation(void **state)
{
    (void)state;
    assert_int_equal(lumis_image_check_size(1, 1, 0), LUMIS_OK);
    assert_int_equal(lumis_image_check_size(0, 5, 0), LUMIS_ERR_BAD_DIMENSIONS);
    assert_int_equal(lumis_image_check_size(5, -1, 0), LUMIS_ERR_BAD_DIMENSIONS);
    assert_int_equal(lumis_image_check_size(INT64_MIN, 2, 0), LUMIS_ERR_BAD_DIMENSIONS);
    assert_int_equal(lumis_image_check_size(16384, 16384, 0), LUMIS_OK);
    assert_int_equal(lumis_image_check_size(16384, 16385, 0), LUMIS_ERR_TOO_LARGE);
    /* Products that overflow 64 bits must not wrap into something small. */
    assert_int_equal(lumis_image_check_size(INT64_MAX, INT64_MAX, 0), LUMIS_ERR_TOO_LARGE);
    assert_int_equal(lumis_image_check_size((int64_t)1 << 32, 1, UINT64_MAX), LUMIS_ERR_TOO_LARGE);
    assert_int_equal(lumis_image_check_size(100, 100, 9999), LUMIS_ERR_TOO_LARGE);
    assert_int_equal(lumis_image_check_size(100, 100, 10000), LUMIS_OK);

    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(0, 3, &img), LUMIS_ERR_BAD_DIMENSIONS);
    assert_null(img);
    assert_int_equal(lumis_image_create(3, 2, &img), LUMIS_OK);
    for (int k = 0; k < 18; k++) assert_true(img->pixels[k] == 0.0f);
    img->pixels[5] = 2.5f;
    img->pixels[17] = 7.0f; /* the last value: the clone copies all three channels */
    lumis_image *copy = NULL;
    assert_int_equal(lumis_image_clone(img, &copy), LUMIS_OK);
    assert_true(copy->pixels[5] == 2.5f && copy->pixels != img->pixels);
    assert_true(copy->pixels[17] == 7.0f);
    lumis_image_destroy(copy);
    lumis_image_destroy(img);
    lumis_image_destroy(NULL);
    assert_int_equal(lumis_image_create(1, 1, NULL), LUMIS_ERR_INVALID_ARGUMENT);
}

static void sanitize_counts_each_kind(void **state)
{
    (void)state;
    float v[] = {1.0f, NAN, -2.0f, INFINITY, -INFINITY, 0.0f, -0.0f, 3e38f, -1e-30f};
    lumis_replaced r = {0};
    assert_int_equal(lumis_sanitize_floats(v, 9, &r), 5);
    assert_int_equal(r.nan, 1);
    assert_int_equal(r.inf, 2);
    assert_int_equal(r.negative, 2);
    assert_true(r.negative_min == -2.0f && r.negative_min_at == 2); /* the worst, and where */
    const float want[] = {1.0f, 0, 0, 0, 0, 0, -0.0f, 3e38f, 0};
    for (int k = 0; k < 9; k++) assert_true(v[k] == want[k]);
    assert_int_equal(lumis_replaced_total(r), 5);
    /* Counts accumulate across calls. */
    float w[] = {NAN};
    lumis_sanitize_floats(w, 1, &r);
    assert_int_equal(r.nan, 2);
    float m[] = {-0.5f, -7.0f};
    lumis_sanitize_floats(m, 2, &r);
    assert_true(r.negative_min == -7.0f && r.negative_min_at == 1 && r.negative == 4);
    /* The largest float is a legal (if bright) value, kept as it is. */
    float big[] = {FLT_MAX};
    assert_int_equal(lumis_sanitize_floats(big, 1, NULL), 0);
    assert_true(big[0] == FLT_MAX);
}

/* A saturated pixel far above its neighbours is a spike; a white sun as bright is not, nor a
 * saturated pixel among neighbours a tenth as bright; columns wrap. */
static void spikes_are_saturated_and_isolated(void **state)
{
    (void)state;
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(12, 6, &img), LUMIS_OK);
    for (int k = 0; k < 12 * 6 * 3; k++) img->pixels[k] = 0.5f + 0.01f * (float)(k % 7);
    float *p = img->pixels;
    const int blue = 3 * (2 * 12 + 0), white = 3 * (4 * 12 + 6), red = 3 * (1 * 12 + 9);
    p[blue] = 0, p[blue + 1] = 0, p[blue + 2] = 9000;          /* (0, 2): at the seam */
    p[white] = 9000, p[white + 1] = 8500, p[white + 2] = 8000; /* a sun */
    p[red] = 3, p[red + 1] = 0, p[red + 2] = 0;                /* saturated, but 6x around it */
    lumis_spike sp[4];
    assert_int_equal(lumis_image_spikes(img, sp, 4), 1);
    assert_int_equal(sp[0].x, 0);
    assert_int_equal(sp[0].y, 2);
    assert_true(sp[0].ratio > 100 && sp[0].ratio < 2000); /* 648 / 0.51 */
    assert_int_equal(lumis_image_spikes(img, NULL, 0), 1);
    assert_int_equal(lumis_image_spikes(NULL, sp, 4), 0);
    lumis_image_destroy(img);
    /* the smallest map with 8 neighbours, 3 x 3: its centre is found; 3 x 2 has none */
    assert_int_equal(lumis_image_create(3, 3, &img), LUMIS_OK);
    for (int k = 0; k < 27; k++) img->pixels[k] = 0.5f;
    img->pixels[3 * 4 + 2] = 9000;
    img->pixels[3 * 4] = img->pixels[3 * 4 + 1] = 0;
    assert_int_equal(lumis_image_spikes(img, sp, 4), 1);
    assert_true(sp[0].x == 1 && sp[0].y == 1);
    lumis_image_destroy(img);
    assert_int_equal(lumis_image_create(3, 2, &img), LUMIS_OK);
    assert_int_equal(lumis_image_spikes(img, sp, 4), 0);
    lumis_image_destroy(img);
}

static void pcg32_matches_the_reference_sequence(void **state)
{
    (void)state;
    /* pcg32-demo of the reference implementation: seed 42, sequence 54. */
    static const uint32_t want[] = {0xa15c02b7, 0x7b47f409, 0xba1d3330,
                                    0x83d2f293, 0xbfa4784b, 0xcbed606e};
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 42u, 54u);
    for (int k = 0; k < 6; k++) assert_int_equal(lumis_pcg32_next(&rng), want[k]);
}

static void pcg32_advance_jumps_both_ways(void **state)
{
    (void)state;
    lumis_pcg32 a, b;
    lumis_pcg32_seed(&a, 7, 3);
    b = a;
    for (int k = 0; k < 1000; k++) (void)lumis_pcg32_next(&a);
    lumis_pcg32_advance(&b, 1000);
    assert_int_equal(a.state, b.state);
    lumis_pcg32_advance(&b, -1000);
    lumis_pcg32 c;
    lumis_pcg32_seed(&c, 7, 3);
    assert_int_equal(b.state, c.state);
}

/* The leapfrogged fill gives the very numbers of successive lumis_pcg32_double calls, for
 * every length (whole chain steps, a tail, shorter than one step) and leaves the generator
 * where the calls would. */
static void pcg32_fill_doubles_matches_successive_draws(void **state)
{
    (void)state;
    for (size_t n = 0; n <= 75; n++) {
        lumis_pcg32 a, b;
        lumis_pcg32_seed(&a, 0x9e37u + n, 11 * n + 1);
        b = a;
        double got[75], want[75];
        lumis_pcg32_fill_doubles(&a, got, n);
        for (size_t k = 0; k < n; k++) want[k] = lumis_pcg32_double(&b);
        for (size_t k = 0; k < n; k++) assert_true(got[k] == want[k]);
        assert_int_equal(a.state, b.state);
        assert_int_equal(lumis_pcg32_next(&a), lumis_pcg32_next(&b));
    }
}

static void pcg32_floats_and_bounded_are_uniform(void **state)
{
    (void)state;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 1, 1);
    enum { N = 200000, B = 7 };
    int hist[B] = {0};
    double sum = 0.0;
    for (int k = 0; k < N; k++) {
        float f = lumis_pcg32_float(&rng);
        double d = lumis_pcg32_double(&rng);
        assert_true(f >= 0.0f && f < 1.0f);
        assert_true(d >= 0.0 && d < 1.0);
        sum += f;
        uint32_t x = lumis_pcg32_bounded(&rng, B);
        assert_true(x < B);
        hist[x]++;
    }
    assert_true(fabs(sum / N - 0.5) < 4.0 * sqrt(1.0 / 12.0 / N));
    /* Chi-square with 6 degrees of freedom; 22.46 is its 0.999 quantile. */
    double chi2 = 0.0, e = (double)N / B;
    for (int k = 0; k < B; k++) chi2 += (hist[k] - e) * (hist[k] - e) / e;
    assert_true(chi2 < 22.46);
}

/* A bound of 3 2^30: without Lemire's rejection (or with a single retry) the multiples of 3
 * take 2 of the 4 preimages of each group, so they would be drawn half the time, not a
 * third of it. */
static void pcg32_bounded_rejects_the_biased_slice(void **state)
{
    (void)state;
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 5, 17);
    enum { N = 30000 };
    const uint32_t bound = 3u << 30;
    int multiples = 0;
    for (int k = 0; k < N; k++) {
        uint32_t x = lumis_pcg32_bounded(&rng, bound);
        assert_true(x < bound);
        multiples += x % 3 == 0;
    }
    /* sigma = sqrt(2/9 / N) = 0.0027; the bias would be 0.042. */
    const double share = (double)multiples / N;
    if (!(fabs(share - 1.0 / 3.0) < 0.015)) fail_msg("multiples of 3: share %.4f, want 1/3", share);
}

/* Every lit entry keeps at least one unit of 2^32: a 1e-12 weight beside a bright one (no
 * test map had an entry under 2^-32 of its table) would otherwise never be drawn, biasing
 * every estimate; the units still sum to the total and follow the weights. */
static void quantize_keeps_every_lit_entry(void **state)
{
    (void)state;
    const double w[5] = {1e-12, 1.0, 0.0, 3e-15, 0.5};
    uint64_t u[5];
    const uint64_t total = (uint64_t)1 << 32;
    lumis__quantize(w, 5, total, u);
    assert_true(u[0] >= 1 && u[3] >= 1 && u[2] == 0);
    assert_true(u[0] + u[1] + u[2] + u[3] + u[4] == total);
    assert_true(llabs((long long)u[1] - (long long)(total * 2 / 3)) <= 2);
    /* Two tiny entries in a row: the second's rounded share lies below what the first's
     * forced unit already gave, and must not wrap round. */
    const double t[3] = {1e-12, 1e-12, 1.0};
    lumis__quantize(t, 3, total, u);
    assert_true(u[0] == 1 && u[1] == 1);
    assert_true(u[0] + u[1] + u[2] == total);
}

/* Weights with dyadic shares, a dark entry in the middle and one at the end: the
 * probabilities are exact, a u on an entry's start lands in that entry with fraction 0
 * (the empty entry before it never), and the search finds the same entry with and without
 * the guide table. */
static void cdf_samples_and_probabilities_are_exact(void **state)
{
    (void)state;
    const double w[6] = {1, 2, 0, 1, 4, 0};
    const double cum[7] = {0, 0.125, 0.375, 0.375, 0.5, 1.0, 1.0}; /* share before entry i */
    for (int guided = 0; guided < 2; guided++) {
        lumis__cdf c;
        assert_int_equal(lumis__cdf_build(&c, w, 6, guided), LUMIS_OK);
        for (uint32_t i = 0; i < 6; i++)
            if (lumis__cdf_prob(&c, i) != cum[i + 1] - cum[i])
                fail_msg("guided %d: entry %u has probability %.17g, want %g", guided, i,
                         lumis__cdf_prob(&c, i), cum[i + 1] - cum[i]);
        for (int q = 0; q <= 1024; q++) {
            const double u = q < 1024 ? q / 1024.0 : 0x1.fffffffffffffp-1;
            uint32_t want = 0;
            for (uint32_t i = 0; i < 5; i++)
                if (cum[i] <= u && cum[i + 1] > cum[i]) want = i;
            const double want_frac = (u - cum[want]) / (cum[want + 1] - cum[want]);
            double frac = -1.0;
            const uint32_t got = lumis__cdf_sample(&c, u, &frac);
            if (got != want || fabs(frac - want_frac) > 1e-9)
                fail_msg("guided %d, u = %.17g: entry %u at %.17g, want %u at %.17g", guided, u,
                         got, frac, want, want_frac);
        }
        lumis__cdf_free(&c);
    }
}

/* The realised probability of each alias entry, from its bins: its own columns' kept
 * share and what the other columns give it. */
static void alias_probabilities(const lumis__alias *a, double *p)
{
    for (uint32_t k = 0; k < a->n; k++) p[k] = 0.0;
    for (uint32_t j = 0; j < a->n; j++) {
        const double keep = a->bin[j].alias == j ? LUMIS__ONE32 : (double)a->bin[j].thresh;
        p[j] += keep;
        if (a->bin[j].alias != j) p[a->bin[j].alias] += LUMIS__ONE32 - keep;
    }
    for (uint32_t k = 0; k < a->n; k++) p[k] /= (double)a->n * LUMIS__ONE32;
}

/* Vose's construction realises the weights exactly, an entry of exactly the mean weight
 * beside larger and smaller ones included ({1, 1, 0.5, 1.5} put the 1s on the small stack
 * and drew them with probability 0), and a tiny entry keeps its unit. */
static void alias_realises_its_weights(void **state)
{
    (void)state;
    static const double cases[3][6] = {
        {1, 1, 0.5, 1.5, 0, 0}, {2, 0.25, 1, 1, 1, 0.75}, {1e-12, 1, 1, 1, 3, 0}};
    static const uint32_t ns[3] = {4, 6, 5};
    for (int c = 0; c < 3; c++) {
        lumis__alias a;
        assert_int_equal(lumis__alias_build(&a, cases[c], ns[c], NULL, NULL), LUMIS_OK);
        double p[6], sum = 0.0;
        alias_probabilities(&a, p);
        for (uint32_t k = 0; k < ns[c]; k++) sum += cases[c][k];
        for (uint32_t k = 0; k < ns[c]; k++) {
            const double want = cases[c][k] / sum;
            if (!(fabs(p[k] - want) <= 4.0 / LUMIS__ONE32 + 1e-12 * want) || !(p[k] > 0.0))
                fail_msg("case %d, entry %u: drawn with probability %.12g, weight share %.12g", c,
                         k, p[k], want);
        }
        lumis__alias_free(&a);
    }
}

/* LUMIS_SIMD=avx512 (set by main before the first query) names the best variant, capped at
 * what the CPU has; forcing a level overrides it until it is released. */
static void simd_variant_follows_the_environment(void **state)
{
    (void)state;
    const char *want = "baseline";
#if LUMIS__MULTIVERSION
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f"))
        want = "avx512";
    else if (__builtin_cpu_supports("avx2"))
        want = "avx2";
#endif
    const char *got = lumis_simd_variant();
    if (!got || strcmp(got, want) != 0)
        fail_msg("LUMIS_SIMD=avx512: variant %s, want %s", got ? got : "(unknown)", want);
    lumis__simd_force(LUMIS__SIMD_BASELINE);
    assert_string_equal(lumis_simd_variant(), "baseline");
    assert_int_equal(lumis__simd_level(), LUMIS__SIMD_BASELINE);
    lumis__simd_force(-1);
    assert_string_equal(lumis_simd_variant(), want);
}

static void radical_inverse_reverses_digits(void **state)
{
    (void)state;
    assert_true(lumis_radical_inverse(0, 0) == 0.0);
    assert_true(lumis_radical_inverse(0, 1) == 0.5);
    assert_true(lumis_radical_inverse(0, 2) == 0.25);
    assert_true(lumis_radical_inverse(0, 3) == 0.75);
    assert_true(lumis_radical_inverse(0, 6) == 0.375); /* 110b -> 0.011b */
    assert_true(fabs(lumis_radical_inverse(1, 1) - 1.0 / 3.0) < 1e-15);
    assert_true(fabs(lumis_radical_inverse(1, 5) - (2.0 / 3.0 + 1.0 / 9.0)) < 1e-15); /* 12_3 */
    assert_true(fabs(lumis_halton(2, 7) - (2.0 / 5.0 + 1.0 / 25.0)) < 1e-15);         /* 12_5 */
    assert_true(lumis_radical_inverse(LUMIS_HALTON_MAX_DIMENSION, 5) == 0.0);
    /* Huge indices stay in [0, 1). */
    for (unsigned d = 0; d < LUMIS_HALTON_MAX_DIMENSION; d++) {
        double x = lumis_radical_inverse(d, UINT64_MAX);
        assert_true(x >= 0.0 && x < 1.0);
    }
    /* The first b^k points of dimension 1 (base 3) fill the b^k strata once each. */
    int seen[81] = {0};
    for (uint64_t i = 0; i < 81; i++) seen[(int)(lumis_halton(1, i) * 81.0 + 1e-9)]++;
    for (int k = 0; k < 81; k++) assert_int_equal(seen[k], 1);
}

int main(void)
{
    /* Before anything reads it (the variant is chosen once per process). */
    setenv("LUMIS_SIMD", "avx512", 1);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(status_names_are_unique_and_total),
        cmocka_unit_test(fail_helper_formats_into_the_sink),
        cmocka_unit_test(image_sizes_are_checked_before_allocation),
        cmocka_unit_test(sanitize_counts_each_kind),
        cmocka_unit_test(spikes_are_saturated_and_isolated),
        cmocka_unit_test(pcg32_matches_the_reference_sequence),
        cmocka_unit_test(pcg32_advance_jumps_both_ways),
        cmocka_unit_test(pcg32_fill_doubles_matches_successive_draws),
        cmocka_unit_test(pcg32_floats_and_bounded_are_uniform),
        cmocka_unit_test(pcg32_bounded_rejects_the_biased_slice),
        cmocka_unit_test(radical_inverse_reverses_digits),
        cmocka_unit_test(quantize_keeps_every_lit_entry),
        cmocka_unit_test(alias_realises_its_weights),
        cmocka_unit_test(cdf_samples_and_probabilities_are_exact),
        cmocka_unit_test(simd_variant_follows_the_environment),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
