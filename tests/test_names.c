/* The public names of every enumeration round-trip (X_name then X_from_name gives X back),
 * unknown and NULL names are refused, and the emitter's closed-form radiance. */
/* Oracles:
 * lumis_tonemap_name — consistency: round trip with lumis_tonemap_from_name, names distinct
 *     (every_enumeration_round_trips)
 * lumis_tonemap_from_name — consistency: round trip; unknown, empty and NULL names refused
 *     (every_enumeration_round_trips)
 * lumis_exr_compression_name — consistency: round trip, names distinct
 *     (every_enumeration_round_trips)
 * lumis_exr_compression_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_luminaire_basis_name — consistency: round trip, names distinct
 *     (every_enumeration_round_trips)
 * lumis_luminaire_basis_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_luminaire_strategy_name — consistency: round trip, names distinct
 *     (every_enumeration_round_trips)
 * lumis_luminaire_strategy_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_luminaire_search_name — consistency: round trip, names distinct
 *     (every_enumeration_round_trips)
 * lumis_luminaire_search_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_visibility_name — consistency: round trip, names distinct (every_enumeration_round_trips)
 * lumis_visibility_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_sequence_name — consistency: round trip, names distinct (every_enumeration_round_trips)
 * lumis_sequence_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_lights_mode_name — consistency: round trip, names distinct (every_enumeration_round_trips)
 * lumis_lights_mode_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_export_frame_name — consistency: round trip, names distinct (every_enumeration_round_trips)
 * lumis_export_frame_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_sampler_method_name — consistency: round trip, names distinct
 *     (every_enumeration_round_trips)
 * lumis_sampler_method_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_photometric_type_name — consistency: round trip over IES codes 1 to 3
 *     (every_enumeration_round_trips)
 * lumis_photometric_type_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_photometric_symmetry_name — consistency: round trip, names distinct
 *     (every_enumeration_round_trips)
 * lumis_photometric_symmetry_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_photometric_shape_name — consistency: round trip, names distinct
 *     (every_enumeration_round_trips)
 * lumis_photometric_shape_from_name — consistency: round trip; bad names refused
 *     (every_enumeration_round_trips)
 * lumis_format_from_path — hand-worked: x.exr, x.hdr, x.pfm, x.png (format_and_status_names)
 * lumis_format_name — hand-worked: each name is part of its extension (format_and_status_names)
 * lumis_status_name — hand-worked: "out-of-memory", "ok" (format_and_status_names)
 * lumis_emitter_radiance — closed form: a disk's radiance on and off its edge, a cos^2 lobe at 45°,
 *     a striped plate's transmission (emitter_radiance_closed_form)
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "lumis/io.h"
#include "lumis/lumis.h"
#include "lumis/render.h"

/* name(v) for v in [first, count) is a distinct non-empty string that from_name maps back to
 * v; "no-such-name", "" and NULL give LUMIS_ERR_INVALID_ARGUMENT and leave *out alone; count
 * (one past the last value) is "unknown"; a NULL out is refused (every pair is defined by
 * LUMIS__ENUM_NAMES in src/core/internal.h, so all behave alike). */
#define ROUND_TRIP(T, first, count, name_fn, from_fn)                                              \
    do {                                                                                           \
        for (int v = (first); v < (count); v++) {                                                  \
            const char *n = name_fn((T)v);                                                         \
            assert_non_null(n);                                                                    \
            assert_true(n[0] != '\0');                                                             \
            T back = (T)-1;                                                                        \
            assert_int_equal(from_fn(n, &back), LUMIS_OK);                                         \
            assert_int_equal((int)back, v);                                                        \
            for (int u = (first); u < v; u++) assert_string_not_equal(name_fn((T)u), n);           \
        }                                                                                          \
        T keep = (T)(first);                                                                       \
        assert_int_equal(from_fn("no-such-name", &keep), LUMIS_ERR_INVALID_ARGUMENT);              \
        assert_int_equal(from_fn("", &keep), LUMIS_ERR_INVALID_ARGUMENT);                          \
        assert_int_equal(from_fn(NULL, &keep), LUMIS_ERR_INVALID_ARGUMENT);                        \
        assert_int_equal((int)keep, (first));                                                      \
        assert_string_equal(name_fn((T)(count)), "unknown");                                       \
        assert_int_equal(from_fn(name_fn((T)(first)), NULL), LUMIS_ERR_INVALID_ARGUMENT);          \
    } while (0)

static void every_enumeration_round_trips(void **state)
{
    (void)state;
    ROUND_TRIP(lumis_tonemap, 0, LUMIS_TONEMAP_COUNT, lumis_tonemap_name, lumis_tonemap_from_name);
    ROUND_TRIP(lumis_exr_compression, 0, LUMIS_EXR_COMPRESSION_COUNT, lumis_exr_compression_name,
               lumis_exr_compression_from_name);
    ROUND_TRIP(lumis_luminaire_basis, 0, LUMIS_BASIS_COUNT, lumis_luminaire_basis_name,
               lumis_luminaire_basis_from_name);
    ROUND_TRIP(lumis_luminaire_strategy, 0, LUMIS_LUM_STRATEGY_COUNT, lumis_luminaire_strategy_name,
               lumis_luminaire_strategy_from_name);
    ROUND_TRIP(lumis_luminaire_search, 0, LUMIS_LUM_SEARCH_COUNT, lumis_luminaire_search_name,
               lumis_luminaire_search_from_name);
    ROUND_TRIP(lumis_visibility, 0, LUMIS_VISIBILITY_COUNT, lumis_visibility_name,
               lumis_visibility_from_name);
    ROUND_TRIP(lumis_sequence, 0, LUMIS_SEQUENCE_COUNT, lumis_sequence_name,
               lumis_sequence_from_name);
    ROUND_TRIP(lumis_lights_mode, 0, LUMIS_LIGHTS_MODE_COUNT, lumis_lights_mode_name,
               lumis_lights_mode_from_name);
    ROUND_TRIP(lumis_export_frame, 0, LUMIS_EXPORT_FRAME_COUNT, lumis_export_frame_name,
               lumis_export_frame_from_name);
    /* 0 is "default", an alias of inversion-guided */
    ROUND_TRIP(lumis_sampler_method, 1, LUMIS_METHOD_COUNT, lumis_sampler_method_name,
               lumis_sampler_method_from_name);
    /* photometric types are IES's codes, 1 to 3 */
    ROUND_TRIP(lumis_photometric_type, 1, 4, lumis_photometric_type_name,
               lumis_photometric_type_from_name);
    ROUND_TRIP(lumis_photometric_symmetry, 0, LUMIS_SYMMETRY_LATERAL + 1,
               lumis_photometric_symmetry_name, lumis_photometric_symmetry_from_name);
    ROUND_TRIP(lumis_photometric_shape, 0, LUMIS_SHAPE_OTHER + 1, lumis_photometric_shape_name,
               lumis_photometric_shape_from_name);
    ROUND_TRIP(lumis_luminaire_preset, 0, LUMIS_PRESET_SMALL + 1, lumis_luminaire_preset_name,
               lumis_luminaire_preset_from_name);
    ROUND_TRIP(lumis_lighting_kind, 0, LUMIS_LIGHTING_KIND_COUNT, lumis_lighting_kind_name,
               lumis_lighting_kind_from_name);
}

static void format_and_status_names(void **state)
{
    (void)state;
    static const char *const ext[] = {"x.exr", "x.hdr", "x.pfm", "x.png"};
    for (int f = LUMIS_FORMAT_EXR; f < LUMIS_FORMAT_COUNT; f++) {
        assert_int_equal(lumis_format_from_path(ext[f - 1]), f);
        assert_non_null(strstr(ext[f - 1], lumis_format_name((lumis_file_format)f)));
    }
    assert_string_equal(lumis_status_name(LUMIS_ERR_OUT_OF_MEMORY), "out-of-memory");
    assert_string_equal(lumis_status_name(LUMIS_OK), "ok");
}

/* One Lambertian disk at z = -1 and one with a cos^2 lobe, seen through a striped plate. */
static void emitter_radiance_closed_form(void **state)
{
    (void)state;
    lumis_emitter_disk disk = {{0, 0, -1}, 2.0, {2.0f, 1.0f, 0.5f}, 0.0};
    lumis_emitter_desc e = {0};
    e.disks = &disk;
    e.disk_count = 1;
    const double delta = 1.0;
    /* straight up through the centre: the disk's radiance */
    lumis_rgb r = lumis_emitter_radiance(&e, delta, 0, 0, 0, 0);
    assert_float_equal(r.r, 2.0f, 1e-6f);
    assert_float_equal(r.g, 1.0f, 1e-6f);
    assert_float_equal(r.b, 0.5f, 1e-6f);
    /* a ray that misses it: back along (1, 0, 1) from u = (2.5, 0) lands at x = 1.5 ... in;
     * from u = (3.5, 0) at x = 2.5: out */
    r = lumis_emitter_radiance(&e, delta, 2.5, 0, 3.5, 0);
    assert_float_equal(r.r, 2.0f, 1e-6f);
    r = lumis_emitter_radiance(&e, delta, 3.5, 0, 4.5, 0);
    assert_float_equal(r.r + r.g + r.b, 0.0f, 0.0f);
    /* a cos^2 lobe: at 45 degrees half the radiance */
    disk.exponent = 2.0;
    r = lumis_emitter_radiance(&e, delta, 0, 0, 1, 0);
    assert_float_equal(r.r, 1.0f, 1e-6f);
    assert_float_equal(r.b, 0.25f, 1e-6f);
    /* stripes of period 1 on a plate at z = -0.5, contrast 0.75: a straight ray at x = 1.5
     * crosses an odd stripe (transmission 0.25), at x = 0.5 an even one (clear) */
    disk.exponent = 0.0;
    e.pattern = LUMIS_PATTERN_STRIPES;
    e.plate_z = -0.5;
    e.period[0] = e.period[1] = 1.0;
    e.contrast = 0.75;
    r = lumis_emitter_radiance(&e, delta, 1.5, 0, 1.5, 0);
    assert_float_equal(r.r, 0.5f, 1e-6f);
    r = lumis_emitter_radiance(&e, delta, 0.5, 0, 0.5, 0);
    assert_float_equal(r.r, 2.0f, 1e-6f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_enumeration_round_trips),
        cmocka_unit_test(format_and_status_names),
        cmocka_unit_test(emitter_radiance_closed_form),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
