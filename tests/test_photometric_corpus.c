/* Real photometric files (tests/data/photometric, issue 34) against an oracle written apart
 * from lumis's reader (tests/oracle/photometric_oracle.py, its output expected.json): for
 * every file, the flux and the peak to 1e-9 relative, the beam and field angles of both
 * principal planes to 0.1 degree.  Every file is checked; the ones that disagree are
 * printed with both numbers, then the test fails. */
/* Oracles:
 * lumis_photometric_read — external: real files of tests/data/photometric against the Python oracle
 *     written apart from lumis (tests/oracle/photometric_oracle.py, expected.json) (check_file)
 * lumis_photometric_get_info — external: flux and peak to 1e-9, beam and field angles of both
 *     principal planes to 0.1° against the Python oracle (check_file)
 * lumis_photometric_get_ratings — external: LOR, efficacy, zonal lumens, CIE flux code, BUG zones
 *     and rating, spacing criterion against the Python oracle (check_ratings)
 * lumis_photometric_spacing_criterion — external: both planes of every type C file against the
 *     Python oracle's own scan and bisection, to 1e-9 (check_ratings)
 * lumis_photometric_intensity_n — consistency: the single call's bits, element by element, on
 *     real type C, B and EULUMDAT files (batches_are_the_single_calls)
 * lumis_photometric_intensity_at_n — consistency: the single call's bits on a grid of angles
 *     past the table's ranges (batches_are_the_single_calls)
 * lumis_photometric_pdf_n — consistency: the single call's bits (batches_are_the_single_calls)
 * lumis_photometric_sample_n — consistency: the single call's directions, pdfs and status
 *     (batches_are_the_single_calls)
 */
#include "lumis/io.h"
#include "lumis/photometry.h"
#include "lumis/rng.h"
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

/* A number of the oracle's, or NAN where it holds null or nothing. */
static double maybe(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* lumis info's designer numbers against the oracle's: LOR, efficacy, zonal lumens, the CIE
 * flux code, the BUG zones and rating (forward = C 270-90, through C0, as TM-15 says) and
 * the spacing criterion.
 * Lumens to 1e-9 of the flux. */
static int stated_bugs; /* files whose stated BUG rating was compared */
static int rated_bugs;  /* files whose B, U and G were compared with the oracle's */
static int spacings;    /* spacing criteria (one per plane) compared with the oracle's */

static int check_ratings(const char *name, const lumis_photometric_file *f, double flux,
                         const cJSON *want)
{
    lumis_photometric_ratings r;
    assert_int_equal(lumis_photometric_get_ratings(f->model, f->input_watts, &r), LUMIS_OK);
    int bad = 0;
    const double lor = maybe(want, "lor"), eff = maybe(want, "efficacy_lm_per_w");
    if (isfinite(lor) != (r.lor > 0) || (isfinite(lor) && !rel_ok(r.lor, lor, 1e-9))) {
        printf("FAIL %s: LOR lumis %.10g oracle %.10g\n", name, r.lor, lor);
        bad++;
    }
    if (isfinite(eff) != (r.efficacy > 0) || (isfinite(eff) && !rel_ok(r.efficacy, eff, 1e-9))) {
        printf("FAIL %s: efficacy lumis %.10g oracle %.10g\n", name, r.efficacy, eff);
        bad++;
    }
    if (!cJSON_IsArray(cJSON_GetObjectItemCaseSensitive(want, "zonal_lm"))) return bad; /* A, B */
    for (int k = 0; k < 6; k++) {
        const double z = num2(want, "zonal_lm", k);
        if (fabs(r.zonal_lm[k] - z) > 1e-9 * flux) {
            printf("FAIL %s: zonal_lm[%d] lumis %.10g oracle %.10g\n", name, k, r.zonal_lm[k], z);
            bad++;
        }
    }
    const cJSON *code = cJSON_GetObjectItemCaseSensitive(want, "cie_flux_code");
    for (int k = 0; k < 5; k++) {
        const cJSON *c = cJSON_GetArrayItem(code, k);
        const int w = cJSON_IsNumber(c) ? (int)c->valueint : -1;
        if (r.cie_flux_code[k] != w) {
            printf("FAIL %s: CIE flux code N%d lumis %d oracle %d\n", name, k + 1,
                   r.cie_flux_code[k], w);
            bad++;
        }
    }
    /* the spacing criterion in C0-C180 and C90-C270: null where it does not apply */
    const cJSON *sc = cJSON_GetObjectItemCaseSensitive(want, "spacing_criterion");
    for (int k = 0; k < 2; k++) {
        const cJSON *c = cJSON_GetArrayItem(sc, k);
        const double w = cJSON_IsNumber(c) ? c->valuedouble : 0.0;
        if ((w > 0) != (r.spacing[k] > 0) || (w > 0 && !rel_ok(r.spacing[k], w, 1e-9))) {
            printf("FAIL %s: spacing criterion [%d] lumis %.10g oracle %.10g\n", name, k,
                   r.spacing[k], w);
            bad++;
        }
        spacings += w > 0;
    }
    const cJSON *zones = cJSON_GetObjectItemCaseSensitive(want, "bug_zone_lm");
    const double got[10] = {r.lcs.fl, r.lcs.fm, r.lcs.fh,  r.lcs.fvh, r.lcs.bl,
                            r.lcs.bm, r.lcs.bh, r.lcs.bvh, r.lcs.ul,  r.lcs.uh};
    static const char *const keys[10] = {"FL", "FM", "FH",  "FVH", "BL",
                                         "BM", "BH", "BVH", "UL",  "UH"};
    for (int k = 0; k < 10; k++)
        if (fabs(got[k] - num(zones, keys[k])) > 1e-9 * flux) {
            printf("FAIL %s: BUG zone %s lumis %.10g oracle %.10g\n", name, keys[k], got[k],
                   num(zones, keys[k]));
            bad++;
        }
    const cJSON *bug = cJSON_GetObjectItemCaseSensitive(want, "bug");
    const int wb[3] = {(int)num(bug, "B"), (int)num(bug, "U"), (int)num(bug, "G")};
    /* all three letters, every type C file (types A and B have none) */
    if (r.bug[0] != wb[0] || r.bug[1] != wb[1] || r.bug[2] != wb[2]) {
        printf("FAIL %s: BUG lumis B%d U%d G%d oracle B%d U%d G%d\n", name, r.bug[0], r.bug[1],
               r.bug[2], wb[0], wb[1], wb[2]);
        bad++;
    }
    rated_bugs++;
    /* a file that states its own rating (the manufacturer's, not the oracle's): all three */
    const cJSON *stated = cJSON_GetObjectItemCaseSensitive(want, "published_bug");
    if (stated) {
        const int sb[3] = {(int)num(stated, "B"), (int)num(stated, "U"), (int)num(stated, "G")};
        if (r.bug[0] != sb[0] || r.bug[1] != sb[1] || r.bug[2] != sb[2]) {
            printf("FAIL %s: BUG lumis B%d U%d G%d, the file states B%d U%d G%d\n", name, r.bug[0],
                   r.bug[1], r.bug[2], sb[0], sb[1], sb[2]);
            bad++;
        }
        stated_bugs++;
    }
    return bad;
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
    bad += check_ratings(name, f, info.flux, want);
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
    assert_true(stated_bugs >= 1);
    assert_true(rated_bugs >= 30);
    assert_true(spacings >= 60);
    if (failed_files) fail_msg("%d of %d files disagree with the oracle", failed_files, files);
}

/* The lumens a file states (EULUMDAT: lamp set 1's flux x LORL; an IES keyword) against
 * the table's flux.  Within 0.2 % unless the file is listed here with the share it is off
 * by, pinned to 0.001 percentage points, and then neither lumis's exact integral nor the
 * zonal-constant rule older software uses (the oracle's flux_zone_midpoint) comes within
 * 0.2 %: the file's own table disagrees with its stated figure (docs/photometric.md,
 * "declared lumens").  A listed file that comes to agree fails too: the list stays true. */
static const struct {
    const char *file;
    double off_percent; /* (table's flux / stated - 1) x 100 */
} self_inconsistent[] = {
    /* measured LED luminaires: stated LORL 100 %, 100.1 %, 100.1 %, the tables' 100.67 %,
     * 102.55 %, 101.10 % of the lamp flux */
    {"ugr_sample_01.ldt", +0.674},
    {"ugr_sample_05.ldt", +2.442},
    {"ugr_sample_08.ldt", +1.000},
    /* a viewer's hand-made test files: round stated lumens, tables not made to match */
    {"pv_absolute.ldt", -9.548},
    {"pv_multiple_lamp_sets.ldt", -9.548},
    {"pv_relative.ldt", -9.548},
    {"pv_symmetry_about_vertical_axis.ldt", -9.548},
    {"pv_no_symmetry.ldt", +272.202},
    {"pv_symmetry_to_c0c180.ldt", +214.083},
    {"pv_symmetry_to_c90c270.ldt", +214.083},
    {"pv_symmetry_to_c0c90c180c270.ldt", +109.467},
};

static void published_lumens_within_0_2_percent(void **state)
{
    (void)state;
    size_t n = 0;
    char *text = (char *)tu_read_file(CORPUS "/expected.json", &n);
    assert_non_null(text);
    cJSON *all = cJSON_ParseWithLength(text, n);
    free(text);
    assert_non_null(all);
    const int nknown = (int)(sizeof self_inconsistent / sizeof self_inconsistent[0]);
    int agree = 0, listed = 0, bad = 0;
    const cJSON *e = NULL;
    cJSON_ArrayForEach(e, all)
    {
        const double stated = maybe(e, "published_lm");
        if (!(stated > 0)) continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", CORPUS, e->string);
        tu_sink sink;
        tu_sink_init(&sink);
        lumis_photometric_file *f = NULL;
        assert_int_equal(lumis_photometric_read(path, &sink.sink, &f), LUMIS_OK);
        const double off = 100.0 * (lumis_photometric_flux(f->model) / stated - 1.0);
        const double mid = 100.0 * (num(e, "flux_zone_midpoint") / stated - 1.0);
        lumis_photometric_file_destroy(f);
        int k = 0;
        while (k < nknown && strcmp(self_inconsistent[k].file, e->string) != 0) k++;
        if (fabs(off) <= 0.2) {
            printf("ok   %s: %+.3f %% of the stated %.6g lm\n", e->string, off, stated);
            agree++;
            if (k < nknown) {
                printf("FAIL %s: listed as off by %+.3f %%, now agrees\n", e->string,
                       self_inconsistent[k].off_percent);
                bad++;
            }
        } else if (k == nknown) {
            printf("FAIL %s: %+.3f %% off the stated %.6g lm\n", e->string, off, stated);
            bad++;
        } else if (fabs(off - self_inconsistent[k].off_percent) > 1e-3 || fabs(mid) <= 0.2) {
            printf("FAIL %s: %+.4f %% (listed %+.3f %%), zone-midpoint rule %+.3f %%\n", e->string,
                   off, self_inconsistent[k].off_percent, mid);
            bad++;
        } else {
            printf("self-inconsistent %s: table %+.3f %%, zone-midpoint rule %+.3f %%\n", e->string,
                   off, mid);
            listed++;
        }
    }
    cJSON_Delete(all);
    printf("%d files within 0.2 %%, %d listed as disagreeing with themselves\n", agree, listed);
    assert_int_equal(listed, nknown); /* every listed file is in the corpus and still off */
    assert_true(agree >= 4);
    if (bad) fail_msg("%d files break the published-lumens rule", bad);
}

/* The batched calls (the Python package's) give the single calls' bits: same directions in,
 * same doubles out, on real files of each type; NULL arrays refused, n 0 accepted. */
static void batches_are_the_single_calls(void **state)
{
    (void)state;
    static const char *files[] = {"luxcore_asa_15m_r2.ies", "mdl_type_b_test.ies",
                                  "lidrs_prolicht_e30.ldt", "pv_no_symmetry.ldt"};
    enum { N = 2000, NH = 37, NV = 41 };
    static lumis_vec3 dirs[N], bd[N];
    static double u[2 * N], a[N], b[N], pa[N], grid[NH * NV], h[NH], v[NV];
    for (size_t fi = 0; fi < sizeof files / sizeof files[0]; fi++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", CORPUS, files[fi]);
        lumis_photometric_file *f = NULL;
        assert_int_equal(lumis_photometric_read(path, NULL, &f), LUMIS_OK);
        const lumis_photometric *m = f->model;
        lumis_pcg32 rng;
        lumis_pcg32_seed(&rng, 40 + fi, 1);
        for (int k = 0; k < N; k++) {
            u[2 * k] = lumis_pcg32_double(&rng);
            u[2 * k + 1] = lumis_pcg32_double(&rng);
            const double z = 1.0 - 2.0 * lumis_pcg32_double(&rng),
                         ph = 6.283185307179586 * lumis_pcg32_double(&rng);
            const double r = sqrt(fmax(0.0, 1.0 - z * z));
            dirs[k] = (lumis_vec3){(float)(r * cos(ph)), (float)(r * sin(ph)), (float)z};
        }
        assert_int_equal(lumis_photometric_intensity_n(m, dirs, N, a), LUMIS_OK);
        assert_int_equal(lumis_photometric_pdf_n(m, dirs, N, b), LUMIS_OK);
        int lit = 0;
        for (int k = 0; k < N; k++) {
            const double i1 = lumis_photometric_intensity(m, dirs[k]),
                         p1 = lumis_photometric_pdf(m, dirs[k]);
            assert_memory_equal(&a[k], &i1, sizeof i1);
            assert_memory_equal(&b[k], &p1, sizeof p1);
            lit += i1 > 0;
        }
        assert_true(lit > N / 10); /* the directions reach the light */
        for (int i = 0; i < NH; i++) h[i] = -200.0 + 560.0 * i / (NH - 1);
        for (int j = 0; j < NV; j++) v[j] = -190.0 + 380.0 * j / (NV - 1);
        assert_int_equal(lumis_photometric_intensity_at_n(m, h, NH, v, NV, grid), LUMIS_OK);
        for (int i = 0; i < NH; i++)
            for (int j = 0; j < NV; j++) {
                const double g = lumis_photometric_intensity_at(m, h[i], v[j]);
                assert_memory_equal(&grid[i * NV + j], &g, sizeof g);
            }
        const lumis_status st = lumis_photometric_sample_n(m, u, N, bd, pa);
        lumis_status first = LUMIS_OK;
        for (int k = 0; k < N; k++) {
            lumis_vec3 d1;
            double p1;
            const lumis_status s1 = lumis_photometric_sample(m, u[2 * k], u[2 * k + 1], &d1, &p1);
            if (first == LUMIS_OK) first = s1;
            assert_memory_equal(&bd[k], &d1, sizeof d1);
            assert_memory_equal(&pa[k], &p1, sizeof p1);
        }
        assert_int_equal(st, first);
        assert_int_equal(st, LUMIS_OK);
        /* edges: NULL arrays with n > 0 refused, n 0 a no-op, a NULL model refused */
        assert_int_equal(lumis_photometric_intensity_n(m, NULL, 1, a), LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_photometric_pdf_n(m, dirs, 1, NULL), LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_photometric_sample_n(m, u, 1, NULL, pa), LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_photometric_intensity_at_n(m, NULL, 2, v, 2, grid),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_photometric_intensity_n(m, NULL, 0, NULL), LUMIS_OK);
        assert_int_equal(lumis_photometric_sample_n(m, NULL, 0, NULL, NULL), LUMIS_OK);
        assert_int_equal(lumis_photometric_intensity_at_n(m, NULL, 0, NULL, 5, NULL), LUMIS_OK);
        assert_int_equal(lumis_photometric_pdf_n(NULL, dirs, 1, b), LUMIS_ERR_INVALID_ARGUMENT);
        printf("ok   %s: %d directions, %d lit; %d x %d grid; %d draws\n", files[fi], N, lit, NH,
               NV, N);
        lumis_photometric_file_destroy(f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(corpus_agrees_with_the_oracle),
        cmocka_unit_test(published_lumens_within_0_2_percent),
        cmocka_unit_test(batches_are_the_single_calls),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
