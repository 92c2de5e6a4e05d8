/* lumis bench SUITE --slurm: a suite as Slurm job arrays (docs/cluster.md).
 *
 * What is not done yet becomes four jobs, chained by dependencies:
 *   references        an array, one task per share of each missing reference (--reference-
 *                     passes P shares per (map, scene) pair), task T = pair T / P, share T % P
 *   merge-references  one job after them: joins each reference's shares (lumis merge)
 *   items             an array, one task per shard (--tasks N) that has items left; each
 *                     task renders its items one at a time on its --cpus cores
 *   report            one job after the items, whatever became of them: the tables and
 *                     index.html, and DIR/slurm/status.txt with what is still missing
 * The plan is made from the outputs alone (results checked, references read), so running
 * the same command again submits only what is left: a failed task alone. */
#define _XOPEN_SOURCE 700 /* realpath, getcwd */
#include "harness.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

/* Slurm's default MaxArraySize is 1001: indices 0 to 1000. */
#define BENCH_SLURM_ARRAY_MAX 1000

/* s as one word of sh: in single quotes, each ' as '\''. */
static void put_quoted(FILE *t, const char *s)
{
    fprintf(t, "'");
    for (const char *c = s; *c; c++)
        if (*c == '\'')
            fprintf(t, "'\\''");
        else
            fprintf(t, "%c", *c);
    fprintf(t, "'");
}

/* The indices as sbatch's --array list: runs as "A-B", joined by commas. */
static void put_array(FILE *t, const int *idx, int n, long max_running)
{
    for (int i = 0; i < n;) {
        int j = i;
        while (j + 1 < n && idx[j + 1] == idx[j] + 1) j++;
        fprintf(t, "%s%d", i ? "," : "", idx[i]);
        if (j > i) fprintf(t, "-%d", idx[j]);
        i = j + 1;
    }
    if (max_running > 0) fprintf(t, "%%%ld", max_running);
}

/* Whether v can be written into an #SBATCH line (what = the option that gave it, for the
 * message; pattern: v is part of a Slurm filename pattern, --output's).  Slurm reads an
 * #SBATCH line itself, not through sh: a line per option, a backslash escapes the next
 * byte, quotes quote, an unquoted # starts a comment.  No escape carries a line break, so
 * a control character is refused; in a filename pattern a backslash turns off every %
 * pattern (sbatch(1)), so it is refused there too.  Usage error naming the value, or
 * EXIT_OK. */
static int sbatch_value_ok(const char *what, const char *v, int pattern)
{
    for (const unsigned char *c = (const unsigned char *)v; *c; c++) {
        const int control = *c < 0x20 || *c == 0x7f;
        if (!control && !(pattern && *c == '\\')) continue;
        char shown[600];
        size_t n = 0;
        for (const unsigned char *d = (const unsigned char *)v; *d && n + 8 < sizeof shown; d++)
            n += (size_t)(*d < 0x20 || *d == 0x7f || *d == '\\'
                              ? snprintf(shown + n, sizeof shown - n, "\\x%02x", *d)
                              : snprintf(shown + n, sizeof shown - n, "%c", *d));
        return tool_usage_error("bench",
                                "--slurm: %s \"%s\": %s cannot be written into an #SBATCH line "
                                "(Slurm reads each line as one; %s)",
                                what, shown, control ? "a control character" : "a backslash",
                                control ? "choose another name"
                                        : "in --output's file name it turns off %A and %a");
    }
    return EXIT_OK;
}

/* An #SBATCH line of one argument, "#SBATCH " + head + v + tail: as it is when every
 * byte is a letter, a digit or one of -_./:=,+@%, else in double quotes with each " and \\
 * after a backslash (Slurm ends an argument at a space even after a backslash: only quotes
 * keep one; inside them a # is no comment).  pattern: v is literal text in a filename
 * pattern, so each % is %%.  The values were checked by sbatch_value_ok. */
static void put_sbatch(FILE *t, const char *head, const char *v, const char *tail, int pattern)
{
    char arg[9000];
    size_t n = 0;
    for (const char *c = head; *c && n + 1 < sizeof arg; c++) arg[n++] = *c;
    for (const char *c = v; *c && n + 2 < sizeof arg; c++) {
        arg[n++] = *c;
        if (*c == '%' && pattern) arg[n++] = '%';
    }
    for (const char *c = tail; *c && n + 1 < sizeof arg; c++) arg[n++] = *c;
    arg[n] = '\0';
    int plain = 1;
    for (const unsigned char *c = (const unsigned char *)arg; *c && plain; c++)
        plain = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') ||
                strchr("-_./:=,+@%", *c);
    fputs("#SBATCH ", t);
    if (!plain) fputc('"', t);
    for (const char *c = arg; *c; c++) {
        if (!plain && (*c == '"' || *c == '\\')) fputc('\\', t);
        fputc(*c, t);
    }
    fputs(plain ? "\n" : "\"\n", t);
}

/* The #SBATCH lines every job has. */
static void put_header(FILE *t, const bench_slurm_opts *o, const char *slurm_dir,
                       const char *suite_name, const char *job, int array, long cpus, int exclusive)
{
    char a[200], b[200];
    fprintf(t, "#!/bin/sh\n");
    snprintf(a, sizeof a, "-%s", job);
    put_sbatch(t, "--job-name=lumis-", suite_name, a, 0);
    snprintf(b, sizeof b, "/logs/%s-%s.out", job, array ? "%A_%a" : "%j");
    put_sbatch(t, "--output=", slurm_dir, b, 1);
    fprintf(t, "#SBATCH --ntasks=1\n#SBATCH --cpus-per-task=%ld\n", cpus);
    if (exclusive) fprintf(t, "#SBATCH --exclusive\n");
    if (o->partition) put_sbatch(t, "--partition=", o->partition, "", 0);
    if (o->time_limit) put_sbatch(t, "--time=", o->time_limit, "", 0);
    for (int k = 0; k < o->nextra; k++) put_sbatch(t, "", o->extra[k], "", 0);
}

/* The start of a job's command (after a line in its log naming the node): exec LUMIS bench
 * SUITE --out DIR */
static void put_command(FILE *t, const char *exe, const char *suite, const char *out)
{
    fprintf(t, "echo \"lumis bench: job ${SLURM_JOB_ID:-?} task ${SLURM_ARRAY_TASK_ID:--} on "
               "$(hostname)\" >&2\n");
    fprintf(t, "exec ");
    put_quoted(t, exe);
    fprintf(t, " bench ");
    put_quoted(t, suite);
    fprintf(t, " --out ");
    put_quoted(t, out);
}

/* A job script's path, DIR/slurm/NAME.sbatch, as a word of sh. */
static void put_script(FILE *t, const char *slurm_dir, const char *name)
{
    char p[9000];
    snprintf(p, sizeof p, "%s/%s.sbatch", slurm_dir, name);
    put_quoted(t, p);
}

/* Runs sh on the script; its output passes through.  Exit code. */
static int run_sh(const char *script)
{
    fflush(NULL);
    const pid_t pid = fork();
    if (pid == 0) {
        execlp("sh", "sh", script, (char *)NULL);
        _exit(127);
    }
    if (pid < 0) return tool_runtime_error("bench: fork: %s", strerror(errno));
    int status = 0;
    if (waitpid(pid, &status, 0) < 0)
        return tool_runtime_error("bench: waitpid: %s", strerror(errno));
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return tool_runtime_error("bench: %s failed (its sbatch error is above); jobs it "
                                  "submitted before stay queued (squeue)",
                                  script);
    return EXIT_OK;
}

/* Whether the command sbatch is on PATH. */
static int have_sbatch(void)
{
    const char *path = getenv("PATH");
    if (!path) return 0;
    char *copy = strdup(path);
    int found = 0;
    for (char *save = NULL, *d = copy ? strtok_r(copy, ":", &save) : NULL; d && !found;
         d = strtok_r(NULL, ":", &save)) {
        char p[8800];
        snprintf(p, sizeof p, "%s/sbatch", *d ? d : ".");
        found = access(p, X_OK) == 0;
    }
    free(copy);
    return found;
}

/* The items tasks: o->tasks, else one per (map, scene) pair, never more than the items. */
static long items_tasks(const suite *s, long tasks)
{
    const long n = bench_nitems(s);
    if (tasks <= 0) tasks = (long)s->nmaps * s->nscenes;
    return tasks < n ? tasks : n;
}

/* Whether each item is done, read once (each check reads the item's result file; the plan
 * asks per pair and per shard). NULL: out of memory. */
static unsigned char *items_done(const suite *s, const char *out)
{
    const int n = bench_nitems(s);
    unsigned char *done = malloc((size_t)n + 1);
    for (int k = 0; done && k < n; k++) {
        item it = bench_item_at(s, k);
        done[k] = (unsigned char)bench_item_done(s, out, &it);
    }
    return done;
}

/* Items of shard k of N not done; *mine: the shard's items. */
static int shard_left(const suite *s, const unsigned char *done, long k, long N, int *mine)
{
    int left = 0;
    *mine = 0;
    for (int i = 0; i < bench_nitems(s); i++)
        if (bench_in_shard(s, i, k, N)) {
            (*mine)++;
            left += !done[i];
        }
    return left;
}

/* Whether the (map, scene) pair's reference is needed (an item of the pair, contiguous in
 * the items' order, is not done) and not done. */
static int reference_missing(const suite *s, const char *out, const unsigned char *done, int m,
                             int sc)
{
    const int per = s->nmethods * s->nbudgets, first = bench_idx(s, m, sc, 0, 0);
    int needed = 0;
    for (int k = first; k < first + per && !needed; k++) needed = !done[k];
    return needed && !bench_reference_ok(s, out, m, sc);
}

int bench_slurm(const suite *s, const char *suite_path, const char *out, const bench_slurm_opts *o)
{
    const long P = o->ref_passes, N = items_tasks(s, o->tasks);
    const long rcpus = o->ref_cpus > 0 ? o->ref_cpus : o->cpus;
    const int nitems = bench_nitems(s), npairs = s->nmaps * s->nscenes;
    char exe[4096], cwd[4096], dir[8800];
    const ssize_t el = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (el <= 0) return tool_runtime_error("bench: --slurm: cannot find this program's path");
    exe[el] = '\0';
    char *suite_abs = realpath(suite_path, NULL), *out_abs = realpath(out, NULL);
    if (!suite_abs || !out_abs || !getcwd(cwd, sizeof cwd)) {
        free(suite_abs);
        free(out_abs);
        return tool_runtime_error("bench: --slurm: %s", strerror(errno));
    }
    snprintf(dir, sizeof dir, "%s/slurm", out_abs);
    /* every value an #SBATCH line holds (the sh words are quoted whatever they hold) */
    int bad = sbatch_value_ok("--out", dir, 1);
    if (bad == EXIT_OK) bad = sbatch_value_ok("the suite's name", s->name, 0);
    if (bad == EXIT_OK && o->partition) bad = sbatch_value_ok("--partition", o->partition, 0);
    if (bad == EXIT_OK && o->time_limit) bad = sbatch_value_ok("--time-limit", o->time_limit, 0);
    for (int k = 0; bad == EXIT_OK && k < o->nextra; k++)
        bad = sbatch_value_ok("--sbatch", o->extra[k], 0);
    if (bad != EXIT_OK) {
        free(suite_abs);
        free(out_abs);
        return bad;
    }
    char logs[8900];
    snprintf(logs, sizeof logs, "%s/logs", dir);
    int rc =
        tool_make_dir(dir) == EXIT_OK && tool_make_dir(logs) == EXIT_OK ? EXIT_OK : EXIT_RUNTIME;

    /* the plan, from what the folder holds */
    int *ref_tasks = malloc(sizeof(int) * (size_t)npairs * (size_t)P + 1);
    int *item_tasks = malloc(sizeof(int) * (size_t)N + 1);
    int nref = 0, nmerge = 0, nshard = 0, left = 0;
    unsigned char *done = items_done(s, out_abs);
    if (!ref_tasks || !item_tasks || !done) rc = tool_runtime_error("bench: out of memory");
    for (int pair = 0; pair < npairs && rc == EXIT_OK; pair++) {
        const int m = pair / s->nscenes, sc = pair % s->nscenes;
        if (!reference_missing(s, out_abs, done, m, sc)) continue;
        nmerge++;
        for (long i = 0; i < P; i++)
            if (!bench_reference_part_ok(s, out_abs, m, sc, i, P))
                ref_tasks[nref++] = (int)(pair * P + i);
    }
    for (long k = 0; k < N && rc == EXIT_OK; k++) {
        int mine = 0;
        const int missing = shard_left(s, done, k, N, &mine);
        if (missing) item_tasks[nshard++] = (int)k;
        left += missing;
    }

    /* the job scripts (the same on every run: the arrays' indices go on sbatch's line):
     * outputs, none of which may be (or link to) the suite */
    static const char *const names[] = {"references.sbatch", "merge-references.sbatch",
                                        "items.sbatch",      "report.sbatch",
                                        "resubmit.sh",       "submit.sh",
                                        "jobs.txt"};
    char outs[7][9000];
    tool_files files = {0};
    tool_files_input(&files, "suite", suite_path);
    for (int k = 0; k < 7; k++) {
        snprintf(outs[k], sizeof outs[k], "%s/%s", dir, names[k]);
        tool_files_output(&files, "--slurm's script", outs[k], TOOL_OUT_FILE);
    }
    if (rc == EXIT_OK) rc = tool_files_check("bench", &files);
    FILE *t = NULL; /* each script built in a temporary file, then written atomically */
    if (rc == EXIT_OK && !(t = tmpfile())) rc = tool_runtime_error("bench: no temporary file");
    if (rc == EXIT_OK) {
        put_header(t, o, dir, s->name, "references", 1, rcpus, 0);
        fprintf(t, "# task T: share T %% %ld of the reference of (map, scene) pair T / %ld\n", P,
                P);
        put_command(t, exe, suite_abs, out_abs);
        fprintf(t,
                " --reference-task \"$SLURM_ARRAY_TASK_ID\" --reference-passes %ld --threads %ld\n",
                P, rcpus);
        rc = tool_commit_tmp(t, outs[0]);
    }
    if (rc == EXIT_OK && !(t = tmpfile())) rc = tool_runtime_error("bench: no temporary file");
    if (rc == EXIT_OK) {
        put_header(t, o, dir, s->name, "merge-references", 0, 1, 0);
        put_command(t, exe, suite_abs, out_abs);
        fprintf(t, " --merge-references --reference-passes %ld\n", P);
        rc = tool_commit_tmp(t, outs[1]);
    }
    if (rc == EXIT_OK && !(t = tmpfile())) rc = tool_runtime_error("bench: no temporary file");
    if (rc == EXIT_OK) {
        put_header(t, o, dir, s->name, "items", 1, o->cpus, o->exclusive);
        fprintf(t,
                "# task I: the items of shard I of %ld, one at a time on its %ld core%s (equal "
                "time needs them to itself)\n",
                N, o->cpus, o->cpus == 1 ? "" : "s");
        put_command(t, exe, suite_abs, out_abs);
        fprintf(t, " --shard \"$SLURM_ARRAY_TASK_ID/%ld\" --items-only --jobs 1 --threads %ld\n", N,
                o->cpus);
        rc = tool_commit_tmp(t, outs[2]);
    }
    if (rc == EXIT_OK && !(t = tmpfile())) rc = tool_runtime_error("bench: no temporary file");
    if (rc == EXIT_OK) {
        put_header(t, o, dir, s->name, "report", 0, 1, 0);
        put_command(t, exe, suite_abs, out_abs);
        fprintf(t, " --report-only --tasks %ld --reference-passes %ld\n", N, P);
        rc = tool_commit_tmp(t, outs[3]);
    }
    if (rc == EXIT_OK && !(t = tmpfile())) rc = tool_runtime_error("bench: no temporary file");
    /* resubmit.sh: this command again, from where it was run */
    if (rc == EXIT_OK) {
        fprintf(t,
                "#!/bin/sh\n# Submits what is not done yet of suite %s (lumis bench --slurm "
                "makes its plan from the outputs)\ncd ",
                s->name);
        put_quoted(t, cwd);
        fprintf(t, " || exit 1\nexec ");
        put_quoted(t, exe);
        fprintf(t, " bench ");
        char word[8800]; /* a suite named -x.json would read as an option: ./-x.json */
        snprintf(word, sizeof word, "%s%s", suite_path[0] == '-' ? "./" : "", suite_path);
        put_quoted(t, word);
        fprintf(t, " ");
        snprintf(word, sizeof word, "--out=%s", out); /* whatever out begins with */
        put_quoted(t, word);
        fprintf(t, " --slurm --tasks %ld --reference-passes %ld --cpus %ld --reference-cpus %ld", N,
                P, o->cpus, rcpus);
        if (o->max_running > 0) fprintf(t, " --max-running %ld", o->max_running);
        if (o->exclusive) fprintf(t, " --exclusive");
        if (o->partition) {
            fprintf(t, " --partition ");
            put_quoted(t, o->partition);
        }
        if (o->time_limit) {
            fprintf(t, " --time-limit ");
            put_quoted(t, o->time_limit);
        }
        for (int k = 0; k < o->nextra; k++) {
            char opt[4200];
            snprintf(opt, sizeof opt, "--sbatch=%s", o->extra[k]);
            fprintf(t, " ");
            put_quoted(t, opt);
        }
        fprintf(t, " \"$@\"\n");
        rc = tool_commit_tmp(t, outs[4]);
    }
    if (rc == EXIT_OK && !(t = tmpfile())) rc = tool_runtime_error("bench: no temporary file");

    /* submit.sh: this plan's sbatch commands, chained */
    const char *jobs = outs[6];
    if (rc == EXIT_OK) {
        char date[64];
        const time_t now = time(NULL);
        strftime(date, sizeof date, "%Y-%m-%d %H:%M:%S", localtime(&now));
        fprintf(
            t,
            "#!/bin/sh\n# Written by lumis bench --slurm on %s for suite %s: what is not done.\n"
            "# %d reference share%s (%d reference%s to merge), %d of %ld items tasks (%d item%s "
            "left).\nset -e\n: > ",
            date, s->name, nref, nref == 1 ? "" : "s", nmerge, nmerge == 1 ? "" : "s", nshard, N,
            left, left == 1 ? "" : "s");
        put_quoted(t, jobs);
        fprintf(t, "\njob() { id=$(sbatch --parsable \"$@\"); id=${id%%%%;*}; echo \"$id\"; }\n");
        const char *after = "";
        if (nref) {
            fprintf(t, "refs=$(job --array=");
            put_array(t, ref_tasks, nref, o->max_running);
            fprintf(t, " ");
            put_script(t, dir, "references");
            fprintf(t, ")\necho \"references $refs\" >> ");
            put_quoted(t, jobs);
            fprintf(t, "\n");
            after = "--dependency=afterany:$refs ";
        }
        if (nmerge) {
            fprintf(t, "merge=$(job %s", after);
            put_script(t, dir, "merge-references");
            fprintf(t, ")\necho \"merge-references $merge\" >> ");
            put_quoted(t, jobs);
            fprintf(t, "\n");
            after = "--dependency=afterok:$merge --kill-on-invalid-dep=yes ";
        }
        if (nshard) {
            fprintf(t, "items=$(job %s--array=", after);
            put_array(t, item_tasks, nshard, o->max_running);
            fprintf(t, " ");
            put_script(t, dir, "items");
            fprintf(t, ")\necho \"items $items\" >> ");
            put_quoted(t, jobs);
            fprintf(t, "\n");
            after = "--dependency=afterany:$items ";
        } else if (nmerge) {
            after = "--dependency=afterany:$merge ";
        }
        fprintf(t, "report=$(job %s", after);
        put_script(t, dir, "report");
        fprintf(t, ")\necho \"report $report\" >> ");
        put_quoted(t, jobs);
        fprintf(t, "\ncat ");
        put_quoted(t, jobs);
        fprintf(t, "\n");
        rc = tool_commit_tmp(t, outs[5]);
    }
    const char *submit = outs[5];
    if (rc == EXIT_OK) {
        fprintf(stderr,
                "lumis bench: suite %s as Slurm jobs: %d reference share%s in %d reference%s, "
                "%d of %ld items tasks (%d of %d items left); scripts in %s\n",
                s->name, nref, nref == 1 ? "" : "s", nmerge, nmerge == 1 ? "" : "s", nshard, N,
                left, nitems, dir);
        int top = nref ? ref_tasks[nref - 1] : 0; /* the highest array index */
        if (nshard && item_tasks[nshard - 1] > top) top = item_tasks[nshard - 1];
        if (top > BENCH_SLURM_ARRAY_MAX)
            fprintf(stderr,
                    "lumis bench: warning: array indices up to %d: Slurm's default MaxArraySize "
                    "(%d) refuses indices above %d; if sbatch does, use fewer --reference-passes "
                    "or --tasks (scontrol show config | grep MaxArraySize says the cluster's)\n",
                    top, BENCH_SLURM_ARRAY_MAX + 1, BENCH_SLURM_ARRAY_MAX);
        if (!nref && !nmerge && !nshard) {
            fprintf(stderr, "lumis bench: every item is done: nothing submitted (--report-only "
                            "rewrites the report)\n");
        } else if (!o->submit) {
            fprintf(stderr, "lumis bench: --no-submit: submit them with: sh %s\n", submit);
        } else if (!have_sbatch()) {
            rc = tool_runtime_error("bench: --slurm: sbatch is not on PATH (is this a Slurm "
                                    "login node?); the scripts are written: sh %s submits them",
                                    submit);
        } else {
            rc = run_sh(submit);
            if (rc == EXIT_OK)
                fprintf(stderr,
                        "lumis bench: submitted (job ids above and in %s); the report job writes "
                        "%s/results.md and %s/status.txt; to resubmit what fails: sh "
                        "%s/resubmit.sh\n",
                        jobs, out_abs, dir, dir);
        }
    }
    free(done);
    free(ref_tasks);
    free(item_tasks);
    free(suite_abs);
    free(out_abs);
    return rc;
}

int bench_slurm_status(const suite *s, const char *out, long tasks, long ref_passes)
{
    const long N = items_tasks(s, tasks);
    const int nitems = bench_nitems(s);
    FILE *t = tmpfile();
    unsigned char *done = items_done(s, out);
    if (!t || !done) {
        tool_runtime_error("bench: no temporary file, or out of memory");
        if (t) fclose(t);
        free(done);
        return nitems;
    }
    int left = 0, bad_tasks = 0, bad_refs = 0;
    for (long k = 0; k < N; k++) {
        int mine = 0;
        const int missing = shard_left(s, done, k, N, &mine);
        if (!missing) continue;
        left += missing;
        bad_tasks++;
        fprintf(t,
                "items task %ld of %ld: %d of its %d items not done (its log: %s/slurm/logs/"
                "items-*_%ld.out)\n",
                k, N, missing, mine, out, k);
    }
    for (int m = 0; m < s->nmaps; m++)
        for (int sc = 0; sc < s->nscenes; sc++) {
            if (!reference_missing(s, out, done, m, sc)) continue;
            bad_refs++;
            const long pair = (long)m * s->nscenes + sc;
            fprintf(t, "reference %s / %s missing (references tasks %ld to %ld)\n",
                    s->maps[m].label, s->scenes[sc].label, pair * ref_passes,
                    pair * ref_passes + ref_passes - 1);
        }
    if (left)
        fprintf(t,
                "%d of %d items not done (%d of %ld items tasks, %d reference%s); submit them "
                "alone with: sh %s/slurm/resubmit.sh\n",
                left, nitems, bad_tasks, N, bad_refs, bad_refs == 1 ? "" : "s", out);
    else
        fprintf(t, "all %d items done\n", nitems);
    /* on stderr too (the report job's log), then written */
    fputs("lumis bench: ", stderr);
    rewind(t);
    for (int c; (c = fgetc(t)) != EOF;) fputc(c, stderr);
    char dir[8800], path[8900];
    snprintf(dir, sizeof dir, "%s/slurm", out);
    snprintf(path, sizeof path, "%s/status.txt", dir);
    if (tool_make_dir(dir) == EXIT_OK)
        tool_commit_tmp(t, path);
    else
        fclose(t);
    free(done);
    return left;
}
