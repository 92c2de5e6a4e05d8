/* Photometric files from analytic distributions (photometric_gen.h). */
#include "photometric_gen.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI  3.14159265358979323846
#define DEG (PI / 180.0)
#define I0  1000.0

double pg_intensity(pg_dist d, double a, double c_deg, double g_deg)
{
    const double g = g_deg * DEG, c = c_deg * DEG, cg = cos(g), sg = sin(g);
    if (d == PG_AIMED) return cg > 0 ? I0 * cg : 0.0; /* g: the angle to the aim */
    if (d == PG_FLOOD)                                /* (c, g) = (H, V) */
        return fabs(c_deg) <= 90 && fabs(g_deg) <= 90 ? I0 * cos(c) * pow(fabs(cg), a) : 0.0;
    if (cg <= 0) return 0.0;
    switch (d) {
    case PG_LAMBERT:
        return I0 * cg;
    case PG_SPOT:
        return I0 * pow(cg, a);
    case PG_BATWING:
        return I0 * cg * (1 + a * sg * sg);
    case PG_ROAD:
        return I0 * cg * (1 + a * sg * cos(c));
    case PG_QUAD:
        return I0 * cg * (1 + a * sg * cos(c) * cos(c));
    case PG_LINEAR:
        return I0 * cg * (1 + a * sg * sg * sin(c) * sin(c));
    default:
        return 0.0;
    }
}

double pg_flux(pg_dist d, double a)
{
    switch (d) {
    case PG_LAMBERT:
    case PG_ROAD:
    case PG_AIMED:
        return PI * I0;
    case PG_SPOT:
        return 2 * PI * I0 / (a + 1);
    case PG_BATWING:
        return 2 * PI * I0 * (0.5 + a / 4);
    case PG_QUAD:
        return PI * I0 * (1 + a / 3); /* the cos^2 C term: pi x int cos g sin^2 g */
    case PG_LINEAR:
        return PI * I0 * (1 + a / 4); /* the sin^2 C term: pi x int cos g sin^3 g */
    default:
        return 0.0;
    }
}

typedef struct buf {
    char *s;
    size_t n, cap;
} buf;

static void put(buf *b, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    char tmp[512];
    const int k = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    if (b->n + (size_t)k + 1 > b->cap) {
        b->cap = (b->cap + (size_t)k + 1) * 2;
        b->s = realloc(b->s, b->cap);
    }
    memcpy(b->s + b->n, tmp, (size_t)k + 1);
    b->n += (size_t)k;
}

/* The direction's angle to -z for types A, B at (h, v). */
static double aim_angle(int type, double h, double v)
{
    (void)type; /* both: cos = cos H cos V */
    const double c = cos(h * DEG) * cos(v * DEG);
    return acos(c < -1 ? -1 : c > 1 ? 1 : c) / DEG;
}

char *pg_ies(const pg_ies_spec *s, size_t *size)
{
    buf b = {0};
    if (s->first_line) put(&b, "%s\r\n", s->first_line);
    put(&b, "[TEST] lumis generator\r\n[MANUFAC] lumis tests\r\n[LUMINAIRE] analytic %d\r\n",
        (int)s->dist);
    put(&b, "[MORE] continued here\r\n[LAMP] none\r\n");
    if (s->tilt_include)
        put(&b, "TILT=INCLUDE\r\n1\r\n3\r\n0 45 90\r\n1.0 0.95 0.9\r\n");
    else
        put(&b, "TILT=NONE\r\n");
    const double m = s->multiplier == 0 ? 1 : s->multiplier;
    put(&b, "1 1000 %g %d %d %d %d %g %g %g\r\n1.0 1.0 50\r\n", m, s->nv, s->nh, s->type, s->units,
        s->width, s->length, s->height);
    for (int j = 0; j < s->nv; j++)
        put(&b, "%.10g%s", s->v0 + (s->v1 - s->v0) * j / (s->nv - 1), j % 10 == 9 ? "\r\n" : " ");
    put(&b, "\r\n");
    for (int i = 0; i < s->nh; i++)
        put(&b, "%.10g ", s->nh == 1 ? s->h0 : s->h0 + (s->h1 - s->h0) * i / (s->nh - 1));
    put(&b, "\r\n");
    for (int i = 0; i < s->nh; i++) {
        const double h = s->nh == 1 ? s->h0 : s->h0 + (s->h1 - s->h0) * i / (s->nh - 1);
        for (int j = 0; j < s->nv; j++) {
            const double v = s->v0 + (s->v1 - s->v0) * j / (s->nv - 1);
            const double I = s->type == 1 || s->dist == PG_FLOOD
                                 ? pg_intensity(s->dist, s->param, h, v)
                                 : pg_intensity(PG_AIMED, 0, 0, aim_angle(s->type, h, v));
            put(&b, "%.10g%s", I / m, j % 8 == 7 ? "\r\n" : " ");
        }
        put(&b, "\r\n");
    }
    *size = b.n;
    return b.s;
}

char *pg_ldt(pg_dist d, double a, int isym, int mc, int ng, int nsets, size_t *size)
{
    buf b = {0};
    put(&b, "lumis tests\n1\n%d\n%d\n%g\n%d\n%g\n", isym, mc, 360.0 / mc, ng, 180.0 / (ng - 1));
    put(&b, "report 1\nanalytic %d\nnumber 1\nfile.ldt\n2026-11-26\n", (int)d);
    put(&b, "600\n600\n100\n500\n0\n0\n0\n0\n0\n"); /* a 500 mm round luminous area */
    put(&b, "100\n80\n1\n0\n%d\n", nsets);
    /* set by set: lamps, type, flux, colour temperature, colour rendering, watts */
    for (int k = 0; k < nsets; k++)
        put(&b, "%d\nLED %d\n%d\n3000\n80\n%d\n", k + 1, k + 1, k == 0 ? 1000 : 2000, 20 + k);
    for (int k = 0; k < 10; k++) put(&b, "0.5\n");
    for (int k = 0; k < mc; k++) put(&b, "%.10g\n", 360.0 * k / mc);
    for (int k = 0; k < ng; k++) put(&b, "%.10g\n", 180.0 * k / (ng - 1));
    const int planes = isym == 0 ? mc : isym == 1 ? 1 : isym == 4 ? mc / 4 + 1 : mc / 2 + 1;
    const int from = isym == 3 ? mc / 4 : 0;
    for (int i = 0; i < planes; i++)
        for (int j = 0; j < ng; j++)
            put(&b, "%.10g\n", pg_intensity(d, a, 360.0 * (from + i) / mc, 180.0 * j / (ng - 1)));
    *size = b.n;
    return b.s;
}
