/* Table-driven option parsing: one parser, --help and Markdown from each command's table
 * (optparse.h). */
#include "optparse.h"

#include "../app/errors.h"
#include "../args.h"
#include "lumis/io.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* A range's end as people write it: 90, 1.7, 1e30 (not 1e+30). */
static void format_number(char *buf, size_t n, double x)
{
    if (x == floor(x) && fabs(x) < 1e15) {
        snprintf(buf, n, "%.0f", x);
        return;
    }
    char tmp[48];
    snprintf(tmp, sizeof tmp, "%g", x);
    size_t o = 0;
    for (const char *p = tmp; *p && o + 1 < n; p++) {
        if (*p == '+' && p > tmp && p[-1] == 'e') continue;
        if (*p == '0' && p > tmp && (p[-1] == 'e' || (p[-1] == '-' && p > tmp + 1 && p[-2] == 'e')))
            continue;
        buf[o++] = *p;
    }
    buf[o] = '\0';
}

/* "needs a count in [1, 4096]" for a number option (none of the range when unbounded). */
static int bad_number(const char *cmd, const char *name, const tool_opt *o, const char *v,
                      const char *dflt)
{
    const char *what = o->what ? o->what : dflt;
    char need[160], lo[48], hi[48];
    if (isinf(o->lo) && isinf(o->hi)) {
        snprintf(need, sizeof need, "needs %s", what);
    } else {
        format_number(lo, sizeof lo, o->lo);
        format_number(hi, sizeof hi, o->hi);
        snprintf(need, sizeof need, "needs %s in %c%s, %s%c", what, o->open_lo ? '(' : '[', lo, hi,
                 o->open_hi ? ')' : ']');
    }
    return tool_bad_value(cmd, name, v, need);
}

static void *field(void *ctx, size_t at)
{
    return (char *)ctx + at;
}

/* The value of option o (given as `name`) into ctx.  Exit code. */
static int take(const char *cmd, const tool_opt *o, const char *name, const char *v, void *ctx)
{
    char need[192];
    switch (o->kind) {
    case TOOL_OPT_FLAG:
        *(int *)field(ctx, o->at) = 1;
        return EXIT_OK;
    case TOOL_OPT_INT:
    case TOOL_OPT_LONG: {
        long x;
        if (!tool_parse_int(v, (long)o->lo, (long)o->hi, &x))
            return bad_number(cmd, name, o, v, "a count");
        if (o->kind == TOOL_OPT_INT)
            *(int *)field(ctx, o->at) = (int)x;
        else
            *(long *)field(ctx, o->at) = x;
        return EXIT_OK;
    }
    case TOOL_OPT_U64: {
        unsigned long long x;
        if (!tool_parse_u64(v, 10, &x) || (o->hi > 0 && (double)x > o->hi)) {
            char hi[48] = "2^64 - 1";
            if (o->hi > 0) format_number(hi, sizeof hi, o->hi);
            snprintf(need, sizeof need, "needs %s in [0, %s]", o->what ? o->what : "an integer",
                     hi);
            return tool_bad_value(cmd, name, v, need);
        }
        *(unsigned long long *)field(ctx, o->at) = x;
        return EXIT_OK;
    }
    case TOOL_OPT_DOUBLE:
    case TOOL_OPT_FLOAT: {
        double x;
        if (!tool_parse_double(v, &x) || x < o->lo || x > o->hi || (o->open_lo && x == o->lo) ||
            (o->open_hi && x == o->hi))
            return bad_number(cmd, name, o, v, "a number");
        if (o->kind == TOOL_OPT_DOUBLE)
            *(double *)field(ctx, o->at) = x;
        else
            *(float *)field(ctx, o->at) = (float)x;
        return EXIT_OK;
    }
    case TOOL_OPT_STRING:
        if (!v || !*v) {
            snprintf(need, sizeof need, "needs %s", o->what ? o->what : "a value");
            return tool_bad_value(cmd, name, v, need);
        }
        *(const char **)field(ctx, o->at) = v;
        return EXIT_OK;
    case TOOL_OPT_SIZE: {
        int w, h;
        const double cap = o->hi > 0 ? o->hi : INT_MAX;
        if (!tool_parse_size(v, &w, &h) || w > cap || h > cap) {
            char hi[48];
            format_number(hi, sizeof hi, cap);
            if (o->hi > 0)
                snprintf(need, sizeof need, "needs WxH up to %sx%s", hi, hi);
            else
                snprintf(need, sizeof need, "needs WxH, e.g. %s", o->what ? o->what : "1024x512");
            return tool_bad_value(cmd, name, v, need);
        }
        *(int *)field(ctx, o->at) = w;
        *(int *)field(ctx, o->at2) = h;
        return EXIT_OK;
    }
    case TOOL_OPT_EXPOSURE: {
        double x;
        float *ev = field(ctx, o->at);
        int *is_auto = field(ctx, o->at2);
        if (v && strcmp(v, "auto") == 0) {
            *is_auto = 1;
            *ev = 0.0f;
            return EXIT_OK;
        }
        if (!tool_parse_double(v, &x) || x < -64 || x > 64)
            return tool_usage_error(cmd, "%s needs 'auto' or stops in [-64, 64], not '%s'", name,
                                    v ? v : "");
        *is_auto = 0;
        *ev = (float)x;
        return EXIT_OK;
    }
    case TOOL_OPT_PARSE:
        if (!v || !o->parse(v, field(ctx, o->at)))
            return tool_bad_value(cmd, name, v, o->what ? o->what : "is not known");
        return EXIT_OK;
    case TOOL_OPT_CUSTOM:
        return o->handle(cmd, o, v, ctx);
    case TOOL_OPT_END:
    case TOOL_OPT_GROUP:
        break;
    }
    return EXIT_OK;
}

/* Edit distance of a[0..na) and b (capped: only small distances matter). */
static size_t distance(const char *a, size_t na, const char *b)
{
    const size_t nb = strlen(b);
    if (na > 63 || nb > 63) return 99;
    size_t row[64];
    for (size_t j = 0; j <= nb; j++) row[j] = j;
    for (size_t i = 1; i <= na; i++) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= nb; j++) {
            const size_t up = row[j];
            const size_t sub = diag + (a[i - 1] != b[j - 1]);
            size_t best = up + 1 < row[j - 1] + 1 ? up + 1 : row[j - 1] + 1;
            row[j] = sub < best ? sub : best;
            diag = up;
        }
    }
    return row[nb];
}

static int unknown_option(const tool_optspec *spec, const char *arg)
{
    const size_t n = strcspn(arg, "=");
    const char *best = NULL;
    size_t best_d = (n + 2) / 4 + 1; /* a typo or two, not another word */
    if (best_d > 3) best_d = 3;
    for (const tool_opt *o = spec->opts; o->kind != TOOL_OPT_END; o++) {
        if (o->kind == TOOL_OPT_GROUP) continue;
        const size_t d = distance(arg, n, o->name);
        if (d <= best_d && (!best || d < distance(arg, n, best))) best = o->name;
    }
    if (best)
        return tool_usage_error(spec->cmd, "unknown option '%s' (did you mean %s?)", arg, best);
    return tool_usage_error(spec->cmd, "unknown option '%s'", arg);
}

/* Whether argv[*i] is option o; then *value (and *i past it) as tool_option, and *name the
 * spelling given. */
static int matches(const tool_opt *o, int argc, char **argv, int *i, const char **value,
                   const char **name)
{
    const char *names[2] = {o->name, o->alias};
    for (int k = 0; k < 2; k++) {
        if (!names[k]) continue;
        *name = names[k];
        if (!o->metavar) {
            if (strcmp(argv[*i], names[k]) == 0) {
                *value = NULL;
                return 1;
            }
            const size_t n = strlen(names[k]);
            if (strncmp(argv[*i], names[k], n) == 0 && argv[*i][n] == '=') {
                *value = argv[*i]; /* a flag with a value: refused by the caller */
                return 2;
            }
        } else if (tool_option(argc, argv, i, names[k], value)) {
            return 1;
        }
    }
    return 0;
}

int tool_optparse(const tool_optspec *spec, int argc, char **argv, void *ctx)
{
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (tool_is_help(a)) {
            tool_opthelp(spec, stdout);
            return EXIT_OK;
        }
        if (!(a[0] == '-' && a[1])) {
            if (!spec->positional) return tool_usage_error(spec->cmd, "unknown argument '%s'", a);
            const int rc = spec->positional(spec->cmd, a, ctx);
            if (rc != EXIT_OK) return rc;
            continue;
        }
        const tool_opt *o = spec->opts;
        const char *v = NULL, *name = NULL;
        int m = 0;
        for (; o->kind != TOOL_OPT_END; o++)
            if (o->kind != TOOL_OPT_GROUP && (m = matches(o, argc, argv, &i, &v, &name)) != 0)
                break;
        if (o->kind == TOOL_OPT_END) return unknown_option(spec, a);
        if (m == 2) return tool_usage_error(spec->cmd, "%s takes no value ('%s')", name, v);
        if (o->note) *(const char **)field(ctx, o->note - 1) = o->name;
        const int rc = take(spec->cmd, o, name, v, ctx);
        if (rc != EXIT_OK) return rc;
    }
    return -1;
}

/* "-o, --output OUT" */
static void left_column(const tool_opt *o, char *buf, size_t n)
{
    const char *value = o->metavar ? o->metavar : o->then;
    snprintf(buf, n, "%s%s%s%s%s", o->alias ? o->alias : "", o->alias ? ", " : "", o->name,
             value ? " " : "", value ? value : "");
}

void tool_opthelp(const tool_optspec *spec, FILE *f)
{
    fprintf(f, "%s\n\n", spec->usage);
    if (spec->intro) fprintf(f, "%s\n\n", spec->intro);
    /* the help column: after the widest option up to 20 columns (wider ones run into it) */
    size_t col = 0;
    for (const tool_opt *o = spec->opts; o->kind != TOOL_OPT_END; o++) {
        char left[128];
        if (o->kind == TOOL_OPT_GROUP) continue;
        left_column(o, left, sizeof left);
        if (strlen(left) > col && strlen(left) <= 20) col = strlen(left);
    }
    if (spec->opts[0].kind != TOOL_OPT_GROUP && spec->opts[0].kind != TOOL_OPT_END)
        fputs("options:\n", f);
    for (const tool_opt *o = spec->opts; o->kind != TOOL_OPT_END; o++) {
        if (o->kind == TOOL_OPT_GROUP) {
            fprintf(f, "%s%s:\n", o == spec->opts ? "" : "\n", o->name);
            continue;
        }
        char left[128];
        left_column(o, left, sizeof left);
        fprintf(f, "  %-*s  ", (int)col, left);
        for (const char *p = o->help; *p;) {
            const size_t n = strcspn(p, "\n");
            fprintf(f, "%.*s\n", (int)n, p);
            p += n;
            if (*p == '\n' && *++p) fprintf(f, "  %-*s  ", (int)col, "");
        }
    }
    if (spec->outro) fprintf(f, "\n%s\n", spec->outro);
}

/* text with its line breaks as spaces and '|' escaped (a Markdown table cell) */
static void cell(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '\n')
            fputc(' ', f);
        else if (*s == '|')
            fputs("\\|", f);
        else
            fputc(*s, f);
    }
}

void tool_optmarkdown(const tool_optspec *spec, FILE *f)
{
    fprintf(f, "## lumis %s\n\n    ", spec->cmd);
    for (const char *p = spec->usage; *p; p++) {
        fputc(*p, f);
        if (*p == '\n') fputs("    ", f);
    }
    fputc('\n', f);
    if (spec->intro) { /* lines joined into paragraphs; an indented line keeps its break */
        fputc('\n', f);
        for (const char *p = spec->intro; *p; p++) {
            if (*p != '\n' || p[1] == '\n' || (p > spec->intro && p[-1] == '\n'))
                fputc(*p, f);
            else if (p[1] == ' ')
                fputs("\\\n", f);
            else
                fputc(' ', f);
        }
        fputc('\n', f);
    }
    int table = 0;
    for (const tool_opt *o = spec->opts; o->kind != TOOL_OPT_END; o++) {
        if (o->kind == TOOL_OPT_GROUP) {
            fprintf(f, "\n**%s**\n", o->name);
            table = 0;
            continue;
        }
        if (!table) fputs("\n| option | meaning |\n|---|---|\n", f);
        table = 1;
        char left[128];
        left_column(o, left, sizeof left);
        fputs("| `", f);
        cell(f, left);
        fputs("` | ", f);
        cell(f, o->help);
        fputs(" |\n", f);
    }
    if (spec->outro) {
        fputc('\n', f);
        cell(f, spec->outro);
        fputc('\n', f);
    }
    fputc('\n', f);
}

int tool_opt_tonemap(const char *value, void *field)
{
    return lumis_tonemap_from_name(value, field) == LUMIS_OK;
}
