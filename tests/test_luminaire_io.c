/* Luminaire files (lumis/io.h): bit-exact round trips through EXR and PFM, every malformed
 * manifest field reported with the file and the field, bad images, and writes that fail
 * without leaving anything behind. */
/* Oracles:
 * lumis_luminaire_write — consistency: bit-exact round trip through lumis_luminaire_read, 17-digit
 *     doubles and odd names included; error paths: failed writes leave nothing (round_trip,
 *     awkward_numbers_and_names_round_trip, failed_writes_leave_nothing)
 * lumis_luminaire_read — consistency: round trip with lumis_luminaire_write; error paths: bad and
 *     mixed image sets named by manifest and field (round_trip, bad_images_name_manifest_and_field,
 *     mixed_image_sets_are_refused)
 * lumis_luminaire_manifest_parse — hand-worked: a manifest written in the test gives 4 images,
 *     paths, delta 100, quadratic basis; every malformed field named (base_manifest_parses,
 *     malformed_manifests_name_file_and_field)
 * lumis_luminaire_manifest_read — consistency: what lumis_luminaire_write wrote (round_trip)
 * lumis_luminaire_manifest_destroy — external: leaks seen by ASan and valgrind
 *     (base_manifest_parses)
 */
#include "testutil.h"

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

/* A folder of its own under the test's temporary folder (created). */
static const char *subdir(const char *name)
{
    const char *d = tu_path(name);
    assert_true(mkdir(d, 0777) == 0);
    return d;
}

static int exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0;
}

static lumis_luminaire *small_luminaire(void)
{
    lumis_luminaire_desc layout;
    lumis_emitter_desc emitter;
    lumis_emitter_disk disks[4];
    assert_int_equal(lumis_luminaire_preset_get(LUMIS_PRESET_SMALL, &layout, &emitter, disks),
                     LUMIS_OK);
    lumis_acquire_desc acq = {0};
    acq.samples_s = 1;
    lumis_luminaire *lum = NULL;
    assert_int_equal(lumis_luminaire_acquire(&layout, &emitter, &acq, &lum), LUMIS_OK);
    return lum;
}

/* Same geometry (every double bit for bit) and the same pixels. */
static void assert_same_luminaire(const lumis_luminaire *a, const lumis_luminaire *b)
{
    lumis_luminaire_desc x, y;
    lumis_luminaire_get_desc(a, &x);
    lumis_luminaire_get_desc(b, &y);
    assert_memory_equal(&x.delta, &y.delta, sizeof x.delta);
    assert_int_equal(x.basis, y.basis);
    assert_memory_equal(x.grid, y.grid, sizeof x.grid);
    assert_memory_equal(x.grid_origin, y.grid_origin, sizeof x.grid_origin);
    assert_memory_equal(x.grid_spacing, y.grid_spacing, sizeof x.grid_spacing);
    assert_int_equal(x.width, y.width);
    assert_int_equal(x.height, y.height);
    assert_memory_equal(x.image_origin, y.image_origin, sizeof x.image_origin);
    assert_memory_equal(x.image_size, y.image_size, sizeof x.image_size);
    const size_t n = (size_t)x.width * (size_t)x.height * 3 * sizeof(float);
    for (int m = 0; m < x.grid[0] * x.grid[1]; m++)
        assert_memory_equal(lumis_luminaire_image(a, m), lumis_luminaire_image(b, m), n);
}

static lumis_luminaire *read_ok(const char *path)
{
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_luminaire_read_options ro = {0};
    ro.errors = sink.sink;
    lumis_luminaire *lum = NULL;
    lumis_status st = lumis_luminaire_read(path, &ro, &lum);
    if (st != LUMIS_OK) fail_msg("%s: %s (%s)", path, lumis_status_name(st), sink.last);
    assert_int_equal(sink.count, 0);
    return lum;
}

static void round_trip(lumis_file_format format, const char *ext)
{
    lumis_luminaire *lum = small_luminaire();
    char dir[512], path[600], image[700];
    snprintf(dir, sizeof dir, "%s", subdir(ext));
    snprintf(path, sizeof path, "%s/lamp.json", dir);
    lumis_luminaire_write_options wo = {0};
    wo.image_format = format;
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_OK);
    lumis_luminaire *back = read_ok(path);
    assert_same_luminaire(lum, back);

    /* The manifest: units, relative names in m = a + W b order, paths beside it. */
    lumis_luminaire_manifest *man = NULL;
    assert_int_equal(lumis_luminaire_manifest_read(path, NULL, &man), LUMIS_OK);
    assert_string_equal(man->units, "mm");
    assert_int_equal(man->version, 1);
    assert_int_equal(man->image_count, 20);
    snprintf(image, sizeof image, "lamp.images/a003_b002.%s", ext);
    assert_string_equal(man->images[3 + 5 * 2], image);
    snprintf(image, sizeof image, "%s/lamp.images/a003_b002.%s", dir, ext);
    assert_string_equal(man->paths[3 + 5 * 2], image);

    /* Orientation: the file's top row is the row of the largest y. */
    lumis_image *img = NULL;
    lumis_read_info info;
    assert_int_equal(lumis_image_read(image, NULL, &img, &info), LUMIS_OK);
    assert_int_equal(info.format, format);
    const float *px = lumis_luminaire_image(lum, 13);
    const size_t row = (size_t)img->width * 3;
    assert_memory_equal(img->pixels, px + (size_t)(img->height - 1) * row, row * sizeof(float));
    lumis_image_destroy(img);

    /* Nothing else in the folders: no temporary files. */
    assert_int_equal(tu_count_entries(dir, "."), 2); /* "." and ".." only */
    char folder[600];
    snprintf(folder, sizeof folder, "%s/lamp.images", dir);
    assert_int_equal(tu_count_entries(folder, "a"), 20);
    assert_int_equal(tu_count_entries(folder, ".") - 2, 0);

    /* Writing again over it: same files, same luminaire. */
    assert_int_equal(lumis_luminaire_write(path, back, &wo), LUMIS_OK);
    assert_int_equal(tu_count_entries(folder, "a"), 20);
    lumis_luminaire *again = read_ok(path);
    assert_same_luminaire(lum, again);
    lumis_luminaire_manifest_destroy(man);
    lumis_luminaire_destroy(again);
    lumis_luminaire_destroy(back);
    lumis_luminaire_destroy(lum);
}

static void pfm_round_trip_is_bit_exact(void **state)
{
    (void)state;
    round_trip(LUMIS_FORMAT_PFM, "pfm");
}

static void exr_round_trip_is_bit_exact(void **state)
{
    (void)state;
    round_trip(LUMIS_FORMAT_EXR, "exr");
}

/* Doubles that need all 17 digits, the B-spline basis, other units, odd names. */
static void awkward_numbers_and_names_round_trip(void **state)
{
    (void)state;
    enum { W = 2, H = 3, w = 5, h = 4 };
    static float px[W * H][w * h * 3];
    const float *ptrs[W * H];
    for (int m = 0; m < W * H; m++) {
        for (int k = 0; k < w * h * 3; k++) px[m][k] = (float)(m + 1) * 1e-3f * (float)k + 1e-30f;
        ptrs[m] = px[m];
    }
    lumis_luminaire_desc d = {0};
    d.delta = 1.0 / 3.0;
    d.basis = LUMIS_BASIS_BSPLINE;
    d.grid[0] = W;
    d.grid[1] = H;
    d.grid_origin[0] = -0.1 - 0.2;
    d.grid_origin[1] = 1e-300;
    d.grid_spacing[0] = 0.7;
    d.grid_spacing[1] = 123456789.123456789;
    d.width = w;
    d.height = h;
    d.image_origin[0] = -5e15;
    d.image_origin[1] = -0.0;
    d.image_size[0] = 2.0 / 7.0;
    d.image_size[1] = 1e300;
    d.pixels = ptrs;
    lumis_luminaire *lum = NULL;
    assert_int_equal(lumis_luminaire_create(&d, &lum), LUMIS_OK);
    const char *dir = subdir("awkward");
    char path[600];
    snprintf(path, sizeof path, "%s/we\\ird.json", dir);
    lumis_luminaire_write_options wo = {0};
    /* A backslash would make image names a reader refuses. */
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(tu_count_entries(dir, "") - 2, 0);
    snprintf(path, sizeof path, "%s/we\"ird name.v1.json", dir);
    wo.image_format = LUMIS_FORMAT_PFM;
    wo.units = "in \"inches\"";
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_OK);
    lumis_luminaire *back = read_ok(path);
    assert_same_luminaire(lum, back);
    lumis_luminaire_manifest *man = NULL;
    assert_int_equal(lumis_luminaire_manifest_read(path, NULL, &man), LUMIS_OK);
    assert_string_equal(man->units, "in \"inches\"");
    assert_string_equal(man->images[0], "we\"ird name.v1.images/a000_b000.pfm");
    assert_int_equal(man->desc.basis, LUMIS_BASIS_BSPLINE);
    lumis_luminaire_manifest_destroy(man);
    lumis_luminaire_destroy(back);
    /* A name that is all extension (".json") has no stem: it keeps its whole name for its
     * images folder, not an empty one. */
    snprintf(path, sizeof path, "%s/.json", dir);
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_OK);
    assert_int_equal(lumis_luminaire_manifest_read(path, NULL, &man), LUMIS_OK);
    assert_string_equal(man->images[0], ".json.images/a000_b000.pfm");
    lumis_luminaire_manifest_destroy(man);
    back = read_ok(path);
    assert_same_luminaire(lum, back);
    lumis_luminaire_destroy(back);
    lumis_luminaire_destroy(lum);
}

/* ---- malformed manifests ------------------------------------------------------------ */

static const char base_manifest[] =
    "{\n"
    "  \"format\": \"lumis-luminaire\",\n"
    "  \"version\": 1,\n"
    "  \"units\": \"mm\",\n"
    "  \"delta\": 100,\n"
    "  \"basis\": \"quadratic\",\n"
    "  \"grid\": [2, 2],\n"
    "  \"grid_origin\": [-5, -5],\n"
    "  \"grid_spacing\": [10, 10],\n"
    "  \"image\": {\"width\": 24, \"height\": 20, \"origin\": [-60, -50], \"size\": [120, 100]},\n"
    "  \"images\": [\"l/a.exr\", \"l/b.exr\", \"l/c.exr\", \"l/d.exr\"]\n"
    "}\n";

/* text (malloc'ed) with the first occurrence of `from` replaced by `to`. */
static char *replace(const char *text, const char *from, const char *to)
{
    const char *at = strstr(text, from);
    if (!at) fail_msg("'%s' not in the manifest", from);
    size_t n = strlen(text) - strlen(from) + strlen(to);
    char *s = malloc(n + 1);
    assert_non_null(s);
    size_t pre = (size_t)(at - text);
    memcpy(s, text, pre);
    strcpy(s + pre, to);
    strcat(s, at + strlen(from));
    return s;
}

static char *mutate(const char *from, const char *to)
{
    return replace(base_manifest, from, to);
}

static void base_manifest_parses(void **state)
{
    (void)state;
    lumis_luminaire_manifest *m = NULL;
    assert_int_equal(lumis_luminaire_manifest_parse(base_manifest, strlen(base_manifest),
                                                    "lamp.json", "some/dir", NULL, &m),
                     LUMIS_OK);
    assert_int_equal(m->image_count, 4);
    assert_string_equal(m->paths[2], "some/dir/l/c.exr");
    assert_string_equal(m->images[2], "l/c.exr");
    assert_true(m->desc.delta == 100.0);
    assert_int_equal(m->desc.basis, LUMIS_BASIS_QUADRATIC);
    assert_int_equal(m->desc.width, 24);
    assert_true(m->desc.image_size[1] == 100.0);
    assert_null(m->desc.pixels);
    lumis_luminaire_manifest_destroy(m);
    /* No base folder: the names as they are; a trailing slash is not doubled. */
    assert_int_equal(
        lumis_luminaire_manifest_parse(base_manifest, strlen(base_manifest), NULL, NULL, NULL, &m),
        LUMIS_OK);
    assert_string_equal(m->paths[0], "l/a.exr");
    lumis_luminaire_manifest_destroy(m);
    assert_int_equal(
        lumis_luminaire_manifest_parse(base_manifest, strlen(base_manifest), NULL, "d/", NULL, &m),
        LUMIS_OK);
    assert_string_equal(m->paths[0], "d/l/a.exr");
    lumis_luminaire_manifest_destroy(m);
    /* Other keys are ignored (tools may add metadata). */
    char *s = mutate("\"units\"", "\"comment\": {\"by\": [1, 2]}, \"units\"");
    assert_int_equal(lumis_luminaire_manifest_parse(s, strlen(s), NULL, NULL, NULL, &m), LUMIS_OK);
    lumis_luminaire_manifest_destroy(m);
    free(s);
}

static void malformed_manifests_name_file_and_field(void **state)
{
    (void)state;
    const lumis_status BH = LUMIS_ERR_BAD_HEADER;
    static const struct {
        const char *from, *to;
        lumis_status want;
        const char *says; /* after "lamp.json: " */
    } cases[] = {
        {"\"lumis-luminaire\"", "\"lumis-scene\"", LUMIS_ERR_BAD_MAGIC,
         "format: expected \"lumis-luminaire\", got \"lumis-scene\""},
        {"\"format\"", "\"formats\"", LUMIS_ERR_BAD_MAGIC, "format: missing"},
        {"\"version\": 1", "\"version\": 2", LUMIS_ERR_UNSUPPORTED, "version: expected 1"},
        {"\"version\": 1", "\"version\": 0", BH, "version: expected 1"},
        {"\"version\": 1", "\"version\": \"1\"", BH, "version: expected 1"},
        {"\"version\": 1", "\"version\": 1.5", BH, "version: expected 1"},
        {"\"units\": \"mm\"", "\"units\": 1", BH, "units: expected a unit name"},
        {"\"units\": \"mm\"", "\"units\": \"\"", BH, "units: expected"},
        {"\"units\": \"mm\"", "\"units\": \"millimetres of the finest quality\"", BH, "units:"},
        {"\"delta\": 100", "\"delta\": -1", BH, "delta: expected a number > 0, got -1"},
        {"\"delta\": 100", "\"delta\": 0", BH, "delta: expected a number > 0, got 0"},
        {"\"delta\": 100", "\"delta\": 1e999", BH, "delta: expected a number > 0, got inf"},
        {"\"delta\": 100", "\"delta\": null", BH, "delta: expected a number > 0, got null"},
        {"\"delta\": 100", "\"delta\": \"100\"", BH, "delta: expected a number > 0, got \"100\""},
        {"\"delta\": 100", "\"Delta\": 100", BH, "delta: missing; expected a number > 0"},
        {"\"quadratic\"", "\"cubic\"", BH, "basis: expected \"quadratic\" or \"bspline\""},
        {"\"quadratic\"", "\"default\"", BH, "basis:"},
        {"\"grid\": [2, 2]", "\"grid\": [2]", BH, "grid: expected an array of 2 integers"},
        {"\"grid\": [2, 2]", "\"grid\": {}", BH, "grid: expected an array of 2 integers"},
        {"\"grid\": [2, 2]", "\"grid\": [0, 2]", BH, "grid[0]: expected an integer in 1..256"},
        {"\"grid\": [2, 2]", "\"grid\": [2, 2.5]", BH, "grid[1]: expected an integer in 1..256"},
        {"\"grid\": [2, 2]", "\"grid\": [2, 300]", BH, "grid[1]: expected an integer in 1..256"},
        {"\"grid\": [2, 2]", "\"grid\": [64, 64]", BH, "grid: expected at most 1024 images"},
        {"\"grid_origin\": [-5, -5]", "\"grid_origin\": [\"a\", 0]", BH,
         "grid_origin[0]: expected a finite number, got \"a\""},
        {"\"grid_spacing\": [10, 10]", "\"grid_spacing\": [10, -1]", BH,
         "grid_spacing[1]: expected a number > 0, got -1"},
        {"\"grid_spacing\": [10, 10]", "\"grid_spacing\": [0, 10]", BH,
         "grid_spacing[0]: expected a number > 0, got 0"},
        {"\"grid_spacing\": [10, 10]", "\"grid_spacing\": [10, 10, 10]", BH,
         "grid_spacing: expected an array of 2 numbers > 0, got an array of 3"},
        {"\"width\": 24", "\"width\": -3", BH,
         "image.width: expected an integer in 1..16384, got -3"},
        {"\"width\": 24", "\"width\": 16385", BH, "image.width: expected an integer in 1..16384"},
        {"\"height\": 20", "\"height\": 1e10", BH,
         "image.height: expected an integer in 1..16384, got 1e+10"},
        {"\"height\": 20", "\"height\": true", BH, "image.height: expected an integer"},
        {", \"origin\": [-60, -50]", "", BH, "image.origin: missing"},
        {"\"size\": [120, 100]", "\"size\": [120, 0]", BH,
         "image.size[1]: expected a number > 0, got 0"},
        {"\"image\": {", "\"image\": 7, \"x\": {", BH, "image: expected an object"},
        {"\"l/a.exr\", ", "", BH,
         "images: expected an array of 4 file names (grid 2 x 2), got "
         "an array of 3"},
        {"\"l/c.exr\"", "\"/etc/passwd\"", BH, "images[2]: expected a relative path"},
        {"\"l/c.exr\"", "\"../c.exr\"", BH, "images[2]: expected a relative path"},
        {"\"l/c.exr\"", "\"l/../../c.exr\"", BH, "images[2]: expected a relative path"},
        {"\"l/c.exr\"", "\"l/..\"", BH, "images[2]:"},
        {"\"l/c.exr\"", "\"\"", BH, "images[2]: expected a relative path"},
        {"\"l/c.exr\"", "\"l\\\\c.exr\"", BH, "images[2]: expected a relative path"},
        {"\"l/c.exr\"", "\"l/\"", BH, "images[2]:"},
        {"\"l/c.exr\"", "3", BH, "images[2]: expected a relative path"},
        {"\"images\"", "\"image_list\"", BH, "images: missing"},
        /* W H width height = 1024 x 16384^2 = 2^38 pixels: counted without overflow. */
        {"\"width\": 24, \"height\": 20", "\"width\": 16384, \"height\": 16384",
         LUMIS_ERR_TOO_LARGE,
         "image: 1024 images (grid 32 x 32) of 16384 x 16384 pixels are 274877906944 pixels"},
        {"\"version\": 1,", "\"version\": 1", BH, ""},   /* malformed JSON */
        {"{\n  \"format\"", "[{\n  \"format\"", BH, ""}, /* malformed JSON */
        {"{\n  \"format\"", "[], {\"format\"", BH, ""},  /* trailing data */
        {"}\n", "}}\n", BH, ""},                         /* trailing data */
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        char *text = mutate(cases[k].from, cases[k].to);
        if (cases[k].want == LUMIS_ERR_TOO_LARGE) { /* and the largest grid */
            char *t2 = replace(text, "\"grid\": [2, 2]", "\"grid\": [32, 32]");
            free(text);
            text = t2;
        }
        tu_sink sink;
        tu_sink_init(&sink);
        lumis_luminaire_read_options ro = {0};
        ro.errors = sink.sink;
        lumis_luminaire_manifest *m = (lumis_luminaire_manifest *)1;
        lumis_status st =
            lumis_luminaire_manifest_parse(text, strlen(text), "lamp.json", "d", &ro, &m);
        if (st != cases[k].want)
            fail_msg("case %zu (%s -> %s): got %s, want %s (%s)", k, cases[k].from, cases[k].to,
                     lumis_status_name(st), lumis_status_name(cases[k].want), sink.last);
        assert_null(m);
        assert_int_equal(sink.count, 1);
        char want[256];
        snprintf(want, sizeof want, "lamp.json%s%s", *cases[k].says ? ": " : "", cases[k].says);
        if (strncmp(sink.last, want, strlen(want)) != 0)
            fail_msg("case %zu: message '%s' does not start with '%s'", k, sink.last, want);
        free(text);
    }
}

static void odd_inputs_to_the_parser(void **state)
{
    (void)state;
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_luminaire_read_options ro = {0};
    ro.errors = sink.sink;
    lumis_luminaire_manifest *m = NULL;
    assert_int_equal(lumis_luminaire_manifest_parse("", 0, "e.json", NULL, &ro, &m),
                     LUMIS_ERR_EMPTY_FILE);
    assert_non_null(strstr(sink.last, "e.json"));
    assert_int_equal(lumis_luminaire_manifest_parse("[1]", 3, "a.json", NULL, &ro, &m),
                     LUMIS_ERR_BAD_MAGIC);
    assert_string_equal(sink.last,
                        "a.json: (top level): expected a JSON object, got an array of 1");
    assert_int_equal(lumis_luminaire_manifest_parse("{\n\n  x", 6, "j.json", NULL, &ro, &m),
                     LUMIS_ERR_BAD_HEADER);
    assert_string_equal(sink.last, "j.json:3: malformed JSON");
    assert_int_equal(lumis_luminaire_manifest_parse(NULL, 3, "n.json", NULL, &ro, &m),
                     LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_manifest_parse(base_manifest, 5, NULL, NULL, NULL, NULL),
                     LUMIS_ERR_INVALID_ARGUMENT);
    /* The pixel limit counts every image: 4 x 24 x 20 = 1920. */
    ro.max_pixels = 1919;
    assert_int_equal(lumis_luminaire_manifest_parse(base_manifest, strlen(base_manifest),
                                                    "lim.json", NULL, &ro, &m),
                     LUMIS_ERR_TOO_LARGE);
    assert_non_null(strstr(sink.last, "lim.json: image: 4 images"));
    assert_non_null(strstr(sink.last, "1920 pixels, over the limit of 1919"));
    ro.max_pixels = 1920;
    assert_int_equal(lumis_luminaire_manifest_parse(base_manifest, strlen(base_manifest),
                                                    "lim.json", NULL, &ro, &m),
                     LUMIS_OK);
    lumis_luminaire_manifest_destroy(m);
    lumis_luminaire_manifest_destroy(NULL);
}

/* ---- bad files ---------------------------------------------------------------------- */

/* Reading path fails with want, the last message starting with "path: field". */
static void expect_read_error(const char *path, lumis_status want, const char *field)
{
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_luminaire_read_options ro = {0};
    ro.errors = sink.sink;
    lumis_luminaire *lum = (lumis_luminaire *)1;
    lumis_status st = lumis_luminaire_read(path, &ro, &lum);
    if (st != want)
        fail_msg("%s: got %s, want %s (%s)", path, lumis_status_name(st), lumis_status_name(want),
                 sink.last);
    assert_null(lum);
    char prefix[700];
    snprintf(prefix, sizeof prefix, "%s%s%s", path, *field ? ": " : "", field);
    if (strncmp(sink.last, prefix, strlen(prefix)) != 0)
        fail_msg("message '%s' does not start with '%s'", sink.last, prefix);
}

static void copy_file(const char *from, const char *to)
{
    size_t n;
    unsigned char *d = tu_read_file(from, &n);
    assert_non_null(d);
    tu_write_file(to, d, n);
    free(d);
}

/* A luminaire written over another that failed half-way left new images beside the old
 * manifest, and the mixture loaded silently.  The manifest records a digest of its pixels:
 * a set with one image of another luminaire (here copied in, as the failed write left it)
 * is refused, naming the field; the intact set loads. */
static void mixed_image_sets_are_refused(void **state)
{
    (void)state;
    lumis_luminaire *a = small_luminaire();
    lumis_luminaire_desc layout;
    lumis_emitter_desc emitter;
    lumis_emitter_disk disks[4];
    assert_int_equal(lumis_luminaire_preset_get(LUMIS_PRESET_SMALL, &layout, &emitter, disks),
                     LUMIS_OK);
    layout.basis = LUMIS_BASIS_BSPLINE; /* another luminaire of the same layout */
    lumis_acquire_desc acq = {0};
    acq.samples_s = 1;
    lumis_luminaire *b = NULL;
    assert_int_equal(lumis_luminaire_acquire(&layout, &emitter, &acq, &b), LUMIS_OK);
    char da[512], db[512], pa[600], pb[600], ia[700], ib[700];
    snprintf(da, sizeof da, "%s", subdir("mix-a"));
    snprintf(db, sizeof db, "%s", subdir("mix-b"));
    snprintf(pa, sizeof pa, "%s/lamp.json", da);
    snprintf(pb, sizeof pb, "%s/lamp.json", db);
    lumis_luminaire_write_options wo = {0};
    wo.image_format = LUMIS_FORMAT_PFM;
    assert_int_equal(lumis_luminaire_write(pa, a, &wo), LUMIS_OK);
    assert_int_equal(lumis_luminaire_write(pb, b, &wo), LUMIS_OK);
    lumis_luminaire_destroy(read_ok(pa));
    snprintf(ia, sizeof ia, "%s/lamp.images/a001_b001.pfm", da);
    snprintf(ib, sizeof ib, "%s/lamp.images/a001_b001.pfm", db);
    copy_file(ib, ia);
    expect_read_error(pa, LUMIS_ERR_CORRUPT, "pixels_digest: the images are not the ones");
    lumis_luminaire_destroy(a);
    lumis_luminaire_destroy(b);
}

static void bad_images_name_manifest_and_field(void **state)
{
    (void)state;
    lumis_luminaire *lum = small_luminaire();
    char dir[512], path[600], img[700], keep[700];
    snprintf(dir, sizeof dir, "%s", subdir("bad"));
    snprintf(path, sizeof path, "%s/lamp.json", dir);
    lumis_luminaire_write_options wo = {0};
    wo.image_format = LUMIS_FORMAT_PFM;
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_OK);
    snprintf(img, sizeof img, "%s/lamp.images/a002_b001.pfm", dir);
    snprintf(keep, sizeof keep, "%s/keep.pfm", dir);
    copy_file(img, keep);

    /* Missing. */
    assert_int_equal(unlink(img), 0);
    expect_read_error(path, LUMIS_ERR_OPEN, "images[7]: cannot read \"lamp.images/a002_b001.pfm\"");
    /* Truncated. */
    size_t n;
    unsigned char *data = tu_read_file(keep, &n);
    tu_write_file(img, data, n - 100);
    free(data);
    expect_read_error(path, LUMIS_ERR_TRUNCATED, "images[7]: cannot read");
    /* Not an image at all. */
    tu_write_file(img, "hello\n", 6);
    expect_read_error(path, LUMIS_ERR_UNKNOWN_FORMAT, "images[7]:");
    /* A folder where the image should be. */
    assert_int_equal(unlink(img), 0);
    assert_int_equal(mkdir(img, 0777), 0);
    expect_read_error(path, LUMIS_ERR_OPEN, "images[7]:");
    assert_int_equal(rmdir(img), 0);
    /* Smaller and larger than the manifest says. */
    lumis_image *other = NULL;
    assert_int_equal(lumis_image_create(24, 19, &other), LUMIS_OK);
    assert_int_equal(lumis_image_write(img, other, NULL), LUMIS_OK);
    expect_read_error(path, LUMIS_ERR_BAD_DIMENSIONS,
                      "images[7]: \"lamp.images/a002_b001.pfm\" is 24 x 19 pixels, expected "
                      "image.width x image.height = 24 x 20");
    lumis_image_destroy(other);
    assert_int_equal(lumis_image_create(25, 20, &other), LUMIS_OK);
    assert_int_equal(lumis_image_write(img, other, NULL), LUMIS_OK);
    expect_read_error(path, LUMIS_ERR_BAD_DIMENSIONS,
                      "images[7]: \"lamp.images/a002_b001.pfm\" "
                      "has more pixels than image.width");
    lumis_image_destroy(other);
    /* Back in place: reads again.  Then negative values are replaced and reported. */
    copy_file(keep, img);
    lumis_luminaire_destroy(read_ok(path));
    lumis_image *neg = NULL;
    assert_int_equal(lumis_image_read(keep, NULL, &neg, NULL), LUMIS_OK);
    neg->pixels[0] = -1.0f;
    neg->pixels[5] = NAN;
    assert_int_equal(lumis_image_write(img, neg, NULL), LUMIS_OK);
    lumis_image_destroy(neg);
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_luminaire_read_options ro = {0};
    ro.errors = sink.sink;
    lumis_luminaire *back = NULL;
    assert_int_equal(lumis_luminaire_read(path, &ro, &back), LUMIS_OK);
    assert_int_equal(sink.status, LUMIS_OK);
    assert_non_null(strstr(sink.last, "2 negative or non-finite pixel values"));
    assert_non_null(strstr(sink.last, path));
    /* and counted in the luminaire's info (`lumis luminaire info` printed "replaced 0") */
    lumis_luminaire_info li;
    lumis_luminaire_get_info(back, &li);
    assert_int_equal(li.replaced, 2);
    lumis_luminaire_destroy(back);
    /* The pixel limit. */
    ro.max_pixels = 20 * 24 * 20 - 1;
    back = (lumis_luminaire *)1;
    assert_int_equal(lumis_luminaire_read(path, &ro, &back), LUMIS_ERR_TOO_LARGE);
    assert_null(back);
    /* The manifest itself: missing, a folder, malformed. */
    char other_path[700];
    snprintf(other_path, sizeof other_path, "%s/none.json", dir);
    expect_read_error(other_path, LUMIS_ERR_OPEN, "");
    expect_read_error(dir, LUMIS_ERR_OPEN, "not a regular file");
    snprintf(other_path, sizeof other_path, "%s/v2.json", dir);
    char *v2 = mutate("\"version\": 1", "\"version\": 2");
    tu_write_file(other_path, v2, strlen(v2));
    free(v2);
    expect_read_error(other_path, LUMIS_ERR_UNSUPPORTED, "version: expected 1");
    /* A manifest naming a sibling folder's image through ".." is refused before opening it. */
    snprintf(other_path, sizeof other_path, "%s/up.json", dir);
    char *up = mutate("\"l/a.exr\"", "\"../bad/keep.pfm\"");
    tu_write_file(other_path, up, strlen(up));
    free(up);
    expect_read_error(other_path, LUMIS_ERR_BAD_HEADER, "images[0]: expected a relative path");
    assert_int_equal(lumis_luminaire_read(NULL, NULL, &back), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_read(path, NULL, NULL), LUMIS_ERR_INVALID_ARGUMENT);
    lumis_luminaire_destroy(lum);
}

/* ---- writing that fails ------------------------------------------------------------- */

static void unwritable_outputs_fail_cleanly(void **state)
{
    (void)state;
    lumis_luminaire *lum = small_luminaire();
    const char *dir = subdir("unwritable");
    tu_sink sink;
    tu_sink_init(&sink);
    lumis_luminaire_write_options wo = {0};
    wo.errors = sink.sink;
    char path[600];

    /* A folder that does not exist. */
    snprintf(path, sizeof path, "%s/no/such/lamp.json", dir);
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_ERR_WRITE);
    assert_non_null(strstr(sink.last, path));
    /* The manifest's name is a folder: every image is written, then the manifest's rename
     * fails, and the images and their folder go again. */
    snprintf(path, sizeof path, "%s/adir.json", dir);
    assert_int_equal(mkdir(path, 0777), 0);
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_ERR_WRITE);
    assert_non_null(strstr(sink.last, path));
    assert_int_equal(rmdir(path), 0);
    snprintf(path, sizeof path, "%s/adir.images", dir);
    assert_false(exists(path));
    /* A file where the image folder should be. */
    snprintf(path, sizeof path, "%s/blocked.images", dir);
    tu_write_file(path, "x", 1);
    snprintf(path, sizeof path, "%s/blocked.json", dir);
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_ERR_WRITE);
    assert_non_null(strstr(sink.last, "blocked.images"));
    snprintf(path, sizeof path, "%s/blocked.images", dir);
    assert_int_equal(unlink(path), 0);
    /* Arguments. */
    snprintf(path, sizeof path, "%s/lamp.json", dir);
    wo.image_format = LUMIS_FORMAT_HDR;
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_ERR_INVALID_ARGUMENT);
    wo.image_format = LUMIS_FORMAT_PNG;
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_ERR_INVALID_ARGUMENT);
    wo.image_format = LUMIS_FORMAT_EXR;
    wo.units = "";
    assert_int_equal(lumis_luminaire_write(path, lum, &wo), LUMIS_ERR_INVALID_ARGUMENT);
    wo.units = NULL;
    char slash[600];
    snprintf(slash, sizeof slash, "%s/", dir);
    assert_int_equal(lumis_luminaire_write(slash, lum, &wo), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_write(path, NULL, &wo), LUMIS_ERR_INVALID_ARGUMENT);
    assert_int_equal(lumis_luminaire_write(NULL, lum, NULL), LUMIS_ERR_INVALID_ARGUMENT);

    /* Nothing was left behind by any of these. */
    assert_int_equal(tu_count_entries(dir, "") - 2, 0);
    lumis_luminaire_destroy(lum);
}

/* W x H images of w x h pixels, all 1. */
static lumis_luminaire *flat_luminaire(int W, int H, int w, int h)
{
    float *px = malloc((size_t)w * (size_t)h * 3 * sizeof(float));
    const float **ptrs = malloc((size_t)W * (size_t)H * sizeof *ptrs);
    assert_true(px && ptrs);
    for (int k = 0; k < w * h * 3; k++) px[k] = 1.0f;
    for (int m = 0; m < W * H; m++) ptrs[m] = px;
    lumis_luminaire_desc d = {0};
    d.delta = 1.0;
    d.grid[0] = W;
    d.grid[1] = H;
    d.grid_spacing[0] = d.grid_spacing[1] = 1.0;
    d.width = w;
    d.height = h;
    d.image_size[0] = d.image_size[1] = 1.0;
    d.pixels = ptrs;
    lumis_luminaire *lum = NULL;
    assert_int_equal(lumis_luminaire_create(&d, &lum), LUMIS_OK);
    free(ptrs);
    free(px);
    return lum;
}

/* Writes that run out of room (a file-size limit, in a child process) leave nothing: the
 * first image too large (the new folder goes again), or every image written and the
 * manifest too large (the images go too). */
static void failed_writes_leave_nothing(void **state)
{
    (void)state;
    const char *dir = subdir("fsize");
    for (int k = 0; k < 4; k++) {
        int format = k & 1, manifest_fails = k >> 1;
        char path[600];
        snprintf(path, sizeof path, "%s/lamp%d.json", dir, k);
        pid_t pid = fork();
        assert_true(pid >= 0);
        if (pid == 0) {
            /* A 24 x 20 PFM is 5.8 KB; 32 x 32 names make a 40 KB manifest of 1-pixel images. */
            lumis_luminaire *lum =
                manifest_fails ? flat_luminaire(32, 32, 1, 1) : flat_luminaire(2, 2, 24, 20);
            signal(SIGXFSZ, SIG_IGN);
            struct rlimit rl = {manifest_fails ? 4096 : 256, manifest_fails ? 4096 : 256};
            setrlimit(RLIMIT_FSIZE, &rl);
            lumis_luminaire_write_options wo = {0};
            wo.image_format = format ? LUMIS_FORMAT_PFM : LUMIS_FORMAT_EXR;
            lumis_status st = lumis_luminaire_write(path, lum, &wo);
            _exit(st == LUMIS_ERR_WRITE ? 0 : 10 + (int)st);
        }
        int status;
        waitpid(pid, &status, 0);
        assert_true(WIFEXITED(status));
        if (WEXITSTATUS(status) != 0) fail_msg("case %d: status %d", k, WEXITSTATUS(status) - 10);
        assert_int_equal(tu_count_entries(dir, "") - 2, 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pfm_round_trip_is_bit_exact),
        cmocka_unit_test(exr_round_trip_is_bit_exact),
        cmocka_unit_test(awkward_numbers_and_names_round_trip),
        cmocka_unit_test(base_manifest_parses),
        cmocka_unit_test(malformed_manifests_name_file_and_field),
        cmocka_unit_test(odd_inputs_to_the_parser),
        cmocka_unit_test(bad_images_name_manifest_and_field),
        cmocka_unit_test(mixed_image_sets_are_refused),
        cmocka_unit_test(unwritable_outputs_fail_cleanly),
        cmocka_unit_test(failed_writes_leave_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
