/* lumis render (and the bench's items, the demo): a scene, its map and sampler, then
 * lumis_render_session, then the outputs and the sidecar. */
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
    {"lighting.sampler", "--method, --blocks"},
    {"lighting.estimator", "--mis none, --method bsdf"},
    {"lighting.light_set.mode", "--lights-mode"},
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

int tool_render(const tool_render_opts *o, tool_render_result *r)
{
    memset(r, 0, sizeof *r);
    double t0 = tool_now_seconds();
    lumis_scene_file *file = NULL;
    lumis_scene_read_options so = {0};
    so.skip_env_map = o->envspec != NULL; /* --env replaces the scene's map: not read */
    so.errors = tool_errors;
    so.load_preset = tool_scene_load_preset; /* presets through the cache */
    /* --luminaire with a built-in scene: placed instead of the scene's own (which is not
     * acquired); with a scene file, it replaces the file's luminaires below. */
    lumis_luminaire *replacement = NULL;
    if (o->luminaire && tool_load_luminaire(o->luminaire, &replacement) != LUMIS_OK)
        return EXIT_RUNTIME;
    /* A built-in scene's own luminaire through the cache too (it would be acquired anew). */
    const char *own = o->scene_name ? lumis_scene_builtin_luminaire_spec(o->scene_name) : NULL;
    if (!replacement && own && tool_load_luminaire(own, &replacement) != LUMIS_OK)
        return EXIT_RUNTIME;
    lumis_status st = o->scene_path ? lumis_scene_file_read(o->scene_path, &so, &file)
                                    : lumis_scene_builtin_with_luminaire(o->scene_name, replacement,
                                                                         &tool_errors, &file);
    if (st != LUMIS_OK) {
        lumis_luminaire_destroy(replacement);
        return EXIT_RUNTIME;
    }
    const char *cmd = o->cmd ? o->cmd : "render";
    /* A scene with luminaires is lit by them alone; its camera rays that escape see black.
     * So is a scene with photometric fixtures (and no luminaires): it is self-lit. */
    const int lum = file->luminaire_count > 0;
    /* --fixture: one fixture instead of the scene's own lights */
    lumis_photometric_file *cli_fixture = NULL;
    lumis_luminaire_choice *chosen = NULL; /* auto: what the render chose, per luminaire */
    lumis_photometric_instance cli_instance;
    memset(&cli_instance, 0, sizeof cli_instance);
    const int fixtures = !lum && (file->photometric_count > 0 || o->fixture),
              self_lit = lum || fixtures;
    if (!lum && file->luminaires_listed > 0) { /* not the default sky instead */
        lumis_scene_file_destroy(file);
        lumis_luminaire_destroy(replacement);
        return tool_runtime_error("%s: every luminaire of the scene has intensity 0: nothing "
                                  "lights it (give one an intensity, or list none to light it "
                                  "by a map)",
                                  o->scene_path ? o->scene_path : o->scene_name);
    }
    if (self_lit && file->env_map[0])
        fprintf(stderr,
                "lumis: warning: %s: the scene's environment (%s) is ignored: a scene with "
                "%s is lit by them alone\n",
                o->scene_path ? o->scene_path : o->scene_name, file->env_map,
                lum ? "luminaires" : "photometric fixtures");
    if (lum && file->photometric_count > 0)
        fprintf(stderr,
                "lumis: warning: %s: its %d photometric fixture%s are ignored: a scene with "
                "luminaires is lit by them alone\n",
                o->scene_path ? o->scene_path : o->scene_name, file->photometric_count,
                file->photometric_count == 1 ? "" : "s");
    if (o->luminaire && !lum) {
        lumis_scene_file_destroy(file);
        lumis_luminaire_destroy(replacement);
        return tool_usage_error(cmd,
                                "--luminaire %s: the scene places no luminaire (try --scene "
                                "headlight)",
                                o->luminaire);
    }
    /* The map lights the scene, unless it lights itself; a map or a sampler asked for
     * regardless is made and given, for lumis_session_check to refuse by name. */
    const char *envspec = o->envspec ? o->envspec
                          : self_lit && !o->sampler_opt
                              ? NULL
                              : (file->env_map[0] ? file->env_map : "sky");
    char sidecar[4096] = "";
    if (o->out && (!o->sidecar || o->sidecar[0])) {
        if (o->sidecar)
            snprintf(sidecar, sizeof sidecar, "%s", o->sidecar);
        else
            tool_sidecar_path(o->out, sidecar, sizeof sidecar);
    }
    /* Every output is checked against every input before the work: a sidecar named after
     * OUT.exr must never replace the scene file (render scene.json -o scene.exr). */
    tool_files files = {0};
    tool_files_input(&files, "scene file", o->scene_path);
    tool_files_input(&files, "environment map", envspec);
    /* A luminaire is its manifest and every image it names: all inputs. */
    lumis_luminaire_manifest *mans[TOOL_FILES_MAX] = {0};
    int nmans = 0;
    for (int k = 0; lumis_scene_file_luminaire_path(file, k); k++) {
        const char *lp = lumis_scene_file_luminaire_path(file, k);
        if (strncmp(lp, "preset:", 7) == 0) continue;
        tool_files_input(&files, "luminaire", lp);
        if (nmans < TOOL_FILES_MAX &&
            lumis_luminaire_manifest_read(lp, NULL, &mans[nmans]) == LUMIS_OK) {
            tool_files_input_list(&files, "luminaire image", mans[nmans]->paths,
                                  mans[nmans]->image_count);
            nmans++;
        }
    }
    for (int k = 0; !o->fixture && lumis_scene_file_photometric_path(file, k); k++)
        tool_files_input(&files, "photometric file", lumis_scene_file_photometric_path(file, k));
    if (o->fixture) tool_files_input(&files, "--fixture", o->fixture);
    if (o->luminaire && strncmp(o->luminaire, "preset:", 7) != 0) {
        tool_files_input(&files, "luminaire", o->luminaire);
        if (nmans < TOOL_FILES_MAX &&
            lumis_luminaire_manifest_read(o->luminaire, NULL, &mans[nmans]) == LUMIS_OK) {
            tool_files_input_list(&files, "luminaire image", mans[nmans]->paths,
                                  mans[nmans]->image_count);
            nmans++;
        }
    }
    for (int k = 0; lumis_scene_file_mesh_path(file, k); k++)
        tool_files_input(&files, "mesh file", lumis_scene_file_mesh_path(file, k));
    tool_files_output(&files, "output", o->out, TOOL_OUT_LINEAR);
    tool_files_output(&files, "--png", o->png, TOOL_OUT_PNG);
    tool_files_sidecar(&files, sidecar, "--sidecar PATH (or none: --no-sidecar)");
    int rc = tool_files_check(cmd, &files);
    for (int k = 0; k < nmans; k++) lumis_luminaire_manifest_destroy(mans[k]);
    if (rc != EXIT_OK) {
        lumis_scene_file_destroy(file);
        lumis_luminaire_destroy(replacement);
        return rc;
    }
    float rotation = o->envspec ? o->rotation_deg : file->env_rotation_deg,
          scale = o->envspec ? o->scale : file->env_scale;
    lumis_camera cam = file->camera;
    if (o->width) cam.width = o->width, cam.height = o->height;
    lumis_envmap *env = NULL;
    lumis_sampler *smp = NULL;
    lumis_light_set *lights = NULL;
    lumis_scene *scene = NULL;
    rc = EXIT_RUNTIME;
    const lumis_image *preloaded = o->envspec ? o->env_image : file->env_image;
    if (envspec && preloaded && !o->envspec) { /* the scene file's map: counted by its reader */
        r->env_replaced = file->env_info.replaced;
        tool_warn_replaced(envspec, r->env_replaced, preloaded);
    } else if (envspec && preloaded) { /* the caller's (lumis bench): it warned when it read it */
        r->env_replaced = o->env_image_replaced;
    }
    if (envspec &&
        tool_make_envmap(envspec, preloaded, rotation, scale, &env, &r->env_replaced) != LUMIS_OK)
        goto done;
    lumis_sampler_desc sd = o->sampler;
    sd.errors = tool_errors;
    /* A light set, luminaires or fixtures light the scene by themselves: no sampler is
     * built unless asked for. */
    if (((!self_lit && !o->lights) || o->sampler_opt) &&
        lumis_sampler_create(env, &sd, &smp) != LUMIS_OK)
        goto done;
    /* The map's loading alone: the sampler's build is reported on its own. */
    r->load_seconds = tool_now_seconds() - t0 - (smp ? lumis_sampler_build_ms(smp) / 1000.0 : 0.0);
    double t1 = tool_now_seconds();
    if (lumis_scene_create(file->objects, file->object_count, &tool_errors, &scene) != LUMIS_OK)
        goto done;
    r->scene_seconds = tool_now_seconds() - t1;

    progress pg = {0};
    pg.enabled = (!o->quiet || o->progress) && isatty(STDERR_FILENO);
    pg.start = tool_now_seconds();
    pg.budget = o->time_budget;
    lumis_render_desc rd = o->rd;
    rd.camera = &cam;
    /* The flags as one lighting value: the kind the scene and the flags choose, and every
     * field a flag gave (lumis_session_check refuses what the kind does not take). */
    rd.lighting.kind = lum         ? LUMIS_LIGHTING_LUMINAIRES
                       : fixtures  ? LUMIS_LIGHTING_PHOTOMETRIC
                       : o->lights ? LUMIS_LIGHTING_LIGHT_SET
                                   : LUMIS_LIGHTING_ENV;
    rd.lighting.env = env;
    rd.lighting.sampler = smp;
    rd.lighting.light_set.mode = o->lights_mode;
    rd.errors = tool_errors;
    /* --luminaire: every placed luminaire of the scene replaced by that one. */
    for (int k = 0; replacement && k < file->luminaire_count; k++)
        file->luminaires[k].luminaire = replacement;
    lumis_luminaire_lighting lighting = o->lum;
    lighting.instances = file->luminaires;
    lighting.auto_costs = o->lum_costs_given ? &o->lum_costs : NULL;
    if (lum && o->lum.strategy == LUMIS_LUM_AUTO && file->luminaire_count > 0) {
        if (!(chosen = calloc((size_t)file->luminaire_count, sizeof *chosen))) {
            tool_runtime_error("out of memory");
            goto done;
        }
        lighting.chosen = chosen;
    }
    lighting.count = file->luminaire_count;
    rd.lighting.luminaires = lum || o->lum_option ? &lighting : NULL;
    lumis_photometric_lighting fixture_lighting = {file->photometrics, file->photometric_count};
    if (o->fixture) {
        if (lumis_photometric_read(o->fixture, &tool_errors, &cli_fixture) != LUMIS_OK) goto done;
        const lumis_vec3 aim = {
            (float)(o->fixture_aim_given ? o->fixture_aim[0] - o->fixture_at[0] : 0),
            (float)(o->fixture_aim_given ? o->fixture_aim[1] - o->fixture_at[1] : -1),
            (float)(o->fixture_aim_given ? o->fixture_aim[2] - o->fixture_at[2] : 0)};
        const lumis_vec3 up = {(float)o->fixture_up[0], (float)o->fixture_up[1],
                               (float)o->fixture_up[2]};
        lumis_photometric_info info;
        lumis_photometric_get_info(cli_fixture->model, &info);
        if (lumis_photometric_orient(info.type, aim, NULL, o->fixture_roll,
                                     cli_instance.placement.r) != LUMIS_OK) {
            tool_usage_error(cmd, "--fixture-aim: a point other than --fixture-at");
            rc = EXIT_USAGE;
            goto done;
        }
        if (o->fixture_up_given && lumis_photometric_orient(info.type, aim, &up, o->fixture_roll,
                                                            cli_instance.placement.r) != LUMIS_OK) {
            tool_usage_error(cmd, "--fixture-up: a direction not along the aim (the fixture's "
                                  "local +x is made perpendicular to the aim)");
            rc = EXIT_USAGE;
            goto done;
        }
        for (int a = 0; a < 3; a++) cli_instance.placement.t[a] = o->fixture_at[a];
        cli_instance.photometric = cli_fixture->model;
        /* LM-63's lamp-tilt factor at this aim (1 without TILT=INCLUDE) */
        cli_instance.multiplier = (o->fixture_multiplier > 0 ? o->fixture_multiplier : 1.0) *
                                  lumis_photometric_tilt_factor(cli_fixture, info.type, aim);
        cli_instance.area = o->fixture_area;
        fixture_lighting.instances = &cli_instance;
        fixture_lighting.count = 1;
    }
    rd.lighting.photometric = fixtures || o->fixture ? &fixture_lighting : NULL;
    if (o->bsdf_only) rd.lighting.estimator = LUMIS_ESTIMATOR_BSDF;
    if (pg.enabled) {
        rd.progress = tool_on_progress;
        rd.progress_user = &pg;
    }
    /* Equal time is equal wall time: what a method needs before its first sample (the
     * sampler's tables, the light set's generation, the pilots that choose K) is spent from
     * the budget, and reported (r->prep_seconds): lumis_render_session does it. */
    lumis_session_desc sess = {0};
    sess.render = rd;
    sess.lights = o->lights;
    sess.lights_k = o->lights_k;
    sess.interleave = o->interleave;
    sess.lights_params = o->lights_params.given ? &o->lights_params : NULL;
    sess.upsample = o->upsample;
    sess.time_budget = o->time_budget;
    sess.spent = smp ? lumis_sampler_build_ms(smp) / 1000.0 : 0.0;
    sess.timed_spp = TOOL_LIGHTS_TIMED_SPP;
    if (o->passes) { /* share I of N: the whole render's samples first .. first + n - 1 */
        tool_share_range(o, &sess.render.spp, &sess.render.first_sample, &sess.share_spp);
    }
    sess.pass_done = on_pass;
    sess.pass_done_user = &pg;
    /* The library alone says which choices do not go together (a usage error here). */
    char refusal[512] = "";
    lumis_session_desc checked = sess;
    checked.render.errors = (lumis_error_sink){keep_message, refusal};
    if (lumis_session_check(&checked) != LUMIS_OK) {
        const char *by = NULL;
        for (size_t k = 0; !by && k < sizeof field_options / sizeof *field_options; k++)
            if (strstr(refusal, field_options[k].field)) by = field_options[k].options;
        rc = by ? tool_usage_error(cmd, "%s [%s]", refusal, by)
                : tool_usage_error(cmd, "%s", refusal);
        goto done;
    }
    lumis_session_result sr;
    st = lumis_render_session(scene, &sess, &r->image, &sr);
    lights = sr.light_set;
    r->stats = sr.stats;
    r->prep_seconds = sr.prep_seconds;
    r->budget_used_seconds = sr.budget_used_seconds;
    r->lights_pilot_seconds = sr.pilot_seconds;
    for (int p = 0; p < LUMIS_SESSION_PILOTS; p++) {
        r->lights_pilot_k[p] = sr.pilot_k[p];
        r->lights_pilot_per_spp[p] = sr.pilot_per_spp[p];
        r->lights_pilot_once[p] = sr.pilot_once[p];
    }
    r->lights_pilot_count = sr.pilot_count;
    r->lights_pilot_chosen = sr.pilot_chosen;
    r->lights_pilot_scale = sr.pilot_scale;
    r->lights_pilot_predicted = sr.pilot_predicted;
    r->lights_k_floor = sr.k_floor;
    r->lights_spp_planned = sr.spp_planned;
    r->lights_k_limit = sr.k_limit;
    r->lights_retried = sr.retried;
    r->wall_seconds = sr.wall_seconds;
    r->cpu_seconds = sr.cpu_seconds;
    r->render_wall_seconds = sr.render_wall_seconds;
    r->render_cpu_seconds = sr.render_cpu_seconds;
    r->cpu_share = sr.cpu_share;
    r->threads_busy = sr.threads_busy;
    /* A timed render compares methods by what their time bought: threads that waited for
     * a core bought less (measured over passes long enough to tell). */
    r->contended = o->time_budget > 0.0 && sr.render_wall_seconds >= 0.05 && sr.cpu_share > 0.0 &&
                   sr.cpu_share < TOOL_CONTENTION_SHARE;
    r->prep_heavy = o->time_budget > 0.0 && sr.prep_seconds > TOOL_PREP_WARN_SHARE * o->time_budget;
    const int factor = sr.upsample;
    r->upsample = factor;
    pg.spp_done = r->stats.spp;
    if (pg.enabled) tool_progress_draw(&pg, 1.0, 1);
    if (st != LUMIS_OK) goto done;
    if (o->out && tool_write_image(o->out, r->image, NULL) != LUMIS_OK) goto done;
    if (o->png) {
        lumis_write_options po = o->png_options;
        if (o->png_auto_exposure) po.exposure_ev = tool_auto_exposure(r->image);
        if (tool_write_image(o->png, r->image, &po) != LUMIS_OK) goto done;
    }
    r->total_seconds = tool_now_seconds() - t0;
    if (smp) {
        r->sampler_build_ms = lumis_sampler_build_ms(smp);
        r->sampler_table_bytes = lumis_sampler_table_bytes(smp);
    }
    for (int k = 0; k < file->luminaire_count; k++) { /* the luminaires' memory */
        int seen = 0; /* an instance may share an earlier one's luminaire */
        for (int q = 0; q < k; q++)
            seen |= file->luminaires[q].luminaire == file->luminaires[k].luminaire;
        lumis_luminaire_info li;
        lumis_luminaire_get_info(file->luminaires[k].luminaire, &li);
        if (!seen) r->sampler_table_bytes += li.bytes;
    }
    if (lights) { /* what lights the image: the light set's build and memory */
        r->sampler_build_ms = sr.lights_build_ms + sr.regions_build_ms;
        r->sampler_table_bytes = sr.lights_bytes + sr.regions_bytes;
    }
    if (lum && o->lum.strategy == LUMIS_LUM_AUTO && chosen) {
        /* what the render chose, for the summary and the sidecar (the first 32) */
        const int n = file->luminaire_count < 32 ? file->luminaire_count : 32;
        r->lum_choice = chosen[0];
        size_t used = 0, ub = 0;
        for (int k = 0;
             k < n && used + 80 < sizeof r->lum_chosen && ub + 40 < sizeof r->lum_budgets; k++) {
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
    const char *method = lum            ? lumis_luminaire_strategy_name(o->lum.strategy)
                         : fixtures     ? "photometric"
                         : o->lights    ? o->lights
                         : o->bsdf_only ? "bsdf"
                                        : lumis_sampler_method_name(lumis_sampler_get_method(smp));
    if (!o->quiet) {
        double rays = r->stats.camera_rays + r->stats.shadow_rays + r->stats.bounce_rays;
        char how[1400], budget[340];
        if (r->lum_chosen[0]) /* auto: per luminaire */
            snprintf(budget, sizeof budget, "%s", r->lum_budgets);
        else
            snprintf(budget, sizeof budget, "%d", o->lum.budget ? o->lum.budget : 32);
        if (lum)
            snprintf(how, sizeof how, "%d luminaire%s: %s%s, K = %s, %s visibility, %s",
                     file->luminaire_count, file->luminaire_count > 1 ? "s" : "",
                     r->lum_chosen[0] ? "auto: " : "", r->lum_chosen[0] ? r->lum_chosen : method,
                     budget, lumis_visibility_name(o->lum.visibility),
                     lumis_sequence_name(lumis_sequence_resolve(o->rd.sequence)));
        else if (fixtures)
            snprintf(how, sizeof how, "%d photometric fixture%s, %s",
                     rd.lighting.photometric->count, rd.lighting.photometric->count > 1 ? "s" : "",
                     tool_estimator_name(&rd));
        else if (lights)
            snprintf(how, sizeof how, "light set %s, %d lights x %d sets built in %.2f ms%s",
                     o->lights, lumis_light_set_get_info(lights)->count,
                     lumis_light_set_sets(lights), lumis_light_set_get_info(lights)->build_ms,
                     o->lights_mode == LUMIS_LIGHTS_STRATIFIED ? ", as strata" : "");
        else
            snprintf(how, sizeof how, "%s, sampler %s built in %.2f ms", tool_estimator_name(&rd),
                     method, r->sampler_build_ms);
        fprintf(stderr,
                "lumis: rendered %dx%d at %d spp (%s%s) in %.3f s, %.3g rays/s (%.3g shadow "
                "rays/s)\n",
                cam.width, cam.height, r->stats.spp,
                o->rd.max_bounces > 0 ? "path traced, " : "direct, ", how, r->stats.seconds,
                rays / r->stats.seconds, r->stats.shadow_rays / r->stats.seconds);
        if (o->time_budget > 0.0)
            fprintf(stderr,
                    "lumis: time budget %.3g s: %.3f s before the first sample (tables, light "
                    "sets, K's pilots) + %.3f s rendering = %.3f s; CPU %.3f s over %.3f s wall "
                    "(%.0f %% of %d thread%s)\n",
                    o->time_budget, r->prep_seconds, r->budget_used_seconds - r->prep_seconds,
                    r->budget_used_seconds, r->cpu_seconds, r->wall_seconds, 100.0 * r->cpu_share,
                    r->threads_busy, r->threads_busy == 1 ? "" : "s");
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
    rc = EXIT_OK;
    if (sidecar[0])
        rc = tool_write_sidecar(o, &rd, sidecar, o->scene_path ? o->scene_path : o->scene_name,
                                envspec, env, smp, lights, file, &cam, r);
    if (rc == EXIT_OK && fixtures && r->image) {
        /* A black image needs a hint, not exit 0 alone.  "Black": no pixel within 1e-9 of the
         * brightest fixture's peak candela (a diffuse surface 100 m away with albedo 0.01
         * is 3e-7 of it, in cd/m^2), which leaves the tails of a beam aimed away. */
        double peak = 0.0, ymax = 0.0;
        for (int k = 0; k < rd.lighting.photometric->count; k++) {
            const lumis_photometric_instance *in = &rd.lighting.photometric->instances[k];
            lumis_photometric_info pi;
            lumis_photometric_get_info(in->photometric, &pi);
            const double c = pi.max_candela * (in->multiplier == 0 ? 1.0 : in->multiplier);
            peak = c > peak ? c : peak;
        }
        const size_t n = (size_t)r->image->width * (size_t)r->image->height;
        for (size_t p = 0; p < n; p++) {
            const float *q = r->image->pixels + 3 * p;
            const double y = 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
            ymax = y > ymax ? y : ymax;
        }
        if (!(ymax > 1e-9 * peak))
            fprintf(stderr,
                    "lumis: warning: the image is black (brightest pixel %.3g cd/m^2 under %.3g "
                    "cd at the fixture's peak): the photometric fixture%s light%s nothing the "
                    "camera sees; check --fixture-at and --fixture-aim (or the scene's "
                    "positions, in metres) and the beam\n",
                    ymax, peak, rd.lighting.photometric->count > 1 ? "s" : "",
                    rd.lighting.photometric->count > 1 ? "" : "s");
    }
    if (rc == EXIT_OK && !o->quiet && o->out) /* every file written, the sidecar's too */
        fprintf(stderr, "lumis: wrote %s%s%s%s%s\n", o->out, o->png ? ", " : "",
                o->png ? o->png : "", sidecar[0] ? ", sidecar " : "", sidecar);
done:
    if (rc != EXIT_OK) {
        lumis_image_destroy(r->image);
        r->image = NULL;
    }
    lumis_scene_destroy(scene);
    lumis_scene_file_destroy(file);
    lumis_photometric_file_destroy(cli_fixture);
    free(chosen);
    lumis_luminaire_destroy(replacement);
    lumis_sampler_destroy(smp);
    lumis_light_set_destroy(lights);
    lumis_envmap_destroy(env);
    return rc;
}
