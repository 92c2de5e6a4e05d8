/* The progress bar (stderr, only on a terminal), the monotonic clock and medians. */
#include "pipeline.h"

#include <stdio.h>

#include "lumis/metrics.h"
#include "lumis/render.h"

#include <cJSON.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- progress bar (stderr, only when it is a terminal) -------------------------------- */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double tool_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof(double), cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double tool_now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void tool_progress_draw(progress *p, double fraction, int final)
{
    double t = tool_now_seconds();
    if (!final && t - p->last < 0.1) return;
    p->last = t;
    if (fraction > 1.0) fraction = 1.0;
    char bar[41];
    int full = (int)(fraction * 40.0);
    for (int k = 0; k < 40; k++) bar[k] = k < full ? '#' : '.';
    bar[40] = '\0';
    fprintf(stderr, "\r  render [%s] %3d%%  %6.1f s  %d spp", bar, (int)(fraction * 100.0),
            t - p->start, p->spp_done);
    if (final) fputs("\r\033[K", stderr);
    fflush(stderr);
}

void tool_on_progress(void *user, int done, int total)
{
    progress *p = user;
    double f = p->budget > 0.0 ? (tool_now_seconds() - p->start) / p->budget
                               : (total > 0 ? (double)done / total : 1.0);
    tool_progress_draw(p, f, 0);
}
