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

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char usage[] =
    "usage: lumis bench SUITE.json [--out DIR] [--jobs N] [--shard I/N] [--merge DIR...]\n"
    "                  [--report-only] [--threads N]\n"
    "       lumis bench SUITE.json --slurm [--out DIR] [--tasks N] [--reference-passes P]\n"
    "                  [--cpus C] [--reference-cpus C] [--exclusive] [--max-running K]\n"
    "                  [--partition NAME] [--time-limit T] [--sbatch=OPTION]... [--no-submit]\n\n"
    "Runs a benchmark suite (docs/bench.md has the format): for every map, scene, method\n"
    "and budget it renders an image, compares it with a reference of the same map and\n"
    "scene (rendered once at high spp and cached under DIR/refs by a hash of everything\n"
    "that makes it), and computes RMSE, relative MSE, PSNR, CIELAB Delta E, LDR-FLIP and\n"
    "HDR-FLIP.  Then it writes DIR/results.csv, results.json, results.md (means, average\n"
    "rankings, pairwise comparisons), convergence-*.svg and index.html.\n\n"
    "options:\n"
    "  --out DIR        output folder (default: bench-out/SUITE_NAME)\n"
    "  --jobs N         N render processes at once, each with cores/N threads (default 1;\n"
    "                   equal-time budgets are fairest with 1)\n"
    "  --shard I/N      only items I, I+N, I+2N, ... (0 <= I < N), for job arrays; writes no\n"
    "                   report: join the shards' folders with --merge\n"
    "  --merge DIR...   copy the results of other runs' folders into DIR, then report\n"
    "  --report-only    render nothing: report on the results DIR has\n"
    "  --threads N      render threads (default: all cores, divided by --jobs)\n\n"
    "An interrupted run resumes where it stopped: finished items are kept.\n\n"
    "On a Slurm cluster (docs/cluster.md; DIR on a filesystem every node shares):\n"
    "  --slurm          submit what is not done as job arrays: the references' shares, their\n"
    "                   merge, one task per shard of items, and a report job after them that\n"
    "                   writes the tables and DIR/slurm/status.txt (what is missing); the\n"
    "                   scripts are in DIR/slurm/.  Run it again to resubmit what failed alone\n"
    "  --tasks N        the items' tasks (shards; default: one per (map, scene) pair)\n"
    "  --reference-passes P  each reference split into P tasks (default 1), merged\n"
    "                   as lumis merge does (equal to one render up to float rounding)\n"
    "  --cpus C         cores of an items task, its render threads (default 1)\n"
    "  --reference-cpus C  cores of a reference task (default: as --cpus)\n"
    "  --exclusive      an items task has its node to itself (equal time, no neighbours)\n"
    "  --max-running K  at most K tasks of an array at once\n"
    "  --partition NAME, --time-limit T (sbatch's --time), --sbatch=OPTION (any sbatch\n"
    "                   option, e.g. --sbatch=--account=NAME; repeatable): for every job\n"
    "  --no-submit      write the scripts and DIR/slurm/submit.sh, submit nothing\n"
    "The jobs run these (each usable alone):\n"
    "  --reference-task T    share T % P of the reference of (map, scene) pair T / P\n"
    "  --merge-references    join the references' shares (with --reference-passes P)\n"
    "  --items-only     render no reference (a missing one is an error), with --shard\n"
    "  --report-only --tasks N   the report, then DIR/slurm/status.txt: exit 1 if any item\n"
    "                   is not done\n";

/* A value that fits an #SBATCH line. */
static int one_line(const char *v)
{
    return v && *v && !strpbrk(v, "\n\r");
}

/* The options only --slurm takes (--cpus, --reference-cpus, --max-running, --exclusive,
 * --no-submit, --partition, --time-limit, --sbatch) into so; *slurm_opt: the last one given.
 * -1 when argv[*i] is none of them, else an exit code. */
static int slurm_option(bench_slurm_opts *so, const char **slurm_opt, int argc, char **argv, int *i)
{
    const char *v;
    if (tool_option(argc, argv, i, "--cpus", &v)) {
        if (!tool_parse_int(v, 1, 4096, &so->cpus))
            return tool_usage_error("bench", "--cpus needs a count in [1, 4096]");
        *slurm_opt = "--cpus";
    } else if (tool_option(argc, argv, i, "--reference-cpus", &v)) {
        if (!tool_parse_int(v, 1, 4096, &so->ref_cpus))
            return tool_usage_error("bench", "--reference-cpus needs a count in [1, 4096]");
        *slurm_opt = "--reference-cpus";
    } else if (tool_option(argc, argv, i, "--max-running", &v)) {
        if (!tool_parse_int(v, 1, 1 << 20, &so->max_running))
            return tool_usage_error("bench", "--max-running needs a count >= 1");
        *slurm_opt = "--max-running";
    } else if (strcmp(argv[*i], "--exclusive") == 0) {
        so->exclusive = 1;
        *slurm_opt = "--exclusive";
    } else if (strcmp(argv[*i], "--no-submit") == 0) {
        so->submit = 0;
        *slurm_opt = "--no-submit";
    } else if (tool_option(argc, argv, i, "--partition", &v)) {
        if (!one_line(v)) return tool_usage_error("bench", "--partition needs a name");
        so->partition = v;
        *slurm_opt = "--partition";
    } else if (tool_option(argc, argv, i, "--time-limit", &v)) {
        if (!one_line(v))
            return tool_usage_error("bench", "--time-limit needs sbatch's --time, e.g. 2:00:00");
        so->time_limit = v;
        *slurm_opt = "--time-limit";
    } else if (tool_option(argc, argv, i, "--sbatch", &v)) {
        if (!one_line(v) || v[0] != '-')
            return tool_usage_error("bench", "--sbatch needs an sbatch option, given as "
                                             "--sbatch=--account=NAME");
        if (so->nextra == BENCH_SLURM_EXTRA_MAX)
            return tool_usage_error("bench", "at most %d --sbatch options", BENCH_SLURM_EXTRA_MAX);
        so->extra[so->nextra++] = v;
        *slurm_opt = "--sbatch";
    } else {
        return -1;
    }
    return EXIT_OK;
}

int cmd_bench(int argc, char **argv)
{
    const char *suite_path = NULL, *out = NULL, *v;
    long jobs = 1, threads = 0, shard_i = 0, shard_n = 1;
    int report_only = 0, merging = 0, sharded = 0;
    int slurm = 0, items_only = 0, merge_refs = 0;
    long ref_task = -1;
    int src;                      /* slurm_option's */
    const char *slurm_opt = NULL; /* the last option that only --slurm takes */
    bench_slurm_opts so = {0};
    so.ref_passes = 1;
    so.cpus = 1;
    so.submit = 1;
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--out", &v)) {
            if (!v || !*v) return tool_usage_error("bench", "--out needs a folder");
            out = v;
        } else if (tool_option(argc, argv, &i, "--jobs", &v)) {
            if (!tool_parse_int(v, 1, 256, &jobs))
                return tool_usage_error("bench", "--jobs needs a count in [1, 256]");
        } else if (tool_option(argc, argv, &i, "--threads", &v)) {
            if (!tool_parse_int(v, 1, 4096, &threads))
                return tool_usage_error("bench", "--threads needs a count in [1, 4096]");
            threads = tool_cap_threads("bench", (int)threads);
        } else if (tool_option(argc, argv, &i, "--shard", &v)) {
            char *slash = v ? strchr(v, '/') : NULL;
            if (!slash) return tool_usage_error("bench", "--shard needs I/N, e.g. 0/4");
            *slash = '\0';
            int ok = tool_parse_int(v, 0, 1 << 20, &shard_i) &&
                     tool_parse_int(slash + 1, 1, 1 << 20, &shard_n) && shard_i < shard_n;
            *slash = '/';
            if (!ok) return tool_usage_error("bench", "--shard needs I/N with 0 <= I < N");
            sharded = 1;
        } else if (strcmp(argv[i], "--merge") == 0) {
            merging = 1;
            struct stat sb;
            if (i + 1 >= argc || stat(argv[i + 1], &sb) != 0 || !S_ISDIR(sb.st_mode))
                return tool_usage_error("bench", "--merge needs folders of earlier runs");
            while (i + 1 < argc && stat(argv[i + 1], &sb) == 0 && S_ISDIR(sb.st_mode)) i++;
        } else if (strcmp(argv[i], "--report-only") == 0) {
            report_only = 1;
        } else if (strcmp(argv[i], "--slurm") == 0) {
            slurm = 1;
        } else if (strcmp(argv[i], "--items-only") == 0) {
            items_only = 1;
        } else if (strcmp(argv[i], "--merge-references") == 0) {
            merge_refs = 1;
        } else if (tool_option(argc, argv, &i, "--reference-task", &v)) {
            if (!tool_parse_int(v, 0, 1 << 24, &ref_task))
                return tool_usage_error("bench", "--reference-task needs a task number >= 0");
        } else if (tool_option(argc, argv, &i, "--reference-passes", &v)) {
            if (!tool_parse_int(v, 1, BENCH_REF_PASSES_MAX, &so.ref_passes))
                return tool_usage_error("bench", "--reference-passes needs a count in [1, %d]",
                                        BENCH_REF_PASSES_MAX);
        } else if (tool_option(argc, argv, &i, "--tasks", &v)) {
            if (!tool_parse_int(v, 1, 1 << 20, &so.tasks))
                return tool_usage_error("bench", "--tasks needs a count >= 1");
        } else if ((src = slurm_option(&so, &slurm_opt, argc, argv, &i)) >= 0) {
            if (src != EXIT_OK) return src;
        } else if (argv[i][0] != '-' && !suite_path) {
            suite_path = argv[i];
        } else {
            return tool_usage_error("bench", "unknown argument '%s'", argv[i]);
        }
    }
    if (!suite_path) return tool_usage_error("bench", "needs a SUITE.json");
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
    bench_opts bo = {suite_path,  out,     jobs,    threads, shard_i,    shard_n,
                     report_only, merging, sharded, slurm,   items_only, merge_refs,
                     ref_task,    so,      argc,    argv};
    return bench_main(&bo);
}
