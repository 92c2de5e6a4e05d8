/* lumis info FILE.ies|FILE.ldt [--json] [--svg OUT.svg]: a photometric file's fixture, its
 * flux from the table against the file's lumens, beam and field angles, and a polar plot of
 * its two principal planes, as photometric tools draw it. */
#include "cli.h"

#include <cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* The planes' names for the file's type. */
static const char *plane_name(lumis_photometric_type t, int k)
{
    if (t == LUMIS_PHOTOMETRIC_C) return k == 0 ? "C0-C180" : "C90-C270";
    return k == 0 ? "V=0 (H)" : "H=0 (V)";
}

/* The number of bytes of s's first n characters (UTF-8 code points; all of s if shorter). */
static size_t utf8_prefix(const char *s, int n)
{
    size_t b = 0;
    for (int k = 0; s[b] && k < n; k++) do
            b++;
        while ((s[b] & 0xC0) == 0x80);
    return b;
}

/* The title in at most two lines of at most `width` characters, broken at a space where one
 * lies in the line's second half; what still does not fit ends in an ellipsis.  Returns the
 * number of lines. */
static int wrap_title(const char *s, int width, char line[2][1200])
{
    int n = 0;
    while (*s && n < 2) {
        while (*s == ' ') s++;
        size_t b = utf8_prefix(s, width);
        const int last = n == 1;
        if (s[b] && last) b = utf8_prefix(s, width - 1); /* room for the ellipsis */
        if (s[b] && s[b] != ' ') { /* break at the last space, if not too early */
            size_t sp = b;
            while (sp > 0 && s[sp] != ' ') sp--;
            if (sp > utf8_prefix(s, width / 2)) b = sp;
        }
        snprintf(line[n], 1200, "%.*s%s", (int)b, s, last && s[b] ? "…" : "");
        s += b;
        n++;
    }
    return n;
}

/* The polar plot: nadir (the aim) down, one curve per principal plane, the radius linear
 * in candela up to a round value above the peak; a title too long for one line wraps onto a
 * second, the plot moving down to make room. */
static int write_svg(const char *path, const char *title, const lumis_photometric *p,
                     const lumis_photometric_info *in)
{
    char line[2][1200] = {{0}};
    /* 13 px sans-serif averages about 7 px a character: 68 fit the 500 px */
    const int lines = wrap_title(title, 68, line);
    const int dy = lines > 1 ? 16 : 0, W = 520, H = 540 + dy;
    const double cx = 260, cy = 250 + dy, R = 200, peak = in->max_candela;
    /* a round scale: 1, 2 or 5 times a power of ten, at or above the peak */
    double top = 1;
    if (peak > 0) {
        const double e = pow(10, floor(log10(peak)));
        top = peak <= e ? e : peak <= 2 * e ? 2 * e : peak <= 5 * e ? 5 * e : 10 * e;
    }
    FILE *t = tmpfile();
    if (!t) return tool_runtime_error("%s: no temporary file", path);
    fprintf(t,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
            "viewBox=\"0 0 %d %d\" font-family=\"sans-serif\" font-size=\"11\">\n",
            W, H, W, H);
    fprintf(t, "<rect width=\"%d\" height=\"%d\" fill=\"white\"/>\n", W, H);
    for (int r = 1; r <= 4; r++) {
        fprintf(t, "<circle cx=\"%g\" cy=\"%g\" r=\"%g\" fill=\"none\" stroke=\"#ccc\"/>\n", cx, cy,
                R * r / 4);
        fprintf(t, "<text x=\"%g\" y=\"%g\" fill=\"#666\">%g cd</text>\n", cx + 3,
                cy - R * r / 4 - 2, top * r / 4);
    }
    for (int a = 0; a < 360; a += 30) {
        const double rad = a * PI / 180, x = cx + R * sin(rad), y = cy + R * cos(rad);
        fprintf(t, "<line x1=\"%g\" y1=\"%g\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#ddd\"/>\n", cx, cy,
                x, y);
        const int shown = a <= 180 ? a : 360 - a;
        fprintf(t, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" fill=\"#666\">%d°</text>\n",
                cx + (R + 14) * sin(rad), cy + (R + 14) * cos(rad) + 4, shown);
    }
    static const char *const style[2] = {"stroke=\"#c0392b\" stroke-width=\"2\"",
                                         "stroke=\"#2471a3\" stroke-width=\"2\" "
                                         "stroke-dasharray=\"6 4\""};
    for (int k = 0; k < 2; k++) {
        fprintf(t, "<polyline fill=\"none\" %s points=\"", style[k]);
        for (int s = 0; s <= 720; s++) {
            const double a = -180.0 + s * 0.5, rad = a * PI / 180;
            const double r = R * lumis_photometric_plane_intensity(p, k, a) / top;
            /* t >= 0 (C0, C90; +H, +V) to the right */
            fprintf(t, "%.1f,%.1f ", cx + r * sin(rad), cy + r * cos(rad));
        }
        fprintf(t, "\"/>\n");
    }
    for (int k = 0; k < lines; k++) {
        fprintf(t, "<text x=\"10\" y=\"%d\" font-size=\"13\">", 18 + 16 * k);
        tool_markup_escape(t, line[k]);
        fputs("</text>\n", t);
    }
    for (int k = 0; k < 2; k++) {
        fprintf(t, "<line x1=\"20\" y1=\"%d\" x2=\"50\" y2=\"%d\" %s/>\n", 485 + dy + 18 * k,
                485 + dy + 18 * k, style[k]);
        fprintf(t, "<text x=\"56\" y=\"%d\">%s: beam %.1f°, field %.1f°</text>\n",
                489 + dy + 18 * k, plane_name(in->type, k), in->beam_deg[k], in->field_deg[k]);
    }
    fprintf(t, "<text x=\"300\" y=\"%d\">%.0f lm, peak %.0f cd</text>\n", 489 + dy, in->flux,
            in->max_candela);
    fprintf(t, "<text x=\"300\" y=\"%d\" fill=\"#666\">0° down (the aim)</text>\n</svg>\n",
            507 + dy);
    return tool_commit_tmp(t, path);
}

/* Why a table has no spacing criterion (lumis_photometric_spacing_criterion), or NULL. */
static const char *spacing_not_applicable(const lumis_photometric_info *in,
                                          const lumis_photometric_ratings *rt)
{
    if (in->type != LUMIS_PHOTOMETRIC_C)
        return "a floodlight (type A or B): its spread on a work plane depends on its aim";
    if (!(in->downward_fraction >= 0.4)) return "under 40 % of the flux goes downward";
    if (rt->spacing[0] > 0 || rt->spacing[1] > 0) return NULL;
    return "no light at nadir";
}

/* The spacing criterion in C0-C180 and C90-C270 as JSON (null: not applicable, and why). */
static void add_spacing_json(cJSON *j, const lumis_photometric_info *in,
                             const lumis_photometric_ratings *rt)
{
    const char *no_sc = spacing_not_applicable(in, rt);
    cJSON *sc = cJSON_AddArrayToObject(j, "spacing_criterion");
    for (int k = 0; k < 2; k++)
        cJSON_AddItemToArray(sc, rt->spacing[k] > 0 ? cJSON_CreateNumber(rt->spacing[k])
                                                    : cJSON_CreateNull());
    if (no_sc)
        cJSON_AddStringToObject(j, "spacing_criterion_not_applicable", no_sc);
    else
        cJSON_AddNullToObject(j, "spacing_criterion_not_applicable");
}

/* The spacing criterion in words. */
static void print_spacing(const lumis_photometric_info *in, const lumis_photometric_ratings *rt)
{
    const char *no_sc = spacing_not_applicable(in, rt);
    if (no_sc) {
        printf("  spacing criterion: not applicable, %s\n", no_sc);
        return;
    }
    printf("  spacing criterion (spacing / mounting height):");
    for (int k = 0; k < 2; k++) {
        printf("%s %s ", k ? "," : "", k ? "C90-C270" : "C0-C180");
        if (rt->spacing[k] > 0)
            printf("%.2f", rt->spacing[k]);
        else
            printf("-");
    }
    printf("\n");
}

/* lumis info --json of a photometric file: what it says and what lumis computes of it. */
static void print_photometric_json(const char *path, const lumis_photometric_file *f,
                                   const lumis_photometric_info *in,
                                   const lumis_photometric_ratings *rt, double diff)
{
    const int type_c = in->type == LUMIS_PHOTOMETRIC_C;
    cJSON *j = cJSON_CreateObject();
    cJSON_AddStringToObject(j, "file", path);
    cJSON_AddStringToObject(j, "format", f->format == LUMIS_PHOTOMETRIC_IES ? "ies" : "ldt");
    cJSON_AddStringToObject(j, "standard", f->standard);
    cJSON_AddStringToObject(j, "manufacturer", f->manufacturer);
    cJSON_AddStringToObject(j, "luminaire", f->luminaire);
    cJSON_AddStringToObject(j, "catalog", f->catalog);
    cJSON_AddStringToObject(j, "lamp", f->lamp);
    cJSON_AddStringToObject(j, "type", lumis_photometric_type_name(in->type));
    cJSON_AddStringToObject(j, "symmetry", lumis_photometric_symmetry_name(in->symmetry));
    cJSON_AddNumberToObject(j, "vertical_angles", in->nv);
    cJSON_AddNumberToObject(j, "horizontal_angles", in->nh);
    cJSON_AddStringToObject(j, "shape", lumis_photometric_shape_name(in->shape));
    double size[3] = {in->width, in->length, in->height};
    cJSON_AddItemToObject(j, "size_m", cJSON_CreateDoubleArray(size, 3));
    cJSON_AddNumberToObject(j, "flux", in->flux);
    if (in->lamp_lumens > 0)
        cJSON_AddNumberToObject(j, "lamp_lumens", in->lamp_lumens);
    else
        cJSON_AddNullToObject(j, "lamp_lumens");
    if (in->luminaire_lumens > 0)
        cJSON_AddNumberToObject(j, "luminaire_lumens", in->luminaire_lumens);
    else
        cJSON_AddNullToObject(j, "luminaire_lumens");
    if (isfinite(diff))
        cJSON_AddNumberToObject(j, "flux_difference", diff);
    else
        cJSON_AddNullToObject(j, "flux_difference");
    cJSON_AddNumberToObject(j, "max_candela", in->max_candela);
    double at[2] = {in->max_h, in->max_v};
    cJSON_AddItemToObject(j, "max_at_deg", cJSON_CreateDoubleArray(at, 2));
    cJSON_AddItemToObject(j, "beam_deg", cJSON_CreateDoubleArray(in->beam_deg, 2));
    cJSON_AddItemToObject(j, "field_deg", cJSON_CreateDoubleArray(in->field_deg, 2));
    cJSON_AddNumberToObject(j, "downward_fraction", in->downward_fraction);
    if (rt->lor > 0)
        cJSON_AddNumberToObject(j, "light_output_ratio", rt->lor);
    else
        cJSON_AddNullToObject(j, "light_output_ratio");
    cJSON_AddNumberToObject(j, "input_watts", f->input_watts);
    if (rt->efficacy > 0)
        cJSON_AddNumberToObject(j, "efficacy_lm_per_w", rt->efficacy);
    else
        cJSON_AddNullToObject(j, "efficacy_lm_per_w");
    cJSON_AddItemToObject(j, "nema_type", cJSON_CreateIntArray(rt->nema, 2));
    if (type_c) {
        cJSON_AddItemToObject(j, "zonal_lm", cJSON_CreateDoubleArray(rt->zonal_lm, 6));
        cJSON *code = cJSON_AddArrayToObject(j, "cie_flux_code"); /* null: undefined */
        for (int k = 0; k < 5; k++)
            cJSON_AddItemToArray(code, rt->cie_flux_code[k] >= 0
                                           ? cJSON_CreateNumber(rt->cie_flux_code[k])
                                           : cJSON_CreateNull());
        const lumis_photometric_lcs *z = &rt->lcs;
        const double zones[10] = {z->fl, z->fm, z->fh,  z->fvh, z->bl,
                                  z->bm, z->bh, z->bvh, z->ul,  z->uh};
        static const char *const zone_names[10] = {"FL", "FM", "FH",  "FVH", "BL",
                                                   "BM", "BH", "BVH", "UL",  "UH"};
        cJSON *bug = cJSON_AddObjectToObject(j, "bug");
        cJSON_AddNumberToObject(bug, "B", rt->bug[0]);
        cJSON_AddNumberToObject(bug, "U", rt->bug[1]);
        cJSON_AddNumberToObject(bug, "G", rt->bug[2]);
        cJSON *zl = cJSON_AddObjectToObject(bug, "zones_lm");
        for (int k = 0; k < 10; k++) cJSON_AddNumberToObject(zl, zone_names[k], zones[k]);
    } else {
        cJSON_AddNullToObject(j, "zonal_lm");
        cJSON_AddNullToObject(j, "cie_flux_code");
        cJSON_AddNullToObject(j, "bug");
    }
    add_spacing_json(j, in, rt);
    cJSON_AddBoolToObject(j, "tilt_included", f->tilt);
    if (f->warning[0])
        cJSON_AddStringToObject(j, "warning", f->warning);
    else
        cJSON_AddNullToObject(j, "warning");
    char *text = cJSON_Print(j);
    if (text) printf("%s\n", text);
    free(text);
    cJSON_Delete(j);
}

/* lumis info of a photometric file, in words; own: the file's own lumens (own_what: which),
 * diff: the table's flux against them. */
static void print_photometric_text(const char *path, const lumis_photometric_file *f,
                                   const lumis_photometric_info *in,
                                   const lumis_photometric_ratings *rt, double own,
                                   const char *own_what, double diff)
{
    const int type_c = in->type == LUMIS_PHOTOMETRIC_C;
    printf("%s: %s, photometric type %s, symmetry %s\n", path, f->standard,
           lumis_photometric_type_name(in->type), lumis_photometric_symmetry_name(in->symmetry));
    if (f->manufacturer[0] || f->luminaire[0])
        printf("  fixture: %s%s%s%s%s\n", f->manufacturer, f->luminaire[0] ? ", " : "",
               f->luminaire, f->catalog[0] ? ", catalogue " : "", f->catalog);
    if (f->lamp[0]) printf("  lamp: %s\n", f->lamp);
    printf("  table: %d vertical angles (%g to %g), %d horizontal (%g to %g)\n", in->nv,
           in->v_first, in->v_last, in->nh, in->h_first, in->h_last);
    printf("  luminous shape: %s", lumis_photometric_shape_name(in->shape));
    if (in->shape != LUMIS_SHAPE_POINT)
        printf(", width %.4g m, length %.4g m, height %.4g m", in->width, in->length, in->height);
    printf("\n  flux: %.6g lm from the table", in->flux);
    if (in->luminaire_lumens > 0) /* a check: the two should agree */
        printf("; the file's %s: %.6g lm (the table's is %+.2f %%)", own_what, own, 100 * diff);
    else if (own > 0) /* the lamps': their ratio is the light output ratio, below */
        printf("; the file's %s: %.6g lm", own_what, own);
    else
        printf("; the file gives no lumens (absolute photometry)");
    printf("\n");
    if (rt->lor > 0) printf("  light output ratio: %.1f %%\n", 100 * rt->lor);
    if (rt->efficacy > 0) printf("  efficacy: %.1f lm/W at %.6g W\n", rt->efficacy, f->input_watts);
    printf("  peak: %.6g cd at %s %g, %s %g\n", in->max_candela, type_c ? "C" : "H", in->max_h,
           type_c ? "gamma" : "V", in->max_v);
    for (int k = 0; k < 2; k++) {
        printf("  %s: beam angle (50 %%) %.1f deg, field angle (10 %%) %.1f deg",
               plane_name(in->type, k), in->beam_deg[k], in->field_deg[k]);
        if (rt->nema[k] > 0) printf(", NEMA %d", rt->nema[k]);
        printf("\n");
    }
    /* a floodlight's light all lies in front of it, whichever way it is aimed */
    printf("  %s: %.1f %% of the flux\n", type_c ? "downward" : "front",
           100 * in->downward_fraction);
    if (type_c) {
        printf("  zonal lumens:");
        for (int k = 0; k < 6; k++)
            printf("%s %d-%d %.1f", k ? "," : "", 30 * k, 30 * k + 30, rt->zonal_lm[k]);
        printf("\n  CIE flux code:");
        for (int k = 0; k < 5; k++) {
            if (rt->cie_flux_code[k] >= 0)
                printf(" %d", rt->cie_flux_code[k]);
            else
                printf(" -");
        }
        const lumis_photometric_lcs *z = &rt->lcs;
        printf("\n  BUG rating (TM-15-11): B%d U%d G%d, forward C270-C90 through C0\n"
               "    lm back BL %.1f BM %.1f BH %.1f BVH %.1f, forward FL %.1f FM %.1f FH %.1f "
               "FVH %.1f, up UL %.1f UH %.1f\n",
               rt->bug[0], rt->bug[1], rt->bug[2], z->bl, z->bm, z->bh, z->bvh, z->fl, z->fm, z->fh,
               z->fvh, z->ul, z->uh);
    }
    print_spacing(in, rt);
    if (f->tilt)
        printf("  tilt: TILT=INCLUDE with %d angles (%g to %g deg, factors %g to %g), "
               "applied by each placed fixture's tilt\n",
               f->ntilt, f->tilt_deg[0], f->tilt_deg[f->ntilt - 1], f->tilt_factor[0],
               f->tilt_factor[f->ntilt - 1]);
}

int tool_photometric_info(const char *path, int json, const char *svg)
{
    lumis_photometric_file *f = NULL;
    if (lumis_photometric_read(path, &tool_errors, &f) != LUMIS_OK) return EXIT_RUNTIME;
    lumis_photometric_info in;
    lumis_photometric_get_info(f->model, &in);
    /* the file's own lumens to compare with: EULUMDAT's luminaire flux (lamps x LOR) when
     * given, else the lamps' (IES: relative photometry) */
    const double own = in.luminaire_lumens > 0 ? in.luminaire_lumens : in.lamp_lumens;
    const char *own_what = in.luminaire_lumens > 0 ? "luminaire flux (lamps x LOR)" : "lamp lumens";
    const double diff = own > 0 ? in.flux / own - 1 : NAN;
    lumis_photometric_ratings rt;
    lumis_photometric_get_ratings(f->model, f->input_watts, &rt);
    int rc = EXIT_OK;
    if (json)
        print_photometric_json(path, f, &in, &rt, diff);
    else
        print_photometric_text(path, f, &in, &rt, own, own_what, diff);
    if (svg) {
        char title[1200];
        snprintf(title, sizeof title, "%s%s%s", f->luminaire[0] ? f->luminaire : path,
                 f->manufacturer[0] ? " - " : "", f->manufacturer);
        rc = write_svg(svg, title, f->model, &in);
        if (rc == EXIT_OK && !json) printf("  polar plot: %s\n", svg);
    }
    lumis_photometric_file_destroy(f);
    return rc;
}

int tool_is_photometric_path(const char *path)
{
    const char *dot = path ? strrchr(path, '.') : NULL;
    if (!dot || strchr(dot, '/')) return 0;
    char ext[8] = {0};
    for (int k = 0; k < 7 && dot[k + 1]; k++) ext[k] = (char)(dot[k + 1] | 0x20);
    return strcmp(ext, "ies") == 0 || strcmp(ext, "ldt") == 0;
}
