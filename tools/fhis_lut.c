/* fhis-lut: computes FHIS's correction-vector table (src/lights/fhis_lut.h) by Lloyd
 * relaxation, as Ostromoukhov, Donohue & Jodoin (2004) describe it: for each of the 21
 * importance indices, the Penrose point set of that constant importance is relaxed, and
 * each point's displacement, in its tile's frame and scale, is averaged over the points of
 * each of the 21 structural indices (three importances across each index's bin).  docs/lights.md
 * (FHIS) says how the table is used.
 *
 *   fhis-lut [--iterations N] [--size D] [--grid R] OUT.h
 *   fhis-lut --spacing
 *
 * N Lloyd steps (default 40) on a D x D domain (default 1024) whose Voronoi cells are
 * measured on an R x R raster (default 1024); statistics from the points at least an eighth
 * of D inside the domain.  The output is written to a temporary file and renamed.
 * --spacing reports what the compiled-in table does: the mean and smallest nearest-neighbour
 * distance, in units of sqrt(area per point), of constant-importance point sets on 512^2
 * without and with the correction (interior points; hexagonal packing gives 1.075). */
#include "lights/fhis_lut.h"
#include "lights/penrose.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PHI   1.6180339887498948482
#define SQRT5 2.2360679774997896964

typedef struct pt {
    double x, y;   /* current position */
    double x0, y0; /* the tile's point */
    int dir, is;   /* tile orientation, structural index */
    double s;      /* tile scale */
} pt;

typedef struct pts {
    pt *p;
    size_t n, cap;
} pts;

static int push(pts *v, const lumis__ptile *t)
{
    if (v->n == v->cap) {
        size_t cap = v->cap ? 2 * v->cap : 1024;
        pt *q = realloc(v->p, cap * sizeof *q);
        if (!q) return -1;
        v->p = q;
        v->cap = cap;
    }
    pt *q = &v->p[v->n++];
    q->x = q->x0 = t->p1[0];
    q->y = q->y0 = t->p1[1];
    q->dir = t->dir;
    q->is = lumis__penrose_structural_index(t->fcode);
    q->s = t->s;
    return 0;
}

/* The point set of constant importance I on [0, D]^2: every tile down to the level I asks
 * for, sampling tiles kept where I reaches their F-code value (as FHIS does). */
static int generate(const lumis__ptile *t, double I, int level, double D, pts *out)
{
    if (t->type == LUMIS__PT_A || t->type == LUMIS__PT_B) {
        if (t->level < level) {
            lumis__ptile c[4];
            lumis__ptile_split(t, c);
            return generate(&c[0], I, level, D, out);
        }
        if (I < lumis__fcode_value(t->fcode, 2 * t->level)) return 0;
        if (t->p1[0] < 0.0 || t->p1[0] >= D || t->p1[1] < 0.0 || t->p1[1] >= D) return 0;
        return push(out, t);
    }
    double p[3][2];
    lumis__ptile_vertices(t, p);
    double x0 = fmin(p[0][0], fmin(p[1][0], p[2][0])), x1 = fmax(p[0][0], fmax(p[1][0], p[2][0]));
    double y0 = fmin(p[0][1], fmin(p[1][1], p[2][1])), y1 = fmax(p[0][1], fmax(p[1][1], p[2][1]));
    if (x1 < 0.0 || y1 < 0.0 || x0 >= D || y0 >= D || t->level >= level) return 0;
    lumis__ptile c[4];
    int n = lumis__ptile_split(t, c);
    for (int k = 0; k < n; k++)
        if (generate(&c[k], I, level, D, out)) return -1;
    return 0;
}

/* Lloyd steps: each raster cell goes to its nearest point (a bucket grid of the points),
 * each point moves to the centroid of its cells. */
static int relax(pts *v, double D, int R, int iterations)
{
    const int B = (int)ceil(sqrt((double)v->n / 2.0)) + 1; /* buckets per side */
    const double bs = D / B;
    int *head = malloc((size_t)B * (size_t)B * sizeof(int));
    int *next = malloc(v->n * sizeof(int));
    double *sx = malloc(v->n * sizeof(double)), *sy = malloc(v->n * sizeof(double));
    double *sw = malloc(v->n * sizeof(double));
    if (!head || !next || !sx || !sy || !sw) {
        free(head), free(next), free(sx), free(sy), free(sw);
        return -1;
    }
    for (int it = 0; it < iterations; it++) {
        for (int b = 0; b < B * B; b++) head[b] = -1;
        for (size_t k = 0; k < v->n; k++) {
            int bx = (int)(v->p[k].x / bs), by = (int)(v->p[k].y / bs);
            bx = bx < 0 ? 0 : (bx >= B ? B - 1 : bx);
            by = by < 0 ? 0 : (by >= B ? B - 1 : by);
            next[k] = head[by * B + bx];
            head[by * B + bx] = (int)k;
            sx[k] = sy[k] = sw[k] = 0.0;
        }
        const double cell = D / R;
        for (int j = 0; j < R; j++)
            for (int i = 0; i < R; i++) {
                const double x = (i + 0.5) * cell, y = (j + 0.5) * cell;
                const int bx = (int)(x / bs), by = (int)(y / bs);
                int best = -1;
                double bd = INFINITY;
                /* rings of buckets until the nearest found is provably nearest */
                for (int r = 0; r < B; r++) {
                    for (int yy = by - r; yy <= by + r; yy++)
                        for (int xx = bx - r; xx <= bx + r; xx++) {
                            if (xx < 0 || yy < 0 || xx >= B || yy >= B) continue;
                            if (r > 0 && xx > bx - r && xx < bx + r && yy > by - r && yy < by + r)
                                continue;
                            for (int k = head[yy * B + xx]; k >= 0; k = next[k]) {
                                double dx = v->p[k].x - x, dy = v->p[k].y - y,
                                       d = dx * dx + dy * dy;
                                if (d < bd) {
                                    bd = d;
                                    best = k;
                                }
                            }
                        }
                    if (best >= 0 && sqrt(bd) <= r * bs) break;
                }
                sx[best] += x;
                sy[best] += y;
                sw[best] += 1.0;
            }
        for (size_t k = 0; k < v->n; k++)
            if (sw[k] > 0.0) {
                v->p[k].x = sx[k] / sw[k];
                v->p[k].y = sy[k] / sw[k];
            }
    }
    free(head), free(next), free(sx), free(sy), free(sw);
    return 0;
}

/* Mean and smallest nearest-neighbour distance of the interior points (brute force). */
static void nn_stats(const pts *v, double D, double *mean, double *min)
{
    const double a = sqrt(D * D / (double)v->n);
    double sum = 0.0, lo = INFINITY;
    long m = 0;
    for (size_t i = 0; i < v->n; i++) {
        const pt *p = &v->p[i];
        if (p->x < D / 8 || p->x > D - D / 8 || p->y < D / 8 || p->y > D - D / 8) continue;
        double b = INFINITY;
        for (size_t j = 0; j < v->n; j++)
            if (j != i) {
                double dx = p->x - v->p[j].x, dy = p->y - v->p[j].y, d = dx * dx + dy * dy;
                if (d < b) b = d;
            }
        b = sqrt(b) / a;
        sum += b;
        lo = b < lo ? b : lo;
        m++;
    }
    *mean = m ? sum / (double)m : 0.0;
    *min = lo;
}

static int spacing(void)
{
    const double D = 512.0;
    const lumis__ptile root = lumis__penrose_root(D, D);
    printf("importance index   points   mean NN (none / table)   min NN (none / table)\n");
    for (int iv = 0; iv < LUMIS__PENROSE_LUT; iv += 4) {
        const double I = (pow(PHI * PHI, 11.0 + (iv + 0.3) / LUMIS__PENROSE_LUT) - 1.0) / SQRT5;
        int level = lumis__penrose_level_for(I);
        if (level < 6) level = 6;
        pts v = {0};
        if (generate(&root, I, level, D, &v)) return 1;
        double m0, n0, m1, n1;
        nn_stats(&v, D, &m0, &n0);
        const int iI = lumis__penrose_importance_index(I);
        for (size_t k = 0; k < v.n; k++) { /* the table's move, in the tile's frame */
            pt *q = &v.p[k];
            double a[2], b[2];
            const float *uw = lumis__fhis_lut[iI][q->is];
            lumis__penrose_dir(q->dir, a);
            lumis__penrose_dir(q->dir + 5, b);
            q->x = q->x0 + q->s * ((double)uw[0] * a[0] + (double)uw[1] * b[0]);
            q->y = q->y0 + q->s * ((double)uw[0] * a[1] + (double)uw[1] * b[1]);
        }
        nn_stats(&v, D, &m1, &n1);
        printf("%16d %8zu   %9.3f / %.3f          %9.3f / %.3f\n", iI, v.n, m0, m1, n0, n1);
        free(v.p);
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 2 && !strcmp(argv[1], "--spacing")) return spacing();
    int iterations = 40, R = 1024;
    double D = 1024.0;
    const char *out = NULL;
    for (int a = 1; a < argc; a++) {
        if (!strcmp(argv[a], "--iterations") && a + 1 < argc)
            iterations = atoi(argv[++a]);
        else if (!strcmp(argv[a], "--size") && a + 1 < argc)
            D = atof(argv[++a]);
        else if (!strcmp(argv[a], "--grid") && a + 1 < argc)
            R = atoi(argv[++a]);
        else if (argv[a][0] != '-' && !out)
            out = argv[a];
        else {
            fprintf(stderr,
                    "usage: fhis-lut [--iterations N] [--size D] [--grid R] OUT.h | --spacing\n");
            return 2;
        }
    }
    if (!out || iterations < 1 || R < 16 || !(D >= 64.0)) {
        fprintf(stderr,
                "usage: fhis-lut [--iterations N] [--size D] [--grid R] OUT.h | --spacing\n");
        return 2;
    }
    static double sum[LUMIS__PENROSE_LUT][LUMIS__PENROSE_LUT][2];
    static long cnt[LUMIS__PENROSE_LUT][LUMIS__PENROSE_LUT];
    /* about I points per root area: importances of one period of log_{phi^2} beyond
     * phi^24 give ~10^4 points on [0, D]^2 */
    const lumis__ptile root = lumis__penrose_root(D, D);
    for (int iv = 0; iv < LUMIS__PENROSE_LUT; iv++)
        for (int sub = 0; sub < 3; sub++) { /* three importances across the index's bin */
            const double t = 12.0 + (iv + (2 * sub + 1) / 6.0) / LUMIS__PENROSE_LUT;
            const double I = (pow(PHI * PHI, t) - 1.0) / SQRT5;
            if (lumis__penrose_importance_index(I) != iv) {
                fprintf(stderr, "fhis-lut: importance %g is not of index %d\n", I, iv);
                return 1;
            }
            int level = lumis__penrose_level_for(I);
            if (level < 6) level = 6;
            pts v = {0};
            if (generate(&root, I, level, D, &v) || relax(&v, D, R, iterations)) {
                fprintf(stderr, "fhis-lut: out of memory\n");
                return 1;
            }
            for (size_t k = 0; k < v.n; k++) {
                const pt *q = &v.p[k];
                if (q->x0 < D / 8 || q->x0 > D - D / 8 || q->y0 < D / 8 || q->y0 > D - D / 8)
                    continue;
                double a[2], b[2], dx = q->x - q->x0, dy = q->y - q->y0;
                lumis__penrose_dir(q->dir, a);
                lumis__penrose_dir(q->dir + 5, b);
                sum[iv][q->is][0] += (dx * a[0] + dy * a[1]) / q->s;
                sum[iv][q->is][1] += (dx * b[0] + dy * b[1]) / q->s;
                cnt[iv][q->is]++;
            }
            fprintf(stderr, "fhis-lut: importance index %2d.%d: %zu points, level %d\n", iv, sub,
                    v.n, level);
            free(v.p);
        }
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.tmp", out) >= (int)sizeof tmp) return 1;
    FILE *f = fopen(tmp, "w");
    if (!f) {
        fprintf(stderr, "fhis-lut: cannot write %s: %s\n", tmp, strerror(errno));
        return 1;
    }
    fprintf(f,
            "/* FHIS correction vectors (u, w) per importance index (rows) and structural index\n"
            " * (columns), in the tile's frame and scale; (0, 0) where no point has that index.\n"
            " * Generated by tools/fhis_lut.c (do not edit):\n"
            " *   fhis-lut --iterations %d --size %g --grid %d OUT.h */\n",
            iterations, D, R);
    /* clang-format would rewrap the rows: the table stays as written, three pairs a line */
    fprintf(f, "#ifndef LUMIS_LIGHTS_FHIS_LUT_H\n#define LUMIS_LIGHTS_FHIS_LUT_H\n\n"
               "/* clang-format off */\n");
    fprintf(f, "static const float lumis__fhis_lut[%d][%d][2] = {\n", LUMIS__PENROSE_LUT,
            LUMIS__PENROSE_LUT);
    for (int iv = 0; iv < LUMIS__PENROSE_LUT; iv++) {
        fprintf(f, "    {");
        for (int is = 0; is < LUMIS__PENROSE_LUT; is++) {
            double u = cnt[iv][is] ? sum[iv][is][0] / (double)cnt[iv][is] : 0.0;
            double w = cnt[iv][is] ? sum[iv][is][1] / (double)cnt[iv][is] : 0.0;
            fprintf(f, "%s{%.6ff, %.6ff}", is ? (is % 3 == 0 ? ",\n     " : ", ") : "", u, w);
        }
        fprintf(f, "}%s\n", iv + 1 < LUMIS__PENROSE_LUT ? "," : "");
    }
    fprintf(f, "};\n/* clang-format on */\n\n#endif\n");
    if (fclose(f) != 0 || rename(tmp, out) != 0) {
        fprintf(stderr, "fhis-lut: cannot write %s: %s\n", out, strerror(errno));
        remove(tmp);
        return 1;
    }
    return 0;
}
