/* lumis/lights.h - representative light sets: an environment map as K directional lights.
 *
 * Each method partitions the map's pixels into K regions and puts one directional light at
 * the energy centroid of each.  A light's power is the sum over its region of radiance
 * times pixel solid angle (RGB, units of radiance x sr), so the powers of a set add up to
 * the map's integrated radiance sum(L * Omega): every method conserves the total exactly
 * (to double rounding).  A renderer lights a shading point x with normal n by
 *     sum over lights k of  f(x, w_o, dir_k) * max(0, n . dir_k) * V(x, dir_k) * power_k.
 * Definitions, formulas and every choice the papers leave open: docs/lights.md.
 *
 * Methods (one descriptor each, valid when zeroed; 0 == the paper's default):
 *   - median cut (Debevec 2005)                  lumis_lights_median_cut
 *   - variance minimisation (Viriyothai & Debevec 2009)   lumis_lights_variance_min
 *   - Wu's decomposition (Wu 2024, "Efficient Environment Map Rendering based on
 *     Decomposition"): EnvDirects on the emissive pixels, EnvIndirects from an
 *     illumination cut of the rest                 lumis_lights_decompose
 *
 * Interleaved sampling: a lumis_light_set holds `sets` light sets, the original (index 0)
 * and sets - 1 copies whose directions are jittered inside each light's directional
 * extent; a renderer gives neighbouring pixels different sets
 * (lumis_light_set_interleave_index).
 *
 * Randomness (the decomposition's importance sampling, the jitter) comes from PCG32
 * streams seeded from the descriptor's seed: results depend only on the inputs. */
#ifndef LUMIS_LIGHTS_H
#define LUMIS_LIGHTS_H

#include "lumis/envmap.h"
#include "lumis/export.h"
#include "lumis/sampler.h"
#include "lumis/status.h"
#include "lumis/types.h"

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What a light stands for. */
typedef enum lumis_light_kind {
    LUMIS_LIGHT_REGION = 0,       /* a region of a partition (median cut, variance min.) */
    LUMIS_LIGHT_ENV_DIRECT = 1,   /* Wu: a cluster of emissive pixels */
    LUMIS_LIGHT_ENV_INDIRECT = 2, /* Wu: a node of the cut over the non-emissive pixels */
} lumis_light_kind;

/* One directional light. */
typedef struct lumis_light {
    lumis_vec3 dir;     /* unit world direction towards the light: its region's energy centroid */
    float extent;       /* radians: half-angle of a cone about the original set's dir that
                           contains the whole region (the directional extent) */
    double power[3];    /* RGB sum over the region of L * Omega (radiance x steradian) */
    double solid_angle; /* steradians covered by the region */
    int pixels;         /* number of pixels in the region */
    lumis_light_kind kind;
} lumis_light;

typedef struct lumis_light_set lumis_light_set;

/* Which algorithm built a set. */
typedef enum lumis_lights_method {
    LUMIS_LIGHTS_MEDIAN_CUT = 1,
    LUMIS_LIGHTS_VARIANCE_MIN = 2,
    LUMIS_LIGHTS_DECOMPOSITION = 3,
    LUMIS_LIGHTS_FHIS = 4,
    LUMIS_LIGHTS_TMMS = 5,
} lumis_lights_method;

/* ---- median cut and variance minimisation ----------------------------------------- */

typedef struct lumis_median_cut_desc {
    int count;     /* K, the number of lights (1 .. pixels); 0 == 64 */
    int sets;      /* light sets for interleaving (1 .. 64); 0 == 8 */
    float jitter;  /* jitter of the extra sets, a fraction of each light's extent
                      (0 .. 1]; 0 == 0.1 */
    uint64_t seed; /* seed of the jitter */
    lumis_error_sink errors;
} lumis_median_cut_desc;

/* Median cut (Debevec 2005): recursively splits rectangles of the equirectangular map in
 * two of equal energy (luminance x solid angle), across the longer side measured in
 * radians on the sphere (the width weighted by the sine of the polar angle at the
 * rectangle's middle row), level by level; K that is not a power of two splits only the
 * most energetic regions of the last level.  Exact pixel-resolution marginals from band
 * sums of 16 rows / columns made in one pass (docs/lights.md).
 * Cost: O(pixels) for the pass, then O(pixels / 16) per level of splits, less where a
 * coarse level of 8 bands covers a region; about w h (4 + 4.1) bytes of temporary memory
 * (a float luminance array and the band sums).  Measured times: docs/benchmarks.md,
 * "Times the headers used to state". */
LUMIS_API lumis_status lumis_lights_median_cut(const lumis_envmap *env,
                                               const lumis_median_cut_desc *desc,
                                               lumis_light_set **out);

typedef lumis_median_cut_desc lumis_variance_min_desc;

/* Variance minimisation (Viriyothai & Debevec 2009): the same recursive scheme, but each
 * rectangle is cut at the position, along either axis, that minimises the summed
 * energy-weighted directional variance of the two halves (docs/lights.md); the last
 * partial level splits the regions of largest variance.  Marginals of energy and moment
 * along both axes from the same band sums as median cut.
 * Cost: O(pixels) for the pass, then O(pixels / 16) per level of splits; about
 * w h (4 + 5.1) bytes of temporary memory.  Measured times: docs/benchmarks.md. */
LUMIS_API lumis_status lumis_lights_variance_min(const lumis_envmap *env,
                                                 const lumis_variance_min_desc *desc,
                                                 lumis_light_set **out);

/* ---- Wu's decomposition ------------------------------------------------------------- */

/* Which parts of the EnvDirect construction run (Table 2 of the paper). */
typedef enum lumis_decomp_variant {
    LUMIS_DECOMP_DEFAULT = 0, /* == LUMIS_DECOMP_FULL */
    LUMIS_DECOMP_IS_ONLY,     /* importance sampling only (seeds drawn with replacement) */
    LUMIS_DECOMP_IS_MASK,     /* sampling with masking, no k-means */
    LUMIS_DECOMP_IS_KMEANS,   /* sampling without masking, then k-means */
    LUMIS_DECOMP_FULL,        /* sampling with masking, then k-means */
    LUMIS_DECOMP_VARIANT_COUNT
} lumis_decomp_variant;

/* How the cut over the non-emissive pixels chooses the node to refine. */
typedef enum lumis_cut_objective {
    LUMIS_CUT_DEFAULT = 0, /* == LUMIS_CUT_MODIFIED */
    LUMIS_CUT_MODIFIED,    /* Eq. 3: w_V V + w_D D + w_E E, each over its current maximum */
    LUMIS_CUT_ORIGINAL,    /* the original illumination cut: variance V only */
    LUMIS_CUT_COUNT
} lumis_cut_objective;

/* How "angular radius s * 4 pi / K" of the mask is read (docs/lights.md). */
typedef enum lumis_mask_radius {
    LUMIS_MASK_DEFAULT = 0,     /* == LUMIS_MASK_CAP_SOLID_ANGLE */
    LUMIS_MASK_CAP_SOLID_ANGLE, /* the cap whose solid angle is s * 4 pi / K */
    LUMIS_MASK_RADIANS,         /* an angular radius of s * 4 pi / K radians */
    LUMIS_MASK_COUNT
} lumis_mask_radius;

typedef struct lumis_decomp_desc {
    int count;                    /* K (1 .. pixels); 0 == 64 */
    int sets;                     /* light sets for interleaving (1 .. 64); 0 == 8 */
    float jitter;                 /* as in lumis_median_cut_desc; 0 == 0.1 */
    uint64_t seed;                /* seed of the importance sampling and the jitter */
    lumis_decomp_variant variant; /* 0 == full */

    /* Eq. 1: L_T = max(L_b, lambda L_avg, gamma L_max); pixels with Y > L_T are emissive. */
    float percentile; /* L_b's percentile of pixel luminance, (0, 100]; 0 == 98 */
    float lambda;     /* >= 0; 0 == 3 */
    float gamma;      /* >= 0; 0 == 0.001 */
    float threshold;  /* > 0: use this L_T instead of Eq. 1; 0 == Eq. 1 */

    /* Eq. 2: N = K G_em / (G_em + G_nem), G = L^a dw^b (L mean luminance, dw solid angle). */
    float budget_a; /* > 0; 0 == 1 */
    float budget_b; /* > 0; 0 == 0.25 */
    /* Eq. 2 can starve a class: on an interior map it leaves a few EnvIndirects for all the
     * room.  min_share in (0, 1] makes each class (emissive, non-emissive) get at least
     * ceil(min_share K P_class / P) of the K lights, P_class its share of the power
     * sum(Y Omega); 1 splits K in proportion to power (when rounding up makes the two
     * floors exceed K, the non-emissive class's wins).  0 == Eq. 2 alone (the paper). */
    float min_share;

    /* EnvDirects. */
    float mask_scale;              /* s of the mask radius s * 4 pi / K; 0 == 0.15 */
    lumis_mask_radius mask_radius; /* 0 == the cap of solid angle s * 4 pi / K */
    float return_factor;           /* pixels farther than this times the mask radius from
                                      their cluster's centre become non-emissive; 0 == 2 */
    int kmeans_max_iterations;     /* 0 == until no pixel changes cluster */

    /* EnvIndirects. */
    lumis_cut_objective cut; /* 0 == Eq. 3 */
    float w_v, w_d, w_e;     /* Eq. 3 weights, >= 0; 0 == 1, 5, 1 */

    lumis_error_sink errors; /* errors, and warnings (reported with status LUMIS_OK) */
} lumis_decomp_desc;

/* Wu's decomposition: classifies pixels by Eq. 1, splits K by Eq. 2, builds EnvDirects by
 * importance sampling the emissive pixels (a sum tree: O(log n) per draw and per masked
 * pixel), masking a cap after each draw and refining with spherical k-means, then covers
 * the non-emissive pixels with K - N EnvIndirects from a cut of a binary light tree.  A
 * map without emissive pixels gets K EnvIndirects; one with only emissive pixels K
 * EnvDirects (fewer only if K exceeds what the pixels can give; a warning says so).
 * Cost: three passes over the pixels (luminance and the exact percentile, classification,
 * the lights), O(pixels) each; a k-means step costs in proportion to the members of the
 * clusters a moved centre can reach, mostly bound checks (docs/lights.md).  Measured
 * times: docs/benchmarks.md. */
LUMIS_API lumis_status lumis_lights_decompose(const lumis_envmap *env,
                                              const lumis_decomp_desc *desc, lumis_light_set **out);

/* ---- Table 1's other baselines (FHIS as published, TMMS a variant: docs/lights.md) ----- */

typedef lumis_median_cut_desc lumis_fhis_desc;

/* FHIS (Ostromoukhov, Donohue & Jodoin 2004): K points of the paper's hierarchical Penrose
 * tiling, thresholded by their Fibonacci-numbered F-codes against the importance (the
 * energy Y Omega per pixel times a magnitude found by bisection, so that exactly K points
 * fall in distinct pixels) and moved by a correction-vector table, one light at each point,
 * whose region is the pixels nearer to it than to any other point (a Voronoi cell on the
 * sphere, so power is conserved).  Deterministic: the seed moves only the interleaved sets'
 * jitter.  Lights sit at the sample points, not at their cells' centroids.  docs/lights.md
 * says what follows the paper and what is ours. */
LUMIS_API lumis_status lumis_lights_fhis(const lumis_envmap *env, const lumis_fhis_desc *desc,
                                         lumis_light_set **out);

typedef struct lumis_tmms_desc {
    int count;             /* K (1 .. pixels); 0 == 64 */
    int sets;              /* light sets for interleaving (1 .. 64); 0 == 8 */
    float jitter;          /* as in lumis_median_cut_desc; 0 == 0.1 */
    uint64_t seed;         /* seed of the jitter */
    float key;             /* tone-mapping key a of Y a / Y_logavg, > 0; 0 == 0.18 */
    float range_bandwidth; /* mean-shift bandwidth on tone-mapped values in [0, 1), (0, 1];
                              0 == 0.1 */
    lumis_error_sink errors;
} lumis_tmms_desc;

/* TMMS-style strata (after Feng et al. 2016, "Tone-Mapped Mean-Shift Based Environment Map
 * Sampling"), a simplified variant: cells of the map are tone mapped (Reinhard's global
 * operator), their values clustered by mean shift into levels, connected cells of a level
 * form strata, and an adaptive split-and-merge on energy yields exactly K strata, one light
 * at the energy centroid of each.  Cost: O(pixels + cells x strata). */
LUMIS_API lumis_status lumis_lights_tmms(const lumis_envmap *env, const lumis_tmms_desc *desc,
                                         lumis_light_set **out);

/* ---- the light set ------------------------------------------------------------------ */

LUMIS_API void lumis_light_set_destroy(lumis_light_set *set);

/* Number of light sets held: 1 + the jittered copies. */
LUMIS_API int lumis_light_set_sets(const lumis_light_set *set);

/* The lights of set `index` (0 == the original) and their number; the array lives as long
 * as the set.  Every set has the same lights in the same order and with the same power and
 * region; only directions differ. */
LUMIS_API lumis_status lumis_light_set_get(const lumis_light_set *set, int index,
                                           const lumis_light **lights, int *count);

/* Region of every pixel: width * height light indices (row-major, row 0 the zenith),
 * -1 for a pixel of no light (none of the methods leaves one). */
LUMIS_API const int32_t *lumis_light_set_labels(const lumis_light_set *set, int *width,
                                                int *height);

/* The set for image pixel (x, y) when `sets` sets are interleaved: an a x b tile with
 * a * b == sets (b the largest divisor <= sqrt(sets)), repeated over the image. */
LUMIS_API int lumis_light_set_interleave_index(int sets, int x, int y);

/* What a build did, for reports and tests. */
typedef struct lumis_light_set_info {
    lumis_lights_method method;
    int requested;   /* K */
    int count;       /* lights per set */
    int direct;      /* EnvDirects (decomposition) */
    int indirect;    /* EnvIndirects (decomposition) */
    double build_ms; /* wall-clock time of the build */
    double power[3]; /* the lights' total power per channel (set 0) */

    /* Decomposition only. */
    double threshold;               /* L_T of Eq. 1 (or the descriptor's) */
    double percentile_luminance;    /* L_b */
    double avg_luminance;           /* L_avg = sum(Y Omega) / 4 pi */
    double max_luminance;           /* L_max */
    int emissive_pixels;            /* Y > L_T */
    int returned_pixels;            /* emissive pixels given back to the non-emissive set */
    double gamma_em, gamma_nem;     /* Eq. 2 */
    int budget;                     /* N of Eq. 2 after clamping */
    double mask_radius;             /* radians */
    int seeds;                      /* seeds drawn */
    int kmeans_iterations;          /* assignment steps */
    int kmeans_converged;           /* nonzero if the last assignment changed no pixel */
    const double *kmeans_objective; /* objective after the seeds' assignment, then after each
                                       update and each assignment step */
    int kmeans_objective_count;
} lumis_light_set_info;

/* The build's report (valid while the set lives). */
LUMIS_API const lumis_light_set_info *lumis_light_set_get_info(const lumis_light_set *set);

/* The irradiance (in luminance) that set 0's lights give a diffuse surface of normal
 * `normal`, sum_k Y(power_k) max(0, n . dir_k), in *set_e, and the map's own, the
 * integral of Y(w) max(0, n . w) over the sphere, in *map_e (exact for every pixel wholly
 * on one side of the surface's horizon: each pixel's first moment dotted with n).  How far
 * a set's point lights are from the map's diffuse lighting, per direction (lumis lights
 * --irradiance).  Cost: O(pixels). */
LUMIS_API lumis_status lumis_light_set_irradiance(const lumis_envmap *env,
                                                  const lumis_light_set *set, lumis_vec3 normal,
                                                  double *set_e, double *map_e);

/* What lumis_light_set_fold_below did. */
typedef struct lumis_light_fold {
    int folded;      /* lights that were at or below the plane, now gone */
    int kept;        /* lights left per set (the set's count now) */
    double power[3]; /* RGB power the folded lights carried, now in the lights above */
    double share;    /* that power's share of the set's, in luminance (0 .. 1) */
} lumis_light_fold;

/* Keeps a set's lights above a ground plane, conserving its power: every light whose
 * direction is at or below the plane through the origin of normal `up` (up . dir <= 0) is
 * removed and its power, solid angle, pixels and region (labels) go to the nearest light
 * above it (largest dir . dir'; the first of equals), whose direction stays and whose extent
 * grows to cover the folded region.  The total power is unchanged (to double rounding); every
 * interleaved set loses the same lights, in the same order.  For an engine with a ground,
 * which would block the light the map shows from below.  LUMIS_ERR_INVALID_ARGUMENT when
 * no light is above the plane or up is zero or not finite (the set is then unchanged).
 * report (may be NULL) says how many lights and how much power moved.  Cost: O(K^2 + K sets
 * + pixels). */
LUMIS_API lumis_status lumis_light_set_fold_below(lumis_light_set *set, lumis_vec3 up,
                                                  const lumis_error_sink *errors,
                                                  lumis_light_fold *report);

/* ---- region samplers: the stratified mode ----------------------------------------------
 * A light set's regions partition the sphere, so they can serve as strata instead of point
 * lights: draw one direction in every region, in proportion to luminance x solid angle
 * inside it, and weight it by radiance over its pdf.  The sum over the regions is an
 * unbiased estimate of the direct illumination (the point lights' is not: each region's
 * light is moved to its centroid), whose error falls as 1 / samples.  This is stratified
 * sampling of the environment map with the light-set method choosing the strata
 * (docs/lights.md, "Stratified mode"); the renderer's stratified light sets use it
 * (lumis_render_desc.lighting.light_set.mode). */

typedef struct lumis_region_sampler lumis_region_sampler;

/* One sampler per region (light) of set 0 of `set`, which must have been made from a map of
 * env's size (env itself is retained).  Pixels of zero luminance are never drawn; a pixel
 * that shines but belongs to no region is refused (LUMIS_ERR_INVALID_ARGUMENT: the strata
 * must cover the map).  Cost: two passes over the pixels and one CDF and guide build per
 * region, O(pixels); 8 bytes per pixel, 20 per pixel of nonzero luminance and 40 per row of
 * a region. */
LUMIS_API lumis_status lumis_region_sampler_create(const lumis_envmap *env,
                                                   const lumis_light_set *set,
                                                   const lumis_error_sink *errors,
                                                   lumis_region_sampler **out);
LUMIS_API void lumis_region_sampler_destroy(lumis_region_sampler *rs);

/* Regions (== the set's lights per set). */
LUMIS_API int lumis_region_sampler_count(const lumis_region_sampler *rs);
/* What region's light stands for (Wu: EnvDirect or EnvIndirect). */
LUMIS_API lumis_light_kind lumis_region_sampler_kind(const lumis_region_sampler *rs, int region);
/* Sum over the region of L Omega, RGB (the light's power, in double); 0 out of range. */
LUMIS_API void lumis_region_sampler_power(const lumis_region_sampler *rs, int region,
                                          double power[3]);
/* Nonzero when the region holds no pixel of nonzero luminance (nothing to draw). */
LUMIS_API int lumis_region_sampler_empty(const lumis_region_sampler *rs, int region);

/* A direction in region `region` from two uniform numbers in [0, 1): a pixel of the region
 * with probability Y Omega / (its sum over the region), then uniform in solid angle inside
 * it, by inversion: u1 picks the region's row (marginal CDF), u2 the pixel in the row
 * (conditional CDF), and where each fell inside its share places the direction inside the
 * pixel (u1 along cos theta, u2 along the azimuth), so the draw is monotone in each of u1
 * and u2 and a stratified set of points gives stratified directions.  pdf is per steradian
 * within the region; radiance is the map's there.  An empty region or an index out of
 * range gives pdf 0 (and a zero direction).  Cost: O(1) on average (guide tables): the
 * row's slot and row (small, cached), the entry's slot and entry, the radiance. */
LUMIS_API lumis_env_sample lumis_region_sampler_sample(const lumis_region_sampler *rs, int region,
                                                       double u1, double u2);
/* n draws, draw k in region regions[k] from u[2k], u[2k + 1]: the same results as n calls
 * of lumis_region_sampler_sample, with the lookups of up to 32 draws in flight at once (what
 * a renderer drawing in every region of a shading point calls). */
LUMIS_API void lumis_region_sampler_sample_n(const lumis_region_sampler *rs, const int *regions,
                                             const double *u, size_t n, lumis_env_sample *out);
/* Density per steradian of drawing dir with region `region`'s sampler: 0 outside it. */
LUMIS_API float lumis_region_sampler_pdf(const lumis_region_sampler *rs, int region,
                                         lumis_vec3 dir);
/* The region dir lies in (-1: none), its density there in that region's sampler and the
 * map's radiance there (either pointer may be NULL), from one pixel lookup: what the MIS
 * weight of a BSDF-sampled direction needs. */
LUMIS_API float lumis_region_sampler_lookup(const lumis_region_sampler *rs, lumis_vec3 dir,
                                            int *region, lumis_rgb *radiance);
/* Bytes the sampler owns; wall-clock milliseconds its build took. */
LUMIS_API size_t lumis_region_sampler_bytes(const lumis_region_sampler *rs);
LUMIS_API double lumis_region_sampler_build_ms(const lumis_region_sampler *rs);

/* ---- methods and parameters by name ------------------------------------------------------
 * What the lumis tool's --method / --lights and --param / --lights-param take, for a host
 * application that exposes the same choices: a method by name, and NAME=VALUE parameters
 * (docs/lights.md lists them).  Methods: "median-cut", "variance-min", "fhis", "tmms", "wu",
 * and Wu's ablations "wu-is", "wu-is-mask", "wu-is-kmeans", "wu-original-cut". */

/* The method names, NULL-terminated. */
LUMIS_API const char *const *lumis_lights_method_names(void);
/* The method a name builds (LUMIS_LIGHTS_DECOMPOSITION for every wu...) into *out;
 * LUMIS_ERR_INVALID_ARGUMENT (*out untouched) for an unknown or NULL name. */
LUMIS_API lumis_status lumis_lights_method_from_name(const char *name, lumis_lights_method *out);

/* Parameters by name.  Zero-initialised: every method's defaults. */
typedef struct lumis_light_params {
    lumis_decomp_desc wu; /* Wu: Eq. 1-3, masking, k-means (count, sets, variant, cut unused) */
    float jitter;         /* every method: the extra sets' jitter */
    uint64_t seed;        /* every method: the seed */
    float key, bandwidth; /* TMMS */
    unsigned given;       /* a bit per parameter given, in lumis_light_params_parse's order */
} lumis_light_params;

/* Adds the pairs of "NAME=VALUE[,NAME=VALUE...]" to p.  LUMIS_ERR_INVALID_ARGUMENT, with a
 * message naming the pair and the value's range, for an unknown name or a bad value (p then
 * holds the pairs before it). */
LUMIS_API lumis_status lumis_light_params_parse(lumis_light_params *p, const char *text,
                                                const lumis_error_sink *errors);
/* LUMIS_OK if every parameter given applies to the method `method` (a name), else
 * LUMIS_ERR_INVALID_ARGUMENT with a message naming the parameter and its method. */
LUMIS_API lumis_status lumis_light_params_check(const lumis_light_params *p, const char *method,
                                                const lumis_error_sink *errors);
/* The parameters given, as "name=value,..." (empty when none; each value the shortest that
 * reads back the same), into buf of cap bytes (truncated to fit). */
LUMIS_API void lumis_light_params_format(const lumis_light_params *p, char *buf, size_t cap);

/* K lights in `sets` interleaved sets by the method `method` (a name) with parameters
 * `params` (NULL: the defaults); 0 for K or sets: the method's default. */
LUMIS_API lumis_status lumis_lights_by_name(const lumis_envmap *env, const char *method, int count,
                                            int sets, const lumis_light_params *params,
                                            const lumis_error_sink *errors, lumis_light_set **out);

#ifdef __cplusplus
}
#endif
#endif
