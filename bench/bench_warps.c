/* bench_warps [--map FILE] [--size WxH] [--runs R] [--json]: does each environment sampler's
 * warp keep the stratification of a low-discrepancy sequence?  For every sampler, the
 * irradiance at 6 normals is estimated with N = 16 .. 4096 samples from independent PCG32
 * numbers and from Owen-scrambled (0,2) Sobol' points (lumis_sobol02, and pmj02 tables
 * Owen-scrambled per run); the variance over R randomisations (the estimators are unbiased:
 * their variance is their mean squared error) gives the log-log slope against N and the
 * variance ratio to PCG32 at 1024 samples.  A warp that keeps the strata (a monotone map of
 * each coordinate, as inversion) turns the points' nets into strata of the map and shows a
 * steeper slope than -1; one that scatters neighbouring numbers (an alias table's coin flip)
 * stays near -1.  One core, deterministic (docs/sampling.md). */
#include "bench_common.h"
#include "lumis/io.h"
#include "lumis/lumis.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char bench_name[] = "bench_warps";

static const char usage[] =
    "usage: bench_warps [--map FILE] [--size WxH] [--runs R] [--json]\n"
    "  --map FILE   an equirectangular map, resized to WxH (default: the procedural sky)\n"
    "  --size WxH   map size (default 1024x512)\n"
    "  --runs R     randomisations per point of the curve (default 48)\n"
    "  --json       one JSON object instead of the table\n";

enum { NORMALS = 6, LEVELS = 9, SEQS = 3 }; /* N = 16 * 2^l, l < LEVELS: 16 .. 4096 */

static const double normals[NORMALS][3] = {{0, 1, 0},           {0, -1, 0},
                                           {1, 0, 0},           {0.57735, 0.57735, 0.57735},
                                           {-0.6, 0.3, 0.7416}, {0.2, -0.4, -0.8944}};
static const char *const seq_names[SEQS] = {"pcg", "sobol", "pmj02"};

/* The estimates with 16 .. 4096 samples of run r (nested prefixes of one sequence). */
static void estimates(const lumis_sampler *smp, int seq, int run, const uint32_t *pmj,
                      double est[LEVELS][NORMALS])
{
    lumis_pcg32 g;
    lumis_pcg32_seed(&g, 0x5eedull + (uint64_t)run, 7);
    double sum[NORMALS] = {0};
    const uint64_t seed = 0x9e3779b97f4a7c15ull * (uint64_t)(run + 1);
    for (int k = 0, next = 16, l = 0; l < LEVELS; k++) {
        double u[2];
        if (seq == 0) {
            u[0] = lumis_pcg32_double(&g);
            u[1] = lumis_pcg32_double(&g);
        } else if (seq == 1) {
            lumis_sobol02((uint32_t)k, seed, u);
        } else {
            u[0] = lumis_owen_scramble(pmj[2 * k], (uint32_t)seed) * 0x1p-32;
            u[1] = lumis_owen_scramble(pmj[2 * k + 1], (uint32_t)(seed >> 32)) * 0x1p-32;
        }
        /* 53 bits: below the net's 32, random (the alias tables read them) */
        u[0] += lumis_pcg32_double(&g) * 0x1p-32 * (seq != 0);
        u[1] += lumis_pcg32_double(&g) * 0x1p-32 * (seq != 0);
        const lumis_env_sample e = lumis_sampler_sample(smp, u[0], u[1]);
        const double Y = 0.2126 * e.radiance.r + 0.7152 * e.radiance.g + 0.0722 * e.radiance.b;
        if (e.pdf > 0.0f)
            for (int n = 0; n < NORMALS; n++) {
                const double c =
                    e.dir.x * normals[n][0] + e.dir.y * normals[n][1] + e.dir.z * normals[n][2];
                if (c > 0.0) sum[n] += Y * c / e.pdf;
            }
        if (k + 1 == next) {
            for (int n = 0; n < NORMALS; n++) est[l][n] = sum[n] / next;
            l++;
            next *= 2;
        }
    }
}

int main(int argc, char **argv)
{
    int w = 1024, h = 512, runs = 48, json = 0;
    const char *map = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(a, "--size") && i + 1 < argc) {
            if (!bench_parse_size(argv[++i], &w, &h)) return bench_usage_error("bad --size");
        } else if (!strcmp(a, "--runs") && i + 1 < argc) {
            if (!bench_parse_int(argv[++i], 4, 10000, &runs))
                return bench_usage_error("bad --runs");
        } else if (!strcmp(a, "--map") && i + 1 < argc) {
            map = argv[++i];
        } else if (!strcmp(a, "--json")) {
            json = 1;
        } else {
            return bench_usage_error("unknown or incomplete option '%s'", a);
        }
    }
    lumis_envmap *env = NULL;
    if (bench_load_map(map, w, h, &env) != 0) return 1;
    lumis_status st;
    enum { NMAX = 16 << (LEVELS - 1) };
    uint32_t *pmj = malloc(sizeof *pmj * 2 * NMAX);
    double(*est)[LEVELS][NORMALS] = malloc(sizeof *est * (size_t)runs);
    if (!pmj || !est) return bench_fail("out of memory");
    if (json)
        printf("{\"bench\": \"bench_warps\", \"map\": \"%s\", \"width\": %d, \"height\": %d, "
               "\"runs\": %d, \"samplers\": [",
               map ? map : "sky", w, h, runs);
    else
        printf("%-16s %-6s %8s %12s %12s\n", "sampler", "seq", "slope", "var@1024", "vs pcg@1024");
    for (int m = LUMIS_METHOD_INVERSION; m < LUMIS_METHOD_COUNT; m++) {
        lumis_sampler_desc sd = {0};
        sd.method = (lumis_sampler_method)m;
        lumis_sampler *smp = NULL;
        if ((st = lumis_sampler_create(env, &sd, &smp)) != LUMIS_OK)
            return bench_fail("sampler %d: %s", m, lumis_status_string(st));
        double var1024[SEQS] = {0};
        if (json) printf("%s{\"method\": \"%s\"", m > 1 ? ", " : "", lumis_sampler_method_name(m));
        for (int q = 0; q < SEQS; q++) {
            for (int r = 0; r < runs; r++) {
                if (q == 2 && lumis_pmj02_generate(NMAX, 1000u + (uint64_t)r, pmj) != LUMIS_OK)
                    return bench_fail("pmj02 tables");
                estimates(smp, q, r, pmj, est[r]);
            }
            /* the variance over runs, averaged over the normals relative to their mean^2 */
            double lx[LEVELS], ly[LEVELS];
            for (int l = 0; l < LEVELS; l++) {
                double rel = 0.0;
                for (int n = 0; n < NORMALS; n++) {
                    double s = 0, s2 = 0;
                    for (int r = 0; r < runs; r++)
                        s += est[r][l][n], s2 += est[r][l][n] * est[r][l][n];
                    const double mean = s / runs, var = (s2 - s * mean) / (runs - 1);
                    rel += mean > 0 ? var / (mean * mean) / NORMALS : 0.0;
                }
                lx[l] = log(16.0 * (1 << l));
                ly[l] = log(rel);
                if (16 << l == 1024) var1024[q] = rel;
            }
            /* least squares over N = 64 .. 4096 */
            double mx = 0, my = 0, sxy = 0, sxx = 0;
            for (int l = 2; l < LEVELS; l++) mx += lx[l] / (LEVELS - 2), my += ly[l] / (LEVELS - 2);
            for (int l = 2; l < LEVELS; l++)
                sxy += (lx[l] - mx) * (ly[l] - my), sxx += (lx[l] - mx) * (lx[l] - mx);
            const double slope = sxy / sxx;
            if (json)
                printf(", \"%s\": {\"slope\": %.4f, \"relvar_1024\": %.6g}", seq_names[q], slope,
                       var1024[q]);
            else
                printf("%-16s %-6s %8.2f %12.3g %12.3f\n", q ? "" : lumis_sampler_method_name(m),
                       seq_names[q], slope, var1024[q], var1024[q] / var1024[0]);
        }
        if (json) printf("}");
        lumis_sampler_destroy(smp);
    }
    if (json) printf("]}\n");
    free(pmj);
    free(est);
    lumis_envmap_destroy(env);
    return 0;
}
