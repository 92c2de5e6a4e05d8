/* The equirectangular environment-map model: coordinates, lookups, statistics.
 * Derivations: docs/coordinates.md. */
#include "lumis/envmap.h"

#include "../core/internal.h"
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- coordinates ------------------------------------------------------------------- */

double lumis_equirect_solid_angle(int width, int height, int j)
{
    if (width <= 0 || height <= 0 || j < 0 || j >= height) return 0.0;
    /* cos a - cos b = 2 sin((a+b)/2) sin((b-a)/2): no cancellation at the poles. */
    double a = LUMIS_PI * j / height, b = LUMIS_PI * (j + 1) / height;
    return (2.0 * LUMIS_PI / width) * 2.0 * sin(0.5 * (a + b)) * sin(0.5 * (b - a));
}

static void uv_to_dir_d(double u, double v, double out[3])
{
    double phi = 2.0 * LUMIS_PI * u, theta = LUMIS_PI * v;
    double st = sin(theta);
    out[0] = st * cos(phi);
    out[1] = cos(theta);
    out[2] = st * sin(phi);
}

static void dir_to_uv_d(double x, double y, double z, double *u, double *v)
{
    double phi = atan2(z, x); /* (-pi, pi] */
    double uu = phi * (0.5 / LUMIS_PI);
    if (uu < 0.0) uu += 1.0;
    if (!(uu < 1.0)) uu = 0.0; /* phi == 2 pi wraps; NaN (zero vector) lands on 0 too */
    double theta = atan2(sqrt(x * x + z * z), y);
    double vv = theta * (1.0 / LUMIS_PI);
    if (!(vv >= 0.0)) vv = 0.0;
    if (vv >= 1.0) vv = 0x1.fffffffffffffp-1;
    *u = uu;
    *v = vv;
}

lumis_vec3 lumis_equirect_to_dir(float u, float v)
{
    double d[3];
    uv_to_dir_d(u, v, d);
    lumis_vec3 r = {(float)d[0], (float)d[1], (float)d[2]};
    return r;
}

/* Rounding to float may reach 1.0: keep the half-open interval [0, 1). */
static void store_uv(double uu, double vv, float *u, float *v)
{
    float fu = (float)uu, fv = (float)vv;
    *u = fu < 1.0f ? fu : 0.0f;
    *v = fv < 1.0f ? fv : 0x1.fffffep-1f;
}

void lumis_equirect_from_dir(lumis_vec3 dir, float *u, float *v)
{
    double uu, vv;
    dir_to_uv_d(dir.x, dir.y, dir.z, &uu, &vv);
    store_uv(uu, vv, u, v);
}

/* World direction -> map frame: rotate by -rotation about +y (phi_map = phi_world - rot). */
static void world_to_map(const lumis_envmap *env, lumis_vec3 d, double out[3])
{
    out[0] = env->cos_rot * d.x + env->sin_rot * d.z;
    out[1] = d.y;
    out[2] = -env->sin_rot * d.x + env->cos_rot * d.z;
}

void lumis_envmap_dir_to_uv(const lumis_envmap *env, lumis_vec3 dir, float *u, float *v)
{
    double m[3];
    world_to_map(env, dir, m);
    double uu, vv;
    dir_to_uv_d(m[0], m[1], m[2], &uu, &vv);
    store_uv(uu, vv, u, v);
}

lumis_vec3 lumis_envmap_uv_to_dir(const lumis_envmap *env, float u, float v)
{
    double m[3];
    uv_to_dir_d(u, v, m);
    /* Map frame -> world: rotate by +rotation about +y. */
    lumis_vec3 r = {(float)(env->cos_rot * m[0] - env->sin_rot * m[2]), (float)m[1],
                    (float)(env->sin_rot * m[0] + env->cos_rot * m[2])};
    return r;
}

void lumis_envmap_dir_to_pixel(const lumis_envmap *env, lumis_vec3 dir, int *i, int *j)
{
    double m[3], u, v;
    world_to_map(env, dir, m);
    dir_to_uv_d(m[0], m[1], m[2], &u, &v);
    *i = lumis__clampi((int)(u * env->width), 0, env->width - 1);
    *j = lumis__clampi((int)(v * env->height), 0, env->height - 1);
}

/* ---- construction ------------------------------------------------------------------ */

lumis_status lumis_envmap_create(const lumis_envmap_desc *desc, lumis_envmap **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!desc || !desc->pixels)
        return lumis__fail(desc ? &desc->errors : NULL, LUMIS_ERR_INVALID_ARGUMENT,
                           "envmap: no pixels given");
    lumis_status st = lumis_image_check_size(desc->width, desc->height, desc->max_pixels);
    if (st != LUMIS_OK)
        return lumis__fail(&desc->errors, st, "envmap: %d x %d: %s", desc->width, desc->height,
                           lumis_status_string(st));
    if (!isfinite(desc->scale) || desc->scale < 0.0f || !isfinite(desc->rotation_deg))
        return lumis__fail(&desc->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "envmap: scale must be finite and >= 0, rotation finite");

    lumis_envmap *env = calloc(1, sizeof *env);
    if (!env) return LUMIS_ERR_OUT_OF_MEMORY;
    atomic_init(&env->refs, 1); /* before the first failure: lumis_envmap_destroy frees at 0 */
    size_t n = (size_t)desc->width * (size_t)desc->height * 3;
    env->pixels = malloc(n * sizeof(float));
    env->row_solid_angle = malloc((size_t)desc->height * sizeof(double));
    env->cos_row = malloc(((size_t)desc->height + 1) * sizeof(double));
    if (!env->pixels || !env->row_solid_angle || !env->cos_row) {
        lumis_envmap_destroy(env);
        return lumis__fail(&desc->errors, LUMIS_ERR_OUT_OF_MEMORY, "envmap: out of memory");
    }
    memcpy(env->pixels, desc->pixels, n * sizeof(float));
    lumis_sanitize_floats(env->pixels, n, &env->replaced);
    env->width = desc->width;
    env->height = desc->height;
    env->scale = desc->scale == 0.0f ? 1.0f : desc->scale;
    env->rotation_deg = desc->rotation_deg;
    double r = fmod((double)desc->rotation_deg, 360.0) * (LUMIS_PI / 180.0);
    env->cos_rot = cos(r);
    env->sin_rot = sin(r);
    for (int j = 0; j < env->height; j++)
        env->row_solid_angle[j] = lumis_equirect_solid_angle(env->width, env->height, j);
    for (int j = 0; j <= env->height; j++) env->cos_row[j] = cos(LUMIS_PI * j / env->height);
    env->cos_row[0] = 1.0;
    env->cos_row[env->height] = -1.0;
    *out = env;
    return LUMIS_OK;
}

lumis_status lumis_envmap_from_image(const lumis_image *image, lumis_envmap **out)
{
    if (!image) return LUMIS_ERR_INVALID_ARGUMENT;
    lumis_envmap_desc d = {0};
    d.pixels = image->pixels;
    d.width = image->width;
    d.height = image->height;
    return lumis_envmap_create(&d, out);
}

const lumis_envmap *lumis__envmap_retain(const lumis_envmap *env)
{
    atomic_fetch_add_explicit(&((lumis_envmap *)env)->refs, 1, memory_order_relaxed);
    return env;
}

void lumis_envmap_destroy(lumis_envmap *env)
{
    if (!env) return;
    /* Samplers hold references: the last holder frees. */
    if (atomic_fetch_sub_explicit(&env->refs, 1, memory_order_acq_rel) != 1) return;
    free(env->cos_row);
    free(env->pixels);
    free(env->row_solid_angle);
    free(env);
}

int lumis_envmap_width(const lumis_envmap *env)
{
    return env->width;
}
int lumis_envmap_height(const lumis_envmap *env)
{
    return env->height;
}
float lumis_envmap_scale(const lumis_envmap *env)
{
    return env->scale;
}
float lumis_envmap_rotation_deg(const lumis_envmap *env)
{
    return env->rotation_deg;
}
const float *lumis_envmap_pixels(const lumis_envmap *env)
{
    return env->pixels;
}
lumis_replaced lumis_envmap_replaced(const lumis_envmap *env)
{
    return env->replaced;
}

double lumis_envmap_pixel_solid_angle(const lumis_envmap *env, int j)
{
    return (j >= 0 && j < env->height) ? env->row_solid_angle[j] : 0.0;
}

/* ---- lookups ------------------------------------------------------------------------ */

lumis_rgb lumis_envmap_texel(const lumis_envmap *env, int i, int j)
{
    i = lumis__clampi(i, 0, env->width - 1);
    j = lumis__clampi(j, 0, env->height - 1);
    const float *p = env->pixels + ((size_t)j * (size_t)env->width + (size_t)i) * 3;
    lumis_rgb c = {p[0] * env->scale, p[1] * env->scale, p[2] * env->scale};
    return c;
}

lumis_rgb lumis_envmap_eval(const lumis_envmap *env, lumis_vec3 dir)
{
    if (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f) {
        lumis_rgb black = {0.0f, 0.0f, 0.0f};
        return black;
    }
    int i, j;
    lumis_envmap_dir_to_pixel(env, dir, &i, &j);
    return lumis_envmap_texel(env, i, j);
}

lumis_rgb lumis_envmap_power(const lumis_envmap *env)
{
    double sum[3] = {0, 0, 0};
    for (int j = 0; j < env->height; j++) {
        double row[3] = {0, 0, 0};
        const float *p = env->pixels + (size_t)j * (size_t)env->width * 3;
        for (int i = 0; i < env->width; i++, p += 3) {
            row[0] += p[0];
            row[1] += p[1];
            row[2] += p[2];
        }
        for (int c = 0; c < 3; c++) sum[c] += row[c] * env->row_solid_angle[j];
    }
    lumis_rgb r = {(float)(sum[0] * env->scale), (float)(sum[1] * env->scale),
                   (float)(sum[2] * env->scale)};
    return r;
}

/* ---- statistics ---------------------------------------------------------------------- */

static void swapf(float *a, float *b)
{
    float t = *a;
    *a = *b;
    *b = t;
}

/* Rearranges a[0..n) so that its k largest values come first (k in [1, n]).
 * Quickselect with a three-way partition, so maps full of equal values (black skies)
 * stay linear. */
static void select_largest(float *a, size_t n, size_t k)
{
    size_t lo = 0, hi = n; /* the boundary k lies in [lo, hi) */
    uint64_t seed = 0x9e3779b97f4a7c15ULL;
    while (hi - lo > 1) {
        seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
        float pivot = a[lo + (size_t)((seed >> 33) % (hi - lo))];
        /* [lo, gt) > pivot, [gt, i) == pivot, [lt, hi) < pivot */
        size_t gt = lo, i = lo, lt = hi;
        while (i < lt) {
            if (a[i] > pivot)
                swapf(&a[i++], &a[gt++]);
            else if (a[i] < pivot)
                swapf(&a[i], &a[--lt]);
            else
                i++;
        }
        if (k <= gt)
            hi = gt;
        else if (k <= lt)
            return; /* the boundary falls among values equal to the pivot */
        else
            lo = lt;
    }
}

lumis_status lumis_envmap_stats_compute(const lumis_envmap *env, lumis_envmap_stats *out)
{
    if (!env || !out) return LUMIS_ERR_INVALID_ARGUMENT;
    return lumis_equirect_stats(env->pixels, env->width, env->height, env->scale, out);
}

lumis_status lumis_equirect_stats(const float *pixels, int width, int height, float scale,
                                  lumis_envmap_stats *out)
{
    if (!pixels || !out) return LUMIS_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    lumis_status st = lumis_image_check_size(width, height, UINT64_MAX);
    if (st != LUMIS_OK) return st;
    size_t n = (size_t)width * (size_t)height;
    float *yw = malloc(n * sizeof(float)); /* Y * Omega per pixel, for the top shares */
    if (!yw) return LUMIS_ERR_OUT_OF_MEMORY;

    const double s = scale;
    double min_y = INFINITY, max_y = 0.0, min_pos = INFINITY, power = 0.0;
    double prgb[3] = {0, 0, 0};
    uint64_t black = 0;
    for (int j = 0; j < height; j++) {
        const double omega = lumis_equirect_solid_angle(width, height, j);
        const float *p = pixels + (size_t)j * (size_t)width * 3;
        double row_y = 0.0, row[3] = {0, 0, 0};
        for (int i = 0; i < width; i++, p += 3) {
            double y = s * (LUMIS_LUMA_R * (double)p[0] + LUMIS_LUMA_G * (double)p[1] +
                            LUMIS_LUMA_B * (double)p[2]);
            if (y < min_y) min_y = y;
            if (y > max_y) max_y = y;
            if (y > 0.0 && y < min_pos) min_pos = y;
            if (y == 0.0) black++;
            row_y += y;
            row[0] += p[0];
            row[1] += p[1];
            row[2] += p[2];
            yw[(size_t)j * (size_t)width + (size_t)i] = (float)(y * omega);
        }
        power += row_y * omega;
        for (int c = 0; c < 3; c++) prgb[c] += s * row[c] * omega;
    }

    out->width = width;
    out->height = height;
    out->min_luminance = min_y;
    out->max_luminance = max_y;
    out->min_positive_luminance = isinf(min_pos) ? 0.0 : min_pos;
    out->dynamic_range = isinf(min_pos) ? 0.0 : max_y / min_pos;
    out->power = power;
    out->avg_luminance = power / (4.0 * LUMIS_PI);
    for (int c = 0; c < 3; c++) out->power_rgb[c] = prgb[c];
    out->black_pixels = black;

    /* The top 1 % (0.1 %) is floor(n / 100) (floor(n / 1000)) pixels, at least one: the
     * definition behind the table of ../shared/data/README.md, which lumis reproduces. */
    size_t k1 = n / 100 ? n / 100 : 1, k01 = n / 1000 ? n / 1000 : 1;
    if (power > 0.0) {
        select_largest(yw, n, k1);
        double top1 = 0.0;
        for (size_t k = 0; k < k1; k++) top1 += yw[k];
        select_largest(yw, k1, k01);
        double top01 = 0.0;
        for (size_t k = 0; k < k01; k++) top01 += yw[k];
        out->top1_share = top1 / power;
        out->top01_share = top01 / power;
    }
    free(yw);
    return LUMIS_OK;
}

/* ---- power-preserving resampling ----------------------------------------------------- */

/* 1D box resampling between two partitions of the same interval given by their edges
 * in a measure mu (u for columns, 1 - cos theta for rows): out[k] is the mu-weighted mean
 * of the inputs over output cell k.  Applied to `lines` lines; within a line, cells are
 * src_step (dst_step) floats apart, and lines src_line (dst_line) floats apart. */
static void resample_1d(const double *e_in, int n_in, const double *e_out, int n_out,
                        const float *src, size_t src_step, float *dst, size_t dst_step,
                        size_t lines, size_t src_line, size_t dst_line)
{
    for (size_t l = 0; l < lines; l++) {
        const float *s = src + l * src_line;
        float *d = dst + l * dst_line;
        int j = 0;
        for (int k = 0; k < n_out; k++) {
            double lo = e_out[k], hi = e_out[k + 1];
            double acc[3] = {0, 0, 0};
            while (j < n_in && e_in[j + 1] <= lo) j++;
            for (int jj = j; jj < n_in && e_in[jj] < hi; jj++) {
                double a = e_in[jj] > lo ? e_in[jj] : lo;
                double b = e_in[jj + 1] < hi ? e_in[jj + 1] : hi;
                double w = b - a;
                if (w <= 0.0) continue;
                const float *p = s + (size_t)jj * src_step;
                acc[0] += w * p[0];
                acc[1] += w * p[1];
                acc[2] += w * p[2];
            }
            double inv = hi > lo ? 1.0 / (hi - lo) : 0.0;
            float *q = d + (size_t)k * dst_step;
            q[0] = (float)(acc[0] * inv);
            q[1] = (float)(acc[1] * inv);
            q[2] = (float)(acc[2] * inv);
        }
    }
}

static void column_edges(int n, double *e)
{
    for (int i = 0; i <= n; i++) e[i] = (double)i / n;
}

static void row_edges(int n, double *e)
{
    /* mu = 1 - cos theta = 2 sin^2(theta / 2): the solid angle of a polar cap / 2 pi. */
    for (int j = 0; j <= n; j++) {
        double s = sin(0.5 * LUMIS_PI * j / n);
        e[j] = 2.0 * s * s;
    }
}

lumis_status lumis_equirect_resize(const float *src, int width, int height, float *dst, int new_w,
                                   int new_h)
{
    if (!src || !dst) return LUMIS_ERR_INVALID_ARGUMENT;
    if (lumis_image_check_size(width, height, 0) != LUMIS_OK ||
        lumis_image_check_size(new_w, new_h, 0) != LUMIS_OK)
        return LUMIS_ERR_BAD_DIMENSIONS;
    float *tmp = malloc((size_t)new_w * (size_t)height * 3 * sizeof(float));
    double *ein = malloc(((size_t)(width > height ? width : height) + 1) * sizeof(double));
    double *eout = malloc(((size_t)(new_w > new_h ? new_w : new_h) + 1) * sizeof(double));
    if (!tmp || !ein || !eout) {
        free(tmp);
        free(ein);
        free(eout);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    /* Columns first (each row is a line of pixels 3 floats apart) ... */
    column_edges(width, ein);
    column_edges(new_w, eout);
    resample_1d(ein, width, eout, new_w, src, 3, tmp, 3, (size_t)height, (size_t)width * 3,
                (size_t)new_w * 3);
    /* ... then rows (each column is a line of pixels a row apart). */
    row_edges(height, ein);
    row_edges(new_h, eout);
    resample_1d(ein, height, eout, new_h, tmp, (size_t)new_w * 3, dst, (size_t)new_w * 3,
                (size_t)new_w, 3, 3);
    free(tmp);
    free(ein);
    free(eout);
    return LUMIS_OK;
}
