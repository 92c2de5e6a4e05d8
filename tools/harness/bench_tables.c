/* lumis bench: the report's results (every item's result file, summarised per budget and
 * method: means and average ranks) and its tables: results.csv, results.json and
 * results.md (with the pairwise comparisons and the per-map table; the convergence
 * analyses, at equal time and at equal samples, are bench_convergence.c's, the markup
 * bench_markup.c's). */
#include "harness.h"

#include <cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

const char *const bench_metric_key[NMETRICS] = {"rmse",        "relmse",   "psnr",
                                                "lab_delta_e", "flip_ldr", "flip_hdr"};
const char *const bench_metric_title[NMETRICS] = {"RMSE",   "relMSE",   "PSNR dB",
                                                  "Lab ΔE", "FLIP-LDR", "FLIP-HDR"};

static double jnum(const cJSON *o, const char *k)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, k);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static int load_results(const suite *s, const char *out, result *res)
{
    int found = 0;
    for (int k = 0; k < bench_nitems(s); k++) {
        item it = bench_item_at(s, k);
        res[k].present = 0;
        if (!bench_pair_listed(s, it.map, it.scene)) continue; /* the suite leaves it out */
        cJSON *j = bench_load_item(s, out, &it); /* stale results (other settings) are left out */
        if (!j) continue;
        for (int m = 0; m < NMETRICS; m++) res[k].v[m] = jnum(j, bench_metric_key[m]);
        if (isnan(res[k].v[M_PSNR]) && res[k].v[M_RMSE] == 0.0) res[k].v[M_PSNR] = INFINITY;
        res[k].seconds = jnum(j, "render_seconds");
        res[k].build_ms = jnum(j, "sampler_build_ms");
        res[k].prep = jnum(j, "prep_seconds"); /* NaN in results made before 2026-11-25 */
        res[k].table_bytes = jnum(j, "sampler_table_bytes");
        res[k].spp = (int)jnum(j, "spp");
        res[k].used = jnum(j, "used_seconds");
        res[k].wall = jnum(j, "wall_seconds");
        res[k].cpu = jnum(j, "cpu_seconds");
        res[k].share = jnum(j, "cpu_share");
        res[k].attempts = isnan(jnum(j, "attempts")) ? 0 : (int)jnum(j, "attempts");
        res[k].contended = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(j, "contention"));
        const cJSON *chosen = cJSON_GetObjectItemCaseSensitive(j, "auto_chosen");
        bench_copy_cut(res[k].auto_chosen, sizeof res[k].auto_chosen,
                       cJSON_IsString(chosen) ? chosen->valuestring : "");
        res[k].present = 1;
        found++;
        cJSON_Delete(j);
    }
    return found;
}

/* Ranks of the methods in one (map, scene, budget) group, 1 = best, ties share the mean
 * rank; NaN where a result is missing. */
static void rank_group(const suite *s, const result *res, int m, int sc, int b, int metric,
                       double *ranks)
{
    int higher_better = metric == M_PSNR;
    for (int a = 0; a < s->nmethods; a++) {
        const result *ra = &res[bench_idx(s, m, sc, a, b)];
        if (!ra->present || isnan(ra->v[metric])) {
            ranks[a] = NAN;
            continue;
        }
        double better = 0, ties = 0;
        for (int o = 0; o < s->nmethods; o++) {
            const result *ro = &res[bench_idx(s, m, sc, o, b)];
            if (o == a || !ro->present || isnan(ro->v[metric])) continue;
            double x = ra->v[metric], y = ro->v[metric];
            if (higher_better ? y > x : y < x)
                better++;
            else if (y == x)
                ties++;
        }
        ranks[a] = 1.0 + better + 0.5 * ties;
    }
}

static void summarize(const suite *s, const result *res, int b, summary *out)
{
    for (int me = 0; me < s->nmethods; me++) memset(&out[me], 0, sizeof out[me]);
    double *ranks = calloc((size_t)s->nmethods, sizeof *ranks);
    int *rank_n = calloc((size_t)s->nmethods * NMETRICS, sizeof *rank_n);
    if (!ranks || !rank_n) {
        free(ranks);
        free(rank_n);
        return;
    }
    for (int m = 0; m < s->nmaps; m++)
        for (int sc = 0; sc < s->nscenes; sc++) {
            for (int metric = 0; metric < NMETRICS; metric++) {
                rank_group(s, res, m, sc, b, metric, ranks);
                for (int me = 0; me < s->nmethods; me++)
                    if (!isnan(ranks[me])) {
                        out[me].rank[metric] += ranks[me];
                        rank_n[me * NMETRICS + metric]++;
                    }
            }
            for (int me = 0; me < s->nmethods; me++) {
                const result *r = &res[bench_idx(s, m, sc, me, b)];
                if (!r->present) continue;
                for (int metric = 0; metric < NMETRICS; metric++)
                    out[me].mean[metric] += r->v[metric];
                out[me].seconds += r->seconds;
                out[me].spp += r->spp;
                out[me].build_ms += r->build_ms;
                out[me].prep += r->prep;
                out[me].used += r->used;
                out[me].table_bytes += r->table_bytes;
                out[me].n++;
            }
        }
    for (int me = 0; me < s->nmethods; me++) {
        summary *u = &out[me];
        if (u->n) {
            for (int metric = 0; metric < NMETRICS; metric++) u->mean[metric] /= u->n;
            u->seconds /= u->n;
            u->spp /= u->n;
            u->build_ms /= u->n;
            u->prep /= u->n;
            u->used /= u->n;
            u->table_bytes /= u->n;
        }
        for (int metric = 0; metric < NMETRICS; metric++) {
            int n = rank_n[me * NMETRICS + metric];
            u->rank[metric] = n ? u->rank[metric] / n : NAN;
        }
    }
    free(ranks);
    free(rank_n);
}

static void machine_facts(char *out, size_t cap)
{
    char model[256] = "unknown CPU";
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[512];
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, "model name", 10) == 0) {
            const char *colon = strchr(line, ':');
            if (colon) snprintf(model, sizeof model, "%s", colon + 2);
            model[strcspn(model, "\n")] = '\0';
            break;
        }
    if (f) fclose(f);
    snprintf(out, cap, "%s, %ld cores", model, sysconf(_SC_NPROCESSORS_ONLN));
}

void bench_write_comparisons(FILE *f, bench_markup mk, const suite *s, const result *res)
{
    char cells[6][4200], text[1024];
    for (int c = 0; c < s->ncompare; c++) {
        int a = bench_method_index(s, s->compare[c][0]),
            bm = bench_method_index(s, s->compare[c][1]);
        if (a < 0 || bm < 0) continue;
        const char *la = s->methods[a].label, *lb = s->methods[bm].label;
        snprintf(text, sizeof text, "%s against %s", la, lb);
        bench_heading(f, mk, text);
        bench_table_begin(f, mk);
        snprintf(cells[0], sizeof cells[0], "budget");
        snprintf(cells[1], sizeof cells[1], "pairs");
        snprintf(cells[2], sizeof cells[2], "%s better (relMSE)", la);
        snprintf(cells[3], sizeof cells[3], "relMSE ratio %s/%s (geometric mean)", la, lb);
        snprintf(cells[4], sizeof cells[4], "%s better (FLIP-LDR)", la);
        snprintf(cells[5], sizeof cells[5], "%s loses on (relMSE ratio)", la);
        bench_table_row(f, mk, 1, 6, cells);
        for (int b = 0; b < s->nbudgets; b++) {
            int pairs = 0, wins = 0, flip_wins = 0, flip_pairs = 0;
            double logsum = 0;
            char losses[4096] = "";
            for (int m = 0; m < s->nmaps; m++)
                for (int sc = 0; sc < s->nscenes; sc++) {
                    const result *ra = &res[bench_idx(s, m, sc, a, b)],
                                 *rb = &res[bench_idx(s, m, sc, bm, b)];
                    if (!ra->present || !rb->present) continue;
                    double x = ra->v[M_RELMSE], y = rb->v[M_RELMSE];
                    if (!(x > 0 && y > 0)) continue;
                    pairs++;
                    logsum += log(x / y);
                    if (x < y) {
                        wins++;
                    } else {
                        size_t len = strlen(losses);
                        snprintf(losses + len, sizeof losses - len, "%s%s/%s (%.2f)",
                                 len ? ", " : "", s->maps[m].label, s->scenes[sc].label, x / y);
                    }
                    if (!isnan(ra->v[M_FLIP_LDR]) && !isnan(rb->v[M_FLIP_LDR])) {
                        flip_pairs++;
                        flip_wins += ra->v[M_FLIP_LDR] < rb->v[M_FLIP_LDR];
                    }
                }
            if (!pairs) continue;
            snprintf(cells[0], sizeof cells[0], "%s", s->budgets[b].label);
            snprintf(cells[1], sizeof cells[1], "%d", pairs);
            snprintf(cells[2], sizeof cells[2], "%d of %d", wins, pairs);
            snprintf(cells[3], sizeof cells[3], "%.3f", exp(logsum / pairs));
            snprintf(cells[4], sizeof cells[4], "%d of %d", flip_wins, flip_pairs);
            snprintf(cells[5], sizeof cells[5], "%s", losses[0] ? losses : "none");
            bench_table_row(f, mk, 0, 6, cells);
        }
        bench_table_end(f, mk);
        snprintf(text, sizeof text, "A ratio below 1 means %s has the smaller error.", la);
        bench_paragraph(f, mk, text);
        /* Memory: the sampling tables, averaged over every item of the two methods. */
        double ta = 0, tb = 0;
        int na = 0, nb = 0;
        for (int k = 0; k < bench_nitems(s); k++) {
            item it = bench_item_at(s, k);
            if (!res[k].present || !(res[k].table_bytes > 0)) continue;
            if (it.method == a) ta += res[k].table_bytes, na++;
            if (it.method == bm) tb += res[k].table_bytes, nb++;
        }
        if (na && nb) {
            snprintf(text, sizeof text,
                     "Sampling tables: %s %.0f bytes, %s %.0f bytes on average: %s's are %.1f "
                     "times %s.",
                     la, ta / na, lb, tb / nb, la,
                     ta / na <= tb / nb ? tb / ta * na / nb : ta / tb * nb / na,
                     ta / na <= tb / nb ? "smaller" : "larger");
            bench_paragraph(f, mk, text);
        }
    }
}

int bench_noisy_reference(const bench_report *r, int budget, int method, int *max_spp)
{
    int n = 0;
    *max_spp = 0;
    for (int k = 0; k < r->n; k++) {
        item it = bench_item_at(r->s, k);
        if (!r->res[k].present || (budget >= 0 && it.budget != budget) ||
            (method >= 0 && it.method != method))
            continue;
        const double spp = r->res[k].spp;
        if ((double)r->s->ref_spp < BENCH_REF_FACTOR * spp) {
            n++;
            if (r->res[k].spp > *max_spp) *max_spp = r->res[k].spp;
        }
    }
    return n;
}

int bench_write_failures(FILE *f, bench_markup mk, const bench_report *r)
{
    /* out/failures/ID.txt, written by bench_run for an item whose process failed */
    int n = 0;
    for (int k = 0; k < r->n; k++) {
        item it = bench_item_at(r->s, k);
        char path[9800];
        snprintf(path, sizeof path, "%s/failures/%s.txt", r->out, it.id);
        size_t len = 0;
        FILE *in = fopen(path, "rb");
        if (!in) continue;
        char line[600] = "";
        len = fread(line, 1, sizeof line - 1, in);
        fclose(in);
        line[len] = '\0';
        for (char *c = line; *c; c++)
            if (*c == '\n' || *c == '<' || *c == '>' || *c == '&') *c = ' ';
        if (n++ == 0)
            fprintf(f, mk == BENCH_HTML ? "<h2>Failed items</h2>\n<ul>\n"
                                        : "\n## Failed items\n\nThese items failed (run the same "
                                          "command again to retry them); the tables leave them "
                                          "out.\n\n");
        fprintf(f, mk == BENCH_HTML ? "<li>%s</li>\n" : "- %s\n", line);
    }
    if (n && mk == BENCH_HTML) fputs("</ul>\n", f);
    return n;
}

void bench_method_words(const suite_method *m, char *out, size_t cap)
{
    if (m->bsdf_only) {
        snprintf(out, cap, "BSDF sampling");
    } else if (m->lights[0]) {
        const int strata = m->lights_mode == LUMIS_LIGHTS_STRATIFIED;
        const int k = m->lights_k ? m->lights_k : strata ? 32 : 64;
        char draws[48] = "";
        if (m->lights_draws) snprintf(draws, sizeof draws, ", %d draws chosen", m->lights_draws);
        snprintf(out, cap, "light set %s, %s, K = %d%s", m->lights, strata ? "stratified" : "point",
                 k, draws);
    } else {
        /* the sampler the render builds: "default" is inversion-guided (sampler.h) */
        const lumis_sampler_method sm =
            m->sampler.method ? m->sampler.method : LUMIS_METHOD_INVERSION_GUIDED;
        snprintf(out, cap, "%s%s", lumis_sampler_method_name(sm),
                 m->estimator == LUMIS_ESTIMATOR_LIGHT ? " (light sampling)"
                 : m->power                            ? " + MIS (power)"
                                                       : " + MIS (balance)");
    }
}

int bench_write_contention_warning(FILE *f, bench_markup mk, const bench_report *r)
{
    const suite *s = r->s;
    int n = 0, timed = 0;
    for (int k = 0; k < r->n; k++) {
        if (!r->res[k].present) continue;
        const item it = bench_item_at(s, k);
        if (s->budgets[it.budget].seconds > 0.0) timed++;
        n += r->res[k].contended;
    }
    if (!n) return 0;
    char text[1024], cells[5][4200];
    snprintf(text, sizeof text,
             "%sWarning: contention.%s %d of the %d equal-time items ran on shared cores: their "
             "render threads got under %.0f %% of their wall time as CPU time, so their "
             "budgets bought fewer samples or lights than on an idle machine, and the methods "
             "compare unequally. Run with fewer %s--jobs%s or %s--threads%s, or on an idle "
             "machine.",
             mk == BENCH_HTML ? "<strong>" : "**", mk == BENCH_HTML ? "</strong>" : "**", n, timed,
             100.0 * TOOL_CONTENTION_SHARE, mk == BENCH_HTML ? "<code>" : "`",
             mk == BENCH_HTML ? "</code>" : "`", mk == BENCH_HTML ? "<code>" : "`",
             mk == BENCH_HTML ? "</code>" : "`");
    if (mk == BENCH_MD) fputs("\n", f);
    bench_paragraph(f, mk, text);
    if (mk == BENCH_MD) fputs("\n", f);
    bench_table_begin(f, mk);
    snprintf(cells[0], sizeof cells[0], "item");
    snprintf(cells[1], sizeof cells[1], "CPU share");
    snprintf(cells[2], sizeof cells[2], "used s");
    snprintf(cells[3], sizeof cells[3], "budget s");
    snprintf(cells[4], sizeof cells[4], "spp");
    bench_table_row(f, mk, 1, 5, cells);
    for (int k = 0; k < r->n; k++) {
        if (!r->res[k].present || !r->res[k].contended) continue;
        const item it = bench_item_at(s, k);
        snprintf(cells[0], sizeof cells[0], "%s", it.id);
        snprintf(cells[1], sizeof cells[1], "%.2f", r->res[k].share);
        snprintf(cells[2], sizeof cells[2], "%.3f", r->res[k].used);
        snprintf(cells[3], sizeof cells[3], "%g", s->budgets[it.budget].seconds);
        snprintf(cells[4], sizeof cells[4], "%d", r->res[k].spp);
        bench_table_row(f, mk, 0, 5, cells);
    }
    bench_table_end(f, mk);
    return n;
}

void bench_write_reference_warning(FILE *f, bench_markup mk, const bench_report *r)
{
    const suite *s = r->s;
    int most = 0, n = bench_noisy_reference(r, -1, -1, &most);
    if (!n) return;
    char text[1024], cells[4][4200];
    snprintf(
        text, sizeof text,
        "%sWarning: a noisy reference.%s The reference has %d spp, fewer than %d times the "
        "samples that %d of the %d items reached (up to %d spp): its own noise weighs in their "
        "errors and may reorder the methods. Raise %sreference.spp%s to %d or more.",
        mk == BENCH_HTML ? "<strong>" : "**", mk == BENCH_HTML ? "</strong>" : "**", s->ref_spp,
        BENCH_REF_FACTOR, n, r->found, most, mk == BENCH_HTML ? "<code>" : "`",
        mk == BENCH_HTML ? "</code>" : "`", BENCH_REF_FACTOR * most);
    bench_paragraph(f, mk, text);
    if (mk == BENCH_MD) fputs("\n", f);
    bench_table_begin(f, mk);
    snprintf(cells[0], sizeof cells[0], "budget");
    snprintf(cells[1], sizeof cells[1], "method");
    snprintf(cells[2], sizeof cells[2], "items");
    snprintf(cells[3], sizeof cells[3], "most spp");
    bench_table_row(f, mk, 1, 4, cells);
    for (int b = 0; b < s->nbudgets; b++)
        for (int me = 0; me < s->nmethods; me++) {
            int bm = bench_noisy_reference(r, b, me, &most);
            if (!bm) continue;
            snprintf(cells[0], sizeof cells[0], "%s", s->budgets[b].label);
            snprintf(cells[1], sizeof cells[1], "%s", s->methods[me].label);
            snprintf(cells[2], sizeof cells[2], "%d", bm);
            snprintf(cells[3], sizeof cells[3], "%d", most);
            bench_table_row(f, mk, 0, 4, cells);
        }
    bench_table_end(f, mk);
}

void bench_write_per_map(FILE *f, bench_markup mk, const suite *s, const result *res)
{
    int lb = s->nbudgets - 1;
    char text[256];
    snprintf(text, sizeof text, "relMSE per map and scene (budget %s)", s->budgets[lb].label);
    bench_heading(f, mk, text);
    char(*cells)[4200] = calloc((size_t)s->nmethods + 2, sizeof *cells);
    if (!cells) return;
    bench_table_begin(f, mk);
    snprintf(cells[0], sizeof cells[0], "map");
    snprintf(cells[1], sizeof cells[1], "scene");
    for (int me = 0; me < s->nmethods; me++)
        snprintf(cells[2 + me], sizeof cells[0], "%s", s->methods[me].label);
    bench_table_row(f, mk, 1, s->nmethods + 2, cells);
    for (int m = 0; m < s->nmaps; m++)
        for (int sc = 0; sc < s->nscenes; sc++) {
            if (!bench_pair_listed(s, m, sc)) continue;
            snprintf(cells[0], sizeof cells[0], "%s", s->maps[m].label);
            snprintf(cells[1], sizeof cells[1], "%s", s->scenes[sc].label);
            for (int me = 0; me < s->nmethods; me++) {
                const result *cell = &res[bench_idx(s, m, sc, me, lb)];
                bench_fmt_metric(cells[2 + me], sizeof cells[0],
                                 cell->present ? cell->v[M_RELMSE] : NAN, M_RELMSE);
            }
            bench_table_row(f, mk, 0, s->nmethods + 2, cells);
        }
    bench_table_end(f, mk);
    free(cells);
}

int bench_report_load(bench_report *r, const suite *s, const char *out, int argc, char **argv)
{
    memset(r, 0, sizeof *r);
    r->s = s;
    r->out = out;
    r->n = bench_nitems(s);
    r->res = calloc((size_t)r->n, sizeof *r->res);
    r->sum = calloc((size_t)s->nmethods * (size_t)s->nbudgets, sizeof *r->sum);
    if (!r->res || !r->sum) {
        bench_report_free(r);
        return tool_runtime_error("bench: out of memory");
    }
    r->found = load_results(s, out, r->res);
    for (int b = 0; b < s->nbudgets; b++) summarize(s, r->res, b, r->sum + b * s->nmethods);
    if (bench_convergence_compute(r) != EXIT_OK) {
        bench_report_free(r);
        return EXIT_RUNTIME;
    }
    machine_facts(r->machine, sizeof r->machine);
    snprintf(r->cmd, sizeof r->cmd, "lumis");
    for (int k = 0; k < argc; k++) {
        size_t len = strlen(r->cmd);
        snprintf(r->cmd + len, sizeof r->cmd - len, " %s", argv[k]);
    }
    time_t now = time(NULL);
    strftime(r->date, sizeof r->date, "%Y-%m-%d %H:%M UTC", gmtime(&now));
    return EXIT_OK;
}

void bench_report_free(bench_report *r)
{
    free(r->res);
    free(r->sum);
    for (int axis = 0; axis < BENCH_NAXES; axis++) bench_convergence_free(&r->conv[axis]);
    r->res = NULL;
    r->sum = NULL;
}

int bench_write_csv(const bench_report *r, const char *path)
{
    const suite *s = r->s;
    const result *res = r->res;
    FILE *f = tmpfile();
    if (!f) return tool_runtime_error("bench: cannot write a temporary file");
    fprintf(f, "map,scene,method,budget,spp,render_seconds,prep_seconds,sampler_build_ms,"
               "sampler_table_bytes");
    for (int m = 0; m < NMETRICS; m++) fprintf(f, ",%s", bench_metric_key[m]);
    /* used_seconds: prep and every attempt (render_seconds is the image's attempt alone);
     * contention: the render threads got under 80 % of their wall time as CPU time */
    /* auto_chosen: what an "auto" method chose (empty for the others) */
    fprintf(f, ",used_seconds,attempts,wall_seconds,cpu_seconds,cpu_share,contention,"
               "auto_chosen\n");
    for (int k = 0; k < r->n; k++) {
        if (!res[k].present) continue;
        item it = bench_item_at(s, k);
        fprintf(f, "%s,%s,%s,%s,%d,%.6g,%.6g,%.6g,%.0f", s->maps[it.map].label,
                s->scenes[it.scene].label, s->methods[it.method].label, s->budgets[it.budget].label,
                res[k].spp, res[k].seconds, res[k].prep, res[k].build_ms, res[k].table_bytes);
        for (int m = 0; m < NMETRICS; m++) fprintf(f, ",%.9g", res[k].v[m]);
        fprintf(f, ",%.6g,%d,%.6g,%.6g,%.4g,%d,%s\n", res[k].used, res[k].attempts, res[k].wall,
                res[k].cpu, res[k].share, res[k].contended, res[k].auto_chosen);
    }
    return tool_commit_tmp(f, path);
}

int bench_write_json(const bench_report *r, const char *path)
{
    const suite *s = r->s;
    const summary *sum = r->sum;
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "suite", s->name);
    cJSON_AddStringToObject(j, "description", s->description);
    cJSON_AddStringToObject(j, "command", r->cmd);
    cJSON_AddStringToObject(j, "lumis_version", LUMIS_VERSION_STRING);
    cJSON_AddStringToObject(j, "machine", r->machine);
    cJSON_AddStringToObject(j, "date", r->date);
    cJSON_AddNumberToObject(j, "items", bench_nlisted(s));
    cJSON_AddNumberToObject(j, "items_done", r->found);
    if (s->exposure_auto)
        cJSON_AddStringToObject(j, "exposure_ev", "auto");
    else
        cJSON_AddNumberToObject(j, "exposure_ev", s->exposure_ev);
    cJSON_AddNumberToObject(j, "reference_spp", s->ref_spp);
    cJSON *jsum = cJSON_AddArrayToObject(j, "summary");
    for (int b = 0; b < s->nbudgets; b++)
        for (int me = 0; me < s->nmethods; me++) {
            const summary *u = &sum[b * s->nmethods + me];
            cJSON *o = cJSON_CreateObject();
            cJSON_AddStringToObject(o, "budget", s->budgets[b].label);
            cJSON_AddStringToObject(o, "method", s->methods[me].label);
            cJSON_AddNumberToObject(o, "n", u->n);
            cJSON_AddNumberToObject(o, "mean_spp", u->spp);
            cJSON_AddNumberToObject(o, "mean_render_seconds", u->seconds);
            if (isfinite(u->used))
                cJSON_AddNumberToObject(o, "mean_used_seconds", u->used);
            else
                cJSON_AddNullToObject(o, "mean_used_seconds");
            if (isfinite(u->prep))
                cJSON_AddNumberToObject(o, "mean_prep_seconds", u->prep);
            else
                cJSON_AddNullToObject(o, "mean_prep_seconds");
            cJSON_AddNumberToObject(o, "mean_sampler_build_ms", u->build_ms);
            cJSON_AddNumberToObject(o, "mean_sampler_table_bytes", u->table_bytes);
            for (int m = 0; m < NMETRICS; m++) {
                char key[64];
                snprintf(key, sizeof key, "mean_%s", bench_metric_key[m]);
                if (isfinite(u->mean[m]))
                    cJSON_AddNumberToObject(o, key, u->mean[m]);
                else
                    cJSON_AddNullToObject(o, key);
                snprintf(key, sizeof key, "rank_%s", bench_metric_key[m]);
                if (isfinite(u->rank[m]))
                    cJSON_AddNumberToObject(o, key, u->rank[m]);
                else
                    cJSON_AddNullToObject(o, key);
            }
            cJSON_AddItemToArray(jsum, o);
        }
    for (int axis = 0; axis < BENCH_NAXES; axis++) bench_json_convergence(j, r, &r->conv[axis]);
    bench_json_auto(j, r);
    int rc = tool_write_json(path, j);
    cJSON_Delete(j);
    return rc;
}

int bench_write_md(const bench_report *r, const char *path)
{
    const suite *s = r->s;
    const result *res = r->res;
    const summary *sum = r->sum;
    const int n = bench_nlisted(s), found = r->found;
    const char *cmd = r->cmd, *date = r->date, *machine = r->machine;
    FILE *md = tmpfile();
    if (!md) return tool_runtime_error("bench: cannot write a temporary file");
    char ref_words[256];
    bench_method_words(&s->reference, ref_words, sizeof ref_words);
    fprintf(md, "# lumis bench: %s\n\n", s->name);
    if (s->description[0]) fprintf(md, "%s\n\n", s->description);
    char expo[128];
    if (s->exposure_auto)
        snprintf(expo, sizeof expo, "2^EV with EV per reference, its mean luminance to 0.18");
    else
        snprintf(expo, sizeof expo, "2^%g", s->exposure_ev);
    fprintf(md,
            "- command: `%s`\n- lumis %s, %s\n- machine: %s\n- %d of %d items (%d maps × %d "
            "scenes%s × %d methods × %d budgets)%s\n- reference: %d spp, %s; errors against "
            "it, lower is better except PSNR\n- RMSE, relMSE (ε = 0.01), PSNR: linear HDR "
            "values, PSNR peak = the reference's largest value; Lab ΔE (CIE76, D65) and "
            "FLIP-LDR on values × %s, clamped to [0, 1]; FLIP-HDR with the reference's "
            "exposure range and ACES; 67.02 pixels per degree\n",
            cmd, LUMIS_VERSION_STRING, date, machine, found, n, s->nmaps, s->nscenes,
            n < bench_nitems(s) ? ", the pairs the scenes list" : "", s->nmethods, s->nbudgets,
            found < n ? " — **incomplete**: run the remaining shards" : "", s->ref_spp, ref_words,
            expo);
    bench_write_failures(md, BENCH_MD, r);
    bench_write_contention_warning(md, BENCH_MD, r);
    bench_write_reference_warning(md, BENCH_MD, r);
    for (int b = 0; b < s->nbudgets; b++) {
        const suite_budget *bu = &s->budgets[b];
        if (bu->spp)
            fprintf(md, "\n## Budget: %d samples per pixel\n\n", bu->spp);
        else
            fprintf(md, "\n## Budget: %g s of rendering (equal time)\n\n", bu->seconds);
        fprintf(md, "Means over (map, scene) pairs; rank = average rank per pair (1 = best); "
                    "prep s = seconds before the first sample (tables, light sets, K's "
                    "pilots), spent from an equal-time budget; used s = prep s and every "
                    "attempt's render (a light set whose K was refitted renders twice; render s "
                    "is the image's attempt alone).\n\n"
                    "| method | n | spp | render s | prep s | used s | build ms | table bytes |");
        for (int m = 0; m < NMETRICS; m++) fprintf(md, " %s |", bench_metric_title[m]);
        for (int m = 0; m < NMETRICS; m++)
            if (m != M_RMSE && m != M_PSNR) fprintf(md, " rank %s |", bench_metric_title[m]);
        fprintf(md, "\n|---|---|---|---|---|---|---|---|");
        for (int m = 0; m < 2 * NMETRICS - 2; m++) fprintf(md, "---|");
        fprintf(md, "\n");
        for (int me = 0; me < s->nmethods; me++) {
            const summary *u = &sum[b * s->nmethods + me];
            fprintf(md, "| %s | %d | %.1f | %.3f | %.3f | %.3f | %.2f | %.0f |",
                    s->methods[me].label, u->n, u->spp, u->seconds, u->prep, u->used, u->build_ms,
                    u->table_bytes);
            char buf[64];
            for (int m = 0; m < NMETRICS; m++) {
                bench_fmt_metric(buf, sizeof buf, u->n ? u->mean[m] : NAN, m);
                fprintf(md, " %s |", buf);
            }
            for (int m = 0; m < NMETRICS; m++)
                if (m != M_RMSE && m != M_PSNR) {
                    if (isnan(u->rank[m]))
                        fprintf(md, " – |");
                    else
                        fprintf(md, " %.2f |", u->rank[m]);
                }
            fprintf(md, "\n");
        }
    }
    bench_write_comparisons(md, BENCH_MD, s, res);
    bench_write_auto(md, BENCH_MD, r);
    for (int axis = 0; axis < BENCH_NAXES; axis++)
        bench_write_convergence(md, BENCH_MD, r, &r->conv[axis]);
    bench_write_per_map(md, BENCH_MD, s, res);
    return tool_commit_tmp(md, path);
}
