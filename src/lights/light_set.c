/* The light-set object and the machinery its methods share: exact pixel moments, region
 * sums, rectangle extents, recursive splitting, jittered copies.  Formulas:
 * docs/lights.md. */
#include "internal.h"

#include "lumis/rng.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

double lumis__now_ms(void)
{
    struct timespec ts;
    timespec_get(&ts, TIME_UTC);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* ---- geometry ------------------------------------------------------------------------ */

/* x - sin x without cancellation for small x. */
static double x_minus_sin(double x)
{
    if (fabs(x) > 0.1) return x - sin(x);
    double x2 = x * x;
    return x * x2 * (1.0 / 6.0 - x2 * (1.0 / 120.0 - x2 * (1.0 / 5040.0 - x2 / 362880.0)));
}

lumis_status lumis__geom_init(lumis__geom *g, const lumis_envmap *env)
{
    memset(g, 0, sizeof *g);
    int w = env->width, h = env->height;
    g->w = w;
    g->h = h;
    size_t H = (size_t)h, W = (size_t)w;
    double *mem = malloc((3 * H + 2 * (H + 1) + 2 * W + 2 * (W + 1)) * sizeof(double));
    if (!mem) return LUMIS_ERR_OUT_OF_MEMORY;
    g->omega = mem;
    g->a = g->omega + H;
    g->b = g->a + H;
    g->cos_t = g->b + H;
    g->sin_t = g->cos_t + H + 1;
    g->cs = g->sin_t + H + 1;
    g->cc = g->cs + W;
    g->cos_p = g->cc + W;
    g->sin_p = g->cos_p + W + 1;
    const double dphi = 2.0 * LUMIS_PI / w, dth = LUMIS_PI / h;
    for (int j = 0; j < h; j++) {
        double t0 = LUMIS_PI * j / h, t1 = LUMIS_PI * (j + 1) / h, s = 0.5 * (t0 + t1);
        g->omega[j] = lumis_envmap_pixel_solid_angle(env, j);
        /* a = int sin^2 = (dth - cos(t0 + t1) sin dth) / 2, written without cancellation */
        double sh = sin(s);
        g->a[j] = 0.5 * (x_minus_sin(dth) + 2.0 * sh * sh * sin(dth));
        /* b = dphi int sin cos = dphi (sin^2 t1 - sin^2 t0) / 2 = dphi sin(2s) sin(dth) / 2 */
        g->b[j] = dphi * 0.5 * sin(2.0 * s) * sin(dth);
    }
    for (int j = 0; j <= h; j++) {
        g->cos_t[j] = env->cos_row[j];
        g->sin_t[j] = (j == 0 || j == h) ? 0.0 : sin(LUMIS_PI * j / h);
    }
    for (int i = 0; i < w; i++) {
        double mid = dphi * (i + 0.5), s2 = 2.0 * sin(0.5 * dphi);
        g->cs[i] = cos(mid) * s2;
        g->cc[i] = sin(mid) * s2;
    }
    for (int i = 0; i <= w; i++) {
        g->cos_p[i] = i == w ? 1.0 : cos(dphi * i);
        g->sin_p[i] = i == w ? 0.0 : sin(dphi * i);
    }
    g->scale = env->scale;
    g->cos_rot = env->cos_rot;
    g->sin_rot = env->sin_rot;
    return LUMIS_OK;
}

void lumis__geom_free(lumis__geom *g)
{
    free(g->omega);
    g->omega = NULL;
}

double lumis__rect_min_dot(const lumis__geom *g, const double d[3], int r0, int r1, int c0, int c1)
{
    /* d . p = d_y cos(theta) + rho sin(theta) cos(phi - phi_d): minimise over phi (the same
     * phi for every theta, as sin(theta) >= 0), then over theta. */
    double rho = sqrt(d[0] * d[0] + d[2] * d[2]), gmin = 0.0;
    if (rho > 0.0) {
        double cd = d[0] / rho, sd = d[2] / rho;
        double span = 2.0 * LUMIS_PI * (c1 - c0) / g->w;
        double anti = atan2(-d[2], -d[0]);
        double t = anti - 2.0 * LUMIS_PI * c0 / g->w;
        t = fmod(t, 2.0 * LUMIS_PI);
        if (t < 0.0) t += 2.0 * LUMIS_PI;
        if (c1 - c0 >= g->w || t <= span)
            gmin = -1.0;
        else {
            double e0 = g->cos_p[c0] * cd + g->sin_p[c0] * sd;
            double e1 = g->cos_p[c1] * cd + g->sin_p[c1] * sd;
            gmin = e0 < e1 ? e0 : e1;
        }
    }
    double q = rho * gmin; /* h(theta) = d_y cos theta + q sin theta */
    double h0 = d[1] * g->cos_t[r0] + q * g->sin_t[r0];
    double h1 = d[1] * g->cos_t[r1] + q * g->sin_t[r1];
    double m = h0 < h1 ? h0 : h1;
    double R = sqrt(d[1] * d[1] + q * q);
    if (R > 0.0) {
        double psi = atan2(q, d[1]), th0 = LUMIS_PI * r0 / g->h, th1 = LUMIS_PI * r1 / g->h;
        double lo1 = psi + LUMIS_PI, lo2 = psi - LUMIS_PI;
        if ((lo1 >= th0 && lo1 <= th1) || (lo2 >= th0 && lo2 <= th1)) m = -R;
    }
    return m < -1.0 ? -1.0 : (m > 1.0 ? 1.0 : m);
}

void lumis__rect_sides(const lumis__geom *g, lumis__rect r, double *width, double *height)
{
    double mid = 0.5 * LUMIS_PI * (r.y0 + r.y1) / g->h;
    *height = LUMIS_PI * (r.y1 - r.y0) / g->h;
    *width = 2.0 * LUMIS_PI * (r.x1 - r.x0) / g->w * sin(mid);
}

/* ---- labels ------------------------------------------------------------------------- */

void lumis__fill_labels(int32_t *labels, int w, lumis__rect r, int32_t label)
{
    for (int j = r.y0; j < r.y1; j++) {
        int32_t *lab = labels + (size_t)j * (size_t)w;
        int i = r.x0;
#if defined(__SSE2__)
        for (; i < r.x1 && ((uintptr_t)(lab + i) & 15u); i++) lab[i] = label;
        const __m128i v = _mm_set1_epi32(label);
        for (; i + 4 <= r.x1; i += 4) _mm_stream_si128((__m128i *)(void *)(lab + i), v);
#endif
        for (; i < r.x1; i++) lab[i] = label;
    }
#if defined(__SSE2__)
    _mm_sfence(); /* the streamed labels are visible before anything reads them */
#endif
}

/* ---- region sums ----------------------------------------------------------------------- */

void lumis__acc_pixel(const lumis__geom *g, const lumis_envmap *env, lumis__acc *acc, int i, int j)
{
    const float *px = env->pixels + ((size_t)j * (size_t)g->w + (size_t)i) * 3;
    double om = g->omega[j], y = lumis__pixel_y(px, g->scale);
    acc->rgb[0] += (double)px[0] * om;
    acc->rgb[1] += (double)px[1] * om;
    acc->rgb[2] += (double)px[2] * om;
    double mx = g->a[j] * g->cs[i], my = g->b[j], mz = g->a[j] * g->cc[i];
    acc->m[0] += y * mx;
    acc->m[1] += y * my;
    acc->m[2] += y * mz;
    acc->g[0] += mx;
    acc->g[1] += my;
    acc->g[2] += mz;
    acc->omega += om;
    acc->pixels++;
}

void lumis__acc_rect_geometry(const lumis__geom *g, lumis__rect r, lumis__acc *acc)
{
    const int n = r.x1 - r.x0;
    /* sums of cs (cc) over the columns telescope to sin (cos) differences at the ends */
    const double gcs = g->sin_p[r.x1] - g->sin_p[r.x0], gcc = g->cos_p[r.x0] - g->cos_p[r.x1];
    for (int j = r.y0; j < r.y1; j++) {
        acc->g[0] += g->a[j] * gcs;
        acc->g[1] += g->b[j] * n;
        acc->g[2] += g->a[j] * gcc;
        acc->omega += g->omega[j] * n;
    }
}

void lumis__acc_rect(const lumis__geom *g, const lumis_envmap *env, int32_t *labels, lumis__rect r,
                     int32_t only, int32_t label, lumis__acc *acc)
{
    const int w = g->w;
    for (int j = r.y0; j < r.y1; j++) {
        const float *row = env->pixels + (size_t)j * (size_t)w * 3;
        int32_t *lab = labels + (size_t)j * (size_t)w;
        /* Two interleaved accumulators per sum halve the add-latency chains. */
        double s[2][6] = {{0, 0, 0, 0, 0, 0}, {0, 0, 0, 0, 0, 0}}, gcs = 0.0, gcc = 0.0;
        int n = 0;
        if (only == INT32_MIN) {
            int i = r.x0;
            for (; i + 1 < r.x1; i += 2)
                for (int u = 0; u < 2; u++) {
                    const float *px = row + (size_t)(i + u) * 3;
                    double y = lumis__pixel_y(px, g->scale);
                    s[u][0] += px[0];
                    s[u][1] += px[1];
                    s[u][2] += px[2];
                    s[u][3] += y;
                    s[u][4] += y * g->cs[i + u];
                    s[u][5] += y * g->cc[i + u];
                    lab[i + u] = label;
                }
            for (; i < r.x1; i++) {
                const float *px = row + (size_t)i * 3;
                double y = lumis__pixel_y(px, g->scale);
                s[0][0] += px[0];
                s[0][1] += px[1];
                s[0][2] += px[2];
                s[0][3] += y;
                s[0][4] += y * g->cs[i];
                s[0][5] += y * g->cc[i];
                lab[i] = label;
            }
            n = r.x1 - r.x0;
            /* sum of cs (cc) over the run telescopes to sin (cos) differences at its ends */
            gcs = g->sin_p[r.x1] - g->sin_p[r.x0];
            gcc = g->cos_p[r.x0] - g->cos_p[r.x1];
        } else {
            for (int i = r.x0; i < r.x1; i++) {
                if (lab[i] != only) continue;
                const float *px = row + (size_t)i * 3;
                double y = lumis__pixel_y(px, g->scale);
                s[0][0] += px[0];
                s[0][1] += px[1];
                s[0][2] += px[2];
                s[0][3] += y;
                s[0][4] += y * g->cs[i];
                s[0][5] += y * g->cc[i];
                gcs += g->cs[i];
                gcc += g->cc[i];
                lab[i] = label;
                n++;
            }
        }
        double t[6];
        for (int k = 0; k < 6; k++) t[k] = s[0][k] + s[1][k];
        double om = g->omega[j];
        acc->rgb[0] += t[0] * om;
        acc->rgb[1] += t[1] * om;
        acc->rgb[2] += t[2] * om;
        acc->m[0] += g->a[j] * t[4];
        acc->m[1] += g->b[j] * t[3];
        acc->m[2] += g->a[j] * t[5];
        acc->g[0] += g->a[j] * gcs;
        acc->g[1] += g->b[j] * n;
        acc->g[2] += g->a[j] * gcc;
        acc->omega += om * n;
        acc->pixels += n;
    }
}

static void normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0.0) {
        v[0] /= l;
        v[1] /= l;
        v[2] /= l;
    } else {
        v[0] = 0.0;
        v[1] = 1.0;
        v[2] = 0.0;
    }
}

void lumis__light_from_acc(const lumis__geom *g, const lumis__acc *acc, lumis_light_kind kind,
                           lumis_light *light)
{
    double d[3];
    /* The energy centroid; a region without luminance gets its geometric centroid. */
    const double *src =
        (acc->m[0] != 0.0 || acc->m[1] != 0.0 || acc->m[2] != 0.0) ? acc->m : acc->g;
    d[0] = src[0];
    d[1] = src[1];
    d[2] = src[2];
    normalize3(d);
    light->dir.x = (float)(g->cos_rot * d[0] - g->sin_rot * d[2]);
    light->dir.y = (float)d[1];
    light->dir.z = (float)(g->sin_rot * d[0] + g->cos_rot * d[2]);
    for (int c = 0; c < 3; c++) light->power[c] = acc->rgb[c] * g->scale;
    light->solid_angle = acc->omega;
    light->pixels = acc->pixels;
    light->kind = kind;
    light->extent = 0.0f;
}

void lumis__light_map_dir(const lumis__geom *g, const lumis_light *light, double d[3])
{
    double x = light->dir.x, y = light->dir.y, z = light->dir.z;
    d[0] = g->cos_rot * x + g->sin_rot * z;
    d[1] = y;
    d[2] = -g->sin_rot * x + g->cos_rot * z;
    normalize3(d);
}

/* ---- the set ------------------------------------------------------------------------- */

lumis_status lumis__common_check(const lumis_envmap *env, const char *what, int count, int sets,
                                 float jitter, uint64_t seed, const lumis_error_sink *errors,
                                 lumis__common *out)
{
    if (!env) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "%s: no envmap given", what);
    long long pixels = (long long)env->width * env->height;
    if (count < 0 || (long long)count > pixels)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: count %d is not in 1 .. %lld (the map's pixels; 0 == 64)", what,
                           count, pixels);
    if (sets < 0 || sets > 64)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: sets %d is not in 1 .. 64 (0 == 8)", what, sets);
    if (!(jitter >= 0.0f && jitter <= 1.0f))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: jitter must be in (0, 1] (0 == 0.1)", what);
    out->count = count ? count : 64;
    if ((long long)out->count > pixels)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "%s: the default count 64 exceeds the map's %lld pixels", what, pixels);
    out->sets = sets ? sets : 8;
    out->jitter = jitter > 0.0f ? jitter : 0.1;
    out->seed = seed;
    out->errors = errors;
    return LUMIS_OK;
}

lumis_status lumis__set_create(const lumis_envmap *env, const lumis__common *c, int count,
                               lumis_lights_method method, int fill, lumis_light_set **out)
{
    lumis_light_set *s = calloc(1, sizeof *s);
    if (!s) return LUMIS_ERR_OUT_OF_MEMORY;
    s->w = env->width;
    s->h = env->height;
    s->sets = c->sets;
    s->count = count;
    s->lights = calloc((size_t)c->sets * (size_t)(count > 0 ? count : 1), sizeof(lumis_light));
    s->labels = malloc((size_t)s->w * (size_t)s->h * sizeof(int32_t));
    if (!s->lights || !s->labels) {
        lumis_light_set_destroy(s);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    if (fill) memset(s->labels, 0xff, (size_t)s->w * (size_t)s->h * sizeof(int32_t)); /* -1 */
    s->info.method = method;
    s->info.requested = c->count;
    *out = s;
    return LUMIS_OK;
}

/* Uniform direction in the cap of half-angle beta about unit d. */
static void jitter_dir(const lumis_vec3 d0, double beta, double u1, double u2, lumis_vec3 *out)
{
    double d[3] = {d0.x, d0.y, d0.z};
    normalize3(d);
    /* Orthonormal basis (Duff et al. 2017). */
    double sign = d[2] >= 0.0 ? 1.0 : -1.0;
    double a = -1.0 / (sign + d[2]), b = d[0] * d[1] * a;
    double t[3] = {1.0 + sign * d[0] * d[0] * a, sign * b, -sign * d[0]};
    double bt[3] = {b, sign + d[1] * d[1] * a, -d[1]};
    double cosa = 1.0 - u1 * (1.0 - cos(beta));
    double sina = sqrt(fmax(0.0, 1.0 - cosa * cosa)), phi = 2.0 * LUMIS_PI * u2;
    double cp = cos(phi), sp = sin(phi), r[3];
    for (int k = 0; k < 3; k++) r[k] = cosa * d[k] + sina * (cp * t[k] + sp * bt[k]);
    normalize3(r);
    out->x = (float)r[0];
    out->y = (float)r[1];
    out->z = (float)r[2];
}

void lumis__set_finish(lumis_light_set *set, const lumis__geom *g, const lumis_envmap *env,
                       const lumis__common *c, double t0_ms)
{
    (void)env;
    (void)g;
    for (int k = 0; k < set->count; k++)
        for (int q = 0; q < 3; q++) set->info.power[q] += set->lights[k].power[q];
    set->info.count = set->count;
    for (int s = 1; s < set->sets; s++) {
        lumis_pcg32 rng;
        lumis_pcg32_seed(&rng, c->seed, (uint64_t)0x6c6967687473 + (uint64_t)s); /* "lights" + s */
        lumis_light *dst = set->lights + (size_t)s * (size_t)set->count;
        for (int k = 0; k < set->count; k++) {
            dst[k] = set->lights[k];
            double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
            jitter_dir(set->lights[k].dir, c->jitter * set->lights[k].extent, u1, u2, &dst[k].dir);
        }
    }
    set->info.build_ms = lumis__now_ms() - t0_ms;
}

void lumis_light_set_destroy(lumis_light_set *set)
{
    if (!set) return;
    free(set->lights);
    free(set->labels);
    free(set->kmeans_objective);
    free(set);
}

int lumis_light_set_sets(const lumis_light_set *set)
{
    return set ? set->sets : 0;
}

lumis_status lumis_light_set_get(const lumis_light_set *set, int index, const lumis_light **lights,
                                 int *count)
{
    if (!set || !lights || !count || index < 0 || index >= set->sets)
        return LUMIS_ERR_INVALID_ARGUMENT;
    *lights = set->lights + (size_t)index * (size_t)set->count;
    *count = set->count;
    return LUMIS_OK;
}

const int32_t *lumis_light_set_labels(const lumis_light_set *set, int *width, int *height)
{
    if (!set) return NULL;
    if (width) *width = set->w;
    if (height) *height = set->h;
    return set->labels;
}

const lumis_light_set_info *lumis_light_set_get_info(const lumis_light_set *set)
{
    return set ? &set->info : NULL;
}

int lumis_light_set_interleave_index(int sets, int x, int y)
{
    if (sets <= 1) return 0;
    int b = 1;
    for (int d = 1; d * d <= sets; d++)
        if (sets % d == 0) b = d;
    int a = sets / b;
    int xm = x % a, ym = y % b;
    if (xm < 0) xm += a;
    if (ym < 0) ym += b;
    return ym * a + xm;
}

/* ---- recursive rectangle splitting ------------------------------------------------------ */

typedef struct prio_item {
    double p;
    int index;
} prio_item;

static int cmp_prio(const void *pa, const void *pb)
{
    const prio_item *a = pa, *b = pb;
    if (a->p > b->p) return -1;
    if (a->p < b->p) return 1;
    return (a->index > b->index) - (a->index < b->index);
}

lumis_status lumis__split_rects(const lumis__splitter *s, int w, int h, int k, lumis__rect *rects)
{
    lumis__rect *next = malloc((size_t)k * sizeof *next);
    unsigned char *chosen = malloc((size_t)k);
    prio_item *items = malloc((size_t)k * sizeof *items);
    if (!next || !chosen || !items) {
        free(next);
        free(chosen);
        free(items);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    lumis__rect whole = {0, 0, w, h};
    rects[0] = whole;
    int n = 1;
    lumis_status st = LUMIS_OK;
    while (n < k) {
        int need = k - n, cand = 0;
        for (int r = 0; r < n; r++) {
            long long area = (long long)(rects[r].x1 - rects[r].x0) * (rects[r].y1 - rects[r].y0);
            chosen[r] = 0;
            if (area > 1) items[cand++] = (prio_item){0.0, r};
        }
        if (cand == 0) {
            st = LUMIS_ERR_INVALID_ARGUMENT; /* k > pixels: checked by the callers */
            break;
        }
        if (need >= cand) {
            for (int c = 0; c < cand; c++) chosen[items[c].index] = 1;
        } else {
            for (int c = 0; c < cand; c++) items[c].p = s->priority(s->ctx, rects[items[c].index]);
            qsort(items, (size_t)cand, sizeof *items, cmp_prio);
            for (int c = 0; c < need; c++) chosen[items[c].index] = 1;
        }
        int m = 0;
        for (int r = 0; r < n; r++) {
            lumis__rect a, b;
            if (chosen[r] && s->split(s->ctx, rects[r], &a, &b)) {
                next[m++] = a;
                next[m++] = b;
            } else {
                next[m++] = rects[r];
            }
        }
        memcpy(rects, next, (size_t)m * sizeof *rects);
        n = m;
    }
    free(next);
    free(chosen);
    free(items);
    return st;
}

void lumis__lights_from_rects(lumis_light_set *set, const lumis__geom *g, const lumis_envmap *env,
                              const lumis__rect *rects, int k)
{
    for (int r = 0; r < k; r++) {
        lumis__acc acc;
        memset(&acc, 0, sizeof acc);
        lumis__acc_rect(g, env, set->labels, rects[r], INT32_MIN, r, &acc);
        lumis_light *l = &set->lights[r];
        lumis__light_from_acc(g, &acc, LUMIS_LIGHT_REGION, l);
        double d[3];
        lumis__light_map_dir(g, l, d);
        double md = lumis__rect_min_dot(g, d, rects[r].y0, rects[r].y1, rects[r].x0, rects[r].x1);
        l->extent = lumis__extent_from_min_dot(md);
    }
}

float lumis__extent_from_min_dot(double min_dot)
{
    double e = acos(min_dot < -1.0 ? -1.0 : (min_dot > 1.0 ? 1.0 : min_dot));
    float f = (float)e;
    return (double)f < e ? nextafterf(f, INFINITY) : f; /* a bound: round up */
}

lumis_status lumis__sat_build(const lumis__geom *g, const lumis_envmap *env, double *e, double *mx,
                              double *my, double *mz)
{
    const int w = g->w, h = g->h;
    const size_t W = (size_t)w + 1;
    if (e) memset(e, 0, W * sizeof(double));
    if (mx) {
        memset(mx, 0, W * sizeof(double));
        memset(my, 0, W * sizeof(double));
        memset(mz, 0, W * sizeof(double));
    }
    for (int j = 0; j < h; j++) {
        const float *px = env->pixels + (size_t)j * (size_t)w * 3;
        const size_t o = (size_t)(j + 1) * W, p = (size_t)j * W;
        const double om = g->omega[j], aj = g->a[j], bj = g->b[j];
        if (e) e[o] = 0.0;
        if (!mx) {
            double re = 0.0;
            for (int i = 0; i < w; i++, px += 3) {
                re += (double)lumis__pixel_y(px, g->scale) * om;
                e[o + (size_t)i + 1] = e[p + (size_t)i + 1] + re;
            }
            continue;
        }
        mx[o] = my[o] = mz[o] = 0.0;
        double re = 0.0, rx = 0.0, ry = 0.0, rz = 0.0;
        for (int i = 0; i < w; i++, px += 3) {
            double y = lumis__pixel_y(px, g->scale);
            re += y * om;
            rx += y * aj * g->cs[i];
            ry += y * bj;
            rz += y * aj * g->cc[i];
            size_t q = (size_t)i + 1;
            if (e) e[o + q] = e[p + q] + re;
            mx[o + q] = mx[p + q] + rx;
            my[o + q] = my[p + q] + ry;
            mz[o + q] = mz[p + q] + rz;
        }
    }
    return LUMIS_OK;
}

/* ---- lights from a labelling ---------------------------------------------------------- */

lumis_status lumis__lights_from_labels(lumis_light_set *set, const lumis__geom *g,
                                       const lumis_envmap *env, const double (*dirs)[3])
{
    const int w = g->w, h = g->h, k = set->count;
    lumis__acc *acc = calloc((size_t)k, sizeof *acc);
    double *rowmin = malloc((size_t)k * sizeof(double)), *ext = calloc((size_t)k, sizeof(double));
    int32_t *touched = malloc((size_t)k * sizeof(int32_t));
    double *cph = malloc(2 * (size_t)w * sizeof(double)), *sph = cph ? cph + w : NULL;
    double(*d)[3] = malloc((size_t)k * sizeof *d);
    if (!acc || !rowmin || !ext || !touched || !cph || !d) {
        free(acc);
        free(rowmin);
        free(ext);
        free(touched);
        free(cph);
        free(d);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    for (int j = 0; j < h; j++) {
        const int32_t *lab = set->labels + (size_t)j * (size_t)w;
        for (int i = 0; i < w; i++) lumis__acc_pixel(g, env, &acc[lab[i]], i, j);
    }
    for (int q = 0; q < k; q++) {
        lumis__light_from_acc(g, &acc[q], LUMIS_LIGHT_REGION, &set->lights[q]);
        if (dirs) { /* the given direction, in world space */
            const double *v = dirs[q];
            set->lights[q].dir.x = (float)(g->cos_rot * v[0] - g->sin_rot * v[2]);
            set->lights[q].dir.y = (float)v[1];
            set->lights[q].dir.z = (float)(g->sin_rot * v[0] + g->cos_rot * v[2]);
        }
        lumis__light_map_dir(g, &set->lights[q], d[q]);
        rowmin[q] = 2.0;
    }
    /* Extent: per row, the smallest dot of each region's pixel centres with its direction;
     * the angle to it plus the pixel's angular radius bound (half its height plus half its
     * width at the widest latitude of the row, a path along a meridian and a parallel)
     * bounds every point of those pixels. */
    const double dph = 2.0 * LUMIS_PI / w, dth = LUMIS_PI / h;
    for (int i = 0; i < w; i++) {
        cph[i] = cos(dph * (i + 0.5));
        sph[i] = sin(dph * (i + 0.5));
    }
    for (int j = 0; j < h; j++) {
        const int32_t *lab = set->labels + (size_t)j * (size_t)w;
        const double th = dth * (j + 0.5), st = sin(th), ct = cos(th);
        double smax = fmax(g->sin_t[j], g->sin_t[j + 1]);
        if (dth * j <= 0.5 * LUMIS_PI && dth * (j + 1) >= 0.5 * LUMIS_PI) smax = 1.0;
        const double rad = 0.5 * dth + 0.5 * dph * smax;
        int nt = 0;
        for (int i = 0; i < w; i++) {
            int q = lab[i];
            double dot = d[q][0] * st * cph[i] + d[q][1] * ct + d[q][2] * st * sph[i];
            if (rowmin[q] > 1.5) touched[nt++] = q;
            if (dot < rowmin[q]) rowmin[q] = dot;
        }
        for (int t = 0; t < nt; t++) {
            int q = touched[t];
            double m = rowmin[q] > 1.0 ? 1.0 : (rowmin[q] < -1.0 ? -1.0 : rowmin[q]);
            double e = acos(m) + rad;
            if (e > ext[q]) ext[q] = e;
            rowmin[q] = 2.0;
        }
    }
    for (int q = 0; q < k; q++)
        set->lights[q].extent = lumis__extent_from_min_dot(cos(fmin(ext[q], LUMIS_PI)));
    free(acc);
    free(rowmin);
    free(ext);
    free(touched);
    free(cph);
    free(d);
    return LUMIS_OK;
}

/* ---- irradiance: how faithful the point lights are to a diffuse surface ------------------ */

lumis_status lumis_light_set_irradiance(const lumis_envmap *env, const lumis_light_set *set,
                                        lumis_vec3 normal, double *set_e, double *map_e)
{
    const double len = sqrt((double)normal.x * normal.x + (double)normal.y * normal.y +
                            (double)normal.z * normal.z);
    if (!env || !set || !set_e || !map_e || !(len > 0.0) || !isfinite(len) ||
        set->w != env->width || set->h != env->height)
        return LUMIS_ERR_INVALID_ARGUMENT;
    const double n[3] = {normal.x / len, normal.y / len, normal.z / len};
    double se = 0.0;
    for (int k = 0; k < set->count; k++) {
        const lumis_light *l = &set->lights[k];
        const double c = n[0] * l->dir.x + n[1] * l->dir.y + n[2] * l->dir.z;
        if (c > 0.0) se += c * (0.2126 * l->power[0] + 0.7152 * l->power[1] + 0.0722 * l->power[2]);
    }
    lumis__geom g;
    if (lumis__geom_init(&g, env) != LUMIS_OK) return LUMIS_ERR_OUT_OF_MEMORY;
    /* the normal in the map's frame (the inverse of its rotation about +y) */
    const double mx = g.cos_rot * n[0] + g.sin_rot * n[2], my = n[1],
                 mz = -g.sin_rot * n[0] + g.cos_rot * n[2];
    double me = 0.0;
    for (int j = 0; j < g.h; j++) {
        const float *px = env->pixels + 3 * (size_t)j * (size_t)g.w;
        double row = 0.0;
        for (int i = 0; i < g.w; i++) {
            /* n . (the pixel's first moment) = the integral of n . w over the pixel */
            const double c = g.a[j] * (mx * g.cs[i] + mz * g.cc[i]) + my * g.b[j];
            if (c > 0.0) row += c * lumis__pixel_y(px + 3 * (size_t)i, 1.0);
        }
        me += row;
    }
    me *= g.scale;
    lumis__geom_free(&g);
    *set_e = se;
    *map_e = me;
    return LUMIS_OK;
}
