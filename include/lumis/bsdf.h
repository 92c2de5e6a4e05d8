/* lumis/bsdf.h - the evaluation renderer's BSDFs (library lumis-render).
 *
 * All directions are in the local shading frame: z is the normal, x the tangent along
 * which alpha_x applies.  Reflection only (both directions above the surface).
 * eval() returns the BSDF value f (not multiplied by the cosine); pdf() and sample() use
 * densities per steradian of the incident direction wi.  Each sampler is exact: the pdf
 * sample() returns equals pdf(wo, wi) for the direction it returns, and integrates to
 * at most 1 (less where sampled directions fall below the surface and are rejected).
 * Derivations: docs/bsdf.md. */
#ifndef LUMIS_BSDF_H
#define LUMIS_BSDF_H

#include "lumis/export.h"
#include "lumis/types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum lumis_bsdf_type {
    LUMIS_BSDF_LAMBERT = 0,   /* albedo / pi; cosine-weighted sampling */
    LUMIS_BSDF_WARD,          /* diffuse + anisotropic Ward lobe (bounded-albedo normalisation),
                                 sampled as in Walter's 2005 notes */
    LUMIS_BSDF_GGX_CONDUCTOR, /* GGX microfacets, Schlick Fresnel from `specular` as F0,
                                 height-correlated Smith masking, visible-normal sampling */
    LUMIS_BSDF_GGX_PLASTIC,   /* a dielectric GGX coat (F0 0.04) over a Lambertian base */
    LUMIS_BSDF_GGX_GLOSSY,    /* Cycles 3.x's Glossy BSDF (GGX): `specular` as a constant colour
                                 (no Fresnel), separable Smith masking G1(wo) G1(wi),
                                 visible-normal sampling; Cycles' roughness r is alpha = r^2 */
    LUMIS_BSDF_TYPE_COUNT
} lumis_bsdf_type;

typedef struct lumis_bsdf {
    lumis_bsdf_type type;
    lumis_rgb diffuse;      /* Lambert albedo; Ward's and plastic's diffuse part */
    lumis_rgb specular;     /* Ward's specular albedo; GGX conductor's F0; glossy's colour */
    float alpha_x, alpha_y; /* roughness along x and y (Ward, GGX); 0 == 0.1 */
} lumis_bsdf;

/* f(wo, wi). */
LUMIS_RENDER_API lumis_rgb lumis_bsdf_eval(const lumis_bsdf *b, lumis_vec3 wo, lumis_vec3 wi);

/* Density per steradian of sample() choosing wi given wo. */
LUMIS_RENDER_API float lumis_bsdf_pdf(const lumis_bsdf *b, lumis_vec3 wo, lumis_vec3 wi);

typedef struct lumis_bsdf_sample {
    lumis_vec3 wi;
    float pdf;        /* 0: no sample (the direction fell below the surface) */
    lumis_rgb weight; /* f cos(theta_i) / pdf, 0 when pdf is 0 */
} lumis_bsdf_sample;

/* Draws wi from three uniform numbers in [0, 1) (u0 chooses a lobe where there are two). */
LUMIS_RENDER_API lumis_bsdf_sample lumis_bsdf_sample_wi(const lumis_bsdf *b, lumis_vec3 wo,
                                                        double u0, double u1, double u2);

#ifdef __cplusplus
}
#endif
#endif
