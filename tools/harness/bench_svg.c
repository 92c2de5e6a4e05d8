/* lumis bench: convergence plots (SVG, no dependency): relMSE against render time,
 * log-log, one line per method through its budgets, one plot per scene; and the convergence
 * analyses' plots (geometric means over all pairs against the time or sample budget). */
#include "harness.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static const char *const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                      "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

/* A log-log plot: nseries lines of npts points each, px[2 * (series * npts + k)] = (log10 x,
 * log10 y), NAN: no point; a legend of labels[series].  Nothing to plot: no file, and no
 * stale one. */
static int write_loglog(const char *path, const char *title, const char *xunit, const char *xname,
                        const char *yname, int nseries, const char *const *labels, const double *px,
                        int npts)
{
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    size_t longest = 0;
    for (int me = 0; me < nseries; me++) {
        if (strlen(labels[me]) > longest) longest = strlen(labels[me]);
        for (int b = 0; b < npts; b++) {
            const double *p = px + 2 * (me * npts + b);
            if (isnan(p[0]) || isnan(p[1])) continue;
            xmin = fmin(xmin, p[0]);
            xmax = fmax(xmax, p[0]);
            ymin = fmin(ymin, p[1]);
            ymax = fmax(ymax, p[1]);
        }
    }
    if (!isfinite(xmin)) { /* nothing to plot: no stale plot either */
        unlink(path);
        return EXIT_OK;
    }
    xmin = floor(xmin - 0.05), xmax = ceil(xmax + 0.05);
    ymin = floor(ymin - 0.05), ymax = ceil(ymax + 0.05);
    /* the legend's width: 170 px, more for long labels (about 7 px a character) */
    const double R = fmax(170, 44 + 7.0 * (double)longest);
    const double H = 420, L = 70, T = 30, B = 50, W = 470 + R;
    FILE *f = tmpfile();
    if (!f) return tool_runtime_error("%s: cannot write a temporary file", path);
#define X(v) (L + ((v)-xmin) / (xmax - xmin) * (W - L - R))
#define Y(v) (H - B - ((v)-ymin) / (ymax - ymin) * (H - T - B))
    fprintf(f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" "
            "viewBox=\"0 0 %g %g\" font-family=\"sans-serif\" font-size=\"12\">\n"
            "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
            "<text x=\"%g\" y=\"18\" font-size=\"14\">%s</text>\n",
            W, H, W, H, L, title);
    for (double d = xmin; d <= xmax + 1e-9; d += 1)
        fprintf(f,
                "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>"
                "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">1e%g%s</text>\n",
                X(d), T, X(d), H - B, X(d), H - B + 16, d, xunit);
    for (double d = ymin; d <= ymax + 1e-9; d += 1)
        fprintf(f,
                "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">1e%g</text>\n",
                L, Y(d), W - R, Y(d), L - 6, Y(d) + 4, d);
    fprintf(f,
            "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">%s</text>\n"
            "<text x=\"16\" y=\"%g\" transform=\"rotate(-90 16 %g)\" "
            "text-anchor=\"middle\">%s</text>\n",
            (L + W - R) / 2, H - 12, xname, (T + H - B) / 2, (T + H - B) / 2, yname);
    for (int me = 0; me < nseries; me++) {
        const char *col = palette[me % 8];
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"", col);
        for (int b = 0; b < npts; b++) {
            const double *p = px + 2 * (me * npts + b);
            if (!isnan(p[0]) && !isnan(p[1])) fprintf(f, "%.1f,%.1f ", X(p[0]), Y(p[1]));
        }
        fprintf(f, "\"/>\n");
        for (int b = 0; b < npts; b++) {
            const double *p = px + 2 * (me * npts + b);
            if (!isnan(p[0]) && !isnan(p[1]))
                fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"%s\"/>\n", X(p[0]),
                        Y(p[1]), col);
        }
        fprintf(f,
                "<rect x=\"%g\" y=\"%d\" width=\"14\" height=\"4\" fill=\"%s\"/>"
                "<text x=\"%g\" y=\"%d\">%s</text>\n",
                W - R + 14, 40 + 18 * me, col, W - R + 34, 45 + 18 * me, labels[me]);
    }
#undef X
#undef Y
    fprintf(f, "</svg>\n");
    return tool_commit_tmp(f, path);
}

/* relMSE (mean over maps) against render time (mean over maps), log-log, per scene. */
int bench_write_svg(const char *path, const suite *s, const result *res, int sc)
{
    double *px = calloc((size_t)s->nmethods * (size_t)s->nbudgets * 2, sizeof *px);
    const char **labels = calloc((size_t)s->nmethods, sizeof *labels);
    if (!px || !labels) {
        free(px);
        free(labels);
        return tool_runtime_error("bench: out of memory");
    }
    for (int me = 0; me < s->nmethods; me++) {
        labels[me] = s->methods[me].label;
        for (int b = 0; b < s->nbudgets; b++) {
            double t = 0, e = 0;
            int n = 0;
            for (int m = 0; m < s->nmaps; m++) {
                const result *r = &res[bench_idx(s, m, sc, me, b)];
                if (!r->present || !(r->v[M_RELMSE] > 0) || !(r->seconds > 0)) continue;
                t += r->seconds;
                e += r->v[M_RELMSE];
                n++;
            }
            double *p = px + 2 * (me * s->nbudgets + b);
            p[0] = n ? log10(t / n) : NAN;
            p[1] = n ? log10(e / n) : NAN;
        }
    }
    char title[300];
    snprintf(title, sizeof title, "%s: relMSE vs render time (means over maps)",
             s->scenes[sc].label);
    int rc = write_loglog(path, title, " s", "render time (log)", "relMSE (log)", s->nmethods,
                          labels, px, s->nbudgets);
    free(px);
    free(labels);
    return rc;
}

/* The geometric mean of relMSE over all pairs against the budget of c's axis, one line per
 * method with its slope in the legend. */
int bench_write_convergence_svg(const bench_report *r, const bench_convergence *c)
{
    const suite *s = r->s;
    const bench_axis_words *w = &bench_axes[c->axis];
    char path[8800], title[200];
    snprintf(path, sizeof path, "%s/%s", r->out, bench_convergence_svg_name(s, c->axis));
    if (c->nt < 2) { /* no analysis: no plot, and no stale one */
        unlink(path);
        return EXIT_OK;
    }
    const int nt = c->nt;
    double *px = calloc((size_t)s->nmethods * (size_t)nt * 2, sizeof *px);
    char(*labels)[200] = calloc((size_t)s->nmethods, sizeof *labels);
    const char **lp = calloc((size_t)s->nmethods, sizeof *lp);
    if (!px || !labels || !lp) {
        free(px);
        free(labels);
        free(lp);
        return tool_runtime_error("bench: out of memory");
    }
    for (int me = 0; me < s->nmethods; me++) {
        if (isfinite(c->slope[me]))
            snprintf(labels[me], sizeof labels[me], "%s (slope %.2f)", s->methods[me].label,
                     fabs(c->slope[me]) < 0.005 ? 0.0 : c->slope[me]); /* no "-0.00" */
        else
            snprintf(labels[me], sizeof labels[me], "%s", s->methods[me].label);
        lp[me] = labels[me];
        for (int k = 0; k < nt; k++) {
            const double g = c->geomean[(size_t)me * nt + k];
            px[2 * (me * nt + k)] = log10(c->x[k]);
            px[2 * (me * nt + k) + 1] = g > 0 && isfinite(g) ? log10(g) : NAN;
        }
    }
    snprintf(title, sizeof title, "relMSE (geometric mean over all pairs) vs %s", w->x_title);
    int rc = write_loglog(path, title, w->unit, w->x_name, "relMSE (log)", s->nmethods, lp, px, nt);
    free(px);
    free(labels);
    free(lp);
    return rc;
}
