/* The lumis executable: exit codes (0 ok, 1 runtime, 2 usage), messages that name the
 * file and the reason, and the documented output of each subcommand. */
#include "testutil.h"

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int run(const char *args, char **out, char **err)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "'%s' %s", LUMIS_CLI, args);
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
    const char *cmds[] = {"info", "convert", "sky", "studio", "demo"};
    for (int k = 0; k < 5; k++) {
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
    expect("convert sky:8x4 out.jpg", 2, "unknown output extension");
    expect("convert sky:8x4 o.png --tonemap filmic", 2, "--tonemap");
    expect("convert sky:8x4 o.png --exposure lots", 2, "--exposure");
    expect("sky --sun-elevation 100 -o x.exr", 2, "--sun-elevation");
    expect("sky --turbidity 0.5 -o x.exr", 2, "--turbidity");
    expect("sky --size 10y5 -o x.exr", 2, "--size");
    expect("sky", 2, "-o OUT");
    expect("studio --intensity -3 -o x.exr", 2, "--intensity");
}

static void runtime_errors_name_file_and_reason(void **state)
{
    (void)state;
    char a[1024];
    snprintf(a, sizeof a, "info '%s'", tu_path("missing.exr"));
    expect(a, 1, "missing.exr: No such file or directory");
    tu_write_file(tu_path("text.exr"), "hello\n", 6);
    snprintf(a, sizeof a, "info '%s'", tu_path("text.exr"));
    expect(a, 1, "text.exr: not an EXR, Radiance HDR or PFM image");
    tu_write_file(tu_path("trunc.hdr"), "#?RADIANCE\n\n-Y 9 +X 9\nAB", 24);
    snprintf(a, sizeof a, "info '%s'", tu_path("trunc.hdr"));
    expect(a, 1, "trunc.hdr");
    snprintf(a, sizeof a, "sky --size 16x8 -o '%s/nope/sky.exr'", tu_tmpdir());
    expect(a, 1, "nope/sky.exr: cannot create a file there");
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
    /* Text output mentions the same quantities. */
    char *out = NULL;
    assert_int_equal(run("info studio:32x16", &out, NULL), 0);
    assert_non_null(strstr(out, "32 x 16"));
    assert_non_null(strstr(out, "top 0.1% share"));
    free(out);
}

static void convert_resize_preserves_power_and_writes_every_format(void **state)
{
    (void)state;
    char a[1024];
    snprintf(a, sizeof a, "sky --size 256x128 --sun-elevation 20 -o '%s'", tu_path("s.exr"));
    expect(a, 0, NULL);
    cJSON *o = info_json(tu_path("s.exr"));
    double p0 = num(o, "power");
    cJSON_Delete(o);
    const char *outs[] = {"r.exr", "r.pfm", "r.hdr"};
    for (int k = 0; k < 3; k++) {
        snprintf(a, sizeof a, "convert '%s' '%s' --resize 100x37", tu_path("s.exr"),
                 tu_path(outs[k]));
        expect(a, 0, NULL);
        o = info_json(tu_path(outs[k]));
        assert_int_equal((int)num(o, "width"), 100);
        double tol = k == 2 ? 1e-2 : 1e-5; /* RGBE keeps 8 bits */
        if (fabs(num(o, "power") - p0) > tol * p0)
            fail_msg("%s: %g vs %g", outs[k], num(o, "power"), p0);
        cJSON_Delete(o);
    }
    snprintf(a, sizeof a, "convert '%s' '%s' --exposure -3 --tonemap aces", tu_path("s.exr"),
             tu_path("r.png"));
    expect(a, 0, NULL);
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
    snprintf(a, sizeof a, "demo --out '%s'", tu_path("demo"));
    assert_int_equal(run(a, &out, NULL), 0);
    assert_non_null(strstr(out, "top 1% share"));
    free(out);
    assert_int_equal(tu_count_entries(tu_path("demo"), "sky.exr"), 1);
    assert_int_equal(tu_count_entries(tu_path("demo"), "sky.png"), 1);
    assert_int_equal(tu_count_entries(tu_path("demo"), "."), 2); /* "." and "..", no temp files */
    cJSON *o = info_json(tu_path("demo/sky.exr"));
    assert_true(num(o, "top01_share") > 0.5);
    cJSON_Delete(o);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(help_version_and_usage_errors),
        cmocka_unit_test(runtime_errors_name_file_and_reason),
        cmocka_unit_test(info_json_has_the_documented_keys),
        cmocka_unit_test(convert_resize_preserves_power_and_writes_every_format),
        cmocka_unit_test(demo_writes_the_sky_and_its_info),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
