/* The sample sequences (lumis/rng.h's (0,2) building blocks, the renderer's sequences in
 * src/render/sequence.h): the stratification each promises, unbiasedness over its
 * randomisations, convergence rates on analytic integrands, and blue noise across pixels
 * for zsobol.  Every check fails for the independent sequence or for a broken variant. */
/* Oracles:
 * lumis_sobol02_bits — brute force: every prefix and aligned block of 2^14 points is a (0,m,2)-net,
 *     counted cell by cell (sobol02_prefixes_and_blocks_are_nets)
 * lumis_sobol02 — hand-worked: in [0, 1) only (sobol02_prefixes_and_blocks_are_nets)
 * lumis_owen_scramble — brute force, statistical: scrambled points still nets; top bits shared stay
 *     shared, a block stays a permutation, the top bit flips for about half the seeds
 *     (sobol02_prefixes_and_blocks_are_nets, owen_scrambling_permutes_aligned_blocks)
 * lumis_owen_permute_reversed — indirect: inside lumis_owen_scramble and the renderer's sequences,
 *     checked as nets (render_streams_are_nets)
 * lumis_reverse_bits32 — indirect: inside lumis_sobol02_bits and lumis_owen_scramble, checked as
 *     nets (sobol02_prefixes_and_blocks_are_nets)
 * lumis_morton2 — indirect: zsobol's pixel order, seen as blue noise across pixels
 *     (zsobol_moves_error_to_high_frequencies)
 * lumis_pmj02_generate — brute force: every prefix of 4096 points is a (0,m,2)-net; deterministic
 *     per seed; bad counts refused (pmj02_prefixes_are_nets)
 * lumis_sequence_resolve — indirect: the renderer's sequences (default resolved) are nets and
 *     unbiased (render_streams_are_nets, every_sequence_is_unbiased)
 * lumis_sequence_name — consistency: round trip with lumis_sequence_from_name (names_and_bad_kinds)
 * lumis_sequence_from_name — consistency: round trip with lumis_sequence_name (names_and_bad_kinds)
 * lumis_sequence_fill — consistency: the renderer's own streams (lumis__stream_start, then the
 *     draw render.c and the light kinds make) bit for bit, every kind, one and three points per
 *     sample; brute force: stratified and zsobol fills of the planned count are nets; error
 *     paths name the field (fill_is_the_renderers_draw)
 * seq_2d_dims (src/render/sequence.h) — consistency: seq_2d for each dimension in turn, bit for
 *     bit, every kind, dimension 0 and repeats, two batches (dims_batch_is_seq_2d)
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "lumis/render.h"
#include "lumis/rng.h"
#include "render/sequence.h"

/* 1 when the n points (x, y 32-bit fractions, stride 2) are a (0,m,2)-net, n = 2^m: each
 * of the m + 1 grids of 2^a x 2^(m-a) cells holds one point in every cell. */
static int is_net(const uint32_t *xy, uint32_t n)
{
    int m = 0;
    while ((1u << m) < n) m++;
    unsigned char *seen = malloc(n);
    assert_non_null(seen);
    int ok = 1;
    for (int a = 0; a <= m && ok; a++) {
        memset(seen, 0, n);
        for (uint32_t i = 0; i < n && ok; i++) {
            const uint32_t X = m ? xy[2 * i] >> (32 - m) : 0, Y = m ? xy[2 * i + 1] >> (32 - m) : 0;
            const size_t c = ((size_t)(Y >> a) << a) | (X >> (m - a));
            if (seen[c]++) ok = 0;
        }
    }
    free(seen);
    return ok;
}

static void sobol02_prefixes_and_blocks_are_nets(void **state)
{
    (void)state;
    enum { N = 1 << 14 };
    uint32_t *xy = malloc(sizeof *xy * 2 * N);
    assert_non_null(xy);
    for (uint32_t seed = 0; seed < 4; seed++) {
        const uint32_t s0 = 0x1234567u * seed + 1, s1 = 0x7654321u * seed + 3;
        for (uint32_t i = 0; i < N; i++) {
            const uint32_t b0 = lumis_sobol02_bits(i, 0), b1 = lumis_sobol02_bits(i, 1);
            xy[2 * i] = seed ? lumis_owen_scramble(b0, s0) : b0;
            xy[2 * i + 1] = seed ? lumis_owen_scramble(b1, s1) : b1;
        }
        for (uint32_t n = 1; n <= N; n *= 2)
            if (!is_net(xy, n)) fail_msg("seed %u: the first %u points are not a net", seed, n);
        /* any aligned block, not only prefixes (what the index shuffle relies on) */
        for (uint32_t n = 2; n <= N / 4; n *= 8)
            for (uint32_t b = 1; b < N / n; b += 3)
                if (!is_net(xy + 2 * (size_t)b * n, n))
                    fail_msg("seed %u: block %u of %u points is not a net", seed, b, n);
    }
    /* the double form is a (0,2)-sequence too, in both coordinates: its values are 32-bit
     * fractions, so they convert back to the bits exactly */
    double u[2];
    for (uint64_t seed = 0; seed < 3; seed++) {
        enum { M = 1 << 10 };
        for (uint32_t i = 0; i < M; i++) {
            lumis_sobol02(i, seed, u);
            assert_true(u[0] >= 0.0 && u[0] < 1.0 && u[1] >= 0.0 && u[1] < 1.0);
            xy[2 * i] = (uint32_t)(u[0] * 0x1p32);
            xy[2 * i + 1] = (uint32_t)(u[1] * 0x1p32);
        }
        for (uint32_t n = 1; n <= M; n *= 2)
            if (!is_net(xy, n))
                fail_msg("lumis_sobol02 seed %u: the first %u points are not a net", (unsigned)seed,
                         n);
    }
    assert_int_equal(lumis_sobol02_bits(3, 2), 0);
    free(xy);
}

static void owen_scrambling_permutes_aligned_blocks(void **state)
{
    (void)state;
    /* values sharing their top k bits share them after scrambling (the scramble of digit i
     * depends only on the digits above it), and a block's values stay distinct */
    lumis_pcg32 g;
    lumis_pcg32_seed(&g, 5, 1);
    for (int t = 0; t < 2000; t++) {
        const uint32_t v = lumis_pcg32_next(&g), w = lumis_pcg32_next(&g),
                       seed = lumis_pcg32_next(&g);
        const int k = (int)(lumis_pcg32_next(&g) % 31) + 1;
        const uint32_t top = ~0u << (32 - k);
        const uint32_t w2 = (v & top) | (w & ~top);
        assert_int_equal(lumis_owen_scramble(v, seed) & top, lumis_owen_scramble(w2, seed) & top);
    }
    enum { B = 1 << 12 };
    unsigned char *seen = calloc(B, 1);
    assert_non_null(seen);
    const uint32_t base = 0xabc00000u;
    uint32_t out_top = lumis_owen_scramble(base, 99u) & ~(uint32_t)(B - 1) << 8;
    for (uint32_t i = 0; i < B; i++) {
        const uint32_t o = lumis_owen_scramble(base | (i << 8), 99u);
        assert_int_equal(o & ~(uint32_t)(B - 1) << 8, out_top);
        const uint32_t slot = (o >> 8) & (B - 1);
        assert_int_equal(seen[slot], 0);
        seen[slot] = 1;
    }
    free(seen);
    /* the top bit is flipped for about half the seeds: the scramble is random */
    int flips = 0;
    for (uint32_t s = 0; s < 1000; s++)
        flips += (int)(lumis_owen_scramble(0, s * 2654435761u) >> 31);
    assert_true(flips > 420 && flips < 580);
}

static void pmj02_prefixes_are_nets(void **state)
{
    (void)state;
    enum { N = 4096 };
    uint32_t *xy = malloc(sizeof *xy * 2 * N), *again = malloc(sizeof *again * 2 * N);
    assert_non_null(xy);
    assert_non_null(again);
    for (uint64_t seed = 0; seed < 6; seed++) {
        assert_int_equal(lumis_pmj02_generate(N, seed, xy), LUMIS_OK);
        for (uint32_t n = 1; n <= N; n *= 2)
            if (!is_net(xy, n))
                fail_msg("seed %u: the first %u points are not a net", (unsigned)seed, n);
    }
    /* the jitter: inside its cell of the finest grid (2^12 strata an axis) the last points
     * placed (at level 12) are uniform, their 20 low bits ranging over the whole cell */
    for (int d = 0; d < 2; d++) {
        const uint32_t low = (1u << 20) - 1u;
        uint32_t any = 0;
        double mean = 0.0, sq = 0.0;
        for (uint32_t i = N / 2; i < N; i++) {
            const uint32_t o = xy[2 * i + (uint32_t)d] & low;
            any |= o;
            mean += o * 0x1p-20 / (N / 2);
            sq += o * 0x1p-20 * (o * 0x1p-20) / (N / 2);
        }
        assert_int_equal(any, low);
        /* uniform on [0, 1): mean 1/2, second moment 1/3, each within ~6 standard errors */
        if (fabs(mean - 0.5) > 0.03 || fabs(sq - 1.0 / 3.0) > 0.03)
            fail_msg("axis %d: jitter mean %g, second moment %g", d, mean, sq);
    }
    /* deterministic in the seed, different across seeds */
    assert_int_equal(lumis_pmj02_generate(N, 5, again), LUMIS_OK);
    assert_memory_equal(xy, again, sizeof *xy * 2 * N);
    assert_int_equal(lumis_pmj02_generate(N, 6, again), LUMIS_OK);
    assert_memory_not_equal(xy, again, sizeof *xy * 2 * N);
    assert_int_equal(lumis_pmj02_generate(1, 0, xy), LUMIS_OK);
    assert_int_equal(lumis_pmj02_generate(0, 0, xy), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_pmj02_generate(48, 0, xy), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_pmj02_generate((1u << 20) * 2, 0, xy), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_pmj02_generate(4, 0, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    free(xy);
    free(again);
}

/* ---- the renderer's sequences ------------------------------------------------------------ */

static lumis__seq make_seq(lumis_sequence kind, uint64_t seed, int spp)
{
    lumis__seq q;
    assert_int_equal(lumis__seq_init(&q, kind, seed, spp, NULL), LUMIS_OK);
    return q;
}

/* Point k of dimension dim of pixel (x, y), the n = 1 way (sample k of the pixel). */
static void point(const lumis__seq *q, int x, int y, int k, uint32_t dim, int one_d, double u[2])
{
    lumis__stream s;
    lumis__stream_start(&s, q, x, y, 64, k);
    if (q->kind == LUMIS_SEQUENCE_PCG) {
        /* PCG ignores dimensions: the numbers come in order */
        for (uint32_t d = 0; d < dim; d++)
            (void)lumis_pcg32_double(&s.rng), (void)lumis_pcg32_double(&s.rng);
        u[0] = lumis_pcg32_double(&s.rng);
        u[1] = lumis_pcg32_double(&s.rng);
        return;
    }
    lumis__seq_point(&s, dim, 0, 1, one_d, u);
}

static double f_smooth(double x, double y)
{
    return exp(-(x * x + y * y)) * (1.0 + 0.5 * cos(3.0 * x * y));
}

static double f_disk(double x, double y)
{
    return (x - 0.45) * (x - 0.45) + (y - 0.4) * (y - 0.4) < 0.3 * 0.3 ? 1.0 : 0.0;
}

static double exact_of(double (*f)(double, double))
{
    /* midpoint rule on a 2048^2 grid (the disk's boundary error: ~1e-7) */
    enum { G = 2048 };
    double s = 0.0;
    for (int j = 0; j < G; j++)
        for (int i = 0; i < G; i++) s += f((i + 0.5) / G, (j + 0.5) / G);
    return s / ((double)G * G);
}

/* Least-squares slope of log(MSE) against log(N), N = 16 .. 4096 points of one pixel's
 * sequence (the first N camera samples), MSE over 64 pixels (64 randomisations). */
static double mse_slope(lumis_sequence kind, uint32_t dim, double (*f)(double, double),
                        double exact)
{
    enum { PIXELS = 64, NMAX = 4096 };
    lumis__seq q = make_seq(kind, 11, 0);
    double lx[9], ly[9];
    int c = 0;
    double *sum = calloc(PIXELS, sizeof *sum);
    assert_non_null(sum);
    int next = 16;
    for (int k = 0; k < NMAX; k++) {
        for (int p = 0; p < PIXELS; p++) {
            double u[2];
            point(&q, p % 8, p / 8, k, dim, 0, u);
            sum[p] += f(u[0], u[1]);
        }
        if (k + 1 == next) {
            double mse = 0.0;
            for (int p = 0; p < PIXELS; p++) {
                const double e = sum[p] / next - exact;
                mse += e * e / PIXELS;
            }
            lx[c] = log((double)next);
            ly[c] = log(mse);
            c++;
            next *= 2;
        }
    }
    free(sum);
    lumis__seq_release(&q);
    double mx = 0, my = 0;
    for (int i = 0; i < c; i++) mx += lx[i] / c, my += ly[i] / c;
    double sxy = 0, sxx = 0;
    for (int i = 0; i < c; i++)
        sxy += (lx[i] - mx) * (ly[i] - my), sxx += (lx[i] - mx) * (lx[i] - mx);
    return sxy / sxx;
}

static void sequences_converge_faster_than_independent_numbers(void **state)
{
    (void)state;
    const double es = exact_of(f_smooth), ed = exact_of(f_disk);
    const lumis_sequence qmc[3] = {LUMIS_SEQUENCE_SOBOL, LUMIS_SEQUENCE_ZSOBOL,
                                   LUMIS_SEQUENCE_PMJ02};
    for (int i = 0; i < 3; i++)
        for (uint32_t dim = 0; dim < 40; dim += 13) { /* past pmj02's 32 tables too */
            const double s = mse_slope(qmc[i], dim, f_smooth, es),
                         d = mse_slope(qmc[i], dim, f_disk, ed);
            print_message("%-6s dim %2u: MSE slope %.2f (smooth), %.2f (disk)\n",
                          lumis_sequence_name(qmc[i]), dim, s, d);
            if (s > -1.5)
                fail_msg("%s dim %u: smooth slope %.2f > -1.5", lumis_sequence_name(qmc[i]), dim,
                         s);
            if (d > -1.25)
                fail_msg("%s dim %u: disk slope %.2f > -1.25", lumis_sequence_name(qmc[i]), dim, d);
        }
    /* the reference: independent numbers fall as 1 / N, and the test sees it */
    const double p = mse_slope(LUMIS_SEQUENCE_PCG, 0, f_smooth, es);
    print_message("pcg   : MSE slope %.2f (smooth)\n", p);
    assert_true(p > -1.2 && p < -0.8);
}

/* Over the randomisations (pixels, seeds) every sequence's estimate is the integral: the
 * mean of 16-point estimates of the disk over 2048 randomisations within 4 standard errors,
 * in 2D, in 1D, for n points per camera sample, past 32 dimensions, and in the bits below
 * a number's top 32 (32-bit points with nothing below them biased the alias tables). */
static void every_sequence_is_unbiased(void **state)
{
    (void)state;
    const double ed = exact_of(f_disk);
    for (int kind = 0; kind < LUMIS_SEQUENCE_COUNT; kind++)
        for (int variant = 0; variant < 5; variant++) {
            enum { R = 2048, N = 16 };
            lumis__seq q = make_seq((lumis_sequence)kind, 3, N);
            const uint32_t dim = variant == 3 ? 45 : (uint32_t)variant;
            double s = 0, s2 = 0;
            for (int r = 0; r < R; r++) {
                double est = 0;
                for (int k = 0; k < N; k++) {
                    lumis__stream st;
                    lumis__stream_start(&st, &q, r % 64, r / 64, 64, variant == 2 ? 1 : k);
                    double u[2];
                    if (variant == 4) { /* the bits below the top 32 (what an alias
                                           table's draw places the direction with) */
                        seq_2d(&st, 2, 0, 1, u);
                        const double y = u[1] * 0x1p32;
                        est += (y - floor(y)) * 2.0 * ed;
                    } else if (variant == 1) { /* 1D: the integral of x^2 */
                        u[0] = seq_1d(&st, dim, 0, 1);
                        est += u[0] * u[0] * 3.0 * ed; /* scaled to share the check */
                    } else if (variant == 2) {         /* 16 points of camera sample 1 */
                        seq_2d(&st, dim, (uint32_t)k, N, u);
                        est += f_disk(u[0], u[1]);
                    } else {
                        seq_2d(&st, dim, 0, 1, u);
                        est += f_disk(u[0], u[1]);
                    }
                }
                est /= N;
                s += est;
                s2 += est * est;
            }
            const double mean = s / R, se = sqrt(fmax(s2 / R - mean * mean, 1e-12) / (R - 1));
            if (fabs(mean - ed) > 4.0 * se + 1e-9)
                fail_msg("%s variant %d: mean %.6f, exact %.6f (%.1f standard errors)",
                         lumis_sequence_name((lumis_sequence)kind), variant, mean, ed,
                         (mean - ed) / se);
            lumis__seq_release(&q);
        }
}

/* The error of a pixel's 4-sample estimate of a smooth integrand across a 64 x 64 screen:
 * zsobol's 2 x 2 neighbours share the nets of their 16 samples, so averaging 2 x 2 blocks
 * cancels most of it (blue noise: the error's power is at high frequencies); per-pixel
 * scrambling leaves white noise (the block mean keeps 1/4 of the variance). */
static double block_variance_ratio(lumis_sequence kind)
{
    enum { W = 64, N = 4 };
    lumis__seq q = make_seq(kind, 5, N);
    static double e[W * W];
    double mean = 0;
    for (int y = 0; y < W; y++)
        for (int x = 0; x < W; x++) {
            double est = 0;
            for (int k = 0; k < N; k++) {
                lumis__stream st;
                lumis__stream_start(&st, &q, x, y, W, k);
                double u[2];
                seq_2d(&st, 1, 0, 1, u);
                est += f_smooth(u[0], u[1]);
            }
            e[y * W + x] = est / N;
            mean += est / N / (W * W);
        }
    double v = 0, vb = 0;
    for (int k = 0; k < W * W; k++) v += (e[k] - mean) * (e[k] - mean) / (W * W);
    for (int y = 0; y < W; y += 2)
        for (int x = 0; x < W; x += 2) {
            const double b =
                (e[y * W + x] + e[y * W + x + 1] + e[(y + 1) * W + x] + e[(y + 1) * W + x + 1]) /
                    4 -
                mean;
            vb += b * b / (W * W / 4);
        }
    lumis__seq_release(&q);
    return vb / v;
}

/* The correlation, over 48 seeds, between the errors of 16-sample disk estimates of
 * pixels 8 apart (in different 8 x 8 blocks of the z-order), averaged over 28 pairs of 8
 * such pixels. */
static double far_error_correlation(lumis_sequence kind)
{
    enum { SEEDS = 48, PIX = 8, N = 16 };
    const double ed = exact_of(f_disk);
    double e[SEEDS][PIX];
    for (int sd = 0; sd < SEEDS; sd++) {
        lumis__seq q = make_seq(kind, 100u + (uint64_t)sd, N);
        for (int p = 0; p < PIX; p++) {
            double est = 0;
            for (int k = 0; k < N; k++) {
                lumis__stream st;
                lumis__stream_start(&st, &q, 3 + 8 * p, 5 + 8 * (p % 3), 64, k);
                double u[2];
                seq_2d(&st, 1, 0, 1, u);
                est += f_disk(u[0], u[1]);
            }
            e[sd][p] = est / N - ed;
        }
        lumis__seq_release(&q);
    }
    double sum = 0;
    int pairs = 0;
    for (int a = 0; a < PIX; a++)
        for (int b = a + 1; b < PIX; b++) {
            double ma = 0, mb = 0, sab = 0, saa = 0, sbb = 0;
            for (int sd = 0; sd < SEEDS; sd++) ma += e[sd][a] / SEEDS, mb += e[sd][b] / SEEDS;
            for (int sd = 0; sd < SEEDS; sd++) {
                sab += (e[sd][a] - ma) * (e[sd][b] - mb);
                saa += (e[sd][a] - ma) * (e[sd][a] - ma);
                sbb += (e[sd][b] - mb) * (e[sd][b] - mb);
            }
            sum += sab / sqrt(saa * sbb);
            pairs++;
        }
    return sum / pairs;
}

static void zsobol_moves_error_to_high_frequencies(void **state)
{
    (void)state;
    const double z = block_variance_ratio(LUMIS_SEQUENCE_ZSOBOL),
                 s = block_variance_ratio(LUMIS_SEQUENCE_SOBOL),
                 p = block_variance_ratio(LUMIS_SEQUENCE_PCG);
    print_message("2x2 block variance / pixel variance: zsobol %.3f, sobol %.3f, pcg %.3f\n", z, s,
                  p);
    assert_true(s > 0.18 && s < 0.32); /* white */
    assert_true(p > 0.18 && p < 0.32);
    assert_true(z < 0.3 * s);
    /* ... without tying distant pixels' errors together (the scrambles are the same for
     * every pixel: only the index's z-order part tells them apart) */
    const double cz = far_error_correlation(LUMIS_SEQUENCE_ZSOBOL),
                 cs = far_error_correlation(LUMIS_SEQUENCE_SOBOL);
    print_message("error correlation of pixels 8 apart: zsobol %.3f, sobol %.3f\n", cz, cs);
    assert_true(fabs(cs) < 0.1);
    assert_true(fabs(cz) < 0.1);
}

/* What the renderer hands a pixel is still a net: the first 2^m camera samples of one
 * dimension of one pixel (sobol, zsobol, pmj02; past pmj02's 32 tables too), and the 2^m
 * points j of one camera sample (n = 2^m per camera sample). */
static void render_streams_are_nets(void **state)
{
    (void)state;
    enum { N = 1024 };
    static uint32_t xy[2 * N];
    const lumis_sequence kinds[3] = {LUMIS_SEQUENCE_SOBOL, LUMIS_SEQUENCE_ZSOBOL,
                                     LUMIS_SEQUENCE_PMJ02};
    for (int c = 0; c < 3; c++)
        for (int per_sample = 0; per_sample < 2; per_sample++) {
            lumis__seq q = make_seq(kinds[c], 9, 0);
            for (uint32_t dim = 0; dim < 40; dim += 7)
                for (int pixel = 0; pixel < 3; pixel++) {
                    for (uint32_t k = 0; k < N; k++) {
                        lumis__stream st;
                        lumis__stream_start(&st, &q, 5 + pixel, 3, 64, per_sample ? 7 : (int)k);
                        double u[2];
                        seq_2d(&st, dim, per_sample ? k : 0, per_sample ? N : 1, u);
                        xy[2 * k] = (uint32_t)(u[0] * 0x1p32);
                        xy[2 * k + 1] = (uint32_t)(u[1] * 0x1p32);
                    }
                    for (uint32_t n = 1; n <= N; n *= 2)
                        if (!is_net(xy, n))
                            fail_msg("%s dim %u pixel %d%s: the first %u points are not a net",
                                     lumis_sequence_name(kinds[c]), dim, pixel,
                                     per_sample ? " (points of one camera sample)" : "", n);
                }
            lumis__seq_release(&q);
        }
}

/* Two dimensions of one camera sample together: a 4D integrand (a discontinuity across
 * both) must keep converging.  (pmj02's tables share their construction, so index k of
 * two tables is nearly the same point: paired as they are, the error stopped falling at
 * 256 samples, until the order of each doubling was drawn per pixel and dimension.) */
static double f4(const double *a, const double *b)
{
    return (a[0] + b[0] < 1.0 ? 1.0 : 0.0) * (a[1] * b[1] > 0.2 ? 1.0 : 0.3);
}

static void pairs_of_dimensions_keep_converging(void **state)
{
    (void)state;
    for (int kind = LUMIS_SEQUENCE_HALTON; kind < LUMIS_SEQUENCE_COUNT; kind++) {
        enum { W = 16 };
        double var[2];
        for (int c = 0; c < 2; c++) {
            const int n = c ? 1024 : 64;
            lumis__seq q = make_seq((lumis_sequence)kind, 5, n);
            double s1 = 0, s2 = 0;
            for (int p = 0; p < W * W; p++) {
                double e = 0;
                for (int k = 0; k < n; k++) {
                    lumis__stream st;
                    lumis__stream_start(&st, &q, p % W, p / W, W, k);
                    double a[2], b[2];
                    seq_2d(&st, 0, 0, 1, a); /* (sobol leaves dimension 0 unshuffled) */
                    seq_2d(&st, 1, 0, 1, b);
                    e += f4(a, b);
                }
                e /= n;
                s1 += e;
                s2 += e * e;
            }
            const double m = s1 / (W * W);
            var[c] = s2 / (W * W) - m * m;
            lumis__seq_release(&q);
        }
        print_message("%-10s 4D variance: %.3g at 64, %.3g at 1024 samples\n",
                      lumis_sequence_name((lumis_sequence)kind), var[0], var[1]);
        /* 16 times the samples: independent numbers divide it by 16, nets by more */
        if (!(var[1] < var[0] / 12.0))
            fail_msg("%s: 4D variance %.3g at 64 samples, %.3g at 1024",
                     lumis_sequence_name((lumis_sequence)kind), var[0], var[1]);
    }
}

static void names_and_bad_kinds(void **state)
{
    (void)state;
    lumis__seq q;
    assert_int_equal(lumis__seq_init(&q, LUMIS_SEQUENCE_COUNT, 1, 4, NULL),
                     LUMIS_ERR_INVALID_ARGUMENT);
    for (int k = 0; k < LUMIS_SEQUENCE_COUNT; k++) {
        lumis_sequence back;
        assert_int_equal(lumis_sequence_from_name(lumis_sequence_name((lumis_sequence)k), &back),
                         LUMIS_OK);
        assert_int_equal(back, k);
    }
}

/* lumis_sequence_fill (the Python package's lumis.render_sequence) hands out the numbers the
 * renderer's streams give, bit for bit: n = 1 as point() above draws them, n = 3 through
 * seq_2d as the light kinds call it. */
static void fill_is_the_renderers_draw(void **state)
{
    (void)state;
    enum { S = 16, N3 = 3 };
    double got[2 * S * N3], want[2];
    for (int kind = 1; kind < LUMIS_SEQUENCE_COUNT; kind++)
        for (uint32_t dim = 0; dim < 5; dim += 2) {
            lumis__seq q = make_seq((lumis_sequence)kind, 77, S);
            lumis_sequence_desc d = {(lumis_sequence)kind, 77, S, 64, 9, 5, (int)dim, 0, {0}};
            assert_int_equal(lumis_sequence_fill(&d, 3, S, got), LUMIS_OK);
            for (int i = 0; i < S; i++) {
                point(&q, 9, 5, 3 + i, dim, 0, want);
                assert_memory_equal(got + 2 * i, want, sizeof want);
            }
            d.per_sample = N3;
            assert_int_equal(lumis_sequence_fill(&d, 0, S, got), LUMIS_OK);
            for (int k = 0, i = 0; k < S; k++) {
                lumis__stream s;
                lumis__stream_start(&s, &q, 9, 5, 64, k);
                for (uint32_t skip = 0; kind == LUMIS_SEQUENCE_PCG && skip < 2 * dim * N3; skip++)
                    (void)lumis_pcg32_double(&s.rng);
                for (uint32_t j = 0; j < N3; j++, i++) {
                    seq_2d(&s, dim, j, N3, want);
                    assert_memory_equal(got + 2 * i, want, sizeof want);
                }
            }
            lumis__seq_release(&q);
        }
    /* the planned count of stratified and zsobol points is a net (stratified: a 4 x 4 grid
     * of 16 holds one in each cell) */
    uint32_t xy[2 * S];
    for (int kind = LUMIS_SEQUENCE_STRATIFIED; kind <= LUMIS_SEQUENCE_ZSOBOL; kind += 2) {
        const lumis_sequence_desc d = {(lumis_sequence)kind, 5, S, 8, 2, 7, 1, 0, {0}};
        assert_int_equal(lumis_sequence_fill(&d, 0, S, got), LUMIS_OK);
        for (int i = 0; i < 2 * S; i++) xy[i] = (uint32_t)(got[i] * 4294967296.0);
        if (kind == LUMIS_SEQUENCE_ZSOBOL)
            assert_true(is_net(xy, S));
        else
            for (int c = 0; c < S; c++) {
                int in = 0;
                for (int i = 0; i < S; i++)
                    in += (xy[2 * i] >> 30) + 4 * (xy[2 * i + 1] >> 30) == (uint32_t)c;
                assert_int_equal(in, 1);
            }
    }
    /* refusals */
    const lumis_sequence_desc ok = {LUMIS_SEQUENCE_SOBOL, 1, 4, 4, 3, 0, 0, 0, {0}};
    lumis_sequence_desc bad = ok;
    assert_int_equal(lumis_sequence_fill(&ok, 0, 0, NULL), LUMIS_OK);
    assert_int_equal(lumis_sequence_fill(&ok, 0, 1, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_sequence_fill(&ok, -1, 1, got), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_sequence_fill(NULL, 0, 1, got), LUMIS_ERR_INVALID_ARGUMENT);
    bad.x = 4;
    assert_int_equal(lumis_sequence_fill(&bad, 0, 1, got), LUMIS_ERR_INVALID_ARGUMENT);
    bad = ok, bad.dimension = -1;
    assert_int_equal(lumis_sequence_fill(&bad, 0, 1, got), LUMIS_ERR_INVALID_ARGUMENT);
    bad = ok, bad.sequence = LUMIS_SEQUENCE_COUNT;
    assert_int_equal(lumis_sequence_fill(&bad, 0, 1, got), LUMIS_ERR_INVALID_ARGUMENT);
    bad = ok, bad.per_sample = -2;
    assert_int_equal(lumis_sequence_fill(&bad, 0, 1, got), LUMIS_ERR_INVALID_ARGUMENT);
}

/* seq_2d_dims (a stratified vertex's K points at once) gives what seq_2d gives for each
 * dimension in turn, bit for bit, for every kind: with dimension 0 among them, dimensions
 * out of order and repeated, more than one batch (70 > 64), at camera samples whose index
 * reversed has high bits set, and the streams left where seq_2d leaves them (PCG32). */
static void dims_batch_is_seq_2d(void **state)
{
    (void)state;
    enum { M = 70 };
    uint32_t dims[M];
    double got[2 * M], want[2];
    for (int q = 0; q < M; q++) dims[q] = (uint32_t)((q * 7 + 3) % 61);
    dims[5] = 0;
    dims[9] = dims[8];
    for (int kind = 1; kind < LUMIS_SEQUENCE_COUNT; kind++) {
        lumis__seq sq = make_seq((lumis_sequence)kind, 91, 64);
        for (int k = 0; k < 64; k += 13)
            for (int m = 0; m <= M; m += M / 2) {
                lumis__stream a, b;
                lumis__stream_start(&a, &sq, 5, 3, 16, k);
                lumis__stream_start(&b, &sq, 5, 3, 16, k);
                seq_2d_dims(&a, dims, m, got);
                for (int q = 0; q < m; q++) {
                    seq_2d(&b, dims[q], 0, 1, want);
                    assert_memory_equal(got + 2 * q, want, sizeof want);
                }
                seq_2d(&a, 4, 0, 1, got);
                seq_2d(&b, 4, 0, 1, want);
                assert_memory_equal(got, want, sizeof want);
            }
        lumis__seq_release(&sq);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sobol02_prefixes_and_blocks_are_nets),
        cmocka_unit_test(owen_scrambling_permutes_aligned_blocks),
        cmocka_unit_test(pmj02_prefixes_are_nets),
        cmocka_unit_test(sequences_converge_faster_than_independent_numbers),
        cmocka_unit_test(every_sequence_is_unbiased),
        cmocka_unit_test(zsobol_moves_error_to_high_frequencies),
        cmocka_unit_test(pairs_of_dimensions_keep_converging),
        cmocka_unit_test(render_streams_are_nets),
        cmocka_unit_test(names_and_bad_kinds),
        cmocka_unit_test(fill_is_the_renderers_draw),
        cmocka_unit_test(dims_batch_is_seq_2d),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
