/* bench_pick [--size WxH] [--samples N] [--runs R] [--json]: the cost of each method's
 * own choice - the pixel or block and its probability, what Ergun et al. time - without
 * the warp to a direction and the radiance fetch that every method shares.  Together with
 * `lumis bench-samplers` (whole samples) it shows where a sample's time goes. */
#include "bench_common.h"
#include "envmap/sampler_method.h"
#include "lumis/lumis.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char bench_name[] = "bench_pick";

int main(int argc, char **argv)
{
    int w = 2048, h = 1024, runs = 5, json = 0;
    long n = 2000000;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--size") && i + 1 < argc && sscanf(argv[i + 1], "%dx%d", &w, &h) == 2)
            i++;
        else if (!strcmp(argv[i], "--samples") && i + 1 < argc)
            n = atol(argv[++i]);
        else if (!strcmp(argv[i], "--runs") && i + 1 < argc)
            runs = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--json"))
            json = 1;
        else {
            fprintf(stderr, "usage: bench_pick [--size WxH] [--samples N] [--runs R] [--json]\n");
            return 2;
        }
    }
    if (n < 1 || runs < 1 || runs > 101) return 2;
    lumis_sky_desc sd = {0};
    sd.width = w;
    sd.height = h;
    sd.sun_elevation_deg = 35.0f;
    sd.sun_azimuth_deg = 60.0f;
    lumis_image *img = NULL;
    lumis_envmap *env = NULL;
    if (lumis_sky_create(&sd, &img) != LUMIS_OK || lumis_envmap_from_image(img, &env) != LUMIS_OK)
        return 1;
    lumis_image_destroy(img);
    double *u = malloc(sizeof(double) * 2 * (size_t)n), t[101];
    lumis_pcg32 rng;
    lumis_pcg32_seed(&rng, 7, 7);
    for (long k = 0; k < 2 * n; k++) u[k] = lumis_pcg32_double(&rng);
    double base = 0.0;
    if (json) printf("[");
    for (int m = LUMIS_METHOD_INVERSION; m < LUMIS_METHOD_COUNT; m++) {
        lumis_sampler_desc d = {0};
        d.method = (lumis_sampler_method)m;
        lumis_sampler *s = NULL;
        if (lumis_sampler_create(env, &d, &s) != LUMIS_OK) return 1;
        volatile double sink = 0.0;
        for (int r = 0; r < runs; r++) {
            double acc = 0.0, t0 = bench_now();
            lumis__pick p;
            for (long k = 0; k < n; k++) {
                s->m->pick(s, u[2 * k], u[2 * k + 1], &p);
                acc += p.density + p.x0;
            }
            t[r] = (double)n / (bench_now() - t0);
            sink += acc;
        }
        (void)sink;
        qsort(t, (size_t)runs, sizeof(double), bench_cmp_double);
        double med = t[runs / 2];
        if (m == LUMIS_METHOD_INVERSION) base = med;
        if (json)
            printf("%s{\"method\":\"%s\",\"size\":\"%dx%d\",\"picks_per_second\":%.6g,\"vs_"
                   "inversion\":%.4g}",
                   m > LUMIS_METHOD_INVERSION ? "," : "", lumis_sampler_method_name(d.method), w, h,
                   med, med / base);
        else
            printf("%-17s %dx%d  picks/s %10.4g   x inversion %6.2f\n",
                   lumis_sampler_method_name(d.method), w, h, med, med / base);
        lumis_sampler_destroy(s);
    }
    if (json) printf("]\n");
    free(u);
    lumis_envmap_destroy(env);
    return 0;
}
