/* lumis/render.h - the evaluation renderer (library lumis-render): a scene of spheres,
 * planes and triangle meshes with BSDFs, traced with Embree, lit by an environment map
 * through any lumis_sampler, with light, BSDF or multiple importance sampling.
 *
 * It exists to measure samplers: direct illumination from the environment only, exact
 * estimators, and images that depend on the seed but never on the thread count. */
#ifndef LUMIS_RENDER_H
#define LUMIS_RENDER_H

#include "lumis/bsdf.h"
#include "lumis/envmap.h"
#include "lumis/image.h"
#include "lumis/sampler.h"
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
    lumis_bsdf material;
} lumis_object;

typedef struct lumis_scene lumis_scene;

/* Builds the Embree scene (objects copied).  errors: an optional sink. */
lumis_status lumis_scene_create(const lumis_object *objects, int count,
                                const lumis_error_sink *errors, lumis_scene **out);
void lumis_scene_destroy(lumis_scene *scene);

typedef enum lumis_estimator {
    LUMIS_ESTIMATOR_MIS = 0, /* light and BSDF samples combined (default) */
    LUMIS_ESTIMATOR_LIGHT,   /* light samples only */
    LUMIS_ESTIMATOR_BSDF     /* BSDF samples only */
} lumis_estimator;

typedef struct lumis_render_desc {
    const lumis_camera *camera;
    const lumis_envmap *env;
    const lumis_sampler *sampler; /* light sampler; NULL for LUMIS_ESTIMATOR_BSDF */
    lumis_estimator estimator;
    int power_heuristic;     /* nonzero: power heuristic (beta = 2), else balance */
    int spp;                 /* camera samples per pixel; 0 == 16 */
    int light_samples;       /* light samples per camera sample; 0 == 1 */
    int bsdf_samples;        /* BSDF samples per camera sample; 0 == 1 */
    unsigned long long seed; /* the image depends on it, never on threads */
    int threads;             /* 0 == all cores */
    lumis_error_sink errors;
} lumis_render_desc;

typedef struct lumis_render_stats {
    double seconds;
    double shadow_rays;
    double camera_rays;
} lumis_render_stats;

/* Renders into a new image (linear radiance).  stats may be NULL. */
lumis_status lumis_render(const lumis_scene *scene, const lumis_render_desc *desc,
                          lumis_image **out, lumis_render_stats *stats);

/* ---- scene files (JSON) ---------------------------------------------------------------
 *
 * {"camera": {"eye": [0,1,5], "look_at": [0,0.5,0], "up": [0,1,0], "fov_deg": 40,
 *             "width": 640, "height": 480},
 *  "environment": {"map": "forest.exr", "rotation_deg": 0, "scale": 1},
 *  "objects": [{"type": "sphere", "center": [0,1,0], "radius": 1, "material": {...}},
 *              {"type": "mesh", "file": "bunny.obj", "transform": {"translate": [1,0,0],
 *               "rotate_deg": [0,30,0], "scale": 0.5}, "material": {...}},
 *              {"type": "plane", "point": [0,0,0], "normal": [0,1,0], "size": 20,
 *               "material": {...}}]}
 * Materials: {"type": "lambert", "albedo": [r,g,b]}, {"type": "ward", "diffuse": ...,
 * "specular": ..., "alpha_x": a, "alpha_y": a}, {"type": "conductor", "f0": [r,g,b],
 * "alpha" (or alpha_x/alpha_y)}, {"type": "plastic", "diffuse": ..., "alpha": a}.
 * Meshes (OBJ, PLY, glTF/GLB, anything assimp reads) and maps resolve against the scene
 * file's folder; "map" may also be a procedural spec (sky, sky:WxH, studio...).  Every
 * error names the file, the JSON path (objects[1].material.alpha_x) and what was
 * expected. */
typedef struct lumis_scene_file {
    lumis_camera camera;
    char env_map[4096]; /* resolved path or procedural spec; "" if the file names none */
    float env_rotation_deg, env_scale;
    lumis_object *objects; /* meshes' vertex and index arrays are owned by the file */
    int object_count;
} lumis_scene_file;

lumis_status lumis_scene_file_read(const char *path, const lumis_error_sink *errors,
                                   lumis_scene_file **out);
void lumis_scene_file_destroy(lumis_scene_file *file);

#ifdef __cplusplus
}
#endif
#endif
