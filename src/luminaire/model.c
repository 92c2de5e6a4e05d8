/* The light-field luminaire model: bases, the descriptor, the copied images and their
 * summed-area tables, radiance L(u -> s), and rigid placement (docs/luminaire.md). */
#include "internal.h"

#include "../core/distrib.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- bases ------------------------------------------------------------------------- */

static const char *const basis_names[] = {"default", "quadratic", "bspline"};

LUMIS__ENUM_NAMES(lumis_luminaire_basis, LUMIS_BASIS_COUNT, basis_names, lumis_luminaire_basis_name,
                  lumis_luminaire_basis_from_name);

double lumis_luminaire_basis_eval(lumis_luminaire_basis basis, double x)
{
    /* Goesele et al.: 1 - 2x^2 on [0, 1/2], 2 (1 - x)^2 on [1/2, 1]; the B-spline: 3/4 - x^2
     * on [0, 1/2], (3/2 - x)^2 / 2 on [1/2, 3/2].  Both C1, and their integer translates add
     * up to one.  The one formula the samplers use (internal.h). */
    return lumis__lum_profile(basis == LUMIS_BASIS_BSPLINE, x);
}

double lumis_luminaire_basis_radius(lumis_luminaire_basis basis)
{
    return basis == LUMIS_BASIS_BSPLINE ? 1.5 : 1.0;
}

/* ---- creation ---------------------------------------------------------------------- */

static int finite_pos(double x)
{
    return isfinite(x) && x > 0.0;
}

lumis_status lumis__lum_check(const lumis_luminaire_desc *d)
{
    const lumis_error_sink *e = &d->errors;
    if (!finite_pos(d->delta))
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT,
                           "luminaire: delta (distance from U to S) must be finite and > 0, "
                           "got %g",
                           d->delta);
    if ((unsigned)d->basis >= (unsigned)LUMIS_BASIS_COUNT)
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT, "luminaire: unknown basis %d",
                           (int)d->basis);
    if (d->grid[0] < 1 || d->grid[1] < 1 || (long)d->grid[0] * d->grid[1] > LUMIS__LUM_MAX_IMAGES)
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT,
                           "luminaire: grid %d x %d: need W, H >= 1 and W H <= %d images",
                           d->grid[0], d->grid[1], LUMIS__LUM_MAX_IMAGES);
    /* the per-point tables hold one entry per grid column and row (estimator.c) */
    if (d->grid[0] > LUMIS__LUM_MAX_GRID || d->grid[1] > LUMIS__LUM_MAX_GRID)
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT,
                           "luminaire: grid %d x %d: at most %d functions along x and along y",
                           d->grid[0], d->grid[1], LUMIS__LUM_MAX_GRID);
    if (!finite_pos(d->grid_spacing[0]) || !finite_pos(d->grid_spacing[1]))
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT,
                           "luminaire: grid spacing %g x %g must be finite and > 0",
                           d->grid_spacing[0], d->grid_spacing[1]);
    if (!isfinite(d->grid_origin[0]) || !isfinite(d->grid_origin[1]) ||
        !isfinite(d->image_origin[0]) || !isfinite(d->image_origin[1]))
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT, "luminaire: non-finite origin");
    if (d->width < 1 || d->height < 1 || d->width > LUMIS__LUM_MAX_SIDE ||
        d->height > LUMIS__LUM_MAX_SIDE)
        return lumis__fail(e, LUMIS_ERR_BAD_DIMENSIONS,
                           "luminaire: images of %d x %d pixels: each side must be in 1..%d",
                           d->width, d->height, LUMIS__LUM_MAX_SIDE);
    if (!finite_pos(d->image_size[0]) || !finite_pos(d->image_size[1]))
        return lumis__fail(e, LUMIS_ERR_INVALID_ARGUMENT,
                           "luminaire: image size on S %g x %g must be finite and > 0",
                           d->image_size[0], d->image_size[1]);
    return LUMIS_OK;
}

/* Builds from already-sanitised RGB (ownership of rgb passes to the luminaire). */
static lumis_status build(const lumis_luminaire_desc *d, float *rgb, size_t replaced,
                          lumis_luminaire **out)
{
    lumis_luminaire *l = calloc(1, sizeof *l);
    if (!l) {
        free(rgb);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    l->delta = d->delta;
    l->basis = d->basis == LUMIS_BASIS_DEFAULT ? LUMIS_BASIS_QUADRATIC : d->basis;
    l->radius = lumis_luminaire_basis_radius(l->basis);
    l->gw = d->grid[0];
    l->gh = d->grid[1];
    l->m = l->gw * l->gh;
    l->gx0 = d->grid_origin[0];
    l->gy0 = d->grid_origin[1];
    l->hx = d->grid_spacing[0];
    l->hy = d->grid_spacing[1];
    l->inv_hx = 1.0 / l->hx;
    l->inv_hy = 1.0 / l->hy;
    l->psi_scale = 1.0 / (l->delta * l->delta * l->hx * l->hy);
    l->w = d->width;
    l->h = d->height;
    l->sx0 = d->image_origin[0];
    l->sy0 = d->image_origin[1];
    l->sw = d->image_size[0];
    l->sh = d->image_size[1];
    l->dx = l->sw / l->w;
    l->dy = l->sh / l->h;
    l->inv_pixel_area = 1.0 / (l->dx * l->dy);
    l->rgb = rgb;
    l->replaced = replaced;
    l->errors = d->errors;

    const size_t npx = (size_t)l->w * (size_t)l->h;
    const size_t ntab = ((size_t)l->w + 1) * ((size_t)l->h + 1);
    const size_t M = (size_t)l->m;
    l->sat = malloc(M * ntab * sizeof(uint32_t));
    l->unit = malloc(M * sizeof(double));
    l->power = malloc(M * sizeof(double));
    l->nz = malloc(M * 4 * sizeof(int));
    l->ptrs = malloc(M * sizeof(const float *));
    double *wts = malloc(npx * sizeof(double));
    uint64_t *units = malloc(npx * sizeof(uint64_t));
    if (!l->sat || !l->unit || !l->power || !l->nz || !l->ptrs || !wts || !units) {
        free(wts);
        free(units);
        lumis_luminaire_destroy(l);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    const size_t stride = (size_t)l->h + 1;
    for (size_t m = 0; m < M; m++) {
        const float *img = rgb + m * npx * 3;
        l->ptrs[m] = img;
        /* Column-major weights, as the table is laid out. */
        double sum = 0.0;
        for (int i = 0; i < l->w; i++)
            for (int j = 0; j < l->h; j++) {
                double y = lumis__lum_y(img + ((size_t)j * (size_t)l->w + (size_t)i) * 3);
                wts[(size_t)i * (size_t)l->h + (size_t)j] = y;
                sum += y;
            }
        uint32_t *t = l->sat + m * ntab;
        memset(t, 0, ntab * sizeof(uint32_t));
        l->power[m] = sum * l->dx * l->dy;
        int *nz = l->nz + 4 * m;
        nz[0] = l->w, nz[1] = -1, nz[2] = l->h, nz[3] = -1;
        if (sum <= 0.0) {
            l->unit[m] = 0.0;
            continue;
        }
        lumis__quantize(wts, npx, (uint64_t)LUMIS__LUM_UNITS, units);
        l->unit[m] = l->power[m] / LUMIS__LUM_UNITS;
        /* t(i, j) = sum of units over columns < i and rows < j; the total, 2^32 - 1, fits. */
        for (int i = 0; i < l->w; i++) {
            uint64_t col = 0;
            for (int j = 0; j < l->h; j++) {
                const uint64_t q = units[(size_t)i * (size_t)l->h + (size_t)j];
                if (q) {
                    nz[0] = nz[0] < i ? nz[0] : i;
                    nz[1] = i;
                    nz[2] = nz[2] < j ? nz[2] : j;
                    nz[3] = nz[3] > j ? nz[3] : j;
                }
                col += q;
                t[(size_t)(i + 1) * stride + (size_t)j + 1] =
                    (uint32_t)(t[(size_t)i * stride + (size_t)j + 1] + col);
            }
        }
        l->total_power += l->power[m];
    }
    free(wts);
    free(units);
    l->bytes = sizeof *l + M * npx * 3 * sizeof(float) + M * ntab * sizeof(uint32_t) +
               M * (2 * sizeof(double) + 4 * sizeof(int) + sizeof(const float *));
    *out = l;
    return LUMIS_OK;
}

lumis_status lumis__lum_build(const lumis_luminaire_desc *d, float *rgb, size_t replaced,
                              lumis_luminaire **out)
{
    lumis_status st = lumis__lum_check(d);
    if (st != LUMIS_OK) {
        free(rgb);
        return st;
    }
    return build(d, rgb, replaced, out);
}

lumis_status lumis_luminaire_check(const lumis_luminaire_desc *d)
{
    return d ? lumis__lum_check(d) : LUMIS_ERR_INVALID_ARGUMENT;
}

lumis_status lumis_luminaire_create(const lumis_luminaire_desc *d, lumis_luminaire **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!d) return LUMIS_ERR_INVALID_ARGUMENT;
    lumis_status st = lumis__lum_check(d);
    if (st != LUMIS_OK) return st;
    const int M = d->grid[0] * d->grid[1];
    if (!d->pixels)
        return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "luminaire: pixels is NULL (need %d image pointers)", M);
    for (int m = 0; m < M; m++)
        if (!d->pixels[m])
            return lumis__fail(&d->errors, LUMIS_ERR_INVALID_ARGUMENT,
                               "luminaire: pixels[%d] (image %d, %d of the %d x %d grid) is NULL",
                               m, m % d->grid[0], m / d->grid[0], d->grid[0], d->grid[1]);
    const size_t n = (size_t)d->width * (size_t)d->height * 3;
    float *rgb = malloc((size_t)M * n * sizeof(float));
    if (!rgb) return LUMIS_ERR_OUT_OF_MEMORY;
    size_t replaced = 0;
    for (int m = 0; m < M; m++) {
        float *dst = rgb + (size_t)m * n;
        for (size_t k = 0; k < n; k++) {
            float v = d->pixels[m][k];
            if (!(isfinite(v) && v >= 0.0f)) {
                v = 0.0f;
                replaced++;
            }
            dst[k] = v;
        }
    }
    if (replaced)
        lumis__fail(&d->errors, LUMIS_OK,
                    "luminaire: %zu negative or non-finite pixel values replaced by 0", replaced);
    return build(d, rgb, replaced + d->replaced_before, out);
}

void lumis_luminaire_destroy(lumis_luminaire *l)
{
    if (!l) return;
    free(l->rgb);
    free(l->sat);
    free(l->unit);
    free(l->power);
    free(l->nz);
    free(l->ptrs);
    free(l);
}

void lumis_luminaire_get_info(const lumis_luminaire *l, lumis_luminaire_info *out)
{
    memset(out, 0, sizeof *out);
    out->images = l->m;
    out->grid[0] = l->gw;
    out->grid[1] = l->gh;
    out->width = l->w;
    out->height = l->h;
    out->delta = l->delta;
    out->pixel[0] = l->dx;
    out->pixel[1] = l->dy;
    out->replaced = l->replaced;
    out->bytes = l->bytes;
    out->total_power = l->total_power;
}

void lumis_luminaire_get_desc(const lumis_luminaire *l, lumis_luminaire_desc *d)
{
    memset(d, 0, sizeof *d);
    d->delta = l->delta;
    d->basis = l->basis;
    d->grid[0] = l->gw;
    d->grid[1] = l->gh;
    d->grid_origin[0] = l->gx0;
    d->grid_origin[1] = l->gy0;
    d->grid_spacing[0] = l->hx;
    d->grid_spacing[1] = l->hy;
    d->width = l->w;
    d->height = l->h;
    d->image_origin[0] = l->sx0;
    d->image_origin[1] = l->sy0;
    d->image_size[0] = l->sw;
    d->image_size[1] = l->sh;
    d->pixels = l->ptrs;
    d->errors = l->errors;
}

const float *lumis_luminaire_image(const lumis_luminaire *l, int m)
{
    if (!l || m < 0 || m >= l->m) return NULL;
    return l->ptrs[m];
}

/* ---- geometry ---------------------------------------------------------------------- */

lumis__where lumis__lum_where(const lumis_luminaire *l, double pz)
{
    if (!(pz > 0.0)) return LUMIS__BEHIND;
    /* Within 1e-7 delta of S the projected boxes are narrower than double precision can
     * sample meaningfully; the integral there is that of p on S to O(1e-7). */
    if (fabs(pz - l->delta) <= 1e-7 * l->delta) return LUMIS__ON_S;
    return LUMIS__FRONT;
}

int lumis__lum_pixel(const lumis_luminaire *l, double sx, double sy, int *i, int *j)
{
    double x = (sx - l->sx0) / l->dx, y = (sy - l->sy0) / l->dy;
    if (!(x >= 0.0 && x < l->w && y >= 0.0 && y < l->h)) return 0;
    *i = lumis__clampi((int)x, 0, l->w - 1);
    *j = lumis__clampi((int)y, 0, l->h - 1);
    return 1;
}

/* ---- one sample's geometry (both strategies' last step) ------------------------- */

void lumis__lum_finish_u(const lumis_luminaire *l, double px, double py, double pz, int m,
                         double ux, double uy, double pdf, int count, lumis_luminaire_sample *o)
{
    o->s[0] = px;
    o->s[1] = py;
    o->u[0] = ux;
    o->u[1] = uy;
    o->image = m;
    o->count = count;
    o->measure = LUMIS_LUM_AREA_U;
    o->pdf = (float)pdf;
    o->radiance.r = o->radiance.g = o->radiance.b = 0.0f;
    o->weight = 0.0f;
    const double vx = ux - px, vy = uy - py, vz = -pz;
    const double dist = sqrt(vx * vx + vy * vy + vz * vz);
    o->distance = (float)dist;
    int i, j;
    if (!(dist > 0.0) || !(pdf > 0.0) || !isfinite(ux) || !isfinite(uy)) {
        o->dir.x = o->dir.y = 0.0f;
        o->dir.z = -1.0f;
        return;
    }
    const double inv = 1.0 / dist;
    o->dir.x = (float)(vx * inv);
    o->dir.y = (float)(vy * inv);
    o->dir.z = (float)(vz * inv);
    if (!lumis__lum_pixel(l, px, py, &i, &j)) return;
    /* r and cos at U: cos = z / r. */
    lumis__lum_shade(l, m % l->gw, m / l->gw, l->rgb + (size_t)m * (size_t)l->w * (size_t)l->h * 3,
                     px, py, ux, uy, i, j, pdf, count, pz, dist * dist * dist, o);
}

int lumis__lum_box_axis(const lumis_luminaire *l, int axis, int index, double pc, double pz,
                        double *lo, double *hi)
{
    /* s = k u + (delta / z) p, k = (z - delta) / z: the line from u through p meets S. */
    const double k = (pz - l->delta) / pz, c = l->delta / pz;
    const double h = axis ? l->hy : l->hx, o = axis ? l->gy0 : l->gx0;
    const double s0 = axis ? l->sy0 : l->sx0, ps = axis ? l->dy : l->dx;
    const double n = axis ? l->h : l->w;
    const double center = o + index * h, r = l->radius * h;
    double a0 = k * (center - r) + c * pc, a1 = k * (center + r) + c * pc;
    if (k < 0.0) { /* p between U and S: the projection flips */
        const double t = a0;
        a0 = a1;
        a1 = t;
    }
    a0 = (a0 - s0) / ps;
    a1 = (a1 - s0) / ps;
    *lo = a0 > 0.0 ? a0 : 0.0;
    *hi = a1 < n ? a1 : n;
    return *lo < *hi;
}

int lumis__lum_box(const lumis_luminaire *l, int m, double px, double py, double pz, lumis__box *b)
{
    const int ax = lumis__lum_box_axis(l, 0, m % l->gw, px, pz, &b->x0, &b->x1);
    const int ay = lumis__lum_box_axis(l, 1, m / l->gw, py, pz, &b->y0, &b->y1);
    return ax && ay;
}

/* ---- radiance ---------------------------------------------------------------------- */

lumis_rgb lumis_luminaire_radiance(const lumis_luminaire *l, double ux, double uy, double sx,
                                   double sy)
{
    lumis_rgb r = {0.0f, 0.0f, 0.0f};
    int i, j;
    if (!lumis__lum_pixel(l, sx, sy, &i, &j)) return r;
    const double ddx = sx - ux, ddy = sy - uy;
    const double d2 = ddx * ddx + ddy * ddy + l->delta * l->delta;
    /* delta^2 / cos^4 theta = d2^2 / delta^2; over the cell area, the integral of Phi_m. */
    const double psi0 = d2 * d2 / (l->delta * l->delta * l->hx * l->hy);
    /* The functions whose support contains u: grid positions within radius of u. */
    const double fa = (ux - l->gx0) / l->hx, fb = (uy - l->gy0) / l->hy;
    int a0 = (int)ceil(fa - l->radius), a1 = (int)floor(fa + l->radius);
    int b0 = (int)ceil(fb - l->radius), b1 = (int)floor(fb + l->radius);
    if (a0 < 0) a0 = 0;
    if (b0 < 0) b0 = 0;
    if (a1 > l->gw - 1) a1 = l->gw - 1;
    if (b1 > l->gh - 1) b1 = l->gh - 1;
    double acc[3] = {0.0, 0.0, 0.0};
    const size_t npx = (size_t)l->w * (size_t)l->h;
    for (int b = b0; b <= b1; b++)
        for (int a = a0; a <= a1; a++) {
            const double phi = lumis_luminaire_basis_eval(l->basis, fa - a) *
                               lumis_luminaire_basis_eval(l->basis, fb - b);
            if (phi <= 0.0) continue;
            const float *px =
                l->rgb + ((size_t)(a + l->gw * b) * npx + (size_t)j * (size_t)l->w + (size_t)i) * 3;
            for (int c = 0; c < 3; c++) acc[c] += phi * (double)px[c];
        }
    r.r = (float)(acc[0] * psi0);
    r.g = (float)(acc[1] * psi0);
    r.b = (float)(acc[2] * psi0);
    return r;
}

/* ---- rigid placement --------------------------------------------------------------- */

lumis_rigid lumis_rigid_identity(void)
{
    lumis_rigid x = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}};
    return x;
}

lumis_status lumis_rigid_check(const lumis_rigid *x)
{
    if (!x) return LUMIS_ERR_INVALID_ARGUMENT;
    for (int a = 0; a < 3; a++) {
        if (!isfinite(x->t[a])) return LUMIS_ERR_INVALID_ARGUMENT;
        for (int b = 0; b < 3; b++) {
            double d = 0.0;
            for (int k = 0; k < 3; k++) d += x->r[3 * k + a] * x->r[3 * k + b];
            if (!(fabs(d - (a == b ? 1.0 : 0.0)) <= 1e-6)) return LUMIS_ERR_INVALID_ARGUMENT;
        }
    }
    const double *r = x->r;
    double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                 r[2] * (r[3] * r[7] - r[4] * r[6]);
    return det > 0.0 ? LUMIS_OK : LUMIS_ERR_INVALID_ARGUMENT;
}

static lumis_vec3 mul(const double *r, int transpose, double x, double y, double z)
{
    lumis_vec3 o;
    if (transpose) {
        o.x = (float)(r[0] * x + r[3] * y + r[6] * z);
        o.y = (float)(r[1] * x + r[4] * y + r[7] * z);
        o.z = (float)(r[2] * x + r[5] * y + r[8] * z);
    } else {
        o.x = (float)(r[0] * x + r[1] * y + r[2] * z);
        o.y = (float)(r[3] * x + r[4] * y + r[5] * z);
        o.z = (float)(r[6] * x + r[7] * y + r[8] * z);
    }
    return o;
}

lumis_vec3 lumis_rigid_point_to_local(const lumis_rigid *x, lumis_vec3 w)
{
    return mul(x->r, 1, w.x - x->t[0], w.y - x->t[1], w.z - x->t[2]);
}

lumis_vec3 lumis_rigid_point_to_world(const lumis_rigid *x, lumis_vec3 l)
{
    lumis_vec3 o = mul(x->r, 0, l.x, l.y, l.z);
    o.x = (float)(o.x + x->t[0]);
    o.y = (float)(o.y + x->t[1]);
    o.z = (float)(o.z + x->t[2]);
    return o;
}

lumis_vec3 lumis_rigid_dir_to_local(const lumis_rigid *x, lumis_vec3 w)
{
    return mul(x->r, 1, w.x, w.y, w.z);
}

lumis_vec3 lumis_rigid_dir_to_world(const lumis_rigid *x, lumis_vec3 l)
{
    return mul(x->r, 0, l.x, l.y, l.z);
}
