/* lumis render SCENE.json | --scene NAME ...: the evaluation renderer, with a fixed sample
 * count or a time budget, a progress bar, and a JSON sidecar describing the run. */
#include "common.h"

#include "lumis/render.h"

#include <cJSON.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static const char usage[] =
    "usage: lumis render [SCENE.json | --scene NAME] [options] -o OUT.exr\n\n"
    "Renders direct illumination from an environment map (or, with --bounces N, path-traced\n"
    "global illumination).  SCENE.json follows the schema in docs/render.md (camera,\n"
    "environment, objects: sphere, plane, mesh with transform or instances).  Built-in\n"
    "scenes: spheres (Lambert, Ward and GGX spheres, Ergun et al.'s Figure 6), bunny-plane\n"
    "(the Stanford bunny and a sphere on a ground plane) and ward-aniso (Ward alpha_x = 0.5,\n"
    "alpha_y = 0.001: their Figure 7).  Without a map in the scene or --env, the procedural\n"
    "sky lights it.  Writes OUT.exr (linear float), an optional PNG preview, and OUT.json:\n"
    "the settings, timings, rays per second and the sampler's build time and bytes.\n\n"
    "options:\n"
    "  --scene NAME       a built-in scene instead of SCENE.json\n"
    "  --env MAP          .exr/.hdr/.pfm file or sky[:WxH] / studio[:WxH] (default: the\n"
    "                     scene's map, else sky)\n"
    "  --method M         light sampler (see lumis sample --help; default inversion-guided)\n"
    "                     or 'bsdf' for BSDF sampling only\n"
    "  --mis H            balance (default), power, or none (light sampling only)\n"
    "  --light-samples N  light samples per camera sample (default 1)\n"
    "  --bsdf-samples N   BSDF samples per camera sample (default 1)\n"
    "  --spp N            camera samples per pixel (default 16)\n"
    "  --time S           instead of --spp: progressive passes until S seconds of rendering\n"
    "                     (equal-time comparisons; the samples reached are reported)\n"
    "  --bounces N        path tracing with up to N indirect bounces (default 0: direct\n"
    "                     illumination only, the evaluation mode)\n"
    "  --seed S           the image depends on it, never on --threads (default 1)\n"
    "  --threads N        worker threads (default: all cores)\n"
    "  --size WxH         image size (default: the scene's camera)\n"
    "  --blocks K         kd-tree blocks\n"
    "  -o, --output OUT   linear EXR (required)\n"
    "  --png OUT          also a tone-mapped PNG preview (--exposure EV, --tonemap T)\n"
    "  --sidecar PATH     where the JSON sidecar goes (default: OUT with .json);\n"
    "                     --no-sidecar writes none\n"
    "  --quiet            no progress bar and no summary line\n";

/* ---- progress bar (stderr, only when it is a terminal) -------------------------------- */

typedef struct progress {
    int enabled;
    double start, budget, last; /* budget > 0: time-based bar */
    int spp_done;
} progress;

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void progress_draw(progress *p, double fraction, int final)
{
    double t = now_seconds();
    if (!final && t - p->last < 0.1) return;
    p->last = t;
    if (fraction > 1.0) fraction = 1.0;
    char bar[41];
    int full = (int)(fraction * 40.0);
    for (int k = 0; k < 40; k++) bar[k] = k < full ? '#' : '.';
    bar[40] = '\0';
    fprintf(stderr, "\r  render [%s] %3d%%  %6.1f s  %d spp", bar, (int)(fraction * 100.0),
            t - p->start, p->spp_done);
    if (final) fputs("\r\033[K", stderr);
    fflush(stderr);
}

static void on_progress(void *user, int done, int total)
{
    progress *p = user;
    double f = p->budget > 0.0 ? (now_seconds() - p->start) / p->budget
                               : (total > 0 ? (double)done / total : 1.0);
    progress_draw(p, f, 0);
}

/* ---- the run --------------------------------------------------------------------------- */

static const char *estimator_name(const lumis_render_desc *d)
{
    return d->estimator == LUMIS_ESTIMATOR_BSDF    ? "bsdf"
           : d->estimator == LUMIS_ESTIMATOR_LIGHT ? "light"
                                                   : "mis";
}

/* OUT.exr -> OUT.json (or OUT + .json). */
static void sidecar_path(const char *out, char *buf, size_t cap)
{
    size_t n = strlen(out);
    const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    if (dot && (!slash || dot > slash) && dot != out && dot[-1] != '/') n = (size_t)(dot - out);
    snprintf(buf, cap, "%.*s.json", (int)n, out);
}

static int write_sidecar(const tool_render_opts *o, const lumis_render_desc *rd, const char *path,
                         const char *scene_label, const char *envspec, const lumis_envmap *env,
                         const lumis_sampler *smp, int objects, const lumis_camera *cam,
                         const tool_render_result *r)
{
    const lumis_render_stats *s = &r->stats;
    cJSON *j = cJSON_CreateObject(), *x;
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
    else
        snprintf(label, sizeof label, "direct illumination from the environment");
    cJSON_AddStringToObject(j, "label", label);
    cJSON_AddStringToObject(j, "scene", scene_label);
    cJSON_AddNumberToObject(j, "objects", objects);
    x = cJSON_AddObjectToObject(j, "environment");
    cJSON_AddStringToObject(x, "map", envspec);
    cJSON_AddNumberToObject(x, "width", lumis_envmap_width(env));
    cJSON_AddNumberToObject(x, "height", lumis_envmap_height(env));
    cJSON_AddNumberToObject(x, "rotation_deg", o->rotation_deg);
    cJSON_AddNumberToObject(x, "scale", o->scale);
    cJSON_AddStringToObject(
        j, "method",
        o->bsdf_only ? "bsdf" : lumis_sampler_method_name(lumis_sampler_get_method(smp)));
    cJSON_AddStringToObject(j, "estimator", estimator_name(rd));
    if (rd->estimator == LUMIS_ESTIMATOR_MIS)
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
    cJSON_AddNumberToObject(j, "passes", s->passes);
    cJSON_AddNumberToObject(j, "seed", (double)o->rd.seed);
    cJSON_AddNumberToObject(j, "threads", s->threads);
    cJSON_AddNumberToObject(j, "width", cam->width);
    cJSON_AddNumberToObject(j, "height", cam->height);
    x = cJSON_AddObjectToObject(j, "timings");
    cJSON_AddNumberToObject(x, "load_seconds", r->load_seconds);
    cJSON_AddNumberToObject(x, "sampler_build_seconds", lumis_sampler_build_ms(smp) / 1000.0);
    cJSON_AddNumberToObject(x, "scene_build_seconds", r->scene_seconds);
    cJSON_AddNumberToObject(x, "render_seconds", s->seconds);
    cJSON_AddNumberToObject(x, "total_seconds", r->total_seconds);
    x = cJSON_AddObjectToObject(j, "rays");
    double total = s->camera_rays + s->shadow_rays + s->bounce_rays;
    cJSON_AddNumberToObject(x, "camera", s->camera_rays);
    cJSON_AddNumberToObject(x, "shadow", s->shadow_rays);
    cJSON_AddNumberToObject(x, "bounce", s->bounce_rays);
    cJSON_AddNumberToObject(x, "total", total);
    cJSON_AddNumberToObject(x, "per_second", s->seconds > 0 ? total / s->seconds : 0);
    cJSON_AddNumberToObject(x, "shadow_per_second",
                            s->seconds > 0 ? s->shadow_rays / s->seconds : 0);
    x = cJSON_AddObjectToObject(j, "sampler");
    cJSON_AddStringToObject(x, "method", lumis_sampler_method_name(lumis_sampler_get_method(smp)));
    cJSON_AddNumberToObject(x, "build_ms", lumis_sampler_build_ms(smp));
    cJSON_AddNumberToObject(x, "table_bytes", (double)lumis_sampler_table_bytes(smp));
    cJSON_AddNumberToObject(x, "total_bytes", (double)lumis_sampler_total_bytes(smp));
    if (lumis_sampler_kdtree_blocks(smp) > 0) {
        cJSON_AddNumberToObject(x, "kdtree_blocks", lumis_sampler_kdtree_blocks(smp));
        cJSON_AddNumberToObject(x, "kdtree_alpha", lumis_sampler_kdtree_alpha(smp));
    }
    x = cJSON_AddObjectToObject(j, "outputs");
    cJSON_AddStringToObject(x, "exr", o->out);
    if (o->png)
        cJSON_AddStringToObject(x, "png", o->png);
    else
        cJSON_AddNullToObject(x, "png");
    int rc = tool_write_json(path, j);
    cJSON_Delete(j);
    return rc;
}

/* Runs passes until the budget: each pass is sized from the time per sample so far, so
 * the last one ends as close to the budget as the estimate allows. */
static lumis_status run_timed(lumis_render_job *job, double budget, progress *pg)
{
    lumis_render_stats s;
    int n = 1;
    for (;;) {
        lumis_status st = lumis_render_job_run(job, n);
        if (st != LUMIS_OK) return st;
        lumis_render_job_stats(job, &s);
        pg->spp_done = s.spp;
        double per = s.seconds / s.spp, left = budget - s.seconds;
        double next = left / per;
        if (next < 0.5 || s.spp >= (1 << 24)) return LUMIS_OK;
        n = next > s.spp ? s.spp : (int)(next + 0.5); /* at most double: estimates settle */
        if (n < 1) n = 1;
    }
}

int tool_render(const tool_render_opts *o, tool_render_result *r)
{
    memset(r, 0, sizeof *r);
    double t0 = now_seconds();
    lumis_scene_file *file = NULL;
    lumis_status st = o->scene_path ? lumis_scene_file_read(o->scene_path, &tool_errors, &file)
                                    : lumis_scene_builtin(o->scene_name, &tool_errors, &file);
    if (st != LUMIS_OK) return EXIT_RUNTIME;
    const char *envspec = o->envspec ? o->envspec : (file->env_map[0] ? file->env_map : "sky");
    float rotation = o->envspec ? o->rotation_deg : file->env_rotation_deg,
          scale = o->envspec ? o->scale : file->env_scale;
    lumis_camera cam = file->camera;
    if (o->width) cam.width = o->width, cam.height = o->height;
    lumis_envmap *env = NULL;
    lumis_sampler *smp = NULL;
    lumis_scene *scene = NULL;
    lumis_render_job *job = NULL;
    int rc = EXIT_RUNTIME;
    if (tool_make_sampler(envspec, rotation, scale, &o->sampler, &env, &smp) != LUMIS_OK) goto done;
    /* The map's loading alone: the sampler's build is reported on its own. */
    r->load_seconds = now_seconds() - t0 - lumis_sampler_build_ms(smp) / 1000.0;
    double t1 = now_seconds();
    if (lumis_scene_create(file->objects, file->object_count, &tool_errors, &scene) != LUMIS_OK)
        goto done;
    r->scene_seconds = now_seconds() - t1;

    progress pg = {0};
    pg.enabled = !o->quiet && isatty(STDERR_FILENO);
    pg.start = now_seconds();
    pg.budget = o->time_budget;
    lumis_render_desc rd = o->rd;
    rd.camera = &cam;
    rd.env = env;
    rd.sampler = smp;
    rd.errors = tool_errors;
    if (o->bsdf_only) rd.estimator = LUMIS_ESTIMATOR_BSDF;
    if (pg.enabled) {
        rd.progress = on_progress;
        rd.progress_user = &pg;
    }
    if (lumis_render_job_create(scene, &rd, &job) != LUMIS_OK) goto done;
    st = o->time_budget > 0.0 ? run_timed(job, o->time_budget, &pg)
                              : lumis_render_job_run(job, rd.spp ? rd.spp : 16);
    lumis_render_job_stats(job, &r->stats);
    pg.spp_done = r->stats.spp;
    if (pg.enabled) progress_draw(&pg, 1.0, 1);
    if (st != LUMIS_OK || lumis_render_job_image(job, &r->image) != LUMIS_OK) goto done;
    if (o->out && tool_write_image(o->out, r->image, NULL) != LUMIS_OK) goto done;
    if (o->png && tool_write_image(o->png, r->image, &o->png_options) != LUMIS_OK) goto done;
    r->total_seconds = now_seconds() - t0;
    r->sampler_build_ms = lumis_sampler_build_ms(smp);
    r->sampler_table_bytes = lumis_sampler_table_bytes(smp);
    const char *method =
        o->bsdf_only ? "bsdf" : lumis_sampler_method_name(lumis_sampler_get_method(smp));
    if (!o->quiet) {
        double rays = r->stats.camera_rays + r->stats.shadow_rays + r->stats.bounce_rays;
        fprintf(stderr,
                "lumis: rendered %dx%d at %d spp (%s%s) in %.3f s, %.3g rays/s (%.3g shadow "
                "rays/s), sampler %s built in %.2f ms\n",
                cam.width, cam.height, r->stats.spp,
                o->rd.max_bounces > 0 ? "path traced, " : "direct, ", estimator_name(&rd),
                r->stats.seconds, rays / r->stats.seconds, r->stats.shadow_rays / r->stats.seconds,
                method, r->sampler_build_ms);
    }
    rc = EXIT_OK;
    if (o->out && (!o->sidecar || o->sidecar[0])) {
        char path[4096];
        if (o->sidecar)
            snprintf(path, sizeof path, "%s", o->sidecar);
        else
            sidecar_path(o->out, path, sizeof path);
        rc = write_sidecar(o, &rd, path, o->scene_path ? o->scene_path : o->scene_name, envspec,
                           env, smp, file->object_count, &cam, r);
    }
done:
    if (rc != EXIT_OK) {
        lumis_image_destroy(r->image);
        r->image = NULL;
    }
    lumis_render_job_destroy(job);
    lumis_scene_destroy(scene);
    lumis_scene_file_destroy(file);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
    return rc;
}

int cmd_render(int argc, char **argv)
{
    tool_render_opts o;
    memset(&o, 0, sizeof o);
    o.scale = 1.0f;
    o.rd.seed = 1;
    o.argc = argc;
    o.argv = argv;
    const char *v;
    int spp_given = 0;
    for (int i = 1; i < argc; i++) {
        long x;
        double d;
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (tool_option(argc, argv, &i, "--scene", &v)) {
            if (!v) return tool_usage_error("render", "--scene needs a name");
            o.scene_name = v;
        } else if (tool_option(argc, argv, &i, "--env", &v)) {
            if (!v) return tool_usage_error("render", "--env needs a map");
            o.envspec = v;
        } else if (tool_option(argc, argv, &i, "--method", &v)) {
            if (v && strcmp(v, "bsdf") == 0)
                o.bsdf_only = 1;
            else if (!v || lumis_sampler_method_from_name(v, &o.sampler.method) != LUMIS_OK)
                return tool_usage_error("render", "--method must be a sampler name or 'bsdf'");
        } else if (tool_option(argc, argv, &i, "--mis", &v)) {
            if (v && strcmp(v, "balance") == 0)
                o.rd.power_heuristic = 0;
            else if (v && strcmp(v, "power") == 0)
                o.rd.power_heuristic = 1;
            else if (v && strcmp(v, "none") == 0)
                o.rd.estimator = LUMIS_ESTIMATOR_LIGHT;
            else
                return tool_usage_error("render", "--mis must be balance, power or none");
        } else if (tool_option(argc, argv, &i, "--light-samples", &v)) {
            if (!tool_parse_int(v, 1, 4096, &x))
                return tool_usage_error("render", "--light-samples needs a count in [1, 4096]");
            o.rd.light_samples = (int)x;
        } else if (tool_option(argc, argv, &i, "--bsdf-samples", &v)) {
            if (!tool_parse_int(v, 1, 4096, &x))
                return tool_usage_error("render", "--bsdf-samples needs a count in [1, 4096]");
            o.rd.bsdf_samples = (int)x;
        } else if (tool_option(argc, argv, &i, "--spp", &v)) {
            if (!tool_parse_int(v, 1, 1 << 20, &x))
                return tool_usage_error("render", "--spp needs a count in [1, 2^20]");
            o.rd.spp = (int)x;
            spp_given = 1;
        } else if (tool_option(argc, argv, &i, "--time", &v)) {
            if (!tool_parse_double(v, &d) || !(d > 0.0) || d > 1e6)
                return tool_usage_error("render", "--time needs seconds, more than 0");
            o.time_budget = d;
        } else if (tool_option(argc, argv, &i, "--bounces", &v)) {
            if (!tool_parse_int(v, 0, 1024, &x))
                return tool_usage_error("render", "--bounces needs a count in [0, 1024]");
            o.rd.max_bounces = (int)x;
        } else if (tool_option(argc, argv, &i, "--seed", &v)) {
            if (!tool_parse_int(v, 0, 2147483647L, &x))
                return tool_usage_error("render", "--seed needs an integer");
            o.rd.seed = (unsigned long long)x;
        } else if (tool_option(argc, argv, &i, "--threads", &v)) {
            if (!tool_parse_int(v, 1, 4096, &x))
                return tool_usage_error("render", "--threads needs a count");
            o.rd.threads = (int)x;
        } else if (tool_option(argc, argv, &i, "--blocks", &v)) {
            if (!tool_parse_int(v, 1, 1 << 24, &x))
                return tool_usage_error("render", "--blocks needs a count");
            o.sampler.kdtree_blocks = (int)x;
        } else if (tool_option(argc, argv, &i, "--size", &v)) {
            if (!tool_parse_size(v, &o.width, &o.height) || o.width > 16384 || o.height > 16384)
                return tool_usage_error("render", "--size needs WxH up to 16384x16384");
        } else if (tool_option(argc, argv, &i, "--output", &v) ||
                   tool_option(argc, argv, &i, "-o", &v)) {
            o.out = v;
        } else if (tool_option(argc, argv, &i, "--png", &v)) {
            o.png = v;
        } else if (tool_option(argc, argv, &i, "--sidecar", &v)) {
            if (!v || !*v) return tool_usage_error("render", "--sidecar needs a path");
            o.sidecar = v;
        } else if (strcmp(argv[i], "--no-sidecar") == 0) {
            o.sidecar = "";
        } else if (strcmp(argv[i], "--quiet") == 0) {
            o.quiet = 1;
        } else if (tool_option(argc, argv, &i, "--exposure", &v)) {
            if (!tool_parse_double(v, &d) || d < -64 || d > 64)
                return tool_usage_error("render", "--exposure needs stops");
            o.png_options.exposure_ev = (float)d;
        } else if (tool_option(argc, argv, &i, "--tonemap", &v)) {
            if (!v || lumis_tonemap_from_name(v, &o.png_options.tonemap) != LUMIS_OK)
                return tool_usage_error("render", "--tonemap must be clamp, reinhard or aces");
        } else if (argv[i][0] != '-' && !o.scene_path) {
            o.scene_path = argv[i];
        } else {
            return tool_usage_error("render", "unknown argument '%s'", argv[i]);
        }
    }
    if (!o.scene_name == !o.scene_path)
        return tool_usage_error("render", "give one scene: SCENE.json or --scene NAME");
    if (o.scene_name) {
        int known = 0;
        for (const char *const *n = lumis_scene_builtin_names(); *n; n++)
            known |= strcmp(*n, o.scene_name) == 0;
        if (!known)
            return tool_usage_error("render",
                                    "unknown scene '%s' (built in: spheres, bunny-plane, "
                                    "ward-aniso)",
                                    o.scene_name);
    }
    if (spp_given && o.time_budget > 0.0)
        return tool_usage_error("render", "give --spp or --time, not both");
    if (!o.out) return tool_usage_error("render", "no output file (-o OUT.exr)");
    tool_render_result r;
    int rc = tool_render(&o, &r);
    lumis_image_destroy(r.image);
    return rc;
}
