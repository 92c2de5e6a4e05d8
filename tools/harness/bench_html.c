/* lumis bench: index.html, a page that needs no script and opens from the file system:
 * the tables, the plots and the image grid.  It writes the assets it shows that no other
 * writer does: the FLIP colour scale and the convergence plots of all pairs (equal time,
 * equal samples). */
#include "harness.h"

#include <math.h>
#include <stdio.h>

/* The FLIP maps' colour scale, drawn by the same colour map as the maps themselves:
 * DIR/flip-legend.png, 256 x 1 pixels from 0 to 1. */
static int write_flip_legend(const char *path)
{
    float ramp[256];
    for (int k = 0; k < 256; k++) ramp[k] = (float)k / 255.0f;
    return tool_write_flip_map(path, ramp, 256, 1);
}

/* The legend on the page: the strip stretched to a bar, ticks from 0 to 1 under it. */
static void flip_legend_svg(FILE *h)
{
    const double x0 = 10, w = 320, y = 4, bar = 14;
    fprintf(h,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" "
            "font-family=\"sans-serif\" font-size=\"11\" role=\"img\" "
            "aria-label=\"FLIP colour scale, 0 to 1\">"
            "<image href=\"flip-legend.png\" x=\"%g\" y=\"%g\" width=\"%g\" height=\"%g\" "
            "preserveAspectRatio=\"none\"/>",
            x0 + w + 100, y + bar + 18, x0, y, w, bar);
    for (int k = 0; k <= 4; k++) {
        double x = x0 + w * k / 4.0;
        fprintf(h,
                "<line x1=\"%g\" y1=\"%g\" x2=\"%g\" y2=\"%g\" stroke=\"#333\"/>"
                "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">%g</text>",
                x, y + bar, x, y + bar + 4, x, y + bar + 15, k / 4.0);
    }
    fprintf(h, "<text x=\"%g\" y=\"%g\">FLIP error</text></svg>\n", x0 + w + 14, y + bar - 2);
}

/* Tables, plots, and the image grid of the last budget. */
/* The page's head, title, command line and warnings (failed items, contention, a noisy
 * reference). */
static void html_head(FILE *h, const bench_report *r)
{
    const suite *s = r->s;
    fprintf(h, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>lumis "
               "bench: ");
    tool_markup_escape(h, s->name);
    fprintf(h, "</title>\n<style>body{font-family:sans-serif;margin:24px;max-width:1400px}"
               "table{border-collapse:collapse;margin:8px 0 20px}td,th{border:1px solid #ccc;"
               "padding:3px 8px;text-align:right}th{background:#f3f3f3}td:first-child,"
               "th:first-child{text-align:left}figure{display:inline-block;margin:4px;"
               "text-align:center;font-size:12px;vertical-align:top}figure img{display:block;"
               "max-width:260px;image-rendering:pixelated}figure a{display:block}"
               ".grid{margin-bottom:16px}.warn{background:#fff4e0;border-left:4px solid #e69500;"
               "padding:6px 10px}"
               "</style></head><body>\n<h1>lumis bench: ");
    tool_markup_escape(h, s->name);
    fprintf(h, "</h1>\n<p>");
    tool_markup_escape(h, s->description);
    fprintf(h, "</p>\n<p>Command: <code>");
    tool_markup_escape(h, r->cmd);
    fprintf(h,
            "</code><br>lumis %s, %s, %s. %d of %d items. Reference: %d spp. Errors "
            "against the reference; lower is better except PSNR. Details: "
            "<a href=\"results.md\">results.md</a>, <a href=\"results.csv\">results.csv</a>, "
            "<a href=\"results.json\">results.json</a>.</p>\n",
            LUMIS_VERSION_STRING, r->date, r->machine, r->found, bench_nlisted(s), s->ref_spp);
    bench_write_failures(h, BENCH_HTML, r);
    int contended = 0;
    for (int k = 0; k < r->n; k++) contended += r->res[k].present && r->res[k].contended;
    if (contended) {
        fputs("<div class=\"warn\">", h);
        bench_write_contention_warning(h, BENCH_HTML, r);
        fputs("</div>\n", h);
    }
    int most;
    if (bench_noisy_reference(r, -1, -1, &most)) {
        fputs("<div class=\"warn\">", h);
        bench_write_reference_warning(h, BENCH_HTML, r);
        fputs("</div>\n", h);
    }
}

int bench_write_html(const bench_report *r, const char *path)
{
    const suite *s = r->s;
    const result *res = r->res;
    const summary *sum = r->sum;
    const char *out = r->out;
    char file[8800];
    snprintf(file, sizeof file, "%s/flip-legend.png", out);
    if (write_flip_legend(file) != EXIT_OK) return EXIT_RUNTIME;
    for (int axis = 0; axis < BENCH_NAXES; axis++)
        if (bench_write_convergence_svg(r, &r->conv[axis]) != EXIT_OK) return EXIT_RUNTIME;
    FILE *h = tmpfile();
    if (!h) return tool_runtime_error("bench: cannot write a temporary file");
    html_head(h, r);
    for (int b = 0; b < s->nbudgets; b++) {
        fprintf(h,
                "<h2>Budget %s</h2>\n<table><tr><th>method</th><th>n</th><th>spp</th>"
                "<th>render s</th>",
                s->budgets[b].label);
        for (int m = 0; m < NMETRICS; m++) fprintf(h, "<th>%s</th>", bench_metric_title[m]);
        fprintf(h, "<th>rank relMSE</th><th>rank FLIP-LDR</th></tr>\n");
        for (int me = 0; me < s->nmethods; me++) {
            const summary *u = &sum[b * s->nmethods + me];
            fprintf(h, "<tr><td>%s</td><td>%d</td><td>%.1f</td><td>%.3f</td>", s->methods[me].label,
                    u->n, u->spp, u->seconds);
            char buf[64];
            for (int m = 0; m < NMETRICS; m++) {
                bench_fmt_metric(buf, sizeof buf, u->n ? u->mean[m] : NAN, m);
                fprintf(h, "<td>%s</td>", buf);
            }
            for (int m = M_RELMSE; m <= M_FLIP_LDR; m += M_FLIP_LDR - M_RELMSE) {
                if (isnan(u->rank[m]))
                    fprintf(h, "<td>–</td>");
                else
                    fprintf(h, "<td>%.2f</td>", u->rank[m]);
            }
            fprintf(h, "</tr>\n");
        }
        fprintf(h, "</table>\n");
    }
    bench_write_comparisons(h, BENCH_HTML, s, res);
    bench_write_auto(h, BENCH_HTML, r);
    for (int axis = 0; axis < BENCH_NAXES; axis++)
        bench_write_convergence(h, BENCH_HTML, r, &r->conv[axis]);
    bench_write_per_map(h, BENCH_HTML, s, res);
    fprintf(h, "<h2>Convergence</h2>\n");
    for (int sc = 0; sc < s->nscenes; sc++) {
        snprintf(file, sizeof file, "%s/convergence-%s.svg", out, s->scenes[sc].label);
        if (bench_file_exists(file))
            fprintf(h,
                    "<img src=\"convergence-%s.svg\" alt=\"convergence, %s\" "
                    "width=\"640\">\n",
                    s->scenes[sc].label, s->scenes[sc].label);
    }
    int lb = s->nbudgets - 1;
    fprintf(h,
            "<h2>Images (budget %s): render, then its FLIP error map</h2>\n<p>Each image "
            "links to its full size. FLIP error maps (%s-FLIP) use this scale:</p>\n",
            s->budgets[lb].label, s->flip_hdr ? "HDR" : "LDR");
    flip_legend_svg(h);
    for (int m = 0; m < s->nmaps; m++)
        for (int sc = 0; sc < s->nscenes; sc++) {
            char key[32];
            bench_reference_key(s, m, sc, key, sizeof key);
            fprintf(h, "<div class=\"grid\"><h3>%s / %s</h3>\n", s->maps[m].label,
                    s->scenes[sc].label);
            snprintf(file, sizeof file, "%s/refs/%s.png", out, key);
            if (bench_file_exists(file))
                fprintf(h,
                        "<figure><a href=\"refs/%s.png\"><img src=\"refs/%s.png\" "
                        "alt=\"reference\" loading=\"lazy\"></a>reference</figure>\n",
                        key, key);
            for (int me = 0; me < s->nmethods; me++) {
                int k = bench_idx(s, m, sc, me, lb);
                if (!res[k].present) continue;
                item it = bench_item_at(s, k);
                fprintf(h,
                        "<figure><a href=\"previews/%s.png\"><img src=\"previews/%s.png\" "
                        "alt=\"%s\" loading=\"lazy\"></a><a href=\"previews/%s-flip.png\">"
                        "<img src=\"previews/%s-flip.png\" alt=\"FLIP %s\" loading=\"lazy\"></a>"
                        "%s: relMSE %.3g, FLIP %.3f</figure>\n",
                        it.id, it.id, it.id, it.id, it.id, it.id, s->methods[me].label,
                        res[k].v[M_RELMSE],
                        s->flip_hdr ? res[k].v[M_FLIP_HDR] : res[k].v[M_FLIP_LDR]);
            }
            fprintf(h, "</div>\n");
        }
    fprintf(h, "</body></html>\n");
    return tool_commit_tmp(h, path);
}
