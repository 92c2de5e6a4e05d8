/* The pipeline every command shares: a map (file or procedural spec) -> an envmap -> a
 * sampler -> a render, its sidecar and its metrics.  The cmd_*.c files parse their options
 * and call these; none of them calls another command. */
#include "common.h"

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

/* ---- maps and samplers ------------------------------------------------------------------- */

void tool_warn_replaced(const char *what, lumis_replaced r)
{
    if (!lumis_replaced_total(r)) return;
    fprintf(stderr,
            "lumis: warning: %s: %llu channel values replaced by 0 (NaN %llu, Inf %llu, "
            "negative %llu)\n",
            what, (unsigned long long)lumis_replaced_total(r), (unsigned long long)r.nan,
            (unsigned long long)r.inf, (unsigned long long)r.negative);
}

lumis_status tool_load_image(const char *spec, lumis_image **out, lumis_read_info *info)
{
    lumis_read_options opt = {0};
    opt.errors = tool_errors;
    lumis_read_info local;
    if (!info) info = &local;
    const lumis_status st = lumis_map_read(spec, &opt, out, info);
    /* every command says what it replaced: a NaN read as 0 changes a render or a score */
    if (st == LUMIS_OK) tool_warn_replaced(spec, info->replaced);
    return st;
}

lumis_status tool_make_envmap(const char *spec, const lumis_image *preloaded, float rotation,
                              float scale, lumis_envmap **env, lumis_replaced *replaced)
{
    lumis_image *img = NULL;
    *env = NULL;
    if (!preloaded) {
        lumis_read_info info;
        lumis_status st = tool_load_image(spec, &img, &info);
        if (st == LUMIS_OK && replaced) *replaced = info.replaced;
        if (st != LUMIS_OK) return st;
        preloaded = img;
    }
    lumis_envmap_desc ed = {0};
    ed.pixels = preloaded->pixels;
    ed.width = preloaded->width;
    ed.height = preloaded->height;
    ed.rotation_deg = rotation;
    ed.scale = scale;
    ed.errors = tool_errors;
    lumis_status st = lumis_envmap_create(&ed, env);
    lumis_image_destroy(img);
    return st;
}

lumis_status tool_make_sampler(const char *spec, float rotation, float scale,
                               const lumis_sampler_desc *desc, lumis_envmap **env,
                               lumis_sampler **sampler)
{
    *sampler = NULL;
    lumis_status st = tool_make_envmap(spec, NULL, rotation, scale, env, NULL);
    if (st != LUMIS_OK) return st;
    lumis_sampler_desc d = *desc;
    d.errors = tool_errors;
    st = lumis_sampler_create(*env, &d, sampler);
    if (st != LUMIS_OK) {
        lumis_envmap_destroy(*env);
        *env = NULL;
    }
    return st;
}

/* ---- light-set methods and parameters: the library's (lumis/lights.h), with the CLI's
 * messages --------------------------------------------------------------------------- */

int tool_lights_method_known(const char *name)
{
    return lumis_lights_method_from_name(name) != 0;
}

int tool_lights_method_is_wu(const char *name)
{
    return lumis_lights_method_from_name(name) == LUMIS_LIGHTS_DECOMPOSITION;
}

const char *tool_lights_method_names(void)
{
    static char list[512];
    if (!list[0])
        for (const char *const *n = lumis_lights_method_names(); *n; n++) {
            if (list[0]) strcat(list, ", ");
            strcat(list, *n);
        }
    return list;
}

/* The library's message, kept for a usage error. */
static void keep_message(void *user, lumis_status status, const char *message)
{
    (void)status;
    snprintf((char *)user, 600, "%s", message);
}

int tool_light_params_parse(lumis_light_params *p, const char *cmd, const char *opt,
                            const char *text)
{
    char msg[600] = "";
    const lumis_error_sink sink = {keep_message, msg};
    if (lumis_light_params_parse(p, text, &sink) != LUMIS_OK)
        return tool_usage_error(cmd, "%s: %s", opt, msg);
    return EXIT_OK;
}

int tool_light_params_check(const lumis_light_params *p, const char *cmd, const char *opt,
                            const char *method)
{
    char msg[600] = "";
    const lumis_error_sink sink = {keep_message, msg};
    if (lumis_light_params_check(p, method, &sink) != LUMIS_OK)
        return tool_usage_error(cmd, "%s: %s", opt, msg);
    return EXIT_OK;
}

/* "auto" exposure: the stops that bring the reference's mean luminance to 0.18. */
/* What shapes an acquired preset: its name, the library's version and the numbers of its
 * layout and emitter (field by field: no padding bytes). */
static uint64_t preset_key(const char *name, lumis_luminaire_preset preset)
{
    lumis_luminaire_desc l;
    lumis_emitter_desc e;
    lumis_emitter_disk disks[16];
    uint64_t h = 0xcbf29ce484222325ull;
    h = tool_fnv(h, name, strlen(name));
    h = tool_fnv(h, LUMIS_VERSION_STRING, strlen(LUMIS_VERSION_STRING));
    if (lumis_luminaire_preset_get(preset, &l, &e, disks) != LUMIS_OK) return h;
    const double g[] = {l.delta,           l.grid_origin[0],  l.grid_origin[1],  l.grid_spacing[0],
                        l.grid_spacing[1], l.image_origin[0], l.image_origin[1], l.image_size[0],
                        l.image_size[1],   e.plate_z,         e.period[0],       e.period[1],
                        e.contrast,        e.tint.r,          e.tint.g,          e.tint.b};
    const int n[] = {(int)l.basis, l.grid[0],    l.grid[1],     l.width,
                     l.height,     e.disk_count, (int)e.pattern};
    h = tool_fnv(h, g, sizeof g);
    h = tool_fnv(h, n, sizeof n);
    for (int k = 0; k < e.disk_count && k < 16; k++) {
        const double dk[] = {disks[k].center[0],  disks[k].center[1],  disks[k].center[2],
                             disks[k].radius,     disks[k].radiance.r, disks[k].radiance.g,
                             disks[k].radiance.b, disks[k].exponent};
        h = tool_fnv(h, dk, sizeof dk);
    }
    return h;
}

/* Acquiring a preset takes seconds (the car: ~10 s), so what was acquired is kept under
 * $XDG_CACHE_HOME/lumis (else ~/.cache/lumis), one luminaire file per key, written
 * atomically and checked on read (its pixels' digest); LUMIS_NO_CACHE=1 turns it off.  A
 * cache that cannot be written or read is only a note: the preset is acquired. */
static lumis_status load_preset(const char *spec, lumis_luminaire_preset preset,
                                lumis_luminaire **out)
{
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME"),
               *off = getenv("LUMIS_NO_CACHE");
    char dir[2048] = "", path[2300] = "";
    if (!(off && *off && strcmp(off, "0") != 0)) {
        if (xdg && xdg[0] == '/')
            snprintf(dir, sizeof dir, "%s/lumis", xdg);
        else if (home && home[0] == '/')
            snprintf(dir, sizeof dir, "%s/.cache/lumis", home);
    }
    if (dir[0]) {
        snprintf(path, sizeof path, "%s/%s-%016llx.json", dir, spec + 7,
                 (unsigned long long)preset_key(spec + 7, preset));
        struct stat sb;
        if (stat(path, &sb) == 0) {
            lumis_luminaire_read_options ro = {0}; /* quiet: a bad entry is replaced */
            if (lumis_luminaire_read(path, &ro, out) == LUMIS_OK) return LUMIS_OK;
            fprintf(stderr, "lumis: the cached %s (%s) does not read back: acquiring it again\n",
                    spec, path);
        }
    }
    fprintf(stderr, "lumis: acquiring %s from its emitter (seconds)%s%s ...\n", spec,
            dir[0] ? "; kept for later runs in " : "", dir);
    lumis_status st = lumis_luminaire_preset_create(preset, LUMIS_BASIS_DEFAULT, &tool_errors, out);
    if (st != LUMIS_OK || !dir[0]) return st;
    /* the cache folder, then the luminaire (its manifest last) */
    if (tool_make_dir(dir) != EXIT_OK) {
        fprintf(stderr, "lumis: note: could not cache %s in %s\n", spec, dir);
        return LUMIS_OK;
    }
    lumis_luminaire_write_options wo = {0};
    wo.image_format = LUMIS_FORMAT_PFM; /* lossless and fast to read */
    if (lumis_luminaire_write(path, *out, &wo) != LUMIS_OK)
        fprintf(stderr, "lumis: note: could not cache %s in %s\n", spec, dir);
    return LUMIS_OK;
}

lumis_status tool_scene_load_preset(void *user, const char *spec, lumis_luminaire **out)
{
    (void)user;
    return tool_load_luminaire(spec, out);
}

lumis_status tool_load_luminaire(const char *spec, lumis_luminaire **out)
{
    if (strncmp(spec, "preset:", 7) == 0) {
        lumis_luminaire_preset preset;
        if (lumis_luminaire_preset_from_name(spec + 7, &preset) != LUMIS_OK) {
            tool_runtime_error("%s: unknown preset (preset:car, preset:bike or preset:small)",
                               spec);
            return LUMIS_ERR_INVALID_ARGUMENT;
        }
        return load_preset(spec, preset, out);
    }
    lumis_luminaire_read_options ro = {0};
    ro.errors = tool_errors;
    return lumis_luminaire_read(spec, &ro, out);
}

float tool_auto_exposure(const lumis_image *ref)
{
    double sum = 0.0;
    const size_t n = (size_t)ref->width * (size_t)ref->height;
    for (size_t p = 0; p < n; p++) {
        const float *q = ref->pixels + 3 * p;
        sum += 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
    }
    double mean = sum / (double)n;
    return mean > 0.0 ? (float)log2(0.18 / mean) : 0.0f;
}

/* ---- map statistics (lumis info, lumis demo) ---------------------------------------- */

static int print_json(FILE *f, const char *name, const lumis_envmap_stats *s,
                      const lumis_read_info *info)
{
    cJSON *o = cJSON_CreateObject();
    if (!o) return EXIT_RUNTIME;
    cJSON_AddStringToObject(o, "file", name);
    cJSON_AddStringToObject(o, "format",
                            info->format ? lumis_format_name(info->format) : "procedural");
    cJSON_AddNumberToObject(o, "width", s->width);
    cJSON_AddNumberToObject(o, "height", s->height);
    cJSON_AddNumberToObject(o, "min_luminance", s->min_luminance);
    cJSON_AddNumberToObject(o, "avg_luminance", s->avg_luminance);
    cJSON_AddNumberToObject(o, "max_luminance", s->max_luminance);
    cJSON_AddNumberToObject(o, "dynamic_range", s->dynamic_range);
    cJSON_AddNumberToObject(o, "power", s->power);
    cJSON *rgb = cJSON_CreateDoubleArray(s->power_rgb, 3);
    cJSON_AddItemToObject(o, "power_rgb", rgb);
    cJSON_AddNumberToObject(o, "top1_share", s->top1_share);
    cJSON_AddNumberToObject(o, "top01_share", s->top01_share);
    cJSON_AddNumberToObject(o, "replaced", (double)lumis_replaced_total(info->replaced));
    cJSON_AddNumberToObject(o, "replaced_nan", (double)info->replaced.nan);
    cJSON_AddNumberToObject(o, "replaced_inf", (double)info->replaced.inf);
    cJSON_AddNumberToObject(o, "replaced_negative", (double)info->replaced.negative);
    char *text = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    if (!text) return EXIT_RUNTIME;
    fprintf(f, "%s\n", text);
    cJSON_free(text);
    return EXIT_OK;
}

int tool_print_info(FILE *f, const char *name, const lumis_image *image,
                    const lumis_read_info *info, int json)
{
    lumis_envmap_stats s;
    lumis_status st = lumis_equirect_stats(image->pixels, image->width, image->height, 1.0f, &s);
    if (st != LUMIS_OK) return tool_runtime_error("%s: %s", name, lumis_status_string(st));
    if (json) return print_json(f, name, &s, info);

    fprintf(f, "file           %s (%s)\n", name,
            info->format ? lumis_format_name(info->format) : "procedural");
    fprintf(f, "resolution     %d x %d\n", s.width, s.height);
    fprintf(f, "luminance      min %.6g  avg %.6g  max %.6g\n", s.min_luminance, s.avg_luminance,
            s.max_luminance);
    if (s.dynamic_range > 0.0)
        fprintf(f, "dynamic range  %.4g : 1 (max / smallest positive)\n", s.dynamic_range);
    else
        fprintf(f, "dynamic range  - (the map is black)\n");
    fprintf(f, "power (Y)      %.6g  (sum Y Omega)\n", s.power);
    fprintf(f, "power (RGB)    %.6g %.6g %.6g\n", s.power_rgb[0], s.power_rgb[1], s.power_rgb[2]);
    fprintf(f, "top 1%% share   %.4f\n", s.top1_share);
    fprintf(f, "top 0.1%% share %.4f\n", s.top01_share);
    fprintf(f, "black pixels   %llu\n", (unsigned long long)s.black_pixels);
    fprintf(f, "replaced       %llu channel values (NaN %llu, Inf %llu, negative %llu)\n",
            (unsigned long long)lumis_replaced_total(info->replaced),
            (unsigned long long)info->replaced.nan, (unsigned long long)info->replaced.inf,
            (unsigned long long)info->replaced.negative);
    if (s.power == 0.0) fprintf(f, "note           the map is black: it emits no light\n");
    return EXIT_OK;
}

/* ---- metrics (lumis compare, lumis bench) ---------------------------------------------- */

void tool_metrics_json(const tool_metrics *m, cJSON *o)
{
    cJSON_AddNumberToObject(o, "rmse", m->err.rmse);
    cJSON_AddNumberToObject(o, "mse", m->err.mse);
    cJSON_AddNumberToObject(o, "relmse", m->err.relmse);
    cJSON_AddNumberToObject(o, "relmse_epsilon", m->err.relmse_epsilon);
    if (isfinite(m->err.psnr))
        cJSON_AddNumberToObject(o, "psnr", m->err.psnr);
    else
        cJSON_AddNullToObject(o, "psnr"); /* identical images */
    cJSON_AddNumberToObject(o, "psnr_peak", m->err.psnr_peak);
    cJSON_AddStringToObject(o, "psnr_domain",
                            "linear HDR values, all channels; peak = the reference's largest "
                            "channel value");
    cJSON_AddNumberToObject(o, "lab_delta_e", m->lab_delta_e);
    cJSON_AddStringToObject(o, "lab_domain",
                            "CIE76, D65; linear values x 2^exposure_ev clamped to [0, 1]");
    cJSON_AddNumberToObject(o, "flip_ldr", m->flip_ldr);
    if (m->has_flip_hdr) {
        cJSON_AddNumberToObject(o, "flip_hdr", m->flip_hdr);
        cJSON_AddNumberToObject(o, "flip_hdr_start_exposure", m->flip_start);
        cJSON_AddNumberToObject(o, "flip_hdr_stop_exposure", m->flip_stop);
    } else {
        cJSON_AddNullToObject(o, "flip_hdr");
    }
    cJSON_AddNumberToObject(o, "pixels_per_degree", m->ppd);
    cJSON_AddNumberToObject(o, "exposure_ev", m->exposure_ev);
}

int tool_compare_images(const lumis_image *ref, const lumis_image *test, float exposure_ev,
                        double ppd, int hdr_flip, tool_metrics *m, float *flip_map)
{
    memset(m, 0, sizeof *m);
    m->exposure_ev = exposure_ev;
    m->ppd = ppd > 0.0 ? ppd : LUMIS_FLIP_DEFAULT_PPD;
    lumis_metric_options mo = {0};
    mo.exposure_ev = exposure_ev;
    mo.errors = tool_errors;
    if (lumis_image_errors(ref, test, &mo, &m->err) != LUMIS_OK ||
        lumis_lab_delta_e(ref, test, &mo, NULL, &m->lab_delta_e) != LUMIS_OK)
        return EXIT_RUNTIME;
    lumis_flip_options fo = {0};
    fo.pixels_per_degree = m->ppd;
    fo.errors = tool_errors;
    /* LDR-FLIP on the exposed values (the library clamps to [0, 1]). */
    lumis_image *a = NULL, *b = NULL;
    const lumis_image *ra = ref, *tb = test;
    if (exposure_ev != 0.0f) {
        const size_t n = 3 * (size_t)ref->width * (size_t)ref->height;
        const float k = exp2f(exposure_ev);
        if (lumis_image_create(ref->width, ref->height, &a) != LUMIS_OK ||
            lumis_image_create(test->width, test->height, &b) != LUMIS_OK) {
            lumis_image_destroy(a);
            return tool_runtime_error("compare: out of memory");
        }
        for (size_t i = 0; i < n; i++) {
            a->pixels[i] = ref->pixels[i] * k;
            b->pixels[i] = test->pixels[i] * k;
        }
        ra = a;
        tb = b;
    }
    /* The map gets LDR-FLIP's errors; HDR-FLIP overwrites them when it runs. */
    lumis_status st = lumis_flip_ldr(ra, tb, &fo, flip_map, &m->flip_ldr);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
    if (st != LUMIS_OK) return EXIT_RUNTIME;
    if (hdr_flip) {
        lumis_flip_hdr_result hr;
        lumis_flip_options quiet = fo;
        memset(&quiet.errors, 0, sizeof quiet.errors);
        st = lumis_flip_hdr(ref, test, &quiet, flip_map, NULL, &hr);
        if (st == LUMIS_ERR_INVALID_ARGUMENT) {
            /* A reference mostly black (median luminance 0) has no default exposure range:
             * the other metrics still stand. */
            fprintf(stderr, "lumis: warning: HDR-FLIP skipped: the reference's median "
                            "luminance is 0, so it has no default exposure range\n");
            return EXIT_OK;
        }
        if (st != LUMIS_OK) return tool_runtime_error("HDR-FLIP: %s", lumis_status_string(st));
        m->flip_hdr = hr.mean;
        m->flip_start = hr.start_exposure;
        m->flip_stop = hr.stop_exposure;
        m->has_flip_hdr = 1;
    }
    return EXIT_OK;
}

int tool_write_flip_map(const char *path, const float *map, int width, int height)
{
    lumis_image *rgb = NULL;
    if (lumis_flip_colormap(map, width, height, &rgb) != LUMIS_OK)
        return tool_runtime_error("%s: cannot colour the error map", path);
    /* The colour map is display-referred already: written without a tone map. */
    int rc = tool_write_image(path, rgb, NULL) == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
    lumis_image_destroy(rgb);
    return rc;
}

/* ---- progress bar (stderr, only when it is a terminal) -------------------------------- */

typedef struct progress {
    int enabled;
    double start, budget, last; /* budget > 0: time-based bar */
    int spp_done;
} progress;

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

double tool_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof(double), cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double tool_now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void progress_draw(progress *p, double fraction, int final)
{
    double t = tool_now_seconds();
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
    double f = p->budget > 0.0 ? (tool_now_seconds() - p->start) / p->budget
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

void tool_sidecar_path(const char *out, char *buf, size_t cap)
{
    size_t n = strlen(out);
    const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
    if (dot && (!slash || dot > slash) && dot != out && dot[-1] != '/') n = (size_t)(dot - out);
    snprintf(buf, cap, "%.*s.json", (int)n, out);
}

static int write_sidecar(const tool_render_opts *o, const lumis_render_desc *rd, const char *path,
                         const char *scene_label, const char *envspec, const lumis_envmap *env,
                         const lumis_sampler *smp, const lumis_light_set *lights,
                         const lumis_scene_file *file, const lumis_camera *cam,
                         const tool_render_result *r)
{
    const int objects = file->object_count, lum = rd->luminaires != NULL;
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
    else if (lum)
        snprintf(label, sizeof label, "direct illumination from light-field luminaires");
    else
        snprintf(label, sizeof label, "direct illumination from the environment");
    cJSON_AddStringToObject(j, "label", label);
    cJSON_AddStringToObject(j, "scene", scene_label);
    cJSON_AddNumberToObject(j, "objects", objects);
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
    cJSON_AddStringToObject(j, "method",
                            lum         ? lumis_luminaire_strategy_name(rd->luminaires->strategy)
                            : o->lights ? o->lights
                            : o->bsdf_only
                                ? "bsdf"
                                : lumis_sampler_method_name(lumis_sampler_get_method(smp)));
    cJSON_AddStringToObject(j, "estimator",
                            lum      ? "luminaire"
                            : lights ? "light set"
                                     : estimator_name(rd));
    if (lum) {
        const lumis_luminaire_lighting *ll = rd->luminaires;
        x = cJSON_AddObjectToObject(j, "luminaires");
        cJSON_AddNumberToObject(x, "count", ll->count);
        cJSON_AddStringToObject(x, "strategy", lumis_luminaire_strategy_name(ll->strategy));
        cJSON_AddNumberToObject(x, "budget", ll->budget ? ll->budget : 32);
        cJSON_AddNumberToObject(x, "k_max", ll->k_max);
        cJSON_AddStringToObject(x, "search", lumis_luminaire_search_name(ll->search));
        cJSON_AddNumberToObject(x, "depth", ll->depth);
        cJSON_AddStringToObject(x, "visibility", lumis_visibility_name(ll->visibility));
        cJSON_AddStringToObject(x, "sequence", lumis_sequence_name(ll->sequence));
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
    if (lights) {
        const lumis_light_set_info *li = lumis_light_set_get_info(lights);
        x = cJSON_AddObjectToObject(j, "lights");
        cJSON_AddStringToObject(x, "method", o->lights);
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
        if (r->lights_pilot_seconds > 0.0) {
            /* --time: K chosen from two pilot renders (seconds per sample at K = 16, 64). */
            cJSON *pl = cJSON_AddObjectToObject(x, "k_from_time");
            cJSON_AddItemToObject(pl, "pilot_k", cJSON_CreateIntArray(r->lights_pilot_k, 2));
            cJSON_AddItemToObject(pl, "pilot_seconds_per_spp",
                                  cJSON_CreateDoubleArray(r->lights_pilot_per_spp, 2));
            cJSON_AddItemToObject(pl, "pilot_seconds_once",
                                  cJSON_CreateDoubleArray(r->lights_pilot_once, 2));
            cJSON_AddNumberToObject(pl, "k_from_pilots", r->lights_pilot_chosen);
            cJSON_AddNumberToObject(pl, "pilot_wall_seconds", r->lights_pilot_seconds);
            cJSON_AddNumberToObject(pl, "spp", r->stats.spp);
            cJSON_AddBoolToObject(pl, "rerendered", r->lights_retried);
        }
    } else {
        cJSON_AddNullToObject(j, "lights");
    }
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
    { /* the code paths this CPU ran: a result is reproduced with the same ones */
        const char *embree = getenv("LUMIS_EMBREE_CONFIG");
        cJSON_AddStringToObject(j, "simd_variant", lumis_simd_variant());
        cJSON_AddStringToObject(j, "embree_config", embree && *embree ? embree : "default");
    }
    cJSON_AddNumberToObject(j, "width", cam->width);
    cJSON_AddNumberToObject(j, "height", cam->height);
    x = cJSON_AddObjectToObject(j, "timings");
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
    x = cJSON_AddObjectToObject(j, "rays");
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
    /* A scene with luminaires is lit by them alone; its camera rays that escape see black. */
    const int lum = file->luminaire_count > 0;
    if (!lum && file->luminaires_listed > 0) { /* not the default sky instead */
        lumis_scene_file_destroy(file);
        lumis_luminaire_destroy(replacement);
        return tool_runtime_error("%s: every luminaire of the scene has intensity 0: nothing "
                                  "lights it (give one an intensity, or list none to light it "
                                  "by a map)",
                                  o->scene_path ? o->scene_path : o->scene_name);
    }
    if (lum && file->env_map[0])
        fprintf(stderr,
                "lumis: warning: %s: the scene's environment (%s) is ignored: a scene with "
                "luminaires is lit by them alone\n",
                o->scene_path ? o->scene_path : o->scene_name, file->env_map);
    const char *clash = o->envspec     ? "--env"
                        : o->lights    ? "--lights"
                        : o->bsdf_only ? "--method bsdf"
                                       : NULL;
    if (lum && clash) {
        lumis_scene_file_destroy(file);
        lumis_luminaire_destroy(replacement);
        return tool_usage_error(cmd, "%s: the scene is lit by its luminaires, not by a map", clash);
    }
    if (!lum && o->lum_option) {
        lumis_scene_file_destroy(file);
        lumis_luminaire_destroy(replacement);
        return tool_usage_error(
            cmd, "%s applies to scenes with luminaires (e.g. --scene headlight)", o->lum_option);
    }
    if (o->luminaire && !lum) {
        lumis_scene_file_destroy(file);
        lumis_luminaire_destroy(replacement);
        return tool_usage_error(cmd,
                                "--luminaire %s: the scene places no luminaire (try --scene "
                                "headlight)",
                                o->luminaire);
    }
    const char *envspec = lum          ? NULL
                          : o->envspec ? o->envspec
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
    tool_files_output(&files, "sidecar", sidecar, TOOL_OUT_FILE);
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
    if (!lum && preloaded && !o->envspec) { /* the scene file's map: counted by its reader */
        r->env_replaced = file->env_info.replaced;
        tool_warn_replaced(envspec, r->env_replaced);
    } else if (!lum && preloaded) { /* the caller's (lumis bench): it warned when it read it */
        r->env_replaced = o->env_image_replaced;
    }
    if (!lum &&
        tool_make_envmap(envspec, preloaded, rotation, scale, &env, &r->env_replaced) != LUMIS_OK)
        goto done;
    lumis_sampler_desc sd = o->sampler;
    sd.errors = tool_errors;
    /* A light set or luminaires light the scene by themselves: no sampler is built. */
    if (!lum && !o->lights && lumis_sampler_create(env, &sd, &smp) != LUMIS_OK) goto done;
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
    rd.env = env;
    rd.sampler = smp;
    rd.light_set = lights;
    rd.errors = tool_errors;
    /* --luminaire: every placed luminaire of the scene replaced by that one. */
    for (int k = 0; replacement && k < file->luminaire_count; k++)
        file->luminaires[k].luminaire = replacement;
    lumis_luminaire_lighting lighting = o->lum;
    lighting.instances = file->luminaires;
    lighting.count = file->luminaire_count;
    rd.luminaires = lum ? &lighting : NULL;
    if (o->bsdf_only) rd.estimator = LUMIS_ESTIMATOR_BSDF;
    if (pg.enabled) {
        rd.progress = on_progress;
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
    sess.lights_params = &o->lights_params;
    sess.upsample = o->upsample;
    sess.time_budget = o->time_budget;
    sess.spent = smp ? lumis_sampler_build_ms(smp) / 1000.0 : 0.0;
    sess.timed_spp = TOOL_LIGHTS_TIMED_SPP;
    sess.pass_done = on_pass;
    sess.pass_done_user = &pg;
    lumis_session_result sr;
    st = lumis_render_session(scene, &sess, &r->image, &sr);
    lights = sr.light_set;
    r->stats = sr.stats;
    r->prep_seconds = sr.prep_seconds;
    r->budget_used_seconds = sr.budget_used_seconds;
    r->lights_pilot_seconds = sr.pilot_seconds;
    for (int p = 0; p < 2; p++) {
        r->lights_pilot_k[p] = sr.pilot_k[p];
        r->lights_pilot_per_spp[p] = sr.pilot_per_spp[p];
        r->lights_pilot_once[p] = sr.pilot_once[p];
    }
    r->lights_pilot_chosen = sr.pilot_chosen;
    r->lights_retried = sr.retried;
    const int factor = sr.upsample;
    r->upsample = factor;
    pg.spp_done = r->stats.spp;
    if (pg.enabled) progress_draw(&pg, 1.0, 1);
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
        int lw = 0, lh = 0;
        lumis_light_set_labels(lights, &lw, &lh);
        r->sampler_build_ms = lumis_light_set_get_info(lights)->build_ms;
        r->sampler_table_bytes = (size_t)lw * (size_t)lh * sizeof(int32_t) +
                                 (size_t)lumis_light_set_sets(lights) *
                                     (size_t)lumis_light_set_get_info(lights)->count *
                                     sizeof(lumis_light);
    }
    const char *method = lum            ? lumis_luminaire_strategy_name(o->lum.strategy)
                         : o->lights    ? o->lights
                         : o->bsdf_only ? "bsdf"
                                        : lumis_sampler_method_name(lumis_sampler_get_method(smp));
    if (!o->quiet) {
        double rays = r->stats.camera_rays + r->stats.shadow_rays + r->stats.bounce_rays;
        char how[160];
        if (lum)
            snprintf(how, sizeof how, "%d luminaire%s: %s, K = %d, %s visibility, %s",
                     file->luminaire_count, file->luminaire_count > 1 ? "s" : "", method,
                     o->lum.budget ? o->lum.budget : 32, lumis_visibility_name(o->lum.visibility),
                     lumis_sequence_name(o->lum.sequence));
        else if (lights)
            snprintf(how, sizeof how, "light set %s, %d lights x %d sets built in %.2f ms",
                     o->lights, lumis_light_set_get_info(lights)->count,
                     lumis_light_set_sets(lights), lumis_light_set_get_info(lights)->build_ms);
        else
            snprintf(how, sizeof how, "%s, sampler %s built in %.2f ms", estimator_name(&rd),
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
                    "sets, K's pilots) + %.3f s rendering = %.3f s\n",
                    o->time_budget, r->prep_seconds, r->budget_used_seconds - r->prep_seconds,
                    r->budget_used_seconds);
    }
    rc = EXIT_OK;
    if (sidecar[0])
        rc = write_sidecar(o, &rd, sidecar, o->scene_path ? o->scene_path : o->scene_name, envspec,
                           env, smp, lights, file, &cam, r);
done:
    if (rc != EXIT_OK) {
        lumis_image_destroy(r->image);
        r->image = NULL;
    }
    lumis_scene_destroy(scene);
    lumis_scene_file_destroy(file);
    lumis_luminaire_destroy(replacement);
    lumis_sampler_destroy(smp);
    lumis_light_set_destroy(lights);
    lumis_envmap_destroy(env);
    return rc;
}
