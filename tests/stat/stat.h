/* Statistical helpers for the sampler tests: chi-square survival function and a
 * goodness-of-fit test over bins with pooling (in the manner of Mitsuba's chi2 tests). */
#ifndef LUMIS_TEST_STAT_H
#define LUMIS_TEST_STAT_H

#include <stddef.h>

/* P(X >= x) for X ~ chi-square with dof degrees of freedom. */
double stat_chi2_sf(double x, double dof);

/* Chi-square test of observed counts against expected counts (same total).  Cells with
 * expected < 5 are pooled together (and the pool merged into the smallest cell if still
 * below 5).  Returns the p-value, or -1 if a cell with expected 0 received samples (an
 * impossible sample).  *dof receives the degrees of freedom. */
double stat_chi2_test(const double *observed, const double *expected, size_t n, int *dof);

#endif
