/* Statistical tests of the BSDFs (fixed seeds): for several materials and outgoing
 * directions, pdf(sample) equals the sampled pdf, the pdf integrates to at most one (one
 * for Lambert), a chi-square test of the samples against the pdf on a (cos theta, phi)
 * grid, the sample weight equals f cos / pdf, and white furnaces (albedo at most one). */
/* Oracles:
 * lumis_bsdf_eval — closed form: GGX conductor (anisotropic D, height-correlated G2, Schlick F),
 *     Cycles' glossy (the same D, separable G1 G1, a constant colour),
 *     Ward, the GGX plastic, written in the test; reciprocity; zero below the horizon
 *     (ggx_matches_its_closed_form, ward_and_plastic_match_their_closed_forms,
 *     below_the_surface_is_black)
 * lumis_bsdf_pdf — brute force, statistical: midpoint quadrature of the pdf integrates to at most 1
 *     (1 for Lambert); chi-square of drawn directions against it (bsdf_statistics)
 * lumis_bsdf_sample_wi — statistical, closed form: chi-square against the pdf, unit directions,
 *     weight = f cos / pdf; Lambert of albedo 1 weighs exactly 1, white furnaces ≤ 1
 *     (bsdf_statistics, white_furnace)
 */
#include "../testutil.h"

#include "lumis/bsdf.h"
#include "stat.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define PI 3.14159265358979323846

typedef struct material {
    const char *name;
    lumis_bsdf b;
} material;

static const material materials[] = {
    {"lambert", {LUMIS_BSDF_LAMBERT, {0.8f, 0.5f, 0.2f}, {0, 0, 0}, 0, 0}},
    {"ward iso 0.15", {LUMIS_BSDF_WARD, {0.1f, 0.1f, 0.1f}, {0.3f, 0.3f, 0.3f}, 0.15f, 0.15f}},
    {"ward aniso 0.5/0.08", {LUMIS_BSDF_WARD, {0, 0, 0}, {0.6f, 0.6f, 0.6f}, 0.5f, 0.08f}},
    {"ggx conductor 0.2", {LUMIS_BSDF_GGX_CONDUCTOR, {0, 0, 0}, {0.95f, 0.64f, 0.54f}, 0.2f, 0.2f}},
    {"ggx aniso 0.1/0.4", {LUMIS_BSDF_GGX_CONDUCTOR, {0, 0, 0}, {0.9f, 0.9f, 0.9f}, 0.1f, 0.4f}},
    {"ggx plastic 0.3", {LUMIS_BSDF_GGX_PLASTIC, {0.5f, 0.2f, 0.1f}, {0, 0, 0}, 0.3f, 0.3f}},
    {"ggx glossy 0.25", {LUMIS_BSDF_GGX_GLOSSY, {0, 0, 0}, {0.8f, 0.6f, 0.4f}, 0.25f, 0.25f}},
    {"ggx glossy aniso 0.5/0.1", {LUMIS_BSDF_GGX_GLOSSY, {0, 0, 0}, {1, 1, 1}, 0.5f, 0.1f}},
};
enum { NMAT = sizeof materials / sizeof materials[0] };
static const double thetas_deg[] = {5.0, 40.0, 75.0};

static lumis_vec3 dir_of(double theta, double phi)
{
    lumis_vec3 v = {(float)(sin(theta) * cos(phi)), (float)(sin(theta) * sin(phi)),
                    (float)cos(theta)};
    return v;
}

enum { NC = 32, NP = 64, SUB = 6 }; /* grid in cos theta and phi, sub-cells per axis */

/* Integral of the pdf over grid cell (a, b) by the midpoint rule on SUB x SUB sub-cells
 * (the grid is uniform in cos theta and phi, so every sub-cell has the same solid angle). */
static double cell_integral(const lumis_bsdf *b, lumis_vec3 wo, int a, int c)
{
    double acc = 0.0, dom = (1.0 / NC) * (2.0 * PI / NP) / (SUB * SUB);
    for (int i = 0; i < SUB; i++)
        for (int j = 0; j < SUB; j++) {
            double ct = (a + (i + 0.5) / SUB) / NC, phi = 2.0 * PI * (c + (j + 0.5) / SUB) / NP;
            acc += lumis_bsdf_pdf(b, wo, dir_of(acos(ct), phi)) * dom;
        }
    return acc;
}

static void bsdf_statistics(void **state)
{
    (void)state;
    const double alpha = 0.01 / (NMAT * 3);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 31, 4);
    for (int m = 0; m < NMAT; m++)
        for (int t = 0; t < 3; t++) {
            const lumis_bsdf *b = &materials[m].b;
            lumis_vec3 wo = dir_of(thetas_deg[t] * PI / 180.0, 0.7);
            double *obs = calloc(NC * NP, sizeof(double)), *exp_ = calloc(NC * NP, sizeof(double));
            const int n = 200000;
            for (int k = 0; k < n; k++) {
                lumis_bsdf_sample s =
                    lumis_bsdf_sample_wi(b, wo, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng),
                                         lumis_pcg32_double(&rng));
                if (s.pdf == 0.0f) continue; /* rejected: mass the pdf does not count */
                float p = lumis_bsdf_pdf(b, wo, s.wi);
                if (fabsf(p - s.pdf) > 1e-5f * s.pdf)
                    fail_msg("%s: pdf %g vs sampled %g", materials[m].name, p, s.pdf);
                lumis_rgb f = lumis_bsdf_eval(b, wo, s.wi);
                if (fabs(s.weight.r - f.r * s.wi.z / s.pdf) > 1e-4 * (fabs(s.weight.r) + 1e-6))
                    fail_msg("%s: weight %g vs f cos / pdf %g", materials[m].name, s.weight.r,
                             f.r * s.wi.z / s.pdf);
                double len = sqrt((double)s.wi.x * s.wi.x + (double)s.wi.y * s.wi.y +
                                  (double)s.wi.z * s.wi.z);
                assert_true(fabs(len - 1.0) < 1e-5);
                int a = (int)(s.wi.z * NC),
                    c = (int)(fmod(atan2(s.wi.y, s.wi.x) + 2 * PI, 2 * PI) / (2 * PI) * NP);
                a = a < 0 ? 0 : (a >= NC ? NC - 1 : a);
                c = c < 0 ? 0 : (c >= NP ? NP - 1 : c);
                obs[a * NP + c] += 1.0;
            }
            double integral = 0.0;
            for (int a = 0; a < NC; a++)
                for (int c = 0; c < NP; c++) {
                    double e = cell_integral(b, wo, a, c);
                    integral += e;
                    exp_[a * NP + c] = n * e;
                }
            if (integral > 1.0 + 2e-3)
                fail_msg("%s at %g deg: pdf integrates to %g", materials[m].name, thetas_deg[t],
                         integral);
            if (b->type == LUMIS_BSDF_LAMBERT && fabs(integral - 1.0) > 1e-3)
                fail_msg("lambert integral %g", integral);
            int dof;
            double p = stat_chi2_test(obs, exp_, NC * NP, &dof);
            if (!(p > alpha))
                fail_msg("%s at %g deg: chi-square p = %g (dof %d)", materials[m].name,
                         thetas_deg[t], p, dof);
            free(obs);
            free(exp_);
        }
}

/* White furnace: with white parameters the albedo (mean sample weight) is at most one;
 * Lambert of albedo one reflects exactly everything, every sample weighing 1. */
static void white_furnace(void **state)
{
    (void)state;
    const lumis_bsdf white[] = {
        {LUMIS_BSDF_LAMBERT, {1, 1, 1}, {0, 0, 0}, 0, 0},
        {LUMIS_BSDF_WARD, {0, 0, 0}, {1, 1, 1}, 0.3f, 0.3f},
        {LUMIS_BSDF_WARD, {0, 0, 0}, {1, 1, 1}, 0.5f, 0.001f},
        {LUMIS_BSDF_GGX_CONDUCTOR, {0, 0, 0}, {1, 1, 1}, 0.05f, 0.05f},
        {LUMIS_BSDF_GGX_CONDUCTOR, {0, 0, 0}, {1, 1, 1}, 0.8f, 0.8f},
        {LUMIS_BSDF_GGX_PLASTIC, {1, 1, 1}, {0, 0, 0}, 0.3f, 0.3f},
        {LUMIS_BSDF_GGX_GLOSSY, {0, 0, 0}, {1, 1, 1}, 0.05f, 0.05f},
        {LUMIS_BSDF_GGX_GLOSSY, {0, 0, 0}, {1, 1, 1}, 0.8f, 0.8f},
    };
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 8, 8);
    for (int m = 0; m < (int)(sizeof white / sizeof white[0]); m++)
        for (int t = 0; t < 3; t++) {
            lumis_vec3 wo = dir_of(thetas_deg[t] * PI / 180.0, 2.0);
            double sum = 0.0, sum2 = 0.0;
            const int n = 100000;
            for (int k = 0; k < n; k++) {
                lumis_bsdf_sample s =
                    lumis_bsdf_sample_wi(&white[m], wo, lumis_pcg32_double(&rng),
                                         lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
                sum += s.weight.g;
                sum2 += (double)s.weight.g * s.weight.g;
                if (m == 0) assert_true(fabsf(s.weight.g - 1.0f) < 1e-5f);
            }
            double mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0.0) / n);
            if (mean > 1.0 + 4 * se + 1e-4)
                fail_msg("white material %d at %g deg: albedo %g +- %g", m, thetas_deg[t], mean,
                         se);
        }
}

/* The unit vector at polar angle deg[0] and azimuth deg[1] (degrees), z up. */
static void dir_deg(const double deg[2], double v[3])
{
    const double th = deg[0] * PI / 180, ph = deg[1] * PI / 180;
    v[0] = sin(th) * cos(ph);
    v[1] = sin(th) * sin(ph);
    v[2] = cos(th);
}

/* The GGX conductor against its closed form, written out here: f = F D G2 / (4 cos o cos i)
 * with the anisotropic D, Smith's height-correlated G2 = 1 / (1 + Lambda(wo) + Lambda(wi))
 * and Schlick's F on the half vector (docs/bsdf.md).  The furnace only bounds the albedo
 * from above: G1(wo) in place of G2 passed it, and every other test. */
static double ggx_lambda(double ax, double ay, const double w[3])
{
    const double t2 = (ax * ax * w[0] * w[0] + ay * ay * w[1] * w[1]) / (w[2] * w[2]);
    return 0.5 * (-1.0 + sqrt(1.0 + t2));
}

static void ggx_matches_its_closed_form(void **state)
{
    (void)state;
    const double axs[3] = {0.3, 0.6, 0.15}, ays[3] = {0.3, 0.6, 0.45};
    const double dirs[4][2][2] = {/* (theta, phi) of wo and wi, degrees */
                                  {{30, 10}, {50, 200}},
                                  {{70, 0}, {60, 170}},
                                  {{10, 90}, {80, 45}},
                                  {{85, 30}, {84, 215}}};
    for (int m = 0; m < 3; m++)
        for (int q = 0; q < 4; q++) {
            lumis_bsdf b = {LUMIS_BSDF_GGX_CONDUCTOR,
                            {0, 0, 0},
                            {0.9f, 0.6f, 0.3f},
                            (float)axs[m],
                            (float)ays[m]};
            double o[3], i[3];
            dir_deg(dirs[q][0], o);
            dir_deg(dirs[q][1], i);
            double h[3] = {o[0] + i[0], o[1] + i[1], o[2] + i[2]};
            const double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
            for (int k = 0; k < 3; k++) h[k] /= hl;
            const double ax = axs[m], ay = ays[m];
            const double e = (h[0] * h[0]) / (ax * ax) + (h[1] * h[1]) / (ay * ay) + h[2] * h[2];
            const double D = 1.0 / (PI * ax * ay * e * e);
            const double G2 = 1.0 / (1.0 + ggx_lambda(ax, ay, o) + ggx_lambda(ax, ay, i));
            const double c = o[0] * h[0] + o[1] * h[1] + o[2] * h[2];
            const float f0[3] = {0.9f, 0.6f, 0.3f};
            const lumis_vec3 wo = {(float)o[0], (float)o[1], (float)o[2]},
                             wi = {(float)i[0], (float)i[1], (float)i[2]};
            const lumis_rgb f = lumis_bsdf_eval(&b, wo, wi);
            const float got[3] = {f.r, f.g, f.b};
            for (int ch = 0; ch < 3; ch++) {
                const double F = f0[ch] + (1.0 - f0[ch]) * pow(1.0 - c, 5.0);
                const double want = F * D * G2 / (4.0 * o[2] * i[2]);
                if (!(fabs(got[ch] - want) <= 2e-5 * want))
                    fail_msg("alpha (%g, %g), pair %d, channel %d: f = %.8g, closed form %.8g", ax,
                             ay, q, ch, got[ch], want);
            }
            /* Cycles' Glossy BSDF: colour x D G1(wo) G1(wi) / (4 cos o cos i), no Fresnel
             * (Cycles 3.4, bsdf_microfacet_ggx_eval_reflect); reciprocal. */
            b.type = LUMIS_BSDF_GGX_GLOSSY;
            const double G11 =
                1.0 / ((1.0 + ggx_lambda(ax, ay, o)) * (1.0 + ggx_lambda(ax, ay, i)));
            const lumis_rgb fg = lumis_bsdf_eval(&b, wo, wi), fr = lumis_bsdf_eval(&b, wi, wo);
            const float gg[3] = {fg.r, fg.g, fg.b}, gr[3] = {fr.r, fr.g, fr.b};
            for (int ch = 0; ch < 3; ch++) {
                const double want = f0[ch] * D * G11 / (4.0 * o[2] * i[2]);
                if (!(fabs(gg[ch] - want) <= 2e-5 * want) || !(fabs(gr[ch] - want) <= 2e-5 * want))
                    fail_msg("glossy alpha (%g, %g), pair %d, channel %d: f = %.8g / %.8g "
                             "(reversed), closed form %.8g",
                             ax, ay, q, ch, gg[ch], gr[ch], want);
            }
        }
}

/* Ward and the GGX plastic against their closed forms (docs/bsdf.md), written out here:
 * Ward f = rho_d / pi + rho_s (h.h) / (pi ax ay hz^4) exp(-(hx^2/ax^2 + hy^2/ay^2) / hz^2)
 * with h = wo + wi unnormalised; the plastic f = F(wo.h) D G2 / (4 cos o cos i) +
 * rho_d (1 - F(cos o)) (1 - F(cos i)) / pi with F0 = 0.04.  Every material is reciprocal,
 * f(wo, wi) = f(wi, wo).  The chi-square and weight checks compare eval with itself, so a
 * Ward diffuse lobe without 1/pi, hz^3 for hz^4, or a coat counted one way passed them. */
static void ward_and_plastic_match_their_closed_forms(void **state)
{
    (void)state;
    const double dirs[4][2][2] = {/* (theta, phi) of wo and wi, degrees */
                                  {{30, 10}, {50, 200}},
                                  {{70, 0}, {60, 170}},
                                  {{10, 90}, {80, 45}},
                                  {{45, 30}, {40, 215}}};
    const lumis_bsdf ward = {LUMIS_BSDF_WARD, {0.2f, 0.3f, 0.1f}, {0.4f, 0.3f, 0.5f}, 0.3f, 0.15f};
    const lumis_bsdf plastic = {LUMIS_BSDF_GGX_PLASTIC, {0.6f, 0.3f, 0.1f}, {0, 0, 0}, 0.25f, 0.4f};
    for (int q = 0; q < 4; q++) {
        double o[3], i[3];
        dir_deg(dirs[q][0], o);
        dir_deg(dirs[q][1], i);
        const lumis_vec3 wo = {(float)o[0], (float)o[1], (float)o[2]},
                         wi = {(float)i[0], (float)i[1], (float)i[2]};
        /* Ward */
        {
            const double ax = 0.3, ay = 0.15;
            const double h[3] = {o[0] + i[0], o[1] + i[1], o[2] + i[2]};
            const double hh = h[0] * h[0] + h[1] * h[1] + h[2] * h[2];
            const double e = (h[0] * h[0] / (ax * ax) + h[1] * h[1] / (ay * ay)) / (h[2] * h[2]);
            const double spec = hh / (PI * ax * ay * pow(h[2], 4.0)) * exp(-e);
            const float rd[3] = {0.2f, 0.3f, 0.1f}, rs[3] = {0.4f, 0.3f, 0.5f};
            const lumis_rgb f = lumis_bsdf_eval(&ward, wo, wi);
            const float got[3] = {f.r, f.g, f.b};
            for (int ch = 0; ch < 3; ch++) {
                const double want = rd[ch] / PI + rs[ch] * spec;
                if (!(fabs(got[ch] - want) <= 2e-5 * want))
                    fail_msg("ward, pair %d, channel %d: f = %.8g, closed form %.8g", q, ch,
                             got[ch], want);
            }
        }
        /* GGX plastic */
        {
            const double ax = 0.25, ay = 0.4, f0 = 0.04;
            double h[3] = {o[0] + i[0], o[1] + i[1], o[2] + i[2]};
            const double hl = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
            for (int k = 0; k < 3; k++) h[k] /= hl;
            const double e = (h[0] * h[0]) / (ax * ax) + (h[1] * h[1]) / (ay * ay) + h[2] * h[2];
            const double D = 1.0 / (PI * ax * ay * e * e);
            const double G2 = 1.0 / (1.0 + ggx_lambda(ax, ay, o) + ggx_lambda(ax, ay, i));
            const double c = o[0] * h[0] + o[1] * h[1] + o[2] * h[2];
            const double F = f0 + (1 - f0) * pow(1 - c, 5.0);
            const double To = 1 - (f0 + (1 - f0) * pow(1 - o[2], 5.0)),
                         Ti = 1 - (f0 + (1 - f0) * pow(1 - i[2], 5.0));
            const float rd[3] = {0.6f, 0.3f, 0.1f};
            const lumis_rgb f = lumis_bsdf_eval(&plastic, wo, wi);
            const float got[3] = {f.r, f.g, f.b};
            for (int ch = 0; ch < 3; ch++) {
                const double want = F * D * G2 / (4.0 * o[2] * i[2]) + rd[ch] * To * Ti / PI;
                if (!(fabs(got[ch] - want) <= 2e-5 * want))
                    fail_msg("plastic, pair %d, channel %d: f = %.8g, closed form %.8g", q, ch,
                             got[ch], want);
            }
        }
        /* reciprocity, every material */
        for (int m = 0; m < NMAT; m++) {
            const lumis_rgb a = lumis_bsdf_eval(&materials[m].b, wo, wi),
                            b = lumis_bsdf_eval(&materials[m].b, wi, wo);
            if (!(fabsf(a.r - b.r) <= 1e-5f * fabsf(a.r) && fabsf(a.g - b.g) <= 1e-5f * fabsf(a.g)))
                fail_msg("%s, pair %d: f(wo, wi) = %g, f(wi, wo) = %g", materials[m].name, q, a.r,
                         b.r);
        }
    }
}

static void below_the_surface_is_black(void **state)
{
    (void)state;
    for (int m = 0; m < NMAT; m++) {
        const lumis_bsdf *b = &materials[m].b;
        lumis_vec3 up = {0, 0, 1}, down = {0.6f, 0, -0.8f};
        lumis_rgb f = lumis_bsdf_eval(b, up, down);
        assert_true(f.r == 0.0f && lumis_bsdf_pdf(b, up, down) == 0.0f);
        lumis_bsdf_sample s = lumis_bsdf_sample_wi(b, down, 0.5, 0.5, 0.5);
        assert_true(s.pdf == 0.0f && s.weight.r == 0.0f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bsdf_statistics),
        cmocka_unit_test(white_furnace),
        cmocka_unit_test(below_the_surface_is_black),
        cmocka_unit_test(ggx_matches_its_closed_form),
        cmocka_unit_test(ward_and_plastic_match_their_closed_forms),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
