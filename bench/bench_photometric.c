/* bench_photometric: how close to a fixture its point model is wrong.  For each photometric
 * file, the illuminance of the point model (I cos / d^2) against the near-field model (the
 * file's luminous opening, every point of it emitting the file's distribution:
 * lumis_photometric_irradiance), on receivers facing the fixture at distance D in every
 * direction of its beam (intensity >= 10 % of the peak, the field), for D from half to 20
 * times the opening's largest dimension; and where the error falls below 1 %, against
 * photometry's rule of thumb (five times the largest dimension).  Then the light field made
 * from the file (lumis_luminaire_from_photometric) against the near field at 1 and 5 sizes.
 *
 *   bench_photometric --fixtures DIR     writes the five study fixtures (a narrow spot, a
 *                                        wide flood, a batwing street light, a linear
 *                                        fixture, and one with a cusp at its aim) as IES
 *                                        files into DIR
 *   bench_photometric [--json] FILE...   the study */
#include "bench_common.h"
#include "photometric_gen.h"

#include "lumis/io.h"
#include "lumis/luminaire.h"
#include "lumis/photometry.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

const char bench_name[] = "bench_photometric";

static const double ratios[] = {0.5, 0.75, 1, 1.5, 2, 3, 4, 5, 6, 8, 10, 15, 20};
#define NR ((int)(sizeof ratios / sizeof ratios[0]))

static int write_fixtures(const char *dir)
{
    const struct {
        const char *name;
        pg_ies_spec spec;
    } fx[] = {
        /* a 10 cm round spot, cos^50: beam 19 degrees */
        {"narrow-spot.ies",
         {PG_SPOT, 50, "IESNA:LM-63-2002", 1, 181, 0, 90, 1, 0, 0, 0, 0, -0.1, -0.1, 0, 2}},
        /* a 60 cm square Lambertian panel */
        {"wide-flood.ies",
         {PG_LAMBERT, 0, "IESNA:LM-63-2002", 1, 91, 0, 90, 1, 0, 0, 0, 0, 0.6, 0.6, 0, 2}},
        /* a 50 x 25 cm street light throwing off its axis: a batwing, I0 cos (1 + 3 sin^2) */
        {"batwing-street.ies",
         {PG_BATWING, 3, "IESNA:LM-63-2002", 1, 91, 0, 90, 1, 0, 0, 0, 0, 0.25, 0.5, 0, 2}},
        /* a 1.2 m x 5 cm linear fixture, wider across its length (sin^2 C): quadrant form */
        {"linear.ies",
         {PG_LINEAR, 1.5, "IESNA:LM-63-2002", 1, 91, 0, 90, 19, 0, 90, 0, 0, 0.05, 1.2, 0, 2}},
        /* the same size, its intensity with a cusp at the aim, I0 cos (1 + b sin g cos^2 C):
         * rising linearly with the angle from the aim, as a cone */
        {"linear-cusp.ies",
         {PG_QUAD, 0.9, "IESNA:LM-63-2002", 1, 91, 0, 90, 19, 0, 90, 0, 0, 0.05, 1.2, 0, 2}},
    };
    for (size_t k = 0; k < sizeof fx / sizeof fx[0]; k++) {
        size_t n = 0;
        char *text = pg_ies(&fx[k].spec, &n), path[4200];
        snprintf(path, sizeof path, "%s/%s", dir, fx[k].name);
        if (!text || lumis_write_text(path, text, n, NULL) != LUMIS_OK) {
            free(text);
            return bench_fail("cannot write %s", path);
        }
        free(text);
        printf("wrote %s\n", path);
    }
    return 0;
}

typedef struct curve {
    double max_err[NR], nadir_err[NR];
    double at_gamma[NR], at_c[NR]; /* where the largest error is */
    double within_1pct;            /* the distance (in sizes) from which every error <= 1 % */
    double lf_err[2];              /* the light field against the near field, at 1 and 5 sizes */
} curve;

static double err_at(const lumis_photometric *p, double D, double g, double c)
{
    const double gr = g * PI / 180, cr = c * PI / 180;
    const lumis_vec3 w = {(float)(sin(gr) * cos(cr)), (float)(sin(gr) * sin(cr)), (float)-cos(gr)};
    const lumis_vec3 x = {(float)(D * w.x), (float)(D * w.y), (float)(D * w.z)};
    const lumis_vec3 n = {-w.x, -w.y, -w.z};
    double near = 0, point = 0;
    lumis_photometric_irradiance(p, 1, x, n, 24, &near);
    lumis_photometric_irradiance(p, 0, x, n, 0, &point);
    return near > 0 ? point / near - 1 : 0.0;
}

static int study(const char *path, curve *cv, lumis_photometric_info *in)
{
    lumis_photometric_file *f = NULL;
    lumis_error_sink sink = {0};
    if (lumis_photometric_read(path, &sink, &f) != LUMIS_OK)
        return bench_fail("cannot read %s", path);
    lumis_photometric_get_info(f->model, in);
    const double size = fmax(in->width, in->length);
    memset(cv, 0, sizeof *cv);
    for (int r = 0; r < NR; r++) {
        const double D = ratios[r] * size;
        for (int gi = 0; gi <= 17; gi++) /* gamma 0 to 85, C every 15 */
            for (int ci = 0; ci < 24; ci++) {
                const double g = 5.0 * gi, c = 15.0 * ci;
                if (gi == 0 && ci > 0) break;
                const lumis_vec3 w = {(float)(sin(g * PI / 180) * cos(c * PI / 180)),
                                      (float)(sin(g * PI / 180) * sin(c * PI / 180)),
                                      (float)-cos(g * PI / 180)};
                if (lumis_photometric_intensity(f->model, w) < 0.1 * in->max_candela) continue;
                const double e = err_at(f->model, D, g, c);
                if (fabs(e) > fabs(cv->max_err[r])) {
                    cv->max_err[r] = e;
                    cv->at_gamma[r] = g;
                    cv->at_c[r] = c;
                }
                if (gi == 0) cv->nadir_err[r] = e;
            }
    }
    /* from which distance on every error stays within 1 %: interpolated in log D */
    cv->within_1pct = NAN;
    for (int r = NR - 1; r >= 0; r--) {
        if (fabs(cv->max_err[r]) > 0.01) {
            if (r + 1 < NR) {
                const double a = log(fabs(cv->max_err[r])), b = log(fabs(cv->max_err[r + 1]));
                const double t = (log(0.01) - a) / (b - a);
                cv->within_1pct = exp(log(ratios[r]) + t * (log(ratios[r + 1]) - log(ratios[r])));
            }
            break;
        }
        if (r == 0) cv->within_1pct = ratios[0];
    }
    /* the light field against the near field, at the peak's direction */
    lumis_luminaire *lum = NULL;
    if (lumis_luminaire_from_photometric(f->model, NULL, &sink, &lum) == LUMIS_OK) {
        const double ds[2] = {1, 5};
        for (int k = 0; k < 2; k++) {
            const double D = ds[k] * size, g = in->max_v * PI / 180, c = in->max_h * PI / 180;
            const double wx = sin(g) * cos(c), wy = sin(g) * sin(c), wz = -cos(g);
            const lumis_vec3 x = {(float)(D * wx), (float)(D * wy), (float)(D * wz)},
                             n = {(float)-wx, (float)-wy, (float)-wz};
            double near = 0;
            lumis_photometric_irradiance(f->model, 1, x, n, 24, &near);
            /* the light field's frame: the fixture's turned half a turn about x */
            const lumis_vec3 xl = {x.x, -x.y, -x.z}, nl = {n.x, -n.y, -n.z};
            lumis_rgb e;
            lumis_luminaire_irradiance(lum, xl, nl, 0, &e);
            cv->lf_err[k] = near > 0 ? e.g / near - 1 : NAN;
        }
        lumis_luminaire_destroy(lum);
    } else {
        cv->lf_err[0] = cv->lf_err[1] = NAN;
    }
    lumis_photometric_file_destroy(f);
    return 0;
}

static void num_or_null(char *buf, size_t cap, double v)
{
    if (isfinite(v))
        snprintf(buf, cap, "%.4g", v);
    else
        snprintf(buf, cap, "null");
}

int main(int argc, char **argv)
{
    int json = 0, nfiles = 0;
    const char *files[16];
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--fixtures") == 0 && i + 1 < argc) return write_fixtures(argv[i + 1]);
        if (strcmp(argv[i], "--json") == 0)
            json = 1;
        else if (argv[i][0] != '-' && nfiles < 16)
            files[nfiles++] = argv[i];
        else
            return bench_usage_error(
                "usage: bench_photometric --fixtures DIR | [--json] FILE.ies...");
    }
    if (!nfiles)
        return bench_usage_error("usage: bench_photometric --fixtures DIR | [--json] FILE.ies...");
    char cpu[256];
    bench_cpu_model(cpu, sizeof cpu);
    if (json) printf("{\"machine\": \"%s\", \"distances_in_sizes\": [", cpu);
    for (int r = 0; json && r < NR; r++) printf("%s%g", r ? ", " : "", ratios[r]);
    if (json) printf("], \"fixtures\": [\n");
    for (int k = 0; k < nfiles; k++) {
        curve cv;
        lumis_photometric_info in;
        const double t0 = bench_now();
        if (study(files[k], &cv, &in)) return 1;
        const double secs = bench_now() - t0;
        const double size = fmax(in.width, in.length);
        if (json) {
            printf("  {\"file\": \"%s\", \"shape\": \"%s\", \"size_m\": %g, \"flux\": %.6g, "
                   "\"beam_deg\": %.4g, \"field_deg\": %.4g, \"max_error\": [",
                   files[k], lumis_photometric_shape_name(in.shape), size, in.flux, in.beam_deg[0],
                   in.field_deg[0]);
            for (int r = 0; r < NR; r++) printf("%s%.5g", r ? ", " : "", cv.max_err[r]);
            printf("], \"nadir_error\": [");
            for (int r = 0; r < NR; r++) printf("%s%.5g", r ? ", " : "", cv.nadir_err[r]);
            printf("], \"worst_gamma_deg\": [");
            for (int r = 0; r < NR; r++) printf("%s%g", r ? ", " : "", cv.at_gamma[r]);
            char w1[32], l0[32], l1[32]; /* JSON has no NaN: null */
            num_or_null(w1, sizeof w1, cv.within_1pct);
            num_or_null(l0, sizeof l0, cv.lf_err[0]);
            num_or_null(l1, sizeof l1, cv.lf_err[1]);
            printf("], \"within_1pct_from_sizes\": %s, \"light_field_error\": [%s, %s], "
                   "\"seconds\": %.3g}%s\n",
                   w1, l0, l1, secs, k + 1 < nfiles ? "," : "");
        } else {
            printf("%s: %s %.3g m, %.0f lm, beam %.1f deg, field %.1f deg (%.2f s)\n", files[k],
                   lumis_photometric_shape_name(in.shape), size, in.flux, in.beam_deg[0],
                   in.field_deg[0], secs);
            printf("  D / size   max |point / near - 1| in the field (at gamma)   at nadir\n");
            for (int r = 0; r < NR; r++)
                printf("  %6.2f     %9.3f %%  (%2.0f deg)                          %8.3f %%\n",
                       ratios[r], 100 * cv.max_err[r], cv.at_gamma[r], 100 * cv.nadir_err[r]);
            printf("  every error within 1 %% from %.2f sizes on (the rule of thumb: 5)\n",
                   cv.within_1pct);
            printf("  light field against the near field at the peak: %+.2f %% at 1 size, %+.2f "
                   "%% at 5\n",
                   100 * cv.lf_err[0], 100 * cv.lf_err[1]);
        }
    }
    if (json) printf("]}\n");
    return 0;
}
