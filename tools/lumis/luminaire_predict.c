/* lumis luminaire predict: which sampling strategy pays for a luminaire over a range of
 * distances (lumis_luminaire_predict), per distance band. */
#include "cli.h"

#include "lumis/luminaire.h"

#include <cJSON.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* "A,B" or "A" (then B = A), 0 < A <= B. */
static int parse_range(const char *v, double out[2])
{
    const int n = tool_parse_doubles(v, out, 2);
    if (n == 1) out[1] = out[0];
    return n > 0 && out[0] > 0.0 && out[1] >= out[0];
}

int tool_parse_costs(const char *v, lumis_luminaire_costs *out)
{
    double x[7];
    if (tool_parse_doubles(v, x, 7) != 7) return 0;
    for (int k = 0; k < 7; k++) /* the draws (3, 4, 5) > 0, the rest >= 0 */
        if (x[k] < 0.0 || ((k >= 3 && k <= 5) && !(x[k] > 0.0))) return 0;
    out->camera = x[0];
    out->image_restricted = x[1];
    out->image_uniform = x[2];
    out->restricted = x[3];
    out->uniform = x[4];
    out->global = x[5];
    out->ray = x[6];
    return 1;
}

static cJSON *strategy_json(const lumis_luminaire_strategy_prediction *s)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "samples", s->samples);
    cJSON_AddNumberToObject(o, "rays", s->rays);
    cJSON_AddNumberToObject(o, "variance", s->variance);
    cJSON_AddNumberToObject(o, "ns", s->ns);
    cJSON_AddNumberToObject(o, "time_ratio", s->time_ratio);
    cJSON_AddNumberToObject(o, "sample_ratio", s->sample_ratio);
    return o;
}

/* What luminaire predict is asked. */
typedef struct predict_opts {
    const char *file;
    double range[2];
    long budget, kmax, probes, pilot, bands, seed;
    int json;
    lumis_luminaire_costs costs;
} predict_opts;

static int parse_distance(const char *v, void *field)
{
    return parse_range(v, field);
}

static int parse_costs(const char *v, void *field)
{
    return tool_parse_costs(v, field);
}

static int predict_positional(const char *cmd, const char *arg, void *ctx)
{
    predict_opts *o = ctx;
    if (o->file) return tool_usage_error(cmd, "unknown argument '%s'", arg);
    o->file = arg;
    return EXIT_OK;
}

#define AT(f) offsetof(predict_opts, f)
static const tool_opt predict_table[] = {
    {.kind = TOOL_OPT_PARSE,
     .name = "--distance",
     .metavar = "A,B",
     .help = "in the luminaire's units (default 2 to 50 times its delta)",
     .at = AT(range),
     .parse = parse_distance,
     .what = "needs A,B with 0 < A <= B (luminaire units), or one distance"},
    {.kind = TOOL_OPT_LONG,
     .name = "--bands",
     .metavar = "N",
     .help = "split the range in N bands, evenly in log distance (default 1)",
     .at = AT(bands),
     .lo = 1,
     .hi = 64},
    {.kind = TOOL_OPT_LONG,
     .name = "--budget",
     .metavar = "K",
     .help = "samples per point, restricted and uniform (default 32)",
     .at = AT(budget),
     .lo = 1,
     .hi = 65536},
    {.kind = TOOL_OPT_LONG,
     .name = "--kmax",
     .metavar = "K",
     .help = "their cap per image (default 0: none)",
     .at = AT(kmax),
     .lo = 0,
     .hi = 65536},
    {.kind = TOOL_OPT_LONG,
     .name = "--probes",
     .metavar = "N",
     .help = "points per band (default 256)",
     .at = AT(probes),
     .lo = 1,
     .hi = 1 << 20},
    {.kind = TOOL_OPT_LONG,
     .name = "--pilot",
     .metavar = "P",
     .help = "pilot samples per image (default 16)",
     .at = AT(pilot),
     .lo = 1,
     .hi = 4096},
    {.kind = TOOL_OPT_LONG,
     .name = "--seed",
     .metavar = "S",
     .help = "the probes' seed",
     .at = AT(seed),
     .lo = 0,
     .hi = 2147483647.0,
     .what = "an integer"},
    {.kind = TOOL_OPT_PARSE,
     .name = "--costs",
     .metavar = "C,IR,IU,R,U,G,RAY",
     .help = "the cost model, ns: camera ray, per image (restricted, uniform), per\n"
             "draw (restricted, uniform, global), per shadow ray (default: measured\n"
             "on the headlight scene; docs/luminaire.md)",
     .at = AT(costs),
     .parse = parse_costs,
     .what = "needs " TOOL_COSTS_HELP},
    {.kind = TOOL_OPT_FLAG,
     .name = "--json",
     .help = "one JSON object: file, budget, k_max, probes, and per band: distance,\n"
             "probes_lit, energy_share, images_lit, best, and for restricted, uniform\n"
             "and global: samples, rays, variance, ns, time_ratio, sample_ratio",
     .at = AT(json)},
    {0},
};

const tool_optspec tool_luminaire_predict_spec = {
    .cmd = "luminaire predict",
    .usage = "usage: lumis luminaire predict LUMINAIRE [--distance A,B] [--bands N] [--budget K]\n"
             "                              [--kmax K] [--probes N] [--pilot P] [--seed S]\n"
             "                              [--costs C,IR,IU,R,U,G,RAY] [--json]",
    .intro = "Which sampling strategy pays (docs/luminaire.md, \"Which strategy pays\"): for\n"
             "points lit by the luminaire at distances A to B from it, facing it, the relative\n"
             "variance and the predicted time of restricted, uniform and global sampling, and how\n"
             "many times less time than global each needs for an equal error (xglob).",
    .opts = predict_table,
    .positional = predict_positional,
};

/* The options into *o.  Exit code; -1 after --help. */
static int parse_predict_args(int argc, char **argv, predict_opts *o)
{
    const int rc = tool_optparse(&tool_luminaire_predict_spec, argc - 1, argv + 1, o);
    if (rc >= 0) return rc == EXIT_OK ? -1 : rc; /* -1: --help printed */
    if (!o->file) return tool_usage_error("luminaire predict", "no luminaire given");
    return EXIT_OK;
}

/* One distance band's prediction: an object added to arr, or (arr NULL) a line of the
 * table. */
static void report_band(cJSON *arr, double d0, double d1, const lumis_luminaire_prediction *p)
{
    if (arr) {
        cJSON *o = cJSON_CreateObject();
        const double dd[2] = {d0, d1};
        cJSON_AddItemToObject(o, "distance", cJSON_CreateDoubleArray(dd, 2));
        cJSON_AddNumberToObject(o, "probes_lit", p->probes_lit);
        cJSON_AddNumberToObject(o, "energy_share", p->energy_share);
        cJSON_AddNumberToObject(o, "images_lit", p->images_lit);
        cJSON_AddItemToObject(o, "restricted", strategy_json(&p->restricted));
        cJSON_AddItemToObject(o, "uniform", strategy_json(&p->uniform));
        cJSON_AddItemToObject(o, "global", strategy_json(&p->global));
        cJSON_AddStringToObject(o, "best", lumis_luminaire_strategy_name(p->best));
        cJSON_AddItemToArray(arr, o);
    } else {
        printf("%7.4g - %-7.4g %5.2f%% %7d | %9.1f %8.0f %8.1fx | %9.1f %8.0f %8.1fx | "
               "%11.3g %8.0f | %s\n",
               d0, d1, 100.0 * p->energy_share, p->images_lit, p->restricted.samples,
               p->restricted.ns, p->restricted.time_ratio, p->uniform.samples, p->uniform.ns,
               p->uniform.time_ratio, p->global.variance, p->global.ns,
               p->probes_lit ? lumis_luminaire_strategy_name(p->best) : "(nothing lit)");
    }
}

/* The bands (geometric in distance), predicted and reported one by one; pr: storage for
 * o->probes probes. */
static int predict_bands(const predict_opts *o, const lumis_luminaire *lum,
                         lumis_luminaire_probe *pr, cJSON *arr)
{
    const double *range = o->range;
    for (int b = 0; b < o->bands; b++) {
        const double r = range[1] / range[0];
        const double d0 = range[0] * pow(r, (double)b / o->bands),
                     d1 = range[0] * pow(r, (double)(b + 1) / o->bands);
        lumis_luminaire_predict_desc d = {0};
        d.probes = pr;
        d.probe_count = (int)o->probes;
        d.budget = (int)o->budget;
        d.k_max = (int)o->kmax;
        d.pilot = (int)o->pilot;
        d.seed = (uint64_t)o->seed;
        d.costs = &o->costs;
        lumis_luminaire_prediction p;
        lumis_status st = lumis_luminaire_probes(lum, d0, d1, (uint64_t)o->seed + (uint64_t)b,
                                                 (int)o->probes, pr);
        if (st == LUMIS_OK) st = lumis_luminaire_predict(lum, &d, &p);
        if (st != LUMIS_OK)
            return tool_runtime_error("%s: prediction failed: %s", o->file,
                                      lumis_status_string(st));
        report_band(arr, d0, d1, &p);
    }
    return EXIT_OK;
}

/* The JSON document around the bands (it takes arr) on stdout. */
static int print_predict_json(const predict_opts *o, cJSON *arr)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "file", o->file);
    cJSON_AddNumberToObject(j, "budget", (double)o->budget);
    cJSON_AddNumberToObject(j, "k_max", (double)o->kmax);
    cJSON_AddNumberToObject(j, "probes", (double)o->probes);
    cJSON_AddItemToObject(j, "bands", arr);
    char *text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    int rc = EXIT_OK;
    if (text)
        puts(text);
    else
        rc = tool_runtime_error("out of memory");
    free(text);
    return rc;
}

int tool_luminaire_predict(int argc, char **argv)
{
    predict_opts o = {.budget = 32, .probes = 256, .pilot = 16, .bands = 1, .seed = 1};
    o.costs = lumis_luminaire_costs_default();
    int rc = parse_predict_args(argc, argv, &o);
    if (rc != EXIT_OK) return rc < 0 ? EXIT_OK : rc;
    lumis_luminaire *lum = NULL;
    if (tool_load_luminaire(o.file, &lum) != LUMIS_OK) return EXIT_RUNTIME;
    lumis_luminaire_info in;
    lumis_luminaire_get_info(lum, &in);
    if (o.range[0] == 0.0) { /* default: 2 to 50 times the distance between the planes */
        o.range[0] = 2.0 * in.delta;
        o.range[1] = 50.0 * in.delta;
    }
    lumis_luminaire_probe *pr = malloc(sizeof *pr * (size_t)o.probes);
    cJSON *arr = o.json ? cJSON_CreateArray() : NULL;
    if (!pr || (o.json && !arr)) {
        free(pr);
        cJSON_Delete(arr);
        lumis_luminaire_destroy(lum);
        return tool_runtime_error("out of memory");
    }
    if (!o.json)
        printf("%-17s %6s %7s | %28s | %28s | %20s | %s\n", "distance", "energy", "images",
               "restricted: samples ns xglob", "uniform:    samples ns xglob", "global: var/smp ns",
               "best");
    rc = predict_bands(&o, lum, pr, arr);
    if (o.json && rc == EXIT_OK) {
        rc = print_predict_json(&o, arr);
        arr = NULL;
    }
    cJSON_Delete(arr);
    free(pr);
    lumis_luminaire_destroy(lum);
    return rc;
}
