/* lumis compare REF TEST: every image metric (RMSE, relative MSE, PSNR, CIELAB Delta E,
 * LDR-FLIP, HDR-FLIP), an error map and a difference image. */
#include "cli.h"

#include "lumis/metrics.h"

#include <cJSON.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

/* More than this share of the pixels clamped at the display exposure: a warning. */
#define CLAMP_WARN 0.05

/* The share of the pixels where a channel of the reference or the test, times 2^ev, exceeds
 * 1: what CIELAB and LDR-FLIP see as white. */
static double clamped_fraction(const lumis_image *ref, const lumis_image *test, float ev)
{
    const size_t n = (size_t)ref->width * (size_t)ref->height;
    const float limit = exp2f(-ev);
    size_t c = 0;
    for (size_t p = 0; p < n; p++) {
        const float *a = ref->pixels + 3 * p, *b = test->pixels + 3 * p;
        c += a[0] > limit || a[1] > limit || a[2] > limit || b[0] > limit || b[1] > limit ||
             b[2] > limit;
    }
    return n ? (double)c / (double)n : 0.0;
}

/* What compare is asked. */
typedef struct compare_opts {
    const char *ref_path, *test_path, *map_path, *diff_path;
    int json, hdr_flip, no_hdr_flip, ev_auto;
    float ev;
    double ppd;
} compare_opts;

static int compare_positional(const char *cmd, const char *arg, void *ctx)
{
    compare_opts *o = ctx;
    if (!o->ref_path)
        o->ref_path = arg;
    else if (!o->test_path)
        o->test_path = arg;
    else
        return tool_usage_error(cmd, "unknown argument '%s'", arg);
    return EXIT_OK;
}

#define AT(f) offsetof(compare_opts, f)
static const tool_opt compare_table[] = {
    {.kind = TOOL_OPT_FLAG,
     .name = "--json",
     .help = "print one JSON object (rmse, relmse, psnr, lab_delta_e, flip_ldr,\n"
             "flip_hdr, and the parameters: psnr_peak, exposure_ev, ...)",
     .at = AT(json)},
    {.kind = TOOL_OPT_EXPOSURE,
     .name = "--exposure",
     .metavar = "EV",
     .help = "exposure of the display-referred metrics (CIELAB, LDR-FLIP): stops,\n"
             "or auto (the default, as lumis bench's \"auto\"): the stops that bring\n"
             "the reference's mean luminance to 0.18.  EV 0 is how NVIDIA's\n"
             "reference tool treats linear input; a render in cd/m^2 then clamps\n"
             "almost everywhere (a warning says when more than 5 % of the pixels\n"
             "clamp)",
     .at = AT(ev),
     .at2 = AT(ev_auto)},
    {.kind = TOOL_OPT_DOUBLE,
     .name = "--ppd",
     .metavar = "N",
     .help = "FLIP's pixels per degree (default 67.02: 0.7 m from a 0.7 m wide\n"
             "4K display, as the reference)",
     .at = AT(ppd),
     .lo = 0,
     .open_lo = 1,
     .hi = 10000,
     .what = "pixels per degree"},
    {.kind = TOOL_OPT_STRING,
     .name = "--map",
     .metavar = "OUT.png",
     .help = "FLIP error map (HDR-FLIP; with --no-hdr-flip, LDR-FLIP), magma colours",
     .at = AT(map_path),
     .what = "a file"},
    {.kind = TOOL_OPT_STRING,
     .name = "--diff",
     .metavar = "OUT",
     .help = "per-pixel |test - ref| (linear; .exr/.pfm/.hdr, or .png)",
     .at = AT(diff_path),
     .what = "a file"},
    {.kind = TOOL_OPT_FLAG,
     .name = "--no-hdr-flip",
     .help = "skip HDR-FLIP (it runs LDR-FLIP once per exposure)",
     .at = AT(no_hdr_flip)},
    {0},
};

const tool_optspec tool_compare_spec = {
    .cmd = "compare",
    .usage = "usage: lumis compare REF TEST [--json] [--map OUT.png] [--diff OUT] [options]",
    .intro = "Compares a test image with a reference.  EXR, HDR and PFM inputs are linear; PNG\n"
             "inputs are decoded from sRGB.  Metrics (docs/metrics.md has every definition):\n"
             "  rmse, relmse    on the linear HDR values, all channels; relmse = mean "
             "(t-r)^2/(r^2+0.01)\n"
             "  psnr            10 log10(peak^2 / mse) dB on the linear HDR values, peak = the\n"
             "                  reference's largest channel value (printed with it)\n"
             "  lab_delta_e     mean CIE76 Delta E (D65) of the values x 2^EV clamped to [0, 1]\n"
             "  flip_ldr        LDR-FLIP of the values x 2^EV clamped to [0, 1]\n"
             "  flip_hdr        HDR-FLIP with the reference's default exposure range and ACES",
    .opts = compare_table,
    .positional = compare_positional,
};

/* The options into *o (*help: --help was given, the usage printed).  Exit code. */
static int parse_compare_args(int argc, char **argv, compare_opts *o, int *help)
{
    const int rc = tool_optparse(&tool_compare_spec, argc, argv, o);
    if (rc >= 0) {
        *help = rc == EXIT_OK;
        return rc;
    }
    if (o->no_hdr_flip) o->hdr_flip = 0;
    if (!o->ref_path || !o->test_path)
        return tool_usage_error("compare", "needs REF and TEST images");
    tool_files files = {0};
    tool_files_input(&files, "reference", o->ref_path);
    tool_files_input(&files, "test image", o->test_path);
    tool_files_output(&files, "--map", o->map_path, TOOL_OUT_PNG);
    tool_files_output(&files, "--diff", o->diff_path, TOOL_OUT_IMAGE);
    return tool_files_check("compare", &files);
}

/* The comparison as one JSON object on stdout. */
static void print_compare_json(const compare_opts *o, const lumis_image *ref,
                               const lumis_read_info *ref_info, const lumis_read_info *test_info,
                               const tool_metrics *m, double clamped)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "reference", o->ref_path);
    cJSON_AddStringToObject(j, "test", o->test_path);
    cJSON_AddNumberToObject(j, "width", ref->width);
    cJSON_AddNumberToObject(j, "height", ref->height);
    cJSON_AddNumberToObject(j, "replaced_reference",
                            (double)lumis_replaced_total(ref_info->replaced));
    cJSON_AddNumberToObject(j, "replaced_test", (double)lumis_replaced_total(test_info->replaced));
    cJSON_AddNumberToObject(j, "nonfinite_test",
                            (double)(test_info->replaced.nan + test_info->replaced.inf));
    tool_metrics_json(m, j);
    cJSON_AddBoolToObject(j, "exposure_auto", o->ev_auto);
    cJSON_AddNumberToObject(j, "clamped_fraction", clamped);
    char *text = cJSON_PrintUnformatted(j);
    cJSON_Delete(j);
    if (text) printf("%s\n", text);
    cJSON_free(text);
}

/* The comparison as a table on stdout. */
static void print_compare_text(const compare_opts *o, const lumis_image *ref,
                               const lumis_read_info *ref_info, const lumis_read_info *test_info,
                               const tool_metrics *m, double clamped)
{
    const float ev = o->ev;
    printf("reference    %s (%d x %d)\n", o->ref_path, ref->width, ref->height);
    printf("test         %s\n", o->test_path);
    if (lumis_replaced_total(ref_info->replaced) || lumis_replaced_total(test_info->replaced))
        printf("replaced     %llu reference, %llu test channel values (NaN, Inf or negative: "
               "scored as 0)\n",
               (unsigned long long)lumis_replaced_total(ref_info->replaced),
               (unsigned long long)lumis_replaced_total(test_info->replaced));
    printf("rmse         %.6g   (linear HDR values, all channels)\n", m->err.rmse);
    printf("relmse       %.6g   (mean (t-r)^2 / (r^2 + %g))\n", m->err.relmse,
           m->err.relmse_epsilon);
    printf("psnr         %.4f dB   (linear HDR; peak = reference maximum %.6g)\n", m->err.psnr,
           m->err.psnr_peak);
    printf("exposure     %.4g EV%s   (of CIELAB and LDR-FLIP; %.1f %% of the pixels clamp)\n",
           (double)ev, o->ev_auto ? ", auto" : "", 100.0 * clamped);
    printf("lab_delta_e  %.6g   (CIE76, D65; values x 2^%.4g clamped to [0, 1])\n", m->lab_delta_e,
           (double)ev);
    printf("flip_ldr     %.6g   (LDR-FLIP, %.4g ppd; values x 2^%.4g clamped to [0, 1])\n",
           m->flip_ldr, m->ppd, (double)ev);
    if (m->has_flip_hdr)
        printf("flip_hdr     %.6g   (HDR-FLIP, %.4g ppd, ACES; exposures %.4g to %.4g)\n",
               m->flip_hdr, m->ppd, m->flip_start, m->flip_stop);
}

/* --diff: per-pixel |test - ref|. */
static int write_diff(const char *path, const lumis_image *ref, const lumis_image *test)
{
    int rc = EXIT_OK;
    lumis_image *d = NULL;
    if (lumis_image_create(ref->width, ref->height, &d) != LUMIS_OK) {
        rc = tool_runtime_error("compare: out of memory");
    } else {
        const size_t n = 3 * (size_t)ref->width * (size_t)ref->height;
        for (size_t i = 0; i < n; i++) d->pixels[i] = fabsf(test->pixels[i] - ref->pixels[i]);
        if (tool_write_image(path, d, NULL) != LUMIS_OK) rc = EXIT_RUNTIME;
        lumis_image_destroy(d);
    }
    return rc;
}

int cmd_compare(int argc, char **argv)
{
    compare_opts o = {.hdr_flip = 1, .ev_auto = 1};
    int help = 0;
    int rc = parse_compare_args(argc, argv, &o, &help);
    if (rc != EXIT_OK || help) return rc;
    const char *ref_path = o.ref_path, *test_path = o.test_path;
    lumis_image *ref = NULL, *test = NULL;
    float *map = NULL;
    rc = EXIT_RUNTIME;
    /* A NaN, Inf or negative value is read as 0 (and warned about): the counts are part of
     * the result, since a test image with NaNs would otherwise score as if it were black
     * there. */
    lumis_read_info ref_info, test_info;
    if (tool_load_render(ref_path, &ref, &ref_info) != LUMIS_OK ||
        tool_load_render(test_path, &test, &test_info) != LUMIS_OK)
        goto done;
    if (ref->width != test->width || ref->height != test->height) {
        rc = tool_runtime_error("%s is %d x %d but %s is %d x %d", ref_path, ref->width,
                                ref->height, test_path, test->width, test->height);
        goto done;
    }
    if (o.map_path) map = malloc(sizeof(float) * (size_t)ref->width * (size_t)ref->height);
    if (o.ev_auto) o.ev = tool_auto_exposure(ref);
    tool_metrics m;
    if ((o.map_path && !map) ||
        tool_compare_images(ref, test, o.ev, o.ppd, o.hdr_flip, &m, map) != EXIT_OK)
        goto done;
    /* CIELAB and LDR-FLIP see the values clamped to [0, 1]: where most pixels clamp, they
     * compare two white images and report a fraction of the error. */
    const double clamped = clamped_fraction(ref, test, o.ev);
    if (clamped > CLAMP_WARN)
        fprintf(stderr,
                "lumis: warning: at exposure 2^%.3g, %.1f %% of the pixels clamp at 1, so "
                "lab_delta_e and flip_ldr miss their errors there; try --exposure auto (%.3g) or "
                "lower\n",
                (double)o.ev, 100.0 * clamped, (double)tool_auto_exposure(ref));
    if (o.json)
        print_compare_json(&o, ref, &ref_info, &test_info, &m, clamped);
    else
        print_compare_text(&o, ref, &ref_info, &test_info, &m, clamped);
    rc = EXIT_OK;
    if (o.map_path && tool_write_flip_map(o.map_path, map, ref->width, ref->height) != EXIT_OK)
        rc = EXIT_RUNTIME;
    if (o.diff_path && rc == EXIT_OK) rc = write_diff(o.diff_path, ref, test);
done:
    free(map);
    lumis_image_destroy(ref);
    lumis_image_destroy(test);
    return rc;
}
