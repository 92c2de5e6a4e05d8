/* Internals of the envmap model shared with the samplers (not public API). */
#ifndef LUMIS_ENVMAP_INTERNAL_H
#define LUMIS_ENVMAP_INTERNAL_H

#include "lumis/envmap.h"

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

#endif
