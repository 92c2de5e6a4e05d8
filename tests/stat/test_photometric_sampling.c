/* Sampling a photometric table in proportion to intensity (lumis_photometric_sample): a
 * chi-square test of the directions against the sampler's own pdf, the pdf integrating to
 * one over the sphere, pdf(sample) equal to the pdf returned, the pdf equal to I / flux,
 * and unbiased estimates of the flux and of an integral of the intensity.  Every type and
 * symmetry form; the tables come from tests/photometric_gen.c; seeds are fixed. */
/* Oracles:
 * lumis_photometric_sample — statistical: chi-square against the pdf on equal-area bins, unbiased
 *     estimates of the flux and of the integral of I d_z^2, every type and symmetry form
 *     (chi_square_goodness_of_fit, pdf_of_samples_and_unbiased_estimates)
 * lumis_photometric_pdf — brute force: integrates to one over the sphere by a midpoint rule; equals
 *     I / flux (pdf_integrates_to_one_and_is_intensity_over_flux)
 * lumis_photometric_flux — indirect: the unbiased flux estimate I / pdf
 *     (pdf_of_samples_and_unbiased_estimates)
 */
#include "photometric_gen.h"
#include "stat.h"
#include "testutil.h"

#include "lumis/rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

typedef struct table_case {
    const char *name;
    pg_ies_spec spec;
} table_case;

/* Coarse tables (so that the cells' interpolants, not the analytic curve, are what is
 * tested), each form once. */
static const table_case cases[] = {
    {"C rotational spot",
     {PG_SPOT, 6, "IESNA:LM-63-2002", 1, 10, 0, 90, 1, 0, 0, 0, 0, 0, 0, 0, 2}},
    {"C 0-180 uplight too",
     {PG_BATWING, 2, "IESNA:LM-63-2002", 1, 13, 0, 180, 5, 0, 180, 0, 0, 0, 0, 0, 2}},
    {"C quadrant", {PG_QUAD, 0.9, "IESNA:LM-63-2002", 1, 7, 0, 90, 4, 0, 90, 0, 0, 0, 0, 0, 2}},
    {"C 90-270", {PG_QUAD, 0.9, "IESNA:LM-63-2002", 1, 7, 0, 90, 7, 90, 270, 0, 0, 0, 0, 0, 2}},
    {"C 0-330 road (wraps)",
     {PG_ROAD, 0.8, "IESNA:LM-63-2002", 1, 7, 0, 90, 12, 0, 330, 0, 0, 0, 0, 0, 2}},
    {"B full", {PG_AIMED, 0, "IESNA:LM-63-2002", 2, 7, -90, 90, 5, -90, 90, 0, 0, 0, 0, 0, 2}},
    {"B lateral, V mirrored",
     {PG_AIMED, 0, "IESNA:LM-63-2002", 2, 4, 0, 90, 4, 0, 90, 0, 0, 0, 0, 0, 2}},
    {"A full", {PG_AIMED, 0, "IESNA:LM-63-2002", 3, 7, -90, 90, 9, -90, 90, 0, 0, 0, 0, 0, 2}},
    {"A lateral", {PG_AIMED, 0, "IESNA:LM-63-2002", 3, 7, -90, 90, 4, 0, 90, 0, 0, 0, 0, 0, 2}},
};
#define NCASES ((int)(sizeof cases / sizeof cases[0]))

static lumis_photometric_file *load(const table_case *c)
{
    size_t n = 0;
    char *text = pg_ies(&c->spec, &n);
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_photometric_file *f = NULL;
    if (lumis_photometric_read_memory(text, n, c->name, &sink.sink, &f) != LUMIS_OK)
        fail_msg("%s: %s", c->name, sink.last);
    free(text);
    return f;
}

/* The sphere in equal-area bins: nz bands of z, nphi sectors. */
enum { NZ = 24, NPHI = 48, SUB = 12 };

static int bin_of(lumis_vec3 d)
{
    int iz = (int)((d.z + 1.0) * 0.5 * NZ);
    iz = iz < 0 ? 0 : iz >= NZ ? NZ - 1 : iz;
    double phi = atan2(d.y, d.x);
    if (phi < 0) phi += 2 * PI;
    int ip = (int)(phi / (2 * PI) * NPHI);
    ip = ip < 0 ? 0 : ip >= NPHI ? NPHI - 1 : ip;
    return iz * NPHI + ip;
}

static lumis_vec3 dir_of(double z, double phi)
{
    const double r = sqrt(fmax(0.0, 1 - z * z));
    lumis_vec3 d = {(float)(r * cos(phi)), (float)(r * sin(phi)), (float)z};
    return d;
}

/* Each bin's probability: the pdf integrated by a SUB x SUB midpoint rule. */
static void bin_probabilities(const lumis_photometric *p, double *prob)
{
    const double area = 4 * PI / (NZ * NPHI);
    for (int iz = 0; iz < NZ; iz++)
        for (int ip = 0; ip < NPHI; ip++) {
            double sum = 0;
            for (int a = 0; a < SUB; a++)
                for (int b = 0; b < SUB; b++) {
                    const double z = -1 + 2.0 * (iz + (a + 0.5) / SUB) / NZ;
                    const double phi = 2 * PI * (ip + (b + 0.5) / SUB) / NPHI;
                    sum += lumis_photometric_pdf(p, dir_of(z, phi));
                }
            prob[iz * NPHI + ip] = sum / (SUB * SUB) * area;
        }
}

static void chi_square_goodness_of_fit(void **state)
{
    (void)state;
    const double alpha = 0.01 / NCASES; /* Bonferroni */
    const int n = 200000;
    for (int k = 0; k < NCASES; k++) {
        lumis_photometric_file *f = load(&cases[k]);
        double obs[NZ * NPHI] = {0}, expct[NZ * NPHI];
        bin_probabilities(f->model, expct);
        for (int b = 0; b < NZ * NPHI; b++) expct[b] *= n;
        lumis_pcg32 rng;
        lumis_pcg32_seed(&rng, 77 + (uint64_t)k, 3);
        for (int s = 0; s < n; s++) {
            lumis_vec3 d;
            double pdf;
            const double u0 = lumis_pcg32_double(&rng), u1 = lumis_pcg32_double(&rng);
            assert_int_equal(lumis_photometric_sample(f->model, u0, u1, &d, &pdf), LUMIS_OK);
            obs[bin_of(d)] += 1;
        }
        int dof = 0;
        const double pv = stat_chi2_test(obs, expct, NZ * NPHI, &dof);
        if (!(pv > alpha)) fail_msg("%s: chi-square p = %g (dof %d)", cases[k].name, pv, dof);
        lumis_photometric_file_destroy(f);
    }
}

/* The pdf integrates to one, and is I / flux (the cells' 2^-32 quantisation aside). */
static void pdf_integrates_to_one_and_is_intensity_over_flux(void **state)
{
    (void)state;
    for (int k = 0; k < NCASES; k++) {
        lumis_photometric_file *f = load(&cases[k]);
        const double flux = lumis_photometric_flux(f->model);
        const int nz = 800, nphi = 1600;
        double sum = 0, worst = 0;
        for (int a = 0; a < nz; a++)
            for (int b = 0; b < nphi; b++) {
                const lumis_vec3 d = dir_of(-1 + 2.0 * (a + 0.5) / nz, 2 * PI * (b + 0.5) / nphi);
                const double pdf = lumis_photometric_pdf(f->model, d);
                sum += pdf;
                const double want = lumis_photometric_intensity(f->model, d) / flux;
                if (want > 1e-3) worst = fmax(worst, fabs(pdf / want - 1));
            }
        const double integral = sum * 4 * PI / ((double)nz * nphi);
        if (fabs(integral - 1) > 2e-3)
            fail_msg("%s: the pdf integrates to %.6f", cases[k].name, integral);
        if (worst > 1e-6) fail_msg("%s: pdf / (I / flux) off by %g", cases[k].name, worst);
        lumis_photometric_file_destroy(f);
    }
}

/* pdf(sample()) is the pdf the sampler returned; the flux estimate I / pdf is the flux;
 * a non-trivial integral, of I(d) d_z^2, is estimated without bias. */
static void pdf_of_samples_and_unbiased_estimates(void **state)
{
    (void)state;
    for (int k = 0; k < NCASES; k++) {
        lumis_photometric_file *f = load(&cases[k]);
        const double flux = lumis_photometric_flux(f->model);
        lumis_pcg32 rng;
        lumis_pcg32_seed(&rng, 500 + (uint64_t)k, 9);
        const int n = 100000;
        double est = 0, est2 = 0, fl = 0;
        for (int s = 0; s < n; s++) {
            lumis_vec3 d;
            double pdf;
            const double u0 = lumis_pcg32_double(&rng), u1 = lumis_pcg32_double(&rng);
            assert_int_equal(lumis_photometric_sample(f->model, u0, u1, &d, &pdf), LUMIS_OK);
            const double again = lumis_photometric_pdf(f->model, d);
            if (fabs(again / pdf - 1) > 1e-4)
                fail_msg("%s: pdf %.9g returned, %.9g at the direction", cases[k].name, pdf, again);
            const double I = lumis_photometric_intensity(f->model, d);
            fl += I / pdf;
            const double x = I * (double)d.z * d.z / pdf;
            est += x;
            est2 += x * x;
        }
        fl /= n;
        if (fabs(fl / flux - 1) > 1e-4)
            fail_msg("%s: flux estimate %g, flux %g", cases[k].name, fl, flux);
        est /= n;
        const double se = sqrt(fmax(0.0, est2 / n - est * est) / n);
        /* the exact integral of I d_z^2, by a fine quadrature */
        const int nz = 1000, nphi = 2000;
        double q = 0;
        for (int a = 0; a < nz; a++)
            for (int b = 0; b < nphi; b++) {
                const double z = -1 + 2.0 * (a + 0.5) / nz;
                q += lumis_photometric_intensity(f->model, dir_of(z, 2 * PI * (b + 0.5) / nphi)) *
                     z * z;
            }
        q *= 4 * PI / ((double)nz * nphi);
        if (fabs(est - q) > 4 * se + 1e-4 * q)
            fail_msg("%s: estimate %g, quadrature %g (standard error %g)", cases[k].name, est, q,
                     se);
        lumis_photometric_file_destroy(f);
    }
}

/* A black table cannot be sampled and says so. */
static void black_table_is_refused(void **state)
{
    (void)state;
    const double v[2] = {0, 90}, h[1] = {0}, cd[2] = {0, 0};
    lumis_photometric_desc d = {0};
    d.type = LUMIS_PHOTOMETRIC_C;
    d.nv = 2;
    d.nh = 1;
    d.v_deg = v;
    d.h_deg = h;
    d.candela = cd;
    lumis_photometric *p = NULL;
    assert_int_equal(lumis_photometric_create(&d, NULL, &p), LUMIS_OK);
    lumis_vec3 dir;
    double pdf = 1;
    assert_int_equal(lumis_photometric_sample(p, 0.5, 0.5, &dir, &pdf), LUMIS_ERR_INVALID_ARGUMENT);
    assert_true(pdf == 0 && lumis_photometric_flux(p) == 0);
    const lumis_vec3 down = {0, 0, -1};
    assert_true(lumis_photometric_pdf(p, down) == 0);
    lumis_photometric_destroy(p);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(chi_square_goodness_of_fit),
        cmocka_unit_test(pdf_integrates_to_one_and_is_intensity_over_flux),
        cmocka_unit_test(pdf_of_samples_and_unbiased_estimates),
        cmocka_unit_test(black_table_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
