/* lumis bench SUITE.json: renders every (map, scene, method, budget) of a suite, compares
 * each image with a cached high-spp reference, and writes results.csv, results.json, a
 * Markdown summary with mean errors and average rankings, convergence plots (SVG) and an
 * HTML page.  Work is resumable (an item is done when its result file exists), splits
 * into shards across machines, and runs in parallel processes with --jobs.
 *
 * This file holds the options and the top-level flow; the parts live in bench_suite.c
 * (the suite file), bench_keys.c (items and cache keys), bench_run.c (rendering),
 * bench_tables.c, bench_svg.c and bench_html.c (the report) and bench_merge.c. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "bench.h"

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

/* --out names a folder, made with its parents when missing: never an existing file, least
 * of all the suite itself (exit 2, before any work). */
static int check_out(const char *out, const char *suite_path)
{
    if (tool_same_file(out, suite_path))
        return tool_usage_error("bench", "--out %s is the suite file; name a folder", out);
    struct stat sb;
    if (stat(out, &sb) != 0) return EXIT_OK; /* made below, parents too */
    /* The bench owns its folder (results.json, results.csv, ... are rewritten): a suite
     * inside it would be replaced by a report of the same name. */
    char *ro = realpath(out, NULL), *rs = realpath(suite_path, NULL);
    const size_t lo = ro ? strlen(ro) : 0;
    const int inside = ro && rs && strncmp(rs, ro, lo) == 0 && rs[lo] == '/';
    free(ro);
    free(rs);
    if (inside)
        return tool_usage_error("bench",
                                "the suite %s lies in --out %s, whose files the bench "
                                "writes: keep the suite elsewhere",
                                suite_path, out);
    tool_files files = {0};
    tool_files_input(&files, "suite", suite_path);
    tool_files_output(&files, "--out", out, TOOL_OUT_DIR);
    return tool_files_check("bench", &files);
}

/* Every file of the report, from the results out holds. */
static int write_report(const suite *s, const char *out, int argc, char **argv)
{
    bench_report r;
    if (bench_report_load(&r, s, out, argc, argv) != EXIT_OK) return EXIT_RUNTIME;
    int rc = EXIT_OK;
    char path[8800];
    snprintf(path, sizeof path, "%s/results.csv", out);
    if (bench_write_csv(&r, path) != EXIT_OK) rc = EXIT_RUNTIME;
    snprintf(path, sizeof path, "%s/results.json", out);
    if (bench_write_json(&r, path) != EXIT_OK) rc = EXIT_RUNTIME;
    snprintf(path, sizeof path, "%s/results.md", out);
    if (bench_write_md(&r, path) != EXIT_OK) rc = EXIT_RUNTIME;
    /* convergence plots, one per scene */
    for (int sc = 0; sc < s->nscenes; sc++) {
        snprintf(path, sizeof path, "%s/convergence-%s.svg", out, s->scenes[sc].label);
        if (bench_write_svg(path, s, r.res, sc) != EXIT_OK) rc = EXIT_RUNTIME;
    }
    snprintf(path, sizeof path, "%s/index.html", out);
    if (bench_write_html(&r, path) != EXIT_OK) rc = EXIT_RUNTIME;
    int most = 0, noisy = bench_noisy_reference(&r, -1, -1, &most);
    if (noisy)
        fprintf(
            stderr,
            "lumis bench: warning: the reference has %d spp, fewer than %d times the samples "
            "that %d items reached (up to %d spp): a noisy reference biases their errors; raise "
            "reference.spp to %d or more (results.md lists them)\n",
            s->ref_spp, BENCH_REF_FACTOR, noisy, most, BENCH_REF_FACTOR * most);
    if (rc == EXIT_OK)
        fprintf(stderr,
                "lumis bench: %d of %d items; wrote %s/results.{csv,json,md}, "
                "convergence-*.svg and index.html\n",
                r.found, r.n, out);
    bench_report_free(&r);
    return rc;
}

/* A value that fits an #SBATCH line. */
static int one_line(const char *v)
{
    return v && *v && !strpbrk(v, "\n\r");
}

int cmd_bench(int argc, char **argv)
{
    const char *suite_path = NULL, *out = NULL, *v;
    long jobs = 1, threads = 0, shard_i = 0, shard_n = 1;
    int report_only = 0, merging = 0, sharded = 0;
    int slurm = 0, items_only = 0, merge_refs = 0;
    long ref_task = -1;
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
        } else if (tool_option(argc, argv, &i, "--cpus", &v)) {
            if (!tool_parse_int(v, 1, 4096, &so.cpus))
                return tool_usage_error("bench", "--cpus needs a count in [1, 4096]");
            slurm_opt = "--cpus";
        } else if (tool_option(argc, argv, &i, "--reference-cpus", &v)) {
            if (!tool_parse_int(v, 1, 4096, &so.ref_cpus))
                return tool_usage_error("bench", "--reference-cpus needs a count in [1, 4096]");
            slurm_opt = "--reference-cpus";
        } else if (tool_option(argc, argv, &i, "--max-running", &v)) {
            if (!tool_parse_int(v, 1, 1 << 20, &so.max_running))
                return tool_usage_error("bench", "--max-running needs a count >= 1");
            slurm_opt = "--max-running";
        } else if (strcmp(argv[i], "--exclusive") == 0) {
            so.exclusive = 1;
            slurm_opt = "--exclusive";
        } else if (strcmp(argv[i], "--no-submit") == 0) {
            so.submit = 0;
            slurm_opt = "--no-submit";
        } else if (tool_option(argc, argv, &i, "--partition", &v)) {
            if (!one_line(v)) return tool_usage_error("bench", "--partition needs a name");
            so.partition = v;
            slurm_opt = "--partition";
        } else if (tool_option(argc, argv, &i, "--time-limit", &v)) {
            if (!one_line(v))
                return tool_usage_error("bench",
                                        "--time-limit needs sbatch's --time, e.g. 2:00:00");
            so.time_limit = v;
            slurm_opt = "--time-limit";
        } else if (tool_option(argc, argv, &i, "--sbatch", &v)) {
            if (!one_line(v) || v[0] != '-')
                return tool_usage_error("bench", "--sbatch needs an sbatch option, given as "
                                                 "--sbatch=--account=NAME");
            if (so.nextra == BENCH_SLURM_EXTRA_MAX)
                return tool_usage_error("bench", "at most %d --sbatch options",
                                        BENCH_SLURM_EXTRA_MAX);
            so.extra[so.nextra++] = v;
            slurm_opt = "--sbatch";
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
    suite s;
    if (bench_parse_suite(suite_path, &s) != EXIT_OK) return EXIT_RUNTIME;
    char outbuf[4096];
    if (!out) {
        snprintf(outbuf, sizeof outbuf, "bench-out/%s", s.name);
        out = outbuf;
    }
    int rc = check_out(out, suite_path);
    const int renders = !merging && !report_only && !slurm && !merge_refs;
    if (rc == EXIT_OK && so.ref_passes > s.ref_spp) /* a share of no samples is no share */
        rc = tool_usage_error("bench",
                              "--reference-passes %ld: more shares than the %d samples "
                              "of the suite's reference",
                              so.ref_passes, s.ref_spp);
    if (rc == EXIT_OK && bench_read_inputs(&s, renders) != EXIT_OK) rc = EXIT_RUNTIME;
    if (rc != EXIT_OK) {
        bench_suite_free(&s);
        return rc;
    }
    static const char *const subs[] = {"", "/refs", "/renders", "/results", "/previews"};
    for (int k = 0; k < 5; k++) {
        char d[8800];
        snprintf(d, sizeof d, "%s%s", out, subs[k]);
        if (tool_make_dir(d) != EXIT_OK) {
            bench_suite_free(&s);
            return EXIT_RUNTIME;
        }
    }
    if (merging)
        for (int i = 1; i < argc && rc == EXIT_OK; i++)
            if (strcmp(argv[i], "--merge") == 0)
                for (int k = i + 1; k < argc && rc == EXIT_OK; k++) {
                    struct stat sb;
                    if (stat(argv[k], &sb) != 0 || !S_ISDIR(sb.st_mode)) break;
                    rc = bench_merge_dir(&s, argv[k], out);
                }
    int failed_items = 0;
    bench_run_opts ro = {out, (int)threads, jobs, shard_i, shard_n, items_only, argc, argv};
    if (slurm || ref_task >= 0 || merge_refs) {
        if (rc == EXIT_OK && slurm) rc = bench_slurm(&s, suite_path, out, &so);
        if (rc == EXIT_OK && ref_task >= 0)
            rc = bench_render_reference_part(&s, &ro, ref_task, so.ref_passes);
        if (rc == EXIT_OK && merge_refs) rc = bench_merge_references(&s, out, so.ref_passes);
        bench_suite_free(&s);
        return rc;
    }
    if (renders && rc == EXIT_OK) rc = bench_run(&s, &ro, &failed_items);
    /* the report also when some items failed: it lists them (and the run still exits 1) */
    if ((rc == EXIT_OK || failed_items > 0) && !sharded) {
        const int wrc = write_report(&s, out, argc, argv);
        if (rc == EXIT_OK) rc = wrc;
    }
    /* the report job of --slurm: what the tasks left undone */
    if (rc == EXIT_OK && report_only && so.tasks &&
        bench_slurm_status(&s, out, so.tasks, so.ref_passes) > 0)
        rc = EXIT_RUNTIME;
    if (rc == EXIT_OK && sharded && items_only)
        fprintf(stderr, "lumis bench: shard %ld/%ld done\n", shard_i, shard_n);
    else if (rc == EXIT_OK && sharded)
        fprintf(stderr,
                "lumis bench: shard %ld/%ld done; join the shards with: lumis bench %s --out DIR "
                "--merge SHARD_DIR...\n",
                shard_i, shard_n, suite_path);
    bench_suite_free(&s);
    return rc;
}
