/* lumis bench: the convergence analyses of a report, one per axis with two or more budgets
 * on it (time budgets: equal time; spp budgets: equal samples): the geometric mean of
 * relMSE per method and budget, the log-log slopes, and where the compare pairs' curves
 * cross (results.md, index.html, results.json, convergence-all.svg, convergence-spp.svg). */
#include "harness.h"

#include <cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the convergence analyses ------------------------------------------------------------ */

const bench_axis_words bench_axes[BENCH_NAXES] = {
    [BENCH_TIME] = {.title = "Convergence (equal time)",
                    .budget = "time budget",
                    .log_x = "log(seconds)",
                    .others = " Budgets in samples take no part.",
                    .note = "",
                    .unit = " s",
                    .json = "convergence",
                    .x_key = "seconds",
                    .scene = "all",
                    .svg = "convergence-all.svg",
                    .svg_alt = "convergence-all-scenes.svg",
                    .x_title = "time budget, equal time",
                    .x_name = "time budget (log)"},
    [BENCH_SPP] = {.title = "Convergence (equal samples)",
                   .budget = "sample budget",
                   .log_x = "log(spp)",
                   .others = " Budgets in time take no part.",
                   .note = " At equal samples a method's cost per sample is left out: the "
                           "ratios and crossings compare the error of a sample, not of a "
                           "second.",
                   .unit = " spp",
                   .json = "convergence_spp",
                   .x_key = "spp",
                   .scene = "spp",
                   .svg = "convergence-spp.svg",
                   .svg_alt = "convergence-spp-scenes.svg",
                   .x_title = "samples per pixel, equal samples",
                   .x_name = "samples per pixel (log)"},
};

double bench_loglog_slope(const double *x, const double *y, int n)
{
    double sx = 0, sy = 0;
    int m = 0;
    for (int k = 0; k < n; k++)
        if (isfinite(x[k]) && isfinite(y[k])) sx += x[k], sy += y[k], m++;
    if (m < 2) return NAN;
    const double mx = sx / m, my = sy / m;
    double sxx = 0, sxy = 0;
    for (int k = 0; k < n; k++)
        if (isfinite(x[k]) && isfinite(y[k])) {
            sxx += (x[k] - mx) * (x[k] - mx);
            sxy += (x[k] - mx) * (y[k] - my);
        }
    return sxx > 0 ? sxy / sxx : NAN;
}

int bench_crossings(const double *t, const double *a, const double *b, int n, double *at,
                    int *after, int cap, int *order)
{
    int found = 0, valid = 0, prev = -1, zero0 = -1, zero1 = -1, below = 0, above = 0;
    double dprev = 0;
    for (int k = 0; k < n; k++) {
        if (!(t[k] > 0 && a[k] > 0 && b[k] > 0 && isfinite(a[k]) && isfinite(b[k]))) continue;
        valid++;
        const double d = log(a[k] / b[k]);
        if (d == 0) { /* equal here: a crossing if the sign differs on either side */
            if (zero0 < 0) zero0 = k;
            zero1 = k;
            continue;
        }
        below += d < 0;
        above += d > 0;
        if (prev >= 0 && (dprev < 0) != (d < 0) && found < cap) {
            if (zero0 >= 0) /* through equality: at the times it was equal (their middle) */
                at[found] = sqrt(t[zero0] * t[zero1]);
            else {
                const double lt0 = log(t[prev]), lt1 = log(t[k]);
                at[found] = exp(lt0 + (0 - dprev) / (d - dprev) * (lt1 - lt0));
            }
            after[found++] = d < 0;
        }
        prev = k;
        dprev = d;
        zero0 = zero1 = -1;
    }
    *order = found || !valid ? 0 : below && !above ? -1 : above && !below ? 1 : 2;
    return found;
}

void bench_convergence_free(bench_convergence *c)
{
    free(c->budget);
    free(c->x);
    free(c->geomean);
    free(c->pairs);
    free(c->slope);
    free(c->sc_geo);
    free(c->sc_slope);
    memset(c, 0, sizeof *c);
}

/* The budget's place on the axis: its seconds or samples per pixel, 0 when it is not on it. */
static double axis_x(const suite_budget *b, bench_axis axis)
{
    if (axis == BENCH_SPP) return b->spp > 0 ? b->spp : 0;
    return !b->spp && b->seconds > 0 ? b->seconds : 0;
}

/* The analysis along one axis (c->nt = 0 with fewer than two budgets on it). */
static int convergence_compute(bench_report *r, bench_axis axis, bench_convergence *c)
{
    const suite *s = r->s;
    memset(c, 0, sizeof *c);
    c->axis = axis;
    int nt = 0;
    for (int b = 0; b < s->nbudgets; b++) nt += axis_x(&s->budgets[b], axis) > 0;
    if (nt < 2) return EXIT_OK;
    const size_t nme = (size_t)s->nmethods, nsc = (size_t)s->nscenes;
    c->budget = calloc((size_t)nt, sizeof *c->budget);
    c->x = calloc((size_t)nt, sizeof *c->x);
    c->geomean = calloc(nme * (size_t)nt, sizeof *c->geomean);
    c->pairs = calloc(nme * (size_t)nt, sizeof *c->pairs);
    c->slope = calloc(nme, sizeof *c->slope);
    c->sc_geo = calloc(nsc * nme * (size_t)nt, sizeof *c->sc_geo);
    c->sc_slope = calloc(nsc * nme, sizeof *c->sc_slope);
    double *logt = calloc((size_t)nt, sizeof *logt), *logg = calloc((size_t)nt, sizeof *logg);
    if (!c->budget || !c->x || !c->geomean || !c->pairs || !c->slope || !c->sc_geo ||
        !c->sc_slope || !logt || !logg) {
        bench_convergence_free(c);
        free(logt);
        free(logg);
        return tool_runtime_error("bench: out of memory");
    }
    c->nt = nt;
    nt = 0;
    for (int b = 0; b < s->nbudgets; b++) {
        const double x = axis_x(&s->budgets[b], axis);
        if (!(x > 0)) continue;
        int k = nt++; /* insertion by increasing x */
        while (k > 0 && axis_x(&s->budgets[c->budget[k - 1]], axis) > x) {
            c->budget[k] = c->budget[k - 1];
            k--;
        }
        c->budget[k] = b;
    }
    for (int k = 0; k < nt; k++) {
        c->x[k] = axis_x(&s->budgets[c->budget[k]], axis);
        logt[k] = log(c->x[k]);
    }
    /* scene -1: every pair; otherwise that scene's maps */
    for (int sc = -1; sc < s->nscenes; sc++)
        for (int me = 0; me < s->nmethods; me++) {
            double *geo = sc < 0 ? c->geomean + (size_t)me * nt
                                 : c->sc_geo + ((size_t)sc * nme + (size_t)me) * nt;
            for (int k = 0; k < nt; k++) {
                double sum = 0;
                int n = 0;
                for (int m = 0; m < s->nmaps; m++)
                    for (int sc2 = sc < 0 ? 0 : sc; sc2 < (sc < 0 ? s->nscenes : sc + 1); sc2++) {
                        const result *x = &r->res[bench_idx(s, m, sc2, me, c->budget[k])];
                        const double v = x->v[M_RELMSE];
                        if (!x->present || !(v > 0) || !isfinite(v)) continue;
                        sum += log(v);
                        n++;
                    }
                geo[k] = n ? exp(sum / n) : NAN;
                logg[k] = n ? sum / n : NAN;
                if (sc < 0) c->pairs[(size_t)me * nt + k] = n;
            }
            const double slope = bench_loglog_slope(logt, logg, nt);
            if (sc < 0)
                c->slope[me] = slope;
            else
                c->sc_slope[(size_t)sc * nme + (size_t)me] = slope;
        }
    free(logt);
    free(logg);
    return EXIT_OK;
}

int bench_convergence_compute(bench_report *r)
{
    for (int axis = 0; axis < BENCH_NAXES; axis++)
        if (convergence_compute(r, (bench_axis)axis, &r->conv[axis]) != EXIT_OK)
            return EXIT_RUNTIME; /* bench_report_free frees the others */
    return EXIT_OK;
}

const char *bench_convergence_svg_name(const suite *s, bench_axis axis)
{
    const bench_axis_words *w = &bench_axes[axis];
    for (int sc = 0; sc < s->nscenes; sc++)
        if (strcmp(s->scenes[sc].label, w->scene) == 0) return w->svg_alt;
    return w->svg;
}

static void fmt_slope(char *buf, size_t cap, double v)
{
    if (isfinite(v))
        snprintf(buf, cap, "%.2f", fabs(v) < 0.005 ? 0.0 : v); /* no "-0.00" */
    else
        snprintf(buf, cap, "–");
}

/* The crossings of methods a and b as text: in seconds or samples per pixel, or the order at
 * every budget. */
static void crossing_text(char *out, size_t cap, const bench_report *r, const bench_convergence *c,
                          int a, int b)
{
    const suite *s = r->s;
    const char *la = s->methods[a].label, *lb = s->methods[b].label;
    double at[64];
    int after[64], order;
    int n = bench_crossings(c->x, c->geomean + (size_t)a * c->nt, c->geomean + (size_t)b * c->nt,
                            c->nt, at, after, 64, &order);
    out[0] = '\0';
    if (!n) {
        if (order == 2)
            snprintf(out, cap, "%s equal to %s at every budget", la, lb);
        else if (order)
            snprintf(out, cap, "%s %s %s at every budget", la, order < 0 ? "below" : "above", lb);
        else
            snprintf(out, cap, "–");
        return;
    }
    for (int k = 0; k < n; k++) {
        size_t len = strlen(out);
        snprintf(out + len, cap - len, "%s%.3g%s (%s %s after)", k ? "; " : "", at[k],
                 bench_axes[c->axis].unit, la, after[k] ? "below" : "above");
    }
}

void bench_write_convergence(FILE *f, bench_markup mk, const bench_report *r,
                             const bench_convergence *c)
{
    const suite *s = r->s;
    const bench_axis_words *w = &bench_axes[c->axis];
    if (c->nt < 2) return;
    const int nt = c->nt, ncol = 1 + nt + 2 + (s->nscenes > 1 ? s->nscenes : 0);
    char(*cells)[4200] = calloc((size_t)(ncol > nt + 2 ? ncol : nt + 2), sizeof *cells);
    if (!cells) return;
    char text[2048];
    bench_heading(f, mk, w->title);
    snprintf(text, sizeof text,
             "Per %s, the geometric mean of relMSE over the (map, scene) pairs that "
             "have a result (pairs: how many, per budget); slope: of log(relMSE) against "
             "%s, least squares over the budgets, over all pairs%s. A consistent "
             "Monte Carlo estimator has slope −1; a biased one flattens towards 0 as its bias "
             "dominates the error.%s%s",
             w->budget, w->log_x,
             s->nscenes > 1 ? " and per scene (the geometric mean over its maps)" : "",
             s->nbudgets > nt ? w->others : "", w->note);
    if (mk == BENCH_MD) /* straight under the heading */
        fprintf(f, "%s\n\n", text);
    else
        bench_paragraph(f, mk, text);
    bench_table_begin(f, mk);
    snprintf(cells[0], sizeof cells[0], "method");
    for (int k = 0; k < nt; k++)
        snprintf(cells[1 + k], sizeof cells[0], "%s", s->budgets[c->budget[k]].label);
    snprintf(cells[1 + nt], sizeof cells[0], "pairs");
    snprintf(cells[2 + nt], sizeof cells[0], "slope");
    for (int sc = 0; s->nscenes > 1 && sc < s->nscenes; sc++)
        snprintf(cells[3 + nt + sc], sizeof cells[0], "slope %s", s->scenes[sc].label);
    bench_table_row(f, mk, 1, ncol, cells);
    for (int me = 0; me < s->nmethods; me++) {
        const double *geo = c->geomean + (size_t)me * nt;
        const int *pairs = c->pairs + (size_t)me * nt;
        snprintf(cells[0], sizeof cells[0], "%s", s->methods[me].label);
        int same = 1;
        for (int k = 0; k < nt; k++) {
            bench_fmt_metric(cells[1 + k], sizeof cells[0], geo[k], M_RELMSE);
            same &= pairs[k] == pairs[0];
        }
        cells[1 + nt][0] = '\0';
        for (int k = 0; k < (same ? 1 : nt); k++) {
            size_t len = strlen(cells[1 + nt]);
            snprintf(cells[1 + nt] + len, sizeof cells[0] - len, "%s%d", k ? ", " : "", pairs[k]);
        }
        fmt_slope(cells[2 + nt], sizeof cells[0], c->slope[me]);
        for (int sc = 0; s->nscenes > 1 && sc < s->nscenes; sc++)
            fmt_slope(cells[3 + nt + sc], sizeof cells[0],
                      c->sc_slope[(size_t)sc * s->nmethods + (size_t)me]);
        bench_table_row(f, mk, 0, ncol, cells);
    }
    bench_table_end(f, mk);
    int npairs = 0;
    for (int p = 0; p < s->ncompare; p++)
        npairs += bench_method_index(s, s->compare[p][0]) >= 0 &&
                  bench_method_index(s, s->compare[p][1]) >= 0;
    if (npairs) {
        bench_paragraph(
            f, mk,
            "Compared pairs: the ratio of the geometric means, first / second, per budget "
            "(below 1: the first has the smaller error), and where the first's curve "
            "crosses the second's (log-log interpolation between budgets).");
        if (mk == BENCH_MD) fputs("\n", f);
        bench_table_begin(f, mk);
        snprintf(cells[0], sizeof cells[0], "pair");
        for (int k = 0; k < nt; k++)
            snprintf(cells[1 + k], sizeof cells[0], "%s", s->budgets[c->budget[k]].label);
        snprintf(cells[1 + nt], sizeof cells[0], "crossing");
        bench_table_row(f, mk, 1, nt + 2, cells);
        for (int p = 0; p < s->ncompare; p++) {
            int a = bench_method_index(s, s->compare[p][0]),
                b = bench_method_index(s, s->compare[p][1]);
            if (a < 0 || b < 0) continue;
            snprintf(cells[0], sizeof cells[0], "%s / %s", s->methods[a].label,
                     s->methods[b].label);
            for (int k = 0; k < nt; k++) {
                double ga = c->geomean[(size_t)a * nt + k], gb = c->geomean[(size_t)b * nt + k];
                if (isfinite(ga / gb))
                    snprintf(cells[1 + k], sizeof cells[0], "%.3f", ga / gb);
                else
                    snprintf(cells[1 + k], sizeof cells[0], "–");
            }
            crossing_text(cells[1 + nt], sizeof cells[0], r, c, a, b);
            bench_table_row(f, mk, 0, nt + 2, cells);
        }
        bench_table_end(f, mk);
    }
    /* the plot, when there is one (bench_write_convergence_svg draws none without a value) */
    int plotted = 0;
    for (int k = 0; k < s->nmethods * nt; k++) plotted |= isfinite(c->geomean[k]);
    const char *svg = bench_convergence_svg_name(s, c->axis);
    if (plotted) {
        if (mk == BENCH_HTML)
            fprintf(f,
                    "<p><img src=\"%s\" alt=\"convergence: geometric mean of relMSE over all "
                    "pairs against the %s\" width=\"640\"></p>\n",
                    svg, w->budget);
        else
            fprintf(f, "\n![convergence: geometric mean of relMSE against the %s](%s)\n", w->budget,
                    svg);
    }
    free(cells);
}

static cJSON *json_num_or_null(double v)
{
    return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull();
}

/* results.json's "convergence" (time) or "convergence_spp" object: the same keys, but
 * "spp" wherever the time's has "seconds". */
void bench_json_convergence(cJSON *j, const bench_report *r, const bench_convergence *c)
{
    const suite *s = r->s;
    const bench_axis_words *w = &bench_axes[c->axis];
    if (c->nt < 2) return;
    const int nt = c->nt;
    cJSON *o = cJSON_AddObjectToObject(j, w->json);
    cJSON *lab = cJSON_AddArrayToObject(o, "budgets");
    cJSON *xs = cJSON_AddArrayToObject(o, w->x_key);
    for (int k = 0; k < nt; k++) {
        cJSON_AddItemToArray(lab, cJSON_CreateString(s->budgets[c->budget[k]].label));
        cJSON_AddItemToArray(xs, cJSON_CreateNumber(c->x[k]));
    }
    cJSON *methods = cJSON_AddArrayToObject(o, "methods");
    for (int me = 0; me < s->nmethods; me++) {
        cJSON *m = cJSON_CreateObject();
        cJSON_AddStringToObject(m, "method", s->methods[me].label);
        cJSON *ms = cJSON_AddArrayToObject(m, w->x_key);
        cJSON *g = cJSON_AddArrayToObject(m, "geomean_relmse");
        cJSON *n = cJSON_AddArrayToObject(m, "pairs");
        for (int k = 0; k < nt; k++) {
            cJSON_AddItemToArray(ms, cJSON_CreateNumber(c->x[k]));
            cJSON_AddItemToArray(g, json_num_or_null(c->geomean[(size_t)me * nt + k]));
            cJSON_AddItemToArray(n, cJSON_CreateNumber(c->pairs[(size_t)me * nt + k]));
        }
        cJSON_AddItemToObject(m, "slope", json_num_or_null(c->slope[me]));
        cJSON *ss = cJSON_AddObjectToObject(m, "scene_slopes");
        for (int sc = 0; sc < s->nscenes; sc++)
            cJSON_AddItemToObject(ss, s->scenes[sc].label,
                                  json_num_or_null(c->sc_slope[(size_t)sc * s->nmethods + me]));
        cJSON_AddItemToArray(methods, m);
    }
    cJSON *cmp = cJSON_AddArrayToObject(o, "compare");
    for (int p = 0; p < s->ncompare; p++) {
        int a = bench_method_index(s, s->compare[p][0]),
            b = bench_method_index(s, s->compare[p][1]);
        if (a < 0 || b < 0) continue;
        cJSON *e = cJSON_CreateObject();
        cJSON_AddStringToObject(e, "a", s->methods[a].label);
        cJSON_AddStringToObject(e, "b", s->methods[b].label);
        cJSON *ratio = cJSON_AddArrayToObject(e, "ratio");
        for (int k = 0; k < nt; k++)
            cJSON_AddItemToArray(ratio, json_num_or_null(c->geomean[(size_t)a * nt + k] /
                                                         c->geomean[(size_t)b * nt + k]));
        double at[64];
        int after[64], order;
        int n = bench_crossings(c->x, c->geomean + (size_t)a * nt, c->geomean + (size_t)b * nt, nt,
                                at, after, 64, &order);
        cJSON_AddStringToObject(e, "order",
                                n            ? "crosses"
                                : order < 0  ? "below"
                                : order == 1 ? "above"
                                : order == 2 ? "equal"
                                             : "none");
        cJSON *cross = cJSON_AddArrayToObject(e, "crossings");
        for (int k = 0; k < n; k++) {
            cJSON *x = cJSON_CreateObject();
            cJSON_AddNumberToObject(x, w->x_key, at[k]);
            cJSON_AddStringToObject(x, "below_after", after[k] ? "a" : "b");
            cJSON_AddItemToArray(cross, x);
        }
        cJSON_AddItemToArray(cmp, e);
    }
}
