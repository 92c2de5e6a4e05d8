/* The evaluation renderer: an Embree scene, a pinhole camera, and direct illumination
 * from the environment map with light, BSDF or multiple importance sampling.
 * Determinism: every pixel draws from its own PCG32 stream (the pixel's index), so the
 * image depends on the seed and never on how rows are spread over threads. */
#include "lumis/render.h"
#include "lumis/rng.h"

#include "../core/internal.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

typedef struct prim {
    lumis_object_type type;
    lumis_vec3 center, normal; /* sphere centre; plane normal */
    lumis_bsdf material;
} prim;

struct lumis_scene {
    RTCDevice device;
    RTCScene rtc;
    prim *prims; /* indexed by Embree geometry id */
    int count;
};

/* ---- small vector helpers ------------------------------------------------------------ */

typedef struct v3 {
    double x, y, z;
} v3;

static v3 mk(double x, double y, double z)
{
    return (v3){x, y, z};
}
static v3 fromf(lumis_vec3 a)
{
    return mk(a.x, a.y, a.z);
}
static v3 add(v3 a, v3 b)
{
    return mk(a.x + b.x, a.y + b.y, a.z + b.z);
}
static v3 sub(v3 a, v3 b)
{
    return mk(a.x - b.x, a.y - b.y, a.z - b.z);
}
static v3 mul(v3 a, double k)
{
    return mk(a.x * k, a.y * k, a.z * k);
}
static double dot(v3 a, v3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static v3 cross(v3 a, v3 b)
{
    return mk(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static v3 norm(v3 a)
{
    double l = sqrt(dot(a, a));
    return l > 0.0 ? mul(a, 1.0 / l) : a;
}
static lumis_vec3 tof(v3 a)
{
    return (lumis_vec3){(float)a.x, (float)a.y, (float)a.z};
}

/* Orthonormal basis around n (Duff et al. 2017). */
static void basis(v3 n, v3 *t, v3 *b)
{
    double s = n.z >= 0.0 ? 1.0 : -1.0;
    double a = -1.0 / (s + n.z), c = n.x * n.y * a;
    *t = mk(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
    *b = mk(c, s + n.y * n.y * a, -n.y);
}

/* ---- the scene ----------------------------------------------------------------------- */

void lumis_scene_destroy(lumis_scene *s)
{
    if (!s) return;
    if (s->rtc) rtcReleaseScene(s->rtc);
    if (s->device) rtcReleaseDevice(s->device);
    free(s->prims);
    free(s);
}

static int add_triangles(lumis_scene *s, const float *v, int nv, const unsigned *idx, int nt)
{
    RTCGeometry g = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                        3 * sizeof(float), (size_t)nv);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                           3 * sizeof(unsigned), (size_t)nt);
    if (!vb || !ib) {
        rtcReleaseGeometry(g);
        return -1;
    }
    memcpy(vb, v, 3 * sizeof(float) * (size_t)nv);
    memcpy(ib, idx, 3 * sizeof(unsigned) * (size_t)nt);
    rtcCommitGeometry(g);
    unsigned id = rtcAttachGeometry(s->rtc, g);
    rtcReleaseGeometry(g);
    return (int)id;
}

lumis_status lumis_scene_create(const lumis_object *objects, int count,
                                const lumis_error_sink *errors, lumis_scene **out)
{
    if (!out || (count > 0 && !objects) || count < 0)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "scene: no objects given");
    *out = NULL;
    lumis_scene *s = calloc(1, sizeof *s);
    if (!s) return LUMIS_ERR_OUT_OF_MEMORY;
    s->device = rtcNewDevice(NULL);
    s->prims = calloc((size_t)(count > 0 ? count : 1), sizeof(prim));
    if (!s->device || !s->prims) {
        lumis_scene_destroy(s);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "scene: cannot start Embree");
    }
    s->rtc = rtcNewScene(s->device);
    for (int k = 0; k < count; k++) {
        const lumis_object *o = &objects[k];
        int id = -1;
        if (o->material.type >= LUMIS_BSDF_TYPE_COUNT) {
            lumis_scene_destroy(s);
            return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "scene: object %d: bad material",
                               k);
        }
        if (o->type == LUMIS_OBJECT_SPHERE) {
            if (!(o->radius > 0.0f)) {
                lumis_scene_destroy(s);
                return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                                   "scene: object %d: sphere radius must be positive", k);
            }
            RTCGeometry g = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
            float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                4 * sizeof(float), 1);
            vb[0] = o->center.x;
            vb[1] = o->center.y;
            vb[2] = o->center.z;
            vb[3] = o->radius;
            rtcCommitGeometry(g);
            id = (int)rtcAttachGeometry(s->rtc, g);
            rtcReleaseGeometry(g);
        } else if (o->type == LUMIS_OBJECT_PLANE) {
            v3 n = norm(fromf(o->normal));
            if (dot(n, n) == 0.0) {
                lumis_scene_destroy(s);
                return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                                   "scene: object %d: plane normal is zero", k);
            }
            v3 t, b, c = fromf(o->center);
            basis(n, &t, &b);
            double h = 0.5 * (o->size > 0.0f ? o->size : 20.0);
            float v[12];
            const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
            for (int q = 0; q < 4; q++) {
                v3 p = add(c, add(mul(t, corner[q][0] * h), mul(b, corner[q][1] * h)));
                v[3 * q] = (float)p.x;
                v[3 * q + 1] = (float)p.y;
                v[3 * q + 2] = (float)p.z;
            }
            const unsigned idx[6] = {0, 1, 2, 0, 2, 3};
            id = add_triangles(s, v, 4, idx, 2);
            s->prims[k].normal = tof(n);
        } else if (o->type == LUMIS_OBJECT_MESH) {
            if (!o->vertices || !o->indices || o->vertex_count <= 0 || o->triangle_count <= 0) {
                lumis_scene_destroy(s);
                return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                                   "scene: object %d: empty mesh", k);
            }
            for (long q = 0; q < 3L * o->triangle_count; q++)
                if (o->indices[q] >= (unsigned)o->vertex_count) {
                    lumis_scene_destroy(s);
                    return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                                       "scene: object %d: index %u out of range", k, o->indices[q]);
                }
            id = add_triangles(s, o->vertices, o->vertex_count, o->indices, o->triangle_count);
        }
        if (id != k) { /* Embree numbers geometries in attach order */
            lumis_scene_destroy(s);
            return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "scene: object %d rejected", k);
        }
        s->prims[k].type = o->type;
        s->prims[k].center = o->center;
        s->prims[k].material = o->material;
    }
    s->count = count;
    rtcCommitScene(s->rtc);
    *out = s;
    return LUMIS_OK;
}

/* ---- tracing ------------------------------------------------------------------------- */

typedef struct hit {
    v3 p, n; /* n faces the incoming ray */
    const prim *prim;
} hit;

static int intersect(const lumis_scene *s, v3 o, v3 d, hit *h)
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
    h->prim = &s->prims[rh.hit.geomID];
    h->p = add(o, mul(d, rh.ray.tfar));
    if (h->prim->type == LUMIS_OBJECT_SPHERE)
        h->n = norm(sub(h->p, fromf(h->prim->center)));
    else if (h->prim->type == LUMIS_OBJECT_PLANE)
        h->n = fromf(h->prim->normal);
    else
        h->n = norm(mk(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
    if (dot(h->n, d) > 0.0) h->n = mul(h->n, -1.0);
    return 1;
}

static int occluded(const lumis_scene *s, v3 o, v3 d)
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
    rtcOccluded1(s->rtc, &ctx, &r);
    return r.tfar < 0.0f;
}

/* ---- shading ------------------------------------------------------------------------- */

static double mis_weight(double nf, double pf, double ng, double pg, int power)
{
    double a = nf * pf, b = ng * pg;
    if (power) {
        a *= a;
        b *= b;
    }
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

typedef struct ctx {
    const lumis_scene *scene;
    const lumis_render_desc *d;
    int nl, nb;
} ctx;

/* Direct light from the environment reflected at h towards -dir. */
static v3 shade(const ctx *c, const hit *h, v3 dir, lumis_pcg32 *rng, double *shadow_rays)
{
    const lumis_render_desc *d = c->d;
    v3 t, b, n = h->n, L = mk(0, 0, 0);
    basis(n, &t, &b);
    v3 wow = mul(dir, -1.0);
    lumis_vec3 wo = tof(mk(dot(wow, t), dot(wow, b), dot(wow, n)));
    const lumis_bsdf *m = &h->prim->material;
    double scale = 1e-4 * fmax(1.0, sqrt(dot(h->p, h->p)));
    v3 org = add(h->p, mul(n, scale));
    int use_light = d->estimator != LUMIS_ESTIMATOR_BSDF,
        use_bsdf = d->estimator != LUMIS_ESTIMATOR_LIGHT;
    int mis = d->estimator == LUMIS_ESTIMATOR_MIS;
    for (int k = 0; use_light && k < c->nl; k++) {
        double u1 = lumis_pcg32_double(rng), u2 = lumis_pcg32_double(rng);
        lumis_env_sample e = lumis_sampler_sample(d->sampler, u1, u2);
        v3 wi = fromf(e.dir);
        double cosn = dot(wi, n);
        if (!(cosn > 0.0) || !(e.pdf > 0.0f)) continue;
        lumis_vec3 wil = tof(mk(dot(wi, t), dot(wi, b), cosn));
        lumis_rgb f = lumis_bsdf_eval(m, wo, wil);
        if (f.r == 0.0f && f.g == 0.0f && f.b == 0.0f) continue;
        *shadow_rays += 1.0;
        if (occluded(c->scene, org, wi)) continue;
        double w =
            mis ? mis_weight(c->nl, e.pdf, c->nb, lumis_bsdf_pdf(m, wo, wil), d->power_heuristic)
                : 1.0;
        double k2 = w * cosn / ((double)e.pdf * c->nl);
        L = add(L, mk(f.r * e.radiance.r * k2, f.g * e.radiance.g * k2, f.b * e.radiance.b * k2));
    }
    for (int k = 0; use_bsdf && k < c->nb; k++) {
        double u0 = lumis_pcg32_double(rng), u1 = lumis_pcg32_double(rng),
               u2 = lumis_pcg32_double(rng);
        lumis_bsdf_sample bs = lumis_bsdf_sample_wi(m, wo, u0, u1, u2);
        if (!(bs.pdf > 0.0f)) continue;
        v3 wi = norm(add(add(mul(t, bs.wi.x), mul(b, bs.wi.y)), mul(n, bs.wi.z)));
        *shadow_rays += 1.0;
        if (occluded(c->scene, org, wi)) continue;
        lumis_rgb Le = lumis_envmap_eval(d->env, tof(wi));
        double w = mis ? mis_weight(c->nb, bs.pdf, c->nl, lumis_sampler_pdf(d->sampler, tof(wi)),
                                    d->power_heuristic)
                       : 1.0;
        double k2 = w / c->nb;
        L = add(L, mk(bs.weight.r * Le.r * k2, bs.weight.g * Le.g * k2, bs.weight.b * Le.b * k2));
    }
    return L;
}

lumis_status lumis_render(const lumis_scene *scene, const lumis_render_desc *d, lumis_image **out,
                          lumis_render_stats *stats)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!scene || !d || !d->env || (d->estimator != LUMIS_ESTIMATOR_BSDF && !d->sampler) ||
        (unsigned)d->estimator > LUMIS_ESTIMATOR_BSDF || d->spp < 0 || d->light_samples < 0 ||
        d->bsdf_samples < 0)
        return lumis__fail(d ? &d->errors : NULL, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: needs a scene, an envmap, a sampler (unless BSDF-only) "
                           "and non-negative sample counts");
    lumis_camera cam = {{0, 1, 5}, {0, 0.5f, 0}, {0, 1, 0}, 40.0f, 640, 480};
    if (d->camera) cam = *d->camera;
    if (cam.fov_deg == 0.0f) cam.fov_deg = 40.0f;
    if (cam.width == 0) cam.width = 640;
    if (cam.height == 0) cam.height = 480;
    if (!(cam.fov_deg > 0.0f && cam.fov_deg < 180.0f))
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: fov must be in (0, 180)");
    lumis_status st = lumis_image_create(cam.width, cam.height, out);
    if (st != LUMIS_OK)
        return lumis__fail(&d->errors, st, "render: %d x %d: %s", cam.width, cam.height,
                           lumis_status_string(st));

    v3 eye = fromf(cam.eye), fwd = norm(sub(fromf(cam.look_at), eye));
    v3 right = norm(cross(fwd, fromf(cam.up)));
    v3 up = cross(right, fwd);
    if (!(dot(right, right) > 0.5)) {
        lumis_image_destroy(*out);
        *out = NULL;
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: camera eye equals look_at, or up is parallel to the view");
    }
    double th = tan(0.5 * cam.fov_deg * LUMIS_PI / 180.0), aspect = (double)cam.width / cam.height;
    ctx c = {scene, d, d->light_samples ? d->light_samples : 1,
             d->bsdf_samples ? d->bsdf_samples : 1};
    const int spp = d->spp ? d->spp : 16;
    const int threads = d->threads > 0 ? d->threads : omp_get_max_threads();
    double shadow = 0.0, t0 = omp_get_wtime();
    float *px = (*out)->pixels;
    const int w = cam.width, h = cam.height;

#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) reduction(+ : shadow)
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, d->seed, (uint64_t)y * (uint64_t)w + (uint64_t)x);
            v3 acc = mk(0, 0, 0);
            for (int sidx = 0; sidx < spp; sidx++) {
                double sx = (x + lumis_pcg32_double(&rng)) / w * 2.0 - 1.0;
                double sy = 1.0 - (y + lumis_pcg32_double(&rng)) / h * 2.0; /* row 0 on top */
                v3 dir = norm(add(fwd, add(mul(right, sx * th * aspect), mul(up, sy * th))));
                hit hh;
                if (intersect(scene, eye, dir, &hh)) {
                    acc = add(acc, shade(&c, &hh, dir, &rng, &shadow));
                } else {
                    lumis_rgb e = lumis_envmap_eval(d->env, tof(dir));
                    acc = add(acc, mk(e.r, e.g, e.b));
                }
            }
            float *p = px + 3 * ((size_t)y * (size_t)w + (size_t)x);
            p[0] = (float)(acc.x / spp);
            p[1] = (float)(acc.y / spp);
            p[2] = (float)(acc.z / spp);
        }
    }
    if (stats) {
        stats->seconds = omp_get_wtime() - t0;
        stats->shadow_rays = shadow;
        stats->camera_rays = (double)w * h * spp;
    }
    return LUMIS_OK;
}
