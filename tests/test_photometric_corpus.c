/* Real photometric files (tests/data/photometric, issue 34) against an oracle written apart
 * from lumis's reader (tests/oracle/photometric_oracle.py, its output expected.json): for
 * every file, the flux and the peak to 1e-9 relative, the beam and field angles of both
 * principal planes to 0.1 degree.  Every file is checked; the ones that disagree are
 * printed with both numbers, then the test fails. */
#include "lumis/io.h"
#include "lumis/photometry.h"
#include "testutil.h"

#include <cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define CORPUS LUMIS_SOURCE_DIR "/tests/data/photometric"

static double num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!cJSON_IsNumber(v)) fail_msg("expected.json: key %s missing or not a number", key);
    return v->valuedouble;
}

static double num2(const cJSON *o, const char *key, int k)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(o, key);
    const cJSON *v = cJSON_GetArrayItem(a, k);
    if (!cJSON_IsNumber(v)) fail_msg("expected.json: %s[%d] missing or not a number", key, k);
    return v->valuedouble;
}

static int rel_ok(double got, double want, double tol)
{
    return fabs(got - want) <= tol * fmax(fabs(want), 1e-300);
}

/* One file: 0 if lumis agrees, else the number of checks that disagree (printed). */
static int check_file(const char *name, const cJSON *want)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", CORPUS, name);
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_photometric_file *f = NULL;
    const lumis_status st = lumis_photometric_read(path, &sink.sink, &f);
    if (st != LUMIS_OK) {
        printf("FAIL %s: read: %s: %s\n", name, lumis_status_name(st), sink.last);
        return 1;
    }
    lumis_photometric_info info;
    assert_int_equal(lumis_photometric_get_info(f->model, &info), LUMIS_OK);
    int bad = 0;
    const double flux = num(want, "flux"), peak = num(want, "peak_cd");
    if (!rel_ok(info.flux, flux, 1e-9)) {
        printf("FAIL %s: flux lumis %.10g oracle %.10g (relative %.3g)\n", name, info.flux, flux,
               (info.flux - flux) / flux);
        bad++;
    }
    if (!rel_ok(info.max_candela, peak, 1e-9)) {
        printf("FAIL %s: max_candela lumis %.10g oracle %.10g\n", name, info.max_candela, peak);
        bad++;
    }
    for (int k = 0; k < 2; k++) {
        const double beam = num2(want, "beam_deg", k), field = num2(want, "field_deg", k);
        if (fabs(info.beam_deg[k] - beam) > 0.1) {
            printf("FAIL %s: beam_deg[%d] lumis %.4f oracle %.4f\n", name, k, info.beam_deg[k],
                   beam);
            bad++;
        }
        if (fabs(info.field_deg[k] - field) > 0.1) {
            printf("FAIL %s: field_deg[%d] lumis %.4f oracle %.4f\n", name, k, info.field_deg[k],
                   field);
            bad++;
        }
    }
    if (!bad)
        printf("ok   %s: flux %.6g lm, peak %.6g cd, beam %.2f/%.2f, field %.2f/%.2f\n", name,
               info.flux, info.max_candela, info.beam_deg[0], info.beam_deg[1], info.field_deg[0],
               info.field_deg[1]);
    lumis_photometric_file_destroy(f);
    return bad;
}

static void corpus_agrees_with_the_oracle(void **state)
{
    (void)state;
    size_t n = 0;
    char *text = (char *)tu_read_file(CORPUS "/expected.json", &n);
    assert_non_null(text);
    cJSON *all = cJSON_ParseWithLength(text, n);
    free(text);
    assert_non_null(all);
    int files = 0, failed_files = 0, failed_checks = 0;
    const cJSON *entry = NULL;
    cJSON_ArrayForEach(entry, all)
    {
        const int bad = check_file(entry->string, entry);
        files++;
        failed_checks += bad;
        failed_files += bad > 0;
    }
    cJSON_Delete(all);
    printf("%d files, %d disagree (%d checks)\n", files, failed_files, failed_checks);
    assert_true(files >= 32);
    if (failed_files) fail_msg("%d of %d files disagree with the oracle", failed_files, files);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(corpus_agrees_with_the_oracle),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
