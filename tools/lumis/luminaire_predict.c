/* lumis luminaire predict: which sampling strategy pays for a luminaire over a range of
 * distances (lumis_luminaire_predict), per distance band. */
#include "cli.h"

#include "lumis/luminaire.h"

#include <cJSON.h>
#include <math.h>
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

int tool_luminaire_predict(int argc, char **argv)
{
    const char *file = NULL;
    double range[2] = {0.0, 0.0};
    long budget = 32, kmax = 0, probes = 256, pilot = 16, bands = 1, seed = 1;
    int json = 0;
    lumis_luminaire_costs costs = lumis_luminaire_costs_default();
    for (int i = 2; i < argc; i++) {
        const char *v = NULL;
        if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (tool_option(argc, argv, &i, "--distance", &v)) {
            if (!parse_range(v, range))
                return tool_bad_value("luminaire predict", "--distance", v,
                                      "A,B with 0 < A <= B (luminaire units), or one distance");
        } else if (tool_option(argc, argv, &i, "--budget", &v)) {
            if (!v || !tool_parse_int(v, 1, 65536, &budget))
                return tool_bad_value("luminaire predict", "--budget", v, "1 to 65536");
        } else if (tool_option(argc, argv, &i, "--kmax", &v)) {
            if (!v || !tool_parse_int(v, 0, 65536, &kmax))
                return tool_bad_value("luminaire predict", "--kmax", v, "0 (none) to 65536");
        } else if (tool_option(argc, argv, &i, "--probes", &v)) {
            if (!v || !tool_parse_int(v, 1, 1 << 20, &probes))
                return tool_bad_value("luminaire predict", "--probes", v, "1 to 1048576");
        } else if (tool_option(argc, argv, &i, "--pilot", &v)) {
            if (!v || !tool_parse_int(v, 1, 4096, &pilot))
                return tool_bad_value("luminaire predict", "--pilot", v, "1 to 4096");
        } else if (tool_option(argc, argv, &i, "--bands", &v)) {
            if (!v || !tool_parse_int(v, 1, 64, &bands))
                return tool_bad_value("luminaire predict", "--bands", v, "1 to 64");
        } else if (tool_option(argc, argv, &i, "--costs", &v)) {
            if (!v || !tool_parse_costs(v, &costs))
                return tool_bad_value("luminaire predict", "--costs", v, TOOL_COSTS_HELP);
        } else if (tool_option(argc, argv, &i, "--seed", &v)) {
            if (!v || !tool_parse_int(v, 0, 2147483647L, &seed))
                return tool_bad_value("luminaire predict", "--seed", v, "0 to 2147483647");
        } else if (argv[i][0] != '-' && !file) {
            file = argv[i];
        } else {
            return tool_usage_error("luminaire predict", "unknown argument '%s'", argv[i]);
        }
    }
    if (!file) return tool_usage_error("luminaire predict", "no luminaire given");
    lumis_luminaire *lum = NULL;
    if (tool_load_luminaire(file, &lum) != LUMIS_OK) return EXIT_RUNTIME;
    lumis_luminaire_info in;
    lumis_luminaire_get_info(lum, &in);
    if (range[0] == 0.0) { /* default: 2 to 50 times the distance between the planes */
        range[0] = 2.0 * in.delta;
        range[1] = 50.0 * in.delta;
    }
    lumis_luminaire_probe *pr = malloc(sizeof *pr * (size_t)probes);
    cJSON *arr = json ? cJSON_CreateArray() : NULL;
    if (!pr || (json && !arr)) {
        free(pr);
        cJSON_Delete(arr);
        lumis_luminaire_destroy(lum);
        return tool_runtime_error("out of memory");
    }
    if (!json)
        printf("%-17s %6s %7s | %28s | %28s | %20s | %s\n", "distance", "energy", "images",
               "restricted: samples ns xglob", "uniform:    samples ns xglob", "global: var/smp ns",
               "best");
    int rc = EXIT_OK;
    for (int b = 0; b < bands && rc == EXIT_OK; b++) {
        const double r = range[1] / range[0];
        const double d0 = range[0] * pow(r, (double)b / bands),
                     d1 = range[0] * pow(r, (double)(b + 1) / bands);
        lumis_luminaire_predict_desc d = {0};
        d.probes = pr;
        d.probe_count = (int)probes;
        d.budget = (int)budget;
        d.k_max = (int)kmax;
        d.pilot = (int)pilot;
        d.seed = (uint64_t)seed;
        d.costs = &costs;
        lumis_luminaire_prediction p;
        lumis_status st =
            lumis_luminaire_probes(lum, d0, d1, (uint64_t)seed + (uint64_t)b, (int)probes, pr);
        if (st == LUMIS_OK) st = lumis_luminaire_predict(lum, &d, &p);
        if (st != LUMIS_OK) {
            rc = tool_runtime_error("%s: prediction failed: %s", file, lumis_status_string(st));
            break;
        }
        if (json) {
            cJSON *o = cJSON_CreateObject();
            const double dd[2] = {d0, d1};
            cJSON_AddItemToObject(o, "distance", cJSON_CreateDoubleArray(dd, 2));
            cJSON_AddNumberToObject(o, "probes_lit", p.probes_lit);
            cJSON_AddNumberToObject(o, "energy_share", p.energy_share);
            cJSON_AddNumberToObject(o, "images_lit", p.images_lit);
            cJSON_AddItemToObject(o, "restricted", strategy_json(&p.restricted));
            cJSON_AddItemToObject(o, "uniform", strategy_json(&p.uniform));
            cJSON_AddItemToObject(o, "global", strategy_json(&p.global));
            cJSON_AddStringToObject(o, "best", lumis_luminaire_strategy_name(p.best));
            cJSON_AddItemToArray(arr, o);
        } else {
            printf("%7.4g - %-7.4g %5.2f%% %7d | %9.1f %8.0f %8.1fx | %9.1f %8.0f %8.1fx | "
                   "%11.3g %8.0f | %s\n",
                   d0, d1, 100.0 * p.energy_share, p.images_lit, p.restricted.samples,
                   p.restricted.ns, p.restricted.time_ratio, p.uniform.samples, p.uniform.ns,
                   p.uniform.time_ratio, p.global.variance, p.global.ns,
                   p.probes_lit ? lumis_luminaire_strategy_name(p.best) : "(nothing lit)");
        }
    }
    if (json && rc == EXIT_OK) {
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "file", file);
        cJSON_AddNumberToObject(j, "budget", (double)budget);
        cJSON_AddNumberToObject(j, "k_max", (double)kmax);
        cJSON_AddNumberToObject(j, "probes", (double)probes);
        cJSON_AddItemToObject(j, "bands", arr);
        arr = NULL;
        char *text = cJSON_PrintUnformatted(j);
        cJSON_Delete(j);
        if (text)
            puts(text);
        else
            rc = tool_runtime_error("out of memory");
        free(text);
    }
    cJSON_Delete(arr);
    free(pr);
    lumis_luminaire_destroy(lum);
    return rc;
}
