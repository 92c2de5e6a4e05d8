/* A far-field photometric table in the near field: the illuminance a fixture's luminous
 * opening gives (every point of it emitting the table's distribution) against the point
 * model's, and the two-plane light field of that opening, so that Lu et al.'s restricted
 * sampling applies to a real fixture (lumis_luminaire_from_photometric).  Derivations:
 * docs/photometric.md, "Near field". */
#include "lumis/photometry.h"

#include "../core/internal.h"
#include "internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The point law from a point y of the opening (z = 0) to the receiver (x, n): the table's
 * intensity towards x, over d^2, times the receiver's cosine; 0 behind the receiver and,
 * from an opening (front > 0), behind the opening. */
static double point_law(const lumis_photometric *p, const double y[2], lumis_vec3 x, lumis_vec3 n,
                        int front)
{
    const double w[3] = {x.x - y[0], x.y - y[1], x.z};
    const double d2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    if (!(d2 > 0)) return 0.0;
    const double d = sqrt(d2);
    if (front && !(w[2] < 0)) return 0.0; /* the opening faces -z */
    const double nl = sqrt((double)n.x * n.x + (double)n.y * n.y + (double)n.z * n.z);
    const double cos_x = -(n.x * w[0] + n.y * w[1] + n.z * w[2]) / (d * (nl > 0 ? nl : 1));
    if (!(cos_x > 0)) return 0.0;
    const lumis_vec3 dir = {(float)(w[0] / d), (float)(w[1] / d), (float)(w[2] / d)};
    return lumis_photometric_intensity(p, dir) * cos_x / d2;
}

lumis_status lumis_photometric_irradiance(const lumis_photometric *p, int opening, lumis_vec3 x,
                                          lumis_vec3 n, int panels, double *E)
{
    if (!p || !E) return LUMIS_ERR_INVALID_ARGUMENT;
    *E = 0.0;
    lumis_photometric_info in;
    lumis_photometric_get_info(p, &in);
    const double origin[2] = {0, 0};
    if (!opening) {
        *E = point_law(p, origin, x, n, 0);
        return LUMIS_OK;
    }
    const int disk = in.shape == LUMIS_SHAPE_DISK;
    if (!(disk || in.shape == LUMIS_SHAPE_RECTANGLE) || !(in.width > 0) || !(disk || in.length > 0))
        return LUMIS_ERR_INVALID_ARGUMENT;
    if (panels <= 0) panels = 16;
    enum { ORDER = 6 };
    double gx[ORDER], gw[ORDER]; /* on [0, 1], weights summing to 1 */
    lumis__gauss01(ORDER, gx, gw);
    double sum = 0.0;
    if (disk) { /* polar: r in panels rings, phi in 4 panels per ring */
        const double R = 0.5 * in.width;
        for (int a = 0; a < panels; a++)
            for (int b = 0; b < 4 * panels; b++)
                for (int i = 0; i < ORDER; i++)
                    for (int j = 0; j < ORDER; j++) {
                        const double r = R * (a + gx[i]) / panels;
                        const double phi = 2 * LUMIS_PI * (b + gx[j]) / (4 * panels);
                        const double y[2] = {r * cos(phi), r * sin(phi)};
                        const double jac = r * (R / panels) * (2 * LUMIS_PI / (4 * panels));
                        sum += gw[i] * gw[j] * jac * point_law(p, y, x, n, 1);
                    }
        *E = sum / (LUMIS_PI * R * R);
    } else { /* length along x, width along y */
        const double L = in.length, Wd = in.width;
        for (int a = 0; a < panels; a++)
            for (int b = 0; b < panels; b++)
                for (int i = 0; i < ORDER; i++)
                    for (int j = 0; j < ORDER; j++) {
                        const double y[2] = {L * ((a + gx[i]) / panels - 0.5),
                                             Wd * ((b + gx[j]) / panels - 0.5)};
                        sum += gw[i] * gw[j] * point_law(p, y, x, n, 1);
                    }
        *E = sum / ((double)panels * panels); /* the mean over the opening */
    }
    return LUMIS_OK;
}

/* ---- the light field of the opening ------------------------------------------------------
 * docs/photometric.md, "Near field", has the reasoning; in short:
 * - every image is the same lattice F of pixel values shifted by whole pixels (the pixels a
 *   whole fraction 1/k of the basis spacing) and weighted by its cell's share of the opening;
 * - far away the light field's intensity is F blurred by a basis and averaged over a pixel
 *   (its cell averages are F convolved with kappa = hat * basis, sampled at whole pixels), so
 *   F is the pixels' exact flux deconvolved by kappa (Richardson-Lucy: non-negative and
 *   flux-preserving), and the far field converges to the table's, not to a blurred one;
 * - the basis blur that is left near the opening shrinks as delta grows for a given spacing:
 *   relative to the point model's error it is 3 (h / size)^2 (D / delta), so delta W^2 =
 *   REACH x size keeps it below out to REACH / 3 sizes. */

#define LF_REACH      200.0 /* delta W^2 / size: the basis blur below the point model to ~66 sizes */
#define LF_DELTA      2.0   /* delta / size */
#define LF_MAX_PIXELS (16u << 20)
#define LF_RL_ITER    80

typedef struct lf_plan {
    int W, H, kx, ky;
    double delta, theta, theta0; /* theta0: where the fade to theta starts */
} lf_plan;

typedef struct lf_ctx {
    const lumis_photometric *p;
    int disk, q;
    double Lx, Ly, A, flux;
    lumis_luminaire_basis basis;
} lf_ctx;

/* The flux through [x0, x1] x [y0, y1] of S (offsets from a basis centre, luminaire frame)
 * within theta of the aim: the integral of I cos^3 / delta^2 (a pixel's solid angle). */
static double cell_flux(const lf_ctx *c, double delta, double R, double R0, double x0, double x1,
                        double y0, double y1, int order, const double *gx, const double *gw)
{
    const double nx = x0 > 0 ? x0 : x1 < 0 ? -x1 : 0, ny = y0 > 0 ? y0 : y1 < 0 ? -y1 : 0;
    if (nx * nx + ny * ny >= R * R) return 0.0;
    double sum = 0.0;
    for (int i = 0; i < order; i++)
        for (int j = 0; j < order; j++) {
            const double sx = x0 + (x1 - x0) * gx[i], sy = y0 + (y1 - y0) * gx[j];
            const double rr = sqrt(sx * sx + sy * sy);
            if (rr >= R) continue;
            /* the fade: 1 within gamma0, linear in gamma to 0 at theta */
            const double w = rr <= R0 ? 1.0
                                      : (atan(R / delta) - atan(rr / delta)) /
                                            (atan(R / delta) - atan(R0 / delta));
            const double r = sqrt(rr * rr + delta * delta);
            /* the luminaire's +z is the table's aim, -z: turned about x */
            const lumis_vec3 dir = {(float)(sx / r), (float)(-sy / r), (float)(-delta / r)};
            sum += gw[i] * gw[j] * w * lumis_photometric_intensity(c->p, dir) * delta / (r * r * r);
        }
    return sum * (x1 - x0) * (y1 - y0);
}

/* kappa(j) = integral of hat(j - x) phi(x / k) / k dx: the cell average, at whole pixels, of
 * a pixel blurred by a basis k pixels wide.  taps[0..2J], J = ceil(radius k) + 1. */
static int kernel(lumis_luminaire_basis basis, int k, double *taps)
{
    const double rb = lumis_luminaire_basis_radius(basis);
    const int J = (int)ceil(rb * k) + 1;
    double gx[8], gw[8], tot = 0.0;
    lumis__gauss01(8, gx, gw);
    for (int j = -J; j <= J; j++) {
        double s = 0.0;
        const int pieces = 48 * k; /* [j - 1, j + 1] in pieces: the knots of both, nearly */
        for (int q = 0; q < pieces; q++)
            for (int i = 0; i < 8; i++) {
                const double x = j - 1 + 2.0 * (q + gx[i]) / pieces;
                s += gw[i] * (2.0 / pieces) * (1 - fabs(j - x)) *
                     lumis_luminaire_basis_eval(basis, x / k) / k;
            }
        taps[j + J] = s;
        tot += s;
    }
    for (int j = 0; j <= 2 * J; j++) taps[j] /= tot;
    return J;
}

/* out = kx * ky * in on an nx x ny lattice, zero beyond it (tmp: nx ny). */
static void blur(const double *in, double *tmp, double *out, int nx, int ny, const double *tx,
                 int Jx, const double *ty, int Jy)
{
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            double s = 0.0;
            for (int d = -Jx; d <= Jx; d++)
                if (i + d >= 0 && i + d < nx) s += tx[d + Jx] * in[(size_t)(j * nx + i + d)];
            tmp[(size_t)(j * nx + i)] = s;
        }
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            double s = 0.0;
            for (int d = -Jy; d <= Jy; d++)
                if (j + d >= 0 && j + d < ny) s += ty[d + Jy] * tmp[(size_t)((j + d) * nx + i)];
            out[(size_t)(j * nx + i)] = s;
        }
}

/* Builds the light field of a plan; *fail_pixels 1 when it would exceed LF_MAX_PIXELS. */
static lumis_status build(const lf_ctx *c, const lf_plan *pl, const lumis_error_sink *errors,
                          lumis_luminaire **out, int *too_big)
{
    *out = NULL;
    *too_big = 0;
    const int W = pl->W, H = pl->H, M = W * H;
    const double hx = c->Lx / W, hy = c->Ly / H, pdx = hx / pl->kx, pdy = hy / pl->ky;
    const double delta = pl->delta, R = delta * tan(pl->theta), R0 = delta * tan(pl->theta0);
    const double rb = lumis_luminaire_basis_radius(c->basis);
    const int Kx = (int)ceil(R / pdx + 0.5) + (int)ceil(rb * pl->kx) + 3,
              Ky = (int)ceil(R / pdy + 0.5) + (int)ceil(rb * pl->ky) + 3;
    const int nx = 2 * Kx + 1, ny = 2 * Ky + 1;
    const double wd = (double)(W - 1) * pl->kx + nx, ht = (double)(H - 1) * pl->ky + ny;
    if (wd > LUMIS__LUM_MAX_SIDE || ht > LUMIS__LUM_MAX_SIDE || wd * ht * M > LF_MAX_PIXELS) {
        *too_big = 1;
        return LUMIS_ERR_INVALID_ARGUMENT;
    }
    const int width = (int)wd, height = (int)ht;
    const size_t nl = (size_t)nx * (size_t)ny, npix = (size_t)width * (size_t)height;
    double *share = malloc(sizeof(double) * (size_t)M);
    double *lat = malloc(sizeof(double) * nl * 4); /* target, F, and two scratch lattices */
    float *pix = malloc(sizeof(float) * 3 * npix * (size_t)M);
    const float **ptr = malloc(sizeof(float *) * (size_t)M);
    if (!share || !lat || !pix || !ptr) {
        free(share);
        free(lat);
        free(pix);
        free(ptr);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "light field: out of memory");
    }
    /* the cells' share of the opening (a disk covers its corner cells in part), scaled so that
     * the shares' area is the opening's: sum_m share_m hx hy = A */
    double covered = 0.0;
    for (int b = 0; b < H; b++)
        for (int a = 0; a < W; a++) {
            double f = 1.0;
            if (c->disk) {
                int inside = 0;
                for (int q = 0; q < 256; q++) {
                    const double x = -0.5 * c->Lx + (a + ((q % 16) + 0.5) / 16) * hx,
                                 y = -0.5 * c->Ly + (b + ((q / 16) + 0.5) / 16) * hy;
                    inside += x * x + y * y <= 0.25 * c->Lx * c->Lx;
                }
                f = inside / 256.0;
            }
            share[b * W + a] = f;
            covered += f * hx * hy;
        }
    for (int m = 0; m < M; m++) share[m] *= c->A / covered;
    /* the target: each pixel's mean of the image convention, I cos^3 hx hy / (A delta^2) */
    double *tgt = lat, *F = lat + nl, *t1 = lat + 2 * nl, *t2 = lat + 3 * nl;
    double gx[16], gw[16];
    lumis__gauss01(c->q, gx, gw);
    const double scale = hx * hy / (c->A * pdx * pdy);
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            const double x0 = (i - Kx - 0.5) * pdx, y0 = (j - Ky - 0.5) * pdy;
            tgt[(size_t)(j * nx + i)] =
                scale * cell_flux(c, delta, R, R0, x0, x0 + pdx, y0, y0 + pdy, c->q, gx, gw);
        }
    /* Richardson-Lucy: F <- F kappa^T (tgt / kappa F); the sum of F stays the sum of tgt */
    double tx[64], ty[64];
    const int Jx = kernel(c->basis, pl->kx, tx), Jy = kernel(c->basis, pl->ky, ty);
    memcpy(F, tgt, sizeof(double) * nl);
    for (int it = 0; it < LF_RL_ITER; it++) {
        blur(F, t1, t2, nx, ny, tx, Jx, ty, Jy);
        for (size_t k = 0; k < nl; k++) t2[k] = t2[k] > 0 ? tgt[k] / t2[k] : 0.0;
        blur(t2, t1, t2, nx, ny, tx, Jx, ty, Jy);
        for (size_t k = 0; k < nl; k++) F[k] *= t2[k];
    }
    for (int m = 0; m < M; m++) {
        const int a = m % W, b = m / W;
        float *img = pix + (size_t)m * 3 * npix;
        ptr[m] = img;
        for (int j = 0; j < height; j++)
            for (int i = 0; i < width; i++) {
                const int li = i - a * pl->kx, lj = j - b * pl->ky;
                const float v = li >= 0 && li < nx && lj >= 0 && lj < ny
                                    ? (float)(share[m] * F[(size_t)(lj * nx + li)])
                                    : 0.0f;
                float *px = img + 3 * ((size_t)j * (size_t)width + (size_t)i);
                px[0] = px[1] = px[2] = v;
            }
    }
    lumis_luminaire_desc ld;
    memset(&ld, 0, sizeof ld);
    ld.delta = delta;
    ld.basis = c->basis;
    ld.grid[0] = W;
    ld.grid[1] = H;
    ld.grid_origin[0] = -0.5 * c->Lx + 0.5 * hx;
    ld.grid_origin[1] = -0.5 * c->Ly + 0.5 * hy;
    ld.grid_spacing[0] = hx;
    ld.grid_spacing[1] = hy;
    ld.width = width;
    ld.height = height;
    ld.image_origin[0] = ld.grid_origin[0] - (Kx + 0.5) * pdx;
    ld.image_origin[1] = ld.grid_origin[1] - (Ky + 0.5) * pdy;
    ld.image_size[0] = width * pdx;
    ld.image_size[1] = height * pdy;
    if (errors) ld.errors = *errors;
    ld.pixels = ptr;
    const lumis_status st = lumis_luminaire_create(&ld, out);
    free(share);
    free(lat);
    free(pix);
    free(ptr);
    return st;
}

/* The far-field error of a built light field: |I_field / I - 1| 1000 sizes away, over the
 * directions within the cone (clear of its edge's blur) holding >= 10 % of their peak. */
static void far_error(const lf_ctx *c, const lf_plan *pl, const lumis_luminaire *lum, double *max,
                      double *mean, int *count)
{
    const double size = fmax(c->Lx, c->Ly), D = 1000.0 * size;
    const double hx = c->Lx / pl->W, hy = c->Ly / pl->H;
    const double rb = lumis_luminaire_basis_radius(c->basis);
    const double edge = (rb * fmax(hx, hy) + 2 * fmax(hx / pl->kx, hy / pl->ky)) / pl->delta;
    const double tmax = tan(pl->theta0) - edge;
    enum { NG = 24, NC = 24 };
    double I[NG][NC], peak = 0.0;
    for (int g = 0; g < NG; g++)
        for (int k = 0; k < NC; k++) {
            const double gam = atan(tmax * g / (NG - 1)), C = 2 * LUMIS_PI * k / NC;
            const lumis_vec3 d = {(float)(sin(gam) * cos(C)), (float)(sin(gam) * sin(C)),
                                  (float)-cos(gam)};
            I[g][k] = tmax > 0 ? lumis_photometric_intensity(c->p, d) : 0.0;
            if (I[g][k] > peak) peak = I[g][k];
        }
    *max = *mean = 0.0;
    *count = 0;
    for (int g = 0; g < NG; g++)
        for (int k = 0; k < NC; k++) {
            if (!(I[g][k] >= 0.1 * peak) || !(peak > 0) || (g == 0 && k > 0)) continue;
            const double gam = atan(tmax * g / (NG - 1)), C = 2 * LUMIS_PI * k / NC;
            const double w[3] = {sin(gam) * cos(C), sin(gam) * sin(C), -cos(gam)};
            const lumis_vec3 x = {(float)(D * w[0]), (float)(D * w[1]), (float)(D * w[2])},
                             n = {(float)-w[0], (float)-w[1], (float)-w[2]};
            double E = 0;
            lumis_photometric_irradiance(c->p, 0, x, n, 0, &E);
            const lumis_vec3 xl = {x.x, -x.y, -x.z}, nl = {n.x, -n.y, -n.z};
            lumis_rgb e;
            if (lumis_luminaire_irradiance(lum, xl, nl, 0, &e) != LUMIS_OK || !(E > 0)) continue;
            const double err = fabs(e.g / E - 1);
            if (err > *max) *max = err;
            *mean += err;
            ++*count;
        }
    if (*count) *mean /= *count;
}

double lumis_photometric_near_weight(const lumis_photometric_light_field_report *r, double distance)
{
    if (!r || !(distance >= 0.0)) return 0.0;
    if (distance <= r->near_until) return 1.0;
    if (!(distance < r->far_from)) return 0.0;
    /* near_until < distance < far_from: near_until may be 0 (then w is 1 only at 0) */
    if (!(r->near_until > 0.0)) return 0.0;
    return log(r->far_from / distance) / log(r->far_from / r->near_until);
}

/* w (field + residual) + (1 - w) point, with the residual given (NULL: none). */
static lumis_status near_irradiance(const lumis_photometric *p, const lumis_photometric *res,
                                    const lumis_luminaire *lf, double w, lumis_vec3 x, lumis_vec3 n,
                                    double *E)
{
    double point = 0.0, resid = 0.0;
    lumis_status st = lumis_photometric_irradiance(p, 0, x, n, 0, &point);
    if (st != LUMIS_OK || !(w > 0.0)) {
        *E = point;
        return st;
    }
    if (res) lumis_photometric_irradiance(res, 0, x, n, 0, &resid);
    /* the light field's frame: the fixture's turned half a turn about x */
    const lumis_vec3 xl = {x.x, -x.y, -x.z}, nl = {n.x, -n.y, -n.z};
    lumis_rgb e = {0, 0, 0};
    if (x.z < 0.0f && (st = lumis_luminaire_irradiance(lf, xl, nl, 0, &e)) != LUMIS_OK) return st;
    *E = w * (e.g + resid) + (1.0 - w) * point;
    return LUMIS_OK;
}

lumis_status lumis_photometric_near_irradiance(const lumis_photometric *p,
                                               const lumis_luminaire *light_field,
                                               const lumis_photometric_light_field_report *r,
                                               lumis_vec3 x, lumis_vec3 n, double *E)
{
    if (E) *E = 0.0;
    if (!p || !light_field || !r || !E) return LUMIS_ERR_INVALID_ARGUMENT;
    const double flux = lumis_photometric_flux(p);
    if (!(fabs(r->flux - flux) <= 1e-9 * fabs(flux))) return LUMIS_ERR_INVALID_ARGUMENT;
    const double D = sqrt((double)x.x * x.x + (double)x.y * x.y + (double)x.z * x.z);
    const double w = lumis_photometric_near_weight(r, D);
    lumis_photometric_info in;
    lumis_photometric_get_info(p, &in);
    lumis_photometric *res = NULL;
    if (w > 0.0 && in.type == LUMIS_PHOTOMETRIC_C && r->ramp_from_deg <= r->max_angle_deg &&
        lumis_photometric_beyond(p, r->ramp_from_deg, r->max_angle_deg, NULL, &res) != LUMIS_OK)
        return LUMIS_ERR_INVALID_ARGUMENT;
    const lumis_status st = near_irradiance(p, res, light_field, w, x, n, E);
    lumis_photometric_destroy(res);
    return st;
}

/* The distances (sizes) the crossover is measured at. */
static const double cross_sizes[] = {0.5, 0.75, 1, 1.5, 2, 3, 5, 7, 10, 15, 20, 30, 50};
#define NCROSS ((int)(sizeof cross_sizes / sizeof cross_sizes[0]))

/* Where the light field (+ residual) stops being closer to the exact opening than the point
 * model (report's crossover_sizes), and the blend around it: near_until and far_from, a
 * factor CROSS_BAND either side of the crossover but never past the distances measured on
 * either side of it, so that at every measured distance the model is the closer one. */
#define CROSS_BAND 1.25
static void crossover(const lumis_photometric *p, const lumis_photometric *res,
                      const lumis_luminaire *lf, double size,
                      lumis_photometric_light_field_report *r)
{
    lumis_photometric_info in;
    lumis_photometric_get_info(p, &in);
    double ef[NCROSS], ep[NCROSS];
    for (int k = 0; k < NCROSS; k++) {
        const double D = cross_sizes[k] * size;
        ef[k] = ep[k] = 0.0;
        for (int gi = 0; gi <= 17; gi++)
            for (int ci = 0; ci < 24; ci++) {
                if (gi == 0 && ci > 0) break;
                const double g = 5.0 * gi * LUMIS_PI / 180, c = 15.0 * ci * LUMIS_PI / 180;
                const double w[3] = {sin(g) * cos(c), sin(g) * sin(c), -cos(g)};
                const lumis_vec3 wd = {(float)w[0], (float)w[1], (float)w[2]};
                if (!(lumis_photometric_intensity(p, wd) >= 0.1 * in.max_candela)) continue;
                const lumis_vec3 x = {(float)(D * w[0]), (float)(D * w[1]), (float)(D * w[2])},
                                 n = {(float)-w[0], (float)-w[1], (float)-w[2]};
                double exact = 0.0, point = 0.0, field = 0.0;
                lumis_photometric_irradiance(p, 1, x, n, 8, &exact);
                if (!(exact > 0.0)) continue;
                lumis_photometric_irradiance(p, 0, x, n, 0, &point);
                near_irradiance(p, res, lf, 1.0, x, n, &field);
                ef[k] = fmax(ef[k], fabs(field / exact - 1));
                ep[k] = fmax(ep[k], fabs(point / exact - 1));
            }
    }
    int k = 0;
    while (k < NCROSS && ef[k] < ep[k]) k++;
    double x, lo, hi;
    if (k == 0) { /* the point is closer from the first distance on */
        r->crossover_sizes = r->near_until = r->far_from = 0.0;
        return;
    }
    if (k < NCROSS) { /* log(ef / ep) crosses 0 between k - 1 and k */
        const double a = log(ef[k - 1] / ep[k - 1]), b = log(fmax(ef[k], 1e-300) / ep[k]);
        const double t = b > a ? -a / (b - a) : 1.0;
        x = exp(log(cross_sizes[k - 1]) + t * (log(cross_sizes[k]) - log(cross_sizes[k - 1])));
        lo = cross_sizes[k - 1];
        hi = cross_sizes[k];
    } else { /* closer at every distance: the point's error falling as its last slope */
        const double l0 = cross_sizes[NCROSS - 2], l1 = cross_sizes[NCROSS - 1];
        double slope = log(ep[NCROSS - 2] / ep[NCROSS - 1]) / log(l1 / l0);
        slope = !(slope >= 1.0) ? 1.0 : slope > 2.0 ? 2.0 : slope;
        const double ratio = ef[NCROSS - 1] > 0.0 ? ep[NCROSS - 1] / ef[NCROSS - 1] : 1e6;
        x = l1 * pow(fmin(ratio, 1e6), 1.0 / slope);
        lo = l1;
        hi = INFINITY;
    }
    r->crossover_sizes = x;
    r->near_until = fmax(x / CROSS_BAND, lo) * size;
    r->far_from = fmin(x * CROSS_BAND, hi) * size;
    if (r->near_until > r->far_from) r->near_until = r->far_from;
}

lumis_status lumis_luminaire_from_photometric(const lumis_photometric *p,
                                              const lumis_photometric_light_field *d,
                                              const lumis_error_sink *errors, lumis_luminaire **out,
                                              lumis_photometric_light_field_report *report)
{
    if (out) *out = NULL;
    if (report) memset(report, 0, sizeof *report);
    if (!p || !out) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "light field: no table");
    lumis_photometric_light_field def = {0};
    if (!d) d = &def;
    lumis_photometric_info in;
    lumis_photometric_get_info(p, &in);
    const int disk = in.shape == LUMIS_SHAPE_DISK;
    if (!(disk || in.shape == LUMIS_SHAPE_RECTANGLE) || !(in.width > 0) || !(disk || in.length > 0))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "light field: the file's luminous shape is \"%s\": a light field needs "
                           "its opening, a disk or a rectangle of non-zero size (box, cylinder "
                           "and sphere openings are not modelled)",
                           lumis_photometric_shape_name(in.shape));
    lf_ctx c;
    c.p = p;
    c.disk = disk;
    c.Lx = disk ? in.width : in.length;
    c.Ly = in.width;
    c.A = disk ? LUMIS_PI * 0.25 * in.width * in.width : c.Lx * c.Ly;
    c.flux = in.flux;
    c.basis = d->basis ? d->basis : LUMIS_BASIS_QUADRATIC;
    c.q = d->supersample > 0 ? d->supersample : 4;
    const double target = d->error_target > 0 ? d->error_target : 0.005;
    double theta_deg = d->max_angle_deg;
    if (!(theta_deg > 0)) { /* where 99.9 % of the flux is, with a margin: S's pixels go to
                               the beam, not to the dark (a narrow spot got 4 across it) */
        double lo = 0, hi = 180;
        for (int it = 0; it < 40; it++) {
            const double mid = 0.5 * (lo + hi);
            if (lumis_photometric_flux_within(p, mid) >= 0.999 * in.flux)
                hi = mid;
            else
                lo = mid;
        }
        theta_deg = hi + 5.0 < 80.0 ? hi + 5.0 : 80.0;
    }
    if (d->grid[0] > 256 || d->grid[1] > 256 || d->grid[0] * d->grid[1] > 1024 ||
        d->width > 16384 || d->height > 16384 || !(theta_deg < 90) || d->supersample > 16 ||
        d->grid[0] < 0 || d->grid[1] < 0 || !(d->error_target >= 0) || !(d->delta >= 0))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "light field: grid %d x %d (at most 256 each, 1024 in all), images %d x "
                           "%d (at most 16384), max angle %g (below 90 degrees), supersampling %d "
                           "(at most 16)",
                           d->grid[0], d->grid[1], d->width, d->height, theta_deg, d->supersample);
    const double theta = theta_deg * LUMIS_PI / 180.0;
    const double cone = lumis_photometric_flux_within(p, theta_deg);
    if (!(cone > 0))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "light field: no flux within %g degrees of the aim (of %g lm): a "
                           "two-plane field carries only the directions in front of the opening",
                           theta_deg, in.flux);
    const double size = fmax(c.Lx, c.Ly);
    /* delta 2 sizes: where the pixels' steps show (points near S see one pixel per image)
     * the point model is 8-100 % off; W^2 delta = REACH size; then the ladder of pixels per
     * basis spacing, coarsest first, until the far field is within the target */
    static const int ladder[] = {1, 2, 3, 4, 6, 8, 12, 16};
    const int nl = (int)(sizeof ladder / sizeof ladder[0]);
    const int given = d->grid[0] > 0 && d->grid[1] > 0;
    lf_plan plans[sizeof ladder / sizeof ladder[0]];
    double cost[sizeof ladder / sizeof ladder[0]];
    int start = 0;
    for (int r = 0; r < nl; r++) {
        lf_plan *pl = &plans[r];
        pl->delta = d->delta > 0 ? d->delta : LF_DELTA * size;
        int Wl = given ? (c.Lx >= c.Ly ? d->grid[0] : d->grid[1])
                       : (int)ceil(sqrt(LF_REACH * size / pl->delta));
        Wl = Wl < 2 ? 2 : Wl > 32 ? 32 : Wl;
        if (given) {
            pl->W = d->grid[0];
            pl->H = d->grid[1];
        } else {
            const int other = (int)lround(Wl * fmin(c.Lx, c.Ly) / size);
            pl->W = c.Lx >= c.Ly ? Wl : (other < 1 ? 1 : other);
            pl->H = c.Lx >= c.Ly ? (other < 1 ? 1 : other) : Wl;
        }
        pl->theta = theta;
        pl->theta0 = theta - fmin(5.0, 0.25 * theta_deg) * LUMIS_PI / 180;
        const double hx = c.Lx / pl->W, hy = c.Ly / pl->H, R = pl->delta * tan(theta);
        /* ladder[r] pixels per spacing along the longer side, square-ish along the other */
        const double pd = fmax(hx, hy) / ladder[r];
        pl->kx = (int)lround(hx / pd);
        pl->ky = (int)lround(hy / pd);
        if (d->width > 0) pl->kx = (int)lround(d->width * hx / (2 * R + c.Lx));
        if (d->height > 0) pl->ky = (int)lround(d->height * hy / (2 * R + c.Ly));
        pl->kx = pl->kx < 1 ? 1 : pl->kx > 16 ? 16 : pl->kx;
        pl->ky = pl->ky < 1 ? 1 : pl->ky > 16 ? 16 : pl->ky;
        const double wx = 2 * R / (hx / pl->kx) + (double)(pl->W + 6) * pl->kx,
                     wy = 2 * R / (hy / pl->ky) + (double)(pl->H + 6) * pl->ky;
        cost[r] = (double)pl->W * pl->H * wx * wy;
    }
    (void)cost;
    if (d->width > 0 || d->height > 0) start = nl - 1; /* one plan: the pixels given */
    lumis_luminaire *best = NULL;
    lf_plan bp = {0};
    double bmax = INFINITY, bmean = 0;
    int bcount = 0, met = 0;
    lumis_status st = LUMIS_OK;
    for (int r = start; r < nl && !met; r++) {
        lumis_luminaire *lum = NULL;
        int too_big = 0;
        st = build(&c, &plans[r], errors, &lum, &too_big);
        if (too_big) {
            st = LUMIS_OK;
            if (best) break;
            continue;
        }
        if (st != LUMIS_OK) break;
        double emax, emean;
        int count;
        far_error(&c, &plans[r], lum, &emax, &emean, &count);
        lumis_luminaire_destroy(best);
        best = lum;
        bp = plans[r];
        bmax = emax;
        bmean = emean;
        bcount = count;
        met = emax <= target;
    }
    if (st != LUMIS_OK || !best) {
        lumis_luminaire_destroy(best);
        if (st != LUMIS_OK) return st;
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "light field: even its coarsest resolution needs more than %u pixels",
                           LF_MAX_PIXELS);
    }
    *out = best;
    if (report) {
        lumis_luminaire_info li;
        lumis_luminaire_get_info(best, &li);
        report->grid[0] = bp.W;
        report->grid[1] = bp.H;
        report->width = li.width;
        report->height = li.height;
        report->pixels_per_spacing[0] = bp.kx;
        report->pixels_per_spacing[1] = bp.ky;
        report->delta = bp.delta;
        report->max_angle_deg = theta_deg;
        report->flux = in.flux;
        report->light_field_flux = li.total_power;
        report->ramp_from_deg = bp.theta0 * 180 / LUMIS_PI;
        report->residual_flux = fmax(0.0, in.flux - li.total_power);
        lumis_photometric *res = NULL;
        if (in.type == LUMIS_PHOTOMETRIC_C &&
            lumis_photometric_beyond(p, report->ramp_from_deg, theta_deg, NULL, &res) == LUMIS_OK)
            report->residual_flux = lumis_photometric_flux(res);
        report->size = size;
        crossover(p, res, best, size, report);
        lumis_photometric_destroy(res);
        report->residual_share = in.flux > 0 ? report->residual_flux / in.flux : 0.0;
        report->error_target = target;
        report->far_field_error = bmax;
        report->far_field_error_mean = bmean;
        report->directions = bcount;
        report->target_met = met;
    }
    return LUMIS_OK;
}
