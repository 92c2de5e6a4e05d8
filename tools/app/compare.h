/* Every metric of `lumis compare` and of the bench (tools/app/metrics_out.c). */
#ifndef LUMIS_APP_COMPARE_H
#define LUMIS_APP_COMPARE_H

#include "lumis/metrics.h"

struct cJSON;

/* Every metric of `lumis compare`. */
typedef struct tool_metrics {
    lumis_image_error_stats err;
    double lab_delta_e, flip_ldr, flip_hdr, flip_start, flip_stop, ppd;
    int has_flip_hdr;
    float exposure_ev;
} tool_metrics;

/* Computes every metric (HDR-FLIP unless hdr_flip == 0); flip_map (optional, width *
 * height) receives the HDR-FLIP map, or the LDR one without HDR-FLIP.  Exit code. */
int tool_compare_images(const lumis_image *ref, const lumis_image *test, float exposure_ev,
                        double ppd, int hdr_flip, tool_metrics *m, float *flip_map);
/* Adds the metrics and their parameters to a JSON object (struct cJSON). */
void tool_metrics_json(const tool_metrics *m, struct cJSON *o);
/* Writes a FLIP error map as a magma-coloured PNG.  Exit code. */
int tool_write_flip_map(const char *path, const float *map, int width, int height);

#endif
