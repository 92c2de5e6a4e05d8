/* The JSON sidecar of a render: every setting, timing and count that made the image. */
#include "errors.h"
#include "files.h"
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

void tool_k_limit_text(const tool_render_opts *o, const tool_render_result *r, char *buf,
                       size_t cap)
{
    const int want = o->rd.spp ? o->rd.spp : TOOL_LIGHTS_TIMED_SPP;
    switch (r->lights_k_limit) {
    case LUMIS_K_LIMIT_FEWER_SPP:
        snprintf(buf, cap,
                 "at %d spp the budget affords fewer than %d lights; %d spp keep K at %d or more",
                 want, r->lights_k_floor, r->lights_spp_planned, r->lights_k_floor);
        break;
    case LUMIS_K_LIMIT_BELOW_FLOOR:
        snprintf(buf, cap,
                 "the budget affords only K = %d (fewer than %d lights) even at %d spp: the "
                 "light set is coarse (give more --time or a smaller --size)",
                 (int)r->lights_pilot_chosen, r->lights_k_floor, r->lights_spp_planned);
        break;
    case LUMIS_K_LIMIT_OVER_BUDGET:
        snprintf(buf, cap,
                 "the budget is shorter than one light at %d spp (predicted %.3f s): K = 1 "
                 "and the render overruns it (give more --time or a smaller --size)",
                 r->lights_spp_planned, r->lights_pilot_predicted);
        break;
    default:
        if (cap) buf[0] = '\0';
    }
}

const char *tool_estimator_name(const lumis_render_desc *d)
{
    return d->lighting.estimator == LUMIS_ESTIMATOR_BSDF    ? "bsdf"
           : d->lighting.estimator == LUMIS_ESTIMATOR_LIGHT ? "light"
                                                            : "mis";
}

void tool_sidecar_path(const char *out, char *buf, size_t cap)
{
    size_t n = strlen(out);
    const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    if (dot && (!slash || dot > slash) && dot != out && dot[-1] != '/') n = (size_t)(dot - out);
    snprintf(buf, cap, "%.*s.json", (int)n, out);
}

/* A file the render read, by content: {"path", "bytes", "fnv64"} (nothing for a name that
 * is not a file: a built-in map or scene, a preset). */
static void add_input(cJSON *arr, const char *path)
{
    struct stat st;
    if (!path || !*path || stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return;
    size_t n = 0;
    int oom = 0;
    unsigned char *b = tool_read_file(path, &n, &oom);
    cJSON *e = cJSON_CreateObject();
    cJSON_AddStringToObject(e, "path", path);
    cJSON_AddNumberToObject(e, "bytes", (double)n);
    char h[32];
    snprintf(h, sizeof h, "%016llx",
             (unsigned long long)(b ? tool_fnv(0xcbf29ce484222325ull, b, n) : 0));
    cJSON_AddStringToObject(e, "fnv64", b ? h : "unreadable");
    cJSON_AddItemToArray(arr, e);
    free(b);
}

/* A luminaire's manifest and every image it names. */
static void add_luminaire(cJSON *arr, const char *path)
{
    if (!path || strncmp(path, "preset:", 7) == 0) return;
    add_input(arr, path);
    lumis_luminaire_manifest *m = NULL;
    if (lumis_luminaire_manifest_read(path, NULL, &m) != LUMIS_OK) return;
    for (int k = 0; k < m->image_count; k++) add_input(arr, m->paths[k]);
    lumis_luminaire_manifest_destroy(m);
}

/* What a section of the sidecar is written from. */
typedef struct sidecar_ctx {
    const tool_render_opts *o;
    const lumis_render_desc *rd;
    const char *path, *scene_label, *envspec;
    const lumis_envmap *env;
    const lumis_sampler *smp;
    const lumis_light_set *lights;
    const lumis_scene_file *file;
    const lumis_camera *cam;
    const tool_render_result *r;
    const lumis_render_stats *s;
    int lum, fixtures; /* luminaires light it; photometric fixtures do */
} sidecar_ctx;

/* The version, the command line, the mode and what lights it, the scene. */
static void side_header(cJSON *j, const sidecar_ctx *c)
{
    const tool_render_opts *o = c->o;
    const lumis_scene_file *file = c->file;
    const int lum = c->lum;
    const int fixtures = c->fixtures;
    const char *scene_label = c->scene_label;
    char cmd[8192] = "lumis";
    for (int k = 0; k < o->argc; k++) {
        size_t n = strlen(cmd);
        snprintf(cmd + n, sizeof cmd - n, " %s", o->argv[k]);
    }
    cJSON_AddStringToObject(j, "lumis_version", LUMIS_VERSION_STRING);
    cJSON_AddStringToObject(j, "command", o->argc ? cmd : "(library call)");
    cJSON_AddStringToObject(j, "mode", o->rd.max_bounces > 0 ? "path" : "direct");
    char label[128];
    if (o->rd.max_bounces > 0)
        snprintf(label, sizeof label, "path traced, global illumination, up to %d bounces",
                 o->rd.max_bounces);
    else if (lum)
        snprintf(label, sizeof label, "direct illumination from light-field luminaires");
    else if (fixtures)
        snprintf(label, sizeof label, "direct illumination from photometric fixtures");
    else
        snprintf(label, sizeof label, "direct illumination from the environment");
    cJSON_AddStringToObject(j, "label", label);
    cJSON_AddStringToObject(j, "scene", scene_label);
    cJSON_AddNumberToObject(j, "objects", file->object_count);
}

/* The map: its size, rotation, scale and the values its reader replaced. */
static void side_environment(cJSON *j, const sidecar_ctx *c)
{
    const tool_render_opts *o = c->o;
    const char *envspec = c->envspec;
    const lumis_envmap *env = c->env;
    const tool_render_result *r = c->r;
    cJSON *x;
    if (env) {
        x = cJSON_AddObjectToObject(j, "environment");
        cJSON_AddStringToObject(x, "map", envspec);
        cJSON_AddNumberToObject(x, "width", lumis_envmap_width(env));
        cJSON_AddNumberToObject(x, "height", lumis_envmap_height(env));
        cJSON_AddNumberToObject(x, "rotation_deg", o->rotation_deg);
        cJSON_AddNumberToObject(x, "scale", o->scale);
        /* channel values the map's reader replaced by 0 (NaN, Inf, negative) */
        cJSON_AddNumberToObject(x, "replaced", (double)lumis_replaced_total(r->env_replaced));
        cJSON_AddNumberToObject(x, "replaced_nan", (double)r->env_replaced.nan);
        cJSON_AddNumberToObject(x, "replaced_inf", (double)r->env_replaced.inf);
        cJSON_AddNumberToObject(x, "replaced_negative", (double)r->env_replaced.negative);
    } else {
        cJSON_AddNullToObject(j, "environment");
    }
    /* --sun: the sun split off the map and sampled as a cone (null: not asked for) */
    const lumis_sun *sun = c->rd->lighting.sun.sun;
    if (o->sun) {
        x = cJSON_AddObjectToObject(j, "sun");
        cJSON_AddBoolToObject(x, "found", sun != NULL);
        if (sun) {
            const double d[3] = {sun->dir.x, sun->dir.y, sun->dir.z};
            cJSON_AddItemToObject(x, "dir", cJSON_CreateDoubleArray(d, 3));
            cJSON_AddNumberToObject(x, "radius_deg", sun->radius * (180.0 / 3.14159265358979));
            cJSON_AddNumberToObject(x, "sample_radius_deg",
                                    sun->sample_radius * (180.0 / 3.14159265358979));
            cJSON_AddNumberToObject(x, "share", sun->share);
            cJSON_AddItemToObject(x, "power_rgb", cJSON_CreateDoubleArray(sun->power, 3));
        }
    } else {
        cJSON_AddNullToObject(j, "sun");
    }
}

/* The method and the estimator. */
static void side_method(cJSON *j, const sidecar_ctx *c)
{
    const tool_render_opts *o = c->o;
    const lumis_render_desc *rd = c->rd;
    const lumis_sampler *smp = c->smp;
    const lumis_light_set *lights = c->lights;
    const int lum = c->lum;
    const int fixtures = c->fixtures;
    lumis_lights_mode mode;
    const char *set_name = tool_render_lights(o, c->r, &mode);
    cJSON_AddStringToObject(j, "method",
                            lum ? lumis_luminaire_strategy_name(rd->lighting.luminaires->strategy)
                            : fixtures ? "photometric"
                            : set_name ? set_name
                            : o->bsdf_only
                                ? "bsdf"
                                : lumis_sampler_method_name(lumis_sampler_get_method(smp)));
    cJSON_AddStringToObject(j, "estimator",
                            lum      ? "luminaire"
                            : lights ? "light set"
                                     : tool_estimator_name(rd));
    const tool_render_result *r = c->r;
    if (r->auto_count > 0) { /* what the pilots measured, and the choice */
        cJSON *a = cJSON_AddObjectToObject(j, "auto_estimator");
        cJSON_AddStringToObject(a, "chosen", lumis_auto_candidate_name(r->auto_chosen));
        cJSON_AddStringToObject(
            a, "why",
            r->auto_mode == LUMIS_AUTO_PREDICT ? "predicted: the diffuse share of the surfaces seen"
            : r->auto_prior == 1               ? "prior: the render too small for pilots"
            : r->auto_prior == 2               ? "prior: the pilots over their cap"
            : r->auto_held ? "prior: no candidate beat it beyond the pilots' noise"
                           : "least relmse_x_seconds of the pilots");
        cJSON_AddBoolToObject(a, "default", !o->auto_estimator);
        cJSON_AddStringToObject(a, "mode",
                                r->auto_mode == LUMIS_AUTO_PREDICT ? "predict" : "pilots");
        if (r->auto_mode == LUMIS_AUTO_PREDICT) {
            cJSON_AddNumberToObject(a, "diffuse_share", r->auto_diffuse_share);
            cJSON_AddNumberToObject(a, "diffuse_share_min", LUMIS_AUTO_DIFFUSE_MIN);
            cJSON_AddNumberToObject(a, "rays_met", r->auto_rays);
        } else {
            cJSON_AddNullToObject(a, "diffuse_share");
            cJSON_AddNullToObject(a, "diffuse_share_min");
            cJSON_AddNullToObject(a, "rays_met");
        }
        cJSON_AddStringToObject(a, "spp_counts", "samples of the chosen estimator");
        cJSON_AddNumberToObject(a, "seconds", r->auto_seconds);
        cJSON_AddNumberToObject(a, "pilot_seconds", r->auto_pilot_seconds);
        cJSON_AddNumberToObject(a, "pilot_cpu_seconds", r->auto_pilot_cpu);
        if (r->auto_cap > 0.0)
            cJSON_AddNumberToObject(a, "pilot_cap_seconds", r->auto_cap);
        else
            cJSON_AddNullToObject(a, "pilot_cap_seconds");
        if (r->auto_sun.found) {
            cJSON *sun = cJSON_AddObjectToObject(a, "sun");
            cJSON_AddNumberToObject(sun, "share", r->auto_sun.share);
            cJSON_AddNumberToObject(sun, "pixels", r->auto_sun.pixels);
            cJSON_AddNumberToObject(sun, "radius_deg",
                                    r->auto_sun.radius * (180.0 / 3.14159265358979));
        } else {
            cJSON_AddNullToObject(a, "sun");
        }
        cJSON *arr = cJSON_AddArrayToObject(a, "candidates");
        for (int k = 0; k < r->auto_count; k++) {
            const lumis_auto_candidate *q = &r->auto_candidates[k];
            cJSON *e = cJSON_CreateObject();
            cJSON_AddStringToObject(e, "name", lumis_auto_candidate_name(k));
            cJSON_AddNumberToObject(e, "lights_k", q->lights_k);
            cJSON_AddBoolToObject(e, "sun", q->sun != 0);
            cJSON_AddBoolToObject(e, "measured", q->pilot_spp > 0);
            if (q->pilot_spp > 0) {
                cJSON_AddNumberToObject(e, "relmse_at_1spp", q->error_per_spp);
                cJSON_AddNumberToObject(e, "relmse_at_1spp_se", q->error_se);
                cJSON_AddNumberToObject(e, "seconds_per_spp", q->per_spp);
                cJSON_AddNumberToObject(e, "relmse_x_seconds", q->efficiency);
            }
            cJSON_AddNumberToObject(e, "seconds_before", q->once);
            cJSON_AddNumberToObject(e, "pilot_spp", q->pilot_spp);
            cJSON_AddItemToArray(arr, e);
        }
        cJSON_AddNullToObject(j, "auto_off_by");
    } else {
        cJSON_AddNullToObject(j, "auto_estimator");
        if (o->auto_fixed_by)
            cJSON_AddStringToObject(j, "auto_off_by", o->auto_fixed_by);
        else
            cJSON_AddNullToObject(j, "auto_off_by");
    }
}

/* Every fixture: its file, placement, multiplier, model and flux. */
static void side_photometric(cJSON *j, const sidecar_ctx *c)
{
    const tool_render_opts *o = c->o;
    const lumis_render_desc *rd = c->rd;
    const lumis_scene_file *file = c->file;
    const int fixtures = c->fixtures;
    if (fixtures) { /* every fixture: its file, placement, multiplier, model and flux */
        cJSON *arr = cJSON_AddArrayToObject(j, "photometric");
        for (int k = 0; k < rd->lighting.photometric->count; k++) {
            const lumis_photometric_instance *in = &rd->lighting.photometric->instances[k];
            lumis_photometric_info pi;
            lumis_photometric_get_info(in->photometric, &pi);
            cJSON *e = cJSON_CreateObject();
            cJSON_AddItemToObject(e, "position", cJSON_CreateDoubleArray(in->placement.t, 3));
            cJSON_AddItemToObject(e, "rotation", cJSON_CreateDoubleArray(in->placement.r, 9));
            cJSON_AddNumberToObject(e, "multiplier", in->multiplier == 0 ? 1.0 : in->multiplier);
            cJSON_AddStringToObject(e, "model",
                                    in->area          ? "opening"
                                    : in->light_field ? "near-field"
                                                      : "point");
            if (in->light_field && in->light_field_report) { /* where it changes models */
                const lumis_photometric_light_field_report *nr = in->light_field_report;
                cJSON *nf = cJSON_AddObjectToObject(e, "near_field");
                cJSON_AddNumberToObject(nf, "crossover_sizes", nr->crossover_sizes);
                cJSON_AddNumberToObject(nf, "near_until_m", nr->near_until);
                cJSON_AddNumberToObject(nf, "far_from_m", nr->far_from);
                cJSON_AddNumberToObject(nf, "far_field_error", nr->far_field_error);
            }
            cJSON_AddStringToObject(e, "shape", lumis_photometric_shape_name(pi.shape));
            cJSON_AddNumberToObject(e, "flux", pi.flux);
            cJSON_AddItemToArray(arr, e);
        }
        cJSON *files = cJSON_AddArrayToObject(j, "photometric_files");
        if (o->fixture) cJSON_AddItemToArray(files, cJSON_CreateString(o->fixture));
        for (int q = 0; !o->fixture && lumis_scene_file_photometric_path(file, q); q++)
            cJSON_AddItemToArray(files,
                                 cJSON_CreateString(lumis_scene_file_photometric_path(file, q)));
    } else {
        cJSON_AddNullToObject(j, "photometric");
    }
}

/* --lum-strategy auto: why it chose (the first luminaire's prediction). */
static void side_lum_prediction(cJSON *x, const sidecar_ctx *ctx)
{
    const tool_render_opts *o = ctx->o;
    const tool_render_result *r = ctx->r;
    const lumis_luminaire_prediction *p = &r->lum_choice.prediction;
    cJSON_AddNumberToObject(x, "band_gain", r->lum_choice.band_gain);
    cJSON *pj = cJSON_AddObjectToObject(x, "prediction");
    cJSON_AddNumberToObject(pj, "probes_lit", p->probes_lit);
    cJSON_AddNumberToObject(pj, "energy_share", p->energy_share);
    cJSON_AddNumberToObject(pj, "restricted_time_ratio", p->restricted.time_ratio);
    cJSON_AddNumberToObject(pj, "uniform_time_ratio", p->uniform.time_ratio);
    cJSON_AddNumberToObject(pj, "restricted_sample_ratio", p->restricted.sample_ratio);
    cJSON_AddNumberToObject(pj, "uniform_sample_ratio", p->uniform.sample_ratio);
    const lumis_luminaire_costs c =
        o->lum_costs_given ? o->lum_costs : lumis_luminaire_costs_default();
    const double cv[7] = {
        c.camera, c.image_restricted, c.image_uniform, c.restricted, c.uniform, c.global, c.ray};
    cJSON_AddItemToObject(pj, "costs", cJSON_CreateDoubleArray(cv, 7));
}

/* The luminaires: their strategy, budget, samples and instances. */
static void side_luminaires(cJSON *j, const sidecar_ctx *c)
{
    const lumis_render_desc *rd = c->rd;
    const lumis_camera *cam = c->cam;
    const tool_render_result *r = c->r;
    const lumis_render_stats *s = c->s;
    const int lum = c->lum;
    cJSON *x;
    if (lum) {
        const lumis_luminaire_lighting *ll = rd->lighting.luminaires;
        x = cJSON_AddObjectToObject(j, "luminaires");
        cJSON_AddNumberToObject(x, "count", ll->count);
        cJSON_AddStringToObject(x, "strategy", lumis_luminaire_strategy_name(ll->strategy));
        if (r->lum_chosen[0]) { /* auto: what it chose, and why (the first luminaire's) */
            cJSON_AddStringToObject(x, "chosen", r->lum_chosen);
            cJSON_AddStringToObject(x, "chosen_budgets", r->lum_budgets);
            side_lum_prediction(x, c);
        }
        cJSON_AddNumberToObject(x, "budget", ll->budget ? ll->budget : 32);
        cJSON_AddNumberToObject(x, "k_max", ll->k_max);
        cJSON_AddStringToObject(x, "search", lumis_luminaire_search_name(ll->search));
        cJSON_AddNumberToObject(x, "depth", ll->depth);
        cJSON_AddStringToObject(x, "visibility", lumis_visibility_name(ll->visibility));
        cJSON_AddNumberToObject(x, "bytes", (double)r->sampler_table_bytes);
        /* Samples evaluated, not the budget: a point draws at least one per image with
         * energy in its box, and the global strategy one per image with any. */
        cJSON_AddNumberToObject(x, "samples", s->light_samples);
        cJSON_AddNumberToObject(x, "samples_per_pixel",
                                s->light_samples / ((double)cam->width * (double)cam->height));
        cJSON *arr = cJSON_AddArrayToObject(x, "instances");
        for (int k = 0; k < ll->count; k++) {
            lumis_luminaire_info li;
            lumis_luminaire_get_info(ll->instances[k].luminaire, &li);
            cJSON *e = cJSON_CreateObject();
            cJSON_AddNumberToObject(e, "images", li.images);
            cJSON_AddNumberToObject(e, "width", li.width);
            cJSON_AddNumberToObject(e, "height", li.height);
            cJSON_AddNumberToObject(e, "delta", li.delta);
            cJSON_AddNumberToObject(e, "scale", ll->instances[k].scale);
            cJSON_AddNumberToObject(e, "intensity", ll->instances[k].intensity);
            cJSON_AddItemToArray(arr, e);
        }
    } else {
        cJSON_AddNullToObject(j, "luminaires");
    }
}

/* --lights with --time: K chosen from pilot renders at the floor, 64 and where the fit
 * lands (seconds per sample and once, scaled to the whole image). */
static void side_k_from_time(cJSON *x, const sidecar_ctx *c)
{
    const tool_render_opts *o = c->o;
    const tool_render_result *r = c->r;
    /* --time: K chosen from pilot renders at the floor, 64 and where the fit lands
     * (seconds per sample and once, scaled to the whole image). */
    const int np = r->lights_pilot_count;
    cJSON *pl = cJSON_AddObjectToObject(x, "k_from_time");
    cJSON_AddItemToObject(pl, "pilot_k", cJSON_CreateIntArray(r->lights_pilot_k, np));
    cJSON_AddItemToObject(pl, "pilot_seconds_per_spp",
                          cJSON_CreateDoubleArray(r->lights_pilot_per_spp, np));
    cJSON_AddItemToObject(pl, "pilot_seconds_once",
                          cJSON_CreateDoubleArray(r->lights_pilot_once, np));
    cJSON_AddNumberToObject(pl, "pilot_pixel_fraction", 1.0 / r->lights_pilot_scale);
    cJSON_AddNumberToObject(pl, "k_from_pilots", r->lights_pilot_chosen);
    cJSON_AddNumberToObject(pl, "k_floor", r->lights_k_floor);
    cJSON_AddNumberToObject(pl, "spp_planned", r->lights_spp_planned);
    cJSON_AddNumberToObject(pl, "predicted_render_seconds", r->lights_pilot_predicted);
    cJSON_AddNumberToObject(pl, "pilot_wall_seconds", r->lights_pilot_seconds);
    cJSON_AddNumberToObject(pl, "spp", r->stats.spp);
    cJSON_AddBoolToObject(pl, "rerendered", r->lights_retried);
    static const char *const limits[] = {"none", "fewer_spp", "below_floor", "over_budget"};
    cJSON_AddStringToObject(pl, "k_limit", limits[r->lights_k_limit]);
    char why[320];
    tool_k_limit_text(o, r, why, sizeof why);
    if (why[0])
        cJSON_AddStringToObject(pl, "k_limit_reason", why);
    else
        cJSON_AddNullToObject(pl, "k_limit_reason");
}

/* The light set: its method, mode, parameters, counts and build. */
static void side_lights(cJSON *j, const sidecar_ctx *c)
{
    const tool_render_opts *o = c->o;
    const lumis_light_set *lights = c->lights;
    const tool_render_result *r = c->r;
    cJSON *x;
    if (lights) {
        const lumis_light_set_info *li = lumis_light_set_get_info(lights);
        x = cJSON_AddObjectToObject(j, "lights");
        lumis_lights_mode mode;
        cJSON_AddStringToObject(x, "method", tool_render_lights(o, r, &mode));
        cJSON_AddStringToObject(x, "mode", lumis_lights_mode_name(mode));
        if (o->rd.lighting.light_set.draws)
            cJSON_AddNumberToObject(x, "draws", o->rd.lighting.light_set.draws);
        if (o->rd.lighting.light_set.region_draws)
            cJSON_AddNumberToObject(x, "region_draws", o->rd.lighting.light_set.region_draws);
        char params[1024];
        lumis_light_params_format(&o->lights_params, params, sizeof params);
        cJSON_AddStringToObject(x, "params", params);
        cJSON_AddNumberToObject(x, "requested", li->requested);
        cJSON_AddNumberToObject(x, "count", li->count);
        cJSON_AddNumberToObject(x, "env_directs", li->direct);
        cJSON_AddNumberToObject(x, "env_indirects", li->indirect);
        cJSON_AddNumberToObject(x, "sets", lumis_light_set_sets(lights));
        cJSON_AddNumberToObject(x, "build_ms", li->build_ms);
        cJSON_AddNumberToObject(x, "upsample", r->upsample);
        if (r->lights_pilot_count > 0) side_k_from_time(x, c);
    } else {
        cJSON_AddNullToObject(j, "lights");
    }
}

/* The estimator's counts, the budget, the share, the sequence, threads and code paths, the
 * size. */
static void side_sampling(cJSON *j, const sidecar_ctx *c)
{
    const tool_render_opts *o = c->o;
    const lumis_render_desc *rd = c->rd;
    const lumis_camera *cam = c->cam;
    const lumis_render_stats *s = c->s;
    if (rd->lighting.estimator == LUMIS_ESTIMATOR_MIS)
        cJSON_AddStringToObject(j, "heuristic", rd->power_heuristic ? "power" : "balance");
    else
        cJSON_AddNullToObject(j, "heuristic");
    cJSON_AddNumberToObject(j, "light_samples", o->rd.light_samples ? o->rd.light_samples : 1);
    cJSON_AddNumberToObject(j, "bsdf_samples", o->rd.bsdf_samples ? o->rd.bsdf_samples : 1);
    cJSON_AddNumberToObject(j, "max_bounces", o->rd.max_bounces);
    if (o->time_budget > 0.0) {
        cJSON_AddNumberToObject(j, "time_budget_seconds", o->time_budget);
        cJSON_AddNullToObject(j, "spp_requested");
    } else {
        cJSON_AddNullToObject(j, "time_budget_seconds");
        cJSON_AddNumberToObject(j, "spp_requested", o->rd.spp ? o->rd.spp : 16);
    }
    cJSON_AddNumberToObject(j, "spp", s->spp);
    if (o->passes) { /* a share of a render split by passes (lumis merge joins them) */
        int total, first, count;
        tool_share_range(o, &total, &first, &count);
        cJSON *p = cJSON_AddObjectToObject(j, "share");
        cJSON_AddNumberToObject(p, "index", o->pass_index);
        cJSON_AddNumberToObject(p, "count", o->passes);
        cJSON_AddNumberToObject(p, "first_sample", first);
        cJSON_AddNumberToObject(p, "spp_total", total);
    } else {
        cJSON_AddNullToObject(j, "share");
    }
    cJSON_AddNumberToObject(j, "passes", s->passes);
    cJSON_AddNumberToObject(j, "seed", (double)o->rd.seed);
    cJSON_AddBoolToObject(j, "pixel_centers", o->rd.pixel_centers != 0);
    cJSON_AddStringToObject(j, "sequence",
                            lumis_sequence_name(lumis_sequence_resolve(o->rd.sequence)));
    cJSON_AddNumberToObject(j, "threads", s->threads);
    { /* the code paths this CPU ran: a result is reproduced with the same ones */
        const char *embree = getenv("LUMIS_EMBREE_CONFIG");
        cJSON_AddStringToObject(j, "simd_variant", lumis_simd_variant());
        cJSON_AddStringToObject(j, "embree_config", embree && *embree ? embree : "default");
    }
    cJSON_AddNumberToObject(j, "width", cam->width);
    cJSON_AddNumberToObject(j, "height", cam->height);
}

/* Timings, and contention. */
static void side_timings(cJSON *j, const sidecar_ctx *c)
{
    const tool_render_opts *o = c->o;
    const tool_render_result *r = c->r;
    const lumis_render_stats *s = c->s;
    cJSON *x = cJSON_AddObjectToObject(j, "timings");
    cJSON_AddNumberToObject(x, "load_seconds", r->load_seconds);
    cJSON_AddNumberToObject(x, "sampler_build_seconds", r->sampler_build_ms / 1000.0);
    cJSON_AddNumberToObject(x, "scene_build_seconds", r->scene_seconds);
    cJSON_AddNumberToObject(x, "render_seconds", s->seconds);
    /* Before the first sample: tables, light-set generation, K's pilots (every attempt). */
    cJSON_AddNumberToObject(x, "prep_seconds", r->prep_seconds);
    if (o->time_budget > 0.0) /* prep + every attempt's render: what the budget paid for */
        cJSON_AddNumberToObject(x, "budget_used_seconds", r->budget_used_seconds);
    else
        cJSON_AddNullToObject(x, "budget_used_seconds");
    cJSON_AddNumberToObject(x, "total_seconds", r->total_seconds);
    /* Contention: wall and CPU time of the session, and of its render passes, whose CPU
     * share of the busy threads' wall time says whether they had their cores. */
    cJSON_AddNumberToObject(x, "wall_seconds", r->wall_seconds);
    cJSON_AddNumberToObject(x, "cpu_seconds", r->cpu_seconds);
    cJSON_AddNumberToObject(x, "render_pass_wall_seconds", r->render_wall_seconds);
    cJSON_AddNumberToObject(x, "render_pass_cpu_seconds", r->render_cpu_seconds);
    cJSON_AddNumberToObject(x, "threads_busy", r->threads_busy);
    cJSON_AddNumberToObject(x, "cpu_share", r->cpu_share);
    cJSON_AddBoolToObject(x, "contention", r->contended);
    cJSON_AddNumberToObject(x, "contention_threshold", TOOL_CONTENTION_SHARE);
    if (o->time_budget > 0.0) {
        cJSON_AddNumberToObject(x, "prep_share", r->prep_seconds / o->time_budget);
        cJSON_AddBoolToObject(x, "prep_over_share", r->prep_heavy);
    } else {
        cJSON_AddNullToObject(x, "prep_share");
        cJSON_AddNullToObject(x, "prep_over_share");
    }
}

/* The rays traced, and the sampler's build and tables. */
static void side_rays_sampler(cJSON *j, const sidecar_ctx *c)
{
    const lumis_sampler *smp = c->smp;
    const lumis_render_stats *s = c->s;
    cJSON *x = cJSON_AddObjectToObject(j, "rays");
    double total = s->camera_rays + s->shadow_rays + s->bounce_rays;
    cJSON_AddNumberToObject(x, "camera", s->camera_rays);
    cJSON_AddNumberToObject(x, "shadow", s->shadow_rays);
    cJSON_AddNumberToObject(x, "bounce", s->bounce_rays);
    cJSON_AddNumberToObject(x, "total", total);
    cJSON_AddNumberToObject(x, "per_second", s->seconds > 0 ? total / s->seconds : 0);
    cJSON_AddNumberToObject(x, "shadow_per_second",
                            s->seconds > 0 ? s->shadow_rays / s->seconds : 0);
    if (smp) {
        x = cJSON_AddObjectToObject(j, "sampler");
        cJSON_AddStringToObject(x, "method",
                                lumis_sampler_method_name(lumis_sampler_get_method(smp)));
        cJSON_AddNumberToObject(x, "build_ms", lumis_sampler_build_ms(smp));
        cJSON_AddNumberToObject(x, "table_bytes", (double)lumis_sampler_table_bytes(smp));
        cJSON_AddNumberToObject(x, "total_bytes", (double)lumis_sampler_total_bytes(smp));
        if (lumis_sampler_kdtree_blocks(smp) > 0) {
            cJSON_AddNumberToObject(x, "kdtree_blocks", lumis_sampler_kdtree_blocks(smp));
            cJSON_AddNumberToObject(x, "kdtree_alpha", lumis_sampler_kdtree_alpha(smp));
        }
    } else {
        cJSON_AddNullToObject(j, "sampler"); /* a light set: see "lights" */
    }
}

/* The outputs and, for a share, its inputs by content, its host, and its render key.  Exit code. */
static int side_outputs(cJSON *j, const sidecar_ctx *c)
{
    const tool_render_opts *o = c->o;
    const char *envspec = c->envspec;
    const lumis_scene_file *file = c->file;
    const char *path = c->path;
    cJSON *x = cJSON_AddObjectToObject(j, "outputs");
    cJSON_AddStringToObject(x, "exr", o->out);
    if (o->png)
        cJSON_AddStringToObject(x, "png", o->png);
    else
        cJSON_AddNullToObject(x, "png");
    if (o->passes) { /* a share: its inputs by content, its host, and its render key */
        cJSON *in = cJSON_AddArrayToObject(j, "inputs");
        add_input(in, o->scene_path);
        add_input(in, envspec);
        for (int k = 0; lumis_scene_file_luminaire_path(file, k); k++)
            add_luminaire(in, lumis_scene_file_luminaire_path(file, k));
        add_luminaire(in, o->luminaire);
        for (int k = 0; !o->fixture && lumis_scene_file_photometric_path(file, k); k++)
            add_input(in, lumis_scene_file_photometric_path(file, k));
        add_input(in, o->fixture);
        for (int k = 0; lumis_scene_file_mesh_path(file, k); k++)
            add_input(in, lumis_scene_file_mesh_path(file, k));
        char host[256] = "";
        if (gethostname(host, sizeof host - 1) != 0) snprintf(host, sizeof host, "?");
        cJSON_AddStringToObject(j, "host", host);
        char key[32];
        if (!tool_render_key(j, key, sizeof key))
            return tool_runtime_error("%s: out of memory", path);
        cJSON_AddStringToObject(j, "render_key", key);
    }
    return EXIT_OK;
}

int tool_write_sidecar(const tool_render_opts *o, const lumis_render_desc *rd, const char *path,
                       const char *scene_label, const char *envspec, const lumis_envmap *env,
                       const lumis_sampler *smp, const lumis_light_set *lights,
                       const lumis_scene_file *file, const lumis_camera *cam,
                       const tool_render_result *r)
{
    const sidecar_ctx c = {o,
                           rd,
                           path,
                           scene_label,
                           envspec,
                           env,
                           smp,
                           lights,
                           file,
                           cam,
                           r,
                           &r->stats,
                           rd->lighting.luminaires != NULL,
                           rd->lighting.photometric != NULL};
    cJSON *j = cJSON_CreateObject();
    side_header(j, &c);
    side_environment(j, &c);
    side_method(j, &c);
    side_photometric(j, &c);
    side_luminaires(j, &c);
    side_lights(j, &c);
    side_sampling(j, &c);
    side_timings(j, &c);
    side_rays_sampler(j, &c);
    int rc = side_outputs(j, &c);
    if (rc == EXIT_OK) rc = tool_write_json(path, j);
    cJSON_Delete(j);
    return rc;
}
