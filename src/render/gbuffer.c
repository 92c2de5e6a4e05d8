/* The G-buffer (normals, albedo, depth per pixel) that joint-bilateral upsampling reads. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "camera.h"
#include "internal.h"
#include "scene.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>

void lumis_gbuffer_destroy(lumis_gbuffer *g)
{
    if (!g) return;
    free(g->normal);
    free(g);
}

lumis_status lumis_render_gbuffer(const lumis_scene *scene, const lumis_camera *camera,
                                  const lumis_error_sink *errors, lumis_gbuffer **out)
{
    return lumis__render_gbuffer(scene, camera, 0, errors, out);
}

lumis_status lumis__render_gbuffer(const lumis_scene *scene, const lumis_camera *camera,
                                   int threads, const lumis_error_sink *errors, lumis_gbuffer **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!scene) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "gbuffer: needs a scene");
    cam_frame cf;
    lumis_status st = lumis__camera_frame(camera, errors, &cf);
    if (st != LUMIS_OK) return st;
    const int w = cf.cam.width, h = cf.cam.height;
    const size_t n = (size_t)w * (size_t)h;
    lumis_gbuffer *g = calloc(1, sizeof *g);
    float *mem = g ? malloc(7 * sizeof(float) * n) : NULL;
    if (!mem) {
        free(g);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "gbuffer: %d x %d: out of memory", w,
                           h);
    }
    g->width = w;
    g->height = h;
    g->normal = mem;
    g->albedo = mem + 3 * n;
    g->depth = mem + 6 * n;
    if (threads <= 0) threads = omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 4) num_threads(threads)
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const size_t p = (size_t)y * (size_t)w + (size_t)x;
            v3 dir = camera_dir(&cf, (x + 0.5) / w * 2.0 - 1.0, 1.0 - (y + 0.5) / h * 2.0);
            hit hh;
            float *nn = g->normal + 3 * p, *a = g->albedo + 3 * p;
            if (!intersect(scene, cf.eye, dir, &hh)) {
                nn[0] = nn[1] = nn[2] = 0.0f;
                a[0] = a[1] = a[2] = 0.0f;
                g->depth[p] = INFINITY;
                continue;
            }
            nn[0] = (float)hh.n.x;
            nn[1] = (float)hh.n.y;
            nn[2] = (float)hh.n.z;
            const lumis_bsdf *m = &hh.prim->material;
            const lumis_rgb c =
                m->type == LUMIS_BSDF_GGX_CONDUCTOR || m->type == LUMIS_BSDF_GGX_GLOSSY
                    ? m->specular
                    : m->diffuse;
            a[0] = c.r;
            a[1] = c.g;
            a[2] = c.b;
            v3 dp = sub(hh.p, cf.eye);
            g->depth[p] = (float)sqrt(dot(dp, dp));
        }
    *out = g;
    return LUMIS_OK;
}