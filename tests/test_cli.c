#define _XOPEN_SOURCE 700 /* realpath */
/* The lumis executable: exit codes (0 ok, 1 runtime, 2 usage), messages that name the
 * file and the reason, and the documented output of each subcommand. */
/* Oracles:
 * lumis_version — indirect: lumis --version prints LUMIS_VERSION_STRING
 *     (help_version_and_usage_errors)
 * lumis_scene_builtin_has_luminaires — indirect: through the CLI, the headlight scene is lit by its
 *     luminaires and refuses --env and --lights (render_with_luminaires)
 * lumis_scene_builtin_luminaire_spec — indirect: through the CLI, the headlight scene loads the car
 *     preset (its images' bytes) (render_with_luminaires)
 * lumis_scene_builtin_with_luminaire — indirect: through the CLI, --scene headlight --luminaire
 *     preset:small renders and merges like one render
 *     (merged_shares_equal_one_render_for_every_light_kind)
 * lumis_scene_file_luminaire_path — indirect: through the CLI, a scene's luminaire manifest is an
 *     input no output may replace (luminaire_files_create_info_render)
 * lumis_scene_file_photometric_path — indirect: through the CLI, a scene's photometric file is an
 *     input no output may replace (render_places_photometric_fixtures)
 * lumis_scene_file_mesh_path — none: the CLI lists a scene's mesh files as inputs; no test checks
 *     the list
 */
#include "photometric_gen.h"
#include "testutil.h"

#include <cJSON.h>
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static int run(const char *args, char **out, char **err)
{
    char cmd[8192 + 4096]; /* room for the longest argument lines the tests build, 8 KB */
    snprintf(cmd, sizeof cmd, "'%s' %s", LUMIS_CLI, args);
    return tu_run(cmd, out, err);
}

/* lumis ARGS with stdin from a file (tu_run itself gives commands /dev/null). */
static int run_stdin(const char *args, const char *input, char **out, char **err)
{
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "(cat '%s' | '%s' %s)", input, LUMIS_CLI, args);
    return tu_run(cmd, out, err);
}

static void expect(const char *args, int code, const char *in_stderr)
{
    char *out = NULL, *err = NULL;
    int rc = run(args, &out, &err);
    if (rc != code) fail_msg("lumis %s: exit %d, want %d; stderr: %s", args, rc, code, err);
    if (in_stderr && !strstr(err, in_stderr))
        fail_msg("lumis %s: stderr lacks \"%s\": %s", args, in_stderr, err);
    free(out);
    free(err);
}

#if defined(__GNUC__) || defined(__clang__)
#define CLI_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define CLI_PRINTF(a, b)
#endif

/* lumis with the arguments printf-style (fmt, ...): its exit code; its stdout and stderr in
 * *out and *err when not NULL (the caller frees them). */
static CLI_PRINTF(3, 4) int runf(char **out, char **err, const char *fmt, ...)
{
    char args[8192];
    va_list ap;
    va_start(ap, fmt);
    const int n = vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= sizeof args) fail_msg("lumis %.80s...: arguments too long", args);
    return run(args, out, err);
}

/* lumis with the arguments printf-style must exit 0 (else the test fails showing its
 * stderr); its stdout in *out when not NULL. */
static CLI_PRINTF(2, 3) void run_ok(char **out, const char *fmt, ...)
{
    char args[8192], *err = NULL;
    va_list ap;
    va_start(ap, fmt);
    const int n = vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= sizeof args) fail_msg("lumis %.80s...: arguments too long", args);
    const int rc = run(args, out, &err);
    if (rc != 0) fail_msg("lumis %s: exit %d, want 0; stderr: %s", args, rc, err);
    free(err);
}

/* expect() with the arguments printf-style. */
static CLI_PRINTF(3, 4) void expectf(int code, const char *in_stderr, const char *fmt, ...)
{
    char args[8192];
    va_list ap;
    va_start(ap, fmt);
    const int n = vsnprintf(args, sizeof args, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= sizeof args) fail_msg("lumis %.80s...: arguments too long", args);
    expect(args, code, in_stderr);
}

/* Malformed input files: each text is written to NAME in the test folder and
 * `lumis CMD 'PATH' REST` must exit 1 with msg and the file's name in its message. */
typedef struct bad_file {
    const char *text, *msg;
} bad_file;

static void expect_bad_files(const char *cmd, const char *name, const char *rest,
                             const bad_file *bad, size_t n)
{
    char a[8192];
    for (size_t k = 0; k < n; k++) {
        tu_write_file(tu_path(name), bad[k].text, strlen(bad[k].text));
        snprintf(a, sizeof a, "%s '%s' %s", cmd, tu_path(name), rest);
        expect(a, 1, bad[k].msg);
        expect(a, 1, name);
    }
}

static void help_version_and_usage_errors(void **state)
{
    (void)state;
    char *out = NULL;
    assert_int_equal(run("--version", &out, NULL), 0);
    assert_non_null(strstr(out, LUMIS_VERSION_STRING));
    free(out);
    assert_int_equal(run("--help", &out, NULL), 0);
    assert_non_null(strstr(out, "info"));
    free(out);
    const char *cmds[] = {"info", "convert", "sky", "studio",
                          "demo", "sample",  "pdf", "bench-samplers"};
    for (int k = 0; k < 8; k++) {
        char a[64];
        snprintf(a, sizeof a, "%s --help", cmds[k]);
        assert_int_equal(run(a, &out, NULL), 0);
        assert_non_null(strstr(out, "usage: lumis"));
        free(out);
    }
    expect("", 2, "usage");
    expect("frobnicate", 2, "unknown command 'frobnicate'");
    expect("info", 2, "no map given");
    expect("info --bogus x.exr", 2, "unknown option '--bogus'");
    expect("convert only-one.exr", 2, "needs IN and OUT");
    expect("convert sky:8x4 out.jpg", 2, "out.jpg: unknown extension");
    /* Bad values are named, with what was expected. */
    expect("render --scene spheres --seed -1 -o x.exr", 2,
           "--seed needs an integer in [0, 2147483647], not '-1'");
    expect("render --scene spheres --method bsdf --mis power -o x.exr", 2, "--mis power");
    expect("render --scene spheres --exposure 2 -o x.exr", 2, "give --png OUT.png");
    expect("convert sky:8x4 x.hdr --half", 2, "--half applies to EXR output only");
    expect("sky --size 8x4 -o x.exr --tonemap aces", 2, "--tonemap applies to PNG output only");
    char *help = NULL;
    assert_int_equal(run("info --help", &help, NULL), 0);
    assert_null(strstr(help, "%%")); /* printed with fputs: no printf escapes */
    assert_non_null(strstr(help, "top 1 % is"));
    free(help);
    expect("convert sky:8x4 o.png --tonemap filmic", 2, "--tonemap");
    expect("convert sky:8x4 o.png --exposure lots", 2, "--exposure");
    expect("sky --sun-elevation 100 -o x.exr", 2, "--sun-elevation");
    expect("sky --turbidity 0.5 -o x.exr", 2, "--turbidity");
    expect("sky --size 10y5 -o x.exr", 2, "--size");
    expect("sky", 2, "-o OUT");
    expect("studio --intensity -3 -o x.exr", 2, "--intensity");
}

/* The option tables (tools/lumis/optparse.c): --name VALUE and --name=VALUE alike, ranges
 * open and closed as the table says, a flag that is given a value and an unknown option
 * refused (with the nearest name), and --help and lumis help --markdown generated from the
 * same table, each option with its metavar and help. */
static void option_tables_parse_and_document(void **state)
{
    (void)state;
    char *out = NULL;
    /* "=VALUE" reaches the same check as a separate value */
    expect("sky --turbidity=11 -o x.exr", 2, "--turbidity needs a value in [1.7, 10], not '11'");
    expect("sky --size=8x4 --output=x.hdr --tonemap=aces", 2, "--tonemap applies to PNG output");
    /* the ends of a range: (0, 90) for --max-angle, [0, 90] for --sun-elevation */
    expect("luminaire create x.json --from a.ies --max-angle 90", 2,
           "--max-angle needs degrees in (0, 90), not '90'");
    expect("sky --sun-elevation 90.5 -o x.exr", 2, "--sun-elevation needs degrees in [0, 90]");
    expect("studio --intensity 0 -o x.exr", 2, "--intensity needs a number in (0, 1e30], not '0'");
    expect("sky --no-sun=1 -o x.exr", 2, "--no-sun takes no value");
    expect("sky --turbidty 3 -o x.exr", 2,
           "unknown option '--turbidty' (did you mean --turbidity?)");
    expect("render --scene spheres --spp 0 -o x.exr", 2, "--spp needs a count in [1, 1048576]");
    expect("bench-samplers sky:8x4 --runs 0", 2, "--runs needs a count in [1, 101], not '0'");
    /* a value in range is taken: 90 is --sun-elevation's top, written as a PFM */
    char a[1024];
    snprintf(a, sizeof a, "sky --sun-elevation=90 --size=8x4 -o '%s'", tu_path("top.pfm"));
    assert_int_equal(run(a, NULL, NULL), 0);
    /* --help and the Markdown come from the table */
    assert_int_equal(run("render --help", &out, NULL), 0);
    assert_non_null(strstr(out, "usage: lumis render"));
    assert_non_null(strstr(out, "  --lum-budget K"));
    assert_non_null(strstr(out, "luminaire samples per camera sample"));
    assert_non_null(strstr(out, "  -o, --output OUT"));
    free(out);
    assert_int_equal(run("help --markdown sky", &out, NULL), 0);
    assert_non_null(strstr(out, "## lumis sky"));
    assert_non_null(strstr(out, "| `--ground-albedo A` | 0..1 (default 0.1) |"));
    assert_null(strstr(out, "## lumis studio"));
    free(out);
    assert_int_equal(run("help --markdown luminaire", &out, NULL), 0);
    assert_non_null(strstr(out, "## lumis luminaire create"));
    assert_non_null(strstr(out, "## lumis luminaire predict"));
    free(out);
    expect("help --markdown nothing", 2, "no option table for 'nothing'");
}

/* Standard output that cannot be written (a full disk: /dev/full) is an error of every
 * command that prints, help included, never exit 0 with the output lost. */
static void stdout_write_errors_are_errors(void **state)
{
    (void)state;
    static const char *const cmds[] = {"info sky:64x32 --json",
                                       "--help",
                                       "--version",
                                       "render --help",
                                       "compare --help",
                                       "sample sky:64x32 --method alias -n 20000",
                                       "bench-samplers sky:32x16 --json --samples 500 --runs 1"};
    for (size_t k = 0; k < sizeof cmds / sizeof *cmds; k++) {
        char a[1024], *err = NULL;
        snprintf(a, sizeof a, "('%s' %s > /dev/full)", LUMIS_CLI, cmds[k]);
        const int rc = tu_run(a, NULL, &err);
        if (rc != 1 || !err || (!strstr(err, "stdout") && !strstr(err, "standard output")))
            fail_msg("lumis %s > /dev/full: exit %d, stderr: %s", cmds[k], rc, err);
        free(err);
    }
}

static void runtime_errors_name_file_and_reason(void **state)
{
    (void)state;
    char a[1024];
    expectf(1, "missing.exr: No such file or directory", "info '%s'", tu_path("missing.exr"));
    tu_write_file(tu_path("text.exr"), "hello\n", 6);
    expectf(1, "text.exr: not an EXR, Radiance HDR, PFM or PNG image", "info '%s'",
            tu_path("text.exr"));
    tu_write_file(tu_path("trunc.hdr"), "#?RADIANCE\n\n-Y 9 +X 9\nAB", 24);
    expectf(1, "trunc.hdr", "info '%s'", tu_path("trunc.hdr"));
    snprintf(a, sizeof a, "sky --size 16x8 -o '%s/nope/sky.exr'", tu_tmpdir());
    expect(a, 2, "nope/sky.exr: the directory");
    expect("info sky:12", 1, "expected sky:WxH");
}

static cJSON *info_json(const char *spec)
{
    char a[1024], *out = NULL;
    snprintf(a, sizeof a, "info --json '%s'", spec);
    assert_int_equal(run(a, &out, NULL), 0);
    cJSON *o = cJSON_Parse(out);
    free(out);
    assert_non_null(o);
    return o;
}

static double num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!cJSON_IsNumber(v)) fail_msg("key %s missing or not a number", key);
    return v->valuedouble;
}

static void info_json_has_the_documented_keys(void **state)
{
    (void)state;
    cJSON *o = info_json("sky:64x32");
    assert_int_equal((int)num(o, "width"), 64);
    assert_int_equal((int)num(o, "height"), 32);
    const char *keys[] = {"avg_luminance", "max_luminance", "power",
                          "top1_share",    "top01_share",   "replaced"};
    for (int k = 0; k < 6; k++) (void)num(o, keys[k]);
    const cJSON *rgb = cJSON_GetObjectItemCaseSensitive(o, "power_rgb");
    assert_true(cJSON_IsArray(rgb) && cJSON_GetArraySize(rgb) == 3);
    assert_true(fabs(num(o, "avg_luminance") * 4 * 3.14159265358979 - num(o, "power")) <
                1e-9 * num(o, "power"));
    cJSON_Delete(o);
    /* The sun (lumis_sun_find): the default sky's, at its documented direction (35 degrees up,
     * azimuth 60: lumis/io.h); none in the studio's soft boxes. */
    o = info_json("sky:1024x512");
    const cJSON *sun = cJSON_GetObjectItemCaseSensitive(o, "sun");
    assert_true(cJSON_IsObject(sun));
    const cJSON *dir = cJSON_GetObjectItemCaseSensitive(sun, "dir");
    assert_true(cJSON_IsArray(dir) && cJSON_GetArraySize(dir) == 3);
    assert_true(fabs(cJSON_GetArrayItem(dir, 1)->valuedouble - sin(35.0 * 3.14159265358979 / 180)) <
                0.005);
    assert_true(num(sun, "share") > 0.5 && num(sun, "radius_deg") < 1.0);
    cJSON_Delete(o);
    o = info_json("studio:256x128");
    assert_true(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(o, "sun")));
    cJSON_Delete(o);
    /* Text output mentions the same quantities. */
    char *out = NULL;
    assert_int_equal(run("info studio:32x16", &out, NULL), 0);
    assert_non_null(strstr(out, "32 x 16"));
    assert_non_null(strstr(out, "top 0.1% share"));
    assert_non_null(strstr(out, "sun            none"));
    free(out);
}

static void convert_resize_preserves_power_and_writes_every_format(void **state)
{
    (void)state;
    char a[1024];
    expectf(0, NULL, "sky --size 256x128 --sun-elevation 20 -o '%s'", tu_path("s.exr"));
    cJSON *o = info_json(tu_path("s.exr"));
    double p0 = num(o, "power");
    cJSON_Delete(o);
    const char *outs[] = {"r.exr", "r.pfm", "r.hdr"};
    for (int k = 0; k < 3; k++) {
        expectf(0, NULL, "convert '%s' '%s' --resize 100x37", tu_path("s.exr"), tu_path(outs[k]));
        o = info_json(tu_path(outs[k]));
        assert_int_equal((int)num(o, "width"), 100);
        double tol = k == 2 ? 1e-2 : 1e-5; /* RGBE keeps 8 bits */
        if (fabs(num(o, "power") - p0) > tol * p0)
            fail_msg("%s: %g vs %g", outs[k], num(o, "power"), p0);
        cJSON_Delete(o);
    }
    expectf(0, NULL, "convert '%s' '%s' --exposure -3 --tonemap aces", tu_path("s.exr"),
            tu_path("r.png"));
    size_t n;
    unsigned char *png = tu_read_file(tu_path("r.png"), &n);
    assert_true(n > 8 && memcmp(png, "\x89PNG", 4) == 0);
    free(png);
    snprintf(a, sizeof a, "convert '%s' '%s' --half --compression piz --tile 32", tu_path("s.exr"),
             tu_path("h.exr"));
    expect(a, 0, NULL);
}

static void demo_writes_the_sky_and_its_info(void **state)
{
    (void)state;
    char a[1024], *out = NULL;
    snprintf(a, sizeof a, "demo --out '%s' --time 0.3", tu_path("demo"));
    assert_int_equal(run(a, &out, NULL), 0);
    assert_non_null(strstr(out, "top 1% share"));
    assert_non_null(strstr(out, "inversion left, kd-tree right"));
    /* the table (and the picture's label) give the time each render took, not its budget */
    double used_printed[2] = {0, 0};
    const char *row = strstr(out, "\n  inversion ");
    assert_non_null(row);
    assert_int_equal(sscanf(row, " inversion %*d %*f %lf", &used_printed[0]), 1);
    row = strstr(out, "\n  kdtree ");
    assert_non_null(row);
    assert_int_equal(sscanf(row, " kdtree %*d %*f %lf", &used_printed[1]), 1);
    free(out);
    const char *files[] = {"sky.exr",
                           "sky.png",
                           "spheres-inversion.exr",
                           "spheres-kdtree.exr",
                           "spheres-inversion.json",
                           "spheres-kdtree.json",
                           "spheres-equal-time.png"};
    for (int k = 0; k < 7; k++) assert_int_equal(tu_count_entries(tu_path("demo"), files[k]), 1);
    assert_int_equal(tu_count_entries(tu_path("demo"), "."), 2); /* "." and "..": no temp files */
    cJSON *o = info_json(tu_path("demo/sky.exr"));
    assert_true(num(o, "top01_share") > 0.5);
    cJSON_Delete(o);
    /* Equal time: both sidecars name the same budget and the method they used. */
    const char *methods[2] = {"inversion", "kdtree"};
    for (int k = 0; k < 2; k++) {
        char name[64];
        snprintf(name, sizeof name, "demo/spheres-%s.json", methods[k]);
        size_t n;
        char *text = (char *)tu_read_file(tu_path(name), &n);
        cJSON *j = cJSON_ParseWithLength(text, n);
        assert_non_null(j);
        assert_true(num(j, "time_budget_seconds") == 0.3);
        assert_true(num(j, "spp") >= 1);
        const double used =
            num(cJSON_GetObjectItemCaseSensitive(j, "timings"), "budget_used_seconds");
        if (!(fabs(used - used_printed[k]) <= 0.0005))
            fail_msg("%s: %g s used, the demo printed %g s", methods[k], used, used_printed[k]);
        assert_string_equal(cJSON_GetObjectItemCaseSensitive(j, "method")->valuestring, methods[k]);
        cJSON_Delete(j);
        free(text);
    }
}

static void sample_and_pdf_agree_and_are_reproducible(void **state)
{
    (void)state;
    const char *methods[] = {"inversion",    "inversion-guided", "alias",  "kdtree",
                             "kdtree-exact", "hierarchical",     "uniform"};
    for (int m = 0; m < 7; m++) {
        char a[1024], *out = NULL, *out2 = NULL;
        snprintf(a, sizeof a, "sample sky:64x32 --method %s -n 200 --seed 3 --blocks 50",
                 methods[m]);
        assert_int_equal(run(a, &out, NULL), 0);
        assert_int_equal(run(a, &out2, NULL), 0);
        assert_string_equal(out, out2); /* same seed, same samples */
        free(out2);
        /* Feed the directions back through 'lumis pdf'. */
        FILE *f = fopen(tu_path("dirs.txt"), "w");
        double pdfs[200];
        int lines = 0;
        for (char *line = strtok(out, "\n"); line; line = strtok(NULL, "\n")) {
            double x, y, z, p, r, g, b;
            assert_int_equal(
                sscanf(line, "%lf %lf %lf %lf %lf %lf %lf", &x, &y, &z, &p, &r, &g, &b), 7);
            assert_true(fabs(x * x + y * y + z * z - 1.0) < 1e-5 && p > 0.0);
            fprintf(f, "%.9g %.9g %.9g\n", x, y, z);
            pdfs[lines++] = p;
        }
        fclose(f);
        free(out);
        assert_int_equal(lines, 200);
        snprintf(a, sizeof a, "pdf sky:64x32 --method %s --blocks 50", methods[m]);
        assert_int_equal(run_stdin(a, tu_path("dirs.txt"), &out, NULL), 0);
        int k = 0;
        for (char *line = strtok(out, "\n"); line; line = strtok(NULL, "\n"), k++) {
            double p, r, g, b;
            assert_int_equal(sscanf(line, "%lf %lf %lf %lf", &p, &r, &g, &b), 4);
            if (fabs(p - pdfs[k]) > 1e-6 * pdfs[k])
                fail_msg("%s line %d: pdf %g vs sampled %g", methods[m], k, p, pdfs[k]);
        }
        assert_int_equal(k, 200);
        free(out);
    }
    expect("sample sky:8x4 --method kdtree", 2, "-n N is required");
    expect("sample sky:8x4 --method cdf -n 3", 2, "--method must be one of");
    /* Messages about what the user did (issue 23's list): a float parameter too small for a
     * float, a studio intensity that overflowed float radiance, help for one command, more
     * threads than processors. */
    expect("lights sky:64x32 --method wu --param gamma=1e-300", 2, "at least 1.2e-38");
    expect("studio --intensity 1e37 -o x.exr", 2, "--intensity needs a number in (0, 1e30]");
    {
        char *hout = NULL;
        assert_int_equal(run("help render", &hout, NULL), 0);
        assert_non_null(strstr(hout, "usage: lumis render"));
        free(hout);
    }
    expect("help nothing", 2, "unknown command 'nothing'");
    {
        /* median cut makes regions: no Wu counts in its summary */
        char *lout = NULL;
        assert_int_equal(run("lights sky:64x32 --method median-cut -k 4", &lout, NULL), 0);
        assert_non_null(strstr(lout, "4 lights by median-cut, 8 sets"));
        assert_null(strstr(lout, "EnvDirects"));
        free(lout);
    }
    expect("sample sky:64x32 --method alias -n 1 --rotate 1e300", 2, "--rotate needs degrees");
    expect("lights sky:64x32 --method median-cut -k 2 --rotate 1e300", 2, "--rotate needs");
    {
        /* Wu's K fitted to the time on a map of 8 pixels: the pilots' K fit the map ("count
         * 16 is not in 1 .. 8" came from a pilot) */
        char a2[1024];
        snprintf(a2, sizeof a2,
                 "render --scene spheres --env sky:4x2 --lights wu --time 0.2 --size 8x6 --quiet "
                 "-o '%s'",
                 tu_path("tiny-wu.exr"));
        expect(a2, 0, NULL);
    }
    {
        char a2[1024];
        snprintf(a2, sizeof a2,
                 "render --scene spheres --size 8x6 --spp 1 --threads 4096 --quiet -o '%s'",
                 tu_path("threads.exr"));
        expect(a2, 0, "--threads 4096: capped at");
    }
    /* strtoull read "-5" as 2^64 - 5; a seed is a plain unsigned integer */
    expect("sample sky:8x4 --method alias -n 1 --seed -5", 2, "--seed needs an integer");
    expect("sample sky:8x4 --method alias -n 1 --seed ' 5'", 2, "--seed needs an integer");
    expect("sample sky:8x4 --method alias -n 1 --seed 18446744073709551616", 2, "--seed");
    expect("sample sky:8x4 --method alias -n 1 --seed 18446744073709551615", 0, NULL);
    expect("pdf", 2, "no map given");
    tu_write_file(tu_path("bad.txt"), "1 2\n", 4);
    char *err = NULL;
    assert_int_equal(run_stdin("pdf sky:8x4", tu_path("bad.txt"), NULL, &err), 1);
    assert_non_null(strstr(err, "stdin line 1: expected 'x y z'"));
    free(err);
    err = NULL;
    tu_write_file(tu_path("zero.txt"), "0 1 0\n0 0 0\n", 12);
    assert_int_equal(run_stdin("pdf sky:8x4", tu_path("zero.txt"), NULL, &err), 1);
    assert_non_null(strstr(err, "stdin line 2: the direction (0 0 0) has no finite"));
    free(err);
}

static void bench_samplers_reports_every_method(void **state)
{
    (void)state;
    char *out = NULL;
    assert_int_equal(
        run("bench-samplers studio:64x32 --json --samples 2000 --runs 1 --blocks 40", &out, NULL),
        0);
    cJSON *arr = cJSON_Parse(out);
    free(out);
    assert_true(cJSON_IsArray(arr));
    assert_int_equal(cJSON_GetArraySize(arr), 8); /* seven methods and the kd-tree's variant */
    const cJSON *o;
    cJSON_ArrayForEach(o, arr)
    {
        const char *keys[] = {"build_ms", "bytes", "samples_per_second", "rel_stderr_64"};
        for (int k = 0; k < 4; k++) (void)num(o, keys[k]);
        assert_true(cJSON_IsString(cJSON_GetObjectItemCaseSensitive(o, "method")));
        /* A method without tables has no compression ratio (it was bytes / 1). */
        const cJSON *comp = cJSON_GetObjectItemCaseSensitive(o, "compression_vs_inversion");
        if (num(o, "bytes") > 0.0)
            assert_true(cJSON_IsNumber(comp) && comp->valuedouble > 0.0);
        else
            assert_true(cJSON_IsNull(comp));
        assert_true(num(o, "samples_per_second") > 0.0);
    }
    cJSON_Delete(arr);
    /* --strata: the light sets' region samplers beside the map's */
    assert_int_equal(run("bench-samplers studio:64x32 --json --samples 2000 --runs 1 --methods "
                         "inversion --strata median-cut,wu --strata-k 6",
                         &out, NULL),
                     0);
    arr = cJSON_Parse(out);
    free(out);
    assert_int_equal(cJSON_GetArraySize(arr), 3);
    const cJSON *st = cJSON_GetArrayItem(arr, 0);
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(st, "method")->valuestring,
                        "strata:median-cut");
    assert_true(num(st, "regions") == 6 && num(st, "bytes") > 0 &&
                num(st, "batch_samples_per_second") > 0);
    /* one draw in each of 6 equal-power strata: below importance sampling's error */
    const double rse_strata = num(st, "rel_stderr_64"),
                 rse_inv = num(cJSON_GetArrayItem(arr, 2), "rel_stderr_64");
    if (!(rse_strata > 0.0 && rse_strata < rse_inv))
        fail_msg("rse@64: strata %g, inversion %g", rse_strata, rse_inv);
    cJSON_Delete(arr);
    expect("bench-samplers sky:16x8 --strata cut", 2, "unknown light-set method");
    /* Text: the columns fit a long path, the methods asked for and no others, the JSON's
     * name for the error column, and a verdict that says which wins and by how much. */
    char a[2048], *err = NULL;
    expectf(0, NULL, "sky --size 32x16 -o '%s'", tu_path("a-rather-long-map-name-here.pfm"));
    snprintf(a, sizeof a, "bench-samplers '%s' --methods inversion,kdtree --samples 500 --runs 1",
             tu_path("a-rather-long-map-name-here.pfm"));
    assert_int_equal(run(a, &out, NULL), 0);
    assert_null(strstr(out, "angles"));
    assert_non_null(strstr(out, "rel_stderr_64"));
    assert_non_null(strstr(out, "verdict (lower is better): lowest error at 64 samples: "));
    assert_non_null(strstr(out, "x the error"));
    const char *row = strstr(out, "\n") + 1, *k = strstr(row, " kdtree");
    const int method_col = (int)(strstr(out, " method") - out),
              row_col = (int)(row[0] ? strstr(row, " inversion") - row : -1);
    assert_int_equal(method_col, row_col); /* the method column lines up with its header */
    assert_non_null(k);
    free(out);
    /* a map that does not load: its error, and no header before it */
    assert_int_equal(run("bench-samplers nope.exr --runs 1 --samples 10", &out, &err), 1);
    assert_string_equal(out, "");
    assert_non_null(strstr(err, "nope.exr"));
    free(out);
    free(err);
}

static cJSON *read_json(const char *name);
static const cJSON *item(const cJSON *o, const char *key);

static void render_writes_the_same_image_on_any_thread_count(void **state)
{
    (void)state;
    char a[1024];
    for (int t = 1; t <= 2; t++) {
        char name[32];
        snprintf(name, sizeof name, "r%d.pfm", t);
        snprintf(a, sizeof a,
                 "render --scene spheres --env sky:64x32 --spp 2 --size 60x24 --threads %d -o '%s'",
                 t, tu_path(name));
        expect(a, 0, "rendered 60x24");
    }
    size_t n1, n2;
    unsigned char *a1 = tu_read_file(tu_path("r1.pfm"), &n1),
                  *a2 = tu_read_file(tu_path("r2.pfm"), &n2);
    assert_true(n1 == n2 && n1 > 60 * 24 * 12);
    assert_memory_equal(a1, a2, n1);
    free(a1);
    free(a2);
    expect("render -o x.exr", 2, "give one scene");
    /* Every sequence renders the same image on any thread count, and the sidecar names the
     * one used (sobol by default, as "default" does). */
    static const char *const seqs[] = {"",           "default", "pcg",  "halton",
                                       "stratified", "zsobol",  "pmj02"};
    for (size_t q = 0; q < sizeof seqs / sizeof seqs[0]; q++)
        for (int t = 1; t <= 2; t++) {
            char name[32];
            snprintf(name, sizeof name, "q%d.pfm", t);
            snprintf(a, sizeof a,
                     "render --scene bunny-plane --env sky:64x32 --spp 3 --size 40x30 --threads %d "
                     "%s%s -o '%s'",
                     t, *seqs[q] ? "--sequence " : "", seqs[q], tu_path(name));
            expect(a, 0, "rendered 40x30");
            if (t == 1) {
                cJSON *j = read_json("q1.json");
                const char *want = !*seqs[q] || !strcmp(seqs[q], "default") ? "sobol" : seqs[q];
                assert_string_equal(item(j, "sequence")->valuestring, want);
                cJSON_Delete(j);
                continue;
            }
            a1 = tu_read_file(tu_path("q1.pfm"), &n1);
            a2 = tu_read_file(tu_path("q2.pfm"), &n2);
            assert_true(n1 == n2 && n1 > 40 * 30 * 12);
            if (memcmp(a1, a2, n1) != 0)
                fail_msg("--sequence %s: threads change the image", seqs[q]);
            free(a1);
            free(a2);
        }
    expect("render --scene spheres --sequence sobel -o x.exr", 2, "must be sobol, zsobol");
    /* A scene file: a sphere, a plane and an OBJ mesh, resolved next to the file. */
    const char obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n";
    tu_write_file(tu_path("quad.obj"), obj, sizeof obj - 1);
    const char scene[] =
        "{\"camera\": {\"eye\": [0,1,5], \"look_at\": [0,0.5,0], \"up\": [0,1,0], "
        "\"fov_deg\": 40, \"width\": 32, \"height\": 24},\n"
        " \"environment\": {\"map\": \"sky:32x16\", \"rotation_deg\": 30, \"scale\": 0.5},\n"
        " \"objects\": [{\"type\": \"sphere\", \"center\": [0,1,0], \"radius\": 1,\n"
        "   \"material\": {\"type\": \"lambert\", \"albedo\": [0.8,0.8,0.8]}},\n"
        "  {\"type\": \"mesh\", \"file\": \"quad.obj\", \"transform\": {\"translate\": [1,0,0], "
        "\"rotate_deg\": [0,30,0], \"scale\": 0.5},\n"
        "   \"material\": {\"type\": \"ward\", \"diffuse\": [0.1,0.1,0.1], \"specular\": "
        "[0.3,0.3,0.3], "
        "\"alpha_x\": 0.1, \"alpha_y\": 0.1}},\n"
        "  {\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,1,0], \"size\": 20,\n"
        "   \"material\": {\"type\": \"lambert\", \"albedo\": [0.5,0.5,0.5]}}]}\n";
    tu_write_file(tu_path("scene.json"), scene, sizeof scene - 1);
    snprintf(a, sizeof a, "render '%s' --spp 1 -o '%s'", tu_path("scene.json"), tu_path("s.exr"));
    expect(a, 0, "rendered 32x24");
    /* Malformed scene files: each error names the file, the JSON path and what was expected. */
    static const bad_file bad[] = {
        {"{\"objects\": [", "malformed JSON"},
        {"{}", "objects: expected an array of objects"},
        {"{\"objects\": [{\"type\": \"cube\", \"material\": {}}]}",
         "objects[0].type: expected sphere, plane or mesh"},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0], \"radius\": 1}]}",
         "objects[0].center: expected an array of 3 numbers"},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": \"big\"}]}",
         "objects[0].radius: expected a number"},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1}]}",
         "objects[0].material: expected a material object (missing)"},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"material\": "
         "{\"type\": \"ward\", \"alpha_x\": 7}}]}",
         "objects[0].material.alpha_x: expected a number in"},
        {"{\"objects\": [{\"type\": \"mesh\", \"file\": \"missing.obj\", \"material\": {\"type\": "
         "\"lambert\"}}]}",
         "objects[0].file: cannot load mesh"},
        {"{\"objects\": [{\"type\": \"mesh\", \"file\": \"broken.obj\", \"material\": {\"type\": "
         "\"lambert\"}}]}",
         "objects[0].file"},
        {"{\"camera\": {\"fov_deg\": 500}, \"objects\": []}",
         "camera.fov_deg: expected a number in"},
    };
    tu_write_file(tu_path("broken.obj"), "v 1 2\nf 9 9 9\nthis is not obj\n", 30);
    snprintf(a, sizeof a, "-o '%s'", tu_path("x.exr"));
    expect_bad_files("render", "bad.json", a, bad, sizeof bad / sizeof bad[0]);
    expect("render --scene bunny -o x.exr", 2, "unknown scene 'bunny'");
    /* every built-in named, as lumis_scene_builtin_names lists them (the last one too) */
    expect("render --scene bunny -o x.exr", 2, "(built in: spheres, bunny-plane, ");
    expect("render --scene bunny -o x.exr", 2,
           ", wu-mixed, headlight, headlight-close, glossy-only, window, open-sky)");
    snprintf(a, sizeof a, "render --scene ward-aniso --env sky:32x16 --spp 1 --size 16x16 -o '%s'",
             tu_path("w.exr"));
    expect(a, 0, "rendered 16x16");
    expect("render --scene spheres --mis sometimes -o x.exr", 2, "--mis must be");
    expect("render --scene spheres --spp 4 --time 1 -o x.exr", 2, "not both");
    expect("render --scene spheres --time 0 -o x.exr", 2, "--time needs seconds");
    expect("render --scene spheres --bounces -1 -o x.exr", 2, "--bounces needs");
}

static cJSON *read_json(const char *name)
{
    size_t n;
    char *text = (char *)tu_read_file(tu_path(name), &n);
    assert_non_null(text);
    cJSON *j = cJSON_ParseWithLength(text, n);
    free(text);
    assert_non_null(j);
    return j;
}

static const cJSON *item(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!v) fail_msg("missing key %s", key);
    return v;
}

/* lights --sun: the sun first in the file (kind sun, with its angular radius), then the
 * residual's K lights; the powers add up to the map's. */
static void lights_sun_exports_the_sun_first(void **state)
{
    (void)state;
    char cmd[1024], *out = NULL;
    snprintf(cmd, sizeof cmd, "lights sky:512x256 --sun -k 3 --json %s", tu_path("lsun.json"));
    assert_int_equal(run(cmd, &out, NULL), 0);
    assert_non_null(strstr(out, "sun: dir ("));
    free(out);
    cJSON *j = read_json("lsun.json");
    const cJSON *lights = item(j, "lights");
    assert_int_equal(cJSON_GetArraySize(lights), 4);
    const cJSON *s0 = cJSON_GetArrayItem(lights, 0);
    assert_string_equal(item(s0, "kind")->valuestring, "sun");
    assert_true(item(s0, "angular_radius_rad")->valuedouble > 0.0);
    double total = 0.0;
    for (int k = 0; k < 4; k++)
        total += cJSON_GetArrayItem(item(cJSON_GetArrayItem(lights, k), "power"), 1)->valuedouble;
    cJSON_Delete(j);
    cJSON *o = info_json("sky:512x256");
    assert_true(fabs(total - cJSON_GetArrayItem(item(o, "power_rgb"), 1)->valuedouble) <
                1e-5 * total);
    cJSON_Delete(o);
}

/* render --sun: the summary and the sidecar say the sun found (the default sky's, 35 degrees
 * up), or that none was (the studio); without --sun the sidecar's "sun" is null. */
static void render_sun_is_reported(void **state)
{
    (void)state;
    char cmd[1024], *err = NULL;
    snprintf(cmd, sizeof cmd,
             "render --scene spheres --env sky:512x256 --sun --spp 1 --size 32x24 -o %s",
             tu_path("sun.exr"));
    assert_int_equal(run(cmd, NULL, &err), 0);
    assert_non_null(strstr(err, "lumis: sun: dir ("));
    free(err);
    cJSON *j = read_json("sun.json");
    const cJSON *sun = item(j, "sun");
    assert_true(cJSON_IsTrue(item(sun, "found")));
    assert_true(fabs(cJSON_GetArrayItem(item(sun, "dir"), 1)->valuedouble -
                     sin(35.0 * 3.14159265358979 / 180)) < 0.01);
    assert_true(item(sun, "share")->valuedouble > 0.5);
    cJSON_Delete(j);
    snprintf(cmd, sizeof cmd,
             "render --scene spheres --env studio:128x64 --sun --spp 1 --size 32x24 -o %s",
             tu_path("nosun.exr"));
    err = NULL;
    assert_int_equal(run(cmd, NULL, &err), 0);
    assert_non_null(strstr(err, "lumis: sun: none found"));
    free(err);
    j = read_json("nosun.json");
    assert_true(cJSON_IsFalse(item(item(j, "sun"), "found")));
    cJSON_Delete(j);
    snprintf(cmd, sizeof cmd, "render --scene spheres --env sky:128x64 --spp 1 --size 32x24 -o %s",
             tu_path("plain.exr"));
    assert_int_equal(run(cmd, NULL, NULL), 0);
    j = read_json("plain.json");
    assert_true(cJSON_IsNull(item(j, "sun")));
    cJSON_Delete(j);
}

/* relMSE of the test folder's image `test` against its `ref`, by lumis compare. */
static double relmse_between(const char *ref, const char *test)
{
    char a[2048], *text = NULL;
    snprintf(a, sizeof a, "compare '%s' '%s' --json --no-hdr-flip", tu_path(ref), tu_path(test));
    assert_int_equal(run(a, &text, NULL), 0);
    cJSON *cmp = cJSON_Parse(text);
    assert_non_null(cmp);
    const double v = num(cmp, "relmse");
    cJSON_Delete(cmp);
    free(text);
    return v;
}

/* The automatic estimator is lumis render's default for a map's light (issue 39): with no
 * option fixing the estimator the sidecar's auto_estimator says what was chosen and why (by
 * the prediction from the scene; --auto-pilots by pilots), and the summary that --spp counts
 * the chosen one's samples; an option that fixes it (--method,
 * --mis, --lights ...) or --no-auto turns it off and the sidecar names that option; --no-auto
 * is the map with MIS through the default sampler, bit for bit; luminaires are not its. */
static void render_default_is_automatic(void **state)
{
    (void)state;
    const char *base = "render --scene spheres --env sky:64x32 --size 40x30 --threads 1";
    /* the default predicts from the scene: the spheres reflect 47 % diffusely (mirror and
     * glossy spheres on a diffuse ground), under the strata's 50 %: MIS, no pilots */
    expectf(0, "predicted from the scene", "%s --spp 4 -o '%s'", base, tu_path("auto.exr"));
    cJSON *j = read_json("auto.json");
    const cJSON *a = item(j, "auto_estimator");
    assert_true(cJSON_IsObject(a));
    assert_true(cJSON_IsTrue(item(a, "default")));
    assert_string_equal(item(a, "mode")->valuestring, "predict");
    assert_string_equal(item(a, "chosen")->valuestring, "mis");
    assert_string_equal(item(a, "why")->valuestring,
                        "predicted: the diffuse share of the surfaces seen");
    const double share = num(a, "diffuse_share");
    assert_true(share > 0.3 && share < 0.5);
    assert_true(num(a, "diffuse_share_min") == 0.5);
    assert_true(num(a, "rays_met") > 0 && num(a, "pilot_seconds") == 0.0);
    assert_string_equal(item(a, "spp_counts")->valuestring, "samples of the chosen estimator");
    assert_true(cJSON_IsNull(item(j, "auto_off_by")));
    cJSON_Delete(j);
    /* --auto-pilots: 64 spp, a cap (0.15 x the render) of 9.6 of the prior's first pilot
     * halves holds the prior's pair and MIS's (5 more after the first and MIS's warm-up) */
    expectf(0, "are ", "%s --spp 64 --auto-pilots -o '%s'", base, tu_path("pilots.exr"));
    j = read_json("pilots.json");
    a = item(j, "auto_estimator");
    assert_true(cJSON_IsFalse(item(a, "default")));
    assert_string_equal(item(a, "mode")->valuestring, "pilots");
    assert_true(cJSON_IsNull(item(a, "diffuse_share")));
    const char *why = item(a, "why")->valuestring;
    assert_true(!strcmp(why, "least relmse_x_seconds of the pilots") ||
                !strcmp(why, "prior: no candidate beat it beyond the pilots' noise"));
    assert_true(num(j, "spp") == 64);
    assert_int_equal(cJSON_GetArraySize(item(a, "candidates")), 6);
    cJSON_Delete(j);
    /* 1 spp: a render smaller than its pilots takes the prior */
    expectf(0, "the prior (no pilots: the render is too small for them",
            "%s --spp 1 --auto-pilots -o '%s'", base, tu_path("auto1.exr"));
    j = read_json("auto1.json");
    assert_string_equal(item(item(j, "auto_estimator"), "chosen")->valuestring, "stratified-32");
    cJSON_Delete(j);
    /* fixed: by an estimator option, or --no-auto */
    static const char *const fixing[][2] = {{"--method inversion-guided", "--method"},
                                            {"--mis balance", "--mis"},
                                            {"--light-samples 1", "--light-samples"},
                                            {"--no-auto", "--no-auto"}};
    for (int k = 0; k < 4; k++) {
        char name[32];
        snprintf(name, sizeof name, "fixed%d.exr", k);
        expectf(0, "rendered 40x30", "%s --spp 4 %s -o '%s'", base, fixing[k][0], tu_path(name));
        snprintf(name, sizeof name, "fixed%d.json", k);
        j = read_json(name);
        assert_true(cJSON_IsNull(item(j, "auto_estimator")));
        assert_string_equal(item(j, "auto_off_by")->valuestring, fixing[k][1]);
        assert_string_equal(item(j, "estimator")->valuestring, "mis");
        cJSON_Delete(j);
    }
    /* --no-auto is the map with MIS as before: the image of --method inversion-guided */
    assert_true(relmse_between("fixed0.exr", "fixed3.exr") == 0.0);
    expectf(2, "--auto and --no-auto: give one", "%s --auto --no-auto -o '%s'", base,
            tu_path("x.exr"));
    expectf(2, "--auto-pilots and --no-auto: give one", "%s --auto-pilots --no-auto -o '%s'", base,
            tu_path("x.exr"));
    expectf(2, "--auto and --auto-pilots: give one", "%s --auto --auto-pilots -o '%s'", base,
            tu_path("x.exr"));
    /* luminaires light the headlight scene: no automatic estimator, nothing turned it off */
    expectf(0, "rendered", "render --scene headlight --size 16x12 --spp 1 --threads 1 -o '%s'",
            tu_path("lum.exr"));
    j = read_json("lum.json");
    assert_true(cJSON_IsNull(item(j, "auto_estimator")));
    assert_true(cJSON_IsNull(item(j, "auto_off_by")));
    cJSON_Delete(j);
}

/* A render split by passes: each share renders the whole render's samples of its range
 * (with zsobol too, whose sequence is planned for the whole count), and lumis merge joins
 * them into the whole render's image (up to float rounding), with the samples, passes and
 * times summed; shares that are not one render's, missing or repeated are refused. */
static void render_passes_and_merge(void **state)
{
    (void)state;
    static const char *const seqs[] = {"sobol", "zsobol", "pcg"};
    char a[2048];
    for (int q = 0; q < 3; q++) {
        /* --no-auto: the whole render and the shares by one estimator (a share is never
         * automatic: the choice would be each machine's timing) */
        const char *base =
            "render --scene bunny-plane --env sky:64x32 --size 40x30 --spp 7 --no-auto";
        expectf(0, "rendered 40x30", "%s --sequence %s --threads 2 -o '%s'", base, seqs[q],
                tu_path("whole.exr"));
        for (int i = 0; i < 3; i++) {
            char name[32];
            snprintf(name, sizeof name, "share%d.exr", i);
            expectf(0, "rendered 40x30", "%s --sequence %s --passes %d/3 --threads 1 -o '%s'", base,
                    seqs[q], i, tu_path(name));
        }
        cJSON *j = read_json("share1.json");
        const cJSON *sh = item(j, "share");
        /* share 1 of 3 of 7 samples: samples 2 .. 3 */
        assert_true(num(sh, "index") == 1 && num(sh, "count") == 3 && num(sh, "spp_total") == 7);
        assert_true(num(sh, "first_sample") == 2 && num(j, "spp") == 2);
        cJSON_Delete(j);
        snprintf(a, sizeof a, "merge '%s' '%s' '%s' -o '%s'", tu_path("share2.exr"),
                 tu_path("share0.exr"), tu_path("share1.exr"), tu_path("merged.exr"));
        expect(a, 0, "merged 3 shares of 7 samples");
        const double e = relmse_between("whole.exr", "merged.exr");
        if (!(e < 1e-12))
            fail_msg("%s: merged shares differ from the whole render: relMSE %g", seqs[q], e);
        j = read_json("merged.json");
        assert_true(num(j, "spp") == 7 && num(j, "passes") == 3);
        assert_true(cJSON_IsNull(item(j, "share")));
        assert_int_equal(cJSON_GetArraySize(item(j, "merged_from")), 3);
        cJSON_Delete(j);
    }
    /* a share rendered with another seed: not one render's */
    snprintf(a, sizeof a,
             "render --scene bunny-plane --env sky:64x32 --size 40x30 --spp 7 --sequence pcg "
             "--passes 1/3 --seed 9 -o '%s'",
             tu_path("other.exr"));
    expect(a, 0, "rendered 40x30");
    expectf(1, "differ in \"seed\"", "merge '%s' '%s' '%s' -o '%s'", tu_path("share0.exr"),
            tu_path("other.exr"), tu_path("share2.exr"), tu_path("m.exr"));
    expectf(1, "missing: 1", "merge '%s' '%s' -o '%s'", tu_path("share0.exr"),
            tu_path("share2.exr"), tu_path("m.exr"));
    expectf(1, "given twice", "merge '%s' '%s' '%s' -o '%s'", tu_path("share0.exr"),
            tu_path("share0.exr"), tu_path("share1.exr"), tu_path("m.exr"));
    expectf(1, "is not a share", "merge '%s' -o '%s'", tu_path("whole.exr"), tu_path("m.exr"));
    expectf(2, "would replace", "merge '%s' '%s' '%s' -o '%s'", tu_path("share0.exr"),
            tu_path("share1.exr"), tu_path("share2.exr"), tu_path("share1.exr"));
    /* the default sidecar of -o share1.pfm is share 1's own */
    snprintf(a, sizeof a, "merge '%s' '%s' '%s' -o '%s'", tu_path("share0.exr"),
             tu_path("share1.exr"), tu_path("share2.exr"), tu_path("share1.pfm"));
    expect(a, 2, "would replace the share's sidecar");
    expect("merge -o m.exr", 2, "no shares");
    expect("render --scene spheres --spp 8 --passes 3/3 -o x.exr", 2, "0 <= I < N");
    expect("render --scene spheres --spp 8 --passes 1 -o x.exr", 2, "--passes");
    expect("render --scene spheres --time 1 --passes 0/2 -o x.exr", 2, "not a time budget");
    expect("render --scene spheres --spp 2 --passes 0/3 -o x.exr", 2, "more shares than");
}

/* Test folders' paths are short: snprintf's bounds are there for safety */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-truncation"
#endif
/* Every light kind and render mode, split by render --passes into N shares for N in
 * {2, 3, 7, 16, 40} and joined by lumis merge, gives the one-machine render's image up to
 * float rounding: environment maps with each sampler, MIS heuristic and BSDF sampling,
 * light sets (point and stratified), Wu with and without upsampling, luminaires with each
 * strategy and visibility, photometric points and openings, path tracing, and each sample
 * sequence (one per mode, in turn). 16x12 pixels at 40 spp; shares two at a time; the
 * luminaire is preset:small (5x4 images of 24x20). */
static void merged_shares_equal_one_render_for_every_light_kind(void **state)
{
    (void)state;
    static const char *const modes[] = {
        "--scene spheres --env sky:32x16 --method inversion",
        "--scene spheres --env sky:32x16 --method inversion-guided",
        "--scene spheres --env sky:32x16 --method alias",
        "--scene spheres --env sky:32x16 --method kdtree",
        "--scene spheres --env sky:32x16 --method kdtree-exact",
        "--scene spheres --env sky:32x16 --method hierarchical",
        "--scene spheres --env sky:32x16 --method uniform",
        "--scene spheres --env sky:32x16 --method alias --mis power",
        "--scene spheres --env sky:32x16 --method alias --mis none",
        "--scene spheres --env sky:32x16 --method bsdf",
        "--scene spheres --env sky:32x16 --lights median-cut --lights-k 8",
        "--scene spheres --env sky:32x16 --lights median-cut --lights-mode stratified "
        "--lights-k 8",
        "--scene spheres --env sky:32x16 --lights wu --lights-k 8",
        "--scene spheres --env sky:32x16 --lights wu --lights-k 8 --upsample 2",
        "--scene headlight --luminaire preset:small --lum-strategy restricted",
        "--scene headlight --luminaire preset:small --lum-strategy uniform",
        "--scene headlight --luminaire preset:small --lum-strategy global",
        "--scene headlight --luminaire preset:small --lum-strategy auto",
        "--scene headlight --luminaire preset:small --visibility approx",
        "--scene headlight --luminaire preset:small --visibility shadowmap",
        "--scene headlight --luminaire preset:small --visibility none",
        "--scene spheres --fixture '" LUMIS_SOURCE_DIR
        "/tests/data/photometric/luxcore_asa_15m_r2.ies' --fixture-at 0,3,1",
        "--scene spheres --fixture '" LUMIS_SOURCE_DIR
        "/tests/data/photometric/luxcore_asa_15m_r2.ies' --fixture-at 0,3,1 --fixture-area",
        "--scene spheres --env sky:32x16 --method inversion --bounces 2",
    };
    static const char *const seqs[] = {"sobol", "zsobol", "pmj02", "halton", "stratified", "pcg"};
    static const int splits[] = {2, 3, 7, 16, 40};
    char a[8192], dir[1024];
    snprintf(dir, sizeof dir, "%s/prop", tu_tmpdir());
    mkdir(dir, 0755);
    for (size_t m = 0; m < sizeof modes / sizeof *modes; m++) {
        char args[2048];
        snprintf(args, sizeof args, "render %s --sequence %s --size 16x12 --spp 40 --quiet",
                 modes[m], seqs[m % 6]);
        expectf(0, NULL, "%s --threads 2 -o '%s/whole.exr'", args, dir);
        /* shadow maps (256x256 per cell, built by every share): 2, 3 and 7 shares only */
        const size_t nsplits = strstr(modes[m], "shadowmap") ? 3 : sizeof splits / sizeof *splits;
        for (size_t s = 0; s < nsplits; s++) {
            const int n = splits[s];
            snprintf(a, sizeof a,
                     "(rm -f '%s'/p*; i=0; while [ $i -lt %d ]; do echo $i; i=$((i+1)); done | "
                     "xargs -P 2 -I @ '%s' %s --threads 1 --passes @/%d -o '%s/p@.exr')",
                     dir, n, LUMIS_CLI, args, n, dir);
            char *err = NULL;
            if (tu_run(a, NULL, &err) != 0) fail_msg("%s, %d shares: %s", modes[m], n, err);
            free(err);
            snprintf(a, sizeof a, "merge '%s'/p*.exr -o '%s/merged.exr'", dir, dir);
            char want[64];
            snprintf(want, sizeof want, "merged %d shares of 40 samples", n);
            expect(a, 0, want);
            char w[1100], t[1100];
            snprintf(w, sizeof w, "prop/whole.exr");
            snprintf(t, sizeof t, "prop/merged.exr");
            const double e = relmse_between(w, t);
            if (!(e < 1e-10))
                fail_msg("%s (%s), %d shares: merged relMSE %g against one render", modes[m],
                         seqs[m % 6], n, e);
        }
    }
}

/* Sets field (a top-level key, or "share.KEY") of a share's sidecar NAME.json to the JSON
 * value text. */
static void edit_sidecar(const char *name, const char *field, const char *text)
{
    char p[1024];
    snprintf(p, sizeof p, "%s.json", name);
    cJSON *j = read_json(p);
    assert_non_null(j);
    cJSON *o = j;
    const char *dot = strchr(field, '.');
    if (dot) {
        char head[64];
        snprintf(head, sizeof head, "%.*s", (int)(dot - field), field);
        o = cJSON_GetObjectItemCaseSensitive(j, head);
        field = dot + 1;
    }
    cJSON_ReplaceItemInObjectCaseSensitive(o, field, cJSON_Parse(text));
    char *s = cJSON_Print(j);
    tu_write_file(tu_path(p), s, strlen(s));
    free(s);
    cJSON_Delete(j);
}

/* Renders share i of n of args to NAMEi.exr (and .json). */
static void render_share(const char *args, int i, int n, const char *name)
{
    char a[4096];
    snprintf(a, sizeof a, "render %s --passes %d/%d --quiet -o '%s%d.exr'", args, i, n,
             tu_path(name), i);
    expect(a, 0, NULL);
}

/* lumis merge refuses shares that are not one render's, or whose sidecars were edited,
 * naming the share and the field: another --pixel-centers, fixture multiplier, fixture file
 * content or position (the render key), sample counts that do not follow from the share's
 * index (3, 1, 2 for 2, 2, 2; fractions), a render key edited, a share with NaN pixels
 * (unless --allow-replaced); a subset of a 16-way split names its missing shares. */
static void merge_refuses_doctored_shares(void **state)
{
    (void)state;
    const char *ls = "--scene spheres --env sky:32x16 --lights median-cut --lights-k 8 "
                     "--size 16x12 --spp 6";
    char a[8192], b[2048];
    for (int i = 0; i < 3; i++) render_share(ls, i, 3, "ls");
    const char *ms = "merge '%s' '%s' '%s' -o '%s'";
#define MERGE3(x0, x1, x2)                                                                         \
    snprintf(a, sizeof a, ms, tu_path(x0), tu_path(x1), tu_path(x2), tu_path("m.exr"))
    MERGE3("ls0.exr", "ls1.exr", "ls2.exr");
    expect(a, 0, "merged 3 shares of 6 samples");
    /* --pixel-centers: another render */
    snprintf(b, sizeof b, "%s --pixel-centers", ls);
    render_share(b, 1, 3, "pc");
    MERGE3("ls0.exr", "pc1.exr", "ls2.exr");
    expect(a, 1, "pc1.exr is not a share of the render of");
    expect(a, 1, "differ in \"pixel_centers\" (true against false)");
    /* the same sidecar edited by hand (its key left): the field is named */
    tu_write_file(tu_path("ed1.exr"), "", 0);
    snprintf(a, sizeof a, "cp '%s' '%s' && cp '%s' '%s'", tu_path("ls1.exr"), tu_path("ed1.exr"),
             tu_path("ls1.json"), tu_path("ed1.json"));
    assert_int_equal(tu_run(a, NULL, NULL), 0);
    edit_sidecar("ed1", "pixel_centers", "true");
    MERGE3("ls0.exr", "ed1.exr", "ls2.exr");
    expect(a, 1, "differ in \"pixel_centers\"");
    MERGE3("ed1.exr", "ls0.exr", "ls2.exr"); /* first: its key does not match its fields */
    expect(a, 1, "ed1.exr: its \"render_key\"");
    /* sample counts: 3, 1, 2 (the same total) and a fraction */
    edit_sidecar("ed1", "pixel_centers", "false");
    edit_sidecar("ed1", "spp", "1");
    MERGE3("ls0.exr", "ed1.exr", "ls2.exr");
    expect(a, 1,
           "ed1.exr: share 1 of 3 of 6 samples holds samples 2 to 3 (2), its sidecar says "
           "\"spp\" 1");
    edit_sidecar("ed1", "spp", "2.5");
    MERGE3("ls0.exr", "ed1.exr", "ls2.exr");
    expect(a, 1, "\"spp\" 2.5");
    edit_sidecar("ed1", "spp", "2");
    edit_sidecar("ed1", "share.spp_total", "6.5");
    MERGE3("ls0.exr", "ed1.exr", "ls2.exr");
    expect(a, 1, "ed1.exr: \"share\" says 3 shares of 6.5 samples");
    edit_sidecar("ed1", "share.spp_total", "6");
    edit_sidecar("ed1", "render_key", "\"0123456789abcdef\"");
    MERGE3("ls0.exr", "ed1.exr", "ls2.exr");
    expect(a, 1, "ed1.exr: its \"render_key\" 0123456789abcdef is not the key of its fields");
    /* fixtures: another multiplier, position, or file content under the same name */
    const char *ies = LUMIS_SOURCE_DIR "/tests/data/photometric/luxcore_asa_15m_r2.ies";
    snprintf(a, sizeof a, "cp '%s' '%s'", ies, tu_path("fx.ies"));
    assert_int_equal(tu_run(a, NULL, NULL), 0);
    snprintf(b, sizeof b, "--scene spheres --fixture '%s' --fixture-at 0,3,1 --size 16x12 --spp 4",
             tu_path("fx.ies"));
    for (int i = 0; i < 3; i++) render_share(b, i, 3, "fx");
    char c[4096];
    snprintf(c, sizeof c, "%s --fixture-multiplier 2", b);
    render_share(c, 1, 3, "fm");
    MERGE3("fx0.exr", "fm1.exr", "fx2.exr");
    expect(a, 1, "differ in \"photometric\"");
    snprintf(c, sizeof c,
             "--scene spheres --fixture '%s' --fixture-at 0,3,1.5 --size 16x12 --spp 4",
             tu_path("fx.ies"));
    render_share(c, 1, 3, "fp");
    MERGE3("fx0.exr", "fp1.exr", "fx2.exr");
    expect(a, 1, "differ in \"photometric\"");
    snprintf(a, sizeof a, "(printf '\\n' >> '%s')", tu_path("fx.ies")); /* same name, new bytes */
    assert_int_equal(tu_run(a, NULL, NULL), 0);
    render_share(b, 1, 3, "fc");
    MERGE3("fx0.exr", "fc1.exr", "fx2.exr");
    expect(a, 1, "differ in \"inputs\"");
    /* a share with a NaN pixel: refused unless asked */
    snprintf(b, sizeof b, "%s --sequence pcg", ls);
    for (int i = 0; i < 3; i++) {
        snprintf(a, sizeof a, "render %s --passes %d/3 --quiet -o '%s%d.pfm'", b, i, tu_path("nan"),
                 i);
        expect(a, 0, NULL);
    }
    size_t len = 0;
    unsigned char *pfm = tu_read_file(tu_path("nan1.pfm"), &len);
    const float nan = NAN;
    memcpy(pfm + len - 4, &nan, 4); /* the last value (a PFM's data ends the file) */
    tu_write_file(tu_path("nan1.pfm"), pfm, len);
    free(pfm);
    snprintf(a, sizeof a, ms, tu_path("nan0.pfm"), tu_path("nan1.pfm"), tu_path("nan2.pfm"),
             tu_path("m.exr"));
    expect(a, 1, "nan1.pfm: share 1 has 1 pixel values that are not finite");
    snprintf(a + strlen(a), sizeof a - strlen(a), " --allow-replaced");
    expect(a, 0, "merged 3 shares");
    /* 16 shares (more than the 15 merge took), 14 of them given: the missing are named */
    const char *ls32 = "--scene spheres --env sky:32x16 --lights median-cut --lights-k 8 "
                       "--size 16x12 --spp 32";
    for (int i = 0; i < 16; i++) render_share(ls32, i, 16, "sx");
    snprintf(a, sizeof a, "merge");
    for (int i = 0; i < 16; i++)
        if (i != 3 && i != 9)
            snprintf(a + strlen(a), sizeof a - strlen(a), " '%s%d.exr'", tu_path("sx"), i);
    snprintf(a + strlen(a), sizeof a - strlen(a), " -o '%s'", tu_path("m.exr"));
    expect(a, 1, "14 of the 16 shares given; missing: 3, 9");
    /* all 16, listed in a file */
    char list[8192] = "";
    for (int i = 15; i >= 0; i--)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%d.exr\n", tu_path("sx"), i);
    tu_write_file(tu_path("list.txt"), list, strlen(list));
    snprintf(a, sizeof a, "merge --shares-from '%s' -o '%s'", tu_path("list.txt"),
             tu_path("m.exr"));
    expect(a, 0, "merged 16 shares of 32 samples");
#undef MERGE3
}

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

/* The sidecar describes the run; --time renders progressive passes; the built-in
 * bunny-plane needs no files; path tracing is labelled; instances in scene files. */
static void render_sidecar_time_budget_and_scenes(void **state)
{
    (void)state;
    char a[1024];
    snprintf(a, sizeof a,
             "render --scene bunny-plane --env sky:64x32 --spp 2 --size 40x30 --method kdtree "
             "--mis power --light-samples 2 -o '%s'",
             tu_path("bp.exr"));
    expect(a, 0, "rendered 40x30 at 2 spp");
    cJSON *j = read_json("bp.json");
    assert_string_equal(item(j, "scene")->valuestring, "bunny-plane");
    assert_string_equal(item(j, "mode")->valuestring, "direct");
    assert_string_equal(item(j, "method")->valuestring, "kdtree");
    assert_string_equal(item(j, "heuristic")->valuestring, "power");
    assert_true(num(j, "objects") == 3 && num(j, "spp") == 2 && num(j, "spp_requested") == 2);
    assert_true(num(j, "light_samples") == 2 && num(j, "width") == 40 && num(j, "height") == 30);
    const cJSON *rays = item(j, "rays"), *tm = item(j, "timings"), *sm = item(j, "sampler");
    assert_true(num(rays, "camera") == 40 * 30 * 2);
    assert_true(num(rays, "shadow") > 0 && num(rays, "per_second") > 0);
    assert_true(num(rays, "bounce") == 0);
    assert_true(num(tm, "render_seconds") > 0 &&
                num(tm, "total_seconds") >= num(tm, "render_seconds"));
    /* Before the first sample: the sampler's tables and the job (no budget: none used). */
    assert_true(num(tm, "prep_seconds") >= num(item(j, "sampler"), "build_ms") / 1000.0);
    assert_true(cJSON_IsNull(item(tm, "budget_used_seconds")));
    assert_true(num(sm, "table_bytes") > 0 && num(sm, "build_ms") >= 0 &&
                num(sm, "kdtree_blocks") > 0);
    assert_string_equal(item(item(j, "outputs"), "exr")->valuestring, tu_path("bp.exr"));
    cJSON_Delete(j);
    /* A time budget: passes until it is spent, the samples reached reported. */
    snprintf(a, sizeof a,
             "render --scene spheres --env sky:64x32 --time 0.4 --size 60x24 --bounces 2 -o '%s' "
             "--sidecar '%s'",
             tu_path("t.exr"), tu_path("t-side.json"));
    expect(a, 0, "path traced");
    j = read_json("t-side.json");
    assert_true(num(j, "time_budget_seconds") == 0.4);
    assert_true(cJSON_IsNull(item(j, "spp_requested")));
    assert_true(num(j, "spp") >= 1 && num(j, "passes") >= 1);
    /* Passes run until less than half a sample's time is left of what the budget leaves
     * after the sampler's tables: at least 2/3 of it is used, however fast the machine
     * (one sample of 2/3 B is the worst case). */
    assert_true(num(item(j, "timings"), "budget_used_seconds") > 0.4 * 0.66);
    assert_string_equal(item(j, "mode")->valuestring, "path");
    assert_non_null(strstr(item(j, "label")->valuestring, "global illumination"));
    assert_true(num(item(j, "rays"), "bounce") > 0);
    cJSON_Delete(j);
    /* --no-sidecar; an unwritable sidecar is an error. */
    snprintf(a, sizeof a,
             "render --scene ward-aniso --env sky:32x16 --spp 1 --size 8x8 -o '%s' --no-sidecar",
             tu_path("ns.exr"));
    expect(a, 0, NULL);
    assert_int_equal(tu_count_entries(tu_path("."), "ns.json"), 0);
    snprintf(a, sizeof a,
             "render --scene ward-aniso --env sky:32x16 --spp 1 --size 8x8 -o '%s' --sidecar "
             "/nonexistent/dir/s.json",
             tu_path("ns.exr"));
    expect(a, 2, "/nonexistent/dir/s.json: the directory /nonexistent/dir does not exist");
    /* Instances: one mesh file, three placements (one object each), loaded once. */
    const char obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n";
    tu_write_file(tu_path("quad2.obj"), obj, sizeof obj - 1);
    const char scene[] =
        "{\"camera\": {\"width\": 16, \"height\": 12},\n"
        " \"environment\": {\"map\": \"sky:32x16\"},\n"
        " \"objects\": [{\"type\": \"mesh\", \"file\": \"quad2.obj\", \"instances\": [\n"
        "   {\"translate\": [-1,0,0]}, {\"translate\": [1,0,0], \"rotate_deg\": [0,45,0]},\n"
        "   {\"scale\": [1,2,1]}],\n"
        "   \"material\": {\"type\": \"lambert\"}},\n"
        "  {\"type\": \"mesh\", \"file\": \"quad2.obj\", \"material\": {\"type\": "
        "\"plastic\"}}]}\n";
    tu_write_file(tu_path("inst.json"), scene, sizeof scene - 1);
    snprintf(a, sizeof a, "render '%s' --spp 1 -o '%s'", tu_path("inst.json"), tu_path("i.exr"));
    expect(a, 0, "rendered 16x12");
    j = read_json("i.json");
    assert_true(num(j, "objects") == 4);
    cJSON_Delete(j);
    static const bad_file bad[] = {
        {"{\"objects\": [{\"type\": \"mesh\", \"file\": \"quad2.obj\", \"transform\": {}, "
         "\"instances\": [{}], \"material\": {\"type\": \"lambert\"}}]}",
         "objects[0]: expected either \"transform\" or \"instances\""},
        {"{\"objects\": [{\"type\": \"mesh\", \"file\": \"quad2.obj\", \"instances\": [], "
         "\"material\": {\"type\": \"lambert\"}}]}",
         "objects[0].instances: expected a non-empty array"},
        {"{\"objects\": [{\"type\": \"mesh\", \"file\": \"quad2.obj\", \"instances\": [{}, "
         "{\"scale\": 0}], \"material\": {\"type\": \"lambert\"}}]}",
         "objects[0].instances[1].scale: expected a non-zero finite scale"},
        {"{\"objects\": [{\"type\": \"mesh\", \"file\": \"quad2.obj\", \"instances\": [7], "
         "\"material\": {\"type\": \"lambert\"}}]}",
         "objects[0].instances[0]: expected an object"},
    };
    snprintf(a, sizeof a, "-o '%s'", tu_path("x.exr"));
    expect_bad_files("render", "bad2.json", a, bad, sizeof bad / sizeof bad[0]);
}

static double num_or_nan(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* lumis compare: every documented key, identical images, a PNG input, the error map and
 * the difference image, and mismatched sizes. */
static int exists(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f) fclose(f);
    return f != NULL;
}

/* No output ever replaces an input, and every output is checked before the work: a bad
 * extension or a missing directory is a usage error (exit 2) within milliseconds, and
 * nothing is written.  `render scene.json -o scene.exr` used to write its sidecar over
 * scene.json. */
static void outputs_never_replace_inputs_and_are_checked_first(void **state)
{
    (void)state;
    static const char scene[] =
        "{\"camera\": {\"width\": 8, \"height\": 6},\n"
        " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0.5, 0], \"radius\": 1,\n"
        "   \"material\": {\"type\": \"lambert\", \"albedo\": [0.5, 0.5, 0.5]}}]}\n";
    tu_write_file(tu_path("io-scene.json"), scene, sizeof scene - 1);
    char a[2048];
    /* The default sidecar of io-scene.exr is io-scene.json: the scene file. */
    snprintf(a, sizeof a, "render '%s' --spp 1 -o '%s'", tu_path("io-scene.json"),
             tu_path("io-scene.exr"));
    expect(a, 2, "would replace the scene file");
    size_t n = 0;
    unsigned char *text = tu_read_file(tu_path("io-scene.json"), &n);
    assert_true(n == sizeof scene - 1 && memcmp(text, scene, n) == 0);
    free(text);
    assert_false(exists(tu_path("io-scene.exr"))); /* refused before rendering */
    /* Through a symbolic link, and as an explicit --sidecar. */
    snprintf(a, sizeof a, "ln -sf '%s' '%s'", tu_path("io-scene.json"), tu_path("io-link.json"));
    assert_int_equal(system(a), 0);
    expectf(2, "io-link.json would replace the scene file",
            "render '%s' --spp 1 -o '%s' --sidecar '%s'", tu_path("io-scene.json"),
            tu_path("io-r.exr"), tu_path("io-link.json"));
    /* The map, and the outputs among themselves. */
    expectf(0, NULL, "sky --size 16x8 -o '%s'", tu_path("io-sky.exr"));
    expectf(2, "would replace the environment map",
            "render --scene spheres --env '%s' --spp 1 -o '%s'", tu_path("io-sky.exr"),
            tu_path("io-sky.exr"));
    expectf(2, "are the same file",
            "render --scene spheres --env sky:16x8 --spp 1 -o '%s' --sidecar '%s'",
            tu_path("io-r.exr"), tu_path("io-r.exr"));
    expectf(2, "would replace the input", "convert '%s' '%s'", tu_path("io-sky.exr"),
            tu_path("io-sky.exr"));
    expectf(2, "would replace the reference", "compare '%s' '%s' --diff '%s'",
            tu_path("io-sky.exr"), tu_path("io-sky.exr"), tu_path("io-sky.exr"));
    /* Formats and folders, before the work. */
    expectf(2, "unknown extension (use .exr, .hdr or .pfm)",
            "render --scene spheres --env sky:16x8 --spp 1 -o '%s'", tu_path("io-r.jpg"));
    expect("render --scene spheres --env sky:16x8 --spp 1 -o /nonexistent/r.exr", 2,
           "the directory /nonexistent does not exist");
    snprintf(a, sizeof a,
             "render --scene spheres --env sky:16x8 --spp 1 -o '%s' --png /nonexistent/x.png",
             tu_path("io-r.exr"));
    expect(a, 2, "--png /nonexistent/x.png");
    assert_false(exists(tu_path("io-r.exr")));
    snprintf(a, sizeof a, "compare '%s' '%s' --map '%s'", tu_path("io-sky.exr"),
             tu_path("io-sky.exr"), tu_path("out.jpg"));
    expect(a, 2, "unknown extension (use .png)");
    expect("sky -o /nonexistent/sky.png", 2, "/nonexistent does not exist");
    expect("studio -o studio.txt", 2, "unknown extension");
    /* A sidecar replaces only a sidecar: `lights --json mylights.json` then `render -o
     * mylights.exr` once replaced the light list, exit 0, no message. */
    expectf(0, NULL, "lights sky:32x16 --method median-cut -k 2 --json '%s'",
            tu_path("io-mine.json"));
    size_t n0 = 0, n1 = 0;
    unsigned char *before = tu_read_file(tu_path("io-mine.json"), &n0);
    snprintf(a, sizeof a, "render --scene spheres --env sky:16x8 --size 8x6 --spp 1 -o '%s'",
             tu_path("io-mine.exr"));
    expect(a, 2, "the sidecar");
    expect(a, 2, "io-mine.json would replace a file that is not a lumis sidecar");
    expect(a, 2, "--sidecar PATH");
    unsigned char *after = tu_read_file(tu_path("io-mine.json"), &n1);
    assert_true(n0 == n1 && memcmp(before, after, n0) == 0);
    free(before);
    free(after);
    assert_false(exists(tu_path("io-mine.exr")));
    /* ... and a render's own sidecar is replaced by the next render; the summary names
     * every file written */
    snprintf(a, sizeof a, "render --scene spheres --env sky:16x8 --size 8x6 --spp 1 -o '%s'",
             tu_path("io-own.exr"));
    expect(a, 0, NULL);
    char want[1024];
    snprintf(want, sizeof want, "wrote %s, sidecar %s", tu_path("io-own.exr"),
             tu_path("io-own.json"));
    expect(a, 0, want);
}

/* --lights renders with a light set: the sidecar names it, its K and its sets; options that
 * do not apply to a light set are refused. */
/* lumis's SIMD variants give the same light sets (test_lights) and so the same image, byte
 * for byte: Wu's (with upsampling) and variance minimisation's renders under every variant
 * LUMIS_SIMD can force; an unknown variant is a usage error; the sidecar names the one used. */
static void simd_variants_render_the_same_image(void **state)
{
    (void)state;
    static const char *const variants[] = {"baseline", "avx2", "avx512"};
    static const char *const methods[] = {"wu", "variance-min"};
    char a[1024];
    for (int m = 0; m < 2; m++) {
        unsigned char *first = NULL;
        size_t first_n = 0;
        for (int v = 0; v < 3; v++) {
            char cmd[2048];
            snprintf(a, sizeof a,
                     "render --scene bunny-plane --env sky:256x128 --lights %s --lights-k 24 "
                     "--spp 1 --size 32x24 -o '%s'",
                     methods[m], tu_path("simd.exr"));
            snprintf(cmd, sizeof cmd, "LUMIS_SIMD=%s '%s' %s", variants[v], LUMIS_CLI, a);
            char *err = NULL;
            if (tu_run(cmd, NULL, &err) != 0) fail_msg("%s: %s", cmd, err);
            free(err);
            cJSON *j = read_json("simd.json");
            const char *used = item(j, "simd_variant")->valuestring;
            assert_true(strcmp(used, variants[v]) == 0 || v == 2 || strcmp(used, "baseline") == 0);
            cJSON_Delete(j);
            size_t n = 0;
            unsigned char *img = tu_read_file(tu_path("simd.exr"), &n);
            assert_non_null(img);
            if (!first) {
                first = img;
                first_n = n;
                continue;
            }
            if (n != first_n || memcmp(img, first, n) != 0)
                fail_msg("%s: LUMIS_SIMD=%s renders another image than the baseline", methods[m],
                         variants[v]);
            free(img);
        }
        free(first);
    }
    char *err = NULL;
    snprintf(a, sizeof a, "LUMIS_SIMD=avx3 '%s' info sky:8x4", LUMIS_CLI);
    assert_int_equal(tu_run(a, NULL, &err), 2);
    assert_non_null(strstr(err, "LUMIS_SIMD=avx3"));
    free(err);
}

/* --lights-mode stratified: unbiased, so it approaches the map's own image as samples grow
 * (the point lights' image does not), with --mis and --bounces allowed, the sidecar naming
 * the mode, and every option that does not apply refused. */
static void render_with_stratified_light_sets(void **state)
{
    (void)state;
    char a[1024];
    snprintf(a, sizeof a,
             "render --scene bunny-plane --env sky:64x32 --method inversion --spp 256 --size "
             "32x24 --seed 9 -o '%s'",
             tu_path("st-ref.exr"));
    expect(a, 0, NULL);
    double relmse[3];
    static const char *const modes[3] = {"point --lights-k 8", "stratified --lights-k 8 --spp 2",
                                         "stratified --lights-k 8 --spp 64 --mis power"};
    for (int m = 0; m < 3; m++) {
        snprintf(a, sizeof a,
                 "render --scene bunny-plane --env sky:64x32 --lights median-cut --lights-mode %s "
                 "%s --size 32x24 -o '%s'",
                 modes[m], m == 0 ? "--spp 64" : "", tu_path("st.exr"));
        expect(a, 0, m ? "as strata" : "light set");
        relmse[m] = relmse_between("st-ref.exr", "st.exr");
        cJSON *j = read_json("st.json");
        assert_string_equal(item(item(j, "lights"), "mode")->valuestring,
                            m ? "stratified" : "point");
        cJSON_Delete(j);
    }
    /* 8 point lights stay biased at 64 spp; 8 strata converge (2 spp noisy, 64 spp close) */
    if (!(relmse[2] < relmse[1] && relmse[2] < 0.5 * relmse[0]))
        fail_msg("relMSE: point %g, stratified at 2 spp %g, at 64 spp %g", relmse[0], relmse[1],
                 relmse[2]);
    /* path tracing with strata at every vertex, and --time with passes */
    snprintf(a, sizeof a,
             "render --scene bunny-plane --env sky:64x32 --lights wu --lights-mode stratified "
             "--bounces 1 --time 0.2 --size 16x12 -o '%s'",
             tu_path("st.exr"));
    expect(a, 0, "path traced");
    cJSON *j = read_json("st.json");
    assert_true(num(j, "spp") >= 1 && num(item(j, "lights"), "count") == 32);
    assert_true(num(item(j, "lights"), "upsample") == 1); /* strata: no filter by default */
    cJSON_Delete(j);
    expect("render --scene spheres --lights-mode stratified -o x.exr", 2,
           "lighting.light_set.mode: does not apply: the scene is lit by the environment map "
           "[--lights-mode]");
    expect("render --scene spheres --lights median-cut --lights-mode planar -o x.exr", 2,
           "must be point or stratified");
    /* draws chosen per shading point: stratified only, 1 .. 4096, said in the sidecar */
    expect("render --scene spheres --lights median-cut --lights-draws 4 -o x.exr", 2,
           "lighting.light_set.draws: does not apply: the scene is lit by a light set in point "
           "mode");
    expect("render --scene spheres --lights median-cut --lights-mode stratified --lights-draws 0 "
           "-o x.exr",
           2, "--lights-draws needs a count in [1, 4096], not '0'");
    snprintf(a, sizeof a,
             "render --scene spheres --env sky:32x16 --lights median-cut --lights-mode stratified "
             "--lights-k 8 --lights-draws 3 --spp 2 --size 16x12 -o '%s'",
             tu_path("sel.exr"));
    expect(a, 0, "as strata chosen per vertex");
    j = read_json("sel.json");
    assert_true(num(item(j, "lights"), "draws") == 3);
    cJSON_Delete(j);
    expect("render --scene spheres --lights median-cut --lights-mode stratified --time 1 --spp 4 "
           "-o x.exr",
           2, "not both");
    expect("render --scene spheres --lights median-cut --lights-mode stratified --method bsdf "
           "-o x.exr",
           2, "lighting.estimator: does not apply: the scene is lit by a light set in stratified");
    expect("render --scene spheres --lights median-cut --lights-mode stratified --light-samples 2 "
           "-o x.exr",
           2, "light_samples: does not apply: the scene is lit by a light set in stratified mode");
    /* a bench suite takes the mode, and refuses point lights as a reference */
    static const bad_file suites[] = {
        {"{\"name\": \"m\", \"maps\": [\"sky:16x8\"], \"scenes\": [\"spheres\"],\n"
         " \"methods\": [{\"method\": \"median-cut\", \"mode\": \"stratified\", \"k\": 4}],\n"
         " \"budgets\": [{\"spp\": 1}],\n"
         " \"reference\": {\"spp\": 8, \"method\": \"median-cut\", \"k\": 4}}\n",
         "a light set is a reference only in"},
        {"{\"name\": \"m\", \"maps\": [\"sky:16x8\"], \"scenes\": [\"spheres\"],\n"
         " \"methods\": [{\"method\": \"inversion\", \"mode\": \"stratified\"}],\n"
         " \"budgets\": [{\"spp\": 1}]}\n",
         "mode belong to light sets"},
        {"{\"name\": \"m\", \"maps\": [\"sky:16x8\"], \"scenes\": [\"spheres\"],\n"
         " \"methods\": [{\"method\": \"median-cut\", \"draws\": 4}],\n"
         " \"budgets\": [{\"spp\": 1}]}\n",
         "methods[0].draws: chooses regions as strata: needs \"mode\": \"stratified\""},
        {"{\"name\": \"m\", \"maps\": [\"sky:16x8\"], \"scenes\": [\"spheres\"],\n"
         " \"methods\": [{\"method\": \"median-cut\", \"mode\": \"stratified\", \"draws\": "
         "0}],\n"
         " \"budgets\": [{\"spp\": 1}]}\n",
         "draws"},
    };
    snprintf(a, sizeof a, "--out '%s'", tu_path("mode-out"));
    expect_bad_files("bench", "mode-suite.json", a, suites, 4);
}

static void render_with_light_sets(void **state)
{
    (void)state;
    char a[1024];
    static const char *const methods[] = {"median-cut", "variance-min"};
    for (int m = 0; m < 2; m++) {
        snprintf(a, sizeof a,
                 "render --scene bunny-plane --env sky:64x32 --lights %s --lights-k 20 "
                 "--interleave 4 --spp 1 --size 32x24 -o '%s'",
                 methods[m], tu_path("ls.exr"));
        expect(a, 0, "light set");
        cJSON *j = read_json("ls.json");
        const cJSON *l = item(j, "lights");
        assert_string_equal(item(l, "method")->valuestring, methods[m]);
        assert_true(num(l, "requested") == 20 && num(l, "count") == 20 && num(l, "sets") == 4);
        assert_string_equal(item(j, "estimator")->valuestring, "light set");
        cJSON_Delete(j);
    }
    /* Wu's split rendering: EnvIndirects at half resolution, upsampled and added to the
     * EnvDirects, is as close to a reference as the same lights at full resolution (a part
     * missing or counted twice would not be; here EnvIndirects carry the sky dome). */
    snprintf(a, sizeof a,
             "render --scene bunny-plane --env sky:128x64 --method inversion --spp 64 --size "
             "64x48 -o '%s'",
             tu_path("wu-ref.exr"));
    expect(a, 0, NULL);
    double relmse[3] = {0, 0, 0};
    for (int f = 1; f <= 2; f++) {
        char out[64];
        snprintf(out, sizeof out, "wu%d.exr", f);
        snprintf(a, sizeof a,
                 "render --scene bunny-plane --env sky:128x64 --lights wu --upsample %d --spp 2 "
                 "--size 64x48 -o '%s'",
                 f, tu_path(out));
        expect(a, 0, "light set wu");
        relmse[f] = relmse_between("wu-ref.exr", out);
        snprintf(out, sizeof out, "wu%d.json", f);
        cJSON *j = read_json(out);
        assert_true(num(item(j, "lights"), "upsample") == f);
        assert_true(num(item(j, "lights"), "env_directs") > 0 &&
                    num(item(j, "lights"), "env_indirects") > 0);
        cJSON_Delete(j);
    }
    if (!(relmse[1] < 0.1 && relmse[2] < 1.5 * relmse[1]))
        fail_msg("relMSE against the reference: %g at full resolution, %g upsampled", relmse[1],
                 relmse[2]);
    /* --time with a light set: K fills the time, from pilot renders at K = 4 (the floor)
     * and, when the budget affords them, 64 and where the fit lands. */
    snprintf(a, sizeof a,
             "render --scene bunny-plane --env sky:256x128 --lights wu --time 0.3 --size 48x36 "
             "-o '%s'",
             tu_path("wut.exr"));
    expect(a, 0, "light set wu");
    cJSON *jt = read_json("wut.json");
    const cJSON *kt = item(item(jt, "lights"), "k_from_time");
    const int npilots = cJSON_GetArraySize(item(kt, "pilot_k"));
    assert_true(npilots >= 1 && npilots <= 3);
    for (int p = 0; p < npilots; p++)
        assert_true(cJSON_GetArrayItem(item(kt, "pilot_seconds_per_spp"), p)->valuedouble > 0.0);
    assert_true(cJSON_GetArrayItem(item(kt, "pilot_k"), 0)->valueint == 4);
    assert_true(num(kt, "k_floor") == 4);
    /* What a run reached is checked, not what a fast machine would reach: the samples are
     * at most the plan's, and K under the floor is never unsaid. */
    const double spp_plan = num(kt, "spp_planned"), count = num(item(jt, "lights"), "count");
    assert_true(num(jt, "spp") >= 1 && num(jt, "spp") <= spp_plan && spp_plan <= 4);
    const char *limit = cJSON_GetStringValue(item(kt, "k_limit"));
    assert_non_null(limit);
    if (spp_plan < 4) assert_true(strcmp(limit, "none") != 0);
    if (count < 4 && !cJSON_IsTrue(item(kt, "rerendered")))
        assert_true(strcmp(limit, "below_floor") == 0 || strcmp(limit, "over_budget") == 0);
    if (strcmp(limit, "none") != 0) assert_true(cJSON_IsString(item(kt, "k_limit_reason")));
    const double rs = num(item(jt, "timings"), "render_seconds");
    assert_true(rs > 0.0);
    /* The set has the pilots' K unless the render was made again with K scaled. */
    if (!cJSON_IsTrue(item(kt, "rerendered"))) assert_true(count == num(kt, "k_from_pilots"));
    /* Equal wall time: the pilots and the set's generation are spent from the budget, before
     * the first sample, and the time used is that plus every attempt's render. */
    const cJSON *tt = item(jt, "timings");
    const double prep = num(tt, "prep_seconds"), used = num(tt, "budget_used_seconds");
    if (!(prep >= num(kt, "pilot_wall_seconds") + num(item(jt, "lights"), "build_ms") / 1000.0))
        fail_msg("prep %g s leaves out the pilots (%g s) or the generation (%g ms)", prep,
                 num(kt, "pilot_wall_seconds"), num(item(jt, "lights"), "build_ms"));
    if (cJSON_IsTrue(item(kt, "rerendered")) ? !(used > prep + rs)
                                             : !(fabs(used - (prep + rs)) < 1e-9))
        fail_msg("budget used %g s, prep %g s, render %g s", used, prep, rs);
    /* CPU time beside wall time, and the budget's parts inside the session's wall time */
    assert_true(num(tt, "cpu_seconds") > 0.0 && num(tt, "wall_seconds") >= used - 1e-6);
    assert_true(num(tt, "cpu_share") > 0.0 && cJSON_IsBool(item(tt, "contention")));
    assert_true(fabs(num(tt, "prep_share") - prep / 0.3) < 1e-9 &&
                cJSON_IsBool(item(tt, "prep_over_share")));
    cJSON_Delete(jt);
    expect("render --scene spheres --lights wu --time 1 --lights-k 8 --spp 2 -o x.exr", 2,
           "--spp does not apply");
    expect("render --scene spheres --lights median-cut --upsample 2 -o x.exr", 2,
           "upsample: applies to Wu's decomposition (lights wu...), not 'median-cut' "
           "[--upsample]");
    expect("render --scene spheres --lights cut -o x.exr", 2, "--lights must be one of");
    /* Options that do not apply: refused by the library (lumis_session_check, one message
     * per condition naming the field) with the options that set it, not ignored. */
    expect("render --scene spheres --lights median-cut --method kdtree -o x.exr", 2,
           "lighting.sampler: does not apply: the scene is lit by a light set in point mode");
    expect("render --scene headlight --method kdtree -o x.exr", 2,
           "lighting.sampler: does not apply: the scene is lit by luminaires");
    expect("render --scene headlight --mis none -o x.exr", 2,
           "lighting.estimator: does not apply: the scene is lit by luminaires");
    expect("render --scene headlight-close --blocks 8 -o x.exr", 2, "[--method, --blocks]");
    expect("render --scene headlight --light-samples 2 -o x.exr", 2,
           "light_samples: does not apply: the scene is lit by luminaires [--light-samples]");
    expect("render --scene headlight --bounces 2 -o x.exr", 2,
           "max_bounces: does not apply: the scene is lit by luminaires (direct illumination "
           "only) [--bounces]");
    expect("render --scene spheres --lights-k 8 -o x.exr", 2,
           "lights_k: does not apply without lights (a light-set method) [--lights-k]");
    expect("render --scene spheres --lights median-cut --mis power -o x.exr", 2,
           "power_heuristic: does not apply: the scene is lit by a light set in point mode");
    expect("render --scene spheres --lights median-cut --bounces 2 -o x.exr", 2,
           "(direct illumination only) [--bounces]");
}

/* Rotates v by the unit quaternion q = (x, y, z, w). */
/* Scenes with luminaires: the sidecar names the strategy and its settings; map and light-set
 * options are refused for them, and luminaire options for scenes without. */
static void render_with_luminaires(void **state)
{
    (void)state;
    char a[1024];
    snprintf(a, sizeof a,
             "render --scene headlight --lum-strategy uniform --lum-budget 8 --lum-kmax 4 "
             "--visibility approx --sequence halton --spp 1 --size 32x20 -o '%s'",
             tu_path("hl.exr"));
    expect(a, 0, "1 luminaire: uniform, K = 8, approx visibility, halton");
    cJSON *j = read_json("hl.json");
    const cJSON *l = item(j, "luminaires");
    assert_string_equal(item(l, "strategy")->valuestring, "uniform");
    assert_true(num(l, "count") == 1 && num(l, "budget") == 8 && num(l, "k_max") == 4);
    assert_string_equal(item(l, "visibility")->valuestring, "approx");
    assert_string_equal(item(j, "sequence")->valuestring, "halton");
    assert_string_equal(item(j, "estimator")->valuestring, "luminaire");
    assert_true(cJSON_IsNull(item(j, "environment")));
    assert_true(num(l, "bytes") > 99 * 256 * 256 * 12.0); /* the car preset's images */
    cJSON_Delete(j);
    expect("render --scene headlight --env sky -o x.exr", 2,
           "lighting.env: does not apply: the scene is lit by luminaires");
    expect("render --scene headlight --lights wu -o x.exr", 2,
           "lights: does not apply: the scene is lit by luminaires");
    expect("render --scene spheres --visibility approx -o x.exr", 2,
           "lighting.luminaires: does not apply: the scene is lit by the environment map");
    expect("render --scene headlight --lum-strategy best -o x.exr", 2, "--lum-strategy");
    expect("render --scene headlight --lum-budget 0 -o x.exr", 2, "--lum-budget");
    expect("render --scene headlight --visibility maybe -o x.exr", 2, "--visibility");
    expect("render --scene headlight --sequence owen -o x.exr", 2, "--sequence");
    /* an option given twice: refused (the first was silently ignored) */
    expect("render --scene spheres -o a.exr -o b.exr", 2, "-o given twice");
    expect("sample sky:16x8 --method inversion -n 2 --seed=1 --seed 2", 2, "--seed given twice");
    /* an option's value is never the next option ("--json --masks" wrote a file "--masks"),
     * and an output option without a value is an error, not ignored */
    expect("lights sky:16x8 --method median-cut -k 2 --json --masks", 2, "--json needs a file");
    expect("lights sky:16x8 --method median-cut -k 2 --gltf", 2, "--gltf needs a file");
    expect("render --scene spheres --size 8x6 --spp 1 -o x.exr --sidecar --quiet", 2,
           "--sidecar needs a path");
    /* two outputs to /dev/null are not one file written twice (--gltf through a link named
     * .glb: a name without .gltf or .glb is refused) */
    unlink(tu_path("null.glb"));
    assert_int_equal(symlink("/dev/null", tu_path("null.glb")), 0);
    char nul[1024];
    snprintf(nul, sizeof nul,
             "lights sky:16x8 --method median-cut -k 2 --json /dev/null --gltf '%s'",
             tu_path("null.glb"));
    expect(nul, 0, "");
    expect("lights sky:16x8 --method median-cut -k 2 --json /dev/null --gltf /dev/null", 2,
           "--gltf /dev/null: unknown extension");
}

/* lumis luminaire: create writes a manifest and its images, info reads them back, render
 * lights the headlight scene with it; scene files place luminaires, and every bad field or
 * file gets a message that names it. */
/* An acquired preset is cached (XDG_CACHE_HOME/lumis), read back checked, and acquired
 * again when the cached copy is damaged: the headlight's car took ~10 s on every run. */
static void acquired_presets_are_cached(void **state)
{
    (void)state;
    char cache[512], a[2048];
    snprintf(cache, sizeof cache, "%s", tu_path("xdg"));
    for (int k = 0; k < 3; k++) {
        if (k == 2) { /* damage every cached image: the digest refuses them */
            char cmd[1024];
            snprintf(cmd, sizeof cmd,
                     "for f in '%s'/lumis/small-*.images/*.pfm; do printf 'PF\\n24 20\\n-1.0\\n' "
                     "> \"$f.h\"; head -c 5760 /dev/zero >> \"$f.h\"; mv \"$f.h\" \"$f\"; done",
                     cache);
            assert_int_equal(tu_run(cmd, NULL, NULL), 0);
        }
        snprintf(a, sizeof a, "XDG_CACHE_HOME='%s' '%s' luminaire info preset:small", cache,
                 LUMIS_CLI);
        char *err = NULL;
        assert_int_equal(tu_run(a, NULL, &err), 0);
        const int acquired = strstr(err, "acquiring preset:small") != NULL;
        if (acquired != (k != 1)) fail_msg("run %d: %s", k, err);
        if (k == 2) assert_non_null(strstr(err, "does not read back"));
        free(err);
    }
    /* A scene file that names the preset reads it from the same cache: no acquisition
     * (before, a preset named in a scene file was acquired on every run). */
    static const char scene[] =
        "{\"camera\": {\"eye\": [0, 1, 4], \"look_at\": [0, 0, 0], \"width\": 8, \"height\": 6},"
        " \"objects\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0],"
        " \"material\": {\"type\": \"lambert\", \"albedo\": [0.5, 0.5, 0.5]}}],"
        " \"luminaires\": [{\"file\": \"preset:small\", \"transform\": {\"translate\": [0, 1, 0],"
        " \"rotate_deg\": [90, 0, 0]}}]}";
    char cache2[512], scene_path[512], out[512];
    snprintf(cache2, sizeof cache2, "%s", tu_path("xdg2"));
    snprintf(scene_path, sizeof scene_path, "%s", tu_path("preset-scene.json"));
    snprintf(out, sizeof out, "%s", tu_path("preset-out.exr"));
    tu_write_file(scene_path, scene, sizeof scene - 1);
    for (int k = 0; k < 2; k++) { /* a fresh cache: the first run acquires, the second not */
        snprintf(a, sizeof a, "XDG_CACHE_HOME='%s' '%s' render '%s' --spp 1 -o '%s'", cache2,
                 LUMIS_CLI, scene_path, out);
        char *err = NULL;
        const int rc = tu_run(a, NULL, &err);
        const int acquired = strstr(err, "acquiring preset:small") != NULL;
        if (rc != 0 || acquired != (k == 0)) fail_msg("scene run %d (exit %d): %s", k, rc, err);
        free(err);
    }
}

static void luminaire_files_create_info_render(void **state)
{
    (void)state;
    char a[2048], man[512]; /* tu_path's buffer is reused by the next call: a copy */
    snprintf(man, sizeof man, "%s", tu_path("small-lum.json"));
    expectf(0, "acquired 20 images of 24 x 20", "luminaire create '%s' --preset small --format pfm",
            man);
    snprintf(a, sizeof a, "luminaire info '%s' --json", man);
    char *out = NULL, *err = NULL;
    assert_int_equal(run(a, &out, &err), 0);
    cJSON *j = cJSON_Parse(out);
    assert_non_null(j);
    assert_true(num(j, "images") == 20 && num(j, "width") == 24 && num(j, "height") == 20);
    assert_true(num(j, "precompute_ms") > 0.0 && num(j, "bytes") > 20 * 24 * 20 * 12.0);
    assert_true(num(j, "total_power") > 0.0);
    assert_string_equal(item(j, "units")->valuestring, "mm");
    cJSON_Delete(j);
    free(out);
    free(err);
    expectf(0, "1 luminaire: restricted, K = 4",
            "luminaire render '%s' --spp 1 --size 16x10 --lum-budget 4 -o '%s'", man,
            tu_path("lr.exr"));
    /* A scene file placing it twice (read once), in metres. */
    char scene[2048];
    snprintf(scene, sizeof scene,
             "{\"camera\": {\"eye\": [1, 1, 1], \"look_at\": [0, 0, -2], \"width\": 16, "
             "\"height\": 10},\n \"objects\": [{\"type\": \"plane\", \"point\": [0, 0, 0], "
             "\"normal\": [0, 1, 0], \"material\": {\"type\": \"lambert\", \"albedo\": [0.5, "
             "0.5, 0.5]}}],\n \"luminaires\": [{\"file\": \"small-lum.json\", \"transform\": "
             "{\"translate\": [0, 0.5, 0], \"rotate_deg\": [-170, 0, 180], \"scale\": 0.001}, "
             "\"intensity\": 1000}, {\"file\": \"small-lum.json\", \"transform\": "
             "{\"translate\": [0.3, 0.5, 0], \"rotate_deg\": [-170, 0, 180], \"scale\": 0.001}}]}");
    tu_write_file(tu_path("lum-scene.json"), scene, strlen(scene));
    snprintf(a, sizeof a, "render '%s' --spp 1 -o '%s'", tu_path("lum-scene.json"),
             tu_path("ls2.exr"));
    expect(a, 0, "2 luminaires");
    cJSON *side = read_json("ls2.json");
    assert_true(num(item(side, "luminaires"), "count") == 2);
    cJSON_Delete(side);
    /* Every luminaire black: an error, not the default sky; a map beside luminaires: a
     * warning that it is ignored. */
    static const char black[] =
        "{\"objects\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], "
        "\"material\": {\"type\": \"lambert\"}}], "
        "\"luminaires\": [{\"file\": \"small-lum.json\", \"intensity\": 0}]}";
    tu_write_file(tu_path("black-scene.json"), black, sizeof black - 1);
    expectf(1, "every luminaire of the scene has intensity 0",
            "render '%s' --spp 1 --size 8x6 -o '%s'", tu_path("black-scene.json"),
            tu_path("black.exr"));
    char with_map[2200];
    snprintf(with_map, sizeof with_map, "{\"environment\": {\"map\": \"sky:16x8\"}, %s", scene + 1);
    tu_write_file(tu_path("lum-map-scene.json"), with_map, strlen(with_map));
    expectf(0, "the scene's environment (sky:16x8) is ignored",
            "render '%s' --spp 1 --size 8x6 -o '%s'", tu_path("lum-map-scene.json"),
            tu_path("lm.exr"));
    /* Its manifest is an input: no output may replace it. */
    snprintf(a, sizeof a, "render '%s' --spp 1 -o '%s' --sidecar '%s'", tu_path("lum-scene.json"),
             tu_path("ls3.exr"), man);
    expect(a, 2, "would replace the luminaire");
    /* So is every image it names: an output over one would destroy the luminaire, from a
     * scene file or from --luminaire (an image's name as the manifest writes it). */
    char img[512];
    snprintf(img, sizeof img, "%s", tu_path("small-lum.images/a002_b001.pfm"));
    expectf(2, "would replace the luminaire image", "render '%s' --spp 1 -o '%s'",
            tu_path("lum-scene.json"), img);
    expectf(2, "would replace the luminaire image",
            "render --scene headlight --luminaire '%s' --spp 1 -o '%s'", tu_path("small-lum.json"),
            img);
    /* Bad fields and files. */
    static const bad_file bad[] = {
        {"{\"objects\": [], \"luminaires\": 3}", "luminaires"},
        {"{\"objects\": [], \"luminaires\": [{\"file\": 5}]}", "luminaires[0].file"},
        {"{\"objects\": [], \"luminaires\": [{\"file\": \"preset:car\", \"transform\": "
         "{\"scale\": [1, 1, 1]}}]}",
         "luminaires[0].transform.scale"},
        {"{\"objects\": [], \"luminaires\": [{\"file\": \"preset:car\", \"intensity\": -1}]}",
         "luminaires[0].intensity"},
        {"{\"objects\": [], \"luminaires\": [{\"file\": \"preset:lamp\"}]}", "preset:small"},
        {"{\"objects\": [], \"luminaires\": [{\"file\": \"nowhere.json\"}]}", "nowhere.json"},
    };
    snprintf(a, sizeof a, "-o '%s'", tu_path("bad.exr"));
    expect_bad_files("render", "bad-lum-scene.json", a, bad, sizeof bad / sizeof bad[0]);
    expect("luminaire create out.txt", 2, ".json");
    expect("luminaire create x.json --preset lamp", 2, "--preset");
    expect("luminaire info /nonexistent/lamp.json", 1, "lamp.json");
    expect("luminaire frobnicate", 2, "create, info, predict or render");
    /* predict: per band, each strategy's numbers; the best is the least work */
    out = NULL;
    assert_int_equal(run("luminaire predict preset:small --distance 2,40 --bands 2 --probes 64 "
                         "--json",
                         &out, NULL),
                     0);
    cJSON *pj = cJSON_Parse(out);
    free(out);
    assert_non_null(pj);
    const cJSON *bands = item(pj, "bands");
    assert_int_equal(cJSON_GetArraySize(bands), 2);
    const cJSON *b0 = cJSON_GetArrayItem(bands, 0);
    assert_true(num(b0, "probes_lit") > 32);
    assert_true(num(b0, "energy_share") > 0.0 && num(b0, "energy_share") < 1.0);
    const char *names[3] = {"restricted", "uniform", "global"};
    double least = 1e300;
    const char *best = NULL;
    for (int k = 0; k < 3; k++) {
        const cJSON *sj = item(b0, names[k]);
        const double work = num(sj, "variance") * num(sj, "ns");
        assert_true(work > 0.0);
        if (work < least) least = work, best = names[k];
        /* global's ratio to itself is 1 */
        if (k == 2) assert_true(fabs(num(sj, "time_ratio") - 1.0) < 1e-12);
    }
    assert_string_equal(cJSON_GetStringValue(item(b0, "best")), best);
    cJSON_Delete(pj);
    assert_int_equal(run("luminaire predict preset:small --distance 5", &out, NULL), 0);
    assert_non_null(strstr(out, "restricted: samples"));
    free(out);
    expect("luminaire predict preset:small --distance 4,2", 2, "--distance");
    expect("luminaire predict preset:small --probes 16 --costs 300,25,23,50,30,10.5,7", 0, NULL);
    expect("luminaire predict preset:small --costs 300,25,23,0,30,10.5,7", 2, "--costs");
    expect("luminaire predict preset:small --costs 1,2,3", 2, "--costs");
    expect("luminaire predict preset:small --bands 0", 2, "--bands");
    expect("luminaire predict", 2, "no luminaire");
    /* auto: the render says what it chose and why, and it is one of the three */
    snprintf(a, sizeof a,
             "render --scene headlight --luminaire preset:small --lum-strategy auto --spp 1 "
             "--size 32x20 --pixel-centers -o '%s'",
             tu_path("auto.exr"));
    expect(a, 0, "auto: ");
    cJSON *aj = read_json("auto.json");
    const cJSON *lj = item(aj, "luminaires");
    assert_string_equal(cJSON_GetStringValue(item(lj, "strategy")), "auto");
    const char *chosen = cJSON_GetStringValue(item(lj, "chosen"));
    assert_true(!strcmp(chosen, "restricted") || !strcmp(chosen, "uniform") ||
                !strcmp(chosen, "global"));
    assert_true(num(item(lj, "prediction"), "probes_lit") > 0);
    assert_true(cJSON_IsTrue(item(aj, "pixel_centers")));
    /* the render is the chosen strategy's at the chosen budget, bit for bit */
    char fixed[2048];
    snprintf(fixed, sizeof fixed,
             "render --scene headlight --luminaire preset:small --lum-strategy %s --lum-budget %s "
             "--spp 1 --size 32x20 --pixel-centers -o '%s'",
             chosen, cJSON_GetStringValue(item(lj, "chosen_budgets")), tu_path("fixed.exr"));
    expect(fixed, 0, NULL);
    cJSON_Delete(aj);
    lumis_image *ai = NULL, *fi = NULL;
    assert_int_equal(lumis_image_read(tu_path("auto.exr"), NULL, &ai, NULL), LUMIS_OK);
    assert_int_equal(lumis_image_read(tu_path("fixed.exr"), NULL, &fi, NULL), LUMIS_OK);
    assert_memory_equal(ai->pixels, fi->pixels, sizeof(float) * 3 * 32 * 20);
    lumis_image_destroy(ai);
    lumis_image_destroy(fi);
    /* its cost model given: recorded with the prediction */
    snprintf(a, sizeof a,
             "render --scene headlight --luminaire preset:small --lum-strategy auto --spp 1 "
             "--size 32x20 --lum-costs 300,25,23,50,30,10.5,7 -o '%s'",
             tu_path("auto.exr"));
    expect(a, 0, "auto: ");
    aj = read_json("auto.json");
    const cJSON *costs = item(item(item(aj, "luminaires"), "prediction"), "costs");
    assert_int_equal(cJSON_GetArraySize(costs), 7);
    assert_true(cJSON_GetArrayItem(costs, 6)->valuedouble == 7.0);
    cJSON_Delete(aj);
    expect("render --scene headlight --lum-strategy auto --lum-costs 1,2 -o x.exr", 2,
           "--lum-costs");
    expect("render --scene spheres --luminaire preset:small -o x.exr", 1, "places no luminaire");
}

static void quat_rotate(const double q[4], const double v[3], double out[3])
{
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]),
                 tz = 2 * (x * v[1] - y * v[0]);
    out[0] = v[0] + w * tx + (y * tz - z * ty);
    out[1] = v[1] + w * ty + (z * tx - x * tz);
    out[2] = v[2] + w * tz + (x * ty - y * tx);
}

/* lumis lights: the JSON and the glTF hold every light; in the glTF each node turns -Z into
 * the light's direction of travel (-dir) and colour x intensity is its power; the regions of
 * --masks cover every pixel once; the powers add up to the map's. */
static void lights_export_parses_back(void **state)
{
    (void)state;
    char a[2048];
    static const char *const methods[] = {"wu", "median-cut", "variance-min", "fhis", "tmms"};
    for (int m = 0; m < 5; m++) {
        snprintf(a, sizeof a,
                 "lights sky:64x32 --method %s -k 12 --json '%s' --masks --gltf '%s' "
                 "--png '%s'",
                 methods[m], tu_path("l.json"), tu_path("l.gltf"), tu_path("l.png"));
        expect(a, 0, NULL);
        cJSON *j = read_json("l.json"), *g = read_json("l.gltf");
        const cJSON *lights = item(j, "lights");
        assert_int_equal(cJSON_GetArraySize(lights), 12);
        const cJSON *gl = item(item(item(g, "extensions"), "KHR_lights_punctual"), "lights");
        const cJSON *nodes = item(g, "nodes");
        assert_int_equal(cJSON_GetArraySize(gl), 12);
        assert_int_equal(cJSON_GetArraySize(nodes), 12);
        assert_string_equal(item(item(g, "asset"), "version")->valuestring, "2.0");
        static char covered[64 * 32];
        memset(covered, 0, sizeof covered);
        for (int k = 0; k < 12; k++) {
            const cJSON *l = cJSON_GetArrayItem(lights, k), *gk = cJSON_GetArrayItem(gl, k),
                        *node = cJSON_GetArrayItem(nodes, k);
            assert_string_equal(item(gk, "type")->valuestring, "directional");
            assert_true(num(item(item(node, "extensions"), "KHR_lights_punctual"), "light") == k);
            double q[4], dir[3], travel[3];
            for (int c = 0; c < 4; c++)
                q[c] = cJSON_GetArrayItem(item(node, "rotation"), c)->valuedouble;
            for (int c = 0; c < 3; c++) dir[c] = cJSON_GetArrayItem(item(l, "dir"), c)->valuedouble;
            const double minus_z[3] = {0, 0, -1};
            quat_rotate(q, minus_z, travel);
            for (int c = 0; c < 3; c++) assert_true(fabs(travel[c] + dir[c]) < 1e-6);
            for (int c = 0; c < 3; c++) {
                double power = cJSON_GetArrayItem(item(l, "power"), c)->valuedouble;
                double col = cJSON_GetArrayItem(item(gk, "color"), c)->valuedouble;
                assert_true(col >= 0.0 && col <= 1.0);
                assert_true(fabs(col * num(gk, "intensity") - power) <= 1e-9 * (power + 1e-30));
            }
            const cJSON *runs = item(l, "region_runs");
            int pixels = 0;
            for (int r = 0; r < cJSON_GetArraySize(runs); r++) {
                const cJSON *run = cJSON_GetArrayItem(runs, r);
                int row = cJSON_GetArrayItem(run, 0)->valueint,
                    col0 = cJSON_GetArrayItem(run, 1)->valueint,
                    len = cJSON_GetArrayItem(run, 2)->valueint;
                for (int i = col0; i < col0 + len; i++) covered[row * 64 + i]++;
                pixels += len;
            }
            assert_true(pixels == (int)num(l, "pixels"));
        }
        for (int p = 0; p < 64 * 32; p++) assert_int_equal(covered[p], 1);
        cJSON_Delete(j);
        cJSON_Delete(g);
    }
    /* No --method: median cut (docs/lights.md, "Which method for which goal"). */
    char *out = NULL;
    assert_int_equal(run("lights sky:16x8 -k 4", &out, NULL), 0);
    assert_non_null(strstr(out, "4 lights by median-cut"));
    free(out);
    /* --above-ground: the sky's lights below the horizon go into the nearest above; the
     * total power stays, the folded share is printed and the files record it. */
    expectf(0, NULL, "lights sky:64x32 -k 16 --json '%s'", tu_path("ag0.json"));
    snprintf(a, sizeof a, "lights sky:64x32 -k 16 --above-ground --json '%s'", tu_path("ag1.json"));
    assert_int_equal(run(a, &out, NULL), 0);
    assert_non_null(strstr(out, "lights below the horizon folded into the nearest above"));
    assert_non_null(strstr(out, "% of the power"));
    free(out);
    cJSON *j0 = read_json("ag0.json"), *j1 = read_json("ag1.json");
    const cJSON *l0 = item(j0, "lights"), *l1 = item(j1, "lights");
    assert_true(cJSON_GetArraySize(l1) < cJSON_GetArraySize(l0));
    double p0[3] = {0, 0, 0}, p1[3] = {0, 0, 0};
    for (int k = 0; k < cJSON_GetArraySize(l0); k++)
        for (int c = 0; c < 3; c++)
            p0[c] += cJSON_GetArrayItem(item(cJSON_GetArrayItem(l0, k), "power"), c)->valuedouble;
    for (int k = 0; k < cJSON_GetArraySize(l1); k++) {
        const cJSON *l = cJSON_GetArrayItem(l1, k);
        assert_true(cJSON_GetArrayItem(item(l, "dir"), 1)->valuedouble > 0.0);
        for (int c = 0; c < 3; c++) p1[c] += cJSON_GetArrayItem(item(l, "power"), c)->valuedouble;
    }
    for (int c = 0; c < 3; c++) assert_true(fabs(p1[c] - p0[c]) <= 1e-9 * p0[c]);
    assert_string_equal(item(j1, "parameters")->valuestring, "above-ground");
    cJSON_Delete(j0);
    cJSON_Delete(j1);
    expect("lights sky:16x8 --method kmeans", 2, "--method must be one of");
    expect("lights sky:16x8 --method wu -k 0", 2, "-k needs a count");
    expect("lights sky:16x8 --method wu --masks", 2, "--masks goes with --json");
    expect("lights sky:16x8 --method wu --png x.jpg", 2, "unknown extension");
    /* --gltf: .gltf text or .glb binary, nothing else; --frame engine (default) or lumis */
    expect("lights sky:16x8 --method wu --gltf x.json", 2,
           "--gltf x.json: unknown extension (use .gltf for text, .glb for binary)");
    expect("lights sky:16x8 --method wu --frame three --json x.json", 2,
           "--frame must be engine or lumis");
    expect("lights sky:16x8 --method wu --frame lumis", 2, "--frame goes with --json");
    snprintf(a, sizeof a, "lights sky:64x32 --method wu -k 4 --gltf '%s' --json '%s' --frame lumis",
             tu_path("lf.glb"), tu_path("lf.json"));
    char *lf_out = NULL;
    assert_int_equal(run(a, &lf_out, NULL), 0);
    assert_non_null(strstr(lf_out, "the files' in the lumis frame"));
    free(lf_out);
    size_t glb_size = 0;
    unsigned char *glb = tu_read_file(tu_path("lf.glb"), &glb_size);
    assert_true(glb && glb_size > 20 && memcmp(glb, "glTF", 4) == 0);
    free(glb);
    cJSON *lf = read_json("lf.json");
    assert_string_equal(item(lf, "frame")->valuestring, "lumis");
    cJSON_Delete(lf);
    snprintf(a, sizeof a, "lights '%s' --method wu --json '%s'", tu_path("l.gltf"),
             tu_path("l.gltf"));
    expect(a, 2, "would replace the map");
}

/* The light tables of `lumis lights` (stdout after its "built in" line), for comparing runs. */
static char *light_table(const char *args)
{
    char *out = NULL, *err = NULL;
    const int rc = run(args, &out, &err);
    if (rc != 0) fail_msg("lumis %s: exit %d; stderr: %s", args, rc, err);
    free(err);
    char *nl = strchr(out, '\n');
    assert_non_null(nl);
    char *table = strdup(nl + 1);
    free(out);
    return table;
}

/* --param and --lights-param reach the library: Eq. 1's threshold, Eq. 3's weights and
 * TMMS' bandwidth change the lights; the sidecar and the summary record what was given;
 * unknown names, zero or out-of-range values and parameters of another method are refused. */
static void light_params_reach_the_methods(void **state)
{
    (void)state;
    char *def = light_table("lights sky:64x32 --method wu -k 12");
    char *thr = light_table("lights sky:64x32 --method wu -k 12 --param threshold=1e30");
    assert_non_null(strstr(thr, "parameters threshold=1e+30\n"));
    assert_non_null(strstr(thr, "emissive pixels 0 (Y > L_T = 1e+30)"));
    assert_null(strstr(def, "emissive pixels 0 "));
    char a[1024];
    snprintf(a, sizeof a,
             "lights sky:64x32 --method wu -k 12 --param wd=1e-6,wv=2 --json '%s' --gltf '%s'",
             tu_path("lp-lights.json"), tu_path("lp-lights.gltf"));
    char *wd = light_table(a);
    cJSON *lj = read_json("lp-lights.json"), *lg = read_json("lp-lights.gltf");
    assert_string_equal(item(lj, "parameters")->valuestring, "wv=2,wd=1e-06");
    assert_string_equal(
        item(item(cJSON_GetArrayItem(item(lg, "scenes"), 0), "extras"), "parameters")->valuestring,
        "wv=2,wd=1e-06");
    cJSON_Delete(lj);
    cJSON_Delete(lg);
    assert_non_null(strstr(wd, "parameters wv=2,wd=1e-06\n"));
    assert_true(strcmp(strstr(def, "total power"), strstr(wd, "total power")) != 0);
    /* the same power whatever the parameters */
    assert_true(strncmp(strstr(def, "total power"), strstr(wd, "total power"), 40) == 0);
    /* the seed of Wu's importance sampling, the mask's reading, lambda of Eq. 1 */
    char *s5 = light_table("lights sky:64x32 --method wu-is -k 12 --param threshold=1,seed=5");
    char *s6 = light_table("lights sky:64x32 --method wu-is -k 12 --param threshold=1,seed=6");
    assert_true(strcmp(strstr(s5, "total power"), strstr(s6, "total power")) != 0);
    char *mc =
        light_table("lights sky:64x32 --method wu-is-mask -k 12 --param threshold=1,mask=cap");
    char *mr =
        light_table("lights sky:64x32 --method wu-is-mask -k 12 --param threshold=1,mask=radians");
    assert_true(strcmp(strstr(mc, "total power"), strstr(mr, "total power")) != 0);
    char *lam = light_table("lights sky:64x32 --method wu -k 12 --param lambda=50");
    assert_true(strcmp(strstr(def, "emissive pixels"), strstr(lam, "emissive pixels")) != 0);
    free(s5);
    free(s6);
    free(mc);
    free(mr);
    free(lam);
    char *t1 = light_table("lights sky:64x32 --method tmms -k 12 --param bandwidth=0.02");
    char *t2 = light_table("lights sky:64x32 --method tmms -k 12 --param bandwidth=1,key=0.5");
    assert_true(strcmp(strstr(t1, "total power"), strstr(t2, "total power")) != 0);
    free(def);
    free(thr);
    free(wd);
    free(t1);
    free(t2);

    snprintf(a, sizeof a,
             "render --scene spheres --env sky:64x32 --lights wu --lights-k 8 "
             "--lights-param lambda=5 --lights-param mask=radians,seed=9 --spp 1 --size 16x12 "
             "-o '%s'",
             tu_path("lp.exr"));
    expect(a, 0, NULL);
    cJSON *j = read_json("lp.json");
    assert_string_equal(item(item(j, "lights"), "params")->valuestring,
                        "lambda=5,mask=radians,seed=9");
    cJSON_Delete(j);
    /* the interleaved sets' jitter moves the lights of the image's other sets */
    size_t n0 = 0, n1 = 0;
    unsigned char *img[2] = {NULL, NULL};
    for (int r = 0; r < 2; r++) {
        snprintf(a, sizeof a,
                 "render --scene spheres --env sky:64x32 --lights median-cut --lights-k 8 "
                 "--lights-param jitter=%s --spp 1 --size 16x12 -o '%s'",
                 r ? "1" : "0.01", tu_path(r ? "lj1.exr" : "lj0.exr"));
        expect(a, 0, NULL);
        img[r] = tu_read_file(tu_path(r ? "lj1.exr" : "lj0.exr"), r ? &n1 : &n0);
    }
    assert_true(n0 != n1 || memcmp(img[0], img[1], n0) != 0);
    free(img[0]);
    free(img[1]);

    expect("lights sky:16x8 --method wu --param foo=1", 2, "unknown parameter 'foo'");
    expect("lights sky:16x8 --method wu --param lambda", 2, "'lambda' is not NAME=VALUE");
    expect("lights sky:16x8 --method wu --param lambda=0", 2, "lambda=VALUE needs");
    expect("lights sky:16x8 --method wu --param percentile=101", 2, "percentile=VALUE needs");
    expect("lights sky:16x8 --method wu --param mask=disc", 2, "mask=VALUE needs");
    expect("lights sky:16x8 --method wu --param seed=-3", 2, "seed=VALUE needs");
    expect("lights sky:16x8 --method wu --param kmeans-iterations=0", 2, "needs a count");
    expect("lights sky:16x8 --method tmms --param bandwidth=2", 2, "bandwidth=VALUE needs");
    expect("lights sky:16x8 --method median-cut --param lambda=3", 2,
           "'lambda' is a parameter of Wu's decomposition");
    expect("lights sky:16x8 --method wu --param key=0.3", 2, "'key' is a parameter of tmms");
    expect("render --scene spheres --lights-param wd=1 -o x.exr", 2,
           "lights_params: does not apply without lights (a light-set method) [--lights-param]");
    expect("render --scene spheres --lights fhis --lights-param wd=1 -o x.exr", 2, "not of fhis");
}

/* K = 2 on a map with a bright spot (the one EnvDirect), a dimmer strip 170 degrees away
 * (emissive, but too far from the EnvDirect: its 32 pixels are given back to the
 * EnvIndirect) and a brighter lower half, which keeps the EnvIndirect's cross off the strip. */
static float two_spots(int i, int j, int c)
{
    (void)c;
    if (i >= 20 && i < 26 && j >= 20 && j < 26) return 1000.0f;
    if (i >= 80 && i < 96 && j >= 12 && j < 14) return 100.0f;
    return j >= 32 ? 10.0f : 1.0f;
}

/* Picture pixels of the returned (magenta) and EnvDirect (orange) tints, read back linear. */
static void count_tints(const char *png, int w, int h, int *magenta, int *orange)
{
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_read(tu_path(png), NULL, &img, NULL), LUMIS_OK);
    assert_int_equal(img->width, w);
    assert_int_equal(img->height, h);
    *magenta = *orange = 0;
    for (int p = 0; p < w * h; p++) {
        const float *q = img->pixels + 3 * p;
        *magenta += q[0] > 0.6f && q[1] < 0.1f && q[2] > 0.6f;
        *orange += q[0] > 0.6f && q[1] > 0.15f && q[1] < 0.4f && q[2] < 0.1f;
    }
    lumis_image_destroy(img);
}

/* lumis lights --png: emissive pixels of the EnvDirects in orange, emissive pixels given back
 * to the EnvIndirects in magenta; --png-width draws at another size, and a picture smaller
 * than the map still shows a spot smaller than one of its pixels. */
static void lights_picture_marks_emissive_pixels(void **state)
{
    (void)state;
    char a[2048], *out = NULL;
    lumis_image *map = tu_image(128, 64, two_spots);
    assert_int_equal(lumis_image_write(tu_path("spots.pfm"), map, NULL), LUMIS_OK);
    lumis_image_destroy(map);
    run_ok(&out, "lights '%s' --method wu -k 2 --png '%s'", tu_path("spots.pfm"),
           tu_path("spots.png"));
    assert_non_null(strstr(out, "1 EnvDirects, 1 EnvIndirects"));
    assert_non_null(strstr(out, "emissive pixels 68 "));
    assert_non_null(strstr(out, "32 given back to the EnvIndirects"));
    free(out);
    int magenta = 0, orange = 0;
    count_tints("spots.png", 128, 64, &magenta, &orange);
    assert_int_equal(magenta, 32);
    assert_true(orange > 0);
    snprintf(a, sizeof a, "lights '%s' --method wu -k 2 --png '%s' --png-width 32",
             tu_path("spots.pfm"), tu_path("small.png"));
    expect(a, 0, NULL);
    count_tints("small.png", 32, 16, &magenta, &orange);
    /* 4 x 4 map pixels to a picture pixel: the strip is 4 wide, and half a row high (rows
     * 12-13 of 12-15, which the pixel's centre, row 14, misses) */
    assert_int_equal(magenta, 4);
    snprintf(a, sizeof a, "lights '%s' --method median-cut -k 2 --png '%s' --png-width 256",
             tu_path("spots.pfm"), tu_path("big.png"));
    expect(a, 0, NULL);
    count_tints("big.png", 256, 128, &magenta, &orange);
    assert_int_equal(magenta + orange, 0); /* no emissive classes outside Wu's methods */
    expect("lights sky:16x8 --method wu --png x.png --png-width 8", 2, "--png-width needs pixels");
    expect("lights sky:16x8 --method wu --png-width 64", 2, "--png-width goes with --png");
}

/* NaN, Inf and negative map values are replaced by 0 everywhere, and every command says
 * so: render (and its sidecar), lights, sample and compare (whose JSON counts them). */
static void replaced_values_are_reported(void **state)
{
    (void)state;
    float px[8 * 4 * 3];
    for (int k = 0; k < 8 * 4 * 3; k++) px[k] = 1.0f;
    px[0] = NAN;
    px[4] = INFINITY;
    px[7] = -2.0f;
    char pfm[64 + sizeof px];
    const int hn = snprintf(pfm, 64, "PF\n8 4\n-1.0\n");
    memcpy(pfm + hn, px, sizeof px);
    const char *map = tu_path("nan.pfm");
    tu_write_file(map, pfm, (size_t)hn + sizeof px);
    char m[512], a[2048];
    snprintf(m, sizeof m, "%s", map);
    /* PFM's first row is the bottom one: value 7 is pixel (2, 3) */
    const char *warn = "3 channel values replaced by 0 (NaN 1, Inf 1, negative 1, the worst -2 at "
                       "pixel (2, 3)";
    expectf(0, warn, "render --scene spheres --env '%s' --size 8x6 --spp 1 --quiet -o '%s'", m,
            tu_path("nan-r.exr"));
    cJSON *j = read_json("nan-r.json");
    const cJSON *e = item(j, "environment");
    assert_true(num(e, "replaced") == 3 && num(e, "replaced_nan") == 1 &&
                num(e, "replaced_inf") == 1 && num(e, "replaced_negative") == 1);
    cJSON_Delete(j);
    expectf(0, warn, "lights '%s' --method median-cut -k 2", m);
    expectf(0, warn, "sample '%s' --method alias -n 1", m);
    snprintf(a, sizeof a, "compare '%s' '%s' --json", m, m);
    char *out = NULL, *err = NULL;
    assert_int_equal(run(a, &out, &err), 0);
    assert_non_null(strstr(err, warn));
    cJSON *c = cJSON_Parse(out);
    assert_non_null(c);
    assert_true(num(c, "replaced_test") == 3 && num(c, "nonfinite_test") == 2);
    cJSON_Delete(c);
    free(out);
    free(err);
    /* lumis bench decodes its maps once itself: it says so too, and each item's sidecar
     * records the counts */
    char suite[1024];
    snprintf(suite, sizeof suite,
             "{\"maps\": [\"%s\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
             "\"alias\"}], \"budgets\": [{\"spp\": 1}], \"reference\": {\"spp\": 2}, "
             "\"size\": [8, 6]}",
             m);
    tu_write_file(tu_path("nan-suite.json"), suite, strlen(suite));
    char dir[512];
    snprintf(dir, sizeof dir, "%s", tu_path("nan-bench"));
    expectf(0, warn, "bench '%s' --out '%s'", tu_path("nan-suite.json"), dir);
    snprintf(a, sizeof a, "%s/renders/nan__spheres__alias__spp1.json", dir);
    size_t n = 0;
    char *side = (char *)tu_read_file(a, &n);
    assert_non_null(side);
    c = cJSON_Parse(side);
    assert_true(num(item(c, "environment"), "replaced") == 3);
    cJSON_Delete(c);
    free(side);
}

/* Writes a w x h PFM of px (rows top first) to the test folder as name; its path. */
static const char *write_pfm(const char *name, const float *px, int w, int h)
{
    const size_t bytes = (size_t)w * (size_t)h * 3 * sizeof(float);
    char *pfm = malloc(64 + bytes);
    const int hn = snprintf(pfm, 64, "PF\n%d %d\n-1.0\n", w, h);
    /* PFM stores the bottom row first */
    for (int y = 0; y < h; y++)
        memcpy(pfm + hn + (size_t)(h - 1 - y) * (size_t)w * 3 * sizeof(float),
               px + (size_t)y * (size_t)w * 3, (size_t)w * 3 * sizeof(float));
    const char *path = tu_path(name);
    tu_write_file(path, pfm, (size_t)hn + bytes);
    free(pfm);
    return path;
}

/* What real HDRIs hold: compression noise (a few tiny negatives) is a note that LUMIS_NOTES=0
 * silences; a broken cluster (a pure-blue spike among large negatives) is a warning naming
 * the worst value's pixel and the spike's. */
static void replaced_noise_is_a_note_and_spikes_are_named(void **state)
{
    (void)state;
    enum { MW = 32, MH = 16 };
    static float px[MW * MH * 3];
    for (int k = 0; k < MW * MH * 3; k++) px[k] = 0.8f + 0.1f * (float)(k % 5);
    px[3 * (5 * MW + 7) + 2] = -1e-4f; /* noise */
    px[3 * (9 * MW + 20) + 0] = -3e-4f;
    char a[2048], m[512];
    snprintf(m, sizeof m, "%s", write_pfm("noise.pfm", px, MW, MH));
    snprintf(a, sizeof a, "info '%s'", m);
    expect(a, 0, "lumis: note: ");
    expect(a, 0, "2 small negative values (down to -0.0003");
    char *out = NULL, *err = NULL;
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "LUMIS_NOTES=0 '%s' info '%s'", LUMIS_CLI, m);
    assert_int_equal(tu_run(cmd, &out, &err), 0);
    if (strstr(err, "negative")) fail_msg("LUMIS_NOTES=0 still notes: %s", err);
    free(out);
    free(err);
    /* a blue spike at (12, 6) among ringing negatives */
    const int sx = 12, sy = 6;
    px[3 * (sy * MW + sx) + 0] = 0;
    px[3 * (sy * MW + sx) + 1] = 0;
    px[3 * (sy * MW + sx) + 2] = 15000;
    px[3 * (sy * MW + sx - 1) + 0] = -2300;
    px[3 * ((sy + 1) * MW + sx) + 1] = -40;
    snprintf(m, sizeof m, "%s", write_pfm("spike.pfm", px, MW, MH));
    snprintf(a, sizeof a, "info '%s'", m);
    expect(a, 0, "the worst -2300 at pixel (11, 6)");
    expect(a, 0, "pixel (12, 6) = (0, 0, 1.5e+04) is a saturated spike");
    /* compared as renders, the same file's spike is no map's: not named (a dark reference's
     * firefly is its estimator's), while what was replaced still is */
    snprintf(cmd, sizeof cmd, "'%s' compare '%s' '%s'", LUMIS_CLI, m, m);
    assert_int_equal(tu_run(cmd, &out, &err), 0);
    if (strstr(err, "saturated spike")) fail_msg("compare names a render's spike: %s", err);
    if (!strstr(err, "the worst -2300 at pixel (11, 6)"))
        fail_msg("compare no longer warns of negatives: %s", err);
    free(out);
    free(err);
}

static void compare_prints_every_metric(void **state)
{
    (void)state;
    char a[2048], *out = NULL;
    const char *base = "render --scene spheres --env sky:64x32 --size 48x20 --quiet --no-sidecar";
    expectf(0, NULL, "%s --spp 1 -o '%s'", base, tu_path("c1.exr"));
    expectf(0, NULL, "%s --spp 16 -o '%s' --png '%s' --exposure -4", base, tu_path("c16.exr"),
            tu_path("c16.png"));
    run_ok(&out, "compare '%s' '%s' --json --exposure -4 --map '%s' --diff '%s'",
           tu_path("c16.exr"), tu_path("c1.exr"), tu_path("map.png"), tu_path("diff.exr"));
    cJSON *j = cJSON_Parse(out);
    free(out);
    assert_non_null(j);
    const char *keys[] = {"rmse",     "relmse",    "psnr",        "lab_delta_e",      "flip_ldr",
                          "flip_hdr", "psnr_peak", "exposure_ev", "pixels_per_degree"};
    for (int k = 0; k < 9; k++)
        if (!(num_or_nan(j, keys[k]) == num_or_nan(j, keys[k]))) fail_msg("no number %s", keys[k]);
    assert_true(num(j, "rmse") > 0 && num(j, "flip_ldr") > 0 && num(j, "flip_ldr") < 1);
    assert_true(num(j, "flip_hdr") > 0 && num(j, "flip_hdr") < 1 && num(j, "exposure_ev") == -4);
    assert_true(fabs(num(j, "pixels_per_degree") - 67.02) < 0.01);
    assert_non_null(
        strstr(cJSON_GetObjectItemCaseSensitive(j, "psnr_domain")->valuestring, "peak"));
    cJSON_Delete(j);
    assert_int_equal(tu_count_entries(tu_path("."), "map.png"), 1);
    assert_int_equal(tu_count_entries(tu_path("."), "diff.exr"), 1);
    /* Identical images: zero error, PSNR null (infinite), FLIP 0. */
    snprintf(a, sizeof a, "compare '%s' '%s' --json", tu_path("c1.exr"), tu_path("c1.exr"));
    assert_int_equal(run(a, &out, NULL), 0);
    j = cJSON_Parse(out);
    free(out);
    assert_true(num(j, "rmse") == 0 && num(j, "flip_ldr") == 0 && num(j, "flip_hdr") == 0);
    assert_true(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(j, "psnr")));
    cJSON_Delete(j);
    /* PNG inputs are decoded from sRGB to linear values in [0, 1]: two previews of the
     * same scene differ a little, and no value exceeds 1. */
    expectf(0, NULL, "%s --spp 1 -o '%s' --png '%s' --exposure -4", base, tu_path("c1b.exr"),
            tu_path("c1.png"));
    snprintf(a, sizeof a, "compare '%s' '%s' --json --no-hdr-flip", tu_path("c16.png"),
             tu_path("c1.png"));
    assert_int_equal(run(a, &out, NULL), 0);
    j = cJSON_Parse(out);
    free(out);
    assert_true(num(j, "rmse") > 0 && num(j, "rmse") < 0.5);
    assert_true(num(j, "psnr_peak") > 0.1 && num(j, "psnr_peak") <= 1.0);
    assert_true(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(j, "flip_hdr")));
    cJSON_Delete(j);
    /* The default exposure is auto (as the bench's): the reference's mean luminance to 0.18,
     * where EV 0 clamps a render under the sky almost everywhere; that warns. */
    run_ok(&out, "compare '%s' '%s' --json --no-hdr-flip", tu_path("c16.exr"), tu_path("c1.exr"));
    j = cJSON_Parse(out);
    free(out);
    assert_true(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(j, "exposure_auto")));
    const double auto_ev = num(j, "exposure_ev"), auto_lab = num(j, "lab_delta_e");
    assert_true(auto_ev < -2 && num(j, "clamped_fraction") < 0.05);
    cJSON_Delete(j);
    run_ok(&out, "compare '%s' '%s' --json --no-hdr-flip --exposure auto", tu_path("c16.exr"),
           tu_path("c1.exr"));
    j = cJSON_Parse(out);
    free(out);
    assert_true(num(j, "exposure_ev") == auto_ev && num(j, "lab_delta_e") == auto_lab);
    cJSON_Delete(j);
    snprintf(a, sizeof a, "compare '%s' '%s' --json --no-hdr-flip --exposure 0", tu_path("c16.exr"),
             tu_path("c1.exr"));
    char *err = NULL;
    assert_int_equal(run(a, &out, &err), 0);
    j = cJSON_Parse(out);
    assert_true(num(j, "clamped_fraction") > 0.5 && num(j, "lab_delta_e") < auto_lab);
    assert_non_null(strstr(err, "of the pixels clamp at 1"));
    assert_non_null(strstr(err, "--exposure auto"));
    cJSON_Delete(j);
    free(out);
    free(err);
    expect("compare a.exr b.exr --exposure bright", 2, "--exposure needs 'auto' or stops");
    expect("compare a.exr", 2, "needs REF and TEST");
    snprintf(a, sizeof a,
             "render --scene spheres --env sky:32x16 --size 10x10 --spp 1 --quiet -o '%s'",
             tu_path("small.exr"));
    expect(a, 0, NULL);
    snprintf(a, sizeof a, "compare '%s' '%s'", tu_path("c1.exr"), tu_path("small.exr"));
    expect(a, 1, "is 48 x 20 but");
}

/* Counts the lines of a file. */
static int count_lines(const char *path)
{
    size_t n;
    char *t = (char *)tu_read_file(path, &n);
    if (!t) return -1;
    int lines = 0;
    for (size_t k = 0; k < n; k++) lines += t[k] == '\n';
    free(t);
    return lines;
}

/* Every src="..." and href="..." of an HTML file names a file that exists beside it. */
static void check_links(const char *dir, const char *html)
{
    size_t n;
    char *t = (char *)tu_read_file(html, &n);
    assert_non_null(t);
    int links = 0;
    static const char *const attrs[] = {"src=\"", "href=\""};
    for (int a = 0; a < 2; a++)
        for (const char *p = t; (p = strstr(p, attrs[a])) || 0;) {
            p += strlen(attrs[a]);
            const char *e = strchr(p, '"');
            assert_non_null(e);
            char path[4096];
            snprintf(path, sizeof path, "%s/%.*s", dir, (int)(e - p), p);
            FILE *f = fopen(path, "rb");
            if (!f) fail_msg("index.html names %s, which is missing", path);
            fclose(f);
            links++;
            p = e;
        }
    assert_true(links > 20);
    free(t);
}

/* lumis bench on the CI suite: every output, resuming, shards and their merge, malformed
 * suites, and (when Chromium is installed) a screenshot of the HTML page. */
/* A suite may list light sets beside samplers: at equal samples with their K, at equal time
 * with K chosen to fill it; results and tables carry them like any method. */
static void bench_runs_light_sets(void **state)
{
    (void)state;
    static const char suite[] =
        "{\"name\": \"lights\", \"maps\": [\"sky:64x32\"], \"scenes\": [\"bunny-plane\"],\n"
        " \"methods\": [{\"method\": \"inversion\"}, {\"method\": \"wu\", \"k\": 16, \"params\": "
        "\"wd=4\"},\n"
        "             {\"method\": \"median-cut\", \"label\": \"mc\", \"interleave\": 2}],\n"
        " \"budgets\": [{\"spp\": 2}, {\"time\": 0.15}],\n"
        " \"reference\": {\"spp\": 64, \"method\": \"variance-min\", \"mode\": "
        "\"stratified\", \"k\": 8},\n \"size\": [48, 36]}\n";
    tu_write_file(tu_path("lights-suite.json"), suite, sizeof suite - 1);
    char a[4096], *err = NULL;
    snprintf(a, sizeof a, "bench '%s' --out '%s'", tu_path("lights-suite.json"), tu_path("bl"));
    assert_int_equal(run(a, NULL, &err), 0);
    assert_non_null(strstr(err, "6 items"));
    free(err);
    char p[4096];
    snprintf(p, sizeof p, "%s/results.csv", tu_path("bl"));
    assert_int_equal(count_lines(p), 7);
    size_t n;
    char *csv = (char *)tu_read_file(p, &n);
    assert_non_null(strstr(csv, ",wu,"));
    assert_non_null(strstr(csv, ",mc,"));
    /* Every item's time used (prep and every attempt: a light set whose K was refitted
     * renders twice), its attempts, and contention: wall and CPU seconds, the CPU share. */
    assert_non_null(strstr(csv,
                           ",flip_hdr,used_seconds,attempts,wall_seconds,cpu_seconds,cpu_share,"
                           "contention,auto_chosen\n"));
    int contended = 0;
    {
        char *save = NULL, *line = strtok_r(csv, "\n", &save);
        while ((line = strtok_r(NULL, "\n", &save))) {
            double v[21];
            const char *f = line;
            for (int c = 0; c < 21; c++) {
                v[c] = c >= 4 ? atof(f) : 0.0;
                f = strchr(f, ',');
                if (!f && c < 20) fail_msg("a row of %d columns: %s", c + 1, line);
                if (f) f++;
            }
            /* used = prep + render for one attempt, more for two */
            const double used = v[15], attempts = v[16], once = v[5] + v[6];
            if (attempts == 1 ? !(fabs(used - once) <= 1e-5 * once + 1e-6)
                              : !(attempts == 2 && used > once))
                fail_msg("used %g s in %g attempts, render + prep %g s: %s", used, attempts, once,
                         line);
            assert_true(v[17] > 0.0 && v[18] > 0.0 && v[19] > 0.0);
            contended += v[20] == 1.0;
        }
    }
    free(csv);
    /* results.md names the reference's method as it is, and warns of contention */
    snprintf(p, sizeof p, "%s/results.md", tu_path("bl"));
    char *md = (char *)tu_read_file(p, &n);
    assert_non_null(strstr(md, "reference: 64 spp, light set variance-min, stratified, K = 8;"));
    assert_true((strstr(md, "**Warning: contention.**") != NULL) == (contended > 0));
    free(md);
    /* A method's params are part of its items' keys: changing them re-renders those items
     * (Wu's two budgets) and no other. */
    char *edited = strdup(suite);
    memcpy(strstr(edited, "wd=4"), "wd=3", 4);
    tu_write_file(tu_path("lights-suite.json"), edited, strlen(edited));
    free(edited);
    err = NULL;
    assert_int_equal(run(a, NULL, &err), 0);
    if (!strstr(err, "(6 in this shard, 2 to render)")) fail_msg("re-run: %s", err);
    free(err);
    /* Malformed light-set methods. */
    static const bad_file bad[] = {
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"median-cut\", \"upsample\": 2}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].upsample: session: upsample: applies to Wu's decomposition"},
        /* which keys a light set takes, in which mode, is the library's check
         * (lumis_session_check), said with the suite's key */
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"wu\", \"mis\": \"power\"}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].mis: render: power_heuristic: does not apply: the scene is lit by a light "
         "set in point mode"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"median-cut\", \"blocks\": 64}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].blocks: render: lighting.sampler: does not apply"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"median-cut\", \"mode\": \"stratified\", \"bsdf_samples\": 2}], \"budgets\": "
         "[{\"spp\": 1}]}",
         "methods[0].bsdf_samples: render: bsdf_samples: does not apply: the scene is lit by a "
         "light set in stratified mode"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"alias\", \"k\": 8}], \"budgets\": [{\"spp\": 1}]}",
         "belong to light sets"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"alias\", \"params\": \"seed=1\"}], \"budgets\": [{\"spp\": 1}]}",
         "belong to light sets"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"wu\", \"params\": \"lambda=-1\"}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].params: lambda=VALUE needs"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"median-cut\", \"params\": \"wd=2\"}], \"budgets\": [{\"spp\": 1}]}",
         "'wd' is a parameter of Wu's decomposition"},
    };
    snprintf(a, sizeof a, "--out '%s'", tu_path("bl-bad"));
    expect_bad_files("bench", "bad-lights.json", a, bad, sizeof bad / sizeof bad[0]);
}

/* The stratified mode's allocated draws (region_draws) are part of an item's key: changing
 * the count re-renders that method's items and no other (a result of another count was
 * taken as this one's). */
static void bench_region_draws_in_the_key(void **state)
{
    (void)state;
    static const char text[] =
        "{\"maps\": [\"sky:32x16\"], \"scenes\": [\"spheres\"], \"methods\": [{\"label\": "
        "\"plain\", \"method\": \"median-cut\", \"mode\": \"stratified\", \"k\": 4}, {\"label\": "
        "\"alloc\", \"method\": \"median-cut\", \"mode\": \"stratified\", \"k\": 4, "
        "\"region_draws\": 8}], \"budgets\": [{\"spp\": 1}], \"reference\": {\"spp\": 2}, "
        "\"size\": [8, 6]}";
    char suite[1024], a[2600], *err = NULL;
    snprintf(suite, sizeof suite, "%s", tu_path("rd-suite.json"));
    tu_write_file(suite, text, sizeof text - 1);
    snprintf(a, sizeof a, "bench '%s' --out '%s'", suite, tu_path("rd-out"));
    assert_int_equal(run(a, NULL, &err), 0);
    if (!strstr(err, "(2 in this shard, 2 to render)")) fail_msg("first run: %s", err);
    free(err);
    char *edited = strdup(text);
    memcpy(strstr(edited, "\"region_draws\": 8"), "\"region_draws\": 9", 17);
    tu_write_file(suite, edited, strlen(edited));
    free(edited);
    err = NULL;
    assert_int_equal(run(a, NULL, &err), 0);
    if (!strstr(err, "(2 in this shard, 1 to render)")) fail_msg("re-run: %s", err);
    free(err);
}

/* A suite method {"auto": true} renders with the automatic estimator (render --auto) inside
 * its budget, and its results say what it chose: each item's result file (the candidates
 * the pilots measured), results.csv's auto_chosen column (empty for the fixed methods),
 * results.md's table of auto against the best fixed method per (map, scene, budget) with
 * its summary, results.json's "auto".  A scene may list the maps it is paired with: the
 * other pairs are neither rendered nor counted.  Bad values are refused with the file and
 * the key. */
static void bench_runs_auto(void **state)
{
    (void)state;
    static const char suite[] =
        "{\"name\": \"auto\", \"maps\": [\"sky:64x32\", \"studio:64x32\"],\n"
        " \"scenes\": [\"wu-glossy\", {\"scene\": \"window\", \"maps\": [\"studio-64x32\"]}],\n"
        " \"methods\": [{\"label\": \"mis\", \"method\": \"inversion\"},\n"
        "             {\"label\": \"strat\", \"method\": \"median-cut\", \"mode\": "
        "\"stratified\", \"k\": 8},\n"
        "             {\"label\": \"auto\", \"auto\": \"pilots\"}],\n"
        " \"budgets\": [{\"time\": 0.3}],\n"
        " \"reference\": {\"spp\": 16, \"method\": \"median-cut\", \"mode\": "
        "\"stratified\", \"k\": 8},\n \"size\": [32, 24]}\n";
    tu_write_file(tu_path("auto-suite.json"), suite, sizeof suite - 1);
    char a[4096], p[4096], *err = NULL;
    snprintf(a, sizeof a, "bench '%s' --out '%s' --jobs 2", tu_path("auto-suite.json"),
             tu_path("ba"));
    assert_int_equal(run(a, NULL, &err), 0);
    /* three pairs (window with the studio alone) of three methods */
    if (!strstr(err, "9 items (9 in this shard, 9 to render)")) fail_msg("%s", err);
    assert_null(strstr(err, "sky-64x32__window"));
    free(err);
    snprintf(p, sizeof p, "%s/results/sky-64x32__window__auto__t0.3s.json", tu_path("ba"));
    assert_int_equal(access(p, F_OK), -1);
    /* each auto item's result: its choice, one of the candidates its pilots measured */
    const char *pairs[3] = {"sky-64x32__wu-glossy", "studio-64x32__wu-glossy",
                            "studio-64x32__window"};
    char chosen[3][32];
    for (int k = 0; k < 3; k++) {
        snprintf(p, sizeof p, "%s/results/%s__auto__t0.3s.json", tu_path("ba"), pairs[k]);
        size_t n;
        char *text = (char *)tu_read_file(p, &n);
        cJSON *j = cJSON_Parse(text);
        free(text);
        const cJSON *c = item(j, "auto_chosen"), *cands = item(j, "auto_candidates");
        assert_string_equal(item(j, "auto_mode")->valuestring, "pilots");
        assert_true(cJSON_IsString(c) && cJSON_IsArray(cands));
        assert_true(cJSON_GetArraySize(cands) >= 2);
        int named = 0;
        for (const cJSON *q = cands->child; q; q = q->next) {
            named += strcmp(item(q, "name")->valuestring, c->valuestring) == 0;
            /* measured (pilot_spp > 0): a positive efficiency; not (capped, no sun): 0 */
            const int measured = item(q, "pilot_spp")->valueint > 0;
            assert_int_equal(item(q, "efficiency")->valuedouble > 0.0, measured);
        }
        assert_int_equal(named, 1);
        snprintf(chosen[k], sizeof chosen[k], "%s", c->valuestring);
        /* a fixed method's result has none */
        snprintf(p, sizeof p, "%s/results/%s__mis__t0.3s.json", tu_path("ba"), pairs[k]);
        text = (char *)tu_read_file(p, &n);
        cJSON *jm = cJSON_Parse(text);
        free(text);
        assert_null(cJSON_GetObjectItemCaseSensitive(jm, "auto_chosen"));
        cJSON_Delete(jm);
        cJSON_Delete(j);
    }
    /* results.csv: the choice in its last column, for auto's rows only */
    snprintf(p, sizeof p, "%s/results.csv", tu_path("ba"));
    assert_int_equal(count_lines(p), 10);
    size_t n;
    char *csv = (char *)tu_read_file(p, &n);
    assert_non_null(strstr(csv, ",contention,auto_chosen\n"));
    for (int k = 0; k < 3; k++) {
        char row_start[128];
        snprintf(row_start, sizeof row_start, "\n%.*s,%s,auto,t0.3s,", (int)strcspn(pairs[k], "_"),
                 pairs[k], strstr(pairs[k], "__") + 2);
        const char *row = strstr(csv, row_start);
        if (!row) fail_msg("no row %s in %s", row_start + 1, csv);
        const char *end = strchr(row + 1, '\n'), *last = end;
        while (last[-1] != ',') last--;
        if ((size_t)(end - last) != strlen(chosen[k]) ||
            strncmp(last, chosen[k], strlen(chosen[k])))
            fail_msg("row %.*s: expected the choice %s", (int)(end - row - 1), row + 1, chosen[k]);
        snprintf(row_start, sizeof row_start, "\n%.*s,%s,mis,t0.3s,", (int)strcspn(pairs[k], "_"),
                 pairs[k], strstr(pairs[k], "__") + 2);
        row = strstr(csv, row_start);
        assert_non_null(row);
        end = strchr(row + 1, '\n');
        assert_true(end[-1] == ','); /* a fixed method: empty */
    }
    free(csv);
    /* results.md: the summary and a row per case, auto against the better of mis and strat */
    snprintf(p, sizeof p, "%s/results.md", tu_path("ba"));
    char *md = (char *)tu_read_file(p, &n);
    assert_non_null(strstr(md, "## auto's choice against the best fixed method"));
    assert_non_null(strstr(md, "| budget | pairs | auto / best fixed (geometric mean) | beyond "
                               "1.10× | chosen |"));
    assert_non_null(strstr(md, "| t0.3s | 3 | "));
    assert_non_null(strstr(md, "9 of 9 items (2 maps × 2 scenes, the pairs the scenes list"));
    free(md);
    /* results.json: the same, per case, with the ratio the table shows */
    snprintf(p, sizeof p, "%s/results.json", tu_path("ba"));
    char *text = (char *)tu_read_file(p, &n);
    cJSON *j = cJSON_Parse(text);
    free(text);
    const cJSON *au = cJSON_GetArrayItem(item(j, "auto"), 0);
    assert_string_equal(item(au, "method")->valuestring, "auto");
    const cJSON *cases = item(au, "cases");
    assert_int_equal(cJSON_GetArraySize(cases), 3);
    double logsum = 0.0;
    for (const cJSON *c = cases->child; c; c = c->next) {
        const double rel = item(c, "relmse")->valuedouble,
                     best = item(c, "best_fixed_relmse")->valuedouble;
        assert_true(rel > 0.0 && best > 0.0);
        assert_true(fabs(item(c, "ratio")->valuedouble - rel / best) <= 1e-12 * rel / best);
        logsum += log(rel / best);
        const char *bf = item(c, "best_fixed")->valuestring;
        assert_true(strcmp(bf, "mis") == 0 || strcmp(bf, "strat") == 0);
    }
    const cJSON *b0 = cJSON_GetArrayItem(item(au, "budgets"), 0);
    assert_int_equal(item(b0, "pairs")->valueint, 3);
    assert_true(fabs(item(b0, "geomean_ratio")->valuedouble - exp(logsum / 3)) <= 1e-9);
    cJSON_Delete(j);
    /* {"auto": true}: the prediction (lumis render's default), no pilots: its mode and the
     * diffuse share in the item's result (wu-diffuse: Lambertian everywhere, strata) */
    static const char predict[] =
        "{\"name\": \"predict\", \"maps\": [\"sky:64x32\"], \"scenes\": [\"wu-diffuse\"],\n"
        " \"methods\": [{\"label\": \"auto\", \"auto\": true}], \"budgets\": [{\"spp\": 1}],\n"
        " \"reference\": {\"spp\": 2, \"method\": \"inversion\"}, \"size\": [32, 24]}\n";
    tu_write_file(tu_path("predict-suite.json"), predict, sizeof predict - 1);
    snprintf(a, sizeof a, "bench '%s' --out '%s'", tu_path("predict-suite.json"), tu_path("bp"));
    assert_int_equal(run(a, NULL, NULL), 0);
    snprintf(p, sizeof p, "%s/results/sky-64x32__wu-diffuse__auto__spp1.json", tu_path("bp"));
    {
        size_t np;
        char *tp = (char *)tu_read_file(p, &np);
        cJSON *jp = cJSON_Parse(tp);
        free(tp);
        assert_string_equal(item(jp, "auto_mode")->valuestring, "predict");
        assert_true(item(jp, "auto_diffuse_share")->valuedouble == 1.0);
        assert_string_equal(item(jp, "auto_chosen")->valuestring, "stratified-32");
        cJSON_Delete(jp);
    }
    /* Malformed: said with the file and the key. */
    static const bad_file bad[] = {
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"auto\": 1}], "
         "\"budgets\": [{\"spp\": 1}]}",
         "methods[0].auto: expected true, false or \"pilots\""},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"auto\": "
         "\"yes\"}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].auto: expected true, false or \"pilots\""},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"auto\": true, "
         "\"method\": \"median-cut\"}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].auto: the session chooses"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"auto\": true, "
         "\"method\": \"bsdf\"}], \"budgets\": [{\"spp\": 1}]}",
         "not 'bsdf'"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"auto\": true, "
         "\"sun\": true}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].auto: chooses the estimator itself: not with \"sun\""},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"auto\": true, "
         "\"mis\": \"none\"}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].auto: chooses the estimator itself: not with \"mis\": \"none\""},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"inversion\"}], \"budgets\": [{\"spp\": 1}], \"reference\": {\"auto\": true}}",
         "reference.auto: unknown key"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [{\"scene\": \"spheres\", \"maps\": "
         "[\"sky\"]}], \"methods\": [{\"method\": \"inversion\"}], \"budgets\": [{\"spp\": 1}]}",
         "scenes[0].maps[0]: expected the label of one of the suite's maps (none is labelled "
         "'sky')"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [{\"scene\": \"spheres\", \"maps\": []}], "
         "\"methods\": [{\"method\": \"inversion\"}], \"budgets\": [{\"spp\": 1}]}",
         "scenes[0].maps: expected a non-empty array of map labels"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [{\"scene\": \"spheres\", \"map\": "
         "[\"sky-8x4\"]}], \"methods\": [{\"method\": \"inversion\"}], \"budgets\": [{\"spp\": "
         "1}]}",
         "scenes[0].map: unknown key"},
    };
    snprintf(a, sizeof a, "--out '%s'", tu_path("ba-bad"));
    expect_bad_files("bench", "bad-auto.json", a, bad, sizeof bad / sizeof bad[0]);
}

/* A bench survives its items: one that fails (here its output path is a folder) is
 * recorded with its error, the others are done, the report lists it, the run exits 1,
 * and a rerun retries it alone.  A malformed scene stops the run before any render. */
static void bench_survives_a_failing_item(void **state)
{
    (void)state;
    char dir[512], suite[600], a[2048], p[1200];
    snprintf(dir, sizeof dir, "%s", tu_path("bsurv"));
    snprintf(suite, sizeof suite, "%s/s.json", dir);
    mkdir(dir, 0777);
    static const char text[] =
        "{\"maps\": [\"sky:32x16\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
        "\"alias\"}, {\"method\": \"inversion\"}], \"budgets\": [{\"spp\": 2}], \"reference\": "
        "{\"spp\": 4}, \"size\": [8, 6]}";
    tu_write_file(suite, text, sizeof text - 1);
    snprintf(p, sizeof p, "%s/out/renders/sky-32x16__spheres__alias__spp2.exr", dir);
    char mk[1400];
    snprintf(mk, sizeof mk, "mkdir -p '%s'", p);
    assert_int_equal(tu_run(mk, NULL, NULL), 0);
    snprintf(a, sizeof a, "bench '%s' --out '%s/out'", suite, dir);
    char *err = NULL;
    assert_int_equal(run(a, NULL, &err), 1);
    assert_non_null(strstr(err, "item sky-32x16__spheres__alias__spp2 failed"));
    assert_non_null(strstr(err, "1 of 2 items"));
    free(err);
    char md_path[1200];
    snprintf(md_path, sizeof md_path, "%s/out/results.md", dir);
    size_t n;
    char *md = (char *)tu_read_file(md_path, &n);
    assert_non_null(md);
    assert_non_null(strstr(md, "## Failed items"));
    free(md);
    assert_int_equal(rmdir(p), 0);
    err = NULL;
    assert_int_equal(run(a, NULL, &err), 0);
    assert_non_null(strstr(err, "(2 in this shard, 1 to render)"));
    free(err);
    md = (char *)tu_read_file(md_path, &n);
    assert_null(strstr(md, "Failed items"));
    free(md);
    /* --merge of another suite's folder: refused, nothing copied (it copied silently) */
    static const char other[] =
        "{\"maps\": [\"sky:32x16\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
        "\"hierarchical\"}], \"budgets\": [{\"spp\": 2}], \"reference\": {\"spp\": 4}, "
        "\"size\": [8, 6]}";
    char suite3[700];
    snprintf(suite3, sizeof suite3, "%s/other.json", dir);
    tu_write_file(suite3, other, sizeof other - 1);
    snprintf(a, sizeof a, "bench '%s' --out '%s/out3' --merge '%s/out'", suite3, dir, dir);
    err = NULL;
    assert_int_equal(run(a, NULL, &err), 1);
    assert_non_null(strstr(err, "none of its 2 results belongs to suite 'other'"));
    free(err);
    /* a malformed scene: refused before the first render */
    static const char bad[] = "{\"objects\": [], \"lumnaires\": []}";
    char scene[700];
    snprintf(scene, sizeof scene, "%s/bad.json", dir);
    tu_write_file(scene, bad, sizeof bad - 1);
    static const char text2[] =
        "{\"maps\": [\"sky:32x16\"], \"scenes\": [\"spheres\", \"bad.json\"], \"methods\": "
        "[{\"method\": \"alias\"}], \"budgets\": [{\"spp\": 2}], \"reference\": {\"spp\": 4}, "
        "\"size\": [8, 6]}";
    tu_write_file(suite, text2, sizeof text2 - 1);
    snprintf(a, sizeof a, "bench '%s' --out '%s/out2'", suite, dir);
    err = NULL;
    assert_int_equal(run(a, NULL, &err), 1);
    assert_non_null(strstr(err, "did you mean \"luminaires\""));
    assert_non_null(strstr(err, "nothing was rendered"));
    assert_null(strstr(err, "reference"));
    free(err);
}

/* Sets the relMSE of a result file of DIR/results/ (its item key kept: still current). */
static void set_relmse(const char *dir, const char *id, double relmse)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/results/%s.json", dir, id);
    size_t n = 0;
    char *text = (char *)tu_read_file(path, &n);
    if (!text) fail_msg("no result %s", path);
    cJSON *j = cJSON_ParseWithLength(text, n);
    free(text);
    cJSON *v = cJSON_GetObjectItemCaseSensitive(j, "relmse");
    if (!cJSON_IsNumber(v)) fail_msg("%s: no relmse", path);
    cJSON_SetNumberValue(v, relmse);
    char *out = cJSON_Print(j);
    tu_write_file(path, out, strlen(out));
    cJSON_free(out);
    cJSON_Delete(j);
}

static double json_path_number(const cJSON *o, const char *what)
{
    if (!cJSON_IsNumber(o)) fail_msg("results.json: %s is not a number", what);
    return o->valuedouble;
}

/* cmocka 1.1's assert_float_equal works in float */
#define assert_double_equal(a, b, eps)                                                             \
    do {                                                                                           \
        const double a_ = (a), b_ = (b);                                                           \
        if (!(fabs(a_ - b_) <= (eps))) fail_msg("%s = %.12g, want %.12g", #a, a_, b_);             \
    } while (0)

/* Reads DIR/results.json (the caller frees it with cJSON_Delete). */
static cJSON *read_results_json(const char *dir)
{
    char p[4096];
    size_t n = 0;
    snprintf(p, sizeof p, "%s/results.json", dir);
    char *text = (char *)tu_read_file(p, &n);
    if (!text) fail_msg("no %s", p);
    cJSON *j = cJSON_ParseWithLength(text, n);
    free(text);
    if (!j) fail_msg("%s: malformed JSON", p);
    return j;
}

/* Hand-made errors of the convergence tests' suites (two scenes, inversion and alias, three
 * budgets whose x = 1, 2, 4 are labelled budgets[k]): inversion 0.08 / x on spheres (slope
 * -1) and 0.02 / sqrt(x) on bunny-plane (-0.5), a geometric mean of 0.04 x^-0.75 (-0.75);
 * alias 0.02 everywhere (slope 0), but 0 (left out) on bunny-plane at the last budget when
 * alias_gap.  alias / inversion = 0.5 x^0.75: 1 at x = 2^(4/3). */
static void set_convergence_errors(const char *dir, const char *map, const char *const budgets[3],
                                   int alias_gap)
{
    for (int k = 0; k < 3; k++) {
        const double x = 1 << k;
        char id[256];
        snprintf(id, sizeof id, "%s__spheres__inversion__%s", map, budgets[k]);
        set_relmse(dir, id, 0.08 / x);
        snprintf(id, sizeof id, "%s__bunny-plane__inversion__%s", map, budgets[k]);
        set_relmse(dir, id, 0.02 / sqrt(x));
        snprintf(id, sizeof id, "%s__spheres__alias__%s", map, budgets[k]);
        set_relmse(dir, id, 0.02);
        snprintf(id, sizeof id, "%s__bunny-plane__alias__%s", map, budgets[k]);
        set_relmse(dir, id, alias_gap && k == 2 ? 0.0 : 0.02);
    }
}

/* inversion's slopes in a convergence object made of set_convergence_errors' errors: -0.75
 * over all pairs, -1 on spheres, -0.5 on bunny-plane. */
static void check_inversion_slopes(const cJSON *inv)
{
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(inv, "method")->valuestring, "inversion");
    assert_double_equal(json_path_number(cJSON_GetObjectItemCaseSensitive(inv, "slope"), "slope"),
                        -0.75, 1e-9);
    const cJSON *ss = cJSON_GetObjectItemCaseSensitive(inv, "scene_slopes");
    assert_double_equal(
        json_path_number(cJSON_GetObjectItemCaseSensitive(ss, "spheres"), "spheres"), -1.0, 1e-9);
    assert_double_equal(
        json_path_number(cJSON_GetObjectItemCaseSensitive(ss, "bunny-plane"), "bunny-plane"), -0.5,
        1e-9);
}

/* The convergence analysis at equal time (two or more time budgets): the section of
 * results.md and index.html, results.json's "convergence" object and convergence-all.svg;
 * on hand-made relMSEs, the slopes (over all pairs and per scene), the pairs counted (an
 * item with relMSE 0 left out), the ratios and the crossing time; no analysis, and no stale
 * plot, with fewer than two time budgets. */
static void bench_convergence_at_equal_time(void **state)
{
    (void)state;
    static const char suite[] =
        "{\"name\": \"conv\", \"maps\": [\"sky:32x16\"], \"scenes\": [\"spheres\", "
        "\"bunny-plane\"],\n \"methods\": [{\"method\": \"inversion\"}, {\"method\": "
        "\"alias\"}],\n \"budgets\": [{\"spp\": 1}, {\"time\": 0.2}, {\"time\": 0.05}, "
        "{\"time\": 0.1}],\n \"reference\": {\"spp\": 8}, \"size\": [8, 6], \"compare\": "
        "[[\"alias\", \"inversion\"]]}\n";
    char dir[512], a[4096], p[4096];
    snprintf(dir, sizeof dir, "%s", tu_path("bconv"));
    tu_write_file(tu_path("conv.json"), suite, sizeof suite - 1);
    expectf(0, "16 of 16 items", "bench '%s' --out '%s' --threads 1", tu_path("conv.json"), dir);
    assert_int_equal(tu_count_entries(dir, "convergence-all.svg"), 1);
    /* Hand-made errors (set_convergence_errors), x = t / 0.05 s (the budgets are listed out
     * of order), alias's left out at 0.2 s on bunny-plane: the crossing at 0.05 2^(4/3) s. */
    static const char *const budgets[] = {"t0.05s", "t0.1s", "t0.2s"};
    set_convergence_errors(dir, "sky-32x16", budgets, 1);
    set_relmse(dir, "sky-32x16__spheres__alias__spp1", 1e3); /* spp budgets take no part */
    snprintf(a, sizeof a, "bench '%s' --out '%s' --report-only", tu_path("conv.json"), dir);
    expect(a, 0, "16 of 16 items");
    size_t n;
    cJSON *j = read_results_json(dir);
    const cJSON *conv = cJSON_GetObjectItemCaseSensitive(j, "convergence");
    if (!cJSON_IsObject(conv)) fail_msg("results.json has no \"convergence\" object");
    const cJSON *sec = cJSON_GetObjectItemCaseSensitive(conv, "seconds");
    assert_int_equal(cJSON_GetArraySize(sec), 3);
    for (int k = 0; k < 3; k++)
        assert_double_equal(json_path_number(cJSON_GetArrayItem(sec, k), "seconds"),
                            0.05 * (1 << k), 1e-12);
    const cJSON *methods = cJSON_GetObjectItemCaseSensitive(conv, "methods");
    assert_int_equal(cJSON_GetArraySize(methods), 2);
    const cJSON *inv = cJSON_GetArrayItem(methods, 0), *ali = cJSON_GetArrayItem(methods, 1);
    check_inversion_slopes(inv);
    const cJSON *geo = cJSON_GetObjectItemCaseSensitive(inv, "geomean_relmse");
    for (int k = 0; k < 3; k++)
        assert_double_equal(json_path_number(cJSON_GetArrayItem(geo, k), "geomean"),
                            0.04 * pow(1 << k, -0.75), 1e-12);
    assert_double_equal(json_path_number(cJSON_GetObjectItemCaseSensitive(ali, "slope"), "slope"),
                        0.0, 1e-9);
    const cJSON *pairs = cJSON_GetObjectItemCaseSensitive(ali, "pairs");
    static const int want_pairs[] = {2, 2, 1};
    for (int k = 0; k < 3; k++)
        assert_int_equal((int)json_path_number(cJSON_GetArrayItem(pairs, k), "pairs"),
                         want_pairs[k]);
    const cJSON *cmp = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(conv, "compare"), 0);
    if (!cmp) fail_msg("results.json: no compare pair in \"convergence\"");
    const cJSON *ratio = cJSON_GetObjectItemCaseSensitive(cmp, "ratio");
    for (int k = 0; k < 3; k++)
        assert_double_equal(json_path_number(cJSON_GetArrayItem(ratio, k), "ratio"),
                            0.5 * pow(1 << k, 0.75), 1e-9);
    const cJSON *xs = cJSON_GetObjectItemCaseSensitive(cmp, "crossings");
    assert_int_equal(cJSON_GetArraySize(xs), 1);
    assert_double_equal(
        json_path_number(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(xs, 0), "seconds"),
                         "crossing"),
        0.05 * pow(2, 4.0 / 3), 1e-9);
    assert_string_equal(
        cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(xs, 0), "below_after")->valuestring,
        "b");
    cJSON_Delete(j);
    /* results.md and index.html: the same section, with the plot */
    snprintf(p, sizeof p, "%s/results.md", dir);
    char *md = (char *)tu_read_file(p, &n);
    const char *md_parts[] = {
        "## Convergence (equal time)",
        "| inversion | 0.04 | 0.02378 | 0.01414 | 2 | -0.75 | -1.00 | -0.50 |",
        "| alias | 0.02 | 0.02 | 0.02 | 2, 2, 1 | 0.00 | 0.00 | 0.00 |",
        "| alias / inversion | 0.500 | 0.841 | 1.414 | 0.126 s (alias above after) |",
        "(convergence-all.svg)"};
    for (int k = 0; k < 5; k++)
        if (!strstr(md, md_parts[k])) fail_msg("results.md lacks \"%s\":\n%s", md_parts[k], md);
    free(md);
    snprintf(p, sizeof p, "%s/index.html", dir);
    char *html = (char *)tu_read_file(p, &n);
    const char *html_parts[] = {"<h2>Convergence (equal time)</h2>",
                                "<td>alias / inversion</td><td>0.500</td>",
                                "<img src=\"convergence-all.svg\""};
    for (int k = 0; k < 3; k++)
        if (!strstr(html, html_parts[k])) fail_msg("index.html lacks %s", html_parts[k]);
    free(html);
    snprintf(p, sizeof p, "%s/convergence-all.svg", dir);
    char *svg = (char *)tu_read_file(p, &n);
    assert_non_null(strstr(svg, "inversion (slope -0.75)"));
    assert_non_null(strstr(svg, "alias (slope 0.00)"));
    free(svg);
    /* One time budget (the same items, so the same results): no analysis, no stale plot. */
    static const char one[] =
        "{\"name\": \"conv\", \"maps\": [\"sky:32x16\"], \"scenes\": [\"spheres\", "
        "\"bunny-plane\"],\n \"methods\": [{\"method\": \"inversion\"}, {\"method\": "
        "\"alias\"}],\n \"budgets\": [{\"spp\": 1}, {\"time\": 0.2}],\n \"reference\": "
        "{\"spp\": 8}, \"size\": [8, 6], \"compare\": [[\"alias\", \"inversion\"]]}\n";
    tu_write_file(tu_path("conv.json"), one, sizeof one - 1);
    expect(a, 0, "8 of 8 items");
    assert_int_equal(tu_count_entries(dir, "convergence-all.svg"), 0);
    snprintf(p, sizeof p, "%s/results.md", dir);
    md = (char *)tu_read_file(p, &n);
    assert_null(strstr(md, "Convergence (equal time)"));
    free(md);
    j = read_results_json(dir);
    assert_null(cJSON_GetObjectItemCaseSensitive(j, "convergence"));
    cJSON_Delete(j);
}

/* The same analysis over the spp budgets (two or more of them): the section "Convergence
 * (equal samples)" of results.md and index.html, results.json's "convergence_spp" (its
 * arrays named "spp") and convergence-spp.svg; finite slopes on the rendered errors, then on
 * hand-made ones the slopes against log(spp), the ratios and the crossing in spp.  The one
 * time budget takes no part and makes no equal-time analysis; with one spp budget left, no
 * analysis and no stale plot. */
static void bench_convergence_at_equal_samples(void **state)
{
    (void)state;
    static const char suite[] =
        "{\"name\": \"convspp\", \"maps\": [\"sky:16x8\"], \"scenes\": [\"spheres\", "
        "\"bunny-plane\"],\n \"methods\": [{\"method\": \"inversion\"}, {\"method\": "
        "\"alias\"}],\n \"budgets\": [{\"spp\": 4}, {\"time\": 0.02}, {\"spp\": 1}, "
        "{\"spp\": 2}],\n \"reference\": {\"spp\": 8}, \"size\": [8, 6], \"compare\": "
        "[[\"alias\", \"inversion\"]]}\n";
    char dir[512], a[4096], p[4096];
    snprintf(dir, sizeof dir, "%s", tu_path("bconvspp"));
    tu_write_file(tu_path("convspp.json"), suite, sizeof suite - 1);
    snprintf(a, sizeof a, "bench '%s' --out '%s' --threads 1", tu_path("convspp.json"), dir);
    expect(a, 0, "16 of 16 items");
    assert_int_equal(tu_count_entries(dir, "convergence-spp.svg"), 1);
    assert_int_equal(tu_count_entries(dir, "convergence-all.svg"), 0);
    /* the rendered errors: a finite slope for every method, over all pairs and per scene */
    cJSON *j = read_results_json(dir);
    assert_null(cJSON_GetObjectItemCaseSensitive(j, "convergence"));
    const cJSON *conv = cJSON_GetObjectItemCaseSensitive(j, "convergence_spp");
    if (!cJSON_IsObject(conv)) fail_msg("results.json has no \"convergence_spp\" object");
    const cJSON *me;
    cJSON_ArrayForEach(me, cJSON_GetObjectItemCaseSensitive(conv, "methods"))
    {
        const char *label = cJSON_GetObjectItemCaseSensitive(me, "method")->valuestring;
        if (!isfinite(json_path_number(cJSON_GetObjectItemCaseSensitive(me, "slope"), "slope")))
            fail_msg("%s: slope not finite", label);
        const cJSON *ss;
        cJSON_ArrayForEach(ss, cJSON_GetObjectItemCaseSensitive(me, "scene_slopes"))
        {
            if (!isfinite(json_path_number(ss, "scene slope")))
                fail_msg("%s: scene slope %s not finite", label, ss->string);
        }
    }
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(conv, "methods")), 2);
    cJSON_Delete(j);
    /* Hand-made errors (set_convergence_errors), x = spp (listed out of order): the
     * crossing at 2^(4/3) = 2.52 spp. */
    static const char *const budgets[] = {"spp1", "spp2", "spp4"};
    set_convergence_errors(dir, "sky-16x8", budgets, 0);
    set_relmse(dir, "sky-16x8__spheres__alias__t0.02s", 1e3); /* time budgets take no part */
    snprintf(a, sizeof a, "bench '%s' --out '%s' --report-only", tu_path("convspp.json"), dir);
    expect(a, 0, "16 of 16 items");
    j = read_results_json(dir);
    conv = cJSON_GetObjectItemCaseSensitive(j, "convergence_spp");
    if (!cJSON_IsObject(conv)) fail_msg("results.json has no \"convergence_spp\" object");
    assert_null(cJSON_GetObjectItemCaseSensitive(conv, "seconds"));
    const cJSON *spp = cJSON_GetObjectItemCaseSensitive(conv, "spp");
    assert_int_equal(cJSON_GetArraySize(spp), 3);
    for (int k = 0; k < 3; k++)
        assert_double_equal(json_path_number(cJSON_GetArrayItem(spp, k), "spp"), 1 << k, 0);
    const cJSON *inv = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(conv, "methods"), 0);
    assert_int_equal(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(inv, "spp")), 3);
    check_inversion_slopes(inv);
    const cJSON *cmp = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(conv, "compare"), 0);
    if (!cmp) fail_msg("results.json: no compare pair in \"convergence_spp\"");
    const cJSON *x0 = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(cmp, "crossings"), 0);
    assert_double_equal(json_path_number(cJSON_GetObjectItemCaseSensitive(x0, "spp"), "crossing"),
                        pow(2, 4.0 / 3), 1e-9);
    cJSON_Delete(j);
    size_t n;
    snprintf(p, sizeof p, "%s/results.md", dir);
    char *md = (char *)tu_read_file(p, &n);
    const char *md_parts[] = {
        "## Convergence (equal samples)",
        "against log(spp)",
        "Budgets in time take no part.",
        "| method | spp1 | spp2 | spp4 | pairs | slope | slope spheres | slope bunny-plane |",
        "| inversion | 0.04 | 0.02378 | 0.01414 | 2 | -0.75 | -1.00 | -0.50 |",
        "| alias | 0.02 | 0.02 | 0.02 | 2 | 0.00 | 0.00 | 0.00 |",
        "| alias / inversion | 0.500 | 0.841 | 1.414 | 2.52 spp (alias above after) |",
        "(convergence-spp.svg)"};
    for (int k = 0; k < 8; k++)
        if (!strstr(md, md_parts[k])) fail_msg("results.md lacks \"%s\":\n%s", md_parts[k], md);
    assert_null(strstr(md, "Convergence (equal time)"));
    free(md);
    snprintf(p, sizeof p, "%s/index.html", dir);
    char *html = (char *)tu_read_file(p, &n);
    assert_non_null(strstr(html, "<h2>Convergence (equal samples)</h2>"));
    assert_non_null(strstr(html, "<img src=\"convergence-spp.svg\""));
    free(html);
    snprintf(p, sizeof p, "%s/convergence-spp.svg", dir);
    char *svg = (char *)tu_read_file(p, &n);
    assert_non_null(strstr(svg, "inversion (slope -0.75)"));
    assert_non_null(strstr(svg, "samples per pixel (log)"));
    free(svg);
    /* One spp budget (the same items): no analysis, no stale plot. */
    static const char one[] =
        "{\"name\": \"convspp\", \"maps\": [\"sky:16x8\"], \"scenes\": [\"spheres\", "
        "\"bunny-plane\"],\n \"methods\": [{\"method\": \"inversion\"}, {\"method\": "
        "\"alias\"}],\n \"budgets\": [{\"spp\": 4}, {\"time\": 0.02}],\n \"reference\": "
        "{\"spp\": 8}, \"size\": [8, 6], \"compare\": [[\"alias\", \"inversion\"]]}\n";
    tu_write_file(tu_path("convspp.json"), one, sizeof one - 1);
    expect(a, 0, "8 of 8 items");
    assert_int_equal(tu_count_entries(dir, "convergence-spp.svg"), 0);
    snprintf(p, sizeof p, "%s/results.md", dir);
    md = (char *)tu_read_file(p, &n);
    assert_null(strstr(md, "Convergence (equal samples)"));
    free(md);
    j = read_results_json(dir);
    assert_null(cJSON_GetObjectItemCaseSensitive(j, "convergence_spp"));
    cJSON_Delete(j);
}

static void bench_runs_resumes_shards_and_reports(void **state)
{
    (void)state;
    char a[4096], *err = NULL;
    const char *suite = LUMIS_SOURCE_DIR "/bench/suites/smoke.json";
    snprintf(a, sizeof a, "bench '%s' --out '%s'", suite, tu_path("b"));
    assert_int_equal(run(a, NULL, &err), 0);
    assert_non_null(strstr(err, "18 items (18 in this shard, 18 to render)"));
    assert_non_null(strstr(err, "loaded 2 maps ("));
    char p[4096];
    snprintf(p, sizeof p, "%s/results.csv", tu_path("b"));
    assert_int_equal(count_lines(p), 19); /* header + 18 items */
    /* The noisy-reference warning: exactly when an item reached more than 128 / 4 spp (the
     * equal-time items' spp depend on the machine's load; column 5 of the CSV). */
    int most = 0; /* the most spp an item reached */
    {
        size_t n = 0;
        char *csv = (char *)tu_read_file(p, &n), *save = NULL;
        for (char *line = strtok_r(csv, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
            const char *f = line;
            for (int c = 0; c < 4 && f; c++) f = strchr(f, ',') ? strchr(f, ',') + 1 : NULL;
            if (f && atoi(f) > most) most = atoi(f);
        }
        free(csv);
        if (most > 32)
            assert_non_null(strstr(err, "warning: the reference has 128 spp"));
        else
            assert_null(strstr(err, "warning: the reference has"));
    }
    free(err);
    const char *files[] = {"results.json", "results.md", "index.html", "convergence-spheres.svg"};
    for (int k = 0; k < 4; k++) assert_int_equal(tu_count_entries(tu_path("b"), files[k]), 1);
    snprintf(p, sizeof p, "%s/results.md", tu_path("b"));
    size_t n;
    char *md = (char *)tu_read_file(p, &n);
    assert_non_null(strstr(md, "## kdtree against inversion"));
    assert_non_null(strstr(md, "18 of 18 items"));
    /* smoke's reference (128 spp) is noisy next to equal-time items past 32 spp: a fast
     * machine's (200+ spp), not a loaded one's; the tables say so exactly then. */
    assert_true((strstr(md, "Warning: a noisy reference") != NULL) == (most > 32));
    free(md);
    snprintf(p, sizeof p, "%s/index.html", tu_path("b"));
    check_links(tu_path("b"), p);
    /* The page has the tables results.md has, thumbnails that link to their full size,
     * and the FLIP maps' colour scale. */
    char *html = (char *)tu_read_file(p, &n);
    const char *parts[] = {"kdtree against inversion</h2>", "relMSE per map and scene",
                           "<a href=\"previews/", "flip-legend.png", "noisy reference"};
    for (int k = 0; k < 4; k++)
        if (!strstr(html, parts[k])) fail_msg("index.html lacks %s", parts[k]);
    assert_true((strstr(html, parts[4]) != NULL) == (most > 32));
    free(html);
    /* Resume: nothing left to render. */
    assert_int_equal(run(a, NULL, &err), 0);
    assert_non_null(strstr(err, "(18 in this shard, 0 to render)"));
    assert_non_null(strstr(err, "loaded 0 maps ("));
    free(err);
    /* A map file serving two maps (rotated, relabelled) is read once for every item. */
    expectf(0, NULL, "sky --size 16x8 -o '%s'", tu_path("m.exr"));
    static const char twice[] =
        "{\"maps\": [\"m.exr\", {\"map\": \"m.exr\", \"rotation_deg\": 90, \"label\": "
        "\"m-rot\"}], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": \"alias\"}], "
        "\"budgets\": [{\"spp\": 1}, {\"spp\": 2}], \"reference\": {\"spp\": 4}, "
        "\"size\": [8, 4]}";
    tu_write_file(tu_path("twice.json"), twice, strlen(twice));
    snprintf(a, sizeof a, "bench '%s' --out '%s'", tu_path("twice.json"), tu_path("tw"));
    expect(a, 0, "loaded 1 map (");
    expect(a, 0, "(4 in this shard, 0 to render)");
    /* Two shards into two folders, then a merge into a third. */
    for (int s = 0; s < 2; s++) {
        char dir[32];
        snprintf(dir, sizeof dir, "shard%d", s);
        assert_int_equal(
            runf(NULL, &err, "bench '%s' --out '%s' --shard %d/2", suite, tu_path(dir), s), 0);
        assert_non_null(strstr(err, "9 in this shard"));
        free(err);
    }
    expectf(0, "18 of 18 items", "bench '%s' --out '%s' --merge '%s' '%s'", suite,
            tu_path("merged"), tu_path("shard0"), tu_path("shard1"));
    snprintf(p, sizeof p, "%s/results.csv", tu_path("merged"));
    assert_int_equal(count_lines(p), 19);
    /* One shard alone reports itself incomplete. */
    expectf(0, "9 of 18 items", "bench '%s' --out '%s' --report-only", suite, tu_path("shard0"));
    /* Parallel jobs (forked after nothing threaded ran in the parent), each with two
     * threads: the run finishes and matches the serial one's item count. */
    snprintf(a, sizeof a, "timeout 300 '%s' bench '%s' --out '%s' --jobs 2 --threads 2", LUMIS_CLI,
             suite, tu_path("jobs"));
    char *out = NULL;
    int rc = tu_run(a, &out, &err);
    if (rc != 0) fail_msg("bench --jobs 2: exit %d: %s", rc, err);
    free(out);
    assert_non_null(strstr(err, "18 of 18 items"));
    free(err);
    /* A suite changed under the same labels: its results are stale and redone. */
    size_t slen;
    char *text = (char *)tu_read_file(suite, &slen);
    char *seed = strstr(text, "\"seed\": 1");
    assert_non_null(seed);
    seed[8] = '2';
    tu_write_file(tu_path("smoke2.json"), text, slen);
    free(text);
    snprintf(a, sizeof a, "bench '%s' --out '%s'", tu_path("smoke2.json"), tu_path("b"));
    expect(a, 0, "18 to render");
    /* Malformed suites name the file and the key. */
    static const bad_file bad[] = {
        {"{\"scenes\": [\"spheres\"]}", "maps: expected a non-empty array"},
        {"{\"maps\": [\"sky:8x4\"]}", "scenes: expected a non-empty array"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": []}",
         "methods: expected a non-empty array"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"alias\"}], \"budgets\": {\"spp\": 1}}",
         "budgets: expected a non-empty array"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"magic\"}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].method: unknown method 'magic'"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"alias\"}], \"budgets\": [{\"spp\": 0}]}",
         "budgets[0].spp: expected an integer from 1"},
        {"{\"maps\": [\"nowhere/\"], \"scenes\": [\"spheres\"]}", "nowhere/"},
        /* Malformed JSON: where cJSON gave up, as line:column. */
        {"[1, 2", "bad-suite.json:1:5: malformed JSON"},
        {"{\n  \"maps\": [\"sky:8x4\"],\n  \"scenes\": [\"spheres\" \"x\"]\n}",
         "bad-suite.json:3:24: malformed JSON near '\"x\"]'"},
        {"[1, 2]", "expected a JSON object"},
        /* Well-formed: the JSON path of the culprit. */
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"alias\"}, {\"method\": \"kdtree\", \"budget\": 2}], \"budgets\": [{\"spp\": 1}]}",
         "methods[1].budget: unknown key"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"kdtree\", \"blocks\": \"64\"}], \"budgets\": [{\"spp\": 1}]}",
         "methods[0].blocks: expected a number"},
        {"{\"maps\": [\"sky:8x4\", {\"map\": \"sky:8x4\", \"rotation\": 9}], \"scenes\": "
         "[\"spheres\"]}",
         "maps[1].rotation: unknown key"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"alias\"}], \"budgets\": [{\"spp\": 1}], \"reference\": {\"spp\": 0}}",
         "reference.spp: expected"},
        {"{\"maps\": [\"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": [{\"method\": "
         "\"alias\"}], \"budgets\": [{\"spp\": 1}], \"compare\": [[\"alias\", \"x\"]]}",
         "compare[0][1]: no method labelled 'x'"},
        {"{\"maps\": [\"sky:8x4\", \"sky:8x4\"], \"scenes\": [\"spheres\"], \"methods\": "
         "[{\"method\": \"alias\"}], \"budgets\": [{\"spp\": 1}]}",
         "two maps are labelled 'sky-8x4'"},
    };
    snprintf(a, sizeof a, "--out '%s'", tu_path("bx"));
    expect_bad_files("bench", "bad-suite.json", a, bad, sizeof bad / sizeof bad[0]);
    expect("bench", 2, "needs a SUITE.json");
    snprintf(a, sizeof a, "bench '%s' --shard 3/2", suite);
    expect(a, 2, "--shard needs I/N");
    /* --out is a folder: never an existing file, least of all the suite. */
    expectf(2, "is the suite file", "bench '%s' --out '%s'", tu_path("twice.json"),
            tu_path("twice.json"));
    snprintf(a, sizeof a, "bench '%s' --out '%s'", tu_path("twice.json"), tu_path("m.exr"));
    expect(a, 2, "is not a directory");
    /* The page opens in headless Chromium and renders to a screenshot. */
    FILE *chromium = fopen("/usr/bin/chromium", "rb");
    if (!chromium) {
        printf("chromium not installed (scripts/install-deps.sh --dev installs it): screenshot "
               "skipped\n");
        return;
    }
    fclose(chromium);
    snprintf(a, sizeof a, "bench '%s' --out '%s'", suite, tu_path("b")); /* back to smoke */
    expect(a, 0, NULL);
    snprintf(a, sizeof a,
             "timeout 120 /usr/bin/chromium --headless --no-sandbox --disable-gpu "
             "--hide-scrollbars --window-size=1200,1600 --screenshot='%s' 'file://%s/index.html'",
             tu_path("shot.png"), tu_path("b"));
    rc = tu_run(a, &out, &err);
    if (rc != 0) fail_msg("chromium: exit %d: %s", rc, err);
    free(out);
    free(err);
    size_t shot = 0;
    unsigned char *png = tu_read_file(tu_path("shot.png"), &shot);
    assert_non_null(png);
    assert_true(shot > 20000 && memcmp(png, "\x89PNG", 4) == 0); /* a page, not a blank */
    free(png);
}

/* The text of DIR/NAME (freed by the caller), failing the test when it is missing. */
static char *read_in(const char *dir, const char *name)
{
    char p[4096];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    size_t n = 0;
    char *t = (char *)tu_read_file(p, &n);
    if (!t) fail_msg("%s is missing", p);
    return t;
}

static void expect_in(const char *dir, const char *name, const char *part)
{
    char *t = read_in(dir, name);
    if (!strstr(t, part)) fail_msg("%s/%s lacks \"%s\":\n%s", dir, name, part, t);
    free(t);
}

static void expect_not_in(const char *dir, const char *name, const char *part)
{
    char *t = read_in(dir, name);
    if (strstr(t, part)) fail_msg("%s/%s has \"%s\":\n%s", dir, name, part, t);
    free(t);
}

/* bench --slurm without a Slurm: the scripts it writes, and the task modes its jobs run
 * (each run by hand here, as the tasks would), through a share that fails, a killed task,
 * a damaged result and a damaged reference.  scripts/ci-slurm.sh runs them on a real Slurm. */
static void bench_runs_as_slurm_job_arrays(void **state)
{
    (void)state;
    static const char suite[] =
        "{\"name\": \"cl\", \"maps\": [\"sky:16x8\", \"studio:16x8\"], \"scenes\": "
        "[\"spheres\"], \"methods\": [{\"method\": \"inversion\"}, {\"method\": \"bsdf\", \"mis\": "
        "\"none\"}], \"budgets\": [{\"spp\": 1}, {\"spp\": 4}], \"reference\": {\"spp\": 16}, "
        "\"size\": [8, 4]}";
    tu_write_file(tu_path("cl.json"), suite, strlen(suite));
    char s[1024], a[4096];
    snprintf(s, sizeof s, "bench '%s' --out '%s'", tu_path("cl.json"), tu_path("cl"));
    const char *d = tu_path("cl");
    char sd[1024];
    snprintf(sd, sizeof sd, "%s/slurm", d);
    /* The plan: 2 references in 2 shares each, 3 items tasks (8 items, round robin). */
    expectf(0, "4 reference shares in 2 references, 3 of 3 items tasks (8 of 8 items left)",
            "%s --slurm --no-submit --tasks 3 --reference-passes 2", s);
    expect_in(sd, "submit.sh", "refs=$(job --array=0-3 ");
    expect_in(sd, "submit.sh", "--dependency=afterany:$refs ");
    expect_in(sd, "submit.sh",
              "items=$(job --dependency=afterok:$merge --kill-on-invalid-dep=yes --array=0-2 ");
    expect_in(sd, "submit.sh", "report=$(job --dependency=afterany:$items ");
    expect_in(sd, "items.sbatch", "#SBATCH --cpus-per-task=1\n");
    expect_in(sd, "items.sbatch",
              "--shard \"$SLURM_ARRAY_TASK_ID/3\" --items-only --jobs 1 --threads 1\n");
    expect_in(sd, "references.sbatch",
              "--reference-task \"$SLURM_ARRAY_TASK_ID\" --reference-passes 2 --threads 1\n");
    expect_in(sd, "merge-references.sbatch", "--merge-references --reference-passes 2\n");
    expect_in(sd, "report.sbatch", "--report-only --tasks 3 --reference-passes 2\n");
    expect_in(sd, "resubmit.sh", " --slurm --tasks 3 --reference-passes 2 --cpus 1 ");
    expect_not_in(sd, "items.sbatch", "--exclusive");
    /* Without sbatch on PATH: the scripts are written, and the error says so. */
    snprintf(a, sizeof a, "env PATH=/nowhere '%s' %s --slurm --tasks 3", LUMIS_CLI, s);
    char *out = NULL, *err = NULL;
    assert_int_equal(tu_run(a, &out, &err), 1);
    assert_non_null(strstr(err, "sbatch is not on PATH"));
    free(out);
    free(err);
    /* Items before their references: an error, nothing rendered. */
    expectf(1, "is missing or does not read: render the references first",
            "%s --shard 0/3 --items-only", s);
    /* Three of the four reference shares; the merge joins the complete one and names the
     * missing share of the other. */
    for (int t = 0; t < 3; t++) {
        expectf(0, "of 16 spp ...", "%s --reference-task %d --reference-passes 2", s, t);
    }
    expectf(0, "share 0 of 2 done before", "%s --reference-task 0 --reference-passes 2", s);
    snprintf(a, sizeof a, "%s --merge-references --reference-passes 2", s);
    expect(a, 1, "the reference of studio-16x8 / spheres lacks its shares 1 of 2");
    expect(a, 1, "merged 0 references"); /* sky's is done: not merged again */
    expectf(0, "1 reference share in 1 reference, 3 of 3 items tasks",
            "%s --slurm --no-submit --tasks 3 --reference-passes 2", s);
    expect_in(sd, "submit.sh", "refs=$(job --array=3 ");
    expectf(0, "share 1 of 2 of 16 spp", "%s --reference-task 3 --reference-passes 2", s);
    expectf(0, "studio-16x8 / spheres: merged its 2 shares",
            "%s --merge-references --reference-passes 2", s);
    char parts[1024];
    snprintf(parts, sizeof parts, "%s/refs/parts", d);
    assert_int_equal(tu_count_entries(parts, ".exr"), 0); /* the merged reference has them */
    expectf(0, "done or not needed", "%s --reference-task 0 --reference-passes 2", s);
    /* Two of the three items tasks; the third is "killed": the report job's run lists it
     * and fails. */
    for (int t = 0; t < 2; t++) {
        expectf(0, "done\n", "%s --shard %d/3 --items-only --jobs 1 --threads 1", s, t);
    }
    snprintf(a, sizeof a, "%s --report-only --tasks 3 --reference-passes 2", s);
    expect(a, 1, "items task 2 of 3: 2 of its 2 items not done");
    expect_in(sd, "status.txt", "2 of 8 items not done (1 of 3 items tasks, 0 references)");
    /* Outputs are checked, not only present: a result without its metrics and a reference
     * that does not read are redone. */
    char *r0 = read_in(d, "results/sky-16x8__spheres__inversion__spp1.json");
    char *ref = strstr(r0, "\"reference\":");
    assert_non_null(ref);
    char key[17] = {0}, refpath[1024];
    memcpy(key, strchr(ref + 12, '"') + 1, 16);
    /* the item's own key, its metrics but relMSE (as a writer cut short would leave it) */
    char *rel0 = strstr(r0, "\"relmse\":");
    assert_non_null(rel0);
    rel0[6] = 'X';
    char rp[1024];
    snprintf(rp, sizeof rp, "%s/results/sky-16x8__spheres__inversion__spp1.json", d);
    tu_write_file(rp, r0, strlen(r0));
    free(r0);
    snprintf(refpath, sizeof refpath, "%s/refs/%s.exr", d, key);
    tu_write_file(refpath, "v/1\x01", 4); /* an EXR's magic, and nothing else */
    expectf(0, "2 reference shares in 1 reference, 2 of 3 items tasks (3 of 8 items left)",
            "%s --slurm --no-submit --tasks 3 --reference-passes 2", s);
    expect_in(sd, "submit.sh", "--array=0,2 ");
    expect_in(sd, "submit.sh", "refs=$(job --array=0-1 ");
    for (int t = 0; t < 2; t++) {
        expectf(0, NULL, "%s --reference-task %d --reference-passes 2", s, t);
    }
    expectf(0, "merged 1 reference", "%s --merge-references --reference-passes 2", s);
    for (int t = 0; t < 3; t += 2) {
        expectf(0, NULL, "%s --shard %d/3 --items-only --jobs 1 --threads 1", s, t);
    }
    expectf(0, "all 8 items done", "%s --report-only --tasks 3 --reference-passes 2", s);
    expectf(0, "every item is done: nothing submitted", "%s --slurm --no-submit --tasks 3", s);
    /* The same suite on one machine: the same renders (equal samples are deterministic),
     * and references equal up to float rounding. */
    expectf(0, "8 of 8 items", "bench '%s' --out '%s' --threads 1", tu_path("cl.json"),
            tu_path("cl1"));
    static const char *const ids[] = {"sky-16x8__spheres__inversion__spp4",
                                      "studio-16x8__spheres__bsdf__spp1"};
    for (int k = 0; k < 2; k++) {
        char n[256];
        snprintf(n, sizeof n, "renders/%s.exr", ids[k]);
        size_t la = 0, lb = 0;
        char pa[1024], pb[1024];
        snprintf(pa, sizeof pa, "%s/%s", d, n);
        snprintf(pb, sizeof pb, "%s/%s", tu_path("cl1"), n);
        unsigned char *x = tu_read_file(pa, &la), *y = tu_read_file(pb, &lb);
        assert_true(x && y && la == lb && memcmp(x, y, la) == 0);
        free(x);
        free(y);
    }
    char ra[1024], rb[1024];
    snprintf(ra, sizeof ra, "%s/refs/%s.exr", tu_path("cl1"), key);
    snprintf(rb, sizeof rb, "%s/refs/%s.exr", d, key);
    assert_int_equal(runf(&out, &err, "compare '%s' '%s' --json", ra, rb), 0);
    cJSON *j = cJSON_Parse(out);
    const cJSON *rel = cJSON_GetObjectItemCaseSensitive(j, "relmse");
    assert_true(cJSON_IsNumber(rel) && rel->valuedouble < 1e-10);
    cJSON_Delete(j);
    free(out);
    free(err);
    /* Every sbatch option reaches every job; --sbatch takes its option after '='. */
    snprintf(a, sizeof a,
             "%s --slurm --no-submit --tasks 2 --exclusive --cpus 2 --reference-cpus 4 "
             "--max-running 3 --partition short --time-limit 1:00:00 --sbatch=--account=proj",
             s);
    expect(a, 0, NULL);
    expect_in(sd, "items.sbatch",
              "#SBATCH --cpus-per-task=2\n#SBATCH --exclusive\n"
              "#SBATCH --partition=short\n#SBATCH --time=1:00:00\n"
              "#SBATCH --account=proj\n");
    expect_in(sd, "items.sbatch", "--items-only --jobs 1 --threads 2\n");
    expect_in(sd, "references.sbatch", "#SBATCH --cpus-per-task=4\n#SBATCH --partition=short");
    expect_not_in(sd, "references.sbatch", "--exclusive");
    expect_in(sd, "resubmit.sh",
              "--max-running 3 --exclusive --partition 'short' --time-limit "
              "'1:00:00' '--sbatch=--account=proj'");
    /* Usage errors, before any work. */
    static const char *const usage[][2] = {
        {"--cpus 2", "--cpus: only with --slurm"},
        {"--slurm --shard 0/2", "not with --slurm"},
        {"--slurm --report-only", "one at a time"},
        {"--slurm --sbatch account", "--sbatch=--account=NAME"},
        {"--slurm --reference-passes 0", "--reference-passes needs a count in [1, 1048576]"},
        {"--slurm --reference-passes 17", "more shares than the 16 samples"},
        {"--tasks 2", "--tasks: only with --slurm or --report-only"},
    };
    for (size_t k = 0; k < sizeof usage / sizeof usage[0]; k++) {
        expectf(2, usage[k][1], "%s %s", s, usage[k][0]);
    }
    snprintf(a, sizeof a, "%s --reference-task 4 --reference-passes 2", s);
    expect(a, 1, "tasks 0 to 3");
}

/* The paths below are a test folder's and short: snprintf's bounds are there for safety */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-truncation"
#endif
/* s as one word of sh (the test's own quoting, for the commands it runs). */
static void sh_word(char *buf, size_t cap, const char *s)
{
    size_t n = 0;
    buf[n++] = '\'';
    for (; *s && n + 5 < cap; s++) {
        if (*s == '\'') {
            memcpy(buf + n, "'\\''", 4);
            n += 4;
        } else {
            buf[n++] = *s;
        }
    }
    buf[n++] = '\'';
    buf[n] = '\0';
}

/* The arguments of a script's #SBATCH lines as Slurm's sbatch reads them (its
 * _get_argument: backslash escapes any byte, '...' and "..." quote, an unquoted # ends the
 * line; each line on its own), joined by \036 after each.  NULL if a quote is unmatched. */
static char *sbatch_args(const char *script)
{
    char *out = calloc(strlen(script) * 2 + 2, 1);
    size_t n = 0;
    for (const char *line = script; line && *line;) {
        const char *end = strchr(line, '\n');
        if (!end) end = line + strlen(line);
        if (strncmp(line, "#SBATCH", 7) == 0) {
            const char *p = line + 7;
            for (;;) {
                while (p < end && isspace((unsigned char)*p)) p++;
                if (p >= end || *p == '#') break;
                char q = 0;
                int esc = 0, any = 0;
                while (p < end && (q || !isspace((unsigned char)*p))) {
                    if (esc) {
                        esc = 0;
                    } else if (*p == '\\') {
                        esc = 1;
                        p++;
                        continue;
                    } else if (q) {
                        if (*p == q) {
                            q = 0;
                            p++;
                            continue;
                        }
                    } else if (*p == '"' || *p == '\'') {
                        q = *p++;
                        continue;
                    } else if (*p == '#') {
                        break;
                    }
                    out[n++] = *p++;
                    any = 1;
                }
                if (q) {
                    free(out);
                    return NULL;
                }
                if (any) out[n++] = '\036';
                if (p < end && *p == '#') break;
            }
        }
        line = *end ? end + 1 : NULL;
    }
    return out;
}

/* Whether list (words each ended by \036) holds word. */
static int has_word(const char *list, const char *word)
{
    const size_t n = strlen(word);
    for (const char *p = list; p && *p;) {
        const char *e = strchr(p, '\036');
        if (!e) break;
        if ((size_t)(e - p) == n && memcmp(p, word, n) == 0) return 1;
        p = e + 1;
    }
    return 0;
}

/* bench --slurm with hostile values (the output folder, the partition, the time limit,
 * --sbatch options): every value written into a script is quoted for its context (a word
 * of sh; an #SBATCH line, which is not one; a Slurm filename pattern) or refused with a
 * message naming it.  Each accepted script passes sh -n, its #SBATCH lines read back (as
 * Slurm reads them) as the values given, and run with a stub sbatch and lumis' exec
 * recorded: the arguments arrive whole, and nothing else runs (no file PWNED appears). */
static void slurm_scripts_survive_hostile_names(void **state)
{
    (void)state;
    static const char suite[] =
        "{\"name\": \"ho\", \"maps\": [\"sky:16x8\"], \"scenes\": [\"spheres\"], \"methods\": "
        "[{\"method\": \"inversion\"}], \"budgets\": [{\"spp\": 1}], \"reference\": {\"spp\": 2}, "
        "\"size\": [8, 4]}";
    char root[8192], a[65536], w[8192], w2[8192], w3[8192], p[8192];
    snprintf(root, sizeof root, "%s/hostile", tu_tmpdir());
    mkdir(root, 0755);
    /* stubs: sbatch records its arguments and answers a job id; REC records exec's */
    char stubs[8192], log[8192], rec[8192];
    snprintf(stubs, sizeof stubs, "%s/stubs", root);
    mkdir(stubs, 0755);
    snprintf(log, sizeof log, "%s/sbatch.log", root);
    snprintf(rec, sizeof rec, "%s/stubs/rec", root);
    static const char record[] = "#!/bin/sh\nfor a; do printf '%s\\037' \"$a\"; done >> \"$LOG\"\n"
                                 "printf '\\036' >> \"$LOG\"\necho 42\n";
    snprintf(p, sizeof p, "%s/sbatch", stubs);
    tu_write_file(p, record, strlen(record));
    chmod(p, 0755);
    snprintf(p, sizeof p, "%s/srun", stubs);
    tu_write_file(p, record, strlen(record));
    chmod(p, 0755);
    tu_write_file(rec, record, strlen(record));
    chmod(rec, 0755);
    static const char *const hostile[] = {
        "nl\nid > PWNED\n#",
        "cr\rtouch PWNED",
        "$(touch PWNED)",
        "`touch PWNED`",
        "qu'ote",
        "dq\"uote",
        "back\\slash",
        "semi;touch PWNED",
        "ha#sh",
        "pct%A%j%%x",
        "-lead",
        "sp ace  x",
        "bytes\xff\xfe\x80",
        "tab\tx",
        "amp&touch PWNED&",
        "gt>PWNED",
    };
    const size_t nh = sizeof hostile / sizeof *hostile;
    /* where each value goes: the folder (--out), --partition, --time-limit, --sbatch= */
    for (int where = 0; where < 4; where++)
        for (size_t k = 0; k < nh; k++) {
            const char *v = hostile[k];
            char out[8192], rel[8192], opt[8192] = "", spath[8192];
            if (where == 0) /* a folder and a suite named so, given relative to root */
                snprintf(rel, sizeof rel, "%s", v);
            else
                snprintf(rel, sizeof rel, "o%d-%zu", where, k);
            snprintf(out, sizeof out, "%s/%s", root, rel);
            snprintf(spath, sizeof spath, "%s/%s.json", root, rel);
            tu_write_file(spath, suite, strlen(suite));
            snprintf(spath, sizeof spath, "./%s.json", rel);
            char value[8192];
            if (where == 3)
                snprintf(value, sizeof value, "--comment=%s", v);
            else
                snprintf(value, sizeof value, "%s", v);
            if (where == 1) {
                sh_word(w, sizeof w, value);
                snprintf(opt, sizeof opt, "--partition %s", w);
            } else if (where == 2) {
                sh_word(w, sizeof w, value);
                snprintf(opt, sizeof opt, "--time-limit %s", w);
            } else if (where == 3) {
                char o2[8192];
                snprintf(o2, sizeof o2, "--sbatch=%s", value);
                sh_word(w, sizeof w, o2);
                snprintf(opt, sizeof opt, "%s", w);
            }
            mkdir(out, 0755);
            sh_word(w, sizeof w, spath);
            sh_word(w2, sizeof w2, rel);
            sh_word(w3, sizeof w3, root);
            snprintf(a, sizeof a,
                     "cd %s && '%s' bench %s --out %s --slurm --no-submit --tasks 1 %s", w3,
                     LUMIS_CLI, w, w2, opt);
            char *e = NULL;
            const int rc = tu_run(a, NULL, &e);
            const int control = strpbrk(v, "\n\r\t") != NULL;
            if (rc == 2) { /* refused: it must say which value, and why */
                if (!control && !(where == 0 && strchr(v, '\\')))
                    fail_msg("bench --slurm refused %d '%s': %s", where, v, e);
                if (!strstr(e, where == 0   ? "--out"
                               : where == 1 ? "--partition"
                               : where == 2 ? "--time-limit"
                                            : "--sbatch"))
                    fail_msg("the refusal of '%s' does not name its option: %s", v, e);
                free(e);
                continue;
            }
            if (rc != 0) fail_msg("bench --slurm with '%s' (%d): exit %d: %s", v, where, rc, e);
            free(e);
            char real[8192];
            size_t ln = 0;
            assert_non_null(realpath(out, real));
            static const char *const scripts[] = {"references.sbatch", "merge-references.sbatch",
                                                  "items.sbatch",      "report.sbatch",
                                                  "submit.sh",         "resubmit.sh"};
            for (int q = 0; q < 6; q++) {
                char sp[8192];
                snprintf(sp, sizeof sp, "%s/slurm/%s", real, scripts[q]);
                sh_word(w, sizeof w, sp);
                snprintf(a, sizeof a, "sh -n %s", w);
                if (tu_run(a, NULL, &e) != 0) fail_msg("sh -n %s: %s", sp, e);
                free(e);
                if (q >= 4) continue;
                /* run, its exec recorded: lumis gets the suite and the folder whole */
                char *text = (char *)tu_read_file(sp, &ln);
                char copy[8192];
                snprintf(copy, sizeof copy, "%s/run.sh", root);
                char *ex = strstr(text, "\nexec ");
                assert_non_null(ex);
                const size_t head = (size_t)(ex - text) + 1;
                FILE *f = fopen(copy, "wb");
                fwrite(text, 1, head, f);
                fprintf(f, "\"$REC\" %s", ex + 6);
                fclose(f);
                unlink(log);
                sh_word(w, sizeof w, root);
                sh_word(w2, sizeof w2, log);
                sh_word(w3, sizeof w3, rec);
                snprintf(a, sizeof a,
                         "cd %s && LOG=%s REC=%s SLURM_ARRAY_TASK_ID=0 SLURM_JOB_ID=7 sh run.sh", w,
                         w2, w3);
                const int src = tu_run(a, NULL, &e);
                snprintf(p, sizeof p, "%s/PWNED", root);
                if (access(p, F_OK) == 0)
                    fail_msg("%s ('%s', %d) ran a command: PWNED written", sp, v, where);
                if (src != 0) fail_msg("%s: %s", sp, e);
                free(e);
                char *got = (char *)tu_read_file(log, &ln);
                assert_non_null(got);
                char want[8192], lumis_real[8192], suite_real[8192];
                assert_non_null(realpath(LUMIS_CLI, lumis_real));
                snprintf(p, sizeof p, "%s/%s.json", root, rel);
                assert_non_null(realpath(p, suite_real));
                snprintf(want, sizeof want, "%s\037bench\037%s\037--out\037%s\037", lumis_real,
                         suite_real, real);
                if (strncmp(got, want, strlen(want)) != 0)
                    fail_msg("%s: exec got\n%s\nnot\n%s", sp, got, want);
                /* the #SBATCH lines as Slurm reads them */
                free(got);
                char *args = sbatch_args(text);
                if (!args) fail_msg("%s: an unmatched quote in an #SBATCH line", sp);
                char pat[8192];
                size_t m = 0;
                for (const char *c = real; *c && m + 3 < sizeof pat; c++) { /* % is %% there */
                    pat[m++] = *c;
                    if (*c == '%') pat[m++] = '%';
                }
                pat[m] = '\0';
                static const char *const job[] = {"references", "merge-references", "items",
                                                  "report"};
                snprintf(want, sizeof want, "--output=%s/slurm/logs/%s-%s.out", pat, job[q],
                         q == 0 || q == 2 ? "%A_%a" : "%j");
                if (!has_word(args, want)) fail_msg("%s: no #SBATCH %s in\n%s", sp, want, text);
                if (where == 1) snprintf(want, sizeof want, "--partition=%s", value);
                if (where == 2) snprintf(want, sizeof want, "--time=%s", value);
                if (where == 3) snprintf(want, sizeof want, "%s", value);
                if (where > 0 && !has_word(args, want))
                    fail_msg("%s: no #SBATCH %s in\n%s", sp, want, text);
                int nargs = 0;
                for (const char *c = args; *c; c++) nargs += *c == '\036';
                if (nargs != 4 + (where > 0)) /* name, output, ntasks, cpus, the value */
                    fail_msg("%s: %d #SBATCH arguments:\n%s", sp, nargs, text);
                free(args);
                free(text);
            }
            /* submit.sh with a stub sbatch: four jobs, each its script's path whole */
            unlink(log);
            char sub[8192];
            snprintf(sub, sizeof sub, "%s/slurm/submit.sh", real);
            sh_word(w, sizeof w, root);
            sh_word(w2, sizeof w2, log);
            sh_word(w3, sizeof w3, stubs);
            char w4[8192];
            sh_word(w4, sizeof w4, sub);
            snprintf(a, sizeof a, "cd %s && LOG=%s PATH=%s:\"$PATH\" sh %s", w, w2, w3, w4);
            if (tu_run(a, NULL, &e) != 0) fail_msg("%s: %s", sub, e);
            free(e);
            char *got = (char *)tu_read_file(log, &ln);
            assert_non_null(got);
            static const char *const jobs[] = {"references", "merge-references", "items", "report"};
            const char *c = got;
            for (int q = 0; q < 4; q++) {
                char want[8192];
                snprintf(want, sizeof want, "\037%s/slurm/%s.sbatch\037\036", real, jobs[q]);
                const char *hit = strstr(c, want);
                if (!hit)
                    fail_msg("%s: sbatch did not get %s.sbatch whole:\n%s", sub, jobs[q], got);
                c = hit + strlen(want);
            }
            if (*c) fail_msg("%s: more than four sbatch calls:\n%s", sub, got);
            free(got);
            /* resubmit.sh: the same command again (submitting through the stub) */
            snprintf(sub, sizeof sub, "%s/slurm/resubmit.sh", real);
            sh_word(w4, sizeof w4, sub);
            unlink(log);
            snprintf(a, sizeof a, "cd %s && LOG=%s PATH=%s:\"$PATH\" sh %s", w, w2, w3, w4);
            if (tu_run(a, NULL, &e) != 0) fail_msg("%s: %s", sub, e);
            if (!strstr(e, "submitted")) fail_msg("%s: %s", sub, e);
            free(e);
            snprintf(p, sizeof p, "%s/PWNED", root);
            if (access(p, F_OK) == 0) fail_msg("'%s' (%d) ran a command: PWNED written", v, where);
            if (control) fail_msg("a control character was written into a script: '%s'", v);
        }
    snprintf(a, sizeof a, "find '%s' -name PWNED | grep -q . && exit 1; exit 0", tu_tmpdir());
    char *e = NULL;
    if (tu_run(a, NULL, &e) != 0) fail_msg("a hostile name ran a command: PWNED was written");
    free(e);
}

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

/* lumis info on photometric files: the fixture, the flux against the file's lumens, the
 * beam angles, JSON, the polar plot; errors name the line; outputs never replace inputs. */
static void info_reads_photometric_files(void **state)
{
    (void)state;
    pg_ies_spec s = {PG_SPOT, 10, "IESNA:LM-63-2002", 1, 91, 0, 90, 1, 0, 0, 0, 0, -0.1, -0.1,
                     0,       2};
    size_t n = 0;
    char *text = pg_ies(&s, &n);
    tu_write_file(tu_path("spot.ies"), text, n);
    free(text);
    char a[4096], *out = NULL, *err = NULL;
    snprintf(a, sizeof a, "info '%s' --svg '%s'", tu_path("spot.ies"), tu_path("spot.svg"));
    assert_int_equal(run(a, &out, &err), 0);
    /* 2 pi 1000 / 11 = 571.2 lm analytically; the 1-degree table's interpolant 571.34 */
    const char *parts[] = {"photometric type C, symmetry rotational", "fixture: lumis tests",
                           "flux: 571.3", "lamp lumens: 1000 lm\n",
                           "C0-C180: beam angle (50 %) 42.", "luminous shape: disk, width 0.1 m",
                           "downward: 100.0 %",
                           /* the ratings: flux / 1000 lm, flux / 50 W, a 74.8 deg field; N1 =
                              100 (1 - 0.75^11) = 95.8; the zones 227 lm on each side below 30
                              deg (B1), nothing above 80 (G0) or 90 (U0) */
                           "light output ratio: 57.1 %\n", "efficacy: 11.4 lm/W at 50 W",
                           "field angle (10 %) 74.8 deg, NEMA 5",
                           "zonal lumens: 0-30 453.8, 30-60 117.2, 60-90 0.3, 90-120 0.0",
                           "CIE flux code: 96 100 100 100 57", "BUG rating (TM-15-11): B1 U0 G0",
                           "lm back BL 226.9 BM 58.6",
                           /* cos^10: 2 (2^(2/13) - 1)^(1/2) = 0.671 */
                           "spacing criterion (spacing / mounting height): C0-C180 0.67, "
                           "C90-C270 0.67\n"};
    for (int k = 0; k < (int)(sizeof parts / sizeof parts[0]); k++)
        if (!strstr(out, parts[k])) fail_msg("info lacks \"%s\":\n%s", parts[k], out);
    free(out);
    free(err);
    size_t svg_n = 0;
    char *svg = (char *)tu_read_file(tu_path("spot.svg"), &svg_n);
    assert_non_null(svg);
    assert_non_null(strstr(svg, "<svg"));
    assert_non_null(strstr(svg, "C0-C180: beam 42."));
    assert_int_equal((int)(strstr(svg, "<polyline") != NULL), 1);
    free(svg);
    /* a title with markup's special characters stays text */
    size_t tn = 0;
    char *spot = (char *)tu_read_file(tu_path("spot.ies"), &tn);
    char *lum = strstr(spot, "[LUMINAIRE] analytic");
    assert_non_null(lum);
    memcpy(lum + 12, "a<b&c\"d", 8);
    tu_write_file(tu_path("markup.ies"), spot, tn);
    free(spot);
    expectf(0, NULL, "info '%s' --svg '%s'", tu_path("markup.ies"), tu_path("markup.svg"));
    svg = (char *)tu_read_file(tu_path("markup.svg"), &svg_n);
    assert_non_null(strstr(svg, ">a&lt;b&amp;c&quot;d"));
    free(svg);
    snprintf(a, sizeof a, "info '%s' --json", tu_path("spot.ies"));
    assert_int_equal(run(a, &out, &err), 0);
    cJSON *j = cJSON_Parse(out);
    assert_non_null(j);
    const cJSON *flux = cJSON_GetObjectItemCaseSensitive(j, "flux");
    assert_true(cJSON_IsNumber(flux) && fabs(flux->valuedouble - 571.3) < 0.1);
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(j, "symmetry")->valuestring, "rotational");
    const cJSON *lor = cJSON_GetObjectItemCaseSensitive(j, "light_output_ratio");
    assert_true(cJSON_IsNumber(lor) && fabs(lor->valuedouble * 1000 - flux->valuedouble) < 1e-9);
    const cJSON *eff = cJSON_GetObjectItemCaseSensitive(j, "efficacy_lm_per_w");
    assert_true(cJSON_IsNumber(eff) && fabs(eff->valuedouble * 50 - flux->valuedouble) < 1e-9);
    const cJSON *code = cJSON_GetObjectItemCaseSensitive(j, "cie_flux_code");
    assert_true(cJSON_IsArray(code) && cJSON_GetArraySize(code) == 5);
    assert_int_equal(cJSON_GetArrayItem(code, 0)->valueint, 96);
    const cJSON *zonal = cJSON_GetObjectItemCaseSensitive(j, "zonal_lm");
    assert_true(cJSON_IsArray(zonal) && cJSON_GetArraySize(zonal) == 6);
    double zsum = 0;
    for (int k = 0; k < 6; k++) zsum += cJSON_GetArrayItem(zonal, k)->valuedouble;
    assert_true(fabs(zsum - flux->valuedouble) < 1e-9 * flux->valuedouble);
    const cJSON *bug = cJSON_GetObjectItemCaseSensitive(j, "bug");
    assert_int_equal(cJSON_GetObjectItemCaseSensitive(bug, "B")->valueint, 1);
    assert_int_equal(cJSON_GetObjectItemCaseSensitive(bug, "G")->valueint, 0);
    const cJSON *zl = cJSON_GetObjectItemCaseSensitive(bug, "zones_lm");
    assert_true(fabs(cJSON_GetObjectItemCaseSensitive(zl, "FL")->valuedouble - 226.9) < 0.1);
    const cJSON *nema = cJSON_GetObjectItemCaseSensitive(j, "nema_type");
    assert_int_equal(cJSON_GetArrayItem(nema, 1)->valueint, 5);
    const cJSON *sc = cJSON_GetObjectItemCaseSensitive(j, "spacing_criterion");
    assert_true(cJSON_IsArray(sc) && cJSON_GetArraySize(sc) == 2);
    for (int k = 0; k < 2; k++)
        assert_true(fabs(cJSON_GetArrayItem(sc, k)->valuedouble - 0.6709) < 1e-3);
    assert_true(
        cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(j, "spacing_criterion_not_applicable")));
    cJSON_Delete(j);
    free(out);
    free(err);
    /* a title longer than the plot is wide wraps onto a second line, still escaped, and
     * ends in an ellipsis; the plot moves down to make room */
    char *spot2 = (char *)tu_read_file(tu_path("spot.ies"), &tn);
    lum = strstr(spot2, "[MORE] continued here");
    assert_non_null(lum);
    char longer[8192];
    snprintf(longer, sizeof longer, "%.*s[MORE] %s%s", (int)(lum - spot2), spot2,
             "with a very long description of its optics & housing, as manufacturers write "
             "them, spread over several [MORE] lines that no plot title can hold whole",
             lum + strlen("[MORE] continued here"));
    free(spot2);
    tu_write_file(tu_path("long.ies"), longer, strlen(longer));
    snprintf(a, sizeof a, "info '%s' --svg '%s'", tu_path("long.ies"), tu_path("long.svg"));
    expect(a, 0, NULL);
    svg = (char *)tu_read_file(tu_path("long.svg"), &svg_n);
    assert_non_null(strstr(svg, "height=\"556\""));
    const char *l1 = strstr(svg, "<text x=\"10\" y=\"18\" font-size=\"13\">");
    const char *l2 = strstr(svg, "<text x=\"10\" y=\"34\" font-size=\"13\">");
    assert_non_null(l1);
    assert_non_null(l2);
    l1 = strchr(l1, '>') + 1;
    l2 = strchr(l2, '>') + 1;
    const char *e1 = strstr(l1, "</text>"), *e2 = strstr(l2, "</text>");
    /* 68 characters, broken at a space */
    const char *want1 = "analytic 1 with a very long description of its optics &amp; housing, as";
    assert_true(e1 - l1 == (long)strlen(want1) && strncmp(l1, want1, strlen(want1)) == 0);
    assert_true(e2 - l2 <= 67 + 3 && strncmp(e2 - 3, "…", 3) == 0);
    assert_null(strstr(svg, "hold whole"));
    free(svg);
    /* EULUMDAT: the luminaire flux (lamps x LOR) is the file's own */
    text = pg_ldt(PG_LAMBERT, 0, 2, 24, 37, 2, &n);
    tu_write_file(tu_path("down.LDT"), text, n);
    free(text);
    snprintf(a, sizeof a, "info '%s'", tu_path("down.LDT"));
    assert_int_equal(run(a, &out, &err), 0);
    assert_non_null(strstr(out, "EULUMDAT, photometric type C, symmetry C0-C180"));
    assert_non_null(strstr(out, "luminaire flux (lamps x LOR): 800 lm"));
    assert_non_null(strstr(out, "efficacy:")); /* EULUMDAT's lamp set watts */
    /* the generator's 1000 cd at nadir per 1000 lamp lumens: pi x 1000 lm from the table */
    assert_non_null(strstr(out, "light output ratio: 314.0 %"));
    free(out);
    free(err);
    /* a floodlight (type B): its light lies in front, whichever way it is aimed; no zones
     * or ratings of type C's */
    pg_ies_spec fl = {PG_AIMED, 0, "IESNA:LM-63-2002", 2, 37, -90, 90, 37, -90, 90, 1, 0, 0, 0,
                      0,        2};
    text = pg_ies(&fl, &n);
    tu_write_file(tu_path("flood.ies"), text, n);
    free(text);
    assert_int_equal(runf(&out, &err, "info '%s'", tu_path("flood.ies")), 0);
    assert_non_null(strstr(out, "front: 100.0 % of the flux"));
    assert_null(strstr(out, "downward"));
    assert_null(strstr(out, "BUG"));
    assert_non_null(strstr(out, "V=0 (H): beam angle"));
    assert_non_null(strstr(out, ", NEMA 7"));
    assert_non_null(strstr(out, "spacing criterion: not applicable, a floodlight"));
    free(out);
    free(err);
    snprintf(a, sizeof a, "info '%s' --json", tu_path("flood.ies"));
    assert_int_equal(run(a, &out, &err), 0);
    j = cJSON_Parse(out);
    assert_non_null(j);
    sc = cJSON_GetObjectItemCaseSensitive(j, "spacing_criterion");
    assert_true(cJSON_IsNull(cJSON_GetArrayItem(sc, 0)) && cJSON_IsNull(cJSON_GetArrayItem(sc, 1)));
    assert_true(
        cJSON_IsString(cJSON_GetObjectItemCaseSensitive(j, "spacing_criterion_not_applicable")));
    cJSON_Delete(j);
    free(out);
    free(err);
    /* errors: the line and the field; the plot never replaces the file */
    tu_write_file(tu_path("bad.ies"),
                  "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 2 1 1 2 0 0 0\n1 1 0\n0 -5\n", 61);
    expectf(1, "bad.ies:5: the vertical angles: -5 after 0", "info '%s'", tu_path("bad.ies"));
    expectf(2, NULL, "info '%s' --svg '%s'", tu_path("spot.ies"), tu_path("spot.ies"));
    expectf(2, "--svg: only for a photometric file", "info '%s' --svg '%s'",
            LUMIS_SOURCE_DIR "/tests/data/grey-y.exr", tu_path("x.svg"));
    /* luminaire create --from: the opening's light field, read back; its errors */
    snprintf(a, sizeof a, "luminaire create '%s' --from '%s' --grid 5x5 --size 32x32 --delta 0.1",
             tu_path("spot-lf.json"), tu_path("spot.ies"));
    expect(a, 0, "5 x 5 images of "); /* --size is about: whole pixels per basis spacing */
    expect(a, 0, "is the far-field point (lumis_photometric_beyond); together ");
    expect(a, 0, "lumis: far-field error ");
    /* the manifest records what the field carries and the error it reached */
    {
        size_t mn = 0;
        char *mt = (char *)tu_read_file(tu_path("spot-lf.json"), &mn);
        cJSON *mj = mt ? cJSON_ParseWithLength(mt, mn) : NULL;
        const cJSON *ph = cJSON_GetObjectItemCaseSensitive(mj, "photometric");
        const cJSON *res = cJSON_GetObjectItemCaseSensitive(ph, "residual");
        const cJSON *lf = cJSON_GetObjectItemCaseSensitive(ph, "light_field_lm");
        const cJSON *rf = cJSON_GetObjectItemCaseSensitive(res, "flux_lm");
        const cJSON *fe = cJSON_GetObjectItemCaseSensitive(ph, "far_field_error");
        assert_true(cJSON_IsNumber(lf) && cJSON_IsNumber(rf) && cJSON_IsNumber(fe));
        assert_true(fabs((lf->valuedouble + rf->valuedouble) / 571.34 - 1) < 1e-3);
        /* and where a near-field fixture hands over to the point model: an ordered pair of
         * distances around the crossover, in metres (the opening's size times sizes) */
        const cJSON *nf = cJSON_GetObjectItemCaseSensitive(ph, "near_field");
        const double sz = cJSON_GetNumberValue(
                         cJSON_GetObjectItemCaseSensitive(nf, "opening_size_m")),
                     cx = cJSON_GetNumberValue(
                         cJSON_GetObjectItemCaseSensitive(nf, "crossover_sizes")),
                     nu =
                         cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(nf, "near_until_m")),
                     ff = cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(nf, "far_from_m"));
        assert_true(sz > 0 && cx > 0 && nu > 0 && nu <= cx * sz && cx * sz <= ff);
        expect(a, 0, "lumis: the field beats the point model out to ");
        cJSON_Delete(mj);
        free(mt);
    }
    snprintf(a, sizeof a, "luminaire info '%s' --json", tu_path("spot-lf.json"));
    assert_int_equal(run(a, &out, &err), 0);
    j = cJSON_Parse(out);
    const cJSON *tp = cJSON_GetObjectItemCaseSensitive(j, "total_power");
    /* the table's flux, all of it within the images' 99.9 % cone */
    assert_true(cJSON_IsNumber(tp) && fabs(tp->valuedouble / 571.34 - 1) < 2e-3);
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(j, "units")->valuestring, "m");
    cJSON_Delete(j);
    free(out);
    free(err);
    /* auto in bands of distance: a floor under the spot far away, a plate near it.  Each
     * point takes its band's strategy with the same numbers, so every pixel equals, bit for
     * bit, the same pixel of a render with one of the bands' strategies (but pixels whose
     * samples straddle the edge). */
    static const char bands_scene[] =
        "{\"camera\": {\"eye\": [2.0, 1.5, 2.5], \"look_at\": [0, -2.0, 0], "
        "\"fov_deg\": 70, \"width\": 64, \"height\": 40},\n"
        " \"objects\": [{\"type\": \"plane\", \"point\": [0.3, -0.2, 0], \"normal\": "
        "[0, 1, 0], \"size\": 0.4, \"material\": {\"type\": \"lambert\", \"albedo\": "
        "[0.7, 0.7, 0.7]}},\n"
        "  {\"type\": \"plane\", \"point\": [0, -8, 0], \"normal\": [0, 1, 0], \"size\": "
        "40, \"material\": {\"type\": \"lambert\", \"albedo\": [0.7, 0.7, 0.7]}}],\n"
        " \"luminaires\": [{\"file\": \"spot-lf.json\", \"transform\": {\"rotate_deg\": "
        "[90, 0, 0]}}]}\n";
    tu_write_file(tu_path("bands.json"), bands_scene, strlen(bands_scene));
    const char *band_runs[3][2] = {{"auto --lum-auto-bands", "bands-auto.exr"},
                                   {"restricted", "bands-r.exr"},
                                   {"uniform", "bands-u.exr"}};
    lumis_image *bimg[3] = {NULL, NULL, NULL};
    for (int k = 0; k < 3; k++) {
        expectf(0, k == 0 ? "auto: restricted to " : NULL,
                "render '%s' --sequence pcg --spp 2 --lum-strategy %s -o '%s'",
                tu_path("bands.json"), band_runs[k][0], tu_path(band_runs[k][1]));
        assert_int_equal(lumis_image_read(tu_path(band_runs[k][1]), NULL, &bimg[k], NULL),
                         LUMIS_OK);
    }
    int same[2] = {0, 0}, lit = 0;
    for (int q = 0; q < bimg[0]->width * bimg[0]->height; q++) {
        const float *p0 = bimg[0]->pixels + 3 * q;
        if (!(p0[0] + p0[1] + p0[2] > 0.0f)) continue;
        lit++;
        for (int k = 0; k < 2; k++)
            same[k] += !memcmp(p0, bimg[k + 1]->pixels + 3 * q, 3 * sizeof(float));
    }
    printf("bands: %d lit pixels, %d as restricted, %d as uniform\n", lit, same[0], same[1]);
    assert_true(same[0] > 0 && same[1] > 0 && same[0] + same[1] >= 0.95 * lit);
    for (int k = 0; k < 3; k++) lumis_image_destroy(bimg[k]);
    cJSON *bj = read_json("bands-auto.json");
    const cJSON *bl = item(bj, "luminaires");
    assert_string_equal(cJSON_GetStringValue(item(bl, "chosen_budgets")), "32+32");
    assert_true(num(bl, "band_gain") > 1.1);
    cJSON_Delete(bj);
    expectf(2, "--from and --preset: one or the other",
            "luminaire create '%s' --from '%s' --preset car", tu_path("y.json"),
            tu_path("spot.ies"));
    expectf(2, "only with --from", "luminaire create '%s' --grid 3x3", tu_path("y.json"));
    expectf(2, "--max-angle", "luminaire create '%s' --from '%s' --max-angle 95", tu_path("y.json"),
            tu_path("spot.ies"));
    pg_ies_spec pt = {PG_SPOT, 10, "IESNA:LM-63-2002", 1, 10, 0, 90, 1, 0, 0, 0, 0, 0, 0, 0, 2};
    text = pg_ies(&pt, &n);
    tu_write_file(tu_path("point.ies"), text, n);
    free(text);
    snprintf(a, sizeof a, "luminaire create '%s' --from '%s'", tu_path("y.json"),
             tu_path("point.ies"));
    expect(a, 1, "the file's luminous shape is \"point\"");
}

/* Scene files place photometric fixtures: rendered, recorded in the sidecar, their files
 * inputs no output may replace; every malformed entry named by its JSON path. */
static void render_places_photometric_fixtures(void **state)
{
    (void)state;
    pg_ies_spec s = {PG_SPOT, 4, "IESNA:LM-63-2002", 1, 46, 0, 90, 1, 0, 0, 0, 0, -0.2, -0.2, 0, 2};
    size_t n = 0;
    char *text = pg_ies(&s, &n);
    tu_write_file(tu_path("fx.ies"), text, n);
    free(text);
    static const char scene[] =
        "{\"camera\": {\"eye\": [0, 3, 4], \"look_at\": [0, 0, 0], \"width\": 24, \"height\": 16},"
        " \"environment\": {\"map\": \"sky:16x8\"},"
        " \"objects\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], "
        "\"size\": 10,"
        " \"material\": {\"type\": \"lambert\", \"albedo\": [0.5, 0.5, 0.5]}}],"
        " \"photometric\": [{\"file\": \"fx.ies\", \"position\": [0, 2, 0]},"
        " {\"file\": \"fx.ies\", \"position\": [1, 2, 0], \"aim\": [2, 0, 0], \"up\": [0, 0, 1],"
        " \"multiplier\": 0.5, \"area\": true}]}";
    tu_write_file(tu_path("fx.json"), scene, strlen(scene));
    char a[4096], *out = NULL, *err = NULL;
    /* -o fx.exr: its sidecar fx.json would replace the scene: refused before any work */
    expectf(2, NULL, "render '%s' --spp 2 -o '%s'", tu_path("fx.json"), tu_path("fx.exr"));
    assert_int_equal(
        runf(&out, &err, "render '%s' --spp 2 -o '%s'", tu_path("fx.json"), tu_path("lit.exr")), 0);
    assert_non_null(strstr(err, "the scene's environment (sky:16x8) is ignored"));
    assert_non_null(strstr(err, "2 photometric fixtures"));
    free(out);
    free(err);
    size_t sn = 0;
    char *side;
    side = (char *)tu_read_file(tu_path("lit.json"), &sn);
    assert_non_null(side);
    cJSON *j = cJSON_Parse(side);
    free(side);
    const cJSON *fx = cJSON_GetObjectItemCaseSensitive(j, "photometric");
    assert_true(cJSON_IsArray(fx) && cJSON_GetArraySize(fx) == 2);
    assert_string_equal(
        cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(fx, 1), "model")->valuestring,
        "opening");
    { /* "up" perpendicular to the aim is the fixture's local +x (the rotation's first column) */
        const cJSON *r = cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(fx, 1), "rotation");
        assert_true(fabs(cJSON_GetArrayItem(r, 0)->valuedouble) < 1e-6 &&
                    fabs(cJSON_GetArrayItem(r, 3)->valuedouble) < 1e-6 &&
                    fabs(cJSON_GetArrayItem(r, 6)->valuedouble - 1) < 1e-6);
    }
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(j, "method")->valuestring, "photometric");
    assert_true(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(j, "photometric_files")) == 1);
    cJSON_Delete(j);
    /* the image is lit, and --env does not apply */
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_read(tu_path("lit.exr"), NULL, &img, NULL), LUMIS_OK);
    double sum = 0;
    for (int k = 0; k < 3 * img->width * img->height; k++) sum += img->pixels[k];
    assert_true(sum > 0);
    lumis_image_destroy(img);
    expectf(2, "lighting.env: does not apply: the scene is lit by photometric fixtures",
            "render '%s' --env sky -o '%s'", tu_path("fx.json"), tu_path("x.exr"));
    snprintf(a, sizeof a, "render '%s' -o '%s'", tu_path("fx.json"), tu_path("fx.ies"));
    expect(a, 2, NULL);
    /* --fixture: one fixture lights a built-in scene instead of its map */
    snprintf(a, sizeof a,
             "render --scene spheres --fixture '%s' --fixture-at 0,3,1 --fixture-aim 0,0,0 "
             "--fixture-multiplier 2 --fixture-area --size 16x12 --spp 2 -o '%s'",
             tu_path("fx.ies"), tu_path("cli.exr"));
    expect(a, 0, "1 photometric fixture");
    side = (char *)tu_read_file(tu_path("cli.json"), &sn);
    assert_non_null(side);
    j = cJSON_Parse(side);
    free(side);
    fx = cJSON_GetObjectItemCaseSensitive(j, "photometric");
    assert_true(cJSON_IsArray(fx) && cJSON_GetArraySize(fx) == 1);
    const cJSON *e0 = cJSON_GetArrayItem(fx, 0);
    assert_true(cJSON_GetObjectItemCaseSensitive(e0, "multiplier")->valuedouble == 2.0);
    assert_string_equal(cJSON_GetObjectItemCaseSensitive(e0, "model")->valuestring, "opening");
    { /* type C aimed at (0, -3, -1): C0 stays +x (tilted from hanging towards -z) */
        const cJSON *r = cJSON_GetObjectItemCaseSensitive(e0, "rotation");
        assert_true(fabs(cJSON_GetArrayItem(r, 0)->valuedouble - 1) < 1e-6);
    }
    assert_string_equal(
        cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "photometric_files"), 0)
            ->valuestring,
        tu_path("fx.ies"));
    cJSON_Delete(j);
    { /* --fixture-near-field: its light field made as the render starts, the sidecar says
       * where it hands over to the table; everything in the scene lies beyond far_from, so
       * the image is the point fixture's bit for bit.  With --fixture-area: the library's
       * refusal, naming the field */
        snprintf(a, sizeof a,
                 "render --scene spheres --fixture '%s' --fixture-at 0,3,1 --fixture-aim 0,0,0 "
                 "--size 16x12 --spp 2 --seed 3 --quiet -o '%s'",
                 tu_path("fx.ies"), tu_path("pt.exr"));
        expect(a, 0, NULL);
        snprintf(a, sizeof a,
                 "render --scene spheres --fixture '%s' --fixture-at 0,3,1 --fixture-aim 0,0,0 "
                 "--fixture-near-field --size 16x12 --spp 2 --seed 3 -o '%s'",
                 tu_path("fx.ies"), tu_path("nf.exr"));
        expect(a, 0, "lumis: near-field fixture: its light field up to ");
        side = (char *)tu_read_file(tu_path("nf.json"), &sn);
        j = cJSON_Parse(side);
        free(side);
        const cJSON *n0 = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "photometric"), 0);
        assert_string_equal(cJSON_GetObjectItemCaseSensitive(n0, "model")->valuestring,
                            "near-field");
        const double far = cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(
            cJSON_GetObjectItemCaseSensitive(n0, "near_field"), "far_from_m"));
        assert_true(far > 0 && far < 1.0); /* the nearest sphere is over 1 m away */
        cJSON_Delete(j);
        lumis_image *pt = NULL, *nf = NULL;
        assert_int_equal(lumis_image_read(tu_path("pt.exr"), NULL, &pt, NULL), LUMIS_OK);
        assert_int_equal(lumis_image_read(tu_path("nf.exr"), NULL, &nf, NULL), LUMIS_OK);
        assert_memory_equal(pt->pixels, nf->pixels, 3 * sizeof(float) * 16 * 12);
        lumis_image_destroy(pt);
        lumis_image_destroy(nf);
        snprintf(a, sizeof a,
                 "render --scene spheres --fixture '%s' --fixture-at 0,3,1 --fixture-area "
                 "--fixture-near-field --size 16x12 --spp 1 -o '%s'",
                 tu_path("fx.ies"), tu_path("x.exr"));
        expect(a, 2, "light_field");
    }
    { /* a fixture that lights nothing the camera sees: a black image, with a hint; a lit one
       * has none */
        char *err = NULL;
        snprintf(a, sizeof a,
                 "render --scene spheres --fixture '%s' --fixture-at 0,-50,0 --fixture-aim "
                 "0,-100,0 --size 16x12 --spp 1 --quiet -o '%s'",
                 tu_path("fx.ies"), tu_path("dark.exr"));
        assert_int_equal(run(a, NULL, &err), 0);
        assert_non_null(strstr(err, "the image is black"));
        assert_non_null(strstr(err, "--fixture-aim"));
        free(err);
        snprintf(a, sizeof a,
                 "render --scene spheres --fixture '%s' --fixture-at 0,3,1 --fixture-aim 0,0,0 "
                 "--size 16x12 --spp 1 --quiet -o '%s'",
                 tu_path("fx.ies"), tu_path("notdark.exr"));
        assert_int_equal(run(a, NULL, &err), 0);
        assert_null(strstr(err, "black"));
        free(err);
        /* a photometric file given for a light-field luminaire: pointed at lumis info, not
         * "malformed JSON" */
        snprintf(a, sizeof a, "luminaire info '%s'", tu_path("fx.ies"));
        expect(a, 1, "is a photometric file (IES or EULUMDAT), not a light-field luminaire");
        expect(a, 1, "'lumis info ");
    }
    /* a type B floodlight aimed the same way hangs on a yoke: its top (+x) above the aim, its
     * lateral axis (+y) horizontal */
    pg_ies_spec sb = {PG_FLOOD, 8, "IESNA:LM-63-2002", 2, 19, -90, 90, 19, -90, 90, 0, 0, 0, 0,
                      0,        2};
    text = pg_ies(&sb, &n);
    tu_write_file(tu_path("fxb.ies"), text, n);
    free(text);
    snprintf(a, sizeof a,
             "render --scene spheres --fixture '%s' --fixture-at 0,3,1 --fixture-aim 0,0,0 "
             "--size 16x12 --spp 1 -o '%s'",
             tu_path("fxb.ies"), tu_path("clib.exr"));
    expect(a, 0, "1 photometric fixture");
    side = (char *)tu_read_file(tu_path("clib.json"), &sn);
    assert_non_null(side);
    j = cJSON_Parse(side);
    free(side);
    {
        const cJSON *r = cJSON_GetObjectItemCaseSensitive(
            cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(j, "photometric"), 0), "rotation");
        assert_true(fabs(cJSON_GetArrayItem(r, 3)->valuedouble - 1 / sqrt(10.0)) < 1e-6 &&
                    fabs(cJSON_GetArrayItem(r, 4)->valuedouble) < 1e-9);
    }
    cJSON_Delete(j);
    static const char *const usage[][2] = {
        {"--fixture '%s'", "needs --fixture-at X,Y,Z"},
        {"--fixture-at 0,1,0", "need --fixture FILE"},
        {"--fixture '%s' --fixture-at 0,1", "--fixture-at"},
        {"--fixture '%s' --fixture-at 0,1,0 --fixture-aim 0,1,0",
         "a point other than --fixture-at"},
        {"--fixture '%s' --fixture-at 0,1,0 --env sky",
         "lighting.env: does not apply: the scene is lit by photometric fixtures"},
        {"--fixture '%s' --fixture-at 0,1,0 --fixture-multiplier -1", "--fixture-multiplier"},
        {"--fixture '%s' --fixture-at 0,1,0 --fixture-up 0,1", "--fixture-up"},
        {"--fixture '%s' --fixture-at 0,1,0 --fixture-up 0,2,0",
         "--fixture-up: a direction not along the aim"},
        {"--fixture-up 1,0,0", "need --fixture FILE"},
    };
    for (size_t k = 0; k < sizeof usage / sizeof usage[0]; k++) {
        char opts[1024];
        snprintf(opts, sizeof opts, usage[k][0], tu_path("fx.ies"));
        snprintf(a, sizeof a, "render --scene spheres %s -o '%s'", opts, tu_path("u.exr"));
        expect(a, 2, usage[k][1]);
    }
    /* malformed fixtures, named by their JSON path */
    static const char *const bad[][2] = {
        {"{\"objects\": [], \"photometric\": [{\"file\": \"none.ies\", \"position\": [0, 1, 0]}]}",
         "photometric[0].file: cannot read photometric file"},
        {"{\"objects\": [], \"photometric\": [{\"file\": \"fx.ies\", \"position\": [0, 1, 0], "
         "\"aim\": [0, 1, 0]}]}",
         "photometric[0].aim: expected a point other than the position"},
        {"{\"objects\": [], \"photometric\": [{\"file\": \"fx.ies\"}]}",
         "photometric[0].position: expected an array of 3 numbers (missing)"},
        {"{\"objects\": [], \"photometric\": [{\"file\": \"fx.ies\", \"position\": [0, 1, 0], "
         "\"area\": 1}]}",
         "photometric[0].area: expected true or false"},
        {"{\"objects\": [], \"photometric\": [{\"file\": \"fx.ies\", \"position\": [0, 1, 0], "
         "\"colour\": 1}]}",
         "photometric[0].colour"},
        {"{\"objects\": [], \"photometric\": {}}", "photometric: expected an array"},
        {"{\"objects\": [], \"photometric\": [{\"file\": \"fx.ies\", \"position\": [0, 1, 0], "
         "\"up\": [0, -2, 0]}]}",
         "photometric[0].up: expected a direction not along the aim"},
        {"{\"objects\": [], \"photometric\": [{\"file\": \"fx.ies\", \"position\": [0, 1, 0], "
         "\"aim\": [3, 1, 0], \"c0\": [-1, 0, 0]}]}",
         "photometric[0].c0: expected a direction not along the aim"},
        {"{\"objects\": [], \"photometric\": [{\"file\": \"fx.ies\", \"position\": [0, 1, 0], "
         "\"up\": [1, 0, 0], \"c0\": [1, 0, 0]}]}",
         "photometric[0].c0: expected up or c0, not both"},
        /* a dark fixture, or none, once left the scene to the default sky, exit 0 */
        {"{\"objects\": [], \"photometric\": [{\"file\": \"fx.ies\", \"position\": [0, 1, 0], "
         "\"multiplier\": 0}]}",
         "photometric[0].multiplier: expected a number > 0"},
        {"{\"objects\": [], \"photometric\": []}", "photometric: expected at least one fixture"},
        {"{\"objects\": [], \"photometric\": [1]}", "photometric[0]: expected an object"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        tu_write_file(tu_path("bad-fx.json"), bad[k][0], strlen(bad[k][0]));
        snprintf(a, sizeof a, "render '%s' -o '%s'", tu_path("bad-fx.json"), tu_path("y.exr"));
        expect(a, 1, bad[k][1]);
    }
    /* an opening the area model lacks is refused, not rendered as a point */
    pg_ies_spec pt = s;
    pt.width = pt.length = 0;
    text = pg_ies(&pt, &n);
    tu_write_file(tu_path("pt.ies"), text, n);
    free(text);
    snprintf(a, sizeof a,
             "render --scene spheres --fixture '%s' --fixture-at 0,1,0 --fixture-area --size 8x6 "
             "--spp 1 -o '%s'",
             tu_path("pt.ies"), tu_path("pt.exr"));
    expect(a, 1, "luminous shape is \"point\": the opening (area) model");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(help_version_and_usage_errors),
        cmocka_unit_test(option_tables_parse_and_document),
        cmocka_unit_test(runtime_errors_name_file_and_reason),
        cmocka_unit_test(stdout_write_errors_are_errors),
        cmocka_unit_test(info_json_has_the_documented_keys),
        cmocka_unit_test(render_sun_is_reported),
        cmocka_unit_test(lights_sun_exports_the_sun_first),
        cmocka_unit_test(convert_resize_preserves_power_and_writes_every_format),
        cmocka_unit_test(demo_writes_the_sky_and_its_info),
        cmocka_unit_test(sample_and_pdf_agree_and_are_reproducible),
        cmocka_unit_test(bench_samplers_reports_every_method),
        cmocka_unit_test(render_writes_the_same_image_on_any_thread_count),
        cmocka_unit_test(render_sidecar_time_budget_and_scenes),
        cmocka_unit_test(outputs_never_replace_inputs_and_are_checked_first),
        cmocka_unit_test(render_with_light_sets),
        cmocka_unit_test(render_with_stratified_light_sets),
        cmocka_unit_test(simd_variants_render_the_same_image),
        cmocka_unit_test(render_with_luminaires),
        cmocka_unit_test(render_default_is_automatic),
        cmocka_unit_test(render_passes_and_merge),
        cmocka_unit_test(merged_shares_equal_one_render_for_every_light_kind),
        cmocka_unit_test(merge_refuses_doctored_shares),
        cmocka_unit_test(luminaire_files_create_info_render),
        cmocka_unit_test(acquired_presets_are_cached),
        cmocka_unit_test(lights_export_parses_back),
        cmocka_unit_test(light_params_reach_the_methods),
        cmocka_unit_test(lights_picture_marks_emissive_pixels),
        cmocka_unit_test(compare_prints_every_metric),
        cmocka_unit_test(replaced_values_are_reported),
        cmocka_unit_test(replaced_noise_is_a_note_and_spikes_are_named),
        cmocka_unit_test(bench_runs_light_sets),
        cmocka_unit_test(bench_runs_auto),
        cmocka_unit_test(bench_region_draws_in_the_key),
        cmocka_unit_test(bench_runs_resumes_shards_and_reports),
        cmocka_unit_test(bench_runs_as_slurm_job_arrays),
        cmocka_unit_test(slurm_scripts_survive_hostile_names),
        cmocka_unit_test(info_reads_photometric_files),
        cmocka_unit_test(render_places_photometric_fixtures),
        cmocka_unit_test(bench_survives_a_failing_item),
        cmocka_unit_test(bench_convergence_at_equal_time),
        cmocka_unit_test(bench_convergence_at_equal_samples),
    };
    /* LUMIS_TEST_FILTER=PATTERN runs only the tests whose names match (cmocka's pattern) */
    const char *only = getenv("LUMIS_TEST_FILTER");
    if (only && *only) cmocka_set_test_filter(only);
    /* LUMIS_TEST_SKIP=PATTERN skips them (CTest runs the merge property test on its own) */
    const char *skip = getenv("LUMIS_TEST_SKIP");
    if (skip && *skip) cmocka_set_skip_filter(skip);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
