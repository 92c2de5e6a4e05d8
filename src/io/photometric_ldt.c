/* EULUMDAT (.ldt) photometric files: the format's fixed lines, read into the far-field
 * model; the line-and-number reading and the entry points are photometric_file.c's, which
 * also reads IES LM-63.  Every failure names the file, the line and the field. */
#include "lumis/io.h"

#include "../core/internal.h"
#include "internal.h"
#include "photometric_text.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Line k (0-based) as a number for field; errors name it. */
static lumis_status ldt_number(text *t, int k, const char *field, double *v)
{
    if (k >= t->nlines)
        return lumis__fail(t->errors, LUMIS_ERR_TRUNCATED, "%s: the file ends before line %d (%s)",
                           t->name, k + 1, field);
    cursor c = {t, k, NULL};
    c.p = t->line[k];
    /* one number per line: the cursor must not run on into the next line */
    char *s = c.p;
    while (*s && isspace((unsigned char)*s)) s++;
    if (!*s)
        return lumis__fail(t->errors, LUMIS_ERR_CORRUPT, "%s:%d: %s: an empty line", t->name, k + 1,
                           field);
    for (char *q = s; *q; q++)
        if (*q == ',') *q = '.'; /* decimal commas are common in EULUMDAT */
    return lumis__pf_read_number(&c, field, v, NULL);
}

static lumis_status ldt_count(text *t, int k, const char *field, int lo, int hi, int *v)
{
    double x;
    lumis_status st = ldt_number(t, k, field, &x);
    if (st != LUMIS_OK) return st;
    if (x != floor(x) || x < lo || x > hi)
        return lumis__fail(t->errors, LUMIS_ERR_BAD_DIMENSIONS,
                           "%s:%d: %s: %g: expected a whole number from %d to %d", t->name, k + 1,
                           field, x, lo, hi);
    *v = (int)x;
    return LUMIS_OK;
}

/* A table whose flux disagrees with the file's own declared luminaire flux (EULUMDAT: the
 * first set's lamp flux x LOR) is most often read wrongly, or written so: said in the
 * file's warning, for every program that reads it to show. */
static void declared_flux_check(lumis_photometric_file *f, const text *t, double declared)
{
    const char *name = t->name;
    lumis_photometric_info info;
    if (!(declared > 0) || lumis_photometric_get_info(f->model, &info) != LUMIS_OK) return;
    const double off = info.flux / declared - 1.0;
    if (fabs(off) > LUMIS_PHOTOMETRIC_FLUX_TOLERANCE)
        snprintf(f->warning, sizeof f->warning,
                 "%s: the table's flux, %.6g lm, is %+.1f %% off the %.6g lm the file declares "
                 "(lamp flux x LOR): the file may be written or read wrongly",
                 name, info.flux, 100.0 * off, declared);
    if (f->warning[0]) lumis__fail(t->errors, LUMIS_OK, "%s", f->warning); /* a warning */
}

lumis_status lumis__pf_read_ldt(text *t, lumis_photometric_file *f)
{
    snprintf(f->standard, sizeof f->standard, "EULUMDAT");
    int ityp = 0, isym = 0, mc = 0, ng = 0, nsets = 0;
    double dims[9], dff, lor, conv, tilt;
    lumis_status st = ldt_count(t, 1, "the type indicator Ityp", 0, 3, &ityp);
    if (st == LUMIS_OK) st = ldt_count(t, 2, "the symmetry indicator Isym", 0, 4, &isym);
    if (st == LUMIS_OK) st = ldt_count(t, 3, "the number of C-planes Mc", 1, 3600, &mc);
    if (st == LUMIS_OK) st = ldt_count(t, 5, "the intensities per C-plane Ng", 2, 3600, &ng);
    if (st != LUMIS_OK) return st;
    if (t->nlines < 26)
        return lumis__fail(t->errors, LUMIS_ERR_TRUNCATED,
                           "%s: %d lines: EULUMDAT's header alone has 26", t->name, t->nlines);
    lumis__pf_copy_field(f->manufacturer, sizeof f->manufacturer, t->line[0]);
    lumis__pf_copy_field(f->test, sizeof f->test, t->line[7]);
    lumis__pf_copy_field(f->luminaire, sizeof f->luminaire, t->line[8]);
    lumis__pf_copy_field(f->catalog, sizeof f->catalog, t->line[9]);
    static const char *const dim_names[9] = {"the luminaire's length (mm)",
                                             "the luminaire's width (mm)",
                                             "the luminaire's height (mm)",
                                             "the luminous area's length (mm)",
                                             "the luminous area's width (mm)",
                                             "the luminous area's height at C0 (mm)",
                                             "the luminous area's height at C90 (mm)",
                                             "the luminous area's height at C180 (mm)",
                                             "the luminous area's height at C270 (mm)"};
    for (int k = 0; k < 9 && st == LUMIS_OK; k++) {
        st = ldt_number(t, 12 + k, dim_names[k], &dims[k]);
        if (st == LUMIS_OK && dims[k] < 0)
            st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT, "%s:%d: %s is %g: expected >= 0",
                             t->name, 13 + k, dim_names[k], dims[k]);
    }
    if (st == LUMIS_OK) st = ldt_number(t, 21, "the downward flux fraction DFF (%)", &dff);
    if (st == LUMIS_OK) st = ldt_number(t, 22, "the light output ratio LORL (%)", &lor);
    if (st == LUMIS_OK) st = ldt_number(t, 23, "the conversion factor for intensities", &conv);
    if (st == LUMIS_OK) st = ldt_number(t, 24, "the tilt during measurement", &tilt);
    if (st == LUMIS_OK) st = ldt_count(t, 25, "the number of lamp sets n", 1, 100, &nsets);
    if (st != LUMIS_OK) return st;
    if (st == LUMIS_OK && !(conv > 0))
        st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                         "%s:24: the conversion factor for intensities is %g: expected > 0",
                         t->name, conv);
    if (st != LUMIS_OK) return st;
    f->lamp_sets = nsets;
    /* Set by set, six lines each: number of lamps, type, total flux, colour temperature,
     * colour rendering, wattage (the format's items 26a-f; real files with 2 and 3 sets
     * agree).  The intensities are given for the first set. */
    const int base = 26;
    double flux = 0, watts = 0;
    int lamps = 0; /* negative: absolute photometry (LEDs) */
    for (int set = 0; set < nsets && st == LUMIS_OK; set++) {
        const int at = base + 6 * set;
        char field[96];
        int n = 0;
        double lm = 0, w = 0;
        snprintf(field, sizeof field, "the number of lamps of set %d", set + 1);
        st = ldt_count(t, at, field, -1000000, 1000000, &n);
        if (st == LUMIS_OK) {
            snprintf(field, sizeof field, "the lamps' total flux of set %d (lm)", set + 1);
            st = ldt_number(t, at + 2, field, &lm);
        }
        if (st == LUMIS_OK) {
            snprintf(field, sizeof field, "the wattage of set %d (W)", set + 1);
            st = ldt_number(t, at + 5, field, &w);
        }
        if (st == LUMIS_OK && set == 0) {
            lamps = n;
            flux = lm;
            watts = w;
            lumis__pf_copy_field(f->lamp, sizeof f->lamp, t->line[at + 1]);
        }
    }
    if (st == LUMIS_OK && !(flux > 0))
        st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                         "%s:%d: the lamps' total flux of set 1 is %g lm: the intensities are per "
                         "1000 lm of it, so it must be > 0",
                         t->name, base + 3, flux);
    if (st != LUMIS_OK) return st;
    f->lamps = lamps;
    f->lumens_per_lamp = lamps != 0 ? flux / abs(lamps) : flux;
    f->input_watts = watts;
    /* then the numbers: 10 direct ratios, Mc C angles, Ng gamma angles, the intensities */
    cursor c = {t, base + 6 * nsets, NULL};
    const int c_at = c.line + 10 + 1; /* after the 10 direct ratios, one a line */
    for (int k = c.line; k < t->nlines; k++)
        for (char *q = t->line[k]; *q; q++)
            if (*q == ',') *q = '.';
    double dr;
    for (int k = 0; k < 10 && st == LUMIS_OK; k++)
        st = lumis__pf_read_number(&c, "the direct ratios", &dr, NULL);
    double *cang = malloc(sizeof(double) * (size_t)mc), *g = malloc(sizeof(double) * (size_t)ng);
    int planes = isym == 0 ? mc : isym == 1 ? 1 : isym == 4 ? mc / 4 + 1 : mc / 2 + 1;
    double *cd = malloc(sizeof(double) * (size_t)planes * (size_t)ng);
    if (!cang || !g || !cd)
        st = lumis__fail(t->errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", t->name);
    if (st == LUMIS_OK) st = lumis__pf_read_angles(&c, "the C-plane angles", mc, cang);
    if (st == LUMIS_OK) st = lumis__pf_read_angles(&c, "the gamma angles", ng, g);
    if (st == LUMIS_OK && (isym == 2 || isym == 3 || isym == 4) && mc % (isym == 4 ? 4 : 2) != 0)
        st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                         "%s:4: symmetry %d with %d C-planes: their number must divide by %d",
                         t->name, isym, mc, isym == 4 ? 4 : 2);
    /* the planes the intensities are given for must be the ones the symmetry names */
    const int from = isym == 3 ? mc / 4 : 0;
    static const double range[5][2] = {{0, 0}, {0, 0}, {0, 180}, {90, 270}, {0, 90}};
    if (st == LUMIS_OK && isym >= 2 &&
        (from + planes > mc || cang[from] != range[isym][0] ||
         cang[from + planes - 1] != range[isym][1]))
        st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                         "%s:%d: symmetry %d gives the planes C%g to C%g, but its %d C-planes "
                         "put C%g to C%g there",
                         t->name, c_at, isym, range[isym][0], range[isym][1], mc,
                         cang[from < mc ? from : mc - 1],
                         cang[from + planes - 1 < mc ? from + planes - 1 : mc - 1]);
    for (int k = 0; k < planes * ng && st == LUMIS_OK; k++) {
        char field[96];
        snprintf(field, sizeof field, "intensity %d of %d x %d (cd/klm)", k + 1, planes, ng);
        int at = 0;
        st = lumis__pf_read_number(&c, field, &cd[k], &at);
        if (st == LUMIS_OK && cd[k] < 0)
            st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                             "%s:%d: %s is %g: intensities cannot be negative", t->name, at, field,
                             cd[k]);
    }
    if (st == LUMIS_OK && lumis__pf_trailing_value(&c))
        st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                         "%s:%d: more values after the %d x %d intensities symmetry %d gives",
                         t->name, c.line + 1, planes, ng, isym);
    if (st == LUMIS_OK) st = lumis__pf_check_light(t, cd, (size_t)planes * (size_t)ng);
    if (st == LUMIS_OK) {
        /* the C angles of the planes given: all, C0 alone, C0-C180, C90-C270 or C0-C90 */
        double hz0 = 0;
        lumis_photometric_desc d = {0};
        d.type = LUMIS_PHOTOMETRIC_C;
        d.nv = ng;
        d.nh = planes;
        d.v_deg = g;
        d.h_deg = isym == 1 ? &hz0 : cang + from;
        d.candela = cd;
        d.multiplier = flux / 1000.0 * conv;
        d.lamp_lumens = lamps < 0 ? -1.0 : flux; /* absolute photometry: no lamp lumens */
        d.luminaire_lumens = lor > 0 ? flux * lor / 100.0 : -1.0;
        /* the luminous area: length along C0 (x), width along C90 (y); width 0: round */
        const double lum_len = dims[3] / 1000.0, lum_w = dims[4] / 1000.0;
        double hmax = 0;
        for (int k = 5; k < 9; k++) hmax = dims[k] > hmax ? dims[k] : hmax;
        d.length = lum_len;
        d.width = lum_w > 0 ? lum_w : lum_len;
        d.height = hmax / 1000.0;
        d.shape = lum_len == 0                 ? LUMIS_SHAPE_POINT
                  : lum_w == 0 && d.height > 0 ? LUMIS_SHAPE_CYLINDER
                  : lum_w == 0                 ? LUMIS_SHAPE_DISK
                  : d.height > 0               ? LUMIS_SHAPE_BOX
                                               : LUMIS_SHAPE_RECTANGLE;
        st = lumis__pf_create_model(t, c_at, &d, &f->model);
        if (st == LUMIS_OK) declared_flux_check(f, t, d.luminaire_lumens);
    }
    free(cang);
    free(g);
    free(cd);
    return st;
}
