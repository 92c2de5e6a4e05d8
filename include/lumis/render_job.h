/* lumis/render_job.h - a render: its description (camera, lighting, counts, seed), the one
 * lighting check, a render in one call, the luminaires' auto choices, and progressive jobs
 * (library lumis-render; lumis/render.h includes every part). */
#ifndef LUMIS_RENDER_JOB_H_PUBLIC
#define LUMIS_RENDER_JOB_H_PUBLIC

#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/render_lighting.h"
#include "lumis/render_scene.h"
#include "lumis/rng.h"
#include "lumis/status.h"

#ifdef __cplusplus
extern "C" {
#endif

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

/* The points a render draws: one pixel's camera samples in one dimension of the render's
 * sequence, the very numbers lumis_render takes there (docs/sampling.md has the layout:
 * dimension 0 is the camera's jitter, then each vertex's light kind and BSDF sample).
 * Zero-initialisable. */
typedef struct lumis_sequence_desc {
    lumis_sequence sequence; /* 0 == sobol (the render's default) */
    unsigned long long seed; /* the render's seed (lumis_render_desc.seed) */
    int planned_spp;         /* the render's spp as given (lumis_render_desc.spp): stratified
                                and zsobol plan their strata for it; 0 == 2^16, as a job */
    int width;               /* the image's width (pixels are numbered y width + x); 0 == 1 */
    int x, y;                /* the pixel */
    int dimension;           /* the dimension (0: the camera's jitter) */
    int per_sample;          /* the points each camera sample draws in the dimension (n light
                                samples ...); 0 == 1 */
    lumis_error_sink errors; /* optional: messages name the field */
} lumis_sequence_desc;

/* Fills out[2 i], out[2 i + 1] with point j of camera sample k = first_sample + i / n, j =
 * i % n (n = per_sample), for i < samples n: the 2D point the renderer draws there.  PCG32,
 * whose stream hands out numbers in the order asked for, gives the stream's pairs from pair
 * dimension n + j on (what the renderer draws there when each earlier dimension drew n
 * pairs).  A dimension the renderer reads one number of takes the first coordinate; the
 * stratified sequence strata such a number over n strata instead, so its first coordinate
 * differs there.  pmj02 makes its tables per call (about 23 ms); the others allocate
 * nothing.  LUMIS_ERR_INVALID_ARGUMENT for an unknown sequence, a negative field, a pixel
 * outside the width, out NULL with samples > 0 (each message names the field). */
LUMIS_RENDER_API lumis_status lumis_sequence_fill(const lumis_sequence_desc *desc, int first_sample,
                                                  int samples, double *out);

#ifdef __cplusplus
}
#endif
#endif
