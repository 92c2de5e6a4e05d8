/* The evaluation renderer: an Embree scene (meshes used more than once are instanced), a
 * pinhole camera, and direct illumination from the environment map with light, BSDF or
 * multiple importance sampling; optionally path tracing on top of it.
 * Determinism: sample k of pixel p takes its numbers from the render's sequence at (p, k)
 * (sequence.h; PCG32: stream p started at a hash of (seed, k)), so the image depends on the
 * seed and the sample count, never on how tiles are spread over threads or samples over
 * passes. */
#include "lumis/render.h"
#include "lumis/rng.h"

#include "../core/internal.h"
#include "internal.h"
#include "camera.h"
#include "sequence.h"
#include "shade.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <omp.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---- jobs: progressive accumulation ------------------------------------------------- */

enum { TILE = 16 };

struct lumis_render_job {
    const lumis_scene *scene;
    lumis_render_desc d;
    lumis_camera cam;
    cam_frame cf;
    double *sum; /* 3 per pixel: the sum of every sample so far, in sample order */
    const lumis__light_kind *kind;
    void *state; /* the kind's (its prepare) */
    lumis__seq seq;
    lumis_render_stats stats;
};

void lumis_render_job_destroy(lumis_render_job *job)
{
    if (!job) return;
    free(job->sum);
    lumis__seq_release(&job->seq);
    if (job->kind) job->kind->release(job->state);
    free(job);
}

lumis_status lumis_render_job_create(const lumis_scene *scene, const lumis_render_desc *d,
                                     lumis_render_job **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!scene || !d || d->spp < 0 || d->light_samples < 0 || d->bsdf_samples < 0 ||
        d->max_bounces < 0 || d->max_bounces > 1024 || d->first_sample < 0 ||
        d->first_sample >= (1 << 30))
        return lumis__fail(d ? &d->errors : NULL, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: needs a scene, non-negative sample counts (a first sample "
                           "below 2^30) and 0 to 1024 bounces");
    const lumis_status lst = lumis_lighting_check(d);
    if (lst != LUMIS_OK) return lst;
    const lumis__light_kind *kind = lumis__light_kind_of(d);
    cam_frame cf;
    lumis_status cst = lumis__camera_frame(d->camera, &d->errors, &cf);
    if (cst != LUMIS_OK) return cst;
    const lumis_camera cam = cf.cam;
    lumis_render_job *job = calloc(1, sizeof *job);
    if (job) job->sum = calloc(3 * (size_t)cam.width * (size_t)cam.height, sizeof(double));
    if (!job || !job->sum) {
        lumis_render_job_destroy(job);
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "render: %d x %d: out of memory",
                           cam.width, cam.height);
    }
    const lumis_status qst = lumis__seq_init(&job->seq, d->sequence, d->seed, d->spp, &d->errors);
    if (qst != LUMIS_OK) {
        lumis_render_job_destroy(job);
        return qst;
    }
    job->kind = kind;
    const lumis_status kst = kind->prepare(scene, d, &job->state);
    if (kst != LUMIS_OK) {
        lumis_render_job_destroy(job);
        return kst;
    }
    job->scene = scene;
    job->d = *d;
    job->d.camera = NULL; /* job->cam is the camera */
    job->cam = cam;
    job->cf = cf;
    *out = job;
    return LUMIS_OK;
}

lumis_status lumis_render_job_run(lumis_render_job *job, int samples)
{
    if (!job) return LUMIS_ERR_INVALID_ARGUMENT;
    if (samples < 1 || samples > (1 << 30) - job->d.first_sample - job->stats.spp)
        return lumis__fail(&job->d.errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "render: %d more samples per pixel is out of range", samples);
    const lumis_render_desc *d = &job->d;
    const lumis__light_kind *kind = job->kind;
    ctx c = {job->scene, d, job->state};
    const int threads = d->threads > 0 ? d->threads : omp_get_max_threads();
    const int w = job->cam.width, h = job->cam.height, first = job->d.first_sample + job->stats.spp;
    const int tx = (w + TILE - 1) / TILE, ty = (h + TILE - 1) / TILE, tiles = tx * ty;
    double shadow = 0.0, bounce = 0.0, lum_samples = 0.0, t0 = omp_get_wtime();
    int done = 0, failed = 0;
    /* A kind may render the camera samples in chunks, with work before each. */
    int chunk = samples;
    if (kind->run_begin) {
        const lumis_status rst = kind->run_begin(job->state, samples, &chunk);
        if (rst != LUMIS_OK) {
            if (kind->run_end) kind->run_end(job->state);
            return rst;
        }
    }
    const int chunks = (samples + chunk - 1) / chunk;
    lumis_status gst = LUMIS_OK;

#pragma omp parallel num_threads(threads) reduction(+ : shadow, bounce, lum_samples)
    {
        void *scratch = kind->thread_begin ? kind->thread_begin(job->state) : NULL;
        if (kind->thread_begin && !scratch) {
#pragma omp atomic write
            failed = 1;
        }
        for (int ci = 0; ci < chunks; ci++) {
            const int k0 = first + ci * chunk,
                      k1 = k0 + chunk < first + samples ? k0 + chunk : first + samples;
#pragma omp barrier
#pragma omp single
            if (kind->chunk_begin) {
                gst = kind->chunk_begin(job->state, d->seed, k0, k1);
                if (gst != LUMIS_OK) failed = 1;
            }
            int stop;
#pragma omp atomic read
            stop = failed;
#pragma omp for schedule(dynamic, 1)
            for (int tile = 0; tile < tiles; tile++) {
                if (stop) continue;
                const int x0 = tile % tx * TILE, y0 = tile / tx * TILE;
                const int x1 = x0 + TILE < w ? x0 + TILE : w, y1 = y0 + TILE < h ? y0 + TILE : h;
                for (int y = y0; y < y1; y++)
                    for (int x = x0; x < x1; x++) {
                        double *acc = job->sum + 3 * ((size_t)y * (size_t)w + (size_t)x);
                        v3 a = mk(acc[0], acc[1], acc[2]);
                        for (int k = k0; k < k1; k++) {
                            /* Sample k of this pixel has its own numbers: passes cannot
                             * change them. */
                            lumis__stream seq;
                            lumis__stream_start(&seq, &job->seq, x, y, w, k);
                            double j[2];
                            seq_2d(&seq, seq_take(&seq), 0, 1, j);
                            if (d->pixel_centers) j[0] = j[1] = 0.5;
                            double sx = (x + j[0]) / w * 2.0 - 1.0;
                            double sy = 1.0 - (y + j[1]) / h * 2.0; /* row 0 on top */
                            v3 dir = camera_dir(&job->cf, sx, sy);
                            const lumis__vertex v = {x, y, k, &seq, scratch, &shadow};
                            a = add(a, lumis__trace_sample(&c, job->kind, job->cf.eye, dir, &v,
                                                           &bounce));
                        }
                        acc[0] = a.x;
                        acc[1] = a.y;
                        acc[2] = a.z;
                    }
                int now;
#pragma omp atomic capture
                now = ++done;
                if (d->progress && omp_get_thread_num() == 0)
                    d->progress(d->progress_user, now, tiles * chunks);
            }
        }
        if (kind->thread_end) kind->thread_end(scratch, &lum_samples);
    }
    if (kind->run_end) kind->run_end(job->state);
    if (gst != LUMIS_OK) return gst; /* the kind said why */
    if (failed)
        return lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "render: %s buffers: out of memory",
                           kind->name);
    if (d->progress) d->progress(d->progress_user, tiles * chunks, tiles * chunks);
    job->stats.spp += samples;
    job->stats.passes++;
    job->stats.threads = threads;
    job->stats.seconds += omp_get_wtime() - t0;
    job->stats.camera_rays += (double)w * h * samples;
    job->stats.shadow_rays += shadow;
    job->stats.light_samples += lum_samples;
    job->stats.bounce_rays += bounce;
    return LUMIS_OK;
}

lumis_status lumis_render_job_image(const lumis_render_job *job, lumis_image **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!job) return LUMIS_ERR_INVALID_ARGUMENT;
    lumis_status st = lumis_image_create(job->cam.width, job->cam.height, out);
    if (st != LUMIS_OK)
        return lumis__fail(&job->d.errors, st, "render: %d x %d: %s", job->cam.width,
                           job->cam.height, lumis_status_string(st));
    const size_t n = 3 * (size_t)job->cam.width * (size_t)job->cam.height;
    const double inv = job->stats.spp > 0 ? 1.0 / job->stats.spp : 0.0;
    for (size_t k = 0; k < n; k++) (*out)->pixels[k] = (float)(job->sum[k] * inv);
    return LUMIS_OK;
}

void lumis_render_job_stats(const lumis_render_job *job, lumis_render_stats *stats)
{
    if (job && stats) *stats = job->stats;
}

lumis_status lumis_render(const lumis_scene *scene, const lumis_render_desc *d, lumis_image **out,
                          lumis_render_stats *stats)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    lumis_render_job *job = NULL;
    lumis_status st = lumis_render_job_create(scene, d, &job);
    if (st == LUMIS_OK) st = lumis_render_job_run(job, d->spp ? d->spp : 16);
    if (st == LUMIS_OK) st = lumis_render_job_image(job, out);
    if (st == LUMIS_OK && stats) lumis_render_job_stats(job, stats);
    lumis_render_job_destroy(job);
    return st;
}
