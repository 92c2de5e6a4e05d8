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

lumis_status lumis_luminaire_from_photometric(const lumis_photometric *p,
                                              const lumis_photometric_light_field *d,
                                              const lumis_error_sink *errors, lumis_luminaire **out)
{
    if (out) *out = NULL;
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
    const double Lx = disk ? in.width : in.length, Ly = in.width; /* extents on U */
    int W = d->grid[0], H = d->grid[1];
    if (W <= 0 || H <= 0) { /* 9 across the longer side, the other in proportion (>= 3) */
        const double lo = Lx < Ly ? Lx : Ly, hi = Lx < Ly ? Ly : Lx;
        const int other = (int)ceil(9.0 * lo / hi);
        W = Lx >= Ly ? 9 : (other < 3 ? 3 : other);
        H = Lx >= Ly ? (other < 3 ? 3 : other) : 9;
    }
    const int width = d->width > 0 ? d->width : 128, height = d->height > 0 ? d->height : 128;
    double theta_deg = d->max_angle_deg;
    if (!(theta_deg > 0)) { /* where 99.9 % of the flux is, with a margin: S's pixels go to
                               the beam, not to the dark (a narrow spot got 4 across it) */
        const double total = lumis_photometric_flux(p);
        double lo = 0, hi = 180;
        for (int it = 0; it < 40; it++) {
            const double mid = 0.5 * (lo + hi);
            if (lumis_photometric_flux_within(p, mid) >= 0.999 * total)
                hi = mid;
            else
                lo = mid;
        }
        theta_deg = hi + 5.0 < 80.0 ? hi + 5.0 : 80.0;
    }
    const double theta = theta_deg * LUMIS_PI / 180.0;
    const double delta = d->delta > 0 ? d->delta : (Lx > Ly ? Lx : Ly);
    const int ss = d->supersample > 0 ? d->supersample : 2;
    if (W > 256 || H > 256 || W * H > 1024 || width > 16384 || height > 16384 ||
        !(theta < 0.5 * LUMIS_PI) || ss > 16)
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT,
                           "light field: grid %d x %d (at most 256 each, 1024 in all), images %d x "
                           "%d (at most 16384), max angle below 90 degrees, supersampling <= 16",
                           W, H, width, height);
    const lumis_luminaire_basis basis = d->basis ? d->basis : LUMIS_BASIS_QUADRATIC;
    const double rb = lumis_luminaire_basis_radius(basis);
    const double hx = Lx / W, hy = Ly / H,
                 A = disk ? LUMIS_PI * 0.25 * in.width * in.width : Lx * Ly;
    /* the cells' share of the opening (a disk covers its corner cells in part), scaled so
     * that the shares' area is the opening's exactly: the light field's flux is the table's
     * (what the images capture of it) */
    double *share = malloc(sizeof(double) * (size_t)(W * H));
    float *pix = NULL;
    const float **ptr = malloc(sizeof(float *) * (size_t)(W * H));
    if (share && ptr)
        pix = malloc(sizeof(float) * 3 * (size_t)width * (size_t)height * (size_t)(W * H));
    if (!share || !ptr || !pix) {
        free(share);
        free(ptr);
        free(pix);
        return lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "light field: out of memory");
    }
    double covered = 0.0;
    for (int b = 0; b < H; b++)
        for (int a = 0; a < W; a++) {
            double f = 1.0;
            if (disk) {
                int inside = 0;
                for (int q = 0; q < 256; q++) {
                    const double x = -0.5 * Lx + (a + ((q % 16) + 0.5) / 16) * hx,
                                 y = -0.5 * Ly + (b + ((q / 16) + 0.5) / 16) * hy;
                    inside += x * x + y * y <= 0.25 * Lx * Lx;
                }
                f = inside / 256.0;
            }
            share[b * W + a] = f;
            covered += f * hx * hy;
        }
    for (int m = 0; m < W * H; m++) share[m] *= A / covered;
    /* S covers, from every point of the bases' supports, directions up to theta */
    const double ux = 0.5 * Lx + rb * hx, uy = 0.5 * Ly + rb * hy;
    const double ex = ux + delta * tan(theta), ey = uy + delta * tan(theta);
    lumis_luminaire_desc ld;
    memset(&ld, 0, sizeof ld);
    ld.delta = delta;
    ld.basis = basis;
    ld.grid[0] = W;
    ld.grid[1] = H;
    ld.grid_origin[0] = -0.5 * Lx + 0.5 * hx;
    ld.grid_origin[1] = -0.5 * Ly + 0.5 * hy;
    ld.grid_spacing[0] = hx;
    ld.grid_spacing[1] = hy;
    ld.width = width;
    ld.height = height;
    ld.image_origin[0] = -ex;
    ld.image_origin[1] = -ey;
    ld.image_size[0] = 2 * ex;
    ld.image_size[1] = 2 * ey;
    if (errors) ld.errors = *errors;
    const double pdx = 2 * ex / width, pdy = 2 * ey / height;
    const size_t npix = (size_t)width * (size_t)height;
    for (int m = 0; m < W * H; m++) {
        const double cx = ld.grid_origin[0] + (m % W) * hx, cy = ld.grid_origin[1] + (m / W) * hy;
        float *img = pix + (size_t)m * 3 * npix;
        ptr[m] = img;
        for (int j = 0; j < height; j++)
            for (int i = 0; i < width; i++) {
                double sum = 0.0;
                for (int sb = 0; sb < ss; sb++)
                    for (int sa = 0; sa < ss; sa++) {
                        const double sx = -ex + (i + (sa + 0.5) / ss) * pdx - cx,
                                     sy = -ey + (j + (sb + 0.5) / ss) * pdy - cy;
                        const double r = sqrt(sx * sx + sy * sy + delta * delta), cz = delta / r;
                        /* the luminaire's +z is the table's aim, -z: turned about x */
                        const lumis_vec3 dir = {(float)(sx / r), (float)(-sy / r), (float)-cz};
                        /* the model's images hold L hx hy cos^4 / delta^2 (lumis_luminaire_
                         * radiance: L = sum Phi_m |s - u|^4 / (delta^2 hx hy) C_m) */
                        const double L = lumis_photometric_intensity(p, dir) / (A * cz);
                        sum += L * hx * hy * cz * cz * cz * cz / (delta * delta);
                    }
                const float v = (float)(share[m] * sum / (ss * ss));
                float *px = img + 3 * ((size_t)j * (size_t)width + (size_t)i);
                px[0] = px[1] = px[2] = v;
            }
    }
    ld.pixels = ptr;
    const lumis_status st = lumis_luminaire_create(&ld, out);
    free(share);
    free(ptr);
    free(pix);
    return st;
}
