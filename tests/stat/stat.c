#include "stat.h"

#include <math.h>

/* Regularised upper incomplete gamma Q(a, x): series for x < a + 1, continued fraction
 * (modified Lentz) otherwise. */
static double gamma_q(double a, double x)
{
    if (x <= 0.0) return 1.0;
    double lg = lgamma(a);
    if (x < a + 1.0) {
        double sum = 1.0 / a, term = sum;
        for (int n = 1; n < 100000; n++) {
            term *= x / (a + n);
            sum += term;
            if (fabs(term) < fabs(sum) * 1e-15) break;
        }
        return 1.0 - sum * exp(-x + a * log(x) - lg);
    }
    double b = x + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
    for (int i = 1; i < 100000; i++) {
        double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (fabs(d) < 1e-300) d = 1e-300;
        c = b + an / c;
        if (fabs(c) < 1e-300) c = 1e-300;
        d = 1.0 / d;
        double del = d * c;
        h *= del;
        if (fabs(del - 1.0) < 1e-15) break;
    }
    return exp(-x + a * log(x) - lg) * h;
}

double stat_chi2_sf(double x, double dof)
{
    return gamma_q(0.5 * dof, 0.5 * x);
}

double stat_chi2_test(const double *obs, const double *exp_, size_t n, int *dof)
{
    double chi2 = 0.0, pool_o = 0.0, pool_e = 0.0;
    int cells = 0;
    for (size_t k = 0; k < n; k++) {
        if (exp_[k] == 0.0) {
            if (obs[k] > 0.0) return -1.0;
            continue;
        }
        if (exp_[k] < 5.0) {
            pool_o += obs[k];
            pool_e += exp_[k];
            continue;
        }
        chi2 += (obs[k] - exp_[k]) * (obs[k] - exp_[k]) / exp_[k];
        cells++;
    }
    if (pool_e > 0.0) {
        if (pool_e >= 5.0 || cells == 0) {
            chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
            cells++;
        }
        /* else: a pool under 5 is too small to test and is left out (a conservative
         * choice: it can only lower the statistic by a term of dubious distribution). */
    }
    *dof = cells > 1 ? cells - 1 : 1;
    return cells > 1 ? stat_chi2_sf(chi2, *dof) : 1.0;
}
