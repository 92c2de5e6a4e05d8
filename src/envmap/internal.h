/* Internals of the envmap model shared with the samplers (not public API). */
#ifndef LUMIS_ENVMAP_INTERNAL_H
#define LUMIS_ENVMAP_INTERNAL_H

#include "lumis/envmap.h"

#include "../core/internal.h"

#include <stdatomic.h>

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

/* A direction uniform in solid angle inside pixel (i, j) from (s, t) in [0,1)^2 (s along
 * the azimuth, t along cos theta), rotation applied, and pulled off the pixel's edges if
 * rounding to float would move it out: it looks pixel (i, j) up again, as every sampler's
 * directions do (src/envmap/sampler.c).  Returns the pixel's index j w + i. */
size_t lumis__envmap_place(const lumis_envmap *env, int i, int j, double s, double t,
                           lumis_vec3 *dir);

/* Solid angle of the pixel rectangle [x0,x1) x [y0,y1). */
static inline double lumis__rect_solid_angle(const lumis_envmap *env, int x0, int y0, int x1,
                                             int y1)
{
    return (2.0 * LUMIS_PI * (x1 - x0) / env->width) * (env->cos_row[y0] - env->cos_row[y1]);
}

#endif
