/* Double-precision 3-vectors for the renderer's geometry (internal to lumis-render). */
#ifndef LUMIS_RENDER_VEC_H
#define LUMIS_RENDER_VEC_H

#include "lumis/types.h"

#include <math.h>

typedef struct v3 {
    double x, y, z;
} v3;

static inline v3 mk(double x, double y, double z)
{
    return (v3){x, y, z};
}
static inline v3 fromf(lumis_vec3 a)
{
    return mk(a.x, a.y, a.z);
}
static inline v3 add(v3 a, v3 b)
{
    return mk(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline v3 sub(v3 a, v3 b)
{
    return mk(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline v3 mul(v3 a, double k)
{
    return mk(a.x * k, a.y * k, a.z * k);
}
static inline double dot(v3 a, v3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline v3 cross(v3 a, v3 b)
{
    return mk(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline v3 norm(v3 a)
{
    double l = sqrt(dot(a, a));
    return l > 0.0 ? mul(a, 1.0 / l) : a;
}
static inline lumis_vec3 tof(v3 a)
{
    return (lumis_vec3){(float)a.x, (float)a.y, (float)a.z};
}

/* r a, r a row-major 3x3 rotation; and its transpose's (the inverse) r^T a. */
static inline v3 rot_apply(const double r[9], v3 a)
{
    return mk(r[0] * a.x + r[1] * a.y + r[2] * a.z, r[3] * a.x + r[4] * a.y + r[5] * a.z,
              r[6] * a.x + r[7] * a.y + r[8] * a.z);
}

static inline v3 rot_apply_t(const double r[9], v3 a)
{
    return mk(r[0] * a.x + r[3] * a.y + r[6] * a.z, r[1] * a.x + r[4] * a.y + r[7] * a.z,
              r[2] * a.x + r[5] * a.y + r[8] * a.z);
}

/* Orthonormal basis around n (Duff et al. 2017). */
static inline void basis(v3 n, v3 *t, v3 *b)
{
    double s = n.z >= 0.0 ? 1.0 : -1.0;
    double a = -1.0 / (s + n.z), c = n.x * n.y * a;
    *t = mk(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    *b = mk(c, s + n.y * n.y * a, -n.y);
}

#endif
