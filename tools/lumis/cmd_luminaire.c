/* lumis luminaire create | info | render: light-field luminaires (lumis/luminaire.h) as
 * files — made by simulated acquisition from a preset's emitter, inspected, and rendered in
 * the headlight scenes. */
#include "cli.h"

#include "lumis/io.h"
#include "lumis/luminaire.h"

#include <cJSON.h>
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
    "preset:car, preset:bike, preset:small (acquired on the fly).\n\n"
    "create   simulates the acquisition of a preset's emitter (a few bright disks behind a\n"
    "         striped lens, like a headlight) through every basis function and writes the\n"
    "         manifest OUT.json and its images in OUT.images/\n"
    "  --preset P     car (11x9 images of 256x256, default) or bike (9x7 of 300x300), the\n"
    "                 sizes of Lu et al.'s Table 1, or small (5x4 of 24x20, for tests)\n"
    "  --basis B      quadratic (Goesele et al., default) or bspline\n"
    "  --format F     exr (default) or pfm images\n"
    "  --from FILE    instead of a preset: the light field of a photometric file's luminous\n"
    "                 opening (a disk or a rectangle), every point of which emits the file's\n"
    "                 distribution (docs/photometric.md, \"Near field\"); in metres\n"
    "  --grid WxH     its basis functions (default: 10 along the longer side)\n"
    "  --size WxH     about this many pixels per image (default: from --error)\n"
    "  --delta D      distance from the opening to the image plane (default twice its size)\n"
    "  --max-angle A  directions the images cover, in degrees from the aim (default: 99.9 %\n"
    "                 of the flux + 5, at most 80); the flux beyond is the far-field residual\n"
    "  --error E      far-field relative error the resolution is chosen for (default 0.005)\n"
    "info     images, grid, delta, basis, units, total power, memory, and the time to read\n"
    "         it and to precompute its tables (the median of 3 builds)\n"
    "  --json         print one JSON object (keys: file, units, images, grid, width, height,\n"
    "                 delta, basis, pixel, total_power, bytes, replaced, read_seconds,\n"
    "                 precompute_ms)\n"
    "predict  which sampling strategy pays (docs/luminaire.md, \"Which strategy pays\"): for\n"
    "         points lit by the luminaire at distances A to B from it, facing it, the relative\n"
    "         variance and the predicted time of restricted, uniform and global sampling, and how\n"
    "         many times less time than global each needs for an equal error (xglob)\n"
    "  --distance A,B  in the luminaire's units (default 2 to 50 times its delta)\n"
    "  --bands N       split the range in N bands, evenly in log distance (default 1)\n"
    "  --budget K      samples per point, restricted and uniform (default 32); --kmax their cap\n"
    "  --probes N      points per band (default 256); --pilot P pilot samples per image (16)\n"
    "  --costs ...     the cost model, ns: camera ray, per image (restricted, uniform), per\n"
    "                  draw (restricted, uniform, global), per shadow ray (default: measured\n"
    "                  on the headlight scene; docs/luminaire.md)\n"
    "  --json          one JSON object: file, budget, k_max, probes, and per band: distance,\n"
    "                  probes_lit, energy_share, images_lit, best, and for restricted, uniform\n"
    "                  and global: samples, rays, variance, ns, time_ratio, sample_ratio\n"
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

/* The options into *o, checked together, and the files.  Exit code. */
static int parse_create_args(int argc, char **argv, create_opts *o)
{
    const char *v;
    lumis_photometric_light_field *lf = &o->lf;
    for (int i = 2; i < argc; i++) {
        if (tool_option(argc, argv, &i, "--from", &v)) {
            if (!v || !*v) return tool_bad_value("luminaire create", "--from", v, "needs a file");
            o->from = v;
        } else if (tool_option(argc, argv, &i, "--grid", &v)) {
            if (!parse_wxh(v, 256, lf->grid))
                return tool_bad_value("luminaire create", "--grid", v,
                                      "must be WxH, each 1 to 256 (1024 in all)");
        } else if (tool_option(argc, argv, &i, "--size", &v)) {
            int wh[2];
            if (!parse_wxh(v, 16384, wh))
                return tool_bad_value("luminaire create", "--size", v,
                                      "must be WxH, each 1 to 16384");
            lf->width = wh[0];
            lf->height = wh[1];
        } else if (tool_option(argc, argv, &i, "--delta", &v)) {
            if (!tool_parse_double(v, &lf->delta) || !(lf->delta > 0) || lf->delta > 1e6)
                return tool_bad_value("luminaire create", "--delta", v, "must be a distance > 0");
        } else if (tool_option(argc, argv, &i, "--max-angle", &v)) {
            if (!tool_parse_double(v, &lf->max_angle_deg) || !(lf->max_angle_deg > 0) ||
                !(lf->max_angle_deg < 90))
                return tool_bad_value("luminaire create", "--max-angle", v,
                                      "must be degrees between 0 and 90");
        } else if (tool_option(argc, argv, &i, "--error", &v)) {
            if (!tool_parse_double(v, &lf->error_target) || !(lf->error_target > 0) ||
                !(lf->error_target < 1))
                return tool_bad_value("luminaire create", "--error", v,
                                      "must be a relative error between 0 and 1");
        } else if (tool_option(argc, argv, &i, "--preset", &v)) {
            o->preset_given = v;
            if (!v || lumis_luminaire_preset_from_name(v, &o->preset) != LUMIS_OK)
                return tool_bad_value("luminaire create", "--preset", v,
                                      "must be car, bike or small");
        } else if (tool_option(argc, argv, &i, "--basis", &v)) {
            if (!v || strcmp(v, "default") == 0 ||
                lumis_luminaire_basis_from_name(v, &o->basis) != LUMIS_OK)
                return tool_bad_value("luminaire create", "--basis", v,
                                      "must be quadratic or bspline");
        } else if (tool_option(argc, argv, &i, "--format", &v)) {
            if (v && strcmp(v, "exr") == 0)
                o->wo.image_format = LUMIS_FORMAT_EXR;
            else if (v && strcmp(v, "pfm") == 0)
                o->wo.image_format = LUMIS_FORMAT_PFM;
            else
                return tool_bad_value("luminaire create", "--format", v, "must be exr or pfm");
        } else if (argv[i][0] != '-' && !o->out) {
            o->out = argv[i];
        } else {
            return tool_usage_error("luminaire create", "unknown argument '%s'", argv[i]);
        }
    }
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
    if (rc != EXIT_OK) return rc;
    return o.from ? create_from_photometric(&o) : create_from_preset(&o);
}

static int info(int argc, char **argv)
{
    const char *file = NULL;
    int json = 0;
    for (int i = 2; i < argc; i++) {
        if (strcmp(argv[i], "--json") == 0)
            json = 1;
        else if (argv[i][0] != '-' && !file)
            file = argv[i];
        else
            return tool_usage_error("luminaire info", "unknown argument '%s'", argv[i]);
    }
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
    if (argc < 2 || tool_is_help(argv[1])) {
        fputs(usage, argc < 2 ? stderr : stdout);
        return argc < 2 ? EXIT_USAGE : EXIT_OK;
    }
    for (int i = 2; i < argc; i++)
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        }
    if (strcmp(argv[1], "create") == 0) return create(argc, argv);
    if (strcmp(argv[1], "info") == 0) return info(argc, argv);
    if (strcmp(argv[1], "predict") == 0) return tool_luminaire_predict(argc, argv);
    if (strcmp(argv[1], "render") == 0) {
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
