/* bench_render: the evaluation renderer's speed on the built-in bunny-plane scene.
 *
 * usage: bench_render [--quick] [--threads N] [--method NAME] [--methods A,B,...]
 *                     [--size WxH] [--spp N] [--shadow-size WxH] [--shadow-spp N]
 *                     [--runs R] [--json]
 *
 * 1. Shadow-ray throughput.  A small image (default 320x240, 16 spp) is rendered once on
 *    one thread while the internal shadow hook records every occlusion ray in order.  Then,
 *    on all threads (or --threads N), each run times: the integrator on the same image,
 *    samples and seed (it traces exactly the recorded rays); raw rtcOccluded1 on the recorded
 *    rays, in order, in contiguous chunks per thread, as render.c's occluded() issues them;
 *    and rtcOccluded16 on packets of 16 consecutive rays.  The integrator's figure charges
 *    all of its work (camera rays, sampling, BSDFs, accumulation) to its shadow rays, so its
 *    ratio to Embree's bounds the renderer's overhead from above.
 * 2. Full renders: bunny-plane at 1024x768, 16 spp, MIS with the balance heuristic, for
 *    each method (default inversion, inversion-guided, alias, kdtree, hierarchical).
 *
 * The environment is the CLI's default sky (1024x512, sun at 35 degrees, azimuth 60).
 * Every measurement is repeated (--runs; default 5 for the throughput, 3 for the full
 * renders) and reported as median, min and max; the runs of the three throughput
 * measurements are interleaved so that a noisy neighbour slows them alike. */
#include "bench_common.h"
#include "lumis/lumis.h"
#include "lumis/render.h"
#include "render/internal.h"

#include <cJSON.h>
#include <embree3/rtcore.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

const char bench_name[] = "bench_render";

#define SKY_W           1024
#define SKY_H           512
#define SKY_ELEVATION   35.0f /* the CLI's default sky (tools/app/load.h) */
#define SKY_AZIMUTH     60.0f
#define SEED            1ull /* the CLI's default seed */
#define MAX_METHODS     16
#define MAX_RUNS        1000
#define DEFAULT_METHODS "inversion,inversion-guided,alias,kdtree,hierarchical"

static const char usage[] =
    "usage: bench_render [--quick] [--threads N] [--method NAME] [--methods A,B,...]\n"
    "                    [--size WxH] [--spp N] [--shadow-size WxH] [--shadow-spp N]\n"
    "                    [--runs R] [--lights median-cut|variance-min] [--lights-k K] [--json]\n\n"
    "Times the evaluation renderer on the built-in bunny-plane scene under the default sky\n"
    "(1024x512, sun at 35 deg, azimuth 60): its shadow rays per second against Embree's raw\n"
    "rtcOccluded1 / rtcOccluded16 on the very same rays, and full renders per method.\n\n"
    "  --quick            small images and one run of each measurement (a smoke test)\n"
    "  --threads N        threads of every parallel measurement (default: all cores)\n"
    "  --method NAME      sampler of the throughput measurement (default inversion-guided);\n"
    "                     also the only method of the full renders unless --methods is given\n"
    "  --methods A,B,...  methods of the full renders (default\n"
    "                     " DEFAULT_METHODS ")\n"
    "  --size WxH         full render size (default 1024x768; --quick 320x240)\n"
    "  --spp N            full render samples per pixel (default 16; --quick 4)\n"
    "  --shadow-size WxH  throughput image size (default 320x240; --quick 160x120)\n"
    "  --shadow-spp N     throughput samples per pixel (default 16; --quick 4)\n"
    "  --runs R           runs of every measurement (default 5 for the throughput, 3 for\n"
    "                     the full renders; --quick 1)\n"
    "  --lights M         light the throughput measurement with a light set (median-cut or\n"
    "                     variance-min; its shadow rays go to Embree in 16-ray packets)\n"
    "                     instead of the sampler; no full renders unless --methods is given\n"
    "  --lights-k K       lights per set (default 64)\n"
    "  --json             print one JSON object instead of text\n\n"
    "Exit status: 0 success, 1 runtime error, 2 usage error.\n";

/* ---- errors and options -------------------------------------------------------------- */

static void print_error(void *user, lumis_status status, const char *message)
{
    (void)user;
    (void)status;
    fprintf(stderr, "bench_render: %s\n", message);
}

static const lumis_error_sink errors = {print_error, NULL};

/* Parses a comma-separated list of method names; returns the count, or 0 on error. */
static int parse_methods(const char *s, lumis_sampler_method *out)
{
    int n = 0;
    char name[64];
    while (*s) {
        size_t len = strcspn(s, ",");
        if (len == 0 || len >= sizeof name || n == MAX_METHODS) return 0;
        memcpy(name, s, len);
        name[len] = '\0';
        if (lumis_sampler_method_from_name(name, &out[n]) != LUMIS_OK) return 0;
        n++;
        s += len;
        if (*s == ',' && *++s == '\0') return 0;
    }
    return n;
}

/* ---- machine facts and statistics ----------------------------------------------------- */

static const char *embree_version(void)
{
#ifdef RTC_VERSION_STRING
    return RTC_VERSION_STRING;
#else
    return "unknown";
#endif
}

typedef struct stat3 {
    double median, min, max;
} stat3;

/* Sorts v[0..n) and returns its median, min and max. */
static stat3 summarize(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, bench_cmp_double);
    stat3 s;
    s.median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    s.min = v[0];
    s.max = v[n - 1];
    return s;
}

static cJSON *json_stat(cJSON *parent, const char *name, stat3 s)
{
    cJSON *o = cJSON_AddObjectToObject(parent, name);
    if (o) {
        cJSON_AddNumberToObject(o, "median", s.median);
        cJSON_AddNumberToObject(o, "min", s.min);
        cJSON_AddNumberToObject(o, "max", s.max);
    }
    return o;
}

/* ---- recorded shadow rays ------------------------------------------------------------- */

typedef struct sray {
    float o[3], d[3];
} sray;

typedef struct ray_list {
    sray *v;
    size_t n, cap;
    int oom;
} ray_list;

/* The shadow hook: appends the ray (called from the one rendering thread). */
static void collect(void *user, const float org[3], const float dir[3])
{
    ray_list *l = user;
    if (l->oom) return;
    if (l->n == l->cap) {
        size_t cap = l->cap ? 2 * l->cap : (size_t)1 << 16;
        sray *v = realloc(l->v, cap * sizeof *v);
        if (!v) {
            l->oom = 1;
            return;
        }
        l->v = v;
        l->cap = cap;
    }
    sray *r = &l->v[l->n++];
    memcpy(r->o, org, sizeof r->o);
    memcpy(r->d, dir, sizeof r->d);
}

/* rtcOccluded1 on rays[0..n), in order, each thread a contiguous chunk, each ray set up as
 * render.c's occluded() does.  Returns the seconds; *occluded counts the blocked rays. */
static double raw_occluded1(RTCScene scene, const sray *rays, size_t n, int threads,
                            size_t *occluded)
{
    size_t occ = 0;
    double t0 = omp_get_wtime();
#pragma omp parallel num_threads(threads) reduction(+ : occ)
    {
        const size_t t = (size_t)omp_get_thread_num(), nt = (size_t)omp_get_num_threads();
        const size_t a = n * t / nt, b = n * (t + 1) / nt;
        for (size_t k = a; k < b; k++) {
            struct RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            struct RTCRay r;
            r.org_x = rays[k].o[0];
            r.org_y = rays[k].o[1];
            r.org_z = rays[k].o[2];
            r.dir_x = rays[k].d[0];
            r.dir_y = rays[k].d[1];
            r.dir_z = rays[k].d[2];
            r.tnear = 0.0f;
            r.tfar = INFINITY;
            r.mask = 0xffffffffu;
            r.flags = 0;
            r.time = 0.0f;
            r.id = 0;
            rtcOccluded1(scene, &ctx, &r);
            occ += r.tfar < 0.0f;
        }
    }
    double dt = omp_get_wtime() - t0;
    *occluded = occ;
    return dt;
}

/* rtcOccluded16 on packets of 16 consecutive rays (the last one masked), each thread a
 * contiguous run of packets.  Returns the seconds; *occluded counts the blocked rays. */
static double raw_occluded16(RTCScene scene, const sray *rays, size_t n, int threads,
                             size_t *occluded)
{
    const size_t packets = (n + 15) / 16;
    size_t occ = 0;
    double t0 = omp_get_wtime();
#pragma omp parallel num_threads(threads) reduction(+ : occ)
    {
        const size_t t = (size_t)omp_get_thread_num(), nt = (size_t)omp_get_num_threads();
        const size_t a = packets * t / nt, b = packets * (t + 1) / nt;
        struct RTCRay16 r;
        int valid[16];
        for (size_t p = a; p < b; p++) {
            for (int i = 0; i < 16; i++) {
                const size_t k = 16 * p + (size_t)i;
                const sray *s = k < n ? &rays[k] : &rays[n - 1];
                valid[i] = k < n ? -1 : 0;
                r.org_x[i] = s->o[0];
                r.org_y[i] = s->o[1];
                r.org_z[i] = s->o[2];
                r.dir_x[i] = s->d[0];
                r.dir_y[i] = s->d[1];
                r.dir_z[i] = s->d[2];
                r.tnear[i] = 0.0f;
                r.tfar[i] = INFINITY;
                r.mask[i] = 0xffffffffu;
                r.flags[i] = 0;
                r.time[i] = 0.0f;
                r.id[i] = 0;
            }
            struct RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            rtcOccluded16(valid, scene, &ctx, &r);
            for (int i = 0; i < 16; i++) occ += valid[i] && r.tfar[i] < 0.0f;
        }
    }
    double dt = omp_get_wtime() - t0;
    *occluded = occ;
    return dt;
}

/* ---- the benchmark -------------------------------------------------------------------- */

typedef struct options {
    int threads, json, runs_shadow, runs_full;
    int width, height, spp; /* full renders */
    int shadow_width, shadow_height, spp_shadow;
    lumis_sampler_method method; /* throughput sampler */
    int lights;                  /* 0: the sampler; 1: median cut, 2: variance minimisation */
    int lights_k;
    lumis_sampler_method methods[MAX_METHODS];
    int method_count;
} options;

typedef struct shadow_result {
    size_t rays, occluded, integrator_shadow_rays;
    double camera_rays, bounce_rays;
    stat3 integ_shadow, integ_all, raw1, raw16; /* rays per second */
    double sampler_build_ms;
} shadow_result;

typedef struct full_result {
    lumis_sampler_method method;
    double build_ms;
    size_t table_bytes;
    stat3 seconds;
    double rays, shadow_rays; /* per render (the same every run) */
} full_result;

static lumis_render_desc make_desc(const lumis_camera *cam, const lumis_envmap *env,
                                   const lumis_sampler *smp, int spp, int threads)
{
    lumis_render_desc d;
    memset(&d, 0, sizeof d);
    d.camera = cam;
    d.lighting.env = env;
    d.lighting.sampler = smp;
    d.lighting.estimator = LUMIS_ESTIMATOR_MIS;
    d.power_heuristic = 0; /* balance */
    d.spp = spp;
    d.seed = SEED;
    d.threads = threads;
    d.errors = errors;
    return d;
}

/* One render; returns 0 or an exit code. */
static int render_once(const lumis_scene *scene, const lumis_render_desc *d,
                       lumis_render_stats *stats)
{
    lumis_image *img = NULL;
    lumis_status st = lumis_render(scene, d, &img, stats);
    lumis_image_destroy(img);
    if (st != LUMIS_OK) return bench_fail("render failed: %s", lumis_status_string(st));
    if (!(stats->seconds > 0.0)) return bench_fail("render took no measurable time");
    return 0;
}

static int bench_shadow(const options *o, const lumis_scene *scene, const lumis_camera *base,
                        const lumis_envmap *env, shadow_result *res)
{
    memset(res, 0, sizeof *res);
    lumis_sampler_desc sd;
    memset(&sd, 0, sizeof sd);
    sd.method = o->method;
    sd.errors = errors;
    lumis_sampler *smp = NULL;
    if (lumis_sampler_create(env, &sd, &smp) != LUMIS_OK)
        return bench_fail("cannot build the sampler");
    res->sampler_build_ms = lumis_sampler_build_ms(smp);
    lumis_camera cam = *base;
    cam.width = o->shadow_width;
    cam.height = o->shadow_height;
    RTCScene rtc = (RTCScene)lumis__scene_rtc(scene);
    ray_list list = {NULL, 0, 0, 0};
    lumis_light_set *set = NULL;
    double *v = calloc(4 * (size_t)o->runs_shadow, sizeof *v);
    int rc = 0;
    if (!v) {
        rc = bench_fail("out of memory");
        goto done;
    }

    /* Record the rays, in order, on one thread. */
    lumis_render_desc d = make_desc(&cam, env, smp, o->spp_shadow, 1);
    if (o->lights) {
        lumis_median_cut_desc md;
        memset(&md, 0, sizeof md);
        md.count = o->lights_k;
        md.errors = errors;
        lumis_status st = o->lights == 1 ? lumis_lights_median_cut(env, &md, &set)
                                         : lumis_lights_variance_min(env, &md, &set);
        if (st != LUMIS_OK) {
            rc = bench_fail("cannot build the light set");
            goto done;
        }
        d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET; /* the set lights it: no sampler */
        d.lighting.sampler = NULL;
        d.lighting.light_set.set = set;
    }
    lumis_render_stats stats;
    d.shadow_ray = collect;
    d.shadow_ray_user = &list;
    rc = render_once(scene, &d, &stats);
    d.shadow_ray = NULL;
    if (rc) goto done;
    if (list.oom) {
        rc = bench_fail("out of memory recording %.0f shadow rays", stats.shadow_rays);
        goto done;
    }
    if (list.n == 0) {
        rc = bench_fail("the integrator traced no shadow rays");
        goto done;
    }
    if ((double)list.n != stats.shadow_rays) {
        rc = bench_fail("recorded %zu shadow rays but the integrator counted %.0f", list.n,
                        stats.shadow_rays);
        goto done;
    }
    res->rays = list.n;

    /* The runs, interleaved: integrator, rtcOccluded1, rtcOccluded16. */
    d.threads = o->threads;
    double *integ_shadow = v, *integ_all = v + o->runs_shadow, *raw1 = v + 2 * o->runs_shadow,
           *raw16 = v + 3 * o->runs_shadow;
    for (int r = 0; r < o->runs_shadow; r++) {
        if ((rc = render_once(scene, &d, &stats))) goto done;
        if (stats.shadow_rays != (double)list.n) {
            rc = bench_fail("with %d threads the integrator traced %.0f shadow rays, not %zu",
                            o->threads, stats.shadow_rays, list.n);
            goto done;
        }
        integ_shadow[r] = stats.shadow_rays / stats.seconds;
        integ_all[r] = (stats.camera_rays + stats.shadow_rays + stats.bounce_rays) / stats.seconds;
        res->integrator_shadow_rays = (size_t)stats.shadow_rays;
        res->camera_rays = stats.camera_rays;
        res->bounce_rays = stats.bounce_rays;

        size_t occ1 = 0, occ16 = 0;
        double t1 = raw_occluded1(rtc, list.v, list.n, o->threads, &occ1);
        double t16 = raw_occluded16(rtc, list.v, list.n, o->threads, &occ16);
        RTCDevice dev = rtcGetSceneDevice(rtc);
        enum RTCError err = rtcGetDeviceError(dev);
        rtcReleaseDevice(dev);
        if (err != RTC_ERROR_NONE) {
            rc = bench_fail("Embree reported error %d during the raw occlusion runs", (int)err);
            goto done;
        }
        if (occ1 != occ16) {
            rc = bench_fail("rtcOccluded1 found %zu occluded rays but rtcOccluded16 %zu", occ1,
                            occ16);
            goto done;
        }
        if (r > 0 && occ1 != res->occluded) {
            rc = bench_fail("rtcOccluded1 found %zu occluded rays, %zu in an earlier run", occ1,
                            res->occluded);
            goto done;
        }
        res->occluded = occ1;
        if (!(t1 > 0.0) || !(t16 > 0.0)) {
            rc = bench_fail("a raw occlusion run took no measurable time");
            goto done;
        }
        raw1[r] = (double)list.n / t1;
        raw16[r] = (double)list.n / t16;
    }
    res->integ_shadow = summarize(integ_shadow, o->runs_shadow);
    res->integ_all = summarize(integ_all, o->runs_shadow);
    res->raw1 = summarize(raw1, o->runs_shadow);
    res->raw16 = summarize(raw16, o->runs_shadow);
done:
    free(list.v);
    free(v);
    lumis_light_set_destroy(set);
    lumis_sampler_destroy(smp);
    return rc;
}

static int bench_full(const options *o, const lumis_scene *scene, const lumis_camera *base,
                      const lumis_envmap *env, lumis_sampler_method method, full_result *res)
{
    memset(res, 0, sizeof *res);
    res->method = method;
    lumis_sampler_desc sd;
    memset(&sd, 0, sizeof sd);
    sd.method = method;
    sd.errors = errors;
    lumis_sampler *smp = NULL;
    if (lumis_sampler_create(env, &sd, &smp) != LUMIS_OK)
        return bench_fail("cannot build the %s sampler", lumis_sampler_method_name(method));
    res->build_ms = lumis_sampler_build_ms(smp);
    res->table_bytes = lumis_sampler_table_bytes(smp);
    lumis_camera cam = *base;
    cam.width = o->width;
    cam.height = o->height;
    lumis_render_desc d = make_desc(&cam, env, smp, o->spp, o->threads);
    double *t = calloc((size_t)o->runs_full, sizeof *t);
    int rc = t ? 0 : bench_fail("out of memory");
    for (int r = 0; r < o->runs_full && rc == 0; r++) {
        lumis_render_stats stats;
        rc = render_once(scene, &d, &stats);
        t[r] = stats.seconds;
        res->rays = stats.camera_rays + stats.shadow_rays + stats.bounce_rays;
        res->shadow_rays = stats.shadow_rays;
    }
    if (rc == 0) res->seconds = summarize(t, o->runs_full);
    free(t);
    lumis_sampler_destroy(smp);
    return rc;
}

/* ---- output --------------------------------------------------------------------------- */

typedef struct machine {
    int threads;
    long nproc;
    char cpu[256];
} machine;

static void print_text_header(const options *o, const machine *m)
{
    printf("bench_render: bunny-plane, default sky %dx%d (sun at %.0f deg, azimuth %.0f), "
           "MIS balance, seed %llu\n",
           SKY_W, SKY_H, (double)SKY_ELEVATION, (double)SKY_AZIMUTH, SEED);
    printf("machine: %s, nproc %ld, %d threads used, Embree %s\n\n", m->cpu, m->nproc, o->threads,
           embree_version());
    fflush(stdout);
}

static const char *light_source(const options *o, char *buf, size_t cap)
{
    if (o->lights)
        snprintf(buf, cap, "light set %s, K = %d, 8 interleaved sets (16-ray packets)",
                 o->lights == 1 ? "median-cut" : "variance-min", o->lights_k ? o->lights_k : 64);
    else
        snprintf(buf, cap, "sampler %s", lumis_sampler_method_name(o->method));
    return buf;
}

static void print_text_shadow(const options *o, const shadow_result *s)
{
    char src[128];
    printf("Shadow-ray throughput: %dx%d at %d spp, %s (sampler built in %.1f ms), %d run%s\n",
           o->shadow_width, o->shadow_height, o->spp_shadow, light_source(o, src, sizeof src),
           s->sampler_build_ms, o->runs_shadow, o->runs_shadow == 1 ? "" : "s");
    printf("  %zu shadow rays recorded on 1 thread (the integrator traces the same %zu on %d);\n"
           "  %zu occluded (%.1f %%), rtcOccluded1 and rtcOccluded16 agree; per render also "
           "%.0f camera rays\n",
           s->rays, s->integrator_shadow_rays, o->threads, s->occluded,
           100.0 * (double)s->occluded / (double)s->rays, s->camera_rays);
    printf("  %-36s %12s %12s %12s %14s\n", "rays per second", "median", "min", "max",
           "ns/ray/thread");
    const struct {
        const char *name;
        stat3 s;
    } rows[] = {{"integrator, shadow rays", s->integ_shadow},
                {"integrator, all rays (camera+shadow)", s->integ_all},
                {"raw rtcOccluded1, same rays", s->raw1},
                {"raw rtcOccluded16, same rays", s->raw16}};
    for (size_t k = 0; k < sizeof rows / sizeof rows[0]; k++)
        printf("  %-36s %12.4g %12.4g %12.4g %14.1f\n", rows[k].name, rows[k].s.median,
               rows[k].s.min, rows[k].s.max, 1e9 * o->threads / rows[k].s.median);
    double r1 = s->integ_shadow.median / s->raw1.median,
           r16 = s->integ_shadow.median / s->raw16.median;
    printf("  integrator shadow rays/s / raw rtcOccluded1 rays/s  = %.3f\n", r1);
    printf("  integrator shadow rays/s / raw rtcOccluded16 rays/s = %.3f\n", r16);
    printf("  Note: the integrator's figure charges ALL of its work - camera rays, light and\n"
           "  BSDF sampling, BSDF evaluation, MIS weights, accumulation - to its shadow rays,\n"
           "  so it understates the shadow rays' own speed: the ratio is a lower bound on the\n"
           "  renderer's efficiency, and 1/ratio - 1 = %.2f (against rtcOccluded1) an upper\n"
           "  bound on its overhead per shadow ray.\n\n",
           1.0 / r1 - 1.0);
    fflush(stdout);
}

static void print_text_full_header(const options *o)
{
    printf("Full renders: bunny-plane %dx%d at %d spp, MIS balance, %d run%s each\n", o->width,
           o->height, o->spp, o->runs_full, o->runs_full == 1 ? "" : "s");
    printf("  %-17s %9s %12s %9s %9s %9s %11s %11s\n", "method", "build ms", "table bytes",
           "median s", "min s", "max s", "rays/s", "shadow/s");
    fflush(stdout);
}

static void print_text_full(const full_result *f)
{
    printf("  %-17s %9.1f %12zu %9.3f %9.3f %9.3f %11.4g %11.4g\n",
           lumis_sampler_method_name(f->method), f->build_ms, f->table_bytes, f->seconds.median,
           f->seconds.min, f->seconds.max, f->rays / f->seconds.median,
           f->shadow_rays / f->seconds.median);
    fflush(stdout);
}

static int print_json(const options *o, const machine *m, const shadow_result *s,
                      const full_result *f, int nf)
{
    cJSON *j = cJSON_CreateObject();
    if (!j) return bench_fail("out of memory");
    cJSON_AddStringToObject(j, "bench", "render");
    cJSON_AddStringToObject(j, "scene", "bunny-plane");
    cJSON *x = cJSON_AddObjectToObject(j, "environment");
    if (x) {
        cJSON_AddStringToObject(x, "map", "sky");
        cJSON_AddNumberToObject(x, "width", SKY_W);
        cJSON_AddNumberToObject(x, "height", SKY_H);
        cJSON_AddNumberToObject(x, "sun_elevation_deg", SKY_ELEVATION);
        cJSON_AddNumberToObject(x, "sun_azimuth_deg", SKY_AZIMUTH);
    }
    cJSON_AddStringToObject(j, "estimator", "mis-balance");
    cJSON_AddNumberToObject(j, "seed", (double)SEED);
    x = cJSON_AddObjectToObject(j, "machine");
    if (x) {
        cJSON_AddNumberToObject(x, "threads", o->threads);
        cJSON_AddNumberToObject(x, "nproc", (double)m->nproc);
        cJSON_AddStringToObject(x, "cpu", m->cpu);
        cJSON_AddStringToObject(x, "embree", embree_version());
    }
    x = cJSON_AddObjectToObject(j, "shadow_throughput");
    if (x) {
        char size[64];
        snprintf(size, sizeof size, "%dx%d", o->shadow_width, o->shadow_height);
        cJSON_AddStringToObject(x, "size", size);
        cJSON_AddNumberToObject(x, "spp", o->spp_shadow);
        cJSON_AddStringToObject(x, "method", lumis_sampler_method_name(o->method));
        char src[128];
        cJSON_AddStringToObject(x, "lights", light_source(o, src, sizeof src));
        cJSON_AddNumberToObject(x, "runs", o->runs_shadow);
        cJSON_AddNumberToObject(x, "shadow_rays", (double)s->rays);
        cJSON_AddNumberToObject(x, "camera_rays", s->camera_rays);
        cJSON_AddNumberToObject(x, "occluded", (double)s->occluded);
        json_stat(x, "integrator_shadow_rays_per_s", s->integ_shadow);
        json_stat(x, "integrator_all_rays_per_s", s->integ_all);
        json_stat(x, "raw_occluded1_rays_per_s", s->raw1);
        json_stat(x, "raw_occluded16_rays_per_s", s->raw16);
        cJSON_AddNumberToObject(x, "ratio_vs_occluded1", s->integ_shadow.median / s->raw1.median);
        cJSON_AddNumberToObject(x, "ratio_vs_occluded16", s->integ_shadow.median / s->raw16.median);
        cJSON_AddStringToObject(x, "note",
                                "the integrator's rate charges all of its work (camera rays, "
                                "sampling, BSDF evaluation, accumulation) to its shadow rays: "
                                "the ratio is a lower bound on its efficiency, an upper bound "
                                "on its overhead");
    }
    x = cJSON_AddObjectToObject(j, "full_render");
    if (x) {
        char size[64];
        snprintf(size, sizeof size, "%dx%d", o->width, o->height);
        cJSON_AddStringToObject(x, "size", size);
        cJSON_AddNumberToObject(x, "spp", o->spp);
        cJSON_AddNumberToObject(x, "runs", o->runs_full);
        cJSON *a = cJSON_AddArrayToObject(x, "methods");
        for (int k = 0; a && k < nf; k++) {
            cJSON *e = cJSON_CreateObject();
            if (!e) break;
            cJSON_AddItemToArray(a, e);
            cJSON_AddStringToObject(e, "method", lumis_sampler_method_name(f[k].method));
            cJSON_AddNumberToObject(e, "build_ms", f[k].build_ms);
            cJSON_AddNumberToObject(e, "table_bytes", (double)f[k].table_bytes);
            json_stat(e, "seconds", f[k].seconds);
            cJSON_AddNumberToObject(e, "rays", f[k].rays);
            cJSON_AddNumberToObject(e, "rays_per_s", f[k].rays / f[k].seconds.median);
            cJSON_AddNumberToObject(e, "shadow_rays_per_s", f[k].shadow_rays / f[k].seconds.median);
        }
    }
    char *text = cJSON_Print(j);
    cJSON_Delete(j);
    if (!text) return bench_fail("out of memory");
    puts(text);
    free(text);
    return 0;
}

int main(int argc, char **argv)
{
    options o;
    memset(&o, 0, sizeof o);
    int quick = 0, runs = 0, width = 0, height = 0, spp = 0, sw = 0, sh = 0, sspp = 0;
    int method_set = 0;
    o.method = LUMIS_METHOD_INVERSION_GUIDED;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = NULL;
        if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            fputs(usage, stdout);
            return 0;
        } else if (strcmp(a, "--json") == 0) {
            o.json = 1;
        } else if (strcmp(a, "--quick") == 0) {
            quick = 1;
        } else if (tool_option(argc, argv, &i, "--threads", &v)) {
            if (!v || !bench_parse_int(v, 1, 1024, &o.threads))
                return bench_usage_error("--threads wants a count in 1..1024");
        } else if (tool_option(argc, argv, &i, "--method", &v)) {
            if (!v || lumis_sampler_method_from_name(v, &o.method) != LUMIS_OK)
                return bench_usage_error("--method wants a method name (e.g. alias), got '%s'",
                                         v ? v : "");
            method_set = 1;
        } else if (tool_option(argc, argv, &i, "--lights", &v)) {
            if (v && strcmp(v, "median-cut") == 0)
                o.lights = 1;
            else if (v && strcmp(v, "variance-min") == 0)
                o.lights = 2;
            else
                return bench_usage_error("--lights wants median-cut or variance-min, got '%s'",
                                         v ? v : "");
        } else if (tool_option(argc, argv, &i, "--lights-k", &v)) {
            if (!v || !bench_parse_int(v, 1, 65536, &o.lights_k))
                return bench_usage_error("--lights-k wants a count in 1..65536");
        } else if (tool_option(argc, argv, &i, "--methods", &v)) {
            if (!v || !(o.method_count = parse_methods(v, o.methods)))
                return bench_usage_error("--methods wants up to %d comma-separated method names, "
                                         "got '%s'",
                                         MAX_METHODS, v ? v : "");
        } else if (tool_option(argc, argv, &i, "--size", &v)) {
            if (!v || !bench_parse_size(v, &width, &height))
                return bench_usage_error("--size wants WxH (each 1..65536), got '%s'", v ? v : "");
        } else if (tool_option(argc, argv, &i, "--shadow-size", &v)) {
            if (!v || !bench_parse_size(v, &sw, &sh))
                return bench_usage_error("--shadow-size wants WxH (each 1..65536), got '%s'",
                                         v ? v : "");
        } else if (tool_option(argc, argv, &i, "--spp", &v)) {
            if (!v || !bench_parse_int(v, 1, 65536, &spp))
                return bench_usage_error("--spp wants a count in 1..65536");
        } else if (tool_option(argc, argv, &i, "--shadow-spp", &v)) {
            if (!v || !bench_parse_int(v, 1, 65536, &sspp))
                return bench_usage_error("--shadow-spp wants a count in 1..65536");
        } else if (tool_option(argc, argv, &i, "--runs", &v)) {
            if (!v || !bench_parse_int(v, 1, MAX_RUNS, &runs))
                return bench_usage_error("--runs wants a count in 1..%d", MAX_RUNS);
        } else {
            return bench_usage_error("unknown option '%s'", a);
        }
    }
    o.width = width ? width : quick ? 320 : 1024;
    o.height = width ? height : quick ? 240 : 768;
    o.spp = spp ? spp : quick ? 4 : 16;
    o.shadow_width = sw ? sw : quick ? 160 : 320;
    o.shadow_height = sw ? sh : quick ? 120 : 240;
    o.spp_shadow = sspp ? sspp : quick ? 4 : 16;
    o.runs_shadow = runs ? runs : quick ? 1 : 5;
    o.runs_full = runs ? runs : quick ? 1 : 3;
    if (!o.threads) o.threads = omp_get_max_threads();
    if (!o.method_count && o.lights) {
        /* --lights measures the light set's shadow rays; full renders only on request. */
    } else if (!o.method_count) {
        if (method_set) {
            o.methods[0] = o.method;
            o.method_count = 1;
        } else {
            o.method_count = parse_methods(DEFAULT_METHODS, o.methods);
        }
    }
    /* The renderer's limit: refuse early rather than after the first measurement. */
    if ((size_t)o.width * (size_t)o.height > ((size_t)1 << 28) ||
        (size_t)o.shadow_width * (size_t)o.shadow_height > ((size_t)1 << 28))
        return bench_usage_error("image sizes are limited to 2^28 pixels");

    machine m;
    m.threads = o.threads;
    m.nproc = sysconf(_SC_NPROCESSORS_ONLN);
    bench_cpu_model(m.cpu, sizeof m.cpu);

    /* The scene and the environment. */
    lumis_scene_file *file = NULL;
    lumis_scene *scene = NULL;
    lumis_image *sky = NULL;
    lumis_envmap *env = NULL;
    full_result full[MAX_METHODS];
    shadow_result shadow;
    int rc = 0;
    if (lumis_scene_builtin("bunny-plane", &errors, &file) != LUMIS_OK) {
        rc = bench_fail("cannot build the bunny-plane scene");
        goto done;
    }
    if (lumis_scene_create(file->objects, file->object_count, &errors, &scene) != LUMIS_OK) {
        rc = bench_fail("cannot build the Embree scene");
        goto done;
    }
    lumis_sky_desc skyd;
    memset(&skyd, 0, sizeof skyd);
    skyd.width = SKY_W;
    skyd.height = SKY_H;
    skyd.sun_elevation_deg = SKY_ELEVATION;
    skyd.sun_azimuth_deg = SKY_AZIMUTH;
    skyd.errors = errors;
    if (lumis_sky_create(&skyd, &sky) != LUMIS_OK ||
        lumis_envmap_from_image(sky, &env) != LUMIS_OK) {
        rc = bench_fail("cannot build the sky");
        goto done;
    }

    if (!o.json) print_text_header(&o, &m);
    if (!o.json)
        fprintf(stderr, "bench_render: shadow-ray throughput (%d run%s)...\n", o.runs_shadow,
                o.runs_shadow == 1 ? "" : "s");
    if ((rc = bench_shadow(&o, scene, &file->camera, env, &shadow))) goto done;
    if (!o.json) {
        print_text_shadow(&o, &shadow);
        if (o.method_count) print_text_full_header(&o);
    }
    for (int k = 0; k < o.method_count; k++) {
        if (!o.json)
            fprintf(stderr, "bench_render: full render, %s (%d run%s)...\n",
                    lumis_sampler_method_name(o.methods[k]), o.runs_full,
                    o.runs_full == 1 ? "" : "s");
        if ((rc = bench_full(&o, scene, &file->camera, env, o.methods[k], &full[k]))) goto done;
        if (!o.json) print_text_full(&full[k]);
    }
    if (o.json) rc = print_json(&o, &m, &shadow, full, o.method_count);
done:
    lumis_envmap_destroy(env);
    lumis_image_destroy(sky);
    lumis_scene_destroy(scene);
    lumis_scene_file_destroy(file);
    return rc;
}
