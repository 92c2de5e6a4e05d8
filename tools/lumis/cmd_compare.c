/* lumis compare REF TEST: every image metric (RMSE, relative MSE, PSNR, CIELAB Delta E,
 * LDR-FLIP, HDR-FLIP), an error map and a difference image. */
#include "cli.h"

#include "lumis/metrics.h"

#include <cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char usage[] =
    "usage: lumis compare REF TEST [--json] [--map OUT.png] [--diff OUT] [options]\n\n"
    "Compares a test image with a reference.  EXR, HDR and PFM inputs are linear; PNG\n"
    "inputs are decoded from sRGB.  Metrics (docs/metrics.md has every definition):\n"
    "  rmse, relmse    on the linear HDR values, all channels; relmse = mean (t-r)^2/(r^2+0.01)\n"
    "  psnr            10 log10(peak^2 / mse) dB on the linear HDR values, peak = the\n"
    "                  reference's largest channel value (printed with it)\n"
    "  lab_delta_e     mean CIE76 Delta E (D65) of the values x 2^EV clamped to [0, 1]\n"
    "  flip_ldr        LDR-FLIP of the values x 2^EV clamped to [0, 1]\n"
    "  flip_hdr        HDR-FLIP with the reference's default exposure range and ACES\n\n"
    "options:\n"
    "  --json          print one JSON object (rmse, relmse, psnr, lab_delta_e, flip_ldr,\n"
    "                  flip_hdr, and the parameters: psnr_peak, exposure_ev, ...)\n"
    "  --exposure EV   exposure of the display-referred metrics (CIELAB, LDR-FLIP): stops,\n"
    "                  or auto (the default, as lumis bench's \"auto\"): the stops that bring\n"
    "                  the reference's mean luminance to 0.18.  EV 0 is how NVIDIA's\n"
    "                  reference tool treats linear input; a render in cd/m^2 then clamps\n"
    "                  almost everywhere (a warning says when more than 5 % of the pixels\n"
    "                  clamp)\n"
    "  --ppd N         FLIP's pixels per degree (default 67.02: 0.7 m from a 0.7 m wide\n"
    "                  4K display, as the reference)\n"
    "  --map OUT.png   FLIP error map (HDR-FLIP; with --no-hdr-flip, LDR-FLIP), magma colours\n"
    "  --diff OUT      per-pixel |test - ref| (linear; .exr/.pfm/.hdr, or .png)\n"
    "  --no-hdr-flip   skip HDR-FLIP (it runs LDR-FLIP once per exposure)\n";

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

int cmd_compare(int argc, char **argv)
{
    const char *ref_path = NULL, *test_path = NULL, *map_path = NULL, *diff_path = NULL, *v;
    int json = 0, hdr_flip = 1, ev_auto = 1;
    float ev = 0.0f;
    double ppd = 0.0;
    for (int i = 1; i < argc; i++) {
        if (tool_is_help(argv[i])) {
            fputs(usage, stdout);
            return EXIT_OK;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (strcmp(argv[i], "--no-hdr-flip") == 0) {
            hdr_flip = 0;
        } else if (tool_option(argc, argv, &i, "--exposure", &v)) {
            const int erc = tool_exposure_option("compare", v, &ev, &ev_auto);
            if (erc != EXIT_OK) return erc;
        } else if (tool_option(argc, argv, &i, "--ppd", &v)) {
            if (!tool_parse_double(v, &ppd) || !(ppd > 0.0) || ppd > 10000)
                return tool_bad_value("compare", "--ppd", v, "needs pixels per degree");
        } else if (tool_option(argc, argv, &i, "--map", &v)) {
            if (!v || !*v) return tool_bad_value("compare", "--map", v, "needs a file");
            map_path = v;
        } else if (tool_option(argc, argv, &i, "--diff", &v)) {
            if (!v || !*v) return tool_bad_value("compare", "--diff", v, "needs a file");
            diff_path = v;
        } else if (argv[i][0] != '-' && !ref_path) {
            ref_path = argv[i];
        } else if (argv[i][0] != '-' && !test_path) {
            test_path = argv[i];
        } else {
            return tool_usage_error("compare", "unknown argument '%s'", argv[i]);
        }
    }
    if (!ref_path || !test_path) return tool_usage_error("compare", "needs REF and TEST images");
    tool_files files = {0};
    tool_files_input(&files, "reference", ref_path);
    tool_files_input(&files, "test image", test_path);
    tool_files_output(&files, "--map", map_path, TOOL_OUT_PNG);
    tool_files_output(&files, "--diff", diff_path, TOOL_OUT_IMAGE);
    int rc = tool_files_check("compare", &files);
    if (rc != EXIT_OK) return rc;
    lumis_image *ref = NULL, *test = NULL;
    float *map = NULL;
    rc = EXIT_RUNTIME;
    /* A NaN, Inf or negative value is read as 0 (and warned about): the counts are part of
     * the result, since a test image with NaNs would otherwise score as if it were black
     * there. */
    lumis_read_info ref_info, test_info;
    if (tool_load_image(ref_path, &ref, &ref_info) != LUMIS_OK ||
        tool_load_image(test_path, &test, &test_info) != LUMIS_OK)
        goto done;
    if (ref->width != test->width || ref->height != test->height) {
        rc = tool_runtime_error("%s is %d x %d but %s is %d x %d", ref_path, ref->width,
                                ref->height, test_path, test->width, test->height);
        goto done;
    }
    if (map_path) map = malloc(sizeof(float) * (size_t)ref->width * (size_t)ref->height);
    if (ev_auto) ev = tool_auto_exposure(ref);
    tool_metrics m;
    if ((map_path && !map) || tool_compare_images(ref, test, ev, ppd, hdr_flip, &m, map) != EXIT_OK)
        goto done;
    /* CIELAB and LDR-FLIP see the values clamped to [0, 1]: where most pixels clamp, they
     * compare two white images and report a fraction of the error. */
    const double clamped = clamped_fraction(ref, test, ev);
    if (clamped > CLAMP_WARN)
        fprintf(stderr,
                "lumis: warning: at exposure 2^%.3g, %.1f %% of the pixels clamp at 1, so "
                "lab_delta_e and flip_ldr miss their errors there; try --exposure auto (%.3g) or "
                "lower\n",
                (double)ev, 100.0 * clamped, (double)tool_auto_exposure(ref));
    if (json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "reference", ref_path);
        cJSON_AddStringToObject(o, "test", test_path);
        cJSON_AddNumberToObject(o, "width", ref->width);
        cJSON_AddNumberToObject(o, "height", ref->height);
        cJSON_AddNumberToObject(o, "replaced_reference",
                                (double)lumis_replaced_total(ref_info.replaced));
        cJSON_AddNumberToObject(o, "replaced_test",
                                (double)lumis_replaced_total(test_info.replaced));
        cJSON_AddNumberToObject(o, "nonfinite_test",
                                (double)(test_info.replaced.nan + test_info.replaced.inf));
        tool_metrics_json(&m, o);
        cJSON_AddBoolToObject(o, "exposure_auto", ev_auto);
        cJSON_AddNumberToObject(o, "clamped_fraction", clamped);
        char *text = cJSON_PrintUnformatted(o);
        cJSON_Delete(o);
        if (text) printf("%s\n", text);
        cJSON_free(text);
    } else {
        printf("reference    %s (%d x %d)\n", ref_path, ref->width, ref->height);
        printf("test         %s\n", test_path);
        if (lumis_replaced_total(ref_info.replaced) || lumis_replaced_total(test_info.replaced))
            printf("replaced     %llu reference, %llu test channel values (NaN, Inf or negative: "
                   "scored as 0)\n",
                   (unsigned long long)lumis_replaced_total(ref_info.replaced),
                   (unsigned long long)lumis_replaced_total(test_info.replaced));
        printf("rmse         %.6g   (linear HDR values, all channels)\n", m.err.rmse);
        printf("relmse       %.6g   (mean (t-r)^2 / (r^2 + %g))\n", m.err.relmse,
               m.err.relmse_epsilon);
        printf("psnr         %.4f dB   (linear HDR; peak = reference maximum %.6g)\n", m.err.psnr,
               m.err.psnr_peak);
        printf("exposure     %.4g EV%s   (of CIELAB and LDR-FLIP; %.1f %% of the pixels clamp)\n",
               (double)ev, ev_auto ? ", auto" : "", 100.0 * clamped);
        printf("lab_delta_e  %.6g   (CIE76, D65; values x 2^%.4g clamped to [0, 1])\n",
               m.lab_delta_e, (double)ev);
        printf("flip_ldr     %.6g   (LDR-FLIP, %.4g ppd; values x 2^%.4g clamped to [0, 1])\n",
               m.flip_ldr, m.ppd, (double)ev);
        if (m.has_flip_hdr)
            printf("flip_hdr     %.6g   (HDR-FLIP, %.4g ppd, ACES; exposures %.4g to %.4g)\n",
                   m.flip_hdr, m.ppd, m.flip_start, m.flip_stop);
    }
    rc = EXIT_OK;
    if (map_path && tool_write_flip_map(map_path, map, ref->width, ref->height) != EXIT_OK)
        rc = EXIT_RUNTIME;
    if (diff_path && rc == EXIT_OK) {
        lumis_image *d = NULL;
        if (lumis_image_create(ref->width, ref->height, &d) != LUMIS_OK) {
            rc = tool_runtime_error("compare: out of memory");
        } else {
            const size_t n = 3 * (size_t)ref->width * (size_t)ref->height;
            for (size_t i = 0; i < n; i++) d->pixels[i] = fabsf(test->pixels[i] - ref->pixels[i]);
            if (tool_write_image(diff_path, d, NULL) != LUMIS_OK) rc = EXIT_RUNTIME;
            lumis_image_destroy(d);
        }
    }
done:
    free(map);
    lumis_image_destroy(ref);
    lumis_image_destroy(test);
    return rc;
}
