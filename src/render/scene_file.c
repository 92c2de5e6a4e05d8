/* A scene file as an object (lumis/render.h): what it owns and how it grows (objects and
 * the meshes they borrow, assimp's triangles copied in, luminaire instances and the
 * luminaires they point to, photometric fixtures and their files, each read once), mesh
 * files through assimp, and the placement matrices.  The JSON schema and its messages are
 * scene_file_read.c's. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "internal.h"

#include "lumis/io.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A scene file owns its meshes through this registry (objects only borrow the arrays, so
 * several can share one mesh). */
typedef struct mesh_entry {
    char path[4096]; /* resolved file name, or a built-in name */
    float *vertices;
    unsigned *indices;
    int vertex_count, triangle_count;
} mesh_entry;

typedef struct file_private {
    lumis_scene_file pub; /* first: a lumis_scene_file * is a file_private * */
    mesh_entry *meshes;
    int mesh_count, object_cap;
    lumis_luminaire **owned; /* the luminaires the instances point to, each once */
    char **owned_paths;      /* the file (or preset) each was read from; NULL: none */
    int owned_count, luminaire_cap;
    /* photometric files the fixtures point to, each read once, and their paths */
    lumis_photometric_file **pfiles;
    char **ppaths;
    int pfile_count;
} file_private;

lumis_scene_file *lumis__scene_file_new(void)
{
    file_private *fp = calloc(1, sizeof *fp);
    if (!fp) return NULL;
    fp->pub.camera = (lumis_camera){{0, 1, 5}, {0, 0.5f, 0}, {0, 1, 0}, 40.0f, 640, 480};
    fp->pub.env_scale = 1.0f;
    return &fp->pub;
}

void lumis_scene_file_destroy(lumis_scene_file *f)
{
    if (!f) return;
    file_private *fp = (file_private *)f;
    for (int k = 0; k < fp->mesh_count; k++) {
        free(fp->meshes[k].vertices);
        free(fp->meshes[k].indices);
    }
    free(fp->meshes);
    free(f->objects);
    for (int k = 0; k < fp->owned_count; k++) {
        lumis_luminaire_destroy(fp->owned[k]);
        free(fp->owned_paths[k]);
    }
    free(fp->owned);
    free(fp->owned_paths);
    free(f->luminaires);
    for (int k = 0; k < fp->pfile_count; k++) {
        lumis_photometric_file_destroy(fp->pfiles[k]);
        free(fp->ppaths[k]);
    }
    free(fp->pfiles);
    free(fp->ppaths);
    free(f->photometrics);
    lumis_image_destroy(f->env_image);
    free(f);
}

const char *lumis_scene_file_mesh_path(const lumis_scene_file *f, int index)
{
    const file_private *fp = (const file_private *)f;
    return f && index >= 0 && index < fp->mesh_count ? fp->meshes[index].path : NULL;
}

/* Appends a copy of o; its mesh arrays must be registered with the file. */
lumis_status lumis__scene_file_push(lumis_scene_file *f, const lumis_object *o)
{
    file_private *fp = (file_private *)f;
    if (f->object_count == fp->object_cap) {
        if (fp->object_cap > (1 << 24)) return LUMIS_ERR_TOO_LARGE;
        int cap = fp->object_cap ? 2 * fp->object_cap : 8;
        lumis_object *grown = realloc(f->objects, (size_t)cap * sizeof *grown);
        if (!grown) return LUMIS_ERR_OUT_OF_MEMORY;
        f->objects = grown;
        fp->object_cap = cap;
    }
    f->objects[f->object_count++] = *o;
    return LUMIS_OK;
}

lumis_status lumis__scene_file_add_luminaire(lumis_scene_file *f, lumis_luminaire *owned,
                                             const char *path, const lumis_luminaire_instance *in)
{
    file_private *fp = (file_private *)f;
    char *copy = NULL;
    if (owned && path && !(copy = malloc(strlen(path) + 1))) {
        lumis_luminaire_destroy(owned);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    if (copy) strcpy(copy, path);
    if (f->luminaire_count == fp->luminaire_cap) {
        if (fp->luminaire_cap >= 4096) {
            lumis_luminaire_destroy(owned);
            free(copy);
            return LUMIS_ERR_TOO_LARGE;
        }
        const int cap = fp->luminaire_cap ? 2 * fp->luminaire_cap : 4;
        lumis_luminaire_instance *grown = realloc(f->luminaires, (size_t)cap * sizeof *grown);
        lumis_luminaire **og = grown ? realloc(fp->owned, (size_t)cap * sizeof *og) : NULL;
        char **pg = og ? realloc(fp->owned_paths, (size_t)cap * sizeof *pg) : NULL;
        if (grown) f->luminaires = grown;
        if (og) fp->owned = og;
        if (pg) fp->owned_paths = pg;
        if (!grown || !og || !pg) {
            lumis_luminaire_destroy(owned);
            free(copy);
            return LUMIS_ERR_OUT_OF_MEMORY;
        }
        fp->luminaire_cap = cap;
    }
    if (owned) {
        fp->owned_paths[fp->owned_count] = copy;
        fp->owned[fp->owned_count++] = owned;
    }
    f->luminaires[f->luminaire_count++] = *in;
    return LUMIS_OK;
}

const char *lumis_scene_file_luminaire_path(const lumis_scene_file *f, int index)
{
    const file_private *fp = (const file_private *)f;
    return f && index >= 0 && index < fp->owned_count ? fp->owned_paths[index] : NULL;
}

lumis_luminaire *lumis__scene_file_luminaire(const lumis_scene_file *f, const char *path)
{
    const file_private *fp = (const file_private *)f;
    for (int k = 0; k < fp->owned_count; k++)
        if (fp->owned_paths[k] && strcmp(fp->owned_paths[k], path) == 0) return fp->owned[k];
    return NULL;
}

/* 1 and o's mesh fields pointed at the mesh f registered under name, or 0 (o untouched). */
static int find_mesh(const lumis_scene_file *f, const char *name, lumis_object *o)
{
    const file_private *fp = (const file_private *)f;
    for (int k = 0; k < fp->mesh_count; k++)
        if (strcmp(fp->meshes[k].path, name) == 0) {
            const mesh_entry *e = &fp->meshes[k];
            o->vertices = e->vertices;
            o->indices = e->indices;
            o->vertex_count = e->vertex_count;
            o->triangle_count = e->triangle_count;
            return 1;
        }
    return 0;
}

static lumis_status mesh_from_assimp(const struct aiScene *sc, lumis_object *o)
{
    size_t nv = 0, nt = 0;
    for (unsigned m = 0; m < sc->mNumMeshes; m++) {
        nv += sc->mMeshes[m]->mNumVertices;
        for (unsigned f = 0; f < sc->mMeshes[m]->mNumFaces; f++)
            nt += sc->mMeshes[m]->mFaces[f].mNumIndices == 3;
    }
    if (nt == 0 || nv > 0x7fffffff || nt > 0x7fffffff) return LUMIS_ERR_CORRUPT;
    float *v = malloc(nv * 3 * sizeof(float));
    unsigned *idx = malloc(nt * 3 * sizeof(unsigned));
    if (!v || !idx) {
        free(v);
        free(idx);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    size_t vbase = 0, t = 0;
    for (unsigned m = 0; m < sc->mNumMeshes; m++) {
        const struct aiMesh *mesh = sc->mMeshes[m];
        for (unsigned k = 0; k < mesh->mNumVertices; k++) {
            v[3 * (vbase + k)] = mesh->mVertices[k].x;
            v[3 * (vbase + k) + 1] = mesh->mVertices[k].y;
            v[3 * (vbase + k) + 2] = mesh->mVertices[k].z;
        }
        for (unsigned f = 0; f < mesh->mNumFaces; f++) {
            const struct aiFace *fc = &mesh->mFaces[f];
            if (fc->mNumIndices != 3) continue; /* points and lines left by triangulation */
            for (int c = 0; c < 3; c++)
                idx[3 * t + (size_t)c] = (unsigned)(vbase + fc->mIndices[c]);
            t++;
        }
        vbase += mesh->mNumVertices;
    }
    o->vertices = v;
    o->indices = idx;
    o->vertex_count = (int)nv;
    o->triangle_count = (int)nt;
    return LUMIS_OK;
}

/* Converts an assimp scene into a mesh the file owns, and points o at it. */
lumis_status lumis__scene_file_add_mesh(lumis_scene_file *f, const char *name,
                                        const struct aiScene *sc, lumis_object *o)
{
    file_private *fp = (file_private *)f;
    mesh_entry *grown = realloc(fp->meshes, (size_t)(fp->mesh_count + 1) * sizeof *grown);
    if (!grown) return LUMIS_ERR_OUT_OF_MEMORY;
    fp->meshes = grown;
    lumis_status st = mesh_from_assimp(sc, o);
    if (st != LUMIS_OK) return st;
    mesh_entry *e = &grown[fp->mesh_count++];
    snprintf(e->path, sizeof e->path, "%s", name);
    e->vertices = (float *)o->vertices;
    e->indices = (unsigned *)o->indices;
    e->vertex_count = o->vertex_count;
    e->triangle_count = o->triangle_count;
    return LUMIS_OK;
}

lumis_status lumis__scene_file_load_mesh(lumis_scene_file *f, const char *full, const char *file,
                                         const char *path, const lumis_error_sink *errors,
                                         lumis_object *o)
{
    if (find_mesh(f, full, o)) return LUMIS_OK;
    const struct aiScene *sc =
        aiImportFile(full, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                               aiProcess_PreTransformVertices);
    if (!sc)
        return lumis__fail(errors, LUMIS_ERR_OPEN, "%s: %s.file: cannot load mesh %s: %s", file,
                           path, full, aiGetErrorString());
    /* A NaN or huge vertex made its triangles vanish from the render without a word. */
    for (unsigned m = 0; m < sc->mNumMeshes; m++)
        for (unsigned k = 0; k < sc->mMeshes[m]->mNumVertices; k++) {
            const struct aiVector3D q = sc->mMeshes[m]->mVertices[k];
            if (!(fabs(q.x) <= 1e30 && fabs(q.y) <= 1e30 && fabs(q.z) <= 1e30)) {
                const double x = q.x, y = q.y, z = q.z;
                aiReleaseImport(sc);
                return lumis__fail(errors, LUMIS_ERR_CORRUPT,
                                   "%s: %s.file: %s: vertex %u of mesh %u is (%g, %g, %g): "
                                   "every coordinate must be finite and at most 1e30",
                                   file, path, full, k, m, x, y, z);
            }
        }
    lumis_status st = lumis__scene_file_add_mesh(f, full, sc, o);
    aiReleaseImport(sc);
    if (st == LUMIS_ERR_CORRUPT)
        return lumis__fail(errors, st, "%s: %s.file: %s has no triangles", file, path, full);
    return st;
}

const char *lumis_scene_file_photometric_path(const lumis_scene_file *f, int index)
{
    const file_private *fp = (const file_private *)f;
    return f && index >= 0 && index < fp->pfile_count ? fp->ppaths[index] : NULL;
}

lumis_photometric_file *lumis__scene_file_photometric(lumis_scene_file *f, const char *path,
                                                      const lumis_error_sink *errors,
                                                      lumis_status *st)
{
    file_private *fp = (file_private *)f;
    for (int k = 0; k < fp->pfile_count; k++)
        if (strcmp(fp->ppaths[k], path) == 0) return fp->pfiles[k];
    if (fp->pfile_count % 8 == 0) {
        lumis_photometric_file **g = realloc(fp->pfiles, (size_t)(fp->pfile_count + 8) * sizeof *g);
        char **h = g ? realloc(fp->ppaths, (size_t)(fp->pfile_count + 8) * sizeof *h) : NULL;
        if (g) fp->pfiles = g;
        if (h) fp->ppaths = h;
        if (!g || !h) {
            *st = LUMIS_ERR_OUT_OF_MEMORY;
            return NULL;
        }
    }
    char *copy = malloc(strlen(path) + 1);
    if (!copy) {
        *st = LUMIS_ERR_OUT_OF_MEMORY;
        return NULL;
    }
    strcpy(copy, path);
    lumis_photometric_file *pf = NULL;
    *st = lumis_photometric_read(path, errors, &pf);
    if (*st != LUMIS_OK) {
        free(copy);
        return NULL;
    }
    fp->ppaths[fp->pfile_count] = copy;
    fp->pfiles[fp->pfile_count++] = pf;
    return pf;
}

/* Scale, then rotation R = Rz Ry Rx (degrees), then translation, as a row-major 3x4
 * matrix. */
void lumis__rotation_deg(const float r[3], double m[9])
{
    const double cx = cos(r[0] * LUMIS_PI / 180), sx = sin(r[0] * LUMIS_PI / 180);
    const double cy = cos(r[1] * LUMIS_PI / 180), sy = sin(r[1] * LUMIS_PI / 180);
    const double cz = cos(r[2] * LUMIS_PI / 180), sz = sin(r[2] * LUMIS_PI / 180);
    for (int j = 0; j < 3; j++) { /* column j: the image of e_j */
        double x = j == 0, y = j == 1, z = j == 2;
        double y1 = cx * y - sx * z, z1 = sx * y + cx * z;     /* about x */
        double x2 = cy * x + sy * z1, z2 = -sy * x + cy * z1;  /* about y */
        double x3 = cz * x2 - sz * y1, y3 = sz * x2 + cz * y1; /* about z */
        m[j] = x3;
        m[3 + j] = y3;
        m[6 + j] = z2;
    }
}

void lumis__transform_matrix(const float t[3], const float r[3], const float s[3], float m[12])
{
    double rot[9];
    lumis__rotation_deg(r, rot);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) m[4 * i + j] = (float)(rot[3 * i + j] * s[j]);
        m[4 * i + 3] = t[i];
    }
}
