/* lumis merge SHARE... -o OUT.exr: the image of a render split by passes (lumis render
 * --passes I/N) from its shares: each share's mean weighted by its samples, which is the
 * whole render's mean.  The shares' sidecars say which shares they are; every share of
 * one render must be there, once. */
#include "cli.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* Appends the lines of file to *in (a growing array of malloc'ed paths).  Exit code. */
static int read_list(const char *file, char ***in, int *n, int *cap)
{
    size_t len = 0;
    int oom = 0;
    char *text = (char *)tool_read_file(file, &len, &oom);
    if (!text)
        return oom ? tool_runtime_error("merge: out of memory")
                   : tool_runtime_error("merge: --shares-from %s: cannot read it", file);
    int rc = EXIT_OK;
    for (size_t a = 0; a < len && rc == EXIT_OK;) {
        size_t b = a;
        while (b < len && text[b] != '\n') b++;
        size_t e = b;
        if (e > a && text[e - 1] == '\r') e--;
        if (e > a) {
            if (*n == *cap) {
                *cap = *cap ? 2 * *cap : 64;
                char **g = realloc(*in, (size_t)*cap * sizeof *g);
                if (!g) {
                    rc = tool_runtime_error("merge: out of memory");
                    break;
                }
                *in = g;
            }
            char *p = malloc(e - a + 1);
            if (!p) {
                rc = tool_runtime_error("merge: out of memory");
                break;
            }
            memcpy(p, text + a, e - a);
            p[e - a] = '\0';
            (*in)[(*n)++] = p;
        }
        a = b + 1;
    }
    free(text);
    return rc;
}

/* What merge reads from its arguments: the shares (malloc'ed paths), the options. */
typedef struct merge_cli {
    char **in;
    int n, cap;
    const char *out;
    int no_sidecar, allow;
} merge_cli;

static int shares_from_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    merge_cli *c = ctx;
    if (!v || !*v) return tool_bad_value(cmd, opt->name, v, "needs a file");
    return read_list(v, &c->in, &c->n, &c->cap);
}

static int merge_positional(const char *cmd, const char *arg, void *ctx)
{
    (void)cmd;
    merge_cli *c = ctx;
    if (c->n == c->cap) {
        const int cap = c->cap ? 2 * c->cap : 64;
        char **g = realloc(c->in, (size_t)cap * sizeof *g);
        if (!g) return tool_runtime_error("merge: out of memory");
        c->in = g;
        c->cap = cap;
    }
    if (!(c->in[c->n] = malloc(strlen(arg) + 1))) return tool_runtime_error("merge: out of memory");
    strcpy(c->in[c->n++], arg);
    return EXIT_OK;
}

#define AT(f) offsetof(merge_cli, f)
static const tool_opt merge_table[] = {
    {.kind = TOOL_OPT_STRING,
     .name = "--output",
     .alias = "-o",
     .metavar = "OUT",
     .help = "the merged image (.exr, .pfm or .hdr; required)",
     .at = AT(out),
     .what = "a file"},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--shares-from",
     .metavar = "LIST",
     .help = "the shares' paths, one a line (for more than a command line holds)",
     .handle = shares_from_option},
    {.kind = TOOL_OPT_FLAG,
     .name = "--allow-replaced",
     .help = "merge a share whose pixels the reader replaced by 0 (NaN, Inf,\n"
             "negative); refused by default, as they would bias the image",
     .at = AT(allow)},
    {.kind = TOOL_OPT_FLAG, .name = "--no-sidecar", .help = "no OUT.json", .at = AT(no_sidecar)},
    {0},
};

const tool_optspec tool_merge_spec = {
    .cmd = "merge",
    .usage = "usage: lumis merge SHARE.exr... -o OUT.exr [--shares-from LIST] [--no-sidecar]\n"
             "                   [--allow-replaced]",
    .intro =
        "Joins the shares of a render split by passes (lumis render --passes I/N, each on its\n"
        "own machine) into the image one render of all the samples gives: the shares' means\n"
        "weighted by their sample counts, in double precision (equal to the whole render's image\n"
        "up to the order of the floating-point sums: a few units in the last place of a float).\n"
        "Each share's sidecar (SHARE.json) must say which share it is and carry the render key\n"
        "(a digest of everything that determines the image); the shares must have one key, and\n"
        "be every share of the render, each once.  A share's samples follow from its index, the\n"
        "share count and the total; a sidecar that says otherwise is refused.  Shares are read\n"
        "one at a time: memory does not grow with their number.  OUT.json gets the first\n"
        "share's sidecar with the samples and the render times summed.",
    .opts = merge_table,
    .positional = merge_positional,
};

int cmd_merge(int argc, char **argv)
{
    merge_cli c = {0};
    int rc = tool_optparse(&tool_merge_spec, argc, argv, &c);
    rc = rc < 0 ? EXIT_OK : rc == EXIT_OK ? -1 : rc; /* -1: --help printed */
    char **in = c.in;
    const char *out = c.out;
    const int n = c.n, sidecar = !c.no_sidecar, allow = c.allow;
    if (rc == EXIT_OK && !out) rc = tool_usage_error("merge", "no output file (-o OUT.exr)");
    if (rc == EXIT_OK && n < 1) rc = tool_usage_error("merge", "no shares to merge");
    if (rc == EXIT_OK && n > TOOL_MERGE_MAX)
        rc = tool_usage_error("merge", "%d shares: at most %d", n, TOOL_MERGE_MAX);
    char **side_in = rc == EXIT_OK && n > 0 ? calloc((size_t)(unsigned)n, sizeof *side_in) : NULL;
    if (rc == EXIT_OK && !side_in) rc = tool_runtime_error("merge: out of memory");
    char side_out[4096];
    if (rc == EXIT_OK) {
        tool_sidecar_path(out, side_out, sizeof side_out);
        tool_files files = {0};
        for (int k = 0; k < n && rc == EXIT_OK; k++) {
            char p[4096];
            tool_sidecar_path(in[k], p, sizeof p);
            if (!(side_in[k] = malloc(strlen(p) + 1)))
                rc = tool_runtime_error("merge: out of memory");
            else
                strcpy(side_in[k], p);
        }
        tool_files_input_list(&files, "share", (const char *const *)in, n);
        tool_files_input_list(&files, "share's sidecar", (const char *const *)side_in, n);
        tool_files_output(&files, "-o", out, TOOL_OUT_LINEAR);
        if (sidecar) tool_files_sidecar(&files, side_out, "--no-sidecar, or another OUT");
        if (rc == EXIT_OK) rc = tool_files_check("merge", &files);
    }
    if (rc == EXIT_OK)
        rc =
            tool_merge_shares((const char *const *)in, n, out, sidecar ? side_out : NULL, 0, allow);
    for (int k = 0; k < n; k++) {
        free(in[k]);
        if (side_in) free(side_in[k]);
    }
    free(in);
    free(side_in);
    return rc < 0 ? EXIT_OK : rc;
}
