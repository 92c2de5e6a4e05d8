/* The Embree scene (internal to lumis-render): what a hit holds, and one ray's intersection
 * and occlusion, inline for the integrator's inner loops.  Built by scene.c. */
#ifndef LUMIS_RENDER_SCENE_H
#define LUMIS_RENDER_SCENE_H

#include "lumis/render.h"

#include "vec.h"

#include <embree3/rtcore.h>
#include <math.h>

typedef struct prim {
    lumis_object_type type;
    lumis_vec3 center, normal; /* sphere centre; plane normal */
    int instanced;             /* a mesh shared with other objects: an Embree instance */
    double cof[9];             /* instanced: maps object-space normals to world space */
    RTCScene child;            /* instanced: the shared mesh (owned by lumis_scene.shared) */
    lumis_bsdf material;
} prim;

struct lumis_scene {
    RTCDevice device;
    RTCScene rtc;
    RTCScene *shared; /* one per mesh used by several objects */
    int shared_count;
    prim *prims; /* indexed by Embree geometry id (top level) */
    int count;
};

typedef struct hit {
    v3 p, n; /* n faces the incoming ray */
    const prim *prim;
} hit;

static inline int intersect(const lumis_scene *s, v3 o, v3 d, hit *h)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    rh.ray.org_x = (float)o.x;
    rh.ray.org_y = (float)o.y;
    rh.ray.org_z = (float)o.z;
    rh.ray.dir_x = (float)d.x;
    rh.ray.dir_y = (float)d.y;
    rh.ray.dir_z = (float)d.z;
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = INFINITY;
    rh.ray.mask = 0xffffffffu;
    rh.ray.flags = 0;
    rh.ray.time = 0.0f;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(s->rtc, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
    unsigned top = rh.hit.instID[0] != RTC_INVALID_GEOMETRY_ID ? rh.hit.instID[0] : rh.hit.geomID;
    h->prim = &s->prims[top];
    h->p = add(o, mul(d, rh.ray.tfar));
    if (h->prim->type == LUMIS_OBJECT_SPHERE) {
        h->n = norm(sub(h->p, fromf(h->prim->center)));
    } else if (h->prim->type == LUMIS_OBJECT_PLANE) {
        h->n = fromf(h->prim->normal);
    } else {
        v3 ng = mk(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z); /* object space if instanced */
        if (h->prim->instanced) {
            const double *c = h->prim->cof;
            ng =
                mk(c[0] * ng.x + c[1] * ng.y + c[2] * ng.z, c[3] * ng.x + c[4] * ng.y + c[5] * ng.z,
                   c[6] * ng.x + c[7] * ng.y + c[8] * ng.z);
        }
        h->n = norm(ng);
    }
    if (dot(h->n, d) > 0.0) h->n = mul(h->n, -1.0);
    return 1;
}

static inline int occluded(const lumis_scene *s, const lumis_render_desc *desc, v3 o, v3 d)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay r;
    r.org_x = (float)o.x;
    r.org_y = (float)o.y;
    r.org_z = (float)o.z;
    r.dir_x = (float)d.x;
    r.dir_y = (float)d.y;
    r.dir_z = (float)d.z;
    r.tnear = 0.0f;
    r.tfar = INFINITY;
    r.mask = 0xffffffffu;
    r.flags = 0;
    r.time = 0.0f;
    if (desc->shadow_ray) {
        const float of[3] = {r.org_x, r.org_y, r.org_z}, df[3] = {r.dir_x, r.dir_y, r.dir_z};
        desc->shadow_ray(desc->shadow_ray_user, of, df);
    }
    rtcOccluded1(s->rtc, &ctx, &r);
    return r.tfar < 0.0f;
}

#endif
