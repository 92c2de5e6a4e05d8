/* bench_flip REF TEST [--runs R] [--json]: single-threaded time of LDR-FLIP and HDR-FLIP
 * (src/metrics/flip.c) on two images, median, min and max of R runs (default 5).
 * docs/metrics.md gives the commands that make the images it was measured on. */
#include "bench_common.h"
#include "lumis/io.h"
#include "lumis/metrics.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char bench_name[] = "bench_flip";

static const char usage[] = "usage: bench_flip REF TEST [--runs R] [--json]\n\n"
                            "Times lumis_flip_ldr and lumis_flip_hdr (default options) on two "
                            "images of the same size.\n";

static void print_error(void *user, lumis_status status, const char *message)
{
    (void)user;
    (void)status;
    fprintf(stderr, "%s: %s\n", bench_name, message);
}

int main(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL}, *v;
    int runs = 5, json = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            fputs(usage, stdout);
            return 0;
        } else if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (tool_option(argc, argv, &i, "--runs", &v)) {
            if (!bench_parse_int(v, 1, 1000, &runs))
                return bench_usage_error("--runs wants a count in 1..1000");
        } else if (argv[i][0] != '-' && !paths[1]) {
            paths[paths[0] ? 1 : 0] = argv[i];
        } else {
            return bench_usage_error("unknown argument '%s'", argv[i]);
        }
    }
    if (!paths[1]) return bench_usage_error("needs REF and TEST images");
    lumis_read_options ro = {0};
    ro.errors = (lumis_error_sink){print_error, NULL};
    lumis_image *img[2] = {NULL, NULL};
    for (int k = 0; k < 2; k++)
        if (lumis_image_read(paths[k], &ro, &img[k], NULL) != LUMIS_OK) {
            lumis_image_destroy(img[0]);
            return 1;
        }
    lumis_flip_options fo = {0};
    fo.errors = ro.errors;
    double t[2][1000], mean[2] = {0, 0};
    int rc = 0;
    for (int r = 0; r < runs && !rc; r++) {
        double t0 = bench_now();
        rc |= lumis_flip_ldr(img[0], img[1], &fo, NULL, &mean[0]) != LUMIS_OK;
        double t1 = bench_now();
        lumis_flip_hdr_result hr;
        rc |= lumis_flip_hdr(img[0], img[1], &fo, NULL, NULL, &hr) != LUMIS_OK;
        t[0][r] = t1 - t0;
        t[1][r] = bench_now() - t1;
        mean[1] = hr.mean;
    }
    if (!rc) {
        char cpu[256];
        bench_cpu_model(cpu, sizeof cpu);
        const char *names[2] = {"ldr", "hdr"};
        if (json)
            printf("{\"width\": %d, \"height\": %d, \"cpu\": \"%s\"", img[0]->width, img[0]->height,
                   cpu);
        else
            printf("%s: %d x %d, %d runs, one thread, %s\n", bench_name, img[0]->width,
                   img[0]->height, runs, cpu);
        for (int k = 0; k < 2; k++) {
            qsort(t[k], (size_t)runs, sizeof(double), bench_cmp_double);
            double med = t[k][runs / 2], lo = t[k][0], hi = t[k][runs - 1];
            if (json)
                printf(", \"%s_seconds\": {\"median\": %.6f, \"min\": %.6f, \"max\": %.6f}, "
                       "\"flip_%s\": %.6f",
                       names[k], med, lo, hi, names[k], mean[k]);
            else
                printf("  %s-FLIP  median %.3f s  min %.3f s  max %.3f s  (mean FLIP %.5f)\n",
                       k ? "HDR" : "LDR", med, lo, hi, mean[k]);
        }
        if (json) printf("}\n");
    }
    lumis_image_destroy(img[0]);
    lumis_image_destroy(img[1]);
    return rc;
}
