/* lumis/render_session.h - a render session: what a host calls to render for a time budget
 * (a light set made, K fitted, Wu's split rendering upsampled) (library lumis-render;
 * lumis/render.h includes every part). */
#ifndef LUMIS_RENDER_SESSION_H_PUBLIC
#define LUMIS_RENDER_SESSION_H_PUBLIC

#include "lumis/export.h"
#include "lumis/image.h"
#include "lumis/lights.h"
#include "lumis/render_job.h"
#include "lumis/render_scene.h"
#include "lumis/status.h"
#include "lumis/sun.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- a render session: what a host calls to render for a time budget ---------------------
 * One call does what the lumis tool's render does between loading and writing: with a
 * light-set method it makes the light set (Wu's split rendering with its EnvIndirects at
 * 1/F resolution, joint-bilateral upsampled, included), and with a time budget it spends
 * the budget as wall time: the light set's generation, and the pilot renders that fit K
 * when none is given, count inside it; otherwise progressive passes fill it. */

/* lumis_session_desc.auto_estimator: how the automatic estimator chooses. */
#define LUMIS_AUTO_PREDICT 1 /* from the surfaces the camera sees, no pilots */
#define LUMIS_AUTO_PILOTS  2 /* from pilot renders of the scene */
/* LUMIS_AUTO_PREDICT: the strata when at least this share of the reflectance the camera
 * sees is diffuse, else MIS; the rays' grid (at most this many per axis). */
#define LUMIS_AUTO_DIFFUSE_MIN 0.5
#define LUMIS_AUTO_GRID        32

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
    /* Nonzero: the session chooses how the map lights the scene (render.lighting of kind env
     * with its env and sampler, estimator MIS, and no `lights`) among the candidates of
     * lumis_auto_candidate (docs/render.md, "The automatic estimator"):
     *
     * LUMIS_AUTO_PREDICT: by a prediction from the scene, without pilots: primary rays on a
     * grid of LUMIS_AUTO_GRID pixels find the surfaces the camera sees, and the share of their
     * reflectance that is diffuse (result->auto_diffuse_share) picks the median-cut regions
     * as strata (K = 32) at LUMIS_AUTO_DIFFUSE_MIN or more, else the map with MIS.  The rule
     * is fitted to measured renders (docs/results/default); it costs a few hundred rays.
     *
     * LUMIS_AUTO_PILOTS: by pilot renders of the scene: the map sampled with MIS through
     * render.lighting.sampler, its median-cut regions as strata (K = 16, 32, 64), and on a
     * sun-dominated map (>= 50 % of the power in <= 0.1 % of the pixels; not when
     * render.lighting.sun is given) the image sun split off with MIS or strata on the
     * residual, whichever the pilots find most efficient on this scene.  The pilots render
     * a sixteenth of the pixels (1200 to 4800) twice per candidate, a stratified pair at one
     * sample per pixel each and an MIS pair for as long; they take at most 15 % of
     * time_budget, or without one of the render's predicted time at the prior (strata,
     * K = 32), which is chosen when no pilot fits (a render of fewer than 4 / 0.15 pilot
     * halves' samples skips them).
     *
     * Either way what the choice took (the rays or pilots, the regions' making) is spent
     * from time_budget, render.spp counts the chosen estimator's samples, and result->auto_*
     * say what was measured and chosen.  Zero (the default): render.lighting as given. */
    int auto_estimator;
    /* With LUMIS_AUTO_PILOTS: samples per pixel in the first half of the MIS pilots (the
     * second has twice as many); 0: as many as take the strata's time (equal time).  Given, every
     * candidate's pilot runs, uncapped, and the pilots' errors depend on the seed alone (their
     * times, and so the choice, still on the machine). */
    int auto_pilot_spp;
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

/* What the automatic estimator measured of one candidate (lumis_session_result).  The
 * candidates: 0 "mis" (the map with MIS through render.lighting.sampler), 1 "stratified-32"
 * (median-cut regions as strata, K = 32: the prior), 2 "sun+mis" and 3 "sun+stratified-32"
 * (a sun-dominated map: the image sun split off, MIS or strata K = 32 on the residual),
 * 4 "stratified-16", 5 "stratified-64". */
#define LUMIS_AUTO_CANDIDATES 6
typedef struct lumis_auto_candidate {
    double error_per_spp; /* its relMSE at one sample per pixel, from the pilot's two halves */
    double per_spp;       /* CPU seconds (all threads') a sample per pixel costs at the
                           * image's size: the pilots' marginal price (wall seconds, for
                           * every candidate, where the CPU clock is missing or saw
                           * nothing of some pilot's pass); compared between candidates
                           * only */
    double efficiency;    /* error_per_spp x per_spp: relMSE x seconds (lower is better) */
    double once;          /* seconds before its first sample (its regions, the sun), spent */
    double error_se;      /* error_per_spp's standard error (the pixels' scatter / sqrt(n)) */
    int pilot_spp;        /* samples per pixel in its pilot's first half (the second has
                             twice as many); 0: not measured
                             (capped, or no sun-dominated map), the fields above but once 0 */
    int lights_k;         /* its regions as strata (0: the map with MIS) */
    int sun;              /* nonzero: the image sun split off, the candidate on the residual */
} lumis_auto_candidate;

/* The candidate's name (above), else "unknown". */
LUMIS_RENDER_API const char *lumis_auto_candidate_name(int candidate);

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
    /* With auto_estimator: every candidate's pilot, the one chosen (the most efficient
     * measured; with strata, lights_k and the regions' build are the set's and light_set is
     * it), and the seconds the choice took (the sets, regions and sun made, the pilots: in
     * prep_seconds).  auto_prior: no pilot pair ran and the prior, "stratified-32", was
     * chosen: 1, the render too small for them (no time budget: its samples x pixels under
     * 4 pilot halves' / 0.15); 2, the pilots' cap passed after the first half; 0 pilots ran.
     * auto_held: 1 when a measured candidate was more efficient than the prior, but not
     * beyond the pilots' noise (2 standard errors of the log ratio: the errors' own and
     * a tenth of each time), so the prior was kept.  auto_cap: the seconds the pilots could
     * take (0: uncapped, auto_pilot_spp given); auto_pilot_seconds: what they took,
     * auto_pilot_cpu: the CPU seconds of their render passes (not the making of their
     * regions or the sun's; 0 without the clock).  The clock is the process's
     * (CLOCK_PROCESS_CPUTIME_ID), every thread's: a host's own threads working beside the
     * session (a UI, another render) are counted in it, and in the pilots' prices
     * (per_spp), which then favour the candidates whose passes they overlapped least; a
     * session that cannot keep its process otherwise idle should read the prices as
     * noisy.  A pass the clock saw nothing of prices every candidate by wall time.
     * auto_sun: the sun looked for (found: sun-dominated; zero when not looked for).
     * auto_mode: the desc's auto_estimator (LUMIS_AUTO_PREDICT: no pilots ran, auto_prior
     * and auto_held are 0 and no candidate is measured).  auto_diffuse_share: with
     * LUMIS_AUTO_PREDICT, the diffuse share of the reflectance the camera's rays met (1
     * when they met no surface); auto_rays: how many met one. */
    int auto_count, auto_chosen, auto_prior, auto_held;
    lumis_auto_candidate auto_candidates[LUMIS_AUTO_CANDIDATES];
    double auto_seconds, auto_cap, auto_pilot_seconds, auto_pilot_cpu;
    lumis_sun auto_sun;
    int auto_mode, auto_rays;
    double auto_diffuse_share;
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

#ifdef __cplusplus
}
#endif
#endif
