/* The image sun (lumis/sun.h): a compact bright region grown from the brightest pixel,
 * fitted as a disk of whole pixels and a cone that holds them, and split off the map so that
 * sun + residual == map exactly (docs/lights.md, "The image sun"). */
#include "lumis/sun.h"

#include "../core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* A pixel's centre as a double vector: the float direction lumis_envmap_uv_to_dir gives,
 * the one function every membership test goes through. */
static void centre(const lumis_envmap *env, int w, int h, int i, int j, double c[3])
{
    const lumis_vec3 d =
        lumis_envmap_uv_to_dir(env, ((float)i + 0.5f) / (float)w, ((float)j + 0.5f) / (float)h);
    c[0] = d.x;
    c[1] = d.y;
    c[2] = d.z;
}

/* The angle between two non-zero vectors, accurate near 0 (atan2 of |a x b| and a . b). */
static double angle(const double a[3], const double b[3])
{
    const double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2],
                 z = a[0] * b[1] - a[1] * b[0];
    return atan2(sqrt(x * x + y * y + z * z), a[0] * b[0] + a[1] * b[1] + a[2] * b[2]);
}

/* The sun's axis in double precision, normalised: what every function measures from. */
static void axis_of(const lumis_sun *sun, double a[3])
{
    const double x = sun->dir.x, y = sun->dir.y, z = sun->dir.z, n = sqrt(x * x + y * y + z * z);
    a[0] = x / n;
    a[1] = y / n;
    a[2] = z / n;
}

/* 1 - cos r, without cancellation. */
static double one_minus_cos(double r)
{
    const double s = sin(0.5 * r);
    return 2.0 * s * s;
}

static int sun_valid(const lumis_sun *sun)
{
    return sun && sun->found && sun->sample_radius > 0.0 && sun->sample_radius <= LUMIS_PI &&
           isfinite(sun->dir.x) && isfinite(sun->dir.y) && isfinite(sun->dir.z) &&
           (sun->dir.x != 0.0f || sun->dir.y != 0.0f || sun->dir.z != 0.0f);
}

int lumis_sun_contains(const lumis_sun *sun, const lumis_envmap *env, int i, int j)
{
    if (!sun_valid(sun) || !env) return 0;
    const int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    if (i < 0 || j < 0 || i >= w || j >= h) return 0;
    double a[3], c[3];
    axis_of(sun, a);
    centre(env, w, h, i, j, c);
    return angle(a, c) <= sun->radius;
}

lumis_rgb lumis_sun_eval(const lumis_sun *sun, const lumis_envmap *env, lumis_vec3 dir)
{
    const lumis_rgb black = {0.0f, 0.0f, 0.0f};
    if (!sun_valid(sun) || !env) return black;
    const double x = dir.x, y = dir.y, z = dir.z, n = sqrt(x * x + y * y + z * z);
    if (!(n > 0.0) || !isfinite(n)) return black;
    double a[3];
    axis_of(sun, a);
    /* Every point of the sun's pixels is inside the sampled cone (with a margin of 1e-5
     * radians): a direction outside it is in none of them. */
    if ((a[0] * x + a[1] * y + a[2] * z) / n < cos(sun->sample_radius)) return black;
    int i, j;
    lumis_envmap_dir_to_pixel(env, dir, &i, &j);
    return lumis_sun_contains(sun, env, i, j) ? lumis_envmap_texel(env, i, j) : black;
}

/* An orthonormal frame (t, b) about the unit vector a. */
static void frame(const double a[3], double t[3], double b[3])
{
    const double s = a[2] >= 0.0 ? 1.0 : -1.0, p = -1.0 / (s + a[2]), q = a[0] * a[1] * p;
    t[0] = 1.0 + s * a[0] * a[0] * p;
    t[1] = s * q;
    t[2] = -s * a[0];
    b[0] = q;
    b[1] = s + a[1] * a[1] * p;
    b[2] = -a[1];
}

double lumis_sun_pdf(const lumis_sun *sun, lumis_vec3 dir)
{
    if (!sun_valid(sun)) return 0.0;
    double a[3], d[3] = {dir.x, dir.y, dir.z};
    if (!(d[0] != 0.0 || d[1] != 0.0 || d[2] != 0.0)) return 0.0;
    axis_of(sun, a);
    return angle(a, d) <= sun->sample_radius
               ? 1.0 / (2.0 * LUMIS_PI * one_minus_cos(sun->sample_radius))
               : 0.0;
}

lumis_vec3 lumis_sun_sample(const lumis_sun *sun, double u1, double u2, double *pdf)
{
    lumis_vec3 out = {0.0f, 0.0f, 0.0f};
    if (pdf) *pdf = 0.0;
    if (!sun_valid(sun)) return out;
    u1 = u1 >= 0.0 ? (u1 < 1.0 ? u1 : 1.0 - 0x1p-53) : 0.0;
    u2 = u2 >= 0.0 ? (u2 < 1.0 ? u2 : 1.0 - 0x1p-53) : 0.0;
    double a[3], t[3], b[3];
    axis_of(sun, a);
    frame(a, t, b);
    const double hmax = one_minus_cos(sun->sample_radius);
    /* A float direction may round just outside the cone at its rim: draw again a hair
     * further in (never for a rim more than 1e-5 radians outside the sun's pixels). */
    for (double shrink = 1.0;; shrink *= 1.0 - 1e-6) {
        const double hh = u1 * hmax * shrink, sn = sqrt(hh * (2.0 - hh)), ct = 1.0 - hh,
                     phi = 2.0 * LUMIS_PI * u2, cp = cos(phi), sp = sin(phi);
        for (int k = 0; k < 3; k++) (&out.x)[k] = (float)(sn * (cp * t[k] + sp * b[k]) + ct * a[k]);
        const double d[3] = {out.x, out.y, out.z};
        if (angle(a, d) <= sun->sample_radius || shrink < 0.5) break;
    }
    if (pdf) *pdf = 1.0 / (2.0 * LUMIS_PI * hmax);
    return out;
}

lumis_status lumis_sun_invert(const lumis_sun *sun, lumis_vec3 dir, double u[2])
{
    if (!u || !sun_valid(sun) || !isfinite(dir.x) || !isfinite(dir.y) || !isfinite(dir.z))
        return LUMIS_ERR_INVALID_ARGUMENT;
    const double x = dir.x, y = dir.y, z = dir.z, n = sqrt(x * x + y * y + z * z);
    if (!(n > 0.0)) return LUMIS_ERR_INVALID_ARGUMENT;
    const double d[3] = {x / n, y / n, z / n};
    double a[3], t[3], b[3];
    axis_of(sun, a);
    const double th = angle(a, d);
    if (th > sun->sample_radius) return LUMIS_ERR_INVALID_ARGUMENT;
    frame(a, t, b);
    double phi =
        atan2(d[0] * b[0] + d[1] * b[1] + d[2] * b[2], d[0] * t[0] + d[1] * t[1] + d[2] * t[2]);
    if (phi < 0.0) phi += 2.0 * LUMIS_PI;
    u[0] = one_minus_cos(th) / one_minus_cos(sun->sample_radius);
    u[1] = phi / (2.0 * LUMIS_PI);
    if (u[0] >= 1.0) u[0] = 1.0 - 0x1p-53;
    if (u[1] >= 1.0) u[1] = 0.0;
    return LUMIS_OK;
}

/* The rows that may hold a pixel centre within r of the unit axis a: a centre's polar angle
 * differs from the axis' by at most their angle (rotation about +y keeps polar angles). */
static void rows_near(const double a[3], double r, int h, int *j0, int *j1)
{
    const double ta = acos(a[1] > 1.0 ? 1.0 : a[1] < -1.0 ? -1.0 : a[1]);
    const double lo = floor((ta - r) / LUMIS_PI * h) - 1.0,
                 hi = ceil((ta + r) / LUMIS_PI * h) + 1.0;
    *j0 = lo < 0.0 ? 0 : (int)lo;
    *j1 = hi > h - 1 ? h - 1 : (int)hi;
}

/* ---- detection ----------------------------------------------------------------------- */

/* Scratch of a search: luminance, the region's queue and its marks. */
typedef struct search {
    const lumis_envmap *env;
    int w, h;
    float *Y;
    int *queue;
    unsigned char *mark;
    int peak;
    double max_radius;
} search;

/* Grows the region of pixels with Y >= cut from the peak (8-neighbours; across the seam,
 * and across a pole to the opposite azimuth).  Returns its pixel count in s->queue, or -1
 * when a pixel centre of it lies farther than max_radius from the peak's. */
static int grow(search *s, float cut)
{
    const int w = s->w, h = s->h;
    double pc[3];
    centre(s->env, w, h, s->peak % w, s->peak / w, pc);
    int head = 0, tail = 0, fail = 0;
    s->queue[tail++] = s->peak;
    s->mark[s->peak] = 1;
    while (head < tail && !fail) {
        const int p = s->queue[head++], i = p % w, j = p / w;
        double c[3];
        centre(s->env, w, h, i, j, c);
        if (angle(pc, c) > s->max_radius) {
            fail = 1;
            break;
        }
        for (int dj = -1; dj <= 1; dj++)
            for (int di = -1; di <= 1; di++) {
                int ii = i + di, jj = j + dj;
                if (jj < 0 || jj >= h) {
                    jj = jj < 0 ? 0 : h - 1;
                    ii += w / 2;
                }
                ii = ((ii % w) + w) % w;
                const int q = jj * w + ii;
                if (s->mark[q] || !(s->Y[q] >= cut)) continue;
                s->mark[q] = 1;
                s->queue[tail++] = q;
            }
    }
    for (int k = 0; k < tail; k++) s->mark[s->queue[k]] = 0;
    return fail ? -1 : tail;
}

/* The largest angle from a pixel's centre to a point of it, bounded by a path: half the
 * row's height along the meridian, then half its width along the parallel of the point. */
static double pixel_reach(int w, int h, int j)
{
    const double t0 = LUMIS_PI * j / h, t1 = LUMIS_PI * (j + 1) / h;
    const double smax = t0 <= 0.5 * LUMIS_PI && t1 >= 0.5 * LUMIS_PI ? 1.0 : fmax(sin(t0), sin(t1));
    return 0.5 * LUMIS_PI / h + LUMIS_PI / w * smax;
}

static lumis_status check_desc(const lumis_sun_desc *d, const lumis_error_sink *errors)
{
    if (!(d->max_radius_deg >= 0.0 && d->max_radius_deg <= 20.0))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "sun: max_radius_deg %g: out of range (0, 20] degrees (0 == 5)",
                           d->max_radius_deg);
    if (!(d->min_share >= 0.0 && d->min_share <= 1.0))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "sun: min_share %g: out of range (0, 1] (0 == 0.1)", d->min_share);
    if (!(d->threshold >= 0.0 && d->threshold < 1.0))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "sun: threshold %g: out of range (0, 1) (0 == automatic)", d->threshold);
    return LUMIS_OK;
}

/* The region's fit: axis, disk, pixels, powers and the sampled cone, into out. */
static void fit(const search *s, int count, lumis_sun *out)
{
    const int w = s->w, h = s->h;
    double m[3] = {0, 0, 0};
    for (int k = 0; k < count; k++) {
        const int p = s->queue[k], j = p / w;
        double c[3];
        centre(s->env, w, h, p % w, j, c);
        const double wt = (double)s->Y[p] * lumis_envmap_pixel_solid_angle(s->env, j);
        for (int q = 0; q < 3; q++) m[q] += wt * c[q];
    }
    const double n = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
    if (!(n > 0.0)) centre(s->env, w, h, s->peak % w, s->peak / w, m);
    const double nn = n > 0.0 ? n : 1.0;
    out->dir.x = (float)(m[0] / nn);
    out->dir.y = (float)(m[1] / nn);
    out->dir.z = (float)(m[2] / nn);
    double a[3];
    axis_of(out, a);
    double r = 0.0;
    for (int k = 0; k < count; k++) {
        double c[3];
        centre(s->env, w, h, s->queue[k] % w, s->queue[k] / w, c);
        r = fmax(r, angle(a, c));
    }
    /* a hair over the largest angle (1e-6 radians, far above the rounding of the axis to
     * float): the region's pixels pass the test again */
    out->radius = r + 1e-6;
    out->found = 1;
    out->sample_radius = LUMIS_PI; /* lumis_sun_contains needs a valid sun meanwhile */
    const double cut = cos(fmin(out->radius, LUMIS_PI)) - 1e-6;
    double reach = 0.0, pw[3] = {0, 0, 0}, om = 0.0;
    int pixels = 0, j0, j1;
    rows_near(a, out->radius, h, &j0, &j1);
    for (int j = j0; j <= j1; j++) {
        const double omj = lumis_envmap_pixel_solid_angle(s->env, j), rj = pixel_reach(w, h, j);
        for (int i = 0; i < w; i++) {
            double c[3];
            centre(s->env, w, h, i, j, c);
            if (a[0] * c[0] + a[1] * c[1] + a[2] * c[2] < cut) continue;
            if (!lumis_sun_contains(out, s->env, i, j)) continue;
            const lumis_rgb L = lumis_envmap_texel(s->env, i, j);
            pw[0] += (double)L.r * omj;
            pw[1] += (double)L.g * omj;
            pw[2] += (double)L.b * omj;
            om += omj;
            pixels++;
            reach = fmax(reach, angle(a, c) + rj);
        }
    }
    out->sample_radius = fmin(reach + 1e-5, LUMIS_PI);
    for (int q = 0; q < 3; q++) out->power[q] = pw[q];
    out->solid_angle = om;
    out->pixels = pixels;
    out->radiance.r = (float)(pw[0] / om);
    out->radiance.g = (float)(pw[1] / om);
    out->radiance.b = (float)(pw[2] / om);
}

/* The map with the sun's pixels zeroed, its rotation and scale kept. */
static lumis_status make_residual(const lumis_envmap *env, const lumis_sun *sun,
                                  const lumis_error_sink *errors, lumis_envmap **out)
{
    const int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    const size_t n = (size_t)w * (size_t)h;
    float *px = malloc(3 * n * sizeof *px);
    if (!px) return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "sun: out of memory");
    memcpy(px, lumis_envmap_pixels(env), 3 * n * sizeof *px);
    double a[3];
    int j0, j1;
    axis_of(sun, a);
    rows_near(a, sun->radius, h, &j0, &j1);
    for (int j = j0; j <= j1; j++)
        for (int i = 0; i < w; i++)
            if (lumis_sun_contains(sun, env, i, j))
                memset(px + 3 * ((size_t)j * (size_t)w + (size_t)i), 0, 3 * sizeof *px);
    lumis_envmap_desc d = {0};
    d.pixels = px;
    d.width = w;
    d.height = h;
    d.rotation_deg = lumis_envmap_rotation_deg(env);
    d.scale = lumis_envmap_scale(env);
    d.max_pixels = (uint64_t)n;
    if (errors) d.errors = *errors;
    const lumis_status st = lumis_envmap_create(&d, out);
    free(px);
    return st;
}

/* Tries the cuts (the one given, or the automatic ladder, lowest first): the first whose
 * region stays compact, its pixel count in s->queue; 0 if none. */
static int best_region(search *s, double given, double *used)
{
    static const double ladder[] = {1e-4, 2e-4, 5e-4, 0.001, 0.002, 0.005,
                                    0.01, 0.02, 0.05, 0.1,   0.2,   0.5};
    const int nl = given > 0.0 ? 1 : (int)(sizeof ladder / sizeof ladder[0]);
    const float peak = s->Y[s->peak];
    for (int k = 0; k < nl; k++) {
        const double t = given > 0.0 ? given : ladder[k];
        const int count = grow(s, (float)(t * peak));
        if (count > 0) {
            *used = t;
            return count;
        }
    }
    return 0;
}

lumis_status lumis_sun_find(const lumis_envmap *env, const lumis_sun_desc *desc, lumis_sun *out,
                            lumis_envmap **residual)
{
    static const lumis_sun_desc zero = {0};
    const lumis_sun_desc *d = desc ? desc : &zero;
    if (residual) *residual = NULL;
    if (!env || !out) return LUMIS_ERR_INVALID_ARGUMENT;
    memset(out, 0, sizeof *out);
    lumis_status st = check_desc(d, &d->errors);
    if (st != LUMIS_OK) return st;
    const double maxr = (d->max_radius_deg > 0.0 ? d->max_radius_deg : 5.0) * LUMIS_PI / 180.0;
    const double min_share = d->min_share > 0.0 ? d->min_share : 0.1;
    search s = {env, lumis_envmap_width(env), lumis_envmap_height(env), NULL, NULL, NULL, 0, maxr};
    const size_t n = (size_t)s.w * (size_t)s.h;
    s.Y = malloc(n * sizeof *s.Y);
    s.queue = malloc(n * sizeof *s.queue);
    s.mark = calloc(n, 1);
    if (!s.Y || !s.queue || !s.mark) {
        st = lumis__fail(&d->errors, LUMIS_ERR_OUT_OF_MEMORY, "sun: out of memory");
        goto done;
    }
    const float *px = lumis_envmap_pixels(env);
    double total = 0.0;
    for (int j = 0; j < s.h; j++) {
        const double om = lumis_envmap_pixel_solid_angle(env, j);
        for (int i = 0; i < s.w; i++) {
            const size_t p = (size_t)j * (size_t)s.w + (size_t)i;
            s.Y[p] = LUMIS_LUMA_R * px[3 * p] + LUMIS_LUMA_G * px[3 * p + 1] +
                     LUMIS_LUMA_B * px[3 * p + 2];
            if (s.Y[p] > s.Y[s.peak]) s.peak = (int)p;
            total += (double)s.Y[p] * om;
        }
    }
    if (!(s.Y[s.peak] > 0.0f)) goto done; /* black: no sun */
    double used = 0.0;
    const int count = best_region(&s, d->threshold, &used);
    if (count == 0) goto done;
    fit(&s, count, out);
    out->threshold = used;
    const double scale = lumis_envmap_scale(env);
    const double ys =
        LUMIS_LUMA_R * out->power[0] + LUMIS_LUMA_G * out->power[1] + LUMIS_LUMA_B * out->power[2];
    out->share = total > 0.0 ? ys / (total * scale) : 0.0;
    if (out->radius > maxr || out->sample_radius > 2.0 * maxr || out->share < min_share) {
        const lumis_sun cand = *out;
        memset(out, 0, sizeof *out);
        out->share = cand.share;
        out->pixels = cand.pixels;
        out->threshold = cand.threshold;
        goto done;
    }
    if (residual) st = make_residual(env, out, &d->errors, residual);
done:
    free(s.Y);
    free(s.queue);
    free(s.mark);
    return st;
}

/* ---- the sun's pixels by their power -------------------------------------------------- */

struct lumis_sun_sampler {
    const lumis_envmap *env;
    int w, h, n;
    int *pixel;   /* the sun's pixels of positive luminance, j w + i, ascending */
    double *cdf;  /* n + 1 cumulative luminance powers, cdf[0] = 0 */
    double total; /* cdf[n] */
};

lumis_status lumis_sun_sampler_create(const lumis_envmap *env, const lumis_sun *sun,
                                      const lumis_error_sink *errors, lumis_sun_sampler **out)
{
    if (out) *out = NULL;
    if (!env || !out || !sun_valid(sun))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "sun sampler: needs a map, a sun found in it and an output");
    lumis_sun_sampler *s = calloc(1, sizeof *s);
    if (!s) return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "sun sampler: out of memory");
    s->env = env;
    s->w = lumis_envmap_width(env);
    s->h = lumis_envmap_height(env);
    double a[3];
    int j0, j1;
    axis_of(sun, a);
    rows_near(a, sun->radius, s->h, &j0, &j1);
    const size_t cap = (size_t)(j1 - j0 + 1) * (size_t)s->w;
    s->pixel = malloc(cap * sizeof *s->pixel);
    s->cdf = malloc((cap + 1) * sizeof *s->cdf);
    if (!s->pixel || !s->cdf) {
        lumis_sun_sampler_destroy(s);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "sun sampler: out of memory");
    }
    s->cdf[0] = 0.0;
    for (int j = j0; j <= j1; j++) {
        const double om = lumis_envmap_pixel_solid_angle(env, j);
        for (int i = 0; i < s->w; i++) {
            if (!lumis_sun_contains(sun, env, i, j)) continue;
            const lumis_rgb L = lumis_envmap_texel(env, i, j);
            const double y = LUMIS_LUMA_R * L.r + LUMIS_LUMA_G * L.g + LUMIS_LUMA_B * L.b;
            if (!(y > 0.0)) continue;
            s->pixel[s->n] = j * s->w + i;
            s->cdf[s->n + 1] = s->cdf[s->n] + y * om;
            s->n++;
        }
    }
    s->total = s->cdf[s->n];
    if (s->n == 0 || !(s->total > 0.0)) {
        lumis_sun_sampler_destroy(s);
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "sun sampler: the sun's pixels hold no light");
    }
    *out = s;
    return LUMIS_OK;
}

void lumis_sun_sampler_destroy(lumis_sun_sampler *s)
{
    if (!s) return;
    free(s->pixel);
    free(s->cdf);
    free(s);
}

/* The index of pixel p among the sun's, or -1. */
static int find_pixel(const lumis_sun_sampler *s, int p)
{
    int lo = 0, hi = s->n - 1;
    while (lo <= hi) {
        const int mid = lo + (hi - lo) / 2;
        if (s->pixel[mid] == p) return mid;
        if (s->pixel[mid] < p)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return -1;
}

double lumis_sun_sampler_pdf(const lumis_sun_sampler *s, lumis_vec3 dir, lumis_rgb *radiance)
{
    const lumis_rgb black = {0.0f, 0.0f, 0.0f};
    if (radiance) *radiance = black;
    if (!s || !isfinite(dir.x) || !isfinite(dir.y) || !isfinite(dir.z) ||
        (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f))
        return 0.0;
    int i, j;
    lumis_envmap_dir_to_pixel(s->env, dir, &i, &j);
    const int k = find_pixel(s, j * s->w + i);
    if (k < 0) return 0.0;
    if (radiance) *radiance = lumis_envmap_texel(s->env, i, j);
    return (s->cdf[k + 1] - s->cdf[k]) / (s->total * lumis_envmap_pixel_solid_angle(s->env, j));
}

lumis_vec3 lumis_sun_sampler_sample(const lumis_sun_sampler *s, double u1, double u2, double *pdf,
                                    lumis_rgb *radiance)
{
    lumis_vec3 out = {0.0f, 0.0f, 0.0f};
    if (pdf) *pdf = 0.0;
    if (radiance) *radiance = (lumis_rgb){0.0f, 0.0f, 0.0f};
    if (!s) return out;
    u1 = u1 >= 0.0 ? (u1 < 1.0 ? u1 : 1.0 - 0x1p-53) : 0.0;
    u2 = u2 >= 0.0 ? (u2 < 1.0 ? u2 : 1.0 - 0x1p-53) : 0.0;
    /* the pixel: the first k with cdf[k + 1] > u1 total */
    const double x = u1 * s->total;
    int lo = 0, hi = s->n - 1;
    while (lo < hi) {
        const int mid = lo + (hi - lo) / 2;
        if (s->cdf[mid + 1] > x)
            hi = mid;
        else
            lo = mid + 1;
    }
    const int k = lo, p = s->pixel[k], i = p % s->w, j = p / s->w;
    double fu = (x - s->cdf[k]) / (s->cdf[k + 1] - s->cdf[k]);
    fu = fu < 0.0 ? 0.0 : fu >= 1.0 ? 1.0 - 0x1p-53 : fu;
    const double z0 = cos(LUMIS_PI * j / s->h), z1 = cos(LUMIS_PI * (j + 1) / s->h);
    /* uniform in solid angle inside the pixel: uniform in azimuth and in cos theta.  A float
     * direction may round into a neighbour: draw again a hair nearer the pixel's centre. */
    double a = fu, b = u2;
    for (int tries = 0;; tries++) {
        const double z = z0 + b * (z1 - z0);
        const float u = (float)((i + a) / s->w), v = (float)(acos(z) / LUMIS_PI);
        out = lumis_envmap_uv_to_dir(s->env, u, v);
        int ii, jj;
        lumis_envmap_dir_to_pixel(s->env, out, &ii, &jj);
        if ((ii == i && jj == j) || tries == 8) break;
        a = 0.5 + (a - 0.5) * 0.9;
        b = 0.5 + (b - 0.5) * 0.9;
    }
    if (pdf)
        *pdf = (s->cdf[k + 1] - s->cdf[k]) / (s->total * lumis_envmap_pixel_solid_angle(s->env, j));
    if (radiance) *radiance = lumis_envmap_texel(s->env, i, j);
    return out;
}
