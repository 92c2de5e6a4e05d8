/* lumis/metrics.h - image-difference metrics between a reference and a test image.
 *
 * Every metric takes two lumis_image of the same size (linear Rec. 709 RGB, 3 floats a
 * pixel), borrows them for the duration of the call only, and returns a lumis_status;
 * messages with context go to the error sink in the options.  docs/metrics.md states
 * every definition and constant. */
#ifndef LUMIS_METRICS_H
#define LUMIS_METRICS_H

#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ==== FLIP (NVIDIA's LDR-FLIP and HDR-FLIP) ============================================
 *
 * Andersson et al., "FLIP: A Difference Evaluator for Alternating Images" (HPG 2020) and
 * "Visualizing Errors in Rendered High Dynamic Range Images" (Eurographics 2021).  The
 * results match NVIDIA's reference implementation (NVlabs/flip, v1.6) to about 1e-6 per
 * pixel; tests/test_metrics_flip.c pins them against numbers made by that tool. */

/* Pixels per degree of visual angle for an observer at distance metres from a display
 * width_m metres wide showing width_px pixels across. */
static inline double lumis_flip_pixels_per_degree(double distance_m, double width_m,
                                                  double width_px)
{
    return distance_m * (width_px / width_m) * (3.14159265358979323846 / 180.0);
}

/* The default: 0.7 m from a 0.7 m wide 4K (3840 pixels) display, about 67.02. */
#define LUMIS_FLIP_DEFAULT_PPD (0.7 * (3840.0 / 0.7) * (3.14159265358979323846 / 180.0))

/* Tone mappers of HDR-FLIP, as in the reference tool. */
typedef enum lumis_flip_tonemapper {
    LUMIS_FLIP_TONEMAP_DEFAULT = 0, /* ACES */
    LUMIS_FLIP_TONEMAP_ACES,        /* Narkowicz's ACES fit of 0.6 c, per channel */
    LUMIS_FLIP_TONEMAP_REINHARD,    /* c / (1 + Y), Y the luminance of c */
    LUMIS_FLIP_TONEMAP_HABLE        /* Hable's filmic curve as a rational fit */
} lumis_flip_tonemapper;

/* Options of both FLIP variants; valid when zeroed. */
typedef struct lumis_flip_options {
    double pixels_per_degree; /* 0 == LUMIS_FLIP_DEFAULT_PPD; otherwise in (0, 100000] */
    /* HDR-FLIP only.  The exposures (in stops: the image is scaled by 2^c) are computed
     * from the reference unless given; a given start must not exceed the stop. */
    int start_exposure_given; /* nonzero: use start_exposure */
    double start_exposure;
    int stop_exposure_given; /* nonzero: use stop_exposure */
    double stop_exposure;
    int num_exposures;                /* 0 == max(2, ceil(stop - start)); 1: start only */
    lumis_flip_tonemapper tonemapper; /* 0 == ACES */
    lumis_error_sink errors;          /* 0 == discard messages */
} lumis_flip_options;

/* What HDR-FLIP used besides the error map. */
typedef struct lumis_flip_hdr_result {
    double mean;           /* mean of the error map */
    double start_exposure; /* as given, or computed from the reference */
    double stop_exposure;
    int num_exposures;
} lumis_flip_hdr_result;

/* LDR-FLIP between two display-referred images given as LINEAR RGB.
 * Each channel is clamped to [0, 1] first (what the reference does with linear input);
 * an 8-bit sRGB file must be decoded to linear first (lumis_image_read does that for PNG),
 * which is what the reference tool does with PNG files.  NaN, infinite and negative
 * values count as 0.
 * error_map: NULL or width * height floats (row-major, row 0 at the top), each in [0, 1].
 * mean: NULL or the mean of the error map.
 * Memory: 32 bytes a pixel of scratch (36 without error_map), freed before returning.
 * Single-threaded: about 0.3 s for 1024 x 768 (docs/metrics.md).
 * Fails with LUMIS_ERR_INVALID_ARGUMENT for NULL or empty images, different sizes or a
 * bad pixels_per_degree; LUMIS_ERR_OUT_OF_MEMORY if the scratch cannot be had. */
LUMIS_API lumis_status lumis_flip_ldr(const lumis_image *reference, const lumis_image *test,
                                      const lumis_flip_options *options, float *error_map,
                                      double *mean);

/* HDR-FLIP between two scene-referred images (linear RGB, any non-negative values).
 * For each of num_exposures exposures c evenly spaced from start to stop, both images are
 * scaled by 2^c, tone mapped, clamped to [0, 1] and compared with LDR-FLIP; each pixel
 * keeps its largest error.  Unless given, start = log2(x / Ymax) and stop =
 * log2(x / Ymedian), with Ymax and Ymedian the largest and the median (element n/2 of
 * the n sorted values) luminance of the reference and x the value the tone mapper maps to
 * 0.85; that fails (LUMIS_ERR_INVALID_ARGUMENT) if Ymedian is 0: give the exposures then.
 * NaN, infinite and negative values count as 0.
 * error_map: NULL or width * height floats in [0, 1].
 * exposure_map: NULL or width * height floats: k / (num_exposures - 1) for the exposure k
 * that gave the largest error (0 where every exposure gave 0, and when num_exposures == 1).
 * result: NULL or what was used (mean, exposures).
 * Memory: 36 bytes a pixel of scratch (40 without error_map), freed before returning.
 * Costs num_exposures LDR-FLIP evaluations.
 * Fails like lumis_flip_ldr, and for a start exposure above the stop one, non-finite
 * exposures or a negative num_exposures. */
LUMIS_API lumis_status lumis_flip_hdr(const lumis_image *reference, const lumis_image *test,
                                      const lumis_flip_options *options, float *error_map,
                                      float *exposure_map, lumis_flip_hdr_result *result);

/* FLIP's magma colour map of an error map, as a new image for PNG output.
 * Value v (clamped to [0, 1]; NaN counts as 0) takes entry floor(255 v + 0.5) of
 * matplotlib's 256-entry magma table, as the reference tool does.  The table holds sRGB
 * values; the image holds them decoded to linear RGB, so that writing it as a PNG with
 * the clamp tone map at exposure 0 gives the reference's bytes.
 * Fails with LUMIS_ERR_INVALID_ARGUMENT for a NULL map or output, or from
 * lumis_image_create for bad sizes; *out is NULL on failure. */
LUMIS_API lumis_status lumis_flip_colormap(const float *error_map, int width, int height,
                                           lumis_image **out);

/* ==== end of FLIP ====================================================================== */

/* ---- errors on linear values and CIELAB ---------------------------------------------- */

typedef struct lumis_metric_options {
    /* Display-referred metrics (CIELAB, LDR-FLIP): values are multiplied by 2^exposure_ev
     * and clamped to [0, 1] first.  0 == no scaling. */
    float exposure_ev;
    double relmse_epsilon; /* relative MSE's eps; 0 == 0.01 */
    lumis_error_sink errors;
} lumis_metric_options;

/* On linear HDR values, over every pixel and channel (non-finite values count as 0):
 *   mse = mean (t - r)^2, rmse = sqrt(mse), relmse = mean (t - r)^2 / (r^2 + eps),
 *   psnr = 10 log10(peak^2 / mse) dB with peak = the reference's largest channel value
 *   (+inf for identical images). */
typedef struct lumis_image_error_stats {
    double mse, rmse, relmse, relmse_epsilon, psnr, psnr_peak;
} lumis_image_error_stats;

LUMIS_API lumis_status lumis_image_errors(const lumis_image *reference, const lumis_image *test,
                                          const lumis_metric_options *options,
                                          lumis_image_error_stats *out);

/* Mean CIE76 Delta E between the images as L*a*b* (D65 white = linear RGB (1,1,1)), after
 * 2^exposure_ev and a clamp to [0, 1] (linear Rec. 709 in, no sRGB curve: CIELAB has its
 * own lightness curve).  map: optional, width * height per-pixel Delta E. */
LUMIS_API lumis_status lumis_lab_delta_e(const lumis_image *reference, const lumis_image *test,
                                         const lumis_metric_options *options, float *map,
                                         double *mean);

#ifdef __cplusplus
}
#endif
#endif
