/* The k-means centres in a uniform 3D grid over [-1, 1]^3, for radius queries: kmeans.h. */
#include "kmeans.h"

#include <stdlib.h>
#include <string.h>

lumis_status lumis__km_grid_init(km_grid *gr, int k)
{
    /* about one centre per cell of the sphere's surface: spacing sqrt(4 pi / K) */
    int g = (int)(2.0 / sqrt(4.0 * LUMIS_PI / (k > 0 ? k : 1)) + 0.5);
    gr->g = g < 1 ? 1 : (g > 48 ? 48 : g);
    gr->h = 2.0 / gr->g;
    gr->inv_h = gr->g / 2.0;
    const size_t cells = (size_t)gr->g * (size_t)gr->g * (size_t)gr->g;
    gr->start = malloc((cells + 1) * sizeof(int32_t));
    gr->item = malloc((size_t)(k > 0 ? k : 1) * sizeof(int32_t));
    gr->cand = malloc((size_t)(k > 0 ? k : 1) * sizeof(int32_t));
    return gr->start && gr->item && gr->cand ? LUMIS_OK : LUMIS_ERR_OUT_OF_MEMORY;
}

void lumis__km_grid_free(km_grid *gr)
{
    free(gr->start);
    free(gr->item);
    free(gr->cand);
}

static int km_grid_axis(const km_grid *gr, double x)
{
    const double f = (x + 1.0) * gr->inv_h;
    return f < 0.0 ? 0 : (f >= gr->g ? gr->g - 1 : (int)f);
}

static int km_grid_cell(const km_grid *gr, const double *p)
{
    return (km_grid_axis(gr, p[2]) * gr->g + km_grid_axis(gr, p[1])) * gr->g +
           km_grid_axis(gr, p[0]);
}

void lumis__km_grid_build(km_grid *gr, const double *c, int k)
{
    const int cells = gr->g * gr->g * gr->g;
    memset(gr->start, 0, ((size_t)cells + 1) * sizeof(int32_t));
    for (int j = 0; j < k; j++) gr->start[km_grid_cell(gr, c + 3 * (size_t)j) + 1]++;
    for (int q = 0; q < cells; q++) gr->start[q + 1] += gr->start[q];
    for (int j = 0; j < k; j++) gr->item[gr->start[km_grid_cell(gr, c + 3 * (size_t)j)]++] = j;
    for (int q = cells; q > 0; q--) gr->start[q] = gr->start[q - 1];
    gr->start[0] = 0;
}

int lumis__km_grid_query(km_grid *gr, const double *p, double r, int k)
{
    r = r * (1.0 + 1e-12) + 1e-12; /* the box's rounding never drops a centre */
    int lo[3], hi[3];
    double cells = 1.0;
    for (int a = 0; a < 3; a++) {
        lo[a] = km_grid_axis(gr, p[a] - r);
        hi[a] = km_grid_axis(gr, p[a] + r);
        cells *= hi[a] - lo[a] + 1;
    }
    if (4.0 * cells > k) return -1; /* a plain scan costs less */
    int n = 0;
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++) {
            const int row = (z * gr->g + y) * gr->g;
            const int32_t b = gr->start[row + lo[0]], e = gr->start[row + hi[0] + 1];
            for (int32_t t = b; t < e; t++) gr->cand[n++] = gr->item[t];
        }
    return n;
}

double lumis__km_nearest_other(km_grid *gr, const double *c, int k, int j)
{
    const double *cj = c + 3 * (size_t)j;
    for (double r = gr->h;; r *= 2.0) {
        const int n = lumis__km_grid_query(gr, cj, r, k);
        double m2 = INFINITY;
        if (n < 0) {
            for (int b = 0; b < k; b++)
                if (b != j) {
                    const double d2 = sq_dist(cj, c + 3 * (size_t)b);
                    if (d2 < m2) m2 = d2;
                }
            return sqrt(m2);
        }
        for (int t = 0; t < n; t++) {
            const int b = gr->cand[t];
            if (b == j) continue;
            const double d2 = sq_dist(cj, c + 3 * (size_t)b);
            if (d2 < m2) m2 = d2;
        }
        if (m2 <= r * r) return sqrt(m2);
    }
}
