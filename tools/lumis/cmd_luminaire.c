/* lumis luminaire create | info | render: light-field luminaires (lumis/luminaire.h) as
 * files — made by simulated acquisition from a preset's emitter, inspected, and rendered in
 * the headlight scenes. */
#include "cli.h"

#include "lumis/io.h"
#include "lumis/luminaire.h"

#include <cJSON.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: lumis luminaire create OUT.json [--preset P] [--basis B] [--format F]\n"
    "       lumis luminaire create OUT.json --from FILE.ies|FILE.ldt [--grid WxH] [--size WxH]\n"
    "                              [--delta D] [--max-angle DEG] [--error E] [--basis B]\n"
    "                              [--format F]\n"
    "       lumis luminaire info LUMINAIRE [--json]\n"
    "       lumis luminaire predict LUMINAIRE [--distance A,B] [--bands N] [--budget K]\n"
    "                              [--kmax K] [--probes N] [--pilot P] [--seed S]\n"
    "                              [--costs C,IR,IU,R,U,G,RAY] [--json]\n"
    "       lumis luminaire render LUMINAIRE [SCENE.json | --scene NAME] [render options]\n"
    "                              -o OUT.exr\n\n"
    "Light-field luminaires (Goesele et al.'s two-plane model, sampled as Lu et al.: docs/\n"
    "luminaire.md).  LUMINAIRE is a manifest written by 'create' (docs/formats.md) or\n"
    "preset:car, preset:bike, preset:small (acquired on the fly).  'lumis luminaire ACTION\n"
    "--help' prints one action's options:\n\n"
    "create   simulates the acquisition of a preset's emitter, or the light field of a\n"
    "         photometric file's opening, and writes a manifest and its images\n"
    "info     images, grid, delta, basis, units, total power, memory, and the time to read\n"
    "         it and to precompute its tables\n"
    "predict  which sampling strategy pays over a range of distances\n"
    "render   'lumis render --luminaire LUMINAIRE', in the built-in scene headlight unless a\n"
    "         scene is given: every luminaire of the scene is replaced by LUMINAIRE, kept\n"
    "         where the scene places it.  Every option of lumis render applies (--lum-*,\n"
    "         --visibility, --sequence, --spp, --time, --size, -o, --png ...).\n";

/* "WxH", each in [1, max]. */
static int parse_wxh(const char *v, long max, int out[2])
{
    const char *x = v ? strchr(v, 'x') : NULL;
    char first[32];
    if (!x || (size_t)(x - v) >= sizeof first) return 0;
    memcpy(first, v, (size_t)(x - v));
    first[x - v] = '\0';
    long a = 0, b = 0;
    if (!tool_parse_int(first, 1, max, &a) || !tool_parse_int(x + 1, 1, max, &b)) return 0;
    out[0] = (int)a;
    out[1] = (int)b;
    return 1;
}

/* Writes a built luminaire (units: its lengths'), fills *info and destroys it. */
static lumis_status write_and_destroy(const char *out, lumis_luminaire *lum,
                                      lumis_luminaire_write_options *wo, const char *units,
                                      lumis_luminaire_info *info)
{
    wo->errors = tool_errors;
    wo->units = units;
    const lumis_status st = lumis_luminaire_write(out, lum, wo);
    lumis_luminaire_get_info(lum, info);
    lumis_luminaire_destroy(lum);
    return st;
}

/* Adds what the light field of a photometric file carries and how close it is to the
 * manifest ("photometric": docs/formats.md): the luminaire reader ignores it. */
static lumis_status record_photometric(const char *out, const char *from,
                                       const lumis_photometric_light_field_report *r)
{
    size_t n = 0;
    int oom = 0;
    unsigned char *text = tool_read_file(out, &n, &oom);
    cJSON *root = text ? cJSON_ParseWithLength((const char *)text, n) : NULL;
    free(text);
    if (!root) {
        fprintf(stderr, "lumis: luminaire create: cannot read back %s\n", out);
        return LUMIS_ERR_READ;
    }
    cJSON *o = cJSON_AddObjectToObject(root, "photometric");
    cJSON_AddStringToObject(o, "source", from);
    cJSON_AddNumberToObject(o, "flux_lm", r->flux);
    cJSON_AddNumberToObject(o, "light_field_lm", r->light_field_flux);
    cJSON_AddNumberToObject(o, "max_angle_deg", r->max_angle_deg);
    cJSON *res = cJSON_AddObjectToObject(o, "residual");
    cJSON_AddNumberToObject(res, "from_deg", r->ramp_from_deg);
    cJSON_AddNumberToObject(res, "to_deg", r->max_angle_deg);
    cJSON_AddNumberToObject(res, "flux_lm", r->residual_flux);
    cJSON_AddNumberToObject(res, "share", r->residual_share);
    cJSON_AddNumberToObject(o, "error_target", r->error_target);
    cJSON_AddNumberToObject(o, "far_field_error", r->far_field_error);
    cJSON_AddNumberToObject(o, "far_field_error_mean", r->far_field_error_mean);
    cJSON_AddBoolToObject(o, "target_met", r->target_met);
    /* where a near-field fixture hands over from the field to the point model */
    cJSON *nf = cJSON_AddObjectToObject(o, "near_field");
    cJSON_AddNumberToObject(nf, "opening_size_m", r->size);
    cJSON_AddNumberToObject(nf, "crossover_sizes", r->crossover_sizes);
    cJSON_AddNumberToObject(nf, "near_until_m", r->near_until);
    cJSON_AddNumberToObject(nf, "far_from_m", r->far_from);
    char *js = cJSON_Print(root);
    cJSON_Delete(root);
    if (!js) return LUMIS_ERR_OUT_OF_MEMORY;
    const size_t len = strlen(js);
    js[len] = '\0';
    char *nl = malloc(len + 2);
    if (!nl) {
        cJSON_free(js);
        return LUMIS_ERR_OUT_OF_MEMORY;
    }
    memcpy(nl, js, len);
    nl[len] = '\n';
    nl[len + 1] = '\0';
    cJSON_free(js);
    const lumis_status st = lumis_write_text(out, nl, len + 1, &tool_errors);
    free(nl);
    return st;
}

/* What luminaire create is asked: a preset's acquisition, or (--from) a photometric file's
 * light field. */
typedef struct create_opts {
    const char *out, *from, *preset_given;
    lumis_luminaire_preset preset;
    lumis_luminaire_basis basis;
    lumis_luminaire_write_options wo;
    lumis_photometric_light_field lf;
} create_opts;

static int parse_grid(const char *v, void *field)
{
    return parse_wxh(v, 256, field);
}

static int size_option(const char *cmd, const tool_opt *opt, const char *v, void *ctx)
{
    create_opts *o = ctx;
    int wh[2];
    if (!parse_wxh(v, 16384, wh)) return tool_bad_value(cmd, opt->name, v, opt->what);
    o->lf.width = wh[0];
    o->lf.height = wh[1];
    return EXIT_OK;
}

static int parse_preset(const char *v, void *field)
{
    return lumis_luminaire_preset_from_name(v, field) == LUMIS_OK;
}

static int parse_basis(const char *v, void *field)
{
    return strcmp(v, "default") != 0 && lumis_luminaire_basis_from_name(v, field) == LUMIS_OK;
}

static int parse_format(const char *v, void *field)
{
    lumis_file_format *f = field;
    if (strcmp(v, "exr") == 0 || strcmp(v, "pfm") == 0) {
        *f = v[0] == 'e' ? LUMIS_FORMAT_EXR : LUMIS_FORMAT_PFM;
        return 1;
    }
    return 0;
}

static int create_positional(const char *cmd, const char *arg, void *ctx)
{
    create_opts *o = ctx;
    if (o->out) return tool_usage_error(cmd, "unknown argument '%s'", arg);
    o->out = arg;
    return EXIT_OK;
}

#define AT(f) offsetof(create_opts, f)
static const tool_opt create_table[] = {
    {.kind = TOOL_OPT_PARSE,
     .name = "--preset",
     .metavar = "P",
     .help = "car (11x9 images of 256x256, default) or bike (9x7 of 300x300), the\n"
             "sizes of Lu et al.'s Table 1, or small (5x4 of 24x20, for tests)",
     .at = AT(preset),
     .parse = parse_preset,
     .what = "must be car, bike or small",
     .note = TOOL_NOTE(create_opts, preset_given)},
    {.kind = TOOL_OPT_PARSE,
     .name = "--basis",
     .metavar = "B",
     .help = "quadratic (Goesele et al., default) or bspline",
     .at = AT(basis),
     .parse = parse_basis,
     .what = "must be quadratic or bspline"},
    {.kind = TOOL_OPT_PARSE,
     .name = "--format",
     .metavar = "F",
     .help = "exr (default) or pfm images",
     .at = AT(wo.image_format),
     .parse = parse_format,
     .what = "must be exr or pfm"},
    {.kind = TOOL_OPT_GROUP, .name = "a photometric file's light field"},
    {.kind = TOOL_OPT_STRING,
     .name = "--from",
     .metavar = "FILE",
     .help = "instead of a preset: the light field of a photometric file's luminous\n"
             "opening (a disk or a rectangle), every point of which emits the file's\n"
             "distribution (docs/photometric.md, \"Near field\"); in metres",
     .at = AT(from),
     .what = "a file"},
    {.kind = TOOL_OPT_PARSE,
     .name = "--grid",
     .metavar = "WxH",
     .help = "its basis functions (default: 10 along the longer side)",
     .at = AT(lf.grid),
     .parse = parse_grid,
     .what = "must be WxH, each 1 to 256 (1024 in all)"},
    {.kind = TOOL_OPT_CUSTOM,
     .name = "--size",
     .metavar = "WxH",
     .help = "about this many pixels per image (default: from --error)",
     .handle = size_option,
     .what = "must be WxH, each 1 to 16384"},
    {.kind = TOOL_OPT_DOUBLE,
     .name = "--delta",
     .metavar = "D",
     .help = "distance from the opening to the image plane (default twice its size)",
     .at = AT(lf.delta),
     .lo = 0,
     .open_lo = 1,
     .hi = 1e6,
     .what = "a distance"},
    {.kind = TOOL_OPT_DOUBLE,
     .name = "--max-angle",
     .metavar = "A",
     .help = "directions the images cover, in degrees from the aim (default: 99.9 %\n"
             "of the flux + 5, at most 80); the flux beyond is the far-field residual",
     .at = AT(lf.max_angle_deg),
     .lo = 0,
     .open_lo = 1,
     .hi = 90,
     .open_hi = 1,
     .what = "degrees"},
    {.kind = TOOL_OPT_DOUBLE,
     .name = "--error",
     .metavar = "E",
     .help = "far-field relative error the resolution is chosen for (default 0.005)",
     .at = AT(lf.error_target),
     .lo = 0,
     .open_lo = 1,
     .hi = 1,
     .open_hi = 1,
     .what = "a relative error"},
    {0},
};
#undef AT

const tool_optspec tool_luminaire_create_spec = {
    .cmd = "luminaire create",
    .usage = "usage: lumis luminaire create OUT.json [--preset P] [--basis B] [--format F]\n"
             "       lumis luminaire create OUT.json --from FILE.ies|FILE.ldt [--grid WxH]\n"
             "                              [--size WxH] [--delta D] [--max-angle DEG]\n"
             "                              [--error E] [--basis B] [--format F]",
    .intro = "Simulates the acquisition of a preset's emitter (a few bright disks behind a\n"
             "striped lens, like a headlight) through every basis function, or takes the light\n"
             "field of a photometric file's opening (--from), and writes the manifest OUT.json\n"
             "and its images in OUT.images/.",
    .opts = create_table,
    .positional = create_positional,
};

/* The options into *o, checked together, and the files.  Exit code. */
static int parse_create_args(int argc, char **argv, create_opts *o)
{
    lumis_photometric_light_field *lf = &o->lf;
    const int rc = tool_optparse(&tool_luminaire_create_spec, argc - 1, argv + 1, o);
    if (rc >= 0) return rc == EXIT_OK ? -1 : rc;
    const char *out = o->out, *from = o->from;
    if (!out) return tool_usage_error("luminaire create", "no output manifest (OUT.json)");
    size_t n = strlen(out);
    if (n < 5 || strcmp(out + n - 5, ".json") != 0)
        return tool_usage_error("luminaire create", "the manifest must end in .json (got '%s')",
                                out);
    if (from && o->preset_given)
        return tool_usage_error("luminaire create", "--from and --preset: one or the other");
    if (!from && (lf->grid[0] || lf->width || lf->delta > 0 || lf->max_angle_deg > 0 ||
                  lf->error_target > 0))
        return tool_usage_error(
            "luminaire create",
            "--grid, --size, --delta, --max-angle and --error: only with --from");
    tool_files files = {0};
    tool_files_output(&files, "manifest", out, TOOL_OUT_FILE);
    if (from) tool_files_input(&files, "photometric file", from);
    return tool_files_check("luminaire create", &files);
}

/* --from: the photometric file's light field, written with its report. */
static int create_from_photometric(create_opts *o)
{
    const char *out = o->out, *from = o->from;
    lumis_photometric_file *pf = NULL;
    if (lumis_photometric_read(from, &tool_errors, &pf) != LUMIS_OK) return EXIT_RUNTIME;
    o->lf.basis = o->basis;
    double t0 = tool_now_seconds();
    lumis_luminaire *lum = NULL;
    lumis_photometric_light_field_report rep;
    const lumis_status bs =
        lumis_luminaire_from_photometric(pf->model, &o->lf, &tool_errors, &lum, &rep);
    lumis_photometric_file_destroy(pf);
    if (bs != LUMIS_OK) return EXIT_RUNTIME;
    const double t1 = tool_now_seconds();
    lumis_luminaire_info info;
    if (write_and_destroy(out, lum, &o->wo, "m", &info) != LUMIS_OK) return EXIT_RUNTIME;
    if (record_photometric(out, from, &rep) != LUMIS_OK) return EXIT_RUNTIME;
    fprintf(stderr,
            "lumis: the light field of %s: %d x %d images of %d x %d, delta %.4g m, built in "
            "%.2f s; wrote %s and its images in %.2f s\n",
            from, info.grid[0], info.grid[1], info.width, info.height, info.delta, t1 - t0, out,
            tool_now_seconds() - t1);
    fprintf(stderr,
            "lumis: it carries %.2f lm within %.1f deg of the aim (fading from %.1f); the "
            "residual, %.2f lm (%.3f %% of the table's %.2f lm), is the far-field point "
            "(lumis_photometric_beyond); together %+.4f %% of the table\n",
            rep.light_field_flux, rep.max_angle_deg, rep.ramp_from_deg, rep.residual_flux,
            100 * rep.residual_share, rep.flux,
            100 * ((rep.light_field_flux + rep.residual_flux) / rep.flux - 1));
    fprintf(stderr,
            "lumis: far-field error %.3f %% at most, %.3f %% on average over %d directions "
            "(target %.2f %%%s)\n",
            100 * rep.far_field_error, 100 * rep.far_field_error_mean, rep.directions,
            100 * rep.error_target,
            rep.target_met ? ", met" : ": NOT met at the largest images allowed");
    fprintf(stderr,
            "lumis: the field beats the point model out to %.3g opening sizes; a near-field "
            "fixture uses it up to %.3g m and the point model from %.3g m\n",
            rep.crossover_sizes, rep.near_until, rep.far_from);
    return EXIT_OK;
}

/* A preset's images, acquired from its emitter, written. */
static int create_from_preset(create_opts *o)
{
    fprintf(stderr, "lumis: acquiring the %s preset's images from its emitter ...\n",
            lumis_luminaire_preset_name(o->preset));
    double t0 = tool_now_seconds();
    lumis_luminaire *lum = NULL;
    if (lumis_luminaire_preset_create(o->preset, o->basis, &tool_errors, &lum) != LUMIS_OK)
        return EXIT_RUNTIME;
    double t1 = tool_now_seconds();
    lumis_luminaire_info info;
    if (write_and_destroy(o->out, lum, &o->wo, "mm", &info) != LUMIS_OK) return EXIT_RUNTIME;
    fprintf(stderr,
            "lumis: acquired %d images of %d x %d in %.2f s; wrote %s and its images (%s) in "
            "%.2f s\n",
            info.images, info.width, info.height, t1 - t0, o->out,
            o->wo.image_format == LUMIS_FORMAT_PFM ? "PFM" : "EXR", tool_now_seconds() - t1);
    return EXIT_OK;
}

static int create(int argc, char **argv)
{
    create_opts o = {.preset = LUMIS_PRESET_CAR, .basis = LUMIS_BASIS_QUADRATIC};
    o.wo.image_format = LUMIS_FORMAT_EXR;
    const int rc = parse_create_args(argc, argv, &o);
    if (rc != EXIT_OK) return rc < 0 ? EXIT_OK : rc; /* -1: --help */
    return o.from ? create_from_photometric(&o) : create_from_preset(&o);
}

typedef struct info_cli {
    const char *file;
    int json;
} info_cli;

static int info_positional(const char *cmd, const char *arg, void *ctx)
{
    info_cli *c = ctx;
    if (c->file) return tool_usage_error(cmd, "unknown argument '%s'", arg);
    c->file = arg;
    return EXIT_OK;
}

static const tool_opt info_table[] = {
    {.kind = TOOL_OPT_FLAG,
     .name = "--json",
     .help = "print one JSON object (keys: file, units, images, grid, width, height,\n"
             "delta, basis, pixel, total_power, bytes, replaced, read_seconds,\n"
             "precompute_ms)",
     .at = offsetof(info_cli, json)},
    {0},
};

const tool_optspec tool_luminaire_info_spec = {
    .cmd = "luminaire info",
    .usage = "usage: lumis luminaire info LUMINAIRE [--json]",
    .intro =
        "Prints a luminaire's images, grid, delta, basis, units, total power, memory, and the\n"
        "time to read it and to precompute its tables (the median of 3 builds).",
    .opts = info_table,
    .positional = info_positional,
};

static int info(int argc, char **argv)
{
    info_cli c = {0};
    const int rc = tool_optparse(&tool_luminaire_info_spec, argc - 1, argv + 1, &c);
    if (rc >= 0) return rc;
    const char *file = c.file;
    const int json = c.json;
    if (!file) return tool_usage_error("luminaire info", "no luminaire given");
    double t0 = tool_now_seconds();
    lumis_luminaire *lum = NULL;
    if (tool_load_luminaire(file, &lum) != LUMIS_OK) return EXIT_RUNTIME;
    const double read_s = tool_now_seconds() - t0;
    char units[32] = "mm"; /* the presets' */
    if (strncmp(file, "preset:", 7) != 0) {
        lumis_luminaire_manifest *m = NULL;
        if (lumis_luminaire_manifest_read(file, NULL, &m) == LUMIS_OK)
            snprintf(units, sizeof units, "%s", m->units);
        lumis_luminaire_manifest_destroy(m);
    }
    /* The precomputation alone (copies, luminance, summed-area tables): built again from
     * the luminaire's own images, three times, the median. */
    lumis_luminaire_desc d;
    lumis_luminaire_get_desc(lum, &d);
    double ms[3];
    for (int k = 0; k < 3; k++) {
        lumis_luminaire *again = NULL;
        double t = tool_now_seconds();
        lumis_status st = lumis_luminaire_create(&d, &again);
        ms[k] = 1e3 * (tool_now_seconds() - t);
        lumis_luminaire_destroy(again);
        if (st != LUMIS_OK) {
            lumis_luminaire_destroy(lum);
            return tool_runtime_error("%s: rebuilding its tables failed: %s", file,
                                      lumis_status_string(st));
        }
    }
    const double precompute_ms = tool_median(ms, 3);
    lumis_luminaire_info in;
    lumis_luminaire_get_info(lum, &in);
    lumis_luminaire_destroy(lum);
    if (json) {
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "file", file);
        cJSON_AddStringToObject(j, "units", units);
        cJSON_AddNumberToObject(j, "images", in.images);
        cJSON_AddItemToObject(j, "grid", cJSON_CreateIntArray(in.grid, 2));
        cJSON_AddNumberToObject(j, "width", in.width);
        cJSON_AddNumberToObject(j, "height", in.height);
        cJSON_AddNumberToObject(j, "delta", in.delta);
        cJSON_AddStringToObject(j, "basis", lumis_luminaire_basis_name(d.basis));
        cJSON_AddItemToObject(j, "pixel", cJSON_CreateDoubleArray(in.pixel, 2));
        cJSON_AddNumberToObject(j, "total_power", in.total_power);
        cJSON_AddNumberToObject(j, "bytes", (double)in.bytes);
        cJSON_AddNumberToObject(j, "replaced", (double)in.replaced);
        cJSON_AddNumberToObject(j, "read_seconds", read_s);
        cJSON_AddNumberToObject(j, "precompute_ms", precompute_ms);
        char *text = cJSON_PrintUnformatted(j);
        cJSON_Delete(j);
        if (!text) return tool_runtime_error("out of memory");
        puts(text);
        free(text);
        return EXIT_OK;
    }
    printf("file           %s\n", file);
    printf("images         %d (%d x %d basis functions, %s)\n", in.images, in.grid[0], in.grid[1],
           lumis_luminaire_basis_name(d.basis));
    printf("pixels         %d x %d per image, %.4g x %.4g %s each\n", in.width, in.height,
           in.pixel[0], in.pixel[1], units);
    printf("delta          %g %s (U at z = 0, S at z = delta)\n", in.delta, units);
    printf("grid spacing   %g x %g %s\n", d.grid_spacing[0], d.grid_spacing[1], units);
    printf("total power    %.6g (luminance integral of every C_m over S)\n", in.total_power);
    printf("memory         %.1f MB (RGB images and summed-area tables)\n", in.bytes / 1e6);
    printf("replaced       %zu negative or non-finite values\n", in.replaced);
    printf("read           %.3f s%s\n", read_s,
           strncmp(file, "preset:", 7) == 0 ? " (acquired from the emitter)" : "");
    printf("precompute     %.1f ms (tables, median of 3)\n", precompute_ms);
    return EXIT_OK;
}

int cmd_luminaire(int argc, char **argv)
{
    if (argc < 2) {
        fputs(usage, stderr);
        return EXIT_USAGE;
    }
    if (tool_is_help(argv[1])) {
        fputs(usage, stdout);
        return EXIT_OK;
    }
    if (strcmp(argv[1], "create") == 0) return create(argc, argv);
    if (strcmp(argv[1], "info") == 0) return info(argc, argv);
    if (strcmp(argv[1], "predict") == 0) return tool_luminaire_predict(argc, argv);
    if (strcmp(argv[1], "render") == 0) {
        for (int i = 2; i < argc; i++)
            if (tool_is_help(argv[i])) {
                fputs(usage, stdout);
                return EXIT_OK;
            }
        if (argc < 3 || argv[2][0] == '-')
            return tool_usage_error("luminaire render", "no luminaire given");
        /* lumis render --luminaire FILE [--scene headlight] REST */
        char **a = calloc((size_t)argc + 4, sizeof *a);
        if (!a) return tool_runtime_error("out of memory");
        /* A scene: SCENE.json right after the luminaire, or --scene NAME anywhere. */
        int n = 0, scene = argc > 3 && argv[3][0] != '-';
        for (int i = 3; i < argc; i++) scene |= strcmp(argv[i], "--scene") == 0;
        a[n++] = "render";
        a[n++] = "--luminaire";
        a[n++] = argv[2];
        if (!scene) {
            a[n++] = "--scene";
            a[n++] = "headlight";
        }
        for (int i = 3; i < argc; i++) a[n++] = argv[i];
        int rc = cmd_render(n, a);
        free(a);
        return rc;
    }
    return tool_usage_error("luminaire", "unknown action '%s' (create, info, predict or render)",
                            argv[1]);
}
