/* The evaluation renderer: furnace, exact irradiance, agreement of estimators, and
 * determinism across thread counts. */
#include "../testutil.h"

#include "lumis/render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

static float f_const(int i, int j, int c)
{
    (void)i, (void)j, (void)c;
    return 2.0f;
}

static lumis_envmap *env_of(lumis_image *img)
{
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    lumis_image_destroy(img);
    return env;
}

static lumis_scene *one_sphere(float albedo)
{
    lumis_object o = {0};
    o.type = LUMIS_OBJECT_SPHERE;
    o.radius = 1.0f;
    o.material.type = LUMIS_BSDF_LAMBERT;
    o.material.diffuse = (lumis_rgb){albedo, albedo, albedo};
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(&o, 1, NULL, &s), LUMIS_OK);
    return s;
}

static const lumis_camera cam = {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 30.0f, 24, 24};

/* Pixels whose centre ray hits the unit sphere at the origin (with a margin). */
static int on_sphere(int x, int y, double *nx, double *ny, double *nz)
{
    double th = tan(0.5 * 30.0 * PI / 180.0);
    double sx = ((x + 0.5) / 24 * 2 - 1) * th, sy = (1 - (y + 0.5) / 24 * 2) * th;
    double l = sqrt(sx * sx + sy * sy + 1), dx = sx / l, dy = sy / l, dz = -1 / l;
    double b = 4 * dz, c = 16 - 1, disc = b * b - c; /* |o + t d|^2 = 1, o = (0,0,4) */
    if (disc < 0.05) return 0;
    double t = -b - sqrt(disc);
    *nx = t * dx;
    *ny = t * dy;
    *nz = 4 + t * dz;
    return 1;
}

static lumis_image *render(const lumis_scene *s, const lumis_envmap *env, lumis_sampler_method m,
                           lumis_estimator est, int spp, unsigned long long seed, int threads)
{
    lumis_sampler_desc sd = {0};
    sd.method = m;
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_sampler_create(env, &sd, &smp), LUMIS_OK);
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.env = env;
    d.sampler = smp;
    d.estimator = est;
    d.spp = spp;
    d.seed = seed;
    d.threads = threads;
    lumis_image *img = NULL;
    lumis_render_stats st;
    assert_int_equal(lumis_render(s, &d, &img, &st), LUMIS_OK);
    assert_true(st.camera_rays == 24.0 * 24 * spp);
    lumis_sampler_destroy(smp);
    return img;
}

static void furnace(void **state)
{
    (void)state;
    lumis_envmap *env = env_of(tu_image(32, 16, f_const));
    lumis_scene *s = one_sphere(0.5f);
    /* BSDF sampling of a Lambertian sphere in a constant map: every sample weighs rho L. */
    lumis_image *img = render(s, env, LUMIS_METHOD_INVERSION, LUMIS_ESTIMATOR_BSDF, 4, 1, 0);
    double nx, ny, nz;
    for (int y = 0; y < 24; y++)
        for (int x = 0; x < 24; x++) {
            float v = img->pixels[3 * (y * 24 + x) + 1];
            if (on_sphere(x, y, &nx, &ny, &nz)) assert_true(fabsf(v - 1.0f) < 1e-4f);
        }
    lumis_image_destroy(img);
    /* Every light sampler, with MIS: the sphere's mean is rho L. */
    for (int m = LUMIS_METHOD_INVERSION; m < LUMIS_METHOD_COUNT; m++) {
        img = render(s, env, (lumis_sampler_method)m, LUMIS_ESTIMATOR_MIS, 16, 2, 0);
        double sum = 0.0;
        int n = 0;
        for (int y = 0; y < 24; y++)
            for (int x = 0; x < 24; x++)
                if (on_sphere(x, y, &nx, &ny, &nz)) {
                    sum += img->pixels[3 * (y * 24 + x) + 1];
                    n++;
                }
        if (fabs(sum / n - 1.0) > 0.01) fail_msg("method %d: furnace mean %g", m, sum / n);
        lumis_image_destroy(img);
    }
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* A Lambertian sphere under a real-looking map: each pixel converges to rho / pi times the
 * exact irradiance, summed over every map pixel (4 x 4 sub-cells), within 3 standard
 * errors estimated from independent renders. */
static void exact_irradiance(void **state)
{
    (void)state;
    lumis_studio_desc sd = {0};
    sd.width = 64;
    lumis_image *map = NULL;
    assert_int_equal(lumis_studio_create(&sd, &map), LUMIS_OK);
    lumis_envmap *env = env_of(map);
    lumis_scene *s = one_sphere(0.7f);
    enum { RUNS = 8 };
    lumis_image *imgs[RUNS];
    for (int r = 0; r < RUNS; r++)
        imgs[r] =
            render(s, env, LUMIS_METHOD_INVERSION, LUMIS_ESTIMATOR_MIS, 32, 100u + (unsigned)r, 0);
    int checked = 0;
    for (int y = 1; y < 24; y += 3)
        for (int x = 1; x < 24; x += 3) {
            double nx, ny, nz;
            if (!on_sphere(x, y, &nx, &ny, &nz)) continue;
            double E = 0.0;
            for (int j = 0; j < 32; j++)
                for (int i = 0; i < 64; i++) {
                    double L = lumis_envmap_texel(env, i, j).g,
                           om = lumis_envmap_pixel_solid_angle(env, j) / 16;
                    for (int b = 0; b < 4; b++)
                        for (int a = 0; a < 4; a++) {
                            double c0 = cos(PI * j / 32), c1 = cos(PI * (j + 1) / 32);
                            float v = (float)(acos(c0 + (b + 0.5) / 4 * (c1 - c0)) / PI);
                            lumis_vec3 d =
                                lumis_envmap_uv_to_dir(env, (float)((i + (a + 0.5) / 4) / 64), v);
                            double c = d.x * nx + d.y * ny + d.z * nz;
                            if (c > 0) E += L * c * om;
                        }
                }
            double want = 0.7 / PI * E, sum = 0, sum2 = 0;
            for (int r = 0; r < RUNS; r++) {
                double v = imgs[r]->pixels[3 * (y * 24 + x) + 1];
                sum += v;
                sum2 += v * v;
            }
            double mean = sum / RUNS, se = sqrt(fmax(sum2 / RUNS - mean * mean, 0) / (RUNS - 1));
            if (fabs(mean - want) > 3 * se + 2e-3 * want)
                fail_msg("pixel (%d, %d): %g +- %g, exact %g", x, y, mean, se, want);
            checked++;
        }
    assert_true(checked > 20);
    for (int r = 0; r < RUNS; r++) lumis_image_destroy(imgs[r]);
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

static void estimators_agree_and_threads_do_not_matter(void **state)
{
    (void)state;
    lumis_sky_desc sd = {0};
    sd.width = 64;
    sd.sun_elevation_deg = 40.0f;
    lumis_image *map = NULL;
    assert_int_equal(lumis_sky_create(&sd, &map), LUMIS_OK);
    lumis_envmap *env = env_of(map);
    lumis_object o[2] = {{0}, {0}};
    o[0].type = LUMIS_OBJECT_SPHERE;
    o[0].radius = 1.0f;
    o[0].material = (lumis_bsdf){LUMIS_BSDF_GGX_PLASTIC, {0.5f, 0.3f, 0.2f}, {0, 0, 0}, 0.3f, 0.3f};
    o[1].type = LUMIS_OBJECT_PLANE;
    o[1].center = (lumis_vec3){0, -1, 0};
    o[1].normal = (lumis_vec3){0, 1, 0};
    o[1].material = (lumis_bsdf){LUMIS_BSDF_LAMBERT, {0.5f, 0.5f, 0.5f}, {0, 0, 0}, 0, 0};
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(o, 2, NULL, &s), LUMIS_OK);
    lumis_image *a = render(s, env, LUMIS_METHOD_KDTREE, LUMIS_ESTIMATOR_MIS, 8, 7, 1);
    lumis_image *b = render(s, env, LUMIS_METHOD_KDTREE, LUMIS_ESTIMATOR_MIS, 8, 7, 2);
    assert_memory_equal(a->pixels, b->pixels, sizeof(float) * 24 * 24 * 3); /* bit for bit */
    lumis_image_destroy(b);
    /* Light-only, BSDF-only and MIS estimate the same image: compare means over the frame. */
    double means[3];
    const lumis_estimator ests[3] = {LUMIS_ESTIMATOR_MIS, LUMIS_ESTIMATOR_LIGHT,
                                     LUMIS_ESTIMATOR_BSDF};
    for (int e = 0; e < 3; e++) {
        lumis_image *img =
            render(s, env, LUMIS_METHOD_INVERSION, ests[e], 256, 9u + (unsigned)e, 0);
        double sum = 0;
        for (int k = 0; k < 24 * 24; k++) sum += img->pixels[3 * k + 1];
        means[e] = sum / (24 * 24);
        lumis_image_destroy(img);
    }
    for (int e = 1; e < 3; e++)
        if (fabs(means[e] - means[0]) > 0.03 * means[0])
            fail_msg("estimator %d: mean %g vs MIS %g", e, means[e], means[0]);
    lumis_image_destroy(a);
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

static void bad_scenes(void **state)
{
    (void)state;
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_object o = {0};
    o.type = LUMIS_OBJECT_SPHERE;
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(&o, 1, &sink.sink, &s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "radius"));
    o.type = LUMIS_OBJECT_MESH;
    assert_int_equal(lumis_scene_create(&o, 1, &sink.sink, &s), LUMIS_ERR_INVALID_ARGUMENT);
    const float v[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    const unsigned idx[3] = {0, 1, 5};
    o.vertices = v;
    o.indices = idx;
    o.vertex_count = 3;
    o.triangle_count = 1;
    assert_int_equal(lumis_scene_create(&o, 1, &sink.sink, &s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "out of range"));
    assert_null(s);
    /* A camera looking straight along its up vector has no frame. */
    lumis_scene *ok = one_sphere(0.5f);
    lumis_envmap *env = env_of(tu_image(8, 4, f_const));
    lumis_camera bad_cam = {{0, 5, 0}, {0, 0, 0}, {0, 1, 0}, 40.0f, 8, 8};
    lumis_render_desc d = {0};
    d.camera = &bad_cam;
    d.env = env;
    d.estimator = LUMIS_ESTIMATOR_BSDF;
    d.errors = sink.sink;
    lumis_image *img = (lumis_image *)1;
    assert_int_equal(lumis_render(ok, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);
    assert_non_null(strstr(sink.last, "parallel"));
    lumis_scene_destroy(ok);
    lumis_envmap_destroy(env);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(furnace),
        cmocka_unit_test(exact_irradiance),
        cmocka_unit_test(estimators_agree_and_threads_do_not_matter),
        cmocka_unit_test(bad_scenes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
