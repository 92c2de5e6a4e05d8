/* Photometric files: IES LM-63 (1986, 1991, 1995, 2002, 2019) and EULUMDAT (.ldt), told
 * apart by their content, read into one model (lumis/photometry.h).  Every failure names
 * the file, the line and the field.  docs/photometric.md has what is read and how. */
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

#define MAX_FILE   ((size_t)64 << 20) /* bytes */
#define MAX_VALUES 10000000           /* candela values in one table */
#define MAX_ANGLES 100000

/* ---- lines and numbers ------------------------------------------------------------------ */

static void text_free(text *t)
{
    free(t->buf);
    free(t->line);
}

/* Copies data and splits it into lines (LF, CR LF or CR). */
static lumis_status text_split(text *t, const void *data, size_t size)
{
    t->buf = malloc(size + 1);
    size_t cap = 64;
    t->line = malloc(cap * sizeof *t->line);
    if (!t->buf || !t->line)
        return lumis__fail(t->errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", t->name);
    memcpy(t->buf, data, size);
    t->buf[size] = '\0';
    for (size_t k = 0; k < size; k++)
        if (t->buf[k] == '\0') t->buf[k] = ' '; /* a NUL ends no line of text */
    char *p = t->buf;
    if (size >= 3 && (unsigned char)p[0] == 0xEF && (unsigned char)p[1] == 0xBB &&
        (unsigned char)p[2] == 0xBF)
        p += 3; /* UTF-8's byte-order mark */
    const char *start = p;
    while (*p || p == start) { /* at least one line, if only an empty one */
        if ((size_t)t->nlines == cap) {
            char **g = realloc(t->line, (cap *= 2) * sizeof *g);
            if (!g)
                return lumis__fail(t->errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory",
                                   t->name);
            t->line = g;
        }
        t->line[t->nlines++] = p;
        char *e = p + strcspn(p, "\r\n");
        if (!*e) break;
        const int crlf = e[0] == '\r' && e[1] == '\n';
        *e = '\0';
        p = e + 1 + crlf;
    }
    return LUMIS_OK;
}

/* The next token's start, or NULL at the end of the text (cursor on its line). */
static char *next_token(cursor *c)
{
    while (c->line < c->t->nlines) {
        if (!c->p) c->p = c->t->line[c->line];
        while (*c->p && (isspace((unsigned char)*c->p) || *c->p == ',')) c->p++;
        if (*c->p) return c->p;
        c->line++;
        c->p = NULL;
    }
    return NULL;
}

/* Whether anything but an end mark follows the table: some writers end their files with
 * a line "END" and DOS's end-of-file byte (^Z), which are not values. */
int lumis__pf_trailing_value(cursor *c)
{
    for (char *s; (s = next_token(c)) != NULL;) {
        const size_t len = strcspn(s, " \t\v\f,");
        const int end_mark = (len == 3 && strncmp(s, "END", 3) == 0) || strspn(s, "\x1a") == len;
        if (!end_mark) return 1;
        c->p = s + len;
    }
    return 0;
}

/* Reads one number for `field`; its line in *at (1-based).  Errors: the end of the file,
 * or a token that is not a number. */
lumis_status lumis__pf_read_number(cursor *c, const char *field, double *v, int *at)
{
    char *s = next_token(c);
    if (!s)
        return lumis__fail(c->t->errors, LUMIS_ERR_TRUNCATED, "%s: the file ends before %s",
                           c->t->name, field);
    char *end;
    errno = 0;
    const size_t len = strcspn(s, " \t\v\f,");
    /* decimal numbers only: strtod would also take hex, "inf" and "nan" */
    const int decimal = strspn(s, "0123456789+-.eE") == len;
    const double x = decimal ? strtod(s, &end) : 0.0;
    if (!decimal) end = s;
    /* an underflow (a denormal, or below it) is a number: tiny, or 0 */
    if (end == s || (size_t)(end - s) != len || (errno == ERANGE && fabs(x) >= 1.0) || !isfinite(x))
        return lumis__fail(c->t->errors, LUMIS_ERR_CORRUPT, "%s:%d: %s: '%.*s' is not a number",
                           c->t->name, c->line + 1, field, (int)(len < 40 ? len : 40), s);
    if (at) *at = c->line + 1;
    c->p = end;
    *v = x;
    return LUMIS_OK;
}

static lumis_status read_count(cursor *c, const char *field, int lo, int hi, int *v)
{
    double x;
    int at = 0;
    lumis_status st = lumis__pf_read_number(c, field, &x, &at);
    if (st != LUMIS_OK) return st;
    if (x != floor(x) || x < lo || x > hi)
        return lumis__fail(c->t->errors, LUMIS_ERR_BAD_DIMENSIONS,
                           "%s:%d: %s: %g: expected a whole number from %d to %d", c->t->name, at,
                           field, x, lo, hi);
    *v = (int)x;
    return LUMIS_OK;
}

/* n angles, increasing; errors name the line of the culprit. */
lumis_status lumis__pf_read_angles(cursor *c, const char *field, int n, double *a)
{
    for (int k = 0; k < n; k++) {
        int at = 0;
        lumis_status st = lumis__pf_read_number(c, field, &a[k], &at);
        if (st != LUMIS_OK) return st;
        if (k > 0 && !(a[k] > a[k - 1]))
            return lumis__fail(c->t->errors, LUMIS_ERR_CORRUPT,
                               "%s:%d: %s: %g after %g: the angles must increase (angle %d of %d)",
                               c->t->name, at, field, a[k], a[k - 1], k + 1, n);
    }
    return LUMIS_OK;
}

/* The length of the valid UTF-8 sequence at s (1 to 4), or 0 if there is none. */
static int utf8_length(const unsigned char *s)
{
    if (s[0] < 0x80) return 1;
    int n = s[0] >= 0xC2 && s[0] <= 0xDF   ? 2
            : s[0] >= 0xE0 && s[0] <= 0xEF ? 3
            : s[0] >= 0xF0 && s[0] <= 0xF4 ? 4
                                           : 0;
    for (int k = 1; k < n; k++)
        if ((s[k] & 0xC0) != 0x80) return 0;
    if (n == 3 && ((s[0] == 0xE0 && s[1] < 0xA0) || (s[0] == 0xED && s[1] >= 0xA0))) return 0;
    if (n == 4 && ((s[0] == 0xF0 && s[1] < 0x90) || (s[0] == 0xF4 && s[1] >= 0x90))) return 0;
    return n;
}

static int utf8_valid(const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p;) {
        const int n = utf8_length(p);
        if (!n) return 0;
        p += n;
    }
    return 1;
}

/* Copies a text field, trimmed, as UTF-8: a field that is not valid UTF-8 is read as
 * Latin-1 (the single bytes of older files' degree signs and non-breaking spaces), C1
 * bytes become U+FFFD, and control characters blanks, so that JSON and XML written from
 * it are always valid.  Never cuts a character in two. */
void lumis__pf_copy_field(char *dst, size_t cap, const char *src)
{
    while (isspace((unsigned char)*src)) src++;
    const int latin1 = !utf8_valid(src);
    size_t o = 0;
    for (const unsigned char *p = (const unsigned char *)src; *p;) {
        unsigned char enc[4];
        int n = 1, used = 1;
        if (*p < 0x20 || *p == 0x7F) {
            enc[0] = ' ';
        } else if (*p < 0x80) {
            enc[0] = *p;
        } else if (!latin1) {
            n = used = utf8_length(p);
            memcpy(enc, p, (size_t)n);
        } else if (*p < 0xA0) { /* U+FFFD */
            enc[0] = 0xEF, enc[1] = 0xBF, enc[2] = 0xBD, n = 3;
        } else {
            enc[0] = (unsigned char)(0xC0 | (*p >> 6)),
            enc[1] = (unsigned char)(0x80 | (*p & 0x3F));
            n = 2;
        }
        if (o + (size_t)n >= cap) break;
        memcpy(dst + o, enc, (size_t)n);
        o += (size_t)n;
        p += used;
    }
    while (o > 0 && isspace((unsigned char)dst[o - 1])) o--;
    dst[o] = '\0';
}

static void append_field(char *dst, size_t cap, const char *src)
{
    const size_t have = strlen(dst);
    if (have + 2 >= cap) return;
    if (have) dst[have] = ' ', dst[have + 1] = '\0';
    lumis__pf_copy_field(dst + strlen(dst), cap - strlen(dst), src);
}

/* The model's own checks (the angle ranges a symmetry covers, ...) know no file: their
 * messages get the file's name and the line of its horizontal angles. */
typedef struct named_sink {
    const lumis_error_sink *inner;
    const char *name;
    int line;
} named_sink;

static void named_message(void *user, lumis_status status, const char *message)
{
    const named_sink *n = user;
    if (!n->inner || !n->inner->fn) return;
    char buf[1024];
    snprintf(buf, sizeof buf, "%s:%d: %s", n->name, n->line, message);
    n->inner->fn(n->inner->user, status, buf);
}

lumis_status lumis__pf_create_model(const text *t, int line, const lumis_photometric_desc *d,
                                    lumis_photometric **out)
{
    named_sink n = {t->errors, t->name, line};
    const lumis_error_sink sink = {named_message, &n};
    return lumis_photometric_create(d, &sink, out);
}

/* A table of zeros lights nothing: refused, not rendered black. */
lumis_status lumis__pf_check_light(const text *t, const double *cd, size_t n)
{
    for (size_t k = 0; k < n; k++)
        if (cd[k] > 0) return LUMIS_OK;
    return lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                       "%s: every one of its %zu intensity values is 0: the file gives no light",
                       t->name, n);
}

/* ---- IES LM-63 ---------------------------------------------------------------------------- */

static int starts_with(const char *s, const char *prefix)
{
    while (isspace((unsigned char)*s)) s++;
    return strncmp(s, prefix, strlen(prefix)) == 0;
}

/* Whether s is the word w, with nothing but blanks after it ("NONEXYZ" is not "NONE"). */
static int is_word(const char *s, const char *w)
{
    const size_t n = strlen(w);
    if (strncmp(s, w, n) != 0) return 0;
    for (s += n; *s; s++)
        if (!isspace((unsigned char)*s)) return 0;
    return 1;
}

/* The line where TILT= is, or -1. */
static int tilt_line(const text *t)
{
    for (int k = 0; k < t->nlines; k++)
        if (starts_with(t->line[k], "TILT=") || starts_with(t->line[k], "TILT =")) return k;
    return -1;
}

static lumis_status read_ies(text *t, lumis_photometric_file *f)
{
    int first = 0, year = 1986;
    const char *l0 = t->line[0];
    while (isspace((unsigned char)*l0)) l0++;
    if (strncmp(l0, "IESNA", 5) == 0 || strncmp(l0, "IES:", 4) == 0) {
        lumis__pf_copy_field(f->standard, sizeof f->standard, l0);
        const char *y = strstr(l0, "LM-63-");
        year = y ? atoi(y + 6) : 1991; /* IESNA91 */
        if (year > 0 && year < 100) year += 1900;
        first = 1;
    } else {
        snprintf(f->standard, sizeof f->standard, "LM-63-1986");
    }
    const int tl = tilt_line(t);
    if (tl < 0)
        return lumis__fail(t->errors, LUMIS_ERR_BAD_HEADER,
                           "%s: no TILT= line: not an IES LM-63 file (it ends after %d lines)",
                           t->name, t->nlines);
    /* keywords: [KEY] value, [MORE] continuing the one before */
    char *last = NULL;
    size_t last_cap = 0;
    for (int k = first; k < tl; k++) {
        const char *s = t->line[k];
        while (isspace((unsigned char)*s)) s++;
        if (*s != '[') continue; /* 1986's free text */
        const char *e = strchr(s, ']');
        if (!e) continue;
        const size_t n = (size_t)(e - s - 1);
        struct {
            const char *key;
            char *dst;
            size_t cap;
        } const keys[] = {{"MANUFAC", f->manufacturer, sizeof f->manufacturer},
                          {"LUMINAIRE", f->luminaire, sizeof f->luminaire},
                          {"LUMCAT", f->catalog, sizeof f->catalog},
                          {"LAMP", f->lamp, sizeof f->lamp},
                          {"TEST", f->test, sizeof f->test}};
        if (n == 4 && strncmp(s + 1, "MORE", 4) == 0) {
            if (last) append_field(last, last_cap, e + 1);
            continue;
        }
        last = NULL;
        for (size_t q = 0; q < sizeof keys / sizeof keys[0]; q++)
            if (strlen(keys[q].key) == n && strncmp(s + 1, keys[q].key, n) == 0) {
                lumis__pf_copy_field(keys[q].dst, keys[q].cap, e + 1);
                last = keys[q].dst;
                last_cap = keys[q].cap;
            }
    }
    /* TILT=NONE, INCLUDE or a file name */
    const char *tv = strchr(t->line[tl], '=') + 1;
    while (isspace((unsigned char)*tv)) tv++;
    cursor c = {t, tl + 1, NULL};
    lumis_status st = LUMIS_OK;
    if (is_word(tv, "NONE")) {
        f->tilt = 0;
    } else if (is_word(tv, "INCLUDE")) {
        f->tilt = 1;
        st = read_count(&c, "TILT's lamp-to-luminaire geometry", 1, 3, &f->tilt_geometry);
        if (st == LUMIS_OK)
            st =
                read_count(&c, "TILT's number of angle and factor pairs", 1, MAX_ANGLES, &f->ntilt);
        if (st == LUMIS_OK) {
            f->tilt_deg = malloc(sizeof(double) * (size_t)f->ntilt);
            f->tilt_factor = malloc(sizeof(double) * (size_t)f->ntilt);
            if (!f->tilt_deg || !f->tilt_factor)
                return lumis__fail(t->errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory",
                                   t->name);
            st = lumis__pf_read_angles(&c, "TILT's angles", f->ntilt, f->tilt_deg);
        }
        for (int k = 0; k < f->ntilt && st == LUMIS_OK; k++) {
            int at = 0;
            st = lumis__pf_read_number(&c, "TILT's multiplying factors", &f->tilt_factor[k], &at);
            if (st == LUMIS_OK && f->tilt_factor[k] < 0)
                st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                                 "%s:%d: TILT's multiplying factor %d is %g: expected >= 0",
                                 t->name, at, k + 1, f->tilt_factor[k]);
        }
    } else {
        return lumis__fail(t->errors, LUMIS_ERR_UNSUPPORTED,
                           "%s:%d: TILT=%.60s: a tilt table in another file is not read "
                           "(put it in this one with TILT=INCLUDE)",
                           t->name, tl + 1, tv);
    }
    if (st != LUMIS_OK) return st;
    /* the two lines of numbers */
    double lumens = 0, mult = 0, w = 0, len = 0, h = 0, ballast = 0, factor = 0;
    int type = 0, units = 0, nv = 0, nh = 0;
    st = read_count(&c, "the number of lamps", -1000000, 1000000, &f->lamps);
    int lumens_at = 0, factors_at = 0;
    if (st == LUMIS_OK) st = lumis__pf_read_number(&c, "the lumens per lamp", &lumens, &lumens_at);
    if (st == LUMIS_OK)
        st = lumis__pf_read_number(&c, "the candela multiplier", &mult, &factors_at);
    if (st == LUMIS_OK) st = read_count(&c, "the number of vertical angles", 2, MAX_ANGLES, &nv);
    if (st == LUMIS_OK) st = read_count(&c, "the number of horizontal angles", 1, MAX_ANGLES, &nh);
    if (st == LUMIS_OK) st = read_count(&c, "the photometric type (1 C, 2 B, 3 A)", 1, 3, &type);
    if (st == LUMIS_OK) st = read_count(&c, "the units type (1 feet, 2 metres)", 1, 2, &units);
    if (st == LUMIS_OK) st = lumis__pf_read_number(&c, "the luminous width", &w, NULL);
    if (st == LUMIS_OK) st = lumis__pf_read_number(&c, "the luminous length", &len, NULL);
    if (st == LUMIS_OK) st = lumis__pf_read_number(&c, "the luminous height", &h, NULL);
    if (st == LUMIS_OK) st = lumis__pf_read_number(&c, "the ballast factor", &ballast, NULL);
    if (st == LUMIS_OK)
        st = lumis__pf_read_number(&c,
                                   year >= 2019   ? "the file generation type"
                                   : year >= 2002 ? "the future-use field"
                                                  : "the ballast-lamp photometric factor",
                                   &factor, NULL);
    if (st == LUMIS_OK) st = lumis__pf_read_number(&c, "the input watts", &f->input_watts, NULL);
    if (st != LUMIS_OK) return st;
    if ((double)nv * nh > MAX_VALUES)
        return lumis__fail(t->errors, LUMIS_ERR_TOO_LARGE,
                           "%s: %d x %d candela values: more than %d", t->name, nv, nh, MAX_VALUES);
    /* a factor of 0 would make the fixture black, a negative one is meaningless: neither is
     * quietly taken as 1 */
    if (!(mult > 0))
        return lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                           "%s:%d: the candela multiplier is %g: expected > 0", t->name, factors_at,
                           mult);
    if (!(ballast > 0))
        return lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                           "%s: the ballast factor is %g: expected > 0", t->name, ballast);
    if (year < 2002 && !(factor > 0))
        return lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                           "%s: the ballast-lamp photometric factor is %g: expected > 0", t->name,
                           factor);
    if (lumens < 0 && lumens != -1)
        return lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                           "%s:%d: the lumens per lamp is %g: expected > 0, or -1 for absolute "
                           "photometry",
                           t->name, lumens_at, lumens);
    double *v = malloc(sizeof(double) * (size_t)nv), *hz = malloc(sizeof(double) * (size_t)nh);
    double *cd = malloc(sizeof(double) * (size_t)nv * (size_t)nh);
    if (!v || !hz || !cd)
        st = lumis__fail(t->errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", t->name);
    if (st == LUMIS_OK) st = lumis__pf_read_angles(&c, "the vertical angles", nv, v);
    int h_at = 0;
    if (st == LUMIS_OK && next_token(&c)) h_at = c.line + 1;
    if (st == LUMIS_OK) st = lumis__pf_read_angles(&c, "the horizontal angles", nh, hz);
    for (int k = 0; k < nv * nh && st == LUMIS_OK; k++) {
        char field[96];
        snprintf(field, sizeof field, "candela value %d of %d x %d", k + 1, nh, nv);
        int at = 0;
        st = lumis__pf_read_number(&c, field, &cd[k], &at);
        if (st == LUMIS_OK && cd[k] < 0)
            st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                             "%s:%d: %s is %g: candela cannot be negative", t->name, at, field,
                             cd[k]);
    }
    if (st == LUMIS_OK && lumis__pf_trailing_value(&c))
        st = lumis__fail(t->errors, LUMIS_ERR_CORRUPT,
                         "%s:%d: more values after the %d x %d candela values the counts give",
                         t->name, c.line + 1, nh, nv);
    if (st == LUMIS_OK) st = lumis__pf_check_light(t, cd, (size_t)nv * (size_t)nh);
    if (st == LUMIS_OK) {
        const double unit = units == 1 ? 0.3048 : 1.0;
        lumis_photometric_desc d = {0};
        d.type = (lumis_photometric_type)type;
        d.nv = nv;
        d.nh = nh;
        d.v_deg = v;
        d.h_deg = hz;
        d.candela = cd;
        /* the ballast factor always; the ballast-lamp factor of files before 2002 (later its
         * place holds a reserved field, then the file generation type) */
        d.multiplier = mult * ballast * (year < 2002 ? factor : 1.0);
        d.lamp_lumens = lumens > 0 ? lumens * fabs((double)f->lamps) : -1.0;
        f->lumens_per_lamp = lumens;
        /* the shape from the signs of the sizes (LM-63-2002, table 1) */
        d.width = fabs(w) * unit;
        d.length = fabs(len) * unit;
        d.height = fabs(h) * unit;
        if (w == 0 && len == 0 && h == 0)
            d.shape = LUMIS_SHAPE_POINT;
        else if (w > 0 && len > 0)
            d.shape = h > 0 ? LUMIS_SHAPE_BOX : h == 0 ? LUMIS_SHAPE_RECTANGLE : LUMIS_SHAPE_OTHER;
        else if (w < 0 && len < 0 && w == len && h == 0)
            d.shape = LUMIS_SHAPE_DISK;
        else if (w < 0 && len == 0 && h >= 0) { /* LM-63-1995's round opening */
            d.shape = h > 0 ? LUMIS_SHAPE_CYLINDER : LUMIS_SHAPE_DISK;
            d.length = d.width; /* a diameter, as in 2002's form */
        } else if (w < 0 && len < 0 && w == len && h < 0 && h == w)
            d.shape = LUMIS_SHAPE_SPHERE;
        else if (w < 0 && len < 0 && w == len && h > 0)
            d.shape = LUMIS_SHAPE_CYLINDER;
        else
            d.shape = LUMIS_SHAPE_OTHER;
        st = lumis__pf_create_model(t, h_at, &d, &f->model);
    }
    free(v);
    free(hz);
    free(cd);
    return st;
}

/* ---- the entry points --------------------------------------------------------------------- */

double lumis_photometric_tilt_factor(const lumis_photometric_file *f, lumis_photometric_type type,
                                     lumis_vec3 aim)
{
    const double len = sqrt((double)aim.x * aim.x + (double)aim.y * aim.y + (double)aim.z * aim.z);
    if (!f || !f->tilt || f->ntilt < 1 || !(len > 0) || !isfinite(len)) return 1.0;
    const double y = fmax(-1.0, fmin(1.0, aim.y / len));
    const double t = type == LUMIS_PHOTOMETRIC_C ? acos(-y) * 180.0 / LUMIS_PI
                                                 : asin(fabs(y)) * 180.0 / LUMIS_PI;
    const double *a = f->tilt_deg, *m = f->tilt_factor;
    const int n = f->ntilt;
    if (t <= a[0]) return m[0];
    if (t >= a[n - 1]) return m[n - 1];
    int k = 0;
    while (k + 2 < n && a[k + 1] <= t) k++;
    return m[k] + (m[k + 1] - m[k]) * (t - a[k]) / (a[k + 1] - a[k]);
}

void lumis_photometric_file_destroy(lumis_photometric_file *f)
{
    if (!f) return;
    lumis_photometric_destroy(f->model);
    free(f->tilt_deg);
    free(f->tilt_factor);
    free(f);
}

/* Whether the text looks like EULUMDAT: Ityp and Isym in range on lines 2 and 3, and
 * enough lines. */
static int looks_ldt(const text *t)
{
    if (t->nlines < 26) return 0;
    char *e1, *e2;
    const long ityp = strtol(t->line[1], &e1, 10), isym = strtol(t->line[2], &e2, 10);
    while (isspace((unsigned char)*e1)) e1++;
    while (isspace((unsigned char)*e2)) e2++;
    return e1 != t->line[1] && !*e1 && e2 != t->line[2] && !*e2 && ityp >= 0 && ityp <= 3 &&
           isym >= 0 && isym <= 4;
}

lumis_status lumis_photometric_read_memory(const void *data, size_t size, const char *name,
                                           const lumis_error_sink *errors,
                                           lumis_photometric_file **out)
{
    if (out) *out = NULL;
    if (!name) name = "<memory>";
    if (!out || (!data && size))
        return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "%s: no data", name);
    if (size == 0) return lumis__fail(errors, LUMIS_ERR_EMPTY_FILE, "%s: the file is empty", name);
    if (size > MAX_FILE)
        return lumis__fail(errors, LUMIS_ERR_TOO_LARGE,
                           "%s: %zu bytes: photometric files of "
                           "more than %zu MB are not read",
                           name, size, MAX_FILE >> 20);
    text t = {name, errors, NULL, NULL, 0};
    lumis_photometric_file *f = calloc(1, sizeof *f);
    lumis_status st = f ? text_split(&t, data, size)
                        : lumis__fail(errors, LUMIS_ERR_OUT_OF_MEMORY, "%s: out of memory", name);
    if (st == LUMIS_OK) {
        const char *l0 = t.line[0];
        while (isspace((unsigned char)*l0)) l0++;
        if (strncmp(l0, "IES", 3) == 0 || tilt_line(&t) >= 0) {
            f->format = LUMIS_PHOTOMETRIC_IES;
            st = read_ies(&t, f);
        } else if (looks_ldt(&t)) {
            f->format = LUMIS_PHOTOMETRIC_LDT;
            st = lumis__pf_read_ldt(&t, f);
        } else {
            st = lumis__fail(errors, LUMIS_ERR_UNKNOWN_FORMAT,
                             "%s: not a photometric file: neither IES LM-63 (a TILT= line) nor "
                             "EULUMDAT (type and symmetry indicators on lines 2 and 3)",
                             name);
        }
    }
    text_free(&t);
    if (st != LUMIS_OK) {
        lumis_photometric_file_destroy(f);
        return st;
    }
    *out = f;
    return LUMIS_OK;
}

lumis_status lumis_photometric_read(const char *path, const lumis_error_sink *errors,
                                    lumis_photometric_file **out)
{
    if (out) *out = NULL;
    if (!out) return lumis__fail(errors, LUMIS_ERR_INVALID_ARGUMENT, "no output");
    char *data = NULL;
    size_t n = 0;
    lumis_status st = lumis__read_whole(path, MAX_FILE, "photometric file", errors, &data, &n);
    if (st == LUMIS_OK) st = lumis_photometric_read_memory(data, n, path, errors, out);
    free(data);
    return st;
}
