/* A luminaire's far-field photometry (lumis/photometry.h): the table, its symmetry, the
 * bilinear interpolation convention, and the exact flux of that interpolant.  The
 * derivations are in docs/photometric.md. */
#include "lumis/photometry.h"

#include "../core/distrib.h"
#include "../core/internal.h"
#include "photometric_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- names ---------------------------------------------------------------------------- */

/* Indexed by the enumerations' values (type: IES's codes 1 to 3; 0 has none). */
static const char *const type_names[] = {NULL, "C", "B", "A"};
static const char *const symmetry_names[] = {"none",     "rotational", "C0-C180",
                                             "C90-C270", "quadrant",   "lateral"};
static const char *const shape_names[] = {"point",    "rectangle", "box",  "disk",
                                          "cylinder", "sphere",    "other"};
LUMIS__ENUM_NAMES(lumis_photometric_type, LUMIS_PHOTOMETRIC_A + 1, type_names,
                  lumis_photometric_type_name, lumis_photometric_type_from_name);

LUMIS__ENUM_NAMES(lumis_photometric_symmetry, LUMIS_SYMMETRY_LATERAL + 1, symmetry_names,
                  lumis_photometric_symmetry_name, lumis_photometric_symmetry_from_name);

LUMIS__ENUM_NAMES(lumis_photometric_shape, LUMIS_SHAPE_OTHER + 1, shape_names,
                  lumis_photometric_shape_name, lumis_photometric_shape_from_name);

/* ---- directions and angles ------------------------------------------------------------- */

lumis_vec3 lumis_photometric_direction(lumis_photometric_type type, double h_deg, double v_deg)
{
    const double h = h_deg * DEG, v = v_deg * DEG;
    lumis_vec3 d;
    if (type == LUMIS_PHOTOMETRIC_B) {
        d.x = (float)(cos(h) * sin(v));
        d.y = (float)sin(h);
        d.z = (float)(-cos(h) * cos(v));
    } else if (type == LUMIS_PHOTOMETRIC_A) {
        d.x = (float)sin(v);
        d.y = (float)(cos(v) * sin(h));
        d.z = (float)(-cos(v) * cos(h));
    } else {
        d.x = (float)(sin(v) * cos(h));
        d.y = (float)(sin(v) * sin(h));
        d.z = (float)-cos(v);
    }
    return d;
}

static double clamp1(double x)
{
    return x < -1.0 ? -1.0 : (x > 1.0 ? 1.0 : x);
}

void lumis_photometric_angles(lumis_photometric_type type, lumis_vec3 d, double *h_deg,
                              double *v_deg)
{
    const double x = d.x, y = d.y, z = d.z;
    if (type == LUMIS_PHOTOMETRIC_B) {
        *h_deg = asin(clamp1(y)) / DEG;
        *v_deg = atan2(x, -z) / DEG;
    } else if (type == LUMIS_PHOTOMETRIC_A) {
        *v_deg = asin(clamp1(x)) / DEG;
        *h_deg = atan2(y, -z) / DEG;
    } else {
        *v_deg = acos(clamp1(-z)) / DEG;
        double c = atan2(y, x) / DEG;
        if (c < 0) c += 360.0;
        if (c >= 360.0) c = 0.0;
        *h_deg = c;
    }
}

/* ---- creation ----------------------------------------------------------------------------- */

static lumis_status check_angles(const double *a, int n, const char *what,
                                 const lumis_error_sink *errors)
{
    for (int k = 0; k < n; k++) {
        if (!isfinite(a[k]))
            return lumis__fail(errors, LUMIS_ERR_CORRUPT, "%s angle %d is not a number", what,
                               k + 1);
        if (k > 0 && !(a[k] > a[k - 1]))
            return lumis__fail(errors, LUMIS_ERR_CORRUPT,
                               "%s angles do not increase: %g after %g (angle %d)", what, a[k],
                               a[k - 1], k + 1);
    }
    return LUMIS_OK;
}

static lumis_status build_sampling(lumis_photometric *p);
static void compute_info(const lumis_photometric *p, lumis_photometric_info *info);

lumis_status lumis_photometric_create(const lumis_photometric_desc *d,
                                      const lumis_error_sink *errors, lumis_photometric **out)
{
    if (out) *out = NULL;
    if (!d || !out || !d->v_deg || !d->h_deg || !d->candela)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "photometric: no table");
    if (d->type != LUMIS_PHOTOMETRIC_A && d->type != LUMIS_PHOTOMETRIC_B &&
        d->type != LUMIS_PHOTOMETRIC_C)
        return lumis__fail(errors, LUMIS_ERR_CORRUPT,
                           "photometric type %d: expected 1 (C), 2 (B) or 3 (A)", (int)d->type);
    if (d->nv < 2 || d->nh < 1 || d->nv > 100000 || d->nh > 100000)
        return lumis__fail(errors, LUMIS_ERR_BAD_DIMENSIONS,
                           "%d vertical and %d horizontal angles: expected 2 to 100000 and 1 to "
                           "100000",
                           d->nv, d->nh);
    lumis_status st = check_angles(d->v_deg, d->nv, "vertical", errors);
    if (st == LUMIS_OK) st = check_angles(d->h_deg, d->nh, "horizontal", errors);
    if (st != LUMIS_OK) return st;
    const double mult = d->multiplier == 0.0 ? 1.0 : d->multiplier;
    if (!isfinite(mult) || mult < 0)
        return lumis__fail(errors, LUMIS_ERR_CORRUPT, "candela multiplier %g: expected >= 0", mult);
    const double v0 = d->v_deg[0], vl = d->v_deg[d->nv - 1], h0 = d->h_deg[0],
                 hl = d->h_deg[d->nh - 1];
    lumis_photometric_symmetry sym = LUMIS_SYMMETRY_NONE;
    int v_mirror = 0;
    if (d->type == LUMIS_PHOTOMETRIC_C) {
        if (v0 < 0 || vl > 180)
            return lumis__fail(errors, LUMIS_ERR_CORRUPT,
                               "vertical angles from %g to %g: type C's lie in 0 to 180", v0, vl);
        if (d->nh == 1)
            sym = LUMIS_SYMMETRY_ROTATIONAL;
        else if (h0 == 0 && hl == 90)
            sym = LUMIS_SYMMETRY_QUADRANT;
        else if (h0 == 0 && hl == 180)
            sym = LUMIS_SYMMETRY_C0_C180;
        else if (h0 == 90 && hl == 270)
            sym = LUMIS_SYMMETRY_C90_C270;
        else if (h0 == 0 && hl > 180 && hl <= 360)
            sym = LUMIS_SYMMETRY_NONE;
        else
            return lumis__fail(errors, LUMIS_ERR_CORRUPT,
                               "horizontal angles from %g to %g: type C's cover 0 alone, 0-90, "
                               "0-180, 90-270 or 0-360",
                               h0, hl);
    } else {
        if (d->nh == 1 || !((h0 == 0 || h0 == -90) && hl == 90))
            return lumis__fail(errors, LUMIS_ERR_CORRUPT,
                               "horizontal angles from %g to %g: type %s's cover -90-90 or 0-90",
                               h0, hl, lumis_photometric_type_name(d->type));
        if (!((v0 == 0 || v0 == -90) && vl == 90))
            return lumis__fail(errors, LUMIS_ERR_CORRUPT,
                               "vertical angles from %g to %g: type %s's cover -90-90 or 0-90", v0,
                               vl, lumis_photometric_type_name(d->type));
        sym = h0 == 0 ? LUMIS_SYMMETRY_LATERAL : LUMIS_SYMMETRY_NONE;
        v_mirror = v0 == 0;
    }
    const size_t n = (size_t)d->nv * (size_t)d->nh;
    for (size_t k = 0; k < n; k++)
        if (!isfinite(d->candela[k]) || d->candela[k] < 0)
            return lumis__fail(errors, LUMIS_ERR_CORRUPT,
                               "candela value %zu (horizontal angle %g, vertical %g) is %g: "
                               "expected a number >= 0",
                               k + 1, d->h_deg[k / (size_t)d->nv], d->v_deg[k % (size_t)d->nv],
                               d->candela[k]);
    const double sizes[3] = {d->width, d->length, d->height};
    for (int k = 0; k < 3; k++)
        if (!isfinite(sizes[k]) || sizes[k] < 0)
            return lumis__fail(errors, LUMIS_ERR_CORRUPT,
                               "luminous %s %g: expected a size >= 0 in metres",
                               k == 0   ? "width"
                               : k == 1 ? "length"
                                        : "height",
                               sizes[k]);
    lumis_photometric *p = calloc(1, sizeof *p);
    if (p) {
        p->v = malloc(sizeof(double) * (size_t)d->nv);
        p->h = malloc(sizeof(double) * (size_t)d->nh);
        p->cd = malloc(sizeof(double) * n);
    }
    if (!p || !p->v || !p->h || !p->cd) {
        lumis_photometric_destroy(p);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "photometric: out of memory");
    }
    memcpy(p->v, d->v_deg, sizeof(double) * (size_t)d->nv);
    memcpy(p->h, d->h_deg, sizeof(double) * (size_t)d->nh);
    double peak = 0.0;
    for (size_t k = 0; k < n; k++) {
        p->cd[k] = d->candela[k] * mult;
        peak = p->cd[k] > peak ? p->cd[k] : peak;
    }
    /* values times the multiplier, or their flux, beyond a double: no model, rather than
     * a flux of inf (or 0, and NaN downstream) */
    if (!isfinite(peak) || peak > 1e250) {
        lumis_photometric_destroy(p);
        return lumis__fail(errors, LUMIS_ERR_TOO_LARGE,
                           "the candela values x the multiplier %g overflow (more than 1e250 cd)",
                           mult);
    }
    p->type = d->type;
    p->sym = sym;
    p->v_mirror = v_mirror;
    p->nv = d->nv;
    p->nh = d->nh;
    p->desc = *d;
    p->desc.v_deg = p->desc.h_deg = p->desc.candela = NULL;
    p->desc.multiplier = mult;
    st = build_sampling(p);
    if (st != LUMIS_OK) {
        lumis_photometric_destroy(p);
        return lumis__fail(errors, st, "photometric: out of memory");
    }
    compute_info(p, &p->info);
    *out = p;
    return LUMIS_OK;
}

void lumis_photometric_destroy(lumis_photometric *p)
{
    if (!p) return;
    free(p->cell_flux);
    lumis__cdf_free(&p->cdf);
    free(p->v);
    free(p->h);
    free(p->cd);
    free(p);
}

/* ---- evaluation --------------------------------------------------------------------------- */

/* The index i with a[i] <= x <= a[i + 1] (n >= 2, a[0] <= x <= a[n - 1]). */
static int bracket(const double *a, int n, double x)
{
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        if (a[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Linear in v along horizontal row i; 0 outside the vertical range. */
static double along_v(const lumis_photometric *p, int i, double v)
{
    const double *a = p->v;
    if (v < a[0] || v > a[p->nv - 1]) return 0.0;
    const int j = bracket(a, p->nv, v);
    const double t = (v - a[j]) / (a[j + 1] - a[j]);
    const double *row = p->cd + (size_t)i * (size_t)p->nv;
    return row[j] + (row[j + 1] - row[j]) * t;
}

/* Where angles (h, v) fall in the table: its cell (as the sampler numbers them) and the
 * interpolated intensity there.  Returns 0 (and *cell -1) outside the table's light. */
static double locate(const lumis_photometric *p, double h, double v, int *cell)
{
    *cell = -1;
    if (!isfinite(h) || !isfinite(v)) return 0.0;
    const int nv = p->nv;
    if (p->type == LUMIS_PHOTOMETRIC_C) {
        if (v < p->v[0] || v > p->v[nv - 1]) return 0.0;
        const int j = bracket(p->v, nv, v);
        if (p->sym == LUMIS_SYMMETRY_ROTATIONAL) {
            *cell = j;
            return along_v(p, 0, v);
        }
        double c = fmod(h, 360.0);
        if (c < 0) c += 360.0;
        switch (p->sym) {
        case LUMIS_SYMMETRY_QUADRANT:
            if (c > 180) c = 360 - c;
            if (c > 90) c = 180 - c;
            break;
        case LUMIS_SYMMETRY_C0_C180:
            if (c > 180) c = 360 - c; /* the mirror image, not the half turn */
            break;
        case LUMIS_SYMMETRY_C90_C270:
            if (c < 90)
                c = 180 - c;
            else if (c > 270)
                c = 540 - c;
            break;
        default:
            break;
        }
        const double hl = p->h[p->nh - 1];
        if (c > hl) { /* a full table that stops short of 360: wrap to its first plane */
            const double t = (c - hl) / (360.0 - hl + p->h[0]);
            const double a = along_v(p, p->nh - 1, v), b = along_v(p, 0, v);
            *cell = (p->nh - 1) * (nv - 1) + j;
            return a + (b - a) * t;
        }
        h = c;
    } else {
        if (fabs(h) > 90 || fabs(v) > 90) return 0.0; /* behind the luminaire */
        if (p->sym == LUMIS_SYMMETRY_LATERAL) h = fabs(h);
        if (p->v_mirror) v = fabs(v);
        if (v < p->v[0] || v > p->v[nv - 1]) return 0.0;
    }
    if (h < p->h[0] || h > p->h[p->nh - 1]) return 0.0;
    const int i = bracket(p->h, p->nh, h), j = bracket(p->v, nv, v);
    const double t = (h - p->h[i]) / (p->h[i + 1] - p->h[i]);
    const double a = along_v(p, i, v), b = along_v(p, i + 1, v);
    *cell = i * (nv - 1) + j;
    return a + (b - a) * t;
}

double lumis_photometric_intensity_at(const lumis_photometric *p, double h, double v)
{
    int cell;
    return p ? locate(p, h, v, &cell) : 0.0;
}

double lumis_photometric_intensity(const lumis_photometric *p, lumis_vec3 d)
{
    if (!p) return 0.0;
    double h, v;
    lumis_photometric_angles(p->type, d, &h, &v);
    return lumis_photometric_intensity_at(p, h, v);
}

/* ---- the flux ----------------------------------------------------------------------------- */

/* The integral over [a0, a1] (radians) of the linear function from x to y times sin. */
static double f_sin(double a0, double a1, double x, double y)
{
    const double w = a1 - a0;
    return x * (cos(a0) - cos(a1)) + (y - x) / w * (sin(a1) - sin(a0) - w * cos(a1));
}

/* The same times cos. */
static double f_cos(double a0, double a1, double x, double y)
{
    const double w = a1 - a0;
    return x * (sin(a1) - sin(a0)) + (y - x) / w * (w * sin(a1) + cos(a1) - cos(a0));
}

/* The bilinear cell between horizontal angles h0, h1 and vertical v0, v1 (degrees), with
 * the values at its corners (iHV), integrated against the solid angle.  vmax clips the
 * vertical extent (type C: the part below it, for the downward flux). */
double lumis__phot_cell(const lumis_photometric *p, double h0, double h1, double v0, double v1,
                        double i00, double i01, double i10, double i11, double vmax)
{
    if (v0 >= vmax) return 0.0;
    if (v1 > vmax) { /* the part below vmax: the values at vmax on the cell's edges */
        const double t = (vmax - v0) / (v1 - v0);
        i01 = i00 + (i01 - i00) * t;
        i11 = i10 + (i11 - i10) * t;
        v1 = vmax;
    }
    const double H0 = h0 * DEG, H1 = h1 * DEG, V0 = v0 * DEG, V1 = v1 * DEG;
    if (p->type == LUMIS_PHOTOMETRIC_C)
        return (H1 - H0) / 2 * (f_sin(V0, V1, i00, i01) + f_sin(V0, V1, i10, i11));
    if (p->type == LUMIS_PHOTOMETRIC_A)
        return (H1 - H0) / 2 * (f_cos(V0, V1, i00, i01) + f_cos(V0, V1, i10, i11));
    return (V1 - V0) / 2 * (f_cos(H0, H1, i00, i10) + f_cos(H0, H1, i01, i11));
}

/* The integral over the sphere of the interpolated table (vmax: type C's part with gamma
 * below vmax degrees; 180 or more: all of it). */
static double flux_below(const lumis_photometric *p, double vmax)
{
    const int nv = p->nv;
    double sum = 0.0;
    const double *cd = p->cd;
    if (p->type == LUMIS_PHOTOMETRIC_C && p->sym == LUMIS_SYMMETRY_ROTATIONAL) {
        for (int j = 0; j + 1 < nv; j++)
            sum += lumis__phot_cell(p, 0, 360, p->v[j], p->v[j + 1], cd[j], cd[j + 1], cd[j],
                                    cd[j + 1], vmax);
        return sum;
    }
    for (int i = 0; i + 1 < p->nh; i++)
        for (int j = 0; j + 1 < nv; j++) {
            const double *a = cd + (size_t)i * (size_t)nv, *b = a + nv;
            sum += lumis__phot_cell(p, p->h[i], p->h[i + 1], p->v[j], p->v[j + 1], a[j], a[j + 1],
                                    b[j], b[j + 1], vmax);
        }
    double mult = 1.0;
    switch (p->sym) {
    case LUMIS_SYMMETRY_QUADRANT:
        mult = 4.0;
        break;
    case LUMIS_SYMMETRY_C0_C180:
    case LUMIS_SYMMETRY_C90_C270:
    case LUMIS_SYMMETRY_LATERAL:
        mult = 2.0;
        break;
    default:
        break;
    }
    if (p->v_mirror) mult *= 2.0;
    const double hl = p->h[p->nh - 1];
    if (p->type == LUMIS_PHOTOMETRIC_C && p->sym == LUMIS_SYMMETRY_NONE && hl < 360.0) {
        const double *a = cd + (size_t)(p->nh - 1) * (size_t)nv, *b = cd; /* the wrap to 360 */
        for (int j = 0; j + 1 < nv; j++)
            sum += lumis__phot_cell(p, hl, 360.0 + p->h[0], p->v[j], p->v[j + 1], a[j], a[j + 1],
                                    b[j], b[j + 1], vmax);
    }
    return sum * mult;
}

/* ---- info ------------------------------------------------------------------------------- */

double lumis_photometric_plane_intensity(const lumis_photometric *p, int k, double t)
{
    if (!p) return 0.0;
    if (p->type == LUMIS_PHOTOMETRIC_C) {
        const double c = k == 0 ? (t >= 0 ? 0.0 : 180.0) : (t >= 0 ? 90.0 : 270.0);
        return lumis_photometric_intensity_at(p, c, fabs(t));
    }
    return k == 0 ? lumis_photometric_intensity_at(p, t, 0.0)
                  : lumis_photometric_intensity_at(p, 0.0, t);
}

/* Plane k's intensity at t degrees, t anywhere on the circle (it wraps). */
static double on_circle(const lumis_photometric *p, int k, double t)
{
    t -= 360.0 * floor((t + 180.0) / 360.0); /* into [-180, 180) */
    return lumis_photometric_plane_intensity(p, k, t);
}

/* Plane k's peak: where the interpolant peaks, at one of the table's angles as the plane
 * meets them (both signs), else on a fine scan; the one nearest the aim on ties. */
static double plane_peak(const lumis_photometric *p, int k, double *at)
{
    double peak = -1.0, tp = 0.0;
    const int c = p->type == LUMIS_PHOTOMETRIC_C;
    const double *a = c || k == 1 ? p->v : p->h;
    const int n = c || k == 1 ? p->nv : p->nh;
    for (int s = 0; s <= 7200 + 2 * n; s++) {
        const double t = s <= 7200 ? -180.0 + s * 0.05 : (s % 2 ? 1 : -1) * a[(s - 7201) / 2];
        const double i = on_circle(p, k, t);
        if (i > peak || (i == peak && (fabs(t) < fabs(tp) || (fabs(t) == fabs(tp) && t > tp)))) {
            peak = i;
            tp = t;
        }
    }
    *at = tp;
    return peak;
}

/* The full width of the arc around the plane's peak where the intensity stays >= share x
 * the peak, on the whole circle of the plane (an uplight's beam spans the zenith): 0.05°
 * steps, each crossing then bisected on the interpolant; 360 when the whole circle is
 * lit that much. */
static double spread(const lumis_photometric *p, int k, double share)
{
    const double step = 0.05;
    double tp;
    const double peak = plane_peak(p, k, &tp);
    if (!(peak > 0)) return 0.0;
    const double level = share * peak;
    double reach[2];
    for (int side = 0; side < 2; side++) {
        const double dir = side ? 1.0 : -1.0;
        reach[side] = 360.0;
        for (int s = 1; s * step <= 360.0; s++) {
            if (on_circle(p, k, tp + dir * s * step) >= level) continue;
            double lo = (s - 1) * step, hi = s * step; /* lit at lo, not at hi */
            for (int b = 0; b < 48; b++) {
                const double mid = 0.5 * (lo + hi);
                if (on_circle(p, k, tp + dir * mid) >= level)
                    lo = mid;
                else
                    hi = mid;
            }
            reach[side] = 0.5 * (lo + hi);
            break;
        }
    }
    const double width = reach[0] + reach[1];
    return width < 360.0 ? width : 360.0;
}

/* The info, once, at creation (its beam scans cost thousands of lookups: not for every
 * caller that wants the shape). */
static void compute_info(const lumis_photometric *p, lumis_photometric_info *info)
{
    memset(info, 0, sizeof *info);
    info->type = p->type;
    info->symmetry = p->sym;
    info->shape = p->desc.shape;
    info->width = p->desc.width;
    info->length = p->desc.length;
    info->height = p->desc.height;
    info->nv = p->nv;
    info->nh = p->nh;
    info->v_first = p->v[0];
    info->v_last = p->v[p->nv - 1];
    info->h_first = p->h[0];
    info->h_last = p->h[p->nh - 1];
    info->lamp_lumens = p->desc.lamp_lumens;
    info->luminaire_lumens = p->desc.luminaire_lumens;
    info->flux = p->flux; /* the sampler's cells', summed at creation */
    info->downward_fraction = p->type != LUMIS_PHOTOMETRIC_C ? 1.0
                              : info->flux > 0               ? flux_below(p, 90.0) / info->flux
                                                             : 0.0;
    for (int i = 0; i < p->nh; i++)
        for (int j = 0; j < p->nv; j++) {
            const double c = p->cd[(size_t)i * (size_t)p->nv + (size_t)j];
            if (c > info->max_candela) {
                info->max_candela = c;
                info->max_h = p->h[i];
                info->max_v = p->v[j];
            }
        }
    for (int k = 0; k < 2; k++) {
        info->beam_deg[k] = spread(p, k, 0.5);
        info->field_deg[k] = spread(p, k, 0.1);
    }
}

lumis_status lumis_photometric_get_info(const lumis_photometric *p, lumis_photometric_info *info)
{
    if (!p || !info) return LUMIS_ERR_INVALID_ARGUMENT;
    *info = p->info;
    return LUMIS_OK;
}

/* ---- sampling in proportion to intensity ------------------------------------------------ */

/* Cell c's angles (degrees) and corner values (iHV: at h0 or h1, v0 or v1). */
void lumis__phot_cell_corners(const lumis_photometric *p, int c, double *h0, double *h1, double *v0,
                              double *v1, double i[4])
{
    const int nv = p->nv;
    const int ci = p->sym == LUMIS_SYMMETRY_ROTATIONAL ? 0 : c / (nv - 1), j = c % (nv - 1);
    *v0 = p->v[j];
    *v1 = p->v[j + 1];
    const double *a, *b;
    if (p->sym == LUMIS_SYMMETRY_ROTATIONAL) {
        *h0 = 0;
        *h1 = 360;
        a = b = p->cd;
    } else if (ci == p->nh - 1) { /* the wrap cell */
        *h0 = p->h[p->nh - 1];
        *h1 = 360.0 + p->h[0];
        a = p->cd + (size_t)ci * (size_t)nv;
        b = p->cd;
    } else {
        *h0 = p->h[ci];
        *h1 = p->h[ci + 1];
        a = p->cd + (size_t)ci * (size_t)nv;
        b = a + nv;
    }
    i[0] = a[j];     /* h0 v0 */
    i[1] = a[j + 1]; /* h0 v1 */
    i[2] = b[j];     /* h1 v0 */
    i[3] = b[j + 1]; /* h1 v1 */
}

static lumis_status build_sampling(lumis_photometric *p)
{
    const int nv = p->nv;
    const int wrap =
        p->type == LUMIS_PHOTOMETRIC_C && p->sym == LUMIS_SYMMETRY_NONE && p->h[p->nh - 1] < 360.0;
    p->ncells = p->sym == LUMIS_SYMMETRY_ROTATIONAL ? nv - 1 : (p->nh - 1 + wrap) * (nv - 1);
    p->nrep = p->sym == LUMIS_SYMMETRY_QUADRANT ? 4
              : p->sym == LUMIS_SYMMETRY_C0_C180 || p->sym == LUMIS_SYMMETRY_C90_C270 ||
                      p->sym == LUMIS_SYMMETRY_LATERAL
                  ? 2
                  : 1;
    if (p->v_mirror) p->nrep *= 2;
    p->cell_flux = malloc(sizeof(double) * (size_t)(p->ncells > 0 ? p->ncells : 1));
    if (!p->cell_flux) return LUMIS_ERR_OUT_OF_MEMORY;
    p->flux = 0.0;
    for (int c = 0; c < p->ncells; c++) {
        double h0, h1, v0, v1, i[4];
        lumis__phot_cell_corners(p, c, &h0, &h1, &v0, &v1, i);
        p->cell_flux[c] = lumis__phot_cell(p, h0, h1, v0, v1, i[0], i[1], i[2], i[3], 1e9);
        if (!(p->cell_flux[c] > 0)) p->cell_flux[c] = 0.0; /* rounding below zero */
        p->flux += p->cell_flux[c] * p->nrep;
    }
    if (!(p->flux > 0)) return LUMIS_OK; /* a black table: nothing to sample */
    return lumis__cdf_build(&p->cdf, p->cell_flux, (uint32_t)p->ncells, 1);
}

/* The x in [x0, x1] (radians) where the integral from x0 of (A + B (x - x0)) w(x), w = sin
 * (use_sin) or cos, reaches the share u of its whole: Newton's steps kept inside a
 * bisection's bracket. */
static double invert_edge(int use_sin, double x0, double x1, double A, double B, double u)
{
    const double w = x1 - x0;
    /* G(x) over [x0, x] */
#define G(x)                                                                                       \
    (use_sin ? A * (cos(x0) - cos(x)) + B * (sin(x) - sin(x0) - ((x)-x0) * cos(x))                 \
             : A * (sin(x) - sin(x0)) + B * (((x)-x0) * sin(x) + cos(x) - cos(x0)))
    const double target = u * G(x1);
    double lo = x0, hi = x1, x = x0 + u * w;
    for (int it = 0; it < 60; it++) {
        const double g = G(x) - target;
        if (g > 0)
            hi = x;
        else
            lo = x;
        const double dens = (A + B * (x - x0)) * (use_sin ? sin(x) : cos(x));
        double next = dens > 0 ? x - g / dens : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (fabs(next - x) < 1e-13 * (1 + fabs(x))) return next;
        x = next;
    }
#undef G
    return x;
}

/* The s in [0, 1) with density proportional to a + (b - a) s at the share u. */
static double invert_linear(double a, double b, double u)
{
    const double d = b - a;
    if (fabs(d) <= 1e-9 * fabs(a + b)) return u;
    const double s = (-a + sqrt(fmax(0.0, a * a + u * (b * b - a * a)))) / d;
    return s < 0 ? 0 : s > 1 ? 1 : s;
}

double lumis_photometric_flux(const lumis_photometric *p)
{
    return p ? p->flux : 0.0;
}

double lumis_photometric_pdf(const lumis_photometric *p, lumis_vec3 d)
{
    if (!p || !(p->flux > 0)) return 0.0;
    double h, v;
    lumis_photometric_angles(p->type, d, &h, &v);
    int c;
    const double I = locate(p, h, v, &c);
    if (c < 0 || !(p->cell_flux[c] > 0)) return 0.0;
    return lumis__cdf_prob(&p->cdf, (uint32_t)c) / p->nrep * I / p->cell_flux[c];
}

lumis_status lumis_photometric_sample(const lumis_photometric *p, double u0, double u1,
                                      lumis_vec3 *dir, double *pdf)
{
    if (!p || !dir || !pdf) return LUMIS_ERR_INVALID_ARGUMENT;
    *pdf = 0.0;
    if (!(p->flux > 0)) return LUMIS_ERR_INVALID_ARGUMENT; /* a black table */
    double frac = 0.0;
    const int c = (int)lumis__cdf_sample(&p->cdf, u0, &frac);
    int r = (int)(frac * p->nrep);
    if (r >= p->nrep) r = p->nrep - 1;
    frac = frac * p->nrep - r; /* the rest of u0, for the cell's first coordinate */
    double h0, h1, v0, v1, i[4];
    lumis__phot_cell_corners(p, c, &h0, &h1, &v0, &v1, i);
    const double H0 = h0 * DEG, H1 = h1 * DEG, V0 = v0 * DEG, V1 = v1 * DEG;
    double h, v;
    if (p->type == LUMIS_PHOTOMETRIC_B) { /* the weight cos H: H first, then V given H */
        const double A = 0.5 * (i[0] + i[1]), B = (0.5 * (i[2] + i[3]) - A) / (H1 - H0);
        const double x = invert_edge(0, H0, H1, A, B, frac), t = (x - H0) / (H1 - H0);
        const double a = i[0] + (i[2] - i[0]) * t, b = i[1] + (i[3] - i[1]) * t;
        h = x / DEG;
        v = v0 + (v1 - v0) * invert_linear(a, b, u1);
    } else { /* C (sin) and A (cos): the weight is on the vertical angle */
        const double A = 0.5 * (i[0] + i[2]), B = (0.5 * (i[1] + i[3]) - A) / (V1 - V0);
        const double x = invert_edge(p->type == LUMIS_PHOTOMETRIC_C, V0, V1, A, B, frac);
        const double t = (x - V0) / (V1 - V0);
        const double a = i[0] + (i[1] - i[0]) * t, b = i[2] + (i[3] - i[2]) * t;
        v = x / DEG;
        h = h0 + (h1 - h0) * invert_linear(a, b, u1);
    }
    /* the replica: the symmetry's image r of the table's cell */
    if (p->type == LUMIS_PHOTOMETRIC_C) {
        switch (p->sym) {
        case LUMIS_SYMMETRY_QUADRANT:
            h = r == 1 ? 180 - h : r == 2 ? 180 + h : r == 3 ? 360 - h : h;
            break;
        case LUMIS_SYMMETRY_C0_C180:
            h = r ? 360 - h : h;
            break;
        case LUMIS_SYMMETRY_C90_C270:
            h = r ? 180 - h : h;
            break;
        default:
            break;
        }
    } else {
        int bit = 0;
        if (p->sym == LUMIS_SYMMETRY_LATERAL && ((r >> bit++) & 1)) h = -h;
        if (p->v_mirror && ((r >> bit) & 1)) v = -v;
    }
    *dir = lumis_photometric_direction(p->type, h, v);
    int cc;
    const double I = locate(p, h, v, &cc);
    *pdf = lumis__cdf_prob(&p->cdf, (uint32_t)c) / p->nrep * I / p->cell_flux[c];
    return *pdf > 0 ? LUMIS_OK : LUMIS_ERR_INVALID_ARGUMENT;
}

double lumis_photometric_flux_within(const lumis_photometric *p, double gamma_deg)
{
    if (!p) return 0.0;
    if (p->type != LUMIS_PHOTOMETRIC_C) return p->flux; /* A, B: all of it lies in front */
    return flux_below(p, gamma_deg);
}

/* ---- batches ------------------------------------------------------------------------------ */

lumis_status lumis_photometric_intensity_n(const lumis_photometric *p, const lumis_vec3 *dirs,
                                           size_t n, double *out)
{
    if (!p || (n && (!dirs || !out))) return LUMIS_ERR_INVALID_ARGUMENT;
    for (size_t k = 0; k < n; k++) out[k] = lumis_photometric_intensity(p, dirs[k]);
    return LUMIS_OK;
}

lumis_status lumis_photometric_intensity_at_n(const lumis_photometric *p, const double *h_deg,
                                              size_t nh, const double *v_deg, size_t nv,
                                              double *out)
{
    if (!p || (nh && nv && (!h_deg || !v_deg || !out))) return LUMIS_ERR_INVALID_ARGUMENT;
    for (size_t i = 0; i < nh && nv; i++)
        for (size_t j = 0; j < nv; j++)
            out[i * nv + j] = lumis_photometric_intensity_at(p, h_deg[i], v_deg[j]);
    return LUMIS_OK;
}

lumis_status lumis_photometric_pdf_n(const lumis_photometric *p, const lumis_vec3 *dirs, size_t n,
                                     double *out)
{
    if (!p || (n && (!dirs || !out))) return LUMIS_ERR_INVALID_ARGUMENT;
    for (size_t k = 0; k < n; k++) out[k] = lumis_photometric_pdf(p, dirs[k]);
    return LUMIS_OK;
}

lumis_status lumis_photometric_sample_n(const lumis_photometric *p, const double *u, size_t n,
                                        lumis_vec3 *dirs, double *pdf)
{
    if (!p || (n && (!u || !dirs || !pdf))) return LUMIS_ERR_INVALID_ARGUMENT;
    lumis_status first = LUMIS_OK;
    for (size_t k = 0; k < n; k++) {
        const lumis_status st =
            lumis_photometric_sample(p, u[2 * k], u[2 * k + 1], dirs + k, pdf + k);
        if (first == LUMIS_OK) first = st;
    }
    return first;
}
