/* Pixel-wise metrics (src/metrics/basic.c): MSE, RMSE, relative MSE and PSNR on linear
 * values, and CIELAB Delta E, against values worked out by hand. */
/* Oracles:
 * lumis_image_errors — hand-worked: MSE, RMSE, relMSE (r^2 + eps), PSNR's peak, NaN/inf as 0, black
 *     reference (errors_on_linear_values)
 * lumis_lab_delta_e — hand-worked: CIELAB Delta E of hand-computed colours (lab_delta_e_by_hand)
 */
#include "testutil.h"

#include "lumis/metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static lumis_image *filled(int w, int h, float r, float g, float b)
{
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(w, h, &img), LUMIS_OK);
    for (int k = 0; k < w * h; k++) {
        img->pixels[3 * k] = r;
        img->pixels[3 * k + 1] = g;
        img->pixels[3 * k + 2] = b;
    }
    return img;
}

static void errors_on_linear_values(void **state)
{
    (void)state;
    lumis_image *ref = filled(4, 3, 1.0f, 1.0f, 1.0f), *test = filled(4, 3, 1.1f, 1.1f, 1.1f);
    ref->pixels[0] = 2.0f; /* the peak */
    test->pixels[0] = 2.0f;
    lumis_image_error_stats e;
    assert_int_equal(lumis_image_errors(ref, test, NULL, &e), LUMIS_OK);
    /* 35 of the 36 values differ by 0.1 (in float: 1.1f - 1 = 0.10000002). */
    double d = (double)1.1f - 1.0, mse = 35.0 * d * d / 36.0;
    assert_true(fabs(e.mse - mse) < 1e-12 && fabs(e.rmse - sqrt(mse)) < 1e-12);
    assert_true(fabs(e.relmse - 35.0 * d * d / 1.01 / 36.0) < 1e-12);
    assert_true(e.relmse_epsilon == 0.01 && e.psnr_peak == 2.0);
    assert_true(fabs(e.psnr - 10.0 * log10(4.0 / mse)) < 1e-9);
    /* Another epsilon; identical images have an infinite PSNR. */
    lumis_metric_options o = {0};
    o.relmse_epsilon = 1.0;
    assert_int_equal(lumis_image_errors(ref, test, &o, &e), LUMIS_OK);
    assert_true(fabs(e.relmse - 35.0 * d * d / 2.0 / 36.0) < 1e-12);
    assert_int_equal(lumis_image_errors(ref, ref, NULL, &e), LUMIS_OK);
    assert_true(e.mse == 0.0 && isinf(e.psnr) && e.psnr > 0);
    /* NaN counts as 0. */
    test->pixels[5] = NAN;
    assert_int_equal(lumis_image_errors(ref, test, NULL, &e), LUMIS_OK);
    assert_true(isfinite(e.mse) && e.mse > mse);
    lumis_image_destroy(ref);
    lumis_image_destroy(test);
    /* relMSE divides by r^2, not r: with r = 3 and 0.5 (where r and r^2 differ, unlike the
     * r = 1 above), t - r = 1 and 0.25: mean of 1/(9 + eps) and 0.0625/(0.25 + eps). */
    ref = filled(2, 1, 3.0f, 3.0f, 3.0f);
    test = filled(2, 1, 4.0f, 4.0f, 4.0f);
    for (int c = 0; c < 3; c++) ref->pixels[3 + c] = 0.5f, test->pixels[3 + c] = 0.75f;
    assert_int_equal(lumis_image_errors(ref, test, NULL, &e), LUMIS_OK);
    const double want = 0.5 * (1.0 / 9.01 + 0.0625 / 0.26);
    if (!(fabs(e.relmse - want) < 1e-12)) fail_msg("relmse %.12g, want %.12g", e.relmse, want);
    /* PSNR's peak is the reference's largest value (3), not the test's (4) */
    const double mse2 = 0.5 * (1.0 + 0.0625);
    assert_true(e.psnr_peak == 3.0);
    assert_true(fabs(e.psnr - 10.0 * log10(9.0 / mse2)) < 1e-9);
    lumis_image_destroy(ref);
    lumis_image_destroy(test);
    /* A black reference against anything else: no peak to compare with, PSNR -infinity
     * (not the +infinity of identical images). */
    ref = filled(2, 1, 0.0f, 0.0f, 0.0f);
    test = filled(2, 1, 1.0f, 1.0f, 1.0f);
    assert_int_equal(lumis_image_errors(ref, test, NULL, &e), LUMIS_OK);
    assert_true(e.mse == 1.0 && e.psnr_peak == 0.0);
    if (!(isinf(e.psnr) && e.psnr < 0)) fail_msg("PSNR of a black reference: %g", e.psnr);
    lumis_image_destroy(ref);
    lumis_image_destroy(test);
    /* An infinite value counts as 0, like NaN: one of six values differs by 1. */
    ref = filled(2, 1, 1.0f, 1.0f, 1.0f);
    test = filled(2, 1, 1.0f, 1.0f, 1.0f);
    test->pixels[0] = INFINITY;
    assert_int_equal(lumis_image_errors(ref, test, NULL, &e), LUMIS_OK);
    if (!(fabs(e.mse - 1.0 / 6.0) < 1e-12 && fabs(e.relmse - 1.0 / 1.01 / 6.0) < 1e-12))
        fail_msg("an infinite pixel: mse %g, relmse %g", e.mse, e.relmse);
    lumis_image_destroy(ref);
    lumis_image_destroy(test);
}

static void lab_delta_e_by_hand(void **state)
{
    (void)state;
    lumis_image *white = filled(2, 2, 1, 1, 1), *black = filled(2, 2, 0, 0, 0);
    double m = -1;
    assert_int_equal(lumis_lab_delta_e(white, black, NULL, NULL, &m), LUMIS_OK);
    assert_true(fabs(m - 100.0) < 1e-9); /* L* 100 against 0, neutral */
    /* Grey 0.18: L* = 116 * 0.18^(1/3) - 16 = 49.496; against black. */
    lumis_image *grey = filled(2, 2, 0.18f, 0.18f, 0.18f);
    float map[4];
    assert_int_equal(lumis_lab_delta_e(grey, black, NULL, map, &m), LUMIS_OK);
    double L = 116.0 * cbrt((double)0.18f) - 16.0;
    assert_true(fabs(m - L) < 1e-4 && fabs(map[3] - L) < 1e-4);
    /* Exposure then clamp: 5 and 10 both clamp to white at EV 0; at EV -4 they differ. */
    lumis_image *five = filled(2, 2, 5, 5, 5), *ten = filled(2, 2, 10, 10, 10);
    assert_int_equal(lumis_lab_delta_e(five, ten, NULL, NULL, &m), LUMIS_OK);
    assert_true(m == 0.0);
    lumis_metric_options o = {0};
    o.exposure_ev = -4.0f;
    assert_int_equal(lumis_lab_delta_e(five, ten, &o, NULL, &m), LUMIS_OK);
    double l5 = 116.0 * cbrt(5.0 / 16) - 16, l10 = 116.0 * cbrt(10.0 / 16) - 16;
    assert_true(fabs(m - (l10 - l5)) < 1e-4);
    /* Red against black: the a* axis carries it. */
    lumis_image *red = filled(2, 2, 1, 0, 0);
    assert_int_equal(lumis_lab_delta_e(red, black, NULL, NULL, &m), LUMIS_OK);
    assert_true(m > 100.0 && m < 200.0);
    /* sRGB red and blue are L*a*b* (53.2408, 80.0925, 67.2032) and (32.2970, 79.1875,
     * -107.8602) (D65); blue's b* checks the 200 of b*, red's a* the 500 of a*. */
    assert_int_equal(lumis_lab_delta_e(red, black, NULL, NULL, &m), LUMIS_OK);
    double want = sqrt(53.2408 * 53.2408 + 80.0925 * 80.0925 + 67.2032 * 67.2032);
    if (!(fabs(m - want) < 1e-3)) fail_msg("red against black: %.6f, want %.6f", m, want);
    lumis_image *blue = filled(2, 2, 0, 0, 1);
    assert_int_equal(lumis_lab_delta_e(blue, black, NULL, NULL, &m), LUMIS_OK);
    want = sqrt(32.2970 * 32.2970 + 79.1875 * 79.1875 + 107.8602 * 107.8602);
    if (!(fabs(m - want) < 1e-3)) fail_msg("blue against black: %.6f, want %.6f", m, want);
    /* Red against blue, neither black: their a* nearly agree (80.09 and 79.19), so a* adds
     * almost nothing; the difference of each coordinate counts, not its sum. */
    assert_int_equal(lumis_lab_delta_e(red, blue, NULL, NULL, &m), LUMIS_OK);
    want =
        sqrt((53.2408 - 32.2970) * (53.2408 - 32.2970) + (80.0925 - 79.1875) * (80.0925 - 79.1875) +
             (67.2032 + 107.8602) * (67.2032 + 107.8602));
    if (!(fabs(m - want) < 1e-3)) fail_msg("red against blue: %.6f, want %.6f", m, want);
    lumis_image_destroy(blue);
    /* Dark greys: Y = 0.001 is on the linear toe, L* = 116 (Y / (3 (6/29)^2)) = 903.3 Y;
     * Y = 0.02 is past (6/29)^3 = 0.008856, on the cube root, though under (6/29)^2. */
    lumis_image *dark = filled(2, 2, 0.001f, 0.001f, 0.001f);
    assert_int_equal(lumis_lab_delta_e(dark, black, NULL, NULL, &m), LUMIS_OK);
    want = (double)0.001f * 116.0 * 841.0 / 108.0;
    if (!(fabs(m - want) < 1e-6)) fail_msg("grey 0.001: L* %.8f, want %.8f", m, want);
    lumis_image_destroy(dark);
    dark = filled(2, 2, 0.02f, 0.02f, 0.02f);
    assert_int_equal(lumis_lab_delta_e(dark, black, NULL, NULL, &m), LUMIS_OK);
    want = 116.0 * cbrt((double)0.02f) - 16.0;
    if (!(fabs(m - want) < 1e-4)) fail_msg("grey 0.02: L* %.8f, want %.8f", m, want);
    lumis_image_destroy(dark);
    lumis_image_destroy(white);
    lumis_image_destroy(black);
    lumis_image_destroy(grey);
    lumis_image_destroy(five);
    lumis_image_destroy(ten);
    lumis_image_destroy(red);
}

static void bad_arguments_are_refused(void **state)
{
    (void)state;
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_metric_options o = {0};
    o.errors = sink.sink;
    lumis_image *a = filled(2, 2, 1, 1, 1), *b = filled(3, 2, 1, 1, 1);
    lumis_image_error_stats e;
    double m;
    assert_int_equal(lumis_image_errors(a, b, &o, &e), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "differ in size"));
    assert_int_equal(lumis_lab_delta_e(a, b, &o, NULL, &m), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_image_errors(NULL, b, &o, &e), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_image_errors(a, a, &o, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_lab_delta_e(a, a, &o, NULL, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(errors_on_linear_values),
        cmocka_unit_test(lab_delta_e_by_hand),
        cmocka_unit_test(bad_arguments_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
