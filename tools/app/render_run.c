/* lumis render (and the bench's items, the demo) in four steps: plan (the scene read, what
 * lights it, every output checked against every input), load (the map, its sampler, the
 * Embree scene), run (the flags as one lighting value, checked by the library, then
 * lumis_render_session), write (the images, the summary and warnings, the sidecar). */
#include "errors.h"
#include "files.h"
#include "load.h"
#include "lights.h"
#include "pipeline.h"

#include "lumis/metrics.h"
#include "lumis/render.h"

#include <cJSON.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- the run --------------------------------------------------------------------------- */

/* The fields lumis_session_check names, and the options that set them. */
static const struct {
    const char *field, *options;
} field_options[] = {
    {"auto_estimator", "--auto or --auto-pilots (--no-auto: off)"},
    {"lighting.sampler", "--method, --blocks"},
    {"lighting.estimator", "--mis none, --method bsdf"},
    {"lighting.light_set.mode", "--lights-mode"},
    {"lighting.light_set.draws", "--lights-draws"},
    {"lighting.light_set.region_draws", "--lights-region-draws"},
    {"lighting.luminaires", "--luminaire, --lum-*, --visibility"},
    {"lighting.photometric", "--fixture"},
    {"lighting.env", "--env"},
    {"power_heuristic", "--mis power"},
    {"light_samples", "--light-samples"},
    {"bsdf_samples", "--bsdf-samples"},
    {"max_bounces", "--bounces"},
    {"session: lights:", "--lights"},
    {"lights_k", "--lights-k"},
    {"interleave", "--interleave"},
    {"lights_params", "--lights-param"},
    {"upsample", "--upsample"},
};

/* The library's refusal, kept to be said with the options that gave the field. */
static void keep_message(void *user, lumis_status status, const char *message)
{
    (void)status;
    snprintf((char *)user, 512, "%s", message);
}

/* The session's passes, for the progress bar. */
static void on_pass(void *user, int spp)
{
    ((progress *)user)->spp_done = spp;
}

/* Everything one render holds between its steps (tool_render owns it; render_release frees). */
typedef struct render_state {
    const char *cmd; /* names the command in usage errors */
    double t0;       /* when the render began */
    lumis_scene_file *file;
    lumis_luminaire *replacement; /* --luminaire, or a built-in scene's own (cached) */
    int lum, fixtures, self_lit;  /* luminaires light it; fixtures do; either */
    const char *envspec;          /* the map that lights it (or is asked for), or NULL */
    char sidecar[4096];           /* "": none */
    lumis_camera cam;             /* rd.camera */
    lumis_envmap *env;
    lumis_sun sun;                  /* --sun: what lumis_sun_find found */
    lumis_envmap *residual;         /* --sun, a sun found: the map without it */
    lumis_sun_sampler *sun_sampler; /* and its pixels by their power */
    double sun_seconds;             /* its detection (spent from the budget) */
    lumis_sampler *smp;
    lumis_light_set *lights; /* the session's */
    lumis_scene *scene;
    lumis_photometric_file *cli_fixture; /* --fixture */
    lumis_photometric_instance cli_instance;
    lumis_luminaire *near_field; /* --fixture-near-field: the light field made of the file */
    lumis_photometric_light_field_report near_report;
    double near_seconds;            /* its making: spent from a time budget */
    lumis_luminaire_choice *chosen; /* auto: what the render chose, per luminaire */
    lumis_luminaire_lighting lighting;
    lumis_photometric_lighting fixture_lighting;
    lumis_render_desc rd;
    lumis_session_desc sess;
    lumis_session_result sr;
    progress pg;
} render_state;

static const char *scene_label(const tool_render_opts *o)
{
    return o->scene_path ? o->scene_path : o->scene_name;
}

/* ---- plan ---------------------------------------------------------------------------------- */

/* Reads the scene (with --luminaire's or its own luminaire through the cache) and decides
 * what lights it: luminaires alone, else photometric fixtures, else a map.  Exit code. */
static int plan_scene(const tool_render_opts *o, render_state *s)
{
    lumis_scene_read_options so = {0};
    so.skip_env_map = o->envspec != NULL; /* --env replaces the scene's map: not read */
    so.errors = tool_errors;
    so.load_preset = tool_scene_load_preset; /* presets through the cache */
    /* --luminaire with a built-in scene: placed instead of the scene's own (which is not
     * acquired); with a scene file, it replaces the file's luminaires below. */
    if (o->luminaire && tool_load_luminaire(o->luminaire, &s->replacement) != LUMIS_OK)
        return EXIT_RUNTIME;
    /* A built-in scene's own luminaire through the cache too (it would be acquired anew). */
    const char *own = o->scene_name ? lumis_scene_builtin_luminaire_spec(o->scene_name) : NULL;
    if (!s->replacement && own && tool_load_luminaire(own, &s->replacement) != LUMIS_OK)
        return EXIT_RUNTIME;
    lumis_status st = o->scene_path ? lumis_scene_file_read(o->scene_path, &so, &s->file)
                                    : lumis_scene_builtin_with_luminaire(
                                          o->scene_name, s->replacement, &tool_errors, &s->file);
    if (st != LUMIS_OK) return EXIT_RUNTIME;
    const lumis_scene_file *file = s->file;
    /* A scene with luminaires is lit by them alone; its camera rays that escape see black.
     * So is a scene with photometric fixtures (and no luminaires): it is self-lit. */
    s->lum = file->luminaire_count > 0;
    s->fixtures = !s->lum && (file->photometric_count > 0 || o->fixture);
    s->self_lit = s->lum || s->fixtures;
    if (!s->lum && file->luminaires_listed > 0) /* not the default sky instead */
        return tool_runtime_error("%s: every luminaire of the scene has intensity 0: nothing "
                                  "lights it (give one an intensity, or list none to light it "
                                  "by a map)",
                                  scene_label(o));
    if (s->self_lit && file->env_map[0])
        fprintf(stderr,
                "lumis: warning: %s: the scene's environment (%s) is ignored: a scene with "
                "%s is lit by them alone\n",
                scene_label(o), file->env_map, s->lum ? "luminaires" : "photometric fixtures");
    if (s->lum && file->photometric_count > 0)
        fprintf(stderr,
                "lumis: warning: %s: its %d photometric fixture%s are ignored: a scene with "
                "luminaires is lit by them alone\n",
                scene_label(o), file->photometric_count, file->photometric_count == 1 ? "" : "s");
    if (o->luminaire && !s->lum)
        return tool_usage_error(s->cmd,
                                "--luminaire %s: the scene places no luminaire (try --scene "
                                "headlight)",
                                o->luminaire);
    /* The map lights the scene, unless it lights itself; a map or a sampler asked for
     * regardless is made and given, for lumis_session_check to refuse by name. */
    s->envspec = o->envspec                       ? o->envspec
                 : s->self_lit && !o->sampler_opt ? NULL
                 : file->env_map[0]               ? file->env_map
                                                  : "sky";
    return EXIT_OK;
}

/* A luminaire manifest read for its images (inputs too); counted in *n. */
static void plan_manifest(tool_files *files, const char *path, lumis_luminaire_manifest **mans,
                          int *n)
{
    if (*n < TOOL_FILES_MAX && lumis_luminaire_manifest_read(path, NULL, &mans[*n]) == LUMIS_OK) {
        tool_files_input_list(files, "luminaire image", mans[*n]->paths, mans[*n]->image_count);
        (*n)++;
    }
}

/* The sidecar's path, then every output checked against every input before the work: a
 * sidecar named after OUT.exr must never replace the scene file (render scene.json -o
 * scene.exr).  Exit code. */
static int plan_outputs(const tool_render_opts *o, render_state *s)
{
    if (o->out && (!o->sidecar || o->sidecar[0])) {
        if (o->sidecar)
            snprintf(s->sidecar, sizeof s->sidecar, "%s", o->sidecar);
        else
            tool_sidecar_path(o->out, s->sidecar, sizeof s->sidecar);
    }
    const lumis_scene_file *file = s->file;
    tool_files files = {0};
    tool_files_input(&files, "scene file", o->scene_path);
    tool_files_input(&files, "environment map", s->envspec);
    /* A luminaire is its manifest and every image it names: all inputs. */
    lumis_luminaire_manifest *mans[TOOL_FILES_MAX] = {0};
    int nmans = 0;
    for (int k = 0; lumis_scene_file_luminaire_path(file, k); k++) {
        const char *lp = lumis_scene_file_luminaire_path(file, k);
        if (strncmp(lp, "preset:", 7) == 0) continue;
        tool_files_input(&files, "luminaire", lp);
        plan_manifest(&files, lp, mans, &nmans);
    }
    for (int k = 0; !o->fixture && lumis_scene_file_photometric_path(file, k); k++)
        tool_files_input(&files, "photometric file", lumis_scene_file_photometric_path(file, k));
    if (o->fixture) tool_files_input(&files, "--fixture", o->fixture);
    if (o->luminaire && strncmp(o->luminaire, "preset:", 7) != 0) {
        tool_files_input(&files, "luminaire", o->luminaire);
        plan_manifest(&files, o->luminaire, mans, &nmans);
    }
    for (int k = 0; lumis_scene_file_mesh_path(file, k); k++)
        tool_files_input(&files, "mesh file", lumis_scene_file_mesh_path(file, k));
    tool_files_output(&files, "output", o->out, TOOL_OUT_LINEAR);
    tool_files_output(&files, "--png", o->png, TOOL_OUT_PNG);
    tool_files_sidecar(&files, s->sidecar, "--sidecar PATH (or none: --no-sidecar)");
    int rc = tool_files_check(s->cmd, &files);
    for (int k = 0; k < nmans; k++) lumis_luminaire_manifest_destroy(mans[k]);
    return rc;
}

/* ---- load ---------------------------------------------------------------------------------- */

/* The map's envmap and, when it lights the scene or is asked for, its sampler; then the
 * Embree scene.  Exit code. */
static int load_inputs(const tool_render_opts *o, render_state *s, tool_render_result *r)
{
    const lumis_scene_file *file = s->file;
    float rotation = o->envspec ? o->rotation_deg : file->env_rotation_deg,
          scale = o->envspec ? o->scale : file->env_scale;
    s->cam = file->camera;
    if (o->width) s->cam.width = o->width, s->cam.height = o->height;
    const lumis_image *preloaded = o->envspec ? o->env_image : file->env_image;
    if (s->envspec && preloaded && !o->envspec) { /* the scene file's map: counted by its reader */
        r->env_replaced = file->env_info.replaced;
        tool_warn_replaced(s->envspec, r->env_replaced, preloaded);
    } else if (s->envspec &&
               preloaded) { /* the caller's (lumis bench): it warned when it read it */
        r->env_replaced = o->env_image_replaced;
    }
    if (s->envspec && tool_make_envmap(s->envspec, preloaded, rotation, scale, &s->env,
                                       &r->env_replaced) != LUMIS_OK)
        return EXIT_RUNTIME;
    /* --sun: the sun split off the map; the sampler and light sets are the residual's */
    if (o->sun && s->env && !s->self_lit) {
        const double ts = tool_now_seconds();
        lumis_sun_desc sund = {0};
        sund.errors = tool_errors;
        if (lumis_sun_find(s->env, &sund, &s->sun, &s->residual) != LUMIS_OK ||
            (s->residual &&
             lumis_sun_sampler_create(s->env, &s->sun, &tool_errors, &s->sun_sampler) != LUMIS_OK))
            return EXIT_RUNTIME;
        s->sun_seconds = tool_now_seconds() - ts;
    }
    lumis_sampler_desc sd = o->sampler;
    sd.errors = tool_errors;
    /* A light set, luminaires or fixtures light the scene by themselves: no sampler is
     * built unless asked for. */
    if (((!s->self_lit && !o->lights) || o->sampler_opt) &&
        lumis_sampler_create(s->residual ? s->residual : s->env, &sd, &s->smp) != LUMIS_OK)
        return EXIT_RUNTIME;
    /* The map's loading alone: the sampler's build is reported on its own. */
    r->load_seconds =
        tool_now_seconds() - s->t0 - (s->smp ? lumis_sampler_build_ms(s->smp) / 1000.0 : 0.0);
    double t1 = tool_now_seconds();
    if (lumis_scene_create(file->objects, file->object_count, &tool_errors, &s->scene) != LUMIS_OK)
        return EXIT_RUNTIME;
    r->scene_seconds = tool_now_seconds() - t1;
    return EXIT_OK;
}

/* --fixture: one fixture instead of the scene's own lights, placed and aimed.  Exit code. */
static int load_fixture(const tool_render_opts *o, render_state *s)
{
    if (lumis_photometric_read(o->fixture, &tool_errors, &s->cli_fixture) != LUMIS_OK)
        return EXIT_RUNTIME;
    lumis_photometric_instance *in = &s->cli_instance;
    const lumis_vec3 aim = {
        (float)(o->fixture_aim_given ? o->fixture_aim[0] - o->fixture_at[0] : 0),
        (float)(o->fixture_aim_given ? o->fixture_aim[1] - o->fixture_at[1] : -1),
        (float)(o->fixture_aim_given ? o->fixture_aim[2] - o->fixture_at[2] : 0)};
    const lumis_vec3 up = {(float)o->fixture_up[0], (float)o->fixture_up[1],
                           (float)o->fixture_up[2]};
    lumis_photometric_info info;
    lumis_photometric_get_info(s->cli_fixture->model, &info);
    if (lumis_photometric_orient(info.type, aim, NULL, o->fixture_roll, in->placement.r) !=
        LUMIS_OK) {
        tool_usage_error(s->cmd, "--fixture-aim: a point other than --fixture-at");
        return EXIT_USAGE;
    }
    if (o->fixture_up_given && lumis_photometric_orient(info.type, aim, &up, o->fixture_roll,
                                                        in->placement.r) != LUMIS_OK) {
        tool_usage_error(s->cmd, "--fixture-up: a direction not along the aim (the fixture's "
                                 "local +x is made perpendicular to the aim)");
        return EXIT_USAGE;
    }
    for (int a = 0; a < 3; a++) in->placement.t[a] = o->fixture_at[a];
    in->photometric = s->cli_fixture->model;
    /* LM-63's lamp-tilt factor at this aim (1 without TILT=INCLUDE) */
    in->multiplier = (o->fixture_multiplier > 0 ? o->fixture_multiplier : 1.0) *
                     lumis_photometric_tilt_factor(s->cli_fixture, info.type, aim);
    in->area = o->fixture_area;
    s->fixture_lighting.instances = in;
    s->fixture_lighting.count = 1;
    if (o->fixture_near_field) { /* the file's light field near it, the table far away */
        const double t0 = tool_now_seconds();
        if (!o->quiet)
            fprintf(stderr, "lumis: making the light field of %s (--fixture-near-field) ...\n",
                    o->fixture);
        if (lumis_luminaire_from_photometric(s->cli_fixture->model, NULL, &tool_errors,
                                             &s->near_field, &s->near_report) != LUMIS_OK)
            return EXIT_RUNTIME;
        s->near_seconds = tool_now_seconds() - t0;
        in->light_field = s->near_field;
        in->light_field_report = &s->near_report;
        if (!o->quiet)
            fprintf(stderr,
                    "lumis: near-field fixture: its light field up to %.3g m, the table from "
                    "%.3g m (%.1f s to make)\n",
                    s->near_report.near_until, s->near_report.far_from, s->near_seconds);
    }
    return EXIT_OK;
}

/* ---- run ----------------------------------------------------------------------------------- */

/* The progress bar (on a terminal), from now: the render's preparation counts. */
static void run_progress(const tool_render_opts *o, render_state *s)
{
    s->pg.enabled = (!o->quiet || o->progress) && isatty(STDERR_FILENO);
    s->pg.start = tool_now_seconds();
    s->pg.budget = o->time_budget;
}

/* The flags as one lighting value: the kind the scene and the flags choose, and every field
 * a flag gave (lumis_session_check refuses what the kind does not take).  Exit code. */
static int run_lighting(const tool_render_opts *o, render_state *s)
{
    lumis_scene_file *file = s->file;
    lumis_render_desc *rd = &s->rd;
    *rd = o->rd;
    rd->camera = &s->cam;
    rd->lighting.kind = s->lum        ? LUMIS_LIGHTING_LUMINAIRES
                        : s->fixtures ? LUMIS_LIGHTING_PHOTOMETRIC
                        : o->lights   ? LUMIS_LIGHTING_LIGHT_SET
                                      : LUMIS_LIGHTING_ENV;
    rd->lighting.env = s->env;
    rd->lighting.sampler = s->smp;
    rd->lighting.light_set.mode = o->lights_mode;
    if (s->residual) {
        rd->lighting.sun.sun = &s->sun;
        rd->lighting.sun.residual = s->residual;
        rd->lighting.sun.sampler = s->sun_sampler;
    }
    rd->errors = tool_errors;
    /* --luminaire: every placed luminaire of the scene replaced by that one. */
    for (int k = 0; s->replacement && k < file->luminaire_count; k++)
        file->luminaires[k].luminaire = s->replacement;
    s->lighting = o->lum;
    s->lighting.instances = file->luminaires;
    s->lighting.auto_costs = o->lum_costs_given ? &o->lum_costs : NULL;
    if (s->lum && o->lum.strategy == LUMIS_LUM_AUTO && file->luminaire_count > 0) {
        if (!(s->chosen = calloc((size_t)file->luminaire_count, sizeof *s->chosen)))
            return tool_runtime_error("out of memory");
        s->lighting.chosen = s->chosen;
    }
    s->lighting.count = file->luminaire_count;
    rd->lighting.luminaires = s->lum || o->lum_option ? &s->lighting : NULL;
    s->fixture_lighting = (lumis_photometric_lighting){file->photometrics, file->photometric_count};
    if (o->fixture) {
        int rc = load_fixture(o, s);
        if (rc != EXIT_OK) return rc;
    }
    rd->lighting.photometric = s->fixtures || o->fixture ? &s->fixture_lighting : NULL;
    if (o->bsdf_only) rd->lighting.estimator = LUMIS_ESTIMATOR_BSDF;
    return EXIT_OK;
}

/* The session: the render and what comes before its first sample.  Equal time is equal
 * wall time: what a method needs before its first sample (the sampler's tables, the light
 * set's generation, the pilots that choose K) is spent from the budget, and reported
 * (r->prep_seconds): lumis_render_session does it.  The library alone says which choices do
 * not go together (a usage error here).  Exit code. */
static int run_session_desc(const tool_render_opts *o, render_state *s)
{
    progress *pg = &s->pg;
    if (pg->enabled) {
        s->rd.progress = tool_on_progress;
        s->rd.progress_user = pg;
    }
    lumis_session_desc *sess = &s->sess;
    sess->render = s->rd;
    sess->lights = o->lights;
    /* the default for a map's light (lumis render with no option fixing the estimator) */
    const lumis_lighting *l = &s->rd.lighting;
    sess->auto_estimator = o->auto_estimator ? o->auto_estimator
                           : o->auto_default && l->kind == LUMIS_LIGHTING_ENV && l->env &&
                                   l->sampler && l->estimator == LUMIS_ESTIMATOR_MIS &&
                                   !l->photometric && !l->luminaires && !l->sun.sun && !o->passes
                               ? LUMIS_AUTO_PREDICT
                               : 0;
    sess->lights_k = o->lights_k;
    sess->interleave = o->interleave;
    sess->lights_params = o->lights_params.given ? &o->lights_params : NULL;
    sess->upsample = o->upsample;
    sess->time_budget = o->time_budget;
    sess->spent =
        (s->smp ? lumis_sampler_build_ms(s->smp) / 1000.0 : 0.0) + s->near_seconds + s->sun_seconds;
    sess->timed_spp = TOOL_LIGHTS_TIMED_SPP;
    if (o->passes) { /* share I of N: the whole render's samples first .. first + n - 1 */
        tool_share_range(o, &sess->render.spp, &sess->render.first_sample, &sess->share_spp);
    }
    sess->pass_done = on_pass;
    sess->pass_done_user = pg;
    char refusal[512] = "";
    lumis_session_desc checked = *sess;
    checked.render.errors = (lumis_error_sink){keep_message, refusal};
    if (lumis_session_check(&checked) == LUMIS_OK) return EXIT_OK;
    const char *by = NULL;
    for (size_t k = 0; !by && k < sizeof field_options / sizeof *field_options; k++)
        if (strstr(refusal, field_options[k].field)) by = field_options[k].options;
    return by ? tool_usage_error(s->cmd, "%s [%s]", refusal, by)
              : tool_usage_error(s->cmd, "%s", refusal);
}

/* What the session reports, into the result. */
static void run_result(const tool_render_opts *o, const lumis_session_result *sr,
                       tool_render_result *r)
{
    r->stats = sr->stats;
    r->prep_seconds = sr->prep_seconds;
    r->budget_used_seconds = sr->budget_used_seconds;
    r->lights_pilot_seconds = sr->pilot_seconds;
    for (int p = 0; p < LUMIS_SESSION_PILOTS; p++) {
        r->lights_pilot_k[p] = sr->pilot_k[p];
        r->lights_pilot_per_spp[p] = sr->pilot_per_spp[p];
        r->lights_pilot_once[p] = sr->pilot_once[p];
    }
    r->lights_pilot_count = sr->pilot_count;
    r->lights_pilot_chosen = sr->pilot_chosen;
    r->lights_pilot_scale = sr->pilot_scale;
    r->lights_pilot_predicted = sr->pilot_predicted;
    r->lights_k_floor = sr->k_floor;
    r->lights_spp_planned = sr->spp_planned;
    r->lights_k_limit = sr->k_limit;
    r->lights_retried = sr->retried;
    r->wall_seconds = sr->wall_seconds;
    r->cpu_seconds = sr->cpu_seconds;
    r->render_wall_seconds = sr->render_wall_seconds;
    r->render_cpu_seconds = sr->render_cpu_seconds;
    r->cpu_share = sr->cpu_share;
    r->threads_busy = sr->threads_busy;
    /* A timed render compares methods by what their time bought: threads that waited for
     * a core bought less (measured over passes long enough to tell). */
    r->contended = o->time_budget > 0.0 && sr->render_wall_seconds >= 0.05 && sr->cpu_share > 0.0 &&
                   sr->cpu_share < TOOL_CONTENTION_SHARE;
    r->prep_heavy =
        o->time_budget > 0.0 && sr->prep_seconds > TOOL_PREP_WARN_SHARE * o->time_budget;
    r->upsample = sr->upsample;
    r->auto_count = sr->auto_count;
    r->auto_chosen = sr->auto_chosen;
    r->auto_prior = sr->auto_prior;
    r->auto_held = sr->auto_held;
    r->auto_mode = sr->auto_mode;
    r->auto_rays = sr->auto_rays;
    r->auto_diffuse_share = sr->auto_diffuse_share;
    r->auto_seconds = sr->auto_seconds;
    r->auto_cap = sr->auto_cap;
    r->auto_pilot_seconds = sr->auto_pilot_seconds;
    r->auto_pilot_cpu = sr->auto_pilot_cpu;
    r->auto_sun = sr->auto_sun;
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) r->auto_candidates[c] = sr->auto_candidates[c];
}

const char *tool_render_lights(const tool_render_opts *o, const tool_render_result *r,
                               lumis_lights_mode *mode)
{
    const int strata = r->auto_count > 0 && r->auto_candidates[r->auto_chosen].lights_k > 0;
    *mode = strata ? LUMIS_LIGHTS_STRATIFIED : o->lights_mode;
    return o->lights ? o->lights : strata ? "median-cut" : NULL;
}

/* lumis_render_session, its account in r, the progress bar finished.  Exit code. */
static int run_render(const tool_render_opts *o, render_state *s, tool_render_result *r)
{
    lumis_status st = lumis_render_session(s->scene, &s->sess, &r->image, &s->sr);
    s->lights = s->sr.light_set;
    run_result(o, &s->sr, r);
    s->pg.spp_done = r->stats.spp;
    if (s->pg.enabled) tool_progress_draw(&s->pg, 1.0, 1);
    return st == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
}

/* ---- write --------------------------------------------------------------------------------- */

/* The image, and its PNG preview.  Exit code. */
static int write_images(const tool_render_opts *o, const tool_render_result *r)
{
    if (o->out && tool_write_image(o->out, r->image, NULL) != LUMIS_OK) return EXIT_RUNTIME;
    if (o->png) {
        lumis_write_options po = o->png_options;
        if (o->png_auto_exposure) po.exposure_ev = tool_auto_exposure(r->image);
        if (tool_write_image(o->png, r->image, &po) != LUMIS_OK) return EXIT_RUNTIME;
    }
    return EXIT_OK;
}

/* --lum-strategy auto: what the render chose, for the summary and the sidecar (the first
 * 32 luminaires). */
static void write_lum_choice(const render_state *s, tool_render_result *r)
{
    const lumis_luminaire_choice *chosen = s->chosen;
    const int n = s->file->luminaire_count < 32 ? s->file->luminaire_count : 32;
    r->lum_choice = chosen[0];
    size_t used = 0, ub = 0;
    for (int k = 0; k < n && used + 80 < sizeof r->lum_chosen && ub + 40 < sizeof r->lum_budgets;
         k++) {
        const lumis_luminaire_choice *c = &chosen[k];
        for (int b = 0; b < c->bands; b++) {
            /* "uniform" or, in bands, "uniform to 0.52 + global" */
            used += (size_t)snprintf(r->lum_chosen + used, sizeof r->lum_chosen - used, "%s%s",
                                     b   ? " + "
                                     : k ? ","
                                         : "",
                                     lumis_luminaire_strategy_name(c->strategy[b]));
            if (b + 1 < c->bands)
                used += (size_t)snprintf(r->lum_chosen + used, sizeof r->lum_chosen - used,
                                         " to %.4g", c->edge[b]);
            ub += (size_t)snprintf(r->lum_budgets + ub, sizeof r->lum_budgets - ub, "%s%d",
                                   b   ? "+"
                                   : k ? ","
                                       : "",
                                   c->budget[b]);
        }
    }
}

/* What the render's tables cost: the sampler's build and memory, the luminaires' memory,
 * or the light set's. */
static void write_costs(const render_state *s, tool_render_result *r)
{
    const lumis_scene_file *file = s->file;
    if (s->smp) {
        r->sampler_build_ms = lumis_sampler_build_ms(s->smp);
        r->sampler_table_bytes = lumis_sampler_table_bytes(s->smp);
    }
    for (int k = 0; k < file->luminaire_count; k++) { /* the luminaires' memory */
        int seen = 0; /* an instance may share an earlier one's luminaire */
        for (int q = 0; q < k; q++)
            seen |= file->luminaires[q].luminaire == file->luminaires[k].luminaire;
        lumis_luminaire_info li;
        lumis_luminaire_get_info(file->luminaires[k].luminaire, &li);
        if (!seen) r->sampler_table_bytes += li.bytes;
    }
    if (s->lights) { /* what lights the image: the light set's build and memory */
        r->sampler_build_ms = s->sr.lights_build_ms + s->sr.regions_build_ms;
        r->sampler_table_bytes = s->sr.lights_bytes + s->sr.regions_bytes;
    }
}

/* The automatic estimator's line: what it chose, why (every measured candidate's relMSE x
 * seconds), what the pilots cost against their cap, and what --spp counts. */
static void tool_auto_summary(const tool_render_opts *o, const tool_render_result *r)
{
    char why[900] = "";
    size_t used = 0;
    for (int k = 0; k < r->auto_count && used < sizeof why; k++) {
        const lumis_auto_candidate *q = &r->auto_candidates[k];
        if (q->pilot_spp > 0)
            used += (size_t)snprintf(why + used, sizeof why - used, "%s%s %.3g", used ? ", " : "",
                                     lumis_auto_candidate_name(k), q->efficiency);
    }
    const char *chosen = lumis_auto_candidate_name(r->auto_chosen);
    char cap[64] = "uncapped";
    if (r->auto_cap > 0.0)
        snprintf(cap, sizeof cap, "%s %.3f s", r->auto_prior ? "over their cap" : "cap",
                 r->auto_cap);
    if (r->auto_mode == LUMIS_AUTO_PREDICT)
        fprintf(stderr,
                "lumis: auto: %s, predicted from the scene (the surfaces %d camera rays met "
                "reflect %.0f %% diffusely: strata from %.0f %%, else MIS; docs/render.md)",
                chosen, r->auto_rays, 100.0 * r->auto_diffuse_share,
                100.0 * LUMIS_AUTO_DIFFUSE_MIN);
    else if (r->auto_prior)
        fprintf(stderr, "lumis: auto: %s, the prior (no pilots: %s; docs/render.md)", chosen,
                r->auto_prior == 1 ? "the render is too small for them" : cap);
    else
        fprintf(stderr, "lumis: auto: %s, %s (relMSE x seconds: %s; pilots %.3f s, %s)", chosen,
                r->auto_held ? "the prior: no other beat it beyond the pilots' noise"
                             : "the most efficient of the pilots on this scene",
                why, r->auto_pilot_seconds, cap);
    if (r->auto_sun.found)
        fprintf(stderr, "; a sun-dominated map (sun share %.3f in %d pixels)", r->auto_sun.share,
                r->auto_sun.pixels);
    if (o->time_budget > 0.0)
        fprintf(stderr, "; %.3f s of the budget before the render\n", r->auto_seconds);
    else
        fprintf(stderr, "; the %d spp are %s's samples\n", r->stats.spp, chosen);
}

/* The summary line (and, with --time, the budget's account and K's pilots). */
static void write_summary(const tool_render_opts *o, const render_state *s,
                          const tool_render_result *r)
{
    const lumis_scene_file *file = s->file;
    lumis_lights_mode mode;
    const char *set_name = tool_render_lights(o, r, &mode);
    const char *method = s->lum        ? lumis_luminaire_strategy_name(o->lum.strategy)
                         : s->fixtures ? "photometric"
                         : set_name    ? set_name
                         : o->bsdf_only
                             ? "bsdf"
                             : lumis_sampler_method_name(lumis_sampler_get_method(s->smp));
    double rays = r->stats.camera_rays + r->stats.shadow_rays + r->stats.bounce_rays;
    char how[1400], budget[340];
    if (r->lum_chosen[0]) /* auto: per luminaire */
        snprintf(budget, sizeof budget, "%s", r->lum_budgets);
    else
        snprintf(budget, sizeof budget, "%d", o->lum.budget ? o->lum.budget : 32);
    if (s->lum)
        snprintf(how, sizeof how, "%d luminaire%s: %s%s, K = %s, %s visibility, %s",
                 file->luminaire_count, file->luminaire_count > 1 ? "s" : "",
                 r->lum_chosen[0] ? "auto: " : "", r->lum_chosen[0] ? r->lum_chosen : method,
                 budget, lumis_visibility_name(o->lum.visibility),
                 lumis_sequence_name(lumis_sequence_resolve(o->rd.sequence)));
    else if (s->fixtures)
        snprintf(how, sizeof how, "%d photometric fixture%s, %s", s->rd.lighting.photometric->count,
                 s->rd.lighting.photometric->count > 1 ? "s" : "", tool_estimator_name(&s->rd));
    else if (s->lights)
        snprintf(how, sizeof how, "light set %s, %d lights x %d sets built in %.2f ms%s", set_name,
                 lumis_light_set_get_info(s->lights)->count, lumis_light_set_sets(s->lights),
                 lumis_light_set_get_info(s->lights)->build_ms,
                 mode != LUMIS_LIGHTS_STRATIFIED         ? ""
                 : s->rd.lighting.light_set.draws        ? ", as strata chosen per vertex"
                 : s->rd.lighting.light_set.region_draws ? ", as strata with allocated draws"
                                                         : ", as strata");
    else
        snprintf(how, sizeof how, "%s, sampler %s built in %.2f ms", tool_estimator_name(&s->rd),
                 method, r->sampler_build_ms);
    fprintf(stderr,
            "lumis: rendered %dx%d at %d spp (%s%s) in %.3f s, %.3g rays/s (%.3g shadow "
            "rays/s)\n",
            s->cam.width, s->cam.height, r->stats.spp,
            o->rd.max_bounces > 0 ? "path traced, " : "direct, ", how, r->stats.seconds,
            rays / r->stats.seconds, r->stats.shadow_rays / r->stats.seconds);
    if (o->sun && s->sun.found)
        fprintf(stderr,
                "lumis: sun: dir (%.4f, %.4f, %.4f), radius %.3f deg (cone %.3f deg), share "
                "%.3f of the map's power, found in %.1f ms: sampled as a cone, the rest of the "
                "map as the residual\n",
                s->sun.dir.x, s->sun.dir.y, s->sun.dir.z,
                s->sun.radius * (180.0 / 3.14159265358979),
                s->sun.sample_radius * (180.0 / 3.14159265358979), s->sun.share,
                1000.0 * s->sun_seconds);
    else if (o->sun)
        fprintf(stderr,
                "lumis: sun: none found in the map (docs/lights.md, \"The image sun\"): the whole "
                "map sampled\n");
    if (o->time_budget > 0.0)
        fprintf(stderr,
                "lumis: time budget %.3g s: %.3f s before the first sample (tables, light "
                "sets, K's pilots) + %.3f s rendering = %.3f s; CPU %.3f s over %.3f s wall "
                "(%.0f %% of %d thread%s)\n",
                o->time_budget, r->prep_seconds, r->budget_used_seconds - r->prep_seconds,
                r->budget_used_seconds, r->cpu_seconds, r->wall_seconds, 100.0 * r->cpu_share,
                r->threads_busy, r->threads_busy == 1 ? "" : "s");
    if (r->auto_count > 0) tool_auto_summary(o, r);
    if (r->lights_pilot_count > 0) {
        char why[320] = "";
        tool_k_limit_text(o, r, why, sizeof why);
        fprintf(stderr,
                "lumis: K = %d at %d spp, from %d pilot%s at 1/%.0f of the pixels (%.3f s, "
                "predicted render %.3f s)%s%s\n",
                (int)r->lights_pilot_chosen, r->lights_spp_planned, r->lights_pilot_count,
                r->lights_pilot_count == 1 ? "" : "s", r->lights_pilot_scale,
                r->lights_pilot_seconds, r->lights_pilot_predicted, why[0] ? ": " : "", why);
    }
}

/* Warnings, quiet or not: a timed result that is not what its budget says. */
static void write_warnings(const tool_render_opts *o, const tool_render_result *r)
{
    if (r->prep_heavy)
        fprintf(stderr,
                "lumis: warning: %.3f s of the %.3g s budget (%.0f %%, over %.0f %%) went before "
                "the first sample (tables, light sets, K's pilots)\n",
                r->prep_seconds, o->time_budget, 100.0 * r->prep_seconds / o->time_budget,
                100.0 * TOOL_PREP_WARN_SHARE);
    if (r->lights_k_limit == LUMIS_K_LIMIT_BELOW_FLOOR ||
        r->lights_k_limit == LUMIS_K_LIMIT_OVER_BUDGET) {
        char why[320];
        tool_k_limit_text(o, r, why, sizeof why);
        fprintf(stderr, "lumis: warning: %s\n", why);
    }
    if (r->contended)
        fprintf(stderr,
                "lumis: warning: contention: the render's %d thread%s had %.0f %% of their "
                "wall time on a CPU (%.3f s CPU over %.3f s): other processes shared the cores, "
                "and the %.3g s budget bought less than on an idle machine\n",
                r->threads_busy, r->threads_busy == 1 ? "" : "s", 100.0 * r->cpu_share,
                r->render_cpu_seconds, r->render_wall_seconds, o->time_budget);
}

/* A black image lit by fixtures needs a hint, not exit 0 alone.  "Black": no pixel within
 * 1e-9 of the brightest fixture's peak candela (a diffuse surface 100 m away with albedo
 * 0.01 is 3e-7 of it, in cd/m^2), which leaves the tails of a beam aimed away. */
static void write_black_warning(const render_state *s, const lumis_image *image)
{
    const lumis_photometric_lighting *ph = s->rd.lighting.photometric;
    double peak = 0.0, ymax = 0.0;
    for (int k = 0; k < ph->count; k++) {
        const lumis_photometric_instance *in = &ph->instances[k];
        lumis_photometric_info pi;
        lumis_photometric_get_info(in->photometric, &pi);
        const double c = pi.max_candela * (in->multiplier == 0 ? 1.0 : in->multiplier);
        peak = c > peak ? c : peak;
    }
    const size_t n = (size_t)image->width * (size_t)image->height;
    for (size_t p = 0; p < n; p++) {
        const float *q = image->pixels + 3 * p;
        const double y = 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
        ymax = y > ymax ? y : ymax;
    }
    if (!(ymax > 1e-9 * peak))
        fprintf(stderr,
                "lumis: warning: the image is black (brightest pixel %.3g cd/m^2 under %.3g "
                "cd at the fixture's peak): the photometric fixture%s light%s nothing the "
                "camera sees; check --fixture-at and --fixture-aim (or the scene's "
                "positions, in metres) and the beam\n",
                ymax, peak, ph->count > 1 ? "s" : "", ph->count > 1 ? "" : "s");
}

/* The images, the costs and choices, the summary and warnings, the sidecar.  Exit code. */
static int write_outputs(const tool_render_opts *o, render_state *s, tool_render_result *r)
{
    if (write_images(o, r) != EXIT_OK) return EXIT_RUNTIME;
    r->total_seconds = tool_now_seconds() - s->t0;
    write_costs(s, r);
    if (s->lum && o->lum.strategy == LUMIS_LUM_AUTO && s->chosen) write_lum_choice(s, r);
    if (!o->quiet) write_summary(o, s, r);
    write_warnings(o, r);
    int rc = EXIT_OK;
    if (s->sidecar[0])
        rc = tool_write_sidecar(o, &s->rd, s->sidecar, scene_label(o), s->envspec, s->env, s->smp,
                                s->lights, s->file, &s->cam, r);
    if (rc == EXIT_OK && s->fixtures && r->image) write_black_warning(s, r->image);
    if (rc == EXIT_OK && !o->quiet && o->out) /* every file written, the sidecar's too */
        fprintf(stderr, "lumis: wrote %s%s%s%s%s\n", o->out, o->png ? ", " : "",
                o->png ? o->png : "", s->sidecar[0] ? ", sidecar " : "", s->sidecar);
    return rc;
}

static void render_release(render_state *s)
{
    lumis_scene_destroy(s->scene);
    lumis_scene_file_destroy(s->file);
    lumis_photometric_file_destroy(s->cli_fixture);
    lumis_luminaire_destroy(s->near_field);
    free(s->chosen);
    lumis_luminaire_destroy(s->replacement);
    lumis_sampler_destroy(s->smp);
    lumis_light_set_destroy(s->lights);
    lumis_envmap_destroy(s->env);
    lumis_envmap_destroy(s->residual);
    lumis_sun_sampler_destroy(s->sun_sampler);
}

int tool_render(const tool_render_opts *o, tool_render_result *r)
{
    memset(r, 0, sizeof *r);
    render_state s;
    memset(&s, 0, sizeof s);
    s.t0 = tool_now_seconds();
    s.cmd = o->cmd ? o->cmd : "render";
    int rc = plan_scene(o, &s);
    if (rc == EXIT_OK) rc = plan_outputs(o, &s);
    if (rc == EXIT_OK) rc = load_inputs(o, &s, r);
    if (rc == EXIT_OK) run_progress(o, &s);
    if (rc == EXIT_OK) rc = run_lighting(o, &s);
    if (rc == EXIT_OK) rc = run_session_desc(o, &s);
    if (rc == EXIT_OK) rc = run_render(o, &s, r);
    if (rc == EXIT_OK) rc = write_outputs(o, &s, r);
    if (rc != EXIT_OK) {
        lumis_image_destroy(r->image);
        r->image = NULL;
    }
    render_release(&s);
    return rc;
}
