/* Clear-sky environment map: Preetham, Shirley and Smits, "A Practical Analytic Model for
 * Daylight" (SIGGRAPH 1999), plus a sun disk attenuated as in that paper's appendix and a
 * Lambertian ground lit by both.  Units: kcd/m^2 of luminance.  Derivation and the
 * constants' sources: docs/sky.md. */
#include "lumis/envmap.h"
#include "lumis/sky.h"

#include "../core/internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Angular radius of the sun seen from the earth (0.2666 degrees). */
#define SUN_RADIUS_RAD 0.004654
/* Solar illuminance outside the atmosphere, in klx (the luminous solar constant). */
#define SUN_ILLUMINANCE_TOA_KLX 128.0

typedef struct perez {
    double a, b, c, d, e;
} perez;

/* Perez et al.'s sky luminance distribution F(theta, gamma). */
static double perez_f(const perez *p, double cos_theta, double gamma, double cos_gamma)
{
    return (1.0 + p->a * exp(p->b / cos_theta)) *
           (1.0 + p->c * exp(p->d * gamma) + p->e * cos_gamma * cos_gamma);
}

static void xyY_to_rgb(double x, double y, double Y, double rgb[3])
{
    if (y <= 0.0) {
        rgb[0] = rgb[1] = rgb[2] = 0.0;
        return;
    }
    double X = x * Y / y, Z = (1.0 - x - y) * Y / y;
    rgb[0] = 3.2404542 * X - 1.5371385 * Y - 0.4985314 * Z;
    rgb[1] = -0.9692660 * X + 1.8760108 * Y + 0.0415560 * Z;
    rgb[2] = 0.0556434 * X - 0.2040259 * Y + 1.0572252 * Z;
    for (int c = 0; c < 3; c++)
        if (rgb[c] < 0.0) rgb[c] = 0.0; /* out-of-gamut blues near the sun */
}

typedef struct sky_model {
    perez py, px, pyy; /* luminance Y, chromaticities x and y */
    double zenith_Y, zenith_x, zenith_y;
    double norm_Y, norm_x, norm_y; /* F(0, theta_s) of each */
    double sun_dir[3];
} sky_model;

static void sky_model_init(sky_model *m, double T, double theta_s, double phi_s)
{
    m->py = (perez){0.1787 * T - 1.4630, -0.3554 * T + 0.4275, -0.0227 * T + 5.3251,
                    0.1206 * T - 2.5771, -0.0670 * T + 0.3703};
    m->px = (perez){-0.0193 * T - 0.2592, -0.0665 * T + 0.0008, -0.0004 * T + 0.2125,
                    -0.0641 * T - 0.8989, -0.0033 * T + 0.0452};
    m->pyy = (perez){-0.0167 * T - 0.2608, -0.0950 * T + 0.0092, -0.0079 * T + 0.2102,
                     -0.0441 * T - 1.6537, -0.0109 * T + 0.0529};

    double chi = (4.0 / 9.0 - T / 120.0) * (LUMIS_PI - 2.0 * theta_s);
    m->zenith_Y = (4.0453 * T - 4.9710) * tan(chi) - 0.2155 * T + 2.4192;
    double t2 = T * T, s = theta_s, s2 = s * s, s3 = s2 * s;
    m->zenith_x = (0.00166 * s3 - 0.00375 * s2 + 0.00209 * s) * t2 +
                  (-0.02903 * s3 + 0.06377 * s2 - 0.03202 * s + 0.00394) * T +
                  (0.11693 * s3 - 0.21196 * s2 + 0.06052 * s + 0.25886);
    m->zenith_y = (0.00275 * s3 - 0.00610 * s2 + 0.00317 * s) * t2 +
                  (-0.04214 * s3 + 0.08970 * s2 - 0.04153 * s + 0.00516) * T +
                  (0.15346 * s3 - 0.26756 * s2 + 0.06670 * s + 0.26688);
    double cs = cos(theta_s);
    m->norm_Y = perez_f(&m->py, 1.0, theta_s, cs);
    m->norm_x = perez_f(&m->px, 1.0, theta_s, cs);
    m->norm_y = perez_f(&m->pyy, 1.0, theta_s, cs);
    m->sun_dir[0] = sin(theta_s) * cos(phi_s);
    m->sun_dir[1] = cs;
    m->sun_dir[2] = sin(theta_s) * sin(phi_s);
}

/* Sky radiance (RGB, kcd/m^2) in a direction above the horizon. */
static void sky_radiance(const sky_model *m, const double d[3], double rgb[3])
{
    double cos_theta = d[1] > 1e-4 ? d[1] : 1e-4;
    double cos_gamma = d[0] * m->sun_dir[0] + d[1] * m->sun_dir[1] + d[2] * m->sun_dir[2];
    if (cos_gamma > 1.0) cos_gamma = 1.0;
    if (cos_gamma < -1.0) cos_gamma = -1.0;
    double gamma = acos(cos_gamma);
    double Y = m->zenith_Y * perez_f(&m->py, cos_theta, gamma, cos_gamma) / m->norm_Y;
    double x = m->zenith_x * perez_f(&m->px, cos_theta, gamma, cos_gamma) / m->norm_x;
    double y = m->zenith_y * perez_f(&m->pyy, cos_theta, gamma, cos_gamma) / m->norm_y;
    xyY_to_rgb(x, y, Y > 0.0 ? Y : 0.0, rgb);
}

/* Transmittance of the atmosphere along the sun's path at wavelength lambda (um):
 * Rayleigh and aerosol (Angstrom) extinction with Preetham's appendix constants. */
static double sun_transmittance(double lambda_um, double T, double theta_s)
{
    double zen_deg = theta_s * 180.0 / LUMIS_PI;
    double m = 1.0 / (cos(theta_s) + 0.15 * pow(93.885 - zen_deg, -1.253));
    double beta = 0.04608 * T - 0.04586;
    double rayleigh = 0.008735 * pow(lambda_um, -4.08);
    double aerosol = beta * pow(lambda_um, -1.3);
    return exp(-m * (rayleigh + aerosol));
}

/* Fraction of a disk above a line at signed distance h (in radii) below its centre. */
static double disk_fraction_above(double h)
{
    if (h >= 1.0) return 1.0;
    if (h <= -1.0) return 0.0;
    return 1.0 - (acos(h) - h * sqrt(1.0 - h * h)) / LUMIS_PI;
}

/* Adds the sun disk: each pixel near the sun gets its covered fraction, measured with
 * SS x SS subsamples uniform in solid angle, then rescaled so the disk's visible solid
 * angle is met exactly - the sun's power is right at any resolution. */
static lumis_status add_sun(float *px, int w, int h, const sky_model *m, const double sun_rgb[3],
                            double visible_omega)
{
    enum { SS = 16 };
    const double cos_r = cos(SUN_RADIUS_RAD);
    double theta_s = acos(m->sun_dir[1]);
    /* Rows and columns that can touch the disk, with a pixel of margin. */
    int j0 = lumis__clampi((int)floor((theta_s - SUN_RADIUS_RAD) / LUMIS_PI * h) - 1, 0, h - 1);
    int j1 = lumis__clampi((int)floor((theta_s + SUN_RADIUS_RAD) / LUMIS_PI * h) + 1, 0, h - 1);
    double sin_t = sin(theta_s);
    double half_u = sin_t > sin(SUN_RADIUS_RAD) ? asin(sin(SUN_RADIUS_RAD) / sin_t) : LUMIS_PI;
    double uc = atan2(m->sun_dir[2], m->sun_dir[0]) / (2.0 * LUMIS_PI);
    if (uc < 0.0) uc += 1.0;
    int ic = lumis__clampi((int)(uc * w), 0, w - 1);
    int nu = (int)ceil(half_u / (2.0 * LUMIS_PI) * w) + 1;
    int i_first = ic - nu, ncols = 2 * nu + 1;
    if (ncols >= w) { /* near a pole the disk may reach every column */
        i_first = 0;
        ncols = w;
    }

    size_t cap = (size_t)(j1 - j0 + 1) * (size_t)ncols;
    double *frac = malloc(cap * sizeof(double));
    int *idx = malloc(cap * 2 * sizeof(int));
    if (!frac || !idx) {
        free(frac);
        free(idx);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    double covered = 0.0;
    size_t count = 0;
    for (int j = j0; j <= j1; j++) {
        double omega = lumis_equirect_solid_angle(w, h, j);
        double mu0 = cos(LUMIS_PI * j / h), mu1 = cos(LUMIS_PI * (j + 1) / h);
        for (int c = 0; c < ncols; c++) {
            int i = ((i_first + c) % w + w) % w;
            int hits = 0;
            for (int sy = 0; sy < SS; sy++) {
                double cy = mu0 + (mu1 - mu0) * (sy + 0.5) / SS;
                if (cy <= 0.0) continue; /* below the horizon: hidden by the ground */
                double st = sqrt(fmax(0.0, 1.0 - cy * cy));
                for (int sx = 0; sx < SS; sx++) {
                    double phi = 2.0 * LUMIS_PI * (i + (sx + 0.5) / SS) / w;
                    double d = st * cos(phi) * m->sun_dir[0] + cy * m->sun_dir[1] +
                               st * sin(phi) * m->sun_dir[2];
                    hits += d >= cos_r;
                }
            }
            if (!hits) continue;
            frac[count] = (double)hits / (SS * SS);
            idx[2 * count] = i;
            idx[2 * count + 1] = j;
            covered += frac[count] * omega;
            count++;
        }
    }
    if (count == 0) {
        /* The disk slipped between subsamples (tiny maps): the pixel of its centre, or the
         * lowest sky row if the centre is under the horizon, takes all of it. */
        int j = lumis__clampi((int)(theta_s / LUMIS_PI * h), 0, h - 1);
        while (j > 0 && LUMIS_PI * j / h >= 0.5 * LUMIS_PI) j--;
        frac[0] = visible_omega / lumis_equirect_solid_angle(w, h, j);
        idx[0] = ic;
        idx[1] = j;
        covered = visible_omega;
        count = 1;
    }
    double k = visible_omega / covered;
    for (size_t n = 0; n < count; n++) {
        float *p = px + ((size_t)idx[2 * n + 1] * (size_t)w + (size_t)idx[2 * n]) * 3;
        for (int c = 0; c < 3; c++) p[c] += (float)(sun_rgb[c] * frac[n] * k);
    }
    free(frac);
    free(idx);
    return LUMIS_OK;
}

lumis_status lumis_sky_create(const lumis_sky_desc *desc, lumis_image **out)
{
    static const lumis_sky_desc zero_desc;
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!desc) desc = &zero_desc;
    const lumis_error_sink *err = &desc->errors;
    int w = desc->width ? desc->width : 1024;
    int h = desc->height ? desc->height : (w / 2 > 0 ? w / 2 : 1);
    double T = desc->turbidity == 0.0f ? 2.5 : desc->turbidity;
    /* zero means the default (DESIGN.md); the horizon is asked for by name */
    if (desc->sun_at_horizon && desc->sun_elevation_deg != 0.0f)
        return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT,
                           "sky: sun_at_horizon with a sun elevation of %g degrees: give one",
                           (double)desc->sun_elevation_deg);
    double elev = desc->sun_at_horizon              ? 0.0
                  : desc->sun_elevation_deg == 0.0f ? LUMIS_SKY_DEFAULT_ELEVATION_DEG
                                                    : desc->sun_elevation_deg;
    double albedo = desc->ground_albedo == 0.0f ? 0.1 : fmax(0.0, desc->ground_albedo);
    if (!(T >= 1.7 && T <= 10.0))
        return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT,
                           "sky: turbidity %g outside the model's range [1.7, 10]", T);
    if (!(elev >= 0.0 && elev <= 90.0))
        return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT,
                           "sky: sun elevation %g outside [0, 90] degrees (the model has no "
                           "twilight)",
                           elev);
    if (!isfinite(desc->sun_azimuth_deg) || !(albedo <= 1.0))
        return lumis__fail(err, LUMIS_ERR_INVALID_ARGUMENT,
                           "sky: azimuth must be finite and ground albedo at most 1");
    lumis_status st = lumis_image_create(w, h, out);
    if (st != LUMIS_OK)
        return lumis__fail(err, st, "sky: %d x %d: %s", w, h, lumis_status_string(st));
    float *px = (*out)->pixels;

    double theta_s = (90.0 - elev) * LUMIS_PI / 180.0;
    double phi_s = fmod((double)desc->sun_azimuth_deg, 360.0) * LUMIS_PI / 180.0;
    sky_model m;
    sky_model_init(&m, T, theta_s, phi_s);

    /* Sky above the horizon; E accumulates the horizontal irradiance it gives. */
    double E[3] = {0, 0, 0};
    for (int j = 0; j < h; j++) {
        double t0 = LUMIS_PI * j / h, t1 = LUMIS_PI * (j + 1) / h;
        if (t0 >= 0.5 * LUMIS_PI) break;
        /* A row across the horizon (odd heights) holds sky over its upper part only. */
        double t_hi = fmin(t1, 0.5 * LUMIS_PI);
        double omega_row = lumis_equirect_solid_angle(w, h, j);
        double sky_frac = (cos(t0) - cos(t_hi)) / (cos(t0) - cos(t1));
        double tc = 0.5 * (t0 + t_hi);
        double s_t = sin(tc), ct = cos(tc);
        for (int i = 0; i < w; i++) {
            double phi = 2.0 * LUMIS_PI * (i + 0.5) / w;
            double d[3] = {s_t * cos(phi), ct, s_t * sin(phi)}, rgb[3];
            sky_radiance(&m, d, rgb);
            float *p = px + ((size_t)j * (size_t)w + (size_t)i) * 3;
            for (int c = 0; c < 3; c++) {
                p[c] = (float)(rgb[c] * sky_frac);
                E[c] += rgb[c] * ct * omega_row * sky_frac;
            }
        }
    }

    /* The sun: top-of-atmosphere luminance, white, times the transmittance at
     * representative wavelengths of the Rec. 709 primaries. */
    double omega_sun = 2.0 * LUMIS_PI * (1.0 - cos(SUN_RADIUS_RAD));
    double visible = disk_fraction_above(elev * LUMIS_PI / 180.0 / SUN_RADIUS_RAD);
    if (!desc->no_sun && visible > 0.0) {
        static const double lambda[3] = {0.65, 0.55, 0.45};
        double L_toa = SUN_ILLUMINANCE_TOA_KLX / omega_sun, sun_rgb[3];
        double cos_sun = fmax(0.0, cos(theta_s));
        for (int c = 0; c < 3; c++) {
            sun_rgb[c] = L_toa * sun_transmittance(lambda[c], T, fmin(theta_s, 0.5 * LUMIS_PI));
            E[c] += sun_rgb[c] * omega_sun * visible * cos_sun;
        }
        st = add_sun(px, w, h, &m, sun_rgb, omega_sun * visible);
        if (st != LUMIS_OK) {
            lumis_image_destroy(*out);
            *out = NULL;
            return lumis__fail(err, st, "sky: out of memory");
        }
    }

    /* Lambertian ground: L = albedo E / pi below the horizon (partly, in a straddling row). */
    for (int j = 0; j < h; j++) {
        double t0 = LUMIS_PI * j / h, t1 = LUMIS_PI * (j + 1) / h;
        if (t1 <= 0.5 * LUMIS_PI) continue;
        double t_lo = fmax(t0, 0.5 * LUMIS_PI);
        double ground_frac = (cos(t_lo) - cos(t1)) / (cos(t0) - cos(t1));
        for (int i = 0; i < w; i++) {
            float *p = px + ((size_t)j * (size_t)w + (size_t)i) * 3;
            for (int c = 0; c < 3; c++) p[c] += (float)(albedo * E[c] / LUMIS_PI * ground_frac);
        }
    }
    return LUMIS_OK;
}
