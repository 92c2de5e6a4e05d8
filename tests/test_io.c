/* Image files: round trips through every writer and reader, and every class of bad input
 * getting its own status and a message that names the file. */
/* Oracles:
 * lumis_image_read — external: PNG layouts written by tests/data/png/make.py from formulas,
 *     tests/data/grey-y.exr; hand-worked: sRGB decode of 156; round trips through every writer
 *     (png_bit_depths_palettes_and_interlacing, exr_grey_reads_into_every_channel,
 *     png_applies_exposure_tonemap_and_srgb, exr_round_trips_every_compression_and_tiling)
 * lumis_image_read_memory — hand-worked: HDR EXPOSURE lines and XYZE white, old-style runs 1 + 1 +
 *     256, PFM grey and bottom-up rows; error paths: truncated and oversized EXR
 *     (hdr_exposures_multiply_and_xyze_converts, hdr_consecutive_old_style_runs,
 *     pfm_grey_and_bottom_up_rows, exr_block_buffers_are_bounded)
 * lumis_image_write — external: stb_image reads the PNG bytes 0, 255, sRGB(0.5) = 188; hand-worked:
 *     NaN black, huge values clamped; round trips exact (PFM), within RGBE and half precision
 *     (png_applies_exposure_tonemap_and_srgb, hdr_writes_nan_as_black,
 *     exr_half_clamps_instead_of_overflowing, pfm_round_trips_exactly_in_both_byte_orders)
 * lumis_tonemap_apply — hand-worked: ACES at 0.18 and 1e9; Reinhard 1 stop down gives sRGB(1/3)
 *     (png_applies_exposure_tonemap_and_srgb)
 * lumis_tonemap_from_name — hand-worked: "aces" known, "filmic" refused
 *     (png_applies_exposure_tonemap_and_srgb)
 * lumis_format_from_path — hand-worked: .EXR in any case, .pic, a directory named .exr, NULL
 *     (format_names_and_detection)
 * lumis_format_from_magic — hand-worked: the magic bytes of HDR, PFM, EXR, PNG; one byte off or
 *     one short of each, not a format (format_names_and_detection)
 * lumis_format_name — hand-worked: "pfm" (format_names_and_detection)
 * lumis_exr_compression_from_name — hand-worked: "dwab"; "lzma" refused
 *     (format_names_and_detection)
 * lumis_exr_compression_name — hand-worked: "piz" (format_names_and_detection)
 * lumis_map_read — hand-worked: "studio:WxH" and "sky:WxH" sizes; a file named like a spec is read
 *     as a file (map_specs_name_sizes_and_files)
 * lumis_write_text — hand-worked: FIFOs, links, descriptors and directories written in place or
 *     refused (outputs_to_fifos_links_and_directories, outputs_through_descriptors_and_links)
 * lumis_output_target — hand-worked: /dev/fd/N, /proc/self/fd/N, /dev/stderr, dangling links,
 *     chains and loops resolved (outputs_through_descriptors_and_links)
 * lumis_io_remove_partial_outputs — hand-worked: a write in progress loses its temporary file and
 *     then fails (partial_outputs_are_removed_on_request)
 * lumis_export_frame_dir — external: every pixel centre lands on its pixel under three.js's and
 *     Blender's own mappings, written from their sources
 *     (export_frame_maps_pixels_where_consumers_show_them)
 * lumis_export_frame_name — hand-worked: "unknown" past the end
 *     (export_frame_maps_pixels_where_consumers_show_them)
 * lumis_export_frame_from_name — hand-worked: "engine", "lumis"; "three" refused
 *     (export_frame_maps_pixels_where_consumers_show_them)
 * lumis_light_set_write_gltf — external: the brightest light lands on the sun's pixel under
 *     three.js's and Blender's mappings; the GLB container per the glTF 2.0 spec (also
 *     tests/consumers) (exported_sun_lands_on_the_sun_pixel, glb_is_a_binary_gltf_container)
 * lumis_light_set_write_json — external: the sun's light lands on the sun's pixel; the frame is
 *     recorded; an image sun first, on its pixel, powers adding up to the map's
 *     (exported_sun_lands_on_the_sun_pixel, exported_image_sun_and_residual)
 */
#include "testutil.h"

#include "io/internal.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stb_image.h>
#include <cJSON.h>

static float f_smooth(int i, int j, int c)
{
    return (float)(0.01 + (i * 7 + j * 13 + c * 5) % 97 * 0.37 + (i == 3 && j == 2 ? 5e4 : 0.0));
}

static lumis_image *sample_image(int w, int h)
{
    return tu_image(w, h, f_smooth);
}

static lumis_status write_img(const char *path, const lumis_image *img,
                              const lumis_write_options *o)
{
    return lumis_image_write(path, img, o);
}

static lumis_image *read_ok(const char *path, lumis_read_info *info)
{
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_read_options ro = {0};
    ro.errors = sink.sink;
    lumis_image *img = NULL;
    lumis_status st = lumis_image_read(path, &ro, &img, info);
    if (st != LUMIS_OK) fail_msg("%s: %s (%s)", path, lumis_status_name(st), sink.last);
    return img;
}

/* Expects a status and a message naming the file from reading path. */
static void expect_read_error(const char *path, lumis_status want)
{
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_read_options ro = {0};
    ro.errors = sink.sink;
    lumis_image *img = (lumis_image *)1;
    lumis_status st = lumis_image_read(path, &ro, &img, NULL);
    if (st != want)
        fail_msg("%s: got %s, want %s (%s)", path, lumis_status_name(st), lumis_status_name(want),
                 sink.last);
    assert_null(img);
    assert_true(sink.count >= 1);
    assert_non_null(strstr(sink.last, path));
}

/* As expect_memory_error, and the message must contain `says`. */
static void expect_memory_message(const char *text, size_t size, lumis_status want,
                                  const char *says)
{
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_read_options ro = {0};
    ro.errors = sink.sink;
    lumis_image *img = NULL;
    lumis_status st =
        lumis_image_read_memory(text, size, LUMIS_FORMAT_AUTO, "mem.x", &ro, &img, NULL);
    if (st != want)
        fail_msg("\"%.40s\": got %s, want %s (%s)", text, lumis_status_name(st),
                 lumis_status_name(want), sink.last);
    assert_null(img);
    assert_non_null(strstr(sink.last, "mem.x"));
    if (says && !strstr(sink.last, says)) fail_msg("message '%s' lacks '%s'", sink.last, says);
}

static void expect_memory_error(const char *text, size_t size, lumis_status want)
{
    expect_memory_message(text, size, want, NULL);
}

static void assert_close(const lumis_image *a, const lumis_image *b, double rel, double abs_tol)
{
    assert_int_equal(a->width, b->width);
    assert_int_equal(a->height, b->height);
    size_t n = (size_t)a->width * a->height * 3;
    for (size_t k = 0; k < n; k++) {
        double x = a->pixels[k], y = b->pixels[k];
        if (!(fabs(x - y) <= rel * fabs(x) + abs_tol))
            fail_msg("value %zu (pixel %zu): %.9g vs %.9g", k, k / 3, x, y);
    }
}

/* ---- round trips ------------------------------------------------------------------- */

static void exr_round_trips_every_compression_and_tiling(void **state)
{
    (void)state;
    static const int sizes[][2] = {{1, 1}, {37, 19}, {64, 32}};
    for (int s = 0; s < 3; s++) {
        lumis_image *img = sample_image(sizes[s][0], sizes[s][1]);
        for (int c = 0; c < LUMIS_EXR_COMPRESSION_COUNT; c++)
            for (int half = 0; half < 2; half++)
                for (int tile = 0; tile < 2; tile++) {
                    lumis_write_options wo = {0};
                    wo.exr_compression = (lumis_exr_compression)c;
                    wo.exr_half = half;
                    wo.exr_tile_size = tile ? 16 : 0;
                    const char *path = tu_path("rt.exr");
                    assert_int_equal(write_img(path, img, &wo), LUMIS_OK);
                    lumis_read_info info;
                    lumis_image *back = read_ok(path, &info);
                    assert_int_equal(info.format, LUMIS_FORMAT_EXR);
                    assert_int_equal(lumis_replaced_total(info.replaced), 0);
                    int lossy = c == LUMIS_EXR_PXR24 || c == LUMIS_EXR_B44 || c == LUMIS_EXR_B44A ||
                                c == LUMIS_EXR_DWAA || c == LUMIS_EXR_DWAB;
                    double rel = half ? 1e-3 : 0.0;
                    if (lossy)
                        rel = c >= LUMIS_EXR_DWAA || c == LUMIS_EXR_B44 || c == LUMIS_EXR_B44A
                                  ? 0.2
                                  : 1e-4;
                    assert_close(img, back, rel, lossy ? 0.5 : 0.0);
                    lumis_image_destroy(back);
                }
        lumis_image_destroy(img);
    }
}

static void exr_half_clamps_instead_of_overflowing(void **state)
{
    (void)state;
    lumis_image *img = sample_image(4, 4);
    img->pixels[0] = 1e6f; /* a sun */
    lumis_write_options wo = {0};
    wo.exr_half = 1;
    assert_int_equal(write_img(tu_path("sun.exr"), img, &wo), LUMIS_OK);
    lumis_read_info info;
    lumis_image *back = read_ok(tu_path("sun.exr"), &info);
    assert_true(back->pixels[0] == 65504.0f);
    assert_int_equal(lumis_replaced_total(info.replaced), 0);
    lumis_image_destroy(back);
    lumis_image_destroy(img);
}

static void hdr_round_trip_within_rgbe_precision(void **state)
{
    (void)state;
    /* Width 64 takes the RLE path of the writer, width 5 the flat one. */
    for (int w = 5; w <= 64; w += 59) {
        lumis_image *img = sample_image(w, 9);
        assert_int_equal(write_img(tu_path("rt.hdr"), img, NULL), LUMIS_OK);
        lumis_read_info info;
        lumis_image *back = read_ok(tu_path("rt.hdr"), &info);
        assert_int_equal(info.format, LUMIS_FORMAT_HDR);
        /* An 8-bit mantissa shared by the pixel: error up to 1/128 of its largest channel. */
        for (size_t k = 0; k < (size_t)w * 9; k++) {
            const float *a = img->pixels + 3 * k, *b = back->pixels + 3 * k;
            float m = fmaxf(a[0], fmaxf(a[1], a[2]));
            for (int c = 0; c < 3; c++) assert_true(fabsf(a[c] - b[c]) <= m / 128.0f);
        }
        lumis_image_destroy(back);
        lumis_image_destroy(img);
    }
}

static void pfm_round_trips_exactly_in_both_byte_orders(void **state)
{
    (void)state;
    lumis_image *img = sample_image(13, 7);
    for (int big = 0; big < 2; big++) {
        lumis_write_options wo = {0};
        wo.pfm_big_endian = big;
        assert_int_equal(write_img(tu_path("rt.pfm"), img, &wo), LUMIS_OK);
        size_t n;
        unsigned char *raw = tu_read_file(tu_path("rt.pfm"), &n);
        assert_non_null(strstr((char *)raw, big ? "\n1.0\n" : "\n-1.0\n"));
        free(raw);
        lumis_image *back = read_ok(tu_path("rt.pfm"), NULL);
        assert_close(img, back, 0.0, 0.0);
        lumis_image_destroy(back);
    }
    lumis_image_destroy(img);
}

static void put_le(unsigned char *b, float f)
{
    memcpy(b, &f, 4);
} /* x86: little-endian */

static void pfm_grey_and_bottom_up_rows(void **state)
{
    (void)state;
    /* 2 x 2 grey, little-endian: bottom row (1, 2), top row (3, 4). */
    unsigned char buf[64];
    int n = snprintf((char *)buf, sizeof buf, "Pf\n2 2\n-1.0\n");
    const float v[4] = {1, 2, 3, 4};
    for (int k = 0; k < 4; k++) put_le(buf + n + 4 * k, v[k]);
    lumis_image *img = NULL;
    lumis_read_info info;
    assert_int_equal(
        lumis_image_read_memory(buf, (size_t)n + 16, LUMIS_FORMAT_AUTO, NULL, NULL, &img, &info),
        LUMIS_OK);
    assert_true(info.grey);
    assert_true(img->pixels[0] == 3 && img->pixels[1] == 3 && img->pixels[3] == 4);
    assert_true(img->pixels[6] == 1 && img->pixels[9] == 2 && img->pixels[11] == 2);
    lumis_image_destroy(img);
}

static void bad_values_are_replaced_and_counted(void **state)
{
    (void)state;
    lumis_image *img = sample_image(3, 2);
    img->pixels[0] = NAN;
    img->pixels[4] = INFINITY;
    img->pixels[5] = -INFINITY;
    img->pixels[7] = -3.0f;
    assert_int_equal(write_img(tu_path("bad.pfm"), img, NULL), LUMIS_OK);
    lumis_read_info info;
    lumis_image *back = read_ok(tu_path("bad.pfm"), &info);
    assert_int_equal(info.replaced.nan, 1);
    assert_int_equal(info.replaced.inf, 2);
    assert_int_equal(info.replaced.negative, 1);
    assert_true(back->pixels[0] == 0.0f && back->pixels[4] == 0.0f && back->pixels[7] == 0.0f);
    assert_true(back->pixels[1] == img->pixels[1]);
    lumis_image_destroy(back);
    /* The same through EXR (float keeps NaN and Inf). */
    assert_int_equal(write_img(tu_path("bad.exr"), img, NULL), LUMIS_OK);
    back = read_ok(tu_path("bad.exr"), &info);
    assert_int_equal(lumis_replaced_total(info.replaced), 4);
    lumis_image_destroy(back);
    lumis_image_destroy(img);
}

static float f_zero(int i, int j, int c)
{
    (void)i, (void)j, (void)c;
    return 0.0f;
}

static void black_and_one_pixel_maps_read_back(void **state)
{
    (void)state;
    lumis_image *black = tu_image(8, 4, f_zero);
    const char *names[] = {"black.exr", "black.hdr", "black.pfm"};
    for (int k = 0; k < 3; k++) {
        assert_int_equal(write_img(tu_path(names[k]), black, NULL), LUMIS_OK);
        lumis_image *back = read_ok(tu_path(names[k]), NULL);
        assert_close(black, back, 0.0, 0.0);
        lumis_image_destroy(back);
    }
    lumis_image_destroy(black);
    lumis_image *one = sample_image(1, 1);
    const char *ones[] = {"one.exr", "one.pfm"};
    for (int k = 0; k < 2; k++) {
        assert_int_equal(write_img(tu_path(ones[k]), one, NULL), LUMIS_OK);
        lumis_image *back = read_ok(tu_path(ones[k]), NULL);
        assert_close(one, back, 0.0, 0.0);
        lumis_image_destroy(back);
    }
    lumis_image_destroy(one);
}

static void png_applies_exposure_tonemap_and_srgb(void **state)
{
    (void)state;
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(4, 1, &img), LUMIS_OK);
    const float v[12] = {0, 0, 0, 1, 1, 1, 0.5f, 0.5f, 0.5f, 8, NAN, -1};
    memcpy(img->pixels, v, sizeof v);
    lumis_write_options wo = {0};
    assert_int_equal(write_img(tu_path("t.png"), img, &wo), LUMIS_OK);
    int w, h, n;
    unsigned char *px = stbi_load(tu_path("t.png"), &w, &h, &n, 3);
    assert_non_null(px);
    assert_true(w == 4 && h == 1);
    assert_int_equal(px[0], 0);
    assert_int_equal(px[3], 255);
    assert_int_equal(px[6], 188); /* sRGB(0.5) = 0.7354 */
    assert_int_equal(px[9], 255); /* clamped */
    assert_int_equal(px[10], 0);  /* NaN is black */
    assert_int_equal(px[11], 0);
    stbi_image_free(px);
    /* One stop down and Reinhard: 1 -> 0.5 / 1.5. */
    wo.exposure_ev = -1.0f;
    wo.tonemap = LUMIS_TONEMAP_REINHARD;
    assert_int_equal(write_img(tu_path("t.png"), img, &wo), LUMIS_OK);
    px = stbi_load(tu_path("t.png"), &w, &h, &n, 3);
    assert_int_equal(px[3], 156); /* sRGB(1/3) = 0.6136 */
    stbi_image_free(px);
    /* Read back: decoded from sRGB to linear (156 / 255 -> 0.3325). */
    lumis_image *back = NULL;
    assert_int_equal(lumis_image_read(tu_path("t.png"), NULL, &back, NULL), LUMIS_OK);
    assert_true(back->width == 4 && back->height == 1);
    assert_true(back->pixels[0] == 0.0f);
    assert_true(fabsf(back->pixels[3] - 0.33245f) < 1e-4f);
    assert_true(fabsf(back->pixels[9] - 0.8f) < 3e-3f); /* Reinhard(4) = 0.8, 8 bits */
    lumis_image_destroy(back);
    /* A PNG cut short is refused with a message. */
    size_t n_png;
    unsigned char *png = tu_read_file(tu_path("t.png"), &n_png);
    tu_write_file(tu_path("cut.png"), png, n_png / 2);
    free(png);
    assert_int_equal(lumis_image_read(tu_path("cut.png"), NULL, &back, NULL), LUMIS_ERR_CORRUPT);
    assert_null(back);
    /* Found by fuzz_png: a 16 x 8 PNG whose IDAT data is corrupt and inflates past the
     * declared size; stb_image's inflater (the reader before libpng) doubled its buffer up
     * to a 2 GB request. libpng inflates row by row and finds the bad stream. */
    static const unsigned char inflating[] = {
        0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
        0x52, 0x00, 0x00, 0x00, 0x10, 0x00, 0x00, 0x00, 0x08, 0x08, 0x02, 0x00, 0x00, 0x00, 0x7f,
        0x14, 0xe8, 0xc0, 0x00, 0x00, 0x00, 0x9a, 0x49, 0x44, 0x41, 0x54, 0x78, 0x5e, 0x63, 0xe4,
        0x11, 0x92, 0x61, 0xf8, 0x0f, 0x03, 0x0c, 0x20, 0x26, 0x94, 0x60, 0x60, 0x60, 0x64, 0x64,
        0x00, 0x11, 0x8c, 0x20, 0x9a, 0x11, 0x0c, 0x80, 0x42, 0x2c, 0xdc, 0x9c, 0x9c, 0x7f, 0xfe,
        0xfc, 0xfd, 0xf6, 0xf7, 0xcf, 0xdf, 0xbf, 0x7f, 0xff, 0xff, 0xfb, 0xfe, 0xfa, 0x0d, 0x44,
        0xbf, 0x81, 0x76, 0x40, 0x6c, 0x00, 0xba, 0x83, 0x01, 0xe4, 0x1a, 0x90, 0x5d, 0x00, 0x00,
        0x9a, 0x49, 0x44, 0x41, 0x54, 0x78, 0x5e, 0x63, 0xe4, 0x11, 0x92, 0x61, 0xf8, 0x0f, 0x03,
        0x0c, 0xf7, 0x9f, 0x01, 0x06, 0x81, 0x8a, 0xff, 0x33, 0x32, 0x30, 0x82, 0x30, 0x23, 0x13,
        0x13, 0x33, 0x33, 0x33, 0x2b, 0x33, 0x0b, 0x0b, 0x0b, 0x33, 0xd3, 0xc9, 0x9d, 0xd3, 0xd9,
        0xd9, 0xd9, 0x58, 0x98, 0x99, 0x99, 0x98, 0x98, 0x18, 0x81, 0x10, 0x48, 0x82, 0x98, 0x40,
        0xcc, 0xcc, 0x08, 0x62, 0x40, 0x05, 0x81, 0x0a, 0x80, 0xca, 0xf8, 0x78, 0xb9, 0x19, 0x35,
        0x34, 0x74, 0x7e, 0xfe, 0xfa, 0x0d, 0x44, 0xbf, 0x81, 0x76, 0x40, 0x6c, 0x00, 0xba, 0x83,
        0x01, 0xe4, 0x1a, 0x90, 0x5d, 0x00, 0x00, 0x9a, 0x49, 0x44, 0x41, 0x54, 0x78, 0x5e, 0x63,
        0xe4, 0x11, 0x92, 0x61, 0xf8, 0x0f, 0x03, 0x0c, 0x98, 0x18, 0x48, 0x04, 0x21, 0xd7, 0x00,
        0x00, 0x20, 0x63, 0x35, 0xab, 0x5a, 0x88, 0x26, 0xb9, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45,
        0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
    tu_write_file(tu_path("inflating.png"), inflating, sizeof inflating);
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_read_options ro = {0};
    ro.errors = sink.sink;
    assert_int_equal(lumis_image_read(tu_path("inflating.png"), &ro, &back, NULL),
                     LUMIS_ERR_CORRUPT);
    assert_non_null(strstr(sink.last, "inflating.png: not a readable PNG: IDAT"));
    assert_null(back);

    /* Found by fuzz_png: a 16-bit PGM handed to the PNG reader made stb_image return fewer
     * bytes than it announced.  Only PNG signatures pass now. */
    static const unsigned char pgm[] = "P53\v01\v5555v#Pf55555555555555555556\v6.,";
    assert_int_equal(
        lumis_image_read_memory(pgm, sizeof pgm - 1, LUMIS_FORMAT_PNG, "pgm", NULL, &back, NULL),
        LUMIS_ERR_BAD_MAGIC);
    assert_null(back);
    /* Tone map names and curves. */
    lumis_tonemap t;
    assert_int_equal(lumis_tonemap_from_name("aces", &t), LUMIS_OK);
    assert_int_equal(t, LUMIS_TONEMAP_ACES);
    assert_int_equal(lumis_tonemap_from_name("filmic", &t), LUMIS_ERR_INVALID_ARGUMENT);
    assert_true(lumis_tonemap_apply(LUMIS_TONEMAP_ACES, 1e9f) == 1.0f);
    assert_true(fabsf(lumis_tonemap_apply(LUMIS_TONEMAP_ACES, 0.18f) - 0.2669f) < 1e-3f);
    lumis_image_destroy(img);
}

/* ---- bad input ---------------------------------------------------------------------- */

/* The sRGB decoding curve (IEC 61966-2-1) in double precision. */
static double srgb_decode(double v)
{
    return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}

/* PNG layouts stb_image_write never produces, written by tests/data/png/make.py (zlib and
 * the chunk format) from the formulas below: every value must decode exactly. */
static void png_bit_depths_palettes_and_interlacing(void **state)
{
    (void)state;
    static const struct {
        const char *file;
        int kind;
    } cases[] = {{"rgba16-adam7.png", 0},  /* 16-bit RGBA, Adam7; alpha dropped */
                 {"palette-adam7.png", 1}, /* 8-bit palette, Adam7 */
                 {"grey16.png", 2},        /* 16-bit grey */
                 {"greyalpha8.png", 3}};   /* 8-bit grey + alpha */
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        char path[1024];
        snprintf(path, sizeof path, "%s/tests/data/png/%s", LUMIS_SOURCE_DIR, cases[c].file);
        lumis_image *img = read_ok(path, NULL);
        assert_int_equal(img->width, 13);
        assert_int_equal(img->height, 11);
        for (int y = 0; y < 11; y++)
            for (int x = 0; x < 13; x++) {
                double want[3];
                switch (cases[c].kind) {
                case 0:
                    want[0] = ((x * 5003) & 65535) / 65535.0;
                    want[1] = ((y * 5807) & 65535) / 65535.0;
                    want[2] = ((x * y * 401) & 65535) / 65535.0;
                    break;
                case 1: {
                    int i = (x * 11 + y * 17) & 255; /* PLTE entry i = (i, 255 - i, 7i) */
                    want[0] = i / 255.0;
                    want[1] = (255 - i) / 255.0;
                    want[2] = ((i * 7) & 255) / 255.0;
                    break;
                }
                case 2:
                    want[0] = want[1] = want[2] = ((x * 5003 + y * 71) & 65535) / 65535.0;
                    break;
                default:
                    want[0] = want[1] = want[2] = ((x * 19 + y) & 255) / 255.0;
                    break;
                }
                const float *px = img->pixels + 3 * ((size_t)y * 13 + (size_t)x);
                for (int k = 0; k < 3; k++)
                    if (fabs(px[k] - srgb_decode(want[k])) > 1e-6)
                        fail_msg("%s (%d, %d)[%d]: %.8g, want %.8g", cases[c].file, x, y, k,
                                 (double)px[k], srgb_decode(want[k]));
            }
        lumis_image_destroy(img);
    }
}

static void missing_empty_and_unknown_files(void **state)
{
    (void)state;
    expect_read_error(tu_path("does-not-exist.exr"), LUMIS_ERR_OPEN);
    expect_read_error(tu_tmpdir(), LUMIS_ERR_OPEN); /* a folder */
    tu_write_file(tu_path("empty.exr"), "", 0);
    expect_read_error(tu_path("empty.exr"), LUMIS_ERR_EMPTY_FILE);
    const char text[] = "this is a text file, renamed\n";
    tu_write_file(tu_path("text.exr"), text, sizeof text - 1);
    expect_read_error(tu_path("text.exr"), LUMIS_ERR_UNKNOWN_FORMAT);
    tu_write_file(tu_path("x.png"), "\x89PNG\r\n\x1a\n0000", 12);
    expect_read_error(tu_path("x.png"), LUMIS_ERR_CORRUPT);
    /* Forced formats check the content too. */
    lumis_image *img = NULL;
    assert_int_equal(
        lumis_image_read_memory(text, sizeof text, LUMIS_FORMAT_EXR, NULL, NULL, &img, NULL),
        LUMIS_ERR_BAD_MAGIC);
    assert_int_equal(
        lumis_image_read_memory(text, sizeof text, LUMIS_FORMAT_HDR, NULL, NULL, &img, NULL),
        LUMIS_ERR_BAD_MAGIC);
    assert_int_equal(
        lumis_image_read_memory(text, sizeof text, LUMIS_FORMAT_PFM, NULL, NULL, &img, NULL),
        LUMIS_ERR_BAD_MAGIC);
    assert_int_equal(lumis_image_read(NULL, NULL, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_image_read_memory(NULL, 5, LUMIS_FORMAT_AUTO, NULL, NULL, &img, NULL),
                     LUMIS_ERR_INVALID_ARGUMENT);
}

static unsigned char *exr_bytes(int w, int h, lumis_exr_compression c, int tile, size_t *n)
{
    lumis_image *img = sample_image(w, h);
    lumis_write_options wo = {0};
    wo.exr_compression = c;
    wo.exr_tile_size = tile;
    assert_int_equal(write_img(tu_path("src.exr"), img, &wo), LUMIS_OK);
    lumis_image_destroy(img);
    return tu_read_file(tu_path("src.exr"), n);
}

/* Offset just past the EXR header: the attribute list ends with an empty name (a NUL). */
static size_t exr_header_end(const unsigned char *b, size_t n)
{
    size_t p = 8; /* magic and version */
    while (p < n && b[p] != 0) {
        p += strlen((const char *)b + p) + 1; /* name */
        p += strlen((const char *)b + p) + 1; /* type */
        uint32_t size;
        memcpy(&size, b + p, 4);
        p += 4 + size;
    }
    return p + 1;
}

static void truncated_and_header_only_exr(void **state)
{
    (void)state;
    for (int tile = 0; tile <= 16; tile += 16) {
        size_t n;
        unsigned char *b = exr_bytes(40, 20, LUMIS_EXR_ZIP, tile, &n);
        size_t hdr = exr_header_end(b, n);
        assert_true(hdr > 8 && hdr < n);
        /* Header only: no offset table, no pixels. */
        tu_write_file(tu_path("header-only.exr"), b, hdr);
        expect_read_error(tu_path("header-only.exr"), LUMIS_ERR_TRUNCATED);
        /* Cut inside the header, inside the offsets, and inside the pixel data. */
        const size_t cuts[] = {6, 20, hdr / 2, hdr + 4, hdr + 30, (hdr + n) / 2, n - 1};
        for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++) {
            tu_write_file(tu_path("cut.exr"), b, cuts[k]);
            tu_sink sink;
            tu_sink_init(&sink);
            lumis_read_options ro = {0};
            ro.errors = sink.sink;
            lumis_image *img = NULL;
            lumis_status st = lumis_image_read(tu_path("cut.exr"), &ro, &img, NULL);
            if (st != LUMIS_ERR_TRUNCATED)
                fail_msg("cut at %zu of %zu (tile %d): %s (%s)", cuts[k], n, tile,
                         lumis_status_name(st), sink.last);
            assert_null(img);
            /* The same bytes from memory. */
            st = lumis_image_read_memory(b, cuts[k], LUMIS_FORMAT_AUTO, NULL, NULL, &img, NULL);
            assert_int_equal(st, LUMIS_ERR_TRUNCATED);
        }
        free(b);
    }
}

static void corrupt_exr_data(void **state)
{
    (void)state;
    size_t n;
    unsigned char *b = exr_bytes(40, 20, LUMIS_EXR_ZIP, 0, &n);
    size_t hdr = exr_header_end(b, n);
    /* Scramble the compressed pixel data (past the offset table of 2 chunks x 8 bytes). */
    for (size_t k = hdr + 2 * 8 + 12; k < n; k += 3) b[k] ^= 0x5a;
    tu_write_file(tu_path("corrupt.exr"), b, n);
    expect_read_error(tu_path("corrupt.exr"), LUMIS_ERR_CORRUPT);
    free(b);
}

/* Found by fuzz_exr: 29 bytes whose attribute claims 2 GiB made OpenEXR allocate it. */
static void exr_attribute_sizes_are_checked_before_openexr(void **state)
{
    (void)state;
    static const unsigned char b[29] = {0x76, 0x2f, 0x31, 0x01, 0x02, 0x00, 0x00, 0x00, 0x78, 0x00,
                                        0x6f, 0x70, 0x61, 0x71, 0x75, 0x65, 0x00, 0xf0, 0xff, 0xff,
                                        0x7f, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
    expect_memory_error((const char *)b, sizeof b, LUMIS_ERR_TRUNCATED);
    tu_write_file(tu_path("bigattr.exr"), b, sizeof b);
    expect_read_error(tu_path("bigattr.exr"), LUMIS_ERR_TRUNCATED);
    /* A negative size is a malformed header. */
    unsigned char c[29];
    memcpy(c, b, sizeof c);
    c[20] = 0xff;
    expect_memory_error((const char *)c, sizeof c, LUMIS_ERR_BAD_HEADER);

    /* Found by fuzz_exr: a channel list declared one byte shorter than its entries. OpenEXR
     * reads a channel list to its terminator whatever its size says, so it and a walk by
     * the sizes part ways; OpenEXR then met an opaque attribute claiming 1.6 GB. */
    static const char chlist_short[] =
        "v/1\001\002\000\000\000channels\000chlist\0007\000\000\000"
        "B\000\001\000\000\000\000\000\000\000\001\000\000\000\001\000\000\000"
        "G\000\001\000\000\000\000\000\000\000\001\000\000\000\001\000\000\000"
        "R\377\000\001\000\000\000\000\000\000\000\001\000\000\000\001\000\000\000\000"
        "compression\000compression\000\001\000\000\000\006"
        "dataWindow\000box2i\000\020\000\000\000\000\000\000\000\000\000\000\000"
        "\017\000\000\000\007\000\000\000"
        "dispwWid\000h\000floa\031\364y\307\037}\347\340}";
    expect_memory_error(chlist_short, sizeof chlist_short - 1, LUMIS_ERR_BAD_HEADER);
    /* Found by fuzz_exr: a 194-byte file whose data window is 13762576 x 1793. OpenEXR
     * sizes its compressor's buffers when the file is opened (1.7 GB here), so the pixel
     * limit is checked on the header before OpenEXR reads it. */
    static const unsigned char wide[] = {
        0x76, 0x2f, 0x31, 0x01, 0x02, 0x00, 0x00, 0x00, 0x63, 0x68, 0x61, 0x6e, 0x6e, 0x65, 0x6c,
        0x73, 0x00, 0x63, 0x68, 0x6c, 0x69, 0x73, 0x74, 0x00, 0x37, 0x00, 0x00, 0x00, 0x42, 0x00,
        0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00,
        0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1d, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00,
        0x01, 0x00, 0x00, 0x00, 0x52, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x01,
        0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x00, 0x63, 0x6f, 0x6d, 0x70, 0x72, 0x65, 0x63,
        0x73, 0x69, 0x6f, 0x6e, 0x00, 0x63, 0x6f, 0x6d, 0x70, 0x72, 0x65, 0x73, 0x73, 0x69, 0x6f,
        0x6e, 0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x64, 0x61, 0x74, 0x61, 0x57, 0x69, 0x6e, 0x64,
        0x6f, 0x77, 0x00, 0x62, 0x6f, 0x78, 0x32, 0x69, 0x00, 0x10, 0x00, 0x00, 0x00, 0x00, 0x00,
        0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x0f, 0x00, 0xd2, 0x00, 0x00, 0x07, 0x00, 0x00, 0x00,
        0x64, 0x69, 0x73, 0x70, 0x77, 0x57, 0x69, 0x64, 0x74, 0x68, 0x00, 0x66, 0x6c, 0x6f, 0x61,
        0x74, 0x00, 0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x80, 0x3f, 0x00, 0x41, 0x08, 0x20, 0x82,
        0x08, 0x20, 0x82, 0x08, 0x20, 0x82, 0x08, 0x20, 0x82, 0x08, 0x20, 0x82, 0x08, 0x20};
    expect_memory_error((const char *)wide, sizeof wide, LUMIS_ERR_TOO_LARGE);
    /* A fixed-size type with another size: a box2i of 12 bytes. */
    unsigned char box[] = "v/1\001\002\000\000\000dataWindow\000box2i\000\014\000\000\000"
                          "\000\000\000\000\000\000\000\000\017\000\000\000\000";
    expect_memory_error((const char *)box, sizeof box - 1, LUMIS_ERR_BAD_HEADER);
    /* A preview of 1 x 2 pixels needs 8 + 8 bytes, and a float vector a multiple of 4
     * (OpenEXR's own preview check would throw later; the message says who caught it). */
    static const char preview[] = "v/1\001\002\000\000\000p\000preview\000\014\000\000\000"
                                  "\001\000\000\000\002\000\000\000\377\377\377\377\000";
    expect_memory_message(preview, sizeof preview - 1, LUMIS_ERR_BAD_HEADER,
                          "'p' of type 'preview' cannot have 12 bytes");
    static const char floats[] = "v/1\001\002\000\000\000f\000floatvector\000\006\000\000\000"
                                 "\000\000\200\077\000\000\000";
    expect_memory_message(floats, sizeof floats - 1, LUMIS_ERR_BAD_HEADER,
                          "'f' of type 'floatvector' cannot have 6 bytes");
    /* Tiles of 100000 x 100000 pixels are over the pixel limit before any are read. */
    static const char tiles[] = "v/1\001\002\002\000\000tiles\000tiledesc\000\011\000\000\000"
                                "\240\206\001\000\240\206\001\000\000\000";
    expect_memory_message(tiles, sizeof tiles - 1, LUMIS_ERR_TOO_LARGE,
                          "tile size 100000 x 100000");
}

static void exr_decodes_the_same_with_any_thread_count(void **state)
{
    (void)state;
    size_t n;
    lumis_image *img = sample_image(200, 100);
    lumis_write_options wo = {0};
    wo.exr_compression = LUMIS_EXR_PIZ;
    assert_int_equal(write_img(tu_path("mt.exr"), img, &wo), LUMIS_OK);
    unsigned char *b = tu_read_file(tu_path("mt.exr"), &n);
    for (int t = 0; t <= 4; t++) {
        lumis_read_options ro = {0};
        ro.threads = t;
        lumis_image *back = NULL;
        assert_int_equal(lumis_image_read_memory(b, n, LUMIS_FORMAT_AUTO, NULL, &ro, &back, NULL),
                         LUMIS_OK);
        assert_close(img, back, 0.0, 0.0);
        lumis_image_destroy(back);
    }
    free(b);
    lumis_image_destroy(img);
}

static void exr_size_is_checked_against_the_limit(void **state)
{
    (void)state;
    size_t n;
    unsigned char *b = exr_bytes(40, 20, LUMIS_EXR_NONE, 0, &n);
    lumis_read_options ro = {0};
    ro.max_pixels = 799;
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_read_memory(b, n, LUMIS_FORMAT_AUTO, NULL, &ro, &img, NULL),
                     LUMIS_ERR_TOO_LARGE);
    ro.max_pixels = 800;
    assert_int_equal(lumis_image_read_memory(b, n, LUMIS_FORMAT_AUTO, NULL, &ro, &img, NULL),
                     LUMIS_OK);
    lumis_image_destroy(img);
    free(b);
}

/* A file of 240 bytes whose one row of 3.3 million pixels under a 32-line compression would
 * make OpenEXR allocate 838 MB before a pixel is read (found by fuzz_exr): refused from the
 * header, within the pixel limit. */
static void exr_block_buffers_are_bounded(void **state)
{
    (void)state;
    static const unsigned char b[] = {
        118, 47,  49,  1,   2,   0,  0,   0,   99,  104, 97,  110, 110, 101, 108, 115, 0,   99,
        104, 108, 105, 115, 116, 0,  55,  0,   0,   0,   66,  0,   1,   0,   0,   0,   0,   0,
        0,   0,   1,   0,   0,   0,  1,   0,   0,   0,   46,  0,   0,   0,   0,   0,   0,   0,
        0,   96,  1,   0,   0,   0,  1,   0,   0,   0,   82,  0,   1,   0,   0,   0,   0,   0,
        0,   0,   1,   0,   0,   0,  1,   0,   0,   0,   0,   99,  111, 109, 112, 114, 101, 115,
        115, 105, 111, 110, 0,   99, 111, 109, 112, 114, 101, 115, 115, 105, 111, 110, 0,   1,
        0,   0,   0,   6,   100, 97, 116, 97,  87,  105, 110, 100, 111, 119, 0,   98,  111, 120,
        50,  105, 0,   16,  0,   0,  0,   0,   0,   0,   0,   0,   0,   0,   0,   0,   0,   50,
        0,   0,   0,   0,   0,   0,  0,   0,   0,   0,   0,   0,   0,   0,   0,   0,   0,   0,
        0,   0,   0,   0,   0,   0,  0,   0,   0,   0,   0,   0,   0,   0,   0,   0,   0,   0,
        0,   0,   0,   0,   0,   0,  0,   0,   0,   0,   0,   0,   0,   0,   0,   0,   0,   0,
        0,   0,   0,   0,   0,   0,  0,   0,   0,   255, 253, 245, 142, 239, 46,  192, 152, 2,
        8,   32,  130, 130, 8,   32, 130, 8,   32,  130, 8,   32};
    lumis_image *img = NULL;
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_read_options ro = {0};
    ro.errors = sink.sink;
    assert_int_equal(
        lumis_image_read_memory(b, sizeof b, LUMIS_FORMAT_AUTO, "oom.exr", &ro, &img, NULL),
        LUMIS_ERR_TOO_LARGE);
    assert_null(img);
    assert_non_null(strstr(sink.last, "limit 256 MB"));
}

static void hdr_headers(void **state)
{
    (void)state;
    const lumis_status TR = LUMIS_ERR_TRUNCATED, BH = LUMIS_ERR_BAD_HEADER;
    struct {
        const char *text;
        lumis_status want;
    } cases[] = {
        {"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n", TR}, /* header never ends */
        {"#?RADIANCE\n\n", TR},                       /* no resolution */
        {"#?RADIANCE\n\n-Y 2 +X", TR},                /* no newline */
        {"#?RADIANCE\n\nhello world\n", BH},          /* garbage */
        {"#?RADIANCE\n\n-Y two +X 4\n", BH},
        {"#?RADIANCE\n\n+X 4 -Y 2\n", LUMIS_ERR_UNSUPPORTED}, /* column-major */
        {"#?RADIANCE\nFORMAT=16-bit_funny\n\n-Y 1 +X 1\nABCD", LUMIS_ERR_UNSUPPORTED},
        {"#?RADIANCE\nEXPOSURE=-2\n\n-Y 1 +X 1\nABCD", BH},
        {"#?RADIANCE\n\n-Y -5 +X 10\n", LUMIS_ERR_BAD_DIMENSIONS},
        {"#?RADIANCE\n\n-Y 0 +X 10\n", LUMIS_ERR_BAD_DIMENSIONS},
        {"#?RADIANCE\n\n-Y 100000000 +X 100000000\n", LUMIS_ERR_TOO_LARGE},
        {"#?RADIANCE\n\n-Y 99999999999999999999999 +X 1\n", LUMIS_ERR_TOO_LARGE},
        {"#?RADIANCE\n\n-Y 4294967297 +X 4294967297\n",
         LUMIS_ERR_TOO_LARGE},                           /* wraps to 1 x 1 in 32 bits */
        {"#?RADIANCE\n\n-Y 1000 +X 1000\nABCDABCD", TR}, /* far more pixels than data */
        {"#?RADIANCE\n\n-Y 2 +X 2\nABCDABCDABCD", TR},   /* one pixel short */
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++)
        expect_memory_error(cases[k].text, strlen(cases[k].text), cases[k].want);
}

/* RGBE holds values below 2^127: at or above it the exponent byte wrapped to 0 and a sun
 * of 3e38 was written as black.  Such values are clamped to RGBE's largest (1.69e38). */
/* A scanline of 300 pixels of noise: stb's RLE writer cuts its literal stretches into runs
 * of 128 bytes, the largest literal count, which a reader that took 128 for a repeat
 * would decode as one byte repeated.  Read back within RGBE's precision. */
static void hdr_long_literal_runs_round_trip(void **state)
{
    (void)state;
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(300, 3, &img), LUMIS_OK);
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 9, 1);
    for (size_t q = 0; q < (size_t)300 * 3 * 3; q++)
        img->pixels[q] = 0.01f + 10.0f * lumis_pcg32_float(&rng);
    const char *path = tu_path("noise.hdr");
    assert_int_equal(lumis_image_write(path, img, NULL), LUMIS_OK);
    lumis_image *back = NULL;
    assert_int_equal(lumis_image_read(path, NULL, &back, NULL), LUMIS_OK);
    for (size_t q = 0; q < (size_t)300 * 3; q++) {
        const float *a = img->pixels + 3 * q, *b = back->pixels + 3 * q;
        const float m = fmaxf(a[0], fmaxf(a[1], a[2]));
        for (int c = 0; c < 3; c++)
            if (!(fabsf(a[c] - b[c]) <= m / 128))
                fail_msg("pixel %zu channel %d: wrote %g, read %g", q, c, a[c], b[c]);
    }
    lumis_image_destroy(back);
    lumis_image_destroy(img);
}

static void hdr_writes_huge_values_clamped(void **state)
{
    (void)state;
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(4, 1, &img), LUMIS_OK);
    const float v[4] = {1.0f, 1e38f, 3e38f, INFINITY};
    for (int k = 0; k < 4; k++)
        img->pixels[3 * k] = img->pixels[3 * k + 1] = img->pixels[3 * k + 2] = v[k];
    const char *path = tu_path("huge.hdr");
    assert_int_equal(lumis_image_write(path, img, NULL), LUMIS_OK);
    lumis_image *back = NULL;
    assert_int_equal(lumis_image_read(path, NULL, &back, NULL), LUMIS_OK);
    for (int k = 0; k < 4; k++) {
        const double got = back->pixels[3 * k], want = v[k] < 0x1.fep126f ? v[k] : 0x1.fep126f;
        if (!(fabs(got - want) <= want / 128))
            fail_msg("pixel %d: wrote %g, read %g", k, v[k], got);
    }
    lumis_image_destroy(back);
    lumis_image_destroy(img);
}

static void hdr_scanline_variants(void **state)
{
    (void)state;
    /* Flat, bottom-up (+Y) and mirrored (-X) 2 x 2 images; EXPOSURE halves the values. */
    const unsigned char px[16] = {128, 0, 0,   129, 0,   128, 0,   129,
                                  0,   0, 128, 129, 128, 128, 128, 129};
    const char *heads[] = {"#?RADIANCE\nEXPOSURE=2\n\n-Y 2 +X 2\n", "#?RGBE\n\n+Y 2 +X 2\n",
                           "#?RADIANCE\n\n-Y 2 -X 2\n"};
    for (int k = 0; k < 3; k++) {
        unsigned char buf[128];
        size_t hl = strlen(heads[k]);
        memcpy(buf, heads[k], hl);
        memcpy(buf + hl, px, 16);
        lumis_image *img = NULL;
        assert_int_equal(
            lumis_image_read_memory(buf, hl + 16, LUMIS_FORMAT_AUTO, NULL, NULL, &img, NULL),
            LUMIS_OK);
        /* (128 + 0.5) / 256 * 2^(129 - 128) = 1.00390625; the empty channels read 0.5/256*2. */
        float big = k == 0 ? 0.501953125f : 1.00390625f;
        int first = k == 1 ? 2 : (k == 2 ? 1 : 0); /* where file pixel 0 lands */
        assert_true(fabsf(img->pixels[3 * first] - big) < 1e-6f);
        assert_true(img->pixels[3 * first + 1] < 0.01f);
        lumis_image_destroy(img);
    }
    /* Old-style RLE: a pixel then (1,1,1,3) repeats it three times. */
    const char *head = "#?RADIANCE\n\n-Y 1 +X 4\n";
    unsigned char buf[64];
    size_t hl = strlen(head);
    memcpy(buf, head, hl);
    const unsigned char rle[8] = {10, 20, 30, 128, 1, 1, 1, 3};
    memcpy(buf + hl, rle, 8);
    lumis_image *img = NULL;
    assert_int_equal(
        lumis_image_read_memory(buf, hl + 8, LUMIS_FORMAT_AUTO, NULL, NULL, &img, NULL), LUMIS_OK);
    for (int x = 1; x < 4; x++) assert_true(img->pixels[3 * x + 1] == img->pixels[1]);
    lumis_image_destroy(img);
    /* A run marker first, or a run past the end of the line, is corrupt. */
    const unsigned char bad1[8] = {1, 1, 1, 3, 10, 20, 30, 128};
    memcpy(buf + hl, bad1, 8);
    expect_memory_error((const char *)buf, hl + 8, LUMIS_ERR_CORRUPT);
    const unsigned char bad2[8] = {10, 20, 30, 128, 1, 1, 1, 9};
    memcpy(buf + hl, bad2, 8);
    expect_memory_error((const char *)buf, hl + 8, LUMIS_ERR_CORRUPT);
    /* New-style RLE with a run overflowing the scanline, and with a wrong width. */
    head = "#?RADIANCE\n\n-Y 1 +X 8\n";
    hl = strlen(head);
    memcpy(buf, head, hl);
    const unsigned char bad3[8] = {2, 2, 0, 8, 128 + 9, 7, 0, 0};
    memcpy(buf + hl, bad3, 8);
    expect_memory_error((const char *)buf, hl + 8, LUMIS_ERR_CORRUPT);
    const unsigned char bad4[8] = {2, 2, 0, 9, 128 + 8, 7, 0, 0};
    memcpy(buf + hl, bad4, 8);
    expect_memory_error((const char *)buf, hl + 8, LUMIS_ERR_CORRUPT);
    const unsigned char short5[6] = {2, 2, 0, 8, 128 + 8, 7};
    memcpy(buf + hl, short5, 6);
    expect_memory_error((const char *)buf, hl + 6, LUMIS_ERR_TRUNCATED);
}

static void pfm_headers(void **state)
{
    (void)state;
    struct {
        const char *text;
        lumis_status want;
    } cases[] = {
        {"PF\n", LUMIS_ERR_TRUNCATED},
        {"PF\n4 4\n", LUMIS_ERR_TRUNCATED},
        {"PF\nfour 4\n-1.0\n", LUMIS_ERR_BAD_HEADER},
        {"PF\n4 4\nscale\n", LUMIS_ERR_BAD_HEADER},
        {"PF\n4 4\n0.0\n", LUMIS_ERR_BAD_HEADER},
        {"PF\n-4 4\n-1.0\n", LUMIS_ERR_BAD_DIMENSIONS},
        {"PF\n4 0\n-1.0\n", LUMIS_ERR_BAD_DIMENSIONS},
        {"PF\n100000 100000\n-1.0\n", LUMIS_ERR_TOO_LARGE},
        {"PF\n99999999999999999999999 1\n-1.0\n", LUMIS_ERR_TOO_LARGE},
        {"PF\n4294967297 4294967297\n-1.0\n", LUMIS_ERR_TOO_LARGE},
        {"PF\n2 2\n-1.0\n0123456789", LUMIS_ERR_TRUNCATED}, /* 48 bytes needed */
        {"PF\n1000 1000\n-1.0\n0123", LUMIS_ERR_TRUNCATED},
        {"PFX\n", LUMIS_ERR_UNKNOWN_FORMAT},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++)
        expect_memory_error(cases[k].text, strlen(cases[k].text), cases[k].want);
}

/* ---- writing ------------------------------------------------------------------------ */

static void unwritable_outputs_fail_cleanly(void **state)
{
    (void)state;
    lumis_image *img = sample_image(8, 4);
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_write_options wo = {0};
    wo.errors = sink.sink;
    const char *formats[] = {"exr", "hdr", "pfm", "png"};
    for (int k = 0; k < 4; k++) {
        char path[512];
        snprintf(path, sizeof path, "%s/no/such/folder/out.%s", tu_tmpdir(), formats[k]);
        assert_int_equal(lumis_image_write(path, img, &wo), LUMIS_ERR_WRITE);
        assert_non_null(strstr(sink.last, path));
    }
    assert_int_equal(lumis_image_write(tu_path("out.jpg"), img, &wo), LUMIS_ERR_UNKNOWN_FORMAT);
    assert_int_equal(lumis_image_write(tu_path("out"), img, &wo), LUMIS_ERR_UNKNOWN_FORMAT);
    wo.exposure_ev = NAN;
    assert_int_equal(lumis_image_write(tu_path("out.png"), img, &wo), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_image_write(NULL, img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    /* Writing into a folder path (EISDIR at rename) fails and leaves nothing behind. */
    wo.exposure_ev = 0.0f;
    assert_int_equal(lumis_image_write(tu_tmpdir(), img, &wo), LUMIS_ERR_UNKNOWN_FORMAT);
    lumis_image_destroy(img);
}

/* A write that fails half-way (file size limit) leaves the old file and no temp file. */
static void failed_writes_leave_the_old_file(void **state)
{
    (void)state;
    const char *formats[] = {"exr", "hdr", "pfm", "png"};
    for (int k = 0; k < 4; k++) {
        char name[64];
        snprintf(name, sizeof name, "keep.%s", formats[k]);
        const char *path = tu_path(name);
        tu_write_file(path, "old contents", 12);
        pid_t pid = fork();
        assert_true(pid >= 0);
        if (pid == 0) {
            signal(SIGXFSZ, SIG_IGN);
            struct rlimit rl = {4096, 4096};
            setrlimit(RLIMIT_FSIZE, &rl);
            /* Noise in [0, 1): far more than 4 KiB in any format, PNG included. */
            lumis_image *img = sample_image(300, 200);
            lumis_pcg32 rng;
            lumis_pcg32_seed(&rng, 5, 5);
            for (size_t q = 0; q < (size_t)300 * 200 * 3; q++)
                img->pixels[q] = lumis_pcg32_float(&rng);
            lumis_status st = lumis_image_write(path, img, NULL);
            _exit(st == LUMIS_ERR_WRITE ? 0 : 10 + (int)st);
        }
        int status;
        waitpid(pid, &status, 0);
        assert_true(WIFEXITED(status));
        if (WEXITSTATUS(status) != 0) fail_msg("%s: status %d", name, WEXITSTATUS(status) - 10);
        size_t n;
        unsigned char *d = tu_read_file(path, &n);
        assert_int_equal(n, 12);
        assert_memory_equal(d, "old contents", 12);
        free(d);
    }
    assert_int_equal(tu_count_entries(tu_tmpdir(), ".keep."), 0);
}

/* An output that is a FIFO (or a device: /dev/null, a terminal) is written in place: a
 * rename over it would replace the node (as root, /dev/null became a regular file).  A
 * reader child takes what arrives; the FIFO must still be a FIFO afterwards. */
static void outputs_to_fifos_links_and_directories(void **state)
{
    (void)state;
    const char *fifo = tu_path("out.fifo");
    unlink(fifo);
    assert_int_equal(mkfifo(fifo, 0600), 0);
    const char text[] = "{\"lights\": []}\n";
    for (int k = 0; k < 2; k++) { /* text, then an image (PFM: a stream, no seeking) */
        int pipefd[2];
        assert_int_equal(pipe(pipefd), 0);
        pid_t pid = fork();
        assert_true(pid >= 0);
        if (pid == 0) { /* the reader: counts the bytes, gives up after 10 s */
            alarm(10);
            close(pipefd[0]);
            FILE *f = fopen(fifo, "rb");
            long n = 0;
            while (f && fgetc(f) != EOF) n++;
            if (write(pipefd[1], &n, sizeof n) != (ssize_t)sizeof n) _exit(2);
            _exit(0);
        }
        close(pipefd[1]);
        lumis_status st;
        long want;
        if (k == 0) {
            st = lumis_write_text(fifo, text, sizeof text - 1, NULL);
            want = (long)sizeof text - 1;
        } else {
            lumis_image *img = sample_image(8, 4);
            lumis_write_options o = {0};
            o.format = LUMIS_FORMAT_PFM;
            st = lumis_image_write(fifo, img, &o);
            lumis_image_destroy(img);
            want = -1;
        }
        /* a reader still waiting (a writer that renamed instead) is released */
        const int fd = open(fifo, O_WRONLY | O_NONBLOCK);
        if (fd >= 0) close(fd);
        long got = -2;
        if (read(pipefd[0], &got, sizeof got) != (ssize_t)sizeof got) got = -2;
        close(pipefd[0]);
        int status;
        waitpid(pid, &status, 0);
        assert_int_equal(st, LUMIS_OK);
        struct stat sb;
        assert_int_equal(stat(fifo, &sb), 0);
        if (!S_ISFIFO(sb.st_mode)) fail_msg("write %d replaced the FIFO with a file", k);
        if (want >= 0)
            assert_int_equal(got, want);
        else
            assert_true(got > 8 * 4 * 3 * 4);
    }
    unlink(fifo);
    /* A symbolic link: its target is replaced, the link stays a link. */
    const char *target = tu_path("linked.json"), *link = tu_path("link.json");
    tu_write_file(target, "old", 3);
    unlink(link);
    assert_int_equal(symlink(target, link), 0);
    assert_int_equal(lumis_write_text(link, text, sizeof text - 1, NULL), LUMIS_OK);
    struct stat lb;
    assert_int_equal(lstat(link, &lb), 0);
    assert_true(S_ISLNK(lb.st_mode));
    size_t n;
    char *d = (char *)tu_read_file(target, &n);
    assert_int_equal(n, sizeof text - 1);
    free(d);
    /* A directory is an error, and stays a directory. */
    tu_sink sink;
    tu_sink_init(&sink);
    assert_int_equal(lumis_write_text(tu_tmpdir(), text, 3, &sink.sink), LUMIS_ERR_WRITE);
    assert_non_null(strstr(sink.last, "is a directory"));
}

/* An interrupted program removes its writes' temporary files: what its SIGINT handler
 * calls (lumis_io_remove_partial_outputs) removes the hidden .NAME.XXXXXX of a write in
 * progress, and the write then fails instead of renaming nothing over the output. */
static void partial_outputs_are_removed_on_request(void **state)
{
    (void)state;
    const char *path = tu_path("partial.json");
    tu_write_file(path, "old", 3);
    lumis__atomic_file af;
    assert_int_equal(lumis__atomic_begin(&af, path, NULL), LUMIS_OK);
    fputs("half of a", af.f);
    assert_int_equal(tu_count_entries(tu_tmpdir(), ".partial.json."), 1);
    lumis_io_remove_partial_outputs();
    assert_int_equal(tu_count_entries(tu_tmpdir(), ".partial.json."), 0);
    assert_int_not_equal(lumis__atomic_end(&af, LUMIS_OK, NULL), LUMIS_OK);
    size_t n;
    char *d = (char *)tu_read_file(path, &n);
    assert_int_equal(n, 3);
    free(d);
}

static void format_names_and_detection(void **state)
{
    (void)state;
    assert_int_equal(lumis_format_from_path("a/b.EXR"), LUMIS_FORMAT_EXR);
    assert_int_equal(lumis_format_from_path("x.pic"), LUMIS_FORMAT_HDR);
    assert_int_equal(lumis_format_from_path("x.pfm"), LUMIS_FORMAT_PFM);
    assert_int_equal(lumis_format_from_path("x.png"), LUMIS_FORMAT_PNG);
    assert_int_equal(lumis_format_from_path("dir.exr/file"), LUMIS_FORMAT_AUTO);
    assert_int_equal(lumis_format_from_path(NULL), LUMIS_FORMAT_AUTO);
    assert_string_equal(lumis_format_name(LUMIS_FORMAT_PFM), "pfm");
    assert_int_equal(lumis_format_from_magic("#?RADIANCE", 10), LUMIS_FORMAT_HDR);
    assert_int_equal(lumis_format_from_magic("Pf\n", 3), LUMIS_FORMAT_PFM);
    assert_int_equal(lumis_format_from_magic("v/1\x01", 4), LUMIS_FORMAT_EXR);
    /* every byte of each magic matters, and so does its length */
    static const struct {
        const char *bytes;
        size_t n;
        lumis_file_format want;
    } magic[] = {
        {"v/1\x02", 4, LUMIS_FORMAT_AUTO},
        {"v/2\x01", 4, LUMIS_FORMAT_AUTO},
        {"v.1\x01", 4, LUMIS_FORMAT_AUTO},
        {"w/1\x01", 4, LUMIS_FORMAT_AUTO},
        {"v/1\x01", 3, LUMIS_FORMAT_AUTO},
        {"#!", 2, LUMIS_FORMAT_AUTO},
        {"#?", 1, LUMIS_FORMAT_AUTO},
        {"x?", 2, LUMIS_FORMAT_AUTO},
        {"#?", 2, LUMIS_FORMAT_HDR},
        {"PF\r", 3, LUMIS_FORMAT_PFM},
        {"PF ", 3, LUMIS_FORMAT_PFM},
        {"Pf\t", 3, LUMIS_FORMAT_PFM},
        {"PF5", 3, LUMIS_FORMAT_AUTO},
        {"PG\n", 3, LUMIS_FORMAT_AUTO},
        {"QF\n", 3, LUMIS_FORMAT_AUTO},
        {"PF\n", 2, LUMIS_FORMAT_AUTO},
        {"\x89PNG\r\n\x1a\n", 8, LUMIS_FORMAT_PNG},
        {"\x89PNG\r\n\x1a\n", 7, LUMIS_FORMAT_AUTO},
        {"", 0, LUMIS_FORMAT_AUTO},
    };
    for (size_t k = 0; k < sizeof magic / sizeof magic[0]; k++)
        if (lumis_format_from_magic(magic[k].bytes, magic[k].n) != magic[k].want)
            fail_msg("magic %zu: %d, want %d", k,
                     (int)lumis_format_from_magic(magic[k].bytes, magic[k].n), (int)magic[k].want);
    lumis_exr_compression c;
    assert_int_equal(lumis_exr_compression_from_name("dwab", &c), LUMIS_OK);
    assert_int_equal(c, LUMIS_EXR_DWAB);
    assert_string_equal(lumis_exr_compression_name(LUMIS_EXR_PIZ), "piz");
    assert_int_equal(lumis_exr_compression_from_name("lzma", &c), LUMIS_ERR_INVALID_ARGUMENT);
}

/* Every EXPOSURE line multiplies the stored values (Radiance's rule): two of 2 and 4 are
 * undone by 8.  An XYZE file's equal-energy white X = Y = Z = v is linear Rec. 709 RGB
 * v (1.2047843, 0.9483008, 0.9088427). */
static void hdr_exposures_multiply_and_xyze_converts(void **state)
{
    (void)state;
    const unsigned char px[4] = {128, 128, 128, 129}; /* (128 + 0.5) / 256 * 2 each */
    const float v = 1.00390625f;
    const char *heads[] = {"#?RADIANCE\nEXPOSURE=2\nEXPOSURE=4\n\n-Y 1 +X 1\n",
                           "#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\n"};
    const float want[2][3] = {{v / 8, v / 8, v / 8},
                              {v * 1.2047843f, v * 0.9483008f, v * 0.9088427f}};
    for (int k = 0; k < 2; k++) {
        unsigned char buf[128];
        size_t hl = strlen(heads[k]);
        memcpy(buf, heads[k], hl);
        memcpy(buf + hl, px, 4);
        lumis_image *img = NULL;
        assert_int_equal(
            lumis_image_read_memory(buf, hl + 4, LUMIS_FORMAT_AUTO, NULL, NULL, &img, NULL),
            LUMIS_OK);
        for (int c = 0; c < 3; c++)
            if (!(fabsf(img->pixels[c] - want[k][c]) < 1e-5f))
                fail_msg("%s: channel %d reads %g, want %g", k ? "XYZE" : "two EXPOSUREs", c,
                         img->pixels[c], want[k][c]);
        lumis_image_destroy(img);
    }
}

/* Consecutive old-style run markers scale by 256 each: a pixel, (1,1,1,1) and (1,1,1,1)
 * make 1 + 1 + 256 = 258 pixels. */
static void hdr_consecutive_old_style_runs(void **state)
{
    (void)state;
    const char *head = "#?RADIANCE\n\n-Y 1 +X 258\n";
    const unsigned char data[12] = {10, 20, 30, 128, 1, 1, 1, 1, 1, 1, 1, 1};
    unsigned char buf[64];
    size_t hl = strlen(head);
    memcpy(buf, head, hl);
    memcpy(buf + hl, data, sizeof data);
    lumis_image *img = NULL;
    assert_int_equal(
        lumis_image_read_memory(buf, hl + sizeof data, LUMIS_FORMAT_AUTO, NULL, NULL, &img, NULL),
        LUMIS_OK);
    for (int x = 1; x < 258; x++)
        for (int c = 0; c < 3; c++) assert_true(img->pixels[3 * x + c] == img->pixels[c]);
    assert_true(img->pixels[0] > 0.0f);
    lumis_image_destroy(img);
}

/* A NaN is written as black, like the other readers' replacement (not as RGBE's largest
 * value, where a value too large to hold goes). */
static void hdr_writes_nan_as_black(void **state)
{
    (void)state;
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(2, 1, &img), LUMIS_OK);
    const float v[6] = {NAN, 1.0f, 1.0f, 3e38f, 1.0f, 1.0f};
    memcpy(img->pixels, v, sizeof v);
    const char *path = tu_path("nan.hdr");
    assert_int_equal(lumis_image_write(path, img, NULL), LUMIS_OK);
    lumis_image *back = NULL;
    assert_int_equal(lumis_image_read(path, NULL, &back, NULL), LUMIS_OK);
    /* 0 in a pixel whose largest channel is 1: the mantissa's centre, 0.5 / 128. */
    if (!(back->pixels[0] < 0.01f)) fail_msg("NaN written as %g", back->pixels[0]);
    assert_true(back->pixels[3] > 1e38f);
    lumis_image_destroy(back);
    lumis_image_destroy(img);
}

/* A grey EXR (one Y channel; tests/data/grey-y.exr, 3 x 2, uncompressed float: 1 2 3 / 4 5
 * 0.25) reads as Y in every channel (it read as (0, 0, Y): blue only). */
static void exr_grey_reads_into_every_channel(void **state)
{
    (void)state;
    char path[1024];
    snprintf(path, sizeof path, "%s/tests/data/grey-y.exr", LUMIS_SOURCE_DIR);
    lumis_image *img = NULL;
    lumis_read_info info;
    assert_int_equal(lumis_image_read(path, NULL, &img, &info), LUMIS_OK);
    assert_true(info.grey);
    assert_int_equal(img->width, 3);
    assert_int_equal(img->height, 2);
    const float y[6] = {1, 2, 3, 4, 5, 0.25f};
    for (int k = 0; k < 6; k++)
        for (int c = 0; c < 3; c++)
            if (img->pixels[3 * k + c] != y[k])
                fail_msg("pixel %d channel %d: %g, not %g", k, c, img->pixels[3 * k + c], y[k]);
    lumis_image_destroy(img);
}

/* The half-float EXR writer clamps what half cannot hold to 65504 and writes NaN as 0 (the
 * clamp alone wrote NaN as 65504, the brightest half value). */
static void exr_half_writes_nan_as_black(void **state)
{
    (void)state;
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(2, 1, &img), LUMIS_OK);
    const float v[6] = {NAN, 1.0f, 2.0f, 1e9f, INFINITY, 0.5f};
    memcpy(img->pixels, v, sizeof v);
    const char *path = tu_path("nan-half.exr");
    lumis_write_options wo = {0};
    wo.exr_half = 1;
    assert_int_equal(lumis_image_write(path, img, &wo), LUMIS_OK);
    lumis_image *back = NULL;
    lumis_read_info info;
    assert_int_equal(lumis_image_read(path, NULL, &back, &info), LUMIS_OK);
    const float want[6] = {0.0f, 1.0f, 2.0f, 65504.0f, 65504.0f, 0.5f};
    for (int k = 0; k < 6; k++)
        if (back->pixels[k] != want[k])
            fail_msg("value %d: %g, not %g", k, back->pixels[k], want[k]);
    lumis_image_destroy(back);
    lumis_image_destroy(img);
}

/* The sRGB curve near black, both ways: linear 0.01 is past the encoder's linear toe
 * (0.0031308) and encodes to 25, not 12.92 * 0.01 * 255 = 33; code 10 is inside the
 * decoder's toe (10 / 255 <= 0.04045) and decodes to 10 / 255 / 12.92. */
static void png_srgb_curve_near_black(void **state)
{
    (void)state;
    lumis_image *img = NULL;
    assert_int_equal(lumis_image_create(2, 1, &img), LUMIS_OK);
    const float dark = (float)(10.0 / 255.0 / 12.92);
    const float v[6] = {0.01f, 0.01f, 0.01f, dark, dark, dark};
    memcpy(img->pixels, v, sizeof v);
    assert_int_equal(write_img(tu_path("dark.png"), img, NULL), LUMIS_OK);
    int w, h, n;
    unsigned char *px = stbi_load(tu_path("dark.png"), &w, &h, &n, 3);
    assert_non_null(px);
    assert_int_equal(px[0], 25);
    assert_int_equal(px[3], 10);
    stbi_image_free(px);
    lumis_image *back = read_ok(tu_path("dark.png"), NULL);
    if (!(fabsf(back->pixels[3] - dark) < 1e-6f * dark))
        fail_msg("code 10 decodes to %.9g, want %.9g", back->pixels[3], dark);
    lumis_image_destroy(back);
    lumis_image_destroy(img);
}

/* "studio:WxH" and "sky:WxH" make maps of that width and height; a file whose name only
 * starts like one ("studio_key.pfm") is read as the file. */
static void map_specs_name_sizes_and_files(void **state)
{
    (void)state;
    lumis_image *img = NULL;
    assert_int_equal(lumis_map_read("studio:64x16", NULL, &img, NULL), LUMIS_OK);
    assert_int_equal(img->width, 64);
    assert_int_equal(img->height, 16);
    lumis_image_destroy(img);
    assert_int_equal(lumis_map_read("sky:24x6", NULL, &img, NULL), LUMIS_OK);
    assert_int_equal(img->width, 24);
    assert_int_equal(img->height, 6);
    lumis_image_destroy(img);
    assert_int_equal(lumis_map_read("sky:24", NULL, &img, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    assert_null(img);

    lumis_image *file = sample_image(5, 3);
    assert_int_equal(write_img(tu_path("studio_key.pfm"), file, NULL), LUMIS_OK);
    char cwd[4096];
    assert_non_null(getcwd(cwd, sizeof cwd));
    assert_int_equal(chdir(tu_tmpdir()), 0);
    lumis_status st = lumis_map_read("studio_key.pfm", NULL, &img, NULL);
    assert_int_equal(chdir(cwd), 0);
    assert_int_equal(st, LUMIS_OK);
    assert_close(file, img, 0.0, 0.0);
    lumis_image_destroy(img);
    lumis_image_destroy(file);
}

/* A glTF directional light shines along its node's -Z turned by the rotation: the
 * quaternion must take -Z to -dir (the light comes from dir), for every direction,
 * the two along Z included. */
static void gltf_rotation_turns_minus_z_into_minus_dir(void **state)
{
    (void)state;
    static const float dirs[][3] = {{1, 0, 0}, {0, 1, 0},  {0.3f, -0.5f, 0.8f}, {-2, 1, -0.5f},
                                    {0, 0, 1}, {0, 0, -1}, {0, -1, 0}};
    for (size_t k = 0; k < sizeof dirs / sizeof dirs[0]; k++) {
        lumis_vec3 d = {dirs[k][0], dirs[k][1], dirs[k][2]};
        double q[4];
        lumis__light_quaternion(d, q);
        /* v' = v + 2 w (u x v) + 2 u x (u x v), with u = q.xyz and v = (0, 0, -1). */
        const double v[3] = {0, 0, -1};
        double uv[3] = {q[1] * v[2] - q[2] * v[1], q[2] * v[0] - q[0] * v[2],
                        q[0] * v[1] - q[1] * v[0]};
        double uuv[3] = {q[1] * uv[2] - q[2] * uv[1], q[2] * uv[0] - q[0] * uv[2],
                         q[0] * uv[1] - q[1] * uv[0]};
        const double n = sqrt((double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z);
        const double want[3] = {-d.x / n, -d.y / n, -d.z / n};
        const double norm = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
        assert_true(fabs(norm - 1.0) < 1e-12);
        for (int c = 0; c < 3; c++) {
            const double got = v[c] + 2.0 * q[3] * uv[c] + 2.0 * uuv[c];
            if (!(fabs(got - want[c]) < 1e-9))
                fail_msg("dir %zu: -Z turns into component %d = %g, want %g", k, c, got, want[c]);
        }
    }
}

/* Where the consumers show a direction of their world on an equirectangular map, as the
 * map's column and row (row 0 the file's top row), written from their sources:
 * three.js (ShaderChunk common: equirectUv, u = atan(z, x) / 2 pi + 1/2, v = asin(y) / pi
 * + 1/2 counted from the bottom; HDRLoader's flipY puts the file's top row at v = 1), and
 * Blender: its glTF importer turns a glTF (x, y, z) into Blender's (x, -z, y), Cycles'
 * direction_to_equirectangular reads u = 1/2 - atan2(b_y, b_x) / 2 pi, v = 1 - acos(b_z) / pi
 * from the bottom. */
static const double PI_ = 3.14159265358979323846;

static void threejs_pixel(const double d[3], int w, int h, int *i, int *j)
{
    const double n = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double u = atan2(d[2], d[0]) / (2.0 * PI_) + 0.5;
    const double v = asin(fmax(-1.0, fmin(1.0, d[1] / n))) / PI_ + 0.5;
    u -= floor(u);
    *i = (int)floor(u * w) % w;
    *j = (int)floor((1.0 - v) * h);
}

static void blender_pixel(const double d[3], int w, int h, int *i, int *j)
{
    const double b[3] = {d[0], -d[2], d[1]};
    const double n = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    double u = 0.5 - atan2(b[1], b[0]) / (2.0 * PI_);
    const double v = 1.0 - acos(fmax(-1.0, fmin(1.0, b[2] / n))) / PI_;
    u -= floor(u);
    *i = (int)floor(u * w) % w;
    *j = (int)floor((1.0 - v) * h);
}

/* Every pixel centre of an odd-sized map: lumis's direction, as the engine frame exports it,
 * lands on the same pixel under three.js's and Blender's own mappings; lumis's frame lands
 * half a turn away (the bug of issue 35).  The names round-trip. */
static void export_frame_maps_pixels_where_consumers_show_them(void **state)
{
    (void)state;
    const int w = 37, h = 19;
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const lumis_vec3 d =
                lumis_equirect_to_dir((float)((i + 0.5) / w), (float)((j + 0.5) / h));
            const lumis_vec3 e = lumis_export_frame_dir(LUMIS_EXPORT_FRAME_ENGINE, d);
            const lumis_vec3 l = lumis_export_frame_dir(LUMIS_EXPORT_FRAME_LUMIS, d);
            const double de[3] = {e.x, e.y, e.z}, dl[3] = {l.x, l.y, l.z};
            int ti, tj, bi, bj, li, lj;
            threejs_pixel(de, w, h, &ti, &tj);
            blender_pixel(de, w, h, &bi, &bj);
            threejs_pixel(dl, w, h, &li, &lj);
            if (ti != i || tj != j || bi != i || bj != j)
                fail_msg("pixel (%d, %d): three.js shows the export at (%d, %d), Blender at "
                         "(%d, %d)",
                         i, j, ti, tj, bi, bj);
            /* lumis's own frame: the column half a turn away (w odd: the pixel centre lands
             * on a border between two columns, either) */
            assert_int_equal(lj, j);
            const int di = abs(li - i) < w - abs(li - i) ? abs(li - i) : w - abs(li - i);
            assert_true(di == w / 2);
        }
    lumis_export_frame f = LUMIS_EXPORT_FRAME_COUNT;
    assert_int_equal(lumis_export_frame_from_name("engine", &f), LUMIS_OK);
    assert_int_equal(f, LUMIS_EXPORT_FRAME_ENGINE);
    assert_int_equal(lumis_export_frame_from_name("lumis", &f), LUMIS_OK);
    assert_int_equal(f, LUMIS_EXPORT_FRAME_LUMIS);
    assert_int_equal(lumis_export_frame_from_name("three", &f), LUMIS_ERR_INVALID_ARGUMENT);
    assert_string_equal(lumis_export_frame_name(LUMIS_EXPORT_FRAME_COUNT), "unknown");
    const lumis_vec3 d = {0.25f, -0.5f, 0.75f};
    const lumis_vec3 u = lumis_export_frame_dir(LUMIS_EXPORT_FRAME_COUNT, d);
    assert_true(u.x == d.x && u.y == d.y && u.z == d.z);
}

/* A dim coloured sky, asymmetric in azimuth and elevation, with a sun on one pixel. */
enum { SUN_W = 37, SUN_H = 19, SUN_I = 29, SUN_J = 5 };
static float f_sun(int i, int j, int c)
{
    if (i == SUN_I && j == SUN_J) return c == 0 ? 4e4f : c == 1 ? 3e4f : 2e4f;
    return (float)(0.2 + 0.1 * c + 0.5 * (double)i / SUN_W + 0.3 * (double)(SUN_H - j) / SUN_H);
}

/* The glTF document of a .gltf or a .glb (its JSON chunk), parsed. */
static cJSON *read_gltf(const char *path)
{
    size_t n = 0;
    unsigned char *b = tu_read_file(path, &n);
    assert_non_null(b);
    cJSON *doc = NULL;
    if (n >= 20 && memcmp(b, "glTF", 4) == 0) {
        const uint32_t len =
            (uint32_t)b[12] | (uint32_t)b[13] << 8 | (uint32_t)b[14] << 16 | (uint32_t)b[15] << 24;
        assert_true(20 + (size_t)len <= n);
        doc = cJSON_ParseWithLength((const char *)b + 20, len);
    } else {
        doc = cJSON_ParseWithLength((const char *)b, n);
    }
    free(b);
    assert_non_null(doc);
    return doc;
}

static const cJSON *at(const cJSON *o, const char *path)
{
    /* "a.b.c": nested objects */
    char buf[128];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = strtok(buf, "."); p && o; p = strtok(NULL, "."))
        o = cJSON_GetObjectItemCaseSensitive(o, p);
    assert_non_null(o);
    return o;
}

/* The light of the largest intensity in a glTF document: the direction it comes from (its
 * node's rotation applied to +Z: a glTF light travels along the node's -Z). */
static void brightest_gltf_light(const cJSON *doc, double to_light[3])
{
    const cJSON *lights = at(doc, "extensions.KHR_lights_punctual.lights");
    const cJSON *nodes = at(doc, "nodes");
    double best = -1.0;
    for (int k = 0; k < cJSON_GetArraySize(nodes); k++) {
        const cJSON *node = cJSON_GetArrayItem(nodes, k);
        const int li = at(node, "extensions.KHR_lights_punctual.light")->valueint;
        const double in = at(cJSON_GetArrayItem(lights, li), "intensity")->valuedouble;
        if (in <= best) continue;
        best = in;
        double q[4];
        for (int c = 0; c < 4; c++) q[c] = cJSON_GetArrayItem(at(node, "rotation"), c)->valuedouble;
        /* R(q) (0, 0, 1): the third column of the rotation matrix */
        to_light[0] = 2.0 * (q[0] * q[2] + q[3] * q[1]);
        to_light[1] = 2.0 * (q[1] * q[2] - q[3] * q[0]);
        to_light[2] = 1.0 - 2.0 * (q[0] * q[0] + q[1] * q[1]);
    }
}

/* lumis_light_set_write_gltf and _json on a map with a sun at an odd pixel: the brightest
 * light of the file lands on the sun's pixel under three.js's and Blender's mappings (the
 * engine frame, default) or half a turn away (--frame lumis); the frame is recorded. */
static void exported_sun_lands_on_the_sun_pixel(void **state)
{
    (void)state;
    lumis_envmap *env = tu_envmap(SUN_W, SUN_H, f_sun, 0.0f, 0.0f);
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(env, "wu", 6, 1, NULL, NULL, &set), LUMIS_OK);
    static const char *const names[] = {"sun.gltf", "sun.glb"};
    for (int f = 0; f < LUMIS_EXPORT_FRAME_COUNT; f++)
        for (int n = 0; n < 2; n++) {
            lumis_light_export_options o = {0};
            o.frame = (lumis_export_frame)f;
            assert_int_equal(lumis_light_set_write_gltf(tu_path(names[n]), set, &o), LUMIS_OK);
            cJSON *doc = read_gltf(tu_path(names[n]));
            assert_string_equal(at(doc, "asset.extras.frame")->valuestring,
                                f == LUMIS_EXPORT_FRAME_ENGINE ? "engine" : "lumis");
            assert_non_null(
                strstr(at(doc, "asset.extras.frame_equirect")->valuestring,
                       f == LUMIS_EXPORT_FRAME_ENGINE ? "u = 1/2 along +x" : "u = 0 along +x"));
            double d[3];
            brightest_gltf_light(doc, d);
            cJSON_Delete(doc);
            int ti, tj, bi, bj;
            threejs_pixel(d, SUN_W, SUN_H, &ti, &tj);
            blender_pixel(d, SUN_W, SUN_H, &bi, &bj);
            const int want =
                f == LUMIS_EXPORT_FRAME_ENGINE ? SUN_I : (SUN_I + SUN_W / 2 + 1) % SUN_W;
            if (ti != want || tj != SUN_J || bi != want || bj != SUN_J)
                fail_msg("%s, frame %s: three.js shows the brightest light at (%d, %d), Blender "
                         "at (%d, %d); the sun is at (%d, %d)",
                         names[n], lumis_export_frame_name(o.frame), ti, tj, bi, bj, SUN_I, SUN_J);
        }
    /* the JSON: the same directions, and its frame */
    lumis_light_export_options o = {0};
    assert_int_equal(lumis_light_set_write_json(tu_path("sun.json"), set, &o), LUMIS_OK);
    cJSON *j = read_gltf(tu_path("sun.json"));
    assert_string_equal(at(j, "frame")->valuestring, "engine");
    const lumis_light *l = NULL;
    int count = 0;
    assert_int_equal(lumis_light_set_get(set, 0, &l, &count), LUMIS_OK);
    for (int k = 0; k < count; k++) {
        const cJSON *dir = at(cJSON_GetArrayItem(at(j, "lights"), k), "dir");
        assert_true(fabs(cJSON_GetArrayItem(dir, 0)->valuedouble + l[k].dir.x) < 1e-6);
        assert_true(fabs(cJSON_GetArrayItem(dir, 1)->valuedouble - l[k].dir.y) < 1e-6);
        assert_true(fabs(cJSON_GetArrayItem(dir, 2)->valuedouble + l[k].dir.z) < 1e-6);
    }
    cJSON_Delete(j);
    o.frame = LUMIS_EXPORT_FRAME_COUNT;
    assert_int_equal(lumis_light_set_write_json(tu_path("bad.json"), set, &o),
                     LUMIS_ERR_INVALID_ARGUMENT);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* An image sun exported with the residual's lights: it comes first, as a directional light of
 * kind "sun" where three.js and Blender show the sun's pixel, with its angular radius; the
 * file's powers add up to the map's (sun + residual == map). */
static void exported_image_sun_and_residual(void **state)
{
    (void)state;
    lumis_envmap *env = tu_envmap(SUN_W, SUN_H, f_sun, 0.0f, 0.0f);
    lumis_sun_desc sd = {0};
    sd.max_radius_deg = 20.0; /* pixels of 10 degrees */
    lumis_sun sun;
    lumis_envmap *res = NULL;
    assert_int_equal(lumis_sun_find(env, &sd, &sun, &res), LUMIS_OK);
    assert_int_equal(sun.found, 1);
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(res, "median-cut", 4, 1, NULL, NULL, &set), LUMIS_OK);
    lumis_light_export_options o = {0};
    o.sun = &sun;
    assert_int_equal(lumis_light_set_write_json(tu_path("isun.json"), set, &o), LUMIS_OK);
    cJSON *j = read_gltf(tu_path("isun.json"));
    assert_int_equal((int)at(j, "sun_index")->valuedouble, 0);
    const cJSON *lights = at(j, "lights");
    assert_int_equal(cJSON_GetArraySize(lights), 5);
    const cJSON *first = cJSON_GetArrayItem(lights, 0);
    assert_string_equal(at(first, "kind")->valuestring, "sun");
    assert_true(fabs(at(first, "angular_radius_rad")->valuedouble - sun.radius) < 1e-12);
    double d[3], total[3] = {0, 0, 0};
    for (int c = 0; c < 3; c++) d[c] = cJSON_GetArrayItem(at(first, "dir"), c)->valuedouble;
    int ti, tj, bi, bj;
    threejs_pixel(d, SUN_W, SUN_H, &ti, &tj);
    blender_pixel(d, SUN_W, SUN_H, &bi, &bj);
    assert_true(ti == SUN_I && tj == SUN_J && bi == SUN_I && bj == SUN_J);
    for (int k = 0; k < 5; k++)
        for (int c = 0; c < 3; c++)
            total[c] +=
                cJSON_GetArrayItem(at(cJSON_GetArrayItem(lights, k), "power"), c)->valuedouble;
    const lumis_rgb pm = lumis_envmap_power(env);
    assert_true(fabs(total[0] - pm.r) < 1e-5 * pm.r && fabs(total[1] - pm.g) < 1e-5 * pm.g &&
                fabs(total[2] - pm.b) < 1e-5 * pm.b);
    cJSON_Delete(j);
    assert_int_equal(lumis_light_set_write_gltf(tu_path("isun.gltf"), set, &o), LUMIS_OK);
    cJSON *g = read_gltf(tu_path("isun.gltf"));
    const cJSON *nodes = at(g, "nodes");
    assert_int_equal(cJSON_GetArraySize(nodes), 5);
    const cJSON *n0 = cJSON_GetArrayItem(nodes, 0);
    assert_string_equal(at(n0, "name")->valuestring, "sun");
    assert_true(fabs(at(n0, "extras")->child->valuedouble - sun.radius) < 1e-12);
    for (int k = 0; k < 5; k++)
        assert_int_equal(
            (int)at(cJSON_GetArrayItem(nodes, k), "extensions")->child->child->valuedouble, k);
    double bd[3];
    brightest_gltf_light(g, bd);
    threejs_pixel(bd, SUN_W, SUN_H, &ti, &tj);
    assert_true(ti == SUN_I && tj == SUN_J);
    cJSON_Delete(g);
    lumis_sun none = {0};
    o.sun = &none;
    assert_int_equal(lumis_light_set_write_json(tu_path("bad.json"), set, &o),
                     LUMIS_ERR_INVALID_ARGUMENT);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(res);
    lumis_envmap_destroy(env);
}

static uint32_t le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* A .glb is a binary glTF container (glTF 2.0, "GLB File Format Specification"): magic
 * "glTF", version 2, the file's length; one JSON chunk, its length a multiple of 4, padded
 * with spaces, holding the document the .gltf holds.  The container follows the name (any
 * case) unless given; any other name is refused and nothing is written. */
static void glb_is_a_binary_gltf_container(void **state)
{
    (void)state;
    lumis_envmap *env = tu_envmap(SUN_W, SUN_H, f_sun, 0.0f, 0.0f);
    lumis_light_set *set = NULL;
    assert_int_equal(lumis_lights_by_name(env, "median-cut", 5, 1, NULL, NULL, &set), LUMIS_OK);
    lumis_light_export_options o = {0};
    o.method = "median-cut";
    /* parameters 1 to 4 characters longer: the JSON's length takes every value mod 4 */
    static const char *const params[] = {"seed=3", "seed=33", "seed=333", "seed=3333"};
    size_t n = 0, padding = 0;
    unsigned char *b = NULL;
    for (int p = 0; p < 4; p++) {
        o.parameters = params[p];
        assert_int_equal(lumis_light_set_write_gltf(tu_path("c.GLB"), set, &o), LUMIS_OK);
        assert_int_equal(lumis_light_set_write_gltf(tu_path("c.gltf"), set, &o), LUMIS_OK);
        b = tu_read_file(tu_path("c.GLB"), &n);
        assert_non_null(b);
        assert_true(n >= 20 && n % 4 == 0);
        assert_memory_equal(b, "glTF", 4);
        assert_int_equal(le32(b + 4), 2);
        assert_int_equal(le32(b + 8), n);
        const uint32_t len = le32(b + 12);
        assert_int_equal(len % 4, 0);
        assert_int_equal(20 + (size_t)len, n); /* one chunk, no BIN chunk: no buffers */
        assert_memory_equal(b + 16, "JSON", 4);
        size_t end = 20 + len;
        while (end > 20 && b[end - 1] == ' ') end--;
        assert_true(end + 4 > 20 + (size_t)len); /* at most 3 bytes of padding */
        assert_int_equal(b[end - 1], '}');
        padding += 20 + len - end;
        cJSON *bin = cJSON_ParseWithLength((const char *)b + 20, len);
        free(b);
        cJSON *text = read_gltf(tu_path("c.gltf"));
        assert_non_null(bin);
        assert_true(cJSON_Compare(bin, text, 1));
        assert_int_equal(cJSON_GetArraySize(at(bin, "nodes")), 5);
        cJSON_Delete(bin);
        cJSON_Delete(text);
    }
    assert_int_equal(padding, 1 + 2 + 3); /* each residue once */

    /* a text .gltf starts with '{'; an explicit container wins over the name */
    b = tu_read_file(tu_path("c.gltf"), &n);
    assert_true(n > 0 && b[0] == '{');
    free(b);
    o.container = LUMIS_GLTF_BINARY;
    assert_int_equal(lumis_light_set_write_gltf(tu_path("c.bin"), set, &o), LUMIS_OK);
    b = tu_read_file(tu_path("c.bin"), &n);
    assert_true(n > 4 && memcmp(b, "glTF", 4) == 0);
    free(b);
    o.container = LUMIS_GLTF_TEXT;
    assert_int_equal(lumis_light_set_write_gltf(tu_path("c2.glb"), set, &o), LUMIS_OK);
    b = tu_read_file(tu_path("c2.glb"), &n);
    assert_true(n > 0 && b[0] == '{');
    free(b);
    /* neither .gltf nor .glb: refused, with a message naming the file, nothing written */
    o.container = LUMIS_GLTF_AUTO;
    tu_sink sink;
    tu_sink_init(&sink);
    o.errors = sink.sink;
    static const char *const bad[] = {"c.txt", "glb", "c.glb.json", "c.gltf/", "c."};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        const char *p = tu_path(bad[k]);
        assert_int_equal(lumis_light_set_write_gltf(p, set, &o), LUMIS_ERR_UNKNOWN_FORMAT);
        assert_non_null(strstr(sink.last, ".glb for binary"));
        struct stat sb;
        assert_int_not_equal(stat(p, &sb), 0);
    }
    o.container = LUMIS_GLTF_COUNT;
    assert_int_equal(lumis_light_set_write_gltf(tu_path("c3.glb"), set, &o),
                     LUMIS_ERR_UNKNOWN_FORMAT);
    lumis_light_set_destroy(set);
    lumis_envmap_destroy(env);
}

/* An output is an ordinary file, 0644 less the umask, not the 0600 of mkstemp's
 * temporary file it was renamed from. */
static void outputs_get_ordinary_permissions(void **state)
{
    (void)state;
    lumis_image *img = sample_image(2, 2);
    const char *path = tu_path("mode.pfm");
    unlink(path);
    assert_int_equal(write_img(path, img, NULL), LUMIS_OK);
    const mode_t mask = umask(022);
    umask(mask);
    struct stat sb;
    assert_int_equal(stat(path, &sb), 0);
    if ((sb.st_mode & 0777) != (0644 & ~mask))
        fail_msg("output mode %o, want %o", (unsigned)(sb.st_mode & 0777),
                 (unsigned)(0644 & ~mask));
    lumis_image_destroy(img);
}

/* A format asked for wins over the name's extension: "x.png" written as PFM is a PFM. */
static void explicit_format_wins_over_the_extension(void **state)
{
    (void)state;
    lumis_image *img = sample_image(3, 2);
    lumis_write_options wo = {0};
    wo.format = LUMIS_FORMAT_PFM;
    assert_int_equal(write_img(tu_path("named.png"), img, &wo), LUMIS_OK);
    size_t n;
    unsigned char *raw = tu_read_file(tu_path("named.png"), &n);
    assert_true(n > 3 && raw[0] == 'P' && raw[1] == 'F');
    free(raw);
    lumis_read_info info;
    lumis_image *back = read_ok(tu_path("named.png"), &info);
    assert_int_equal(info.format, LUMIS_FORMAT_PFM);
    assert_close(img, back, 0.0, 0.0);
    lumis_image_destroy(back);
    lumis_image_destroy(img);
}

/* Outputs named through descriptors and links: /dev/fd/N and /proc/self/fd/N are written
 * where the descriptor stands (a file opened for appending keeps what it had), a dangling
 * link creates its target and stays a link, a chain of links is followed, and malformed
 * descriptor names are ordinary (here unwritable) paths. */
static void outputs_through_descriptors_and_links(void **state)
{
    (void)state;
    char path[600], name[64], text[64];
    snprintf(path, sizeof path, "%s", tu_path("fd-target.txt"));
    FILE *f = fopen(path, "w+");
    assert_non_null(f);
    fputs("HEAD", f);
    fflush(f);
    const int fd = fileno(f);
    snprintf(name, sizeof name, "/dev/fd/%d", fd);
    assert_int_equal(lumis_write_text(name, "abc", 3, NULL), LUMIS_OK);
    snprintf(name, sizeof name, "/proc/self/fd/%d", fd);
    assert_int_equal(lumis_write_text(name, "de", 2, NULL), LUMIS_OK);
    fclose(f);
    size_t n = 0;
    unsigned char *got = tu_read_file(path, &n);
    assert_non_null(got);
    assert_int_equal(n, 9);
    assert_memory_equal(got, "HEADabcde", 9);
    free(got);
    assert_int_not_equal(lumis_write_text("/dev/fd/12abc", "x", 1, NULL), LUMIS_OK);
    assert_int_not_equal(lumis_write_text("/dev/fd/", "x", 1, NULL), LUMIS_OK);
    /* a dangling link, and a link to it: the target is made, both links stay links */
    char target[600], link1[600], link2[600];
    snprintf(target, sizeof target, "%s", tu_path("made-by-link.txt"));
    snprintf(link1, sizeof link1, "%s", tu_path("link1.txt"));
    snprintf(link2, sizeof link2, "%s", tu_path("link2.txt"));
    assert_int_equal(symlink("made-by-link.txt", link1), 0);
    assert_int_equal(symlink("link1.txt", link2), 0);
    assert_int_equal(lumis_write_text(link2, "through two links", 17, NULL), LUMIS_OK);
    got = tu_read_file(target, &n);
    assert_non_null(got);
    snprintf(text, sizeof text, "%.*s", (int)n, (const char *)got);
    assert_string_equal(text, "through two links");
    free(got);
    char where[600];
    assert_int_equal(lumis_output_target(link2, where, sizeof where), LUMIS_OK);
    assert_string_equal(where, target);
    assert_int_equal(lumis_output_target(link2, where, 8), LUMIS_ERR_INVALID_ARGUMENT);
    snprintf(name, sizeof name, "/dev/fd/%d", 1);
    assert_int_equal(lumis_output_target(name, where, sizeof where), LUMIS_OK);
    assert_string_equal(where, name); /* a descriptor: written in place */
    struct stat sb;
    assert_int_equal(lstat(link1, &sb), 0);
    assert_true(S_ISLNK(sb.st_mode));
    assert_int_equal(lstat(link2, &sb), 0);
    assert_true(S_ISLNK(sb.st_mode));
    /* a folder is refused, by name or through a link */
    assert_int_not_equal(lumis_write_text(tu_tmpdir(), "x", 1, NULL), LUMIS_OK);
    /* no path, buffer or room; no text */
    assert_int_equal(lumis_output_target(NULL, where, sizeof where), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_output_target(link2, NULL, sizeof where), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_output_target(link2, where, 0), LUMIS_ERR_INVALID_ARGUMENT);
    tu_sink sink;
    tu_sink_init(&sink);
    assert_int_equal(lumis_write_text(target, NULL, 3, &sink.sink), LUMIS_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(sink.last, "no text to write"));
    /* stderr, and a link to it by an absolute path: a descriptor, the path as given */
    assert_int_equal(lumis_output_target("/dev/stderr", where, sizeof where), LUMIS_OK);
    assert_string_equal(where, "/dev/stderr");
    char to_err[600];
    snprintf(to_err, sizeof to_err, "%s", tu_path("to-stderr"));
    assert_int_equal(symlink("/dev/stderr", to_err), 0);
    assert_int_equal(lumis_output_target(to_err, where, sizeof where), LUMIS_OK);
    assert_string_equal(where, to_err);
    /* descriptor numbers no int holds, or not numbers: paths like any other */
    static const char *const not_fds[] = {"/dev/fd/99999999999", "/dev/fd/-3", "/dev/fd/"};
    for (int k = 0; k < 3; k++) {
        assert_int_equal(lumis_output_target(not_fds[k], where, sizeof where), LUMIS_OK);
        assert_string_equal(where, not_fds[k]);
    }
    /* a loop of links ends after 40 hops on one of its two names */
    char loop_a[600], loop_b[600];
    snprintf(loop_a, sizeof loop_a, "%s", tu_path("loop-a"));
    snprintf(loop_b, sizeof loop_b, "%s", tu_path("loop-b"));
    assert_int_equal(symlink("loop-b", loop_a), 0);
    assert_int_equal(symlink("loop-a", loop_b), 0);
    assert_int_equal(lumis_output_target(loop_a, where, sizeof where), LUMIS_OK);
    assert_true(strcmp(where, loop_a) == 0 || strcmp(where, loop_b) == 0);
    /* a name without a folder (its folder, ".", is synced), and without syncing at all */
    char cwd[4096];
    assert_non_null(getcwd(cwd, sizeof cwd));
    assert_int_equal(chdir(tu_tmpdir()), 0);
    const char *was = getenv("LUMIS_NO_FSYNC");
    char kept[64];
    snprintf(kept, sizeof kept, "%s", was ? was : "");
    setenv("LUMIS_NO_FSYNC", "0", 1);
    const lumis_status rel = lumis_write_text("relative.txt", "here", 4, NULL);
    setenv("LUMIS_NO_FSYNC", "1", 1);
    const lumis_status nosync = lumis_write_text("unsynced.txt", "fast", 4, NULL);
    if (was)
        setenv("LUMIS_NO_FSYNC", kept, 1);
    else
        unsetenv("LUMIS_NO_FSYNC");
    assert_int_equal(chdir(cwd), 0);
    assert_int_equal(rel, LUMIS_OK);
    assert_int_equal(nosync, LUMIS_OK);
    got = tu_read_file(tu_path("relative.txt"), &n);
    assert_true(got && n == 4 && memcmp(got, "here", 4) == 0);
    free(got);
    got = tu_read_file(tu_path("unsynced.txt"), &n);
    assert_true(got && n == 4 && memcmp(got, "fast", 4) == 0);
    free(got);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(exr_round_trips_every_compression_and_tiling),
        cmocka_unit_test(exr_half_clamps_instead_of_overflowing),
        cmocka_unit_test(hdr_round_trip_within_rgbe_precision),
        cmocka_unit_test(pfm_round_trips_exactly_in_both_byte_orders),
        cmocka_unit_test(pfm_grey_and_bottom_up_rows),
        cmocka_unit_test(bad_values_are_replaced_and_counted),
        cmocka_unit_test(black_and_one_pixel_maps_read_back),
        cmocka_unit_test(png_applies_exposure_tonemap_and_srgb),
        cmocka_unit_test(png_bit_depths_palettes_and_interlacing),
        cmocka_unit_test(missing_empty_and_unknown_files),
        cmocka_unit_test(truncated_and_header_only_exr),
        cmocka_unit_test(corrupt_exr_data),
        cmocka_unit_test(exr_attribute_sizes_are_checked_before_openexr),
        cmocka_unit_test(exr_decodes_the_same_with_any_thread_count),
        cmocka_unit_test(exr_size_is_checked_against_the_limit),
        cmocka_unit_test(exr_block_buffers_are_bounded),
        cmocka_unit_test(hdr_headers),
        cmocka_unit_test(hdr_scanline_variants),
        cmocka_unit_test(hdr_writes_huge_values_clamped),
        cmocka_unit_test(hdr_long_literal_runs_round_trip),
        cmocka_unit_test(pfm_headers),
        cmocka_unit_test(unwritable_outputs_fail_cleanly),
        cmocka_unit_test(failed_writes_leave_the_old_file),
        cmocka_unit_test(outputs_to_fifos_links_and_directories),
        cmocka_unit_test(partial_outputs_are_removed_on_request),
        cmocka_unit_test(format_names_and_detection),
        cmocka_unit_test(hdr_exposures_multiply_and_xyze_converts),
        cmocka_unit_test(hdr_consecutive_old_style_runs),
        cmocka_unit_test(hdr_writes_nan_as_black),
        cmocka_unit_test(exr_half_writes_nan_as_black),
        cmocka_unit_test(exr_grey_reads_into_every_channel),
        cmocka_unit_test(outputs_through_descriptors_and_links),
        cmocka_unit_test(png_srgb_curve_near_black),
        cmocka_unit_test(map_specs_name_sizes_and_files),
        cmocka_unit_test(gltf_rotation_turns_minus_z_into_minus_dir),
        cmocka_unit_test(export_frame_maps_pixels_where_consumers_show_them),
        cmocka_unit_test(exported_sun_lands_on_the_sun_pixel),
        cmocka_unit_test(exported_image_sun_and_residual),
        cmocka_unit_test(glb_is_a_binary_gltf_container),
        cmocka_unit_test(outputs_get_ordinary_permissions),
        cmocka_unit_test(explicit_format_wins_over_the_extension),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
