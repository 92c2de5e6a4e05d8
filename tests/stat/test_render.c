/* The evaluation renderer: furnace, exact irradiance, agreement of estimators, and
 * determinism across thread counts. */
/* Oracles:
 * lumis_render — closed form: furnace (every BSDF sample weighs rho L, MIS means rho L),
 *     integrating sphere rho f L sum (rho (1 - f))^k, exact irradiance summed over every map pixel,
 *     a light set's floor rho / pi sum max(0, n.d) power and a glossy floor's sum f cos power
 *     (furnace, integrating_sphere, exact_irradiance, light_set_lights_each_pixel_with_its_set,
 *     light_set_shades_glossy_surfaces_with_their_bsdf)
 * lumis_render_job_create — consistency: any split into passes gives the image of one lumis_render
 *     call, bit for bit, every sequence (passes_do_not_change_the_image)
 * lumis_render_job_run — consistency: passes of 1, 2, 1, 4 samples give one pass's image; 0 refused
 *     (passes_do_not_change_the_image)
 * lumis_render_job_image — consistency: the image of one lumis_render call
 *     (passes_do_not_change_the_image)
 * lumis_render_job_stats — hand-worked: spp 8, 4 passes, 24 x 24 x 8 camera rays
 *     (passes_do_not_change_the_image)
 * lumis_render_job_destroy — external: leaks seen by ASan and valgrind
 *     (passes_do_not_change_the_image)
 * lumis_render_session — consistency: the image of its parts (sampler, light set by name, Wu with
 *     upsampled EnvIndirects) bit for bit; hand-worked: a budget's pilots, floor of K and time
 *     accounting; its automatic estimator's image is the chosen candidate's by hand, the choice the
 *     least relMSE x seconds it reports (render_session_equals_its_parts,
 *     render_session_budget_holds, auto_estimator_renders_what_it_chose)
 * lumis_auto_candidate_name — hand-worked: "mis", "stratified-32", "sun+mis", ..., "unknown"
 *     (auto_estimator_renders_what_it_chose)
 * lumis_render_gbuffer — hand-worked: depth 3.0015, normal and albedo at the sphere's centre pixel,
 *     infinite depth off it (upsampling_keeps_constants_and_depth_edges)
 * lumis_gbuffer_destroy — external: leaks seen by ASan and valgrind
 *     (upsampling_keeps_constants_and_depth_edges)
 * lumis_joint_bilateral_upsample — hand-worked: a constant stays constant, a depth step stays a
 *     step (fails without the depth term), objects and background do not mix
 *     (upsampling_keeps_constants_and_depth_edges, upsampling_builtins_and_scene_values)
 * lumis_scene_create — metamorphic: instances render as baked copies, a mirror transform works;
 *     error paths: a singular transform refused (instances_match_baked_copies, bad_scenes)
 * lumis_scene_destroy — external: leaks seen by ASan and valgrind (bad_scenes)
 * lumis_scene_builtin — hand-worked: the meshes' heights as given, every object standing on y = 0
 *     (builtin_scenes_build, upsampling_builtins_and_scene_values)
 * lumis_scene_builtin_names — hand-worked: 12 names, each builds (builtin_scenes_build)
 * lumis_scene_file_read — hand-worked: the map read beside the scene or from a spec; error paths:
 *     misspelt and repeated keys, trailing text, NaN vertices, and a value of the wrong kind
 *     or range at every level (camera, environment, objects, materials, transforms,
 *     luminaires, fixtures), each named by JSON path; no path, no output, a folder
 *     (scene_file_reads_its_map, scene_files_are_strict)
 * lumis_scene_file_destroy — external: leaks seen by ASan and valgrind (scene_files_are_strict)
 * lumis_envmap_from_image — indirect: the map of every render test, its radiance checked by the
 *     exact irradiance (exact_irradiance)
 */
#include "../testutil.h"

#include "lumis/render.h"
#include "render/internal.h"
#include "render/packet.h"
#include "render/scene.h"
#include "stat.h"

#include <math.h>
#include <stdio.h>
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

/* The unit normal where the ray through image position (px, py) (pixel units, row 0 on
 * top) meets the unit sphere at the origin; 0 if it misses. */
static int sphere_normal(double px, double py, double n[3])
{
    double th = tan(0.5 * 30.0 * PI / 180.0);
    double sx = (px / 24 * 2 - 1) * th, sy = (1 - py / 24 * 2) * th;
    double l = sqrt(sx * sx + sy * sy + 1), dx = sx / l, dy = sy / l, dz = -1 / l;
    double b = 4 * dz, c = 16 - 1, disc = b * b - c; /* |o + t d|^2 = 1, o = (0,0,4) */
    n[0] = n[1] = n[2] = 0.0;                        /* written on every path, a miss included */
    if (disc < 1e-3) return 0;
    double t = -b - sqrt(disc);
    n[0] = t * dx;
    n[1] = t * dy;
    n[2] = 4 + t * dz;
    return 1;
}

/* Pixels whose whole footprint lies on the sphere (every jittered sample hits it). */
static int on_sphere(int x, int y)
{
    double n[3];
    for (int k = 0; k < 4; k++)
        if (!sphere_normal(x + (k & 1), y + (k >> 1), n)) return 0;
    return 1;
}

/* Renders with sampler m and `base`'s settings (heuristic, sample counts; NULL: none). */
static lumis_image *render_with(const lumis_scene *s, const lumis_envmap *env,
                                lumis_sampler_method m, lumis_estimator est, int spp,
                                unsigned long long seed, int threads, const lumis_render_desc *base)
{
    lumis_sampler_desc sd = {0};
    sd.method = m;
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_sampler_create(env, &sd, &smp), LUMIS_OK);
    lumis_render_desc d = {0};
    if (base) d = *base;
    d.camera = &cam;
    d.lighting.env = env;
    d.lighting.sampler = smp;
    d.lighting.estimator = est;
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

static lumis_image *render(const lumis_scene *s, const lumis_envmap *env, lumis_sampler_method m,
                           lumis_estimator est, int spp, unsigned long long seed, int threads)
{
    return render_with(s, env, m, est, spp, seed, threads, NULL);
}

/* Mean of the green channel over the pixels wholly on the sphere. */
static double sphere_mean(const lumis_image *img)
{
    double sum = 0.0;
    int n = 0;
    for (int y = 0; y < 24; y++)
        for (int x = 0; x < 24; x++)
            if (on_sphere(x, y)) {
                sum += img->pixels[3 * (y * 24 + x) + 1];
                n++;
            }
    return sum / n;
}

typedef struct ray_count {
    long n, bad;
} ray_count;

static void count_ray(void *user, const float org[3], const float dir[3])
{
    ray_count *c = user;
    (void)org;
    c->n++;
    float len2 = dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2];
    c->bad += !(fabsf(len2 - 1.0f) < 1e-4f);
}

/* The descriptor's shadow-ray callback sees every shadow ray the statistics count, each
 * with a unit direction, and two renders with their own callbacks do not mix (it used to
 * be a static hook shared by every render). */
static void shadow_ray_callback(void **state)
{
    (void)state;
    lumis_envmap *env = env_of(tu_image(32, 16, f_const));
    lumis_scene *s = one_sphere(0.5f);
    lumis_sampler_desc sd = {0};
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_sampler_create(env, &sd, &smp), LUMIS_OK);
    ray_count c[2] = {{0, 0}, {0, 0}};
    for (int k = 0; k < 2; k++) {
        lumis_render_desc d = {0};
        d.camera = &cam;
        d.lighting.env = env;
        d.lighting.sampler = smp;
        d.spp = 1 + k;
        d.threads = 1;
        d.shadow_ray = count_ray;
        d.shadow_ray_user = &c[k];
        lumis_image *img = NULL;
        lumis_render_stats st;
        assert_int_equal(lumis_render(s, &d, &img, &st), LUMIS_OK);
        assert_true(st.shadow_rays > 0 && (double)c[k].n == st.shadow_rays);
        assert_int_equal(c[k].bad, 0);
        lumis_image_destroy(img);
    }
    assert_true(c[1].n > c[0].n);
    lumis_sampler_destroy(smp);
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

static void furnace(void **state)
{
    (void)state;
    lumis_envmap *env = env_of(tu_image(32, 16, f_const));
    lumis_scene *s = one_sphere(0.5f);
    /* BSDF sampling of a Lambertian sphere in a constant map: every sample weighs rho L. */
    lumis_image *img = render(s, env, LUMIS_METHOD_INVERSION, LUMIS_ESTIMATOR_BSDF, 4, 1, 0);
    for (int y = 0; y < 24; y++)
        for (int x = 0; x < 24; x++) {
            float v = img->pixels[3 * (y * 24 + x) + 1];
            if (on_sphere(x, y)) assert_true(fabsf(v - 1.0f) < 1e-4f);
        }
    lumis_image_destroy(img);
    /* Every light sampler, with MIS: the sphere's mean is rho L. */
    for (int m = LUMIS_METHOD_INVERSION; m < LUMIS_METHOD_COUNT; m++) {
        img = render(s, env, (lumis_sampler_method)m, LUMIS_ESTIMATOR_MIS, 16, 2, 0);
        const double mean = sphere_mean(img);
        if (fabs(mean - 1.0) > 0.01) fail_msg("method %d: furnace mean %g", m, mean);
        lumis_image_destroy(img);
    }
    /* Both heuristics, with unequal sample counts: MIS weights that do not sum to 1 over
     * the strategies (a power heuristic squaring one term only, a count left out) bias the
     * furnace (the map's pdf, uniform on the sphere, and the BSDF's, cosine, differ). */
    for (int power = 0; power < 2; power++)
        for (int c = 0; c < 3; c++) {
            static const int nl[3] = {1, 2, 1}, nb[3] = {1, 1, 3};
            lumis_render_desc base = {0};
            base.power_heuristic = power;
            base.light_samples = nl[c];
            base.bsdf_samples = nb[c];
            img = render_with(s, env, LUMIS_METHOD_INVERSION, LUMIS_ESTIMATOR_MIS, 16, 3, 0, &base);
            const double mean = sphere_mean(img);
            if (fabs(mean - 1.0) > 0.01)
                fail_msg("%s heuristic, %d light + %d BSDF samples: furnace mean %g",
                         power ? "power" : "balance", nl[c], nb[c], mean);
            lumis_image_destroy(img);
        }
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* A Lambertian sphere under a real-looking map: each pixel converges to rho / pi times the
 * exact irradiance, summed over every map pixel (4 x 4 sub-cells) and averaged over the
 * pixel's footprint (4 x 4 positions: the camera jitters inside the pixel), within 4.5
 * standard errors estimated from 32 independent renders, with no bias shared by all the
 * pixels (the sum of their z scores). */
/* Every sub-cell of a 64 x 32 map (4 x 4 a pixel, equal in solid angle): its direction and
 * L * solid angle, per channel, into cell[q][0..5]. */
enum { MAP_CELLS = 64 * 32 * 16 };
static void map_cells(const lumis_envmap *env, double (*cell)[6])
{
    for (int j = 0, q = 0; j < 32; j++)
        for (int i = 0; i < 64; i++) {
            const lumis_rgb tx = lumis_envmap_texel(env, i, j);
            const double om = lumis_envmap_pixel_solid_angle(env, j) / 16;
            for (int b = 0; b < 4; b++)
                for (int a = 0; a < 4; a++, q++) {
                    double c0 = cos(PI * j / 32), c1 = cos(PI * (j + 1) / 32);
                    float v = (float)(acos(c0 + (b + 0.5) / 4 * (c1 - c0)) / PI);
                    lumis_vec3 d =
                        lumis_envmap_uv_to_dir(env, (float)((i + (a + 0.5) / 4) / 64), v);
                    cell[q][0] = d.x;
                    cell[q][1] = d.y;
                    cell[q][2] = d.z;
                    cell[q][3] = tx.r * om;
                    cell[q][4] = tx.g * om;
                    cell[q][5] = tx.b * om;
                }
        }
}

/* Checks RUNS renders of one_sphere(albedo) under env against the exact irradiance (see
 * exact_irradiance); `what` names the renders in messages. */
static void check_irradiance(lumis_image *const *imgs, int runs, const lumis_envmap *env,
                             double albedo, const char *what)
{
    enum { CELLS = MAP_CELLS };
    assert_int_equal(lumis_envmap_width(env), 64);
    /* Every sub-cell of the map: its direction and L * solid angle, per channel: the map is
     * coloured, its channels not in proportion (a sample that mixes them up must show). */
    static double cell[CELLS][6];
    map_cells(env, cell);
    int checked = 0;
    double zsum[3] = {0, 0, 0};
    for (int y = 1; y < 24; y += 3)
        for (int x = 1; x < 24; x += 3) {
            if (!on_sphere(x, y)) continue;
            double E[3] = {0, 0, 0};
            for (int sub = 0; sub < 16; sub++) {
                double n[3];
                assert_true(sphere_normal(x + (sub % 4 + 0.5) / 4, y + (sub / 4 + 0.5) / 4, n));
                for (int q = 0; q < CELLS; q++) {
                    double c = cell[q][0] * n[0] + cell[q][1] * n[1] + cell[q][2] * n[2];
                    if (c > 0)
                        for (int ch = 0; ch < 3; ch++) E[ch] += cell[q][3 + ch] * c / 16;
                }
            }
            for (int ch = 0; ch < 3; ch++) {
                double want = albedo / PI * E[ch], sum = 0, sum2 = 0;
                for (int r = 0; r < runs; r++) {
                    double v = imgs[r]->pixels[3 * (y * 24 + x) + ch];
                    sum += v;
                    sum2 += v * v;
                }
                double mean = sum / runs,
                       se = sqrt(fmax(sum2 / runs - mean * mean, 0) / (runs - 1));
                double z = (mean - want) / fmax(se, 1e-3 * want);
                /* About 40 pixels: 4.5 standard errors each (Student t, 31 degrees of freedom:
                 * p ~ 1e-4 per pixel), and the sum of their z scores within 3.5 sqrt(n), which
                 * catches a bias of a few tenths of a percent shared by every pixel. */
                if (fabs(z) > 4.5)
                    fail_msg("%s: pixel (%d, %d) channel %d: %g +- %g, exact %g (z = %.2f)", what,
                             x, y, ch, mean, se, want, z);
                zsum[ch] += z;
            }
            checked++;
        }
    assert_true(checked > 20);
    for (int ch = 0; ch < 3; ch++)
        if (fabs(zsum[ch]) > 3.5 * sqrt(checked))
            fail_msg("%s: pixels share a bias in channel %d: sum of z = %.2f over %d pixels", what,
                     ch, zsum[ch], checked);
}

static lumis_envmap *studio_map(void)
{
    lumis_studio_desc sd = {0};
    sd.width = 64;
    lumis_image *map = NULL;
    assert_int_equal(lumis_studio_create(&sd, &map), LUMIS_OK);
    /* coloured, and not uniformly: red grows with u, blue with v, so that no channel is a
     * multiple of another (grey data hides colour bugs) */
    for (int j = 0; j < map->height; j++)
        for (int i = 0; i < map->width; i++) {
            float *px = map->pixels + 3 * ((size_t)j * (size_t)map->width + (size_t)i);
            px[0] *= 0.4f + 1.2f * (float)i / (float)map->width;
            px[2] *= 0.3f + 1.4f * (float)j / (float)map->height;
        }
    return env_of(map);
}

/* A Lambertian sphere under a real-looking map: each pixel converges to rho / pi times the
 * exact irradiance, summed over every map pixel (4 x 4 sub-cells) and averaged over the
 * pixel's footprint (4 x 4 positions: the camera jitters inside the pixel), within 4.5
 * standard errors estimated from 32 independent renders, with no bias shared by all the
 * pixels (the sum of their z scores). */
static void exact_irradiance(void **state)
{
    (void)state;
    lumis_envmap *env = studio_map();
    lumis_scene *s = one_sphere(0.7f);
    enum { RUNS = 32 };
    lumis_image *imgs[RUNS];
    for (int r = 0; r < RUNS; r++)
        imgs[r] =
            render(s, env, LUMIS_METHOD_INVERSION, LUMIS_ESTIMATOR_MIS, 64, 100u + (unsigned)r, 0);
    check_irradiance(imgs, RUNS, env, 0.7, "inversion + MIS (the default sequence)");
    for (int r = 0; r < RUNS; r++) lumis_image_destroy(imgs[r]);
    /* Every sample sequence converges to the same irradiance (its randomisations, the
     * seeds, make the runs independent), with two light samples per camera sample so that
     * the points j of n of one dimension are used too. */
    for (int q = LUMIS_SEQUENCE_PCG; q < LUMIS_SEQUENCE_COUNT; q++) {
        lumis_render_desc base = {0};
        base.sequence = (lumis_sequence)q;
        base.light_samples = 2;
        for (int r = 0; r < RUNS; r++)
            imgs[r] = render_with(s, env, LUMIS_METHOD_INVERSION, LUMIS_ESTIMATOR_MIS, 16,
                                  300u + (unsigned)r, 0, &base);
        char what[64];
        snprintf(what, sizeof what, "inversion + MIS, %s", lumis_sequence_name((lumis_sequence)q));
        check_irradiance(imgs, RUNS, env, 0.7, what);
        for (int r = 0; r < RUNS; r++) lumis_image_destroy(imgs[r]);
    }
    /* A sampler built on another map object with the same pixels (not fused with the map:
     * the radiance and the light pdf come from two lookups) and unequal sample counts: the
     * MIS weights must still carry the counts (issue 37: dropped there, ~-30 % bias, unseen
     * with one sample of each). */
    {
        lumis_envmap *twin = studio_map();
        lumis_sampler_desc sd = {0};
        sd.method = LUMIS_METHOD_INVERSION;
        lumis_sampler *smp = NULL;
        assert_int_equal(lumis_sampler_create(twin, &sd, &smp), LUMIS_OK);
        for (int r = 0; r < RUNS; r++) {
            lumis_render_desc d = {0};
            d.camera = &cam;
            d.lighting.env = env;
            d.lighting.sampler = smp;
            d.lighting.estimator = LUMIS_ESTIMATOR_MIS;
            d.light_samples = 3;
            d.bsdf_samples = 1;
            d.spp = 16;
            d.seed = 700u + (unsigned)r;
            assert_int_equal(lumis_render(s, &d, &imgs[r], NULL), LUMIS_OK);
        }
        check_irradiance(imgs, RUNS, env, 0.7, "inversion + MIS, a twin map's sampler, 3 + 1");
        for (int r = 0; r < RUNS; r++) lumis_image_destroy(imgs[r]);
        lumis_sampler_destroy(smp);
        lumis_envmap_destroy(twin);
    }
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* A sun split off the map (lighting.sun) is exact: the sphere converges to the whole map's
 * irradiance when the sun is drawn as a cone and the residual by its sampler (light, MIS,
 * power heuristic) or by a stratified light set made from the residual. */
static void sun_split_converges_to_the_exact_irradiance(void **state)
{
    (void)state;
    lumis_envmap *studio = studio_map();
    /* a small, very bright, coloured source at (40, 9) and its neighbour */
    float *px = malloc(sizeof(float) * 3 * 64 * 32);
    assert_non_null(px);
    memcpy(px, lumis_envmap_pixels(studio), sizeof(float) * 3 * 64 * 32);
    const float sun[2][3] = {{900.0f, 600.0f, 300.0f}, {400.0f, 500.0f, 700.0f}};
    for (int k = 0; k < 3; k++) {
        px[3 * (9 * 64 + 40) + k] = sun[0][k];
        px[3 * (9 * 64 + 41) + k] = sun[1][k];
    }
    lumis_envmap_desc ed = {0};
    ed.pixels = px;
    ed.width = 64;
    ed.height = 32;
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_create(&ed, &env), LUMIS_OK);
    free(px);
    lumis_envmap_destroy(studio);
    lumis_sun_desc sdesc = {0};
    sdesc.max_radius_deg = 20.0; /* pixels of 5.6 degrees */
    lumis_sun sn;
    lumis_envmap *res = NULL;
    assert_int_equal(lumis_sun_find(env, &sdesc, &sn, &res), LUMIS_OK);
    assert_int_equal(sn.found, 1);
    assert_true(sn.share > 0.3);
    lumis_sampler_desc smd = {0};
    smd.method = LUMIS_METHOD_INVERSION;
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_sampler_create(res, &smd, &smp), LUMIS_OK);
    lumis_sun_sampler *ss = NULL;
    assert_int_equal(lumis_sun_sampler_create(env, &sn, NULL, &ss), LUMIS_OK);
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(res, "median-cut", 8, 0, NULL, NULL, &set), LUMIS_OK);
    lumis_scene *s = one_sphere(0.7f);
    enum { RUNS = 32 };
    static const struct {
        lumis_lighting_kind kind;
        lumis_estimator est;
        int power;
        const char *what;
    } cases[] = {
        {LUMIS_LIGHTING_ENV, LUMIS_ESTIMATOR_MIS, 0, "sun + residual, MIS"},
        {LUMIS_LIGHTING_ENV, LUMIS_ESTIMATOR_LIGHT, 0, "sun + residual, light sampling"},
        {LUMIS_LIGHTING_ENV, LUMIS_ESTIMATOR_MIS, 1, "sun + residual, power heuristic"},
        {LUMIS_LIGHTING_LIGHT_SET, LUMIS_ESTIMATOR_MIS, 0, "sun + stratified median cut"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        lumis_image *imgs[RUNS];
        for (int r = 0; r < RUNS; r++) {
            lumis_render_desc d = {0};
            d.camera = &cam;
            d.lighting.kind = cases[c].kind;
            d.lighting.env = env;
            d.lighting.sun.sun = &sn;
            d.lighting.sun.residual = res;
            d.lighting.sun.sampler = ss;
            d.lighting.estimator = cases[c].est;
            d.power_heuristic = cases[c].power;
            if (cases[c].kind == LUMIS_LIGHTING_ENV) {
                d.lighting.sampler = smp;
            } else {
                d.lighting.light_set.set = set;
                d.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
            }
            d.spp = 16;
            d.seed = 900u + (unsigned)r;
            assert_int_equal(lumis_render(s, &d, &imgs[r], NULL), LUMIS_OK);
        }
        check_irradiance(imgs, RUNS, env, 0.7, cases[c].what);
        for (int r = 0; r < RUNS; r++) lumis_image_destroy(imgs[r]);
    }
    /* the check's refusals, each naming its field */
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.lighting.env = env;
    d.lighting.sampler = smp;
    d.lighting.sun.sun = &sn;
    d.lighting.sun.sampler = ss;
    d.spp = 1;
    lumis_image *img = NULL;
    tu_sink k;
    tu_sink_init(&k);
    d.errors = k.sink;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(k.last, "lighting.sun.residual: missing"));
    d.lighting.sun.residual = env;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(k.last, "lighting.sampler: must sample lighting.sun.residual"));
    lumis_sun none = {0};
    d.lighting.sun.sun = &none;
    d.lighting.sun.residual = res;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(k.last, "lighting.sun.sun: no sun"));
    lumis_scene_destroy(s);
    lumis_light_set_destroy(set);
    lumis_sampler_destroy(smp);
    lumis_sun_sampler_destroy(ss);
    lumis_envmap_destroy(res);
    lumis_envmap_destroy(env);
}

/* A light set's stratified mode is unbiased: the same exact irradiance, for median cut,
 * and for Wu's EnvDirects and EnvIndirects rendered as two layers and added (each layer
 * lights only its own regions, MIS included), with light sampling alone and with both
 * heuristics.  (BSDF sampling alone is the map's own, and too heavy-tailed on this map
 * for a 4.5-sigma test at this sample count.) */
static void stratified_light_sets_converge_to_the_exact_irradiance(void **state)
{
    (void)state;
    lumis_envmap *env = studio_map();
    lumis_scene *s = one_sphere(0.7f);
    enum { RUNS = 32 };
    static const struct {
        const char *method;
        int k, split;
        lumis_estimator est;
        int power;
        lumis_sequence seq; /* a dimension per region */
    } cases[] = {
        {"median-cut", 8, 0, LUMIS_ESTIMATOR_MIS, 0, LUMIS_SEQUENCE_PCG},
        {"wu", 12, 1, LUMIS_ESTIMATOR_MIS, 0, LUMIS_SEQUENCE_PCG},
        {"variance-min", 5, 0, LUMIS_ESTIMATOR_LIGHT, 0, LUMIS_SEQUENCE_PCG},
        {"tmms", 8, 0, LUMIS_ESTIMATOR_MIS, 1, LUMIS_SEQUENCE_PCG},
        {"median-cut", 8, 0, LUMIS_ESTIMATOR_MIS, 0, LUMIS_SEQUENCE_SOBOL},
        {"wu", 12, 1, LUMIS_ESTIMATOR_MIS, 0, LUMIS_SEQUENCE_ZSOBOL},
        {"fhis", 16, 0, LUMIS_ESTIMATOR_MIS, 0, LUMIS_SEQUENCE_PMJ02},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        lumis_light_set *set = NULL;
        assert_int_equal(
            lumis_lights_by_name(env, cases[c].method, cases[c].k, 0, NULL, NULL, &set), LUMIS_OK);
        lumis_region_sampler *rs = NULL;
        assert_int_equal(lumis_region_sampler_create(env, set, NULL, &rs), LUMIS_OK);
        if (cases[c].split) {
            const lumis_light_set_info *info = lumis_light_set_get_info(set);
            assert_true(info->direct > 0 && info->indirect > 0);
        }
        lumis_image *imgs[RUNS];
        for (int r = 0; r < RUNS; r++) {
            lumis_render_desc d = {0};
            d.camera = &cam;
            d.lighting.env = env;
            d.lighting.light_set.set = set;
            d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
            d.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
            d.lighting.light_set.regions = r % 2 ? rs : NULL; /* made by the render, or given */
            d.lighting.estimator = cases[c].est;
            d.power_heuristic = cases[c].power;
            d.sequence = cases[c].seq;
            d.spp = 16;
            d.seed = 500u + (unsigned)r;
            lumis_render_stats st;
            if (cases[c].split) d.lighting.light_set.kinds = 1u << LUMIS_LIGHT_ENV_DIRECT;
            assert_int_equal(lumis_render(s, &d, &imgs[r], &st), LUMIS_OK);
            assert_true(st.shadow_rays > 0.0);
            if (cases[c].split) {
                lumis_image *other = NULL;
                d.lighting.light_set.kinds = 1u << LUMIS_LIGHT_ENV_INDIRECT;
                d.lighting.hide_environment = 1;
                assert_int_equal(lumis_render(s, &d, &other, NULL), LUMIS_OK);
                for (int k = 0; k < 3 * 24 * 24; k++) imgs[r]->pixels[k] += other->pixels[k];
                lumis_image_destroy(other);
            }
        }
        char what[64];
        snprintf(what, sizeof what, "stratified %s (estimator %d, %s)", cases[c].method,
                 (int)cases[c].est, lumis_sequence_name(cases[c].seq));
        check_irradiance(imgs, RUNS, env, 0.7, what);
        for (int r = 0; r < RUNS; r++) lumis_image_destroy(imgs[r]);
        lumis_region_sampler_destroy(rs);
        lumis_light_set_destroy(set);
    }
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* Renders of `s` lit by `set`'s regions in stratified mode, with draws chosen per shading
 * point (light_set.draws) or allocated over the regions (light_set.region_draws), seeds
 * seed0 + r. */
static void render_strata(const lumis_scene *s, const lumis_envmap *env, const lumis_light_set *set,
                          const lumis_region_sampler *rs, int draws, int region_draws,
                          lumis_estimator est, int power, lumis_sequence seq, unsigned kinds,
                          int spp, unsigned seed0, int runs, lumis_image **imgs)
{
    for (int r = 0; r < runs; r++) {
        lumis_render_desc d = {0};
        d.camera = &cam;
        d.lighting.env = env;
        d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
        d.lighting.light_set.set = set;
        d.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
        d.lighting.light_set.regions = r % 2 ? rs : NULL;
        d.lighting.light_set.draws = draws;
        d.lighting.light_set.region_draws = region_draws;
        d.lighting.light_set.kinds = kinds;
        d.lighting.estimator = est;
        d.power_heuristic = power;
        d.sequence = seq;
        d.spp = spp;
        d.seed = seed0 + (unsigned)r;
        lumis_render_stats st;
        assert_int_equal(lumis_render(s, &d, &imgs[r], &st), LUMIS_OK);
        assert_true(st.shadow_rays > 0.0);
        if (kinds == 1u << LUMIS_LIGHT_ENV_DIRECT) { /* Wu's split: the other layer added */
            lumis_image *other = NULL;
            d.lighting.light_set.kinds = 1u << LUMIS_LIGHT_ENV_INDIRECT;
            d.lighting.hide_environment = 1;
            assert_int_equal(lumis_render(s, &d, &other, NULL), LUMIS_OK);
            for (int k = 0; k < 3 * 24 * 24; k++) imgs[r]->pixels[k] += other->pixels[k];
            lumis_image_destroy(other);
        }
    }
}

/* Selected draws (N draws per vertex over regions picked in proportion to a bound of their
 * contribution) are unbiased: every pixel of the Lambertian sphere converges to the exact
 * irradiance summed over the map's pixels, in all three channels of the coloured map, for
 * one draw and for several, light sampling alone and MIS with both heuristics, Wu's two
 * layers added, and several sequences (the draws' choices and directions are their own
 * dimensions). */
static void selected_draws_converge_to_the_exact_irradiance(void **state)
{
    (void)state;
    lumis_envmap *env = studio_map();
    lumis_scene *s = one_sphere(0.7f);
    enum { RUNS = 32 };
    static const struct {
        const char *method;
        int k, draws, split;
        lumis_estimator est;
        int power;
        lumis_sequence seq;
    } cases[] = {
        {"median-cut", 8, 1, 0, LUMIS_ESTIMATOR_MIS, 0, LUMIS_SEQUENCE_PCG},
        {"median-cut", 16, 3, 0, LUMIS_ESTIMATOR_LIGHT, 0, LUMIS_SEQUENCE_SOBOL},
        {"wu", 12, 4, 1, LUMIS_ESTIMATOR_MIS, 1, LUMIS_SEQUENCE_ZSOBOL},
        {"fhis", 32, 8, 0, LUMIS_ESTIMATOR_MIS, 0, LUMIS_SEQUENCE_PMJ02},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        lumis_light_set *set = NULL;
        assert_int_equal(
            lumis_lights_by_name(env, cases[c].method, cases[c].k, 0, NULL, NULL, &set), LUMIS_OK);
        lumis_region_sampler *rs = NULL;
        assert_int_equal(lumis_region_sampler_create(env, set, NULL, &rs), LUMIS_OK);
        lumis_image *imgs[RUNS];
        render_strata(s, env, set, rs, cases[c].draws, 0, cases[c].est, cases[c].power,
                      cases[c].seq, cases[c].split ? 1u << LUMIS_LIGHT_ENV_DIRECT : 0u, 16, 700u,
                      RUNS, imgs);
        char what[96];
        snprintf(what, sizeof what, "selected draws %s K %d N %d (estimator %d, %s)",
                 cases[c].method, cases[c].k, cases[c].draws, (int)cases[c].est,
                 lumis_sequence_name(cases[c].seq));
        check_irradiance(imgs, RUNS, env, 0.7, what);
        for (int r = 0; r < RUNS; r++) lumis_image_destroy(imgs[r]);
        lumis_region_sampler_destroy(rs);
        lumis_light_set_destroy(set);
    }
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* Allocated draws (light_set.region_draws = N: n_r >= 1 draws in every region r, N in all,
 * each region's draws averaged, MIS as n_r light samples against one BSDF sample) are
 * unbiased: every pixel of the Lambertian sphere converges to the exact irradiance summed over
 * the map's pixels, in all three channels of the coloured map, with N at the regions' count
 * (one each), odd and larger, light sampling alone and MIS with both heuristics, Wu's two
 * layers added, and several sequences (a region's n_r points of its own dimension). */
static void allocated_draws_converge_to_the_exact_irradiance(void **state)
{
    (void)state;
    lumis_envmap *env = studio_map();
    lumis_scene *s = one_sphere(0.7f);
    enum { RUNS = 32 };
    static const struct {
        const char *method;
        int k, draws, split;
        lumis_estimator est;
        int power;
        lumis_sequence seq;
    } cases[] = {
        {"median-cut", 8, 8, 0, LUMIS_ESTIMATOR_MIS, 0, LUMIS_SEQUENCE_PCG},
        {"median-cut", 8, 21, 0, LUMIS_ESTIMATOR_MIS, 0, LUMIS_SEQUENCE_SOBOL},
        {"median-cut", 16, 37, 0, LUMIS_ESTIMATOR_LIGHT, 0, LUMIS_SEQUENCE_SOBOL},
        {"wu", 12, 40, 1, LUMIS_ESTIMATOR_MIS, 1, LUMIS_SEQUENCE_ZSOBOL},
        {"fhis", 16, 64, 0, LUMIS_ESTIMATOR_MIS, 1, LUMIS_SEQUENCE_PMJ02},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        lumis_light_set *set = NULL;
        assert_int_equal(
            lumis_lights_by_name(env, cases[c].method, cases[c].k, 0, NULL, NULL, &set), LUMIS_OK);
        lumis_region_sampler *rs = NULL;
        assert_int_equal(lumis_region_sampler_create(env, set, NULL, &rs), LUMIS_OK);
        lumis_image *imgs[RUNS];
        render_strata(s, env, set, rs, 0, cases[c].draws, cases[c].est, cases[c].power,
                      cases[c].seq, cases[c].split ? 1u << LUMIS_LIGHT_ENV_DIRECT : 0u, 16, 900u,
                      RUNS, imgs);
        char what[96];
        snprintf(what, sizeof what, "allocated draws %s K %d N %d (estimator %d, %s)",
                 cases[c].method, cases[c].k, cases[c].draws, (int)cases[c].est,
                 lumis_sequence_name(cases[c].seq));
        check_irradiance(imgs, RUNS, env, 0.7, what);
        for (int r = 0; r < RUNS; r++) lumis_image_destroy(imgs[r]);
        lumis_region_sampler_destroy(rs);
        lumis_light_set_destroy(set);
    }
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* The least of sum_k s2[k] / n_k over every n_k >= 1 with sum n_k = left + (K - k) (brute
 * force over the compositions, for the test alone). */
static double neyman_brute(const double *s2, int K, int k, int left)
{
    if (k == K - 1) return s2[k] / (double)(1 + left);
    double best = INFINITY;
    for (int e = 0; e <= left; e++) {
        const double v = s2[k] / (double)(1 + e) + neyman_brute(s2, K, k + 1, left - e);
        if (v < best) best = v;
    }
    return best;
}

/* Allocated draws are Neyman's allocation against s_r = Y(P_r) Omega_r^(1/4): for several
 * N the counts are at least one a region, add up to N, and reach the least variance term
 * sum s_r^2 / n_r that a brute-force search over every split of N finds (ties may split
 * differently, the sum may not); a larger s never gets fewer draws.  Refused: N under the
 * regions lit, N with draws, N in point mode, a negative N, each naming the field. */
static void allocated_draws_follow_neyman(void **state)
{
    (void)state;
    lumis_envmap *env = studio_map();
    enum { K = 7 };
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(env, "median-cut", K, 0, NULL, NULL, &set), LUMIS_OK);
    const lumis_light *l = NULL;
    int count = 0;
    assert_int_equal(lumis_light_set_get(set, 0, &l, &count), LUMIS_OK);
    assert_int_equal(count, K);
    double s2[K];
    for (int k = 0; k < K; k++) {
        const double y = 0.2126 * l[k].power[0] + 0.7152 * l[k].power[1] + 0.0722 * l[k].power[2];
        s2[k] = y * y * sqrt(l[k].solid_angle);
    }
    lumis_render_desc d = {0};
    d.lighting.env = env;
    d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    d.lighting.light_set.set = set;
    d.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
    int spread = 0;
    for (int N = K; N <= 40; N += 3) {
        d.lighting.light_set.region_draws = N;
        int n[K];
        assert_int_equal(lumis__light_set_allocation(&d, n), LUMIS_OK);
        int sum = 0;
        double v = 0;
        for (int k = 0; k < K; k++) {
            if (n[k] < 1) fail_msg("N %d: region %d gets %d draws", N, k, n[k]);
            sum += n[k];
            v += s2[k] / n[k];
            for (int j = 0; j < K; j++)
                if (s2[j] > s2[k] * (1 + 1e-9) && n[j] < n[k])
                    fail_msg("N %d: region %d (s2 %g) gets %d draws, region %d (s2 %g) %d", N, j,
                             s2[j], n[j], k, s2[k], n[k]);
            if (n[k] > n[0] + 1 || n[k] < n[0] - 1) spread = 1;
        }
        assert_int_equal(sum, N);
        const double best = neyman_brute(s2, K, 0, N - K);
        if (v > best * (1 + 1e-12)) fail_msg("N %d: sum s2 / n %.12g, the least %.12g", N, v, best);
    }
    assert_true(spread); /* the map's regions differ enough that the counts are not all equal */
    int n[K];
    d.lighting.light_set.region_draws = K - 1;
    assert_int_equal(lumis__light_set_allocation(&d, n), LUMIS_ERR_INVALID_ARGUMENT);
    static const lumis_camera one = {{0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 40.0f, 4, 4};
    lumis_scene *s = one_sphere(0.5f);
    lumis_image *img = NULL;
    const struct {
        int region_draws, draws;
        lumis_lights_mode mode;
    } bad[] = {{K - 1, 0, LUMIS_LIGHTS_STRATIFIED},
               {2 * K, 3, LUMIS_LIGHTS_STRATIFIED},
               {2 * K, 0, LUMIS_LIGHTS_POINT},
               {-1, 0, LUMIS_LIGHTS_STRATIFIED}};
    for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
        tu_sink k;
        tu_sink_init(&k);
        d.camera = &one;
        d.spp = 1;
        d.errors = k.sink;
        d.lighting.light_set.region_draws = bad[b].region_draws;
        d.lighting.light_set.draws = bad[b].draws;
        d.lighting.light_set.mode = bad[b].mode;
        assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
        assert_null(img);
        if (!strstr(k.last, "lighting.light_set.region_draws"))
            fail_msg("case %zu: the message names no field: %s", b, k.last);
    }
    lumis_scene_destroy(s);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* Allocated draws with no region lit (kinds that select none of the set's regions: a median
 * cut's are all LUMIS_LIGHT_REGION): nothing to allocate, so region_draws N is accepted
 * whatever N (at least the zero regions lit) and the render is the one of region_draws 0,
 * bit for bit, black with the map hidden (the set adds no light, the BSDF samples find no
 * region drawn from); every region gets 0 draws.  prepare once ran allocate_draws' loop N
 * times on a one-slot array it never set (an increment of an uninitialised int, which
 * nothing read: valgrind --error-exitcode=1 passes this test with and without the fix). */
static void allocated_draws_with_no_region_lit(void **state)
{
    (void)state;
    lumis_envmap *env = studio_map();
    enum { K = 6 };
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(env, "median-cut", K, 0, NULL, NULL, &set), LUMIS_OK);
    lumis_region_sampler *rs = NULL;
    assert_int_equal(lumis_region_sampler_create(env, set, NULL, &rs), LUMIS_OK);
    static const lumis_camera small = {{0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 40.0f, 6, 6};
    lumis_scene *s = one_sphere(0.5f);
    lumis_render_desc d = {0};
    d.camera = &small;
    d.spp = 2;
    d.seed = 5;
    d.lighting.env = env;
    d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    d.lighting.light_set.set = set;
    d.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
    d.lighting.light_set.kinds = 1u << LUMIS_LIGHT_ENV_INDIRECT; /* none of the set's */
    d.lighting.hide_environment = 1;
    lumis_image *ref = NULL;
    assert_int_equal(lumis_render(s, &d, &ref, NULL), LUMIS_OK);
    const size_t m = 3 * (size_t)small.width * (size_t)small.height;
    for (size_t k = 0; k < m; k++) assert_true(ref->pixels[k] == 0.0f);
    const int ns[3] = {1, K, LUMIS_LIGHT_SET_MAX_DRAWS};
    for (int c = 0; c < 3; c++)
        for (int given = 0; given < 2; given++) {
            d.lighting.light_set.region_draws = ns[c];
            d.lighting.light_set.regions = given ? rs : NULL;
            int n[K];
            for (int k = 0; k < K; k++) n[k] = -1;
            assert_int_equal(lumis__light_set_allocation(&d, n), LUMIS_OK);
            for (int k = 0; k < K; k++) assert_int_equal(n[k], 0);
            lumis_image *img = NULL;
            assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
            assert_memory_equal(img->pixels, ref->pixels, m * sizeof(float));
            lumis_image_destroy(img);
        }
    lumis_image_destroy(ref);
    lumis_scene_destroy(s);
    lumis_region_sampler_destroy(rs);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* region_draws under the regions lit is refused by lumis_lighting_check and
 * lumis_session_check, before anything is built, when the caller gives the region samplers
 * (the lit count is theirs, O(K)); without them the checks cannot know it (a region's
 * emptiness is the samplers') and the render refuses it once it has made them.  N at the
 * regions lit passes, and so does any N when kinds select no region. */
static void allocated_draws_refused_before_the_render(void **state)
{
    (void)state;
    lumis_envmap *env = studio_map();
    enum { K = 7 };
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(env, "median-cut", K, 0, NULL, NULL, &set), LUMIS_OK);
    lumis_region_sampler *rs = NULL;
    assert_int_equal(lumis_region_sampler_create(env, set, NULL, &rs), LUMIS_OK);
    static const lumis_camera one = {{0, 0, 3}, {0, 0, 0}, {0, 1, 0}, 40.0f, 4, 4};
    tu_sink k;
    tu_sink_init(&k);
    lumis_session_desc sd;
    memset(&sd, 0, sizeof sd);
    lumis_render_desc *d = &sd.render;
    d->camera = &one;
    d->spp = 1;
    d->errors = k.sink;
    d->lighting.env = env;
    d->lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    d->lighting.light_set.set = set;
    d->lighting.light_set.regions = rs;
    d->lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
    d->lighting.light_set.region_draws = K - 1;
    assert_int_equal(lumis_lighting_check(d), LUMIS_ERR_INVALID_ARGUMENT);
    if (!strstr(k.last, "lighting.light_set.region_draws 6: under the 7 regions lit"))
        fail_msg("the message: %s", k.last);
    k.last[0] = '\0';
    assert_int_equal(lumis_session_check(&sd), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(k.last, "lighting.light_set.region_draws"));
    d->lighting.light_set.region_draws = K;
    assert_int_equal(lumis_lighting_check(d), LUMIS_OK);
    assert_int_equal(lumis_session_check(&sd), LUMIS_OK);
    d->lighting.light_set.region_draws = 1;
    d->lighting.light_set.kinds = 1u << LUMIS_LIGHT_ENV_DIRECT; /* none of a median cut's */
    assert_int_equal(lumis_session_check(&sd), LUMIS_OK);
    /* the render makes the samplers: the checks cannot count, the render refuses */
    d->lighting.light_set.kinds = 0;
    d->lighting.light_set.region_draws = K - 1;
    d->lighting.light_set.regions = NULL;
    assert_int_equal(lumis_session_check(&sd), LUMIS_OK);
    lumis_scene *s = one_sphere(0.5f);
    lumis_image *img = NULL;
    k.last[0] = '\0';
    assert_int_equal(lumis_render(s, d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);
    assert_non_null(strstr(k.last, "lighting.light_set.region_draws 6: under the 7 regions lit"));
    /* and one draw in all, the least N: refused the same way (N = 1 is no special case) */
    d->lighting.light_set.region_draws = 1;
    k.last[0] = '\0';
    assert_int_equal(lumis_render(s, d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);
    assert_non_null(strstr(k.last, "lighting.light_set.region_draws 1: under the 7 regions lit"));
    lumis_scene_destroy(s);
    lumis_region_sampler_destroy(rs);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* A glossy sphere (GGX plastic, coloured base) under the coloured map: each checked pixel
 * converges to the integral of f(wo, wi) L(wi) cos over the map, summed here over every map
 * pixel (4 x 4 sub-cells, the BSDF evaluated at each) and averaged over the pixel's
 * footprint (4 x 4 positions), within 4.5 standard errors of `runs` renders, with no shared
 * bias (the sum of the z scores).  Today's stratified mode (draws 0) passes it too, which
 * checks the quadrature. */
static void check_glossy(lumis_image *const *imgs, int runs, const lumis_envmap *env,
                         const lumis_bsdf *m, const char *what)
{
    enum { CELLS = MAP_CELLS };
    static double cell[CELLS][6];
    map_cells(env, cell);
    int checked = 0;
    double zsum[3] = {0, 0, 0};
    for (int y = 2; y < 24; y += 4)
        for (int x = 2; x < 24; x += 4) {
            if (!on_sphere(x, y)) continue;
            double E[3] = {0, 0, 0};
            for (int sub = 0; sub < 16; sub++) {
                double n[3];
                assert_true(sphere_normal(x + (sub % 4 + 0.5) / 4, y + (sub / 4 + 0.5) / 4, n));
                /* the frame: any tangents (the BSDF is isotropic); wo towards the eye */
                double t[3] = {0, 0, 0}, b[3];
                t[fabs(n[0]) < 0.6 ? 0 : 1] = 1;
                double tn = t[0] * n[0] + t[1] * n[1] + t[2] * n[2];
                for (int k = 0; k < 3; k++) t[k] -= tn * n[k];
                double tl = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
                for (int k = 0; k < 3; k++) t[k] /= tl;
                b[0] = n[1] * t[2] - n[2] * t[1];
                b[1] = n[2] * t[0] - n[0] * t[2];
                b[2] = n[0] * t[1] - n[1] * t[0];
                double e[3] = {-n[0], -n[1], 4 - n[2]}; /* to the eye at (0, 0, 4) */
                double el = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
                const lumis_vec3 wo = {(float)((e[0] * t[0] + e[1] * t[1] + e[2] * t[2]) / el),
                                       (float)((e[0] * b[0] + e[1] * b[1] + e[2] * b[2]) / el),
                                       (float)((e[0] * n[0] + e[1] * n[1] + e[2] * n[2]) / el)};
                for (int q = 0; q < CELLS; q++) {
                    const double *w = cell[q];
                    double c = w[0] * n[0] + w[1] * n[1] + w[2] * n[2];
                    if (!(c > 0)) continue;
                    const lumis_vec3 wi = {(float)(w[0] * t[0] + w[1] * t[1] + w[2] * t[2]),
                                           (float)(w[0] * b[0] + w[1] * b[1] + w[2] * b[2]),
                                           (float)c};
                    const lumis_rgb f = lumis_bsdf_eval(m, wo, wi);
                    E[0] += f.r * w[3] * c / 16;
                    E[1] += f.g * w[4] * c / 16;
                    E[2] += f.b * w[5] * c / 16;
                }
            }
            for (int ch = 0; ch < 3; ch++) {
                double sum = 0, sum2 = 0;
                for (int r = 0; r < runs; r++) {
                    double v = imgs[r]->pixels[3 * (y * 24 + x) + ch];
                    sum += v;
                    sum2 += v * v;
                }
                double mean = sum / runs,
                       se = sqrt(fmax(sum2 / runs - mean * mean, 0) / (runs - 1));
                double z = (mean - E[ch]) / fmax(se, 2e-3 * E[ch]);
                if (fabs(z) > 4.5)
                    fail_msg("%s: pixel (%d, %d) channel %d: %g +- %g, exact %g (z = %.2f)", what,
                             x, y, ch, mean, se, E[ch], z);
                zsum[ch] += z;
            }
            checked++;
        }
    assert_true(checked > 10);
    for (int ch = 0; ch < 3; ch++)
        if (fabs(zsum[ch]) > 3.5 * sqrt(checked))
            fail_msg("%s: pixels share a bias in channel %d: sum of z = %.2f over %d pixels", what,
                     ch, zsum[ch], checked);
}

/* Selected draws on a glossy sphere: the BSDF's bound chooses the regions and the BSDF's
 * pdf enters the MIS weights; each pixel converges to the brute-force integral of the GGX
 * plastic's f L cos over the map's pixels, like today's stratified mode (draws 0). */
static void selected_draws_shade_glossy_surfaces_exactly(void **state)
{
    (void)state;
    lumis_envmap *env = studio_map();
    lumis_object o = {0};
    o.type = LUMIS_OBJECT_SPHERE;
    o.radius = 1.0f;
    o.material = (lumis_bsdf){LUMIS_BSDF_GGX_PLASTIC, {0.6f, 0.35f, 0.15f}, {0, 0, 0}, 0.3f, 0.3f};
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(&o, 1, NULL, &s), LUMIS_OK);
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(env, "median-cut", 32, 0, NULL, NULL, &set), LUMIS_OK);
    enum { RUNS = 24 };
    static const struct {
        int draws, power;
    } cases[] = {{0, 0}, {4, 0}, {2, 1}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        lumis_image *imgs[RUNS];
        render_strata(s, env, set, NULL, cases[c].draws, 0, LUMIS_ESTIMATOR_MIS, cases[c].power,
                      LUMIS_SEQUENCE_SOBOL, 0, 32, 700u, RUNS, imgs);
        char what[64];
        snprintf(what, sizeof what, "glossy, draws %d, %s heuristic", cases[c].draws,
                 cases[c].power ? "power" : "balance");
        check_glossy(imgs, RUNS, env, &o.material, what);
        for (int r = 0; r < RUNS; r++) lumis_image_destroy(imgs[r]);
    }
    lumis_light_set_destroy(set);
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

typedef struct region_hits {
    const lumis_region_sampler *rs;
    double *count; /* per region */
    long rays;
} region_hits;

static void count_region(void *user, const float org[3], const float dir[3])
{
    region_hits *h = user;
    (void)org;
    int r = -1;
    lumis_region_sampler_lookup(h->rs, (lumis_vec3){dir[0], dir[1], dir[2]}, &r, NULL);
    if (r >= 0) h->count[r] += 1.0;
    h->rays++;
}

/* How selected draws choose regions.  (1) The probabilities are the documented weights for a
 * Lambertian surface, q_k proportional to Y(P_k) (max(0, n . dir_k) + 0.2 cosmax_k), cosmax_k
 * = max(cos(angle(n, dir_k) - extent_k), 1e-4) (1 inside the cone), computed here from the
 * set's lights, and exactly 0 for a region whose cone lies below the horizon (n . dir_k <=
 * -sin extent_k): such a region is never picked.  (2) The draws
 * follow q: a floor facing the zenith, light sampling alone, N = 4; each shadow ray's region
 * counted against q_k times the share of region k's power above the horizon (the equator is a
 * row boundary of the map, so every pixel is wholly on one side), the draws below it in one
 * more bin: chi-square (the four draws of a vertex are systematic, so their counts vary less
 * than a multinomial's: the test is conservative, and still sees a choice off by a region). */
static void selected_draws_choose_regions_by_their_bound(void **state)
{
    (void)state;
    lumis_envmap *env = studio_map();
    const int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    enum { K = 24 };
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(env, "median-cut", K, 0, NULL, NULL, &set), LUMIS_OK);
    const lumis_light *l = NULL;
    int count = 0;
    assert_int_equal(lumis_light_set_get(set, 0, &l, &count), LUMIS_OK);
    assert_int_equal(count, K);
    lumis_render_desc d = {0};
    d.lighting.env = env;
    d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    d.lighting.light_set.set = set;
    d.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
    d.lighting.light_set.draws = 4;
    const lumis_bsdf lambert = {LUMIS_BSDF_LAMBERT, {0.5f, 0.5f, 0.5f}, {0, 0, 0}, 0, 0};
    const lumis_vec3 zenith = lumis_envmap_uv_to_dir(env, 0.5f, 0.0f);
    const lumis_vec3 normals[4] = {
        zenith, {0.6f, -0.64f, 0.48f}, {-0.8f, 0.0f, 0.6f}, {0.0f, -1.0f, 0.0f}};
    double q[K];
    int below = 0;
    for (int c = 0; c < 4; c++) {
        const lumis_vec3 n = normals[c];
        const lumis_vec3 view = {-n.x, -n.y, -n.z};
        assert_int_equal(lumis__light_set_selection(&d, n, view, &lambert, q), LUMIS_OK);
        double want[K], sum = 0;
        for (int k = 0; k < K; k++) {
            const double cn = l[k].dir.x * n.x + l[k].dir.y * n.y + l[k].dir.z * n.z;
            const double th = acos(fmax(-1.0, fmin(1.0, cn)));
            const double cb = th <= l[k].extent ? 1.0 : cos(th - l[k].extent);
            const double y =
                0.2126 * l[k].power[0] + 0.7152 * l[k].power[1] + 0.0722 * l[k].power[2];
            want[k] = cn <= -sin(l[k].extent) - 1e-4 && l[k].extent < 1.5f
                          ? 0.0
                          : y * (fmax(cn, 0.0) + 0.2 * fmax(cb, 1e-4));
            sum += want[k];
        }
        double qs = 0;
        for (int k = 0; k < K; k++) {
            want[k] /= sum;
            qs += q[k];
            if (want[k] == 0.0) {
                below++;
                if (q[k] != 0.0)
                    fail_msg("normal %d: region %d below the horizon: q %g", c, k, q[k]);
            } else if (fabs(q[k] - want[k]) > 1e-4 * want[k] + 1e-12) {
                fail_msg("normal %d: region %d: q %.9g, the bound gives %.9g", c, k, q[k], want[k]);
            }
        }
        assert_true(fabs(qs - 1.0) < 1e-9);
    }
    assert_true(below >= 8); /* the test saw regions below the horizon */

    /* (2) the draws of a floor facing the zenith */
    lumis_region_sampler *rs = NULL;
    assert_int_equal(lumis_region_sampler_create(env, set, NULL, &rs), LUMIS_OK);
    lumis_object floor_ = {0};
    floor_.type = LUMIS_OBJECT_PLANE;
    floor_.normal = zenith;
    floor_.size = 100.0f;
    floor_.material = lambert;
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(&floor_, 1, NULL, &s), LUMIS_OK);
    const lumis_camera top = {{3 * zenith.x, 3 * zenith.y, 3 * zenith.z},
                              {0, 0, 0},
                              {zenith.y, zenith.z, zenith.x},
                              30.0f,
                              16,
                              16};
    assert_int_equal(lumis__light_set_selection(
                         &d, zenith, (lumis_vec3){-zenith.x, -zenith.y, -zenith.z}, &lambert, q),
                     LUMIS_OK);
    /* each region's share of its power above the horizon (rows 0 .. h/2 - 1) */
    double above[K] = {0}, all[K] = {0};
    int lw = 0, lh = 0;
    const int32_t *labels = lumis_light_set_labels(set, &lw, &lh);
    assert_true(lw == w && lh == h);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const lumis_rgb t = lumis_envmap_texel(env, i, j);
            const double y = (0.2126 * t.r + 0.7152 * t.g + 0.0722 * t.b) *
                             lumis_envmap_pixel_solid_angle(env, j);
            const int r = labels[j * w + i];
            all[r] += y;
            if (j < h / 2) above[r] += y;
        }
    double hits[K + 1] = {0};
    region_hits rh = {rs, hits, 0};
    d.camera = &top;
    d.lighting.light_set.regions = rs;
    d.lighting.estimator = LUMIS_ESTIMATOR_LIGHT;
    d.spp = 64;
    d.seed = 5;
    d.threads = 1;
    d.shadow_ray = count_region;
    d.shadow_ray_user = &rh;
    lumis_image *img = NULL;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
    lumis_image_destroy(img);
    const double draws = 16.0 * 16.0 * 64.0 * 4.0; /* every camera ray meets the floor */
    double expected[K + 1], traced = 0;
    expected[K] = 0;
    for (int k = 0; k < K; k++) {
        const double a = all[k] > 0 ? above[k] / all[k] : 0.0;
        expected[k] = draws * q[k] * a;
        expected[K] += draws * q[k] * (1.0 - a);
        traced += hits[k];
    }
    hits[K] = draws - traced;
    assert_true((double)rh.rays == traced);
    int dof = 0;
    const double p = stat_chi2_test(hits, expected, K + 1, &dof);
    if (p < 1e-4) {
        for (int k = 0; k <= K; k++)
            print_message("bin %d: %g drawn, %g expected\n", k, hits[k], expected[k]);
        fail_msg("region choices against q: p = %g (%d degrees of freedom)", p, dof);
    }
    lumis_scene_destroy(s);
    lumis_region_sampler_destroy(rs);
    lumis_light_set_destroy(set);
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
    /* and with every sequence, path traced (the bounces' dimensions too) */
    for (int q = 0; q < LUMIS_SEQUENCE_COUNT; q++) {
        lumis_render_desc base = {0};
        base.sequence = (lumis_sequence)q;
        base.max_bounces = 2;
        lumis_image *one = render_with(s, env, LUMIS_METHOD_KDTREE, LUMIS_ESTIMATOR_MIS, 4, 7, 1,
                                       &base),
                    *two = render_with(s, env, LUMIS_METHOD_KDTREE, LUMIS_ESTIMATOR_MIS, 4, 7, 2,
                                       &base);
        if (memcmp(one->pixels, two->pixels, sizeof(float) * 24 * 24 * 3) != 0)
            fail_msg("%s: the image depends on the threads",
                     lumis_sequence_name((lumis_sequence)q));
        lumis_image_destroy(one);
        lumis_image_destroy(two);
    }
    /* Light-only, BSDF-only and MIS estimate the same image: compare means over the frame. */
    double means[3];
    const lumis_estimator ests[3] = {LUMIS_ESTIMATOR_MIS, LUMIS_ESTIMATOR_LIGHT,
                                     LUMIS_ESTIMATOR_BSDF};
    /* BSDF sampling of the sun is heavy-tailed: one 256-spp render of it strays by 4 % (with
     * any sequence), so each mean is over 8 seeds. */
    for (int e = 0; e < 3; e++) {
        double sum = 0;
        for (unsigned r = 0; r < 8; r++) {
            lumis_image *img =
                render(s, env, LUMIS_METHOD_INVERSION, ests[e], 256, 9u + 8u * (unsigned)e + r, 0);
            for (int k = 0; k < 24 * 24; k++) sum += img->pixels[3 * k + 1];
            lumis_image_destroy(img);
        }
        means[e] = sum / (24 * 24 * 8);
    }
    for (int e = 1; e < 3; e++)
        if (fabs(means[e] - means[0]) > 0.03 * means[0])
            fail_msg("estimator %d: mean %g vs MIS %g", e, means[e], means[0]);
    /* A light set's strata on the glossy sphere (the BSDF evaluated and its pdf in the MIS
     * weights, not Lambert's shortcut) estimate the same image. */
    {
        lumis_light_set *set = NULL;
        assert_int_equal(lumis_lights_by_name(env, "median-cut", 16, 0, NULL, NULL, &set),
                         LUMIS_OK);
        for (int power = 0; power < 2; power++) {
            lumis_render_desc d = {0};
            d.camera = &cam;
            d.lighting.env = env;
            d.lighting.light_set.set = set;
            d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
            d.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
            d.power_heuristic = power;
            d.spp = 128;
            d.seed = 21;
            lumis_image *img = NULL;
            assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
            double sum = 0;
            for (int k = 0; k < 24 * 24; k++) sum += img->pixels[3 * k + 1];
            if (fabs(sum / (24 * 24) - means[0]) > 0.02 * means[0])
                fail_msg("strata (%s heuristic): mean %g vs MIS %g", power ? "power" : "balance",
                         sum / (24 * 24), means[0]);
            lumis_image_destroy(img);
        }
        lumis_light_set_destroy(set);
    }
    lumis_image_destroy(a);
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* Passes: any split of the samples gives the image of one pass, bit for bit, with every
 * sample sequence (the planned count is the job's desc spp). */
static void passes_do_not_change_the_image(void **state)
{
    (void)state;
    lumis_envmap *env = env_of(tu_image(32, 16, f_const));
    lumis_scene *s = one_sphere(0.5f);
    lumis_sampler_desc sd = {0};
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_sampler_create(env, &sd, &smp), LUMIS_OK);
    for (int q = 0; q < LUMIS_SEQUENCE_COUNT; q++) {
        lumis_render_desc d = {0};
        d.camera = &cam;
        d.lighting.env = env;
        d.lighting.sampler = smp;
        d.spp = 8;
        d.seed = 3;
        d.sequence = (lumis_sequence)q;
        lumis_image *one = NULL;
        assert_int_equal(lumis_render(s, &d, &one, NULL), LUMIS_OK);
        lumis_render_job *job = NULL;
        assert_int_equal(lumis_render_job_create(s, &d, &job), LUMIS_OK);
        const int split[4] = {1, 2, 1, 4};
        for (int k = 0; k < 4; k++) assert_int_equal(lumis_render_job_run(job, split[k]), LUMIS_OK);
        lumis_render_stats st;
        lumis_render_job_stats(job, &st);
        assert_int_equal(st.spp, 8);
        assert_int_equal(st.passes, 4);
        assert_true(st.camera_rays == 24.0 * 24 * 8);
        lumis_image *many = NULL;
        assert_int_equal(lumis_render_job_image(job, &many), LUMIS_OK);
        assert_memory_equal(one->pixels, many->pixels, sizeof(float) * 24 * 24 * 3);
        assert_int_equal(lumis_render_job_run(job, 0), LUMIS_ERR_INVALID_ARGUMENT);
        lumis_render_job_destroy(job);
        lumis_image_destroy(one);
        lumis_image_destroy(many);
    }
    lumis_sampler_destroy(smp);
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* A unit cube's 12 triangles, outward facing. */
static const float cube_v[24] = {-1, -1, -1, 1, -1, -1, 1, 1, -1, -1, 1, -1,
                                 -1, -1, 1,  1, -1, 1,  1, 1, 1,  -1, 1, 1};
static const unsigned cube_i[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                    3, 6, 2, 3, 7, 6, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};

static void set_transform(lumis_object *o, float sx, float sy, float sz, float tx, float ty,
                          float angle_y)
{
    float c = cosf(angle_y), s = sinf(angle_y);
    const float m[12] = {c * sx, 0, s * sz, tx, 0, sy, 0, ty, -s * sx, 0, c * sz, 0};
    memcpy(o->transform, m, sizeof m);
}

/* Instancing: two objects sharing one mesh (Embree instances, normals through the inverse
 * transpose) render as two baked copies do; a mirror transform works; a singular one is
 * refused. */
static void instances_match_baked_copies(void **state)
{
    (void)state;
    lumis_sky_desc sky = {0};
    sky.width = 64;
    lumis_image *map = NULL;
    assert_int_equal(lumis_sky_create(&sky, &map), LUMIS_OK);
    lumis_envmap *env = env_of(map);
    lumis_object inst[3], baked[3];
    memset(inst, 0, sizeof inst);
    for (int k = 0; k < 2; k++) {
        inst[k].type = LUMIS_OBJECT_MESH;
        inst[k].vertices = cube_v;
        inst[k].indices = cube_i;
        inst[k].vertex_count = 8;
        inst[k].triangle_count = 12;
        inst[k].material =
            (lumis_bsdf){LUMIS_BSDF_GGX_PLASTIC, {0.5f, 0.4f, 0.3f}, {0, 0, 0}, 0.3f, 0.3f};
    }
    set_transform(&inst[0], 0.6f, 0.9f, 0.5f, -1.0f, 0.0f, 0.5f);
    set_transform(&inst[1], -0.5f, 0.5f, 0.7f, 1.1f, 0.2f, -0.3f); /* a mirror */
    inst[2].type = LUMIS_OBJECT_PLANE;
    inst[2].center = (lumis_vec3){0, -1, 0};
    inst[2].normal = (lumis_vec3){0, 1, 0};
    inst[2].material = (lumis_bsdf){LUMIS_BSDF_LAMBERT, {0.5f, 0.5f, 0.5f}, {0, 0, 0}, 0, 0};
    float world[2][24];
    memcpy(baked, inst, sizeof inst);
    for (int k = 0; k < 2; k++) {
        const float *m = inst[k].transform;
        for (int v = 0; v < 8; v++)
            for (int r = 0; r < 3; r++)
                world[k][3 * v + r] = m[4 * r] * cube_v[3 * v] + m[4 * r + 1] * cube_v[3 * v + 1] +
                                      m[4 * r + 2] * cube_v[3 * v + 2] + m[4 * r + 3];
        baked[k].vertices = world[k];
        memset(baked[k].transform, 0, sizeof baked[k].transform);
    }
    lumis_scene *si = NULL, *sb = NULL;
    assert_int_equal(lumis_scene_create(inst, 3, NULL, &si), LUMIS_OK);
    assert_int_equal(lumis_scene_create(baked, 3, NULL, &sb), LUMIS_OK);
    lumis_image *a = render(si, env, LUMIS_METHOD_INVERSION, LUMIS_ESTIMATOR_MIS, 16, 5, 0);
    lumis_image *b = render(sb, env, LUMIS_METHOD_INVERSION, LUMIS_ESTIMATOR_MIS, 16, 5, 0);
    /* The same rays and random numbers: equal up to float rounding of the hit points. */
    int far = 0;
    double suma = 0;
    for (int k = 0; k < 24 * 24 * 3; k++) {
        suma += a->pixels[k];
        if (fabsf(a->pixels[k] - b->pixels[k]) > 1e-3f * (fabsf(b->pixels[k]) + 1e-3f)) far++;
    }
    if (far > 24 * 24 * 3 / 100) fail_msg("%d of %d values differ", far, 24 * 24 * 3);
    assert_true(suma > 0.0);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
    lumis_scene_destroy(si);
    lumis_scene_destroy(sb);
    /* A singular transform is refused with a message. */
    tu_sink sink;
    tu_sink_init(&sink);
    set_transform(&inst[1], 0.0f, 0.5f, 0.7f, 1.1f, 0.2f, 0.0f);
    lumis_scene *bad = NULL;
    assert_int_equal(lumis_scene_create(inst, 3, &sink.sink, &bad), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "singular"));
    assert_null(bad);
    lumis_envmap_destroy(env);
}

/* Path tracing in an integrating sphere: a Lambertian sphere of albedo rho, seen from
 * inside, with a polar cap of area fraction f cut away, under a constant map L.  Every
 * point of the inner wall sees every other one, and the view factor from any wall point to
 * any region of the sphere is that region's area fraction, so the wall's radiance is
 * uniform: after D bounces it is rho f L sum_{k=0..D} (rho (1 - f))^k.  The wall is a fine
 * mesh (its facets move the answer by about 1e-4); the test is to 4 standard errors plus
 * 0.3 %. */
static void integrating_sphere(void **state)
{
    (void)state;
    enum { NPHI = 160, NTH = 80, CUT = 20 }; /* hole: the first 20 of 80 rings */
    const double rho = 0.5, Lenv = 2.0;
    static float v[(NTH + 1) * NPHI * 3];
    static unsigned idx[NTH * NPHI * 6];
    for (int j = 0; j <= NTH; j++)
        for (int i = 0; i < NPHI; i++) {
            double th = PI * j / NTH, ph = 2 * PI * i / NPHI;
            float *p = v + 3 * (j * NPHI + i);
            p[0] = (float)(sin(th) * cos(ph));
            p[1] = (float)cos(th);
            p[2] = (float)(sin(th) * sin(ph));
        }
    int nt = 0;
    for (int j = CUT; j < NTH; j++)
        for (int i = 0; i < NPHI; i++) {
            unsigned a = (unsigned)(j * NPHI + i), b = (unsigned)(j * NPHI + (i + 1) % NPHI);
            unsigned c = a + NPHI, d = b + NPHI;
            const unsigned q[6] = {a, b, d, a, d, c};
            memcpy(idx + 3 * nt, q, sizeof q);
            nt += 2;
        }
    /* The hole is the polygon through ring CUT: its area fraction seen from inside is the
     * exact cap's, (1 - cos theta) / 2, to the facets' accuracy. */
    const double f = (1.0 - cos(PI * CUT / NTH)) / 2.0;
    lumis_object o = {0};
    o.type = LUMIS_OBJECT_MESH;
    o.vertices = v;
    o.indices = idx;
    o.vertex_count = (NTH + 1) * NPHI;
    o.triangle_count = nt;
    o.material = (lumis_bsdf){LUMIS_BSDF_LAMBERT, {0.5f, 0.5f, 0.5f}, {0, 0, 0}, 0, 0};
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(&o, 1, NULL, &s), LUMIS_OK);
    lumis_envmap *env = env_of(tu_image(32, 16, f_const));
    lumis_sampler_desc sd = {0};
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_sampler_create(env, &sd, &smp), LUMIS_OK);
    /* From the centre, looking down at the wall below the hole. */
    const lumis_camera inside = {{0, 0.3f, 0}, {0, -1, 0.2f}, {0, 1, 0}, 60.0f, 16, 16};
    /* Every estimator at every depth: with MIS or BSDF sampling the map a continuation sees
     * when it escapes is its vertex's BSDF sample's share (integrator.c), so those paths
     * must count it once, weighed as the direct estimator weighs it; 2 BSDF samples: the
     * first continues the path, the second is a shadow ray. */
    enum { CASES = 10 };
    const int depths[CASES] = {0, 1, 4, 1, 4, 4, 1, 0, 4, 4};
    const int bsdf_samples[CASES] = {1, 1, 1, 1, 1, 1, 1, 1, 2, 2};
    const lumis_estimator ests[CASES] = {
        LUMIS_ESTIMATOR_MIS, LUMIS_ESTIMATOR_LIGHT, LUMIS_ESTIMATOR_BSDF, LUMIS_ESTIMATOR_MIS,
        LUMIS_ESTIMATOR_MIS, LUMIS_ESTIMATOR_LIGHT, LUMIS_ESTIMATOR_BSDF, LUMIS_ESTIMATOR_BSDF,
        LUMIS_ESTIMATOR_MIS, LUMIS_ESTIMATOR_BSDF};
    for (int t = 0; t < CASES; t++) {
        lumis_render_desc d = {0};
        d.camera = &inside;
        d.lighting.env = env;
        d.lighting.sampler = smp;
        d.lighting.estimator = ests[t];
        d.max_bounces = depths[t];
        d.bsdf_samples = bsdf_samples[t];
        d.spp = 256;
        d.seed = 11u + (unsigned)t;
        lumis_image *img = NULL;
        lumis_render_stats st;
        assert_int_equal(lumis_render(s, &d, &img, &st), LUMIS_OK);
        assert_true(depths[t] == 0 ? st.bounce_rays == 0.0 : st.bounce_rays > 0.0);
        double want = 0.0, term = rho * f * Lenv;
        for (int k = 0; k <= depths[t]; k++, term *= rho * (1 - f)) want += term;
        /* Pixels are independent: the spread of their means gives the standard error. */
        double sum = 0, sum2 = 0;
        const int n = 16 * 16;
        for (int k = 0; k < n; k++) {
            double x = img->pixels[3 * k];
            sum += x;
            sum2 += x * x;
        }
        double mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0) / (n - 1));
        if (fabs(mean - want) > 4 * se + 3e-3 * want)
            fail_msg("%d bounces, estimator %d, %d BSDF samples: %g +- %g, exact %g", depths[t],
                     (int)ests[t], bsdf_samples[t], mean, se, want);
        lumis_image_destroy(img);
    }
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
    lumis_scene_destroy(s);
}

static float f_bands(int i, int j, int c)
{
    return (float)(0.2 + 0.1 * ((i * 7 + j * 3) % 5) + 0.3 * c + (j == 1 && i == 5 ? 20.0 : 0.0));
}

/* The light-set kind of the light interface: a Lambertian floor seen from above has the
 * same normal and BSDF at every shading point and nothing occludes it, so each pixel must
 * equal rho/pi sum_k max(0, n . dir_k) power_k over the lights of the set its position
 * selects (lumis_light_set_interleave_index): this checks the interleaving, the cosine,
 * the units of power, every lane of the 16-ray packets and the kind mask. */
static void light_set_lights_each_pixel_with_its_set(void **state)
{
    (void)state;
    lumis_envmap *env = env_of(tu_image(16, 8, f_bands));
    lumis_object o = {0};
    o.type = LUMIS_OBJECT_PLANE;
    o.normal = (lumis_vec3){0, 1, 0};
    o.size = 1000.0f;
    o.material.type = LUMIS_BSDF_LAMBERT;
    o.material.diffuse = (lumis_rgb){0.5f, 0.5f, 0.5f};
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(&o, 1, NULL, &s), LUMIS_OK);
    lumis_median_cut_desc md = {0};
    md.count = 37; /* two full packets and a partial one */
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_median_cut(env, &md, &set), LUMIS_OK);
    const int sets = lumis_light_set_sets(set);
    assert_true(sets == 8);
    const lumis_camera down = {{0, 5, 0}, {0, 0, 0}, {0, 0, -1}, 30.0f, 12, 10};
    for (unsigned kinds = 0; kinds < 2; kinds++) {
        lumis_render_desc d = {0};
        d.camera = &down;
        d.lighting.env = env;
        d.lighting.light_set.set = set;
        d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
        d.lighting.light_set.kinds =
            kinds ? 1u << LUMIS_LIGHT_ENV_DIRECT : 0; /* median cut has none */
        d.spp = 2;
        lumis_image *img = NULL;
        lumis_render_stats st;
        assert_int_equal(lumis_render(s, &d, &img, &st), LUMIS_OK);
        double rays = 0.0;
        for (int y = 0; y < down.height; y++)
            for (int x = 0; x < down.width; x++) {
                const lumis_light *l = NULL;
                int count = 0;
                assert_int_equal(lumis_light_set_get(
                                     set, lumis_light_set_interleave_index(sets, x, y), &l, &count),
                                 LUMIS_OK);
                double want[3] = {0, 0, 0};
                for (int k = 0; k < count && !kinds; k++)
                    if (l[k].dir.y > 0.0f) {
                        rays += 2;
                        for (int ch = 0; ch < 3; ch++)
                            want[ch] += 0.5 / PI * l[k].dir.y * l[k].power[ch];
                    }
                const float *px = img->pixels + 3 * (y * down.width + x);
                for (int ch = 0; ch < 3; ch++)
                    if (fabs(px[ch] - want[ch]) > 2e-5 * want[ch] + 1e-9)
                        fail_msg("pixel (%d, %d) channel %d: %.9g, want %.9g", x, y, ch, px[ch],
                                 want[ch]);
            }
        assert_true(st.shadow_rays == rays);
        lumis_image_destroy(img);
    }
    /* Path tracing is not a light set's: refused. */
    lumis_render_desc d = {0};
    d.lighting.env = env;
    d.lighting.light_set.set = set;
    d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    d.max_bounces = 1;
    lumis_render_job *job = NULL;
    assert_int_equal(lumis_render_job_create(s, &d, &job), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_light_set_destroy(set);
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* A light set on a glossy floor: each pixel is sum_k f(wo, dir_k) (n . dir_k) power_k with
 * the floor's BSDF, not albedo / pi (a GGX conductor has no albedo: the Lambertian shortcut
 * taken for every material rendered it black, and the Lambertian floor above cannot tell).
 * A narrow view from straight above: wo is the same to 1e-4 rad over a pixel's samples. */
static void light_set_shades_glossy_surfaces_with_their_bsdf(void **state)
{
    (void)state;
    lumis_envmap *env = env_of(tu_image(16, 8, f_bands));
    lumis_object o = {0};
    o.type = LUMIS_OBJECT_PLANE;
    o.normal = (lumis_vec3){0, 1, 0};
    o.size = 100.0f;
    o.material = (lumis_bsdf){LUMIS_BSDF_GGX_CONDUCTOR, {0, 0, 0}, {0.9f, 0.6f, 0.3f}, 0.5f, 0.35f};
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(&o, 1, NULL, &s), LUMIS_OK);
    lumis_median_cut_desc md = {0};
    md.count = 21;
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_median_cut(env, &md, &set), LUMIS_OK);
    const int sets = lumis_light_set_sets(set);
    const lumis_camera view = {{1.5f, 5, 0.5f}, {0, 0, 0}, {0, 0, -1}, 0.2f, 8, 6};
    lumis_render_desc d = {0};
    d.camera = &view;
    d.lighting.env = env;
    d.lighting.light_set.set = set;
    d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    d.spp = 2;
    lumis_image *img = NULL;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
    /* the camera's frame, as lumis_render builds it */
    const double e[3] = {1.5, 5, 0.5}, el = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    const double fwd[3] = {-e[0] / el, -e[1] / el, -e[2] / el}, up[3] = {0, 0, -1};
    double r[3] = {fwd[1] * up[2] - fwd[2] * up[1], fwd[2] * up[0] - fwd[0] * up[2],
                   fwd[0] * up[1] - fwd[1] * up[0]};
    const double rl = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    for (int k = 0; k < 3; k++) r[k] /= rl;
    const double u[3] = {r[1] * fwd[2] - r[2] * fwd[1], r[2] * fwd[0] - r[0] * fwd[2],
                         r[0] * fwd[1] - r[1] * fwd[0]};
    const double th = tan(0.5 * 0.2 * PI / 180), aspect = 8.0 / 6.0;
    double total = 0.0;
    for (int y = 0; y < 6; y++)
        for (int x = 0; x < 8; x++) {
            const double sx = (x + 0.5) / 8 * 2 - 1, sy = 1 - (y + 0.5) / 6 * 2;
            double dir[3];
            for (int k = 0; k < 3; k++) dir[k] = fwd[k] + r[k] * sx * th * aspect + u[k] * sy * th;
            const double dl = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
            /* local frame (x, z, y): the material is isotropic in its frame's turn */
            const lumis_vec3 wo = {(float)(-dir[0] / dl), (float)(-dir[2] / dl),
                                   (float)(-dir[1] / dl)};
            const lumis_light *l = NULL;
            int count = 0;
            assert_int_equal(
                lumis_light_set_get(set, lumis_light_set_interleave_index(sets, x, y), &l, &count),
                LUMIS_OK);
            double want[3] = {0, 0, 0};
            for (int k = 0; k < count; k++) {
                if (!(l[k].dir.y > 0.0f)) continue;
                const lumis_vec3 wi = {l[k].dir.x, l[k].dir.z, l[k].dir.y};
                const lumis_rgb f = lumis_bsdf_eval(&o.material, wo, wi);
                want[0] += f.r * l[k].dir.y * l[k].power[0];
                want[1] += f.g * l[k].dir.y * l[k].power[1];
                want[2] += f.b * l[k].dir.y * l[k].power[2];
            }
            const float *px = img->pixels + 3 * (y * 8 + x);
            for (int ch = 0; ch < 3; ch++) {
                total += want[ch];
                if (!(fabs(px[ch] - want[ch]) <= 2e-3 * want[ch] + 1e-9))
                    fail_msg("pixel (%d, %d) channel %d: %.7g, want %.7g", x, y, ch, px[ch],
                             want[ch]);
            }
        }
    assert_true(total > 0.0);
    lumis_image_destroy(img);
    lumis_light_set_destroy(set);
    lumis_scene_destroy(s);
    lumis_envmap_destroy(env);
}

/* What every light kind hands Embree: a shadow packet filled with 0 .. 16 rays over stale
 * bytes (0xff: NaN floats).  The filled lanes answer occluded or not; every idle lane is a
 * valid ray that cannot hit (finite origin, unit direction, tnear = 0 > tfar, valid = 0),
 * since Embree's SSE4.2 and AVX2 kernels check each half of the packet lane by lane (the
 * renders aborted there when idle lanes held whatever the stack held). */
static void packets_hand_embree_initialised_lanes(void **state)
{
    (void)state;
    lumis_scene *s = one_sphere(0.5f);
    RTCScene rtc = (RTCScene)lumis__scene_rtc(s);
    const float o[3] = {0.0f, 0.0f, 4.0f}, to[3] = {0.0f, 0.0f, -1.0f}, away[3] = {0, 0, 1};
    for (int n = 0; n <= LUMIS__PACKET; n++) {
        lumis__packet p;
        memset(&p, 0xff, sizeof p);
        p.n = 0;
        for (int k = 0; k < n; k++) lumis__packet_push(&p, o, k % 2 ? away : to, INFINITY);
        lumis__packet_trace(rtc, NULL, NULL, &p);
        assert_int_equal(p.n, n);
        for (int k = 0; k < n; k++)
            if ((p.r.tfar[k] < 0.0f) != (k % 2 == 0))
                fail_msg("%d rays: lane %d answered %s", n, k,
                         p.r.tfar[k] < 0.0f ? "occluded" : "free");
        for (int k = n; k < LUMIS__PACKET; k++) {
            const float dx = p.r.dir_x[k], dy = p.r.dir_y[k], dz = p.r.dir_z[k];
            if (!(p.valid[k] == 0 && isfinite(p.r.org_x[k]) && isfinite(p.r.org_y[k]) &&
                  isfinite(p.r.org_z[k]) && fabsf(dx * dx + dy * dy + dz * dz - 1.0f) < 1e-6f &&
                  p.r.tnear[k] == 0.0f && p.r.tfar[k] < p.r.tnear[k] && p.r.time[k] == 0.0f &&
                  p.r.flags[k] == 0))
                fail_msg("%d rays: idle lane %d handed to Embree uninitialised", n, k);
        }
    }
    lumis_scene_destroy(s);
}

/* The bunny-plane scene (triangles) lit by a 37-light median-cut set (two full shadow
 * packets and a partial one), rendered with Embree's kernels pinned through
 * LUMIS_EMBREE_CONFIG, on the calling thread. */
static lumis_image *scene_light_set(const char *config)
{
    if (config)
        setenv("LUMIS_EMBREE_CONFIG", config, 1);
    else
        unsetenv("LUMIS_EMBREE_CONFIG");
    lumis_scene_file *f = NULL;
    assert_int_equal(lumis_scene_builtin("bunny-plane", NULL, &f), LUMIS_OK);
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(f->objects, f->object_count, NULL, &s), LUMIS_OK);
    lumis_envmap *env = env_of(tu_image(32, 16, f_bands));
    lumis_median_cut_desc md = {0};
    md.count = 37;
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_median_cut(env, &md, &set), LUMIS_OK);
    lumis_camera c = f->camera;
    c.width = 40;
    c.height = 30;
    lumis_render_desc d = {0};
    d.camera = &c;
    d.lighting.env = env;
    d.lighting.light_set.set = set;
    d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    d.spp = 2;
    d.threads = 1;
    lumis_image *img = NULL;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
    lumis_scene_destroy(s);
    lumis_scene_file_destroy(f);
    return img;
}

/* Embree's SSE4.2 and AVX2 kernels split a 16-ray packet and check every lane of each half
 * (Debian's build asserts it), so a light set must render on each of them; whether an idle,
 * uninitialised lane trips that check depends on what the stack held, so the guard that
 * always fails is valgrind's (.ci/run, memcheck) and ctest's runs of this program with each
 * kernel forced (tests/CMakeLists.txt).  Here: each kernel renders the same image up to the
 * last bits of the primary hits (the kernels order their float operations differently,
 * with or without FMA), and an isa Embree would ignore is refused by name. */
static void every_embree_kernel_renders_light_sets(void **state)
{
    (void)state;
    const char *outer = getenv("LUMIS_EMBREE_CONFIG"); /* the kernels CI pinned, if any */
    char saved[256] = "";
    if (outer) snprintf(saved, sizeof saved, "%s", outer);
    lumis_image *best = scene_light_set(NULL);
    const char *const kernels[] = {"isa=sse4.2", "isa=avx2", "threads=1,isa=avx2"};
    for (size_t k = 0; k < sizeof kernels / sizeof *kernels; k++) {
        lumis_image *img = scene_light_set(kernels[k]);
        double err = 0.0, ref = 0.0;
        for (int p = 0; p < 3 * img->width * img->height; p++) {
            err += fabs((double)img->pixels[p] - best->pixels[p]);
            ref += fabs((double)best->pixels[p]);
        }
        if (!(err <= 1e-5 * ref)) fail_msg("%s: relative L1 difference %g", kernels[k], err / ref);
        lumis_image_destroy(img);
    }
    lumis_image_destroy(best);
    tu_sink sink;
    tu_sink_init(&sink);
    setenv("LUMIS_EMBREE_CONFIG", "isa=avx-2", 1);
    lumis_object o = {0};
    o.type = LUMIS_OBJECT_SPHERE;
    o.radius = 1.0f;
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(&o, 1, &sink.sink, &s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(s);
    assert_non_null(strstr(sink.last, "isa=avx-2"));
    if (outer)
        setenv("LUMIS_EMBREE_CONFIG", saved, 1);
    else
        unsetenv("LUMIS_EMBREE_CONFIG");
}

/* A synthetic G-buffer: depth 1 left of column edge, 2 from it on; one normal and albedo. */
static lumis_gbuffer *step_gbuffer(int w, int h, int edge)
{
    lumis_gbuffer *g = calloc(1, sizeof *g);
    float *mem = calloc(7 * (size_t)w * (size_t)h, sizeof(float));
    assert_true(g && mem);
    g->width = w;
    g->height = h;
    g->normal = mem;
    g->albedo = mem + 3 * w * h;
    g->depth = mem + 6 * w * h;
    for (int p = 0; p < w * h; p++) {
        g->normal[3 * p + 1] = 1.0f;
        g->albedo[3 * p] = g->albedo[3 * p + 1] = g->albedo[3 * p + 2] = 0.5f;
        g->depth[p] = p % w < edge ? 1.0f : 2.0f;
    }
    return g;
}

/* Joint-bilateral upsampling: a constant image stays constant, and a step in depth stays a
 * step (every output pixel takes its own side's value, next to the edge too), which plain
 * bilinear or Gaussian upsampling would blur. */
static void upsampling_keeps_constants_and_depth_edges(void **state)
{
    (void)state;
    lumis_gbuffer *lo = step_gbuffer(8, 6, 4), *hi = step_gbuffer(16, 12, 8);
    lumis_image *low = NULL, *up = NULL;
    assert_int_equal(lumis_image_create(8, 6, &low), LUMIS_OK);
    for (int p = 0; p < 8 * 6; p++)
        for (int c = 0; c < 3; c++) low->pixels[3 * p + c] = 0.25f + 0.5f * (float)c;
    assert_int_equal(lumis_joint_bilateral_upsample(low, lo, hi, NULL, &up), LUMIS_OK);
    assert_true(up->width == 16 && up->height == 12);
    for (int p = 0; p < 16 * 12; p++)
        for (int c = 0; c < 3; c++)
            assert_float_equal(up->pixels[3 * p + c], 0.25f + 0.5f * (float)c, 1e-6);
    lumis_image_destroy(up);
    for (int p = 0; p < 8 * 6; p++)
        for (int c = 0; c < 3; c++) low->pixels[3 * p + c] = p % 8 < 4 ? 1.0f : 5.0f;
    assert_int_equal(lumis_joint_bilateral_upsample(low, lo, hi, NULL, &up), LUMIS_OK);
    for (int p = 0; p < 16 * 12; p++)
        if (fabsf(up->pixels[3 * p] - (p % 16 < 8 ? 1.0f : 5.0f)) > 1e-5f)
            fail_msg("pixel (%d, %d): %g across a depth step", p % 16, p / 16, up->pixels[3 * p]);
    lumis_image_destroy(up);
    /* Without the depth term (a huge sigma) the step blurs: the test can fail. */
    lumis_upsample_desc ud = {0};
    ud.sigma_depth = 1e6f;
    assert_int_equal(lumis_joint_bilateral_upsample(low, lo, hi, &ud, &up), LUMIS_OK);
    assert_true(up->pixels[3 * 7] > 1.01f);
    lumis_image_destroy(up);
    /* x and y alike: a ramp in y upsamples to the transpose of the same ramp in x (on one
     * flat G-buffer, the spatial term alone decides), and in between its samples, strictly
     * between their values (a spatial term that used x for y fails both). */
    {
        lumis_gbuffer *flo = step_gbuffer(8, 8, 8), *fhi = step_gbuffer(16, 16, 16);
        lumis_image *rx = NULL, *ry = NULL, *ux = NULL, *uy = NULL;
        assert_int_equal(lumis_image_create(8, 8, &rx), LUMIS_OK);
        assert_int_equal(lumis_image_create(8, 8, &ry), LUMIS_OK);
        for (int y = 0; y < 8; y++)
            for (int x = 0; x < 8; x++)
                for (int ch = 0; ch < 3; ch++) {
                    rx->pixels[3 * (y * 8 + x) + ch] = (float)(x * x + 1);
                    ry->pixels[3 * (y * 8 + x) + ch] = (float)(y * y + 1);
                }
        assert_int_equal(lumis_joint_bilateral_upsample(rx, flo, fhi, NULL, &ux), LUMIS_OK);
        assert_int_equal(lumis_joint_bilateral_upsample(ry, flo, fhi, NULL, &uy), LUMIS_OK);
        for (int y = 0; y < 16; y++)
            for (int x = 0; x < 16; x++) {
                const float a = ux->pixels[3 * (y * 16 + x)], b = uy->pixels[3 * (x * 16 + y)];
                if (!(fabsf(a - b) <= 1e-5f * fabsf(a)))
                    fail_msg("ramp in x at (%d, %d): %g; ramp in y at (%d, %d): %g", x, y, a, y, x,
                             b);
            }
        /* between low rows 3 and 4 (values 10 and 17): high rows 7 and 8 */
        for (int y = 7; y <= 8; y++) {
            const float v = uy->pixels[3 * (y * 16 + 5)];
            if (!(v > 10.0f && v < 17.0f)) fail_msg("row %d: %g not between 10 and 17", y, v);
        }
        lumis_image_destroy(rx);
        lumis_image_destroy(ry);
        lumis_image_destroy(ux);
        lumis_image_destroy(uy);
        lumis_gbuffer_destroy(flo);
        lumis_gbuffer_destroy(fhi);
    }
    /* Mismatched sizes are refused. */
    tu_sink sink;
    tu_sink_init(&sink);
    ud.errors = sink.sink;
    assert_int_equal(lumis_joint_bilateral_upsample(low, hi, hi, &ud, &up),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(up);
    assert_non_null(strstr(sink.last, "differ"));
    lumis_image_destroy(low);
    lumis_gbuffer_destroy(lo);
    lumis_gbuffer_destroy(hi);
    /* A rendered G-buffer: the sphere's pixels see it, the corners see the background. */
    lumis_scene *s = one_sphere(0.5f);
    lumis_gbuffer *g = NULL;
    assert_int_equal(lumis_render_gbuffer(s, &cam, NULL, &g), LUMIS_OK);
    assert_true(g->width == 24 && g->height == 24);
    assert_true(isinf(g->depth[0]) && g->normal[0] == 0.0f);
    const int c = 12 * 24 + 12;
    assert_float_equal(g->depth[c], 3.0015f, 1e-4); /* eye at z = 4, the sphere's front near 1 */
    assert_float_equal(g->normal[3 * c + 2], 0.99888f, 1e-4);
    assert_float_equal(g->albedo[3 * c], 0.5f, 0.0);
    lumis_gbuffer_destroy(g);
    lumis_scene_destroy(s);
}

/* Objects and background do not mix: a low-resolution image whose right half is the
 * background (infinite depth) upsamples to exactly its two values, next to the edge too.
 * The built-in scenes' meshes have the heights they are given and stand where they are
 * put.  A scene file's alpha_y and a reflectance of exactly 1 are kept, and rotate_deg is
 * a rotation (R = Rz Ry Rx): orthonormal, each axis turning the right way. */
static void upsampling_builtins_and_scene_values(void **state)
{
    (void)state;
    lumis_gbuffer *lo = step_gbuffer(8, 6, 4), *hi = step_gbuffer(16, 12, 8);
    for (int p = 0; p < 8 * 6; p++)
        if (p % 8 >= 4) lo->depth[p] = INFINITY;
    for (int p = 0; p < 16 * 12; p++)
        if (p % 16 >= 8) hi->depth[p] = INFINITY;
    lumis_image *low = NULL, *up = NULL;
    assert_int_equal(lumis_image_create(8, 6, &low), LUMIS_OK);
    for (int p = 0; p < 8 * 6; p++)
        for (int c = 0; c < 3; c++) low->pixels[3 * p + c] = p % 8 < 4 ? 1.0f : 5.0f;
    assert_int_equal(lumis_joint_bilateral_upsample(low, lo, hi, NULL, &up), LUMIS_OK);
    for (int p = 0; p < 16 * 12; p++)
        if (!(fabsf(up->pixels[3 * p] - (p % 16 < 8 ? 1.0f : 5.0f)) <= 1e-5f))
            fail_msg("pixel (%d, %d): %g across the object's edge", p % 16, p / 16,
                     up->pixels[3 * p]);
    lumis_image_destroy(up);
    lumis_image_destroy(low);
    lumis_gbuffer_destroy(lo);
    lumis_gbuffer_destroy(hi);

    static const struct {
        const char *scene;
        int object, centred;
        float height, x, z;
    } meshes[] = {{"bunny-plane", 0, 0, 1.1f, 0, 0},
                  {"wu-diffuse", 0, 1, 1.0f, -1.15f, -0.1f},
                  {"wu-diffuse", 1, 1, 0.95f, 0.1f, -0.35f}};
    for (size_t k = 0; k < sizeof meshes / sizeof *meshes; k++) {
        lumis_scene_file *f = NULL;
        assert_int_equal(lumis_scene_builtin(meshes[k].scene, NULL, &f), LUMIS_OK);
        const lumis_object *o = &f->objects[meshes[k].object];
        assert_int_equal(o->type, LUMIS_OBJECT_MESH);
        const float *m = o->transform;
        float top = -INFINITY, lb[3] = {INFINITY, INFINITY, INFINITY},
              hb[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int v = 0; v < o->vertex_count; v++) {
            const float *p = o->vertices + 3 * v;
            top = fmaxf(top, m[4] * p[0] + m[5] * p[1] + m[6] * p[2] + m[7]);
            for (int a = 0; a < 3; a++) {
                lb[a] = fminf(lb[a], p[a]);
                hb[a] = fmaxf(hb[a], p[a]);
            }
        }
        if (fabsf(top - meshes[k].height) > 1e-4f)
            fail_msg("%s, object %d: top at y = %g, height %g", meshes[k].scene, meshes[k].object,
                     top, meshes[k].height);
        if (meshes[k].centred) { /* the middle of its bounds' foot lands on (x, z) */
            const float c[3] = {0.5f * (lb[0] + hb[0]), lb[1], 0.5f * (lb[2] + hb[2])};
            const float wx = m[0] * c[0] + m[1] * c[1] + m[2] * c[2] + m[3],
                        wz = m[8] * c[0] + m[9] * c[1] + m[10] * c[2] + m[11];
            if (fabsf(wx - meshes[k].x) > 1e-4f || fabsf(wz - meshes[k].z) > 1e-4f)
                fail_msg("%s, object %d: foot centre at (%g, %g), want (%g, %g)", meshes[k].scene,
                         meshes[k].object, wx, wz, meshes[k].x, meshes[k].z);
        }
        lumis_scene_file_destroy(f);
    }

    static const char text[] =
        "{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
        "\"material\": {\"type\": \"ward\", \"alpha_x\": 0.2, \"alpha_y\": 0.5}}, "
        "{\"type\": \"sphere\", \"center\": [3, 0, 0], \"radius\": 1, \"material\": {\"type\": "
        "\"lambert\", \"albedo\": [1, 1, 1]}}]}";
    lumis_scene_file *f = NULL;
    assert_int_equal(lumis__scene_file_parse(text, sizeof text - 1, "t.json", "", 0, NULL, &f),
                     LUMIS_OK);
    assert_int_equal(f->object_count, 2);
    assert_float_equal(f->objects[0].material.alpha_x, 0.2f, 1e-7);
    assert_float_equal(f->objects[0].material.alpha_y, 0.5f, 1e-7);
    assert_true(f->objects[1].material.diffuse.r == 1.0f);
    lumis_scene_file_destroy(f);

    const float axes[3][3] = {{0, 0, 90}, {90, 0, 0}, {0, 90, 0}};
    const int from[3] = {0, 1, 2}, to[3] = {1, 2, 0}; /* x -> y, y -> z, z -> x */
    for (int a = 0; a < 3; a++) {
        double R[9];
        lumis__rotation_deg(axes[a], R);
        for (int i = 0; i < 3; i++) /* column from[a]: the image of that axis */
            assert_true(fabs(R[3 * i + from[a]] - (i == to[a] ? 1.0 : 0.0)) < 1e-12);
    }
    const float any[3] = {30, -40, 125};
    double R[9];
    lumis__rotation_deg(any, R);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double dot = 0.0;
            for (int k = 0; k < 3; k++) dot += R[3 * k + i] * R[3 * k + j];
            assert_true(fabs(dot - (i == j ? 1.0 : 0.0)) < 1e-12);
        }
}

/* The solid angle of the rectangle x = d (d > 0), y in [y0, y1], z in [z0, z1], seen from
 * the origin: the signed sum over its corners of atan(y z / (d r)), r the corner's distance. */
static double rect_solid_angle(double d, double y0, double y1, double z0, double z1)
{
    const double y[2] = {y0, y1}, z[2] = {z0, z1};
    double om = 0.0;
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 2; b++)
            om += (a == b ? 1.0 : -1.0) *
                  atan(y[a] * z[b] / (d * sqrt(d * d + y[a] * y[a] + z[b] * z[b])));
    return om;
}

/* The window scene's room is closed but for its window (builtin.c, window_room: 0.8 x 0.6 in
 * the wall x = 2, sill at 1.2, z from -0.4 to 0.4): from points inside, the share of
 * directions whose ray escapes is the window's solid angle over 4 pi (a gap at an edge, a
 * missing wall or a window of another size would change it), and every ray that hits, hits
 * inside the room.  Directions: a Fibonacci sphere of 40000 (low discrepancy, so the
 * tolerance is a few hundred-thousandths of the sphere plus the window's rim). */
static void window_room_is_closed(void **state)
{
    (void)state;
    lumis_scene_file *f = NULL;
    assert_int_equal(lumis_scene_builtin("window", NULL, &f), LUMIS_OK);
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(f->objects, f->object_count, NULL, &s), LUMIS_OK);
    static const double pts[3][3] = {{0.0, 1.25, 0.0}, {-1.5, 0.3, 1.8}, {1.0, 2.2, -2.0}};
    const int n = 40000;
    for (int k = 0; k < 3; k++) {
        const double *o = pts[k];
        const double om =
            rect_solid_angle(2.0 - o[0], 1.2 - o[1], 1.8 - o[1], -0.4 - o[2], 0.4 - o[2]);
        int escaped = 0;
        for (int i = 0; i < n; i++) {
            const double z = 1.0 - (2.0 * i + 1.0) / n, r = sqrt(1.0 - z * z),
                         phi = 2.399963229728653 * i;
            const v3 d = {r * cos(phi), r * sin(phi), z};
            hit h;
            if (!intersect(s, (v3){o[0], o[1], o[2]}, d, &h)) {
                escaped++;
                continue;
            }
            if (!(fabs(h.p.x) <= 2.011 && h.p.y >= -1e-3 && h.p.y <= 2.511 && fabs(h.p.z) <= 2.511))
                fail_msg("from (%g, %g, %g) a ray hit (%g, %g, %g), outside the room", o[0], o[1],
                         o[2], h.p.x, h.p.y, h.p.z);
        }
        const double share = (double)escaped / n, expect = om / (4.0 * PI);
        /* the rim: directions within a thousandth of a radian of its edges */
        const double tol = 2e-4 + 0.02 * expect;
        if (!(fabs(share - expect) <= tol))
            fail_msg("from (%g, %g, %g): %.5f of the directions escape, the window subtends %.5f",
                     o[0], o[1], o[2], share, expect);
    }
    lumis_scene_destroy(s);
    lumis_scene_file_destroy(f);
}

/* The scenes made for the automatic estimator's suite (glossy-only, window, open-sky): each
 * renders finite, non-black pixels under a uniform map (the share of pixels lit: most of
 * them; in the window's room, the surfaces that see the window), and equals a reference in
 * its expectation: inversion + MIS against BSDF sampling alone with an independent seed, on
 * a map of bands with a bright spot.  Their difference, pixel by pixel, has mean zero: the
 * mean over the image of the difference is within 4 standard errors of 0 (its spread
 * measured from the pixels). */
static void new_builtin_scenes_render(void **state)
{
    (void)state;
    static const struct {
        const char *name;
        double lit; /* the least share of pixels lit by the uniform map */
    } scenes[] = {{"glossy-only", 0.99}, {"window", 0.6}, {"open-sky", 0.99}};
    lumis_envmap *flat = env_of(tu_image(32, 16, f_const));
    lumis_envmap *bands = env_of(tu_image(32, 16, f_bands));
    for (int k = 0; k < 3; k++) {
        lumis_scene_file *f = NULL;
        assert_int_equal(lumis_scene_builtin(scenes[k].name, NULL, &f), LUMIS_OK);
        lumis_scene *s = NULL;
        assert_int_equal(lumis_scene_create(f->objects, f->object_count, NULL, &s), LUMIS_OK);
        lumis_camera c = f->camera;
        c.width = 32;
        c.height = 24;
        lumis_image *img[3] = {NULL, NULL, NULL};
        for (int r = 0; r < 3; r++) {
            lumis_sampler_desc sd = {0};
            sd.method = LUMIS_METHOD_INVERSION;
            lumis_sampler *smp = NULL;
            const lumis_envmap *env = r == 0 ? flat : bands;
            assert_int_equal(lumis_sampler_create(env, &sd, &smp), LUMIS_OK);
            lumis_render_desc d = {0};
            d.camera = &c;
            d.lighting.env = env;
            d.lighting.sampler = smp;
            d.lighting.estimator = r == 2 ? LUMIS_ESTIMATOR_BSDF : LUMIS_ESTIMATOR_MIS;
            d.spp = r == 0 ? 256 : r == 1 ? 64 : 256;
            d.seed = 7 + (unsigned long long)r;
            d.threads = 2;
            assert_int_equal(lumis_render(s, &d, &img[r], NULL), LUMIS_OK);
            lumis_sampler_destroy(smp);
        }
        const int np = c.width * c.height;
        int lit = 0;
        double sum = 0.0, sum2 = 0.0, mean_ref = 0.0;
        for (int i = 0; i < np; i++) {
            const float *px = img[0]->pixels + 3 * i;
            for (int ch = 0; ch < 3; ch++)
                if (!isfinite(px[ch]) || px[ch] < 0.0f)
                    fail_msg("%s: pixel %d channel %d is %g", scenes[k].name, i, ch, px[ch]);
            lit += px[0] + px[1] + px[2] > 0.0f;
            double dl = 0.0;
            for (int ch = 0; ch < 3; ch++) {
                const float a = img[1]->pixels[3 * i + ch], b = img[2]->pixels[3 * i + ch];
                if (!isfinite(a) || !isfinite(b)) fail_msg("%s: pixel %d", scenes[k].name, i);
                dl += (double)a - (double)b;
                mean_ref += b / (3.0 * np);
            }
            sum += dl;
            sum2 += dl * dl;
        }
        if (!((double)lit >= scenes[k].lit * np))
            fail_msg("%s: %d of %d pixels lit by a uniform map", scenes[k].name, lit, np);
        assert_true(mean_ref > 0.0);
        const double mean = sum / np, var = (sum2 - np * mean * mean) / (np - 1.0),
                     z = mean / sqrt(var / np);
        if (!(fabs(z) < 4.0))
            fail_msg("%s: MIS and BSDF sampling differ by %g per pixel (z = %.2f; the reference's "
                     "mean %g)",
                     scenes[k].name, mean / 3.0, z, mean_ref);
        for (int r = 0; r < 3; r++) lumis_image_destroy(img[r]);
        lumis_scene_destroy(s);
        lumis_scene_file_destroy(f);
    }
    lumis_envmap_destroy(flat);
    lumis_envmap_destroy(bands);
}

/* Every built-in scene builds, with its objects standing on (not sinking into or floating
 * above) the ground: the lowest vertex of each mesh is at y = 0 to float rounding. */
static void builtin_scenes_build(void **state)
{
    (void)state;
    /* which built-in scenes bring their own luminaires: the headlight ones, and no other */
    assert_int_equal(lumis_scene_builtin_has_luminaires("headlight"), 1);
    assert_int_equal(lumis_scene_builtin_has_luminaires("headlight-close"), 1);
    assert_int_equal(lumis_scene_builtin_has_luminaires("spheres"), 0);
    assert_int_equal(lumis_scene_builtin_has_luminaires("no-such-scene"), 0);
    int n = 0;
    for (const char *const *name = lumis_scene_builtin_names(); *name; name++, n++) {
        lumis_scene_file *f = NULL;
        assert_int_equal(lumis_scene_builtin(*name, NULL, &f), LUMIS_OK);
        lumis_scene *s = NULL;
        assert_int_equal(lumis_scene_create(f->objects, f->object_count, NULL, &s), LUMIS_OK);
        for (int k = 0; k < f->object_count; k++) {
            const lumis_object *o = &f->objects[k];
            if (o->type != LUMIS_OBJECT_MESH) continue;
            const float *m = o->transform;
            float lo = INFINITY;
            for (int v = 0; v < o->vertex_count; v++) {
                const float *p = o->vertices + 3 * v;
                lo = fminf(lo, m[4] * p[0] + m[5] * p[1] + m[6] * p[2] + m[7]);
            }
            if (fabsf(lo) > 1e-4f) fail_msg("%s: object %d's lowest point at y = %g", *name, k, lo);
        }
        lumis_scene_destroy(s);
        lumis_scene_file_destroy(f);
    }
    assert_int_equal(n, 12);
    lumis_scene_file *f = NULL;
    /* ward-aniso: its one sphere in the middle of the view (the camera's centre ray passes
     * within a tenth of its radius of its centre) */
    assert_int_equal(lumis_scene_builtin("ward-aniso", NULL, &f), LUMIS_OK);
    assert_int_equal(f->object_count, 1);
    {
        const lumis_camera *c = &f->camera;
        const lumis_object *o = &f->objects[0];
        const double e[3] = {c->eye.x, c->eye.y, c->eye.z},
                     v[3] = {c->look_at.x - e[0], c->look_at.y - e[1], c->look_at.z - e[2]},
                     q[3] = {o->center.x - e[0], o->center.y - e[1], o->center.z - e[2]};
        const double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2],
                     t = (q[0] * v[0] + q[1] * v[1] + q[2] * v[2]) / vv;
        double d2 = 0.0;
        for (int a = 0; a < 3; a++) d2 += (q[a] - t * v[a]) * (q[a] - t * v[a]);
        if (!(t > 0.0 && sqrt(d2) < 0.1 * o->radius))
            fail_msg("ward-aniso: the centre ray passes %g from the sphere's centre", sqrt(d2));
    }
    lumis_scene_file_destroy(f);
    assert_int_equal(lumis_scene_builtin("wu-mixed", NULL, &f), LUMIS_OK);
    assert_int_equal(f->object_count, 5); /* bunny, Suzanne, two spheres, the ground */
    assert_int_equal(f->luminaire_count, 0);
    lumis_scene_file_destroy(f);
    /* glossy-only: every surface, the ground too, glossy GGX (no diffuse part), at four
     * roughnesses */
    assert_int_equal(lumis_scene_builtin("glossy-only", NULL, &f), LUMIS_OK);
    assert_int_equal(f->object_count, 4);
    for (int k = 0; k < f->object_count; k++) {
        const lumis_bsdf *b = &f->objects[k].material;
        assert_int_equal(b->type, LUMIS_BSDF_GGX_GLOSSY);
        for (int j = 0; j < k; j++) assert_true(f->objects[j].material.alpha_x != b->alpha_x);
    }
    lumis_scene_file_destroy(f);
    /* open-sky: a ground and objects on it, nothing above them (every object's top under 1
     * unit, the camera above it all) */
    assert_int_equal(lumis_scene_builtin("open-sky", NULL, &f), LUMIS_OK);
    assert_int_equal(f->object_count, 5);
    for (int k = 0; k < f->object_count; k++) {
        const lumis_object *o = &f->objects[k];
        if (o->type == LUMIS_OBJECT_SPHERE) assert_true(o->center.y + o->radius <= 1.0f);
        if (o->type == LUMIS_OBJECT_PLANE) assert_true(o->normal.y == 1.0f && o->center.y == 0.0f);
        if (o->type != LUMIS_OBJECT_MESH) continue;
        const float *m = o->transform;
        for (int v = 0; v < o->vertex_count; v++) {
            const float *q = o->vertices + 3 * v;
            assert_true(m[4] * q[0] + m[5] * q[1] + m[6] * q[2] + m[7] <= 1.0f);
        }
    }
    assert_true(f->camera.eye.y > 1.0f);
    lumis_scene_file_destroy(f);
    /* The headlight lights its scene by itself: a lit floor, and black where rays escape. */
    assert_int_equal(lumis_scene_builtin("headlight", NULL, &f), LUMIS_OK);
    assert_int_equal(f->luminaire_count, 1);
    /* Its layout (render.h, builtin.c): the lamp 0.7 m above the floor, in millimetres, aimed
     * 5 degrees down, with the bunny and the ball in its beam: at their depth its axis
     * passes between them. */
    {
        const lumis_rigid *pl = &f->luminaires[0].placement;
        const lumis_object *floor_ = NULL, *ball = NULL, *bunny = NULL;
        for (int k = 0; k < f->object_count; k++) {
            const lumis_object *o = &f->objects[k];
            if (o->type == LUMIS_OBJECT_PLANE && o->normal.y == 1.0f) floor_ = o;
            if (o->type == LUMIS_OBJECT_SPHERE) ball = o;
            if (o->type == LUMIS_OBJECT_MESH) bunny = o;
        }
        assert_true(floor_ && ball && bunny);
        assert_true(fabs(pl->t[1] - floor_->center.y - 0.7) < 1e-9);
        assert_true(f->luminaires[0].scale == 0.001);
        const double ax[3] = {pl->r[2], pl->r[5], pl->r[8]}; /* local +z, the beam */
        assert_true(fabs(ax[1] + sin(5.0 * PI / 180.0)) < 1e-9 && ax[2] < 0.0);
        const float *m = bunny->transform;
        double bx = 0.0;
        for (int v = 0; v < bunny->vertex_count; v++) {
            const float *p = bunny->vertices + 3 * v;
            bx += (m[0] * p[0] + m[1] * p[1] + m[2] * p[2] + m[3]) / bunny->vertex_count;
        }
        const double z = ball->center.z, x = pl->t[0] + ax[0] * (z - pl->t[2]) / ax[2];
        if (!(x > fmin(bx, ball->center.x) && x < fmax(bx, ball->center.x)))
            fail_msg("headlight: the beam's axis at x = %g, the bunny at %g, the ball at %g", x, bx,
                     (double)ball->center.x);
    }
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(f->objects, f->object_count, NULL, &s), LUMIS_OK);
    lumis_luminaire_lighting ll = {0};
    ll.instances = f->luminaires;
    ll.count = f->luminaire_count;
    ll.budget = 8;
    lumis_camera cam = f->camera;
    cam.width = 32;
    cam.height = 20;
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.lighting.luminaires = &ll;
    d.lighting.kind = LUMIS_LIGHTING_LUMINAIRES;
    d.spp = 1;
    lumis_image *img = NULL;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
    int lit = 0;
    for (int k = 0; k < 32 * 20; k++) lit += img->pixels[3 * k + 1] > 0.0f;
    assert_true(lit > 32 * 20 / 4);
    lumis_image_destroy(img);
    lumis_scene_destroy(s);
    lumis_scene_file_destroy(f);
}

/* A scene file's map is read by the reader, through lumis-io: a procedural spec or a file
 * beside the scene; skipped on request; a missing map fails the read and names the file. */
static void scene_file_reads_its_map(void **state)
{
    (void)state;
    tu_sink sink;
    tu_sink_init(&sink);
    static const char with_sky[] =
        "{\"environment\": {\"map\": \"sky:16x8\"}, \"objects\": [{\"type\": \"sphere\", "
        "\"center\": [0, 0, 0], \"radius\": 1, \"material\": {\"type\": \"lambert\"}}]}";
    tu_write_file(tu_path("sky-scene.json"), with_sky, sizeof with_sky - 1);
    lumis_scene_read_options so = {0};
    so.errors = sink.sink;
    lumis_scene_file *f = NULL;
    assert_int_equal(lumis_scene_file_read(tu_path("sky-scene.json"), &so, &f), LUMIS_OK);
    assert_non_null(f->env_image);
    assert_true(f->env_image->width == 16 && f->env_image->height == 8);
    lumis_scene_file_destroy(f);
    so.skip_env_map = 1;
    assert_int_equal(lumis_scene_file_read(tu_path("sky-scene.json"), &so, &f), LUMIS_OK);
    assert_null(f->env_image);
    assert_string_equal(f->env_map, "sky:16x8");
    lumis_scene_file_destroy(f);
    /* A file beside the scene, named relative to it. */
    lumis_image *img = tu_image(8, 4, f_const);
    assert_int_equal(lumis_image_write(tu_path("beside.pfm"), img, NULL), LUMIS_OK);
    lumis_image_destroy(img);
    static const char beside[] = "{\"environment\": {\"map\": \"beside.pfm\"}, \"objects\": []}";
    tu_write_file(tu_path("beside-scene.json"), beside, sizeof beside - 1);
    so.skip_env_map = 0;
    assert_int_equal(lumis_scene_file_read(tu_path("beside-scene.json"), &so, &f), LUMIS_OK);
    assert_true(f->env_image && f->env_image->width == 8 && f->env_info.format == LUMIS_FORMAT_PFM);
    lumis_scene_file_destroy(f);
    static const char missing[] = "{\"environment\": {\"map\": \"missing.exr\"}, \"objects\": []}";
    tu_write_file(tu_path("missing-scene.json"), missing, sizeof missing - 1);
    assert_int_equal(lumis_scene_file_read(tu_path("missing-scene.json"), &so, &f), LUMIS_ERR_OPEN);
    assert_null(f);
    assert_non_null(strstr(sink.last, "missing.exr"));
}

/* Scene files are read strictly: a misspelt or unknown key, a key given twice, text after
 * the closing brace, a fractional width, or a NaN / huge mesh vertex each used to be
 * ignored or to change the scene without a word.  Each is now an error that names the
 * JSON path (and the nearest known key). */
/* A scene file's text and the message its refusal must hold. */
typedef struct scene_refusal {
    const char *text, *msg;
} scene_refusal;

/* Each text refused (not LUMIS_OK, no output) with its message, as "s.json", files not read. */
static void expect_scene_refusals(const scene_refusal *cases, size_t n)
{
    for (size_t k = 0; k < n; k++) {
        tu_sink sink;
        tu_sink_init(&sink);
        lumis_scene_file *f = (lumis_scene_file *)1;
        const lumis_status st = lumis__scene_file_parse(cases[k].text, strlen(cases[k].text),
                                                        "s.json", "", 0, &sink.sink, &f);
        if (st == LUMIS_OK || f != NULL || !strstr(sink.last, cases[k].msg))
            fail_msg("case %zu: status %d, message \"%s\", want \"%s\"", k, (int)st, sink.last,
                     cases[k].msg);
    }
}

static void scene_files_are_strict(void **state)
{
    (void)state;
    static const char ok[] =
        "{\"camera\": {\"width\": 24, \"height\": 16}, \"objects\": [{\"type\": \"sphere\", "
        "\"center\": [0, 0, 0], \"radius\": 1, \"material\": {\"type\": \"lambert\", \"albedo\": "
        "[0.5, 0.5, 0.5]}}]}";
    static const scene_refusal cases[] = {
        {"{\"objects\": [], \"lumnaires\": []}", "did you mean \"luminaires\""},
        {"{\"objects\": [], \"frobnicate\": 1}", "\"frobnicate\": unknown key (known:"},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, "
         "\"material\": {\"type\": \"lambert\", \"albedo \": [1,1,1]}}]}",
         "objects[0].material.albedo \": unknown key (did you mean \"albedo\""},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, "
         "\"material\": {\"type\": \"conductor\", \"specular\": [1,1,1]}}]}",
         "material.specular\": unknown key"},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, "
         "\"material\": {\"type\": \"plastic\", \"f0\": [1,1,1]}}]}",
         "material.f0\": unknown key"},
        {"{\"objects\": [], \"luminaires\": [{\"file\": \"preset:small\", \"intensty\": 2}]}",
         "did you mean \"intensity\""},
        {"{\"objects\": [], \"camera\": {\"width\": 24, \"width\": 32}}",
         "camera.width: given twice"},
        {"{\"objects\": []} trailing", "text after the scene's closing brace"},
        {"{\"objects\": [], \"camera\": {\"width\": 24.5}}", "camera.width: expected a whole"},
        {"{\"objects\": [], \"camera\": {\"eye\": [1e300, 0, 0]}}",
         "camera.eye: expected an array of 3 numbers within [-1e30, 1e30]"},
        {"{\"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,1,0], "
         "\"sise\": 3, \"material\": {\"type\": \"lambert\"}}]}",
         "did you mean \"size\""},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, "
         "\"material\": {\"type\": \"ward\", \"alpha_x\": 0.0007}}]}",
         "material.alpha_x"}, /* below the 1e-3 the BSDFs are specified down to */
    };
    /* each value of the wrong kind or range, at every level, refused by its path */
#define SPHERE_WITH(mat)                                                                           \
    "{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1, \"material\": " mat \
    "}]}"
#define MESH_WITH(keys)                                                                            \
    "{\"objects\": [{\"type\": \"mesh\", \"file\": \"m.obj\", " keys                               \
    "\"material\": {\"type\": \"lambert\"}}]}"
#define LUMINAIRE(body) "{\"objects\": [], \"luminaires\": [" body "]}"
#define FIXTURE(body)   "{\"objects\": [], \"photometric\": [" body "]}"
    static const scene_refusal refusals[] = {
        {"[1, 2]", "s.json: (top level): expected an object"},
        {"{\"objects\": [", "s.json:1: malformed JSON"},
        {"{\"objects\": []}\n\n  x", "s.json:3: text after the scene's closing brace"},
        {"{\"objects\": {}}", "objects: expected an array of objects"},
        {"{\"objects\": [], \"camera\": 5}", "camera: expected an object"},
        {"{\"objects\": [], \"camera\": {\"eye\": [1, 2]}}", "camera.eye: expected an array of 3"},
        {"{\"objects\": [], \"camera\": {\"look_at\": [0, \"a\", 0]}}",
         "camera.look_at: expected an array of 3 numbers within"},
        {"{\"objects\": [], \"camera\": {\"up\": 1}}", "camera.up: expected an array of 3"},
        {"{\"objects\": [], \"camera\": {\"fov_deg\": 180}}",
         "camera.fov_deg: expected a number in [0.001, 179]"},
        {"{\"objects\": [], \"environment\": []}", "environment: expected an object"},
        {"{\"objects\": [], \"environment\": {\"map\": 3}}",
         "environment.map: expected a file name or sky/studio spec"},
        {"{\"objects\": [], \"environment\": {\"rotation_deg\": \"x\"}}",
         "environment.rotation_deg: expected a number"},
        {"{\"objects\": [], \"environment\": {\"scale\": -1}}",
         "environment.scale: expected a number in [0, 1e+30]"},
        {"{\"objects\": [3]}", "objects[0]: expected an object"},
        {"{\"objects\": [{\"type\": 3}]}", "objects[0].type: expected a string: sphere, plane"},
        {"{\"objects\": [{\"type\": \"cube\"}]}",
         "objects[0].type: expected sphere, plane or mesh"},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0]}]}",
         "objects[0].radius: expected a positive number (missing)"},
        {"{\"objects\": [{\"type\": \"sphere\", \"radius\": 1}]}",
         "objects[0].center: expected an array of 3 numbers (missing)"},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 0}]}",
         "objects[0].radius: expected a number in [1e-06, 1e+09]"},
        {"{\"objects\": [{\"type\": \"sphere\", \"center\": [0,0,0], \"radius\": 1}]}",
         "objects[0].material: expected a material object (missing)"},
        {SPHERE_WITH("5"), "objects[0].material: expected a material object"},
        {SPHERE_WITH("{\"type\": 1}"), "objects[0].material.type: expected a string: lambert"},
        {SPHERE_WITH("{\"type\": \"velvet\"}"),
         "objects[0].material.type: expected lambert, ward, conductor, plastic or glossy"},
        {SPHERE_WITH("{\"type\": \"lambert\", \"albedo\": [2, 0, 0]}"),
         "objects[0].material.albedo: expected reflectances in [0, 1]"},
        {SPHERE_WITH("{\"type\": \"lambert\", \"albedo\": [0, -0.1, 0]}"),
         "objects[0].material.albedo: expected reflectances in [0, 1]"},
        {SPHERE_WITH("{\"type\": \"plastic\", \"diffuse\": [0.5, 0.5, 1.5]}"),
         "objects[0].material.diffuse: expected reflectances in [0, 1]"},
        {SPHERE_WITH("{\"type\": \"ward\", \"specular\": [0.5, 0.5]}"),
         "objects[0].material.specular: expected an array of 3 numbers"},
        {SPHERE_WITH("{\"type\": \"glossy\", \"color\": [1, 1, 3]}"),
         "objects[0].material.color: expected reflectances in [0, 1]"},
        {SPHERE_WITH("{\"type\": \"ggx\", \"alpha\": 2}"),
         "objects[0].material.alpha: expected a number in [0.001, 1]"},
        {SPHERE_WITH("{\"type\": \"conductor\", \"f0\": [1, 1, 1], \"alpha_x\": \"a\"}"),
         "objects[0].material.alpha_x: expected a number"},
        {SPHERE_WITH("{\"type\": \"ward\", \"alpha_y\": 5}"),
         "objects[0].material.alpha_y: expected a number in [0.001, 1]"},
        {"{\"objects\": [{\"type\": \"plane\", \"normal\": [0,1,0]}]}",
         "objects[0].point: expected an array of 3 numbers (missing)"},
        {"{\"objects\": [{\"type\": \"plane\", \"point\": [0,0,0]}]}",
         "objects[0].normal: expected an array of 3 numbers (missing)"},
        {"{\"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,0,0]}]}",
         "objects[0].normal: expected a non-zero vector"},
        {"{\"objects\": [{\"type\": \"plane\", \"point\": [0,0,0], \"normal\": [0,1,0], "
         "\"size\": 0}]}",
         "objects[0].size: expected a number in [1e-06, 1e+09]"},
        {"{\"objects\": [{\"type\": \"mesh\", \"file\": \"\"}]}",
         "objects[0].file: expected a mesh file name"},
        {"{\"objects\": [{\"type\": \"mesh\", \"file\": 3}]}",
         "objects[0].file: expected a mesh file name"},
        {MESH_WITH("\"transform\": {}, \"instances\": [{}], "),
         "objects[0]: expected either \"transform\" or \"instances\", not both"},
        {MESH_WITH("\"instances\": [], "),
         "objects[0].instances: expected a non-empty array of transforms"},
        {MESH_WITH("\"instances\": {}, "),
         "objects[0].instances: expected a non-empty array of transforms"},
        {MESH_WITH("\"transform\": 3, "),
         "objects[0].transform: expected an object with translate, rotate_deg, scale"},
        {MESH_WITH("\"transform\": {\"scale\": 0}, "),
         "objects[0].transform.scale: expected a non-zero finite scale"},
        {MESH_WITH("\"transform\": {\"scale\": [1, 0, 1]}, "),
         "objects[0].transform.scale: expected a non-zero finite scale"},
        {MESH_WITH("\"transform\": {\"scale\": [1e30, 1e30, 1e30]}, "),
         "objects[0].transform.scale: expected a non-zero finite scale"},
        {MESH_WITH("\"transform\": {\"scale\": \"big\"}, "),
         "objects[0].transform.scale: expected an array of 3 numbers"},
        {MESH_WITH("\"transform\": {\"translate\": [1]}, "),
         "objects[0].transform.translate: expected an array of 3 numbers"},
        {MESH_WITH("\"transform\": {\"rotate_deg\": \"x\"}, "),
         "objects[0].transform.rotate_deg: expected an array of 3 numbers"},
        {MESH_WITH(""), "objects[0].file: mesh files are not loaded here"},
        {"{\"objects\": [], \"luminaires\": 3}", "luminaires: expected an array of luminaires"},
        {LUMINAIRE("3"), "luminaires[0]: expected an object with file, transform, intensity"},
        {LUMINAIRE("{\"file\": \"\"}"), "luminaires[0].file: expected a luminaire manifest"},
        {LUMINAIRE("{\"file\": \"preset:car\", \"transform\": 3}"),
         "luminaires[0].transform: expected an object with translate, rotate_deg, scale"},
        {LUMINAIRE("{\"file\": \"preset:car\", \"transform\": {\"sclae\": 2}}"),
         "luminaires[0].transform.sclae\": unknown key (did you mean \"scale\""},
        {LUMINAIRE("{\"file\": \"preset:car\", \"transform\": {\"translate\": \"x\"}}"),
         "luminaires[0].transform.translate: expected an array of 3 numbers"},
        {LUMINAIRE("{\"file\": \"preset:car\", \"transform\": {\"rotate_deg\": [1, 2]}}"),
         "luminaires[0].transform.rotate_deg: expected an array of 3 numbers"},
        {LUMINAIRE("{\"file\": \"preset:car\", \"transform\": {\"scale\": [1, 1, 1]}}"),
         "luminaires[0].transform.scale: expected a positive number (a luminaire scales "
         "uniformly"},
        {LUMINAIRE("{\"file\": \"preset:car\", \"transform\": {\"scale\": 0}}"),
         "luminaires[0].transform.scale: expected a number in [1e-12, 1e+12]"},
        {LUMINAIRE("{\"file\": \"preset:car\", \"intensity\": -1}"),
         "luminaires[0].intensity: expected a number in [0, 1e+30]"},
        {"{\"objects\": [], \"photometric\": 3}",
         "photometric: expected an array of photometric fixtures"},
        {"{\"objects\": [], \"photometric\": []}", "photometric: expected at least one fixture"},
        {FIXTURE("3"), "photometric[0]: expected an object with file, position"},
        {FIXTURE("{\"file\": \"\"}"), "photometric[0].file: expected a photometric file"},
        {FIXTURE("{\"file\": \"a.ies\"}"),
         "photometric[0].position: expected an array of 3 numbers (missing)"},
        {FIXTURE("{\"file\": \"a.ies\", \"position\": [0,2,0], \"aim\": [0]}"),
         "photometric[0].aim: expected an array of 3 numbers"},
        {FIXTURE("{\"file\": \"a.ies\", \"position\": [0,2,0], \"aim\": [0,2,0]}"),
         "photometric[0].aim: expected a point other than the position"},
        {FIXTURE("{\"file\": \"a.ies\", \"position\": [0,2,0], \"up\": [1,0,0], \"c0\": [1,0,0]}"),
         "photometric[0].c0: expected up or c0, not both"},
        {FIXTURE("{\"file\": \"a.ies\", \"position\": [0,2,0], \"up\": \"x\"}"),
         "photometric[0].up: expected an array of 3 numbers"},
        {FIXTURE("{\"file\": \"a.ies\", \"position\": [0,2,0], \"c0\": [0,-1,0]}"),
         "photometric[0].c0: expected a direction not along the aim"},
        {FIXTURE("{\"file\": \"a.ies\", \"position\": [0,2,0], \"roll_deg\": 1e9}"),
         "photometric[0].roll_deg: expected a number in [-36000, 36000]"},
        {FIXTURE("{\"file\": \"a.ies\", \"position\": [0,2,0], \"multiplier\": -1}"),
         "photometric[0].multiplier: expected a number in [0, 1e+30]"},
        {FIXTURE("{\"file\": \"a.ies\", \"position\": [0,2,0], \"multiplier\": 0}"),
         "photometric[0].multiplier: expected a number > 0"},
        {FIXTURE("{\"file\": \"a.ies\", \"position\": [0,2,0], \"area\": 1}"),
         "photometric[0].area: expected true or false"},
    };
#undef SPHERE_WITH
#undef MESH_WITH
#undef LUMINAIRE
#undef FIXTURE
    lumis_scene_file *f = NULL;
    assert_int_equal(lumis__scene_file_parse(ok, sizeof ok - 1, "ok.json", "", 0, NULL, &f),
                     LUMIS_OK);
    assert_int_equal(f->camera.width, 24);
    lumis_scene_file_destroy(f);
    expect_scene_refusals(cases, sizeof cases / sizeof *cases);
    expect_scene_refusals(refusals, sizeof refusals / sizeof *refusals);
    /* no file, no output, a folder: refused, the folder said */
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_scene_read_options so = {0};
    so.errors = sink.sink;
    assert_int_equal(lumis_scene_file_read(NULL, &so, &f), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_scene_file_read("s.json", &so, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    f = (lumis_scene_file *)1;
    assert_int_not_equal(lumis_scene_file_read(tu_tmpdir(), &so, &f), LUMIS_OK);
    assert_null(f);
    assert_non_null(strstr(sink.last, tu_tmpdir()));
    f = (lumis_scene_file *)1;
    assert_int_equal(lumis__scene_file_parse(NULL, 1, "s.json", "", 0, NULL, &f),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis__scene_file_parse(ok, sizeof ok - 1, NULL, "", 0, NULL, &f),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis__scene_file_parse(ok, sizeof ok - 1, "s.json", NULL, 0, NULL, &f),
                     LUMIS_ERR_INVALID_ARGUMENT);
    /* A luminaire file that cannot be read, with no error sink: refused, no message */
    static const char nolum[] = "{\"objects\": [], \"luminaires\": [{\"file\": "
                                "\"no-such-luminaire.json\"}]}";
    f = (lumis_scene_file *)1;
    assert_int_not_equal(
        lumis__scene_file_parse(nolum, sizeof nolum - 1, "s.json", "", 1, NULL, &f), LUMIS_OK);
    assert_null(f);
    /* A mesh with a vertex past float's range (infinite once read) or past 1e30: refused,
     * with the vertex (assimp's OBJ reader takes "nan" for 0, so NaN cannot come this way). */
    const char *const objs[] = {"v 0 0 0\nv 1 0 0\nv 0 -1e35 0\nf 1 2 3\n",
                                "v 0 0 0\nv 1 0 0\nv 0 1e39 0\nf 1 2 3\n"};
    for (int k = 0; k < 2; k++) {
        tu_write_file(tu_path("badv.obj"), objs[k], strlen(objs[k]));
        static const char mesh[] = "{\"objects\": [{\"type\": \"mesh\", \"file\": \"badv.obj\", "
                                   "\"material\": {\"type\": \"lambert\"}}]}";
        tu_write_file(tu_path("badv.json"), mesh, sizeof mesh - 1);
        tu_sink sink;
        tu_sink_init(&sink);
        lumis_scene_read_options so = {0};
        so.errors = sink.sink;
        f = NULL;
        const lumis_status st = lumis_scene_file_read(tu_path("badv.json"), &so, &f);
        if (st == LUMIS_OK || !strstr(sink.last, "must be finite and at most 1e30"))
            fail_msg("mesh %d: status %d, \"%s\"", k, (int)st, sink.last);
        lumis_scene_file_destroy(f);
    }
}

/* A 2 x 2 luminaire of 2 x 2 grey images, for a scene file's "preset:" entries. */
static lumis_status tiny_preset(void *user, const char *spec, lumis_luminaire **out)
{
    (void)user, (void)spec;
    return tu_tiny_luminaire(out);
}

/* A scene file's defaults and refusals, each as render.h and docs/render.md give them: a
 * Ward material without "specular" gets 0.3 grey (and 0.1 diffuse); an environment
 * without "scale" has scale 1; a luminaire keeps the path it was read from; a transform
 * with an unknown key and more than 4096 photometric fixtures are refused by name. */
static void scene_file_defaults_and_refusals(void **state)
{
    (void)state;
    static const char ward[] =
        "{\"environment\": {\"map\": \"sky:16x8\"}, \"objects\": [{\"type\": \"sphere\", "
        "\"center\": [0, 0, 0], \"radius\": 1, \"material\": {\"type\": \"ward\"}}]}";
    lumis_scene_file *f = NULL;
    assert_int_equal(lumis__scene_file_parse(ward, sizeof ward - 1, "w.json", "", 0, NULL, &f),
                     LUMIS_OK);
    const lumis_bsdf *b = &f->objects[0].material;
    assert_int_equal(b->type, LUMIS_BSDF_WARD);
    assert_true(b->specular.r == 0.3f && b->specular.g == 0.3f && b->specular.b == 0.3f);
    assert_true(b->diffuse.r == 0.1f && b->diffuse.g == 0.1f && b->diffuse.b == 0.1f);
    assert_true(f->env_scale == 1.0f && f->env_rotation_deg == 0.0f);
    lumis_scene_file_destroy(f);

    /* glossy (Cycles' Glossy BSDF): "color" is its constant colour, "f0" is refused */
    static const char glossy[] =
        "{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
        "\"material\": {\"type\": \"glossy\", \"color\": [0.8, 0.6, 0.4], \"alpha\": 0.09}}]}";
    assert_int_equal(lumis__scene_file_parse(glossy, sizeof glossy - 1, "g.json", "", 0, NULL, &f),
                     LUMIS_OK);
    b = &f->objects[0].material;
    assert_int_equal(b->type, LUMIS_BSDF_GGX_GLOSSY);
    assert_true(b->specular.r == 0.8f && b->specular.g == 0.6f && b->specular.b == 0.4f);
    assert_true(b->diffuse.r == 0.0f && b->alpha_x == 0.09f && b->alpha_y == 0.09f);
    lumis_scene_file_destroy(f);
    static const char glossy_f0[] =
        "{\"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
        "\"material\": {\"type\": \"glossy\", \"f0\": [1, 1, 1]}}]}";
    assert_int_equal(
        lumis__scene_file_parse(glossy_f0, sizeof glossy_f0 - 1, "g.json", "", 0, NULL, &f),
        LUMIS_ERR_BAD_HEADER);

    /* a luminaire keeps its path ("preset:small", loaded by the caller's loader) */
    static const char lum[] =
        "{\"objects\": [], \"luminaires\": [{\"file\": \"preset:small\", \"intensity\": 2}]}";
    tu_write_file(tu_path("lum-scene.json"), lum, sizeof lum - 1);
    lumis_scene_read_options so = {0};
    so.load_preset = tiny_preset;
    assert_int_equal(lumis_scene_file_read(tu_path("lum-scene.json"), &so, &f), LUMIS_OK);
    assert_int_equal(f->luminaire_count, 1);
    assert_true(f->luminaires[0].intensity == 2.0f);
    const char *lp = lumis_scene_file_luminaire_path(f, 0);
    assert_non_null(lp);
    assert_string_equal(lp, "preset:small");
    assert_null(lumis_scene_file_luminaire_path(f, 1));
    lumis_scene_file_destroy(f);

    /* an unknown key in a mesh's transform */
    static const char tri[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    tu_write_file(tu_path("tri.obj"), tri, sizeof tri - 1);
    static const char shear[] = "{\"objects\": [{\"type\": \"mesh\", \"file\": \"tri.obj\", "
                                "\"transform\": {\"shear\": 1}, \"material\": {\"type\": "
                                "\"lambert\"}}]}";
    tu_write_file(tu_path("shear.json"), shear, sizeof shear - 1);
    tu_sink sink;
    tu_sink_init(&sink);
    so.errors = sink.sink;
    f = (lumis_scene_file *)1;
    const lumis_status sst = lumis_scene_file_read(tu_path("shear.json"), &so, &f);
    if (sst == LUMIS_OK || f != NULL ||
        !strstr(sink.last, "objects[0].transform.shear\": unknown key"))
        fail_msg("shear: status %d, \"%s\"", (int)sst, sink.last);

    /* 4097 fixtures: refused as too many (not for what the first of them is) */
    const size_t cap = 64 + 4097 * 3;
    char *many = malloc(cap);
    assert_non_null(many);
    size_t n = (size_t)snprintf(many, cap, "{\"objects\": [], \"photometric\": [");
    for (int k = 0; k < 4097; k++) n += (size_t)snprintf(many + n, cap - n, k ? ",{}" : "{}");
    n += (size_t)snprintf(many + n, cap - n, "]}");
    tu_sink_init(&sink);
    f = (lumis_scene_file *)1;
    const lumis_status mst = lumis__scene_file_parse(many, n, "many.json", "", 0, &sink.sink, &f);
    if (mst == LUMIS_OK || f != NULL || !strstr(sink.last, "photometric") ||
        !strstr(sink.last, "at most 4096 fixtures"))
        fail_msg("4097 fixtures: status %d, \"%s\"", (int)mst, sink.last);
    free(many);
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
    d.lighting.env = env;
    d.lighting.estimator = LUMIS_ESTIMATOR_BSDF;
    d.errors = sink.sink;
    lumis_image *img = (lumis_image *)1;
    assert_int_equal(lumis_render(ok, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);
    assert_non_null(strstr(sink.last, "parallel"));
    lumis_scene_destroy(ok);
    lumis_envmap_destroy(env);
}

/* The render session gives what its parts give: with a sample count and no light set the
 * image of lumis_render, bit for bit; with a light set by name and K the image of that set
 * (lumis_lights_by_name) rendered by lumis_render; with Wu's method and F = 2 the full
 * layer plus the upsampled low one.  A budget is spent (prep and render reported, K chosen
 * by the pilots), and bad requests are refused. */
/* Oracle: arithmetic on the budget.  A timed render starts only passes that end within its
 * budget (a tenth of a pass of slack), at most doubling the samples; with a cap, one sample a
 * pass until the cap or until less than three quarters of one fits. */
static void timed_passes_end_within_the_budget(void **state)
{
    (void)state;
    /* issue 35: one stratified sample took 1.23 s of a 2 s budget; the second pass was run */
    assert_int_equal(lumis__timed_next_pass(1.23, 2.0 - 1.23, 1, 0), 0);
    assert_int_equal(lumis__timed_next_pass(1.0, 0.91, 1, 0), 1);    /* all but fits: run */
    assert_int_equal(lumis__timed_next_pass(1.0, 0.89, 1, 0), 0);    /* a tenth short: not */
    assert_int_equal(lumis__timed_next_pass(0.01, 10.0, 8, 0), 8);   /* at most doubling */
    assert_int_equal(lumis__timed_next_pass(0.01, 0.057, 64, 0), 5); /* floor(5.7 + 0.1) */
    assert_int_equal(lumis__timed_next_pass(0.01, -0.5, 64, 0), 0);  /* past it already */
    assert_int_equal(lumis__timed_next_pass(0.0, 1.0, 3, 0), 3);     /* no time yet: double */
    assert_int_equal(lumis__timed_next_pass(0.01, 1e9, 1 << 24, 0), 0);
    /* cap: one a pass while three quarters of one fits and the cap is not reached */
    assert_int_equal(lumis__timed_next_pass(1.0, 0.76, 2, 4), 1);
    assert_int_equal(lumis__timed_next_pass(1.0, 0.74, 2, 4), 0);
    assert_int_equal(lumis__timed_next_pass(0.1, 100.0, 4, 4), 0);
    assert_int_equal(lumis__timed_next_pass(0.0, 1.0, 3, 4), 1);
}

/* Oracle: arithmetic on the pilots.  The prediction is piecewise linear through them, and no
 * segment may fall or be flatter than a tenth of the first pilot's cost per light: timing
 * noise that makes 64 lights look cheaper than 4 must not make them look free. */
static void pilots_predict_with_a_floor_on_the_slope(void **state)
{
    (void)state;
    const int k[3] = {4, 64, 256};
    const double per[3] = {0.25, 0.125, 1.0}, once[3] = {0, 0, 0};
    /* t = (1, 0.5, 4) at 4 spp; the floor slope 0.1 * 1 / 4: t1 = 1 + 0.025 * 60 = 2.5 */
    assert_true(fabs(lumis__pilots_predict(k, per, once, 3, 64, 4) - 2.5) < 1e-12);
    assert_true(fabs(lumis__pilots_predict(k, per, once, 3, 4, 4) - 1.0) < 1e-12);
    /* the second segment is clamped too: 4 at 256 rises to 2.5 + 0.025 * 192 = 7.3, and
     * halfway along it, at 160, the prediction is 4.9 */
    assert_true(fabs(lumis__pilots_predict(k, per, once, 3, 160, 4) - 4.9) < 1e-12);
    /* below the first pilot the first segment extended, 1 - 0.025 * 2 = 0.95 (falling no
     * faster than K would allow 0.5); one pilot scales linearly beyond it */
    assert_true(fabs(lumis__pilots_predict(k, per, once, 3, 2, 4) - 0.95) < 1e-12);
    assert_true(fabs(lumis__pilots_predict(k, per, once, 1, 8, 4) - 2.0) < 1e-12);
}

/* A map of w x h pixels, each channel `base` (R a little more than B: coloured) plus `peak`
 * in one pixel near the top (a compact source: 0 for none). */
static lumis_envmap *gradient_map(int w, int h, float base, float peak)
{
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(w, h, &img), LUMIS_OK);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            float *p = img->pixels + 3 * ((size_t)y * w + x);
            const float g = base * (1.0f + 0.5f * (float)(h - y) / h);
            p[0] = 1.2f * g;
            p[1] = g;
            p[2] = 0.8f * g;
        }
    float *q = img->pixels + 3 * ((size_t)(h / 5) * w + w / 3);
    q[0] += peak;
    q[1] += peak;
    q[2] += peak;
    return env_of(img);
}

/* Candidate c of the automatic estimator rendered by hand, as session_auto.c makes it: the
 * map with MIS through the caller's sampler; median cut K as strata; the image sun (found at
 * a 0.5 share) split off, the caller's sampler method on the residual or strata of it. */
static lumis_image *auto_by_hand(const lumis_scene *s, const lumis_render_desc *rd,
                                 const lumis_auto_candidate *c)
{
    lumis_render_desc d = *rd;
    const lumis_envmap *map = d.lighting.env;
    lumis_sun sun;
    lumis_envmap *res = NULL;
    lumis_sun_sampler *ss = NULL;
    lumis_sampler *smp = NULL;
    lumis_light_set *set = NULL;
    lumis_region_sampler *rs = NULL;
    if (c->sun) {
        lumis_sun_desc sd = {0};
        sd.min_share = 0.5;
        assert_int_equal(lumis_sun_find(map, &sd, &sun, &res), LUMIS_OK);
        assert_true(sun.found);
        assert_int_equal(lumis_sun_sampler_create(map, &sun, NULL, &ss), LUMIS_OK);
        d.lighting.sun.sun = &sun;
        d.lighting.sun.residual = res;
        d.lighting.sun.sampler = ss;
        map = res;
        lumis_sampler_desc sdesc = {0};
        sdesc.method = lumis_sampler_get_method(rd->lighting.sampler);
        assert_int_equal(lumis_sampler_create(res, &sdesc, &smp), LUMIS_OK);
        d.lighting.sampler = smp;
    }
    if (c->lights_k) {
        assert_int_equal(lumis_lights_by_name(map, "median-cut", c->lights_k, 0, NULL, NULL, &set),
                         LUMIS_OK);
        assert_int_equal(lumis_region_sampler_create(map, set, NULL, &rs), LUMIS_OK);
        d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
        d.lighting.sampler = NULL;
        d.lighting.light_set.set = set;
        d.lighting.light_set.regions = rs;
        d.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
    }
    lumis_image *img = NULL;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
    lumis_region_sampler_destroy(rs);
    lumis_light_set_destroy(set);
    lumis_sampler_destroy(smp);
    lumis_sun_sampler_destroy(ss);
    lumis_envmap_destroy(res);
    return img;
}

/* The automatic estimator: the session's image is, bit for bit, the image of the candidate
 * it reports it chose, rendered by hand, and the choice is the least relMSE x seconds of the
 * candidates it measured (with auto_pilot_spp, all of them: the sun's two only on the map
 * with a dominating compact source).  Against a uniform "sampler" of a map with a compact
 * bright source the pilots see MIS's variance at one sample some 60x the strata's, and MIS
 * is not chosen.  Refused, naming the field, wherever it cannot choose. */
static void auto_estimator_renders_what_it_chose(void **state)
{
    (void)state;
    lumis_scene *s = one_sphere(0.7f);
    const size_t bytes = 24 * 24 * 3 * sizeof(float);
    for (int map = 0; map < 2; map++) {
        /* smooth, sampled by inversion; a compact bright source, sampled uniformly */
        lumis_envmap *env = gradient_map(63, 31, 0.5f, map ? 2e3f : 0.0f);
        lumis_sampler_desc sdesc = {0};
        sdesc.method = map ? LUMIS_METHOD_UNIFORM : LUMIS_METHOD_INVERSION;
        lumis_sampler *smp = NULL;
        assert_int_equal(lumis_sampler_create(env, &sdesc, &smp), LUMIS_OK);
        lumis_session_desc sess = {0};
        sess.render.camera = &cam;
        sess.render.lighting.env = env;
        sess.render.lighting.sampler = smp;
        sess.render.spp = 4;
        sess.render.seed = 5;
        sess.render.threads = 1;
        sess.auto_estimator = LUMIS_AUTO_PILOTS;
        sess.auto_pilot_spp = 16; /* every pilot, their errors from the seed alone */
        lumis_session_result r;
        lumis_image *a = NULL, *b = NULL;
        assert_int_equal(lumis_render_session(s, &sess, &a, &r), LUMIS_OK);
        assert_int_equal(r.auto_count, LUMIS_AUTO_CANDIDATES);
        assert_int_equal(r.auto_prior, 0);
        assert_int_equal(r.auto_sun.found, map);
        const lumis_auto_candidate *c = r.auto_candidates;
        int least = -1;
        for (int k = 0; k < r.auto_count; k++) {
            const int measured = !c[k].sun || map; /* the sun's: only with a sun */
            assert_int_equal(c[k].pilot_spp > 0, measured);
            if (!measured) continue;
            assert_true(c[k].error_per_spp > 0 && c[k].per_spp > 0 &&
                        c[k].efficiency == c[k].error_per_spp * c[k].per_spp);
            /* the standard error of a mean over >= 1200 pixels: well below the mean */
            assert_true(c[k].error_se > 0 && c[k].error_se < 0.5 * c[k].error_per_spp);
            if (least < 0 || c[k].efficiency < c[least].efficiency) least = k;
        }
        /* the rule (docs/render.md): the least, but another than the prior (1) only when it
         * beats the prior's efficiency by more than 2 standard errors of the log ratio */
        int expect = 1;
        for (int k = 0; k < r.auto_count; k++) {
            if (k == 1 || c[k].pilot_spp <= 0) continue;
            const double rk = c[k].error_se / c[k].error_per_spp,
                         r1 = c[1].error_se / c[1].error_per_spp;
            const double margin = 2.0 * sqrt(rk * rk + r1 * r1 + 2 * 0.1 * 0.1);
            if (log(c[1].efficiency / c[k].efficiency) > margin &&
                c[k].efficiency < c[expect].efficiency)
                expect = k;
        }
        assert_int_equal(r.auto_chosen, expect);
        assert_int_equal(r.auto_held, expect != least);
        assert_int_equal(c[0].lights_k, 0);
        assert_int_equal(c[1].lights_k, 32);
        assert_int_equal(c[4].lights_k, 16);
        assert_int_equal(c[5].lights_k, 64);
        assert_true(c[2].sun && c[3].sun && !c[0].sun && !c[1].sun);
        /* a compact source drawn uniformly: the strata's error at one sample is far below
         * MIS's; which wins in error x time depends on the machine's timing (a loaded CI
         * machine, another instruction set), so only the errors are pinned, and with a fixed
         * pilot (16 samples a half) they depend on the seed alone */
        assert_int_equal(c[0].pilot_spp, 16);
        if (map == 1) {
            assert_true(c[1].error_per_spp < 0.1 * c[0].error_per_spp);
            /* the sun split off: MIS on the residual far better than the whole map's */
            assert_true(c[2].error_per_spp < 0.1 * c[0].error_per_spp);
            assert_int_not_equal(r.auto_chosen, 0);
        }
        assert_int_equal(r.stats.spp, 4);
        assert_int_equal(r.lights_k, c[r.auto_chosen].lights_k);
        if (c[r.auto_chosen].lights_k)
            assert_non_null(r.light_set);
        else
            assert_null(r.light_set);
        b = auto_by_hand(s, &sess.render, &c[r.auto_chosen]);
        assert_memory_equal(a->pixels, b->pixels, bytes);
        lumis_image_destroy(a);
        lumis_image_destroy(b);
        lumis_light_set_destroy(r.light_set);
        /* refused, naming what is not a map sampled with MIS */
        tu_sink sink;
        tu_sink_init(&sink);
        const char *msg = sink.last;
        lumis_session_desc bad = sess;
        bad.render.errors = sink.sink;
        bad.render.lighting.estimator = LUMIS_ESTIMATOR_LIGHT;
        assert_int_equal(lumis_render_session(s, &bad, &a, NULL), LUMIS_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(msg, "auto_estimator"));
        assert_non_null(strstr(msg, "render.lighting.estimator is not that"));
        bad = sess;
        bad.render.errors = sink.sink;
        bad.render.lighting.sampler = NULL;
        assert_int_equal(lumis_render_session(s, &bad, &a, NULL), LUMIS_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(msg, "render.lighting.sampler is not that"));
        bad = sess;
        bad.render.errors = sink.sink;
        bad.lights = "median-cut";
        assert_int_equal(lumis_session_check(&bad), LUMIS_ERR_INVALID_ARGUMENT);
        bad = sess;
        bad.render.errors = sink.sink;
        bad.auto_estimator = 0; /* a pilot's size without the choice */
        assert_int_equal(lumis_session_check(&bad), LUMIS_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(msg, "auto_pilot_spp"));
        lumis_sampler_destroy(smp);
        lumis_envmap_destroy(env);
    }
    assert_string_equal(lumis_auto_candidate_name(0), "mis");
    assert_string_equal(lumis_auto_candidate_name(1), "stratified-32");
    assert_string_equal(lumis_auto_candidate_name(2), "sun+mis");
    assert_string_equal(lumis_auto_candidate_name(3), "sun+stratified-32");
    assert_string_equal(lumis_auto_candidate_name(4), "stratified-16");
    assert_string_equal(lumis_auto_candidate_name(5), "stratified-64");
    assert_string_equal(lumis_auto_candidate_name(6), "unknown");
    assert_string_equal(lumis_auto_candidate_name(-1), "unknown");
    lumis_scene_destroy(s);
}

/* The prediction (LUMIS_AUTO_PREDICT): no pilot, the share of the reflectance the camera's
 * grid of rays meets that is diffuse decides -- strata (K = 32) from 0.5, else MIS -- and the
 * image is, bit for bit, the chosen candidate's rendered by hand.  The oracle: one sphere of
 * one material, whose diffuse share is d / (d + g) of the albedos' luminances wherever the
 * rays meet it, and whose hits are counted apart (sphere_normal at the 24 x 24 grid's cell
 * centres, the image's own pixels: fewer than LUMIS_AUTO_GRID per axis). */
static void auto_estimator_predicts_from_the_surfaces(void **state)
{
    (void)state;
    static const struct {
        lumis_bsdf m;
        double share; /* d / (d + g), by hand; -1: none reflects (1 then) */
        int chosen;   /* 1: strata K = 32, 0: MIS */
    } cases[] = {
        {{LUMIS_BSDF_LAMBERT, {0.7f, 0.7f, 0.7f}, {0, 0, 0}, 0, 0}, 1.0, 1},
        {{LUMIS_BSDF_WARD, {0.6f, 0.6f, 0.6f}, {0.2f, 0.2f, 0.2f}, 0.3f, 0.3f}, 0.75, 1},
        {{LUMIS_BSDF_WARD, {0.3f, 0.3f, 0.3f}, {0.3f, 0.3f, 0.3f}, 0.3f, 0.3f}, 0.5, 1},
        {{LUMIS_BSDF_WARD, {0.2f, 0.2f, 0.2f}, {0.6f, 0.6f, 0.6f}, 0.3f, 0.3f}, 0.25, 0},
        {{LUMIS_BSDF_GGX_GLOSSY, {0, 0, 0}, {0.8f, 0.8f, 0.8f}, 0.1f, 0.1f}, 0.0, 0},
        {{LUMIS_BSDF_GGX_CONDUCTOR, {0.9f, 0.9f, 0.9f}, {0.9f, 0.6f, 0.5f}, 0.3f, 0.3f}, 0.0, 0},
        /* coloured: red diffuse (luminance 0.27008), blue gloss (0.15776) */
        {{LUMIS_BSDF_GGX_PLASTIC, {0.9f, 0.1f, 0.1f}, {0.1f, 0.1f, 0.9f}, 0.2f, 0.2f},
         0.27008 / (0.27008 + 0.15776),
         1},
        {{LUMIS_BSDF_LAMBERT, {0, 0, 0}, {0, 0, 0}, 0, 0}, -1.0, 1},
    };
    int hits = 0; /* the grid's cell centres on the sphere */
    for (int y = 0; y < 24; y++)
        for (int x = 0; x < 24; x++) {
            double n[3];
            hits += sphere_normal(x + 0.5, y + 0.5, n);
        }
    lumis_envmap *env = gradient_map(63, 31, 0.5f, 2e3f);
    lumis_sampler *smp = NULL;
    lumis_sampler_desc sdesc = {0};
    assert_int_equal(lumis_sampler_create(env, &sdesc, &smp), LUMIS_OK);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        lumis_object o = {0};
        o.type = LUMIS_OBJECT_SPHERE;
        o.radius = 1.0f;
        o.material = cases[k].m;
        lumis_scene *s = NULL;
        assert_int_equal(lumis_scene_create(&o, 1, NULL, &s), LUMIS_OK);
        lumis_session_desc sess = {0};
        sess.render.camera = &cam;
        sess.render.lighting.env = env;
        sess.render.lighting.sampler = smp;
        sess.render.spp = 4;
        sess.render.seed = 9;
        sess.render.threads = 1;
        sess.auto_estimator = LUMIS_AUTO_PREDICT;
        lumis_session_result r;
        lumis_image *a = NULL, *b = NULL;
        assert_int_equal(lumis_render_session(s, &sess, &a, &r), LUMIS_OK);
        assert_int_equal(r.auto_mode, LUMIS_AUTO_PREDICT);
        assert_int_equal(r.auto_count, LUMIS_AUTO_CANDIDATES);
        const double want = cases[k].share < 0.0 ? 1.0 : cases[k].share;
        if (fabs(r.auto_diffuse_share - want) > 1e-4)
            fail_msg("case %zu: diffuse share %.6f, want %.6f", k, r.auto_diffuse_share, want);
        assert_true(abs(r.auto_rays - hits) <= 2); /* grazing cells aside */
        assert_int_equal(r.auto_chosen, cases[k].chosen);
        /* no pilot ran: nothing measured, no prior's rule, no sun looked for */
        assert_int_equal(r.auto_prior, 0);
        assert_int_equal(r.auto_held, 0);
        assert_true(r.auto_pilot_seconds == 0.0 && r.auto_pilot_cpu == 0.0);
        assert_int_equal(r.auto_sun.found, 0);
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++)
            assert_int_equal(r.auto_candidates[c].pilot_spp, 0);
        assert_int_equal(r.stats.spp, 4);
        assert_int_equal(r.lights_k, cases[k].chosen ? 32 : 0);
        b = auto_by_hand(s, &sess.render, &r.auto_candidates[r.auto_chosen]);
        assert_memory_equal(a->pixels, b->pixels, 24 * 24 * 3 * sizeof(float));
        lumis_image_destroy(a);
        lumis_image_destroy(b);
        lumis_light_set_destroy(r.light_set);
        lumis_scene_destroy(s);
    }
    /* nothing in view (the camera looks away from the sphere): no ray meets a surface */
    lumis_scene *s = one_sphere(0.7f);
    const lumis_camera away = {{0, 0, 4}, {0, 0, 8}, {0, 1, 0}, 30.0f, 40, 20};
    double share = 0.0;
    int rays = -1;
    assert_int_equal(lumis__auto_diffuse_share(s, &away, NULL, &share, &rays), LUMIS_OK);
    assert_true(share == 1.0 && rays == 0);
    /* a wide image: a grid of 32 x 16 cells, every one on a sphere that fills the view */
    const lumis_camera inside = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 30.0f, 400, 200};
    assert_int_equal(lumis__auto_diffuse_share(s, &inside, NULL, &share, &rays), LUMIS_OK);
    assert_true(share == 1.0 && rays == LUMIS_AUTO_GRID * LUMIS_AUTO_GRID / 2);
    const lumis_camera tall = {{0, 0, 0}, {0, 0, -1}, {0, 1, 0}, 30.0f, 100, 300};
    assert_int_equal(lumis__auto_diffuse_share(s, &tall, NULL, &share, &rays), LUMIS_OK);
    assert_int_equal(rays, 10 * LUMIS_AUTO_GRID); /* 32 rows of floor(32 / 3) */
    /* a camera that frames nothing (its eye on its target) is refused, nothing measured */
    const lumis_camera blind = {{0, 0, 0}, {0, 0, 0}, {0, 1, 0}, 30.0f, 40, 30};
    share = -1.0, rays = -1;
    assert_int_equal(lumis__auto_diffuse_share(s, &blind, NULL, &share, &rays),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_true(share == -1.0 && rays == -1);
    lumis_scene_destroy(s);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
}

/* The sun's candidates only on a sun-dominated map (>= 50 % of the power in <= 0.1 % of the
 * pixels): a compact source holding a third of the power (a sun lumis_sun_find accepts at
 * its default 0.1 share) makes none, one holding most of it makes both. */
static void auto_estimator_sun_only_when_dominated(void **state)
{
    (void)state;
    lumis_scene *s = one_sphere(0.7f);
    const float peaks[2] = {2e2f, 2e3f};
    for (int m = 0; m < 2; m++) {
        lumis_envmap *env = gradient_map(63, 31, 0.5f, peaks[m]);
        lumis_sun sun;
        lumis_sun_desc sd = {0};
        assert_int_equal(lumis_sun_find(env, &sd, &sun, NULL), LUMIS_OK);
        assert_true(sun.found); /* a sun either way, at the default share */
        assert_true(m ? sun.share > 0.5 : sun.share > 0.1 && sun.share < 0.5);
        lumis_sampler *smp = NULL;
        lumis_sampler_desc sdesc = {0};
        assert_int_equal(lumis_sampler_create(env, &sdesc, &smp), LUMIS_OK);
        lumis_session_desc sess = {0};
        sess.render.camera = &cam;
        sess.render.lighting.env = env;
        sess.render.lighting.sampler = smp;
        sess.render.spp = 1;
        sess.render.threads = 1;
        sess.auto_estimator = LUMIS_AUTO_PILOTS;
        sess.auto_pilot_spp = 2;
        lumis_session_result r;
        lumis_image *a = NULL;
        assert_int_equal(lumis_render_session(s, &sess, &a, &r), LUMIS_OK);
        assert_int_equal(r.auto_sun.found, m);
        assert_int_equal(r.auto_candidates[2].pilot_spp > 0, m);
        assert_int_equal(r.auto_candidates[3].pilot_spp > 0, m);
        assert_int_equal(r.auto_candidates[4].pilot_spp > 0, 1);
        lumis_image_destroy(a);
        lumis_light_set_destroy(r.light_set);
        lumis_sampler_destroy(smp);
        lumis_envmap_destroy(env);
    }
    lumis_scene_destroy(s);
}

/* The pilots' price of a sample is its marginal cost.  Oracle, written apart from the code:
 * a fake cost model, a pass of n samples taking o + n m seconds (o what a pass costs
 * whatever its samples, m a sample's), priced from passes of n and 2n samples, must come
 * out m whatever o (the second pass's average, o / 2n + m, would not), up to o = 6 n m,
 * beyond which the price is held at a quarter of that average; a negative o (noise) gives
 * the average.  Then two candidates under that model: the prior (strata, one sample a pass,
 * dear samples, large o) and MIS (8 samples a pass, cheap ones, the same o).  By the rule
 * in docs/render.md MIS is chosen exactly when log(e_prior / e_mis) > 2 sqrt(r_mis^2 +
 * r_prior^2 + 2 x 0.1^2) (r: the errors' relative standard errors, e: error x price);
 * computed here for MIS's marginal cost at the flip, the choice must flip between 0.98 and
 * 1.02 of it -- where pricing by the average would still pick the prior. */
static void auto_estimator_prices_the_marginal_sample(void **state)
{
    (void)state;
    /* the MIS pilot's size: as long as the prior's first half, by CPU time when both
     * clocks saw something, else by wall time; rounded, within [1, 64] */
    assert_int_equal(lumis__auto_mis_n(0.06, 0.01, 1.0, 1.0), 6);  /* CPU: 6 MIS samples */
    assert_int_equal(lumis__auto_mis_n(0.064, 0.01, 1.0, 1.0), 6); /* 6.4 rounds to 6 */
    assert_int_equal(lumis__auto_mis_n(0.066, 0.01, 1.0, 1.0), 7); /* 6.6 to 7 */
    assert_int_equal(lumis__auto_mis_n(0.0, 0.01, 0.09, 0.03), 3); /* no CPU time: wall */
    assert_int_equal(lumis__auto_mis_n(0.06, 0.0, 0.09, 0.03), 3); /* no CPU clock: wall */
    assert_int_equal(lumis__auto_mis_n(0.001, 0.01, 1.0, 1.0), 1); /* at least one */
    assert_int_equal(lumis__auto_mis_n(10.0, 0.01, 1.0, 1.0), 64); /* at most 64 */
    assert_int_equal(lumis__auto_mis_n(0.0, 0.0, 0.05, 0.0), 64);  /* no MIS time: the cap */
    const double os[3] = {0.0, 2e-3, 0.05}, ms[2] = {1e-3, 0.02};
    const int ns[3] = {1, 4, 16};
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 2; k++)
            for (int q = 0; q < 3; q++) {
                const double o = os[i], m = ms[k];
                const int n = ns[q];
                const double price = lumis__auto_price(o + n * m, n, o + 2 * n * m, 2 * n);
                const double avg = (o + 2 * n * m) / (2 * n);
                if (o <= 6.0 * n * m)
                    assert_true(fabs(price - m) <= 1e-9 * m);
                else
                    assert_true(fabs(price - 0.25 * avg) <= 1e-9 * avg);
            }
    /* a first pass dearer per sample than... the second cheaper than the first (noise): */
    assert_true(fabs(lumis__auto_price(0.010, 1, 0.008, 2) - 0.25 * 0.004) < 1e-15);
    /* negative overhead (the first pass cheap): the average */
    assert_true(fabs(lumis__auto_price(0.001, 1, 0.010, 2) - 0.005) < 1e-15);
    assert_true(lumis__auto_price(0.01, 1, 0.0, 2) == 0.0);
    assert_true(fabs(lumis__auto_price(0.01, 2, 0.01, 2) - 0.005) < 1e-15);

    /* the choice under the fake model */
    const double o = 4e-3;                  /* per pass, both */
    const double v_p = 0.05, se_p = 2.5e-3; /* the prior: strata K = 32, n = 1 */
    const double m_p = 6e-3;
    const double v_c = 0.6, se_c = 0.03; /* MIS, n = 8 */
    const double r_p = se_p / v_p, r_c = se_c / v_c;
    const double sd = sqrt(r_c * r_c + r_p * r_p + 2 * 0.1 * 0.1);
    const double m_star = v_p * m_p * exp(-2.0 * sd) / v_c; /* MIS's m at the flip */
    const double fs[4] = {0.5, 0.98, 1.02, 1.5};
    for (int f = 0; f < 4; f++) {
        lumis_auto_candidate a[LUMIS_AUTO_CANDIDATES];
        memset(a, 0, sizeof a);
        const double m_c = fs[f] * m_star;
        a[1].pilot_spp = 1;
        a[1].error_per_spp = v_p;
        a[1].error_se = se_p;
        a[1].per_spp = lumis__auto_price(o + m_p, 1, o + 2 * m_p, 2);
        a[1].efficiency = v_p * a[1].per_spp;
        a[0].pilot_spp = 8;
        a[0].error_per_spp = v_c;
        a[0].error_se = se_c;
        a[0].per_spp = lumis__auto_price(o + 8 * m_c, 8, o + 16 * m_c, 16);
        a[0].efficiency = v_c * a[0].per_spp;
        int held = -1;
        const int pick = lumis__auto_choose(a, 1, &held);
        assert_int_equal(pick, fs[f] < 1.0 ? 0 : 1);
        /* held: MIS the more efficient (m_c < v_p m_p / v_c = m_star e^{2 sd}) yet kept back */
        assert_int_equal(held, fs[f] > 1.0 && m_c < v_p * m_p / v_c);
        /* priced by the second pass's average instead (o / 16 + m_c against o / 2 + m_p:
         * MIS's 16 samples share o, the strata's 2 do not), 0.98 would keep the prior: the
         * flip above is the slope's */
        if (f == 1) {
            const double avg_p = (o + 2 * m_p) / 2, avg_c = (o + 16 * m_c) / 16;
            assert_true(log(v_p * avg_p / (v_c * avg_c)) < 2.0 * sd);
        }
    }
    /* without the prior measured: the least */
    lumis_auto_candidate a[LUMIS_AUTO_CANDIDATES];
    memset(a, 0, sizeof a);
    a[4].pilot_spp = a[5].pilot_spp = 1;
    a[4].per_spp = a[5].per_spp = 1e-3;
    a[4].efficiency = 2.0;
    a[5].efficiency = 1.0;
    int held = -1;
    assert_int_equal(lumis__auto_choose(a, 0, &held), 5);
    assert_int_equal(held, 0);
    memset(a, 0, sizeof a);
    assert_int_equal(lumis__auto_choose(a, 0, &held), 1); /* none measured: the prior */

    /* A pass the CPU clock saw nothing of (the clock missing, or a pass shorter than a
     * coarse clock's tick) prices a sample at 0, its efficiency 0: every candidate is then
     * priced by wall time (one clock for all: CPU seconds over 4 threads are 4x the wall's
     * here), never one at 0 beside the others' CPU prices. */
    lumis__pilot_times t[LUMIS_AUTO_CANDIDATES];
    memset(t, 0, sizeof t);
    const int tn[LUMIS_AUTO_CANDIDATES] = {8, 1, 0, 0, 1, 1};
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
        const double m = 1e-3 * (c + 1), o = 2e-3; /* a pass: o + n m wall seconds */
        t[c].n = tn[c];
        t[c].wall[0] = o + tn[c] * m;
        t[c].wall[1] = o + 2 * tn[c] * m;
        t[c].cpu[0] = 4.0 * t[c].wall[0];
        t[c].cpu[1] = 4.0 * t[c].wall[1];
    }
    double price[LUMIS_AUTO_CANDIDATES];
    assert_int_equal(lumis__auto_prices(t, LUMIS_AUTO_CANDIDATES, price), 0);
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++)
        assert_true(tn[c] ? fabs(price[c] - 4e-3 * (c + 1)) < 1e-12 : price[c] == 0.0);
    t[5].cpu[0] = t[5].cpu[1] = 0.0; /* K = 64's passes under a tick */
    assert_int_equal(lumis__auto_prices(t, LUMIS_AUTO_CANDIDATES, price), 1);
    for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++)
        assert_true(tn[c] ? fabs(price[c] - 1e-3 * (c + 1)) < 1e-12 : price[c] == 0.0);
    t[5].cpu[0] = 4.0 * t[5].wall[0]; /* the first half seen, the second not */
    assert_int_equal(lumis__auto_prices(t, LUMIS_AUTO_CANDIDATES, price), 1);
    t[5].cpu[1] = 4.0 * t[5].wall[1];
    t[2].cpu[1] = 0.0; /* a candidate not measured (n 0) does not count */
    assert_int_equal(lumis__auto_prices(t, LUMIS_AUTO_CANDIDATES, price), 0);

    /* A candidate priced at 0 all the same is not ranked: it neither wins nor makes the rule
     * hold the prior back (auto_held); priced, the prior is kept by the least efficiency. */
    for (int prior = 0; prior < 2; prior++) {
        memset(a, 0, sizeof a);
        for (int c = 0; c < LUMIS_AUTO_CANDIDATES; c++) {
            if (c == 2 || c == 3) continue;
            a[c].pilot_spp = 1;
            a[c].error_per_spp = 0.1 * (c + 1);
            a[c].error_se = 1e-3;
            a[c].per_spp = 1e-3;
            a[c].efficiency = a[c].error_per_spp * a[c].per_spp;
        }
        a[0].per_spp = 5e-3; /* MIS: 5e-4 against the prior's 2e-4 */
        a[0].efficiency = a[0].error_per_spp * a[0].per_spp;
        a[4].per_spp = a[4].efficiency = 0.0;
        if (!prior) a[1].pilot_spp = 0, a[1].per_spp = a[1].efficiency = 0.0;
        held = -1;
        assert_int_equal(lumis__auto_choose(a, prior, &held), prior ? 1 : 0);
        assert_int_equal(held, 0);
    }
}

/* The pilots' error of an image without noise: a constant map seen straight (the camera
 * looks away from the sphere), every pixel the map's radiance whatever the sample, so every
 * candidate's two halves agree and its relMSE at one sample is 0 (up to the halves'
 * rounding, far below one part in the pixels' count, 1 / 576 here). */
static void auto_estimator_error_of_a_noiseless_image(void **state)
{
    (void)state;
    lumis_scene *s = one_sphere(0.7f);
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(32, 16, &img), LUMIS_OK);
    for (size_t k = 0; k < 3 * 32 * 16; k++) img->pixels[k] = 0.75f;
    lumis_envmap *env = env_of(img);
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_sampler_create(env, NULL, &smp), LUMIS_OK);
    lumis_camera away = cam; /* at (0, 0, 4), looking further away from the sphere */
    away.look_at.z = 8.0f;
    lumis_session_desc sess = {0};
    sess.render.camera = &away;
    sess.render.lighting.env = env;
    sess.render.lighting.sampler = smp;
    sess.render.spp = 2;
    sess.render.threads = 1;
    sess.auto_estimator = LUMIS_AUTO_PILOTS;
    sess.auto_pilot_spp = 3;
    lumis_session_result r;
    lumis_image *a = NULL;
    assert_int_equal(lumis_render_session(s, &sess, &a, &r), LUMIS_OK);
    int measured = 0;
    for (int k = 0; k < r.auto_count; k++) {
        const lumis_auto_candidate *c = &r.auto_candidates[k];
        if (c->pilot_spp <= 0) continue;
        measured++;
        assert_true(c->error_per_spp >= 0.0 && c->error_per_spp < 1e-3 / 576.0);
        assert_true(c->error_se >= 0.0 && c->error_se < 1e-3 / 576.0);
    }
    assert_int_equal(measured, 4); /* MIS, strata 16, 32, 64: no sun */
    for (size_t k = 0; k < 3 * 24 * 24; k++) assert_true(fabsf(a->pixels[k] - 0.75f) < 1e-5f);
    lumis_image_destroy(a);
    lumis_light_set_destroy(r.light_set);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
    lumis_scene_destroy(s);
}

/* The pilots' bounds.  A render smaller than the pilots (24 x 24 at 4 spp, no budget) runs
 * none and renders the prior, strata K = 32 (auto_prior 1); a budget whose 15 % cannot hold
 * the first pair and MIS's runs one half and renders the prior (auto_prior 2); a budget that
 * holds some runs pilots within 15 % of it (the last one's prediction may miss by its own
 * time: at most 1.5 x the cap), and the cap is 0.15 x the budget. */
static void auto_estimator_pilots_capped(void **state)
{
    (void)state;
    lumis_scene *s = one_sphere(0.7f);
    lumis_envmap *env = gradient_map(63, 31, 0.5f, 2e3f);
    lumis_sampler *smp = NULL;
    lumis_sampler_desc sdesc = {0};
    assert_int_equal(lumis_sampler_create(env, &sdesc, &smp), LUMIS_OK);
    lumis_session_desc sess = {0};
    sess.render.camera = &cam;
    sess.render.lighting.env = env;
    sess.render.lighting.sampler = smp;
    sess.render.spp = 4;
    sess.render.threads = 1;
    sess.auto_estimator = LUMIS_AUTO_PILOTS;
    lumis_session_result r;
    lumis_image *a = NULL, *b = NULL;
    assert_int_equal(lumis_render_session(s, &sess, &a, &r), LUMIS_OK);
    assert_int_equal(r.auto_prior, 1);
    assert_int_equal(r.auto_chosen, 1);
    for (int k = 0; k < LUMIS_AUTO_CANDIDATES; k++)
        assert_int_equal(r.auto_candidates[k].pilot_spp, 0);
    b = auto_by_hand(s, &sess.render, &r.auto_candidates[1]);
    assert_memory_equal(a->pixels, b->pixels, 24 * 24 * 3 * sizeof(float));
    lumis_image_destroy(a);
    lumis_image_destroy(b);
    lumis_light_set_destroy(r.light_set);
    /* 64 x 64: the pilots render all 4096 pixels; a stratified half there (32 shadow rays
     * a pixel) takes far more than 15 % of 2 ms */
    lumis_camera big = cam;
    big.width = big.height = 64;
    sess.render.camera = &big;
    sess.render.spp = 0;
    sess.time_budget = 0.002;
    assert_int_equal(lumis_render_session(s, &sess, &a, &r), LUMIS_OK);
    assert_int_equal(r.auto_prior, 2);
    assert_int_equal(r.auto_chosen, 1);
    assert_true(fabs(r.auto_cap - 0.15 * 0.002) < 1e-12);
    lumis_image_destroy(a);
    lumis_light_set_destroy(r.light_set);
    sess.time_budget = 0.5;
    assert_int_equal(lumis_render_session(s, &sess, &a, &r), LUMIS_OK);
    assert_true(fabs(r.auto_cap - 0.15 * 0.5) < 1e-12);
    /* in CPU time: the pilots' wall time is the machine's (a loaded one stretched it past
     * 1.5 x the cap), their CPU time is what the cap bounds: a pilot starts only while the
     * wall time so far and its prediction stay within the cap, and CPU time runs no faster */
    assert_true(r.auto_pilot_cpu > 0.0 && r.auto_pilot_cpu <= 1.5 * r.auto_cap);
    lumis_image_destroy(a);
    lumis_light_set_destroy(r.light_set);
    /* without a budget (48 spp) the cap is 0.15 x the prior's render, 7.2 of its first
     * pilot halves (u): the warm-up, the prior's pair and MIS's fit (6.2 u), all six pairs
     * (some 19.5 u, the wall times and the cap alike in u whatever the load) do not */
    sess.time_budget = 0.0;
    sess.render.spp = 48;
    assert_int_equal(lumis_render_session(s, &sess, &a, &r), LUMIS_OK);
    int measured = 0;
    for (int k = 0; k < LUMIS_AUTO_CANDIDATES; k++) measured += r.auto_candidates[k].pilot_spp > 0;
    assert_true(measured < LUMIS_AUTO_CANDIDATES);
    assert_true(r.auto_pilot_cpu > 0.0 && r.auto_pilot_cpu <= 1.5 * r.auto_cap);
    lumis_image_destroy(a);
    lumis_light_set_destroy(r.light_set);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
    lumis_scene_destroy(s);
}

static void render_session_equals_its_parts(void **state)
{
    (void)state;
    lumis_scene *s = one_sphere(0.7f);
    lumis_image *sky = NULL;
    lumis_sky_desc sd = {0};
    sd.width = 64;
    sd.height = 32;
    assert_int_equal(lumis_sky_create(&sd, &sky), LUMIS_OK);
    lumis_envmap *env = env_of(sky);
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_sampler_create(env, NULL, &smp), LUMIS_OK);
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.lighting.env = env;
    d.lighting.sampler = smp;
    d.spp = 3;
    d.seed = 11;
    d.threads = 2;
    const size_t bytes = 24 * 24 * 3 * sizeof(float);
    /* the map's sampler, 3 spp */
    lumis_image *a = NULL, *b = NULL;
    assert_int_equal(lumis_render(s, &d, &a, NULL), LUMIS_OK);
    lumis_session_desc sess = {0};
    sess.render = d;
    lumis_session_result r;
    assert_int_equal(lumis_render_session(s, &sess, &b, &r), LUMIS_OK);
    assert_memory_equal(a->pixels, b->pixels, bytes);
    assert_int_equal(r.stats.spp, 3);
    assert_null(r.light_set);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
    /* median cut, K = 12, by name */
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(env, "median-cut", 12, 0, NULL, NULL, &set), LUMIS_OK);
    d.lighting.light_set.set = set;
    d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    d.lighting.sampler = NULL; /* the set lights it */
    assert_int_equal(lumis_render(s, &d, &a, NULL), LUMIS_OK);
    sess.render = d;
    sess.render.lighting.light_set.set = NULL; /* the session makes it */
    sess.lights = "median-cut";
    sess.lights_k = 12;
    assert_int_equal(lumis_render_session(s, &sess, &b, &r), LUMIS_OK);
    assert_memory_equal(a->pixels, b->pixels, bytes);
    assert_int_equal(r.lights_k, 12);
    assert_int_equal(r.upsample, 1);
    assert_non_null(r.light_set);
    lumis_light_set_destroy(r.light_set);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
    lumis_light_set_destroy(set);
    /* Wu, F = 2: EnvDirects at full resolution + EnvIndirects at 12 x 12, upsampled */
    assert_int_equal(lumis_lights_by_name(env, "wu", 12, 0, NULL, NULL, &set), LUMIS_OK);
    lumis_render_desc full = d, low = d;
    full.lighting.light_set.set = low.lighting.light_set.set = set;
    full.lighting.light_set.kinds = 1u << LUMIS_LIGHT_ENV_DIRECT;
    low.lighting.light_set.kinds = 1u << LUMIS_LIGHT_ENV_INDIRECT;
    low.lighting.hide_environment = low.pixel_centers = 1;
    low.spp = 1;
    lumis_camera lc = cam;
    lc.width = lc.height = 12;
    low.camera = &lc;
    lumis_image *lo = NULL, *up = NULL;
    lumis_gbuffer *gf = NULL, *gl = NULL;
    assert_int_equal(lumis_render(s, &full, &a, NULL), LUMIS_OK);
    assert_int_equal(lumis_render(s, &low, &lo, NULL), LUMIS_OK);
    assert_int_equal(lumis_render_gbuffer(s, &cam, NULL, &gf), LUMIS_OK);
    assert_int_equal(lumis_render_gbuffer(s, &lc, NULL, &gl), LUMIS_OK);
    assert_int_equal(lumis_joint_bilateral_upsample(lo, gl, gf, NULL, &up), LUMIS_OK);
    for (size_t k = 0; k < 24 * 24 * 3; k++) a->pixels[k] += up->pixels[k];
    sess.lights = "wu";
    assert_int_equal(lumis_render_session(s, &sess, &b, &r), LUMIS_OK);
    assert_memory_equal(a->pixels, b->pixels, bytes);
    assert_int_equal(r.upsample, 2);
    lumis_light_set_destroy(r.light_set);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
    lumis_image_destroy(lo);
    lumis_image_destroy(up);
    lumis_gbuffer_destroy(gf);
    lumis_gbuffer_destroy(gl);
    lumis_light_set_destroy(set);
    /* a budget: K from the pilots, everything inside the budget's accounting */
    sess.lights_k = 0;
    sess.time_budget = 0.2;
    sess.spent = 0.01;
    assert_int_equal(lumis_render_session(s, &sess, &b, &r), LUMIS_OK);
    assert_true(r.pilot_count >= 1 && r.pilot_k[0] == 4 && r.lights_k >= 1);
    assert_true(r.prep_seconds >= 0.01 && r.budget_used_seconds > r.prep_seconds);
    assert_true(r.budget_used_seconds >= r.prep_seconds + r.stats.seconds - 1e-9);
    lumis_light_set_destroy(r.light_set);
    lumis_image_destroy(b);
    /* refused */
    lumis_session_desc bad = sess;
    bad.lights = "no-such";
    b = NULL;
    assert_int_equal(lumis_render_session(s, &bad, &b, &r), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(b);
    bad = sess;
    bad.lights = "median-cut";
    bad.upsample = 2; /* upsampling is Wu's */
    assert_int_equal(lumis_render_session(s, &bad, &b, &r), LUMIS_ERR_INVALID_ARGUMENT);
    bad = sess;
    bad.time_budget = -1.0;
    assert_int_equal(lumis_render_session(s, &bad, &b, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(b);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
    lumis_scene_destroy(s);
}

/* A light set's K fitted to a budget (issue 35): the pilots, the floor of K, the plan's
 * samples and the time's accounting, on budgets that cannot and that can afford the floor. */
static void render_session_budget_holds(void **state)
{
    (void)state;
    lumis_scene *s = one_sphere(0.7f);
    lumis_image *sky = NULL;
    lumis_sky_desc sd = {0};
    sd.width = 64;
    sd.height = 32;
    assert_int_equal(lumis_sky_create(&sd, &sky), LUMIS_OK);
    lumis_envmap *env = env_of(sky);
    /* 320 x 240 for 10 ms on one thread: K = 4 at 4 spp costs more on any CPU */
    lumis_camera big = cam;
    big.width = 320;
    big.height = 240;
    lumis_session_desc sess = {0};
    sess.render.camera = &big;
    sess.render.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    sess.render.lighting.env = env;
    sess.render.threads = 1;
    sess.lights = "wu";
    sess.time_budget = 0.01;
    sess.spent = 0.001; /* the caller's: in the budget, not in the session's wall time */
    lumis_session_result r;
    lumis_image *img = NULL;
    assert_int_equal(lumis_render_session(s, &sess, &img, &r), LUMIS_OK);
    assert_int_equal(r.k_floor, 4);
    assert_true(r.pilot_count >= 1 && r.pilot_k[0] == 4);
    /* never under the floor unsaid: fewer samples first, down to one; then fewer lights */
    assert_true(r.k_limit != LUMIS_K_LIMIT_NONE);
    if (r.k_limit == LUMIS_K_LIMIT_FEWER_SPP)
        assert_true(r.lights_k >= 4 && r.spp_planned < 4);
    else
        assert_true(r.spp_planned == 1 && r.lights_k >= 1 &&
                    (r.lights_k < 4 || r.k_limit == LUMIS_K_LIMIT_OVER_BUDGET));
    assert_true(r.stats.spp >= 1 && r.stats.spp <= r.spp_planned);
    /* the budget's parts are disjoint spans of the session's wall time (the G-buffers are
     * render time, not preparation too) */
    if (!(r.budget_used_seconds - sess.spent <= r.wall_seconds + 1e-6))
        fail_msg("budget used %g s (%g s the caller's) in a session of %g s", r.budget_used_seconds,
                 sess.spent, r.wall_seconds);
    /* one thread's CPU time is at most its wall time */
    assert_int_equal(r.threads_busy, 1);
    assert_true(r.cpu_share > 0.0 && r.cpu_share <= 1.05);
    assert_true(r.cpu_seconds > 0.0 && r.render_wall_seconds > 0.0);
    lumis_light_set_destroy(r.light_set);
    lumis_image_destroy(img);
    /* A map of 128 pixels caps K at 128, which a generous budget affords at once: the
     * render keeps its plan's samples and leaves the rest of the budget unspent. */
    lumis_image *small = NULL;
    sd.width = 16;
    sd.height = 8;
    assert_int_equal(lumis_sky_create(&sd, &small), LUMIS_OK);
    lumis_envmap *env_small = env_of(small);
    sess.render.lighting.env = env_small;
    sess.render.camera = &cam;
    sess.time_budget = 0.5;
    assert_int_equal(lumis_render_session(s, &sess, &img, &r), LUMIS_OK);
    if (r.lights_k != 128)
        fail_msg("K = %d (pilots %d: %d %d %d, predicted %g s)", r.lights_k, r.pilot_count,
                 r.pilot_k[0], r.pilot_k[1], r.pilot_k[2], r.pilot_predicted);
    assert_int_equal(r.k_limit, LUMIS_K_LIMIT_NONE);
    assert_int_equal(r.spp_planned, 4);
    assert_int_equal(r.stats.spp, 4);
    lumis_light_set_destroy(r.light_set);
    lumis_image_destroy(img);
    lumis_envmap_destroy(env_small);
    lumis_envmap_destroy(env);
    lumis_scene_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(furnace),
        cmocka_unit_test(builtin_scenes_build),
        cmocka_unit_test(window_room_is_closed),
        cmocka_unit_test(new_builtin_scenes_render),
        cmocka_unit_test(timed_passes_end_within_the_budget),
        cmocka_unit_test(pilots_predict_with_a_floor_on_the_slope),
        cmocka_unit_test(render_session_equals_its_parts),
        cmocka_unit_test(render_session_budget_holds),
        cmocka_unit_test(upsampling_keeps_constants_and_depth_edges),
        cmocka_unit_test(light_set_lights_each_pixel_with_its_set),
        cmocka_unit_test(light_set_shades_glossy_surfaces_with_their_bsdf),
        cmocka_unit_test(upsampling_builtins_and_scene_values),
        cmocka_unit_test(packets_hand_embree_initialised_lanes),
        cmocka_unit_test(every_embree_kernel_renders_light_sets),
        cmocka_unit_test(scene_file_reads_its_map),
        cmocka_unit_test(shadow_ray_callback),
        cmocka_unit_test(exact_irradiance),
        cmocka_unit_test(stratified_light_sets_converge_to_the_exact_irradiance),
        cmocka_unit_test(sun_split_converges_to_the_exact_irradiance),
        cmocka_unit_test(selected_draws_converge_to_the_exact_irradiance),
        cmocka_unit_test(allocated_draws_converge_to_the_exact_irradiance),
        cmocka_unit_test(allocated_draws_follow_neyman),
        cmocka_unit_test(allocated_draws_with_no_region_lit),
        cmocka_unit_test(allocated_draws_refused_before_the_render),
        cmocka_unit_test(selected_draws_shade_glossy_surfaces_exactly),
        cmocka_unit_test(selected_draws_choose_regions_by_their_bound),
        cmocka_unit_test(estimators_agree_and_threads_do_not_matter),
        cmocka_unit_test(bad_scenes),
        cmocka_unit_test(scene_files_are_strict),
        cmocka_unit_test(scene_file_defaults_and_refusals),
        cmocka_unit_test(passes_do_not_change_the_image),
        cmocka_unit_test(auto_estimator_renders_what_it_chose),
        cmocka_unit_test(auto_estimator_predicts_from_the_surfaces),
        cmocka_unit_test(auto_estimator_sun_only_when_dominated),
        cmocka_unit_test(auto_estimator_pilots_capped),
        cmocka_unit_test(auto_estimator_prices_the_marginal_sample),
        cmocka_unit_test(auto_estimator_error_of_a_noiseless_image),
        cmocka_unit_test(instances_match_baked_copies),
        cmocka_unit_test(integrating_sphere),
    };
    /* LUMIS_TEST_FILTER=render_session* runs the tests of that name alone */
    if (getenv("LUMIS_TEST_FILTER")) cmocka_set_test_filter(getenv("LUMIS_TEST_FILTER"));
    return cmocka_run_group_tests(tests, NULL, NULL);
}
