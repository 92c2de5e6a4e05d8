/* Image comparison as the tools report it (lumis compare, lumis bench): every metric,
 * as text or JSON, and FLIP's error map. */
#include "errors.h"
#include "files.h"
#include "lights.h"
#include "compare.h"

#include "lumis/metrics.h"
#include "lumis/render.h"

#include <cJSON.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- metrics (lumis compare, lumis bench) ---------------------------------------------- */

void tool_metrics_json(const tool_metrics *m, cJSON *o)
{
    cJSON_AddNumberToObject(o, "rmse", m->err.rmse);
    cJSON_AddNumberToObject(o, "mse", m->err.mse);
    cJSON_AddNumberToObject(o, "relmse", m->err.relmse);
    cJSON_AddNumberToObject(o, "relmse_epsilon", m->err.relmse_epsilon);
    if (isfinite(m->err.psnr))
        cJSON_AddNumberToObject(o, "psnr", m->err.psnr);
    else
        cJSON_AddNullToObject(o, "psnr"); /* identical images */
    cJSON_AddNumberToObject(o, "psnr_peak", m->err.psnr_peak);
    cJSON_AddStringToObject(o, "psnr_domain",
                            "linear HDR values, all channels; peak = the reference's largest "
                            "channel value");
    cJSON_AddNumberToObject(o, "lab_delta_e", m->lab_delta_e);
    cJSON_AddStringToObject(o, "lab_domain",
                            "CIE76, D65; linear values x 2^exposure_ev clamped to [0, 1]");
    cJSON_AddNumberToObject(o, "flip_ldr", m->flip_ldr);
    if (m->has_flip_hdr) {
        cJSON_AddNumberToObject(o, "flip_hdr", m->flip_hdr);
        cJSON_AddNumberToObject(o, "flip_hdr_start_exposure", m->flip_start);
        cJSON_AddNumberToObject(o, "flip_hdr_stop_exposure", m->flip_stop);
    } else {
        cJSON_AddNullToObject(o, "flip_hdr");
    }
    cJSON_AddNumberToObject(o, "pixels_per_degree", m->ppd);
    cJSON_AddNumberToObject(o, "exposure_ev", m->exposure_ev);
}

int tool_compare_images(const lumis_image *ref, const lumis_image *test, float exposure_ev,
                        double ppd, int hdr_flip, tool_metrics *m, float *flip_map)
{
    memset(m, 0, sizeof *m);
    m->exposure_ev = exposure_ev;
    m->ppd = ppd > 0.0 ? ppd : LUMIS_FLIP_DEFAULT_PPD;
    lumis_metric_options mo = {0};
    mo.exposure_ev = exposure_ev;
    mo.errors = tool_errors;
    if (lumis_image_errors(ref, test, &mo, &m->err) != LUMIS_OK ||
        lumis_lab_delta_e(ref, test, &mo, NULL, &m->lab_delta_e) != LUMIS_OK)
        return EXIT_RUNTIME;
    lumis_flip_options fo = {0};
    fo.pixels_per_degree = m->ppd;
    fo.errors = tool_errors;
    /* LDR-FLIP on the exposed values (the library clamps to [0, 1]). */
    lumis_image *a = NULL, *b = NULL;
    const lumis_image *ra = ref, *tb = test;
    if (exposure_ev != 0.0f) {
        const size_t n = 3 * (size_t)ref->width * (size_t)ref->height;
        const float k = exp2f(exposure_ev);
        if (lumis_image_create(ref->width, ref->height, &a) != LUMIS_OK ||
            lumis_image_create(test->width, test->height, &b) != LUMIS_OK) {
            lumis_image_destroy(a);
            return tool_runtime_error("compare: out of memory");
        }
        for (size_t i = 0; i < n; i++) {
            a->pixels[i] = ref->pixels[i] * k;
            b->pixels[i] = test->pixels[i] * k;
        }
        ra = a;
        tb = b;
    }
    /* The map gets LDR-FLIP's errors; HDR-FLIP overwrites them when it runs. */
    lumis_status st = lumis_flip_ldr(ra, tb, &fo, flip_map, &m->flip_ldr);
    lumis_image_destroy(a);
    lumis_image_destroy(b);
    if (st != LUMIS_OK) return EXIT_RUNTIME;
    if (hdr_flip) {
        lumis_flip_hdr_result hr;
        lumis_flip_options quiet = fo;
        memset(&quiet.errors, 0, sizeof quiet.errors);
        st = lumis_flip_hdr(ref, test, &quiet, flip_map, NULL, &hr);
        if (st == LUMIS_ERR_INVALID_ARGUMENT) {
            /* A reference mostly black (median luminance 0) has no default exposure range:
             * the other metrics still stand. */
            fprintf(stderr, "lumis: warning: HDR-FLIP skipped: the reference's median "
                            "luminance is 0, so it has no default exposure range\n");
            return EXIT_OK;
        }
        if (st != LUMIS_OK) return tool_runtime_error("HDR-FLIP: %s", lumis_status_string(st));
        m->flip_hdr = hr.mean;
        m->flip_start = hr.start_exposure;
        m->flip_stop = hr.stop_exposure;
        m->has_flip_hdr = 1;
    }
    return EXIT_OK;
}

int tool_write_flip_map(const char *path, const float *map, int width, int height)
{
    lumis_image *rgb = NULL;
    if (lumis_flip_colormap(map, width, height, &rgb) != LUMIS_OK)
        return tool_runtime_error("%s: cannot colour the error map", path);
    /* The colour map is display-referred already: written without a tone map. */
    int rc = tool_write_image(path, rgb, NULL) == LUMIS_OK ? EXIT_OK : EXIT_RUNTIME;
    lumis_image_destroy(rgb);
    return rc;
}
