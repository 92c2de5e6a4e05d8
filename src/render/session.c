/* A render session (lumis_render_session): a light set made by name, Wu's split rendering
 * (EnvDirects at full resolution, EnvIndirects at 1/F joined by joint-bilateral
 * upsampling), and a time budget spent as wall time: the light set's generation and the
 * pilots that fit K count inside it, or progressive passes fill it.  The process's CPU
 * time beside the wall time says whether the threads had their cores (contention). */
#define _POSIX_C_SOURCE 200809L /* clock_gettime's CPU-time clock */
#include "lumis/render.h"

#include "../core/internal.h"
#include "internal.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void)
{
    return omp_get_wtime();
}

/* The process's CPU time, every thread's (0 where the clock is missing: no contention is
 * then ever seen, cpu_share reads 0 and says so). */
double lumis__cpu_now(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0) return 0.0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---- a unit: what one render runs ----------------------------------------------------------
 * A job, or for Wu's split two (EnvDirects at full resolution with the map behind them,
 * EnvIndirects at 1/F of it on black) and the G-buffers that join them. */
typedef struct unit {
    lumis_render_job *full, *low;
    lumis_gbuffer *g_full, *g_low;
    double join_seconds;      /* the G-buffers and the upsampling: render time too */
    int low_every_pass;       /* the low layer is a Monte Carlo estimate too (stratified) */
    double run_wall, run_cpu; /* over its passes: wall time and the process's CPU time */
    int threads;              /* the caller's (0: OpenMP's default) */
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
    u->low_every_pass = rd->lighting.light_set.mode == LUMIS_LIGHTS_STRATIFIED;
    u->threads = rd->threads;
    if (factor <= 1) return lumis_render_job_create(scene, rd, &u->full);
    lumis_render_desc direct = *rd, indirect = *rd;
    direct.lighting.light_set.kinds = 1u << LUMIS_LIGHT_ENV_DIRECT;
    indirect.lighting.light_set.kinds = 1u << LUMIS_LIGHT_ENV_INDIRECT;
    indirect.lighting.hide_environment = 1;
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
    if (st == LUMIS_OK)
        st = lumis__render_gbuffer(scene, rd->camera, rd->threads, &rd->errors, &u->g_full);
    if (st == LUMIS_OK)
        st = lumis__render_gbuffer(scene, &low, rd->threads, &rd->errors, &u->g_low);
    u->join_seconds = now() - t0;
    if (st != LUMIS_OK) unit_destroy(u);
    return st;
}

static lumis_status unit_run(unit *u, int n)
{
    const double w0 = now(), c0 = lumis__cpu_now();
    lumis_status st = lumis_render_job_run(u->full, n);
    lumis_render_stats s;
    if (u->low) lumis_render_job_stats(u->low, &s);
    if (st == LUMIS_OK && u->low && (s.spp == 0 || u->low_every_pass))
        st = lumis_render_job_run(u->low, u->low_every_pass ? n : 1);
    u->run_wall += now() - w0;
    u->run_cpu += lumis__cpu_now() - c0;
    return st;
}

/* Seconds a further sample per pixel costs: the full layer's, and the low one's when it
 * samples every pass (point lights' low layer runs once). */
static double unit_per_sample(const unit *u)
{
    lumis_render_stats f, l;
    lumis_render_job_stats(u->full, &f);
    double per = f.spp ? f.seconds / f.spp : 0.0;
    if (u->low && u->low_every_pass) {
        lumis_render_job_stats(u->low, &l);
        if (l.spp) per += l.seconds / l.spp;
    }
    return per;
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
    ud.threads = u->threads;
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

/* The fewest lights K falls to before the samples per pixel do: below it a light set is a
 * few blobs of light (K = 1 lights a scene with one shadow), and a sample per pixel fewer
 * costs the image less than lights fewer do. */
enum { K_FLOOR = 4, K_PILOT_HIGH = 64 };
/* The pilots spend at most this share of the budget; the rest renders. */
#define PILOT_SHARE 0.2

/* K in [1, min(65536, the map's pixels)]: every method needs a pixel per light. */
static int clamp_k(double k, const lumis_envmap *env)
{
    const double pixels = (double)lumis_envmap_width(env) * lumis_envmap_height(env);
    if (!(k >= 1.0)) k = 1.0;
    if (k > 65536.0) k = 65536.0;
    if (k > pixels) k = pixels;
    return (int)k;
}

/* The camera's pixels (0 == 640 x 480, as lumis_camera says). */
static void cam_size(const lumis_camera *c, int *w, int *h)
{
    *w = c->width ? c->width : 640;
    *h = c->width ? c->height : 480;
}

/* A pilot: the light set at K, rendered at the pilot camera and timed, its times scaled to
 * the whole image (per pixel, everything but the generation costs alike). */
typedef struct pilot {
    int k;
    double scale;   /* the image's pixels over the pilot's */
    double per_spp; /* seconds a sample per pixel of the full layer costs */
    double once;    /* Wu's low layer, G-buffers and upsampling, plus the set's generation */
    double wall;    /* what the pilot itself took */
} pilot;

static lumis_status run_pilot(const lumis_scene *scene, const lumis_session_desc *s,
                              const lumis_render_desc *rd, int d, int factor, int k,
                              double min_seconds, pilot *p)
{
    const double t0 = now();
    int cw, ch;
    cam_size(rd->camera, &cw, &ch);
    lumis_camera cam = *rd->camera;
    cam.width = (cw + d / 2) / d;
    cam.height = (ch + d / 2) / d;
    if (cam.width < 1) cam.width = 1;
    if (cam.height < 1) cam.height = 1;
    const double scale = (double)cw * ch / ((double)cam.width * cam.height);
    lumis_light_set *set = NULL;
    unit u;
    memset(&u, 0, sizeof u);
    memset(p, 0, sizeof *p);
    p->k = k;
    p->scale = scale;
    lumis_render_desc pd = *rd;
    pd.progress = NULL;
    pd.camera = &cam;
    lumis_status st = lumis_lights_by_name(lumis__light_map(rd), s->lights, k, s->interleave,
                                           s->lights_params, &rd->errors, &set);
    const double gen = now() - t0;
    pd.lighting.light_set.set = set;
    if (st == LUMIS_OK) st = unit_create(scene, &pd, factor, &u);
    /* Samples until the full layer has run long enough to time. */
    lumis_render_stats all, f;
    memset(&f, 0, sizeof f);
    for (int n = 1; st == LUMIS_OK; n *= 2) {
        st = unit_run(&u, n);
        lumis_render_job_stats(u.full, &f);
        if (f.seconds >= min_seconds || f.spp >= 64) break;
    }
    lumis_image *img = NULL;
    if (st == LUMIS_OK) st = unit_image(&u, &img); /* the upsampling is render time too */
    if (st == LUMIS_OK) {
        unit_stats(&u, &all);
        p->per_spp = scale * f.seconds / f.spp;
        p->once = scale * (all.seconds - f.seconds) + gen;
    }
    lumis_image_destroy(img);
    unit_destroy(&u);
    lumis_light_set_destroy(set);
    p->wall = now() - t0;
    return st;
}

/* The seconds the pilots (n, sorted by K) predict for K lights at spp samples per pixel:
 * piecewise linear through them, the end segments extended.  A segment's slope is at
 * least a tenth of the first pilot's cost per light (timing noise must not make more
 * lights look free), and below the first pilot the time falls no faster than K. */
static double predict(const pilot *p, int n, double k, int spp)
{
    double t[LUMIS_SESSION_PILOTS] = {0};
    if (n < 1) return HUGE_VAL; /* no pilot: nothing fits */
    for (int i = 0; i < n; i++) t[i] = spp * p[i].per_spp + p[i].once;
    const double min_slope = 0.1 * t[0] / p[0].k;
    for (int i = 1; i < n; i++)
        if (t[i] < t[i - 1] + min_slope * (p[i].k - p[i - 1].k))
            t[i] = t[i - 1] + min_slope * (p[i].k - p[i - 1].k);
    if (n == 1) return k > p[0].k ? t[0] * k / p[0].k : t[0];
    int i = 0; /* the segment i .. i + 1 */
    while (i + 2 < n && k > p[i + 1].k) i++;
    const double slope = (t[i + 1] - t[i]) / (p[i + 1].k - p[i].k);
    const double v = t[i] + slope * (k - p[i].k);
    return k < p[0].k && v < t[0] * k / p[0].k ? t[0] * k / p[0].k : v;
}

double lumis__pilots_predict(const int *k, const double *per_spp, const double *once, int n,
                             double kq, int spp)
{
    pilot p[LUMIS_SESSION_PILOTS];
    memset(p, 0, sizeof p);
    n = n < LUMIS_SESSION_PILOTS ? n : LUMIS_SESSION_PILOTS;
    for (int i = 0; i < n; i++) {
        p[i].k = k[i];
        p[i].per_spp = per_spp[i];
        p[i].once = once[i];
    }
    return predict(p, n, kq, spp);
}

/* The most lights in [1, kmax] whose predicted time fits `budget` at spp; 0 if none. */
static int solve_k(const pilot *p, int n, double budget, int spp, int kmax)
{
    if (!(predict(p, n, 1, spp) <= budget)) return 0;
    int lo = 1, hi = kmax; /* the prediction grows with K: bisection */
    while (lo < hi) {
        const int mid = lo + (hi - lo + 1) / 2;
        if (predict(p, n, mid, spp) <= budget)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* The largest pixel divisor per axis, up to `most`, that keeps a pilot at four 16 x 16
 * tiles a thread (where the image has them: a thread without work would be timed idle). */
static int max_divisor(double px, int threads, int most)
{
    const double min_px = 1024.0 * (threads > 4 ? threads : 4);
    int d = 1;
    while (d < most && px / (4.0 * d * d) >= min_px) d *= 2;
    return d;
}

/* Wu's equal-time rule: a light set spends the time on lights, not samples.  Pilots at K =
 * the floor and 64, and a third where their fit lands, fit the time as piecewise linear in
 * K; K is then what fills the budget at `spp` samples per pixel.  The pilots spend at most
 * PILOT_SHARE of the budget: each renders a reduced image (1/64 of the pixels first, then
 * as many as its share affords, at least four tiles a thread), timed over enough samples
 * to be measurable, its times scaled to the image; one that would pass the share is left
 * out (the fit makes do with fewer).  When the budget affords fewer lights than the floor,
 * the samples per pixel fall first (unless spp_fixed: the caller's count), and what K is
 * left says why (r->k_limit). */
static lumis_status choose_k(const lumis_scene *scene, const lumis_session_desc *s,
                             const lumis_render_desc *rd, int factor, double budget, int spp,
                             int spp_fixed, lumis_session_result *r, int *k_out, int *spp_out)
{
    const lumis_envmap *env = rd->lighting.env;
    const int kmax = clamp_k(65536.0, env), kfloor = kmax < K_FLOOR ? kmax : K_FLOOR;
    const double t0 = now();
    const int threads = rd->threads > 0 ? rd->threads : omp_get_max_threads();
    int cw, ch;
    cam_size(rd->camera, &cw, &ch);
    const double px = (double)cw * ch, cap = PILOT_SHARE * budget;
    const double min_seconds = budget / 200 < 0.01 ? budget / 200 : 0.01;
    pilot p[LUMIS_SESSION_PILOTS];
    int n = 0;
    const int ks[3] = {kfloor, kmax < K_PILOT_HIGH ? kmax : K_PILOT_HIGH, 0};
    for (int i = 0; i < 3; i++) {
        int k = ks[i];
        if (i == 1 && k <= ks[0]) continue;
        if (i == 2) {
            /* where the fit lands, unless a pilot is within 30 % of it: the time is not
             * linear in K (packets of shadow rays grow more coherent with more lights) */
            k = solve_k(p, n, budget - (now() - t0), spp, kmax);
            int near = 0;
            for (int j = 0; j < n; j++) near |= k <= 1.3 * p[j].k && p[j].k <= 1.3 * k;
            if (n < 2 || k <= kfloor || near) break;
        }
        /* Its expected time at full size: the last pilot's time per sample scaled by K (an
         * upper bound: the time grows more slowly than K) and its time once, at one
         * sample per pixel; plus the timing's floor of min_seconds (at most twice it). */
        const double left = cap - (now() - t0);
        int d = max_divisor(px, threads, 8); /* the first: 1/64 of the pixels */
        if (n) {
            const pilot *l = &p[n - 1];
            const double est = l->per_spp * (k > l->k ? (double)k / l->k : 1.0) + l->once;
            const int most = max_divisor(px, threads, 16);
            for (d = 1; d < most && est / ((double)d * d) + 2 * min_seconds > left / (3 - i);)
                d *= 2;
            if (est / ((double)d * d) + min_seconds > left) break; /* past the share */
        }
        pilot q;
        const lumis_status st = run_pilot(scene, s, rd, d, factor, k, min_seconds, &q);
        if (st != LUMIS_OK) return st;
        int at = n; /* sorted by K */
        while (at > 0 && p[at - 1].k > q.k) {
            p[at] = p[at - 1];
            at--;
        }
        p[at] = q;
        n++;
    }
    const double rest = budget - (now() - t0);
    int k = solve_k(p, n, rest, spp, kmax), sp = spp;
    r->k_limit = LUMIS_K_LIMIT_NONE;
    if (k < kfloor) {
        /* Too few lights: fewer samples first, down to one a pixel; then fewer lights, said. */
        for (sp = spp - 1; !spp_fixed && sp >= 1; sp--)
            if ((k = solve_k(p, n, rest, sp, kmax)) >= kfloor) break;
        if (sp < 1 || spp_fixed) sp = spp_fixed ? spp : 1;
        if (k >= kfloor)
            r->k_limit = LUMIS_K_LIMIT_FEWER_SPP;
        else {
            k = solve_k(p, n, rest, sp, kmax);
            r->k_limit = k >= 1 ? LUMIS_K_LIMIT_BELOW_FLOOR : LUMIS_K_LIMIT_OVER_BUDGET;
        }
    }
    if (k < 1) k = 1;
    *k_out = k;
    *spp_out = sp;
    r->pilot_seconds = now() - t0;
    r->pilot_count = n;
    for (int i = 0; i < n; i++) {
        r->pilot_k[i] = p[i].k;
        r->pilot_per_spp[i] = p[i].per_spp;
        r->pilot_once[i] = p[i].once;
    }
    r->pilot_scale = p[0].scale;
    r->pilot_chosen = k;
    r->pilot_predicted = predict(p, n, k, sp);
    r->k_floor = kfloor;
    r->spp_planned = sp;
    return LUMIS_OK;
}

/* the share of one pass a timed render's last pass may be predicted to end past its budget
 * (the estimate's noise: a pass that all but fits is run) */
#define TIMED_SLACK 0.1

int lumis__timed_next_pass(double per, double left, int spp, int cap)
{
    if (spp >= (1 << 24)) return 0;
    if (cap) { /* K was fitted to cap samples: they are made unless far too slow */
        if (spp >= cap || (per > 0.0 && left / per < 0.75)) return 0;
        return 1;
    }
    /* Only whole passes that end within the budget are started (but for a tenth of a pass):
     * a pass that would cross it by half its length used to be run, and one slow pass (a
     * stratified sample, 1.2 s on one core) then took a 2 s budget to 2.5 s.  Equal time
     * means no method gets more than the budget. */
    const double fits = per > 0.0 ? left / per + TIMED_SLACK : (double)(1 << 24);
    if (fits < 1.0) return 0;
    return fits > spp ? spp : (int)fits; /* at most double: estimates settle */
}

/* Runs passes until the budget: each pass is sized from the time per sample so far, and
 * none is started that the estimate says would end past the budget.  cap > 0: at most cap
 * samples per pixel, one a pass (point lights' K fills the time at a planned count: when
 * the pilots misjudged it, or the machine got busier, the budget ends the render first, a
 * sample at most a quarter of one past it). */
static lumis_status run_timed(unit *u, double budget, const lumis_session_desc *s, int cap)
{
    lumis_render_stats st;
    for (int n = 1; n > 0;) {
        const lumis_status rs = unit_run(u, n);
        if (rs != LUMIS_OK) return rs;
        unit_stats(u, &st);
        if (s->pass_done) s->pass_done(s->pass_done_user, st.spp);
        n = lumis__timed_next_pass(unit_per_sample(u), budget - st.seconds, st.spp, cap);
    }
    return LUMIS_OK;
}

/* ---- the session -------------------------------------------------------------------------- */

lumis_status lumis_session_check(const lumis_session_desc *s)
{
    if (!s) return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis_error_sink *errors = &s->render.errors;
    const lumis_lighting *l = &s->render.lighting;
    if (!isfinite(s->time_budget) || s->time_budget < 0.0 || !isfinite(s->spent) ||
        s->lights_k < 0 || s->interleave < 0 || s->upsample < 0 || s->timed_spp < 0 ||
        s->auto_pilot_spp < 0 || s->auto_pilot_spp > 4096 || s->auto_estimator < 0 ||
        s->auto_estimator > LUMIS_AUTO_PILOTS)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: needs a finite budget >= 0, non-negative counts and "
                           "auto_estimator 0, LUMIS_AUTO_PREDICT or LUMIS_AUTO_PILOTS");
    if (s->share_spp < 0 || (s->share_spp > 0 && s->time_budget > 0.0))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: a share of a render is a number of samples (share_spp "
                           ">= 0), not a time budget");
    lumis_lights_method method = (lumis_lights_method)0;
    if (s->lights && lumis_lights_method_from_name(s->lights, &method) != LUMIS_OK)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: lights '%s': unknown light-set method", s->lights);
    const char *needs_lights = s->lights_k        ? "lights_k"
                               : s->interleave    ? "interleave"
                               : s->lights_params ? "lights_params"
                               : s->upsample      ? "upsample"
                                                  : NULL;
    if (!s->lights && needs_lights)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: %s: does not apply without lights (a light-set method)",
                           needs_lights);
    if (s->upsample && method != LUMIS_LIGHTS_DECOMPOSITION)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: upsample: applies to Wu's decomposition (lights wu...), not "
                           "'%s'",
                           s->lights);
    if (s->lights && (unsigned)l->kind < LUMIS_LIGHTING_KIND_COUNT &&
        l->kind != LUMIS_LIGHTING_LIGHT_SET)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: lights: does not apply: the scene is lit by %s "
                           "(render.lighting.kind %s)",
                           lumis__lighting_lit_by(l->kind), lumis_lighting_kind_name(l->kind));
    if (s->lights && (l->light_set.set || l->light_set.regions))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: render.lighting.light_set.%s: given, and lights makes the "
                           "set: give one or the other",
                           l->light_set.set ? "set" : "regions");
    if (s->auto_pilot_spp && s->auto_estimator != LUMIS_AUTO_PILOTS)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: auto_pilot_spp: applies with auto_estimator "
                           "LUMIS_AUTO_PILOTS");
    if (s->auto_estimator) {
        const char *bad = s->lights                             ? "lights"
                          : l->kind != LUMIS_LIGHTING_ENV       ? "render.lighting.kind"
                          : !l->env                             ? "render.lighting.env"
                          : !l->sampler                         ? "render.lighting.sampler"
                          : l->estimator != LUMIS_ESTIMATOR_MIS ? "render.lighting.estimator"
                          : !s->render.camera                   ? "render.camera"
                          : s->share_spp                        ? "share_spp"
                                                                : NULL;
        if (bad)
            return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "session: auto_estimator: chooses how the map lights the scene "
                               "(render.lighting of kind env with its env and sampler, estimator "
                               "MIS, a camera, no lights, not a share): %s is not that",
                               bad);
    }
    if (s->lights && !s->render.camera)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "session: render.camera: missing: a light set's session needs it");
    return lumis__lighting_check(&s->render, s->lights != NULL);
}

lumis_status lumis_render_session(const lumis_scene *scene, const lumis_session_desc *s,
                                  lumis_image **out, lumis_session_result *result)
{
    const double wall0 = now(), cpu0 = lumis__cpu_now();
    lumis_session_result scratch;
    lumis_session_result *r = result ? result : &scratch;
    memset(r, 0, sizeof *r);
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!s || !scene) return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis_error_sink *errors = &s->render.errors;
    const lumis_status cst = lumis_session_check(s);
    if (cst != LUMIS_OK) return cst;
    if (s->auto_estimator) return lumis__session_auto(scene, s, out, r, result != NULL);
    lumis_lights_method method = (lumis_lights_method)0;
    const int wu = s->lights && lumis_lights_method_from_name(s->lights, &method) == LUMIS_OK &&
                   method == LUMIS_LIGHTS_DECOMPOSITION;
    const int stratified = s->render.lighting.kind == LUMIS_LIGHTING_LIGHT_SET &&
                           s->render.lighting.light_set.mode == LUMIS_LIGHTS_STRATIFIED;
    /* the joint-bilateral filter is a bias: strata, which converge, go without it unless
     * asked */
    const int factor = wu ? (s->upsample ? s->upsample : stratified ? 1 : 2) : 1;
    /* Point lights spend the time on K; strata spend it on passes at a fixed K (their
     * error keeps falling, so K is set for the budget's first passes, not its end). */
    const int k_fills_time = s->lights && !stratified && s->time_budget > 0.0 && !s->lights_k;
    const int timed_spp = s->timed_spp ? s->timed_spp : 4;
    const double B = s->time_budget;
    lumis_render_desc rd = s->render;
    /* strata: 32 measured best from 0.25 s to 4 s (docs/results/convergence) */
    int k = s->lights_k ? s->lights_k : stratified ? 32 : 64;
    r->prep_seconds = s->spent;
    lumis_status st = LUMIS_OK;
    /* point lights under a budget: K fills it at these samples per pixel (the caller's, or
     * timed_spp, which may fall when the budget affords too few lights) */
    int spp_plan = rd.spp ? rd.spp : timed_spp;
    if (k_fills_time) {
        const double tp = now();
        st = choose_k(scene, s, &rd, factor, B - r->prep_seconds, spp_plan, rd.spp != 0, r, &k,
                      &spp_plan);
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
        if (s->lights &&
            (st = lumis_lights_by_name(lumis__light_map(&rd), s->lights, k, s->interleave,
                                       s->lights_params, errors, &lights)) != LUMIS_OK)
            break;
        if (s->lights) { /* the session's own set (and strata): the caller gave none */
            rd.lighting.light_set.set = lights;
            if (stratified && (st = lumis_region_sampler_create(lumis__light_map(&rd), lights,
                                                                errors, &regions)) != LUMIS_OK)
                break;
            rd.lighting.light_set.regions = regions;
        }
        if ((st = unit_create(scene, &rd, factor, &u)) != LUMIS_OK) break;
        /* the G-buffers (u.join_seconds) are render time: in the stats, not here */
        r->prep_seconds += now() - tg - u.join_seconds;
        /* A light set under a budget without a K: K fills the time at a fixed sample count.
         * Otherwise the budget adds passes until what is left of it is spent. */
        const double left = B - r->prep_seconds - rendered;
        st = k_fills_time ? run_timed(&u, left, s, spp_plan)
             : B > 0.0    ? run_timed(&u, left, s, 0)
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
        const int k2 = clamp_k(k * rest / (T + g > 1e-9 ? T + g : 1e-9), rd.lighting.env);
        if (k2 <= k) break;
        rendered += T;
        r->render_wall_seconds += u.run_wall;
        r->render_cpu_seconds += u.run_cpu;
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
    /* contention: did the render's threads have their cores? */
    r->render_wall_seconds += u.run_wall;
    r->render_cpu_seconds += u.run_cpu;
    r->threads_busy = r->stats.threads;
    if (s->render.camera) {
        int cw, ch;
        cam_size(s->render.camera, &cw, &ch);
        const int tiles = ((cw + 15) / 16) * ((ch + 15) / 16);
        if (tiles < r->threads_busy) r->threads_busy = tiles;
    }
    if (r->render_wall_seconds > 0.0 && r->threads_busy > 0)
        r->cpu_share = r->render_cpu_seconds / (r->render_wall_seconds * r->threads_busy);
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
    r->wall_seconds = now() - wall0;
    r->cpu_seconds = lumis__cpu_now() - cpu0;
    return st;
}
