/* Low-discrepancy building blocks: Owen scrambling by hashing, the Owen-scrambled (0,2)
 * Sobol' sequence, and the progressive multi-jittered (0,2) generator.
 * Derivations and the tests that pin each property: docs/sampling.md. */
#include "lumis/rng.h"

#include "internal.h"

#include <stdlib.h>
#include <string.h>

static const char *const sequence_names[] = {"default", "pcg",    "halton", "stratified",
                                             "sobol",   "zsobol", "pmj02"};

LUMIS__ENUM_NAMES(lumis_sequence, LUMIS_SEQUENCE_COUNT, sequence_names, lumis_sequence_name,
                  lumis_sequence_from_name);

lumis_sequence lumis_sequence_resolve(lumis_sequence q)
{
    return q == LUMIS_SEQUENCE_DEFAULT ? LUMIS_SEQUENCE_SOBOL : q;
}

void lumis_sobol02(uint32_t index, uint64_t seed, double u[2])
{
    const uint64_t h = lumis__mix64(seed);
    u[0] = lumis_owen_scramble(lumis_sobol02_bits(index, 0), (uint32_t)h) * 0x1p-32;
    u[1] = lumis_owen_scramble(lumis_sobol02_bits(index, 1), (uint32_t)(h >> 32)) * 0x1p-32;
}

/* ---- progressive multi-jittered (0,2) points -------------------------------------------- */

/* Occupancy of the elementary intervals of one level m (2^m points): shape a is the grid of
 * 2^a columns by 2^(m-a) rows, a = 0 .. m, one byte per cell. */
typedef struct pmj_grid {
    int m;
    uint8_t *cell; /* (m + 1) 2^m */
} pmj_grid;

static size_t pmj_cell(const pmj_grid *g, int a, uint32_t X, uint32_t Y)
{
    /* X, Y: the point's stratum at resolution 2^m on each axis */
    const int m = g->m;
    return ((size_t)a << m) + (((size_t)(Y >> a) << a) | (X >> (m - a)));
}

static int pmj_free(const pmj_grid *g, uint32_t X, uint32_t Y)
{
    for (int a = 0; a <= g->m; a++)
        if (g->cell[pmj_cell(g, a, X, Y)]) return 0;
    return 1;
}

static void pmj_occupy(pmj_grid *g, uint32_t X, uint32_t Y)
{
    for (int a = 0; a <= g->m; a++) g->cell[pmj_cell(g, a, X, Y)] = 1;
}

/* Adds point i at a position uniform among those of sub-quadrant (sx, sy) (the cell of
 * side 2^-h at (cx, cy), halves sx, sy) that fill no occupied interval of level m.
 * Returns 0 when none is left. */
static int pmj_place(pmj_grid *g, uint32_t *xy, uint32_t i, int h, uint32_t cx, uint32_t cy, int sx,
                     int sy, lumis_pcg32 *rng, uint32_t *cand)
{
    const int m = g->m, r = m - (h + 1); /* strata of level m per sub-quadrant: 2^r */
    const uint32_t x0 = ((cx << 1) | (uint32_t)sx) << r, y0 = ((cy << 1) | (uint32_t)sy) << r;
    uint32_t count = 0;
    for (uint32_t X = x0; X < x0 + (1u << r); X++) {
        if (g->cell[pmj_cell(g, m, X, 0)]) continue; /* the column is taken */
        for (uint32_t Y = y0; Y < y0 + (1u << r); Y++)
            if (pmj_free(g, X, Y)) cand[count++] = (X << 16) ^ Y;
    }
    if (count == 0) return 0;
    const uint32_t c = cand[lumis_pcg32_bounded(rng, count)];
    const uint32_t X = c >> 16, Y = c & 0xffffu;
    pmj_occupy(g, X, Y);
    /* uniform inside the chosen cell of the finest grid (the jitter) */
    const uint32_t low = m < 32 ? (1u << (32 - m)) - 1u : 0u;
    xy[2 * i] = (X << (32 - m)) | (lumis_pcg32_next(rng) & low);
    xy[2 * i + 1] = (Y << (32 - m)) | (lumis_pcg32_next(rng) & low);
    return 1;
}

/* Doubles n points to 2n (level m = log2(2n)).  Christensen et al.'s rule: with n = 4^k
 * each point's partner goes to the sub-quadrant diagonally opposite its own in its cell of
 * the 2^k grid; with n = 2 4^k each cell of that grid holds two points on one diagonal,
 * and its two new points take the other diagonal, which one where drawn at random. */
static int pmj_extend(pmj_grid *g, uint32_t *xy, uint32_t n, lumis_pcg32 *rng, uint32_t *cand)
{
    memset(g->cell, 0, ((size_t)g->m + 1) << g->m);
    const int m = g->m;
    for (uint32_t i = 0; i < n; i++)
        pmj_occupy(g, xy[2 * i] >> (32 - m), xy[2 * i + 1] >> (32 - m));
    int k = 0;
    while ((1u << (2 * (k + 1))) <= n) k++;
    const int even = (1u << (2 * k)) == n; /* n = 4^k, else n = 2 4^k */
    const uint32_t half = even ? n : n / 2;
    for (uint32_t i = 0; i < half; i++) {
        const uint32_t x = xy[2 * i], y = xy[2 * i + 1];
        const uint32_t cx = k ? x >> (32 - k) : 0u, cy = k ? y >> (32 - k) : 0u;
        const int sx = (int)((x >> (31 - k)) & 1u), sy = (int)((y >> (31 - k)) & 1u);
        if (even) {
            if (!pmj_place(g, xy, n + i, k, cx, cy, !sx, !sy, rng, cand)) return 0;
        } else {
            const int flip = (int)(lumis_pcg32_next(rng) & 1u);
            const uint32_t a = n + i, b = n + half + i;
            if (!pmj_place(g, xy, flip ? b : a, k, cx, cy, sx, !sy, rng, cand) ||
                !pmj_place(g, xy, flip ? a : b, k, cx, cy, !sx, sy, rng, cand))
                return 0;
        }
    }
    return 1;
}

lumis_status lumis_pmj02_generate(uint32_t n, uint64_t seed, uint32_t *xy)
{
    if (!xy || n == 0 || n > (1u << 20) || (n & (n - 1)) != 0) return LUMIS_ERR_INVALID_ARGUMENT;
    int M = 0;
    while ((1u << M) < n) M++;
    pmj_grid g = {0, malloc(((size_t)M + 1) << M)};
    uint32_t *cand = malloc(sizeof *cand << (M > 0 ? M : 1));
    if (!g.cell || !cand) {
        free(g.cell);
        free(cand);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, lumis__mix64(seed), 0x706d6a3032ull);
    xy[0] = lumis_pcg32_next(&rng);
    xy[1] = lumis_pcg32_next(&rng);
    if (n == 1) {
        free(g.cell);
        free(cand);
        return LUMIS_OK;
    }
    for (uint32_t have = 1; have < n;) {
        g.m = 0;
        while ((1u << g.m) < 2 * have) g.m++;
        /* A greedy choice can leave a new point no free position; the doubling is then
         * drawn again (the first `have` points stay). */
        int ok = 0;
        for (int attempt = 0; attempt < 64 && !ok; attempt++)
            ok = pmj_extend(&g, xy, have, &rng, cand);
        if (!ok) break;
        have *= 2;
        if (have == n) {
            free(g.cell);
            free(cand);
            return LUMIS_OK;
        }
    }
    free(g.cell);
    free(cand);
    return LUMIS_ERR_UNSUPPORTED; /* no valid doubling in 64 draws: not seen in tests */
}
