/* The image sun (lumis/sun.h): detection, the exact split, and the cone's sampling. */
/* Oracles:
 * lumis_sun_find — closed form: a disk of known direction, radius and radiance drawn on a
 *     coloured asymmetric background at odd sizes (rotated too; over either pole and with its
 *     rim across one, where the fit's rows end at the map's edge), and the Preetham sky's sun of
 *     docs/sky.md (direction from its elevation and azimuth, power from its transmittance);
 *     brute force: the residual + the sun's pixels == the map, pixel by pixel and in power;
 *     hand-worked: no sun in a uniform, black, NaN, 1 x 1, too coarse, sunless-sky or
 *     pmndrs-venice map (synthetic_disk_is_recovered, suns_at_the_poles_are_recovered,
 *     sky_sun_is_recovered, split_is_exact, no_sun_where_there_is_none,
 *     find_refuses_bad_arguments)
 * lumis_sun_eval — brute force: eval + the residual's eval == the map's eval, bit for bit, in
 *     random directions and at every pixel centre (split_is_exact,
 *     sun_functions_refuse_bad_input)
 * lumis_sun_contains — brute force: the pixels the test's own centre formula puts within the
 *     radius; hand-worked: nothing for a sun no find returns (not found, a cone of no or too
 *     wide an angle, an axis zero or not finite), no map, a pixel off the map, a direction
 *     zero or not finite, and the same of every function below (split_is_exact,
 *     sun_functions_refuse_bad_input)
 * lumis_sun_sample — statistical: chi-square over equal-area bins of a frame built by the
 *     test; unbiased estimates of the map's power and of the irradiance on planes against a
 *     brute-force sum over sub-pixels, with the residual's sampler, on all three channels
 *     (cone_chi_square, power_is_unbiased, irradiance_matches_brute_force,
 *     sun_functions_refuse_bad_input)
 * lumis_sun_pdf — closed form: integrates to 1 over the sphere by quadrature, 0 outside the
 *     cone; consistency: equals the sample's pdf (cone_pdf_integrates_to_one, cone_chi_square,
 *     sun_functions_refuse_bad_input)
 * lumis_sun_invert — consistency: invert(sample(u)) == u, the round trip (cone_chi_square,
 *     sun_functions_refuse_bad_input)
 * lumis_sun_sampler_create — brute force: the pixels and probabilities the test computes from
 *     the map's luminance (sun_pixels_by_power, suns_at_the_poles_are_recovered,
 *     sun_functions_refuse_bad_input)
 * lumis_sun_sampler_sample — statistical: chi-square over the sun's pixels against Y Omega /
 *     sum; unbiased power and brute-force irradiance, all channels (sun_pixels_by_power,
 *     power_is_unbiased, irradiance_matches_brute_force, sun_functions_refuse_bad_input)
 * lumis_sun_sampler_pdf — brute force: Y / sum(Y Omega) at every pixel, 0 off the sun, sums to
 *     1 over the map (sun_pixels_by_power, suns_at_the_poles_are_recovered,
 *     sun_functions_refuse_bad_input)
 * lumis_sun_sampler_destroy — consistency: frees what create made (every test, under the
 *     sanitizers' leak check)
 */
#include "testutil.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* The direction of map coordinate (u, v) (docs/coordinates.md), written here apart. */
static void dir_uv(double u, double v, double d[3])
{
    const double th = PI * v, ph = 2.0 * PI * u;
    d[0] = sin(th) * cos(ph);
    d[1] = cos(th);
    d[2] = sin(th) * sin(ph);
}

static double ang(const double a[3], const double b[3])
{
    const double c =
        (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]) /
        sqrt((a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) * (b[0] * b[0] + b[1] * b[1] + b[2] * b[2]));
    return acos(c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c);
}

static double solid(int w, int h, int j)
{
    return 2.0 * PI / w * (cos(PI * j / h) - cos(PI * (j + 1) / h));
}

/* A disk of radius rad_deg about (theta0, phi0) of radiance sun[] over a coloured, asymmetric
 * background; pixels by their centres.  Returns the pixels (caller frees) and the disk's
 * power per channel. */
static float *disk_map(int w, int h, double th0, double ph0, double rad_deg, const float sun[3],
                       double power[3])
{
    float *px = malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
    assert_non_null(px);
    double s0[3];
    dir_uv(ph0 / (2.0 * PI), th0 / PI, s0);
    power[0] = power[1] = power[2] = 0.0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const double u = (i + 0.5) / w, v = (j + 0.5) / h;
            double c[3];
            dir_uv(u, v, c);
            float *p = px + 3 * ((size_t)j * w + i);
            if (ang(c, s0) <= rad_deg * PI / 180.0) {
                for (int k = 0; k < 3; k++) {
                    p[k] = sun[k];
                    power[k] += sun[k] * solid(w, h, j);
                }
            } else {
                p[0] = (float)(0.3 + 0.2 * u);
                p[1] = (float)(0.5 * (1.0 - v) + 0.1);
                p[2] = (float)(0.2 + 0.4 * u * v);
            }
        }
    return px;
}

static lumis_envmap *env_of(const float *px, int w, int h, float rot, float scale)
{
    lumis_envmap_desc d = {0};
    d.pixels = px;
    d.width = w;
    d.height = h;
    d.rotation_deg = rot;
    d.scale = scale;
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_create(&d, &env), LUMIS_OK);
    return env;
}

static double lum(const double p[3])
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

static void synthetic_disk_is_recovered(void **state)
{
    (void)state;
    static const int sizes[][2] = {{301, 151}, {512, 256}, {1023, 511}};
    const float sun[3] = {5.0e4f, 3.0e4f, 1.0e4f};
    const double th0 = 50.0 * PI / 180.0, ph0 = 123.0 * PI / 180.0, rad = 2.5;
    for (int s = 0; s < 3; s++)
        for (int r = 0; r < 2; r++) {
            const int w = sizes[s][0], h = sizes[s][1];
            const float rot = r ? 37.0f : 0.0f, scale = r ? 2.0f : 1.0f;
            double pw[3];
            float *px = disk_map(w, h, th0, ph0, rad, sun, pw);
            lumis_envmap *env = env_of(px, w, h, rot, scale);
            lumis_sun f;
            lumis_envmap *res = NULL;
            assert_int_equal(lumis_sun_find(env, NULL, &f, &res), LUMIS_OK);
            assert_int_equal(f.found, 1);
            assert_non_null(res);
            /* the disk's centre, turned by the map's rotation about +y */
            double m[3], want[3];
            dir_uv(ph0 / (2.0 * PI), th0 / PI, m);
            const double cr = cos(rot * PI / 180.0), sr = sin(rot * PI / 180.0);
            want[0] = cr * m[0] - sr * m[2];
            want[1] = m[1];
            want[2] = sr * m[0] + cr * m[2];
            const double got[3] = {f.dir.x, f.dir.y, f.dir.z}, pix = 180.0 / h; /* degrees */
            /* within a tenth of a pixel: the disk's pixels are symmetric to that */
            assert_true(ang(got, want) * 180.0 / PI < 0.1 * pix);
            /* the disk's pixel centres reach to within a pixel of its rim */
            assert_true(f.radius * 180.0 / PI <= rad + 0.1 * pix);
            assert_true(f.radius * 180.0 / PI >= rad - pix);
            assert_true(f.sample_radius >= f.radius);
            assert_true(f.sample_radius * 180.0 / PI <= rad + 2.5 * pix);
            /* its power: the disk's pixels (scaled), and the little background whose pixel
             * centres the fitted disk also holds */
            for (int k = 0; k < 3; k++) {
                assert_true(f.power[k] >= scale * pw[k] * (1.0 - 1e-6));
                assert_true(f.power[k] <= scale * pw[k] * (1.0 + 1e-3));
            }
            const lumis_rgb tot = lumis_envmap_power(env);
            const double tp[3] = {tot.r, tot.g, tot.b};
            assert_true(fabs(f.share - lum(pw) * scale / lum(tp)) < 1e-4);
            /* the mean radiance of its pixels: the disk's, diluted by any background pixel
             * the fitted disk holds */
            assert_true(fabs(f.radiance.g * f.solid_angle - f.power[1]) < 1e-6 * f.power[1]);
            assert_true(f.radiance.g <= sun[1] * scale && f.radiance.g > 0.8 * sun[1] * scale);
            lumis_envmap_destroy(res);
            lumis_envmap_destroy(env);
            free(px);
        }
}

/* A disk over a pole, and one whose rim crosses it: the rows the fit, the residual and the
 * sampler visit run from the top row or to the bottom one (where the padding row about the
 * disk is clamped away), so the power, direction and radius must still be the disk's, the
 * residual zero on all its pixels and the sampler's pdf Y / sum(Y Omega) on each.  The nadir's disk
 * holds whole rows (the bottom row is a quarter of its power at 151 rows), the zenith's is its
 * mirror image. */
static void suns_at_the_poles_are_recovered(void **state)
{
    (void)state;
    static const int sizes[][2] = {{301, 151}, {512, 256}};
    /* the disk's centre, degrees from the zenith: nadir, zenith, 1.5 degrees off each */
    static const double theta[] = {180.0, 0.0, 178.5, 1.5};
    const float sun[3] = {4.0e4f, 2.0e4f, 1.0e4f};
    const double rad = 2.5, ph0 = 77.0 * PI / 180.0;
    for (int s = 0; s < 2; s++)
        for (int t = 0; t < 4; t++) {
            const int w = sizes[s][0], h = sizes[s][1];
            const double th0 = theta[t] * PI / 180.0, pix = 180.0 / h; /* degrees */
            double pw[3];
            float *px = disk_map(w, h, th0, ph0, rad, sun, pw);
            lumis_envmap *env = env_of(px, w, h, 0.0f, 1.0f);
            lumis_sun f;
            lumis_envmap *res = NULL;
            assert_int_equal(lumis_sun_find(env, NULL, &f, &res), LUMIS_OK);
            assert_int_equal(f.found, 1);
            lumis_sun_sampler *ss = NULL;
            assert_int_equal(lumis_sun_sampler_create(env, &f, NULL, &ss), LUMIS_OK);
            /* the residual is zero on the sun's pixels and the map elsewhere; the sampler
             * draws every sun pixel by its Y Omega, the first and last rows included */
            double sumY = 0.0;
            int inside = 0;
            for (int j = 0; j < h; j++)
                for (int i = 0; i < w; i++)
                    if (lumis_sun_contains(&f, env, i, j)) {
                        const float *q = px + 3 * ((size_t)j * w + i);
                        sumY += (0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2]) * solid(w, h, j);
                    }
            for (int j = 0; j < h; j++)
                for (int i = 0; i < w; i++) {
                    const int in = lumis_sun_contains(&f, env, i, j);
                    const lumis_rgb m = lumis_envmap_texel(env, i, j),
                                    r = lumis_envmap_texel(res, i, j);
                    if (in)
                        assert_true(r.r == 0.0f && r.g == 0.0f && r.b == 0.0f);
                    else
                        assert_true(r.r == m.r && r.g == m.g && r.b == m.b);
                    inside += in;
                    const float *q = px + 3 * ((size_t)j * w + i);
                    const double want_pdf =
                        in ? (0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2]) / sumY : 0.0;
                    const lumis_vec3 c =
                        lumis_envmap_uv_to_dir(env, ((float)i + 0.5f) / w, ((float)j + 0.5f) / h);
                    const double pdf = lumis_sun_sampler_pdf(ss, c, NULL);
                    if (!(fabs(pdf - want_pdf) <= 1e-5 * want_pdf))
                        fail_msg("%d x %d, disk at %g degrees: pixel (%d, %d): pdf %g, want %g", w,
                                 h, theta[t], i, j, pdf, want_pdf);
                }
            assert_int_equal(inside, f.pixels);
            lumis_sun_sampler_destroy(ss);
            lumis_envmap_destroy(res);
            double want[3];
            dir_uv(ph0 / (2.0 * PI), th0 / PI, want);
            const double got[3] = {f.dir.x, f.dir.y, f.dir.z};
            const double off = ang(got, want) * 180.0 / PI;
            /* over the pole the disk's pixels are symmetric about its centre; off it, a
             * row's pixels are not, by up to a pixel's width there */
            if (!(off < (t < 2 ? 1e-4 : 0.25) * pix))
                fail_msg("%d x %d, disk at %g degrees: direction %g degrees off", w, h, theta[t],
                         off);
            assert_true(f.radius * 180.0 / PI <= rad + 0.25 * pix);
            assert_true(f.radius * 180.0 / PI >= rad - pix);
            for (int k = 0; k < 3; k++)
                if (!(f.power[k] >= pw[k] * (1.0 - 1e-6) && f.power[k] <= pw[k] * (1.0 + 2e-3)))
                    fail_msg("%d x %d, disk at %g degrees: channel %d power %.9g, the disk's %.9g",
                             w, h, theta[t], k, f.power[k], pw[k]);
            lumis_envmap_destroy(env);
            free(px);
        }
}

static void sky_sun_is_recovered(void **state)
{
    (void)state;
    lumis_sky_desc sd = {0};
    sd.sun_elevation_deg = 35.0f;
    sd.sun_azimuth_deg = 60.0f;
    lumis_image *img = NULL;
    assert_int_equal(lumis_sky_create(&sd, &img), LUMIS_OK);
    lumis_envmap *env = tu_envmap_of(img, 0.0f, 0.0f);
    lumis_sun f;
    assert_int_equal(lumis_sun_find(env, NULL, &f, NULL), LUMIS_OK);
    assert_int_equal(f.found, 1);
    const double e = 35.0 * PI / 180.0, a = 60.0 * PI / 180.0;
    const double want[3] = {cos(e) * cos(a), sin(e), cos(e) * sin(a)},
                 got[3] = {f.dir.x, f.dir.y, f.dir.z};
    /* the 0.27 degree disk is rasterised onto pixels of 0.35 degrees */
    assert_true(ang(got, want) * 180.0 / PI < 0.2);
    assert_true(f.radius * 180.0 / PI < 1.0);
    /* the sun's power of docs/sky.md (128 klx times the transmittance), plus the little sky
     * inside its pixels */
    const double zen = 55.0, zr = zen * PI / 180.0;
    const double mass = 1.0 / (cos(zr) + 0.15 * pow(93.885 - zen, -1.253));
    const double lambda[3] = {0.65, 0.55, 0.45};
    for (int c = 0; c < 3; c++) {
        const double tau = exp(-mass * (0.008735 * pow(lambda[c], -4.08) +
                                        (0.04608 * 2.5 - 0.04586) * pow(lambda[c], -1.3)));
        assert_true(f.power[c] >= 128.0 * tau * (1.0 - 1e-4));
        assert_true(f.power[c] <= 128.0 * tau * 1.003);
    }
    assert_true(f.share > 0.5 && f.share < 0.6);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

static void split_is_exact(void **state)
{
    (void)state;
    const int w = 301, h = 151;
    const float sun[3] = {2.0e4f, 4.0e4f, 1.0e4f};
    double pw[3];
    /* near the pole, across the seam */
    float *px = disk_map(w, h, 4.0 * PI / 180.0, 359.0 * PI / 180.0, 3.0, sun, pw);
    lumis_envmap *env = env_of(px, w, h, 11.0f, 0.5f);
    lumis_sun f;
    lumis_envmap *res = NULL;
    assert_int_equal(lumis_sun_find(env, NULL, &f, &res), LUMIS_OK);
    assert_int_equal(f.found, 1);
    /* pixel by pixel: the residual is the map off the sun and zero on it */
    int inside = 0;
    double cone = 0.0;
    const double a[3] = {f.dir.x, f.dir.y, f.dir.z};
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const lumis_rgb m = lumis_envmap_texel(env, i, j), r = lumis_envmap_texel(res, i, j);
            const lumis_vec3 c =
                lumis_envmap_uv_to_dir(env, ((float)i + 0.5f) / w, ((float)j + 0.5f) / h);
            const double cd[3] = {c.x, c.y, c.z};
            const int in = lumis_sun_contains(&f, env, i, j);
            /* the test's own angle agrees away from the rim's rounding */
            if (fabs(ang(a, cd) - f.radius) > 1e-6) assert_int_equal(in, ang(a, cd) <= f.radius);
            inside += in;
            if (in) {
                assert_true(r.r == 0.0f && r.g == 0.0f && r.b == 0.0f);
                cone = fmax(cone, ang(a, cd));
            } else {
                assert_true(r.r == m.r && r.g == m.g && r.b == m.b);
            }
            const lumis_rgb s = lumis_sun_eval(&f, env, c);
            assert_true(s.r + r.r == m.r && s.g + r.g == m.g && s.b + r.b == m.b);
        }
    assert_int_equal(inside, f.pixels);
    /* in random directions */
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 7, 1);
    for (int k = 0; k < 200000; k++) {
        double u[2] = {lumis_pcg32_double(&rng), lumis_pcg32_double(&rng)}, d[3];
        lumis_vec3 v;
        if (k & 1) { /* half of them near the sun */
            v = lumis_sun_sample(&f, u[0], u[1], NULL);
        } else {
            dir_uv(u[0], u[1], d);
            v.x = (float)d[0];
            v.y = (float)d[1];
            v.z = (float)d[2];
        }
        const lumis_rgb m = lumis_envmap_eval(env, v), r = lumis_envmap_eval(res, v),
                        s = lumis_sun_eval(&f, env, v);
        assert_true(s.r + r.r == m.r && s.g + r.g == m.g && s.b + r.b == m.b);
        assert_true((s.r == 0.0f && s.g == 0.0f && s.b == 0.0f) ||
                    (r.r == 0.0f && r.g == 0.0f && r.b == 0.0f));
    }
    /* in power */
    const lumis_rgb pm = lumis_envmap_power(env), pr = lumis_envmap_power(res);
    assert_true(fabs(pr.r + f.power[0] - pm.r) < 1e-5 * pm.r);
    assert_true(fabs(pr.g + f.power[1] - pm.g) < 1e-5 * pm.g);
    assert_true(fabs(pr.b + f.power[2] - pm.b) < 1e-5 * pm.b);
    lumis_envmap_destroy(res);
    lumis_envmap_destroy(env);
    free(px);
}

/* A sun found in the synthetic disk map (w x h), for the sampling tests. */
static lumis_envmap *sun_map(int w, int h, lumis_sun *f, lumis_envmap **res, float **px)
{
    const float sun[3] = {3.0e3f, 2.0e3f, 5.0e3f};
    double pw[3];
    *px = disk_map(w, h, 70.0 * PI / 180.0, 200.0 * PI / 180.0, 2.0, sun, pw);
    lumis_envmap *env = env_of(*px, w, h, 23.0f, 0.0f);
    assert_int_equal(lumis_sun_find(env, NULL, f, res), LUMIS_OK);
    assert_int_equal(f->found, 1);
    return env;
}

/* An orthonormal frame about a, built here (not the library's). */
static void test_frame(const double a[3], double t[3], double b[3])
{
    const double h[3] = {fabs(a[0]) < 0.9 ? 1.0 : 0.0, fabs(a[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    t[0] = h[1] * a[2] - h[2] * a[1];
    t[1] = h[2] * a[0] - h[0] * a[2];
    t[2] = h[0] * a[1] - h[1] * a[0];
    const double n = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (int k = 0; k < 3; k++) t[k] /= n;
    b[0] = a[1] * t[2] - a[2] * t[1];
    b[1] = a[2] * t[0] - a[0] * t[2];
    b[2] = a[0] * t[1] - a[1] * t[0];
}

static void cone_chi_square(void **state)
{
    (void)state;
    lumis_sun f;
    lumis_envmap *res = NULL;
    float *px = NULL;
    lumis_envmap *env = sun_map(401, 201, &f, &res, &px);
    double a[3] = {f.dir.x, f.dir.y, f.dir.z}, t[3], b[3];
    const double na = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int k = 0; k < 3; k++) a[k] /= na;
    test_frame(a, t, b);
    enum { RINGS = 20, SECTORS = 16, N = 320000 };
    static double count[RINGS * SECTORS];
    memset(count, 0, sizeof count);
    const double hmax = 1.0 - cos(f.sample_radius), want_pdf = 1.0 / (2.0 * PI * hmax);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 3, 5);
    for (int k = 0; k < N; k++) {
        const double u1 = lumis_pcg32_double(&rng), u2 = lumis_pcg32_double(&rng);
        double pdf = 0.0;
        const lumis_vec3 v = lumis_sun_sample(&f, u1, u2, &pdf);
        assert_true(fabs(pdf - want_pdf) < 1e-6 * want_pdf);
        assert_true(lumis_sun_pdf(&f, v) == pdf);
        double uu[2];
        assert_int_equal(lumis_sun_invert(&f, v, uu), LUMIS_OK);
        assert_true(fabs(uu[0] - u1) < 2e-3 &&
                    (fabs(uu[1] - u2) < 1e-4 || fabs(uu[1] - u2) > 0.9999));
        const double d[3] = {v.x, v.y, v.z}, th = ang(a, d);
        const double hh = 1.0 - cos(th);
        int ring = (int)(hh / hmax * RINGS);
        ring = ring >= RINGS ? RINGS - 1 : ring;
        double ph =
            atan2(d[0] * b[0] + d[1] * b[1] + d[2] * b[2], d[0] * t[0] + d[1] * t[1] + d[2] * t[2]);
        if (ph < 0.0) ph += 2.0 * PI;
        int sec = (int)(ph / (2.0 * PI) * SECTORS);
        sec = sec >= SECTORS ? SECTORS - 1 : sec;
        count[ring * SECTORS + sec] += 1.0;
    }
    double chi2 = 0.0;
    const double e = (double)N / (RINGS * SECTORS);
    for (int k = 0; k < RINGS * SECTORS; k++) chi2 += (count[k] - e) * (count[k] - e) / e;
    const double dof = RINGS * SECTORS - 1;
    /* p ~ 1e-5 for 319 degrees of freedom */
    assert_true(chi2 < dof + 4.5 * sqrt(2.0 * dof));
    lumis_envmap_destroy(res);
    lumis_envmap_destroy(env);
    free(px);
}

static void cone_pdf_integrates_to_one(void **state)
{
    (void)state;
    lumis_sun f;
    lumis_envmap *res = NULL;
    float *px = NULL;
    lumis_envmap *env = sun_map(257, 129, &f, &res, &px);
    double a[3] = {f.dir.x, f.dir.y, f.dir.z}, t[3], b[3];
    const double na = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    for (int k = 0; k < 3; k++) a[k] /= na;
    test_frame(a, t, b);
    /* midpoint rule in (1 - cos, phi) about the axis: fine near it, coarse beyond (where the
     * pdf must be 0) */
    const double hcut = 4.0 * (1.0 - cos(f.sample_radius));
    double sum = 0.0;
    for (int pass = 0; pass < 2; pass++) {
        const int nh = pass ? 400 : 4000, nphi = 64;
        const double h0 = pass ? hcut : 0.0, h1 = pass ? 2.0 : hcut, dh = (h1 - h0) / nh;
        for (int i = 0; i < nh; i++) {
            const double hh = h0 + (i + 0.5) * dh, ct = 1.0 - hh, st = sqrt(hh * (2.0 - hh));
            for (int k = 0; k < nphi; k++) {
                const double ph = 2.0 * PI * (k + 0.5) / nphi;
                lumis_vec3 v;
                v.x = (float)(st * (cos(ph) * t[0] + sin(ph) * b[0]) + ct * a[0]);
                v.y = (float)(st * (cos(ph) * t[1] + sin(ph) * b[1]) + ct * a[1]);
                v.z = (float)(st * (cos(ph) * t[2] + sin(ph) * b[2]) + ct * a[2]);
                const double p = lumis_sun_pdf(&f, v);
                if (pass) assert_true(p == 0.0);
                sum += p * dh * 2.0 * PI / nphi;
            }
        }
    }
    assert_true(fabs(sum - 1.0) < 1e-3);
    lumis_envmap_destroy(res);
    lumis_envmap_destroy(env);
    free(px);
}

static lumis_sampler *residual_sampler(const lumis_envmap *res)
{
    lumis_sampler_desc sd = {0};
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_sampler_create(res, &sd, &smp), LUMIS_OK);
    return smp;
}

static void power_is_unbiased(void **state)
{
    (void)state;
    lumis_sun f;
    lumis_envmap *res = NULL;
    float *px = NULL;
    lumis_envmap *env = sun_map(301, 151, &f, &res, &px);
    lumis_sampler *smp = residual_sampler(res);
    lumis_sun_sampler *ss = NULL;
    assert_int_equal(lumis_sun_sampler_create(env, &f, NULL, &ss), LUMIS_OK);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 11, 2);
    const int n = 400000;
    const lumis_rgb pm = lumis_envmap_power(env);
    const double want[3] = {pm.r, pm.g, pm.b};
    for (int way = 0; way < 2; way++) { /* the cone, then the sun's pixels by power */
        double s1[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
        for (int k = 0; k < n; k++) {
            double p = 0.0;
            const double a1 = lumis_pcg32_double(&rng), a2 = lumis_pcg32_double(&rng);
            lumis_rgb lr = {0.0f, 0.0f, 0.0f};
            const lumis_vec3 v = way ? lumis_sun_sampler_sample(ss, a1, a2, &p, &lr)
                                     : lumis_sun_sample(&f, a1, a2, &p);
            const lumis_rgb ls = lumis_sun_eval(&f, env, v);
            if (way) {
                assert_true(ls.r == lr.r && ls.g == lr.g && ls.b == lr.b);
                assert_true(lumis_sun_sampler_pdf(ss, v, NULL) == p);
            }
            const lumis_env_sample e =
                lumis_sampler_sample(smp, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
            const double x[3] = {ls.r / p + e.radiance.r / e.pdf, ls.g / p + e.radiance.g / e.pdf,
                                 ls.b / p + e.radiance.b / e.pdf};
            for (int c = 0; c < 3; c++) {
                s1[c] += x[c];
                s2[c] += x[c] * x[c];
            }
        }
        for (int c = 0; c < 3; c++) {
            const double mean = s1[c] / n, var = s2[c] / n - mean * mean, se = sqrt(var / n);
            assert_true(fabs(mean - want[c]) < 4.0 * se + 1e-6 * want[c]);
            assert_true(se < 0.01 * want[c]); /* a test that can fail */
        }
    }
    lumis_sun_sampler_destroy(ss);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(res);
    lumis_envmap_destroy(env);
    free(px);
}

/* The irradiance on a plane of normal n under the map, by brute force: every pixel split into
 * 12 x 12 cells uniform in (u, cos theta), cos+ at each cell's centre. */
static void irradiance_brute(const float *px, int w, int h, float rot, const double n[3],
                             double E[3])
{
    E[0] = E[1] = E[2] = 0.0;
    const double cr = cos(rot * PI / 180.0), sr = sin(rot * PI / 180.0);
    enum { S = 12 };
    for (int j = 0; j < h; j++) {
        const double z0 = cos(PI * j / h), z1 = cos(PI * (j + 1) / h);
        const double cell = 2.0 * PI / w / S * (z0 - z1) / S;
        for (int i = 0; i < w; i++) {
            double sum = 0.0;
            for (int a = 0; a < S; a++)
                for (int b = 0; b < S; b++) {
                    const double u = (i + (a + 0.5) / S) / w, z = z0 + (z1 - z0) * (b + 0.5) / S;
                    const double s = sqrt(1.0 - z * z), ph = 2.0 * PI * u;
                    const double m[3] = {s * cos(ph), z, s * sin(ph)};
                    const double d[3] = {cr * m[0] - sr * m[2], m[1], sr * m[0] + cr * m[2]};
                    const double c = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
                    if (c > 0.0) sum += c * cell;
                }
            const float *p = px + 3 * ((size_t)j * w + i);
            for (int c = 0; c < 3; c++) E[c] += p[c] * sum;
        }
    }
}

/* The renderer's estimator, written here: the sun (cone) and the residual (its sampler) are
 * each combined with a cosine-distributed sample by the balance heuristic. */
static void irradiance_matches_brute_force(void **state)
{
    (void)state;
    lumis_sun f;
    lumis_envmap *res = NULL;
    float *px = NULL;
    const int w = 181, h = 91;
    lumis_envmap *env = sun_map(w, h, &f, &res, &px);
    lumis_sampler *smp = residual_sampler(res);
    lumis_sun_sampler *ss = NULL;
    assert_int_equal(lumis_sun_sampler_create(env, &f, NULL, &ss), LUMIS_OK);
    const double normals[][3] = {{0, 1, 0}, {-0.6, 0.3, -0.74}, {0.8, -0.5, 0.33}};
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 5, 9);
    for (int q = 0; q < 6; q++) { /* three normals, by the cone then by the sun's pixels */
        const int by_pixels = q >= 3;
        double n[3] = {normals[q % 3][0], normals[q % 3][1], normals[q % 3][2]}, t[3], b[3];
        const double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int k = 0; k < 3; k++) n[k] /= nn;
        test_frame(n, t, b);
        double want[3];
        irradiance_brute(px, w, h, 23.0f, n, want);
        const int N = 200000;
        double s1[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
        for (int k = 0; k < N; k++) {
            double x[3] = {0, 0, 0};
            /* sun sample */
            double ps = 0.0;
            const double a1 = lumis_pcg32_double(&rng), a2 = lumis_pcg32_double(&rng);
            lumis_vec3 v = by_pixels ? lumis_sun_sampler_sample(ss, a1, a2, &ps, NULL)
                                     : lumis_sun_sample(&f, a1, a2, &ps);
            double c = n[0] * v.x + n[1] * v.y + n[2] * v.z;
            if (c > 0.0) {
                const lumis_rgb L = lumis_sun_eval(&f, env, v);
                const double wgt = ps / (ps + c / PI) * c / ps;
                x[0] += L.r * wgt, x[1] += L.g * wgt, x[2] += L.b * wgt;
            }
            /* residual sample */
            const lumis_env_sample e =
                lumis_sampler_sample(smp, lumis_pcg32_double(&rng), lumis_pcg32_double(&rng));
            c = n[0] * e.dir.x + n[1] * e.dir.y + n[2] * e.dir.z;
            if (c > 0.0) {
                const double wgt = e.pdf / (e.pdf + c / PI) * c / e.pdf;
                x[0] += e.radiance.r * wgt, x[1] += e.radiance.g * wgt, x[2] += e.radiance.b * wgt;
            }
            /* a cosine sample, weighed against each light */
            const double r1 = lumis_pcg32_double(&rng), r2 = lumis_pcg32_double(&rng);
            const double sr = sqrt(r1), ph = 2.0 * PI * r2, ct = sqrt(1.0 - r1);
            for (int k2 = 0; k2 < 3; k2++)
                (&v.x)[k2] = (float)(sr * (cos(ph) * t[k2] + sin(ph) * b[k2]) + ct * n[k2]);
            c = n[0] * v.x + n[1] * v.y + n[2] * v.z;
            if (c > 0.0) {
                const double pb = c / PI;
                const lumis_rgb Ls = lumis_sun_eval(&f, env, v);
                lumis_rgb Lr;
                const double pr = lumis_sampler_pdf_radiance(smp, v, &Lr);
                const double psun =
                    by_pixels ? lumis_sun_sampler_pdf(ss, v, NULL) : lumis_sun_pdf(&f, v);
                const double wsun = pb / (pb + psun) * c / pb, wres = pb / (pb + pr) * c / pb;
                x[0] += Ls.r * wsun + Lr.r * wres;
                x[1] += Ls.g * wsun + Lr.g * wres;
                x[2] += Ls.b * wsun + Lr.b * wres;
            }
            for (int k2 = 0; k2 < 3; k2++) {
                s1[k2] += x[k2];
                s2[k2] += x[k2] * x[k2];
            }
        }
        for (int k2 = 0; k2 < 3; k2++) {
            const double mean = s1[k2] / N, se = sqrt((s2[k2] / N - mean * mean) / N);
            /* the sub-pixel reference is good to ~1e-4 */
            assert_true(fabs(mean - want[k2]) < 4.0 * se + 3e-4 * want[k2]);
            assert_true(se < 0.01 * want[k2]);
        }
    }
    lumis_sun_sampler_destroy(ss);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(res);
    lumis_envmap_destroy(env);
    free(px);
}

/* The sun sampler: every draw lands in a sun pixel, in proportion to its Y Omega (chi-square
 * over the pixels, the expected counts from the test's own luminance sums), the pdf is Y /
 * sum(Y Omega) there and 0 off the sun, and sums to 1 over the map's pixels. */
static void sun_pixels_by_power(void **state)
{
    (void)state;
    const int w = 421, h = 211;
    /* a sun whose pixels differ: a bright core in a dimmer aureole */
    float *px = malloc(sizeof(float) * 3 * (size_t)w * (size_t)h);
    assert_non_null(px);
    double s0[3], sumY = 0.0;
    dir_uv(0.3, 0.35, s0);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            double c[3];
            dir_uv((i + 0.5) / w, (j + 0.5) / h, c);
            const double a = ang(c, s0) * 180.0 / PI;
            float *p = px + 3 * ((size_t)j * w + i);
            const float k = a < 1.0 ? 5.0e4f : a < 4.0 ? (float)(2.0e3 / (a * a)) : 0.0f;
            p[0] = 0.2f + k;
            p[1] = 0.3f + 0.7f * k;
            p[2] = 0.4f + 0.4f * k * (float)(i % 3 + 1);
        }
    lumis_envmap *env = env_of(px, w, h, 0.0f, 0.0f);
    lumis_sun f;
    assert_int_equal(lumis_sun_find(env, NULL, &f, NULL), LUMIS_OK);
    assert_int_equal(f.found, 1);
    lumis_sun_sampler *ss = NULL;
    assert_int_equal(lumis_sun_sampler_create(env, &f, NULL, &ss), LUMIS_OK);
    /* the expected probabilities, from the pixels */
    double *prob = calloc((size_t)w * (size_t)h, sizeof *prob),
           *count = calloc((size_t)w * (size_t)h, sizeof *count);
    assert_non_null(prob);
    assert_non_null(count);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            if (!lumis_sun_contains(&f, env, i, j)) continue;
            const float *p = px + 3 * ((size_t)j * w + i);
            const double y = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            prob[(size_t)j * w + i] = y * solid(w, h, j);
            sumY += y * solid(w, h, j);
        }
    double total = 0.0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            prob[(size_t)j * w + i] /= sumY;
            const lumis_vec3 c =
                lumis_envmap_uv_to_dir(env, ((float)i + 0.5f) / w, ((float)j + 0.5f) / h);
            const double pdf = lumis_sun_sampler_pdf(ss, c, NULL);
            assert_true(fabs(pdf * solid(w, h, j) - prob[(size_t)j * w + i]) <=
                        1e-5 * prob[(size_t)j * w + i]);
            total += pdf * solid(w, h, j);
        }
    assert_true(fabs(total - 1.0) < 1e-9);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 17, 3);
    const int N = 300000;
    for (int k = 0; k < N; k++) {
        double p = 0.0;
        const lumis_vec3 v = lumis_sun_sampler_sample(ss, lumis_pcg32_double(&rng),
                                                      lumis_pcg32_double(&rng), &p, NULL);
        double d[3] = {v.x, v.y, v.z}, uu, vv;
        /* the pixel by the test's own formula */
        vv = acos(d[1] / sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])) / PI;
        uu = atan2(d[2], d[0]) / (2.0 * PI);
        if (uu < 0.0) uu += 1.0;
        const int i = (int)(uu * w) % w, j = (int)(vv * h) < h ? (int)(vv * h) : h - 1;
        assert_true(prob[(size_t)j * w + i] > 0.0);
        assert_true(lumis_sun_sampler_pdf(ss, v, NULL) == p);
        count[(size_t)j * w + i] += 1.0;
    }
    /* chi-square over the pixels expecting 5 or more draws, the rest pooled */
    double chi2 = 0.0, pooled_o = 0.0, pooled_e = 0.0;
    int bins = 0;
    for (size_t q = 0; q < (size_t)w * (size_t)h; q++) {
        const double e = prob[q] * N;
        if (e <= 0.0) continue;
        if (e < 5.0) {
            pooled_o += count[q];
            pooled_e += e;
            continue;
        }
        chi2 += (count[q] - e) * (count[q] - e) / e;
        bins++;
    }
    if (pooled_e > 0.0) {
        chi2 += (pooled_o - pooled_e) * (pooled_o - pooled_e) / pooled_e;
        bins++;
    }
    assert_true(bins > 20);
    assert_true(chi2 < (bins - 1) + 4.5 * sqrt(2.0 * (bins - 1)));
    /* off the sun: nothing */
    lumis_vec3 away = {(float)-s0[0], (float)-s0[1], (float)-s0[2]};
    lumis_rgb L;
    assert_true(lumis_sun_sampler_pdf(ss, away, &L) == 0.0 && L.r == 0.0f);
    lumis_sun none = {0};
    lumis_sun_sampler *bad = (lumis_sun_sampler *)1;
    assert_int_equal(lumis_sun_sampler_create(env, &none, NULL, &bad), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(bad);
    lumis_sun_sampler_destroy(ss);
    free(prob);
    free(count);
    lumis_envmap_destroy(env);
    free(px);
}

static float uniform_px(int i, int j, int c)
{
    (void)i, (void)j;
    return 0.5f + 0.1f * (float)c;
}

static float black_px(int i, int j, int c)
{
    (void)i, (void)j, (void)c;
    return 0.0f;
}

static float nan_px(int i, int j, int c)
{
    (void)c;
    return (i + j) % 2 ? NAN : 0.0f;
}

/* One very bright pixel in an 8 x 4 map: a pixel spans 45 degrees, no sun. */
static float coarse_px(int i, int j, int c)
{
    (void)c;
    return i == 3 && j == 1 ? 1e6f : 1.0f;
}

static void expect_none(lumis_envmap *env)
{
    lumis_sun f;
    lumis_envmap *res = (lumis_envmap *)1;
    assert_int_equal(lumis_sun_find(env, NULL, &f, &res), LUMIS_OK);
    assert_int_equal(f.found, 0);
    assert_null(res);
    assert_true(f.radius == 0.0 && f.sample_radius == 0.0 && f.power[0] == 0.0);
    /* a sun not found lights nothing and samples nothing */
    lumis_vec3 up = {0.0f, 1.0f, 0.0f};
    lumis_rgb L = lumis_sun_eval(&f, env, up);
    assert_true(L.r == 0.0f && L.g == 0.0f && L.b == 0.0f);
    assert_true(lumis_sun_pdf(&f, up) == 0.0);
    double p = 1.0, u[2];
    lumis_sun_sample(&f, 0.5, 0.5, &p);
    assert_true(p == 0.0);
    assert_int_equal(lumis_sun_invert(&f, up, u), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_envmap_destroy(env);
}

static void no_sun_where_there_is_none(void **state)
{
    (void)state;
    expect_none(tu_envmap(64, 32, uniform_px, 0.0f, 0.0f));
    expect_none(tu_envmap(33, 17, black_px, 0.0f, 0.0f));
    expect_none(tu_envmap(33, 17, nan_px, 0.0f, 0.0f));
    expect_none(tu_envmap(1, 1, uniform_px, 0.0f, 0.0f));
    expect_none(tu_envmap(8, 4, coarse_px, 0.0f, 0.0f));
    lumis_sky_desc sd = {0};
    sd.width = 512;
    sd.no_sun = 1;
    lumis_image *img = NULL;
    assert_int_equal(lumis_sky_create(&sd, &img), LUMIS_OK);
    expect_none(tu_envmap_of(img, 0.0f, 0.0f));
    lumis_image_destroy(img);
    img = NULL;
    if (lumis_image_read(LUMIS_DATA_DIR "/hdri/pmndrs-venice.exr", NULL, &img, NULL) == LUMIS_OK) {
        expect_none(tu_envmap_of(img, 0.0f, 0.0f));
        lumis_image_destroy(img);
    }
    /* blender-sunrise: the sun of data/README.md (61 % in 0.1 % of the pixels) */
    if (lumis_image_read(LUMIS_DATA_DIR "/hdri/blender-sunrise.exr", NULL, &img, NULL) ==
        LUMIS_OK) {
        lumis_envmap *env = tu_envmap_of(img, 0.0f, 0.0f);
        lumis_sun f;
        assert_int_equal(lumis_sun_find(env, NULL, &f, NULL), LUMIS_OK);
        assert_int_equal(f.found, 1);
        assert_true(f.share > 0.5 && f.radius < 3.0 * PI / 180.0);
        lumis_envmap_destroy(env);
        lumis_image_destroy(img);
    }
}

static void find_refuses_bad_arguments(void **state)
{
    (void)state;
    lumis_envmap *env = tu_envmap(16, 8, uniform_px, 0.0f, 0.0f);
    lumis_sun f;
    tu_sink s;
    tu_sink_init(&s);
    assert_int_equal(lumis_sun_find(NULL, NULL, &f, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_sun_find(env, NULL, NULL, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_sun_desc d = {0};
    d.errors = s.sink;
    d.max_radius_deg = 30.0;
    assert_int_equal(lumis_sun_find(env, &d, &f, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(s.last, "max_radius_deg 30"));
    d.max_radius_deg = -1.0;
    assert_int_equal(lumis_sun_find(env, &d, &f, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(s.last, "max_radius_deg -1"));
    d.max_radius_deg = 0.0;
    d.min_share = 2.0;
    assert_int_equal(lumis_sun_find(env, &d, &f, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(s.last, "min_share 2"));
    d.min_share = -0.5;
    assert_int_equal(lumis_sun_find(env, &d, &f, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(s.last, "min_share -0.5"));
    d.min_share = 0.0;
    d.threshold = 1.0;
    assert_int_equal(lumis_sun_find(env, &d, &f, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(s.last, "threshold 1"));
    d.threshold = NAN;
    assert_int_equal(lumis_sun_find(env, &d, &f, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_envmap_destroy(env);
}

/* The sun's functions given what no find returns (no sun, a cone of no or too wide an angle,
 * an axis not finite or zero), no map, pixels off the map, directions zero or not finite, and
 * numbers outside [0, 1): nothing, never a crash, and failures said. */
static void sun_functions_refuse_bad_input(void **state)
{
    (void)state;
    const int w = 301, h = 151;
    const float sun[3] = {3.0e4f, 3.0e4f, 3.0e4f};
    double pw[3];
    float *px = disk_map(w, h, 60.0 * PI / 180.0, 200.0 * PI / 180.0, 2.0, sun, pw);
    lumis_envmap *env = env_of(px, w, h, 0.0f, 1.0f);
    lumis_sun f;
    assert_int_equal(lumis_sun_find(env, NULL, &f, NULL), LUMIS_OK);
    assert_int_equal(f.found, 1);
    int si = -1, sj = -1; /* a pixel of the sun */
    for (int j = 0; j < h && si < 0; j++)
        for (int i = 0; i < w && si < 0; i++)
            if (lumis_sun_contains(&f, env, i, j)) si = i, sj = j;
    assert_true(si >= 0);
    const lumis_vec3 at = f.dir, zero = {0.0f, 0.0f, 0.0f};
    tu_sink sink;
    tu_sink_init(&sink);
    /* suns no find returns */
    lumis_sun bad[9];
    for (int k = 0; k < 9; k++) bad[k] = f;
    bad[0].found = 0;
    bad[1].sample_radius = 0.0;
    bad[2].sample_radius = 4.0;
    bad[3].sample_radius = NAN;
    bad[4].dir.x = NAN;
    bad[5].dir.y = INFINITY;
    bad[6].dir.z = NAN;
    bad[7].dir = zero;
    for (int k = 0; k < 9; k++) {
        const lumis_sun *b = k < 8 ? &bad[k] : NULL; /* and no sun at all */
        assert_int_equal(lumis_sun_contains(b, env, si, sj), 0);
        const lumis_rgb e = lumis_sun_eval(b, env, at);
        assert_true(e.r == 0.0f && e.g == 0.0f && e.b == 0.0f);
        assert_true(lumis_sun_pdf(b, at) == 0.0);
        double pdf = 1.0, u[2];
        const lumis_vec3 d = lumis_sun_sample(b, 0.5, 0.5, &pdf);
        assert_true(d.x == 0.0f && d.y == 0.0f && d.z == 0.0f && pdf == 0.0);
        assert_int_equal(lumis_sun_invert(b, at, u), LUMIS_ERR_INVALID_ARGUMENT);
        lumis_sun_sampler *ss = (lumis_sun_sampler *)&sink;
        assert_int_equal(lumis_sun_sampler_create(env, b, &sink.sink, &ss),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_null(ss);
        assert_non_null(strstr(sink.last, "needs a map, a sun found in it"));
    }
    /* the sun, with no map, pixels off the map, directions zero or not finite */
    assert_int_equal(lumis_sun_contains(&f, env, si, sj), 1);
    assert_int_equal(lumis_sun_contains(&f, NULL, si, sj), 0);
    const int off[4][2] = {{-1, sj}, {si, -1}, {w, sj}, {si, h}};
    for (int k = 0; k < 4; k++)
        assert_int_equal(lumis_sun_contains(&f, env, off[k][0], off[k][1]), 0);
    const lumis_vec3 odd[] = {zero, {NAN, 0.0f, 1.0f}, {0.0f, INFINITY, 0.0f}, {0.0f, 0.0f, NAN}};
    for (int k = 0; k < 4; k++) {
        const lumis_rgb e = lumis_sun_eval(&f, env, odd[k]);
        assert_true(e.r == 0.0f && e.g == 0.0f && e.b == 0.0f);
        double u[2];
        assert_int_equal(lumis_sun_invert(&f, odd[k], u), LUMIS_ERR_INVALID_ARGUMENT);
        lumis_rgb L = {1.0f, 1.0f, 1.0f};
        assert_true(lumis_sun_sampler_pdf(NULL, at, &L) == 0.0);
        assert_true(L.r == 0.0f && L.g == 0.0f && L.b == 0.0f);
    }
    const lumis_rgb e = lumis_sun_eval(&f, NULL, at);
    assert_true(e.r == 0.0f && e.g == 0.0f && e.b == 0.0f);
    assert_true(lumis_sun_pdf(&f, zero) == 0.0);
    /* on the axes, away from the sun: no density */
    const lumis_vec3 ax[] = {{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}};
    for (int k = 0; k < 3; k++) assert_true(lumis_sun_pdf(&f, ax[k]) == 0.0);
    assert_true(lumis_sun_pdf(&f, at) > 0.0);
    double u[2];
    assert_int_equal(lumis_sun_invert(&f, at, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    const lumis_vec3 away = {-at.x, -at.y, -at.z};
    assert_int_equal(lumis_sun_invert(&f, away, u), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_sun_invert(&f, at, u), LUMIS_OK);
    /* numbers outside [0, 1) are clamped into it: a direction in the cone, of the cone's pdf */
    const double us[][2] = {{-1.0, 0.5}, {2.0, 0.5}, {0.5, -3.0}, {0.5, 1.0}, {NAN, NAN}};
    for (int k = 0; k < 5; k++) {
        double pdf = 0.0;
        const lumis_vec3 d = lumis_sun_sample(&f, us[k][0], us[k][1], &pdf);
        const double dd[3] = {d.x, d.y, d.z}, a[3] = {at.x, at.y, at.z};
        assert_true(ang(dd, a) <= f.sample_radius);
        assert_true(pdf > 0.0 && pdf == lumis_sun_pdf(&f, d));
        assert_true(lumis_sun_sample(&f, us[k][0], us[k][1], NULL).x == d.x);
    }
    /* the sampler: no map, no output, a map whose sun pixels are black */
    lumis_sun_sampler *ss = NULL;
    assert_int_equal(lumis_sun_sampler_create(NULL, &f, NULL, &ss), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(ss);
    assert_int_equal(lumis_sun_sampler_create(env, &f, NULL, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    float *dark = calloc(3 * (size_t)w * (size_t)h, sizeof *dark);
    assert_non_null(dark);
    lumis_envmap *black = env_of(dark, w, h, 0.0f, 1.0f);
    assert_int_equal(lumis_sun_sampler_create(black, &f, &sink.sink, &ss),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(ss);
    assert_non_null(strstr(sink.last, "the sun's pixels hold no light"));
    lumis_envmap_destroy(black);
    free(dark);
    assert_int_equal(lumis_sun_sampler_create(env, &f, NULL, &ss), LUMIS_OK);
    for (int k = 0; k < 4; k++) {
        lumis_rgb L = {1.0f, 1.0f, 1.0f};
        assert_true(lumis_sun_sampler_pdf(ss, odd[k], &L) == 0.0);
        assert_true(L.r == 0.0f && L.g == 0.0f && L.b == 0.0f);
    }
    for (int k = 0; k < 5; k++) {
        double pdf = 0.0;
        lumis_rgb L;
        const lumis_vec3 d = lumis_sun_sampler_sample(ss, us[k][0], us[k][1], &pdf, &L);
        assert_true(pdf > 0.0 && pdf == lumis_sun_sampler_pdf(ss, d, NULL));
        assert_true(L.r == sun[0]);
        assert_true(lumis_sun_sampler_sample(ss, us[k][0], us[k][1], NULL, NULL).y == d.y);
    }
    double pdf = 1.0;
    lumis_rgb L = {1.0f, 1.0f, 1.0f};
    const lumis_vec3 d = lumis_sun_sampler_sample(NULL, 0.5, 0.5, &pdf, &L);
    assert_true(d.x == 0.0f && d.y == 0.0f && d.z == 0.0f && pdf == 0.0 && L.g == 0.0f);
    lumis_sun_sampler_destroy(ss);
    lumis_sun_sampler_destroy(NULL);
    lumis_envmap_destroy(env);
    free(px);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(synthetic_disk_is_recovered),
        cmocka_unit_test(suns_at_the_poles_are_recovered),
        cmocka_unit_test(sky_sun_is_recovered),
        cmocka_unit_test(split_is_exact),
        cmocka_unit_test(cone_chi_square),
        cmocka_unit_test(cone_pdf_integrates_to_one),
        cmocka_unit_test(power_is_unbiased),
        cmocka_unit_test(irradiance_matches_brute_force),
        cmocka_unit_test(sun_pixels_by_power),
        cmocka_unit_test(no_sun_where_there_is_none),
        cmocka_unit_test(find_refuses_bad_arguments),
        cmocka_unit_test(sun_functions_refuse_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
