/* lumis bench's flow (bench_main): the suite read, its folder made, then one way to run
 * (render, merge, report, Slurm and its tasks); the parts live in bench_suite.c (the suite
 * file), bench_keys.c (items and cache keys), bench_run.c (rendering), bench_tables.c,
 * bench_svg.c and bench_html.c (the report), bench_merge.c and bench_slurm.c. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "harness.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

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
                r.found, bench_nlisted(r.s), out);
    bench_report_free(&r);
    return rc;
}

int bench_main(const bench_opts *o)
{
    const char *suite_path = o->suite_path, *out = o->out;
    const int merging = o->merging, report_only = o->report_only, slurm = o->slurm;
    const int merge_refs = o->merge_refs, sharded = o->sharded, items_only = o->items_only;
    const long ref_task = o->ref_task, shard_i = o->shard_i, shard_n = o->shard_n;
    const bench_slurm_opts so = o->so;
    const int argc = o->argc;
    char **argv = o->argv;
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
    bench_run_opts ro = {out, (int)o->threads, o->jobs, shard_i, shard_n, items_only, argc, argv};
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
