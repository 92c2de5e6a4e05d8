/* The render pipeline a program runs (tools/app/render_run.c): one render as `lumis render`
 * does it, also run by `lumis demo` and the bench's items and references; its sidecar
 * (sidecar.c), render key (render_key.c), shares and their merge (merge.c), progress bar and
 * clock (progress.c). */
#ifndef LUMIS_APP_PIPELINE_H
#define LUMIS_APP_PIPELINE_H

#include "lumis/io.h"
#include "lumis/lumis.h"
#include "lumis/render.h"

#include <stddef.h>

/* One render, as `lumis render` does it (also used by `lumis demo`). */
typedef struct tool_render_opts {
    const char *scene_name, *scene_path; /* one of them */
    const char *envspec;                 /* NULL: the scene's map, else "sky" */
    const lumis_image *env_image;        /* envspec's pixels, loaded by the caller (borrowed);
                                            NULL: loaded from envspec */
    lumis_replaced env_image_replaced;   /* what loading env_image replaced (the sidecar's) */
    float rotation_deg, scale;           /* of envspec when given */
    lumis_sampler_desc sampler;
    const char *sampler_opt; /* --method (not bsdf) or --blocks, if given: a sampler is built
                                whatever lights the scene (the library refuses it by name) */
    int bsdf_only;
    int auto_estimator;        /* --auto (LUMIS_AUTO_PREDICT) or --auto-pilots (_PILOTS): the
                                  session chooses how the map lights the scene */
    int auto_default;          /* lumis render with no option fixing the estimator: auto_estimator
                                  when the map lights the scene (not luminaires or fixtures) */
    const char *auto_fixed_by; /* the option that turned the default off, or NULL */
    int sun; /* --sun: a sun found in the map (lumis_sun_find) is sampled as a cone, the rest
                of the map (the residual) by the sampler or light set */
    const char *lights;               /* a light-set method (tool_lights_method_known), or NULL */
    lumis_lights_mode lights_mode;    /* --lights-mode: point (0) or stratified */
    int lights_k, interleave;         /* its K and number of interleaved sets (0: defaults) */
    lumis_light_params lights_params; /* --lights-param (zero: the method's defaults) */
    int upsample;         /* Wu: EnvIndirects at 1/F resolution per axis (0: 2; 1: none) */
    lumis_render_desc rd; /* estimator, heuristic, counts, seed, threads, bounces */
    /* Scenes with luminaires: how they are sampled (the instances come from the scene). */
    lumis_luminaire_lighting lum;
    lumis_luminaire_costs lum_costs; /* --lum-costs (lum.auto_costs points here when given) */
    int lum_costs_given;
    const char *lum_option; /* the first --lum-* / --visibility / --sequence option given */
    /* --fixture FILE: a photometric fixture lights the scene instead of its own lights (map,
     * fixtures), at --fixture-at (required), aimed at --fixture-aim (default straight down,
     * -y), its local +x towards --fixture-up, rolled, scaled, as its opening with
     * --fixture-area */
    const char *fixture;
    double fixture_at[3], fixture_aim[3], fixture_up[3], fixture_roll, fixture_multiplier;
    int fixture_at_given, fixture_aim_given, fixture_up_given, fixture_area;
    int fixture_near_field; /* --fixture-near-field: its light field near it (made at the
                               start, spent from a time budget), the table far away */
    const char *luminaire;  /* --luminaire: replaces every luminaire of the scene (a manifest
                               or preset:NAME); NULL: the scene's own */
    double time_budget;     /* > 0: progressive passes until this much render time */
    int pass_index, passes; /* --passes I/N (passes 0: the whole render) */
    int width, height;      /* 0: the scene's camera */
    const char *out, *png;  /* out NULL: nothing written */
    const char *sidecar;    /* NULL: OUT.json; "": none */
    const char *cmd;        /* names the command in usage errors (NULL: "render") */
    lumis_write_options png_options;
    int png_auto_exposure; /* nonzero: png_options.exposure_ev from the image (auto) */
    int quiet;             /* no progress bar, no summary line */
    int progress;          /* the progress bar (on a terminal) even when quiet */
    int argc;              /* the command line, for the sidecar */
    char **argv;
} tool_render_opts;

typedef struct tool_render_result {
    lumis_image *image; /* the caller destroys it */
    lumis_render_stats stats;
    double load_seconds, scene_seconds, total_seconds, sampler_build_ms;
    size_t sampler_table_bytes;
    int upsample; /* the factor used (1: none) */
    /* --lights with --time: the pilot renders that chose K (0 seconds: none ran), and the
     * session's account of it (lumis_session_result: k_floor, spp_planned, k_limit ...). */
    double lights_pilot_seconds, lights_pilot_per_spp[LUMIS_SESSION_PILOTS],
        lights_pilot_once[LUMIS_SESSION_PILOTS];
    double lights_pilot_chosen; /* K the pilots chose, before any re-render */
    int lights_pilot_k[LUMIS_SESSION_PILOTS], lights_pilot_count;
    double lights_pilot_scale, lights_pilot_predicted;
    int lights_k_floor, lights_spp_planned;
    lumis_k_limit lights_k_limit;
    int lights_retried; /* the pilots misjudged: rendered again with K scaled */
    /* Contention (lumis_session_result): the session's wall and CPU seconds, and over its
     * render passes the CPU share of the busy threads' wall time. */
    double wall_seconds, cpu_seconds, render_wall_seconds, render_cpu_seconds, cpu_share;
    int threads_busy;
    int contended;  /* cpu_share below TOOL_CONTENTION_SHARE: warned */
    int prep_heavy; /* --time: prep_seconds above TOOL_PREP_WARN_SHARE of it: warned */
    /* Equal wall time: seconds before the first sample (sampler tables, light-set generation
     * of every attempt, K's pilots), and that plus every attempt's render (--time only). */
    double prep_seconds, budget_used_seconds;
    lumis_replaced env_replaced; /* the map's values its reader replaced by 0 */
    /* --lum-strategy auto: the strategy of each luminaire, comma-separated (the first 32;
     * "uniform to 0.52 + global" in bands of distance), and the first one's choice */
    char lum_chosen[640];
    char lum_budgets[320]; /* their K (auto gives a global one more: render.h) */
    lumis_luminaire_choice lum_choice;
    /* the automatic estimator: every candidate's pilot and the one chosen
     * (lumis_session_result) */
    int auto_count, auto_chosen, auto_prior, auto_held, auto_mode, auto_rays;
    lumis_auto_candidate auto_candidates[LUMIS_AUTO_CANDIDATES];
    double auto_seconds, auto_cap, auto_pilot_seconds, auto_pilot_cpu, auto_diffuse_share;
    lumis_sun auto_sun;
} tool_render_result;

/* The light set that lit the render: --lights, or the median-cut strata the automatic
 * estimator chose (NULL: none), and its mode. */
const char *tool_render_lights(const tool_render_opts *o, const tool_render_result *r,
                               lumis_lights_mode *mode);

/* Samples per pixel of a light set rendered to a time budget (--lights with --time): the
 * budget goes to the number of lights. */
#define TOOL_LIGHTS_TIMED_SPP 4

/* A timed render whose threads got less than this share of their wall time as CPU time
 * waited for cores (another process ran on them): the CLI warns, the sidecar and the bench
 * report say so.  Idle, a render's passes measure 0.95-1.0; one thread sharing its core with
 * one busy process, about 0.5. */
#define TOOL_CONTENTION_SHARE 0.8
/* A --time render that spent more than this share of its budget before its first sample
 * (tables, light sets, K's pilots) warns: the method's preparation is then what is compared. */
#define TOOL_PREP_WARN_SHARE 0.3

/* The default sidecar of OUT: OUT.exr -> OUT.json (or OUT + .json). */
void tool_sidecar_path(const char *out, char *buf, size_t cap);
/* The sidecar of a render (sidecar.c): every setting, timing and count.  Exit code. */
int tool_write_sidecar(const tool_render_opts *o, const lumis_render_desc *rd, const char *path,
                       const char *scene_label, const char *envspec, const lumis_envmap *env,
                       const lumis_sampler *smp, const lumis_light_set *lights,
                       const lumis_scene_file *file, const lumis_camera *cam,
                       const tool_render_result *r);
/* "bsdf", "light" or "mis". */
const char *tool_estimator_name(const lumis_render_desc *d);
/* Why K fitted to --time is what it is (r->lights_k_limit), in words; "" when it is what
 * the pilots fitted at the planned samples. */
void tool_k_limit_text(const tool_render_opts *o, const tool_render_result *r, char *buf,
                       size_t cap);

/* The progress bar (progress.c): on stderr when it is a terminal; budget > 0: by time. */
typedef struct progress {
    int enabled;
    double start, budget, last;
    int spp_done;
} progress;
void tool_progress_draw(progress *p, double fraction, int final);
/* lumis_render_desc.progress for a progress (user). */
void tool_on_progress(void *user, int done, int total);

/* Checks every output against every input (the scene file, the map, the meshes) before any
 * work (exit 2), then renders.  Returns an exit code; prints errors, a progress bar (stderr is a
 * terminal) and, unless quiet, a summary line. */
int tool_render(const tool_render_opts *o, tool_render_result *r);
/* The samples of o's share (--passes I/N): the whole render's total, the share's first
 * sample and count (without --passes: 0 and all of them). */
void tool_share_range(const tool_render_opts *o, int *total, int *first, int *count);
/* The most shares of a merge: as many as render --passes makes. */
#define TOOL_MERGE_MAX (1 << 20)
/* lumis merge (merge.c): joins the n shares in[] of one render (each with its sidecar)
 * into out, each share's mean weighted by its samples; side_out: the merged sidecar (NULL:
 * none).  Checks that they are every share of one render, each once.  Prints errors (and,
 * unless quiet, a line of what it merged).  Exit code. */
int tool_merge_shares(const char *const *in, int n, const char *out, const char *side_out,
                      int quiet, int allow_replaced);

struct cJSON;
/* The render key (render_key.c): a digest of a share's sidecar less what may differ between
 * the shares of one render (timings, counts of work, host, share index), in out (16 hex
 * digits).  0 when out of memory. */
int tool_render_key(const struct cJSON *side, char *out, size_t cap);
/* Whether "key" or "object.key" of a sidecar may differ between shares of one render. */
int tool_render_key_may_differ(const char *path);
/* The first field of the render key in which sidecars a and b differ, in field, with their
 * values (JSON, shortened) in va and vb; 0 if none. */
int tool_render_key_difference(const struct cJSON *a, const struct cJSON *b, char *field,
                               size_t cap, char *va, char *vb, size_t vcap);

/* Monotonic wall-clock seconds. */
double tool_now_seconds(void);
/* The median of n values (sorts them). */
double tool_median(double *v, int n);

#endif
