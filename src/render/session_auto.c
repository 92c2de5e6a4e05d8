/* A session's automatic estimator (lumis_session_desc.auto_estimator): how the map lights the
 * scene -- sampled with MIS, its median-cut regions as strata (K = 16, 32, 64), and, on a
 * sun-dominated map, the image sun split off with MIS or strata on the residual -- chosen by
 * pilot renders of the scene itself.
 *
 * Each candidate renders a small copy of the image (a sixteenth of its pixels, between
 * AUTO_MIN_PIXELS and AUTO_MAX_PIXELS) twice, independently; the two halves' difference
 * estimates each pixel's variance without a reference, (A - B)^2 / 2 for one half.  Over the
 * pixels, relative to a common mean image (every measured candidate's pilots together) as the
 * relMSE weighs them:
 *
 *     v_c = mean_p n_c (A_p - B_p)^2 / 2 / (m_p^2 + eps)     (eps = 0.01, lumis_compare's)
 *
 * is candidate c's relMSE at one sample per pixel (n_c samples in each half).  Its cost,
 * t_c seconds a sample per pixel at the image's size, is the pilot's time scaled by the
 * pixels.  With a time budget the render has L seconds left after the pilots, so c would
 * reach relMSE v_c t_c / L; without one, c reaches relMSE e in v_c t_c / e seconds.  Either
 * way the smallest v_c t_c wins.
 *
 * The pilots are capped (AUTO_CAP): they run in a fixed order (strata K = 32, then MIS, the
 * sun's two, K = 16, K = 64), each only if the pilots' time so far and its predicted cost stay
 * within AUTO_CAP of the budget (--time) or of the render's predicted time at the prior
 * (--spp); without a budget a render of fewer samples than 4 / AUTO_CAP pilot halves skips
 * them.  No pilot pair measured: the prior, strata K = 32 (the convergence suite's best on
 * average). */
#include "lumis/render.h"
#include "lumis/sun.h"

#include "../core/internal.h"
#include "camera.h"
#include "internal.h"
#include "scene.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#define AUTO_MIN_PIXELS 1200 /* the pilots' pixels at least (40 x 30), unless the image's */
#define AUTO_MAX_PIXELS 4800 /* and at most (80 x 60) */
#define AUTO_MAX_HALF   64   /* most samples per pixel in a pilot's half */
#define AUTO_CAP        0.15 /* the pilots' share of the budget (or of the render) at most */
#define AUTO_SUN_SHARE  0.5  /* sun-dominated: >= half the power ... */
#define AUTO_SUN_PIXELS 1e-3 /* ... in <= 0.1 % of the pixels (issue 39) */
#define AUTO_PRIOR      1    /* strata K = 32: chosen when no pilot pair ran */
#define AUTO_Z          2.0  /* standard errors a candidate must beat the prior by */
#define AUTO_TIME_NOISE 0.1  /* a pilot price's relative scatter on a shared machine */
#define AUTO_SLOPE_MIN  0.25 /* the price at least this share of the second pass's average */

/* The candidates (lumis_auto_candidate_name), in the order their pilots run after the
 * prior's. */
static const struct {
    const char *name;
    int k;   /* regions as strata; 0: the map with MIS */
    int sun; /* the image sun split off, the candidate on the residual */
} cands[LUMIS_AUTO_CANDIDATES] = {
    {"mis", 0, 0},
    {"stratified-32", 32, 0},
    {"sun+mis", 0, 1},
    {"sun+stratified-32", 32, 1},
    {"stratified-16", 16, 0},
    {"stratified-64", 64, 0},
};

const char *lumis_auto_candidate_name(int candidate)
{
    return candidate >= 0 && candidate < LUMIS_AUTO_CANDIDATES ? cands[candidate].name : "unknown";
}

/* One pilot half: n more samples per pixel in job j; the image of those n alone (from the
 * job's running mean: after spp = a + n, half = (spp img - a prev) / n). */
static lumis_status half(lumis_render_job *j, int n, const lumis_image *prev, lumis_image **out)
{
    lumis_render_stats st;
    lumis_render_job_stats(j, &st);
    const int a = st.spp;
    lumis_status rs = lumis_render_job_run(j, n);
    if (rs == LUMIS_OK) rs = lumis_render_job_image(j, out);
    if (rs != LUMIS_OK || !prev) return rs;
    const size_t m = 3 * (size_t)(*out)->width * (size_t)(*out)->height;
    for (size_t k = 0; k < m; k++)
        (*out)->pixels[k] =
            (float)(((double)(a + n) * (*out)->pixels[k] - (double)a * prev->pixels[k]) / n);
    return LUMIS_OK;
}

static double lum(const float *p)
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

typedef struct pilot_pair {
    lumis_image *a, *b;   /* the two halves (NULL: not measured) */
    lumis__pilot_times t; /* n (samples per pixel in the first half; the second has 2n) and
                             the halves' CPU and wall seconds */
    double seconds;       /* what the two took (wall) */
} pilot_pair;

double lumis__auto_price(double t_a, int n_a, double t_b, int n_b)
{
    if (!(t_b > 0.0) || n_b <= 0) return 0.0;
    const double mean = t_b / n_b; /* the second pass's average, overhead and all */
    if (n_b <= n_a) return mean;
    const double slope = (t_b - t_a) / (n_b - n_a);
    return fmin(mean, fmax(AUTO_SLOPE_MIN * mean, slope));
}

int lumis__auto_prices(const lumis__pilot_times *t, int count, double *price)
{
    int by_wall = 0;
    for (int c = 0; c < count; c++) {
        price[c] = 0.0;
        if (t[c].n <= 0) continue;
        price[c] = lumis__auto_price(t[c].cpu[0], t[c].n, t[c].cpu[1], 2 * t[c].n);
        if (!(price[c] > 0.0)) by_wall = 1;
    }
    for (int c = 0; by_wall && c < count; c++)
        price[c] =
            t[c].n > 0 ? lumis__auto_price(t[c].wall[0], t[c].n, t[c].wall[1], 2 * t[c].n) : 0.0;
    return by_wall;
}

int lumis__auto_mis_n(double prior_cpu, double mis_cpu, double prior_wall, double mis_wall)
{
    const double ratio =
        mis_cpu > 0.0 && prior_cpu > 0.0 ? prior_cpu / mis_cpu : prior_wall / fmax(mis_wall, 1e-9);
    return (int)fmin(AUTO_MAX_HALF, fmax(1.0, floor(ratio + 0.5)));
}

/* The first half of a pair: n samples per pixel in job j, timed. */
static lumis_status first_half(lumis_render_job *j, int n, pilot_pair *p)
{
    p->t.n = n;
    const double w0 = omp_get_wtime(), c0 = lumis__cpu_now();
    const lumis_status st = half(j, n, NULL, &p->a);
    p->t.cpu[0] = c0 > 0.0 ? lumis__cpu_now() - c0 : 0.0;
    p->t.wall[0] = omp_get_wtime() - w0;
    return st;
}

/* The second: 2n samples more, timed; the price, the slope between the two passes' times
 * (what a pass costs whatever its samples cancels), is lumis__auto_prices' once every pair
 * has run. */
static lumis_status second_half(lumis_render_job *j, pilot_pair *p)
{
    const double w0 = omp_get_wtime(), c0 = lumis__cpu_now();
    const lumis_status st = half(j, 2 * p->t.n, p->a, &p->b);
    p->t.cpu[1] = c0 > 0.0 ? lumis__cpu_now() - c0 : 0.0;
    p->t.wall[1] = omp_get_wtime() - w0;
    p->seconds = p->t.wall[0] + p->t.wall[1];
    return st;
}

/* Candidate rd's pair, n and 2n samples per pixel, in a job made and dropped here. */
static lumis_status run_pair(const lumis_scene *scene, const lumis_render_desc *rd, int n,
                             pilot_pair *p)
{
    lumis_render_job *j = NULL;
    lumis_status st = lumis_render_job_create(scene, rd, &j);
    if (st == LUMIS_OK) st = first_half(j, n, p);
    if (st == LUMIS_OK) st = second_half(j, p);
    lumis_render_job_destroy(j);
    return st;
}

/* v_c of every measured candidate from its pair, against the mean of all measured pairs,
 * and in se[c] its standard error (of the mean over the pixels). */
static void variances(const pilot_pair *p, double *v, double *se)
{
    double v2[LUMIS_AUTO_CANDIDATES] = {0};
    int first = -1, count = 0;
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
        v[c] = 0.0;
        if (p[c].b) count++, first = first < 0 ? c : first;
    }
    if (!count) return;
    const size_t px = (size_t)p[first].a->width * (size_t)p[first].a->height;
    for (size_t k = 0; k < px; k++) {
        double m = 0.0;
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++)
            if (p[c].b) m += lum(p[c].a->pixels + 3 * k) + lum(p[c].b->pixels + 3 * k);
        m /= 2.0 * count;
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
            if (!p[c].b) continue;
            const double d = lum(p[c].a->pixels + 3 * k) - lum(p[c].b->pixels + 3 * k);
            const double x = d * d * (2.0 * p[c].t.n / 3.0) / (m * m + 1e-2);
            v[c] += x;
            v2[c] += x * x;
        }
    }
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
        v[c] /= (double)px;
        se[c] = sqrt(fmax(0.0, v2[c] / (double)px - v[c] * v[c]) / (double)px);
    }
}

/* The choice among the measured candidates a (pilot_spp > 0): the least efficiency, but
 * another than the prior only when it beats the prior's beyond the pilots' noise -- by more
 * than AUTO_Z standard errors of the log of their efficiencies' ratio, the errors' own
 * (error_se) and AUTO_TIME_NOISE of each time.  Near-ties (strata at K = 16, 32 and 64 are
 * often within 10 % of each other, the pilots' noise 30-40 %) then keep the prior, the
 * convergence suite's best on average, instead of the luckiest pilot.  *held: 1 when the
 * least was another's, kept back by the rule.  Without the prior measured: the least. */
static int priced(const lumis_auto_candidate *a)
{
    return a->pilot_spp > 0 && a->per_spp > 0.0;
}

int lumis__auto_choose(const lumis_auto_candidate *a, int prior_measured, int *held)
{
    int least = -1;
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++)
        if (priced(&a[c]) && (least < 0 || a[c].efficiency < a[least].efficiency)) least = c;
    *held = 0;
    if (least < 0) return AUTO_PRIOR;
    if (!prior_measured || !priced(&a[AUTO_PRIOR]) || least == AUTO_PRIOR) return least;
    const lumis_auto_candidate *p = &a[AUTO_PRIOR];
    int pick = AUTO_PRIOR;
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
        if (c == AUTO_PRIOR || !priced(&a[c]) || !(a[c].efficiency > 0.0)) continue;
        const double rc = a[c].error_se / fmax(a[c].error_per_spp, 1e-300);
        const double rp = p->error_se / fmax(p->error_per_spp, 1e-300);
        const double sd = sqrt(rc * rc + rp * rp + 2.0 * AUTO_TIME_NOISE * AUTO_TIME_NOISE);
        if (log(p->efficiency / a[c].efficiency) > AUTO_Z * sd &&
            a[c].efficiency < a[pick].efficiency)
            pick = c;
    }
    *held = pick != least;
    return pick;
}

/* What the candidates need, made as their pilots come (and the chosen one's kept). */
typedef struct auto_state {
    lumis_light_set *set[LUMIS_AUTO_CANDIDATES];
    lumis_region_sampler *regions[LUMIS_AUTO_CANDIDATES];
    double once[LUMIS_AUTO_CANDIDATES]; /* seconds its making took */
    lumis_sun sun;                      /* the image sun (sun.found: one, sun-dominated) */
    lumis_envmap *residual;
    lumis_sun_sampler *sun_sampler;
    lumis_sampler *residual_sampler; /* sun+mis: the caller's method on the residual */
    double sun_seconds;              /* the sun's finding and its samplers */
    int sun_looked;
} auto_state;

/* The lighting of candidate c (its set, regions, sun made on first use). */
static lumis_status candidate_lighting(const lumis_render_desc *ud, int c, auto_state *as,
                                       lumis_render_desc *rd)
{
    const lumis_error_sink *errors = &ud->errors;
    lumis_status st = LUMIS_OK;
    if (cands[c].sun && !as->residual_sampler && cands[c].k == 0) {
        const double t = omp_get_wtime();
        lumis_sampler_desc sd = {0};
        sd.method = lumis_sampler_get_method(ud->lighting.sampler);
        sd.errors = *errors;
        st = lumis_sampler_create(as->residual, &sd, &as->residual_sampler);
        as->sun_seconds += omp_get_wtime() - t;
    }
    if (st == LUMIS_OK && cands[c].k && !as->set[c]) {
        const double t = omp_get_wtime();
        const lumis_envmap *map = cands[c].sun ? as->residual : lumis__light_map(ud);
        st = lumis_lights_by_name(map, "median-cut", cands[c].k, 0, NULL, errors, &as->set[c]);
        if (st == LUMIS_OK)
            st = lumis_region_sampler_create(map, as->set[c], errors, &as->regions[c]);
        as->once[c] = omp_get_wtime() - t;
    }
    if (st != LUMIS_OK) return st;
    if (cands[c].sun) {
        rd->lighting.sun.sun = &as->sun;
        rd->lighting.sun.residual = as->residual;
        rd->lighting.sun.sampler = as->sun_sampler;
        if (!cands[c].k) rd->lighting.sampler = as->residual_sampler;
    }
    if (cands[c].k) {
        rd->lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
        rd->lighting.sampler = NULL;
        rd->lighting.light_set.set = as->set[c];
        rd->lighting.light_set.regions = as->regions[c];
        rd->lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
        rd->lighting.light_set.draws = 0;
        rd->light_samples = rd->bsdf_samples = 0;
    }
    return LUMIS_OK;
}

/* The image sun, looked for once: a sun holding AUTO_SUN_SHARE of the power in at most
 * AUTO_SUN_PIXELS of the pixels makes the sun candidates (not when the caller split one). */
static lumis_status find_sun(const lumis_render_desc *ud, auto_state *as)
{
    as->sun_looked = 1;
    if (ud->lighting.sun.sun) return LUMIS_OK;
    const double t = omp_get_wtime();
    lumis_sun_desc sd = {0};
    sd.min_share = AUTO_SUN_SHARE;
    sd.errors = ud->errors;
    const lumis_envmap *env = ud->lighting.env;
    lumis_status st = lumis_sun_find(env, &sd, &as->sun, &as->residual);
    const double pixels = (double)lumis_envmap_width(env) * lumis_envmap_height(env);
    if (st == LUMIS_OK && as->sun.found && as->sun.pixels > AUTO_SUN_PIXELS * pixels) {
        as->sun.found = 0; /* a sun, not a dominating one: the candidates are the map's */
        lumis_envmap_destroy(as->residual);
        as->residual = NULL;
    }
    if (st == LUMIS_OK && as->sun.found)
        st = lumis_sun_sampler_create(env, &as->sun, &ud->errors, &as->sun_sampler);
    as->sun_seconds += omp_get_wtime() - t;
    return st;
}

static void state_free(auto_state *as)
{
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
        lumis_region_sampler_destroy(as->regions[c]);
        lumis_light_set_destroy(as->set[c]);
    }
    lumis_sampler_destroy(as->residual_sampler);
    lumis_sun_sampler_destroy(as->sun_sampler);
    lumis_envmap_destroy(as->residual);
}

/* ---- the prediction (LUMIS_AUTO_PREDICT) ----------------------------------------------- */

/* What a surface reflects diffusely and by its glossy lobe (luminance of the albedos). */
static void reflectance(const lumis_bsdf *b, double *diffuse, double *glossy)
{
    const float *d = &b->diffuse.r, *g = &b->specular.r;
    *diffuse = *glossy = 0.0;
    switch (b->type) {
    case LUMIS_BSDF_LAMBERT:
        *diffuse = lum(d);
        break;
    case LUMIS_BSDF_WARD:
    case LUMIS_BSDF_GGX_PLASTIC:
        *diffuse = lum(d);
        *glossy = lum(g); /* Ward's lobe, the plastic's coat */
        break;
    default: /* GGX conductor and glossy: no diffuse part */
        *glossy = lum(g);
        break;
    }
}

lumis_status lumis__auto_diffuse_share(const lumis_scene *scene, const lumis_camera *camera,
                                       const lumis_error_sink *errors, double *share, int *rays)
{
    cam_frame cf;
    const lumis_status st = lumis__camera_frame(camera, errors, &cf);
    if (st != LUMIS_OK) return st;
    /* a grid of at most LUMIS_AUTO_GRID per axis, the image's aspect, a ray per cell centre */
    const int w = cf.cam.width, h = cf.cam.height;
    const int gw = w >= h ? (w < LUMIS_AUTO_GRID ? w : LUMIS_AUTO_GRID)
                          : (int)fmax(1.0, floor((double)LUMIS_AUTO_GRID * w / h));
    const int gh = h > w ? (h < LUMIS_AUTO_GRID ? h : LUMIS_AUTO_GRID)
                         : (int)fmax(1.0, floor((double)gw * h / w));
    double sd = 0.0, sg = 0.0;
    int met = 0;
    for (int y = 0; y < gh; y++)
        for (int x = 0; x < gw; x++) {
            const double sx = (x + 0.5) / gw * 2.0 - 1.0, sy = 1.0 - (y + 0.5) / gh * 2.0;
            hit hh;
            if (!intersect(scene, cf.eye, camera_dir(&cf, sx, sy), &hh)) continue;
            double d, g;
            reflectance(&hh.prim->material, &d, &g);
            sd += d;
            sg += g;
            met++;
        }
    *rays = met;
    *share = sd + sg > 0.0 ? sd / (sd + sg) : 1.0; /* black or no surface: the strata */
    return LUMIS_OK;
}

/* The candidate the prediction takes: strata K = 32 on mostly diffuse surfaces, else MIS. */
static lumis_status predict(const lumis_scene *scene, const lumis_session_desc *s,
                            lumis_session_result *r, int *best)
{
    double share = 1.0;
    int rays = 0;
    const lumis_status st =
        lumis__auto_diffuse_share(scene, s->render.camera, &s->render.errors, &share, &rays);
    r->auto_diffuse_share = share;
    r->auto_rays = rays;
    *best = share >= LUMIS_AUTO_DIFFUSE_MIN ? AUTO_PRIOR : 0;
    return st;
}

/* ---- the pilots (LUMIS_AUTO_PILOTS) ------------------------------------------------------- */

/* Every pilot that fits its cap, and the choice among those measured (*best; the prior when
 * none).  rd: the candidates' descriptions, their lighting made here. */
static lumis_status pilots(const lumis_scene *scene, const lumis_session_desc *s, auto_state *as,
                           lumis_render_desc *rd, lumis_session_result *r, int *best)
{
    const lumis_render_desc *ud = &s->render;
    pilot_pair pp[LUMIS_AUTO_CANDIDATES];
    memset(pp, 0, sizeof pp);
    /* the pilots' camera: a sixteenth of the pixels, within [AUTO_MIN_PIXELS, _MAX_] */
    lumis_camera cam = *ud->camera;
    const int cw = cam.width ? cam.width : 640, ch = cam.width ? cam.height : 480;
    const double px = (double)cw * ch;
    const double target = fmin(AUTO_MAX_PIXELS, fmax(AUTO_MIN_PIXELS, px / 16.0));
    const int d = px > target ? (int)floor(sqrt(px / target)) : 1;
    cam.width = cw / d > 0 ? cw / d : 1;
    cam.height = ch / d > 0 ? ch / d : 1;
    const double ppx = (double)cam.width * cam.height, scale = px / ppx;
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
        rd[c].camera = &cam;
        rd[c].progress = NULL;
        rd[c].first_sample = 0;
        rd[c].seed = ud->seed ^ 0x5eedau; /* the pilots' numbers are not the render's */
        rd[c].spp = 3 * AUTO_MAX_HALF;
    }
    /* the prior's set and strata, made first (kept if chosen) */
    lumis_status st = candidate_lighting(ud, AUTO_PRIOR, as, &rd[AUTO_PRIOR]);
    const double tp = omp_get_wtime(); /* the pilots' clock starts */
    const int spp = ud->spp ? ud->spp : 16;
    const int fixed = s->auto_pilot_spp > 0; /* every candidate, uncapped */
    /* the cap: a share of the budget, or (--spp) of the prior's render, known after a half;
     * a render of fewer samples than 4 / AUTO_CAP pilot halves at the prior skips them */
    double cap = fixed ? INFINITY : s->time_budget > 0.0 ? AUTO_CAP * s->time_budget : 0.0;
    const int small = !fixed && !(s->time_budget > 0.0) && 4.0 * ppx > AUTO_CAP * spp * px;
    int run = !small;
    int measured = 0;
    double u = 0.0;              /* seconds of the prior's first half (one sample per pixel) */
    double mis1 = 0.0, w1 = 0.0; /* one sample of MIS: CPU seconds (0 without the clock), wall */
    if (st == LUMIS_OK && run) { /* one MIS sample: warms the scene up, and times MIS */
        lumis_render_job *j = NULL;
        st = lumis_render_job_create(scene, &rd[0], &j);
        const double w0 = omp_get_wtime(), c0 = lumis__cpu_now();
        if (st == LUMIS_OK) st = lumis_render_job_run(j, 1);
        mis1 = c0 > 0.0 ? lumis__cpu_now() - c0 : 0.0;
        w1 = omp_get_wtime() - w0;
        lumis_render_job_destroy(j);
    }
    if (st == LUMIS_OK && run) { /* the prior's pair, its first half the probe of the cost */
        pilot_pair *p = &pp[AUTO_PRIOR];
        lumis_render_job *j = NULL;
        st = lumis_render_job_create(scene, &rd[AUTO_PRIOR], &j);
        if (st == LUMIS_OK) st = first_half(j, 1, p);
        u = p->t.wall[0];
        if (!(s->time_budget > 0.0) && !fixed) cap = AUTO_CAP * spp * u * scale;
        /* the rest of the pair and MIS's for as long: 5 halves' worth more (as below) */
        run = st == LUMIS_OK && (fixed || (omp_get_wtime() - tp) + 5.0 * u <= cap);
        if (run) {
            st = second_half(j, p);
            measured += st == LUMIS_OK;
        }
        lumis_render_job_destroy(j);
    }
    /* MIS's first half as long as the prior's (by CPU time; the sun's with the same n) */
    const int mis_n =
        fixed ? s->auto_pilot_spp : lumis__auto_mis_n(pp[AUTO_PRIOR].t.cpu[0], mis1, u, w1);
    /* then MIS, the sun's two, K = 16, 64 (their indices' order) */
    for (int q = 0; st == LUMIS_OK && run && q < LUMIS_AUTO_CANDIDATES; q++) {
        if (q == AUTO_PRIOR) continue;
        if (cands[q].sun) {
            if (!as->sun_looked) {
                const double pred = as->once[AUTO_PRIOR]; /* a scan of the map, as the set's */
                if (!fixed && (omp_get_wtime() - tp) + pred > cap) break;
                st = find_sun(ud, as);
                if (st != LUMIS_OK) break;
            }
            if (!as->sun.found) continue;
        }
        /* its predicted cost: the making (as the prior's, by K) and a pair (3 halves of the
         * first's size), a stratified sample's cost growing with its draws (K + 4 rays'
         * worth); MIS's first half as long as the prior's: 3 halves */
        const double make = cands[q].k && !as->set[q] ? as->once[AUTO_PRIOR] * cands[q].k / 32.0
                            : cands[q].sun && !as->residual_sampler
                                ? lumis_sampler_build_ms(ud->lighting.sampler) / 1000.0
                                : 0.0;
        const double pair = u * (cands[q].k ? 3.0 * (cands[q].k + 4.0) / 36.0 : 3.0);
        if (!fixed && q != 0 && (omp_get_wtime() - tp) + make + pair > cap) continue;
        st = candidate_lighting(ud, q, as, &rd[q]);
        if (st != LUMIS_OK) break;
        /* strata at one sample per pixel in the first half; MIS as long as the prior's */
        st = run_pair(scene, &rd[q], cands[q].k ? 1 : mis_n, &pp[q]);
        if (st == LUMIS_OK) measured++;
    }
    if (st == LUMIS_OK) {
        double v[LUMIS_AUTO_CANDIDATES], se[LUMIS_AUTO_CANDIDATES];
        variances(pp, v, se);
        lumis__pilot_times t[LUMIS_AUTO_CANDIDATES];
        double price[LUMIS_AUTO_CANDIDATES];
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
            t[c] = pp[c].t;
            if (!pp[c].b) t[c].n = 0; /* a first half alone is no measure */
        }
        lumis__auto_prices(t, LUMIS_AUTO_CANDIDATES, price);
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
            lumis_auto_candidate *a = &r->auto_candidates[c];
            if (!pp[c].b) continue; /* not measured: zeros */
            a->error_per_spp = v[c];
            a->error_se = se[c];
            a->per_spp = scale * price[c];
            a->pilot_spp = pp[c].t.n;
            a->efficiency = v[c] * a->per_spp; /* relMSE x seconds */
        }
        int held = 0;
        *best = lumis__auto_choose(r->auto_candidates, pp[AUTO_PRIOR].b != NULL, &held);
        r->auto_held = held;
        r->auto_prior = measured > 0 ? 0 : small ? 1 : 2;
        r->auto_cap = isfinite(cap) ? cap : 0.0;
        r->auto_pilot_seconds = omp_get_wtime() - tp;
        r->auto_pilot_cpu = mis1;
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++)
            r->auto_pilot_cpu += pp[c].t.cpu[0] + pp[c].t.cpu[1];
        r->auto_sun = as->sun;
    }
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
        lumis_image_destroy(pp[c].a);
        lumis_image_destroy(pp[c].b);
        rd[c].camera = ud->camera; /* not this function's pilot camera, gone on return */
    }
    return st;
}

/* ---- the session ------------------------------------------------------------------------ */

lumis_status lumis__session_auto(const lumis_scene *scene, const lumis_session_desc *s,
                                 lumis_image **out, lumis_session_result *r, int keep_set)
{
    const double t0 = omp_get_wtime();
    const lumis_render_desc *ud = &s->render;
    auto_state as;
    memset(&as, 0, sizeof as);
    lumis_render_desc rd[LUMIS_AUTO_CANDIDATES];
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) rd[c] = *ud;
    int best = AUTO_PRIOR;
    lumis_status st = s->auto_estimator == LUMIS_AUTO_PREDICT ? predict(scene, s, r, &best)
                                                              : pilots(scene, s, &as, rd, r, &best);
    if (st == LUMIS_OK) st = candidate_lighting(ud, best, &as, &rd[best]); /* made: kept */
    lumis_session_desc fin = *s;
    fin.auto_estimator = fin.auto_pilot_spp = 0;
    if (st == LUMIS_OK) {
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
            lumis_auto_candidate *a = &r->auto_candidates[c];
            a->lights_k = cands[c].k;
            a->sun = cands[c].sun;
            a->once = as.once[c] + (cands[c].sun ? as.sun_seconds : 0.0);
        }
        r->auto_count = LUMIS_AUTO_CANDIDATES;
        r->auto_chosen = best;
        r->auto_mode = s->auto_estimator;
        r->auto_seconds = omp_get_wtime() - t0;
        fin.spent = s->spent + r->auto_seconds;
        fin.render.lighting = rd[best].lighting;
        fin.render.light_samples = rd[best].light_samples;
        fin.render.bsdf_samples = rd[best].bsdf_samples;
    }
    const lumis_session_result keep = *r;
    if (st == LUMIS_OK) {
        st = lumis_render_session(scene, &fin, out, r);
        /* the render's own result, with the choice and what it cost */
        r->auto_count = keep.auto_count;
        r->auto_chosen = keep.auto_chosen;
        r->auto_prior = keep.auto_prior;
        r->auto_held = keep.auto_held;
        r->auto_mode = keep.auto_mode;
        r->auto_rays = keep.auto_rays;
        r->auto_diffuse_share = keep.auto_diffuse_share;
        r->auto_cap = keep.auto_cap;
        r->auto_pilot_seconds = keep.auto_pilot_seconds;
        r->auto_pilot_cpu = keep.auto_pilot_cpu;
        r->auto_sun = keep.auto_sun;
        r->auto_seconds = keep.auto_seconds;
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++)
            r->auto_candidates[c] = keep.auto_candidates[c];
        if (cands[best].k) {
            r->lights_k = cands[best].k;
            r->lights_build_ms = lumis_light_set_get_info(as.set[best])->build_ms;
            r->regions_build_ms = lumis_region_sampler_build_ms(as.regions[best]);
            r->regions_bytes = lumis_region_sampler_bytes(as.regions[best]);
        }
    }
    if (st == LUMIS_OK && cands[best].k && keep_set) {
        r->light_set = as.set[best]; /* the caller's now, as a session's own set is */
        as.set[best] = NULL;
    }
    state_free(&as);
    if (st != LUMIS_OK) {
        lumis_image_destroy(*out);
        *out = NULL;
    }
    r->wall_seconds += r->auto_seconds;
    return st;
}
