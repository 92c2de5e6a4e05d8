/* The sampler interface: building, the shared warp from a picked rectangle to a
 * direction, pdf lookups, and the importance every table-based method starts from.
 * Derivations: docs/samplers.md. */
#include "sampler_method.h"

#include "../core/internal.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static const char *const method_names[] = {"default",      "inversion", "inversion-guided",
                                           "alias",        "kdtree",    "kdtree-exact",
                                           "hierarchical", "uniform"};

LUMIS__ENUM_NAMES(lumis_sampler_method, LUMIS_METHOD_COUNT, method_names, lumis_sampler_method_name,
                  lumis_sampler_method_from_name);

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
    s->inv_w = 1.0 / s->w;
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

/* The per-sample path is inlined into sample() and sample_n(); rare paths are not. */
#if defined(__GNUC__) || defined(__clang__)
#define LUMIS__INLINE   static inline __attribute__((always_inline))
#define LUMIS__NOINLINE static __attribute__((noinline))
#else
#define LUMIS__INLINE   static inline
#define LUMIS__NOINLINE static
#endif

/* The row holding cos theta = c within rows [y0, y1): the largest j with cos_row[j] >= c.
 * theta from Abramowitz and Stegun's 4.4.46 (error below 2e-8 rad, a row is pi / h)
 * names the row or a neighbour; two comparisons settle it.  No table, no search. */
static int find_row(const lumis_envmap *env, double c, int y0, int y1)
{
    const double *cr = env->cos_row;
    double x = c < 0.0 ? -c : c;
    double a = sqrt(1.0 - x) *
               (1.5707963050 +
                x * (-0.2145988016 +
                     x * (0.0889789874 +
                          x * (-0.0501743046 +
                               x * (0.0308918810 + x * (-0.0170881256 +
                                                        x * (0.0066700901 - 0.0012624911 * x)))))));
    double theta = c < 0.0 ? LUMIS_PI - a : a;
    int j = (int)(theta * (env->height / LUMIS_PI));
    if (j < y0) j = y0;
    if (j > y1 - 1) j = y1 - 1;
    while (j > y0 && cr[j] < c) j--;
    while (j < y1 - 1 && cr[j + 1] >= c) j++;
    return j;
}

/* sin(theta) of a world direction, as both sample() and pdf() compute it. */
static double sin_theta(lumis_vec3 d)
{
    double xz = sqrt((double)d.x * d.x + (double)d.z * d.z);
    return xz / sqrt(xz * xz + (double)d.y * d.y);
}

LUMIS__INLINE float final_pdf(const lumis_sampler *s, double density, lumis_vec3 dir)
{
    /* Uniform in angles, the density grows as 1 / sin(theta) towards a pole; at the pole
     * itself (a set of measure zero) it is capped so it stays finite. */
    if (s->m->uniform_angles) {
        double st = sin_theta(dir);
        density /= st > 1e-12 ? st : 1e-12;
    }
    return density < FLT_MAX ? (float)density : FLT_MAX;
}

/* Point (s, t) of the rectangle -> map-frame direction m, uniform in solid angle (or in
 * angles), and the pixel holding it; returns whether the point is clear of that pixel's
 * edges.  A one-pixel rectangle (inversion, alias, hierarchical) is its own pixel. */
LUMIS__INLINE int warp(const lumis_sampler *smp, const lumis__pick *p, double s, double t,
                       double m[3], int *pi, int *pj)
{
    const lumis_envmap *env = smp->env;
    const int nx = p->x1 - p->x0;
    double x = s * nx;
    int i = (int)x;
    if (i >= nx) i = nx - 1;
    double fx = x - i;
    double c, st;
    if (smp->m->uniform_angles) {
        /* theta / 2 pi = v / 2 */
        lumis__sincos_turns((p->y0 + t * (p->y1 - p->y0)) * (0.5 / env->height), &st, &c);
    } else {
        double c0 = env->cos_row[p->y0], c1 = env->cos_row[p->y1];
        c = c0 + t * (c1 - c0);
        double s2 = (1.0 - c) * (1.0 + c);
        st = sqrt(s2 > 0.0 ? s2 : 0.0);
    }
    int j = p->y1 - p->y0 == 1 ? p->y0 : find_row(env, c, p->y0, p->y1);
    *pi = p->x0 + i;
    *pj = j;
#if defined(__GNUC__) || defined(__clang__)
    /* The radiance is read last; start bringing it in while the direction is computed. */
    __builtin_prefetch(env->pixels + 3 * ((size_t)j * (size_t)env->width + (size_t)*pi));
#endif
    double sp, cp;
    lumis__sincos_turns((p->x0 + x) * smp->inv_w, &sp, &cp);
    m[0] = st * cp;
    m[1] = c;
    m[2] = st * sp;
    /* Distances to the four edges, in radians (azimuth) and in cos theta; minima written
     * so that they compile to minsd, not to branches on random data. */
    double gx = 1.0 - fx, ex = fx < gx ? fx : gx;
    double dphi = (2.0 * LUMIS_PI) * smp->inv_w * ex;
    double up = env->cos_row[j] - c, down = c - env->cos_row[j + 1];
    double d = up < down ? up : down;
    d = dphi < d ? dphi : d;
    return d >= LUMIS__EDGE_MARGIN;
}

static void to_world(const lumis_envmap *env, const double m[3], lumis_vec3 *dir)
{
    dir->x = (float)(env->cos_rot * m[0] - env->sin_rot * m[2]);
    dir->y = (float)m[1];
    dir->z = (float)(env->sin_rot * m[0] + env->cos_rot * m[2]);
}

/* A point within rounding distance of an edge (about one sample in 10^3): look the
 * rounded direction up as pdf() will, and if it left the rectangle pull the point
 * inwards, so that direction, pdf and radiance always belong together.  Out of line: it
 * keeps the common path short. */
LUMIS__NOINLINE size_t place_near_edge(const lumis_sampler *s, const lumis__pick *p,
                                       lumis_vec3 *dir)
{
    const lumis_envmap *env = s->env;
    int pi = 0, pj = 0;
    double s0 = p->s, t0 = p->t;
    for (int attempt = 0;; attempt++) {
        lumis_envmap_dir_to_pixel(env, *dir, &pi, &pj);
        if ((pi >= p->x0 && pi < p->x1 && pj >= p->y0 && pj < p->y1) || attempt == 3) break;
        s0 = attempt < 2 ? 0.5 + (s0 - 0.5) * 0.999 : 0.5;
        t0 = attempt < 2 ? 0.5 + (t0 - 0.5) * 0.999 : 0.5;
        double m[3];
        int clear = warp(s, p, s0, t0, m, &pi, &pj);
        to_world(env, m, dir);
        if (clear) break;
    }
    return (size_t)pj * (size_t)env->width + (size_t)pi;
}

/* Direction of a picked point; returns the pixel it lies in. */
LUMIS__INLINE size_t place(const lumis_sampler *s, const lumis__pick *p, lumis_vec3 *dir)
{
    double m[3];
    int pi, pj;
    int clear = warp(s, p, p->s, p->t, m, &pi, &pj);
    to_world(s->env, m, dir);
    if (!clear) return place_near_edge(s, p, dir);
    return (size_t)pj * (size_t)s->env->width + (size_t)pi;
}

/* One pixel as a rectangle of a sampler of its own: the warp and the edge handling every
 * sampler uses, for callers that pick pixels themselves (a light set's region samplers). */
static void no_pick(const lumis_sampler *s, double u1, double u2, lumis__pick *p)
{
    (void)s, (void)u1, (void)u2, (void)p;
}

static const lumis__method pixel_method = {no_pick, NULL, NULL, 0, NULL, NULL};

size_t lumis__envmap_place(const lumis_envmap *env, int i, int j, double s, double t,
                           lumis_vec3 *dir)
{
    s = lumis__clamp_u(s);
    t = lumis__clamp_u(t);
    const double inv_w = 1.0 / env->width;
    if (lumis__envmap_place_clear(env, inv_w, i, j, s, t, dir))
        return (size_t)j * (size_t)env->width + (size_t)i;
    lumis_sampler one;
    memset(&one, 0, sizeof one);
    one.m = &pixel_method;
    one.env = env;
    one.w = env->width;
    one.h = env->height;
    one.inv_w = inv_w;
    const lumis__pick p = {i, j, i + 1, j + 1, s, t, 0.0};
    return place_near_edge(&one, &p, dir); /* what place() does with a point not clear */
}

lumis_env_sample lumis_sampler_sample(const lumis_sampler *s, double u1, double u2)
{
    lumis__pick p;
    s->m->pick(s, lumis__clamp_u(u1), lumis__clamp_u(u2), &p);
    lumis_env_sample r;
    size_t pixel = place(s, &p, &r.dir);
    r.pdf = final_pdf(s, p.density, r.dir);
    r.radiance = lumis__envmap_radiance(s->env, pixel);
    return r;
}

/* In batches: all picks first (their table lookups overlap), then all directions, with
 * each radiance prefetched, then the radiance - so the cache misses of a batch overlap
 * instead of following one another.  The results are identical to sample()'s. */
void lumis_sampler_sample_n(const lumis_sampler *s, const double *u, size_t n,
                            lumis_env_sample *out)
{
    enum { BATCH = LUMIS__BATCH };
    lumis__pick p[BATCH];
    size_t pixel[BATCH];
    double uc[2 * BATCH];
    for (size_t k0 = 0; k0 < n; k0 += BATCH) {
        size_t m = n - k0 < BATCH ? n - k0 : BATCH;
        for (size_t k = 0; k < 2 * m; k++) uc[k] = lumis__clamp_u(u[2 * k0 + k]);
        if (s->m->pick_n)
            s->m->pick_n(s, uc, (int)m, p);
        else
            for (size_t k = 0; k < m; k++) s->m->pick(s, uc[2 * k], uc[2 * k + 1], &p[k]);
        for (size_t k = 0; k < m; k++) {
            pixel[k] = place(s, &p[k], &out[k0 + k].dir);
#if defined(__GNUC__) || defined(__clang__)
            __builtin_prefetch(s->env->pixels + 3 * pixel[k]);
#endif
        }
        for (size_t k = 0; k < m; k++) {
            out[k0 + k].pdf = final_pdf(s, p[k].density, out[k0 + k].dir);
            out[k0 + k].radiance = lumis__envmap_radiance(s->env, pixel[k]);
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

lumis_status lumis_sampler_invert(const lumis_sampler *s, lumis_vec3 dir, double u[2])
{
    if (!s || !u) return LUMIS_ERR_INVALID_ARGUMENT;
    if (!s->m->invert) return LUMIS_ERR_UNSUPPORTED;
    double len = sqrt((double)dir.x * dir.x + (double)dir.y * dir.y + (double)dir.z * dir.z);
    if (!(len > 0.0) || !(len < INFINITY)) return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis_envmap *env = s->env;
    /* The pixel from the lookup pdf() and eval() use; the point inside it from the same
     * coordinates the warp produced: azimuth in turns and cos theta. */
    int i, j;
    lumis_envmap_dir_to_pixel(env, dir, &i, &j);
    double mx = env->cos_rot * dir.x + env->sin_rot * dir.z;
    double mz = -env->sin_rot * dir.x + env->cos_rot * dir.z;
    double a = atan2(mz, mx) * (0.5 / LUMIS_PI);
    if (a < 0.0) a += 1.0;
    if (!(a < 1.0)) a = 0.0; /* as lumis_envmap_dir_to_pixel: 2 pi wraps to column 0 */
    double ps = a * s->w - i;
    double c = dir.y / len;
    double pt = (env->cos_row[j] - c) / (env->cos_row[j] - env->cos_row[j + 1]);
    ps = ps > 0.0 ? (ps < 1.0 ? ps : 0x1.fffffffffffffp-1) : 0.0;
    pt = pt > 0.0 ? (pt < 1.0 ? pt : 0x1.fffffffffffffp-1) : 0.0;
    s->m->invert(s, i, j, ps, pt, u);
    return LUMIS_OK;
}

void lumis_sampler_pdf_n(const lumis_sampler *s, const lumis_vec3 *dirs, size_t n, float *pdf,
                         lumis_rgb *radiance)
{
    for (size_t k = 0; k < n; k++) {
        if (radiance)
            pdf[k] = lumis_sampler_pdf_radiance(s, dirs[k], &radiance[k]);
        else
            pdf[k] = lumis_sampler_pdf(s, dirs[k]);
    }
}

lumis_status lumis_sampler_invert_n(const lumis_sampler *s, const lumis_vec3 *dirs, size_t n,
                                    double *u, size_t *failed)
{
    for (size_t k = 0; k < n; k++) {
        lumis_status st = lumis_sampler_invert(s, dirs[k], u + 2 * k);
        if (st != LUMIS_OK) {
            if (failed) *failed = k;
            return st;
        }
    }
    if (failed) *failed = n;
    return LUMIS_OK;
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

/* The whole map is one rectangle: u1 is the azimuth in turns, u2 (1 - cos theta) / 2. */
static void uniform_invert(const lumis_sampler *s, int i, int j, double ps, double pt, double u[2])
{
    const double *cr = s->env->cos_row;
    double c = cr[j] + pt * (cr[j + 1] - cr[j]);
    u[0] = (i + ps) * s->inv_w;
    u[1] = 0.5 * (1.0 - c);
    if (u[0] >= 1.0) u[0] = 0x1.fffffffffffffp-1;
    if (u[1] >= 1.0) u[1] = 0x1.fffffffffffffp-1;
}

/* Cost: no table lookups. */
static const lumis__method uniform_method = {uniform_pick, uniform_density, NULL, 0,
                                             NULL,         uniform_invert};

lumis_status lumis__uniform_init(lumis_sampler *s)
{
    s->m = &uniform_method;
    return LUMIS_OK;
}
