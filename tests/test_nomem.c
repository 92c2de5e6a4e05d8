/* Out of memory, at every allocation: each public operation is run once per allocation it
 * makes, with that one allocation failing, and must return LUMIS_ERR_OUT_OF_MEMORY (never
 * success with a hole, never a crash); under the sanitizer build LeakSanitizer also checks
 * that every failed call freed what it had made.  The library's own calls to malloc, calloc
 * and realloc are redirected here by the linker (-Wl,--wrap: tests/CMakeLists.txt), so only
 * lumis's allocations fail, never those of libc, Embree or OpenEXR. */
/* Oracles:
 * lumis_envmap_from_image — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (procedural_maps_and_envmap)
 * lumis_flip_colormap — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (map_specs_and_metrics)
 * lumis_flip_hdr — error paths only: each of its allocations failing gives LUMIS_ERR_OUT_OF_MEMORY,
 *     nothing leaked (light_export_luminaire_files_and_metrics)
 * lumis_flip_ldr — error paths only: each of its allocations failing gives LUMIS_ERR_OUT_OF_MEMORY,
 *     nothing leaked (light_export_luminaire_files_and_metrics)
 * lumis_image_errors — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (light_export_luminaire_files_and_metrics)
 * lumis_image_read_memory — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_image_format)
 * lumis_image_write — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_image_format)
 * lumis_joint_bilateral_upsample — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (renders_of_every_light_kind)
 * lumis_lab_delta_e — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (map_specs_and_metrics)
 * lumis_light_set_irradiance — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_light_set_method)
 * lumis_light_set_write_gltf — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (light_export_luminaire_files_and_metrics)
 * lumis_light_set_write_json — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (light_export_luminaire_files_and_metrics)
 * lumis_lights_decompose — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_light_set_method)
 * lumis_lights_fhis — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_light_set_method)
 * lumis_lights_median_cut — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_light_set_method)
 * lumis_lights_tmms — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_light_set_method)
 * lumis_lights_variance_min — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_light_set_method)
 * lumis_luminaire_from_photometric — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (photometric_files_and_fixtures)
 * lumis_luminaire_read — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (light_export_luminaire_files_and_metrics)
 * lumis_luminaire_write — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (light_export_luminaire_files_and_metrics)
 * lumis_map_read — error paths only: each of its allocations failing gives LUMIS_ERR_OUT_OF_MEMORY,
 *     nothing leaked (map_specs_and_metrics)
 * lumis_photometric_read_memory — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (photometric_files_and_fixtures)
 * lumis_region_sampler_create — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_light_set_method)
 * lumis_render — error paths only: each of its allocations failing gives LUMIS_ERR_OUT_OF_MEMORY,
 *     nothing leaked (photometric_files_and_fixtures, renders_of_every_light_kind)
 * lumis_render_gbuffer — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (renders_of_every_light_kind)
 * lumis_render_session — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (renders_of_every_light_kind)
 * lumis_sampler_create — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (every_sampler)
 * lumis_scene_create — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (renders_of_every_light_kind)
 * lumis_scene_file_read — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (scene_file)
 * lumis_sky_create — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (procedural_maps_and_envmap)
 * lumis_studio_create — error paths only: each of its allocations failing gives
 *     LUMIS_ERR_OUT_OF_MEMORY, nothing leaked (procedural_maps_and_envmap)
 */
#include <execinfo.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cJSON.h>
#include <cmocka.h>

#include "lumis/io.h"
#include "lumis/lumis.h"
#include "lumis/render.h"
#include "photometric_gen.h"
#include "testutil.h"

void *__real_malloc(size_t size);
void *__real_calloc(size_t n, size_t size);
void *__real_realloc(void *p, size_t size);
void *__wrap_malloc(size_t size);
void *__wrap_calloc(size_t n, size_t size);
void *__wrap_realloc(void *p, size_t size);

static atomic_long calls;   /* allocations counted since the scenario started */
static atomic_long fail_at; /* the one that fails (1-based); 0 == none */
static atomic_int injected; /* it was reached */
static void *where[24];     /* the call stack of the failed allocation */
static int where_depth;

static int should_fail(void)
{
    long n = atomic_fetch_add(&calls, 1) + 1;
    if (n == atomic_load(&fail_at)) {
        atomic_store(&injected, 1);
        where_depth = backtrace(where, 24);
        return 1;
    }
    return 0;
}

void *__wrap_malloc(size_t size)
{
    return should_fail() ? NULL : __real_malloc(size);
}
void *__wrap_calloc(size_t n, size_t size)
{
    return should_fail() ? NULL : __real_calloc(n, size);
}
void *__wrap_realloc(void *p, size_t size)
{
    return should_fail() ? NULL : __real_realloc(p, size);
}

/* What an operation made, as one number (0 when it does not say): a call that succeeds
 * with an allocation failed must have fallen back to the same result. */
static double digest;

/* Runs op with allocation 1, 2, ... failing until it makes no more allocations than the
 * failing one.  op returns its status and frees whatever it made, on success too.  A
 * failed allocation must give LUMIS_ERR_OUT_OF_MEMORY, or success with the same digest
 * (a fallback that needs no memory, e.g. Wu's extents computed without their bounds). */
typedef lumis_status (*op_fn)(void *ctx);
static void each_allocation_fails(const char *name, op_fn op, void *ctx)
{
    atomic_store(&fail_at, 0);
    atomic_store(&calls, 0);
    digest = 0;
    assert_int_equal(op(ctx), LUMIS_OK);
    const double expect = digest;
    long total = atomic_load(&calls);
    int wrong = 0, fell_back = 0;
    for (long k = 1; k <= total + 1; k++) {
        atomic_store(&calls, 0);
        atomic_store(&injected, 0);
        digest = 0;
        atomic_store(&fail_at, k);
        lumis_status st = op(ctx);
        atomic_store(&fail_at, 0);
        if (!atomic_load(&injected)) {
            if (st != LUMIS_OK) {
                printf("%s: failed with %s when no allocation failed\n", name,
                       lumis_status_string(st));
                wrong++;
            }
            break;
        }
        if (st == LUMIS_OK && expect != 0 && digest == expect) {
            fell_back++;
            continue;
        }
        if (st != LUMIS_ERR_OUT_OF_MEMORY) {
            printf("%s: allocation %ld of %ld failed, the call returned %s; the allocation "
                   "(addr2line -f -e test_nomem):\n",
                   name, k, total, lumis_status_string(st));
            fflush(stdout);
            backtrace_symbols_fd(where, where_depth, STDOUT_FILENO);
            wrong++;
        }
    }
    printf("%s: %ld allocations, each failed once (%d fell back to the same result)\n", name, total,
           fell_back);
    assert_int_equal(wrong, 0);
}

/* ---- inputs, made before any allocation fails ---------------------------------------- */

typedef struct inputs {
    lumis_image *sky;          /* 64 x 32 procedural sky */
    lumis_envmap *env;         /* of it */
    lumis_light_set *set;      /* median cut, 8 lights */
    lumis_image *a, *b;        /* 24 x 16 images for the metrics */
    lumis_luminaire *lum;      /* a 2 x 2 light field of 6 x 5 images */
    lumis_luminaire *lum2;     /* another: 3 x 2, B-spline, other pixels */
    lumis_scene_file *spheres; /* the built-in scene's objects */
    lumis_scene *scene;        /* of them */
    lumis_sampler *sampler;    /* kd-tree sampler of env */
    char dir[512];             /* a scratch folder */
    void *file_bytes[LUMIS_FORMAT_COUNT];
    size_t file_size[LUMIS_FORMAT_COUNT];
} inputs;

static inputs in;

static const char *const ext[LUMIS_FORMAT_COUNT] = {NULL, "exr", "hdr", "pfm", "png"};

static void *slurp(const char *path, size_t *size)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    void *p = __real_malloc((size_t)n);
    assert_int_equal(fread(p, 1, (size_t)n, f), (size_t)n);
    fclose(f);
    *size = (size_t)n;
    return p;
}

static int setup(void **state)
{
    (void)state;
    lumis_sky_desc sd = {0};
    sd.width = 64;
    sd.height = 32;
    if (lumis_sky_create(&sd, &in.sky) != LUMIS_OK) return -1;
    if (lumis_envmap_from_image(in.sky, &in.env) != LUMIS_OK) return -1;
    lumis_median_cut_desc md = {0};
    md.count = 8;
    if (lumis_lights_median_cut(in.env, &md, &in.set) != LUMIS_OK) return -1;
    if (lumis_image_create(24, 16, &in.a) != LUMIS_OK) return -1;
    if (lumis_image_create(24, 16, &in.b) != LUMIS_OK) return -1;
    for (int i = 0; i < 24 * 16 * 3; i++) {
        in.a->pixels[i] = 0.05f * (float)(i % 17);
        in.b->pixels[i] = 0.05f * (float)(i % 13);
    }
    enum { W = 2, H = 2, w = 6, h = 5 };
    static float px[W * H][w * h * 3];
    const float *ptrs[W * H];
    for (int m = 0; m < W * H; m++) {
        for (int k = 0; k < w * h * 3; k++) px[m][k] = 0.1f + 0.01f * (float)((k * 7 + m) % 23);
        ptrs[m] = px[m];
    }
    lumis_luminaire_desc d = {0};
    d.grid[0] = W;
    d.grid[1] = H;
    d.grid_origin[0] = d.grid_origin[1] = -0.5;
    d.grid_spacing[0] = d.grid_spacing[1] = 1.0;
    d.delta = 1.0;
    d.width = w;
    d.height = h;
    d.image_origin[0] = d.image_origin[1] = -1.0;
    d.image_size[0] = d.image_size[1] = 2.0;
    d.pixels = ptrs;
    if (lumis_luminaire_create(&d, &in.lum) != LUMIS_OK) return -1;
    static float px2[3 * 2][w * h * 3];
    const float *ptrs2[3 * 2];
    for (int m = 0; m < 3 * 2; m++) {
        for (int k = 0; k < w * h * 3; k++) px2[m][k] = 0.5f + 0.02f * (float)((k * 5 + m) % 19);
        ptrs2[m] = px2[m];
    }
    d.grid[0] = 3;
    d.basis = LUMIS_BASIS_BSPLINE;
    d.pixels = ptrs2;
    if (lumis_luminaire_create(&d, &in.lum2) != LUMIS_OK) return -1;
    if (lumis_scene_builtin("spheres", NULL, &in.spheres) != LUMIS_OK) return -1;
    if (lumis_scene_create(in.spheres->objects, in.spheres->object_count, NULL, &in.scene) !=
        LUMIS_OK)
        return -1;
    lumis_sampler_desc sdsc = {0};
    sdsc.method = LUMIS_METHOD_KDTREE;
    sdsc.kdtree_blocks = 64;
    if (lumis_sampler_create(in.env, &sdsc, &in.sampler) != LUMIS_OK) return -1;
    snprintf(in.dir, sizeof in.dir, "%s", tu_tmpdir());
    for (int f = 1; f < LUMIS_FORMAT_COUNT; f++) {
        char path[600];
        snprintf(path, sizeof path, "%s/in.%s", in.dir, ext[f]);
        if (lumis_image_write(path, in.a, NULL) != LUMIS_OK) return -1;
        in.file_bytes[f] = slurp(path, &in.file_size[f]);
    }
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    for (int f = 1; f < LUMIS_FORMAT_COUNT; f++) free(in.file_bytes[f]);
    lumis_sampler_destroy(in.sampler);
    lumis_scene_destroy(in.scene);
    lumis_scene_file_destroy(in.spheres);
    lumis_luminaire_destroy(in.lum2);
    lumis_luminaire_destroy(in.lum);
    lumis_image_destroy(in.a);
    lumis_image_destroy(in.b);
    lumis_light_set_destroy(in.set);
    lumis_envmap_destroy(in.env);
    lumis_image_destroy(in.sky);
    return 0;
}

/* ---- the operations ---------------------------------------------------------------------- */

static lumis_status op_sky(void *ctx)
{
    (void)ctx;
    lumis_sky_desc d = {0};
    d.width = 32;
    d.height = 16;
    lumis_image *img = NULL;
    lumis_status st = lumis_sky_create(&d, &img);
    lumis_image_destroy(img);
    return st;
}

static lumis_status op_studio(void *ctx)
{
    (void)ctx;
    lumis_studio_desc d = {0};
    d.width = 32;
    d.height = 16;
    lumis_image *img = NULL;
    lumis_status st = lumis_studio_create(&d, &img);
    lumis_image_destroy(img);
    return st;
}

static lumis_status op_envmap(void *ctx)
{
    (void)ctx;
    lumis_envmap *env = NULL;
    lumis_status st = lumis_envmap_from_image(in.sky, &env);
    lumis_envmap_destroy(env);
    return st;
}

static lumis_status op_sampler(void *ctx)
{
    lumis_sampler_desc d = {0};
    d.method = *(const lumis_sampler_method *)ctx;
    d.kdtree_blocks = 64;
    lumis_sampler *s = NULL;
    lumis_status st = lumis_sampler_create(in.env, &d, &s);
    lumis_sampler_destroy(s);
    return st;
}

static double set_digest(const lumis_light_set *set)
{
    double d = 1;
    for (int s = 0; s < lumis_light_set_sets(set); s++) {
        const lumis_light *l = NULL;
        int n = 0;
        if (lumis_light_set_get(set, s, &l, &n) != LUMIS_OK) return -1;
        for (int k = 0; k < n; k++)
            d += (k + 1) * (l[k].dir.x + 2 * l[k].dir.y + 3 * l[k].dir.z + l[k].extent +
                            l[k].power[0] + l[k].power[1] + l[k].power[2]);
    }
    return d;
}

static lumis_status op_lights(void *ctx)
{
    int method = *(const int *)ctx;
    lumis_light_set *set = NULL;
    lumis_status st;
    switch (method) {
    case 0: {
        lumis_median_cut_desc d = {0};
        d.count = 16;
        st = lumis_lights_median_cut(in.env, &d, &set);
        break;
    }
    case 1: {
        lumis_variance_min_desc d = {0};
        d.count = 16;
        st = lumis_lights_variance_min(in.env, &d, &set);
        break;
    }
    case 2: {
        lumis_decomp_desc d = {0};
        d.count = 16;
        d.sets = 2;
        st = lumis_lights_decompose(in.env, &d, &set);
        break;
    }
    case 3: {
        lumis_fhis_desc d = {0};
        d.count = 16;
        st = lumis_lights_fhis(in.env, &d, &set);
        break;
    }
    default: {
        lumis_tmms_desc d = {0};
        d.count = 16;
        st = lumis_lights_tmms(in.env, &d, &set);
        break;
    }
    }
    digest = st == LUMIS_OK ? set_digest(set) : 0;
    lumis_light_set_destroy(set);
    return st;
}

static lumis_status op_read(void *ctx)
{
    int f = *(const int *)ctx;
    lumis_image *img = NULL;
    lumis_status st = lumis_image_read_memory(in.file_bytes[f], in.file_size[f],
                                              (lumis_file_format)f, "in", NULL, &img, NULL);
    lumis_image_destroy(img);
    return st;
}

static lumis_status op_write(void *ctx)
{
    int f = *(const int *)ctx;
    char path[600];
    snprintf(path, sizeof path, "%s/out.%s", in.dir, ext[f]);
    return lumis_image_write(path, in.a, NULL);
}

/* The exports build their documents with cJSON, which allocates through its own hooks (a
 * shared libcjson's malloc is not lumis's, so --wrap does not reach it): the scenario sends
 * them to the failing allocator too.  The digest is the file written, byte by byte: a
 * document with a hole, or none, is not the same success. */
static lumis_status op_export(void *ctx)
{
    int gltf = *(const int *)ctx;
    char path[600];
    snprintf(path, sizeof path, "%s/lights.%s", in.dir, gltf == 2 ? "glb" : gltf ? "gltf" : "json");
    remove(path);
    lumis_light_export_options o = {0};
    o.masks = 1; /* the region runs too */
    o.method = "fhis";
    o.parameters = "seed=3";
    const lumis_status st = gltf ? lumis_light_set_write_gltf(path, in.set, &o)
                                 : lumis_light_set_write_json(path, in.set, &o);
    if (st == LUMIS_OK) {
        size_t n = 0;
        unsigned char *b = slurp(path, &n);
        uint64_t hash = 1469598103934665603ull; /* FNV-1a */
        for (size_t k = 0; b && k < n; k++) hash = (hash ^ b[k]) * 1099511628211ull;
        digest = b ? (double)(hash >> 11) + (double)n : -1.0;
        free(b);
    }
    return st;
}

static lumis_status op_luminaire_files(void *ctx)
{
    (void)ctx;
    char path[600];
    snprintf(path, sizeof path, "%s/lum.json", in.dir);
    lumis_status st = lumis_luminaire_write(path, in.lum, NULL);
    if (st != LUMIS_OK) return st;
    lumis_luminaire *back = NULL;
    st = lumis_luminaire_read(path, NULL, &back);
    lumis_luminaire_destroy(back);
    return st;
}

/* 1 when the two luminaires have the same grid, basis and pixels. */
static int same_luminaire(const lumis_luminaire *x, const lumis_luminaire *y)
{
    lumis_luminaire_desc a, b;
    lumis_luminaire_get_desc(x, &a);
    lumis_luminaire_get_desc(y, &b);
    if (a.grid[0] != b.grid[0] || a.grid[1] != b.grid[1] || a.basis != b.basis ||
        a.width != b.width || a.height != b.height)
        return 0;
    for (int m = 0; m < a.grid[0] * a.grid[1]; m++)
        if (memcmp(a.pixels[m], b.pixels[m], (size_t)a.width * (size_t)a.height * 3 * 4) != 0)
            return 0;
    return 1;
}

/* Writes lum2 over a luminaire file of lum.  When that fails, the file must still read back
 * as lum, with no staging folder left beside it (else LUMIS_ERR_CORRUPT); after a success
 * lum is written back (allocations then do not fail). */
static lumis_status op_luminaire_overwrite(void *ctx)
{
    (void)ctx;
    char path[600];
    snprintf(path, sizeof path, "%s/over.json", in.dir);
    lumis_status st = lumis_luminaire_write(path, in.lum2, NULL);
    const long armed = atomic_exchange(&fail_at, 0);
    lumis_luminaire *back = NULL;
    int intact = lumis_luminaire_read(path, NULL, &back) == LUMIS_OK &&
                 same_luminaire(back, st == LUMIS_OK ? in.lum2 : in.lum) &&
                 tu_count_entries(in.dir, "over.images.") == 0;
    lumis_luminaire_destroy(back);
    if (st == LUMIS_OK && lumis_luminaire_write(path, in.lum, NULL) != LUMIS_OK) intact = 0;
    atomic_store(&fail_at, armed);
    return intact ? st : LUMIS_ERR_CORRUPT;
}

static lumis_status op_metrics(void *ctx)
{
    (void)ctx;
    lumis_flip_hdr_result r;
    lumis_status st = lumis_flip_hdr(in.a, in.b, NULL, NULL, NULL, &r);
    if (st != LUMIS_OK) return st;
    double mean = 0;
    st = lumis_flip_ldr(in.a, in.b, NULL, NULL, &mean);
    if (st != LUMIS_OK) return st;
    lumis_image_error_stats e;
    return lumis_image_errors(in.a, in.b, NULL, &e);
}

static lumis_status op_scene_file(void *ctx)
{
    (void)ctx;
    char path[600];
    snprintf(path, sizeof path, "%s/scene.json", in.dir);
    lumis_scene_file *sf = NULL;
    lumis_status st = lumis_scene_file_read(path, NULL, &sf);
    lumis_scene_file_destroy(sf);
    return st;
}

static double image_digest(const lumis_image *img)
{
    double d = 1;
    for (int i = 0; i < img->width * img->height * 3; i++) d += (i % 7 + 1) * img->pixels[i];
    return d;
}

static const lumis_camera tiny_cam = {{0, 0.5f, 5}, {0, 0, 0}, {0, 1, 0}, 40.0f, 8, 6};

/* ctx: 0 environment with MIS, 1 a light set, 2 luminaires, 3 path tracing */
static lumis_status op_render(void *ctx)
{
    const int kind = *(const int *)ctx;
    lumis_render_desc d = {0};
    d.camera = &tiny_cam;
    d.lighting.env = in.env;
    d.lighting.sampler = in.sampler;
    d.spp = 2;
    d.threads = 1;
    d.seed = 7;
    lumis_luminaire_instance inst = {0};
    lumis_luminaire_lighting lit = {0};
    if (kind == 1 || kind == 4) { /* a light set lights it: the map's sampler does not apply */
        d.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
        d.lighting.sampler = NULL;
        d.lighting.light_set.set = in.set;
    }
    if (kind == 2 || kind == 6) { /* luminaires light it alone: no map */
        d.lighting.env = NULL;
        d.lighting.sampler = NULL;
        inst.luminaire = in.lum;
        inst.placement = lumis_rigid_identity();
        inst.placement.t[1] = 3;
        lit.instances = &inst;
        lit.count = 1;
        lit.budget = 4;
        d.lighting.luminaires = &lit;
        d.lighting.kind = LUMIS_LIGHTING_LUMINAIRES;
        if (kind == 6) { /* auto: the prediction, its probes' selection, bands */
            lit.strategy = LUMIS_LUM_AUTO;
            lit.auto_bands = 1;
        }
    }
    if (kind == 3) d.max_bounces = 2;
    if (kind == 5) d.sequence = LUMIS_SEQUENCE_PMJ02; /* its tables */
    if (kind == 4) /* the set's regions as strata, made by the render */
        d.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
    lumis_image *img = NULL;
    lumis_status st = lumis_render(in.scene, &d, &img, NULL);
    digest = st == LUMIS_OK ? image_digest(img) : 0;
    lumis_image_destroy(img);
    return st;
}

/* ctx: 0 the map's sampler, 1 median cut by name, 2 Wu with its upsampled low layer */
static lumis_status op_session(void *ctx)
{
    const int kind = *(const int *)ctx;
    lumis_session_desc s = {0};
    s.render.camera = &tiny_cam;
    s.render.lighting.env = in.env;
    s.render.lighting.sampler = in.sampler;
    s.render.spp = 2;
    s.render.threads = 1;
    s.lights = kind == 1 ? "median-cut" : kind >= 2 ? "wu" : NULL;
    s.lights_k = kind ? 8 : 0;
    if (kind) { /* the session's light set lights it */
        s.render.lighting.kind = LUMIS_LIGHTING_LIGHT_SET;
        s.render.lighting.sampler = NULL;
    }
    if (kind == 3) /* with its two layers */
        s.render.lighting.light_set.mode = LUMIS_LIGHTS_STRATIFIED;
    lumis_image *img = NULL;
    lumis_session_result r;
    lumis_status st = lumis_render_session(in.scene, &s, &img, &r);
    digest = st == LUMIS_OK ? image_digest(img) : 0;
    if (st == LUMIS_OK) lumis_light_set_destroy(r.light_set);
    lumis_image_destroy(img);
    return st;
}

static lumis_status op_scene_create(void *ctx)
{
    (void)ctx;
    lumis_scene *sc = NULL;
    lumis_status st = lumis_scene_create(in.spheres->objects, in.spheres->object_count, NULL, &sc);
    lumis_scene_destroy(sc);
    return st;
}

static lumis_status op_upsample(void *ctx)
{
    (void)ctx;
    lumis_camera lo = tiny_cam, hi = tiny_cam;
    lo.width = 4;
    lo.height = 3;
    lumis_gbuffer *glo = NULL, *ghi = NULL;
    lumis_image *low = NULL, *out = NULL;
    lumis_status st = lumis_render_gbuffer(in.scene, &lo, NULL, &glo);
    if (st == LUMIS_OK) st = lumis_render_gbuffer(in.scene, &hi, NULL, &ghi);
    if (st == LUMIS_OK) st = lumis_image_create(4, 3, &low);
    if (st == LUMIS_OK) {
        for (int i = 0; i < 4 * 3 * 3; i++) low->pixels[i] = (float)(i % 5);
        st = lumis_joint_bilateral_upsample(low, glo, ghi, NULL, &out);
    }
    lumis_image_destroy(out);
    lumis_image_destroy(low);
    lumis_gbuffer_destroy(ghi);
    lumis_gbuffer_destroy(glo);
    return st;
}

static lumis_status op_map_spec(void *ctx)
{
    const char *spec = ctx;
    lumis_image *img = NULL;
    lumis_status st = lumis_map_read(spec, NULL, &img, NULL);
    lumis_image_destroy(img);
    return st;
}

static lumis_status op_more_metrics(void *ctx)
{
    (void)ctx;
    float map[24 * 16];
    double mean = 0;
    lumis_status st = lumis_lab_delta_e(in.a, in.b, NULL, map, &mean);
    if (st != LUMIS_OK) return st;
    for (int i = 0; i < 24 * 16; i++) map[i] = (float)(i % 11) / 10.0f;
    lumis_image *cm = NULL;
    st = lumis_flip_colormap(map, 24, 16, &cm);
    lumis_image_destroy(cm);
    return st;
}

/* ---- the tests --------------------------------------------------------------------------- */

static void procedural_maps_and_envmap(void **state)
{
    (void)state;
    each_allocation_fails("sky", op_sky, NULL);
    each_allocation_fails("studio", op_studio, NULL);
    each_allocation_fails("envmap", op_envmap, NULL);
}

static void every_sampler(void **state)
{
    (void)state;
    for (int m = 1; m < LUMIS_METHOD_COUNT; m++) {
        lumis_sampler_method method = (lumis_sampler_method)m;
        char name[64];
        snprintf(name, sizeof name, "sampler %s", lumis_sampler_method_name(method));
        each_allocation_fails(name, op_sampler, &method);
    }
}

static lumis_status op_regions(void *ctx)
{
    (void)ctx;
    lumis_region_sampler *rs = NULL;
    lumis_status st = lumis_region_sampler_create(in.env, in.set, NULL, &rs);
    if (st == LUMIS_OK) {
        const lumis_env_sample e = lumis_region_sampler_sample(rs, 0, 0.3, 0.6);
        digest = (double)e.pdf + (double)lumis_region_sampler_bytes(rs);
    }
    lumis_region_sampler_destroy(rs);
    return st;
}

static lumis_status op_irradiance(void *ctx)
{
    (void)ctx;
    double se = 0.0, me = 0.0;
    lumis_status st = lumis_light_set_irradiance(in.env, in.set, (lumis_vec3){0, 1, 0}, &se, &me);
    digest = se + me;
    return st;
}

static void every_light_set_method(void **state)
{
    (void)state;
    static const char *const names[] = {"median cut", "variance min", "Wu", "FHIS", "TMMS"};
    for (int m = 0; m < 5; m++) each_allocation_fails(names[m], op_lights, &m);
    each_allocation_fails("region samplers", op_regions, NULL);
    each_allocation_fails("light set irradiance", op_irradiance, NULL);
}

static void every_image_format(void **state)
{
    (void)state;
    for (int f = 1; f < LUMIS_FORMAT_COUNT; f++) {
        char name[64];
        snprintf(name, sizeof name, "read %s", ext[f]);
        each_allocation_fails(name, op_read, &f);
        snprintf(name, sizeof name, "write %s", ext[f]);
        each_allocation_fails(name, op_write, &f);
    }
}

static int cjson_hooks_off(void **state)
{
    (void)state;
    cJSON_InitHooks(NULL);
    return 0;
}

static void light_export_luminaire_files_and_metrics(void **state)
{
    (void)state;
    int gltf = 0;
    cJSON_Hooks hooks = {__wrap_malloc, free};
    cJSON_InitHooks(&hooks);
    each_allocation_fails("lights json", op_export, &gltf);
    gltf = 1;
    each_allocation_fails("lights gltf", op_export, &gltf);
    gltf = 2;
    each_allocation_fails("lights glb", op_export, &gltf);
    cJSON_InitHooks(NULL); /* back to libc's (and in the teardown, should a check fail) */
    each_allocation_fails("luminaire write + read", op_luminaire_files, NULL);
    char path[600];
    snprintf(path, sizeof path, "%s/over.json", in.dir);
    assert_int_equal(lumis_luminaire_write(path, in.lum, NULL), LUMIS_OK);
    each_allocation_fails("luminaire written over another", op_luminaire_overwrite, NULL);
    each_allocation_fails("metrics", op_metrics, NULL);
}

static void scene_file(void **state)
{
    (void)state;
    char path[600];
    snprintf(path, sizeof path, "%s/scene.json", in.dir);
    static const char text[] =
        "{\"camera\": {\"eye\": [0, 1, 4], \"look_at\": [0, 0, 0], \"width\": 8, \"height\": 6},"
        " \"environment\": {\"map\": \"sky:16x8\"},"
        " \"objects\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1,"
        "   \"material\": {\"type\": \"conductor\", \"alpha\": 0.3}},"
        "  {\"type\": \"plane\", \"point\": [0, -1, 0], \"normal\": [0, 1, 0],"
        "   \"material\": {\"type\": \"lambert\", \"albedo\": [0.5, 0.5, 0.5]}}]}";
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
    each_allocation_fails("scene file", op_scene_file, NULL);
}

static void renders_of_every_light_kind(void **state)
{
    (void)state;
    each_allocation_fails("scene create", op_scene_create, NULL);
    static const char *const names[] = {"render environment MIS",
                                        "render light set",
                                        "render luminaire",
                                        "render path tracing",
                                        "render stratified light set",
                                        "render pmj02",
                                        "render luminaire, auto"};
    for (int k = 0; k < 7; k++) each_allocation_fails(names[k], op_render, &k);
    each_allocation_fails("G-buffers + upsampling", op_upsample, NULL);
    static const char *const sessions[] = {"session: the map's sampler", "session: median cut",
                                           "session: Wu, upsampled",
                                           "session: Wu, stratified and upsampled"};
    for (int k = 0; k < 4; k++) each_allocation_fails(sessions[k], op_session, &k);
}

/* A photometric file (an IES of a 20 cm disk's road light) read, described, sampled and
 * made a light field; then rendered as a point and as its opening. */
static char *ies_text;
static size_t ies_size;

static lumis_status op_photometric(void *ctx)
{
    (void)ctx;
    lumis_photometric_file *f = NULL;
    lumis_status st = lumis_photometric_read_memory(ies_text, ies_size, "road.ies", NULL, &f);
    lumis_photometric_info info;
    if (st == LUMIS_OK) st = lumis_photometric_get_info(f->model, &info);
    lumis_vec3 d;
    double pdf = 0;
    if (st == LUMIS_OK) st = lumis_photometric_sample(f->model, 0.3, 0.6, &d, &pdf);
    lumis_luminaire *lum = NULL;
    lumis_photometric_light_field lf = {0};
    lf.grid[0] = lf.grid[1] = 2;
    lf.width = lf.height = 6;
    if (st == LUMIS_OK) st = lumis_luminaire_from_photometric(f->model, &lf, NULL, &lum, NULL);
    lumis_luminaire_info li;
    if (st == LUMIS_OK) lumis_luminaire_get_info(lum, &li);
    digest = st == LUMIS_OK ? info.flux + pdf + li.total_power : 0;
    lumis_luminaire_destroy(lum);
    lumis_photometric_file_destroy(f);
    return st;
}

static lumis_status op_render_photometric(void *ctx)
{
    lumis_photometric_file *f = NULL;
    lumis_status st = lumis_photometric_read_memory(ies_text, ies_size, "road.ies", NULL, &f);
    if (st != LUMIS_OK) return st;
    lumis_photometric_instance inst = {0};
    inst.photometric = f->model;
    inst.placement = lumis_rigid_identity();
    inst.placement.t[1] = 3;
    inst.area = *(const int *)ctx;
    const lumis_photometric_lighting lit = {&inst, 1};
    lumis_render_desc d = {0};
    d.camera = &tiny_cam;
    d.lighting.photometric = &lit;
    d.lighting.kind = LUMIS_LIGHTING_PHOTOMETRIC;
    d.spp = 2;
    d.threads = 1;
    d.seed = 7;
    lumis_image *img = NULL;
    st = lumis_render(in.scene, &d, &img, NULL);
    digest = st == LUMIS_OK ? image_digest(img) : 0;
    lumis_image_destroy(img);
    lumis_photometric_file_destroy(f);
    return st;
}

static void photometric_files_and_fixtures(void **state)
{
    (void)state;
    const pg_ies_spec s = {
        PG_ROAD, 0.8, "IESNA:LM-63-2002", 1, 10, 0, 90, 5, 0, 360, 0, 1, -0.2, -0.2,
        0,       2}; /* TILT=INCLUDE too */
    ies_text = pg_ies(&s, &ies_size);
    each_allocation_fails("photometric read, info, sample, light field", op_photometric, NULL);
    int area = 0;
    each_allocation_fails("render photometric point", op_render_photometric, &area);
    area = 1;
    each_allocation_fails("render photometric opening", op_render_photometric, &area);
    free(ies_text);
}

static void map_specs_and_metrics(void **state)
{
    (void)state;
    static const char *const specs[] = {"sky:16x8", "studio:16x8"};
    for (int k = 0; k < 2; k++) each_allocation_fails(specs[k], op_map_spec, (void *)specs[k]);
    each_allocation_fails("delta E + colour map", op_more_metrics, NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(procedural_maps_and_envmap),
        cmocka_unit_test(every_sampler),
        cmocka_unit_test(every_light_set_method),
        cmocka_unit_test(every_image_format),
        cmocka_unit_test_teardown(light_export_luminaire_files_and_metrics, cjson_hooks_off),
        cmocka_unit_test(scene_file),
        cmocka_unit_test(renders_of_every_light_kind),
        cmocka_unit_test(map_specs_and_metrics),
        cmocka_unit_test(photometric_files_and_fixtures),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
