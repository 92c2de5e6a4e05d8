/* lumis bench: the automatic estimator against the fixed ones.  A method with "auto": true
 * lets the session choose its estimator (lumis_session_desc.auto_estimator) inside the
 * item's budget; its result records what it chose.  Per (map, scene, budget) the report
 * puts that choice and its relMSE beside the best of the suite's other methods at the same
 * budget (every fixed method of the suite, whether or not auto can choose it), and sums
 * up per budget: the geometric mean of auto / best fixed and the cases beyond
 * BENCH_AUTO_MISS. */
#include "harness.h"

#include <cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* One (map, scene, budget) of an auto method: the best fixed method (-1: none has a
 * relMSE > 0 there) and the two errors.  Returns 0 when the auto item has no relMSE > 0. */
static int auto_case(const suite *s, const result *res, int m, int sc, int me, int b, int *best,
                     double *rel, double *best_rel)
{
    const result *ra = &res[bench_idx(s, m, sc, me, b)];
    *best = -1;
    *best_rel = NAN;
    *rel = ra->present ? ra->v[M_RELMSE] : NAN;
    if (!(*rel > 0) || !isfinite(*rel)) return 0;
    for (int o = 0; o < s->nmethods; o++) {
        const result *ro = &res[bench_idx(s, m, sc, o, b)];
        if (s->methods[o].auto_estimator || !ro->present) continue;
        const double v = ro->v[M_RELMSE];
        if (v > 0 && isfinite(v) && (*best < 0 || v < *best_rel)) {
            *best = o;
            *best_rel = v;
        }
    }
    return 1;
}

/* Per budget of one auto method: the cases with a best fixed method, the geometric mean of
 * their ratios, how many are beyond BENCH_AUTO_MISS, and how often each choice was made. */
#define AUTO_NAMES 8
typedef struct auto_tally {
    int n, misses, nnames;
    double logsum;
    char names[AUTO_NAMES][32];
    int counts[AUTO_NAMES];
} auto_tally;

static void tally_choice(auto_tally *t, const char *chosen)
{
    const char *c = *chosen ? chosen : "unknown";
    int k = 0;
    while (k < t->nnames && strcmp(t->names[k], c) != 0) k++;
    if (k == t->nnames && k < AUTO_NAMES) {
        bench_copy_cut(t->names[k], sizeof t->names[k], c);
        t->counts[t->nnames++] = 0;
    }
    if (k < t->nnames) t->counts[k]++;
}

/* "mis 3, stratified 13" */
static void tally_words(const auto_tally *t, char *out, size_t cap)
{
    out[0] = '\0';
    for (int k = 0; k < t->nnames; k++) {
        size_t len = strlen(out);
        snprintf(out + len, cap - len, "%s%s %d", k ? ", " : "", t->names[k], t->counts[k]);
    }
}

static auto_tally tally_budget(const suite *s, const result *res, int me, int b)
{
    auto_tally t;
    memset(&t, 0, sizeof t);
    for (int m = 0; m < s->nmaps; m++)
        for (int sc = 0; sc < s->nscenes; sc++) {
            int best;
            double rel, best_rel;
            if (!auto_case(s, res, m, sc, me, b, &best, &rel, &best_rel)) continue;
            tally_choice(&t, res[bench_idx(s, m, sc, me, b)].auto_chosen);
            if (best < 0) continue;
            t.n++;
            t.logsum += log(rel / best_rel);
            t.misses += rel > BENCH_AUTO_MISS * best_rel;
        }
    return t;
}

int bench_auto_methods(const suite *s)
{
    int n = 0;
    for (int me = 0; me < s->nmethods; me++) n += s->methods[me].auto_estimator;
    return n;
}

/* A table that follows a paragraph or a table needs a blank line before it in Markdown. */
static void table_after_text(FILE *f, bench_markup mk)
{
    if (mk == BENCH_MD) fputc('\n', f);
    bench_table_begin(f, mk);
}

void bench_write_auto(FILE *f, bench_markup mk, const bench_report *r)
{
    const suite *s = r->s;
    const result *res = r->res;
    char cells[8][4200], text[1024];
    for (int me = 0; me < s->nmethods; me++) {
        if (!s->methods[me].auto_estimator) continue;
        const char *la = s->methods[me].label;
        snprintf(text, sizeof text, "%s's choice against the best fixed method", la);
        bench_heading(f, mk, text);
        snprintf(text, sizeof text,
                 "%s renders with the automatic estimator: its pilots and the regions are spent "
                 "from the same budget as every method's. Per budget, over the (map, scene) "
                 "pairs: the geometric mean of %s's relMSE over the best other method's at that "
                 "budget (the best of all the suite's fixed methods, whether %s can choose it "
                 "or not), and the pairs where it is more than %.2f times that.",
                 la, la, la, BENCH_AUTO_MISS);
        bench_paragraph(f, mk, text);
        table_after_text(f, mk);
        snprintf(cells[0], sizeof cells[0], "budget");
        snprintf(cells[1], sizeof cells[1], "pairs");
        snprintf(cells[2], sizeof cells[2], "%s / best fixed (geometric mean)", la);
        snprintf(cells[3], sizeof cells[3], "beyond %.2f×", BENCH_AUTO_MISS);
        snprintf(cells[4], sizeof cells[4], "chosen");
        bench_table_row(f, mk, 1, 5, cells);
        auto_tally all;
        memset(&all, 0, sizeof all);
        for (int b = 0; b < s->nbudgets; b++) {
            const auto_tally t = tally_budget(s, res, me, b);
            if (!t.n && !t.nnames) continue;
            all.n += t.n;
            all.misses += t.misses;
            all.logsum += t.logsum;
            snprintf(cells[0], sizeof cells[0], "%s", s->budgets[b].label);
            snprintf(cells[1], sizeof cells[1], "%d", t.n);
            snprintf(cells[2], sizeof cells[2], "%.3f", t.n ? exp(t.logsum / t.n) : NAN);
            snprintf(cells[3], sizeof cells[3], "%d of %d", t.misses, t.n);
            tally_words(&t, cells[4], sizeof cells[4]);
            bench_table_row(f, mk, 0, 5, cells);
        }
        if (all.n) {
            snprintf(cells[0], sizeof cells[0], "all");
            snprintf(cells[1], sizeof cells[1], "%d", all.n);
            snprintf(cells[2], sizeof cells[2], "%.3f", exp(all.logsum / all.n));
            snprintf(cells[3], sizeof cells[3], "%d of %d", all.misses, all.n);
            snprintf(cells[4], sizeof cells[4], " ");
            bench_table_row(f, mk, 0, 5, cells);
        }
        bench_table_end(f, mk);
        table_after_text(f, mk);
        snprintf(cells[0], sizeof cells[0], "map");
        snprintf(cells[1], sizeof cells[1], "scene");
        snprintf(cells[2], sizeof cells[2], "budget");
        snprintf(cells[3], sizeof cells[3], "chosen");
        snprintf(cells[4], sizeof cells[4], "best fixed");
        snprintf(cells[5], sizeof cells[5], "%s relMSE", la);
        snprintf(cells[6], sizeof cells[6], "best fixed relMSE");
        snprintf(cells[7], sizeof cells[7], "%s / best", la);
        bench_table_row(f, mk, 1, 8, cells);
        for (int m = 0; m < s->nmaps; m++)
            for (int sc = 0; sc < s->nscenes; sc++)
                for (int b = 0; b < s->nbudgets; b++) {
                    int best;
                    double rel, best_rel;
                    if (!auto_case(s, res, m, sc, me, b, &best, &rel, &best_rel)) continue;
                    const result *ra = &res[bench_idx(s, m, sc, me, b)];
                    snprintf(cells[0], sizeof cells[0], "%s", s->maps[m].label);
                    snprintf(cells[1], sizeof cells[1], "%s", s->scenes[sc].label);
                    snprintf(cells[2], sizeof cells[2], "%s", s->budgets[b].label);
                    snprintf(cells[3], sizeof cells[3], "%s",
                             ra->auto_chosen[0] ? ra->auto_chosen : "–");
                    snprintf(cells[4], sizeof cells[4], "%s",
                             best >= 0 ? s->methods[best].label : "–");
                    bench_fmt_metric(cells[5], sizeof cells[5], rel, M_RELMSE);
                    bench_fmt_metric(cells[6], sizeof cells[6], best_rel, M_RELMSE);
                    if (best >= 0)
                        snprintf(cells[7], sizeof cells[7], "%.3f%s", rel / best_rel,
                                 rel > BENCH_AUTO_MISS * best_rel ? " (miss)" : "");
                    else
                        snprintf(cells[7], sizeof cells[7], "–");
                    bench_table_row(f, mk, 0, 8, cells);
                }
        bench_table_end(f, mk);
    }
}

void bench_json_auto(cJSON *j, const bench_report *r)
{
    const suite *s = r->s;
    const result *res = r->res;
    if (!bench_auto_methods(s)) return;
    cJSON *arr = cJSON_AddArrayToObject(j, "auto");
    for (int me = 0; me < s->nmethods; me++) {
        if (!s->methods[me].auto_estimator) continue;
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "method", s->methods[me].label);
        cJSON_AddNumberToObject(o, "miss_ratio", BENCH_AUTO_MISS);
        cJSON *budgets = cJSON_AddArrayToObject(o, "budgets");
        for (int b = 0; b < s->nbudgets; b++) {
            const auto_tally t = tally_budget(s, res, me, b);
            cJSON *jb = cJSON_CreateObject();
            cJSON_AddStringToObject(jb, "budget", s->budgets[b].label);
            cJSON_AddNumberToObject(jb, "pairs", t.n);
            if (t.n)
                cJSON_AddNumberToObject(jb, "geomean_ratio", exp(t.logsum / t.n));
            else
                cJSON_AddNullToObject(jb, "geomean_ratio");
            cJSON_AddNumberToObject(jb, "misses", t.misses);
            char words[512];
            tally_words(&t, words, sizeof words);
            cJSON_AddStringToObject(jb, "chosen", words);
            cJSON_AddItemToArray(budgets, jb);
        }
        cJSON *cases = cJSON_AddArrayToObject(o, "cases");
        for (int m = 0; m < s->nmaps; m++)
            for (int sc = 0; sc < s->nscenes; sc++)
                for (int b = 0; b < s->nbudgets; b++) {
                    int best;
                    double rel, best_rel;
                    if (!auto_case(s, res, m, sc, me, b, &best, &rel, &best_rel)) continue;
                    cJSON *c = cJSON_CreateObject();
                    cJSON_AddStringToObject(c, "map", s->maps[m].label);
                    cJSON_AddStringToObject(c, "scene", s->scenes[sc].label);
                    cJSON_AddStringToObject(c, "budget", s->budgets[b].label);
                    cJSON_AddStringToObject(c, "chosen",
                                            res[bench_idx(s, m, sc, me, b)].auto_chosen);
                    cJSON_AddNumberToObject(c, "relmse", rel);
                    if (best >= 0) {
                        cJSON_AddStringToObject(c, "best_fixed", s->methods[best].label);
                        cJSON_AddNumberToObject(c, "best_fixed_relmse", best_rel);
                        cJSON_AddNumberToObject(c, "ratio", rel / best_rel);
                    } else {
                        cJSON_AddNullToObject(c, "best_fixed");
                    }
                    cJSON_AddItemToArray(cases, c);
                }
        cJSON_AddItemToArray(arr, o);
    }
}
