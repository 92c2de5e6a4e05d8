/* lumis bench: the report's markup, shared by its tables (bench_tables.c) and its
 * convergence analysis (bench_convergence.c): Markdown or HTML headings, paragraphs and
 * tables, a method by label, a metric as the tables print it. */
#include "harness.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int bench_method_index(const suite *s, const char *label)
{
    for (int k = 0; k < s->nmethods; k++)
        if (strcmp(s->methods[k].label, label) == 0) return k;
    return -1;
}

/* One row of a table, in Markdown ("| a | b |", a rule under the header) or HTML.  The
 * cells are labels and numbers: nothing in them needs escaping. */
void bench_table_row(FILE *f, bench_markup mk, int header, int n, char cells[][4200])
{
    if (mk == BENCH_HTML) {
        fputs("<tr>", f);
        for (int k = 0; k < n; k++) fprintf(f, header ? "<th>%s</th>" : "<td>%s</td>", cells[k]);
        fputs("</tr>\n", f);
        return;
    }
    fputs("|", f);
    for (int k = 0; k < n; k++) fprintf(f, " %s |", cells[k]);
    fputs("\n", f);
    if (!header) return;
    fputs("|", f);
    for (int k = 0; k < n; k++) fputs("---|", f);
    fputs("\n", f);
}

void bench_heading(FILE *f, bench_markup mk, const char *text)
{
    fprintf(f, mk == BENCH_HTML ? "<h2>%s</h2>\n" : "\n## %s\n\n", text);
}

void bench_table_end(FILE *f, bench_markup mk)
{
    if (mk == BENCH_HTML) fputs("</table>\n", f);
}

void bench_table_begin(FILE *f, bench_markup mk)
{
    if (mk == BENCH_HTML) fputs("<table>\n", f);
}

void bench_paragraph(FILE *f, bench_markup mk, const char *text)
{
    fprintf(f, mk == BENCH_HTML ? "<p>%s</p>\n" : "\n%s\n", text);
}

void bench_fmt_metric(char *buf, size_t cap, double v, int metric)
{
    if (isnan(v))
        snprintf(buf, cap, "–");
    else if (isinf(v))
        snprintf(buf, cap, "∞");
    else if (metric == M_PSNR)
        snprintf(buf, cap, "%.2f", v);
    else
        snprintf(buf, cap, "%.4g", v);
}
