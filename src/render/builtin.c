/* Built-in scenes: the papers' test scenes, usable by name with no files.  The bunny is
 * compiled in (assets/bunny.glb through cmake/embed.cmake) and decoded by assimp. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "internal.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <math.h>
#include <string.h>

extern const unsigned char lumis__bunny_glb[];
extern const unsigned long lumis__bunny_glb_size;
extern const unsigned char lumis__suzi_glb[];
extern const unsigned long lumis__suzi_glb_size;

static const char *const names[] = {
    "spheres",   "bunny-plane", "ward-aniso", "wu-diffuse",      "wu-satin",
    "wu-glossy", "wu-mixed",    "headlight",  "headlight-close", "glossy-only",
    "window",    "open-sky",    NULL};

const char *const *lumis_scene_builtin_names(void)
{
    return names;
}

int lumis_scene_builtin_has_luminaires(const char *name)
{
    return lumis_scene_builtin_luminaire_spec(name) != NULL;
}

const char *lumis_scene_builtin_luminaire_spec(const char *name)
{
    const int lit =
        name && (strcmp(name, "headlight") == 0 || strcmp(name, "headlight-close") == 0);
    return lit ? "preset:car" : NULL; /* headlight_scene's */
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

/* An embedded glTF mesh stood on the plane y = 0: lowest vertex on it, `height` tall,
 * turned by yaw degrees about y, then moved by (x, z); with centre, its foot's centre (the
 * middle of its bounds in x and z) lands on (x, z). */
static lumis_status embedded_mesh(lumis_scene_file *f, const char *name, const unsigned char *glb,
                                  unsigned long size, float height, float x, float z, float yaw,
                                  int centre, lumis_bsdf material, lumis_object *o)
{
    const struct aiScene *sc = aiImportFileFromMemory(
        (const char *)glb, (unsigned)size,
        aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices,
        "glb");
    if (!sc) return LUMIS_ERR_CORRUPT;
    memset(o, 0, sizeof *o);
    o->type = LUMIS_OBJECT_MESH;
    lumis_status st = lumis__scene_file_add_mesh(f, name, sc, o);
    aiReleaseImport(sc);
    if (st != LUMIS_OK) return st;
    float lo = o->vertices[1], hi = lo, xl = o->vertices[0], xh = xl, zl = o->vertices[2], zh = zl;
    for (int k = 1; k < o->vertex_count; k++) {
        const float *v = o->vertices + 3 * k;
        lo = v[1] < lo ? v[1] : lo;
        hi = v[1] > hi ? v[1] : hi;
        xl = v[0] < xl ? v[0] : xl;
        xh = v[0] > xh ? v[0] : xh;
        zl = v[2] < zl ? v[2] : zl;
        zh = v[2] > zh ? v[2] : zh;
    }
    const float s = height / (hi - lo), cx = centre ? 0.5f * (xl + xh) * s : 0.0f,
                cz = centre ? 0.5f * (zl + zh) * s : 0.0f;
    const float c = cosf(yaw * (float)(LUMIS_PI / 180.0)),
                sn = sinf(yaw * (float)(LUMIS_PI / 180.0));
    /* Ry applied after the scale: the foot's centre (cx, cz) turns to (c cx + s cz, -s cx + c cz).
     */
    const float t[3] = {x - (c * cx + sn * cz), -lo * s, z - (-sn * cx + c * cz)},
                r[3] = {0, yaw, 0}, sc3[3] = {s, s, s};
    lumis__transform_matrix(t, r, sc3, o->transform);
    o->material = material;
    return LUMIS_OK;
}

static lumis_object ground_plane(float albedo)
{
    lumis_object g;
    memset(&g, 0, sizeof g);
    g.type = LUMIS_OBJECT_PLANE;
    g.normal = (lumis_vec3){0, 1, 0};
    g.size = 200.0f; /* its edge stays below the horizon of the camera */
    g.material = (lumis_bsdf){LUMIS_BSDF_LAMBERT, {albedo, albedo, albedo}, {0, 0, 0}, 0, 0};
    return g;
}

/* The bunny and a glossy sphere on a diffuse ground plane: contact shadows and a shadowed
 * ground, where visibility decides what a light sample is worth (as in Wu's scenes). */
static lumis_status bunny_plane(lumis_scene_file *f)
{
    lumis_object bunny;
    lumis_status st = embedded_mesh(
        f, "builtin:bunny", lumis__bunny_glb, lumis__bunny_glb_size, 1.1f, -0.55f, 0.0f, 20.0f, 0,
        (lumis_bsdf){LUMIS_BSDF_LAMBERT, {0.75f, 0.75f, 0.75f}, {0, 0, 0}, 0, 0}, &bunny);
    if (st != LUMIS_OK) return st;
    lumis_object ball = sphere(
        0.85f, 0.45f, 0.35f, 0.45f,
        (lumis_bsdf){
            LUMIS_BSDF_GGX_PLASTIC, {0.6f, 0.12f, 0.08f}, {0.04f, 0.04f, 0.04f}, 0.2f, 0.2f});
    lumis_object ground = ground_plane(0.5f);
    f->camera = (lumis_camera){{0, 1.3f, 4.0f}, {0.1f, 0.45f, 0}, {0, 1, 0}, 35.0f, 640, 480};
    if ((st = lumis__scene_file_push(f, &bunny)) != LUMIS_OK) return st;
    if ((st = lumis__scene_file_push(f, &ball)) != LUMIS_OK) return st;
    return lumis__scene_file_push(f, &ground);
}

/* Wu's test scenes, as described: three or four objects on a ground plane, from diffuse to
 * semi-glossy, lit by the map alone, so that shadows matter.  The bunny, Suzanne and a
 * sphere (and in wu-mixed a second, small sphere), the same layout in each; only the
 * materials change. */
typedef struct wu_materials {
    lumis_bsdf bunny, suzi, ball, extra;
    int has_extra;
    const lumis_bsdf *ground; /* NULL: Lambertian, albedo 0.5 */
} wu_materials;

static lumis_status wu_scene(lumis_scene_file *f, const wu_materials *m)
{
    lumis_object bunny, suzi;
    lumis_status st = embedded_mesh(f, "builtin:bunny", lumis__bunny_glb, lumis__bunny_glb_size,
                                    1.0f, -1.15f, -0.1f, 25.0f, 1, m->bunny, &bunny);
    if (st == LUMIS_OK)
        st = embedded_mesh(f, "builtin:suzi", lumis__suzi_glb, lumis__suzi_glb_size, 0.95f, 0.1f,
                           -0.35f, -15.0f, 1, m->suzi, &suzi);
    if (st != LUMIS_OK) return st;
    lumis_object ball = sphere(1.25f, 0.5f, 0.15f, 0.5f, m->ball);
    lumis_object extra = sphere(0.35f, 0.22f, 0.75f, 0.22f, m->extra);
    lumis_object ground = ground_plane(0.5f);
    if (m->ground) ground.material = *m->ground;
    f->camera = (lumis_camera){{0, 1.6f, 4.2f}, {0.05f, 0.35f, 0}, {0, 1, 0}, 38.0f, 640, 480};
    if ((st = lumis__scene_file_push(f, &bunny)) != LUMIS_OK) return st;
    if ((st = lumis__scene_file_push(f, &suzi)) != LUMIS_OK) return st;
    if ((st = lumis__scene_file_push(f, &ball)) != LUMIS_OK) return st;
    if (m->has_extra && (st = lumis__scene_file_push(f, &extra)) != LUMIS_OK) return st;
    return lumis__scene_file_push(f, &ground);
}

static lumis_bsdf mat_lambert(float r, float g, float b)
{
    return (lumis_bsdf){LUMIS_BSDF_LAMBERT, {r, g, b}, {0, 0, 0}, 0, 0};
}

static lumis_bsdf mat_ward(float d, float sp, float alpha)
{
    return (lumis_bsdf){LUMIS_BSDF_WARD, {d, d, d}, {sp, sp, sp}, alpha, alpha};
}

static lumis_bsdf mat_plastic(float r, float g, float b, float alpha)
{
    return (lumis_bsdf){LUMIS_BSDF_GGX_PLASTIC, {r, g, b}, {0.04f, 0.04f, 0.04f}, alpha, alpha};
}

/* Every object Lambertian. */
static lumis_status wu_diffuse(lumis_scene_file *f)
{
    const wu_materials m = {mat_lambert(0.75f, 0.75f, 0.75f),
                            mat_lambert(0.7f, 0.55f, 0.35f),
                            mat_lambert(0.35f, 0.45f, 0.7f),
                            mat_lambert(0, 0, 0),
                            0,
                            NULL};
    return wu_scene(f, &m);
}

/* Broad glossy lobes (Ward, alpha 0.3): diffuse-looking, light direction still matters. */
static lumis_status wu_satin(lumis_scene_file *f)
{
    const wu_materials m = {mat_ward(0.6f, 0.15f, 0.3f),
                            mat_ward(0.5f, 0.2f, 0.3f),
                            mat_ward(0.45f, 0.25f, 0.25f),
                            mat_lambert(0, 0, 0),
                            0,
                            NULL};
    return wu_scene(f, &m);
}

/* Semi-glossy plastics (GGX, alpha 0.15 to 0.25). */
static lumis_status wu_glossy(lumis_scene_file *f)
{
    const wu_materials m = {mat_plastic(0.7f, 0.7f, 0.7f, 0.25f),
                            mat_plastic(0.6f, 0.35f, 0.15f, 0.2f),
                            mat_plastic(0.15f, 0.3f, 0.65f, 0.15f),
                            mat_lambert(0, 0, 0),
                            0,
                            NULL};
    return wu_scene(f, &m);
}

/* Four objects, diffuse to semi-glossy: a Lambertian bunny, a satin Suzanne, a plastic
 * sphere and a small rough copper sphere. */
static lumis_status wu_mixed(lumis_scene_file *f)
{
    const wu_materials m = {
        mat_lambert(0.75f, 0.75f, 0.75f),
        mat_ward(0.5f, 0.2f, 0.3f),
        mat_plastic(0.6f, 0.12f, 0.08f, 0.2f),
        (lumis_bsdf){LUMIS_BSDF_GGX_CONDUCTOR, {0, 0, 0}, {0.95f, 0.64f, 0.54f}, 0.3f, 0.3f},
        1,
        NULL};
    return wu_scene(f, &m);
}

static lumis_bsdf mat_glossy(float r, float g, float b, float alpha)
{
    return (lumis_bsdf){LUMIS_BSDF_GGX_GLOSSY, {0, 0, 0}, {r, g, b}, alpha, alpha};
}

/* Wu's three objects and the ground, every surface glossy GGX (Cycles' Glossy BSDF, no
 * diffuse part) at four roughnesses: a near-mirror sphere (0.05), Suzanne (0.15), the
 * bunny (0.3) and a rough ground (0.4).  What the map's bright parts reflect decides the
 * image: the BSDF's lobe, not the cosine, selects the light. */
static lumis_status glossy_only(lumis_scene_file *f)
{
    static const lumis_bsdf ground = {
        LUMIS_BSDF_GGX_GLOSSY, {0, 0, 0}, {0.5f, 0.5f, 0.5f}, 0.4f, 0.4f};
    const wu_materials m = {mat_glossy(0.75f, 0.75f, 0.75f, 0.3f),
                            mat_glossy(0.8f, 0.55f, 0.3f, 0.15f),
                            mat_glossy(0.6f, 0.7f, 0.9f, 0.05f),
                            mat_lambert(0, 0, 0),
                            0,
                            &ground};
    return wu_scene(f, &m);
}

/* The room of `window`: a box 4 wide (x), 2.5 high (y), 5 deep (z) whose only opening is
 * a window 0.8 wide and 0.6 high in the wall x = +2, its sill 1.2 above the floor.  The
 * walls are one mesh of axis-aligned quads, each overlapping its neighbours by 1 cm so no
 * edge lets light through (the walls stand on the floor, which reaches 1 cm past them); written as
 * OBJ text and read by assimp like the other meshes. */
static lumis_status window_room(lumis_scene_file *f, lumis_object *o)
{
    static const float W = 2.0f, H = 2.5f, D = 2.5f, e = 0.01f;
    static const float z0 = -0.4f, z1 = 0.4f, y0 = 1.2f, y1 = 1.8f; /* the window */
    /* quads as (axis of the normal, its coordinate, two ranges of the others in order
     * (x, y, z) without the axis) */
    const float q[][6] = {
        {1, 0, -W - e, W + e, -D - e, D + e}, /* floor y = 0: x, z */
        {1, H, -W - e, W + e, -D - e, D + e}, /* ceiling */
        {0, -W, 0, H + e, -D - e, D + e},     /* wall x = -W: y, z */
        {2, -D, -W - e, W + e, 0, H + e},     /* wall z = -D: x, y */
        {2, D, -W - e, W + e, 0, H + e},      /* wall z = +D */
        {0, W, 0, y0, -D - e, D + e},         /* wall x = +W: below the window */
        {0, W, y1, H + e, -D - e, D + e},     /* above it */
        {0, W, y0 - e, y1 + e, -D - e, z0},   /* beside it */
        {0, W, y0 - e, y1 + e, z1, D + e},    /* and on its other side */
    };
    enum { NQ = sizeof q / sizeof *q };
    char text[NQ * 4 * 64 + NQ * 2 * 64];
    size_t n = 0;
    for (int k = 0; k < NQ; k++) {
        const int ax = (int)q[k][0];
        const float a[4][2] = {
            {q[k][2], q[k][4]}, {q[k][3], q[k][4]}, {q[k][3], q[k][5]}, {q[k][2], q[k][5]}};
        for (int c = 0; c < 4; c++) {
            float v[3];
            v[ax] = q[k][1];
            v[ax == 0 ? 1 : 0] = a[c][0];
            v[ax == 2 ? 1 : 2] = a[c][1];
            n += (size_t)snprintf(text + n, sizeof text - n, "v %.3f %.3f %.3f\n", (double)v[0],
                                  (double)v[1], (double)v[2]);
        }
    }
    for (int k = 0; k < NQ; k++)
        n += (size_t)snprintf(text + n, sizeof text - n, "f %d %d %d\nf %d %d %d\n", 4 * k + 1,
                              4 * k + 2, 4 * k + 3, 4 * k + 1, 4 * k + 3, 4 * k + 4);
    if (n >= sizeof text) return LUMIS_ERR_CORRUPT; /* cannot happen: 3 short numbers a line */
    const struct aiScene *sc = aiImportFileFromMemory(
        text, (unsigned)n, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices, "obj");
    if (!sc) return LUMIS_ERR_CORRUPT;
    memset(o, 0, sizeof *o);
    o->type = LUMIS_OBJECT_MESH;
    const lumis_status st = lumis__scene_file_add_mesh(f, "builtin:window-room", sc, o);
    aiReleaseImport(sc);
    o->material = mat_lambert(0.6f, 0.6f, 0.6f);
    return st;
}

/* A closed room lit only through a small window (window_room): the map is seen through
 * 0.48 m^2 of opening, so from any point inside most directions are occluded, and what
 * comes through depends on where the map is bright.  Inside: a Lambertian sphere and a
 * glossy plastic one; the camera, in the corner beside the window's wall, looks across the
 * room at what the window lights (the floor, the far walls, the spheres). */
static lumis_status window_scene(lumis_scene_file *f)
{
    lumis_object room;
    lumis_status st = window_room(f, &room);
    if (st != LUMIS_OK) return st;
    lumis_object ball = sphere(0.6f, 0.45f, -0.9f, 0.45f, mat_lambert(0.7f, 0.7f, 0.7f));
    lumis_object gloss = sphere(0.4f, 0.35f, 1.0f, 0.35f, mat_plastic(0.6f, 0.12f, 0.08f, 0.2f));
    f->camera =
        (lumis_camera){{1.7f, 1.7f, 2.3f}, {-1.0f, 0.6f, -1.0f}, {0, 1, 0}, 60.0f, 640, 480};
    if ((st = lumis__scene_file_push(f, &room)) != LUMIS_OK) return st;
    if ((st = lumis__scene_file_push(f, &ball)) != LUMIS_OK) return st;
    return lumis__scene_file_push(f, &gloss);
}

/* An open ground plane seen from above, with the bunny and three spheres (Lambertian,
 * plastic, rough copper) spread over it and nothing overhead: the whole upper hemisphere
 * lights every point of the ground away from the objects' shadows (an open sky: pair it
 * with sunny and overcast maps). */
static lumis_status open_sky(lumis_scene_file *f)
{
    lumis_object bunny;
    lumis_status st =
        embedded_mesh(f, "builtin:bunny", lumis__bunny_glb, lumis__bunny_glb_size, 0.9f, -1.4f,
                      0.6f, 35.0f, 1, mat_lambert(0.75f, 0.75f, 0.75f), &bunny);
    if (st != LUMIS_OK) return st;
    const lumis_object balls[3] = {
        sphere(1.3f, 0.4f, 0.9f, 0.4f, mat_lambert(0.35f, 0.45f, 0.7f)),
        sphere(0.1f, 0.5f, -1.2f, 0.5f, mat_plastic(0.6f, 0.5f, 0.2f, 0.2f)),
        sphere(
            -0.2f, 0.25f, 1.6f, 0.25f,
            (lumis_bsdf){LUMIS_BSDF_GGX_CONDUCTOR, {0, 0, 0}, {0.95f, 0.64f, 0.54f}, 0.3f, 0.3f}),
    };
    lumis_object ground = ground_plane(0.5f);
    f->camera = (lumis_camera){{0, 4.5f, 5.0f}, {0, 0.2f, 0.1f}, {0, 1, 0}, 45.0f, 640, 480};
    if ((st = lumis__scene_file_push(f, &bunny)) != LUMIS_OK) return st;
    for (int k = 0; k < 3; k++)
        if ((st = lumis__scene_file_push(f, &balls[k])) != LUMIS_OK) return st;
    return lumis__scene_file_push(f, &ground);
}

/* A car headlight (the "car" preset, in millimetres) 0.7 m above a floor, aimed 5 degrees
 * down towards a wall 5 m away, with the bunny and a glossy sphere in its beam: shadows on
 * the floor and on the wall (Lu et al., Fig. 13). */
static lumis_status headlight_scene(lumis_scene_file *f, const lumis_luminaire *given)
{
    lumis_luminaire *lum = NULL; /* acquired here and owned by f, unless one is given */
    lumis_status st =
        given ? LUMIS_OK
              : lumis_luminaire_preset_create(LUMIS_PRESET_CAR, LUMIS_BASIS_DEFAULT, NULL, &lum);
    if (st != LUMIS_OK) return st;
    const double tilt = 5.0 * LUMIS_PI / 180.0, sn = sin(tilt), cs = cos(tilt);
    /* Local +z (the beam) to (0, -sin, -cos), local +y to up-ish, local +x to -x. */
    lumis_luminaire_instance in = {
        given ? given : lum, {{-1, 0, 0, 0, cs, -sn, 0, -sn, -cs}, {0, 0.7, 0}}, 0.001, 8000.0f};
    if ((st = lumis__scene_file_add_luminaire(f, lum, "preset:car", &in)) != LUMIS_OK) return st;
    lumis_object bunny;
    st = embedded_mesh(f, "builtin:bunny", lumis__bunny_glb, lumis__bunny_glb_size, 0.6f, -0.5f,
                       -2.2f, 30.0f, 1, mat_lambert(0.75f, 0.75f, 0.75f), &bunny);
    if (st != LUMIS_OK) return st;
    lumis_object ball = sphere(0.55f, 0.3f, -2.8f, 0.3f, mat_plastic(0.6f, 0.12f, 0.08f, 0.2f));
    lumis_object floor_ = ground_plane(0.5f);
    floor_.size = 40.0f;
    lumis_object wall;
    memset(&wall, 0, sizeof wall);
    wall.type = LUMIS_OBJECT_PLANE;
    wall.center = (lumis_vec3){0, 0, -5.0f};
    wall.normal = (lumis_vec3){0, 0, 1};
    wall.size = 40.0f;
    wall.material = mat_lambert(0.7f, 0.7f, 0.7f);
    if ((st = lumis__scene_file_push(f, &bunny)) != LUMIS_OK) return st;
    if ((st = lumis__scene_file_push(f, &ball)) != LUMIS_OK) return st;
    if ((st = lumis__scene_file_push(f, &floor_)) != LUMIS_OK) return st;
    return lumis__scene_file_push(f, &wall);
}

/* The whole scene from behind and above the lamp. */
static void headlight_far(lumis_scene_file *f)
{
    f->camera = (lumis_camera){{2.2f, 1.8f, 1.2f}, {0, 0.3f, -2.8f}, {0, 1, 0}, 45.0f, 640, 400};
}

/* The floor just in front of the lamp, where the beam starts (the near field). */
static void headlight_close(lumis_scene_file *f)
{
    f->camera = (lumis_camera){{0.6f, 0.9f, 0.3f}, {0, 0, -1.6f}, {0, 1, 0}, 40.0f, 640, 400};
}

lumis_status lumis_scene_builtin(const char *name, const lumis_error_sink *errors,
                                 lumis_scene_file **out)
{
    return lumis_scene_builtin_with_luminaire(name, NULL, errors, out);
}

lumis_status lumis_scene_builtin_with_luminaire(const char *name, const lumis_luminaire *luminaire,
                                                const lumis_error_sink *errors,
                                                lumis_scene_file **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    void (*camera)(lumis_scene_file *) = NULL; /* the headlight scenes */
    if (name && strcmp(name, "headlight") == 0) camera = headlight_far;
    if (name && strcmp(name, "headlight-close") == 0) camera = headlight_close;
    /* (lumis_scene_builtin_has_luminaires names the same two) */
    if (luminaire && !camera)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "scene '%s' places no luminaire (headlight and headlight-close do)",
                           name ? name : "(null)");
    lumis_status (*make)(lumis_scene_file *) = NULL;
    if (name && strcmp(name, "spheres") == 0) make = spheres;
    if (name && strcmp(name, "bunny-plane") == 0) make = bunny_plane;
    if (name && strcmp(name, "ward-aniso") == 0) make = ward_aniso;
    if (name && strcmp(name, "wu-diffuse") == 0) make = wu_diffuse;
    if (name && strcmp(name, "wu-satin") == 0) make = wu_satin;
    if (name && strcmp(name, "wu-glossy") == 0) make = wu_glossy;
    if (name && strcmp(name, "wu-mixed") == 0) make = wu_mixed;
    if (name && strcmp(name, "glossy-only") == 0) make = glossy_only;
    if (name && strcmp(name, "window") == 0) make = window_scene;
    if (name && strcmp(name, "open-sky") == 0) make = open_sky;
    if (!make && !camera)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "unknown scene '%s' (built in: spheres, bunny-plane, ward-aniso, "
                           "wu-diffuse, wu-satin, wu-glossy, wu-mixed, headlight, "
                           "headlight-close, glossy-only, window, open-sky)",
                           name ? name : "(null)");
    lumis_scene_file *f = lumis__scene_file_new();
    if (!f) return LUMIS_ERR_OUT_OF_MEMORY;
    lumis_status st = LUMIS_OK;
    if (camera) {
        camera(f);
        st = headlight_scene(f, luminaire);
    } else {
        st = make(f);
    }
    if (st != LUMIS_OK) {
        lumis_scene_file_destroy(f);
        return lumis__fail(errors, st, "scene %s: %s", name, lumis_status_string(st));
    }
    *out = f;
    return LUMIS_OK;
}
