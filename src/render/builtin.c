/* Built-in scenes: the papers' test scenes, usable by name with no files.  The bunny is
 * compiled in (assets/bunny.glb through cmake/embed.cmake) and decoded by assimp. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "internal.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <string.h>

extern const unsigned char lumis__bunny_glb[];
extern const unsigned long lumis__bunny_glb_size;

static const char *const names[] = {"spheres", "bunny-plane", "ward-aniso", NULL};

const char *const *lumis_scene_builtin_names(void)
{
    return names;
}

static lumis_object sphere(float x, float y, float z, float r, lumis_bsdf m)
{
    lumis_object o;
    memset(&o, 0, sizeof o);
    o.type = LUMIS_OBJECT_SPHERE;
    o.center = (lumis_vec3){x, y, z};
    o.radius = r;
    o.material = m;
    return o;
}

/* Three spheres of different materials side by side (Ergun et al., Figure 6). */
static lumis_status spheres(lumis_scene_file *f)
{
    const lumis_bsdf mats[3] = {
        {LUMIS_BSDF_LAMBERT, {0.8f, 0.8f, 0.8f}, {0, 0, 0}, 0, 0},
        {LUMIS_BSDF_WARD, {0.1f, 0.1f, 0.1f}, {0.3f, 0.3f, 0.3f}, 0.1f, 0.1f},
        {LUMIS_BSDF_GGX_CONDUCTOR, {0, 0, 0}, {0.95f, 0.64f, 0.54f}, 0.15f, 0.15f},
    };
    lumis_status st = LUMIS_OK;
    for (int k = 0; k < 3 && st == LUMIS_OK; k++) {
        lumis_object o = sphere(-2.3f + 2.3f * (float)k, 0.0f, 0.0f, 1.0f, mats[k]);
        st = lumis__scene_file_push(f, &o);
    }
    f->camera = (lumis_camera){{0, 0.6f, 8.0f}, {0, 0, 0}, {0, 1, 0}, 30.0f, 600, 240};
    return st;
}

/* One sphere with the anisotropic Ward BRDF (Ergun et al., Figure 7). */
static lumis_status ward_aniso(lumis_scene_file *f)
{
    lumis_object o = sphere(
        0, 0, 0, 1.0f,
        (lumis_bsdf){LUMIS_BSDF_WARD, {0.05f, 0.05f, 0.05f}, {0.5f, 0.5f, 0.5f}, 0.5f, 0.001f});
    f->camera = (lumis_camera){{0, 0.5f, 4.0f}, {0, 0, 0}, {0, 1, 0}, 35.0f, 400, 400};
    return lumis__scene_file_push(f, &o);
}

/* The bunny and a glossy sphere on a diffuse ground plane: contact shadows and a shadowed
 * ground, where visibility decides what a light sample is worth (as in Wu's scenes). */
static lumis_status bunny_plane(lumis_scene_file *f)
{
    const struct aiScene *sc = aiImportFileFromMemory(
        (const char *)lumis__bunny_glb, (unsigned)lumis__bunny_glb_size,
        aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices,
        "glb");
    if (!sc) return LUMIS_ERR_CORRUPT;
    lumis_object bunny;
    memset(&bunny, 0, sizeof bunny);
    bunny.type = LUMIS_OBJECT_MESH;
    lumis_status st = lumis__scene_file_add_mesh(f, "builtin:bunny", sc, &bunny);
    aiReleaseImport(sc);
    if (st != LUMIS_OK) return st;
    /* Stand it on the plane: its lowest vertex at y = 0, 1.1 units tall. */
    float lo = bunny.vertices[1], hi = lo;
    for (int k = 1; k < bunny.vertex_count; k++) {
        float y = bunny.vertices[3 * k + 1];
        lo = y < lo ? y : lo;
        hi = y > hi ? y : hi;
    }
    float s = 1.1f / (hi - lo);
    const float t[3] = {-0.55f, -lo * s, 0.0f}, r[3] = {0, 20, 0}, sc3[3] = {s, s, s};
    lumis__transform_matrix(t, r, sc3, bunny.transform);
    bunny.material = (lumis_bsdf){LUMIS_BSDF_LAMBERT, {0.75f, 0.75f, 0.75f}, {0, 0, 0}, 0, 0};
    lumis_object ball = sphere(
        0.85f, 0.45f, 0.35f, 0.45f,
        (lumis_bsdf){
            LUMIS_BSDF_GGX_PLASTIC, {0.6f, 0.12f, 0.08f}, {0.04f, 0.04f, 0.04f}, 0.2f, 0.2f});
    lumis_object ground;
    memset(&ground, 0, sizeof ground);
    ground.type = LUMIS_OBJECT_PLANE;
    ground.normal = (lumis_vec3){0, 1, 0};
    ground.size = 200.0f; /* its edge stays below the horizon of the camera */
    ground.material = (lumis_bsdf){LUMIS_BSDF_LAMBERT, {0.5f, 0.5f, 0.5f}, {0, 0, 0}, 0, 0};
    f->camera = (lumis_camera){{0, 1.3f, 4.0f}, {0.1f, 0.45f, 0}, {0, 1, 0}, 35.0f, 640, 480};
    if ((st = lumis__scene_file_push(f, &bunny)) != LUMIS_OK) return st;
    if ((st = lumis__scene_file_push(f, &ball)) != LUMIS_OK) return st;
    return lumis__scene_file_push(f, &ground);
}

lumis_status lumis_scene_builtin(const char *name, const lumis_error_sink *errors,
                                 lumis_scene_file **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    lumis_status (*make)(lumis_scene_file *) = NULL;
    if (name && strcmp(name, "spheres") == 0) make = spheres;
    if (name && strcmp(name, "bunny-plane") == 0) make = bunny_plane;
    if (name && strcmp(name, "ward-aniso") == 0) make = ward_aniso;
    if (!make)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "unknown scene '%s' (built in: spheres, bunny-plane, ward-aniso)",
                           name ? name : "(null)");
    lumis_scene_file *f = lumis__scene_file_new();
    if (!f) return LUMIS_ERR_OUT_OF_MEMORY;
    lumis_status st = make(f);
    if (st != LUMIS_OK) {
        lumis_scene_file_destroy(f);
        return lumis__fail(errors, st, "scene %s: %s", name, lumis_status_string(st));
    }
    *out = f;
    return LUMIS_OK;
}
