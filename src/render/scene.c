/* The Embree scene: spheres, planes and meshes (a mesh used by several objects is built once
 * and instanced), the device and its configuration (LUMIS_EMBREE_CONFIG). */
#include "lumis/render.h"

#include "../core/internal.h"
#include "internal.h"
#include "scene.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void lumis_scene_destroy(lumis_scene *s)
{
    if (!s) return;
    if (s->rtc) rtcReleaseScene(s->rtc);
    for (int k = 0; k < s->shared_count; k++)
        if (s->shared[k]) rtcReleaseScene(s->shared[k]);
    if (s->device) rtcReleaseDevice(s->device);
    free(s->shared);
    free(s->prims);
    free(s);
}

/* Attaches a triangle geometry to `into`, its vertices mapped by m (NULL: as given).
 * Returns the geometry id, or -1. */
static int add_triangles(RTCDevice dev, RTCScene into, const float *v, int nv, const unsigned *idx,
                         int nt, const double *m)
{
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!g) return -1;
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                        3 * sizeof(float), (size_t)nv);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                           3 * sizeof(unsigned), (size_t)nt);
    if (!vb || !ib) {
        rtcReleaseGeometry(g);
        return -1;
    }
    if (!m)
        memcpy(vb, v, 3 * sizeof(float) * (size_t)nv);
    else
        for (size_t k = 0; k < (size_t)nv; k++) {
            const float *p = v + 3 * k;
            for (int r = 0; r < 3; r++)
                vb[3 * k + (size_t)r] = (float)(m[4 * r] * p[0] + m[4 * r + 1] * p[1] +
                                                m[4 * r + 2] * p[2] + m[4 * r + 3]);
        }
    memcpy(ib, idx, 3 * sizeof(unsigned) * (size_t)nt);
    rtcCommitGeometry(g);
    unsigned id = rtcAttachGeometry(into, g);
    rtcReleaseGeometry(g);
    return (int)id;
}

/* Mesh objects grouped by their arrays (sorted, so a scene of many instances builds in
 * O(n log n)): for object k, the first object with the same mesh and how many share it. */
typedef struct mesh_key {
    uintptr_t v, i;
    int nv, nt, k;
} mesh_key;

static int cmp_mesh_key(const void *pa, const void *pb)
{
    const mesh_key *a = pa, *b = pb;
    if (a->v != b->v) return a->v < b->v ? -1 : 1;
    if (a->i != b->i) return a->i < b->i ? -1 : 1;
    if (a->nv != b->nv) return a->nv < b->nv ? -1 : 1;
    if (a->nt != b->nt) return a->nt < b->nt ? -1 : 1;
    return a->k < b->k ? -1 : (a->k > b->k);
}

static int group_meshes(const lumis_object *o, int count, int *first, int *users)
{
    mesh_key *keys = malloc(sizeof *keys * (size_t)(count > 0 ? count : 1));
    if (!keys) return -1;
    int n = 0;
    for (int k = 0; k < count; k++) {
        first[k] = k;
        users[k] = 1;
    }
    for (int k = 0; k < count; k++)
        if (o[k].type == LUMIS_OBJECT_MESH)
            keys[n++] = (mesh_key){(uintptr_t)o[k].vertices, (uintptr_t)o[k].indices,
                                   o[k].vertex_count, o[k].triangle_count, k};
    qsort(keys, (size_t)n, sizeof *keys, cmp_mesh_key);
    for (int a = 0, b; a < n; a = b) {
        for (b = a + 1; b < n && keys[b].v == keys[a].v && keys[b].i == keys[a].i &&
                        keys[b].nv == keys[a].nv && keys[b].nt == keys[a].nt;
             b++) {
        }
        for (int q = a; q < b; q++) {
            first[keys[q].k] = keys[a].k; /* the smallest index: keys sort by k last */
            users[keys[q].k] = b - a;
        }
    }
    free(keys);
    return 0;
}

/* The object's transform (identity when all zeros) and the cofactor matrix that maps its
 * normals (the inverse transpose times the determinant: normals are renormalised).
 * Returns 0 for a singular or non-finite transform. */
static int object_transform(const lumis_object *o, double m[12], double cof[9], int *identity)
{
    int zero = 1;
    for (int k = 0; k < 12; k++) zero &= o->transform[k] == 0.0f;
    for (int k = 0; k < 12; k++) m[k] = zero ? (k % 5 == 0 ? 1.0 : 0.0) : o->transform[k];
    *identity = zero;
    for (int k = 0; k < 12; k++)
        if (!isfinite(m[k])) return 0;
    const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9],
                 i = m[10];
    const double cm[9] = {e * i - f * h, f * g - d * i, d * h - e * g, c * h - b * i, a * i - c * g,
                          b * g - a * h, b * f - c * e, c * d - a * f, a * e - b * d};
    memcpy(cof, cm, sizeof cm);
    double det = a * cm[0] + b * cm[1] + c * cm[2];
    double scale = 0.0;
    for (int k = 0; k < 9; k++) scale = fmax(scale, fabs(m[k / 3 * 4 + k % 3]));
    return isfinite(det) && fabs(det) > 1e-12 * scale * scale * scale;
}

static lumis_status object_fail(const lumis_error_sink *errors, lumis_status st, int k,
                                const char *what)
{
    return lumis__fail(errors, st, "scene: object %d: %s", k, what);
}

/* Adds objects[k] to the scene as Embree geometry k.  first, users: its mesh group. */
static lumis_status add_object(lumis_scene *s, const lumis_object *objects, int k, int first,
                               int users, const lumis_error_sink *errors)
{
    const lumis_object *o = &objects[k];
    prim *pr = &s->prims[k];
    int id = -1;
    if (o->material.type >= LUMIS_BSDF_TYPE_COUNT)
        return object_fail(errors, LUMIS_ERR_INVALID_ARGUMENT, k, "bad material");
    if (o->type == LUMIS_OBJECT_SPHERE) {
        if (!(o->radius > 0.0f) || !isfinite(o->radius))
            return object_fail(errors, LUMIS_ERR_INVALID_ARGUMENT, k,
                               "sphere radius must be positive");
        RTCGeometry g = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        float *vb = g ? rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                4 * sizeof(float), 1)
                      : NULL;
        if (!vb) {
            if (g) rtcReleaseGeometry(g);
            return object_fail(errors, LUMIS_ERR_OUT_OF_MEMORY, k, "cannot build the sphere");
        }
        vb[0] = o->center.x;
        vb[1] = o->center.y;
        vb[2] = o->center.z;
        vb[3] = o->radius;
        rtcCommitGeometry(g);
        id = (int)rtcAttachGeometry(s->rtc, g);
        rtcReleaseGeometry(g);
    } else if (o->type == LUMIS_OBJECT_PLANE) {
        v3 n = norm(fromf(o->normal));
        if (!(dot(n, n) > 0.5))
            return object_fail(errors, LUMIS_ERR_INVALID_ARGUMENT, k, "plane normal is zero");
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
        id = add_triangles(s->device, s->rtc, v, 4, idx, 2, NULL);
        pr->normal = tof(n);
    } else if (o->type == LUMIS_OBJECT_MESH) {
        if (!o->vertices || !o->indices || o->vertex_count <= 0 || o->triangle_count <= 0)
            return object_fail(errors, LUMIS_ERR_INVALID_ARGUMENT, k, "empty mesh");
        double m[12];
        int identity;
        if (!object_transform(o, m, pr->cof, &identity))
            return object_fail(errors, LUMIS_ERR_INVALID_ARGUMENT, k,
                               "mesh transform is singular or not finite");
        if (first == k)
            for (long q = 0; q < 3L * o->triangle_count; q++)
                if (o->indices[q] >= (unsigned)o->vertex_count)
                    return object_fail(errors, LUMIS_ERR_INVALID_ARGUMENT, k,
                                       "triangle index out of range");
        if (users == 1) { /* alone: its triangles go straight into the world */
            id = add_triangles(s->device, s->rtc, o->vertices, o->vertex_count, o->indices,
                               o->triangle_count, identity ? NULL : m);
        } else { /* shared: one Embree scene, instanced with each object's transform */
            if (first == k) {
                RTCScene child = rtcNewScene(s->device);
                if (!child || add_triangles(s->device, child, o->vertices, o->vertex_count,
                                            o->indices, o->triangle_count, NULL) < 0) {
                    if (child) rtcReleaseScene(child);
                    return object_fail(errors, LUMIS_ERR_OUT_OF_MEMORY, k, "cannot build the mesh");
                }
                rtcCommitScene(child);
                s->shared[s->shared_count++] = child;
                pr->child = child;
            } else {
                pr->child = s->prims[first].child;
            }
            float mf[12];
            for (int q = 0; q < 12; q++) mf[q] = (float)m[q];
            RTCGeometry g = rtcNewGeometry(s->device, RTC_GEOMETRY_TYPE_INSTANCE);
            if (!g) return object_fail(errors, LUMIS_ERR_OUT_OF_MEMORY, k, "cannot instance");
            rtcSetGeometryInstancedScene(g, pr->child);
            rtcSetGeometryTimeStepCount(g, 1);
            rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, mf);
            rtcCommitGeometry(g);
            id = (int)rtcAttachGeometry(s->rtc, g);
            rtcReleaseGeometry(g);
            pr->instanced = 1;
        }
    }
    if (id != k) /* Embree numbers geometries in attach order */
        return object_fail(errors, LUMIS_ERR_INVALID_ARGUMENT, k, "rejected by Embree");
    pr->type = o->type;
    pr->center = o->center;
    pr->material = o->material;
    return LUMIS_OK;
}

/* Embree 3 ignores an isa or max_isa value it does not know (the device then picks the best
 * kernels), so a misspelt isa=avx-2 would quietly test the wrong ones: lumis checks the names
 * itself. */
static int embree_isa_known(const char *config)
{
    static const char *const keys[] = {"isa=", "max_isa="};
    static const char *const names[] = {"sse", "sse2", "sse3", "ssse3",  "sse4.1",    "sse4.2",
                                        "avx", "avxi", "avx2", "avx512", "avx512knl", "avx512skx"};
    for (const char *p = config; *p;) {
        while (*p == ',' || *p == ' ') p++;
        const size_t len = strcspn(p, ",");
        for (size_t k = 0; k < sizeof keys / sizeof *keys; k++) {
            const size_t kl = strlen(keys[k]);
            if (len < kl || strncmp(p, keys[k], kl) != 0) continue;
            int ok = 0;
            for (size_t i = 0; i < sizeof names / sizeof *names; i++)
                ok |= strlen(names[i]) == len - kl && strncmp(p + kl, names[i], len - kl) == 0;
            if (!ok) return 0;
        }
        p += len;
    }
    return 1;
}

lumis_status lumis_scene_create(const lumis_object *objects, int count,
                                const lumis_error_sink *errors, lumis_scene **out)
{
    if (!out || (count > 0 && !objects) || count < 0)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "scene: no objects given");
    *out = NULL;
    lumis_scene *s = calloc(1, sizeof *s);
    if (!s) return LUMIS_ERR_OUT_OF_MEMORY;
    const size_t n = (size_t)(count > 0 ? count : 1);
    /* LUMIS_EMBREE_CONFIG is handed to Embree as its device configuration (isa=sse4.2,
     * threads=1, verbose=1, ...; docs/render.md), so a user can pin Embree's kernels and
     * CI runs the same tests on the kernels of older CPUs. */
    const char *config = getenv("LUMIS_EMBREE_CONFIG");
    if (config && !embree_isa_known(config)) {
        free(s);
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "scene: LUMIS_EMBREE_CONFIG=\"%s\": unknown isa (Embree knows sse2, "
                           "sse4.2, avx, avx2, avx512; it would ignore the key silently)",
                           config);
    }
    s->device = rtcNewDevice(config && *config ? config : NULL);
    if (!s->device) {
        free(s);
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "scene: Embree refused its device configuration "
                           "(LUMIS_EMBREE_CONFIG=\"%s\")",
                           config ? config : "");
    }
    s->prims = calloc(n, sizeof(prim));
    s->shared = calloc(n, sizeof(RTCScene));
    int *first = malloc(n * sizeof(int)), *users = malloc(n * sizeof(int));
    lumis_status st = LUMIS_OK;
    if (!s->device || !s->prims || !s->shared || !first || !users ||
        !(s->rtc = rtcNewScene(s->device)) || group_meshes(objects, count, first, users) != 0)
        st = lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "scene: cannot start Embree");
    for (int k = 0; k < count && st == LUMIS_OK; k++)
        st = add_object(s, objects, k, first[k], users[k], errors);
    free(first);
    free(users);
    if (st == LUMIS_OK) {
        s->count = count;
        rtcCommitScene(s->rtc);
        if (rtcGetDeviceError(s->device) != RTC_ERROR_NONE)
            st = lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "scene: Embree failed to build it");
    }
    if (st != LUMIS_OK) {
        lumis_scene_destroy(s);
        return st;
    }
    *out = s;
    return LUMIS_OK;
}

void *lumis__scene_rtc(const lumis_scene *scene)
{
    return scene ? scene->rtc : NULL;
}
