/* Synthetic acquisition: an emitter with a known light field (disks behind a patterned
 * plate) photographed through each basis function, as Goesele et al.'s setup would, giving
 * the images C_m of a luminaire whose ground truth is known.  docs/luminaire.md,
 * "Synthetic acquisition". */
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Transmission of the plate at (x, y), per channel. */
static void plate(const lumis_emitter_desc *e, double x, double y, double *t)
{
    t[0] = t[1] = t[2] = 1.0;
    if (e->pattern == LUMIS_PATTERN_NONE) return;
    long a = (long)floor(x / e->period[0]);
    long b = e->pattern == LUMIS_PATTERN_CHECKER ? (long)floor(y / e->period[1]) : 0;
    if (((a + b) & 1) == 0) return;
    const int white = e->tint.r == 0.0f && e->tint.g == 0.0f && e->tint.b == 0.0f;
    const double tint[3] = {white ? 1.0 : e->tint.r, white ? 1.0 : e->tint.g,
                            white ? 1.0 : e->tint.b};
    for (int c = 0; c < 3; c++) t[c] = (1.0 - e->contrast) * tint[c];
}

/* Disk k's radiance along the ray from (ux, uy, 0) towards (tx, ty, tz), tz > 0. */
static void disk_radiance(const lumis_emitter_desc *e, int k, double ux, double uy, double tx,
                          double ty, double tz, double *rgb)
{
    rgb[0] = rgb[1] = rgb[2] = 0.0;
    const lumis_emitter_disk *d = &e->disks[k];
    const double ex = tx - ux, ey = ty - uy;
    /* Backwards to the disk's plane: u + (t - u) z_k / tz. */
    const double f = d->center[2] / tz;
    const double qx = ux + ex * f - d->center[0], qy = uy + ey * f - d->center[1];
    if (qx * qx + qy * qy > d->radius * d->radius) return;
    const double cosine = tz / sqrt(ex * ex + ey * ey + tz * tz);
    const double lobe = d->exponent > 0.0 ? pow(cosine, d->exponent) : 1.0;
    double t[3];
    const double fp = e->plate_z / tz;
    plate(e, ux + ex * fp, uy + ey * fp, t);
    rgb[0] = d->radiance.r * lobe * t[0];
    rgb[1] = d->radiance.g * lobe * t[1];
    rgb[2] = d->radiance.b * lobe * t[2];
}

lumis_rgb lumis_emitter_radiance(const lumis_emitter_desc *e, double delta, double ux, double uy,
                                 double sx, double sy)
{
    double acc[3] = {0.0, 0.0, 0.0}, c[3];
    for (int k = 0; k < e->disk_count; k++) {
        disk_radiance(e, k, ux, uy, sx, sy, delta, c);
        for (int i = 0; i < 3; i++) acc[i] += c[i];
    }
    lumis_rgb r = {(float)acc[0], (float)acc[1], (float)acc[2]};
    return r;
}

/* The disk of U whose rays towards (tx, ty, tz) cross disk k: centre and radius. */
static void footprint(const lumis_emitter_disk *d, double tx, double ty, double tz, double *cx,
                      double *cy, double *r)
{
    /* u (1 - z_k / tz) + t z_k / tz = c. */
    const double a = 1.0 - d->center[2] / tz, f = d->center[2] / tz;
    *cx = (d->center[0] - tx * f) / a;
    *cy = (d->center[1] - ty * f) / a;
    *r = d->radius / a;
}

/* Node i of the n-point Gauss-Legendre rule on [0, 1] and its weight (Newton on P_n). */
static void gauss01(int n, int i, double *t, double *w)
{
    double z = cos(LUMIS_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
    for (int it = 0; it < 100; it++) {
        double p0 = 1.0, p1 = 0.0;
        for (int j = 0; j < n; j++) {
            const double p2 = p1;
            p1 = p0;
            p0 = ((2.0 * j + 1.0) * z * p1 - j * p2) / (j + 1.0);
        }
        dp = n * (z * p0 - p1) / (z * z - 1.0);
        const double dz = p0 / dp;
        z -= dz;
        if (fabs(dz) < 1e-15) break;
    }
    *t = 0.5 * (1.0 - z);
    *w = 1.0 / ((1.0 - z * z) * dp * dp);
}

/* Polar quadrature of the unit disk: Gauss-Legendre in t = rho^2 (dA = dt dphi / 2), the
 * midpoint rule in phi (staggered ring to ring); weights sum to pi. */
static int disk_nodes(int radial, int angular, double *x, double *y, double *w)
{
    int n = 0;
    for (int i = 0; i < radial; i++) {
        double t, wt;
        gauss01(radial, i, &t, &wt);
        const double rho = sqrt(t);
        for (int a = 0; a < angular; a++) {
            const double phi = 2.0 * LUMIS_PI * (a + ((i & 1) ? 0.25 : 0.75)) / angular;
            x[n] = rho * cos(phi);
            y[n] = rho * sin(phi);
            w[n] = wt * LUMIS_PI / angular;
            n++;
        }
    }
    return n;
}

static lumis_status check_emitter(const lumis_emitter_desc *e, const lumis_error_sink *sink)
{
    if (!e || e->disk_count < 1 || !e->disks)
        return lumis__fail(sink, LUMIS_ERR_INVALID_ARGUMENT, "emitter: needs at least one disk");
    for (int k = 0; k < e->disk_count; k++) {
        const lumis_emitter_disk *d = &e->disks[k];
        if (!(d->center[2] < 0.0) || !(d->radius > 0.0) || !isfinite(d->radius) ||
            !(d->exponent >= 0.0) || !isfinite(d->center[0]) || !isfinite(d->center[1]))
            return lumis__fail(sink, LUMIS_ERR_INVALID_ARGUMENT,
                               "emitter: disk %d must lie behind U (z < 0) with radius > 0 and "
                               "exponent >= 0 (z %g, radius %g, exponent %g)",
                               k, d->center[2], d->radius, d->exponent);
        if (e->pattern != LUMIS_PATTERN_NONE && !(e->plate_z > d->center[2]))
            return lumis__fail(sink, LUMIS_ERR_INVALID_ARGUMENT,
                               "emitter: the plate (z %g) must lie between disk %d (z %g) and U",
                               e->plate_z, k, d->center[2]);
    }
    if ((unsigned)e->pattern >= (unsigned)LUMIS_PATTERN_COUNT)
        return lumis__fail(sink, LUMIS_ERR_INVALID_ARGUMENT, "emitter: unknown pattern %d",
                           (int)e->pattern);
    if (e->pattern != LUMIS_PATTERN_NONE &&
        (!(e->plate_z < 0.0) || !(e->period[0] > 0.0) ||
         (e->pattern == LUMIS_PATTERN_CHECKER && !(e->period[1] > 0.0)) ||
         !(e->contrast >= 0.0 && e->contrast <= 1.0)))
        return lumis__fail(sink, LUMIS_ERR_INVALID_ARGUMENT,
                           "emitter: a pattern needs plate_z < 0, periods > 0 and contrast in "
                           "[0, 1]");
    return LUMIS_OK;
}

#define MAX_NODES 4096

lumis_status lumis_emitter_irradiance(const lumis_emitter_desc *e, lumis_vec3 p, lumis_vec3 n,
                                      int radial, int angular, lumis_rgb *out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    out->r = out->g = out->b = 0.0f;
    lumis_status st = check_emitter(e, NULL);
    if (st != LUMIS_OK) return st;
    if (radial <= 0) radial = 48;
    if (angular <= 0) angular = 96;
    if (radial > 64 || (long)radial * angular > 65536) return LUMIS_ERR_INVALID_ARGUMENT;
    const double px = p.x, py = p.y, pz = p.z;
    if (!(pz > 0.0)) return LUMIS_OK;
    const double nl = sqrt((double)n.x * n.x + (double)n.y * n.y + (double)n.z * n.z);
    if (!(nl > 0.0)) return LUMIS_ERR_INVALID_ARGUMENT;
    double acc[3] = {0.0, 0.0, 0.0};
    /* Nodes are generated ring by ring to stay allocation-free at any size. */
    for (int k = 0; k < e->disk_count; k++) {
        double fx, fy, fr;
        footprint(&e->disks[k], px, py, pz, &fx, &fy, &fr);
        for (int i = 0; i < radial; i++) {
            double t, wt;
            gauss01(radial, i, &t, &wt);
            const double rho = sqrt(t) * fr;
            for (int a = 0; a < angular; a++) {
                const double phi = 2.0 * LUMIS_PI * (a + 0.5) / angular;
                const double ux = fx + rho * cos(phi), uy = fy + rho * sin(phi);
                double c[3];
                disk_radiance(e, k, ux, uy, px, py, pz, c);
                if (c[0] == 0.0 && c[1] == 0.0 && c[2] == 0.0) continue;
                const double vx = ux - px, vy = uy - py, vz = -pz;
                const double r2 = vx * vx + vy * vy + vz * vz, r = sqrt(r2);
                const double cp = (n.x * vx + n.y * vy + n.z * vz) / (nl * r);
                if (!(cp > 0.0)) continue;
                const double g = (pz / r) * cp / r2;
                const double wgt = wt * (LUMIS_PI / angular) * fr * fr * g;
                for (int ch = 0; ch < 3; ch++) acc[ch] += wgt * c[ch];
            }
        }
    }
    out->r = (float)acc[0];
    out->g = (float)acc[1];
    out->b = (float)acc[2];
    return LUMIS_OK;
}

lumis_status lumis_luminaire_acquire(const lumis_luminaire_desc *layout,
                                     const lumis_emitter_desc *e, const lumis_acquire_desc *acq,
                                     lumis_luminaire **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    if (!layout) return LUMIS_ERR_INVALID_ARGUMENT;
    lumis_acquire_desc a = {0};
    if (acq) a = *acq;
    const lumis_error_sink *sink = a.errors.fn ? &a.errors : &layout->errors;
    lumis_status st = check_emitter(e, sink);
    if (st != LUMIS_OK) return st;
    const int ns = a.samples_s > 0 ? a.samples_s : 2;
    const int nr = a.samples_radial > 0 ? a.samples_radial : 6;
    const int na = a.samples_angular > 0 ? a.samples_angular : 16;
    if (ns > 64 || nr > 64 || (long)nr * na > MAX_NODES)
        return lumis__fail(sink, LUMIS_ERR_INVALID_ARGUMENT,
                           "acquire: at most 64 sensor samples per axis and %d nodes per disk",
                           MAX_NODES);
    lumis_luminaire_desc d = *layout;
    if (a.errors.fn) d.errors = a.errors;
    st = lumis__lum_check(&d);
    if (st != LUMIS_OK) return st;
    const lumis_luminaire_basis basis =
        d.basis == LUMIS_BASIS_DEFAULT ? LUMIS_BASIS_QUADRATIC : d.basis;
    const double radius = lumis_luminaire_basis_radius(basis);
    const int W = d.grid[0], H = d.grid[1], M = W * H;
    const size_t npx = (size_t)d.width * (size_t)d.height;
    float *rgb = calloc((size_t)M * npx * 3, sizeof(float));
    double *nx = malloc(MAX_NODES * sizeof(double)), *ny = malloc(MAX_NODES * sizeof(double));
    double *nw = malloc(MAX_NODES * sizeof(double));
    double *acc = malloc((size_t)M * 3 * sizeof(double));
    if (!rgb || !nx || !ny || !nw || !acc) {
        free(rgb), free(nx), free(ny), free(nw), free(acc);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    const int nn = disk_nodes(nr, na, nx, ny, nw);
    const double delta = d.delta, hx = d.grid_spacing[0], hy = d.grid_spacing[1];
    const double pdx = d.image_size[0] / d.width, pdy = d.image_size[1] / d.height;
    for (int j = 0; j < d.height; j++)
        for (int i = 0; i < d.width; i++) {
            memset(acc, 0, (size_t)M * 3 * sizeof(double));
            for (int sa = 0; sa < ns; sa++)
                for (int sb = 0; sb < ns; sb++) {
                    const double sx = d.image_origin[0] + (i + (sa + 0.5) / ns) * pdx;
                    const double sy = d.image_origin[1] + (j + (sb + 0.5) / ns) * pdy;
                    for (int k = 0; k < e->disk_count; k++) {
                        double fx, fy, fr;
                        footprint(&e->disks[k], sx, sy, delta, &fx, &fy, &fr);
                        for (int q = 0; q < nn; q++) {
                            const double ux = fx + fr * nx[q], uy = fy + fr * ny[q];
                            const double ga = (ux - d.grid_origin[0]) / hx;
                            const double gb = (uy - d.grid_origin[1]) / hy;
                            int a0 = (int)ceil(ga - radius), a1 = (int)floor(ga + radius);
                            int b0 = (int)ceil(gb - radius), b1 = (int)floor(gb + radius);
                            if (a0 < 0) a0 = 0;
                            if (b0 < 0) b0 = 0;
                            if (a1 > W - 1) a1 = W - 1;
                            if (b1 > H - 1) b1 = H - 1;
                            if (a0 > a1 || b0 > b1) continue;
                            double c[3];
                            disk_radiance(e, k, ux, uy, sx, sy, delta, c);
                            if (c[0] == 0.0 && c[1] == 0.0 && c[2] == 0.0) continue;
                            /* E_m(s) integrand: L Phi_m cos^4 theta / delta^2, times the node's
                             * area (fr^2 w) and the sensor sample's share of the pixel. */
                            const double ex = sx - ux, ey = sy - uy;
                            const double e2 = ex * ex + ey * ey + delta * delta;
                            const double f =
                                delta * delta / (e2 * e2) * fr * fr * nw[q] / ((double)ns * ns);
                            double pa[4], pb[4];
                            for (int aa = a0; aa <= a1; aa++)
                                pa[aa - a0] = lumis_luminaire_basis_eval(basis, ga - aa);
                            for (int bb = b0; bb <= b1; bb++)
                                pb[bb - b0] = lumis_luminaire_basis_eval(basis, gb - bb);
                            for (int bb = b0; bb <= b1; bb++)
                                for (int aa = a0; aa <= a1; aa++) {
                                    const double phi = pa[aa - a0] * pb[bb - b0] * f;
                                    if (phi <= 0.0) continue;
                                    double *o = acc + (size_t)(aa + W * bb) * 3;
                                    o[0] += phi * c[0];
                                    o[1] += phi * c[1];
                                    o[2] += phi * c[2];
                                }
                        }
                    }
                }
            for (int m = 0; m < M; m++)
                for (int c = 0; c < 3; c++)
                    rgb[((size_t)m * npx + (size_t)j * (size_t)d.width + (size_t)i) * 3 +
                        (size_t)c] = (float)acc[(size_t)m * 3 + (size_t)c];
        }
    free(nx), free(ny), free(nw), free(acc);
    d.pixels = NULL;
    return lumis__lum_build(&d, rgb, 0, out);
}

/* ---- presets ----------------------------------------------------------------------- */

lumis_status lumis_luminaire_preset_get(lumis_luminaire_preset preset, lumis_luminaire_desc *l,
                                        lumis_emitter_desc *e, lumis_emitter_disk *disks)
{
    if (!l || !e || !disks) return LUMIS_ERR_INVALID_ARGUMENT;
    int W, H, w, h;
    switch (preset) {
    case LUMIS_PRESET_BIKE:
        W = 9, H = 7, w = 300, h = 300;
        break;
    case LUMIS_PRESET_CAR:
        W = 11, H = 9, w = 256, h = 256;
        break;
    case LUMIS_PRESET_SMALL:
        W = 5, H = 4, w = 24, h = 20;
        break;
    default:
        return LUMIS_ERR_INVALID_ARGUMENT;
    }
    memset(l, 0, sizeof *l);
    memset(e, 0, sizeof *e);
    /* Units: millimetres.  A grid of 10 mm cells centred on the axis, S 100 mm in front,
     * the images covering the grid plus 30 degrees of beam on each side. */
    const double hstep = 10.0, delta = 100.0, spread = delta * tan(LUMIS_PI / 6.0);
    l->delta = delta;
    l->basis = LUMIS_BASIS_QUADRATIC;
    l->grid[0] = W;
    l->grid[1] = H;
    l->grid_spacing[0] = l->grid_spacing[1] = hstep;
    l->grid_origin[0] = -0.5 * (W - 1) * hstep;
    l->grid_origin[1] = -0.5 * (H - 1) * hstep;
    l->width = w;
    l->height = h;
    const double ex = 0.5 * (W - 1) * hstep + spread, ey = 0.5 * (H - 1) * hstep + spread;
    l->image_origin[0] = -ex;
    l->image_origin[1] = -ey;
    l->image_size[0] = 2.0 * ex;
    l->image_size[1] = 2.0 * ey;
    /* A headlight: bright small disks with narrow lobes behind a striped lens. */
    const double s = preset == LUMIS_PRESET_SMALL ? 0.4 : 1.0;
    const lumis_emitter_disk d[4] = {
        {{-10.0 * s, 0.0, -20.0}, 4.0 * s, {40.0f, 38.0f, 33.0f}, 40.0},
        {{10.0 * s, 1.0 * s, -22.0}, 4.0 * s, {36.0f, 37.0f, 40.0f}, 40.0},
        {{0.0, 7.0 * s, -30.0}, 3.0 * s, {60.0f, 50.0f, 30.0f}, 80.0},
        {{0.0, -7.0 * s, -18.0}, 2.5 * s, {20.0f, 20.0f, 20.0f}, 20.0},
    };
    memcpy(disks, d, sizeof d);
    e->disks = disks;
    e->disk_count = 4;
    e->pattern = LUMIS_PATTERN_STRIPES;
    e->plate_z = -8.0;
    e->period[0] = e->period[1] = 2.5 * s;
    e->contrast = 0.6;
    e->tint.r = 1.0f;
    e->tint.g = 0.85f;
    e->tint.b = 0.6f;
    return LUMIS_OK;
}

static const char *const preset_names[] = {"bike", "car", "small"};

LUMIS__ENUM_NAMES(lumis_luminaire_preset, LUMIS_PRESET_SMALL + 1, preset_names,
                  lumis_luminaire_preset_name, lumis_luminaire_preset_from_name);

lumis_status lumis_luminaire_preset_create(lumis_luminaire_preset preset,
                                           lumis_luminaire_basis basis,
                                           const lumis_error_sink *errors, lumis_luminaire **out)
{
    if (!out) return LUMIS_ERR_INVALID_ARGUMENT;
    *out = NULL;
    lumis_luminaire_desc layout;
    lumis_emitter_desc emitter;
    lumis_emitter_disk disks[4];
    lumis_status st = lumis_luminaire_preset_get(preset, &layout, &emitter, disks);
    if (st != LUMIS_OK) return lumis__fail(errors, st, "luminaire preset %d: unknown", (int)preset);
    if (basis != LUMIS_BASIS_DEFAULT) layout.basis = basis;
    lumis_acquire_desc acq = {0};
    if (errors) acq.errors = layout.errors = *errors;
    return lumis_luminaire_acquire(&layout, &emitter, &acq, out);
}
