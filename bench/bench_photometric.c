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
 *   bench_photometric [--json] FILE...   the study
 *   bench_photometric --light-field [--target E] [--corrected] [--max-gamma DEG] FILE...
 *       the light field (+ residual) against the exact opening and the point model;
 *       --corrected: the field plus a signed point of the table's intensity less the
 *       field's own far field (the field's irradiance 1000 sizes away) instead of the
 *       residual, so that its far field is the table's (a study of issue 34's item 7);
 *       --max-gamma: only the receivers within DEG of the aim; --near-field: a column for
 *       the near-field fixture (lumis_photometric_near_irradiance: the field up to the
 *       crossover its report measured, the point beyond, blended between) */
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
        /* a 40 x 20 cm road light throwing towards C0, I0 cos (1 + 0.8 sin cos C): no
         * symmetry, 1 x 5 degree table */
        {"road.ies",
         {PG_ROAD, 0.8, "IESNA:LM-63-2002", 1, 91, 0, 90, 73, 0, 360, 0, 0, 0.2, 0.4, 0, 2}},
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
    lumis_photometric_file_destroy(f);
    return 0;
}

/* ---- the light field against the exact opening and the point model --------------------
 * For each distance D (in sizes), on receivers facing the fixture in every direction of its
 * field (gamma 0 to 85 in 5 degree steps, C every 15, I >= 10 % of the peak): the light
 * field plus its far-field residual (the table beyond its cone, as a point) against the
 * exact opening (lumis_photometric_irradiance, 24 x 24 panels), and the point model
 * against the same; the largest and the mean |model / exact - 1|. */
static const double lf_ratios[] = {1, 2, 3, 5, 7, 10, 15, 20, 30, 50};
#define NLR ((int)(sizeof lf_ratios / sizeof lf_ratios[0]))

static int light_field_study(const char *path, int json, double target, int corrected,
                             int nearfield, double max_gamma, int last)
{
    lumis_photometric_file *f = NULL;
    lumis_error_sink sink = {0};
    if (lumis_photometric_read(path, &sink, &f) != LUMIS_OK)
        return bench_fail("cannot read %s", path);
    lumis_photometric_info in;
    lumis_photometric_get_info(f->model, &in);
    const double size = fmax(in.width, in.length);
    lumis_photometric_light_field lf = {0};
    lf.error_target = target;
    lumis_photometric_light_field_report rep;
    lumis_luminaire *lum = NULL;
    const double t0 = bench_now();
    if (lumis_luminaire_from_photometric(f->model, &lf, &sink, &lum, &rep) != LUMIS_OK) {
        lumis_photometric_file_destroy(f);
        return bench_fail("no light field for %s", path);
    }
    const double build_s = bench_now() - t0;
    lumis_photometric *res = NULL;
    if (rep.residual_flux > 0 &&
        lumis_photometric_beyond(f->model, rep.ramp_from_deg, rep.max_angle_deg, &sink, &res) !=
            LUMIS_OK) {
        lumis_luminaire_destroy(lum);
        lumis_photometric_file_destroy(f);
        return bench_fail("no residual for %s", path);
    }
    const double res_flux = res ? lumis_photometric_flux(res) : 0.0;
    double lfmax[NLR], lfmean[NLR], ptmax[NLR], ptmean[NLR], nfmax[NLR], nfmean[NLR];
    int nrec = 0;
    const double t1 = bench_now();
    for (int r = 0; r < NLR; r++) {
        const double D = lf_ratios[r] * size;
        lfmax[r] = lfmean[r] = ptmax[r] = ptmean[r] = nfmax[r] = nfmean[r] = 0;
        int n = 0;
        for (int gi = 0; gi <= 17; gi++)
            for (int ci = 0; ci < 24; ci++) {
                const double g = 5.0 * gi * PI / 180, c = 15.0 * ci * PI / 180;
                if (gi == 0 && ci > 0) break;
                if (5.0 * gi > max_gamma) continue;
                const double w[3] = {sin(g) * cos(c), sin(g) * sin(c), -cos(g)};
                const lumis_vec3 wd = {(float)w[0], (float)w[1], (float)w[2]};
                if (lumis_photometric_intensity(f->model, wd) < 0.1 * in.max_candela) continue;
                const lumis_vec3 x = {(float)(D * w[0]), (float)(D * w[1]), (float)(D * w[2])},
                                 nn = {(float)-w[0], (float)-w[1], (float)-w[2]};
                double exact = 0, point = 0, resid = 0;
                lumis_photometric_irradiance(f->model, 1, x, nn, 24, &exact);
                lumis_photometric_irradiance(f->model, 0, x, nn, 0, &point);
                if (res) lumis_photometric_irradiance(res, 0, x, nn, 0, &resid);
                const lumis_vec3 xl = {x.x, -x.y, -x.z}, nl = {nn.x, -nn.y, -nn.z};
                lumis_rgb e;
                lumis_luminaire_irradiance(lum, xl, nl, 0, &e);
                if (!(exact > 0)) continue;
                double model = e.g + resid;
                if (corrected) { /* the field's own far field, 1000 sizes away, as a point */
                    const double Df = 1000.0 * size;
                    const lumis_vec3 xf = {(float)(Df * w[0]), (float)(-Df * w[1]),
                                           (float)(-Df * w[2])};
                    lumis_rgb ef;
                    lumis_luminaire_irradiance(lum, xf, nl, 0, &ef);
                    model = e.g + point - ef.g * (Df / D) * (Df / D);
                }
                const double el = fabs(model / exact - 1), ep = fabs(point / exact - 1);
                if (nearfield) { /* the near-field fixture: field near, point far, blended */
                    double nf = 0;
                    lumis_photometric_near_irradiance(f->model, lum, &rep, x, nn, &nf);
                    nfmax[r] = fmax(nfmax[r], fabs(nf / exact - 1));
                    nfmean[r] += fabs(nf / exact - 1);
                }
                lfmax[r] = fmax(lfmax[r], el);
                ptmax[r] = fmax(ptmax[r], ep);
                lfmean[r] += el;
                ptmean[r] += ep;
                n++;
            }
        if (n) {
            lfmean[r] /= n;
            ptmean[r] /= n;
            nfmean[r] /= n;
        }
        nrec = n;
    }
    const double study_s = bench_now() - t1;
    lumis_luminaire_info li;
    lumis_luminaire_get_info(lum, &li);
    if (json) {
        printf("  {\"file\": \"%s\", \"flux\": %.8g, \"light_field_flux\": %.8g, "
               "\"residual_flux\": %.8g, \"residual_table_flux\": %.8g, \"max_angle_deg\": %.4g, "
               "\"grid\": [%d, %d], \"image\": [%d, %d], \"delta\": %.5g, \"bytes\": %zu, "
               "\"error_target\": %g, \"far_field_error\": %.5g, \"far_field_error_mean\": %.5g, "
               "\"receivers\": %d, \"build_seconds\": %.3g, \"study_seconds\": %.3g, "
               "\"crossover_sizes\": %.5g, \"near_until_sizes\": %.5g, "
               "\"far_from_sizes\": %.5g, \"distances\": [",
               path, rep.flux, rep.light_field_flux, rep.residual_flux, res_flux, rep.max_angle_deg,
               rep.grid[0], rep.grid[1], rep.width, rep.height, rep.delta, li.bytes,
               rep.error_target, rep.far_field_error, rep.far_field_error_mean, nrec, build_s,
               study_s, rep.crossover_sizes, rep.near_until / size, rep.far_from / size);
        for (int r = 0; r < NLR; r++)
            printf("%s{\"sizes\": %g, \"light_field_max\": %.5g, \"light_field_mean\": %.5g, "
                   "\"point_max\": %.5g, \"point_mean\": %.5g",
                   r ? ", " : "", lf_ratios[r], lfmax[r], lfmean[r], ptmax[r], ptmean[r]);
        for (int r = 0; r < NLR; r++)
            if (nearfield)
                printf(", \"near_field_max\": %.5g, \"near_field_mean\": %.5g}", nfmax[r],
                       nfmean[r]);
            else
                printf("}");
        printf("]}%s\n", last ? "" : ",");
    } else {
        printf("%s: %s %.3g m, %.1f lm; light field %d x %d images of %d x %d, delta %.3g m, "
               "%.0f MB, within %.1f deg (built in %.2f s)\n",
               path, lumis_photometric_shape_name(in.shape), size, rep.flux, rep.grid[0],
               rep.grid[1], rep.width, rep.height, rep.delta, li.bytes / 1e6, rep.max_angle_deg,
               build_s);
        printf("  power: light field %.2f + residual %.2f (its table %.2f) = %.2f lm, the table "
               "%.2f lm (%+.4f %%)\n",
               rep.light_field_flux, rep.residual_flux, res_flux, rep.light_field_flux + res_flux,
               rep.flux, 100 * ((rep.light_field_flux + res_flux) / rep.flux - 1));
        printf("  far-field error %.3f %% max, %.3f %% mean (target %.2f %%, %s)\n",
               100 * rep.far_field_error, 100 * rep.far_field_error_mean, 100 * rep.error_target,
               rep.target_met ? "met" : "not met");
        if (nearfield)
            printf("  near-field fixture: crossover %.3g sizes; the field up to %.3g sizes, the "
                   "point from %.3g\n",
                   rep.crossover_sizes, rep.near_until / size, rep.far_from / size);
        printf("  D / size   light field max / mean   point max / mean%s   (%d receivers)\n",
               nearfield ? "   near-field fixture max / mean" : "", nrec);
        for (int r = 0; r < NLR; r++) {
            printf("  %6.0f     %7.3f %% / %7.3f %%    %7.3f %% / %7.3f %%", lf_ratios[r],
                   100 * lfmax[r], 100 * lfmean[r], 100 * ptmax[r], 100 * ptmean[r]);
            if (nearfield)
                printf("    %7.3f %% / %7.3f %%%s\n", 100 * nfmax[r], 100 * nfmean[r],
                       nfmax[r] <= fmin(lfmax[r], ptmax[r]) * 1.0001 ? "" : "   <- not the closer");
            else
                printf("%s\n",
                       lfmax[r] < ptmax[r] && lfmean[r] < ptmean[r] ? "" : "   <- not below");
        }
    }
    lumis_photometric_destroy(res);
    lumis_luminaire_destroy(lum);
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
    int json = 0, nfiles = 0, lfmode = 0, corrected = 0, nearfield = 0;
    double target = 0, max_gamma = 85;
    const char *files[16];
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--light-field") == 0) {
            lfmode = 1;
            continue;
        }
        if (strcmp(argv[i], "--near-field") == 0) {
            nearfield = 1;
            continue;
        }
        if (strcmp(argv[i], "--corrected") == 0) {
            corrected = 1;
            continue;
        }
        if (strcmp(argv[i], "--max-gamma") == 0 && i + 1 < argc) {
            max_gamma = atof(argv[++i]);
            continue;
        }
        if (strcmp(argv[i], "--target") == 0 && i + 1 < argc) {
            target = atof(argv[++i]);
            continue;
        }
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
    if (lfmode) {
        if (json) printf("{\"machine\": \"%s\", \"light_fields\": [\n", cpu);
        for (int k = 0; k < nfiles; k++)
            if (light_field_study(files[k], json, target, corrected, nearfield, max_gamma,
                                  k + 1 == nfiles))
                return 1;
        if (json) printf("]}\n");
        return 0;
    }
    if (json) printf("{\"machine\": \"%s\", \"distances_in_sizes\": [", cpu);
    for (int r = 0; json && r < NR; r++) printf("%s%g", r ? ", " : "", ratios[r]);
    if (json) printf("], \"fixtures\": [\n");
    for (int k = 0; k < nfiles; k++) {
        curve cv;
        memset(&cv, 0, sizeof cv);
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
            char w1[32]; /* JSON has no NaN: null */
            num_or_null(w1, sizeof w1, cv.within_1pct);
            printf("], \"within_1pct_from_sizes\": %s, \"seconds\": %.3g}%s\n", w1, secs,
                   k + 1 < nfiles ? "," : "");
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
        }
    }
    if (json) printf("]}\n");
    return 0;
}
