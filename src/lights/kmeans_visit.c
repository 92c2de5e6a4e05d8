/* An assignment step of the EnvDirects' k-means, one cluster at a time: the members whose
 * lazy Hamerly bound fails, re-evaluated against the near centres; scalar, and with
 * AVX-512 eight members at a time (the same operations in the same order: the same bits).
 * kmeans.h. */
#include "kmeans.h"

#ifdef KM_AVX512
#include <immintrin.h>
#endif

/* The positions q0 <= q < n whose bound fails, !(key[q] - now > KM_MARGIN), in ascending
 * order into out; returns their number.  Scalar: branchless, one member at a time. */
static int km_failing(const double *key, int q0, int n, double now, int32_t *out)
{
    int nf = 0;
    for (int q = q0; q < n; q++) {
        out[nf] = q;
        nf += !(key[q] - now > KM_MARGIN);
    }
    return nf;
}

#ifdef KM_AVX512
/* The same with AVX-512: sixteen keys per step, the failing positions compressed in a
 * register and stored whole (a compressing store to memory is microcoded and measured
 * slower than the scalar loop), so out needs room for n + 16.  The same subtraction and
 * comparison: the same positions in the same order. */
__attribute__((target("avx512f"))) static int km_failing_avx512(const double *key, int n,
                                                                double now, int32_t *out)
{
    const __m512d vnow = _mm512_set1_pd(now), vm = _mm512_set1_pd(KM_MARGIN);
    __m512i idx = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const __m512i step = _mm512_set1_epi32(16);
    int nf = 0, q = 0;
    for (; q + 16 <= n; q += 16) {
        const __mmask8 p0 =
            _mm512_cmp_pd_mask(_mm512_sub_pd(_mm512_loadu_pd(key + q), vnow), vm, _CMP_GT_OQ);
        const __mmask8 p1 =
            _mm512_cmp_pd_mask(_mm512_sub_pd(_mm512_loadu_pd(key + q + 8), vnow), vm, _CMP_GT_OQ);
        const __mmask16 f = (__mmask16) ~((unsigned)p0 | ((unsigned)p1 << 8));
        _mm512_storeu_si512((void *)(out + nf), _mm512_maskz_compress_epi32(f, idx));
        nf += __builtin_popcount((unsigned)f);
        idx = _mm512_add_epi32(idx, step);
    }
    return nf + km_failing(key, q, n, now, out + nf);
}
#endif

/* Failing member q of cluster ca compared with the near centres nb[0 .. nn): the nearest
 * (the current centre, then the first in nb's order, wins ties) into *bd's centre, the
 * second-largest dot product into *sec. */
static inline LUMIS__ALWAYS_INLINE int km_nearest(const double *c, int ca, const int32_t *nb,
                                                  int nn, double x0, double x1, double x2,
                                                  double da, double *bd_out, double *sec_out)
{
    int best = ca;
    double bd = da, sec = -INFINITY;
    for (int t = 0; t < nn; t++) {
        const double *cb = c + 3 * (size_t)nb[t];
        double dt = x0 * cb[0] + x1 * cb[1] + x2 * cb[2];
        if (dt > bd) { /* the current centre wins ties */
            sec = bd;
            bd = dt;
            best = nb[t];
        } else if (dt > sec) {
            sec = dt;
        }
    }
    *bd_out = bd;
    *sec_out = sec;
    return best;
}

/* The member's new bound, or its move: centres beyond the reach are at least far - |x - c_a|
 * away.  Returns the number of moves. */
static inline LUMIS__ALWAYS_INLINE int km_settle(km_cluster *cl, int q, int ca, int best, double da,
                                                 double bd, double sec, double far, double now,
                                                 km_move *moves, int nm)
{
    const double ua = chord_bound(da), lo = chord_lower(sec), lf = far - ua;
    const double lb = lo < lf ? lo : lf; /* no NaN here: no libm fmin */
    const double slack = lb - (best == ca ? ua : chord_bound(bd));
    if (best == ca) {
        cl->key[q] = slack + now;
    } else {
        moves[nm++] = (km_move){cl->id[q], best, slack};
    }
    return nm;
}

/* The failing members fail[0 .. nf) of cluster ca (centre c + 3 ca) re-evaluated against
 * the near centres nb[0 .. nn); returns the new number of moves. */
static int km_visit(km_cluster *cl, const int32_t *fail, int nf, const double *c, int ca,
                    const int32_t *nb, int nn, double far, double now, km_move *moves, int nm)
{
    const double *cc = c + 3 * (size_t)ca;
    for (int f = 0; f < nf; f++) {
        const int q = fail[f];
        const double x0 = cl->x[q], x1 = cl->y[q], x2 = cl->z[q];
        const double da = x0 * cc[0] + x1 * cc[1] + x2 * cc[2];
        double bd, sec;
        const int best = km_nearest(c, ca, nb, nn, x0, x1, x2, da, &bd, &sec);
        nm = km_settle(cl, q, ca, best, da, bd, sec, far, now, moves, nm);
    }
    return nm;
}

#ifdef KM_AVX512
/* km_visit for eight failing members at a time with AVX-512, lane by lane the scalar
 * arithmetic: the dot products with their centre and with each near centre (the largest
 * kept per lane), and for a member that stays, which is most of them (no near centre's dot
 * product exceeds its own centre's), the new bound: its nearest is its centre and its
 * second-largest dot product the near centres' largest.  A member that may move goes
 * through the scalar km_nearest (first wins ties) and km_settle, in member order, so the
 * moves are listed as km_visit lists them.  Same operations in the same order, no
 * contraction (-ffp-contract=off on this file), and IEEE square roots: the same bits. */
/* GCC's gather and scatter macros (unoptimised builds) convert their mask with a sign
 * change that -Wconversion reports; the masks here are plain 8-bit lane masks. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-conversion"
__attribute__((target("avx512f"))) static int km_visit_avx512(km_cluster *cl, const int32_t *fail,
                                                              int nf, const double *c, int ca,
                                                              const int32_t *nb, int nn, double far,
                                                              double now, km_move *moves, int nm)
{
    if (nn == 0) return km_visit(cl, fail, nf, c, ca, nb, nn, far, now, moves, nm);
    const double *cc = c + 3 * (size_t)ca;
    const __m512d c0 = _mm512_set1_pd(cc[0]), c1 = _mm512_set1_pd(cc[1]),
                  c2 = _mm512_set1_pd(cc[2]), two = _mm512_set1_pd(2.0), zero = _mm512_setzero_pd(),
                  eps = _mm512_set1_pd(4e-15), vfar = _mm512_set1_pd(far),
                  vnow = _mm512_set1_pd(now);
    for (int f = 0; f < nf; f += 8) {
        const __mmask8 live = (__mmask8)(nf - f >= 8 ? 0xff : (1u << (nf - f)) - 1u);
        /* fail has room (zeroed) for 16 past its members: inactive lanes are never used */
        const __m256i qi = _mm256_loadu_si256((const __m256i *)(const void *)(fail + f));
        const __m512d x0 = _mm512_mask_i32gather_pd(zero, live, qi, cl->x, 8),
                      x1 = _mm512_mask_i32gather_pd(zero, live, qi, cl->y, 8),
                      x2 = _mm512_mask_i32gather_pd(zero, live, qi, cl->z, 8);
        const __m512d da = _mm512_add_pd(
            _mm512_add_pd(_mm512_mul_pd(x0, c0), _mm512_mul_pd(x1, c1)), _mm512_mul_pd(x2, c2));
        __m512d m1 = _mm512_set1_pd(-INFINITY);
        for (int t = 0; t < nn; t++) {
            const double *cb = c + 3 * (size_t)nb[t];
            const __m512d dt =
                _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(x0, _mm512_set1_pd(cb[0])),
                                            _mm512_mul_pd(x1, _mm512_set1_pd(cb[1]))),
                              _mm512_mul_pd(x2, _mm512_set1_pd(cb[2])));
            m1 = _mm512_max_pd(m1, dt);
        }
        /* the members that stay: chord_bound(da), chord_lower(m1), the slack, the key */
        const __mmask8 moving = _mm512_mask_cmp_pd_mask(live, m1, da, _CMP_GT_OQ);
        const __mmask8 stay = (__mmask8)(live & ~moving);
        const __m512d ua = _mm512_sqrt_pd(
            _mm512_add_pd(_mm512_max_pd(_mm512_sub_pd(two, _mm512_mul_pd(two, da)), zero), eps));
        const __m512d lo = _mm512_sqrt_pd(
            _mm512_max_pd(_mm512_sub_pd(_mm512_sub_pd(two, _mm512_mul_pd(two, m1)), eps), zero));
        const __m512d lb = _mm512_min_pd(lo, _mm512_sub_pd(vfar, ua));
        const __m512d key = _mm512_add_pd(_mm512_sub_pd(lb, ua), vnow);
        _mm512_mask_i32scatter_pd(cl->key, stay, qi, key, 8);
        for (unsigned mv = moving; mv; mv &= mv - 1) {
            const int q = fail[f + __builtin_ctz(mv)];
            const double y0 = cl->x[q], y1 = cl->y[q], y2 = cl->z[q];
            const double d = y0 * cc[0] + y1 * cc[1] + y2 * cc[2];
            double bd, sec;
            const int best = km_nearest(c, ca, nb, nn, y0, y1, y2, d, &bd, &sec);
            nm = km_settle(cl, q, ca, best, d, bd, sec, far, now, moves, nm);
        }
    }
    return nm;
}
#pragma GCC diagnostic pop
#endif

int lumis__km_visit_cluster(km_cluster *cl, const double *c, int ca, const int32_t *nb, int nn,
                            double far, double now, int avx512, int32_t *fail, km_move *moves,
                            int nm)
{
#ifdef KM_AVX512
    if (avx512) {
        const int nf = km_failing_avx512(cl->key, cl->n, now, fail);
        return km_visit_avx512(cl, fail, nf, c, ca, nb, nn, far, now, moves, nm);
    }
#else
    (void)avx512;
#endif
    const int nf = km_failing(cl->key, 0, cl->n, now, fail);
    return km_visit(cl, fail, nf, c, ca, nb, nn, far, now, moves, nm);
}
