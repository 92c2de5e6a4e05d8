/* lumis bench SUITE.json: renders every (map, scene, method, budget) of a suite, compares
 * each image with a cached high-spp reference, and writes results.csv, results.json, a
 * Markdown summary with mean errors and average rankings, convergence plots (SVG) and an
 * HTML page.  Work is resumable (an item is done when its result file exists), splits
 * into shards across machines, and runs in parallel processes with --jobs.
 *
 * This file holds the options; the flow and its parts are the harness (tools/harness,
 * harness.h: bench_main). */
#include "../harness/harness.h"
#include "cli.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* What lumis bench reads from its arguments: the harness's options, and what the checks
 * after them need. */
typedef struct bench_cli {
    bench_opts bo;
    const char *slurm_opt; /* the last option that only --slurm takes */
    const char *shard;     /* --shard, if given */
    int no_submit, merge_folders;
} bench_cli;

/* A value that fits an #SBATCH line. */
static int one_line(const char *v)
{
    return v && *v && !strpbrk(v, "\n\r");
}

static int shard_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    bench_opts *bo = &((bench_cli *)ctx)->bo;
    char head[32];
    const char *slash = v ? strchr(v, '/') : NULL;
    if (!slash) return tool_bad_value(cmd, opt->name, v, "needs I/N, e.g. 0/4");
    const size_t n = (size_t)(slash - v);
    if (n < sizeof head) {
        memcpy(head, v, n);
        head[n] = '\0';
    }
    if (n >= sizeof head || !tool_parse_int(head, 0, 1 << 20, &bo->shard_i) ||
        !tool_parse_int(slash + 1, 1, 1 << 20, &bo->shard_n) || bo->shard_i >= bo->shard_n)
        return tool_bad_value(cmd, opt->name, v, "needs I/N with 0 <= I < N");
    bo->sharded = 1;
    return EXIT_OK;
}

static int one_line_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    if (!one_line(v)) return tool_bad_value(cmd, opt->name, v, opt->what);
    *(const char **)((char *)ctx + opt->at) = v;
    return EXIT_OK;
}

static int sbatch_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    bench_slurm_opts *so = &((bench_cli *)ctx)->bo.so;
    if (!one_line(v) || v[0] != '-')
        return tool_usage_error(cmd, "--sbatch needs an sbatch option, given as "
                                     "--sbatch=--account=NAME");
    if (so->nextra == BENCH_SLURM_EXTRA_MAX)
        return tool_usage_error(cmd, "at most %d %s options", BENCH_SLURM_EXTRA_MAX, opt->name);
    so->extra[so->nextra++] = v;
    return EXIT_OK;
}

/* --merge DIR...: the folders are the directories after it (bench_main reads them from
 * argv); here they are counted. */
static int bench_positional(const char *cmd, const char *arg, void *ctx)
{
    bench_cli *c = ctx;
    struct stat sb;
    if (c->bo.merging && c->merge_folders >= 0 && stat(arg, &sb) == 0 && S_ISDIR(sb.st_mode)) {
        c->merge_folders++;
        return EXIT_OK;
    }
    if (c->bo.merging && c->merge_folders == 0)
        return tool_usage_error(cmd, "--merge needs folders of earlier runs");
    c->merge_folders = c->bo.merging ? -1 : c->merge_folders; /* the folders have ended */
    if (c->bo.suite_path) return tool_usage_error(cmd, "unknown argument '%s'", arg);
    c->bo.suite_path = arg;
    return EXIT_OK;
}

#define AT(f)      offsetof(bench_cli, bo.f)
#define SLURM_ONLY TOOL_NOTE(bench_cli, slurm_opt)
static const tool_opt bench_opts_table[] = {
    {.kind = TOOL_OPT_STRING,
     .name = "--out",
     .metavar = "DIR",
     .help = "output folder (default: bench-out/SUITE_NAME)",
     .at = AT(out),
     .what = "a folder"},
    {.kind = TOOL_OPT_LONG,
     .name = "--jobs",
     .metavar = "N",
     .help = "N render processes at once, each with cores/N threads (default 1;\n"
             "equal-time budgets are fairest with 1)",
     .at = AT(jobs),
     .lo = 1,
     .hi = 256},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--shard",
     .metavar = "I/N",
     .help = "only items I, I+N, I+2N, ... (0 <= I < N), for job arrays; writes no\n"
             "report: join the shards' folders with --merge",
     .handle = shard_option},
    {.kind = TOOL_OPT_FLAG,
     .name = "--merge",
     .then = "DIR...",
     .help = "copy the results of other runs' folders into DIR, then report",
     .at = AT(merging)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--report-only",
     .help = "render nothing: report on the results DIR has",
     .at = AT(report_only)},
    {.kind = TOOL_OPT_LONG,
     .name = "--threads",
     .metavar = "N",
     .help = "render threads (default: all cores, divided by --jobs)",
     .at = AT(threads),
     .lo = 1,
     .hi = 4096},

    {.kind = TOOL_OPT_GROUP,
     .name = "on a Slurm cluster (docs/cluster.md; DIR on a filesystem every node shares)"},
    {.kind = TOOL_OPT_FLAG,
     .name = "--slurm",
     .help = "submit what is not done as job arrays: the references' shares, their\n"
             "merge, one task per shard of items, and a report job after them that\n"
             "writes the tables and DIR/slurm/status.txt (what is missing); the\n"
             "scripts are in DIR/slurm/.  Run it again to resubmit what failed alone",
     .at = AT(slurm)},
    {.kind = TOOL_OPT_LONG,
     .name = "--tasks",
     .metavar = "N",
     .help = "the items' tasks (shards; default: one per (map, scene) pair)",
     .at = AT(so.tasks),
     .lo = 1,
     .hi = 1 << 20},
    {.kind = TOOL_OPT_LONG,
     .name = "--reference-passes",
     .metavar = "P",
     .help = "each reference split into P tasks (default 1), merged\n"
             "as lumis merge does (equal to one render up to float rounding)",
     .at = AT(so.ref_passes),
     .lo = 1,
     .hi = BENCH_REF_PASSES_MAX},
    {.kind = TOOL_OPT_LONG,
     .name = "--cpus",
     .metavar = "C",
     .help = "cores of an items task, its render threads (default 1)",
     .at = AT(so.cpus),
     .lo = 1,
     .hi = 4096,
     .note = SLURM_ONLY},
    {.kind = TOOL_OPT_LONG,
     .name = "--reference-cpus",
     .metavar = "C",
     .help = "cores of a reference task (default: as --cpus)",
     .at = AT(so.ref_cpus),
     .lo = 1,
     .hi = 4096,
     .note = SLURM_ONLY},
    {.kind = TOOL_OPT_FLAG,
     .name = "--exclusive",
     .help = "an items task has its node to itself (equal time, no neighbours)",
     .at = AT(so.exclusive),
     .note = SLURM_ONLY},
    {.kind = TOOL_OPT_LONG,
     .name = "--max-running",
     .metavar = "K",
     .help = "at most K tasks of an array at once",
     .at = AT(so.max_running),
     .lo = 1,
     .hi = 1 << 20,
     .note = SLURM_ONLY},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--partition",
     .metavar = "NAME",
     .help = "the partition of every job",
     .handle = one_line_option,
     .at = AT(so.partition),
     .what = "needs a name",
     .note = SLURM_ONLY},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--time-limit",
     .metavar = "T",
     .help = "sbatch's --time of every job",
     .handle = one_line_option,
     .at = AT(so.time_limit),
     .what = "needs sbatch's --time, e.g. 2:00:00",
     .note = SLURM_ONLY},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--sbatch",
     .metavar = "OPTION",
     .help = "any sbatch option for every job, e.g. --sbatch=--account=NAME\n"
             "(repeatable)",
     .handle = sbatch_option,
     .note = SLURM_ONLY},
    {.kind = TOOL_OPT_FLAG,
     .name = "--no-submit",
     .help = "write the scripts and DIR/slurm/submit.sh, submit nothing",
     .at = offsetof(bench_cli, no_submit),
     .note = SLURM_ONLY},

    {.kind = TOOL_OPT_GROUP, .name = "what the jobs run (each usable alone)"},
    {.kind = TOOL_OPT_LONG,
     .name = "--reference-task",
     .metavar = "T",
     .help = "share T % P of the reference of (map, scene) pair T / P",
     .at = AT(ref_task),
     .lo = 0,
     .hi = 1 << 24,
     .what = "a task number"},
    {.kind = TOOL_OPT_FLAG,
     .name = "--merge-references",
     .help = "join the references' shares (with --reference-passes P)",
     .at = AT(merge_refs)},
    {.kind = TOOL_OPT_FLAG,
     .name = "--items-only",
     .help = "render no reference (a missing one is an error), with --shard",
     .at = AT(items_only)},
    {0},
};

const tool_optspec tool_bench_spec = {
    .cmd = "bench",
    .usage =
        "usage: lumis bench SUITE.json [--out DIR] [--jobs N] [--shard I/N] [--merge DIR...]\n"
        "                  [--report-only] [--threads N]\n"
        "       lumis bench SUITE.json --slurm [--out DIR] [--tasks N] [--reference-passes P]\n"
        "                  [--cpus C] [--reference-cpus C] [--exclusive] [--max-running K]\n"
        "                  [--partition NAME] [--time-limit T] [--sbatch=OPTION]... [--no-submit]",
    .intro = "Runs a benchmark suite (docs/bench.md has the format): for every map, scene, method\n"
             "and budget it renders an image, compares it with a reference of the same map and\n"
             "scene (rendered once at high spp and cached under DIR/refs by a hash of everything\n"
             "that makes it), and computes RMSE, relative MSE, PSNR, CIELAB Delta E, LDR-FLIP and\n"
             "HDR-FLIP.  Then it writes DIR/results.csv, results.json, results.md (means, average\n"
             "rankings, pairwise comparisons), convergence-*.svg and index.html.  An interrupted\n"
             "run resumes where it stopped: finished items are kept.",
    .opts = bench_opts_table,
    .positional = bench_positional,
    .outro = "--report-only --tasks N: the report, then DIR/slurm/status.txt: exit 1 if any item\n"
             "is not done (the Slurm report job).",
};

int cmd_bench(int argc, char **argv)
{
    bench_cli c = {0};
    bench_opts *b = &c.bo;
    b->jobs = 1;
    b->shard_n = 1;
    b->ref_task = -1;
    b->so.ref_passes = 1;
    b->so.cpus = 1;
    b->argc = argc;
    b->argv = argv;
    const int rc = tool_optparse(&tool_bench_spec, argc, argv, &c);
    if (rc >= 0) return rc;
    b->so.submit = !c.no_submit;
    if (b->threads) b->threads = tool_cap_threads("bench", (int)b->threads);
    if (b->merging && c.merge_folders == 0)
        return tool_usage_error("bench", "--merge needs folders of earlier runs");
    const bench_opts bo = *b;
    const char *slurm_opt = c.slurm_opt;
    const bench_slurm_opts so = b->so;
    const long jobs = bo.jobs, ref_task = bo.ref_task;
    const int sharded = bo.sharded, merging = bo.merging, report_only = bo.report_only,
              slurm = bo.slurm, items_only = bo.items_only, merge_refs = bo.merge_refs;
    if (!bo.suite_path) return tool_usage_error("bench", "needs a SUITE.json");
    if (sharded && (merging || report_only))
        return tool_usage_error("bench", "--shard renders; --merge and --report-only report");
    const int modes = slurm + items_only + merge_refs + (ref_task >= 0) + report_only + merging;
    if (modes > 1)
        return tool_usage_error("bench", "--slurm, --reference-task, --merge-references, "
                                         "--items-only, --report-only and --merge are ways to "
                                         "run: one at a time");
    if (slurm_opt && !slurm) return tool_usage_error("bench", "%s: only with --slurm", slurm_opt);
    if (so.tasks && !slurm && !report_only)
        return tool_usage_error("bench", "--tasks: only with --slurm or --report-only");
    if ((slurm || ref_task >= 0 || merge_refs) && (sharded || jobs != 1))
        return tool_usage_error("bench", "--shard and --jobs: not with --slurm, "
                                         "--reference-task or --merge-references");
    return bench_main(&bo);
}
