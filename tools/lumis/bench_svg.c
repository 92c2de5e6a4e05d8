/* lumis bench: convergence plots (SVG, no dependency): relMSE against render time,
 * log-log, one line per method through its budgets, one plot per scene. */
#include "bench.h"

#include <math.h>
#include <stdlib.h>
#include <unistd.h>

static const char *const palette[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd",
                                      "#ff7f0e", "#8c564b", "#e377c2", "#17becf"};

/* relMSE (mean over maps) against render time (mean over maps), log-log, per scene. */
int bench_write_svg(const char *path, const suite *s, const result *res, int sc)
{
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    double *px = calloc((size_t)s->nmethods * (size_t)s->nbudgets * 2, sizeof *px);
    if (!px) return tool_runtime_error("bench: out of memory");
    for (int me = 0; me < s->nmethods; me++)
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
            if (n) {
                xmin = fmin(xmin, p[0]);
                xmax = fmax(xmax, p[0]);
                ymin = fmin(ymin, p[1]);
                ymax = fmax(ymax, p[1]);
            }
        }
    if (!isfinite(xmin)) { /* nothing to plot: no stale plot either */
        free(px);
        unlink(path);
        return EXIT_OK;
    }
    xmin = floor(xmin - 0.05), xmax = ceil(xmax + 0.05);
    ymin = floor(ymin - 0.05), ymax = ceil(ymax + 0.05);
    const double W = 640, H = 420, L = 70, R = 170, T = 30, B = 50;
    FILE *f = tmpfile();
    if (!f) {
        free(px);
        return tool_runtime_error("%s: cannot write a temporary file", path);
    }
#define X(v) (L + ((v)-xmin) / (xmax - xmin) * (W - L - R))
#define Y(v) (H - B - ((v)-ymin) / (ymax - ymin) * (H - T - B))
    fprintf(f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" "
            "viewBox=\"0 0 %g %g\" font-family=\"sans-serif\" font-size=\"12\">\n"
            "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
            "<text x=\"%g\" y=\"18\" font-size=\"14\">%s: relMSE vs render time (means over "
            "maps)</text>\n",
            W, H, W, H, L, s->scenes[sc].label);
    for (double d = xmin; d <= xmax + 1e-9; d += 1)
        fprintf(f,
                "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/>"
                "<text x=\"%.1f\" y=\"%g\" text-anchor=\"middle\">1e%g s</text>\n",
                X(d), T, X(d), H - B, X(d), H - B + 16, d);
    for (double d = ymin; d <= ymax + 1e-9; d += 1)
        fprintf(f,
                "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/>"
                "<text x=\"%g\" y=\"%.1f\" text-anchor=\"end\">1e%g</text>\n",
                L, Y(d), W - R, Y(d), L - 6, Y(d) + 4, d);
    fprintf(f,
            "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">render time (log)</text>\n"
            "<text x=\"16\" y=\"%g\" transform=\"rotate(-90 16 %g)\" "
            "text-anchor=\"middle\">relMSE (log)</text>\n",
            (L + W - R) / 2, H - 12, (T + H - B) / 2, (T + H - B) / 2);
    for (int me = 0; me < s->nmethods; me++) {
        const char *col = palette[me % 8];
        fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\" points=\"", col);
        for (int b = 0; b < s->nbudgets; b++) {
            const double *p = px + 2 * (me * s->nbudgets + b);
            if (!isnan(p[0])) fprintf(f, "%.1f,%.1f ", X(p[0]), Y(p[1]));
        }
        fprintf(f, "\"/>\n");
        for (int b = 0; b < s->nbudgets; b++) {
            const double *p = px + 2 * (me * s->nbudgets + b);
            if (!isnan(p[0]))
                fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.5\" fill=\"%s\"/>\n", X(p[0]),
                        Y(p[1]), col);
        }
        fprintf(f,
                "<rect x=\"%g\" y=\"%d\" width=\"14\" height=\"4\" fill=\"%s\"/>"
                "<text x=\"%g\" y=\"%d\">%s</text>\n",
                W - R + 14, 40 + 18 * me, col, W - R + 34, 45 + 18 * me, s->methods[me].label);
    }
#undef X
#undef Y
    fprintf(f, "</svg>\n");
    free(px);
    return bench_commit_tmp(f, path);
}
