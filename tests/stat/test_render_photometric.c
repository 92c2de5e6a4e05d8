/* Photometric fixtures in the renderer (lumis_photometric_lighting): the illuminance on a
 * floor under a fixture follows the inverse-square law from the table, E = I(theta) cos
 * theta / d^2, pixel by pixel (an asymmetric road light, so that the C planes' orientation
 * is checked too); a rotationally symmetric file gives a rotationally symmetric image; a
 * fixture aimed elsewhere lights where it is aimed; an occluder casts a shadow; a luminous
 * opening far away is the point, and its light, BSDF and MIS estimates agree. */
/* Oracles:
 * lumis_render — closed form: E = I(theta) cos theta / d^2 pixel by pixel under an asymmetric road
 *     light; a Lambertian disk's on-axis E = I0 / (h^2 + R^2); brute force: box, cylinder and
 *     sphere openings against a Gauss-Legendre quadrature written in the test; invariance: a
 *     rotational table gives an image with the square's 8 symmetries
 *     (illuminance_follows_the_inverse_square_law, a_disk_meets_its_closed_form,
 *     solid_openings_meet_a_quadrature, rotational_symmetry_gives_a_symmetric_image)
 * lumis_photometric_orient — closed form: a proper rotation taking -z to the aim, continuous in
 *     tilt, azimuth and roll; invariance: the fixture turned about y turns the image; metamorphic:
 *     twice the height lights twice the offset a quarter as much; a floodlight lights a horizontal
 *     band (orientation_is_a_continuous_explicit_frame, aimed_fixtures_over_a_floor,
 *     floodlights_light_a_horizontal_band)
 * lumis_photometric_irradiance — closed form: the disk's on-axis E = I0 / (h^2 + R^2)
 *     (a_disk_meets_its_closed_form)
 * lumis_photometric_near_irradiance — metamorphic: the renderer's near-field fixture estimates
 *     it (mean over the floor within four standard errors), and is the point fixture bit for
 *     bit where the field has no share, the residual beyond its cone included
 *     (a_near_field_fixture_renders_its_model)
 */
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
    d.lighting.photometric = &pl;
    d.lighting.kind = LUMIS_LIGHTING_PHOTOMETRIC;
    d.spp = spp;
    d.lighting.estimator = est;
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

/* lumis_photometric_orient: a narrow spot aimed at a point of the floor lights it most; its
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
    assert_int_equal(lumis_photometric_orient(LUMIS_PHOTOMETRIC_C, aim, NULL, 30.0, in.placement.r),
                     LUMIS_OK);
    assert_int_equal(lumis_rigid_check(&in.placement), LUMIS_OK);
    const lumis_vec3 zero = {0, 0, 0};
    double unused[9];
    assert_int_equal(lumis_photometric_orient(LUMIS_PHOTOMETRIC_C, zero, NULL, 0, unused),
                     LUMIS_ERR_INVALID_ARGUMENT);
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
    assert_int_equal(
        lumis_photometric_orient(LUMIS_PHOTOMETRIC_C, aim2, NULL, 40.0, tilted.placement.r),
        LUMIS_OK);
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
        d.lighting.photometric = &pl;
        d.lighting.kind = LUMIS_LIGHTING_PHOTOMETRIC;
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
    d.lighting.photometric = &pl;
    d.lighting.kind = LUMIS_LIGHTING_PHOTOMETRIC;
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
    /* an opening asked of a file that gives none (a point: width and length 0) is refused,
     * not rendered quietly as a point, though its area (0) is finite */
    pg_ies_spec pt = {PG_LAMBERT, 0, "IESNA:LM-63-2002", 1, 10, 0, 90, 1, 0, 0, 0, 0, 0, 0, 0, 2};
    lumis_photometric_file *fp = load(&pt);
    bad = in;
    bad.photometric = fp->model;
    bad.area = 1;
    tu_sink sink;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    img = (lumis_image *)1;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);
    if (!strstr(sink.last, "photometric fixture 0") || !strstr(sink.last, "\"point\""))
        fail_msg("a point with area: \"%s\"", sink.last);
    bad.area = 0; /* as a point it renders */
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_OK);
    lumis_image_destroy(img);
    img = NULL;
    lumis_photometric_file_destroy(fp);
    bad = in;
    d.errors = (lumis_error_sink){0};
    pl.count = 0; /* not this kind: the map's, and there is none */
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);
    lumis_scene_destroy(s);
    lumis_photometric_file_destroy(f);
}

/* A Lambertian disk (I0 cos gamma over an opening of radius R) gives E = I0 / (h^2 + R^2) on
 * its axis at distance h: the closed form pins the opening's size, which light and BSDF
 * sampling, consistent with each other, would not (issue 37's survivor: a disk rendered at
 * twice its radius).  The renderer's three estimators and lumis_photometric_irradiance. */
static void a_disk_meets_its_closed_form(void **state)
{
    (void)state;
    const double R = 0.2, h = 0.3;
    pg_ies_spec spec = {
        PG_LAMBERT, 0, "IESNA:LM-63-2002", 1, 181, 0, 90, 1, 0, 0, 0, 0, -2 * R, -2 * R, 0, 2};
    lumis_photometric_file *f = load(&spec);
    const double I0 = lumis_photometric_intensity_at(f->model, 0, 0);
    const double want = I0 / (h * h + R * R);
    const lumis_vec3 x = {0, 0, (float)-h}, n = {0, 0, 1};
    double E = 0;
    assert_int_equal(lumis_photometric_irradiance(f->model, 1, x, n, 0, &E), LUMIS_OK);
    if (fabs(E / want - 1) > 1e-3) fail_msg("irradiance %g, closed form %g", E, want);
    lumis_scene *s = floor_scene(0);
    double X, Y;
    floor_point(W / 2, H / 2, &X, &Y);
    lumis_photometric_instance in = {0};
    in.photometric = f->model;
    in.area = 1;
    in.placement.t[0] = X;
    in.placement.t[1] = Y;
    in.placement.t[2] = h;
    const lumis_estimator ests[3] = {LUMIS_ESTIMATOR_LIGHT, LUMIS_ESTIMATOR_BSDF,
                                     LUMIS_ESTIMATOR_MIS};
    for (int e = 0; e < 3; e++) {
        enum { RUNS = 6 };
        double sum = 0, sum2 = 0;
        for (int r = 0; r < RUNS; r++) {
            lumis_image *img = render(s, &in, 1, 128, ests[e], 1, 70 + (unsigned long long)r);
            const double v = px(img, W / 2, H / 2) * PI;
            sum += v;
            sum2 += v * v;
            lumis_image_destroy(img);
        }
        const double mean = sum / RUNS, se = sqrt(fmax(0, sum2 / RUNS - mean * mean) / (RUNS - 1));
        if (fabs(mean - want) > 4 * se + 3e-3 * want)
            fail_msg("estimator %d: E %g +- %g, closed form %g", e, mean, se, want);
    }
    lumis_scene_destroy(s);
    lumis_photometric_file_destroy(f);
}

/* ---- solid openings: a box, a cylinder, a sphere ------------------------------------------ */

/* Gauss-Legendre nodes and weights on [-1, 1], 16 points (Golub-Welsch by Newton). */
static void gauss16(double x[16], double w[16])
{
    for (int i = 0; i < 16; i++) {
        double z = cos(PI * (i + 0.75) / 16.5), dp = 1;
        for (int it = 0; it < 100; it++) {
            double p0 = 1, p1 = z;
            for (int k = 2; k <= 16; k++) {
                const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = 16 * (z * p1 - p0) / (z * z - 1);
            const double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-15) break;
        }
        x[i] = z;
        w[i] = 2 / ((1 - z * z) * dp * dp);
    }
}

typedef struct solid {
    int kind; /* 0 box, 1 cylinder, 2 sphere */
    double hx, hy, hz, r;
} solid;

/* The solid's area seen from unit direction d, written apart from the renderer's. */
static double seen_area(const solid *q, const double d[3])
{
    if (q->kind == 0)
        return 4 * (q->hy * q->hz * fabs(d[0]) + q->hx * q->hz * fabs(d[1]) +
                    q->hx * q->hy * fabs(d[2]));
    if (q->kind == 1)
        return PI * q->r * q->r * fabs(d[2]) + 4 * q->r * q->hz * sqrt(1 - d[2] * d[2]);
    return PI * q->r * q->r;
}

/* One surface element at y (normal n, area da) of a solid centred at c lighting the floor
 * point (X, Y, 0) (normal +z): L(d) (n.d) cos_floor / r^2 da, L = I(d) / seen_area(d). */
static double element(const lumis_photometric *p, const solid *q, const double c[3],
                      const double y[3], const double n[3], double da, double X, double Y)
{
    const double v[3] = {X - (c[0] + y[0]), Y - (c[1] + y[1]), -(c[2] + y[2])};
    const double r2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2], r = sqrt(r2);
    const double d[3] = {v[0] / r, v[1] / r, v[2] / r};
    const double cos_l = n[0] * d[0] + n[1] * d[1] + n[2] * d[2], cos_f = -d[2];
    if (!(cos_l > 0) || !(cos_f > 0)) return 0;
    const lumis_vec3 dl = {(float)d[0], (float)d[1], (float)d[2]};
    return lumis_photometric_intensity(p, dl) / seen_area(q, d) * cos_l * cos_f / r2 * da;
}

/* The illuminance at (X, Y, 0) from the solid at c (identity frame), by 16-point Gauss-
 * Legendre on each face (a box's six; a cylinder's caps in r and phi, its side in phi and
 * z; a sphere in cos theta and phi): the reference the renderer's three estimators meet. */
static double solid_illuminance(const lumis_photometric *p, const solid *q, const double c[3],
                                double X, double Y)
{
    double gx[16], gw[16], E = 0;
    gauss16(gx, gw);
    for (int i = 0; i < 16; i++)
        for (int j = 0; j < 16; j++) {
            const double a = gx[i], b = gx[j], w = gw[i] * gw[j];
            if (q->kind == 0) {
                const double h[3] = {q->hx, q->hy, q->hz};
                for (int ax = 0; ax < 3; ax++)
                    for (int sg = -1; sg <= 1; sg += 2) {
                        const int u = (ax + 1) % 3, v = (ax + 2) % 3;
                        double y[3], n[3] = {0, 0, 0};
                        y[ax] = sg * h[ax];
                        y[u] = a * h[u];
                        y[v] = b * h[v];
                        n[ax] = sg;
                        E += element(p, q, c, y, n, w * h[u] * h[v], X, Y);
                    }
            } else if (q->kind == 1) {
                const double phi = PI * (a + 1), rr = q->r * (b + 1) / 2;
                for (int sg = -1; sg <= 1; sg += 2) { /* caps: dA = r dr dphi */
                    const double y[3] = {rr * cos(phi), rr * sin(phi), sg * q->hz},
                                 n[3] = {0, 0, sg};
                    E += element(p, q, c, y, n, w * PI * q->r / 2 * rr, X, Y);
                }
                const double z = b * q->hz, n[3] = {cos(phi), sin(phi), 0},
                             y[3] = {q->r * n[0], q->r * n[1], z};
                E += element(p, q, c, y, n, w * PI * q->r * q->hz, X, Y);
            } else {
                const double ct = a, st = sqrt(1 - ct * ct), phi = PI * (b + 1);
                const double n[3] = {st * cos(phi), st * sin(phi), ct},
                             y[3] = {q->r * n[0], q->r * n[1], q->r * n[2]};
                E += element(p, q, c, y, n, w * PI * q->r * q->r, X, Y);
            }
        }
    return E;
}

/* Box, cylinder and sphere openings (LM-63's signs of the sizes): under each, at 0.35 m
 * above its top, the light, BSDF and MIS estimates meet the quadrature at five floor points
 * within 4 standard errors + 0.5 %; at 10 m each is the point to 0.5 %.  Their upper faces
 * carry a road light's sideways light too, which a flat opening would lose. */
static void solid_openings_meet_a_quadrature(void **state)
{
    (void)state;
    const struct {
        double w, l, h;
        solid q;
    } cases[3] = {{0.4, 0.6, 0.3, {0, 0.3, 0.2, 0.15, 0}},
                  {-0.4, -0.4, 0.5, {1, 0, 0, 0.25, 0.2}},
                  {-0.5, -0.5, -0.5, {2, 0, 0, 0, 0.25}}};
    static const lumis_photometric_shape shapes[3] = {LUMIS_SHAPE_BOX, LUMIS_SHAPE_CYLINDER,
                                                      LUMIS_SHAPE_SPHERE};
    static const int pxs[5][2] = {{W / 2, H / 2},
                                  {W / 2 - 3, H / 2},
                                  {W / 2 + 4, H / 2 + 2},
                                  {W / 2, H / 2 - 5},
                                  {W / 2 + 7, H / 2 - 6}};
    lumis_scene *s = floor_scene(0);
    for (int k = 0; k < 3; k++) {
        pg_ies_spec spec = {
            PG_ROAD, 0.8, "IESNA:LM-63-2002", 1,          91,         0, 90, 73, 0, 360,
            0,       0,   cases[k].w,         cases[k].l, cases[k].h, 2};
        lumis_photometric_file *f = load(&spec);
        lumis_photometric_info info;
        lumis_photometric_get_info(f->model, &info);
        assert_int_equal(info.shape, shapes[k]);
        const solid *q = &cases[k].q;
        const double top = q->kind == 2 ? q->r : q->hz;
        lumis_photometric_instance in = {0};
        in.photometric = f->model;
        in.area = 1;
        in.placement.t[0] = 0.05;
        in.placement.t[1] = -0.1;
        in.placement.t[2] = 0.35 + top;
        const double c[3] = {in.placement.t[0], in.placement.t[1], in.placement.t[2]};
        const lumis_estimator ests[3] = {LUMIS_ESTIMATOR_LIGHT, LUMIS_ESTIMATOR_BSDF,
                                         LUMIS_ESTIMATOR_MIS};
        for (int e = 0; e < 3; e++) {
            enum { RUNS = 6 };
            double sum[5] = {0}, sum2[5] = {0};
            for (int r = 0; r < RUNS; r++) {
                lumis_image *img =
                    render(s, &in, 1, e == 1 ? 256 : 64, ests[e], 1, 40 + (unsigned long long)r);
                for (int t = 0; t < 5; t++) {
                    const double v = px(img, pxs[t][0], pxs[t][1]);
                    sum[t] += v;
                    sum2[t] += v * v;
                }
                lumis_image_destroy(img);
            }
            for (int t = 0; t < 5; t++) {
                double X, Y;
                floor_point(pxs[t][0], pxs[t][1], &X, &Y);
                const double want = solid_illuminance(f->model, q, c, X, Y) / PI;
                const double mean = sum[t] / RUNS,
                             se = sqrt(fmax(0, sum2[t] / RUNS - mean * mean) / (RUNS - 1));
                if (fabs(mean - want) > 4 * se + 5e-3 * want)
                    fail_msg("%s, estimator %d, pixel %d: %g +- %g, quadrature %g",
                             lumis_photometric_shape_name(shapes[k]), e, t, mean, se, want);
            }
        }
        /* far away, the point */
        in.placement.t[2] = 10;
        double m_area, se_area, m_point, se_point;
        image_mean(s, &in, LUMIS_ESTIMATOR_LIGHT, 16, 8, 0, &m_area, &se_area);
        in.area = 0;
        image_mean(s, &in, LUMIS_ESTIMATOR_LIGHT, 1, 2, 0, &m_point, &se_point);
        if (fabs(m_area - m_point) > 4 * se_area + 2e-3 * m_point)
            fail_msg("%s at 10 m: %g +- %g, the point %g", lumis_photometric_shape_name(shapes[k]),
                     m_area, se_area, m_point);
        lumis_photometric_file_destroy(f);
    }
    lumis_scene_destroy(s);
}

/* A box seen only from its top: a fixture turned upside down over the floor shows the floor
 * its local +z face and never its -z face, the last of the six, whose weight is then zero
 * (the face choice must skip it).  And a box of zero length is refused by name, as a
 * rectangle of zero length is. */
static void box_faces_and_degenerate_boxes(void **state)
{
    (void)state;
    lumis_scene *s = floor_scene(0);
    pg_ies_spec spec = {PG_ROAD, 0.8, "IESNA:LM-63-2002", 1, 91, 0, 180, 73, 0, 360, 0, 0, 0.4, 0.6,
                        0.3,     2};
    lumis_photometric_file *f = load(&spec);
    lumis_photometric_info info;
    lumis_photometric_get_info(f->model, &info);
    assert_int_equal(info.shape, LUMIS_SHAPE_BOX);
    lumis_photometric_instance in = {0};
    in.photometric = f->model;
    in.area = 1;
    in.placement = lumis_rigid_identity();
    in.placement.r[4] = -1.0; /* a half turn about x: the aim (local -z) points up */
    in.placement.r[8] = -1.0;
    in.placement.t[2] = 1.0;
    lumis_image *img = render(s, &in, 1, 4, LUMIS_ESTIMATOR_LIGHT, 1, 3);
    for (int k = 0; k < W * H * 3; k++)
        assert_true(isfinite(img->pixels[k]) && img->pixels[k] >= 0);
    lumis_image_destroy(img);
    lumis_photometric_file_destroy(f);
    /* a box of zero length, made through the descriptor */
    static const double v[3] = {0, 45, 90}, h[1] = {0}, cd[3] = {100, 80, 0};
    lumis_photometric_desc d = {0};
    d.type = LUMIS_PHOTOMETRIC_C;
    d.nv = 3;
    d.nh = 1;
    d.v_deg = v;
    d.h_deg = h;
    d.candela = cd;
    d.shape = LUMIS_SHAPE_BOX;
    d.width = 0.2;
    d.length = 0.0;
    d.height = 0.1;
    lumis_photometric *p = NULL;
    assert_int_equal(lumis_photometric_create(&d, NULL, &p), LUMIS_OK); /* a table may say so */
    {
        lumis_photometric_instance z = {0};
        z.photometric = p;
        z.area = 1;
        z.placement = lumis_rigid_identity();
        z.placement.t[2] = 1.0;
        lumis_photometric_lighting pl = {&z, 1};
        lumis_render_desc rd = {0};
        rd.camera = &cam;
        rd.lighting.kind = LUMIS_LIGHTING_PHOTOMETRIC;
        rd.lighting.photometric = &pl;
        rd.spp = 1;
        rd.threads = 1;
        tu_sink sink;
        tu_sink_init(&sink);
        rd.errors = sink.sink;
        lumis_image *bad = NULL;
        assert_int_equal(lumis_render(s, &rd, &bad, NULL), LUMIS_ERR_INVALID_ARGUMENT);
        assert_null(bad);
        lumis_photometric_destroy(p);
    }
    lumis_scene_destroy(s);
}

/* ---- aiming (lumis_photometric_orient) --------------------------------------------------- */

static const lumis_photometric_type types[3] = {LUMIS_PHOTOMETRIC_C, LUMIS_PHOTOMETRIC_B,
                                                LUMIS_PHOTOMETRIC_A};

/* The unit aim tilted t degrees from straight down towards azimuth p (p 0: +x, 90: +z). */
static lumis_vec3 tilted_aim(double t_deg, double p_deg)
{
    const double t = t_deg * PI / 180, p = p_deg * PI / 180;
    return (lumis_vec3){(float)(sin(t) * cos(p)), (float)-cos(t), (float)(sin(t) * sin(p))};
}

static void orient(lumis_photometric_type type, lumis_vec3 aim, const lumis_vec3 *up, double roll,
                   double R[9])
{
    if (lumis_photometric_orient(type, aim, up, roll, R) != LUMIS_OK)
        fail_msg("orient type %d (%g, %g, %g) roll %g refused", (int)type, aim.x, aim.y, aim.z,
                 roll);
}

/* R is a proper rotation (orthonormal, det +1) that takes local -z to the unit `aim`. */
static void assert_frame(const double R[9], lumis_vec3 aim)
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            const double d = R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j];
            if (fabs(d - (i == j)) > 1e-12) fail_msg("columns %d, %d: dot %g", i, j, d);
        }
    const double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                       R[2] * (R[3] * R[7] - R[4] * R[6]);
    if (fabs(det - 1) > 1e-12) fail_msg("det %g", det);
    const double n = sqrt((double)aim.x * aim.x + (double)aim.y * aim.y + (double)aim.z * aim.z);
    if (fabs(-R[2] - aim.x / n) + fabs(-R[5] - aim.y / n) + fabs(-R[8] - aim.z / n) > 1e-12)
        fail_msg("R (0, 0, -1) = (%g, %g, %g), aim (%g, %g, %g)", -R[2], -R[5], -R[8], aim.x, aim.y,
                 aim.z);
}

static double frame_distance(const double A[9], const double B[9])
{
    double m = 0;
    for (int k = 0; k < 9; k++) m = fmax(m, fabs(A[k] - B[k]));
    return m;
}

/* Ry(theta) M, theta about +y (theta -90: +x to +z). */
static void turn_y(double theta_deg, const double M[9], double out[9])
{
    const double t = theta_deg * PI / 180, c = cos(t), s = sin(t);
    for (int j = 0; j < 3; j++) {
        out[j] = c * M[j] + s * M[6 + j];
        out[3 + j] = M[3 + j];
        out[6 + j] = -s * M[j] + c * M[6 + j];
    }
}

static lumis_vec3 turn_y_vec(double theta_deg, lumis_vec3 v)
{
    const double t = theta_deg * PI / 180, c = cos(t), s = sin(t);
    return (lumis_vec3){(float)(c * v.x + s * v.z), v.y, (float)(-s * v.x + c * v.z)};
}

/* The frame of every type: a proper rotation taking -z to the aim; continuous along tilts
 * from straight down to nearly straight up in many azimuths, along azimuths at many tilts
 * (across the ~64 degrees where the old frame jumped a quarter turn) and along rolls, a
 * step of 0.25 degrees moving it by O(step); defined straight up and down; `up` honoured and
 * refused along the aim; a floodlight's yoke keeps its lateral axis horizontal and turns
 * with a turn about y; a downlight keeps its C0 as it tilts, so that tilted towards +z it
 * is tilted towards +x and turned about y up to a quarter roll. */
static void orientation_is_a_continuous_explicit_frame(void **state)
{
    (void)state;
    const double step = 0.25, rad = step * PI / 180;
    const double azimuths[] = {0, 30, 90, 135, 200, 270, 333};
    const double rolls[] = {0, 37, -120};
    for (int ty = 0; ty < 3; ty++)
        for (int r = 0; r < 3; r++) {
            for (int ia = 0; ia < 7; ia++) { /* along tilts */
                double prev[9] = {0}, R[9];
                for (int k = 0; k <= 4 * 179; k++) {
                    const double t = k * step;
                    if (types[ty] != LUMIS_PHOTOMETRIC_C && k == 0) continue; /* the yoke's pole */
                    const lumis_vec3 a = tilted_aim(t, azimuths[ia]);
                    orient(types[ty], a, NULL, rolls[r], R);
                    assert_frame(R, a);
                    if (k > 1 && frame_distance(R, prev) > 2.5 * rad)
                        fail_msg("type %d, azimuth %g, roll %g: tilt %g to %g moves the frame "
                                 "by %g",
                                 (int)types[ty], azimuths[ia], rolls[r], t - step, t,
                                 frame_distance(R, prev));
                    memcpy(prev, R, sizeof R);
                }
            }
            const double tilts[] = {0.5, 10, 45, 64, 64.2, 65, 90, 120, 170, 179.5};
            for (int it = 0; it < 10; it++) { /* along azimuths */
                double prev[9] = {0}, R[9];
                for (int k = 0; k <= 4 * 360; k++) {
                    const lumis_vec3 a = tilted_aim(tilts[it], k * step);
                    orient(types[ty], a, NULL, rolls[r], R);
                    assert_frame(R, a);
                    if (k > 0 && frame_distance(R, prev) > 2.5 * rad)
                        fail_msg("type %d, tilt %g, roll %g: azimuth %g to %g moves the frame "
                                 "by %g",
                                 (int)types[ty], tilts[it], rolls[r], (k - 1) * step, k * step,
                                 frame_distance(R, prev));
                    memcpy(prev, R, sizeof R);
                }
            }
        }
    /* along rolls */
    for (int ty = 0; ty < 3; ty++) {
        double prev[9] = {0}, R[9];
        const lumis_vec3 a = tilted_aim(64.1, 0);
        for (int k = 0; k <= 4 * 360; k++) {
            orient(types[ty], a, NULL, k * step - 180, R);
            assert_frame(R, a);
            if (k > 0) assert_true(frame_distance(R, prev) <= 1.01 * rad);
            memcpy(prev, R, sizeof R);
        }
    }
    /* straight down and up: defined, C0 (or the top) +x; a type C fixture hangs with C90 -z */
    const lumis_vec3 down = {0, -1, 0}, upward = {0, 2, 0};
    const double hang[9] = {1, 0, 0, 0, 0, 1, 0, -1, 0}, flip[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};
    for (int ty = 0; ty < 3; ty++) {
        double R[9];
        orient(types[ty], down, NULL, 0, R);
        assert_true(frame_distance(R, hang) < 1e-15);
        orient(types[ty], upward, NULL, 0, R);
        assert_true(frame_distance(R, flip) < 1e-15);
        /* nearly straight up, still a rotation */
        const lumis_vec3 near_up = {1e-7f, 1, -3e-8f};
        orient(types[ty], near_up, NULL, 10, R);
        assert_frame(R, near_up);
    }
    /* type C: C0 stays +x tilting towards +z; follows the tilt towards +x */
    {
        double R[9];
        orient(LUMIS_PHOTOMETRIC_C, tilted_aim(15, 90), NULL, 0, R);
        assert_true(fabs(R[0] - 1) < 1e-12);
        orient(LUMIS_PHOTOMETRIC_C, tilted_aim(15, 0), NULL, 0, R);
        assert_true(fabs(R[0] - cos(15 * PI / 180)) < 1e-7 &&
                    fabs(R[3] - sin(15 * PI / 180)) < 1e-7);
    }
    /* rotations of each other about y: the whole aim turned; a floodlight as it is, a
     * downlight with its C0 (`up`) turned too, or rolled a quarter turn back */
    for (int ty = 0; ty < 3; ty++)
        for (int k = 0; k < 12; k++) {
            const double t = 3 + 14.5 * k, p = 17.0 * k - 40, turn = k == 0 ? -90 : 31.0 * k;
            const lumis_vec3 a = tilted_aim(t, p), b = turn_y_vec(turn, a);
            const lumis_vec3 u = {0.3f, 0.9f, -0.2f}, ub = turn_y_vec(turn, u);
            double Ra[9], Rb[9], Rt[9];
            orient(types[ty], a, &u, 25, Ra);
            orient(types[ty], b, &ub, 25, Rb);
            turn_y(turn, Ra, Rt);
            assert_true(frame_distance(Rt, Rb) < 1e-6);
            orient(types[ty], a, NULL, 25, Ra);
            turn_y(turn, Ra, Rt);
            if (types[ty] != LUMIS_PHOTOMETRIC_C) {
                orient(types[ty], b, NULL, 25, Rb);
                if (frame_distance(Rt, Rb) > 1e-6)
                    fail_msg("type %d: tilt %g azimuth %g turned %g: %g", (int)types[ty], t, p,
                             turn, frame_distance(Rt, Rb));
            } else {
                orient(types[ty], b, NULL, 25 + turn, Rb);
                if (frame_distance(Rt, Rb) > 1e-6)
                    fail_msg("type C: tilt %g azimuth %g turned %g: %g", t, p, turn,
                             frame_distance(Rt, Rb));
            }
        }
    { /* the case: 15 degrees towards +x and towards +z */
        double Rx[9], Rz[9], Rt[9];
        orient(LUMIS_PHOTOMETRIC_C, tilted_aim(15, 0), NULL, 0, Rx);
        orient(LUMIS_PHOTOMETRIC_C, tilted_aim(15, 90), NULL, -90, Rz);
        turn_y(-90, Rx, Rt);
        assert_true(frame_distance(Rt, Rz) < 1e-6);
        orient(LUMIS_PHOTOMETRIC_C, tilted_aim(15, 90), NULL, 0, Rz); /* not without the roll */
        assert_true(frame_distance(Rt, Rz) > 0.9);
    }
    /* the yoke: lateral axis horizontal, the top above the aim, for any aim but the poles */
    for (int k = 1; k < 180; k += 7)
        for (int ty = 1; ty < 3; ty++) {
            double R[9];
            orient(types[ty], tilted_aim(k, 11.0 * k), NULL, 0, R);
            assert_true(fabs(R[4]) < 1e-12 && R[3] > 0);
        }
    /* `up`: local +x as close to it as the aim allows */
    {
        const lumis_vec3 a = tilted_aim(40, 70), u = {0.2f, 0.3f, 0.9f};
        double R[9];
        orient(LUMIS_PHOTOMETRIC_B, a, &u, 0, R);
        assert_frame(R, a);
        const double ua = (u.x * -R[2] + u.y * -R[5] + u.z * -R[8]);
        double px[3] = {u.x + ua * R[2], u.y + ua * R[5], u.z + ua * R[8]};
        const double n = sqrt(px[0] * px[0] + px[1] * px[1] + px[2] * px[2]);
        assert_true(fabs(px[0] / n - R[0]) + fabs(px[1] / n - R[3]) + fabs(px[2] / n - R[6]) <
                    1e-7);
        /* perpendicular to the aim already: exactly it */
        const lumis_vec3 z = {0, 0, 1};
        orient(LUMIS_PHOTOMETRIC_C, down, &z, 0, R);
        assert_true(fabs(R[6] - 1) < 1e-15);
    }
    /* refusals */
    double R[9];
    const lumis_vec3 zero = {0, 0, 0}, along = {0, -3, 0}, against = {1e-8f, 1, 0},
                     nan3 = {NAN, 0, 0};
    assert_int_equal(lumis_photometric_orient(LUMIS_PHOTOMETRIC_C, down, &along, 0, R),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_photometric_orient(LUMIS_PHOTOMETRIC_A, down, &against, 0, R),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_photometric_orient(LUMIS_PHOTOMETRIC_B, down, &zero, 0, R),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_photometric_orient(LUMIS_PHOTOMETRIC_B, down, &nan3, 0, R),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_photometric_orient(LUMIS_PHOTOMETRIC_C, nan3, NULL, 0, R),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_photometric_orient(LUMIS_PHOTOMETRIC_C, down, NULL, NAN, R),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_photometric_orient((lumis_photometric_type)0, down, NULL, 0, R),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_photometric_orient((lumis_photometric_type)4, down, NULL, 0, R),
                     LUMIS_ERR_INVALID_ARGUMENT);
}

/* ---- aimed fixtures over a floor (y up) ------------------------------------------------- */

#define N 33 /* odd: the centre pixel looks straight down at the origin */

/* The floor y = 0 (white Lambertian), seen straight down from (0, 6, 0) over 90 degrees:
 * pixel (i, j) is the floor point (X, Z) = 6 (2 (i + 1/2) / N - 1, 2 (j + 1/2) / N - 1). */
static lumis_scene *yfloor(void)
{
    lumis_object o;
    memset(&o, 0, sizeof o);
    o.type = LUMIS_OBJECT_PLANE;
    o.normal = (lumis_vec3){0, 1, 0};
    o.size = 100.0f;
    o.material.type = LUMIS_BSDF_LAMBERT;
    o.material.diffuse = (lumis_rgb){1, 1, 1};
    lumis_scene *s = NULL;
    assert_int_equal(lumis_scene_create(&o, 1, NULL, &s), LUMIS_OK);
    return s;
}

static lumis_image *render_above(const lumis_scene *s, const lumis_photometric_instance *in)
{
    static const lumis_camera top = {{0, 6, 0}, {0, 0, 0}, {0, 0, -1}, 90.0f, N, N};
    lumis_photometric_lighting pl = {in, 1};
    lumis_render_desc d = {0};
    d.camera = &top;
    d.lighting.photometric = &pl;
    d.lighting.kind = LUMIS_LIGHTING_PHOTOMETRIC;
    d.spp = 1;
    d.pixel_centers = 1;
    d.threads = 1;
    lumis_image *img = NULL;
    tu_sink sink;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    if (lumis_render(s, &d, &img, NULL) != LUMIS_OK) fail_msg("render: %s", sink.last);
    return img;
}

static double at(const lumis_image *img, int i, int j)
{
    return img->pixels[3 * (j * N + i) + 1];
}

/* The fixture at height h above the origin, aimed by lumis_photometric_orient. */
static lumis_image *aimed(const lumis_scene *s, const lumis_photometric *p, double h,
                          lumis_vec3 aim, const lumis_vec3 *up, double roll)
{
    lumis_photometric_info info;
    lumis_photometric_get_info(p, &info);
    lumis_photometric_instance in = {0};
    in.photometric = p;
    in.placement.t[1] = h;
    orient(info.type, aim, up, roll, in.placement.r);
    return render_above(s, &in);
}

/* sum |a - b| / sum a over the image */
static double image_change(const lumis_image *a, const lumis_image *b)
{
    double num = 0, den = 0;
    for (int k = 0; k < N * N; k++) {
        num += fabs(a->pixels[3 * k + 1] - b->pixels[3 * k + 1]);
        den += a->pixels[3 * k + 1];
    }
    return num / den;
}

/* An asymmetric road light (type C) and floodlights wide across and narrow up and down
 * (types B and A) over a floor, rendered at many tilts, azimuths and rolls:
 *  - continuity: half a degree more tilt, azimuth or roll changes the image by little, and an
 *    eighth of a degree by about a quarter of that (O(step)), across the tilt of ~64 degrees
 *    where the old frame turned a quarter turn;
 *  - rotation: the fixture turned about y as a whole (aim, and a type C's C0 by its roll)
 *    gives the image turned, pixel by pixel;
 *  - the inverse-square law: at twice the height, the floor at twice the offset from the
 *    foot is lit a quarter as much (same directions, twice the distance), pixel by pixel. */
static void aimed_fixtures_over_a_floor(void **state)
{
    (void)state;
    pg_ies_spec road = {PG_ROAD, 0.8, "IESNA:LM-63-2002", 1, 91, 0, 90, 73, 0, 360, 0, 0, 0, 0,
                        0,       2};
    pg_ies_spec flood_b = {
        PG_FLOOD, 30, "IESNA:LM-63-2002", 2, 181, -90, 90, 181, -90, 90, 0, 0, 0, 0, 0, 2};
    pg_ies_spec flood_a = flood_b;
    flood_a.type = 3;
    lumis_photometric_file *f[3] = {load(&road), load(&flood_b), load(&flood_a)};
    lumis_scene *s = yfloor();
    const double tilts[] = {15, 40, 64, 75}; /* 64 to 64.5: the old jump at 64.16 */
    const double azimuths[] = {0, 90, 210};
    const double rolls[] = {0, 30};
    double worst[3] = {0, 0, 0};
    for (int q = 0; q < 3; q++) {
        const lumis_photometric *p = f[q]->model;
        for (int it = 0; it < 4; it++)
            for (int ia = 0; ia < 3; ia++)
                for (int ir = 0; ir < 2; ir++) {
                    const double t = tilts[it], az = azimuths[ia], ro = rolls[ir];
                    lumis_image *base = aimed(s, p, 1.5, tilted_aim(t, az), NULL, ro);
                    lumis_image *moved[3][2];
                    const double dd[2] = {0.5, 0.125};
                    for (int k = 0; k < 2; k++) {
                        moved[0][k] = aimed(s, p, 1.5, tilted_aim(t + dd[k], az), NULL, ro);
                        moved[1][k] = aimed(s, p, 1.5, tilted_aim(t, az + dd[k]), NULL, ro);
                        moved[2][k] = aimed(s, p, 1.5, tilted_aim(t, az), NULL, ro + dd[k]);
                    }
                    for (int m = 0; m < 3; m++) {
                        const double big = image_change(base, moved[m][0]),
                                     small = image_change(base, moved[m][1]);
                        worst[q] = fmax(worst[q], big);
                        if (!(big < 0.06) || !(small < 0.35 * big + 1e-5))
                            fail_msg("fixture %d, tilt %g azimuth %g roll %g, change %d: "
                                     "0.5 degrees %g, 0.125 degrees %g",
                                     q, t, az, ro, m, big, small);
                        lumis_image_destroy(moved[m][0]);
                        lumis_image_destroy(moved[m][1]);
                    }
                    /* turned a quarter turn about y: aim towards az + 90 (x to z), a type C
                     * rolled back a quarter turn; pixel (i, j) goes to (N - 1 - j, i) */
                    lumis_image *turned =
                        aimed(s, p, 1.5, tilted_aim(t, az + 90), NULL, q == 0 ? ro - 90 : ro);
                    double peak = 0;
                    for (int k = 0; k < N * N; k++) peak = fmax(peak, base->pixels[3 * k + 1]);
                    for (int j = 0; j < N; j++)
                        for (int i = 0; i < N; i++)
                            if (fabs(at(turned, N - 1 - j, i) - at(base, i, j)) > 1e-4 * peak)
                                fail_msg("fixture %d, tilt %g azimuth %g: turned (%d, %d) %g, "
                                         "not %g",
                                         q, t, az, i, j, at(turned, N - 1 - j, i), at(base, i, j));
                    lumis_image_destroy(turned);
                    /* twice as high: (16 + k, 16 + m) at h is (16 + 2k, 16 + 2m) at 2h */
                    lumis_image *high = aimed(s, p, 3.0, tilted_aim(t, az), NULL, ro);
                    for (int m = -8; m <= 8; m++)
                        for (int k = -8; k <= 8; k++) {
                            const double e1 = at(base, 16 + k, 16 + m),
                                         e2 = at(high, 16 + 2 * k, 16 + 2 * m);
                            if (fabs(4 * e2 - e1) > 1e-4 * e1 + 1e-6 * peak)
                                fail_msg("fixture %d, tilt %g azimuth %g roll %g: (%d, %d) at "
                                         "1.5 m %g, at 3 m %g",
                                         q, t, az, ro, k, m, e1, e2);
                        }
                    lumis_image_destroy(high);
                    lumis_image_destroy(base);
                }
    }
    print_message("worst change of the image for half a degree: road %.4f, B %.4f, A %.4f\n",
                  worst[0], worst[1], worst[2]);
    /* straight below: E = I(0) / h^2 */
    for (int q = 0; q < 3; q++) {
        const lumis_vec3 down = {0, -1, 0}, ax = {0, 0, -1};
        lumis_image *a = aimed(s, f[q]->model, 1.5, down, NULL, 0),
                    *b = aimed(s, f[q]->model, 3.0, down, NULL, 0);
        const double I0 = lumis_photometric_intensity(f[q]->model, ax);
        assert_true(fabs(at(a, 16, 16) / (I0 / (1.5 * 1.5) / PI) - 1) < 1e-5);
        assert_true(fabs(at(a, 16, 16) / at(b, 16, 16) - 4) < 1e-4);
        lumis_image_destroy(a);
        lumis_image_destroy(b);
    }
    lumis_scene_destroy(s);
    for (int q = 0; q < 3; q++) lumis_photometric_file_destroy(f[q]);
}

/* World illuminance at x on a surface of normal n from a fixture placed by R at t (the point
 * model, lumis_photometric_irradiance in its frame). */
static double world_irradiance(const lumis_photometric *p, const double R[9], const double t[3],
                               const double x[3], const double n[3])
{
    const double w[3] = {x[0] - t[0], x[1] - t[1], x[2] - t[2]};
    lumis_vec3 xl, nl;
    xl.x = (float)(R[0] * w[0] + R[3] * w[1] + R[6] * w[2]);
    xl.y = (float)(R[1] * w[0] + R[4] * w[1] + R[7] * w[2]);
    xl.z = (float)(R[2] * w[0] + R[5] * w[1] + R[8] * w[2]);
    nl.x = (float)(R[0] * n[0] + R[3] * n[1] + R[6] * n[2]);
    nl.y = (float)(R[1] * n[0] + R[4] * n[1] + R[7] * n[2]);
    nl.z = (float)(R[2] * n[0] + R[5] * n[1] + R[8] * n[2]);
    double E = 0;
    assert_int_equal(lumis_photometric_irradiance(p, 0, xl, nl, 0, &E), LUMIS_OK);
    return E;
}

/* A near-field fixture (lumis_photometric_instance.light_field) over a floor, seen close:
 * a 0.2 m Lambertian disk 0.15 m up, whose field is used within near_until (0.2 m), blended
 * out to far_from (0.29 m) and the point beyond.  Where the field has a share, the render's
 * mean over the floor is lumis_photometric_near_irradiance's (four seeds, within four
 * standard errors); where it has none, every pixel is the point fixture's bit for bit. */
/* A near-field fixture f (field lum, report rep) at height h above the floor, its aim turned
 * tilt_deg from straight down about y, seen by a camera 1 above the floor: the render's sum
 * over the pixels where the field has a share (w > 0) against the model
 * (lumis_photometric_near_irradiance / pi on the white floor), within 4 standard errors of
 * 4 runs; every other pixel equals the point fixture's render bit for bit.  Returns how
 * many pixels had a share; *point_px those without. */
static int near_field_matches_model(const lumis_photometric_file *f, const lumis_luminaire *lum,
                                    const lumis_photometric_light_field_report *rep, double h,
                                    double tilt_deg, int *point_px)
{
    lumis_scene *s = floor_scene(0);
    const double c = cos(tilt_deg * PI / 180), sn = sin(tilt_deg * PI / 180);
    lumis_photometric_instance in = {0};
    in.photometric = f->model;
    const double R[9] = {c, 0, sn, 0, 1, 0, -sn, 0, c}; /* about y: local -z to (-sn, 0, -c) */
    memcpy(in.placement.r, R, sizeof R);
    in.placement.t[2] = h;
    const lumis_camera close = {{0, 0, 1}, {0, 0, 0}, {0, 1, 0}, 60.0f, W, H};
    lumis_photometric_lighting pl = {&in, 1};
    lumis_render_desc d = {0};
    d.camera = &close;
    d.lighting.kind = LUMIS_LIGHTING_PHOTOMETRIC;
    d.lighting.photometric = &pl;
    d.pixel_centers = 1;
    d.threads = 1;
    d.spp = 1;
    tu_sink sink;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    lumis_image *point = NULL;
    if (lumis_render(s, &d, &point, NULL) != LUMIS_OK) fail_msg("%s", sink.last);
    in.light_field = lum;
    in.light_field_report = rep;
    /* the model at each pixel's floor point (in the fixture's frame: R^T (p - t)), and the
     * field's weight there */
    const double th = tan(30.0 * PI / 180.0);
    double model = 0, wsum[W * H];
    const lumis_vec3 n = {(float)R[6], (float)R[7], (float)R[8]}; /* R^T (0, 0, 1) */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const double X = ((x + 0.5) / W * 2.0 - 1.0) * th, Y = (1.0 - (y + 0.5) / H * 2.0) * th;
            wsum[y * W + x] = lumis_photometric_near_weight(rep, sqrt(X * X + Y * Y + h * h));
            if (!(wsum[y * W + x] > 0)) continue;
            const double p[3] = {X, Y, -h};
            const lumis_vec3 xl = {(float)(R[0] * p[0] + R[3] * p[1] + R[6] * p[2]),
                                   (float)(R[1] * p[0] + R[4] * p[1] + R[7] * p[2]),
                                   (float)(R[2] * p[0] + R[5] * p[1] + R[8] * p[2])};
            double E = 0;
            assert_int_equal(lumis_photometric_near_irradiance(f->model, lum, rep, xl, n, &E),
                             LUMIS_OK);
            model += E / PI;
        }
    enum { RUNS = 4 };
    double sum = 0, sum2 = 0;
    int field_px = 0;
    *point_px = 0;
    d.spp = 16;
    for (int r = 0; r < RUNS; r++) {
        d.seed = 7 + (unsigned long long)r;
        lumis_image *img = NULL;
        if (lumis_render(s, &d, &img, NULL) != LUMIS_OK) fail_msg("%s", sink.last);
        double m = 0;
        for (int k = 0; k < W * H; k++) {
            const double v = img->pixels[3 * k + 1];
            if (wsum[k] > 0) {
                m += v;
                field_px += r == 0;
            } else {
                if (v != point->pixels[3 * k + 1])
                    fail_msg("pixel %d (no field share): %.9g, the point fixture %.9g", k, v,
                             point->pixels[3 * k + 1]);
                *point_px += r == 0;
            }
        }
        sum += m;
        sum2 += m * m;
        lumis_image_destroy(img);
    }
    const double mean = sum / RUNS, se = sqrt(fmax(0.0, sum2 / RUNS - mean * mean) / (RUNS - 1));
    if (!(fabs(mean - model) <= 4 * se + 2e-3 * model))
        fail_msg("near-field fixture (h %g, tilt %g) over %d pixels: %g +- %g, its model %g", h,
                 tilt_deg, field_px, mean, se, model);
    lumis_image_destroy(point);
    lumis_scene_destroy(s);
    return field_px;
}

/* A near-field fixture renders its model: hanging 0.15 above the floor (the field, the blend
 * and the point all seen), and lower (0.1) and tilted 60 degrees, so that floor points within
 * the field's reach lie beyond its cone, where the residual table gives their light. */
static void a_near_field_fixture_renders_its_model(void **state)
{
    (void)state;
    pg_ies_spec spec = {PG_LAMBERT, 0, "IESNA:LM-63-2002", 1, 91, 0, 90, 1, 0, 0, 0, 0, -0.2, -0.2,
                        0,          2};
    lumis_photometric_file *f = load(&spec);
    lumis_photometric_light_field_report rep;
    lumis_luminaire *lum = NULL;
    assert_int_equal(lumis_luminaire_from_photometric(f->model, NULL, NULL, &lum, &rep), LUMIS_OK);
    assert_true(rep.near_until > 0.15 && rep.far_from < 0.5);
    int point_px = 0;
    assert_true(near_field_matches_model(f, lum, &rep, 0.15, 0.0, &point_px) > 20 && point_px > 20);
    assert_true(near_field_matches_model(f, lum, &rep, 0.1, 60.0, &point_px) > 20);
    lumis_scene *s = floor_scene(0);
    lumis_photometric_instance in = {0};
    in.photometric = f->model;
    in.placement.t[2] = 0.15;
    in.light_field = lum;
    in.light_field_report = &rep;
    lumis_photometric_lighting pl = {&in, 1};
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.lighting.kind = LUMIS_LIGHTING_PHOTOMETRIC;
    d.lighting.photometric = &pl;
    d.spp = 1;
    d.threads = 1;
    tu_sink sink;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    /* what it refuses, naming the field */
    in.area = 1;
    tu_sink_init(&sink);
    lumis_image *img = NULL;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "light_field"));
    in.area = 0;
    lumis_photometric_light_field_report other = rep;
    other.flux *= 2;
    in.light_field_report = &other;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "not the table's"));
    in.light_field_report = NULL;
    assert_int_equal(lumis_render(s, &d, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "needs both"));
    lumis_luminaire_destroy(lum);
    lumis_scene_destroy(s);
    lumis_photometric_file_destroy(f);
}

/* A floodlight (types B and A) wide across (cos H) and narrow up and down (cos^30 V: a 25
 * degree beam), panned to many azimuths (towards +x, +z and between) and tilted up and down,
 * lights a wall facing it in a horizontal band: 1.5 m beside the aimed point on the wall
 * 5 m away it gives more than 70 % of the aimed point's light, 1.5 m above or below less
 * than 35 %.  Lying on its side (as the old frame laid it unless it was aimed towards +x), it
 * would be the other way round. */
static void floodlights_light_a_horizontal_band(void **state)
{
    (void)state;
    for (int type = 2; type <= 3; type++) {
        pg_ies_spec flood = {
            PG_FLOOD, 30, "IESNA:LM-63-2002", type, 181, -90, 90, 181, -90, 90, 0, 0, 0, 0, 0, 2};
        lumis_photometric_file *f = load(&flood);
        const lumis_photometric *p = f->model;
        lumis_photometric_info info;
        lumis_photometric_get_info(p, &info);
        assert_int_equal((int)info.type, type == 2 ? LUMIS_PHOTOMETRIC_B : LUMIS_PHOTOMETRIC_A);
        for (int ia = 0; ia < 8; ia++)
            for (int ie = 0; ie < 3; ie++) {
                const double pan = 45.0 * ia * PI / 180, el = (-20.0 + 20 * ie) * PI / 180;
                /* the aim, its horizontal direction h and the wall's horizontal tangent s */
                const double h[3] = {cos(pan), 0, sin(pan)}, sd[3] = {-sin(pan), 0, cos(pan)};
                const double a[3] = {cos(el) * h[0], sin(el), cos(el) * h[2]};
                const double t[3] = {0, 3, 0}, D = 5;
                double R[9];
                orient(info.type, (lumis_vec3){(float)a[0], (float)a[1], (float)a[2]}, NULL, 0, R);
                /* the wall: the plane through t + D h facing back, n = -h; the aimed point
                 * on it c = t + (D / cos el) a */
                const double n[3] = {-h[0], 0, -h[2]}, L = D / cos(el);
                const double c[3] = {t[0] + L * a[0], t[1] + L * a[1], t[2] + L * a[2]};
                const double side[3] = {c[0] + 1.5 * sd[0], c[1], c[2] + 1.5 * sd[2]},
                             above[3] = {c[0], c[1] + 1.5, c[2]},
                             below[3] = {c[0], c[1] - 1.5, c[2]};
                const double Ec = world_irradiance(p, R, t, c, n),
                             Es = world_irradiance(p, R, t, side, n),
                             Ea = world_irradiance(p, R, t, above, n),
                             Eb = world_irradiance(p, R, t, below, n);
                if (!(Ec > 0) || !(Es > 0.7 * Ec) || !(Ea < 0.35 * Ec) || !(Eb < 0.35 * Ec))
                    fail_msg("type %d panned %g tilted %g: centre %g, beside %g, above %g, "
                             "below %g",
                             type, pan * 180 / PI, el * 180 / PI, Ec, Es, Ea, Eb);
            }
        lumis_photometric_file_destroy(f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(illuminance_follows_the_inverse_square_law),
        cmocka_unit_test(rotational_symmetry_gives_a_symmetric_image),
        cmocka_unit_test(aim_and_shadows),
        cmocka_unit_test(an_opening_is_unbiased_and_far_away_a_point),
        cmocka_unit_test(rectangles_estimators_and_refusals),
        cmocka_unit_test(solid_openings_meet_a_quadrature),
        cmocka_unit_test(box_faces_and_degenerate_boxes),
        cmocka_unit_test(a_disk_meets_its_closed_form),
        cmocka_unit_test(orientation_is_a_continuous_explicit_frame),
        cmocka_unit_test(aimed_fixtures_over_a_floor),
        cmocka_unit_test(floodlights_light_a_horizontal_band),
        cmocka_unit_test(a_near_field_fixture_renders_its_model),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
