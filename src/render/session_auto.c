/* A session's automatic estimator (lumis_session_desc.auto_estimator): the map sampled with
 * MIS, or its median-cut regions as strata, chosen by pilot renders of the scene itself.
 *
 * Each candidate renders a small copy of the image (about a sixteenth of its pixels) twice,
 * independently; the two halves' difference estimates each pixel's variance without a
 * reference, (A - B)^2 / 2 for one half.  Over the pixels, relative to a common mean image
 * (every candidate's pilots together) as the relMSE weighs them:
 *
 *     v_c = mean_p n_c (A_p - B_p)^2 / 2 / (m_p^2 + eps)     (eps = 0.01, lumis_compare's)
 *
 * is candidate c's relMSE at one sample per pixel (n_c samples in each half).  Its cost,
 * t_c seconds a sample per pixel at the image's size, is the pilot's time scaled by the
 * pixels.  With a time budget the render has L seconds left after the pilots, so c would
 * reach relMSE v_c t_c / L (its light set is made already, and kept); without one, c
 * reaches relMSE e in v_c t_c / e seconds.  Either way the smallest v_c t_c wins: the
 * prediction is the estimators' efficiency, measured where it counts, on this scene, map,
 * camera and materials.  The halves of the MIS pilot take as long as the stratified ones
 * (equal time), so both variances are measured at the same cost. */
#include "lumis/render.h"

#include "../core/internal.h"
#include "internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#define AUTO_K        32   /* the stratified candidate's regions (docs/results/convergence) */
#define AUTO_PIXELS   4800 /* the pilots' pixels at least (80 x 60) */
#define AUTO_MAX_HALF 64   /* most samples per pixel in a pilot's half */

static const char *const candidate_names[LUMIS_AUTO_CANDIDATES] = {"mis", "stratified"};

const char *lumis_auto_candidate_name(int candidate)
{
    return candidate >= 0 && candidate < LUMIS_AUTO_CANDIDATES ? candidate_names[candidate]
                                                               : "unknown";
}

/* One pilot half: n more samples per pixel in job j; the image of those n alone (from the
 * job's running mean: after spp = a + n, half = (spp img - a prev) / n). */
static lumis_status half(lumis_render_job *j, int n, const lumis_image *prev, lumis_image **out)
{
    lumis_render_stats st;
    lumis_render_job_stats(j, &st);
    const int a = st.spp;
    lumis_status rs = lumis_render_job_run(j, n);
    if (rs == LUMIS_OK) rs = lumis_render_job_image(j, out);
    if (rs != LUMIS_OK || !prev) return rs;
    const size_t m = 3 * (size_t)(*out)->width * (size_t)(*out)->height;
    for (size_t k = 0; k < m; k++)
        (*out)->pixels[k] =
            (float)(((double)(a + n) * (*out)->pixels[k] - (double)a * prev->pixels[k]) / n);
    return LUMIS_OK;
}

static double lum(const float *p)
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

typedef struct pilot_pair {
    lumis_image *a, *b; /* the two halves */
    int n;              /* samples per pixel in each */
    double seconds;     /* what the two took */
} pilot_pair;

/* Candidate rd's two halves at n samples per pixel each, or (n == 0) as many as take about
 * `seconds` each (doubling from 1).  The job is made and dropped here. */
static lumis_status run_pair(const lumis_scene *scene, const lumis_render_desc *rd, int n,
                             double seconds, pilot_pair *p)
{
    lumis_render_job *j = NULL;
    memset(p, 0, sizeof *p);
    lumis_status st = lumis_render_job_create(scene, rd, &j);
    if (st != LUMIS_OK) return st;
    if (n <= 0) { /* time one sample, then fill the half's time */
        lumis_render_stats s0;
        st = lumis_render_job_run(j, 1);
        lumis_render_job_stats(j, &s0);
        const double per = s0.seconds > 1e-9 ? s0.seconds : 1e-9;
        n = (int)fmin(AUTO_MAX_HALF, fmax(1.0, floor(seconds / per + 0.5)));
        lumis_render_job_destroy(j); /* a fresh job: the halves start at sample 0 */
        j = NULL;
        if (st == LUMIS_OK) st = lumis_render_job_create(scene, rd, &j);
    }
    p->n = n;
    if (st == LUMIS_OK) st = half(j, n, NULL, &p->a);
    if (st == LUMIS_OK) st = half(j, n, p->a, &p->b);
    lumis_render_stats s;
    lumis_render_job_stats(j, &s);
    p->seconds = s.seconds;
    lumis_render_job_destroy(j);
    return st;
}

/* v_c of every candidate from its pair, against the mean of all pairs. */
static void variances(const pilot_pair *p, int count, double *v)
{
    const size_t px = (size_t)p[0].a->width * (size_t)p[0].a->height;
    for (int c = 0; c < count; c++) v[c] = 0.0;
    for (size_t k = 0; k < px; k++) {
        double m = 0.0;
        for (int c = 0; c < count; c++)
            m += lum(p[c].a->pixels + 3 * k) + lum(p[c].b->pixels + 3 * k);
        m /= 2.0 * count;
        for (int c = 0; c < count; c++) {
            const double d = lum(p[c].a->pixels + 3 * k) - lum(p[c].b->pixels + 3 * k);
            v[c] += p[c].n * d * d / 2.0 / (m * m + 1e-2);
        }
    }
    for (int c = 0; c < count; c++) v[c] /= (double)px;
}

lumis_status lumis__session_auto(const lumis_scene *scene, const lumis_session_desc *s,
                                 lumis_image **out, lumis_session_result *r, int keep_set)
{
    const double t0 = omp_get_wtime();
    const lumis_error_sink *errors = &s->render.errors;
    const lumis_render_desc *ud = &s->render;
    lumis_light_set *set = NULL;
    lumis_region_sampler *regions = NULL;
    pilot_pair pp[LUMIS_AUTO_CANDIDATES];
    memset(pp, 0, sizeof pp);
    /* the stratified candidate's set and strata: made once, kept if it is chosen */
    lumis_status st =
        lumis_lights_by_name(lumis__light_map(ud), "median-cut", AUTO_K, 0, NULL, errors, &set);
    /* (with a sun split off, both candidates light from the residual and add the sun) */
    if (st == LUMIS_OK)
        st = lumis_region_sampler_create(lumis__light_map(ud), set, errors, &regions);
    const double once = omp_get_wtime() - t0;
    /* the pilots' camera: a sixteenth of the pixels (at least AUTO_PIXELS) */
    lumis_camera cam = *ud->camera;
    const int cw = cam.width ? cam.width : 640, ch = cam.width ? cam.height : 480;
    const double px = (double)cw * ch, target = fmax(AUTO_PIXELS, px / 16.0);
    const int d = px > target ? (int)floor(sqrt(px / target)) : 1;
    cam.width = cw / d > 0 ? cw / d : 1;
    cam.height = ch / d > 0 ? ch / d : 1;
    const double scale = (double)cw * ch / ((double)cam.width * cam.height);
    lumis_render_desc rd[LUMIS_AUTO_CANDIDATES];
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
        rd[c] = *ud;
        rd[c].camera = &cam;
        rd[c].progress = NULL;
        rd[c].first_sample = 0;
        rd[c].seed = ud->seed ^ 0x5eedau; /* the pilots' numbers are not the render's */
        rd[c].spp = 2 * AUTO_MAX_HALF;
    }
    rd[1].lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    rd[1].lighting.sampler = NULL;
    rd[1].lighting.light_set.set = set;
    rd[1].lighting.light_set.regions = regions;
    rd[1].lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
    rd[1].light_samples = rd[1].bsdf_samples = 0;
    /* stratified at one sample per pixel a half; MIS for as long */
    if (st == LUMIS_OK) st = run_pair(scene, &rd[1], 1, 0.0, &pp[1]);
    if (st == LUMIS_OK)
        st = run_pair(scene, &rd[0], s->auto_pilot_spp, pp[1].seconds / 2.0, &pp[0]);
    lumis_session_desc fin = *s;
    fin.auto_estimator = fin.auto_pilot_spp = 0;
    if (st == LUMIS_OK) {
        double v[LUMIS_AUTO_CANDIDATES];
        variances(pp, LUMIS_AUTO_CANDIDATES, v);
        int best = 0;
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
            lumis_auto_candidate *a = &r->auto_candidates[c];
            a->error_per_spp = v[c];
            a->per_spp = scale * pp[c].seconds / (2.0 * pp[c].n);
            a->once = c == 1 ? once : 0.0;
            a->pilot_spp = pp[c].n;
            a->efficiency = v[c] * a->per_spp; /* relMSE x seconds */
            if (a->efficiency < r->auto_candidates[best].efficiency) best = c;
        }
        r->auto_count = LUMIS_AUTO_CANDIDATES;
        r->auto_chosen = best;
        r->auto_seconds = omp_get_wtime() - t0;
        fin.spent = s->spent + r->auto_seconds;
        if (best == 1) {
            fin.render.lighting = rd[1].lighting;
            fin.render.light_samples = fin.render.bsdf_samples = 0;
        }
    }
    lumis_session_result keep = *r;
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
        lumis_image_destroy(pp[c].a);
        lumis_image_destroy(pp[c].b);
    }
    if (st == LUMIS_OK) {
        st = lumis_render_session(scene, &fin, out, r);
        /* the render's own result, with the choice and what it cost */
        r->auto_count = keep.auto_count;
        r->auto_chosen = keep.auto_chosen;
        r->auto_seconds = keep.auto_seconds;
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++)
            r->auto_candidates[c] = keep.auto_candidates[c];
        if (r->auto_chosen == 1) {
            r->lights_k = AUTO_K;
            r->lights_build_ms = lumis_light_set_get_info(set)->build_ms;
            r->regions_build_ms = lumis_region_sampler_build_ms(regions);
            r->regions_bytes = lumis_region_sampler_bytes(regions);
        }
    }
    lumis_region_sampler_destroy(regions);
    if (st == LUMIS_OK && r->auto_chosen == 1 && keep_set) {
        r->light_set = set; /* the caller's now, as a session's own set is */
        set = NULL;
    }
    lumis_light_set_destroy(set);
    if (st != LUMIS_OK) {
        lumis_image_destroy(*out);
        *out = NULL;
    }
    r->wall_seconds += r->auto_seconds;
    return st;
}
