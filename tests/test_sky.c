/* Procedural maps: the Preetham clear sky with its sun, and the studio. */
/* Oracles:
 * lumis_sky_create — closed form: the sun's power recomputed from docs/sky.md at any resolution,
 *     Preetham's zenith luminance, a sun cut by the horizon's chord, the ground's reflection;
 *     invariance: mirror about the sun's plane (sun_power_is_exact_at_any_resolution,
 *     zenith_matches_preetham_and_sky_is_symmetric, sun_partly_below_the_horizon,
 *     ground_reflects_what_falls_on_it)
 * lumis_studio_create — hand-worked: pixels inside the key light at one pixel per degree;
 *     invariance: power independent of resolution (studio_pixels_by_hand,
 *     studio_power_is_resolution_independent)
 * lumis_equirect_solid_angle — indirect: the power sums of every sky test, checked against closed
 *     forms (sun_power_is_exact_at_any_resolution)
 */
#include "testutil.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static lumis_image *sky(int w, int h, float elev, float az, float T, float albedo, int no_sun)
{
    lumis_sky_desc d = {0};
    d.width = w;
    d.height = h;
    d.sun_elevation_deg = elev;
    d.sun_at_horizon = elev == 0.0f; /* 0 alone means the default, 35 degrees */
    d.sun_azimuth_deg = az;
    d.turbidity = T;
    d.ground_albedo = albedo;
    d.no_sun = no_sun;
    lumis_image *img = NULL;
    assert_int_equal(lumis_sky_create(&d, &img), LUMIS_OK);
    assert_int_equal(img->width, w);
    assert_int_equal(img->height, h);
    return img;
}

static void power_rgb(const lumis_image *img, double p[3])
{
    p[0] = p[1] = p[2] = 0.0;
    for (int j = 0; j < img->height; j++) {
        double om = lumis_equirect_solid_angle(img->width, img->height, j);
        for (int i = 0; i < img->width; i++)
            for (int c = 0; c < 3; c++)
                p[c] += img->pixels[3 * ((size_t)j * img->width + i) + c] * om;
    }
}

/* The sun of docs/sky.md, computed here independently of src/envmap/sky.c. */
static void expected_sun_power(double elev_deg, double T, double out[3])
{
    const double zen = 90.0 - elev_deg, zr = zen * PI / 180;
    const double m = 1.0 / (cos(zr) + 0.15 * pow(93.885 - zen, -1.253));
    const double lambda[3] = {0.65, 0.55, 0.45};
    for (int c = 0; c < 3; c++) {
        double tau = exp(-m * (0.008735 * pow(lambda[c], -4.08) +
                               (0.04608 * T - 0.04586) * pow(lambda[c], -1.3)));
        out[c] = 128.0 * tau; /* (128 klx / omega) * tau * omega */
    }
}

static void sun_power_is_exact_at_any_resolution(void **state)
{
    (void)state;
    static const int sizes[][2] = {{8, 4}, {33, 17}, {256, 128}, {1024, 512}, {2048, 1024}};
    static const float elevs[] = {35.0f, 3.0f, 89.9f};
    for (int e = 0; e < 3; e++) {
        double want[3];
        expected_sun_power(elevs[e], 2.5, want);
        for (int s = 0; s < 5; s++) {
            lumis_image *a = sky(sizes[s][0], sizes[s][1], elevs[e], 40.0f, 0.0f, -1.0f, 0);
            lumis_image *b = sky(sizes[s][0], sizes[s][1], elevs[e], 40.0f, 0.0f, -1.0f, 1);
            double pa[3], pb[3];
            power_rgb(a, pa);
            power_rgb(b, pb);
            for (int c = 0; c < 3; c++)
                assert_true(fabs((pa[c] - pb[c]) - want[c]) < 2e-5 * want[c]);
            lumis_image_destroy(a);
            lumis_image_destroy(b);
        }
    }
    /* On the horizon half the disk is hidden by the ground. */
    double want[3], pa[3], pb[3];
    expected_sun_power(0.0, 2.5, want);
    lumis_image *a = sky(512, 256, 0.0f, 0.0f, 0.0f, -1.0f, 0);
    lumis_image *b = sky(512, 256, 0.0f, 0.0f, 0.0f, -1.0f, 1);
    power_rgb(a, pa);
    power_rgb(b, pb);
    assert_true(fabs((pa[1] - pb[1]) - 0.5 * want[1]) < 1e-4 * want[1]);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
}

static void sun_is_where_it_was_asked_and_holds_most_power(void **state)
{
    (void)state;
    lumis_image *img = sky(1024, 512, 35.0f, 60.0f, 0.0f, 0.0f, 0);
    size_t best = 0;
    for (size_t k = 1; k < (size_t)1024 * 512; k++)
        if (img->pixels[3 * k + 1] > img->pixels[3 * best + 1]) best = k;
    /* Elevation 35 -> v = 55/180; azimuth 60 -> u = 1/6. */
    assert_int_equal((int)(best / 1024), (int)(55.0 / 180.0 * 512));
    assert_int_equal((int)(best % 1024), (int)(1024.0 / 6.0));
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    lumis_envmap_stats s;
    assert_int_equal(lumis_envmap_stats_compute(env, &s), LUMIS_OK);
    assert_true(s.top01_share > 0.5); /* as in real sun maps */
    assert_true(s.max_luminance > 1e5 * s.min_positive_luminance);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

static double lum(const float *p)
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

static void zenith_matches_preetham_and_sky_is_symmetric(void **state)
{
    (void)state;
    const double T = 4.0, elev = 50.0, ts = (90.0 - elev) * PI / 180;
    lumis_image *img = sky(720, 360, (float)elev, 90.0f, (float)T, 0.0f, 1);
    /* Preetham's zenith luminance, kcd/m^2. */
    double chi = (4.0 / 9.0 - T / 120.0) * (PI - 2 * ts);
    double Yz = (4.0453 * T - 4.9710) * tan(chi) - 0.2155 * T + 2.4192;
    double top = 0.0;
    for (int i = 0; i < 720; i++) top += lum(img->pixels + 3 * i);
    assert_true(fabs(top / 720 - Yz) < 0.01 * Yz);
    /* Mirror symmetry about the sun's vertical plane (azimuth 90 = column 180). */
    for (int j = 0; j < 180; j += 7)
        for (int d = 1; d < 180; d += 13) {
            const float *a = img->pixels + 3 * (j * 720 + 180 + d);
            const float *b = img->pixels + 3 * (j * 720 + 180 - 1 - d + 0);
            /* Column 180+d has centre at 180+d+0.5, its mirror is 179-d+0.5. */
            for (int c = 0; c < 3; c++) assert_true(fabsf(a[c] - b[c]) <= 1e-5f * a[c] + 1e-6f);
        }
    lumis_image_destroy(img);
}

static void ground_reflects_what_falls_on_it(void **state)
{
    (void)state;
    const int w = 400, h = 200;
    const double albedo = 0.3;
    lumis_image *img = sky(w, h, 25.0f, 0.0f, 3.0f, (float)albedo, 0);
    /* Horizontal irradiance: every upper-hemisphere pixel, cosine-weighted at its centre
     * (the sun included: its pixels are part of the map). */
    double E = 0.0;
    for (int j = 0; j < h / 2; j++) {
        double ct = cos(PI * (j + 0.5) / h), om = lumis_equirect_solid_angle(w, h, j);
        for (int i = 0; i < w; i++) E += img->pixels[3 * (j * w + i) + 1] * ct * om;
    }
    double g = img->pixels[3 * ((h - 1) * w) + 1];
    /* Pixel centres vs. the true cosine inside the sun's few pixels: 0.5 % slack. */
    assert_true(fabs(g - albedo * E / PI) < 5e-3 * g);
    for (int j = h / 2; j < h; j++)
        for (int i = 0; i < w; i += 37) assert_true(img->pixels[3 * (j * w + i) + 1] == (float)g);
    lumis_image_destroy(img);
}

static void sky_is_deterministic_and_finite_at_odd_sizes(void **state)
{
    (void)state;
    static const int sizes[][2] = {{1, 1}, {3, 1}, {5, 3}, {101, 51}};
    for (int s = 0; s < 4; s++) {
        lumis_image *a = sky(sizes[s][0], sizes[s][1], 10.0f, 200.0f, 7.0f, 0.0f, 0);
        lumis_image *b = sky(sizes[s][0], sizes[s][1], 10.0f, 200.0f, 7.0f, 0.0f, 0);
        size_t n = (size_t)sizes[s][0] * sizes[s][1] * 3;
        assert_memory_equal(a->pixels, b->pixels, n * sizeof(float));
        for (size_t k = 0; k < n; k++) assert_true(isfinite(a->pixels[k]) && a->pixels[k] >= 0.0f);
        lumis_image_destroy(a);
        lumis_image_destroy(b);
    }
    /* A zeroed descriptor is a valid 1024 x 512 sky. */
    lumis_image *img = NULL;
    assert_int_equal(lumis_sky_create(NULL, &img), LUMIS_OK);
    assert_int_equal(img->width, 1024);
    assert_int_equal(img->height, 512);
    lumis_image_destroy(img);
}

static void sky_rejects_parameters_outside_the_model(void **state)
{
    (void)state;
    tu_sink sink;
    tu_sink_init(&sink);
    const float bad[][3] = {{1.0f, 30, 0.1f}, {11.0f, 30, 0.1f}, {NAN, 30, 0.1f},
                            {3.0f, -1, 0.1f}, {3.0f, 91, 0.1f},  {3.0f, 30, 2.0f}};
    for (int k = 0; k < 6; k++) {
        lumis_sky_desc d = {0};
        d.width = 16;
        d.turbidity = bad[k][0];
        d.sun_elevation_deg = bad[k][1];
        d.ground_albedo = bad[k][2];
        d.errors = sink.sink;
        lumis_image *img = (lumis_image *)1;
        assert_int_equal(lumis_sky_create(&d, &img), LUMIS_ERR_INVALID_ARGUMENT);
        assert_null(img);
    }
    assert_int_equal(sink.count, 6);
    assert_non_null(strstr(sink.last, "albedo"));
    lumis_sky_desc d = {0};
    d.width = -5;
    lumis_image *img = NULL;
    assert_int_equal(lumis_sky_create(&d, &img), LUMIS_ERR_BAD_DIMENSIONS);
}

/* The elevation of the brightest pixel's row (the sun's), in degrees. */
static double brightest_elevation(const lumis_image *img)
{
    double best = -1.0;
    int row = 0;
    for (int j = 0; j < img->height; j++)
        for (int i = 0; i < img->width; i++) {
            const double y = lum(img->pixels + 3 * ((size_t)j * img->width + i));
            if (y > best) best = y, row = j;
        }
    return 90.0 - (row + 0.5) * 180.0 / img->height;
}

/* Zero means the documented default (DESIGN.md): a zero-initialised descriptor puts the sun
 * at 35 degrees, not on the horizon; the horizon is asked for by name, and asking for both
 * is an error. */
static void zero_descriptor_is_the_default_sky(void **state)
{
    (void)state;
    lumis_sky_desc d = {0};
    d.width = 360;
    lumis_image *img = NULL;
    assert_int_equal(lumis_sky_create(&d, &img), LUMIS_OK);
    const double e = brightest_elevation(img);
    if (!(fabs(e - LUMIS_SKY_DEFAULT_ELEVATION_DEG) <= 1.0)) fail_msg("sun at %g degrees", e);
    lumis_image_destroy(img);
    d.sun_at_horizon = 1;
    assert_int_equal(lumis_sky_create(&d, &img), LUMIS_OK);
    const double h = brightest_elevation(img);
    if (!(fabs(h) <= 1.0)) fail_msg("sun_at_horizon: sun at %g degrees", h);
    lumis_image_destroy(img);
    d.sun_elevation_deg = 20.0f;
    img = (lumis_image *)1;
    assert_int_equal(lumis_sky_create(&d, &img), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);
}

static void studio_power_is_resolution_independent(void **state)
{
    (void)state;
    static const int sizes[][2] = {{64, 32}, {333, 111}, {1024, 512}, {2048, 1024}};
    double p0[3] = {0, 0, 0};
    for (int s = 0; s < 4; s++) {
        lumis_studio_desc d = {0};
        d.width = sizes[s][0];
        d.height = sizes[s][1];
        lumis_image *img = NULL;
        assert_int_equal(lumis_studio_create(&d, &img), LUMIS_OK);
        double p[3];
        power_rgb(img, p);
        if (s == 0) memcpy(p0, p, sizeof p);
        for (int c = 0; c < 3; c++) assert_true(fabs(p[c] - p0[c]) < 1e-5 * p0[c]);
        lumis_image_destroy(img);
    }
    /* Bright boxes on a dark surround: the boxes dominate the power. */
    lumis_image *img = NULL;
    assert_int_equal(lumis_studio_create(NULL, &img), LUMIS_OK);
    float mx = 0.0f, mn = 1e30f;
    for (size_t k = 0; k < (size_t)1024 * 512 * 3; k++) {
        if (img->pixels[k] > mx) mx = img->pixels[k];
        if (img->pixels[k] < mn) mn = img->pixels[k];
    }
    assert_true(mn > 0.0f && mx > 1000.0f * mn);
    lumis_image_destroy(img);
    lumis_studio_desc d = {0};
    d.intensity = -1.0f;
    assert_int_equal(lumis_studio_create(&d, &img), LUMIS_ERR_INVALID_ARGUMENT);
}

/* A sun whose centre is h radii above the horizon shows the part of its disk above the
 * chord: 1 - (acos h - h sqrt(1 - h^2)) / pi of its power (0.838 at 0.15 degrees). */
static void sun_partly_below_the_horizon(void **state)
{
    (void)state;
    const double elev = 0.15, h = elev * PI / 180.0 / 0.004654;
    const double visible = 1.0 - (acos(h) - h * sqrt(1.0 - h * h)) / PI;
    double want[3], pa[3], pb[3];
    expected_sun_power(elev, 2.5, want);
    lumis_image *a = sky(512, 256, (float)elev, 0.0f, 0.0f, -1.0f, 0);
    lumis_image *b = sky(512, 256, (float)elev, 0.0f, 0.0f, -1.0f, 1);
    power_rgb(a, pa);
    power_rgb(b, pb);
    if (!(fabs((pa[1] - pb[1]) - visible * want[1]) < 1e-4 * want[1]))
        fail_msg("sun at %g degrees: power %.6g, want %.6g (%.4f of the disk)", elev, pa[1] - pb[1],
                 visible * want[1], visible);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
}

/* At an odd height the middle row straddles the horizon: its upper half is sky, seen at
 * the middle of that half (the very row of a map twice as high, at half weight), and its
 * lower half ground (half the ground's radiance). */
static void odd_heights_split_the_horizon_row(void **state)
{
    (void)state;
    const int w = 64;
    lumis_image *lit = sky(w, 33, 30.0f, 0.0f, 3.0f, 0.3f, 1);
    lumis_image *bare = sky(w, 33, 30.0f, 0.0f, 3.0f, -1.0f, 1); /* albedo 0: no ground */
    lumis_image *fine = sky(w, 66, 30.0f, 0.0f, 3.0f, -1.0f, 1);
    for (int i = 0; i < w; i++)
        for (int c = 0; c < 3; c++) {
            const float sky_half = bare->pixels[3 * (16 * w + i) + c];
            const float sky_fine = fine->pixels[3 * (32 * w + i) + c];
            if (!(fabsf(sky_half - 0.5f * sky_fine) <= 1e-5f * sky_fine))
                fail_msg("column %d: the horizon row's sky %g, want half of %g", i, sky_half,
                         sky_fine);
            const float ground_half = lit->pixels[3 * (16 * w + i) + c] - sky_half;
            const float ground = lit->pixels[3 * (32 * w + i) + c];
            if (!(fabsf(ground_half - 0.5f * ground) <= 1e-4f * ground))
                fail_msg("column %d: the horizon row's ground %g, want half of %g", i, ground_half,
                         ground);
        }
    lumis_image_destroy(lit);
    lumis_image_destroy(bare);
    lumis_image_destroy(fine);
}

/* Known pixels of the studio at one pixel per degree: inside the key light (azimuth 20..50,
 * elevation 15..45) the wall plus intensity x (40, 38, 35); the bottom row is floor, the
 * top row wall. */
static void studio_pixels_by_hand(void **state)
{
    (void)state;
    static const double wall[3] = {0.02, 0.02, 0.021}, floor_[3] = {0.035, 0.033, 0.03},
                        key[3] = {40.0, 38.0, 35.0};
    for (int k = 1; k <= 2; k++) {
        lumis_studio_desc d = {0};
        d.width = 360;
        d.height = 180;
        d.intensity = (float)k;
        lumis_image *img = NULL;
        assert_int_equal(lumis_studio_create(&d, &img), LUMIS_OK);
        const float *in_key = img->pixels + 3 * (60 * 360 + 30); /* elevation 29..30 */
        const float *top = img->pixels + 3 * 5, *bottom = img->pixels + 3 * (179 * 360 + 5);
        for (int c = 0; c < 3; c++) {
            const double want = wall[c] + k * key[c];
            if (!(fabs(in_key[c] - want) < 1e-5 * want))
                fail_msg("intensity %d: key light channel %d = %g, want %g", k, c, in_key[c], want);
            assert_true(fabs(top[c] - wall[c]) < 1e-7 && fabs(bottom[c] - floor_[c]) < 1e-7);
        }
        lumis_image_destroy(img);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sun_power_is_exact_at_any_resolution),
        cmocka_unit_test(sun_is_where_it_was_asked_and_holds_most_power),
        cmocka_unit_test(zenith_matches_preetham_and_sky_is_symmetric),
        cmocka_unit_test(ground_reflects_what_falls_on_it),
        cmocka_unit_test(sky_is_deterministic_and_finite_at_odd_sizes),
        cmocka_unit_test(sky_rejects_parameters_outside_the_model),
        cmocka_unit_test(studio_power_is_resolution_independent),
        cmocka_unit_test(zero_descriptor_is_the_default_sky),
        cmocka_unit_test(sun_partly_below_the_horizon),
        cmocka_unit_test(odd_heights_split_the_horizon_row),
        cmocka_unit_test(studio_pixels_by_hand),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
