/* The sampler interface: building, the shared warp from a picked rectangle to a
 * direction, pdf lookups, and the importance every table-based method starts from.
 * Derivations: docs/samplers.md. */
#include "sampler_internal.h"

#include "../core/internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char *const method_names[LUMIS_METHOD_COUNT] = {
    "default", "inversion",    "inversion-guided", "alias",
    "kdtree",  "kdtree-exact", "hierarchical",     "uniform"};

const char *lumis_sampler_method_name(lumis_sampler_method method)
{
    return (unsigned)method < LUMIS_METHOD_COUNT ? method_names[method] : "unknown";
}

lumis_status lumis_sampler_method_from_name(const char *name, lumis_sampler_method *out)
{
    for (int m = 0; name && m < LUMIS_METHOD_COUNT; m++)
        if (strcmp(name, method_names[m]) == 0) {
            *out = (lumis_sampler_method)m;
            return LUMIS_OK;
        }
    return LUMIS_ERR_INVALID_ARGUMENT;
}

double lumis__rect_solid_angle(const lumis_envmap *env, int x0, int y0, int x1, int y1)
{
    return (2.0 * LUMIS_PI * (x1 - x0) / env->width) * (env->cos_row[y0] - env->cos_row[y1]);
}

/* ---- importance ---------------------------------------------------------------------- */

static double pixel_value(lumis_importance kind, const float *p)
{
    switch (kind) {
    case LUMIS_IMPORTANCE_AVERAGE:
        return ((double)p[0] + p[1] + p[2]) / 3.0;
    case LUMIS_IMPORTANCE_MAX_CHANNEL:
        return fmax(fmax(p[0], p[1]), p[2]);
    default:
        return LUMIS_LUMA_R * (double)p[0] + LUMIS_LUMA_G * (double)p[1] +
               LUMIS_LUMA_B * (double)p[2];
    }
}

lumis_status lumis__importance(const lumis_envmap *env, const lumis_sampler_desc *desc,
                               double **out, double *total)
{
    const int w = env->width, h = env->height;
    double *imp = malloc((size_t)w * (size_t)h * sizeof(double));
    if (!imp) return LUMIS_ERR_OUT_OF_MEMORY;
    double sum = 0.0, value_sum = 0.0;
    for (int j = 0; j < h; j++) {
        const double omega = env->row_solid_angle[j];
        double row = 0.0;
        for (int i = 0; i < w; i++) {
            size_t k = (size_t)j * (size_t)w + (size_t)i;
            double v = pixel_value(desc->importance, env->pixels + 3 * k);
            imp[k] = v; /* the value; times the solid angle below */
            row += v;
        }
        value_sum += row * omega;
    }
    if (desc->compensate) {
        /* Karlik et al. 2019: subtract the mean value over the sphere and clamp at zero;
         * keep the plain importance if nothing is left (a constant map). */
        const double mean = value_sum / (4.0 * LUMIS_PI);
        double left = 0.0;
        for (size_t k = 0; k < (size_t)w * (size_t)h; k++) left += fmax(imp[k] - mean, 0.0);
        if (left > 0.0)
            for (size_t k = 0; k < (size_t)w * (size_t)h; k++) imp[k] = fmax(imp[k] - mean, 0.0);
    }
    for (int j = 0; j < h; j++) {
        const double omega = env->row_solid_angle[j];
        for (int i = 0; i < w; i++) {
            size_t k = (size_t)j * (size_t)w + (size_t)i;
            imp[k] *= omega;
            sum += imp[k];
        }
    }
    *out = imp;
    *total = sum;
    return LUMIS_OK;
}

/* ---- building ------------------------------------------------------------------------ */

static double now_ms(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

lumis_status lumis_sampler_create(const lumis_envmap *env, const lumis_sampler_desc *desc,
                                  lumis_sampler **out)
{
    static const lumis_sampler_desc zero_desc;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!desc) desc = &zero_desc;
    const lumis_error_sink *err = &desc->errors;
    if (!env) return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT, "sampler: no envmap given");
    if ((unsigned)desc->method >= LUMIS_METHOD_COUNT ||
        (unsigned)desc->importance >= LUMIS_IMPORTANCE_COUNT || desc->kdtree_blocks < 0)
        return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT,
                           "sampler: unknown method or importance, or negative block count");
    double t0 = now_ms();
    lumis_sampler *s = calloc(1, sizeof *s);
    if (!s) return lumis__fail(err, LUMIS_ERR_OUT_OF_MEMORY, "sampler: out of memory");
    s->env = env;
    s->w = env->width;
    s->h = env->height;
    s->method = desc->method == LUMIS_METHOD_DEFAULT ? LUMIS_METHOD_INVERSION_GUIDED : desc->method;

    lumis_status st = LUMIS_OK;
    double *imp = NULL, total = 0.0;
    if (s->method != LUMIS_METHOD_UNIFORM) {
        st = lumis__importance(env, desc, &imp, &total);
        if (st == LUMIS_OK && !(total > 0.0)) {
            s->fallback = 1;
            lumis__fail(err, LUMIS_OK,
                        "sampler: the map has no importance anywhere (it is black); "
                        "sampling uniformly instead of with %s",
                        lumis_sampler_method_name(s->method));
        }
    }
    if (st == LUMIS_OK) {
        if (s->method == LUMIS_METHOD_UNIFORM || s->fallback)
            st = lumis__uniform_init(s);
        else if (s->method == LUMIS_METHOD_INVERSION)
            st = lumis__inversion_init(s, imp, 0);
        else if (s->method == LUMIS_METHOD_INVERSION_GUIDED)
            st = lumis__inversion_init(s, imp, 1);
        else if (s->method == LUMIS_METHOD_ALIAS)
            st = lumis__alias_init(s, imp);
        else if (s->method == LUMIS_METHOD_HIERARCHICAL)
            st = lumis__hierarchical_init(s, imp);
        else
            st = lumis__kdtree_init(s, imp, desc);
    }
    free(imp);
    if (st != LUMIS_OK) {
        if (s->m && s->m->destroy) s->m->destroy(s);
        free(s);
        return lumis__fail(err, st, "sampler: %s: %s", lumis_sampler_method_name(desc->method),
                           lumis_status_string(st));
    }
    lumis__envmap_retain(env);
    s->total_bytes += sizeof *s;
    s->build_ms = now_ms() - t0;
    *out = s;
    return LUMIS_OK;
}

void lumis_sampler_destroy(lumis_sampler *s)
{
    if (!s) return;
    if (s->m->destroy) s->m->destroy(s);
    lumis_envmap_destroy((lumis_envmap *)s->env);
    free(s);
}

/* ---- sampling ------------------------------------------------------------------------ */

/* Point (s, t) of the rectangle -> map-frame direction, uniform in solid angle (or in
 * angles), in double precision; *cos_theta reports where it went. */
static void warp(const lumis_sampler *smp, const lumis__pick *p, double s, double t, double d[3],
                 double *cos_theta)
{
    const lumis_envmap *env = smp->env;
    double phi = 2.0 * LUMIS_PI * (p->x0 + s * (p->x1 - p->x0)) / env->width;
    double c, st;
    if (smp->m->uniform_angles) {
        double theta = LUMIS_PI * (p->y0 + t * (p->y1 - p->y0)) / env->height;
        c = cos(theta);
        st = sin(theta);
    } else {
        c = env->cos_row[p->y0] + t * (env->cos_row[p->y1] - env->cos_row[p->y0]);
        st = sqrt(fmax(0.0, (1.0 - c) * (1.0 + c)));
    }
    d[0] = st * cos(phi);
    d[1] = c;
    d[2] = st * sin(phi);
    *cos_theta = c;
}

/* sin(theta) of a world direction, as both sample() and pdf() compute it. */
static double sin_theta(lumis_vec3 d)
{
    double xz = sqrt((double)d.x * d.x + (double)d.z * d.z);
    return xz / sqrt(xz * xz + (double)d.y * d.y);
}

static float final_pdf(const lumis_sampler *s, double density, lumis_vec3 dir)
{
    /* Uniform in angles, the density grows as 1 / sin(theta) towards a pole; at the pole
     * itself (a set of measure zero) it is capped so it stays finite. */
    if (s->m->uniform_angles) density /= fmax(sin_theta(dir), 1e-12);
    return density < FLT_MAX ? (float)density : FLT_MAX;
}

/* Inputs outside [0, 1) (a float generator rounding up to 1, NaN) are clamped in. */
static double clamp_u(double u)
{
    return u >= 0.0 ? (u < 1.0 ? u : 0x1.fffffffffffffp-1) : 0.0;
}

/* Rounding a direction to float moves it by about 1e-7 radians; a point at least this
 * far (in radians, or in cos theta, which changes no faster) from every edge of its pixel
 * is certain to look up that pixel again. */
#define EDGE_MARGIN 1e-6

/* The pixel holding the warped point, and whether it is clear of that pixel's edges. */
static int locate(const lumis_sampler *smp, const lumis__pick *p, double s, double c, int *pi,
                  int *pj)
{
    const lumis_envmap *env = smp->env;
    double x = s * (p->x1 - p->x0);
    int i = (int)x;
    if (i >= p->x1 - p->x0) i = p->x1 - p->x0 - 1;
    double fx = x - i;
    *pi = p->x0 + i;
    /* The row: cos theta decreases down the rows; binary search within the rectangle. */
    int lo = p->y0, hi = p->y1 - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (env->cos_row[mid] >= c)
            lo = mid;
        else
            hi = mid - 1;
    }
    *pj = lo;
    double dphi = 2.0 * LUMIS_PI / env->width * fmin(fx, 1.0 - fx);
    double dcos = fmin(env->cos_row[lo] - c, c - env->cos_row[lo + 1]);
    return dphi >= EDGE_MARGIN && dcos >= EDGE_MARGIN;
}

/* Direction of a picked point and the pixel it lies in (pixel index into *pixel). */
static void place(const lumis_sampler *s, const lumis__pick *p, lumis_vec3 *dir, size_t *pixel)
{
    const lumis_envmap *env = s->env;
    int pi = 0, pj = 0;
    double s0 = p->s, t0 = p->t;
    for (int attempt = 0;; attempt++) {
        double m[3], c;
        warp(s, p, s0, t0, m, &c);
        int clear = locate(s, p, s0, c, &pi, &pj);
        dir->x = (float)(env->cos_rot * m[0] - env->sin_rot * m[2]);
        dir->y = (float)m[1];
        dir->z = (float)(env->sin_rot * m[0] + env->cos_rot * m[2]);
        if (clear) break;
        /* Within rounding distance of an edge (about one sample in 10^3): look the
         * rounded direction up as pdf() will, and if it left the rectangle pull the point
         * inwards, so that direction, pdf and radiance always belong together. */
        lumis_envmap_dir_to_pixel(env, *dir, &pi, &pj);
        if ((pi >= p->x0 && pi < p->x1 && pj >= p->y0 && pj < p->y1) || attempt == 3) break;
        s0 = attempt < 2 ? 0.5 + (s0 - 0.5) * 0.999 : 0.5;
        t0 = attempt < 2 ? 0.5 + (t0 - 0.5) * 0.999 : 0.5;
    }
    *pixel = (size_t)pj * (size_t)env->width + (size_t)pi;
}

static lumis_rgb radiance(const lumis_envmap *env, size_t pixel)
{
    const float *q = env->pixels + 3 * pixel;
    lumis_rgb c = {q[0] * env->scale, q[1] * env->scale, q[2] * env->scale};
    return c;
}

lumis_env_sample lumis_sampler_sample(const lumis_sampler *s, double u1, double u2)
{
    lumis__pick p;
    s->m->pick(s, clamp_u(u1), clamp_u(u2), &p);
    lumis_env_sample r;
    size_t pixel;
    place(s, &p, &r.dir, &pixel);
    r.pdf = final_pdf(s, p.density, r.dir);
    r.radiance = radiance(s->env, pixel);
    return r;
}

/* In batches: all picks first (their table lookups overlap), then all directions, with
 * each radiance prefetched, then the radiance - so the cache misses of a batch overlap
 * instead of following one another.  The results are identical to sample()'s. */
void lumis_sampler_sample_n(const lumis_sampler *s, const double *u, size_t n,
                            lumis_env_sample *out)
{
    enum { BATCH = 32 };
    lumis__pick p[BATCH];
    size_t pixel[BATCH];
    for (size_t k0 = 0; k0 < n; k0 += BATCH) {
        size_t m = n - k0 < BATCH ? n - k0 : BATCH;
        for (size_t k = 0; k < m; k++)
            s->m->pick(s, clamp_u(u[2 * (k0 + k)]), clamp_u(u[2 * (k0 + k) + 1]), &p[k]);
        for (size_t k = 0; k < m; k++) {
            place(s, &p[k], &out[k0 + k].dir, &pixel[k]);
#if defined(__GNUC__) || defined(__clang__)
            __builtin_prefetch(s->env->pixels + 3 * pixel[k]);
#endif
        }
        for (size_t k = 0; k < m; k++) {
            out[k0 + k].pdf = final_pdf(s, p[k].density, out[k0 + k].dir);
            out[k0 + k].radiance = radiance(s->env, pixel[k]);
        }
    }
}

/* The density of dir and its pixel; 0 (pixel untouched) for the zero vector. */
static float pdf_and_pixel(const lumis_sampler *s, lumis_vec3 dir, int *i, int *j)
{
    if (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f) return 0.0f;
    lumis_envmap_dir_to_pixel(s->env, dir, i, j);
    return final_pdf(s, s->m->density(s, *i, *j), dir);
}

float lumis_sampler_pdf(const lumis_sampler *s, lumis_vec3 dir)
{
    int i, j;
    return pdf_and_pixel(s, dir, &i, &j);
}

float lumis_sampler_pdf_radiance(const lumis_sampler *s, lumis_vec3 dir, lumis_rgb *radiance)
{
    int i = -1, j = -1;
    float pdf = pdf_and_pixel(s, dir, &i, &j);
    *radiance = i >= 0 ? lumis_envmap_texel(s->env, i, j) : (lumis_rgb){0.0f, 0.0f, 0.0f};
    return pdf;
}

const lumis_envmap *lumis_sampler_envmap(const lumis_sampler *s)
{
    return s->env;
}

/* ---- queries ------------------------------------------------------------------------- */

size_t lumis_sampler_table_bytes(const lumis_sampler *s)
{
    return s->table_bytes;
}
size_t lumis_sampler_total_bytes(const lumis_sampler *s)
{
    return s->total_bytes;
}
double lumis_sampler_build_ms(const lumis_sampler *s)
{
    return s->build_ms;
}
lumis_sampler_method lumis_sampler_get_method(const lumis_sampler *s)
{
    return s->method;
}
int lumis_sampler_is_uniform_fallback(const lumis_sampler *s)
{
    return s->fallback;
}
double lumis_sampler_kdtree_alpha(const lumis_sampler *s)
{
    return s->kd_alpha;
}
int lumis_sampler_kdtree_blocks(const lumis_sampler *s)
{
    return s->kd_blocks;
}

/* ---- uniform: one rectangle, the whole map ------------------------------------------- */

static void uniform_pick(const lumis_sampler *s, double u1, double u2, lumis__pick *p)
{
    p->x0 = p->y0 = 0;
    p->x1 = s->w;
    p->y1 = s->h;
    p->s = u1;
    p->t = u2;
    p->density = 1.0 / (4.0 * LUMIS_PI);
}

static double uniform_density(const lumis_sampler *s, int i, int j)
{
    (void)s, (void)i, (void)j;
    return 1.0 / (4.0 * LUMIS_PI);
}

/* Cost: no table lookups. */
static const lumis__method uniform_method = {uniform_pick, uniform_density, NULL, 0};

lumis_status lumis__uniform_init(lumis_sampler *s)
{
    s->m = &uniform_method;
    return LUMIS_OK;
}
