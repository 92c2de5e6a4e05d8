/* Error metrics on linear images: MSE, RMSE, relative MSE and PSNR on the HDR values, and
 * the mean CIELAB Delta E (CIE76) on display-referred values.  docs/metrics.md states every
 * definition; the outputs of `lumis compare` repeat the domain and the peak. */
#include "lumis/metrics.h"

#include "../core/internal.h"

#include <math.h>
#include <stdlib.h>

static lumis_status check_pair(const lumis_image *ref, const lumis_image *test,
                               const lumis_error_sink *errors, const char *what)
{
    if (!ref || !test || !ref->pixels || !test->pixels || ref->width < 1 || ref->height < 1)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "%s: needs two images", what);
    if (ref->width != test->width || ref->height != test->height)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: the images differ in size (%d x %d and %d x %d)", what, ref->width,
                           ref->height, test->width, test->height);
    return LUMIS_OK;
}

/* Non-finite values count as 0, as they do when a file is read. */
static double finite_or_zero(float v)
{
    return isfinite(v) ? (double)v : 0.0;
}

lumis_status lumis_image_errors(const lumis_image *ref, const lumis_image *test,
                                const lumis_metric_options *options, lumis_image_error_stats *out)
{
    const lumis_error_sink *errors = options ? &options->errors : NULL;
    if (!out) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "errors: no output");
    lumis_status st = check_pair(ref, test, errors, "errors");
    if (st != LUMIS_OK) return st;
    const double eps = options && options->relmse_epsilon > 0.0 ? options->relmse_epsilon : 1e-2;
    const size_t n = 3 * (size_t)ref->width * (size_t)ref->height;
    double se = 0.0, rel = 0.0, peak = 0.0;
    for (size_t k = 0; k < n; k++) {
        double r = finite_or_zero(ref->pixels[k]), t = finite_or_zero(test->pixels[k]);
        double d = t - r;
        se += d * d;
        rel += d * d / (r * r + eps);
        peak = fmax(peak, r);
    }
    out->mse = se / (double)n;
    out->rmse = sqrt(out->mse);
    out->relmse = rel / (double)n;
    out->relmse_epsilon = eps;
    out->psnr_peak = peak;
    out->psnr = out->mse > 0.0 && peak > 0.0 ? 10.0 * log10(peak * peak / out->mse)
                                             : (out->mse > 0.0 ? -INFINITY : INFINITY);
    return LUMIS_OK;
}

/* CIELAB's companding function. */
static double lab_f(double t)
{
    const double d = 6.0 / 29.0;
    return t > d * d * d ? cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

/* Linear Rec. 709 RGB in [0, 1] to L*a*b*, white = the image of RGB (1, 1, 1) (D65). */
static void rgb_to_lab(const double rgb[3], double lab[3])
{
    static const double M[3][3] = {{0.4124564, 0.3575761, 0.1804375},
                                   {0.2126729, 0.7151522, 0.0721750},
                                   {0.0193339, 0.1191920, 0.9503041}};
    double xyz[3];
    for (int i = 0; i < 3; i++) {
        double white = M[i][0] + M[i][1] + M[i][2];
        xyz[i] = (M[i][0] * rgb[0] + M[i][1] * rgb[1] + M[i][2] * rgb[2]) / white;
    }
    double fx = lab_f(xyz[0]), fy = lab_f(xyz[1]), fz = lab_f(xyz[2]);
    lab[0] = 116.0 * fy - 16.0;
    lab[1] = 500.0 * (fx - fy);
    lab[2] = 200.0 * (fy - fz);
}

lumis_status lumis_lab_delta_e(const lumis_image *ref, const lumis_image *test,
                               const lumis_metric_options *options, float *map, double *mean)
{
    const lumis_error_sink *errors = options ? &options->errors : NULL;
    if (!mean) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "Lab: no output");
    lumis_status st = check_pair(ref, test, errors, "Lab");
    if (st != LUMIS_OK) return st;
    const double k = exp2(options ? (double)options->exposure_ev : 0.0);
    const size_t n = (size_t)ref->width * (size_t)ref->height;
    double sum = 0.0;
    for (size_t p = 0; p < n; p++) {
        double a[3], b[3], la[3], lb[3];
        for (int c = 0; c < 3; c++) {
            a[c] = fmin(fmax(finite_or_zero(ref->pixels[3 * p + (size_t)c]) * k, 0.0), 1.0);
            b[c] = fmin(fmax(finite_or_zero(test->pixels[3 * p + (size_t)c]) * k, 0.0), 1.0);
        }
        rgb_to_lab(a, la);
        rgb_to_lab(b, lb);
        double de = sqrt((la[0] - lb[0]) * (la[0] - lb[0]) + (la[1] - lb[1]) * (la[1] - lb[1]) +
                         (la[2] - lb[2]) * (la[2] - lb[2]));
        if (map) map[p] = (float)de;
        sum += de;
    }
    *mean = sum / (double)n;
    return LUMIS_OK;
}
