/* Photometric fixtures in the renderer (lumis_photometric_lighting): the illuminance on a
 * floor under a fixture follows the inverse-square law from the table, E = I(theta) cos
 * theta / d^2, pixel by pixel (an asymmetric road light, so that the C planes' orientation
 * is checked too); a rotationally symmetric file gives a rotationally symmetric image; a
 * fixture aimed elsewhere lights where it is aimed; an occluder casts a shadow; a luminous
 * opening far away is the point, and its light, BSDF and MIS estimates agree. */
#include "photometric_gen.h"
#include "testutil.h"

#include "lumis/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define W  32
#define H  32

static lumis_photometric_file *load(const pg_ies_spec *spec)
{
    size_t n = 0;
    char *text = pg_ies(spec, &n);
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_photometric_file *f = NULL;
    if (lumis_photometric_read_memory(text, n, "gen.ies", &sink.sink, &f) != LUMIS_OK)
        fail_msg("%s", sink.last);
    free(text);
    return f;
}

/* A white Lambertian floor (z = 0, albedo 1), optionally a sphere above it. */
static lumis_scene *floor_scene(int with_sphere)
{
    lumis_object o[2];
    memset(o, 0, sizeof o);
    o[0].type = LUMIS_OBJECT_PLANE;
    o[0].normal = (lumis_vec3){0, 0, 1};
    o[0].size = 100.0f;
    o[0].material.type = LUMIS_BSDF_LAMBERT;
    o[0].material.diffuse = (lumis_rgb){1, 1, 1};
    o[1].type = LUMIS_OBJECT_SPHERE;
    o[1].center = (lumis_vec3){0.6f, 0.3f, 2.0f};
    o[1].radius = 0.3f;
    o[1].material = o[0].material;
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(o, with_sphere ? 2 : 1, NULL, &s), LUMIS_OK);
    return s;
}

/* The camera looks straight down from height 5 (fov 60): pixel (x, y)'s centre meets the
 * floor at floor_point(x, y). */
static const lumis_camera cam = {{0, 0, 5}, {0, 0, 0}, {0, 1, 0}, 60.0f, W, H};

static void floor_point(int x, int y, double *X, double *Y)
{
    const double th = tan(30.0 * PI / 180.0);
    *X = 5.0 * ((x + 0.5) / W * 2.0 - 1.0) * th;
    *Y = 5.0 * (1.0 - (y + 0.5) / H * 2.0) * th;
}

static lumis_image *render(const lumis_scene *s, const lumis_photometric_instance *in, int n,
                           int spp, lumis_estimator est, int centers, unsigned long long seed)
{
    lumis_photometric_lighting pl = {in, n};
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.photometric = &pl;
    d.spp = spp;
    d.estimator = est;
    d.pixel_centers = centers;
    d.seed = seed;
    d.threads = 1;
    lumis_image *img = NULL;
    tu_sink sink;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    if (lumis_render(s, &d, &img, NULL) != LUMIS_OK) fail_msg("render: %s", sink.last);
    return img;
}

static double px(const lumis_image *img, int x, int y)
{
    return img->pixels[3 * (y * W + x) + 1];
}

/* E = I(theta) cos(theta) / d^2 on the floor, from the analytic distribution the table was
 * made from: within 0.5 % at every pixel the light reaches (the table's 1-degree grid
 * interpolates it to about 1e-4), and exactly the model's value to float rounding. */
static void illuminance_follows_the_inverse_square_law(void **state)
{
    (void)state;
    pg_ies_spec spec = {PG_ROAD, 0.8, "IESNA:LM-63-2002", 1, 91, 0, 90, 361, 0, 360, 0, 0, 0, 0,
                        0,       2};
    lumis_photometric_file *f = load(&spec);
    lumis_scene *s = floor_scene(0);
    lumis_photometric_instance in = {0};
    in.photometric = f->model;
    in.placement.t[2] = 2.0; /* 2 above the floor, aimed down (identity: C0 along +x) */
    lumis_image *img = render(s, &in, 1, 1, LUMIS_ESTIMATOR_MIS, 1, 1);
    int checked = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double X, Y;
            floor_point(x, y, &X, &Y);
            const double d2 = X * X + Y * Y + 4.0, d = sqrt(d2), cos_t = 2.0 / d;
            const double gamma = acos(cos_t) * 180 / PI;
            double C = atan2(Y, X) * 180 / PI;
            if (C < 0) C += 360;
            const double want = pg_intensity(PG_ROAD, 0.8, C, gamma) * cos_t / d2 / PI;
            const lumis_vec3 dir = {(float)(X / d), (float)(Y / d), (float)(-2.0 / d)};
            const double model = lumis_photometric_intensity(f->model, dir) * cos_t / d2 / PI;
            const double got = px(img, x, y);
            if (fabs(got / want - 1) > 5e-3)
                fail_msg("pixel (%d, %d): %g, inverse-square law %g", x, y, got, want);
            if (fabs(got / model - 1) > 1e-5)
                fail_msg("pixel (%d, %d): %g, the model's %g", x, y, got, model);
            checked++;
        }
    assert_int_equal(checked, W * H);
    /* the road light throws more to +x (C0) than to -x: not mirrored */
    assert_true(px(img, W - 4, H / 2) > 1.2 * px(img, 3, H / 2));
    /* the multiplier scales it */
    in.multiplier = 2.5;
    lumis_image *img2 = render(s, &in, 1, 1, LUMIS_ESTIMATOR_MIS, 1, 1);
    assert_true(fabs(px(img2, 7, 9) / px(img, 7, 9) - 2.5) < 1e-5);
    lumis_image_destroy(img2);
    lumis_image_destroy(img);
    lumis_scene_destroy(s);
    lumis_photometric_file_destroy(f);
}

/* A rotationally symmetric table under a camera looking down its axis: the image is
 * symmetric under the square's eight symmetries. */
static void rotational_symmetry_gives_a_symmetric_image(void **state)
{
    (void)state;
    pg_ies_spec spec = {PG_SPOT, 5, "IESNA:LM-63-2002", 1, 46, 0, 90, 1, 0, 0, 0, 0, 0, 0, 0, 2};
    lumis_photometric_file *f = load(&spec);
    lumis_scene *s = floor_scene(0);
    lumis_photometric_instance in = {0};
    in.photometric = f->model;
    in.placement.t[2] = 1.5;
    lumis_image *img = render(s, &in, 1, 1, LUMIS_ESTIMATOR_LIGHT, 1, 3);
    double peak = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const double v = px(img, x, y),
                         vs[3] = {px(img, y, x), px(img, W - 1 - x, y), px(img, x, H - 1 - y)};
            for (int k = 0; k < 3; k++)
                if (fabs(vs[k] - v) > 1e-5 * fmax(v, 1e-6))
                    fail_msg("(%d, %d): %g, its image %d %g", x, y, v, k, vs[k]);
            peak = fmax(peak, v);
        }
    assert_true(peak > 0);
    lumis_image_destroy(img);
    lumis_scene_destroy(s);
    lumis_photometric_file_destroy(f);
}

/* lumis_photometric_aim: a narrow spot aimed at a point of the floor lights it most; its
 * frame is a proper rotation; an occluder casts a shadow the light does not reach. */
static void aim_and_shadows(void **state)
{
    (void)state;
    pg_ies_spec spec = {PG_SPOT, 200, "IESNA:LM-63-2002", 1, 181, 0, 90, 1, 0, 0, 0, 0, 0, 0, 0, 2};
    lumis_photometric_file *f = load(&spec);
    lumis_scene *s = floor_scene(0);
    lumis_photometric_instance in = {0};
    in.photometric = f->model;
    in.placement.t[0] = -1.0;
    in.placement.t[2] = 2.0;
    const double target[2] = {1.2, -0.8};
    const lumis_vec3 aim = {(float)(target[0] + 1.0), (float)target[1], -2.0f};
    assert_int_equal(lumis_photometric_aim(aim, 30.0, in.placement.r), LUMIS_OK);
    assert_int_equal(lumis_rigid_check(&in.placement), LUMIS_OK);
    const lumis_vec3 zero = {0, 0, 0};
    double unused[9];
    assert_int_equal(lumis_photometric_aim(zero, 0, unused), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_image *img = render(s, &in, 1, 1, LUMIS_ESTIMATOR_MIS, 1, 1);
    int bx = 0, by = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            if (px(img, x, y) > px(img, bx, by)) bx = x, by = y;
    double X, Y;
    floor_point(bx, by, &X, &Y);
    const double pitch = 2 * 5 * tan(30 * PI / 180) / W;
    if (hypot(X - target[0], Y - target[1]) > pitch)
        fail_msg("the brightest pixel is at (%g, %g), aimed at (%g, %g)", X, Y, target[0],
                 target[1]);
    lumis_image_destroy(img);
    /* an asymmetric table, tilted and rolled: every pixel as the frame says, world to local
     * by the transpose of R */
    pg_ies_spec road = {PG_ROAD, 0.8, "IESNA:LM-63-2002", 1, 91, 0, 90, 73, 0, 360, 0, 0, 0, 0,
                        0,       2};
    lumis_photometric_file *rf = load(&road);
    lumis_photometric_instance tilted = in;
    tilted.photometric = rf->model;
    const lumis_vec3 aim2 = {0.5f, -0.3f, -1.0f};
    assert_int_equal(lumis_photometric_aim(aim2, 40.0, tilted.placement.r), LUMIS_OK);
    img = render(s, &tilted, 1, 1, LUMIS_ESTIMATOR_MIS, 1, 1);
    const double *R = tilted.placement.r, *T = tilted.placement.t;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            floor_point(x, y, &X, &Y);
            const double w[3] = {X - T[0], Y - T[1], -T[2]};
            const double d2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2], d = sqrt(d2);
            const lumis_vec3 loc = {(float)((R[0] * w[0] + R[3] * w[1] + R[6] * w[2]) / d),
                                    (float)((R[1] * w[0] + R[4] * w[1] + R[7] * w[2]) / d),
                                    (float)((R[2] * w[0] + R[5] * w[1] + R[8] * w[2]) / d)};
            const double want = lumis_photometric_intensity(rf->model, loc) * (T[2] / d) / d2 / PI;
            if (fabs(px(img, x, y) - want) > 1e-5 * want + 1e-9)
                fail_msg("tilted (%d, %d): %g, want %g", x, y, px(img, x, y), want);
        }
    lumis_image_destroy(img);
    lumis_photometric_file_destroy(rf);
    lumis_scene_destroy(s);
    /* a sphere between a downlight and the floor: black below it, lit beside it */
    lumis_scene *s2 = floor_scene(1);
    pg_ies_spec lam = {PG_LAMBERT, 0, "IESNA:LM-63-2002", 1, 91, 0, 90, 1, 0, 0, 0, 0, 0, 0, 0, 2};
    lumis_photometric_file *g = load(&lam);
    lumis_photometric_instance down = {0};
    down.photometric = g->model;
    down.placement.t[2] = 3.0;
    lumis_image *shadow = render(s2, &down, 1, 1, LUMIS_ESTIMATOR_MIS, 1, 1);
    /* the floor point behind the sphere's centre as the light sees it: (0.6, 0.3) x 3; the
     * camera sees the floor there (the sphere's image is around (1, 0.5), radius 0.5) */
    int sx = 0, sy = 0, lx = 0, ly = 0;
    double ds = 1e9, dl = 1e9;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) { /* the pixels nearest to it and to its mirror image */
            floor_point(x, y, &X, &Y);
            if (hypot(X - 1.8, Y - 0.9) < ds) ds = hypot(X - 1.8, Y - 0.9), sx = x, sy = y;
            if (hypot(X + 1.8, Y + 0.9) < dl) dl = hypot(X + 1.8, Y + 0.9), lx = x, ly = y;
        }
    assert_true(px(shadow, sx, sy) == 0.0);
    assert_true(px(shadow, lx, ly) > 0.01);
    lumis_image_destroy(shadow);
    lumis_scene_destroy(s2);
    lumis_photometric_file_destroy(g);
    lumis_photometric_file_destroy(f);
}

/* The mean of the floor's pixels (centre: of the 2 x 2 below the fixture) over renders of
 * seeds 100 .. 100 + runs - 1: its mean and standard error. */
static void image_mean(const lumis_scene *s, const lumis_photometric_instance *in,
                       lumis_estimator est, int spp, int runs, int centre, double *mean, double *se)
{
    double sum = 0, sum2 = 0;
    for (int r = 0; r < runs; r++) {
        lumis_image *img = render(s, in, 1, spp, est, 1, 100 + (unsigned long long)r);
        double m = 0;
        int count = 0;
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                if (!centre || (abs(2 * x + 1 - W) < 2 && abs(2 * y + 1 - H) < 2)) {
                    m += px(img, x, y);
                    count++;
                }
        m /= count;
        sum += m;
        sum2 += m * m;
        lumis_image_destroy(img);
    }
    *mean = sum / runs;
    *se = sqrt(fmax(0.0, sum2 / runs - *mean * *mean) / (runs - 1));
}

/* A disk opening (0.5 m): far away (10 m) it is the point to 0.5 %; close (0.4 m) its
 * light, BSDF and MIS estimates agree with each other within their errors; closer still
 * (0.25 m) it is not the point below it. */
static void an_opening_is_unbiased_and_far_away_a_point(void **state)
{
    (void)state;
    pg_ies_spec spec = {PG_SPOT, 3, "IESNA:LM-63-2002", 1, 91, 0, 90, 1, 0, 0, 0, 0, -0.5, -0.5,
                        0,       2};
    lumis_photometric_file *f = load(&spec);
    lumis_scene *s = floor_scene(0);
    lumis_photometric_instance in = {0};
    in.photometric = f->model;
    in.area = 1;
    in.placement.t[2] = 10.0;
    double m_area, se_area, m_point, se_point;
    image_mean(s, &in, LUMIS_ESTIMATOR_LIGHT, 4, 4, 0, &m_area, &se_area);
    in.area = 0;
    image_mean(s, &in, LUMIS_ESTIMATOR_LIGHT, 1, 2, 0, &m_point, &se_point);
    if (fabs(m_area / m_point - 1) > 5e-3)
        fail_msg("at 10 m: opening %g, point %g", m_area, m_point);
    in.area = 1;
    in.placement.t[2] = 0.4;
    double m[3], se[3];
    const lumis_estimator ests[3] = {LUMIS_ESTIMATOR_LIGHT, LUMIS_ESTIMATOR_BSDF,
                                     LUMIS_ESTIMATOR_MIS};
    /* below the opening (the whole floor's mean is its flux, whatever the estimator draws
     * on the opening: it would not tell) */
    for (int k = 0; k < 3; k++) image_mean(s, &in, ests[k], 64, 8, 1, &m[k], &se[k]);
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++)
            if (fabs(m[a] - m[b]) > 4 * sqrt(se[a] * se[a] + se[b] * se[b]) + 1e-4 * m[a])
                fail_msg("estimators %d and %d: %g +- %g against %g +- %g", a, b, m[a], se[a], m[b],
                         se[b]);
    /* below it, the opening's light is not the point's so close: the checks above are not
     * vacuous */
    double mc, sec, m0, se0;
    in.placement.t[2] = 0.25;
    image_mean(s, &in, LUMIS_ESTIMATOR_MIS, 16, 4, 1, &mc, &sec);
    in.area = 0;
    image_mean(s, &in, LUMIS_ESTIMATOR_LIGHT, 1, 2, 1, &m0, &se0);
    if (!(fabs(m0 / mc - 1) > 0.05))
        fail_msg("below a 0.5 m opening at 0.25 m: %g, the point %g", mc, m0);
    lumis_scene_destroy(s);
    lumis_photometric_file_destroy(f);
}

/* A rectangular opening's estimators agree (the power heuristic too); a point is lit the
 * same whatever the estimator (no BSDF sample can find it); what prepare refuses. */
static void rectangles_estimators_and_refusals(void **state)
{
    (void)state;
    pg_ies_spec spec = {PG_BATWING, 2, "IESNA:LM-63-2002", 1, 46, 0, 90, 1, 0, 0, 0, 0, 0.2, 0.4,
                        0,          2};
    lumis_photometric_file *f = load(&spec);
    lumis_scene *s = floor_scene(0);
    lumis_photometric_instance in = {0};
    in.photometric = f->model;
    in.area = 1;
    in.placement.t[2] = 0.3;
    double m[3], se[3];
    const lumis_estimator ests[3] = {LUMIS_ESTIMATOR_LIGHT, LUMIS_ESTIMATOR_BSDF,
                                     LUMIS_ESTIMATOR_MIS};
    for (int k = 0; k < 3; k++) image_mean(s, &in, ests[k], 64, 8, 1, &m[k], &se[k]);
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++)
            if (fabs(m[a] - m[b]) > 4 * sqrt(se[a] * se[a] + se[b] * se[b]) + 1e-4 * m[a])
                fail_msg("rectangle: estimators %d and %d: %g +- %g against %g +- %g", a, b, m[a],
                         se[a], m[b], se[b]);
    /* the power heuristic, two light and two BSDF samples */
    {
        lumis_photometric_lighting pl = {&in, 1};
        lumis_render_desc d = {0};
        d.camera = &cam;
        d.photometric = &pl;
        d.spp = 64;
        d.power_heuristic = 1;
        d.light_samples = 2;
        d.bsdf_samples = 2;
        d.pixel_centers = 1;
        d.threads = 1;
        double sum = 0;
        int count = 0;
        for (int r = 0; r < 4; r++) {
            d.seed = 900 + (unsigned long long)r;
            lumis_image *img = NULL;
            assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++)
                    if (abs(2 * x + 1 - W) < 2 && abs(2 * y + 1 - H) < 2) {
                        sum += px(img, x, y);
                        count++;
                    }
            lumis_image_destroy(img);
        }
        const double mp = sum / count;
        if (fabs(mp - m[2]) > 4 * se[2] + 0.02 * m[2])
            fail_msg("power heuristic %g, balance %g +- %g", mp, m[2], se[2]);
    }
    /* a point: the same image whatever the estimator */
    in.area = 0;
    lumis_image *a = render(s, &in, 1, 1, LUMIS_ESTIMATOR_LIGHT, 1, 5);
    lumis_image *b = render(s, &in, 1, 1, LUMIS_ESTIMATOR_BSDF, 1, 5);
    for (int k = 0; k < 3 * W * H; k++) assert_true(a->pixels[k] == b->pixels[k]);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
    /* refusals: no table, a reflection, a negative multiplier, no fixture and no map */
    lumis_photometric_instance bad = in;
    lumis_photometric_lighting pl = {&bad, 1};
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.photometric = &pl;
    d.spp = 1;
    lumis_image *img = NULL;
    bad.photometric = NULL;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    bad = in;
    bad.placement.r[0] = -1;
    bad.placement.r[4] = bad.placement.r[8] = 1;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    bad = in;
    bad.multiplier = -2;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    pl.count = 0; /* not this kind: the map's, and there is none */
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);
    lumis_scene_destroy(s);
    lumis_photometric_file_destroy(f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(illuminance_follows_the_inverse_square_law),
        cmocka_unit_test(rotational_symmetry_gives_a_symmetric_image),
        cmocka_unit_test(aim_and_shadows),
        cmocka_unit_test(an_opening_is_unbiased_and_far_away_a_point),
        cmocka_unit_test(rectangles_estimators_and_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
