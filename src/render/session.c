/* A render session (lumis_render_session): a light set made by name, Wu's split rendering
 * (EnvDirects at full resolution, EnvIndirects at 1/F joined by joint-bilateral
 * upsampling), and a time budget spent as wall time: the light set's generation and the
 * pilots that fit K count inside it, or progressive passes fill it. */
#include "lumis/render.h"

#include "../core/internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

static double now(void)
{
    return omp_get_wtime();
}

/* ---- a unit: what one render runs ----------------------------------------------------------
 * A job, or for Wu's split two (EnvDirects at full resolution with the map behind them,
 * EnvIndirects at 1/F of it on black) and the G-buffers that join them. */
typedef struct unit {
    lumis_render_job *full, *low;
    lumis_gbuffer *g_full, *g_low;
    double join_seconds; /* the G-buffers and the upsampling: render time too */
    int low_every_pass;  /* the low layer is a Monte Carlo estimate too (stratified) */
    lumis_error_sink errors;
} unit;

static void unit_destroy(unit *u)
{
    lumis_render_job_destroy(u->full);
    lumis_render_job_destroy(u->low);
    lumis_gbuffer_destroy(u->g_full);
    lumis_gbuffer_destroy(u->g_low);
    memset(u, 0, sizeof *u);
}

/* factor > 1: the split (rd must light with a light set). */
static lumis_status unit_create(const lumis_scene *scene, const lumis_render_desc *rd, int factor,
                                unit *u)
{
    memset(u, 0, sizeof *u);
    u->errors = rd->errors;
    u->low_every_pass = rd->lights_mode == LUMIS_LIGHTS_STRATIFIED;
    if (factor <= 1) return lumis_render_job_create(scene, rd, &u->full);
    lumis_render_desc direct = *rd, indirect = *rd;
    direct.light_kinds = 1u << LUMIS_LIGHT_ENV_DIRECT;
    indirect.light_kinds = 1u << LUMIS_LIGHT_ENV_INDIRECT;
    indirect.hide_environment = 1;
    /* The low layer is lit where its G-buffer looked: at the pixels' centres, so a pixel on
     * a silhouette is not darkened by the background it half covers.  Point lights are
     * deterministic, so one sample per pixel is the whole layer; strata take a sample at
     * every pass, as the full layer does. */
    indirect.pixel_centers = 1;
    indirect.progress = NULL;
    lumis_camera low = *rd->camera;
    low.width = (rd->camera->width + factor / 2) / factor;
    low.height = (rd->camera->height + factor / 2) / factor;
    if (low.width < 1) low.width = 1;
    if (low.height < 1) low.height = 1;
    indirect.camera = &low;
    const double t0 = now();
    lumis_status st = lumis_render_job_create(scene, &direct, &u->full);
    if (st == LUMIS_OK) st = lumis_render_job_create(scene, &indirect, &u->low);
    if (st == LUMIS_OK) st = lumis_render_gbuffer(scene, rd->camera, &rd->errors, &u->g_full);
    if (st == LUMIS_OK) st = lumis_render_gbuffer(scene, &low, &rd->errors, &u->g_low);
    u->join_seconds = now() - t0;
    if (st != LUMIS_OK) unit_destroy(u);
    return st;
}

static lumis_status unit_run(unit *u, int n)
{
    lumis_status st = lumis_render_job_run(u->full, n);
    lumis_render_stats s;
    if (u->low) lumis_render_job_stats(u->low, &s);
    if (st == LUMIS_OK && u->low && (s.spp == 0 || u->low_every_pass))
        st = lumis_render_job_run(u->low, u->low_every_pass ? n : 1);
    return st;
}

static void unit_stats(const unit *u, lumis_render_stats *s)
{
    lumis_render_job_stats(u->full, s);
    if (!u->low) return;
    lumis_render_stats l;
    lumis_render_job_stats(u->low, &l);
    s->seconds += l.seconds + u->join_seconds;
    s->camera_rays += l.camera_rays;
    s->shadow_rays += l.shadow_rays;
    s->bounce_rays += l.bounce_rays;
    s->light_samples += l.light_samples;
}

/* The image: the full job's, plus the low one's upsampled (timed as render time). */
static lumis_status unit_image(unit *u, lumis_image **out)
{
    lumis_status st = lumis_render_job_image(u->full, out);
    if (st != LUMIS_OK || !u->low) return st;
    const double t0 = now();
    lumis_image *low = NULL, *up = NULL;
    lumis_upsample_desc ud = {0};
    ud.errors = u->errors;
    st = lumis_render_job_image(u->low, &low);
    if (st == LUMIS_OK) st = lumis_joint_bilateral_upsample(low, u->g_low, u->g_full, &ud, &up);
    if (st == LUMIS_OK) {
        const size_t n = 3 * (size_t)up->width * (size_t)up->height;
        for (size_t k = 0; k < n; k++) (*out)->pixels[k] += up->pixels[k];
    } else {
        lumis_image_destroy(*out);
        *out = NULL;
    }
    lumis_image_destroy(low);
    lumis_image_destroy(up);
    u->join_seconds += now() - t0;
    return st;
}

/* ---- K for a time budget --------------------------------------------------------------- */

/* K in [1, min(65536, the map's pixels)]: every method needs a pixel per light. */
static int clamp_k(double k, const lumis_envmap *env)
{
    const double pixels = (double)lumis_envmap_width(env) * lumis_envmap_height(env);
    if (!(k >= 1.0)) k = 1.0;
    if (k > 65536.0) k = 65536.0;
    if (k > pixels) k = pixels;
    return (int)k;
}

/* Wu's equal-time rule: a light set spends the time on lights, not samples.  Two pilot
 * renders at one sample per pixel with K = 16 and 64 lights fit the time as linear in K;
 * K is then what fills the budget at `spp` samples per pixel. */
static lumis_status choose_k(const lumis_scene *scene, const lumis_session_desc *s,
                             const lumis_render_desc *rd, int factor, double budget, int spp,
                             lumis_session_result *r, int *k_out)
{
    const lumis_envmap *env = rd->env;
    /* K = 16 and 64, or fewer on a map of fewer pixels (a 4 x 2 map has 8 lights at most) */
    const double px = (double)lumis_envmap_width(env) * lumis_envmap_height(env);
    const int ks[2] = {px >= 16 ? 16 : (px >= 2 ? (int)px / 2 : 1), px >= 64 ? 64 : (int)px};
    double t[2] = {0, 0}, once[2] = {0, 0}; /* per sample (the full layer); once (the rest) */
    double gen[2] = {0, 0};                 /* the light set's generation */
    const double t0 = now();
    for (int p = 0; p < 2; p++) {
        lumis_light_set *set = NULL;
        unit u;
        memset(&u, 0, sizeof u);
        lumis_render_desc pd = *rd;
        pd.progress = NULL;
        const double tg = now();
        lumis_status st = lumis_lights_by_name(env, s->lights, ks[p], s->interleave,
                                               s->lights_params, &rd->errors, &set);
        gen[p] = now() - tg;
        pd.light_set = set;
        if (st == LUMIS_OK) st = unit_create(scene, &pd, factor, &u);
        /* Samples until the full layer has run long enough to time (small images). */
        lumis_render_stats st_all, f;
        memset(&f, 0, sizeof f);
        for (int n = 1; st == LUMIS_OK; n *= 2) {
            st = unit_run(&u, n);
            lumis_render_job_stats(u.full, &f);
            if (f.seconds >= 0.02 || f.seconds >= s->time_budget / 50 || f.spp >= 1024) break;
        }
        lumis_image *img = NULL;
        if (st == LUMIS_OK) st = unit_image(&u, &img); /* the upsampling is render time too */
        if (st == LUMIS_OK) {
            unit_stats(&u, &st_all);
            t[p] = f.seconds / f.spp;
            once[p] = st_all.seconds - f.seconds; /* the low layer, G-buffers, upsampling */
        }
        lumis_image_destroy(img);
        unit_destroy(&u);
        lumis_light_set_destroy(set);
        if (st != LUMIS_OK) return st;
    }
    /* total(K) = spp (a + b K) + c + d K: the full layer runs every sample, the low layer
     * of Wu's split, its G-buffers and the upsampling once, and the set's generation once
     * (in c and d: equal time is equal wall time, the lights' making included).  The
     * budget is what is left after the pilots. */
    once[0] += gen[0];
    once[1] += gen[1];
    budget -= now() - t0;
    const double dk = ks[1] > ks[0] ? ks[1] - ks[0] : 1.0; /* a 1-pixel map: one pilot K */
    double b = (t[1] - t[0]) / dk, a = t[0] - b * ks[0];
    double d = (once[1] - once[0]) / dk, c = once[0] - d * ks[0];
    if (!(b > 0.0) || !(a >= 0.0)) { /* too noisy to separate: proportional */
        a = 0.0;
        b = t[1] / ks[1];
    }
    if (!(d >= 0.0) || !(c >= 0.0)) {
        c = 0.0;
        d = once[1] / ks[1];
    }
    *k_out = clamp_k((budget - spp * a - c) / (spp * b + d), env);
    r->pilot_seconds = now() - t0;
    for (int p = 0; p < 2; p++) {
        r->pilot_k[p] = ks[p];
        r->pilot_per_spp[p] = t[p];
        r->pilot_once[p] = once[p];
    }
    r->pilot_chosen = *k_out;
    return LUMIS_OK;
}

/* Runs passes until the budget: each pass is sized from the time per sample so far, so the
 * last one ends as close to the budget as the estimate allows. */
static lumis_status run_timed(unit *u, double budget, const lumis_session_desc *s)
{
    lumis_render_stats st;
    int n = 1;
    for (;;) {
        const lumis_status rs = unit_run(u, n);
        if (rs != LUMIS_OK) return rs;
        unit_stats(u, &st);
        if (s->pass_done) s->pass_done(s->pass_done_user, st.spp);
        const double per = st.seconds / st.spp, left = budget - st.seconds;
        const double next = left / per;
        if (next < 0.5 || st.spp >= (1 << 24)) return LUMIS_OK;
        n = next > st.spp ? st.spp : (int)(next + 0.5); /* at most double: estimates settle */
        if (n < 1) n = 1;
    }
}

/* ---- the session -------------------------------------------------------------------------- */

lumis_status lumis_render_session(const lumis_scene *scene, const lumis_session_desc *s,
                                  lumis_image **out, lumis_session_result *result)
{
    lumis_session_result scratch;
    lumis_session_result *r = result ? result : &scratch;
    memset(r, 0, sizeof *r);
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!s || !scene) return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis_error_sink *errors = &s->render.errors;
    const int wu =
        s->lights && lumis_lights_method_from_name(s->lights) == LUMIS_LIGHTS_DECOMPOSITION;
    if (s->lights && !lumis_lights_method_from_name(s->lights))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: unknown light-set method '%s'", s->lights);
    if (!isfinite(s->time_budget) || s->time_budget < 0.0 || !isfinite(s->spent) ||
        s->lights_k < 0 || s->interleave < 0 || s->upsample < 0 || s->timed_spp < 0 ||
        (s->lights && !s->render.env) || (s->upsample > 1 && !wu) ||
        (s->lights && !s->render.camera))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: needs a finite budget >= 0, non-negative counts, a map and "
                           "a camera for a light set, and upsampling only with Wu's method");
    if ((unsigned)s->lights_mode >= LUMIS_LIGHTS_MODE_COUNT)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "session: unknown lights mode %d",
                           (int)s->lights_mode);
    if (s->share_spp < 0 || (s->share_spp > 0 && s->time_budget > 0.0))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: a share of a render is a number of samples (share_spp "
                           ">= 0), not a time budget");
    const int stratified = s->lights && s->lights_mode == LUMIS_LIGHTS_STRATIFIED;
    /* the joint-bilateral filter is a bias: strata, which converge, go without it unless
     * asked */
    const int factor = wu ? (s->upsample ? s->upsample : stratified ? 1 : 2) : 1;
    /* Point lights spend the time on K; strata spend it on passes at a fixed K (their
     * error keeps falling, so K is set for the budget's first passes, not its end). */
    const int k_fills_time = s->lights && !stratified && s->time_budget > 0.0 && !s->lights_k;
    const int timed_spp = s->timed_spp ? s->timed_spp : 4;
    const double B = s->time_budget;
    lumis_render_desc rd = s->render;
    rd.light_set = NULL;
    rd.light_kinds = 0;
    rd.lights_mode = stratified ? LUMIS_LIGHTS_STRATIFIED : LUMIS_LIGHTS_POINT;
    rd.regions = NULL;
    /* strata: 32 measured best from 0.25 s to 4 s (docs/results/convergence) */
    int k = s->lights_k ? s->lights_k : stratified ? 32 : 64;
    r->prep_seconds = s->spent;
    lumis_status st = LUMIS_OK;
    if (k_fills_time) {
        const double tp = now();
        st = choose_k(scene, s, &rd, factor, B - r->prep_seconds, timed_spp, r, &k);
        r->prep_seconds += now() - tp;
        if (st != LUMIS_OK) return st;
    }
    double rendered = 0.0; /* render seconds of earlier attempts */
    lumis_light_set *lights = NULL;
    lumis_region_sampler *regions = NULL;
    unit u;
    memset(&u, 0, sizeof u);
    for (int attempt = 0;; attempt++) {
        const double tg = now(), prep_before = r->prep_seconds;
        if (s->lights && (st = lumis_lights_by_name(rd.env, s->lights, k, s->interleave,
                                                    s->lights_params, errors, &lights)) != LUMIS_OK)
            break;
        rd.light_set = lights;
        if (stratified &&
            (st = lumis_region_sampler_create(rd.env, lights, errors, &regions)) != LUMIS_OK)
            break;
        rd.regions = regions;
        if ((st = unit_create(scene, &rd, factor, &u)) != LUMIS_OK) break;
        r->prep_seconds += now() - tg;
        /* A light set under a budget without a K: K fills the time at a fixed sample count.
         * Otherwise the budget adds passes until what is left of it is spent. */
        const double left = B - r->prep_seconds - rendered;
        st = k_fills_time ? unit_run(&u, rd.spp ? rd.spp : timed_spp)
             : B > 0.0    ? run_timed(&u, left, s)
                          : unit_run(&u, s->share_spp ? s->share_spp
                                         : rd.spp     ? rd.spp
                                                      : 16);
        if (st == LUMIS_OK) st = unit_image(&u, out);
        unit_stats(&u, &r->stats);
        const double T = r->stats.seconds;
        r->budget_used_seconds = r->prep_seconds + rendered + T;
        /* The pilots misjudged the time (a loaded machine, a tiny image) and less than 60 %
         * of the budget went: K is scaled to what is left, and the render is made again,
         * once (the first attempt's time stays spent).  Over the budget, nothing can be won
         * back: the time used is reported as it is. */
        if (st != LUMIS_OK || !k_fills_time || attempt > 0 || r->budget_used_seconds > 0.6 * B)
            break;
        const double rest = B - r->budget_used_seconds, g = r->prep_seconds - prep_before;
        const int k2 = clamp_k(k * rest / (T + g > 1e-9 ? T + g : 1e-9), rd.env);
        if (k2 <= k) break;
        rendered += T;
        k = k2;
        r->retried = 1;
        lumis_image_destroy(*out);
        *out = NULL;
        unit_destroy(&u);
        lumis_light_set_destroy(lights);
        lights = NULL;
        lumis_region_sampler_destroy(regions);
        regions = NULL;
    }
    r->upsample = factor;
    if (lights && st == LUMIS_OK) { /* what lights the image: the light set's build and memory */
        const lumis_light_set_info *li = lumis_light_set_get_info(lights);
        int lw = 0, lh = 0;
        lumis_light_set_labels(lights, &lw, &lh);
        r->lights_k = k;
        r->lights_build_ms = li->build_ms;
        r->lights_bytes =
            (size_t)lw * (size_t)lh * sizeof(int32_t) +
            (size_t)lumis_light_set_sets(lights) * (size_t)li->count * sizeof(lumis_light);
        r->regions_build_ms = lumis_region_sampler_build_ms(regions);
        r->regions_bytes = lumis_region_sampler_bytes(regions);
    }
    unit_destroy(&u);
    lumis_region_sampler_destroy(regions);
    if (st == LUMIS_OK && result)
        result->light_set = lights; /* the caller's now */
    else
        lumis_light_set_destroy(lights);
    if (st != LUMIS_OK) {
        lumis_image_destroy(*out);
        *out = NULL;
    }
    return st;
}
