/* lumis/render_scene_file.h - scene files (JSON) and the built-in scenes (library lumis-
 * render; lumis/render.h includes every part). */
#ifndef LUMIS_RENDER_SCENE_FILE_H_PUBLIC
#define LUMIS_RENDER_SCENE_FILE_H_PUBLIC

#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/io.h"
#include "lumis/render_lighting.h"
#include "lumis/render_scene.h"
#include "lumis/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- scene files (JSON) and built-in scenes -------------------------------------------
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
 * "alpha" (or alpha_x/alpha_y)}, {"type": "plastic", "diffuse": ..., "alpha": a},
 * {"type": "glossy", "color": [r,g,b], "alpha": a} (Cycles' Glossy BSDF, GGX).
 * A mesh may give "instances": [{"translate": ..., "rotate_deg": ..., "scale": ...}, ...]
 * instead of one "transform": one object per entry, sharing the mesh (Embree instances).
 * Rotation is Rz Ry Rx in degrees, applied after the scale and before the translation.
 * "luminaires": [{"file": "lamp.json" or "preset:car", "transform": {"translate",
 * "rotate_deg", "scale" (one number: lengths only)}, "intensity": 1}] places light-field
 * luminaires (docs/render.md); a scene with luminaires is lit by them.
 * Meshes (OBJ, PLY, glTF/GLB, anything assimp reads) and maps resolve against the scene
 * file's folder; the same file named twice is loaded once and instanced; "map" may also be a
 * procedural spec (sky, sky:WxH, studio...).  Every error names the file, the JSON path
 * (objects[1].material.alpha_x) and what was expected. */
typedef struct lumis_scene_file {
    lumis_camera camera;
    char env_map[4096];       /* resolved path or procedural spec; "" if the file names none */
    lumis_image *env_image;   /* that map, read through lumis-io (owned by the file); NULL
                                 when the file names none or it was skipped */
    lumis_read_info env_info; /* what reading it did (replaced values, format) */
    float env_rotation_deg, env_scale;
    lumis_object *objects; /* meshes' vertex and index arrays are owned by the file */
    int object_count;
    /* Placed light-field luminaires (the file owns the luminaires; an instance's pointer
     * may be shared).  A scene with luminaires is lit by them (lumis_luminaire_lighting). */
    lumis_luminaire_instance *luminaires;
    int luminaire_count;
    /* Luminaires the file lists, those of intensity 0 (left out of `luminaires`) included:
     * a scene that lists some is lit by its luminaires, even when all of them are black. */
    int luminaires_listed;
    /* Placed photometric fixtures ("photometric": [...]; the file owns their models).  A
     * scene with fixtures (and no luminaires) is lit by them (lumis_photometric_lighting). */
    lumis_photometric_instance *photometrics;
    int photometric_count;
} lumis_scene_file;

typedef struct lumis_scene_read_options {
    int skip_env_map;       /* nonzero: leave env_image NULL (the caller lights the scene with
                               another map) */
    lumis_read_options map; /* how the map is read (pixel limit, threads) */
    lumis_error_sink errors;
    /* Optional: how a luminaire the file names as "preset:NAME" is made, e.g. read from a
     * cache of acquired luminaires (as the lumis tool does, under $XDG_CACHE_HOME/lumis).
     * spec is "preset:NAME"; on success *out is a luminaire the scene file then owns.
     * NULL: acquired with lumis_luminaire_preset_create (seconds). */
    lumis_status (*load_preset)(void *user, const char *spec, lumis_luminaire **out);
    void *load_preset_user;
} lumis_scene_read_options;

/* Reads a scene file, its meshes and its map (lumis_map_read: a file beside the scene or a
 * procedural spec).  options may be NULL (everything read, no messages). */
LUMIS_RENDER_API lumis_status lumis_scene_file_read(const char *path,
                                                    const lumis_scene_read_options *options,
                                                    lumis_scene_file **out);

/* Built-in scenes, with no files:
 *   spheres     Lambert, Ward and GGX spheres side by side (Ergun et al., Figure 6)
 *   bunny-plane the Stanford bunny and a glossy sphere on a diffuse ground plane, so
 *               shadows matter (as in Wu's scenes); the bunny is compiled into the library
 *   ward-aniso  a sphere with Ward alpha_x = 0.5, alpha_y = 0.001 (Ergun et al., Figure 7)
 *   wu-diffuse, wu-satin, wu-glossy, wu-mixed
 *               the bunny, Suzanne and one or two spheres on a ground plane, from all
 *               Lambertian to semi-glossy (Wu's scenes); Suzanne is compiled in too
 *   headlight, headlight-close
 *               a car headlight (the luminaire preset "car": 11 x 9 images of 256 x 256,
 *               acquired from its emitter in about 2 s) lighting a floor and a wall past
 *               the bunny and a sphere, which cast shadows (Lu et al., Fig. 13): a far view
 *               of the scene, and a close-up of the floor just in front of the lamp
 *   glossy-only Wu's three objects and the ground, every surface glossy GGX (no diffuse
 *               part) at alpha 0.05, 0.15, 0.3 and 0.4
 *   window      a closed room (4 x 2.5 x 5) lit only through a small window (0.8 x 0.6),
 *               a Lambertian and a plastic sphere inside
 *   open-sky    the bunny and three spheres spread over an open ground plane, seen from
 *               above, nothing overhead
 * They name no map (env_map is ""). */
LUMIS_RENDER_API lumis_status lumis_scene_builtin(const char *name, const lumis_error_sink *errors,
                                                  lumis_scene_file **out);
/* As lumis_scene_builtin, but a scene that places luminaires (headlight, headlight-close)
 * places `luminaire` (borrowed: it must outlive the file) instead of acquiring its own; for
 * another scene, LUMIS_ERR_INVALID_ARGUMENT.  NULL: the same as lumis_scene_builtin. */
LUMIS_RENDER_API lumis_status lumis_scene_builtin_with_luminaire(const char *name,
                                                                 const lumis_luminaire *luminaire,
                                                                 const lumis_error_sink *errors,
                                                                 lumis_scene_file **out);
/* The mesh files a scene file read (resolved paths; built-in meshes by name), index 0 up;
 * NULL past the last.  A tool checks its outputs against them and the map. */
LUMIS_RENDER_API const char *lumis_scene_file_mesh_path(const lumis_scene_file *file, int index);
/* The luminaire files a scene file read (resolved paths, or "preset:NAME"), index 0 up; NULL
 * past the last. */
LUMIS_RENDER_API const char *lumis_scene_file_luminaire_path(const lumis_scene_file *file,
                                                             int index);
/* The photometric file of fixture `index` (resolved against the scene's folder), or NULL. */
LUMIS_RENDER_API const char *lumis_scene_file_photometric_path(const lumis_scene_file *file,
                                                               int index);
/* The built-in names, NULL-terminated. */
LUMIS_RENDER_API const char *const *lumis_scene_builtin_names(void);
/* 1 when the built-in scene `name` is lit by luminaires (headlight, headlight-close), so a
 * tool can refuse options that do not apply before acquiring them (seconds); else 0. */
LUMIS_RENDER_API int lumis_scene_builtin_has_luminaires(const char *name);
/* The preset the built-in scene `name` places ("preset:car"), NULL for a scene without
 * luminaires: a tool may acquire it (or read it from a cache) and pass it to
 * lumis_scene_builtin_with_luminaire. */
LUMIS_RENDER_API const char *lumis_scene_builtin_luminaire_spec(const char *name);
LUMIS_RENDER_API void lumis_scene_file_destroy(lumis_scene_file *file);

#ifdef __cplusplus
}
#endif
#endif
