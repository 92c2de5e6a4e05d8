/* Internals of the envmap model shared with the samplers (not public API). */
#ifndef LUMIS_ENVMAP_INTERNAL_H
#define LUMIS_ENVMAP_INTERNAL_H

#include "lumis/envmap.h"

#include "../core/internal.h"

#include <math.h>
#include <stdatomic.h>
#include <stdint.h>
#include <string.h>

struct lumis_envmap {
    int width, height;
    float *pixels; /* sanitized, unscaled */
    float scale;
    float rotation_deg;
    double cos_rot, sin_rot;
    double *row_solid_angle; /* height entries */
    double *cos_row;         /* height + 1 entries: cos(pi j / height), exactly +-1 at the ends */
    lumis_replaced replaced;
    atomic_int refs; /* the creator's reference plus one per sampler */
};

/* Takes a reference (released by lumis_envmap_destroy). */
const lumis_envmap *lumis__envmap_retain(const lumis_envmap *env);

/* Radiance of pixel index j w + i, scale applied (what eval() returns for its directions). */
static inline lumis_rgb lumis__envmap_radiance(const lumis_envmap *env, size_t pixel)
{
    const float *q = env->pixels + 3 * pixel;
    lumis_rgb c = {q[0] * env->scale, q[1] * env->scale, q[2] * env->scale};
    return c;
}

/* A sampler's uniform number clamped into [0, 1) (a float generator rounding up to 1,
 * NaN). */
static inline double lumis__clamp_u(double u)
{
    return u >= 0.0 ? (u < 1.0 ? u : 0x1.fffffffffffffp-1) : 0.0;
}

/* sin and cos of 2 pi a for a >= 0 (a in turns), to about 2e-9: far below the float
 * rounding of the direction, and a fraction of libm's cost.  The argument is reduced to
 * the nearest quarter turn in double (exact to 1e-16), then truncated Taylor series on
 * |r| <= pi/4 (remainders r^11/11! < 1.8e-9 and r^12/12! < 1.2e-10). */
static inline void lumis__sincos_turns(double a, double *sn, double *cs)
{
    int q = (int)(a * 4.0 + 0.5);
    double r = (a - 0.25 * q) * (2.0 * LUMIS_PI), r2 = r * r;
    double s =
        r + r * r2 * (-1.0 / 6 + r2 * (1.0 / 120 + r2 * (-1.0 / 5040 + r2 * (1.0 / 362880))));
    double c =
        1.0 + r2 * (-0.5 + r2 * (1.0 / 24 +
                                 r2 * (-1.0 / 720 + r2 * (1.0 / 40320 + r2 * (-1.0 / 3628800)))));
    /* Quadrant q: swap for odd q and flip signs, on the bits: the quadrant is random, and
     * a mispredicted branch here would discard the work of the samples after it. */
    uint64_t sb, cb, swap = 0 - (uint64_t)(q & 1);
    memcpy(&sb, &s, sizeof s);
    memcpy(&cb, &c, sizeof c);
    uint64_t a1 = ((cb & swap) | (sb & ~swap)) ^ ((uint64_t)(q & 2) << 62);
    uint64_t a2 = ((sb & swap) | (cb & ~swap)) ^ ((uint64_t)((q + 1) & 2) << 62);
    memcpy(sn, &a1, sizeof a1);
    memcpy(cs, &a2, sizeof a2);
}

/* Rounding a direction to float moves it by about 1e-7 radians (the warp's own error is
 * 2e-9); a point at least this far (in radians, or in cos theta, which changes no faster)
 * from every edge of its pixel is certain to look up that pixel again. */
#define LUMIS__EDGE_MARGIN 1e-6

/* A direction uniform in solid angle inside pixel (i, j) from (s, t) in [0,1)^2 (s along
 * the azimuth, t along cos theta), rotation applied, and pulled off the pixel's edges if
 * rounding to float would move it out: it looks pixel (i, j) up again, as every sampler's
 * directions do (src/envmap/sampler.c).  Returns the pixel's index j w + i. */
size_t lumis__envmap_place(const lumis_envmap *env, int i, int j, double s, double t,
                           lumis_vec3 *dir);

/* lumis__envmap_place's common case, inline (a region sampler places a direction per
 * draw): the direction of (s, t) in [0, 1)^2 inside pixel (i, j), uniform in solid angle,
 * rotation applied (inv_w: 1 / the map's width), by the arithmetic of the samplers' warp
 * for a one-pixel rectangle (src/envmap/sampler.c), so the same float; returns 1 when the
 * point is clear of the pixel's edges by LUMIS__EDGE_MARGIN (the direction then looks
 * pixel (i, j) up again), 0 when it is not: the caller then places it with
 * lumis__envmap_place, which pulls it inwards if rounding moved it out. */
static inline int lumis__envmap_place_clear(const lumis_envmap *env, double inv_w, int i, int j,
                                            double s, double t, lumis_vec3 *dir)
{
    const double c0 = env->cos_row[j], c1 = env->cos_row[j + 1];
    const double c = c0 + t * (c1 - c0), s2 = (1.0 - c) * (1.0 + c);
    const double st = sqrt(s2 > 0.0 ? s2 : 0.0);
    double sp, cp;
    lumis__sincos_turns((i + s) * inv_w, &sp, &cp);
    const double m0 = st * cp, m2 = st * sp;
    dir->x = (float)(env->cos_rot * m0 - env->sin_rot * m2);
    dir->y = (float)c;
    dir->z = (float)(env->sin_rot * m0 + env->cos_rot * m2);
    /* distances to the four edges, in radians (azimuth) and in cos theta */
    const double gx = 1.0 - s, ex = s < gx ? s : gx;
    const double dphi = (2.0 * LUMIS_PI) * inv_w * ex;
    const double up = c0 - c, down = c - c1;
    double d = up < down ? up : down;
    d = dphi < d ? dphi : d;
    return d >= LUMIS__EDGE_MARGIN;
}

/* Solid angle of the pixel rectangle [x0,x1) x [y0,y1). */
static inline double lumis__rect_solid_angle(const lumis_envmap *env, int x0, int y0, int x1,
                                             int y1)
{
    return (2.0 * LUMIS_PI * (x1 - x0) / env->width) * (env->cos_row[y0] - env->cos_row[y1]);
}

#endif
