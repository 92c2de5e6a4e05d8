/* Decodes a mesh file with assimp exactly as lumis-render does for its built-in meshes
 * (aiProcess_Triangulate | JoinIdenticalVertices | PreTransformVertices; the glTF's Draco
 * compression included) and writes its vertices and triangles, untransformed, as OBJ.
 * bench/cycles/scene.py places the bunny from this file the way builtin.c's embedded_mesh
 * places it, so Cycles sees the same triangles as lumis.
 *
 *   cc -O2 -o /tmp/cycles/glb2obj bench/cycles/glb2obj.c -lassimp
 *   /tmp/cycles/glb2obj assets/bunny.glb > bench/cycles/bunny-assimp.obj */
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <stdio.h>

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: glb2obj MESH.glb > MESH.obj\n");
        return 2;
    }
    const struct aiScene *sc =
        aiImportFile(argv[1], aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                  aiProcess_PreTransformVertices);
    if (!sc) {
        fprintf(stderr, "glb2obj: %s: %s\n", argv[1], aiGetErrorString());
        return 1;
    }
    printf("# %s decoded by assimp (Triangulate, JoinIdenticalVertices, PreTransformVertices)\n",
           argv[1]);
    unsigned base = 1;
    for (unsigned m = 0; m < sc->mNumMeshes; m++) {
        const struct aiMesh *mesh = sc->mMeshes[m];
        for (unsigned k = 0; k < mesh->mNumVertices; k++)
            printf("v %.9g %.9g %.9g\n", mesh->mVertices[k].x, mesh->mVertices[k].y,
                   mesh->mVertices[k].z);
        for (unsigned f = 0; f < mesh->mNumFaces; f++) {
            const struct aiFace *fc = &mesh->mFaces[f];
            if (fc->mNumIndices != 3) continue; /* as lumis: points and lines are dropped */
            printf("f %u %u %u\n", base + fc->mIndices[0], base + fc->mIndices[1],
                   base + fc->mIndices[2]);
        }
        base += mesh->mNumVertices;
    }
    aiReleaseImport(sc);
    return 0;
}
