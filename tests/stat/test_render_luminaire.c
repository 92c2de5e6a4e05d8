/* Luminaires as the renderer's lights (lumis/render.h, lumis_luminaire_lighting): a pixel's
 * mean equals albedo / pi times the quadrature irradiance for every strategy and sequence,
 * wherever the luminaire is placed and whatever its scale; exact visibility with no
 * occluder gives the unshadowed image bit for bit; an occluder that covers the whole
 * luminaire gives black with exact and approximate visibility, a partial one something in
 * between; bad lighting descriptors get a clear error. */
/* Oracles:
 * lumis_render — statistical: a pixel's mean equals albedo / pi times the luminaire's quadrature
 *     irradiance for every strategy and sequence, any placement and scale; hand-worked: a covering
 *     occluder gives black, exact visibility without one the unshadowed image (pixels_are_unbiased,
 *     visibility)
 * lumis_render_luminaire_choices — indirect: the auto strategy's choice inside lumis_render,
 *     checked unbiased (pixels_are_unbiased)
 * lumis_render_job_run — consistency: the image depends on seed and samples, not on passes or
 *     threads (passes_and_threads_do_not_matter)
 * lumis_visibility_from_name — hand-worked: "approx" and "shadowmap" give their values, "raster"
 *     refused (bad_lighting)
 * lumis_sequence_from_name — hand-worked: "halton" (bad_lighting)
 * lumis_sequence_name — hand-worked: "halton" (bad_lighting)
 */
#include "../testutil.h"

#include "lum_fixture.h"
#include "lumis/render.h"
#include "lumis/rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* A placement: world = R (scale local) + t. */
typedef struct placement {
    double r[9], t[3], scale;
} placement;

static lumis_vec3 to_world(const placement *x, double a, double b, double c, int point)
{
    const double k = point ? x->scale : 1.0, o = point ? 1.0 : 0.0;
    const double v[3] = {a * k, b * k, c * k};
    lumis_vec3 w;
    w.x = (float)(x->r[0] * v[0] + x->r[1] * v[1] + x->r[2] * v[2] + o * x->t[0]);
    w.y = (float)(x->r[3] * v[0] + x->r[4] * v[1] + x->r[5] * v[2] + o * x->t[1]);
    w.z = (float)(x->r[6] * v[0] + x->r[7] * v[1] + x->r[8] * v[2] + o * x->t[2]);
    return w;
}

/* The local shading point and the objects around it: a Lambertian floor through p facing
 * the luminaire, and optionally a sphere (centre, radius, local units) in between. */
static const double P[3] = {0.3, -0.2, 3.0};
static const float ALBEDO = 0.5f;

static lumis_scene *make_scene(const placement *x, const double *sphere, double radius)
{
    lumis_object o[2];
    memset(o, 0, sizeof o);
    o[0].type = LUMIS_OBJECT_PLANE;
    o[0].center = to_world(x, P[0], P[1], P[2], 1);
    o[0].normal = to_world(x, 0, 0, -1, 0);
    o[0].size = (float)(20.0 * x->scale);
    o[0].material.type = LUMIS_BSDF_LAMBERT;
    o[0].material.diffuse = (lumis_rgb){ALBEDO, ALBEDO, ALBEDO};
    int n = 1;
    if (sphere) {
        o[1].type = LUMIS_OBJECT_SPHERE;
        o[1].center = to_world(x, sphere[0], sphere[1], sphere[2], 1);
        o[1].radius = (float)(radius * x->scale);
        o[1].material = o[0].material;
        n = 2;
    }
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(o, n, NULL, &s), LUMIS_OK);
    return s;
}

/* The sequence render_pixel renders with (0: the default). */
static lumis_sequence pixel_sequence;

/* A 1 x 1 image through the pixel's centre, which sees P from the side (above any sphere
 * of the tests). */
static lumis_rgb render_pixel(const lumis_scene *s, const placement *x,
                              const lumis_luminaire_lighting *ll, uint64_t seed, int spp)
{
    lumis_camera cam = {to_world(x, P[0] + 2.0, P[1], 2.8, 1),
                        to_world(x, P[0], P[1], P[2], 1),
                        to_world(x, 0, 1, 0, 0),
                        1.0f,
                        1,
                        1};
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.lighting.luminaires = ll;
    d.lighting.kind = LUMIS_LIGHTING_LUMINAIRES;
    d.pixel_centers = 1;
    d.sequence = pixel_sequence;
    d.spp = spp;
    d.seed = seed;
    d.threads = 1;
    lumis_image *img = NULL;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
    lumis_rgb c = {img->pixels[0], img->pixels[1], img->pixels[2]};
    lumis_image_destroy(img);
    return c;
}

static const placement IDENTITY = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}, 1.0};
/* Local +z to world -y, millimetres to metres, moved. */
static const placement TURNED = {{1, 0, 0, 0, 0, -1, 0, 1, 0}, {0.4, 0.7, -2.0}, 0.001};

static void pixels_are_unbiased(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 7);
    lumis_rgb ref;
    const lumis_vec3 p = {(float)P[0], (float)P[1], (float)P[2]}, n = {0, 0, -1};
    assert_int_equal(lumis_luminaire_irradiance(f.lum, p, n, 6, &ref), LUMIS_OK);
    const double expect = ALBEDO / PI * ref.g;
    assert_true(expect > 0.0);
    const placement *where[2] = {&IDENTITY, &TURNED};
    for (int w = 0; w < 2; w++) {
        lumis_scene *s = make_scene(where[w], NULL, 0.0);
        lumis_luminaire_instance in = {0};
        in.luminaire = f.lum;
        memcpy(in.placement.r, where[w]->r, sizeof in.placement.r);
        memcpy(in.placement.t, where[w]->t, sizeof in.placement.t);
        in.scale = where[w]->scale;
        for (int strategy = LUMIS_LUM_RESTRICTED; strategy < LUMIS_LUM_STRATEGY_COUNT; strategy++)
            for (int seq = 0; seq < LUMIS_SEQUENCE_COUNT; seq++) {
                lumis_luminaire_lighting ll = {0};
                ll.instances = &in;
                ll.count = 1;
                ll.budget = 16;
                ll.strategy = (lumis_luminaire_strategy)strategy;
                pixel_sequence = (lumis_sequence)seq;
                ll.visibility = LUMIS_VISIBILITY_NONE;
                enum { RUNS = 32 };
                double sum = 0.0, sum2 = 0.0;
                for (int r = 0; r < RUNS; r++) {
                    double v = render_pixel(s, where[w], &ll, 100 + (uint64_t)r, 64).g;
                    sum += v;
                    sum2 += v * v;
                }
                const double mean = sum / RUNS,
                             se = sqrt(fmax(sum2 / RUNS - mean * mean, 0.0) / (RUNS - 1));
                if (!(fabs(mean - expect) <= 4.0 * se + 1e-6 * expect))
                    fail_msg("placement %d, %s, %s: mean %.6g, expected %.6g, se %.3g", w,
                             lumis_luminaire_strategy_name(ll.strategy),
                             lumis_sequence_name(pixel_sequence), mean, expect, se);
                /* Restricted sampling is far better than 30% relative error per run here. */
                if (strategy == LUMIS_LUM_RESTRICTED) assert_true(se * sqrt(RUNS) < 0.3 * expect);
            }
        lumis_scene_destroy(s);
    }
    free_fixture(&f);
}

static void visibility(void **state)
{
    (void)state;
    for (int basis = LUMIS_BASIS_QUADRATIC; basis <= LUMIS_BASIS_BSPLINE; basis++) {
        fixture f = make_fixture((lumis_luminaire_basis)basis, 11);
        lumis_luminaire_instance in = {0};
        in.luminaire = f.lum; /* zero placement: the identity */
        lumis_luminaire_lighting ll = {0};
        ll.instances = &in;
        ll.count = 1;
        ll.budget = 24;
        /* No occluder: exact visibility traces rays that all pass, the same image bit for
         * bit; approximate visibility too. */
        lumis_scene *open = make_scene(&IDENTITY, NULL, 0.0);
        ll.visibility = LUMIS_VISIBILITY_NONE;
        const lumis_rgb free_ = render_pixel(open, &IDENTITY, &ll, 5, 4);
        assert_true(free_.g > 0.0f);
        for (int v = LUMIS_VISIBILITY_EXACT; v <= LUMIS_VISIBILITY_APPROX; v++) {
            ll.visibility = (lumis_visibility)v;
            const lumis_rgb c = render_pixel(open, &IDENTITY, &ll, 5, 4);
            assert_true(c.r == free_.r && c.g == free_.g && c.b == free_.b);
        }
        lumis_scene_destroy(open);
        /* A sphere that hides all of U from P: black either way. */
        const double centre[3] = {P[0], P[1], 2.0};
        lumis_scene *closed = make_scene(&IDENTITY, centre, 0.8);
        for (int v = LUMIS_VISIBILITY_EXACT; v <= LUMIS_VISIBILITY_APPROX; v++) {
            ll.visibility = (lumis_visibility)v;
            const lumis_rgb c = render_pixel(closed, &IDENTITY, &ll, 5, 4);
            assert_true(c.r == 0.0f && c.g == 0.0f && c.b == 0.0f);
        }
        lumis_scene_destroy(closed);
        /* Shadow maps: no false shadows without an occluder (the bias), black behind the
         * big sphere. */
        ll.visibility = LUMIS_VISIBILITY_SHADOW_MAP;
        lumis_scene *open2 = make_scene(&IDENTITY, NULL, 0.0);
        const lumis_rgb sm = render_pixel(open2, &IDENTITY, &ll, 5, 4);
        assert_true(sm.r == free_.r && sm.g == free_.g && sm.b == free_.b);
        ll.visibility = LUMIS_VISIBILITY_NONE;
        const lumis_rgb free64 = render_pixel(open2, &IDENTITY, &ll, 5, 64);
        ll.visibility = LUMIS_VISIBILITY_SHADOW_MAP;
        lumis_scene_destroy(open2);
        lumis_scene *closed2 = make_scene(&IDENTITY, centre, 0.8);
        const lumis_rgb smc = render_pixel(closed2, &IDENTITY, &ll, 5, 4);
        assert_true(smc.r == 0.0f && smc.g == 0.0f && smc.b == 0.0f);
        lumis_scene_destroy(closed2);
        /* A small one that hides part of it (13-22 %): strictly between, every way, against
         * the unshadowed estimate from the same 64 samples (shadows only remove light).  At
         * P[0] + 0.3 it hid 0.54 % (4096 samples), and "below 0.99" passed on PCG32's noise. */
        const double part[3] = {P[0] + 0.1, P[1], 1.5};
        lumis_scene *some = make_scene(&IDENTITY, part, 0.15);
        for (int v = LUMIS_VISIBILITY_EXACT; v <= LUMIS_VISIBILITY_SHADOW_MAP; v++) {
            if (v == LUMIS_VISIBILITY_NONE) continue;
            ll.visibility = (lumis_visibility)v;
            const lumis_rgb c = render_pixel(some, &IDENTITY, &ll, 5, 64);
            if (!(c.g > 0.05f * free64.g && c.g < 0.99f * free64.g))
                fail_msg("%s visibility: %g of the unshadowed %g",
                         lumis_visibility_name(ll.visibility), c.g, free64.g);
        }
        lumis_scene_destroy(some);
        free_fixture(&f);
    }
}

/* A shadow ray ends at the luminaire, in world units: a sphere behind U (beyond the
 * luminaire seen from P) casts no shadow, for the identity placement and for one scaled
 * from millimetres to metres (a ray's length left in the luminaire's units reached 1000
 * times too far there). */
static void blockers_behind_the_luminaire_cast_no_shadow(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 11);
    const placement *where[2] = {&IDENTITY, &TURNED};
    const double behind[3] = {P[0], P[1], -3.0};
    for (int w = 0; w < 2; w++) {
        lumis_luminaire_instance in = {0};
        in.luminaire = f.lum;
        memcpy(in.placement.r, where[w]->r, sizeof in.placement.r);
        memcpy(in.placement.t, where[w]->t, sizeof in.placement.t);
        in.scale = where[w]->scale;
        lumis_luminaire_lighting ll = {0};
        ll.instances = &in;
        ll.count = 1;
        ll.budget = 24;
        lumis_scene *s = make_scene(where[w], behind, 2.0);
        ll.visibility = LUMIS_VISIBILITY_NONE;
        const lumis_rgb free_ = render_pixel(s, where[w], &ll, 5, 4);
        ll.visibility = LUMIS_VISIBILITY_EXACT;
        const lumis_rgb c = render_pixel(s, where[w], &ll, 5, 4);
        assert_true(free_.g > 0.0f);
        if (!(fabsf(c.g - free_.g) <= 1e-6f * free_.g))
            fail_msg("placement %d: %g with exact visibility, %g without", w, c.g, free_.g);
        lumis_scene_destroy(s);
    }
    free_fixture(&f);
}

/* Every strategy, the global one drawn once per camera sample for all pixels included: the
 * image depends on the seed and the sample count, not on passes or threads. */
static void passes_and_threads_do_not_matter(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_BSPLINE, 9);
    lumis_scene *s = make_scene(&IDENTITY, NULL, 0.0);
    lumis_luminaire_instance in[2] = {{0}, {0}};
    in[0].luminaire = in[1].luminaire = f.lum;
    in[1].placement.t[0] = 0.4;
    in[1].placement.r[0] = in[1].placement.r[4] = in[1].placement.r[8] = 1.0;
    lumis_camera cam = {{2, 0.3f, 2}, {0, 0, 3}, {0, 1, 0}, 50.0f, 24, 16};
    for (int strategy = LUMIS_LUM_RESTRICTED; strategy < LUMIS_LUM_STRATEGY_COUNT; strategy++) {
        lumis_luminaire_lighting ll = {0};
        ll.instances = in;
        ll.count = 2;
        ll.budget = 12;
        ll.strategy = (lumis_luminaire_strategy)strategy;
        lumis_render_desc d = {0};
        d.camera = &cam;
        d.lighting.luminaires = &ll;
        d.lighting.kind = LUMIS_LIGHTING_LUMINAIRES;
        d.seed = 3;
        d.threads = 1;
        d.spp = 6;
        lumis_image *one = NULL, *split = NULL;
        lumis_render_stats st1, st2;
        assert_int_equal(lumis_render(s, &d, &one, &st1), LUMIS_OK);
        d.threads = 2;
        lumis_render_job *job = NULL;
        assert_int_equal(lumis_render_job_create(s, &d, &job), LUMIS_OK);
        assert_int_equal(lumis_render_job_run(job, 1), LUMIS_OK);
        assert_int_equal(lumis_render_job_run(job, 2), LUMIS_OK);
        assert_int_equal(lumis_render_job_run(job, 3), LUMIS_OK);
        assert_int_equal(lumis_render_job_image(job, &split), LUMIS_OK);
        lumis_render_job_stats(job, &st2);
        lumis_render_job_destroy(job);
        /* The samples evaluated: the same count, at least the budget per lit camera
         * sample of a pixel (each point draws >= K, two luminaires) and no more than the
         * capacity per luminaire. */
        assert_true(st1.light_samples == st2.light_samples);
        assert_true(st1.light_samples >= 12.0 &&
                    st1.light_samples <=
                        24.0 * 16 * 6 * 2 * (double)lumis_luminaire_capacity(f.lum, 12));
        double sum = 0.0;
        for (int k = 0; k < 3 * 24 * 16; k++) {
            assert_true(one->pixels[k] == split->pixels[k]);
            sum += one->pixels[k];
        }
        assert_true(sum > 0.0);
        lumis_image_destroy(one);
        lumis_image_destroy(split);
    }
    lumis_scene_destroy(s);
    free_fixture(&f);
}

/* Auto's choice, per luminaire: its prediction in distance bands (equal counts of the
 * probes, here 4 of a floor filling the view), and the strategies it takes over them with
 * neighbouring bands of one strategy merged into one (render.h): so without auto_bands one
 * band, and with them no two neighbours alike; each band's budget that of its strategy. */
static void auto_merges_neighbouring_bands_of_one_strategy(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_BSPLINE, 9);
    lumis_scene *s = make_scene(&IDENTITY, NULL, 0.0);
    lumis_luminaire_instance in = {0};
    in.luminaire = f.lum;
    lumis_camera cam = {{2, 0.3f, 2}, {0, 0, 3}, {0, 1, 0}, 50.0f, 24, 16};
    for (int banded = 0; banded < 2; banded++) {
        lumis_luminaire_lighting ll = {0};
        ll.instances = &in;
        ll.count = 1;
        ll.budget = 12;
        ll.strategy = LUMIS_LUM_AUTO;
        ll.auto_bands = banded;
        lumis_render_desc d = {0};
        d.camera = &cam;
        d.lighting.luminaires = &ll;
        d.lighting.kind = LUMIS_LIGHTING_LUMINAIRES;
        d.spp = 1;
        lumis_luminaire_choice c;
        assert_int_equal(lumis_render_luminaire_choices(s, &d, &c), LUMIS_OK);
        assert_true(c.prediction.bands >= 2); /* what there was to merge */
        assert_true(c.bands >= 1 && c.bands <= c.prediction.bands);
        if (!banded) assert_int_equal(c.bands, 1);
        for (int b = 0; b < c.bands; b++) {
            assert_true(c.strategy[b] == LUMIS_LUM_RESTRICTED ||
                        c.strategy[b] == LUMIS_LUM_UNIFORM || c.strategy[b] == LUMIS_LUM_GLOBAL);
            if (b > 0 && c.strategy[b] == c.strategy[b - 1])
                fail_msg("auto_bands %d: bands %d and %d both %s", banded, b - 1, b,
                         lumis_luminaire_strategy_name(c.strategy[b]));
            if (b > 0) assert_true(c.edge[b - 1] > (b > 1 ? c.edge[b - 2] : 0.0));
            if (c.strategy[b] != LUMIS_LUM_GLOBAL) assert_int_equal(c.budget[b], 12);
        }
    }
    lumis_scene_destroy(s);
    free_fixture(&f);
}

static void bad_lighting(void **state)
{
    (void)state;
    fixture f = make_fixture(LUMIS_BASIS_QUADRATIC, 3);
    lumis_scene *s = make_scene(&IDENTITY, NULL, 0.0);
    lumis_camera cam = {{2, 0, 2}, {0, 0, 3}, {0, 1, 0}, 30.0f, 4, 4};
    lumis_luminaire_instance in = {0};
    in.luminaire = f.lum;
    lumis_luminaire_lighting ll = {0};
    ll.instances = &in;
    ll.count = 1;
    tu_sink sink;
    tu_sink_init(&sink);
    const char *msg = sink.last;
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.lighting.luminaires = &ll;
    d.lighting.kind = LUMIS_LIGHTING_LUMINAIRES;
    d.spp = 1;
    d.errors = sink.sink;
    lumis_render_job *job = NULL;
    assert_int_equal(lumis_render_job_create(s, &d, &job), LUMIS_OK); /* no map needed */
    lumis_render_job_destroy(job);
    in.scale = -1.0;
    assert_int_equal(lumis_render_job_create(s, &d, &job), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(msg, "scale"));
    in.scale = 0.0;
    in.placement.r[0] = 2.0; /* not a rotation */
    assert_int_equal(lumis_render_job_create(s, &d, &job), LUMIS_ERR_INVALID_ARGUMENT);
    in.placement.r[0] = 0.0;
    ll.strategy = LUMIS_LUM_STRATEGY_COUNT;
    assert_int_equal(lumis_render_job_create(s, &d, &job), LUMIS_ERR_INVALID_ARGUMENT);
    ll.strategy = LUMIS_LUM_RESTRICTED;
    d.max_bounces = 1;
    assert_int_equal(lumis_render_job_create(s, &d, &job), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(msg, "max_bounces"));
    d.max_bounces = 0;
    in.luminaire = NULL;
    assert_int_equal(lumis_render_job_create(s, &d, &job), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(job);
    lumis_visibility v;
    lumis_sequence q;
    assert_int_equal(lumis_visibility_from_name("approx", &v), LUMIS_OK);
    assert_int_equal(v, LUMIS_VISIBILITY_APPROX);
    assert_int_equal(lumis_visibility_from_name("shadowmap", &v), LUMIS_OK);
    assert_int_equal(v, LUMIS_VISIBILITY_SHADOW_MAP);
    assert_int_equal(lumis_visibility_from_name("raster", &v), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_sequence_from_name("halton", &q), LUMIS_OK);
    assert_string_equal(lumis_sequence_name(q), "halton");
    lumis_scene_destroy(s);
    free_fixture(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pixels_are_unbiased),
        cmocka_unit_test(visibility),
        cmocka_unit_test(blockers_behind_the_luminaire_cast_no_shadow),
        cmocka_unit_test(passes_and_threads_do_not_matter),
        cmocka_unit_test(bad_lighting),
        cmocka_unit_test(auto_merges_neighbouring_bands_of_one_strategy),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
