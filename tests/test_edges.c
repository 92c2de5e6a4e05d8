/* The edges of the public interface: every function that can fail refuses missing and
 * absurd arguments with a status (never a crash, never success), leaves its output NULL,
 * and says why through the error sink when it has one; the BSDFs are zero, with zero
 * density, below the horizon. */
/* Oracles:
 * lumis_lighting_check — hand-worked: 32 incompatible or missing fields, one per condition, each
 *     refused with its own message naming the field (lighting_check_names_the_field)
 * lumis_session_check — hand-worked: the session's own options refused by name (each count,
 *     budget and share out of range, light-set options without lights, the automatic
 *     estimator with what it does not choose from), then the lighting's
 *     (lighting_check_names_the_field)
 * lumis_lighting_kind_name — hand-worked: "light-set" for its kind; round trip of every kind
 *     (lighting_check_names_the_field)
 * lumis_lighting_kind_from_name — hand-worked: "sun" refused; round trip of every kind
 *     (lighting_check_names_the_field)
 * lumis_emitter_irradiance — error paths only: missing and absurd arguments refused; 0 behind
 *     U (luminaires, emitters_refuse_what_they_cannot_be)
 * lumis_envmap_create — error paths only: missing and absurd arguments refused (core_and_maps)
 * lumis_envmap_stats_compute — error paths only: missing and absurd arguments refused
 *     (core_and_maps)
 * lumis_equirect_resize — error paths only: missing and absurd arguments refused (core_and_maps)
 * lumis_equirect_stats — error paths only: missing and absurd arguments refused (core_and_maps)
 * lumis_flip_colormap — error paths only: missing and absurd arguments refused (files_and_metrics)
 * lumis_flip_hdr — error paths only: missing and absurd arguments refused (files_and_metrics)
 * lumis_flip_ldr — error paths only: missing and absurd arguments refused (files_and_metrics)
 * lumis_image_check_size — error paths only: missing and absurd arguments refused (core_and_maps)
 * lumis_image_clone — error paths only: missing and absurd arguments refused (core_and_maps)
 * lumis_image_errors — error paths only: missing and absurd arguments refused (files_and_metrics)
 * lumis_image_read — error paths only: missing and absurd arguments refused (files_and_metrics)
 * lumis_image_read_memory — error paths only: missing and absurd arguments refused
 *     (files_and_metrics)
 * lumis_image_write — error paths only: missing and absurd arguments refused, each option by
 *     its message, nothing written (files_and_metrics)
 * lumis_joint_bilateral_upsample — error paths only: missing and absurd arguments refused
 *     (renderer)
 * lumis_lab_delta_e — error paths only: missing and absurd arguments refused (files_and_metrics)
 * lumis_light_set_irradiance — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_light_set_write_gltf — error paths only: missing and absurd arguments refused
 *     (files_and_metrics)
 * lumis_light_set_write_json — error paths only: missing and absurd arguments refused
 *     (files_and_metrics)
 * lumis_lights_decompose — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_lights_fhis — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_lights_median_cut — error paths only: missing and absurd arguments refused (renderer,
 *     samplers_and_light_sets)
 * lumis_lights_tmms — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_lights_variance_min — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_luminaire_acquire — error paths only: missing and absurd arguments refused, each
 *     emitter condition by its message (luminaires, emitters_refuse_what_they_cannot_be)
 * lumis_luminaire_create — error paths only: missing and absurd arguments refused (luminaires)
 * lumis_luminaire_global_draw — error paths only: missing and absurd arguments refused (luminaires)
 * lumis_luminaire_global_finish — error paths only: missing and absurd arguments refused
 *     (luminaires)
 * lumis_luminaire_invert — consistency: inverts lumis_luminaire_sample_image's draw, restricted
 *     and uniform; error paths: missing and absurd arguments, a point behind U, of S outside
 *     the box or p on S refused (luminaires, luminaire_images_refuse_what_they_cannot_sample)
 * lumis_luminaire_irradiance — error paths only: missing and absurd arguments refused (luminaires)
 * lumis_luminaire_manifest_parse — error paths only: missing and absurd arguments refused
 *     (files_and_metrics)
 * lumis_luminaire_manifest_read — error paths only: missing and absurd arguments refused
 *     (files_and_metrics)
 * lumis_luminaire_preset_create — error paths only: missing and absurd arguments refused
 *     (luminaires)
 * lumis_luminaire_read — error paths only: missing and absurd arguments refused (files_and_metrics)
 * lumis_luminaire_sample_image — consistency: its pdf lumis_luminaire_pdf's, every strategy, p
 *     in front and on S; error paths: missing and absurd arguments, the automatic strategy, p
 *     behind U or on S off the image refused (luminaires,
 *     luminaire_images_refuse_what_they_cannot_sample)
 * lumis_luminaire_pdf — consistency: the sample's pdf; 0 outside the box and for what
 *     sample_image refuses (luminaire_images_refuse_what_they_cannot_sample)
 * lumis_luminaire_sample_point — error paths only: missing and absurd arguments refused
 *     (luminaires)
 * lumis_luminaire_write — error paths only: missing and absurd arguments refused
 *     (files_and_metrics)
 * lumis_map_read — error paths only: missing and absurd arguments refused (files_and_metrics)
 * lumis_region_sampler_build_ms — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_region_sampler_bytes — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_region_sampler_create — error paths only: missing and absurd arguments refused (renderer,
 *     samplers_and_light_sets)
 * lumis_region_sampler_kind — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_region_sampler_lookup — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_region_sampler_pdf — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_region_sampler_power — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_render — error paths only: missing and absurd arguments refused (renderer)
 * lumis_render_gbuffer — error paths only: missing and absurd arguments refused (renderer)
 * lumis_render_job_create — error paths only: missing and absurd arguments refused (renderer)
 * lumis_render_job_image — error paths only: missing and absurd arguments refused (renderer)
 * lumis_render_job_run — error paths only: missing and absurd arguments refused (renderer)
 * lumis_render_session — error paths only: missing and absurd arguments refused (renderer)
 * lumis_rigid_check — error paths only: missing and absurd arguments refused (luminaires)
 * lumis_sampler_create — error paths only: missing and absurd arguments refused (renderer,
 *     samplers_and_light_sets)
 * lumis_sampler_invert — error paths only: missing and absurd arguments refused
 *     (samplers_and_light_sets)
 * lumis_scene_builtin — error paths only: missing and absurd arguments refused (renderer)
 * lumis_scene_builtin_with_luminaire — error paths only: a scene without luminaires takes none
 *     (renderer)
 * lumis_scene_create — error paths only: missing and absurd arguments refused (renderer)
 * lumis_scene_file_read — error paths only: missing and absurd arguments refused (renderer)
 * lumis_sky_create — error paths only: missing and absurd arguments refused (core_and_maps)
 * lumis_studio_create — error paths only: missing and absurd arguments refused (core_and_maps)
 * lumis_write_text — error paths only: missing and absurd arguments refused (files_and_metrics)
 * lumis_bsdf_eval — hand-worked: 0 when either direction is below the horizon, every material
 *     (bsdfs_below_the_horizon)
 * lumis_bsdf_pdf — hand-worked: density 0 below the horizon (bsdfs_below_the_horizon)
 * lumis_bsdf_sample_wi — hand-worked: pdf and weight 0 from below the horizon
 *     (bsdfs_below_the_horizon)
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "lumis/bsdf.h"
#include "lumis/io.h"
#include "lumis/lumis.h"
#include "lumis/render.h"
#include "testutil.h"

/* st must be a failure, and out (if given) still NULL. */
#define REFUSED(st, out)                                                                           \
    do {                                                                                           \
        const lumis_status st_ = (st);                                                             \
        if (st_ == LUMIS_OK) fail_msg("%s: accepted", #st);                                        \
        if ((out) != NULL)                                                                         \
            fail_msg("%s: refused (%s) but wrote an output", #st, lumis_status_name(st_));         \
    } while (0)

static lumis_image *small_image(int w, int h, float v)
{
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(w, h, &img), LUMIS_OK);
    for (int i = 0; i < w * h * 3; i++) img->pixels[i] = v;
    return img;
}

static void core_and_maps(void **state)
{
    (void)state;
    lumis_image *img = NULL;
    REFUSED(lumis_image_create(0, 4, &img), img);
    REFUSED(lumis_image_create(4, -1, &img), img);
    REFUSED(lumis_image_create(1 << 30, 1 << 30, &img), img);
    assert_int_not_equal(lumis_image_create(4, 4, NULL), LUMIS_OK);
    REFUSED(lumis_image_clone(NULL, &img), img);
    assert_int_equal(lumis_image_check_size(0, 1, 0), LUMIS_ERR_BAD_DIMENSIONS);
    assert_int_equal(lumis_image_check_size(1000, 1000, 999999), LUMIS_ERR_TOO_LARGE);

    lumis_envmap *env = NULL;
    REFUSED(lumis_envmap_create(NULL, &env), env);
    lumis_envmap_desc ed = {0};
    REFUSED(lumis_envmap_create(&ed, &env), env); /* no pixels */
    float px[2 * 1 * 3] = {1, 1, 1, 1, 1, 1};
    ed.pixels = px;
    ed.width = 2;
    ed.height = 1;
    ed.scale = NAN;
    tu_sink sink;
    tu_sink_init(&sink);
    ed.errors = sink.sink;
    REFUSED(lumis_envmap_create(&ed, &env), env);
    assert_non_null(strstr(sink.last, "scale"));
    ed.scale = 1.0f;
    ed.rotation_deg = INFINITY;
    REFUSED(lumis_envmap_create(&ed, &env), env);
    ed.rotation_deg = 0.0f;
    ed.width = -2;
    REFUSED(lumis_envmap_create(&ed, &env), env);
    REFUSED(lumis_envmap_from_image(NULL, &env), env);
    lumis_envmap_stats stats;
    assert_int_not_equal(lumis_envmap_stats_compute(NULL, &stats), LUMIS_OK);
    assert_int_not_equal(lumis_equirect_stats(NULL, 2, 1, 1.0f, &stats), LUMIS_OK);
    assert_int_not_equal(lumis_equirect_stats(px, 0, 1, 1.0f, &stats), LUMIS_OK);
    float dst[12];
    assert_int_not_equal(lumis_equirect_resize(NULL, 2, 1, dst, 2, 1), LUMIS_OK);
    assert_int_not_equal(lumis_equirect_resize(px, 2, 1, NULL, 2, 1), LUMIS_OK);
    assert_int_not_equal(lumis_equirect_resize(px, 2, 1, dst, 0, 1), LUMIS_OK);

    lumis_sky_desc sd = {0};
    sd.width = -3;
    REFUSED(lumis_sky_create(&sd, &img), img);
    sd.width = 8;
    sd.turbidity = NAN;
    REFUSED(lumis_sky_create(&sd, &img), img);
    lumis_studio_desc std = {0};
    std.width = -1;
    REFUSED(lumis_studio_create(&std, &img), img);
    assert_int_not_equal(lumis_sky_create(NULL, NULL), LUMIS_OK);
}

static void samplers_and_light_sets(void **state)
{
    (void)state;
    lumis_image *img = small_image(8, 4, 1.0f);
    lumis_envmap *env = NULL;
    assert_int_equal(lumis_envmap_from_image(img, &env), LUMIS_OK);
    lumis_sampler *s = NULL;
    REFUSED(lumis_sampler_create(NULL, NULL, &s), s);
    lumis_sampler_desc d = {0};
    d.method = LUMIS_METHOD_COUNT;
    REFUSED(lumis_sampler_create(env, &d, &s), s);
    d.method = LUMIS_METHOD_KDTREE;
    d.kdtree_blocks = -5;
    REFUSED(lumis_sampler_create(env, &d, &s), s);
    d.kdtree_blocks = 0;
    d.importance = LUMIS_IMPORTANCE_COUNT;
    REFUSED(lumis_sampler_create(env, &d, &s), s);
    double u[2];
    assert_int_not_equal(lumis_sampler_invert(NULL, (lumis_vec3){0, 1, 0}, u), LUMIS_OK);

    lumis_light_set *set = NULL;
    lumis_median_cut_desc mc = {0};
    REFUSED(lumis_lights_median_cut(NULL, &mc, &set), set);
    mc.count = -1;
    REFUSED(lumis_lights_median_cut(env, &mc, &set), set);
    mc.count = 4;
    mc.sets = 1000;
    REFUSED(lumis_lights_median_cut(env, &mc, &set), set);
    mc.sets = 1;
    mc.jitter = 2.0f;
    REFUSED(lumis_lights_median_cut(env, &mc, &set), set);
    lumis_variance_min_desc vm = {0};
    vm.count = 1000; /* more lights than the 32 pixels */
    REFUSED(lumis_lights_variance_min(env, &vm, &set), set);
    lumis_decomp_desc dd = {0};
    dd.percentile = 150.0f;
    REFUSED(lumis_lights_decompose(env, &dd, &set), set);
    dd.percentile = 0.0f;
    dd.variant = LUMIS_DECOMP_VARIANT_COUNT;
    REFUSED(lumis_lights_decompose(env, &dd, &set), set);
    lumis_fhis_desc fd = {0};
    fd.count = -2;
    REFUSED(lumis_lights_fhis(env, &fd, &set), set);
    lumis_tmms_desc td = {0};
    td.key = -1.0f;
    REFUSED(lumis_lights_tmms(env, &td, &set), set);
    const lumis_light *l = NULL;
    int n = 0;
    assert_int_not_equal(lumis_light_set_get(NULL, 0, &l, &n), LUMIS_OK);
    mc.count = 4;
    mc.jitter = 0.0f;
    assert_int_equal(lumis_lights_median_cut(env, &mc, &set), LUMIS_OK);
    assert_int_not_equal(lumis_light_set_get(set, 1, &l, &n), LUMIS_OK); /* one set only */
    assert_int_not_equal(lumis_light_set_get(set, -1, &l, &n), LUMIS_OK);
    dd.variant = 0;
    dd.min_share = 1.5f;
    lumis_light_set *wu = NULL;
    REFUSED(lumis_lights_decompose(env, &dd, &wu), wu);
    double se = 0.0, me = 0.0;
    assert_int_not_equal(lumis_light_set_irradiance(env, set, (lumis_vec3){0, 0, 0}, &se, &me),
                         LUMIS_OK);
    assert_int_not_equal(lumis_light_set_irradiance(NULL, set, (lumis_vec3){0, 1, 0}, &se, &me),
                         LUMIS_OK);
    assert_int_not_equal(lumis_light_set_irradiance(env, set, (lumis_vec3){0, 1, 0}, NULL, &me),
                         LUMIS_OK);
    assert_int_not_equal(lumis_light_set_irradiance(env, NULL, (lumis_vec3){0, 1, 0}, &se, &me),
                         LUMIS_OK);
    assert_int_not_equal(lumis_light_set_irradiance(env, set, (lumis_vec3){0, 1, 0}, &se, NULL),
                         LUMIS_OK);
    assert_int_not_equal(lumis_light_set_irradiance(env, set, (lumis_vec3){NAN, 1, 0}, &se, &me),
                         LUMIS_OK);
    assert_int_not_equal(
        lumis_light_set_irradiance(env, set, (lumis_vec3){0, INFINITY, 0}, &se, &me), LUMIS_OK);
    /* a map of another size than the set's */
    lumis_image *other_img = small_image(16, 8, 1.0f);
    lumis_envmap *other = NULL;
    assert_int_equal(lumis_envmap_from_image(other_img, &other), LUMIS_OK);
    assert_int_not_equal(lumis_light_set_irradiance(other, set, (lumis_vec3){0, 1, 0}, &se, &me),
                         LUMIS_OK);
    lumis_envmap_destroy(other);
    lumis_image_destroy(other_img);
    /* the accessors: nothing of no set, no place to put the lights */
    assert_int_equal(lumis_light_set_sets(NULL), 0);
    assert_null(lumis_light_set_get_info(NULL));
    int lw = -1, lh = -1;
    assert_null(lumis_light_set_labels(NULL, &lw, &lh));
    assert_true(lw == -1 && lh == -1);
    assert_non_null(lumis_light_set_labels(set, NULL, NULL));
    assert_int_equal(lumis_light_set_get(set, 0, NULL, &n), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_light_set_get(set, 0, &l, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_light_set_get(set, 0, &l, &n), LUMIS_OK);
    assert_int_equal(n, 4);
    lumis_region_sampler *rs = NULL;
    REFUSED(lumis_region_sampler_create(env, NULL, NULL, &rs), rs);
    assert_int_equal(lumis_region_sampler_create(env, set, NULL, &rs), LUMIS_OK);
    double pw[3];
    lumis_region_sampler_power(rs, 99, pw); /* out of range: nothing */
    assert_true(pw[0] == 0.0 && pw[1] == 0.0 && pw[2] == 0.0);
    assert_int_equal(lumis_region_sampler_kind(rs, -1), LUMIS_LIGHT_REGION);
    assert_true(lumis_region_sampler_pdf(rs, 99, (lumis_vec3){0, 1, 0}) == 0.0f);
    assert_true(lumis_region_sampler_lookup(NULL, (lumis_vec3){0, 1, 0}, NULL, NULL) == 0.0f);
    assert_true(lumis_region_sampler_bytes(NULL) == 0 && lumis_region_sampler_build_ms(NULL) == 0);
    lumis_region_sampler_destroy(rs);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
    lumis_image_destroy(img);
}

/* lumis_image_write's refusals, each by its message, before anything is written; and
 * lumis_image_read_memory's of no data or no output. */
static void image_write_refusals(const lumis_image *a)
{
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_write_options o = {0};
    o.errors = sink.sink;
    lumis_image hollow = *a;
    hollow.pixels = NULL;
    assert_int_equal(lumis_image_write(tu_path("w.exr"), &hollow, &o), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "write: no path or image given"));
    lumis_image flat = *a;
    flat.width = 0;
    assert_int_equal(lumis_image_write(tu_path("w.exr"), &flat, &o), LUMIS_ERR_BAD_DIMENSIONS);
    assert_non_null(strstr(sink.last, "image has bad dimensions"));
    o.format = LUMIS_FORMAT_COUNT;
    assert_int_equal(lumis_image_write(tu_path("w.exr"), a, &o), LUMIS_ERR_UNKNOWN_FORMAT);
    assert_non_null(strstr(sink.last, "unknown output format"));
    o.format = LUMIS_FORMAT_AUTO;
    for (int k = 0; k < 4; k++) {
        lumis_write_options b = o;
        if (k == 0) b.exposure_ev = NAN;
        if (k == 1) b.tonemap = LUMIS_TONEMAP_COUNT;
        if (k == 2) b.exr_compression = LUMIS_EXR_COMPRESSION_COUNT;
        if (k == 3) b.exr_tile_size = -1;
        sink.last[0] = '\0';
        assert_int_equal(lumis_image_write(tu_path("w.exr"), a, &b), LUMIS_ERR_INVALID_ARGUMENT);
        assert_non_null(strstr(sink.last, "w.exr: bad exposure or tone map"));
    }
    assert_int_equal(tu_count_entries(tu_tmpdir(), "w.exr"), 0); /* nothing written */
    lumis_read_options ro = {0};
    ro.errors = sink.sink;
    lumis_image *img = (lumis_image *)&sink;
    assert_int_equal(lumis_image_read_memory(NULL, 10, LUMIS_FORMAT_EXR, NULL, &ro, &img, NULL),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);
    assert_non_null(strstr(sink.last, "no data given"));
    assert_int_equal(lumis_image_read_memory("PF\n", 3, LUMIS_FORMAT_AUTO, NULL, NULL, NULL, NULL),
                     LUMIS_ERR_INVALID_ARGUMENT);
}

static void files_and_metrics(void **state)
{
    (void)state;
    lumis_image *img = NULL, *a = small_image(4, 3, 0.5f), *b = small_image(5, 3, 0.5f);
    REFUSED(lumis_image_read(NULL, NULL, &img, NULL), img);
    REFUSED(lumis_map_read(NULL, NULL, &img, NULL), img);
    REFUSED(lumis_map_read("sky:0x0", NULL, &img, NULL), img);
    REFUSED(lumis_map_read("sky:axb", NULL, &img, NULL), img);
    REFUSED(lumis_image_read_memory(NULL, 10, LUMIS_FORMAT_EXR, "x", NULL, &img, NULL), img);
    REFUSED(lumis_image_read_memory("", 0, LUMIS_FORMAT_PFM, "x", NULL, &img, NULL), img);
    assert_int_not_equal(lumis_image_write(NULL, a, NULL), LUMIS_OK);
    assert_int_not_equal(lumis_image_write(tu_path("x.exr"), NULL, NULL), LUMIS_OK);
    assert_int_not_equal(lumis_image_write(tu_path("x.unknown"), a, NULL), LUMIS_OK);
    image_write_refusals(a);
    assert_int_not_equal(lumis_write_text(NULL, "x", 1, NULL), LUMIS_OK);
    assert_int_not_equal(lumis_write_text("", "x", 1, NULL), LUMIS_OK);
    assert_int_not_equal(lumis_write_text(tu_path("t.txt"), NULL, 3, NULL), LUMIS_OK);
    assert_int_equal(lumis_write_text(tu_path("t.txt"), NULL, 0, NULL), LUMIS_OK); /* empty */
    assert_int_not_equal(lumis_light_set_write_json(tu_path("l.json"), NULL, NULL), LUMIS_OK);
    assert_int_not_equal(lumis_light_set_write_gltf(NULL, NULL, NULL), LUMIS_OK);
    lumis_luminaire *lum = NULL;
    REFUSED(lumis_luminaire_read(NULL, NULL, &lum), lum);
    assert_int_not_equal(lumis_luminaire_write(tu_path("m.json"), NULL, NULL), LUMIS_OK);
    lumis_luminaire_manifest *man = NULL;
    REFUSED(lumis_luminaire_manifest_parse(NULL, 4, "m", "", NULL, &man), man);
    REFUSED(lumis_luminaire_manifest_read(NULL, NULL, &man), man);

    lumis_image_error_stats es;
    assert_int_not_equal(lumis_image_errors(a, b, NULL, &es), LUMIS_OK); /* sizes differ */
    assert_int_not_equal(lumis_image_errors(NULL, a, NULL, &es), LUMIS_OK);
    double mean = 0;
    assert_int_not_equal(lumis_lab_delta_e(a, b, NULL, NULL, &mean), LUMIS_OK);
    assert_int_not_equal(lumis_flip_ldr(a, b, NULL, NULL, &mean), LUMIS_OK);
    lumis_flip_hdr_result r;
    assert_int_not_equal(lumis_flip_hdr(a, NULL, NULL, NULL, NULL, &r), LUMIS_OK);
    lumis_flip_options fo = {0};
    fo.pixels_per_degree = -1.0f;
    assert_int_not_equal(lumis_flip_ldr(a, a, &fo, NULL, &mean), LUMIS_OK);
    REFUSED(lumis_flip_colormap(NULL, 4, 3, &img), img);
    float map[12] = {0};
    REFUSED(lumis_flip_colormap(map, 0, 3, &img), img);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
}

static void luminaires(void **state)
{
    (void)state;
    lumis_luminaire *lum = NULL;
    REFUSED(lumis_luminaire_create(NULL, &lum), lum);
    lumis_luminaire_desc d = {0};
    REFUSED(lumis_luminaire_create(&d, &lum), lum); /* an empty grid */
    assert_int_equal(lumis_luminaire_check(NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_not_equal(lumis_luminaire_check(&d), LUMIS_OK);
    lumis_rigid bad = {{0}, {0, 0, 0}};
    bad.r[0] = 2.0; /* not a rotation */
    assert_int_not_equal(lumis_rigid_check(&bad), LUMIS_OK);
    assert_int_not_equal(lumis_rigid_check(NULL), LUMIS_OK);
    lumis_rigid id = lumis_rigid_identity();
    assert_int_equal(lumis_rigid_check(&id), LUMIS_OK);
    REFUSED(
        lumis_luminaire_preset_create((lumis_luminaire_preset)7, LUMIS_BASIS_DEFAULT, NULL, &lum),
        lum);
    lumis_luminaire_desc layout;
    lumis_emitter_desc em;
    lumis_emitter_disk disks[16];
    assert_int_not_equal(lumis_luminaire_preset_get((lumis_luminaire_preset)7, &layout, &em, disks),
                         LUMIS_OK);
    REFUSED(lumis_luminaire_acquire(NULL, NULL, NULL, &lum), lum);
    lumis_rgb e;
    assert_int_not_equal(
        lumis_emitter_irradiance(NULL, (lumis_vec3){0, 0, 1}, (lumis_vec3){0, 0, -1}, 4, 8, &e),
        LUMIS_OK);
    lumis_luminaire_sample smp[4];
    int n = 0;
    double u[8] = {0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5};
    assert_int_not_equal(lumis_luminaire_sample_point(NULL, NULL, u, 4, smp, &n), LUMIS_OK);
    assert_int_not_equal(lumis_luminaire_global_draw(NULL, NULL, u, 4, smp, &n), LUMIS_OK);
    assert_int_not_equal(
        lumis_luminaire_global_finish(NULL, (lumis_vec3){0, 0, 1}, smp, 0, smp, &n), LUMIS_OK);
    assert_int_not_equal(lumis_luminaire_sample_image(NULL, NULL, 0, 0.5, 0.5, smp), LUMIS_OK);
    double u1, u2;
    assert_int_not_equal(lumis_luminaire_invert(NULL, NULL, 0, 0, 0, &u1, &u2), LUMIS_OK);
    assert_int_not_equal(
        lumis_luminaire_irradiance(NULL, (lumis_vec3){0, 0, 1}, (lumis_vec3){0, 0, -1}, 2, &e),
        LUMIS_OK);
}

/* An emitter the acquisition and the true irradiance cannot take: refused with what it
 * must be (no disks, a disk not behind U or of no size, a plate not between the disks and
 * U, an unknown pattern, a pattern's period or contrast), and their own numbers out of
 * range. */
static void emitters_refuse_what_they_cannot_be(void **state)
{
    (void)state;
    lumis_luminaire_desc layout;
    lumis_emitter_desc em;
    lumis_emitter_disk disks[16];
    assert_int_equal(lumis_luminaire_preset_get(LUMIS_PRESET_SMALL, &layout, &em, disks), LUMIS_OK);
    assert_true(em.pattern != LUMIS_PATTERN_NONE && em.disk_count >= 1);
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_acquire_desc acq = {0};
    acq.errors = sink.sink;
    enum { CASES = 15 };
    static const char *const msgs[CASES] = {
        "needs at least one disk",
        "needs at least one disk",
        "disk 0 must lie behind U",
        "disk 0 must lie behind U",
        "disk 0 must lie behind U",
        "disk 0 must lie behind U",
        "disk 0 must lie behind U",
        "disk 0 must lie behind U",
        "must lie between disk 0",
        "unknown pattern 3",
        "a pattern needs plate_z < 0, periods > 0 and contrast in [0, 1]",
        "a pattern needs plate_z",
        "a pattern needs plate_z",
        "a pattern needs plate_z",
        "a pattern needs plate_z"};
    for (int k = 0; k < CASES; k++) {
        lumis_emitter_desc e = em;
        lumis_emitter_disk d[16];
        memcpy(d, disks, sizeof d);
        e.disks = d;
        switch (k) {
        case 0:
            e.disk_count = 0;
            break;
        case 1:
            e.disks = NULL;
            break;
        case 2:
            d[0].center[2] = 1.0;
            break;
        case 3:
            d[0].radius = 0.0;
            break;
        case 4:
            d[0].radius = INFINITY;
            break;
        case 5:
            d[0].exponent = -1.0;
            break;
        case 6:
            d[0].center[0] = NAN;
            break;
        case 7:
            d[0].center[1] = INFINITY;
            break;
        case 8:
            e.plate_z = d[0].center[2] - 1.0;
            break;
        case 9:
            e.pattern = LUMIS_PATTERN_COUNT;
            break;
        case 10:
            e.plate_z = 0.5, d[0].center[2] = -1.0;
            break;
        case 11:
            e.period[0] = 0.0;
            break;
        case 12:
            e.pattern = LUMIS_PATTERN_CHECKER, e.period[1] = 0.0;
            break;
        case 13:
            e.contrast = 1.5;
            break;
        default:
            e.contrast = -0.1;
            break;
        }
        if (k == 10) /* every disk behind the plate */
            for (int q = 1; q < e.disk_count; q++) d[q].center[2] = -1.0;
        lumis_luminaire *lum = (lumis_luminaire *)&sink;
        const lumis_status st = lumis_luminaire_acquire(&layout, &e, &acq, &lum);
        if (st != LUMIS_ERR_INVALID_ARGUMENT || lum || !strstr(sink.last, msgs[k]))
            fail_msg("emitter case %d: status %d, \"%s\", want \"%s\"", k, (int)st, sink.last,
                     msgs[k]);
        lumis_rgb out;
        assert_int_equal(
            lumis_emitter_irradiance(&e, (lumis_vec3){0, 0, 1}, (lumis_vec3){0, 0, -1}, 4, 8, &out),
            LUMIS_ERR_INVALID_ARGUMENT);
    }
    lumis_luminaire *lum = NULL;
    REFUSED(lumis_luminaire_acquire(&layout, NULL, &acq, &lum), lum);
    REFUSED(lumis_luminaire_acquire(NULL, &em, &acq, &lum), lum);
    assert_int_equal(lumis_luminaire_acquire(&layout, &em, &acq, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    /* more quadrature nodes than a sample may take */
    acq.samples_s = 65;
    REFUSED(lumis_luminaire_acquire(&layout, &em, &acq, &lum), lum);
    acq.samples_s = 0;
    acq.samples_radial = 65;
    REFUSED(lumis_luminaire_acquire(&layout, &em, &acq, &lum), lum);
    acq.samples_radial = 64;
    acq.samples_angular = 1000;
    REFUSED(lumis_luminaire_acquire(&layout, &em, &acq, &lum), lum);
    assert_non_null(strstr(sink.last, "at most 64 sensor samples per axis and 4096 nodes"));
    /* the true irradiance: no output, too many nodes, no normal; nothing behind U */
    const lumis_vec3 p = {0, 0, 1}, n = {0, 0, -1}, zero = {0, 0, 0};
    lumis_rgb e = {1, 1, 1};
    assert_int_equal(lumis_emitter_irradiance(&em, p, n, 4, 8, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_emitter_irradiance(&em, p, n, 65, 8, &e), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_emitter_irradiance(&em, p, n, 64, 2000, &e), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_emitter_irradiance(&em, p, zero, 4, 8, &e), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_emitter_irradiance(&em, (lumis_vec3){0, 0, -1}, n, 4, 8, &e), LUMIS_OK);
    assert_true(e.r == 0.0f && e.g == 0.0f && e.b == 0.0f);
    assert_int_equal(lumis_emitter_irradiance(&em, p, n, 0, 0, &e), LUMIS_OK);
    assert_true(e.r > 0.0f && e.g > 0.0f && e.b > 0.0f);
}

/* One image's sampler, density and inverse (restricted.c) on a real luminaire: refused or 0
 * for a missing argument, an image out of range, the automatic strategy (renders only), a
 * point behind U, and a point of S or of U outside what the image can draw; accepted, each
 * the other's inverse, for what it can. */
static void luminaire_images_refuse_what_they_cannot_sample(void **state)
{
    (void)state;
    lumis_luminaire *lum = NULL;
    assert_int_equal(tu_tiny_luminaire(&lum), LUMIS_OK);
    lumis_luminaire_sample smp;
    double u1, u2;
    for (int strat = LUMIS_LUM_RESTRICTED; strat <= LUMIS_LUM_GLOBAL; strat++) {
        lumis_luminaire_query q = {0};
        q.p = (lumis_vec3){0.1f, -0.2f, 3.0f};
        q.strategy = (lumis_luminaire_strategy)strat;
        assert_int_equal(lumis_luminaire_sample_image(lum, &q, 1, 0.3, 0.6, &smp), LUMIS_OK);
        const double pdf = lumis_luminaire_pdf(lum, &q, 1, smp.s[0], smp.s[1]);
        assert_true(pdf > 0.0 && fabs(pdf - smp.pdf) <= 1e-5 * pdf);
        if (strat != LUMIS_LUM_GLOBAL) { /* the inverse of the restricted and uniform draws */
            assert_int_equal(lumis_luminaire_invert(lum, &q, 1, smp.s[0], smp.s[1], &u1, &u2),
                             LUMIS_OK);
            assert_true(fabs(u1 - 0.3) < 1e-6 && fabs(u2 - 0.6) < 1e-6);
        }
        /* a point of S outside the image's box */
        assert_true(lumis_luminaire_pdf(lum, &q, 1, 50.0, 0.0) == 0.0);
        assert_true(lumis_luminaire_pdf(lum, &q, 1, 0.0, -50.0) == 0.0);
        assert_int_equal(lumis_luminaire_invert(lum, &q, 1, 50.0, 0.0, &u1, &u2),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_luminaire_invert(lum, &q, 1, 0.0, -50.0, &u1, &u2),
                         LUMIS_ERR_INVALID_ARGUMENT);
        /* no luminaire, query or output; images -1 and M */
        assert_int_equal(lumis_luminaire_sample_image(lum, NULL, 1, 0.5, 0.5, &smp),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_luminaire_sample_image(lum, &q, 1, 0.5, 0.5, NULL),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_true(lumis_luminaire_pdf(NULL, &q, 1, 0.0, 0.0) == 0.0);
        assert_true(lumis_luminaire_pdf(lum, NULL, 1, 0.0, 0.0) == 0.0);
        assert_int_equal(lumis_luminaire_invert(lum, NULL, 1, 0.0, 0.0, &u1, &u2),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_luminaire_invert(lum, &q, 1, 0.0, 0.0, NULL, &u2),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_int_equal(lumis_luminaire_invert(lum, &q, 1, 0.0, 0.0, &u1, NULL),
                         LUMIS_ERR_INVALID_ARGUMENT);
        for (int m = -1; m <= 4; m += 5) {
            assert_int_equal(lumis_luminaire_sample_image(lum, &q, m, 0.5, 0.5, &smp),
                             LUMIS_ERR_INVALID_ARGUMENT);
            assert_true(lumis_luminaire_pdf(lum, &q, m, 0.0, 0.0) == 0.0);
            assert_int_equal(lumis_luminaire_invert(lum, &q, m, 0.0, 0.0, &u1, &u2),
                             LUMIS_ERR_INVALID_ARGUMENT);
        }
        /* behind U (z <= 0): the light travels towards +z */
        q.p.z = -0.5f;
        assert_int_equal(lumis_luminaire_sample_image(lum, &q, 1, 0.5, 0.5, &smp),
                         LUMIS_ERR_INVALID_ARGUMENT);
        assert_true(lumis_luminaire_pdf(lum, &q, 1, 0.0, 0.0) == 0.0);
        if (strat != LUMIS_LUM_GLOBAL)
            assert_int_equal(lumis_luminaire_invert(lum, &q, 1, 0.0, 0.0, &u1, &u2),
                             LUMIS_ERR_INVALID_ARGUMENT);
        /* on S: uniform over Phi_m's support on U (the global strategy ignores p); off the
         * image, refused */
        q.p = (lumis_vec3){0.25f, 0.25f, 1.0f};
        assert_int_equal(lumis_luminaire_sample_image(lum, &q, 1, 0.5, 0.5, &smp), LUMIS_OK);
        const double *at = strat == LUMIS_LUM_GLOBAL ? smp.s : smp.u;
        const double on = lumis_luminaire_pdf(lum, &q, 1, at[0], at[1]);
        if (!(on > 0.0 && fabs(on - smp.pdf) <= 1e-5 * on))
            fail_msg("strategy %d on S: pdf %g, the sample's %g", strat, on, (double)smp.pdf);
        if (strat != LUMIS_LUM_GLOBAL) {
            assert_true(lumis_luminaire_pdf(lum, &q, 1, 50.0, smp.u[1]) == 0.0);
            assert_true(lumis_luminaire_pdf(lum, &q, 1, smp.u[0], -50.0) == 0.0);
            assert_int_equal(lumis_luminaire_invert(lum, &q, 1, smp.u[0], smp.u[1], &u1, &u2),
                             LUMIS_ERR_INVALID_ARGUMENT);
            q.p.x = 5.0f; /* on S's plane, off the image */
            assert_int_equal(lumis_luminaire_sample_image(lum, &q, 1, 0.5, 0.5, &smp),
                             LUMIS_ERR_INVALID_ARGUMENT);
            assert_true(lumis_luminaire_pdf(lum, &q, 1, 0.0, 0.0) == 0.0);
        }
    }
    /* the automatic strategy is the renderer's choice, not a sampler */
    lumis_luminaire_query q = {0};
    q.p = (lumis_vec3){0.0f, 0.0f, 3.0f};
    q.strategy = LUMIS_LUM_AUTO;
    assert_int_equal(lumis_luminaire_sample_image(lum, &q, 1, 0.5, 0.5, &smp),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_true(lumis_luminaire_pdf(lum, &q, 1, 0.0, 0.0) == 0.0);
    assert_int_equal(lumis_luminaire_invert(lum, &q, 1, 0.0, 0.0, &u1, &u2),
                     LUMIS_ERR_INVALID_ARGUMENT);
    lumis_luminaire_destroy(lum);
}

static void renderer(void **state)
{
    (void)state;
    lumis_scene *scene = NULL;
    REFUSED(lumis_scene_create(NULL, 3, NULL, &scene), scene);
    lumis_object sphere = {0};
    sphere.type = LUMIS_OBJECT_SPHERE;
    sphere.radius = -1.0f;
    REFUSED(lumis_scene_create(&sphere, 1, NULL, &scene), scene);
    sphere.radius = 1.0f;
    assert_int_equal(lumis_scene_create(&sphere, 1, NULL, &scene), LUMIS_OK);
    lumis_image *img = NULL, *sky = small_image(8, 4, 1.0f);
    lumis_envmap *env = NULL;
    lumis_sampler *smp = NULL;
    assert_int_equal(lumis_envmap_from_image(sky, &env), LUMIS_OK);
    assert_int_equal(lumis_sampler_create(env, NULL, &smp), LUMIS_OK);
    REFUSED(lumis_render(scene, NULL, &img, NULL), img);
    lumis_camera cam = {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40.0f, 8, 6};
    lumis_render_desc d = {0};
    d.camera = &cam;
    d.spp = 1;
    REFUSED(lumis_render(scene, &d, &img, NULL), img); /* MIS with no map and no sampler */
    d.lighting.env = env;
    tu_sink sink;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    REFUSED(lumis_render(scene, &d, &img, NULL), img); /* a map but no sampler for MIS */
    assert_non_null(strstr(sink.last, "lighting.sampler: missing"));
    d.errors = (lumis_error_sink){0};
    d.lighting.sampler = smp;
    assert_int_equal(lumis_render(scene, &d, &img, NULL), LUMIS_OK);
    lumis_image_destroy(img);
    img = NULL;
    REFUSED(lumis_render(NULL, &d, &img, NULL), img);
    cam.width = -8;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    cam.width = 8;
    cam.fov_deg = 200.0f;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    cam.fov_deg = 40.0f;
    cam.eye = cam.look_at; /* no direction to look in */
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    cam.eye = (lumis_vec3){0, 0, 4};
    cam.up = (lumis_vec3){0, 0, 1}; /* parallel to the view */
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    cam.up = (lumis_vec3){0, 1, 0};
    { /* light sets: an unknown mode, and region samplers of another set */
        lumis_median_cut_desc mc = {0};
        mc.count = 4;
        lumis_light_set *set = NULL, *other = NULL;
        assert_int_equal(lumis_lights_median_cut(env, &mc, &set), LUMIS_OK);
        mc.count = 2;
        assert_int_equal(lumis_lights_median_cut(env, &mc, &other), LUMIS_OK);
        lumis_region_sampler *rs = NULL;
        assert_int_equal(lumis_region_sampler_create(env, other, NULL, &rs), LUMIS_OK);
        lumis_render_desc ld = d;
        ld.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
        ld.lighting.sampler = NULL;
        ld.lighting.light_set.set = set;
        ld.lighting.light_set.mode = LUMIS_LIGHTS_MODE_COUNT;
        REFUSED(lumis_render(scene, &ld, &img, NULL), img);
        ld.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
        ld.lighting.light_set.regions = rs; /* 2 regions for a set of 4 lights */
        REFUSED(lumis_render(scene, &ld, &img, NULL), img);
        ld.lighting.light_set.regions = NULL;
        assert_int_equal(lumis_render(scene, &ld, &img, NULL), LUMIS_OK);
        lumis_image_destroy(img);
        img = NULL;
        lumis_session_desc sd = {0};
        sd.render = ld;
        sd.render.lighting.light_set.set = NULL;
        sd.lights = "median-cut";
        sd.render.lighting.light_set.mode = (lumis_lights_mode)9;
        REFUSED(lumis_render_session(scene, &sd, &img, NULL), img);
        lumis_region_sampler_destroy(rs);
        lumis_light_set_destroy(set);
        lumis_light_set_destroy(other);
    }
    cam.up = (lumis_vec3){0, 1, 0};
    cam.width = 70000;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    cam.width = 8;
    cam.height = 1 << 17;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    cam.height = 6;
    cam.fov_deg = 0.0f; /* zero: the default 40 degrees */
    assert_int_equal(lumis_render(scene, &d, &img, NULL), LUMIS_OK);
    lumis_image_destroy(img);
    img = NULL;
    cam.fov_deg = 40.0f;
    d.spp = -4;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    d.spp = 1;
    d.max_bounces = -1;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    d.max_bounces = 0;
    d.lighting.estimator = (lumis_estimator)9;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    d.lighting.estimator = LUMIS_ESTIMATOR_MIS;
    /* a share's first sample: not negative, and the samples numbered below 2^30 */
    d.first_sample = -1;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    d.first_sample = 1 << 30;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    d.first_sample = (1 << 30) - 1; /* the job is made, but its 2 samples do not fit */
    d.spp = 2;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    d.spp = 1; /* the last sample that fits */
    assert_int_equal(lumis_render(scene, &d, &img, NULL), LUMIS_OK);
    lumis_image_destroy(img);
    img = NULL;
    d.first_sample = 0;
    d.sequence = LUMIS_SEQUENCE_COUNT;
    REFUSED(lumis_render(scene, &d, &img, NULL), img);
    d.sequence = LUMIS_SEQUENCE_DEFAULT;
    { /* a session's share is samples, never a time budget */
        lumis_session_desc sd = {0};
        sd.render = d;
        sd.share_spp = -1;
        REFUSED(lumis_render_session(scene, &sd, &img, NULL), img);
        sd.share_spp = 2;
        sd.time_budget = 1.0;
        REFUSED(lumis_render_session(scene, &sd, &img, NULL), img);
    }
    lumis_render_job *job = NULL;
    REFUSED(lumis_render_job_create(scene, NULL, &job), job);
    assert_int_not_equal(lumis_render_job_run(NULL, 1), LUMIS_OK);
    REFUSED(lumis_render_job_image(NULL, &img), img);
    lumis_gbuffer *g = NULL;
    cam.height = -1;
    REFUSED(lumis_render_gbuffer(scene, &cam, NULL, &g), g);
    cam.height = 6;
    REFUSED(lumis_render_gbuffer(NULL, &cam, NULL, &g), g);
    lumis_sampler_destroy(smp);
    lumis_envmap_destroy(env);
    lumis_image_destroy(sky);

    /* upsampling: missing buffers, sizes that disagree, absurd sigmas */
    assert_int_equal(lumis_render_gbuffer(scene, &cam, NULL, &g), LUMIS_OK);
    lumis_image *low = small_image(8, 6, 1.0f), *wrong = small_image(4, 6, 1.0f);
    REFUSED(lumis_joint_bilateral_upsample(NULL, g, g, NULL, &img), img);
    REFUSED(lumis_joint_bilateral_upsample(low, NULL, g, NULL, &img), img);
    REFUSED(lumis_joint_bilateral_upsample(low, g, NULL, NULL, &img), img);
    REFUSED(lumis_joint_bilateral_upsample(wrong, g, g, NULL, &img), img);
    lumis_upsample_desc ud = {0};
    ud.sigma_depth = INFINITY;
    REFUSED(lumis_joint_bilateral_upsample(low, g, g, &ud, &img), img);
    ud.sigma_depth = 0.0f;
    ud.radius = 99;
    REFUSED(lumis_joint_bilateral_upsample(low, g, g, &ud, &img), img);
    ud.radius = 0;
    assert_int_equal(lumis_joint_bilateral_upsample(low, g, g, &ud, &img), LUMIS_OK);
    lumis_image_destroy(img);
    lumis_image_destroy(low);
    lumis_image_destroy(wrong);
    lumis_gbuffer_destroy(g);
    lumis_scene_destroy(scene);

    lumis_scene_file *f = NULL;
    REFUSED(lumis_scene_builtin("no-such-scene", NULL, &f), f);
    REFUSED(lumis_scene_builtin(NULL, NULL, &f), f);
    REFUSED(
        lumis_scene_builtin_with_luminaire("spheres", (const lumis_luminaire *)&sphere, NULL, &f),
        f); /* a scene without luminaires takes none */
    REFUSED(lumis_scene_file_read(NULL, NULL, &f), f);
    REFUSED(lumis_scene_file_read(tu_path("no-such-file.json"), NULL, &f), f);
}

/* Every BSDF is 0, with density 0, when either direction is below the horizon, and at
 * grazing or mirrored configurations it stays finite. */
/* How a render is lit is one value: lumis_lighting_check alone refuses what a kind lacks or
 * does not take, one message per condition naming the field (the check reads pointers for
 * NULL only, so stand-ins do here). */
/* One field of a session given wrong, and the words its refusal must hold. */
typedef struct session_case {
    int field;
    const char *msg;
} session_case;

/* A map's session (MIS, no lights) with case k's field set; kind light-set for the cases
 * of lights. */
static void session_with(lumis_session_desc *s, int field)
{
    static const lumis_light_params params = {0};
    switch (field) {
    case 0:
        s->time_budget = NAN;
        break;
    case 1:
        s->time_budget = -1.0;
        break;
    case 2:
        s->spent = INFINITY;
        break;
    case 3:
        s->lights_k = -1;
        break;
    case 4:
        s->interleave = -1;
        break;
    case 5:
        s->upsample = -1;
        break;
    case 6:
        s->timed_spp = -1;
        break;
    case 7:
        s->auto_pilot_spp = -1;
        break;
    case 8:
        s->auto_pilot_spp = 5000;
        break;
    case 9:
        s->share_spp = -1;
        break;
    case 10:
        s->share_spp = 4, s->time_budget = 1.0;
        break;
    case 11:
        s->lights = "bogus";
        break;
    case 12:
        s->lights_k = 8;
        break;
    case 13:
        s->lights_params = &params;
        break;
    case 14:
        s->upsample = 2;
        break;
    case 15:
        s->auto_pilot_spp = 16;
        break;
    case 16:
        s->auto_estimator = 1, s->render.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
        break;
    case 17:
        s->auto_estimator = 1, s->render.lighting.env = NULL;
        break;
    case 18:
        s->auto_estimator = 1, s->render.lighting.sampler = NULL;
        break;
    case 19:
        s->auto_estimator = 1, s->render.lighting.estimator = LUMIS_ESTIMATOR_LIGHT;
        break;
    case 20:
        s->auto_estimator = 1, s->render.camera = NULL;
        break;
    case 21:
        s->auto_estimator = 1, s->share_spp = 4;
        break;
    case 22:
        s->auto_estimator = LUMIS_AUTO_PILOTS + 1; /* neither predict nor pilots */
        break;
    case 23:
        s->auto_estimator = -1;
        break;
    case 24:
        s->auto_estimator = LUMIS_AUTO_PREDICT, s->auto_pilot_spp = 16; /* no pilots to size */
        break;
    default:
        break;
    }
}

/* The session's own fields, each refused with its message (lumis_session_check; it reads
 * no map, sampler or regions: the caller's stand-ins do). */
static void session_refusals(const lumis_camera *cam, const lumis_envmap *env,
                             const lumis_sampler *smp, const lumis_region_sampler *rs)
{
    static const session_case cases[] = {
        {0, "needs a finite budget >= 0, non-negative counts"},
        {1, "needs a finite budget >= 0"},
        {2, "needs a finite budget >= 0"},
        {3, "non-negative counts"},
        {4, "non-negative counts"},
        {5, "non-negative counts"},
        {6, "non-negative counts"},
        {7, "non-negative counts"},
        {8, "non-negative counts"},
        {9, "a share of a render is a number of samples (share_spp >= 0)"},
        {10, "not a time budget"},
        {11, "lights 'bogus': unknown light-set method"},
        {12, "lights_k: does not apply without lights"},
        {13, "lights_params: does not apply without lights"},
        {14, "upsample: does not apply without lights"},
        {15, "auto_pilot_spp: applies with auto_estimator LUMIS_AUTO_PILOTS"},
        {16, "render.lighting.kind is not that"},
        {17, "render.lighting.env is not that"},
        {18, "render.lighting.sampler is not that"},
        {19, "render.lighting.estimator is not that"},
        {20, "render.camera is not that"},
        {21, "share_spp is not that"},
        {22, "auto_estimator 0, LUMIS_AUTO_PREDICT or LUMIS_AUTO_PILOTS"},
        {23, "auto_estimator 0, LUMIS_AUTO_PREDICT or LUMIS_AUTO_PILOTS"},
        {24, "auto_pilot_spp: applies with auto_estimator LUMIS_AUTO_PILOTS"},
    };
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_session_desc base = {0};
    base.render.camera = cam;
    base.render.errors = sink.sink;
    base.render.lighting.env = env;
    base.render.lighting.sampler = smp;
    assert_int_equal(lumis_session_check(&base), LUMIS_OK);
    assert_int_equal(lumis_session_check(NULL), LUMIS_ERR_INVALID_ARGUMENT);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        lumis_session_desc s = base;
        session_with(&s, cases[k].field);
        sink.last[0] = '\0';
        const lumis_status st = lumis_session_check(&s);
        if (st != LUMIS_ERR_INVALID_ARGUMENT || !strstr(sink.last, cases[k].msg))
            fail_msg("session case %d: status %d, \"%s\", want \"%s\"", cases[k].field, (int)st,
                     sink.last, cases[k].msg);
    }
    /* a light set's session: the automatic estimator and the caller's regions are not its,
     * and it needs a camera */
    lumis_session_desc s = base;
    s.lights = "median-cut";
    s.render.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    s.render.lighting.sampler = NULL;
    assert_int_equal(lumis_session_check(&s), LUMIS_OK);
    s.auto_estimator = 1;
    assert_int_equal(lumis_session_check(&s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "auto_estimator: chooses how the map lights the scene"));
    assert_non_null(strstr(sink.last, ": lights is not that"));
    s.auto_estimator = 0;
    s.render.camera = NULL;
    assert_int_equal(lumis_session_check(&s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "render.camera: missing: a light set's session needs it"));
    s.render.camera = cam;
    s.render.lighting.light_set.regions = rs;
    assert_int_equal(lumis_session_check(&s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "render.lighting.light_set.regions: given"));
}

static void lighting_check_names_the_field(void **state)
{
    (void)state;
    static char stand_in[4];
    const lumis_envmap *env = (const lumis_envmap *)stand_in;
    const lumis_sampler *smp = (const lumis_sampler *)stand_in;
    const lumis_light_set *set = (const lumis_light_set *)stand_in;
    const lumis_region_sampler *rs = (const lumis_region_sampler *)stand_in;
    const lumis_luminaire_lighting *lum = (const lumis_luminaire_lighting *)stand_in;
    const lumis_photometric_lighting *fix = (const lumis_photometric_lighting *)stand_in;
    enum { ENV, SET, LUM, FIX };
    static const struct {
        int kind, sampler, est, set, mode, regions, lum, fix, env, hide, power, nl, nb, bounces;
        const char *said; /* NULL: accepted */
    } cases[] = {
        /* kind     smp est set mode rs lum fix env hide pow nl nb bnc */
        {ENV, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, "lighting.env: missing"},
        {ENV, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, "lighting.sampler: missing"},
        {ENV, 0, 2, 0, 0, 0, 0, 0, 1, 1, 1, 2, 2, 3, NULL}, /* BSDF-only needs no sampler */
        {ENV, 1, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, NULL},
        {ENV, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, "lighting.light_set.set: does not apply"},
        {ENV, 1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, "lighting.light_set.mode: does not apply"},
        {ENV, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 0, "lighting.luminaires: does not apply"},
        {ENV, 1, 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0, "lighting.photometric: does not apply"},
        {SET, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, "lighting.light_set.set: missing"},
        {SET, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, "lighting.env: missing"},
        {SET, 0, 0, 1, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, NULL},
        {SET, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, "lighting.sampler: does not apply"},
        {SET, 0, 1, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, "lighting.estimator: does not apply"},
        {SET, 0, 0, 1, 0, 1, 0, 0, 1, 0, 0, 0, 0, 0, "lighting.light_set.regions: does not"},
        {SET, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, "power_heuristic: does not apply"},
        {SET, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, "max_bounces: does not apply"},
        {SET, 0, 1, 1, 1, 1, 0, 0, 1, 1, 1, 0, 0, 2, NULL}, /* strata: light/MIS, paths */
        {SET, 0, 2, 1, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, "lighting.estimator: does not apply"},
        {SET, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 2, 0, 0, "light_samples: does not apply"},
        {SET, 0, 0, 1, 1, 0, 0, 0, 1, 0, 0, 0, 2, 0, "bsdf_samples: does not apply"},
        {LUM, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, "lighting.luminaires: missing"},
        {LUM, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, NULL},
        {LUM, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 0, 0, "lighting.env: does not apply"},
        {LUM, 0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 0, 0, "lighting.hide_environment: does not"},
        {LUM, 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0, 0, "lighting.photometric: does not apply"},
        {LUM, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 1, "max_bounces: does not apply"},
        {LUM, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 3, 0, "bsdf_samples: does not apply"},
        {FIX, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, "lighting.photometric: missing"},
        {FIX, 0, 2, 0, 0, 0, 0, 1, 0, 0, 1, 2, 2, 4, NULL},
        {FIX, 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0, 0, "lighting.luminaires: does not apply"},
        {FIX, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, "lighting.sampler: does not apply"},
        {FIX, 0, 0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 0, "lighting.env: does not apply"},
    };
    for (size_t c = 0; c < sizeof cases / sizeof *cases; c++) {
        lumis_render_desc d = {0};
        lumis_lighting *l = &d.lighting;
        l->kind = (lumis_lighting_kind)cases[c].kind;
        l->sampler = cases[c].sampler ? smp : NULL;
        l->estimator = (lumis_estimator)cases[c].est;
        l->light_set.set = cases[c].set ? set : NULL;
        l->light_set.mode = (lumis_lights_mode)cases[c].mode;
        l->light_set.regions = cases[c].regions ? rs : NULL;
        l->luminaires = cases[c].lum ? lum : NULL;
        l->photometric = cases[c].fix ? fix : NULL;
        l->env = cases[c].env ? env : NULL;
        l->hide_environment = cases[c].hide;
        d.power_heuristic = cases[c].power;
        d.light_samples = cases[c].nl;
        d.bsdf_samples = cases[c].nb;
        d.max_bounces = cases[c].bounces;
        tu_sink sink;
        tu_sink_init(&sink);
        d.errors = sink.sink;
        const lumis_status st = lumis_lighting_check(&d);
        if (!cases[c].said && st != LUMIS_OK) fail_msg("case %zu: refused: %s", c, sink.last);
        if (cases[c].said && (st != LUMIS_ERR_INVALID_ARGUMENT || sink.count != 1 ||
                              !strstr(sink.last, cases[c].said)))
            fail_msg("case %zu: wanted \"%s\", got %s (%d messages): %s", c, cases[c].said,
                     lumis_status_name(st), sink.count, sink.last);
    }
    /* unknown values, each named */
    lumis_render_desc d = {0};
    tu_sink sink;
    tu_sink_init(&sink);
    d.errors = sink.sink;
    d.lighting.kind = LUMIS_LIGHTING_KIND_COUNT;
    assert_int_equal(lumis_lighting_check(&d), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "lighting.kind 4: unknown"));
    d.lighting.kind = LUMIS_LIGHTING_ENV;
    d.lighting.light_set.mode = (lumis_lights_mode)7;
    assert_int_equal(lumis_lighting_check(&d), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "lighting.light_set.mode 7: unknown"));
    d.lighting.light_set.mode = LUMIS_LIGHTS_POINT;
    d.lighting.estimator = (lumis_estimator)3;
    assert_int_equal(lumis_lighting_check(&d), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "lighting.estimator 3: unknown"));
    assert_int_equal(lumis_lighting_check(NULL), LUMIS_ERR_INVALID_ARGUMENT);
    /* the kinds' names */
    for (int k = 0; k < LUMIS_LIGHTING_KIND_COUNT; k++) {
        lumis_lighting_kind back = LUMIS_LIGHTING_KIND_COUNT;
        assert_int_equal(
            lumis_lighting_kind_from_name(lumis_lighting_kind_name((lumis_lighting_kind)k), &back),
            LUMIS_OK);
        assert_int_equal(back, k);
    }
    assert_string_equal(lumis_lighting_kind_name(LUMIS_LIGHTING_LIGHT_SET), "light-set");
    lumis_lighting_kind k = LUMIS_LIGHTING_ENV;
    assert_int_equal(lumis_lighting_kind_from_name("sun", &k), LUMIS_ERR_INVALID_ARGUMENT);
    /* a session: its light-set options only with `lights`, `lights` only with a light-set
     * lighting of no set of the caller's (the session's to come counts as given) */
    lumis_camera cam = {{0, 0, 4}, {0, 0, 0}, {0, 1, 0}, 40.0f, 8, 6};
    lumis_session_desc s = {0};
    s.render.camera = &cam;
    s.render.errors = sink.sink;
    s.render.lighting.env = env;
    s.render.lighting.sampler = smp;
    s.lights = "median-cut";
    assert_int_equal(lumis_session_check(&s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "session: lights: does not apply: the scene is lit by "
                                      "the environment map"));
    s.render.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
    assert_int_equal(lumis_session_check(&s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "lighting.sampler: does not apply"));
    s.render.lighting.sampler = NULL;
    assert_int_equal(lumis_session_check(&s), LUMIS_OK);
    s.render.lighting.light_set.set = set;
    assert_int_equal(lumis_session_check(&s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "render.lighting.light_set.set: given"));
    s.render.lighting.light_set.set = NULL;
    s.upsample = 2;
    assert_int_equal(lumis_session_check(&s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "upsample: applies to Wu's decomposition"));
    s.upsample = 0;
    s.lights = NULL;
    s.interleave = 4;
    assert_int_equal(lumis_session_check(&s), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "interleave: does not apply without lights"));
    session_refusals(&cam, env, smp, rs);
}

static void bsdfs_below_the_horizon(void **state)
{
    (void)state;
    const lumis_vec3 up = {0, 0, 1}, down = {0.3f, 0, -0.95f}, side = {1, 0, 0},
                     tilt = {0.6f, 0, 0.8f}, mirror = {-0.6f, 0, 0.8f};
    for (int t = 0; t < LUMIS_BSDF_TYPE_COUNT; t++) {
        lumis_bsdf b = {(lumis_bsdf_type)t, {0.5f, 0.5f, 0.5f}, {0.5f, 0.5f, 0.5f}, 0.2f, 0.3f};
        const lumis_vec3 pairs[][2] = {{up, down}, {down, up}, {down, down}, {side, up}};
        for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++) {
            const lumis_rgb f = lumis_bsdf_eval(&b, pairs[k][0], pairs[k][1]);
            if (f.r != 0.0f || f.g != 0.0f || f.b != 0.0f)
                fail_msg("type %d pair %zu: f = %g", t, k, (double)f.r);
            if (lumis_bsdf_pdf(&b, pairs[k][0], pairs[k][1]) != 0.0f)
                fail_msg("type %d pair %zu: pdf > 0", t, k);
        }
        /* a sample from below the horizon is refused (pdf 0, weight 0) */
        lumis_bsdf_sample s = lumis_bsdf_sample_wi(&b, down, 0.3, 0.6, 0.9);
        assert_true(s.pdf == 0.0f && s.weight.r == 0.0f);
        /* the mirror direction: finite, positive */
        const lumis_rgb f = lumis_bsdf_eval(&b, tilt, mirror);
        assert_true(isfinite(f.r) && f.r > 0.0f);
        assert_true(isfinite(lumis_bsdf_pdf(&b, tilt, mirror)));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(core_and_maps),
        cmocka_unit_test(samplers_and_light_sets),
        cmocka_unit_test(files_and_metrics),
        cmocka_unit_test(luminaires),
        cmocka_unit_test(luminaire_images_refuse_what_they_cannot_sample),
        cmocka_unit_test(emitters_refuse_what_they_cannot_be),
        cmocka_unit_test(renderer),
        cmocka_unit_test(bsdfs_below_the_horizon),
        cmocka_unit_test(lighting_check_names_the_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
