/* lumis/render_gbuffer.h - G-buffers and joint-bilateral upsampling (Wu's reduced-
 * resolution EnvIndirects) (library lumis-render; lumis/render.h includes every part). */
#ifndef LUMIS_RENDER_GBUFFER_H_PUBLIC
#define LUMIS_RENDER_GBUFFER_H_PUBLIC

#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/render_job.h"
#include "lumis/render_scene.h"
#include "lumis/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- G-buffer and joint-bilateral upsampling (Wu's reduced-resolution EnvIndirects) ------
 *
 * A G-buffer holds, per pixel of a camera, what the primary ray through the pixel's centre
 * hits: the normal (facing the camera), the distance from the eye, and an albedo (the
 * material's diffuse colour; a conductor's F0).  A pixel that sees no object has depth
 * +inf, normal and albedo 0. */
typedef struct lumis_gbuffer {
    int width, height;
    float *normal; /* 3 per pixel, row-major, row 0 on top */
    float *albedo; /* 3 per pixel */
    float *depth;  /* 1 per pixel */
} lumis_gbuffer;

LUMIS_RENDER_API lumis_status lumis_render_gbuffer(const lumis_scene *scene,
                                                   const lumis_camera *camera,
                                                   const lumis_error_sink *errors,
                                                   lumis_gbuffer **out);
LUMIS_RENDER_API void lumis_gbuffer_destroy(lumis_gbuffer *gbuffer);

typedef struct lumis_upsample_desc {
    float sigma_normal;  /* range sigma on |n_p - n_q|; 0 == 0.005 (Wu) */
    float sigma_depth;   /* on the depth difference over the high-resolution buffer's depth
                            range (max - min over the pixels that see an object); 0 == 0.005 */
    float sigma_albedo;  /* on |a_p - a_q|; 0 == 0.005 */
    float sigma_spatial; /* on the distance in low-resolution pixels; 0 == 1.0 */
    int radius;          /* window radius in low-resolution pixels, at most 8; 0 == 2 (5 x 5) */
    int threads;         /* 0 == OpenMP's default */
    lumis_error_sink errors;
} lumis_upsample_desc;

/* Joint-bilateral upsampling (Kopf et al. 2007, as Wu uses it): each high-resolution pixel
 * p is the weighted mean of the low-resolution pixels q of a window around it, weights
 * G(spatial) G(normal) G(depth) G(albedo) from the two G-buffers (low's for q, high's for
 * p).  Pixels seeing no object take only others that see none (and the reverse).  Weights
 * are normalised by the largest, so a window with no similar pixel gives the most similar
 * (a soft nearest match), never an underflow.
 * low and low_g must have the same size, high_g gives the output's.  Details and the
 * tests: docs/render.md. */
LUMIS_RENDER_API lumis_status lumis_joint_bilateral_upsample(const lumis_image *low,
                                                             const lumis_gbuffer *low_g,
                                                             const lumis_gbuffer *high_g,
                                                             const lumis_upsample_desc *desc,
                                                             lumis_image **out);

#ifdef __cplusplus
}
#endif
#endif
