/* lumis bench-samplers MAP... [--json]: for each map and method, build time, table bytes,
 * compression against inversion, samples per second on one core (scalar and batched,
 * medians of several runs), and the relative standard error at 64 samples of the
 * irradiance E(n) = integral of Y(w) max(0, n.w) dw averaged over 16 fixed normals,
 * computed by quadrature over the pixels (Var = int f^2/p - E^2), not by sampling. */
#include "cli.h"

#include <cJSON.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { NNORMALS = 16, SPP = 64 };

/* The quadrature both the reference and the variance use: every pixel at its centre
 * (the pdfs are constant per pixel, so only the cosine is approximated). */
typedef struct quad {
    int n;
    lumis_vec3 *dir;
    double *yw; /* Y * Omega */
    double *om; /* Omega */
} quad;

static void quad_free(quad *q)
{
    free(q->dir);
    free(q->yw);
    free(q->om);
}

static int quad_build(const lumis_envmap *env, quad *q)
{
    int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    q->n = 0;
    q->dir = malloc(sizeof(lumis_vec3) * (size_t)w * (size_t)h);
    q->yw = malloc(sizeof(double) * (size_t)w * (size_t)h);
    q->om = malloc(sizeof(double) * (size_t)w * (size_t)h);
    if (!q->dir || !q->yw || !q->om) return 0;
    for (int j = 0; j < h; j++) {
        double c0 = cos(3.14159265358979 * j / h), c1 = cos(3.14159265358979 * (j + 1) / h);
        float v = (float)(acos(0.5 * (c0 + c1)) / 3.14159265358979);
        double om = lumis_envmap_pixel_solid_angle(env, j);
        for (int i = 0; i < w; i++) {
            double y = lumis_luminance(lumis_envmap_texel(env, i, j));
            if (y == 0.0) continue;
            q->dir[q->n] = lumis_envmap_uv_to_dir(env, (float)((i + 0.5) / w), v);
            q->om[q->n] = om;
            q->yw[q->n++] = y * om;
        }
    }
    return 1;
}

static void fibonacci_normals(lumis_vec3 *normals)
{
    for (int k = 0; k < NNORMALS; k++) {
        double z = 1.0 - (2.0 * k + 1.0) / NNORMALS, r = sqrt(1.0 - z * z),
               phi = k * 2.399963229728653;
        normals[k] = (lumis_vec3){(float)(r * cos(phi)), (float)z, (float)(r * sin(phi))};
    }
}

/* Relative standard error of the 64-sample estimator of E(n), exactly (no sampling):
 * Var = int f^2 / p dw - E^2 with f = Y max(0, n.w), by the quadrature above.  Rare
 * events (a uniform sampler hitting a sun) count with their true weight. */
static double rel_stderr_64(const lumis_sampler *s, const quad *q, const lumis_vec3 *normals)
{
    double E[NNORMALS] = {0}, M2[NNORMALS] = {0};
    for (int p = 0; p < q->n; p++) {
        double pdf = lumis_sampler_pdf(s, q->dir[p]);
        for (int k = 0; k < NNORMALS; k++) {
            double c = q->dir[p].x * normals[k].x + q->dir[p].y * normals[k].y +
                       q->dir[p].z * normals[k].z;
            if (c <= 0.0) continue;
            double fw = q->yw[p] * c; /* f Omega */
            E[k] += fw;
            if (pdf > 0.0)
                M2[k] += fw * fw / (pdf * q->om[p]);
            else
                M2[k] = INFINITY; /* light the sampler can never reach: biased */
        }
    }
    double acc = 0.0;
    int used = 0;
    for (int k = 0; k < NNORMALS; k++) {
        if (!(E[k] > 0.0)) continue;
        acc += sqrt(fmax(M2[k] - E[k] * E[k], 0.0) / SPP) / E[k];
        used++;
    }
    return used ? acc / used : 0.0;
}

typedef struct result {
    double build_ms, sps, batch_sps, rse;
    size_t bytes, total_bytes;
    int blocks;
    double alpha;
} result;

static int bench_one(const lumis_envmap *env, lumis_sampler_desc d, int runs, long nsamples,
                     const double *u, lumis_env_sample *out, const quad *q,
                     const lumis_vec3 *normals, result *r)
{
    double *t = malloc(sizeof(double) * (size_t)runs);
    lumis_sampler *s = NULL;
    for (int k = 0; k < runs; k++) {
        lumis_sampler_destroy(s);
        s = NULL;
        d.errors = tool_errors;
        if (lumis_sampler_create(env, &d, &s) != LUMIS_OK) {
            free(t);
            return EXIT_RUNTIME;
        }
        t[k] = lumis_sampler_build_ms(s);
    }
    r->build_ms = tool_median(t, runs);
    r->bytes = lumis_sampler_table_bytes(s);
    r->total_bytes = lumis_sampler_total_bytes(s);
    r->blocks = lumis_sampler_kdtree_blocks(s);
    r->alpha = lumis_sampler_kdtree_alpha(s);
    volatile float sink = 0.0f;
    for (int k = 0; k < runs; k++) {
        double t0 = tool_now_seconds();
        float acc = 0.0f;
        for (long q = 0; q < nsamples; q++)
            acc += lumis_sampler_sample(s, u[2 * q], u[2 * q + 1]).pdf;
        t[k] = (double)nsamples / (tool_now_seconds() - t0);
        sink += acc;
    }
    r->sps = tool_median(t, runs);
    for (int k = 0; k < runs; k++) {
        double t0 = tool_now_seconds();
        lumis_sampler_sample_n(s, u, (size_t)nsamples, out);
        t[k] = (double)nsamples / (tool_now_seconds() - t0);
        sink += out[nsamples - 1].pdf;
    }
    (void)sink;
    r->batch_sps = tool_median(t, runs);
    r->rse = rel_stderr_64(s, q, normals);
    lumis_sampler_destroy(s);
    free(t);
    return EXIT_OK;
}

/* rel_stderr_64 of the stratified estimator: 64 / K draws in each of the K regions, each
 * region's variance int_R f^2 / p_R - (int_R f)^2 summed (strata are independent). */
static double strata_rel_stderr_64(const lumis_region_sampler *rs, const quad *q,
                                   const lumis_vec3 *normals)
{
    const int K = lumis_region_sampler_count(rs);
    double *E = calloc((size_t)K * NNORMALS, sizeof(double)),
           *M2 = calloc((size_t)K * NNORMALS, sizeof(double));
    if (!E || !M2) {
        free(E);
        free(M2);
        return NAN;
    }
    for (int p = 0; p < q->n; p++) {
        int r = -1;
        const double pdf = lumis_region_sampler_lookup(rs, q->dir[p], &r, NULL);
        if (r < 0) continue;
        for (int k = 0; k < NNORMALS; k++) {
            double c = q->dir[p].x * normals[k].x + q->dir[p].y * normals[k].y +
                       q->dir[p].z * normals[k].z;
            if (c <= 0.0) continue;
            double fw = q->yw[p] * c;
            E[(size_t)r * NNORMALS + (size_t)k] += fw;
            M2[(size_t)r * NNORMALS + (size_t)k] +=
                pdf > 0.0 ? fw * fw / (pdf * q->om[p]) : INFINITY;
        }
    }
    double acc = 0.0;
    int used = 0;
    for (int k = 0; k < NNORMALS; k++) {
        double e = 0.0, var = 0.0;
        for (int r = 0; r < K; r++) {
            const double er = E[(size_t)r * NNORMALS + (size_t)k];
            e += er;
            var += fmax(M2[(size_t)r * NNORMALS + (size_t)k] - er * er, 0.0);
        }
        if (!(e > 0.0)) continue;
        acc += sqrt(var * K / SPP) / e;
        used++;
    }
    free(E);
    free(M2);
    return used ? acc / used : 0.0;
}

/* The region samplers of light-set method `method` with K regions, timed as bench_one
 * times a sampler: draw q goes to region q mod K. */
static int bench_strata(const lumis_envmap *env, const char *method, int K, int runs, long nsamples,
                        const double *u, lumis_env_sample *out, const quad *q,
                        const lumis_vec3 *normals, result *r)
{
    double *t = malloc(sizeof(double) * (size_t)runs);
    int *regions = malloc(sizeof(int) * (size_t)nsamples);
    lumis_light_set *set = NULL;
    lumis_region_sampler *rs = NULL;
    int rc = EXIT_RUNTIME;
    if (!t || !regions) goto done;
    for (int k = 0; k < runs; k++) {
        lumis_region_sampler_destroy(rs);
        lumis_light_set_destroy(set);
        rs = NULL;
        if (lumis_lights_by_name(env, method, K, 1, NULL, &tool_errors, &set) != LUMIS_OK ||
            lumis_region_sampler_create(env, set, &tool_errors, &rs) != LUMIS_OK)
            goto done;
        t[k] = lumis_light_set_get_info(set)->build_ms + lumis_region_sampler_build_ms(rs);
    }
    r->build_ms = tool_median(t, runs);
    r->bytes = r->total_bytes = lumis_region_sampler_bytes(rs);
    r->blocks = lumis_region_sampler_count(rs);
    r->alpha = 0.0;
    const int n = lumis_region_sampler_count(rs);
    for (long k = 0; k < nsamples; k++) regions[k] = (int)(k % n);
    volatile float sink = 0.0f;
    for (int k = 0; k < runs; k++) {
        double t0 = tool_now_seconds();
        float acc = 0.0f;
        for (long s = 0; s < nsamples; s++)
            acc += lumis_region_sampler_sample(rs, regions[s], u[2 * s], u[2 * s + 1]).pdf;
        t[k] = (double)nsamples / (tool_now_seconds() - t0);
        sink += acc;
    }
    r->sps = tool_median(t, runs);
    for (int k = 0; k < runs; k++) {
        double t0 = tool_now_seconds();
        lumis_region_sampler_sample_n(rs, regions, u, (size_t)nsamples, out);
        t[k] = (double)nsamples / (tool_now_seconds() - t0);
        sink += out[nsamples - 1].pdf;
    }
    (void)sink;
    r->batch_sps = tool_median(t, runs);
    r->rse = strata_rel_stderr_64(rs, q, normals);
    rc = isnan(r->rse) ? tool_runtime_error("bench-samplers: out of memory") : EXIT_OK;
done:
    lumis_region_sampler_destroy(rs);
    lumis_light_set_destroy(set);
    free(regions);
    free(t);
    return rc;
}

/* The widths of the table's map and method columns (the longest name given). */
static int map_w = 3, method_w = 13;

/* A map's rows, for its verdict. */
typedef struct verdict_row {
    char name[64];
    double rse, sps;
} verdict_row;
static verdict_row vrows[64];
static int nvrows;

/* One row: a JSON object added to arr, or (arr NULL) a line of the table.  count_key names
 * the result's blocks (the kd-tree's) or regions (the strata's); a method without tables
 * (uniform) has no compression to speak of. */
static void report_row(cJSON *arr, const char *map, const char *name, const char *variant,
                       const result *r, size_t inv_bytes, const char *count_key)
{
    if (nvrows < 64) {
        verdict_row *v = &vrows[nvrows++];
        snprintf(v->name, sizeof v->name, "%s%s", name, *variant ? "-angles" : "");
        v->rse = r->rse;
        v->sps = r->sps;
    }
    const double comp = r->bytes ? (double)inv_bytes / (double)r->bytes : 0.0;
    if (arr) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "map", map);
        cJSON_AddStringToObject(o, "method", name);
        cJSON_AddStringToObject(o, "variant", variant);
        cJSON_AddNumberToObject(o, "build_ms", r->build_ms);
        cJSON_AddNumberToObject(o, "bytes", (double)r->bytes);
        cJSON_AddNumberToObject(o, "total_bytes", (double)r->total_bytes);
        if (r->bytes)
            cJSON_AddNumberToObject(o, "compression_vs_inversion", comp);
        else
            cJSON_AddNullToObject(o, "compression_vs_inversion");
        cJSON_AddNumberToObject(o, "samples_per_second", r->sps);
        cJSON_AddNumberToObject(o, "batch_samples_per_second", r->batch_sps);
        cJSON_AddNumberToObject(o, "rel_stderr_64", r->rse);
        cJSON_AddNumberToObject(o, count_key, r->blocks);
        if (strcmp(count_key, "blocks") == 0) cJSON_AddNumberToObject(o, "alpha", r->alpha);
        cJSON_AddItemToArray(arr, o);
        return;
    }
    char comp_text[32];
    snprintf(comp_text, sizeof comp_text, r->bytes ? "%.1f" : "-", comp);
    printf("%-*s %-*s %9.2f %11zu %8s %12.4g %12.4g %13.4f\n", map_w, map, method_w,
           vrows[nvrows - 1].name, r->build_ms, r->bytes, comp_text, r->sps, r->batch_sps, r->rse);
    fflush(stdout);
}

/* The best of a map's rows by key (0: rel_stderr_64; 1: rel_stderr_64^2 / samples per
 * second), the runner-up, and the runner-up's ratio to the best. */
static double verdict_cost(const verdict_row *v, int key)
{
    return key == 0 ? v->rse : v->sps > 0.0 ? v->rse * v->rse / v->sps : INFINITY;
}

static void print_verdict(void)
{
    if (nvrows < 2) return;
    char text[2][256];
    for (int key = 0; key < 2; key++) {
        int best = 0, next = -1;
        for (int k = 1; k < nvrows; k++)
            if (verdict_cost(&vrows[k], key) < verdict_cost(&vrows[best], key)) best = k;
        for (int k = 0; k < nvrows; k++)
            if (k != best &&
                (next < 0 || verdict_cost(&vrows[k], key) < verdict_cost(&vrows[next], key)))
                next = k;
        const double b = verdict_cost(&vrows[best], key), n = verdict_cost(&vrows[next], key);
        /* per second: the ratio of the times to equal error */
        if (b > 0.0)
            snprintf(text[key], sizeof text[key], "%.63s, %.63s next with %.3gx", vrows[best].name,
                     vrows[next].name, n / b);
        else
            snprintf(text[key], sizeof text[key], "%.63s (error 0)", vrows[best].name);
    }
    printf("verdict (lower is better): lowest error at 64 samples: %s the error; lowest error "
           "per second of sampling: %s the time to equal error\n",
           text[0], text[1]);
}

/* What bench-samplers is asked: the maps, the methods and the light sets' strata. */
typedef struct samplers_opts {
    const char *maps[64];
    int nmaps, json, runs, blocks;
    long nsamples;
    lumis_sampler_method methods[LUMIS_METHOD_COUNT];
    int nmethods, methods_given, strata_k, nstrata;
    char strata_buf[256]; /* what strata point into */
    const char *strata[16];
} samplers_opts;

static int strata_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    samplers_opts *o = ctx;
    snprintf(o->strata_buf, sizeof o->strata_buf, "%s", v ? v : "");
    for (char *tok = strtok(o->strata_buf, ","); tok; tok = strtok(NULL, ",")) {
        if (o->nstrata == 16 || !tool_lights_method_known(tok))
            return tool_usage_error(cmd, "%s: unknown light-set method '%s' (%s)", opt->name, tok,
                                    tool_lights_method_names());
        o->strata[o->nstrata++] = tok;
    }
    if (!o->nstrata) return tool_usage_error(cmd, "%s needs a list", opt->name);
    return EXIT_OK;
}

static int methods_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    samplers_opts *o = ctx;
    char buf[256];
    snprintf(buf, sizeof buf, "%s", v ? v : "");
    for (char *tok = strtok(buf, ","); tok; tok = strtok(NULL, ",")) {
        if (o->nmethods == LUMIS_METHOD_COUNT ||
            lumis_sampler_method_from_name(tok, &o->methods[o->nmethods]) != LUMIS_OK)
            return tool_usage_error(cmd, "unknown method '%s' in %s", tok, opt->name);
        o->nmethods++;
    }
    if (!o->nmethods) return tool_usage_error(cmd, "%s needs a list", opt->name);
    return EXIT_OK;
}

static int samplers_positional(const char *cmd, const char *arg, void *ctx)
{
    (void)cmd;
    samplers_opts *o = ctx;
    if (o->nmaps < 64) o->maps[o->nmaps++] = arg;
    return EXIT_OK;
}

#define AT(f) offsetof(samplers_opts, f)
static const tool_opt samplers_table[] = {
    {.kind = TOOL_OPT_FLAG,
     .name = "--json",
     .help = "print a JSON array of objects (map, method, variant, build_ms, bytes,\n"
             "total_bytes, compression_vs_inversion (null without tables),\n"
             "samples_per_second, batch_samples_per_second, rel_stderr_64, blocks, alpha)",
     .at = AT(json)},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--methods",
     .metavar = "LIST",
     .help = "comma-separated (default: all seven)",
     .handle = methods_option},
    {.kind = TOOL_OPT_LONG,
     .name = "--samples",
     .metavar = "N",
     .help = "samples per timing run (default 1000000)",
     .at = AT(nsamples),
     .lo = 1,
     .hi = 100000000},
    {.kind = TOOL_OPT_INT,
     .name = "--runs",
     .metavar = "R",
     .help = "timing runs and builds; medians are reported (default 5)",
     .at = AT(runs),
     .lo = 1,
     .hi = 101},
    {.kind = TOOL_OPT_INT,
     .name = "--blocks",
     .metavar = "K",
     .help = "kd-tree blocks (default 6144)",
     .at = AT(blocks),
     .lo = 1,
     .hi = 1 << 24},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--strata",
     .metavar = "LIST",
     .help = "also the light sets' region samplers (the stratified mode of lumis\n"
             "render --lights-mode stratified) of these light-set methods\n"
             "(comma-separated, e.g. median-cut,wu), as method strata:NAME: build\n"
             "= the light set's and the region samplers', a sample = a direction\n"
             "drawn in one region (the regions in turn, as a render draws one in\n"
             "each), rel_stderr_64 of 64 / K draws in every region",
     .handle = strata_option},
    {.kind = TOOL_OPT_INT,
     .name = "--strata-k",
     .metavar = "K",
     .help = "regions of those light sets (default 32, as lumis render)",
     .at = AT(strata_k),
     .lo = 1,
     .hi = 65536},
    {0},
};

const tool_optspec tool_bench_samplers_spec = {
    .cmd = "bench-samplers",
    .usage = "usage: lumis bench-samplers MAP... [options]",
    .intro =
        "MAP: an image file or sky:WxH / studio:WxH (any size, e.g. sky:8192x4096).\n"
        "For every map and method: build time (median of --runs builds), table bytes and\n"
        "compression against inversion's tables, samples per second on one core for the\n"
        "scalar sample() loop and for sample_n() (medians of --runs runs of --samples), and\n"
        "rel_stderr_64: the standard deviation of a 64-sample estimate of the irradiance\n"
        "E(n) = int Y(w) max(0, n.w) dw over its value, averaged over 16 normals, computed\n"
        "exactly by summing f^2/p and f over every pixel (at its centre), not by sampling.\n\n"
        "Without --methods, the kd-tree is also run as the paper's literal variant (uniform in\n"
        "angles inside a block), reported as method kdtree with variant \"uniform-angles\"\n"
        "(the row \"kdtree-angles\").\n\n"
        "After each map's rows, a verdict: which method has the lowest rel_stderr_64 (lower\n"
        "is better: the error of 64 samples) and by how much, and which is best per second\n"
        "of sampling (rel_stderr_64^2 / samples per second: the error at equal sampling time;\n"
        "a render spends most of its time elsewhere, docs/results/ergun2012).  To compare two\n"
        "samplers on your map: lumis bench-samplers MAP --methods inversion,kdtree",
    .opts = samplers_table,
    .positional = samplers_positional,
};

/* The options into *o (*help: --help was given, the usage printed).  Exit code. */
static int parse_samplers_args(int argc, char **argv, samplers_opts *o, int *help)
{
    const int rc = tool_optparse(&tool_bench_samplers_spec, argc, argv, o);
    if (rc >= 0) {
        *help = rc == EXIT_OK;
        return rc;
    }
    if (!o->nmaps) return tool_usage_error("bench-samplers", "no map given");
    o->methods_given = o->nmethods > 0;
    if (!o->nmethods)
        for (int m = LUMIS_METHOD_INVERSION; m < LUMIS_METHOD_COUNT; m++)
            o->methods[o->nmethods++] = (lumis_sampler_method)m;
    return EXIT_OK;
}

/* One map's rows (the table's header before the first: *header) and its verdict; u and
 * out: the samples' numbers and storage. */
static int bench_map(const samplers_opts *o, const char *map, const double *u,
                     lumis_env_sample *out, cJSON *arr, int *header)
{
    lumis_image *img = NULL;
    if (tool_load_image(map, &img, NULL) != LUMIS_OK) return EXIT_RUNTIME;
    if (!o->json && !(*header)++) /* after the first map loads: no header before an error */
        printf("%-*s %-*s %9s %11s %8s %12s %12s %13s\n", map_w, "map", method_w, "method",
               "build_ms", "bytes", "compress", "samples/s", "batch/s", "rel_stderr_64");
    nvrows = 0;
    lumis_envmap *env = NULL;
    lumis_envmap_from_image(img, &env);
    lumis_image_destroy(img);
    lumis_vec3 normals[NNORMALS];
    fibonacci_normals(normals);
    quad q;
    if (!quad_build(env, &q)) {
        quad_free(&q);
        lumis_envmap_destroy(env);
        return tool_runtime_error("out of memory");
    }
    /* Inversion's tables: the yardstick of the paper's compression ratio. */
    size_t inv_bytes = 4 * ((size_t)lumis_envmap_width(env) * (size_t)lumis_envmap_height(env) +
                            (size_t)lumis_envmap_height(env));
    int rc = EXIT_OK;
    /* The light sets' region samplers asked for (--strata). */
    for (int k = 0; k < o->nstrata && rc == EXIT_OK; k++) {
        result r;
        rc = bench_strata(env, o->strata[k], o->strata_k, o->runs, o->nsamples, u, out, &q, normals,
                          &r);
        if (rc != EXIT_OK) break;
        char name[64];
        snprintf(name, sizeof name, "strata:%s", o->strata[k]);
        report_row(arr, map, name, "", &r, inv_bytes, "regions");
    }
    /* Every method, and after kdtree its literal variant (uniform in angles) when no
     * --methods were given. */
    for (int k = 0, variant = 0; k < o->nmethods && rc == EXIT_OK; k += variant ? 0 : 1) {
        lumis_sampler_desc d = {0};
        d.method = o->methods[k];
        d.kdtree_blocks = o->blocks;
        d.kdtree_uniform_angles = variant;
        result r;
        rc = bench_one(env, d, o->runs, o->nsamples, u, out, &q, normals, &r);
        if (rc != EXIT_OK) break;
        report_row(arr, map, lumis_sampler_method_name(o->methods[k]),
                   variant ? "uniform-angles" : "", &r, inv_bytes, "blocks");
        variant = o->methods[k] == LUMIS_METHOD_KDTREE && !variant && !o->methods_given;
    }
    if (!o->json && rc == EXIT_OK) print_verdict();
    quad_free(&q);
    lumis_envmap_destroy(env);
    return rc;
}

int cmd_bench_samplers(int argc, char **argv)
{
    samplers_opts o = {.runs = 5, .nsamples = 1000000, .strata_k = 32};
    int help = 0;
    int rc = parse_samplers_args(argc, argv, &o, &help);
    if (rc != EXIT_OK || help) return rc;
    const long nsamples = o.nsamples;
    double *u = malloc(sizeof(double) * 2 * (size_t)nsamples);
    lumis_env_sample *out = malloc(sizeof(lumis_env_sample) * (size_t)nsamples);
    if (!u || !out) return tool_runtime_error("out of memory for %ld samples", nsamples);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 7, 7);
    for (long q = 0; q < 2 * nsamples; q++) u[q] = lumis_pcg32_double(&rng);

    cJSON *arr = o.json ? cJSON_CreateArray() : NULL;
    for (int mi = 0; mi < o.nmaps; mi++)
        if ((int)strlen(o.maps[mi]) > map_w) map_w = (int)strlen(o.maps[mi]);
    for (int k = 0; k < o.nstrata; k++)
        if ((int)strlen(o.strata[k]) + 7 > method_w) method_w = (int)strlen(o.strata[k]) + 7;
    int header = 0;
    for (int mi = 0; mi < o.nmaps && rc == EXIT_OK; mi++)
        rc = bench_map(&o, o.maps[mi], u, out, arr, &header);
    if (o.json && rc == EXIT_OK) {
        char *text = cJSON_Print(arr);
        if (text) printf("%s\n", text);
        cJSON_free(text);
    }
    cJSON_Delete(arr);
    free(u);
    free(out);
    return rc;
}
