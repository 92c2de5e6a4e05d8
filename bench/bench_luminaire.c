/* bench_luminaire: position-dependent sampling of light-field luminaires (Lu et al. 2015)
 * on one core.
 *
 * usage: bench_luminaire [--preset car|bike|small] [--points N] [--budget K] [--runs R]
 *                        [--trials T] [--json]
 *
 * Builds the preset's synthetic luminaire (lumis_luminaire_acquire: 11 x 9 images of
 * 256 x 256 for car, Table 1 of the paper), then reports
 *   1. speed: nanoseconds per restricted sample of lumis_luminaire_sample_point (box
 *      projection, A_m(p), K_m(p) and the 2D inversions, amortised over the K samples of a
 *      point) for the secant and the binary search, the random numbers drawn beforehand
 *      (PCG32) so only the sampler is timed; thread CPU time, median of R.  Two orders of N points:
 * a wall at z = 3 delta shaded in raster order, as a renderer's pixels come (neighbouring points
 * read neighbouring table entries), and random points in the beam (every point's lookups miss the
 * caches: the worst case);
 *   2. search depth (Fig. 5): the mean distance, in pixels, between the sample a depth-
 *      limited search gives and the exact one, per depth, secant against binary;
 *   3. quality (Fig. 8, 11, 12): the relative RMS error of the irradiance estimate at a few
 *      points against quadrature, for the restricted, uniform and global strategies with
 *      PCG32 and Halton numbers, over T independent estimates of K samples. */
#include "bench_common.h"
#include "lumis/lumis.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

const char bench_name[] = "bench_luminaire";

/* CPU seconds of this thread: on a shared machine, time slices given to other processes
 * do not count (wall-clock time would). */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static const char usage[] =
    "usage: bench_luminaire [--preset car|bike|small] [--points N] [--budget K] [--runs R]\n"
    "                       [--trials T] [--json]\n\n"
    "Times and measures the luminaire samplers of lumis/luminaire.h on one core.\n\n"
    "  --preset P   car (11x9 images of 256x256, default), bike (9x7 of 300x300), small\n"
    "  --points N   random shading points for the speed test (default 20000)\n"
    "  --budget K   samples per point (default 64)\n"
    "  --runs R     timed runs, the median reported (default 5)\n"
    "  --trials T   estimates per point for the quality test (default 400)\n"
    "  --json       print one JSON object instead of text\n";

static double luma(lumis_rgb c)
{
    return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

/* Point k of N on a wall at z = 3 delta, x and y within 0.3 z of the axis, in raster
 * order (rows of 2 sqrt(N) points). */
static lumis_vec3 wall_point(int k, int n, double delta)
{
    const int cols = (int)ceil(sqrt(2.0 * n)), rows = (n + cols - 1) / cols;
    const double z = 3.0 * delta, e = 0.3 * z;
    lumis_vec3 p;
    p.x = (float)(-e + 2.0 * e * ((k % cols) + 0.5) / cols);
    p.y = (float)(-e + 2.0 * e * ((k / cols) + 0.5) / rows);
    p.z = (float)z;
    return p;
}

/* A point in the beam: z in [1.5, 10] delta, x and y within 0.3 z of the axis. */
static lumis_vec3 beam_point(lumis_pcg32 *rng, double delta)
{
    lumis_vec3 p;
    const double z = delta * (1.5 + 8.5 * lumis_pcg32_double(rng));
    p.x = (float)(0.3 * z * (2.0 * lumis_pcg32_double(rng) - 1.0));
    p.y = (float)(0.3 * z * (2.0 * lumis_pcg32_double(rng) - 1.0));
    p.z = (float)z;
    return p;
}

int main(int argc, char **argv)
{
    int points = 20000, budget = 64, runs = 5, trials = 400, json = 0;
    lumis_luminaire_preset preset = LUMIS_PRESET_CAR;
    const char *preset_name = "car";
    for (int i = 1; i < argc; i++) {
        const char *v = NULL;
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return 0;
        } else if (tool_option(argc, argv, &i, "--preset", &v)) {
            if (!v) return bench_usage_error("--preset needs a value");
            if (!strcmp(v, "car"))
                preset = LUMIS_PRESET_CAR;
            else if (!strcmp(v, "bike"))
                preset = LUMIS_PRESET_BIKE;
            else if (!strcmp(v, "small"))
                preset = LUMIS_PRESET_SMALL;
            else
                return bench_usage_error("unknown preset '%s'", v);
            preset_name = v;
        } else if (tool_option(argc, argv, &i, "--points", &v)) {
            if (!v || !bench_parse_int(v, 1, 10000000, &points))
                return bench_usage_error("--points needs 1..1e7");
        } else if (tool_option(argc, argv, &i, "--budget", &v)) {
            if (!v || !bench_parse_int(v, 1, 4096, &budget))
                return bench_usage_error("--budget needs 1..4096");
        } else if (tool_option(argc, argv, &i, "--runs", &v)) {
            if (!v || !bench_parse_int(v, 1, 101, &runs))
                return bench_usage_error("--runs needs 1..101");
        } else if (tool_option(argc, argv, &i, "--trials", &v)) {
            if (!v || !bench_parse_int(v, 2, 1000000, &trials))
                return bench_usage_error("--trials needs 2..1e6");
        } else if (!strcmp(argv[i], "--json")) {
            json = 1;
        } else {
            return bench_usage_error("unknown argument '%s'", argv[i]);
        }
    }

    lumis_luminaire_desc layout;
    lumis_emitter_desc em;
    lumis_emitter_disk disks[4];
    if (lumis_luminaire_preset_get(preset, &layout, &em, disks) != LUMIS_OK)
        return bench_fail("no preset");
    lumis_acquire_desc acq = {0};
    acq.samples_s = 1;
    lumis_luminaire *lum = NULL;
    double t0 = bench_now();
    if (lumis_luminaire_acquire(&layout, &em, &acq, &lum) != LUMIS_OK)
        return bench_fail("acquisition failed");
    const double acquire_s = bench_now() - t0;
    lumis_luminaire_info info;
    lumis_luminaire_get_info(lum, &info);
    char cpu[256];
    bench_cpu_model(cpu, sizeof cpu);

    /* ---- 1. speed ---- */
    const int cap = lumis_luminaire_capacity(lum, budget);
    lumis_luminaire_sample *out = malloc((size_t)cap * sizeof *out);
    lumis_vec3 *pts = malloc((size_t)points * sizeof *pts);
    const int pool = 1 << 16; /* random numbers reused cyclically: cache-resident */
    double *u = malloc(((size_t)pool + 2 * (size_t)cap) * sizeof(double));
    if (!out || !pts || !u) return bench_fail("out of memory");
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 2015, 1);
    for (int k = 0; k < points; k++) pts[k] = beam_point(&rng, info.delta);
    for (int k = 0; k < pool + 2 * cap; k++) u[k] = lumis_pcg32_double(&rng);
    lumis_vec3 *wall = malloc((size_t)points * sizeof *wall);
    if (!wall) return bench_fail("out of memory");
    for (int k = 0; k < points; k++) wall[k] = wall_point(k, points, info.delta);
    const lumis_luminaire_search searches[2] = {LUMIS_LUM_SECANT, LUMIS_LUM_BINARY};
    static const char *const orders[2] = {"wall", "beam"};
    double ns[2][2], per_point_ns[2][2], masses_ns[2];
    double *mass = malloc((size_t)info.images * sizeof(double));
    if (!mass) return bench_fail("out of memory");
    for (int o = 0; o < 2; o++) { /* the per-point part alone: A_m(p) for every image */
        const lumis_vec3 *set = o == 0 ? wall : pts;
        double best = 1e300;
        for (int r = 0; r < runs; r++) {
            double start = cpu_now(), acc = 0.0;
            for (int k = 0; k < points; k++) {
                lumis_luminaire_masses(lum, set[k], mass);
                acc += mass[k % info.images];
            }
            double el = cpu_now() - start;
            if (el < best) best = el;
            if (acc < 0.0) return 1;
        }
        masses_ns[o] = best * 1e9 / points;
    }
    long total_samples[2] = {0, 0};
    double *t = malloc((size_t)runs * sizeof(double));
    for (int o = 0; o < 2; o++)
        for (int si = 0; si < 2; si++) {
            const lumis_vec3 *set = o == 0 ? wall : pts;
            for (int pass = 0; pass < 2; pass++) { /* pass 1: K = 1, the per-point share */
                lumis_luminaire_query q = {0};
                q.budget = pass ? 1 : budget;
                q.search = searches[si];
                long samples = 0;
                for (int r = -1; r < runs; r++) { /* r = -1: warm-up */
                    samples = 0;
                    size_t off = 0;
                    double start = cpu_now();
                    for (int k = 0; k < points; k++) {
                        q.p = set[k];
                        int n = 0;
                        lumis_luminaire_sample_point(lum, &q, u + off, cap, out, &n);
                        samples += n;
                        off = (off + 2 * (size_t)n + 1) % (size_t)pool;
                    }
                    if (r >= 0) t[r] = cpu_now() - start;
                }
                qsort(t, (size_t)runs, sizeof(double), bench_cmp_double);
                if (pass == 0) {
                    ns[o][si] = t[runs / 2] * 1e9 / (double)samples;
                    total_samples[o] = samples;
                } else {
                    per_point_ns[o][si] = t[runs / 2] * 1e9 / points;
                }
            }
        }

    /* ---- 2. search depth ---- */
    enum { DEPTHS = 10 };
    double depth_err[2][DEPTHS];
    for (int si = 0; si < 2; si++)
        for (int d = 1; d <= DEPTHS; d++) {
            double err = 0.0;
            long cnt = 0;
            lumis_pcg32 r2;
            lumis_pcg32_seed(&r2, 7, 7);
            for (int k = 0; k < 2000; k++) {
                lumis_luminaire_query q = {0};
                q.p = pts[k % points];
                q.search = searches[si];
                const int m = (int)lumis_pcg32_bounded(&r2, (uint32_t)info.images);
                const double u1 = lumis_pcg32_double(&r2), u2 = lumis_pcg32_double(&r2);
                lumis_luminaire_sample a, b;
                if (lumis_luminaire_sample_image(lum, &q, m, u1, u2, &a) != LUMIS_OK) continue;
                q.depth = d;
                lumis_luminaire_sample_image(lum, &q, m, u1, u2, &b);
                err += hypot((a.s[0] - b.s[0]) / info.pixel[0], (a.s[1] - b.s[1]) / info.pixel[1]);
                cnt++;
            }
            depth_err[si][d - 1] = cnt ? err / cnt : 0.0;
        }

    /* ---- 3. quality ---- */
    const lumis_vec3 qp[3] = {
        {0.0f, 0.0f, (float)(1.5 * info.delta)},
        {(float)(0.4 * info.delta), (float)(-0.2 * info.delta), (float)(3.0 * info.delta)},
        {(float)(-1.0 * info.delta), (float)(0.5 * info.delta), (float)(8.0 * info.delta)}};
    const lumis_vec3 nrm = {0.0f, 0.0f, -1.0f};
    const lumis_luminaire_strategy strategies[3] = {LUMIS_LUM_RESTRICTED, LUMIS_LUM_UNIFORM,
                                                    LUMIS_LUM_GLOBAL};
    double rel_rmse[3][3][2], zero_frac[3][3];
    double refs[3];
    for (int pi = 0; pi < 3; pi++) {
        lumis_rgb ref;
        lumis_luminaire_irradiance(lum, qp[pi], nrm, 4, &ref);
        refs[pi] = luma(ref);
        for (int st = 0; st < 3; st++)
            for (int gen = 0; gen < 2; gen++) {
                lumis_luminaire_query q = {0};
                q.p = qp[pi];
                q.budget = budget;
                q.strategy = strategies[st];
                lumis_pcg32 r3;
                lumis_pcg32_seed(&r3, 11, (uint64_t)(pi * 8 + st));
                const uint64_t scramble = lumis_pcg32_next(&r3);
                double se = 0.0;
                long zero = 0, all = 0;
                for (int tr = 0; tr < trials; tr++) {
                    for (int k = 0; k < cap; k++) {
                        if (gen == 0) {
                            u[2 * k] = lumis_pcg32_double(&r3);
                            u[2 * k + 1] = lumis_pcg32_double(&r3);
                        } else { /* Halton (2, 3), one run of the sequence per trial */
                            const uint64_t idx = (uint64_t)tr * (uint64_t)cap + (uint64_t)k + 1;
                            u[2 * k] = lumis_halton(0, idx + scramble % 1024);
                            u[2 * k + 1] = lumis_halton(1, idx + scramble % 1024);
                        }
                    }
                    int n = 0;
                    lumis_luminaire_sample_point(lum, &q, u, cap, out, &n);
                    for (int k = 0; k < n; k++) zero += out[k].radiance.g == 0.0f, all++;
                    const double e = luma(lumis_luminaire_estimate(out, n, nrm)) - refs[pi];
                    se += e * e;
                }
                rel_rmse[pi][st][gen] = sqrt(se / trials) / refs[pi];
                zero_frac[pi][st] = all ? (double)zero / (double)all : 0.0;
            }
    }

    if (json) {
        printf("{\"preset\":\"%s\",\"cpu\":\"%s\",\"images\":%d,\"width\":%d,\"height\":%d,"
               "\"bytes\":%zu,\"acquire_s\":%.4g,\"budget\":%d,\"points\":%d,\"speed\":[",
               preset_name, cpu, info.images, info.width, info.height, info.bytes, acquire_s,
               budget, points);
        for (int o = 0; o < 2; o++)
            for (int si = 0; si < 2; si++)
                printf("%s{\"points\":\"%s\",\"search\":\"%s\",\"samples\":%ld,"
                       "\"ns_per_sample\":%.4g,\"ns_per_point_k1\":%.4g}",
                       o || si ? "," : "", orders[o], lumis_luminaire_search_name(searches[si]),
                       total_samples[o], ns[o][si], per_point_ns[o][si]);
        printf("],\"masses_ns_per_point\":{\"wall\":%.4g,\"beam\":%.4g},\"depth_error_px\":{",
               masses_ns[0], masses_ns[1]);
        for (int si = 0; si < 2; si++) {
            printf("%s\"%s\":[", si ? "," : "", lumis_luminaire_search_name(searches[si]));
            for (int d = 0; d < DEPTHS; d++) printf("%s%.4g", d ? "," : "", depth_err[si][d]);
            printf("]");
        }
        printf("},\"quality\":[");
        for (int pi = 0; pi < 3; pi++)
            for (int st = 0; st < 3; st++)
                printf("%s{\"point\":[%g,%g,%g],\"strategy\":\"%s\",\"reference\":%.6g,"
                       "\"rel_rmse_pcg\":%.4g,\"rel_rmse_halton\":%.4g,\"zero_samples\":%.4g}",
                       pi || st ? "," : "", qp[pi].x, qp[pi].y, qp[pi].z,
                       lumis_luminaire_strategy_name(strategies[st]), refs[pi], rel_rmse[pi][st][0],
                       rel_rmse[pi][st][1], zero_frac[pi][st]);
        printf("]}\n");
    } else {
        printf("luminaire %s: %d images of %dx%d, %.1f MB, acquired in %.2f s (%s)\n", preset_name,
               info.images, info.width, info.height, (double)info.bytes / 1048576.0, acquire_s,
               cpu);
        printf("speed, K = %d, %d points, median of %d runs:\n", budget, points, runs);
        for (int o = 0; o < 2; o++)
            for (int si = 0; si < 2; si++)
                printf("  %-5s %-7s %7.1f ns/sample  (%ld samples; %8.1f ns per point with K = "
                       "1)\n",
                       orders[o], lumis_luminaire_search_name(searches[si]), ns[o][si],
                       total_samples[o], per_point_ns[o][si]);
        printf("  A_m(p) of all %d images: %.1f ns per point on the wall, %.1f in the beam "
               "(best of %d)\n",
               info.images, masses_ns[0], masses_ns[1], runs);
        printf("search depth: mean distance to the exact sample, pixels\n  depth  ");
        for (int d = 1; d <= DEPTHS; d++) printf("%7d", d);
        for (int si = 0; si < 2; si++) {
            printf("\n  %-7s", lumis_luminaire_search_name(searches[si]));
            for (int d = 0; d < DEPTHS; d++) printf("%7.3f", depth_err[si][d]);
        }
        printf("\nquality: relative RMS error of I(p), K = %d, %d estimates (PCG32 / Halton), "
               "share of samples without energy\n",
               budget, trials);
        for (int pi = 0; pi < 3; pi++)
            for (int st = 0; st < 3; st++)
                printf("  p (%6.0f, %6.0f, %6.0f)  %-10s  %8.4f / %8.4f   %5.1f%%\n", qp[pi].x,
                       qp[pi].y, qp[pi].z, lumis_luminaire_strategy_name(strategies[st]),
                       rel_rmse[pi][st][0], rel_rmse[pi][st][1], 100.0 * zero_frac[pi][st]);
    }
    free(t);
    free(mass);
    free(wall);
    free(out);
    free(pts);
    free(u);
    lumis_luminaire_destroy(lum);
    return 0;
}
