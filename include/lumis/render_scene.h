/* lumis/render_scene.h - the scene the renderer traces: a camera, objects (spheres, planes,
 * triangle meshes with their BSDFs) and the Embree scene built from them (library lumis-
 * render; lumis/render.h includes every part). */
#ifndef LUMIS_RENDER_SCENE_H_PUBLIC
#define LUMIS_RENDER_SCENE_H_PUBLIC

#include "lumis/bsdf.h"
#include "lumis/export.h"
#include "lumis/status.h"
#include "lumis/types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct lumis_camera {
    lumis_vec3 eye, look_at, up;
    float fov_deg;     /* vertical; 0 == 40 */
    int width, height; /* 0 == 640 x 480 */
} lumis_camera;

typedef enum lumis_object_type {
    LUMIS_OBJECT_SPHERE = 0,
    LUMIS_OBJECT_PLANE, /* a square of side `size` through `center` facing `normal` */
    LUMIS_OBJECT_MESH   /* triangles, world space */
} lumis_object_type;

typedef struct lumis_object {
    lumis_object_type type;
    lumis_vec3 center;       /* sphere centre, plane point */
    float radius;            /* sphere */
    lumis_vec3 normal;       /* plane */
    float size;              /* plane side; 0 == 20 */
    const float *vertices;   /* mesh: 3 floats each, borrowed for lumis_scene_create */
    const unsigned *indices; /* mesh: 3 per triangle */
    int vertex_count, triangle_count;
    /* mesh: object to world, a row-major 3x4 matrix [R | t]; all zeros == identity.
     * Mesh objects that share the same vertex and index arrays are built once and
     * instanced, each with its own transform and material. */
    float transform[12];
    lumis_bsdf material;
} lumis_object;

typedef struct lumis_scene lumis_scene;

/* Builds the Embree scene (objects copied; mesh arrays need not outlive the call).
 * errors: an optional sink. */
LUMIS_RENDER_API lumis_status lumis_scene_create(const lumis_object *objects, int count,
                                                 const lumis_error_sink *errors, lumis_scene **out);
LUMIS_RENDER_API void lumis_scene_destroy(lumis_scene *scene);

#ifdef __cplusplus
}
#endif
#endif
