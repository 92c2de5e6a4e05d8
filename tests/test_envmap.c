/* The environment-map model: coordinates, solid angles, lookups, power, statistics,
 * power-preserving resampling. */
/* Oracles:
 * lumis_equirect_to_dir — hand-worked: zenith, +x, +z, -x and the nadir at their documented u, v
 *     (directions_are_pinned)
 * lumis_equirect_from_dir — hand-worked: -z at u = 3/4; the nadir and u just below 1 stay in range
 *     (directions_are_pinned)
 * lumis_equirect_solid_angle — closed form: DESIGN.md's row formula at the pole; rows sum to 4 pi
 *     at 1 x 1 to 8192 x 4096 (solid_angles_cover_the_sphere)
 * lumis_envmap_create — hand-worked: a constant map's radiance and power; error paths: missing
 *     pixels, bad sizes, NaN and negative scale (power_is_radiance_times_solid_angle,
 *     invalid_descriptors_are_refused)
 * lumis_envmap_destroy — external: leaks seen by ASan and valgrind; NULL accepted
 *     (invalid_descriptors_are_refused)
 * lumis_envmap_uv_to_dir — hand-worked: directions on a map rotated by 30 degrees
 *   (rotated_coordinates_by_hand); round trip pixel -> direction -> pixel and uv at 7 sizes
 *     and 3 rotations (pixel_direction_pixel_round_trip)
 * lumis_envmap_dir_to_uv — hand-worked: (u, v) of two world directions on a rotated map
 *   (rotated_coordinates_by_hand); round trip with lumis_envmap_uv_to_dir
 *     (pixel_direction_pixel_round_trip)
 * lumis_envmap_dir_to_pixel — hand-worked: pixels of two world directions on a rotated map
 *   (rotated_coordinates_by_hand); round trip at pixel centres
 *     and corners (pixel_direction_pixel_round_trip)
 * lumis_envmap_eval — hand-worked: a rotation of +90° moves +x to +z; a constant map scaled by 3
 *     reads 6 (rotation_turns_the_map_about_y, power_is_radiance_times_solid_angle)
 * lumis_envmap_texel — hand-worked: pixel (i, j) with distinct channels times the scale, on a 12 x
 *     5 map (power_per_channel_and_texels)
 * lumis_envmap_rotation_deg — hand-worked: returns the 90° asked for
 *     (rotation_turns_the_map_about_y)
 * lumis_envmap_scale — hand-worked: returns the 3 asked for (power_is_radiance_times_solid_angle)
 * lumis_envmap_power — brute force: per-channel sum of radiance x solid angle written in the test;
 *     closed form: constant map 4 pi L (power_per_channel_and_texels,
 *     power_is_radiance_times_solid_angle)
 * lumis_envmap_replaced — hand-worked: one NaN, one inf, one negative counted; the caller's buffer
 *     unchanged (bad_pixels_are_replaced_and_counted)
 * lumis_envmap_stats_compute — brute force, hand-worked: top shares against a full sort; power per
 *     channel summed in the test; one hot pixel, a black map, 1 x 1 (top_shares_match_a_full_sort,
 *     power_per_channel_and_texels, stats_of_special_maps)
 * lumis_equirect_stats — indirect: the body of lumis_envmap_stats_compute
 *     (top_shares_match_a_full_sort)
 * lumis_equirect_resize — invariance: power preserved to 1e-5 at 6 sizes up and down; same size is
 *     the identity; a constant stays constant (resize_preserves_power)
 */
#include "testutil.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static float f_const(int i, int j, int c)
{
    (void)i, (void)j, (void)c;
    return 2.0f;
}
static float f_index(int i, int j, int c)
{
    return (float)(1 + i + 1000 * j + c * 100000);
}

static void directions_are_pinned(void **state)
{
    (void)state;
    /* y up; row 0 the zenith; u = 0 looks along +x, u = 1/4 along +z. */
    lumis_vec3 d = lumis_equirect_to_dir(0.0f, 0.0f);
    assert_true(fabsf(d.y - 1.0f) < 1e-6f);
    d = lumis_equirect_to_dir(0.0f, 0.5f);
    assert_true(fabsf(d.x - 1.0f) < 1e-6f && fabsf(d.y) < 1e-6f && fabsf(d.z) < 1e-6f);
    d = lumis_equirect_to_dir(0.25f, 0.5f);
    assert_true(fabsf(d.z - 1.0f) < 1e-6f);
    d = lumis_equirect_to_dir(0.5f, 0.5f);
    assert_true(fabsf(d.x + 1.0f) < 1e-6f);
    d = lumis_equirect_to_dir(0.3f, 1.0f);
    assert_true(fabsf(d.y + 1.0f) < 1e-6f);
    float u, v;
    lumis_equirect_from_dir((lumis_vec3){0, 0, -1}, &u, &v);
    assert_true(fabsf(u - 0.75f) < 1e-6f && fabsf(v - 0.5f) < 1e-6f);
    lumis_equirect_from_dir((lumis_vec3){0, -3, 0}, &u, &v); /* unnormalized, nadir */
    assert_true(u >= 0.0f && u < 1.0f && v < 1.0f && v > 0.9999f);
    lumis_equirect_from_dir((lumis_vec3){1, 0, -1e-30f}, &u, &v); /* just below u = 1 */
    assert_true(u >= 0.0f && u < 1.0f);
}

static void pixel_direction_pixel_round_trip(void **state)
{
    (void)state;
    static const int sizes[][2] = {{1, 1}, {3, 1}, {1, 3}, {3, 2}, {7, 5}, {64, 32}, {512, 256}};
    static const float rotations[] = {0.0f, 37.0f, -400.0f};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++)
        for (size_t r = 0; r < 3; r++) {
            int w = sizes[s][0], h = sizes[s][1];
            lumis_image *img = tu_image(w, h, f_index);
            lumis_envmap *env = tu_envmap_of(img, rotations[r], 0.0f);
            for (int j = 0; j < h; j++)
                for (int i = 0; i < w; i++) {
                    /* Centre and points near the corners of the pixel. */
                    static const float off[][2] = {{0.5f, 0.5f}, {0.01f, 0.01f}, {0.99f, 0.99f}};
                    for (int k = 0; k < 3; k++) {
                        float u = ((float)i + off[k][0]) / (float)w;
                        float v = ((float)j + off[k][1]) / (float)h;
                        lumis_vec3 d = lumis_envmap_uv_to_dir(env, u, v);
                        int ii, jj;
                        lumis_envmap_dir_to_pixel(env, d, &ii, &jj);
                        /* At the poles every column is the same point. */
                        if (j == 0 && k == 1 && h == 1) continue;
                        assert_int_equal(jj, j);
                        if (fabs(d.y) < 0.9999) assert_int_equal(ii, i);
                        float uu, vv;
                        lumis_envmap_dir_to_uv(env, d, &uu, &vv);
                        if (fabs(d.y) < 0.9999) {
                            double du = fabs(uu - u);
                            assert_true(fmin(du, 1.0 - du) < 2e-6 && fabsf(vv - v) < 2e-6f);
                        }
                        lumis_rgb c = lumis_envmap_eval(env, d);
                        lumis_rgb t = lumis_envmap_texel(env, ii, jj);
                        assert_true(c.r == t.r && c.g == t.g && c.b == t.b);
                    }
                }
            lumis_envmap_destroy(env);
            lumis_image_destroy(img);
        }
}

static void rotation_turns_the_map_about_y(void **state)
{
    (void)state;
    lumis_image *img = tu_image(36, 18, f_index);
    lumis_envmap *plain = tu_envmap_of(img, 0.0f, 0.0f), *rot = tu_envmap_of(img, 90.0f, 0.0f);
    /* Rotating the map by +90 degrees moves what was at +x to +z. */
    lumis_vec3 px = {1, 0.2f, 0}, pz = {0, 0.2f, 1};
    lumis_rgb a = lumis_envmap_eval(plain, px), b = lumis_envmap_eval(rot, pz);
    assert_true(a.r == b.r && a.g == b.g);
    assert_true(lumis_envmap_rotation_deg(rot) == 90.0f);
    lumis_envmap_destroy(plain);
    lumis_envmap_destroy(rot);
    lumis_image_destroy(img);
}

/* Hand-worked: the map's coordinates of world directions on a rotated map, from
 * docs/coordinates.md's formulas worked by hand (phi = 2 pi u + rotation, theta = pi v),
 * not from lumis's own inverse.  A mirrored azimuth, a rotation of the wrong sign or a
 * half-pixel offset each moves one of these. */
static void rotated_coordinates_by_hand(void **state)
{
    (void)state;
    lumis_image *img = tu_image(36, 18, f_index);
    lumis_envmap *rot = tu_envmap_of(img, 30.0f, 0.0f);
    /* u = 0.25, v = 0.5: azimuth 90 + 30 = 120 degrees on the horizon, (cos 120, 0, sin 120) */
    lumis_vec3 d = lumis_envmap_uv_to_dir(rot, 0.25f, 0.5f);
    assert_true(fabsf(d.x + 0.5f) < 1e-6f && fabsf(d.y) < 1e-6f && fabsf(d.z - 0.8660254f) < 1e-6f);
    /* u = 0.5, v = 1/3: azimuth 210, polar 60: (sin 60 cos 210, cos 60, sin 60 sin 210) */
    d = lumis_envmap_uv_to_dir(rot, 0.5f, 1.0f / 3.0f);
    assert_true(fabsf(d.x + 0.75f) < 1e-6f && fabsf(d.y - 0.5f) < 1e-6f &&
                fabsf(d.z + 0.4330127f) < 1e-6f);
    /* world azimuth 100, polar 125 (unnormalised, times 2): u = (100 - 30) / 360 = 0.194444,
     * v = 125 / 180 = 0.694444; pixel (floor(7.0), floor(12.5)) = (7, 12) */
    const double az = 100 * 3.14159265358979 / 180, po = 125 * 3.14159265358979 / 180;
    const lumis_vec3 w = {(float)(2 * sin(po) * cos(az)), (float)(2 * cos(po)),
                          (float)(2 * sin(po) * sin(az))};
    float u, v;
    lumis_envmap_dir_to_uv(rot, w, &u, &v);
    assert_true(fabsf(u - 0.1944444f) < 1e-5f && fabsf(v - 0.6944444f) < 1e-5f);
    int i, j;
    lumis_envmap_dir_to_pixel(rot, w, &i, &j);
    assert_int_equal(i, 7);
    assert_int_equal(j, 12);
    /* world -z (azimuth 270): u = (270 - 30) / 360 = 2/3, pixel 24 of 36; the horizon row 9 */
    lumis_envmap_dir_to_uv(rot, (lumis_vec3){0, 0, -1}, &u, &v);
    assert_true(fabsf(u - 2.0f / 3.0f) < 1e-6f && fabsf(v - 0.5f) < 1e-6f);
    lumis_envmap_dir_to_pixel(rot, (lumis_vec3){0, -0.01f, -1}, &i, &j);
    assert_int_equal(i, 24);
    assert_int_equal(j, 9);
    lumis_envmap_destroy(rot);
    lumis_image_destroy(img);
}

static void solid_angles_cover_the_sphere(void **state)
{
    (void)state;
    static const int sizes[][2] = {{1, 1}, {3, 1}, {4, 3}, {1024, 512}, {8192, 4096}};
    for (size_t s = 0; s < 5; s++) {
        double total = 0.0;
        for (int j = 0; j < sizes[s][1]; j++)
            total += sizes[s][0] * lumis_equirect_solid_angle(sizes[s][0], sizes[s][1], j);
        assert_true(fabs(total - 4.0 * PI) < 1e-12);
    }
    /* The formula of DESIGN.md, including the tiny rows at the poles. */
    double a = (2 * PI / 8) * (cos(0.0) - cos(PI / 4));
    assert_true(fabs(lumis_equirect_solid_angle(8, 4, 0) - a) < 1e-15);
    assert_true(lumis_equirect_solid_angle(8, 4, 4) == 0.0);
    assert_true(lumis_equirect_solid_angle(8, 4, -1) == 0.0);
}

/* Each channel's power is its own, the map's scale applied (lumis_envmap_power and the
 * statistics' power_rgb alike), and a texel is the pixel at column i of row j, on a map
 * whose width and height differ and whose channels differ. */
static void power_per_channel_and_texels(void **state)
{
    (void)state;
    const int w = 12, h = 5;
    lumis_image *img = tu_image(w, h, f_index);
    lumis_envmap *env = tu_envmap_of(img, 0.0f, 2.0f);
    double want[3] = {0, 0, 0};
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++)
            for (int c = 0; c < 3; c++)
                want[c] += 2.0 * f_index(i, j, c) * lumis_equirect_solid_angle(w, h, j);
    lumis_rgb p = lumis_envmap_power(env);
    const float got[3] = {p.r, p.g, p.b};
    lumis_envmap_stats st;
    assert_int_equal(lumis_envmap_stats_compute(env, &st), LUMIS_OK);
    for (int c = 0; c < 3; c++) {
        if (!(fabs(got[c] - want[c]) < 1e-6 * want[c]))
            fail_msg("channel %d: power %.9g, want %.9g", c, got[c], want[c]);
        if (!(fabs(st.power_rgb[c] - want[c]) < 1e-9 * want[c]))
            fail_msg("channel %d: stats power %.9g, want %.9g", c, st.power_rgb[c], want[c]);
    }
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            lumis_rgb t = lumis_envmap_texel(env, i, j);
            assert_true(t.r == 2.0f * f_index(i, j, 0) && t.g == 2.0f * f_index(i, j, 1) &&
                        t.b == 2.0f * f_index(i, j, 2));
        }
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

static void power_is_radiance_times_solid_angle(void **state)
{
    (void)state;
    lumis_image *img = tu_image(40, 20, f_const);
    lumis_envmap *env = tu_envmap_of(img, 10.0f, 3.0f);
    lumis_rgb p = lumis_envmap_power(env);
    assert_true(fabs(p.r - 3.0 * 2.0 * 4.0 * PI) < 1e-4);
    lumis_rgb c = lumis_envmap_eval(env, (lumis_vec3){0.3f, -0.4f, 0.5f});
    assert_true(c.g == 6.0f);
    assert_true(lumis_envmap_scale(env) == 3.0f);
    lumis_envmap_stats s;
    assert_int_equal(lumis_envmap_stats_compute(env, &s), LUMIS_OK);
    assert_true(fabs(s.avg_luminance - 6.0) < 1e-6);
    assert_true(fabs(s.power - 6.0 * 4 * PI) < 1e-5);
    assert_true(s.dynamic_range == 1.0);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

static float f_bad(int i, int j, int c)
{
    if (i == 0 && j == 0) return c == 0 ? NAN : (c == 1 ? INFINITY : -1.0f);
    return 1.0f;
}

static void bad_pixels_are_replaced_and_counted(void **state)
{
    (void)state;
    lumis_image *img = tu_image(4, 2, f_bad);
    lumis_envmap *env = tu_envmap_of(img, 0.0f, 0.0f);
    lumis_replaced r = lumis_envmap_replaced(env);
    assert_int_equal(r.nan, 1);
    assert_int_equal(r.inf, 1);
    assert_int_equal(r.negative, 1);
    lumis_rgb t = lumis_envmap_texel(env, 0, 0);
    assert_true(t.r == 0.0f && t.g == 0.0f && t.b == 0.0f);
    /* The caller's buffer was only borrowed: it is unchanged. */
    assert_true(isnan(img->pixels[0]));
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

static void invalid_descriptors_are_refused(void **state)
{
    (void)state;
    tu_sink sink;
    tu_sink_init(&sink);
    float px[3] = {1, 1, 1};
    lumis_envmap_desc d = {0};
    lumis_envmap *env = (lumis_envmap *)1;
    d.errors = sink.sink;
    assert_int_equal(lumis_envmap_create(&d, &env), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(env);
    d.pixels = px;
    assert_int_equal(lumis_envmap_create(&d, &env), LUMIS_ERR_BAD_DIMENSIONS);
    d.width = d.height = 1;
    d.scale = NAN;
    assert_int_equal(lumis_envmap_create(&d, &env), LUMIS_ERR_INVALID_ARGUMENT);
    d.scale = -1.0f;
    assert_int_equal(lumis_envmap_create(&d, &env), LUMIS_ERR_INVALID_ARGUMENT);
    assert_true(sink.count == 4 && strlen(sink.last) > 0);
    d.scale = 0.0f;
    d.width = 1 << 20;
    d.height = 1 << 20; /* never allocated: over the pixel limit */
    assert_int_equal(lumis_envmap_create(&d, &env), LUMIS_ERR_TOO_LARGE);
    assert_int_equal(lumis_envmap_create(NULL, &env), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_envmap_create(&d, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_envmap_destroy(NULL);
}

static int hot_i, hot_j;
static float f_hot(int i, int j, int c)
{
    (void)c;
    return (i == hot_i && j == hot_j) ? 1000.0f : 0.0f;
}
static float f_black(int i, int j, int c)
{
    (void)i, (void)j, (void)c;
    return 0.0f;
}

static void stats_of_special_maps(void **state)
{
    (void)state;
    /* One lit pixel holds all the power: both top shares are 1. */
    hot_i = 5;
    hot_j = 3;
    lumis_image *img = tu_image(20, 10, f_hot);
    lumis_envmap *env = tu_envmap_of(img, 0.0f, 0.0f);
    lumis_envmap_stats s;
    assert_int_equal(lumis_envmap_stats_compute(env, &s), LUMIS_OK);
    assert_true(fabs(s.top1_share - 1.0) < 1e-6 && fabs(s.top01_share - 1.0) < 1e-6);
    assert_true(fabs(s.power - 1000.0 * lumis_equirect_solid_angle(20, 10, 3)) < 1e-3);
    assert_true(s.max_luminance == 1000.0 && s.min_luminance == 0.0);
    assert_int_equal(s.black_pixels, 199);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);

    /* A black map: zero power is not an error, and nothing divides by it. */
    img = tu_image(8, 4, f_black);
    env = tu_envmap_of(img, 0.0f, 0.0f);
    assert_int_equal(lumis_envmap_stats_compute(env, &s), LUMIS_OK);
    assert_true(s.power == 0.0 && s.top1_share == 0.0 && s.dynamic_range == 0.0);
    assert_int_equal(s.black_pixels, 32);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);

    /* 1x1: one pixel is the whole sphere. */
    img = tu_image(1, 1, f_const);
    env = tu_envmap_of(img, 0.0f, 0.0f);
    assert_int_equal(lumis_envmap_stats_compute(env, &s), LUMIS_OK);
    assert_true(fabs(s.power - 2.0 * 4 * PI) < 1e-6 && fabs(s.top01_share - 1.0) < 1e-6);
    lumis_rgb c = lumis_envmap_eval(env, (lumis_vec3){0, -1, 0});
    assert_true(c.r == 2.0f);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

static float f_ramp(int i, int j, int c)
{
    return (float)(1.0 + 0.5 * sin(0.3 * i) + 0.01 * j * j + c);
}

/* Top shares against a brute-force sort. */
static int cmp_desc(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x < y) - (x > y);
}

static void top_shares_match_a_full_sort(void **state)
{
    (void)state;
    int w = 300, h = 150;
    lumis_image *img = tu_image(w, h, f_ramp);
    lumis_envmap *env = tu_envmap_of(img, 0.0f, 0.0f);
    lumis_envmap_stats s;
    assert_int_equal(lumis_envmap_stats_compute(env, &s), LUMIS_OK);
    double *yw = malloc(sizeof(double) * (size_t)(w * h)), total = 0.0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const float *p = img->pixels + 3 * (j * w + i);
            double y = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            yw[j * w + i] = y * lumis_equirect_solid_angle(w, h, j);
            total += yw[j * w + i];
        }
    qsort(yw, (size_t)(w * h), sizeof(double), cmp_desc);
    double t1 = 0.0, t01 = 0.0;
    for (int k = 0; k < w * h / 100; k++) t1 += yw[k];
    for (int k = 0; k < w * h / 1000; k++) t01 += yw[k];
    assert_true(fabs(s.top1_share - t1 / total) < 1e-5);
    assert_true(fabs(s.top01_share - t01 / total) < 1e-5);
    assert_true(fabs(s.power - total) < 1e-6 * total);
    free(yw);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

static double power_of(const float *px, int w, int h)
{
    double p = 0.0;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++)
            p += px[3 * (j * w + i) + 1] * lumis_equirect_solid_angle(w, h, j);
    return p;
}

static void resize_preserves_power(void **state)
{
    (void)state;
    static const int to[][2] = {{150, 75}, {301, 149}, {600, 300}, {1, 1}, {7, 3}, {1000, 777}};
    lumis_image *img = tu_image(300, 150, f_ramp);
    double p0 = power_of(img->pixels, 300, 150);
    for (size_t k = 0; k < sizeof to / sizeof to[0]; k++) {
        int w = to[k][0], h = to[k][1];
        float *dst = malloc(sizeof(float) * 3 * (size_t)(w * h));
        assert_int_equal(lumis_equirect_resize(img->pixels, 300, 150, dst, w, h), LUMIS_OK);
        assert_true(fabs(power_of(dst, w, h) - p0) < 1e-5 * p0);
        free(dst);
    }
    /* Same size is the identity; a constant map stays constant at any size. */
    float *same = malloc(sizeof(float) * 3 * 300 * 150);
    assert_int_equal(lumis_equirect_resize(img->pixels, 300, 150, same, 300, 150), LUMIS_OK);
    for (int k = 0; k < 3 * 300 * 150; k++)
        assert_true(fabsf(same[k] - img->pixels[k]) < 1e-5f * img->pixels[k]);
    free(same);
    lumis_image_destroy(img);
    img = tu_image(13, 9, f_const);
    float out[3 * 5 * 4];
    assert_int_equal(lumis_equirect_resize(img->pixels, 13, 9, out, 5, 4), LUMIS_OK);
    for (int k = 0; k < 60; k++) assert_true(fabsf(out[k] - 2.0f) < 1e-5f);
    assert_int_equal(lumis_equirect_resize(img->pixels, 13, 9, out, 0, 4),
                     LUMIS_ERR_BAD_DIMENSIONS);
    lumis_image_destroy(img);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(directions_are_pinned),
        cmocka_unit_test(pixel_direction_pixel_round_trip),
        cmocka_unit_test(rotation_turns_the_map_about_y),
        cmocka_unit_test(rotated_coordinates_by_hand),
        cmocka_unit_test(solid_angles_cover_the_sphere),
        cmocka_unit_test(power_is_radiance_times_solid_angle),
        cmocka_unit_test(power_per_channel_and_texels),
        cmocka_unit_test(bad_pixels_are_replaced_and_counted),
        cmocka_unit_test(invalid_descriptors_are_refused),
        cmocka_unit_test(stats_of_special_maps),
        cmocka_unit_test(top_shares_match_a_full_sort),
        cmocka_unit_test(resize_preserves_power),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
