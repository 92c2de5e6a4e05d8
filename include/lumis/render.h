/* lumis/render.h - the evaluation renderer (library lumis-render): a scene of spheres,
 * planes and (instanced) triangle meshes with BSDFs, traced with Embree, lit by an
 * environment map through any lumis_sampler, with light, BSDF or multiple importance
 * sampling.
 *
 * It exists to measure samplers: direct illumination from the environment (or, clearly
 * labelled, path-traced global illumination for references), exact estimators, and images
 * that depend on the seed and the sample count but never on the thread count or on how the
 * samples were split into passes. */
#ifndef LUMIS_RENDER_H
#define LUMIS_RENDER_H

#include "lumis/bsdf.h"
#include "lumis/envmap.h"
#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/io.h"
#include "lumis/lights.h"
#include "lumis/luminaire.h"
#include "lumis/photometry.h"
#include "lumis/rng.h"
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
    /* mesh: object to world, a row-major 3x4 matrix [R | t]; all zeros == identity.
     * Mesh objects that share the same vertex and index arrays are built once and
     * instanced, each with its own transform and material. */
    float transform[12];
    lumis_bsdf material;
} lumis_object;

typedef struct lumis_scene lumis_scene;

/* Builds the Embree scene (objects copied; mesh arrays need not outlive the call).
 * errors: an optional sink. */
LUMIS_RENDER_API lumis_status lumis_scene_create(const lumis_object *objects, int count,
                                                 const lumis_error_sink *errors, lumis_scene **out);
LUMIS_RENDER_API void lumis_scene_destroy(lumis_scene *scene);

typedef enum lumis_estimator {
    LUMIS_ESTIMATOR_MIS = 0, /* light and BSDF samples combined (default) */
    LUMIS_ESTIMATOR_LIGHT,   /* light samples only */
    LUMIS_ESTIMATOR_BSDF     /* BSDF samples only */
} lumis_estimator;

/* How a light set lights a shading point (docs/lights.md, "Stratified mode"). */
typedef enum lumis_lights_mode {
    LUMIS_LIGHTS_POINT = 0,      /* each region as a point light at its centroid: every light
                                    of the pixel's interleaved set, deterministic, biased (the
                                    preview, and what the export writes) */
    LUMIS_LIGHTS_STRATIFIED = 1, /* each region as a stratum of the map: one direction drawn
                                    in every region per camera sample and vertex, weighted by
                                    radiance over pdf, combined with BSDF sampling by MIS:
                                    unbiased, error falling as 1 / samples */
    LUMIS_LIGHTS_MODE_COUNT
} lumis_lights_mode;

/* "point", "stratified". */
LUMIS_RENDER_API const char *lumis_lights_mode_name(lumis_lights_mode mode);
LUMIS_RENDER_API lumis_status lumis_lights_mode_from_name(const char *name, lumis_lights_mode *out);

/* ---- light-field luminaires in a scene (Lu et al.; lumis/luminaire.h) -------------------- */

/* A luminaire placed in a scene: world = R (scale local) + t.  Radiance is unchanged by the
 * scale (it only converts lengths: 0.001 puts a luminaire measured in millimetres into a scene
 * in metres), so irradiance is too. */
typedef struct lumis_luminaire_instance {
    const lumis_luminaire *luminaire;
    lumis_rigid placement; /* R a proper rotation (lumis_rigid_check); all zeros == identity */
    double scale;          /* world units per luminaire unit, > 0; 0 == 1 */
    float intensity;       /* radiance multiplier, >= 0; 0 == 1 */
} lumis_luminaire_instance;

/* How a luminaire sample's visibility is decided. */
typedef enum lumis_visibility {
    LUMIS_VISIBILITY_EXACT = 0,  /* one shadow ray per light sample, to its point on U */
    LUMIS_VISIBILITY_APPROX,     /* Lu et al. 6.2: per cell of the basis grid on U one ray to
                                    the cell's centre; a sample of image m is weighted by the
                                    mean visibility v_m(p) over the cells of Phi_m's support
                                    (rays here where the paper uses shadow maps) */
    LUMIS_VISIBILITY_NONE,       /* no shadows (the paper's irradiance, Eq. 2) */
    LUMIS_VISIBILITY_SHADOW_MAP, /* approx, with the visibility of each cell's centre read
                                   from a depth map rendered from it when the render starts
                                   (as the paper): no ray per shading point */
    LUMIS_VISIBILITY_COUNT
} lumis_visibility;

/* Where a render's numbers come from: lumis_sequence (lumis/rng.h, docs/sampling.md). */

/* "exact", "approx", "none", "shadowmap". */
LUMIS_RENDER_API const char *lumis_visibility_name(lumis_visibility visibility);
LUMIS_RENDER_API lumis_status lumis_visibility_from_name(const char *name, lumis_visibility *out);

/* Luminaires as the renderer's lights: every camera sample's hit is lit by each instance with
 * lumis_luminaire_sample_point (budget samples shared among its images) and the material's
 * BSDF.  The instances and their luminaires must outlive the render. */
typedef struct lumis_luminaire_lighting {
    const lumis_luminaire_instance *instances;
    int count;
    int budget;                        /* K per instance per camera sample; 0 == 32 */
    int k_max;                         /* most samples for one image; 0 == no cap */
    lumis_luminaire_strategy strategy; /* 0 == restricted (Lu et al.); LUMIS_LUM_AUTO:
                                          per instance, lumis_render_luminaire_choices */
    lumis_luminaire_search search;     /* 0 == the library's default */
    int depth;                         /* search depth; 0 == exact */
    lumis_visibility visibility;       /* 0 == exact */
    int auto_bands; /* with LUMIS_LUM_AUTO, nonzero: a band of distance may take its own
                       strategy (lumis_render_luminaire_choices); off by default, since a
                       band's choice also applies to what no probe saw in it */
    const lumis_luminaire_costs *auto_costs; /* with LUMIS_LUM_AUTO: the cost model (NULL ==
                                                lumis_luminaire_costs_default()) */
    /* NULL, or count entries: with LUMIS_LUM_AUTO the render writes there, as it prepares,
     * how it samples each luminaire (what lumis_render_luminaire_choices returns: the
     * caller need not predict again to report it). */
    struct lumis_luminaire_choice *chosen;
} lumis_luminaire_lighting;

/* ---- photometric fixtures in a scene (IES, EULUMDAT; lumis/photometry.h) --------------- */

/* A fixture's far-field table placed in a scene: world = R local + t, its aim (local -z)
 * R (0, 0, -1).  As a point at t; or, with `area`, as the file's luminous opening centred at
 * t: a flat disk or rectangle facing the aim (radiance I(d) / (A cos) towards d, zero
 * behind it), or a solid box, vertical cylinder or sphere (every surface point emits
 * I(d) / A_proj(d), A_proj the area the solid shows towards d), so that far away each is
 * the point; lumis_render refuses `area` for a point or an "other" shape.  White light:
 * the render's three channels are candela times the multiplier. */
typedef struct lumis_photometric_instance {
    const lumis_photometric *photometric;
    lumis_rigid placement; /* R a proper rotation; all zeros == identity */
    double multiplier;     /* >= 0; 0 == 1 */
    int area;              /* nonzero: the luminous opening, else a point */
} lumis_photometric_instance;

/* Photometric fixtures as the renderer's lights: at every vertex each is sampled
 * light_samples times (a point: its one direction; an opening: points on it by area, with
 * the BSDF's samples and MIS as lighting.estimator says), one shadow ray each.  The
 * instances and their models must outlive the render. */
typedef struct lumis_photometric_lighting {
    const lumis_photometric_instance *instances;
    int count;
} lumis_photometric_lighting;

/* A fixture's rotation (world = R local, row-major) for a file of photometric `type`: local
 * -z along `aim` (a direction), local +x (C0 for type C; the fixture's top for types A and
 * B: lumis/photometry.h) chosen as follows, then turned `roll_deg` about the aim (+x towards
 * +y: counter-clockwise seen from behind the fixture).  With a = aim / |aim|:
 *  - `up` given: +x = up made perpendicular to the aim, (u - (u.a) a) / |...|.
 *  - type C: the hanging pose (aim -y, C0 +x, C90 -z) turned by the smallest rotation that
 *    takes -y to a (about (-a.z, 0, a.x)): C0 = (1 - a.x^2 / (1 - a.y), a.x,
 *    -a.x a.z / (1 - a.y)).  Continuous in the aim except at straight up (+y), where the
 *    frame is the half turn about x: C0 +x, C90 +z.
 *  - types A, B: a yoke.  The lateral axis (local +y) is horizontal, (a.z, 0, -a.x) / h with
 *    h = sqrt(a.x^2 + a.z^2), and +x (up) points above the aim, so a horizontal beam stays
 *    horizontal however the fixture is panned and tilted.  Continuous except at straight
 *    up and down (h < 1e-9): there +x is world +x.
 * Turning the aim and `up` about any axis turns R with them; without `up` so does any turn
 * of a floodlight (A, B) about y, while a type C fixture keeps its C0 as it tilts
 * (docs/photometric.md, "Aiming a fixture", has the figure).  LUMIS_ERR_INVALID_ARGUMENT
 * (R unchanged) for an unknown type, a zero or non-finite aim or roll, or an `up` that is
 * zero, not finite or within 1e-6 (sine) of the aim's line. */
LUMIS_RENDER_API lumis_status lumis_photometric_orient(lumis_photometric_type type, lumis_vec3 aim,
                                                       const lumis_vec3 *up, double roll_deg,
                                                       double R[9]);

/* ---- how a render is lit: one value ------------------------------------------------------
 *
 * A render is lit by exactly one kind of light.  Each kind needs some fields of
 * lumis_lighting and takes some of the render's (lumis_render_desc); every other lighting
 * field must be left at zero, and lumis_lighting_check refuses a field that a kind does not
 * use, naming it ("lighting.sampler", "max_bounces"...).  Zero is the environment map
 * sampled with MIS.
 *
 *   kind          needs                          also takes
 *   env           env; sampler (unless the       estimator, hide_environment, power_heuristic,
 *                 estimator is BSDF)             light_samples, bsdf_samples, max_bounces
 *   light-set     env; light_set.set             light_set.kinds, hide_environment; in
 *                                                stratified mode light_set.regions, estimator
 *                                                (light or MIS), power_heuristic, max_bounces
 *   luminaires    luminaires (count >= 1)        -- (camera rays that escape see black)
 *   photometric   photometric (count >= 1)       estimator, power_heuristic, light_samples,
 *                                                bsdf_samples, max_bounces (escaping: black)
 */
typedef enum lumis_lighting_kind {
    LUMIS_LIGHTING_ENV = 0,     /* the environment map, sampled per pixel through `sampler`
                                   with `estimator` (light, BSDF or MIS sampling) */
    LUMIS_LIGHTING_LIGHT_SET,   /* a light set (lumis/lights.h), as light_set.mode says */
    LUMIS_LIGHTING_LUMINAIRES,  /* light-field luminaires (lumis_luminaire_lighting) */
    LUMIS_LIGHTING_PHOTOMETRIC, /* photometric fixtures (lumis_photometric_lighting) */
    LUMIS_LIGHTING_KIND_COUNT
} lumis_lighting_kind;

/* "env", "light-set", "luminaires", "photometric". */
LUMIS_RENDER_API const char *lumis_lighting_kind_name(lumis_lighting_kind kind);
LUMIS_RENDER_API lumis_status lumis_lighting_kind_from_name(const char *name,
                                                            lumis_lighting_kind *out);

/* A light set as the renderer's lights (kind light-set).  The set (and regions) must outlive
 * the render. */
typedef struct lumis_light_set_lighting {
    /* Point mode: every light of the pixel's interleaved set (lumis_light_set_interleave_
     * index), one shadow ray each, traced 16 at a time; deterministic apart from the
     * camera's jitter; direct illumination only.  Stratified mode: the set's regions are
     * strata instead, one direction in each (the regions of `kinds`) per vertex, combined
     * with the BSDF's by `estimator` (MIS by default: each region's pdf against the
     * BSDF's), path tracing allowed; interleaving does not apply. */
    const lumis_light_set *set;          /* required */
    unsigned kinds;                      /* lights of the set used: 0 == all, else a mask of bits
                                            1u << lumis_light_kind (e.g. EnvDirects only) */
    lumis_lights_mode mode;              /* 0 == point */
    const lumis_region_sampler *regions; /* stratified: made from this set and env; NULL ==
                                            the render makes them */
} lumis_light_set_lighting;

/* How a render is lit (the table above says which fields each kind uses; zero-init: the
 * environment map, sampled with MIS). */
typedef struct lumis_lighting {
    lumis_lighting_kind kind;           /* 0 == env */
    const lumis_envmap *env;            /* env, light-set: the light, also seen by camera rays that
                                           escape; required by them, refused by the others */
    const lumis_sampler *sampler;       /* env: the map's light sampler; NULL for the BSDF
                                           estimator */
    lumis_estimator estimator;          /* 0 == MIS (env, stratified light sets, fixtures) */
    int hide_environment;               /* env, light-set: nonzero: camera rays that escape see
                                           black (a layer added to another which shows the map) */
    lumis_light_set_lighting light_set; /* light-set */
    const lumis_luminaire_lighting *luminaires;    /* luminaires: NULL for another kind */
    const lumis_photometric_lighting *photometric; /* photometric: NULL for another kind */
} lumis_lighting;

typedef struct lumis_render_desc {
    const lumis_camera *camera;
    lumis_lighting lighting; /* how the scene is lit; zero: the map, sampled with MIS */
    int pixel_centers;       /* nonzero: every camera ray through its pixel's centre (a layer
                                upsampled with a G-buffer, which samples the centres) */
    int power_heuristic;     /* nonzero: power heuristic (beta = 2), else balance */
    int spp;                 /* camera samples per pixel; 0 == 16 (a job plans its
                                sequence's strata for it; 0: 2^16) */
    int light_samples;       /* light samples per camera sample; 0 == 1 */
    int bsdf_samples;        /* BSDF samples per camera sample; 0 == 1 */
    unsigned long long seed; /* the image depends on it, never on threads */
    lumis_sequence sequence; /* where the numbers come from; 0 == sobol */
    /* The index of the first camera sample a job draws (0: the first).  A share of a render
     * split by passes over several machines (lumis render --passes I/N) numbers its samples
     * as the whole render does, so sample k is the same whichever machine draws it; spp
     * stays the whole render's count (the sequence is planned for it). */
    int first_sample;
    int threads; /* 0 == all cores */
    /* 0: direct illumination from the environment (the evaluation mode).  N > 0: path
     * tracing with up to N indirect bounces; every vertex gets the direct estimator above
     * and the path continues by BSDF sampling (global illumination, for references). */
    int max_bounces;
    /* Optional progress report: called with tiles done and total of the current pass,
     * from one rendering thread at a time (never concurrently). */
    void (*progress)(void *user, int done, int total);
    void *progress_user;
    /* Optional: every shadow ray the integrator traces (origin, unit direction, unbounded)
     * is also handed to it before it is traced, from the rendering threads concurrently
     * (render with threads = 1 to record them in order).  For benchmarks and debugging. */
    void (*shadow_ray)(void *user, const float org[3], const float dir[3]);
    void *shadow_ray_user;
    lumis_error_sink errors;
} lumis_render_desc;

typedef struct lumis_render_stats {
    int spp;              /* camera samples per pixel so far */
    int passes;           /* lumis_render_job_run calls so far */
    int threads;          /* worker threads of the last pass */
    double seconds;       /* wall time spent rendering (all passes) */
    double camera_rays;   /* primary rays */
    double shadow_rays;   /* occlusion rays of the direct estimators */
    double bounce_rays;   /* continuation rays of path tracing */
    double light_samples; /* luminaire samples evaluated, summed over shading points (the
                             global strategy's shared draws count at every point): what
                             an equal-samples comparison counts; 0 for other lights */
} lumis_render_stats;

/* Whether desc->lighting is one valid choice with the rest of desc: the kind known, what
 * it needs given (an environment map, a sampler, a light set, luminaires, fixtures), and
 * no field it does not use set (lighting.sampler for a light set, max_bounces for
 * luminaires...).  LUMIS_ERR_INVALID_ARGUMENT with one message through desc->errors naming
 * the field, else LUMIS_OK.  Reads the fields only (a luminaire or fixture lighting's count
 * too); lumis_render_job_create calls it, a host may call it first to refuse early. */
LUMIS_RENDER_API lumis_status lumis_lighting_check(const lumis_render_desc *desc);

/* Renders desc->spp samples per pixel into a new image (linear radiance).  stats may be
 * NULL.  The same as a job run once with desc->spp samples. */
LUMIS_RENDER_API lumis_status lumis_render(const lumis_scene *scene, const lumis_render_desc *desc,
                                           lumis_image **out, lumis_render_stats *stats);

/* How one placed luminaire is sampled: by distance from its origin (in its own units),
 * band b from edge[b - 1] to edge[b] with strategy[b] at budget[b] per camera sample. */
typedef struct lumis_luminaire_choice {
    int bands; /* 1 to LUMIS_LUM_MAX_BANDS */
    double edge[LUMIS_LUM_MAX_BANDS - 1];
    lumis_luminaire_strategy strategy[LUMIS_LUM_MAX_BANDS];
    int budget[LUMIS_LUM_MAX_BANDS];
    double band_gain; /* predicted: the best single strategy's work over the best banded
                         assignment's (>= 1; what bands would gain, taken or not) */
    lumis_luminaire_prediction prediction; /* over every probe, in bands (zeros unless auto) */
} lumis_luminaire_choice;

/* How each placed luminaire of d->lighting.luminaires is sampled (out: count entries): the
 * lighting's strategy and budget, one band; or with LUMIS_LUM_AUTO, from
 * lumis_luminaire_predict at the points the render will shade (the first hits of 96 x 60
 * camera rays through pixel centres, in the instance's frame, of which 240 are selected by
 * their brightness), at the lighting's budget and cap, 16 pilot samples per image,
 * stratified as the render's sequence and spp stratify, in up to 4 bands of distance
 * (equal counts of the probes, at least 288 each).  Every
 * assignment of strategies to bands is scored by (mean variance) x (mean ns) per camera
 * sample; one strategy for all unless ll->auto_bands is set and bands predict 10 % less
 * work (band_gain is then their predicted gain even when not taken).  A luminaire (or band)
 * auto samples globally gets at least 20 camera rays' worth of draws per camera sample
 * (its best: the model counts no camera ray per global sample), e.g. 1024 on the presets.
 * What the render does itself; deterministic.  Cost with auto: lumis_luminaire_predict's
 * per luminaire (O(probes x images with energy); measured: docs/benchmarks.md), counted
 * before the first sample. */
LUMIS_RENDER_API lumis_status lumis_render_luminaire_choices(const lumis_scene *scene,
                                                             const lumis_render_desc *d,
                                                             lumis_luminaire_choice *out);

/* Progressive rendering: a job accumulates passes; lumis_render_job_run(job, n) adds n
 * samples per pixel.  Sample k of a pixel is the same whichever pass draws it, so 16
 * passes of 1 sample give the image of one pass of 16, bit for bit.  The scene and the
 * camera, envmap and sampler of desc must outlive the job (desc itself is copied;
 * desc->spp is ignored). */
typedef struct lumis_render_job lumis_render_job;
LUMIS_RENDER_API lumis_status lumis_render_job_create(const lumis_scene *scene,
                                                      const lumis_render_desc *desc,
                                                      lumis_render_job **out);
LUMIS_RENDER_API lumis_status lumis_render_job_run(lumis_render_job *job, int samples);
/* The mean so far, as a new image (black before the first pass). */
LUMIS_RENDER_API lumis_status lumis_render_job_image(const lumis_render_job *job,
                                                     lumis_image **out);
LUMIS_RENDER_API void lumis_render_job_stats(const lumis_render_job *job,
                                             lumis_render_stats *stats);
LUMIS_RENDER_API void lumis_render_job_destroy(lumis_render_job *job);

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

/* ---- a render session: what a host calls to render for a time budget ---------------------
 * One call does what the lumis tool's render does between loading and writing: with a
 * light-set method it makes the light set (Wu's split rendering with its EnvIndirects at
 * 1/F resolution, joint-bilateral upsampled, included), and with a time budget it spends
 * the budget as wall time: the light set's generation, and the pilot renders that fit K
 * when none is given, count inside it; otherwise progressive passes fill it. */

typedef struct lumis_session_desc {
    /* camera, lighting, counts, seed, threads, progress ...: as lumis_render.  With
     * `lights`, render.lighting is of kind light-set with its set and regions NULL (the
     * session makes them; light_set.mode: point lights or strata of the map) */
    lumis_render_desc render;
    const char *lights;                      /* a light-set method by name, or NULL */
    int lights_k;                            /* K; 0: point mode fits it to time_budget,
                                                else 64; the stratified mode 32 */
    int interleave;                          /* interleaved sets; 0: the method's default */
    const lumis_light_params *lights_params; /* NULL: the method's defaults */
    int upsample;       /* Wu: EnvIndirects at 1/F resolution per axis; 0 == 2 (point mode)
                           or 1 (stratified: upsampling is a bias), 1 == none */
    double time_budget; /* > 0: seconds of wall time; 0: render.spp samples (0 == 16).
                           Stratified light sets fill it with passes at a fixed K. */
    double spent;       /* seconds of the budget already spent (a sampler's build) */
    int timed_spp;      /* with lights, time_budget and no K: samples per pixel; 0 == 4 */
    /* > 0: render only this many samples, a share of the render.spp of the whole render
     * starting at render.first_sample (no time budget); the shares' images weighted by
     * their counts average to the whole render's (the tool's `lumis merge`). */
    int share_spp;
    /* Optional: called after every pass with the samples per pixel so far. */
    void (*pass_done)(void *user, int spp);
    void *pass_done_user;
} lumis_session_desc;

/* Why a light set's K fitted to a time budget is what it is (lumis_session_result.k_limit). */
typedef enum lumis_k_limit {
    LUMIS_K_LIMIT_NONE = 0,    /* K given, or fitted at the planned samples per pixel */
    LUMIS_K_LIMIT_FEWER_SPP,   /* at timed_spp the budget affords fewer than k_floor lights:
                                  K fills it at spp_planned < timed_spp samples instead */
    LUMIS_K_LIMIT_BELOW_FLOOR, /* even at 1 sample per pixel (or render.spp, which is kept)
                                  the budget affords fewer than k_floor lights */
    LUMIS_K_LIMIT_OVER_BUDGET  /* K = 1 at the fewest samples is predicted to take longer
                                  than the budget: the render overruns it */
} lumis_k_limit;

/* The pilots that fit K: at most this many (the floor, 64, and where the fit lands). */
#define LUMIS_SESSION_PILOTS 3

typedef struct lumis_session_result {
    lumis_render_stats stats;   /* of the render that made the image (both layers) */
    double prep_seconds;        /* before the first sample: spent + generation + pilots */
    double budget_used_seconds; /* prep_seconds + every render (time_budget only) */
    int lights_k;               /* K of the light set used (0: none) */
    int upsample;               /* the factor used (1: none) */
    double lights_build_ms;     /* the light set's generation */
    size_t lights_bytes;        /* its lights and labels */
    /* With lights, time_budget and no K: the pilots that chose K.  They render at 1/pilot_
     * scale of the pixels and spend at most a fifth of the budget; their times are scaled
     * to the whole image (per sample per pixel of the full layer; once: the rest, and the
     * set's generation).  pilot_count: how many ran (0: none). */
    double pilot_seconds, pilot_per_spp[LUMIS_SESSION_PILOTS], pilot_once[LUMIS_SESSION_PILOTS];
    int pilot_k[LUMIS_SESSION_PILOTS], pilot_count, pilot_chosen;
    double pilot_scale;      /* the image's pixels over a pilot's */
    double pilot_predicted;  /* seconds the fit predicts for pilot_chosen at spp_planned */
    int k_floor;             /* the fewest lights K falls to before samples do (4) */
    int spp_planned;         /* samples per pixel K was fitted at */
    lumis_k_limit k_limit;   /* why K is what it is */
    int retried;             /* the pilots misjudged the time: rendered again with K scaled, once */
    double regions_build_ms; /* the stratified mode's region samplers (in prep_seconds) */
    size_t regions_bytes;
    lumis_light_set *light_set; /* the set that lit the image (NULL: none): the caller
                                   destroys it (lumis_light_set_destroy) */
    /* Contention: the session's wall time and the process's CPU time over it (every thread;
     * with a caller's threads running beside it, theirs too), and over the image's render
     * passes alone (every attempt).  cpu_share = render_cpu_seconds / (render_wall_seconds x
     * threads busy): near 1 when every render thread had a core to itself; well below it
     * (0.8, say), the threads waited for a CPU, and a time budget bought fewer samples or
     * lights than the same budget on an idle machine. */
    double wall_seconds, cpu_seconds;
    double render_wall_seconds, render_cpu_seconds, cpu_share;
    int threads_busy; /* render threads with work: min(threads, the full layer's tiles) */
} lumis_session_result;

/* Whether desc is a session lumis_render_session takes: a finite budget and non-negative
 * counts, the light-set options only with `lights` (a known method; upsample only Wu's),
 * `lights` only with render.lighting of kind light-set and no set or regions of the
 * caller's, and render as lumis_lighting_check says (the set the session makes counts as
 * given).  LUMIS_ERR_INVALID_ARGUMENT with one message naming the field, else LUMIS_OK:
 * a host may call it to refuse before it loads or builds anything else. */
LUMIS_RENDER_API lumis_status lumis_session_check(const lumis_session_desc *desc);

/* Renders scene under desc into *out (linear RGB); result (may be NULL) says how. */
LUMIS_RENDER_API lumis_status lumis_render_session(const lumis_scene *scene,
                                                   const lumis_session_desc *desc,
                                                   lumis_image **out, lumis_session_result *result);

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
 * "alpha" (or alpha_x/alpha_y)}, {"type": "plastic", "diffuse": ..., "alpha": a}.
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
