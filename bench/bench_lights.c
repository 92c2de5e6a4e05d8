/* bench_lights: wall-clock time of building representative light sets on one core.
 *
 * usage: bench_lights [--size WxH] [--count K] [--runs N] [--sets S] [--map FILE]
 *                     [--methods A,B,...] [--json]
 *
 * Builds median cut, variance minimisation, Wu's decomposition (and its three
 * ablations), FHIS and TMMS N times each (default 11) on a WxH map (default 2048x1024: the
 * procedural sky, or FILE resized with lumis_equirect_resize) with K lights (default 64) and S sets
 * (default 8, the interleaved sets included), and prints the min and median milliseconds
 * of each.  The library is single-threaded, so one build runs on one core.  The first
 * run of each method is a warm-up and not counted (page faults of fresh tables). */
#include "bench_common.h"
#include "lumis/io.h"
#include "lumis/lumis.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

const char bench_name[] = "bench_lights";

static const char usage[] =
    "usage: bench_lights [--size WxH] [--count K] [--runs N] [--sets S] [--map FILE]\n"
    "                    [--methods A,B,...] [--json]\n\n"
    "Times the light-set methods of lumis/lights.h on one core.\n\n"
    "  --size WxH   map size (default 2048x1024)\n"
    "  --count K    lights per set (default 64)\n"
    "  --runs N     timed runs per method after one warm-up (default 11)\n"
    "  --sets S     light sets, interleaved copies included (default 8)\n"
    "  --map FILE   an equirectangular map, resized to WxH (default: the procedural sky)\n"
    "  --methods L  comma-separated subset of: median-cut, variance-min, wu, wu-is-only,\n"
    "               wu-is-mask, wu-is-kmeans, fhis, tmms (default: all)\n"
    "  --json       print one JSON object instead of text\n";

typedef struct method {
    const char *name;
    int kind; /* 0 median cut, 1 variance min, 2 decomposition, 3 FHIS, 4 TMMS */
    lumis_decomp_variant variant;
} method;

static lumis_status build(const method *m, const lumis_envmap *env, int k, int sets,
                          lumis_light_set **out)
{
    if (m->kind == 0 || m->kind == 1) {
        lumis_median_cut_desc d = {0};
        d.count = k;
        d.sets = sets;
        return m->kind == 0 ? lumis_lights_median_cut(env, &d, out)
                            : lumis_lights_variance_min(env, &d, out);
    }
    if (m->kind == 3) {
        lumis_fhis_desc d = {0};
        d.count = k;
        d.sets = sets;
        d.seed = 1;
        return lumis_lights_fhis(env, &d, out);
    }
    if (m->kind == 4) {
        lumis_tmms_desc d = {0};
        d.count = k;
        d.sets = sets;
        return lumis_lights_tmms(env, &d, out);
    }
    lumis_decomp_desc d = {0};
    d.count = k;
    d.sets = sets;
    d.seed = 1;
    d.variant = m->variant;
    return lumis_lights_decompose(env, &d, out);
}

/* CPU time of this thread in seconds: on a shared machine the wall clock also counts the
 * time other processes held the core; this does not. */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Whether `name` is one of the comma-separated names of `list` (NULL: all). */
static int listed(const char *list, const char *name)
{
    if (!list) return 1;
    size_t n = strlen(name);
    for (const char *p = list; *p;) {
        const char *e = strchr(p, ',');
        size_t len = e ? (size_t)(e - p) : strlen(p);
        if (len == n && !strncmp(p, name, n)) return 1;
        if (!e) break;
        p = e + 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    int w = 2048, h = 1024, k = 64, runs = 11, sets = 8, json = 0;
    const char *map = NULL, *only = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            fputs(usage, stdout);
            return 0;
        } else if (!strcmp(a, "--json")) {
            json = 1;
        } else if (!strcmp(a, "--size") && i + 1 < argc) {
            if (!bench_parse_size(argv[++i], &w, &h))
                return bench_usage_error("--size wants WxH, got '%s'", argv[i]);
        } else if (!strcmp(a, "--count") && i + 1 < argc) {
            if (!bench_parse_int(argv[++i], 1, 1 << 20, &k))
                return bench_usage_error("--count wants 1..1048576, got '%s'", argv[i]);
        } else if (!strcmp(a, "--runs") && i + 1 < argc) {
            if (!bench_parse_int(argv[++i], 1, 1000, &runs))
                return bench_usage_error("--runs wants 1..1000, got '%s'", argv[i]);
        } else if (!strcmp(a, "--sets") && i + 1 < argc) {
            if (!bench_parse_int(argv[++i], 1, 64, &sets))
                return bench_usage_error("--sets wants 1..64, got '%s'", argv[i]);
        } else if (!strcmp(a, "--map") && i + 1 < argc) {
            map = argv[++i];
        } else if (!strcmp(a, "--methods") && i + 1 < argc) {
            only = argv[++i];
        } else {
            return bench_usage_error("unknown or incomplete option '%s'", a);
        }
    }

    lumis_envmap *env = NULL;
    if (bench_load_map(map, w, h, &env) != 0) return 1;
    lumis_status st;

    static const method methods[] = {
        {"median-cut", 0, LUMIS_DECOMP_DEFAULT},
        {"variance-min", 1, LUMIS_DECOMP_DEFAULT},
        {"wu", 2, LUMIS_DECOMP_FULL},
        {"wu-is-only", 2, LUMIS_DECOMP_IS_ONLY},
        {"wu-is-mask", 2, LUMIS_DECOMP_IS_MASK},
        {"wu-is-kmeans", 2, LUMIS_DECOMP_IS_KMEANS},
        {"fhis", 3, LUMIS_DECOMP_DEFAULT},
        {"tmms", 4, LUMIS_DECOMP_DEFAULT},
    };
    const int nm = (int)(sizeof methods / sizeof methods[0]);
    if (only) { /* every listed name must be a method */
        for (const char *p = only; *p;) {
            const char *e = strchr(p, ',');
            size_t len = e ? (size_t)(e - p) : strlen(p);
            int known = 0;
            for (int mi = 0; mi < nm; mi++)
                known |= strlen(methods[mi].name) == len && !strncmp(p, methods[mi].name, len);
            if (!known) return bench_usage_error("--methods: unknown method in '%s'", only);
            if (!e) break;
            p = e + 1;
        }
    }
    double *t = malloc((size_t)runs * sizeof *t), *tc = malloc((size_t)runs * sizeof *tc);
    if (!t || !tc) return bench_fail("out of memory");
    char cpu[256];
    bench_cpu_model(cpu, sizeof cpu);
    if (json)
        printf("{\"bench\":\"lights\",\"size\":\"%dx%d\",\"count\":%d,\"sets\":%d,\"runs\":%d,"
               "\"map\":\"%s\",\"cpu\":\"%s\",\"methods\":[",
               w, h, k, sets, runs, map ? map : "sky", cpu);
    else
        printf("light sets, %dx%d %s, K = %d, %d sets, %d runs after a warm-up, one core (%s)\n", w,
               h, map ? map : "procedural sky", k, sets, runs, cpu);
    int rc = 0;
    int printed = 0;
    for (int mi = 0; mi < nm && rc == 0; mi++) {
        if (!listed(only, methods[mi].name)) continue;
        lumis_light_set *set = NULL;
        lumis_light_set_info info;
        memset(&info, 0, sizeof info);
        for (int r = -1; r < runs; r++) {
            double t0 = bench_now(), c0 = cpu_now();
            st = build(&methods[mi], env, k, sets, &set);
            double dt = (bench_now() - t0) * 1e3, dc = (cpu_now() - c0) * 1e3;
            if (st != LUMIS_OK) {
                rc = bench_fail("%s: %s", methods[mi].name, lumis_status_string(st));
                break;
            }
            if (r >= 0) {
                t[r] = dt;
                tc[r] = dc;
            }
            info = *lumis_light_set_get_info(set);
            lumis_light_set_destroy(set);
        }
        if (rc) break;
        qsort(t, (size_t)runs, sizeof *t, bench_cmp_double);
        double med = runs % 2 ? t[runs / 2] : 0.5 * (t[runs / 2 - 1] + t[runs / 2]);
        qsort(tc, (size_t)runs, sizeof *tc, bench_cmp_double);
        double cmed = runs % 2 ? tc[runs / 2] : 0.5 * (tc[runs / 2 - 1] + tc[runs / 2]);
        if (json)
            printf("%s{\"method\":\"%s\",\"median_ms\":%.4f,\"min_ms\":%.4f,\"max_ms\":%.4f,"
                   "\"cpu_median_ms\":%.4f,"
                   "\"lights\":%d,\"direct\":%d,\"emissive_pixels\":%d,\"kmeans_iterations\":%d}",
                   printed++ ? "," : "", methods[mi].name, med, t[0], t[runs - 1], cmed, info.count,
                   info.direct, info.emissive_pixels, info.kmeans_iterations);
        else
            printf("  %-13s median %8.3f ms   min %8.3f ms   max %8.3f ms   cpu median %8.3f ms   "
                   "lights %d (direct %d, emissive pixels %d, k-means steps %d)\n",
                   methods[mi].name, med, t[0], t[runs - 1], cmed, info.count, info.direct,
                   info.emissive_pixels, info.kmeans_iterations);
    }
    if (json && rc == 0) printf("]}\n");
    free(t);
    free(tc);
    lumis_envmap_destroy(env);
    return rc;
}
