/* Representative light sets: median cut, variance minimisation, Wu's decomposition.
 * Conservation, regions, exact per-pixel lights, the threshold, k-means, the cut, bad
 * input (docs/lights.md). */
/* Oracles:
 * lumis_lights_median_cut — brute force: power conserved against a long-double pixel sum, solid
 *     angles sum to 4 pi, regions inside their cones, equal energy halves by Gauss-Legendre, the
 *     second split by priority; invariance: brightness x10 (check_set,
 *     median_cut_regions_have_equal_energy, the_second_split_takes_the_larger_priority,
 *     every_method_is_invariant_to_the_maps_brightness)
 * lumis_lights_variance_min — brute force: every split the least summed variance over all cuts,
 *     moments by quadrature; invariance: brightness
 *     (variance_min_splits_minimise_the_summed_variance,
 *     every_method_is_invariant_to_the_maps_brightness)
 * lumis_lights_decompose — brute force: emissive threshold a sorted percentile, Eq. 2's budget and
 *     min_share recomputed from the pixels, exactly K lights, power conserved, k-means's fixed
 *     point (every member nearest its own centroid, recomputed from exact pixel moments);
 *     statistical: seeds by energy (binomial bounds); invariance: Eq. 3 under 2^10 scale
 *     (emissive_threshold_is_a_brute_force_percentile, eq2_budget_from_the_pixels,
 *     kmeans_stops_at_a_fixed_point,
 *     min_share_on_one_map, the_cut_yields_exactly_k_lights, envdirect_seeds_follow_energy,
 *     eq3_is_invariant_to_the_maps_scale)
 * lumis_lights_fhis — statistical: points follow importance (2:1 halves), uniform per solid angle
 *     on a constant map; brute force: Penrose children tile their parent; power conserved with
 *     exactly K lights (fhis_points_follow_the_importance,
 *     fhis_points_are_uniform_on_a_constant_map,
 *     fhis_and_tmms_conserve_power_with_exactly_k_lights)
 * lumis_lights_tmms — brute force: power conserved with exactly K lights, pixel corners inside the
 *     light's cone; invariance: brightness x10 (fhis_and_tmms_conserve_power_with_exactly_k_lights,
 *     label_extents_cover_whole_pixels, every_method_is_invariant_to_the_maps_brightness)
 * lumis_light_set_get — brute force: per-light power, solid angle and pixel count recomputed from
 *     the labels (check_set)
 * lumis_light_set_get_info — brute force: count and total power against the pixel sum (check_set)
 * lumis_light_set_labels — brute force: every pixel labelled, inside its light's cone (check_set,
 *     label_extents_cover_whole_pixels)
 * lumis_light_set_sets — consistency: jittered sets keep the first set's pixels and powers, within
 *     jitter of its directions (check_set)
 * lumis_light_set_fold_below — brute force: each light's power its own plus the folded lights
 *     nearest to it, total unchanged (fold_below_conserves_power_into_the_nearest_light)
 * lumis_light_set_interleave_index — hand-worked: every set once per tile for 1 to 64 sets,
 *     periodic; 8 sets at (3, 1) is 7 (interleave_pattern_covers_every_set)
 * lumis_light_set_destroy — external: leaks seen by ASan and valgrind
 *     (every_method_conserves_power)
 * lumis_lights_by_name — consistency: bit for bit the method's own call; unknown names refused
 *     (methods_and_parameters_by_name)
 * lumis_lights_method_from_name — hand-worked: 9 names, "wu-is", "fhis"; "median", NULL name,
 *     NULL out refused
 *     (methods_and_parameters_by_name)
 * lumis_lights_method_names — hand-worked: 9 names, each known to lumis_lights_method_from_name
 *     (methods_and_parameters_by_name)
 * lumis_light_params_parse — hand-worked: NAME=VALUE pairs set lambda, mask, jitter, seed
 *     (methods_and_parameters_by_name)
 * lumis_light_params_format — hand-worked: "lambda=5,mask=radians,jitter=0.25,seed=9" in table
 *     order (methods_and_parameters_by_name)
 * lumis_light_params_check — hand-worked: a Wu parameter refused for median cut, with its name in
 *     the message (methods_and_parameters_by_name)
 * lumis_envmap_pixels — indirect: the pixel sums of check_set (map_power)
 * lumis_light_set_irradiance — closed form: the map's irradiance facing up and down, row by row
 *     (sin^2 bands); brute force: the set's sum over its lights, a tilted normal too
 *     (light_set_irradiance_against_closed_forms)
 */
#include "testutil.h"

#include "core/internal.h"
#include "lights/penrose.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

typedef lumis_status (*build_fn)(const lumis_envmap *, int count, lumis_light_set **);

/* ---- maps ------------------------------------------------------------------------------- */

static uint32_t hash(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

/* A sky: a gradient, texture, a sun of a few pixels and two smaller bright spots. */
static float sky_pixel(int w, int h, int i, int j, int c)
{
    double u = (i + 0.5) / w, v = (j + 0.5) / h;
    double base = (v < 0.5 ? 1.0 + 2.0 * (0.5 - v) : 0.3) * (c == 2 ? 1.3 : 1.0);
    base *= 0.8 + 0.4 * (double)(hash((uint32_t)(j * w + i) * 3u + (uint32_t)c) & 1023) / 1023.0;
    double du = u - 0.3, dv = v - 0.25;
    if (du * du + dv * dv < 0.0009) base += 5000.0;
    du = u - 0.8, dv = v - 0.4;
    if (du * du + dv * dv < 0.0004) base += 300.0 * (c + 1);
    du = u - 0.55, dv = v - 0.7;
    if (du * du + dv * dv < 0.0002) base += 150.0;
    return (float)base;
}

static lumis_envmap *make_env(int w, int h, float (*f)(int, int, int, int, int), float rot,
                              float scale)
{
    float *px = malloc((size_t)w * (size_t)h * 3 * sizeof(float));
    assert_non_null(px);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++)
            for (int c = 0; c < 3; c++)
                px[((size_t)j * (size_t)w + (size_t)i) * 3 + (size_t)c] = f(w, h, i, j, c);
    lumis_envmap_desc d = {0};
    d.pixels = px;
    d.width = w;
    d.height = h;
    d.rotation_deg = rot;
    d.scale = scale;
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_create(&d, &env), LUMIS_OK);
    free(px);
    return env;
}

static float const_pixel(int w, int h, int i, int j, int c)
{
    (void)w, (void)h, (void)i, (void)j, (void)c;
    return 0.5f;
}
static float black_pixel(int w, int h, int i, int j, int c)
{
    (void)w, (void)h, (void)i, (void)j, (void)c;
    return 0.0f;
}
/* Many scattered bright pixels: a hard case for k-means. */
static float speckle_pixel(int w, int h, int i, int j, int c)
{
    (void)h;
    uint32_t r = hash((uint32_t)(j * w + i));
    return (r % 37 == 0) ? (float)(50 + (r >> 20) % 400) : 0.2f + 0.1f * (float)c;
}

/* Bright exactly at the pixels the decomposition samples to place its percentile bound
 * on maps of 2^18 pixels (every 16th, from the 8th), each a different value, and dim
 * elsewhere: the bound lands over the true percentile. */
static float sample_trap_pixel(int w, int h, int i, int j, int c)
{
    (void)h;
    (void)c;
    const int p = j * w + i;
    return p % 16 == 8 ? 100.0f + (float)(p / 16) : 1.0f;
}

/* The luminance every method weighs pixels by (docs/lights.md). */
static float pixel_y(const lumis_envmap *env, int i, int j)
{
    const float *p =
        lumis_envmap_pixels(env) + ((size_t)j * (size_t)lumis_envmap_width(env) + (size_t)i) * 3;
    return (float)((double)lumis_envmap_scale(env) *
                   (0.2126 * (double)p[0] + 0.7152 * (double)p[1] + 0.0722 * (double)p[2]));
}

/* The map's sum(L Omega) per channel, in long double, pixel by pixel. */
static void map_power(const lumis_envmap *env, long double out[3])
{
    int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
    const float *p = lumis_envmap_pixels(env);
    out[0] = out[1] = out[2] = 0.0L;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++)
            for (int c = 0; c < 3; c++)
                out[c] += (long double)p[((size_t)j * (size_t)w + (size_t)i) * 3 + (size_t)c] *
                          (long double)lumis_envmap_pixel_solid_angle(env, j) *
                          (long double)lumis_envmap_scale(env);
}

/* ---- builders ----------------------------------------------------------------------- */

static lumis_status build_mc(const lumis_envmap *env, int k, lumis_light_set **out)
{
    lumis_median_cut_desc d = {0};
    d.count = k;
    return lumis_lights_median_cut(env, &d, out);
}
static lumis_status build_vm(const lumis_envmap *env, int k, lumis_light_set **out)
{
    lumis_variance_min_desc d = {0};
    d.count = k;
    return lumis_lights_variance_min(env, &d, out);
}
static lumis_status build_wu(const lumis_envmap *env, int k, lumis_light_set **out)
{
    lumis_decomp_desc d = {0};
    d.count = k;
    d.seed = 7;
    return lumis_lights_decompose(env, &d, out);
}
static lumis_status build_wu_cut_only(const lumis_envmap *env, int k, lumis_light_set **out)
{
    lumis_decomp_desc d = {0};
    d.count = k;
    d.threshold = 1e30f; /* no emissive pixel: the whole set is the cut */
    return lumis_lights_decompose(env, &d, out);
}

static lumis_status build_fhis(const lumis_envmap *env, int k, lumis_light_set **out)
{
    lumis_fhis_desc d = {0};
    d.count = k;
    d.seed = 3;
    return lumis_lights_fhis(env, &d, out);
}
static lumis_status build_tmms(const lumis_envmap *env, int k, lumis_light_set **out)
{
    lumis_tmms_desc d = {0};
    d.count = k;
    return lumis_lights_tmms(env, &d, out);
}

/* ---- the invariants every set must satisfy ------------------------------------------ */

/* The angle between a and b, neither necessarily of unit length: atan2 of the cross and
 * dot products, accurate for small angles too (acos of a dot product of float-rounded
 * directions is off by ~1e-4 rad at angles of 1e-3). */
static double angle(lumis_vec3 a, double b[3])
{
    const double x = a.x, y = a.y, z = a.z;
    const double cx = y * b[2] - z * b[1], cy = z * b[0] - x * b[2], cz = x * b[1] - y * b[0];
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), x * b[0] + y * b[1] + z * b[2]);
}

static void check_set(const lumis_light_set *set, const lumis_envmap *env)
{
    int w, h;
    const int32_t *lab = lumis_light_set_labels(set, &w, &h);
    assert_int_equal(w, lumis_envmap_width(env));
    assert_int_equal(h, lumis_envmap_height(env));
    const lumis_light *L;
    int n;
    assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
    assert_true(n >= 1);
    long double want[3];
    map_power(env, want);
    const lumis_light_set_info *info = lumis_light_set_get_info(set);
    assert_int_equal(info->count, n);
    /* Per-light sums recomputed from the labels. */
    long double *pw = calloc((size_t)n * 3, sizeof(long double));
    double *om = calloc((size_t)n, sizeof(double));
    int *cnt = calloc((size_t)n, sizeof(int));
    const float *px = lumis_envmap_pixels(env);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            int32_t k = lab[(size_t)j * (size_t)w + (size_t)i];
            assert_true(k >= 0 && k < n);
            cnt[k]++;
            om[k] += lumis_envmap_pixel_solid_angle(env, j);
            for (int c = 0; c < 3; c++)
                pw[3 * k + c] +=
                    (long double)px[((size_t)j * (size_t)w + (size_t)i) * 3 + (size_t)c] *
                    (long double)lumis_envmap_pixel_solid_angle(env, j) *
                    (long double)lumis_envmap_scale(env);
            /* The region lies inside the light's cone (pixel centre, float slack). */
            lumis_vec3 cd =
                lumis_envmap_uv_to_dir(env, (float)((i + 0.5) / w), (float)((j + 0.5) / h));
            double d[3] = {cd.x, cd.y, cd.z};
            assert_true(angle(L[k].dir, d) <= (double)L[k].extent + 1e-5);
        }
    double omega_sum = 0.0;
    for (int s = 0; s < lumis_light_set_sets(set); s++) {
        const lumis_light *Ls;
        int ns;
        assert_int_equal(lumis_light_set_get(set, s, &Ls, &ns), LUMIS_OK);
        assert_int_equal(ns, n);
        double tot[3] = {0, 0, 0};
        for (int k = 0; k < n; k++) {
            for (int c = 0; c < 3; c++) tot[c] += Ls[k].power[c];
            double len =
                sqrt((double)Ls[k].dir.x * Ls[k].dir.x + (double)Ls[k].dir.y * Ls[k].dir.y +
                     (double)Ls[k].dir.z * Ls[k].dir.z);
            assert_true(fabs(len - 1.0) < 1e-6);
            assert_int_equal(Ls[k].pixels, L[k].pixels);
            assert_true(Ls[k].power[0] == L[k].power[0] && Ls[k].solid_angle == L[k].solid_angle);
            /* Jittered copies stay within jitter (0.1) of the extent about the original. */
            double od[3] = {L[k].dir.x, L[k].dir.y, L[k].dir.z};
            assert_true(angle(Ls[k].dir, od) <= 0.1 * (double)L[k].extent + 1e-5);
        }
        for (int c = 0; c < 3; c++) {
            long double ref = want[c] > 0 ? want[c] : 1.0L;
            assert_true(fabsl((long double)tot[c] - want[c]) <= 1e-12L * ref);
            assert_true(fabs(info->power[c] - (double)want[c]) <= 1e-12 * (double)ref);
        }
    }
    for (int k = 0; k < n; k++) {
        assert_int_equal(cnt[k], L[k].pixels);
        assert_true(cnt[k] >= 1);
        omega_sum += L[k].solid_angle;
        assert_true(fabs(L[k].solid_angle - om[k]) <= 1e-12 * 4 * PI);
        for (int c = 0; c < 3; c++) {
            long double ref = pw[3 * k + c] > 0 ? pw[3 * k + c] : 1e-300L;
            assert_true(fabsl((long double)L[k].power[c] - pw[3 * k + c]) <= 1e-12L * ref);
        }
    }
    assert_true(fabs(omega_sum - 4 * PI) < 1e-12);
    free(pw);
    free(om);
    free(cnt);
}

/* ---- tests ---------------------------------------------------------------------------- */

static void every_method_conserves_power(void **state)
{
    (void)state;
    static const build_fn fns[] = {build_mc, build_vm, build_wu, build_wu_cut_only};
    static const int sizes[][2] = {{64, 32}, {200, 100}, {17, 9}};
    static const float rots[] = {0.0f, 73.0f};
    static const int ks[] = {1, 2, 3, 7, 16, 64, 100};
    for (size_t s = 0; s < 3; s++)
        for (size_t r = 0; r < 2; r++) {
            lumis_envmap *env =
                make_env(sizes[s][0], sizes[s][1], sky_pixel, rots[r], r ? 2.5f : 0.0f);
            for (size_t f = 0; f < 4; f++)
                for (size_t k = 0; k < sizeof ks / sizeof ks[0]; k++) {
                    lumis_light_set *set = NULL;
                    assert_int_equal(fns[f](env, ks[k], &set), LUMIS_OK);
                    check_set(set, env);
                    assert_int_equal(lumis_light_set_get_info(set)->count, ks[k]);
                    lumis_light_set_destroy(set);
                }
            lumis_envmap_destroy(env);
        }
}

/* Maps of 2^16 pixels or more take the decomposition's tiled paths (T = 4: EnvIndirect
 * sums from the tiles, tiles with emissive pixels summed again, sub-tile nodes of the cut
 * from pixels); widths that are not multiples of 4 give partial edge tiles, and K = 5000
 * on 65 x 64 tiles forces sub-tile rectangles.  Every invariant of check_set holds. */
static void wu_on_tiled_maps_conserves_power(void **state)
{
    (void)state;
    static const int sizes[][2] = {{512, 256}, {514, 130}, {260, 256}};
    static const int ks[] = {1, 7, 64, 500, 5000};
    float (*maps[])(int, int, int, int, int) = {sky_pixel, speckle_pixel};
    for (size_t s = 0; s < 3; s++)
        for (size_t mp = 0; mp < 2; mp++) {
            lumis_envmap *env =
                make_env(sizes[s][0], sizes[s][1], maps[mp], mp ? 0.0f : 31.0f, 0.0f);
            for (size_t k = 0; k < sizeof ks / sizeof ks[0]; k++) {
                if (ks[k] == 5000 && s != 2) continue;
                lumis_light_set *set = NULL;
                assert_int_equal(build_wu(env, ks[k], &set), LUMIS_OK);
                check_set(set, env);
                const lumis_light_set_info *info = lumis_light_set_get_info(set);
                assert_int_equal(info->count, ks[k]);
                assert_true(ks[k] == 1 || (info->direct > 0 && info->indirect > 0));
                lumis_light_set_destroy(set);
            }
            lumis_envmap_destroy(env);
        }
}

typedef struct box {
    int x0, y0, x1, y1;
} box;

static box label_box(const int32_t *lab, int w, int h, int k)
{
    box b = {w, h, 0, 0};
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++)
            if (lab[(size_t)j * (size_t)w + (size_t)i] == k) {
                if (i < b.x0) b.x0 = i;
                if (j < b.y0) b.y0 = j;
                if (i + 1 > b.x1) b.x1 = i + 1;
                if (j + 1 > b.y1) b.y1 = j + 1;
            }
    return b;
}

static double box_energy(const lumis_envmap *env, box b)
{
    double e = 0.0;
    for (int j = b.y0; j < b.y1; j++)
        for (int i = b.x0; i < b.x1; i++)
            e += (double)pixel_y(env, i, j) * lumis_envmap_pixel_solid_angle(env, j);
    return e;
}

static void median_cut_regions_have_equal_energy(void **state)
{
    (void)state;
    /* Large enough that no region of 64 is a single pixel, which could not split and
     * would shift its neighbours out of pairs. */
    lumis_envmap *env = make_env(256, 128, sky_pixel, 0.0f, 0.0f);
    int checked = 0;
    for (int k = 2; k <= 64; k *= 2) {
        lumis_light_set *set = NULL;
        assert_int_equal(build_mc(env, k, &set), LUMIS_OK);
        int w, h;
        const int32_t *lab = lumis_light_set_labels(set, &w, &h);
        /* Power of two: lights 2i and 2i + 1 are the halves of one split. */
        for (int p = 0; p < k; p += 2) {
            box a = label_box(lab, w, h, p), b = label_box(lab, w, h, p + 1);
            box sa = a, sb = b; /* the columns (rows) on either side of the cut */
            /* The cut crosses the parent's longer side, in radians on the sphere (its width
             * at its middle latitude against its height), as Debevec's median cut does. */
            const double mid = 0.5 * PI * (a.y0 + b.y1) / h,
                         wd = 2.0 * PI * (b.x1 - a.x0) / w * sin(mid), ht = PI * (b.y1 - a.y0) / h;
            const int across_x = a.x1 == b.x0 && a.y0 == b.y0 && a.y1 == b.y1;
            if (across_x ? !(wd >= ht || b.y1 - a.y0 < 2) : !(ht > wd || b.x1 - a.x0 < 2))
                fail_msg("K = %d, lights %d and %d: a %s cut of a region %g wide and %g high", k, p,
                         p + 1, across_x ? "vertical" : "horizontal", wd, ht);
            if (a.x1 == b.x0 && a.y0 == b.y0 && a.y1 == b.y1) {
                sa.x0 = a.x1 - 1;
                sb.x1 = b.x0 + 1;
            } else {
                assert_true(a.y1 == b.y0 && a.x0 == b.x0 && a.x1 == b.x1);
                sa.y0 = a.y1 - 1;
                sb.y1 = b.y0 + 1;
            }
            double ea = box_energy(env, a), eb = box_energy(env, b);
            double bound = fmax(box_energy(env, sa), box_energy(env, sb));
            assert_true(fabs(ea - eb) <= bound + 1e-9 * (ea + eb));
            checked++;
        }
        lumis_light_set_destroy(set);
    }
    assert_int_equal(checked, 1 + 2 + 4 + 8 + 16 + 32);
    lumis_envmap_destroy(env);
}

/* 16-point Gauss-Legendre (two 8-point rules on the halves) of f over [a, b]. */
static double gauss16(double (*f)(double), double a, double b)
{
    static const double x8[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                 -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                 0.7966664774136267,  0.9602898564975363};
    static const double w8[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                 0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                 0.2223810344533745, 0.1012285362903763};
    double s = 0.0;
    for (int k = 0; k < 16; k++)
        s += w8[k % 8] * f(0.5 * (a + b) + 0.25 * (b - a) * ((k < 8 ? -1 : 1) + x8[k % 8]));
    return s * 0.25 * (b - a);
}
static double sin_sq(double t)
{
    return sin(t) * sin(t);
}
static double sin_cos(double t)
{
    return sin(t) * cos(t);
}

/* Energy-weighted directional variance E - |M|^2 / E of a region from its sums. */
static long double region_variance(const long double v[4])
{
    if (!(v[0] > 0)) return 0;
    long double r = v[0] - (v[1] * v[1] + v[2] * v[2] + v[3] * v[3]) / v[0];
    return r > 0 ? r : 0;
}

/* Variance minimisation picks, for every region it splits, the cut of least summed
 * variance of the two halves over every column and row position: checked against brute
 * force in long double, with the pixels' first moments by quadrature (a map of 300 x 150
 * takes the band sums' fine, coarse and direct paths). */
static void variance_min_splits_minimise_the_summed_variance(void **state)
{
    (void)state;
    const int W = 300, H = 150;
    lumis_envmap *env = make_env(W, H, sky_pixel, 0.0f, 0.0f);
    /* per-pixel sums: E = Y Omega and M = Y m, m = (A_j C_i, B_j, A_j S_i) */
    long double *q = malloc((size_t)W * H * 4 * sizeof(long double));
    assert_non_null(q);
    for (int j = 0; j < H; j++) {
        double t0 = PI * j / H, t1 = PI * (j + 1) / H;
        double A = gauss16(sin_sq, t0, t1), B = gauss16(sin_cos, t0, t1) * 2 * PI / W;
        for (int i = 0; i < W; i++) {
            double p0 = 2 * PI * i / W, p1 = 2 * PI * (i + 1) / W;
            long double y = pixel_y(env, i, j), *o = q + ((size_t)j * W + (size_t)i) * 4;
            o[0] = y * (long double)lumis_envmap_pixel_solid_angle(env, j);
            o[1] = y * (long double)(A * (sin(p1) - sin(p0)));
            o[2] = y * (long double)B;
            o[3] = y * (long double)(A * (cos(p0) - cos(p1)));
        }
    }
    int checked = 0;
    for (int k = 2; k <= 16; k *= 2) {
        lumis_light_set *set = NULL;
        assert_int_equal(build_vm(env, k, &set), LUMIS_OK);
        int w, h;
        const int32_t *lab = lumis_light_set_labels(set, &w, &h);
        for (int p = 0; p < k; p += 2) { /* lights 2i and 2i + 1: the halves of one split */
            box a = label_box(lab, w, h, p), b = label_box(lab, w, h, p + 1);
            box u = {a.x0 < b.x0 ? a.x0 : b.x0, a.y0 < b.y0 ? a.y0 : b.y0,
                     a.x1 > b.x1 ? a.x1 : b.x1, a.y1 > b.y1 ? a.y1 : b.y1};
            const int nx = u.x1 - u.x0, ny = u.y1 - u.y0;
            /* the parent's column and row marginals */
            long double *col = calloc((size_t)nx * 4, sizeof *col),
                        *row = calloc((size_t)ny * 4, sizeof *row), tot[4] = {0, 0, 0, 0};
            assert_true(col && row);
            for (int j = u.y0; j < u.y1; j++)
                for (int i = u.x0; i < u.x1; i++)
                    for (int c = 0; c < 4; c++) {
                        long double v = q[((size_t)j * W + (size_t)i) * 4 + (size_t)c];
                        col[(i - u.x0) * 4 + c] += v;
                        row[(j - u.y0) * 4 + c] += v;
                        tot[c] += v;
                    }
            long double best = INFINITY, chosen = -1;
            for (int axis = 0; axis < 2; axis++) {
                const int n = axis ? ny : nx;
                const long double *m = axis ? row : col;
                long double pre[4] = {0, 0, 0, 0};
                for (int c = 1; c < n; c++) {
                    long double rest[4];
                    for (int t = 0; t < 4; t++) {
                        pre[t] += m[(c - 1) * 4 + t];
                        rest[t] = tot[t] - pre[t];
                    }
                    long double v = region_variance(pre) + region_variance(rest);
                    if (v < best) best = v;
                    int hit = axis ? (a.y1 == u.y0 + c && b.y0 == a.y1)
                                   : (a.x1 == u.x0 + c && b.x0 == a.x1);
                    if (hit) chosen = v;
                }
            }
            assert_true(chosen >= 0); /* the two halves are the two sides of one cut */
            assert_true(chosen <= best + 1e-9L * tot[0]);
            free(col);
            free(row);
            checked++;
        }
        lumis_light_set_destroy(set);
    }
    assert_int_equal(checked, 1 + 2 + 4 + 8);
    free(q);
    lumis_envmap_destroy(env);
}

/* The first moment of pixel (i, j) of a w x h map by 16 x 16 Gauss-Legendre quadrature in
 * (theta, phi): independent of the library's closed form. */
static void pixel_moment_quadrature(int w, int h, int i, int j, double m[3])
{
    static const double x8[8] = {-0.9602898564975363, -0.7966664774136267, -0.5255324099163290,
                                 -0.1834346424956498, 0.1834346424956498,  0.5255324099163290,
                                 0.7966664774136267,  0.9602898564975363};
    static const double w8[8] = {0.1012285362903763, 0.2223810344533745, 0.3137066458778873,
                                 0.3626837833783620, 0.3626837833783620, 0.3137066458778873,
                                 0.2223810344533745, 0.1012285362903763};
    double t0 = PI * j / h, t1 = PI * (j + 1) / h, p0 = 2 * PI * i / w, p1 = 2 * PI * (i + 1) / w;
    m[0] = m[1] = m[2] = 0.0;
    for (int a = 0; a < 16; a++)
        for (int b = 0; b < 16; b++) {
            /* two 8-point rules on the halves of each interval */
            double ta = 0.5 * (t0 + t1) + 0.25 * (t1 - t0) * ((a < 8 ? -1 : 1) + x8[a % 8]);
            double pb = 0.5 * (p0 + p1) + 0.25 * (p1 - p0) * ((b < 8 ? -1 : 1) + x8[b % 8]);
            double wt = w8[a % 8] * w8[b % 8] * 0.25 * (t1 - t0) * 0.25 * (p1 - p0) * sin(ta);
            m[0] += wt * sin(ta) * cos(pb);
            m[1] += wt * cos(ta);
            m[2] += wt * sin(ta) * sin(pb);
        }
}

static void one_light_per_pixel_is_exact(void **state)
{
    (void)state;
    static const build_fn fns[] = {build_mc, build_vm, build_wu_cut_only};
    const int w = 8, h = 4;
    for (int rot = 0; rot < 2; rot++) {
        lumis_envmap *env = make_env(w, h, sky_pixel, rot ? 100.0f : 0.0f, rot ? 3.0f : 0.0f);
        float rr = (float)(rot ? 100.0 * PI / 180.0 : 0.0);
        for (size_t f = 0; f < 3; f++) {
            lumis_light_set *set = NULL;
            assert_int_equal(fns[f](env, w * h, &set), LUMIS_OK);
            check_set(set, env);
            const lumis_light *L;
            int n;
            assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
            assert_int_equal(n, w * h);
            const int32_t *lab = lumis_light_set_labels(set, NULL, NULL);
            for (int j = 0; j < h; j++)
                for (int i = 0; i < w; i++) {
                    const lumis_light *l = &L[lab[j * w + i]];
                    assert_int_equal(l->pixels, 1);
                    double om = lumis_envmap_pixel_solid_angle(env, j);
                    assert_true(l->solid_angle == om);
                    const float *p = lumis_envmap_pixels(env) + (j * w + i) * 3;
                    for (int c = 0; c < 3; c++) {
                        double want = (double)p[c] * om * (double)lumis_envmap_scale(env);
                        assert_true(fabs(l->power[c] - want) <= 1e-15 * want);
                    }
                    double m[3];
                    pixel_moment_quadrature(w, h, i, j, m);
                    double len = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
                    /* rotate the map-frame centroid into the world */
                    double cr = cos(rr), sr = sin(rr);
                    double want[3] = {(cr * m[0] - sr * m[2]) / len, m[1] / len,
                                      (sr * m[0] + cr * m[2]) / len};
                    assert_true(fabs(l->dir.x - want[0]) < 2e-7);
                    assert_true(fabs(l->dir.y - want[1]) < 2e-7);
                    assert_true(fabs(l->dir.z - want[2]) < 2e-7);
                }
            lumis_light_set_destroy(set);
        }
        lumis_envmap_destroy(env);
    }
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static void emissive_threshold_is_a_brute_force_percentile(void **state)
{
    (void)state;
    static const float pcts[] = {0.0f, 50.0f, 90.0f, 99.9f, 100.0f, 0.01f};
    /* The last four have >= 2^18 pixels, where only the pixels at or over a bound drawn
     * from a sample are gathered: the constant map overflows the gathering, the trap map
     * puts the bound over the percentile, and both take the full second pass. */
    lumis_envmap *maps[7] = {make_env(97, 51, sky_pixel, 0.0f, 0.0f),
                             make_env(64, 32, speckle_pixel, 20.0f, 0.25f),
                             make_env(16, 8, const_pixel, 0.0f, 0.0f),
                             make_env(1031, 517, sky_pixel, 0.0f, 0.0f),
                             make_env(1024, 512, speckle_pixel, 0.0f, 2.0f),
                             make_env(1024, 256, const_pixel, 0.0f, 0.0f),
                             make_env(1024, 256, sample_trap_pixel, 0.0f, 0.0f)};
    for (int e = 0; e < 7; e++) {
        lumis_envmap *env = maps[e];
        int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
        size_t n = (size_t)w * (size_t)h;
        float *y = malloc(n * sizeof(float));
        double pow_y = 0.0, ymax = 0.0;
        for (int j = 0; j < h; j++)
            for (int i = 0; i < w; i++) {
                y[(size_t)j * (size_t)w + (size_t)i] = pixel_y(env, i, j);
                pow_y += (double)pixel_y(env, i, j) * lumis_envmap_pixel_solid_angle(env, j);
                ymax = fmax(ymax, pixel_y(env, i, j));
            }
        float *sorted = malloc(n * sizeof(float));
        memcpy(sorted, y, n * sizeof(float));
        qsort(sorted, n, sizeof(float), cmp_float);
        for (size_t p = 0; p < sizeof pcts / sizeof pcts[0]; p++) {
            lumis_decomp_desc d = {0};
            d.count = 8;
            d.percentile = pcts[p];
            lumis_light_set *set = NULL;
            assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
            const lumis_light_set_info *info = lumis_light_set_get_info(set);
            double pct = pcts[p] > 0.0f ? (double)pcts[p] : 98.0;
            size_t rank = (size_t)ceil(pct / 100.0 * (double)n);
            rank = rank < 1 ? 1 : rank;
            assert_true(info->percentile_luminance == (double)sorted[rank - 1]);
            double avg = pow_y / (4 * PI);
            assert_true(fabs(info->avg_luminance - avg) <= 1e-12 * avg);
            assert_true(info->max_luminance == ymax);
            double lt = fmax(info->percentile_luminance, fmax(3.0 * avg, 0.001 * ymax));
            assert_true(fabs(info->threshold - lt) <= 1e-12 * lt);
            int em = 0;
            for (size_t q = 0; q < n; q++) em += (double)y[q] > info->threshold;
            assert_int_equal(info->emissive_pixels, em);
            if (e < 3) check_set(set, env); /* the large maps: the threshold only */
            lumis_light_set_destroy(set);
        }
        /* A threshold given under the sampled bound: every pixel over it is emissive. */
        for (int t = 0; t < 2; t++) {
            lumis_decomp_desc d = {0};
            d.count = 8;
            d.threshold = t ? sorted[n / 2] : fmaxf(sorted[n / 10], 1e-30f);
            lumis_light_set *set = NULL;
            assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
            const lumis_light_set_info *info = lumis_light_set_get_info(set);
            int em = 0;
            for (size_t q = 0; q < n; q++) em += (double)y[q] > (double)d.threshold;
            assert_int_equal(info->emissive_pixels, em);
            lumis_light_set_destroy(set);
        }
        free(y);
        free(sorted);
        lumis_envmap_destroy(env);
    }
}

static void kmeans_terminates_and_never_increases_its_objective(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(256, 128, speckle_pixel, 0.0f, 0.0f);
    static const lumis_decomp_variant vars[] = {LUMIS_DECOMP_IS_KMEANS, LUMIS_DECOMP_FULL};
    int iterated = 0;
    for (int v = 0; v < 2; v++)
        for (uint64_t seed = 0; seed < 6; seed++) {
            lumis_decomp_desc d = {0};
            d.count = 64;
            d.seed = seed;
            d.variant = vars[v];
            d.threshold = 10.0f; /* every speckle is emissive: about 900 pixels */
            lumis_light_set *set = NULL;
            assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
            const lumis_light_set_info *info = lumis_light_set_get_info(set);
            assert_true(info->emissive_pixels > 500);
            assert_true(info->kmeans_converged);
            assert_true(info->kmeans_objective_count >= 2);
            for (int k = 1; k < info->kmeans_objective_count; k++)
                assert_true(info->kmeans_objective[k] <=
                            info->kmeans_objective[k - 1] * (1.0 + 1e-12));
            if (info->kmeans_iterations > 2) iterated++;
            /* After convergence the last assignment step changed nothing. */
            int c = info->kmeans_objective_count;
            assert_true(info->kmeans_objective[c - 1] == info->kmeans_objective[c - 2]);
            check_set(set, env);
            lumis_light_set_destroy(set);
        }
    assert_true(iterated > 0); /* the test exercised real iterations */
    lumis_envmap_destroy(env);
}

static void the_cut_yields_exactly_k_lights(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(64, 32, sky_pixel, 0.0f, 0.0f);
    for (int cut = LUMIS_CUT_MODIFIED; cut <= LUMIS_CUT_ORIGINAL; cut++)
        for (int k = 1; k <= 1024; k++) {
            lumis_decomp_desc d = {0};
            d.count = k;
            d.sets = 1;
            d.cut = (lumis_cut_objective)cut;
            d.threshold = 1e30f;
            lumis_light_set *set = NULL;
            assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
            const lumis_light_set_info *info = lumis_light_set_get_info(set);
            assert_int_equal(info->count, k);
            assert_int_equal(info->indirect, k);
            if (k % 97 == 1) check_set(set, env);
            lumis_light_set_destroy(set);
            /* With emissive pixels the direct and indirect lights still add up to K. */
            d.threshold = 0.0f;
            assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
            info = lumis_light_set_get_info(set);
            assert_int_equal(info->count, k);
            assert_int_equal(info->direct + info->indirect, k);
            if (k % 97 == 1) check_set(set, env);
            lumis_light_set_destroy(set);
        }
    lumis_envmap_destroy(env);
}

static void wu_parts_and_ablations(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(256, 128, sky_pixel, 30.0f, 0.0f);
    for (int v = LUMIS_DECOMP_DEFAULT; v < LUMIS_DECOMP_VARIANT_COUNT; v++)
        for (int mr = 0; mr < LUMIS_MASK_COUNT; mr++) {
            lumis_decomp_desc d = {0};
            d.count = 32;
            d.seed = 3;
            d.variant = (lumis_decomp_variant)v;
            d.mask_radius = (lumis_mask_radius)mr;
            lumis_light_set *set = NULL;
            assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
            const lumis_light_set_info *info = lumis_light_set_get_info(set);
            assert_true(info->emissive_pixels > 0);
            assert_true(info->direct >= 1 && info->indirect >= 1);
            assert_int_equal(info->count, 32);
            double want_r =
                mr == LUMIS_MASK_RADIANS ? 0.15 * 4 * PI / 32 : acos(1.0 - 2.0 * 0.15 / 32);
            assert_true(fabs(info->mask_radius - want_r) < 1e-12);
            const lumis_light *L;
            int n;
            lumis_light_set_get(set, 0, &L, &n);
            for (int k = 0; k < n; k++)
                assert_int_equal(L[k].kind, k < info->direct ? LUMIS_LIGHT_ENV_DIRECT
                                                             : LUMIS_LIGHT_ENV_INDIRECT);
            /* Every EnvDirect pixel is emissive and within the return radius. */
            const int32_t *lab = lumis_light_set_labels(set, NULL, NULL);
            for (int j = 0; j < 128; j++)
                for (int i = 0; i < 256; i++) {
                    int32_t k = lab[j * 256 + i];
                    if (k < info->direct) assert_true((double)pixel_y(env, i, j) > info->threshold);
                }
            check_set(set, env);
            lumis_light_set_destroy(set);
        }
    lumis_envmap_destroy(env);
}

/* Table 1's other baselines: every invariant of the others, on every map kind. */
/* ---- FHIS's Penrose tiling ----------------------------------------------------------- */

static double tri_area(double p[3][2])
{
    return 0.5 *
           ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]));
}

static int in_tri(double p[3][2], double x, double y)
{
    for (int e = 0; e < 3; e++) {
        const double *a = p[e], *b = p[(e + 1) % 3];
        if ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0]) < 0) return 0;
    }
    return 1;
}

typedef struct tiling {
    lumis__ptile *tri;
    int ntri, nsamp, max_is, fcode_ok;
} tiling;

static void tile_down(const lumis__ptile *t, int level, tiling *out)
{
    if (t->level == level) {
        if (t->type >= LUMIS__PT_C)
            out->tri[out->ntri++] = *t;
        else {
            out->nsamp++;
            int is = lumis__penrose_structural_index(t->fcode);
            if (is > out->max_is) out->max_is = is;
        }
        /* no two adjacent ones: a Zeckendorf code */
        if (t->fcode & (t->fcode >> 1)) out->fcode_ok = 0;
        return;
    }
    lumis__ptile c[4];
    int n = lumis__ptile_split(t, c);
    for (int k = 0; k < n; k++) tile_down(&c[k], level, out);
}

/* Every split's children tile their parent exactly: down to level 9 the triangles' areas
 * add up to the root's, all counter-clockwise, and random points of the root fall in
 * exactly one; triangles and sampling tiles grow as the Fibonacci numbers. */
static void penrose_children_tile_their_parent(void **state)
{
    (void)state;
    lumis__ptile root = lumis__penrose_root(300, 200);
    double rp[3][2];
    lumis__ptile_vertices(&root, rp);
    const double ra = tri_area(rp);
    assert_true(ra > 0);
    /* the root covers the map */
    assert_true(in_tri(rp, 0, 0) && in_tri(rp, 300, 0) && in_tri(rp, 0, 200) &&
                in_tri(rp, 300, 200));
    static const int tris[] = {1, 3, 8, 21, 55, 144, 377, 987, 2584, 6765};
    static const int samp[] = {0, 1, 3, 9, 26, 71, 188, 493, 1291, 3381};
    tiling t = {malloc(6765 * sizeof(lumis__ptile)), 0, 0, 0, 1};
    assert_non_null(t.tri);
    for (int level = 0; level <= 9; level++) {
        t.ntri = t.nsamp = 0;
        tile_down(&root, level, &t);
        assert_int_equal(t.ntri, tris[level]);
        assert_int_equal(t.nsamp, samp[level]);
        double sum = 0.0;
        for (int k = 0; k < t.ntri; k++) {
            double p[3][2];
            lumis__ptile_vertices(&t.tri[k], p);
            double a = tri_area(p);
            assert_true(a > 0);
            sum += a;
        }
        assert_true(fabs(sum - ra) <= 1e-9 * ra);
        if (level < 4) continue;
        uint32_t r = 7;
        for (int q = 0; q < 300; q++) {
            double u = (hash(r++) & 0xffff) / 65536.0, v = (hash(r++) & 0xffff) / 65536.0;
            if (u + v > 1) u = 1 - u, v = 1 - v;
            double x = rp[0][0] + u * (rp[1][0] - rp[0][0]) + v * (rp[2][0] - rp[0][0]);
            double y = rp[0][1] + u * (rp[1][1] - rp[0][1]) + v * (rp[2][1] - rp[0][1]);
            int hits = 0;
            for (int k = 0; k < t.ntri; k++) {
                double p[3][2];
                lumis__ptile_vertices(&t.tri[k], p);
                hits += in_tri(p, x, y);
            }
            assert_int_equal(hits, 1);
        }
    }
    assert_true(t.fcode_ok);
    assert_int_equal(t.max_is, 20); /* structural indices 0 .. 20 */
    free(t.tri);
    /* F-code values and indices */
    assert_true(lumis__fcode_value(1, 1) == 1 && lumis__fcode_value(1, 2) == 2);
    assert_true(lumis__fcode_value(2, 2) == 1 && lumis__fcode_value(5, 3) == 4);
    assert_true(lumis__fcode_value((uint64_t)1 << 40, 42) == 2); /* weights stay put */
    assert_int_equal(lumis__penrose_level_for(0.0), 0);
    assert_int_equal(lumis__penrose_level_for(1.0), 1);
    for (int iv = 0; iv < 21; iv++) {
        double I = (pow(2.6180339887498949, 9.0 + (iv + 0.5) / 21.0) - 1.0) / sqrt(5.0);
        assert_int_equal(lumis__penrose_importance_index(I), iv);
    }
}

/* FHIS's points follow the importance: on a map twice as bright on its left half, the
 * left half gets about twice the lights (one light per point, K = 600). */
static float halves_pixel(int w, int h, int i, int j, int c)
{
    (void)h, (void)j, (void)c;
    return i < w / 2 ? 2.0f : 1.0f;
}

static void fhis_points_follow_the_importance(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(256, 128, halves_pixel, 0.0f, 0.0f);
    lumis_light_set *set = NULL;
    assert_int_equal(build_fhis(env, 600, &set), LUMIS_OK);
    const lumis_light *L;
    int n, left = 0;
    assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
    assert_int_equal(n, 600);
    for (int k = 0; k < n; k++) {
        float u, v;
        lumis_envmap_dir_to_uv(env, L[k].dir, &u, &v);
        left += u < 0.5f;
    }
    assert_true(left > 370 && left < 430); /* 400 expected */
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* Three lit pixels on black (FHIS's corrected points spill into unlit pixels near them). */
static float three_lit_pixel(int w, int h, int i, int j, int c)
{
    (void)h;
    const int p = j * w + i;
    return p == 20 || p == 45 || p == 100 ? 10.0f + 5.0f * (float)c + (float)p : 0.0f;
}

/* FHIS's lights are the Voronoi cells of its points: each light's direction lies in a pixel
 * of its own region, and each light's power is the brute-force sum of L Omega over the
 * pixels whose centre is nearer to it than to any other light (a pixel within 1e-6 of a
 * tie counts for the light its label names, one of the tied), but for the pixel that holds
 * a light's point, which is that light's.  With a light for every pixel the tiles cannot
 * find them all, and the rest go to the pixels left, at their centres. */
static void fhis_regions_are_the_points_voronoi_cells(void **state)
{
    (void)state;
    static const struct {
        int w, h, k;
        float (*f)(int, int, int, int, int);
    } cases[] = {{48, 24, 20, sky_pixel},
                 {16, 8, 10, three_lit_pixel},
                 {8, 4, 5, black_pixel},
                 {8, 4, 32, sky_pixel},
                 {16, 8, 128, three_lit_pixel}};
    for (size_t t = 0; t < sizeof cases / sizeof cases[0]; t++) {
        const int w = cases[t].w, h = cases[t].h;
        lumis_envmap *env = make_env(w, h, cases[t].f, 0.0f, 0.0f);
        lumis_light_set *set = NULL;
        assert_int_equal(build_fhis(env, cases[t].k, &set), LUMIS_OK);
        const lumis_light *L;
        int n, lw, lh;
        assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
        assert_int_equal(n, cases[t].k);
        const int32_t *lab = lumis_light_set_labels(set, &lw, &lh);
        int *own = malloc((size_t)w * (size_t)h * sizeof *own);
        assert_non_null(own);
        for (int p = 0; p < w * h; p++) own[p] = -1;
        for (int k = 0; k < n; k++) {
            int i, j;
            lumis_envmap_dir_to_pixel(env, L[k].dir, &i, &j);
            if (lab[j * w + i] != k || own[j * w + i] >= 0)
                fail_msg("case %zu: light %d points into pixel (%d, %d) of light %d", t, k, i, j,
                         lab[j * w + i]);
            own[j * w + i] = k;
        }
        double *pw = calloc((size_t)n * 3, sizeof(double));
        assert_non_null(pw);
        for (int j = 0; j < h; j++)
            for (int i = 0; i < w; i++) {
                /* the pixel's centre (row 0 at the zenith, +y up), checked against the map */
                const double th = PI * (j + 0.5) / h, ph = 2.0 * PI * (i + 0.5) / w;
                const double c[3] = {sin(th) * cos(ph), cos(th), sin(th) * sin(ph)};
                int ci, cj;
                lumis_envmap_dir_to_pixel(env, (lumis_vec3){(float)c[0], (float)c[1], (float)c[2]},
                                          &ci, &cj);
                assert_true(ci == i && cj == j);
                int best = -1;
                double b1 = -2.0, b2 = -2.0;
                for (int k = 0; k < n; k++) {
                    const double d = c[0] * L[k].dir.x + c[1] * L[k].dir.y + c[2] * L[k].dir.z;
                    if (d > b1) {
                        b2 = b1;
                        b1 = d;
                        best = k;
                    } else if (d > b2) {
                        b2 = d;
                    }
                }
                /* a pixel holding a point is that point's, nearest or not */
                const int32_t got = lab[j * w + i], mine = own[j * w + i];
                const int owner = mine >= 0 ? mine : b1 - b2 > 1e-6 ? best : got;
                if (got != owner)
                    fail_msg("case %zu: pixel (%d, %d) is light %d's, nearest is %d", t, i, j, got,
                             owner);
                const lumis_rgb r = lumis_envmap_texel(env, i, j);
                const double om = 2.0 * PI / w * (cos(PI * j / h) - cos(PI * (j + 1) / h));
                pw[3 * owner] += r.r * om;
                pw[3 * owner + 1] += r.g * om;
                pw[3 * owner + 2] += r.b * om;
            }
        for (int k = 0; k < n; k++)
            for (int c = 0; c < 3; c++)
                if (!(fabs(L[k].power[c] - pw[3 * k + c]) <= 1e-9 * pw[3 * k + c] + 1e-300))
                    fail_msg("case %zu: light %d channel %d: power %.12g, Voronoi sum %.12g", t, k,
                             c, L[k].power[c], pw[3 * k + c]);
        free(pw);
        free(own);
        lumis_light_set_destroy(set);
        lumis_envmap_destroy(env);
    }
}

static void fhis_and_tmms_conserve_power_with_exactly_k_lights(void **state)
{
    (void)state;
    static const build_fn fns[] = {build_fhis, build_tmms};
    static const int sizes[][2] = {{64, 32}, {200, 100}, {17, 9}};
    static const int ks[] = {1, 2, 3, 7, 16, 64, 100};
    float (*maps[])(int, int, int, int, int) = {sky_pixel, speckle_pixel, black_pixel, const_pixel};
    for (size_t s = 0; s < 3; s++)
        for (size_t mp = 0; mp < 4; mp++) {
            lumis_envmap *env =
                make_env(sizes[s][0], sizes[s][1], maps[mp], mp ? 0.0f : 73.0f, mp ? 0.0f : 2.5f);
            for (size_t f = 0; f < 2; f++)
                for (size_t k = 0; k < sizeof ks / sizeof ks[0]; k++) {
                    lumis_light_set *set = NULL;
                    assert_int_equal(fns[f](env, ks[k], &set), LUMIS_OK);
                    check_set(set, env);
                    const lumis_light_set_info *info = lumis_light_set_get_info(set);
                    assert_int_equal(info->count, ks[k]);
                    assert_int_equal(info->method, f ? LUMIS_LIGHTS_TMMS : LUMIS_LIGHTS_FHIS);
                    lumis_light_set_destroy(set);
                }
            lumis_envmap_destroy(env);
        }
    /* One light per pixel. */
    lumis_envmap *env = make_env(8, 4, sky_pixel, 0.0f, 0.0f);
    for (size_t f = 0; f < 2; f++) {
        lumis_light_set *set = NULL;
        assert_int_equal(fns[f](env, 32, &set), LUMIS_OK);
        check_set(set, env);
        const lumis_light *L;
        int n;
        assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
        for (int k = 0; k < n; k++) assert_int_equal(L[k].pixels, 1);
        lumis_light_set_destroy(set);
    }
    lumis_envmap_destroy(env);
}

/* A map ten times as bright gives the same lights, each ten times as powerful: no method may
 * depend on the map's absolute level (issue 37: TMMS's log average over 2 pi instead of
 * 4 pi kept every estimator agreeing, and only this invariance sees it).  Wu's split
 * uses a relative threshold here; an absolute one is the caller's to scale. */
/* Closed form: with the normal up and an even number of rows no pixel straddles the horizon,
 * and the map's irradiance is sum over the upper rows of Y (2 pi / w) (sin^2 theta_1 -
 * sin^2 theta_0) / 2 (the integral of cos theta sin theta); facing down, the lower rows'.
 * The set's is the sum over its lights of Y(power) max(0, n . dir), added here from the
 * lights.  A coloured, asymmetric sky and a tilted normal for the set's sum. */
static void light_set_irradiance_against_closed_forms(void **state)
{
    (void)state;
    const int w = 48, h = 24;
    lumis_envmap *env = make_env(w, h, sky_pixel, 0.0f, 0.0f);
    lumis_median_cut_desc md = {0};
    md.count = 16;
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_median_cut(env, &md, &set), LUMIS_OK);
    const lumis_light *L = NULL;
    int n = 0;
    assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
    const lumis_vec3 normals[] = {{0, 1, 0}, {0, -1, 0}, {0.48f, 0.6f, -0.64f}};
    for (int q = 0; q < 3; q++) {
        const lumis_vec3 nn = normals[q];
        double se = -1, me = -1;
        assert_int_equal(lumis_light_set_irradiance(env, set, nn, &se, &me), LUMIS_OK);
        long double want_set = 0;
        for (int k = 0; k < n; k++) {
            const double c =
                (double)nn.x * L[k].dir.x + (double)nn.y * L[k].dir.y + (double)nn.z * L[k].dir.z;
            const double y =
                0.2126 * L[k].power[0] + 0.7152 * L[k].power[1] + 0.0722 * L[k].power[2];
            if (c > 0) want_set += (long double)(y * c);
        }
        assert_true(fabs(se - (double)want_set) <= 1e-9 * fabs((double)want_set));
        if (q == 2) continue; /* a tilted horizon cuts pixels: the closed form is for y only */
        long double want_map = 0;
        for (int j = 0; j < h; j++) {
            const double t0 = PI * j / h, t1 = PI * (j + 1) / h;
            const int up = j < h / 2;
            if (up != (nn.y > 0)) continue;
            const double band = 0.5 * fabs(sin(t1) * sin(t1) - sin(t0) * sin(t0));
            for (int i = 0; i < w; i++)
                want_map += (long double)pixel_y(env, i, j) * (2 * PI / w) * band;
        }
        assert_true(fabs(me - (double)want_map) <= 1e-6 * (double)want_map);
    }
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

static void every_method_is_invariant_to_the_maps_brightness(void **state)
{
    (void)state;
    static const build_fn fns[] = {build_mc, build_vm, build_wu_cut_only, build_fhis, build_tmms};
    static const char *const names[] = {"median cut", "variance min", "wu (cut)", "fhis", "tmms"};
    lumis_envmap *a = make_env(61, 31, sky_pixel, 73.0f, 1.0f);
    lumis_envmap *b = make_env(61, 31, sky_pixel, 73.0f, 10.0f);
    for (size_t f = 0; f < sizeof fns / sizeof fns[0]; f++) {
        lumis_light_set *sa = NULL, *sb = NULL;
        assert_int_equal(fns[f](a, 12, &sa), LUMIS_OK);
        assert_int_equal(fns[f](b, 12, &sb), LUMIS_OK);
        const lumis_light *la, *lb;
        int na, nb;
        assert_int_equal(lumis_light_set_get(sa, 0, &la, &na), LUMIS_OK);
        assert_int_equal(lumis_light_set_get(sb, 0, &lb, &nb), LUMIS_OK);
        if (na != nb) fail_msg("%s: %d lights, then %d", names[f], na, nb);
        for (int k = 0; k < na; k++) {
            const double dd = fabs(la[k].dir.x - lb[k].dir.x) + fabs(la[k].dir.y - lb[k].dir.y) +
                              fabs(la[k].dir.z - lb[k].dir.z);
            if (dd > 1e-5 || la[k].pixels != lb[k].pixels)
                fail_msg("%s: light %d moved (%d against %d pixels)", names[f], k, la[k].pixels,
                         lb[k].pixels);
            for (int c = 0; c < 3; c++)
                if (fabs(lb[k].power[c] - 10 * la[k].power[c]) > 1e-6 * fabs(lb[k].power[c]))
                    fail_msg("%s: light %d channel %d: %g, then %g (x10 expected)", names[f], k, c,
                             la[k].power[c], lb[k].power[c]);
        }
        lumis_light_set_destroy(sa);
        lumis_light_set_destroy(sb);
    }
    lumis_envmap_destroy(a);
    lumis_envmap_destroy(b);
}

/* A ring of four pixels (one row), luminances 3, 1, 9, 27. */
static float ring_pixel(int w, int h, int i, int j, int c)
{
    (void)w, (void)h, (void)j, (void)c;
    static const float y[4] = {3.0f, 1.0f, 9.0f, 27.0f};
    return y[i];
}

/* TMMS's merge by hand: on a 4 x 1 map every pixel is a cell, and with a narrow bandwidth
 * (0.01) each its own level and stratum.  For 3 lights the weakest stratum (pixel 1, Y 1)
 * merges into its weakest neighbour: pixel 0 (Y 3) on its left, not pixel 2 (Y 9) on its
 * right.  Then {0, 1} (4) is the weakest and the only one that could split: no trade.  The
 * lights: {0, 1}, {2}, {3}. */
static void tmms_merges_into_the_weakest_neighbour(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(4, 1, ring_pixel, 0.0f, 0.0f);
    lumis_tmms_desc d = {0};
    d.count = 3;
    d.range_bandwidth = 0.01f;
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_tmms(env, &d, &set), LUMIS_OK);
    int w, h;
    const int32_t *lab = lumis_light_set_labels(set, &w, &h);
    assert_true(w == 4 && h == 1);
    if (!(lab[0] == lab[1] && lab[1] != lab[2] && lab[2] != lab[3] && lab[1] != lab[3]))
        fail_msg("strata %d %d %d %d, want pixels 0 and 1 together", lab[0], lab[1], lab[2],
                 lab[3]);
    const lumis_light *L;
    int n;
    assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
    assert_int_equal(n, 3);
    assert_int_equal(L[lab[0]].pixels, 2);
    /* its power: Y 3 + 1 over two pixels of pi each (the four share 4 pi) */
    assert_true(fabs(L[lab[0]].power[1] - 4.0 * PI) < 1e-9);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* A sky over black ground: a sun, a dim coloured gradient above the horizon, nothing below
 * it (regions of no energy). */
static float sky_over_black(int w, int h, int i, int j, int c)
{
    if (j >= h / 2) return 0.0f;
    const double u = (i + 0.5) / w, v = (j + 0.5) / h;
    const double du = u - 0.3, dv = v - 0.2;
    if (du * du + dv * dv < 0.002) return 2000.0f;
    return (float)((1.0 + 0.5 * c) * (1.0 + u) * (0.6 - v));
}

/* Black but for a 16 x 16 patch of lit pixel pairs and black pairs, column by column: a
 * cut led by energy (Eq. 3's extent weight near 0) splits the patch below its 4 x 4 tiles,
 * into lit and black halves of tiles. */
static float striped_patch(int w, int h, int i, int j, int c)
{
    (void)w, (void)h;
    if (i < 100 || i >= 116 || j < 120 || j >= 136 || i % 4 >= 2) return 0.0f;
    return (float)(1.0 + 0.25 * c + 0.1 * (i - 100) + 0.05 * (j - 120));
}

/* The exact first moment of pixel (i, j): the integral of the direction over it. */
static void pixel_moment(int w, int h, int i, int j, double m[3])
{
    const double t0 = PI * j / h, t1 = PI * (j + 1) / h, p0 = 2.0 * PI * i / w,
                 p1 = 2.0 * PI * (i + 1) / w;
    const double s2 = 0.5 * (t1 - t0) - 0.25 * (sin(2.0 * t1) - sin(2.0 * t0)); /* int sin^2 */
    m[0] = s2 * (sin(p1) - sin(p0));
    m[1] = 0.5 * (sin(t1) * sin(t1) - sin(t0) * sin(t0)) * (p1 - p0);
    m[2] = s2 * (cos(p0) - cos(p1));
}

/* Each of Wu's EnvIndirects points at its region's luminance-weighted mean direction, and a
 * region of no energy at its plain mean direction: brute-force sums of the exact pixel
 * moments over the pixels labelled with it.  On a map of 2^16 pixels or more the sums come
 * from 4 x 4 tiles; regions smaller than a tile are summed pixel by pixel (the striped
 * patch's). */
static void wu_indirect_lights_point_at_their_regions_centroid(void **state)
{
    (void)state;
    static const int sizes[][3] = {{61, 29, 24}, {371, 185, 40}, {256, 256, 64}};
    for (size_t t = 0; t < sizeof sizes / sizeof sizes[0]; t++) {
        const int w = sizes[t][0], h = sizes[t][1];
        lumis_envmap *env = make_env(w, h, t < 2 ? sky_over_black : striped_patch, 0.0f, 0.0f);
        lumis_light_set *set = NULL;
        lumis_decomp_desc d = {0};
        d.count = sizes[t][2];
        d.seed = 7;
        if (t == 2) { /* no emissive pixel, and a cut led by energy, not by extent */
            d.threshold = 1e30f;
            d.w_d = 1e-6f;
        }
        assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
        const lumis_light *L;
        int n, lw, lh, dark = 0, lit = 0;
        assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
        const int32_t *lab = lumis_light_set_labels(set, &lw, &lh);
        double(*ym)[3] = calloc((size_t)n, sizeof *ym), (*gm)[3] = calloc((size_t)n, sizeof *gm);
        assert_true(ym && gm);
        for (int j = 0; j < h; j++)
            for (int i = 0; i < w; i++) {
                const int k = lab[j * w + i];
                double m[3];
                pixel_moment(w, h, i, j, m);
                const double y = pixel_y(env, i, j);
                for (int c = 0; c < 3; c++) {
                    ym[k][c] += y * m[c];
                    gm[k][c] += m[c];
                }
            }
        for (int k = 0; k < n; k++) {
            if (L[k].kind != LUMIS_LIGHT_ENV_INDIRECT) continue;
            const int black = L[k].power[0] == 0.0 && L[k].power[1] == 0.0 && L[k].power[2] == 0.0;
            dark += black;
            lit += !black;
            double *want = black ? gm[k] : ym[k];
            const double a = angle(L[k].dir, want);
            if (!(a < 1e-5))
                fail_msg("%d x %d: %s indirect light %d is %g rad off its region's centroid", w, h,
                         black ? "black" : "lit", k, a);
        }
        assert_true(dark >= 2 && lit >= 2);
        free(ym);
        free(gm);
        lumis_light_set_destroy(set);
        lumis_envmap_destroy(env);
    }
}

/* Lloyd's fixed point, brute force: with nothing returned (return_factor far over pi), every
 * EnvDirect's region is its k-means cluster, so after convergence each member's nearest
 * centre, by the chord between unit vectors that k-means minimises, is its own cluster's,
 * and each centre is its cluster's energy centroid normalize(sum Y m_p) over the exact pixel
 * moments m_p, summed here.  The light's direction must be that centroid too. */
static void kmeans_stops_at_a_fixed_point(void **state)
{
    (void)state;
    const int w = 256, h = 128;
    lumis_envmap *env = make_env(w, h, speckle_pixel, 0.0f, 0.0f);
    static const lumis_decomp_variant vars[] = {LUMIS_DECOMP_IS_KMEANS, LUMIS_DECOMP_FULL};
    int iterated = 0;
    for (int v = 0; v < 2; v++)
        for (uint64_t seed = 0; seed < 4; seed++) {
            lumis_decomp_desc d = {0};
            d.count = 64;
            d.seed = seed;
            d.variant = vars[v];
            d.threshold = 10.0f;    /* the speckles */
            d.return_factor = 1e6f; /* return no pixel */
            lumis_light_set *set = NULL;
            assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
            const lumis_light_set_info *info = lumis_light_set_get_info(set);
            assert_true(info->kmeans_converged);
            iterated += info->kmeans_iterations > 2;
            const lumis_light *L;
            int n, lw, lh;
            assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
            const int32_t *lab = lumis_light_set_labels(set, &lw, &lh);
            double(*c)[3] = calloc((size_t)n, sizeof *c);
            double(*x)[3] = calloc((size_t)w * (size_t)h, sizeof *x);
            assert_true(c && x);
            int members = 0;
            for (int j = 0; j < h; j++)
                for (int i = 0; i < w; i++) {
                    const int k = lab[j * w + i];
                    const double y = pixel_y(env, i, j);
                    /* every emissive pixel stays in its cluster, and only those are in one */
                    assert_int_equal(L[k].kind == LUMIS_LIGHT_ENV_DIRECT, y > d.threshold);
                    if (L[k].kind != LUMIS_LIGHT_ENV_DIRECT) continue;
                    double *m = x[j * w + i];
                    pixel_moment(w, h, i, j, m);
                    for (int q = 0; q < 3; q++) c[k][q] += y * m[q];
                    const double len = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]);
                    for (int q = 0; q < 3; q++) m[q] /= len;
                    members++;
                }
            assert_true(members > 500);
            for (int k = 0; k < n; k++) {
                if (L[k].kind != LUMIS_LIGHT_ENV_DIRECT) continue;
                const double len = sqrt(c[k][0] * c[k][0] + c[k][1] * c[k][1] + c[k][2] * c[k][2]);
                for (int q = 0; q < 3; q++) c[k][q] /= len;
                const double a = angle(L[k].dir, c[k]);
                if (!(a < 1e-6))
                    fail_msg("seed %d: light %d is %g rad off its centroid", (int)seed, k, a);
            }
            for (int p = 0; p < w * h; p++) {
                const int k = lab[p];
                if (L[k].kind != LUMIS_LIGHT_ENV_DIRECT) continue;
                const double *e = x[p];
                const double own = e[0] * c[k][0] + e[1] * c[k][1] + e[2] * c[k][2];
                for (int o = 0; o < n; o++) {
                    if (o == k || L[o].kind != LUMIS_LIGHT_ENV_DIRECT) continue;
                    /* |x - c|^2 = 2 - 2 x.c: nearer is a larger dot product */
                    const double other = e[0] * c[o][0] + e[1] * c[o][1] + e[2] * c[o][2];
                    if (!(other <= own + 1e-12))
                        fail_msg("variant %d, seed %d: pixel %d of cluster %d is nearer to %d's "
                                 "centre (dot %.15f, its own %.15f)",
                                 v, (int)seed, p, k, o, other, own);
                }
            }
            free(c);
            free(x);
            lumis_light_set_destroy(set);
        }
    assert_true(iterated > 0); /* real iterations, not only the seeds' assignment */
    lumis_envmap_destroy(env);
}

static void fhis_and_tmms_are_deterministic_and_refuse_bad_options(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(128, 64, speckle_pixel, 0.0f, 0.0f);
    for (int f = 0; f < 2; f++) {
        lumis_light_set *a = NULL, *b = NULL, *c = NULL;
        lumis_fhis_desc fd = {0};
        lumis_tmms_desc td = {0};
        fd.count = td.count = 40;
        fd.seed = td.seed = 11;
        if (f == 0) {
            assert_int_equal(lumis_lights_fhis(env, &fd, &a), LUMIS_OK);
            assert_int_equal(lumis_lights_fhis(env, &fd, &b), LUMIS_OK);
            fd.seed = 12;
            assert_int_equal(lumis_lights_fhis(env, &fd, &c), LUMIS_OK);
        } else {
            assert_int_equal(lumis_lights_tmms(env, &td, &a), LUMIS_OK);
            assert_int_equal(lumis_lights_tmms(env, &td, &b), LUMIS_OK);
            td.seed = 12;
            assert_int_equal(lumis_lights_tmms(env, &td, &c), LUMIS_OK);
        }
        int differs = 0;
        for (int s = 0; s < 8; s++) {
            const lumis_light *la, *lb, *lc;
            int na, nb, nc;
            lumis_light_set_get(a, s, &la, &na);
            lumis_light_set_get(b, s, &lb, &nb);
            lumis_light_set_get(c, s, &lc, &nc);
            assert_int_equal(na, 40);
            assert_int_equal(na, nb);
            assert_memory_equal(la, lb, (size_t)na * sizeof *la);
            differs |= memcmp(la, lc, (size_t)na * sizeof *la) != 0;
        }
        assert_true(differs); /* the seed moves every interleaved set's jitter */
        assert_memory_equal(lumis_light_set_labels(a, NULL, NULL),
                            lumis_light_set_labels(b, NULL, NULL), 128 * 64 * sizeof(int32_t));
        lumis_light_set_destroy(a);
        lumis_light_set_destroy(b);
        lumis_light_set_destroy(c);
    }
    lumis_envmap_destroy(env);

    env = make_env(16, 8, sky_pixel, 0.0f, 0.0f);
    lumis_light_set *set = (lumis_light_set *)&set;
    assert_int_equal(lumis_lights_fhis(NULL, NULL, &set), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(set);
    assert_int_equal(lumis_lights_tmms(env, NULL, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_lights_fhis(env, NULL, &set), LUMIS_OK); /* NULL == defaults */
    lumis_light_set_destroy(set);
    struct {
        int count, sets;
        float jitter, key, bw;
    } bad[] = {{-1, 0, 0.0f, 0.0f, 0.0f}, {129, 0, 0.0f, 0.0f, 0.0f},  {0, -2, 0.0f, 0.0f, 0.0f},
               {0, 65, 0.0f, 0.0f, 0.0f}, {4, 0, 1.5f, 0.0f, 0.0f},    {4, 0, NAN, 0.0f, 0.0f},
               {4, 0, 0.0f, -1.0f, 0.0f}, {4, 0, 0.0f, NAN, 0.0f},     {4, 0, 0.0f, 0.0f, 1.5f},
               {4, 0, 0.0f, 0.0f, -0.1f}, {4, 0, 0.0f, INFINITY, 0.0f}};
    for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
        tu_sink sink;
        tu_sink_init(&sink);
        lumis_tmms_desc td = {0};
        td.count = bad[b].count;
        td.sets = bad[b].sets;
        td.jitter = bad[b].jitter;
        td.key = bad[b].key;
        td.range_bandwidth = bad[b].bw;
        td.errors = sink.sink;
        set = (lumis_light_set *)&set;
        assert_int_equal(lumis_lights_tmms(env, &td, &set), LUMIS_ERR_INVALID_ARGUMENT);
        assert_null(set);
        assert_true(sink.count == 1 && strstr(sink.last, "tmms"));
        if (b < 6) {
            lumis_fhis_desc fd = {0};
            tu_sink_init(&sink);
            fd.count = td.count;
            fd.sets = td.sets;
            fd.jitter = td.jitter;
            fd.errors = sink.sink;
            assert_int_equal(lumis_lights_fhis(env, &fd, &set), LUMIS_ERR_INVALID_ARGUMENT);
            assert_null(set);
            assert_true(sink.count == 1 && strstr(sink.last, "fhis"));
        }
    }
    lumis_envmap_destroy(env);
}

static void deterministic_with_fixed_seeds(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(128, 64, speckle_pixel, 0.0f, 0.0f);
    lumis_decomp_desc d = {0};
    d.count = 40;
    d.seed = 11;
    d.threshold = 10.0f;
    lumis_light_set *a = NULL, *b = NULL, *c = NULL;
    assert_int_equal(lumis_lights_decompose(env, &d, &a), LUMIS_OK);
    assert_int_equal(lumis_lights_decompose(env, &d, &b), LUMIS_OK);
    d.seed = 12;
    assert_int_equal(lumis_lights_decompose(env, &d, &c), LUMIS_OK);
    int differs = 0;
    for (int s = 0; s < 8; s++) {
        const lumis_light *la, *lb, *lc;
        int na, nb, nc;
        lumis_light_set_get(a, s, &la, &na);
        lumis_light_set_get(b, s, &lb, &nb);
        lumis_light_set_get(c, s, &lc, &nc);
        assert_int_equal(na, nb);
        assert_memory_equal(la, lb, (size_t)na * sizeof *la);
        differs |= na != nc || memcmp(la, lc, (size_t)na * sizeof *la) != 0;
    }
    assert_true(differs);
    assert_memory_equal(lumis_light_set_labels(a, NULL, NULL),
                        lumis_light_set_labels(b, NULL, NULL), 128 * 64 * sizeof(int32_t));
    lumis_light_set_destroy(a);
    lumis_light_set_destroy(b);
    lumis_light_set_destroy(c);
    lumis_envmap_destroy(env);
}

/* Every light of every set (and Wu's labels) of the three methods with SIMD passes. */
typedef struct simd_result {
    lumis_light_set *set[3];
} simd_result;

static simd_result simd_lights(const lumis_envmap *env)
{
    simd_result r;
    lumis_median_cut_desc md = {0};
    md.count = 64;
    lumis_variance_min_desc vd = {0};
    vd.count = 64;
    lumis_decomp_desc dd = {0};
    dd.count = 64;
    dd.seed = 3;
    assert_int_equal(lumis_lights_median_cut(env, &md, &r.set[0]), LUMIS_OK);
    assert_int_equal(lumis_lights_variance_min(env, &vd, &r.set[1]), LUMIS_OK);
    assert_int_equal(lumis_lights_decompose(env, &dd, &r.set[2]), LUMIS_OK);
    return r;
}

/* lumis's SIMD variants (the band sums for AVX-512, AVX2 and the baseline; Wu's passes for
 * AVX2 and the baseline; k-means' AVX-512 visits) give the same light sets bit for bit: each
 * variant the CPU has is forced in turn and compared with the baseline, on maps whose sides
 * are no multiple of the passes' widths (partial bands and tiles) and one large enough for
 * the coarse band level.  CI also runs the whole suite with each variant forced
 * (LUMIS_SIMD). */
static void simd_variants_give_identical_lights(void **state)
{
    (void)state;
    const char *best = lumis_simd_variant();
    assert_non_null(best);
    int top = strcmp(best, "avx512") == 0 ? LUMIS__SIMD_AVX512
              : strcmp(best, "avx2") == 0 ? LUMIS__SIMD_AVX2
                                          : LUMIS__SIMD_BASELINE;
    if (top < LUMIS__SIMD_AVX512)
        print_message("note: this CPU (or LUMIS_SIMD) stops at %s; the higher variants are "
                      "not compared here\n",
                      best);
    lumis_envmap *maps[] = {make_env(517, 259, speckle_pixel, 0.3f, 0.0f),
                            make_env(1031, 515, sky_pixel, 0.0f, 0.0f)};
    for (size_t m = 0; m < sizeof maps / sizeof *maps; m++) {
        lumis__simd_force(LUMIS__SIMD_BASELINE);
        simd_result base = simd_lights(maps[m]);
        for (int level = LUMIS__SIMD_AVX2; level <= top; level++) {
            lumis__simd_force(level);
            simd_result r = simd_lights(maps[m]);
            for (int k = 0; k < 3; k++) {
                const int sets = lumis_light_set_sets(base.set[k]);
                assert_int_equal(lumis_light_set_sets(r.set[k]), sets);
                for (int s = 0; s < sets; s++) {
                    const lumis_light *la, *lb;
                    int na, nb;
                    lumis_light_set_get(base.set[k], s, &la, &na);
                    lumis_light_set_get(r.set[k], s, &lb, &nb);
                    assert_int_equal(na, nb);
                    if (memcmp(la, lb, (size_t)na * sizeof *la) != 0)
                        fail_msg("map %zu, method %d, set %d: variant %d differs from the "
                                 "baseline",
                                 m, k, s, level);
                }
                const int32_t *a = lumis_light_set_labels(base.set[k], NULL, NULL),
                              *b = lumis_light_set_labels(r.set[k], NULL, NULL);
                assert_true((a == NULL) == (b == NULL));
                if (a)
                    assert_memory_equal(a, b,
                                        (size_t)lumis_envmap_width(maps[m]) *
                                            (size_t)lumis_envmap_height(maps[m]) * sizeof(int32_t));
                lumis_light_set_destroy(r.set[k]);
            }
        }
        for (int k = 0; k < 3; k++) lumis_light_set_destroy(base.set[k]);
        lumis_envmap_destroy(maps[m]);
    }
    lumis__simd_force(-1);
}

/* Eq. 3's terms are three different things: with one weight dominant at a time (variance,
 * directional extent, energy), the modified cut splits different nodes on a map where
 * they rank the nodes differently, so every pair of the three cuts differs.  (An extent
 * computed from the variance passed every test: nothing looked at which node Eq. 3 picks.)
 * The map's emissive threshold is set out of reach, so every light is an EnvIndirect. */
static void eq3_terms_each_steer_the_cut(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(256, 128, sky_pixel, 0.0f, 0.0f);
    const float w[3][3] = {{1, 1e-6f, 1e-6f}, {1e-6f, 1, 1e-6f}, {1e-6f, 1e-6f, 1}};
    int32_t *labels[3];
    for (int k = 0; k < 3; k++) {
        lumis_decomp_desc d = {0};
        d.count = 24;
        d.sets = 1;
        d.threshold = 1e30f;
        d.w_v = w[k][0];
        d.w_d = w[k][1];
        d.w_e = w[k][2];
        lumis_light_set *set = NULL;
        assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
        assert_int_equal(lumis_light_set_get_info(set)->direct, 0);
        int lw, lh;
        const int32_t *l = lumis_light_set_labels(set, &lw, &lh);
        labels[k] = malloc((size_t)lw * (size_t)lh * sizeof(int32_t));
        memcpy(labels[k], l, (size_t)lw * (size_t)lh * sizeof(int32_t));
        lumis_light_set_destroy(set);
    }
    static const char *const names[3] = {"variance", "extent", "energy"};
    for (int a = 0; a < 3; a++)
        for (int b = a + 1; b < 3; b++)
            if (memcmp(labels[a], labels[b], 256 * 128 * sizeof(int32_t)) == 0)
                fail_msg("the cut by %s alone equals the cut by %s alone", names[a], names[b]);
    for (int k = 0; k < 3; k++) free(labels[k]);
    lumis_envmap_destroy(env);
}

/* Two emissive patches of equal size, one three times as bright as the other. */
static float two_patches(int w, int h, int i, int j, int c)
{
    (void)w, (void)h, (void)c;
    if (j >= 20 && j < 40 && i >= 20 && i < 60) return 10.0f;
    if (j >= 20 && j < 40 && i >= 140 && i < 180) return 30.0f;
    return 0.1f;
}

/* The first pixel (row-major) of every EnvDirect's region, Wu's importance sampling alone
 * (no masking, no k-means: each seed keeps its cluster) with K = 400 and L_T = 5; returns
 * their number (at most cap) and the map's width in *w. */
static int envdirect_seed_pixels(const lumis_envmap *env, uint64_t seed, int *pixels, int cap,
                                 int *w)
{
    lumis_decomp_desc d = {0};
    d.count = 400;
    d.sets = 1;
    d.seed = seed;
    d.threshold = 5.0f;
    d.variant = LUMIS_DECOMP_IS_ONLY;
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
    const lumis_light *l = NULL;
    int n = 0, h, found = 0;
    assert_int_equal(lumis_light_set_get(set, 0, &l, &n), LUMIS_OK);
    const int32_t *lab = lumis_light_set_labels(set, w, &h);
    for (int k = 0; k < n && found < cap; k++) {
        if (l[k].kind != LUMIS_LIGHT_ENV_DIRECT) continue;
        for (int p = 0; p < *w * h; p++)
            if (lab[p] == k) {
                pixels[found++] = p;
                break;
            }
    }
    lumis_light_set_destroy(set);
    return found;
}

/* EnvDirect seeds are drawn in proportion to energy: with importance sampling alone (no
 * masking, no k-means, so each seed keeps its cluster), the dimmer patch, a quarter of the
 * emissive energy, gets about a quarter of the EnvDirects (binomial bounds, fixed seed).
 * Seeds drawn out of proportion to energy (uniformly over the emissive pixels) give it
 * half: nothing looked at the seeds before. */
static void envdirect_seeds_follow_energy(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(256, 128, two_patches, 0.0f, 0.0f);
    int seeds[400], w, dim = 0, bright = 0;
    const int n = envdirect_seed_pixels(env, 5, seeds, 400, &w);
    for (int k = 0; k < n; k++) *(seeds[k] % w < 128 ? &dim : &bright) += 1;
    const int total = dim + bright;
    /* p = 1/4: mean total / 4, standard deviation sqrt(total 3 / 16); 4.5 of them */
    const double mean = total / 4.0, sd = sqrt(total * 3.0 / 16.0);
    if (total < 40 || fabs(dim - mean) > 4.5 * sd)
        fail_msg("%d EnvDirects: %d on the dim patch, %d on the bright one (want %.1f +- %.1f)",
                 total, dim, bright, mean, 4.5 * sd);
    lumis_envmap_destroy(env);
}

/* Eq. 2 from the pixels: with the emissive pixels those over the reported L_T, G = L^a
 * dw^b per part (L its mean luminance, dw its solid angle, a = 1 and b = 1/4 by default
 * or as given), N = round(K G_em / (G_em + G_nem)) clamped to [1, K - 1].  Only the lights'
 * kinds were checked before: a budget from the emissive part's total energy, or from the
 * exponents swapped, passed. */
static void eq2_budget_from_the_pixels(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(128, 64, sky_pixel, 0.0f, 0.0f);
    const float ab[2][2] = {{0.0f, 0.0f}, {0.5f, 0.75f}};
    for (int v = 0; v < 2; v++) {
        lumis_decomp_desc d = {0};
        d.count = 48;
        d.sets = 1;
        d.seed = 1;
        d.budget_a = ab[v][0];
        d.budget_b = ab[v][1];
        lumis_light_set *set = NULL;
        assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
        const lumis_light_set_info *info = lumis_light_set_get_info(set);
        long double e[2] = {0, 0}, o[2] = {0, 0};
        int m = 0;
        for (int j = 0; j < 64; j++)
            for (int i = 0; i < 128; i++) {
                const double y = pixel_y(env, i, j), om = lumis_envmap_pixel_solid_angle(env, j);
                const int em = y > info->threshold;
                m += em;
                e[em] += (long double)y * om;
                o[em] += om;
            }
        assert_int_equal(info->emissive_pixels, m);
        assert_true(m > 0 && m < 128 * 64);
        const double a = v ? 0.5 : 1.0, b = v ? 0.75 : 0.25;
        const double g_ne = pow((double)(e[0] / o[0]), a) * pow((double)o[0], b),
                     g_em = pow((double)(e[1] / o[1]), a) * pow((double)o[1], b);
        if (!(fabs(info->gamma_em - g_em) <= 1e-9 * g_em &&
              fabs(info->gamma_nem - g_ne) <= 1e-9 * g_ne))
            fail_msg("a = %g, b = %g: Gamma_em %.12g (want %.12g), Gamma_nem %.12g (want %.12g)", a,
                     b, info->gamma_em, g_em, info->gamma_nem, g_ne);
        long long N = llround(48.0 * g_em / (g_em + g_ne));
        N = N < 1 ? 1 : (N > 47 ? 47 : N);
        N = N > m ? m : N;
        assert_int_equal(info->budget, (int)N);
        lumis_light_set_destroy(set);
    }
    lumis_envmap_destroy(env);
}

/* Most of the sphere bright (Y 2 to 3 over the upper 70 % of rows), the rest dim: with
 * L_T = 1 the emissive class is the larger by solid angle, which Eq. 2 (Delta w^(1/4))
 * gives fewer lights than its power share. */
/* A dim room with 64 small bright spots (L_T = 5): Eq. 2 gives the spots most lights, far
 * more than their power share (the lobby's case). */
static float bright_spots(int w, int h, int i, int j, int c)
{
    (void)c, (void)w, (void)h;
    return i % 16 == 3 && j % 8 == 3 ? 20.0f : 1.0f;
}

static float bright_majority(int w, int h, int i, int j, int c)
{
    (void)c, (void)w;
    return j < (7 * h) / 10 ? 2.0f + (float)((i * 7 + j * 3) % 11) / 10.0f : 0.5f;
}

/* min_share: each class gets at least ceil(q K P_class / P) lights, clamped before Eq. 2's
 * own clamps; q = 1 is the split by power.  With bright spots in a dim room (the ceiling
 * binds) and on a mostly bright map (the floor binds), every q from 0.25 to 1 gives the
 * budget that formula predicts from the pixels. */
static void min_share_on_one_map(int map)
{
    lumis_envmap *env = make_env(128, 64, map ? bright_majority : bright_spots, 0.0f, 0.0f);
    long double e[2] = {0, 0};
    double base_n = 0.0;
    int bound = 0; /* the floor or the ceiling changed Eq. 2's N */
    for (int v = 0; v < 5; v++) {
        static const float q[5] = {0.0f, 0.25f, 0.5f, 0.75f, 1.0f};
        lumis_decomp_desc d = {0};
        d.count = 48;
        d.sets = 1;
        d.seed = 1;
        d.threshold = map ? 1.0f : 5.0f;
        d.min_share = q[v];
        lumis_light_set *set = NULL;
        assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
        const lumis_light_set_info *info = lumis_light_set_get_info(set);
        if (v == 0) {
            for (int j = 0; j < 64; j++)
                for (int i = 0; i < 128; i++) {
                    const double y = pixel_y(env, i, j),
                                 om = lumis_envmap_pixel_solid_angle(env, j);
                    e[y > info->threshold] += (long double)y * om;
                }
            base_n = info->budget;
        } else {
            const double p_em = (double)(e[1] / (e[0] + e[1]));
            long long lo = (long long)ceil(q[v] * 48 * p_em - 1e-9),
                      hi = 48 - (long long)ceil(q[v] * 48 * (1 - p_em) - 1e-9);
            long long N = (long long)base_n;
            N = N < lo ? lo : N; /* the floor, then the ceiling: when rounding up makes
                                    both classes' floors exceed K, the non-emissive wins */
            N = N > hi ? hi : N;
            N = N < 1 ? 1 : (N > 47 ? 47 : N);
            N = N > info->emissive_pixels ? info->emissive_pixels : N;
            if (info->budget != (int)N)
                fail_msg("map %d, min_share %g: budget %d, want %lld (Eq. 2 alone %g, P_em/P "
                         "%.4f)",
                         map, q[v], info->budget, N, base_n, p_em);
            bound |= info->budget != (int)base_n;
            if (v == 4 && !(map ? info->budget > base_n : info->budget < base_n))
                fail_msg("map %d: min_share 1 gives %d EnvDirects, Eq. 2 %g", map, info->budget,
                         base_n);
        }
        lumis_light_set_destroy(set);
    }
    assert_true(bound);
    lumis_envmap_destroy(env);
}

static void min_share_floors_each_class_by_power(void **state)
{
    (void)state;
    min_share_on_one_map(0);
    min_share_on_one_map(1);
}

/* The light tree splits a node across its longer side (in radians), at the middle: the
 * whole 256 x 128 map (2 pi wide, pi high) splits into its left and right halves, each of
 * those (pi by pi at the equator) again across x. */
static void the_cut_splits_the_longer_side_in_the_middle(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(256, 128, sky_pixel, 0.0f, 0.0f);
    for (int k = 2; k <= 4; k += 2) {
        lumis_decomp_desc d = {0};
        d.count = k;
        d.sets = 1;
        d.threshold = 1e30f;
        d.cut = LUMIS_CUT_ORIGINAL;
        lumis_light_set *set = NULL;
        assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_OK);
        const int32_t *lab = lumis_light_set_labels(set, NULL, NULL);
        for (int q = 0; q < k; q++) {
            box b = label_box(lab, 256, 128, q);
            const int wdt = 256 / k;
            if (!(b.y0 == 0 && b.y1 == 128 && b.x1 - b.x0 == wdt && b.x0 % wdt == 0))
                fail_msg("K = %d, light %d: columns [%d, %d), rows [%d, %d)", k, q, b.x0, b.x1,
                         b.y0, b.y1);
        }
        lumis_light_set_destroy(set);
    }
    lumis_envmap_destroy(env);
}

/* Eq. 3 normalises each term by its maximum over the cut, so a map scaled by 2^10 (every
 * variance and energy scaled exactly, the extents unchanged) gives the very same cut; a
 * term normalised by another term's maximum does not. */
static void eq3_is_invariant_to_the_maps_scale(void **state)
{
    (void)state;
    lumis_envmap *a = make_env(256, 128, sky_pixel, 0.0f, 1.0f),
                 *b = make_env(256, 128, sky_pixel, 0.0f, 1024.0f);
    lumis_decomp_desc d = {0};
    d.count = 40;
    d.sets = 1;
    d.threshold = 1e30f;
    lumis_light_set *sa = NULL, *sb = NULL;
    assert_int_equal(lumis_lights_decompose(a, &d, &sa), LUMIS_OK);
    assert_int_equal(lumis_lights_decompose(b, &d, &sb), LUMIS_OK);
    assert_memory_equal(lumis_light_set_labels(sa, NULL, NULL),
                        lumis_light_set_labels(sb, NULL, NULL), 256 * 128 * sizeof(int32_t));
    lumis_light_set_destroy(sa);
    lumis_light_set_destroy(sb);
    lumis_envmap_destroy(a);
    lumis_envmap_destroy(b);
}

/* Two emissive patches of equal luminance and size, one near the pole and one on the
 * equator: EnvDirect seeds are drawn by energy (luminance times solid angle), so the polar
 * patch gets its share of the energy, about 15 %, not half (binomial bounds, fixed seed). */
static float pole_and_equator(int w, int h, int i, int j, int c)
{
    (void)w, (void)h, (void)c;
    if (i >= 40 && i < 80 && ((j >= 4 && j < 9) || (j >= 61 && j < 66))) return 20.0f;
    return 0.1f;
}

static void envdirect_seeds_weigh_solid_angle(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(256, 128, pole_and_equator, 0.0f, 0.0f);
    double ep = 0.0, eq = 0.0;
    for (int j = 4; j < 9; j++) ep += lumis_envmap_pixel_solid_angle(env, j);
    for (int j = 61; j < 66; j++) eq += lumis_envmap_pixel_solid_angle(env, j);
    int seeds[400], w, polar = 0;
    const int total = envdirect_seed_pixels(env, 9, seeds, 400, &w);
    for (int k = 0; k < total; k++) polar += seeds[k] / w < 32;
    const double f = ep / (ep + eq), mean = total * f, sd = sqrt(total * f * (1 - f));
    if (total < 40 || fabs(polar - mean) > 4.5 * sd)
        fail_msg("%d EnvDirects: %d on the polar patch (want %.1f +- %.1f)", total, polar, mean,
                 4.5 * sd);
    lumis_envmap_destroy(env);
}

/* FHIS's importance is energy: on a constant map its points are uniform per solid angle,
 * so half of them lie within 60 degrees of a pole (|y| > 1/2), not the two thirds of the
 * rows there. */
static void fhis_points_are_uniform_on_a_constant_map(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(256, 128, const_pixel, 0.0f, 0.0f);
    lumis_light_set *set = NULL;
    assert_int_equal(build_fhis(env, 600, &set), LUMIS_OK);
    const lumis_light *L;
    int n, caps = 0;
    assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
    assert_int_equal(n, 600);
    for (int k = 0; k < n; k++) caps += fabsf(L[k].dir.y) > 0.5f;
    if (!(caps > 255 && caps < 345)) fail_msg("%d of 600 points near the poles (want 300)", caps);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* A light's extent bounds every point of its pixels, not only their centres: the corners
 * and edge midpoints of every pixel of FHIS's and TMMS's Voronoi-like regions lie in the
 * light's cone.  And TMMS takes a range bandwidth of exactly 1 (documented as (0, 1]). */
static void label_extents_cover_whole_pixels(void **state)
{
    (void)state;
    static const build_fn fns[] = {build_fhis, build_tmms};
    lumis_envmap *env = make_env(64, 32, sky_pixel, 0.0f, 0.0f);
    for (size_t f = 0; f < 2; f++)
        for (int k = 5; k <= 40; k *= 2) {
            lumis_light_set *set = NULL;
            assert_int_equal(fns[f](env, k, &set), LUMIS_OK);
            const lumis_light *L;
            int n;
            assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
            const int32_t *lab = lumis_light_set_labels(set, NULL, NULL);
            for (int j = 0; j < 32; j++)
                for (int i = 0; i < 64; i++) {
                    const lumis_light *l = &L[lab[j * 64 + i]];
                    for (int c = 0; c < 9; c++) {
                        if (c == 4) continue; /* the centre: check_set's */
                        const float u = (float)((i + 0.5 * (c % 3)) / 64),
                                    v = (float)((j + 0.5 * (c / 3)) / 32);
                        const lumis_vec3 p = lumis_envmap_uv_to_dir(env, u, v);
                        double dd[3] = {p.x, p.y, p.z};
                        if (!(angle(l->dir, dd) <= (double)l->extent + 1e-5))
                            fail_msg("%s, K = %d: pixel (%d, %d), point %d at %g of an extent %g",
                                     f ? "tmms" : "fhis", k, i, j, c, angle(l->dir, dd),
                                     (double)l->extent);
                    }
                }
            lumis_light_set_destroy(set);
        }
    lumis_tmms_desc td = {0};
    td.count = 8;
    td.range_bandwidth = 1.0f;
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_tmms(env, &td, &set), LUMIS_OK);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* The energy E and first moment M of a box by the pixel quadrature of
 * variance_min_splits_minimise_the_summed_variance (v: E, Mx, My, Mz). */
static void box_sums(const lumis_envmap *env, box b, long double v[4])
{
    const int W = lumis_envmap_width(env), H = lumis_envmap_height(env);
    v[0] = v[1] = v[2] = v[3] = 0;
    for (int j = b.y0; j < b.y1; j++) {
        const double t0 = PI * j / H, t1 = PI * (j + 1) / H;
        const double A = gauss16(sin_sq, t0, t1), B = gauss16(sin_cos, t0, t1) * 2 * PI / W;
        for (int i = b.x0; i < b.x1; i++) {
            const double p0 = 2 * PI * i / W, p1 = 2 * PI * (i + 1) / W;
            const long double y = pixel_y(env, i, j);
            v[0] += y * (long double)lumis_envmap_pixel_solid_angle(env, j);
            v[1] += y * (long double)(A * (sin(p1) - sin(p0)));
            v[2] += y * (long double)B;
            v[3] += y * (long double)(A * (cos(p0) - cos(p1)));
        }
    }
}

/* With K = 3 the second split goes to the first split's half of larger priority: energy
 * for median cut, variance for variance minimisation (the halves of K = 2 are the first
 * split; lights 0, 1 or 1, 2 of K = 3 are the halves of the one split again).  Only
 * powers of two were checked before, where every region splits: a priority by area, or
 * by energy for variance minimisation, passed. */
static void the_second_split_takes_the_larger_priority(void **state)
{
    (void)state;
    lumis_envmap *maps[] = {make_env(256, 128, sky_pixel, 0.0f, 0.0f),
                            make_env(200, 100, sky_pixel, 0.0f, 0.0f),
                            make_env(300, 150, sky_pixel, 0.0f, 0.0f),
                            make_env(64, 32, sky_pixel, 0.0f, 0.0f),
                            make_env(128, 64, speckle_pixel, 0.0f, 0.0f),
                            make_env(96, 48, speckle_pixel, 0.0f, 0.0f),
                            make_env(256, 128, two_patches, 0.0f, 0.0f),
                            make_env(256, 128, pole_and_equator, 0.0f, 0.0f)};
    for (size_t e = 0; e < sizeof maps / sizeof *maps; e++)
        for (int method = 0; method < 2; method++) {
            lumis_envmap *env = maps[e];
            const int w = lumis_envmap_width(env), h = lumis_envmap_height(env);
            const build_fn fn = method ? build_vm : build_mc;
            lumis_light_set *two = NULL, *three = NULL;
            assert_int_equal(fn(env, 2, &two), LUMIS_OK);
            assert_int_equal(fn(env, 3, &three), LUMIS_OK);
            const int32_t *l2 = lumis_light_set_labels(two, NULL, NULL),
                          *l3 = lumis_light_set_labels(three, NULL, NULL);
            const box a = label_box(l2, w, h, 0), b = label_box(l2, w, h, 1);
            const box t0 = label_box(l3, w, h, 0), t2 = label_box(l3, w, h, 2);
            const int a_split = memcmp(&t2, &b, sizeof b) == 0,
                      b_split = memcmp(&t0, &a, sizeof a) == 0;
            assert_true(a_split != b_split);
            long double va[4], vb[4];
            box_sums(env, a, va);
            box_sums(env, b, vb);
            const long double pa = method ? region_variance(va) : va[0],
                              pb = method ? region_variance(vb) : vb[0];
            const long double split = a_split ? pa : pb, kept = a_split ? pb : pa;
            if (!(split >= kept * (1 - 1e-9L)))
                fail_msg("map %zu, %s: the half of %s %Lg split before the one of %Lg", e,
                         method ? "variance minimisation" : "median cut",
                         method ? "variance" : "energy", split, kept);
            lumis_light_set_destroy(two);
            lumis_light_set_destroy(three);
        }
    for (size_t e = 0; e < sizeof maps / sizeof *maps; e++) lumis_envmap_destroy(maps[e]);
}

static void special_maps_get_a_clear_answer(void **state)
{
    (void)state;
    static const build_fn fns[] = {build_mc, build_vm, build_wu, build_wu_cut_only};
    /* Black and constant maps: K lights, no emissive pixel, nothing lost. */
    lumis_envmap *black = make_env(32, 16, black_pixel, 0.0f, 0.0f);
    lumis_envmap *flat = make_env(32, 16, const_pixel, 0.0f, 0.0f);
    for (size_t f = 0; f < 4; f++)
        for (int k = 1; k <= 20; k += 19) {
            lumis_light_set *set = NULL;
            assert_int_equal(fns[f](black, k, &set), LUMIS_OK);
            check_set(set, black);
            assert_int_equal(lumis_light_set_get_info(set)->count, k);
            lumis_light_set_destroy(set);
            assert_int_equal(fns[f](flat, k, &set), LUMIS_OK);
            check_set(set, flat);
            assert_int_equal(lumis_light_set_get_info(set)->count, k);
            assert_int_equal(lumis_light_set_get_info(set)->direct, 0);
            lumis_light_set_destroy(set);
        }
    /* Only emissive pixels: every light is an EnvDirect. */
    for (int k = 1; k <= 64; k *= 4) {
        lumis_decomp_desc d = {0};
        d.count = k;
        d.threshold = 1e-6f;
        tu_sink sink;
        tu_sink_init(&sink);
        d.errors = sink.sink;
        lumis_light_set *set = NULL;
        assert_int_equal(lumis_lights_decompose(flat, &d, &set), LUMIS_OK);
        const lumis_light_set_info *info = lumis_light_set_get_info(set);
        assert_int_equal(info->emissive_pixels, 32 * 16);
        assert_true(info->count >= 1);
        if (info->count < k) assert_true(sink.count > 0 && strstr(sink.last, "lights instead of"));
        check_set(set, flat);
        lumis_light_set_destroy(set);
        /* Without masking and k-means' drop of duplicates the budget is spent in full. */
    }
    lumis_envmap_destroy(black);
    lumis_envmap_destroy(flat);
}

static void malformed_options_are_refused(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(16, 8, sky_pixel, 0.0f, 0.0f);
    lumis_light_set *set = (lumis_light_set *)&set; /* must be reset to NULL */
    tu_sink sink;
    lumis_median_cut_desc m = {0};
    assert_int_equal(lumis_lights_median_cut(NULL, &m, &set), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(set);
    assert_int_equal(lumis_lights_median_cut(env, &m, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_lights_variance_min(env, NULL, &set), LUMIS_OK); /* NULL == defaults */
    lumis_light_set_destroy(set);
    struct {
        int count, sets;
        float jitter;
    } bad_common[] = {{-1, 0, 0.0f}, {129, 0, 0.0f}, {0, -2, 0.0f}, {0, 65, 0.0f},
                      {4, 0, 1.5f},  {4, 0, -0.1f},  {4, 0, NAN}};
    for (size_t b = 0; b < sizeof bad_common / sizeof bad_common[0]; b++) {
        tu_sink_init(&sink);
        m.count = bad_common[b].count;
        m.sets = bad_common[b].sets;
        m.jitter = bad_common[b].jitter;
        m.errors = sink.sink;
        assert_int_equal(lumis_lights_median_cut(env, &m, &set), LUMIS_ERR_INVALID_ARGUMENT);
        assert_null(set);
        assert_true(sink.count == 1 && strlen(sink.last) > 10);
        assert_int_equal(lumis_lights_variance_min(env, &m, &set), LUMIS_ERR_INVALID_ARGUMENT);
        lumis_decomp_desc d = {0};
        d.count = m.count;
        d.sets = m.sets;
        d.jitter = m.jitter;
        assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_ERR_INVALID_ARGUMENT);
    }
    /* The default K = 64 on a map of fewer pixels is refused, not silently reduced. */
    lumis_envmap *tiny = make_env(4, 2, sky_pixel, 0.0f, 0.0f);
    assert_int_equal(lumis_lights_median_cut(tiny, NULL, &set), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_envmap_destroy(tiny);
    for (int b = 0; b < 14; b++) {
        lumis_decomp_desc d = {0};
        tu_sink_init(&sink);
        d.errors = sink.sink;
        d.count = 4;
        switch (b) {
        case 0:
            d.variant = (lumis_decomp_variant)99;
            break;
        case 1:
            d.cut = (lumis_cut_objective)-1;
            break;
        case 2:
            d.mask_radius = LUMIS_MASK_COUNT;
            break;
        case 3:
            d.percentile = 100.5f;
            break;
        case 4:
            d.percentile = -1.0f;
            break;
        case 5:
            d.lambda = -3.0f;
            break;
        case 6:
            d.gamma = INFINITY;
            break;
        case 7:
            d.threshold = NAN;
            break;
        case 8:
            d.budget_a = -1.0f;
            break;
        case 9:
            d.budget_b = NAN;
            break;
        case 10:
            d.mask_scale = -0.15f;
            break;
        case 11:
            d.return_factor = -2.0f;
            break;
        case 12:
            d.kmeans_max_iterations = -1;
            break;
        default:
            d.w_d = -5.0f;
            break;
        }
        assert_int_equal(lumis_lights_decompose(env, &d, &set), LUMIS_ERR_INVALID_ARGUMENT);
        assert_null(set);
        assert_true(sink.count == 1 && strstr(sink.last, "decomposition"));
    }
    const lumis_light *L = NULL;
    int n = 0;
    assert_int_equal(lumis_light_set_get(NULL, 0, &L, &n), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(build_mc(env, 4, &set), LUMIS_OK);
    assert_int_equal(lumis_light_set_get(set, 8, &L, &n), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_light_set_get(set, -1, &L, &n), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_light_set_destroy(set);
    lumis_light_set_destroy(NULL);
    lumis_envmap_destroy(env);
}

/* Folding the lights below the ground into the nearest ones above: none left below, every
 * region still labelled and inside its light's cone, the power of each light what brute force
 * says (its own plus the folded lights nearest to it), the total unchanged, and the report's
 * folded power that of the lights that went. */
static void fold_below_conserves_power_into_the_nearest_light(void **state)
{
    (void)state;
    lumis_envmap *env = make_env(64, 32, sky_pixel, 30.0f, 1.0f);
    for (int method = 0; method < 2; method++) {
        lumis_light_set *set = NULL;
        assert_int_equal(method ? build_wu(env, 16, &set) : build_mc(env, 16, &set), LUMIS_OK);
        const lumis_light *L;
        int n;
        assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
        lumis_light before[16];
        assert_true(n <= 16);
        memcpy(before, L, sizeof *L * (size_t)n);
        /* brute force: each light's power after the fold, in the order the kept ones stay */
        double want[16][3] = {{0}}, moved[3] = {0, 0, 0};
        int kept = 0, slot[16];
        for (int k = 0; k < n; k++) slot[k] = before[k].dir.y > 0.0f ? kept++ : -1;
        assert_true(kept > 0 && kept < n); /* the map's floor makes lights below */
        for (int k = 0; k < n; k++) {
            int to = k;
            if (slot[k] < 0) {
                double best = -2.0;
                for (int q = 0; q < n; q++) {
                    const double c = (double)before[k].dir.x * before[q].dir.x +
                                     (double)before[k].dir.y * before[q].dir.y +
                                     (double)before[k].dir.z * before[q].dir.z;
                    if (slot[q] >= 0 && c > best) best = c, to = q;
                }
                for (int c = 0; c < 3; c++) moved[c] += before[k].power[c];
            }
            for (int c = 0; c < 3; c++) want[slot[to]][c] += before[k].power[c];
        }
        lumis_light_fold r;
        const lumis_vec3 up = {0.0f, 2.0f, 0.0f}; /* any length */
        assert_int_equal(lumis_light_set_fold_below(set, up, NULL, &r), LUMIS_OK);
        assert_int_equal(r.kept, kept);
        assert_int_equal(r.folded, n - kept);
        assert_int_equal(lumis_light_set_get_info(set)->count, kept);
        check_set(set, env); /* labels, cones, sets, the map's power */
        assert_int_equal(lumis_light_set_get(set, 0, &L, &n), LUMIS_OK);
        assert_int_equal(n, kept);
        double total = 0.0, y_moved = 0.2126 * moved[0] + 0.7152 * moved[1] + 0.0722 * moved[2];
        for (int k = 0; k < n; k++) {
            assert_true(L[k].dir.y > 0.0f);
            for (int c = 0; c < 3; c++)
                assert_true(fabs(L[k].power[c] - want[k][c]) <= 1e-12 * want[k][c]);
            total += 0.2126 * L[k].power[0] + 0.7152 * L[k].power[1] + 0.0722 * L[k].power[2];
        }
        for (int c = 0; c < 3; c++) assert_true(fabs(r.power[c] - moved[c]) <= 1e-12 * moved[c]);
        assert_true(r.share > 0.0 && fabs(r.share - y_moved / total) < 1e-12);
        if (method) { /* Wu's kinds are counted again */
            const lumis_light_set_info *info = lumis_light_set_get_info(set);
            int d = 0;
            for (int k = 0; k < n; k++) d += L[k].kind == LUMIS_LIGHT_ENV_DIRECT;
            assert_int_equal(info->direct, d);
            assert_int_equal(info->indirect, n - d);
        }
        /* nothing above the opposite plane now: refused, the set unchanged */
        tu_sink sink;
        tu_sink_init(&sink);
        const lumis_vec3 down = {0.0f, -1.0f, 0.0f}, zero = {0.0f, 0.0f, 0.0f};
        assert_int_equal(lumis_light_set_fold_below(set, down, &sink.sink, &r),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(sink.last, "above the plane"));
        assert_int_equal(lumis_light_set_fold_below(set, zero, NULL, NULL),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_light_set_fold_below(NULL, up, NULL, NULL),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_light_set_get_info(set)->count, kept);
        /* folding again changes nothing */
        assert_int_equal(lumis_light_set_fold_below(set, up, NULL, &r), LUMIS_OK);
        assert_true(r.folded == 0 && r.kept == kept && r.share == 0.0);
        lumis_light_set_destroy(set);
    }
    lumis_envmap_destroy(env);
}

static void interleave_pattern_covers_every_set(void **state)
{
    (void)state;
    for (int sets = 1; sets <= 64; sets++) {
        int seen[64] = {0};
        /* one tile: every set exactly once, and the pattern repeats */
        int b = 1;
        for (int d = 1; d * d <= sets; d++)
            if (sets % d == 0) b = d;
        int a = sets / b;
        for (int y = 0; y < b; y++)
            for (int x = 0; x < a; x++) {
                int s = lumis_light_set_interleave_index(sets, x, y);
                assert_true(s >= 0 && s < sets);
                seen[s]++;
                assert_int_equal(lumis_light_set_interleave_index(sets, x + 5 * a, y + 3 * b), s);
            }
        for (int s = 0; s < sets; s++) assert_int_equal(seen[s], 1);
    }
    assert_int_equal(lumis_light_set_interleave_index(8, 3, 1), 7); /* a 4 x 2 tile */
}

/* Methods and parameters by name (what a host application exposes, as the tool does): every
 * name builds the method it names, the same lights as the method's own call; NAME=VALUE
 * pairs set their fields, format back in table order, and bad ones are refused with a
 * message naming them. */
static void methods_and_parameters_by_name(void **state)
{
    (void)state;
    int n = 0;
    lumis_lights_method method = (lumis_lights_method)0;
    for (const char *const *name = lumis_lights_method_names(); *name; name++, n++) {
        method = (lumis_lights_method)0;
        assert_int_equal(lumis_lights_method_from_name(*name, &method), LUMIS_OK);
        assert_int_not_equal(method, 0);
    }
    assert_int_equal(n, 9);
    assert_int_equal(lumis_lights_method_from_name("wu-is", &method), LUMIS_OK);
    assert_int_equal(method, LUMIS_LIGHTS_DECOMPOSITION);
    assert_int_equal(lumis_lights_method_from_name("fhis", &method), LUMIS_OK);
    assert_int_equal(method, LUMIS_LIGHTS_FHIS);
    /* a refused name leaves *out as it was */
    assert_int_equal(lumis_lights_method_from_name("median", &method), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(method, LUMIS_LIGHTS_FHIS);
    assert_int_equal(lumis_lights_method_from_name(NULL, &method), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_lights_method_from_name("fhis", NULL), LUMIS_ERR_INVALID_ARGUMENT);

    lumis_light_params p = {0};
    assert_int_equal(
        lumis_light_params_parse(&p, "seed=9,lambda=5,,mask=radians,jitter=0.25", NULL), LUMIS_OK);
    assert_float_equal(p.wu.lambda, 5.0f, 0.0f);
    assert_int_equal(p.wu.mask_radius, LUMIS_MASK_RADIANS);
    assert_float_equal(p.jitter, 0.25f, 0.0f);
    assert_true(p.seed == 9);
    char buf[256];
    lumis_light_params_format(&p, buf, sizeof buf);
    assert_string_equal(buf, "lambda=5,mask=radians,jitter=0.25,seed=9");
    assert_int_equal(lumis_light_params_check(&p, "wu-is-mask", NULL), LUMIS_OK);
    tu_sink sink;
    tu_sink_init(&sink);
    assert_int_equal(lumis_light_params_check(&p, "median-cut", &sink.sink),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "'lambda' is a parameter of Wu"));
    static const struct {
        const char *text, *says;
    } bad[] = {{"lambda=0", "lambda=VALUE needs"},
               {"percentile=100.5", "in (0, 100]"},
               {"jitter=1.5", "in (0, 1]"},
               {"seed=-3", "an unsigned integer"},
               {"kmeans-iterations=0", "a count"},
               {"gamma=1e-300", "at least 1.2e-38"},
               {"wv=1e39", "at most 3.4e38"},
               {"mask=disc", "cap"},
               {"lambda", "is not NAME=VALUE"},
               {"frobnicate=1", "unknown parameter"},
               {"", "NAME=VALUE"}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        lumis_light_params q = {0};
        tu_sink_init(&sink);
        if (lumis_light_params_parse(&q, bad[k].text, &sink.sink) != LUMIS_ERR_INVALID_ARGUMENT ||
            !strstr(sink.last, bad[k].says))
            fail_msg("'%s': '%s'", bad[k].text, sink.last);
    }
    /* a refused pair changes nothing: p holds the pairs before it (lights.h), bit for bit */
    lumis_light_params before = {0};
    assert_int_equal(lumis_light_params_parse(&before, "jitter=0.5,percentile=90,key=2", NULL),
                     LUMIS_OK);
    static const char *const refused[] = {
        "jitter=1.5", "percentile=100.5",    "key=0",     "bandwidth=-1",
        "gamma=1e39", "kmeans-iterations=0", "mask=disc", "seed=x"};
    for (size_t k = 0; k < sizeof refused / sizeof refused[0]; k++) {
        lumis_light_params q;
        memcpy(&q, &before, sizeof q); /* padding too, for the memcmp */
        assert_int_equal(lumis_light_params_parse(&q, refused[k], NULL),
                         LUMIS_ERR_INVALID_ARGUMENT);
        if (memcmp(&q, &before, sizeof q) != 0) fail_msg("'%s' changed the parameters", refused[k]);
    }
    /* by name == the method's own call, bit for bit */
    lumis_envmap *env = make_env(64, 32, sky_pixel, 0.0f, 0.0f);
    lumis_light_set *a = NULL, *b = NULL;
    lumis_light_params wp = {0};
    assert_int_equal(lumis_light_params_parse(&wp, "threshold=2,seed=3", NULL), LUMIS_OK);
    assert_int_equal(lumis_lights_by_name(env, "wu-is-kmeans", 16, 2, &wp, NULL, &a), LUMIS_OK);
    lumis_decomp_desc d = {0};
    d.count = 16;
    d.sets = 2;
    d.threshold = 2.0f;
    d.seed = 3;
    d.variant = LUMIS_DECOMP_IS_KMEANS;
    assert_int_equal(lumis_lights_decompose(env, &d, &b), LUMIS_OK);
    for (int set = 0; set < 2; set++) {
        const lumis_light *la = NULL, *lb = NULL;
        int na = 0, nb = 0;
        assert_int_equal(lumis_light_set_get(a, set, &la, &na), LUMIS_OK);
        assert_int_equal(lumis_light_set_get(b, set, &lb, &nb), LUMIS_OK);
        assert_int_equal(na, nb);
        assert_memory_equal(la, lb, (size_t)na * sizeof *la);
    }
    lumis_light_set_destroy(a);
    lumis_light_set_destroy(b);
    a = NULL;
    assert_int_equal(lumis_lights_by_name(env, "no-such", 16, 2, NULL, NULL, &a),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(a);
    lumis_envmap_destroy(env);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_method_conserves_power),
        cmocka_unit_test(fold_below_conserves_power_into_the_nearest_light),
        cmocka_unit_test(wu_on_tiled_maps_conserves_power),
        cmocka_unit_test(median_cut_regions_have_equal_energy),
        cmocka_unit_test(variance_min_splits_minimise_the_summed_variance),
        cmocka_unit_test(penrose_children_tile_their_parent),
        cmocka_unit_test(fhis_points_follow_the_importance),
        cmocka_unit_test(fhis_and_tmms_conserve_power_with_exactly_k_lights),
        cmocka_unit_test(fhis_regions_are_the_points_voronoi_cells),
        cmocka_unit_test(tmms_merges_into_the_weakest_neighbour),
        cmocka_unit_test(wu_indirect_lights_point_at_their_regions_centroid),
        cmocka_unit_test(fhis_and_tmms_are_deterministic_and_refuse_bad_options),
        cmocka_unit_test(every_method_is_invariant_to_the_maps_brightness),
        cmocka_unit_test(light_set_irradiance_against_closed_forms),
        cmocka_unit_test(one_light_per_pixel_is_exact),
        cmocka_unit_test(emissive_threshold_is_a_brute_force_percentile),
        cmocka_unit_test(kmeans_terminates_and_never_increases_its_objective),
        cmocka_unit_test(kmeans_stops_at_a_fixed_point),
        cmocka_unit_test(the_cut_yields_exactly_k_lights),
        cmocka_unit_test(wu_parts_and_ablations),
        cmocka_unit_test(deterministic_with_fixed_seeds),
        cmocka_unit_test(simd_variants_give_identical_lights),
        cmocka_unit_test(eq3_terms_each_steer_the_cut),
        cmocka_unit_test(envdirect_seeds_follow_energy),
        cmocka_unit_test(eq2_budget_from_the_pixels),
        cmocka_unit_test(min_share_floors_each_class_by_power),
        cmocka_unit_test(the_cut_splits_the_longer_side_in_the_middle),
        cmocka_unit_test(eq3_is_invariant_to_the_maps_scale),
        cmocka_unit_test(envdirect_seeds_weigh_solid_angle),
        cmocka_unit_test(methods_and_parameters_by_name),
        cmocka_unit_test(fhis_points_are_uniform_on_a_constant_map),
        cmocka_unit_test(label_extents_cover_whole_pixels),
        cmocka_unit_test(the_second_split_takes_the_larger_priority),
        cmocka_unit_test(special_maps_get_a_clear_answer),
        cmocka_unit_test(malformed_options_are_refused),
        cmocka_unit_test(interleave_pattern_covers_every_set),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
